"""Generated Fortran user subroutines against the runtime, under the hosts' calling sequences.

Each target is compiled once per parameter set and unit system (gfortran -Wall) into a shared
library with a shim that calls the documented entry point for many contact points; a Python
"host" drives increments with several iterations (state passed in as at the start of the
increment, kept only when the increment converges, discarded on a cut-back) and compares every
iteration node by node with ``frictionlaw.traction_update`` + ``HistoryState``. Both reload
forms: the paper's Eq. 25 (``default``, ``soft``, ``sharp``) and the tabulated form (``tab``,
``tab_flat``, tests/reload_tables.py), whose pressures also hit the table's levels; both
first-loading forms: Eq. 24 and the tabulated first loading (``first_*``, on either reload
form), whose pressures hit its levels too.
"""

import dataclasses
import re

import numpy as np
import pytest
from default_params import DEFAULT
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from reload_tables import FIRST, FLAT, PAIR, SINGLE, STRONG, levels

import frictionlaw as fl
import frictionlaw.export as exp
from frictionlaw.export import harness
from frictionlaw.export._templates import fortran_double
from frictionlaw.params import TangentialStiffness
from frictionlaw.reload_form import S2_RANGE

pytestmark = pytest.mark.skipif(
    harness.gfortran() is None,
    reason="gfortran not installed (.ci/run installs it: apt-get install -y gfortran)",
)

KT_TABLE = TangentialStiffness(p=(1e7, 1e8, 6e8), k_t=(2e12, 8e12, 3e13))
PARAM_SETS = {
    "default": fl.FrictionParams(**DEFAULT),
    # extremes of the runtime's tests: n from 0.1 to 1000, continuous reload, Eq. 26, k_t table
    "soft": fl.FrictionParams(
        **{**DEFAULT, "n1": 0.1, "n2": 1000.0},
        continuous_reload=True,
        geo_ratio=0.3,
        k_t=KT_TABLE,
    ),
    "sharp": fl.FrictionParams(**{**DEFAULT, "n1": 1000.0, "n2": 0.1, "C1": 10.0, "C2": 0.5}),
    # the tabulated reload form: the default scene's shape, and a flat C2 with n2 varying tenfold
    # (continuous, Eq. 26, k_t table)
    "tab": fl.FrictionParams(**DEFAULT, reload_form="tabulated", reload_table=STRONG),
    "tab_flat": fl.FrictionParams(
        **DEFAULT,
        continuous_reload=True,
        geo_ratio=0.3,
        k_t=KT_TABLE,
        reload_form="tabulated",
        reload_table=FLAT,
    ),
    # one level (constant C2, n2), two levels (the straight line), with the sharp Eq. 24
    "tab_single": fl.FrictionParams(
        **DEFAULT, continuous_reload=True, reload_form="tabulated", reload_table=SINGLE
    ),
    "tab_pair": fl.FrictionParams(
        **{**DEFAULT, "n1": 1000.0, "C1": 10.0}, reload_form="tabulated", reload_table=PAIR
    ),
    # s2 at its lower bound: dtau/dp reaches the kernel's exp(700) bound at subnormal p
    "tab_steep": fl.FrictionParams(
        **DEFAULT, reload_form="tabulated", reload_table=dataclasses.replace(STRONG, s2=S2_RANGE[0])
    ),
}
# the tabulated first loading (tests/reload_tables.py, FIRST) on either reload form: the default
# scene's, the bump with the tabulated reload form (continuous, Eq. 26, k_t table), full contact
# from 100 MPa and from the first level (the one-level reload table), the two-level table, the
# flat top below full contact
for _key, _first, _extra in (
    ("first_default", "default", {}),
    (
        "first_bump",
        "bump",
        dict(
            reload_form="tabulated",
            reload_table=STRONG,
            continuous_reload=True,
            geo_ratio=0.3,
            k_t=KT_TABLE,
        ),
    ),
    ("first_full", "early_full", dict(continuous_reload=True)),
    (
        "first_one",
        "full",
        dict(reload_form="tabulated", reload_table=SINGLE, continuous_reload=True),
    ),
    ("first_pair", "pair", dict(reload_form="tabulated", reload_table=PAIR)),
    ("first_flat", "flat", {}),
):
    PARAM_SETS[_key] = fl.FrictionParams(
        **DEFAULT, first_loading_form="tabulated", first_loading_table=FIRST[_first], **_extra
    )
