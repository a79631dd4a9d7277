"""The tabulated reload fit's fast residual (issue 39): the runtime's kernel on buffers made once."""

import numpy as np
import pytest

from halfspace_calib.pipeline.law.fit import ReloadCurve
from halfspace_calib.pipeline.law.reload_table import (
    TABLE_C_BOUNDS,
    TABLE_N_BOUNDS,
    _Level,
    _level_alpha,
    fit_reload_table,
    table_alpha,
)

H = 1.0e9


@pytest.mark.parametrize("continuous", [False, True])
@pytest.mark.parametrize("first", [None, ("tabulated", None)])
def test_level_residual_is_the_runtime_kernel_bit_for_bit(continuous, first):
    if first is not None:
        from halfspace_calib.pipeline.law.first_table import fit_first_loading_table

        p = np.array([10e6, 30e6, 100e6, 300e6, 760e6])
        a = np.array([0.08, 0.2, 0.5, 0.85, 0.97])
        first = ("tabulated", fit_first_loading_table(p, a, H).table)
    curve = ReloadCurve(400e6, np.linspace(0.15, 0.9, 6) * 400e6, np.linspace(0.2, 0.7, 6))
    lv = _Level(curve, H, 2.0, 0.8, continuous, TABLE_C_BOUNDS, TABLE_N_BOUNDS, first)
    rng = np.random.default_rng(3)
    for _ in range(20):
        s2 = rng.uniform(0.25, 2.0)
        x = rng.uniform(np.log([1e-2, 0.2]), np.log([1e3, 20.0]))
        c2, n2 = np.exp(x)
        want = _level_alpha(curve.p, curve.p_hist, H, 2.0, 0.8, continuous, s2, c2, n2, lv.tail)
        got = lv.alpha(s2, x)
        assert np.array_equal(got, want)
    # the returned array is the caller's: a later call does not change it
    kept = lv.alpha(1.0, np.log([1.0, 1.0]))
    before = kept.copy()
    lv.alpha(0.5, np.log([10.0, 3.0]))
    assert np.array_equal(kept, before)


def test_fit_recovers_a_table_it_made():
    """Curves computed by a known table are fitted back to rounding (the fit's own model).

    Two levels: no interior level, so the cross-validated term of ``s2``'s search is 0.
    """
    from frictionlaw.reload_form import ReloadTable

    true = ReloadTable(p_hist=(200e6, 700e6), C2=(3.0, 1.5), n2=(1.5, 3.0), s2=0.7)
    curves = []
    for ph in true.p_hist:
        p = np.linspace(0.15, 0.9, 6) * ph
        curves.append(ReloadCurve(ph, p, table_alpha(p, ph, true, H, 2.0, 0.8, False)))
    fit = fit_reload_table(curves, H, 2.0, 0.8)
    assert fit.success
    assert fit.max_abs_residual < 1e-4  # s2 is searched to 2e-3
    assert np.allclose(fit.table.C2, true.C2, rtol=1e-3)
    assert np.allclose(fit.table.n2, true.n2, rtol=1e-2)
    assert abs(fit.s2 - 0.7) < 5e-3


def test_eq24_model_is_alpha_first_bit_for_bit():
    """Eq. 24's fit evaluates its model by the kernel directly: the same numbers as alpha_first."""
    from frictionlaw import alpha_first
    from halfspace_calib.pipeline.law.alpha_bound import eq24_model
    from halfspace_calib.pipeline.law.fit import _law

    p = np.array([10e6, 31.6e6, 100e6, 166e6, 275.7e6, 457.7e6, 760e6])
    model = eq24_model(p, H)
    rng = np.random.default_rng(1)
    kept = model(1.0, 2.0)
    for _ in range(50):
        c, n = np.exp(rng.uniform(np.log([0.05, 0.2]), np.log([50.0, 40.0])))
        assert np.array_equal(model(c, n), alpha_first(p, _law(H, c, n)))
    assert np.array_equal(kept, alpha_first(p, _law(H, 1.0, 2.0)))  # a result is the caller's
