"""Numba kernels of the flattening under bulk strain (private): the update and the law with it.

The per-node update of Eq. F6 and the contact fraction of Eq. F5 (docs/flattening.md), written
for the traction update: a node's flattening state is its *flattened contact fraction*
``alpha_f`` (0 for a surface never flattened), the workpiece's, whatever law runs. The NumPy
reference the tests compare against is :func:`frictionlaw.flattening.flattening_update` and
:func:`frictionlaw.flattening.flattened_alpha` (through :func:`~frictionlaw.flattening.
flattening_pressure`, the pressure ``p_f`` whose ``alpha1`` is ``alpha_f``).

Flattening data of a law (one contiguous float64 array, :func:`frictionlaw.law.flattening_data`)

=====  ==========================================================================================
slot   content
=====  ==========================================================================================
0      ``tan(theta)``, the asperities' flank slope
1      ``beta``, the factor on the sinking rate (Eq. F3)
2      ``s0 = 2 k``, the layer's in-plane flow stress of the file (Pa)
3      ``sigma_y`` of the file (Pa): the host's flow stress ``sigy`` scales ``s0`` by ``sigy / sigma_y``
4      the pressure from which ``alpha1`` is 1 to rounding (Pa), the largest flattening pressure
5 ..   the law's coefficient array with ``tau_max = 1`` (its ``shear_scalar`` is ``alpha1``)
=====  ==========================================================================================

An empty array is a law without flattening. The update solves Eq. F6 on the increment's own
interval only: with ``t = p cosh(v)`` the equivalent strain of Eq. F4 grows by
``int_u0^u1 alpha1'(p cosh v) cosh v sinh(v)^2 / W dv = D``,
``D = d_eps r beta s0 / (tan(theta) p^2)``, ``r = sqrt(3) / 2`` the stretch across the ridges per unit
equivalent plastic strain (:data:`frictionlaw.flattening.STRETCH_PER_EQUIVALENT_STRAIN`),
``W = 1 + g cosh v sinh v c_L`` with ``g = p / s0`` and the lattice's rate
``c_L = 1 + tan(theta) (1 - alpha1(p cosh v))``,
by Newton's method, its first step in ``w = sinh(u)^3 / 3`` (``dJ/dw = alpha1' / W``: exact for a
law linear in ``p`` without the lattice) and the next ones in ``u``, each step's
interval summed by Gauss-Legendre
panels no wider than 0.5 in ``v`` (the reference's rule; fewer nodes on narrow intervals; split at
the tabulated first loading's levels, where its slope has kinks, and where Eq. F2c's limit starts
to act; :mod:`frictionlaw._kernels_flattening_quad`), bisection where a step leaves the
bracket or every eighth step. Every kernel has an explicit signature, ``cache=True`` and no
``fastmath``; serial and ``prange`` array kernels are separate functions.
"""

import math

import numba as nb
from numba import float64, int8, int64, types

from ._codes import CODE_SBMF_RELOAD
from ._flattening_block import HARDENING_SINK, P_MIN_RATIO
from ._flattening_block import STRETCH_PER_EQUIVALENT_STRAIN as STRETCH
from ._kernels import first_scalar, return_map_row, shear_scalar
from ._kernels_branches import _RO, _RO2, _opts
from ._kernels_flattening_quad import (
    alpha1_inverse,
    flat_quad,
    flat_rate,
    flat_switch,
    flat_weight,
)

__all__ = [
    "FLAT_HEAD",
    "P_MIN_RATIO",
    "alpha1_inverse",
    "flat_weight",
    "flat_rate",
    "flat_quad",
    "flattening_solve",
    "flattening_scalar",
    "flat_shear_scalar",
    "flat_shear_of",
    "traction_array_flat",
    "traction_array_flat_parallel",
    "traction_array_zoned_flat",
    "traction_array_zoned_flat_parallel",
]

#: slots before the law's ``tau_max = 1`` coefficients in a law's flattening data
FLAT_HEAD = 5
_ROI = types.Array(int64, 1, "C", readonly=True)


