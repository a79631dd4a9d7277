"""Calibration from real instrument files: two grids, both periodicities, and the resolution check.

For each file in a folder of measured surfaces (the five files ``metropro-1.dat``, ``mnt-1.mnt``,
``x3p-2.x3p``, ``sur-3.sur``, ``matrix-3.txt`` of SurfaceTopography's public test set,
``test/file_format_examples/``), the file is used as workpiece and as tool (the composite
of a scan with itself), with the default scene otherwise (Table 1 materials, default pressures):

- the default calibration (the default S-filter ``lambda_s`` and grid of each file, the default
  boundary of files, with the resolution check): the time of the main run and of the check;
- the same scene at the default grid G and at G / 2, periodic and isolated (DC-FFT; without the
  check): mu_eff, C1, n1, C2, n2, the fits' R^2 and the wall time of each
  (``benchmarks/patch_boundary.py`` compares these with the mirror-symmetric boundary).

Writes ``benchmarks/results/measured_surfaces.csv`` and ``.md`` (the table of
``docs/measured_surfaces.md``) and prints the table. Run from the repository root::

    python benchmarks/measured_surfaces.py --folder FOLDER [--max-grid 256]

The sur-3 file (89 % undefined points) runs with ``max_undefined=0.95`` to show the fill; the
default policy refuses it.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import time
from pathlib import Path

from _provenance import RESULTS, commit, law_fields, write_rows

from halfspace_calib.pipeline.calibration import Scene, calibrate

FILES = ["metropro-1.dat", "mnt-1.mnt", "x3p-2.x3p", "sur-3.sur", "matrix-3.txt"]


def _row(name, cal, grid, periodic, seconds, kind):
    rec = cal.files[0]
    return {
        "file": name,
        "run": kind,
        "grid": grid,
        "lambda_s_um": cal.scene.lambda_s * 1e6 if cal.scene.lambda_s else 0.0,
        "element_um": cal.sweeps.surfaces["workpiece"].dx * 1e6,
        "periodic": periodic,
        **law_fields(cal),
        "seconds": seconds,
        "undefined_fraction": rec.undefined_fraction,
        "problems": len(cal.problems()),
    }


def run(folder, max_grid=None):
    rows, checks = [], []
    for name in FILES:
        path = Path(folder) / name
        if not path.is_file():
            print(f"skip {name}: not in {folder}")
            continue
        extra = {"max_undefined": 0.95} if name.startswith("sur-") else {}
        # one process (workers=1) so that the times compare with the other one-core tables
        base = Scene(workpiece=str(path), tool=str(path), workers=1, **extra)
        if max_grid is not None:
            from halfspace_calib.pipeline.sweep.scene_surfaces import load_scene_surfaces

            g = min(load_scene_surfaces(base).grid, max_grid)
            base = dataclasses.replace(base, grid=g)
        t0 = time.perf_counter()
        cal = calibrate(base, progress=False)
        total = time.perf_counter() - t0
        rc = cal.resolution
        g = cal.scene.grid
        checks.append(
            {
                "file": name,
                "grid": g,
                "lambda_s_um": cal.scene.lambda_s * 1e6 if cal.scene.lambda_s else 0.0,
                "seconds_total": total,
                "seconds_check": rc.seconds,
                "boundary": cal.scene.boundary,
                "check_share": rc.seconds / total,
                "warning": bool(rc.warning),
                "mu_eff_change": rc.params["mu_eff"][2] if rc.params else float("nan"),
                "alpha_change": rc.alpha_change,
            }
        )
        print(f"{name}: default grid {g}, {total:.1f} s (check {rc.seconds:.1f} s)")
        for grid in (g, g // 2):
            for periodic in (False, True):
                sc = dataclasses.replace(base, grid=grid, periodic=periodic, resolution_check=False)
                t0 = time.perf_counter()
                c = calibrate(sc, progress=False)
                dt = time.perf_counter() - t0
                rows.append(_row(name, c, grid, periodic, dt, "study"))
                r = rows[-1]
                print(
                    f"  grid {grid:4d} periodic={periodic!s:5}: mu_eff {r['mu_eff']:.4g}, "
                    f"C1 {r['C1']:.4g}, n1 {r['n1']:.4g}, C2 {r['C2']:.4g}, n2 {r['n2']:.4g}, "
                    f"{dt:.1f} s"
                )
    return rows, checks


def write(rows, checks, rev):
    RESULTS.mkdir(exist_ok=True)
    write_rows(RESULTS / "measured_surfaces.csv", rows)
    head = (
        f"commit {rev}, {platform.machine()} {platform.processor() or ''}, "
        f"Python {platform.python_version()}; one process, workers=1; "
        f"load average at the end {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs\n\n"
    )
    lines = [
        "| file | lambda_s (um) | grid | element (um) | periodic | mu_eff | C1 | n1 | C2 | n2 "
        "| R^2 Eq. 24 / 25 | time (s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['file']} | {r['lambda_s_um']:.3g} | {r['grid']} | {r['element_um']:.3g} | "
            f"{'yes' if r['periodic'] else 'no (DC-FFT)'} | {r['mu_eff']:.3g} | {r['C1']:.3g} | "
            f"{r['n1']:.3g} | {r['C2']:.3g} | {r['n2']:.3g} | "
            f"{r['r2_first']:.3f} / {r['r2_reload']:.3f} | {r['seconds']:.1f} |"
        )
    lines += [
        "",
        "Resolution check (default calibration: default lambda_s and grid, default boundary "
        f"({', '.join(sorted({c['boundary'] for c in checks}))}), check at half the grid):",
        "",
        "| file | lambda_s (um) | grid | total (s) | check (s) | share of total | mu_eff change | "
        "max alpha change | warning |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for c in checks:
        lines.append(
            f"| {c['file']} | {c['lambda_s_um']:.3g} | {c['grid']} | {c['seconds_total']:.1f} | "
            f"{c['seconds_check']:.1f} | "
            f"{100 * c['check_share']:.0f} % | {100 * c['mu_eff_change']:.1f} % | "
            f"{100 * c['alpha_change']:.1f} % | {'yes' if c['warning'] else 'no'} |"
        )
    text = head + "\n".join(lines) + "\n"
    (RESULTS / "measured_surfaces.md").write_text(text)
    print(text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--folder", required=True, help="folder holding the five files")
    ap.add_argument("--max-grid", type=int, help="cap the default grid (quick runs)")
    a = ap.parse_args()
    rev = commit()  # the code that runs, read before the run
    rows, checks = run(a.folder, a.max_grid)
    write(rows, checks, rev)


if __name__ == "__main__":
    main()
