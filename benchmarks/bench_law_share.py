"""Share of the friction law + traction update in a host's Newton iterations (target: <= 5 %).

The figure that matters to a host code is not the law's speed against NumPy but what the law costs
inside one Newton iteration. This script wraps ``frictionlaw.traction_update`` (the law, the
history state and the stick/slip update with its tangent, everything the host calls per contact
node) with a timer and runs

- ``fe_demo`` upsetting with the SBMF law (shipped example parameters), 2,048 and 288 elements,
  the first K of 50 increments;
- the GetFEM ring coupling (``couplings/getfem/ring.py``, Debian's python3-getfem, run by the
  interpreter ``couplings.getfem.compare`` picks) with the SBMF law, the first K of 50 increments;

and reports the law's seconds, the Newton iterations and the law's share of the run's time (both
CPU time of the process, so that the share does not depend on the machine's load). Writes benchmarks/results/law_share.csv.

Run: python benchmarks/bench_law_share.py [K]   (default K = 10)
"""

import csv
import json
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _provenance import run_record

ROOT = Path(__file__).resolve().parents[1]
OUT = Path(__file__).resolve().parent / "results"

_TIMER = """
import json, sys, time
sys.path.insert(0, {root!r})
import frictionlaw
_real = frictionlaw.traction_update
_t = [0.0, 0]
def _timed(*a, **k):
    t0 = time.process_time()
    r = _real(*a, **k)
    _t[0] += time.process_time() - t0
    _t[1] += 1
    return r
"""

_FE = (
    _TIMER
    + """
import fe_demo.solver.contact
fe_demo.solver.contact.traction_update = _timed
from fe_demo.scenes import run_upsetting
run_upsetting("sbmf", nr=4, n_increments=2, reduction=0.02, progress=False)  # JIT warm-up
_t[:] = [0.0, 0]
c0, w0 = time.process_time(), time.perf_counter()
res = run_upsetting("sbmf", nr={nr}, n_increments={k}, reduction=0.5 * {k} / 50, progress=False)
print(json.dumps({{"host": "fe_demo upsetting", "elements": res.info["n_elements"],
    "contact_nodes": int(res.model.contact.nodes.size),
    "newton": res.info["newton_iterations"], "calls": _t[1], "law_s": _t[0],
    "cpu_s": time.process_time() - c0, "wall_s": time.perf_counter() - w0}}))
"""
)

_GF = (
    _TIMER
    + """
frictionlaw.traction_update = _timed
from couplings.getfem import ring as R
R.run(R.RingSetup(law="sbmf", nr=4, increments=2, reduction=0.02))  # JIT warm-up
_t[:] = [0.0, 0]
c0, w0 = time.process_time(), time.perf_counter()
res = R.run(R.RingSetup(law="sbmf", nr={nr}, increments={k}, reduction=0.5 * {k} / 50))
info = res[3]
print(json.dumps({{"host": "GetFEM ring (3D wedge)", "elements": info["n_hexahedra"],
    "contact_nodes": info["n_contact_candidates"],
    "newton": info["newton_iterations"], "calls": _t[1], "law_s": _t[0],
    "cpu_s": time.process_time() - c0, "wall_s": time.perf_counter() - w0}}))
"""
)


def _child(python, code):
    r = subprocess.run([python, "-c", code], capture_output=True, text=True, cwd=ROOT)
    if r.returncode:
        raise RuntimeError(r.stderr[-2000:])
    return json.loads(r.stdout.strip().splitlines()[-1])


def main(k):
    OUT.mkdir(exist_ok=True)
    rows = []
    for nr in (24, 64):
        rows.append(_child(sys.executable, _FE.format(root=str(ROOT), nr=nr, k=k)))
        print(rows[-1], flush=True)
    from couplings.getfem.compare import getfem_missing, getfem_python

    why = getfem_missing()
    if why:
        print(f"GetFEM coupling skipped: {why}")
    else:
        rows.append(_child(getfem_python(), _GF.format(root=str(ROOT), nr=16, k=k)))
        print(rows[-1], flush=True)
    for r in rows:
        r["increments"] = k
        r["law_share_of_cpu"] = r["law_s"] / r["cpu_s"]
        r["law_ms_per_newton"] = 1e3 * r["law_s"] / max(r["newton"], 1)
    with (OUT / "law_share.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print("host  elements  contact nodes  Newton its  law calls  law s  run CPU s  share")
    for r in rows:
        print(
            f"{r['host']}  {r['elements']}  {r['contact_nodes']}  {r['newton']}  {r['calls']}"
            f"  {r['law_s']:.3f}  {r['cpu_s']:.2f}  {100 * r['law_share_of_cpu']:.2f} %"
        )


if __name__ == "__main__":
    with run_record(__file__):
        main(int(sys.argv[1]) if len(sys.argv) > 1 else 10)
