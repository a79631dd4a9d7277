"""Stick/slip return map against the NumPy oracle, consistent tangent, history semantics."""

import numba
import numpy as np
import pytest

import frictionlaw as fl
from frictionlaw import _reference as ref
from frictionlaw import kernels

H = 800e6
P = fl.FrictionParams(m=0.6, sigma_y=H / 2.8, H=H, C1=1.2, n1=2.0, C2=3.0, n2=2.0)
LAWS = [fl.Coulomb(0.12), fl.Tresca(0.6, 150e6), fl.CoulombCap(0.12, 60e6), fl.SBMFLaw(P)]


def random_case(rng, n, d):
    p = rng.uniform(-0.2, 1.5, n) * H
    p[:5] = 0.0
    du = rng.normal(size=(n, d)) * 1e-6
    t_old = rng.normal(size=(n, d)) * 2e7
    kt = rng.uniform(1e12, 1e14, n)
    return p, du, t_old, kt


@pytest.mark.parametrize("law", LAWS, ids=lambda x: type(x).__name__)
@pytest.mark.parametrize("d", [1, 2])
def test_against_numpy_oracle(law, d):
    rng = np.random.default_rng(1)
    p, du, t_old, kt = random_case(rng, 2000, d)
    p_hist = rng.uniform(0, 1.5, p.size) * H
    state = fl.HistoryState(p_hist=p_hist) if law.uses_history else None
    res = fl.traction_update(law, p, du, t_old, kt, state)
    tau, _ = law.shear_limit(p, p_hist if law.uses_history else 0.0)
    tau = np.where(p > 0, tau, np.nan)
    t_ref, st_ref = ref.traction_update(tau, du, t_old, kt)
    np.testing.assert_allclose(res.traction, t_ref, rtol=1e-13, atol=1e-6)
    assert np.array_equal(res.status, st_ref)
    assert {0, 1, 2} <= set(np.unique(res.status))
    # complementarity: |t| <= tau everywhere, = tau on slip nodes, 0 on open nodes
    norm = np.linalg.norm(res.traction, axis=1)
    closed = p > 0
    assert np.all(norm[closed] <= tau[closed] * (1 + 1e-14))
    np.testing.assert_allclose(norm[res.status == 2], tau[res.status == 2], rtol=1e-14)
    assert np.all(norm[~closed] == 0)


@pytest.mark.parametrize("law", LAWS, ids=lambda x: type(x).__name__)
def test_consistent_tangent_matches_finite_differences(law):
    rng = np.random.default_rng(2)
    p, du, t_old, kt = random_case(rng, 400, 2)
    p = np.abs(p) + 1e7
    state_hist = rng.uniform(0, 1.5, p.size) * H
    state = fl.HistoryState(p_hist=state_hist) if law.uses_history else None
    res = fl.traction_update(law, p, du, t_old, kt, state)
    h = 1e-7 * np.maximum(np.abs(du).max(axis=1), 1e-9)
    for b in range(2):
        e = np.zeros_like(du)
        e[:, b] = h
        plus = fl.traction_update(law, p, du + e, t_old, kt, state).traction
        minus = fl.traction_update(law, p, du - e, t_old, kt, state).traction
        fd = (plus - minus) / (2 * h[:, None])
        np.testing.assert_allclose(res.dt_dslip[:, :, b], fd, rtol=1e-5, atol=1e-6 * kt.max())
    hp = 1e-7 * p
    away = np.abs(p - state_hist) > 1e-3 * H  # the paper's law may jump at p = p_hist
    plus = fl.traction_update(law, p + hp, du, t_old, kt, state).traction
    minus = fl.traction_update(law, p - hp, du, t_old, kt, state).traction
    fd = (plus - minus) / (2 * hp[:, None])
    np.testing.assert_allclose(res.dt_dp[away], fd[away], rtol=1e-5, atol=1e-9)


