"""Measured ring tests from CSV files: the points, and the ring and material the file states.

A file has two columns, one row per ring: the height reduction and the change of the inner
diameter at the mid-plane (or of the smallest inner diameter), each as a fraction or in percent.
The columns may be named as ``fe-demo``'s ``history.csv`` names them (``height_reduction``,
``inner_diameter_change``, ``inner_diameter_min_change``, with or without ``_fraction``) or as
labs write them, in English or German (:data:`SPELLINGS`: ``height reduction (%)``,
``Höhenabnahme [%]``, ``ID change``, ``Innendurchmesseränderung in %``, ...); case, spaces,
``_``, ``-`` and umlauts do not matter. The unit comes from the header: ``(%)``, ``[%]``, ``in %``,
``_%`` or ``percent`` for percent; ``(-)``, ``(1)``, ``fraction`` or none for fractions (as
before). It may be what a spreadsheet writes:

- UTF-8 with or without a byte-order mark (Excel's "CSV UTF-8");
- separated by commas, or by semicolons (or tabs) with decimal commas (a European export:
  ``0,3;0,0102``);
- empty rows (Excel's trailing ``;``) are skipped, and other columns (remarks) left unread, each
  with a note (:attr:`RingTest.notes`).

Every message names the file's line (comment lines counted) and quotes only the bad value.

Lines starting with ``#`` are comments. Two of them may state the test's conditions, each a list
of ``key = value unit`` items separated by commas (by semicolons where the values have decimal
commas)::

    # geometry: OD = 18 mm, ID = 9 mm, H = 6 mm
    # material: E = 210 GPa, nu = 0.3, K = 530 MPa, eps0 = 0.006, n = 0.24

``geometry``: the ring's outer and inner diameter and height before the test (``OD``, ``ID``,
``H``; units ``m``, ``mm`` or ``um``). ``material``: the Swift flow curve
``sigma_f = K (eps0 + eps_p)^n`` and the elastic constants (``K`` and ``E`` in ``Pa``, ``kPa``,
``MPa``, ``GPa``, ``N/mm²``, ``psi`` or ``ksi``; ``nu``, ``eps0``, ``n`` without a unit); ``K``,
``eps0`` and ``n`` are required, ``E`` and ``nu`` default to ``fe-demo``'s DC04 values. Pooled
files must state the same conditions where they state any.
"""

from __future__ import annotations

import csv
import hashlib
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from frictionlaw._table import STRESS_UNITS
from sbmf_cli import ParameterError

__all__ = [
    "COLUMNS",
    "REDUCTION_RANGE",
    "SPELLINGS",
    "UNITS",
    "RingTest",
    "accepted_columns",
    "read_ring_tests",
]

#: reductions the ring fit accepts
REDUCTION_RANGE = (0.0, 0.7)
COLUMNS = ("inner_diameter_change", "inner_diameter_min_change")

_LENGTH = {"m": 1.0, "mm": 1e-3, "um": 1e-6}
#: key -> (name in the record, units it takes (None: none), required)
_GEOMETRY = {
    "od": ("outer_diameter", _LENGTH, True),
    "id": ("inner_diameter", _LENGTH, True),
    "h": ("height", _LENGTH, True),
}
_MATERIAL = {
    "e": ("E", STRESS_UNITS, False),
    "nu": ("nu", None, False),
    "k": ("K", STRESS_UNITS, True),
    "eps0": ("eps0", None, True),
    "n": ("n", None, True),
}
_STATED = {"geometry": _GEOMETRY, "material": _MATERIAL}


@dataclass(frozen=True)
class RingTest:
    """Measured ring tests, pooled: one row per ring (repeated reductions allowed).

    ``reduction`` and ``d_inner`` are fractions (a file's percent converted); ``column`` the
    diameter measured, by fe-demo's name. ``geometry`` (``outer_diameter``, ``inner_diameter``,
    ``height`` in m) and ``material`` (``E``, ``K`` in Pa; ``nu``, ``eps0``, ``n``) are what the
    files state (``None`` where none does); ``sha256`` the files' hashes, in the order of
    ``sources``; ``notes`` what the reading did besides (empty rows skipped, columns not read,
    percent converted), one sentence each.
    """

    reduction: np.ndarray
    d_inner: np.ndarray
    column: str
    sources: tuple
    geometry: dict | None = None
    material: dict | None = None
    sha256: tuple = ()
    notes: tuple = ()


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
        m = re.fullmatch(
            r"\s*([A-Za-z_0-9]+)\s*=\s*([-+0-9.,eE]+)\s*((?:[A-Za-z][A-Za-z/^0-9\u00b2]*)?)\s*",
            item,
        )
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


