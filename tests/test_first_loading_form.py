"""The tabulated first-loading form (frictionlaw.first_loading): kernels against the NumPy oracle
and SciPy's interpolant, the form's exact limits, the reload branch on its alpha1(p_hist), and
the parameter file's version 3."""

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
from frictionlaw.first_loading import FirstLoadingTable
from frictionlaw.law import sbmf_coeffs
from frictionlaw.reload_form import ReloadTable

H = 800e6
P_LEVELS = (10e6, 25e6, 50e6, 100e6, 200e6, 300e6, 400e6, 500e6, 600e6, 700e6, 760e6)
# the default scene's first loading (128^2), a nearly conforming scan in full contact from
# 100 MPa (metropro-1 against itself) and a scan whose alpha / (p / H) rises (sur-3)
TABLES = {
    "default": (
        0.015,
        0.0355,
        0.0696,
        0.1362,
        0.2659,
        0.3926,
        0.5197,
        0.6432,
        0.7661,
        0.8853,
        0.9554,
    ),
    "early_full": (0.648, 0.886, 0.9759, 0.9999, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0),
    "bump": (
        0.0129,
        0.0316,
        0.0627,
        0.1265,
        0.3384,
        0.5188,
        0.6537,
        0.7629,
        0.8301,
        0.8888,
        0.9503,
    ),
}
RELOAD = ReloadTable(
    p_hist=P_LEVELS[3:],
    C2=(4.5, 4.8, 5.1, 5.6, 7.0, 10.0, 20.8, 83.6),
    n2=(0.95, 0.84, 0.75, 0.71, 0.61, 0.51, 0.40, 0.29),
    s2=0.67,
)


def params(name="default", reload_form="paper", cont=False, **kw):
    table = FirstLoadingTable(p=P_LEVELS, alpha=TABLES[name])
    return FrictionParams(
        m=0.5,
        sigma_y=H / 2.8,
        H=H,
        C1=1.02,
        n1=16.5,
        C2=17.5,
        n2=0.41,
        first_loading_form="tabulated",
        first_loading_table=table,
        reload_form=reload_form,
        reload_table=RELOAD,
        continuous_reload=cont,
        **kw,
    )


def scipy_first(table, p):
    """SciPy's monotone interpolant of ln alpha over ln(p/H), the form's extensions beyond."""
    u = np.log(np.asarray(table.p) / H)
    v = np.log(np.asarray(table.alpha))
    f = PchipInterpolator(u, v)
    d_end = float(f.derivative()(u[-1]))
    uq = np.log(np.asarray(p, float) / H)
    inner = f(np.clip(uq, u[0], u[-1]))
    lna = np.where(
        uq < u[0], v[0] + uq - u[0], np.where(uq > u[-1], v[-1] + d_end * (uq - u[-1]), inner)
    )
    return np.exp(np.minimum(lna, 0.0)), f.derivative()(u)


PRESSURES = np.concatenate(
    [np.geomspace(1e-3, 1.2 * H, 700), P_LEVELS, np.array(P_LEVELS) * (1 + 1e-9), [H, 2 * H]]
)


# -- kernels against the oracle and SciPy -------------------------------------------------------


@pytest.mark.parametrize("name", sorted(TABLES))
def test_kernel_agrees_with_the_oracle_and_scipy(name):
    P = params(name)
    t = P.first_loading_table
    want, slopes = scipy_first(t, PRESSURES)
    # the form's slopes are SciPy's (frictionlaw.reload_form.pchip_slopes)
    np.testing.assert_allclose(t.knots(H)["d"], slopes, rtol=1e-12, atol=1e-14)
    oracle = ref.alpha_first_tabulated(PRESSURES, t.p, t.alpha, slopes, H)
    got = alpha_first(PRESSURES, P)
    np.testing.assert_allclose(got, oracle, rtol=2e-13, atol=0)
    np.testing.assert_allclose(got, want, rtol=2e-13, atol=0)
    np.testing.assert_allclose(shear_limit(PRESSURES, 0.0, P), P.tau_max * got, rtol=1e-15)
    # at the levels: the computed points themselves
    np.testing.assert_allclose(alpha_first(np.array(P_LEVELS), P), TABLES[name], rtol=1e-14)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.floats(0.05, 1.0), min_size=2, max_size=12),
    st.lists(st.floats(0.0, 0.5), min_size=12, max_size=12),
    st.floats(0.001, 0.3),
)
def test_random_tables_against_the_oracle(steps, rises, a0):
    """Monotone tables of every shape (flat stretches, full contact) agree with the oracle."""
    p = 1e6 * np.exp(np.cumsum(steps))
    p = p[p < 0.99 * H]
    if p.size < 2:
        return
    alpha = np.minimum(a0 * np.exp(np.cumsum(rises[: p.size])), 1.0)
    alpha = np.maximum(alpha, p / H)
    t = FirstLoadingTable(p=p, alpha=np.maximum.accumulate(alpha))
    P = params().replace(first_loading_table=t)
    q = np.concatenate([np.geomspace(1e-2, 2 * H, 300), p])
    _, slopes = scipy_first(t, q)
    oracle = ref.alpha_first_tabulated(q, t.p, t.alpha, slopes, H)
    np.testing.assert_allclose(alpha_first(q, P), oracle, rtol=1e-12, atol=1e-300)