@nb.jit(
    types.UniTuple(float64, 3)(_RO, float64, float64, float64, float64, float64, float64, float64),
    **_opts,
)
def flattening_solve(c1, p, P0, D, cap, g, m, cmax):
    """Eq. F6 from ``P0``: ``(P, d alpha1(P) / d p, alpha1(P))``, ``int_u0^u1 ... = D``.

    ``P = p cosh(u1)`` (``cap`` where the strain reaches full contact); the second value is the
    consistent tangent of the update, ``alpha1'(P) dP/dp = (D + I) W(u1) / (cosh u1 sinh u1)``
    with ``I`` the second integral of :func:`flat_quad` (0 at ``cap``); the third the fraction
    reached, which ``W(u1)`` needs too (module text).
    """
    u0 = math.acosh(max(P0 / p, 1.0))
    ucap = math.acosh(cap / p)
    vc = flat_switch(c1, p, P0, cap, m, cmax)  # where F2c's limit starts to act (inf: nowhere)
    u = u0
    F = 0.0  # the integral from u0 to u
    Ic = 0.0
    lo = u0
    hi = ucap
    hi_checked = False  # F(hi) >= D is known
    for it in range(200):
        r = D - F
        if it > 0 and abs(r) <= 1e-15 * D:
            break
        ch = math.cosh(u)
        sh = math.sinh(u)
        a, d = first_scalar(c1, p * ch)
        cl, lim = flat_rate(m, a, cmax)
        w = flat_weight(g, ch, sh, cl)
        d = d / w  # alpha1' / W: what the strain integral's integrand has
        un = math.nan
        if it == 0:  # Newton in w = sinh(u)^3 / 3 (dF/dw = alpha1' / W): the step from u0
            if d > 0.0:
                wn = sh * sh * sh / 3.0 + r / d
                if wn > 0.0:
                    un = math.asinh((3.0 * wn) ** (1.0 / 3.0))
        elif d > 0.0:  # then in u itself (dF/du = alpha1' cosh u sinh(u)^2 / W): no cube root
            un = u + r / (d * ch * sh * sh)
            if abs(un - u) <= 1e-7 * (1.0 + u) and lo < un < hi:
                # the last step: the integrand is linear over it to 3 (un - u)^2 relative,
                # below 1e-13, so F + r and the tangent's integral by its value at u
                Ic += (un - u) * d * ch * (1.0 - lim * g * cl * ch * sh * sh * sh) / w
                u = un
                break
        if not un < hi:
            un = hi if not hi_checked else 0.5 * (lo + hi)
        elif not un > lo or (it % 8 == 7 and hi_checked):
            un = 0.5 * (lo + hi)
        dF, dI = flat_quad(c1, p, u, un, g, m, cmax, vc)
        Fn = F + dF
        In = Ic + dI
        if un == ucap and not hi_checked:
            if not Fn > D:
                return cap, 0.0, first_scalar(c1, cap)[0]
            hi_checked = True
        if Fn < D:
            lo = un
        else:
            hi = un
            hi_checked = True
        step = abs(un - u)
        u = un
        F = Fn
        Ic = In
        if step <= 1e-14 * (1.0 + u) or (hi_checked and hi - lo <= 1e-14 * (1.0 + hi)):
            break
    ch = math.cosh(u)
    P = min(p * ch, cap)
    if not P < cap:
        return cap, 0.0, first_scalar(c1, cap)[0]
    sh = math.sinh(u)
    aP = first_scalar(c1, P)[0]
    w = flat_weight(g, ch, sh, flat_rate(m, aP, cmax)[0])
    return P, (D + Ic) * w / (ch * sh), aP


