"""Contact pressures against the law's calibrated range, per increment and over a run.

With a parameter file that records its ``calibrated_range`` (``p_min, p_max``), every
accepted increment gets the columns of :data:`RANGE_COLUMNS` (from
:func:`frictionlaw.check_pressure_range` on the die's contact nodes), and the run's
``summary.json`` a ``calibrated_range`` record: the range, the worst increment (the largest
count and peak over the run) and the last one. Laws without parameters (Coulomb, Tresca,
cap) add nothing; an SBMF parameter set without a range says so.
"""

import numpy as np

from frictionlaw import check_pressure_range

__all__ = ["RANGE_COLUMNS", "range_columns", "range_summary", "range_lines"]

#: history columns (per accepted increment) when the law has a calibrated range
RANGE_COLUMNS = (
    "n_above_range",  # contact nodes with p > p_max
    "n_hist_above_range",  # nodes with p_hist > p_max
    "n_below_range",  # contact nodes with 0 < p < p_min
    "p_peak",  # largest contact pressure (Pa)
    "p_hist_peak",  # largest p_hist (Pa)
    "p_peak_over_p_max",  # p_peak / p_max
)


def _params(model):
    return getattr(model.contact.law, "params", None)


def range_columns(model):
    """The :data:`RANGE_COLUMNS` of the accepted state, or ``{}`` without a range."""
    ev = model.accepted
    c = check_pressure_range(_params(model), ev.p, model.contact.state.p_hist)
    if c is None:
        return {}
    vals = (c.n_above, c.n_hist_above, c.n_below, c.p_peak, c.p_hist_peak, c.ratio)
    return dict(zip(RANGE_COLUMNS, vals, strict=True))


def range_summary(model, history):
    """The ``calibrated_range`` record of ``summary.json``.

    Returns ``None`` for laws without parameters, a note for a parameter set without a
    range, else ``p_min_Pa``, ``p_max_Pa``, ``max_over_run`` and ``end`` (each the columns
    of :data:`RANGE_COLUMNS`, plus ``n_contact`` at the end).
    """
    params = _params(model)
    if params is None:
        return None
    if params.p_range is None:
        return {"note": "the parameter file records no calibrated_range: not checked"}
    out = {"p_min_Pa": params.p_range[0], "p_max_Pa": params.p_range[1]}
    if not history or RANGE_COLUMNS[0] not in history:
        return out
    out["max_over_run"] = {k: np.max(history[k]).item() for k in RANGE_COLUMNS}
    out["end"] = {k: np.asarray(history[k])[-1].item() for k in RANGE_COLUMNS}
    ev = model.accepted
    out["end"]["n_contact"] = 0 if ev is None else int(np.count_nonzero(ev.p > 0))
    return out


def range_lines(label, rec):
    """Console lines for one run's ``calibrated_range`` record (none for ``None``)."""
    if rec is None:
        return []
    if "note" in rec:
        return [f"[{label}] calibrated range: {rec['note']}"]
    lo, hi = rec["p_min_Pa"] / 1e6, rec["p_max_Pa"] / 1e6
    if "end" not in rec:
        return [f"[{label}] calibrated range {lo:g}-{hi:g} MPa: no accepted increment"]
    e, w = rec["end"], rec["max_over_run"]
    head = f"[{label}] calibrated range {lo:g}-{hi:g} MPa: "
    if w["n_above_range"] == 0 and w["n_hist_above_range"] == 0:
        return [head + f"every contact pressure inside (peak p/p_max {w['p_peak_over_p_max']:.2f})"]
    return [
        head + f"law EXTRAPOLATED beyond p_max: at the end {e['n_above_range']} of "
        f"{e['n_contact']} contact nodes above (p up to {e['p_peak'] / 1e6:.0f} MPa, "
        f"p/p_max {e['p_peak_over_p_max']:.2f}; p_hist up to {e['p_hist_peak'] / 1e6:.0f} MPa, "
        f"{e['n_hist_above_range']} nodes); over the run at most {w['n_above_range']} nodes "
        f"above, p/p_max up to {w['p_peak_over_p_max']:.2f}; {e['n_below_range']} contact "
        f"nodes below p_min at the end",
    ]
