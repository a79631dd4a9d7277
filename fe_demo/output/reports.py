"""The report pages of fe-demo's runs (``report.html``) and the calibrated range's console lines."""

from __future__ import annotations

import html
from pathlib import Path

from sbmf_cli.htmlpage import figure, number_cell, page

__all__ = ["range_lines", "write_band_report", "write_run_report"]


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
    out = []
    limit = w.get("n_above_H", 0) or w.get("n_hist_above_H", 0)
    if w["n_above_range"] == 0 and w["n_hist_above_range"] == 0 and not limit:
        out.append(
            head + f"every contact pressure inside (peak p/p_max {w['p_peak_over_p_max']:.2f})"
        )
    elif w["n_above_range"] == 0 and w["n_hist_above_range"] == 0:
        out.append(head + "no node between p_max and H: the law is not extrapolated")
    else:
        out.append(
            head + f"law EXTRAPOLATED between p_max and H: at the end {e['n_above_range']} of "
            f"{e['n_contact']} contact nodes there (p_hist: {_nodes(e['n_hist_above_range'])}); "
            f"over the run at most {_nodes(w['n_above_range'])}; {e['n_below_range']} contact "
            f"nodes below p_min at the end"
        )
    if limit:
        out.append(
            f"[{label}] at the half-space model's limit p >= H = {rec['H_Pa'] / 1e6:g} MPa "
            f"(full contact, alpha = 1; the law gives alpha1(H) = {rec['alpha1_at_H']:.4f}): "
            f"at the end {e['n_above_H']} of {e['n_contact']} contact nodes (p up to "
            f"{e['p_peak'] / 1e6:.0f} MPa, p_hist >= H: {_nodes(e['n_hist_above_H'])}); over the "
            f"run at most {_nodes(w['n_above_H'])}"
        )
    return out


def _nodes(k):
    """``"1 node"``, ``"3 nodes"``."""
    return f"{k} node" if k == 1 else f"{k} nodes"


def write_run_report(folder, info, title):
    """``report.html`` of one ordinary run from its summary.json record ``info``.

    Run status, end of run, the calibrated-range report and the run's plots (force-stroke,
    die profile; the ring chart where the folder has one).
    """
    folder = Path(folder)
    rows = [
        ("converged", info.get("converged")),
        ("stopped_at_height_reduction", info.get("stopped_at_height_reduction")),
        ("wall_time_s", info.get("wall_time_s")),
    ]
    if "inner_diameter_change" in info:  # a ring test's measured quantities, at the end
        rows.insert(2, ("inner_diameter_change", info["inner_diameter_change"]))
        rows.insert(3, ("inner_diameter_min_change", info["inner_diameter_min_change"]))
    body = ["<table><tr><th>quantity</th><th>value</th></tr>"]
    for k, v in rows:
        cell = number_cell(v, k) if isinstance(v, float) else f"<td>{html.escape(str(v))}</td>"
        body.append(f"<tr><td>{k}</td>{cell}</tr>")
    body.append("</table>")
    body.append(f"<p>{html.escape(str(info.get('message', '')))}</p>")
    body.append("<h2>Calibrated range</h2>")
    lines = range_lines(title, info.get("calibrated_range")) or ["law without parameters"]
    body.append("<ul>" + "".join(f"<li>{html.escape(x)}</li>" for x in lines) + "</ul>")
    for fname, cap in (
        ("force_stroke.png", "force against height reduction"),
        ("die_profile.png", "pressure, shear and p_hist along the die"),
        ("../ring_chart.png", "ring chart"),
        ("ring_chart.png", "ring chart"),
    ):
        body.append(figure(folder / fname, cap))
    (folder / "report.html").write_text(page(f"fe-demo: {title}", body), encoding="utf-8")


def write_band_report(out, rec, images):
    """``report.html`` of a band run from its summary record (numbers carry their summary.json path)."""
    out = Path(out)
    body = [
        f"<p>scene {html.escape(rec['scene'])}, {html.escape(rec['meaning'])}"
        + (f" at {100 * rec['level']:g} %" if rec["mode"] == "band" else "")
        + "</p>"
    ]
    for key in [k for k in rec if k.endswith("_at")]:
        body.append(
            f"<h2>{html.escape(key[:-3])} [{html.escape(next(iter(rec[key].values()))['unit'])}]"
            "</h2><table><tr><th>height reduction</th><th>central</th><th>lower</th>"
            "<th>upper</th><th>+-</th></tr>"
        )
        for red, v in rec[key].items():
            body.append(
                f"<tr><td>{html.escape(red)}</td>"
                + "".join(
                    number_cell(v[f], f"{key}.{red}.{f}")
                    for f in ("central", "lower", "upper", "plus_minus")
                )
                + "</tr>"
            )
        body.append("</table>")
    body += [figure(out / fname, cap) for fname, cap in images]
    body.append(
        "<h2>Runs</h2><table><tr><th>run</th><th>converged</th><th>message</th>"
        "<th>calibrated range</th></tr>"
    )
    for name, s in rec["runs"].items():
        rng = "; ".join(range_lines(name, s.get("calibrated_range"))) or "-"
        body.append(
            f"<tr><td>{html.escape(name)}</td><td>{s['converged']}</td>"
            f"<td>{html.escape(str(s.get('message', '')))}</td><td>{html.escape(rng)}</td></tr>"
        )
    body.append("</table>")
    title = f"fe-demo {rec['scene']}: the friction law's band carried to the FE result"
    doc = page(title, body)
    (out / "report.html").write_text(doc, encoding="utf-8")
