"""The Newton tangent's linear solve: a sparse LU reused across iterations as a preconditioner.

Newton's tangents change little from one iteration to the next (and often from one increment to
the next): the plastic zone and the contact status move by a few points. A fresh sparse LU
(SuperLU, ``MMD_AT_PLUS_A`` ordering, which suits the structurally symmetric 2D FE pattern) costs
about 35 triangular solves at 20,000 elements, so :class:`TangentSolver` keeps the last
factorisation and solves a new tangent by iterative refinement with it (preconditioned
Richardson: ``x += LU_old^-1 (b - K x)``); when the observed contraction says the tolerance will
not be reached within ``max_iter`` refinements, it stops early and factorises the tangent afresh.
The answer is the direct solve's to ``rtol`` (relative residual ``|K d - b| <= rtol |b|``, default
``1e-10``, checked on the true residual), far below Newton's own tolerance, so the Newton iterates,
iteration counts and results are those of a fresh LU per iteration (``tests/test_fe_linsolve.py``).
Measured speed-up: docs/fe_demo.md.

Why refinement and not SciPy's GMRES: GMRES needs 6-13 iterations where refinement needs 5-11 on
these tangents, but its Arnoldi steps are BLAS level-2 products which, with OpenBLAS's threads on a
loaded 2-core machine, cost 60x their single-thread CPU time; measured, GMRES made the 5,000-element
run 2.8x slower. Refinement needs only sparse products, triangular solves and sums. The reuse
policy is the demo's own; UMFPACK was not installable here (scikit-umfpack builds from source
against SuiteSparse and needs swig). This paragraph and the one above are about SuperLU.

PARDISO (optional extra ``pardiso``: ``pip install sbmf-friction[pardiso]``, which brings pypardiso
and Intel's MKL, a 221 MB x86-64 wheel): ``backend="pardiso"`` factorises with MKL PARDISO instead
of SuperLU. The sparsity pattern is analysed (METIS ordering) once and kept while it stays the
same (fe_demo's tangents have a fixed pattern); a tangent symmetric to rounding (Tresca friction,
frictionless contact) is factorised as symmetric indefinite from its upper triangle, any other as
unsymmetric; PARDISO's own iterative refinement is off. Measured on 20,000-element upsetting
tangents (40,300 free dofs, 715,470 nonzeros), CPU time on the shared 2-core machine: a SuperLU
factorisation (``MMD_AT_PLUS_A``) 0.32 s; PARDISO 0.086 s unsymmetric, 0.049 s symmetric (analysis
0.06-0.07 s, once); one triangular solve 0.008-0.011 s with either. A PARDISO factorisation costs
about 5-8 solves, so refinement with a stored one does not pay: over the whole Tresca run at 20,000
elements, refinement with at most 3 steps took 37.5 s of CPU, a fresh factorisation per Newton
iteration 35.2 s. With PARDISO every solve therefore factorises afresh (``reuse`` applies to
SuperLU only). MKL's two threads took 0.15 s of CPU (and as much wall time) per unsymmetric
factorisation on the loaded machine against 0.085 s with one; a whole 5,000-element run took 28.0 s
wall with two threads against 7.6 s with one while another job ran, and 5.4 s against 6.0 s (8.9
against 6.0 s of CPU) when it paused. So the default is one thread (``threads``, at most 2). ``backend="auto"`` takes PARDISO when pypardiso imports and SuperLU otherwise. The
whole-run effect: docs/fe_demo.md.
"""

import ctypes
import importlib.util
import math
import os

import numpy as np
from scipy.sparse.linalg import splu

__all__ = ["TangentSolver", "BACKENDS", "pardiso_available"]

#: the direct solvers a :class:`TangentSolver` can use
BACKENDS = ("superlu", "pardiso", "auto")


def pardiso_available():
    """True when pypardiso (the optional extra ``pardiso``) can be imported."""
    return importlib.util.find_spec("pypardiso") is not None


def _resolve_backend(backend):
    if backend not in BACKENDS:
        raise ValueError(f"linear solver backend must be one of {BACKENDS}, got {backend!r}")
    if backend == "auto":
        return "pardiso" if pardiso_available() else "superlu"
    if backend == "pardiso" and not pardiso_available():
        raise ImportError(
            "linear solver 'pardiso' needs pypardiso, which is not installed: "
            "pip install 'sbmf-friction[pardiso]' (or pypardiso), or use "
            "SolverOptions(linear_solver='superlu')"
        )
    return backend


class _SuperLU:
    """A SuperLU factorisation of one matrix."""

    def __init__(self, K, permc_spec):
        self._lu = splu(K, permc_spec=permc_spec)
        self.shape = K.shape

    def solve(self, b):
        return self._lu.solve(b)


