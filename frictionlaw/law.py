"""The constitutive friction law of Sec. 4 (Eqs. 24-25), vectorised.

Each function accepts scalars or arrays (broadcast together), works in float64,
never warns, and raises ``ValueError`` on NaN input. A scalar result is returned
as a Python float when every input was a scalar.

Notation: ``g(x; n) = tanh(x**n) ** (1/n)``, a smooth minimum of ``x`` and 1
whose corner sharpens as ``n`` grows (see docs/design.md for the reading
of the typesetting).
"""

from types import ModuleType
from typing import TYPE_CHECKING, TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _codes as K

if TYPE_CHECKING:
    from .params import FrictionParams

#: a result of the law: a Python float for scalar input, else a float64 array
FloatOrArray: TypeAlias = float | NDArray[np.float64]


def kernels() -> ModuleType:
    """The numba kernel module, imported on first use so that ``import frictionlaw`` stays light."""
    from . import _kernels

    return _kernels


__all__ = [
    "alpha_first",
    "alpha_reload",
    "shear_limit",
    "shear_limit_dp",
    "reload_jump",
    "PARALLEL_THRESHOLD",
]

#: arrays with at least this many nodes use the parallel kernels
PARALLEL_THRESHOLD = 50_000


def as_float_array(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """``value`` as a float64 array; ``ValueError`` naming ``name`` if it holds NaN.

    Only integer and floating-point input is accepted: complex numbers, strings, bytes,
    booleans, dates and objects are refused rather than converted.
    """
    arr = np.asarray(value)
    if arr.dtype.kind not in "iuf":
        raise ValueError(
            f"{name} must be real numbers (integers or floats), got an array of dtype {arr.dtype}"
        )
    arr = arr.astype(np.float64, copy=False)
    if np.isnan(arr).any():
        raise ValueError(f"{name} must not contain NaN")
    return arr


def sbmf_coeffs(params: "FrictionParams", tau_max: float | None = None) -> NDArray[np.float64]:
    """Kernel coefficient vector of the SBMF law (layout in :mod:`frictionlaw._kernels`).

    The paper's form fills 8 slots; the tabulated reload form appends ``s2``, the number of
    levels ``K`` and the interpolant (``z``, ``ln C2`` and its slopes, ``ln n2`` and its
    slopes: ``10 + 5 K`` slots in all). One contiguous float64 array in every case.
    """
    tm = params.tau_max if tau_max is None else tau_max
    table = params.reload_table if params.reload_form == "tabulated" else None
    k = 0 if table is None else len(table.p_hist)
    c = np.zeros(8 if table is None else 10 + 5 * k)
    c[:7] = (
        tm,
        params.H,
        params.C1,
        params.n1,
        params.C2,
        params.n2,
        float(params.continuous_reload),
    )
    if table is not None:
        kn = table.knots(params.H)
        c[7] = float(K.FORM_TABULATED)
        c[8] = table.s2
        c[9] = float(k)
        c[10:] = np.concatenate([kn["z"], kn["lnC2"], kn["dlnC2"], kn["lnn2"], kn["dlnn2"]])
    return c


def evaluate(
    code: int,
    coeffs: ArrayLike,
    p: ArrayLike,
    p_hist: ArrayLike = 0.0,
    *,
    parallel: bool | None = None,
) -> tuple[FloatOrArray, FloatOrArray]:
    """Run the array shear kernel of law ``code`` on broadcast ``p``, ``p_hist``.

    Returns ``(tau, dtau_dp)`` shaped like the broadcast inputs (floats for scalars).
    """
    p = as_float_array("p", p)
    p_hist = as_float_array("p_hist", p_hist)
    if (p_hist < 0).any():
        raise ValueError("p_hist must be >= 0 (the largest pressure the node has carried)")
    scalar = p.ndim == 0 and p_hist.ndim == 0
    pb, hb = np.broadcast_arrays(p, p_hist)
    pb.flags.writeable = hb.flags.writeable = False  # read-only views (the kernels only read)
    shape = pb.shape
    pf = np.ascontiguousarray(pb).reshape(-1)
    hf = np.ascontiguousarray(hb).reshape(-1)
    tau = np.empty(pf.size)
    dtau = np.empty(pf.size)
    if parallel is None:
        parallel = pf.size >= PARALLEL_THRESHOLD
    kern = kernels().shear_array_parallel if parallel else kernels().shear_array
    kern(int(code), np.ascontiguousarray(coeffs, dtype=np.float64), pf, hf, tau, dtau)
    if scalar:
        return float(tau[0]), float(dtau[0])
    return tau.reshape(shape), dtau.reshape(shape)


def alpha_first(p: ArrayLike, params: "FrictionParams") -> FloatOrArray:
    """Contact ratio on first loading, ``alpha1(p) = g(p C1 / H; n1)``, 0 for ``p <= 0``.

    This is Eq. 24.

    Parameters
    ----------
    p : float or array_like
        Contact pressure in Pa.
    params : FrictionParams
        Law parameters (``C1``, ``n1``, ``H`` are used).
    """
    return evaluate(K.CODE_SBMF, sbmf_coeffs(params, 1.0), p, 0.0)[0]


def alpha_reload(p: ArrayLike, p_hist: ArrayLike, params: "FrictionParams") -> FloatOrArray:
    """Reload contact ratio ``alpha2 = alpha1(p_hist) g(p C2 / (H alpha1(p_hist)); n2)``.

    This is Eq. 25.

    Evaluated on the reload branch whatever ``p`` is. With
    ``params.continuous_reload`` it is divided by its value at ``p = p_hist``,
    so that it equals ``alpha1(p_hist)`` there; extrapolated to ``p > p_hist`` that form
    would exceed 1, and it is capped at a contact ratio of 1. ``alpha1(p_hist) -> 0`` gives 0.
    """
    return evaluate(K.CODE_SBMF_RELOAD, sbmf_coeffs(params, 1.0), p, p_hist)[0]


def shear_limit(p: ArrayLike, p_hist: ArrayLike, params: "FrictionParams") -> FloatOrArray:
    """Friction shear limit ``tau`` (Pa) of the paper's law at ``p`` after the history ``p_hist``.

    It evaluates Eqs. 24-25.

    ``tau = m k alpha2(p)`` (Eq. 25) while ``p < p_hist``, else
    ``tau = m k alpha1(p)`` (Eq. 24). ``p <= 0`` gives 0.
    """
    return evaluate(K.CODE_SBMF, sbmf_coeffs(params), p, p_hist)[0]


def shear_limit_dp(p: ArrayLike, p_hist: ArrayLike, params: "FrictionParams") -> FloatOrArray:
    """Derivative ``d tau / d p`` of :func:`shear_limit` (for implicit hosts), 0 for ``p <= 0``."""
    return evaluate(K.CODE_SBMF, sbmf_coeffs(params), p, p_hist)[1]


def reload_jump(params: "FrictionParams", p_hist: ArrayLike) -> FloatOrArray:
    """Jump of the law at ``p = p_hist``: ``tau_Eq24(p_hist) - tau_Eq25(p_hist)`` in Pa.

    The paper's Eq. 25 at ``p -> p_hist`` is ``m k alpha1(p_hist) g(x2h; n2)``
    with ``x2h = p_hist C2 / (H alpha1(p_hist))``, which is below Eq. 24 there
    since ``g < 1``: the shear drops when the pressure falls just below its
    history. Zero (to rounding) with ``continuous_reload=True``.

    Returns
    -------
    jump : float or ndarray
        Absolute jump in Pa (``>= 0``).
    """
    first = shear_limit(p_hist, 0.0, params)
    below = evaluate(K.CODE_SBMF_RELOAD, sbmf_coeffs(params), p_hist, p_hist)[0]
    return first - below
