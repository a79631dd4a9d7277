"""The preparation chain of a measured surface (halfspace_calib/topography/chain.py).

Each stage returns the surface and its lines of provenance; run stage by stage with the scene's
parameters, the chain gives the loader's solver surface to the last digit, with the same steps.
The plan (halfspace_calib/pipeline/sweep/surface_plan.py) decides every parameter and refuses bad input
before any stage runs; the run only runs it.
"""

import dataclasses

import numpy as np
import pytest
from realfiles import real_file

from halfspace_calib.pipeline.calibration import Scene
from halfspace_calib.pipeline.sweep.scene_surfaces import load_scene_surfaces, run_plan
from halfspace_calib.pipeline.sweep.surface_plan import plan_surfaces
from halfspace_calib.topography import Surface, chain, filters, read_raw, rq
from sbmf_cli import ParameterError


def test_the_chain_by_hand_is_the_loader():
    path = real_file("metropro-1.dat")
    scene = Scene(workpiece=str(path), grid=64, resolution_check=False)
    loaded = load_scene_surfaces(scene)
    rec = loaded.files[0]
    h, dx, dy, prov = read_raw(path)
    h, steps, bad = chain.fill_holes(h, scene.max_undefined, path)
    s = Surface(h, dx, dy, provenance=prov, periodic=False)
    s, levelled = chain.level_scan(s)
    s, filtered = chain.filter_scan(s, loaded.lambda_s, loaded.lambda_c)
    s, resampled = chain.crop_resample(s, rec.crop_size, loaded.grid, loaded.lambda_s)
    s, last = chain.level_patch(s)
    assert bad == rec.undefined_points
    np.testing.assert_array_equal(s.heights, loaded.workpiece.heights)
    assert steps + levelled + filtered + resampled + last == rec.steps
    assert rq(s) == pytest.approx(rec.rq_patch, rel=1e-12)


def test_each_stage_says_what_it_did_and_only_that():
    rng = np.random.default_rng(3)
    h = rng.normal(0.0, 1e-6, (40, 40)) + np.linspace(0, 1e-5, 40)[:, None]
    s = Surface(h, 1e-6, 1e-6, periodic=False)
    out, steps = chain.level_scan(s)
    assert steps == ("levelled: least-squares plane removed over the whole scan",)
    assert rq(out) < rq(s)  # the tilt is gone
    same, none = chain.filter_scan(out, 0.0, None)
    assert same is out and none == ()
    filtered, (line,) = chain.filter_scan(out, 5e-6, None)
    assert "lambda_s = 5 um" in line and rq(filtered) < rq(out)
    whole, none = chain.crop_resample(out, 40e-6, 40, 0.0)
    assert whole is out and none == ()  # already the square and the grid: nothing done
    cropped, lines = chain.crop_resample(s, 20e-6, 10, 0.0)
    assert cropped.shape == (10, 10) and cropped.dx == pytest.approx(2e-6)
    assert lines[0].startswith("cropped from 40 x 40 um") and "area-averaged" in lines[1]
    interp, lines = chain.crop_resample(filtered, 40e-6, 80, 5e-6)
    assert interp.shape == (80, 80) and "band-limited" in lines[-1]


def test_holes_are_filled_up_to_the_limit_and_refused_beyond_it():
    h = np.ones((10, 10))
    h[2, 3] = h[5, 5] = np.nan
    filled, (line,), bad = chain.fill_holes(h, 0.05, "scan.dat")
    assert bad == 2 and np.isfinite(filled).all() and "filled 2 undefined points" in line
    with pytest.raises(ValueError, match="more than max_undefined = 1 %"):
        chain.fill_holes(h, 0.01, "scan.dat")


def test_the_plan_decides_once_and_the_run_gives_the_loaders_surfaces():
    path = str(real_file("metropro-1.dat"))
    scene = Scene(workpiece=path, tool=path, resolution_check=False)
    plan = plan_surfaces(scene)
    with pytest.raises(dataclasses.FrozenInstanceError):
        plan.grid = 8
    run = run_plan(plan)
    loaded = load_scene_surfaces(scene)
    assert (run.grid, run.block, run.lambda_s, run.lambda_s_source, run.lambda_c, run.notes) == (
        plan.grid,
        plan.block,
        plan.lambda_s,
        plan.lambda_s_source,
        plan.lambda_c,
        plan.notes,
    )
    assert run.lambda_s_source.startswith("default") and plan.side == run.files[0].crop_size
    np.testing.assert_array_equal(run.workpiece.heights, loaded.workpiece.heights)
    assert run.records() == loaded.records()
    # the same plan on another grid is what the loader prepares on that grid
    half = plan.with_grid(plan.grid // 2, check_sampling=False)
    assert (half.side, half.lambda_s, half.grid) == (plan.side, plan.lambda_s, plan.grid // 2)
    ref = load_scene_surfaces(scene, grid=plan.grid // 2, check_sampling=False)
    np.testing.assert_array_equal(run_plan(half).tool.heights, ref.tool.heights)
    assert run_plan(half).records() == ref.records()


def test_the_plan_refuses_bad_input_before_any_stage_runs(monkeypatch):
    path = str(real_file("metropro-1.dat"))  # 640 x 480 pixels of 1.1 um: a 0.527 mm square

    def no_stage(*args, **kwargs):
        raise AssertionError("a stage of the chain ran while planning")

    for name in ("level_scan", "filter_scan", "crop_resample", "level_patch"):
        monkeypatch.setattr(chain, name, no_stage)
    monkeypatch.setattr(filters, "_smooth", no_stage)
    cases = [
        (dict(crop_size=1e-3), {}, "crop_size", "exceeds the largest common square"),
        (dict(lambda_c=2e-3), {}, "lambda_c", "lambda_c = 0.002 m is outside"),
        (dict(lambda_s=1e-7), {}, "lambda_s", "lambda_s = 1e-07 m is outside"),
        (dict(grid=1024), {}, "grid", "times the scan's pixel pitch"),
        (dict(effects=("normal", "inclined"), grid=400), {}, "grid", "inclined effect needs"),
        (dict(grid=16), dict(grid=70_000), None, "GiB per normal solve"),
    ]
    for kw, override, name, needle in cases:
        scene = Scene(workpiece=path, tool=path, resolution_check=False, **kw)
        with pytest.raises(ValueError, match=needle) as info:
            plan_surfaces(scene, **override)
        if name is not None:
            assert isinstance(info.value, ParameterError) and name in info.value.names, kw
