"""Friction laws with one interface: Coulomb, Tresca, Coulomb with a cap, and the SBMF law.

Every law has ``shear_limit(p, p_hist=0) -> (tau, dtau_dp)`` and the kernel
description (``code``, ``coeffs``) that :func:`frictionlaw.traction_update`
and a host's own numba loop (:func:`frictionlaw.kernels.shear_scalar`) use.

Nomenclature
------------
mu : Coulomb coefficient, ``tau = mu p``
m, k : Tresca factor and shear flow stress, ``tau = m k``
tau_max : shear cap of Coulomb-with-cap (Abaqus TAUMAX, Orowan), ``tau = min(mu p, tau_max)``
"""

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _codes as K
from ._flattening_block import LIMIT_MODEL
from .flattening import flattening_data
from .law import FloatOrArray, evaluate, sbmf_coeffs
from .params import FrictionParams, check_range

__all__ = ["Coulomb", "Tresca", "CoulombCap", "SBMFLaw", "LAW_NAMES", "law_from_name"]


class _Law:
    code: int
    uses_history = False
    #: the data of the flattening kernels (empty: no flattening under bulk strain)
    flattening_data: NDArray[np.float64] = np.zeros(0)
    #: the two-state kernels' edge-slope table (the block's ``edge_slope``; empty: none)
    edge_data: NDArray[np.float64] = np.zeros(0)

    @property
    def uses_flattening(self) -> bool:
        """True for a law with a flattening block (it reads the bulk strain increment)."""
        return self.flattening_data.size > 0

    @property
    def uses_two_state(self) -> bool:
        """True for a flattening block of the two-state model (``limit-analysis``)."""
        flat = getattr(getattr(self, "params", None), "flattening", None)
        return flat is not None and flat.model == LIMIT_MODEL

    @property
    def coeffs(self) -> NDArray[np.float64]:
        raise NotImplementedError

    def shear_limit(
        self, p: ArrayLike, p_hist: ArrayLike = 0.0
    ) -> tuple[FloatOrArray, FloatOrArray]:
        """Return ``(tau, dtau_dp)`` for pressure ``p`` (Pa) and history ``p_hist``."""
        return evaluate(self.code, self.coeffs, p, p_hist)

    def __call__(self, p: ArrayLike, p_hist: ArrayLike = 0.0) -> FloatOrArray:
        """The shear limit ``tau`` (Pa) at pressure ``p`` and history ``p_hist`` (broadcasting).

        ``law(p, p_hist)`` equals ``shear_limit(p, p_hist, params)`` for an :class:`SBMFLaw`;
        :meth:`shear_limit` also gives ``dtau/dp``.
        """
        return self.shear_limit(p, p_hist)[0]


def _pos(name: str, v: float) -> float:
    return check_range(name, v, 0.0, math.inf, hi_open=True)


@dataclass(frozen=True)
class Coulomb(_Law):
    """Coulomb's law ``tau = mu p``."""

    mu: float
    code = K.CODE_COULOMB

    def __post_init__(self) -> None:
        object.__setattr__(self, "mu", _pos("mu", self.mu))

    @property
    def coeffs(self) -> NDArray[np.float64]:
        return np.array([self.mu, 0, 0, 0, 0, 0, 0, 0], float)


@dataclass(frozen=True)
class Tresca(_Law):
    """Tresca's law ``tau = m k`` wherever ``p > 0``."""

    m: float
    k: float
    code = K.CODE_TRESCA

    def __post_init__(self) -> None:
        object.__setattr__(self, "m", check_range("m", self.m, 0.0, 1.0))
        object.__setattr__(self, "k", _pos("k", self.k))

    @property
    def coeffs(self) -> NDArray[np.float64]:
        return np.array([self.m * self.k, 0, 0, 0, 0, 0, 0, 0], float)


