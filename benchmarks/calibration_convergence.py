"""Speed against accuracy of the calibration: grid resolution and solver tolerance.

The same physical surfaces (generated on a 1024 x 1024 "measurement" grid and block-averaged to the
solver grid) are calibrated at 64, 128, 256, 512 and 1024 squared with two solver tolerances. For each run
the table gives C1, n1, C2, n2, the law's shear at 100, 300 and 600 MPa (first loading) and at
100 MPa after loading to 600 MPa (reload), the deviation of those shears from the finest run, and
the wall time.

Run: python benchmarks/calibration_convergence.py [--grids 64,128,256,512] [--tols 1e-6,1e-8]
Writes benchmarks/results/calibration_convergence.csv / .md / .png and prints the table.
"""

import argparse
import csv
import os
import time
from pathlib import Path

import numpy as np
from _provenance import run_record

from frictionlaw import shear_limit
from halfspace_calib.pipeline.calibration import Scene, calibrate

RESULTS = Path(__file__).parent / "results"
PROBES = [(100e6, 0.0), (300e6, 0.0), (600e6, 0.0), (100e6, 600e6)]
PROBE_NAMES = ["tau_100", "tau_300", "tau_600", "tau_100_after_600"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grids", default="64,128,256,512,1024")
    ap.add_argument("--tols", default="1e-6,1e-8")
    ap.add_argument("--measured-n", type=int, default=1024)
    ap.add_argument("--workers", type=int, default=1)
    args = ap.parse_args(argv)
    grids = [int(g) for g in args.grids.split(",")]
    tols = [float(t) for t in args.tols.split(",")]
    rows = []
    for tol in tols:
        for n in grids:
            t0 = time.perf_counter()
            cal = calibrate(
                Scene(grid=n, measured_n=args.measured_n, tol=tol, workers=args.workers),
                progress=False,
            )
            dt = time.perf_counter() - t0
            P = cal.params
            taus = [float(shear_limit(p, ph, P)) for p, ph in PROBES]
            rows.append(
                {
                    "grid": n,
                    "tol": tol,
                    "C1": P.C1,
                    "n1": P.n1,
                    "C2": P.C2,
                    "n2": P.n2,
                    **dict(zip(PROBE_NAMES, taus, strict=True)),
                    "seconds": dt,
                    "r2_first": cal.first.r_squared,
                    "r2_reload": cal.reload.r_squared,
                }
            )
            print(
                f"grid {n:4d} tol {tol:.0e}: {dt:7.1f} s  C1={P.C1:.4f} n1={P.n1:.3f} "
                f"C2={P.C2:.3f} n2={P.n2:.3f}",
                flush=True,
            )
    ref = max(rows, key=lambda r: (r["grid"], -r["tol"]))
    for r in rows:
        r["max_dev_tau"] = max(abs(r[k] / ref[k] - 1) for k in PROBE_NAMES)
    RESULTS.mkdir(exist_ok=True)
    with open(RESULTS / "calibration_convergence.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    lines = [
        f"Reference: grid {ref['grid']}, tol {ref['tol']:.0e}. Shears in MPa (m = 0.5, k = H/5.6).",
        f"Machine: {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f} at the end.",
        "",
        "| grid | tol | C1 | n1 | C2 | n2 | tau(100) | tau(300) | tau(600) | tau(100 after 600) "
        "| max dev. of tau | wall time [s] |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['grid']} | {r['tol']:.0e} | {r['C1']:.4f} | {r['n1']:.3f} | {r['C2']:.3f} | "
            f"{r['n2']:.3f} | {r['tau_100'] / 1e6:.2f} | {r['tau_300'] / 1e6:.2f} | "
            f"{r['tau_600'] / 1e6:.2f} | {r['tau_100_after_600'] / 1e6:.2f} | "
            f"{100 * r['max_dev_tau']:.2f} % | {r['seconds']:.1f} |"
        )
    text = "\n".join(lines) + "\n"
    (RESULTS / "calibration_convergence.md").write_text(text)
    print(text)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for tol in tols:
        sel = [r for r in rows if r["tol"] == tol]
        g = np.array([r["grid"] for r in sel])
        for k, mk in zip(PROBE_NAMES, "osd^", strict=True):
            axes[0].semilogx(
                g, [r[k] / 1e6 for r in sel], mk + "-", base=2, label=f"{k}, tol {tol:.0e}"
            )
        axes[1].loglog(g, [r["seconds"] for r in sel], "o-", base=2, label=f"tol {tol:.0e}")
    axes[0].set(xlabel="grid N (N x N)", ylabel="tau [MPa]", title="Calibrated law's shear")
    axes[1].set(xlabel="grid N (N x N)", ylabel="wall time [s]", title="Calibration time")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(RESULTS / "calibration_convergence.png", dpi=120)


if __name__ == "__main__":
    with run_record(__file__):
        main()
