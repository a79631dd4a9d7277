"""The files of a ring fit (``fe-demo ring-fit``)."""

from __future__ import annotations

import csv
import html
import json
from pathlib import Path

import numpy as np

from sbmf_cli import column_name
from sbmf_cli.htmlpage import figure, number_cell, page

__all__ = ["input_rows", "ring_fit_figure", "write_ring_fit"]


def write_ring_fit(out, test, fit, chart, params, record):
    """The files of a ring fit in ``out``.

    ring_fit.json, params.json (``params``, the law's parameter set with the fitted ``m``;
    ``None`` for the chart's law alone), ring_fit.csv, ring_fit.png and report.html. ``test``,
    ``fit`` and ``chart`` are the measured tests and the two fits
    (:mod:`fe_demo.analysis.ringfit`); ``record`` the ``ring_fit.json`` record.
    """
    out = Path(out)
    (out / "ring_fit.json").write_text(json.dumps(record, indent=2, default=str) + "\n")
    if params is not None:
        params.to_json(out / "params.json")
    pred = fit.predict(test.reduction)
    with (out / "ring_fit.csv").open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                column_name("height_reduction", "fraction"),
                column_name(f"{test.column}_measured", "fraction"),
                column_name(f"{test.column}_fit", "fraction"),
                column_name("residual", "fraction"),
            ]
        )
        for r, d, p in zip(test.reduction, test.d_inner, pred, strict=True):
            w.writerow([f"{r:.6g}", f"{d:.6g}", f"{p:.6g}", f"{d - p:.6g}"])
    ring_fit_figure(test, fit, chart).savefig(out / "ring_fit.png", dpi=120)
    rows = "".join(
        f"<tr><td>{k}</td>{number_cell(record[k], k)}<td></td></tr>"
        for k in ("m", "m_lower", "m_upper", "m_tresca_chart", "bias_chart_minus_law")
    )
    rows += (
        f"<tr><td>rmse of {html.escape(test.column)}</td>"
        f"{number_cell(record['rmse_fraction'], 'rmse_fraction', '.4g', 100.0)}"
        "<td>% (percentage points)</td></tr>"
    )
    body = [
        f"<p>law {html.escape(fit.law)}"
        + (" (<b>illustrative</b>, not a calibration)" if record.get("illustrative") else "")
        + f", {fit.n_points} points ({html.escape(test.column)}), {record['n_fe_runs']} FE "
        f"runs, band {100 * fit.band_level:g} %</p>",
        "<h2>Inputs</h2>",
        _inputs_table(record),
        "<h2>Result</h2>",
        f"<table><tr><th>quantity</th><th>value</th><th>unit</th></tr>{rows}</table>",
        figure(
            out / "ring_fit.png", "measured points, the fitted curve with its band, Tresca curves"
        ),
    ]
    (out / "report.html").write_text(page("fe-demo ring-fit", body), encoding="utf-8")


def _inputs_table(record):
    """The files, ring and material the fit ran on, as an HTML table."""
    cells = "".join(
        "<tr>" + "".join(f"<td class='t'>{html.escape(str(c))}</td>" for c in row) + "</tr>"
        for row in input_rows(record)
    )
    return f"<table><tr><th>input</th><th>what</th><th>source</th></tr>{cells}</table>"


def input_rows(record):
    """``[(input, what, source)]``: the files, ring and material a fit ran on (its record's).

    The parameter file and the ring-test files with their sha256, the ring and the material with
    where each came from (an option, the files' header, a default).
    """
    rows = []
    src = record.get("source_params")
    if src:
        what = "illustrative law (shipped)" if src.get("illustrative") else "parameter file"
        rows.append((what, src["path"], f"sha256 {src['sha256']}"))
    for f in record.get("measured_files", []):
        rows.append(("ring tests", f["path"], f"sha256 {f['sha256']}"))
    g, m = record["geometry_m"], record["material"]
    ring = (
        f"OD {1e3 * g['outer_diameter']:g} mm, ID {1e3 * g['inner_diameter']:g} mm, "
        f"H {1e3 * g['height']:g} mm"
    )
    material = (
        f"E {m['E'] / 1e9:g} GPa, nu {m['nu']:g}, K {m['K'] / 1e6:g} MPa, eps0 {m['eps0']:g}, "
        f"n {m['n']:g}"
    )
    rows.append(("ring", ring, record.get("geometry_source", "")))
    rows.append(("material", material, record.get("material_source", "")))
    return rows


def ring_fit_figure(test, fit, chart):
    """The plot of a ring fit: points, the fitted curve with its band, the Tresca runs.

    Each Tresca run of the chart's fit is a grey curve; the grid's runs are labelled with their
    ``m`` at the curve's end (a label that would overlap another is left out), the refinement
    runs near the optimum are not, and the chart's fitted ``m`` is its own dashed curve, labelled
    with the digits the console and ``ring_fit.json`` give.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.4))
    FigureCanvasAgg(fig)  # a renderer, to place the labels without overlaps
    ax = fig.subplots()
    r = np.linspace(0.0, float(test.reduction.max()), 60)[1:]
    for m in sorted(chart.curves):
        red, d = chart.curves[m]
        ax.plot(100 * red, 100 * d, color="0.75", lw=0.8)
    if chart is not fit:
        ax.plot(
            100 * r,
            100 * chart.predict(r),
            color="0.4",
            lw=1.0,
            ls="--",
            label=f"Tresca chart's fit, m = {chart.m:.4f}",
        )
    ax.fill_between(
        100 * r,
        100 * fit.predict(r, fit.m_lower),
        100 * fit.predict(r, fit.m_upper),
        alpha=0.3,
        label=f"{100 * fit.band_level:g} % band on m",
    )
    ax.plot(100 * r, 100 * fit.predict(r), "C0", label=f"{fit.law}, m = {fit.m:.4f}")
    ax.plot(100 * test.reduction, 100 * test.d_inner, "ko", ms=4, label="measured")
    ax.plot([], [], color="0.75", label="Tresca runs, m as labelled")
    ax.set_xlabel("height reduction (%)")
    ax.set_ylabel(f"{test.column.replace('_', ' ')} (%)")
    ax.legend(fontsize=8)
    ax.set_xlim(right=100 * max(c[0][-1] for c in chart.curves.values()) * 1.1)  # room for labels
    fig.tight_layout()
    _label_runs(fig, ax, {m: c for m, c in chart.curves.items() if m not in chart.refined})
    return fig


def _label_runs(fig, ax, curves):
    """Label each Tresca run with its ``m`` at its end, leaving out labels that would overlap."""
    renderer = fig.canvas.get_renderer()
    placed = []
    for m in sorted(curves):
        red, d = curves[m]
        text = ax.annotate(f"{m:g}", (100 * red[-1], 100 * d[-1]), fontsize=7, color="0.5")
        box = text.get_window_extent(renderer)
        if any(box.overlaps(other) for other in placed):
            text.remove()
        else:
            placed.append(box)
