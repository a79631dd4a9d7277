"""The study of Figs. 9-10 (Sec. 3.2): geometric shear of inclined patches against adhesion.

A workpiece and a tool are given as *measured* height maps, finer than the solver grid: each solver
element is the block average of its ``s = block^2`` measured points (Sec. 3.1, "sampled down"), and
the least-squares plane through the same points gives its inclination (Eqs. 19-21,
:func:`halfspace_calib.studies.inclined.fit_patch_planes`). At each mean pressure the elasto-plastic normal
contact of the block-averaged surfaces is solved (Sec. 2.1); then

- ``tau_adh = m (sigma_y / 2) alpha_rc``: the adhesive shear under full sliding, every contact
  element at the Eq. 18 cap (no tangential solve, :func:`halfspace_calib.contact.tangential.tau_adh_full_sliding`);
- ``tau_geo``: Eq. 23 over the entering flanks, with the paper's normal rule (elastic element:
  mean of both normals; plastic element, ``p = H``: the tool's normal),
  :func:`halfspace_calib.studies.inclined.tau_geo_from_surfaces`;
- their ratio (Fig. 10).

Eq. 26 reads ``tau = m [k alpha + f(p_mean, Ra)]`` with ``k = sigma_y / 2``. Adding the geometric
shear to the adhesive one, ``m k alpha + tau_geo``, gives ``f = tau_geo / m``; the runtime
(:class:`frictionlaw.FrictionParams`) evaluates ``f = geo_ratio k alpha(p)``, so
:func:`fit_geo_ratio` fits ``geo_ratio`` by least squares to ``tau_geo(p) = geo_ratio tau_adh(p)``.

Synthetic "measurements" (:func:`~halfspace_calib.topography.synthesis.measured_surfaces`): the presets of
:mod:`halfspace_calib.topography` generated on the fine grid and scaled so that the block-averaged
solver surface has the Table 1 ``Ra`` (the paper's Table 1 lists the roughness "of the simulated
surfaces", i.e. after sampling down; ``roughness_on="measured"`` puts it on the fine grid instead).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .. import topography as _surf
from ..common.checks import tolerance, tresca_factor
from ..contact.materials import records
from ..contact.normal import solve_normal_pair
from ..contact.tangential import tau_adh_full_sliding
from ..topography.synthesis import measured_surfaces
from .inclined import tau_geo_from_surfaces

__all__ = [
    "GEO_PRESSURES",
    "GeometricResult",
    "GeometricStudy",
    "geometric_sweep",
    "geometric_study",
    "fit_geo_ratio",
]

#: p_mean of Figs. 9-10: 100-600 MPa in steps of 100 MPa
GEO_PRESSURES = (100e6, 200e6, 300e6, 400e6, 500e6, 600e6)


@dataclass
class GeometricResult:
    """``tau_adh``, ``tau_geo`` and their ratio per pressure for one workpiece/tool pair (SI units).

    Attributes
    ----------
    label : str
        Name of the pair (e.g. ``"smooth tool"``).
    p_mean, alpha, tau_adh, tau_geo, ratio, plastic_fraction : ndarray
        Per pressure: mean pressure (Pa), contact ratio, ``m (sigma_y/2) alpha`` (Pa), Eq. 23 (Pa),
        ``tau_geo / tau_adh``, fraction of elements at ``p = H``.
    converged : ndarray of bool
        Whether each normal solve converged.
    messages : list of str
        The normal solver's messages.
    settings : dict
        Grid, block, materials and the roughness of both solver surfaces.
    seconds : float
        Wall time of the sweep.
    """

    label: str
    p_mean: np.ndarray
    alpha: np.ndarray
    tau_adh: np.ndarray
    tau_geo: np.ndarray
    ratio: np.ndarray
    plastic_fraction: np.ndarray
    converged: np.ndarray
    messages: list = field(default_factory=list)
    settings: dict = field(default_factory=dict)
    seconds: float = 0.0

    @property
    def ratio_mean(self):
        """Mean of ``tau_geo / tau_adh`` over the converged pressures."""
        ok = self.converged
        return float(np.mean(self.ratio[ok])) if ok.any() else float("nan")

    @property
    def all_converged(self):
        """True if every normal solve converged."""
        return bool(np.all(self.converged))

    def summary(self):
        """JSON-ready summary (per-pressure rows, mean ratio, spread, least-squares ``geo_ratio``)."""
        ok = self.converged
        rows = [
            {
                "p_mean": float(self.p_mean[i]),
                "alpha": float(self.alpha[i]),
                "tau_adh": float(self.tau_adh[i]),
                "tau_geo": float(self.tau_geo[i]),
                "ratio": float(self.ratio[i]),
                "plastic_fraction": float(self.plastic_fraction[i]),
                "converged": bool(self.converged[i]),
            }
            for i in range(self.p_mean.size)
        ]
        return {
            "label": self.label,
            "rows": rows,
            "ratio_mean": self.ratio_mean,
            "ratio_min": float(np.min(self.ratio[ok])) if ok.any() else float("nan"),
            "ratio_max": float(np.max(self.ratio[ok])) if ok.any() else float("nan"),
            "geo_ratio_lsq": fit_geo_ratio(self)["geo_ratio"] if ok.any() else float("nan"),
            "all_converged": self.all_converged,
            "settings": self.settings,
            "seconds": self.seconds,
        }


@dataclass
class GeometricStudy:
    """The Figs. 9-10 study: one :class:`GeometricResult` per tool."""

    results: list
    seconds: float

    def summary(self):
        """JSON-ready summary of every pair."""
        return {"pairs": [r.summary() for r in self.results], "seconds": self.seconds}


# ----------------------------------------------------------------------------- sweep
def _heights(name, s):
    if isinstance(s, _surf.Surface):
        return np.asarray(s.heights), s.dx, s.dy
    raise ValueError(f"{name} must be a halfspace_calib.topography.Surface (the measured map)")


def _check(pressures, H, m, sigma_y, tol):
    pressures = tuple(float(p) for p in pressures)
    if not pressures:
        raise ValueError("pressures must hold at least one p_mean (Pa)")
    if not (np.isfinite(H) and H > 0):
        raise ValueError(f"H must be a finite number > 0 (Pa), got {H!r}")
    bad = [p for p in pressures if not (0 < p < H)]
    if bad:
        raise ValueError(f"pressures must be in (0, H) = (0, {H:g}) Pa, got {bad}")
    tresca_factor(m, allow_zero=False, why=" (tau_adh = 0 at m = 0: no ratio)")
    if not (np.isfinite(sigma_y) and sigma_y > 0):
        raise ValueError(f"sigma_y must be a finite number > 0 (Pa), got {sigma_y!r}")
    tolerance(tol)
    return pressures


def geometric_sweep(
    workpiece,
    tool,
    pressures=GEO_PRESSURES,
    *,
    block,
    materials=None,
    solver=None,
    direction=1,
    label="",
):
    """``tau_adh``, ``tau_geo`` (Eq. 23) and ``tau_geo / tau_adh`` over ``pressures`` (Figs. 9-10).

    Parameters
    ----------
    workpiece, tool : Surface
        Measured (fine) height maps on the same grid, shape ``(Nx block, Ny block)``; the tool's
        heights positive towards the workpiece. The solver surfaces are their block averages.
    pressures : sequence of float
        ``p_mean`` values in Pa, each in ``(0, H)``; solved in ascending order with warm starts.
    block : int or (int, int)
        Measured points per element along ``x`` and ``y``.
    materials : Materials, optional
        Both bodies (``E_star`` of Eq. 2), ``H``, ``sigma_y`` and the Tresca factor ``m``, here in
        ``(0, 1]``; default Table 1 (:class:`~halfspace_calib.contact.materials.Materials`).
    solver : SolverSettings, optional
        ``tol``, ``periodic``, ``volume_conservation`` (and ``maxiter``) of the normal solves.
    direction : {1, -1}
        Sliding direction of the tool along ``x`` (entering flanks, Eq. 23).
    label : str
        Name of the pair in the outputs.

    Returns
    -------
    GeometricResult
    """
    mat, sol = records(materials, solver)
    H, m, sigma_y, tol = mat.H, mat.m, mat.sigma_y, sol.tol
    pressures = _check(pressures, H, m, sigma_y, tol)
    zw, dxf, dyf = _heights("workpiece", workpiece)
    zt, dxt, dyt = _heights("tool", tool)
    if zw.shape != zt.shape or not (np.isclose(dxf, dxt) and np.isclose(dyf, dyt)):
        raise ValueError(
            f"workpiece and tool must share the measured grid, got {zw.shape} at {dxf:g} x {dyf:g} m "
            f"and {zt.shape} at {dxt:g} x {dyt:g} m"
        )
    sx, sy = (block, block) if np.isscalar(block) else tuple(block)
    if zw.shape[0] % sx or zw.shape[1] % sy:
        raise ValueError(f"block {(sx, sy)} must divide the measured grid {zw.shape}")
    nx, ny = zw.shape[0] // sx, zw.shape[1] // sy
    wc = _surf.block_average(workpiece, (nx, ny))
    tc = _surf.block_average(tool, (nx, ny))
    E_star = mat.E_star
    order = np.argsort(pressures)
    k = len(pressures)
    out = {key: np.zeros(k) for key in ("alpha", "tau_adh", "tau_geo", "plastic_fraction")}
    conv = np.zeros(k, bool)
    msgs = [""] * k
    t0 = time.perf_counter()
    p_init = None
    for i in order:
        r = solve_normal_pair(
            wc.heights,
            tc.heights,
            wc.dx,
            E_star,
            pressures[i],
            H=H,
            dy=wc.dy,
            p_init=p_init,
            volume_conservation=sol.volume_conservation,
            **sol.normal_kwargs(),
        )
        p_init = r.pressure
        out["alpha"][i] = r.alpha
        out["plastic_fraction"][i] = r.plastic_fraction
        out["tau_adh"][i] = tau_adh_full_sliding(r.alpha, m, sigma_y)
        out["tau_geo"][i] = tau_geo_from_surfaces(
            r.pressure, zw, zt, (sx, sy), dxf, dyf, plastic=r.pressure >= H, direction=direction
        )
        conv[i] = r.converged
        msgs[i] = r.message
    ratio = np.divide(out["tau_geo"], out["tau_adh"], out=np.zeros(k), where=out["tau_adh"] > 0)
    settings = {
        "grid": [nx, ny],
        "block": [int(sx), int(sy)],
        "measured_grid": list(zw.shape),
        "dx": wc.dx,
        "dy": wc.dy,
        "E_star": E_star,
        "H": float(H),
        "m": float(m),
        "sigma_y": float(sigma_y),
        "tol": tol,
        "periodic": bool(sol.periodic),
        "direction": int(direction),
        "workpiece_Ra": _surf.ra(wc),
        "workpiece_Rq": _surf.rq(wc),
        "tool_Ra": _surf.ra(tc),
        "tool_Rq": _surf.rq(tc),
    }
    return GeometricResult(
        label,
        np.asarray(pressures),
        ratio=ratio,
        converged=conv,
        messages=msgs,
        settings=settings,
        seconds=time.perf_counter() - t0,
        **out,
    )


def fit_geo_ratio(result):
    """Eq. 26's extra term ``f(p) = geo_ratio k alpha(p)``, fitted to ``tau_geo(p)``.

    With ``tau = m [k alpha + f]`` and the geometric shear added to the adhesive one,
    ``m f = tau_geo``; the runtime's ``f = geo_ratio k alpha`` then gives
    ``tau_geo = geo_ratio tau_adh``. Least squares over the converged pressures:
    ``geo_ratio = sum(tau_geo tau_adh) / sum(tau_adh^2)``.

    Parameters
    ----------
    result : GeometricResult

    Returns
    -------
    dict
        ``geo_ratio``, ``ratio_mean`` (the plain mean of ``tau_geo / tau_adh``), ``rms_misfit``
        (RMS of ``tau_geo - geo_ratio tau_adh`` over RMS of ``tau_geo``) and ``pressures`` used.
    """
    ok = np.asarray(result.converged, bool) & (result.tau_adh > 0)
    if not ok.any():
        raise ValueError("no converged pressure with tau_adh > 0: nothing to fit")
    ta, tg = result.tau_adh[ok], result.tau_geo[ok]
    g = float(np.sum(tg * ta) / np.sum(ta * ta))
    rms_tg = float(np.sqrt(np.mean(tg * tg)))
    misfit = float(np.sqrt(np.mean((tg - g * ta) ** 2)) / rms_tg) if rms_tg > 0 else 0.0
    return {
        "geo_ratio": g,
        "ratio_mean": float(np.mean(tg / ta)),
        "rms_misfit": misfit,
        "pressures": [float(p) for p in result.p_mean[ok]],
    }


def geometric_study(
    pressures=GEO_PRESSURES,
    *,
    n=128,
    block=4,
    seed_workpiece=1,
    seed_tool=2,
    roughness_on="solver",
    materials=None,
    solver=None,
):
    """The geometric study: the DC04-like workpiece against the smooth and the rough tool.

    It gives Figs. 9-10.

    Parameters
    ----------
    pressures : sequence of float
        ``p_mean`` in Pa (default 100-600 MPa).
    n, block, seed_workpiece, seed_tool, roughness_on
        See :func:`~halfspace_calib.topography.synthesis.measured_surfaces` (default 128 elements from a 512 x 512 measurement).
    materials, solver
        See :func:`geometric_sweep`.

    Returns
    -------
    GeometricStudy
        Results labelled ``"smooth tool"`` and ``"rough tool"``.
    """
    t0 = time.perf_counter()
    results = []
    for rough, label in ((False, "smooth tool"), (True, "rough tool")):
        wp, tl = measured_surfaces(
            n,
            block,
            rough_tool=rough,
            seed_workpiece=seed_workpiece,
            seed_tool=seed_tool,
            roughness_on=roughness_on,
        )
        results.append(
            geometric_sweep(
                wp,
                tl,
                pressures,
                block=block,
                materials=materials,
                solver=solver,
                label=label,
            )
        )
    return GeometricStudy(results, time.perf_counter() - t0)
