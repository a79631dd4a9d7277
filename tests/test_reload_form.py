"""The tabulated reload form (frictionlaw.reload_form): kernels against the NumPy oracle with
SciPy's interpolant, the properties issue 31 asks of the branch, and the parameter file."""

import json
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import PchipInterpolator

from frictionlaw import (
    FrictionParams,
    HistoryState,
    SBMFLaw,
    alpha_first,
    alpha_reload,
    reload_jump,
    shear_limit,
    shear_limit_dp,
    traction_update,
)
from frictionlaw import _reference as ref
from frictionlaw._kernels import smooth_min_log, smooth_min_log_slope
from frictionlaw.reload_form import (
    S2_RANGE,
    ReloadTable,
    hermite,
    history_coordinate,
    pchip_slopes,
)

H = 800e6
LEVELS = (100e6, 200e6, 300e6, 400e6, 500e6, 600e6, 700e6, 760e6)
C2 = (1.65, 1.64, 1.67, 1.69, 1.62, 1.52, 1.54, 1.61)
N2 = (7.3, 4.8, 2.75, 1.55, 0.87, 0.64, 0.61, 0.88)
# a second table with the strongly varying shape of the default scene (C2 rises 20-fold)
C2B = (4.5, 4.8, 5.1, 5.6, 7.0, 10.0, 20.8, 83.6)
N2B = (0.95, 0.84, 0.75, 0.71, 0.61, 0.51, 0.40, 0.29)


def params(cont=False, table=None, s2=0.67, **kw):
    tab = table or ReloadTable(p_hist=LEVELS, C2=C2B, n2=N2B, s2=s2)
    return FrictionParams(
        m=0.5,
        sigma_y=H / 2.8,
        H=H,
        C1=1.02,
        n1=16.5,
        C2=17.5,
        n2=0.41,
        continuous_reload=cont,
        reload_form="tabulated",
        reload_table=tab,
        **kw,
    )


def scipy_table(table, p_hist):
    """SciPy's interpolant between the levels, the first level's values below them; above the
    last, ln C2 linear in z at the last two levels' secant slope (at least 0), at most ln 1e6."""
    z = history_coordinate(table.p_hist, H)
    x = np.asarray(p_hist, float) / H
    with np.errstate(divide="ignore"):
        zq = np.where(x < 1, -np.log1p(-np.minimum(x, 1.0)), np.inf)
    lc = np.log(table.C2)
    slope = max(0.0, (lc[-1] - lc[-2]) / (z[-1] - z[-2]))
    zc = np.clip(zq, z[0], z[-1])
    lnc = PchipInterpolator(z, lc)(zc)
    if slope > 0:
        with np.errstate(invalid="ignore"):
            up = np.minimum(lc[-1] + slope * (zq - z[-1]), np.log(1e6))
        lnc = np.where(zq > z[-1], up, lnc)
    n2 = np.exp(PchipInterpolator(z, np.log(table.n2))(zc))
    return np.exp(lnc), n2


# -- the interpolant ----------------------------------------------------------------------------


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.floats(0.01, 10.0), min_size=2, max_size=9),
    # values of the size of ln C2 and ln n2 (SciPy itself overflows on subnormal secants)
    st.lists(
        st.floats(-5.0, 5.0).filter(lambda v: v == 0.0 or abs(v) > 1e-9), min_size=9, max_size=9
    ),
)
def test_pchip_slopes_are_scipys(steps, values):
    x = np.cumsum(steps)
    y = np.asarray(values[: x.size])
    d = pchip_slopes(x, y)
    want = PchipInterpolator(x, y).derivative()(x)
    np.testing.assert_allclose(d, want, rtol=1e-12, atol=1e-12)
    xq = np.linspace(x[0] - 1, x[-1] + 1, 301)
    got = hermite(xq, x, y, d)
    np.testing.assert_allclose(
        got, PchipInterpolator(x, y)(np.clip(xq, x[0], x[-1])), rtol=1e-12, atol=1e-12
    )


