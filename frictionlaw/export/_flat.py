"""The flattening under bulk strain in the Fortran routines (issue 43; private).

:class:`FlatSpec` holds what ``core/sbmf_flat.f`` (the law's flattening routines, a port of
:mod:`frictionlaw._kernels_flattening`) is rendered with, in the host's units; each target's
:class:`~frictionlaw.export.Routine` says how its host gives the bulk strain (``flattening``) or
why it cannot (its kind-9 message, written once per process, and the law then runs without).
"""

from dataclasses import dataclass

import numpy as np

from ..flattening import STRETCH_PER_EQUIVALENT_STRAIN, flattening_data

__all__ = [
    "FlatSpec",
    "flat_spec",
    "FlowSpec",
    "flow_spec",
    "FLAT_STATE_NEUTRAL",
    "FLAT_STATE_LSDYNA",
]

#: the state slot of the flattened fraction in SBMF_FRICTION_V's STATE
FLAT_STATE_NEUTRAL = 5
#: LS-DYNA's history slots: the fraction, the plastic strain and the cycle of the last call
FLAT_STATE_LSDYNA = (5, 6, 7)


@dataclass(frozen=True)
class FlatSpec:
    """A law's flattening block as the Fortran routines carry it (host units).

    Attributes
    ----------
    slope, beta : float
        ``tan(theta)`` and ``beta`` of the block.
    stretch : float
        The stretch across the ridges per unit equivalent plastic strain, ``sqrt(3) / 2``
        (:data:`frictionlaw.flattening.STRETCH_PER_EQUIVALENT_STRAIN`).
    s0 : float
        The layer's flow stress ``2 k`` of the file (host stress unit).
    sigma_y : float
        The file's ``sigma_y`` (host stress unit): a host's flow stress scales ``s0`` by it.
    cap : float
        The pressure from which ``alpha1`` is 1 to rounding (host stress unit), the runtime's.
    p_min : float
        ``1e-12 H``: below it nothing flattens (host stress unit).
    gx, gw : tuple of float
        The 2-, 4- and 8-point Gauss-Legendre nodes and weights, one after the other.
    width, narrow : float, (float, float)
        The widest panel in ``v`` and the widest interval of the 2- and 4-point rules.
    """

    slope: float
    beta: float
    stretch: float
    s0: float
    sigma_y: float
    cap: float
    p_min: float
    gx: tuple
    gw: tuple
    width: float
    narrow: tuple


def flat_spec(params, units):
    """The :class:`FlatSpec` of ``params`` in ``units`` (None without a flattening block).

    ``ValueError`` for ``m = 0`` (``tau_max = 0``: no friction to flatten; the routines read
    ``alpha1`` as the first loading's shear over ``tau_max``).
    """
    data = flattening_data(params)
    if data.size == 0:
        return None
    from .. import _kernels_flattening as K  # the rules the kernels integrate by (numba loads)

    if not params.tau_max > 0:
        raise ValueError(
            "a flattening block with m = 0: the law has no friction to flatten; export the "
            "file without its flattening block"
        )
    s = units.stress
    slope, beta, s0, sigma_y, cap = (float(v) for v in data[: K.FLAT_HEAD])
    H = params.H * s
    return FlatSpec(
        slope,
        beta,
        STRETCH_PER_EQUIVALENT_STRAIN,
        s0 * s,
        sigma_y * s,
        cap * s,
        float(np.float64(K.P_MIN_RATIO) * np.float64(H)),
        tuple(float(x) for x in K._GX),
        tuple(float(w) for w in K._GW),
        float(K._WIDTH),
        tuple(float(x) for x in K._NARROW),
    )


@dataclass(frozen=True)
class FlowSpec:
    """The workpiece's flow curve baked into a routine, in the host's stress unit.

    For a host that passes only the total plastic strain (LS-DYNA's ``usrfrc``,
    ``--flow-curve``).

    Attributes
    ----------
    form : str
        ``"swift"`` (``K``, ``eps0``, ``n``) or ``"table"`` (``strain``, ``stress``: joined by
        straight lines, the last segment continued beyond the last strain, as LS-DYNA continues
        its load curves).
    describe : str
        The curve in words (SI), for the header and README.
    """

    form: str
    describe: str
    K: float = 0.0
    eps0: float = 0.0
    n: float = 0.0
    strain: tuple = ()
    stress: tuple = ()


def flow_spec(curve, units):
    """The :class:`FlowSpec` of a :mod:`frictionlaw.flow_curve` curve in ``units``."""
    s = units.stress
    d = curve.to_dict()
    if d["form"] == "swift":
        return FlowSpec("swift", curve.describe(), K=d["K_Pa"] * s, eps0=d["eps0"], n=d["n"])
    return FlowSpec(
        "table",
        curve.describe(),
        strain=tuple(d["strain"]),
        stress=tuple(v * s for v in d["sigma_y_Pa"]),
    )
