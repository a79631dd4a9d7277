"""The tangential traction update of a friction user subroutine (stick/slip return map).

Penalty regularised stick: the trial traction ``t_tr = t_old + k_t du`` is kept
while ``|t_tr| <= tau(p, p_hist)`` (stick), otherwise returned radially onto the
limit circle (slip). Outputs include the consistent tangent for implicit hosts.
"""

import math
from types import ModuleType
from typing import TYPE_CHECKING, NamedTuple, TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _codes as K
from .law import PARALLEL_THRESHOLD, as_float_array, kernels

if TYPE_CHECKING:
    from .laws import Coulomb, CoulombCap, SBMFLaw, Tresca
    from .state import HistoryState
    from .zones import ZonedLaw

    #: the laws a traction update takes
    Law: TypeAlias = Coulomb | Tresca | CoulombCap | SBMFLaw | ZonedLaw

__all__ = ["TractionResult", "traction_update", "traction_update_force", "OPEN", "STICK", "SLIP"]

OPEN, STICK, SLIP = K.STATUS_OPEN, K.STATUS_STICK, K.STATUS_SLIP
_P_MAX = np.finfo(np.float64).max


class TractionResult(NamedTuple):
    """Result of :func:`traction_update` (stress based) or :func:`traction_update_force`.

    Attributes
    ----------
    traction : ndarray, shape (n, d)
        New tangential traction (Pa); force (N) from the force adapter.
    status : ndarray of int8, shape (n,)
        0 open, 1 stick, 2 slip.
    dt_dslip : ndarray, shape (n, d, d)
        Consistent tangent ``d traction / d slip_increment`` (Pa/m); ``d force / d slip``
        (N/m) from the force adapter.
    dt_dp : ndarray, shape (n, d)
        ``d traction / d p`` (1); ``d force / d f_n`` (1) from the force adapter.
    """

    traction: np.ndarray
    status: np.ndarray
    dt_dslip: np.ndarray
    dt_dp: np.ndarray


def _as_2d(name: str, v: ArrayLike, n: int) -> NDArray[np.float64]:
    a = as_float_array(name, v)
    if a.ndim == 1:
        a = a[:, None]
    if a.ndim != 2 or a.shape[0] != n or a.shape[1] not in (1, 2):
        raise ValueError(f"{name} must have shape ({n},), ({n}, 1) or ({n}, 2), got {np.shape(v)}")
    if not np.isfinite(a).all():
        raise ValueError(f"{name} must be finite")
    return np.ascontiguousarray(a)


