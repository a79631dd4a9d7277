"""The upper-bound limit analysis of the flattening studies (benchmarks/flattening_limit.py), held
to the rigid-plastic problem's exact answers: a flat strip stretched without pressure dissipates
exactly the uniform stretch's ``2 k`` per area, and a flat punch on the strip collapses at
Prandtl's plane-strain pressure ``(2 + pi) k`` (bounded below it, unbounded above it, within the
discretisation's few per cent). ``flattening_limit_law.py``'s flank reading gives the homogeneous
stretch's convection of the slope, ``-2 s``, on a field that is homogeneous; the unilateral plateau
is a relaxation of the tied one."""

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
    (docs/flattening.md: the tied plateau of the studies is not what sets their rates)."""
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
