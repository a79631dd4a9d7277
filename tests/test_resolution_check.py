"""The resolution check compares the law the parameter file runs (probe h53, findings 1-2).

A calibration that runs the tabulated forms is checked against an independent calibration
at half the grid (same load levels): the check's ``mu_eff`` is the two parameter files'
``mu_eff``, and Eq. 24 / Eq. 25 appear only beside it, labelled not run.
"""

import dataclasses

import numpy as np
import pytest

from frictionlaw import alpha_first
from halfspace_calib.pipeline.calibration import Scene, calibrate
from halfspace_calib.pipeline.law import forms as _forms
from halfspace_calib.pipeline.sweep.resolution import RESOLUTION_TOL, resolution_check

#: grid 16 against 8: the check's sweeps take about a second
SCENE = Scene(
    grid=16,
    periodic=False,
    resolution_check=True,
    first_loading_form="tabulated",
    reload_form="tabulated",
    workers=1,
)


@pytest.fixture(scope="module")
def runs():
    fine = calibrate(SCENE, progress=False)
    half = calibrate(  # what the check does, through the public calibration
        dataclasses.replace(
            SCENE,
            grid=8,
            resolution_check=False,
            pressures=tuple(lv.p_hist for lv in fine.sweeps.levels),
            adaptive_levels=False,
        ),
        progress=False,
    )
    return fine, half


def test_tabulated_law_compared_with_its_own_mu_eff(runs):
    fine, half = runs
    rc = fine.resolution
    assert fine.params.first_loading_form == "tabulated" == fine.params.reload_form
    assert rc.forms == {"first_loading": "tabulated", "reload": "tabulated"}
    # the running law's mu_eff at both grids: m k alpha_0 / p_0 of each file's table
    a, b, d = rc.params["mu_eff"]
    assert a == pytest.approx(fine.params.mu_eff, rel=1e-12)
    assert b == pytest.approx(half.params.mu_eff, rel=1e-12)
    want = abs(half.params.mu_eff - fine.params.mu_eff) / fine.params.mu_eff
    assert d == pytest.approx(want, rel=1e-12)
    # Eq. 24's Coulomb slope differs from the tabulated one: it is reported beside, not run
    eq24 = [f.first_fits["eq24"] for f in runs]
    mu24 = [f.params.m * f.params.k * e.C1 / f.params.H for f, e in zip(runs, eq24, strict=True)]
    assert abs(mu24[0] - fine.params.mu_eff) > 0.01 * fine.params.mu_eff
    assert rc.beside["mu_eff"][:2] == pytest.approx(tuple(mu24), rel=1e-12)
    assert rc.beside["C1"][:2] == pytest.approx((eq24[0].C1, eq24[1].C1), rel=1e-12)
    assert set(rc.params) == {"mu_eff"} and {"C1", "n1", "C2", "n2"} <= set(rc.beside)
    # the table's contact ratio: the two files' first loading at the fine run's levels
    p, _ = fine.sweeps.loading
    a1, b1 = alpha_first(p, fine.params), alpha_first(p, half.params)
    assert rc.law_alpha["first_loading"] == pytest.approx(np.max(np.abs(b1 - a1) / a1))
    # the warning names the running law's numbers only, never a form beside it
    moved = d > RESOLUTION_TOL or max(rc.law_alpha.values()) > RESOLUTION_TOL
    assert bool(rc.warning) == (moved or rc.alpha_change > RESOLUTION_TOL)
    assert "C1" not in rc.warning and "n2" not in rc.warning
    if d > RESOLUTION_TOL:
        assert f"mu_eff {100 * d:.1f} %" in rc.warning
    rec = rc.as_dict()
    assert rec["params"]["mu_eff"] == list(rc.params["mu_eff"]) and "n1" in rec["beside_not_run"]


def test_named_forms_compared_when_they_run(runs):
    """Eq. 24 and Eq. 25 running: ``C1, n1, C2, n2`` are the law's, nothing beside."""
    fine, half = runs
    scene = dataclasses.replace(fine.scene, first_loading_form="eq24", reload_form="paper")
    p, alpha = fine.sweeps.loading
    law = _forms.fit_law(scene, p, alpha, fine.sweeps.reload_curves(), heldout=False)
    rc = resolution_check(scene, law, fine.sweeps)
    assert not rc.skipped and rc.beside == {}
    assert set(rc.params) == {"mu_eff", "C1", "n1", "C2", "n2"}
    c1 = (fine.first_fits["eq24"].C1, half.first_fits["eq24"].C1)
    assert rc.params["C1"][:2] == pytest.approx(c1, rel=1e-12)
    mk_h = fine.params.m * fine.params.k / fine.params.H
    assert rc.params["mu_eff"][:2] == pytest.approx((mk_h * c1[0], mk_h * c1[1]), rel=1e-12)
