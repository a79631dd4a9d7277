"""The sliding study of Sec. 3.3: one sliding sweep per pressure, as independent jobs.

:func:`sliding_study` runs :func:`~halfspace_calib.studies.sliding.sliding_sweep` per pressure;
:class:`SlidingStudy` summarises them (Fig. 15's ratio per pressure).
"""

import time
from dataclasses import dataclass

import numpy as np

from ..common.jobs import run_jobs
from ..contact.materials import Materials, SolverSettings, records
from ..topography import Surface
from .sliding import (
    SLIDING_PRESSURES,
    _as_array,
    _check_sweep,
    sliding_surfaces,
    sliding_sweep,
)

__all__ = ["SlidingStudy", "sliding_study"]


@dataclass
class SlidingStudy:
    """One :class:`SlidingResult` per pressure (``None`` where the job failed, see ``errors``)."""

    pressures: tuple
    results: list
    errors: dict
    seconds: float
    settings: dict

    @property
    def ok(self):
        """The successful sweeps."""
        return [r for r in self.results if r is not None]

    def summary(self):
        """Steady-sliding summary per pressure (positions ``>= 1``), plus the overall maximum."""
        rows = [r.steady for r in self.ok]
        return {
            "rows": rows,
            "ratio_max": max((r["ratio_max"] for r in rows), default=float("nan")),
            "failed_pressures": sorted(self.errors),
            "unconverged": {r.p_mean: r.failed_positions for r in self.ok if not r.all_converged},
            "seconds": self.seconds,
        }


@dataclass(frozen=True)
class _SweepJob:
    """One pressure of the study (sent to a worker process)."""

    workpiece: np.ndarray
    tool: np.ndarray
    dx: float
    p_mean: float
    materials: Materials
    solver: SolverSettings
    positions: int | None
    warm_start: str
    dy: float | None


def _sweep_job(job):
    return sliding_sweep(
        job.workpiece,
        job.tool,
        job.dx,
        job.p_mean,
        materials=job.materials,
        solver=job.solver,
        positions=job.positions,
        warm_start=job.warm_start,
        dy=job.dy,
    )


def sliding_study(
    pressures=SLIDING_PRESSURES,
    *,
    workpiece=None,
    tool=None,
    dx=None,
    materials=None,
    solver=None,
    positions=None,
    warm_start="tool",
    seed_workpiece=1,
    seed_tool=2,
    rough_tool=False,
    workers=1,
    scheduler=None,
    progress=True,
):
    """The sliding study: one :func:`sliding_sweep` per pressure, as independent jobs.

    It is the paper's Sec. 3.3.

    Parameters
    ----------
    pressures : sequence of float
        ``p_mean`` values in Pa (default 100-600 MPa), each in ``(0, H)``.
    workpiece, tool : array_like or Surface, optional
        Default: :func:`sliding_surfaces` (384 x 128 strip of 6.33 mm x 2.11 mm, Ra 0.989 um /
        Rq 1.201 um; 128 x 128 tool of Table 1). ``dx`` defaults to the workpiece Surface's
        element size.
    materials, solver, positions, warm_start
        As in :func:`~halfspace_calib.studies.sliding.sliding_sweep`.
    seed_workpiece, seed_tool, rough_tool
        Settings of the default surfaces.
    workers, scheduler, progress
        Passed to :func:`halfspace_calib.common.jobs.run_jobs` (one job per pressure).

    Returns
    -------
    SlidingStudy
    """
    mat, sol = records(materials, solver)
    pressures = tuple(float(p) for p in pressures)
    if not pressures:
        raise ValueError("pressures must hold at least one p_mean (Pa)")
    H = mat.H
    bad = [p for p in pressures if not (0 < p < H)]
    if bad:
        raise ValueError(f"pressures must be in (0, H) = (0, {H:g}) Pa, got {bad}")
    if workpiece is None or tool is None:
        dwp, dtl = sliding_surfaces(
            seed_workpiece=seed_workpiece, seed_tool=seed_tool, rough_tool=rough_tool
        )
        workpiece = dwp if workpiece is None else workpiece
        tool = dtl if tool is None else tool
    if dx is None:
        if not isinstance(workpiece, Surface):
            raise ValueError("dx (m) is required when the workpiece is a plain array")
        dx = workpiece.dx
    dy = workpiece.dy if isinstance(workpiece, Surface) else None
    for s, name in ((workpiece, "workpiece"), (tool, "tool")):
        if isinstance(s, Surface) and not (
            np.isclose(s.dx, dx, rtol=1e-6) and np.isclose(s.dy, dy or dx, rtol=1e-6)
        ):
            raise ValueError(f"{name} element size {s.dx:g} x {s.dy:g} m differs from dx={dx:g} m")
    E_star = mat.E_star
    wp_h, tl_h = _as_array("workpiece", workpiece), _as_array("tool", tool)
    # validate everything once, before any job runs
    _check_sweep(
        wp_h,
        tl_h,
        dx,
        E_star,
        pressures[0],
        H,
        mat.m,
        mat.sigma_y,
        positions,
        sol.tol,
        dy,
        warm_start,
    )
    jobs = [_SweepJob(wp_h, tl_h, dx, p, mat, sol, positions, warm_start, dy) for p in pressures]
    t0 = time.perf_counter()
    out = run_jobs(
        _sweep_job,
        jobs,
        workers=workers,
        scheduler=scheduler,
        progress=progress,
        desc="sliding study",
    )
    results = [j.value if j.ok else None for j in out]
    errors = {pressures[j.index]: j.error for j in out if not j.ok}
    settings = dict(
        H=H,
        m=mat.m,
        sigma_y=mat.sigma_y,
        positions=positions,
        tol=sol.tol,
        volume_conservation=sol.volume_conservation,
        periodic=sol.periodic,
        warm_start=warm_start,
        dy=dy,
        E_star=E_star,
        dx=dx,
        workpiece_shape=list(wp_h.shape),
        tool_shape=list(tl_h.shape),
    )
    return SlidingStudy(pressures, results, errors, time.perf_counter() - t0, settings)
