"""The rate table of the two-state flattening law and its integrator (private, NumPy).

Model ``limit-analysis`` of docs/flattening.md: a node's flattening state is its contact
fraction ``A`` and its asperities' current flank slope ``s``; both grow with the stretch across
the ridges at the rates of the rigid-perfectly plastic optimum of the wedge cell, tabulated over
``p / H_P`` (``H_P = (2 + pi) k``, the Prandtl hardness of the bulk), ``A`` and ``s`` in
``data/limit_rates.csv`` (computed by the project's limit analysis, benchmarks/
flattening_limit_law.py and flattening_limit_low.py; gathered by flattening_limit_ship.py).

Reading the table (the studies' reading, docs/flattening_studies.md): at one tabulated pressure,
bilinear in ``A`` and ``ln s``, clamped to the grid (below ``s = 0.01`` the rates of 0.01, beyond
``A = 0.96`` those of 0.96); between pressures linear in ``ln p`` at the same ``A``, clamped
to the table's first and last pressure; ``dA / d eps`` held at ``>= 0`` (a node's flattening
never falls). Integration: the explicit midpoint rule in ``(A, ln s)``, steps of
:data:`STEP` in stretch, ``A`` at most 1, ``s`` at least :data:`S_FLOOR`.

A block with an ``edge_slope`` table (the workpiece's edge slope ``E(A)`` at equally spaced
contact fractions, :func:`edge_at`) carries the flank's turn ``r = s / E(A)`` instead: the
midpoint rule runs in ``(A, ln r)``, the table is read at ``s = max(r E(A), S_FLOOR)`` and its
``d ln s / d eps`` turns ``r``, so that ``s`` follows the surface's own edges as the contact
grows. Without a table ``E = 1`` and ``r = s``: the same operations, the same numbers.

This module is the NumPy reference of the kernels in ``_kernels_limit.py``.
"""

import math
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

import numpy as np
from numpy.typing import NDArray

from ._flattening_block import LIMIT_MODEL, LIMIT_SLOPE_RANGE

__all__ = [
    "LIMIT_MODEL",
    "PRANDTL_FACTOR",
    "STEP",
    "S_FLOOR",
    "LIMIT_SLOPE_RANGE",
    "RateTable",
    "rate_table",
    "table_rates",
    "edge_at",
    "integrate",
    "integrate_shared",
]

#: the Prandtl hardness over the shear flow stress, ``2 + pi``: the table's pressure unit
PRANDTL_FACTOR = 2.0 + math.pi
#: stretch per midpoint step (the studies': 0.0005 and 0.0001 agree to 8e-4 in ``A``)
STEP = 0.0005
#: the flank slope never falls below this while it turns (the studies' floor)
S_FLOOR = 1e-3


@dataclass(frozen=True)
class RateTable:
    """The rates at each tabulated pressure (rows ``offsets[i]:offsets[i + 1]`` of pressure ``i``).

    ``pressures`` ascending ``p / H_P``; ``a`` each row's contact fraction (ascending within a
    pressure); ``ln_s`` the slopes' logarithms; ``dA`` and ``ds`` of shape ``(rows, slopes)``;
    ``key`` each row's ``2 k + A`` (``k`` its pressure), ascending since ``A`` lies in [0, 1].
    """

    pressures: NDArray[np.float64]
    offsets: NDArray[np.int64]
    a: NDArray[np.float64]
    ln_s: NDArray[np.float64]
    dA: NDArray[np.float64]
    ds: NDArray[np.float64]
    key: NDArray[np.float64]


