"""The resolution check: the normal sweeps and the law that runs again at half the grid.

What it compares (and what decides its warning): the law the parameter file runs, fitted
again in the same forms to the sweeps at ``grid // 2``: its ``mu_eff``; the parameters of a
named form that runs (Eq. 24's ``C1, n1``, the paper's Eq. 25's ``C2, n2``); the contact
ratio of both branches of the law that runs at the main run's points (for a tabulated form:
its table); and the computed contact ratios themselves. A relative change above
:data:`RESOLUTION_TOL` in any of them is the warning. The other forms' numbers (Eq. 24 and
Eq. 25 when the file runs the tabulated forms) are reported beside, labelled not run; they
never warn.
"""

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np

from frictionlaw import FrictionParams, alpha_first, alpha_reload

from ..law import fit as _fit
from ..law import forms as _forms
from .scene_surfaces import load_scene_surfaces
from .sweeps import run_sweeps

__all__ = [
    "RESOLUTION_TOL",
    "ResolutionCheck",
    "alpha_points",
    "check_sweeps",
    "fit_sweeps",
    "law_alpha_change",
    "resolution_check",
    "running_params",
]

#: relative change between the chosen grid and half of it above which the check warns
RESOLUTION_TOL = 0.10

#: the branches' words in the console and the warning
_BRANCH_WORDS = {"first_loading": "first-loading alpha", "reload": "reload alpha"}


