"""Throughput of the runtime law: NumPy reference vs numba serial vs numba parallel.

For 1e3 ... 1e7 contact nodes: `shear_limit` with a per-node `p_hist` and the 2-direction traction
update (with state), after JIT warm-up, best of several repeats. The baseline is a memory copy that
moves the same number of bytes (read + write) in the same run, so ratios hold on a noisy machine.

Run: python benchmarks/bench_runtime.py [--max-exp 7] [--repeat 5]
Writes benchmarks/results/runtime.csv and prints a table.
"""

import argparse
import os
import time
from pathlib import Path

import numba
import numpy as np
from _provenance import run_record, write_rows

import frictionlaw as fl
from frictionlaw import _reference as ref
from frictionlaw import kernels as K

H = 800e6
P = fl.FrictionParams(m=0.7, sigma_y=H / 2.8, H=H, C1=1.0, n1=2.0, C2=2.5, n2=2.0)


def best(fn, repeat):
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def case(n, rng):
    p = rng.uniform(0, 1.2 * H, n)
    ph = rng.uniform(0, 1.2 * H, n)
    du = rng.normal(size=(n, 2)) * 1e-6
    t_old = rng.normal(size=(n, 2)) * 3e7
    kt = np.full(n, 1e13)
    return p, ph, du, t_old, kt


def shear_runs(n, p, ph, repeat):
    law = fl.SBMFLaw(P)
    coeffs = law.coeffs
    tau, dtau = np.empty(n), np.empty(n)
    src = np.empty(2 * n)  # traffic: read p, p_hist (16 B), write tau, dtau (16 B) = copy of 16 B
    dst = np.empty(2 * n)
    return {
        "numpy": best(lambda: ref.sbmf_shear(p, ph, P.tau_max, P.C1, P.n1, P.C2, P.n2, H), repeat),
        "numba_serial": best(lambda: K.shear_array(3, coeffs, p, ph, tau, dtau), repeat),
        "numba_parallel": best(lambda: K.shear_array_parallel(3, coeffs, p, ph, tau, dtau), repeat),
        # the array kernel always writes into the caller's buffers
        "numba_parallel_out": best(
            lambda: K.shear_array_parallel(3, coeffs, p, ph, tau, dtau), repeat
        ),
        "memcopy": best(lambda: np.copyto(dst, src), repeat),
    }


def traction_runs(n, p, ph, du, t_old, kt, repeat):
    law = fl.SBMFLaw(P)
    state = fl.HistoryState(p_hist=ph)

    def numpy_ref():
        tau = ref.sbmf_shear(p, ph, P.tau_max, P.C1, P.n1, P.C2, P.n2, H)
        return ref.traction_update(np.where(p > 0, tau, np.nan), du, t_old, kt), np.maximum(ph, p)

    # traffic: read p, p_hist, du(2), t_old(2), k_t = 56 B; write t(2), status, tangent(4), dt_dp(2),
    # p_trial = 73 B; total 129 B/node = a copy of ~64 B/node (8 float64)
    src = np.empty(8 * n)
    dst = np.empty(8 * n)
    out = fl.traction_update(law, p, du, t_old, kt, state)
    return {
        "numpy": best(numpy_ref, repeat),
        "numba_serial": best(
            lambda: fl.traction_update(law, p, du, t_old, kt, state, parallel=False), repeat
        ),
        "numba_parallel": best(
            lambda: fl.traction_update(law, p, du, t_old, kt, state, parallel=True), repeat
        ),
        # the host keeps its output arrays between calls (out=): no allocation per call
        "numba_parallel_out": best(
            lambda: fl.traction_update(law, p, du, t_old, kt, state, parallel=True, out=out), repeat
        ),
        "memcopy": best(lambda: np.copyto(dst, src), repeat),
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max-exp", type=int, default=7)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", default=str(Path(__file__).parent / "results" / "runtime.csv"))
    args = ap.parse_args(argv)
    rng = np.random.default_rng(0)
    rows = []
    print(f"threads: numba {numba.get_num_threads()}, cpus {os.cpu_count()}")
    hdr = (
        f"{'op':9} {'nodes':>9} {'numpy':>11} {'nb serial':>11} {'nb parallel':>11} {'par, out=':>11} "
        f"{'memcopy':>11} {'par/numpy':>9} {'par/copy':>8}   (Mnodes/s; ratios for 'par, out=')"
    )
    print(hdr)
    for e in range(3, args.max_exp + 1):
        n = 10**e
        p, ph, du, t_old, kt = case(n, rng)
        rep = args.repeat if n <= 10**6 else max(2, args.repeat // 2)
        for op, t in (
            ("shear", shear_runs(n, p, ph, rep)),
            ("traction", traction_runs(n, p, ph, du, t_old, kt, rep)),
        ):
            row = {"op": op, "nodes": n, **{f"t_{k}": v for k, v in t.items()}}
            row["speedup_parallel_vs_numpy"] = t["numpy"] / t["numba_parallel_out"]
            row["parallel_over_memcopy"] = t["numba_parallel_out"] / t["memcopy"]
            rows.append(row)
            mn = {k: n / v / 1e6 for k, v in t.items()}
            print(
                f"{op:9} {n:9.0e} {mn['numpy']:11.1f} {mn['numba_serial']:11.1f} "
                f"{mn['numba_parallel']:11.1f} {mn['numba_parallel_out']:11.1f} {mn['memcopy']:11.1f} "
                f"{row['speedup_parallel_vs_numpy']:9.1f} {row['parallel_over_memcopy']:8.2f}"
            )
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_rows(out, rows)
    print(f"wrote {out}")


if __name__ == "__main__":
    with run_record(__file__):
        main()
