"""Eqs. 24-25: exact limits, extremes, the NumPy oracle, derivatives and the reload jump."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import frictionlaw as fl
from frictionlaw import _reference as ref
from frictionlaw import kernels

H = 800e6


def params(n1=2.0, n2=2.0, C1=1.2, C2=3.0, m=0.6, continuous=False):
    return fl.FrictionParams(
        m=m, sigma_y=H / 2.8, H=H, C1=C1, n1=n1, C2=C2, n2=n2, continuous_reload=continuous
    )


P_EXTREME = np.array([0.0, -1.0, -np.inf, 1e-300, 1e-12 * H, H, 1e6 * H, np.inf])
N_VALUES = [0.1, 0.3, 1.0, 2.0, 10.0, 100.0, 1000.0]


@pytest.mark.parametrize("n", N_VALUES)
def test_first_loading_extremes(n):
    P = params(n1=n)
    tau = fl.shear_limit(P_EXTREME, 0.0, P)
    assert np.all(np.isfinite(tau))
    assert np.all((tau >= 0) & (tau <= P.tau_max))
    assert tau[0] == 0 and tau[1] == 0 and tau[2] == 0
    # large-p cap: exactly m k at 1e6 H and at infinity
    assert tau[-1] == P.tau_max
    ref_val = float(ref.sbmf_shear(1e6 * H, 0.0, P.tau_max, P.C1, n, P.C2, P.n2, H))
    assert tau[-2] == pytest.approx(ref_val, rel=1e-12)
    y = math.exp(min(n * math.log(1e6 * P.C1), 700.0))
    if 2 * math.exp(-2 * y) / n < 1e-13:  # tanh saturated: the Tresca cap holds to 1e-12
        assert tau[-2] == pytest.approx(P.tau_max, rel=1e-12)
    # at p = H the value is the closed form tanh(C1^n)^(1/n)
    assert tau[5] == pytest.approx(P.tau_max * math.tanh(P.C1**n) ** (1 / n), rel=1e-12)
    # small-p Coulomb slope where the analytic limit holds to 1e-12: g(x) = x (1 - y^2/(3n) + ...)
    for p in P_EXTREME[3:5]:
        y = (p * P.C1 / H) ** n
        if y * y / (3 * n) < 1e-13:
            assert fl.shear_limit(p, 0.0, P) == pytest.approx(P.mu_eff * p, rel=1e-12)
    assert fl.shear_limit(1e-300, 0.0, P) == pytest.approx(P.mu_eff * 1e-300, rel=1e-12)


@pytest.mark.parametrize("n", N_VALUES)
def test_small_p_coulomb_and_large_p_tresca_limits(n):
    P = params(n1=n)
    # choose p so small that the relative deviation y^2/(3n) is below 1e-13
    x = (1e-7 * 3 * n) ** (1 / (2 * n)) if n >= 1 else 1e-300
    x = min(x, 1e-6)
    p = x * H / P.C1
    y = x**n
    if y * y / (3 * n) < 1e-13:
        assert fl.shear_limit(p, 0.0, P) == pytest.approx(P.mu_eff * p, rel=1e-12)
        assert fl.shear_limit_dp(p, 0.0, P) == pytest.approx(P.mu_eff, rel=1e-12)
    # large p: within 1e-12 of the cap once tanh(y) = 1 - 2 exp(-2y) has saturated
    x_big = (40.0) ** (1 / n)
    assert fl.shear_limit(x_big * H / P.C1, 0.0, P) == pytest.approx(P.tau_max, rel=1e-12)


def test_tiny_pressure_keeps_full_precision_for_any_n():
    for n in N_VALUES:
        P = params(n1=max(n, 1.0))
        for p in [1e-300, 1e-250, 1e-100, 1e-20]:
            assert fl.shear_limit(p, 0.0, P) == pytest.approx(P.mu_eff * p, rel=1e-12)


@pytest.mark.parametrize("n1, n2", [(0.1, 0.1), (1.0, 2.0), (2.0, 1000.0), (1000.0, 0.5)])
def test_monotone_and_bounded_on_each_branch(n1, n2):
    P = params(n1=n1, n2=n2)
    p = np.concatenate([[0.0], np.geomspace(1e-6, 1e3, 4000) * H])
    t1 = fl.shear_limit(p, 0.0, P)
    assert np.all(np.diff(t1) >= 0)
    assert np.all((t1 >= 0) & (t1 <= P.tau_max))
    for p_hist in [1e-3 * H, 0.3 * H, 2 * H, 1e4 * H]:
        below = p[p < p_hist]
        t2 = fl.shear_limit(below, p_hist, P)
        assert np.all(np.diff(t2) >= 0)
        a1h = fl.alpha_first(p_hist, P)
        assert np.all((t2 >= 0) & (t2 <= P.tau_max * a1h * (1 + 1e-15)))


def test_zero_history_and_zero_pressure():
    P = params()
    assert fl.shear_limit(0.0, 0.0, P) == 0.0
    assert fl.shear_limit_dp(0.0, 0.0, P) == 0.0
    assert fl.alpha_reload(0.0, 0.0, P) == 0.0
    # p > 0 with p_hist = 0 is first loading
    assert fl.shear_limit(1e8, 0.0, P) == fl.shear_limit(1e8, 1e8, P)


@pytest.mark.parametrize("continuous", [False, True])
def test_alpha1_of_history_down_to_1e_300(continuous):
    P = params(continuous=continuous)
    # alpha1(p_hist) ~ p_hist C1 / H for tiny p_hist
    for a1h in [1e-12, 1e-100, 1e-300]:
        p_hist = a1h * H / P.C1
        assert fl.alpha_first(p_hist, P) == pytest.approx(a1h, rel=1e-12)
        p = 0.5 * p_hist
        tau = fl.shear_limit(p, p_hist, P)
        # exact limit for alpha1(p_hist) -> 0: x2 = (p / p_hist) C2 / C1 stays finite
        x2 = 0.5 * P.C2 / P.C1
        g = math.tanh(x2**P.n2) ** (1 / P.n2)
        if continuous:
            g /= math.tanh((P.C2 / P.C1) ** P.n2) ** (1 / P.n2)
        assert tau == pytest.approx(P.tau_max * a1h * g, rel=1e-12)
        assert np.isfinite(fl.shear_limit_dp(p, p_hist, P))
    # a history so small that alpha1 underflows to zero: the limit is tau -> 0, no NaN
    assert fl.shear_limit(1e-323, 2e-323, P) == 0.0


def test_mixed_shapes_broadcast():
    P = params()
    p = np.linspace(0, 1e9, 6).reshape(2, 3)
    ph = np.array([0.0, 5e8, 2e9])
    tau = fl.shear_limit(p, ph, P)
    assert tau.shape == (2, 3)
    for i in range(2):
        for j in range(3):
            assert tau[i, j] == fl.shear_limit(float(p[i, j]), float(ph[j]), P)
    assert isinstance(fl.shear_limit(1e8, 0.0, P), float)
    assert fl.shear_limit([1e8], 0.0, P).shape == (1,)
    assert fl.shear_limit(np.empty((0, 4)), 0.0, P).shape == (0, 4)


def test_nan_raises():
    P = params()
    with pytest.raises(ValueError, match="p must not contain NaN"):
        fl.shear_limit([1e8, np.nan], 0.0, P)
    with pytest.raises(ValueError, match="p_hist must not contain NaN"):
        fl.shear_limit(1e8, np.nan, P)
    with pytest.raises(ValueError, match="p_hist must be >= 0"):
        fl.shear_limit(1e8, -1.0, P)


def test_large_n1_reproduces_coulomb_with_cap():
    P = params(n1=1e4)
    cap = fl.SBMFLaw(P).coulomb_cap_equivalent()
    assert cap.mu == pytest.approx(P.m * P.sigma_y * P.C1 / (2 * H), rel=1e-15)
    p = np.concatenate([np.geomspace(1e-3, 0.97, 300), np.geomspace(1.03, 1e3, 300)]) * H / P.C1
    t_sbmf, _ = fl.SBMFLaw(P).shear_limit(p)
    t_cap, _ = cap.shear_limit(p)
    # away from the corner |x - 1| >= 3 %, the smooth minimum equals min(x, 1) to ~exp(-2 * 1.03^1e4)
    np.testing.assert_allclose(t_sbmf, t_cap, rtol=1e-12)


def test_derivative_matches_central_differences():
    for cont in (False, True):
        P = params(n1=1.7, n2=2.3, continuous=cont)
        for p_hist in (0.0, 0.6 * H):
            p = np.linspace(0.01, 1.5, 60) * H
            p = p[(p < p_hist * 0.98) | (p > p_hist * 1.02)]
            h = 1e-5 * p
            fd = (fl.shear_limit(p + h, p_hist, P) - fl.shear_limit(p - h, p_hist, P)) / (2 * h)
            np.testing.assert_allclose(fl.shear_limit_dp(p, p_hist, P), fd, rtol=1e-6, atol=1e-12)


def test_reload_jump_paper_and_continuous():
    P = params(C2=2.0, n2=1.5)
    p_hist = np.array([1e8, 3e8, 6e8])
    jump = fl.reload_jump(P, p_hist)
    a1h = fl.alpha_first(p_hist, P)
    x2h = p_hist * P.C2 / (H * a1h)
    g2h = np.tanh(x2h**P.n2) ** (1 / P.n2)
    np.testing.assert_allclose(jump, P.tau_max * a1h * (1 - g2h), rtol=1e-9)
    assert np.all(jump > 0)
    # the law itself shows the jump just below p_hist
    below = fl.shear_limit(p_hist * (1 - 1e-13), p_hist, P)
    np.testing.assert_allclose(fl.shear_limit(p_hist, p_hist, P) - below, jump, rtol=1e-6)
    # the continuous variant meets Eq. 24 at p_hist
    Pc = P.replace(continuous_reload=True)
    np.testing.assert_allclose(fl.reload_jump(Pc, p_hist), 0.0, atol=1e-9 * P.tau_max)
    np.testing.assert_allclose(
        fl.shear_limit(p_hist * (1 - 1e-13), p_hist, Pc),
        fl.shear_limit(p_hist, 0.0, Pc),
        rtol=1e-11,
    )
    # larger C2 shrinks the paper's jump
    assert np.all(fl.reload_jump(P.replace(C2=20.0), p_hist) < jump)


def test_no_warnings_under_strict_errstate():
    P = params(n1=0.1, n2=1000.0)
    with np.errstate(all="raise"):
        p = np.array([0.0, 1e-320, 1e-300, 1.0, H, 1e300, np.inf, -np.inf])
        for ph in (0.0, 1e-310, H, np.inf):
            assert np.all(np.isfinite(fl.shear_limit(p, ph, P)))
            assert np.all(np.isfinite(fl.shear_limit_dp(p, ph, P)))


# ---------------------------------------------------------------- oracle (hypothesis)
pos = st.floats(min_value=1e-6, max_value=1e3)


@settings(max_examples=300, deadline=None)
@given(
    xp=st.floats(min_value=1e-8, max_value=1e4),
    ratio=st.floats(min_value=0.0, max_value=2.0),
    n1=st.floats(min_value=0.1, max_value=1000.0),
    n2=st.floats(min_value=0.1, max_value=1000.0),
    C1=st.floats(min_value=0.05, max_value=20.0),
    C2=st.floats(min_value=0.05, max_value=50.0),
    cont=st.booleans(),
)
def test_kernels_agree_with_numpy_oracle(xp, ratio, n1, n2, C1, C2, cont):
    P = params(n1=n1, n2=n2, C1=C1, C2=C2, continuous=cont)
    p = xp * H / C1
    p_hist = ratio * p
    got = fl.shear_limit(p, p_hist, P)
    want = ref.sbmf_shear(p, p_hist, P.tau_max, C1, n1, C2, n2, H, cont)
    assert got == pytest.approx(float(want), rel=1e-12, abs=1e-300)
    assert fl.alpha_first(p, P) == pytest.approx(float(ref.alpha_first(p, C1, n1, H)), rel=1e-12)
    if p_hist > 0:
        a2 = ref.alpha_reload(p, p_hist, C1, n1, C2, n2, H, cont)
        assert fl.alpha_reload(p, p_hist, P) == pytest.approx(float(a2), rel=1e-12, abs=1e-300)


@settings(max_examples=200, deadline=None)
@given(x=st.floats(min_value=1e-300, max_value=1e300), n=st.floats(min_value=0.1, max_value=1000.0))
def test_smooth_min_scalar_kernel_against_oracle(x, n):
    g, gox, dg = kernels.smooth_min_scalar(x, n)
    assert g == pytest.approx(float(ref.smooth_min(x, n)), rel=1e-12, abs=1e-300)
    assert 0.0 <= g <= 1.0 and 0.0 <= dg <= 1.0 + 1e-15


def test_serial_and_parallel_kernels_identical():
    P = params()
    rng = np.random.default_rng(0)
    p = rng.uniform(0, 2 * H, 200_001)
    ph = rng.uniform(0, 2 * H, p.size)
    coeffs = fl.SBMFLaw(P).coeffs
    out = [np.empty(p.size) for _ in range(4)]
    kernels.shear_array(3, coeffs, p, ph, out[0], out[1])
    kernels.shear_array_parallel(3, coeffs, p, ph, out[2], out[3])
    assert np.array_equal(out[0], out[2]) and np.array_equal(out[1], out[3])
