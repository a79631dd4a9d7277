"""The flattening under bulk strain in the runtime (issue 43 part C): kernels, state, zones.

The NumPy oracle is part A's model itself (frictionlaw.flattening: flattening_update, Eq. F6,
and flattened_alpha, Eq. F5), which integrates Eq. F4 from the virgin surface by its own
quadrature and inverts it by its own Newton; the kernels integrate the increment's interval
only and hold the state as a contact fraction (docs/flattening.md, "In the runtime").
"""

import math

import numpy as np
import pytest
from scipy import integrate, optimize

import frictionlaw as fl
from frictionlaw import _kernels_flattening as KF
from frictionlaw.first_loading import FirstLoadingTable
from frictionlaw.flattening import (
    flattened_alpha,
    flattening_pressure,
    flattening_update,
)
from frictionlaw.law import evaluate, sbmf_coeffs
from frictionlaw.reload_form import ReloadTable

H = 8e8
BASE = dict(m=0.5, sigma_y=H / 2.8, H=H, C1=1.05, n1=2.87, C2=7.44, n2=0.575)
RT = ReloadTable((1e8, 4e8, 7e8), (3.0, 6.0, 12.0), (0.5, 1.0, 2.0), 0.7)
FT = FirstLoadingTable(
    p=(2e7, 5e7, 1e8, 2e8, 3e8, 4e8, 6e8, 7.6e8),
    alpha=(0.026, 0.064, 0.127, 0.25, 0.37, 0.48, 0.66, 0.79),
)


def law(slope=0.05, beta=1.0, **kw):
    return fl.FrictionParams(**{**BASE, **kw}, flattening=fl.Flattening(slope=slope, beta=beta))


FORMS = {
    "eq24-paper": {},
    "eq24-tabulated-continuous": dict(
        reload_form="tabulated", reload_table=RT, continuous_reload=True
    ),
    "tabulated-first": dict(first_loading_form="tabulated", first_loading_table=FT),
}


def update(P, p, p_hist, alpha_f, d_eps, sigma_y=None, zone=None, law_=None, hardening=None):
    """One traction update at slipping nodes: (tau, dt_dp, trial alpha_f, trial p_hist)."""
    n = np.size(p)
    state = fl.HistoryState(p_hist=np.broadcast_to(p_hist, n), alpha_f=np.broadcast_to(alpha_f, n))
    du = np.full(n, 1.0)  # a large slip: every node in contact slips
    res = fl.traction_update(
        law_ or fl.SBMFLaw(P),
        p,
        du,
        np.zeros(n),
        1e20,
        state,
        d_eps=d_eps,
        sigma_y=sigma_y,
        zone=zone,
        hardening=hardening,
    )
    return res.traction, res.dt_dp, state.alpha_f_trial.copy(), state.p_hist_trial.copy()


def grid():
    p = np.array([0.01, 0.05, 0.1, 0.3, 0.6, 0.9]) * H
    ph_fac = np.array([0.0, 0.5, 1.0, 2.0])
    af = np.array([0.0, 0.2, 0.5, 0.8])
    de = np.array([1e-5, 1e-3, 0.01, 0.1, 0.5])
    g = np.meshgrid(p, ph_fac, af, de, indexing="ij")
    p, fac, af, de = (a.ravel() for a in g)
    return p, fac * p, af, de


# ----------------------------------------------------------------------------- the oracle
@pytest.mark.parametrize("form", FORMS)
def test_kernel_update_and_law_against_the_numpy_model(form):
    P = law(**FORMS[form])
    p, ph, af, de = grid()
    tau, _, a_k, ph_trial = update(P, p, ph, af, de)
    # the oracle: the fraction as part A's flattening pressure, Eq. F6 from the trial history
    pf0 = flattening_pressure(af, P)
    pf = flattening_update(pf0, np.maximum(ph, p), p, de, P)
    a_ref = np.maximum(fl.alpha_first(pf, P), af)
    # both quadratures split at the tabulated form's kinks (its levels and where it reaches 1)
    tol = 1e-9
    assert np.allclose(a_k, a_ref, rtol=tol, atol=1e-12)
    assert np.all(a_k >= af) and np.all(a_k <= 1.0)
    assert np.array_equal(ph_trial, np.maximum(ph, p))
    # the runtime's state is the fraction: F5 reads it at the pressure whose alpha1 it is (where
    # the fraction is 1 the solve's p_f is any pressure beyond the tabulated form's top)
    tau_ref = P.tau_max * flattened_alpha(p, ph, flattening_pressure(a_ref, P), P)
    # a history already in full contact (alpha1(p_hist) = 1): flattening adds nothing and the
    # runtime runs the law itself; part A reads the reload branch at its capped p_f there
    full = (p < ph) & (fl.alpha_first(ph, P) >= 1.0)
    assert np.allclose(tau[~full], tau_ref[~full], rtol=tol, atol=0)
    assert np.array_equal(tau[full], fl.shear_limit(p[full], ph[full], P))


