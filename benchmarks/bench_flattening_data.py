"""Cost of ``halfspace-calib --flattening-data`` on large lab sheets, before and after; params.json.

The fit of ``beta`` (``fit_beta``) to synthetic lab sheets of 10-10 000 rows, made with the
runtime's own ``frictionlaw.flattening_curve`` at ``beta = 0.7`` plus noise of 0.01 in ``alpha``
(strains 0-0.02, slope 0.08, the paper's Eq. 24 law at H = 800 MPa), timed in turn in one run:

- ``before``: the model point by point for every trial ``beta`` (``flattening_curve`` at every
  row, 32 midpoint steps a row along a flow curve): the former ``fit_beta``, through the same
  search (``_fit``);
- ``after``: ``fit_beta`` (one curve per distinct pressure: ``FlatteningCurves``, or
  ``FlatteningPaths`` along a flow curve).

Sheets: three pressures (0.1, 0.25, 0.4 H, rows cycling through them) or every row its own
pressure (uniform in 0.05-0.6 H, a continuous log), each perfectly plastic and along DC04's
Swift curve (``--flow-curve``). ``before`` runs where it takes at most about three minutes
(``--before-max``); its ms a row are measured, not extrapolated. The fitted ``beta`` of both in
the table (relative difference). Then ``params.json`` of the command (grid 16) on three-pressure
sheets of 10-100 000 rows: its size now and the size the former record had (the same file with
the rows and every distinct pressure put back, as the former code wrote them).
Run: python benchmarks/bench_flattening_data.py [--sizes 10,100,1000,10000] [--quick]
Writes benchmarks/results/bench_flattening_data.csv/.md and prints the tables.
"""

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _provenance import RESULTS, commit, run_record, write_rows

from frictionlaw import Flattening, FrictionParams, flattening_curve
from frictionlaw.flow_curve import SwiftCurve
from halfspace_calib.pipeline.sweep.flattening import FlatteningData, _fit, fit_beta

H = 8e8
LAW = FrictionParams(m=0.5, sigma_y=H / 2.8, H=H, C1=1.05, n1=2.87, C2=7.44, n2=0.575)
SLOPE, BETA = 0.08, 0.7
DC04 = SwiftCurve(530e6, 0.006, 0.24)
#: the largest sheet each ``before`` case runs at by default (rows): about three minutes here
BEFORE_MAX = {"3 p, plastic": 10_000, "all p, plastic": 1000, "3 p, flow curve": 100,
              "all p, flow curve": 10}  # fmt: skip
AFTER_MAX = {"all p, flow curve": 1000}  # the paths: about 25 ms a distinct pressure


def sheet(n, distinct, flow_curve, seed=0):
    """A synthetic lab sheet of ``n`` rows (the runtime's curve at BETA plus noise)."""
    rng = np.random.default_rng(seed)
    if distinct:
        p = rng.uniform(0.05, 0.6, n) * H
    else:
        p = (np.array([0.1, 0.25, 0.4]) * H)[np.arange(n) % 3]
    eps = rng.uniform(0.0, 0.02, n)
    made = LAW.replace(flattening=Flattening(slope=SLOPE, beta=BETA))
    if flow_curve is None:
        a = flattening_curve(p, eps, made)
    else:
        a = flattening_curve(p, eps, made, flow_curve=flow_curve, steps=32)
    alpha = np.clip(a + rng.normal(0.0, 0.01, n), 0.0, 1.0)
    return FlatteningData(f"{n} rows", eps, alpha, p, flow_curve=flow_curve)


def fit_before(data):
    """The former fit: the model at every row for every trial beta, the same search."""
    base = LAW.replace(flattening=Flattening(slope=SLOPE))
    fc = data.flow_curve

    def models(ln_beta):
        out = []
        for b in ln_beta:
            if fc is None:
                out.append(flattening_curve(data.p, math.exp(b) * data.strain, base))
            else:
                law = LAW.replace(flattening=Flattening(slope=SLOPE, beta=math.exp(b)))
                out.append(flattening_curve(data.p, data.strain, law, flow_curve=fc, steps=32))
        return np.stack(out)

    return _fit(models, data, 0.9)


