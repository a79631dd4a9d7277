"""A CSV as spreadsheets write it, read into its rows (for the lab sheets the tools take).

``#`` comment lines and blank lines skipped, a UTF-8 byte-order mark (Excel's "CSV UTF-8")
dropped, commas, semicolons or tabs between the columns (the first of them the header row
holds), the file's own line numbers kept for the messages. The csv module parses; this only
fixes the conventions every reader of a lab sheet here shares.
"""

import csv
from pathlib import Path

__all__ = ["read_rows"]


def read_rows(path) -> tuple[list[int], list[list[str]]]:
    """``(line_numbers, rows)``: the header row first, then the data rows, as cell strings.

    ``ValueError`` naming the file when it is not UTF-8 text (``OSError`` as the system says).
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path}: not a UTF-8 text file ({exc})") from None
    numbered = [
        (n, ln)
        for n, ln in enumerate(text.splitlines(), start=1)
        if not ln.lstrip().startswith("#") and ln.strip()
    ]
    sep = next((d for d in (",", ";", "\t") if numbered and d in numbered[0][1]), ",")
    parsed = zip(numbered, csv.reader((ln for _, ln in numbered), delimiter=sep), strict=True)
    line_of, rows = [], []
    for (n, _), r in parsed:  # one record a line
        if any(c.strip() for c in r):
            line_of.append(n)
            rows.append(r)
    return line_of, rows
