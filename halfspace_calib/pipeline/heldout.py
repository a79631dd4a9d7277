"""Acceptance of a calibration by measured error: each branch against the model, in and out of sample.

For each branch of the law the calibration reports the largest and the root-mean-square
``|alpha_law - alpha_model|``:

* **in sample**: on the computed points the fit saw;
* **held out**: each interior load level left out in turn, the branch refitted without it and
  its points predicted (Eq. 24: one pressure of the first loading; Eq. 25: one reload curve);
* **extrapolation**: the same for the top level, reported apart (the law beyond its data).

The reload branch's held-out maximum decides (:data:`HELDOUT_TOL`, ``Scene.heldout_tol``, the
CLI's ``--heldout-tol``): the branch's form is this project's choice, and what it must do is
predict the model between the calibrated levels.

The first loading is the paper's Eq. 24, two parameters whose form no calibration can change: its
errors are reported, with a note above the tolerance, and fail the run only at a gross miss
(:data:`GROSS_MISS` in sample, where a wrong input is likelier than a poor law). Measured on the
default calibrations of real pairs, Eq. 24 misses the model by up to 0.07 in sample (sur-3 and
mnt-1 against the synthetic tool; the bound ``alpha1 >= p / H`` costs part of it) while the
reload branch predicts unseen levels within 0.045 (``benchmarks/reload_law.py``). Its held-out
error is reported too, but where a curve rises steeply and saturates early (nearly conforming
scans: ``alpha`` from 0.6 to 0.95 between 10 and 50 MPa), the one pressure left out is most of
what fixes it, so it measures the sampling of the sweep rather than the law (0.084 held out
against 0.003 in sample).

R^2 is not a judge: a curve that saturates early (full contact from low pressure, a valid
physical result) has almost no variance for it to divide by.
"""

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from frictionlaw import FrictionParams, alpha_first, alpha_reload

from . import fit as _fit
from .reload_table import (
    S2_BOUNDS,
    cross_validation,
    fit_reload_table,
    level_grid,
    table_alpha,
    table_of,
)

__all__ = [
    "HELDOUT_TOL",
    "GROSS_MISS",
    "FULL_CONTACT_ALPHA",
    "FULL_CONTACT_P",
    "BranchErrors",
    "first_loading_errors",
    "reload_errors",
    "reload_table_errors",
    "full_contact_pressure",
    "reload_forms",
    "reload_law",
    "choose_reload_form",
]

#: default tolerance on the reload branch's held-out max |d alpha| (an option)
HELDOUT_TOL = 0.05
#: a branch that misses the model by this much in alpha has collapsed (most likely a wrong input:
#: a size or unit typed wrong), rather than fitted poorly: Eq. 24 fails the run only there
GROSS_MISS = 0.15
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
        ``"first_loading"``, ``"reload"`` or ``"reload_paper"`` (the paper's Eq. 25 beside a
        tabulated calibration).
    form : str
        ``"eq24"``, ``"paper"`` or ``"tabulated"``.
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

    @property
    def decides_heldout(self):
        """The held-out error decides (reload); for Eq. 24 the in-sample one (see the module)."""
        return self.branch != "first_loading" and math.isfinite(self.heldout_max)

    def limit(self, tol):
        """The error beyond which the branch fails the run: ``tol``, for Eq. 24 a gross miss."""
        return tol if self.branch != "first_loading" else max(tol, GROSS_MISS)

    def exceeds(self, tol):
        """The deciding error (:attr:`decides_heldout`) exceeds :meth:`limit`."""
        worst = self.heldout_max if self.decides_heldout else self.in_sample_max
        return worst > self.limit(tol)

    def warning(self, tol, name):
        """A note when an error that does not fail the run exceeds ``tol``, else ``""``."""
        if self.branch != "first_loading" or self.exceeds(tol):
            return ""
        held = self.heldout_max if math.isfinite(self.heldout_max) else 0.0
        if max(self.in_sample_max, held) <= tol:
            return ""
        text = (
            f"{name}: max |d alpha| = {self.in_sample_max:.3g} on the computed points, "
            f"{held:.3g} held out, beyond {tol:g}: the paper's Eq. 24 (two parameters) does not "
            "follow this first loading closer; the run fails only at a miss of "
            f"{GROSS_MISS:g} (a wrong input)"
        )
        if held > 2.0 * max(self.in_sample_max, 1e-12):
            text += (
                "; where the curve rises steeply few pressures fix it, so the held-out error "
                "there measures the sweep (add pressures, --pressures)"
            )
        return text

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
            f"{self.limit(tol):g}: the fit has collapsed"
        )

    def summary(self):
        """JSON-ready record."""
        ext = self.extrapolation
        return {
            "form": self.form,
            "in_sample_max": self.in_sample_max,
            "in_sample_rms": self.in_sample_rms,
            "heldout_max": _finite(self.heldout_max),
            "heldout_rms": _finite(self.heldout_rms),
            "heldout": [{"level": lv, "max_abs": e} for lv, e in self.heldout],
            "extrapolation": None if ext is None else {"level": ext[0], "max_abs": ext[1]},
            "n_points": self.n_points,
        }


def _finite(v):
    return float(v) if math.isfinite(v) else None


def _errors(branch, form, insample, held, ext):
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
        extrapolation=None if ext is None else (float(ext[0]), float(np.max(np.abs(ext[1])))),
        n_points=int(ins.size),
    )


def _law(H, C1, n1, C2=1.0, n2=1.0, continuous=False):
    return FrictionParams(
        m=1.0, sigma_y=H, H=H, C1=C1, n1=n1, C2=C2, n2=n2, continuous_reload=continuous
    )


