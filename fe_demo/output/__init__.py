"""Writers of fe-demo's runs: history CSV, VTU series, PNG plots, console tables, report pages.

Below the scenes (it reads their records, never imports them): :mod:`.history` (CSV with units,
VTU, the console table), :mod:`.figures` (a ``*_figure`` and a ``plot_*`` per plot),
:mod:`.reports` (``report.html`` pages, the calibrated range's lines), :mod:`.band` (a band run's
files), :mod:`.ring_fit` (a ring fit's files).
"""

from .figures import (
    die_profile_figure,
    force_stroke_figure,
    law_comparison_figure,
    plot_die_profile,
    plot_force_stroke,
    plot_law_comparison,
    plot_recontact,
    plot_ring_chart,
    recontact_figure,
    ring_chart_figure,
)
from .history import HISTORY_UNITS, csv_header, summary_table, write_history_csv, write_vtu_series

__all__ = [
    "HISTORY_UNITS",
    "csv_header",
    "write_history_csv",
    "write_vtu_series",
    "summary_table",
    "force_stroke_figure",
    "die_profile_figure",
    "law_comparison_figure",
    "ring_chart_figure",
    "recontact_figure",
    "plot_force_stroke",
    "plot_die_profile",
    "plot_law_comparison",
    "plot_ring_chart",
    "plot_recontact",
]
