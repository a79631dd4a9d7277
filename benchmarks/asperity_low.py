"""The asperity truth below its table: 0.02 H, where much of sheet forming lives (issue 43).

``asperity_flattening.py``'s table starts at 0.05 H. Sheet forming's contact pressures are often
lower, and the law is used there. This script runs the same truth (the strip, the flat, the
stretch: ``fe_demo.asperity.asperity_contact_fraction``, nothing fitted) at ``LOW_P_OVER_H``:
every profile of the table on 128 x 48 elements (the table's 64 x 32 puts the contact of
0.02 H, about 0.025 of the flank, on one or two elements), and the shallowest and steepest
wedges and the measured row on 256 x 64 as well, to show what the mesh does (a rerun computes
only the jobs ``asperity_low.csv`` or its partial file does not hold). Writes ``results/asperity_low.csv`` /
``.md``; ``flattening_truth.py`` puts the law beside it.

``--stiff``: the 10 deg wedge with Young's modulus times 10 and 100 and the 3 deg wedge times 10
(yield, Poisson's ratio and H unchanged) at 0.02 H on 128 x 48, to strains of 0.1: is it
elasticity that slows the truth below the table? (``asperity_flattening.py --stiff`` found it is
not at 0.05 and 0.1 H.) Writes ``results/asperity_low_stiff.csv`` / ``.md`` beside the table's
``E`` from ``asperity_low.csv``.

Run: python benchmarks/asperity_low.py [--workers 2] [--stiff] (77 min with one worker on the
shared machine)
"""

import argparse

from _provenance import RESULTS, read_rows, run_record, write_report
from asperity_flattening import (
    REFINE_STRAINS,
    ROW_STRAINS,
    cached_cases,
    perfectly_plastic,
    profiles,
    run_cases,
    stiff_table,
)

LOW_P_OVER_H = (0.02,)
LOW_MESHES = ((128, 48), (256, 64))
# also on the finest mesh: the shallowest and steepest wedges, and the measured row (which
# 128 x 48 does not resolve: asperity_flattening.py --rows)
FINEST_PROFILES = ("wedge 3 deg", "wedge 10 deg", "matrix-3 row (lambda_s 0.8 um)")
STIFF_CASES = (("wedge 10 deg", 10.0), ("wedge 10 deg", 100.0), ("wedge 3 deg", 10.0))


def jobs(mat):
    out = []
    for name, prof in profiles().items():
        for nx, nz in LOW_MESHES:
            if (nx, nz) != LOW_MESHES[0] and name not in FINEST_PROFILES:
                continue
            for ph in LOW_P_OVER_H:
                out.append((name, prof, ph, REFINE_STRAINS, nx, nz, mat))
    return out


def stiff(mat, workers):
    """``--stiff``: ``STIFF_CASES`` at ``LOW_P_OVER_H`` on the first mesh beside the table's E."""
    nx, nz = LOW_MESHES[0]
    prof = profiles()
    todo = [
        (
            f"{name}, E x {f:g}",
            prof[name],
            ph,
            ROW_STRAINS,
            nx,
            nz,
            perfectly_plastic(E=mat.E * f, nu=mat.nu),
        )
        for name, f in STIFF_CASES
        for ph in LOW_P_OVER_H
    ]
    rows = [r for part in run_cases(todo, workers) for r in part]
    cases = {}
    for name, f in STIFF_CASES:
        cases.setdefault(name, []).append(f)
    base = {
        (r["profile"], float(r["p_over_H"]), float(r["strain"])): float(r["alpha"])
        for r in read_rows(RESULTS / "asperity_low.csv")
        if (int(r["nx"]), int(r["nz"])) == (nx, nz)
    }
    lines = [
        "# The truth below its table with a stiffer elasticity (0.02 H)",
        "",
        f"`benchmarks/asperity_low.py --stiff`: {nx} x {nz} elements, Young's modulus "
        f"{mat.E / 1e9:g} GPa times 1 (`asperity_low.csv`) and the factor shown; yield, Poisson's "
        "ratio and H unchanged. alpha after each strain.",
        "",
        *stiff_table(cases, LOW_P_OVER_H, rows, base),
    ]
    write_report("asperity_low_stiff", rows, lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2, help="processes (2)")
    ap.add_argument(
        "--stiff", action="store_true", help="the 10 and 3 deg wedges with E x 10 (and x 100)"
    )
    args = ap.parse_args()
    mat = perfectly_plastic()
    if args.stiff:
        stiff(mat, args.workers)
        return
    rows = cached_cases(jobs(mat), "asperity_low", args.workers)
    lines = [
        "# The asperity truth below its table (0.02 H)",
        "",
        "`benchmarks/asperity_low.py`: every profile of `asperity_flattening.py`'s table at p/H "
        + ", ".join(f"{v:g}" for v in LOW_P_OVER_H)
        + " on "
        + " and ".join(f"{nx} x {nz}" for nx, nz in LOW_MESHES)
        + f" elements (the latter: {', '.join(FINEST_PROFILES)}); alpha after each strain.",
        "",
        "| profile | p/H | mesh | " + " | ".join(f"{e:g}" for e in REFINE_STRAINS) + " |",
        "|---|---|---|" + "---|" * len(REFINE_STRAINS),
    ]
    keys = list(dict.fromkeys((r["profile"], r["p_over_H"], r["nx"], r["nz"]) for r in rows))
    for k in keys:
        by = {
            r["strain"]: r["alpha"]
            for r in rows
            if (r["profile"], r["p_over_H"], r["nx"], r["nz"]) == k
        }
        lines.append(
            f"| {k[0]} | {k[1]:g} | {k[2]} x {k[3]} | "
            + " | ".join(f"{by[e]:.3f}" if e in by else "-" for e in REFINE_STRAINS)
            + " |"
        )
    write_report("asperity_low", rows, lines)


if __name__ == "__main__":
    import sys

    with run_record(__file__, "asperity_low_stiff" if "--stiff" in sys.argv else None):
        main()
