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
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import effects as _eff
from . import fit as _fit
from . import surfaces as _surf
from .cerruti import E_prime
from .jobs import run_jobs
from .normal import composite_modulus, solve_normal_pair
from .presliding import presliding_curve

__all__ = [
    "Scene",
    "SweepResult",
    "Calibration",
    "load_scene",
    "scene_surfaces",
    "run_sweeps",
    "calibrate",
]

MPa = 1e6
DEFAULT_PRESSURES = (10e6, 25e6, 50e6, 100e6, 200e6, 300e6, 400e6, 500e6, 600e6)
DEFAULT_RELOAD_FRACTIONS = (0.05, 0.1, 0.25, 0.5, 0.75, 0.9)


@dataclass
class Scene:
    """Everything a calibration needs; every field has the paper's default (Table 1, Sec. 3.1).

    Surfaces: ``workpiece`` / ``tool`` are file paths (read with
    :func:`halfspace_calib.surfaces.read_surface`; ``unit`` (or ``workpiece_unit`` / ``tool_unit``
    for each file) and ``size`` for plain files) or
    ``None`` for the synthetic DC04-EDT-like sheet and tool of Table 1 (``rough_tool`` for the
    rough tool; ``measured_n``, a multiple of ``grid``, generates them on that finer grid and
    block-averages, so that one seed is the same physical surface at every ``grid``). Both are levelled and block-averaged to ``grid x grid`` elements.
    Materials in Pa; ``sigma_y`` defaults to ``H / 2.8`` (Bowden and Tabor). ``m`` is Tresca's
    factor: it does not enter the half-space model, only the parameter file (measure it, e.g. by
    ring compression).

    Effects (:mod:`halfspace_calib.effects`): ``effects`` names what is modelled besides the
    always-on ``"normal"`` sweeps: ``"tangential"`` (pre-sliding stiffness), ``"inclined"``
    (Eq. 23 and, if the mean ``tau_geo / tau_adh`` exceeds ``geo_threshold``, Eq. 26's
    ``geo_ratio``), ``"sliding"`` (Sec. 3.3). With ``"inclined"`` on synthetic surfaces
    ``measured_n`` defaults to ``4 grid``: the inclined patches are fitted on that measured grid
    and the calibration's surfaces are block averages of the same random field.
    """

    workpiece: str | None = None
    tool: str | None = None
    unit: str = "um"
    workpiece_unit: str | None = None
    tool_unit: str | None = None
    size: float | None = None
    rough_tool: bool = False
    seed_workpiece: int = 1
    seed_tool: int = 2
    grid: int = 128
    measured_n: int | None = None
    E_workpiece: float = 210e9
    nu_workpiece: float = 0.3
    E_tool: float = 210e9
    nu_tool: float = 0.3
    H: float = 800e6
    sigma_y: float | None = None
    m: float = 0.5
    pressures: tuple = DEFAULT_PRESSURES
    reload_from: float = 100e6
    reload_fractions: tuple = DEFAULT_RELOAD_FRACTIONS
    tol: float = 1e-8
    periodic: bool = True
    volume_conservation: bool = True
    reload_surface: str = "plastic"
    continuous_reload: bool = False
    workers: int = 1
    scheduler: str | None = None
    effects: tuple = ("normal",)
    geo_threshold: float = 0.05

    def __post_init__(self):
        self.effects = _eff.check_effects(self.effects)
        synthetic = self.workpiece is None and self.tool is None
        if "inclined" in self.effects and synthetic and self.measured_n is None:
            # the inclined patches need the measured grid: calibrate on the same random field
            self.measured_n = 4 * self.grid if isinstance(self.grid, int) else None
        self.pressures = tuple(float(p) for p in self.pressures)
        self.reload_fractions = tuple(float(f) for f in self.reload_fractions)
        if self.sigma_y is None:
            self.sigma_y = self.H / 2.8
        self.validate()

    def validate(self):
        """Raise ``ValueError`` naming the first bad field and its allowed range."""
        for name in ("E_workpiece", "E_tool", "H", "sigma_y"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be a finite number > 0 (Pa), got {v!r}")
        for name in ("nu_workpiece", "nu_tool"):
            v = getattr(self, name)
            if not (-1.0 < v <= 0.5):
                raise ValueError(f"{name} must be in (-1, 0.5], got {v!r}")
        if not (0.0 <= self.m <= 1.0):
            raise ValueError(f"m must be in [0, 1], got {self.m!r}")
        if not isinstance(self.grid, int) or self.grid < 8:
            raise ValueError(f"grid must be an integer >= 8, got {self.grid!r}")
        if len(self.pressures) < 3:
            raise ValueError("pressures must hold at least 3 values (Pa) for the fit of C1, n1")
        bad = [p for p in self.pressures if not (0 < p < self.H)]
        if bad:
            raise ValueError(f"pressures must be in (0, H) = (0, {self.H:g}) Pa, got {bad}")
        if any(not (0 < f < 1) for f in self.reload_fractions):
            raise ValueError("reload_fractions must be in (0, 1)")
        if not (0 < self.tol < 1):
            raise ValueError(f"tol must be in (0, 1), got {self.tol!r}")
        if self.reload_surface not in ("plastic", "volume_conserving"):
            raise ValueError("reload_surface must be 'plastic' or 'volume_conserving'")
        if not isinstance(self.workers, int) or self.workers < 0:
            raise ValueError(f"workers must be an integer >= 0, got {self.workers!r}")
        self.effects = _eff.check_effects(self.effects)
        g = self.geo_threshold
        if not (isinstance(g, (int, float)) and math.isfinite(g) and g >= 0):
            raise ValueError(f"geo_threshold must be a finite number >= 0 (a ratio), got {g!r}")
        if "inclined" in self.effects and self.workpiece is None and self.tool is None:
            mn = self.measured_n
            if mn is not None and (not isinstance(mn, int) or mn % self.grid or mn < 2 * self.grid):
                raise ValueError(
                    f"measured_n must be a multiple >= 2 of grid={self.grid} for the inclined "
                    f"effect (measured points per element), got {mn!r}"
                )

    @property
    def E_star(self):
        """Composite modulus, Eq. 2."""
        return composite_modulus(self.E_workpiece, self.nu_workpiece, self.E_tool, self.nu_tool)

    @property
    def reload_levels(self):
        """The ``p_hist`` values that get a reload curve."""
        return tuple(p for p in self.pressures if p >= self.reload_from)

    def as_dict(self):
        """Plain dict of the settings (for the provenance)."""
        return dataclasses.asdict(self)


def load_scene(path, **overrides):
    """Read a scene file (TOML, keys as the :class:`Scene` fields, SI units) and apply overrides."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not a valid TOML scene file ({exc})") from None
    data = data.get("scene", data)
    known = {f.name for f in dataclasses.fields(Scene)}
    unknown = set(data) - known
    if unknown:
        raise ValueError(f"{path}: unknown scene keys {sorted(unknown)}; known: {sorted(known)}")
    for key in ("workpiece", "tool"):  # relative paths are relative to the scene file
        if data.get(key) and not Path(data[key]).is_absolute():
            data[key] = str(path.parent / data[key])
    data.update({k: v for k, v in overrides.items() if v is not None})
    return Scene(**data)


def scene_surfaces(scene):
    """The workpiece and tool surfaces of a scene on the solver grid: ``(workpiece, tool)``."""
    n = scene.grid
    out = []
    for which in ("workpiece", "tool"):
        path = getattr(scene, which)
        if path is None:
            if which == "workpiece":
                s = _surf.dc04_edt_like(n, seed=scene.seed_workpiece, measured_n=scene.measured_n)
            else:
                s = _surf.tool_like(
                    n, rough=scene.rough_tool, seed=scene.seed_tool, measured_n=scene.measured_n
                )
        else:
            unit = getattr(scene, f"{which}_unit") or scene.unit
            s = _surf.read_surface(path, unit=unit, size=scene.size)
            s = _surf.level(s)
            if s.shape != (n, n):
                s = _surf.block_average(s, (n, n), trim=True)
        out.append(s)
    wp, tl = out
    if not np.isclose(wp.dx, tl.dx, rtol=1e-6) or not np.isclose(wp.dy, tl.dy, rtol=1e-6):
        raise ValueError(
            f"workpiece and tool must have the same element size, got {wp.dx:g} x {wp.dy:g} m "
            f"and {tl.dx:g} x {tl.dy:g} m (crop them to the same physical size)"
        )
    return wp, tl


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
        volume_conservation=True,
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


def run_sweeps(scene, *, progress=True):
    """Run the first-loading and reload sweeps of ``scene``; failures are recorded, not raised."""
    wp, tl = scene_surfaces(scene)
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
            "seconds": self.seconds,
        }


def calibrate(scene=None, *, progress=True):
    """Run the sweeps of ``scene`` (default: the built-in scene) and fit the law.

    Raises ``RuntimeError`` if too few load levels converged for a fit (the sweep's
    failures are in the message).
    """
    scene = Scene() if scene is None else scene
    t0 = time.perf_counter()
    measured = _eff.scene_measured_surfaces(scene) if "inclined" in scene.effects else None
    sweeps = run_sweeps(scene, progress=progress)
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
    wp, tl = sweeps.surfaces["workpiece"], sweeps.surfaces["tool"]
    effects = _run_effects(scene, sweeps, measured, progress)
    params = _fit.make_params(
        first,
        reload,
        m=scene.m,
        sigma_y=scene.sigma_y,
        H=scene.H,
        surfaces={"workpiece": wp, "tool": tl},
        grid={"shape": list(wp.shape), "dx": wp.dx, "dy": wp.dy, "periodic": scene.periodic},
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
        },
        p_range=(float(p.min()), float(p.max())),
        k_t=_eff.stiffness_table(effects.get("tangential")),
    )
    if "inclined" in effects:
        params = params.replace(
            geo_ratio=effects["inclined"].get("decision", {}).get("geo_ratio", 0.0)
        )
    return Calibration(params, first, reload, sweeps, scene, time.perf_counter() - t0, effects)


def _run_effects(scene, sweeps, measured, progress):
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
        out["inclined"] = _eff.run_inclined(scene, measured=measured)
    if "sliding" in scene.effects:
        out["sliding"] = _eff.run_sliding(scene, progress=progress)
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
