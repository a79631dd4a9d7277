"""The laws of a band, in the forms the pooled law runs (issue 37).

A band of several samples is made from laws: the bootstrap's resample laws (the pooled law
refitted with each sample counted as often as it was drawn), the two edge laws (fitted to the
band's edges) and every sample's own law. Each runs the forms the pooled law runs
(``FrictionParams.first_loading_form`` and ``reload_form``): the band is the band of the law
the file runs, and an FE run of an edge or sample law runs that law's forms.

Every law refits the file's header too (Eq. 24's ``C1, n1``, the paper's ``C2, n2`` on the
form's ``alpha1(p_hist)``), so that the parameter intervals stay defined, and then

* the tabulated first loading: the table of the (weighted) points
  (:func:`~.first_table.fit_first_loading_table`: a weighted mean per level);
* the tabulated reload form: each level's ``C2, n2`` at the pooled law's ``s2`` (one exponent for
  the band). The resample laws start each level from the pooled law's values (a resample moves
  them little: about 4 ms a level); the edge and sample laws from the grid of the full fit
  (:func:`~.reload_table.fit_reload_table` with ``s2`` held).

A first-loading or reload form without a band refit here is refused (``ValueError`` naming it).
"""

import math

import numpy as np
from scipy.optimize import least_squares

from frictionlaw import alpha_first, alpha_reload
from frictionlaw.reload_form import ReloadTable
from frictionlaw.uncertainty import BandLaw, SampleLaw

from ..law import fit as _fit
from ..law.alpha_bound import floor_fit, floor_violation
from ..law.first_table import fit_first_loading_table
from ..law.reload_table import (
    TABLE_C_BOUNDS,
    TABLE_N_BOUNDS,
    TABLE_N_BOUNDS_CONTINUOUS,
    _level_alpha,
    first_tail,
    fit_reload_table,
)

__all__ = ["Stacked", "resample_law", "edge_law", "sample_law", "check_band_forms"]

_FIRST_FORMS = ("eq24", "tabulated")
_RELOAD_FORMS = ("paper", "tabulated")


def check_band_forms(central):
    """``ValueError`` unless the band can refit the forms ``central`` runs."""
    if central.first_loading_form not in _FIRST_FORMS:
        raise ValueError(
            f"a band of the first-loading form {central.first_loading_form!r} is not defined "
            f"(bands refit {', '.join(_FIRST_FORMS)})"
        )
    if central.reload_form not in _RELOAD_FORMS:
        raise ValueError(
            f"a band of the reload form {central.reload_form!r} is not defined (bands refit "
            f"{', '.join(_RELOAD_FORMS)})"
        )


class Stacked:
    """All samples' points as flat arrays with each point's sample index (for weighted refits).

    ``p1, a1, i1``: first loading; ``p2, h2, a2, i2``: every reload point with its ``p_hist``;
    ``levels``: ``[(p_hist, mask into p2)]`` ascending.
    """

    def __init__(self, samples):
        self.p1 = np.concatenate([s.p for s in samples])
        self.a1 = np.concatenate([s.alpha for s in samples])
        self.i1 = np.concatenate([np.full(s.p.size, i) for i, s in enumerate(samples)])
        rc = [(i, c) for i, s in enumerate(samples) for c in s.reload]
        self.p2 = np.concatenate([c.p for _, c in rc])
        self.h2 = np.concatenate([np.full(c.p.size, c.p_hist) for _, c in rc])
        self.a2 = np.concatenate([c.alpha for _, c in rc])
        self.i2 = np.concatenate([np.full(c.p.size, i) for i, c in rc])
        self.levels = [(float(ph), self.h2 == ph) for ph in np.unique(self.h2)]


def _refit(model, alpha, w, x0, lb, ub):
    """Weighted least squares in log-parameters from ``x0``: the fitted parameters."""

    def residual(x):
        return (model(*np.exp(x)) - alpha) * w

    x0 = np.clip(np.log(x0), np.log(lb) + 1e-9, np.log(ub) - 1e-9)
    sol = least_squares(residual, x0, bounds=(np.log(lb), np.log(ub)), method="trf")
    return np.exp(sol.x)


def _eq24(p, a, w, H, start, floor_to):
    """Eq. 24's ``C1, n1`` refitted (weighted, from ``start``, with the pooled fit's bound)."""
    lb = np.array([_fit.C_BOUNDS[0], _fit.N_BOUNDS[0]])
    ub = np.array([_fit.C_BOUNDS[1], _fit.N_BOUNDS[1]])

    def model(c, n):
        return alpha_first(p, _fit._law(H, c, n))

    c1, n1 = _refit(model, a, w, start, lb, ub)
    if floor_to is not None and floor_violation(c1, n1, H, floor_to)[0] > 1e-12:
        x0 = np.clip(np.log([c1, n1]), np.log(lb) + 1e-9, np.log(ub) - 1e-9)
        par = floor_fit(
            lambda x: (model(*np.exp(x)) - a) * w, H, floor_to, x0, lb, ub, ("C1", "n1")
        )
        c1, n1 = par[0]["C1"], par[0]["n1"]
    return float(c1), float(n1)


