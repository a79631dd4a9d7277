"""Ring compression: upper-bound chart (closed form vs quadrature) and FE against it."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from fe_demo.analysis.ring_chart import neutral_radius, ring_chart, ring_pressure_bound
from fe_demo.scenes import run_ring


def _bound_by_quadrature(Rn, Ro, Ri, T, m):
    wi = quad(lambda r: r * math.sqrt(1 + Rn**4 / (3 * r**4)), Ri, Ro, epsabs=0, epsrel=1e-12)[0]
    pts = [Rn] if Ri < Rn < Ro else None
    wf = quad(lambda r: abs(r * r - Rn * Rn), Ri, Ro, points=pts, epsabs=0, epsrel=1e-12)[0]
    return (2 * wi + 2 * m / math.sqrt(3) / T * wf) / (Ro**2 - Ri**2)


@pytest.mark.parametrize("Rn", [0.0, 0.7, 1.5, 2.2, 3.0])
@pytest.mark.parametrize("m", [0.0, 0.3, 1.0])
def test_bound_closed_form_matches_quadrature(Rn, m):
    assert ring_pressure_bound(Rn, 3.0, 1.5, 2.0, m) == pytest.approx(
        _bound_by_quadrature(Rn, 3.0, 1.5, 2.0, m), rel=1e-9
    )


def test_frictionless_bound_is_flow_stress_and_neutral_radius_grows_with_m():
    assert neutral_radius(3.0, 1.5, 2.0, 0.0) == pytest.approx(0.0, abs=1e-6)
    assert ring_pressure_bound(0.0, 3.0, 1.5, 2.0, 0.0) == pytest.approx(1.0)
    rn = [neutral_radius(3.0, 1.5, 2.0, m) for m in (0.05, 0.1, 0.2, 0.3, 0.5, 1.0)]
    assert np.all(np.diff(rn) > 0)
    # hole grows while Rn < Ri, shrinks once Rn > Ri
    assert rn[0] < 1.5 < rn[-1]
    # brute-force minimum on a fine grid
    for m in (0.1, 0.5):
        grid = np.linspace(0, 3, 30001)
        best = grid[np.argmin([ring_pressure_bound(r, 3.0, 1.5, 2.0, m) for r in grid])]
        assert neutral_radius(3.0, 1.5, 2.0, m) == pytest.approx(best, abs=2e-4)


def test_chart_limits():
    # m = 0: homogeneous, D_i / D_i0 = sqrt(h0 / h); midpoint rule converges at order 2
    errs = []
    for n in (10, 20, 40):
        red, d0 = ring_chart(0.0, 0.5, n_steps=n)
        errs.append(np.abs(d0 - (np.sqrt(1 / (1 - red)) - 1)).max())
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    np.testing.assert_allclose(rates, 2.0, atol=0.1)
    assert errs[-1] < 5e-5
    _, d1 = ring_chart(1.0, 0.5, n_steps=20)
    _, d01 = ring_chart(0.1, 0.5, n_steps=20)
    assert d1[-1] < -0.3 and 0 < d01[-1] < d0[-1]
    with pytest.raises(ValueError, match="m must be"):
        ring_chart(1.5)


@pytest.fixture(scope="module")
def fe_rings():
    out = {}
    for m in (0.0, 0.3, 1.0):
        res = run_ring("tresca" if m else "none", m=m, nr=12, n_increments=20)
        assert res.converged, res.message
        out[m] = res.history
    return out


def test_fe_ring_follows_upper_bound_chart(fe_rings):
    for m, h in fe_rings.items():
        assert h["height_reduction"][-1] == pytest.approx(0.5)
        red, chart = ring_chart(m, 0.5, n_steps=50)
        ref = np.interp(h["height_reduction"], red, chart)
        err = np.abs(h["inner_diameter_change"] - ref)
        # measured on this 12-element-wide mesh: m=0 1e-4, m=0.3 <= 0.02, m=1 <= 0.05
        tol = {0.0: 2e-3, 0.3: 0.03, 1.0: 0.06}[m]
        assert err.max() < tol, (m, err.max())
    # inner diameter grows at m = 0 and shrinks at high m
    assert fe_rings[0.0]["inner_diameter_change"][-1] > 0.35
    assert fe_rings[1.0]["inner_diameter_change"][-1] < -0.3
    assert np.all(np.diff(fe_rings[1.0]["inner_diameter_change"]) < 0)
