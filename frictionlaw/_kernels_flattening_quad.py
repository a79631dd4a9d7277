"""Numba kernels of the flattening's integrals (private): Eq. F4's two integrals and their rules.

The strain integral of Eq. F4 and the consistent tangent's integral over an interval of
``v`` (``t = p cosh v``), summed by Gauss-Legendre panels, split where the integrand is not
smooth: at a tabulated first loading's levels (its slope has kinks there) and where Eq. F2c's
limit on the lattice's rate starts to act (:func:`flat_switch`: the strain integral's integrand
has a kink there and the tangent's a jump). Also the inverse of ``alpha1`` the update needs.
The kernels that use them are :mod:`frictionlaw._kernels_flattening`'s; the NumPy reference
is :mod:`frictionlaw.flattening` (docs/flattening.md, F4 and F6). Every kernel has an explicit
signature, ``cache=True`` and no ``fastmath``.
"""

import math

import numba as nb
import numpy as np
from numba import float64, types

from ._kernels import first_offset, first_scalar
from ._kernels_branches import _RO, _opts

__all__ = [
    "alpha1_inverse",
    "flat_weight",
    "flat_rate",
    "flat_switch",
    "flat_panels",
    "flat_quad",
    "flat_kinked",
]

#: Gauss-Legendre nodes and weights of the 2-, 4- and 8-point rules, one after the other
_GX, _GW = (
    np.ascontiguousarray(np.concatenate(r))
    for r in zip(*(np.polynomial.legendre.leggauss(m) for m in (2, 4, 8)), strict=True)
)
_WIDTH = 0.5  # the widest panel in v, as the reference's
_NARROW = (7e-4, 0.05)  # the widest interval of the 2- and of the 4-point rule


@nb.jit(float64(_RO, float64, float64, float64), **_opts)
def alpha1_inverse(c1, a, lo, hi):
    """The pressure ``P`` in ``[lo, hi]`` with ``alpha1(P) = a`` (``c1``: ``tau_max = 1``).

    ``alpha1(lo) < a``; ``hi`` where ``alpha1(hi) <= a``. Safeguarded Newton in ``ln P`` on
    ``ln alpha1`` (concave for Eq. 24, so from below it stays below), bisection in ``ln P`` where
    a step leaves the bracket; to 1e-15 in ``ln P``.
    """
    if not a < first_scalar(c1, hi)[0]:
        return hi
    ln_a = math.log(a)
    ylo = math.log(lo)
    yhi = math.log(hi)
    y = ylo
    for it in range(200):
        P = math.exp(y)
        al, d = first_scalar(c1, P)
        if not al > 0.0:
            g = -math.inf
        else:
            g = math.log(al) - ln_a
        if g == 0.0:
            return P
        if g < 0.0:
            ylo = y
        else:
            yhi = y
        s = P * d / al if al > 0.0 else 0.0
        yn = y - g / s if s > 0.0 else math.nan
        if abs(yn - y) <= 1e-15 * (1.0 + abs(y)):  # converged: the rest is below rounding
            return math.exp(yn)
        if not (ylo < yn < yhi) or it % 8 == 7:
            yn = 0.5 * (ylo + yhi)
        if abs(yn - y) <= 1e-15 * (1.0 + abs(y)) or yhi - ylo <= 1e-15 * (1.0 + abs(yhi)):
            return math.exp(yn)
        y = yn
    return math.exp(y)


@nb.jit(float64(float64, float64, float64, float64), **_opts)
def flat_weight(g, ch, sh, cl):
    """``W = 1 + g cosh v sinh v c_L``: the lattice's rate over the layer's in Eq. F4's integrand."""
    return 1.0 + g * ch * sh * cl


@nb.jit(types.UniTuple(float64, 2)(float64, float64, float64), **_opts)
def flat_rate(m, a, cmax):
    """The lattice's rate at the fraction ``a`` and the weight of its term in the tangent.

    ``(c_L, 1)`` with ``c_L = 1 + m (1 - a)`` (``m = tan(theta)``; a function of ``t = p cosh v``
    through ``a``), or ``(cmax (1 - a), 0)`` where the hardening limits it (Eq. F2c: ``cmax = 6 p
    / h``; ``p`` times a function of ``t``, whose tangent has no such term; docs/flattening.md,
    F6). ``cmax`` infinite: no limit.
    """
    cl = 1.0 + m * (1.0 - a)
    if cmax < math.inf and cl > cmax * (1.0 - a):
        return cmax * (1.0 - a), 0.0
    return cl, 1.0


@nb.jit(
    types.UniTuple(float64, 2)(_RO, float64, float64, float64, float64, float64, float64), **_opts
)
def flat_panels(c1, p, ua, ub, g, slope, cmax):
    """The two integrals of :func:`flat_quad` over ``ua..ub`` where the integrand is smooth.

    ``g = p / s0``, ``slope = tan(theta)`` and the hardening's limit ``cmax`` on the lattice's
    rate (Eq. F2c, per unit ``1 - A``; ``inf``: none) set ``W`` (:func:`flat_weight`). Where the
    limit acts the lattice's rate is ``cmax (1 - alpha1(t))``, ``cmax = 6 p / h``: ``p`` times a
    function of ``t``, and the tangent's integrand is ``alpha1' cosh v / W^2`` there
    (docs/flattening.md, F6).

    Gauss-Legendre on equal panels no wider than 0.5 in ``v``: 8 nodes a panel, 4 on an
    interval narrower than 0.05 and 2 below 7e-4 (the Newton corrections), each within about
    1e-13 of the panel's integral for an integrand whose derivatives grow as ``6^k``.
    """
    span = ub - ua
    n = max(1, int(math.ceil(abs(span) / _WIDTH)))
    h = span / n
    if abs(h) <= _NARROW[0]:
        k0, m = 0, 2
    elif abs(h) <= _NARROW[1]:
        k0, m = 2, 4
    else:
        k0, m = 6, 8
    s1 = 0.0
    s2 = 0.0
    for k in range(n):
        mid = ua + (k + 0.5) * h
        for j in range(k0, k0 + m):
            v = mid + 0.5 * h * _GX[j]
            ch = math.cosh(v)
            sh = math.sinh(v)
            a, d = first_scalar(c1, p * ch)
            cl, lim = flat_rate(slope, a, cmax)
            w = flat_weight(g, ch, sh, cl)
            s1 += _GW[j] * (d * ch * sh * sh / w)
            s2 += _GW[j] * (d * ch * (1.0 - lim * g * cl * ch * sh * sh * sh) / (w * w))
    return 0.5 * h * s1, 0.5 * h * s2