@nb.jit(
    types.UniTuple(float64, 3)(_RO, float64, float64, float64, float64, float64, float64), **_opts
)
def flattening_scalar(fdata, p, p_hist, alpha_f, d_eps, sigy, hard):
    """One node's flattening over a strain increment (Eq. F6): ``(alpha_f', p_f, dalpha/dp)``.

    From the committed fraction ``alpha_f`` and history ``p_hist``, at the pressure ``p`` with the
    bulk's plastic strain increment ``d_eps`` (and flow stress ``sigy``, ``<= 0``: the file's;
    hardening modulus ``hard``, ``<= 0``: perfectly plastic, Eqs. F2c and F2d):
    ``P0 = max(p_f, p_hist, p)`` (``p_f`` the pressure whose ``alpha1`` is ``alpha_f``), then F6,
    held at ``alpha1(max(p_hist, p)) + 3 p / (4 h tan(theta))`` (F2d; its pressure then 0).
    Returns the trial fraction (never below ``alpha_f``), its flattening pressure where it was
    needed and the node is flattened beyond ``max(p_hist, p)`` (else 0), and the update's
    ``d alpha / d p`` (0 without one). ``d_eps = 0``, ``p <= 1e-12 H`` and a surface in full contact leave
    ``alpha_f`` as it is.
    """
    c1 = fdata[FLAT_HEAD:]
    cap = fdata[4]
    H = c1[1]
    if not (d_eps > 0.0 and p > P_MIN_RATIO * H):
        return alpha_f, 0.0, 0.0
    P0 = max(p_hist, p)
    pf = 0.0
    if alpha_f > 0.0 and alpha_f > first_scalar(c1, P0)[0]:
        P0 = alpha1_inverse(c1, alpha_f, P0, cap)
        pf = P0
    if not P0 < cap:
        return alpha_f, pf, 0.0
    s0 = fdata[2]
    if sigy > 0.0:
        s0 = s0 * (sigy / fdata[3])
    x = p / H
    # 1/Pa, as the integrals; the equivalent strain stretches the ridges by STRETCH of it
    D = d_eps * STRETCH * fdata[1] * (s0 / H) / (fdata[0] * x * x) / H
    cmax = 6.0 * p / hard if hard > 0.0 else math.inf  # Eq. F2c, per unit 1 - A
    P, dadp, aP = flattening_solve(c1, p, P0, D, cap, p / s0, fdata[0], cmax)
    if hard > 0.0:  # Eq. F2d: no further than the sinking the hardening holds
        a_b, d_b = first_scalar(c1, max(p_hist, p))
        k = HARDENING_SINK / (hard * fdata[0])
        if a_b + k * p < 1.0 and aP > a_b + k * p:
            aP, P, dadp = a_b + k * p, 0.0, k + (d_b if p >= p_hist else 0.0)
    if aP > alpha_f:
        return aP, P, dadp
    return alpha_f, pf, 0.0


@nb.jit(
    types.UniTuple(float64, 2)(int64, _RO, _RO, float64, float64, float64, float64, float64),
    **_opts,
)
def flat_shear_of(code, coeffs, fdata, p, p_hist, a, pf, dadp):
    """``(tau, dtau/dp)`` of Eq. F5 at the trial fraction ``a`` (``dadp`` its ``d a / d p``).

    For ``p >= p_hist`` the larger of ``tau_max alpha1(p)`` and ``tau_max a`` (``dtau/dp`` the
    update's there); below it the law itself where ``a <= alpha1(p_hist)``, else its reload
    branch of the level ``p_f`` (``alpha1(p_f) = a``; ``pf`` when the update found it above
    ``p_hist``) at ``p p_f / p_hist`` (``dtau/dp`` at that fixed level).
    """
    tm = coeffs[0]
    if p >= p_hist:
        t1, d1 = first_scalar(coeffs, p)
        ta = tm * a
        if ta > t1:
            return ta, tm * dadp
        return t1, d1
    c1 = fdata[FLAT_HEAD:]
    if not a > first_scalar(c1, p_hist)[0]:
        return shear_scalar(code, coeffs, p, p_hist)
    if not pf > p_hist:
        pf = alpha1_inverse(c1, a, p_hist, fdata[4])
    t, d = shear_scalar(CODE_SBMF_RELOAD, coeffs, (p / p_hist) * pf, pf)
    return t, d * (pf / p_hist)


@nb.jit(
    types.UniTuple(float64, 3)(
        int64, _RO, _RO, float64, float64, float64, float64, float64, float64
    ),
    **_opts,
)
def flat_shear_scalar(code, coeffs, fdata, p, p_hist, alpha_f, d_eps, sigy, hard):
    """``(tau, dtau/dp, alpha_f')`` of law ``code`` with the flattening of Eq. F5 and F6.

    Without flattening data, or with ``alpha_f = 0`` and ``d_eps = 0``: :func:`shear_scalar`
    itself (bit for bit) and ``alpha_f`` unchanged. Otherwise the trial fraction ``a`` of
    :func:`flattening_scalar`, then Eq. F5 (:func:`flat_shear_of`).
    """
    if fdata.shape[0] == 0 or not p > 0.0 or (d_eps == 0.0 and alpha_f == 0.0):
        t, d = shear_scalar(code, coeffs, p, p_hist)
        return t, d, alpha_f
    a, pf, dadp = flattening_scalar(fdata, p, p_hist, alpha_f, d_eps, sigy, hard)
    t, d = flat_shear_of(code, coeffs, fdata, p, p_hist, a, pf, dadp)
    return t, d, a