def traction_update(
    law: "Law",
    p: ArrayLike,
    slip_increment: ArrayLike,
    traction_old: ArrayLike,
    k_t: ArrayLike,
    state: "HistoryState | None" = None,
    *,
    parallel: bool | None = None,
    out: "TractionResult | None" = None,
    zone: ArrayLike | None = None,
    d_eps: ArrayLike | None = None,
    sigma_y: ArrayLike | None = None,
    hardening: ArrayLike | None = None,
) -> "TractionResult":
    """Stick/slip traction update at every contact node (stress based).

    Parameters
    ----------
    law : Coulomb, Tresca, CoulombCap, SBMFLaw or ZonedLaw
        The friction law (a :class:`frictionlaw.ZonedLaw`: each node runs its zone's law).
    p : array_like, shape (n,)
        Contact pressure (Pa), finite; ``p <= 0`` is an open node (zero traction).
    slip_increment : array_like, shape (n,), (n, 1) or (n, 2)
        Relative tangential displacement increment (m), 1 or 2 directions.
    traction_old : array_like, same shape as ``slip_increment``
        Traction at the end of the last accepted increment (Pa).
    k_t : float or array_like, shape (n,)
        Tangential penalty stiffness (Pa/m), ``> 0``.
    state : HistoryState, optional
        ``p_hist`` per node for laws with history. Its committed history is
        used and the trial history ``max(p_hist, p)`` is proposed; the host
        commits once per accepted increment. Without a state every node is
        on first loading (``p_hist = 0``).
    parallel : bool, optional
        Force the parallel (True) or serial (False) kernel; by size otherwise.
    out : TractionResult, optional
        Arrays to write the result into (a previous result of the same shapes), so that a
        host's Newton loop allocates nothing per call; C-contiguous, float64 (status int8).
    zone : array_like of int, shape (n,), optional
        Each node's zone id (an index into ``law.laws``), for a :class:`~frictionlaw.ZonedLaw`
        only (required there, refused for any other law). The node's ``p_hist`` is its own
        whatever zone it is in (docs/runtime.md, "Zones").
    d_eps : float or array_like, shape (n,), optional
        Each node's bulk equivalent plastic strain increment of the increment (``>= 0``,
        finite): the flattening of the asperities under bulk strain (docs/flattening.md, Eqs.
        F5-F6) for a law with a ``flattening`` block (a :class:`~frictionlaw.ZonedLaw`: its zones
        with one; refused for laws without). The node's flattened fraction ``alpha_f`` is read
        from the state's committed one and the trial one written, like ``p_hist``; the shear
        uses the trial fraction (its ``dt_dp`` includes the update's ``d alpha / d p`` on first
        loading). ``None`` (or all zeros with ``alpha_f = 0``): the law as calibrated, bit for bit.
    sigma_y : float or array_like, shape (n,), optional
        The bulk's current flow stress per node (Pa, in ``[1e3, 1e13]``), with ``d_eps`` only:
        it scales the layer's flow stress ``2 k`` by ``sigma_y`` over the file's (how strain
        rate and hardening enter); the file's ``sigma_y`` by default.
    hardening : float or array_like, shape (n,), optional
        The bulk's hardening modulus ``d sigma_y / d eps_eq`` per node (Pa, finite, ``>= 0``),
        with ``d_eps`` only: it limits the slip-line lattice's sinking rate to ``6 p (1 - A) / h``
        and the flattening beyond the pressing to ``3 p / (4 h tan(theta))`` (Eqs. F2c and
        F2d, docs/flattening.md); ``None`` or 0: a perfectly plastic bulk, as before.
        Refused for a block of the two-state model (``limit-analysis``), whose table is
        perfectly plastic, and for a zoned law with such a zone; that model reads and writes
        the state's ``slope_f`` beside ``alpha_f``.

    Returns
    -------
    TractionResult
        ``out`` itself when it was given.
    """
    p = as_float_array("p", p)
    if p.ndim != 1:
        raise ValueError(f"p must be 1-D (one value per node), got shape {p.shape}")
    if not np.isfinite(p).all():
        raise ValueError("p must be finite (it becomes the node's trial p_hist)")
    n = p.size
    zoned = _zoned(law, zone, n)
    if sigma_y is not None and d_eps is None:
        raise ValueError("sigma_y applies with d_eps only (the flattening's flow stress)")
    if hardening is not None and d_eps is None:
        raise ValueError("hardening applies with d_eps only (the flattening's lattice, Eq. F2c)")
    if hardening is not None and getattr(law, "uses_two_state", False):
        raise ValueError(
            "hardening does not apply to the two-state flattening (model 'limit-analysis'): its "
            "table is perfectly plastic"
        )
    squeeze = np.ndim(slip_increment) == 1
    du = _as_2d("slip_increment", slip_increment, n)
    t_old = _as_2d("traction_old", traction_old, n)
    if t_old.shape != du.shape:
        raise ValueError("traction_old must have the shape of slip_increment")
    kt = as_float_array("k_t", k_t)
    if kt.shape not in ((), (1,), (n,)):
        raise ValueError(f"k_t must be a scalar or have shape ({n},), got shape {kt.shape}")
    kt = np.array(np.broadcast_to(kt, (n,)), dtype=np.float64)
    if not (np.isfinite(kt).all() and (kt > 0).all()):
        raise ValueError("k_t must be finite and > 0")
    if getattr(law, "uses_history", False) and state is not None:
        if state.n_nodes != n:
            raise ValueError(f"state has {state.n_nodes} nodes, p has {n}")
        p_hist = state.committed_array()
    else:
        p_hist = np.zeros(n)
    d = du.shape[1]
    if out is None:
        t_new, status, dt_ddu, dt_dp = (
            np.empty((n, d)),
            np.empty(n, np.int8),
            np.empty((n, d, d)),
            np.empty((n, d)),
        )
    else:
        t_new, status, dt_ddu, dt_dp = _out_views(out, n, d, squeeze)
    history = state is not None and getattr(law, "uses_history", False)
    # the kernel writes the trial history max(p_hist, p) straight into the state
    p_trial = state.trial_array() if history and state is not None else np.empty(n)
    if parallel is None:
        parallel = n >= PARALLEL_THRESHOLD
    tail = (du, t_old, kt, t_new, status, dt_ddu, dt_dp, p_trial)
    if (
        d_eps is None
        and history
        and getattr(law, "uses_flattening", False)
        and np.any(state.alpha_f > 0)  # type: ignore[union-attr]
    ):
        # a stored flattening is the node's state, as p_hist is: without a strain increment it
        # is read (no growth), never dropped
        d_eps = 0.0
    if d_eps is not None:
        de, sy, hd, (a_c, a_t) = _flattening_inputs(law, d_eps, sigma_y, hardening, state, n)
        if getattr(law, "uses_two_state", False):  # model limit-analysis: a second state
            _limit_update(law, zoned, p, p_hist, a_c, a_t, de, sy, hd, state, tail, parallel)
        else:
            fk = flattening_kernels()
            if zoned is not None:
                zdata = law.kernel_data()  # type: ignore[union-attr]
                fdata = law.flattening_kernel_data()  # type: ignore[union-attr]
                fkern = (
                    fk.traction_array_zoned_flat_parallel
                    if parallel
                    else fk.traction_array_zoned_flat
                )
                fhead: tuple = (*zdata, *fdata, zoned)
            else:
                fkern = fk.traction_array_flat_parallel if parallel else fk.traction_array_flat
                fhead = (int(law.code), law.coeffs, law.flattening_data)  # type: ignore[union-attr]
            fkern(*fhead, np.ascontiguousarray(p), p_hist, a_c, de, sy, hd, *tail, a_t)
    elif zoned is not None:
        zk = zoned_kernels()
        zkern = zk.traction_array_zoned_parallel if parallel else zk.traction_array_zoned
        zkern(*law.kernel_data(), zoned, np.ascontiguousarray(p), p_hist, *tail)  # type: ignore[union-attr]
    else:
        kern = kernels().traction_array_parallel if parallel else kernels().traction_array
        kern(int(law.code), law.coeffs, np.ascontiguousarray(p), p_hist, *tail)  # type: ignore[union-attr]
    if out is not None:
        return out
    if squeeze:
        return TractionResult(t_new[:, 0], status, dt_ddu[:, 0, 0], dt_dp[:, 0])
    return TractionResult(t_new, status, dt_ddu, dt_dp)


