import numpy as np
import pytest
from scipy import integrate

from halfspace_calib.contact.reference import (
    fourier_mode_displacement,
    hertz,
    hertz_pressure,
    westergaard_contact_halfwidth,
    westergaard_full_contact_pressure,
    westergaard_pressure,
)

E = 115.4e9


def test_hertz_force_balance_and_approach():
    F, R = 12.0, 5e-3
    s = hertz(F, R, E)
    force, _ = integrate.quad(
        lambda r: 2 * np.pi * r * hertz_pressure(r, F, R, E), 0, s.a, epsabs=0, epsrel=1e-12
    )
    assert force == pytest.approx(F, rel=1e-9)
    # classical forms: a^3 = 3FR/(4E*), delta = (9 F^2 / (16 R E*^2))^(1/3), p0 = 2 E* a / (pi R)
    assert s.a**3 == pytest.approx(3 * F * R / (4 * E), rel=1e-13)
    assert s.delta == pytest.approx((9 * F**2 / (16 * R * E**2)) ** (1 / 3), rel=1e-12)
    assert s.p0 == pytest.approx(2 * E * s.a / (np.pi * R), rel=1e-12)
    assert hertz_pressure(2 * s.a, F, R, E) == 0.0


@pytest.mark.parametrize("ratio", [0.05, 0.4, 0.9, 1.0, 1.5])
def test_westergaard_mean_pressure(ratio):
    g, lam = 1e-7, 1e-4
    ps = westergaard_full_contact_pressure(g, lam, E)
    pm = ratio * ps
    mean, _ = integrate.quad(
        lambda x: westergaard_pressure(x, pm, g, lam, E),
        -lam / 2,
        lam / 2,
        points=[
            -westergaard_contact_halfwidth(pm, g, lam, E),
            westergaard_contact_halfwidth(pm, g, lam, E),
        ],
        epsabs=0,
        epsrel=1e-10,
        limit=200,
    )
    assert mean / lam == pytest.approx(pm, rel=1e-7)


def test_westergaard_limits():
    g, lam = 2e-7, 3e-4
    ps = westergaard_full_contact_pressure(g, lam, E)
    assert ps == pytest.approx(np.pi * E * g / lam)
    assert westergaard_contact_halfwidth(ps, g, lam, E) == pytest.approx(lam / 2)
    # continuity at the onset of full contact: p(x) -> p*(1 + cos)
    x = np.linspace(-lam / 2, lam / 2, 101)
    p_below = westergaard_pressure(x, ps * (1 - 1e-10), g, lam, E)
    p_at = westergaard_pressure(x, ps, g, lam, E)
    np.testing.assert_allclose(p_below, p_at, atol=1e-4 * ps)
    # light load: Hertz-like cylinder of curvature 4 pi^2 g / lam^2: a^2 = 4 R P / (pi E*)
    pm = 1e-4 * ps
    a = westergaard_contact_halfwidth(pm, g, lam, E)
    R = lam**2 / (4 * np.pi**2 * g)
    assert a == pytest.approx(np.sqrt(4 * R * pm * lam / (np.pi * E)), rel=1e-4)
    # periodic in x
    assert westergaard_pressure(0.1 * lam, 0.5 * ps, g, lam, E) == pytest.approx(
        westergaard_pressure(1.1 * lam, 0.5 * ps, g, lam, E)
    )


def test_fourier_mode_consistent_with_westergaard():
    """Full contact of h = g cos(q x) needs u_el = g cos(q x) from p* cos(q x): 2 p*/(E* q) = g."""
    g, lam = 3e-7, 2e-4
    ps = westergaard_full_contact_pressure(g, lam, E)
    assert fourier_mode_displacement(ps, 2 * np.pi / lam, E) == pytest.approx(g, rel=1e-14)
    # and the mode response scales as 1/q: halving the wavelength halves the displacement
    assert fourier_mode_displacement(1e6, 2.0, E) == pytest.approx(
        0.5 * fourier_mode_displacement(1e6, 1.0, E)
    )


def test_bad_input():
    with pytest.raises(ValueError, match="F"):
        hertz(-1.0, 1e-3, E)
    with pytest.raises(ValueError, match="lam"):
        westergaard_full_contact_pressure(1e-7, 0.0, E)
