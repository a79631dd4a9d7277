"""The hardening asperity truth at 0.02 H, where much of sheet forming lives (issue 43).

``flattening_hardening.py`` holds the law given the hardening modulus (docs/flattening.md, Eqs.
F2c and F2d) to a hardening FE truth at 0.05, 0.2 and 0.45 H; ``asperity_low.py`` holds the
perfectly plastic law to a perfectly plastic truth at 0.02 H, where it is far too fast (the
lattice's rate does not fall with the pressure). A sheet metal hardens and is pressed at such
pressures, and this is where the default law (one state, the host passing the modulus) is used
most. This script runs the hardening truth there: every profile of the table at ``P_OVER_H``
on 128 x 48 elements (as ``asperity_low.py``: the table's 64 x 32 puts the contact on one or two
elements), DC04's Swift curve or another of its initial yield (``--material K,eps0,n --tag``),
strains to 0.2, and puts beside it, nothing fitted:

- the one-state law without the modulus (the current flow stress only),
- the one-state law with it (F2c and F2d: ``flattening_hardening.candidate_curve``, checked
  against the runtime's ``flattening_update(..., hardening=)``),
- the two-state law (``limit-analysis``) along the flow curve (its table read at each step's
  flow stress; it takes no modulus),

each with ``alpha1`` the hardening truth's pressing-alone fractions: this run's at 0.02 H and
``flattening_hardening[_tag].csv``'s at 0.05, 0.2 and 0.45 H (64 x 32), as
``flattening_truth.low_law`` builds the perfectly plastic law below the table. The perfectly
plastic truth at 0.02 H (``asperity_low.csv``, 128 x 48) is shown beside it.

``--reuse``: the truth of the CSV a previous run wrote, only the laws computed again.

Run: python benchmarks/flattening_hardening_low.py [--workers 2] [--material K,eps0,n --tag NAME]
[--nx 256 --nz 64 --tag fine] [--reuse] (DC04: 2.5 min with two workers; 256 x 64: 7 min).
Writes benchmarks/results/flattening_hardening_low[_NAME].csv, .md and .png (run record:
.run.json).
"""

import argparse
import math
from pathlib import Path

import flattening_hardening as fh
import numpy as np
from _provenance import RESULTS, read_rows, write_rows
from asperity_flattening import profiles
from flattening_hardening import (
    STRAINS,
    _material,
    candidate_curve,
    law_curve,
    miss_summary,
    run_tagged,
)
from flattening_truth import law_of, law_strain, read_truth

import frictionlaw as fl
from frictionlaw.flow_curve import SwiftCurve

P_OVER_H = 0.02
MESH = (128, 48)
STEM = "flattening_hardening_low"


def _perfectly_plastic_low(mesh):
    """``{profile: {strain: alpha}}``: the perfectly plastic truth at 0.02 H on ``mesh``."""
    out = {}
    for r in read_rows(RESULTS / "asperity_low.csv"):
        if (int(r["nx"]), int(r["nz"])) == mesh and float(r["p_over_H"]) == P_OVER_H:
            out.setdefault(r["profile"], {})[round(float(r["strain"]), 6)] = float(r["alpha"])
    return out


