"""Numba kernels for a host's own ``@njit`` contact loop (public re-exports).

Example
-------
>>> import numba, numpy as np
>>> from frictionlaw import SBMFLaw, FrictionParams, kernels
>>> law = SBMFLaw(FrictionParams(m=0.5, sigma_y=300e6, H=800e6, C1=1.2, n1=2, C2=3, n2=2))
>>> code, coeffs = law.code, law.coeffs
>>> @numba.njit
... def host_loop(p, p_hist, out):
...     for i in range(p.size):
...         out[i] = kernels.shear_scalar(code, coeffs, p[i], p_hist[i])[0]
"""

from ._codes import (
    CODE_CAP,
    CODE_COULOMB,
    CODE_SBMF,
    CODE_TRESCA,
    STATUS_OPEN,
    STATUS_SLIP,
    STATUS_STICK,
)
from ._kernels import (
    first_scalar,
    sbmf_first_scalar,
    sbmf_first_table_scalar,
    sbmf_reload_scalar,
    sbmf_shear_scalar,
    shear_array,
    shear_array_parallel,
    shear_scalar,
    smooth_min_scalar,
    traction_array,
    traction_array_parallel,
    traction_row,
    traction_scalar,
)

__all__ = [
    "CODE_CAP",
    "CODE_COULOMB",
    "CODE_SBMF",
    "CODE_TRESCA",
    "STATUS_OPEN",
    "STATUS_SLIP",
    "STATUS_STICK",
    "first_scalar",
    "sbmf_first_scalar",
    "sbmf_first_table_scalar",
    "sbmf_reload_scalar",
    "sbmf_shear_scalar",
    "shear_array",
    "shear_array_parallel",
    "shear_scalar",
    "smooth_min_scalar",
    "traction_array",
    "traction_array_parallel",
    "traction_row",
    "traction_scalar",
]
