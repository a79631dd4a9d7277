"""Output of a calibration: parameter file, CSV tables of every curve, PNG plots, a summary."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ._files import write_csv

__all__ = ["REPORT_IMAGES", "calibration_figures", "write_outputs", "write_plots"]

#: the plots of every calibration and their captions in report.html
REPORT_IMAGES = [
    ("alpha_first_loading.png", "First loading: half-space model and the form that runs"),
    (
        "alpha_reload.png",
        "Un-/reloading curves: the form that runs (solid) and the form beside it (dotted)",
    ),
    ("roughness.png", "Workpiece roughness after unloading (Figs. 3-4)"),
    ("pressure_map.png", "Contact pressure map at the highest load"),
]


# columns of one normal solve, in the loading and the reload table: (record key, CSV header
# with its unit; dimensionless quantities carry none)
_SOLVE_COLUMNS = [
    ("alpha", "alpha"),
    ("converged", "converged"),
    ("nit", "nit"),
    ("residual", "residual"),
    ("max_pressure", "max_pressure_Pa"),
    ("plastic_fraction", "plastic_fraction"),
]
_SOLVE_HEADERS = [h for _, h in _SOLVE_COLUMNS]


def _solve_cells(rec):
    """The :data:`_SOLVE_COLUMNS` cells of a loading or reload record (``converged`` as 0/1)."""
    return [
        int(getattr(rec, k)) if k == "converged" else getattr(rec, k) for k, _ in _SOLVE_COLUMNS
    ]


def write_tables(cal, out):
    """``loading.csv``, ``reload.csv`` and ``roughness.csv`` (SI units in every header: Pa, m)."""
    lv = cal.sweeps.levels
    write_csv(
        out / "loading.csv",
        ["p_mean_Pa", *_SOLVE_HEADERS, "u0_m"],
        [[v.p_hist, *_solve_cells(v.loading), v.loading.u0] for v in lv],
    )
    write_csv(
        out / "reload.csv",
        ["p_hist_Pa", "p_mean_Pa", *_SOLVE_HEADERS],
        [[v.p_hist, r.p_mean, *_solve_cells(r)] for v in lv for r in v.reload],
    )
    rows = _roughness_rows(cal)
    write_csv(out / "roughness.csv", ["p_mean_Pa", "Ra_m", "Rq_m"], rows)


def _roughness_rows(cal):
    """``[p_mean, Ra, Rq]`` (Pa, m): the solver-grid workpiece (``p = 0``), then after each level."""
    wp = cal.sweeps.surfaces["workpiece"]
    h0 = np.asarray(wp.heights) - np.mean(wp.heights)
    rows = [[0.0, float(np.mean(np.abs(h0))), float(np.sqrt(np.mean(h0 * h0)))]]
    rows += [[v.p_hist, v.Ra_after, v.Rq_after] for v in cal.sweeps.levels]
    return rows


def _axes(figsize):
    """A new figure (not registered with pyplot) and its one axes."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize)
    return fig, fig.subplots()


def _beside(law, branch, P):
    """``[(form description, P running that form)]`` of the forms beside the one that runs."""
    from frictionlaw.forms import branch_form

    return [(f, branch_form(branch, f.form).switch(P)) for f in law.branch(branch).others]


