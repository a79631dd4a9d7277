"""Numba kernels of the FE demo's element loops (private).

All numba code of :mod:`fe_demo` lives here. Every kernel has an explicit signature (so it is
compiled, or loaded from numba's on-disk cache, at import), ``cache=True`` and no ``fastmath``.
Each loops over elements (or Gauss points) and does per element what the vectorised NumPy
functions of :mod:`fe_demo.solver.element` and :mod:`fe_demo.solver.material` do for all elements at once;
those NumPy functions are the independent oracles the tests compare against
(``tests/test_fe_kernels.py``). The radial return has a scalar (one point) kernel,
:func:`radial_return_row`, and an array kernel built on it.

Array layouts are those of :mod:`fe_demo.solver.element`: ``N (4, nq)``, ``dN (4, 2, nq)``,
``w (nq,)``, ``B (n_el, nq, 4, 8)``, ``dV, r (n_el, nq)``, ``dNdx (n_el, nq, 4, 2)``; Voigt
vectors ``[rr, zz, tt, rz]`` with engineering shear.
"""

import math

import numba as nb
import numpy as np
from numba import boolean, float64, int64, types

_opts = dict(nopython=True, cache=True, nogil=True, error_model="numpy")

_RO1 = types.Array(float64, 1, "C", readonly=True)
_RO2 = types.Array(float64, 2, "C", readonly=True)
_RO3 = types.Array(float64, 3, "C", readonly=True)
_RO4 = types.Array(float64, 4, "C", readonly=True)
_RI1 = types.Array(int64, 1, "C", readonly=True)
_RI2 = types.Array(int64, 2, "C", readonly=True)
_TWO_PI = 2.0 * math.pi


@nb.jit(
    float64(
        _RO2,
        _RI2,
        _RO2,
        _RO3,
        _RO1,
        boolean,
        float64[:, :, :, ::1],
        float64[:, ::1],
        float64[:, ::1],
        float64[:, :, :, ::1],
    ),
    **_opts,
)
def kinematics(x, t, N, dN, w, axisymmetric, B, dV, r, dNdx):
    """B-bar matrices, volume weights, radii and shape-function gradients of every element.

    Fills ``B``, ``dV``, ``r``, ``dNdx`` as :func:`fe_demo.solver.element.kinematics` does and returns
    the smallest Jacobian determinant. ``t`` is the connectivity ``(4, n_el)``;
    ``axisymmetric`` False gives the plane-strain element (no ``N / r`` row, ``dV = detJ w``).
    """
    ne = t.shape[1]
    nq = w.shape[0]
    min_det = math.inf
    xe_r = np.empty(4)
    xe_z = np.empty(4)
    bvol = np.empty((nq, 8))
    for e in range(ne):
        for a in range(4):
            node = t[a, e]
            xe_r[a] = x[node, 0]
            xe_z[a] = x[node, 1]
        vol = 0.0
        for q in range(nq):
            j00 = 0.0
            j01 = 0.0
            j10 = 0.0
            j11 = 0.0
            rq = 0.0
            for a in range(4):
                j00 += xe_r[a] * dN[a, 0, q]
                j01 += xe_r[a] * dN[a, 1, q]
                j10 += xe_z[a] * dN[a, 0, q]
                j11 += xe_z[a] * dN[a, 1, q]
                rq += N[a, q] * xe_r[a]
            det = j00 * j11 - j01 * j10
            if det < min_det:
                min_det = det
            det_s = det if det > 0.0 else 1.0
            i00 = j11 / det_s
            i11 = j00 / det_s
            i01 = -j01 / det_s
            i10 = -j10 / det_s
            r[e, q] = rq
            r_s = rq if rq > 0.0 else 1.0
            dv = _TWO_PI * rq * det * w[q] if axisymmetric else det * w[q]
            dV[e, q] = dv
            vol += dv
            for a in range(4):
                gr = dN[a, 0, q] * i00 + dN[a, 1, q] * i10
                gz = dN[a, 0, q] * i01 + dN[a, 1, q] * i11
                dNdx[e, q, a, 0] = gr
                dNdx[e, q, a, 1] = gz
                nr = N[a, q] / r_s if axisymmetric else 0.0
                B[e, q, 0, 2 * a] = gr
                B[e, q, 0, 2 * a + 1] = 0.0
                B[e, q, 1, 2 * a] = 0.0
                B[e, q, 1, 2 * a + 1] = gz
                B[e, q, 2, 2 * a] = nr
                B[e, q, 2, 2 * a + 1] = 0.0
                B[e, q, 3, 2 * a] = gz
                B[e, q, 3, 2 * a + 1] = gr
                bvol[q, 2 * a] = gr + nr
                bvol[q, 2 * a + 1] = gz
        # mean dilatation: the volumetric part of B replaced by its element average
        vol_s = vol if abs(vol) > 0.0 else 1.0
        for k in range(8):
            bbar = 0.0
            for q in range(nq):
                bbar += dV[e, q] * bvol[q, k]
            bbar /= vol_s
            for q in range(nq):
                corr = (bbar - bvol[q, k]) / 3.0
                B[e, q, 0, k] += corr
                B[e, q, 1, k] += corr
                B[e, q, 2, k] += corr
    return min_det


