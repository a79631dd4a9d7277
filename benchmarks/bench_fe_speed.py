"""Speed of the default upsetting run and its scaling with the element count.

Cylinder D0 = 20 mm, h0 = 10 mm to 50 % height reduction in 50 increments with the
SBMF law (shipped example parameters). Reports wall and CPU time, Newton iterations
and where the time goes (kinematics + return map, assembly, sparse solve, contact),
and the scaling exponent of time against elements (ratios to the smallest mesh of
the same run). Writes benchmarks/results/fe_speed.csv.

Run: python benchmarks/bench_fe_speed.py [nr ...]   (default: 24 48 64 100 200)
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

OUT = Path(__file__).resolve().parent / "results"


def main(nrs):
    OUT.mkdir(exist_ok=True)
    rows = []
    for nr in nrs:
        c0 = time.process_time()
        res = run_upsetting("sbmf", nr=nr, n_increments=50, reduction=0.5)
        cpu = time.process_time() - c0
        tm = res.info["timings"]
        rows.append(
            {
                "nr": nr,
                "elements": res.info["n_elements"],
                "dofs": res.info["n_dof"],
                "converged": res.converged,
                "newton": res.info["newton_iterations"],
                "cutbacks": len(res.info["cutback_log"]),
                "wall_s": round(res.wall_time, 2),
                "cpu_s": round(cpu, 2),
                "kin_material_s": round(tm["kinematics"] + tm["material"], 2),
                "assembly_s": round(tm["assembly"], 2),
                "solve_s": round(tm["solve"], 2),
                "contact_s": round(tm["contact"], 2),
                "force_kN": round(float(res.history["force"][-1]) / 1e3, 3),
            }
        )
        print(rows[-1], flush=True)
    base = rows[0]
    for r in rows:
        r["cpu_ratio"] = round(r["cpu_s"] / base["cpu_s"], 2)
    el = np.array([r["elements"] for r in rows], float)
    cpu = np.array([r["cpu_s"] for r in rows], float)
    slope = np.polyfit(np.log(el), np.log(cpu), 1)[0] if len(rows) > 1 else float("nan")
    with (OUT / "fe_speed.csv").open("w", newline="") as fh:
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
        args = [int(a) for a in sys.argv[1:]] or [24, 48, 64, 100, 200]
        main(args)
