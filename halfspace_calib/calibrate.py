"""Calibration pipeline (Sec. 3.1 and 4): surfaces in, sweeps, fit, ``FrictionParams`` out.

A :class:`Scene` holds everything a calibration needs (surfaces, materials, pressures, solver
settings). :func:`run_sweeps` runs the first-loading and un-/reloading sweeps as independent jobs
(one per load level ``p_hist``: load, record, then reload the deformed workpiece at pressures below
``p_hist`` with warm starts between neighbouring pressures). :func:`calibrate` fits Eqs. 24-25 to
the curves and returns the parameters with their provenance; :func:`write_outputs` writes the
parameter file, CSV tables and plots.

Reading of the paper for the reload surface: the plastically flattened workpiece (``h - u_pl``) is
what is contacted again. The Pullen-Williamson volume conservation lifts every out-of-contact
element by ``V_removed / A_out``; at high loads that lift exceeds the flattened plateau, so a
reload on that surface is *not* elastic, against the paper's own statement that it is. The lifted
surface is therefore used for the roughness after unloading (Figs. 3-4) and, on request
(``reload_surface="volume_conserving"``), for the reload; the report states which one ran and the
largest reload pressure against ``H``.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np

from . import effects as _eff
from . import fit as _fit
from ._scene import Scene, load_scene
from ._scene_surfaces import SceneSurfaces, load_scene_surfaces
from .cerruti import E_prime
from .jobs import run_jobs
from .normal import solve_normal_pair
from .presliding import presliding_curve

__all__ = [
    "Scene",
    "SweepResult",
    "Calibration",
    "ResolutionCheck",
    "SceneSurfaces",
    "load_scene",
    "load_scene_surfaces",
    "scene_surfaces",
    "run_sweeps",
    "calibrate",
]

#: a first-loading or reload fit with R^2 below this makes the run fail (exit code 1)
R2_MIN = 0.9
#: relative change between the chosen grid and half of it above which the check warns
RESOLUTION_TOL = 0.10


def scene_surfaces(scene):
    """The workpiece and tool surfaces of a scene on the solver grid: ``(workpiece, tool)``.

    The solver-grid half of :func:`load_scene_surfaces` (the one loader for a scene).
    """
    s = load_scene_surfaces(scene)
    return s.workpiece, s.tool


# ----------------------------------------------------------------------------- sweeps
def _record(res):
    return {
        "alpha": float(res.alpha),
        "nit": int(res.nit),
        "converged": bool(res.converged),
        "residual": float(res.residual),
        "message": res.message,
        "max_pressure": float(res.pressure.max()),
        "plastic_fraction": float(res.plastic_fraction),
        "u0": float(res.u0),
    }


def _level_job(job):
    """One load level: first loading to ``p_hist``, then the reload curve below it."""
    kw = dict(H=job["H"], tol=job["tol"], periodic=job["periodic"], dy=job["dy"])
    res = solve_normal_pair(
        job["tool"],
        job["workpiece"],
        job["dx"],
        job["E_star"],
        job["p_hist"],
        volume_conservation=job["volume_conservation"],
        **kw,
    )
    out = {"p_hist": job["p_hist"], "loading": _record(res)}
    # Figs. 3-4: roughness of the unloaded workpiece (volume-conserving surface)
    deformed_vc = res.deformed_workpiece
    h = deformed_vc - deformed_vc.mean()
    out["Ra_after"] = float(np.mean(np.abs(h)))
    out["Rq_after"] = float(np.sqrt(np.mean(h * h)))
    if job["volume_conservation"]:
        out["volume_change"] = float(
            (deformed_vc.sum() - job["workpiece"].sum()) * job["dx"] * job["dy"]
        )
    if job["keep_map"]:
        out["pressure_map"] = res.pressure
    if job.get("tangential") is not None:
        out["tangential"] = _tangential_record(res, job)
    reload = []
    if job["reload_pressures"]:
        if job["reload_surface"] == "plastic":
            surface = job["workpiece"] - res.plastic_displacement
        else:
            surface = deformed_vc
        p_init = res.pressure
        for p in sorted(job["reload_pressures"], reverse=True):  # warm start from the neighbour
            r = solve_normal_pair(
                job["tool"],
                surface,
                job["dx"],
                job["E_star"],
                p,
                volume_conservation=False,
                p_init=p_init,
                **kw,
            )
            rec = _record(r)
            rec["p_mean"] = p
            reload.append(rec)
            p_init = r.pressure
        reload.reverse()
    out["reload"] = reload
    return out


def _tangential_record(res, job):
    """Pre-sliding curve on the loaded contact (the tangential effect); errors are recorded."""
    t = job["tangential"]
    t0 = time.perf_counter()
    try:
        curve = presliding_curve(
            res.pressure,
            job["dx"],
            job["E_star"],
            t["E_prime"],
            m=t["m"],
            sigma_y=t["sigma_y"],
            dy=job["dy"],
            periodic=job["periodic"],
            tol=t["tol"],
        )
    except Exception as exc:  # noqa: BLE001 - one failed curve must not lose the load level
        return {"error": f"{type(exc).__name__}: {exc}", "seconds": time.perf_counter() - t0}
    return dict(curve.as_dict(), seconds=time.perf_counter() - t0)


@dataclass
class SweepResult:
    """Curves of the sweeps: one entry per load level, in the scene's pressure order."""

    levels: list
    failed: list
    seconds: float
    surfaces: dict = field(default_factory=dict)

    @property
    def loading(self):
        """``(p_mean, alpha)`` arrays of the converged first-loading points."""
        ok = [lv for lv in self.levels if lv["loading"]["converged"]]
        return (
            np.array([lv["p_hist"] for lv in ok]),
            np.array([lv["loading"]["alpha"] for lv in ok]),
        )

    def reload_curves(self):
        """Converged reload curves as :class:`halfspace_calib.fit.ReloadCurve` objects."""
        curves = []
        for lv in self.levels:
            pts = [r for r in lv["reload"] if r["converged"]]
            if lv["loading"]["converged"] and len(pts) >= 2:
                curves.append(
                    _fit.ReloadCurve(
                        lv["p_hist"],
                        np.array([r["p_mean"] for r in pts]),
                        np.array([r["alpha"] for r in pts]),
                    )
                )
        return curves

    def not_converged(self):
        """Solves that did not reach the tolerance (left out of the fit): ``[{p_hist, p_mean, message}]``."""
        out = []
        for lv in self.levels:
            if not lv["loading"]["converged"]:
                out.append(
                    {
                        "p_hist": lv["p_hist"],
                        "p_mean": lv["p_hist"],
                        "message": lv["loading"]["message"],
                    }
                )
            for r in lv["reload"]:
                if not r["converged"]:
                    out.append(
                        {"p_hist": lv["p_hist"], "p_mean": r["p_mean"], "message": r["message"]}
                    )
        return out

    def max_reload_pressure(self):
        """Largest local pressure reached on any reload (Pa): ``< H`` means the reloads were elastic."""
        vals = [r["max_pressure"] for lv in self.levels for r in lv["reload"]]
        return max(vals) if vals else 0.0

    def max_reload_plastic_fraction(self):
        """Largest fraction of elements at the cap on any reload (0 for an elastic reload)."""
        vals = [r["plastic_fraction"] for lv in self.levels for r in lv["reload"]]
        return max(vals) if vals else 0.0


