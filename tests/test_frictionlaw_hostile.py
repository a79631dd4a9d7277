"""Issue 12: the runtime under hostile input (read-only arrays, extremes, bad files and dtypes)."""

import math
import os
import subprocess
import sys

import numba
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import frictionlaw as fl
from frictionlaw import _reference as ref
from frictionlaw.params import C_RANGE, K_RANGE, N_RANGE, STRESS_RANGE

H = 800e6


def params(**kw):
    base = dict(m=0.6, sigma_y=H / 2.8, H=H, C1=1.2, n1=2.0, C2=3.0, n2=2.0)
    base.update(kw)
    return fl.FrictionParams(**base)


def readonly(a):
    a = np.array(a, dtype=float)
    a.flags.writeable = False
    return a


# -- item 1: read-only input everywhere --------------------------------------------------------


def test_read_only_arrays_are_accepted():
    P = params()
    state = fl.HistoryState(p_hist=np.array([0.0, 0.5 * H, 2 * H]))
    p = np.array([0.3, 0.4, 1.0]) * H
    want = fl.shear_limit(p, state.p_hist.copy(), P)
    assert not state.p_hist.flags.writeable
    np.testing.assert_array_equal(fl.shear_limit(p, state.p_hist, P), want)
    np.testing.assert_array_equal(fl.shear_limit(readonly(p), state.p_hist, P), want)
    # one node against a scalar history: a broadcast view, read-only, no FutureWarning
    assert fl.shear_limit(p[:1], 0.0, P)[0] == fl.shear_limit(p[0], 0.0, P)
    np.testing.assert_array_equal(fl.SBMFLaw(P).shear_limit(p, state.p_hist)[0], want)
    np.testing.assert_array_equal(
        fl.shear_limit_dp(readonly(p), state.p_hist, P),
        fl.shear_limit_dp(p, state.p_hist.copy(), P),
    )
    law = fl.SBMFLaw(P)
    du = np.array([[1e-6, 0.0], [0.0, -1e-7], [2e-7, 2e-7]])
    t_old = np.full((3, 2), 1e6)
    kt = np.full(3, 1e13)
    want = fl.traction_update(law, p, du, t_old, kt, state)
    got = fl.traction_update(law, readonly(p), readonly(du), readonly(t_old), readonly(kt), state)
    for a, b in zip(want, got, strict=True):
        np.testing.assert_array_equal(a, b)


def test_read_only_arrays_in_a_host_njit_loop():
    from frictionlaw import kernels

    law = fl.SBMFLaw(params())
    code, coeffs = law.code, readonly(law.coeffs)

    @numba.njit
    def host(p, p_hist, du, t_old, out):
        t_new, dtd, dtp = np.empty((p.size, 2)), np.empty((p.size, 2, 2)), np.empty((p.size, 2))
        for i in range(p.size):
            out[i] = kernels.traction_row(
                code, coeffs, p[i], p_hist[i], du, t_old, 1e13, t_new, dtd, dtp, i
            )

    p = readonly([0.0, 0.5 * H, H])
    du = np.zeros((3, 2))
    du[1, 0] = 1.0
    out = np.empty(3)
    host(p, readonly([0, 0, 0]), readonly(du), readonly(np.zeros((3, 2))), out)
    assert list(out) == [fl.OPEN, fl.SLIP, fl.STICK]


# -- item 10: frictionlaw.kernels as the README spells it ---------------------------------------


