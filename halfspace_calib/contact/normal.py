"""Elastic and elasto-plastic normal contact of rough surfaces on a half-space (Sec. 2.1).

Problem (Eqs. 3, 6-9), with ``h`` the composite topography (higher touches first, Fig. 2)::

    g_k = h_max - h_k + u_el,k + u_pl,k - u0            gap (Eq. 9)
    u_el = C p                                           Love / FFT (Eqs. 3-4)
    0 <= p_k <= H                                        Eqs. 6, 8
    p_k = 0      => g_k >= 0       (out of contact)
    0 < p_k < H  => g_k = 0        (elastic contact)
    p_k = H      => u_pl,k = -(h_max - h_k + u_el,k - u0) >= 0   (plastic set)
    mean(p) = p_mean                                     load control, fixes u0

Algorithm
---------
The elastic gap ``g_el = h_max - h + C p - u0`` is the gradient of the complementary energy
``1/2 p.Cp - p.(h - h_max + u0)``; the conditions above are exactly the KKT conditions of its
minimisation over the box ``0 <= p <= H`` with ``sum(p) = N p_mean`` (``u0`` is the multiplier of
the load constraint, ``u_pl = max(-g_el, 0)`` on the upper bound the multiplier of the cap). The
functional is strictly convex on the constraint set, so the minimiser is unique: it is the
fixed point of the paper's outer loop (plastic set at ``H``, elastic problem re-solved with the
plastic displacement in the gap, Eq. 9) and of any other convergent scheme.

We minimise it with the load-controlled active-set conjugate gradient of Polonsky and Keer
(Wear 231, 1999), extended to the box as in the "saturated" variants of the method (Bugnicourt,
Sainsot, Dureisseix, Gauthier, Lubrecht 2018, Tribol. Lett. 66:29): CG directions live on the
free set ``0 < p < H`` with ``u0`` chosen so that the gap has zero mean there; after each step the
pressure is projected onto ``[0, H]``; elements at a bound whose gap says they should leave it
(``p = 0, g < 0`` or ``p = H, g > 0``) are released by a gradient step and reset the conjugacy; the
load is then restored by scaling the free elements. A pressure at the cap is then by
construction the plastic set, with its overlap as plastic displacement.

Three modifications make it fast and robust:

- preconditioning (``precondition=True``, in the spirit of Vollebregt, J. Optim. Theory Appl.
  161, 2014): the gap on the free and violating elements is multiplied in Fourier space by
  ``E_star |q| / 2``, the inverse of the continuous Green's function, before it enters the CG
  recurrence and the release step (2-6x fewer iterations on rough surfaces for one more FFT
  pair per iteration);
- the CG direction is centred on the free set (zero sum), so a CG step keeps the load and the
  step length ``tau = g.t / t.Ct`` follows from the spectrum of ``t`` alone (Parseval,
  :meth:`InfluenceOperator.energy`); the pressure spectrum then follows the step as
  ``p_hat <- p_hat - tau t_hat`` and one inverse FFT gives ``u = C p``: one forward and one
  inverse FFT per iteration, plus a forward FFT of ``p`` on iterations where the projection,
  a release or the load scaling changed the pressure (refreshed every ``refresh`` iterations
  and before convergence is accepted). The element-wise passes are fused in numba
  (``_kernels.py``).
- when the residual has not halved for 50 iterations (the projected CG can cycle on very stiff,
  almost fully plastic problems), accelerated projected-gradient steps (FISTA with the exact
  projection onto ``{0 <= p <= H, mean(p) = p_mean}``, convergent for this convex problem) are
  taken before the CG restarts; their number doubles on each stall.

Residual: the RMS over all elements of the violation of the complementarity conditions by the
gap (``g`` on free elements, ``min(g, 0)`` at ``p = 0``, ``max(g, 0)`` at ``p = H``), divided by
the RMS roughness ``std(h)`` (by ``p_mean dx / E_star`` for a flat input): dimensionless.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..common.checks import tolerance
from ..common.heap import keep_heap
from ..common.jobs import fft_threads
from ._box_cg import (
    _pk_box_cg,
    _residual_scale,
    _shift,
    project_box_sum,
    volume_conserving_lift,
)
from .influence import BOUNDARIES, InfluenceOperator, MirrorOperator, boundary_of, normal_operator

__all__ = [
    "BOUNDARIES",
    "NormalResult",
    "composite_heights",
    "composite_modulus",
    "estimate_memory",
    "project_box_sum",
    "solve_normal",
    "solve_normal_pair",
]


@dataclass
class NormalResult:
    """Result of :func:`solve_normal`.

    Attributes
    ----------
    pressure : numpy.ndarray
        Contact pressure ``p`` per element in Pa (``0 <= p <= H``).
    alpha : float
        Contact ratio ``alpha_rc = A_real / A0``: fraction of elements with ``p > 0``.
    u0 : float
        Global approach in m (Eq. 7), measured from first touch (``h_max``). In periodic and
        mirror mode the elastic displacement has zero mean over the patch (its gauge).
    elastic_displacement : numpy.ndarray
        ``u_el = C p`` in m.
    plastic_displacement : numpy.ndarray
        ``u_pl >= 0`` in m, non-zero on the plastic set only (elements at ``p = H``).
    gap : numpy.ndarray
        Gap of Eq. 9 in m (zero on contact elements to the tolerance).
    deformed_heights : numpy.ndarray
        Composite heights after unloading: ``h - u_pl`` plus, with volume conservation, the
        removed volume spread evenly over the elements out of contact.
    deformed_workpiece : numpy.ndarray or None
        The workpiece heights after unloading when two surfaces were given.
    plastic_fraction : float
        Fraction of elements at the cap.
    removed_volume : float
        Plastically displaced volume in m^3 (``sum(u_pl) * dx * dy``).
    nit : int
        CG iterations on the solution's grid (with ``nested``, the fine grid only).
    converged : bool
        Whether the residual dropped below ``tol``.
    residual : float
        Dimensionless complementarity error (module docstring).
    message : str
        Human-readable outcome.
    coarse_nit : tuple of int
        With ``nested``: the CG iterations spent on each coarser grid, finest first (each
        coarse iteration costs about a quarter of one on the next finer grid); ``()`` otherwise.
    periodic : bool
        The patch's opposite edges are joined (``boundary == "periodic"``).
    boundary : str
        The boundary treatment of the solve: ``"periodic"``, ``"mirror"`` or ``"isolated"``.
    """

    pressure: np.ndarray
    alpha: float
    u0: float
    elastic_displacement: np.ndarray
    plastic_displacement: np.ndarray
    gap: np.ndarray
    deformed_heights: np.ndarray
    plastic_fraction: float
    removed_volume: float
    nit: int
    converged: bool
    residual: float
    message: str
    p_mean: float
    H: float | None
    periodic: bool
    deformed_workpiece: np.ndarray | None = None
    coarse_nit: tuple = ()
    boundary: str = "periodic"


def composite_modulus(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """Composite elastic modulus ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``. This is Eq. 2.

    Parameters
    ----------
    E1, E2 : float
        Young's moduli in Pa (> 0; ``numpy.inf`` for a rigid body).
    nu1, nu2 : float
        Poisson's ratios in ``(-1, 0.5]``.

    Returns
    -------
    float
        ``E_star`` in Pa.
    """
    for name, E in (("E1", E1), ("E2", E2)):
        if not (E > 0):
            raise ValueError(f"{name} must be > 0 (inf for a rigid body), got {E!r}")
    for name, nu in (("nu1", nu1), ("nu2", nu2)):
        if not (-1.0 < nu <= 0.5):
            raise ValueError(f"{name} must be in (-1, 0.5], got {nu!r}")
    inv = (1.0 - nu1**2) / E1 + (1.0 - nu2**2) / E2
    if inv <= 0:
        raise ValueError("E1 and E2 cannot both be infinite (rigid on rigid)")
    return 1.0 / inv


def composite_heights(workpiece: np.ndarray, tool: np.ndarray) -> np.ndarray:
    """Composite topography of two facing surfaces, workpiece first. It is the paper's Fig. 2.

    Both height maps are measured outward from their own body (asperities point towards the
    other body) on the same grid, so that the separation at element ``k`` is
    ``const - tool_k - workpiece_k``: the composite heights are their sum.
    """
    workpiece = np.asarray(workpiece, dtype=float)
    tool = np.asarray(tool, dtype=float)
    if tool.shape != workpiece.shape or tool.ndim != 2:
        raise ValueError(
            f"workpiece and tool must be 2-D arrays of the same shape, got {workpiece.shape} "
            f"and {tool.shape}"
        )
    return tool + workpiece


def _validate(heights, dx, dy, E_star, p_mean, H, tol, maxiter, p_init, max_memory, boundary):
    shape = np.shape(heights)  # before any conversion: a huge grid is refused without a copy
    if len(shape) != 2 or min(shape) < 2:
        raise ValueError(f"heights must be a 2-D array with at least 2 x 2 elements, got {shape}")
    need = estimate_memory(shape, boundary)
    if need > max_memory:
        raise ValueError(
            f"grid {shape} needs about {need / 2**30:.2f} GiB (boundary {boundary}), more than "
            f"max_memory={max_memory / 2**30:.2f} GiB; coarsen the grid or raise max_memory"
        )
    h = np.asarray(heights, dtype=float)
    if not np.all(np.isfinite(h)):
        raise ValueError("heights must be finite (no NaN or inf)")
    for name, v in (("dx", dx), ("E_star", E_star), ("p_mean", p_mean)):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
    if dy is not None and not (np.isfinite(dy) and dy > 0):
        raise ValueError(f"dy must be a finite number > 0, got {dy!r}")
    if H is not None:
        if not (np.isfinite(H) and H > 0):
            raise ValueError(f"H must be a finite number > 0 or None, got {H!r}")
        if not p_mean < H:
            raise ValueError(
                f"p_mean must be < H (even full contact at the hardness cannot carry more), "
                f"got p_mean={p_mean!r} Pa, H={H!r} Pa"
            )
    tolerance(tol)
    if int(maxiter) < 1:
        raise ValueError(f"maxiter must be >= 1, got {maxiter!r}")
    if p_init is not None:
        p_init = np.asarray(p_init, dtype=float)
        if p_init.shape != h.shape:
            raise ValueError(f"p_init must have the shape of heights {h.shape}, got {p_init.shape}")
        if not np.all(np.isfinite(p_init)):
            raise ValueError("p_init must be finite")
    return h, p_init


def estimate_memory(shape, periodic: bool | str) -> int:
    """Rough peak memory of :func:`solve_normal` in bytes (about 14 real fields + FFT buffers).

    ``periodic``: ``True`` or the boundary ``"periodic"`` or ``"mirror"`` (transforms of the
    grid's size), ``False`` or ``"isolated"`` (zero-padded to twice the grid per axis).
    """
    nx, ny = shape
    padded = periodic is False or periodic == "isolated"
    fx, fy = (2 * nx, 2 * ny) if padded else (nx, ny)
    return int(8 * (14 * nx * ny + fx * fy) + 16 * 3 * fx * (fy // 2 + 1))


def solve_normal(
    heights,
    dx: float,
    E_star: float,
    p_mean: float,
    *,
    H: float | None = None,
    periodic: bool | None = None,
    tol: float = 1e-8,
    dy: float | None = None,
    maxiter: int = 5000,
    p_init=None,
    volume_conservation: bool = True,
    kernel: str = "spectral",
    operator: InfluenceOperator | MirrorOperator | None = None,
    refresh: int = 32,
    precondition: bool = True,
    single: bool = False,
    max_memory: float = 8 * 2**30,
    workers: int | None = None,
    nested: bool = False,
    boundary: str | None = None,
) -> NormalResult:
    """Solve the normal contact of a rough surface at a prescribed mean pressure.

    The model is the paper's Sec. 2.1.

    Parameters
    ----------
    heights : array_like, shape (Nx, Ny)
        Composite topography in m, higher touches first (Fig. 2; see :func:`composite_heights`).
    dx : float
        Element size ``2a`` in m (along axis 0); ``dy`` (``2b``, axis 1) defaults to ``dx``.
    E_star : float
        Composite modulus (Eq. 2) in Pa; see :func:`composite_modulus`.
    p_mean : float
        Mean pressure over the apparent area in Pa, ``> 0`` and ``< H``.
    H : float, optional
        Hardness cap of Eq. 8 in Pa; ``None`` for a purely elastic contact.
    periodic : bool, optional
        The older switch of ``boundary``: True is ``"periodic"`` (the default), False
        ``"isolated"``.
    tol : float
        Tolerance on the dimensionless residual (module docstring).
    maxiter : int
        Maximum CG iterations; on reaching it ``converged`` is False and ``message`` says so.
    p_init : array_like, optional
        Warm start (e.g. the pressure of a previous, nearby load); clipped to ``[0, H]`` and
        rescaled to ``p_mean``. Default: uniform ``p_mean``.
    volume_conservation : bool
        Spread the plastically removed volume evenly over the out-of-contact elements in
        ``deformed_heights`` (Pullen and Williamson; the paper's default).
    kernel : {"spectral", "love"}
        Periodic influence kernel, see :func:`halfspace_calib.contact.influence.normal_operator`.
    operator : InfluenceOperator, optional
        A prebuilt operator (reuse across loads of a sweep); must match the grid and mode.
    refresh : int
        Recompute the pressure spectrum from scratch at least every ``refresh`` iterations
        (it is otherwise updated by the CG recurrence; results agree to roundoff).
    precondition : bool
        Precondition the CG by the inverse of the continuous Green's function,
        ``E_star |q| / 2`` (one extra FFT pair per iteration, several times fewer iterations);
        False gives the plain Polonsky-Keer iteration. Needs ``operator.inverse_spectrum``
        (set by :func:`~halfspace_calib.contact.influence.normal_operator`); ignored without it.
    single : bool
        Run the FFTs in single precision (measured speed-accuracy trade, see the docs; use with
        ``tol >= 1e-6``, enforced: roundoff limits the residual to about 1e-7). Element-wise work stays
        in double precision.
    max_memory : float
        Refuse (``ValueError``) grids whose estimated memory exceeds this many bytes.
    workers : int, optional
        Threads for ``scipy.fft`` (default: :func:`~halfspace_calib.common.jobs.fft_threads`).
    nested : bool
        Nested iteration (multilevel initial guess, Polonsky and Keer 1999): while both sides
        of the grid are even and the halved grid keeps at least ``NESTED_MIN`` elements a side,
        solve first on the grid coarsened by 2 x 2 block averages of the heights (elements of
        ``2 dx x 2 dy``; ``p_init``, if given, block-averaged too), recursively, and start the
        fine iteration from the prolongated pressure (each coarse value on its 2 x 2 fine
        elements: the contact and plastic sets come with it; with ``p_init``, the warm start
        plus the prolongated coarse correction). The fine solve still has to
        reach ``tol`` on the fine grid; ``nit`` counts its iterations, ``coarse_nit`` the
        coarse ones.
    boundary : {"periodic", "mirror", "isolated"}, optional
        ``"periodic"`` (default): the grid is one period of a periodic surface (roughness;
        exact spectral Green's function). ``"mirror"``: the grid is a patch of a larger surface
        that is solved as one quarter of the period of its mirror-symmetric extension
        (:class:`~halfspace_calib.contact.influence.MirrorOperator`): no seam between opposite
        edges and no edge of a finite body, at the cost of the periodic solve. ``"isolated"``:
        an isolated finite body (zero-padded DC-FFT, e.g. Hertz, a punch).

    Returns
    -------
    NormalResult
    """
    boundary = boundary_of(periodic, boundary)
    h, p_init = _validate(
        heights, dx, dy, E_star, p_mean, H, tol, maxiter, p_init, max_memory, boundary
    )
    keep_heap()  # grid-sized temporaries reused, not page-faulted in anew (common/heap.py)
    if single and tol < 1e-6:
        raise ValueError(f"tol must be >= 1e-6 with single=True (roundoff floor), got {tol!r}")
    dy_ = dx if dy is None else dy
    coarse_nit = ()
    nx, ny = h.shape
    if nested and nx % 2 == 0 and ny % 2 == 0 and min(nx, ny) // 2 >= NESTED_MIN:
        coarse = solve_normal(
            _restrict(h),
            2.0 * dx,
            E_star,
            p_mean,
            H=H,
            boundary=boundary,
            tol=max(tol, NESTED_TOL),
            dy=2.0 * dy_,
            maxiter=maxiter,
            p_init=None if p_init is None else _restrict(p_init),
            volume_conservation=False,
            kernel=kernel,
            refresh=refresh,
            precondition=precondition,
            single=single and max(tol, NESTED_TOL) >= 1e-6,
            max_memory=max_memory,
            workers=workers,
            nested=True,
        )
        if p_init is None:
            p_init = _prolong(coarse.pressure)
        else:
            # coarse-grid correction of the warm start: keep its fine detail, move it as the
            # coarse solution moved from the warm start's block averages
            p_init = p_init + _prolong(coarse.pressure - _restrict(p_init))
        coarse_nit = (coarse.nit, *coarse.coarse_nit)
    if operator is None:
        threads = fft_threads() if workers is None else int(workers)
        operator = _cached_operator(
            h.shape, float(dx), float(E_star), float(dy_), boundary, kernel, threads
        )
    elif operator.shape != h.shape or getattr(operator, "boundary", None) != boundary:
        raise ValueError(
            f"operator must have shape {h.shape} and boundary {boundary!r}, got "
            f"{operator.shape} and {getattr(operator, 'boundary', None)!r}"
        )
    p, u, g, nit, converged, res = _pk_box_cg(
        operator.single() if single else operator,
        h,
        float(p_mean),
        H,
        p_init,
        tol,
        int(maxiter),
        refresh,
        scale=_residual_scale(h, p_mean, dx, E_star),
        precondition=bool(precondition) and operator.inverse_spectrum is not None,
    )
    out = _finish(
        h, p, u, g, nit, converged, res, tol, p_mean, H, boundary, volume_conservation, dx * dy_
    )
    out.coarse_nit = coarse_nit
    return out


#: nested iteration stops coarsening below this many elements a side
NESTED_MIN = 64
#: tolerance of the coarse solves of the nested iteration (the fine solve has its own ``tol``)
NESTED_TOL = 1e-6


def _restrict(a):
    """2 x 2 block averages of a field with even sides (the coarse grid of the nested iteration)."""
    nx, ny = a.shape
    return a.reshape(nx // 2, 2, ny // 2, 2).mean(axis=(1, 3))


def _prolong(a):
    """Each coarse value on its 2 x 2 fine elements (piecewise constant prolongation)."""
    return np.repeat(np.repeat(a, 2, axis=0), 2, axis=1)


@lru_cache(maxsize=4)
def _cached_operator(shape, dx, E_star, dy, boundary, kernel, workers):
    """The normal operator of a grid, built once per process for the solves of a sweep.

    A sweep solves the same grid dozens of times (first loading, reloads, the coarse grids of
    the nested iteration); building the spectrum (and, non-periodic, Love's coefficients on the
    padded grid) costs several FFT pairs each time. Four entries: a grid and its coarse levels.
    """
    return normal_operator(
        shape, dx, E_star, dy=dy, boundary=boundary, kernel=kernel, workers=workers
    )


def _finish(h, p, u, g, nit, converged, res, tol, p_mean, H, boundary, vc, dA):
    g_raw = u - h
    shift = _shift(g_raw, p, H)
    gap = g_raw + shift
    u0 = float(h.max() - shift)
    if H is not None:
        u_pl = np.where(p >= H, np.maximum(-gap, 0.0), 0.0)
    else:
        u_pl = np.zeros_like(p)
    gap_total = gap + u_pl
    contact = p > 0
    deformed = h - u_pl
    removed = float(u_pl.sum())
    note = ""
    if vc and removed > 0:
        lift, rest = volume_conserving_lift(np.where(contact, 0.0, np.maximum(gap, 0.0)), removed)
        deformed += lift
        if rest > 0:
            deformed += rest / deformed.size
            note = (
                f" (the valleys hold only {100 * (1 - rest / removed):.1f} % of the removed "
                "volume: the rest raises the whole surface evenly)"
            )
    load_error = abs(float(p.mean()) - p_mean) / p_mean
    if converged and not load_error <= tol:
        converged = False
        note += (
            f"; the load is not carried: mean(p) = {float(p.mean()):.6g} Pa for p_mean = "
            f"{p_mean:.6g} Pa (relative error {load_error:.1e} > tol {tol:.1e})"
        )
    if converged:
        msg = f"converged in {nit} iterations, residual {res:.2e} < tol {tol:.1e}{note}"
    else:
        msg = f"NOT converged: residual {res:.2e} >= tol {tol:.1e} after {nit} iterations{note}"
    return NormalResult(
        pressure=p,
        alpha=float(np.count_nonzero(contact) / p.size),
        u0=u0,
        elastic_displacement=u,
        plastic_displacement=u_pl,
        gap=gap_total,
        deformed_heights=deformed,
        plastic_fraction=float(np.count_nonzero(p >= H) / p.size) if H is not None else 0.0,
        removed_volume=removed * dA,
        nit=nit,
        converged=converged,
        residual=res,
        message=msg,
        p_mean=float(p_mean),
        H=None if H is None else float(H),
        periodic=boundary == "periodic",
        boundary=boundary,
    )


def solve_normal_pair(
    workpiece, tool, dx: float, E_star: float, p_mean: float, **kwargs
) -> NormalResult:
    """Normal contact of a workpiece and a tool surface (two height maps in, workpiece first).

    The composite gap is formed by :func:`composite_heights`; the plastic displacement and the
    volume conservation belong to the workpiece (the softer body), and the result carries
    ``deformed_workpiece``: the workpiece heights after unloading, ready for a later contact
    (reloading, a further stage, sliding). All keyword arguments go to :func:`solve_normal`.
    """
    hc = composite_heights(workpiece, tool)
    res = solve_normal(hc, dx, E_star, p_mean, **kwargs)
    res.deformed_workpiece = np.asarray(workpiece, dtype=float) + (res.deformed_heights - hc)
    return res