class _Pardiso:
    """MKL PARDISO (via pypardiso) for a sequence of matrices of one sparsity pattern.

    ``factorize`` analyses the pattern when it is new (phase 11, METIS ordering) and factorises
    numerically (phase 22); ``solve`` is a forward/backward substitution with the last
    factorisation (phase 33, PARDISO's iterative refinement off). A matrix that is symmetric to
    rounding (``|K - K^T| <= 1e-14 max |K|``, e.g. Tresca friction or frictionless contact:
    the J2 consistent tangent is symmetric) is factorised as real symmetric indefinite
    (``mtype = -2``, Bunch-Kaufman, about half the work) from its upper triangle; any other as
    real unsymmetric (``mtype = 11``). Each kind keeps its own analysis.
    """

    def __init__(self, threads):
        self._threads = int(threads)
        self._solvers = {}
        self._pattern = None
        self._analysed = set()
        self.symmetric = False
        self.n_symmetric = 0
        self.shape = None

    def release(self):
        """Free PARDISO's internal memory (its factors live outside Python's reach)."""
        for ps in self._solvers.values():
            ps.free_memory(everything=True)
        self._solvers = {}
        self._pattern = None
        self._analysed = set()

    def __del__(self):
        try:
            self.release()
        except Exception:  # at interpreter shutdown the library may be gone
            pass

    def _solver(self, mtype):
        ps = self._solvers.get(mtype)
        if ps is None:
            from pypardiso import PyPardisoSolver

            ps = PyPardisoSolver(mtype=mtype)
            # pypardiso searches sys.prefix for libmkl_rt on every construction (about 1 s);
            # tell later ones where this one found it
            os.environ.setdefault("PYPARDISO_MKL_RT", ps.libmkl._name)
            ps.libmkl.MKL_Set_Num_Threads(ctypes.c_int(self._threads))
            ps.set_iparm(1, 1)  # the values below, not PARDISO's defaults
            ps.set_iparm(2, 2)  # METIS nested dissection
            ps.set_iparm(8, 0)  # no iterative refinement (TangentSolver checks the true residual)
            # pivot perturbation 1e-13 (unsymmetric) or 1e-8 (symmetric), PARDISO's defaults;
            # scaling and weighted matching for the unsymmetric factorisation (its defaults)
            ps.set_iparm(10, 13 if mtype == 11 else 8)
            ps.set_iparm(11, 1 if mtype == 11 else 0)
            ps.set_iparm(13, 1 if mtype == 11 else 0)
            self._solvers[mtype] = ps
        return ps

    def _call(self, mtype, phase, K, b):
        from pypardiso.pardiso_wrapper import PyPardisoError

        ps = self._solver(mtype)
        ps.set_phase(phase)
        try:
            return ps._call_pardiso(K, b)
        except PyPardisoError as exc:  # the Newton loop handles RuntimeError (a singular tangent)
            raise RuntimeError(f"PARDISO phase {phase}: {exc}") from exc

    def _new_pattern(self, K):
        """Transpose map and upper-triangle mask of a new pattern; analyses are redone."""
        n, nnz = K.shape[0], K.nnz
        self.release()
        T = type(K)((np.arange(1.0, nnz + 1.0), K.indices, K.indptr), shape=K.shape).T.tocsr()
        T.sort_indices()
        if np.array_equal(T.indices, K.indices) and np.array_equal(T.indptr, K.indptr):
            self._tperm = T.data.astype(np.int64) - 1
        else:  # structurally unsymmetric: never symmetric
            self._tperm = None
        rows = np.repeat(np.arange(n), np.diff(K.indptr))
        self._upper = K.indices >= rows
        counts = np.bincount(rows[self._upper], minlength=n)
        self._upper_indptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int32)
        self._upper_indices = K.indices[self._upper]

    def _is_symmetric(self, K):
        if self._tperm is None:
            return False
        d = K.data
        scale = float(np.abs(d).max())
        return float(np.abs(d - d[self._tperm]).max()) <= 1e-14 * scale

    def factorize(self, K):
        K = K.tocsr()
        if not K.has_sorted_indices:
            K = K.sorted_indices()
        pattern = (K.shape, K.indptr.tobytes(), K.indices.tobytes())
        if pattern != self._pattern:
            self._new_pattern(K)  # releases the old analyses and factors first
            self._pattern = pattern
        self.symmetric = self._is_symmetric(K)
        mtype = -2 if self.symmetric else 11
        A = K
        if self.symmetric:
            A = type(K)(
                (K.data[self._upper], self._upper_indices, self._upper_indptr), shape=K.shape
            )
            self.n_symmetric += 1
        zeros = np.zeros((K.shape[0], 1))
        if mtype not in self._analysed:
            self._call(mtype, 11, A, zeros)
            self._analysed.add(mtype)
        self._call(mtype, 22, A, zeros)
        self._A = A
        self._mtype = mtype
        self.shape = K.shape
        return self

    def solve(self, b):
        return self._call(self._mtype, 33, self._A, np.asfortranarray(b.reshape(-1, 1)))[:, 0]


