"""Analytic reference solutions of frictionless normal contact on an elastic half-space.

Used to validate the numerical solver (Sec. 2.1) and as documentation of the expected physics.

Nomenclature
------------
=========  ====  ===========================================================================
symbol     unit  meaning
=========  ====  ===========================================================================
E_star     Pa    composite modulus, Eq. 2: 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2
R          m     radius of the sphere (Hertz), composite: 1/R = 1/R1 + 1/R2
F          N     normal force (Hertz)
a          m     contact radius (Hertz) or contact half-width (Westergaard)
p0         Pa    peak pressure (Hertz)
delta      m     approach of distant points (Hertz), equal to u0 of Eq. 7
r          m     distance from the centre of contact
lam        m     wavelength of the wavy surface (Westergaard)
g          m     amplitude of the wavy surface, h(x) = g cos(2 pi x / lam)
p_mean     Pa    mean pressure over the apparent area (one wavelength)
p_star     Pa    full-contact pressure of the wavy surface, pi E* g / lam
q          1/m   angular wavenumber |q| = 2 pi / lam of a Fourier mode
=========  ====  ===========================================================================

References: K. L. Johnson, Contact Mechanics, CUP 1985, Sec. 4.2 (Hertz), Sec. 13.2
(Westergaard 1939 wavy surface), Eq. 13.5 ff.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..common.checks import positive

__all__ = [
    "HertzSolution",
    "fourier_mode_displacement",
    "hertz",
    "hertz_pressure",
    "westergaard_contact_halfwidth",
    "westergaard_full_contact_pressure",
    "westergaard_pressure",
]


@dataclass(frozen=True)
class HertzSolution:
    """Hertz contact of a sphere on a flat half-space (Johnson Sec. 4.2).

    Attributes
    ----------
    a : float
        Contact radius ``(3 F R / (4 E*))^(1/3)`` in m.
    p0 : float
        Peak pressure ``3 F / (2 pi a^2)`` in Pa.
    delta : float
        Approach ``a^2 / R`` in m.
    """

    a: float
    p0: float
    delta: float


def hertz(F: float, R: float, E_star: float) -> HertzSolution:
    """Hertz sphere-on-flat solution for a force ``F`` (N), radius ``R`` (m), modulus ``E_star`` (Pa)."""
    F, R, E_star = positive("F", F), positive("R", R), positive("E_star", E_star)
    a = (3.0 * F * R / (4.0 * E_star)) ** (1.0 / 3.0)
    return HertzSolution(a=a, p0=3.0 * F / (2.0 * np.pi * a**2), delta=a**2 / R)


def hertz_pressure(r, F: float, R: float, E_star: float) -> np.ndarray:
    """Hertz pressure ``p0 sqrt(1 - r^2/a^2)`` inside ``r < a``, 0 outside (Pa)."""
    s = hertz(F, R, E_star)
    r = np.asarray(r, dtype=float)
    return s.p0 * np.sqrt(np.clip(1.0 - (r / s.a) ** 2, 0.0, None))


def westergaard_full_contact_pressure(g: float, lam: float, E_star: float) -> float:
    """Mean pressure ``p_star = pi E* g / lam`` beyond which the wavy surface is in full contact."""
    return np.pi * positive("E_star", E_star) * positive("g", g) / positive("lam", lam)


def westergaard_contact_halfwidth(p_mean: float, g: float, lam: float, E_star: float) -> float:
    """Contact half-width ``a``: ``sin^2(pi a / lam) = p_mean / p_star`` (``lam/2`` in full contact)."""
    p_star = westergaard_full_contact_pressure(g, lam, E_star)
    ratio = min(positive("p_mean", p_mean) / p_star, 1.0)
    return lam / np.pi * np.arcsin(np.sqrt(ratio))


def westergaard_pressure(x, p_mean: float, g: float, lam: float, E_star: float) -> np.ndarray:
    """Pressure under the wavy surface ``h(x) = g cos(2 pi x / lam)`` pressed to ``p_mean``.

    Partial contact (``p_mean < p_star``), with ``x`` folded into ``[-lam/2, lam/2]``::

        p(x) = 2 p_mean cos(pi x / lam) / sin^2(pi a / lam)
               * sqrt(sin^2(pi a / lam) - sin^2(pi x / lam))     for |x| < a, else 0

    Full contact (``p_mean >= p_star``): ``p(x) = p_mean + p_star cos(2 pi x / lam)``.
    """
    p_star = westergaard_full_contact_pressure(g, lam, E_star)
    x = np.asarray(x, dtype=float)
    xf = (x + lam / 2) % lam - lam / 2
    if p_mean >= p_star:
        return p_mean + p_star * np.cos(2 * np.pi * xf / lam)
    a = westergaard_contact_halfwidth(p_mean, g, lam, E_star)
    s2a = np.sin(np.pi * a / lam) ** 2
    inner = np.clip(s2a - np.sin(np.pi * xf / lam) ** 2, 0.0, None)
    return 2 * p_mean * np.cos(np.pi * xf / lam) / s2a * np.sqrt(inner) * (np.abs(xf) < a)


def fourier_mode_displacement(p_amp: float, q: float, E_star: float) -> float:
    """Displacement amplitude ``2 p / (E* q)`` of the pressure mode ``p cos(q . x)`` (Eq. 1)."""
    return 2.0 * float(p_amp) / (positive("E_star", E_star) * positive("q", q))
