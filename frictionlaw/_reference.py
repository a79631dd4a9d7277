"""Pure-NumPy reference of the runtime law: the test oracle and the NumPy baseline.

Written independently of :mod:`frictionlaw._kernels` (whole-array operations,
``np.errstate`` instead of branches, a different grouping of the terms), so
that agreement between the two is evidence and not an echo.
"""

import numpy as np

from ._codes import Q_START

__all__ = [
    "ln_smooth_min",
    "smooth_min",
    "alpha_first",
    "alpha_first_tabulated",
    "alpha_reload",
    "alpha_reload_tabulated",
    "sbmf_shear",
    "traction_update",
]


def ln_smooth_min(lnx, n):
    """``ln g`` of ``g(x) = tanh(x**n) ** (1/n)`` from ``ln x`` (any value, ``+-inf`` included).

    In logs throughout, so that no under- or overflowing ``x`` or ``g`` is ever formed.
    """
    lnx, n = np.broadcast_arrays(np.asarray(lnx, float), np.asarray(n, float))
    with np.errstate(over="ignore", divide="ignore", invalid="ignore", under="ignore"):
        lny = np.minimum(n * lnx, 700.0)
        y = np.exp(lny)
        # ln tanh(y) = ln y + ln(tanh(y)/y); the last term by its series near 0
        small = y < 1e-3
        ratio_log = np.where(
            small,
            -(y**2) / 3.0 + 7.0 * y**4 / 90.0 - 62.0 * y**6 / 2835.0,
            np.log(np.tanh(y) / np.where(small, 1.0, y)),
        )
        ln_tanh = np.where(y < 1.0, lny + ratio_log, np.log(np.tanh(y)))
        return ln_tanh / n


def _ln_x(p, C, H):
    """``ln(p C / H)`` as a sum of logs (``p > 0``)."""
    with np.errstate(divide="ignore"):
        return np.log(p) + (np.log(C) - np.log(H))


def smooth_min(x, n):
    """``g(x) = tanh(x**n) ** (1/n)`` for ``x >= 0`` in logs; 0 where ``x <= 0``."""
    x, n = np.broadcast_arrays(np.asarray(x, float), np.asarray(n, float))
    out = np.zeros(x.shape)
    pos = x > 0
    with np.errstate(under="ignore"):
        out[pos] = np.exp(ln_smooth_min(np.log(x[pos]), n[pos]))
    return out


def alpha_first(p, C1, n1, H):
    """Eq. 24's contact ratio ``alpha1(p)``."""
    p = np.asarray(p, float)
    out = np.zeros(p.shape)
    pos = p > 0
    with np.errstate(under="ignore"):
        out[pos] = np.exp(ln_smooth_min(_ln_x(p[pos], C1, H), n1))
    return out


def alpha_first_tabulated(p, p_knots, alpha_knots, slopes, H):
    """The tabulated first loading ``alpha1(p)`` with the knot slopes given (``dv/du``).

    ``v = ln alpha`` over ``u = ln(p / H)``: the cubic through the knots in its power form
    ``v0 + t (h d0 + t (3 dv - h (2 d0 + d1) + t (h (d0 + d1) - 2 dv)))``, ``dv = v1 - v0``;
    below the first knot ``alpha_0 p / p_0``; above the last ``alpha_{J-1} (p / p_{J-1}) **
    d_{J-1}``, at most 1. 0 for ``p <= 0``. (The tests take the slopes from SciPy's
    ``PchipInterpolator``.)
    """
    p = np.asarray(p, float)
    pk = np.asarray(p_knots, float)
    uk = np.log(pk) - np.log(H)
    vk = np.log(np.asarray(alpha_knots, float))
    dk = np.asarray(slopes, float)
    out = np.zeros(p.shape)
    pos = p > 0
    with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
        u = np.log(p[pos]) - np.log(H)
        j = np.clip(np.searchsorted(uk, u) - 1, 0, uk.size - 2)
        h = uk[j + 1] - uk[j]
        t = (u - uk[j]) / h
        dv = vk[j + 1] - vk[j]
        c2 = 3.0 * dv - h * (2.0 * dk[j] + dk[j + 1])
        c3 = h * (dk[j] + dk[j + 1]) - 2.0 * dv
        inner = vk[j] + t * (h * dk[j] + t * (c2 + t * c3))
        above = vk[-1] + np.where(dk[-1] > 0, dk[-1] * (u - uk[-1]), 0.0)
        ln_a = np.where(u <= uk[0], vk[0] + (u - uk[0]), np.where(u >= uk[-1], above, inner))
        out[pos] = np.exp(np.minimum(ln_a, 0.0))
    return out


def alpha_reload(p, p_hist, C1, n1, C2, n2, H, continuous=False, ln_a1h=None):
    """Eq. 25's contact ratio ``alpha2(p; p_hist)`` (optionally normalised at ``p_hist``).

    The continuous variant, extrapolated to ``p > p_hist``, is capped at a contact ratio of 1.
    ``ln_a1h``: ``ln alpha1(p_hist)`` of another first-loading form (broadcast like ``p``);
    ``None``: Eq. 24's with ``C1, n1``.
    """
    p, p_hist = np.broadcast_arrays(np.asarray(p, float), np.asarray(p_hist, float))
    out = np.zeros(p.shape)
    ok = (p > 0) & (p_hist > 0)
    ph = p_hist[ok]
    ln_a1h = _ln_a1h(ph, C1, n1, H, ln_a1h, ok, p.shape)
    ln_val = ln_a1h + ln_smooth_min(_ln_x(p[ok], C2, H) - ln_a1h, n2)
    if continuous:
        ln_val = ln_val - ln_smooth_min(_ln_x(ph, C2, H) - ln_a1h, n2)
    with np.errstate(under="ignore"):
        out[ok] = np.minimum(np.exp(ln_val), 1.0)
    return out


