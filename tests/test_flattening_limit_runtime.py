"""The two-state flattening (model limit-analysis) in the runtime: kernels, state, tangent.

The NumPy oracle is frictionlaw.flattening_limit.limit_update (the table read and integrated by
frictionlaw._limit_table in NumPy) with Eq. F5 of frictionlaw.flattening; the kernels of
frictionlaw/_kernels_limit.py read the same table node by node.
"""

import math

import numpy as np
import pytest

import frictionlaw as fl
from frictionlaw import _kernels_limit as KL
from frictionlaw._limit_table import rate_table, table_rates
from frictionlaw.flattening import flattened_alpha, flattening_pressure
from frictionlaw.flattening_limit import limit_update
from frictionlaw.reload_form import ReloadTable

H = 8e8
BASE = dict(m=0.5, sigma_y=H / 2.8, H=H, C1=1.05, n1=2.87, C2=7.44, n2=0.575)
RT = ReloadTable((1e8, 4e8, 7e8), (3.0, 6.0, 12.0), (0.5, 1.0, 2.0), 0.7)
FORMS = {
    "eq24-paper": {},
    "eq24-tabulated-continuous": dict(
        reload_form="tabulated", reload_table=RT, continuous_reload=True
    ),
}


def law(slope=0.1, beta=1.0, model="limit-analysis", **kw):
    flat = fl.Flattening(slope=slope, beta=beta, model=model)
    return fl.FrictionParams(**{**BASE, **kw}, flattening=flat)


def update(P, p, p_hist, alpha_f, slope_f, d_eps, sigma_y=None, parallel=None, zone=None):
    """One traction update at slipping nodes: (tau, dt_dp, state after it). ``P`` a parameter
    file, or a ZonedLaw with each node's ``zone``."""
    n = np.size(p)
    state = fl.HistoryState(
        p_hist=np.broadcast_to(p_hist, n),
        alpha_f=np.broadcast_to(alpha_f, n),
        slope_f=np.broadcast_to(slope_f, n),
    )
    law, kw = (P, {"zone": zone}) if zone is not None else (fl.SBMFLaw(P), {})
    res = fl.traction_update(
        law, p, np.ones(n), np.zeros(n), 1e20, state, d_eps=d_eps, sigma_y=sigma_y,
        parallel=parallel, **kw,
    )  # fmt: skip
    return res.traction, res.dt_dp, state


def grid():
    p = np.array([0.005, 0.02, 0.05, 0.1, 0.3, 0.6, 0.9]) * H
    g = np.meshgrid(
        p, [0.0, 0.5, 1.0, 2.0], [0.0, 0.2, 0.6], [0.0, 0.03], [0.0, 1e-4, 0.01, 0.1], indexing="ij"
    )
    p, fac, af, sf, de = (a.ravel() for a in g)
    return p, fac * p, af, sf, de