def zoned_kernels() -> ModuleType:
    """The zoned laws' numba kernels, imported on first use."""
    from . import _kernels_zones

    return _kernels_zones


def flattening_kernels() -> ModuleType:
    """The flattening kernels (issue 43), imported on first use."""
    from . import _kernels_flattening

    return _kernels_flattening


def _limit_update(
    law: "Law",
    zoned: NDArray[np.int64] | None,
    p: NDArray[np.float64],
    p_hist: NDArray[np.float64],
    a_c: NDArray[np.float64],
    a_t: NDArray[np.float64],
    de: NDArray[np.float64],
    sy: NDArray[np.float64],
    hd: NDArray[np.float64],
    state: "HistoryState | None",
    tail: tuple,
    parallel: bool,
) -> None:
    """The return map with the two-state flattening (model limit-analysis).

    Its kernels read the shipped rate table and write the trial ``slope_f`` beside ``alpha_f``;
    a zoned law (``zoned``, each node's zone) runs each node's zone law, its one-state zones
    with the hardening modulus ``hd``.
    """
    from ._limit_table import rate_table

    n = p.size
    s_c, s_t = state.slope_arrays() if state is not None else (np.zeros(n), np.empty(n))
    t = rate_table()
    table = (t.pressures, t.offsets, t.a, t.ln_s, t.dA, t.ds)
    lk = limit_kernels()
    nodes = (np.ascontiguousarray(p), p_hist, a_c, s_c, de, sy)
    if zoned is not None:
        kern = lk.traction_array_zoned_limit_parallel if parallel else lk.traction_array_zoned_limit
        head = (*law.kernel_data(), *law.flattening_kernel_data(), law.flattening_models())  # type: ignore[union-attr]
        kern(*head, *table, *law.edge_kernel_data(), zoned, *nodes, hd, *tail, a_t, s_t)  # type: ignore[union-attr]
        return
    kern = lk.traction_array_limit_parallel if parallel else lk.traction_array_limit
    head = (int(law.code), law.coeffs, law.flattening_data)  # type: ignore[union-attr]
    kern(*head, *table, law.edge_data, *nodes, *tail, a_t, s_t)  # type: ignore[union-attr]