UNITS = exp.UNIT_SYSTEMS
TINY = np.finfo(float).tiny
FSLIP = 0.005

_LIBS = {}


def _write_params(tmp_path_factory, key):
    path = tmp_path_factory.getbasetemp() / f"params_{key}.json"
    if not path.exists():
        PARAM_SETS[key].to_json(path)
    return path


def lib_for(tmp_path_factory, target, key, units, k_t=None):
    """Compile (once per session) ``target`` for parameter set ``key`` in ``units``."""
    tag = (target, key, units, k_t)
    if tag not in _LIBS:
        files, _ = exp.render(target, _write_params(tmp_path_factory, key), units=units, k_t=k_t)
        src = {n: t for n, t in files.items() if n.endswith(".f")}
        name = re.sub(r"[^a-z0-9]", "_", f"{target}_{key}_{units}_{k_t}".lower())
        wd = tmp_path_factory.mktemp(name)
        _LIBS[tag] = exp.target(target).harness.load(src, wd, name=name)
    return _LIBS[tag]


# -- data of one iteration --------------------------------------------------------------------
#: log10 of the largest pressure over H the routines run the law at: above 100 H their guards
#: stop the run (docs/fe_codes.md, "Guards"; tests/test_export_guards.py); the host-neutral
#: SBMF_FRICTION returns the law there too, with its status, and is driven up to 1e6 H
TOP = 1.9


def pressures(rng, n, p_hist, H, levels=(), top=TOP):
    """A mix: open, tiny (down to 1e-300 Pa), at/around p_hist, below it (Eq. 25), up to
    ``10**top`` H (1e6 H for the host-neutral entry, just below 100 H for the others).

    With a tabulated reload form's ``levels``, a quarter of the points also land exactly on a
    level or one ulp either side of it (so that ``p_hist`` is committed there), and a tenth just
    below ``p_hist`` (1e-16 .. 1e-8 relative).
    """
    kind = rng.integers(0, 7, n)
    p = 10.0 ** rng.uniform(np.log10(H) - 3, np.log10(H) + top, n)  # first loading / reloading
    p = np.where(kind == 0, -rng.uniform(0, H, n) * (rng.random(n) < 0.5), p)  # open (0 or < 0)
    p = np.where(kind == 1, 10.0 ** rng.uniform(-300, -200, n), p)
    p = np.where(kind == 2, p_hist, p)
    below = p_hist * rng.uniform(0.0, 1.0, n)
    p = np.where((kind >= 3) & (kind <= 4) & (p_hist > 0), below, p)
    p = np.where(kind == 5, 10.0 ** rng.uniform(np.log10(H) - 2, np.log10(H) + min(top, 0.5), n), p)
    if len(levels):
        at = np.asarray(levels)[rng.integers(0, len(levels), n)]
        side = rng.integers(-1, 2, n)
        at = np.where(
            side < 0, np.nextafter(at, 0), np.where(side > 0, np.nextafter(at, 2 * at), at)
        )
        p = np.where(rng.random(n) < 0.25, at, p)
        near = p_hist * (1.0 - 10.0 ** rng.uniform(-16, -8, n))
        p = np.where((rng.random(n) < 0.1) & (p_hist > 0), near, p)
    return p


def slips(rng, n, nd, params, k_scale):
    """Slip increments that give both stick and slip (trial traction 0.01 .. 10 tau_max)."""
    mag = params.tau_max / k_scale * 10.0 ** rng.uniform(-2, 1, (n, 1))
    return rng.normal(size=(n, nd)) * mag


def expected_kt(params, kt_spec, units, p, tau, chr_):
    """The k_t the routine must use (SI), mirroring the three stiffness sources."""
    if kt_spec.kind == "constant":
        return np.full(p.shape, kt_spec.value / units.stiffness)
    if kt_spec.kind == "table":
        return params.k_t(p)
    # the floor acts in the host's units (TINY MPa is not TINY Pa)
    return np.maximum(tau * units.stress, TINY) / (FSLIP * chr_ * units.length) / units.stiffness


