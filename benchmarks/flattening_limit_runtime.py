"""The runtime's two-state flattening (model limit-analysis) against the FE asperity truth (issue 43).

``flattening_limit_law.py`` and ``flattening_limit_low.py`` integrated the two-state law as a
study, from each truth curve's pressing-alone fraction. The runtime now carries it
(``frictionlaw.flattening_limit``: the shipped table, read between pressures in ``ln p``,
integrated node by node). This script puts the runtime's curves (``frictionlaw.flattening_curve``
with the block's model ``limit-analysis``) beside the truth, beside the study's curves (they
must agree: the same table and rule) and beside the one-state model (``layer-yield``), each law
built from the truth's inputs only as ``flattening_truth.py`` builds it (its ``alpha1`` the
truth's pressing-alone fractions, the profile's slope, ``beta = 1``); nothing fitted.

Curves: the 30 of ``asperity_flattening.csv`` (0.05-0.6 H, 64 x 32 elements) and the low
truth's at 0.02 H (``asperity_low.csv``), each profile on its finest mesh; and the 15 of the
hardening truth (``flattening_hardening.csv``: DC04's Swift curve, 0.05-0.45 H), where the
two-state law reads the table at the current flow stress (``flow_curve``: the only way the
perfectly plastic table sees the hardening) beside the one-state model with the hardening
modulus (Eqs. F2c and F2d, that study's column). Writes ``results/flattening_limit_runtime.md``,
``.csv`` and ``.png`` (a panel per pressure: the truth, both laws); seconds.

Run: python benchmarks/flattening_limit_runtime.py
"""

import math

import numpy as np
from _provenance import RESULTS, read_rows, run_record, write_report
from flattening_truth import (
    curve_misses,
    law_of,
    law_strain,
    low_curves,
    low_law,
    read_truth,
)

import frictionlaw as fl
from frictionlaw.flow_curve import SwiftCurve

TWO = "limit-analysis"
#: the hardening truth's bulk (fe_demo's DC04, flattening_hardening.py)
DC04 = SwiftCurve(K=530e6, eps0=0.006, n=0.24)


def _two_state(P):
    """The same law with the two-state block (the same slope and beta)."""
    return P.replace(flattening=fl.Flattening(P.flattening.slope, model=TWO))


def _study():
    """The study's two-state curves: ``{(profile, p/H, strain): alpha}`` (RMS-slope rows)."""
    out = {}
    for r in read_rows(RESULTS / "flattening_limit_law.csv"):
        out[(r["profile"], float(r["p_over_H"]), float(r["strain"]))] = float(r["alpha_limit"])
    for r in read_rows(RESULTS / "flattening_limit_low.csv"):
        key = (r["profile"], float(r["p_over_H"]), float(r["strain"]))
        out.setdefault(key + (r["mesh"],), float(r["alpha_limit"]))
    return out


def curves():
    """Every truth curve: ``(profile, deg, p/H, mesh, {strain: alpha}, law)``."""
    truth, H = read_truth(RESULTS / "asperity_flattening.csv")
    out = [
        (name, deg, ph, "64x32", col, law_of(table, deg, H))
        for (name, deg), table in truth.items()
        for ph, col in sorted(table.items())
    ]
    finest = {}
    for name, deg, ph, nx, nz, col in low_curves(RESULTS / "asperity_low.csv"):
        if int(nx) >= int(finest.get(name, ("0",))[0]):
            finest[name] = (nx, nz, deg, ph, col)
    for name, (nx, nz, deg, ph, col) in finest.items():
        out.append((name, deg, ph, f"{nx}x{nz}", col, low_law(truth, H, name, deg, ph, col)))
    return out, H