def figure(rows, path, title):
    """The truth (dots), the one-state law with the modulus (solid), without it (dotted) and the
    two-state law (dashed), a colour per profile."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 4.6))
    ax = fig.subplots()
    for i, name in enumerate(dict.fromkeys(r["profile"] for r in rows)):
        sel = [r for r in rows if r["profile"] == name]
        e, c = [r["strain"] for r in sel], f"C{i}"
        ax.plot(e, [r["alpha_hardening"] for r in sel], "o", color=c, ms=4)
        ax.plot(e, [r["alpha_law_with_hardening_modulus"] for r in sel], "-", color=c, label=name)
        ax.plot(e, [r["alpha_law"] for r in sel], ":", color=c, lw=0.8)
        ax.plot(e, [r["alpha_two_state"] for r in sel], "--", color=c, lw=0.8)
    ax.set_xscale("symlog", linthresh=0.005)
    ax.set_xlabel("bulk strain (stretch, 1)")
    ax.set_ylabel("contact fraction alpha (1)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2, help="processes for the FE runs (2)")
    ap.add_argument(
        "--material",
        default=None,
        help="another Swift curve K,eps0,n (K in Pa) of DC04's initial yield (default: DC04)",
    )
    ap.add_argument(
        "--nx", type=int, default=MESH[0], help=f"elements along the period ({MESH[0]})"
    )
    ap.add_argument(
        "--nz", type=int, default=MESH[1], help=f"elements through the depth ({MESH[1]})"
    )
    ap.add_argument(
        "--tag",
        default=None,
        help="results' name suffix, and the table's hardening run alpha1 is read from "
        "(flattening_hardening_<tag>.csv; needed with --material and a mesh)",
    )
    ap.add_argument(
        "--reuse", action="store_true", help="the truth of the CSV a previous run wrote"
    )
    args = ap.parse_args(argv)
    mesh = (args.nx, args.nz)
    if (args.material or mesh != MESH) and not args.tag:
        ap.error("--material and a mesh need --tag (the table's hardening run to read alpha1 from)")
    suffix = f"_{args.tag}" if args.tag else ""
    stem = STEM + suffix
    mat = _material(args.material)
    flow = SwiftCurve(K=mat.K, eps0=mat.eps0, n=mat.n)
    pp, H = read_truth(RESULTS / "asperity_flattening.csv")
    profs = profiles()
    names = list(profs)
    if args.reuse:
        stored = fh._stored_truth(stem)
    else:
        stored = fh._fe_runs(names, profs, args, mat, (P_OVER_H,))
    truth = {n: stored[(n, P_OVER_H)] for n in names}
    table = fh._stored_truth("flattening_hardening" + suffix)  # its pressing-alone fractions
    plastic = _perfectly_plastic_low(mesh)
    p = P_OVER_H * H
    rows, lines, check = [], [], 0.0
    misses = {"one-state, no modulus": [], "one-state, F2c and F2d": [], "two-state": []}
    for name in names:
        deg = next(k for k in pp if k[0] == name)[1]
        a_h, ok = truth[name]
        first = {ph: {0.0: float(table[(name, ph)][0][0])} for ph in fh.P_OVER_H}
        first[P_OVER_H] = {0.0: float(a_h[0])}
        P = law_of(first, deg, H)
        slope = math.tan(math.radians(deg))
        plain = law_curve(P, p, STRAINS, mat)
        held = candidate_curve(P, p, slope, STRAINS, mat)
        runtime = law_curve(P, p, STRAINS, mat, hardening=True)
        check = max(check, float(np.abs(runtime - held).max()))
        two_law = P.replace(flattening=fl.Flattening(P.flattening.slope, model="limit-analysis"))
        two = fl.flattening_curve(p, law_strain(STRAINS), two_law, flow_curve=flow, steps=256)
        for key, curve in zip(misses, (plain, held, two), strict=True):
            misses[key].append(curve - a_h)
        pl = plastic.get(name, {})
        for i, e in enumerate(STRAINS):
            rows.append(
                {
                    "profile": name,
                    "p_over_H": P_OVER_H,
                    "strain": e,
                    "alpha_hardening": a_h[i],
                    "alpha_perfectly_plastic": pl.get(round(e, 6), math.nan),
                    "alpha_law": round(float(plain[i]), 5),
                    "alpha_law_with_hardening_modulus": round(float(held[i]), 5),
                    "alpha_two_state": round(float(two[i]), 5),
                    "converged": ok,
                }
            )

        def fmt(v):
            return " ".join("-" if not np.isfinite(x) else f"{x:.3f}" for x in v)

        lines.append(
            f"| {name} | {fmt(a_h)} | {fmt([pl.get(round(e, 6), math.nan) for e in STRAINS])} | "
            f"{fmt(plain)} | {fmt(held)} | {fmt(two)} | "
            + " / ".join(f"{np.abs(c - a_h).max():.3f}" for c in (plain, held, two))
            + " |"
        )
    write_rows(RESULTS / f"{stem}.csv", rows)
    figure(
        rows,
        RESULTS / f"{stem}.png",
        f"Hardening truth at {P_OVER_H:g} H (dots, Swift n {mat.n:g}): one-state law with the "
        "modulus (solid),\nwithout it (dotted), two-state law (dashed); nothing fitted",
    )
    head = [
        "# The hardening asperity truth at 0.02 H (issue 43 study)",
        "",
        f"`benchmarks/flattening_hardening_low.py`; mesh {mesh[0]} x {mesh[1]}; "
        f"{'DC04 ' if not args.material else ''}Swift (K {mat.K / 1e6:.4g} MPa, eps0 "
        f"{mat.eps0:g}, n {mat.n:g}; initial yield {mat.sigma_y0 / 1e6:.1f} MPa), H = "
        f"{H / 1e6:.1f} MPa; p = {P_OVER_H:g} H; strains "
        + ", ".join(f"{e:g}" for e in STRAINS)
        + ". The laws: alpha1 the hardening truth's pressing-alone fractions (this run's at "
        f"{P_OVER_H:g} H, flattening_hardening{suffix}.csv's at 0.05, 0.2 and 0.45 H), the "
        "profile's slope, beta = 1, each step at the current flow stress; nothing fitted.",
        "",
        "| profile | alpha, hardening truth | alpha, perfectly plastic truth (asperity_low.csv) | "
        "one-state law without the modulus | one-state law with it (F2c, F2d) | two-state law | "
        "largest miss: no modulus / F2c and F2d / two-state |",
        "|---|---|---|---|---|---|---|",
    ]
    lines += [
        "",
        miss_summary(misses),
        "",
        f"The one-state ODE with the limits against the runtime given the hardening modulus "
        f"(`flattening_update(..., hardening=)`): {check:.1e} largest difference in alpha.",
        "",
        "Converged: " + ("every job." if all(ok for _, ok in truth.values()) else "NOT every job."),
    ]
    text = "\n".join(head + lines) + "\n"
    Path(RESULTS / f"{stem}.md").write_text(text, encoding="utf-8")
    print(text)


if __name__ == "__main__":
    run_tagged(__file__, STEM, main)
