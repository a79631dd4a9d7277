"""The two-state law with the workpiece's edge slope (``flattening.edge_slope``, issue 43).

The block's edge-slope table makes the flank slope the law reads follow the surface's own
edges as the contact grows (``s = r E(A)``, ``r`` the flank's turn). Checked here: the block's
field, the NumPy model against an analytic limit (a constant table is the block's one slope),
the kernels against the NumPy model, zones, and the geometry of the table from a surface (a
wedge lattice, a sinusoid, ridges). The calibration's block is checked in
tests/test_flattening_limit.py, the exported routines in tests/test_export_flattening_limit.py,
tests/test_export_zones_flattening.py and, inside ccx, tests/test_calculix_flattening.py.
"""

import math

import numpy as np
import pytest
from test_flattening_limit_runtime import update

import frictionlaw as fl
from frictionlaw import _kernels_limit as KL
from frictionlaw._limit_table import edge_at
from frictionlaw.flattening import flattened_alpha, flattening_pressure
from frictionlaw.flattening_limit import edge_slope_at, limit_update
from halfspace_calib.pipeline.sweep.flattening_edges import (
    EDGE_POINTS,
    edge_slope_table,
    profile_edge_slopes,
)

H = 8e8
BASE = dict(m=0.5, sigma_y=H / 2.8, H=H, C1=1.05, n1=2.87, C2=7.44, n2=0.575)
#: a surface whose edges steepen with the contact fraction, as a measured row's mostly do
EDGE = tuple(float(v) for v in 0.02 + 0.08 * np.linspace(0.0, 1.0, 21) ** 1.5)


def law(edge=EDGE, slope=0.05, beta=1.0):
    flat = fl.Flattening(slope=slope, beta=beta, model="limit-analysis", edge_slope=edge)
    return fl.FrictionParams(**BASE, flattening=flat)


def grid():
    p = np.array([0.005, 0.02, 0.05, 0.1, 0.3, 0.6]) * H
    g = np.meshgrid(
        p, [0.0, 0.5, 2.0], [0.0, 0.2, 0.6], [0.0, 0.01, 0.05], [0.0, 1e-3, 0.01, 0.1],
        indexing="ij",
    )  # fmt: skip
    p, fac, af, sf, de = (a.ravel() for a in g)
    return p, fac * p, af, sf, de


def test_the_block_carries_the_table_and_refuses_what_it_cannot_read():
    P = law()
    doc = P.flattening.to_dict()
    assert doc["edge_slope"] == list(EDGE)
    assert fl.Flattening.from_dict(doc) == P.flattening
    assert "edge_slope" not in fl.Flattening(slope=0.05, model="limit-analysis").to_dict()
    with pytest.raises(ValueError, match="limit-analysis' only"):
        fl.Flattening(slope=0.05, edge_slope=EDGE)
    with pytest.raises(ValueError, match=r"2-1001 slopes .* got 1"):
        fl.Flattening(slope=0.05, model="limit-analysis", edge_slope=[0.05])
    with pytest.raises(ValueError, match=r"edge_slope\[1\] must be in \[1e-08, 10\]"):
        fl.Flattening(slope=0.05, model="limit-analysis", edge_slope=[0.05, -1.0])
    with pytest.raises(ValueError, match="must be a list"):
        fl.Flattening(slope=0.05, model="limit-analysis", edge_slope="0.05")
    # read as the kernels read it: linear between equally spaced fractions
    A = np.array([0.0, 0.025, 0.5, 0.999, 1.0])
    ref = np.interp(A, np.linspace(0, 1, len(EDGE)), EDGE)
    assert np.allclose(edge_slope_at(A, P), ref, rtol=1e-14)
    for a, r in zip(A, ref, strict=True):
        assert math.isclose(KL.edge_scalar(np.array(EDGE), a)[0], r, rel_tol=1e-14)


