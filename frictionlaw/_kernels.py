"""Numba kernels of the runtime law (private).

All numba code of :mod:`frictionlaw` lives here. Every kernel has an explicit
signature, ``cache=True`` and no ``fastmath``. There is a scalar kernel for each
operation, which a host's own ``@njit`` loop can call, and array kernels (serial
and ``prange`` parallel) built on the scalar ones. The independent NumPy oracle
that the tests compare against is :mod:`frictionlaw._reference`.

Law codes and coefficient layout (``coeffs`` is one contiguous float64 array, of length 8
but for the tabulated reload form):

====  ===========  =====================================================
code  law          coeffs
====  ===========  =====================================================
0     Coulomb      ``[mu]``
1     Tresca       ``[tau_max]`` (``m k``)
2     Coulomb+cap  ``[mu, tau_max]``
3     SBMF         ``[tau_max, H, C1, n1, C2, n2, continuous, form]``, and with
                   ``form = 1`` (tabulated reload, :mod:`frictionlaw.reload_form`)
                   ``s2, K, z[K], lnC2[K], dlnC2[K], lnn2[K], dlnn2[K]``
4     Eq. 25 only  as SBMF
====  ===========  =====================================================

``form = 0`` (or an 8-slot array) is the paper's Eq. 25 with ``C2, n2``.
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
    Q_START,
    STATUS_OPEN,
    STATUS_SLIP,
    STATUS_STICK,
)

_Y_SATURATED = 350.0  # tanh(y) == 1 and 2y/sinh(2y) < 1e-300 beyond

_opts = dict(nopython=True, cache=True, nogil=True, error_model="numpy")


_LN_Y_SMALL = math.log(1e-4)  # series of ln(tanh(y)/y) below
_LN_Y_SATURATED = math.log(_Y_SATURATED)


@nb.jit(types.UniTuple(float64, 4)(float64, float64), **_opts)
def smooth_min_log(lnx, n):
    """Smooth minimum ``g(x) = tanh(x**n) ** (1/n)`` of ``x`` and 1 from ``ln x`` (Eqs. 24-25).

    Returns ``(g, g / x, dg/dx, ln g)``. Working from ``ln x`` means that no ``x`` that
    under- or overflows a double (a subnormal pressure times ``C/H``, or ``p_hist`` huge) is
    ever formed: ``y = x**n = exp(n ln x)``. For ``y < 1`` it is evaluated as
    ``g = x (tanh(y)/y) ** (1/n)`` so that the small-``x`` limit ``g -> x`` survives any ``n``
    (``y`` may underflow to 0), and as ``exp(ln tanh(y) / n)`` above; ``tanh`` and
    ``dg/dx = (g/x) 2y/sinh(2y)`` both come from one ``expm1(-2y)``.
    ``ln x = +inf`` gives ``(1, 0, 0, 0)``.
    """
    lny = n * lnx
    if lny < _LN_Y_SMALL:
        # ln(tanh(y)/y) = -y^2/3 + 7 y^4/90 + O(y^6); z/sinh(z) = 1 - z^2/6 + O(z^4), z = 2y
        y = math.exp(lny)
        y2 = y * y
        lngox = (-y2 / 3.0 + 7.0 * y2 * y2 / 90.0) / n
        gox = math.exp(lngox)
        return math.exp(lnx) * gox, gox, gox * (1.0 - 2.0 * y2 / 3.0), lnx + lngox
    if lny > _LN_Y_SATURATED:
        return 1.0, math.exp(-lnx), 0.0, 0.0
    y = math.exp(lny)
    em = math.expm1(-2.0 * y)  # e - 1 with e = exp(-2y), accurate for small y
    two_e = 2.0 + em  # 1 + e
    t = -em / two_e  # tanh(y)
    s = 4.0 * y * (1.0 + em) / (-em * two_e)  # 2y / sinh(2y)
    if y < 1.0:
        lngox = math.log(t / y) / n
        gox = math.exp(lngox)
        return math.exp(lnx) * gox, gox, gox * s, lnx + lngox
    lng = math.log1p(-2.0 * (1.0 + em) / two_e) / n
    gox = math.exp(lng - lnx)
    return math.exp(lng), gox, gox * s, lng


@nb.jit(types.UniTuple(float64, 2)(float64, float64), **_opts)
def smooth_min_log_slope(lnx, n):
    """``(ln g, d ln g / d ln x)`` of the smooth minimum ``g = tanh(x**n) ** (1/n)`` from ``ln x``.

    ``ln g`` by the statements of :func:`smooth_min_log` (bitwise its fourth value), and the
    logarithmic slope ``x g'/g = 2y/sinh(2y)`` (``y = x**n``): the factor that
    :func:`smooth_min_log` multiplies ``g/x`` by to give ``dg/dx``, ``1 - 2y^2/3`` on its series
    branch and 0 in saturation. Neither ``g`` nor ``g/x`` is formed (one or two ``exp`` less):
    for a caller that needs ``ln g`` and ``dg/dx`` only through ``g' = (g/x) x g'/g``.
    """
    lny = n * lnx
    if lny < _LN_Y_SMALL:
        y = math.exp(lny)
        y2 = y * y
        return lnx + (-y2 / 3.0 + 7.0 * y2 * y2 / 90.0) / n, 1.0 - 2.0 * y2 / 3.0
    if lny > _LN_Y_SATURATED:
        return 0.0, 0.0
    y = math.exp(lny)
    em = math.expm1(-2.0 * y)
    two_e = 2.0 + em
    s = 4.0 * y * (1.0 + em) / (-em * two_e)
    if y < 1.0:
        return lnx + math.log((-em / two_e) / y) / n, s
    return math.log1p(-2.0 * (1.0 + em) / two_e) / n, s


@nb.jit(float64(float64, float64), **_opts)
def log_product(p, c):
    """``ln(p c)`` for ``p, c > 0`` without forming an under- or overflowing product."""
    x = p * c
    if 1e-300 < x < 1e300:
        return math.log(x)
    return math.log(p) + math.log(c)


@nb.jit(types.UniTuple(float64, 3)(float64, float64), **_opts)
def smooth_min_scalar(x, n):
    """:func:`smooth_min_log` from ``x``: ``(g, g / x, dg/dx)``; ``x <= 0`` gives ``(0, 1, 1)``."""
    if not x > 0.0:
        return 0.0, 1.0, 1.0
    g, gox, dg, _ = smooth_min_log(math.log(x), n)
    return g, gox, dg


@nb.jit(types.UniTuple(float64, 2)(float64, float64, float64, float64, float64), **_opts)
def sbmf_first_scalar(p, tau_max, H, C1, n1):
    """Eq. 24: ``(tau, dtau/dp)`` with ``tau = tau_max g(p C1 / H; n1)``; 0 for ``p <= 0``."""
    if not p > 0.0:
        return 0.0, 0.0
    c1 = C1 / H
    lnx1 = log_product(p, c1)
    g, gox, dg, _ = smooth_min_log(lnx1, n1)
    if lnx1 < 0.0:
        tau = p * (tau_max * c1) * gox  # full precision for tiny p
    else:
        tau = tau_max * g
    return min(tau, tau_max), tau_max * c1 * dg


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
    in logs, so that ``a1h -> 0`` cannot overflow; the limit there is ``tau -> 0``.
    Bounded by ``tau_max a1h`` (``p <= p_hist``) and by ``tau_max`` (``p > p_hist``, where
    the continuous variant, extrapolated, would exceed a contact ratio of 1).
    """
    if not (p > 0.0 and p_hist > 0.0):
        return 0.0, 0.0
    c2 = C2 / H
    _, _, _, lna1h = smooth_min_log(log_product(p_hist, C1 / H), n1)
    lnx2 = log_product(p, c2) - lna1h
    g2, gox2, dg2, lng2 = smooth_min_log(lnx2, n2)
    lng2h = 0.0
    if continuous != 0.0:
        _, _, _, lng2h = smooth_min_log(log_product(p_hist, c2) - lna1h, n2)
    scale = math.exp(-lng2h)
    if continuous != 0.0:  # in logs: g2 and g2h may both be below the smallest double
        tau = tau_max * math.exp(lna1h + lng2 - lng2h)
    elif lnx2 < 0.0:
        tau = p * (tau_max * c2) * gox2  # alpha1(p_hist) cancels
    else:
        tau = tau_max * math.exp(lna1h) * g2
    dtau = tau_max * c2 * dg2 * scale
    cap = tau_max * math.exp(lna1h) if p <= p_hist else tau_max
    if tau >= cap:
        return cap, (0.0 if p > p_hist else dtau)
    return tau, dtau


