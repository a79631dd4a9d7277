"""Numba kernels of the runtime law (private): dispatch, array kernels, the return map.

All numba code of :mod:`frictionlaw` lives in this module and in
:mod:`frictionlaw._kernels_branches` (the scalar kernels of the law's branches, re-exported
here). Every kernel has an explicit signature, ``cache=True`` and no ``fastmath``. There is a
scalar kernel for each operation, which a host's own ``@njit`` loop can call, and array kernels
(serial and ``prange`` parallel) built on the scalar ones. The independent NumPy oracle that the
tests compare against is :mod:`frictionlaw._reference`.

Law codes:

====  ===========  =========================================
code  law          coeffs
====  ===========  =========================================
0     Coulomb      ``[mu]``
1     Tresca       ``[tau_max]`` (``m k``)
2     Coulomb+cap  ``[mu, tau_max]``
3     SBMF         the SBMF layout below
4     Eq. 25 only  as SBMF (the reload branch whatever ``p`` is)
====  ===========  =========================================

Coefficient layout of the SBMF law (one contiguous float64 array, :func:`frictionlaw.law.sbmf_coeffs`)

=====================  ==========================================================================
slots                  content
=====================  ==========================================================================
0-7 (header)           ``tau_max, H, C1, n1, C2, n2, continuous, reload form`` (0 paper, 1 tabulated)
8, 9                   ``s2, K``: the tabulated reload form's exponent and levels (``1, 0`` when
                       the paper's form runs and a first-loading block follows)
10 .. 10+5K-1          ``z[K], lnC2[K], dlnC2[K], lnn2[K], dlnn2[K]`` (:mod:`frictionlaw.reload_form`)
f0 = 10+5K             first-loading form (0 Eq. 24, 1 tabulated): absent for Eq. 24
f0+1                   ``J``, the tabulated first loading's levels
f0+2 .. f0+2+3J-1      ``u[J] = ln(p_j / H)``, ``v[J] = ln alpha_j``, ``d[J] = dv/du`` at the knots
                       (:mod:`frictionlaw.first_loading`)
=====================  ==========================================================================

An 8-slot array is Eq. 24 with the paper's Eq. 25; ``10 + 5 K`` slots Eq. 24 with the tabulated
reload form; a first-loading block makes ``12 + 5 K + 3 J``. Every knot is dimensionless (``z``,
``u``, ``v``), so no unit system changes the blocks. The reload branch is scaled by
``alpha1(p_hist)`` of the first-loading form that runs (:func:`ln_alpha1`).
"""

import math

import numba as nb
from numba import float64, int8, int64, types

from ._codes import (
    CODE_CAP,
    CODE_COULOMB,
    CODE_SBMF_RELOAD,
    CODE_TRESCA,
    FORM_TABULATED,
    STATUS_OPEN,
    STATUS_SLIP,
    STATUS_STICK,
)
from ._kernels_branches import (
    _RO,
    _RO2,
    _opts,
    first_offset,
    first_table_log,
    ln_alpha1,
    log_product,
    log_ratio,
    reload_paper_log,
    reload_table_at,
    sbmf_first_scalar,
    sbmf_first_table_scalar,
    sbmf_reload_scalar,
    sbmf_reload_table_scalar,
    smooth_min_log,
    smooth_min_log_slope,
    smooth_min_scalar,
)

__all__ = [
    "first_offset",
    "first_table_log",
    "ln_alpha1",
    "log_product",
    "log_ratio",
    "reload_paper_log",
    "reload_table_at",
    "sbmf_first_scalar",
    "sbmf_first_table_scalar",
    "sbmf_reload_scalar",
    "sbmf_reload_table_scalar",
    "smooth_min_log",
    "smooth_min_log_slope",
    "smooth_min_scalar",
    "sbmf_shear_scalar",
    "first_scalar",
    "shear_scalar",
    "shear_array",
    "shear_array_parallel",
    "traction_row",
    "return_map_row",
    "traction_scalar",
    "traction_array",
    "traction_array_parallel",
]


@nb.jit(
    types.UniTuple(float64, 2)(
        float64, float64, float64, float64, float64, float64, float64, float64, float64
    ),
    **_opts,
)
def sbmf_shear_scalar(p, p_hist, tau_max, H, C1, n1, C2, n2, continuous):
    """Shear limit of the SBMF law: Eq. 25 while ``p < p_hist``, else Eq. 24."""
    if p < p_hist:
        return sbmf_reload_scalar(p, p_hist, tau_max, H, C1, n1, C2, n2, continuous)
    return sbmf_first_scalar(p, tau_max, H, C1, n1)


@nb.jit(types.UniTuple(float64, 2)(_RO, float64), **_opts)
def first_scalar(coeffs, p):
    """First loading ``(tau, dtau/dp)`` of the form ``coeffs`` carries: Eq. 24 or the table."""
    f0 = first_offset(coeffs)
    if f0 < 0:
        return sbmf_first_scalar(p, coeffs[0], coeffs[1], coeffs[2], coeffs[3])
    return sbmf_first_table_scalar(p, coeffs, f0)


