"""One set of conventions for the four command lines (sbmf_cli).

--version, --quiet against --no-progress, stdout/stderr, help text with every default and no RST,
output folders that appear whole.
"""

import argparse
import re
from importlib import metadata
from pathlib import Path

import pytest

from fe_demo import cli as fe_cli
from fe_demo.cli import runs as fe_runs
from frictionlaw import __main__ as law_demo
from frictionlaw.export import cli as law_export
from halfspace_calib import cli as hs_cli
from sbmf_cli import OutputFolder

MAINS = {
    "halfspace-calib": hs_cli.main,
    "fe-demo": fe_cli.main,
    "frictionlaw-export": law_export.main,
    "frictionlaw-demo": law_demo.main,
}
PARSERS = {
    "halfspace-calib": hs_cli.build_parser,
    "fe-demo": fe_cli.build_parser,
    "frictionlaw-export": law_export.build_parser,
    "frictionlaw-demo": law_demo.build_parser,
}
FE_FAST = ["--nr", "4", "--increments", "3", "--reduction", "0.15", "--vtu-every", "1"]


def _all_parsers(parser):
    """The parser and every sub-parser below it."""
    out = [parser]
    for a in parser._actions:
        if isinstance(a, argparse._SubParsersAction):
            for sub in a.choices.values():
                out += _all_parsers(sub)
    return out


