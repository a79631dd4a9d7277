"""Interrupts end a run cleanly: Ctrl-C, SIGINT to the main process alone, and SIGTERM.

A two-process calibration (``--workers 2``) is started in its own process group; once both
workers are computing, the signal is sent (to the group for Ctrl-C, to the main process alone as
``timeout -s INT`` does, or SIGTERM as ``kill`` does). The run must end within a few seconds with
130 / 143, print one line saying what was interrupted and no traceback, leave no worker
running, and leave an earlier output in ``--out`` untouched (no half-written folder beside it).
"""

import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from sbmf_cli import version

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


# -- Ctrl-C in the first seconds: during the imports of NumPy, SciPy, numba, before the run --
EXAMPLE = Path(__file__).resolve().parents[1] / "fe_demo" / "data"
STARTUP = {
    "halfspace-calib": (["-m", "halfspace_calib"], [], "during the calibration"),
    "fe-demo upsetting": (["-m", "fe_demo"], ["upsetting"], "during the FE run"),
    "fe-demo ring-fit": (
        ["-m", "fe_demo"],
        # a calibration's file (the example law's numbers) and rings that state their test
        [
            "ring-fit",
            "--measured",
            str(EXAMPLE / "ring_example.csv"),
            "--params",
            str(EXAMPLE / "sbmf_example.json"),
        ],
        "during the FE run",
    ),
}


@pytest.mark.parametrize("after", [0.3, 0.8, 1.5])
@pytest.mark.parametrize("command", sorted(STARTUP))
def test_ctrl_c_at_any_moment_after_start_up_is_one_line_and_130(command, after, tmp_path):
    """Ctrl-C 0.3, 0.8 and 1.5 s after the start: one line on stderr, exit 130, nothing else.

    At 0.3 s the interpreter is importing NumPy / SciPy / numba (the commands' light entry
    points, ``halfspace_calib.__main__`` and ``fe_demo.__main__``, handle the signal already);
    at 1.5 s a run may have begun.
    """
    module, args, what = STARTUP[command]
    cmd = [sys.executable, *module, *args, "--no-progress", "--out", str(tmp_path / "out")]
    proc = subprocess.Popen(
        cmd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=tmp_path,
        start_new_session=True,
        preexec_fn=_default_sigint,
    )
    time.sleep(after)
    if proc.poll() is not None:
        pytest.fail(f"{command} ended before {after} s: {proc.communicate()}")
    os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C: the terminal signals the foreground group
    try:
        _, stderr = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        pytest.fail(f"{command}: did not stop within 30 s of Ctrl-C at {after} s")
    assert proc.returncode == 130, (command, after, proc.returncode, stderr)
    lines = stderr.splitlines()
    assert len(lines) == 1, f"{command} at {after} s: {stderr}"
    assert "interrupted by SIGINT" in lines[0] and what in lines[0], lines[0]
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "command",
    [
        ["-m", "halfspace_calib"],
        ["-m", "fe_demo"],
        ["-m", "frictionlaw.export"],
        ["-m", "frictionlaw"],
    ],
)
def test_version_answers_at_once(command):
    """``--version`` of every command answers before the heavy imports: best of 3 under 2 s
    here (a generous bound for a shared machine; measured 0.09-0.47 s, docs/architecture.md)."""
    best = math.inf
    for _ in range(3):
        t0 = time.perf_counter()
        run = subprocess.run(
            [sys.executable, *command, "--version"], capture_output=True, text=True, check=False
        )
        best = min(best, time.perf_counter() - t0)
        assert run.returncode == 0 and run.stdout.strip().endswith(version()), run
    assert best < 2.0, f"{command}: --version took {best:.2f} s"


SWALLOWED = r"""
import os, signal, sys, time
from sbmf_cli import interruptible

class Swallow:
    def __del__(self):  # the handler's exception is raised in here, and Python ignores it
        os.kill(os.getpid(), signal.SIGINT)
        for _ in range(100000):
            pass

@interruptible("demo", "the demo")
def main(argv):
    Swallow()
    print("went on", flush=True)  # the interrupt raised in __del__ did not stop main
    t0 = time.monotonic()
    while time.monotonic() - t0 < 10:
        time.sleep(0.01)
    return 0

sys.exit(main())
"""


def test_an_interrupt_python_swallowed_is_delivered_again(tmp_path):
    """An interrupt raised where Python ignores exceptions (a ``__del__``, the import system's
    weakref callbacks) is sent again once the run goes on: 130 within a second, not 0 after 10 s;
    the swallowed one is not printed ("Exception ignored" with a traceback, e.g. from the
    ``logging`` module's after-fork hook when a SIGINT arrives while a pool worker is forked)."""
    t0 = time.monotonic()
    run = subprocess.run(
        [sys.executable, "-c", SWALLOWED],
        capture_output=True,
        text=True,
        timeout=30,
        preexec_fn=_default_sigint,
        check=False,
    )
    took = time.monotonic() - t0
    assert "went on" in run.stdout  # the first one was swallowed
    assert "Exception ignored" not in run.stderr and "Traceback" not in run.stderr, run.stderr
    assert run.returncode == 130 and took < 5, (run.returncode, took, run.stderr)
    lines = [ln for ln in run.stderr.splitlines() if "interrupted by SIGINT" in ln]
    assert lines == ["demo: interrupted by SIGINT during the demo; the output folder was not "
                     "written (an earlier output there is unchanged)"]  # fmt: skip


def test_an_interrupt_waits_for_numba_to_finish_compiling():
    """Inside numba's compiler (its lock held) the handler records the signal and does not
    raise: an exception there left a half-built library ("no compiled object yet") or a
    segmentation fault. Outside, it raises. (A dummy watcher: no signal is sent again here.)"""
    from numba.core.compiler_lock import global_compiler_lock

    from sbmf_cli._processes import _Interrupts, numba_compiling

    handler = _Interrupts()
    handler.watcher = object()  # the real watcher would send SIGINT to this test process
    assert not numba_compiling()
    with global_compiler_lock:
        assert numba_compiling()
        handler(signal.SIGINT, None)  # held back
        assert handler.signum == signal.SIGINT
    with pytest.raises(KeyboardInterrupt):
        handler(signal.SIGINT, None)
    handler.handled = True


def test_an_interrupt_wrapped_in_another_exception_is_still_the_interrupt(capsys):
    """Python wraps an exception raised in a class body's ``__set_name__`` in a RuntimeError: an
    error escaping the run after a signal arrived is reported as the interrupt, one line, 130;
    without a signal it propagates unchanged."""
    from sbmf_cli import interruptible

    # the run installs its handler only over Python's default one: give it that here (a runner
    # may start its processes with another, e.g. SIGINT ignored in a background job), and put
    # back what was there
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        _wrapped_interrupt(interruptible, capsys)
    finally:
        signal.signal(signal.SIGINT, before)


def _wrapped_interrupt(interruptible, capsys):
    def main(argv=None):
        signal.raise_signal(signal.SIGINT)  # caught by the run's handler, raised here ...
        return 0

    class Named:
        def __set_name__(self, owner, name):
            raise KeyboardInterrupt

    def wrapped(argv=None):
        try:
            main(argv)
        except KeyboardInterrupt:
            type("Owner", (), {"field": Named()})  # ... and raised again inside __set_name__
        return 0

    assert interruptible("prog", "during the test")(wrapped)() == 130
    assert capsys.readouterr().err.count("\n") == 1

    @interruptible("prog", "during the test")
    def failing(argv=None):
        raise RuntimeError("a real error")

    with pytest.raises(RuntimeError, match="a real error"):
        failing()
