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
    "integrate",
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
    pressure); ``ln_s`` the slopes' logarithms; ``dA`` and ``ds`` of shape ``(rows, slopes)``.
    """

    pressures: NDArray[np.float64]
    offsets: NDArray[np.int64]
    a: NDArray[np.float64]
    ln_s: NDArray[np.float64]
    dA: NDArray[np.float64]
    ds: NDArray[np.float64]


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
    return RateTable(
        pressures=pressures,
        offsets=offsets,
        a=np.ascontiguousarray(a[::n_s]),
        ln_s=np.log(slopes),
        dA=np.ascontiguousarray(dA.reshape(-1, n_s)),
        ds=np.ascontiguousarray(ds.reshape(-1, n_s)),
    )


def _at_pressure(t: RateTable, i: int, A: NDArray, ls: NDArray) -> tuple[NDArray, NDArray]:
    """Bilinear in ``A`` and ``ln s`` at tabulated pressure ``i``, clamped to its grid."""
    lo, hi = int(t.offsets[i]), int(t.offsets[i + 1])
    a = t.a[lo:hi]
    ia = np.clip(np.searchsorted(a, A) - 1, 0, a.size - 2)
    js = np.clip(np.searchsorted(t.ln_s, ls) - 1, 0, t.ln_s.size - 2)
    ta = np.clip((A - a[ia]) / (a[ia + 1] - a[ia]), 0.0, 1.0)
    ts = np.clip((ls - t.ln_s[js]) / (t.ln_s[js + 1] - t.ln_s[js]), 0.0, 1.0)
    r = lo + ia
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
    dA, ds = np.zeros(x.shape), np.zeros(x.shape)
    for k in np.unique(i):
        m = i == k
        a0, s0 = _at_pressure(t, int(k), A[m], ls[m])
        a1, s1 = _at_pressure(t, int(k) + 1, A[m], ls[m])
        dA[m] = (1 - w[m]) * a0 + w[m] * a1
        ds[m] = (1 - w[m]) * s0 + w[m] * s1
    return np.maximum(dA, 0.0), ds


def integrate(
    A: NDArray, s: NDArray, x: NDArray, stretch: NDArray, t: RateTable
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(A, s)`` after ``stretch`` at ``p / H_P = x`` (flat arrays of one size).

    The midpoint rule in ``(A, ln s)`` with steps of :data:`STEP` (the last one shorter), ``A``
    at most 1 (it then stops), ``s`` at least :data:`S_FLOOR`.
    """
    A = np.minimum(np.array(A, dtype=float), 1.0)
    q = np.log(np.maximum(np.asarray(s, dtype=float), S_FLOOR))
    left = np.array(stretch, dtype=float)
    x = np.asarray(x, dtype=float)
    act = np.flatnonzero((left > 0) & (A < 1.0))
    while act.size:
        a, qa, xa = A[act], q[act], x[act]
        h = np.minimum(STEP, left[act])
        dA, ds = table_rates(xa, a, np.maximum(np.exp(qa), S_FLOOR), t)
        am = np.minimum(a + 0.5 * h * dA, 1.0)
        qm = qa + 0.5 * h * ds / np.maximum(np.exp(qa), S_FLOOR)
        dA, ds = table_rates(xa, am, np.maximum(np.exp(qm), S_FLOOR), t)
        A[act] = np.minimum(a + h * dA, 1.0)
        q[act] = qa + h * ds / np.maximum(np.exp(qm), S_FLOOR)
        left[act] -= h
        act = act[(left[act] > 1e-12) & (A[act] < 1.0)]
    return A, np.maximum(np.exp(q), S_FLOOR)
