"""Figs. 9-10: tau_geo, tau_adh and their ratio over 100-600 MPa, smooth and rough tool.

Default: 128 x 128 solver grid from a 512 x 512 synthetic measurement (block 4), Table 1 Ra on the
solver grid. Also the knobs: measured points per element (block 2, 4, 8) and where Table 1's
roughness sits (solver or measured grid). Writes ``benchmarks/results/geometric/`` (CSV, PNG,
``knobs.csv``) and prints the tables.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/geometric_study.py [--grid 128]``
"""

import argparse
import csv
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _provenance import run_record  # noqa: E402

from halfspace_calib.output.geometric import write_geometric_outputs  # noqa: E402
from halfspace_calib.studies.geometric import geometric_study  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "geometric"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--grid", type=int, default=128)
    args = ap.parse_args()
    n = args.grid
    t0 = time.perf_counter()
    study = geometric_study(n=n, block=4)
    t_default = time.perf_counter() - t0
    write_geometric_outputs(study, OUT)
    smooth, rough = study.results
    print(f"Figs. 9-10, grid {n} from {4 * n} (block 4), {t_default:.1f} s for both tools")
    print(
        "| p_mean (MPa) | alpha smooth | tau_adh smooth (MPa) | tau_geo smooth (MPa) | ratio smooth "
        "| alpha rough | tau_adh rough (MPa) | tau_geo rough (MPa) | ratio rough |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for i, p in enumerate(smooth.p_mean):
        print(
            f"| {p / 1e6:.0f} | {smooth.alpha[i]:.3f} | {smooth.tau_adh[i] / 1e6:.2f} | "
            f"{smooth.tau_geo[i] / 1e6:.3f} | {smooth.ratio[i]:.4f} | {rough.alpha[i]:.3f} | "
            f"{rough.tau_adh[i] / 1e6:.2f} | {rough.tau_geo[i] / 1e6:.3f} | {rough.ratio[i]:.4f} |"
        )
    print(f"| mean | | | | {smooth.ratio_mean:.4f} | | | | {rough.ratio_mean:.4f} |")
    for r in study.results:
        st = r.settings
        print(
            f"  {r.label}: solver surfaces Ra workpiece {st['workpiece_Ra'] * 1e6:.3f} um, tool "
            f"{st['tool_Ra'] * 1e6:.3f} um (Rq {st['tool_Rq'] * 1e6:.3f} um); "
            f"converged {r.all_converged}"
        )

    rows = []
    for block in (2, 4, 8):
        for where in ("solver", "measured"):
            t0 = time.perf_counter()
            st = (
                study
                if (block, where) == (4, "solver")
                else geometric_study(n=n, block=block, roughness_on=where)
            )
            secs = t_default if (block, where) == (4, "solver") else time.perf_counter() - t0
            s, r = st.results
            rows.append(
                [
                    block,
                    n * block,
                    where,
                    s.ratio_mean,
                    s.ratio.min(),
                    s.ratio.max(),
                    r.ratio_mean,
                    r.ratio.min(),
                    r.ratio.max(),
                    s.settings["tool_Ra"],
                    r.settings["tool_Ra"],
                    round(secs, 2),
                ]
            )
    head = [
        "block",
        "measured_n",
        "table1_on",
        "smooth_mean",
        "smooth_min",
        "smooth_max",
        "rough_mean",
        "rough_min",
        "rough_max",
        "smooth_tool_Ra_solver",
        "rough_tool_Ra_solver",
        "seconds",
    ]
    with open(OUT / "knobs.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(head)
        w.writerows(rows)
    print(
        "\n| block | measured grid | Table 1 Ra on | ratio smooth mean (min-max) | "
        "ratio rough mean (min-max) | tool Ra on solver grid smooth / rough (um) | time (s) |"
    )
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r[0]} | {r[1]} | {r[2]} | {r[3]:.4f} ({r[4]:.4f}-{r[5]:.4f}) | "
            f"{r[6]:.4f} ({r[7]:.4f}-{r[8]:.4f}) | {r[9] * 1e6:.3f} / {r[10] * 1e6:.3f} | "
            f"{r[11]:.1f} |"
        )


if __name__ == "__main__":
    with run_record(__file__):
        main()