class TangentSolver:
    """Solve ``K d = b`` for a sequence of similar sparse tangents.

    Parameters
    ----------
    reuse : bool
        Keep the last LU factorisation for iterative refinement (``False``: a fresh LU for every
        solve, the reference).
    rtol : float
        Required relative residual of a refined answer, in (0, 1e-6].
    max_iter : int
        Refinement steps allowed before the tangent is factorised afresh, >= 1.
    permc_spec : str
        SuperLU's column ordering.
    backend : {"superlu", "pardiso", "auto"}
        The direct solver (:data:`BACKENDS`); ``"pardiso"`` needs the optional pypardiso
        (``ImportError`` naming the option otherwise), ``"auto"`` takes it when installed.
    threads : int
        MKL threads for PARDISO, 1 or 2.

    With PARDISO every solve factorises afresh (``reuse`` applies to SuperLU only): its
    factorisation costs about 5 solves, and refinement with a stored one did not pay (see the
    module docstring).

    Attributes
    ----------
    n_factor, n_krylov_solves, n_krylov_iterations : int
        Factorisations, solves answered by refinement with a stored LU, and refinement steps
        spent (also on the attempts that fell back to a factorisation).
    n_factor_symmetric : int
        Of the factorisations, those PARDISO did as symmetric (always 0 with SuperLU).
    """

    def __init__(
        self,
        reuse=True,
        rtol=1e-10,
        max_iter=12,
        permc_spec="MMD_AT_PLUS_A",
        backend="superlu",
        threads=1,
    ):
        if not (0.0 < rtol <= 1e-6):
            raise ValueError(f"rtol must be in (0, 1e-6], got {rtol!r}")
        if int(max_iter) != max_iter or max_iter < 1:
            raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
        if threads not in (1, 2):
            raise ValueError(f"threads must be 1 or 2, got {threads!r}")
        self.backend = _resolve_backend(backend)
        self.reuse = bool(reuse) and self.backend == "superlu"
        self.rtol = float(rtol)
        self.max_iter = int(max_iter)
        self.permc_spec = permc_spec
        self.threads = int(threads)
        self._lu = None
        self._pardiso = None
        self.n_factor = 0
        self.n_factor_symmetric = 0
        self.n_krylov_solves = 0
        self.n_krylov_iterations = 0

    def __getstate__(self):
        """Settings and counters without the LU (SuperLU cannot be copied or pickled).

        A copy factorises at its first solve.
        """
        state = dict(self.__dict__)
        state["_lu"] = None
        state["_pardiso"] = None
        return state

    def reset(self):
        """Forget the stored factorisation (the next solve factorises)."""
        self._lu = None

    def solve(self, K, b):
        """The solution of ``K d = b`` (``K`` sparse CSC, ``b`` 1-D).

        Raises
        ------
        RuntimeError
            The tangent is singular (from SuperLU), or PARDISO failed.
        """
        if self.reuse and self._lu is not None and self._lu.shape == K.shape:
            d = self._refine(K, b)
            if d is not None:
                return d
        self._lu = self._factorize(K)
        self.n_factor += 1
        d = self._lu.solve(b)
        if not self.reuse:
            self._lu = None
        return d

    def _factorize(self, K):
        if self.backend == "superlu":
            return _SuperLU(K, self.permc_spec)
        if self._pardiso is None:
            self._pardiso = _Pardiso(self.threads)
        self._pardiso.factorize(K)
        self.n_factor_symmetric += self._pardiso.symmetric
        return self._pardiso

    def _refine(self, K, b):
        """Iterative refinement with the stored LU; ``None`` if it will miss ``rtol``."""
        bn = _norm(b)
        if bn == 0.0:
            return np.zeros_like(b)
        lu, goal = self._lu, self.rtol * bn
        x = lu.solve(b)
        r_old = None
        for k in range(self.max_iter + 1):
            r = b - K @ x
            rn = _norm(r)
            if not math.isfinite(rn):
                return None
            if rn <= goal:
                self.n_krylov_solves += 1
                return x
            if k == self.max_iter:
                return None
            if r_old is not None:  # contraction so far: give up early if it cannot make it
                rho = rn / r_old
                if rho >= 1.0 or k + math.log(goal / rn) / math.log(rho) > self.max_iter:
                    return None
            r_old = rn
            x += lu.solve(r)
            self.n_krylov_iterations += 1
        return None  # pragma: no cover - the loop returns


def _norm(v):
    """Euclidean norm without BLAS (whose threads stall on a loaded machine)."""
    return math.sqrt(float(np.einsum("i,i->", v, v)))
