"""The friction factor ``m`` from ring-compression tests, with the law itself (``fe-demo ring-fit``).

The law is ``tau = m k alpha(p, p_hist)``: the roughness calibration gives the shape of ``alpha``,
the ring test the magnitude ``m``. A classical ring chart assumes ``tau = m k`` on the whole die
face, so its ``m`` is not the ``m`` of this law. Here the ring is computed by the FE model with
the calibrated law at several ``m``, and ``m`` is the least-squares fit of the computed
inner-diameter change to the measured one; the same fit with Tresca's law gives the ``m`` a
Tresca chart of the same FE model would give (``m_tresca_chart``).

Method (docs/getting_m.md):

1. One FE run to the largest measured reduction gives the whole curve ``d(reduction)`` at one
   ``m``. Runs at ``m`` in :data:`M_GRID` (two at a time where two CPUs are free).
2. At each measured reduction, ``d`` is interpolated across ``m`` by a monotone cubic (PCHIP),
   and ``m`` minimises the sum of squared residuals on ``[0, 1]``.
3. One or two refinement runs at the optimum join the grid and the fit is repeated, until ``m``
   moves by less than :data:`M_TOL` (at most :data:`MAX_REFINE` refinements).
4. The band: ``m -+ t_(N-1) s / sqrt(sum J_i^2)``, with ``s`` the residual standard deviation and
   ``J_i = dd/dm`` at each point (the linearised least-squares interval), clipped to ``[0, 1]``.

The runs at ``m = 0`` and ``m = 1`` bound every curve the law can give: points outside that
range by more than :data:`RANGE_TOL` are refused (no ``m`` can produce them), saying which way.
"""

from __future__ import annotations

import math
from concurrent.futures import as_completed
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import PchipInterpolator
from scipy.optimize import minimize_scalar
from scipy.stats import t as student_t

from frictionlaw import FrictionParams
from sbmf_cli import ParameterError, available_cpus, process_pool

from ..scenes import run_ring
from ..scenes.drive import ProgressBar
from .ring_tests import RingTest, read_ring_tests

__all__ = [
    "M_GRID",
    "RingTest",
    "RingFit",
    "RingFitError",
    "read_ring_tests",
    "ring_curve",
    "fit_m",
    "least_squares_m",
    "band_half_width",
]

#: the m of the first FE runs (0 and 1 bound every curve the law can give)
M_GRID = (0.0, 0.15, 0.3, 0.6, 1.0)
#: the fit stops when m moves by less than this between refinements
M_TOL = 2e-3
#: at most this many refinement runs per fit
MAX_REFINE = 2
#: a point may lie this far (inner-diameter change, a fraction) outside the m = 0 / m = 1 curves
RANGE_TOL = 0.02


class RingFitError(RuntimeError):
    """An FE ring run failed; ``m`` names the friction factor at which it failed."""

    def __init__(self, m, message):
        super().__init__(m, message)  # both in args: the error crosses process boundaries
        self.m, self.message = m, message

    def __str__(self):
        return f"the FE ring run at m = {self.m:g} failed: {self.message}"


@dataclass(frozen=True)
class RingFit:
    """Result of :func:`fit_m`."""

    law: str
    m: float
    m_lower: float
    m_upper: float
    band_level: float
    rmse: float
    n_points: int
    residuals: np.ndarray
    n_fe_runs: int
    curves: dict = field(repr=False)  # m -> (reduction, d) of each FE run
    message: str = ""
    #: the m of the refinement runs (the others are the grid's, or a grid run's retry)
    refined: tuple = ()
    #: the response surfaces ``m -> d`` built so far, by the reductions they are at
    _surfaces: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def surface(self, reduction):
        """``m -> d`` at ``reduction`` (PCHIP across the FE runs' m), built once per reduction set.

        The surface depends only on the FE runs and the reductions, so every prediction at the
        same reductions (the fitted curve and its band's two edges) shares one.
        """
        r = np.atleast_1d(np.asarray(reduction, float))
        key = (r.shape, r.tobytes())
        if key not in self._surfaces:
            self._surfaces[key] = _surface(self.curves, r)
        return self._surfaces[key]

    def predict(self, reduction, m=None):
        """The inner-diameter change the model gives at ``reduction`` for ``m`` (the fit's)."""
        return self.surface(reduction)(self.m if m is None else m)


def _law_kw(law, m, params):
    if law == "tresca":
        return {"m": m}
    return {"params": params.replace(m=m)}