#: the column spellings a file may use, by quantity (written as a lab writes them; compared
#: after :func:`_plain`): English and German, fe-demo's own names first
SPELLINGS = {
    "height_reduction": (
        "height_reduction",
        "height reduction",
        "relative height reduction",
        "reduction in height",
        "reduction",
        "Höhenabnahme",
        "bezogene Höhenabnahme",
        "relative Höhenabnahme",
        "Höhenreduktion",
        "Höhenreduzierung",
        "Stauchung",
    ),
    "inner_diameter_change": (
        "inner_diameter_change",
        "inner diameter change",
        "inner-diameter change",
        "change of inner diameter",
        "change in inner diameter",
        "change of the inner diameter",
        "ID change",
        "Innendurchmesseränderung",
        "Änderung Innendurchmesser",
        "Änderung des Innendurchmessers",
        "Innendurchmesser-Änderung",
    ),
    "inner_diameter_min_change": (
        "inner_diameter_min_change",
        "minimum inner diameter change",
        "min. inner diameter change",
        "smallest inner diameter change",
        "change of the smallest inner diameter",
        "min ID change",
        "Änderung kleinster Innendurchmesser",
        "Änderung des kleinsten Innendurchmessers",
        "kleinste Innendurchmesseränderung",
    ),
}
#: the units a header may give, by how they are written (compared lower case) -> factor to a
#: fraction
UNITS = {
    "%": 0.01,
    "percent": 0.01,
    "prozent": 0.01,
    "pct": 0.01,
    "": 1.0,
    "-": 1.0,
    "1": 1.0,
    "fraction": 1.0,
    "frac": 1.0,
    "mm/mm": 1.0,
}
_UMLAUT = str.maketrans({"ä": "ae", "ö": "oe", "ü": "ue", "ß": "ss"})


def _plain(name):
    """A column name compared by its words: lower case, umlauts spelt out, ``_-.`` as spaces."""
    text = name.strip().lower().translate(_UMLAUT)
    return " ".join(re.sub(r"[_\-./]+", " ", text).split())


_KNOWN = {_plain(n): q for q, names in SPELLINGS.items() for n in names}
_UNIT_SUFFIX = re.compile(
    r"^(?P<name>.*?)\s*(?:[(\[]\s*(?P<bracket>[^)\]]*?)\s*[)\]]"
    r"|\s+in\s+(?P<inword>%|percent|prozent)|\s*/\s*(?P<slash>%|-|1)"
    r"|[_ ]?(?P<tail>%|percent|pct|fraction|frac))$",
    flags=re.IGNORECASE,
)


#: the quantities in words
_WORDS = {
    "height_reduction": "height reduction",
    "inner_diameter_change": "inner-diameter change",
    "inner_diameter_min_change": "change of the smallest inner diameter",
}


def accepted_columns():
    """The accepted column spellings and units in words (the messages and the docs say them)."""
    names = "; ".join(f"{_WORDS[k]}: {', '.join(v)}" for k, v in SPELLINGS.items())
    return (
        f"accepted columns (any case, '_' or '-' for spaces): {names}; units in the header: "
        "(%), [%], 'in %' or '_%' for percent, (-), (1), 'fraction' or none for fractions "
        "(docs/getting_m.md)"
    )


def _header_cell(cell):
    """``(quantity or None, factor to a fraction, unit as written)`` of one header cell."""
    text = cell.strip()
    m = _UNIT_SUFFIX.match(text)
    unit = ""
    if m:
        unit = next(g for g in (m["bracket"], m["inword"], m["slash"], m["tail"]) if g is not None)
        text = m["name"]
    quantity = _KNOWN.get(_plain(text))
    factor = UNITS.get(unit.strip().lower())
    return quantity, factor, unit.strip()


@dataclass(frozen=True)
class _Column:
    """A measured quantity's column in one file: where it is, its name and unit as written."""

    index: int
    written: str
    factor: float
    unit: str


def _columns(path, line_no, cells, column):
    """``(height column, diameter column, diameter quantity, notes)`` of a header."""
    found, notes, unused = {}, [], []
    for i, cell in enumerate(cells):
        quantity, factor, unit = _header_cell(cell)
        if quantity is None or quantity in found:
            if cell.strip():
                unused.append(cell.strip())
            continue
        if factor is None:
            raise _bad(
                path,
                f", line {line_no}: column {cell.strip()!r} has the unit {unit!r}; a height "
                "reduction and an inner-diameter change are fractions or percent: "
                + accepted_columns(),
            )
        found[quantity] = _Column(i, cell.strip(), factor, "%" if factor != 1.0 else "fraction")
    have = [c for c in COLUMNS if c in found]
    if "height_reduction" not in found or not have:
        missing = (
            "a height-reduction column"
            if "height_reduction" not in found
            else ("an inner-diameter column")
        )
        shown = "; ".join(repr(c.strip()) for c in cells) or "none"
        raise _bad(
            path, f", line {line_no}: {missing} is missing (header: {shown}); " + accepted_columns()
        )
    diameter = have[0]
    if column is not None and diameter != column:
        raise _bad(
            path,
            f": gives {diameter!r} where an earlier file gives {column!r}; pool files that "
            "measure the same diameter",
        )
    unused += [found[c].written for c in have[1:]]
    if unused:
        notes.append(
            f"{path.name}: column(s) not read: {', '.join(repr(u) for u in unused)} (line "
            f"{line_no}; the fit reads the height reduction and the {diameter} column)"
        )
    for q in ("height_reduction", diameter):
        c = found[q]
        if c.factor != 1.0:
            notes.append(f"{path.name}: {c.written!r} read in percent (the header's unit)")
    return found["height_reduction"], found[diameter], diameter, notes


