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

import importlib

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


def __getattr__(name):
    """Import a public name (or a subpackage) on first use."""
    if name in _SOURCES:
        value = getattr(importlib.import_module(_SOURCES[name], __name__), name)
        globals()[name] = value
        return value
    if name in _SUBPACKAGES:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__) | set(_SUBPACKAGES))