def run_sweeps(scene, *, progress=True, surfaces=None):
    """Run the first-loading and reload sweeps of ``scene``; failures are recorded, not raised.

    ``surfaces``: the scene's :class:`SceneSurfaces` if already loaded.
    """
    if surfaces is None:
        wp, tl = scene_surfaces(scene)
    else:
        wp, tl = surfaces.workpiece, surfaces.tool
    E_star = scene.E_star
    tangential = None
    if "tangential" in scene.effects and scene.m > 0:
        tangential = {
            "E_prime": E_prime(scene.E_workpiece, scene.nu_workpiece, scene.E_tool, scene.nu_tool),
            "m": scene.m,
            "sigma_y": scene.sigma_y,
            "tol": scene.tol,
        }
    jobs = []
    top = max(scene.pressures)
    for p in scene.pressures:
        reload = [f * p for f in scene.reload_fractions] if p >= scene.reload_from else []
        jobs.append(
            {
                "tool": np.asarray(tl.heights),
                "workpiece": np.asarray(wp.heights),
                "dx": wp.dx,
                "dy": wp.dy,
                "E_star": E_star,
                "H": scene.H,
                "p_hist": p,
                "tol": scene.tol,
                "periodic": scene.periodic,
                "volume_conservation": scene.volume_conservation,
                "reload_surface": scene.reload_surface,
                "reload_pressures": reload,
                "keep_map": p == top,
                "tangential": tangential,
            }
        )
    t0 = time.perf_counter()
    results = run_jobs(
        _level_job,
        jobs,
        workers=scene.workers,
        scheduler=scene.scheduler,
        progress=progress,
        desc="half-space sweeps",
    )
    levels, failed = [], []
    for job, r in zip(jobs, results, strict=True):
        if r.ok:
            levels.append(r.value)
        else:
            failed.append({"p_hist": job["p_hist"], "error": r.error})
    return SweepResult(levels, failed, time.perf_counter() - t0, {"workpiece": wp, "tool": tl})


