"""The iteration of the normal solver (Sec. 2.1).

Projections onto the load-controlled box, the preconditioned active-set conjugate gradient with
its FISTA fallback, and the volume-conserving lift. :mod:`halfspace_calib.contact.normal` describes the method; this module holds its steps.
"""

import numpy as np

from . import _kernels as _k

__all__ = ["project_box_sum", "volume_conserving_lift"]


def _restore_load(p, target, H):
    """Scale the sub-cap pressures so that ``sum(p) = target`` while keeping ``p <= H``.

    Returns ``(p_new, c)``: elements at the cap stay there, positive ones below it are scaled
    by ``c`` (those that would pass ``H`` are capped; :func:`_kernels.restore_load`). Falls back
    to the Euclidean projection :func:`project_box_sum` (``c = None``) when scaling cannot carry
    the load.
    """
    pmax = np.inf if H is None else float(H)
    q = np.array(p, dtype=float)  # a contiguous copy: the kernel works in place
    ok, c, _ = _k.restore_load(q.ravel(), float(target), pmax)
    if ok:
        return q, c
    return project_box_sum(p, target, H), None


def project_box_sum(y, target, H=None):
    """Euclidean projection of ``y`` onto ``{0 <= p <= H, sum(p) = target}``.

    The projection is ``clip(y + lam, 0, H)`` with the scalar ``lam`` solving the monotone,
    piecewise linear equation ``sum(clip(y + lam, 0, H)) = target``, found by safeguarded
    Newton steps (exact once the free set stops changing) inside a bisection bracket (the
    loop is the numba kernel :func:`_kernels.project_box_sum`).
    """
    y = np.asarray(y, dtype=float)
    n = y.size
    if H is not None and not target < n * H:
        raise ValueError(f"target must be < size * H = {n * H!r}, got {target!r}")
    out = np.empty(y.shape)
    _k.project_box_sum(
        np.ascontiguousarray(y).ravel(),
        float(target),
        np.inf if H is None else float(H),
        out.ravel(),
    )
    return out


def _shift(g_raw, p, H, free=None):
    """Gap offset ``h_max - u0`` that zeroes the mean gap over the free elements."""
    if free is None:
        free = (p > 0) & (p < (np.inf if H is None else H))
    if free.any():
        return -g_raw[free].mean()
    # no free element: every contact is at the cap; place u0 at the edge of the cap set
    on = p > 0
    return -g_raw[on].max() if on.any() else -g_raw.min()


def _residual_scale(h, p_mean, dx, E_star):
    s = float(np.std(h))
    return s if s > 0 else p_mean * dx / E_star