@nb.jit(
    [
        types.UniTuple(float64, 2)(int64, float64[::1], float64, float64),
        types.UniTuple(float64, 2)(int64, _RO, float64, float64),
    ],
    **_opts,
)
def shear_scalar(code, coeffs, p, p_hist):
    """Shear limit ``(tau, dtau/dp)`` of law ``code`` (see the module table)."""
    if not p > 0.0:
        return 0.0, 0.0
    if code == CODE_COULOMB:
        return (coeffs[0] * p if coeffs[0] > 0.0 else 0.0), coeffs[0]
    if code == CODE_TRESCA:
        return coeffs[0], 0.0
    if code == CODE_CAP:
        t = coeffs[0] * p if coeffs[0] > 0.0 else 0.0
        if t < coeffs[1]:
            return t, coeffs[0]
        return coeffs[1], 0.0
    if coeffs.shape[0] > 9 and coeffs[7] == FORM_TABULATED:
        if code == CODE_SBMF_RELOAD or p < p_hist:
            return sbmf_reload_table_scalar(p, p_hist, coeffs)
        return first_scalar(coeffs, p)
    f0 = first_offset(coeffs)
    if f0 >= 0:  # the paper's Eq. 25 on the tabulated first loading
        if code == CODE_SBMF_RELOAD or p < p_hist:
            if not p_hist > 0.0:
                return 0.0, 0.0
            lna1h = first_table_log(coeffs, f0, log_ratio(p_hist, coeffs[1]))[0]
            return reload_paper_log(
                p, p_hist, lna1h, coeffs[0], coeffs[1], coeffs[4], coeffs[5], coeffs[6]
            )
        return sbmf_first_table_scalar(p, coeffs, f0)
    if code == CODE_SBMF_RELOAD:
        return sbmf_reload_scalar(
            p, p_hist, coeffs[0], coeffs[1], coeffs[2], coeffs[3], coeffs[4], coeffs[5], coeffs[6]
        )
    return sbmf_shear_scalar(
        p, p_hist, coeffs[0], coeffs[1], coeffs[2], coeffs[3], coeffs[4], coeffs[5], coeffs[6]
    )


_shear_array_sig = types.void(int64, _RO, _RO, _RO, float64[::1], float64[::1])


# Serial and parallel array kernels are separate functions: numba's on-disk cache is keyed by
# the Python function, so one function jitted twice would share (and swap) cache entries.
@nb.jit(_shear_array_sig, **_opts)
def shear_array(code, coeffs, p, p_hist, tau, dtau):
    """``tau[i], dtau[i] = shear_scalar(code, coeffs, p[i], p_hist[i])``, serial."""
    for i in range(p.shape[0]):
        tau[i], dtau[i] = shear_scalar(code, coeffs, p[i], p_hist[i])


@nb.jit(_shear_array_sig, parallel=True, **_opts)
def shear_array_parallel(code, coeffs, p, p_hist, tau, dtau):
    """As :func:`shear_array`, threads over the nodes."""
    for i in nb.prange(p.shape[0]):
        tau[i], dtau[i] = shear_scalar(code, coeffs, p[i], p_hist[i])


def _traction_row_sig(coeffs_type):
    return int64(
        int64,
        coeffs_type,
        float64,
        float64,
        _RO2,
        _RO2,
        float64,
        float64[:, ::1],
        float64[:, :, ::1],
        float64[:, ::1],
        int64,
    )


