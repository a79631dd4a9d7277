"""The resolution check: the normal sweeps and fits again at half the grid."""

import dataclasses
import math
import time
from dataclasses import dataclass

from ..law import fit as _fit
from .scene_surfaces import load_scene_surfaces
from .sweeps import run_sweeps

__all__ = [
    "RESOLUTION_TOL",
    "ResolutionCheck",
    "alpha_points",
    "check_sweeps",
    "fit_sweeps",
    "resolution_check",
]

#: relative change between the chosen grid and half of it above which the check warns
RESOLUTION_TOL = 0.10


@dataclass(frozen=True)
class ResolutionCheck:
    """The normal sweeps and fits again at half the grid: how much the answer moves.

    Attributes
    ----------
    grid, half_grid : int
        The chosen solver grid and half of it.
    params : dict
        ``name -> (value at grid, value at half_grid, relative change)`` for ``mu_eff``,
        ``C1``, ``n1``, ``C2``, ``n2``.
    alpha_change : float
        Largest relative change of the contact ratio over the first-loading and reload points
        both grids converged at.
    tolerance : float
        :data:`RESOLUTION_TOL`.
    warning : str
        Why the result is resolution-dependent, or ``""``.
    seconds : float
        Wall time of the check (sweeps and fits at ``half_grid``).
    skipped : str
        Why the check did not run (``""`` if it ran).
    """

    grid: int
    half_grid: int
    params: dict
    alpha_change: float
    tolerance: float
    warning: str
    seconds: float
    skipped: str = ""

    def as_dict(self):
        """JSON-ready dict."""
        return {
            "grid": self.grid,
            "half_grid": self.half_grid,
            "params": {k: list(v) for k, v in self.params.items()},
            "alpha_change": self.alpha_change,
            "tolerance": self.tolerance,
            "warning": self.warning,
            "seconds": self.seconds,
            "skipped": self.skipped,
        }


def alpha_points(sweeps):
    """``{(p_hist, p_mean): alpha}`` of every converged solve."""
    pts = {}
    for lv in sweeps.levels:
        if lv.loading.converged:
            pts[(lv.p_hist, lv.p_hist)] = lv.loading.alpha
        for r in lv.reload:
            if r.converged:
                pts[(lv.p_hist, r.p_mean)] = r.alpha
    return pts


def check_sweeps(sweeps):
    """``(p, alpha)`` of the first loading; ``RuntimeError`` if too few solves converged to fit."""
    p, alpha = sweeps.loading
    curves = sweeps.reload_curves()
    if p.size < 3 or not curves:
        raise RuntimeError(
            f"calibration needs >= 3 converged load levels and one reload curve; got {p.size} and "
            f"{len(curves)}. Failures: {sweeps.failed}; non-converged: "
            + "; ".join(
                f"{lv.p_hist:g} Pa: {lv.loading.message}"
                for lv in sweeps.levels
                if not lv.loading.converged
            )
        )
    return p, alpha


def fit_sweeps(scene, sweeps):
    """``(first, reload)``: Eqs. 24-25 fitted to the sweeps (what the resolution check compares).

    ``RuntimeError`` if too few solves converged (:func:`check_sweeps`).
    """
    p, alpha = check_sweeps(sweeps)
    curves = sweeps.reload_curves()
    floor_to = None if scene.alpha_floor is None else scene.alpha_floor * scene.H
    first = _fit.fit_first_loading(p, alpha, scene.H, floor_to=floor_to)
    reload = _fit.fit_reload(
        curves, scene.H, first.C1, first.n1, continuous=scene.continuous_reload
    )
    return first, reload


def resolution_check(scene, first, reload, sweeps, *, progress=False):
    """Run the normal sweeps at ``scene.grid // 2`` and compare with the main result.

    Returns
    -------
    ResolutionCheck
        With ``skipped`` set if half the grid is below 8 elements or its fit fails.
    """
    n = scene.grid
    half = n // 2
    if half < 8:
        return ResolutionCheck(n, half, {}, 0.0, RESOLUTION_TOL, "", 0.0, "grid / 2 < 8")
    t0 = time.perf_counter()
    coarse = dataclasses.replace(  # the main run's levels (adaptive ones as computed there)
        scene,
        grid=half,
        effects=("normal",),
        resolution_check=False,
        workers=scene.workers,
        pressures=tuple(lv.p_hist for lv in sweeps.levels),
        adaptive_levels=False,
    )
    try:
        surfs = load_scene_surfaces(coarse, check_sampling=False)
        sw = run_sweeps(coarse, progress=progress, surfaces=surfs)
        f2, r2 = fit_sweeps(coarse, sw)
    except (RuntimeError, ValueError) as exc:
        return ResolutionCheck(
            n, half, {}, 0.0, RESOLUTION_TOL, "", time.perf_counter() - t0, str(exc)
        )
    mu = scene.m * scene.sigma_y / 2 / scene.H  # mu_eff = m k C1 / H (geo_ratio aside)
    vals = {
        "mu_eff": (mu * first.C1, mu * f2.C1),
        "C1": (first.C1, f2.C1),
        "n1": (first.n1, f2.n1),
        "C2": (reload.C2, r2.C2),
        "n2": (reload.n2, r2.n2),
    }
    params = {k: (a, b, abs(b - a) / abs(a) if a else math.inf) for k, (a, b) in vals.items()}
    fine, crs = alpha_points(sweeps), alpha_points(sw)
    common = [k for k in fine if k in crs and fine[k] > 0]
    da = max((abs(crs[k] - fine[k]) / fine[k] for k in common), default=0.0)
    moved = [f"{k} {100 * v[2]:.1f} %" for k, v in params.items() if v[2] > RESOLUTION_TOL]
    if da > RESOLUTION_TOL:
        moved.append(f"alpha up to {100 * da:.1f} %")
    warning = ""
    if moved:
        warning = (
            f"the result depends on the resolution: from grid {n} to {half} "
            + ", ".join(moved)
            + f" (tolerance {100 * RESOLUTION_TOL:g} %); a finer grid (--grid) would move it "
            "further"
        )
    return ResolutionCheck(
        n, half, params, float(da), RESOLUTION_TOL, warning, time.perf_counter() - t0
    )