def _pk_box_cg(op, h, p_mean, H, p_init, tol, maxiter, refresh, scale, precondition):
    """Polonsky-Keer CG on the box ``[0, H]`` with load control; see the module docstring."""
    shape = h.shape
    n = h.size
    target = p_mean * n
    pmax = np.inf if H is None else float(H)
    hf = np.ascontiguousarray(h, dtype=float).ravel()
    if p_init is None:
        p = np.full(shape, p_mean)
    else:
        p, _ = _restore_load(np.clip(p_init, 0.0, pmax), target, H)
        p = np.ascontiguousarray(p)
    q = np.empty(shape)
    g = np.empty(shape)
    t = np.zeros(shape)
    ga = np.empty(shape) if precondition else None
    ph = op.forward(p)
    u = op.backward(ph)
    exact = True
    G_old = 1.0
    delta = 0.0
    since_refresh = 0
    converged = False
    res = np.inf
    nit = 0
    best, it_best, n_fista = np.inf, 0, _STALL
    res_prev = np.inf
    lipschitz = op.norm
    while True:
        pf, uf = p.ravel(), np.ascontiguousarray(u).ravel()
        sg, n_free = _k.free_gap_sum(uf, hf, pf, pmax)
        shift = -sg / n_free if n_free else _shift(u - h, p, H)
        viol, G = _k.gap_and_residual(uf, hf, pf, pmax, shift, g.ravel())
        res = float(np.sqrt(viol / n) / scale)
        if res < tol:
            if exact:
                converged = True
                break
            ph = op.forward(p)  # confirm with an exact displacement
            u = op.backward(ph)
            exact, since_refresh = True, 0
            continue
        if nit >= maxiter:
            break
        if res < 0.5 * best:
            best, it_best = res, nit
        elif nit - it_best >= _STALL:
            # no halving of the residual for _STALL iterations: take provably convergent
            # accelerated projected-gradient steps, then restart the CG from there
            k = min(n_fista, maxiter - nit)
            p = np.ascontiguousarray(_fista(op, h, p, target, H, lipschitz, k))
            nit += k
            n_fista *= 2
            ph = op.forward(p)
            u = op.backward(ph)
            exact, since_refresh, delta = True, 0, 0.0
            best, it_best = np.inf, nit
            continue
        nit += 1
        if precondition:
            # z = C^-1 g on the free and violating elements (Vollebregt 2014 style)
            _k.active_gap(g.ravel(), pf, pmax, ga.ravel())
            z = op.apply_inverse(ga)
            G = _k.dot_free(g.ravel(), z.ravel(), pf, pmax)
        else:
            z = g
        gt = _k.direction(z.ravel(), g.ravel(), pf, pmax, delta * G / G_old, t.ravel())
        G_old = G if G > 0 else 1.0
        th = op.forward(t)
        tKt = op.energy(th)
        tau = gt / tKt if tKt > 0 else 0.0
        tf, gf, zf, qf = t.ravel(), g.ravel(), z.ravel(), q.ravel()
        for _ in range(_BACKTRACK + 1):
            released, changed, s_free, m_free, n_cap = _k.step_project(
                pf, tf, gf, zf, tau, pmax, qf
            )
            rest = target - (pmax * n_cap if n_cap else 0.0)
            c = rest / s_free if (rest > 0 and s_free > 0) else 0.0
            if c > 0 and c * m_free < pmax:  # the usual case: one scaling pass
                _k.scale_free(qf, c, pmax)
                ok, passes = True, 1
                break
            ok, c, passes = _k.restore_load(qf, target, pmax)
            if ok:
                break
            # the step emptied the support below what the cap can carry: a shorter step
            # (still a descent step along t) instead of a projection that lifts every zero
            tau *= 0.5
        # Polonsky and Keer reset the conjugacy whenever an element leaves a bound; on a reload
        # the contact set shrinks by a few elements on most iterations, and those resets made
        # the solve preconditioned steepest descent (default scene 256^2, p_hist 600 MPa:
        # 22-36 iterations per reload). Reset only when the residual also grew: 21-25 there,
        # and no stall on the big first release of a reload's plastic set (never resetting
        # took 108-110 iterations on mnt-1 at 64^2, through the FISTA fallback)
        delta = 0.0 if (released and res > res_prev) else 1.0
        res_prev = res
        if not ok:
            q, c = project_box_sum(q, target, H), None
            changed = True
        elif passes > 1:
            changed = True
        since_refresh += 1
        if c is not None and not changed and since_refresh < refresh:
            # no projection or release: the spectrum follows the CG step (and the load
            # scaling, c = 1 up to roundoff) exactly
            ph -= tau * th
            ph *= c
            exact = False
        else:
            ph = op.forward(q)
            exact, since_refresh = True, 0
        u = op.backward(ph)
        p, q = q, p
    return p, u, g, nit, converged, res


_STALL = 50
#: halvings of a CG step whose load cannot be restored by scaling (then: projection)
_BACKTRACK = 30


def _fista(op, h, p, target, H, lipschitz, iters):
    """FISTA (Beck and Teboulle 2009) on ``1/2 p.Cp - p.h`` over the box and the load.

    Each step is a gradient step of length ``1 / lipschitz`` (the largest eigenvalue of ``C``
    is bounded by the largest modulus of its circulant spectrum) followed by the exact
    projection :func:`project_box_sum`; the objective converges at rate ``O(1/k^2)``.
    """
    x_old = p
    y = p
    tk = 1.0
    for _ in range(iters):
        x = project_box_sum(y - (op.apply(y) - h) / lipschitz, target, H)
        tk1 = 0.5 * (1.0 + np.sqrt(1.0 + 4.0 * tk * tk))
        y = x + ((tk - 1.0) / tk1) * (x - x_old)
        x_old, tk = x, tk1
    return x_old


def volume_conserving_lift(gap, volume):
    """Spread a plastically removed volume over the out-of-contact elements (Pullen, Williamson).

    The paper adds the volume "evenly on the element patches that are not in contact". Read
    literally, at high loads that lift exceeds the flattened plateau and pushes valleys through
    the tool. Here the lift is even but capped by each element's loaded gap (material flows into
    a valley until it meets the tool): ``lift_k = min(c, gap_k)`` with ``c`` such that
    ``sum(lift) = volume`` (water filling).

    Parameters
    ----------
    gap : ndarray
        Loaded gap per element (m), ``>= 0``; 0 on contact elements (they get no lift).
    volume : float
        Removed volume in element units (m, i.e. ``sum(u_pl)``).

    Returns
    -------
    lift : ndarray
        Height added per element (m).
    rest : float
        Volume that did not fit below the tool (``> 0`` only if every valley is filled).
    """
    g = np.asarray(gap, dtype=float)
    cap = float(g.sum())
    if volume >= cap:
        return g.copy(), float(volume - cap)
    gs = np.sort(g[g > 0].ravel())
    n = gs.size
    # filled(c) = sum(min(c, g_k)) is piecewise linear: find the segment holding the volume
    below = np.concatenate([[0.0], np.cumsum(gs)[:-1]])
    filled_at = below + gs * (n - np.arange(n))
    j = int(np.searchsorted(filled_at, volume))
    c = (volume - below[j]) / (n - j)
    return np.minimum(g, c), 0.0