def _value(path, line_no, cells, col, what, decimal_comma):
    """The fraction in ``cells[col.index]``; a bad value is quoted alone."""
    raw = cells[col.index].strip() if col.index < len(cells) else ""
    if not raw:
        raise _bad(
            path, f", line {line_no}: no {what} in column {col.written!r} (the cell is empty)"
        )
    try:
        v = _number(path, raw, decimal_comma)
    except ValueError:
        raise _bad(
            path, f", line {line_no}: {what} {raw!r} in column {col.written!r} is not a number"
        ) from None
    if math.isnan(v):
        raise _bad(path, f", line {line_no}: {what} is NaN in column {col.written!r}")
    return v * col.factor, raw


def _point(path, line_no, cells, cols, decimal_comma):
    """``(reduction, d)`` of one data line, checked (fractions)."""
    hcol, dcol, column = cols
    name = _WORDS[column]
    r, r_raw = _value(path, line_no, cells, hcol, "height reduction", decimal_comma)
    d, d_raw = _value(path, line_no, cells, dcol, name, decimal_comma)
    lo, hi = REDUCTION_RANGE
    pct = hcol.factor != 1.0
    r_raw += " %" if pct else ""
    d_raw += " %" if dcol.factor != 1.0 else ""
    if not (lo < r <= hi):
        rng = (
            f"({100 * lo:g}, {100 * hi:g}] %"
            if pct
            else f"({lo:g}, {hi:g}] (a fraction: 0.5 for 50 %)"
        )
        raise _bad(path, f", line {line_no}: height reduction {r_raw} is outside {rng}")
    if not (-1.0 < d < 2.0) or math.isinf(d):
        plausible = "-100 % < d < 200 %" if dcol.factor != 1.0 else "-1 < d < 2; 0.05 for +5 %"
        raise _bad(path, f", line {line_no}: {name} {d_raw} is not plausible ({plausible})")
    return r, d


def _read_file(path, column):
    """``(points, column, conditions, sha256, notes)`` of one file."""
    if not path.is_file():
        raise _bad(path, ": no such file")
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")  # a byte-order mark (Excel's "CSV UTF-8") is dropped
    except UnicodeDecodeError:
        raise _bad(path, ": not UTF-8 text (save the sheet as CSV UTF-8)") from None
    numbered = list(enumerate(text.splitlines(), start=1))
    comments = [s for _, s in numbered if s.lstrip().startswith("#")]
    data = [(n, s) for n, s in numbered if not s.lstrip().startswith("#")]
    header = next(((n, s) for n, s in data if s.strip()), None)
    if header is None:
        raise _bad(
            path,
            ": no header line (the file is empty or holds only comments); " + accepted_columns(),
        )
    sep = _delimiter(header[1])
    cols = _columns(path, header[0], next(csv.reader([header[1]], delimiter=sep)), column)
    hcol, dcol, column, notes = cols
    points, empty = [], []
    for n, line in data:
        if n <= header[0]:
            continue
        cells = next(csv.reader([line], delimiter=sep), [])
        if not any(c.strip() for c in cells):
            empty.append(n)
            continue
        points.append(_point(path, n, cells, (hcol, dcol, column), decimal_comma=sep != ","))
    while empty and empty[-1] == len(numbered) and not numbered[-1][1].strip():
        empty.pop()  # a blank last line is no row
    if empty:
        notes.append(f"{path.name}: {len(empty)} empty row(s) skipped (line(s) {_ranges(empty)})")
    return points, column, _conditions(path, comments), hashlib.sha256(raw).hexdigest(), notes


def _ranges(numbers):
    """``3, 7-9``: line numbers as ranges."""
    out, start = [], numbers[0]
    for a, b in zip(numbers, [*numbers[1:], None], strict=True):
        if b != a + 1:
            out.append(f"{start}" if start == a else f"{start}-{a}")
            start = b
    return ", ".join(out)


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

    Raises :class:`sbmf_cli.ParameterError` (a ``ValueError``) naming ``paths``, the file, its
    line and column: a missing column (the message lists the accepted spellings and units), a
    unit other than percent or a fraction, a value that is no number (quoted alone), a reduction
    outside ``(0, 0.7]`` (``(0, 70] %``), NaN, fewer than 2 points in all, files that give
    different columns or state different conditions, an unreadable ``# geometry:`` or
    ``# material:`` line.
    """
    paths = [Path(p) for p in paths]
    if not paths:
        raise ParameterError("{paths} needs at least one CSV file", "paths")
    points, column, found, sha, notes = [], None, [], [], []
    for path in paths:
        pts, column, conditions, digest, said = _read_file(path, column)
        points += pts
        found.append((path, conditions))
        sha.append(digest)
        notes += said
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
        notes=tuple(notes),
    )
