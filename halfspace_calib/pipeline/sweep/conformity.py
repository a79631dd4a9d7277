"""Diagnosis of a nearly conforming contact in the isolated solve (docs/measured_surfaces.md).

With ``boundary="isolated"`` (DC-FFT, zero padding; the default for measured files before the
mirror-symmetric boundary) the patch is a finite body pressed on a half-space. When the
surfaces are so smooth that the contact becomes complete at small pressures, the patch acts as
a flat punch: the pressure rises towards its edge (Boussinesq's punch has an inverse
square-root edge singularity), the edge elements reach the hardness cap ``H`` and deform
plastically, and the reload curves then measure the plastic rim of the patch, not the
roughness: they fall with ``p_hist``, below the first loading. Eq. 25 does not describe such
curves. :func:`edge_plasticity` measures where the cap is reached on a pressure map (the
border band against the centre, on any boundary: the benchmark ``patch_boundary.py`` reports
it for each), and :func:`punch_edge_problem` turns a punch edge of an isolated calibration into
the sentence that :meth:`halfspace_calib.pipeline.calibration.Calibration.problems` prints.
The default ``boundary="mirror"`` has no patch edge (nor a seam): the two fractions are equal
there on every measured file (docs/measured_surfaces.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import PchipInterpolator

__all__ = [
    "CENTRE_RATIO_MAX",
    "RIM_MIN",
    "EdgePlasticity",
    "ReloadDeficit",
    "ReloadGridChange",
    "edge_plasticity",
    "punch_edge_problem",
    "reload_deficit",
    "reload_grid_change",
]

#: the cap counts as a punch edge when at least this fraction of the border band is at the cap
RIM_MIN = 0.5
#: ... and the central square (the middle half along each side) at most this fraction of it
CENTRE_RATIO_MAX = 0.1


@dataclass(frozen=True)
class EdgePlasticity:
    """Where the elements at the hardness cap lie on a pressure map.

    Attributes
    ----------
    capped_fraction : float
        Fraction of the patch's elements at the cap (``p >= H (1 - 1e-6)``).
    rim_capped : float
        Fraction of the elements of the border band (within ``band`` elements of the edge) at
        the cap.
    centre_capped : float
        Fraction of the elements of the central square (the middle half along each side) at the
        cap.
    band : int
        Width of the border band (elements).
    """

    capped_fraction: float
    rim_capped: float
    centre_capped: float
    band: int

    @property
    def punch_edge(self):
        """The cap is reached at the patch's edge and hardly in its centre.

        At least :data:`RIM_MIN` of the border band is capped, and the central square at most
        :data:`CENTRE_RATIO_MAX` times as much (a rough contact spreads its plastic asperities
        evenly: the two fractions are then about equal).
        """
        return (
            self.rim_capped >= RIM_MIN and self.centre_capped <= CENTRE_RATIO_MAX * self.rim_capped
        )


def edge_plasticity(pressure, H, band=None):
    """Measure how much of the cap ``H`` is reached at the edge of a pressure map.

    Parameters
    ----------
    pressure : ndarray (n, m)
        Contact pressure (Pa) of a solve (the punch edge is the isolated boundary's).
    H : float
        Hardness (Pa), the pressure cap.
    band : int, optional
        Border band width in elements; default ``max(2, min(n, m) // 16)``.
    """
    p = np.asarray(pressure, dtype=np.float64)
    if p.ndim != 2 or min(p.shape) < 8:
        raise ValueError(f"pressure must be a 2-D map of at least 8 x 8 elements, got {p.shape}")
    if not np.isfinite(p).all():
        raise ValueError("pressure must be finite (no NaN or inf)")
    if not (math.isfinite(H) and H > 0):
        raise ValueError(f"H must be a finite pressure > 0 (Pa), got {H!r}")
    n, m = p.shape
    b = max(2, min(n, m) // 16) if band is None else int(band)
    if not 1 <= b <= min(n, m) // 4:
        raise ValueError(f"band must be in [1, {min(n, m) // 4}] elements, got {band!r}")
    capped = p >= H * (1 - 1e-6)
    rim = np.ones_like(capped)
    rim[b:-b, b:-b] = False
    centre = capped[n // 4 : n - n // 4, m // 4 : m - m // 4]
    return EdgePlasticity(
        capped_fraction=float(capped.mean()),
        rim_capped=float(capped[rim].mean()),
        centre_capped=float(centre.mean()),
        band=b,
    )


def punch_edge_problem(cal):
    """The sentence explaining a failed reload fit by a plastic punch edge, or ``""``.

    Only for a calibration with ``boundary="isolated"`` whose reload branch fails its measured
    error (the held-out maximum beyond ``scene.heldout_tol``, :mod:`.heldout`) and whose highest
    load level has its capped elements at the patch's edge (:attr:`EdgePlasticity.punch_edge`).
    """
    err = cal.errors.get("reload")
    if cal.scene.boundary != "isolated" or err is None or not err.exceeds(cal.scene.heldout_tol):
        return ""
    top = max(cal.sweeps.levels, key=lambda lv: lv.p_hist, default=None)
    if top is None or top.pressure_map is None:
        return ""
    e = edge_plasticity(top.pressure_map, cal.scene.H)
    if not e.punch_edge:
        return ""
    p, a = cal.sweeps.loading
    return (
        f"the contact is nearly conforming (contact ratio {a[0]:.2f} at {p[0] / 1e6:g} MPa), "
        "and in the isolated solve (boundary isolated) the patch then acts as a flat punch whose "
        "edge goes "
        f"plastic: at p_hist = {top.p_hist / 1e6:g} MPa, {100 * e.rim_capped:.0f} % of the "
        f"elements within {e.band} elements of the patch's edge are at the hardness H, "
        f"{100 * e.centre_capped:.0f} % of its central square. The reload curves measure that "
        "plastic rim, not the roughness, and Eq. 25 cannot describe them. Rerun with --boundary "
        "mirror (Scene(boundary='mirror'), the default for files: the patch's mirror-symmetric "
        "extension, no patch edge and no seam; docs/measured_surfaces.md)"
    )


@dataclass(frozen=True)
class ReloadDeficit:
    """How far the reload curves fall below the first loading at the same pressure.

    Attributes
    ----------
    worst : float
        Largest ``alpha_first(p) - alpha_reload(p)`` over the reload points (``<= 0``: every
        point lies at or above the first loading).
    p_hist, p : float
        Where it is (Pa).
    points : int
        Reload points compared (those within the first loading's pressure range).
    """

    worst: float
    p_hist: float
    p: float
    points: int


def reload_deficit(first_p, first_alpha, curves):
    """Compare each reload curve with the first loading at the same pressure.

    A plastically flattened surface carries at least the contact of the virgin one at the
    same mean pressure: in the half-space model each reload point lies at or above the first
    loading. A patch edge (the isolated boundary's flat punch) breaks that.

    Parameters
    ----------
    first_p, first_alpha : array_like
        The first loading: mean pressures (Pa, any order) and contact ratios. A reload pressure
        found among them (to 9 digits) is compared with that point; others with the monotone cubic
        (PCHIP) interpolant in ``log p``. Reload points outside their range are not compared.
    curves : sequence
        Reload curves with ``p_hist``, ``p`` and ``alpha`` (e.g.
        :meth:`~halfspace_calib.pipeline.sweep.sweeps.SweepResult.reload_curves`).

    Returns
    -------
    ReloadDeficit
    """
    p1 = np.asarray(first_p, dtype=float)
    a1 = np.asarray(first_alpha, dtype=float)
    if p1.ndim != 1 or p1.shape != a1.shape or p1.size < 2:
        raise ValueError("first_p and first_alpha must be 1-D arrays of the same length >= 2")
    if not (np.isfinite(p1).all() and np.isfinite(a1).all() and (p1 > 0).all()):
        raise ValueError("first_p must be finite pressures > 0 (Pa), first_alpha finite")
    order = np.argsort(p1)
    p1, a1 = p1[order], a1[order]
    if np.any(np.diff(p1) <= 0):
        raise ValueError("first_p must hold distinct pressures")
    interp = PchipInterpolator(np.log(p1), a1)
    exact = {_key(p): float(a) for p, a in zip(p1, a1, strict=True)}
    worst, where, n = -np.inf, (math.nan, math.nan), 0
    for c in curves:
        for p, a in zip(np.asarray(c.p, float), np.asarray(c.alpha, float), strict=True):
            if not p1[0] <= p <= p1[-1]:
                continue
            ref = exact.get(_key(p))
            ref = float(interp(math.log(p))) if ref is None else ref
            n += 1
            if ref - a > worst:
                worst, where = ref - a, (float(c.p_hist), float(p))
    if n == 0:
        raise ValueError("no reload point lies within the first loading's pressure range")
    return ReloadDeficit(float(worst), where[0], where[1], n)


@dataclass(frozen=True)
class ReloadGridChange:
    """The largest change of the reload curves' contact ratio between two grids.

    Attributes
    ----------
    worst : float
        Largest ``|alpha - alpha_half|`` over the reload points both have.
    p_hist, p : float
        Where it is (Pa).
    points : int
        Points compared.
    """

    worst: float
    p_hist: float
    p: float
    points: int


def reload_grid_change(curves, curves_half):
    """Compare the reload curves of two grids point by point (the same ``p_hist`` and ``p``).

    ``curves``, ``curves_half``: reload curves with ``p_hist``, ``p`` and ``alpha``, for
    example of the calibration's grid and of half of it. Points are matched by their
    pressures (relative 1e-9); unmatched ones are ignored.
    """
    half = {}
    for c in curves_half:
        for p, a in zip(np.asarray(c.p, float), np.asarray(c.alpha, float), strict=True):
            half[(_key(c.p_hist), _key(p))] = float(a)
    worst, where, n = 0.0, (math.nan, math.nan), 0
    for c in curves:
        for p, a in zip(np.asarray(c.p, float), np.asarray(c.alpha, float), strict=True):
            b = half.get((_key(c.p_hist), _key(p)))
            if b is None:
                continue
            n += 1
            if abs(a - b) >= worst:
                worst, where = abs(a - b), (float(c.p_hist), float(p))
    if n == 0:
        raise ValueError("the two sets of reload curves have no point in common")
    return ReloadGridChange(float(worst), where[0], where[1], n)


def _key(p):
    """A pressure rounded to 9 significant digits (matching points of two sweeps)."""
    return float(f"{float(p):.9g}")
