"""Pressures against the calibrated range: where the law is extrapolated.

The calibration fits Eq. 24 on first-loading pressures ``p_min .. p_max`` (the file's
``calibrated_range``) and Eq. 25 on reloads from histories inside that range. A node whose
pressure ``p`` lies between ``p_max`` and the hardness ``H`` uses Eq. 24 beyond its data
(extrapolated); a node whose history ``p_hist`` lies there reloads on Eq. 25 scaled by the
extrapolated ``alpha1(p_hist)``; a node with ``0 < p < p_min`` uses Eq. 24's low-pressure
(Coulomb-like) end below its data. Nodes at ``p >= H`` (or ``p_hist >= H``) are counted
separately: there the half-space model has an exact limit, full contact (``alpha = 1`` at
``p_mean = H``: every local pressure is at most ``H``), which Eq. 24 approaches
(``alpha1(H) = tanh(C1**n1)**(1/n1)``, 0.994 for the default calibration fitted with the
bound ``alpha1 >= p / H`` up to 0.99 H), so these nodes follow the model's limit rather than
an extrapolation. :func:`check_pressure_range` counts them; NumPy only (no kernel, no numba
import), a handful of array passes per call.
"""

from dataclasses import dataclass, fields
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from .law import as_float_array

if TYPE_CHECKING:
    from .params import FrictionParams

__all__ = ["RangeCheck", "check_pressure_range"]


@dataclass(frozen=True)
class RangeCheck:
    """Contact pressures of one evaluation (or the worst of several) against ``p_range``.

    Attributes
    ----------
    p_min, p_max : float
        The calibrated first-loading range (Pa).
    n_contact : int
        Nodes in contact (``p > 0``).
    n_above : int
        Nodes with ``p_max < p < H`` (Eq. 24 extrapolated upwards).
    n_hist_above : int
        Nodes with ``p_max < p_hist < H`` (their Eq. 25 branch rests on an extrapolated
        ``alpha1(p_hist)``); 0 when no history was given.
    n_below : int
        Nodes with ``0 < p < p_min`` (Eq. 24 below its data, towards its Coulomb limit).
    p_peak : float
        Largest ``p`` (Pa), 0 when no node is in contact.
    p_hist_peak : float
        Largest ``p_hist`` (Pa), 0 when no history was given.
    ratio : float
        ``p_peak / p_max``: how far beyond the range the pressure went (``> 1``: beyond).
    n_above_H : int
        Contact nodes with ``p >= H``: at the half-space model's exact limit (full contact),
        not counted in ``n_above``.
    n_hist_above_H : int
        Nodes with ``p_hist >= H``, not counted in ``n_hist_above``.
    H : float
        The hardness (Pa) that separates the two (``inf`` for a check without one).
    """

    p_min: float
    p_max: float
    n_contact: int
    n_above: int
    n_hist_above: int
    n_below: int
    p_peak: float
    p_hist_peak: float
    ratio: float
    n_above_H: int = 0
    n_hist_above_H: int = 0
    H: float = float("inf")

    @property
    def beyond(self) -> bool:
        """True if any node's ``p`` or ``p_hist`` lies between ``p_max`` and ``H`` (extrapolated)."""
        return self.n_above > 0 or self.n_hist_above > 0

    @property
    def at_limit(self) -> bool:
        """True if any node's ``p`` or ``p_hist`` is at least ``H`` (the model's limit)."""
        return self.n_above_H > 0 or self.n_hist_above_H > 0

    def worst(self, other: "RangeCheck | None") -> "RangeCheck":
        """Field-wise maximum with ``other`` (same range): the worst over several increments.

        Counts are maxima over the evaluations, not sums (a node beyond the range in ten
        increments counts once per increment, so a sum would mean nothing).
        """
        if other is None:
            return self
        if (other.p_min, other.p_max, other.H) != (self.p_min, self.p_max, self.H):
            raise ValueError("worst() needs two checks against the same calibrated range")
        vals = {f.name: max(getattr(self, f.name), getattr(other, f.name)) for f in fields(self)}
        return RangeCheck(**vals)


def check_pressure_range(
    params: "FrictionParams | None", p: ArrayLike, p_hist: ArrayLike | None = None
) -> RangeCheck | None:
    """Check contact pressures (and histories) against the calibrated range of ``params``.

    Parameters
    ----------
    params : FrictionParams or None
        The law's parameters; without a ``p_range`` (hand-made parameter sets) or ``None``
        the check has nothing to compare with and returns ``None``.
    p : array_like
        Contact pressures (Pa) per node; ``p <= 0`` is an open node and is not counted.
    p_hist : array_like, optional
        Pressure history (Pa) per node; every node counts here, in contact or not (a
        history is carried through an opening).

    Returns
    -------
    RangeCheck or None
    """
    rng = getattr(params, "p_range", None)
    if params is None or rng is None:
        return None
    p_min, p_max = rng
    p = as_float_array("p", p).ravel()
    on = p > 0.0
    n_on = int(np.count_nonzero(on))
    H = float(params.H)
    p_peak = float(p.max(initial=0.0))
    n_above = int(np.count_nonzero((p > p_max) & (p < H)))
    n_above_H = int(np.count_nonzero(p >= H))
    n_below = int(np.count_nonzero(on & (p < p_min)))
    n_hist, n_hist_H, h_peak = 0, 0, 0.0
    if p_hist is not None:
        h = as_float_array("p_hist", p_hist).ravel()
        n_hist = int(np.count_nonzero((h > p_max) & (h < H)))
        n_hist_H = int(np.count_nonzero(h >= H))
        h_peak = float(h.max(initial=0.0))
    ratio = p_peak / p_max
    return RangeCheck(
        p_min, p_max, n_on, n_above, n_hist, n_below, p_peak, h_peak, ratio, n_above_H, n_hist_H, H
    )
