"""The upper-bound limit analysis of the flattening studies (benchmarks/flattening_limit.py), held
to the rigid-plastic problem's exact answers: a flat strip stretched without pressure dissipates
exactly the uniform stretch's ``2 k`` per area, and a flat punch on the strip collapses at
Prandtl's plane-strain pressure ``(2 + pi) k`` (bounded below it, unbounded above it, within the
discretisation's few per cent). ``flattening_limit_law.py``'s flank reading gives the homogeneous
stretch's convection of the slope, ``-2 s``, on a field that is homogeneous; the unilateral plateau
is a relaxation of the tied one. ``flattening_limit_rows.py``'s edge slope of a profile is the
harmonic mean at its bearing level, and the curve that carries it is exact for constant rates and
resolves a profile whose edge slope varies faster than the strain step."""

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


def _load(name):
    if str(BENCH) not in sys.path:
        sys.path.insert(0, str(BENCH))
    spec = importlib.util.spec_from_file_location(name, BENCH / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def limit():
    return _load("flattening_limit")


def test_flat_strip_dissipates_the_uniform_stretch(limit):
    f = limit.limit_field(0.0, 0.0, 0.0, 8, 8, 12)
    # exact: the uniform stretch is optimal (so are the lattice's fields of F2a, at the same cost)
    assert f["dissipation_ratio"] == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize(("factor", "bounded"), [(0.95, True), (1.25, False)])
def test_flat_punch_collapses_at_prandtls_pressure(limit, factor, bounded):
    A = 0.25  # the plateau on a flat strip (s = 0) is a flat punch of half-width A
    if bounded:
        f = limit.limit_field(factor * limit.H * A, A, 0.0, 12, 16, 12)
        assert f["extra_sinking"] > 0.0
    else:
        with pytest.raises(RuntimeError, match="did not solve"):
            limit.limit_field(factor * limit.H * A, A, 0.0, 12, 16, 12)


def test_flank_reading_of_a_homogeneous_field(monkeypatch):
    law = _load("flattening_limit_law")
    s, A = 0.1, 0.4
    x = np.linspace(A, 1.0, 13)
    z = -s * (x - A)
    surface = np.column_stack([x, x, -(z + 4.0)])  # u = x, w = -(z + depth): the stretch alone

    def homogeneous(*args, **kwargs):
        return {
            "surface": surface,
            "W": -4.0,
            "flank_element": 0.05,
            "dA_de_1": 0.0,
            "dA_de_2": 0.0,
            "dissipation_ratio": 1.0,
            "seconds": 0.0,
        }

    monkeypatch.setattr(law, "limit_field", homogeneous)
    r = law.rates(0.1, A, s, 12, 16, 12)
    assert r["dA_de"] == pytest.approx(0.0, abs=1e-12)  # the stretch carries the edge along
    assert r["ds_de"] == pytest.approx(-2 * s, rel=1e-12)
    assert math.isfinite(r["dA_de"])


def test_unilateral_plateau_is_a_relaxation_that_keeps_the_tied_optimum(limit):
    """Letting plateau nodes sink away from the tool (``w_i <= W``) relaxes the tied plateau: its
    optimum is no worse, and at a low-pressure state of a steep wedge it is the same field
    (docs/flattening_studies.md: the tied plateau of the studies is not what sets their rates)."""
    p, A, s = 0.05 * limit.H, 0.2, 0.16
    tied = limit.limit_field(p, A, s, 12, 16, 12, 6)
    free = limit.limit_field(p, A, s, 12, 16, 12, 6, unilateral=True)

    area = limit.DEPTH - 0.5 * s * (1 - A) ** 2  # the half cell less the valley

    def objective(f):  # the dissipation less the pressure's work (what the programme minimises)
        return 2 * area * f["dissipation_ratio"] + p * f["W"]

    assert objective(free) <= objective(tied) + 1e-6
    assert free["dissipation_ratio"] == pytest.approx(tied["dissipation_ratio"], abs=1e-3)
    assert free["W"] == pytest.approx(tied["W"], abs=1e-2)
    x, _, w = free["surface"].T
    assert np.ptp(w[x <= A + 1e-9]) < 1e-2  # the plateau hardly leaves the tool


@pytest.mark.parametrize("sides", [12, 48])
def test_yield_polygon_is_inscribed(limit, sides):
    """The polygon takes exactly ``1 - cos(pi / sides)`` off the dissipation of a homogeneous
    strain rate midway between two of its directions, and nothing off one along a direction: the
    error that decides the low-pressure rates (docs/flattening_studies.md, "The yield polygon")."""
    lp = limit.program(0.0, 0.0, 0.0, 6, 6, sides)
    P, n = lp["P"], lp["n"]
    for phi, factor in ((math.pi / sides, math.cos(math.pi / sides)), (0.0, 1.0)):
        a, b = math.cos(phi), math.sin(phi)  # d_xx - d_zz = a, 2 d_xz = b: norm 1
        u, w = 0.5 * a * P[:, 0] + b * P[:, 1], -0.5 * a * P[:, 1]
        bounds = list(lp["bounds"])
        bounds[:n] = [(v, v) for v in u]
        bounds[n : 2 * n] = [(v, v) for v in w]
        res = limit.solve({**lp, "bounds": bounds}, lp["cost"])
        assert res.fun == pytest.approx(factor * lp["area"].sum(), rel=1e-7)


def test_band_holds_the_optimum_and_widens():
    """The range of both rates over near-optimal fields contains the optimum's and widens with
    the dissipation allowed above it."""
    law = _load("flattening_limit_law")
    state = (0.15, 0.4, 0.17, 8, 12, 12)
    r = law.rates(*state)
    narrow, wide = (law.band(*state, delta) for delta in (1e-5, 1e-3))
    for key in ("dA_de", "ds_de"):
        assert narrow[key] == pytest.approx(r[key], rel=1e-5, abs=1e-6)
        assert wide[f"{key}_lo"] <= narrow[f"{key}_lo"] + 1e-6
        assert narrow[f"{key}_lo"] <= r[key] + 1e-6 <= narrow[f"{key}_hi"] + 2e-6
        assert narrow[f"{key}_hi"] <= wide[f"{key}_hi"] + 1e-6
    assert wide["dA_de_hi"] - wide["dA_de_lo"] > narrow["dA_de_hi"] - narrow["dA_de_lo"]


def test_edge_slope_is_the_harmonic_mean_at_the_bearing_level():
    law = _load("flattening_limit_rows")
    # one flank of a wedge: its own slope at every contact fraction
    x, z = np.array([0.0, 1.0]), np.array([0.1, 0.0])
    for A in (0.05, 0.5, 0.95):
        assert law.edge_slope(x, z, A) == pytest.approx(0.1, rel=1e-9)
    # a plateau-free bump with flanks 0.2 (rising) and 0.05 (falling), and a lower one with 0.1
    x = np.array([0.0, 0.5, 2.5, 3.0, 4.0, 5.0])
    z = np.array([0.0, 0.1, 0.0, 0.0, 0.05, 0.0])
    h = law.bearing_level(x, z, 0.2)
    above = np.interp(np.linspace(0, 5, 500001), x, z) > h
    assert above.mean() == pytest.approx(0.2, abs=1e-5)
    assert h > 0.05  # only the high bump: its two edges, 0.2 and 0.05
    assert law.edge_slope(x, z, 0.2) == pytest.approx(2 / (1 / 0.2 + 1 / 0.05), rel=1e-9)
    h = law.bearing_level(x, z, 0.5)
    assert h < 0.05  # both bumps: four edges
    want = 4 / (1 / 0.2 + 1 / 0.05 + 2 / 0.05)
    assert law.edge_slope(x, z, 0.5) == pytest.approx(want, rel=1e-9)


def test_curve_follows_the_profile_and_turns_the_flank(limit):
    # dA / d eps = 1 and d ln s / d eps = -1: A = A0 + eps, s = exp(-eps) slope_of(A)
    def rate(A, s):
        return 1.0, -s

    def shape(A):
        return 0.05 + 0.1 * A

    out = limit.curve(rate, 0.1, None, [0.05, 0.2], 0.0005, slope_of=shape)
    for (A, s), e in zip(out, (0.05, 0.2), strict=True):
        assert A == pytest.approx(0.1 + e, abs=1e-12)
        assert s == pytest.approx(math.exp(-e) * shape(0.1 + e), rel=1e-7)
    # a constant shape is the wedge's curve
    wedge = limit.curve(rate, 0.1, 0.07, [0.05, 0.2], 0.0005)
    same = limit.curve(rate, 0.1, None, [0.05, 0.2], 0.0005, slope_of=lambda A: 0.07)
    assert wedge == same


def test_curve_resolves_a_profile_that_varies_faster_than_its_step(limit):
    """A profile's edge slope varies on the scale of its samples; ``dA_max`` keeps a step within
    it. Growth ``c / s`` over an edge slope alternating between 0.01 and 0.04 every 0.005 of
    ``A`` crosses a band in ``s 0.005 / c`` of strain: exact, the mean slope's curve."""
    c, width = 2.0, 0.005

    def shape(A):
        return 0.01 if math.floor(A / width) % 2 == 0 else 0.04

    def rate(A, s):
        return c / s, 0.0

    strains = [0.002, 0.005]
    # a pair of bands takes 0.005 (0.01 + 0.04) / c of strain: A = c e / 0.025 at whole pairs
    exact = [c * e / 0.025 for e in strains]
    fine = limit.curve(rate, 0.0, None, strains, 0.0005, slope_of=shape, dA_max=2e-5)
    coarse = limit.curve(rate, 0.0, None, strains, 0.0005, slope_of=shape)
    for (A, _), a in zip(fine, exact, strict=True):
        assert A == pytest.approx(a, abs=2e-4)
    # the strain step alone (A moves by up to 0.1 a step, twenty bands) does not resolve it
    assert max(abs(A - a) for (A, _), a in zip(coarse, exact, strict=True)) > 0.01


def test_a_deformed_flank_that_is_straight_is_the_straight_cell(limit):
    """``top_of`` drawing the straight flank gives the straight cell's mesh and optimum; a
    flank bent below the line changes the optimum (the flank is read, not ignored)."""
    A, s = 0.3, 0.12
    P0, six0, xs0, top0 = limit.cell(A, s, 8, 8, 5)
    P1, six1, xs1, top1 = limit.cell(A, s, 8, 8, 5, top_of=lambda x: -s * (x - A))
    np.testing.assert_array_equal(six0, six1)
    np.testing.assert_allclose(P1, P0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(top1, top0, rtol=0, atol=1e-15)
    p = 0.2 * limit.H
    f0 = limit.limit_field(p, A, s, 8, 8, 12, 5)
    f1 = limit.limit_field(p, A, s, 8, 8, 12, 5, top_of=lambda x: -s * (x - A))
    assert f1["W"] == pytest.approx(f0["W"], abs=1e-9)
    assert f1["dissipation_ratio"] == pytest.approx(f0["dissipation_ratio"], abs=1e-9)
    bent = limit.limit_field(
        p, A, s, 8, 8, 12, 5, top_of=lambda x: -s * np.maximum(x - A, 0.0) ** 0.5
    )
    _, _, _, top2 = limit.cell(A, s, 8, 8, 5, top_of=lambda x: -s * np.maximum(x - A, 0.0) ** 0.5)
    assert np.all(top2[xs0 > A] < top0[xs0 > A])
    assert abs(bent["dissipation_ratio"] - f0["dissipation_ratio"]) > 1e-4


def test_table_between_pressures_meets_its_ends():
    """``flattening_limit_pressure.Between`` at a neighbour's pressure is that neighbour's table
    (every scheme, at states inside and outside its grid), and halfway in ``ln p`` with the same
    ``A`` is the mean of the two."""
    lim = _load("flattening_limit_pressure")
    rows = lim._read(lim.TABLE)
    lo, hi = 0.1, 0.2
    r_lo, r_hi = lim.Rates(rows, lo), lim.Rates(rows, hi)
    for scheme in lim.SCHEMES:
        for A, s in ((0.3, 0.05), (0.5, 0.012), (0.95, 0.19)):
            np.testing.assert_allclose(lim.Between(rows, lo, hi, lo, scheme)(A, s), r_lo(A, s))
            np.testing.assert_allclose(lim.Between(rows, lo, hi, hi, scheme)(A, s), r_hi(A, s))
    mid = math.sqrt(lo * hi)
    b = lim.Between(rows, lo, hi, mid, "same A, linear in ln p")
    for A, s in ((0.3, 0.05), (0.6, 0.1)):
        np.testing.assert_allclose(b(A, s), 0.5 * (np.array(r_lo(A, s)) + r_hi(A, s)))
    with pytest.raises(ValueError, match="scheme"):
        lim.Between(rows, lo, hi, mid, "same p")