def assert_close(a, b, rtol, what, scale=None, floor=TINY):
    """Node-wise ``max |a - b| <= rtol max(max |b|, floor)`` (``scale`` replaces ``max |b|``)."""
    a, b = np.asarray(a), np.asarray(b)
    axes = tuple(range(1, a.ndim))
    if scale is None:
        scale = np.max(np.abs(b), axis=axes) if axes else np.abs(b)
    err = np.max(np.abs(a - b), axis=axes) if axes else np.abs(a - b)
    bad = err > rtol * np.maximum(scale, floor)
    assert not bad.any(), (
        f"{what}: {bad.sum()} nodes off, worst rel {np.max(err / np.maximum(scale, TINY)):.3g}"
    )


def dtdp_rounding(law, p, p_hist, units):
    """Per node: how far the runtime's ``|dtau/dp|`` moves when ``p`` moves by the host's rounding.

    In SI the routine sees the runtime's own inputs (the bound is 0). In other units it sees
    ``p s`` and ``p_hist s``, rounded, and forms ``ln(p C / H)`` from them: a relative
    perturbation of ``x = p C2 / (H alpha1(p_hist))`` up to about ``eps (|ln p_s| + |ln p_hist_s|)``.
    Near the knee of a sharp law (``n2 = 1000`` at ``x ~ 1``) ``dtau/dp`` amplifies that by
    ``n``, so the agreement of DDTDDP is bounded by the runtime's own spread over those inputs
    (found at ``p ~ 1e-203 Pa``, ``p / p_hist = 0.14``, ``n2 = 1000``: 7.9e-10 relative).
    """
    return _rounding_spread(law, p, p_hist, units, 1)


def tau_rounding(law, p, p_hist, units):
    """Per node: how far the runtime's shear limit moves when ``p`` moves by the host's rounding.

    :func:`dtdp_rounding`'s spread for ``tau`` itself: near the knee of a sharp law the mm-t-s
    routine's rounded ``p s`` moves ``tau`` by ``n2`` times the rounding (found: 1.24e-12
    relative at ``n2 = 1000``), which bounds the traction's agreement as it bounds DDTDDP's.
    """
    return _rounding_spread(law, p, p_hist, units, 0)


def _rounding_spread(law, p, p_hist, units, k):
    """The spread of ``law.shear_limit(...)[k]`` over ``p`` moved by the host's rounding."""
    if units.name == "SI":
        return np.zeros(np.shape(p))
    s = units.stress
    with np.errstate(divide="ignore"):
        lnp = np.abs(np.log(np.where(p > 0, p * s, 1.0)))
        lnh = np.abs(np.log(np.where(p_hist > 0, p_hist * s, 1.0)))
    d = 4 * np.finfo(float).eps * (1.0 + lnp + lnh)
    below = p < p_hist  # stay on the branch the node is on (Eq. 25 below p_hist, else Eq. 24)
    p_lo = np.where(below, p * (1 - d), np.maximum(p * (1 - d), p_hist))
    p_hi = np.where(below, np.minimum(p * (1 + d), np.nextafter(p_hist, 0)), p * (1 + d))
    ref = law.shear_limit(p, p_hist)[k]
    lo = law.shear_limit(p_lo, p_hist)[k]
    hi = law.shear_limit(p_hi, p_hist)[k]
    return np.maximum(np.abs(lo - ref), np.abs(hi - ref))


def assert_dtdp_close(a, b, spread, what):
    """``assert_close(a, b, 1e-10)`` widened node-wise by the runtime's rounding ``spread``."""
    a, b = np.asarray(a), np.asarray(b)
    err = np.max(np.abs(a - b), axis=1)
    allowed = 1e-10 * np.maximum(np.max(np.abs(b), axis=1), TINY) + spread
    bad = err > allowed
    assert not bad.any(), f"{what}: {bad.sum()} nodes off, worst excess {np.max(err - allowed):.3g}"


def host_floor(factor):
    """The floor of :func:`assert_close` for a routine output in host units (SI value x factor).

    Below the smallest normal double the comparison is absolute (``rtol TINY``): a subnormal
    carries fewer than 53 bits. The routine computes in the host's units, so the floor is
    the smallest normal double of *those* units, expressed in SI (``TINY`` in SI, as before).
    Since the runtime slips at any trial ``|t| > tau`` (its scaled norm; the old ``|t|^2``
    underflowed and reported stick for ``|t| < 1e-154``), Abaqus' fallback ``k_t`` (proportional
    to ``tau``) at pressures of 1e-300 .. 1e-200 Pa gives slip tangents ``k_t tau/|t_tr|`` that
    are subnormal in MPa/mm (1e-9 Pa/m) while still normal in Pa/m.
    """
    return max(TINY, TINY / factor)