def test_history_is_proposed_not_committed_during_iterations():
    law = fl.SBMFLaw(P)
    st = fl.HistoryState(2)
    du = np.zeros((2, 1))
    for p_iter in ([5e8, 1e8], [3e8, 2e8], [4e8, 1e8]):  # Newton iterations of one increment
        fl.traction_update(law, np.array(p_iter), du, du, 1e13, st)
        assert np.array_equal(st.p_hist, [0, 0])
    assert np.array_equal(st.p_hist_trial, [4e8, 1e8])  # last iteration, not the maximum seen
    st.commit()
    # next increment unloads node 0 to 1e8 Pa: Eq. 25 applies there
    res = fl.traction_update(law, np.array([1e8, 1e8]), np.ones((2, 1)), np.zeros((2, 1)), 1e13, st)
    np.testing.assert_allclose(
        res.traction[:, 0], [fl.shear_limit(1e8, 4e8, P), fl.shear_limit(1e8, 0, P)]
    )
    assert res.traction[0, 0] > res.traction[1, 0]  # smoothed surface: more real contact area


def test_force_adapter_equals_stress_update_times_area():
    rng = np.random.default_rng(3)
    p, du, t_old, kt = random_case(rng, 500, 2)
    area = rng.uniform(1e-6, 1e-4, p.size)
    law = fl.SBMFLaw(P)
    s = fl.traction_update(law, p, du, t_old, kt)
    f = fl.traction_update_force(law, p * area, area, du, t_old * area[:, None], kt * area)
    np.testing.assert_allclose(f.traction, s.traction * area[:, None], rtol=1e-13, atol=1e-20)
    np.testing.assert_allclose(f.dt_dslip, s.dt_dslip * area[:, None, None], rtol=1e-13)
    np.testing.assert_allclose(f.dt_dp, s.dt_dp, rtol=1e-13)
    assert np.array_equal(f.status, s.status)


def test_one_direction_shape_and_serial_parallel_agree():
    rng = np.random.default_rng(4)
    p, du, t_old, kt = random_case(rng, 1000, 1)
    law = fl.CoulombCap(0.1, 50e6)
    r1 = fl.traction_update(law, p, du[:, 0], t_old[:, 0], kt, parallel=False)
    r2 = fl.traction_update(law, p, du[:, 0], t_old[:, 0], kt, parallel=True)
    assert r1.traction.shape == (1000,) and r1.dt_dslip.shape == (1000,)
    for a, b in zip(r1, r2, strict=True):
        assert np.array_equal(a, b)


def test_scalar_kernel_callable_from_host_njit_loop():
    law = fl.SBMFLaw(P)
    code, coeffs = law.code, law.coeffs

    @numba.njit
    def host(p, p_hist, out):
        for i in range(p.size):
            out[i] = kernels.shear_scalar(code, coeffs, p[i], p_hist[i])[0]

    p = np.linspace(0, 2 * H, 50)
    ph = np.full(50, 0.7 * H)
    out = np.empty(50)
    host(p, ph, out)
    np.testing.assert_array_equal(out, fl.shear_limit(p, ph, P))


def test_bad_input_messages():
    law = fl.Coulomb(0.1)
    z = np.zeros((3, 2))
    with pytest.raises(ValueError, match="k_t must be finite and > 0"):
        fl.traction_update(law, np.ones(3), z, z, 0.0)
    with pytest.raises(ValueError, match=r"slip_increment must have shape \(3,\)"):
        fl.traction_update(law, np.ones(3), np.zeros((3, 3)), np.zeros((3, 3)), 1.0)
    with pytest.raises(ValueError, match="traction_old must be finite"):
        fl.traction_update(law, np.ones(3), z, np.full((3, 2), np.inf), 1.0)
    with pytest.raises(ValueError, match="state has 2 nodes"):
        fl.traction_update(fl.SBMFLaw(P), np.ones(3), z, z, 1.0, fl.HistoryState(2))
    with pytest.raises(ValueError, match="mu must be in"):
        fl.Coulomb(-0.1)
    with pytest.raises(ValueError, match="law must be one of"):
        fl.law_from_name("amontons")