def ring_curve(law, m, *, params=None, column="inner_diameter_change", reduction=0.5, **kw):
    """``(reduction, d)`` of one FE ring run with ``law`` at friction factor ``m``."""
    try:
        res = run_ring(law, reduction=reduction, **_law_kw(law, m, params), **kw)
    except (ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
        raise RingFitError(m, str(exc)) from None
    if not res.converged or not res.history:
        raise RingFitError(m, res.message or "did not converge")
    h = res.history
    return np.asarray(h["height_reduction"], float), np.asarray(h[column], float)


#: an FE run that fails is tried once more at m shifted by this (the grid's m are arbitrary)
M_RETRY = 0.01


def _curve_job(args):
    """One run at ``m``, retried once at ``m -+ M_RETRY`` if it fails; a second failure raises.

    The grid's ``m`` are arbitrary, so the neighbouring run is as good a point of the response
    surface; the error names the ``m`` of the first try.
    """
    law, m, params, column, reduction, kw = args
    try:
        return m, ring_curve(law, m, params=params, column=column, reduction=reduction, **kw)
    except RingFitError as first:
        m2 = round(m - M_RETRY if m + M_RETRY > 1.0 else m + M_RETRY, 6)
        try:
            return m2, ring_curve(law, m2, params=params, column=column, reduction=reduction, **kw)
        except RingFitError:
            raise RingFitError(m, f"{first.message} (and again at m = {m2:g})") from None


def _run_curves(law, ms, params, column, reduction, kw, workers, bar):
    """``{m: (reduction, d)}`` of one FE run per ``m``; ``bar.update()`` after each run."""
    jobs = [(law, float(m), params, column, reduction, kw) for m in ms]
    if workers > 1 and len(jobs) > 1:
        with process_pool(min(workers, len(jobs))) as pool:  # an interrupt ends the workers
            futures = [pool.submit(_curve_job, j) for j in jobs]
            for _ in as_completed(futures):
                bar.update()
            return dict(f.result() for f in futures)  # a failure: the first in job order
    out = {}
    for job in jobs:
        m, curve = _curve_job(job)
        out[m] = curve
        bar.update()
    return out


def _surface(curves, reduction):
    """``m -> d`` at every measured reduction: PCHIP across the runs' m (monotone)."""
    ms = np.array(sorted(curves))
    table = np.array([np.interp(reduction, *curves[m]) for m in ms])  # (n_m, n_points)
    return PchipInterpolator(ms, table, axis=0, extrapolate=False)


def least_squares_m(surface, d):
    """``m`` in ``[0, 1]`` minimising ``sum (surface(m) - d)^2``."""

    def ssr(m):
        return float(np.sum((surface(m) - d) ** 2))

    return float(
        minimize_scalar(ssr, bounds=(0.0, 1.0), method="bounded", options={"xatol": 1e-5}).x
    )


def band_half_width(residuals, jac, level):
    """Half width of the linearised least-squares band on ``m``: ``t_(N-1) s / sqrt(sum J^2)``.

    ``s`` is the residual standard deviation (``N - 1`` degrees of freedom, one parameter),
    ``J = dd/dm`` at each point; infinite where the data do not depend on ``m``.
    """
    n = len(residuals)
    s = math.sqrt(float(np.sum(np.square(residuals))) / max(n - 1, 1))
    sj = math.sqrt(float(np.sum(np.square(jac))))
    tq = float(student_t.ppf(0.5 + level / 2.0, max(n - 1, 1)))
    return tq * s / sj if sj > 0 else math.inf


def _check_range(test, curves):
    lo_m, hi_m = min(curves), max(curves)
    d0 = np.interp(test.reduction, *curves[lo_m])
    d1 = np.interp(test.reduction, *curves[hi_m])
    top, bottom = np.maximum(d0, d1), np.minimum(d0, d1)
    above = np.flatnonzero(test.d_inner > top + RANGE_TOL)
    below = np.flatnonzero(test.d_inner < bottom - RANGE_TOL)
    for idx, way, ref, m_ref in (
        (above, "above", top, "0 (no friction)"),
        (below, "below", bottom, "1 (sticking)"),
    ):
        if idx.size:
            i = int(idx[0])
            raise ParameterError(
                f"{{test}}: {idx.size} point(s) lie {way} what any m in [0, 1] gives (by more than "
                f"{RANGE_TOL:g}): e.g. reduction {test.reduction[i]:g}, {test.column} "
                f"{test.d_inner[i]:+.4f} against {ref[i]:+.4f} at m = {m_ref}; check the sign "
                "and units (fractions: -0.1 for -10 %), the geometry and the material",
                "test",
            )


def _fit_runs(test, law, params, top, ring_kw, workers, bar):
    """The FE runs of a fit and its least-squares ``m``: ``(curves, surface, m, refined m)``.

    The grid's runs first (:data:`M_GRID`; points outside what ``m = 0`` and ``m = 1`` give are
    refused), then a run at the optimum joins until ``m`` moves by less than :data:`M_TOL`.
    """
    col = test.column
    curves = _run_curves(law, M_GRID, params, col, top, ring_kw, workers, bar)
    _check_range(test, curves)
    m_fit, refined = None, []
    while True:
        surf = _surface(curves, test.reduction)
        m_new = least_squares_m(surf, test.d_inner)
        done = m_fit is not None and abs(m_new - m_fit) < M_TOL
        m_fit = m_new
        if done or len(refined) >= MAX_REFINE:
            break
        near = min(curves, key=lambda m: abs(m - m_fit))
        if abs(near - m_fit) < M_TOL / 2:
            break
        run = _run_curves(law, [round(m_fit, 6)], params, col, top, ring_kw, 1, bar)
        curves |= run
        refined += list(run)
    return curves, surf, m_fit, tuple(refined)


def fit_m(
    test, law="sbmf", *, params=None, band_level=0.9, workers=None, progress=False, **ring_kw
):
    """Fit the friction factor ``m`` of ``law`` to measured ring tests.

    Parameters
    ----------
    test : RingTest
        Measured points (:func:`read_ring_tests`).
    law : {"sbmf", "tresca"}
        ``sbmf``: the calibrated law of ``params`` (its ``k``, ``sigma_y / 2`` by default, and its
        ``alpha``), ``m`` varied; ``tresca``: the classical chart's law ``tau = m k`` of the FE
        model (``k`` the current flow stress over ``sqrt(3)``).
    params : FrictionParams
        For ``sbmf``.
    band_level : float
        Level of the band on ``m`` in ``(0, 1)``.
    workers : int, optional
        Processes for the FE runs (default: 2 where two CPUs are free, else 1;
        :func:`sbmf_cli.available_cpus`).
    progress : bool
        A progress bar over the FE runs (stderr).
    **ring_kw
        Geometry, mesh, increments and material of :func:`fe_demo.run_ring`.

    Returns
    -------
    RingFit

    Raises
    ------
    ValueError
        Points that no ``m`` in ``[0, 1]`` can produce (after the two extreme runs).
    RingFitError
        An FE run failed (naming its ``m``).
    """
    if law not in ("sbmf", "tresca"):
        raise ValueError(f"law must be 'sbmf' or 'tresca', got {law!r}")
    if law == "sbmf" and not isinstance(params, FrictionParams):
        raise ValueError("law sbmf needs params (a FrictionParams)")
    if not (0.0 < band_level < 1.0):
        raise ValueError(f"band_level must be in (0, 1), got {band_level!r}")
    if workers is None:
        workers = min(2, available_cpus())
    top = min(0.7, float(test.reduction.max()) + 0.02)  # the runs go a little past the data
    bar = ProgressBar(progress, len(M_GRID) + MAX_REFINE, f"ring fit ({law})", "FE run")
    try:
        curves, surf, m_fit, refined = _fit_runs(test, law, params, top, ring_kw, workers, bar)
    finally:
        bar.close()
    res = test.d_inner - surf(m_fit)  # surf: the surface of the final set of runs
    n = res.size
    half = band_half_width(res, surf.derivative()(m_fit), band_level)
    fit = RingFit(
        law=law,
        m=m_fit,
        m_lower=max(0.0, m_fit - half),
        m_upper=min(1.0, m_fit + half),
        band_level=band_level,
        rmse=math.sqrt(float(np.mean(res**2))),
        n_points=n,
        residuals=res,
        n_fe_runs=len(curves),
        curves=curves,
        message=f"{len(curves)} FE runs, {len(refined)} refinement(s)",
        refined=refined,
    )
    r = np.atleast_1d(np.asarray(test.reduction, float))
    fit._surfaces[(r.shape, r.tobytes())] = surf  # the measured points' surface, already built
    return fit
