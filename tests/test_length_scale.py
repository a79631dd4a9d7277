"""The calibration's short-wavelength cut-off: lambda_s in the scene, the loader, the CLI, params.json."""

import json
import math

import numpy as np
import pytest
from realfiles import real_file

from halfspace_calib import topography as S
from halfspace_calib.cli import main
from halfspace_calib.pipeline.calibration import Scene
from halfspace_calib.pipeline.sweep.scene_surfaces import (
    ELEMENTS_PER_LAMBDA_S,
    ISO_NESTING_INDICES,
    ISO_SAMPLING_RATIO,
    MAX_DEFAULT_GRID,
    area_resample,
    default_lambda_s,
    load_scene_surfaces,
)
from halfspace_calib.topography.filters import l_filter, s_filter

FAST = ["--pressures", "20e6,100e6,300e6,500e6", "--reload-fractions", "0.25,0.5,0.8"]


def _grid_notes(ss):
    """The loader's notes on the grid (the patch-size note is tested in test_measured_patch_size)."""
    return [n for n in ss.notes if "elements per lambda_s" in n]


def _file(tmp_path, n=96, pitch=1e-6, seed=5):
    """A rough non-periodic scan on disk (um heights, n x n pixels of ``pitch``)."""
    s = S.self_affine((n, n), (n * pitch, n * pitch), rq=0.4e-6, seed=seed)
    f = tmp_path / f"scan{seed}.txt"
    S.write_surface(s, f, unit="um")
    return dict(workpiece=str(f), tool=str(f), unit="um", size=n * pitch), s


@pytest.mark.parametrize(
    "side, pitch", [(1.113e-3, 1.855e-6), (10e-6, 3.9e-8), (100e-6, 5e-6), (0.15, 3e-4)]
)
def test_default_lambda_s_is_the_smallest_iso_index_meeting_both_bounds(side, pitch):
    lam = default_lambda_s(side, pitch, MAX_DEFAULT_GRID)
    need = max(ISO_SAMPLING_RATIO * pitch, ELEMENTS_PER_LAMBDA_S * side / MAX_DEFAULT_GRID)
    assert lam >= need * (1 - 1e-12)
    assert any(math.isclose(lam, v, rel_tol=1e-12) for v in ISO_NESTING_INDICES)
    smaller = [v for v in ISO_NESTING_INDICES if v < lam * (1 - 1e-9)]
    assert not smaller or smaller[-1] < need


def test_loader_filters_after_levelling_and_before_resampling(tmp_path):
    f, s = _file(tmp_path)
    lam = 24e-6
    ss = load_scene_surfaces(Scene(**f, lambda_s=lam))
    # the rule: 16 elements per lambda_s, as a multiple of 8, at most the scan's sampling
    assert ss.grid == min(96, 8 * math.ceil(ELEMENTS_PER_LAMBDA_S * 96e-6 / lam / 8))
    ref = S.level(area_resample(s_filter(S.level(s), lam), 96e-6, ss.grid))
    tol = 1e-9 * np.ptp(ref.heights)
    np.testing.assert_allclose(ss.workpiece.heights, ref.heights, rtol=0, atol=tol)
    rec = ss.files[0]
    assert any("S-filter" in st and "24 um" in st for st in rec.steps)
    assert rec.rq_filtered == pytest.approx(S.rq(S.level(s_filter(S.level(s), lam))), rel=1e-9)
    assert rec.rq_filtered < rec.rq_scan  # the roughness below lambda_s is gone
    assert (ss.lambda_s, ss.lambda_s_source, _grid_notes(ss)) == (lam, "option", [])
    sc = ss.scale_record()
    assert sc["lambda_s"] == lam and sc["grid"] == ss.grid
    assert sc["element"] == pytest.approx(96e-6 / ss.grid)
    assert sc["elements_per_lambda_s"] == pytest.approx(lam * ss.grid / 96e-6)


def test_l_filter_and_no_filter(tmp_path):
    f, s = _file(tmp_path)
    kw = dict(**f, grid=48)
    ss = load_scene_surfaces(Scene(**kw, lambda_s=4e-6, lambda_c=40e-6))
    ref = S.level(area_resample(s_filter(l_filter(S.level(s), 40e-6), 4e-6), 96e-6, 48))
    np.testing.assert_allclose(ss.workpiece.heights, ref.heights, atol=1e-9 * np.ptp(ref.heights))
    assert any("L-filter" in st for st in ss.files[0].steps) and ss.lambda_c == 40e-6
    off = load_scene_surfaces(Scene(**kw, lambda_s=0.0))
    ref = S.level(area_resample(s, 96e-6, 48))
    np.testing.assert_allclose(off.workpiece.heights, ref.heights, atol=1e-9 * np.ptp(ref.heights))
    assert not any("filter" in st for st in off.files[0].steps)
    assert off.lambda_s == 0.0 and "no S-filter" in off.lambda_s_source
    assert off.scale_record()["lambda_s"] is None


