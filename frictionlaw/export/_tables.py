"""The first-loading law as a pressure-dependent friction-coefficient table (private).

The first loading is the parameter file's form (Eq. 24 or the tabulated first loading,
:mod:`frictionlaw.first_loading`): ``frictionlaw.shear_limit`` at ``p_hist = 0``. A host that
interpolates ``mu(p)`` linearly between the table's pressures and caps the shear at ``TAUMAX``
(Abaqus ``*FRICTION, TAUMAX=``; LS-DYNA's ``VC``) gives ``tau_table(p) = min(mu_interp(p) p,
cap)``, the cap being the law's supremum (``tau_max``, or ``tau_max alpha_top`` for a tabulated
first loading that stays below full contact above its top level). The pressures are chosen by
bisection until that stays within ``tol tau_max`` of the first loading everywhere; the error is
then measured on an independent dense grid. A table has no history: Eq. 25 (un-/reloading below
``p_hist``) cannot be carried.
"""

from dataclasses import dataclass

import numpy as np

from ..law import shear_limit

__all__ = ["TABLE_TOL", "FrictionTable", "build_table", "table_shear", "table_error"]

#: the tables' default bound on ``|tau_table - tau| / tau_max`` (``--table-tol``)
TABLE_TOL = 1e-3

_SAMPLES = 65  # error samples inside each interval while bisecting
_SAFETY = 0.5  # bisect until the sampled error is below SAFETY * tol
_MAX_POINTS = 2000


@dataclass(frozen=True)
class FrictionTable:
    """Friction-coefficient table of the first loading.

    Attributes
    ----------
    p : ndarray
        Pressures (Pa), starting at 0, increasing.
    mu : ndarray
        ``tau(p) / p`` at each pressure (``mu_eff`` at ``p = 0``).
    tau_max : float
        ``m k (1 + geo_ratio)`` (Pa), the scale of the error.
    tol : float
        Requested bound on ``|tau_table - tau| / tau_max``.
    max_error : float
        Measured ``max |tau_table - tau| / tau_max`` on the dense check grid.
    max_error_p : float
        Pressure (Pa) where it occurs.
    cap : float
        The host's cap on the shear (``TAUMAX``, ``VC``; Pa): the first loading's supremum,
        ``tau_max`` unless the law stays below full contact at every pressure.
    """

    p: np.ndarray
    mu: np.ndarray
    tau_max: float
    tol: float
    max_error: float
    max_error_p: float
    cap: float


def table_shear(p, table_p, table_mu, cap):
    """The host's view of a table: ``min(mu_interp(p) p, cap)``, mu constant beyond the ends."""
    p = np.asarray(p, dtype=float)
    mu = np.interp(p, table_p, table_mu)
    return np.minimum(mu * p, cap)


def _mu(params, p):
    p = np.asarray(p, dtype=float)
    tau = shear_limit(np.where(p > 0, p, 1.0), 0.0, params)
    return np.where(p > 0, tau / np.where(p > 0, p, 1.0), params.mu_eff)


def _interval_error(params, cap, a, b, mu_a, mu_b):
    s = np.linspace(a, b, _SAMPLES)[1:-1]
    mu = mu_a + (mu_b - mu_a) * (s - a) / (b - a)
    approx = np.minimum(mu * s, cap)
    return np.max(np.abs(approx - shear_limit(s, 0.0, params))) / params.tau_max


def law_cap(params):
    """The first loading's supremum (Pa): its shear at the largest double (it never decreases).

    ``tau_max`` for Eq. 24 and for a tabulated first loading that reaches full contact;
    ``tau_max alpha_top`` for one whose power law above the top level is flat.
    """
    return float(shear_limit(np.finfo(float).max, 0.0, params))


def _saturation_pressure(params, cap, tol):
    """A pressure beyond which the first loading is within ``SAFETY tol tau_max`` of ``cap``."""
    p = params.H / params.C1
    top = np.finfo(float).max / 2.0
    while p < top and shear_limit(p, 0.0, params) < cap - _SAFETY * tol * params.tau_max:
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
    tab = table_shear(p, table_p, table_mu, law_cap(params))
    err = np.abs(tab - shear_limit(p, 0.0, params))
    i = int(np.argmax(err))
    return float(err[i] / params.tau_max), float(p[i])


def build_table(params, tol=TABLE_TOL):
    """Pressures and coefficients so that the table's shear is within ``tol tau_max`` of the law.

    The law's first loading: ``shear_limit`` at ``p_hist = 0``, the form the parameter file runs.

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
    cap = law_cap(params)
    p_end = _saturation_pressure(params, cap, tol)
    pts = {0.0: float(params.mu_eff), p_end: float(_mu(params, p_end))}
    stack = [(0.0, p_end)]
    while stack:
        a, b = stack.pop()
        if _interval_error(params, cap, a, b, pts[a], pts[b]) <= _SAFETY * tol:
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
    return FrictionTable(p, mu, float(params.tau_max), float(tol), err, where, cap)