def test_kernels_reachable_as_attribute_and_import_stays_light():
    code = (
        "import sys, frictionlaw\n"
        "assert 'numba' not in sys.modules\n"
        "f = frictionlaw.kernels.shear_scalar\n"
        "print(f(0, frictionlaw.Coulomb(0.5).coeffs, 2.0, 0.0)[0])\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert float(out.stdout) == 1.0


# -- items 2-4: the law over its whole validated range ------------------------------------------


def test_out_of_range_parameters_are_refused_with_the_reason():
    for field, value, fragment in [
        ("n2", 3e-4, "n2 must be in [0.001, 1e+06]"),
        ("C1", 1e301, "C1 must be in [1e-06, 1e+06]"),
        ("H", 1e-300, "H must be in [1000, 1e+13]"),
    ]:
        with pytest.raises(ValueError) as exc:
            params(**{field: value})
        assert fragment in str(exc.value) and "finite for every pressure" in str(exc.value)


def test_range_corners_stay_finite_and_match_the_oracle():
    # the cases, moved to the corners of the validated range
    P = params(n2=1e-3, continuous_reload=True)
    tau = fl.shear_limit(2e8, 4e8, P)
    want = ref.sbmf_shear(2e8, 4e8, P.tau_max, P.C1, P.n1, P.C2, P.n2, H, True)
    assert np.isfinite(fl.shear_limit_dp(2e8, 4e8, P))
    assert tau == pytest.approx(float(want), rel=1e-12)
    P = params(C1=1e6, H=1e3, sigma_y=1e13)
    assert fl.shear_limit(1e-300, 0.0, P) == pytest.approx(P.mu_eff * 1e-300, rel=1e-12)
    assert fl.shear_limit_dp(1e-300, 0.0, P) == pytest.approx(P.mu_eff, rel=1e-12)
    law = fl.SBMFLaw(P)
    r = fl.traction_update(law, np.array([1e-300]), np.zeros((1, 2)), np.zeros((1, 2)), 1.0)
    assert np.isfinite(r.dt_dp).all() and np.isfinite(r.dt_dslip).all()


def test_continuous_reload_contact_ratio_stays_below_one():
    P = params(C2=0.05, continuous_reload=True)
    p = np.array([0.05, 0.1, 0.5, 1.0, 10.0, 100.0]) * H
    a = fl.alpha_reload(p, 0.1 * H, P)
    assert np.all((a >= 0) & (a <= 1.0))
    # at and below p_hist it is Eq. 25 normalised to alpha1(p_hist), unchanged by the cap
    assert a[1] == pytest.approx(fl.alpha_first(0.1 * H, P), rel=1e-12)
    want = ref.alpha_reload(p, 0.1 * H, P.C1, P.n1, P.C2, P.n2, H, True)
    np.testing.assert_allclose(a, want, rtol=1e-12)


def test_subnormal_pressures_with_small_n_are_monotone_and_match_the_oracle():
    P = params(n1=1e-3)
    p = np.array([5e-324, 1e-320, 1e-310, 1e-300, 1e-200, 1e-100])
    tau = fl.shear_limit(p, 0.0, P)
    assert np.all(np.diff(tau) >= 0)
    want = ref.sbmf_shear(p, 0.0, P.tau_max, P.C1, P.n1, P.C2, P.n2, H)
    np.testing.assert_allclose(tau, want, rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(
        fl.alpha_first(p, P), ref.alpha_first(p, P.C1, P.n1, H), rtol=1e-12, atol=1e-300
    )


# -- the whole validated range, fuzzed ------------------------------------------------------------


def _log_uniform(lo, hi):
    """Log-uniform floats in [lo, hi] with the bounds themselves drawn often."""
    inner = st.floats(math.log10(lo), math.log10(hi)).map(lambda e: min(max(10.0**e, lo), hi))
    return st.one_of(st.sampled_from([lo, hi]), inner)


@st.composite
def _params(draw):
    """A FrictionParams anywhere in the validated range; an explicit ``k`` lies in the
    ``k / sigma_y`` band [1/2, 2/3] (which keeps it inside K_RANGE for every sigma_y)."""
    sigma_y = draw(_log_uniform(*STRESS_RANGE))
    ratio = draw(st.one_of(st.none(), st.sampled_from([0.5, 2.0 / 3.0]), st.floats(0.5, 2 / 3)))
    k = None if ratio is None else min(max(ratio * sigma_y, K_RANGE[0]), K_RANGE[1])
    return fl.FrictionParams(
        m=draw(st.one_of(st.sampled_from([0.0, 1.0]), st.floats(0.0, 1.0))),
        sigma_y=sigma_y,
        H=draw(_log_uniform(*STRESS_RANGE)),
        C1=draw(_log_uniform(*C_RANGE)),
        n1=draw(_log_uniform(*N_RANGE)),
        C2=draw(_log_uniform(*C_RANGE)),
        n2=draw(_log_uniform(*N_RANGE)),
        k=k,
        continuous_reload=draw(st.booleans()),
        geo_ratio=draw(st.one_of(st.sampled_from([0.0, 10.0]), st.floats(0.0, 10.0))),
    )


PARAMS = _params()
# pressures from 0 through the subnormals to the largest double (and beyond, +inf)
SPECIAL_P = [0.0, 5e-324, 1e-320, 2.2250738585072014e-308, 1.7976931348623157e308, math.inf]
PRESSURE = st.one_of(
    st.sampled_from(SPECIAL_P),
    st.floats(-323.3, 308.25).map(lambda e: 10.0**e),
    st.floats(2.0, 14.0).map(lambda e: 10.0**e),  # where p C / H ~ 1 for most parameters
)
N_PTS = 16
FUZZ_EXAMPLES = int(os.environ.get("SBMF_FUZZ_EXAMPLES", "400"))
FUZZ_CASES = {"law": 0}


def _close(a, b):
    return np.allclose(a, b, rtol=1e-11, atol=1e-290)


@settings(max_examples=FUZZ_EXAMPLES, deadline=None)
@given(
    P=PARAMS,
    p=st.lists(PRESSURE, min_size=N_PTS, max_size=N_PTS),
    ph=st.lists(PRESSURE, min_size=N_PTS, max_size=N_PTS),
)
def test_fuzz_law_finite_bounded_and_equal_to_the_oracle(P, p, ph):
    p, ph = np.array(p), np.array(ph)
    args = (P.C1, P.n1, P.C2, P.n2, P.H)
    tau = fl.shear_limit(p, ph, P)
    dtau = fl.shear_limit_dp(p, ph, P)
    a1 = fl.alpha_first(p, P)
    a2 = fl.alpha_reload(p, ph, P)
    for v in (tau, dtau, a1, a2):
        assert np.isfinite(v).all()
    assert np.all((tau >= 0) & (tau <= P.tau_max)) and np.all(dtau >= 0)
    assert np.all((a1 >= 0) & (a1 <= 1)) and np.all((a2 >= 0) & (a2 <= 1))
    assert _close(a1, ref.alpha_first(p, P.C1, P.n1, P.H))
    assert _close(a2, ref.alpha_reload(p, ph, *args, P.continuous_reload))
    want = ref.sbmf_shear(p, ph, P.tau_max, P.C1, P.n1, P.C2, P.n2, P.H, P.continuous_reload)
    assert _close(tau, want)
    FUZZ_CASES["law"] += p.size


# -- item 5: traction_update at the extremes -----------------------------------------------------


def _one(law, p, du, t_old, kt):
    return fl.traction_update(law, np.array([p]), np.array([du]), np.array([t_old]), kt)


def test_huge_trial_traction_slips_onto_the_limit():
    law = fl.SBMFLaw(params())
    tau = fl.shear_limit(1e8, 0.0, law.params)
    r = _one(law, 1e8, [0.0, 0.0], [1e200, 0.0], 1e10)  # |t|^2 overflowed
    assert r.status[0] == fl.SLIP
    np.testing.assert_allclose(r.traction[0], [tau, 0.0], rtol=1e-15)
    r = _one(law, 1e8, [1e10, -1e10], [0.0, 0.0], 1e300)  # k_t du overflows
    assert r.status[0] == fl.SLIP
    np.testing.assert_allclose(r.traction[0], [tau / 2**0.5, -tau / 2**0.5], rtol=1e-15)
    for a in r:
        assert np.isfinite(a).all()
    # consistent tangent k_t tau / |t_tr| (I - n n): tiny but finite
    assert 0 <= r.dt_dslip[0, 0, 0] < 1e-2


def test_zero_shear_limit_gives_zero_traction_and_zero_tangent():
    law = fl.SBMFLaw(params(m=0.0))
    r = _one(law, 1e8, [0.0, 0.0], [0.0, 0.0], 1e10)
    assert r.status[0] == fl.SLIP
    assert np.all(r.traction == 0) and np.all(r.dt_dslip == 0)
    r = _one(law, 1e8, [0.0, 0.0], [1e-170, 0.0], 1e10)  # |t|^2 underflows
    assert r.status[0] == fl.SLIP and np.all(r.traction == 0) and np.all(r.dt_dslip == 0)
    r = fl.traction_update(fl.Tresca(0.0, 1e8), np.ones(2), np.zeros(2), np.zeros(2), 1e10)
    assert list(r.status) == [fl.SLIP, fl.SLIP] and np.all(r.dt_dslip == 0)


def test_tiny_trial_traction_keeps_its_direction():
    law = fl.Coulomb(0.1)
    r = _one(law, 1e-300, [0.0, 0.0], [3e-170, 4e-170], 1e10)  # tau = 1e-301 < |t| = 5e-170
    assert r.status[0] == fl.SLIP
    np.testing.assert_allclose(r.traction[0], [0.6e-301, 0.8e-301], rtol=1e-14)


def test_k_t_of_the_wrong_shape_is_named():
    z = np.zeros((2, 2))
    with pytest.raises(ValueError, match=r"k_t must be a scalar or have shape \(2,\)"):
        fl.traction_update(fl.Coulomb(0.1), np.ones(2), z, z, np.ones(3))
    with pytest.raises(ValueError, match="p must be finite"):  # it would enter p_hist
        fl.traction_update(fl.Coulomb(0.1), np.array([1.0, np.inf]), z, z, 1.0)


COMPONENT = st.one_of(
    st.sampled_from([0.0, 5e-324, -1e-320, 1e-170, -1e200, 1e300, -1.7e308]),
    st.tuples(st.sampled_from([-1.0, 1.0]), st.floats(-323.3, 308.2)).map(
        lambda t: t[0] * 10 ** t[1]
    ),
)


@settings(max_examples=FUZZ_EXAMPLES // 2, deadline=None)
@given(
    P=PARAMS,
    p=st.lists(PRESSURE, min_size=N_PTS, max_size=N_PTS),
    ph=st.lists(PRESSURE, min_size=N_PTS, max_size=N_PTS),
    du=st.lists(COMPONENT, min_size=2 * N_PTS, max_size=2 * N_PTS),
    t_old=st.lists(COMPONENT, min_size=2 * N_PTS, max_size=2 * N_PTS),
    kt=st.lists(_log_uniform(1e-300, 1e300), min_size=N_PTS, max_size=N_PTS),
    d=st.sampled_from([1, 2]),
)
def test_fuzz_traction_update_finite_and_equal_to_the_oracle(P, p, ph, du, t_old, kt, d):
    big = np.finfo(float).max  # a host's pressures and history are finite
    p, ph, kt = np.minimum(p, big), np.minimum(ph, big), np.array(kt)
    du = np.array(du).reshape(N_PTS, 2)[:, :d]
    t_old = np.array(t_old).reshape(N_PTS, 2)[:, :d]
    law = fl.SBMFLaw(P)
    r = fl.traction_update(law, p, du, t_old, kt, fl.HistoryState(p_hist=ph))
    for a in r:
        assert np.isfinite(a).all()
    tau = fl.shear_limit(p, ph, P)
    tau_ref = np.where(p > 0, tau, np.nan)
    t_ref, s_ref = ref.traction_update(tau_ref, du, t_old, kt)
    mag = np.hypot.reduce(np.abs(r.traction), axis=1)
    # at subnormal tau each component t = tau n_a rounds to a multiple of 4.9e-324, so |t| may
    # exceed tau by a few such units (seen: 7.856e-321 against 7.85e-321)
    assert np.all(mag <= tau * (1 + 1e-12) + 4 * np.finfo(float).smallest_subnormal)
    assert np.allclose(r.traction, t_ref, rtol=1e-12, atol=1e-290)
    with np.errstate(over="ignore"):
        norm = np.hypot.reduce(np.abs(t_old + kt[:, None] * du), axis=1)
    tie = np.isclose(norm, tau, rtol=1e-12)
    assert np.array_equal(r.status[~tie], s_ref[~tie])
    FUZZ_CASES["traction"] = FUZZ_CASES.get("traction", 0) + p.size


# -- item 6: the force adapter -------------------------------------------------------------------


def test_force_adapter_scalar_area_out_and_overflow():
    law = fl.SBMFLaw(params())
    rng = np.random.default_rng(3)
    n, area = 5, 2e-6
    f_n = rng.uniform(0, 1, n) * H * area
    du = rng.normal(size=(n, 2)) * 1e-6
    f_old = rng.normal(size=(n, 2)) * 1e7 * area
    want = fl.traction_update_force(law, f_n, np.full(n, area), du, f_old, 1e13 * area)
    got = fl.traction_update_force(law, f_n, area, du, f_old, 1e13 * area)  # scalar area
    for a, b in zip(want, got, strict=True):
        np.testing.assert_array_equal(a, b)
    # out= is filled with the forces and returned, as in traction_update
    buf = fl.TractionResult(*(np.full_like(a, 7) for a in want))
    again = fl.traction_update_force(law, f_n, area, du, f_old, 1e13 * area, out=buf)
    assert again is buf
    for a, b in zip(want, buf, strict=True):
        np.testing.assert_array_equal(a, b)
    # the stress-based update times the area, field by field (N, N/m, 1)
    s = fl.traction_update(law, f_n / area, du, f_old / area, 1e13)
    np.testing.assert_allclose(buf.traction, s.traction * area, rtol=1e-14)
    np.testing.assert_allclose(buf.dt_dslip, s.dt_dslip * area, rtol=1e-14)
    np.testing.assert_allclose(buf.dt_dp, s.dt_dp, rtol=1e-14)
    # an overflowing pressure is the largest double (the law is at its cap there), no warning
    r = fl.traction_update_force(law, [1e300], 1e-10, [[1.0, 0.0]], [[0.0, 0.0]], 1.0)
    assert r.status[0] == fl.SLIP
    np.testing.assert_allclose(r.traction[0], [law.params.tau_max * 1e-10, 0.0], rtol=1e-15)
    with pytest.raises(ValueError, match=r"area must be a scalar or have shape \(5,\)"):
        fl.traction_update_force(law, f_n, np.ones(3), du, f_old, 1.0)


# -- item 7: restart and parameter files ---------------------------------------------------------


def test_unreadable_restart_files_name_the_path(tmp_path):
    good = fl.HistoryState(p_hist=np.linspace(0, 1e9, 50)).save(tmp_path / "good.npz")
    blob = good.read_bytes()
    cases = {
        "empty.npz": b"",
        "truncated.npz": blob[: len(blob) // 2],
        "flipped.npz": blob[:40] + bytes([blob[40] ^ 0xFF]) + blob[41:],
        "text.npz": b"hello, this is not a zip archive\n",
    }
    for i in range(0, len(blob), 7):  # every 7th byte flipped in turn
        cases[f"flip{i}.npz"] = blob[:i] + bytes([blob[i] ^ 0x55]) + blob[i + 1 :]
    n_err = 0
    for name, data in cases.items():
        f = tmp_path / name
        f.write_bytes(data)
        try:
            st_ = fl.HistoryState.load(f)
        except ValueError as exc:
            assert str(f) in str(exc)
            n_err += 1
        else:  # a flip in a byte nothing reads (e.g. a timestamp) may leave a valid file
            np.testing.assert_array_equal(st_.p_hist, np.linspace(0, 1e9, 50))
    assert n_err >= 4


@pytest.mark.parametrize(
    "field, value, fragment",
    [
        ("version", np.array("1"), "version must be an integer"),
        ("version", np.array(1.0), "version must be an integer"),
        ("version", np.array(True), "version must be an integer"),
        ("format", np.array(5), "format"),
        ("p_hist", np.array([1.0, np.inf]), "p_hist must be finite"),
        ("p_hist", np.array(["a"]), "p_hist must be real numbers"),
    ],
)
def test_restart_file_fields_are_checked(tmp_path, field, value, fragment):
    doc = dict(format=np.array("sbmf-friction-restart"), version=np.array(1), p_hist=np.zeros(2))
    doc[field] = value
    np.savez(tmp_path / "r.npz", **doc)
    with pytest.raises(ValueError, match=fragment) as exc:
        fl.HistoryState.load(tmp_path / "r.npz")
    assert str(tmp_path / "r.npz") in str(exc.value)


def test_history_state_counts_are_integers_and_agree():
    for bad in (2.7, "3", True, np.float64(2.0)):
        with pytest.raises(ValueError, match="n_nodes must be an integer"):
            fl.HistoryState(bad)
    assert fl.HistoryState(np.int64(3)).n_nodes == 3
    with pytest.raises(ValueError, match="n_nodes = 3 disagrees with p_hist of 2 nodes"):
        fl.HistoryState(3, p_hist=[1.0, 2.0])
    assert fl.HistoryState(2, p_hist=[1.0, 2.0]).n_nodes == 2
    with pytest.raises(ValueError, match="p_hist must be finite"):
        fl.HistoryState(p_hist=[np.inf])
    s = fl.HistoryState(2)
    with pytest.raises(ValueError, match="n_nodes must be an integer"):
        s.resize(1.5)
    with pytest.raises(ValueError, match="n_new must be an integer"):
        s.grow(0.5)


@pytest.mark.parametrize(
    "mutate, fragment",
    [
        (lambda d: d.update(version=1.0), "unsupported version 1.0"),
        (lambda d: d.update(version=True), "unsupported version True"),
        (lambda d: d.update(units="Pa"), "'units' must be a JSON object"),
        (lambda d: d.update(options=[True]), "'options' must be a JSON object"),
        (lambda d: d.update(provenance=[1]), "'provenance' must be a JSON object"),
        (lambda d: d["options"].update(bogus=1), "unknown options"),
    ],
)
def test_malformed_parameter_documents(tmp_path, mutate, fragment):
    import json

    d = json.loads(json.dumps(params().to_dict()))
    mutate(d)
    f = tmp_path / "p.json"
    f.write_text(json.dumps(d))
    with pytest.raises(ValueError, match=fragment) as exc:
        fl.FrictionParams.from_json(f)
    assert str(f) in str(exc.value)


# -- item 8: non-real input ----------------------------------------------------------------------


@pytest.mark.parametrize(
    "value",
    [
        np.array([1e8 + 1j]),
        np.array(["1e8"]),
        np.array([b"1e8"]),
        np.array(["2020-01-01"], dtype="datetime64[D]"),
        np.array([1, 2], dtype="timedelta64[s]"),
        np.array([1e8, None]),
        np.array([True]),
    ],
    ids=["complex", "str", "bytes", "datetime", "timedelta", "object", "bool"],
)
def test_non_real_inputs_are_refused(value):
    P = params()
    with pytest.raises(ValueError, match="p must be real numbers"):
        fl.shear_limit(value, 0.0, P)
    with pytest.raises(ValueError, match="p_hist must be real numbers"):
        fl.shear_limit(1e8, value, P)
    with pytest.raises(ValueError, match="p must be real numbers"):
        fl.traction_update(fl.SBMFLaw(P), value, np.zeros(value.size), np.zeros(value.size), 1.0)
    with pytest.raises(ValueError, match="p_hist must be real numbers"):
        fl.HistoryState(p_hist=value)
    assert fl.shear_limit(np.array([100_000_000]), 0, P) == fl.shear_limit(1e8, 0.0, P)


# -- item 9: files keep the user's umask ---------------------------------------------------------


def test_written_files_follow_the_umask(tmp_path):
    import os
    import stat

    old = os.umask(0o027)
    try:
        a = params().to_json(tmp_path / "params.json")
        b = fl.HistoryState(2).save(tmp_path / "restart.npz")
        c = tmp_path / "plain.txt"
        c.write_text("x")
    finally:
        os.umask(old)
    modes = {stat.S_IMODE(x.stat().st_mode) for x in (a, b, c)}
    assert modes == {0o640}
