"""The half-space model's exact bound ``alpha >= p / H`` against Eq. 24 (issue 26).

Every local pressure of the half-space model is at most ``H``, so the real contact area is at
least ``p_mean A0 / H``: ``alpha >= p / H``, and full contact (``alpha = 1``) at ``p_mean = H``.
Eq. 24 meets the bound only below ``H``: ``alpha1(H) = tanh(C1**n1)**(1/n1) < 1`` for every
finite ``C1, n1``. :func:`floor_violation` measures how far a fitted law falls below the bound;
:func:`floor_fit` is the least-squares fit subject to it (used by
:func:`~halfspace_calib.pipeline.law.fit.fit_first_loading`'s ``floor_to``).
"""

import math

import numpy as np
from scipy.optimize import minimize

from frictionlaw import FrictionParams, alpha_first

from ...common.checks import positive

__all__ = ["FLOOR_POINTS", "bound_record", "eq24_model", "floor_fit", "floor_violation"]

#: points (equally spaced in p up to p_top) on which alpha1(p) >= p / H is imposed
FLOOR_POINTS = 400
#: points on which the violation of alpha1(p) >= p / H is measured
_VIOLATION_POINTS = 4000


def _law(H, C1, n1):
    """Eq. 24's parameters for evaluating ``alpha1`` (``m``, ``sigma_y``, ``C2``, ``n2`` unused)."""
    return FrictionParams(m=1.0, sigma_y=H, H=H, C1=C1, n1=n1, C2=1.0, n2=1.0)


def eq24_model(p, H):
    """``model(C1, n1) = alpha_first(p, _law(H, C1, n1))`` (Eq. 24), bit for bit, made fast.

    The runtime's kernel on the points fixed once (:class:`frictionlaw.law.FixedPoints`): a fit
    evaluates the model some hundred times.
    """
    from frictionlaw._codes import CODE_SBMF
    from frictionlaw.law import FixedPoints, sbmf_coeffs

    run = FixedPoints(CODE_SBMF, sbmf_coeffs(_law(H, 1.0, 1.0), 1.0), p)

    def model(c, n):
        run.coeffs[2], run.coeffs[3] = c, n
        return run()

    return model


def floor_violation(C1, n1, H, p_top):
    """Largest violation of ``alpha1(p) >= p / H`` by Eq. 24 on ``0 < p <= p_top``.

    Returns ``(violation, p)``: ``max(p / H - alpha1(p))`` (0 if the bound holds everywhere)
    and the pressure (Pa) where it is largest (``p_top`` if it holds). Measured on
    ``_VIOLATION_POINTS`` equally spaced pressures.
    """
    p_top = positive("p_top", p_top)
    p = np.linspace(p_top / _VIOLATION_POINTS, p_top, _VIOLATION_POINTS)
    v = p / H - alpha_first(p, _law(H, C1, n1))
    i = int(np.argmax(v))
    if v[i] <= 0:
        return 0.0, float(p_top)
    return float(v[i]), float(p[i])


def floor_fit(residual, H, p_top, x0, lb, ub, names):
    """Least squares subject to ``alpha1(p) >= p / H`` on ``0 < p <= p_top`` (SLSQP, log space).

    Returns ``(params, stderr, success, message, nfev)``.
    """
    grid = np.linspace(p_top / FLOOR_POINTS, p_top, FLOOR_POINTS)
    alpha1 = eq24_model(grid, H)
    scale = max(float(residual(x0) @ residual(x0)), 1e-300)

    def cost(x):
        r = residual(x)
        return float(r @ r) / scale

    def margin(x):
        c, n = np.exp(x)
        return alpha1(c, n) - grid / H

    sol = minimize(
        cost,
        x0,
        method="SLSQP",
        bounds=list(zip(np.log(lb), np.log(ub), strict=True)),
        constraints=[{"type": "ineq", "fun": margin}],
        options={"ftol": 1e-14, "maxiter": 500},
    )
    x = sol.x
    # asymptotic standard errors at the constrained optimum (3-point Jacobian in log space)
    h = 1e-6
    jac = np.column_stack(
        [(residual(x + h * e) - residual(x - h * e)) / (2 * h) for e in np.eye(x.size)]
    )
    res = residual(x)
    s2 = float(res @ res) / max(res.size - x.size, 1)
    jtj = jac.T @ jac
    cov = np.linalg.inv(jtj) * s2 if np.linalg.cond(jtj) < 1e14 else None
    vals = np.exp(x)
    stderr = {}
    for i, nm in enumerate(names):
        var = math.inf if cov is None else float(cov[i, i])
        stderr[nm] = float(vals[i] * math.sqrt(var)) if 0 <= var < math.inf else math.inf
    ok = bool(sol.success) and float(np.min(margin(x))) >= -1e-9
    msg = f"constrained to alpha1(p) >= p/H up to {p_top:g} Pa (SLSQP): {sol.message}"
    params = {nm: float(v) for nm, v in zip(names, vals, strict=True)}
    return params, stderr, ok, msg, int(sol.nfev)


def bound_record(fit):
    """JSON-ready record of the bound for a :class:`~.fit.FirstLoadingFit`.

    ``imposed_to_Pa`` (``None``: not imposed), ``active``, ``r_squared``,
    ``r_squared_unconstrained`` and ``r_squared_cost`` (what the bound cost), ``p_max_Pa`` (the
    data's largest pressure), ``max_violation_to_p_max`` / ``max_violation_to_H`` (the largest
    ``p / H - alpha1(p)`` up to ``p_max`` / ``H``, 0 where the bound holds, with the pressure
    ``..._at_Pa``) and ``alpha1_at_H`` (the model has 1 there).
    """
    v_max, p_at = floor_violation(fit.C1, fit.n1, fit.H, fit.p_max)
    v_h, p_h = floor_violation(fit.C1, fit.n1, fit.H, fit.H)
    cost = fit.r_squared_unconstrained - fit.r_squared
    return {
        "imposed_to_Pa": fit.floor_to,
        "active": fit.floor_active,
        "r_squared": fit.r_squared,
        "r_squared_unconstrained": fit.r_squared_unconstrained,
        "r_squared_cost": cost if math.isfinite(cost) else None,
        "p_max_Pa": fit.p_max,
        "max_violation_to_p_max": v_max,
        "max_violation_to_p_max_at_Pa": p_at,
        "max_violation_to_H": v_h,
        "max_violation_to_H_at_Pa": p_h,
        "alpha1_at_H": float(alpha_first(fit.H, _law(fit.H, fit.C1, fit.n1))),
    }
