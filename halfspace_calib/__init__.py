"""Calibration of the SBMF friction law from elasto-plastic half-space contact of rough surfaces.

Sec. 2-3 of the paper: surfaces in, ``FrictionParams`` JSON out. Start with ``docs/architecture.md``
(the subpackages and what each may import). The main entry points:

- :func:`calibrate` with a :class:`Scene`, then :func:`write_outputs` (and the
  ``halfspace-calib`` command)
- :func:`solve_normal`, :func:`solve_normal_pair` (Sec. 2.1), :func:`solve_tangential` (Sec. 2.2)
- surfaces: :func:`read_surface`, :func:`dc04_edt_like`, :func:`tool_like`, :func:`self_affine`
- fits: :func:`fit_first_loading` (Eq. 24), :func:`fit_reload` (Eq. 25)
- studies: :func:`geometric_study` (Sec. 3.2), :func:`sliding_study` (Sec. 3.3), each taking a
  :class:`Materials` and a :class:`SolverSettings` record
- subpackages, one way down: ``cli`` -> ``pipeline`` -> ``output`` -> ``studies`` ->
  ``contact`` / ``topography`` -> ``common``
"""

from .contact.influence import InfluenceOperator, love_coefficients, normal_operator
from .contact.materials import Materials, SolverSettings, sigma_y_from_hardness
from .contact.normal import (
    NormalResult,
    composite_heights,
    composite_modulus,
    solve_normal,
    solve_normal_pair,
)
from .contact.tangential import solve_tangential, tau_adh_full_sliding
from .output.report import calibration_figures, write_outputs
from .pipeline.calibration import Calibration, calibrate
from .pipeline.fit import fit_first_loading, fit_reload
from .pipeline.params import make_params
from .pipeline.scene import Scene, load_scene
from .studies.geometric import geometric_study
from .studies.sliding import sliding_sweep
from .studies.sliding_study import sliding_study
from .topography import (
    Surface,
    block_average,
    dc04_edt_like,
    level,
    read_surface,
    roughness,
    self_affine,
    tool_like,
)

__all__: list[str] = [
    "calibration_figures",
    "Calibration",
    "InfluenceOperator",
    "Materials",
    "NormalResult",
    "Scene",
    "SolverSettings",
    "Surface",
    "block_average",
    "calibrate",
    "composite_heights",
    "composite_modulus",
    "dc04_edt_like",
    "fit_first_loading",
    "fit_reload",
    "geometric_study",
    "level",
    "load_scene",
    "love_coefficients",
    "make_params",
    "normal_operator",
    "read_surface",
    "roughness",
    "self_affine",
    "sigma_y_from_hardness",
    "sliding_study",
    "sliding_sweep",
    "solve_normal",
    "solve_normal_pair",
    "solve_tangential",
    "tau_adh_full_sliding",
    "tool_like",
    "write_outputs",
]
