"""The files of a ring fit (``fe-demo ring-fit``)."""

from __future__ import annotations

import csv
import html
import json
from pathlib import Path

import numpy as np

from sbmf_cli.htmlpage import figure, number_cell, page

__all__ = ["write_ring_fit"]


def write_ring_fit(out, test, fit, chart, params, record):
    """The files of a ring fit in ``out``.

    ring_fit.json, params.json, ring_fit.csv, ring_fit.png and report.html. ``test``, ``fit`` and ``chart`` are the measured tests and the two fits
    (:mod:`fe_demo.analysis.ringfit`); ``params`` the fitted law's parameter set (``None`` for
    the chart's law alone); ``record`` the ``ring_fit.json`` record.
    """
    out = Path(out)
    (out / "ring_fit.json").write_text(json.dumps(record, indent=2, default=str) + "\n")
    if params is not None:
        prov = dict(params.provenance)
        prov["ring_test"] = {k: record[k] for k in record if k != "software"}
        params.replace(m=fit.m, provenance=prov).to_json(out / "params.json")
    pred = fit.predict(test.reduction)
    with (out / "ring_fit.csv").open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(
            ["height_reduction", f"{test.column}_measured", f"{test.column}_fit", "residual"]
        )
        for r, d, p in zip(test.reduction, test.d_inner, pred, strict=True):
            w.writerow([f"{r:.6g}", f"{d:.6g}", f"{p:.6g}", f"{d - p:.6g}"])
    _plot(out / "ring_fit.png", test, fit, chart)
    rows = "".join(
        f"<tr><td>{k}</td>{number_cell(record[k], k)}</tr>"
        for k in ("m", "m_lower", "m_upper", "rmse", "m_tresca_chart", "bias_chart_minus_law")
    )
    body = [
        f"<p>law {html.escape(fit.law)}, {fit.n_points} points ({html.escape(test.column)}), "
        f"{record['n_fe_runs']} FE runs, band {100 * fit.band_level:g} %</p>",
        f"<table><tr><th>quantity</th><th>value</th></tr>{rows}</table>",
        figure(
            out / "ring_fit.png", "measured points, the fitted curve with its band, Tresca curves"
        ),
    ]
    (out / "report.html").write_text(page("fe-demo ring-fit", body), encoding="utf-8")


def _plot(path, test, fit, chart):
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.4))
    ax = fig.subplots()
    r = np.linspace(0.0, float(test.reduction.max()), 60)[1:]
    for m in sorted(chart.curves):
        red, d = chart.curves[m]
        ax.plot(100 * red, 100 * d, color="0.75", lw=0.8)
        ax.annotate(f"{m:.3g}", (100 * red[-1], 100 * d[-1]), fontsize=7, color="0.5")
    ax.fill_between(
        100 * r,
        100 * fit.predict(r, fit.m_lower),
        100 * fit.predict(r, fit.m_upper),
        alpha=0.3,
        label=f"{100 * fit.band_level:g} % band on m",
    )
    ax.plot(100 * r, 100 * fit.predict(r), "C0", label=f"{fit.law}, m = {fit.m:.3f}")
    ax.plot(100 * test.reduction, 100 * test.d_inner, "ko", ms=4, label="measured")
    ax.plot([], [], color="0.75", label="Tresca, m as labelled")
    ax.set_xlabel("height reduction (%)")
    ax.set_ylabel(f"{test.column.replace('_', ' ')} (%)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
