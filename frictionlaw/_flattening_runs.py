"""Curves of constant pressure as running maxima over strain (``flattening_curve`` and the fit).

Private: :func:`frictionlaw.flattening.flattening_curve` and
:mod:`frictionlaw.flattening_curves` share it.
"""

import numpy as np
from numpy.typing import NDArray

__all__ = ["strain_runs", "running_max"]


def strain_runs(p: NDArray, strains: NDArray) -> tuple[NDArray, list]:
    """The points' order by pressure, then strain, and the runs of one pressure (two points up).

    Flat arrays of equal size; the result is what :func:`running_max` reads, computed once for
    points that are evaluated many times (a fit).
    """
    order = np.lexsort((strains, p))
    ps = p[order]
    starts = np.flatnonzero(np.r_[True, ps[1:] != ps[:-1]])
    ends = np.r_[starts[1:], ps.size]
    many = ends - starts > 1
    return order, list(zip(starts[many].tolist(), ends[many].tolist(), strict=True))


def running_max(alpha: NDArray, runs: tuple[NDArray, list]) -> NDArray[np.float64]:
    """``alpha`` as a running maximum over increasing strain at each pressure.

    ``runs`` from :func:`strain_runs` of the same points: the solvers' last-digit scatter cannot
    make a curve of constant pressure fall.
    """
    order, spans = runs
    a = alpha[order]
    for s, e in spans:
        a[s:e] = np.maximum.accumulate(a[s:e])
    out = np.empty_like(a)
    out[order] = a
    return out
