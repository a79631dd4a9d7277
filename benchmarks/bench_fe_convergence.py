"""Mesh and increment convergence of the upsetting force at 30 % height reduction.

Tresca m = 0.3, D0 = 20 mm, h0 = 10 mm. Writes benchmarks/results/fe_convergence.csv,
fe_convergence.png and prints the tables. Run: python benchmarks/bench_fe_convergence.py
"""

import csv
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _provenance import run_record

from fe_demo.scenes import run_upsetting  # noqa: E402
from fe_demo.solver.model import SolverOptions  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"
MESHES = (8, 16, 32, 64)
INCREMENTS = (8, 15, 30, 60)


def run(nr, n_inc, **opt):
    c0 = time.process_time()
    res = run_upsetting(
        "tresca", m=0.3, nr=nr, n_increments=n_inc, reduction=0.3, options=SolverOptions(**opt)
    )
    cpu = time.process_time() - c0
    assert res.converged, res.message
    h = res.history
    return {
        "nr": nr,
        "elements": res.info["n_elements"],
        "increments": n_inc,
        "force_kN": h["force"][-1] / 1e3,
        "avg_pressure_MPa": h["avg_pressure"][-1] / 1e6,
        "newton": res.info["newton_iterations"],
        "wall_s": res.wall_time,
        "cpu_s": cpu,
        "penalty_factor": opt.get("penalty_factor", 10.0),
        "rtol": opt.get("rtol", 1e-6),
    }


def rates(rows, key):
    f = np.array([r["force_kN"] for r in rows])
    d = np.abs(np.diff(f))
    out = [float("nan")] * 2 + list(np.log2(d[:-1] / d[1:]))
    return d, out


def main():
    OUT.mkdir(exist_ok=True)
    mesh_rows = [run(nr, 30) for nr in MESHES]
    inc_rows = [run(32, n) for n in INCREMENTS]
    pen_rows = [run(32, 30, penalty_factor=f) for f in (1.0, 10.0, 100.0)]
    tol_rows = [run(32, 30, rtol=t) for t in (1e-4, 1e-6, 1e-8)]
    with (OUT / "fe_convergence.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=["study", *mesh_rows[0]])
        w.writeheader()
        for r in mesh_rows:
            w.writerow({"study": "mesh", **r})
        for r in inc_rows:
            w.writerow({"study": "increments", **r})
        for r in pen_rows:
            w.writerow({"study": "penalty_factor", **r})
        for r in tol_rows:
            w.writerow({"study": "rtol", **r})
    for name, rows in (("mesh (30 increments)", mesh_rows), ("increments (nr=32)", inc_rows)):
        d, rate = rates(rows, "force_kN")
        print(f"\n{name}")
        print("nr  elements  incr  force_kN   |dF|_kN   order  newton  wall_s  cpu_s")
        for i, r in enumerate(rows):
            dd = f"{d[i - 1]:.3f}" if i else "-"
            print(
                f"{r['nr']:<3} {r['elements']:<9} {r['increments']:<5} {r['force_kN']:<10.3f} "
                f"{dd:<9} {rate[i]:<6.2f} {r['newton']:<7} {r['wall_s']:<7.2f} {r['cpu_s']:.2f}"
            )
    for name, rows, key in (("penalty", pen_rows, "penalty_factor"), ("rtol", tol_rows, "rtol")):
        print(f"\n{name} (nr=32, 30 increments)")
        print(f"{key:<15} force_kN    newton  cpu_s")
        for r in rows:
            print(f"{r[key]:<15g} {r['force_kN']:<11.4f} {r['newton']:<7} {r['cpu_s']:.2f}")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    f_ref = mesh_rows[-1]["force_kN"]
    h = [1 / r["nr"] for r in mesh_rows[:-1]]
    e = [abs(r["force_kN"] - f_ref) / f_ref for r in mesh_rows[:-1]]
    a1.loglog(h, e, "o-", label="|F - F(nr=64)| / F(nr=64)")
    a1.loglog(h, [e[0] * (x / h[0]) for x in h], "k--", lw=0.7, label="order 1")
    a1.set_xlabel("1 / nr")
    a1.set_ylabel("relative force error at 30 %")
    a1.legend()
    a2.plot([r["wall_s"] for r in mesh_rows], [r["force_kN"] for r in mesh_rows], "o-")
    for r in mesh_rows:
        a2.annotate(f"{r['elements']} el", (r["wall_s"], r["force_kN"]), fontsize=8)
    a2.set_xscale("log")
    a2.set_xlabel("wall time (s)")
    a2.set_ylabel("force at 30 % (kN)")
    for a in (a1, a2):
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(OUT / "fe_convergence.png", dpi=120)


if __name__ == "__main__":
    with run_record(__file__):
        main()
