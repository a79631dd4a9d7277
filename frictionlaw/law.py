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


def broadcast_named(**arrays: ArrayLike) -> list[NDArray[np.float64]]:
    """The named arrays (:func:`as_float_array`) broadcast together, in the order given.

    ``ValueError`` naming the argument that does not broadcast, its shape and the shape of the
    one before it that it disagrees with, instead of NumPy's positional message.
    """
    named = {name: as_float_array(name, value) for name, value in arrays.items()}
    try:
        return list(np.broadcast_arrays(*named.values()))
    except ValueError:
        pass
    seen: dict[str, tuple[int, ...]] = {}
    shape: tuple[int, ...] = ()
    for name, a in named.items():
        try:
            shape = np.broadcast_shapes(shape, a.shape)
        except ValueError:
            other = next(
                (n for n, s in seen.items() if not _broadcastable(s, a.shape)), ", ".join(seen)
            )
            theirs = seen.get(other, shape)
            raise ValueError(
                f"{name} has shape {a.shape}, {other} {theirs}: they need one shape, or shapes "
                "that broadcast (a scalar applies to every node)"
            ) from None
        seen[name] = a.shape
    raise AssertionError("unreachable: the shapes broadcast")  # pragma: no cover


def _broadcastable(a: tuple[int, ...], b: tuple[int, ...]) -> bool:
    try:
        np.broadcast_shapes(a, b)
    except ValueError:
        return False
    return True


def sbmf_coeffs(params: "FrictionParams", tau_max: float | None = None) -> NDArray[np.float64]:
    """Kernel coefficient vector of the SBMF law (layout in :mod:`frictionlaw._kernels`).

    The header fills 8 slots (Eq. 24 with the paper's Eq. 25: nothing more); the reload form
    that runs appends its block (the tabulated form: ``s2``, the number of levels ``K`` and the
    interpolant, ``2 + 5 K`` slots), then a first-loading form other than Eq. 24 its code and
    block (the tabulated form: ``J``, ``u``, ``v``, ``d``: ``2 + 3 J`` slots; with the paper's
    reload form after the placeholder ``s2 = 1, K = 0``). Each block is what the form's record
    (:class:`frictionlaw.forms.BranchForm`) lowers its data to. One contiguous float64 array.
    """
    tm = params.tau_max if tau_max is None else tau_max
    first, reload = params.branch_forms()
    rcode, rblock = reload.lower(params.reload_table, params.H)
    fcode, fblock = first.lower(params.first_loading_table, params.H)
    head = [
        tm,
        params.H,
        params.C1,
        params.n1,
        params.C2,
        params.n2,
        float(params.continuous_reload),
        float(rcode),
    ]
    if fcode == K.FIRST_EQ24:
        return np.concatenate([head, rblock]).astype(np.float64)
    if rblock.size == 0:
        rblock = np.array([1.0, 0.0])  # s2 = 1, K = 0: no reload table
    return np.concatenate([head, rblock, [float(fcode)], fblock]).astype(np.float64)


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


class FixedPoints:
    """The serial array kernel of law ``code`` on points fixed once, coefficients to vary.

    For fits that evaluate a law some thousand times at the same points with a few coefficients
    changed: :func:`evaluate`'s checks, broadcasting and allocations cost 10-20 times the kernel
    on a dozen points. Set slots of :attr:`coeffs` (the layout of :func:`sbmf_coeffs`), then call:
    ``tau`` at ``p, p_hist``, bit for bit :func:`evaluate`'s, as a new array shaped like ``p``.
    Inputs are trusted (finite, ``p_hist >= 0``): validate them before.
    """

    def __init__(self, code: int, coeffs: ArrayLike, p: ArrayLike, p_hist: ArrayLike = 0.0):
        self.code = int(code)
        self.coeffs = np.array(coeffs, dtype=np.float64)
        self.shape = np.shape(p)
        self.p = np.ascontiguousarray(p, dtype=np.float64).ravel()
        self.p_hist = np.ascontiguousarray(np.broadcast_to(p_hist, self.shape), dtype=np.float64)
        self.p_hist = self.p_hist.ravel()
        self._tau = np.empty(self.p.size)
        self._dtau = np.empty(self.p.size)
        self._kernel = kernels().shear_array

    def __call__(self) -> NDArray[np.float64]:
        self._kernel(self.code, self.coeffs, self.p, self.p_hist, self._tau, self._dtau)
        return self._tau.reshape(self.shape).copy()


def alpha_first(p: ArrayLike, params: "FrictionParams") -> FloatOrArray:
    """Contact ratio on first loading ``alpha1(p)`` of the form that runs, 0 for ``p <= 0``.

    This is Eq. 24, ``alpha1(p) = g(p C1 / H; n1)``, with ``first_loading_form="eq24"``, and
    the computed first loading interpolated with ``"tabulated"``
    (:mod:`frictionlaw.first_loading`).

    Parameters
    ----------
    p : float or array_like
        Contact pressure in Pa.
    params : FrictionParams
        Law parameters (``C1``, ``n1``, ``H`` or the first-loading table are used).
    """
    return evaluate(K.CODE_SBMF, sbmf_coeffs(params, 1.0), p, 0.0)[0]


def alpha_reload(p: ArrayLike, p_hist: ArrayLike, params: "FrictionParams") -> FloatOrArray:
    """Reload contact ratio ``alpha2 = alpha1(p_hist) g(p C2 / (H alpha1(p_hist)); n2)``.

    This is Eq. 25 (or its tabulated form, :mod:`frictionlaw.reload_form`), with
    ``alpha1(p_hist)`` of the first-loading form that runs.

    Evaluated on the reload branch whatever ``p`` is. With
    ``params.continuous_reload`` it is divided by its value at ``p = p_hist``,
    so that it equals ``alpha1(p_hist)`` there; extrapolated to ``p > p_hist`` that form
    would exceed 1, and it is capped at a contact ratio of 1. ``alpha1(p_hist) -> 0`` gives 0.
    """
    return evaluate(K.CODE_SBMF_RELOAD, sbmf_coeffs(params, 1.0), p, p_hist)[0]


def shear_limit(p: ArrayLike, p_hist: ArrayLike, params: "FrictionParams") -> FloatOrArray:
    """Friction shear limit ``tau`` (Pa) of the paper's law at ``p`` after the history ``p_hist``.

    It evaluates Eqs. 24-25 (in the forms ``params`` runs).

    ``tau = m k alpha2(p)`` (Eq. 25) while ``p < p_hist``, else
    ``tau = m k alpha1(p)`` (Eq. 24 or the tabulated first loading). ``p <= 0`` gives 0.
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
