"""Pure-NumPy reference of the runtime law: the test oracle and the NumPy baseline.

Written independently of :mod:`frictionlaw._kernels` (whole-array operations,
``np.errstate`` instead of branches, a different grouping of the terms), so
that agreement between the two is evidence and not an echo.
"""

import numpy as np

__all__ = ["smooth_min", "alpha_first", "alpha_reload", "sbmf_shear", "traction_update"]


def smooth_min(x, n):
    """``g(x) = tanh(x**n) ** (1/n)`` for ``x >= 0`` in logs; 0 where ``x <= 0``."""
    x, n = np.broadcast_arrays(np.asarray(x, float), np.asarray(n, float))
    out = np.zeros(x.shape)
    pos = x > 0
    xp, npos = x[pos], n[pos]
    with np.errstate(over="ignore", divide="ignore", invalid="ignore", under="ignore"):
        lny = np.minimum(npos * np.log(xp), 700.0)
        y = np.exp(lny)
        # ln tanh(y) = ln y + ln(tanh(y)/y); the last term by its series near 0
        small = y < 1e-3
        ratio_log = np.where(
            small,
            -(y**2) / 3.0 + 7.0 * y**4 / 90.0 - 62.0 * y**6 / 2835.0,
            np.log(np.tanh(y) / np.where(small, 1.0, y)),
        )
        ln_tanh = np.where(y < 1.0, lny + ratio_log, np.log(np.tanh(y)))
        out[pos] = np.exp(ln_tanh / npos)
    return out


def alpha_first(p, C1, n1, H):
    """Eq. 24's contact ratio ``alpha1(p)``."""
    return smooth_min(np.asarray(p, float) * C1 / H, n1)


def alpha_reload(p, p_hist, C1, n1, C2, n2, H, continuous=False):
    """Eq. 25's contact ratio ``alpha2(p; p_hist)`` (optionally normalised at ``p_hist``)."""
    p, p_hist = np.broadcast_arrays(np.asarray(p, float), np.asarray(p_hist, float))
    a1h = alpha_first(p_hist, C1, n1, H)
    out = np.zeros(p.shape)
    ok = (p > 0) & (a1h > 0)
    with np.errstate(over="ignore"):  # x2 = inf is a valid argument of smooth_min (g = 1)
        x2 = p[ok] * C2 / (H * a1h[ok])
        val = a1h[ok] * smooth_min(x2, n2)
        if continuous:
            val = val / smooth_min(p_hist[ok] * C2 / (H * a1h[ok]), n2)
    out[ok] = val
    return out


def sbmf_shear(p, p_hist, tau_max, C1, n1, C2, n2, H, continuous=False):
    """Shear limit ``tau`` of Eqs. 24-25 with branch selection on ``p < p_hist``."""
    p, p_hist = np.broadcast_arrays(np.asarray(p, float), np.asarray(p_hist, float))
    first = alpha_first(p, C1, n1, H)
    reload = alpha_reload(p, p_hist, C1, n1, C2, n2, H, continuous)
    return tau_max * np.where(p < p_hist, reload, first)


def traction_update(tau, du, t_old, k_t):
    """Reference return map: returns ``(t_new, status)`` with 0 open, 1 stick, 2 slip.

    ``tau`` is the shear limit per node (``nan`` marks an open node).
    """
    du = np.asarray(du, float)
    t_old = np.asarray(t_old, float)
    t_tr = t_old + np.asarray(k_t, float)[:, None] * du
    norm = np.linalg.norm(t_tr, axis=1)
    open_ = np.isnan(tau)
    stick = ~open_ & (norm <= np.nan_to_num(tau))
    slip = ~open_ & ~stick
    t_new = np.zeros_like(t_tr)
    t_new[stick] = t_tr[stick]
    t_new[slip] = t_tr[slip] * (tau[slip] / norm[slip])[:, None]
    status = np.where(open_, 0, np.where(stick, 1, 2))
    return t_new, status
