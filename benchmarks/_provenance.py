"""Run record for every benchmark: which commit, which machine, how long, which files.

Each benchmark script ends with::

    if __name__ == "__main__":
        with run_record(__file__):
            main()

and ``benchmarks/results/<script>.run.json`` then says which git commit (and whether the tree had
uncommitted changes), which machine and library versions produced the result files written during
the run, the command line and the wall time. Results from different commits or machines are not
comparable; this file is how a reader tells.
"""

import contextlib
import json
import math
import os
import platform
import subprocess
import sys
import time
from datetime import UTC, datetime
from pathlib import Path

RESULTS = Path(__file__).resolve().parent / "results"
ROOT = Path(__file__).resolve().parents[1]


def _git(*args):
    try:
        out = subprocess.run(
            ["git", *args], cwd=ROOT, capture_output=True, text=True, timeout=10, check=True
        )
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.strip()


def commit():
    """The short hash of the checked-out commit (``"unknown"`` outside git)."""
    return _git("rev-parse", "--short", "HEAD") or "unknown"


def law_fields(cal):
    """A calibration's law and fit quality as result-table columns."""
    P = cal.params
    return {
        "mu_eff": P.mu_eff,
        "C1": P.C1,
        "n1": P.n1,
        "C2": P.C2,
        "n2": P.n2,
        "r2_first": cal.first.r_squared,
        "r2_reload": cal.reload.r_squared,
    }


def pct(v):
    """A fraction as ``"12.3 %"``; ``"-"`` for a missing (non-numeric) or non-finite value."""
    ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
    return f"{100 * v:.1f} %" if ok else "-"


def write_rows(path, rows, fieldnames=None):
    """Write dict ``rows`` as CSV (columns: ``fieldnames`` or the first row's keys)."""
    import csv

    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(fieldnames or rows[0]))
        w.writeheader()
        w.writerows(rows)


def write_report(stem, rows, lines):
    """``results/<stem>.csv`` from ``rows`` and ``results/<stem>.md`` from ``lines``, printed."""
    write_rows(RESULTS / f"{stem}.csv", rows)
    text = "\n".join(lines)
    (RESULTS / f"{stem}.md").write_text(text + "\n", encoding="utf-8")
    print(text)


def read_rows(path):
    """The rows of the CSV at ``path`` as dicts of strings (what :func:`write_rows` wrote); none
    if there is no file."""
    import csv

    if not Path(path).exists():
        return []
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def _cpu_model():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _versions():
    out = {"python": platform.python_version()}
    for name in ("numpy", "scipy", "numba", "skfem"):
        with contextlib.suppress(ImportError):
            out[name] = __import__(name).__version__
    return out


def machine():
    """The machine and library versions, JSON-ready."""
    return {
        "hostname": platform.node(),
        "platform": platform.platform(),
        "cpu": _cpu_model(),
        "cpu_count": os.cpu_count(),
        "versions": _versions(),
    }


@contextlib.contextmanager
def run_record(script, stem=None):
    """Write ``results/<stem>.run.json`` after the block (also when it fails).

    ``stem`` defaults to the script's; a mode that writes other results than the script's
    default run names its own, so that the default run's record is kept.

    A block that exits (``SystemExit``: ``--help``, a usage error) before writing any result
    ran nothing: the earlier run's record is kept.
    """
    t0_wall, t0 = time.time(), time.perf_counter()
    status = "failed"
    exited = False
    try:
        yield
        status = "completed"
    except SystemExit:
        exited = True
        raise
    finally:
        written = sorted(
            str(p.relative_to(RESULTS))
            for p in RESULTS.rglob("*")
            if p.is_file() and p.stat().st_mtime >= t0_wall - 1 and not p.name.endswith(".run.json")
        )
        if not (exited and not written):
            _write_record(script, status, t0_wall, t0, written, stem)


def _write_record(script, status, t0_wall, t0, written, stem=None):
    """The run record of :func:`run_record` (the files the run wrote, its status and machine)."""
    record = {
        "script": f"benchmarks/{Path(script).name}",
        "command": " ".join([Path(sys.executable).name, *sys.argv]),
        "status": status,
        "started_utc": datetime.fromtimestamp(t0_wall, UTC).isoformat(timespec="seconds"),
        "wall_seconds": round(time.perf_counter() - t0, 2),
        "git_commit": _git("rev-parse", "HEAD"),
        "git_dirty": bool(_git("status", "--porcelain", "--untracked-files=no")),
        "machine": machine(),
        "files_written": written,
    }
    RESULTS.mkdir(exist_ok=True)
    path = RESULTS / f"{stem or Path(script).stem}.run.json"
    path.write_text(json.dumps(record, indent=1) + "\n")
    print(f"run record: {path.relative_to(ROOT)}")
