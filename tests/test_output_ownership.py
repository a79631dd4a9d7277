"""Output folders belong to the command that wrote them (issue: nothing of a user's lost).

Every case here lost files or replaced another command's output before the ownership marker:
a command replaces a folder only if its marker names that command and the folder holds nothing
but what that run wrote; another command's output, a user's file (also one level down), a folder
without a marker, and a folder holding the run's own input are refused with exit 2, naming what is
in the way, and left untouched; ``--force`` changes none of that. Folders follow the umask.
"""

import json
import os
import stat

import pytest

from fe_demo.cli import main as fe_demo
from frictionlaw.export.cli import main as export
from halfspace_calib.cli import main as calib
from sbmf_cli import MARKER, OutputFolder, lock_path, read_marker

CALIB = [
    "--grid", "16",
    "--pressures", "1e8,2e8,3e8,5e8",
    "--reload-fractions", "0.3,0.6",
    "--heldout-tol", "0.5",  # a toy grid: the acceptance is tested in test_failed_fit
    "--first-loading-form", "eq24",  # the export (below) carries Eq. 24
    "--quiet",
]  # fmt: skip
FE = ["upsetting", "--nr", "4", "--increments", "2", "--vtu-every", "0", "--quiet"]


def _tree(folder):
    """Every file below ``folder`` with its bytes (to show a refused run changed nothing)."""
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


@pytest.fixture(scope="module")
def calibration(tmp_path_factory):
    out = tmp_path_factory.mktemp("c") / "calibration"
    assert calib([*CALIB, "--out", str(out)]) == 0
    return out


def test_a_users_folder_holding_a_calibration_is_not_wiped(calibration, tmp_path, capsys):
    # the user's folder: a calibration one level down and their notes (issue case 1)
    user = tmp_path / "project"
    user.mkdir()
    (user / "notes.txt").write_text("my notes")
    os.system(f"cp -r {calibration} {user / 'calibration'}")
    before = _tree(user)
    assert fe_demo([*FE, "--law", "tresca", "--out", str(user)]) == 2
    err = capsys.readouterr().err
    assert "holds no fe-demo output" in err and "notes.txt" in err and "Traceback" not in err
    assert _tree(user) == before


def test_fe_demo_does_not_replace_a_calibration(calibration, capsys):
    before = _tree(calibration)
    assert fe_demo([*FE, "--law", "tresca", "--out", str(calibration)]) == 2
    err = capsys.readouterr().err
    assert "holds the output of halfspace-calib" in err
    assert _tree(calibration) == before


def test_halfspace_calib_does_not_replace_an_fe_demo_output(tmp_path, capsys):
    fe = tmp_path / "fe"
    assert fe_demo([*FE, "--law", "tresca", "--out", str(fe)]) == 0
    before = _tree(fe)
    assert calib([*CALIB, "--out", str(fe)]) == 2
    assert "holds the output of fe-demo" in capsys.readouterr().err
    assert _tree(fe) == before


def test_own_output_with_a_users_file_one_level_down_is_refused(tmp_path, capsys):
    fe = tmp_path / "fe"
    assert fe_demo([*FE, "--law", "tresca", "--out", str(fe)]) == 0
    sub = (
        next(p for p in fe.iterdir() if p.is_dir()) if any(p.is_dir() for p in fe.iterdir()) else fe
    )
    (sub / "my_plot_notes.txt").write_text("keep me")
    before = _tree(fe)
    assert fe_demo([*FE, "--law", "tresca", "--out", str(fe)]) == 2
    err = capsys.readouterr().err
    assert "did not write" in err and "my_plot_notes.txt" in err
    assert _tree(fe) == before
    # without the stranger the command replaces its own output, whole
    (sub / "my_plot_notes.txt").unlink()
    assert fe_demo([*FE, "--law", "tresca", "--out", str(fe)]) == 0
    assert read_marker(fe)["command"] == "fe-demo"


def test_export_force_never_deletes_its_own_input(calibration, tmp_path, capsys):
    folder = tmp_path / "X"
    os.system(f"cp -r {calibration} {folder}")
    before = _tree(folder)
    params = folder / "params.json"
    rc = export(["abaqus-fric", "--params", str(params), "--out", str(folder), "--force"])
    assert rc == 2
    assert "holds the input" in capsys.readouterr().err
    assert _tree(folder) == before


def test_export_force_replaces_only_its_own_export(calibration, tmp_path, capsys):
    out = tmp_path / "fric"
    params = str(calibration / "params.json")
    assert export(["abaqus-fric", "--params", params, "--out", str(out)]) == 0
    assert read_marker(out)["command"] == "frictionlaw-export"
    assert export(["abaqus-fric", "--params", params, "--out", str(out)]) == 2  # needs --force
    assert "--force" in capsys.readouterr().err
    assert export(["abaqus-fric", "--params", params, "--out", str(out), "--force"]) == 0
    (out / "model.inp").write_text("*HEADING\n")  # the user's deck beside the routine
    before = _tree(out)
    assert export(["abaqus-fric", "--params", params, "--out", str(out), "--force"]) == 2
    assert "model.inp" in capsys.readouterr().err
    assert _tree(out) == before


