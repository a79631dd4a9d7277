"""NumPy's ufuncs against numba loops for the law's transcendental functions, and numba's SVML state.

The runtime law spends its time in ``exp``, ``log``, ``expm1``, ``log1p``, ``tanh``. This measures,
per 1e7 doubles (best of 5, CPU seconds of this process), NumPy's ufunc and a numba loop (serial,
explicit signature, no fastmath, as in ``frictionlaw/_kernels.py``), and prints whether numba uses
Intel's SVML (vectorised math) here. Writes benchmarks/results/transcendentals.csv.

Run: python benchmarks/bench_transcendentals.py
"""

import csv
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import llvmlite  # noqa: E402
import numba  # noqa: E402
from _provenance import run_record  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"
N = 10_000_000


def _loop(fn):
    @numba.njit("void(float64[::1], float64[::1])", cache=False)
    def kernel(x, out):
        for i in range(x.size):
            out[i] = fn(x[i])

    return kernel


FUNCS = {
    "exp": (np.exp, math.exp, (-5.0, 5.0)),
    "log": (np.log, math.log, (1e-3, 1e3)),
    "expm1": (np.expm1, math.expm1, (-1.0, 1.0)),
    "log1p": (np.log1p, math.log1p, (-0.5, 5.0)),
    "tanh": (np.tanh, math.tanh, (-3.0, 3.0)),
}


def _best(f, repeat=5):
    best = math.inf
    for _ in range(repeat):
        t0 = time.process_time()
        f()
        best = min(best, time.process_time() - t0)
    return best


def main():
    OUT.mkdir(exist_ok=True)
    svml = bool(getattr(numba.config, "USING_SVML", False))
    print(
        f"numba {numba.__version__}, llvmlite {llvmlite.__version__} "
        f"(LLVM {'.'.join(map(str, llvmlite.binding.llvm_version_info))}), "
        f"numba.config.USING_SVML = {svml}"
    )
    rng = np.random.default_rng(0)
    rows = []
    for name, (ufunc, mfn, (lo, hi)) in FUNCS.items():
        x = rng.uniform(lo, hi, N)
        out = np.empty_like(x)
        kernel = _loop(mfn)
        kernel(x[:10], out[:10])  # compile
        t_np = _best(lambda u=ufunc, x=x, out=out: u(x, out=out))
        ref = out.copy()
        t_nb = _best(lambda k=kernel, x=x, out=out: k(x, out))
        err = float(np.max(np.abs(out - ref) / np.maximum(np.abs(ref), 1e-300)))
        rows.append(
            {
                "function": name,
                "n": N,
                "numpy_ms": round(1e3 * t_np, 1),
                "numba_ms": round(1e3 * t_nb, 1),
                "numba_over_numpy": round(t_nb / t_np, 2),
                "max_rel_diff": err,
                "numba_svml": svml,
            }
        )
        print(rows[-1], flush=True)
    with (OUT / "transcendentals.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print("function  NumPy ms  numba ms  numba/NumPy  (per 1e7 doubles)")
    for r in rows:
        print(
            f"{r['function']:8s}  {r['numpy_ms']:8.1f}  {r['numba_ms']:8.1f}  "
            f"{r['numba_over_numpy']:.2f}"
        )


if __name__ == "__main__":
    with run_record(__file__):
        main()