# ----------------------------------------------------------------------------- resolution
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


def _alpha_points(sweeps):
    """``{(p_hist, p_mean): alpha}`` of every converged solve."""
    pts = {}
    for lv in sweeps.levels:
        if lv["loading"]["converged"]:
            pts[(lv["p_hist"], lv["p_hist"])] = lv["loading"]["alpha"]
        for r in lv["reload"]:
            if r["converged"]:
                pts[(lv["p_hist"], r["p_mean"])] = r["alpha"]
    return pts


def _fit_sweeps(scene, sweeps):
    """``(first, reload)`` fits of the sweeps; ``RuntimeError`` if too few solves converged."""
    p, alpha = sweeps.loading
    curves = sweeps.reload_curves()
    if p.size < 3 or not curves:
        raise RuntimeError(
            f"calibration needs >= 3 converged load levels and one reload curve; got {p.size} and "
            f"{len(curves)}. Failures: {sweeps.failed}; non-converged: "
            + "; ".join(
                f"{lv['p_hist']:g} Pa: {lv['loading']['message']}"
                for lv in sweeps.levels
                if not lv["loading"]["converged"]
            )
        )
    first = _fit.fit_first_loading(p, alpha, scene.H)
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
    coarse = dataclasses.replace(
        scene, grid=half, effects=("normal",), resolution_check=False, workers=scene.workers
    )
    try:
        surfs = load_scene_surfaces(coarse, check_sampling=False)
        sw = run_sweeps(coarse, progress=progress, surfaces=surfs)
        f2, r2 = _fit_sweeps(coarse, sw)
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
    fine, crs = _alpha_points(sweeps), _alpha_points(sw)
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


