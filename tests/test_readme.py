"""The README's first screen and CI run the same commands."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _readme_commands():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    return re.findall(r"```bash\n(.+?)\n```", text, flags=re.S)[:2]


def test_ci_runs_the_readme_test_command():
    main_job, tests = _readme_commands()
    ci = [ln for ln in (ROOT / ".ci/run").read_text().splitlines() if ln and ln[0] != "#"]
    assert tests in ci, f"README test command {tests!r} is not a line of .ci/run"


def test_readme_commands_make_their_own_virtual_environment():
    for cmd in _readme_commands():
        assert cmd.startswith("python3 -m venv .venv && . .venv/bin/activate && pip install -e ")
    main_job, _ = _readme_commands()
    assert "halfspace-calib --out out/calibration" in main_job
    assert "fe-demo upsetting --law sbmf --params out/calibration/params.json" in main_job


def _readme():
    return (ROOT / "README.md").read_text(encoding="utf-8")


def test_readme_getfem_test_count_and_skip_conditions_are_true():
    import ast

    text = _readme()
    m = re.search(r"GetFEM ring tests \((\d+) test functions, (\d+) test items\)", text)
    assert m, "README must state the GetFEM ring tests' count"
    tree = ast.parse((ROOT / "tests" / "test_getfem_ring.py").read_text(encoding="utf-8"))
    funcs = [n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name.startswith("test_")]
    assert int(m.group(1)) == len(funcs)
    items = 0
    for f in funcs:  # one item, or one per parametrize value
        n = 1
        for d in f.decorator_list:
            if isinstance(d, ast.Call) and getattr(d.func, "attr", "") == "parametrize":
                n *= len(d.args[1].elts)  # the literal list of parameter sets
        items += n
    assert int(m.group(2)) == items
    # the coupling's own check names what a skip needs; the README names the same packages
    compare = (ROOT / "couplings" / "getfem" / "compare.py").read_text(encoding="utf-8")
    for pkg in ("python3-getfem", "python3-numba", "python3-scipy"):
        assert pkg in compare and pkg in text


def test_readme_progress_options_per_command_are_true():
    from fe_demo.cli import build_parser as fe_parser
    from frictionlaw.__main__ import main as demo_main  # noqa: F401 - the command exists
    from frictionlaw.export.cli import build_parser as export_parser
    from halfspace_calib.cli import build_parser as calib_parser

    text = " ".join(_readme().split())
    assert "`halfspace-calib` and `fe-demo` have both, `frictionlaw-export` only `--quiet`" in text

    def opts(parser):
        return {s for a in parser._actions for s in a.option_strings}

    fe_ring = fe_parser()._subparsers._group_actions[0].choices["ring"]
    for p in (calib_parser(), fe_ring):
        assert {"--quiet", "--no-progress"} <= opts(p)
    assert "--quiet" in opts(export_parser()) and "--no-progress" not in opts(export_parser())


def test_readme_does_not_call_ls_dyna_both_drop_in_and_not():
    text = " ".join(_readme().split())
    assert "LS-DYNA's and ANSYS's friction-routine argument lists are not public" not in text
    assert "ANSYS's friction-routine argument list is not public" in text


def test_default_output_folders_are_git_ignored():
    ignored = (ROOT / ".gitignore").read_text(encoding="utf-8").split()
    assert "out/" in ignored and "fe_out/" in ignored


_CCX_PLUGIN = """
def pytest_collection_modifyitems(session, config, items):
    n = sum("ccx_work" in getattr(item, "fixturenames", ()) for item in items)
    print("CCX_ITEMS", n)
    n = sum(item.get_closest_marker("shared_surfaces") is not None for item in items)
    print("SHARED_ITEMS", n)
