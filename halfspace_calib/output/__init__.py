"""Every file the package writes: CSV tables, PNG plots (matplotlib's object API) and JSON.

- :mod:`.report`: the calibration's ``params.json``, ``summary.json``, tables and plots
- :mod:`.effects`, :mod:`.geometric`, :mod:`.sliding`: the effects' folders
"""

from .effects import write_effect_outputs, write_stiffness_csv, write_tangential_outputs
from .geometric import write_geometric_outputs
from .report import write_outputs
from .sliding import write_sliding_outputs

__all__ = [
    "write_effect_outputs",
    "write_geometric_outputs",
    "write_outputs",
    "write_sliding_outputs",
    "write_stiffness_csv",
    "write_tangential_outputs",
]
