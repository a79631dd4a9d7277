"""The console lines of a calibrated law: each branch's form that runs, its errors, the other form.

Built from the description every report shares (:func:`frictionlaw.describe.describe_law`, in
``summary.json`` as ``law``), so that the console, ``summary.json``, ``report.html`` and the
plots name the same law.
"""

__all__ = ["law_lines"]


def law_lines(cal, s):
    """The console lines of the law ``params.json`` runs, with the forms beside it.

    ``s``: the calibration's summary (its ``law`` record, the jump at ``p_hist``, the fits'
    notes).
    """
    from frictionlaw.describe import describe_law

    law = describe_law(cal.params)
    lines = [f"  the law the parameter file runs: {law.forms_label()}"]
    lines += [f"  {line}" for line in law.lines()]
    lines.append(
        f"  largest drop at p_hist {100 * s['max_jump_relative']:.2f} % of tau (the form that runs)"
    )
    lines += [f"  note: {n}" for n in s["fit_notes"]]
    return lines
