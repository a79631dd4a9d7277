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

Importing the package loads none of it: each name is imported on first use (PEP 562), so that
the ``fe-demo`` command (:mod:`fe_demo.__main__`) starts, answers ``--version`` and handles
Ctrl-C before NumPy, SciPy and numba are loaded.
"""

from sbmf_cli import lazy_names

#: the public names and the module each comes from (imported on first use)
_SOURCES = {
    "DC04": ".solver",
    "Material": ".solver",
    "FormingModel": ".solver",
    "SolverOptions": ".solver",
    "SceneResult": ".scenes",
    "run_upsetting": ".scenes",
    "run_ring": ".scenes",
    "run_multistage": ".scenes",
}
#: the subpackages, as attributes (``fe_demo.scenes``), imported on first use
_SUBPACKAGES = ("analysis", "cli", "output", "scenes", "solver")

__all__ = list(_SOURCES)


__getattr__, __dir__ = lazy_names(__name__, _SOURCES, _SUBPACKAGES)
