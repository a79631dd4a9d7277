"""Private helpers of the output writers (CSV tables and PNG plots)."""

from __future__ import annotations

import csv

__all__ = ["pyplot", "save_png", "write_csv"]


def write_csv(path, header, rows):
    """Write ``header`` and then ``rows`` (iterables of cells) to the CSV file ``path``."""
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(rows)


def pyplot():
    """``matplotlib.pyplot`` on the non-interactive Agg backend (imported on first use)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_png(fig, path):
    """Lay out ``fig``, write it to ``path`` at 120 dpi and close it; return ``fig``.

    A closed figure keeps its artists: the plot functions return their figures so that tests
    read the plotted data back.
    """
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return fig