def test_default_lambda_s_and_grid_for_a_file(tmp_path):
    f, _ = _file(tmp_path, n=128, pitch=0.5e-6)
    ss = load_scene_surfaces(Scene(**f))
    assert ss.lambda_s == default_lambda_s(64e-6, 0.5e-6, MAX_DEFAULT_GRID)
    assert ss.lambda_s_source.startswith("default")
    assert ss.workpiece.dx <= ss.lambda_s / ELEMENTS_PER_LAMBDA_S * (1 + 1e-9) or ss.grid == 128
    # the resolution check's half grid keeps the lambda_s (the grid is a numerical choice only)
    half = load_scene_surfaces(
        Scene(**f, lambda_s=ss.lambda_s),
        grid=ss.grid // 2,
        check_sampling=False,
    )
    assert half.lambda_s == ss.lambda_s and half.notes == ()


def test_a_coarse_grid_is_warned_not_refused(tmp_path):
    f, _ = _file(tmp_path)
    ss = load_scene_surfaces(Scene(**f, lambda_s=8e-6, grid=24))
    (note,) = _grid_notes(ss)
    assert "2 elements per lambda_s = 8 um" in note and "--grid 192" in note
    assert "does not sample" not in note
    ss = load_scene_surfaces(Scene(**f, lambda_s=4e-6, grid=16))
    assert "does not sample the filtered surface" in _grid_notes(ss)[0]


@pytest.mark.parametrize(
    "kw, match",
    [
        (dict(lambda_s=-1e-6), "lambda_s must be a length >= 0"),
        (dict(lambda_s=math.nan), "lambda_s must be"),
        (dict(lambda_s=True), "lambda_s must be"),
        (dict(lambda_c=0.0), "lambda_c must be a length > 0"),
        (dict(lambda_s=5e-6, lambda_c=5e-6), "lambda_c = 5e-06 m must exceed lambda_s"),
    ],
)
def test_scene_refuses_bad_cutoffs(tmp_path, kw, match):
    with pytest.raises(ValueError, match=match):
        Scene(workpiece="x.txt", unit="um", size=1e-4, **kw)


def test_synthetic_scenes_keep_their_spectrum():
    with pytest.raises(ValueError, match="lambda_s apply to surface files only"):
        Scene(lambda_s=10e-6)


def test_lambda_s_outside_the_scan_is_refused_with_its_range(tmp_path):
    f, _ = _file(tmp_path)
    for lam in (1e-6, 1e-3):  # one pixel; beyond the 96 um scan
        with pytest.raises(ValueError, match=r"lambda_s = .* allowed range \[2e-06, 9.6e-05\]"):
            load_scene_surfaces(Scene(**f, lambda_s=lam))


def _cli(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_lambda_s_recorded_in_params_json(tmp_path, capsys):
    f, _ = _file(tmp_path, n=64)
    out = tmp_path / "out"
    args = ["--workpiece", f["workpiece"], "--tool", f["tool"], "--unit", "um", "--size", "64e-6"]
    code, text, err = _cli(
        capsys, *args, "--lambda-s", "8e-6", "--grid", "32", "--out", str(out), *FAST
    )
    assert code in (0, 1), err
    assert "lambda_s = 8 um (option), 4 elements per lambda_s" in text
    assert "warning: grid 32 has 4 elements per lambda_s" in err and "--grid 128" in err
    prov = json.loads((out / "params.json").read_text())["provenance"]
    ls = prov["extra"]["length_scale"]
    assert ls["lambda_s"] == 8e-6 and ls["grid"] == 32 and ls["element"] == pytest.approx(2e-6)
    assert ls["lambda_s_source"] == "option" and ls["notes"]
    assert prov["extra"]["resolution_check"]["half_grid"] == 16
    # bad values: exit 2, the parameter and its range named, no traceback
    for bad, word in (("-1e-6", "lambda_s must be a length >= 0"), ("1", "allowed range")):
        code, _, err = _cli(capsys, *args, f"--lambda-s={bad}", "--out", str(tmp_path / "o2"))
        assert code == 2 and word in err and "Traceback" not in err
    code, help_text, _ = _cli(capsys, "--help")
    assert code == 0 and "--lambda-s" in help_text and "ISO 25178-3" in help_text


def test_shared_matrix_file_default(tmp_path):
    p = real_file("matrix-3.txt")
    ss = load_scene_surfaces(Scene(workpiece=str(p), tool=str(p)))
    lam = default_lambda_s(10e-6, 10e-6 / 256, MAX_DEFAULT_GRID)
    assert ss.lambda_s == lam and ss.grid == 8 * math.ceil(16 * 10e-6 / lam / 8 - 1e-9)
    assert _grid_notes(ss) == []