@nb.jit(float64(_RO, float64, float64, float64, float64, float64), **_opts)
def flat_switch(c1, p, P0, cap, m, cmax):
    """``v`` where Eq. F2c's limit starts to act on the way from ``P0`` up (``t = p cosh v``).

    The limit ``cmax (1 - A)`` falls below the lattice's ``1 + m (1 - A)`` where ``(1 - A)
    (cmax - m) < 1``: above ``A_c = 1 - 1 / (cmax - m)``, everywhere for ``cmax <= m + 1``.
    There the strain integral's integrand has a kink and the tangent's a jump, which the panels
    must not straddle. ``inf`` where the limit acts nowhere (``cmax`` infinite), from ``P0`` on
    or only beyond ``cap``.
    """
    if not (cmax < math.inf and cmax > m + 1.0):
        return math.inf
    ac = 1.0 - 1.0 / (cmax - m)
    if not ac > first_scalar(c1, P0)[0]:
        return math.inf
    tc = alpha1_inverse(c1, ac, P0, cap)
    if not tc < cap:
        return math.inf
    return math.acosh(tc / p)


@nb.jit(
    types.UniTuple(float64, 2)(_RO, float64, float64, float64, float64, float64, float64), **_opts
)
def flat_kinked(c1, p, lo, hi, g, m, cmax):
    """:func:`flat_quad`'s two integrals over ``lo..hi``, ``lo <= hi``, split at ``alpha1``'s kinks.

    Eq. 24's ``alpha1'`` is smooth: :func:`flat_panels` over the interval. The tabulated first
    loading's is continuous with kinks in its slope at the levels and where its top extension
    reaches a contact fraction of 1: the interval is split there (at ``v = acosh(p_j / p)``) and
    each piece summed by :func:`flat_panels`.
    """
    f0 = first_offset(c1)
    if f0 < 0:
        return flat_panels(c1, p, lo, hi, g, m, cmax)
    nj = int(c1[f0 + 1])
    H = c1[1]
    s1 = 0.0
    s2 = 0.0
    a = lo
    for j in range(nj + 1):
        if j < nj:
            tk = H * math.exp(c1[f0 + 2 + j])
        else:  # where the top level's power law reaches ln alpha = 0
            dtop = c1[f0 + 1 + 3 * nj]
            if not dtop > 0.0:
                break
            tk = H * math.exp(c1[f0 + 1 + nj] - c1[f0 + 1 + 2 * nj] / dtop)
        if not tk > p:
            continue
        vk = math.acosh(tk / p)
        if vk >= hi:
            break
        if vk > a:
            r1, r2 = flat_panels(c1, p, a, vk, g, m, cmax)
            s1 += r1
            s2 += r2
            a = vk
    r1, r2 = flat_panels(c1, p, a, hi, g, m, cmax)
    return s1 + r1, s2 + r2


@nb.jit(
    types.UniTuple(float64, 2)(_RO, float64, float64, float64, float64, float64, float64, float64),
    **_opts,
)
def flat_quad(c1, p, ua, ub, g, m, cmax, vc):
    """The strain integral of Eq. F4 and the tangent's integral over ``ua..ub``.

    ``(int alpha1' cosh v sinh(v)^2 / W dv, int alpha1' cosh v (1 - g c_L cosh v sinh(v)^3) /
    W^2 dv)`` over ``ua..ub``, ``alpha1'`` at ``p cosh v``, ``W`` of :func:`flat_weight` with
    ``g = p / s0`` and ``c_L = min(1 + m (1 - alpha1), cmax (1 - alpha1))``, ``m = tan(theta)``
    (the second where the hardening limits it, Eq. F2c, the second integrand ``alpha1' cosh v /
    W^2`` there). Both integrals at once (the second is the tangent's, Eq. F6's ``d p_f / d p``
    at a fixed ``s0``); ``ub < ua`` gives their negatives. Split at ``vc``, where the limit
    starts to act (:func:`flat_switch`; ``inf``: nowhere), and at a tabulated first loading's
    kinks (:func:`flat_kinked`).
    """
    sign = 1.0
    lo = ua
    hi = ub
    if hi < lo:
        sign = -1.0
        lo = ub
        hi = ua
    if lo < vc < hi:
        s1, s2 = flat_kinked(c1, p, lo, vc, g, m, cmax)
        r1, r2 = flat_kinked(c1, p, vc, hi, g, m, cmax)
        return sign * (s1 + r1), sign * (s2 + r2)
    s1, s2 = flat_kinked(c1, p, lo, hi, g, m, cmax)
    return sign * s1, sign * s2
