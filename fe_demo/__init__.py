"""Axisymmetric upsetting and ring-compression models in scikit-fem that use ``frictionlaw``.

Never imports ``halfspace_calib``: calibrated parameters come in as a JSON file
(``frictionlaw.FrictionParams.from_json``). Entry points: :mod:`fe_demo.scenes`
(``run_upsetting``, ``run_ring``, ``run_multistage``) and the ``fe-demo`` console script.
"""

from .material import DC04, Material
from .model import FormingModel, SolverOptions
from .scenes import SceneResult, run_multistage, run_ring, run_upsetting

__all__ = [
    "DC04",
    "Material",
    "FormingModel",
    "SolverOptions",
    "SceneResult",
    "run_upsetting",
    "run_ring",
    "run_multistage",
]
