"""Cost of the tabulated reload form in a calibration: the default scene in both forms, same run.

``calibrate(Scene(grid=G, reload_form=F))`` for F = "paper" and "tabulated", alternated
(paper, tabulated, paper, tabulated, ...) after a JIT warm-up, in one process with one worker, so
that both see the same machine; the ratio tabulated / paper is taken pair by pair and its median
reported (issue 31's bound: 1.1 at 512^2). The tabulated form adds its own fit (one ``C2, n2``
per level and ``s2``) and its held-out errors (each interior level left out and the table
refitted); both forms fit the paper's Eq. 25 and Eq. 24 and run the same sweeps.

Run: python benchmarks/reload_form_cost.py [--grid 512] [--pairs 3]
Writes benchmarks/results/reload_form_cost.csv and .md and prints the table.
"""

import argparse
import statistics
import time

from _provenance import RESULTS, run_record, write_rows

from halfspace_calib.pipeline.calibration import Scene, calibrate


def _time(grid, form):
    t0 = time.perf_counter()
    cal = calibrate(Scene(grid=grid, reload_form=form, workers=1), progress=False)
    seconds = time.perf_counter() - t0
    fit = cal.reload_table.seconds if cal.reload_table is not None else 0.0
    return seconds, fit, cal.params.reload_form


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--grid", type=int, default=512, help="grid of the default scene (default 512)")
    ap.add_argument("--pairs", type=int, default=3, help="paper/tabulated pairs (default 3)")
    a = ap.parse_args(argv)
    calibrate(Scene(grid=32, workers=1), progress=False)  # JIT warm-up
    rows = []
    for i in range(a.pairs):
        (tp, _, fp), (tt, fit, ft) = _time(a.grid, "paper"), _time(a.grid, "tabulated")
        assert (fp, ft) == ("paper", "tabulated")
        rows.append(
            {
                "pair": i + 1,
                "grid": a.grid,
                "paper_s": round(tp, 2),
                "tabulated_s": round(tt, 2),
                "table_fit_s": round(fit, 3),
                "ratio": round(tt / tp, 4),
            }
        )
        print(rows[-1], flush=True)
    med = statistics.median(r["ratio"] for r in rows)
    RESULTS.mkdir(exist_ok=True)
    write_rows(RESULTS / "reload_form_cost.csv", rows)
    cols = list(rows[0])
    md = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    md += ["| " + " | ".join(str(r[c]) for c in cols) + " |" for r in rows]
    text = "\n".join(md) + f"\n\nmedian ratio tabulated / paper: {med:.4f} (bound 1.1)\n"
    (RESULTS / "reload_form_cost.md").write_text(text)
    print(text)


if __name__ == "__main__":
    with run_record(__file__):
        main()
