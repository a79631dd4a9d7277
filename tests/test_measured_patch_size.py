"""A patch a few lambda_s across does not represent a surface (issue 26, item 2).

Below :data:`MIN_PATCH_LAMBDA_S` the loader warns (stderr, ``params.json``
``length_scale.notes``, ``summary.json`` ``warnings``) and points to ``--patches``; the run is
not failed by it (``problems`` stays empty, exit 0).
"""

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from halfspace_calib import topography as S
from halfspace_calib.cli import main
from halfspace_calib.pipeline.calibration import Scene
from halfspace_calib.pipeline.sweep.length_scale import MIN_PATCH_LAMBDA_S, check_patch_size
from halfspace_calib.pipeline.sweep.scene_surfaces import load_scene_surfaces

FAST = ["--pressures", "20e6,100e6,300e6,500e6", "--reload-fractions", "0.25,0.5,0.8"]
RESULTS = Path(__file__).resolve().parents[1] / "benchmarks" / "results"
N, PITCH = 128, 1e-6  # the scan: 128 um at 1 um pixels
LAM = N * PITCH / MIN_PATCH_LAMBDA_S  # the whole scan is exactly the minimum across


def _scan(tmp_path):
    s = S.self_affine((N, N), (N * PITCH, N * PITCH), rq=0.4e-6, seed=11)
    f = tmp_path / "scan.txt"
    S.write_surface(s, f, unit="um")
    return str(f)


def test_check_patch_size_threshold_and_message():
    assert check_patch_size(MIN_PATCH_LAMBDA_S * 1e-5, 1e-5) == ()
    assert check_patch_size(1.0, 0.0) == ()  # no S-filter: no lambda_s to measure against
    (msg,) = check_patch_size(0.5 * MIN_PATCH_LAMBDA_S * 1e-5, 1e-5)
    assert f"{0.5 * MIN_PATCH_LAMBDA_S:.3g} lambda_s across" in msg
    assert f"fewer than {MIN_PATCH_LAMBDA_S} lambda_s" in msg and "--patches" in msg


def test_loader_warns_for_a_small_patch_and_not_for_a_large_one(tmp_path):
    f = _scan(tmp_path)
    kw = dict(workpiece=f, tool=f, unit="um", size=N * PITCH, lambda_s=LAM)
    whole = load_scene_surfaces(Scene(**kw))
    assert not [n for n in whole.notes if "the patch is" in n]
    half = load_scene_surfaces(Scene(**kw, crop_size=N * PITCH / 2))
    (note,) = [n for n in half.notes if "the patch is" in n]
    assert f"{MIN_PATCH_LAMBDA_S / 2:.3g} lambda_s across" in note
    assert half.scale_record()["notes"] == list(half.notes)


@pytest.mark.parametrize("crop, warned", [(None, False), (N * PITCH / 2, True)])
def test_cli_patch_warning_on_stderr_and_in_summary_not_a_failure(tmp_path, capsys, crop, warned):
    f = _scan(tmp_path)
    out = tmp_path / "out"
    argv = ["--workpiece", f, "--tool", f, "--unit", "um", "--size", str(N * PITCH)]
    argv += ["--lambda-s", str(LAM), "--grid", "32", "--no-resolution-check", "--no-progress"]
    argv += ["--out", str(out), *FAST] + (["--crop-size", str(crop)] if crop else [])
    code = main(argv)
    _, err = capsys.readouterr()
    summary = json.loads((out / "summary.json").read_text())
    patch = [w for w in summary["warnings"] if "the patch is" in w]
    assert code == 0, err
    assert summary["problems"] == []
    if warned:
        assert "halfspace-calib: warning: the patch is 64 um" in err and "--patches" in err
        assert len(patch) == 1 and "--patches" in patch[0]
        notes = json.loads((out / "params.json").read_text())["provenance"]["extra"]
        assert patch[0] in notes["length_scale"]["notes"]
    else:
        assert "the patch is" not in err and patch == []


def test_minimum_is_where_the_measured_scatter_falls_to_the_check_tolerance():
    # MIN_PATCH_LAMBDA_S is the smallest measured patch size at which mu_eff of metropro-1's
    # patches scatters by at most the resolution check's 10 % (benchmarks/patch_size.py)
    from halfspace_calib.pipeline.sweep.resolution import RESOLUTION_TOL

    with open(RESULTS / "patch_size.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    mine = [r for r in rows if r["scan"] == "metropro-1.dat"]
    cv = {}
    for k in sorted({int(r["patch_lambda_s"]) for r in mine}):
        v = np.array([float(r["mu_eff"]) for r in mine if int(r["patch_lambda_s"]) == k])
        cv[k] = v.std(ddof=1) / v.mean()
    ok = [k for k in cv if cv[k] <= RESOLUTION_TOL]
    assert ok and min(ok) == MIN_PATCH_LAMBDA_S
    assert all(cv[k] > RESOLUTION_TOL for k in cv if k < MIN_PATCH_LAMBDA_S)
