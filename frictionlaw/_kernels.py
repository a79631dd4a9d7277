"""Numba kernels of the runtime law (private).

All numba code of :mod:`frictionlaw` lives here. Every kernel has an explicit
signature, ``cache=True`` and no ``fastmath``. There is a scalar kernel for each
operation, which a host's own ``@njit`` loop can call, and array kernels (serial
and ``prange`` parallel) built on the scalar ones. The independent NumPy oracle
that the tests compare against is :mod:`frictionlaw._reference`.

Law codes and coefficient layout (``coeffs`` is a float64 array of length 8):

====  ===========  =====================================================
code  law          coeffs
====  ===========  =====================================================
0     Coulomb      ``[mu]``
1     Tresca       ``[tau_max]`` (``m k``)
2     Coulomb+cap  ``[mu, tau_max]``
3     SBMF         ``[tau_max, H, C1, n1, C2, n2, continuous, 0]``
4     Eq. 25 only  as SBMF
====  ===========  =====================================================
"""

import math

import numba as nb
from numba import float64, int8, int64, types

from ._codes import (
    CODE_CAP,
    CODE_COULOMB,
    CODE_SBMF_RELOAD,
    CODE_TRESCA,
    STATUS_OPEN,
    STATUS_SLIP,
    STATUS_STICK,
)

_Y_SATURATED = 350.0  # tanh(y) == 1 and 2y/sinh(2y) < 1e-300 beyond

_opts = dict(nopython=True, cache=True, nogil=True, error_model="numpy")


@nb.jit(types.UniTuple(float64, 3)(float64, float64), **_opts)
def smooth_min_scalar(x, n):
    """Smooth minimum ``g(x) = tanh(x**n) ** (1/n)`` of ``x`` and 1 (Eqs. 24-25).

    Returns ``(g, g / x, dg/dx)``. With ``y = x**n``: for ``y < 1`` it is
    evaluated as ``g = x (tanh(y)/y) ** (1/n)`` so that the small-``x`` limit
    ``g -> x`` survives any ``n`` (``y`` may underflow to 0), and as
    ``exp(ln tanh(y) / n)`` above; ``tanh`` and ``dg/dx = (g/x) 2y/sinh(2y)``
    both come from one ``expm1(-2y)``. ``x <= 0`` gives ``(0, 1, 1)``, the right limits.
    """
    if not x > 0.0:
        return 0.0, 1.0, 1.0
    y = x**n
    if y < 1e-4:
        # ln(tanh(y)/y) = -y^2/3 + 7 y^4/90 + O(y^6); z/sinh(z) = 1 - z^2/6 + O(z^4), z = 2y
        y2 = y * y
        gox = math.exp((-y2 / 3.0 + 7.0 * y2 * y2 / 90.0) / n)
        return x * gox, gox, gox * (1.0 - 2.0 * y2 / 3.0)
    if y > _Y_SATURATED:
        return 1.0, 1.0 / x, 0.0
    em = math.expm1(-2.0 * y)  # e - 1 with e = exp(-2y), accurate for small y
    two_e = 2.0 + em  # 1 + e
    t = -em / two_e  # tanh(y)
    s = 4.0 * y * (1.0 + em) / (-em * two_e)  # 2y / sinh(2y)
    if y < 1.0:
        gox = math.exp(math.log(t / y) / n)
        g = x * gox
    else:
        g = math.exp(math.log1p(-2.0 * (1.0 + em) / two_e) / n)
        gox = g / x
    return g, gox, gox * s


@nb.jit(types.UniTuple(float64, 2)(float64, float64, float64, float64, float64), **_opts)
def sbmf_first_scalar(p, tau_max, H, C1, n1):
    """Eq. 24: ``(tau, dtau/dp)`` with ``tau = tau_max g(p C1 / H; n1)``; 0 for ``p <= 0``."""
    if not p > 0.0:
        return 0.0, 0.0
    x1 = p * C1 / H
    g, gox, dg = smooth_min_scalar(x1, n1)
    if x1 < 1.0:
        tau = p * (tau_max * C1 / H) * gox  # full precision for tiny p
    else:
        tau = tau_max * g
    return min(tau, tau_max), tau_max * C1 / H * dg


