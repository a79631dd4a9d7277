"""Many points of constant-pressure flattening curves at once: one curve per distinct pressure.

:func:`frictionlaw.flattening_curve` solves Eq. F4 for every point on its own: a Newton
iteration whose every step sums ``J`` from 0 (docs/flattening.md). A fit of ``beta`` to a lab
sheet of thousands of rows runs that dozens of times. Here the work is done once per distinct
pressure, and a point costs a few polynomial evaluations:

* :class:`FlatteningCurves`, at a constant flow stress: ``J(p, p cosh u) / p^3`` is summed once
  per pressure over segments of ``u`` (at most :data:`SEGMENT_WIDTH` wide, split at the kinks of a
  tabulated ``alpha1``, 8 Gauss-Legendre nodes each, the nodes of the runtime's own ``J``
  integral); a point finds its segment in the running sums and solves the rest in it, on the
  degree-7 Legendre interpolant of the integrand at those nodes. ``beta`` only scales the strain
  axis (Eq. F4), so one table serves every trial ``beta`` of a fit.
* :class:`FlatteningPaths`, along a flow curve: each distinct pressure is integrated once along
  its strains (Eq. F6 step by step, the flow stress and hardening modulus of each step's middle,
  as a host passes them increment by increment), on :data:`PATH_STEPS` steps graded toward zero
  strain plus the points of a tabulated curve; a point is one more step from the node below it.

Both give what :func:`~frictionlaw.flattening_curve` gives: without a flow curve to rounding
(``J`` by two quadratures of ``1e-13`` typical error, tests/test_flattening_curves.py), along a
flow curve the same integral of Eq. F3 on a finer grid than its ``steps`` midpoint steps per
point (closer to the converged curve, the test says how close).
"""

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._flattening_j import _GW, _GX, _j_integrand, _split_at_kinks
from ._flattening_rates import lattice_hardening_factor
from ._flattening_runs import running_max, strain_runs
from .flattening import (
    P_MIN_RATIO,
    _coeffs,
    _flattening_of,
    _kinks,
    _p_cap,
    _s0,
    _sinking_bound,
    _strain_scale,
    flattening_pressure,
)
from .law import alpha_first, broadcast_named

if TYPE_CHECKING:
    from .flow_curve import FlowCurve
    from .params import FrictionParams

__all__ = ["FlatteningCurves", "FlatteningPaths", "SEGMENT_WIDTH", "PATH_STEPS"]

#: widest segment of ``u`` (``p_f = p cosh u``) the integrand is interpolated on: the degree-7
#: interpolant's error is below 1e-13 of ``J`` there (tests/test_flattening_curves.py)
SEGMENT_WIDTH = 0.05
#: steps of a pressure's path along a flow curve (graded, :class:`FlatteningPaths`), besides
#: the points of a tabulated curve
PATH_STEPS = 256
#: the paths' grading: the first of ``steps`` steps is about ``ln(1 + R) / (R steps)`` of the
#: largest strain, a step a fixed fraction ``ln(1 + R) / steps`` of ``a`` plus its strain
_GRADING = 100.0
#: nodes evaluated at once while a table is built (bounds the memory: about 8 arrays of it)
_CHUNK = 1 << 20

# Legendre coefficients of the degree-7 interpolant from its values at the 8 Gauss nodes
# (c_m = (2m + 1) / 2 sum_q w_q P_m(x_q) f_q), and of its integral from -1 (degree 8)
_PROJ = ((2 * np.arange(8) + 1) / 2)[:, None] * (
    np.polynomial.legendre.legvander(_GX, 7) * _GW[:, None]
).T
_INT = np.stack([np.polynomial.legendre.legint(np.eye(8)[m], lbnd=-1.0) for m in range(8)], axis=1)


def _legendre(s: NDArray, degree: int) -> NDArray[np.float64]:
    """``P_0 .. P_degree`` at ``s`` (rows of the result), Bonnet's recurrence."""
    out = np.empty((degree + 1, s.size))
    out[0] = 1.0
    out[1] = s
    for n in range(1, degree):
        out[n + 1] = ((2 * n + 1) * s * out[n] - n * out[n - 1]) / (n + 1)
    return out


