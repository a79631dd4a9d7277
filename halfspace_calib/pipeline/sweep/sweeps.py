"""The normal (and, with the tangential effect, pre-sliding) sweeps of a scene (Sec. 3.1).

:func:`run_sweeps` runs one independent job per load level ``p_hist``: load, record, then reload
the deformed workpiece at pressures below ``p_hist`` with warm starts between neighbouring
pressures. See :mod:`halfspace_calib.pipeline.calibration` for the reading of the reload surface.
"""

import time
from dataclasses import dataclass, field

import numpy as np

from ...common.jobs import default_workers, run_jobs
from ...contact.area import corrected_contact_ratio
from ...contact.materials import Materials, SolverSettings
from ...contact.normal import solve_normal_pair
from ...studies.presliding import PreslidingCurve, presliding_curve
from . import levels as _levels
from .scene_surfaces import load_scene_surfaces

__all__ = [
    "FailedLevel",
    "LevelResult",
    "NotConverged",
    "SolveRecord",
    "SweepResult",
    "scene_surfaces",
    "run_sweeps",
]


def scene_surfaces(scene):
    """The workpiece and tool surfaces of a scene on the solver grid: ``(workpiece, tool)``.

    The solver-grid half of :func:`load_scene_surfaces` (the one loader for a scene).
    """
    s = load_scene_surfaces(scene)
    return s.workpiece, s.tool


# ----------------------------------------------------------------------------- records
@dataclass(frozen=True)
class SolveRecord:
    """One normal solve of a sweep (SI units): what the tables, the fit and the report read."""

    p_mean: float
    alpha: float
    nit: int
    converged: bool
    residual: float
    message: str
    max_pressure: float
    plastic_fraction: float
    u0: float
    coarse_nit: tuple = ()

    @classmethod
    def of(cls, res, contact_area="count"):
        """The record of a :class:`~halfspace_calib.contact.normal.NormalResult`.

        ``contact_area``: ``"count"`` records the solver's element count ``alpha``;
        ``"perimeter"`` the count corrected with the contact perimeter (Yastrebov et al. 2017,
        :func:`~halfspace_calib.contact.area.corrected_contact_ratio`).
        """
        if contact_area == "perimeter":
            alpha = corrected_contact_ratio(res.pressure, periodic=res.periodic)
        else:
            alpha = res.alpha
        return cls(
            p_mean=float(res.p_mean),
            alpha=float(alpha),
            nit=int(res.nit),
            converged=bool(res.converged),
            residual=float(res.residual),
            message=res.message,
            max_pressure=float(res.pressure.max()),
            plastic_fraction=float(res.plastic_fraction),
            u0=float(res.u0),
            coarse_nit=tuple(int(k) for k in res.coarse_nit),
        )


@dataclass
class LevelResult:
    """One load level ``p_hist``: its first loading, the reload curve below it, the roughness after.

    Attributes
    ----------
    p_hist : float
        The level (Pa).
    loading : SolveRecord
        The first loading to ``p_hist``.
    reload : list of SolveRecord
        The reloads of the deformed workpiece, ascending ``p_mean``.
    Ra_after, Rq_after : float
        Roughness of the unloaded (volume-conserving) workpiece (m, Figs. 3-4).
    volume_change : float or None
        Volume change of the workpiece (m^3) with volume conservation on, else ``None``.
    pressure_map : ndarray or None
        Contact pressure at ``p_hist`` (kept for the highest level only).
    tangential : PreslidingCurve or None
        The pre-sliding curve (tangential effect), ``None`` if it did not run or failed.
    tangential_error : str or None
        Why the pre-sliding curve failed.
    tangential_seconds : float
        Wall time of the pre-sliding curve.
    loading_seconds, reload_seconds : float
        Wall time of the first loading and of the reload curve (the normal solves).
    """

    p_hist: float
    loading: SolveRecord
    reload: list = field(default_factory=list)
    Ra_after: float = 0.0
    Rq_after: float = 0.0
    volume_change: float | None = None
    pressure_map: np.ndarray | None = None
    tangential: PreslidingCurve | None = None
    tangential_error: str | None = None
    tangential_seconds: float = 0.0
    loading_seconds: float = 0.0
    reload_seconds: float = 0.0


