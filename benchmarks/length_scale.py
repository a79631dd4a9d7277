"""The calibration's length scale on real scans: grid convergence at fixed lambda_s, and lambda_s.

For each file in a folder of measured surfaces (the five files of SurfaceTopography's public
test set, ``test/file_format_examples/``: ``metropro-1.dat``, ``mnt-1.mnt``, ``x3p-2.x3p``,
``sur-3.sur``, ``matrix-3.txt``), the scan is workpiece and tool (a scan against itself), the
scene is the default one otherwise (Table 1 materials, 10-600 MPa, the default boundary of
files: mirror-symmetric since issue 31, docs/measured_surfaces.md; column "solve"):

1. **Grid convergence at fixed lambda_s** (the default ``lambda_s`` of the file, or
   ``--lambda-s-factor`` times it): the calibration at the default grid ``G`` (``16`` elements
   per ``lambda_s``) and at ``G / 2`` and ``G / 4`` (``--grid-factor 2`` runs ``2G, G, G/2``):
   ``mu_eff``, ``C1``, ``n1``, ``C2``, ``n2``, the contact ratio at 10 MPa and the change between
   the two finest grids.
2. **mu_eff against lambda_s**: the default and the ISO 25178-3 nesting indices two steps
   below and above it, each at its own default grid (``16`` elements per ``lambda_s``, at most
   the scan's sampling and ``--max-grid``, default 256: the table gives the elements per
   ``lambda_s`` each run had).

Writes ``benchmarks/results/length_scale.md`` and ``length_scale_{grid,lambda_s}.csv`` (the tables
of ``docs/measured_surfaces.md``; ``length_scale_custom*`` for any non-default option) and prints
them. Run from the repository root::

    python benchmarks/length_scale.py --folder FOLDER [--grid-factor 2] [--max-grid 512]
                                      [--only mnt-1.mnt ...] [--tables grid,lambda_s]

``sur-3.sur`` (89 % undefined points) runs with ``max_undefined=0.95``. Cost: about 6-12 min for
both tables on one core of the loaded 2-core machine, with the other jobs' load (``--grid-factor 2`` for mnt-1 and x3p-2: about
3 min, the finest grids 93 s and 51 s).
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import math
import time
from pathlib import Path

from _provenance import run_record

from halfspace_calib.pipeline.calibration import Scene, calibrate
from halfspace_calib.pipeline.sweep.scene_surfaces import (
    ELEMENTS_PER_LAMBDA_S,
    ISO_NESTING_INDICES,
    load_scene_surfaces,
)

FILES = ["metropro-1.dat", "mnt-1.mnt", "x3p-2.x3p", "sur-3.sur", "matrix-3.txt"]
RESULTS = Path(__file__).resolve().parent / "results"
KEYS = ("mu_eff", "C1", "n1", "C2", "n2")


def _run(scene, label, **kw):
    sc = dataclasses.replace(scene, resolution_check=False, **kw)
    t0 = time.perf_counter()
    cal = calibrate(sc, progress=False)
    dt = time.perf_counter() - t0
    P = cal.params
    p, a = cal.sweeps.loading
    row = {
        "file": label,
        "lambda_s_um": cal.scene.lambda_s * 1e6,
        "grid": cal.scene.grid,
        "element_um": cal.sweeps.surfaces["workpiece"].dx * 1e6,
        "elements_per_lambda_s": cal.scene.lambda_s / cal.sweeps.surfaces["workpiece"].dx,
        "rq_patch_nm": cal.files[0].rq_patch * 1e9,
        "alpha_10MPa": float(a[0]) if p[0] == 10e6 else math.nan,
        **{k: getattr(P, k) for k in KEYS},
        "r2_first": cal.first.r_squared,
        "r2_reload": cal.reload.r_squared,
        "seconds": dt,
        "problems": len(cal.problems()),
        "periodic": cal.scene.periodic,
        "boundary": cal.scene.boundary,
    }
    print(
        f"  {label} lambda_s {row['lambda_s_um']:.4g} um grid {row['grid']}: "
        + ", ".join(f"{k} {row[k]:.4g}" for k in ("alpha_10MPa",) + KEYS)
        + f", {dt:.1f} s",
        flush=True,
    )
    return row


def grid_table(folder, files, grid_factor, lambda_factor):
    rows = []
    for name in files:
        base = _base(folder, name)
        surf = load_scene_surfaces(base)
        lam = surf.lambda_s * lambda_factor
        base = dataclasses.replace(base, lambda_s=lam)
        g = load_scene_surfaces(base).grid * grid_factor
        for grid in (g, g // 2, g // 4):
            rows.append(_run(base, name, grid=grid))
    return rows


def lambda_table(folder, files, max_grid):
    rows = []
    for name in files:
        base = _base(folder, name)
        ss = load_scene_surfaces(base)
        lam, rec = ss.lambda_s, ss.files[0]
        native = int(rec.crop_size / max(rec.pitch) * (1 + 1e-9))
        i = min(range(len(ISO_NESTING_INDICES)), key=lambda j: abs(ISO_NESTING_INDICES[j] - lam))
        for j in (i - 2, i, i + 2):
            v = ISO_NESTING_INDICES[j]
            want = 8 * math.ceil(ELEMENTS_PER_LAMBDA_S * rec.crop_size / v / 8 - 1e-9)
            rows.append(_run(base, name, lambda_s=v, grid=max(8, min(want, native, max_grid))))
    return rows


def _base(folder, name):
    path = Path(folder) / name
    extra = {"max_undefined": 0.95} if name.startswith("sur-") else {}
    return Scene(workpiece=str(path), tool=str(path), **extra)


def _change(rows):
    """Relative change of each parameter between the two finest grids of each file."""
    out = {}
    for r in rows:
        out.setdefault(r["file"], []).append(r)
    res = {}
    for name, rs in out.items():
        rs = sorted(rs, key=lambda r: -r["grid"])
        res[name] = {k: abs(rs[1][k] - rs[0][k]) / abs(rs[0][k]) for k in KEYS}
    return res


def write(grid_rows, lam_rows, name="length_scale"):
    RESULTS.mkdir(exist_ok=True)
    for tag, rows in (("grid", grid_rows), ("lambda_s", lam_rows)):
        if rows:
            with open(RESULTS / f"{name}_{tag}.csv", "w", newline="") as fh:
                w = csv.DictWriter(fh, fieldnames=list(rows[0]))
                w.writeheader()
                w.writerows(rows)
    lines = []
    if grid_rows:
        ch = _change(grid_rows)
        lines += [
            f"Grid convergence at fixed lambda_s (default grid = "
            f"{ELEMENTS_PER_LAMBDA_S} elements per lambda_s; solve: the boundary of the patch):",
            "",
            "| file | lambda_s (um) | grid | element (um) | elements / lambda_s | Rq patch (nm) "
            "| alpha(10 MPa) | mu_eff | C1 | n1 | C2 | n2 | solve | time (s) |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
        ]
        for r in grid_rows:
            lines.append(
                f"| {r['file']} | {r['lambda_s_um']:.4g} | {r['grid']} | {r['element_um']:.3g} | "
                f"{r['elements_per_lambda_s']:.3g} | {r['rq_patch_nm']:.4g} | "
                f"{r['alpha_10MPa']:.4f} | "
                + " | ".join(f"{r[k]:.4g}" for k in KEYS)
                + f" | {r['boundary']} | {r['seconds']:.1f} |"
            )
        lines += [
            "",
            "Change between the two finest grids:",
            "",
            "| file | " + " | ".join(KEYS) + " |",
            "|---|" + "---|" * len(KEYS),
        ]
        for fname, c in ch.items():
            lines.append(f"| {fname} | " + " | ".join(f"{100 * c[k]:.1f} %" for k in KEYS) + " |")
        lines.append("")
    if lam_rows:
        lines += [
            "mu_eff against lambda_s (each at its default grid; solve as above):",
            "",
            "| file | lambda_s (um) | grid | elements / lambda_s | Rq patch (nm) | alpha(10 MPa) "
            "| mu_eff | C1 | n1 | C2 | n2 | solve | time (s) |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
        ]
        for r in lam_rows:
            lines.append(
                f"| {r['file']} | {r['lambda_s_um']:.4g} | {r['grid']} | "
                f"{r['elements_per_lambda_s']:.3g} | {r['rq_patch_nm']:.4g} | "
                f"{r['alpha_10MPa']:.4f} | "
                + " | ".join(f"{r[k]:.4g}" for k in KEYS)
                + f" | {r['boundary']} | {r['seconds']:.1f} |"
            )
    text = "\n".join(lines) + "\n"
    (RESULTS / f"{name}.md").write_text(text)
    print(text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--folder", required=True, help="folder holding the five files")
    ap.add_argument("--only", nargs="+", default=FILES, help="files to run (default: all five)")
    ap.add_argument(
        "--grid-factor", type=int, default=1, help="finest grid = factor x default (default 1)"
    )
    ap.add_argument(
        "--lambda-s-factor",
        type=float,
        default=1.0,
        help="lambda_s of the grid table = factor x the default (default 1)",
    )
    ap.add_argument(
        "--max-grid",
        type=int,
        default=256,
        help="largest grid of the lambda_s table (default %(default)s, as the default rule)",
    )
    ap.add_argument(
        "--tables",
        default="grid,lambda_s",
        help="which tables: grid, lambda_s or both (default: %(default)s)",
    )
    a = ap.parse_args()
    which = set(a.tables.split(","))
    g = grid_table(a.folder, a.only, a.grid_factor, a.lambda_s_factor) if "grid" in which else []
    lam = lambda_table(a.folder, a.only, a.max_grid) if "lambda_s" in which else []
    default = a.grid_factor == 1 and a.lambda_s_factor == 1 and a.max_grid == 256
    name = "length_scale" if default and len(a.only) == len(FILES) else "length_scale_custom"
    write(g, lam, name)


if __name__ == "__main__":
    with run_record(__file__):
        main()
