"""The calibrated tangential interface stiffness ``k_t(p)`` of a parameter file (its own object)."""

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._io import read_versioned

__all__ = ["TangentialStiffness", "K_T_FORMAT_VERSION"]

#: version of the optional ``tangential_stiffness`` object inside a parameter file
K_T_FORMAT_VERSION = 1


def _positive_table(name: str, values: object) -> tuple[float, ...]:
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a list of real numbers, got {values!r}") from None
    if arr.ndim != 1 or arr.size < 1:
        raise ValueError(f"{name} must be a non-empty 1-D list, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
        raise ValueError(f"{name} must hold finite values in (0, inf), got {values!r}")
    return tuple(float(v) for v in arr)


@dataclass(frozen=True)
class TangentialStiffness:
    """Calibrated tangential interface stiffness ``k_t(p)`` of the roughness layer.

    A table of the stiffness (Pa/m, traction per slip) at the calibration's pressures (Pa),
    evaluated by log-log interpolation between the points and held constant beyond the
    first and last point (no extrapolation of a power law outside the calibrated range).
    It is the penalty ``k_t`` of :func:`frictionlaw.traction_update` per node at its pressure.

    Parameters
    ----------
    p : sequence of float
        Mean contact pressures (Pa), strictly increasing, ``> 0``.
    k_t : sequence of float
        Stiffness at each pressure (Pa/m), ``> 0``, same length as ``p``.
    """

    p: tuple
    k_t: tuple

    def __post_init__(self) -> None:
        p = _positive_table("k_t table p", self.p)
        k = _positive_table("k_t table k_t", self.k_t)
        if len(p) != len(k):
            raise ValueError(f"k_t table: p has {len(p)} values, k_t has {len(k)}; need equal")
        if any(b <= a for a, b in zip(p, p[1:], strict=False)):
            raise ValueError(f"k_t table p must be strictly increasing, got {p}")
        object.__setattr__(self, "p", p)
        object.__setattr__(self, "k_t", k)

    def __call__(self, p: ArrayLike) -> NDArray[np.float64]:
        """``k_t`` (Pa/m) at pressures ``p`` (Pa); ``p <= 0`` gets the lowest tabulated value."""
        p = np.asarray(p, dtype=float)
        lp = np.log(np.clip(p, self.p[0], self.p[-1]))
        k = np.exp(np.interp(lp, np.log(self.p), np.log(self.k_t)))
        k = np.where(p <= self.p[0], self.k_t[0], k)
        return np.where(p >= self.p[-1], self.k_t[-1], k)

    def to_dict(self) -> dict[str, Any]:
        """The JSON object (with its own version and units)."""
        return {
            "version": K_T_FORMAT_VERSION,
            "units": {"p": "Pa", "k_t": "Pa/m"},
            "interpolation": "log-log, constant beyond the end points",
            "p": list(self.p),
            "k_t": list(self.k_t),
        }

    @classmethod
    def from_dict(cls, doc: object, *, source: str = "<dict>") -> "TangentialStiffness":
        """Build from :meth:`to_dict`'s object; raises ``ValueError`` if malformed."""
        where = f"{source}: tangential_stiffness"
        if not isinstance(doc, dict):
            raise ValueError(f"{where} must be a JSON object")
        return read_versioned(
            doc,
            where,
            K_T_FORMAT_VERSION,
            {"p": "Pa", "k_t": "Pa/m"},
            lambda d: cls(p=d["p"], k_t=d["k_t"]),
        )
