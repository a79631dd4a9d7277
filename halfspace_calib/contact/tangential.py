"""Uncoupled tangential contact after a normal solve (Sec. 2.2, Eqs. 13 and 18).

Problem (displacement control). The tool is shifted rigidly by ``delta`` in ``+x`` relative to the
workpiece. On the contact elements (``p > 0``) the tangential traction ``q`` (Pa, on the workpiece,
positive in ``+x``) satisfies the bound ``|q| <= g`` (Eq. 18: ``g = m sigma_y / 2``, the Tresca cap;
optionally Coulomb ``g = mu p``); outside contact ``q = 0``. With ``u = C^xx q`` (Eq. 13) the relative
tangential elastic displacement, each contact element either sticks (``u = delta``, ``|q| < g``) or
slips in the direction of its traction (``q = +g`` with ``delta - u >= 0`` or ``q = -g`` with
``delta - u <= 0``). These are exactly the optimality conditions of the box-constrained convex
quadratic program::

    min_q  1/2 q^T C q - delta * sum(q)    subject to  -g <= q <= g,

which is solved by MPRGP (modified proportioning with reduced gradient projections, Dostal & Schoeberl
2005: conjugate gradients on the free set, projected expansion steps, proportioning steps that
release bound elements; finite termination for SPD ``C``) with one FFT convolution per iteration.
The paper's projected Gauss-Seidel sweep (dense ``C`` restricted to the contact set) is available as
``method="gauss-seidel"`` for small grids, as a reference.

Force control: a prescribed mean tangential traction ``q_mean`` (Pa, the tangential force divided
by the apparent area ``A0``) is reached by a bracketed root search (Brent) on ``delta``: the mean
traction is a continuous non-decreasing function of ``delta`` that is 0 at ``delta = 0`` and reaches
the sliding limit ``mean(g)`` at ``delta_hi = max(C g)`` on the contact set.

Array convention: arrays are indexed ``[ix, iy]`` (``numpy.meshgrid(..., indexing="ij")``), axis 0 is
the sliding direction ``x``.

The Cerruti matrix is applied by the package's generic :class:`~.influence.InfluenceOperator`
(built by the private ``_cerruti_operator``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import optimize

from ..common.checks import tolerance
from ..common.heap import keep_heap
from .cerruti import _check_moduli, _check_sizes, cerruti_coefficients
from .influence import InfluenceOperator

__all__ = [
    "TangentialResult",
    "tangential_bound",
    "tau_adh_full_sliding",
    "solve_tangential",
]

# --------------------------------------------------------------------------------------------
# FFT application of the Cerruti kernel by the package's generic influence operator.
# --------------------------------------------------------------------------------------------


def _cerruti_operator(shape, dx, dy, E_star, E_prime, periodic) -> InfluenceOperator:
    """``u = C^xx q`` on an ``nx x ny`` grid by FFT (an :class:`InfluenceOperator`).

    Non-periodic: the closed-form coefficients of Eq. 16 sampled at all offsets
    ``-(n-1)..(n-1)`` in a ``2nx x 2ny`` circulant embedding (offset ``+n`` in the spare slot);
    zero-padded ``q`` gives the exact discrete (Toeplitz) sum. The embedding is fixed here rather
    than left to :meth:`InfluenceOperator.from_coefficients` because its spectrum sets the norm
    bound ``op.norm``, hence the MPRGP step length and the iterates. Periodic: the continuous
    Fourier symbol of the Cerruti kernel (:func:`_cerruti_symbol`).
    """
    if periodic:
        return InfluenceOperator.from_spectrum(
            lambda kx, ky: _cerruti_symbol(kx, ky, E_star, E_prime), shape, dx, dy
        )
    nx, ny = shape
    ix = np.arange(2 * nx)
    iy = np.arange(2 * ny)
    ox = np.where(ix <= nx, ix, ix - 2 * nx) * dx
    oy = np.where(iy <= ny, iy, iy - 2 * ny) * dy
    X, Y = np.meshgrid(ox, oy, indexing="ij")
    return InfluenceOperator(cerruti_coefficients(X, Y, dx, dy, E_star, E_prime), shape, False)


_CerrutiOperator = _cerruti_operator  # the former class name, kept for tests and benchmarks


def _cerruti_symbol(kx, ky, E_star, E_prime):
    """Fourier symbol of the Cerruti kernel, ``(2 / |k|) [1/E* + (k_y^2/|k|^2) / E']``.

    The mean mode ``k = 0`` is set to zero (a periodic half-space has no finite mean tangential
    displacement, so ``delta`` is measured from the mean surface displacement).
    """
    k2 = kx**2 + ky**2
    nz = k2 > 0
    k2 = np.where(nz, k2, 1.0)
    return np.where(nz, 2.0 / np.sqrt(k2) * (1.0 / E_star + ky**2 / k2 / E_prime), 0.0)


# --------------------------------------------------------------------------------------------
# Public API
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class TangentialResult:
    """Result of :func:`solve_tangential`.

    Attributes
    ----------
    q : ndarray
        Tangential traction on the workpiece (Pa), ``[ix, iy]``, 0 outside contact.
    stick, slip : ndarray of bool
        Contact elements that stick (``|q| < g``) and that slip (``|q| = g``).
    delta : float
        Rigid tangential shift of the tool (m): prescribed, or found under force control.
    q_mean : float
        Mean tangential traction over the apparent area (Pa) = tangential force / ``A0``.
    residual : float
        Max-norm of the projected gradient ``u - delta`` over contact elements, divided by
        ``|delta|`` (dimensionless KKT error of the final inner solve).
    nit : int
        Operator applications (MPRGP) or sweeps (Gauss-Seidel), summed over the inner solves.
    converged : bool
        Whether every tolerance was met.
    message : str
        Human-readable status.
    """

    q: np.ndarray
    stick: np.ndarray
    slip: np.ndarray
    delta: float
    q_mean: float
    residual: float
    nit: int
    converged: bool
    message: str


def tangential_bound(p, *, m=None, sigma_y=None, mu=None):
    """Local traction bound ``g``, Eq. 18 (Tresca) or Coulomb.

    Tresca (the paper): ``g = m sigma_y / 2`` on contact elements (``p > 0``), 0 elsewhere.
    Coulomb (option, e.g. for Cattaneo-Mindlin): ``g = mu p``.

    Parameters
    ----------
    p : array_like
        Contact pressure (Pa), ``>= 0``.
    m, sigma_y : float, optional
        Tresca friction factor ``0 <= m <= 1`` and yield stress (Pa). Give both, or ``mu``.
    mu : float, optional
        Coulomb coefficient ``>= 0``.

    Returns
    -------
    ndarray
        Bound ``g`` (Pa), same shape as ``p``.
    """
    p = _check_pressure(p)
    tresca = m is not None or sigma_y is not None
    if tresca == (mu is not None):
        raise ValueError("give either m and sigma_y (Tresca, Eq. 18) or mu (Coulomb), not both")
    if tresca:
        if m is None or sigma_y is None:
            raise ValueError("Tresca bound needs both m and sigma_y")
        if not (np.isfinite(m) and 0.0 <= m <= 1.0):
            raise ValueError(f"m must lie in [0, 1], got {m!r}")
        if not (np.isfinite(sigma_y) and sigma_y > 0):
            raise ValueError(f"sigma_y must be a finite positive stress in Pa, got {sigma_y!r}")
        return np.where(p > 0, 0.5 * m * sigma_y, 0.0)
    if not (np.isfinite(mu) and mu >= 0):
        raise ValueError(f"mu must be finite and >= 0, got {mu!r}")
    return mu * p


def tau_adh_full_sliding(alpha_rc, m, sigma_y):
    """Adhesive shear under full sliding, no tangential solve: ``m (sigma_y / 2) alpha_rc``.

    Under full sliding every contact element is at the Eq. 18 cap, so the mean tangential
    traction over the apparent area is the cap times the contact ratio.

    Parameters
    ----------
    alpha_rc : float or array_like
        Contact ratio ``A_real / A0`` in ``[0, 1]``.
    m : float
        Tresca friction factor in ``[0, 1]``.
    sigma_y : float
        Yield stress (Pa), positive.

    Returns
    -------
    float or ndarray
        ``tau_adh`` in Pa.
    """
    a = np.asarray(alpha_rc, dtype=float)
    if not np.all(np.isfinite(a) & (a >= 0) & (a <= 1)):
        raise ValueError("alpha_rc must lie in [0, 1]")
    if not (np.isfinite(m) and 0.0 <= m <= 1.0):
        raise ValueError(f"m must lie in [0, 1], got {m!r}")
    if not (np.isfinite(sigma_y) and sigma_y > 0):
        raise ValueError(f"sigma_y must be a finite positive stress in Pa, got {sigma_y!r}")
    out = 0.5 * m * sigma_y * a
    return float(out) if out.ndim == 0 else out


def solve_tangential(
    p,
    dx,
    E_star,
    E_prime,
    *,
    delta=None,
    q_mean=None,
    m=None,
    sigma_y=None,
    mu=None,
    dy=None,
    periodic=True,
    method="mprgp",
    q0=None,
    tol=1e-8,
    maxiter=10000,
):
    """Uncoupled tangential contact after a normal solve. It solves Eq. 13 with the bound of Eq. 18.

    Parameters
    ----------
    p : array_like, shape (nx, ny)
        Contact pressure of the normal solution (Pa), ``[ix, iy]`` with ``x`` the shift direction.
    dx : float
        Element size in ``x`` (the paper's ``2a``), m.
    E_star, E_prime : float
        Composite moduli of Eqs. 2 and 17 (Pa).
    delta : float, optional
        Prescribed rigid tangential shift of the tool (m). Exactly one of ``delta``, ``q_mean``.
    q_mean : float, optional
        Prescribed mean tangential traction over the apparent area (Pa); ``|q_mean|`` must not
        exceed the sliding limit ``mean(g)``.
    m, sigma_y, mu : float, optional
        Bound, see :func:`tangential_bound` (Tresca ``m, sigma_y`` or Coulomb ``mu``).
    dy : float, optional
        Element size in ``y`` (``2b``), default ``dx``.
    periodic : bool
        Periodic half-space (spectral kernel, ``delta`` relative to the mean displacement) or
        isolated finite contact (zero padding, exact discrete sum).
        Default True, as in :func:`~halfspace_calib.contact.normal.solve_normal`: a tangential
        solve on a normal solution uses the same boundary conditions.
    method : {"mprgp", "gauss-seidel"}
        Fast FFT-based MPRGP, or the paper's projected Gauss-Seidel (dense, small grids only).
    q0 : array_like, optional
        Initial traction (warm start).
    tol : float
        Relative KKT tolerance: ``max |projected(u - delta)| <= tol |delta|``; under force control
        also the relative tolerance on ``delta`` of the root search.
    maxiter : int
        Iteration limit per inner solve.

    Returns
    -------
    TangentialResult
    """
    p = _check_pressure(p)
    if p.ndim != 2:
        raise ValueError(f"p must be a 2-D array (nx, ny), got shape {p.shape}")
    dy = dx if dy is None else dy
    _check_sizes(dx, dy)
    _check_moduli(E_star, E_prime)
    if (delta is None) == (q_mean is None):
        raise ValueError(
            "give exactly one of delta (displacement control) or q_mean (force control)"
        )
    if method not in ("mprgp", "gauss-seidel"):
        raise ValueError(f"method must be 'mprgp' or 'gauss-seidel', got {method!r}")
    tolerance(tol)
    if int(maxiter) < 1:
        raise ValueError(f"maxiter must be >= 1, got {maxiter!r}")
    keep_heap()  # grid-sized temporaries reused, not page-faulted in anew (common/heap.py)
    g_full = tangential_bound(p, m=m, sigma_y=sigma_y, mu=mu)
    idx = np.flatnonzero(g_full > 0)
    if method == "gauss-seidel" and idx.size > _GS_MAX:
        raise ValueError(
            f"method='gauss-seidel' is a dense reference for at most {_GS_MAX} loaded contact "
            f"elements, got {idx.size}; use method='mprgp'"
        )
    if q0 is not None:
        q0 = np.asarray(q0, dtype=float)
        if q0.shape != p.shape or not np.all(np.isfinite(q0)):
            raise ValueError(f"q0 must be finite with shape {p.shape}")
    for name, v in (("delta", delta), ("q_mean", q_mean)):
        if v is not None and not np.isfinite(v):
            raise ValueError(f"{name} must be finite, got {v!r}")
    q_limit = float(g_full.mean())
    if q_mean is not None and abs(q_mean) > q_limit * (1 + 1e-12):
        raise ValueError(
            f"|q_mean| = {abs(q_mean):.6g} Pa exceeds the sliding limit mean(g) = {q_limit:.6g} Pa: "
            "no sticking solution exists (full sliding; use tau_adh_full_sliding)"
        )

    op = _cerruti_operator(p.shape, dx, dy, E_star, E_prime, periodic)
    g = g_full.ravel()[idx]
    x0 = np.zeros(idx.size) if q0 is None else q0.ravel()[idx]
    inner = _make_inner(op, idx, g, method, tol, int(maxiter))

    if delta is not None:
        x, res, nit, ok, msg = inner(float(delta), x0)
        return _result(p.shape, idx, g, x, float(delta), res, nit, ok, msg)
    return _force_control(p.shape, op, idx, g, float(q_mean), q_limit, inner, x0, tol)


# --------------------------------------------------------------------------------------------
# Internals
# --------------------------------------------------------------------------------------------

_GS_MAX = 4096  # dense float64 matrix of at most 128 MiB


def _check_pressure(p):
    p = np.asarray(p, dtype=float)
    if not np.all(np.isfinite(p)):
        raise ValueError("p must be finite")
    if np.any(p < 0):
        raise ValueError("p must be >= 0 (contact pressure, compression positive)")
    return p


def _result(shape, idx, g, x, delta, res, nit, ok, msg):
    q = np.zeros(shape)
    q.ravel()[idx] = x
    slip_flat = np.zeros(q.size, dtype=bool)
    slip_flat[idx] = np.abs(x) >= g * (1.0 - 1e-12)
    stick_flat = np.zeros(q.size, dtype=bool)
    stick_flat[idx] = ~slip_flat[idx]
    return TangentialResult(
        q=q,
        stick=stick_flat.reshape(shape),
        slip=slip_flat.reshape(shape),
        delta=delta,
        q_mean=float(q.mean()),
        residual=res,
        nit=int(nit),
        converged=bool(ok),
        message=msg,
    )


def _make_inner(op, idx, g, method, tol, maxiter):
    """Inner solver ``(delta, x0) -> (x, residual, nit, converged, message)`` on the contact set."""
    lo, hi = -g, g
    n_grid = op.shape[0] * op.shape[1]

    def A(v):
        full = np.zeros(n_grid)
        full[idx] = v
        return op(full.reshape(op.shape)).ravel()[idx]

    dense = op.dense_matrix(idx) if method == "gauss-seidel" else None
    # expansion step length 1.95/norm, inside the admissible (0, 2/norm] (~25 % fewer iterations than 1/norm)
    alpha_bar = 1.95 / op.norm

    def inner(delta, x0):
        if idx.size == 0:
            return np.zeros(0), 0.0, 0, True, "no contact elements: q = 0"
        if delta == 0.0:
            return np.zeros(idx.size), 0.0, 0, True, "delta = 0: q = 0"
        b = np.full(idx.size, delta)
        tol_abs = tol * abs(delta)
        if method == "mprgp":
            x, nit, ok = _mprgp(A, b, lo, hi, x0, tol_abs, maxiter, alpha_bar)
        else:
            x, nit, ok = _pgs(dense, b, lo, hi, x0, tol_abs, maxiter)
        res = _kkt_residual(x, A(x) - b, lo, hi) / abs(delta)
        msg = f"{method}: {'converged' if ok else 'NOT converged'} in {nit} iterations, KKT residual {res:.2e}"
        return x, res, nit, ok, msg

    return inner


def _projected_gradient(x, grad, lo, hi):
    pg = grad.copy()
    at_lo = x <= lo
    at_hi = x >= hi
    pg[at_lo] = np.minimum(grad[at_lo], 0.0)
    pg[at_hi] = np.maximum(grad[at_hi], 0.0)
    return pg


def _kkt_residual(x, grad, lo, hi):
    if x.size == 0:
        return 0.0
    return float(np.max(np.abs(_projected_gradient(x, grad, lo, hi))))


def _mprgp(A, b, lo, hi, x0, tol_abs, maxiter, alpha_bar, gamma=1.0):
    """MPRGP for ``min 1/2 x^T A x - b^T x``, ``lo <= x <= hi`` (Dostal & Schoeberl 2005).

    Returns ``(x, n_matvec, converged)``; stops when the projected gradient's max-norm is at most
    ``tol_abs``.
    """
    x = np.clip(x0, lo, hi)
    grad = A(x) - b
    nmv = 1

    def split(x, grad):
        free = (x > lo) & (x < hi)
        phi = np.where(free, grad, 0.0)
        beta = np.where(x <= lo, np.minimum(grad, 0.0), 0.0) + np.where(
            x >= hi, np.maximum(grad, 0.0), 0.0
        )
        return phi, beta

    def reduced(x, phi):
        pos = np.minimum((x - lo) / alpha_bar, phi)
        neg = np.maximum((x - hi) / alpha_bar, phi)
        return np.where(phi > 0, pos, np.where(phi < 0, neg, 0.0))

    phi, beta = split(x, grad)
    d = phi.copy()
    while True:
        if np.max(np.abs(phi + beta), initial=0.0) <= tol_abs:
            return x, nmv, True
        if nmv >= maxiter:
            return x, nmv, False
        if _dot(beta, beta) <= gamma**2 * _dot(reduced(x, phi), phi):
            Ad = A(d)
            nmv += 1
            dAd = _dot(d, Ad)
            # zero curvature (periodic mean mode under full contact): go to the bound
            a_cg = _dot(grad, d) / dAd if dAd > 0 else np.inf
            a_f = _max_step(x, d, lo, hi)
            if a_cg <= a_f:
                x = x - a_cg * d
                grad = grad - a_cg * Ad
                phi, beta = split(x, grad)
                d = phi - _dot(phi, Ad) / dAd * d
            else:
                # expansion: feasible half step, then a projected gradient step on the free set
                x = np.clip(x - a_f * d, lo, hi)
                grad = grad - a_f * Ad
                phi, _ = split(x, grad)
                x_new = np.clip(x - alpha_bar * phi, lo, hi)
                grad = grad + A(x_new - x)
                nmv += 1
                x = x_new
                phi, beta = split(x, grad)
                d = phi.copy()
        else:
            # proportioning: release bound elements along the chopped gradient
            Ab = A(beta)
            nmv += 1
            bAb = _dot(beta, Ab)
            a_max = _max_step(x, beta, lo, hi)
            a = min(_dot(grad, beta) / bAb, a_max) if bAb > 0 else a_max
            x = np.clip(x - a * beta, lo, hi)
            grad = grad - a * Ab
            phi, beta = split(x, grad)
            d = phi.copy()


def _dot(a, b):
    """Dot product without BLAS: multithreaded BLAS ``ddot`` stalls badly on a busy machine."""
    return float(np.einsum("i,i->", a, b))


def _max_step(x, d, lo, hi):
    """Largest ``a >= 0`` with ``lo <= x - a d <= hi``."""
    with np.errstate(divide="ignore", invalid="ignore"):
        steps = np.where(d > 0, (x - lo) / d, np.where(d < 0, (x - hi) / d, np.inf))
    return float(np.min(steps, initial=np.inf))


def _pgs(C, b, lo, hi, x0, tol_abs, maxiter):
    """Projected Gauss-Seidel (the paper's method): sweeps over the contact elements."""
    x = np.clip(x0, lo, hi).copy()
    u = C @ x
    diag = np.diag(C).copy()
    n = x.size
    for sweep in range(1, maxiter + 1):
        for k in range(n):
            xk = min(max(x[k] + (b[k] - u[k]) / diag[k], lo[k]), hi[k])
            dk = xk - x[k]
            if dk != 0.0:
                u += C[:, k] * dk
                x[k] = xk
        if _kkt_residual(x, u - b, lo, hi) <= tol_abs:
            return x, sweep, True
    return x, maxiter, False


def _force_control(shape, op, idx, g, q_mean, q_limit, inner, x0, tol):
    """Find ``delta`` so that ``mean(q) = q_mean`` (Brent's method on the monotone response)."""
    n_grid = shape[0] * shape[1]
    if q_mean == 0.0 or idx.size == 0:
        return _result(shape, idx, g, np.zeros(idx.size), 0.0, 0.0, 0, True, "q_mean = 0: q = 0")
    sign = 1.0 if q_mean > 0 else -1.0
    target = abs(q_mean)
    full = np.zeros(n_grid)
    full[idx] = g
    delta_hi = float(np.max(op(full.reshape(shape)).ravel()[idx]))
    state = {"x": sign * np.clip(x0, -g, g) if x0 is not None else np.zeros(idx.size), "nit": 0}
    state["last"] = None

    if target >= q_limit * (1 - 1e-12):
        x, res, nit, ok, msg = inner(delta_hi, g.copy())
        return _result(
            shape,
            idx,
            g,
            sign * x,
            sign * delta_hi,
            res,
            nit,
            ok,
            "full sliding at the limit: delta is the smallest shift that slides all; " + msg,
        )

    def f(d):
        x, res, nit, ok, msg = inner(d, state["x"])
        state["x"] = x
        state["nit"] += nit
        state["last"] = (x, res, ok, msg, d)
        return x.sum() / n_grid - target

    d_sol, info = optimize.brentq(
        f,
        0.0,
        delta_hi,
        xtol=tol * delta_hi,
        rtol=4 * np.finfo(float).eps,
        maxiter=200,
        full_output=True,
        disp=False,
    )
    if state["last"] is None or state["last"][4] != d_sol:
        f(d_sol)
    x, res, ok, msg, _ = state["last"]
    got = x.sum() / n_grid
    ok_q = abs(got - target) <= max(1e-6 * target, 10 * tol * q_limit)
    ok_all = bool(ok and info.converged and ok_q)
    msg = (
        f"force control: Brent {'converged' if info.converged else 'NOT converged'} in "
        f"{info.iterations} steps, mean traction error {abs(got - target) / target:.1e} "
        f"(relative); last inner solve: {msg}"
    )
    return _result(shape, idx, g, sign * x, sign * d_sol, res, state["nit"], ok_all, msg)
