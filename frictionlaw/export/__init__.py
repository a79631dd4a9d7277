"""``frictionlaw-export``: the calibrated law as FE user subroutines and friction tables.

Imported only on demand (``import frictionlaw`` does not load it). From a parameter file it writes
self-contained sources with the constants baked in as double-precision literals, a provenance
header (the file's sha256, the fit summary, the unit system) and a README saying how to compile
and activate them. See ``docs/fe_codes.md``.

Targets: ``abaqus-fric``, ``abaqus-vfric``, ``abaqus-vfriction``, ``lsdyna-usrfrc``,
``lsdyna-usrfrc-mpp``, ``lsdyna``, ``ansys-userfric`` (Fortran), ``calculix`` (the ``abaqus-fric``
routine with a patch for CalculiX 2.20 and the script that builds ``ccx`` with both),
``abaqus-table``, ``lsdyna-table`` (the first loading, Eq. 24 or the tabulated form, as a
friction-coefficient table; no history).

Each target is one :class:`Target` record in :data:`REGISTRY`; its Fortran, README sections and
table decks are template files shipped in this package (one folder per host, the law core in
``core/sbmf_core.f``, the tabulated first loading's part in ``core/sbmf_first_table.f``). :func:`render` and :func:`export` read the record alone; the command is
:mod:`frictionlaw.export.cli`, the host emulation :mod:`frictionlaw.export.harness`.


The names load on first use (PEP 562), so that the command (:mod:`frictionlaw.export.__main__`)
answers ``--version`` and handles Ctrl-C before the templates and NumPy are loaded.
"""

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ._law import UNIT_SYSTEMS, StiffnessSpec, UnitSystem, law_constants, stiffness_spec
    from ._render import ExportResult, export, render
    from ._targets import (
        CALCULIX_DIR,
        REGISTRY,
        TARGETS,
        Extra,
        Host,
        Routine,
        Style,
        Table,
        Target,
        register,
        target,
    )

#: the public names and the module each comes from (imported on first use)
_SOURCES = {
    "UNIT_SYSTEMS": "._law",
    "StiffnessSpec": "._law",
    "UnitSystem": "._law",
    "law_constants": "._law",
    "stiffness_spec": "._law",
    "ExportResult": "._render",
    "export": "._render",
    "render": "._render",
    "CALCULIX_DIR": "._targets",
    "REGISTRY": "._targets",
    "TARGETS": "._targets",
    "Extra": "._targets",
    "Host": "._targets",
    "Routine": "._targets",
    "Style": "._targets",
    "Table": "._targets",
    "Target": "._targets",
    "register": "._targets",
    "target": "._targets",
}

__all__ = [
    "TARGETS",
    "UNIT_SYSTEMS",
    "UnitSystem",
    "StiffnessSpec",
    "ExportResult",
    "export",
    "render",
    "stiffness_spec",
    "law_constants",
    "Target",
    "Host",
    "Routine",
    "Table",
    "Style",
    "Extra",
    "REGISTRY",
    "register",
    "target",
    "CALCULIX_DIR",
]


def __getattr__(name: str) -> Any:
    """A public name, imported from its module on first access."""
    if name in _SOURCES:
        value = getattr(importlib.import_module(_SOURCES[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