def limit_kernels() -> ModuleType:
    """The two-state flattening's kernels (model limit-analysis), imported on first use."""
    from . import _kernels_limit

    return _kernels_limit


def _flattening_inputs(
    law: object,
    d_eps: ArrayLike,
    sigma_y: ArrayLike | None,
    hardening: ArrayLike | None,
    state: "HistoryState | None",
    n: int,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], tuple[NDArray, NDArray]]:
    """``(d_eps, sigy, hard, (alpha_f committed, trial))`` checked for the flattening kernels.

    ``sigy`` is 0 where the file's ``sigma_y`` applies, ``hard`` 0 for a perfectly plastic bulk.
    Without a state every node is a virgin surface (``alpha_f = 0``) and the trial fraction goes
    to a scratch array.
    """
    if not getattr(law, "uses_flattening", False):
        raise ValueError(
            "d_eps applies to a law with a flattening block (FrictionParams.flattening, "
            "docs/flattening.md); this law has none"
        )
    de = _per_node("d_eps", d_eps, n, 0.0, math.inf, "finite and >= 0 (a plastic strain increment)")
    sy = np.zeros(n)
    if sigma_y is not None:
        sy = _per_node(
            "sigma_y", sigma_y, n, 1e3, 1e13, "in [1e3, 1e13] Pa (the bulk's flow stress)"
        )
    hd = np.zeros(n)
    if hardening is not None:
        why = "finite and >= 0 (Pa, d sigma_y / d eps_eq; 0: perfectly plastic)"
        hd = _per_node("hardening", hardening, n, 0.0, math.inf, why)
    if state is None:
        return de, sy, hd, (np.zeros(n), np.empty(n))
    if state.n_nodes != n:
        raise ValueError(f"state has {state.n_nodes} nodes, p has {n}")
    return de, sy, hd, state.flattening_arrays()


def _per_node(
    name: str, value: ArrayLike, n: int, lo: float, hi: float, allowed: str
) -> NDArray[np.float64]:
    """``value`` as ``n`` nodes' C-contiguous float64 array, finite, in ``[lo, hi]``.

    A scalar is broadcast; ``ValueError`` naming ``name`` and what is ``allowed`` otherwise.
    """
    a = as_float_array(name, value)
    if a.shape not in ((), (1,), (n,)):
        raise ValueError(f"{name} must be a scalar or have shape ({n},), got shape {a.shape}")
    if not (np.isfinite(a).all() and (a >= lo).all() and (a <= hi).all()):
        raise ValueError(f"{name} must be {allowed}")
    return np.ascontiguousarray(np.broadcast_to(a, (n,)), dtype=np.float64)


def _zoned(law: object, zone: ArrayLike | None, n: int) -> NDArray[np.int64] | None:
    """The checked zone ids of a zoned law; None for a one-law update (``zone`` refused there)."""
    from .zones import ZonedLaw, check_zone_ids

    if isinstance(law, ZonedLaw):
        if zone is None:
            raise ValueError(
                f"zone is required with a ZonedLaw: one zone id per node in [0, {law.n_zones - 1}]"
            )
        return check_zone_ids(zone, n, law.n_zones)
    if zone is not None:
        raise ValueError("zone applies to a ZonedLaw only (this law is the same at every node)")
    return None


