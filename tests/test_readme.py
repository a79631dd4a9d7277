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
