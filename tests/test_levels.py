"""Load levels from the model's answer (issue 39, halfspace_calib.pipeline.sweep.levels).

The refinement is driven here by known curves instead of the solver (a ``run_round`` that
evaluates them), so that what it must do is exact: a first loading the tabulated form follows
exactly (a power law: linear in ln alpha over ln p) with reload curves of one Eq. 25 is not
refined past the checks; an early full contact gets at least 4 levels below alpha 0.99 and at
most 3 at alpha >= 0.995; a kink is bracketed more finely than the smooth rest. One small real
calibration checks that the plan is what the sweeps computed and what the summary reports.
"""

import dataclasses
import math

import numpy as np
import pytest

from frictionlaw import alpha_reload
from halfspace_calib.pipeline.calibration import Scene, calibrate
from halfspace_calib.pipeline.law.fit import _law
from halfspace_calib.pipeline.sweep import levels as L
from halfspace_calib.pipeline.sweep.sweeps import LevelResult, SolveRecord

H = 800e6


def _rec(p, alpha):
    return SolveRecord(p, float(alpha), 10, True, 1e-9, "converged", H, 0.0, 0.0)


def _runner(first, scene, calls, C2=30.0, n2=1.0):
    """A ``run_round`` evaluating ``first(p)`` and the paper's continuous Eq. 25 below it."""

    def run_round(ps):
        calls.append(sorted(ps))
        out = {}
        for p in ps:
            lv = LevelResult(p, _rec(p, first(p)))
            if p >= scene.reload_from:
                a1 = first(p)
                # Eq. 25 scaled by the level's own first loading (C1 chosen so Eq. 24 meets it)
                law = _law(H, 1.0, 1.0, C2, n2, True, ("tabulated", _table(first, p)))
                for f in sorted(scene.reload_fractions):
                    a = float(alpha_reload(f * p, p, law))
                    lv.reload.append(_rec(f * p, min(a, a1)))
            out[p] = lv
        return out

    return run_round


def _table(first, p_hist):
    from frictionlaw.first_loading import FirstLoadingTable

    ps = (p_hist / 2, p_hist)
    return FirstLoadingTable(p=ps, alpha=tuple(first(q) for q in ps))


def test_power_law_not_refined_past_the_checks():
    """alpha = (p / H) ** 0.8 is exact for the tabulated form: the grid and its midpoints only."""
    scene = Scene(grid=16)
    calls = []
    res, plan = L.adaptive_levels(scene, _runner(lambda p: (p / H) ** 0.8, scene, calls))
    assert plan.adaptive
    assert calls[0] == [10e6, 100e6, 760e6]  # the ends and reload_from
    mids = sorted({math.sqrt(10e6 * 100e6), math.sqrt(100e6 * 760e6)})
    assert calls[1] == pytest.approx(mids)
    # the check of 276 MPa had two other histories: both halves checked once more, then settled
    top = math.sqrt(100e6 * 760e6)
    assert calls[2] == pytest.approx([math.sqrt(100e6 * top), math.sqrt(top * 760e6)])
    assert len(calls) == 3, plan.lines()
    assert plan.pressures == tuple(sorted(res))
    assert [r.reason for r in plan.levels].count("initial grid") == 3
    assert sum("within tolerance" in d for d in plan.decisions) == 3, plan.lines()
    assert sum("fewer than 3 other reload histories" in d for d in plan.decisions) == 1


def test_early_full_contact():
    """alpha 0.7 at 10 MPa, 1 by about 45 MPa: >= 4 levels below 0.99, <= 3 at >= 0.995."""

    def first(p):
        return min(1.0, 0.7 * (p / 10e6) ** 0.24)

    scene = Scene(grid=16)
    res, plan = L.adaptive_levels(scene, _runner(first, scene, []))
    a = np.array([first(p) for p in plan.pressures])
    assert np.sum(a < 0.99) >= 4, plan.lines()
    assert np.sum(a >= 0.995) <= 3, plan.lines()
    assert any("full contact" in d for d in plan.decisions)
    assert max(plan.pressures) == 760e6  # the range's top is always computed