# -- the form's exact limits and its tangent ---------------------------------------------------


@pytest.mark.parametrize("name", sorted(TABLES))
def test_coulomb_line_below_and_power_law_above(name):
    P = params(name)
    a = TABLES[name]
    mu = P.tau_max * a[0] / P_LEVELS[0]
    assert P.mu_eff == pytest.approx(mu, rel=1e-15)
    p = np.array([1e-310, 1e-3, 1.0, 1e6, 0.5 * P_LEVELS[0], P_LEVELS[0]])
    np.testing.assert_allclose(shear_limit(p, 0.0, P), mu * p, rtol=1e-14)
    np.testing.assert_allclose(shear_limit_dp(p[:-1], 0.0, P), mu, rtol=1e-14)
    # above the top level: alpha_top (p / p_top) ** d_top, capped at 1
    d_top = P.first_loading_table.knots(H)["d"][-1]
    q = np.array([770e6, 790e6, 799e6])
    want = np.minimum(a[-1] * (q / P_LEVELS[-1]) ** d_top, 1.0)
    np.testing.assert_allclose(alpha_first(q, P), want, rtol=1e-13)
    assert alpha_first(1e30, P) == 1.0 and alpha_first(np.inf, P) == 1.0
    if a[-1] == 1.0:  # the top level in full contact: 1 exactly beyond it
        assert np.all(alpha_first(np.geomspace(P_LEVELS[-1], 1e12, 50), P) == 1.0)


@pytest.mark.parametrize("name", sorted(TABLES))
def test_derivative_is_exact_finite_and_tau_monotone(name):
    P = params(name)
    p = np.geomspace(1e3, 1.1 * H, 3000)
    p = p[np.min(np.abs(p[:, None] / np.array(P_LEVELS) - 1), axis=1) > 1e-5]  # off the kinks
    h = p * 1e-7
    fd = (shear_limit(p + h, 0.0, P) - shear_limit(p - h, 0.0, P)) / (2 * h)
    d = shear_limit_dp(p, 0.0, P)
    tau = shear_limit(p, 0.0, P)
    np.testing.assert_allclose(d, fd, rtol=2e-6, atol=1e-9 * P.mu_eff)
    assert np.all(np.diff(tau) >= 0.0) and np.all(d >= 0.0) and np.all(np.isfinite(d))


def test_no_nan_or_warning_at_any_pressure():
    P = params("early_full", "tabulated", cont=True)
    p = np.array([0.0, 5e-324, 1e-300, 1.0, P_LEVELS[0], H, 1e300, np.inf])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for ph in (0.0, 5e-324, 1e-300, 1.0, 50e6, H, 1e300):
            for f in (shear_limit, shear_limit_dp):
                v = f(p, ph, P)
                assert np.all(np.isfinite(v)) and np.all(v >= 0.0)
    assert shear_limit(0.0, 0.0, P) == 0.0 and shear_limit_dp(0.0, 0.0, P) == 0.0


# -- the reload branch on alpha1(p_hist) of the tabulated form ----------------------------------


@pytest.mark.parametrize("cont", [False, True])
@pytest.mark.parametrize("reload_form", ["paper", "tabulated"])
def test_reload_branch_is_scaled_by_the_tabulated_alpha1(reload_form, cont):
    P = params("bump", reload_form, cont)
    rng = np.random.default_rng(5)
    ph = np.concatenate([rng.uniform(1e6, 1.2 * H, 300), P_LEVELS])
    p = ph * rng.uniform(0.0, 1.0, ph.size)
    t = P.first_loading_table
    _, slopes = scipy_first(t, ph)
    ln_a1h = np.log(ref.alpha_first_tabulated(ph, t.p, t.alpha, slopes, H))
    if reload_form == "paper":
        want = ref.alpha_reload(p, ph, P.C1, P.n1, P.C2, P.n2, H, cont, ln_a1h=ln_a1h)
    else:
        c2, n2 = RELOAD.at(ph, H)
        want = ref.alpha_reload_tabulated(p, ph, P.C1, P.n1, H, c2, n2, RELOAD.s2, cont, ln_a1h)
    np.testing.assert_allclose(alpha_reload(p, ph, P), want, rtol=5e-12, atol=1e-300)
    below = p < ph
    np.testing.assert_allclose(
        shear_limit(p[below], ph[below], P), P.tau_max * want[below], rtol=5e-12
    )
    if cont:  # the continuous variant meets the tabulated first loading at p_hist
        jump = np.asarray(reload_jump(P, np.array(P_LEVELS)))
        assert np.all(np.abs(jump) <= 1e-12 * P.tau_max)