@dataclass(frozen=True)
class ResolutionCheck:
    """The normal sweeps and the law that runs again at half the grid: how much it moves.

    Attributes
    ----------
    grid, half_grid : int
        The chosen solver grid and half of it.
    params : dict
        ``name -> (value at grid, value at half_grid, relative change)`` of the law the
        parameter file runs: ``mu_eff`` (its first loading's Coulomb slope, without
        ``geo_ratio``), and ``C1, n1`` when it runs Eq. 24, ``C2, n2`` when it runs the
        paper's Eq. 25.
    alpha_change : float
        Largest relative change of the computed contact ratio over the first-loading and
        reload points both grids converged at.
    tolerance : float
        :data:`RESOLUTION_TOL`.
    warning : str
        Why the result is resolution-dependent (a change of ``params``, ``law_alpha`` or
        ``alpha_change`` above ``tolerance``), or ``""``.
    seconds : float
        Wall time of the check (sweeps and fits at ``half_grid``).
    skipped : str
        Why the check did not run (``""`` if it ran).
    forms : dict
        ``{"first_loading": form, "reload": form}``: the forms compared (those that run).
    law_alpha : dict
        ``branch -> `` largest relative change of the law's contact ratio, evaluated at the
        main run's points (first loading at its levels, reload at its ``(p_hist, p)``).
    beside : dict
        As ``params``, of the forms fitted beside the law that runs and not run (Eq. 24's
        ``mu_eff``, ``C1, n1``; the paper's ``C2, n2``); information only, never a warning.
    """

    grid: int
    half_grid: int
    params: dict
    alpha_change: float
    tolerance: float
    warning: str
    seconds: float
    skipped: str = ""
    forms: dict = field(default_factory=dict)
    law_alpha: dict = field(default_factory=dict)
    beside: dict = field(default_factory=dict)

    def as_dict(self):
        """JSON-ready dict."""
        return {
            "grid": self.grid,
            "half_grid": self.half_grid,
            "forms": dict(self.forms),
            "params": {k: list(v) for k, v in self.params.items()},
            "law_alpha": dict(self.law_alpha),
            "beside_not_run": {k: list(v) for k, v in self.beside.items()},
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
    """``(first, reload)``: Eqs. 24-25 fitted to the sweeps (the paper's forms alone).

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


def running_params(scene, law):
    """The :class:`~frictionlaw.FrictionParams` of ``law`` (a :class:`~..law.forms.FittedLaw`).

    The forms the fit chose, on ``scene``'s ``m``, ``sigma_y`` and ``H``; no ``geo_ratio``
    (the check solves the normal sweeps alone).
    """
    eq24, paper = law.eq24, law.paper
    base = FrictionParams(
        m=scene.m,
        sigma_y=scene.sigma_y,
        H=scene.H,
        C1=eq24.C1,
        n1=eq24.n1,
        C2=paper.C2,
        n2=paper.n2,
    )
    return law.apply(base)


def law_alpha_change(fine, coarse, sweeps):
    """Largest relative change of the contact ratio of the law that runs, per branch.

    ``fine``, ``coarse``: the two grids' :class:`~frictionlaw.FrictionParams`; evaluated at
    the main run's converged points: first loading at its load levels, reload at its
    ``(p_hist, p_mean)`` points. Returns ``{"first_loading": ..., "reload": ...}``.
    """
    p, _ = sweeps.loading
    a1, b1 = alpha_first(p, fine), alpha_first(p, coarse)
    pts = [(c.p_hist, q) for c in sweeps.reload_curves() for q in np.atleast_1d(c.p)]
    ph = np.array([x for x, _ in pts], dtype=float)
    q = np.array([y for _, y in pts], dtype=float)
    a2, b2 = alpha_reload(q, ph, fine), alpha_reload(q, ph, coarse)

    def rel(a, b):
        a, b = np.atleast_1d(a), np.atleast_1d(b)
        ok = a > 0
        return float(np.max(np.abs(b[ok] - a[ok]) / a[ok])) if np.any(ok) else 0.0

    return {"first_loading": rel(a1, b1), "reload": rel(a2, b2) if ph.size else 0.0}


def _change(a, b):
    return (float(a), float(b), abs(b - a) / abs(a) if a else math.inf)


def _compared(law, law2, fine, coarse):
    """``(params, beside)``: the running law's numbers and the other forms' (not run)."""
    params = {"mu_eff": _change(fine.mu_eff, coarse.mu_eff)}
    beside = {}
    f1, f2 = law.eq24, law2.eq24
    r1, r2 = law.paper, law2.paper
    eq = {"C1": (f1.C1, f2.C1), "n1": (f1.n1, f2.n1)}
    pa = {"C2": (r1.C2, r2.C2), "n2": (r1.n2, r2.n2)}
    for running, vals in ((law.first.form == "eq24", eq), (law.reload.form == "paper", pa)):
        for k, (a, b) in vals.items():
            (params if running else beside)[k] = _change(a, b)
    if law.first.form != "eq24":  # Eq. 24's own Coulomb slope m k C1 / H, beside the running one
        mu = fine.tau_max / fine.H
        beside = {"mu_eff": _change(mu * f1.C1, mu * f2.C1), **beside}
    return params, beside


def resolution_check(scene, law, sweeps, *, progress=False):
    """Run the normal sweeps at ``scene.grid // 2``, fit the law that runs, and compare.

    ``law``: the main run's :class:`~..law.forms.FittedLaw`; the half grid's law is fitted in
    the same forms (no held-out refits: the forms are named), so that a tabulated law is
    compared with a tabulated law.

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
    forms = {"first_loading": law.first.form, "reload": law.reload.form}
    coarse = dataclasses.replace(  # the main run's levels (adaptive ones as computed there)
        scene,
        grid=half,
        effects=("normal",),
        resolution_check=False,
        workers=scene.workers,
        pressures=tuple(lv.p_hist for lv in sweeps.levels),
        adaptive_levels=False,
        first_loading_form=forms["first_loading"],
        reload_form=forms["reload"],
    )
    try:
        surfs = load_scene_surfaces(coarse, check_sampling=False)
        sw = run_sweeps(coarse, progress=progress, surfaces=surfs)
        p2, a2 = check_sweeps(sw)
        law2 = _forms.fit_law(coarse, p2, a2, sw.reload_curves(), heldout=False)
        fine, crs = running_params(scene, law), running_params(coarse, law2)
    except (RuntimeError, ValueError) as exc:
        return ResolutionCheck(
            n, half, {}, 0.0, RESOLUTION_TOL, "", time.perf_counter() - t0, str(exc), forms
        )
    params, beside = _compared(law, law2, fine, crs)
    law_alpha = law_alpha_change(fine, crs, sweeps)
    pf, pc = alpha_points(sweeps), alpha_points(sw)
    common = [k for k in pf if k in pc and pf[k] > 0]
    da = max((abs(pc[k] - pf[k]) / pf[k] for k in common), default=0.0)
    moved = [f"{k} {100 * v[2]:.1f} %" for k, v in params.items() if v[2] > RESOLUTION_TOL]
    moved += [
        f"{_BRANCH_WORDS[k]} of the law up to {100 * v:.1f} %"
        for k, v in law_alpha.items()
        if v > RESOLUTION_TOL
    ]
    if da > RESOLUTION_TOL:
        moved.append(f"computed alpha up to {100 * da:.1f} %")
    warning = ""
    if moved:
        warning = (
            f"the law the parameter file runs depends on the resolution: from grid {n} to "
            f"{half} "
            + ", ".join(moved)
            + f" (tolerance {100 * RESOLUTION_TOL:g} %); a finer grid (--grid) would move it "
            "further"
        )
    return ResolutionCheck(
        n,
        half,
        params,
        float(da),
        RESOLUTION_TOL,
        warning,
        time.perf_counter() - t0,
        "",
        forms,
        law_alpha,
        beside,
    )
