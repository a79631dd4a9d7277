"""Measured ring tests from CSV files: the points, and the ring and material the file states.

A file has the columns of ``fe-demo``'s ``history.csv``: ``height_reduction`` and
``inner_diameter_change`` (mid-plane) or ``inner_diameter_min_change`` (smallest inner diameter),
both fractions; one row per ring. It may be what a spreadsheet writes:

- UTF-8 with or without a byte-order mark (Excel's "CSV UTF-8");
- separated by commas, or by semicolons (or tabs) with decimal commas (a European export:
  ``0,3;0,0102``).

Lines starting with ``#`` are comments. Two of them may state the test's conditions, each a list
of ``key = value unit`` items separated by commas (by semicolons where the values have decimal
commas)::

    # geometry: OD = 18 mm, ID = 9 mm, H = 6 mm
    # material: E = 210 GPa, nu = 0.3, K = 530 MPa, eps0 = 0.006, n = 0.24

``geometry``: the ring's outer and inner diameter and height before the test (``OD``, ``ID``,
``H``; units ``m``, ``mm`` or ``um``). ``material``: the Swift flow curve
``sigma_f = K (eps0 + eps_p)^n`` and the elastic constants (``K`` and ``E`` in ``Pa``, ``kPa``,
``MPa`` or ``GPa``; ``nu``, ``eps0``, ``n`` without a unit); ``K``, ``eps0`` and ``n`` are required,
``E`` and ``nu`` default to ``fe-demo``'s DC04 values. Pooled files must state the same
conditions where they state any.
"""

from __future__ import annotations

import csv
import hashlib
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from sbmf_cli import ParameterError

__all__ = ["COLUMNS", "REDUCTION_RANGE", "RingTest", "read_ring_tests"]

#: reductions the ring fit accepts
REDUCTION_RANGE = (0.0, 0.7)
COLUMNS = ("inner_diameter_change", "inner_diameter_min_change")

_LENGTH = {"m": 1.0, "mm": 1e-3, "um": 1e-6}
_STRESS = {"pa": 1.0, "kpa": 1e3, "mpa": 1e6, "gpa": 1e9}
#: key -> (name in the record, units it takes (None: none), required)
_GEOMETRY = {
    "od": ("outer_diameter", _LENGTH, True),
    "id": ("inner_diameter", _LENGTH, True),
    "h": ("height", _LENGTH, True),
}
_MATERIAL = {
    "e": ("E", _STRESS, False),
    "nu": ("nu", None, False),
    "k": ("K", _STRESS, True),
    "eps0": ("eps0", None, True),
    "n": ("n", None, True),
}
_STATED = {"geometry": _GEOMETRY, "material": _MATERIAL}


@dataclass(frozen=True)
class RingTest:
    """Measured ring tests, pooled: one row per ring (repeated reductions allowed).

    ``geometry`` (``outer_diameter``, ``inner_diameter``, ``height`` in m) and ``material``
    (``E``, ``K`` in Pa; ``nu``, ``eps0``, ``n``) are what the files state (``None`` where none
    does); ``sha256`` the files' hashes, in the order of ``sources``.
    """

    reduction: np.ndarray
    d_inner: np.ndarray
    column: str
    sources: tuple
    geometry: dict | None = None
    material: dict | None = None
    sha256: tuple = ()


def _bad(path, text):
    """Bad input in a measured file, naming the ``paths`` parameter (``--measured``)."""
    return ParameterError(f"{{paths}} {path}{text}", "paths")


def _number(path, text, decimal_comma):
    text = text.strip()
    if decimal_comma:
        text = text.replace(",", ".")
    return float(text)


def _shown(kind, key):
    """How a key is written: ``OD``, ``ID``, ``H``; ``E``, ``nu``, ``K``, ``eps0``, ``n``."""
    return key.upper() if kind == "geometry" else _MATERIAL[key][0]


def _stated(path, kind, body):
    """``{name: value in SI}`` of a ``# geometry:`` or ``# material:`` line."""
    keys = _STATED[kind]
    sep = ";" if ";" in body else ","
    out = {}
    for item in (s for s in body.split(sep) if s.strip()):
        m = re.fullmatch(r"\s*([A-Za-z_0-9]+)\s*=\s*([-+0-9.,eE]+)\s*([A-Za-z]*)\s*", item)
        if not m or m.group(1).lower() not in keys:
            raise _bad(
                path,
                f": cannot read {item.strip()!r} in the '# {kind}:' line: write 'key = value "
                f"unit' with keys {', '.join(_shown(kind, k) for k in keys)}"
                " (docs/getting_m.md)",
            )
        name, units, _ = keys[m.group(1).lower()]
        unit = m.group(3).lower()
        try:
            value = _number(path, m.group(2), sep == ";")
        except ValueError:
            raise _bad(path, f": {m.group(1)} = {m.group(2)!r} is not a number") from None
        if units is None and unit:
            raise _bad(path, f": {m.group(1)} takes no unit, got {m.group(3)!r}")
        if units is not None and unit not in units:
            raise _bad(
                path,
                f": {m.group(1)} needs a unit, one of {', '.join(sorted(units))} (got "
                f"{m.group(3) or 'none'!r})",
            )
        out[name] = value * (units[unit] if units else 1.0)
    missing = [_shown(kind, k) for k, (n, _, req) in keys.items() if req and n not in out]
    if missing:
        raise _bad(path, f": the '# {kind}:' line lacks {', '.join(missing)}")
    return out


