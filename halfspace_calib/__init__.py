"""Calibration of the SBMF friction law from elasto-plastic half-space contact of rough surfaces.

Sec. 2-3 of the paper: surfaces in, ``FrictionParams`` JSON out.
"""

from .influence import InfluenceOperator, love_coefficients, normal_operator
from .normal import (
    NormalResult,
    composite_heights,
    composite_modulus,
    solve_normal,
    solve_normal_pair,
)

__all__: list[str] = [
    "InfluenceOperator",
    "NormalResult",
    "composite_heights",
    "composite_modulus",
    "love_coefficients",
    "normal_operator",
    "solve_normal",
    "solve_normal_pair",
]