def test_traction_update_runs_the_form():
    P = params("bump", "tabulated")
    p = np.array([5e6, 60e6, 300e6, 900e6])
    state = HistoryState(p_hist=np.array([0.0, 400e6, 300e6, 0.0]))
    du = np.array([[1e-3, 0.0]] * 4)
    res = traction_update(SBMFLaw(P), p, du, np.zeros((4, 2)), 1e12, state)
    want = shear_limit(p, state.p_hist, P)
    np.testing.assert_allclose(res.traction[:, 0], want, rtol=1e-15)
    assert np.all(res.status == 2)


def test_eq24_arrays_are_unchanged():
    """A file running Eq. 24 keeps the coefficient arrays of earlier versions (8 or 10 + 5 K)."""
    P = params().replace(first_loading_form="eq24")
    assert sbmf_coeffs(P).size == 8
    assert sbmf_coeffs(P.replace(reload_form="tabulated")).size == 10 + 5 * len(RELOAD.p_hist)
    assert sbmf_coeffs(params()).size == 12 + 3 * len(P_LEVELS)
    assert sbmf_coeffs(params(reload_form="tabulated")).size == 12 + 5 * 8 + 3 * len(P_LEVELS)
    assert P.mu_eff == pytest.approx(P.tau_max * P.C1 / H, rel=1e-15)


# -- validation and the parameter file ----------------------------------------------------------


@pytest.mark.parametrize(
    "kw, fragment",
    [
        (dict(p=(1e6,), alpha=(0.1,)), "at least 2"),
        (dict(p=(2e6, 1e6), alpha=(0.1, 0.2)), "strictly increasing"),
        (dict(p=(1e6, 2e6), alpha=(0.2, 0.1)), "must not decrease"),
        (dict(p=(1e6, 2e6), alpha=(0.0, 0.1)), "(0, 1]"),
        (dict(p=(1e6, 2e6), alpha=(0.1, 1.5)), "(0, 1]"),
        (dict(p=(1e6, np.nan), alpha=(0.1, 0.2)), "finite"),
        (dict(p=(1e6, 2e6, 3e6), alpha=(0.1, 0.2)), "one value per level"),
    ],
)
def test_bad_tables_are_refused(kw, fragment):
    with pytest.raises(ValueError, match="first-loading table") as exc:
        FirstLoadingTable(**kw)
    assert fragment in str(exc.value)


def test_params_need_a_table_below_H_for_the_form():
    with pytest.raises(ValueError, match="first_loading_table"):
        params().replace(first_loading_table=None)
    with pytest.raises(ValueError, match="below H"):
        params().replace(first_loading_table=FirstLoadingTable(p=(1e6, 900e6), alpha=(0.1, 1.0)))
    with pytest.raises(ValueError, match="first_loading_form must be one of eq24, tabulated"):
        params().replace(first_loading_form="spline")


def test_version_3_round_trip_and_the_lowest_version(tmp_path):
    P = params("bump", "tabulated", True)
    doc = json.loads(P.to_json(tmp_path / "p.json").read_text())
    assert doc["version"] == 3 and doc["first_loading_law"]["form"] == "tabulated"
    assert doc["first_loading_law"]["units"] == {"p": "Pa", "alpha": "1"}
    assert "interpolation" in doc["first_loading_law"]
    Q = FrictionParams.from_json(tmp_path / "p.json")
    assert Q == P and Q.first_loading_table == P.first_loading_table and Q.mu_eff == P.mu_eff
    # switched to Eq. 24 the table is kept (version 3); without one, 2 or 1 as before
    sw = P.replace(first_loading_form="eq24")
    assert FrictionParams.from_dict(sw.to_dict()) == sw and sw.to_dict()["version"] == 3
    assert P.replace(first_loading_form="eq24", first_loading_table=None).to_dict()["version"] == 2
    bare = P.replace(
        first_loading_form="eq24", first_loading_table=None, reload_form="paper", reload_table=None
    )
    assert bare.to_dict()["version"] == 1


@pytest.mark.parametrize(
    "edit, field",
    [
        (lambda d: d["first_loading_law"].update(form="spline"), "first_loading_law.form"),
        (lambda d: d["first_loading_law"].update(version=2), "first_loading_law.version"),
        (lambda d: d["first_loading_law"]["alpha"].__setitem__(2, float("nan")), "finite"),
        (lambda d: d["first_loading_law"]["alpha"].__setitem__(3, 0.01), "must not decrease"),
        (lambda d: d["first_loading_law"]["p"].__setitem__(-1, 900e6), "below H"),
        (lambda d: d["first_loading_law"].pop("alpha"), "'alpha'"),
        (lambda d: d["first_loading_law"]["units"].update(p="MPa"), "'Pa'"),
        (lambda d: d.update(version=2), "'first_loading_law' needs version 3"),
    ],
)
def test_bad_files_are_refused_naming_the_field(edit, field):
    doc = json.loads(json.dumps(params().to_dict()))
    edit(doc)
    with pytest.raises(ValueError) as exc:
        FrictionParams.from_dict(doc, source="p.json")
    assert field in str(exc.value) and "p.json" in str(exc.value)
