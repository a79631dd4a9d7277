"""Side-by-side ring figures: the GetFEM coupling against ``fe-demo ring``.

Runs ``couplings/getfem/ring.py`` in a Python that imports GetFEM (a subprocess:
Debian's ``python3-getfem`` is built against Debian's NumPy, not the project's)
and ``fe_demo.scenes.run_ring`` in this process, and interpolates both histories
at the requested height reductions.
"""

import csv
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

__all__ = ["getfem_python", "getfem_missing", "run_getfem_ring", "read_history", "at_reductions"]

ROOT = Path(__file__).resolve().parents[2]
RING = Path(__file__).resolve().with_name("ring.py")


def getfem_python():
    """Interpreter for the coupling: ``$FRICTIONLAW_GETFEM_PYTHON``, else ``/usr/bin/python3``."""
    return os.environ.get("FRICTIONLAW_GETFEM_PYTHON", "/usr/bin/python3")


def getfem_missing():
    """``None`` when the coupling can run, else the reason (for pytest's skip)."""
    py = getfem_python()
    if not Path(py).exists():
        return f"{py} not found (set FRICTIONLAW_GETFEM_PYTHON)"
    r = subprocess.run(
        [py, "-c", "import getfem, numba, scipy"], capture_output=True, text=True, check=False
    )
    if r.returncode:
        tail = r.stderr.strip().splitlines()[-1:] or ["?"]
        return (
            f"GetFEM coupling not runnable with {py} ({tail[0]}); install it with "
            "apt-get install -y python3-getfem python3-numba python3-scipy"
        )
    return None


def run_getfem_ring(out, args, timeout=3600):
    """Run the coupling script; returns (exit status, wall seconds, combined output)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    cmd = [getfem_python(), str(RING), "--out", str(out), *args]
    t0 = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout, check=False)
    return r.returncode, time.perf_counter() - t0, r.stdout + r.stderr


def read_history(path):
    """``history.csv`` as a dict of column -> array."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def at_reductions(hist, reductions):
    """Force (N) and inner-diameter change interpolated at the given height reductions."""
    red = np.concatenate([[0.0], hist["height_reduction"]])
    force = np.concatenate([[0.0], hist["force"]])
    d = np.concatenate([[0.0], hist["inner_diameter_change"]])
    if max(reductions) > red[-1] + 1e-9:
        raise ValueError(f"history ends at reduction {red[-1]:.4f} < {max(reductions)}")
    return np.interp(reductions, red, force), np.interp(reductions, red, d)


if __name__ == "__main__":
    print(getfem_missing() or f"GetFEM coupling runnable with {getfem_python()}")
    sys.exit(0)
