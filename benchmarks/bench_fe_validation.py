"""Validation tables of the FE demo against the slab method and the upper-bound ring chart.

Writes benchmarks/results/fe_validation_slab.csv, fe_validation_ring.csv and
fe_ring_chart.png, and prints the tables. Run: python benchmarks/bench_fe_validation.py
"""

import csv
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _provenance import run_record

from fe_demo.analysis.ring_chart import CHART_M, ring_chart  # noqa: E402
from fe_demo.output import plot_ring_chart  # noqa: E402
from fe_demo.scenes import run_ring, run_upsetting  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"
AT = (0.1, 0.3, 0.5)


def slab_table(nr=32, n_inc=25):
    rows = []
    cases = [("none", {}, "m=0")]
    cases += [("tresca", {"m": m}, f"tresca m={m:g}") for m in (0.1, 0.3, 0.5, 1.0)]
    cases += [("coulomb", {"mu": mu}, f"coulomb mu={mu:g}") for mu in (0.05, 0.1, 0.2)]
    cases += [("cap", {"mu": 0.1, "m": 0.2}, "cap mu=0.1 m=0.2 (slab ODE)")]
    cases += [("sbmf", {}, "sbmf example (slab ODE)")]
    for law, kw, lab in cases:
        res = run_upsetting(law, nr=nr, n_increments=n_inc, **kw)
        h = res.history
        row = {"case": lab, "converged": res.converged}
        for a in AT:
            i = int(np.argmin(np.abs(h["height_reduction"] - a)))
            row[f"ratio_at_{a:g}"] = round(float(h["avg_pressure"][i] / h["slab_pressure"][i]), 4)
        rows.append(row)
        print(row, flush=True)
    return rows


def ring_table(nr=16, n_inc=50):
    rows, fe, chart = [], {}, {}
    for m in CHART_M:
        red_c, d_c = ring_chart(m, 0.5)
        chart[m] = (red_c, d_c)
        res = run_ring("tresca" if m else "none", m=m, nr=nr, n_increments=n_inc)
        h = res.history
        ref = np.interp(h["height_reduction"], red_c, d_c)
        fe[f"FE m={m:g}"] = (h["height_reduction"], h["inner_diameter_change"])
        rows.append(
            {
                "m": m,
                "converged": res.converged,
                "reached": round(float(h["height_reduction"][-1]), 3),
                "fe_dDi_end_pct": round(100 * float(h["inner_diameter_change"][-1]), 2),
                "chart_dDi_end_pct": round(100 * float(ref[-1]), 2),
                "max_abs_diff_pct": round(
                    100 * float(np.abs(h["inner_diameter_change"] - ref).max()), 2
                ),
                "cutbacks": len(res.info["cutback_log"]),
                "wall_s": round(res.wall_time, 1),
            }
        )
        print(rows[-1], flush=True)
    plot_ring_chart(OUT / "fe_ring_chart.png", chart, fe)
    return rows


def _write(path, rows):
    with path.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def main():
    OUT.mkdir(exist_ok=True)
    _write(OUT / "fe_validation_slab.csv", slab_table())
    _write(OUT / "fe_validation_ring.csv", ring_table())


if __name__ == "__main__":
    with run_record(__file__):
        main()
