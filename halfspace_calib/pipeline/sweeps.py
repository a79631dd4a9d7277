"""The normal (and, with the tangential effect, pre-sliding) sweeps of a scene (Sec. 3.1).

:func:`run_sweeps` runs one independent job per load level ``p_hist``: load, record, then reload
the deformed workpiece at pressures below ``p_hist`` with warm starts between neighbouring
pressures. See :mod:`halfspace_calib.pipeline.calibration` for the reading of the reload surface.
"""

import time
from dataclasses import dataclass, field

import numpy as np

from ..common.jobs import run_jobs
from ..contact.cerruti import E_prime
from ..contact.normal import solve_normal_pair
from ..studies.presliding import presliding_curve
from . import fit as _fit
from .scene_surfaces import load_scene_surfaces

__all__ = ["SweepResult", "scene_surfaces", "run_sweeps"]


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
        job["workpiece"],
        job["tool"],
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
                surface,
                job["tool"],
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
