"""Issue 39: load levels where alpha changes against the fixed default levels.

Each case is calibrated twice in one process, as a user would (``calibrate(scene)`` after a JIT
warm-up): with the fixed default levels (``adaptive_levels=False``: 11 levels 10-760 MPa, 8
reload histories from 100 MPa) and with the levels the refinement places
(:mod:`halfspace_calib.pipeline.sweep.levels`, the default). Per run: the levels and reload histories
computed, the levels with ``alpha < 0.99`` and with ``alpha >= 0.995``, the CG iterations of the
normal solves, the transforms counted in this process (as FFT pairs of the grid; a sweep on 2 processes,
the default at 512^2, makes its transforms in the workers: counted on 1 process) and the wall time in FFT pairs
(the fastest ``rfft2 + irfft2`` of the grid timed in the same process, 1 thread or all:
``bench_calibration_cost.py``'s unit), the held-out errors of both branches (the run's own
leave-one-level-out), the largest relative change of the first loading the law runs at the
fixed levels, and whether the run passed its acceptance. A third run per case, the adaptive
levels at the solver's own tolerance 1e-8 instead of the scene's default 1e-6
(:data:`~halfspace_calib.pipeline.sweep.scene.SCENE_TOL`), gives the tolerance's trade: its
iterations and time, and the largest ``|d alpha|`` between the two runs over the points both
computed (first loading and reload).

Cases: the default synthetic scene at ``--grid`` (the issue's cost case: 512), metropro-1.dat
against itself (a nearly conforming pair in full contact by about 50 MPa: ``alpha`` 0.66 at
10 MPa at 64^2) and each shipped file against the synthetic default tool at ``--file-grid``
(files without the resolution check, to keep the run short; the check runs at the main run's
levels).

Run: python benchmarks/adaptive_levels.py [--grid 512] [--file-grid 128] [--folder DIR]
Writes benchmarks/results/adaptive_levels.csv / .md and prints the table.
"""

import argparse
import dataclasses
import time
from pathlib import Path

import bench_calibration_cost as cost
import numpy as np
from _provenance import RESULTS, run_record, write_rows

from frictionlaw import alpha_first
from halfspace_calib.pipeline.calibration import Scene, calibrate
from halfspace_calib.pipeline.sweep.resolution import alpha_points
from halfspace_calib.pipeline.sweep.scene import DEFAULT_PRESSURES

FILES = ["metropro-1.dat", "mnt-1.mnt", "x3p-2.x3p", "sur-3.sur", "matrix-3.txt"]
COLUMNS = [
    ("case", "case"),
    ("levels", "levels"),
    ("n_levels", "levels computed"),
    ("n_hist", "reload histories"),
    ("below_099", "levels alpha < 0.99"),
    ("full", "levels alpha >= 0.995"),
    ("nit", "CG iterations"),
    ("counted", "counted FFT pairs"),
    ("pairs", "wall FFT pairs"),
    ("first_held", "first loading held out"),
    ("reload_held", "reload held out"),
    ("first_change", "first loading change vs fixed"),
    ("tol_dalpha", "max d alpha vs tol 1e-8"),
    ("exit", "exit"),
]


def _run(case, scene, unit, fixed_law=None):
    cost.COUNTS.clear()
    t0 = time.perf_counter()
    cal = calibrate(scene, progress=False)
    seconds = time.perf_counter() - t0
    lv = cal.sweeps.levels
    a = np.array([x.loading.alpha for x in lv])
    e = cal.errors
    row = {
        "case": case,
        "levels": " ".join(f"{x.p_hist / 1e6:.4g}" for x in lv),
        "n_levels": len(lv),
        "n_hist": sum(1 for x in lv if x.reload),
        "below_099": int(np.sum(a < 0.99)),
        "full": int(np.sum(a >= 0.995)),
        "nit": sum(x.loading.nit for x in lv) + sum(r.nit for x in lv for r in x.reload),
        "counted": 0.5 * sum(cost.COUNTS.values()),
        "pairs": seconds / unit,
        "first_held": e["first_loading"].deciding,
        "reload_held": e["reload"].deciding,
        "first_change": "",
        "tol_dalpha": "",
        "exit": 1 if cal.problems() else 0,
    }
    if fixed_law is not None:
        P = np.array(sorted(p for p in DEFAULT_PRESSURES if p < scene.H))
        a_fix, a_new = alpha_first(P, fixed_law), alpha_first(P, cal.params)
        row["first_change"] = float(np.max(np.abs(a_new / a_fix - 1)))
    return row, cal