def _table_levels(st, counts, central, c1, n1, first):
    """The tabulated reload form's levels refitted (weighted), from the pooled law's values."""
    H, cont = central.H, central.continuous_reload
    table = central.reload_table
    s2 = table.s2
    tail = first_tail(H, c1, n1, first)
    nb = TABLE_N_BOUNDS_CONTINUOUS if cont else TABLE_N_BOUNDS
    lb, ub = np.log([TABLE_C_BOUNDS[0], nb[0]]), np.log([TABLE_C_BOUNDS[1], nb[1]])
    c2s, n2s = [], []
    for (ph, m), c2, n2 in zip(st.levels, table.C2, table.n2, strict=True):
        p, a = st.p2[m], st.a2[m]
        w = np.sqrt(counts[st.i2[m]].astype(float))

        def residual(x, p=p, ph=ph, a=a, w=w):
            return (_level_alpha(p, ph, H, c1, n1, cont, s2, *np.exp(x), tail) - a) * w

        x0 = np.clip(np.log([c2, n2]), lb + 1e-9, ub - 1e-9)
        sol = least_squares(
            residual, x0, bounds=(lb, ub), method="trf", jac="2-point", ftol=1e-8, xtol=1e-8
        )
        c2s.append(float(math.exp(sol.x[0])))
        n2s.append(float(math.exp(sol.x[1])))
    return ReloadTable(p_hist=table.p_hist, C2=tuple(c2s), n2=tuple(n2s), s2=s2)


def resample_law(st, counts, central, floor_to=None):
    """The pooled law refitted with sample ``i`` counted ``counts[i]`` times, in its forms.

    Returns a ``FrictionParams`` (``central``'s, with the refitted data).
    """
    H, cont = central.H, central.continuous_reload
    w1 = np.sqrt(counts[st.i1].astype(float))
    c1, n1 = _eq24(st.p1, st.a1, w1, H, (central.C1, central.n1), floor_to)
    kw = {}
    first = None
    if central.first_loading_form == "tabulated":
        w = (
            counts[st.i1].astype(float) + 1e-9
        )  # a level only undrawn samples reached keeps its mean
        tab = fit_first_loading_table(st.p1, st.a1, H, weights=w)
        first = ("tabulated", tab.table)
        kw["first_loading_table"] = tab.table
    w2 = np.sqrt(counts[st.i2].astype(float))
    lb = np.array([_fit.C_BOUNDS[0], _fit.N_BOUNDS[0]])
    ub = np.array([_fit.C_BOUNDS[1], _fit.N_BOUNDS[1]])
    c2, n2 = _refit(
        lambda c, n: alpha_reload(st.p2, st.h2, _fit._law(H, c1, n1, c, n, cont, first)),
        st.a2,
        w2,
        (central.C2, central.n2),
        lb,
        ub,
    )
    if central.reload_form == "tabulated":
        kw["reload_table"] = _table_levels(st, counts, central, c1, n1, first)
    return central.replace(C1=c1, n1=n1, C2=float(c2), n2=float(n2), uncertainty=None, **kw)


def _fit_forms(central, p, alpha, curves, floor_to):
    """``central``'s forms fitted to unweighted points: ``(C1, n1, C2, n2, first, reload)``."""
    H, cont = central.H, central.continuous_reload
    f1 = _fit.fit_first_loading(p, alpha, H, floor_to=floor_to)
    first = None
    if central.first_loading_form == "tabulated":
        first = ("tabulated", fit_first_loading_table(p, alpha, H).table)
    rel = _fit.fit_reload(curves, H, f1.C1, f1.n1, continuous=cont, first=first)
    reload = None
    if central.reload_form == "tabulated":
        t = fit_reload_table(
            curves, H, f1.C1, f1.n1, continuous=cont, s2=central.reload_table.s2, first=first
        )
        reload = ("tabulated", t.table)
    return f1.C1, f1.n1, rel.C2, rel.n2, first, reload


def edge_law(central, grid1, grid2, edge, floor_to=None):
    """The :class:`~frictionlaw.uncertainty.BandLaw` fitted to one band edge.

    ``edge``: ``alpha`` of the edge on ``grid1`` (first loading), then on each reload level's
    grid of ``grid2`` (``{p_hist: pressures}``). The tabulated first loading takes the edge at
    the pooled table's levels (points of ``grid1``).
    """
    a1 = np.clip(edge[0], 0.0, 1.0)
    curves = [
        _fit.ReloadCurve(ph, g, np.clip(a, 0.0, 1.0))
        for (ph, g), a in zip(grid2.items(), edge[1:], strict=True)
        if g[0] > 0
    ]
    p, alpha = grid1, a1
    if central.first_loading_form == "tabulated":
        levels = np.asarray(central.first_loading_table.p)
        keep = np.isin(grid1, levels)
        p, alpha = grid1[keep], a1[keep]
    c1, n1, c2, n2, first, reload = _fit_forms(central, p, alpha, curves, floor_to)
    if central.first_loading_form == "tabulated":  # Eq. 24 (the header) on the whole edge
        c1, n1 = _eq24(grid1, a1, np.ones_like(a1), central.H, (c1, n1), floor_to)
    return BandLaw(c1, n1, c2, n2, first, reload)


def sample_law(sample, central, floor_to=None):
    """One sample's own law in ``central``'s forms, as a :class:`~frictionlaw.uncertainty.SampleLaw`."""
    vals = _fit_forms(central, sample.p, sample.alpha, list(sample.reload), floor_to)
    if not all(math.isfinite(v) for v in vals[:4]):  # pragma: no cover - fits return finite values
        raise RuntimeError(f"sample {sample.name}: the fit gave non-finite parameters {vals[:4]}")
    return SampleLaw(sample.name, *vals)