def first_loading_errors(p, alpha, H, first, floor_to=None):
    """:class:`BranchErrors` of Eq. 24: each interior pressure left out, refitted, predicted."""
    p, alpha = np.asarray(p, float), np.asarray(alpha, float)
    order = np.argsort(p)
    p, alpha = p[order], alpha[order]

    def predict(i):
        keep = np.arange(p.size) != i
        f = _fit.fit_first_loading(p[keep], alpha[keep], H, floor_to=floor_to)
        return np.atleast_1d(alpha_first(p[i], _law(H, f.C1, f.n1)) - alpha[i])

    held = [(p[i], predict(i)) for i in range(1, p.size - 1)] if p.size >= 4 else []
    ext = (p[-1], predict(p.size - 1)) if p.size >= 4 else None
    return _errors("first_loading", "eq24", first.residuals, held, ext)


def reload_errors(curves, H, C1, n1, reload, continuous=False, branch="reload"):
    """:class:`BranchErrors` of the paper's Eq. 25: each interior curve left out and predicted."""
    cs = sorted(curves, key=lambda c: c.p_hist)

    def predict(j):
        rest = [c for i, c in enumerate(cs) if i != j]
        f = _fit.fit_reload(rest, H, C1, n1, continuous=continuous)
        law = _law(H, C1, n1, f.C2, f.n2, continuous)
        return alpha_reload(cs[j].p, cs[j].p_hist, law) - cs[j].alpha

    held = [(cs[j].p_hist, predict(j)) for j in range(1, len(cs) - 1)] if len(cs) >= 3 else []
    ext = (cs[-1].p_hist, predict(len(cs) - 1)) if len(cs) >= 2 else None
    return _errors(branch, "paper", reload.residuals, held, ext)


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

    def predict(j):
        keep = np.arange(n) != j
        rest = [c for c, k in zip(cs, keep, strict=True) if k]

        def objective(s2):
            X, sse = fits[s2]
            cv = cross_validation(rest, X[keep], s2, f.H, f.C1, f.n1, f.continuous)
            return float(sse[keep].sum()) + cv

        s2 = min(grid, key=objective)
        table = table_of(rest, fits[s2][0][keep], s2)
        c = cs[j]
        return table_alpha(c.p, c.p_hist, table, f.H, f.C1, f.n1, f.continuous) - c.alpha

    held = [(cs[j].p_hist, predict(j)) for j in range(1, n - 1)] if n >= 3 else []
    ext = (cs[-1].p_hist, predict(n - 1)) if n >= 2 else None
    return _errors("reload", "tabulated", f.residuals, held, ext)


def reload_law(scene, p, alpha, curves, first, reload):
    """``(form, table fit or None, errors)``: the reload form a file runs and every branch's errors.

    ``p, alpha``: the first loading; ``curves``: one reload curve per level. ``scene.reload_form``:
    ``"paper"`` fits the paper's Eq. 25 only; ``"tabulated"`` also the table and runs it;
    ``"auto"`` (the default) fits both and runs the one whose held-out error is smaller
    (:func:`choose_reload_form`). Used by a calibration and by the pooled law of several samples.
    """
    floor_to = None if scene.alpha_floor is None else scene.alpha_floor * scene.H
    errors = {"first_loading": first_loading_errors(p, alpha, scene.H, first, floor_to)}
    table, form, more = reload_forms(scene, curves, first, reload)
    errors.update(more)
    return form, table, errors


def reload_forms(scene, curves, first, reload):
    """The reload forms of ``scene.reload_form`` fitted to ``curves``: ``(table, form, errors)``.

    ``errors["reload"]`` is the branch the file runs; the other form's, when fitted, is
    ``errors["reload_paper"]`` or ``errors["reload_tabulated"]``.
    """
    cont = scene.continuous_reload
    paper = reload_errors(curves, scene.H, first.C1, first.n1, reload, cont)
    if scene.reload_form == "paper":
        return None, "paper", {"reload": paper}
    table = fit_reload_table(curves, scene.H, first.C1, first.n1, continuous=cont)
    tab = reload_table_errors(table)
    form = "tabulated" if scene.reload_form == "tabulated" else choose_reload_form(tab, paper)
    if form == "tabulated":
        return (
            table,
            form,
            {"reload": tab, "reload_paper": dataclasses.replace(paper, branch="reload_paper")},
        )
    return (
        table,
        form,
        {
            "reload": paper,
            "reload_tabulated": dataclasses.replace(tab, branch="reload_tabulated"),
        },
    )


def choose_reload_form(tabulated, paper):
    """``"tabulated"`` or ``"paper"``: the form whose held-out max ``|d alpha|`` is smaller.

    In sample where fewer than three levels leave nothing to hold out; the tabulated form on a
    tie. Where the reload curves are the first loading's own (an elastic, nearly conforming
    contact: ``alpha`` a function of ``p`` alone), the paper's form knows it (``x2`` linear in
    ``p``) and the table does not: the patches of mnt-1 against itself held out 0.063 tabulated.
    """

    def worst(e):
        return e.heldout_max if math.isfinite(e.heldout_max) else e.in_sample_max

    return "paper" if worst(paper) < worst(tabulated) else "tabulated"


def full_contact_pressure(p, alpha, H):
    """The lowest first-loading pressure (Pa) with ``alpha >= 0.95`` if it is ``<= 0.1 H``, else None.

    Such a pair is in full contact from low pressure: its law is Tresca's from there on, a
    valid result that is reported, not failed.
    """
    p, alpha = np.asarray(p, float), np.asarray(alpha, float)
    hit = p[(alpha >= FULL_CONTACT_ALPHA) & (p <= FULL_CONTACT_P * H)]
    return float(hit.min()) if hit.size else None
