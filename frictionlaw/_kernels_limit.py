"""Numba kernels of the two-state flattening law, model ``limit-analysis`` (private).

A node's flattening state is its contact fraction ``alpha_f`` and its asperities' flank slope
``slope_f`` (0: never flattened, the block's slope). The NumPy reference the tests compare
against is :func:`frictionlaw.flattening_limit.limit_update` (``frictionlaw._limit_table``'s
reading and integrator); the contact fraction then enters the shear through Eq. F5 as in the
one-state model (:func:`frictionlaw._kernels_flattening.flat_shear_of`).

The law's flattening data is the one-state layout (``frictionlaw.flattening.flattening_data``):
slot 0 the block's slope, 1 ``beta``, 2 ``2 k`` of the file, 3 its ``sigma_y``, 4 the pressure
where ``alpha1`` is 1, 5.. ``alpha1``'s coefficients. The rate table comes as six arrays
(``RateTable``'s fields): pressures, row offsets, ``A`` per row, ``ln s`` and the two rates.
The update's ``d alpha / d p`` is a forward difference of the integration (relative step
:data:`DP`): the table is piecewise linear, a derivative of its interpolation would be no more
exact. Explicit signatures, ``cache=True``, no ``fastmath``; serial and ``prange`` array
kernels are separate functions.
"""

import math

import numba as nb
from numba import float64, int8, int64, types

from ._flattening_block import STRETCH_PER_EQUIVALENT_STRAIN as STRETCH
from ._kernels import first_scalar, return_map_row, shear_scalar
from ._kernels_branches import _RO, _RO2, _opts
from ._kernels_flattening import FLAT_HEAD, P_MIN_RATIO, flat_shear_of, flat_shear_scalar
from ._limit_table import PRANDTL_FACTOR, S_FLOOR, STEP

__all__ = [
    "DP",
    "limit_rates_scalar",
    "limit_integrate",
    "limit_scalar",
    "limit_shear_scalar",
    "traction_array_limit",
    "traction_array_limit_parallel",
    "zoned_limit_row",
    "traction_array_zoned_limit",
    "traction_array_zoned_limit_parallel",
]

#: relative pressure step of the update's ``d alpha / d p``
DP = 1e-7
_ROI = types.Array(int64, 1, "C", readonly=True)
_TAB = (_RO, _ROI, _RO, _RO, _RO2, _RO2)


@nb.jit(int64(_RO, int64, int64, float64), **_opts)
def _cell(v, lo, hi, x):
    """The interval ``[v[i], v[i + 1]]`` of ``v[lo:hi]`` (ascending) holding ``x``, clamped."""
    i = lo
    while i < hi - 2 and x > v[i + 1]:
        i += 1
    return i


@nb.jit(types.UniTuple(float64, 2)(*_TAB, int64, float64, float64), **_opts)
def _at_pressure(P, off, a, ls, dA, ds, i, A, lns):
    """Bilinear in ``A`` and ``ln s`` at tabulated pressure ``i``, clamped to its grid."""
    lo, hi = off[i], off[i + 1]
    r = _cell(a, lo, hi, A)
    j = _cell(ls, 0, ls.shape[0], lns)
    ta = min(max((A - a[r]) / (a[r + 1] - a[r]), 0.0), 1.0)
    ts = min(max((lns - ls[j]) / (ls[j + 1] - ls[j]), 0.0), 1.0)
    ra = (1 - ta) * ((1 - ts) * dA[r, j] + ts * dA[r, j + 1]) + ta * (
        (1 - ts) * dA[r + 1, j] + ts * dA[r + 1, j + 1]
    )
    rs = (1 - ta) * ((1 - ts) * ds[r, j] + ts * ds[r, j + 1]) + ta * (
        (1 - ts) * ds[r + 1, j] + ts * ds[r + 1, j + 1]
    )
    return ra, rs


