"""The patch's boundary: reload curves of the roughness, not of the patch (issue 31, item 3).

A measured scan is a patch of a larger surface. How the solver closes it decides whether the
reload curves describe the roughness: an isolated patch (DC-FFT, zero padding) is a finite body
whose nearly conforming contact is a flat punch with a plastic rim; a periodic patch joins its
opposite edges into a seam. This script compares five boundary treatments on the default scene
and on measured files, from the solver's raw output (the contact ratio and the mean pressure of
one region of the same pressure field, nothing clamped):

- ``mirror``: the patch as one quarter of the period of its mirror-symmetric extension
  (``boundary="mirror"``, the default for files);
- ``periodic``: the patch as one period (``boundary="periodic"``, synthetic surfaces' default);
- ``isolated``: a finite body on a half-space (``boundary="isolated"``, the files' default
  before the mirror);
- ``central``: the isolated solve, with ``alpha`` and the pressure read in the central square
  (the middle half along each side) only;
- ``guard``: the isolated solve of the patch inside a guard band of a quarter of its width on
  each side, mirrored from the patch and tapered down by the composite's peak-to-valley
  (a raised cosine) towards the band's outer edge; the load is scaled so that the padded grid
  carries ``p N^2 / (N + 2 w)^2`` on average; ``alpha`` and the pressure are read on the patch.

The first three are the package's own sweeps (:func:`run_sweeps`); ``central`` and ``guard``
are candidates built here (the same load, plastic surface and warm-started reloads as the
sweeps). For each case and method, at the default grid ``G`` and at ``G / 2``:

1. the largest deficit of a reload point below the first loading at the same pressure
   (:func:`~halfspace_calib.pipeline.sweep.conformity.reload_deficit`; the first loading is also
   solved at every reload pressure, so no interpolation is needed for the package's methods);
2. the largest change of a reload point's ``alpha`` from ``G`` to ``G / 2``
   (:func:`~halfspace_calib.pipeline.sweep.conformity.reload_grid_change`; the region methods read
   slightly different pressures, interpolated);
3. the fraction of the border band and of the central square at the hardness at the top
   level (:func:`~halfspace_calib.pipeline.sweep.conformity.edge_plasticity`);

and the sweep time at ``G`` and ``G / 2`` and the memory estimate of one solve. Then the
calibration (``calibrate()``, with its resolution check) of each case with the old and the new
default boundary, timed interleaved in this run.

Cases: the default scene (synthetic, periodic), the five files of ``--folder`` each against
itself (sur-3 with ``max_undefined=0.95``), and metropro-1, x3p-2 and mnt-1 against the default
synthetic tool. Writes ``benchmarks/results/patch_boundary.csv`` (methods),
``patch_boundary_cost.csv`` (calibrations) and ``patch_boundary.md``, and prints the tables::

    python benchmarks/patch_boundary.py --folder ../shared/surfaces [--cases ...] [--methods ...]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import time
from pathlib import Path

import numpy as np
from _provenance import RESULTS, commit, law_fields, run_record, write_rows
from scipy.interpolate import PchipInterpolator

from halfspace_calib.contact.normal import estimate_memory, solve_normal_pair
from halfspace_calib.pipeline.calibration import Scene, calibrate
from halfspace_calib.pipeline.law.fit import ReloadCurve
from halfspace_calib.pipeline.sweep.conformity import (
    edge_plasticity,
    reload_deficit,
    reload_grid_change,
)
from halfspace_calib.pipeline.sweep.resolution import fit_sweeps
from halfspace_calib.pipeline.sweep.scene_surfaces import load_scene_surfaces
from halfspace_calib.pipeline.sweep.sweeps import SolveRecord, run_sweeps

METHODS = ("mirror", "periodic", "isolated", "central", "guard")
#: case name -> (workpiece file, tool file or None for the synthetic tool, extra Scene fields)
CASES = {
    "default scene": (None, None, {}),
    "metropro-1": ("metropro-1.dat", "metropro-1.dat", {}),
    "mnt-1": ("mnt-1.mnt", "mnt-1.mnt", {}),
    "x3p-2": ("x3p-2.x3p", "x3p-2.x3p", {}),
    "sur-3": ("sur-3.sur", "sur-3.sur", {"max_undefined": 0.95}),
    "matrix-3": ("matrix-3.txt", "matrix-3.txt", {}),
    "metropro-1 / tool": ("metropro-1.dat", None, {}),
    "x3p-2 / tool": ("x3p-2.x3p", None, {}),
    "mnt-1 / tool": ("mnt-1.mnt", None, {}),
}


def scene_of(case, folder, **kw):
    """The case's scene (default boundary) with ``kw``."""
    wp, tl, extra = CASES[case]
    files = {k: str(Path(folder) / v) for k, v in (("workpiece", wp), ("tool", tl)) if v}
    return Scene(**files, **extra, **kw)


