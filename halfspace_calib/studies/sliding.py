"""Sliding of an elastic tool window over a longer elasto-plastic workpiece (Sec. 3.3).

The tool window (``Nt x Ny`` elements, the stamp of Sec. 3.1) is moved in ``+x`` over a longer
workpiece (``Nw x Ny``, ``Nw > Nt``) by one element ``2a`` per position. At position ``i`` the
window covers the workpiece rows ``i .. i + Nt - 1``; the normal contact at ``p_mean`` is solved
there (Sec. 2.1, :func:`halfspace_calib.contact.normal.solve_normal_pair`) and the window's plastic
deformation (and, with volume conservation, the material lifted into its valleys) is written back
into the long workpiece before the next position. The leading row ``i + Nt - 1`` is the only row
that no earlier position has loaded.

Per position (the paper's Figs. 11-15):

- ``u0`` (Fig. 11) and ``alpha = A_real / A0`` (Fig. 12);
- deformation work ``W_def = H * dV`` with ``dV`` the volume plastically displaced at that
  position (:func:`deformation_work`; "the cross-section of the grooved track multiplied by H",
  times the step ``2a``);
- adhesive work ``W_adh = tau_adh * A0 * 2a`` with ``tau_adh = m (sigma_y / 2) alpha_rc``
  (:func:`adhesive_work`, Eq. 24's Tresca-in-the-real-area shear at full sliding: every contact
  element is at the cap, so no tangential solve is needed);
- the ratio ``W_def / W_adh`` (Fig. 15; the paper finds it below 0.008).

Position 0 is the first indentation of a fresh surface: its ``W_def`` is the plastic work of the
whole window, not of sliding. The summaries (:attr:`SlidingResult.steady`) use positions ``>= 1``.

Boundary conditions of the window
---------------------------------
The solver offers two influence operators: periodic in both axes (spectral) or non-periodic in
both (DC-FFT, an isolated body). The default is ``periodic=True``:

- in ``y`` the 2.11 mm strip is periodic (the synthetic sheet is, and a measured strip stands
  for a wider sheet);
- in ``x`` the window stands for the neighbourhood of one contact node inside a much larger tool
  contact: the sheet ahead of and behind the window carries ``p_mean`` on average, which the
  periodic Green's function supplies (the loaded neighbours of the leading row are the window's
  trailing rows at the same mean pressure). A non-periodic window is instead an isolated
  2.11 mm x 2.11 mm stamp: its edges carry the pressure peaks of a finite flat punch, which at
  every position plough the sheet under the moving leading edge, a work that belongs to the
  stamp's size and not to the roughness;
- it is the calibration's default (``Scene.periodic``), so ``alpha_rc`` is the quantity of
  Eq. 24, and it is 3-4 times faster (no zero padding).

The price: the fresh leading row is an elastic neighbour of the flattened trailing row (no
geometric overlap; only the elastic interaction wraps around). ``periodic=False`` is offered and
the two are compared in ``benchmarks/bench_sliding.py`` (``docs/sliding.md``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .. import topography as _surf
from ..common.checks import positive, tolerance, tresca_factor
from ..contact.influence import normal_operator
from ..contact.materials import records, sigma_y_from_hardness
from ..contact.normal import solve_normal_pair
from ..contact.tangential import tau_adh_full_sliding

__all__ = [
    "SLIDING_PRESSURES",
    "SLIDING_ROUGHNESS",
    "SLIDING_SHAPE",
    "SLIDING_SIZE",
    "SlidingResult",
    "adhesive_work",
    "deformation_work",
    "sliding_surfaces",
    "sliding_sweep",
    "sliding_workpiece",
]

#: p_mean of the sliding study (Sec. 3.3): 100-600 MPa in steps of 100 MPa
SLIDING_PRESSURES = (100e6, 200e6, 300e6, 400e6, 500e6, 600e6)
#: workpiece grid and size of Sec. 3.3 (Nx x Ny elements, Lx x Ly in m)
SLIDING_SHAPE = (384, 128)
SLIDING_SIZE = (6.33e-3, 2.11e-3)
#: roughness of the longer DC04 surface of Sec. 3.3 (m)
SLIDING_ROUGHNESS = {"Ra": 0.989e-6, "Rq": 1.201e-6}


# ----------------------------------------------------------------------------- equations
def deformation_work(H, displaced_volume):
    """Deformation work of one sliding position, Sec. 3.3: ``W_def = H * dV``.

    Parameters
    ----------
    H : float or array_like
        Hardness in Pa.
    displaced_volume : float or array_like
        Volume plastically displaced at that position in m^3 (the cross-section of the grooved
        track times the step ``2a``).

    Returns
    -------
    float or numpy.ndarray
        ``W_def`` in J.
    """
    return np.multiply(H, displaced_volume)


def adhesive_work(m, sigma_y, alpha, A0, step):
    """Adhesive work of one sliding position, Sec. 3.3: ``W_adh = tau_adh * A0 * 2a``.

    ``tau_adh`` is :func:`~halfspace_calib.contact.tangential.tau_adh_full_sliding`, the Tresca shear in
    the real contact area (Eq. 18 at the cap on every contact element, i.e. full sliding).

    Parameters
    ----------
    m : float
        Tresca friction factor in ``(0, 1]``.
    sigma_y : float
        Yield stress of the softer body in Pa.
    alpha : float or array_like
        Contact ratio ``alpha_rc = A_real / A0``.
    A0 : float
        Apparent area of the tool window in m^2.
    step : float
        Sliding step ``2a`` in m.

    Returns
    -------
    float or numpy.ndarray
        ``W_adh`` in J.
    """
    return tau_adh_full_sliding(alpha, m, sigma_y) * A0 * step


# ----------------------------------------------------------------------------- surfaces
def sliding_workpiece(
    shape=SLIDING_SHAPE,
    size=SLIDING_SIZE,
    *,
    seed=1,
    ra=SLIDING_ROUGHNESS["Ra"],
    rq=SLIDING_ROUGHNESS["Rq"],
):
    """Synthetic stand-in for the longer DC04 EDT sheet of Sec. 3.3 (Ra 0.989 um, Rq 1.201 um).

    The spectrum of :func:`halfspace_calib.topography.dc04_edt_like` (self-affine, Hurst 0.8,
    100 um roll-off) on the ``6.33 mm x 2.11 mm`` strip, with Ra and Rq both matched
    (:func:`halfspace_calib.topography.self_affine`). On grids too coarse for the roll-off
    (Nyquist wavelength ``>= 100 um``) the roll-off moves just above the Nyquist wavelength:
    band-limited white noise, as the presets do.
    """
    nx, ny = shape
    nyquist = 2 * max(size[0] / nx, size[1] / ny)
    rolloff = max(100e-6, 1.001 * nyquist)
    return _surf.self_affine(
        shape, size, hurst=0.8, rolloff_wavelength=rolloff, ra=ra, rq=rq, seed=seed
    )


def sliding_surfaces(
    shape=SLIDING_SHAPE,
    size=SLIDING_SIZE,
    *,
    tool_n=None,
    rough_tool=False,
    seed_workpiece=1,
    seed_tool=2,
):
    """Default workpiece strip and tool window of Sec. 3.3: ``(workpiece, tool)`` Surfaces.

    The tool is :func:`halfspace_calib.topography.tool_like` on a square of the strip's width
    (``tool_n`` elements a side, default the strip's ``Ny``), with the strip's element size.
    """
    wp = sliding_workpiece(shape, size, seed=seed_workpiece)
    n = shape[1] if tool_n is None else int(tool_n)
    tl = _surf.tool_like(n, rough=rough_tool, size=n * wp.dy, seed=seed_tool)
    return wp, tl


# ----------------------------------------------------------------------------- result
@dataclass
class SlidingResult:
    """Per-position results of :func:`sliding_sweep` (SI units).

    Attributes
    ----------
    position : numpy.ndarray of int
        Position index ``i`` (the window covers workpiece rows ``i .. i + Nt - 1``).
    x : numpy.ndarray
        Sliding distance ``i * 2a`` in m.
    u0, alpha : numpy.ndarray
        Global approach (m, Fig. 11) and contact ratio ``A_real / A0`` (Fig. 12). ``u0`` is
        measured from first touch (Eq. 7), so it jumps when a higher peak enters the window.
    separation : numpy.ndarray
        ``h_max - u0`` (m): height of the rigid tool datum in the frame of the composite heights
        (0 = mean plane of the initial surfaces); smooth along the path, unlike ``u0``.
    displaced_volume : numpy.ndarray
        Volume plastically displaced at each position (m^3).
    W_def, W_adh, ratio : numpy.ndarray
        Deformation work, adhesive work (J, Figs. 13-14) and ``W_def / W_adh`` (Fig. 15).
    plastic_fraction, nit, residual : numpy.ndarray
        Solver diagnostics per position.
    converged : numpy.ndarray of bool
        Per-position convergence flags.
    messages : list of str
        Solver message per position.
    workpiece_initial, workpiece_final : numpy.ndarray
        The long workpiece before and after the sweep (m).
    plastic_displacement : numpy.ndarray
        Plastic displacement accumulated on the long workpiece (m), the sum over positions.
    """

    p_mean: float
    H: float
    m: float
    sigma_y: float
    dx: float
    dy: float
    tool_shape: tuple
    periodic: bool
    volume_conservation: bool
    tol: float
    position: np.ndarray
    x: np.ndarray
    u0: np.ndarray
    separation: np.ndarray
    alpha: np.ndarray
    displaced_volume: np.ndarray
    W_def: np.ndarray
    W_adh: np.ndarray
    ratio: np.ndarray
    plastic_fraction: np.ndarray
    nit: np.ndarray
    residual: np.ndarray
    converged: np.ndarray
    messages: list = field(default_factory=list)
    workpiece_initial: np.ndarray | None = None
    workpiece_final: np.ndarray | None = None
    plastic_displacement: np.ndarray | None = None
    seconds: float = 0.0

    @property
    def all_converged(self):
        """True if every position converged."""
        return bool(np.all(self.converged))

    @property
    def failed_positions(self):
        """Indices of the positions whose solve did not converge."""
        return [int(i) for i in self.position[~self.converged]]

    @property
    def message(self):
        """One line: how many positions converged, and which failed."""
        n = self.position.size
        bad = self.failed_positions
        if not bad:
            return f"all {n} positions converged (tol {self.tol:.1e})"
        shown = ", ".join(str(i) for i in bad[:10]) + (" ..." if len(bad) > 10 else "")
        return (
            f"{len(bad)} of {n} positions NOT converged (tol {self.tol:.1e}): {shown}; "
            f"first: {self.messages[bad[0]]}"
        )

    @property
    def steady(self):
        """Summary over the sliding positions ``>= 1`` (position 0 is the first indentation)."""
        sl = slice(1, None) if self.position.size > 1 else slice(None)
        r = self.ratio[sl]
        return {
            "p_mean": self.p_mean,
            "positions": int(self.position.size),
            "ratio_mean": float(np.mean(r)),
            "ratio_max": float(np.max(r)),
            "W_def_mean": float(np.mean(self.W_def[sl])),
            "W_adh_mean": float(np.mean(self.W_adh[sl])),
            "alpha_mean": float(np.mean(self.alpha[sl])),
            "first_ratio": float(self.ratio[0]),
            "converged": self.all_converged,
            "seconds": float(self.seconds),
        }

    @property
    def total_displaced_volume(self):
        """Sum of the per-position displaced volumes (m^3)."""
        return float(self.displaced_volume.sum())


# ----------------------------------------------------------------------------- sweep
def _as_array(name, s):
    h = s.heights if isinstance(s, _surf.Surface) else s
    h = np.array(h, dtype=float, copy=True)
    if h.ndim != 2 or min(h.shape) < 2:
        raise ValueError(
            f"{name} must be a 2-D height map with at least 2 x 2 elements, got shape {h.shape}"
        )
    if not np.all(np.isfinite(h)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    return h


def _check_sweep(
    workpiece, tool, dx, E_star, p_mean, H, m, sigma_y, positions, tol, dy, warm_start="tool"
):
    wp = _as_array("workpiece", workpiece)
    tl = _as_array("tool", tool)
    if wp.shape[1] != tl.shape[1]:
        raise ValueError(
            f"workpiece and tool must have the same width Ny (axis 1), got "
            f"workpiece {wp.shape} and tool {tl.shape}"
        )
    if wp.shape[0] < tl.shape[0]:
        raise ValueError(
            f"workpiece must be at least as long as the tool (axis 0), got "
            f"workpiece {wp.shape} and tool {tl.shape}"
        )
    dx = positive("dx", dx)
    dy = dx if dy is None else positive("dy", dy)
    E_star = positive("E_star", E_star)
    p_mean = positive("p_mean", p_mean)
    H = positive("H", H)
    if not p_mean < H:
        raise ValueError(f"p_mean must be in (0, H) = (0, {H:g}) Pa, got {p_mean!r}")
    m = tresca_factor(m, allow_zero=False, why=" (W_adh = 0 at m = 0)")
    sigma_y = sigma_y_from_hardness(H) if sigma_y is None else positive("sigma_y", sigma_y)
    if warm_start not in WARM_STARTS:
        raise ValueError(f"warm_start must be one of {WARM_STARTS}, got {warm_start!r}")
    tolerance(tol)
    n_max = wp.shape[0] - tl.shape[0] + 1
    if positions is None:
        positions = n_max
    if (
        isinstance(positions, bool)
        or not isinstance(positions, (int, np.integer))
        or not (1 <= positions <= n_max)
    ):
        raise ValueError(
            f"positions must be an integer in [1, {n_max}] (workpiece rows - tool "
            f"rows + 1), got {positions!r}"
        )
    return wp, tl, dx, dy, E_star, p_mean, H, float(m), sigma_y, int(positions)


WARM_STARTS = ("tool", "workpiece", "none")


def _warm_start(p, p_mean, mode):
    """Initial pressure of the next position from the previous one (``None``: uniform).

    ``"tool"``: the previous field as it is, i.e. fixed in the tool (window) frame: once the
    plateau has conformed to the tool, the pressure pattern follows the tool's asperities.
    ``"workpiece"``: shifted by one element with the workpiece (which moves one row back under
    the tool); the fresh leading row starts at ``p_mean``. ``benchmarks/bench_sliding.py``
    compares them (iterations per position).
    """
    if p is None or mode == "none":
        return None
    if mode == "tool":
        return p
    out = np.empty_like(p)
    out[:-1] = p[1:]
    out[-1] = p_mean
    return out


def sliding_sweep(
    workpiece,
    tool,
    dx,
    p_mean,
    *,
    materials=None,
    solver=None,
    positions=None,
    warm_start="tool",
    dy=None,
    progress=False,
):
    """Slide the tool window over the workpiece, one element per position.

    This is the paper's Sec. 3.3.

    Parameters
    ----------
    workpiece : array_like or Surface, shape (Nw, Ny)
        Heights of the long elasto-plastic workpiece in m (asperities up, Fig. 2); axis 0 is the
        sliding direction ``x``.
    tool : array_like or Surface, shape (Nt, Ny)
        Heights of the elastic tool window in m, ``Nt <= Nw``.
    dx : float
        Element size ``2a`` in m (the step per position); ``dy`` (``2b``) defaults to ``dx``.
    p_mean : float
        Mean pressure over the window in Pa, in ``(0, H)``.
    materials : Materials, optional
        ``E_star`` (Eq. 2) of the two bodies, the workpiece's hardness ``H`` (Eq. 8) and yield
        stress ``sigma_y``, the Tresca factor ``m`` (here in ``(0, 1]``); default Table 1
        (:class:`~halfspace_calib.contact.materials.Materials`).
    solver : SolverSettings, optional
        ``tol``; ``volume_conservation`` (spread each position's displaced volume over the
        window's out-of-contact elements); ``periodic``: the window operator, periodic (default,
        a patch of a larger contact) or non-periodic (an isolated stamp), see the module
        docstring; ``maxiter`` per position (``None``: 5000).
    positions : int, optional
        Number of positions, ``1 .. Nw - Nt + 1`` (default: all, 257 for 384 over 128).
    warm_start : {"tool", "workpiece", "none"}
        Initial pressure of each position after the first: the previous field in the tool frame
        (default; fewest iterations, measured), shifted one element with the workpiece, or
        uniform (cold). The converged answer does not depend on it (the problem is convex).
    progress : bool
        Show a progress bar.

    Returns
    -------
    SlidingResult
        A position that does not converge is kept (its best iterate is written back and the sweep
        goes on) and reported in ``converged`` / ``message``.
    """
    mat, sol = records(materials, solver)
    tol, periodic, volume_conservation = sol.tol, sol.periodic, sol.volume_conservation
    maxiter = 5000 if sol.maxiter is None else sol.maxiter
    wp, tl, dx, dy, E_star, p_mean, H, m, sigma_y, n_pos = _check_sweep(
        workpiece,
        tool,
        dx,
        mat.E_star,
        p_mean,
        mat.H,
        mat.m,
        mat.sigma_y,
        positions,
        tol,
        dy,
        warm_start,
    )
    t0 = time.perf_counter()
    nt = tl.shape[0]
    op = normal_operator(tl.shape, dx, E_star, dy=dy, periodic=periodic)
    A0 = tl.size * dx * dy
    initial = wp.copy()
    upl = np.zeros_like(wp)
    rec = {k: np.empty(n_pos) for k in ("u0", "sep", "alpha", "dV", "pf", "res")}
    nit = np.empty(n_pos, dtype=int)
    conv = np.empty(n_pos, dtype=bool)
    msgs = []
    p_prev = None
    bar = _bar(n_pos, progress, f"sliding {p_mean / 1e6:g} MPa")
    for i in range(n_pos):
        win = wp[i : i + nt]
        rec["sep"][i] = float((tl + win).max())  # h_max of the composite heights
        p_init = _warm_start(p_prev, p_mean, warm_start)
        r = solve_normal_pair(
            win,
            tl,
            dx,
            E_star,
            p_mean,
            H=H,
            periodic=periodic,
            tol=tol,
            dy=dy,
            maxiter=maxiter,
            p_init=p_init,
            volume_conservation=volume_conservation,
            operator=op,
        )
        wp[i : i + nt] = r.deformed_workpiece
        upl[i : i + nt] += r.plastic_displacement
        rec["u0"][i], rec["alpha"][i], rec["dV"][i] = r.u0, r.alpha, r.removed_volume
        rec["pf"][i], rec["res"][i] = r.plastic_fraction, r.residual
        nit[i], conv[i] = r.nit, r.converged
        msgs.append(r.message)
        p_prev = r.pressure
        if bar is not None:
            bar.update()
    if bar is not None:
        bar.close()
    rec["sep"] -= rec["u0"]
    W_def = deformation_work(H, rec["dV"])
    W_adh = adhesive_work(m, sigma_y, rec["alpha"], A0, dx)
    pos = np.arange(n_pos)
    return SlidingResult(
        p_mean=p_mean,
        H=H,
        m=m,
        sigma_y=sigma_y,
        dx=dx,
        dy=dy,
        tool_shape=tuple(tl.shape),
        periodic=bool(periodic),
        volume_conservation=bool(volume_conservation),
        tol=float(tol),
        position=pos,
        x=pos * dx,
        u0=rec["u0"],
        separation=rec["sep"],
        alpha=rec["alpha"],
        displaced_volume=rec["dV"],
        W_def=W_def,
        W_adh=W_adh,
        ratio=W_def / W_adh,
        plastic_fraction=rec["pf"],
        nit=nit,
        residual=rec["res"],
        converged=conv,
        messages=msgs,
        workpiece_initial=initial,
        workpiece_final=wp,
        plastic_displacement=upl,
        seconds=time.perf_counter() - t0,
    )


def _bar(n, progress, desc):
    if not progress:
        return None
    from tqdm.auto import tqdm

    return tqdm(total=n, desc=desc, leave=False)
