"""How mu_eff and C1 scatter with the size of the patch calibrated, in units of lambda_s.

A large scan is S-filtered once at ``lambda_s`` and cut into non-overlapping square patches of
4, 8, 16 and 32 ``lambda_s`` a side (at most ``--max-patches`` per size, a fixed random
choice among the layout's patches); each patch is calibrated on its own (default scene: Table 1 materials, default
pressures, the isolated boundary (zero-padded DC-FFT, as before issue 31's mirror-symmetric
default), no resolution check, one process) and the table gives, per size,
the number of patches, the mean of ``mu_eff`` and ``C1``, their coefficient of variation
(standard deviation / mean over the patches), their range (max - min) / mean, and the mean's
offset from the mean of the largest patches.

Scans (each real one against itself, the tool patch being the workpiece patch, as in
docs/measured_surfaces.md; ``lambda_s`` the smallest ISO 25178-3 index of at least 3 of the
scan's coarser pixels):

- ``mnt-1.mnt`` (1779 x 1113 um, 1.85 um pixels), ``lambda_s`` = 8 um;
- ``metropro-1.dat`` (703 x 527 um, 1.10 um pixels), ``lambda_s`` = 5 um;
- ``x3p-2.x3p`` (83 x 204 um, 0.128 x 0.315 um pixels), ``lambda_s`` = 2 um;
- ``synthetic``: Table 1's DC04 EDT-like workpiece (roll-off 100 um) and the smooth tool
  generated at 1024 x 1024 over 8.44 mm (8.24 um pixels), used as scans (levelled, not
  periodic), ``lambda_s`` = 50 um (6.1 pixels); the workpiece patch against the tool patch at
  the same place.

Patches are put on ``--elements`` elements per ``lambda_s`` (default 8, half the default rule:
the resolution check's grid; on the five files this moves ``mu_eff`` by 0.3-2.6 %, the same
bias for every patch size, docs/measured_surfaces.md) with
:func:`~halfspace_calib.topography.resample.band_limited_resample` (the filtered scan's
cosine series, exact cell means; patches away from the scan's edges need no edge treatment)
and levelled. Writes ``benchmarks/results/patch_size.csv`` (one row per patch) and
``patch_size.md``; prints the table. Run from the repository root::

    python benchmarks/patch_size.py --folder /work/shared/surfaces [--max-patches 12]
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import time
from pathlib import Path

import numpy as np
from _provenance import RESULTS, commit, law_fields, pct, write_rows

from halfspace_calib import topography as S
from halfspace_calib.pipeline.calibration import Scene, calibrate
from halfspace_calib.pipeline.sweep.scene_surfaces import SceneSurfaces
from halfspace_calib.topography.filters import s_filter
from halfspace_calib.topography.resample import band_limited_resample

SIZES = (4, 8, 16, 32)  # patch edge in lambda_s


#: the real scans and their lambda_s (m): the smallest ISO index >= 3 of their coarser pixels
#: (mnt-1: 1.85 um, metropro-1: 1.10 um; x3p-2: 0.315 um, one index up to fit the bound less)
REAL = (("mnt-1.mnt", 8e-6), ("metropro-1.dat", 5e-6), ("x3p-2.x3p", 2e-6))


def _scans(folder, only=None):
    """``[(name, workpiece scan, tool scan, lambda_s, file path or None)]``, levelled, filtered."""
    out = []
    for name, lam in REAL:
        if only and name not in only:
            continue
        path = Path(folder) / name
        if not path.is_file():
            print(f"skip {name}: not in {folder}")
            continue
        h, dx, dy, prov = S.read_raw(path)
        f = s_filter(S.level(S.Surface(h, dx, dy, provenance=prov)), lam)
        out.append((name, f, f, lam, str(path)))
    if only and "synthetic" not in only:
        return out
    n, size = 1024, 4 * S.PAPER_SIZE
    wp = S.dc04_edt_like(n, size=size, seed=1)
    tl = S.tool_like(n, size=size, seed=2)
    pair = []
    for s in (wp, tl):
        s = S.level(S.Surface(s.heights, s.dx, s.dy, provenance=s.provenance, periodic=False))
        pair.append(s_filter(s, 50e-6))
    out.append(("synthetic", pair[0], pair[1], 50e-6, None))
    return out


def _origins(lx, ly, side, max_patches):
    """Origins of non-overlapping ``side`` squares on a centred layout.

    At most ``max_patches``: a fixed random choice (seed 0) among them, spread over the scan.
    """
    kx, ky = int(lx / side + 1e-9), int(ly / side + 1e-9)
    x0, y0 = 0.5 * (lx - kx * side), 0.5 * (ly - ky * side)
    allo = [(x0 + i * side, y0 + j * side) for i in range(kx) for j in range(ky)]
    if len(allo) <= max_patches:
        return allo
    pick = np.random.default_rng(0).choice(len(allo), max_patches, replace=False)
    return [allo[k] for k in sorted(pick)]


def run(folder, max_patches, elements, sizes, only=None):
    rows = []
    for name, wp, tl, lam, path in _scans(folder, only):
        lx, ly = wp.size
        for k in sizes:
            side = k * lam
            grid = int(round(k * elements))
            origins = _origins(lx, ly, side, max_patches)
            if not origins:
                print(f"{name}: no patch of {k} lambda_s ({side * 1e6:.4g} um) fits")
                continue
            for o in origins:
                pair = [S.level(band_limited_resample(s, side, grid, origin=o)) for s in (wp, tl)]
                surfs = SceneSurfaces(pair[0], pair[1], None, None, 1, grid, ())
                scene = Scene(
                    workpiece=path,
                    tool=path,
                    grid=grid,
                    lambda_s=lam if path else None,
                    boundary="isolated",  # as the published table (before the mirror, issue 31)
                    resolution_check=False,
                    workers=1,
                )
                t0 = time.perf_counter()
                try:
                    cal = calibrate(scene, progress=False, surfaces=surfs)
                except RuntimeError as exc:
                    print(f"{name} {k} lambda_s at {o}: failed: {exc}")
                    continue
                dt = time.perf_counter() - t0
                P = cal.params
                rows.append(
                    {
                        "scan": name,
                        "lambda_s_um": lam * 1e6,
                        "patch_lambda_s": k,
                        "side_um": side * 1e6,
                        "grid": grid,
                        "x0_um": o[0] * 1e6,
                        "y0_um": o[1] * 1e6,
                        "rq_workpiece_nm": float(S.rq(pair[0])) * 1e9,
                        **law_fields(cal),
                        "problems": len(cal.problems()),
                        "seconds": dt,
                    }
                )
                print(
                    f"{name} {k:2d} lambda_s ({side * 1e6:.4g} um, grid {grid}) at "
                    f"({o[0] * 1e6:.4g}, {o[1] * 1e6:.4g}) um: mu_eff {P.mu_eff:.4g}, "
                    f"C1 {P.C1:.4g}, n1 {P.n1:.3g}, {dt:.1f} s",
                    flush=True,
                )
    return rows


def stats(rows):
    """Per scan and size: n, means, coefficients of variation, ranges, offset of the mean."""
    out = []
    for scan in dict.fromkeys(r["scan"] for r in rows):
        mine = [r for r in rows if r["scan"] == scan]
        sizes = sorted({r["patch_lambda_s"] for r in mine})
        ref = {
            q: float(np.mean([r[q] for r in mine if r["patch_lambda_s"] == sizes[-1]]))
            for q in ("mu_eff", "C1")
        }
        for k in sizes:
            sel = [r for r in mine if r["patch_lambda_s"] == k]
            d = {"scan": scan, "patch_lambda_s": k, "n": len(sel), "grid": sel[0]["grid"]}
            d["side_um"] = sel[0]["side_um"]
            for q in ("mu_eff", "C1", "n1"):
                v = np.array([r[q] for r in sel])
                d[f"{q}_mean"] = float(v.mean())
                d[f"{q}_cv"] = float(v.std(ddof=1) / v.mean()) if v.size > 1 else math.nan
                d[f"{q}_range"] = float(np.ptp(v) / v.mean())
            for q in ("mu_eff", "C1"):
                d[f"{q}_offset"] = d[f"{q}_mean"] / ref[q] - 1
            d["failed"] = sum(r["problems"] > 0 for r in sel)
            d["seconds"] = float(np.mean([r["seconds"] for r in sel]))
            out.append(d)
    return out


def table(st):
    lines = [
        "| scan | patch (lambda_s) | patch (um) | grid | patches | mu_eff mean | mu_eff CV | "
        "mu_eff range | C1 mean | C1 CV | C1 range | n1 CV | mean vs largest | runs failed "
        "| time per patch (s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for d in st:
        lines.append(
            f"| {d['scan']} | {d['patch_lambda_s']} | {d['side_um']:.4g} | {d['grid']} | "
            f"{d['n']} | {d['mu_eff_mean']:.4g} | {pct(d['mu_eff_cv'])} | "
            f"{pct(d['mu_eff_range'])} | {d['C1_mean']:.4g} | {pct(d['C1_cv'])} | "
            f"{pct(d['C1_range'])} | {pct(d['n1_cv'])} | {pct(d['mu_eff_offset'])} | "
            f"{d['failed']} | {d['seconds']:.1f} |"
        )
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--folder", required=True, help="folder holding x3p-2.x3p")
    ap.add_argument("--max-patches", type=int, default=12, help="patches per size at most")
    ap.add_argument("--elements", type=float, default=8.0, help="elements per lambda_s")
    ap.add_argument("--sizes", type=int, nargs="*", default=list(SIZES), help="in lambda_s")
    ap.add_argument("--only", nargs="*", help="scans to run (file names or 'synthetic')")
    a = ap.parse_args()
    rev = commit()
    rows = run(a.folder, a.max_patches, a.elements, a.sizes, a.only)
    RESULTS.mkdir(exist_ok=True)
    write_rows(RESULTS / "patch_size.csv", rows)
    head = (
        f"commit {rev}, {platform.machine()}, Python {platform.python_version()}; one "
        f"process; {a.elements:g} elements per lambda_s; at most {a.max_patches} patches per "
        f"size; load average at the end {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs\n\n"
    )
    text = head + table(stats(rows)) + "\n"
    (RESULTS / "patch_size.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
