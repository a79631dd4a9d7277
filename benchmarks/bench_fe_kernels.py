"""FE speed: NumPy kernels + SuperLU (the baseline) against numba kernels and PARDISO, one run.

Issue 23, item 6. Cylinder upsetting D0 = 20 mm, h0 = 10 mm, Tresca m = 0.3, 50 increments to
50 % height reduction, at each ``nr`` (elements of the half model: nr=64: 2,048, 100: 5,000,
200: 20,000). For each mesh the configurations run back to back in this one process (after one
small warm-up run of each, so numba's and MKL's first-call costs are not timed):

- ``numpy+superlu``: ``SolverOptions(kernels="numpy", linear_solver="superlu")``, the code before
  this change (vectorised NumPy element loops, SuperLU with factorisation reuse);
- ``numba+superlu``: numba element loops and return map (fe_demo/solver/_kernels.py), the free-dof tangent
  scattered straight into a fixed CSC pattern, SuperLU;
- ``numba+pardiso``: the same with MKL PARDISO (one thread), if pypardiso is installed.

Reports wall and CPU time (``time.process_time``), the phase times the model records, Newton
iterations, factorisations, the speed-up as CPU and wall ratios to the baseline of the same mesh,
and the force at 50 % with its relative difference to the baseline's. The machine is shared
(2 cores): ratios within one run are the measure, absolute seconds depend on the load (the load
average before and after each run is recorded). Writes benchmarks/results/fe_kernels.csv and
fe_kernels.md.

Run: python benchmarks/bench_fe_kernels.py [--configs a,b,c] [nr ...]   (default nr: 64 100 200)
"""

import csv
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _provenance import run_record

from fe_demo.scenes import run_upsetting  # noqa: E402
from fe_demo.solver.linsolve import pardiso_available  # noqa: E402
from fe_demo.solver.model import SolverOptions  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"

CONFIGS = {
    "numpy+superlu": {"kernels": "numpy", "linear_solver": "superlu"},
    "numba+superlu": {"kernels": "numba", "linear_solver": "superlu"},
    "numba+pardiso": {"kernels": "numba", "linear_solver": "pardiso"},
}


def _run(nr, opts, n_inc=50):
    la0 = os.getloadavg()[0]
    c0 = time.process_time()
    w0 = time.perf_counter()
    res = run_upsetting("tresca", m=0.3, nr=nr, n_increments=n_inc, options=SolverOptions(**opts))
    wall = time.perf_counter() - w0
    cpu = time.process_time() - c0
    return res, wall, cpu, la0, os.getloadavg()[0]


def main(nrs, configs):
    OUT.mkdir(exist_ok=True)
    for name in configs:  # warm-up: numba's cache load, MKL's first call
        _run(8, CONFIGS[name], 5)
    rows = []
    for nr in nrs:
        base = None
        for name in configs:
            res, wall, cpu, la0, la1 = _run(nr, CONFIGS[name])
            tm = res.info["timings"]
            force = float(res.history["force"][-1])
            row = {
                "nr": nr,
                "elements": res.info["n_elements"],
                "config": name,
                "converged": res.converged,
                "newton": res.info["newton_iterations"],
                "factorisations": res.info["linear_solver"]["factorisations"],
                "wall_s": round(wall, 2),
                "cpu_s": round(cpu, 2),
                "kinematics_s": round(tm["kinematics"], 2),
                "material_s": round(tm["material"], 2),
                "assembly_s": round(tm["assembly"], 2),
                "solve_s": round(tm["solve"], 2),
                "contact_s": round(tm["contact"], 2),
                "force_kN": round(force / 1e3, 6),
                "load_before": round(la0, 2),
                "load_after": round(la1, 2),
            }
            if base is None:
                base = (cpu, wall, force)
            row["cpu_speedup"] = round(base[0] / cpu, 2)
            row["wall_speedup"] = round(base[1] / wall, 2)
            row["force_rel_diff"] = f"{abs(force - base[2]) / abs(base[2]):.1e}"
            rows.append(row)
            print(row, flush=True)
            _write(rows)
    keys = list(rows[0])
    print("  ".join(keys))
    for r in rows:
        print("  ".join(str(r[k]) for k in keys))


def _write(rows):
    keys = list(rows[0])
    with (OUT / "fe_kernels.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    lines = [
        "| elements | configuration | Newton its | factorisations | CPU (s) | wall (s) "
        "| CPU speed-up | wall speed-up | kinematics (s) | material | assembly | solve | contact "
        "| force at 50 % (kN) | force vs baseline |",
        "|" + "---|" * 15,
    ]
    for r in rows:
        lines.append(
            f"| {r['elements']:,} | {r['config']} | {r['newton']} | {r['factorisations']} "
            f"| {r['cpu_s']} | {r['wall_s']} | {r['cpu_speedup']}x | {r['wall_speedup']}x "
            f"| {r['kinematics_s']} | {r['material_s']} | {r['assembly_s']} | {r['solve_s']} "
            f"| {r['contact_s']} | {r['force_kN']:.3f} | {r['force_rel_diff']} |"
        )
    (OUT / "fe_kernels.md").write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    with run_record(__file__):
        argv = sys.argv[1:]
        names = list(CONFIGS) if pardiso_available() else list(CONFIGS)[:2]
        if "--configs" in argv:
            i = argv.index("--configs")
            names = argv[i + 1].split(",")
            del argv[i : i + 2]
            if unknown := set(names) - set(CONFIGS):
                raise SystemExit(
                    f"unknown configurations {sorted(unknown)}; known: {list(CONFIGS)}"
                )
        main([int(a) for a in argv] or [64, 100, 200], names)
