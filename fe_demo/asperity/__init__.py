"""The asperity truth of issue 43: a plane-strain FE model of a rough profile pressed and stretched.

A strip whose top is a measured or regular profile (:mod:`.mesh`) is pressed by a rigid,
frictionless flat to a nominal pressure and stretched in-plane between its symmetry sides at
that pressure (:mod:`.model`, on fe_demo's own element, J2 return map and linear solve); the
real contact fraction against bulk strain is the result (:func:`asperity_contact_fraction`),
against which the flattening law is judged (docs/flattening_truth.md). It imports the FE core
(:mod:`fe_demo.solver`) and nothing else of fe_demo.
"""

from .flattening import (
    AsperityHistory,
    AsperityMesh,
    AsperityOptions,
    AsperityResult,
    PunchResult,
    asperity_contact_fraction,
    contact_fraction,
    flat_punch_pressure,
    perfectly_plastic,
    prandtl_hardness,
)
from .mesh import StripMesh, check_profile, sine_profile, strip_mesh, wedge_profile
from .model import StepResult, StripModel, geometric_stiffness

__all__ = [
    "AsperityHistory",
    "AsperityMesh",
    "AsperityOptions",
    "AsperityResult",
    "PunchResult",
    "StepResult",
    "StripMesh",
    "StripModel",
    "asperity_contact_fraction",
    "check_profile",
    "contact_fraction",
    "flat_punch_pressure",
    "geometric_stiffness",
    "perfectly_plastic",
    "prandtl_hardness",
    "sine_profile",
    "strip_mesh",
    "wedge_profile",
]
