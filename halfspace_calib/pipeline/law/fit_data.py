"""The data the fits take, checked: first-loading points, reload curves and parameter bounds.

:func:`_data` and :func:`_curve` refuse what no fit can use (mismatched lengths, NaN, ``p <= 0``,
``alpha`` outside ``[0, 1]``, reload pressures at or above ``p_hist``), naming the argument;
:func:`_bounds` checks a pair of bounds against the law's validated range.
"""

import math
from dataclasses import dataclass

import numpy as np

from ...common.checks import positive

__all__ = ["ReloadCurve"]


@dataclass(frozen=True)
class ReloadCurve:
    """One un-/reloading curve: ``alpha`` at pressures ``p < p_hist`` (Pa)."""

    p_hist: float
    p: np.ndarray
    alpha: np.ndarray


# -- validation -------------------------------------------------------------------------


def _bounds(name, b, allowed):
    """``(lo, hi)`` with ``0 < lo < hi``, inside ``allowed`` (FrictionParams' validated range)."""
    try:
        lo, hi = (float(x) for x in b)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair (lo, hi) with 0 < lo < hi, got {b!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
        raise ValueError(f"{name} must be a pair (lo, hi) with 0 < lo < hi < inf, got {b!r}")
    if lo < allowed[0] or hi > allowed[1]:
        raise ValueError(
            f"{name} must lie within [{allowed[0]:g}, {allowed[1]:g}] (the law's validated "
            f"range), got {b!r}"
        )
    return lo, hi


def _data(p, alpha, p_name="p", alpha_name="alpha"):
    p = np.asarray(p, dtype=np.float64)
    alpha = np.asarray(alpha, dtype=np.float64)
    if p.ndim != 1 or alpha.ndim != 1:
        raise ValueError(f"{p_name} and {alpha_name} must be 1-D arrays")
    if p.shape != alpha.shape:
        raise ValueError(
            f"{alpha_name} must have the same length as {p_name}: {alpha.size} != {p.size}"
        )
    if not np.isfinite(p).all():
        raise ValueError(f"{p_name} must be finite (no NaN or inf)")
    if not np.isfinite(alpha).all():
        raise ValueError(f"{alpha_name} must be finite (no NaN or inf)")
    if (p <= 0).any():
        raise ValueError(f"{p_name} must be > 0 (Pa), got min {p.min():g}")
    if ((alpha < 0) | (alpha > 1)).any():
        raise ValueError(
            f"{alpha_name} must be in [0, 1] (a contact ratio), got range "
            f"[{alpha.min():g}, {alpha.max():g}]"
        )
    return p, alpha


def _curve(i, c):
    if isinstance(c, ReloadCurve):
        ph, p, a = c.p_hist, c.p, c.alpha
    elif isinstance(c, dict):
        try:
            ph, p, a = c["p_hist"], c["p"], c["alpha"]
        except KeyError as exc:
            raise ValueError(f"curves[{i}] lacks key {exc}") from None
    else:
        try:
            ph, p, a = c
        except (TypeError, ValueError):
            raise ValueError(
                f"curves[{i}] must be a ReloadCurve, a dict or a tuple (p_hist, p, alpha)"
            ) from None
    ph = positive(f"curves[{i}].p_hist", ph)
    p, a = _data(p, a, f"curves[{i}].p", f"curves[{i}].alpha")
    if (p >= ph).any():
        raise ValueError(
            f"curves[{i}].p must be < p_hist = {ph:g} Pa (reloading), got max {p.max():g}"
        )
    return ReloadCurve(ph, p, a)