def test_marker_names_command_version_and_every_file(calibration):
    doc = json.loads((calibration / MARKER).read_text())
    assert doc["command"] == "halfspace-calib" and doc["version"]
    on_disk = sorted(
        p.relative_to(calibration).as_posix()
        for p in calibration.rglob("*")
        if p.is_file() and p.name != MARKER
    )
    assert sorted(doc["files"]) == on_disk


def test_output_folders_follow_the_umask(tmp_path):
    old = os.umask(0o022)
    try:
        with OutputFolder(tmp_path / "o", command="t", what="t") as f:
            (f.tmp / "a").write_text("1")
            f.commit()
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "o").stat().st_mode) == 0o755


RING_FIT = ["--nr", "8", "--increments", "20", "--illustrative", "--quiet"]


@pytest.fixture(scope="module")
def ring_fit_out(tmp_path_factory):
    """A ring fit's output folder (the synthetic example rings, coarse mesh)."""
    from fe_demo.scenes.laws import EXAMPLE_PARAMS_PATH

    rings = EXAMPLE_PARAMS_PATH.with_name("ring_example.csv")
    out = tmp_path_factory.mktemp("rf") / "ring_fit"
    assert fe_demo(["ring-fit", "--measured", str(rings), *RING_FIT, "--out", str(out)]) == 0
    return out, rings


def test_markers_name_the_subcommand(ring_fit_out):
    out, _ = ring_fit_out
    doc = read_marker(out)
    assert doc["command"] == "fe-demo" and doc["subcommand"] == "ring-fit"


def test_one_subcommand_does_not_replace_anothers_output(ring_fit_out, tmp_path, capsys):
    """upsetting deleted a ring fit's params.json and report; ring-fit an upsetting's VTU."""
    out, rings = ring_fit_out
    before = _tree(out)
    assert fe_demo([*FE, "--law", "tresca", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "holds the output of fe-demo ring-fit, not of fe-demo upsetting" in err
    assert fe_demo([*FE, "--law", "tresca", "--out", str(out), "--force"]) == 2  # force or not
    assert _tree(out) == before
    ups = tmp_path / "ups"
    every = [*FE[: FE.index("--vtu-every")], *FE[FE.index("--vtu-every") + 2 :]]
    assert fe_demo([*every, "--law", "tresca", "--vtu-every", "1", "--out", str(ups)]) == 0
    before = _tree(ups)
    assert fe_demo(["ring-fit", "--measured", str(rings), *RING_FIT, "--out", str(ups)]) == 2
    assert (
        "holds the output of fe-demo upsetting, not of fe-demo ring-fit" in capsys.readouterr().err
    )
    assert _tree(ups) == before


def test_an_old_marker_naming_no_subcommand_is_replaced_only_with_force(tmp_path, capsys):
    old = tmp_path / "old"
    old.mkdir()
    (old / "history.csv").write_text("height_reduction,force_N\n")
    (old / MARKER).write_text(
        json.dumps({"command": "fe-demo", "version": "0.1.0", "files": ["history.csv"]})
    )
    before = _tree(old)
    assert fe_demo([*FE, "--law", "tresca", "--out", str(old)]) == 2
    err = capsys.readouterr().err
    assert "marker names no subcommand" in err and "--force" in err
    assert _tree(old) == before
    assert fe_demo([*FE, "--law", "tresca", "--out", str(old), "--force"]) == 0
    assert read_marker(old)["subcommand"] == "upsetting"


HOLD = """
import sys, time
from sbmf_cli import OutputFolder
folder = OutputFolder(sys.argv[1], command="halfspace-calib", what="calibration output")
print("holding", flush=True)
time.sleep(60)
"""


def test_a_folder_another_running_command_writes_is_refused_naming_it(tmp_path, capsys):
    """Two runs on one --out at once: the second exits 2 naming the first's process; once that
    process has ended (here: killed, its lock left behind) the lock is stale and taken over."""
    import subprocess
    import sys

    out = tmp_path / "cal"
    holder = subprocess.Popen(
        [sys.executable, "-c", HOLD, str(out)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert holder.stdout.readline().strip() == "holding"
        assert calib([*CALIB, "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert "is being written by another run: halfspace-calib" in err
        assert f"process {holder.pid}" in err and "Traceback" not in err
        with pytest.raises(ValueError, match=f"process {holder.pid}"):
            OutputFolder(out, command="fe-demo", what="fe-demo output")
    finally:
        holder.kill()
        holder.wait()
        holder.stdout.close()
    assert lock_path(out).is_file()  # left by the killed run
    assert calib([*CALIB, "--out", str(out)]) == 0
    assert not lock_path(out).exists()  # released at the end
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cal"]


def test_two_folders_of_one_process_on_one_out_are_refused(tmp_path):
    with OutputFolder(tmp_path / "o", command="t", what="t") as first:
        with pytest.raises(ValueError, match=f"process {os.getpid()}"):
            OutputFolder(tmp_path / "o", command="t", what="t")
        first.commit()
    with OutputFolder(tmp_path / "o", command="t", what="t") as again:  # released: free
        again.commit()
