"""Speed of the default upsetting run and its scaling with the element count.

Cylinder D0 = 20 mm, h0 = 10 mm to 50 % height reduction in 50 increments with the
SBMF law (shipped example parameters). Reports wall and CPU time, Newton iterations
and where the time goes (kinematics + return map, assembly, sparse solve, contact),
and the scaling exponent of time against elements (ratios to the smallest mesh of
the same run), and how many tangents were factorised (the rest were solved by GMRES
preconditioned with the last factorisation, fe_demo/solver/linsolve.py). Writes
benchmarks/results/fe_speed.csv.

Run: python benchmarks/bench_fe_speed.py [--first K] [--fresh-lu] [nr ...]
(default nr: 24 48 64 100 200). ``--first K`` runs only the first K of the 50 increments (the
same step size, to 0.5 K / 50 reduction), to keep the 20,000-element case affordable;
``--fresh-lu`` factorises every tangent (the reference linear solve).
Element counts of the half model: nr=24: 288, 48: 1,152, 64: 2,048, 100: 5,000, 200: 20,000.
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


def main(nrs, first=50, fresh_lu=False):
    OUT.mkdir(exist_ok=True)
    rows = []
    opts = SolverOptions(reuse_factorisation=not fresh_lu)
    for nr in nrs:
        c0 = time.process_time()
        res = run_upsetting(
            "sbmf", nr=nr, n_increments=first, reduction=0.5 * first / 50, options=opts
        )
        cpu = time.process_time() - c0
        tm = res.info["timings"]
        rows.append(
            {
                "nr": nr,
                "elements": res.info["n_elements"],
                "dofs": res.info["n_dof"],
                "converged": res.converged,
                "increments": first,
                "newton": res.info["newton_iterations"],
                "factorisations": res.info["linear_solver"]["factorisations"],
                "cutbacks": len(res.info["cutback_log"]),
                "wall_s": round(res.wall_time, 2),
                "cpu_s": round(cpu, 2),
                "kin_material_s": round(tm["kinematics"] + tm["material"], 2),
                "assembly_s": round(tm["assembly"], 2),
                "solve_s": round(tm["solve"], 2),
                "contact_s": round(tm["contact"], 2),
                "force_kN": round(float(res.history["force"][-1]) / 1e3, 4),
            }
        )
        print(rows[-1], flush=True)
    base = rows[0]
    for r in rows:
        r["cpu_ratio"] = round(r["cpu_s"] / base["cpu_s"], 2)
    el = np.array([r["elements"] for r in rows], float)
    cpu = np.array([r["cpu_s"] for r in rows], float)
    slope = np.polyfit(np.log(el), np.log(cpu), 1)[0] if len(rows) > 1 else float("nan")
    name = (
        "fe_speed" + ("_fresh_lu" if fresh_lu else "") + (f"_first{first}" if first != 50 else "")
    )
    with (OUT / f"{name}.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    keys = list(rows[0])
    print("  ".join(keys))
    for r in rows:
        print("  ".join(str(r[k]) for k in keys))
    print(f"CPU time ~ elements^{slope:.2f}")


if __name__ == "__main__":
    with run_record(__file__):
        argv = sys.argv[1:]
        first, fresh = 50, "--fresh-lu" in argv
        argv = [a for a in argv if a != "--fresh-lu"]
        if "--first" in argv:
            i = argv.index("--first")
            first = int(argv[i + 1])
            del argv[i : i + 2]
            if not 1 <= first <= 50:
                raise SystemExit("--first must be in 1..50")
        main([int(a) for a in argv] or [24, 48, 64, 100, 200], first, fresh)