def test_tabulated_first_loading_against_adaptive_quadrature():
    """The tabulated form's kinks: the kernel splits its interval there, SciPy's quad too."""
    P = law(**FORMS["tabulated-first"])
    c = sbmf_coeffs(P, 1.0)
    nj = len(FT.p)
    u, v, d = (c[-3 * nj :][k * nj : (k + 1) * nj] for k in range(3))
    # the levels, and where the top level's power law reaches a contact fraction of 1
    knots = np.r_[FT.p, H * np.exp(u[-1] - v[-1] / d[-1])]

    def J(p, top):
        def f(t):
            a, d = evaluate(3, c, t, 0.0)
            s = np.sqrt(max(t * t - p * p, 0.0))
            W = 1.0 + (1.0 + 0.05 * (1.0 - a)) * t * s / (2 * P.k * p)  # the lattice's share
            return d * t * s / W

        pts = [k for k in knots if p < k < top] or None
        return integrate.quad(f, p, top, points=pts, limit=1000, epsabs=0, epsrel=1e-12)[0]

    cap = fl.SBMFLaw(P).flattening_data[4]
    for pr, af, de in (
        (0.05, 0, 1e-3),
        (0.1, 0, 0.01),
        (0.3, 0, 0.01),
        (0.2, 0, 0.005),
        (0.3, 0, 0.003),
        (0.01, 0.8, 0.002),
    ):
        p = pr * H
        pf0 = max(float(flattening_pressure(af, P)), p)
        target = J(p, pf0) + de * (math.sqrt(3.0) / 2.0) * 2 * P.k * p / 0.05  # stretch
        assert J(p, cap) > target  # each case ends below full contact
        top = optimize.brentq(lambda x, p=p, t=target: J(p, x) - t, pf0, cap, xtol=1e-6)
        _, _, a, _ = update(P, np.array([p]), 0.0, af, de)
        assert a[0] == pytest.approx(fl.alpha_first(top, P), rel=1e-11)


def test_zero_strain_is_todays_law_bit_for_bit():
    for kw in FORMS.values():
        P = law(**kw)
        rng = np.random.default_rng(3)
        n = 500
        p = rng.uniform(-0.1, 1.3, n) * H
        ph = rng.uniform(0, 1.2, n) * H * (rng.random(n) < 0.7)
        du = rng.normal(size=(n, 2)) * 1e-6
        t_old = rng.normal(size=(n, 2)) * 3e7
        base = fl.traction_update(fl.SBMFLaw(P), p, du, t_old, 1e13, fl.HistoryState(p_hist=ph))
        s = fl.HistoryState(p_hist=ph)
        flat = fl.traction_update(fl.SBMFLaw(P), p, du, t_old, 1e13, s, d_eps=np.zeros(n))
        for a, b in zip(base, flat, strict=True):
            assert np.array_equal(a, b)
        assert np.array_equal(s.alpha_f_trial, np.zeros(n))
        # a law without the block, no d_eps: the same numbers again
        plain = fl.FrictionParams(**{**BASE, **kw})
        again = fl.traction_update(
            fl.SBMFLaw(plain), p, du, t_old, 1e13, fl.HistoryState(p_hist=ph)
        )
        for a, b in zip(base, again, strict=True):
            assert np.array_equal(a, b)


