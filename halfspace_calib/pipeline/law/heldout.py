"""Acceptance of a calibration by measured error: each branch against the model, out of sample.

For each branch of the law the calibration reports the largest and the root-mean-square
``|alpha_law - alpha_model|``:

* **in sample**: on the computed points the fit saw;
* **held out**: each interior load level left out in turn, the branch refitted without it and
  its points predicted (first loading: the points at one pressure; reload: one reload curve);
* **extrapolation**: the same for the top level and for the lowest (the law beyond its data),
  reported apart.

One acceptance for both branches (issue 37): the held-out maximum of the form each branch runs
decides (:data:`HELDOUT_TOL`, ``Scene.heldout_tol``, the CLI's ``--heldout-tol``; in sample
where fewer levels leave nothing interior to hold out). Each branch's form is this project's
choice (:mod:`.forms`), and what it must do is predict the model between the calibrated levels;
the extrapolations are reported, not decided.

R^2 is not a judge: a curve that saturates early (full contact from low pressure, a valid
physical result) has almost no variance for it to divide by.
"""

import math
from dataclasses import dataclass

import numpy as np

from frictionlaw import alpha_first, alpha_reload

from . import fit as _fit
from .reload_table import S2_BOUNDS, cross_validation, level_grid, table_alpha, table_of

__all__ = [
    "HELDOUT_TOL",
    "FULL_CONTACT_ALPHA",
    "FULL_CONTACT_P",
    "BranchErrors",
    "level_errors",
    "first_loading_errors",
    "reload_errors",
    "reload_table_errors",
    "full_contact_pressure",
]

#: default tolerance on each branch's held-out max |d alpha| (an option)
HELDOUT_TOL = 0.05
#: a pair is "in full contact from low pressure" when alpha >= FULL_CONTACT_ALPHA at a first-loading
#: pressure p <= FULL_CONTACT_P H: reported, not failed (the law is then Tresca from low pressure)
FULL_CONTACT_ALPHA = 0.95
FULL_CONTACT_P = 0.1
_S2_STEPS = (-0.1, -0.05, 0.0, 0.05, 0.1)  # the held-out refits' s2, about the full fit's


@dataclass(frozen=True)
class BranchErrors:
    """Measured ``|alpha_law - alpha_model|`` of one branch.

    Attributes
    ----------
    branch : str
        ``"first_loading"`` or ``"reload"`` (the form that runs), or ``"<branch>_<form>"`` (a
        form fitted beside it: ``"reload_paper"``, ``"first_loading_eq24"``, ...).
    form : str
        The form (:mod:`.forms`): ``"eq24"``, ``"tabulated"``, ``"paper"``.
    in_sample_max, in_sample_rms : float
        On the points the fit saw.
    heldout : tuple of (float, float)
        ``(level, max |d alpha|)`` for each interior level left out (level: the pressure for
        the first loading, ``p_hist`` for a reload curve, Pa).
    heldout_max, heldout_rms : float
        Over all held-out points (``nan`` with fewer than 3 levels: nothing interior).
    extrapolation : tuple of (float, float) or None
        ``(top level, max |d alpha|)`` predicted from the levels below it.
    n_points : int
        Points in sample.
    extrapolation_below : tuple of (float, float) or None
        ``(lowest level, max |d alpha|)`` predicted from the levels above it.
    """

    branch: str
    form: str
    in_sample_max: float
    in_sample_rms: float
    heldout: tuple
    heldout_max: float
    heldout_rms: float
    extrapolation: tuple | None
    n_points: int
    extrapolation_below: tuple | None = None

    @property
    def decides_heldout(self):
        """The held-out error decides (in sample without interior levels to hold out)."""
        return math.isfinite(self.heldout_max)

    @property
    def deciding(self):
        """The error the acceptance judges: held out, else in sample."""
        return self.heldout_max if self.decides_heldout else self.in_sample_max

    def exceeds(self, tol):
        """The deciding error exceeds ``tol``."""
        return self.deciding > tol

    def problem(self, tol, name):
        """The failure sentence if :meth:`exceeds`, else ``""``."""
        if not self.exceeds(tol):
            return ""
        if self.decides_heldout:
            lv = max(self.heldout, key=lambda t: t[1])[0]
            return (
                f"{name}: held-out max |d alpha| = {self.heldout_max:.3g} (level {lv / 1e6:g} MPa "
                f"left out and predicted) exceeds the tolerance {tol:g}"
            )
        return (
            f"{name}: max |d alpha| = {self.in_sample_max:.3g} on the computed points exceeds "
            f"the tolerance {tol:g} (too few levels to hold one out)"
        )

    def summary(self):
        """JSON-ready record."""
        ext, low = self.extrapolation, self.extrapolation_below
        return {
            "form": self.form,
            "in_sample_max": self.in_sample_max,
            "in_sample_rms": self.in_sample_rms,
            "heldout_max": _finite(self.heldout_max),
            "heldout_rms": _finite(self.heldout_rms),
            "heldout": [{"level": lv, "max_abs": e} for lv, e in self.heldout],
            "extrapolation": None if ext is None else {"level": ext[0], "max_abs": ext[1]},
            "extrapolation_below": None if low is None else {"level": low[0], "max_abs": low[1]},
            "n_points": self.n_points,
        }


