"""Fused element-wise passes of the normal contact CG (numba).

Each kernel replaces several NumPy passes over the grid by one compiled loop; the FFTs stay in
``scipy.fft``. Every kernel has a NumPy oracle in ``tests/test_normal.py``. Arrays are flat,
contiguous float64 (inputs typed read-only, so read-only arrays are accepted); ``pmax`` is the
hardness cap (``inf`` for elastic contact). An element is *free* when ``0 < p < pmax``.

The per-iteration loops test membership without branches: a condition is a bitwise ``&`` / ``|``
of comparisons, and a sum adds ``x * cond`` (``x`` or ``0.0``, added in the same order, so the
sums equal a branching loop's bit for bit). A contact set is a random pattern to the branch
predictor: the branching loops ran about 5x slower on a 512^2 grid half in contact (1.4 ms
against 0.26 ms a pass), which made them cost as much as the CG's FFTs (issue 39).
"""

from __future__ import annotations

import numba as nb
import numpy as np

__all__ = [
    "active_gap",
    "direction",
    "dot_free",
    "free_gap_sum",
    "gap_and_residual",
    "project_box_sum",
    "restore_load",
    "scale_free",
    "step_project",
]

_F = nb.float64
_I = nb.int64
_A = nb.float64[::1]
#: read-only input (a writable array converts to it; ``Surface.heights`` is read-only by design)
_R = nb.types.Array(nb.float64, 1, "C", readonly=True)


@nb.njit(nb.types.Tuple((_F, _I))(_R, _R, _R, _F), cache=True)
def free_gap_sum(u, h, p, pmax):
    """Sum of ``u - h`` over the free elements and their count."""
    s = 0.0
    n = 0
    for k in range(p.size):
        pk = p[k]
        free = (pk > 0.0) & (pk < pmax)
        s += (u[k] - h[k]) * free
        n += free
    return s, n


@nb.njit(nb.types.Tuple((_F, _F))(_R, _R, _R, _F, _F, _A), cache=True)
def gap_and_residual(u, h, p, pmax, shift, g):
    """Gap ``g = u - h + shift`` written to ``g``, with its KKT violation.

    Returns the sum of squares of the violation (``g`` free, ``min(g, 0)`` at ``p = 0``,
    ``max(g, 0)`` at ``p = pmax``) and ``G = sum_free g^2``.
    """
    viol = 0.0
    G = 0.0
    for k in range(p.size):
        gk = u[k] - h[k] + shift
        g[k] = gk
        pk = p[k]
        free = (pk > 0.0) & (pk < pmax)
        bad = free | ((pk <= 0.0) & (gk < 0.0)) | ((pk >= pmax) & (gk > 0.0))
        g2 = gk * gk
        viol += g2 * bad
        G += g2 * free
    return viol, G


@nb.njit(_F(_R, _R, _R, _F, _F, _A), cache=True)
def direction(z, g, p, pmax, beta, t):
    """Load-neutral conjugate direction, in place.

    ``t = z + beta t`` on free elements, 0 elsewhere, then minus its mean over the free
    elements (``z`` is the gap ``g`` or its preconditioned version). Returns ``sum_free g t``.
    """
    s = 0.0
    n = 0
    for k in range(p.size):
        pk = p[k]
        free = (pk > 0.0) & (pk < pmax)
        tk = (z[k] + beta * t[k]) * free
        t[k] = tk
        s += tk
        n += free
    m = s / n if n > 0 else 0.0
    gt = 0.0
    for k in range(p.size):
        pk = p[k]
        free = (pk > 0.0) & (pk < pmax)
        tk = t[k] - m * free
        t[k] = tk
        gt += (g[k] * tk) * free
    return gt


@nb.njit(
    nb.types.Tuple((nb.boolean, nb.boolean, _F, _F, _I))(_R, _R, _R, _R, _F, _F, _A), cache=True
)
def step_project(p, t, g, d, tau, pmax, q):
    """Projected CG step ``q = clip(p - tau t, 0, pmax)``, releasing bound elements.

    Bound elements whose gap ``g`` asks them to leave the bound get ``q = p - tau d`` (clipped),
    with ``d`` the (preconditioned) gap.

    Returns ``(any_release, changed, sum_free, max_free, n_cap)``: whether a bound element was
    released, whether ``q`` differs from ``p - tau t`` anywhere, the sum and the maximum of ``q``
    over its free elements and the number of elements of ``q`` at the cap.
    """
    released = False
    changed = False
    sfree = 0.0
    mfree = 0.0
    ncap = 0
    for k in range(p.size):
        pk = p[k]
        gk = g[k]
        raw = pk - tau * t[k]
        rel = ((pk <= 0.0) & (gk < 0.0)) | ((pk >= pmax) & (gk > 0.0))
        qk = (pk - tau * d[k]) if rel else raw
        released |= rel
        qk = 0.0 if qk < 0.0 else qk
        qk = pmax if qk > pmax else qk
        changed |= qk != raw
        q[k] = qk
        ncap += qk >= pmax
        free = (qk > 0.0) & (qk < pmax)
        sfree += qk * free
        qf = qk * free
        mfree = qf if qf > mfree else mfree
    return released, changed, sfree, mfree, ncap