def compare():
    cs, H = curves()
    study = _study()
    rows = []
    for name, deg, ph, mesh, col, P in cs:
        strains = sorted(col)
        eps = law_strain(strains)
        two = fl.flattening_curve(ph * H, eps, _two_state(P))
        one = fl.flattening_curve(ph * H, eps, P)
        for e, a2, a1 in zip(strains, two, one, strict=True):
            s = study.get((name, ph, e), study.get((name, ph, e, mesh), math.nan))
            rows.append(
                {
                    "profile": name,
                    "slope_deg": deg,
                    "p_over_H": ph,
                    "mesh": mesh,
                    "strain": e,
                    "alpha_truth": col[e],
                    "alpha_two_state": round(float(a2), 5),
                    "alpha_study": s,
                    "alpha_one_state": round(float(a1), 5),
                    "alpha_two_state_f2c": math.nan,
                    "alpha_two_state_f2d": math.nan,
                    "alpha_two_state_f2c_f2d": math.nan,
                }
            )
    return rows


def capped_curve(a0, s0, p, strains, flow_curve, factor=6.0, held=False):
    """The two-state law along ``flow_curve`` with F2c's limit on its rate, a study (not in the
    runtime): ``tan(theta) dA / d eps <= factor p (1 - A) / h`` (``h`` the curve's modulus), the
    one-state model's limit of the lattice applied to the whole tabulated rate; the runtime's
    midpoint rule in ``(A, ln s)`` at each step's middle flow stress and modulus. ``factor``
    None: no limit on the rate; ``held``: F2d's bound on the fraction, ``A <= a0 + 3 p / (4 h
    s0)`` with the virgin flank's slope ``s0``, as the one-state runtime holds it."""
    from frictionlaw._limit_table import PRANDTL_FACTOR, S_FLOOR, STEP, rate_table, table_rates

    t, rs = rate_table(), math.sqrt(3.0) / 2.0
    A, q, e, out = a0, math.log(s0), 0.0, []
    for target in strains:
        while e < target - 1e-12 and A < 1.0:
            h = min(STEP / rs, target - e)  # equivalent strain per step (STEP of stretch)
            mid = e + 0.5 * h
            x = p * math.sqrt(3.0) / (PRANDTL_FACTOR * float(flow_curve.sigma_y(mid)))
            hm = float(flow_curve.hardening(mid))
            cap = math.inf if factor is None else factor * p / hm

            def rates(A, q, x=x, cap=cap):
                s = max(math.exp(q), S_FLOOR)
                dA, ds = table_rates(np.array([x]), np.array([A]), np.array([s]), t)
                return min(float(dA[0]), cap * (1.0 - A) / s), float(ds[0]) / s

            dA, dq = rates(A, q)
            dA, dq = rates(min(A + 0.5 * h * rs * dA, 1.0), q + 0.5 * h * rs * dq)
            A_new = min(A + h * rs * dA, 1.0)
            if held:
                A_new = max(A, min(A_new, a0 + 0.75 * p / (hm * s0)))
            A, q, e = A_new, q + h * rs * dq, e + h
        out.append(A)
    return np.array(out)