@nb.jit(
    types.void(_RO4, _RO4, _RI2, _RO1, _RO3, float64[:, :, ::1], float64[:, :, ::1]),
    **_opts,
)
def strain_spin_rotate(B, dNdx, edofs, du, sigma, deps, sig_rot):
    """Strain increments ``B du`` and the stresses rotated by the spin of ``du``.

    ``B``, ``dNdx`` are the mid-increment configuration's, ``sigma (n_el, nq, 4)`` the stresses
    of the last increment; fills ``deps`` and ``sig_rot`` (both ``(n_el, nq, 4)``) as
    ``einsum("eqia,ea->eqi", B, du[edofs])`` and :func:`fe_demo.solver.model._rotate` do, with the
    in-plane spin ``w = (d du_r / dz - d du_z / dr) / 2``.
    """
    ne = B.shape[0]
    nq = B.shape[1]
    due = np.empty(8)
    for e in range(ne):
        for k in range(8):
            due[k] = du[edofs[e, k]]
        for q in range(nq):
            for i in range(4):
                s = 0.0
                for k in range(8):
                    s += B[e, q, i, k] * due[k]
                deps[e, q, i] = s
            a1 = 0.0
            a2 = 0.0
            for a in range(4):
                a1 += dNdx[e, q, a, 1] * due[2 * a]
                a2 += dNdx[e, q, a, 0] * due[2 * a + 1]
            ang = 0.5 * (a1 - a2)
            c = math.cos(ang)
            sn = math.sin(ang)
            sa = sigma[e, q, 0]
            sb = sigma[e, q, 1]
            sd = sigma[e, q, 3]
            sig_rot[e, q, 0] = c * c * sa + 2 * c * sn * sd + sn * sn * sb
            sig_rot[e, q, 1] = sn * sn * sa - 2 * c * sn * sd + c * c * sb
            sig_rot[e, q, 2] = sigma[e, q, 2]
            sig_rot[e, q, 3] = -c * sn * sa + (c * c - sn * sn) * sd + c * sn * sb


@nb.jit(types.UniTuple(float64, 2)(float64, float64, float64, float64), **_opts)
def _flow(K, eps0, n, ep):
    """Swift flow stress ``K a**n`` and slope ``n K a**(n-1)``, ``a = eps0 + max(ep, 0)``.

    The slope is formed as ``n sigma_f / a``: one ``pow`` per call.
    """
    a = eps0 + max(ep, 0.0)
    f = K * a**n
    return f, n * f / a


_rr_row_sig = int64(
    _RO2, _RO1, _RO2, _RO1, _RO2, float64[:, ::1], float64[::1], float64[:, :, ::1], int64
)


