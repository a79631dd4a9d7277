"""Self-contained HTML pages of the project's reports (``report.html``).

``halfspace-calib``, ``fe-demo`` and ``fe-demo ring-fit`` write a ``report.html`` from the same
records as their ``summary.json`` or ``ring_fit.json``; this module is the one place that builds
such a page: images embedded as base64 (no network), every number carrying
``data-key="<dotted path in the JSON record>"`` so that a reader or a test can check the page
against the file. Standard library only, like the rest of the command layer.
"""

from __future__ import annotations

import base64
import html
import math
from pathlib import Path

__all__ = ["figure", "number_cell", "page"]

_STYLE = (
    "body{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222}"
    "table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;padding:2px 8px;"
    "text-align:right}th{background:#eee}td.t{text-align:left}.bad{color:#b00}"
    "img{max-width:100%;border:1px solid #ddd;margin:4px 0}"
)


def number_cell(value, key, fmt=".6g"):
    """A ``<td>`` with the number and its ``data-key`` (the path of the value in summary.json)."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        text = "-"
    else:
        text = format(value, fmt)
    return f'<td data-key="{html.escape(key)}">{text}</td>'


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