@nb.jit(types.UniTuple(float64, 2)(*_TAB, float64, float64, float64), **_opts)
def limit_rates_scalar(P, off, a, ls, dA, ds, x, A, s):
    """``(dA / d eps, ds / d eps)`` at ``p / H_P = x``, ``A`` and ``s``.

    Linear in ``ln x`` between the two tabulated pressures around it (clamped), each at the
    same ``A``; ``dA >= 0``.
    """
    i = _cell(P, 0, P.shape[0], x)
    w = min(max(math.log(x / P[i]) / math.log(P[i + 1] / P[i]), 0.0), 1.0)
    lns = math.log(s)
    a0, s0 = _at_pressure(P, off, a, ls, dA, ds, i, A, lns)
    a1, s1 = _at_pressure(P, off, a, ls, dA, ds, i + 1, A, lns)
    return max((1 - w) * a0 + w * a1, 0.0), (1 - w) * s0 + w * s1


@nb.jit(types.UniTuple(float64, 2)(*_TAB, float64, float64, float64, float64), **_opts)
def limit_integrate(P, off, a, ls, dA, ds, A, s, x, stretch):
    """``(A, s)`` after ``stretch`` at ``x``.

    The midpoint rule in ``(A, ln s)``, steps of ``STEP`` (the last shorter), ``A`` at most 1
    (it then stops), ``s`` at least ``S_FLOOR``.
    """
    A = min(A, 1.0)
    q = math.log(max(s, S_FLOOR))
    left = stretch
    while left > 1e-12 and A < 1.0:
        h = min(STEP, left)
        sq = max(math.exp(q), S_FLOOR)
        ra, rs = limit_rates_scalar(P, off, a, ls, dA, ds, x, A, sq)
        am = min(A + 0.5 * h * ra, 1.0)
        qm = q + 0.5 * h * rs / sq
        sm = max(math.exp(qm), S_FLOOR)
        ra, rs = limit_rates_scalar(P, off, a, ls, dA, ds, x, am, sm)
        A = min(A + h * ra, 1.0)
        q = q + h * rs / sm
        left -= h
    return A, max(math.exp(q), S_FLOOR)


@nb.jit(
    types.UniTuple(float64, 2)(_RO, *_TAB, float64, float64, float64, float64, float64, float64),
    **_opts,
)
def _advance(fdata, P, off, a, ls, dA, ds, p, p_hist, alpha_f, s0, d_eps, k):
    """One node's states at pressure ``p`` (``k`` the shear flow stress): ``(alpha_f', s)``."""
    c1 = fdata[FLAT_HEAD:]
    a0 = max(alpha_f, first_scalar(c1, max(p, p_hist))[0])
    x = p / (PRANDTL_FACTOR * k)
    A, s = limit_integrate(P, off, a, ls, dA, ds, a0, s0, x, STRETCH * fdata[1] * d_eps)
    return max(A, alpha_f), s


@nb.jit(
    types.UniTuple(float64, 3)(_RO, *_TAB, float64, float64, float64, float64, float64, float64),
    **_opts,
)
def limit_scalar(fdata, P, off, a, ls, dA, ds, p, p_hist, alpha_f, slope_f, d_eps, sigy):
    """One node's two states over a strain increment: ``(alpha_f', slope_f', d alpha / d p)``.

    From the committed ``alpha_f`` and ``slope_f`` (0: the block's slope) and the trial history
    ``p_hist``, at ``p`` with the bulk's equivalent plastic strain increment ``d_eps`` (flow
    stress ``sigy``, ``<= 0``: the file's). ``d_eps = 0``, ``p <= 1e-12 H`` and full contact
    leave both states as they are (and ``d alpha / d p = 0``). The derivative is computed
    where Eq. F5 reads it, on first loading (``p >= p_hist``) above ``alpha1(p)``; 0 elsewhere.
    """
    H = fdata[FLAT_HEAD + 1]
    if not (d_eps > 0.0 and p > P_MIN_RATIO * H and alpha_f < 1.0):
        return alpha_f, slope_f, 0.0
    s0 = slope_f if slope_f > 0.0 else fdata[0]
    k = 0.5 * fdata[2]
    if sigy > 0.0:
        k = k * (sigy / fdata[3])
    A, s = _advance(fdata, P, off, a, ls, dA, ds, p, p_hist, alpha_f, s0, d_eps, k)
    if p < p_hist or not A > first_scalar(fdata[FLAT_HEAD:], p)[0]:
        return A, s, 0.0  # F5 reads no derivative of the update here (flat_shear_of)
    pd = p * (1.0 + DP)
    Ad, _ = _advance(fdata, P, off, a, ls, dA, ds, pd, p_hist, alpha_f, s0, d_eps, k)
    return A, s, (Ad - A) / (pd - p)


