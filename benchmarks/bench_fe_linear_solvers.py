"""The upsetting tangent's linear solve: SuperLU orderings, a reused factorisation, what else is there.

Takes the Newton tangents of the first increment of the default upsetting run (SBMF law) at
``nr`` (default 200: 20,000 elements, 40,300 free dofs) and times, in CPU seconds (best of 3):

- ``splu`` with each ``permc_spec`` (``MMD_AT_PLUS_A``, ``MMD_ATA``, ``COLAMD``; ``NATURAL`` is
  hopeless on a 2D mesh and left out), its fill ``nnz(L) + nnz(U)``, and with
  ``SymmetricMode`` (no row pivoting off the diagonal);
- one triangular solve with an existing factorisation;
- the project's :class:`fe_demo.solver.linsolve.TangentSolver` over the increment's sequence of tangents,
  against a fresh factorisation per tangent;

and checks every answer's relative residual. With pypardiso installed (the optional extra
``pardiso``, Intel MKL) also MKL PARDISO as fe_demo uses it (one thread, METIS): the analysis, a
numerical factorisation (symmetric indefinite when the tangent is symmetric to rounding, as
Tresca's are; unsymmetric otherwise), one solve, and the sequence with ``backend="pardiso"``.
Whether scikit-umfpack imports is printed (it builds from source against SuiteSparse and needs
swig). Writes benchmarks/results/fe_linear_solvers.csv (``--law tresca``:
fe_linear_solvers_tresca.csv).

Run: python benchmarks/bench_fe_linear_solvers.py [--law sbmf|tresca] [nr]
"""

import csv
import importlib.util
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _provenance import run_record
from scipy.sparse.linalg import splu

import fe_demo.solver.model as M
from fe_demo.scenes import run_upsetting
from fe_demo.solver.linsolve import TangentSolver, _Pardiso, pardiso_available
from fe_demo.solver.model import SolverOptions

OUT = Path(__file__).resolve().parent / "results"


def _best(f, repeat=3):
    best, out = math.inf, None
    for _ in range(repeat):
        t0 = time.process_time()
        out = f()
        best = min(best, time.process_time() - t0)
    return best, out


def _tangents(nr, law):
    """The tangents (and right-hand sides) of the run's first increment."""
    seen = []
    real = M.TangentSolver.solve

    def grab(self, K, b):
        seen.append((K.copy(), b.copy()))
        return real(self, K, b)

    M.TangentSolver.solve = grab
    try:
        run_upsetting(
            law,
            nr=nr,
            n_increments=1,
            reduction=0.01,
            progress=False,
            options=SolverOptions(linear_solver="superlu"),  # CSC tangents
        )
    finally:
        M.TangentSolver.solve = real
    return seen


def main(nr, law="sbmf"):
    OUT.mkdir(exist_ok=True)
    seq = _tangents(nr, law)
    K, b = seq[-1]
    n = K.shape[0]
    rows = []

    def res(x, A=K, rhs=b):
        return float(np.linalg.norm(A @ x - rhs) / np.linalg.norm(rhs))

    for spec in ("MMD_AT_PLUS_A", "MMD_ATA", "COLAMD"):
        t, lu = _best(lambda s=spec: splu(K, permc_spec=s))
        rows.append(
            {
                "method": f"splu {spec}",
                "cpu_s": t,
                "fill": lu.L.nnz + lu.U.nnz,
                "residual": res(lu.solve(b)),
            }
        )
    t, lu = _best(
        lambda: splu(
            K,
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    )
    rows.append(
        {
            "method": "splu MMD_AT_PLUS_A, SymmetricMode, no pivoting",
            "cpu_s": t,
            "fill": lu.L.nnz + lu.U.nnz,
            "residual": res(lu.solve(b)),
        }
    )
    lu = splu(K, permc_spec="MMD_AT_PLUS_A")
    t, x = _best(lambda: lu.solve(b))
    rows.append({"method": "triangular solve only", "cpu_s": t, "fill": 0, "residual": res(x)})
    if pardiso_available():
        p = _Pardiso(threads=1)
        t0 = time.process_time()
        p.factorize(K)
        first = time.process_time() - t0
        t, _ = _best(lambda: p.factorize(K))
        kind = "symmetric indefinite" if p.symmetric else "unsymmetric"
        rows.append(
            {
                "method": "pardiso analysis (METIS, once per pattern) + first factorisation",
                "cpu_s": first,
                "fill": 0,
                "residual": res(p.solve(b)),
            }
        )
        rows.append(
            {
                "method": f"pardiso numerical factorisation, {kind}",
                "cpu_s": t,
                "fill": 0,
                "residual": res(p.solve(b)),
            }
        )
        t, x = _best(lambda: p.solve(b))
        rows.append(
            {"method": "pardiso triangular solve only", "cpu_s": t, "fill": 0, "residual": res(x)}
        )
        p.release()
    backends = [("superlu", False), ("superlu", True)]
    if pardiso_available():
        backends.append(("pardiso", False))
    for backend, reuse in backends:
        s = TangentSolver(reuse=reuse, backend=backend)
        t0 = time.process_time()
        worst = max(res(s.solve(A, rhs), A, rhs) for A, rhs in seq)
        rows.append(
            {
                "method": f"{len(seq)} tangents, {backend}, "
                + ("reused LU + refinement" if reuse else "fresh factorisation each")
                + f" ({s.n_factor} factorisations)",
                "cpu_s": time.process_time() - t0,
                "fill": 0,
                "residual": worst,
            }
        )
    for r in rows:
        r["dofs"] = n
    name = "fe_linear_solvers" + ("" if law == "sbmf" else f"_{law}")
    with (OUT / f"{name}.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(
        f"law {law}: tangent asymmetry |K - K^T| / max|K| = {abs(K - K.T).max() / abs(K).max():.1e}"
    )
    for mod in ("scikits.umfpack", "pypardiso"):
        try:
            ok = importlib.util.find_spec(mod) is not None
        except ModuleNotFoundError:
            ok = False
        print(f"{mod}: {'importable' if ok else 'not installed'}")
    print(f"{n} dofs, nnz {K.nnz}")
    for r in rows:
        print(
            f"{r['method']:60s} {r['cpu_s']:7.3f} s  fill {r['fill']:>9d}  resid {r['residual']:.1e}"
        )


if __name__ == "__main__":
    with run_record(__file__):
        argv = sys.argv[1:]
        law = "sbmf"
        if "--law" in argv:
            i = argv.index("--law")
            law = argv[i + 1]
            del argv[i : i + 2]
            if law not in ("sbmf", "tresca"):
                raise SystemExit("--law must be sbmf or tresca")
        main(int(argv[0]) if argv else 200, law)