@nb.jit(_rr_row_sig, inline="always", **_opts)
def radial_return_row(De, prm, sigma_old, eps_p_old, d_eps, sigma, eps_p, D, i):
    """Radial return with the consistent tangent at point ``i`` (row ``i`` of the arrays).

    ``prm = [G, K_bulk, K, eps0, n, tol, max_iter, sigma_y0]`` (Swift flow curve
    ``K (eps0 + eps_p)**n``), ``De`` the elastic matrix. Writes ``sigma[i]``, ``eps_p[i]``,
    ``D[i]`` as :func:`fe_demo.solver.material.radial_return` does; returns 0 (elastic), 1 (plastic)
    or -1 (the local Newton iteration did not converge).
    """
    G = prm[0]
    Kb = prm[1]
    K = prm[2]
    eps0 = prm[3]
    n = prm[4]
    tol = prm[5]
    max_iter = int(prm[6])
    sy0 = prm[7]
    d0 = d_eps[i, 0]
    d1 = d_eps[i, 1]
    d2 = d_eps[i, 2]
    d3 = d_eps[i, 3]
    # trial stress, scalars only (a list here would be allocated at every point)
    t0 = sigma_old[i, 0] + (De[0, 0] * d0 + De[0, 1] * d1 + De[0, 2] * d2 + De[0, 3] * d3)
    t1 = sigma_old[i, 1] + (De[1, 0] * d0 + De[1, 1] * d1 + De[1, 2] * d2 + De[1, 3] * d3)
    t2 = sigma_old[i, 2] + (De[2, 0] * d0 + De[2, 1] * d1 + De[2, 2] * d2 + De[2, 3] * d3)
    t3 = sigma_old[i, 3] + (De[3, 0] * d0 + De[3, 1] * d1 + De[3, 2] * d2 + De[3, 3] * d3)
    p_tr = (t0 + t1 + t2) / 3.0
    s0 = t0 - p_tr
    s1 = t1 - p_tr
    s2 = t2 - p_tr
    s3 = t3
    snorm = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2 + 2.0 * s3 * s3)
    q = math.sqrt(1.5) * snorm
    ep0 = eps_p_old[i]
    f0, h0 = _flow(K, eps0, n, ep0)
    f_tr = q - f0
    if not f_tr > tol * sy0:
        sigma[i, 0] = t0
        sigma[i, 1] = t1
        sigma[i, 2] = t2
        sigma[i, 3] = t3
        for a in range(4):
            for b in range(4):
                D[i, a, b] = De[a, b]
        eps_p[i] = ep0
        return 0
    dg = 0.0
    converged = False
    for it in range(max_iter):
        # at dg = 0 the flow stress and slope are the trial's (ep0 + 0.0 == ep0): no new pow
        f, h = (f0, h0) if it == 0 else _flow(K, eps0, n, ep0 + dg)
        res = q - 3.0 * G * dg - f
        dres = -3.0 * G - h
        step = -res / dres
        dg = max(dg + step, 0.0)
        if abs(res) <= tol * q:
            converged = True
            break
    if not converged:
        return -1
    fac = 1.0 - 3.0 * G * dg / q
    sdev = (s0, s1, s2, s3)
    for a in range(4):
        sigma[i, a] = fac * sdev[a] + (p_tr if a < 3 else 0.0)
    eps_p[i] = ep0 + dg
    Hs = _flow(K, eps0, n, ep0 + dg)[1]
    c1 = 2.0 * G * fac
    c2 = 6.0 * G * G * (dg / q - 1.0 / (3.0 * G + Hs))
    for a in range(4):
        na = sdev[a] / snorm
        for b in range(4):
            nb_ = sdev[b] / snorm
            one = 1.0 if (a < 3 and b < 3) else 0.0
            idev = (1.0 if a == b else 0.0) * (0.5 if a == 3 else 1.0) - one / 3.0
            D[i, a, b] = Kb * one + c1 * idev + c2 * (na * nb_)
    return 1


@nb.jit(
    int64(
        _RO2,
        _RO1,
        _RO2,
        _RO1,
        _RO2,
        float64[:, ::1],
        float64[::1],
        float64[:, :, ::1],
        boolean[::1],
    ),
    **_opts,
)
def radial_return(De, prm, sigma_old, eps_p_old, d_eps, sigma, eps_p, D, plastic):
    """:func:`radial_return_row` at every point; returns the count of points not converged."""
    bad = 0
    for i in range(sigma_old.shape[0]):
        code = radial_return_row(De, prm, sigma_old, eps_p_old, d_eps, sigma, eps_p, D, i)
        plastic[i] = code != 0
        if code < 0:
            bad += 1
    return bad


@nb.jit(types.void(_RO4, _RO2, _RO3, float64[:, ::1]), **_opts)
def internal_force(B, dV, sigma, fe):
    """Element internal force vectors ``fe[e] = sum_q B[e, q]^T sigma[e, q] dV[e, q]``."""
    ne = B.shape[0]
    nq = B.shape[1]
    for e in range(ne):
        for k in range(8):
            fe[e, k] = 0.0
        for q in range(nq):
            for i in range(4):
                sd = sigma[e, q, i] * dV[e, q]
                for k in range(8):
                    fe[e, k] += B[e, q, i, k] * sd
    return


@nb.jit(types.void(_RO4, _RO2, _RO4, float64[:, :, ::1]), **_opts)
def stiffness(B, dV, D, ke):
    """Element tangent matrices ``ke[e] = sum_q B[e, q]^T D[e, q] B[e, q] dV[e, q]``."""
    ne = B.shape[0]
    nq = B.shape[1]
    db = np.empty((4, 8))
    for e in range(ne):
        for k in range(8):
            for m in range(8):
                ke[e, k, m] = 0.0
        for q in range(nq):
            dv = dV[e, q]
            for i in range(4):
                for m in range(8):
                    s = 0.0
                    for j in range(4):
                        s += D[e, q, i, j] * B[e, q, j, m]
                    db[i, m] = s * dv
            for k in range(8):
                for i in range(4):
                    bik = B[e, q, i, k]
                    for m in range(8):
                        ke[e, k, m] += bik * db[i, m]
    return


@nb.jit(types.void(_RO1, _RI1, float64[::1]), **_opts)
def scatter_add(values, pos, out):
    """``out[pos[j]] += values[j]`` for every ``j`` with ``pos[j] >= 0`` (``out`` not zeroed)."""
    for j in range(values.shape[0]):
        p = pos[j]
        if p >= 0:
            out[p] += values[j]
    return