def timing(sizes, before_max):
    rows = []
    fit_after = lambda d: fit_beta(LAW.replace(flattening=Flattening(slope=SLOPE)), d)  # noqa: E731
    fit_after(sheet(10, False, None))  # JIT of the law's kernels
    for case, distinct, fc in (
        ("3 p, plastic", False, None),
        ("all p, plastic", True, None),
        ("3 p, flow curve", False, DC04),
        ("all p, flow curve", True, DC04),
    ):
        for n in sizes:
            if n > AFTER_MAX.get(case, math.inf):
                continue
            data = sheet(n, distinct, fc, seed=n)
            t0 = time.perf_counter()
            after = fit_after(data)
            t_after = time.perf_counter() - t0
            row = {
                "case": case,
                "rows": n,
                "pressures": int(np.unique(data.p).size),
                "after_s": t_after,
                "after_ms_per_row": 1e3 * t_after / n,
                "before_s": None,
                "before_ms_per_row": None,
                "ratio": None,
                "beta_after": after["beta"],
                "beta_before": None,
                "beta_rel_diff": None,
                "band_rel_diff": None,
            }
            if n <= before_max.get(case, 0):
                t0 = time.perf_counter()
                before = fit_before(data)
                t_before = time.perf_counter() - t0
                row.update(
                    before_s=t_before,
                    before_ms_per_row=1e3 * t_before / n,
                    ratio=t_before / t_after,
                    beta_before=before["beta"],
                    beta_rel_diff=after["beta"] / before["beta"] - 1.0,
                    band_rel_diff=max(
                        abs(a / b - 1.0) for a, b in zip(after["band"], before["band"], strict=True)
                    ),
                )
            rows.append(row)
            print(_timing_line(row), flush=True)
    return rows


def _g(v, fmt):
    return "-" if v is None else format(v, fmt)


def _timing_line(r):
    return (
        f"| {r['case']} | {r['rows']} | {r['pressures']} | {_g(r['before_s'], '.3g')} | "
        f"{_g(r['before_ms_per_row'], '.3g')} | {r['after_s']:.3g} | "
        f"{r['after_ms_per_row']:.3g} | {_g(r['ratio'], '.3g')} | {r['beta_after']:.6g} | "
        f"{_g(r['beta_rel_diff'], '.1e')} | {_g(r['band_rel_diff'], '.1e')} |"
    )


def write_csv_sheet(path, data):
    lines = ["strain,alpha,p_Pa"]
    lines += [
        f"{e:.17g},{a:.17g},{p:.17g}"
        for e, a, p in zip(data.strain, data.alpha, data.p, strict=True)
    ]
    path.write_text("\n".join(lines) + "\n")


