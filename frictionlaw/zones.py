"""Zonal laws: one law per tool zone, chosen per contact node by the node's zone id.

A forming tool is not one surface: a polished radius, a ground flank and a textured land differ
in roughness, so each zone has a calibration of its own. :class:`ZonedLaw` holds the laws keyed
by zone name; a host gives every contact node its zone id (an index into the laws, e.g. from
:meth:`ZonedLaw.index` of the name the host's contact carries), and
:func:`frictionlaw.traction_update` / :meth:`ZonedLaw.shear_limit` run each node on its zone's
law with the node's own ``p_hist``.

``p_hist`` is the workpiece's: the largest pressure the node's surface has carried, whichever
zone carried it. A node that moves to another zone keeps its ``p_hist`` and is evaluated with
the new zone's law (its ``alpha1(p_hist)`` recomputed from that law); nothing of the old zone's
law travels with it. The flattening state (issue 43) is the workpiece's too, and it is the
flattened contact *fraction* ``alpha_f`` that travels: a zone with a flattening block reads it
as its own law's pressure ``p_f`` (``alpha1(p_f) = alpha_f`` of that law) and grows it; a zone
without one runs its calibrated law and leaves ``alpha_f`` as it came. The two-state model's
flank slope ``slope_f`` travels the same way: a two-state zone reads and turns it (0: its own
block's slope), any other zone leaves it as it came. Names are compared trimmed and
case-insensitive (:func:`zone_key`), as the exported routines compare the names their hosts pass
(docs/fe_codes.md, "Zones").
"""

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import ModuleType

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .law import PARALLEL_THRESHOLD, FloatOrArray, as_float_array
from .laws import Coulomb, CoulombCap, SBMFLaw, Tresca

__all__ = ["ZonedLaw", "zone_key", "check_zone_ids"]

_LAW_TYPES = (Coulomb, Tresca, CoulombCap, SBMFLaw)


def zone_key(name: object) -> str:
    """The key a zone name is compared by: trimmed and upper case (``" Rim "`` -> ``"RIM"``)."""
    if not isinstance(name, str):
        raise ValueError(f"a zone name must be a string, got {name!r}")
    return name.strip().upper()


def check_zone_ids(zone: ArrayLike, n: int, n_zones: int) -> NDArray[np.int64]:
    """``zone`` as a C-contiguous int64 array of shape ``(n,)`` with every id in ``[0, n_zones)``.

    A scalar is broadcast to every node. Booleans, floats and other types are refused, naming
    ``zone`` and the allowed range.
    """
    z = np.asarray(zone)
    if z.dtype.kind not in "iu":
        raise ValueError(
            f"zone must be integer zone ids in [0, {n_zones - 1}], got an array of dtype {z.dtype}"
        )
    if z.shape not in ((), (n,)):
        raise ValueError(f"zone must be a scalar or have shape ({n},), got shape {z.shape}")
    if z.size and (z.min() < 0 or z.max() >= n_zones):
        raise ValueError(
            f"zone ids must be in [0, {n_zones - 1}] (the laws of the ZonedLaw), got "
            f"{int(z.min())}..{int(z.max())}"
        )
    return np.ascontiguousarray(np.broadcast_to(z, (n,)), dtype=np.int64)


def _kernels() -> ModuleType:
    from . import _kernels_zones

    return _kernels_zones


