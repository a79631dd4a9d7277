"""What ``halfspace-calib`` says about a run (issue 33): an unreachable tolerance is refused up
front, an error inside a run is a failed run and no traceback, a failed run never announces the
``params.json`` it does not write, its advice names only listed options, and one run time is
reported the same way on the console and in ``summary.json``, close to the wall clock.
"""

import dataclasses
import json
import re
import subprocess
import sys
import time

import numpy as np
import pytest

import halfspace_calib.cli as cli
from halfspace_calib.cli import build_parser, main
from halfspace_calib.cli._paths import exit_code
from halfspace_calib.pipeline.calibration import calibrate
from halfspace_calib.pipeline.sweep.scene import Scene
from sbmf_cli import Console, flags_of

QUICK = ["--grid", "16", "--pressures", "1e8,2e8,3e8,5e8", "--reload-fractions", "0.3,0.6"]


def test_an_unreachable_tolerance_is_refused_before_any_sweep(tmp_path, capsys, monkeypatch):
    """--tol 1e-15 ran 94 s and ended in a traceback writing nothing."""

    def no_run(*a, **k):
        raise AssertionError("a calibration started")

    monkeypatch.setattr(cli, "calibrate", no_run)
    assert main([*QUICK, "--tol", "1e-15", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "--tol must be in [1e-12, 1)" in err and "got 1e-15" in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()
    with pytest.raises(ValueError, match=r"^tol must be in \[1e-12, 1\)"):
        Scene(tol=1e-15)


def test_an_error_inside_the_run_is_a_failed_run(tmp_path, capsys, monkeypatch):
    def broken(*a, **k):
        raise ValueError("curves need at least 3 points (p, alpha) to fit 2 parameters, got 2")

    monkeypatch.setattr(cli, "calibrate", broken)
    assert main([*QUICK, "--no-progress", "--out", str(tmp_path / "o")]) == 1
    err = capsys.readouterr().err
    assert "the run failed: curves need at least 3 points" in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()


def test_a_failed_run_never_announces_params_json(tmp_path, capsys):
    heights = np.random.default_rng(2).normal(0.0, 1e-6, (64, 64))
    np.save(tmp_path / "s.npy", heights)
    s = str(tmp_path / "s.npy")
    out = tmp_path / "o"
    argv = ["--workpiece", s, "--tool", s, "--size", "2e-3", "--unit", "m", "--grid", "32"]
    argv += ["--heldout-tol", "1e-4"]  # a tolerance no law meets: the run fails
    assert main([*argv, "--no-progress", "--out", str(out)]) == 1
    cap = capsys.readouterr()
    assert "calibration FAILED after" in cap.out and "params.failed.json" in cap.out
    assert "params.json" not in cap.out + cap.err.replace("not as params.json", "")
    assert (out / "params.failed.json").is_file() and not (out / "params.json").exists()


def test_the_advice_of_a_failed_solve_names_listed_options(capsys):
    """The solver's '(raise maxiter or tol)' named an option --help does not list."""
    cal = calibrate(Scene(grid=16, pressures=(1e8, 2e8, 3e8, 5e8), reload_fractions=(0.3, 0.6)),
                    progress=False)  # fmt: skip
    lv = cal.sweeps.levels[1]
    lv.reload = [dataclasses.replace(lv.reload[0], converged=False, message="NOT converged")]
    problems = cal.problems()
    hint = next(p for p in problems if "left out of the fit" in p)
    assert "raise tol (now 1e-06" in hint  # the Python name for a library caller
    parser = build_parser()
    listed = set(re.findall(r"--[a-zA-Z][\w-]*", parser.format_help()))
    assert exit_code(Console("halfspace-calib", flags=flags_of(parser)), problems) == 1
    err = capsys.readouterr().err
    assert "raise --tol (now 1e-06" in err and "maxiter" not in err
    assert set(re.findall(r"--[a-zA-Z][\w-]*", err)) <= listed


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="process start from /proc")
def test_one_run_time_on_the_console_in_summary_json_and_on_the_wall_clock(tmp_path):
    out = tmp_path / "o"
    cmd = [sys.executable, "-m", "halfspace_calib", *QUICK, "--no-progress", "--out", str(out)]
    t0 = time.perf_counter()
    run = subprocess.run(cmd, capture_output=True, text=True, check=True)
    wall = time.perf_counter() - t0
    m = re.search(
        r"calibrated in ([0-9.]+) s \(([0-9.]+) s of it solving and fitting\)", run.stdout
    )
    assert m, run.stdout
    summary = json.loads((out / "summary.json").read_text())
    assert f"{summary['command_seconds']:.1f}" == m.group(1)
    assert f"{summary['seconds']:.1f}" == m.group(2)
    # the console's time runs from the process's start (imports included) to the outputs: the
    # wall clock adds only the writing and the exit
    assert summary["seconds"] < summary["command_seconds"] <= wall
    assert summary["command_seconds"] > 0.6 * wall, (summary["command_seconds"], wall)