# ----------------------------------------------------------------------------- readings
@dataclasses.dataclass
class Curves:
    """The raw points of one method at one grid: first loading, reloads, the top level's map."""

    loading: list  # (p, alpha) of the first loading at the scene's levels
    first: list  # ... and at every reload pressure too
    reload: list  # ReloadCurve per p_hist, ascending
    top_map: np.ndarray
    seconds: float
    memory: int


def _region(n, w):
    """Slices of the patch and of its central square in a grid padded by ``w``."""
    whole = (slice(w, w + n), slice(w, w + n))
    c = n // 4
    return whole, (slice(w + c, w + n - c), slice(w + c, w + n - c))


def _package(scene, surfs):
    """``mirror`` / ``periodic`` / ``isolated``: the package's sweeps, read as recorded."""
    t0 = time.perf_counter()
    sw = run_sweeps(scene, progress=False, surfaces=surfs)
    seconds = time.perf_counter() - t0
    p, a = sw.loading
    loading = list(zip(p.tolist(), a.tolist(), strict=True))
    first = loading + _virgin(scene, surfs, sw, have=set(p.tolist()))
    top = max(sw.levels, key=lambda lv: lv.p_hist)
    n = surfs.grid
    memory = estimate_memory((n, n), scene.boundary)
    curves = sorted(sw.reload_curves(), key=lambda c: c.p_hist)
    return Curves(loading, first, curves, top.pressure_map, seconds, memory)


def _virgin(scene, surfs, sw, have):
    """The first loading at every reload pressure not among the levels (the raw element count)."""
    out = []
    ps = sorted({float(q) for c in sw.reload_curves() for q in c.p} - have)
    for q in ps:
        r = solve_normal_pair(
            surfs.workpiece.heights,
            surfs.tool.heights,
            surfs.workpiece.dx,
            scene.E_star,
            q,
            H=scene.H,
            dy=surfs.workpiece.dy,
            **scene.solver.normal_kwargs(),
        )
        out.append((q, SolveRecord.of(r, scene.contact_area).alpha))
    return out


