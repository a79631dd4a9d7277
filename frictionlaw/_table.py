"""A CSV as spreadsheets write it, read into its rows (for the lab sheets the tools take).

``#`` comment lines and blank lines skipped, a UTF-8 byte-order mark (Excel's "CSV UTF-8")
dropped, commas, semicolons or tabs between the columns (the one the header row holds most
often: a header cell "note (sample, lot)" in a semicolon sheet does not make it a comma
sheet), the file's own line numbers kept for the messages. The csv module parses; this only
fixes the conventions every reader of a lab sheet here shares.
"""

import csv
import re
from pathlib import Path

__all__ = [
    "read_rows",
    "number",
    "STRESS_UNITS",
    "STRESS_SHOWN",
    "STRAIN_UNITS",
    "STRAIN_SHOWN",
    "plain",
    "known_names",
    "find_columns",
    "header_and_rows",
]

#: the stress and pressure units a lab sheet's header may give (compared in lower case) ->
#: factor to Pa (psi and ksi exactly, from the pound-force and the inch)
STRESS_UNITS = {
    "pa": 1.0,
    "kpa": 1e3,
    "mpa": 1e6,
    "gpa": 1e9,
    "n/mm2": 1e6,
    "n/mm\u00b2": 1e6,
    "n/mm^2": 1e6,
    "psi": 6894.757293168361,
    "ksi": 6894757.293168361,
}
#: the same, as the messages show them
STRESS_SHOWN = "Pa, kPa, MPa, GPa, N/mm², psi, ksi"
#: the units a strain column may give (a fraction or per cent) -> factor to the fraction
STRAIN_UNITS = {"": 1.0, "-": 1.0, "1": 1.0, "mm/mm": 1.0, "m/m": 1.0, "%": 0.01}
#: the same, as the messages show them
STRAIN_SHOWN = "none, -, 1, mm/mm, m/m, %"


def read_rows(path) -> tuple[list[int], list[list[str]], str]:
    """``(line_numbers, rows, separator)``: the header row first, then the data rows, as cells.

    With a semicolon or tab separator a cell's decimal comma is the reader's to accept (as
    spreadsheets in German or French write numbers); with commas it cannot be one.

    ``ValueError`` naming the file when it is not UTF-8 text (with the line and what to save it
    as; the ring-test reader of ``fe_demo`` refuses such a sheet the same way) or a data row has more cells
    than the header (a decimal comma in a comma-separated file, a shifted row), naming the
    line; ``OSError`` as the system says.
    """
    path = Path(path)
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:  # Excel's "CSV (Trennzeichen-getrennt)": a code page
        line = raw[: exc.start].count(b"\n") + 1
        raise ValueError(
            f"{path}: line {line}: not UTF-8 text (byte 0x{raw[exc.start]:02x}, an umlaut or a "
            "degree sign of a sheet saved in a code page such as Windows-1252?): save the sheet "
            'as "CSV UTF-8"'
        ) from None
    numbered = [
        (n, ln)
        for n, ln in enumerate(text.splitlines(), start=1)
        if not ln.lstrip().startswith("#") and ln.strip()
    ]
    head = numbered[0][1] if numbered else ""
    sep = max((";", "\t", ","), key=head.count) if any(d in head for d in ",;\t") else ","
    parsed = zip(numbered, csv.reader((ln for _, ln in numbered), delimiter=sep), strict=True)
    line_of: list[int] = []
    rows: list[list[str]] = []
    for (n, _), r in parsed:  # one record a line
        if not any(c.strip() for c in r):
            continue
        if rows and len(r) > len(rows[0]) and any(c.strip() for c in r[len(rows[0]) :]):
            raise ValueError(
                f"{path}: line {n}: {len(r)} cells under a header of {len(rows[0])} columns (a "
                "decimal comma in a comma-separated file, or a shifted row?)"
            )
        line_of.append(n)
        rows.append(r)
    return line_of, rows, sep


def number(cell: str, sep: str) -> float:
    """A cell's number; a decimal comma is read as a point where the separator is not a comma.

    ``ValueError`` (the ``float`` message) for anything else.
    """
    text = cell.strip()
    if sep != "," and text.count(",") == 1 and "." not in text:
        text = text.replace(",", ".")
    return float(text)


_UMLAUT = str.maketrans({"ä": "ae", "ö": "oe", "ü": "ue", "ß": "ss"})
#: ``name [unit]``, ``name (unit)``, ``name in unit``, ``name / unit``
_BRACKETED = re.compile(
    r"^(?P<name>.*?)\s*(?:[(\[]\s*(?P<b>[^)\]]*?)\s*[)\]]|\s+in\s+(?P<w>\S+)|\s*/\s*(?P<s>\S+))$",
    flags=re.IGNORECASE,
)


def plain(name: str) -> str:
    """A column name as the readers compare it.

    Lower case, umlauts spelt out, ``_``, ``-`` and ``.`` as spaces.
    """
    text = name.strip().lower().translate(_UMLAUT)
    return " ".join(re.sub(r"[_\-.]+", " ", text).split())


def known_names(names: dict) -> dict[str, str]:
    """``{plain name: quantity}`` of ``{quantity: (names, ...)}``."""
    return {plain(n): q for q, spelt in names.items() for n in spelt}