@dataclass(frozen=True)
class CoulombCap(_Law):
    """Coulomb with a shear cap: ``tau = min(mu p, tau_max)`` (Abaqus TAUMAX, Orowan)."""

    mu: float
    tau_max: float
    code = K.CODE_CAP

    def __post_init__(self) -> None:
        object.__setattr__(self, "mu", _pos("mu", self.mu))
        object.__setattr__(self, "tau_max", _pos("tau_max", self.tau_max))

    @property
    def coeffs(self) -> NDArray[np.float64]:
        return np.array([self.mu, self.tau_max, 0, 0, 0, 0, 0, 0], float)


@dataclass(frozen=True)
class SBMFLaw(_Law):
    """The paper's friction law with the pressure history ``p_hist`` per node. It is Eqs. 24-25."""

    params: FrictionParams
    code = K.CODE_SBMF
    uses_history = True

    def __post_init__(self) -> None:
        if not isinstance(self.params, FrictionParams):
            raise ValueError("params must be a FrictionParams instance")
        data = flattening_data(self.params)
        flat = self.params.flattening
        edge = np.array(() if flat is None else flat.edge_slope or (), dtype=np.float64)
        for name, value in (("_flattening_data", data), ("_edge_data", edge)):
            value.flags.writeable = False
            object.__setattr__(self, name, value)

    @property
    def flattening_data(self) -> NDArray[np.float64]:  # type: ignore[override]
        """The flattening kernels' data of the file's block (empty without one; read-only)."""
        return self._flattening_data  # type: ignore[attr-defined]

    @property
    def edge_data(self) -> NDArray[np.float64]:  # type: ignore[override]
        """The block's ``edge_slope`` as the two-state kernels read it (empty: none; read-only).

        Made once with the law, as its flattening data is.
        """
        return self._edge_data  # type: ignore[attr-defined]

    @property
    def coeffs(self) -> NDArray[np.float64]:
        return sbmf_coeffs(self.params)

    def coulomb_cap_equivalent(self) -> "CoulombCap":
        """The Coulomb-with-cap law this one tends to for ``n1 -> inf``."""
        return CoulombCap(mu=self.params.mu_eff, tau_max=self.params.tau_max)


LAW_NAMES = ("coulomb", "tresca", "cap", "sbmf")


def law_from_name(
    name: str,
    *,
    mu: float | None = None,
    m: float | None = None,
    k: float | None = None,
    tau_max: float | None = None,
    params: FrictionParams | None = None,
) -> "Coulomb | Tresca | CoulombCap | SBMFLaw":
    """Build a law from its name, the one factory of the project (CLI, FE demo, exports).

    Parameters
    ----------
    name : {"coulomb", "tresca", "cap", "sbmf"}
        ``coulomb``: ``tau = mu p``; ``tresca``: ``tau = m k``; ``cap``: ``tau = min(mu p,
        tau_max)`` with ``tau_max = m k`` unless ``tau_max`` is given (Pa); ``sbmf``: Eqs. 24-25
        with ``params``.
    mu, m, k, tau_max : float, optional
        The parameters the chosen law needs (Pa for ``k`` and ``tau_max``).
    params : FrictionParams, optional
        For ``sbmf``.
    """
    key = str(name).lower()
    if key not in LAW_NAMES:
        raise ValueError(f"law must be one of {LAW_NAMES}, got {name!r}")
    if key == "coulomb":
        return Coulomb(mu)  # type: ignore[arg-type]  # None: refused by the law, naming it
    if key == "tresca":
        return Tresca(m, k)  # type: ignore[arg-type]  # None: refused by the law, naming it
    if key == "cap":
        if tau_max is None:
            if m is None or k is None:
                raise ValueError("cap needs tau_max (Pa) or both m and k to set tau_max = m k")
            tau_max = float(m) * float(k)
        return CoulombCap(mu, tau_max)  # type: ignore[arg-type]  # None: refused by the law, naming it
    return SBMFLaw(params)  # type: ignore[arg-type]  # None: refused by the law, naming it