def _finite(v):
    return float(v) if math.isfinite(v) else None


def _max(e):
    return (float(e[0]), float(np.max(np.abs(e[1])))) if e is not None else None


def _errors(branch, form, insample, held, ext, below=None):
    ins = np.abs(np.asarray(insample, float))
    pts = np.concatenate([np.abs(e) for _, e in held]) if held else np.zeros(0)
    return BranchErrors(
        branch=branch,
        form=form,
        in_sample_max=float(ins.max()) if ins.size else 0.0,
        in_sample_rms=float(np.sqrt(np.mean(ins**2))) if ins.size else 0.0,
        heldout=tuple((float(lv), float(np.max(np.abs(e)))) for lv, e in held),
        heldout_max=float(pts.max()) if pts.size else math.nan,
        heldout_rms=float(np.sqrt(np.mean(pts**2))) if pts.size else math.nan,
        extrapolation=_max(ext),
        n_points=int(ins.size),
        extrapolation_below=_max(below),
    )


def level_errors(p, alpha, residuals, refit_predict, form, branch="first_loading"):
    """:class:`BranchErrors` of a first-loading form: each load level left out and predicted.

    ``p, alpha``: the points (a level is a distinct pressure: the points of several samples at
    one pressure are left out together); ``residuals``: the fit's in sample;
    ``refit_predict(keep, p_out)``: the form refitted on the points ``keep`` (a mask), its
    ``alpha`` at ``p_out``. Interior levels are held out with 4 levels or more; the top and the
    lowest are the extrapolations.
    """
    p, alpha = np.asarray(p, float), np.asarray(alpha, float)
    levels = np.unique(p)

    def predict(lv):
        out = p == lv
        return np.atleast_1d(refit_predict(~out, p[out])) - alpha[out]

    if levels.size < 4:
        return _errors(branch, form, residuals, [], None)
    held = [(lv, predict(lv)) for lv in levels[1:-1]]
    ext = (levels[-1], predict(levels[-1]))
    below = (levels[0], predict(levels[0]))
    return _errors(branch, form, residuals, held, ext, below)


def first_loading_errors(p, alpha, H, first, floor_to=None):
    """:class:`BranchErrors` of Eq. 24: each interior pressure left out, refitted, predicted."""
    p, alpha = np.asarray(p, float), np.asarray(alpha, float)

    def refit_predict(keep, p_out):
        f = _fit.fit_first_loading(p[keep], alpha[keep], H, floor_to=floor_to)
        return alpha_first(p_out, _fit._law(H, f.C1, f.n1))

    return level_errors(p, alpha, first.residuals, refit_predict, "eq24")


