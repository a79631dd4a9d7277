"""The report pages of fe-demo's runs (``report.html``) and the calibrated range's console lines."""

from __future__ import annotations

import html
from pathlib import Path

from sbmf_cli.htmlpage import figure, law_section, number_cell, page

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


def _row(what, value, key, unit="", scale=None, fmt=".5g"):
    """A table row: what, the number (its ``data-key`` in summary.json), the unit shown."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        cell = number_cell(value, key, fmt, scale)
    else:
        cell = f"<td class='t'>{html.escape(str(value))}</td>"
    return f"<tr><td class='t'>{html.escape(what)}</td>{cell}<td class='t'>{unit}</td></tr>"


def _table(rows):
    head = "<table><tr><th>quantity</th><th>value</th><th>unit</th></tr>"
    return head + "".join(rows) + "</table>"


def _result(info):
    """The numbers a forming engineer hands on: the force at the end, where the run ended."""
    rows = [
        _row("die force at the end", info.get("force_end_N"), "force_end_N", "kN", 1e-3, ".5g"),
        _row(
            "height reduction at the end",
            info.get("stopped_at_height_reduction"),
            "stopped_at_height_reduction",
            "%",
            100.0,
            ".4g",
        ),
    ]
    for key, what in (
        ("inner_diameter_change", "inner diameter change at the mid-plane"),
        ("inner_diameter_min_change", "change of the smallest inner diameter"),
    ):
        if key in info:  # a ring test's measured quantities, at the end
            rows.append(_row(what, info[key], key, "%", 100.0, ".4g"))
    rows.append(_row("converged", "yes" if info.get("converged") else "NO", "converged"))
    return _table(rows) + f"<p>{html.escape(str(info.get('message', '')))}</p>"


def _law(info):
    """The friction law the run used: for sbmf the parameter file's law, described."""
    lp = info.get("law_parameters") or {}
    name = info.get("law", "")
    if "law" in lp:  # the SBMF law: m, source, forms, each branch's parameters and errors
        m = lp["law"]["inputs"]["m"]
        return (
            f"<p>law <b>sbmf</b>, m = <span data-key='law_parameters.m'>{lp['m']:.4g}</span> "
            f"({html.escape(m['meaning'])})</p>" + law_section(lp["law"], "law_parameters.law")
        )
    if not lp:
        return f"<p>law {html.escape(name)}: no friction</p>"
    units = {"mu": "", "m": "", "tau_max": "MPa"}
    rows = [
        _row(k, v, f"law_parameters.{k}", units.get(k, ""), 1e-6 if k == "tau_max" else None)
        for k, v in lp.items()
    ]
    return f"<p>law <b>{html.escape(name)}</b></p>" + _table(rows)


_BILLET = {
    "diameter_m": "diameter D0",
    "outer_diameter_m": "outer diameter OD",
    "inner_diameter_m": "inner diameter ID",
    "height_m": "height h0",
}


def _setup(info):
    """The billet, its mesh and material, and how the run went (increments, solver)."""
    b, mesh, mat = info.get("billet", {}), info.get("mesh", {}), info.get("material", {})
    rows = [_row("billet", b.get("shape", info.get("scene", "")), "billet.shape")]
    rows += [_row(w, b[k], f"billet.{k}", "mm", 1e3, ".4g") for k, w in _BILLET.items() if k in b]
    if mesh:
        rows += [
            _row("elements across the radius", mesh["elements_radial"], "mesh.elements_radial"),
            _row("elements over the height", mesh["elements_axial"], "mesh.elements_axial"),
            _row("elements (at the end)", mesh["n_elements"], "mesh.n_elements"),
            _row("element", mesh["element"], "mesh.element"),
        ]
    if mat:
        rows += [
            _row("Young's modulus E", mat["E_Pa"], "material.E_Pa", "GPa", 1e-9, ".4g"),
            _row("Poisson's ratio nu", mat["nu"], "material.nu"),
            _row("Swift K", mat["K_Pa"], "material.K_Pa", "MPa", 1e-6, ".4g"),
            _row("Swift eps0", mat["eps0"], "material.eps0"),
            _row("Swift n", mat["n"], "material.n"),
        ]
    rows += [
        _row("accepted increments", info.get("increments_accepted", "-"), "increments_accepted"),
        _row("Newton iterations", info.get("newton_iterations", "-"), "newton_iterations"),
        _row("remeshes", info.get("n_remesh", 0), "n_remesh"),
        _row("wall time", info.get("wall_time_s"), "wall_time_s", "s", None, ".3g"),
    ]
    return _table(rows)


def write_run_report(folder, info, title):
    """``report.html`` of one ordinary run from its summary.json record ``info``.

    What a forming engineer hands on: the force at the end (kN) and the force-stroke curve; the
    friction law (for the SBMF law ``m``, the parameter file with its sha256, the forms that run
    with their parameters and measured errors, the form beside them); the billet, mesh and
    material; the pressure and shear along the die at the reduction the run ended at; the
    calibrated-range report; the ring chart where the folder has one. Every number carries its
    key in ``summary.json`` (``data-key``; ``data-scale`` where shown in kN, MPa, mm or %).
    """
    folder = Path(folder)
    red = info.get("stopped_at_height_reduction")
    at = f" at height reduction {100 * red:.1f} % (the end of the run)" if red is not None else ""
    body = [
        f"<p>run <b>{html.escape(str(info.get('run', title)))}</b>, scene "
        f"{html.escape(str(info.get('scene', '')))}</p>",
        "<h2>Result</h2>",
        _result(info),
        figure(folder / "force_stroke.png", "die force against height reduction"),
        "<h2>Friction law</h2>",
        _law(info),
        "<h2>Billet, mesh, material and run</h2>",
        _setup(info),
        f"<h2>Along the die{html.escape(at)}</h2>",
        figure(folder / "die_profile.png", f"pressure, p_hist and shear along the die{at}"),
        "<h2>Calibrated range</h2>",
    ]
    lines = range_lines(title, info.get("calibrated_range")) or ["law without parameters"]
    body.append("<ul>" + "".join(f"<li>{html.escape(x)}</li>" for x in lines) + "</ul>")
    for fname, cap in (("../ring_chart.png", "ring chart"), ("ring_chart.png", "ring chart")):
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
