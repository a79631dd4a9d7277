"""The law's options of the command, and the console lines of a calibrated law."""

from ..pipeline.forms import form_names

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
        "sets how finely the levels are placed: heldout_tol / 10 in first loading, / 2 in "
        f"reload (default: {_D['heldout_tol']:g})",
    )


def _err(e):
    """``max / rms`` of a branch's errors: in sample, held out, and the extrapolations."""
    held = (
        f"held out {e['heldout_max']:.4f} / {e['heldout_rms']:.4f}"
        if e["heldout_max"] is not None
        else "held out: too few levels"
    )
    ext = e["extrapolation"]
    ext = f", top level extrapolated {ext['max_abs']:.4f}" if ext else ""
    low = e.get("extrapolation_below")
    low = f", lowest {low['max_abs']:.4f}" if low else ""
    return (
        f"|d alpha| max / rms in sample {e['in_sample_max']:.4f} / {e['in_sample_rms']:.4f}, "
        f"{held}{ext}{low}"
    )


def _first_labels(cal, s):
    P = cal.params
    labels = {
        "eq24": f"Eq. 24: C1 = {P.C1:.4g}, n1 = {P.n1:.4g}  (R^2 = {s['first_loading_r2']:.5f})"
    }
    t = cal.first_fits.get("tabulated")
    if t is not None:
        p = t.table.p
        labels["tabulated"] = (
            f"first loading tabulated: the computed points ({len(p)} levels {p[0] / 1e6:.4g}-"
            f"{p[-1] / 1e6:.4g} MPa), monotone cubic in ln p, Coulomb below the lowest"
        )
    return labels


def _reload_labels(cal, s):
    P = cal.params
    labels = {"paper": f"Eq. 25: C2 = {P.C2:.4g}, n2 = {P.n2:.4g}  (R^2 = {s['reload_r2']:.5f})"}
    if cal.reload_table is not None:
        t = cal.reload_table.table
        labels["tabulated"] = (
            f"Eq. 25 tabulated over p_hist ({len(t.p_hist)} levels {t.p_hist[0] / 1e6:.4g}-"
            f"{t.p_hist[-1] / 1e6:.4g} MPa): C2 {min(t.C2):.4g}-{max(t.C2):.4g}, n2 "
            f"{min(t.n2):.4g}-{max(t.n2):.4g}, s2 = {t.s2:.4g}"
        )
    return labels


def _branch(branch, running, labels, err):
    lines = [f"  {labels.get(running, running)}", "    " + _err(err[branch])]
    for name, label in labels.items():
        key = f"{branch}_{name}"
        if name != running and key in err:
            lines += [f"  beside it, {label}", "    " + _err(err[key])]
    return lines


def law_lines(cal, s):
    """The console lines of the fitted law: each branch with its measured errors."""
    err = s["errors"]
    lines = _branch("first_loading", cal.first_loading_form, _first_labels(cal, s), err)
    lines += _branch("reload", cal.reload_form, _reload_labels(cal, s), err)
    below = s.get("reload_below_first") or {}
    variant = (
        "continuous (meets first loading at p_hist)" if s.get("continuous_reload") else "as printed"
    )
    lines.append(
        f"  reload branch {variant}: largest drop at p_hist {100 * s['max_jump_relative']:.2f} % "
        f"of tau; reload curves below first loading by at most {below.get('max', 0.0):.4f} in "
        "alpha"
    )
    lines += [f"  note: {n}" for n in s["fit_notes"]]
    if cal.sweeps.plan is not None:
        lines += ["  " + line for line in cal.sweeps.plan.lines()]
    return lines