def test_alpha1_inverse_against_bisection():
    for kw in FORMS.values():
        P = law(**kw)
        fd = fl.SBMFLaw(P).flattening_data
        a = np.array([1e-6, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.97])
        ref = flattening_pressure(a, P)
        assert np.allclose(fl.alpha_first(ref, P), a, rtol=1e-13)
        ker = np.array([KF.alpha1_inverse(fd[KF.FLAT_HEAD :], x, 1.0, fd[4]) for x in a])
        assert np.allclose(ker, ref, rtol=1e-12)


# ----------------------------------------------------------------------------- Eq. F6 rules
def test_two_increments_are_one_and_iterations_never_ratchet():
    P = law()
    p = np.array([0.05, 0.2, 0.4]) * H
    # one increment of 0.02 against two of 0.01, committed between
    _, _, a_one, _ = update(P, p, 0.0, 0.0, 0.02)
    s = fl.HistoryState(3)
    kw = dict(d_eps=0.01)
    for _ in range(2):
        fl.traction_update(fl.SBMFLaw(P), p, np.ones(3), np.zeros(3), 1e20, s, **kw)
        s.commit()
    assert np.allclose(s.alpha_f, a_one, rtol=1e-10)
    # Newton iterations of one increment: each from the committed state, the last one counts
    s = fl.HistoryState(3)
    for de in (0.05, 0.001, 0.01):
        fl.traction_update(fl.SBMFLaw(P), p, np.ones(3), np.zeros(3), 1e20, s, d_eps=de)
    _, _, a_ref, _ = update(P, p, 0.0, 0.0, 0.01)
    assert np.array_equal(s.alpha_f_trial, a_ref) and np.array_equal(s.alpha_f, np.zeros(3))
    s.rollback()
    assert np.array_equal(s.alpha_f_trial, np.zeros(3))


def test_restart_remap_and_resize_carry_alpha_f(tmp_path):
    P = law()
    s = fl.HistoryState(4)
    p = np.array([0.1, 0.2, 0.0, 0.4]) * H
    fl.traction_update(fl.SBMFLaw(P), p, np.ones(4), np.zeros(4), 1e20, s, d_eps=0.02)
    s.commit()
    assert s.alpha_f[2] == 0.0 and np.all(s.alpha_f[[0, 1, 3]] > fl.alpha_first(p[[0, 1, 3]], P))
    t = fl.HistoryState.load(s.save(tmp_path / "r.npz"))
    assert np.array_equal(t.alpha_f, s.alpha_f) and np.array_equal(t.p_hist, s.p_hist)
    t.remap(np.array([3, -1, 0]))
    assert np.array_equal(t.alpha_f, [s.alpha_f[3], 0.0, s.alpha_f[0]])
    t.resize(5)
    assert t.alpha_f[3:].tolist() == [0.0, 0.0]
    # a version 1 restart file (p_hist only) reads with alpha_f = 0
    np.savez(
        tmp_path / "v1.npz",
        format=np.array("sbmf-friction-restart"),
        version=np.array(1),
        p_hist=np.ones(2),
    )
    assert np.array_equal(fl.HistoryState.load(tmp_path / "v1.npz").alpha_f, np.zeros(2))
    with pytest.raises(ValueError, match=r"alpha_f must be contact fractions in \[0, 1\]"):
        fl.HistoryState(p_hist=[1.0], alpha_f=[1.5])


def test_tangent_is_the_derivative_of_the_flattened_shear():
    P = law()
    for pr, phr, af in ((0.2, 0.0, 0.0), (0.3, 0.1, 0.4), (0.05, 0.0, 0.0), (0.1, 0.3, 0.5)):
        p, ph = pr * H, phr * H
        h = 1e-6 * p
        t, dtdp, _, _ = update(P, np.array([p - h, p, p + h]), ph, af, 0.01)
        fd = (t[2] - t[0]) / (2 * h)
        # on first loading (p >= p_hist) the update's d alpha / d p is in the tangent
        if p >= ph:
            assert dtdp[1] == pytest.approx(fd, rel=1e-5, abs=1e-12)
        else:  # below the history: the reload branch at its fixed level (docs)
            assert np.isfinite(dtdp[1])


