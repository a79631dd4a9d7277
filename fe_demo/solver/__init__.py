"""The FE core: the model and everything it is made of.

Mesh, element (B-bar), J2 material, die contact with the runtime law, linear solve, the
updated-Lagrangian model and its remeshing; numba kernels in :mod:`._kernels`. It knows nothing of scenes, outputs or the command line.
"""

from .material import DC04, Material
from .model import FormingModel, SolverOptions

__all__ = ["DC04", "Material", "FormingModel", "SolverOptions"]
