import numpy as np
import pytest
from scipy import integrate

from halfspace_calib.contact.cerruti import (
    E_prime,
    cerruti_coefficients,
    cerruti_point_force,
    rectangle_integrals,
    shear_modulus_composite,
)

E, NU = 210e9, 0.3
E_STAR = 1.0 / (2 * (1 - NU**2) / E)
E_PR = E_prime(E, NU, E, NU)


def _quad_rect(fun, X, Y, dx, dy):
    """int over [-dx/2, dx/2] x [-dy/2, dy/2] of fun(X - xi, Y - eta), split at the field point."""
    a, b = dx / 2, dy / 2
    xs = sorted({-a, a, *([X] if -a < X < a else [])})
    ys = sorted({-b, b, *([Y] if -b < Y < b else [])})
    total = 0.0
    for x0, x1 in zip(xs[:-1], xs[1:], strict=False):
        for y0, y1 in zip(ys[:-1], ys[1:], strict=False):
            val, _ = integrate.dblquad(
                lambda eta, xi: fun(X - xi, Y - eta), x0, x1, y0, y1, epsabs=1e-13, epsrel=1e-11
            )
            total += val
    return total


def _inv_r(s, t):
    return 1.0 / np.hypot(s, t)


def _s2_r3(s, t):
    return s * s / np.hypot(s, t) ** 3


@pytest.mark.parametrize(
    "X,Y",
    [(0.0, 0.0), (0.3, -0.2), (0.5, 0.25), (-0.5, -0.5), (1.3, 0.65), (-2.0, 3.1), (7.0, -4.0)],
)
@pytest.mark.parametrize("dx,dy", [(1.0, 1.0), (1.0, 0.5)])
def test_closed_form_matches_quadrature(X, Y, dx, dy):
    I1, I2 = rectangle_integrals(X * dx, Y * dy, dx, dy)
    q1 = _quad_rect(_inv_r, X * dx, Y * dy, dx, dy)
    q2 = _quad_rect(_s2_r3, X * dx, Y * dy, dx, dy)
    assert I1 == pytest.approx(q1, rel=1e-8)
    assert I2 == pytest.approx(q2, rel=1e-8)


def test_centre_values_love():
    a = 0.7e-6
    I1, I2 = rectangle_integrals(0.0, 0.0, 2 * a, 2 * a)
    assert I1 == pytest.approx(8 * a * np.arcsinh(1.0), rel=1e-14)  # Love: 8a ln(1 + sqrt 2)
    assert I2 == pytest.approx(4 * a * np.arcsinh(1.0), rel=1e-14)  # half of it on a square


def test_x2_plus_y2_identity_and_symmetry():
    rng = np.random.default_rng(0)
    X = rng.uniform(-5, 5, 200)
    Y = rng.uniform(-5, 5, 200)
    dx, dy = 1.0, 0.6
    I1, I2 = rectangle_integrals(X, Y, dx, dy)
    J1, J2 = rectangle_integrals(Y, X, dy, dx)  # axes swapped: int t^2/r^3 of the original
    np.testing.assert_allclose(J1, I1, rtol=1e-12)
    np.testing.assert_allclose(I2 + J2, I1, rtol=1e-12)
    C = cerruti_coefficients(X, Y, dx, dy, E_STAR, E_PR)
    for sx, sy in [(-1, 1), (1, -1), (-1, -1)]:
        np.testing.assert_allclose(
            cerruti_coefficients(sx * X, sy * Y, dx, dy, E_STAR, E_PR), C, rtol=1e-12
        )
    # Anisotropy: along x the x^2/r^3 term adds, along y it vanishes (positive E')
    cx = cerruti_coefficients(3.0, 0.0, 1.0, 1.0, E_STAR, E_PR)
    cy = cerruti_coefficients(0.0, 3.0, 1.0, 1.0, E_STAR, E_PR)
    assert cx > cy


def test_far_field_is_point_force_second_order():
    dx = dy = 1e-5
    errs = []
    for R in (10, 20, 40, 80):
        for ang in (0.0, 0.7, np.pi / 2):
            X, Y = R * dx * np.cos(ang), R * dy * np.sin(ang)
            c = cerruti_coefficients(X, Y, dx, dy, E_STAR, E_PR)
            ref = cerruti_point_force(X, Y, E_STAR, E_PR) * dx * dy
            errs.append((R, abs(c / ref - 1)))
    by_R = {}
    for R, e in errs:
        by_R[R] = max(by_R.get(R, 0.0), e)
    assert by_R[80] < 2e-5
    # error ~ (dx/R)^2: halving 1/R divides it by ~4
    for r0, r1 in [(10, 20), (20, 40), (40, 80)]:
        assert 3.5 < by_R[r0] / by_R[r1] < 4.5


def test_point_force_matches_cerruti_with_G():
    # u_x = Q / (2 pi G) [(1 - nu)/r + nu x^2 / r^3] for one body on a rigid one
    G = E / (2 * (1 + NU))
    e_star1 = E / (1 - NU**2)
    e_pr1 = E / (NU * (1 + NU))
    X, Y = 3e-4, -2e-4
    r = np.hypot(X, Y)
    ref = ((1 - NU) / r + NU * X**2 / r**3) / (2 * np.pi * G)
    assert cerruti_point_force(X, Y, e_star1, e_pr1) == pytest.approx(ref, rel=1e-13)


def test_moduli():
    assert E_prime(E, 0.0, E, 0.0) == np.inf
    assert E_prime(E, NU, E, NU) == pytest.approx(E / (2 * NU * (1 + NU)), rel=1e-14)
    assert E_STAR / E_PR == pytest.approx(NU / (1 - NU), rel=1e-14)
    G = E / (2 * (1 + NU))
    assert shear_modulus_composite(E, NU, E, NU) == pytest.approx(G / (2 * (2 - NU)), rel=1e-14)
    # rigid counter-body limit
    assert shear_modulus_composite(E, NU, 1e30, NU) == pytest.approx(G / (2 - NU), rel=1e-12)
    # nu = 0: the x^2/r^3 term vanishes
    c0 = cerruti_coefficients(2.0, 1.0, 1.0, 1.0, E_STAR, np.inf)
    I1, _ = rectangle_integrals(2.0, 1.0, 1.0, 1.0)
    assert c0 == pytest.approx(I1 / (np.pi * E_STAR), rel=1e-14)


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(dx=0.0),
        dict(dx=-1.0),
        dict(dy=np.nan),
        dict(E_star=0.0),
        dict(E_star=np.inf),
        dict(E_prime=0.0),
        dict(E_prime=np.nan),
        dict(E_prime=-1e9),
    ],
)
def test_bad_input_raises(kwargs):
    args = dict(X=1.0, Y=0.0, dx=1.0, dy=1.0, E_star=E_STAR, E_prime=E_PR)
    args.update(kwargs)
    with pytest.raises(ValueError):
        cerruti_coefficients(**args)


def test_bad_material_raises():
    with pytest.raises(ValueError, match="nu1"):
        E_prime(E, 0.6, E, NU)
    with pytest.raises(ValueError, match="E2"):
        shear_modulus_composite(E, NU, -1.0, NU)
    with pytest.raises(ValueError, match="singular"):
        cerruti_point_force(0.0, 0.0, E_STAR, E_PR)