@nb.jit(
    types.UniTuple(float64, 2)(
        float64, float64, float64, float64, float64, float64, float64, float64, float64
    ),
    **_opts,
)
def sbmf_reload_scalar(p, p_hist, tau_max, H, C1, n1, C2, n2, continuous):
    """Eq. 25: ``(tau, dtau/dp)`` on the un-/reload branch below ``p_hist``.

    ``tau = tau_max a1h g(x2; n2)`` with ``a1h = alpha1(p_hist)`` and
    ``x2 = p C2 / (H a1h)``; divided by ``g(x2(p_hist); n2)`` when
    ``continuous != 0`` so that it meets Eq. 24 at ``p_hist``. ``x2`` is formed
    from the ratio ``p / p_hist`` so that ``a1h -> 0`` cannot overflow;
    the limit there is ``tau -> 0``.
    """
    if not p > 0.0:
        return 0.0, 0.0
    x1h = p_hist * C1 / H
    a1h, gox1h, _ = smooth_min_scalar(x1h, n1)
    if x1h < 1.0:
        x2 = (p / p_hist) * (C2 / C1) / gox1h
        x2h = (C2 / C1) / gox1h
    else:
        x2 = (p * C2 / H) / a1h
        x2h = (p_hist * C2 / H) / a1h
    g2, gox2, dg2 = smooth_min_scalar(x2, n2)
    scale = 1.0
    if continuous != 0.0:
        g2h, _, _ = smooth_min_scalar(x2h, n2)
        scale = 1.0 / g2h
    if x2 < 1.0:
        tau = p * (tau_max * C2 / H) * gox2 * scale  # alpha1(p_hist) cancels
    else:
        tau = tau_max * a1h * g2 * scale
    return min(tau, tau_max * a1h * scale), tau_max * C2 / H * dg2 * scale


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


# Inputs are typed read-only: numba converts a writable array to these safely, so read-only
# arrays (a HistoryState's p_hist view, a host's frozen coeffs) are accepted as well.
_RO = types.Array(float64, 1, "C", readonly=True)
_RO2 = types.Array(float64, 2, "C", readonly=True)


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
        return coeffs[0] * p, coeffs[0]
    if code == CODE_TRESCA:
        return coeffs[0], 0.0
    if code == CODE_CAP:
        t = coeffs[0] * p
        if t < coeffs[1]:
            return t, coeffs[0]
        return coeffs[1], 0.0
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


@nb.jit([_traction_row_sig(float64[::1]), _traction_row_sig(_RO)], **_opts)
def traction_row(code, coeffs, p, p_hist, du, t_old, k_t, t_new, dt_ddu, dt_dp, i):
    """Stick/slip return map at node ``i`` (row ``i`` of the 2-D arrays); returns the status.

    Trial ``t_tr = t_old + k_t du``. Open (``p <= 0``): ``t = 0``, status 0.
    Stick (``|t_tr| <= tau``): ``t = t_tr``, tangent ``dt/ddu = k_t I``, status 1.
    Slip: ``t = tau t_tr/|t_tr|``, tangent ``k_t tau/|t_tr| (I - n n)`` and
    ``dt/dp = dtau/dp n``, status 2. ``p_hist`` is the committed history.
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
    tau, dtau = shear_scalar(code, coeffs, p, p_hist)
    norm2 = 0.0
    for a in range(nd):
        v = t_old[i, a] + k_t * du[i, a]
        t_new[i, a] = v
        norm2 += v * v
    norm = math.sqrt(norm2)
    if norm <= tau:
        for a in range(nd):
            dt_ddu[i, a, a] = k_t
        return STATUS_STICK
    # slip: radial return onto the limit circle (norm > tau >= 0, so norm > 0)
    f = k_t * tau / norm
    for a in range(nd):
        t_new[i, a] /= norm  # unit direction n
    for a in range(nd):
        dt_dp[i, a] = dtau * t_new[i, a]
        for b in range(nd):
            dt_ddu[i, a, b] = f * ((1.0 if a == b else 0.0) - t_new[i, a] * t_new[i, b])
    for a in range(nd):
        t_new[i, a] *= tau
    return STATUS_SLIP


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