def test_row_and_scalar_kernels_match_the_array_kernel():
    rng = np.random.default_rng(5)
    p, du, t_old, kt = random_case(rng, 300, 2)
    law = fl.SBMFLaw(P)
    ph = rng.uniform(0, 1.5, p.size) * H
    res = fl.traction_update(law, p, du, t_old, kt, fl.HistoryState(p_hist=ph))
    # row kernel over the host's 2-D arrays, node by node
    t_new, dtd, dtp = np.empty_like(du), np.empty((p.size, 2, 2)), np.empty_like(du)
    st = [
        kernels.traction_row(
            law.code, law.coeffs, p[i], ph[i], du, t_old, kt[i], t_new, dtd, dtp, i
        )
        for i in range(p.size)
    ]
    assert np.array_equal(st, res.status)
    for a, b in ((t_new, res.traction), (dtd, res.dt_dslip), (dtp, res.dt_dp)):
        np.testing.assert_array_equal(a, b)
    # 1-D scalar kernel, one node at a time
    for i in range(0, p.size, 7):
        t1, d1, q1 = np.empty(2), np.empty((2, 2)), np.empty(2)
        s1 = kernels.traction_scalar(
            law.code, law.coeffs, p[i], ph[i], du[i].copy(), t_old[i].copy(), kt[i], t1, d1, q1
        )
        assert s1 == res.status[i]
        np.testing.assert_array_equal(t1, res.traction[i])
        np.testing.assert_array_equal(d1, res.dt_dslip[i])
        np.testing.assert_array_equal(q1, res.dt_dp[i])


@pytest.mark.parametrize("d", [1, 2])
def test_output_buffers_are_reused(d):
    rng = np.random.default_rng(6)
    p, du, t_old, kt = random_case(rng, 500, d)
    if d == 1:
        du, t_old = du[:, 0], t_old[:, 0]
    law = fl.SBMFLaw(P)
    first = fl.traction_update(law, p, du, t_old, kt)
    buf = fl.TractionResult(*(np.full_like(a, 7) for a in first))
    again = fl.traction_update(law, p, du, t_old, kt, out=buf)
    assert again is buf
    for a, b in zip(first, buf, strict=True):
        np.testing.assert_array_equal(a, b)
    with pytest.raises(ValueError, match="out.status must be a writable C-contiguous int8 array"):
        fl.traction_update(law, p, du, t_old, kt, out=buf._replace(status=np.zeros(500)))


def test_one_law_factory_for_runtime_and_fe_demo():
    from fe_demo.scenes.laws import make_law_factory

    # cap with m = 0 has a zero cap (it used to fall back to tau_max = k)
    assert fl.law_from_name("cap", mu=0.1, m=0.0, k=1e8).tau_max == 0.0
    assert fl.law_from_name("cap", mu=0.1, tau_max=5e7).tau_max == 5e7
    with pytest.raises(ValueError, match="cap needs tau_max"):
        fl.law_from_name("cap", mu=0.1)

    class Model:  # the FE demo's k = sigma_f / sqrt(3) at the current strain
        def flow_stress_hom(self):
            return 3e8

    k = 3e8 / np.sqrt(3.0)
    for name in ("coulomb", "tresca", "cap"):
        got = make_law_factory(name, mu=0.12, m=0.3)(Model())
        assert got == fl.law_from_name(name, mu=0.12, m=0.3, k=k)
    assert make_law_factory("cap", mu=0.1, m=0.0)(Model()).tau_max == 0.0
    sbmf = make_law_factory("sbmf", params=P)(Model())
    assert sbmf == fl.law_from_name("sbmf", params=P)
