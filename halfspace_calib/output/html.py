"""``report.html``: one self-contained page of a calibration (images embedded, no network).

Built from the same record as ``summary.json`` (the calibration's ``summary()`` dict) and the
PNG files the writers produced, never parsed back from ``summary.json``. Every number of the
record that the page shows carries ``data-key="<dotted path in summary.json>"`` so that a
reader (or a test) can check the page against the file.
"""

from __future__ import annotations

import html
from pathlib import Path

from sbmf_cli.htmlpage import figure, law_section, number_cell, page

from .flattening import flattening_section

__all__ = ["write_report"]


def _list(items, cls=""):
    if not items:
        return "<p>none</p>"
    c = f" class='{cls}'" if cls else ""
    return "<ul>" + "".join(f"<li{c}>{html.escape(str(i))}</li>" for i in items) + "</ul>"


def _checks_table(s):
    """The checks of the fit beside the law: the drop at p_hist, the bound alpha >= p/H."""
    rows = [
        ("heldout_tol", "tolerance of the held-out |d alpha| (--heldout-tol)"),
        ("max_jump_relative", "largest drop at p_hist / tau, of the form that runs"),
        ("alpha_bound_violation_to_p_max", "largest p/H - alpha1(p) up to p_max (alpha >= p/H)"),
        ("alpha_bound_violation_to_H", "largest p/H - alpha1(p) up to H (Eq. 24 < 1 at H)"),
        ("alpha1_at_H", "alpha1(H) of Eq. 24 (the model's limit: 1)"),
        ("alpha_bound_r2_cost", "R^2 given up for the bound alpha1 >= p/H"),
    ]
    out = ["<table><tr><th>quantity</th><th>value</th><th>meaning</th></tr>"]
    for k, what in rows:
        out.append(
            f"<tr><td class='t'>{k}</td>{number_cell(s.get(k), k)}<td class='t'>{what}</td></tr>"
        )
    out.append("</table>")
    return "".join(out)


def _uncertainty(s):
    u = s.get("uncertainty")
    if not u:
        return ""
    out = [
        f"<h2>Band over {s['samples']['calibrated']} samples "
        f"({100 * u['level']:g} % bootstrap, {u['n_bootstrap']} resamples, "
        f"{html.escape(str(u.get('band_method', 'percentile')))} band)</h2>",
        "<table><tr><th>quantity</th><th>pooled</th><th>lower</th><th>upper</th></tr>",
    ]
    for k, v in u["parameters"].items():
        out.append(
            f"<tr><td class='t'>{k}</td>"
            + "".join(number_cell(v[f], f"uncertainty.parameters.{k}.{f}") for f in v)
            + "</tr>"
        )
    for p, v in u["tau_first_at"].items():
        out.append(
            f"<tr><td class='t'>tau at {html.escape(p)} [Pa]</td>"
            + "".join(number_cell(v[f], f"uncertainty.tau_first_at.{p}.{f}") for f in v)
            + "</tr>"
        )
    out.append(
        "</table><h3>Per-sample laws (Eq. 24 and the paper's Eq. 25, the band's parameters)"
        "</h3><table><tr><th>sample</th>"
    )
    keys = ("C1", "n1", "C2", "n2")
    out.append("".join(f"<th>{k}</th>" for k in keys) + "</tr>")
    for i, x in enumerate(s["samples"]["per_sample"]):
        out.append(
            f"<tr><td class='t'>{html.escape(x['name'])}</td>"
            + "".join(number_cell(x[k], f"samples.per_sample.{i}.{k}") for k in keys)
            + "</tr>"
        )
    out.append("</table>")
    if s["samples"]["failed"]:
        out.append(
            "<p class='bad'>Failed samples:</p>"
            + _list([f"{n}: {e}" for n, e in s["samples"]["failed"].items()], "bad")
        )
    return "".join(out)