@nb.jit(
    types.UniTuple(float64, 4)(
        int64, _RO, _RO, *_TAB, float64, float64, float64, float64, float64, float64
    ),
    **_opts,
)
def limit_shear_scalar(
    code, coeffs, fdata, P, off, a, ls, dA, ds, p, p_hist, alpha_f, slope_f, d_eps, sigy
):
    """``(tau, dtau/dp, alpha_f', slope_f')`` of law ``code`` with the two-state flattening.

    With ``alpha_f = 0`` and ``d_eps = 0`` (or ``p <= 0``): :func:`shear_scalar` itself, bit for
    bit, and the states unchanged; otherwise :func:`limit_scalar`, then Eq. F5.
    """
    if not p > 0.0 or (d_eps == 0.0 and alpha_f == 0.0):
        t, d = shear_scalar(code, coeffs, p, p_hist)
        return t, d, alpha_f, slope_f
    A, s, dadp = limit_scalar(
        fdata, P, off, a, ls, dA, ds, p, p_hist, alpha_f, slope_f, d_eps, sigy
    )
    t, d = flat_shear_of(code, coeffs, fdata, p, p_hist, A, 0.0, dadp)
    return t, d, A, s


_traction_limit_sig = types.void(
    int64,
    _RO,
    _RO,
    *_TAB,
    _RO,
    _RO,
    _RO,
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
    float64[::1],
    float64[::1],
)


