"""The smaller frictions a new user met, each pinned by a test (issue: nothing lost, nothing hung)."""

import inspect
import json

import numpy as np
import pytest

import fe_demo
from fe_demo.cli import build_parser
from fe_demo.cli import main as fe_demo_main
from fe_demo.scenes.laws import EXAMPLE_PARAMS_PATH
from frictionlaw import FrictionParams, SBMFLaw, Tresca, shear_limit
from halfspace_calib import Scene, calibrate
from halfspace_calib.cli import main as calib

TINY = ["--nr", "6", "--increments", "4", "--vtu-every", "0", "--no-progress"]


def test_laws_are_callable_and_give_the_shear_limit():
    P = FrictionParams.from_json(EXAMPLE_PARAMS_PATH)
    p = np.array([50e6, 200e6, 500e6])
    h = np.array([0.0, 400e6, 100e6])
    np.testing.assert_array_equal(SBMFLaw(P)(p, h), shear_limit(p, h, P))
    assert Tresca(0.3, 100e6)(5e8) == pytest.approx(30e6, rel=1e-15)


def test_calibration_repr_is_one_short_line():
    cal = calibrate(
        Scene(grid=16, pressures=(1e8, 2e8, 3e8, 5e8), reload_fractions=(0.3, 0.6)),
        progress=False,
    )
    r = repr(cal)
    assert "\n" not in r and len(r) < 200
    assert r.startswith("Calibration(") and f"C1={cal.params.C1:.4g}" in r


def test_hardness_in_mpa_typed_as_pa_is_named(capsys):
    with pytest.raises(ValueError, match=r"H = 800 Pa .* most likely MPa were typed as Pa"):
        Scene(H=800)
    assert calib(["--H", "800", "--quiet", "--out", "unused"]) == 2
    err = capsys.readouterr().err
    assert "H = 800 Pa" in err and "pressures must be" not in err


def test_params_imply_the_sbmf_law_and_tresca_with_params_says_what_to_add(tmp_path, capsys):
    out = tmp_path / "ring"
    rc = fe_demo_main(["ring", "--params", str(EXAMPLE_PARAMS_PATH), *TINY, "--out", str(out)])
    assert rc == 0
    info = json.loads((out / "summary.json").read_text())
    assert info["law"] == "sbmf" or "sbmf" in json.dumps(info.get("law_parameters", info))
    rc = fe_demo_main(
        ["ring", "--law", "tresca", "--params", str(EXAMPLE_PARAMS_PATH), *TINY, "--out", str(out)]
    )
    assert rc == 2
    assert "add --law sbmf" in capsys.readouterr().err


def test_one_default_law_per_scene_for_cli_and_api():
    sub = build_parser()._subparsers._group_actions[0].choices
    for scene, fn in (
        ("upsetting", fe_demo.run_upsetting),
        ("ring", fe_demo.run_ring),
        ("multistage", fe_demo.run_multistage),
    ):
        api = inspect.signature(fn).parameters["law"].default
        assert sub[scene].get_default("default_law") == api, scene


def test_a_typo_in_a_subcommand_option_shows_that_subcommands_usage(capsys):
    assert fe_demo_main(["ring", "--nrr", "5"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: fe-demo ring") and "unrecognized arguments: --nrr 5" in err


def test_a_parameter_file_without_units_is_refused(tmp_path):
    doc = json.loads(EXAMPLE_PARAMS_PATH.read_text())
    del doc["units"]
    path = tmp_path / "p.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(ValueError, match="no 'units' block"):
        FrictionParams.from_json(path)


def test_ring_reports_the_inner_diameter_change(tmp_path, capsys):
    out = tmp_path / "ring"
    assert fe_demo_main(["ring", "--law", "tresca", "--m", "0.3", *TINY, "--out", str(out)]) == 0
    table = capsys.readouterr().out
    assert "ID_change_%" in table
    info = json.loads((out / "summary.json").read_text())
    assert -1.0 < info["inner_diameter_change"] < 1.0
    html = (out / "report.html").read_text()
    assert 'data-key="inner_diameter_change"' in html
