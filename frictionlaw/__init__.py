"""Runtime of the SBMF constitutive friction law (Eqs. 24-25) for FE contact nodes.

Light by design: ``import frictionlaw`` loads numpy only; the numba kernels
(:mod:`frictionlaw.kernels`) load on first use, also when reached as ``frictionlaw.kernels``.
"""

from ._range import RangeCheck, check_pressure_range
from .flattening import Flattening, flattening_curve
from .law import alpha_first, alpha_reload, reload_jump, shear_limit, shear_limit_dp
from .laws import LAW_NAMES, Coulomb, CoulombCap, SBMFLaw, Tresca, law_from_name
from .params import FrictionParams, TangentialStiffness
from .state import HistoryState
from .traction import (
    OPEN,
    SLIP,
    STICK,
    TractionResult,
    traction_update,
    traction_update_force,
)
from .zones import ZonedLaw, zone_key

__version__ = "0.1.0"

__all__ = [
    "FrictionParams",
    "TangentialStiffness",
    "Flattening",
    "flattening_curve",
    "RangeCheck",
    "check_pressure_range",
    "alpha_first",
    "alpha_reload",
    "shear_limit",
    "shear_limit_dp",
    "reload_jump",
    "Coulomb",
    "Tresca",
    "CoulombCap",
    "SBMFLaw",
    "LAW_NAMES",
    "law_from_name",
    "ZonedLaw",
    "zone_key",
    "HistoryState",
    "TractionResult",
    "traction_update",
    "traction_update_force",
    "OPEN",
    "STICK",
    "SLIP",
]


def __getattr__(name):
    """Load the numba kernel module on first access (``frictionlaw.kernels.shear_scalar``)."""
    if name == "kernels":
        import importlib

        return importlib.import_module(".kernels", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