# Inputs are typed read-only: numba converts a writable array to these safely, so read-only
# arrays (a HistoryState's p_hist view, a host's frozen coeffs) are accepted as well.
_RO = types.Array(float64, 1, "C", readonly=True)
_RO2 = types.Array(float64, 2, "C", readonly=True)

_TAB = 10  # coeffs index of z[0] in the tabulated reload form
_LN_Q_START = math.log(Q_START)  # below it the tabulated branch's x2 starts quadratically
_LN_D_MAX = 700.0  # bound on ln(dtau/dp / (tau_max s2 x g'/g)) where it is formed in logs
_D_MAX = 1.7976931348623157e308  # the largest double: dtau/dp is held below it


@nb.jit(types.UniTuple(float64, 2)(_RO, float64), **_opts)
def reload_table_at(coeffs, x):
    """``(ln C2, ln n2)`` of the tabulated reload form at ``x = p_hist / H``.

    The monotone cubic Hermite interpolant over ``z = -ln(1 - x)`` whose knots and slopes
    ``coeffs`` carries (:func:`frictionlaw.reload_form.pchip_slopes`); the first level's values
    up to it, the last level's from it on (``x >= 1`` included). ``z`` is ``-log1p(-x)`` formed
    from ``log`` (Kahan's ``log(u) x / (u - 1)``, ``u = 1 - x`` rounded: within a few ulps of
    ``log1p``, whose libm version costs about three ``log`` here).
    """
    k = int(coeffs[9])
    zk = _TAB
    c0 = _TAB + k
    n0 = _TAB + 3 * k
    if k == 1 or not x < 1.0:
        j = 0 if k == 1 else k - 1
        return coeffs[c0 + j], coeffs[n0 + j]
    u = 1.0 - x
    z = x if u == 1.0 else -math.log(u) * (x / (1.0 - u))
    if not z > coeffs[zk]:
        return coeffs[c0], coeffs[n0]
    if not z < coeffs[zk + k - 1]:
        return coeffs[c0 + k - 1], coeffs[n0 + k - 1]
    j = 0
    while j < k - 2 and z >= coeffs[zk + j + 1]:
        j += 1
    h = coeffs[zk + j + 1] - coeffs[zk + j]
    t = (z - coeffs[zk + j]) / h
    u = 1.0 - t
    h00 = (1.0 + 2.0 * t) * u * u
    h10 = t * u * u * h
    h01 = t * t * (3.0 - 2.0 * t)
    h11 = t * t * (t - 1.0) * h
    lnc = (
        h00 * coeffs[c0 + j]
        + h10 * coeffs[c0 + k + j]
        + h01 * coeffs[c0 + j + 1]
        + h11 * coeffs[c0 + k + j + 1]
    )
    lnn = (
        h00 * coeffs[n0 + j]
        + h10 * coeffs[n0 + k + j]
        + h01 * coeffs[n0 + j + 1]
        + h11 * coeffs[n0 + k + j + 1]
    )
    return lnc, lnn