class _Grid:
    """The segments of ``u`` per distinct pressure and the integrand on them.

    ``ph`` the distinct pressures in units of ``H`` (all between ``P_MIN_RATIO`` and the cap),
    ``edges[j]`` the segments' ends from 0 to ``ucap[j] = acosh(cap / p_j)``, nondecreasing (a
    tabulated ``alpha1``'s kinks are ends; kinks outside a pressure's range end empty segments).
    """

    def __init__(self, ph: NDArray, params: "FrictionParams", cap: float) -> None:
        self.params, self.H, self.coeffs = params, params.H, _coeffs(params)
        self.slope = _flattening_of(params).slope
        self.ph = ph
        self.ucap = np.arccosh(cap / (ph * self.H))
        m = max(1, math.ceil(float(self.ucap.max(initial=0.0)) / SEGMENT_WIDTH))
        edges = self.ucap[:, None] * np.linspace(0.0, 1.0, m + 1)[None, :]
        kinks = _kinks(params, cap)
        if kinks is not None and kinks.size:
            edges = _split_at_kinks(edges, ph, self.ucap, kinks)
        self.edges = edges

    def samples(self, j: NDArray, seg: NDArray, g: NDArray, c_max: NDArray) -> NDArray:
        """The integrand (:func:`_j_integrand`) at the 8 nodes of segment ``seg`` of pressure ``j``.

        One row per item, ``g = p / s0`` and ``c_max`` (Eq. F2c) the item's; ``(n, 8)``.
        """
        a, b = self.edges[j, seg], self.edges[j, seg + 1]
        v = (a + b)[:, None] / 2 + (b - a)[:, None] / 2 * _GX[None, :]
        return _j_integrand(self.ph[j], v, self.coeffs, self.H, g, self.slope, c_max)

    def totals(self, g: NDArray, c_max: NDArray) -> NDArray[np.float64]:
        """``int f`` over every segment of every pressure, ``(n_p, n_segments)``, in chunks."""
        n, k = self.edges.shape[0], self.edges.shape[1] - 1
        out = np.empty((n, k))
        per = max(1, _CHUNK // (8 * k))
        for lo in range(0, n, per):
            j = np.arange(lo, min(n, lo + per))
            jj, ss = np.repeat(j, k), np.tile(np.arange(k), j.size)
            f = self.samples(jj, ss, np.repeat(g[j], k), np.repeat(c_max[j], k))
            w = self.edges[jj, ss + 1] - self.edges[jj, ss]
            out[j] = (w / 2 * (f @ _GW)).reshape(j.size, k)
        return out

    def solve(self, j, seg, rest, g, c_max, f=None) -> NDArray[np.float64]:
        """``u`` in segment ``seg`` of pressure ``j`` where ``int f`` from its start is ``rest``.

        Newton on the Legendre interpolant's integral in ``s`` (``[-1, 1]`` over the segment),
        bisection where a step leaves the bracket; ``rest`` at most the segment's integral.
        ``f``: the segment's :meth:`samples` if at hand.
        """
        a, b = self.edges[j, seg], self.edges[j, seg + 1]
        half = (b - a) / 2
        f = self.samples(j, seg, g, c_max) if f is None else f
        c = f @ _PROJ.T  # (n, 8) Legendre coefficients
        d = c @ _INT.T  # (n, 9): the integral from s = -1
        total = half * d.sum(axis=1)  # P_m(1) = 1
        frac = np.clip(np.divide(rest, total, out=np.zeros_like(rest), where=total > 0), 0, 1)
        # J ~ u^3 from u = 0 (the integrand ~ v^2): a cube root starts the first segment
        s = np.where(a == 0.0, 2.0 * np.cbrt(frac) - 1.0, 2.0 * frac - 1.0)
        lo, hi = np.full(s.size, -1.0), np.ones(s.size)
        act = (half > 0) & (frac > 0) & (frac < 1)
        for _ in range(100):
            if not act.any():
                break
            sa = s[act]
            P = _legendre(sa, 8)
            F = half[act] * np.einsum("ij,ji->i", d[act], P) - rest[act]
            dF = half[act] * np.einsum("ij,ji->i", c[act], P[:8])
            below = F < 0
            la, ha = np.where(below, sa, lo[act]), np.where(below, hi[act], sa)
            with np.errstate(divide="ignore", invalid="ignore"):
                step = sa - F / dF
            bad = ~np.isfinite(step) | (step <= la) | (step >= ha)
            new = np.where(bad, 0.5 * (la + ha), step)
            hit = np.abs(F) <= 4e-16 * (np.abs(rest[act]) + total[act])
            new = np.where(hit, sa, new)
            done = hit | (np.abs(new - sa) <= 1e-14) | (ha - la <= 1e-14)
            lo[act], hi[act], s[act] = la, ha, new
            act[np.flatnonzero(act)[done]] = False
        if act.any():  # a bracket halved 100 times is below rounding: unreachable
            raise RuntimeError(f"flattening: the segment solve did not converge at {act.sum()}")
        s = np.where(frac >= 1, 1.0, np.where(frac <= 0, -1.0, s))
        return a + (s + 1.0) * half


def _search(table: NDArray, j: NDArray, x: NDArray) -> NDArray[np.intp]:
    """Per item the last column ``k < table.shape[1] - 1`` of row ``j`` with ``table[j, k] <= x``.

    Rows nondecreasing, ``table[j, 0] <= x``: a bisection over all items at once.
    """
    lo, hi = np.zeros(x.size, dtype=np.intp), np.full(x.size, table.shape[1] - 1, dtype=np.intp)
    while np.any(hi - lo > 1):
        mid = (lo + hi) // 2
        right = table[j, mid] <= x
        lo, hi = np.where(right, mid, lo), np.where(right, hi, mid)
    return lo


def _prepare(p: ArrayLike, strains: ArrayLike, params: "FrictionParams"):
    """Checked flat pressures and strains, the cap, the distinct flattening pressures.

    Returns ``(shape, p, eps, cap, levels, j, go)``: ``levels`` the distinct pressures between
    ``P_MIN_RATIO H`` and the cap (the others never flatten), ``j`` each point's index into them,
    ``go`` the points that flatten at all.
    """
    _flattening_of(params)
    p, eps = broadcast_named(p=p, strains=strains)
    if not (np.all(np.isfinite(p)) and np.all(p > 0)):
        raise ValueError("p must be finite and > 0 (Pa)")
    if not (np.all(np.isfinite(eps)) and np.all(eps >= 0)):
        raise ValueError("strains must be finite and >= 0")
    shape, pf, ef = p.shape, p.ravel(), eps.ravel()
    cap = _p_cap(params, _coeffs(params))
    live = (pf > P_MIN_RATIO * params.H) & (pf < cap)
    levels, j = np.unique(np.where(live, pf, cap), return_inverse=True)
    keep = levels < cap
    remap = np.cumsum(keep) - 1
    return shape, pf, ef, cap, levels[keep], remap[j], live


class FlatteningCurves:
    """The contact fraction of a virgin surface after bulk strain at given constant pressures.

    What :func:`~frictionlaw.flattening_curve` gives for ``(p, strains)`` with ``params`` at its
    flow stress (no hardening modulus), to rounding, with the work done once per distinct
    pressure: build it for the points' pressures, then :meth:`alpha` for their strains, as often
    as needed (a fit of ``beta``: each trial ``beta`` scales the strain axis, Eq. F4).

    Parameters
    ----------
    p : array_like
        Contact pressure of each point (Pa), ``> 0``.
    params : FrictionParams
        A law with a ``flattening`` block.

    Memory: two rows of about ``acosh(p_cap / p_min) / SEGMENT_WIDTH`` numbers (plus a tabulated
    ``alpha1``'s levels) per distinct pressure; building costs 8 integrand values per segment.
    """

    def __init__(self, p: ArrayLike, params: "FrictionParams") -> None:
        shape, pf, _, cap, levels, j, live = _prepare(p, np.zeros(np.shape(p)), params)
        self.params, self.shape, self.p, self.cap = params, shape, pf, cap
        self._j, self._live = j, live
        flat = _flattening_of(params)
        H = params.H
        self._grid = _Grid(levels / H, params, cap)
        s0 = _s0(params, None, levels.shape)
        self._g, self._c_max = levels / s0, np.full(levels.shape, np.inf)
        # Eq. F4: int_0^u f dv = eps / (kappa ph^2) at the block's beta
        self._per_strain = 1.0 / (_strain_scale(flat, H, s0) * (levels / H) ** 2)
        totals = self._grid.totals(self._g, self._c_max)
        self._cum = np.concatenate([np.zeros((levels.size, 1)), np.cumsum(totals, axis=1)], 1)
        self._alpha0 = np.asarray(alpha_first(pf, params), dtype=float)
        self._runs: tuple | None = None
        self._runs_of: NDArray | None = None

    @property
    def pressures(self) -> int:
        """The number of distinct pressures that flatten (one curve each)."""
        return int(self._grid.ph.size)

    def alpha(self, strains: ArrayLike, beta: float | None = None) -> NDArray[np.float64]:
        """The contact fraction of each point after ``strains`` (broadcast to the points).

        ``beta`` (finite, ``> 0``) replaces the block's; ``None`` keeps it (Eq. F4: the strain
        axis scales as ``1 / beta``).
        """
        eps = np.broadcast_to(np.asarray(strains, dtype=float), self.shape).ravel()
        if not (np.all(np.isfinite(eps)) and np.all(eps >= 0)):
            raise ValueError("strains must be finite and >= 0")
        scale = 1.0
        if beta is not None:
            if not (isinstance(beta, (int, float)) and math.isfinite(beta) and beta > 0):
                raise ValueError(f"beta must be a finite number > 0, got {beta!r}")
            scale = float(beta) / _flattening_of(self.params).beta
        out = self._alpha0.copy()
        go = self._live & (eps > 0)
        if go.any():
            j = self._j[go]
            with np.errstate(over="ignore"):  # a strain beyond any forming: full contact
                target = scale * eps[go] * self._per_strain[j]
            full = target >= self._cum[j, -1]
            u = self._grid.ucap[j].copy()
            if (~full).any():
                jn, tn = j[~full], target[~full]
                seg = _search(self._cum, jn, tn)
                rest = tn - self._cum[jn, seg]
                u[~full] = self._grid.solve(jn, seg, rest, self._g[jn], self._c_max[jn])
            p_f = np.minimum(self.p[go] * np.cosh(u), self.cap)
            out[go] = alpha_first(np.maximum(p_f, self.p[go]), self.params)
        if self._runs is None or self._runs_of is None or not np.array_equal(self._runs_of, eps):
            self._runs, self._runs_of = strain_runs(self.p, eps), eps.copy()
        return running_max(out, self._runs).reshape(self.shape)


class FlatteningPaths:
    """The contact fraction after bulk strain at constant pressures along the bulk's flow curve.

    What :func:`~frictionlaw.flattening_curve` with ``flow_curve`` gives for ``(p, strains)``,
    integrated once per distinct pressure along its strains instead of once per point: Eq. F6
    over ``steps`` steps from 0 to the pressure's largest strain, the k-th ending at
    ``a ((1 + 100)^(k / steps) - 1)`` with ``a`` a hundredth of it (a step is about a fixed
    fraction of the strain, finer where a Swift curve hardens fastest), a tabulated curve's
    points ends too (no step straddles a jump of its modulus), each step at the flow stress and
    hardening modulus of its middle; a point is one more such step from the end below it.
    Build it for the points, then :meth:`alpha` for one ``beta`` or many at once (their paths
    run side by side): the cost grows with the distinct pressures (times the ``beta`` values)
    times ``steps``, a point's with a few polynomial evaluations.

    Parameters
    ----------
    p, strains : array_like
        Contact pressure (Pa, ``> 0``) and equivalent bulk plastic strain (``>= 0``, at most the
        curve's last strain) of each point, broadcast together.
    params : FrictionParams
        A law with a ``flattening`` block.
    flow_curve : SwiftCurve or TabulatedCurve
        The bulk's flow curve from zero strain (:mod:`frictionlaw.flow_curve`).
    steps : int
        Steps of each pressure's path, in ``[1, 100000]`` (default :data:`PATH_STEPS`).
    """

    def __init__(
        self,
        p: ArrayLike,
        strains: ArrayLike,
        params: "FrictionParams",
        flow_curve: "FlowCurve",
        *,
        steps: int = PATH_STEPS,
    ) -> None:
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)):
            raise ValueError(f"steps must be an integer in [1, 100000], got {steps!r}")
        if not 1 <= steps <= 100_000:
            raise ValueError(f"steps must be an integer in [1, 100000], got {steps!r}")
        shape, pf, ef, cap, levels, j, live = _prepare(p, strains, params)
        if ef.size and float(ef.max()) > flow_curve.strain_max:
            raise ValueError(
                f"strains reach {float(ef.max()):.4g}, beyond the flow curve's last strain "
                f"{flow_curve.strain_max:g}: extend the table (it is not extrapolated)"
            )
        self.params, self.flow_curve, self.shape, self.cap = params, flow_curve, shape, cap
        self.p, self.strains, self.levels = pf, ef, levels
        self._alpha0 = np.asarray(alpha_first(pf, params), dtype=float)
        self._runs = strain_runs(pf, ef)
        self._go = live & (ef > 0)
        self._j = j[self._go]
        top = np.zeros(levels.size)
        np.maximum.at(top, self._j, ef[self._go])
        self._grid = _Grid(levels / params.H, params, cap)
        self._nodes = _path_nodes(top, int(steps), flow_curve)  # (n_p, n_ends), rows end at top
        self._k = _search(self._nodes, self._j, ef[self._go])
        # each step's terms and each point's last step: fixed, whatever beta
        mids = (self._nodes[:, :-1] + self._nodes[:, 1:]) / 2
        terms = [_step_terms(levels, mids[:, k], params, flow_curve) for k in range(mids.shape[1])]
        kn, eg = self._nodes[self._j, self._k], ef[self._go]
        last = _step_terms(levels[self._j], (kn + eg) / 2, params, flow_curve)
        # F2d's bounds of every step and point as u, in one inversion of alpha1
        p_all = np.concatenate([np.tile(levels, len(terms)), levels[self._j]])
        a_all = np.concatenate([t[3] for t in terms] + [last[3]])
        u_all = np.split(_held_u(p_all, a_all, params), np.arange(1, len(terms) + 1) * levels.size)
        self._steps = [t[:3] + (u,) for t, u in zip(terms, u_all[:-1], strict=True)]
        self._last = last[:3] + (u_all[-1],)
        self._last_de = eg - kn

    @property
    def pressures(self) -> int:
        """The number of distinct pressures that flatten (one path each)."""
        return int(self.levels.size)

    def alpha(self, beta: ArrayLike | None = None) -> NDArray[np.float64]:
        """The contact fraction of each point; ``beta`` replaces the block's (``None`` keeps it).

        An array of ``beta`` (each finite and ``> 0``) gives one row per value.
        """
        block = _flattening_of(self.params).beta
        b = np.atleast_1d(np.asarray(block if beta is None else beta, dtype=float))
        if b.ndim != 1 or not (np.all(np.isfinite(b)) and np.all(b > 0)):
            raise ValueError("beta must be finite and > 0 (one value or a 1-D array)")
        n_b, n_p = b.size, self.levels.size
        out = np.repeat(self._alpha0[None, :], n_b, axis=0)
        if self._go.any():
            scale = np.repeat(b / block, n_p)  # Eq. F4: the strain per J scales as 1 / beta
            lv = np.tile(np.arange(n_p), n_b)
            u = np.zeros((n_b * n_p, self._nodes.shape[1]))
            for k, (g, c_max, per, held) in enumerate(self._steps):
                de = np.tile(self._nodes[:, k + 1] - self._nodes[:, k], n_b)
                q = scale * de * np.tile(per, n_b)
                uk = _advance(self._grid, lv, u[:, k], q, np.tile(g, n_b), np.tile(c_max, n_b))
                u[:, k + 1] = np.maximum(np.minimum(uk, np.tile(held, n_b)), u[:, k])  # F2d
            g, c_max, per, held = self._last
            n_g = self._j.size
            row = (np.arange(n_b)[:, None] * n_p + self._j[None, :]).ravel()
            kr = np.tile(self._k, n_b)
            q = np.repeat(b / block, n_g) * np.tile(self._last_de * per, n_b)
            jj = np.tile(self._j, n_b)
            ur = _advance(self._grid, jj, u[row, kr], q, np.tile(g, n_b), np.tile(c_max, n_b))
            ur = np.maximum(np.minimum(ur, np.tile(held, n_b)), u[row, kr])  # F2d
            ur = np.minimum(ur, u[row, kr + 1])  # the step to the next end holds the point
            pg = np.tile(self.p[self._go], n_b)
            p_f = np.minimum(pg * np.cosh(ur), self.cap)
            a = np.asarray(alpha_first(np.maximum(p_f, pg), self.params), dtype=float)
            out[:, self._go] = a.reshape(n_b, n_g)
        res = np.stack([running_max(o, self._runs) for o in out])
        if beta is not None and np.ndim(beta) == 1:
            return res.reshape(n_b, *self.shape)
        return res[0].reshape(self.shape)