@pytest.mark.parametrize("form", FORMS)
def test_the_hardening_limit_against_the_numpy_model(form):
    """Eq. F2c in the kernels against the NumPy model: moduli that limit the lattice everywhere
    (1e11 Pa), nowhere (1e6) and in between (where the limit starts inside the step: a kink the
    quadratures do not split, 5e-5 there; the tabulated form's own kinks are split by both)."""
    P = law(**FORMS[form])
    p, ph, af, de = grid()
    pf0 = flattening_pressure(af, P)
    for h, tol, n_held in ((1e11, 1e-9, 150), (1e6, 1e-9, 0), (4e9, 5e-5, 60)):
        _, _, a_k, _ = update(P, p, ph, af, de, hardening=h)
        pf = flattening_update(pf0, np.maximum(ph, p), p, de, P, hardening=h)
        a_ref = np.maximum(fl.alpha_first(pf, P), af)
        assert np.allclose(a_k, a_ref, rtol=tol, atol=1e-12), h
        # Eq. F2d: held at the sinking the modulus holds on so many nodes of the grid
        held = fl.alpha_first(np.maximum(ph, p), P) + 0.75 * p / (h * P.flattening.slope)
        assert np.sum(np.abs(a_k - held) < 1e-12) >= n_held, h
    _, _, a0, _ = update(P, p, ph, af, de)
    _, _, a1, _ = update(P, p, ph, af, de, hardening=0.0)
    assert np.array_equal(a0, a1)  # 0: perfectly plastic, bit for bit
    _, _, a2, _ = update(P, p, ph, af, de, hardening=1e11)
    assert np.all(a2 <= a1) and np.any(a2 < a1 - 1e-3)


def test_the_tangent_with_the_hardening_limit():
    """Where the limit acts the lattice's rate is ``6 p (1 - A) / h``, ``p`` times a function of
    ``t = p cosh v``: the consistent tangent's integrand changes (docs/flattening.md, F6); a
    central difference."""
    P = law()
    # the limit everywhere, and (the last two) from inside the step on: 6 p (1 - A) / h falls
    # below c_L = 1 + 0.05 (1 - A) at A = 0.3 and 0.2 (the step takes A from 0.21 and 0.105 to
    # 0.53 and 0.42 without the limit)
    for pr, h in (
        (0.2, 1e11),
        (0.05, 1e10),
        (0.3, 3e9),
        (0.2, 1.2 * H / (0.05 + 1 / 0.7)),
        (0.1, 0.6 * H / (0.05 + 1 / 0.8)),
    ):
        p = pr * H
        dp = 1e-6 * p
        t, dtdp, _, _ = update(P, np.array([p - dp, p, p + dp]), 0.0, 0.0, 0.01, hardening=h)
        assert dtdp[1] == pytest.approx((t[2] - t[0]) / (2 * dp), rel=1e-5, abs=1e-12), (pr, h)
    # held by the hardening (Eq. F2d): alpha1'(p) + 3 / (4 h tan(theta)) on first loading;
    # below a history the fraction's history term is fixed (the tangent there: the reload
    # branch at its fixed level, as above)
    for pr, ph_fac in ((0.2, 0.0), (0.05, 0.0), (0.2, 1.0 + 1e-5)):
        p, h = pr * H, 1e11
        dp = 1e-6 * p
        pp = np.array([p - dp, p, p + dp])
        t, dtdp, a, _ = update(P, pp, ph_fac * p, 0.0, 0.5, hardening=h)
        held = fl.alpha_first(np.maximum(ph_fac * p, pp), P) + 0.75 * pp / (h * 0.05)
        assert P.flattening.slope == 0.05 and np.allclose(a, held, rtol=1e-13, atol=0)
        if ph_fac == 0.0:
            assert dtdp[1] == pytest.approx((t[2] - t[0]) / (2 * dp), rel=1e-5, abs=1e-12), pr


def test_the_host_flow_stress_against_the_numpy_model():
    """The host's flow stress scales the layer's rate (F2's ``s0``), not the lattice's."""
    P = law()
    p = np.array([0.05, 0.2, 0.5]) * H
    _, _, a1, _ = update(P, p, 0.0, 0.0, 0.01)
    _, _, a2, _ = update(P, p, 0.0, 0.0, 0.01, sigma_y=2 * P.sigma_y)
    ref = fl.alpha_first(flattening_update(0.0, p, p, 0.01, P, sigma_y=2 * P.sigma_y), P)
    assert np.allclose(a2, ref, rtol=1e-11)
    assert np.all(a2 > a1)  # a harder bulk carries a larger share of the layer's rate