def header_cell(cell: str, known: dict[str, str]) -> tuple[str | None, str]:
    """``(quantity or None, unit as written)`` of one header cell.

    ``name``, ``name [unit]``, ``name (unit)``, ``name in unit``, ``name / unit``, ``name%``,
    ``name_unit``; ``known``: ``{plain name: quantity}`` (:func:`known_names`).
    """
    text = cell.strip()
    if plain(text) in known:
        return known[plain(text)], ""
    m = _BRACKETED.match(text)
    if m and plain(m["name"]) in known:
        return known[plain(m["name"])], next(u for u in (m["b"], m["w"], m["s"]) if u is not None)
    if text.endswith("%") and plain(text[:-1]) in known:  # alpha%, alpha_%
        return known[plain(text[:-1])], "%"
    for sep in ("_", " "):  # p_MPa, p_kPa, strain_-
        name, _, tail = text.rpartition(sep)
        if name and plain(name) in known:
            return known[plain(name)], tail
    return None, ""


def is_units_row(head: list[str], row: list[str], sep: str, known: dict[str, str]) -> bool:
    """Whether the row under the header gives units, as lab software writes them.

    No number in a column the reader reads, and one cell there at least.
    """
    cells = [
        row[j].strip() if j < len(row) else ""
        for j, c in enumerate(head)
        if header_cell(c, known)[0]
    ]
    if not any(cells):
        return False
    for cell in cells:
        try:
            number(cell, sep)
            return False
        except ValueError:
            pass
    return True


def with_units(path, line: int, head: list[str], units: list[str], known, allowed, shown):
    """The header with the units row's units (``p`` over ``MPa`` is ``p [MPa]``).

    ``allowed`` and ``shown``: each quantity's units (lower case -> factor) and how a message
    says them. ``ValueError`` naming the line and the column for a unit the reader does not know
    or one the header contradicts.
    """
    out = list(head)
    for j, cell in enumerate(head):
        quantity, unit = header_cell(cell, known)
        unit = unit.strip()
        given = units[j].strip() if j < len(units) else ""
        given = given[1:-1].strip() if given[:1] + given[-1:] in ("[]", "()") else given
        if quantity is None or not given:
            continue
        if unit and unit.lower() == given.lower():
            continue  # p_MPa over MPa
        if unit:
            raise ValueError(
                f"{path}: line {line} (the units row): the column {cell.strip()!r} says "
                f"{unit!r} and the units row {given!r}: keep one"
            )
        if allowed[quantity].get(given.lower()) is None:
            raise ValueError(
                f"{path}: line {line} (the units row), column {cell.strip()!r}: unknown unit "
                f"{given!r}; {quantity} takes {shown[quantity]}"
            )
        out[j] = f"{cell.strip()} [{given}]"
    return out


def find_columns(path, line: int, head: list[str], known, allowed, shown, *, named, refuse=None):
    """``{quantity: (index, factor, header as written)}`` of the columns a header names.

    ``known``: ``{plain name: quantity}``; ``allowed`` and ``shown``: each quantity's units
    (lower case -> factor; a quantity without ``""`` needs one) and how a message says them;
    ``named``: ``{quantity: (its name in a message, an example header)}`` for the quantities
    that need a unit; ``refuse``: a function of a header cell giving the message for a column
    the reader refuses (an engineering strain), or ``None``. Cells naming no quantity are not
    read. ``ValueError`` naming the line and the column for a quantity named twice, a unit the
    reader does not know or one missing; which quantities must be there is the caller's.
    """
    found: dict[str, tuple[int, float, str]] = {}
    for j, cell in enumerate(head):
        written = cell.strip()
        message = refuse(written) if refuse is not None else None
        if message:
            raise ValueError(f"{path}: line {line}: {message}")
        quantity, unit = header_cell(written, known)
        if quantity is None:
            continue  # a remark or another column: not read
        if quantity in found:
            raise ValueError(
                f"{path}: line {line}: the column {quantity} appears twice ({found[quantity][2]!r} "
                f"and {written!r}): keep one (which one to read would be a guess)"
            )
        factor = allowed[quantity].get(unit.strip().lower())
        if factor is None and not unit.strip():
            what, example = named[quantity]
            raise ValueError(
                f"{path}: line {line}: the {what} column {written!r} gives no unit: name it with "
                f"one, e.g. {example} (units: {shown[quantity]})"
            )
        if factor is None:
            raise ValueError(
                f"{path}: line {line}: the column {written!r}: unknown unit {unit.strip()!r}; "
                f"{quantity} takes {shown[quantity]}"
            )
        found[quantity] = (j, factor, written)
    return found


def header_and_rows(path, line_of, rows, sep, known, allowed, shown):
    """``(header, line_of, rows)`` of a sheet :func:`read_rows` read.

    A units row under the header is folded into it (:func:`with_units`) and dropped from the
    rows; without one all is as :func:`read_rows` gave it.
    """
    head = rows[0] if rows else []
    if len(rows) > 1 and is_units_row(head, rows[1], sep, known):
        head = with_units(path, line_of[1], head, rows[1], known, allowed, shown)
        line_of, rows = line_of[:1] + line_of[2:], rows[:1] + rows[2:]
    return head, line_of, rows