@dataclass(frozen=True)
class ZonedLaw:
    """Several friction laws keyed by zone; each contact node runs its zone's law.

    Parameters
    ----------
    names : tuple of str
        The zones' names, in the order of ``laws`` (non-empty; unique when trimmed and
        compared case-insensitive).
    laws : tuple of Coulomb, Tresca, CoulombCap or SBMFLaw
        Law ``i`` is zone ``i``'s: a node with zone id ``i`` runs it.

    Zone ids are indices into ``laws``; :meth:`index` gives the id of a name.
    """

    names: tuple
    laws: tuple
    _codes: NDArray[np.int64] = field(init=False, repr=False, compare=False)
    _offsets: NDArray[np.int64] = field(init=False, repr=False, compare=False)
    _coeffs: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    _f_offsets: NDArray[np.int64] = field(init=False, repr=False, compare=False)
    _fdata: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    _models: NDArray[np.int64] = field(init=False, repr=False, compare=False)
    _edges: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    _e_offsets: NDArray[np.int64] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        names, laws = tuple(self.names), tuple(self.laws)
        if not laws or len(names) != len(laws):
            raise ValueError(
                f"names and laws must be as many and at least one, got {len(names)} names and "
                f"{len(laws)} laws"
            )
        keys = [zone_key(n) for n in names]
        if any(not k for k in keys):
            raise ValueError(f"a zone name must not be empty or blank, got {names!r}")
        dup = sorted({n for n in keys if keys.count(n) > 1})
        if dup:
            raise ValueError(f"zone names must differ (trimmed, case-insensitive): {dup} repeat")
        for n, law in zip(names, laws, strict=True):
            if not isinstance(law, _LAW_TYPES):
                raise ValueError(
                    f"the law of zone {n!r} must be a Coulomb, Tresca, CoulombCap or SBMFLaw, "
                    f"got {type(law).__name__}"
                )
        coeffs = [np.ascontiguousarray(law.coeffs, dtype=np.float64) for law in laws]
        offsets = np.concatenate([[0], np.cumsum([c.size for c in coeffs])]).astype(np.int64)
        fdata = [np.ascontiguousarray(law.flattening_data, dtype=np.float64) for law in laws]
        f_offsets = np.concatenate([[0], np.cumsum([d.size for d in fdata])]).astype(np.int64)
        edges = [law.edge_data for law in laws]
        e_offsets = np.concatenate([[0], np.cumsum([e.size for e in edges])]).astype(np.int64)
        for name, value in (
            ("names", names),
            ("laws", laws),
            ("_codes", np.array([law.code for law in laws], dtype=np.int64)),
            ("_offsets", offsets),
            ("_coeffs", np.concatenate(coeffs)),
            ("_f_offsets", f_offsets),
            ("_fdata", np.concatenate(fdata)),
            ("_models", np.array([int(law.uses_two_state) for law in laws], dtype=np.int64)),
            ("_edges", np.concatenate(edges).astype(np.float64)),
            ("_e_offsets", e_offsets),
        ):
            if isinstance(value, np.ndarray):
                value.flags.writeable = False
            object.__setattr__(self, name, value)

    @classmethod
    def from_mapping(cls, zones: Mapping) -> "ZonedLaw":
        """``ZonedLaw`` from ``{name: law}`` (in the mapping's order)."""
        return cls(tuple(zones), tuple(zones.values()))

    @property
    def n_zones(self) -> int:
        """Number of zones."""
        return len(self.laws)

    @property
    def uses_history(self) -> bool:
        """True if any zone's law uses ``p_hist``."""
        return any(law.uses_history for law in self.laws)

    @property
    def uses_flattening(self) -> bool:
        """True if any zone's law has a flattening block (it reads the bulk strain increment)."""
        return any(law.uses_flattening for law in self.laws)

    @property
    def uses_two_state(self) -> bool:
        """True if any zone's flattening block is the two-state model (``limit-analysis``).

        The nodes then carry the flank slope ``slope_f`` too, which only those zones turn.
        """
        return bool(self._models.any())

    def index(self, name: str) -> int:
        """The zone id of ``name`` (trimmed, case-insensitive); ValueError naming it if none."""
        key = zone_key(name)
        for i, n in enumerate(self.names):
            if zone_key(n) == key:
                return i
        raise ValueError(f"zone {name!r} is none of this law's zones ({', '.join(self.names)})")

    def law(self, name: str) -> "Coulomb | Tresca | CoulombCap | SBMFLaw":
        """The law of zone ``name``."""
        return self.laws[self.index(name)]

    def kernel_data(self) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
        """``(codes, offsets, coeffs)``: the packed laws the zoned kernels read (read-only)."""
        return self._codes, self._offsets, self._coeffs

    def flattening_kernel_data(self) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
        """``(f_offsets, fdata)``: each zone's flattening data (an empty slice: none; read-only)."""
        return self._f_offsets, self._fdata

    def edge_kernel_data(self) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
        """``(edges, e_offsets)``: each two-state zone's edge-slope table (empty: none)."""
        return self._edges, self._e_offsets

    def flattening_models(self) -> NDArray[np.int64]:
        """Each zone's flattening model for the kernels: 1 two-state, 0 otherwise (read-only)."""
        return self._models

    def shear_limit(
        self, p: ArrayLike, p_hist: ArrayLike, zone: ArrayLike, *, parallel: bool | None = None
    ) -> tuple[FloatOrArray, FloatOrArray]:
        """``(tau, dtau/dp)`` of each node's zone law at ``p`` (Pa) after ``p_hist`` (Pa).

        ``p``, ``p_hist`` and ``zone`` (integer zone ids) broadcast together; floats are
        returned when all three are scalars.
        """
        p = as_float_array("p", p)
        p_hist = as_float_array("p_hist", p_hist)
        if (p_hist < 0).any():
            raise ValueError("p_hist must be >= 0 (the largest pressure the node has carried)")
        z = np.asarray(zone)
        scalar = p.ndim == 0 and p_hist.ndim == 0 and z.ndim == 0
        try:
            pb, hb, zb = np.broadcast_arrays(p, p_hist, z)
        except ValueError:
            raise ValueError(
                f"p, p_hist and zone must broadcast together, got shapes {p.shape}, "
                f"{p_hist.shape}, {z.shape}"
            ) from None
        shape = pb.shape
        pf = np.ascontiguousarray(pb).reshape(-1)
        hf = np.ascontiguousarray(hb).reshape(-1)
        zf = check_zone_ids(np.ascontiguousarray(zb).reshape(-1), pf.size, self.n_zones)
        tau = np.empty(pf.size)
        dtau = np.empty(pf.size)
        if parallel is None:
            parallel = pf.size >= PARALLEL_THRESHOLD
        k = _kernels()
        kern = k.shear_array_zoned_parallel if parallel else k.shear_array_zoned
        kern(*self.kernel_data(), zf, pf, hf, tau, dtau)
        if scalar:
            return float(tau[0]), float(dtau[0])
        return tau.reshape(shape), dtau.reshape(shape)

    def __call__(self, p: ArrayLike, p_hist: ArrayLike, zone: ArrayLike) -> FloatOrArray:
        """The shear limit ``tau`` (Pa) of each node's zone law (:meth:`shear_limit`)."""
        return self.shear_limit(p, p_hist, zone)[0]