@pytest.mark.parametrize("slope", [1e-8, 0.05, 10.0])
def test_extremes_are_finite_and_at_most_one(slope):
    """The validated slopes' ends too (a polished sheet: 1e-8 flattens at any strain)."""
    P = law(slope=slope)
    p = np.array([1e-13 * H, 2e-12 * H, 1e-6 * H, 0.5 * H, 5 * H, 1e6 * H])
    for de in (1e-12, 0.3, 1e6, 1e300):
        for af in (0.0, 0.6, 1.0):
            with np.errstate(all="raise"):
                t, d, a, _ = update(P, p, 0.0, af, de)
            assert np.all(np.isfinite(t)) and np.all(np.isfinite(d))
            assert np.all((a >= af) & (a <= 1.0))
    # below 1e-12 H nothing flattens; a strain beyond any forming is full contact
    _, _, a, _ = update(P, p[:2], 0.0, 0.0, 1e300)
    assert a[0] == 0.0 and a[1] == 1.0


def test_serial_and_parallel_agree_bit_for_bit():
    P = law()
    p, ph, af, de = grid()
    n = p.size
    args = (p, np.ones(n), np.zeros(n), 1e20)
    res = []
    for par in (False, True):
        s = fl.HistoryState(p_hist=ph, alpha_f=af)
        r = fl.traction_update(fl.SBMFLaw(P), *args, s, parallel=par, d_eps=de)
        res.append((*r, s.alpha_f_trial.copy()))
    for a, b in zip(*res, strict=True):
        assert np.array_equal(a, b)


# ----------------------------------------------------------------------------- zones
def test_zones_carry_the_fraction():
    rough = law(slope=0.05)
    smooth = law(slope=0.2, C1=1.6, m=0.8)
    plain = fl.FrictionParams(**BASE)
    zl = fl.ZonedLaw(("a", "b", "c"), (fl.SBMFLaw(rough), fl.SBMFLaw(smooth), fl.SBMFLaw(plain)))
    p = np.array([0.05, 0.1, 0.3]) * H
    # each zone's node is its one-law update bit for bit
    for z, P in enumerate((rough, smooth)):
        one = update(P, p, 0.0, 0.2, 0.01)
        zoned = update(None, p, 0.0, 0.2, 0.01, zone=np.full(3, z), law_=zl)
        for a, b in zip(one, zoned, strict=True):
            assert np.array_equal(a, b)
    # flattened under a, the node comes under b: b reads the fraction through its own alpha1
    _, _, a_a, _ = update(rough, p, 0.0, 0.0, 0.05)
    t_b, _, a_b, _ = update(None, p, p, a_a, 0.0, zone=np.ones(3, int), law_=zl)
    assert np.array_equal(a_b, a_a)  # no strain: the fraction as it came
    expect = smooth.tau_max * np.maximum(fl.alpha_first(p, smooth), a_a)
    assert np.allclose(t_b, expect, rtol=1e-12)
    # the zone without a block runs its calibrated law and leaves the fraction as it came
    t_c, _, a_c, _ = update(None, p, p, a_a, 0.05, zone=np.full(3, 2, int), law_=zl)
    assert np.array_equal(a_c, a_a)
    assert np.array_equal(t_c, fl.shear_limit(p, p, plain))


