"""The preparation chain of a measured surface (halfspace_calib/topography/chain.py).

Each stage returns the surface and its lines of provenance; run stage by stage with the scene's
parameters, the chain gives the loader's solver surface to the last digit, with the same steps.
"""

import numpy as np
import pytest
from realfiles import real_file

from halfspace_calib.pipeline.calibration import Scene
from halfspace_calib.pipeline.scene_surfaces import load_scene_surfaces
from halfspace_calib.topography import Surface, chain, read_raw, rq


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