def test_a_constant_table_is_the_blocks_one_slope():
    """E(A) = s everywhere: the turn r = s / E carries the same flank as the slope itself (to
    rounding: exp(ln r) E against exp(ln s))."""
    p, ph, af, sf, de = grid()
    flat_one = law(edge=None, slope=0.05)
    flat_tab = law(edge=(0.05,) * 7, slope=0.05)
    a1, s1 = limit_update(af, sf, ph, p, de, flat_one)
    a2, s2 = limit_update(af, sf, ph, p, de, flat_tab)
    assert np.allclose(a1, a2, rtol=1e-12, atol=1e-14) and np.allclose(s1, s2, rtol=1e-11)
    assert np.any(a1 > af + 0.05)
    t1, d1, _ = update(flat_one, p, ph, af, sf, de)
    t2, d2, _ = update(flat_tab, p, ph, af, sf, de)
    assert np.allclose(t1, t2, rtol=1e-11) and np.allclose(d1, d2, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("parallel", [False, True])
def test_kernels_against_the_numpy_model(parallel):
    P = law()
    p, ph, af, sf, de = grid()
    tau, dtdp, st = update(P, p, ph, af, sf, de, parallel=parallel)
    a_ref, s_ref = limit_update(af, sf, np.maximum(ph, p), p, de, P)
    assert np.allclose(st.alpha_f_trial, a_ref, rtol=1e-13, atol=0)
    assert np.allclose(st.slope_f_trial, s_ref, rtol=1e-13, atol=0)
    # Eq. F5 on the NumPy states
    tau_ref = P.tau_max * flattened_alpha(p, ph, flattening_pressure(a_ref, P), P)
    full = (p < ph) & (fl.alpha_first(ph, P) >= 1.0)  # the law itself there (as one-state)
    np.testing.assert_allclose(tau[~full], tau_ref[~full], rtol=1e-9, atol=0)
    # the slope follows the table: a virgin node pressed at 0.6 H (the table's turn is small
    # there) ends near E(A) at its new fraction, not at the block's one slope
    v = (sf == 0) & (af == 0) & (de == 0.01) & (p == 0.6 * H) & (ph == 0)
    e_end = edge_at(np.array(EDGE), st.alpha_f_trial[v])
    assert np.allclose(st.slope_f_trial[v], e_end, rtol=0.1)
    assert np.all(np.abs(st.slope_f_trial[v] - 0.05) > 0.01)


def test_the_tangent_is_the_derivative_of_the_numpy_model():
    """d alpha/dp carried through the steps (with dE/dA) against a forward difference."""
    P = law()
    p, ph, af, sf, de = grid()
    load = (p >= ph) & (de > 0) & (p > 0.01 * H)
    p, ph, af, sf, de = p[load], ph[load], af[load], sf[load], de[load]
    tau, dtdp, st = update(P, p, ph, af, sf, de)
    dp = 1e-7 * p
    a0, _ = limit_update(af, sf, ph, p, de, P)
    a1, _ = limit_update(af, sf, ph, p + dp, de, P)
    fd = (a1 - a0) / dp
    inside = st.alpha_f_trial > fl.alpha_first(p, P) + 1e-6
    d_alpha = np.sign(tau) * dtdp / P.tau_max
    ok = inside & (st.alpha_f_trial < 0.999)
    assert ok.sum() > 30
    assert np.allclose(d_alpha[ok], fd[ok], rtol=2e-4, atol=1e-3 / H)


def test_zones_read_each_zones_table():
    """Two two-state zones with different tables and a one-state zone: each node is its zone's
    one-law update bit for bit."""
    a, b = law(), law(edge=tuple(reversed(EDGE)))
    one = fl.FrictionParams(**BASE, flattening=fl.Flattening(slope=0.05))
    zl = fl.ZonedLaw(("a", "b", "c"), tuple(fl.SBMFLaw(x) for x in (a, b, one)))
    p, ph, af, sf, de = grid()
    for z, P in enumerate((a, b)):
        tz, dz, sz = update(zl, p, ph, af, sf, de, zone=np.full(p.size, z))
        t1, d1, s1 = update(P, p, ph, af, sf, de)
        assert np.array_equal(tz, t1) and np.array_equal(dz, d1)
        assert np.array_equal(sz.slope_f_trial, s1.slope_f_trial)
    _, _, sa = update(zl, p, ph, af, sf, de, zone=np.zeros(p.size, int))
    _, _, sb = update(zl, p, ph, af, sf, de, zone=np.ones(p.size, int))
    assert np.abs(sa.alpha_f_trial - sb.alpha_f_trial).max() > 0.05


def test_curves_follow_the_surface():
    """A surface whose edges are shallow at first contact flattens faster than the wedge of
    its mean slope early on; at zero strain both are alpha1 exactly."""
    P_edge, P_mean = law(), law(edge=None, slope=float(np.mean(EDGE)))
    eps = np.array([0.0, 0.005, 0.02])
    for ph in (0.05, 0.2):
        c_edge = fl.flattening_curve(ph * H, eps, P_edge)
        c_mean = fl.flattening_curve(ph * H, eps, P_mean)
        assert c_edge[0] == c_mean[0] == fl.alpha_first(ph * H, P_edge)
        assert c_edge[1] > c_mean[1] + 0.01
        assert np.all(np.diff(c_edge) >= 0) and c_edge[-1] <= 1.0


def test_the_table_of_a_wedge_lattice_is_its_slope():
    x = np.arange(256) / 256
    h = (0.1 / 8 * np.abs(((x * 8) % 1) - 0.5) * 2)[:, None] * np.ones((1, 3))
    assert np.allclose(profile_edge_slopes(h, 1 / 256, True, 51), 0.2, rtol=1e-12)


def test_the_table_of_a_sinusoid_is_its_bins_mean():
    """z = a sin(k x): the bearing level of share A is a cos(pi A), crossed 2 / lambda times a
    length; over the bin [A1, A2] the harmonic mean slope is (k / pi) a (cos pi A1 - cos pi A2)
    / (A2 - A1) (to the sampling's piecewise-linear error)."""
    n_x, a = 4096, 1e-6
    x = np.arange(n_x) / n_x * 4e-4  # four wavelengths of 100 um
    k = 2 * np.pi / 1e-4
    h = (a * np.sin(k * x))[:, None]
    got = profile_edge_slopes(h, x[1] - x[0], True, 21)
    A = np.linspace(0, 1, 21)
    A1, A2 = np.clip(A - 0.025, 0, 1), np.clip(A + 0.025, 0, 1)
    ref = k / np.pi * a * (np.cos(np.pi * A1) - np.cos(np.pi * A2)) / (A2 - A1)
    assert np.allclose(got, ref, rtol=2e-3)


def test_ridges_take_the_blocks_quadratic_mean():
    """Ridges along y: the x profiles carry the slope, the y profiles none; their quadratic
    mean is s / sqrt(2), as the block's RMS slope combines them."""
    from halfspace_calib.topography.surface import Surface

    x = np.arange(128) / 128
    z = 1e-6 * np.abs(((x * 4) % 1) - 0.5) * 2  # slope 8e-6 / (1/128 m ...) per unit x
    s = Surface(np.repeat(z[:, None], 32, axis=1), dx=1e-5, dy=1e-5, periodic=True)
    table = edge_slope_table(s)
    slope = 1e-6 * 2 * 4 / (128 * 1e-5)  # dz/dx of the sawtooth
    assert len(table) == EDGE_POINTS
    assert np.allclose(table, slope / math.sqrt(2), rtol=1e-9)


def test_a_flat_topped_and_quantised_scan_gets_a_table_the_block_takes():
    """Heights rounded to steps (an instrument's resolution) and cut flat at the top (a
    skin-passed sheet): bins spanned by level segments alone are held at the floor, the block
    takes the table, and the law runs."""
    from halfspace_calib.pipeline.sweep.flattening_edges import EDGE_FLOOR
    from halfspace_calib.topography.surface import Surface

    rng = np.random.default_rng(5)
    h = rng.normal(size=(64, 64))
    h = np.fft.irfft2(np.fft.rfft2(h) * np.exp(-0.02 * np.arange(33)[None, :] ** 2), s=h.shape)
    h = np.minimum(h, np.quantile(h, 0.8))  # the top 20 % flat
    h = np.round(h / (h.std() / 8)) * (h.std() / 8) * 1e-6  # 8 steps per RMS height, in m
    table = edge_slope_table(Surface(h, dx=1e-6, dy=1e-6, periodic=True))
    assert len(table) == EDGE_POINTS and np.all(np.isfinite(table))
    assert min(table) >= EDGE_FLOOR and max(table) > 10 * EDGE_FLOOR
    P = law(edge=table, slope=0.05)
    assert np.all(np.diff(fl.flattening_curve(0.1 * H, [0.0, 0.01, 0.05], P)) >= 0)
    # a band of levels crossed only by a nearly level ramp (slope 1e-9): held at the floor
    z = np.r_[np.linspace(0.0, 1.0, 11), 1.0 + 1e-9 * np.arange(1, 101), np.linspace(1.1, 2.0, 10)]
    z = np.r_[z, z[::-1][1:-1]] * 1e-6
    ridge = Surface(np.repeat(z[:, None], 4, axis=1), dx=1e-6, dy=1e-6, periodic=True)
    raw = profile_edge_slopes(ridge.heights, 1e-6, True, 51)
    assert np.nanmin(raw) < 1e-6
    assert min(edge_slope_table(ridge)) == EDGE_FLOOR