# ----------------------------------------------------------------------------- calibration
@dataclass
class Calibration:
    """Result of :func:`calibrate`: the parameters, the fits and the sweeps behind them."""

    params: object
    first: object
    reload: object
    sweeps: SweepResult
    scene: Scene
    seconds: float
    effects: dict = field(default_factory=dict)
    files: tuple = ()
    resolution: ResolutionCheck | None = None

    def problems(self):
        """Why the run failed, one sentence each (empty if it did not).

        A failed or non-converged load level or solve, a fit with ``R^2 <`` :data:`R2_MIN`, a
        fitted parameter on its bound or a fit that did not converge, and failed effect solves.
        """
        out = [f"load level {f['p_hist']:g} Pa failed" for f in self.sweeps.failed]
        out += [
            f"not converged, left out of the fit: p_hist {nc['p_hist']:g} Pa, p_mean "
            f"{nc['p_mean']:g} Pa: {nc['message']}"
            for nc in self.sweeps.not_converged()
        ]
        for name, fit in (("first loading (Eq. 24)", self.first), ("reload (Eq. 25)", self.reload)):
            if fit.r_squared < R2_MIN:
                out.append(
                    f"{name} fit R^2 = {fit.r_squared:.4f} < {R2_MIN:g}: the law does not "
                    "describe the computed curve (check units, pressures and the surfaces)"
                )
            if fit.at_bound:
                out.append(
                    f"{name} fit: {', '.join(fit.at_bound)} ended on a bound ({fit.message})"
                )
            elif not fit.converged:
                out.append(f"{name} fit did not converge: {fit.message}")
        t = self.effects.get("tangential", {})
        if "summary" in t:
            out += [
                f"tangential solve at {e['p_mean']:g} Pa failed: {e['error']}"
                for e in t["summary"]["errors"]
            ]
            out += [
                f"tangential solve at {r['p_mean']:g} Pa did not converge"
                for r in t["summary"]["rows"]
                if not r["converged"]
            ]
        sl = self.effects.get("sliding", {})
        if "study" in sl:
            out += [
                f"sliding at {p:g} Pa failed: {e.splitlines()[0]}"
                for p, e in sl["study"].errors.items()
            ]
        inc = self.effects.get("inclined", {})
        if "result" in inc and not inc["result"].all_converged:
            out.append("an inclined-patch normal solve did not converge")
        return out

    @property
    def degenerate(self):
        """``""`` when both fits are usable, else why not (see ``FitResult.degenerate``)."""
        parts = [
            f"{name}: {fit.degenerate}"
            for name, fit in (("first loading", self.first), ("reload", self.reload))
            if fit.degenerate
        ]
        return "; ".join(parts)

    def summary(self):
        """JSON-ready summary (also stored in the parameter file's provenance)."""
        P = self.params
        return {
            "C1": P.C1,
            "n1": P.n1,
            "C2": P.C2,
            "n2": P.n2,
            "m": P.m,
            "sigma_y": P.sigma_y,
            "H": P.H,
            "mu_eff": P.mu_eff,
            "tau_max": P.tau_max,
            "first_loading_r2": self.first.r_squared,
            "reload_r2": self.reload.r_squared,
            "fit_degenerate": {
                "first_loading": self.first.degenerate,
                "reload": self.reload.degenerate,
            },
            "max_jump_relative": float(np.max(self.reload.jump_relative))
            if self.reload.jump.size
            else 0.0,
            "failed_levels": self.sweeps.failed,
            "not_converged": self.sweeps.not_converged(),
            "max_reload_pressure_over_H": self.sweeps.max_reload_pressure() / self.scene.H,
            "max_reload_plastic_fraction": self.sweeps.max_reload_plastic_fraction(),
            "geo_ratio": P.geo_ratio,
            "effects": list(self.scene.effects),
            "effect_results": _effects_record(self.effects),
            "grid": self.scene.grid,
            "periodic": self.scene.periodic,
            "files": [f.as_dict() for f in self.files],
            "resolution_check": None if self.resolution is None else self.resolution.as_dict(),
            "problems": self.problems(),
            "seconds": self.seconds,
        }