def sizes_of_files(sizes):
    """params.json and summary.json of the command on three-pressure sheets; the former size."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            rng = np.random.default_rng(n)
            p = (np.array([0.1, 0.25, 0.4]) * H)[np.arange(n) % 3]
            eps = rng.uniform(0.0, 0.02, n)
            made = LAW.replace(flattening=Flattening(slope=SLOPE, beta=BETA))
            from frictionlaw.flattening_curves import FlatteningCurves

            a = np.clip(FlatteningCurves(p, made).alpha(eps) + rng.normal(0, 0.01, n), 0, 1)
            csv = Path(tmp) / f"sheet{n}.csv"
            write_csv_sheet(csv, FlatteningData("", eps, a, p))
            out = Path(tmp) / f"o{n}"
            argv = [sys.executable, "-m", "halfspace_calib", "--grid", "16", "--pressures",
                    "1e8,2e8,3e8,5e8", "--reload-fractions", "0.3,0.6", "--flattening-data",
                    str(csv), "--no-progress", "--out", str(out)]  # fmt: skip
            t0 = time.perf_counter()
            subprocess.run(argv, check=True, capture_output=True)
            seconds = time.perf_counter() - t0
            text = (out / "params.json").read_text()
            doc = json.loads(text)
            fit = doc["provenance"]["flattening"]["fit"]
            # the former record: every row and every distinct pressure, no data summary
            old = {k: v for k, v in fit.items() if k not in ("record_version", "data")}
            old["pressures_Pa"] = sorted({float(v) for v in p})
            old.update(strain=eps.tolist(), alpha=a.tolist(), p_Pa=p.tolist())
            doc["provenance"]["flattening"]["fit"] = old
            before = len(json.dumps(doc, indent=2).encode()) + 1
            summary = (out / "summary.json").stat().st_size
            row = {
                "rows": n,
                "csv_bytes": csv.stat().st_size,
                "params_bytes_before": before,
                "params_bytes_after": len(text.encode()),
                "summary_bytes_after": summary,
                "rows_kept": fit["data"]["rows_kept"],
                "command_s": seconds,
            }
            rows.append(row)
            print(
                f"| {n} | {row['csv_bytes']} | {before} | {row['params_bytes_after']} | "
                f"{summary} | {'yes' if row['rows_kept'] else 'no'} | {seconds:.1f} |",
                flush=True,
            )
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="10,100,1000,10000")
    ap.add_argument("--file-sizes", default="10,100,1000,10000,100000")
    ap.add_argument("--quick", action="store_true", help="sizes 10,100; before up to 100 rows")
    args = ap.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",")]
    file_sizes = [int(s) for s in args.file_sizes.split(",")]
    before_max = dict(BEFORE_MAX)
    if args.quick:
        sizes, file_sizes = [10, 100], [10, 2000]
        before_max = {k: min(v, 100) for k, v in before_max.items()}
    head = (
        "| sheet | rows | pressures | before s | before ms/row | after s | after ms/row | "
        "before / after | beta after | beta after/before - 1 | band, largest rel. diff |"
    )
    print(head + "\n|---|---|---|---|---|---|---|---|---|---|---|")
    t_rows = timing(sizes, before_max)
    fhead = (
        "| rows | CSV bytes | params.json before | params.json after | summary.json after | "
        "rows kept | command s |"
    )
    print("\n" + fhead + "\n|---|---|---|---|---|---|---|")
    f_rows = sizes_of_files(file_sizes)
    RESULTS.mkdir(exist_ok=True)
    write_rows(RESULTS / "bench_flattening_data.csv", t_rows)
    write_rows(RESULTS / "bench_flattening_data_files.csv", f_rows)
    md = [
        "# `--flattening-data` on large lab sheets: the fit before and after, params.json",
        "",
        f"`benchmarks/bench_flattening_data.py` at commit {commit()} (the run record says which "
        "machine); before = the model point by point for every trial beta (the former "
        "`fit_beta`, same search), after = one curve per distinct pressure. Sheets made with "
        f"`flattening_curve` at beta = {BETA}, slope {SLOPE}, noise 0.01, strains 0-0.02; "
        "flow curve: DC04's Swift curve (before: 32 midpoint steps a row, after: 256 graded "
        "steps a pressure, so beta differs by the former steps' error). '-': not run (over "
        "about three minutes).",
        "",
        head,
        "|---|---|---|---|---|---|---|---|---|---|---|",
        *(_timing_line(r) for r in t_rows),
        "",
        "## params.json of the command (grid 16, three pressures)",
        "",
        "Before: the same file with the rows and every distinct pressure in the fit's record, as "
        "the former code wrote them (the new `data` summary taken out).",
        "",
        fhead,
        "|---|---|---|---|---|---|---|",
        *(
            f"| {r['rows']} | {r['csv_bytes']} | {r['params_bytes_before']} | "
            f"{r['params_bytes_after']} | {r['summary_bytes_after']} | "
            f"{'yes' if r['rows_kept'] else 'no'} | {r['command_s']:.1f} |"
            for r in f_rows
        ),
        "",
    ]
    (RESULTS / "bench_flattening_data.md").write_text("\n".join(md))
    print(f"wrote {RESULTS / 'bench_flattening_data.md'}")


if __name__ == "__main__":
    with run_record(__file__):
        main()
