"""Every file the package writes: CSV tables, PNG plots (matplotlib's object API) and JSON.

- :mod:`.report`: the calibration's ``params.json``, ``summary.json``, tables and plots
- :mod:`.effects`, :mod:`.geometric`, :mod:`.sliding`: the effects' folders
"""

from .effects import write_effect_outputs, write_stiffness_csv, write_tangential_outputs
from .geometric import write_geometric_outputs
from .report import calibration_figures, write_outputs, write_plots
from .sliding import write_sliding_outputs

__all__ = [
    "calibration_figures",
    "write_effect_outputs",
    "write_geometric_outputs",
    "write_outputs",
    "write_plots",
    "write_sliding_outputs",
    "write_stiffness_csv",
    "write_tangential_outputs",
]
