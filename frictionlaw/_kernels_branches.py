"""Numba kernels of the law's branches (private): smooth minimum, Eqs. 24-25, their tables.

The scalar kernels of each branch, which :mod:`frictionlaw._kernels` dispatches to by the
coefficient layout (documented there) and a host's own ``@njit`` loop may call. Every kernel has
an explicit signature, ``cache=True`` and no ``fastmath``; the NumPy oracle the tests compare
against is :mod:`frictionlaw._reference`.
"""

import math

import numba as nb
from numba import float64, int64, types

from ._codes import FIRST_TABULATED, Q_START, TABLE_START

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
        float64, float64, float64, float64, float64, float64, float64, float64
    ),
    **_opts,
)
def reload_paper_log(p, p_hist, lna1h, tau_max, H, C2, n2, continuous):
    """Eq. 25 given ``ln a1h = ln alpha1(p_hist)`` of the first-loading form that runs.

    The body of :func:`sbmf_reload_scalar` (``p > 0``, ``p_hist > 0``).
    """
    c2 = C2 / H
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


@nb.jit(
    types.UniTuple(float64, 2)(
        float64, float64, float64, float64, float64, float64, float64, float64, float64
    ),
    **_opts,
)
def sbmf_reload_scalar(p, p_hist, tau_max, H, C1, n1, C2, n2, continuous):
    """Eq. 25: ``(tau, dtau/dp)`` on the un-/reload branch below ``p_hist``.

    ``tau = tau_max a1h g(x2; n2)`` with ``a1h = alpha1(p_hist)`` of Eq. 24 and
    ``x2 = p C2 / (H a1h)``; divided by ``g(x2(p_hist); n2)`` when
    ``continuous != 0`` so that it meets Eq. 24 at ``p_hist``. ``x2`` is formed
    in logs, so that ``a1h -> 0`` cannot overflow; the limit there is ``tau -> 0``.
    Bounded by ``tau_max a1h`` (``p <= p_hist``) and by ``tau_max`` (``p > p_hist``, where
    the continuous variant, extrapolated, would exceed a contact ratio of 1).
    """
    if not (p > 0.0 and p_hist > 0.0):
        return 0.0, 0.0
    _, _, _, lna1h = smooth_min_log(log_product(p_hist, C1 / H), n1)
    return reload_paper_log(p, p_hist, lna1h, tau_max, H, C2, n2, continuous)


# Inputs are typed read-only: numba converts a writable array to these safely, so read-only
# arrays (a HistoryState's p_hist view, a host's frozen coeffs) are accepted as well.
_RO = types.Array(float64, 1, "C", readonly=True)
_RO2 = types.Array(float64, 2, "C", readonly=True)

_TAB = TABLE_START  # coeffs index of z[0] in the tabulated reload form
_LNC2_MAX = math.log(1e6)  # the tabulated C2's top (frictionlaw.reload_form.LN_C2_MAX)
_LN_Q_START = math.log(Q_START)  # below it the tabulated branch's x2 starts quadratically
_LN_D_MAX = 700.0  # bound on ln(dtau/dp / (tau_max s2 x g'/g)) where it is formed in logs
_D_MAX = 1.7976931348623157e308  # the largest double: dtau/dp is held below it


@nb.jit(float64(float64, float64), **_opts)
def log_ratio(p, H):
    """``ln(p / H)`` for ``p, H > 0``, one ``log`` of the quotient where it is a normal double."""
    x = p / H
    if 1e-300 < x < 1e300:
        return math.log(x)
    return math.log(p) - math.log(H)


@nb.jit(int64(_RO), **_opts)
def first_offset(coeffs):
    """Index of the first-loading block's form code in ``coeffs``, or -1 (Eq. 24: no block).

    The block follows the reload block: at ``TABLE_START + 5 K`` with ``K = coeffs[9]`` (the
    reload table's levels, 0 with the paper's form).
    """
    n = coeffs.shape[0]
    if n <= TABLE_START:
        return -1
    f0 = TABLE_START + 5 * int(coeffs[9])
    if n > f0 + 1 and coeffs[f0] == FIRST_TABULATED:
        return f0
    return -1


@nb.jit(types.UniTuple(float64, 2)(_RO, int64, float64), **_opts)
def first_table_log(coeffs, f0, lnq):
    """``(ln alpha1, d ln alpha1 / d ln p)`` of the tabulated first loading at ``lnq = ln(p/H)``.

    The block at ``f0`` holds the form code, ``J`` and the knots ``u = ln(p_j / H)``,
    ``v = ln alpha_j`` and the slopes ``d`` (:class:`frictionlaw.first_loading.FirstLoadingTable`).
    Below ``u_0`` the Coulomb line ``v_0 + (lnq - u_0)`` (slope 1); between the knots the cubic
    Hermite interpolant; above ``u_{J-1}`` the power law ``v_{J-1} + d_{J-1} (lnq - u_{J-1})``,
    capped at ``ln alpha = 0`` (slope 0 there). ``lnq = +inf`` gives ``(0, 0)``.
    """
    nj = int(coeffs[f0 + 1])
    u = f0 + 2
    v = u + nj
    d = v + nj
    if not lnq > coeffs[u]:
        return coeffs[v] + (lnq - coeffs[u]), 1.0
    top = coeffs[u + nj - 1]
    if not lnq < top:
        s = coeffs[d + nj - 1]
        if s == 0.0:
            return min(coeffs[v + nj - 1], 0.0), 0.0
        lna = coeffs[v + nj - 1] + s * (lnq - top)
        if not lna < 0.0:
            return 0.0, 0.0
        return lna, s
    j = 0
    while j < nj - 2 and lnq >= coeffs[u + j + 1]:
        j += 1
    h = coeffs[u + j + 1] - coeffs[u + j]
    t = (lnq - coeffs[u + j]) / h
    w = 1.0 - t
    y0 = coeffs[v + j]
    y1 = coeffs[v + j + 1]
    d0 = coeffs[d + j]
    d1 = coeffs[d + j + 1]
    lna = (1.0 + 2.0 * t) * w * w * y0 + t * w * w * h * d0 + t * t * (3.0 - 2.0 * t) * y1
    lna += t * t * (t - 1.0) * h * d1
    # d/dlnq: dh00/dt = 6t(t - 1) = -dh01/dt, dh10/dt = w(1 - 3t), dh11/dt = t(3t - 2)
    slope = (
        6.0 * t * (t - 1.0) * (y0 - y1) / h + w * (1.0 - 3.0 * t) * d0 + t * (3.0 * t - 2.0) * d1
    )
    return min(lna, 0.0), slope