def calibrate(scene=None, *, progress=True, surfaces=None):
    """Run the sweeps of ``scene`` (default: the built-in scene) and fit the law.

    ``surfaces``: the scene's :class:`SceneSurfaces` if already loaded (the CLI loads them
    first, to refuse bad input before any sweep). For files, ``scene.grid=None`` becomes the
    loader's grid and, with ``scene.resolution_check``, the normal sweeps run again at half
    the grid (:func:`resolution_check`).

    Raises ``RuntimeError`` if too few load levels converged for a fit (the sweep's
    failures are in the message).
    """
    scene = Scene() if scene is None else scene
    t0 = time.perf_counter()
    surfs = load_scene_surfaces(scene) if surfaces is None else surfaces
    if scene.grid != surfs.grid:
        scene = dataclasses.replace(scene, grid=surfs.grid)
    sweeps = run_sweeps(scene, progress=progress, surfaces=surfs)
    p, _ = sweeps.loading
    first, reload = _fit_sweeps(scene, sweeps)
    wp, tl = sweeps.surfaces["workpiece"], sweeps.surfaces["tool"]
    effects = _run_effects(scene, sweeps, surfs, progress)
    resolution = (
        resolution_check(scene, first, reload, sweeps, progress=progress)
        if scene.resolution_check
        else None
    )
    params = _fit.make_params(
        first,
        reload,
        m=scene.m,
        sigma_y=scene.sigma_y,
        H=scene.H,
        surfaces={"workpiece": wp, "tool": tl},
        grid={
            "shape": list(wp.shape),
            "dx": wp.dx,
            "dy": wp.dy,
            "periodic": scene.periodic,
            "periodic_reason": "measured files: a scan is not one period of a surface, "
            "non-periodic (DC-FFT) solve"
            if scene.from_files and not scene.periodic
            else ("synthetic surfaces are periodic" if scene.periodic else "chosen"),
        },
        tolerance=scene.tol,
        pressures={
            "loading": list(scene.pressures),
            "reload_fractions": list(scene.reload_fractions),
            "reload_from": scene.reload_from,
        },
        material={
            "E_workpiece": scene.E_workpiece,
            "nu_workpiece": scene.nu_workpiece,
            "E_tool": scene.E_tool,
            "nu_tool": scene.nu_tool,
            "E_star": scene.E_star,
            "H": scene.H,
            "sigma_y": scene.sigma_y,
            "m": scene.m,
        },
        extra={
            "model": {
                "volume_conservation": scene.volume_conservation,
                "reload_surface": scene.reload_surface,
                "effects": list(scene.effects),
                "max_reload_pressure_over_H": sweeps.max_reload_pressure() / scene.H,
                "max_reload_plastic_fraction": sweeps.max_reload_plastic_fraction(),
                "failed_levels": sweeps.failed,
                "geo_threshold": scene.geo_threshold,
            },
            "effects": _effects_record(effects),
            "files": surfs.records(),
            "resolution_check": None if resolution is None else resolution.as_dict(),
        },
        p_range=(float(p.min()), float(p.max())),
        k_t=_eff.stiffness_table(effects.get("tangential")),
    )
    if "inclined" in effects:
        params = params.replace(
            geo_ratio=effects["inclined"].get("decision", {}).get("geo_ratio", 0.0)
        )
    return Calibration(
        params,
        first,
        reload,
        sweeps,
        scene,
        time.perf_counter() - t0,
        effects,
        surfs.files,
        resolution,
    )


def _run_effects(scene, sweeps, surfs, progress):
    """Run (or collect) every effect of the scene but ``"normal"``; see :mod:`.effects`."""
    out = {}
    if "tangential" in scene.effects:
        if scene.m == 0:
            out["tangential"] = {
                "skipped": "m = 0: the Tresca bound (Eq. 18) is zero, no "
                "tangential traction and no stiffness"
            }
        else:
            secs = sum(lv.get("tangential", {}).get("seconds", 0.0) for lv in sweeps.levels)
            out["tangential"] = {
                "summary": _eff.summarize_tangential(sweeps.levels),
                "seconds": secs,
            }
    if "inclined" in scene.effects:
        measured = (surfs.measured_workpiece, surfs.measured_tool, surfs.block)
        out["inclined"] = _eff.run_inclined(scene, measured=measured)
    if "sliding" in scene.effects:
        out["sliding"] = _eff.run_sliding(scene, progress=progress, tool=surfs.tool)
    return out


def _effects_record(effects):
    """JSON-ready record of the effects' key results (provenance and ``summary.json``)."""
    rec = {}
    for name, e in effects.items():
        if "skipped" in e:
            rec[name] = {"skipped": e["skipped"]}
        elif name == "tangential":
            rec[name] = dict(e["summary"], seconds=e["seconds"])
        elif name == "inclined":
            d = e["decision"]
            rec[name] = {
                "geo_ratio": d["geo_ratio"],
                "applied": d["applied"],
                "ratio_mean": d["ratio_mean"],
                "threshold": d["threshold"],
                "reason": d["reason"],
                "method": d["method"],
                "fit": d["fit"],
                "study": e["result"].summary(),
                "seconds": e["seconds"],
            }
        elif name == "sliding":
            st = e["study"]
            rec[name] = dict(
                st.summary(),
                errors={str(k): v.splitlines()[0] for k, v in st.errors.items()},
                seconds=e["seconds"],
            )
    return rec
