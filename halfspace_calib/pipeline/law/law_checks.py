"""What the calibrated law does at and below ``p_hist``: its drop there, its reload curves.

Issue 37. The half-space model's reload curve meets the first loading at ``p = p_hist`` and lies above
it below (the flattened surface keeps contact). The law is checked for both on a dense grid of
histories over the calibrated first-loading range (not only at the calibrated levels):

* ``max_jump_relative``: the largest drop of ``tau`` just below ``p_hist``,
  ``(tau_first(p_hist) - tau_reload(p_hist-)) / tau_first(p_hist)`` (0 by construction in the
  continuous variant);
* ``reload_below_first``: the largest ``alpha1(p) - alpha2(p; p_hist)`` over ``0 < p < p_hist``
  (0 when every reload curve lies at or above the first loading), with where it occurs, and
  ``calibrated_max``, the same over the histories from the lowest reload level on (below it the
  reload branch is extrapolated in ``p_hist``; the paper's Eq. 25 is kept within the tolerance
  there, :func:`~.fit.fit_reload`).

Both are reported in ``summary.json``; beyond :data:`JUMP_TOL` and :data:`DIP_TOL` a note says so.
"""

import numpy as np

from frictionlaw import alpha_first, alpha_reload, reload_jump, shear_limit

__all__ = ["JUMP_TOL", "DIP_TOL", "law_checks"]

#: the drop of tau at p_hist beyond which a note is written (relative to tau there)
JUMP_TOL = 0.005
#: how far (in alpha) a reload curve may lie below the first loading before a note is written
DIP_TOL = 0.01
_N_HIST = 48  # histories on the dense grid (geometric), besides the calibrated levels
_Q = np.concatenate(
    [np.geomspace(1e-3, 0.02, 16, endpoint=False), np.linspace(0.02, 1 - 1e-6, 200)]
)


def law_checks(params, curves=()):
    """``{"max_jump_relative", "jump_at_p_hist", "reload_below_first"}`` of the law ``params``.

    The histories: ``_N_HIST`` geometrically spaced over ``params.p_range`` (the calibrated
    first loading) and the calibrated reload levels of ``curves``; the pressures below each:
    216 fractions of ``p_hist`` from 0.001 to 1 (dense near ``p_hist``).
    """
    levels = sorted({float(c.p_hist) for c in curves})
    lo, hi = params.p_range or (min(levels), max(levels))
    ph = np.unique(np.concatenate([np.geomspace(lo, hi, _N_HIST), levels]))
    tau1 = np.atleast_1d(shear_limit(ph, 0.0, params))
    jump = np.atleast_1d(reload_jump(params, ph)) / np.where(tau1 > 0, tau1, 1.0)
    P = ph[:, None] * _Q[None, :]
    below = alpha_first(P, params) - alpha_reload(P, ph[:, None], params)
    i, j = np.unravel_index(int(np.argmax(below)), below.shape)
    k = int(np.argmax(jump))
    calibrated = ph >= (min(levels) if levels else lo)
    return {
        "max_jump_relative": max(float(jump[k]), 0.0),
        "jump_at_p_hist": float(ph[k]),
        "reload_below_first": {
            "max": max(float(below[i, j]), 0.0),
            "calibrated_max": max(float(np.max(below[calibrated])), 0.0),
            "p_hist": float(ph[i]),
            "p": float(P[i, j]),
            "tolerance": DIP_TOL,
            "p_hist_range": [float(lo), float(hi)],
            "n_p_hist": int(ph.size),
            "n_p": int(_Q.size),
        },
    }
