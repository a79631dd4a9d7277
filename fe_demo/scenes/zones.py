"""Zones of the flat die (issue 42): a law per ring of the die, from a radius outward.

A forming tool is not one surface: a die whose rim is rougher than its centre (a worn or
textured land) has a law of its own there. :class:`RadialZones` splits the die into rings: the
run's law (``--params``, the die's default law) inside, and each named zone from its radius
outward (``fe-demo upsetting --zone rim=PARAMS.json --zone-from-radius rim=R``). A contact
node runs the law of the zone under it at the start of the increment (its radius there: the law
stays fixed through the increment's Newton iterations, as the stick stiffness does) with its own
``p_hist``, which it keeps when it slides into another zone (the workpiece's pressure history,
:mod:`frictionlaw.zones`).
"""

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from frictionlaw import FrictionParams, SBMFLaw, ZonedLaw, zone_key

__all__ = ["RadialZones", "radial_zones", "check_radial_zones", "DIE_ZONE"]

#: the name of the die's default zone (the run's own law, inside the first zone's radius)
DIE_ZONE = "die"


@dataclass(frozen=True)
class RadialZones:
    """The die's laws by radius: law 0 from the axis, law ``i`` from ``radii[i]`` outward.

    Attributes
    ----------
    law : frictionlaw.ZonedLaw
        The laws, ``law.names[0]`` the default (:data:`DIE_ZONE`).
    radii : tuple of float
        Where each law starts (m): ``radii[0] = 0``, then strictly increasing.
    """

    law: ZonedLaw
    radii: tuple

    @property
    def uses_history(self) -> bool:
        """True if any zone's law uses ``p_hist``."""
        return self.law.uses_history

    def zone_at(self, r: ArrayLike) -> NDArray[np.int64]:
        """The zone id at radius ``r`` (m): the last zone whose radius is at or below ``r``."""
        return np.searchsorted(np.asarray(self.radii), np.asarray(r), side="right") - 1

    def default_law(self):
        """The die's default law (law 0): the one the slab-method column evaluates."""
        return self.law.laws[0]

    def describe(self) -> list:
        """``[{"zone", "from_radius_m", "law parameters"}, ...]`` for ``summary.json``."""
        out = []
        for name, law, r in zip(self.law.names, self.law.laws, self.radii, strict=True):
            params = getattr(law, "params", None)
            entry = {"zone": name, "from_radius_m": float(r)}
            if params is not None:
                entry.update(params.to_dict()["parameters"])
            out.append(entry)
        return out


def check_radial_zones(zones) -> list:
    """``zones`` (``(name, params, radius)`` each) sorted by radius, checked.

    Names unique (trimmed, case-insensitive) and not :data:`DIE_ZONE`, radii finite, ``> 0``
    and distinct; ValueError naming ``zones``.
    """
    zones = sorted(zones, key=lambda z: float(z[2]))
    seen, radii = {DIE_ZONE.upper()}, set()
    for name, _, radius in zones:
        r = float(radius)
        if not (np.isfinite(r) and r > 0):
            raise ValueError(
                f"zones: the radius of zone {name!r} must be finite and > 0 (m), got {radius!r}"
            )
        if r in radii:
            raise ValueError(f"zones: zones start at distinct radii, {r!r} m repeats")
        key = zone_key(name)
        if key in seen:
            raise ValueError(
                f"zones: zone {name!r} repeats a name (trimmed, case-insensitive; {DIE_ZONE!r} is "
                "the die's default law)"
            )
        seen.add(key)
        radii.add(r)
    return zones


def radial_zones(default, zones) -> RadialZones:
    """The die's :class:`RadialZones`: ``default`` (a law) inside, ``zones`` outward.

    Parameters
    ----------
    default : frictionlaw law
        The run's law, from the axis to the first zone.
    zones : sequence of (name, params, radius)
        Each zone's name, its parameter file (``FrictionParams`` or a JSON path) and the radius
        (m) from which it applies (:func:`check_radial_zones`).
    """
    names, laws, radii = [DIE_ZONE], [default], [0.0]
    for name, params, radius in check_radial_zones(zones):
        if not isinstance(params, FrictionParams):
            params = FrictionParams.from_json(params)
        names.append(name)
        laws.append(SBMFLaw(params))
        radii.append(float(radius))
    return RadialZones(ZonedLaw(tuple(names), tuple(laws)), tuple(radii))