def _ln_a1h(ph, C1, n1, H, given, ok, shape):
    if given is None:
        return ln_smooth_min(_ln_x(ph, C1, H), n1)
    return np.broadcast_to(np.asarray(given, float), shape)[ok]


def alpha_reload_tabulated(p, p_hist, C1, n1, H, C2, n2, s2, continuous=False, ln_a1h=None):
    """The tabulated form's ``alpha2(p; p_hist)`` with ``C2``, ``n2`` given per point.

    ``C2`` and ``n2`` are the table's values at each ``p_hist`` (the tests take them from
    SciPy's ``PchipInterpolator``); ``x2 = (p_hist C2 / (H a1h)) r(p / p_hist)``, ``r(q) =
    q**s2`` and below ``q0 = Q_START`` the quadratic start ``q0**s2 (t (2 - s2) + t**2 (s2 - 1))``,
    ``t = q / q0``. Capped
    at a contact ratio of 1, 0 where ``p <= 0`` or ``p_hist <= 0``. ``ln_a1h`` as in
    :func:`alpha_reload`.
    """
    p, p_hist, C2, n2 = np.broadcast_arrays(*(np.asarray(v, float) for v in (p, p_hist, C2, n2)))
    out = np.zeros(p.shape)
    ok = (p > 0) & (p_hist > 0)
    ph, c2, nn = p_hist[ok], C2[ok], n2[ok]
    ln_a1h = _ln_a1h(ph, C1, n1, H, ln_a1h, ok, p.shape)
    ln_x2h = _ln_x(ph, c2, H) - ln_a1h
    # x2 = x2h r(q): q**s2, below q0 the quadratic q0**s2 (t (2 - s2) + t**2 (s2 - 1)), t = q/q0
    lnq = np.log(p[ok]) - np.log(ph)
    q0 = Q_START
    t = np.exp(np.minimum(lnq - np.log(q0), 0.0))
    with np.errstate(divide="ignore"):
        ln_r = np.where(
            lnq < np.log(q0),
            s2 * np.log(q0) + np.log(t * ((2.0 - s2) + (s2 - 1.0) * t)),
            s2 * lnq,
        )
    ln_val = ln_a1h + ln_smooth_min(ln_x2h + ln_r, nn)
    if continuous:
        ln_val = ln_val - ln_smooth_min(ln_x2h, nn)
    with np.errstate(under="ignore"):
        out[ok] = np.minimum(np.exp(ln_val), 1.0)
    return out


def sbmf_shear(p, p_hist, tau_max, C1, n1, C2, n2, H, continuous=False):
    """Shear limit ``tau`` of Eqs. 24-25 with branch selection on ``p < p_hist``."""
    p, p_hist = np.broadcast_arrays(np.asarray(p, float), np.asarray(p_hist, float))
    first = alpha_first(p, C1, n1, H)
    reload = alpha_reload(p, p_hist, C1, n1, C2, n2, H, continuous)
    return tau_max * np.where(p < p_hist, reload, first)


def traction_update(tau, du, t_old, k_t):
    """Reference return map: returns ``(t_new, status)`` with 0 open, 1 stick, 2 slip.

    ``tau`` is the shear limit per node (``nan`` marks an open node). Stick needs
    ``0 < |t_tr| <= tau``; ``|t_tr|`` by ``hypot``; a trial that overflows takes its direction
    from ``t_old / s + (k_t / s) du``, ``s = max(k_t, |t_old|)``.
    """
    du = np.asarray(du, float)
    t_old = np.asarray(t_old, float)
    k_t = np.asarray(k_t, float)
    with np.errstate(over="ignore", invalid="ignore"):
        t_tr = t_old + k_t[:, None] * du
    over = ~np.isfinite(t_tr).all(axis=1)
    w = t_tr.copy()
    s = np.maximum(k_t, np.abs(t_old).max(axis=1))[over][:, None]
    w[over] = t_old[over] / s + (k_t[over][:, None] / s) * du[over]
    big = np.abs(w).max(axis=1)  # |t_tr| = big * unit, hypot of the row scaled by its largest
    unit = np.hypot.reduce(np.abs(w) / np.where(big > 0, big, 1.0)[:, None], axis=1)
    open_ = np.isnan(tau)
    tau0 = np.nan_to_num(tau)
    with np.errstate(divide="ignore"):
        stick = ~open_ & ~over & (big <= tau0 / np.where(unit > 0, unit, 1.0)) & (tau0 > 0)
    slip = ~open_ & ~stick
    t_new = np.zeros_like(t_tr)
    t_new[stick] = t_tr[stick]
    turn = slip & (big > 0)
    t_new[turn] = w[turn] / big[turn][:, None] / unit[turn][:, None] * tau0[turn][:, None]
    status = np.where(open_, 0, np.where(stick, 1, 2))
    return t_new, status