def reload_errors(
    curves, H, C1, n1, reload, continuous=False, branch="reload", first=None, dip_range=None
):
    """:class:`BranchErrors` of the paper's Eq. 25: each interior curve left out and predicted.

    ``first``: the first-loading form that runs (``None``: Eq. 24 with ``C1, n1``);
    ``dip_range``: the fit's constraint on its curves below first loading, as the fit's own
    (:func:`~.fit.fit_reload`).
    """
    cs = sorted(curves, key=lambda c: c.p_hist)

    def predict(j):
        rest = [c for i, c in enumerate(cs) if i != j]
        f = _fit.fit_reload(
            rest, H, C1, n1, continuous=continuous, first=first, dip_range=dip_range
        )
        law = _fit._law(H, C1, n1, f.C2, f.n2, continuous, first)
        return alpha_reload(cs[j].p, cs[j].p_hist, law) - cs[j].alpha

    n = len(cs)
    held = [(cs[j].p_hist, predict(j)) for j in range(1, n - 1)] if n >= 3 else []
    # the extrapolation is reported only where the other curves hold the fit's 3 points (two
    # histories of two reloads each, as adaptive levels in full contact leave: not an error)
    ext = (cs[-1].p_hist, predict(n - 1)) if n >= 2 and _points(cs[:-1]) >= 3 else None
    below = (cs[0].p_hist, predict(0)) if n >= 3 else None
    return _errors(branch, "paper", reload.residuals, held, ext, below)


def _points(curves):
    return sum(np.asarray(c.p).size for c in curves)


def reload_table_errors(table_fit):
    """:class:`BranchErrors` of the tabulated form: each interior level left out of the table.

    Without the level left out, ``s2`` is chosen again as the fit chooses it (the levels' squared
    residuals plus the cross-validation among them), over a grid of step 0.05 within 0.1 of the
    full fit's value; each level's own fit at a given ``s2`` does not depend on the level left
    out, so one pass over the grid serves all (:func:`~.reload_table.level_grid`). The level left
    out then shapes nothing of its prediction.
    """
    f = table_fit
    cs = list(f.curves)
    n = len(cs)
    grid = sorted({float(np.clip(f.s2 + d, *S2_BOUNDS)) for d in _S2_STEPS})
    fits = level_grid(f, grid) if n >= 2 else {}
    args = (f.H, f.C1, f.n1, f.continuous, f.first)

    def predict(j):
        keep = np.arange(n) != j
        rest = [c for c, k in zip(cs, keep, strict=True) if k]

        def objective(s2):
            X, sse = fits[s2]
            return float(sse[keep].sum()) + cross_validation(rest, X[keep], s2, *args)

        s2 = min(grid, key=objective)
        table = table_of(rest, fits[s2][0][keep], s2)
        c = cs[j]
        return table_alpha(c.p, c.p_hist, table, *args) - c.alpha

    held = [(cs[j].p_hist, predict(j)) for j in range(1, n - 1)] if n >= 3 else []
    ext = (cs[-1].p_hist, predict(n - 1)) if n >= 2 else None
    below = (cs[0].p_hist, predict(0)) if n >= 3 else None
    return _errors("reload", "tabulated", f.residuals, held, ext, below)


def full_contact_pressure(p, alpha, H):
    """The lowest first-loading pressure (Pa) with ``alpha >= 0.95`` if it is ``<= 0.1 H``, else None.

    Such a pair is in full contact from low pressure: its law is Tresca's from there on, a
    valid result that is reported, not failed.
    """
    p, alpha = np.asarray(p, float), np.asarray(alpha, float)
    hit = p[(alpha >= FULL_CONTACT_ALPHA) & (p <= FULL_CONTACT_P * H)]
    return float(hit.min()) if hit.size else None
