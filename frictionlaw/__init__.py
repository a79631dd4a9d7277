"""Runtime of the SBMF constitutive friction law (Eqs. 24-25) for FE contact nodes.

Light by design: ``import frictionlaw`` loads nothing but this module, and each public name is
imported on first use (PEP 562): the law's modules load NumPy, the numba kernels
(:mod:`frictionlaw.kernels`) load on first evaluation, also when reached as
``frictionlaw.kernels``. So the package's commands (``frictionlaw-demo``,
``frictionlaw-export``) answer ``--version`` and handle Ctrl-C before NumPy is loaded.
"""

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # the names as a type checker and a reader see them
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

#: the public names and the module each comes from (imported on first use)
_SOURCES = {
    "RangeCheck": "._range",
    "check_pressure_range": "._range",
    "Flattening": ".flattening",
    "flattening_curve": ".flattening",
    "alpha_first": ".law",
    "alpha_reload": ".law",
    "reload_jump": ".law",
    "shear_limit": ".law",
    "shear_limit_dp": ".law",
    "LAW_NAMES": ".laws",
    "Coulomb": ".laws",
    "CoulombCap": ".laws",
    "SBMFLaw": ".laws",
    "Tresca": ".laws",
    "law_from_name": ".laws",
    "FrictionParams": ".params",
    "TangentialStiffness": ".params",
    "HistoryState": ".state",
    "OPEN": ".traction",
    "SLIP": ".traction",
    "STICK": ".traction",
    "TractionResult": ".traction",
    "traction_update": ".traction",
    "traction_update_force": ".traction",
    "ZonedLaw": ".zones",
    "zone_key": ".zones",
}

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


def __getattr__(name: str) -> Any:
    """A public name, imported from its module on first access; ``kernels``, the numba module."""
    if name in _SOURCES:
        value = getattr(importlib.import_module(_SOURCES[name], __name__), name)
        globals()[name] = value  # found directly from now on
        return value
    if name == "kernels":
        return importlib.import_module(".kernels", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