def traction_scale(units, ref_t, t_old, kt, du):
    """SI: the traction itself, and a few ulps of the largest term of ``t_old + k_t du``: a
    ``k_t`` interpolated in logs from a calibrated table agrees with the runtime's to an ulp, and
    the stick update may cancel (a node with terms of 1.35e6 Pa and a traction of 196 Pa: 1.2e-12
    of the traction, 2 ulps of the terms). mm-t-s: the largest term itself, because the unit
    conversion perturbs the inputs by an ulp too."""
    scale = np.max(np.abs(ref_t), axis=1)
    terms = np.maximum(np.max(np.abs(t_old), axis=1), np.max(np.abs(kt[:, None] * du), axis=1))
    if units.name == "SI":
        return np.maximum(scale, terms * (4.0 * np.finfo(float).eps / 1e-12))
    return np.maximum(scale, terms)


def same_branch(p, p_hist, units):
    """Nodes on which the routine (inputs in host units) takes the runtime's branch.

    In mm-t-s a ``p`` within a few ulps of ``p_hist`` (the tabulated tests put points 1e-16 ..
    1e-8 below it) may round to the other side of ``p_hist``: the routine then takes Eq. 24
    where the runtime, on the SI values, takes Eq. 25 (a jump of the law, or of its slope in the
    continuous variant). Those nodes are compared in SI only (there every node is compared).
    """
    s = units.stress
    with np.errstate(over="ignore"):
        return (p * s < p_hist * s) == (p < p_hist)


def knife_edge(t_old, du, kt, tau, eps):
    """Nodes whose trial |t| is within eps of tau (stick/slip may differ by rounding there)."""
    tr = np.linalg.norm(t_old + kt[:, None] * du, axis=1)
    return np.abs(tr - tau) <= eps * np.maximum(tau, TINY)


def check_cache(params, p_hist, cache):
    """Cache = -ln alpha1(p_hist) (p_hist > 0), alpha1 to 1e-12 relative.

    The runtime's Eq. 25 now works from ``ln alpha1(p_hist)`` (``smooth_min_log``), so the
    routine caches that logarithm (negated, so that ``<= 0`` still means "recompute") instead
    of ``alpha1 / x1`` or ``alpha1``; ``|d ln alpha1| <= 1e-12`` is the old ``rtol=1e-12`` on
    ``alpha1``. Where ``alpha1`` underflows (``x1 <= 1e-300``, ``x1 = p_hist s0`` with the
    form's small-pressure slope ``s0 = lim alpha1 / p``: ``C1 / H`` of Eq. 24, ``alpha_0 / p_0``
    of the tabulated first loading) the exact small-``x1`` limit ``alpha1 = x1 (1 + O(x1**(2
    n1)))`` (the tabulated form's Coulomb line: exactly ``x1``) is the reference:
    ``-ln alpha1 = -ln(p_hist s0)``.
    """
    on = p_hist > 0
    assert np.all(cache[on] >= 0)
    s0 = params.branch_forms()[0].slope0(params)
    x1 = p_hist[on] * s0
    ok = x1 > 1e-300
    a1 = fl.alpha_first(p_hist[on][ok], params)
    np.testing.assert_allclose(-cache[on][ok], np.log(a1), rtol=0, atol=1e-12)
    tiny = ~ok
    want = -(np.log(p_hist[on][tiny]) + np.log(s0))
    np.testing.assert_allclose(cache[on][tiny], want, rtol=1e-12)


