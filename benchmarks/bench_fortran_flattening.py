"""Per-node cost of the flattening in the generated Fortran routine, against the law without it.

The host-neutral entry ``SBMF_FRICTION_V`` (what the ``lsdyna`` and ``ansys-userfric`` targets
ship; gfortran -O2), exported three times from one law (``bench_flattening_runtime.py``'s:
pressures 0.05-0.6 H, half of the points below a history, 2 slip directions): without a
flattening block, with the one-state block (``layer-yield``) and with the two-state block
(``limit-analysis``, its table as DATA). Each routine is called once per point for all points
(``reps = 1``, from a fresh copy of the committed state each round), the three timed in turn in
every round, in CPU time of the calling thread. Cases: no strain (``DEPS = 0`` on a virgin
surface), an increment of 0.002 and one of 0.02 on a virgin surface. Ratios are the case's time
over the routine without a block in the same round (no strain), the median over rounds.

Run: python benchmarks/bench_fortran_flattening.py [--nodes 50000] [--repeat 7]
Writes benchmarks/results/fortran_flattening.csv and prints a table.
"""

import argparse
import re
import tempfile
import time
from pathlib import Path

import numpy as np
from _provenance import RESULTS, run_record, write_rows
from bench_flattening_runtime import P2, H, P

from frictionlaw import export as exp
from frictionlaw.export import harness

LAWS = {"without": P.replace(flattening=None), "one-state": P, "two-state": P2}
CASES = {"no strain": 0.0, "strain 0.002, virgin": 0.002, "strain 0.02, virgin": 0.02}


def _load(params, workdir, name):
    path = workdir / f"{name}.json"
    params.to_json(path)
    files, _ = exp.render("lsdyna", path, units="SI")
    src = {n: t for n, t in files.items() if n.endswith(".f")}
    tag = re.sub(r"[^a-z0-9]", "_", f"bf_{name}")
    host, warnings = exp.target("lsdyna").harness.load(src, workdir / tag, name=tag)
    if "Error" in warnings:
        raise SystemExit(warnings)
    return host


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", type=int, default=50_000, help="contact points (default 50000)")
    ap.add_argument("--repeat", type=int, default=7, help="rounds (default 7)")
    args = ap.parse_args()
    if harness.gfortran() is None:
        raise SystemExit("needs gfortran")
    rng = np.random.default_rng(7)
    n = args.nodes
    p = rng.uniform(0.05, 0.6, n) * H
    ph = np.where(rng.random(n) < 0.5, p * rng.uniform(1.0, 1.5, n), 0.0)
    du = np.tile([1e-3, 5e-4], (n, 1))
    t_old = np.zeros((n, 2))
    state0 = np.zeros((n, 7))
    state0[:, 0] = ph
    times = {}
    with tempfile.TemporaryDirectory() as tmp:
        hosts = {name: _load(params, Path(tmp), name) for name, params in LAWS.items()}
        for r in range(args.repeat):
            for case, de in CASES.items():
                for name, host in hosts.items():
                    if name == "without" and de > 0:
                        continue
                    state = state0.copy()
                    t = time.thread_time()
                    out = host.friction("", p, state, du, t_old, 1e30, deps=de)
                    times.setdefault((case, name), []).append(time.thread_time() - t)
                    if r == 0 and not np.all(out["ierr"] == 0):
                        raise SystemExit(f"{name}, {case}: IERR {set(out['ierr'].tolist())}")
    base = np.array(times[("no strain", "without")])
    rows = []
    for (case, name), ts in times.items():
        ts = np.array(ts)
        rows.append(
            {
                "case": case,
                "routine": name,
                "nodes": n,
                "ns_per_node": round(float(ts.min()) / n * 1e9, 1),
                "ratio_to_without": round(float(np.median(ts / base)), 2),
            }
        )
    RESULTS.mkdir(exist_ok=True)
    write_rows(RESULTS / "fortran_flattening.csv", rows)
    print(f"{n} points, best of {args.repeat}; ratio: median over rounds of the round's ratio")
    print(f"{'case':24} {'routine':10} {'ns/point':>9} {'ratio':>6}")
    for r in rows:
        print(
            f"{r['case']:24} {r['routine']:10} {r['ns_per_node']:9.1f} {r['ratio_to_without']:6.2f}"
        )


if __name__ == "__main__":
    with run_record(__file__):
        main()
