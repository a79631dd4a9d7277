"""Self-contained HTML pages of the project's reports (``report.html``).

``halfspace-calib``, ``fe-demo`` and ``fe-demo ring-fit`` write a ``report.html`` from the same
records as their ``summary.json`` or ``ring_fit.json``; this module is the one place that builds
such a page: images embedded as base64 (no network), every number carrying
``data-key="<dotted path in the JSON record>"`` so that a reader or a test can check the page
against the file. A number shown in another unit than the record's (a pressure in MPa where the
record holds Pa, a force in kN) also carries ``data-scale``: the text is the record's value times
it. :func:`law_section` renders the description of a law (``frictionlaw.describe``'s record) for
every report that shows one. Standard library only, like the rest of the command layer.
"""

from __future__ import annotations

import base64
import html
import math
from pathlib import Path

__all__ = ["figure", "law_section", "number_cell", "page"]

_STYLE = (
    "body{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222}"
    "table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;padding:2px 8px;"
    "text-align:right}th{background:#eee}td.t{text-align:left}.bad{color:#b00}"
    "img{max-width:100%;border:1px solid #ddd;margin:4px 0}"
)


def number_cell(value, key, fmt=".6g", scale=None):
    """A ``<td>`` with the number and its ``data-key`` (the path of the value in summary.json).

    ``scale``: the number is shown as ``value * scale`` (``1e-6``: Pa as MPa) and the cell says
    so (``data-scale``), so that the page can still be checked against the record.
    """
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        text = "-"
    else:
        text = format(value * scale if scale else value, fmt)
    extra = f' data-scale="{scale:g}"' if scale else ""
    return f'<td data-key="{html.escape(key)}"{extra}>{text}</td>'


#: units shown scaled: record unit -> (scale, unit shown)
_SHOWN = {"Pa": (1e-6, "MPa"), "N": (1e-3, "kN")}


def _value_cell(value, unit, key):
    """A number cell in the unit a reader expects (Pa as MPa) and the unit it is shown in."""
    scale, shown = _SHOWN.get(unit, (None, "" if unit == "1" else unit))
    return number_cell(value, key, ".6g", scale), shown


def _quantities(rows, key):
    """A table of ``{name: {value, unit, meaning}}`` records."""
    out = ["<table><tr><th>quantity</th><th>value</th><th>unit</th><th>meaning</th></tr>"]
    for name, q in rows.items():
        cell, unit = _value_cell(q["value"], q["unit"], f"{key}.{name}.value")
        out.append(
            f"<tr><td class='t'>{html.escape(name)}</td>{cell}<td class='t'>{unit}</td>"
            f"<td class='t'>{html.escape(str(q.get('meaning', '')))}</td></tr>"
        )
    out.append("</table>")
    return "".join(out)


def _form_table(table, key):
    """A form's table: one row per level, each column with its unit."""
    cols = table["columns"]
    shown = [_SHOWN.get(c["unit"], (None, "" if c["unit"] == "1" else c["unit"])) for c in cols]
    head = "".join(
        f"<th>{html.escape(c['name'])}" + (f" [{u}]" if u else "") + "</th>"
        for c, (_, u) in zip(cols, shown, strict=True)
    )
    out = [f"<table><tr>{head}</tr>"]
    for i, row in enumerate(table["rows"]):
        cells = "".join(
            number_cell(v, f"{key}.rows.{i}.{j}", ".5g", shown[j][0]) for j, v in enumerate(row)
        )
        out.append(f"<tr>{cells}</tr>")
    out.append(f"</table><p>between levels: {html.escape(table['interpolation'])}</p>")
    return "".join(out)


