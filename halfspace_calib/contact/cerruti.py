"""Cerruti influence coefficients for tangential surface traction (Sec. 2.2, Eqs. 15-17).

Surface displacement of an elastic half-space under a tangential point force ``Q_x`` at the origin
(Cerruti; Johnson, *Contact Mechanics*, eq. 2.19 at ``z = 0``)::

    u_x = Q_x / (4 pi G) * [2 (1 - nu) / r + 2 nu x^2 / r^3]
        = Q_x * [(1 - nu^2) / (pi E) / r + nu (1 + nu) / (pi E) * x^2 / r^3].

So the second integrand of the paper's Eq. 15 is ``(x - x')^2 / rho^3`` (the text prints ``/ rho``;
Eq. 16 has the correct ``rho^3``). For two bodies loaded by opposite tractions the relative
displacement adds both compliances, giving ``1 / E*`` (Eq. 2) in front of the ``1/rho`` term and
``1 / E'`` (Eq. 17) in front of the ``x^2/rho^3`` term (Eq. 16).

Closed form for a uniformly loaded ``2a x 2b`` rectangle
----------------------------------------------------------
With ``s = x_k - x_l - xi``, ``t = y_k - y_l - eta`` and ``r = sqrt(s^2 + t^2)``::

    d^2/(ds dt) [ s asinh(t/|s|) + t asinh(s/|t|) ] = 1 / r
    d^2/(ds dt) [ t asinh(s/|t|) ]                  = s^2 / r^3

(check: ``d/ds [t asinh(s/|t|)] = t / r`` and ``d/dt (t / r) = s^2 / r^3``; the first line is
Love's antiderivative ``s ln(t + r) + t ln(s + r)`` with the functions of ``s`` alone and of ``t``
alone removed, which cancel in the corner sum). Both terms vanish on ``s = 0`` or ``t = 0``. The
integral over the element is the alternating sum of an antiderivative over the four corners
``(X +- a, Y +- b)``, ``X = x_k - x_l``, ``Y = y_k - y_l``. In this asinh form no logarithm of a
vanishing argument occurs, on or off the element.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "E_prime",
    "shear_modulus_composite",
    "cerruti_coefficients",
    "cerruti_point_force",
    "rectangle_integrals",
]


def _check_material(E, nu, name_E, name_nu):
    if not (np.isfinite(E) and E > 0):
        raise ValueError(f"{name_E} must be a finite positive modulus in Pa, got {E!r}")
    if not (np.isfinite(nu) and -1.0 < nu <= 0.5):
        raise ValueError(f"{name_nu} must lie in (-1, 0.5], got {nu!r}")


def E_prime(E1, nu1, E2, nu2):
    """Composite modulus ``E'`` of the Cerruti ``x^2/rho^3`` term, Eq. 17.

    ``1 / E' = nu1 (1 + nu1) / E1 + nu2 (1 + nu2) / E2``.

    Parameters
    ----------
    E1, E2 : float
        Young's moduli of the two bodies (Pa), positive.
    nu1, nu2 : float
        Poisson's ratios, in ``(-1, 0.5]``.

    Returns
    -------
    float
        ``E'`` in Pa; ``inf`` when both Poisson's ratios are zero (the term vanishes), negative for
        auxetic materials (the operator stays positive definite because ``1/E* + 1/E' > 0``).
    """
    _check_material(E1, nu1, "E1", "nu1")
    _check_material(E2, nu2, "E2", "nu2")
    inv = nu1 * (1.0 + nu1) / E1 + nu2 * (1.0 + nu2) / E2
    if inv == 0.0:
        return np.inf
    return 1.0 / inv


def shear_modulus_composite(E1, nu1, E2, nu2):
    """Composite tangential modulus ``G*`` of Mindlin's theory.

    ``1 / G* = (2 - nu1) / G1 + (2 - nu2) / G2`` with ``G_i = E_i / (2 (1 + nu_i))`` (Johnson,
    *Contact Mechanics*, eq. 7.42). With it the initial tangential stiffness of a circular stick
    contact of radius ``a`` is ``8 a G*`` and the Cattaneo-Mindlin compliance reads
    ``delta = 3 mu P / (16 a G*) [1 - (1 - Q / (mu P))^(2/3)]``. Not an equation of the paper;
    used for validating the tangential solver.

    Parameters
    ----------
    E1, E2 : float
        Young's moduli (Pa), positive.
    nu1, nu2 : float
        Poisson's ratios in ``(-1, 0.5]``.

    Returns
    -------
    float
        ``G*`` in Pa.
    """
    _check_material(E1, nu1, "E1", "nu1")
    _check_material(E2, nu2, "E2", "nu2")
    G1 = E1 / (2.0 * (1.0 + nu1))
    G2 = E2 / (2.0 * (1.0 + nu2))
    return 1.0 / ((2.0 - nu1) / G1 + (2.0 - nu2) / G2)


def _check_moduli(E_star, E_prime):
    if not (np.isfinite(E_star) and E_star > 0):
        raise ValueError(f"E_star must be a finite positive modulus in Pa, got {E_star!r}")
    if np.isnan(E_prime) or E_prime == 0:
        raise ValueError(f"E_prime must be nonzero (inf allowed for nu = 0), got {E_prime!r}")
    if 1.0 / E_star + 1.0 / E_prime <= 0:
        raise ValueError(
            f"1/E_star + 1/E_prime must be positive (positive definite Cerruti operator), "
            f"got E_star={E_star!r}, E_prime={E_prime!r}"
        )


def _x_asinh(u, v):
    """``u * asinh(v / |u|)``, continuous with value 0 at ``u = 0``."""
    u, v = np.broadcast_arrays(u, v)
    out = np.zeros(u.shape)
    nz = u != 0
    un = u[nz]
    out[nz] = un * np.arcsinh(v[nz] / np.abs(un))
    return out


def _corner_sum(fun, X, Y, a, b):
    """Alternating corner sum of an antiderivative over ``s in [X-a, X+a]``, ``t in [Y-b, Y+b]``."""
    return fun(X + a, Y + b) - fun(X - a, Y + b) - fun(X + a, Y - b) + fun(X - a, Y - b)


def _f_inv_r(s, t):
    return _x_asinh(s, t) + _x_asinh(t, s)


def _f_s2_r3(s, t):
    return _x_asinh(t, s)


def rectangle_integrals(X, Y, dx, dy):
    """Integrals ``I1 = int 1/rho`` and ``I2 = int (X - xi)^2 / rho^3`` over one element.

    The element is ``[-dx/2, dx/2] x [-dy/2, dy/2]`` (the paper's ``2a x 2b``), the field point at
    offset ``(X, Y)`` from its centre. Closed form, see the module docstring.

    Parameters
    ----------
    X, Y : array_like
        Offsets ``x_k - x_l``, ``y_k - y_l`` (m), broadcastable.
    dx, dy : float
        Element sizes ``2a`` and ``2b`` (m).

    Returns
    -------
    I1, I2 : ndarray
        In metres.
    """
    X = np.asarray(X, dtype=float)
    Y = np.asarray(Y, dtype=float)
    X, Y = np.broadcast_arrays(X, Y)
    a = 0.5 * dx
    b = 0.5 * dy
    I1 = _corner_sum(_f_inv_r, X, Y, a, b)
    I2 = _corner_sum(_f_s2_r3, X, Y, a, b)
    return I1, I2


def cerruti_coefficients(X, Y, dx, dy, E_star, E_prime):
    """Cerruti influence coefficients ``C^xx`` of Eq. 16, closed form.

    ``C^xx(X, Y) = I1 / (pi E*) + I2 / (pi E')``: relative tangential displacement (m) at offset
    ``(X, Y)`` from the centre of a ``dx x dy`` element carrying a unit uniform tangential traction
    (1 Pa) in ``x``. Units m/Pa.

    Parameters
    ----------
    X, Y : array_like
        Offsets ``x_k - x_l`` and ``y_k - y_l`` (m), broadcastable.
    dx, dy : float
        Element sizes (the paper's ``2a`` and ``2b``), positive (m).
    E_star : float
        Composite modulus of Eq. 2 (Pa).
    E_prime : float
        Composite modulus of Eq. 17 (Pa); ``inf`` when both Poisson's ratios vanish.

    Returns
    -------
    ndarray
        ``C^xx`` in m/Pa, shape of the broadcast of ``X`` and ``Y``.
    """
    _check_sizes(dx, dy)
    _check_moduli(E_star, E_prime)
    I1, I2 = rectangle_integrals(X, Y, dx, dy)
    return I1 / (np.pi * E_star) + I2 / (np.pi * E_prime)


def cerruti_point_force(X, Y, E_star, E_prime):
    """Surface relative displacement per unit tangential point force (Cerruti), m/N.

    ``u_x / Q_x = 1 / (pi E* r) + X^2 / (pi E' r^3)`` (kernel of Eqs. 15-16), the far-field limit of
    :func:`cerruti_coefficients` divided by the element area. Singular at ``r = 0``: callers pass
    ``r > 0`` (a ``ValueError`` otherwise).

    Parameters
    ----------
    X, Y : array_like
        Offsets from the force (m), not both zero.
    E_star, E_prime : float
        Composite moduli of Eqs. 2 and 17 (Pa).

    Returns
    -------
    ndarray
        Displacement per force, m/N.
    """
    _check_moduli(E_star, E_prime)
    X = np.asarray(X, dtype=float)
    Y = np.asarray(Y, dtype=float)
    r = np.hypot(X, Y)
    if np.any(r == 0):
        raise ValueError("X, Y: the point-force solution is singular at r = 0; pass r > 0")
    return 1.0 / (np.pi * E_star * r) + X**2 / (np.pi * E_prime * r**3)


def _check_sizes(dx, dy):
    for name, v in (("dx", dx), ("dy", dy)):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite positive element size in m, got {v!r}")
