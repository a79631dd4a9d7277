"""Interrupts end a run cleanly: Ctrl-C, SIGINT to the main process alone, and SIGTERM.

A two-process calibration (``--workers 2``) is started in its own process group; once both
workers are computing, the signal is sent (to the group for Ctrl-C, to the main process alone as
``timeout -s INT`` does, or SIGTERM as ``kill`` does). The run must end within a few seconds with
130 / 143, print one line saying what was interrupted and no traceback, leave no worker
running, and leave an earlier output in ``--out`` untouched (no half-written folder beside it).
"""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="uses /proc")

# a grid large enough that each load level takes seconds, so the run is mid-sweep when signalled
RUN = ["--grid", "384", "--workers", "2", "--no-progress"]


def _children(pid):
    """PIDs whose parent is ``pid`` (from /proc)."""
    out = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        ppid = int(stat.rsplit(")", 1)[1].split()[1])
        if ppid == pid:
            out.append(int(entry.name))
    return out


def _alive(pid):
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def _default_sigint():
    signal.signal(signal.SIGINT, signal.SIG_DFL)  # as an interactive shell starts a command


def _start(out):
    cmd = [sys.executable, "-m", "halfspace_calib", *RUN, "--out", str(out)]
    proc = subprocess.Popen(
        cmd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group, as a terminal's foreground job
        preexec_fn=_default_sigint,
    )
    t0 = time.monotonic()
    while time.monotonic() - t0 < 120:
        kids = _children(proc.pid)
        if len(kids) >= 2:
            time.sleep(1.0)  # both workers computing
            return proc, kids
        if proc.poll() is not None:
            break
        time.sleep(0.1)
    proc.kill()
    pytest.fail(f"the two-process run did not start its workers: {proc.communicate()}")


@pytest.fixture
def earlier(tmp_path):
    """An earlier calibration output in --out that an interrupted run must leave as it was."""
    out = tmp_path / "calibration"
    from halfspace_calib.cli import main

    rc = main(
        [
            "--grid",
            "16",
            "--pressures",
            "1e8,2e8,3e8,5e8",
            "--reload-fractions",
            "0.3,0.6",
            "--heldout-tol",
            "0.5",
            "--quiet",
            "--out",
            str(out),
        ]
    )  # fmt: skip (toy grid)
    assert rc == 0
    return out, {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}


@pytest.mark.parametrize(
    "how, code",
    [("ctrl-c", 130), ("sigint-main", 130), ("sigterm", 143)],
)
def test_signal_ends_a_two_process_run_cleanly(how, code, earlier):
    out, before = earlier
    proc, workers = _start(out)
    t0 = time.monotonic()
    if how == "ctrl-c":
        os.killpg(proc.pid, signal.SIGINT)
    elif how == "sigint-main":
        os.kill(proc.pid, signal.SIGINT)
    else:
        os.kill(proc.pid, signal.SIGTERM)
    try:
        stdout, stderr = proc.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        pytest.fail(f"{how}: the run did not stop within 20 s")
    took = time.monotonic() - t0
    assert proc.returncode == code, (how, proc.returncode, stderr)
    assert took < 10, f"{how}: took {took:.1f} s to stop"
    assert "Traceback" not in stderr and "KeyboardInterrupt" not in stderr, stderr
    lines = [ln for ln in stderr.splitlines() if "interrupted" in ln]
    assert len(lines) == 1 and "during the calibration" in lines[0], stderr
    deadline = time.monotonic() + 5
    while any(_alive(w) for w in workers) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not any(_alive(w) for w in workers), f"{how}: a worker outlived the run"
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()} == before
    assert sorted(p.name for p in out.parent.iterdir()) == ["calibration"]  # no temp folder left