@nb.jit(types.UniTuple(float64, 2)(float64, float64, _RO), **_opts)
def sbmf_reload_table_scalar(p, p_hist, coeffs):
    """Eq. 25, tabulated over ``p_hist``: ``(tau, dtau/dp)`` on the un-/reload branch.

    ``tau = tau_max a1h g(x2; n2)`` with ``a1h = alpha1(p_hist)``, ``(C2, n2)`` of the table at
    ``p_hist`` (:func:`reload_table_at`), ``x2h = p_hist C2 / (H a1h)`` and
    ``x2 = x2h (p / p_hist) ** s2`` (below ``p / p_hist = q0 = Q_START`` the C1 quadratic start
    ``x2h q0**s2 (a t + b t**2)``, ``t = q / q0``, ``a = 2 - s2``, ``b = s2 - 1``, so that
    ``d tau / dp`` stays finite at ``p -> 0``); divided by ``g(x2h; n2)`` when ``continuous != 0``
    so that it meets Eq. 24 at ``p_hist``. All in logs, as :func:`sbmf_reload_scalar`:
    ``ln x2h = ln(p_hist / H) + ln C2 - ln a1h`` and ``ln(p / p_hist)``, each one ``log`` of the
    quotient where it is a normal double (else of its terms); ``tau = tau_max exp(ln a1h +
    ln g2 [- ln g2h])``.
    ``dtau/dp = tau m (x2 g'/g)(x2) / p`` with ``m = d ln x2 / d ln p`` (``s2``, below ``q0``
    ``1 + b t / (a + b t)``) and the logarithmic slope of :func:`smooth_min_log_slope`; held
    below the largest double; where ``tau s2 x2 g'/g`` is below 1e-290 (``tau`` subnormal or 0:
    ``p_hist`` below about 1e-290 Pa) it is formed in logs instead, its logarithm held below 700.
    Bounded by ``tau_max a1h`` (``p <= p_hist``; the comparison made in logs, so that the bound
    is formed only where it applies) and by ``tau_max`` (``p > p_hist``).
    """
    if not (p > 0.0 and p_hist > 0.0):
        return 0.0, 0.0
    tau_max = coeffs[0]
    H = coeffs[1]
    _, _, _, lna1h = smooth_min_log(log_product(p_hist, coeffs[2] / H), coeffs[3])
    x = p_hist / H
    lnc2, lnn2 = reload_table_at(coeffs, x)
    n2 = math.exp(lnn2)
    s2 = coeffs[8]
    if 1e-300 < x < 1e300:
        lnx2h = math.log(x) + lnc2 - lna1h
    else:
        lnx2h = math.log(p_hist) - math.log(H) + lnc2 - lna1h
    q = p / p_hist
    if 1e-300 < q < 1e300:
        lnq = math.log(q)
    else:
        lnq = math.log(p) - math.log(p_hist)
    slope = s2  # d ln x2 / d ln p
    if lnq < _LN_Q_START:
        # below q0 = p / p_hist of 0.01: the C1 quadratic start q0**s2 (a t + b t**2),
        # t = q / q0, a = 2 - s2, b = s2 - 1 (finite d tau/dp at p -> 0; q**s2 itself for s2 = 1, 2)
        t = math.exp(lnq - _LN_Q_START)
        u = (2.0 - s2) + (s2 - 1.0) * t
        lnx2 = lnx2h + s2 * _LN_Q_START + (lnq - _LN_Q_START) + math.log(u)
        slope = 1.0 + (s2 - 1.0) * t / u
    else:
        lnx2 = lnx2h + s2 * lnq
    lng2, sl2 = smooth_min_log_slope(lnx2, n2)
    lng2h = 0.0
    if coeffs[6] != 0.0:
        _, _, _, lng2h = smooth_min_log(lnx2h, n2)
    lnt = lna1h + lng2 - lng2h
    tau = tau_max * math.exp(lnt)
    if p > p_hist and tau >= tau_max:
        return tau_max, 0.0
    d = tau * (slope * sl2)
    if d > 1e-290:
        dtau = min(d / p, _D_MAX)
    elif sl2 > 0.0:
        dtau = min(tau_max * slope * sl2 * math.exp(min(lnt - math.log(p), _LN_D_MAX)), _D_MAX)
    else:
        dtau = 0.0
    if p <= p_hist and lnt >= lna1h:  # tau >= tau_max a1h (exp is monotone)
        return tau_max * math.exp(lna1h), dtau
    return tau, dtau


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
        return sbmf_first_scalar(p, coeffs[0], coeffs[1], coeffs[2], coeffs[3])
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
    Stick (``|t_tr| <= tau``, ``tau > 0``): ``t = t_tr``, tangent ``dt/ddu = k_t I``, status 1.
    Slip: ``t = tau t_tr/|t_tr|``, tangent ``k_t tau/|t_tr| (I - n n)`` and
    ``dt/dp = dtau/dp n``, status 2; with ``tau = 0`` the traction and the tangent are 0.
    ``|t_tr|`` is a scaled norm (no under- or overflow of ``|t|^2``); a trial that overflows
    a double is formed as ``t_tr / s`` with ``s = max(k_t, |t_old|)`` (it slips).
    ``p_hist`` is the committed history.
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
