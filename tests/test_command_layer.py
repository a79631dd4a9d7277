"""The command layer (sbmf_cli): library errors in Python names, command errors in flags.

Library code raises :class:`sbmf_cli.ParameterError` naming its parameters as a Python caller
wrote them; the command that called it words the same message with its own flags. Before the
command layer, 27 library ``raise`` sites spoke of flags (``--measured``, ``--size``) to Python
users who never typed one.
"""

import ast
import pickle
import re
from pathlib import Path

import numpy as np
import pytest

from fe_demo.analysis.ringfit import read_ring_tests
from halfspace_calib.cli import build_parser as calib_parser
from halfspace_calib.topography import chain
from sbmf_cli import Console, ParameterError, flags_of

REPO = Path(__file__).resolve().parents[1]
FLAG = re.compile(r"--[a-z][a-z0-9-]*")
#: modules that are commands (their messages are for command-line users)
COMMANDS = re.compile(
    r"(/cli/|/cli\.py$|_cmd\.py$|__main__\.py$|^sbmf_cli/|^couplings/getfem/ring\.py$)"
)
#: raise sites that still name flags, each with the reason it is left
LEFT = {
    # the parameter file's own checks: the runtime law imports nothing of the project, so it
    # cannot raise sbmf_cli's ParameterError; both name the Python argument first and the
    # commands' flag beside it ("accept_failed=True; --accept-failed-fit on the command lines")
    "frictionlaw/params.py": 2,
}


def _flag_raises():
    """``{file: count}`` of raise sites outside the commands whose message names a flag."""
    found = {}
    for pkg in ("frictionlaw", "halfspace_calib", "fe_demo", "couplings"):
        for path in sorted((REPO / pkg).rglob("*.py")):
            rel = path.relative_to(REPO).as_posix()
            if COMMANDS.search(rel):
                continue
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, ast.Raise) and node.exc is not None:
                    text = " ".join(
                        c.value
                        for c in ast.walk(node.exc)
                        if isinstance(c, ast.Constant) and isinstance(c.value, str)
                    )
                    if FLAG.search(text):
                        found[rel] = found.get(rel, 0) + 1
    return found


def test_library_raise_sites_speak_python_names():
    assert _flag_raises() == LEFT


def test_a_parameter_error_reads_in_python_names_and_in_flags():
    err = ParameterError("{lambda_s} {x} must be > 0, got {'a': 1}", "lambda_s")
    assert str(err) == "lambda_s {x} must be > 0, got {'a': 1}"  # other braces kept
    assert err.render({"lambda_s": "--lambda-s"}) == "--lambda-s {x} must be > 0, got {'a': 1}"
    assert isinstance(err, ValueError)
    back = pickle.loads(pickle.dumps(err))  # crosses process boundaries with its names
    assert back.render({"lambda_s": "--ls"}).startswith("--ls ")


def test_flags_of_maps_dests_to_the_listed_flags():
    flags = flags_of(calib_parser())
    assert flags["lambda_s"] == "--lambda-s" and flags["max_undefined"] == "--max-undefined"
    assert flags["periodic"] == "--periodic" and flags["E_workpiece"] == "--E-workpiece"


def test_a_library_check_names_the_parameter_and_the_command_its_flag(capsys):
    h = np.ones((8, 8))
    h[:4] = np.nan
    with pytest.raises(ParameterError) as info:
        chain.fill_holes(h, 0.05, "scan.dat")
    assert "max_undefined = 5 %" in str(info.value) and "--" not in str(info.value)
    con = Console("halfspace-calib", flags=flags_of(calib_parser()))
    assert con.error(info.value, 2) == 2
    assert "raise --max-undefined (a fraction" in capsys.readouterr().err


def test_ring_tests_name_paths_in_python_and_measured_on_the_command_line(tmp_path, capsys):
    from fe_demo.cli import main

    with pytest.raises(ParameterError, match=r"^paths .*missing.csv: no such file"):
        read_ring_tests([tmp_path / "missing.csv"])
    rc = main(
        [
            "ring-fit",
            "--measured",
            str(tmp_path / "missing.csv"),
            "--illustrative",
            "--out",
            str(tmp_path / "o"),
        ]
    )
    assert (
        rc == 2
        and f"--measured {tmp_path / 'missing.csv'}: no such file" in capsys.readouterr().err
    )


def test_refuse_repeats_refuses_a_second_value_and_leaves_flags_and_appends(capsys):
    import argparse

    from sbmf_cli import file_path, refuse_repeats

    ap = argparse.ArgumentParser(prog="x")
    ap.add_argument("--data", type=file_path)
    ap.add_argument("--grid", type=int, default=128)
    ap.add_argument("--zone", action="append")
    ap.add_argument("--force", action="store_true")
    sub = ap.add_subparsers(dest="cmd")
    sub.add_parser("run").add_argument("--n", type=int)
    refuse_repeats(ap)
    # one of each, flags twice and appends many times are fine; the parser runs again and again
    for _ in range(3):
        a = ap.parse_args(["--data", "a.csv", "--grid", "16", "--zone", "a", "--zone", "b"])
        assert (a.data, a.grid, a.zone) == ("a.csv", 16, ["a", "b"])
    assert ap.parse_args(["--force", "--force"]).force is True
    assert ap.parse_args(["run", "--n", "3"]).n == 3
    for argv, said in [
        (["--data", "a.csv", "--data", "b.csv"], "given more than once ('a.csv', then 'b.csv')"),
        (["--grid", "16", "--grid=32"], "given more than once (16, then 32)"),
        (["--gr", "16", "--grid", "32"], "given more than once"),  # an abbreviation counts
        (["run", "--n", "1", "--n", "2"], "given more than once (1, then 2)"),
        (["--data", ""], "an empty value: give a file path"),
    ]:
        with pytest.raises(SystemExit) as exc:
            ap.parse_args(argv)
        assert exc.value.code == 2 and said in capsys.readouterr().err