@dataclass(frozen=True)
class FailedLevel:
    """A load level whose job raised (left out of the fit)."""

    p_hist: float
    error: str


@dataclass(frozen=True)
class NotConverged:
    """A solve that did not reach the tolerance (left out of the fit)."""

    p_hist: float
    p_mean: float
    message: str


@dataclass(frozen=True)
class _LevelJob:
    """Everything one load level's job needs (sent to a worker process)."""

    workpiece: np.ndarray
    tool: np.ndarray
    dx: float
    dy: float
    p_hist: float
    materials: Materials
    solver: SolverSettings
    reload_surface: str
    reload_pressures: tuple
    keep_map: bool
    tangential: bool
    contact_area: str = "count"


# ----------------------------------------------------------------------------- sweeps
def _level_job(job):
    """One load level: first loading to ``p_hist``, then the reload curve below it."""
    mat, sol = job.materials, job.solver
    kw = dict(H=mat.H, dy=job.dy, **sol.normal_kwargs())
    E_star = mat.E_star
    t0 = time.perf_counter()
    res = solve_normal_pair(
        job.workpiece,
        job.tool,
        job.dx,
        E_star,
        job.p_hist,
        volume_conservation=sol.volume_conservation,
        **kw,
    )
    out = LevelResult(job.p_hist, SolveRecord.of(res, job.contact_area))
    out.loading_seconds = time.perf_counter() - t0
    # Figs. 3-4: roughness of the unloaded workpiece (volume-conserving surface)
    deformed_vc = res.deformed_workpiece
    h = deformed_vc - deformed_vc.mean()
    out.Ra_after = float(np.mean(np.abs(h)))
    out.Rq_after = float(np.sqrt(np.mean(h * h)))
    if sol.volume_conservation:
        out.volume_change = float((deformed_vc.sum() - job.workpiece.sum()) * job.dx * job.dy)
    if job.keep_map:
        out.pressure_map = res.pressure
    if job.tangential:
        _tangential(out, res, job)
    if job.reload_pressures:
        if job.reload_surface == "plastic":
            surface = job.workpiece - res.plastic_displacement
        else:
            surface = deformed_vc
        t0 = time.perf_counter()
        # continuation down the reload curve: each solve starts from the secant extrapolation
        # of the two previous solutions (on the plastic surface the loaded state is the reload's
        # solution at p_hist): 4-7 % fewer iterations than starting from the neighbour alone
        prev = (job.p_hist, res.pressure)
        p_init = res.pressure
        order = sorted(job.reload_pressures, reverse=True)
        for i, p in enumerate(order):
            r = solve_normal_pair(
                surface,
                job.tool,
                job.dx,
                E_star,
                p,
                volume_conservation=False,
                p_init=p_init,
                **kw,
            )
            out.reload.append(SolveRecord.of(r, job.contact_area))
            p_init = r.pressure
            if i + 1 < len(order) and prev[0] != p:
                w = (order[i + 1] - p) / (p - prev[0])
                p_init = r.pressure + w * (r.pressure - prev[1])  # clipped to [0, H] by the solver
            prev = (p, r.pressure)
        out.reload.reverse()
        out.reload_seconds = time.perf_counter() - t0
    return out


def _tangential(out, res, job):
    """Pre-sliding curve on the loaded contact (the tangential effect); errors are recorded."""
    t0 = time.perf_counter()
    try:
        out.tangential = presliding_curve(
            res.pressure, job.dx, materials=job.materials, solver=job.solver, dy=job.dy
        )
    except Exception as exc:  # noqa: BLE001 - one failed curve must not lose the load level
        out.tangential_error = f"{type(exc).__name__}: {exc}"
    out.tangential_seconds = time.perf_counter() - t0