def test_interpolant_does_not_overshoot_the_levels():
    tab = ReloadTable(p_hist=LEVELS, C2=C2, n2=N2, s2=0.67)
    ph = np.linspace(1e6, 799e6, 4001)
    c2, n2 = tab.at(ph, H)
    for vals, got in ((tab.C2, c2), (tab.n2, n2)):
        for a, b in zip(LEVELS, LEVELS[1:], strict=False):
            i, j = LEVELS.index(a), LEVELS.index(b)
            sel = (ph >= a) & (ph <= b)
            lo, hi = min(vals[i], vals[j]), max(vals[i], vals[j])
            assert np.all(got[sel] >= lo * (1 - 1e-12)) and np.all(got[sel] <= hi * (1 + 1e-12))
    # below the first level: constant; above the last: n2 constant, ln C2 linear in
    # z = -ln(1 - p_hist/H) at the last two levels' secant slope, up to C2 = 1e6 (p_hist -> H)
    c2e, n2e = tab.at(np.array([1.0, 50e6, 780e6, 800e6, 1e12]), H)
    z = -np.log1p(-np.array([700e6, 760e6, 780e6]) / H)
    s = np.log(C2[-1] / C2[-2]) / (z[1] - z[0])
    assert s > 0
    want = [C2[0], C2[0], C2[-1] * np.exp(s * (z[2] - z[1])), 1e6, 1e6]
    np.testing.assert_allclose(c2e, want, rtol=1e-13)
    np.testing.assert_allclose(n2e, [N2[0], N2[0], N2[-1], N2[-1], N2[-1]], rtol=1e-15)
    # a falling last secant (noise) keeps the last level's values
    fall = ReloadTable(p_hist=LEVELS, C2=C2[:-1] + (1.50,), n2=N2, s2=0.67)
    np.testing.assert_allclose(fall.at(np.array([780e6, 1e12]), H)[0], [1.50, 1.50], rtol=1e-15)


# -- kernels against the oracle --------------------------------------------------------------


@pytest.mark.parametrize("cont", [False, True])
@pytest.mark.parametrize("table", ["a", "b"])
def test_kernel_agrees_with_oracle_and_scipy(cont, table):
    tab = ReloadTable(
        p_hist=LEVELS, C2=C2 if table == "a" else C2B, n2=N2 if table == "a" else N2B, s2=0.67
    )
    P = params(cont, tab)
    rng = np.random.default_rng(3)
    ph = np.concatenate([rng.uniform(0, 1.3 * H, 400), np.array(LEVELS), [1e3, 50e6, 900e6]])
    p = ph * rng.uniform(0.0, 1.0, ph.size)
    c2, n2 = scipy_table(tab, ph)
    want = ref.alpha_reload_tabulated(p, ph, P.C1, P.n1, H, c2, n2, 0.67, cont)
    got = alpha_reload(p, ph, P)
    np.testing.assert_allclose(got, want, rtol=2e-12, atol=1e-300)
    tau = shear_limit(p, ph, P)
    np.testing.assert_allclose(tau, P.tau_max * want, rtol=2e-12, atol=1e-300)
    # at and above the history: Eq. 24
    np.testing.assert_allclose(
        shear_limit(ph * 1.1, ph, P), P.tau_max * alpha_first(ph * 1.1, P), rtol=1e-15
    )


