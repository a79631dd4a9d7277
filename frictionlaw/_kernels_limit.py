"""Numba kernels of the two-state flattening law, model ``limit-analysis`` (private).

A node's flattening state is its contact fraction ``alpha_f`` and its asperities' flank slope
``slope_f`` (0: never flattened, the block's slope). The NumPy reference the tests compare
against is :func:`frictionlaw.flattening_limit.limit_update` (``frictionlaw._limit_table``'s
reading and integrator); the contact fraction then enters the shear through Eq. F5 as in the
one-state model (:func:`frictionlaw._kernels_flattening.flat_shear_of`).

A block's ``edge_slope`` table (the workpiece's edge slope at equally spaced contact fractions)
comes as one more array ``E`` after the rate table (empty: the block's one slope): the
integrators then carry the flank's turn ``r = s / E(A)`` in place of ``s`` and read the table at
``max(r E(A), S_FLOOR)`` (:func:`edge_scalar`; ``frictionlaw._limit_table``'s rule).

The law's flattening data is the one-state layout (``frictionlaw.flattening.flattening_data``):
slot 0 the block's slope, 1 ``beta``, 2 ``2 k`` of the file, 3 its ``sigma_y``, 4 the pressure
where ``alpha1`` is 1, 5.. ``alpha1``'s coefficients. The rate table comes as six arrays
(``RateTable``'s fields): pressures, row offsets, ``A`` per row, ``ln s`` and the two rates.
The update's ``d alpha / d p`` (on first loading, where Eq. F5 reads it) is carried forward
through the same midpoint steps as the states (:func:`limit_integrate_d`): the derivative of the
table's bilinear and log-linear reading, 0 where a coordinate is clamped (the right derivative
at a grid line; the table is piecewise linear). It replaced a forward difference of a second
integration (agreeing to 6e-6 relative on the tests' grid). Explicit signatures,
``cache=True``, no ``fastmath``; serial and ``prange`` array kernels are separate functions.
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
    "edge_scalar",
    "limit_rates_scalar",
    "limit_rates_d",
    "limit_integrate",
    "limit_integrate_d",
    "limit_scalar",
    "limit_shear_scalar",
    "traction_array_limit",
    "traction_array_limit_parallel",
    "zoned_limit_row",
    "traction_array_zoned_limit",
    "traction_array_zoned_limit_parallel",
]

_ROI = types.Array(int64, 1, "C", readonly=True)
_TAB = (_RO, _ROI, _RO, _RO, _RO2, _RO2)
#: the rate table and the edge-slope table (empty: none)
_ETAB = (*_TAB, _RO)


@nb.jit(types.UniTuple(float64, 2)(_RO, float64), **_opts)
def edge_scalar(E, A):
    """``(E(A), dE/dA)``: the edge slope linear between ``E``'s equally spaced fractions.

    ``(1, 0)`` for an empty table; the right derivative at a grid point (0 at ``A = 1``).
    """
    n = E.shape[0]
    if n == 0:
        return 1.0, 0.0
    u = A * (n - 1)
    i = min(int(math.floor(u)), n - 2)
    g = (E[i + 1] - E[i]) * (n - 1) if u < n - 1 else 0.0
    return E[i] + (u - i) * (E[i + 1] - E[i]), g


@nb.jit(float64(_RO, float64), **_opts)
def _start_log(E, s):
    """``ln s`` floored at ``S_FLOOR``, or ``ln r`` with an edge table (``_limit_table``)."""
    if E.shape[0] == 0:
        return math.log(max(s, S_FLOOR))
    return math.log(max(s, 1e-300))


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


@nb.jit(types.UniTuple(float64, 2)(*_ETAB, float64, float64, float64, float64), **_opts)
def limit_integrate(P, off, a, ls, dA, ds, E, A, s, x, stretch):
    """``(A, s)`` after ``stretch`` at ``x``.

    The midpoint rule in ``(A, ln s)``, steps of ``STEP`` (the last shorter), ``A`` at most 1
    (it then stops), ``s`` at least ``S_FLOOR``. With an edge table ``E`` the given ``s`` is
    the turn ``r`` and the rule runs in ``(A, ln r)``; the end's slope is ``max(r E(A), S_FLOOR)``.
    """
    A = min(A, 1.0)
    q = _start_log(E, s)
    left = stretch
    while left > 1e-12 and A < 1.0:
        h = min(STEP, left)
        sq = max(math.exp(q) * edge_scalar(E, A)[0], S_FLOOR)
        ra, rs = limit_rates_scalar(P, off, a, ls, dA, ds, x, A, sq)
        am = min(A + 0.5 * h * ra, 1.0)
        qm = q + 0.5 * h * rs / sq
        sm = max(math.exp(qm) * edge_scalar(E, am)[0], S_FLOOR)
        ra, rs = limit_rates_scalar(P, off, a, ls, dA, ds, x, am, sm)
        A = min(A + h * ra, 1.0)
        q = q + h * rs / sm
        left -= h
    return A, max(math.exp(q) * edge_scalar(E, A)[0], S_FLOOR)


@nb.jit(types.UniTuple(float64, 6)(*_TAB, int64, float64, float64), **_opts)
def _at_pressure_d(P, off, a, ls, dA, ds, i, A, lns):
    """:func:`_at_pressure` (bit for bit) and its derivatives in ``A`` and ``ln s``.

    Returns ``(ra, rs, dra/dA, drs/dA, dra/dlns, drs/dlns)``; a derivative is 0 where its
    coordinate is clamped to the grid (the right derivative at a grid line). The value path
    keeps its own function: reading the rates through this one cost the two-state update 15-24 %
    a node (``bench_flattening_runtime.py``, tried and reverted).
    """
    lo, hi = off[i], off[i + 1]
    r = _cell(a, lo, hi, A)
    j = _cell(ls, 0, ls.shape[0], lns)
    ua = (A - a[r]) / (a[r + 1] - a[r])
    us = (lns - ls[j]) / (ls[j + 1] - ls[j])
    ta = min(max(ua, 0.0), 1.0)
    ts = min(max(us, 0.0), 1.0)
    ga = 1.0 / (a[r + 1] - a[r]) if 0.0 <= ua < 1.0 else 0.0
    gs = 1.0 / (ls[j + 1] - ls[j]) if 0.0 <= us < 1.0 else 0.0
    a0 = (1 - ts) * dA[r, j] + ts * dA[r, j + 1]
    a1 = (1 - ts) * dA[r + 1, j] + ts * dA[r + 1, j + 1]
    s0 = (1 - ts) * ds[r, j] + ts * ds[r, j + 1]
    s1 = (1 - ts) * ds[r + 1, j] + ts * ds[r + 1, j + 1]
    ra = (1 - ta) * a0 + ta * a1
    rs = (1 - ta) * s0 + ta * s1
    ra_l = gs * ((1 - ta) * (dA[r, j + 1] - dA[r, j]) + ta * (dA[r + 1, j + 1] - dA[r + 1, j]))
    rs_l = gs * ((1 - ta) * (ds[r, j + 1] - ds[r, j]) + ta * (ds[r + 1, j + 1] - ds[r + 1, j]))
    return ra, rs, ga * (a1 - a0), ga * (s1 - s0), ra_l, rs_l


@nb.jit(types.UniTuple(float64, 8)(*_TAB, float64, float64, float64), **_opts)
def limit_rates_d(P, off, a, ls, dA, ds, x, A, s):
    """:func:`limit_rates_scalar` (bit for bit) and its derivatives in ``x``, ``A`` and ``s``.

    Returns ``(ra, rs, dra/dx, drs/dx, dra/dA, drs/dA, dra/ds, drs/ds)``; those of ``ra`` are 0
    where it is held at 0.
    """
    i = _cell(P, 0, P.shape[0], x)
    lg = math.log(P[i + 1] / P[i])
    uw = math.log(x / P[i]) / lg
    w = min(max(uw, 0.0), 1.0)
    gw = 1.0 / (x * lg) if 0.0 <= uw < 1.0 else 0.0
    lns = math.log(s)
    a0, s0, a0A, s0A, a0l, s0l = _at_pressure_d(P, off, a, ls, dA, ds, i, A, lns)
    a1, s1, a1A, s1A, a1l, s1l = _at_pressure_d(P, off, a, ls, dA, ds, i + 1, A, lns)
    raw = (1 - w) * a0 + w * a1
    rs = (1 - w) * s0 + w * s1
    rs_x, rs_A, rs_s = gw * (s1 - s0), (1 - w) * s0A + w * s1A, ((1 - w) * s0l + w * s1l) / s
    if not raw > 0.0:
        return 0.0, rs, 0.0, rs_x, 0.0, rs_A, 0.0, rs_s
    ra_s = ((1 - w) * a0l + w * a1l) / s
    return raw, rs, gw * (a1 - a0), rs_x, (1 - w) * a0A + w * a1A, rs_A, ra_s, rs_s


@nb.jit(
    types.UniTuple(float64, 3)(*_ETAB, float64, float64, float64, float64, float64, float64),
    **_opts,
)
def limit_integrate_d(P, off, a, ls, dA, ds, E, A, s, x, stretch, A_p, x_p):
    """:func:`limit_integrate` (its states bit for bit) with ``dA / dp`` of its end.

    The derivative is carried forward through the same steps: ``A_p`` the start's ``dA / dp``,
    ``x_p = dx / dp`` (the start's slope does not depend on ``p``); 0 through a step where ``A``
    reaches 1 or ``s`` its floor. Returns ``(A, s, dA / dp)``.
    """
    A = min(A, 1.0)
    Ad = A_p if A < 1.0 else 0.0
    q = _start_log(E, s)
    qd = 0.0
    left = stretch
    while left > 1e-12 and A < 1.0:
        h = min(STEP, left)
        g, gA = edge_scalar(E, A)
        e = math.exp(q) * g
        sq = max(e, S_FLOOR)
        sqd = e * qd + math.exp(q) * gA * Ad if e > S_FLOOR else 0.0
        ra, rs, rax, rsx, raA, rsA, ras, rss = limit_rates_d(P, off, a, ls, dA, ds, x, A, sq)
        rad = rax * x_p + raA * Ad + ras * sqd
        rsd = rsx * x_p + rsA * Ad + rss * sqd
        amr = A + 0.5 * h * ra
        am = min(amr, 1.0)
        amd = Ad + 0.5 * h * rad if amr < 1.0 else 0.0
        qm = q + 0.5 * h * rs / sq
        qmd = qd + 0.5 * h * (rsd - rs * sqd / sq) / sq
        g, gA = edge_scalar(E, am)
        em = math.exp(qm) * g
        sm = max(em, S_FLOOR)
        smd = em * qmd + math.exp(qm) * gA * amd if em > S_FLOOR else 0.0
        ra, rs, rax, rsx, raA, rsA, ras, rss = limit_rates_d(P, off, a, ls, dA, ds, x, am, sm)
        rad = rax * x_p + raA * amd + ras * smd
        rsd = rsx * x_p + rsA * amd + rss * smd
        Ar = A + h * ra
        A = min(Ar, 1.0)
        Ad = Ad + h * rad if Ar < 1.0 else 0.0
        q = q + h * rs / sm
        qd = qd + h * (rsd - rs * smd / sm) / sm
        left -= h
    return A, max(math.exp(q) * edge_scalar(E, A)[0], S_FLOOR), Ad


@nb.jit(
    types.UniTuple(float64, 2)(_RO, *_ETAB, float64, float64, float64, float64, float64, float64),
    **_opts,
)
def _advance(fdata, P, off, a, ls, dA, ds, E, p, p_hist, alpha_f, s0, d_eps, k):
    """One node's states at pressure ``p`` (``k`` the shear flow stress): ``(alpha_f', s)``."""
    c1 = fdata[FLAT_HEAD:]
    a0 = max(alpha_f, first_scalar(c1, max(p, p_hist))[0])
    x = p / (PRANDTL_FACTOR * k)
    A, s = limit_integrate(P, off, a, ls, dA, ds, E, a0, s0, x, STRETCH * fdata[1] * d_eps)
    return max(A, alpha_f), s


@nb.jit(
    types.UniTuple(float64, 3)(_RO, *_ETAB, float64, float64, float64, float64, float64, float64),
    **_opts,
)
def limit_scalar(fdata, P, off, a, ls, dA, ds, E, p, p_hist, alpha_f, slope_f, d_eps, sigy):
    """One node's two states over a strain increment: ``(alpha_f', slope_f', d alpha / d p)``.

    From the committed ``alpha_f`` and ``slope_f`` (0: the block's slope) and the trial history
    ``p_hist``, at ``p`` with the bulk's equivalent plastic strain increment ``d_eps`` (flow
    stress ``sigy``, ``<= 0``: the file's); with an edge table the turn ``slope_f / E(alpha_f)``
    (1 never flattened). ``d_eps = 0``, ``p <= 1e-12 H`` and full contact
    leave both states as they are (and ``d alpha / d p = 0``). The derivative is computed
    where Eq. F5 reads it, on first loading (``p >= p_hist``) above ``alpha1(p)``; 0 elsewhere.
    """
    H = fdata[FLAT_HEAD + 1]
    if not (d_eps > 0.0 and p > P_MIN_RATIO * H and alpha_f < 1.0):
        return alpha_f, slope_f, 0.0
    if E.shape[0] == 0:
        s0 = slope_f if slope_f > 0.0 else fdata[0]
    else:
        s0 = slope_f / edge_scalar(E, alpha_f)[0] if slope_f > 0.0 else 1.0
    k = 0.5 * fdata[2]
    if sigy > 0.0:
        k = k * (sigy / fdata[3])
    if p < p_hist:  # F5 reads no derivative of the update below p_hist (flat_shear_of)
        A, s = _advance(fdata, P, off, a, ls, dA, ds, E, p, p_hist, alpha_f, s0, d_eps, k)
        return A, s, 0.0
    # first loading: the same integration carries d A / d p forward (from alpha1' where the
    # start is alpha1(p), and from x = p / H_P)
    c1 = fdata[FLAT_HEAD:]
    a1, a1_p = first_scalar(c1, p)
    a0 = max(alpha_f, a1)
    x = p / (PRANDTL_FACTOR * k)
    A, s, A_p = limit_integrate_d(
        P, off, a, ls, dA, ds, E, a0, s0, x, STRETCH * fdata[1] * d_eps,
        a1_p if a1 >= alpha_f else 0.0, 1.0 / (PRANDTL_FACTOR * k),
    )  # fmt: skip
    if not A > alpha_f:
        A, A_p = alpha_f, 0.0
    if not A > a1:
        A_p = 0.0  # F5 reads the first loading's own slope here
    return A, s, A_p


@nb.jit(
    types.UniTuple(float64, 4)(
        int64, _RO, _RO, *_ETAB, float64, float64, float64, float64, float64, float64
    ),
    **_opts,
)
def limit_shear_scalar(
    code, coeffs, fdata, P, off, a, ls, dA, ds, E, p, p_hist, alpha_f, slope_f, d_eps, sigy
):
    """``(tau, dtau/dp, alpha_f', slope_f')`` of law ``code`` with the two-state flattening.

    With ``alpha_f = 0`` and ``d_eps = 0`` (or ``p <= 0``): :func:`shear_scalar` itself, bit for
    bit, and the states unchanged; otherwise :func:`limit_scalar`, then Eq. F5.
    """
    if not p > 0.0 or (d_eps == 0.0 and alpha_f == 0.0):
        t, d = shear_scalar(code, coeffs, p, p_hist)
        return t, d, alpha_f, slope_f
    A, s, dadp = limit_scalar(
        fdata, P, off, a, ls, dA, ds, E, p, p_hist, alpha_f, slope_f, d_eps, sigy
    )
    t, d = flat_shear_of(code, coeffs, fdata, p, p_hist, A, 0.0, dadp)
    return t, d, A, s


_traction_limit_sig = types.void(
    int64,
    _RO,
    _RO,
    *_ETAB,
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
    code, coeffs, fdata, P, off, a, ls, dA, ds, E, p, p_hist, alpha_f, slope_f, d_eps, sigy,
    du, t_old, k_t, t_new, status, dt_ddu, dt_dp, p_trial, a_trial, s_trial,
):  # fmt: skip
    """The return map with the two-state flattened law at every node.

    Writes the trial ``p_hist``, ``alpha_f`` and ``slope_f``.
    """
    for i in range(p.shape[0]):
        tau, dtau, A, s = limit_shear_scalar(
            code, coeffs, fdata, P, off, a, ls, dA, ds, E,
            p[i], p_hist[i], alpha_f[i], slope_f[i], d_eps[i], sigy[i],
        )  # fmt: skip
        status[i] = return_map_row(tau, dtau, p[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i)
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
        a_trial[i] = A
        s_trial[i] = s


@nb.jit(_traction_limit_sig, parallel=True, **_opts)
def traction_array_limit_parallel(
    code, coeffs, fdata, P, off, a, ls, dA, ds, E, p, p_hist, alpha_f, slope_f, d_eps, sigy,
    du, t_old, k_t, t_new, status, dt_ddu, dt_dp, p_trial, a_trial, s_trial,
):  # fmt: skip
    """As :func:`traction_array_limit`, threads over the nodes."""
    for i in nb.prange(p.shape[0]):
        tau, dtau, A, s = limit_shear_scalar(
            code, coeffs, fdata, P, off, a, ls, dA, ds, E,
            p[i], p_hist[i], alpha_f[i], slope_f[i], d_eps[i], sigy[i],
        )  # fmt: skip
        status[i] = return_map_row(tau, dtau, p[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i)
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
        a_trial[i] = A
        s_trial[i] = s


@nb.jit(
    types.UniTuple(float64, 4)(
        _ROI, _ROI, _RO, _ROI, _RO, _ROI, *_ETAB, _ROI, int64,
        float64, float64, float64, float64, float64, float64, float64,
    ),
    **_opts,
)  # fmt: skip
def zoned_limit_row(
    codes, offsets, coeffs, f_offsets, fdata, models, P, off, a, ls, dA, ds, E, e_off, z,
    p, p_hist, alpha_f, slope_f, d_eps, sigy, hard,
):  # fmt: skip
    """``(tau, dtau/dp, alpha_f', slope_f')`` of zone ``z``'s law at one node.

    A two-state zone (``models[z] == 1``) runs :func:`limit_shear_scalar`; another zone its
    one-state flattening or none (``frictionlaw._kernels_flattening.flat_shear_scalar``, with
    the hardening modulus ``hard``) and passes ``slope_f`` on unchanged: the flank slope is the
    workpiece's, as the fraction is, and only a two-state zone turns it. Zone ``z``'s edge
    table is ``E[e_off[z]:e_off[z + 1]]`` (empty: its block's one slope).
    """
    c = coeffs[offsets[z] : offsets[z + 1]]
    fd = fdata[f_offsets[z] : f_offsets[z + 1]]
    if models[z] == 1:
        ez = E[e_off[z] : e_off[z + 1]]
        return limit_shear_scalar(
            codes[z], c, fd, P, off, a, ls, dA, ds, ez, p, p_hist, alpha_f, slope_f, d_eps, sigy
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
    *_ETAB,
    _ROI,
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
    codes, offsets, coeffs, f_offsets, fdata, models, P, off, a, ls, dA, ds, E, e_off, zone,
    p, p_hist, alpha_f, slope_f, d_eps, sigy, hard,
    du, t_old, k_t, t_new, status, dt_ddu, dt_dp, p_trial, a_trial, s_trial,
):  # fmt: skip
    """The return map of a zoned law with a two-state zone: each node's zone law.

    :func:`zoned_limit_row` per node; writes the trial ``p_hist``, ``alpha_f`` and ``slope_f``.
    """
    for i in range(p.shape[0]):
        tau, dtau, A, s = zoned_limit_row(
            codes, offsets, coeffs, f_offsets, fdata, models, P, off, a, ls, dA, ds, E, e_off, zone[i],
            p[i], p_hist[i], alpha_f[i], slope_f[i], d_eps[i], sigy[i], hard[i],
        )  # fmt: skip
        status[i] = return_map_row(tau, dtau, p[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i)
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
        a_trial[i] = A
        s_trial[i] = s


@nb.jit(_zoned_limit_sig, parallel=True, **_opts)
def traction_array_zoned_limit_parallel(
    codes, offsets, coeffs, f_offsets, fdata, models, P, off, a, ls, dA, ds, E, e_off, zone,
    p, p_hist, alpha_f, slope_f, d_eps, sigy, hard,
    du, t_old, k_t, t_new, status, dt_ddu, dt_dp, p_trial, a_trial, s_trial,
):  # fmt: skip
    """As :func:`traction_array_zoned_limit`, threads over the nodes."""
    for i in nb.prange(p.shape[0]):
        tau, dtau, A, s = zoned_limit_row(
            codes, offsets, coeffs, f_offsets, fdata, models, P, off, a, ls, dA, ds, E, e_off, zone[i],
            p[i], p_hist[i], alpha_f[i], slope_f[i], d_eps[i], sigy[i], hard[i],
        )  # fmt: skip
        status[i] = return_map_row(tau, dtau, p[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i)
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
        a_trial[i] = A
        s_trial[i] = s
