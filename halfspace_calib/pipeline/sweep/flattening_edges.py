"""The workpiece's edge slope against the contact fraction: the two-state law's surface map.

The two-state flattening law (model ``limit-analysis``, docs/flattening.md) reads the flank
slope of the asperities at the contact's edge. A wedge lattice has one slope; a measured surface
meets its shallow flanks first and its steep ones later. The *edge slope* at contact fraction
``A`` is the mean ``|dz/dx|`` of the profiles where the level that leaves the share ``A`` of
them above it (the bearing level) crosses them: a wedge lattice's contact grows by
``dA / dh = 1 / (l s)`` per level ``dh``, a profile's by ``(1 / L) sum 1 / |z'_i|`` over its
``n`` crossings, and with ``l = L / n`` the two agree at the crossings' harmonic mean slope.

Here it is averaged over a bin of contact fractions around each tabulated ``A`` (the profiles
piecewise linear between samples): over the levels of a bin, the crossings' harmonic mean is
``sum over segments of the bin's height range they span / (L dA)``, which a sort and prefix sums
give for all bins at once. The x and the y profiles are taken apart and combined as the block's
RMS slope is (their quadratic mean), so that a surface of ridges gets the same slope either
way and an isotropic one its profiles' own.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["EDGE_POINTS", "EDGE_FLOOR", "edge_slope_table", "profile_edge_slopes"]

#: contact fractions of the block's ``edge_slope`` (0, 0.02, ..., 1): coarser tables (26, 21
#: points) and finer ones (101, 1601) move the resolved measured rows' largest miss by at most
#: 0.01 (docs/flattening.md, "The edge slope")
EDGE_POINTS = 51
#: the table's smallest value: the two-state law's floor on the flank slope it integrates
#: (``1e-3``; its rates are read at 0.01 below 0.01). A flat-topped or height-quantised scan has
#: bins spanned by level segments alone, whose edge slope would be 0
EDGE_FLOOR = 1e-3


def _segments(h: NDArray, step: float, periodic: bool) -> tuple[NDArray, NDArray, float]:
    """``(lo, hi, total length)`` of the profiles along axis 0, piecewise linear."""
    nxt = np.roll(h, -1, 0) if periodic else h[1:]
    cur = h if periodic else h[:-1]
    lo, hi = np.minimum(cur, nxt).ravel(), np.maximum(cur, nxt).ravel()
    return lo, hi, lo.size * step


class _Profiles:
    """The share above a level and the height spans below it, for one set of profiles."""

    def __init__(self, lo: NDArray, hi: NDArray, step: float, length: float) -> None:
        span = hi - lo
        slant = span > 0
        self.flat = np.sort(lo[~slant])  # flat segments: all above a level or all below
        self.lo, self.hi = np.sort(lo[slant]), np.sort(hi[slant])
        g = step / span[slant]  # length per unit height of a slanted segment
        order_lo, order_hi = np.argsort(lo[slant]), np.argsort(hi[slant])
        self.g_lo, self.g_hi = g[order_lo], g[order_hi]
        self.step, self.length = step, length
        self.c_lo = np.concatenate([[0.0], np.cumsum(self.lo)])
        self.c_hi = np.concatenate([[0.0], np.cumsum(self.hi)])
        self.cg_lo = np.concatenate([[0.0], np.cumsum(self.g_lo)])
        self.cg_hi = np.concatenate([[0.0], np.cumsum(self.g_hi)])
        self.cgl_lo = np.concatenate([[0.0], np.cumsum(self.g_lo * self.lo)])
        self.cgh_hi = np.concatenate([[0.0], np.cumsum(self.g_hi * self.hi)])

    def spanned(self, z: NDArray) -> NDArray:
        """``sum over slanted segments of clip(z - lo, 0, hi - lo)``: heights spanned below ``z``."""
        i, j = np.searchsorted(self.lo, z), np.searchsorted(self.hi, z)
        return (z * i - self.c_lo[i]) - (z * j - self.c_hi[j])

    def share(self, z: NDArray) -> NDArray:
        """The share of the profiles' length above level ``z`` (piecewise linear profiles)."""
        i, j = np.searchsorted(self.lo, z), np.searchsorted(self.hi, z)
        # sum of g clip(z - lo, 0, hi - lo): the slanted length below z
        below = (z * self.cg_lo[i] - self.cgl_lo[i]) - (z * self.cg_hi[j] - self.cgh_hi[j])
        flat_below = self.step * np.searchsorted(self.flat, z, side="right")
        return 1.0 - (below + flat_below) / self.length


def _level(prof: _Profiles, A: NDArray, z_min: float, z_max: float) -> NDArray:
    """The bearing level of each share ``A`` (bisection on :meth:`_Profiles.share`)."""
    lo, hi = np.full(A.shape, z_min), np.full(A.shape, z_max)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        above = prof.share(mid) > A
        lo, hi = np.where(above, mid, lo), np.where(above, hi, mid)
    return 0.5 * (lo + hi)


def profile_edge_slopes(
    h: NDArray, step: float, periodic: bool, n: int = EDGE_POINTS
) -> NDArray[np.float64]:
    """The edge slope of the profiles along axis 0 of ``h`` (spacing ``step``) at ``n`` fractions.

    At ``A_i = i / (n - 1)``, averaged over the bin ``[A_i - d / 2, A_i + d / 2]`` (clipped to
    [0, 1]; ``d = 1 / (n - 1)``): ``sum of the height range the segments span in the bin's levels
    / (L dA)``. ``nan`` where the bin holds no slanted segment.
    """
    lo, hi, length = _segments(np.asarray(h, dtype=float), step, periodic)
    prof = _Profiles(lo, hi, step, length)
    d = 1.0 / (n - 1)
    centres = np.linspace(0.0, 1.0, n)
    a_top, a_bot = np.clip(centres - 0.5 * d, 0.0, 1.0), np.clip(centres + 0.5 * d, 0.0, 1.0)
    z_min, z_max = float(np.min(h)), float(np.max(h))
    z_top, z_bot = _level(prof, a_top, z_min, z_max), _level(prof, a_bot, z_min, z_max)
    dA = prof.share(z_bot) - prof.share(z_top)
    spans = prof.spanned(z_top) - prof.spanned(z_bot)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where((dA > 0) & (spans > 0), spans / (length * dA), np.nan)
    return out


def edge_slope_table(surface, n: int = EDGE_POINTS) -> tuple[float, ...]:
    """The block's ``edge_slope``: the x and y profiles' edge slopes, their quadratic mean.

    :func:`profile_edge_slopes` of both directions of a :class:`Surface` at ``n`` contact
    fractions; a fraction where a direction has no crossing takes its nearest neighbour's; at
    least :data:`EDGE_FLOOR`. ``ValueError`` for a flat surface.
    """
    h = np.asarray(surface.heights, dtype=float)
    sx = profile_edge_slopes(h, surface.dx, surface.periodic, n)
    sy = profile_edge_slopes(h.T, surface.dy, surface.periodic, n)
    out = []
    for s in (sx, sy):
        ok = np.isfinite(s)
        if not ok.any():
            s = np.zeros(n)
        else:
            idx = np.flatnonzero(ok)
            s = s[idx[np.abs(np.arange(n)[:, None] - idx[None, :]).argmin(axis=1)]]
        out.append(s)
    e = np.sqrt(0.5 * (out[0] ** 2 + out[1] ** 2))
    if not np.any(e > 0):
        raise ValueError("the workpiece has no slanted profile segment: no edge slope")
    return tuple(float(v) for v in np.maximum(e, EDGE_FLOOR))