@pytest.mark.parametrize("n", [0.1, 0.29, 1.0, 2.75, 16.5, 1000.0])
def test_smooth_min_log_slope_against_the_oracle(n):
    """``ln g`` and ``x g'/g`` of the smooth minimum, the tabulated branch's (``SBMF_SMINS``)."""
    lnx = np.linspace(-745.0, 745.0, 4001)  # every branch: series, tanh, saturated
    got = np.array([smooth_min_log_slope(v, n) for v in lnx])
    full = np.array([smooth_min_log(v, n) for v in lnx])
    # the statements of smooth_min_log: its ln g, and dg/dx = (g/x) (x g'/g), bit for bit
    assert np.array_equal(got[:, 0], full[:, 3])
    assert np.array_equal(full[:, 2], full[:, 1] * got[:, 1])
    eps = np.finfo(float).eps
    lng = ref.ln_smooth_min(lnx, n)
    np.testing.assert_allclose(got[:, 0], lng, rtol=1e-15, atol=4.0 * eps / n)  # ln g = ln t / n
    # x g'/g = 2y/sinh(2y), y = x**n, in NumPy (e = exp(-2y) above y = 1). The kernel's is within
    # 1e-12 relative or a few y eps absolute: 1 + expm1(-2y) cancels for large y (as dg/dx does)
    with np.errstate(all="ignore"):  # the branches np.where does not take
        y = np.exp(np.minimum(n * lnx, 700.0))
        e = np.exp(-2.0 * y)
        want = np.where(
            y < 1e-6,
            1.0 - 2.0 * y**2 / 3.0,
            np.where(y < 1.0, 2.0 * y / np.sinh(2.0 * y), 4.0 * y * e / ((1.0 - e) * (1.0 + e))),
        )
    assert np.all(np.abs(got[:, 1] - want) <= 1e-12 * want + 4.0 * np.maximum(y, 1.0) * eps)


def test_one_level_with_s2_1_is_the_papers_eq25():
    for cont in (False, True):
        tab = ReloadTable(p_hist=(400e6,), C2=(3.0,), n2=(2.0,), s2=1.0)
        P = params(cont, tab).replace(C2=3.0, n2=2.0)
        paper = P.replace(reload_form="paper")
        ph = np.geomspace(1e3, 2 * H, 60)[:, None]
        p = ph * np.geomspace(1e-6, 1.5, 40)[None, :]
        np.testing.assert_allclose(
            shear_limit(p, ph, P), shear_limit(p, ph, paper), rtol=1e-13, atol=1e-300
        )
        np.testing.assert_allclose(
            shear_limit_dp(p, ph, P), shear_limit_dp(p, ph, paper), rtol=1e-12, atol=1e-300
        )


# -- the properties of the branch ---------------------------------------------------------------


@pytest.mark.parametrize("cont", [False, True])
@pytest.mark.parametrize("ph", [1e3, 5e6, 100e6, 150e6, 555e6, 730e6, 760e6, 790e6, 1.5 * H])
def test_continuous_and_monotone_in_p_below_p_hist(cont, ph):
    P = params(cont)
    p = np.linspace(0.0, ph, 20001)[:-1]
    tau = shear_limit(p, ph, P)
    assert np.all(np.diff(tau) >= 0.0)
    # continuity: no step on the fine grid away from p = 0 (where tau ~ p ** s2 rises steeply
    # from 0: its first steps shrink like the grid spacing ** s2)
    steps = np.diff(tau)
    assert steps[200:].max() < 0.005 * P.tau_max
    fine = shear_limit(np.array([1e-6, 1e-7, 1e-8]) * ph, ph, P)
    if ph < H:
        assert shear_limit(1e-9 * ph, ph, P) < 1e-3 * P.tau_max
        assert fine[0] > fine[1] > fine[2] > 0
    else:  # a history at the hardness: flattened to full contact, it recontacts at once
        assert fine[0] > fine[1] > fine[2] > 0
        full = P.tau_max * alpha_first(ph, P)
        assert shear_limit(1e-3 * ph, ph, P) > (1 - 1e-9) * full


@pytest.mark.parametrize("cont", [False, True])
def test_meets_eq24_at_p_hist_up_to_the_reported_jump(cont):
    P = params(cont)
    ph = np.concatenate([np.geomspace(1e3, 0.999 * H, 200), np.array(LEVELS), [H, 2 * H]])
    below = shear_limit(ph * (1 - 1e-12), ph, P)
    at = shear_limit(ph, ph, P)
    jump = reload_jump(P, ph)
    np.testing.assert_allclose(at - below, jump, rtol=1e-6, atol=1e-9 * P.tau_max)
    if cont:
        assert np.max(np.abs(jump)) <= 1e-9 * P.tau_max
    else:
        assert np.all(jump >= -1e-9 * P.tau_max)