_traction_flat_sig = types.void(
    int64,
    _RO,
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
)


@nb.jit(_traction_flat_sig, **_opts)
def traction_array_flat(
    code,
    coeffs,
    fdata,
    p,
    p_hist,
    alpha_f,
    d_eps,
    sigy,
    hard,
    du,
    t_old,
    k_t,
    t_new,
    status,
    dt_ddu,
    dt_dp,
    p_trial,
    a_trial,
):
    """The return map with the flattened law at every node; trial ``p_hist`` and ``alpha_f``."""
    for i in range(p.shape[0]):
        tau, dtau, a = flat_shear_scalar(
            code, coeffs, fdata, p[i], p_hist[i], alpha_f[i], d_eps[i], sigy[i], hard[i]
        )
        status[i] = return_map_row(tau, dtau, p[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i)
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
        a_trial[i] = a


@nb.jit(_traction_flat_sig, parallel=True, **_opts)
def traction_array_flat_parallel(
    code,
    coeffs,
    fdata,
    p,
    p_hist,
    alpha_f,
    d_eps,
    sigy,
    hard,
    du,
    t_old,
    k_t,
    t_new,
    status,
    dt_ddu,
    dt_dp,
    p_trial,
    a_trial,
):
    """As :func:`traction_array_flat`, threads over the nodes."""
    for i in nb.prange(p.shape[0]):
        tau, dtau, a = flat_shear_scalar(
            code, coeffs, fdata, p[i], p_hist[i], alpha_f[i], d_eps[i], sigy[i], hard[i]
        )
        status[i] = return_map_row(tau, dtau, p[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i)
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
        a_trial[i] = a


_zoned_flat_sig = types.void(
    _ROI,
    _ROI,
    _RO,
    _ROI,
    _RO,
    _ROI,
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
)


@nb.jit(_zoned_flat_sig, **_opts)
def traction_array_zoned_flat(
    codes,
    offsets,
    coeffs,
    f_offsets,
    fdata,
    zone,
    p,
    p_hist,
    alpha_f,
    d_eps,
    sigy,
    hard,
    du,
    t_old,
    k_t,
    t_new,
    status,
    dt_ddu,
    dt_dp,
    p_trial,
    a_trial,
):
    """Each node's zone law with that zone's flattening (none: the law, ``alpha_f`` kept)."""
    for i in range(p.shape[0]):
        z = zone[i]
        tau, dtau, a = flat_shear_scalar(
            codes[z],
            coeffs[offsets[z] : offsets[z + 1]],
            fdata[f_offsets[z] : f_offsets[z + 1]],
            p[i],
            p_hist[i],
            alpha_f[i],
            d_eps[i],
            sigy[i],
            hard[i],
        )
        status[i] = return_map_row(tau, dtau, p[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i)
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
        a_trial[i] = a


@nb.jit(_zoned_flat_sig, parallel=True, **_opts)
def traction_array_zoned_flat_parallel(
    codes,
    offsets,
    coeffs,
    f_offsets,
    fdata,
    zone,
    p,
    p_hist,
    alpha_f,
    d_eps,
    sigy,
    hard,
    du,
    t_old,
    k_t,
    t_new,
    status,
    dt_ddu,
    dt_dp,
    p_trial,
    a_trial,
):
    """As :func:`traction_array_zoned_flat`, threads over the nodes."""
    for i in nb.prange(p.shape[0]):
        z = zone[i]
        tau, dtau, a = flat_shear_scalar(
            codes[z],
            coeffs[offsets[z] : offsets[z + 1]],
            fdata[f_offsets[z] : f_offsets[z + 1]],
            p[i],
            p_hist[i],
            alpha_f[i],
            d_eps[i],
            sigy[i],
            hard[i],
        )
        status[i] = return_map_row(tau, dtau, p[i], du, t_old, k_t[i], t_new, dt_ddu, dt_dp, i)
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
        a_trial[i] = a
