"""Private helpers of the output writers (CSV tables and PNG plots)."""

from __future__ import annotations

import csv

__all__ = ["write_csv"]


def write_csv(path, header, rows):
    """Write ``header`` and then ``rows`` (iterables of cells) to the CSV file ``path``."""
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(rows)