def hardening():
    """The hardening truth's curves: the two-state law along DC04's flow curve (``alpha1`` the
    hardening truth's pressing-alone fractions) beside the one-state law with the modulus."""
    pp, H = read_truth(RESULTS / "asperity_flattening.csv")
    src = read_rows(RESULTS / "flattening_hardening.csv")
    out = []
    for name in dict.fromkeys(r["profile"] for r in src):
        key = next(k for k in pp if k[0] == name)
        mine = [r for r in src if r["profile"] == name]
        pres = sorted({float(r["p_over_H"]) for r in mine})
        at = {(float(r["p_over_H"]), float(r["strain"])): r for r in mine}
        P = _two_state(
            law_of({ph: {0.0: float(at[(ph, 0.0)]["alpha_hardening"])} for ph in pres}, key[1], H)
        )
        for ph in pres:
            strains = sorted(e for q, e in at if q == ph)
            two = fl.flattening_curve(ph * H, law_strain(strains), P, flow_curve=DC04, steps=256)
            a0 = float(at[(ph, 0.0)]["alpha_hardening"])
            s0, es = P.flattening.slope, law_strain(strains)
            capped = capped_curve(a0, s0, ph * H, es, DC04)
            held = capped_curve(a0, s0, ph * H, es, DC04, factor=None, held=True)
            both = capped_curve(a0, s0, ph * H, es, DC04, held=True)
            for e, a2, ac, ad, ab in zip(strains, two, capped, held, both, strict=True):
                r = at[(ph, e)]
                out.append(
                    {
                        "profile": name,
                        "slope_deg": key[1],
                        "p_over_H": ph,
                        "mesh": "64x32 (hardening)",
                        "strain": e,
                        "alpha_truth": float(r["alpha_hardening"]),
                        "alpha_two_state": round(float(a2), 5),
                        "alpha_study": math.nan,
                        "alpha_one_state": round(float(r["alpha_law_with_hardening_modulus"]), 5),
                        "alpha_two_state_f2c": round(float(ac), 5),
                        "alpha_two_state_f2d": round(float(ad), 5),
                        "alpha_two_state_f2c_f2d": round(float(ab), 5),
                    }
                )
    return out


def _band(rows, low):
    sel = [r for r in rows if low(r)]
    out = {col: curve_misses(sel, col) for col in ("alpha_two_state", "alpha_one_state")}
    known = [r for r in sel if math.isfinite(r["alpha_study"])]
    out["study"] = max((abs(r["alpha_two_state"] - r["alpha_study"]) for r in known), default=None)
    out["study_points"] = len(known)
    return out


def report(rows):
    lines = [
        "# The runtime's two-state flattening against the FE asperity truth",
        "",
        "`benchmarks/flattening_limit_runtime.py`: `frictionlaw.flattening_curve` with the block's "
        "model `limit-analysis` (the shipped table, `frictionlaw/data/limit_rates.csv`) and with "
        "the one-state `layer-yield`, each law built from the truth's inputs only (its `alpha1` "
        "the truth's pressing-alone fractions, the profile's slope, the measured row's RMS "
        "slope, `beta = 1`); nothing fitted. The study's curves (`flattening_limit_law.py`, "
        "`flattening_limit_low.py`: the same table and rule, 4 decimals) beside them.",
        "",
        "| band | largest miss: two-state / one-state | RMS: two-state / one-state | curves "
        "within 0.05: two-state / one-state | runtime against the study (points) |",
        "|---|---|---|---|---|",
    ]
    bands = (
        (lambda r: "hardening" not in r["mesh"] and r["p_over_H"] >= 0.05, "0.05-0.6 H (64 x 32)"),
        (lambda r: r["p_over_H"] < 0.05, "0.02 H (finest mesh)"),
        (
            lambda r: "hardening" in r["mesh"],
            "DC04 hardening, 0.05-0.45 H (one-state: with F2c, F2d)",
        ),
    )
    for sel, label in bands:
        b = _band(rows, sel)
        t, o = b["alpha_two_state"], b["alpha_one_state"]
        vs = "-" if b["study"] is None else f"{b['study']:.1e} ({b['study_points']})"
        lines.append(
            f"| {label} | {t[0]:.3f} / {o[0]:.3f} | {t[1]:.3f} / {o[1]:.3f} | {t[2]} / {o[2]} of "
            f"{t[3]} | {vs} |"
        )
    hard = [r for r in rows if "hardening" in r["mesh"]]
    m = {c: curve_misses(hard, f"alpha_two_state_{c}") for c in ("f2c", "f2d", "f2c_f2d")}
    lines += [
        "",
        "The one-state model's limits by the hardening applied to the two-state law along DC04's "
        "curve, a study (`capped_curve`, not in the runtime), on the hardening truth (largest "
        "miss / RMS / curves within 0.05): the lattice's limit (Eq. F2c, `tan(theta) dA / "
        f"d eps <= 6 p (1 - A) / h`) on the whole tabulated rate {m['f2c'][0]:.3f} / {m['f2c'][1]:.3f} "
        f"/ {m['f2c'][2]}; the sinking the hardening holds (Eq. F2d, `A <= alpha1(p) + 3 p / "
        f"(4 h tan(theta))`) {m['f2d'][0]:.3f} / {m['f2d'][1]:.3f} / {m['f2d'][2]}; both "
        f"{m['f2c_f2d'][0]:.3f} / {m['f2c_f2d'][1]:.3f} / {m['f2c_f2d'][2]} of {m['f2d'][3]}.",
    ]
    lines += [
        "",
        "| profile | p/H | mesh | largest miss: two-state | one-state |",
        "|---|---|---|---|---|",
    ]
    for key in dict.fromkeys((r["profile"], r["p_over_H"], r["mesh"]) for r in rows):
        sel = [r for r in rows if (r["profile"], r["p_over_H"], r["mesh"]) == key]
        m2 = max(sel, key=lambda r: abs(r["alpha_two_state"] - r["alpha_truth"]))
        m1 = max(sel, key=lambda r: abs(r["alpha_one_state"] - r["alpha_truth"]))
        lines.append(
            f"| {key[0]} | {key[1]:g} | {key[2]} | "
            f"{m2['alpha_two_state'] - m2['alpha_truth']:+.3f} ({m2['strain']:g}) | "
            f"{m1['alpha_one_state'] - m1['alpha_truth']:+.3f} ({m1['strain']:g}) |"
        )
    return lines


