"""The Newton tangent's linear solve: a sparse LU reused across iterations as a preconditioner.

Newton's tangents change little from one iteration to the next (and often from one increment to
the next): the plastic zone and the contact status move by a few points. A fresh sparse LU
(SuperLU, ``MMD_AT_PLUS_A`` ordering, which suits the structurally symmetric 2D FE pattern) costs
about 35 triangular solves at 20,000 elements, so :class:`TangentSolver` keeps the last
factorisation and solves a new tangent by restarted GMRES preconditioned with it; only when GMRES
does not reach the tolerance within ``max_krylov`` iterations (measured on the true residual) is
the tangent factorised afresh. The answer is the direct solve's to ``rtol`` (relative residual
``|K d - b| <= rtol |b|``, default ``1e-10``), far below Newton's own tolerance, so the Newton
iterates, iteration counts and results are those of a fresh LU per iteration
(``tests/test_fe_linsolve.py``). Measured speed-up: docs/fe_demo.md.

Written here rather than taken from a library: scipy provides the pieces (``splu``, ``gmres``), and
the reuse policy (when to refactorise) is the demo's own; UMFPACK and PARDISO bindings were not
installable here (scikit-umfpack builds from source against SuiteSparse, pypardiso needs MKL).
"""

import numpy as np
from scipy.sparse.linalg import LinearOperator, gmres, splu

__all__ = ["TangentSolver"]


class TangentSolver:
    """Solve ``K d = b`` for a sequence of similar sparse tangents.

    Parameters
    ----------
    reuse : bool
        Keep the last LU factorisation as GMRES preconditioner (``False``: a fresh LU for every
        solve, the reference).
    rtol : float
        Required relative residual of a preconditioned-GMRES answer, in (0, 1e-6].
    max_krylov : int
        GMRES iterations allowed before the tangent is factorised afresh, >= 1.
    permc_spec : str
        SuperLU's column ordering.

    Attributes
    ----------
    n_factor, n_krylov_solves, n_krylov_iterations : int
        Factorisations, solves answered by GMRES, and GMRES iterations spent (also on the
        attempts that fell back to a factorisation).
    """

    def __init__(self, reuse=True, rtol=1e-10, max_krylov=12, permc_spec="MMD_AT_PLUS_A"):
        if not (0.0 < rtol <= 1e-6):
            raise ValueError(f"rtol must be in (0, 1e-6], got {rtol!r}")
        if int(max_krylov) != max_krylov or max_krylov < 1:
            raise ValueError(f"max_krylov must be an integer >= 1, got {max_krylov!r}")
        self.reuse = bool(reuse)
        self.rtol = float(rtol)
        self.max_krylov = int(max_krylov)
        self.permc_spec = permc_spec
        self._lu = None
        self.n_factor = 0
        self.n_krylov_solves = 0
        self.n_krylov_iterations = 0

    def __getstate__(self):
        """Settings and counters without the LU (SuperLU cannot be copied or pickled).

        A copy factorises at its first solve.
        """
        state = dict(self.__dict__)
        state["_lu"] = None
        return state

    def reset(self):
        """Forget the stored factorisation (the next solve factorises)."""
        self._lu = None

    def solve(self, K, b):
        """The solution of ``K d = b`` (``K`` sparse CSC, ``b`` 1-D).

        Raises
        ------
        RuntimeError
            The tangent is singular (from SuperLU).
        """
        if self.reuse and self._lu is not None and self._lu.shape == K.shape:
            d = self._krylov(K, b)
            if d is not None:
                return d
        self._lu = splu(K, permc_spec=self.permc_spec)
        self.n_factor += 1
        d = self._lu.solve(b)
        if not self.reuse:
            self._lu = None
        return d

    def _krylov(self, K, b):
        """GMRES preconditioned by the stored LU; ``None`` if it misses ``rtol``."""
        bn = float(np.linalg.norm(b))
        if bn == 0.0:
            return np.zeros_like(b)
        lu = self._lu
        M = LinearOperator(K.shape, matvec=lu.solve, dtype=float)
        count = [0]

        def tick(_):
            count[0] += 1

        x0 = lu.solve(b)  # the stale factor's own answer: often already close
        if not np.all(np.isfinite(x0)):
            return None
        if np.linalg.norm(K @ x0 - b) <= self.rtol * bn:
            self.n_krylov_solves += 1
            return x0
        x, _ = gmres(
            K,
            b,
            x0=x0,
            rtol=0.1 * self.rtol,
            atol=0.0,
            restart=self.max_krylov,
            maxiter=1,
            M=M,
            callback=tick,
            callback_type="pr_norm",
        )
        self.n_krylov_iterations += count[0]
        if not np.all(np.isfinite(x)) or np.linalg.norm(K @ x - b) > self.rtol * bn:
            return None
        self.n_krylov_solves += 1
        return x