@pytest.mark.parametrize("prog", sorted(MAINS))
def test_version(prog, capsys):
    assert MAINS[prog](["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"{prog} {metadata.version('sbmf-friction')}"


@pytest.mark.parametrize("prog", sorted(PARSERS))
def test_every_option_has_help_with_its_default_and_no_rst(prog):
    parsers = _all_parsers(PARSERS[prog]())
    assert len(parsers) == (5 if prog == "fe-demo" else 1)  # upsetting, ring, multistage, ring-fit
    for p in parsers:
        text = p.format_help()
        assert "``" not in text and not re.search(r":(class|func|meth|data|attr):", text), p.prog
        fmt = p._get_formatter()
        for a in p._actions:
            if not a.option_strings or isinstance(a, argparse._HelpAction):
                continue
            assert a.help, f"{p.prog} {a.option_strings[0]} has no help"
            if a.nargs == 0 or a.required:  # flags: off unless given; required: no default
                continue
            shown = fmt._expand_help(a) if a.help else ""
            assert "default" in shown, f"{p.prog} {a.option_strings[0]}: no default in {shown!r}"


def test_the_help_formatter_adds_a_default_only_where_missing():
    from sbmf_cli import HelpFormatter

    ap = argparse.ArgumentParser(formatter_class=HelpFormatter)
    ap.add_argument("--a", type=float, default=2.5, help="an a")
    ap.add_argument("--b", default=None, help="a b (default: none)")
    ap.add_argument("--c", type=int, default=3, help="a c (default 3)")
    ap.add_argument("--d", action="store_true", help="a flag")
    text = " ".join(ap.format_help().split())
    assert "an a (default: 2.5)" in text
    assert text.count("default") == 3 and "a flag" in text


def _fast(*extra):
    """FE_FAST with the options ``extra`` gives left out (a value option is given once)."""
    given = {x for x in extra if str(x).startswith("--")}
    pairs = zip(FE_FAST[::2], FE_FAST[1::2], strict=True)
    return [x for opt, v in pairs if opt not in given for x in (opt, v)]


def _fe(tmp_path, *extra, scene="upsetting"):
    return fe_cli.main([scene, *_fast(*extra), "--out", str(tmp_path), *extra])


def test_quiet_hides_progress_and_summary_no_progress_only_progress(tmp_path, capsys):
    assert _fe(tmp_path / "q", "--quiet") == 0
    cap = capsys.readouterr()
    assert cap.out == "" and cap.err == ""
    assert (tmp_path / "q" / "history.csv").is_file()
    assert _fe(tmp_path / "n", "--no-progress") == 0
    cap = capsys.readouterr()
    assert "sbmf" in cap.out and f"output in {tmp_path / 'n'}" in cap.out and cap.err == ""
    # the summary on stdout is also the run's summary.txt
    assert "sbmf" in (tmp_path / "n" / "summary.txt").read_text()


def test_errors_go_to_stderr_with_exit_2(tmp_path, capsys):
    for argv in (
        ["upsetting", "--reduction", "2", "--out", str(tmp_path / "a")],
        ["ring", "--law", "coulomb", "--m-list", "0.1", "--out", str(tmp_path / "b")],
    ):
        assert fe_cli.main(argv) == 2
        cap = capsys.readouterr()
        assert (
            cap.out == "" and cap.err.startswith("fe-demo: error: ") and "Traceback" not in cap.err
        )
    assert law_demo.main(["--params", str(tmp_path / "missing.json")]) == 2
    cap = capsys.readouterr()
    assert cap.out == "" and "frictionlaw-demo: error: --params" in cap.err
    assert law_demo.main(["--p-hist", "-1"]) == 2
    assert "--p-hist must be" in capsys.readouterr().err
    assert law_demo.main([]) == 0
    assert "Eq. 25 jump" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv",
    [
        ["frictionlaw-demo"],
        ["halfspace-calib", "--help"],
        ["fe-demo", "--help"],
        ["frictionlaw-export", "--help"],
    ],
)
def test_a_reader_that_stops_early_gets_no_traceback(argv):
    """``command | head -1``: the reader closes the pipe after one line; the command stops
    writing, exits 0 and says nothing on stderr (``frictionlaw-demo`` printed a BrokenPipeError
    traceback and exited 1)."""
    import shutil
    import subprocess
    import sys

    exe = shutil.which(argv[0]) or str(Path(sys.executable).with_name(argv[0]))
    with subprocess.Popen([exe, *argv[1:]], stdout=subprocess.PIPE, stderr=subprocess.PIPE) as proc:
        proc.stdout.readline()
        proc.stdout.close()  # the reader goes away
        err = proc.stderr.read().decode()
        code = proc.wait(timeout=120)
    assert code == 0 and err == "", err


def test_the_law_demo_shows_a_flattening_block(capsys):
    """A file with a flattening block: its slope, beta and the contact fraction after strain,
    equal to ``flattening_curve``; the header without an empty parenthesis for tabulated forms."""
    from fe_demo.scenes.laws import EXAMPLE_FLATTENING_PATH
    from frictionlaw import FrictionParams, flattening_curve

    assert law_demo.main(["--params", str(EXAMPLE_FLATTENING_PATH)]) == 0
    out = capsys.readouterr().out
    assert "()" not in out.splitlines()[0]
    P = FrictionParams.from_json(EXAMPLE_FLATTENING_PATH)
    assert f"tan(theta) = {P.flattening.slope:.4g}, beta = 1;" in out
    row = next(ln for ln in out.splitlines() if ln.split()[:1] == ["0.3"])
    want = flattening_curve(0.3 * P.H, law_demo.FLAT_STRAINS, P)
    assert [float(v) for v in row.split()[1:]] == pytest.approx(want, abs=5e-4)


def test_fe_demo_output_folder_appears_whole(tmp_path, capsys):
    out = tmp_path / "ups"
    assert (
        fe_cli.main(["upsetting", *_fast("--increments"), "--increments", "5", "--out", str(out)])
        == 0
    )
    assert sorted(p.name for p in (out / "vtu").glob("*.vtu"))[-1] == "step_0005.vtu"
    assert _fe(out, "--increments", "2") == 0
    vtu = sorted(p.name for p in (out / "vtu").glob("*.vtu"))
    pvd = (out / "vtu" / "step.pvd").read_text()
    assert vtu == ["step_0000.vtu", "step_0001.vtu", "step_0002.vtu"]  # no stale steps
    assert pvd.count("<DataSet") == len(vtu)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ups"]  # no temporary folder left
    # a folder holding something else is refused before any work, and left alone
    other = tmp_path / "other"
    other.mkdir()
    (other / "notes.txt").write_text("mine")
    assert _fe(other) == 2
    assert "holds no fe-demo output" in capsys.readouterr().err
    assert [p.name for p in other.iterdir()] == ["notes.txt"]
    capsys.readouterr()


def test_fe_demo_failed_write_keeps_the_previous_output(tmp_path, capsys, monkeypatch):
    out = tmp_path / "ups"
    assert _fe(out) == 0
    before = (out / "history.csv").read_bytes()

    def broken(*a, **k):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(fe_runs, "write_history_csv", broken)
    assert _fe(out, "--increments", "2") == 1
    err = capsys.readouterr().err
    assert "No space left" in err and "unchanged" in err and "Traceback" not in err
    assert (out / "history.csv").read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ups"]


def test_output_folder_policy(tmp_path):
    out = tmp_path / "o"
    with OutputFolder(out, command="thing", what="thing") as f:
        (f.tmp / "m.json").write_text("1")
        (f.tmp / "old.txt").write_text("1")
        f.commit()
    with OutputFolder(out, command="thing", what="thing") as f:
        (f.tmp / "m.json").write_text("2")
        f.commit()
    assert sorted(p.name for p in out.iterdir()) == [".sbmf-output.json", "m.json"]
    with OutputFolder(out, command="thing", what="thing") as f:
        (f.tmp / "m.json").write_text("3")  # no commit: discarded
    assert (out / "m.json").read_text() == "2"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o"]
    (tmp_path / "x").mkdir()
    (tmp_path / "x" / "y").write_text("")
    with pytest.raises(ValueError, match="holds no thing"):
        OutputFolder(tmp_path / "x", command="thing", what="thing")
    with pytest.raises(ValueError, match="not a folder"):
        OutputFolder(tmp_path / "x" / "y", command="thing", what="thing")
    # force never deletes a folder the command did not write
    with pytest.raises(ValueError, match="holds no thing"):
        OutputFolder(tmp_path / "x", command="thing", what="thing", force=True)
    assert (tmp_path / "x" / "y").is_file()


@pytest.mark.parametrize("name", sorted(PARSERS))
def test_a_value_option_given_twice_is_refused_in_every_command(name, capsys):
    """argparse keeps the last of ``--opt A --opt B`` without a word; every command (and each
    subcommand) refuses the repetition instead, naming the option (exit 2)."""
    from sbmf_cli._options import _StoreOnce

    parsers = _all_parsers(PARSERS[name]())
    stores = [a for p in parsers for a in p._actions if isinstance(a, argparse._StoreAction)]
    assert stores and all(type(a) is _StoreOnce for a in stores)
    option = {
        "halfspace-calib": ["--grid", "16", "--grid", "32"],
        "fe-demo": ["upsetting", "--nr", "4", "--nr", "8"],
        "frictionlaw-export": ["calculix", "--out", "a", "--out", "b"],
        "frictionlaw-demo": ["--params", "a.json", "--params", "b.json"],
    }[name]
    with pytest.raises(SystemExit) as e:
        PARSERS[name]().parse_args(option)
    assert e.value.code == 2
    assert f"argument {option[-2]}: given more than once" in capsys.readouterr().err
