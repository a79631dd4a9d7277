"""Private helpers of the output writers (CSV tables and PNG plots)."""

from __future__ import annotations

import csv

__all__ = ["new_axes", "pyplot", "save_png", "write_csv"]


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


def new_axes(figsize):
    """A new figure and its one axes, not registered with pyplot (nothing to close)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize)
    return fig, fig.subplots()


def save_png(fig, path):
    """Lay out ``fig``, write it to ``path`` at 120 dpi (not with ``path=None``); return ``fig``.

    A figure from pyplot is closed after writing; it keeps its artists: the plot functions return
    their figures so that tests (and notebooks) read the plotted data back.
    """
    fig.tight_layout()
    if path is None:
        return fig
    fig.savefig(path, dpi=120)
    if fig.canvas.manager is not None:
        import matplotlib.pyplot as plt

        plt.close(fig)
    return fig
