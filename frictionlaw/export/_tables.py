"""First-loading law (Eq. 24) as a pressure-dependent friction-coefficient table (private).

A host that interpolates ``mu(p)`` linearly between the table's pressures and caps the shear at
``TAUMAX`` (Abaqus ``*FRICTION, TAUMAX=``; LS-DYNA's ``VC``) gives
``tau_table(p) = min(mu_interp(p) p, tau_max)``. The pressures are chosen by bisection until that
stays within ``tol tau_max`` of Eq. 24 everywhere; the error is then measured on an independent
dense grid. A table has no history: Eq. 25 (un-/reloading below ``p_hist``) cannot be carried.
"""

from dataclasses import dataclass

import numpy as np

from ..law import shear_limit

__all__ = ["FrictionTable", "build_table", "table_shear", "table_error"]

_SAMPLES = 65  # error samples inside each interval while bisecting
_SAFETY = 0.5  # bisect until the sampled error is below SAFETY * tol
_MAX_POINTS = 2000


@dataclass(frozen=True)
class FrictionTable:
    """Friction-coefficient table of Eq. 24.

    Attributes
    ----------
    p : ndarray
        Pressures (Pa), starting at 0, increasing.
    mu : ndarray
        ``tau(p) / p`` at each pressure (``mu_eff`` at ``p = 0``).
    tau_max : float
        Cap ``m k (1 + geo_ratio)`` (Pa).
    tol : float
        Requested bound on ``|tau_table - tau| / tau_max``.
    max_error : float
        Measured ``max |tau_table - tau| / tau_max`` on the dense check grid.
    max_error_p : float
        Pressure (Pa) where it occurs.
    """

    p: np.ndarray
    mu: np.ndarray
    tau_max: float
    tol: float
    max_error: float
    max_error_p: float


def table_shear(p, table_p, table_mu, tau_max):
    """The host's view of a table: ``min(mu_interp(p) p, tau_max)``, mu constant beyond the ends."""
    p = np.asarray(p, dtype=float)
    mu = np.interp(p, table_p, table_mu)
    return np.minimum(mu * p, tau_max)


def _mu(params, p):
    p = np.asarray(p, dtype=float)
    tau = shear_limit(np.where(p > 0, p, 1.0), 0.0, params)
    return np.where(p > 0, tau / np.where(p > 0, p, 1.0), params.mu_eff)


def _interval_error(params, a, b, mu_a, mu_b):
    s = np.linspace(a, b, _SAMPLES)[1:-1]
    mu = mu_a + (mu_b - mu_a) * (s - a) / (b - a)
    approx = np.minimum(mu * s, params.tau_max)
    return np.max(np.abs(approx - shear_limit(s, 0.0, params))) / params.tau_max


def _saturation_pressure(params, tol):
    """A pressure beyond which Eq. 24 is within ``SAFETY tol`` of ``tau_max``."""
    p = params.H / params.C1
    while shear_limit(p, 0.0, params) < (1.0 - _SAFETY * tol) * params.tau_max:
        p *= 2.0
    return p


def table_error(params, table_p, table_mu, n_check=200_000):
    """Measured ``max |tau_table - tau| / tau_max`` and where, on a dense independent grid.

    The grid is linear up to 4x the last table pressure and logarithmic from 1e-6 of the first
    non-zero one (the small-pressure end, where ``mu`` must meet ``mu_eff``).
    """
    p_last = table_p[-1]
    lin = np.linspace(0.0, 4.0 * p_last, n_check)
    log = np.geomspace(max(table_p[1], 1e-300) * 1e-6, 4.0 * p_last, n_check // 4)
    p = np.concatenate([lin, log, [16.0 * p_last, 1e3 * p_last]])
    err = np.abs(table_shear(p, table_p, table_mu, params.tau_max) - shear_limit(p, 0.0, params))
    i = int(np.argmax(err))
    return float(err[i] / params.tau_max), float(p[i])


def build_table(params, tol=1e-3):
    """Pressures and coefficients so that the table's shear is within ``tol tau_max`` of Eq. 24.

    Parameters
    ----------
    params : FrictionParams
    tol : float
        Bound on the interpolation error relative to ``tau_max``, in ``[1e-6, 0.1]``.

    Returns
    -------
    FrictionTable
    """
    if not (1e-6 <= float(tol) <= 0.1):
        raise ValueError(f"table tolerance must be in [1e-6, 0.1], got {tol!r}")
    if params.tau_max <= 0.0:
        raise ValueError("m must be > 0 for a friction table (tau_max = m k (1 + geo_ratio) = 0)")
    p_end = _saturation_pressure(params, tol)
    pts = {0.0: float(params.mu_eff), p_end: float(_mu(params, p_end))}
    stack = [(0.0, p_end)]
    while stack:
        a, b = stack.pop()
        if _interval_error(params, a, b, pts[a], pts[b]) <= _SAFETY * tol:
            continue
        c = 0.5 * (a + b)
        pts[c] = float(_mu(params, c))
        if len(pts) > _MAX_POINTS:
            raise RuntimeError(
                f"friction table did not reach tol={tol} within {_MAX_POINTS} points"
            )
        stack += [(a, c), (c, b)]
    p = np.array(sorted(pts))
    mu = np.array([pts[v] for v in p])
    err, where = table_error(params, p, mu)
    if err > tol:
        raise RuntimeError(
            f"friction table error {err:.3g} tau_max at p={where:.4g} Pa exceeds tol={tol}"
        )
    return FrictionTable(p, mu, float(params.tau_max), float(tol), err, where)
