"""Slab-method (elementary theory) references for the average die pressure in cylinder upsetting.

A cylinder of current diameter ``d`` and height ``h`` between flat dies, rigid-plastic
with flow stress ``sigma_f`` (homogeneous strain assumed), friction on both faces.
The radial equilibrium of a slab, ``d sigma_r / d r = -2 tau / h``, with the yield
condition ``p = sigma_f - sigma_r`` gives the pressure distribution; its area
average is the reference. See Lange, *Handbook of Metal Forming* (1985), ch. 15, or
Dieter, *Mechanical Metallurgy*, sec. 19-4 (Siebel 1923 for the Coulomb form).
"""

import math

import numpy as np
from scipy.integrate import solve_ivp

__all__ = [
    "slab_pressure_tresca",
    "slab_pressure_coulomb",
    "slab_profile_tresca",
    "slab_pressure_law",
]


def _check(sigma_f, d, h):
    for name, v in (("sigma_f", sigma_f), ("d", d), ("h", h)):
        if not np.all(np.isfinite(v)) or np.any(np.asarray(v) <= 0):
            raise ValueError(f"{name} must be finite and > 0, got {v!r}")


def slab_pressure_tresca(sigma_f, m, d, h):
    """Average die pressure with Tresca friction ``tau = m k``, ``k = sigma_f / sqrt(3)`` (Pa).

    ``p(r) = sigma_f + 2 m k (R - r) / h``, averaged over the face:
    ``p_avg = sigma_f (1 + m d / (3 sqrt(3) h))``.
    """
    _check(sigma_f, d, h)
    if not np.all((np.asarray(m) >= 0) & (np.asarray(m) <= 1)):
        raise ValueError(f"m must be in [0, 1], got {m!r}")
    return sigma_f * (1.0 + m * d / (3.0 * math.sqrt(3.0) * h))


def slab_profile_tresca(r, sigma_f, m, d, h):
    """Pressure profile ``p(r)`` of :func:`slab_pressure_tresca` (Pa)."""
    _check(sigma_f, d, h)
    return sigma_f + 2.0 * m * sigma_f / math.sqrt(3.0) * (d / 2 - np.asarray(r)) / h


def slab_pressure_coulomb(sigma_f, mu, d, h, *, form="siebel"):
    """Average die pressure with Coulomb friction ``tau = mu p`` (Pa).

    Parameters
    ----------
    form : {"siebel", "exact"}
        ``"siebel"``: Siebel's linearised ``p_avg = sigma_f (1 + mu d / (3 h))``;
        ``"exact"``: the average of ``p = sigma_f exp(2 mu (R - r) / h)``,
        ``p_avg = 2 sigma_f (e^a - 1 - a) / a^2`` with ``a = mu d / h``.
    """
    _check(sigma_f, d, h)
    if not np.all(np.asarray(mu) >= 0):
        raise ValueError(f"mu must be >= 0, got {mu!r}")
    if form == "siebel":
        return sigma_f * (1.0 + mu * d / (3.0 * h))
    if form == "exact":
        a = np.asarray(mu * d / h, dtype=float)
        small = a < 1e-4
        a_s = np.where(small, 1.0, a)
        val = np.where(small, 1.0 + a / 3.0, 2.0 * (np.expm1(a_s) - a_s) / a_s**2)
        return sigma_f * (val if val.ndim else float(val))
    raise ValueError(f"form must be 'siebel' or 'exact', got {form!r}")


def slab_pressure_law(sigma_f, tau_of_p, d, h, *, rtol=1e-9):
    """Average die pressure for any pressure-dependent friction law ``tau(p)`` (Pa).

    Integrates the slab equation ``dp/ds = 2 tau(p) / h`` inwards from the free edge
    (``s = R - r``, ``p(0) = sigma_f``) together with ``int p r dr`` (``solve_ivp``,
    RK45), and returns ``2 int_0^R p r dr / R^2``. For Coulomb with a cap (``tau =
    min(mu p, tau_max)``) and the SBMF law (first loading, Eq. 24), which have no
    closed form.

    Parameters
    ----------
    tau_of_p : callable
        ``tau_of_p(p) -> tau`` for a scalar pressure (Pa -> Pa), ``>= 0``.
    """
    _check(sigma_f, d, h)
    R = 0.5 * d

    def rhs(s, y):
        p = y[0]
        return [2.0 * float(tau_of_p(p)) / h, p * (R - s)]

    sol = solve_ivp(rhs, (0.0, R), [float(sigma_f), 0.0], method="RK45", rtol=rtol, atol=1e-12)
    if not sol.success:
        raise RuntimeError(f"slab integration failed: {sol.message}")
    return 2.0 * sol.y[1, -1] / (R * R)