@nb.njit(nb.void(_A, _F, _F), cache=True)
def scale_free(q, c, pmax):
    """Multiply the free elements of ``q`` by ``c`` in place (caller ensures ``c q < pmax``)."""
    for k in range(q.size):
        qk = q[k]
        q[k] = c * qk if (qk > 0.0) & (qk < pmax) else qk


@nb.njit(nb.void(_R, _R, _F, _A), cache=True)
def active_gap(g, p, pmax, out):
    """``out = g`` on free elements and on bound elements whose gap violates the bound, else 0."""
    for k in range(p.size):
        pk = p[k]
        gk = g[k]
        keep = ((pk > 0.0) & (pk < pmax)) | ((pk <= 0.0) & (gk < 0.0)) | ((pk >= pmax) & (gk > 0.0))
        out[k] = gk if keep else 0.0


@nb.njit(_F(_R, _R, _R, _F), cache=True)
def dot_free(a, b, p, pmax):
    """``sum_free a b``."""
    s = 0.0
    for k in range(p.size):
        pk = p[k]
        s += (a[k] * b[k]) * ((pk > 0.0) & (pk < pmax))
    return s


@nb.njit(nb.types.Tuple((nb.boolean, _F, _I))(_A, _F, _F), cache=True)
def restore_load(q, target, pmax):
    """Scale the sub-cap pressures of ``q`` so that ``sum(q) = target`` with ``q <= pmax``, in place.

    Elements at the cap stay there; positive ones below it are multiplied by one factor ``c``,
    and those that would pass ``pmax`` are capped (water filling: ``c`` grows as the capped set
    grows, so the capped set is ``{q >= pmax / c}`` of the input). Returns ``(ok, c, passes)``;
    ``ok`` is False, and ``q`` untouched, when even the capped support cannot carry ``target``,
    nothing below the cap is positive, or ``c`` underflows to 0. ``passes == 1``: nothing new was capped.
    """
    thr = pmax
    passes = 0
    while True:
        passes += 1
        ncap = 0
        sfree = 0.0
        mfree = 0.0
        for k in range(q.size):
            qk = q[k]
            if qk >= thr:
                ncap += 1
            elif qk > 0.0:
                sfree += qk
                if qk > mfree:
                    mfree = qk
        rest = target - (pmax * ncap if ncap > 0 else 0.0)
        if not (rest > 0.0 and sfree > 0.0):
            return False, 0.0, passes
        c = rest / sfree
        if not c > 0.0:
            return False, 0.0, passes  # underflow: a tiny target on a large support
        if c * mfree < pmax:
            break
        # the elements that pass the cap at this c, at least the largest free one: in floating
        # point c * mfree >= pmax does not imply pmax / c <= mfree (1 ulp), and without the
        # min the capped set stayed the same and the loop never ended (sur-3 at 48^2)
        thr = min(pmax / c, mfree)
    for k in range(q.size):
        qk = q[k]
        if qk >= thr:
            q[k] = pmax
        elif qk > 0.0:
            q[k] = c * qk
    return True, c, passes


@nb.njit(nb.void(_R, _F, _F, _A), cache=True)
def project_box_sum(y, target, pmax, out):
    """Euclidean projection of ``y`` onto ``{0 <= p <= pmax, sum(p) = target}``, into ``out``.

    ``out = clip(y - max(y) + lam, 0, pmax)`` with the scalar ``lam`` solving the monotone,
    piecewise linear ``sum(clip(...)) = target`` by safeguarded Newton steps (exact once the
    free set stops changing) inside a bisection bracket; the rounding error of the sum is put
    on the free elements. The shift by ``max(y)`` keeps a tiny target next to large ``y`` from
    being lost to cancellation. The caller ensures ``target < size * pmax``.
    """
    n = y.size
    ymax = -np.inf
    ymin = np.inf
    ysum = 0.0
    for k in range(n):
        yk = y[k]
        if yk > ymax:
            ymax = yk
        if yk < ymin:
            ymin = yk
    for k in range(n):
        ysum += y[k] - ymax
    ymin -= ymax
    lo = 0.0  # -(max of the shifted y)
    hi = (target / n if pmax == np.inf else pmax) - ymin
    lam = target / n - ysum / n
    for _ in range(200):
        S = 0.0
        nfree = 0
        ncap = 0
        yfree = 0.0
        for k in range(n):
            zk = (y[k] - ymax) + lam
            if zk >= pmax:
                S += pmax
                ncap += 1
            elif zk > 0.0:
                S += zk
                nfree += 1
                yfree += y[k] - ymax
        if S == target:
            break
        if S < target:
            lo = lam
        else:
            hi = lam
        at_cap = ncap * pmax if ncap > 0 else 0.0
        step = (target - at_cap - yfree) / nfree if nfree > 0 else np.inf
        if step == lam:
            break  # the root of this piece is lam itself: exact up to rounding
        lam = step if lo < step < hi else 0.5 * (lo + hi)
        if hi - lo <= 1e-15 * max(abs(lo), abs(hi), 1e-300):
            break
    s = 0.0
    nfree = 0
    for k in range(n):
        v = (y[k] - ymax) + lam
        if v <= 0.0:
            v = 0.0
        elif v >= pmax:
            v = pmax
        else:
            nfree += 1
        out[k] = v
        s += v
    if nfree > 0:
        d = (target - s) / nfree
        for k in range(n):
            if 0.0 < out[k] < pmax:
                out[k] += d