def test_continuous_in_p_hist_across_the_levels():
    P = params(False)
    p = 30e6
    ph = np.linspace(60e6, 799e6, 100001)
    tau = shear_limit(p, ph, P)
    assert np.max(np.abs(np.diff(tau))) < 1e-4 * P.tau_max


@pytest.mark.parametrize("cont", [False, True])
def test_tangent_matches_central_differences(cont):
    P = params(cont)
    rng = np.random.default_rng(7)
    ph = rng.uniform(20e6, 1.2 * H, 300)
    p = ph * rng.uniform(0.02, 0.98, ph.size)
    h = 1e-6 * p
    fd = (shear_limit(p + h, ph, P) - shear_limit(p - h, ph, P)) / (2 * h)
    # the difference's rounding: a few ulps of tau over 2 h (where the curve is near saturation
    # above the last level, its slope is small against tau / p)
    rounding = 8 * np.finfo(float).eps * shear_limit(p, ph, P) / (2 * h)
    assert np.all(np.abs(shear_limit_dp(p, ph, P) - fd) <= 2e-6 * np.abs(fd) + rounding)


@pytest.mark.parametrize("cont", [False, True])
@pytest.mark.parametrize("s2", [0.67, S2_RANGE[0]])
def test_no_nan_inf_or_warning_at_the_edges(cont, s2):
    # s2 at its lower bound: dtau/dp ~ p**(s2 - 1) exceeds the largest double at subnormal p
    P = params(cont, s2=s2)
    tiny = np.nextafter(0, 1)
    p = np.array([0.0, tiny, 1e-300, 1.0, 1e6, 760e6, 800e6, 1e9, 1e300, 1.7e308])
    ph = np.array([0.0, tiny, 1e-300, 1.0, 1e6, 760e6, 800e6, 1e9, 1e300, 1.7e308])
    with warnings.catch_warnings(), np.errstate(all="raise"):
        warnings.simplefilter("error")
        pp, hh = np.meshgrid(p, ph)
        tau = shear_limit(pp, hh, P)
        dtau = shear_limit_dp(pp, hh, P)
        jump = reload_jump(P, ph)
    assert np.all(np.isfinite(tau)) and np.all(np.isfinite(dtau)) and np.all(np.isfinite(jump))
    assert np.all(tau >= 0) and np.all(tau <= P.tau_max)
    assert np.all(tau[:, 0] == 0) and np.all(tau[0, 1:] == shear_limit(p[1:], 0.0, P))


def test_traction_update_and_history_use_the_table():
    P = params(False)
    law = SBMFLaw(P)
    st_ = HistoryState(p_hist=[700e6, 700e6, 0.0])
    p = np.array([50e6, 800e6, 50e6])
    res = traction_update(law, p, np.full((3, 2), 1.0), np.zeros((3, 2)), np.full(3, 1e12), st_)
    tau = np.hypot(*res.traction.T)
    np.testing.assert_allclose(tau, shear_limit(p, st_.p_hist, P), rtol=1e-14)
    assert tau[0] > tau[2]  # the flattened surface carries more than the virgin one at 50 MPa


# -- the parameter file ----------------------------------------------------------------------


def test_json_round_trip_and_version(tmp_path):
    P = params(True)
    path = P.to_json(tmp_path / "p.json")
    doc = json.loads(path.read_text())
    assert doc["version"] == 2 and doc["reload_law"]["form"] == "tabulated"
    Q = FrictionParams.from_json(path)
    assert Q == P and Q.reload_table == P.reload_table
    # the paper form without a table writes version 1, which every earlier runtime reads
    paper = FrictionParams(m=0.5, sigma_y=3e8, H=H, C1=1.0, n1=2.0, C2=3.0, n2=2.0)
    assert paper.to_dict()["version"] == 1 and "reload_law" not in paper.to_dict()
    # a calibration switched to the paper's form keeps its table
    sw = P.replace(reload_form="paper")
    assert FrictionParams.from_dict(sw.to_dict()) == sw


