"""Fit of the tabulated first-loading form: the computed points, made monotone and bounded.

The form (:mod:`frictionlaw.first_loading`) runs the computed first loading ``(p_j, alpha_j)``
itself. Its "fit" makes the points a valid table: the contact ratios at each load level
(averaged where several samples share a level: the least-squares table of pooled points, with
``weights`` per point for the bootstrap), made non-decreasing by their least-squares
non-decreasing sequence (pool-adjacent-violators: a solve that lands a hair below its neighbour
is averaged with it, not lifted to it), then clipped to ``[p_j / H, 1]`` (the half-space model's
exact bound ``alpha >= p / H``: every local pressure is at most ``H``; clipping keeps the
sequence non-decreasing because ``p_j / H`` increases). The in-sample residuals are what these
two steps changed: zero on a monotone curve within the bound.
"""

import numpy as np

from frictionlaw.first_loading import FirstLoadingTable

from ...common.checks import positive

__all__ = ["FirstLoadingTableFit", "fit_first_loading_table", "monotone_increasing"]


class FirstLoadingTableFit:
    """Result of :func:`fit_first_loading_table`.

    Attributes
    ----------
    table : frictionlaw.first_loading.FirstLoadingTable
        The levels and their contact ratios, ready for ``FrictionParams``.
    residuals : ndarray
        ``alpha_table - alpha`` at every data point (in the order given).
    changed : int
        Levels whose value the monotone sequence or the bound changed by more than 1e-12.
    H : float
        The hardness (Pa) of the bound.
    """

    success = True
    converged = True
    at_bound: tuple = ()
    degenerate = ""
    message = "the computed points, made non-decreasing and bounded by p / H and 1"

    def __init__(self, table, residuals, changed, H):
        self.table = table
        self.residuals = np.asarray(residuals, float)
        self.changed = int(changed)
        self.H = float(H)

    @property
    def max_abs_residual(self):
        """Largest ``|alpha_table - alpha|`` in sample."""
        return float(np.max(np.abs(self.residuals))) if self.residuals.size else 0.0

    def summary(self):
        """JSON-ready record of the fit (for the provenance and ``summary.json``)."""
        t = self.table
        return {
            "form": "tabulated",
            "levels": [{"p": p, "alpha": a} for p, a in zip(t.p, t.alpha, strict=True)],
            "mu_eff_over_tau_max": t.slope0,
            "changed_levels": self.changed,
            "max_abs_residual": self.max_abs_residual,
            "n_points": int(self.residuals.size),
            "success": True,
            "converged": True,
            "message": self.message,
        }


def monotone_increasing(y, w=None):
    """The weighted least-squares non-decreasing sequence of ``y`` (pool-adjacent-violators)."""
    y = np.asarray(y, float)
    w = np.ones_like(y) if w is None else np.asarray(w, float)
    vals, wts, counts = [], [], []
    for v, wt in zip(y, w, strict=True):
        vals.append(v)
        wts.append(wt)
        counts.append(1)
        while len(vals) > 1 and vals[-2] > vals[-1]:
            wsum = wts[-2] + wts[-1]
            merged = (vals[-2] * wts[-2] + vals[-1] * wts[-1]) / wsum
            n = counts[-2] + counts[-1]
            del vals[-1], wts[-1], counts[-1]
            vals[-1], wts[-1], counts[-1] = merged, wsum, n
    return np.repeat(vals, counts)


def fit_first_loading_table(p, alpha, H, weights=None):
    """The tabulated first loading of the points ``(p, alpha)`` (module docstring).

    Parameters
    ----------
    p : array_like
        First-loading mean pressures (Pa), ``> 0``, below ``H``; repeated values (several
        samples at one level) are averaged.
    alpha : array_like
        Contact ratios at ``p`` in ``[0, 1]``.
    H : float
        Hardness (Pa).
    weights : array_like, optional
        A weight ``>= 0`` per point (the bootstrap's counts); each level needs a positive sum.

    Returns
    -------
    FirstLoadingTableFit
    """
    H = positive("H", H)
    p = np.asarray(p, float)
    alpha = np.asarray(alpha, float)
    if p.ndim != 1 or p.shape != alpha.shape:
        raise ValueError("p and alpha must be 1-D arrays of one length")
    if not (np.isfinite(p).all() and np.isfinite(alpha).all()):
        raise ValueError("p and alpha must be finite")
    if (p <= 0).any() or (p >= H).any():
        raise ValueError(f"p must lie in (0, H) = (0, {H:g}) Pa")
    w = np.ones_like(p) if weights is None else np.asarray(weights, float)
    levels, inv = np.unique(p, return_inverse=True)
    if levels.size < 2:
        raise ValueError(f"p needs at least 2 distinct levels for a table, got {levels.size}")
    wsum = np.bincount(inv, weights=w, minlength=levels.size)
    if (wsum <= 0).any():
        raise ValueError("weights must give every level a positive sum")
    mean = np.bincount(inv, weights=w * alpha, minlength=levels.size) / wsum
    fitted = np.clip(monotone_increasing(mean, wsum), levels / H, 1.0)
    table = FirstLoadingTable(p=tuple(levels), alpha=tuple(fitted))
    return FirstLoadingTableFit(
        table,
        fitted[inv] - alpha,
        int(np.sum(np.abs(fitted - mean) > 1e-12)),
        H,
    )
