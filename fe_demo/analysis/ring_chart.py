"""Upper-bound ring-compression calibration chart (Avitzur 1964; Male and DePierre 1970 type).

A ring (outer radius ``Ro``, inner ``Ri``, height ``T``), rigid-perfectly plastic
with flow stress ``sigma_0`` and Tresca friction ``tau = m k`` on both faces,
``k = sigma_0 / sqrt(3)`` (von Mises), is compressed at the rate ``U``. The
kinematically admissible field (no bulging) is

``u_r = U / (2 T) (r - Rn**2 / r)``,  ``u_z = -U z / T``,

with the neutral radius ``Rn`` free. Its power, internal plus friction, divided by
``sigma_0 U pi (Ro**2 - Ri**2)``, is the upper bound of the average pressure
(:func:`ring_pressure_bound`); the best ``Rn`` minimises it (:func:`neutral_radius`).
With ``Rn < Ri`` all material flows outwards and the hole grows; with ``Rn > Ri``
the inner part flows inwards and the hole shrinks. Integrating the geometry with
the optimal ``Rn`` step by step gives the chart (:func:`ring_chart`).
"""

import math

import numpy as np
from scipy.optimize import minimize_scalar

__all__ = ["ring_pressure_bound", "neutral_radius", "ring_chart", "CHART_M"]

#: friction factors of the standard ring-compression calibration chart
CHART_M = (0.0, 0.1, 0.2, 0.3, 0.5, 1.0)


def _check_geom(Ro, Ri, T, m):
    if not (0 < Ri < Ro and T > 0):
        raise ValueError(f"need 0 < Ri < Ro and T > 0, got Ro={Ro!r}, Ri={Ri!r}, T={T!r}")
    if not (0.0 <= m <= 1.0):
        raise ValueError(f"m must be in [0, 1], got {m!r}")


def _internal(Rn, Ro, Ri):
    """``int_Ri^Ro r sqrt(1 + Rn^4 / (3 r^4)) dr`` in closed form."""
    c = Rn * Rn / math.sqrt(3.0)

    def F(u):
        s = math.sqrt(u * u + c * c)
        return 0.5 * (s - c * math.log((c + s) / u)) if c > 0 else 0.5 * u

    return F(Ro * Ro) - F(Ri * Ri)


def _friction(Rn, Ro, Ri):
    """``int_Ri^Ro |r^2 - Rn^2| dr`` in closed form."""

    def F(r):
        return r**3 / 3.0 - Rn * Rn * r

    if Rn <= Ri:
        return F(Ro) - F(Ri)
    if Rn >= Ro:
        return F(Ri) - F(Ro)
    return (F(Ro) - F(Rn)) - (F(Rn) - F(Ri))


def ring_pressure_bound(Rn, Ro, Ri, T, m):
    """Upper bound ``p_avg / sigma_0`` of the field with neutral radius ``Rn``.

    Internal power ``sigma_0 int eps_dot_eq dV`` with
    ``eps_dot_eq = (U / T) sqrt(1 + Rn^4 / (3 r^4))``, friction power
    ``2 int m k |u_r| 2 pi r dr`` on the two faces, ``k = sigma_0 / sqrt(3)``.
    """
    _check_geom(Ro, Ri, T, m)
    if Rn < 0:
        raise ValueError(f"Rn must be >= 0, got {Rn!r}")
    wi = 2.0 * _internal(Rn, Ro, Ri)
    wf = 2.0 * m / math.sqrt(3.0) / T * _friction(Rn, Ro, Ri)
    return (wi + wf) / (Ro * Ro - Ri * Ri)


def neutral_radius(Ro, Ri, T, m):
    """Neutral radius ``Rn`` in ``[0, Ro]`` that minimises :func:`ring_pressure_bound`.

    A grid scan brackets the minimum, a bounded Brent search refines it.
    """
    _check_geom(Ro, Ri, T, m)
    grid = np.linspace(0.0, Ro, 201)
    vals = [ring_pressure_bound(r, Ro, Ri, T, m) for r in grid]
    i = int(np.argmin(vals))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    res = minimize_scalar(
        ring_pressure_bound,
        bounds=(lo, hi),
        args=(Ro, Ri, T, m),
        method="bounded",
        options={"xatol": 1e-10 * Ro},
    )
    return float(res.x) if res.fun <= vals[i] else float(grid[i])


def ring_chart(m, reduction=0.5, *, ratio=(6.0, 3.0, 2.0), n_steps=100):
    """Inner-diameter change against height reduction for friction factor ``m``.

    Parameters
    ----------
    m : float
        Tresca factor in ``[0, 1]``.
    reduction : float
        Final height reduction in ``(0, 0.9)``.
    ratio : tuple
        ``OD : ID : T`` (6:3:2 standard ring; the chart is scale free).
    n_steps : int
        Integration steps (midpoint rule).

    Returns
    -------
    red : ndarray
        Height reductions, starting at 0. For large ``m`` the upper-bound field closes the
        hole (``Ri -> 0``) before ``reduction``; the curve then ends at the last step with
        ``Ri > 0`` (``red[-1] < reduction``).
    dDi : ndarray
        ``(Di - Di0) / Di0``.
    """
    if not (0.0 < reduction < 0.9):
        raise ValueError(f"reduction must be in (0, 0.9), got {reduction!r}")
    if int(n_steps) < 1:
        raise ValueError(f"n_steps must be >= 1, got {n_steps!r}")
    od, idd, t = (float(v) for v in ratio)
    Ro, Ri, T = od / 2, idd / 2, t
    _check_geom(Ro, Ri, T, m)
    T0, Ri0 = T, Ri
    dT = T0 * reduction / n_steps
    red = [0.0]
    out = [0.0]

    def rates(Ro, Ri, T):
        rn = neutral_radius(Ro, Ri, T, m)
        f = 1.0 / (2.0 * T)
        return f * (Ro - rn * rn / Ro), f * (Ri - rn * rn / Ri)

    for _ in range(int(n_steps)):
        a1, b1 = rates(Ro, Ri, T)
        if Ri + 0.5 * dT * b1 <= 0.0:
            break  # the field closes the hole within this step: the chart ends here
        a2, b2 = rates(Ro + 0.5 * dT * a1, Ri + 0.5 * dT * b1, T - 0.5 * dT)
        if Ri + dT * b2 <= 0.0:
            break
        Ro, Ri, T = Ro + dT * a2, Ri + dT * b2, T - dT
        red.append(1.0 - T / T0)
        out.append(Ri / Ri0 - 1.0)
    return np.array(red), np.array(out)