def tol_dalpha(a, b):
    """Largest ``|d alpha|`` of two calibrations over the points both computed."""
    pa, pb = alpha_points(a.sweeps), alpha_points(b.sweeps)
    common = set(pa) & set(pb)
    return max(abs(pa[k] - pb[k]) for k in common) if common else float("nan")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grid", type=int, default=512)
    ap.add_argument("--file-grid", type=int, default=128)
    ap.add_argument("--folder", default="/work/shared/surfaces")
    ap.add_argument("--files", default=",".join(FILES))
    args = ap.parse_args(argv)
    cost.install_counters()
    calibrate(Scene(grid=16), progress=False)  # JIT warm-up
    rows = []
    S = Path(args.folder)
    cases = [
        (f"default-{args.grid}", Scene(grid=args.grid), args.grid),
        (f"default-{args.grid} 1 process", Scene(grid=args.grid, workers=1), args.grid),
    ]
    cases.append(
        (
            "metropro-1.dat x itself",
            Scene(
                workpiece=str(S / "metropro-1.dat"),
                tool=str(S / "metropro-1.dat"),
                grid=args.file_grid,
                resolution_check=False,
            ),
            args.file_grid,
        )
    )
    for f in [x for x in args.files.split(",") if x]:
        kw = {"max_undefined": 0.95} if f.startswith("sur-3") else {}
        sc = Scene(workpiece=str(S / f), grid=args.file_grid, resolution_check=False, **kw)
        cases.append((f"{f} x tool", sc, args.file_grid))
    for case, scene, grid in cases:
        unit = cost.pair_seconds((grid, grid))
        fixed, fcal = _run(case + " fixed", dataclasses.replace(scene, adaptive_levels=False), unit)
        new, ncal = _run(case + " adaptive", scene, unit, fcal.params)
        new["pairs_ratio"] = new["pairs"] / fixed["pairs"]
        tight, tcal = _run(
            case + " adaptive, tol 1e-8", dataclasses.replace(scene, tol=1e-8), unit, fcal.params
        )
        tight["pairs_ratio"] = tight["pairs"] / fixed["pairs"]
        new["tol_dalpha"] = tight["tol_dalpha"] = tol_dalpha(ncal, tcal)
        for r in (fixed, new, tight):
            rows.append(r)
            print(" | ".join(_fmt(r[k]) for k, _ in COLUMNS), flush=True)
    keys = [k for k, _ in COLUMNS] + ["pairs_ratio"]
    write_rows(RESULTS / "adaptive_levels.csv", rows, keys)
    md = [
        "# Load levels where alpha changes (adaptive) against the fixed default levels",
        "",
        "| " + " | ".join(t for _, t in COLUMNS) + " | wall pairs / fixed |",
        "|" + "---|" * (len(COLUMNS) + 1),
    ]
    for r in rows:
        md.append("| " + " | ".join(_fmt(r.get(k, "")) for k in keys) + " |")
    (RESULTS / "adaptive_levels.md").write_text("\n".join(md) + "\n")
    print(RESULTS / "adaptive_levels.md")


def _fmt(v):
    return f"{v:.4g}" if isinstance(v, float) else str(v)


if __name__ == "__main__":
    with run_record(__file__):
        main()
