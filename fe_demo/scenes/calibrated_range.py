"""Contact pressures against the law's calibrated range, per increment and over a run.

With a parameter file that records its ``calibrated_range`` (``p_min, p_max``), every
accepted increment gets the columns of :data:`RANGE_COLUMNS` (from
:func:`frictionlaw.check_pressure_range` on the die's contact nodes), and the run's
``summary.json`` a ``calibrated_range`` record: the range, the worst increment (the largest
count and peak over the run) and the last one (its console lines:
:func:`fe_demo.output.reports.range_lines`). Laws without parameters (Coulomb, Tresca,
cap) add nothing; an SBMF parameter set without a range says so.

Nodes at ``p >= H`` are counted apart (``n_above_H``, ``n_hist_above_H``): the half-space model
has an exact limit there (full contact, ``alpha = 1`` at ``p_mean = H``) which the law follows
(``alpha1(H)`` in the record), so they are not an extrapolation; ``n_above_range`` (the
EXTRAPOLATED warning) counts only the nodes between ``p_max`` and ``H``.
"""

import numpy as np

from frictionlaw import alpha_first, check_pressure_range

__all__ = ["RANGE_COLUMNS", "range_columns", "range_summary"]

#: history columns (per accepted increment) when the law has a calibrated range
RANGE_COLUMNS = (
    "n_above_range",  # contact nodes with p_max < p < H (extrapolated)
    "n_hist_above_range",  # nodes with p_max < p_hist < H
    "n_below_range",  # contact nodes with 0 < p < p_min
    "p_peak",  # largest contact pressure (Pa)
    "p_hist_peak",  # largest p_hist (Pa)
    "p_peak_over_p_max",  # p_peak / p_max
    "n_above_H",  # contact nodes with p >= H (the half-space model's limit, full contact)
    "n_hist_above_H",  # nodes with p_hist >= H
)


def _params(model):
    return getattr(model.contact.law, "params", None)


def range_columns(model):
    """The :data:`RANGE_COLUMNS` of the accepted state, or ``{}`` without a range."""
    ev = model.accepted
    c = check_pressure_range(_params(model), ev.p, model.contact.state.p_hist)
    if c is None:
        return {}
    vals = (
        c.n_above,
        c.n_hist_above,
        c.n_below,
        c.p_peak,
        c.p_hist_peak,
        c.ratio,
        c.n_above_H,
        c.n_hist_above_H,
    )
    return dict(zip(RANGE_COLUMNS, vals, strict=True))


def range_summary(model, history):
    """The ``calibrated_range`` record of ``summary.json``.

    Returns ``None`` for laws without parameters, a note for a parameter set without a
    range, else ``p_min_Pa``, ``p_max_Pa``, ``H_Pa``, ``alpha1_at_H`` (the law's contact ratio
    at the model's limit, where the model has 1), ``max_over_run`` and ``end`` (each the columns
    of :data:`RANGE_COLUMNS`, plus ``n_contact`` at the end).
    """
    params = _params(model)
    if params is None:
        return None
    if params.p_range is None:
        return {"note": "the parameter file records no calibrated_range: not checked"}
    out = {
        "p_min_Pa": params.p_range[0],
        "p_max_Pa": params.p_range[1],
        "H_Pa": params.H,
        "alpha1_at_H": float(alpha_first(params.H, params)),
    }
    if not history or RANGE_COLUMNS[0] not in history:
        return out
    out["max_over_run"] = {k: np.max(history[k]).item() for k in RANGE_COLUMNS}
    out["end"] = {k: np.asarray(history[k])[-1].item() for k in RANGE_COLUMNS}
    ev = model.accepted
    out["end"]["n_contact"] = 0 if ev is None else int(np.count_nonzero(ev.p > 0))
    return out