"""


def test_readme_calculix_skip_count_is_true(tmp_path):
    """The README's count of CalculiX tests that skip without the patched build: the test items
    that need the build (the ``ccx_work`` fixture, directly or through another fixture)."""
    import os
    import subprocess
    import sys

    m = re.search(r"the CalculiX\s+tests \((\d+)\) without the patched library", _readme())
    assert m, "README must state how many CalculiX tests skip without the build"
    (tmp_path / "ccx_count.py").write_text(_CCX_PLUGIN)
    env = dict(os.environ, PYTHONPATH=str(tmp_path) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    run = subprocess.run(
        [sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "ccx_count",
         "-p", "no:cacheprovider",
         *(str(f) for f in sorted((ROOT / "tests").glob("test_calculix*.py")))],
        capture_output=True, text=True, env=env, cwd=ROOT, check=False,
    )  # fmt: skip
    n = re.search(r"CCX_ITEMS (\d+)", run.stdout)
    assert n, run.stdout + run.stderr
    assert int(m.group(1)) == int(n.group(1))


def test_readme_shared_files_skip_count_is_true(tmp_path):
    """The README's count of the tests that need ``../shared/surfaces/``: the items marked
    ``shared_surfaces`` (``tests/realfiles.py`` fails a test that reads such a file unmarked)."""
    import os
    import subprocess
    import sys

    m = re.search(r"\(`mnt-1.mnt`, `x3p-2.x3p`, [\d.]+ MB\) stay out of the repository; their "
                  r"(\d+) tests", " ".join(_readme().split()))  # fmt: skip
    assert m, "README must state how many tests need ../shared/surfaces"
    (tmp_path / "ccx_count.py").write_text(_CCX_PLUGIN)
    env = dict(os.environ, PYTHONPATH=str(tmp_path) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    # the test modules that can carry the mark (the others cannot, and realfiles.real_file fails
    # a test that reads a shared file without it)
    marks = ("needs_shared", "file_params", "shared_surfaces")
    files = [str(p) for p in sorted((ROOT / "tests").glob("test_*.py"))
             if p.name != "test_readme.py"
             and any(m in p.read_text(encoding="utf-8") for m in marks)]  # fmt: skip
    run = subprocess.run(
        [sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "ccx_count",
         "-p", "no:cacheprovider", *files],
        capture_output=True, text=True, env=env, cwd=ROOT, check=False,
    )  # fmt: skip
    n = re.search(r"SHARED_ITEMS (\d+)", run.stdout)
    assert n, run.stdout[-2000:] + run.stderr
    assert int(m.group(1)) == int(n.group(1)) > 0


def test_readme_default_run_figures_are_a_fresh_runs(tmp_path):
    """The default calibration's parameters and its drop at p_hist in the README are what a fresh
    run of ``halfspace-calib`` gives now (the law's work changes them: this test says so)."""
    import json

    from halfspace_calib.cli import main

    out = tmp_path / "calibration"
    assert main(["--quiet", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    P = json.loads((out / "params.json").read_text())["parameters"]
    text = " ".join(_readme().split())
    default = re.search(
        r"Default scene \(128\^2.*?the first loading runs the computed points \(tabulated\), "
        r"held-out max `\|d alpha\|` ([\d.]+) \(Eq. 24 beside it.*?: `C1 = ([\d.]+), n1 = "
        r"([\d.]+)` \(R\^2 ([\d.]+)\), held out ([\d.]+)\); the continuous reload branch "
        r"tabulated over (\d+) levels with `s2 = ([\d.]+)`, held-out max `\|d alpha\|` ([\d.]+) "
        r"\(the paper's one pair beside it: `C2 = ([\d.]+), n2 = ([\d.]+)` \(R\^2 ([\d.]+)\), "
        r"held out ([\d.]+)\); `mu_eff = ([\d.]+)` with `m = ([\d.]+)`",
        text,
    )
    assert default, "README must give the default scene's parameters"

    def same(shown, value):  # the README's digits are the value rounded to them
        digits = len(shown.split(".")[1]) if "." in shown else 0
        return f"{value:.{digits}f}" == shown

    held1, C1, n1, r1, held24, levels, s2, held, C2, n2, r2, held_p, mu, m = default.groups()
    err = s["errors"]
    assert (s["first_loading_form"], s["continuous_reload"]) == ("tabulated", True)
    got = {
        "first held out": (held1, err["first_loading"]["heldout_max"]),
        "C1": (C1, P["C1"]), "n1": (n1, P["n1"]), "first R^2": (r1, s["first_loading_r2"]),
        "held out, Eq. 24": (held24, err["first_loading_eq24"]["heldout_max"]),
        "levels": (levels, len(s["errors"]["reload"]["heldout"]) + 2), "s2": (s2, s["s2"]),
        "held out": (held, err["reload"]["heldout_max"]),
        "C2": (C2, P["C2"]), "n2": (n2, P["n2"]), "reload R^2": (r2, s["reload_r2"]),
        "held out, paper": (held_p, err["reload_paper"]["heldout_max"]),
        "mu_eff": (mu, s["mu_eff"]), "m": (m, P["m"]),
    }  # fmt: skip
    wrong = {k: v for k, v in got.items() if not same(*v)}
    assert not wrong, f"README default-run figures differ from a fresh run: {wrong}"
    jump = re.search(r"default calibration the largest drop is ([\d.]+) % of `tau`", text)
    assert s["reload_form"] == "tabulated"
    assert jump and same(jump.group(1), 100 * s["max_jump_relative"]), (
        jump and jump.group(1),
        100 * s["max_jump_relative"],
    )
