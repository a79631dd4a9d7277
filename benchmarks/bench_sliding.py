"""Benchmark of the sliding study (Sec. 3.3): time of the full default sweep, all six pressures,
and the speed/accuracy knobs (warm start, tolerance, window operator, volume conservation).

Run from the repository root::

    python benchmarks/bench_sliding.py            # knobs on 40 positions + all six full sweeps
    python benchmarks/bench_sliding.py --quick    # knobs only
    python benchmarks/bench_sliding.py --decomposition  # steady ratio: tool vs flat tool, vc
    python benchmarks/bench_sliding.py --resolution     # steady ratio against the element size

Writes ``benchmarks/results/sliding_bench.csv`` (knobs), ``benchmarks/results/sliding_study.csv``
(per pressure), ``benchmarks/results/sliding_decomposition.csv``, ``sliding_resolution.csv`` and the study's CSV/PNG into ``benchmarks/results/sliding/``.

OpenBLAS is limited to one thread (before numpy loads): on a machine with more busy threads than
cores, its threaded ``ddot`` (``np.vdot`` in the solver) spin-waits and one 128 x 128 dot product
takes ~20 ms instead of ~10 us (measured here), which slows the solver 20-50 fold.
"""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import csv  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _provenance import run_record  # noqa: E402

from halfspace_calib.contact.materials import Materials, SolverSettings  # noqa: E402
from halfspace_calib.output.sliding import write_sliding_outputs  # noqa: E402
from halfspace_calib.studies.sliding import (  # noqa: E402
    SLIDING_PRESSURES,
    sliding_surfaces,
    sliding_sweep,
)
from halfspace_calib.studies.sliding_study import sliding_study  # noqa: E402

RES = Path(__file__).resolve().parent / "results"


def _solver(kw):
    """The solver settings among a case's options (removed from ``kw``)."""
    keys = ("tol", "periodic", "volume_conservation")
    return SolverSettings(**{k: kw.pop(k) for k in keys if k in kw})


def load():
    return os.getloadavg()[0]


