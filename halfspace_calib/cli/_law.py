"""The law's options of the command, and the console lines of a calibrated law.

The lines name each branch's form that runs, its errors and the form beside it, built from the
description every report shares (:func:`frictionlaw.describe.describe_law`, in ``summary.json``
as ``law``), so that the console, ``summary.json``, ``report.html`` and the plots name the same
law.
"""

from ..pipeline.law.forms import form_names

__all__ = ["add_law_options", "law_lines"]


def add_law_options(g, _D):
    """The options that choose the law's forms and its acceptance, in the argument group ``g``.

    ``_D``: the scene's defaults by field name (shown in the help).
    """
    g.add_argument(
        "--continuous-reload",
        dest="continuous_reload",
        action="store_true",
        default=None,
        help="fit and run the reload branch that meets the first loading at p_hist (no drop "
        "of tau just below p_hist; default: on)",
    )
    g.add_argument(
        "--no-continuous-reload",
        dest="continuous_reload",
        action="store_false",
        help="the paper's Eq. 25 as printed, which may drop below the first loading at p_hist "
        "(default: off)",
    )
    g.add_argument(
        "--first-loading-form",
        choices=["auto", *form_names("first_loading")],
        help="the first-loading branch of params.json: the computed first loading, a monotone "
        "cubic in ln p through the points (tabulated), the paper's Eq. 24 with C1, n1 (eq24), or "
        "whichever predicts the held-out load levels better (auto); the other form's error is "
        "reported beside it (default: " + _D["first_loading_form"] + ")",
    )
    g.add_argument(
        "--reload-form",
        choices=["auto", *form_names("reload")],
        help="the reload branch of params.json: Eq. 25 with C2, n2 per load level "
        "(tabulated), the paper's one C2, n2 (paper), or whichever predicts the held-out load "
        "levels better (auto); the other form's error is reported beside it (default: "
        + _D["reload_form"]
        + ")",
    )
    g.add_argument(
        "--heldout-tol",
        type=float,
        help="what decides a run: the largest |d alpha| either branch of the law that runs may "
        "have on a load level it did not see (each interior level left out, the branch refitted "
        "and the level predicted; first loading: the points at one pressure, reload: one reload "
        "curve); beyond it the run fails with exit 1. The extrapolations above the top level and "
        f"below the lowest are reported, they do not decide; with the default pressures it also "
        "sets how finely the levels are placed: 0.1 of it in first loading, 0.3 in a reload "
        f"curve (default: {_D['heldout_tol']:g})",
    )


def law_lines(cal, s):
    """The console lines of the law ``params.json`` runs, with the forms beside it.

    ``s``: the calibration's summary (its ``law`` record, the drop at ``p_hist``, the reload
    curves below first loading, the fits' notes).
    """
    from frictionlaw.describe import describe_law

    law = describe_law(cal.params)
    lines = [f"  the law the parameter file runs: {law.forms_label()}"]
    lines += [f"  {line}" for line in law.lines()]
    below = s.get("reload_below_first") or {}
    lines.append(
        f"  largest drop at p_hist {100 * s['max_jump_relative']:.2f} % of tau; reload curves "
        f"below first loading by at most {below.get('max', 0.0):.4f} in alpha (the forms that run)"
    )
    lines += [f"  note: {n}" for n in s["fit_notes"]]
    if cal.sweeps.plan is not None:
        lines += ["  " + line for line in cal.sweeps.plan.lines()]
    return lines
