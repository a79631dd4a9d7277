"""Zonal laws in the runtime (issue 42): ZonedLaw, its numba kernels against the NumPy oracle.

Each node runs its zone's law with its own ``p_hist``: the zoned kernels must give, node by
node, the NumPy oracle of that node's law (and the one-law kernels bitwise); a node that changes
zone keeps its ``p_hist`` and is evaluated with the new zone's law.
"""

import numpy as np
import pytest
from reload_tables import FIRST, STRONG

import frictionlaw as fl
from frictionlaw import _reference as ref

H = 800e6
A = fl.FrictionParams(m=0.6, sigma_y=H / 2.8, H=H, C1=1.2, n1=2.0, C2=3.0, n2=2.0)
B = fl.FrictionParams(m=0.9, sigma_y=H / 2.5, H=0.6 * H, C1=3.0, n1=1.5, C2=5.0, n2=1.0)
C = A.replace(reload_form="tabulated", reload_table=STRONG, first_loading_form="tabulated",
              first_loading_table=FIRST["bump"])  # fmt: skip
ZL = fl.ZonedLaw(
    ("die", "Rim", "flank", "land"),
    (fl.SBMFLaw(A), fl.SBMFLaw(B), fl.Coulomb(0.12), fl.SBMFLaw(C)),
)


def _oracle_tau(p, p_hist, zone):
    """The NumPy oracle of each node's law (zone 3, the tabulated forms: the one-law kernel)."""
    out = np.empty(p.size)
    for z, P in ((0, A), (1, B)):
        m = zone == z
        out[m] = ref.sbmf_shear(p[m], p_hist[m], P.tau_max, P.C1, P.n1, P.C2, P.n2, P.H)
    m = zone == 2
    out[m] = 0.12 * np.maximum(p[m], 0.0)
    m = zone == 3
    out[m] = fl.shear_limit(p[m], p_hist[m], C)
    return np.where(p > 0, out, 0.0)


