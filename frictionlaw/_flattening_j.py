"""The ``J`` integral of Eq. F4 and its inversion (private): the NumPy model's quadrature.

``J(p, p_f) = p^3 int_0^u alpha1'(p cosh v) cosh v sinh(v)^2 / W dv`` (``p_f = p cosh u``),
summed by composite Gauss-Legendre, split at a tabulated first loading's kinks and where Eq.
F2c's limit on the lattice's rate starts to act, and solved for ``u`` by safeguarded Newton;
:mod:`frictionlaw.flattening` builds Eqs. F4 and F6 on it, the kernels
(:mod:`frictionlaw._kernels_flattening_quad`) sum the same integrals node by node.
"""

import math
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from . import _codes as K
from ._flattening_rates import lattice_sink_rate, limit_at
from .law import evaluate

#: Gauss-Legendre nodes per panel of the ``J`` integral (F4), at least ``_PANELS`` panels and
#: none wider than ``_WIDTH`` in ``u``: within 1e-9 of adaptive quadrature (the test's tolerance;
#: 1e-13 typical) over ``p / H`` 1e-3 to 0.9 and ``p_f / p`` up to 4 (tests/test_flattening.py)
_PANELS, _NODES, _WIDTH = 16, 8, 0.5
_GX, _GW = np.polynomial.legendre.leggauss(_NODES)