def test_bump_is_bracketed():
    """A bump of alpha / (p / H) about 250 MPa (issue 37's) gets levels nearer than 1.25x."""

    def first(p):
        return min(1.0, p / H * (1.02 + 0.3 * math.exp(-((math.log(p / 250e6) / 0.3) ** 2))))

    scene = Scene(grid=16, reload_fractions=(0.5, 0.9))
    _, plan = L.adaptive_levels(scene, _runner(first, scene, []))
    ps = np.array(plan.pressures)
    assert any("refined at" in d for d in plan.decisions), plan.lines()
    near = np.sort(np.abs(np.log(ps / 250e6)))[:2]
    assert (near < math.log(1.25)).all(), plan.lines()
    low = ps[ps < 100e6]
    assert len(low) <= 3  # the smooth low range is not refined: 10, 31.6 MPa
    assert len(ps) <= L.MAX_LEVELS


def test_scene_switch():
    assert Scene(grid=16).adaptive_levels is True
    assert Scene(grid=16, pressures=(1e8, 2e8, 3e8)).adaptive_levels is False
    assert Scene(grid=16, pressures="paper").adaptive_levels is False
    with pytest.raises(ValueError, match="adaptive_levels must be"):
        Scene(grid=16, adaptive_levels="yes")


def test_given_levels_are_computed_as_given():
    scene = Scene(grid=16, pressures=(20e6, 100e6, 300e6, 500e6), reload_fractions=(0.3, 0.6))
    plan = L.fixed_plan(scene)
    assert plan.pressures == scene.pressures and not plan.adaptive
    assert "no refinement" in plan.lines()[0]


def test_calibration_reports_its_levels():
    """A real small run: the sweeps are the plan's levels, the summary and lines say why."""
    scene = Scene(grid=24, reload_fractions=(0.25, 0.5, 0.9), heldout_tol=0.2)  # few levels
    cal = calibrate(scene, progress=False)
    plan = cal.sweeps.plan
    assert plan.adaptive
    assert plan.pressures == tuple(lv.p_hist for lv in cal.sweeps.levels)
    hist = [lv.p_hist for lv in cal.sweeps.levels if lv.reload]
    assert hist == [r.p for r in plan.levels if r.reload]
    assert min(hist) == 100e6 and all(p >= 100e6 for p in hist)
    s = cal.summary()["levels"]
    assert s["adaptive"] and len(s["levels"]) == len(plan.levels)
    assert s["tol_first"] == pytest.approx(cal.scene.heldout_tol / 10)
    assert plan.lines()[0].startswith(f"load levels: {len(plan.levels)} computed")
    # the resolution check and several samples compute given levels: replace() keeps them so
    fixed = dataclasses.replace(cal.scene, pressures=plan.pressures, adaptive_levels=False)
    assert L.fixed_plan(fixed).pressures == plan.pressures


def test_cli_pressures_are_given_levels():
    """``--pressures`` is computed as given, also when it lists the default levels."""
    from halfspace_calib.cli import build_parser, scene_from_args
    from halfspace_calib.pipeline.sweep.scene import DEFAULT_PRESSURES

    default = ",".join(f"{p:g}" for p in DEFAULT_PRESSURES)
    given = scene_from_args(build_parser().parse_args(["--pressures", default]))
    assert given.pressures == DEFAULT_PRESSURES and given.adaptive_levels is False
    assert scene_from_args(build_parser().parse_args([])).adaptive_levels is True


def test_samples_share_the_first_samples_levels():
    """The pooled curves group by p_hist: every sample computes the first sample's levels."""
    from halfspace_calib.pipeline.band.samples import SampleSpec, load_samples, run_samples

    scene = Scene(grid=16, reload_fractions=(0.5, 0.9), heldout_tol=0.2)
    out = run_samples(load_samples(scene, SampleSpec(patches=4))[:2], progress=False)
    first, second = (out.calibrations[s.name] for s in out.samples)
    assert first.sweeps.plan.adaptive and not second.sweeps.plan.adaptive
    assert second.sweeps.plan.pressures == first.sweeps.plan.pressures
    assert [lv.p_hist for lv in second.sweeps.levels if lv.reload] == [
        lv.p_hist for lv in first.sweeps.levels if lv.reload
    ]