def _out_views(out: object, n: int, d: int, squeeze: bool) -> list[NDArray]:
    """2-D/3-D views of the caller's output arrays (which the kernel fills in place)."""
    if not isinstance(out, TractionResult):
        raise ValueError("out must be a TractionResult (e.g. the result of a previous call)")
    shapes = ((n,), (n,), (n,), (n,)) if squeeze else ((n, d), (n,), (n, d, d), (n, d))
    full = ((n, d), (n,), (n, d, d), (n, d))
    views = []
    for name, arr, shape, shp2, dtype in zip(
        out._fields, out, shapes, full, (np.float64, np.int8, np.float64, np.float64), strict=True
    ):
        if (
            not isinstance(arr, np.ndarray)
            or arr.shape != shape
            or arr.dtype != dtype
            or not arr.flags.c_contiguous
            or not arr.flags.writeable
        ):
            raise ValueError(
                f"out.{name} must be a writable C-contiguous {np.dtype(dtype).name} array of "
                f"shape {shape}"
            )
        views.append(arr.reshape(shp2))
    return views


def traction_update_force(
    law: "Law",
    f_n: ArrayLike,
    area: ArrayLike,
    slip_increment: ArrayLike,
    force_old: ArrayLike,
    k_force: ArrayLike,
    state: "HistoryState | None" = None,
    *,
    parallel: bool | None = None,
    out: "TractionResult | None" = None,
    zone: ArrayLike | None = None,
    d_eps: ArrayLike | None = None,
    sigma_y: ArrayLike | None = None,
    hardening: ArrayLike | None = None,
) -> "TractionResult":
    """Force-based adapter (Abaqus/Explicit VFRIC style): forces and nodal areas in, forces out.

    ``p = f_n / area``, ``t_old = force_old / area`` and ``k_t = k_force / area``, then
    :func:`traction_update`. A pressure that overflows a double is taken as the largest
    double (where every law but Coulomb's is at its cap).

    Parameters
    ----------
    f_n : array_like, shape (n,)
        Normal contact force per node (N); ``<= 0`` is open.
    area : float or array_like, shape (n,)
        Nodal contact area (m^2), ``> 0``.
    slip_increment : array_like, shape (n,), (n, 1) or (n, 2)
        Tangential slip increment (m).
    force_old : array_like, same shape as ``slip_increment``
        Tangential force of the last accepted increment (N).
    k_force : float or array_like, shape (n,)
        Tangential penalty stiffness (N/m), ``> 0``.
    state, parallel, zone, d_eps, sigma_y : optional
        As in :func:`traction_update`.
    out : TractionResult, optional
        As in :func:`traction_update`: filled with this function's outputs (the forces
        below) and returned.

    Returns
    -------
    TractionResult
        ``traction``: new tangential force (N); ``status``; ``dt_dslip``:
        ``d force / d slip`` (N/m); ``dt_dp``: ``d force / d f_n`` (1).
    """
    f_n = as_float_array("f_n", f_n)
    if f_n.ndim != 1:
        raise ValueError(f"f_n must be 1-D (one value per node), got shape {f_n.shape}")
    n = f_n.size
    area = as_float_array("area", area)
    if area.shape not in ((), (n,)):
        raise ValueError(f"area must be a scalar or have shape ({n},), got shape {area.shape}")
    if not (np.isfinite(area).all() and (area > 0).all()):
        raise ValueError("area must be finite and > 0")
    area = np.broadcast_to(area, (n,))
    force_old = as_float_array("force_old", force_old)
    a_old = area[:, None] if force_old.ndim == 2 else area
    with np.errstate(over="ignore"):
        p = np.minimum(f_n / area, _P_MAX)  # the largest double where it overflows
        t_old = force_old / a_old
        k_t = as_float_array("k_force", k_force) / area
    if not np.isfinite(t_old).all():
        raise ValueError("force_old / area must be finite (force_old must be finite)")
    if not np.isfinite(k_t).all():
        raise ValueError("k_force / area must be finite (k_force must be finite and > 0)")
    res = traction_update(
        law,
        p,
        slip_increment,
        t_old,
        k_t,
        state,
        parallel=parallel,
        out=out,
        zone=zone,
        d_eps=d_eps,
        sigma_y=sigma_y,
    )
    a2 = area[:, None] if res.traction.ndim == 2 else area
    a3 = area[:, None, None] if res.dt_dslip.ndim == 3 else area
    np.multiply(res.traction, a2, out=res.traction)
    np.multiply(res.dt_dslip, a3, out=res.dt_dslip)
    return res