@lru_cache(maxsize=64)
def _rule(panels: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Composite Gauss-Legendre nodes and weights on ``[0, 1]`` with ``panels`` equal panels."""
    e = np.linspace(0.0, 1.0, panels + 1)
    x = ((e[:-1, None] + e[1:, None]) / 2 + np.diff(e)[:, None] / 2 * _GX).ravel()
    return x, (np.diff(e)[:, None] / 2 * _GW).ravel()


# ----------------------------------------------------------------------------- equations
def _panels(u_max: float, kinked: bool = False) -> int:
    """Panels of the ``J`` sum up to ``u_max``: at least ``_PANELS``, none wider than ``_WIDTH``.

    ``kinked``: the kinks of a tabulated ``alpha1`` split the interval as well, and half the
    floor does (the width rule stays), so that the split costs little more than the plain sum.
    """
    return max(_PANELS // 2 if kinked else _PANELS, math.ceil(u_max / _WIDTH))


def _j_integral(
    ph: NDArray,
    u: NDArray,
    coeffs: NDArray,
    H: float,
    g: NDArray,
    slope: float,
    c_max: NDArray,
    panels: int | None = None,
    kinks: NDArray | None = None,
    vc: NDArray | None = None,
) -> NDArray[np.float64]:
    """``J / H^2`` of Eq. F4 up to ``p_f = p cosh(u)``, pressures in units of ``H`` (``ph``).

    ``t = p cosh(v)`` turns ``J`` into ``p^3 int_0^u alpha1'(t) cosh v sinh(v)^2 / W dv`` with
    ``W = 1 + g cosh v sinh v min(c_L(A), c_max (1 - A))``, ``A = alpha1(t)``, ``g = p / s0``,
    ``c_max`` the hardening's limit of Eq. F2c per unit ``1 - A`` (``inf``: none): a smooth
    integrand but for a kink where the limit starts to act, at ``v = vc`` of each row (``inf``:
    nowhere), summed by composite Gauss-Legendre (``_NODES`` per panel, at least ``_PANELS``
    panels, none wider than ``_WIDTH``) split there; a solve passes one ``panels`` for all its
    calls, so that ``J`` is one function of ``u`` throughout. ``kinks`` (:func:`_kinks`,
    pressures in units of ``H``): a tabulated ``alpha1``'s slope jumps there, and the panels are
    split at them, as the kernels split.
    """
    kinked = kinks is not None and kinks.size > 0
    switch = vc is not None and bool(np.any((vc > 0.0) & (vc < u)))
    if panels is None:
        panels = _panels(float(u.max(initial=0.0)), kinked)
    if not (kinked or switch):
        x, w = _rule(panels)
        v = u[:, None] * x[None, :]
        f = _j_integrand(ph, v, coeffs, H, g, slope, c_max)
        return ph**3 * u * (f @ w)
    edges = u[:, None] * np.linspace(0.0, 1.0, panels + 1)[None, :]
    if kinks is not None and kinked:
        edges = _split_at_kinks(edges, ph, u, kinks)
    if vc is not None and switch:  # an empty segment at 0 or u where a row's switch lies outside
        edges = np.sort(np.concatenate([edges, np.clip(vc, 0.0, u)[:, None]], axis=1), axis=1)
    half = np.diff(edges, axis=1)[:, :, None] / 2
    v = ((edges[:, :-1, None] + edges[:, 1:, None]) / 2 + half * _GX).reshape(len(ph), -1)
    f = _j_integrand(ph, v, coeffs, H, g, slope, c_max)
    return ph**3 * np.sum(f * (half * _GW).reshape(len(ph), -1), axis=1)


def _split_at_kinks(edges: NDArray, ph: NDArray, u: NDArray, kinks: NDArray) -> NDArray:
    """``edges`` (a row per pressure ``ph``, from 0 to ``u``) with each row's kinks, sorted.

    A kink ``t_k`` (units of ``H``) lies at ``v_k = acosh(t_k / p)`` of row ``p``: every segment
    between the result's edges is then one where ``alpha1'`` is smooth (the kernels split there
    too). Kinks outside every row's ``0..u`` split nothing and are left out; inside some rows,
    they end empty segments in the others.
    """
    with np.errstate(invalid="ignore"):
        vk = np.arccosh(np.maximum(kinks[None, :] / ph[:, None], 1.0))
    vk = vk[:, ((vk > 0.0) & (vk < u[:, None])).any(axis=0)]
    return np.sort(np.concatenate([edges, np.minimum(vk, u[:, None])], axis=1), axis=1)


def _j_integrand(ph, v, coeffs, H, g, slope, c_max):
    """``alpha1'(p cosh v) H cosh v sinh(v)^2 / W`` (F4 in ``v``; ``ph``, ``g``, ``c_max``: rows)."""
    ch, sh = np.cosh(v), np.sinh(v)
    a, d = evaluate(K.CODE_SBMF, coeffs, ph[:, None] * ch * H, 0.0)
    c = np.minimum(lattice_sink_rate(np.asarray(a), slope), limit_at(c_max[:, None], a))
    W = 1.0 + g[:, None] * ch * sh * c
    return np.asarray(d) * H * ch * sh**2 / W


def _solve_j(ph, target, lo, hi, jx, panels):
    """``u`` in ``[lo, hi]`` with ``J(u) = target`` (``hi`` where ``J(hi) <= target``).

    Safeguarded Newton in ``u`` (``dJ/du``: :func:`_j_integrand` times ``p^3``), bisection where
    the step leaves the bracket and every fifth step (so that the bracket shrinks even
    where rounding makes Newton circle the root); ``J`` increases with ``u``.
    """
    lo, hi = lo.copy(), hi.copy()
    coeffs, H, g, slope, c_max, kinks, vc = jx
    full = _j_integral(ph, hi, coeffs, H, g, slope, c_max, panels, kinks, vc) <= target
    u = np.where(full, hi, 0.5 * (lo + hi))
    act = ~full
    for it in range(300):
        if not act.any():
            break
        ua = u[act]
        ga, ca = g[act], c_max[act]
        J = _j_integral(ph[act], ua, coeffs, H, ga, slope, ca, panels, kinks, vc[act])
        dJ = ph[act] ** 3 * _j_integrand(ph[act], ua[:, None], coeffs, H, ga, slope, ca)[:, 0]
        below = J < target[act]
        la, ha = np.where(below, ua, lo[act]), np.where(below, hi[act], ua)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = ua - (J - target[act]) / dJ
        bad = ~np.isfinite(step) | (step <= la) | (step >= ha) | (it % 5 == 4)
        hit = np.abs(J - target[act]) <= 4e-16 * np.abs(target[act])  # ua is the root
        new = np.where(hit, ua, np.where(bad, 0.5 * (la + ha), step))
        done = hit | (np.abs(new - ua) <= 1e-14 * (1.0 + ua)) | (ha - la <= 1e-14 * (1.0 + ha))
        lo[act], hi[act], u[act] = la, ha, new
        idx = np.flatnonzero(act)
        act[idx[done]] = False
    if act.any():  # every fifth step halves a bracket of at most ~60: unreachable, said if not
        raise RuntimeError(f"flattening: the J inversion did not converge at {act.sum()} nodes")
    return u