@nb.jit(_traction_limit_sig, **_opts)
def traction_array_limit(
    code, coeffs, fdata, P, off, a, ls, dA, ds, p, p_hist, alpha_f, slope_f, d_eps, sigy,
    du, t_old, k_t, t_new, status, dt_ddu, dt_dp, p_trial, a_trial, s_trial,
):  # fmt: skip
    """The return map with the two-state flattened law at every node.

    Writes the trial ``p_hist``, ``alpha_f`` and ``slope_f``.
    """
    for i in range(p.shape[0]):
        tau, dtau, A, s = limit_shear_scalar(
            code, coeffs, fdata, P, off, a, ls, dA, ds,
            p[i], p_hist[i], alpha_f[i], slope_f[i], d_eps[i], sigy[i],
        )  # fmt: skip
        status[i] = return_map_row(tau, dtau, p[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i)
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
        a_trial[i] = A
        s_trial[i] = s


@nb.jit(_traction_limit_sig, parallel=True, **_opts)
def traction_array_limit_parallel(
    code, coeffs, fdata, P, off, a, ls, dA, ds, p, p_hist, alpha_f, slope_f, d_eps, sigy,
    du, t_old, k_t, t_new, status, dt_ddu, dt_dp, p_trial, a_trial, s_trial,
):  # fmt: skip
    """As :func:`traction_array_limit`, threads over the nodes."""
    for i in nb.prange(p.shape[0]):
        tau, dtau, A, s = limit_shear_scalar(
            code, coeffs, fdata, P, off, a, ls, dA, ds,
            p[i], p_hist[i], alpha_f[i], slope_f[i], d_eps[i], sigy[i],
        )  # fmt: skip
        status[i] = return_map_row(tau, dtau, p[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i)
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
        a_trial[i] = A
        s_trial[i] = s


@nb.jit(
    types.UniTuple(float64, 4)(
        _ROI, _ROI, _RO, _ROI, _RO, _ROI, *_TAB, int64,
        float64, float64, float64, float64, float64, float64, float64,
    ),
    **_opts,
)  # fmt: skip
def zoned_limit_row(
    codes, offsets, coeffs, f_offsets, fdata, models, P, off, a, ls, dA, ds, z,
    p, p_hist, alpha_f, slope_f, d_eps, sigy, hard,
):  # fmt: skip
    """``(tau, dtau/dp, alpha_f', slope_f')`` of zone ``z``'s law at one node.

    A two-state zone (``models[z] == 1``) runs :func:`limit_shear_scalar`; another zone its
    one-state flattening or none (``frictionlaw._kernels_flattening.flat_shear_scalar``, with
    the hardening modulus ``hard``) and passes ``slope_f`` on unchanged: the flank slope is the
    workpiece's, as the fraction is, and only a two-state zone turns it.
    """
    c = coeffs[offsets[z] : offsets[z + 1]]
    fd = fdata[f_offsets[z] : f_offsets[z + 1]]
    if models[z] == 1:
        return limit_shear_scalar(
            codes[z], c, fd, P, off, a, ls, dA, ds, p, p_hist, alpha_f, slope_f, d_eps, sigy
        )
    t, d, af = flat_shear_scalar(codes[z], c, fd, p, p_hist, alpha_f, d_eps, sigy, hard)
    return t, d, af, slope_f


_zoned_limit_sig = types.void(
    _ROI,
    _ROI,
    _RO,
    _ROI,
    _RO,
    _ROI,
    *_TAB,
    _ROI,
    _RO,
    _RO,
    _RO,
    _RO,
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
    float64[::1],
    float64[::1],
)


@nb.jit(_zoned_limit_sig, **_opts)
def traction_array_zoned_limit(
    codes, offsets, coeffs, f_offsets, fdata, models, P, off, a, ls, dA, ds, zone,
    p, p_hist, alpha_f, slope_f, d_eps, sigy, hard,
    du, t_old, k_t, t_new, status, dt_ddu, dt_dp, p_trial, a_trial, s_trial,
):  # fmt: skip
    """The return map of a zoned law with a two-state zone: each node's zone law.

    :func:`zoned_limit_row` per node; writes the trial ``p_hist``, ``alpha_f`` and ``slope_f``.
    """
    for i in range(p.shape[0]):
        tau, dtau, A, s = zoned_limit_row(
            codes, offsets, coeffs, f_offsets, fdata, models, P, off, a, ls, dA, ds, zone[i],
            p[i], p_hist[i], alpha_f[i], slope_f[i], d_eps[i], sigy[i], hard[i],
        )  # fmt: skip
        status[i] = return_map_row(tau, dtau, p[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i)
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
        a_trial[i] = A
        s_trial[i] = s


@nb.jit(_zoned_limit_sig, parallel=True, **_opts)
def traction_array_zoned_limit_parallel(
    codes, offsets, coeffs, f_offsets, fdata, models, P, off, a, ls, dA, ds, zone,
    p, p_hist, alpha_f, slope_f, d_eps, sigy, hard,
    du, t_old, k_t, t_new, status, dt_ddu, dt_dp, p_trial, a_trial, s_trial,
):  # fmt: skip
    """As :func:`traction_array_zoned_limit`, threads over the nodes."""
    for i in nb.prange(p.shape[0]):
        tau, dtau, A, s = zoned_limit_row(
            codes, offsets, coeffs, f_offsets, fdata, models, P, off, a, ls, dA, ds, zone[i],
            p[i], p_hist[i], alpha_f[i], slope_f[i], d_eps[i], sigy[i], hard[i],
        )  # fmt: skip
        status[i] = return_map_row(tau, dtau, p[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i)
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
        a_trial[i] = A
        s_trial[i] = s