def _files(s):
    files = s.get("files") or []
    if not files:
        return "<p>synthetic surfaces (Table 1), no files</p>"
    out = [
        "<table><tr><th>sample/role</th><th>file</th><th>format</th><th>points</th>"
        "<th>size [um]</th><th>unit</th><th>undefined</th><th>steps</th><th>sha256</th></tr>"
    ]
    for f in files:
        who = f"{f.get('sample', '')} {f['role']}".strip()
        out.append(
            f"<tr><td class='t'>{html.escape(who)}</td><td class='t'>{html.escape(f['path'])}</td>"
            f"<td class='t'>{html.escape(f['format'])}</td>"
            f"<td>{f['native_shape'][0]} x {f['native_shape'][1]}</td>"
            f"<td>{f['native_size'][0] * 1e6:.4g} x {f['native_size'][1] * 1e6:.4g}</td>"
            f"<td class='t'>{html.escape(f['unit'])} ({html.escape(f['unit_source'])})</td>"
            f"<td>{100 * f['undefined_fraction']:.2f} %</td>"
            f"<td class='t'>{html.escape('; '.join(f['steps']))}</td>"
            f"<td class='t'><code>{html.escape(f['sha256'])}</code></td></tr>"
        )
    out.append("</table>")
    return "".join(out)


def _resolution(s):
    rc = s.get("resolution_check")
    if rc is None:
        why = "not run" + (
            " (multi-sample calibration: run one sample alone for it)" if s.get("samples") else ""
        )
        return f"<p>{why}</p>"
    if rc.get("skipped"):
        return f"<p>skipped: {html.escape(rc['skipped'])}</p>"
    out = [
        f"<p>grid {rc['grid']} against {rc['half_grid']}</p><table><tr><th>parameter</th>"
        "<th>grid</th><th>half grid</th><th>change</th></tr>"
    ]
    for key, label in (("params", "{k}"), ("beside_not_run", "{k} (beside it, not run)")):
        for k, (a, b, d) in rc.get(key, {}).items():
            out.append(
                f"<tr><td class='t'>{html.escape(label.format(k=k))}</td>"
                f"{number_cell(a, f'resolution_check.{key}.{k}.0')}"
                f"{number_cell(b, f'resolution_check.{key}.{k}.1')}<td>{100 * d:.2f} %</td></tr>"
            )
    out.append("</table>")
    for k, v in rc.get("law_alpha", {}).items():
        out.append(f"<p>{html.escape(k)} alpha of the law that runs: up to {100 * v:.2f} %</p>")
    if rc.get("warning"):
        out.append(f"<p class='bad'>{html.escape(rc['warning'])}</p>")
    return "".join(out)


def _levels(s):
    """The computed load levels and why (adaptive refinement or given), from ``summary.json``."""
    lv = s.get("levels")
    if not lv:
        return "<p>not recorded</p>"
    head = "refined where alpha changes" if lv["adaptive"] else "given, computed as given"
    rows = "".join(
        f"<tr><td>{r['p'] / 1e6:.4g}</td><td>{'yes' if r['reload'] else ''}</td>"
        f"<td>{r['round']}</td><td>{html.escape(r['reason'])}</td></tr>"
        for r in lv["levels"]
    )
    return (
        f"<p>{len(lv['levels'])} levels, {head}</p><table><tr><th>p (MPa)</th><th>reload</th>"
        f"<th>round</th><th>why</th></tr>{rows}</table>" + _list(lv.get("decisions", []))
    )


def write_report(summary, out, images, title="Friction law calibration"):
    """Write ``out/report.html`` from the summary record and the PNGs ``[(file, caption)]``."""
    s = summary
    out = Path(out)
    warnings = []
    rc = s.get("resolution_check") or {}
    if rc.get("warning"):
        warnings.append(rc["warning"])
    body = [
        f"<p>grid {s.get('grid')} x {s.get('grid')}, periodic: {s.get('periodic')}, "
        f"run time {s.get('seconds', 0):.1f} s</p>",
        "<h2>The law the parameter file runs</h2>",
        law_section(s["law"], "law"),
        "<h2>Checks of the fit</h2>",
        _checks_table(s),
        _uncertainty(s),
        flattening_section(s, out),
        "<h2>Curves</h2>",
        "".join(figure(out / f, c) for f, c in images),
        "<h2>Load levels</h2>",
        _levels(s),
        "<h2>Resolution check</h2>",
        _resolution(s),
        "<h2>Files (provenance)</h2>",
        _files(s),
        "<h2>Warnings</h2>",
        _list(warnings),
        "<h2>Problems</h2>",
        _list(s.get("problems", []), "bad"),
    ]
    path = out / "report.html"
    path.write_text(page(title, "\n".join(body)), encoding="utf-8")
    return path