# -- FRIC ---------------------------------------------------------------------------------------
def run_fric(host, params, kt_spec, units, seed, nd, nstatv, n=48, n_incr=6):
    """Drive FRIC through increments/iterations/cut-backs and compare with the runtime."""
    rng = np.random.default_rng(seed)
    law = fl.SBMFLaw(params)
    s, ln = units.stress, units.length
    state = fl.HistoryState(n)
    sv = np.zeros((n, nstatv))  # Abaqus' STATEV at the start of the increment (committed)
    tau_c = np.zeros((n, nd))  # TAU at the start of the increment (SI)
    chr_ = 10.0 ** rng.uniform(-4, -2, n)  # CHRLNGTH (m)
    k_scale = params.tau_max / (FSLIP * 1e-3)
    checked = 0
    for _ in range(n_incr):
        for _attempt in range(2):
            ph = state.p_hist.copy()
            dgam = np.zeros((n, nd))
            for _it in range(int(rng.integers(1, 4))):
                p = pressures(rng, n, ph, params.H, levels(params))
                dgam = dgam + slips(rng, n, nd, params, k_scale)  # total since increment start
                tau_lim = law.shear_limit(p, ph)[0]
                kt = expected_kt(params, kt_spec, units, p, tau_lim, chr_)
                ref = fl.traction_update(law, p, dgam, tau_c, kt, state)
                out = host(p * s, dgam * ln, tau_c * s, sv, chr_ * ln)
                # traction, tangents (host units -> SI), state
                m = same_branch(p, ph, units)
                scale = traction_scale(units, ref.traction, tau_c, kt, dgam)
                widened = scale + tau_rounding(law, p, ph, units) / 1e-12
                assert_close(out["tau"][m] / s, ref.traction[m], 1e-12, "traction", widened[m])
                assert_close(
                    out["ddtddg"][m] / (s / ln),
                    ref.dt_dslip[m],
                    1e-10,
                    "DDTDDG",
                    floor=host_floor(units.stiffness),
                )
                spread = dtdp_rounding(law, p, ph, units)
                assert_dtdp_close(out["ddtddp"][m], ref.dt_dp[m], spread[m], "DDTDDP")
                assert np.array_equal(
                    out["statev"][:, 0], np.maximum(ph * s, np.where(p > 0, p * s, 0))
                )
                np.testing.assert_allclose(out["statev"][:, 0] / s, state.p_hist_trial, rtol=1e-15)
                open_ = ~(p > 0)
                assert np.array_equal(out["lm"] == 2, open_)
                assert np.all(out["lm"][~open_] == 0)
                if nstatv >= 2:  # the alpha1(p_hist) cache matches the new p_hist
                    check_cache(params, out["statev"][:, 0] / s, out["statev"][:, 1])
                if nstatv >= 3:
                    edge = knife_edge(tau_c, dgam, kt, tau_lim, 1e-9 if units.name != "SI" else 0)
                    edge |= ~m
                    st_f = out["statev"][:, 2].astype(int)
                    assert np.array_equal(st_f[~edge], ref.status[~edge]), "stick/slip status"
                    # frictional slip only when slipping
                    assert np.all(out["dslip"][st_f == 1] == 0)
                checked += n
                last = (out, ref)
            if rng.random() < 0.3:  # cut-back: Abaqus discards STATEV and TAU of the attempt
                state.rollback()
                continue
            out, ref = last
            sv = out["statev"].copy()
            tau_c = out["tau"] / s
            state.commit()
            assert np.array_equal(sv[:, 0], state.p_hist * s) or units.name != "SI"
            break
        else:
            state.rollback()
    return checked


@pytest.mark.parametrize("units", ["SI", "mm-t-s"])
@pytest.mark.parametrize(
    "key", ["default", "soft", "sharp", "tab", "tab_flat", "first_bump", "first_full"]
)
def test_fric_compiles_cleanly(tmp_path_factory, key, units):
    _, warnings = lib_for(tmp_path_factory, "abaqus-fric", key, units)
    # only the documented interface's unused arguments may warn
    others = [w for w in re.findall(r"Warning: (.*)", warnings) if "Unused dummy argument" not in w]
    assert others == []


FRIC_CASES = st.tuples(
    st.integers(0, 2**32 - 1), st.sampled_from([1, 2]), st.sampled_from([1, 2, 3])
)