@lru_cache(maxsize=1)
def rate_table() -> RateTable:
    """The shipped table (read once)."""
    text = resources.files("frictionlaw").joinpath("data/limit_rates.csv").read_text("utf-8")
    lines = [ln for ln in text.splitlines() if ln and not ln.startswith("#")]
    rows = np.array([[float(v) for v in ln.split(",")[1:6]] for ln in lines[1:]])
    ph, a, s, dA, ds = rows.T
    slopes = np.unique(s)
    pressures = np.unique(ph)
    n_s = slopes.size
    order = np.lexsort((s, a, ph))
    ph, a, dA, ds = ph[order], a[order], dA[order], ds[order]
    counts = np.array([np.count_nonzero(ph == q) for q in pressures])
    if np.any(counts % n_s):
        raise RuntimeError("data/limit_rates.csv: a pressure lacks a slope at some A")
    offsets = np.concatenate([[0], np.cumsum(counts // n_s)]).astype(np.int64)
    a_rows = np.ascontiguousarray(a[::n_s])
    k = np.repeat(np.arange(pressures.size), np.diff(offsets))
    return RateTable(
        pressures=pressures,
        offsets=offsets,
        a=a_rows,
        ln_s=np.log(slopes),
        dA=np.ascontiguousarray(dA.reshape(-1, n_s)),
        ds=np.ascontiguousarray(ds.reshape(-1, n_s)),
        key=2.0 * k + a_rows,
    )


def _at_pressure(t: RateTable, i: NDArray, A: NDArray, ls: NDArray) -> tuple[NDArray, NDArray]:
    """Bilinear in ``A`` and ``ln s`` at tabulated pressures ``i`` (one per point).

    Each point is clamped to its own pressure's grid; the rows of all pressures are searched at
    once in ``t.key`` (``2 k + A`` of pressure ``k``'s rows, ascending over the whole table).
    """
    lo, hi = t.offsets[i], t.offsets[i + 1]
    r = np.clip(np.searchsorted(t.key, 2.0 * i + A) - 1, lo, hi - 2)
    js = np.clip(np.searchsorted(t.ln_s, ls) - 1, 0, t.ln_s.size - 2)
    ta = np.clip((A - t.a[r]) / (t.a[r + 1] - t.a[r]), 0.0, 1.0)
    ts = np.clip((ls - t.ln_s[js]) / (t.ln_s[js + 1] - t.ln_s[js]), 0.0, 1.0)
    out = []
    for v in (t.dA, t.ds):
        out.append(
            (1 - ta) * ((1 - ts) * v[r, js] + ts * v[r, js + 1])
            + ta * ((1 - ts) * v[r + 1, js] + ts * v[r + 1, js + 1])
        )
    return out[0], out[1]


def table_rates(x: NDArray, A: NDArray, s: NDArray, t: RateTable) -> tuple[NDArray, NDArray]:
    """``(dA / d eps, ds / d eps)`` per unit stretch at ``p / H_P = x`` (broadcast arrays).

    Linear in ``ln x`` between the two tabulated pressures around ``x`` (clamped to the first
    and last), each read at the same ``A``; ``dA`` held at ``>= 0``.
    """
    x, A, s = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, A, s)))
    P = t.pressures
    i = np.clip(np.searchsorted(P, x) - 1, 0, P.size - 2)
    w = np.clip(np.log(x / P[i]) / np.log(P[i + 1] / P[i]), 0.0, 1.0)
    ls = np.log(s)
    a0, s0 = _at_pressure(t, i, A, ls)
    a1, s1 = _at_pressure(t, i + 1, A, ls)
    return np.maximum((1 - w) * a0 + w * a1, 0.0), (1 - w) * s0 + w * s1


def edge_at(edge: NDArray | None, A: NDArray) -> NDArray[np.float64] | float:
    """The edge slope ``E(A)``, linear between the table's equally spaced fractions (1 without).

    ``edge`` holds ``E`` at ``A = i / (n - 1)``; ``A`` in [0, 1]. The kernels' arithmetic:
    ``u = A (n - 1)``, ``i = min(floor(u), n - 2)``, ``E[i] + (u - i) (E[i + 1] - E[i])``.
    """
    if edge is None or len(edge) == 0:
        return 1.0
    e = np.asarray(edge, dtype=float)
    u = np.asarray(A, dtype=float) * (e.size - 1)
    i = np.minimum(np.floor(u), e.size - 2).astype(np.int64)
    return e[i] + (u - i) * (e[i + 1] - e[i])


def start_log(s: NDArray, edge: NDArray | None) -> NDArray[np.float64]:
    """The integration's start ``ln s`` (floored at :data:`S_FLOOR`), or ``ln r`` with a table."""
    s = np.asarray(s, dtype=float)
    if edge is None or len(edge) == 0:
        return np.log(np.maximum(s, S_FLOOR))
    return np.log(np.maximum(s, 1e-300))