def _path_nodes(top: NDArray, steps: int, flow_curve: "FlowCurve") -> NDArray[np.float64]:
    """Each pressure's path: 0, the graded ends up to ``top``, a tabulated curve's points below.

    ``a ((1 + R)^(k / steps) - 1)``, ``a = top / R``, ``R`` = :data:`_GRADING`.
    """
    ends = top[:, None] / _GRADING * ((1.0 + _GRADING) ** (np.arange(steps + 1) / steps) - 1.0)
    ends[:, -1] = top
    pts = np.asarray(getattr(flow_curve, "strain", ()), dtype=float)
    if pts.size:
        extra = np.minimum(pts[None, :], top[:, None])
        ends = np.sort(np.concatenate([ends, extra], axis=1), axis=1)
    return ends


def _step_terms(p, mid, params, flow_curve):
    """``g = p / s0``, both hardening limits and ``1 / (kappa ph^2)`` at the strains ``mid``.

    The limits: F2c's on the lattice's rate and F2d's bound on the fraction (``inf``: none).
    """
    H = params.H
    s0 = _s0(params, flow_curve.sigma_y(mid), p.shape)
    h = flow_curve.hardening(mid)
    c_max = lattice_hardening_factor(p, h)
    per = 1.0 / (_strain_scale(_flattening_of(params), H, s0) * (p / H) ** 2)
    return p / s0, c_max, per, _sinking_bound(p, p, h, params)


