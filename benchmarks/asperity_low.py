"""The asperity truth below its table: 0.02 H, where much of sheet forming lives (issue 43).

``asperity_flattening.py``'s table starts at 0.05 H. Sheet forming's contact pressures are often
lower, and the law is used there. This script runs the same truth (the strip, the flat, the
stretch: ``fe_demo.asperity.asperity_contact_fraction``, nothing fitted) at ``LOW_P_OVER_H``:
every profile of the table on 128 x 48 elements (the table's 64 x 32 puts the contact of
0.02 H, about 0.025 of the flank, on one or two elements), and the shallowest and steepest
wedges on 256 x 64 as well, to show what the mesh does. Writes ``results/asperity_low.csv`` /
``.md``; ``flattening_truth.py`` puts the law beside it.

Run: python benchmarks/asperity_low.py [--workers 2] (77 min with one worker on the shared machine)
"""

import argparse

from _provenance import run_record, write_report
from asperity_flattening import REFINE_STRAINS, perfectly_plastic, profiles, run_cases

LOW_P_OVER_H = (0.02,)
LOW_MESHES = ((128, 48), (256, 64))
FINEST_PROFILES = ("wedge 3 deg", "wedge 10 deg")  # also on the finest mesh


def jobs(mat):
    out = []
    for name, prof in profiles().items():
        for nx, nz in LOW_MESHES:
            if (nx, nz) != LOW_MESHES[0] and name not in FINEST_PROFILES:
                continue
            for ph in LOW_P_OVER_H:
                out.append((name, prof, ph, REFINE_STRAINS, nx, nz, mat))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2, help="processes (2)")
    args = ap.parse_args()
    mat = perfectly_plastic()
    todo = jobs(mat)
    rows = [r for part in run_cases(todo, args.workers) for r in part]
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
    with run_record(__file__):
        main()