def _candidate(method, scene, surfs):
    """``central`` / ``guard``: isolated solves read on a region (the sweeps' loading and reloads)."""
    wp = np.asarray(surfs.workpiece.heights)
    tl = np.asarray(surfs.tool.heights)
    n = wp.shape[0]
    w, scale = 0, 1.0
    if method == "guard":
        w = max(2, n // 4)
        d = np.maximum(np.maximum(w - np.arange(n + 2 * w), np.arange(n + 2 * w) - (n + w - 1)), 0)
        D = np.maximum.outer(d / w, d / w)  # 0 on the patch, 1 at the band's outer edge
        depth = np.ptp(wp + tl)
        wp = np.pad(wp, w, mode="symmetric") - depth * (1 - np.cos(np.pi * D)) / 2
        tl = np.pad(tl, w, mode="symmetric")
        scale = n * n / (n + 2 * w) ** 2
    whole, centre = _region(n, w)
    region = centre if method == "central" else whole
    kw = dict(H=scene.H, dy=surfs.workpiece.dy, boundary="isolated", tol=scene.tol)
    dx, E = surfs.workpiece.dx, scene.E_star

    def read(res):
        p = res.pressure[region]
        return float(p.mean()), float(np.count_nonzero(p > 0) / p.size)

    first, reload, top_map = [], [], None
    t0 = time.perf_counter()
    top = max(scene.pressures)
    for ph in scene.pressures:
        res = solve_normal_pair(wp, tl, dx, E, ph * scale, **kw)
        first.append(read(res))
        if ph == top:
            top_map = res.pressure[region].copy()
        if ph < scene.reload_from:
            continue
        surface, p_init, pts = wp - res.plastic_displacement, res.pressure, []
        for f in sorted(scene.reload_fractions, reverse=True):
            r = solve_normal_pair(
                surface, tl, dx, E, f * ph * scale, volume_conservation=False, p_init=p_init, **kw
            )
            p_init = r.pressure
            pts.append(read(r))
        pts = sorted(q for q in pts if q[0] > 0)  # a region without contact: no pressure
        p_hist = read(res)[0]  # the region's own pressure at the level
        reload.append(
            ReloadCurve(p_hist, np.array([p for p, _ in pts]), np.array([a for _, a in pts]))
        )
    seconds = time.perf_counter() - t0
    loading = list(first)
    reload_p = sorted({f * ph for ph in scene.reload_levels for f in scene.reload_fractions})
    for q in reload_p:
        first.append(read(solve_normal_pair(wp, tl, dx, E, q * scale, **kw)))
    memory = estimate_memory(wp.shape, "isolated")
    return Curves(loading, first, reload, top_map, seconds, memory)


def run_method(method, scene, surfs):
    """One method at one grid: its :class:`Curves`."""
    if method in ("mirror", "periodic", "isolated"):
        return _package(dataclasses.replace(scene, boundary=method), surfs)
    return _candidate(method, scene, surfs)


# ----------------------------------------------------------------------------- criteria
def _first_curve(points):
    """First-loading points sorted by pressure, duplicates (to 9 digits) dropped."""
    seen, out = set(), []
    for p, a in sorted(points):
        if p <= 0:  # a region without contact carries no pressure to compare at
            continue
        k = f"{p:.9g}"
        if k not in seen:
            seen.add(k)
            out.append((p, a))
    return np.array([p for p, _ in out]), np.array([a for _, a in out])


def _resampled(curves_half, curves):
    """The half grid's reload curves (level by level) at the pressures of ``curves``.

    PCHIP in ``log p``: the package's methods prescribe the same pressures on both grids, where
    the interpolant returns the point itself; the region methods read slightly different
    pressures on the two grids (and extrapolate by at most that difference).
    """
    out = []
    for c, h in zip(curves, curves_half, strict=True):
        f = PchipInterpolator(np.log(h.p), h.alpha, extrapolate=True)
        out.append(ReloadCurve(c.p_hist, c.p, f(np.log(c.p))))
    return out


def criteria(full, half, H):
    """The three criteria of one method: a dict of table columns."""
    p1, a1 = _first_curve(full.first)
    d = reload_deficit(p1, a1, full.reload)
    g = reload_grid_change(full.reload, _resampled(half.reload, full.reload))
    e = edge_plasticity(full.top_map, H)
    return {
        "reload_deficit": d.worst,
        "deficit_at": f"{d.p / 1e6:.4g} MPa after {d.p_hist / 1e6:.4g} MPa",
        "reload_grid_change": g.worst,
        "grid_change_at": f"{g.p / 1e6:.4g} MPa after {g.p_hist / 1e6:.4g} MPa",
        "rim_capped": e.rim_capped,
        "centre_capped": e.centre_capped,
        "band": e.band,
    }


def _fit(full, scene):
    """Eq. 24-25 fits of a method's curves (the package's fit), or ``{}`` if they fail."""
    p = np.array([q for q, _ in full.loading])
    a = np.array([x for _, x in full.loading])

    class _Sweeps:  # what fit_sweeps reads
        loading = (p, a)

        @staticmethod
        def reload_curves():
            return full.reload

    try:
        f1, f2 = fit_sweeps(scene, _Sweeps())
    except (RuntimeError, ValueError):
        return {}
    mu = scene.m * scene.sigma_y / 2 / scene.H
    return {"mu_eff": mu * f1.C1, "C1": f1.C1, "n1": f1.n1, "C2": f2.C2, "n2": f2.n2}


def compare(folder, cases, methods):
    """The method comparison: one row per case and method."""
    rows = []
    for case in cases:
        base = scene_of(case, folder, workers=1)
        surfs = load_scene_surfaces(base)
        g = surfs.grid
        sc = dataclasses.replace(base, grid=g, lambda_s=surfs.lambda_s if base.from_files else None)
        sh = dataclasses.replace(sc, grid=g // 2)
        surfs_h = load_scene_surfaces(sh, check_sampling=False)
        for m in methods:
            full, half = run_method(m, sc, surfs), run_method(m, sh, surfs_h)
            try:
                crit = criteria(full, half, sc.H)
            except ValueError as exc:  # e.g. a region without contact at every reload point
                crit = dict.fromkeys(("reload_deficit", "reload_grid_change"), math.nan)
                crit.update(rim_capped=math.nan, centre_capped=math.nan, error=str(exc))
            row = {
                "case": case,
                "method": m,
                "grid": g,
                **crit,
                "seconds_grid": full.seconds,
                "seconds_half": half.seconds,
                "memory_MiB": full.memory / 2**20,
                **_fit(full, sc),
            }
            rows.append(row)
            print(
                f"{case:18s} {m:9s} grid {g:3d}: deficit {row['reload_deficit']:+.3f}, "
                f"half grid {row['reload_grid_change']:.3f}, rim/centre at H "
                f"{row['rim_capped']:.2f}/{row['centre_capped']:.2f}, "
                f"{row['seconds_grid']:.2f} + {row['seconds_half']:.2f} s",
                flush=True,
            )
    return rows


def cost(folder, cases, rounds):
    """Calibrations with the old and the new default boundary, interleaved; one row each."""
    rows = []
    for case in cases:
        new = scene_of(case, folder)
        old = dataclasses.replace(new, boundary="isolated") if new.from_files else new
        kinds = (("new", new), ("old", old)) if new.from_files else (("new", new),)
        for r in range(rounds):
            for kind, sc in kinds if r % 2 == 0 else kinds[::-1]:
                t0 = time.perf_counter()
                cal = calibrate(sc, progress=False)
                dt = time.perf_counter() - t0
                rc = cal.resolution
                rows.append(
                    {
                        "case": case,
                        "default": kind,
                        "boundary": cal.scene.boundary,
                        "round": r,
                        "grid": cal.scene.grid,
                        "seconds": dt,
                        "seconds_check": rc.seconds if rc else 0.0,
                        **law_fields(cal),
                        **{
                            f"change_{k}": v[2]
                            for k, v in (rc.params if rc and rc.params else {}).items()
                        },
                        "alpha_change_half": rc.alpha_change if rc else math.nan,
                        "check_warns": bool(rc and rc.warning),
                        "problems": len(cal.problems()),
                        "problem_text": " | ".join(cal.problems()),
                    }
                )
                print(
                    f"{case:18s} {kind} ({cal.scene.boundary:8s}) round {r}: {dt:.1f} s, mu_eff "
                    f"{cal.params.mu_eff:.4g}, problems {len(cal.problems())}",
                    flush=True,
                )
    return rows


# ----------------------------------------------------------------------------- tables
def _f(v, fmt):
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, fmt)


def tables(rows, costs, rev):
    """The markdown text of the three tables."""
    head = (
        f"commit {rev}; load average at the end {os.getloadavg()[0]:.1f} on {os.cpu_count()} "
        "CPUs; method sweeps in one process (workers=1), calibrations with the default workers\n\n"
    )
    lines = [
        "Methods (criteria at the default grid G; times of the sweeps at G and G / 2; memory of "
        "one solve at G):",
        "",
        "| case | method | G | reload below first loading (max) | reload change at G / 2 (max) "
        "| border band at H | centre at H | sweeps G + G/2 (s) | memory (MiB) | mu_eff | C2 | n2 |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['case']} | {r['method']} | {r['grid']} | {_f(r['reload_deficit'], '+.3f')} | "
            f"{_f(r['reload_grid_change'], '.3f')} | {_f(r['rim_capped'], '.2f')} | "
            f"{_f(r['centre_capped'], '.2f')} | "
            f"{r['seconds_grid']:.2f} + {r['seconds_half']:.2f} | {r['memory_MiB']:.0f} | "
            f"{_f(r.get('mu_eff'), '.4g')} | {_f(r.get('C2'), '.4g')} | {_f(r.get('n2'), '.3g')} |"
        )
    if costs:
        lines += [
            "",
            "Calibrations (calibrate() with its resolution check; old default: isolated, new: "
            "mirror; the default scene keeps periodic; median over the rounds):",
            "",
            "| case | G | new: time (s) | old: time (s) | old / new | new: mu_eff, C2, problems | "
            "old: mu_eff, C2, problems |",
            "|---|---|---|---|---|---|---|",
        ]
        for case in dict.fromkeys(c["case"] for c in costs):
            sel = {
                k: [c for c in costs if c["case"] == case and c["default"] == k]
                for k in ("new", "old")
            }
            med = {
                k: float(np.median([c["seconds"] for c in v])) if v else math.nan
                for k, v in sel.items()
            }

            def law(v):
                return f"{v[0]['mu_eff']:.4g}, {v[0]['C2']:.4g}, {v[0]['problems']}" if v else "-"

            lines.append(
                f"| {case} | {sel['new'][0]['grid']} | {med['new']:.1f} | {_f(med['old'], '.1f')} | "
                f"{_f(med['old'] / med['new'], '.2f')} | {law(sel['new'])} | {law(sel['old'])} |"
            )
    return head + "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--folder", required=True, help="folder holding the five measured files")
    ap.add_argument("--cases", nargs="+", choices=tuple(CASES), default=tuple(CASES))
    ap.add_argument("--methods", nargs="+", choices=METHODS, default=METHODS)
    ap.add_argument("--rounds", type=int, default=2, help="calibration rounds per default (2)")
    ap.add_argument("--no-cost", action="store_true", help="skip the calibrations")
    a = ap.parse_args()
    rev = commit()
    rows = compare(a.folder, a.cases, a.methods)
    costs = [] if a.no_cost else cost(a.folder, a.cases, a.rounds)
    RESULTS.mkdir(exist_ok=True)
    write_rows(
        RESULTS / "patch_boundary.csv", rows, fieldnames=dict.fromkeys(k for r in rows for k in r)
    )
    if costs:
        keys = dict.fromkeys(k for r in costs for k in r)
        write_rows(RESULTS / "patch_boundary_cost.csv", costs, keys)
    text = tables(rows, costs, rev)
    (RESULTS / "patch_boundary.md").write_text(text)
    print(text)


if __name__ == "__main__":
    with run_record(__file__):
        main()