@dataclass
class SweepResult:
    """Curves of the sweeps: one :class:`LevelResult` per load level, ascending ``p_hist``."""

    levels: list
    failed: list
    seconds: float
    surfaces: dict = field(default_factory=dict)
    plan: _levels.LevelPlan | None = None  # the levels computed and why

    @property
    def loading(self):
        """``(p_mean, alpha)`` arrays of the converged first-loading points."""
        ok = [lv for lv in self.levels if lv.loading.converged]
        return (
            np.array([lv.p_hist for lv in ok]),
            np.array([lv.loading.alpha for lv in ok]),
        )

    def reload_curves(self):
        """Converged reload curves as :class:`halfspace_calib.pipeline.law.fit.ReloadCurve` objects."""
        return _levels.reload_curves(self.levels)

    def not_converged(self):
        """Solves that did not reach the tolerance (left out of the fit): :class:`NotConverged`."""
        out = []
        for lv in self.levels:
            if not lv.loading.converged:
                out.append(NotConverged(lv.p_hist, lv.p_hist, lv.loading.message))
            out += [
                NotConverged(lv.p_hist, r.p_mean, r.message) for r in lv.reload if not r.converged
            ]
        return out

    def max_reload_pressure(self):
        """Largest local pressure reached on any reload (Pa): ``< H`` means the reloads were elastic."""
        vals = [r.max_pressure for lv in self.levels for r in lv.reload]
        return max(vals) if vals else 0.0

    def max_reload_plastic_fraction(self):
        """Largest fraction of elements at the cap on any reload (0 for an elastic reload)."""
        vals = [r.plastic_fraction for lv in self.levels for r in lv.reload]
        return max(vals) if vals else 0.0


def run_sweeps(scene, *, progress=True, surfaces=None):
    """Run the first-loading and reload sweeps of ``scene``; failures are recorded, not raised.

    ``surfaces``: the scene's :class:`SceneSurfaces` if already loaded. With
    ``scene.adaptive_levels`` the levels come from :func:`.levels.adaptive_levels` (computed in
    rounds, each round's levels as parallel jobs), else they are ``scene.pressures``; the
    result's ``plan`` says which were computed and why.
    """
    if surfaces is None:
        wp, tl = scene_surfaces(scene)
    else:
        wp, tl = surfaces.workpiece, surfaces.tool
    tangential = "tangential" in scene.effects and scene.m > 0
    materials, solver = scene.materials, scene.solver
    top = max(scene.pressures)

    def job(p):
        reload = [f * p for f in scene.reload_fractions] if p >= scene.reload_from else []
        return _LevelJob(
            workpiece=np.asarray(wp.heights),
            tool=np.asarray(tl.heights),
            dx=wp.dx,
            dy=wp.dy,
            p_hist=p,
            materials=materials,
            solver=solver,
            reload_surface=scene.reload_surface,
            reload_pressures=tuple(reload),
            keep_map=p == top,
            tangential=tangential,
            contact_area=scene.contact_area,
        )

    workers = scene.workers
    if workers is None and scene.scheduler is None:
        pad = 2 if solver.boundary == "isolated" else 1  # isolated: zero-padded (DC-FFT) FFTs
        workers = default_workers(wp.heights.shape[0] * wp.heights.shape[1] * pad * pad)
    failed = []
    computed = {}  # job results by pressure, kept until a round asks for them

    def run_round(pressures, ahead=()):
        """The levels ``pressures`` by pressure (failures recorded).

        ``ahead``: levels a later round will probably ask for, computed now beside them and
        kept until asked for.
        """
        todo = [p for p in pressures if p not in computed]
        todo += [p for p in ahead if p not in computed and p not in todo]
        # the longest jobs first (a reload curve is 7 solves, a first loading alone 1), so that
        # a short job fills the other worker's time instead of delaying the round's end
        todo.sort(key=lambda p: (p < scene.reload_from, -p))
        jobs = [job(p) for p in todo]
        results = run_jobs(
            _level_job,
            jobs,
            workers=workers,
            scheduler=scene.scheduler,
            progress=progress,
            desc="half-space sweeps",
        )
        for jb, r in zip(jobs, results, strict=True):
            computed[jb.p_hist] = r
        done = {}
        for p in pressures:
            r = computed.pop(p)
            if r.ok:
                done[p] = r.value
            else:
                failed.append(FailedLevel(p, r.error))
        return done

    t0 = time.perf_counter()
    if scene.adaptive_levels:
        parallel = scene.scheduler is not None or workers != 1
        done, plan = _levels.adaptive_levels(scene, run_round, ahead=parallel)
    else:
        done, plan = run_round(list(scene.pressures)), _levels.fixed_plan(scene)
    levels = [done[p] for p in sorted(done)]
    failed.sort(key=lambda f: f.p_hist)
    return SweepResult(
        levels, failed, time.perf_counter() - t0, {"workpiece": wp, "tool": tl}, plan
    )