@pytest.mark.parametrize(
    "key,units,k_t",
    [
        ("default", "SI", None),
        ("default", "mm-t-s", None),
        ("soft", "SI", None),
        ("soft", "mm-t-s", None),
        ("sharp", "SI", 5e12),
        ("tab", "SI", None),
        ("tab", "mm-t-s", None),
        ("tab_flat", "SI", None),
        ("tab_flat", "mm-t-s", 5e12),
        ("first_bump", "mm-t-s", None),
        ("first_full", "SI", None),
    ],
)
@settings(
    max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(case=FRIC_CASES)
def test_fric_agrees_with_runtime(tmp_path_factory, key, units, k_t, case):
    seed, nd, nstatv = case
    host, _ = lib_for(tmp_path_factory, "abaqus-fric", key, units, k_t)
    params = PARAM_SETS[key]
    us = UNITS[units]
    kt_spec = exp.stiffness_spec(params, us, k_t)
    assert run_fric(host, params, kt_spec, us, seed, nd, nstatv) > 0


# -- VFRIC --------------------------------------------------------------------------------------
def run_vfric(host, params, units, seed, nsv, n=48, n_incr=8):
    """Explicit increments (no iterations, every increment commits) against the force adapter."""
    rng = np.random.default_rng(seed)
    law = fl.SBMFLaw(params)
    s, ln = units.stress, units.length
    state = fl.HistoryState(n)
    statev = np.zeros((n, nsv))
    for _ in range(n_incr):
        ph = state.p_hist.copy()
        area = 10.0 ** rng.uniform(-8, -4, n)  # m^2
        p = pressures(rng, n, ph, params.H, levels(params))
        if units.name != "SI":  # forces of 1e-300 Pa x 1e-8 m^2 are subnormal: SI covers them
            p = np.where((p > 0) & (p < 1e-280), 1e-280, p)
        f_n = p * area
        f_stick = params.tau_max * area * 10.0 ** rng.uniform(-2, 1, n)
        # the force adapter with k_force = area (k_t = 1): trial = -stick force
        ref = fl.traction_update_force(law, f_n, area, -f_stick / area, np.zeros(n), area, state)
        ft = host(f_n * s * ln**2, f_stick * s * ln**2, area * ln**2, statev)
        # p = fNormal / area rounds differently in mm-t-s: at p == p_hist that may pick the other
        # branch of Eq. 24/25 (a jump of the law); those nodes are compared in SI only
        si = units.name == "SI"
        keep = si | ~(np.abs(p - ph) <= 1e-12 * ph)
        assert_close(ft[keep, 0] / (s * ln**2), ref.traction[keep], 1e-12, "fTangential(1)")
        assert np.all(ft[:, 1] == 0)
        assert np.all(ft[:, 0] <= 0) and np.all(-ft[:, 0] <= f_stick * s * ln**2 * (1 + 1e-15))
        np.testing.assert_allclose(statev[keep, 0] / s, state.p_hist_trial[keep], rtol=1e-15)
        if si:
            assert np.array_equal(statev[:, 0], state.p_hist_trial)
        if nsv >= 2:
            check_cache(params, statev[:, 0] / s, statev[:, 1])
        if nsv >= 3:
            tau = law.shear_limit(p, ph)[0]
            edge = np.abs(f_stick / area - tau) <= 1e-9 * np.maximum(tau, TINY)
            edge |= ~keep
            assert np.array_equal(statev[~edge, 2].astype(int), ref.status[~edge])
        state.commit()
    return n * n_incr


@pytest.mark.parametrize(
    "key,units",
    [
        ("default", "SI"),
        ("default", "mm-t-s"),
        ("soft", "SI"),
        ("tab", "SI"),
        ("tab", "mm-t-s"),
        ("tab_flat", "SI"),
        ("first_one", "mm-t-s"),
    ],
)
@settings(
    max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(seed=st.integers(0, 2**32 - 1), nsv=st.sampled_from([1, 2, 3]))
def test_vfric_agrees_with_runtime(tmp_path_factory, key, units, seed, nsv):
    host, warnings = lib_for(tmp_path_factory, "abaqus-vfric", key, units)
    others = [w for w in re.findall(r"Warning: (.*)", warnings) if "Unused dummy argument" not in w]
    assert others == []
    assert run_vfric(host, PARAM_SETS[key], UNITS[units], seed, nsv) > 0


# -- host-neutral entry (LS-DYNA, ANSYS) ------------------------------------------------------
def run_generic(host, params, kt_spec, units, seed, nd, n=48, n_incr=6):
    """Implicit-host sequence with the state kept by the caller, as the glue must do."""
    rng = np.random.default_rng(seed)
    law = fl.SBMFLaw(params)
    s, ln = units.stress, units.length
    state = fl.HistoryState(n)
    ph_c = np.zeros(n)  # committed state in host units
    g1_c = np.zeros(n)
    t_c = np.zeros((n, nd))
    k_host = 10.0 ** rng.uniform(11, 14, n)  # Pa/m
    for _ in range(n_incr):
        du = np.zeros((n, nd))
        for _it in range(int(rng.integers(1, 4))):
            p = pressures(rng, n, state.p_hist, params.H, levels(params), top=6)
            du = du + slips(rng, n, nd, params, 1e13)
            kt = k_host if kt_spec.kind == "host" else expected_kt(params, kt_spec, units, p, 0, 1)
            ref = fl.traction_update(law, p, du, t_c, kt, state)
            out = host(p * s, ph_c, g1_c, du * ln, t_c * s, k_host * units.stiffness)
            # the guards' status: -6 for a committed p_hist above 100 H, else -4 for a pressure
            # above it (the caller must stop, an implicit one may cut back), else 0 (no p_range)
            limit = 100 * params.H * s
            want = np.where(ph_c > limit, -6, np.where(p * s > limit, -4, 0))
            assert np.array_equal(out["ierr"], want)
            m = same_branch(p, state.p_hist, units)
            scale = traction_scale(units, ref.traction, t_c, np.broadcast_to(kt, p.shape), du)
            scale = scale + tau_rounding(law, p, ph_c / s, units) / 1e-12
            assert_close(out["t"][m] / s, ref.traction[m], 1e-12, "traction", scale[m])
            assert_close(
                host.tangent(out)[m] / units.stiffness,
                ref.dt_dslip[m],
                1e-10,
                "dt/ddu",
                floor=host_floor(units.stiffness),
            )
            spread = dtdp_rounding(law, p, state.p_hist.copy(), units)
            assert_dtdp_close(out["dt_dp"][m], ref.dt_dp[m], spread[m], "dt/dp")
            np.testing.assert_allclose(out["p_hist"] / s, state.p_hist_trial, rtol=1e-15)
            tau = law.shear_limit(p, state.p_hist.copy())[0]
            edge = knife_edge(t_c, du, kt, tau, 1e-9 if units.name != "SI" else 0) | ~m
            assert np.array_equal(out["status"][~edge], ref.status[~edge])
        if rng.random() < 0.3:
            state.rollback()  # cut-back: the glue drops PHNEW, G1NEW
            continue
        ph_c, g1_c, t_c = out["p_hist"].copy(), out["g1h"].copy(), out["t"] / s
        state.commit()
        check_cache(params, ph_c / s, g1_c)
    return n * n_incr


@pytest.mark.parametrize("target", ["lsdyna", "ansys-userfric"])
@pytest.mark.parametrize(
    "key,units",
    [
        ("default", "SI"),
        ("soft", "mm-t-s"),
        ("tab", "SI"),
        ("tab_flat", "mm-t-s"),
        ("first_pair", "SI"),
        ("first_flat", "mm-t-s"),
    ],
)
@settings(
    max_examples=10, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(seed=st.integers(0, 2**32 - 1), nd=st.sampled_from([1, 2]))
def test_generic_agrees_with_runtime(tmp_path_factory, target, key, units, seed, nd):
    host, warnings = lib_for(tmp_path_factory, target, key, units)
    assert "Warning" not in warnings  # the core and the entry point compile without any warning
    params = PARAM_SETS[key]
    us = UNITS[units]
    assert run_generic(host, params, exp.stiffness_spec(params, us), us, seed, nd) > 0


def test_constants_are_exact_double_literals():
    for v in (0.1, 1.0466452593966644, 142857142.85714287, 5e-324, 1.7976931348623157e308):
        lit = fortran_double(v)
        assert float(lit.replace("D", "e")) == v


# -- longer runs (slow) -------------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("key", ["default", "soft", "sharp", "tab", "tab_flat"])
@pytest.mark.parametrize("units", ["SI", "mm-t-s"])
@settings(
    max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(case=FRIC_CASES, vseed=st.integers(0, 2**32 - 1), nsv=st.sampled_from([1, 2, 3]))
def test_all_targets_agree_long(tmp_path_factory, key, units, case, vseed, nsv):
    seed, nd, nstatv = case
    params, us = PARAM_SETS[key], UNITS[units]
    kt_spec = exp.stiffness_spec(params, us)
    host, _ = lib_for(tmp_path_factory, "abaqus-fric", key, units)
    run_fric(host, params, kt_spec, us, seed, nd, nstatv)
    host, _ = lib_for(tmp_path_factory, "abaqus-vfric", key, units)
    run_vfric(host, params, us, vseed, nsv)
    host, _ = lib_for(tmp_path_factory, "lsdyna", key, units)
    run_generic(host, params, kt_spec, us, seed, nd)