def _errors(err, r_squared, key):
    """A form's measured errors (``|d alpha|``) and its ``R^2`` where recorded."""
    if err is None:
        return "<p>measured errors: not recorded in the parameter file</p>"
    ext = err.get("extrapolation") or {}
    rows = [
        ("held out, max", err.get("heldout_max"), f"{key}.errors.heldout_max"),
        ("held out, rms", err.get("heldout_rms"), f"{key}.errors.heldout_rms"),
        ("in sample, max", err.get("in_sample_max"), f"{key}.errors.in_sample_max"),
        ("in sample, rms", err.get("in_sample_rms"), f"{key}.errors.in_sample_rms"),
        (
            "top level extrapolated, max",
            ext.get("max_abs"),
            f"{key}.errors.extrapolation.max_abs",
        ),
    ]
    out = ["<table><tr><th>|d alpha| (law against the half-space model)</th><th>value</th></tr>"]
    out += [
        f"<tr><td class='t'>{what}</td>{number_cell(v, k, '.4g')}</tr>"
        for what, v, k in rows
        if v is not None or what.startswith("held out, max")
    ]
    if r_squared is not None:
        out.append(f"<tr><td class='t'>R^2</td>{number_cell(r_squared, f'{key}.r_squared')}</tr>")
    out.append("</table>")
    return "".join(out)


def law_section(law, key="law"):
    """The law a run uses, as HTML: the description record of ``frictionlaw.describe``.

    Per branch, the form that runs (its parameters or table, its measured errors), then each
    form the file carries beside it, marked as a comparison; then the inputs (``m``,
    ``sigma_y``, ``H``, ``k``) and the derived numbers. ``key``: the record's path in the JSON
    file the page belongs to (``law``, ``law_parameters.law``).
    """
    src = law.get("source")
    out = [f"<p>forms that run: <b>{html.escape(law['forms'])}</b></p>"]
    if src:
        out.append(
            f"<p>from <code>{html.escape(src['path'])}</code>, sha256 "
            f"<code>{html.escape(src['sha256'])}</code></p>"
        )
    for bname, b in law["branches"].items():
        out.append(f"<h3>{html.escape(b['title'])}</h3>")
        for fname, f in b["forms"].items():
            fkey = f"{key}.branches.{bname}.forms.{fname}"
            state = "runs" if f["runs"] else "beside it for comparison, not run"
            out.append(f"<h4>{html.escape(f['name'])}: {state}</h4>")
            if f["parameters"]:
                out.append(_quantities(f["parameters"], f"{fkey}.parameters"))
            if f.get("table"):
                out.append(_form_table(f["table"], f"{fkey}.table"))
            out.append(_errors(f.get("errors"), f.get("r_squared"), fkey))
    out.append("<h3>Inputs and derived numbers</h3>")
    out.append(_quantities(law["inputs"], f"{key}.inputs"))
    out.append(_quantities(law["derived"], f"{key}.derived"))
    rng = law.get("calibrated_range")
    if rng:
        out.append(
            "<p>calibrated first-loading range: "
            f"<span data-key='{html.escape(key)}.calibrated_range.p_min' data-scale='1e-06'>"
            f"{rng['p_min'] / 1e6:.4g}</span>-<span data-key='{html.escape(key)}."
            f"calibrated_range.p_max' data-scale='1e-06'>{rng['p_max'] / 1e6:.4g}</span> MPa"
            "</p>"
        )
    out += [f"<p>{html.escape(n)}</p>" for n in law.get("notes", ())]
    return "\n".join(out)


def figure(path, caption):
    """A ``<figure>`` with the PNG at ``path`` embedded as base64 (``""`` if it does not exist)."""
    path = Path(path)
    if not path.is_file():
        return ""
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return (
        f"<figure><img alt='{html.escape(caption)}' src='data:image/png;base64,{data}'>"
        f"<figcaption>{html.escape(caption)}</figcaption></figure>"
    )


def page(title, body):
    """A whole HTML document (no network) around ``body`` (a string or a sequence of parts)."""
    if not isinstance(body, str):
        body = "\n".join(body)
    return (
        "<!DOCTYPE html>\n<html><head><meta charset='utf-8'>"
        f"<title>{html.escape(title)}</title><style>{_STYLE}</style></head>"
        f"<body><h1>{html.escape(title)}</h1>\n{body}\n</body></html>\n"
    )
