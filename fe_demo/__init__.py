"""Axisymmetric upsetting and ring-compression models in scikit-fem that use ``frictionlaw``.

Never imports ``halfspace_calib``: calibrated parameters come in as a JSON file
(``frictionlaw.FrictionParams.from_json``). By role, imports one way (bottom to top):

- :mod:`fe_demo.solver`: the FE core (mesh, element, material, contact, linear solve, model,
  remeshing, numba kernels);
- :mod:`fe_demo.output`: writers of runs' records (CSV, VTU, plots, report pages);
- :mod:`fe_demo.scenes`: upsetting, ring, multistage (``run_upsetting``, ``run_ring``,
  ``run_multistage``), their laws and run specification;
- :mod:`fe_demo.analysis`: the ring fit of ``m``, the ring chart, the law's band;
- :mod:`fe_demo.cli`: the ``fe-demo`` console script.
"""

from .scenes import SceneResult, run_multistage, run_ring, run_upsetting
from .solver import DC04, FormingModel, Material, SolverOptions

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