def _conditions(path, comments):
    """What the comment lines state: ``{"geometry": {...}, "material": {...}}`` (either absent)."""
    out = {}
    for line in comments:
        m = re.match(r"\s*#\s*(geometry|material)\s*:(.*)$", line, flags=re.IGNORECASE)
        if m:
            kind = m.group(1).lower()
            if kind in out:
                raise _bad(path, f": two '# {kind}:' lines")
            out[kind] = _stated(path, kind, m.group(2))
    g = out.get("geometry")
    if g and not (0 < g["inner_diameter"] < g["outer_diameter"] and g["height"] > 0):
        raise _bad(path, ": the '# geometry:' line needs 0 < ID < OD and H > 0")
    return out


def _delimiter(header):
    """The separator of the header line: ``,`` unless it has none and ``;`` or a tab."""
    if "," in header:
        return ","
    for sep in (";", "\t"):
        if sep in header:
            return sep
    return ","


def _column(path, names, column):
    """The measured diameter column of a file's header (the same in every pooled file)."""
    if "height_reduction" not in names:
        raise _bad(path, f": missing column 'height_reduction' ({names})")
    have = [c for c in COLUMNS if c in names]
    if not have:
        raise _bad(
            path,
            ": missing column 'inner_diameter_change' (mid-plane) or "
            f"'inner_diameter_min_change' (smallest inner diameter); found {names}",
        )
    if column is not None and have[0] != column:
        raise _bad(
            path,
            f": gives {have[0]!r} where an earlier file gives {column!r}; pool files that "
            "measure the same diameter",
        )
    return have[0]


def _point(path, i, row, col, decimal_comma):
    """``(reduction, d)`` of one data row, checked."""
    try:
        r = _number(path, row["height_reduction"], decimal_comma)
        d = _number(path, row[col], decimal_comma)
    except (TypeError, ValueError, AttributeError):
        raise _bad(
            path,
            f", row {i}: height_reduction and {col} must be numbers (fractions), got "
            f"{row.get('height_reduction')!r}, {row.get(col)!r}",
        ) from None
    if math.isnan(r) or math.isnan(d):
        raise _bad(path, f", row {i}: NaN in height_reduction or {col}")
    lo, hi = REDUCTION_RANGE
    if not (lo < r <= hi):
        raise _bad(
            path,
            f", row {i}: height_reduction {r:g} is outside ({lo:g}, {hi:g}] (a fraction: 0.5 "
            "for 50 %)",
        )
    if not (-1.0 < d < 2.0) or math.isinf(d):
        raise _bad(
            path, f", row {i}: {col} {d:g} is not a plausible fraction (-1 < d < 2; 0.05 for +5 %)"
        )
    return r, d


def _read_file(path, column):
    """``(points, column, conditions, sha256)`` of one file."""
    if not path.is_file():
        raise _bad(path, ": no such file")
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")  # a byte-order mark (Excel's "CSV UTF-8") is dropped
    except UnicodeDecodeError:
        raise _bad(path, ": not UTF-8 text (save the sheet as CSV UTF-8)") from None
    lines = text.splitlines()
    comments = [s for s in lines if s.lstrip().startswith("#")]
    data = [s for s in lines if s.strip() and not s.lstrip().startswith("#")]
    sep = _delimiter(data[0] if data else "")
    reader = csv.DictReader(data, delimiter=sep)
    column = _column(path, [n.strip() for n in (reader.fieldnames or [])], column)
    points = []
    for i, row in enumerate(reader, start=2):
        row = {k.strip(): v for k, v in row.items() if k is not None}
        points.append(_point(path, i, row, column, decimal_comma=sep != ","))
    return points, column, _conditions(path, comments), hashlib.sha256(raw).hexdigest()


def _same(kind, found):
    """The one statement of ``kind`` the files make (``None``); different ones are refused."""
    stated = [(p, c[kind]) for p, c in found if kind in c]
    for p, v in stated[1:]:
        if any(not math.isclose(v[k], stated[0][1].get(k, math.nan), rel_tol=1e-9) for k in v):
            raise ParameterError(
                f"{{paths}}: {stated[0][0]} and {p} state different {kind}s ({stated[0][1]} "
                f"against {v}); pool tests of one ring and material",
                "paths",
            )
    return dict(stated[0][1]) if stated else None


def read_ring_tests(paths):
    """Read and check measured ring tests (CSV; the module docstring gives the format).

    Raises :class:`sbmf_cli.ParameterError` (a ``ValueError``) naming ``paths``, the file, column,
    row or range: a missing column, a reduction outside ``(0, 0.7]``, NaN, fewer than 2 points in
    all, files that give different columns or state different conditions, an unreadable
    ``# geometry:`` or ``# material:`` line.
    """
    paths = [Path(p) for p in paths]
    if not paths:
        raise ParameterError("{paths} needs at least one CSV file", "paths")
    points, column, found, sha = [], None, [], []
    for path in paths:
        pts, column, conditions, digest = _read_file(path, column)
        points += pts
        found.append((path, conditions))
        sha.append(digest)
    if len(points) < 2:
        raise ParameterError(
            f"{{paths}}: at least 2 points are needed to fit m and its band, got {len(points)}",
            "paths",
        )
    red, dd = np.array(points).T
    return RingTest(
        red,
        dd,
        column,
        tuple(str(p) for p in paths),
        geometry=_same("geometry", found),
        material=_same("material", found),
        sha256=tuple(sha),
    )