def test_files_before_the_table_load_as_the_paper_form():
    doc = FrictionParams(m=0.5, sigma_y=3e8, H=H, C1=1.0, n1=2.0, C2=3.0, n2=2.0).to_dict()
    P = FrictionParams.from_dict(doc)
    assert P.reload_form == "paper" and P.reload_table is None


@pytest.mark.parametrize(
    "edit, field",
    [
        (lambda d: d["reload_law"].update(form="spline"), "reload_law.form"),
        (lambda d: d["reload_law"].update(version=3), "reload_law.version"),
        (lambda d: d["reload_law"]["C2"].__setitem__(2, float("nan")), "C2"),
        (lambda d: d["reload_law"]["n2"].__setitem__(0, -1.0), "n2"),
        (lambda d: d["reload_law"]["p_hist"].__setitem__(3, 1e6), "strictly increasing"),
        (lambda d: d["reload_law"]["p_hist"].__setitem__(7, 900e6), "below H"),
        (lambda d: d["reload_law"].update(s2=0.0), "s2"),
        (lambda d: d["reload_law"].pop("n2"), "'n2'"),
        (lambda d: d.update(version=1), "version 2"),
    ],
)
def test_bad_tables_are_refused_naming_the_field(edit, field):
    doc = json.loads(json.dumps(params().to_dict()))
    edit(doc)
    with pytest.raises(ValueError, match="reload_law|reload table|version") as exc:
        FrictionParams.from_dict(doc, source="p.json")
    assert field in str(exc.value)


def test_tabulated_form_needs_a_table():
    with pytest.raises(ValueError, match="reload_table"):
        FrictionParams(
            m=0.5, sigma_y=3e8, H=H, C1=1.0, n1=2.0, C2=3.0, n2=2.0, reload_form="tabulated"
        )
    with pytest.raises(ValueError, match="reload_form must be one of"):
        FrictionParams(m=0.5, sigma_y=3e8, H=H, C1=1.0, n1=2.0, C2=3.0, n2=2.0, reload_form="x")


@pytest.mark.parametrize("s2", [0.3, 0.67, 1.0, 1.6])
def test_quadratic_start_below_q0_is_c1_with_a_finite_slope_at_zero(s2):
    """Below p / p_hist = Q_START, x2 starts as a quadratic in p: tau and d tau/dp continuous at
    Q_START, d tau/dp finite as p -> 0 (q**s2 alone has an infinite slope there for s2 < 1, which
    stalled GetFEM's Newton on re-contact); s2 = 1 stays Eq. 25's linear x2 exactly."""
    from frictionlaw._codes import Q_START

    P = params(False, ReloadTable(p_hist=LEVELS, C2=C2B, n2=N2B, s2=s2))
    ph = 500e6
    q0p = Q_START * ph
    lo, hi = q0p * (1 - 1e-10), q0p * (1 + 1e-10)
    t = shear_limit(np.array([lo, hi]), ph, P)
    d = shear_limit_dp(np.array([lo, hi]), ph, P)
    assert abs(t[1] - t[0]) <= 1e-8 * t[1] and abs(d[1] - d[0]) <= 1e-6 * d[1]
    p = np.array([1e-300, 1e-12, 1.0, 1e3])
    d0 = shear_limit_dp(p, ph, P)
    assert np.all(np.isfinite(d0)) and np.all(d0 <= (2.0 - s2) / s2 * d[0] * 10 + d[0])
    # the slope at 0: tau = tau_max a1h g(x2) -> tau_max a1h x2 with x2 -> x2(q0) (2 - s2) t
    c2, n2 = P.reload_table.at(ph, H)
    a1h = alpha_first(ph, P)
    x2q0 = ph * float(c2) / (H * a1h) * Q_START**s2
    want = (2.0 - s2) * P.tau_max * a1h * x2q0 / q0p
    assert d0[0] == pytest.approx(want, rel=1e-6)
