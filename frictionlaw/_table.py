"""A CSV as spreadsheets write it, read into its rows (for the lab sheets the tools take).

``#`` comment lines and blank lines skipped, a UTF-8 byte-order mark (Excel's "CSV UTF-8")
dropped, commas, semicolons or tabs between the columns (the one the header row holds most
often: a header cell "note (sample, lot)" in a semicolon sheet does not make it a comma
sheet), the file's own line numbers kept for the messages. The csv module parses; this only
fixes the conventions every reader of a lab sheet here shares.
"""

import csv
from pathlib import Path

__all__ = ["read_rows"]


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
