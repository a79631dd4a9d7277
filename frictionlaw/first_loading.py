"""The first-loading branch's tabulated form: the computed contact ratios themselves.

The paper's Eq. 24 has two parameters, ``C1`` and ``n1``. On measured pairs the half-space
model's first loading takes shapes no two-parameter smooth minimum follows: full contact from
low pressure (``alpha`` 0.65 at 10 MPa, 1 from 100 MPa), or an ``alpha / (p / H)`` that rises
between two pressures (benchmarks/first_loading.py; Eq. 24 misses such curves by 0.05-0.07 in
``alpha``). The ``"tabulated"`` form runs the computed points ``(p_j, alpha_j)``, ``j = 0 ..
J - 1``, and interpolates between them:

* between the first and the last level: a monotone cubic Hermite interpolant (Fritsch and
  Carlson 1980, the slopes of SciPy's ``PchipInterpolator``,
  :func:`frictionlaw.reload_form.pchip_slopes`) of ``v = ln alpha`` over ``u = ln(p / H)``; it
  does not overshoot, so ``alpha`` is non-decreasing and at most ``alpha_{J-1} <= 1``;
* below the lowest level the Coulomb line through the origin, ``alpha = alpha_0 p / p_0``: the
  small-pressure limit is ``tau = mu_eff p`` with ``mu_eff = tau_max alpha_0 / p_0``. The
  interpolant's first slope is its own (shape-preserving) end slope, not the line's 1: a curve
  that already bends at the lowest level (nearly conforming pairs, ``alpha`` 0.65 at 10 MPa)
  is missed by up to 0.05 between the first two levels when the joint is forced smooth, so the
  slope of ``tau`` has a kink at ``p_0`` there (measured in docs/runtime.md);
* above the top level the power law of the interpolant's end slope,
  ``alpha = alpha_{J-1} (p / p_{J-1}) ** d_{J-1}``, capped at 1 (1 exactly when the top level is
  in full contact).

``d tau / d p = tau (d ln alpha / d ln p) / p`` is finite at every ``p > 0`` and equals
``mu_eff`` below the lowest level. The knots ``u = ln(p / H)`` and ``v = ln alpha`` are
dimensionless, so no unit system changes them (the coefficient layout in
:mod:`frictionlaw._kernels`).
"""

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._io import read_versioned
from .reload_form import pchip_slopes

__all__ = ["FIRST_LOADING_TABLE_VERSION", "P_MIN_H", "FirstLoadingTable"]

#: version of the ``first_loading_law`` object inside a parameter file
FIRST_LOADING_TABLE_VERSION = 1
#: the lowest level a table may have, as a fraction of ``H``
P_MIN_H = 1e-9

_INTERPOLATION = (
    "monotone cubic Hermite (Fritsch-Carlson, the slopes of SciPy's PchipInterpolator) of "
    "ln alpha over ln(p/H) between the levels; below the first level the Coulomb line "
    "alpha = alpha_0 p / p_0; above the last level the power law of the end slope, capped at 1"
)


def _values(name: str, values: object) -> tuple[float, ...]:
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"first-loading table {name} must be a list of real numbers") from None
    if arr.ndim != 1 or arr.size < 2:
        raise ValueError(
            f"first-loading table {name} must be a 1-D list of at least 2 values, got "
            f"shape {arr.shape}"
        )
    if not np.isfinite(arr).all():
        raise ValueError(f"first-loading table {name} must hold finite values")
    return tuple(float(v) for v in arr)


@dataclass(frozen=True)
class FirstLoadingTable:
    """The computed first loading ``(p_j, alpha_j)`` the ``"tabulated"`` form interpolates.

    Parameters
    ----------
    p : sequence of float
        Mean contact pressures (Pa), strictly increasing, ``> 0`` (and below ``H``, which
        :class:`~frictionlaw.FrictionParams` checks); at least 2.
    alpha : sequence of float
        Contact ratios at ``p``, non-decreasing, in ``(0, 1]``.
    """

    p: tuple
    alpha: tuple

    def __post_init__(self) -> None:
        p = _values("p", self.p)
        a = _values("alpha", self.alpha)
        if len(p) != len(a):
            raise ValueError(
                f"first-loading table: p and alpha need one value per level, got {len(p)} "
                f"and {len(a)}"
            )
        if p[0] <= 0.0 or any(b <= x for x, b in zip(p, p[1:], strict=False)):
            raise ValueError(
                f"first-loading table p must be > 0 and strictly increasing (Pa), got {p}"
            )
        bad = [v for v in a if not 0.0 < v <= 1.0]
        if bad:
            raise ValueError(
                f"first-loading table alpha must be contact ratios in (0, 1], got {bad[0]!r}"
            )
        if any(b < x for x, b in zip(a, a[1:], strict=False)):
            raise ValueError(
                "first-loading table alpha must not decrease with p (the contact grows on "
                f"first loading), got {a}"
            )
        object.__setattr__(self, "p", p)
        object.__setattr__(self, "alpha", a)

    def check_hardness(self, H: float) -> None:
        """``ValueError`` unless every level lies in ``[1e-9 H, H)`` (Pa).

        Below ``H``: a mean pressure cannot reach the hardness. From ``1e-9 H``: the Coulomb
        slope ``alpha_0 / p_0`` below the lowest level stays finite for every ``tau_max``
        (calibrated levels start near ``0.01 H``).
        """
        if self.p[-1] >= H:
            raise ValueError(
                f"first-loading table p must lie below H = {H:g} Pa (a mean pressure cannot "
                f"reach the hardness), got {self.p[-1]:g} Pa"
            )
        if self.p[0] < P_MIN_H * H:
            raise ValueError(
                f"first-loading table p must start at {P_MIN_H:g} H = {P_MIN_H * H:g} Pa or "
                f"above (the Coulomb slope alpha_0 / p_0 below it), got {self.p[0]:g} Pa"
            )

    def knots(self, H: float) -> dict[str, NDArray[np.float64]]:
        """The interpolant's data: ``u = ln(p / H)``, ``v = ln alpha`` and the slopes ``dv/du``."""
        u = np.log(np.asarray(self.p)) - math.log(H)
        v = np.log(np.asarray(self.alpha))
        return {"u": u, "v": v, "d": pchip_slopes(u, v)}

    @property
    def slope0(self) -> float:
        """``alpha_0 / p_0`` (1/Pa): the Coulomb line's slope below the lowest level."""
        return self.alpha[0] / self.p[0]

    def to_dict(self, form: str) -> dict[str, Any]:
        """The ``first_loading_law`` JSON object of a parameter file (own version and units)."""
        return {
            "form": form,
            "version": FIRST_LOADING_TABLE_VERSION,
            "interpolation": _INTERPOLATION,
            "units": {"p": "Pa", "alpha": "1"},
            "p": list(self.p),
            "alpha": list(self.alpha),
        }

    @classmethod
    def from_dict(cls, doc: dict, *, source: str = "<dict>") -> "FirstLoadingTable":
        """The table of a ``first_loading_law`` object; ``ValueError`` naming the field."""
        return read_versioned(
            doc,
            f"{source}: first_loading_law",
            FIRST_LOADING_TABLE_VERSION,
            {"p": "Pa", "alpha": "1"},
            lambda d: cls(p=d["p"], alpha=d["alpha"]),
        )