def figure(rows, path):
    """One panel per pressure of the perfectly plastic truth (0.02 H on its finest meshes) and of
    the hardening truth: the truth (dots), the two-state law (solid), the one-state (dashed), a
    colour per profile."""
    from matplotlib.figure import Figure

    panels = [
        (f"{'DC04 hardening' if hard else 'perfectly plastic'}, p/H {ph:g}", hard, ph)
        for hard in (False, True)
        for ph in sorted({r["p_over_H"] for r in rows if ("hardening" in r["mesh"]) == hard})
    ]
    profiles = list(dict.fromkeys(r["profile"] for r in rows))
    ncol = 4
    nrow = -(-len(panels) // ncol)
    fig = Figure(figsize=(13, 3.2 * nrow))
    axes = np.atleast_1d(fig.subplots(nrow, ncol, sharey=True)).ravel()
    for ax in axes[len(panels) :]:
        ax.set_visible(False)
    for ax, (title, hard, ph) in zip(axes, panels, strict=False):
        for i, name in enumerate(profiles):
            sel = [
                r
                for r in rows
                if r["profile"] == name
                and r["p_over_H"] == ph
                and ("hardening" in r["mesh"]) == hard
            ]
            if not sel:
                continue
            e = [r["strain"] for r in sel]
            c = f"C{i}"
            ax.plot(e, [r["alpha_truth"] for r in sel], "o", color=c, ms=3)
            ax.plot(e, [r["alpha_two_state"] for r in sel], "-", color=c, label=name)
            ax.plot(e, [r["alpha_one_state"] for r in sel], "--", color=c, lw=0.8)
        ax.set_xscale("symlog", linthresh=0.005)
        ax.set_xlabel("bulk strain (1)")
        ax.set_title(title, fontsize=9)
        ax.grid(alpha=0.3)
    for ax in axes[::ncol]:
        ax.set_ylabel("contact fraction alpha (1)")
    axes[0].legend(fontsize=7)
    fig.suptitle(
        "FE asperity truth (dots), the two-state law (solid) and the one-state law (dashed; "
        "with the hardening modulus on DC04), nothing fitted"
    )
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def main():
    rows = compare() + hardening()
    write_report("flattening_limit_runtime", rows, report(rows))
    figure(rows, RESULTS / "flattening_limit_runtime.png")


if __name__ == "__main__":
    with run_record(__file__, "flattening_limit_runtime"):
        main()