@pytest.mark.parametrize("form", FORMS)
def test_kernel_states_and_shear_against_the_numpy_model(form):
    P = law(**FORMS[form])
    p, ph, af, sf, de = grid()
    tau, _, st = update(P, p, ph, af, sf, de)
    a_ref, s_ref = limit_update(af, sf, np.maximum(ph, p), p, de, P)
    np.testing.assert_allclose(st.alpha_f_trial, a_ref, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(st.slope_f_trial, s_ref, rtol=1e-13, atol=0)
    assert np.array_equal(st.p_hist_trial, np.maximum(ph, p))
    tau_ref = P.tau_max * flattened_alpha(p, ph, flattening_pressure(a_ref, P), P)
    full = (p < ph) & (fl.alpha_first(ph, P) >= 1.0)  # the law itself there (as one-state)
    np.testing.assert_allclose(tau[~full], tau_ref[~full], rtol=1e-9, atol=0)


def test_the_rate_kernel_against_the_numpy_reading():
    t = rate_table()
    tab = (t.pressures, t.offsets, t.a, t.ln_s, t.dA, t.ds)
    rng = np.random.default_rng(7)
    x = 10 ** rng.uniform(-2.5, 0.2, 3000)
    A = rng.uniform(0, 1, 3000)
    s = 10 ** rng.uniform(-3, 0, 3000)
    dA, ds = table_rates(x, A, s, t)
    got = np.array(
        [KL.limit_rates_scalar(*tab, xi, ai, si) for xi, ai, si in zip(x, A, s, strict=True)]
    )
    np.testing.assert_allclose(got[:, 0], dA, rtol=1e-13, atol=1e-12)
    np.testing.assert_allclose(got[:, 1], ds, rtol=1e-13, atol=1e-12)


def test_zero_strain_and_no_state_is_todays_law_bit_for_bit():
    P = law()
    p, ph, *_ = grid()
    tau, dtdp, st = update(P, p, ph, 0.0, 0.0, 0.0)
    plain = fl.FrictionParams(**BASE)
    n = p.size
    ref = fl.traction_update(
        fl.SBMFLaw(plain), p, np.ones(n), np.zeros(n), 1e20, fl.HistoryState(p_hist=ph)
    )
    assert np.array_equal(tau, ref.traction) and np.array_equal(dtdp, ref.dt_dp)
    assert np.array_equal(st.slope_f_trial, np.zeros(n))


def test_two_increments_are_one_iterations_never_ratchet_and_restart_carries_both(tmp_path):
    P = law()
    p = np.array([0.02, 0.1, 0.4]) * H
    d = 0.01 / (math.sqrt(3) / 2)  # a stretch of 20 steps
    _, _, one = update(P, p, 0.0, 0.0, 0.0, 2 * d)
    s = fl.HistoryState(3)
    for _ in range(2):
        fl.traction_update(fl.SBMFLaw(P), p, np.ones(3), np.zeros(3), 1e20, s, d_eps=d)
        s.commit()
    np.testing.assert_allclose(s.alpha_f, one.alpha_f_trial, atol=1e-14)
    np.testing.assert_allclose(s.slope_f, one.slope_f_trial, rtol=1e-13)
    # iterations of one increment start from the committed states; a cut-back drops them
    committed = (s.alpha_f.copy(), s.slope_f.copy())
    for de in (0.05, 0.001):
        fl.traction_update(fl.SBMFLaw(P), p, np.ones(3), np.zeros(3), 1e20, s, d_eps=de)
    a_ref, s_ref = limit_update(*committed, s.p_hist, p, 0.001, P)
    assert np.array_equal(s.alpha_f_trial, a_ref) and np.array_equal(s.slope_f_trial, s_ref)
    s.rollback()
    assert np.array_equal(s.slope_f_trial, committed[1])
    t = fl.HistoryState.load(s.save(tmp_path / "r.npz"))
    assert np.array_equal(t.slope_f, s.slope_f) and np.array_equal(t.alpha_f, s.alpha_f)
    # without a strain increment a flattened node is read (no growth), its slope kept
    tau, _, st = update(P, p, t.p_hist, t.alpha_f, t.slope_f, 0.0)
    assert np.array_equal(st.slope_f_trial, t.slope_f)
    np.testing.assert_allclose(tau, P.tau_max * t.alpha_f, rtol=1e-12)


def test_tangent_is_the_derivative_of_the_flattened_shear():
    P = law()
    for pr, phr, af in ((0.2, 0.0, 0.0), (0.05, 0.0, 0.0), (0.3, 0.1, 0.4), (0.02, 0.0, 0.0)):
        p, ph = pr * H, phr * H
        h = 1e-4 * p
        t, dtdp, _ = update(P, np.array([p - h, p, p + h]), ph, af, 0.0, 0.01)
        fd = (t[2] - t[0]) / (2 * h)
        assert dtdp[1] == pytest.approx(fd, rel=2e-3)


def test_tangent_is_the_forward_difference_of_the_numpy_model():
    """The update's d alpha/dp, carried through the integration, against a forward difference
    (relative step 1e-7) of the NumPy model's fraction at every first-loading node of the grid
    that flattened beyond alpha1(p): 6e-6 relative (the difference's own error; the right
    derivative at the table's grid lines and at p = p_hist, as the difference takes it)."""
    P = law()
    p, ph, af, sf, de = grid()
    _, dtdp, st = update(P, p, ph, af, sf, de)
    sel = (p >= ph) & (st.alpha_f_trial > fl.alpha_first(p, P)) & (de > 0)
    assert sel.sum() > 300
    h = 1e-7
    a_up, _ = limit_update(af, sf, np.maximum(ph, p * (1 + h)), p * (1 + h), de, P)
    a_at, _ = limit_update(af, sf, np.maximum(ph, p), p, de, P)
    fd = (a_up - a_at) / (p * (1 + h) - p)
    np.testing.assert_allclose(dtdp[sel] / P.tau_max, fd[sel], rtol=1e-5)


def test_serial_and_parallel_agree_bit_for_bit():
    P = law()
    p, ph, af, sf, de = grid()
    a = update(P, p, ph, af, sf, de, parallel=False)
    b = update(P, p, ph, af, sf, de, parallel=True)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    assert np.array_equal(a[2].slope_f_trial, b[2].slope_f_trial)
    assert np.array_equal(a[2].alpha_f_trial, b[2].alpha_f_trial)


def test_the_host_flow_stress_against_the_numpy_model():
    P = law()
    p, ph, af, sf, de = grid()
    sy = np.linspace(0.5, 2.0, p.size) * P.sigma_y
    _, _, st = update(P, p, ph, af, sf, de, sigma_y=sy)
    a_ref, s_ref = limit_update(af, sf, np.maximum(ph, p), p, de, P, sigma_y=sy)
    np.testing.assert_allclose(st.alpha_f_trial, a_ref, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(st.slope_f_trial, s_ref, rtol=1e-13)


def test_hardening_is_refused_before_any_work():
    P = law()
    s = fl.HistoryState(2)
    with pytest.raises(ValueError, match="hardening does not apply to the two-state"):
        fl.traction_update(
            fl.SBMFLaw(P), [1e8, 1e8], np.ones(2), np.zeros(2), 1e20, s, d_eps=0.01, hardening=1e9
        )
    assert np.array_equal(s.alpha_f_trial, np.zeros(2))
    zl = fl.ZonedLaw.from_mapping(
        {"die": fl.SBMFLaw(P), "punch": fl.SBMFLaw(law(model="layer-yield"))}
    )
    with pytest.raises(ValueError, match="hardening does not apply to the two-state"):
        fl.traction_update(
            zl, [1e8, 1e8], np.ones(2), np.zeros(2), 1e20, s, zone=[1, 1], d_eps=0.01,
            hardening=1e9,
        )  # fmt: skip


@pytest.mark.parametrize("parallel", [False, True])
def test_zones_run_each_zone_and_the_states_travel(parallel):
    """A zoned law with a two-state zone, a one-state zone and one without a block: each node is
    its zone's one-law update bit for bit (the two-state zone's both states; the others'
    fraction, the slope passed on as it came), serial and parallel alike."""
    two, one, plain = law(0.1), law(0.05, model="layer-yield"), fl.FrictionParams(**BASE)
    zl = fl.ZonedLaw(("a", "b", "c"), (fl.SBMFLaw(two), fl.SBMFLaw(one), fl.SBMFLaw(plain)))
    assert zl.uses_two_state and list(zl.flattening_models()) == [1, 0, 0]
    p, ph, af, sf, de = grid()
    n = p.size
    for z, P in enumerate((two, one, plain)):
        zone = np.full(n, z)
        tz, dz, sz = update(zl, p, ph, af, sf, de, parallel=parallel, zone=zone)
        if P.flattening is None:
            ref = fl.SBMFLaw(P).shear_limit(p, ph)
            assert np.array_equal(tz, ref[0]) and np.array_equal(sz.alpha_f_trial, af)
        else:
            t1, d1, s1 = update(P, p, ph, af, sf, de, parallel=parallel) if z == 0 else (
                *_one_state(P, p, ph, af, de), None
            )  # fmt: skip
            assert np.array_equal(tz, t1) and np.array_equal(dz, d1)
            if s1 is not None:
                assert np.array_equal(sz.alpha_f_trial, s1.alpha_f_trial)
                assert np.array_equal(sz.slope_f_trial, s1.slope_f_trial)
        if z > 0:  # only a two-state zone turns the flank
            assert np.array_equal(sz.slope_f_trial, sf)
    # flattened under a, the node comes under b: b reads the fraction through its own alpha1
    # and leaves the slope as it came; back under a, the turned slope is read again
    q = np.array([0.05, 0.1, 0.3]) * H
    _, _, s_a = update(zl, q, 0.0, 0.0, 0.0, 0.05, zone=np.zeros(3, int))
    a_a, f_a = s_a.alpha_f_trial.copy(), s_a.slope_f_trial.copy()
    assert np.all(f_a > 0) and np.any(np.abs(f_a - 0.1) > 1e-3)
    t_b, _, s_b = update(zl, q, q, a_a, f_a, 0.0, zone=np.ones(3, int))
    assert np.array_equal(s_b.alpha_f_trial, a_a) and np.array_equal(s_b.slope_f_trial, f_a)
    assert np.allclose(t_b, one.tau_max * np.maximum(fl.alpha_first(q, one), a_a), rtol=1e-12)
    _, _, s_back = update(zl, q, q, a_a, f_a, 0.02, zone=np.zeros(3, int))
    _, _, s_ref = update(two, q, q, a_a, f_a, 0.02)
    assert np.array_equal(s_back.slope_f_trial, s_ref.slope_f_trial)


def _one_state(P, p, p_hist, alpha_f, d_eps):
    """The one-state law's update at slipping nodes: (tau, dt_dp)."""
    n = np.size(p)
    state = fl.HistoryState(p_hist=np.broadcast_to(p_hist, n), alpha_f=np.broadcast_to(alpha_f, n))
    res = fl.traction_update(fl.SBMFLaw(P), p, np.ones(n), np.zeros(n), 1e20, state, d_eps=d_eps)
    return res.traction, res.dt_dp


def test_extremes_are_finite_and_at_most_one():
    P = law(0.2)
    p = np.array([1e-30, 1e-3, 1e5, 0.5 * H, 3 * H, 1e3 * H])
    tau, dtdp, st = update(P, p, 0.0, 0.0, 0.0, 1e3)
    assert np.all(np.isfinite(tau)) and np.all(np.isfinite(dtdp))
    assert np.all(st.alpha_f_trial <= 1.0) and np.all(st.slope_f_trial >= 0)


def test_the_routines_whose_host_passes_the_strain_export_it(tmp_path, capsys):
    """Every routine target whose host passes the bulk strain exports the two-state block (exit
    0; its routine carries the table, tests/test_export_flattening_limit.py runs them); hosts
    without strain and tables run the law without flattening, with the user's word, as for the
    one-state block."""
    from frictionlaw import export as exp
    from frictionlaw.export.cli import main

    path = law().to_json(tmp_path / "two.json")
    for target in ("lsdyna-usrfrc", "lsdyna-usrfrc-mpp", "lsdyna", "ansys-userfric", "calculix"):
        out = tmp_path / target
        assert main([target, "--params", str(path), "--out", str(out), "--quiet"]) == 0
        routine = next(f for f in out.iterdir() if f.suffix == ".f")
        assert "SBMF_TSHR" in routine.read_text()
    assert main(["abaqus-fric", "--params", str(path), "--out", str(tmp_path / "a")]) == 2
    assert "--without-flattening" in capsys.readouterr().err
    assert exp.render("abaqus-fric", path, without_flattening=True)[0]
    assert exp.render("abaqus-table", path, without_flattening=True)[0]