@nb.jit(
    int64(
        float64,
        float64,
        float64,
        _RO2,
        _RO2,
        float64,
        float64[:, ::1],
        float64[:, :, ::1],
        float64[:, ::1],
        int64,
    ),
    **_opts,
)
def return_map_row(tau, dtau, p, du, t_old, k_t, t_new, dt_ddu, dt_dp, i):
    """Stick/slip return map at node ``i`` with the shear limit ``tau`` and its ``dtau/dp``.

    Trial ``t_tr = t_old + k_t du``. Open (``p <= 0``): ``t = 0``, status 0.
    Stick (``|t_tr| <= tau``, ``tau > 0``): ``t = t_tr``, tangent ``dt/ddu = k_t I``, status 1.
    Slip: ``t = tau t_tr/|t_tr|``, tangent ``k_t tau/|t_tr| (I - n n)`` and
    ``dt/dp = dtau/dp n``, status 2; with ``tau = 0`` the traction and the tangent are 0.
    ``|t_tr|`` is a scaled norm (no under- or overflow of ``|t|^2``); a trial that overflows
    a double is formed as ``t_tr / s`` with ``s = max(k_t, |t_old|)`` (it slips).
    Rows are indexed in place (no per-node array views: they cost ~100 ns a node).
    """
    nd = du.shape[1]
    for a in range(nd):
        dt_dp[i, a] = 0.0
        for b in range(nd):
            dt_ddu[i, a, b] = 0.0
    if not p > 0.0:
        for a in range(nd):
            t_new[i, a] = 0.0
        return STATUS_OPEN
    vmax = 0.0
    for a in range(nd):
        v = t_old[i, a] + k_t * du[i, a]
        t_new[i, a] = v
        vmax = max(vmax, abs(v))
    kscale = k_t  # k_t / s: the trial held in t_new is t_tr / s
    if not vmax < math.inf:
        s = k_t
        for a in range(nd):
            s = max(s, abs(t_old[i, a]))
        kscale = k_t / s
        vmax = 0.0
        for a in range(nd):
            v = t_old[i, a] / s + kscale * du[i, a]
            t_new[i, a] = v
            vmax = max(vmax, abs(v))
    # |t_tr| = vmax r with r = |t_tr / vmax| in [1, sqrt(d)]: nothing squared under- or overflows
    r = 0.0
    if vmax > 0.0:
        for a in range(nd):
            q = t_new[i, a] / vmax
            r += q * q
        r = math.sqrt(r)
    if kscale == k_t and tau > 0.0 and vmax <= tau / r:
        for a in range(nd):
            dt_ddu[i, a, a] = k_t
        return STATUS_STICK
    if vmax == 0.0:  # tau = 0 and no trial traction: t = 0, zero tangent
        return STATUS_SLIP

    # slip: radial return onto the limit circle (|t_tr| > tau >= 0)
    f = kscale * ((tau / vmax) / r)
    for a in range(nd):
        t_new[i, a] = (t_new[i, a] / vmax) / r  # unit direction n
    for a in range(nd):
        dt_dp[i, a] = dtau * t_new[i, a]
        for b in range(nd):
            dt_ddu[i, a, b] = f * ((1.0 if a == b else 0.0) - t_new[i, a] * t_new[i, b])
    for a in range(nd):
        t_new[i, a] *= tau
    return STATUS_SLIP


@nb.jit([_traction_row_sig(float64[::1]), _traction_row_sig(_RO)], **_opts)
def traction_row(code, coeffs, p, p_hist, du, t_old, k_t, t_new, dt_ddu, dt_dp, i):
    """Stick/slip return map at node ``i`` (row ``i`` of the 2-D arrays); returns the status.

    The shear limit ``(tau, dtau/dp)`` of law ``code`` at ``p`` after the committed history
    ``p_hist`` (:func:`shear_scalar`; 0 for ``p <= 0``), then :func:`return_map_row`.
    """
    tau, dtau = shear_scalar(code, coeffs, p, p_hist)
    return return_map_row(tau, dtau, p, du, t_old, k_t, t_new, dt_ddu, dt_dp, i)


@nb.jit(
    int64(
        int64,
        _RO,
        float64,
        float64,
        _RO,
        _RO,
        float64,
        float64[::1],
        float64[:, ::1],
        float64[::1],
    ),
    **_opts,
)
def traction_scalar(code, coeffs, p, p_hist, du, t_old, k_t, t_new, dt_ddu, dt_dp):
    """:func:`traction_row` for one node given as 1-D arrays (``du``, ``t_old``, ``t_new``: (d,))."""
    nd = du.shape[0]
    return traction_row(
        code,
        coeffs,
        p,
        p_hist,
        du.reshape((1, nd)),
        t_old.reshape((1, nd)),
        k_t,
        t_new.reshape((1, nd)),
        dt_ddu.reshape((1, nd, nd)),
        dt_dp.reshape((1, nd)),
        0,
    )


_traction_array_sig = types.void(
    int64,
    _RO,
    _RO,
    _RO,
    _RO2,
    _RO2,
    _RO,
    float64[:, ::1],
    int8[::1],
    float64[:, :, ::1],
    float64[:, ::1],
    float64[::1],
)


@nb.jit(_traction_array_sig, **_opts)
def traction_array(code, coeffs, p, p_hist, du, t_old, k_t, t_new, status, dt_ddu, dt_dp, p_trial):
    """:func:`traction_row` at every node, and the trial history ``max(p_hist, p)``, serial."""
    for i in range(p.shape[0]):
        status[i] = traction_row(
            code, coeffs, p[i], p_hist[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i
        )
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]


@nb.jit(_traction_array_sig, parallel=True, **_opts)
def traction_array_parallel(
    code, coeffs, p, p_hist, du, t_old, k_t, t_new, status, dt_ddu, dt_dp, p_trial
):
    """As :func:`traction_array`, threads over the nodes."""
    for i in nb.prange(p.shape[0]):
        status[i] = traction_row(
            code, coeffs, p[i], p_hist[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i
        )
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
