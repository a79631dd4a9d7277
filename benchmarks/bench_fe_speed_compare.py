"""Before/after timing of the default upsetting run: this tree against an earlier one, interleaved.

Timings on a shared machine drift with its load, so each mesh runs the earlier code and this code
back to back (each in its own process, CPU time measured there), and the table reports their
ratio. The earlier tree is a plain copy of an earlier commit, e.g.::

    git archive 2e71c61 | tar -x -C /tmp/before
    python benchmarks/bench_fe_speed_compare.py /tmp/before 24 64 100 200:10

``NR:K`` runs only the first K of the 50 increments (same step size; the 20,000-element case at
K = 10 keeps the run affordable). Writes benchmarks/results/fe_speed_compare.csv and prints a table.
"""

import csv
import json
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _provenance import run_record

HERE = Path(__file__).resolve().parents[1]
OUT = Path(__file__).resolve().parent / "results"

_CHILD = """
import json, sys, time
sys.path.insert(0, {root!r})
from fe_demo.scenes import run_upsetting
run_upsetting("sbmf", nr=4, n_increments=2, reduction=0.02, progress=False)  # numba load
c0 = time.process_time()
res = run_upsetting("sbmf", nr={nr}, n_increments={k}, reduction=0.5 * {k} / 50, progress=False)
cpu = time.process_time() - c0
tm = res.info["timings"]
print(json.dumps({{
    "elements": res.info["n_elements"], "newton": res.info["newton_iterations"],
    "factorisations": res.info.get("linear_solver", {{}}).get("factorisations",
                                                             res.info["newton_iterations"]),
    "cpu_s": cpu, "wall_s": res.wall_time, "solve_s": tm["solve"],
    "assembly_s": tm["assembly"], "kin_material_s": tm["kinematics"] + tm["material"],
    "force_N": float(res.history["force"][-1]), "converged": bool(res.converged),
}}))
"""


def _run(root, nr, k):
    code = _CHILD.format(root=str(root), nr=nr, k=k)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(before, specs):
    OUT.mkdir(exist_ok=True)
    rows = []
    for spec in specs:
        nr, _, k = spec.partition(":")
        nr, k = int(nr), int(k or 50)
        b = _run(before, nr, k)
        a = _run(HERE, nr, k)
        row = {"nr": nr, "elements": a["elements"], "increments": k}
        for tag, r in (("before", b), ("after", a)):
            for key in (
                "newton",
                "factorisations",
                "cpu_s",
                "solve_s",
                "kin_material_s",
                "assembly_s",
                "wall_s",
                "force_N",
            ):
                row[f"{key}_{tag}"] = round(r[key], 4) if isinstance(r[key], float) else r[key]
        row["cpu_ratio"] = round(b["cpu_s"] / a["cpu_s"], 2)
        row["force_rel_diff"] = abs(a["force_N"] - b["force_N"]) / abs(b["force_N"])
        rows.append(row)
        print(row, flush=True)
    with (OUT / "fe_speed_compare.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(
        "elements  increments  newton(b/a)  LU(b/a)  CPU s (b/a)  solve s (b/a)  ratio  force diff"
    )
    for r in rows:
        print(
            f"{r['elements']:8d}  {r['increments']:10d}  {r['newton_before']}/{r['newton_after']}"
            f"  {r['factorisations_before']}/{r['factorisations_after']}"
            f"  {r['cpu_s_before']:.1f}/{r['cpu_s_after']:.1f}"
            f"  {r['solve_s_before']:.1f}/{r['solve_s_after']:.1f}"
            f"  {r['cpu_ratio']:.2f}  {r['force_rel_diff']:.1e}"
        )


if __name__ == "__main__":
    with run_record(__file__):
        if len(sys.argv) < 2:
            raise SystemExit(__doc__)
        main(Path(sys.argv[1]), sys.argv[2:] or ["24", "64", "100", "200:10"])