def calibration_figures(cal):
    """The calibration's figures, for a notebook: nothing is written, pyplot is not touched.

    alpha against p with Eq. 24, the reload curves with Eq. 25, Ra/Rq after unloading against p,
    and the contact-pressure map of the highest level that kept one. :func:`write_plots` writes
    the same figures as PNG files.

    Parameters
    ----------
    cal : Calibration
        The result of :func:`~halfspace_calib.pipeline.calibration.calibrate`.

    Returns
    -------
    dict
        ``{PNG file name: matplotlib.figure.Figure}``, laid out.
    """
    figs = {}

    from frictionlaw import alpha_first, alpha_reload
    from frictionlaw.describe import describe_law

    P = cal.params
    law = describe_law(P)
    MPa = 1e6
    p, a = cal.sweeps.loading
    pp = np.linspace(0, max(p.max() * 1.1, 1.0), 300)
    first = law.branch("first_loading").running
    fig, ax = _axes((6.4, 4.6))
    ax.plot(p / MPa, a, "o", label="half-space model")
    ax.plot(pp / MPa, alpha_first(pp, P), "-", label=f"{first.label()} (runs)")
    for f, other in _beside(law, "first_loading", P):  # for comparison
        ax.plot(pp / MPa, alpha_first(pp, other), ":", label=f"{f.label()}, beside it (not run)")
    ax.set(xlabel="p_mean [MPa]", ylabel="alpha_rc = A_real / A0")
    ax.set_title(law.title("first_loading"), fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    figs["alpha_first_loading.png"] = fig

    reload = law.branch("reload")
    runs = reload.running
    beside = _beside(law, "reload", P)
    fig, ax = _axes((6.4, 4.8))
    ax.plot(pp / MPa, alpha_first(pp, P), "k-", lw=1, label=f"{first.name} (first loading)")
    hists = []  # several samples share a p_hist: one colour and one fitted curve each
    for c in cal.sweeps.reload_curves():
        new = c.p_hist not in hists
        hists += [c.p_hist] if new else []
        col = f"C{hists.index(c.p_hist) % 10}"
        ax.plot(c.p / MPa, c.alpha, "o", color=col, ms=4)
        if new:
            q = np.linspace(0, c.p_hist, 100)
            ax.plot(
                q / MPa,
                alpha_reload(q, c.p_hist, P),
                "-",
                color=col,
                label=f"p_hist = {c.p_hist / MPa:.0f} MPa",
            )
    for f, other in beside:  # the forms beside the one that runs, for comparison
        for k, ph in enumerate(hists):
            q = np.linspace(0, ph, 100)
            ax.plot(
                q / MPa,
                alpha_reload(q, ph, other),
                ":",
                color="0.45",
                lw=1,
                label=f"{f.name}, beside it (not run)" if k == 0 else None,
            )
    ax.set(xlabel="p_mean [MPa]", ylabel="alpha_rc")
    ax.set_title(law.title("reload"), fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, title=f"runs: {runs.name}", title_fontsize=7)
    figs["alpha_reload.png"] = fig

    lv = cal.sweeps.levels
    rows = _roughness_rows(cal)
    fig, ax = _axes((6, 4.2))
    pr = np.array([r[0] for r in rows]) / MPa
    ax.plot(pr, [r[1] * 1e6 for r in rows], "o-", label="Ra")
    ax.plot(pr, [r[2] * 1e6 for r in rows], "s-", label="Rq")
    ax.set(
        xlabel="p_mean [MPa] (0: as measured)",
        ylabel="roughness after unloading [um] (roughness.csv: m)",
        title="Workpiece roughness after unloading (Figs. 3-4)",
    )
    ax.grid(alpha=0.3)
    ax.legend()
    figs["roughness.png"] = fig

    maps = [v for v in lv if v.pressure_map is not None]
    if maps:
        v = maps[-1]
        wp = cal.sweeps.surfaces["workpiece"]
        fig, ax = _axes((5.4, 4.6))
        ext = [0, wp.shape[1] * wp.dy * 1e3, 0, wp.shape[0] * wp.dx * 1e3]
        im = ax.imshow(v.pressure_map / MPa, origin="lower", extent=ext, cmap="viridis")
        fig.colorbar(im, ax=ax, label="p [MPa]")
        ax.set(
            xlabel="y [mm]",
            ylabel="x [mm]",
            title=f"Contact pressure at p_mean = {v.p_hist / MPa:.0f} MPa",
        )
        figs["pressure_map.png"] = fig
    for fig in figs.values():
        fig.tight_layout()
    return figs


def write_plots(cal, out):
    """Write :func:`calibration_figures` as PNG files (120 dpi) into ``out``.

    Returns
    -------
    dict
        ``{file name: matplotlib Figure}`` of the plots written.
    """
    figs = calibration_figures(cal)
    for name, fig in figs.items():
        fig.savefig(Path(out) / name, dpi=120)
    return figs


def write_outputs(cal, out, *, clock=None):
    """Write ``params.json``, the CSV tables, the plots and ``summary.json`` into ``out``.

    Each modelled effect writes its CSV and PNG into a subfolder: ``tangential/``,
    ``geometric/`` (the inclined patches) and ``sliding/``. ``clock()``: the command's run time
    so far (:func:`sbmf_cli.process_seconds`), read when every other file is written and recorded
    in ``summary.json`` as ``command_seconds`` beside ``seconds`` (the calibration's solves and
    fits); the command reports that number.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    cal.params.to_json(out / "params.json")
    write_tables(cal, out)
    write_plots(cal, out)
    from .effects import write_effect_outputs

    write_effect_outputs(cal, out)
    if getattr(cal, "flattening", None):
        from .flattening import write_flattening

        write_flattening(cal, out)
    summary = cal.summary()  # one record for summary.json and report.html
    if clock is not None:
        summary["command_seconds"] = clock()
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=float) + "\n")
    from .html import write_report

    write_report(summary, out, REPORT_IMAGES)
    return out