def knobs(n_pos=40, p_mean=600e6):
    wp, tl = sliding_surfaces()
    flat = np.zeros_like(tl.heights)
    base = dict(materials=Materials(H=800e6, m=0.5), positions=n_pos)
    cases = [
        ("default (periodic, vc, tol 1e-8, warm tool)", tl.heights, {}),
        ("warm start shifted with the workpiece", tl.heights, dict(warm_start="workpiece")),
        ("no warm start", tl.heights, dict(warm_start="none")),
        ("tol 1e-6", tl.heights, dict(tol=1e-6)),
        ("tol 1e-10", tl.heights, dict(tol=1e-10)),
        ("non-periodic window (isolated stamp)", tl.heights, dict(periodic=False)),
        ("no volume conservation", tl.heights, dict(volume_conservation=False)),
        ("flat tool (workpiece rows only)", flat, {}),
    ]
    rows = []
    ref = None
    for name, tool, kw in cases:
        l0 = load()
        t0 = time.perf_counter()
        r = sliding_sweep(wp, tool, wp.dx, p_mean, solver=_solver(kw), **base, **kw)
        dt = time.perf_counter() - t0
        s = r.steady
        if ref is None:
            ref = r
        dev = float(np.max(np.abs(r.W_def[1:] - ref.W_def[1:])) / np.mean(ref.W_def[1:]))
        rows.append(
            dict(
                case=name,
                p_mean=p_mean,
                positions=n_pos,
                seconds=round(dt, 2),
                s_per_position=round(dt / n_pos, 3),
                nit_mean=round(float(r.nit.mean()), 1),
                ratio_mean=s["ratio_mean"],
                ratio_max=s["ratio_max"],
                alpha_mean=s["alpha_mean"],
                max_rel_dev_W_def_vs_default=dev,
                converged=r.all_converged,
                load_avg=round((l0 + load()) / 2, 2),
            )
        )
        print(
            f"{name:45s} {dt:7.2f} s  nit {r.nit.mean():6.1f}  ratio mean "
            f"{s['ratio_mean']:.4f} max {s['ratio_max']:.4f}  dev {dev:.2e}  load {load():.1f}",
            flush=True,
        )
    with open(RES / "sliding_bench.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def full(workers):
    l0 = load()
    st = sliding_study(SLIDING_PRESSURES, workers=workers, progress=False)
    l1 = load()
    write_sliding_outputs(st, RES / "sliding")
    rows = []
    for r in st.ok:
        s = r.steady
        rows.append(
            dict(
                p_mean=r.p_mean,
                positions=s["positions"],
                seconds=round(r.seconds, 1),
                nit_mean=round(float(r.nit.mean()), 1),
                W_def_mean=s["W_def_mean"],
                W_adh_mean=s["W_adh_mean"],
                ratio_mean=s["ratio_mean"],
                ratio_max=s["ratio_max"],
                first_ratio=s["first_ratio"],
                alpha_mean=s["alpha_mean"],
                converged=s["converged"],
            )
        )
        print(
            f"{r.p_mean / 1e6:5.0f} MPa  {r.seconds:7.1f} s  W_def {s['W_def_mean']:.3e} J  "
            f"W_adh {s['W_adh_mean']:.3e} J  ratio mean {s['ratio_mean']:.4f} "
            f"max {s['ratio_max']:.4f}  {r.message}",
            flush=True,
        )
    for p, e in st.errors.items():
        print(f"{p / 1e6:g} MPa FAILED: {e}")
    print(
        f"all six pressures: {st.seconds:.1f} s wall (workers={workers}), "
        f"load average {l0:.1f} -> {l1:.1f}"
    )
    with open(RES / "sliding_study.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
        fh.write(
            f"# all six pressures: {st.seconds:.1f} s wall, workers={workers}, "
            f"load average {l0:.1f} -> {l1:.1f}, nproc {os.cpu_count()}\n"
        )


def decomposition(n_pos=60):
    """Steady ratio per pressure: the Table 1 tool, a flat tool (only the entering row is fresh),
    without volume conservation, and the tool-slope estimate 2 H / (m sigma_y) <(t_k - t_k+1)^+> / 2a.
    """
    wp, tl = sliding_surfaces()
    t = tl.heights
    slope = float(np.maximum(t[:-1] - t[1:], 0).mean() / wp.dx)
    H, m = 800e6, 0.5
    est_tool = 2 * H / (m * H / 2.8) * slope
    rows = []
    for p in SLIDING_PRESSURES:
        row = dict(p_mean=p, positions=n_pos, tool_slope_estimate=est_tool)
        for name, tool, kw in (
            ("tool", t, {}),
            ("flat_tool", 0 * t, {}),
            ("tool_no_vc", t, dict(volume_conservation=False)),
            ("flat_tool_no_vc", 0 * t, dict(volume_conservation=False)),
        ):
            r = sliding_sweep(
                wp,
                tool,
                wp.dx,
                p,
                materials=Materials(H=H, m=m),
                positions=n_pos,
                solver=_solver(kw),
            )
            # steady part: the last half of the positions
            row[f"ratio_{name}"] = float(np.mean(r.ratio[n_pos // 2 :]))
            row[f"alpha_{name}"] = float(np.mean(r.alpha[n_pos // 2 :]))
        rows.append(row)
        print(" ".join(f"{k}={v:.4g}" for k, v in row.items()), flush=True)
    with open(RES / "sliding_decomposition.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def resolution(pressures=(300e6, 600e6)):
    """Steady ratio against the element size: the same surfaces block-averaged to 3n x n."""
    from halfspace_calib import topography as S

    wp0, _ = sliding_surfaces()
    rows = []
    for n in (32, 64, 128):
        wp = S.block_average(wp0, (3 * n, n))
        tl = S.tool_like(n, size=2.11e-3, seed=2, measured_n=128)
        t = tl.heights
        slope = float(np.maximum(t[:-1] - t[1:], 0).mean() / wp.dx)
        n_pos = min(2 * n + 1, 80)
        for p in pressures:
            row = dict(
                n=n,
                dx=wp.dx,
                p_mean=p,
                positions=n_pos,
                Ra_workpiece=S.ra(wp),
                Ra_tool=S.ra(tl),
                tool_slope=slope,
            )
            for name, tool in (("tool", t), ("flat_tool", 0 * t)):
                r = sliding_sweep(wp, tool, wp.dx, p, positions=n_pos)
                row[f"ratio_{name}"] = float(np.mean(r.ratio[n_pos // 2 :]))
            rows.append(row)
            print(" ".join(f"{k}={v:.4g}" for k, v in row.items()), flush=True)
    with open(RES / "sliding_resolution.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="knobs only")
    ap.add_argument("--no-knobs", action="store_true")
    ap.add_argument(
        "--decomposition",
        action="store_true",
        help="only the per-pressure decomposition (tool / flat tool / no vc)",
    )
    ap.add_argument(
        "--resolution", action="store_true", help="only the element-size study (n = 32, 64, 128)"
    )
    ap.add_argument("--workers", type=int, default=1)
    a = ap.parse_args()
    RES.mkdir(parents=True, exist_ok=True)
    print(f"load average {os.getloadavg()}, nproc {os.cpu_count()}", flush=True)
    if a.decomposition:
        decomposition()
        return
    if a.resolution:
        resolution()
        return
    if not a.no_knobs:
        knobs()
    if not a.quick:
        full(a.workers)


if __name__ == "__main__":
    with run_record(__file__):
        main()