def _slope(a, q, edge):
    """The flank slope the table is read at: ``max(exp(q) E(a), S_FLOOR)``."""
    return np.maximum(np.exp(q) * edge_at(edge, a), S_FLOOR)


def _midpoint(a, qa, xa, h, t, edge=None):
    """One midpoint step of length ``h`` from ``(a, ln r)``: the rule of :func:`integrate`."""
    sa = _slope(a, qa, edge)
    dA, ds = table_rates(xa, a, sa, t)
    am = np.minimum(a + 0.5 * h * dA, 1.0)
    qm = qa + 0.5 * h * ds / sa
    sm = _slope(am, qm, edge)
    dA, ds = table_rates(xa, am, sm, t)
    return np.minimum(a + h * dA, 1.0), qa + h * ds / sm


def integrate(
    A: NDArray,
    s: NDArray,
    x: NDArray,
    stretch: NDArray,
    t: RateTable,
    edge: NDArray | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(A, s)`` after ``stretch`` at ``p / H_P = x`` (flat arrays of one size).

    The midpoint rule in ``(A, ln s)`` with steps of :data:`STEP` (the last one shorter), ``A``
    at most 1 (it then stops), ``s`` at least :data:`S_FLOOR`. With an ``edge`` table (module
    text) the given ``s`` is the flank's turn ``r`` at the start and the rule runs in
    ``(A, ln r)``; the slope returned is ``max(r E(A), S_FLOOR)`` at the end.
    """
    A = np.minimum(np.array(A, dtype=float), 1.0)
    q = start_log(s, edge)
    left = np.array(stretch, dtype=float)
    x = np.asarray(x, dtype=float)
    act = np.flatnonzero((left > 0) & (A < 1.0))
    while act.size:
        h = np.minimum(STEP, left[act])
        A[act], q[act] = _midpoint(A[act], q[act], x[act], h, t, edge)
        left[act] -= h
        act = act[(left[act] > 1e-12) & (A[act] < 1.0)]
    return A, _slope(A, q, edge)


#: the most states :func:`integrate_shared` keeps (steps times distinct starts); beyond, per point
_DENSE_MAX = 4_000_000


def integrate_shared(
    A: NDArray,
    s: NDArray,
    x: NDArray,
    stretch: NDArray,
    t: RateTable,
    edge: NDArray | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """:func:`integrate` for many points that share their start ``(A, s, x)`` (a curve's points).

    Each distinct start is integrated once in full steps of :data:`STEP`, its state kept after
    every step; a point takes the state after its own number of full steps and then its last,
    shorter step, which are the operations :func:`integrate` does for it alone (equal to
    rounding); the steps stop once every start is in full contact. Falls back to
    :func:`integrate` where the kept states would pass :data:`_DENSE_MAX`.
    """
    A, s, x, stretch = (np.asarray(v, dtype=float) for v in (A, s, x, stretch))
    keys, inv = np.unique(np.stack([A, s, x]), axis=1, return_inverse=True)
    inv = inv.ravel()
    full = np.floor(stretch / STEP).astype(np.int64)
    part = stretch - full * STEP
    # a remainder within rounding of a step is that step (integrate's min(STEP, left))
    whole = part >= STEP * (1 - 1e-9)
    full, part = full + whole, np.where(whole, 0.0, part)
    n = int(full.max(initial=0))
    g0 = np.minimum(keys[0], 1.0)
    As, qs = [g0], [start_log(keys[1], edge)]
    for _ in range(n):  # until every start is in full contact (its state then stays)
        a, q = As[-1].copy(), qs[-1].copy()
        go = a < 1.0
        if not go.any():
            break
        if len(As) * g0.size > _DENSE_MAX:
            return integrate(A, s, x, stretch, t, edge)
        a[go], q[go] = _midpoint(a[go], q[go], keys[2][go], STEP, t, edge)
        As.append(a)
        qs.append(q)
    full = np.minimum(full, len(As) - 1)
    a, q = np.array(As)[full, inv], np.array(qs)[full, inv]
    go = (part > 1e-12) & (a < 1.0)
    if go.any():
        a[go], q[go] = _midpoint(a[go], q[go], x[go], part[go], t, edge)
    return a, _slope(a, q, edge)
