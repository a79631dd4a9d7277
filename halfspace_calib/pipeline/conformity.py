"""Diagnosis of a nearly conforming contact in the non-periodic solve (docs/measured_surfaces.md).

In the non-periodic solve (DC-FFT, zero padding) the patch is a finite body pressed on a
half-space. When the surfaces are so smooth that the contact becomes complete at small
pressures, the patch acts as a flat punch: the pressure rises towards its edge (Boussinesq's
punch has an inverse square-root edge singularity), the edge elements reach the hardness cap
``H`` and deform plastically, and the reload curves then measure the plastic rim of the patch,
not the roughness. Eq. 25 does not describe such curves. :func:`edge_plasticity` measures it on
the pressure map of the highest load level, and :func:`punch_edge_problem` turns it into the
sentence that :meth:`halfspace_calib.pipeline.calibration.Calibration.problems` prints.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CENTRE_RATIO_MAX", "RIM_MIN", "EdgePlasticity", "edge_plasticity", "punch_edge_problem"]

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
        Contact pressure (Pa) of the non-periodic solve.
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

    Only for a non-periodic calibration whose reload fit is unusable (``R^2 <`` the fit's
    minimum or a parameter on its bound) and whose highest load level has its capped elements at
    the patch's edge (:attr:`EdgePlasticity.punch_edge`).
    """
    from .fit import R2_MIN

    if cal.scene.periodic or (cal.reload.r_squared >= R2_MIN and not cal.reload.at_bound):
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
        "and in the non-periodic solve the patch then acts as a flat punch whose edge goes "
        f"plastic: at p_hist = {top.p_hist / 1e6:g} MPa, {100 * e.rim_capped:.0f} % of the "
        f"elements within {e.band} elements of the patch's edge are at the hardness H, "
        f"{100 * e.centre_capped:.0f} % of its central square. The reload curves measure that plastic rim, not the "
        "roughness, and Eq. 25 cannot describe them. Rerun with --periodic (Scene(periodic=True):"
        " no patch edge; the scan's opposite edges are joined), or with a smaller --lambda-s and "
        "a larger --grid, so that the contact stays partial (docs/measured_surfaces.md)"
    )
