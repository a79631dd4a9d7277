"""Contact mechanics of rough surfaces on elastic half-spaces (Sec. 2): physics and algorithms only.

- :mod:`.influence`: the Love / DC-FFT influence operator of the normal problem (Eqs. 3-4)
- :mod:`.cerruti`: the Cerruti coefficients of the tangential problem (Eqs. 13-16)
- :mod:`.normal`: the elasto-plastic normal solver (Sec. 2.1, Eqs. 2, 5-9)
- :mod:`.tangential`: the tangential (pre-sliding) solver with the Tresca cap (Sec. 2.2)
- :mod:`.reference`: analytic solutions (Hertz, Westergaard) the tests compare with
- :mod:`.materials`: the :class:`Materials` and :class:`SolverSettings` records every sweep takes

No files, no plots, no scene: arrays and numbers in, typed results out.
"""

from .cerruti import E_prime, cerruti_coefficients, shear_modulus_composite
from .influence import InfluenceOperator, love_coefficients, normal_operator
from .materials import Materials, SolverSettings, sigma_y_from_hardness
from .normal import (
    NormalResult,
    composite_heights,
    composite_modulus,
    estimate_memory,
    solve_normal,
    solve_normal_pair,
)
from .tangential import TangentialResult, solve_tangential, tangential_bound, tau_adh_full_sliding

__all__ = [
    "E_prime",
    "InfluenceOperator",
    "Materials",
    "NormalResult",
    "SolverSettings",
    "TangentialResult",
    "cerruti_coefficients",
    "composite_heights",
    "composite_modulus",
    "estimate_memory",
    "love_coefficients",
    "normal_operator",
    "shear_modulus_composite",
    "sigma_y_from_hardness",
    "solve_normal",
    "solve_normal_pair",
    "solve_tangential",
    "tangential_bound",
    "tau_adh_full_sliding",
]