def test_early_full_contact_of_a_measured_pair():
    """metropro-1.dat against itself (alpha 0.66 at 10 MPa, 1 from 75 MPa), the real solver."""
    from pathlib import Path

    f = str(Path(__file__).parent / "data" / "metropro-1.dat")
    scene = Scene(workpiece=f, tool=f, grid=48, resolution_check=False)
    cal = calibrate(scene, progress=False)
    a = np.array([lv.loading.alpha for lv in cal.sweeps.levels])
    assert a[0] < 0.7 and a[-1] == 1.0
    assert np.sum(a < 0.99) >= 4 and np.sum(a >= 0.995) <= 3, cal.sweeps.plan.lines()
    assert any("full contact" in d for d in cal.sweeps.plan.decisions)
    assert not cal.problems()


def test_two_histories_of_two_reloads_have_no_extrapolation():
    """Two histories of 2 reloads (adaptive levels in full contact, two fractions): Eq. 25
    refitted without the top one has 2 points, too few for C2, n2: the extrapolation is not
    reported (it raised ValueError out of calibrate)."""
    from halfspace_calib.pipeline.law import heldout
    from halfspace_calib.pipeline.law.fit import ReloadCurve, fit_reload

    curves = [
        ReloadCurve(100e6, np.array([50e6, 90e6]), np.array([0.98, 1.0])),
        ReloadCurve(760e6, np.array([380e6, 684e6]), np.array([1.0, 1.0])),
    ]
    fit = fit_reload(curves, H, 1.0, 16.0, continuous=True)
    err = heldout.reload_errors(curves, H, 1.0, 16.0, fit, continuous=True)
    assert err.extrapolation is None and err.heldout == () and not err.decides_heldout


def _ahead_runner(inner, computed):
    """``inner`` (a one-argument ``run_round``) with ``run_sweeps``' look-ahead: levels asked for
    ahead are computed with the round and kept until a round asks for them."""
    kept = {}

    def run_round(ps, ahead=()):
        new = [p for p in list(ps) + list(ahead) if p not in kept]
        computed.append(sorted(new))
        kept.update(inner(new))
        return {p: kept.pop(p) for p in ps if p in kept}

    return run_round, kept


@pytest.mark.parametrize(
    "first",
    [lambda p: (p / H) ** 0.8, lambda p: min(1.0, 0.7 * (p / 10e6) ** 0.24)],
    ids=["power-law", "early-full-contact"],
)
def test_look_ahead_changes_nothing_but_the_rounds(first):
    """``ahead=True`` (parallel sweeps) computes the first midpoints with the initial grid: the
    same levels, decisions and results in one round fewer; a midpoint not asked for is dropped."""
    scene = Scene(grid=16)
    calls, computed = [], []
    res0, plan0 = L.adaptive_levels(scene, _runner(first, scene, calls))
    run_round, kept = _ahead_runner(_runner(first, scene, []), computed)
    res1, plan1 = L.adaptive_levels(scene, run_round, ahead=True)
    assert plan1 == plan0 and sorted(res1) == sorted(res0)
    for p in res0:
        assert res1[p].loading.alpha == res0[p].loading.alpha
        assert [r.alpha for r in res1[p].reload] == [r.alpha for r in res0[p].reload]
    rounds = [c for c in computed if c]  # a round whose levels were all computed ahead is empty
    asked = sum(len(c) for c in calls)
    assert sum(len(c) for c in rounds) == asked + len(kept)  # kept: computed, never asked for
    if not kept:  # every first midpoint was asked for: one round fewer
        assert rounds[0] == pytest.approx(sorted(calls[0] + calls[1]))
        assert len(rounds) == len(calls) - 1
    else:  # early full contact: the midpoint between two full-contact levels was not asked for
        assert [round(p / 1e6, 1) for p in kept] == [275.7] and first(min(kept)) == 1.0