@nb.jit(types.UniTuple(float64, 2)(float64, _RO, int64), **_opts)
def sbmf_first_table_scalar(p, coeffs, f0):
    """The tabulated first loading: ``(tau, dtau/dp)`` with ``tau = tau_max alpha1(p)``.

    Below the lowest level ``tau = mu p``, ``mu = tau_max alpha_0 / p_0 = tau_max exp(v_0 -
    u_0) / H`` (exact for every tiny ``p``); above it ``tau = tau_max exp(ln alpha1)`` and
    ``dtau/dp = tau (d ln alpha1 / d ln p) / p``. 0 for ``p <= 0``.
    """
    if not p > 0.0:
        return 0.0, 0.0
    tau_max = coeffs[0]
    H = coeffs[1]
    nj = int(coeffs[f0 + 1])
    u0 = coeffs[f0 + 2]
    lnq = log_ratio(p, H)
    if not lnq > u0:
        mu = tau_max * math.exp(coeffs[f0 + 2 + nj] - u0) / H
        return p * mu, mu
    lna, s = first_table_log(coeffs, f0, lnq)
    tau = tau_max * math.exp(lna)
    if s == 0.0:
        return tau, 0.0
    return tau, min(tau * s / p, _D_MAX)


@nb.jit(float64(_RO, float64), **_opts)
def ln_alpha1(coeffs, p_hist):
    """``ln alpha1(p_hist)`` (``p_hist > 0``) of the first-loading form that runs.

    Eq. 24 by the statements of :func:`smooth_min_log` (bitwise its fourth value, through
    :func:`smooth_min_log_slope`), or the tabulated form (:func:`first_table_log`).
    """
    f0 = first_offset(coeffs)
    H = coeffs[1]
    if f0 < 0:
        return smooth_min_log_slope(log_product(p_hist, coeffs[2] / H), coeffs[3])[0]
    return first_table_log(coeffs, f0, log_ratio(p_hist, H))[0]


@nb.jit(types.UniTuple(float64, 2)(_RO, float64), **_opts)
def reload_table_at(coeffs, x):
    """``(ln C2, ln n2)`` of the tabulated reload form at ``x = p_hist / H``.

    The monotone cubic Hermite interpolant over ``z = -ln(1 - x)`` whose knots and slopes
    ``coeffs`` carries (:func:`frictionlaw.reload_form.pchip_slopes`); the first level's values
    up to it; above the last level ``ln n2`` held and ``ln C2`` linear in ``z`` with the last two
    levels' secant slope, at least 0, at most ``ln 1e6`` (:func:`frictionlaw.reload_form.
    top_slope`; ``x >= 1``: that cap where the slope is positive). ``z`` is ``-log1p(-x)`` formed
    from ``log`` (Kahan's ``log(u) x / (u - 1)``, ``u = 1 - x`` rounded: within a few ulps of
    ``log1p``, whose libm version costs about three ``log`` here).
    """
    k = int(coeffs[9])
    zk = _TAB
    c0 = _TAB + k
    n0 = _TAB + 3 * k
    if k == 1:
        return coeffs[c0], coeffs[n0]
    if not x < 1.0:
        z = math.inf  # p_hist >= H: the rule above the last level at its limit
    else:
        u = 1.0 - x
        z = x if u == 1.0 else -math.log(u) * (x / (1.0 - u))
    if not z > coeffs[zk]:
        return coeffs[c0], coeffs[n0]
    if not z < coeffs[zk + k - 1]:  # above the last level: its secant, only here
        top = coeffs[c0 + k - 1]
        slope = (top - coeffs[c0 + k - 2]) / (coeffs[zk + k - 1] - coeffs[zk + k - 2])
        if slope > 0.0:
            top = min(top + slope * (z - coeffs[zk + k - 1]), max(top, _LNC2_MAX))
        return top, coeffs[n0 + k - 1]
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

    ``tau = tau_max a1h g(x2; n2)`` with ``a1h = alpha1(p_hist)`` of the first-loading form that
    runs (:func:`ln_alpha1`), ``(C2, n2)`` of the table at
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
    lna1h = ln_alpha1(coeffs, p_hist)
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
