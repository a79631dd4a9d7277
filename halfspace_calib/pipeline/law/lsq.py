"""Bounded least squares in the logarithms of a law's ``C`` and ``n``: the fits' common core.

:func:`_fit_c_n` fits a law ``model(C, n)`` from the best point of a coarse grid around the
small-pressure slope (:func:`_start`) with :func:`_solve` (trust-region reflective, 3-point
Jacobian, asymptotic standard errors); :func:`_degenerate` says why a fit is not usable.
"""

import math

import numpy as np
from scipy.optimize import least_squares

__all__ = ["R2_MIN"]

#: a fit whose R^2 is below this is degenerate: the law explains less than 90 % of the variance
#: of alpha (calibrations reach 0.99-0.9998; constant data give 0, decreasing data < 0)
R2_MIN = 0.9

_N_GRID = (0.5, 1.0, 2.0, 4.0, 8.0, 16.0)
_C_GRID = tuple(np.geomspace(0.25, 4.0, 9))


def _weights(alpha, relative):
    if not relative:
        return np.ones_like(alpha)
    if (alpha <= 0).any():
        raise ValueError("alpha must be > 0 for a relative fit (relative=True)")
    return 1.0 / alpha


def _r_squared(res, alpha):
    ss_tot = float(np.sum((alpha - alpha.mean()) ** 2))
    ss_res = float(np.sum(res**2))
    return 1.0 - ss_res / ss_tot if ss_tot > 0 else 0.0


def _solve(residual, x_start, lb, ub, names):
    """Bounded least squares in log-parameters; returns params, stderr, sol, note."""
    x0 = np.clip(np.log(x_start), np.log(lb) + 1e-9, np.log(ub) - 1e-9)
    sol = least_squares(
        residual,
        x0,
        bounds=(np.log(lb), np.log(ub)),
        method="trf",
        jac="3-point",
        ftol=1e-14,
        xtol=1e-14,
        gtol=1e-14,
        max_nfev=2000,
    )
    vals = np.exp(sol.x)
    res = sol.fun
    dof = max(res.size - len(names), 1)
    s2 = float(res @ res) / dof
    jtj = sol.jac.T @ sol.jac
    try:
        cov = np.linalg.inv(jtj) * s2 if np.linalg.cond(jtj) < 1e14 else None
    except np.linalg.LinAlgError:
        cov = None
    stderr = {}
    for i, nm in enumerate(names):
        var = math.inf if cov is None else float(cov[i, i])
        stderr[nm] = float(vals[i] * math.sqrt(var)) if 0 <= var < math.inf else math.inf
    at = tuple(
        nm
        for i, nm in enumerate(names)
        if sol.active_mask[i] != 0 or np.isclose(vals[i], (lb[i], ub[i]), rtol=1e-6).any()
    )
    msg = sol.message
    if at:
        msg += f" Note: {', '.join(at)} ended on a bound; the data do not fix it within them."
    params = {nm: float(v) for nm, v in zip(names, vals, strict=True)}
    return params, stderr, sol, at, msg


def _start(cost, c_slope, n_bounds, c_bounds):
    """Best point of a coarse (C, n) grid around the small-pressure slope estimate."""
    best, arg = math.inf, (c_slope, 1.0)
    for cm in _C_GRID:
        c = min(max(c_slope * cm, c_bounds[0]), c_bounds[1])
        for n in _N_GRID:
            n = min(max(n, n_bounds[0]), n_bounds[1])
            v = cost(c, n)
            if v < best:
                best, arg = v, (c, n)
    return arg


def _fit_c_n(model, p, alpha, w, H, cb, nb, names):
    """Weighted (``w``) least squares of a law ``model(C, n)`` to ``alpha`` at ``p``.

    ``cb``, ``nb`` bound ``C`` and ``n``. The start is the best point of :func:`_start` around
    the slope ``C = max(alpha H / p)`` (``alpha1 <= p C1 / H``, tight at small ``p``;
    ``alpha2 ~ p C2 / H`` at small ``p``). Returns the :class:`FitResult` fields as a dict,
    the parameters under ``names``.
    """

    def residual(x):
        return (model(*np.exp(x)) - alpha) * w

    c_slope = float(np.max(alpha * H / p)) or 1.0
    start = _start(lambda c, n: float(np.sum(((model(c, n) - alpha) * w) ** 2)), c_slope, nb, cb)
    lb, ub = np.array([cb[0], nb[0]]), np.array([cb[1], nb[1]])
    return _fit_fields(model, alpha, H, lb, ub, names, _solve(residual, start, lb, ub, names))


def _fit_fields(model, alpha, H, lb, ub, names, solved):
    """The :class:`~.fit.FitResult` fields of ``_solve``'s answer ``solved`` as a dict."""
    params, stderr, sol, at, msg = solved
    res = model(params[names[0]], params[names[1]]) - alpha
    r2 = _r_squared(res, alpha)
    return dict(
        params=params,
        stderr=stderr,
        residuals=res,
        r_squared=r2,
        rmse=float(np.sqrt(np.mean(res**2))),
        success=bool(sol.success),
        message=msg,
        nfev=int(sol.nfev),
        at_bound=at,
        H=H,
        degenerate=_degenerate(params, at, lb, ub, r2, alpha),
    )


def _degenerate(params, at_bound, lb, ub, r2, alpha):
    """Why a fit is not usable (``""`` if it is): parameters on a bound, ``R^2 < R2_MIN``."""
    why = []
    for i, (name, value) in enumerate(params.items()):
        if name in at_bound:
            bound = lb[i] if abs(value - lb[i]) <= abs(value - ub[i]) else ub[i]
            why.append(f"{name} ended on its bound {bound:g}")
    if not r2 >= R2_MIN:
        if np.ptp(alpha) == 0:
            why.append(f"R^2 = {r2:.3g} < {R2_MIN}: alpha is constant, there is nothing to fit")
        else:
            why.append(f"R^2 = {r2:.3g} < {R2_MIN}: the model explains too little of the data")
    return "; ".join(why)