def _held_u(p, a, params):
    """F2d's bounds ``a`` on the fraction as ``u = acosh(p_f / p)`` (``inf`` from 1 on)."""
    held = np.full(p.shape, np.inf)
    b = a < 1.0
    held[b] = np.arccosh(np.maximum(flattening_pressure(a[b], params) / p[b], 1.0))
    return held


def _advance(grid: _Grid, j, u0, q, g, c_max) -> NDArray[np.float64]:
    """``u`` with ``int_{u0}^{u} f = q`` on pressure ``j``'s segments (its ``ucap`` if beyond)."""
    edges = grid.edges
    last = edges.shape[1] - 2
    seg = np.minimum(_search(edges, j, u0), last)
    # the integral from the start of u0's segment: q plus the part before u0
    a, b = edges[j, seg], edges[j, seg + 1]
    half = (b - a) / 2
    f = grid.samples(j, seg, g, c_max)
    c = f @ _PROJ.T
    s0 = np.where(half > 0, (u0 - a) / np.where(half > 0, half, 1.0) - 1.0, -1.0)
    P = _legendre(np.clip(s0, -1.0, 1.0), 8)
    rest = q + half * np.einsum("ij,ji->i", c @ _INT.T, P)
    out = grid.ucap[j].copy()
    act = np.ones(j.size, dtype=bool)
    total = half * (f @ _GW)
    while act.any():
        inside = act & (rest <= total)
        if inside.any():
            i = np.flatnonzero(inside)
            out[i] = grid.solve(j[i], seg[i], rest[i], g[i], c_max[i], f[i])
        act &= ~inside
        act &= seg < last  # beyond the last segment: full contact (ucap)
        if not act.any():
            break
        i = np.flatnonzero(act)
        rest[i] -= total[i]
        seg[i] += 1
        f[i] = grid.samples(j[i], seg[i], g[i], c_max[i])
        total[i] = (edges[j[i], seg[i] + 1] - edges[j[i], seg[i]]) / 2 * (f[i] @ _GW)
    return np.maximum(out, u0)
