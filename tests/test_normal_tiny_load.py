"""Issue 12, item 16: solve_normal carries a tiny load or says it is not converged."""

import numpy as np
import pytest

from halfspace_calib.contact.normal import project_box_sum, solve_normal

H = 8e8


@pytest.fixture(scope="module")
def rough():
    return np.random.default_rng(0).normal(size=(32, 32)) * 1e-6


@pytest.mark.parametrize("p_mean", [1e-2, 1e-10, 1e-20, 1e-30, 1e-100, 1e-300, 5e-324])
@pytest.mark.parametrize("hardness", [H, None], ids=["plastic", "elastic"])
def test_tiny_mean_pressure_is_carried_or_reported(rough, p_mean, hardness):
    r = solve_normal(rough, 1e-6, 1e11, p_mean, H=hardness)
    if r.converged:
        # below any elastic deflection the highest element carries the whole load alone
        assert r.pressure.mean() == pytest.approx(p_mean, rel=1e-8)
        assert r.alpha == 1 / rough.size
        assert r.pressure.ravel()[np.argmax(rough)] == pytest.approx(p_mean * rough.size, rel=1e-8)
    else:
        assert "the load is not carried" in r.message
    # the elasto-plastic case carries every load down to the smallest subnormal
    assert r.converged or hardness is None


def test_projection_keeps_a_tiny_target_next_to_large_values():
    rng = np.random.default_rng(1)
    y = rng.uniform(-1e9, 8e8, 1024)
    y[:516] = 8e8  # a tie at the cap, as after a CG step that overshoots
    for target in (1e-97, 1e-27, 1.0, 1e5):
        out = project_box_sum(y, target, H)
        assert out.min() >= 0 and out.max() <= H
        assert out.sum() == pytest.approx(target, rel=1e-12)
        np.testing.assert_allclose(out[:516], target / 516, rtol=1e-12)