def _case(rng, n):
    p = rng.uniform(-0.1, 1.4, n) * H
    p_hist = rng.uniform(0.0, 1.4, n) * H
    p_hist[: n // 5] = 0.0
    zone = rng.integers(0, ZL.n_zones, n)
    return p, p_hist, zone


def test_zoned_shear_is_each_zones_law():
    rng = np.random.default_rng(4)
    p, ph, zone = _case(rng, 4000)
    tau, dtau = ZL.shear_limit(p, ph, zone)
    np.testing.assert_allclose(tau, _oracle_tau(p, ph, zone), rtol=1e-11, atol=0)
    for z, law in enumerate(ZL.laws):  # the one-law kernels, bitwise
        m = zone == z
        t1, d1 = law.shear_limit(p[m], ph[m] if law.uses_history else 0.0)
        assert np.array_equal(tau[m], t1) and np.array_equal(dtau[m], d1)
    # the zones differ: the same node in another zone gives another shear
    other = ZL.shear_limit(p, ph, (zone + 1) % ZL.n_zones)[0]
    assert np.mean(np.abs(other - tau) > 1e-3 * np.abs(tau)) > 0.5


def test_parallel_equals_serial_and_scalars():
    rng = np.random.default_rng(5)
    p, ph, zone = _case(rng, 3000)
    s = ZL.shear_limit(p, ph, zone, parallel=False)
    q = ZL.shear_limit(p, ph, zone, parallel=True)
    assert all(np.array_equal(a, b) for a, b in zip(s, q, strict=True))
    t, d = ZL.shear_limit(3e8, 4e8, 1)
    assert isinstance(t, float) and t == fl.shear_limit(3e8, 4e8, B)
    assert ZL(3e8, 4e8, np.array([0, 1]))[1] == t


@pytest.mark.parametrize("d", [1, 2])
def test_traction_update_against_oracle(d):
    rng = np.random.default_rng(6)
    n = 3000
    p, ph, zone = _case(rng, n)
    du = rng.normal(size=(n, d)) * 1e-6
    t_old = rng.normal(size=(n, d)) * 2e7
    kt = rng.uniform(1e12, 1e14, n)
    state = fl.HistoryState(p_hist=ph)
    res = fl.traction_update(ZL, p, du, t_old, kt, state, zone=zone)
    tau = np.where(p > 0, _oracle_tau(p, ph, zone), np.nan)
    t_ref, st_ref = ref.traction_update(tau, du, t_old, kt)
    np.testing.assert_allclose(res.traction, t_ref, rtol=1e-11, atol=1e-6)
    assert np.array_equal(res.status, st_ref)
    assert {0, 1, 2} <= set(np.unique(res.status))
    # p_hist is the node's whatever its zone: trial max(p_hist, p), committed unchanged
    assert np.array_equal(state.p_hist_trial, np.maximum(ph, np.where(p > 0, p, 0.0)))
    assert np.array_equal(state.p_hist, ph)
    par = fl.traction_update(ZL, p, du, t_old, kt, fl.HistoryState(p_hist=ph), zone=zone,
                             parallel=True)  # fmt: skip
    assert np.array_equal(par.traction, res.traction) and np.array_equal(par.dt_dp, res.dt_dp)
    # each zone's nodes: the one-law update bitwise
    for z, law in enumerate(ZL.laws):
        m = zone == z
        one = fl.traction_update(law, p[m], du[m], t_old[m], kt[m], fl.HistoryState(p_hist=ph[m]))
        assert np.array_equal(one.traction, res.traction[m])
        assert np.array_equal(one.dt_dslip, res.dt_dslip[m])


def test_a_node_that_changes_zone_keeps_its_p_hist():
    """Loaded to 600 MPa under zone 0, unloaded to 200 MPa under zone 1: zone 1's Eq. 25."""
    state = fl.HistoryState(1)
    slip = np.array([1e-3])  # far beyond stick: the shear limit itself
    fl.traction_update(ZL, [600e6], slip, [0.0], 1e12, state, zone=[0])
    state.commit()
    assert state.p_hist[0] == 600e6
    r = fl.traction_update(ZL, [200e6], slip, [0.0], 1e12, state, zone=[1])
    want = fl.shear_limit(200e6, 600e6, B)
    assert r.traction[0] == pytest.approx(want, rel=1e-14)
    # not zone 1's first loading, not zone 0's reload
    assert abs(want - fl.shear_limit(200e6, 0.0, B)) > 0.01 * want
    assert abs(want - fl.shear_limit(200e6, 600e6, A)) > 0.01 * want


def test_names_trimmed_case_insensitive():
    assert ZL.index(" RIM ") == 1 and ZL.index("die") == 0
    assert ZL.law("LAND").params is C
    assert fl.zone_key("  Rim\t") == "RIM"
    with pytest.raises(ValueError, match="'tip' is none of this law's zones"):
        ZL.index("tip")


@pytest.mark.parametrize(
    "names, laws, match",
    [
        (("a", " A "), (fl.Coulomb(0.1), fl.Coulomb(0.2)), "must differ"),
        (("a", "  "), (fl.Coulomb(0.1), fl.Coulomb(0.2)), "must not be empty"),
        (("a",), (fl.Coulomb(0.1), fl.Coulomb(0.2)), "as many"),
        ((), (), "as many"),
        (("a",), (A,), "must be a Coulomb"),
        ((3,), (fl.Coulomb(0.1),), "must be a string"),
    ],
)
def test_bad_zoned_law_refused(names, laws, match):
    with pytest.raises(ValueError, match=match):
        fl.ZonedLaw(names, laws)


@pytest.mark.parametrize(
    "law, zone, match",
    [
        (ZL, None, "zone is required"),
        (fl.SBMFLaw(A), [0, 0], "applies to a ZonedLaw only"),
        (ZL, [0, 4], r"in \[0, 3\]"),
        (ZL, [0, -1], r"in \[0, 3\]"),
        (ZL, [0.0, 1.0], "integer zone ids"),
        (ZL, [True, False], "integer zone ids"),
        (ZL, [0, 1, 2], r"shape \(2,\)"),
    ],
)
def test_bad_zone_ids_refused(law, zone, match):
    with pytest.raises(ValueError, match=match):
        fl.traction_update(law, [1e8, 2e8], [1e-6, 1e-6], [0.0, 0.0], 1e12, zone=zone)