# ----------------------------------------------------------------------------- bad input
def test_bad_input_is_named():
    P = law()
    L = fl.SBMFLaw(P)
    args = (L, np.ones(2) * 1e8, np.ones(2), np.zeros(2), 1e13)
    for bad, msg in (
        (dict(d_eps=[-1.0, 0.0]), "d_eps must be finite and >= 0"),
        (dict(d_eps=[np.nan, 0.0]), "d_eps must not contain NaN"),
        (dict(d_eps=np.zeros(3)), r"d_eps must be a scalar or have shape \(2,\)"),
        (dict(d_eps=0.1, sigma_y=1.0), r"sigma_y must be in \[1e3, 1e13\] Pa"),
        (dict(sigma_y=3e8), "sigma_y applies with d_eps only"),
        (dict(hardening=1e9), "hardening applies with d_eps only"),
        (dict(d_eps=0.1, hardening=-1.0), "hardening must be finite and >= 0"),
        (dict(d_eps=0.1, hardening=[np.inf, 0.0]), "hardening must be finite and >= 0"),
        (dict(d_eps=0.1, hardening=np.ones(3)), r"hardening must be a scalar or have shape \(2,\)"),
    ):
        with pytest.raises(ValueError, match=msg):
            fl.traction_update(*args, **bad)
    with pytest.raises(ValueError, match="d_eps applies to a law with a flattening block"):
        fl.traction_update(fl.Coulomb(0.1), *args[1:], d_eps=0.1)
    with pytest.raises(ValueError, match="d_eps applies to a law with a flattening block"):
        fl.traction_update(fl.SBMFLaw(fl.FrictionParams(**BASE)), *args[1:], d_eps=0.1)


def test_a_stored_flattened_fraction_is_read_without_a_strain_increment():
    """alpha_f is the node's state, as p_hist: a call without d_eps reads it (no growth) rather
    than dropping it; a never-flattened state runs the law itself."""
    from fe_demo.scenes.laws import EXAMPLE_FLATTENING_PATH

    P = fl.FrictionParams.from_json(EXAMPLE_FLATTENING_PATH)
    law_ = fl.SBMFLaw(P)
    p = [0.01 * P.H]

    def shear(**kw):
        st = fl.HistoryState(p_hist=[0.0], alpha_f=[0.9])
        return fl.traction_update(law_, p, [1e-3], [0.0], 1e12, st, **kw).traction[0]

    assert shear() == shear(d_eps=0.0) == pytest.approx(0.9 * P.tau_max, rel=1e-12)
    virgin = fl.traction_update(law_, p, [1e-3], [0.0], 1e12, fl.HistoryState(1)).traction[0]
    assert virgin == pytest.approx(float(fl.shear_limit(p[0], 0.0, P)), rel=1e-12)


@pytest.mark.parametrize("form", ["eq24", "tabulated"])
def test_the_switch_of_the_hardening_limit_against_the_numpy_model(form):
    """Where Eq. F2c's limit starts to act (``A_c = 1 - 1 / (c_max - tan(theta))``, the kink
    both sums are split at): the kernel's ``v`` against the NumPy model's (1e-12), ``inf``
    where the limit acts from the start, nowhere, or only beyond the cap."""
    from frictionlaw._kernels_flattening_quad import flat_switch
    from frictionlaw.flattening import _p_cap, _switch, flattening_data

    P = law() if form == "eq24" else law(**FORMS["tabulated-first"])
    fd = flattening_data(P)
    c1, cap, m = fd[KF.FLAT_HEAD :], float(fd[4]), P.flattening.slope
    p = np.array([0.01, 0.05, 0.1, 0.2, 0.4]) * H
    for a_c in (-0.5, 0.0, 0.1, 0.3, 0.6, 0.95):
        cmax = np.full(p.shape, m + 1.0 / (1.0 - a_c))
        want = _switch(p, cmax, P, _p_cap(P, sbmf_coeffs(P, 1.0)))
        got = np.array([flat_switch(c1, q, q, cap, m, c) for q, c in zip(p, cmax, strict=True)])
        assert np.array_equal(np.isinf(got), np.isinf(want)), a_c
        fin = np.isfinite(want)
        assert np.allclose(got[fin], want[fin], rtol=1e-12, atol=0), a_c
        a0 = fl.alpha_first(p, P)
        assert np.all(np.isinf(want[a0 >= a_c]))  # limited from the start
        assert np.all(np.isfinite(want[a0 < a_c]) | (a_c <= 0.0)), a_c
        at = fl.alpha_first(p[fin] * np.cosh(want[fin]), P)
        assert np.allclose(at, a_c, rtol=0, atol=1e-12)
    assert flat_switch(c1, p[1], p[1], cap, m, math.inf) == math.inf
