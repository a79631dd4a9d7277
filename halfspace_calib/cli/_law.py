"""The console lines of a calibrated law: each branch with its measured errors."""

__all__ = ["law_lines"]


def _err(e):
    """``max / rms`` of a branch's errors: in sample, held out, and the extrapolation."""
    held = (
        f"held out {e['heldout_max']:.4f} / {e['heldout_rms']:.4f}"
        if e["heldout_max"] is not None
        else "held out: fewer than 3 levels"
    )
    ext = e["extrapolation"]
    ext = f", top level extrapolated {ext['max_abs']:.4f}" if ext else ""
    return f"|d alpha| max / rms in sample {e['in_sample_max']:.4f} / {e['in_sample_rms']:.4f}, {held}{ext}"


def law_lines(cal, s):
    """The console lines of the fitted law: each branch with its measured errors."""
    P, err = cal.params, s["errors"]
    lines = [
        f"  Eq. 24: C1 = {P.C1:.4g}, n1 = {P.n1:.4g}  (R^2 = {s['first_loading_r2']:.5f})",
        "    " + _err(err["first_loading"]),
    ]
    jump = f"largest jump at p_hist {100 * s['max_jump_relative']:.2f} % of tau"
    paper = f"C2 = {P.C2:.4g}, n2 = {P.n2:.4g}  (R^2 = {s['reload_r2']:.5f}"
    t = cal.reload_table.table if cal.reload_table is not None else None
    table = (
        f"Eq. 25 tabulated over p_hist ({len(t.p_hist)} levels {t.p_hist[0] / 1e6:.4g}-"
        f"{t.p_hist[-1] / 1e6:.4g} MPa): C2 {min(t.C2):.4g}-{max(t.C2):.4g}, n2 "
        f"{min(t.n2):.4g}-{max(t.n2):.4g}, s2 = {t.s2:.4g}"
        if t is not None
        else ""
    )
    if cal.reload_form == "tabulated":
        lines += [
            f"  {table}  ({jump})",
            "    " + _err(err["reload"]),
            f"  the paper's Eq. 25 beside it: {paper})",
            "    " + _err(err["reload_paper"]),
        ]
    else:
        lines += [f"  Eq. 25: {paper}, {jump})", "    " + _err(err["reload"])]
        if t is not None:
            lines += [
                f"  {table}, beside it",
                "    " + _err(err["reload_tabulated"]),
            ]
    lines += [f"  note: {n}" for n in s["fit_notes"]]
    return lines
