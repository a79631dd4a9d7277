"""The law's values in a host's units: unit systems, the stick stiffness source, the constants.

What every target bakes in, decided from the parameter file before any template is rendered
(private; the names are public through :mod:`frictionlaw.export`).
"""

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["UnitSystem", "UNIT_SYSTEMS", "StiffnessSpec", "stiffness_spec", "law_constants"]


@dataclass(frozen=True)
class UnitSystem:
    """A host unit system: host value = SI value times the factor."""

    name: str
    stress: float  # Pa -> host stress unit
    length: float  # m -> host length unit
    stress_unit: str
    length_unit: str

    @property
    def stiffness(self):
        """Factor for a tangential stiffness (stress per length)."""
        return self.stress / self.length


UNIT_SYSTEMS = {
    "SI": UnitSystem("SI", 1.0, 1.0, "Pa", "m"),
    "mm-t-s": UnitSystem("mm-t-s", 1e-6, 1e3, "MPa", "mm"),
}


@dataclass(frozen=True)
class StiffnessSpec:
    """Where the generated routine takes the tangential stick stiffness ``k_t`` from.

    ``kind`` is ``"table"`` (the parameter file's calibrated ``k_t(p)``, log-log interpolated),
    ``"constant"`` (``--k-t``) or ``"host"`` (the host's own penalty: for Abaqus FRIC an elastic
    slip of 0.005 x CHRLNGTH). Values are in the host's units.
    """

    kind: str
    p: tuple = ()
    k: tuple = ()
    log_p: tuple = ()
    log_k: tuple = ()
    value: float = 0.0

    def describe(self, units):
        """One line for headers and READMEs."""
        k_unit = f"{units.stress_unit}/{units.length_unit}"
        if self.kind == "table":
            return (
                f"calibrated k_t(p) table from the parameter file ({len(self.p)} points, "
                f"{self.k[0]:.4g}..{self.k[-1]:.4g} {k_unit}, log-log, constant beyond the ends)"
            )
        if self.kind == "constant":
            return f"constant k_t = {self.value:.6g} {k_unit} (--k-t)"
        return "the host's penalty (no calibrated k_t in the parameter file, no --k-t)"


def stiffness_spec(params, units, k_t=None):
    """The stiffness source: ``k_t`` (Pa/m) if given, else the file's table, else the host's."""
    if k_t is not None:
        v = float(k_t)
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"--k-t must be a finite stiffness > 0 in Pa/m, got {k_t!r}")
        return StiffnessSpec("constant", value=v * units.stiffness)
    table = getattr(params, "k_t", None)
    if table is None:
        return StiffnessSpec("host")
    p = tuple(float(v) * units.stress for v in table.p)
    k = tuple(float(v) * units.stiffness for v in table.k_t)
    return StiffnessSpec(
        "table", p=p, k=k, log_p=tuple(np.log(p).tolist()), log_k=tuple(np.log(k).tolist())
    )


def law_constants(params, units):
    """The constants baked into the Fortran core, in the host's units."""
    return {
        "TMAX": params.tau_max * units.stress,
        "H": params.H * units.stress,
        "C1": params.C1,
        "XN1": params.n1,
        "C2": params.C2,
        "XN2": params.n2,
    }
