"""The forms of the law's two branches as records: the calibration side.

Each form of each branch is one :class:`FormCalibration`: how it is fitted to the computed
curves, how it predicts them, its held-out refit (:mod:`.heldout`: each interior level left out,
refitted, predicted) and the data it hands the runtime. Its runtime side (the data's type, the
coefficient block the kernels run, the small-pressure slope, the export template) is the
record of the same name in :mod:`frictionlaw.forms`: :attr:`FormCalibration.runtime_form`.

===============  =========  ==============================  ==================================
branch           name       fit                             held-out refit
===============  =========  ==============================  ==================================
first_loading    eq24       :func:`.fit.fit_first_loading`  :func:`.heldout.first_loading_errors`
first_loading    tabulated  :func:`.first_table.fit_first_loading_table`  each level left out
reload           paper      :func:`.fit.fit_reload`         :func:`.heldout.reload_errors`
reload           tabulated  :func:`.reload_table.fit_reload_table`  :func:`.heldout.reload_table_errors`
===============  =========  ==============================  ==================================

:func:`first_loading_law` and :func:`reload_law` fit the forms a scene asks for
(``Scene.first_loading_form``, ``Scene.reload_form``; ``"auto"``: every candidate) and choose
the one with the smallest held-out error. The reload forms are fitted on ``alpha1(p_hist)`` of
the first-loading form that runs (:class:`FitContext`). A new form is a :func:`register` call
here and one in :mod:`frictionlaw.forms` (tests/test_branch_forms.py).
"""

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from frictionlaw import alpha_first, alpha_reload
from frictionlaw import forms as _rt

from . import fit as _fit
from . import heldout as _held
from .first_table import fit_first_loading_table
from .reload_table import fit_reload_table, table_alpha

__all__ = [
    "FitContext",
    "FormCalibration",
    "BranchLaw",
    "register",
    "unregister",
    "calibration_form",
    "form_names",
    "first_loading_law",
    "reload_law",
    "FittedLaw",
    "fit_law",
    "choose",
    "cached_reload_table",
]


@dataclass(frozen=True)
class FitContext:
    """What a form's fit needs besides its curves.

    ``H`` (Pa); ``floor_to``: Eq. 24's bound ``alpha1 >= p / H`` up to it (Pa, ``None``: not
    imposed); ``continuous``: the reload branch's continuous variant; ``C1, n1``: Eq. 24's fit
    (always made: the file's header); ``first``: ``(form, data)`` of the first-loading form that
    runs, whose ``alpha1(p_hist)`` scales the reload branch (``None``: Eq. 24); ``dip_range``:
    the calibrated histories (Pa, from the lowest reload level to the top first-loading
    pressure) on which the paper's Eq. 25 is kept from lying below the first loading
    (:func:`~.fit.fit_reload`); below the lowest reload level the law is extrapolated, and its
    dip there is reported (:mod:`.law_checks`), not constrained.
    """

    H: float
    floor_to: float | None = None
    continuous: bool = False
    C1: float = math.nan
    n1: float = math.nan
    first: tuple | None = None
    dip_range: tuple | None = None

    @classmethod
    def of(cls, scene):
        """The context of a :class:`~.scene.Scene` (before any fit)."""
        floor_to = None if scene.alpha_floor is None else scene.alpha_floor * scene.H
        return cls(scene.H, floor_to, bool(scene.continuous_reload))

    def law(self, C2=1.0, n2=1.0):
        """The ``FrictionParams`` that evaluates ``alpha`` with this first loading."""
        return _fit._law(self.H, self.C1, self.n1, C2, n2, self.continuous, self.first)


@dataclass(frozen=True)
class FormCalibration:
    """The calibration side of one form of one branch (the runtime side: ``runtime_form``).

    Attributes
    ----------
    name, branch : str
        As the runtime record (:mod:`frictionlaw.forms`) names them.
    fit : callable
        First loading: ``fit(p, alpha, ctx)``; reload: ``fit(curves, ctx)``.
    predict : callable
        First loading: ``predict(fit, p, ctx)``; reload: ``predict(fit, curve, ctx)`` (``alpha``
        at ``curve.p`` after ``curve.p_hist``).
    heldout : callable
        First loading: ``heldout(p, alpha, fit, ctx)``; reload: ``heldout(curves, fit, ctx)``:
        the :class:`~.heldout.BranchErrors` in sample, held out and extrapolated.
    runtime : callable
        ``runtime(fit)``: the data ``FrictionParams`` runs the form with (``None``: the form
        runs from ``C1, n1`` / ``C2, n2``).
    candidate : bool
        ``"auto"`` fits and weighs it.
    """

    name: str
    branch: str
    fit: Callable[..., Any]
    predict: Callable[..., Any]
    heldout: Callable[..., Any]
    runtime: Callable[[Any], Any]
    candidate: bool = True

    @property
    def runtime_form(self):
        """The runtime record (:class:`frictionlaw.forms.BranchForm`) of this form."""
        return _rt.branch_form(self.branch, self.name)

    @property
    def export_template(self):
        """The Fortran law-core template that exports the form (``None``: not exported yet)."""
        return self.runtime_form.export_template


_REGISTRY: dict[tuple[str, str], FormCalibration] = {}
_BUILTIN = {_rt.FIRST_LOADING: ("eq24", "tabulated"), _rt.RELOAD: ("paper", "tabulated")}
#: the form that is always fitted (the header's parameters) per branch
_ALWAYS = {_rt.FIRST_LOADING: "eq24", _rt.RELOAD: "paper"}


def register(form, *, replace=False):
    """Add a :class:`FormCalibration`; its runtime record must be registered already."""
    form.runtime_form  # noqa: B018 - ValueError naming the runtime's forms if it is not
    key = (form.branch, form.name)
    if key in _REGISTRY and not replace:
        raise ValueError(f"the {form.branch} form {form.name!r} is registered already")
    _REGISTRY[key] = form
    return form


def unregister(branch, name):
    """Remove a registered form (a test's own); the built-in forms cannot be removed."""
    if name in _BUILTIN.get(branch, ()):
        raise ValueError(f"the built-in {branch} form {name!r} cannot be removed")
    _REGISTRY.pop((branch, name), None)


def form_names(branch):
    """The calibrated forms of ``branch``, built-in ones first."""
    return tuple(n for (b, n) in _REGISTRY if b == branch)


def calibration_form(branch, name):
    """The registered :class:`FormCalibration`; ``ValueError`` naming the known ones."""
    try:
        return _REGISTRY[(branch, name)]
    except KeyError:
        raise ValueError(
            f"{branch}_form must be one of auto, {', '.join(form_names(branch))}; got {name!r}"
        ) from None


@dataclass(frozen=True)
class BranchLaw:
    """The forms of one branch fitted to a calibration's curves, and the one that runs.

    ``form``: the name of the form that runs; ``fits``: name -> fit of every form fitted;
    ``errors``: ``"<branch>"`` -> the :class:`~.heldout.BranchErrors` of the form that runs,
    ``"<branch>_<name>"`` -> each other form's, reported beside it.
    """

    branch: str
    form: str
    fits: dict
    errors: dict

    @property
    def fit(self):
        """The fit of the form that runs."""
        return self.fits[self.form]

    def runtime(self):
        """``(form, data)``: what ``FrictionParams`` runs (data kept for a data-less form)."""
        rec = calibration_form(self.branch, self.form)
        data = rec.runtime(self.fit)
        if data is None:  # keep a fitted table beside the paper's equation
            kept = [calibration_form(self.branch, n).runtime(f) for n, f in self.fits.items()]
            data = next((d for d in kept if d is not None), None)
        return self.form, data


def choose(errors, order):
    """The name in ``order`` whose held-out max (in sample without levels to hold out) is least.

    A tie goes to the first in ``order`` (the tabulated forms come first).
    """

    def worst(name):
        e = errors[name]
        return e.heldout_max if math.isfinite(e.heldout_max) else e.in_sample_max

    return min(order, key=lambda n: (worst(n), order.index(n)))


def _fitted(branch, wanted):
    """The forms to fit: the always-fitted one and ``wanted`` (``"auto"``: every candidate)."""
    if wanted == "auto":
        names = [n for n in form_names(branch) if calibration_form(branch, n).candidate]
    else:
        calibration_form(branch, wanted)
        names = [wanted]
    return sorted({_ALWAYS[branch], *names}, key=lambda n: (n == _ALWAYS[branch], n))


def _branch_law(branch, wanted, fits, errors):
    names = list(fits)
    form = wanted if wanted != "auto" else choose(errors, [n for n in names if n in errors])
    out = {}
    for n in (n for n in names if n in errors):
        key = branch if n == form else f"{branch}_{n}"
        out[key] = dataclasses.replace(errors[n], branch=key)
    return BranchLaw(branch, form, fits, out)


def _check_heldout(wanted, heldout):
    if not heldout and wanted == "auto":
        raise ValueError("the auto form is chosen by held-out error: heldout=False needs a form")


def first_loading_law(scene, p, alpha, ctx=None, *, heldout=True):
    """The first-loading forms of ``scene.first_loading_form`` fitted to ``(p, alpha)``.

    Returns a :class:`BranchLaw`; Eq. 24 is always fitted (``fits["eq24"]``: the file's
    ``C1, n1``). ``heldout=False`` skips the held-out refits (no errors; a named form only).
    """
    ctx = FitContext.of(scene) if ctx is None else ctx
    wanted = scene.first_loading_form
    _check_heldout(wanted, heldout)
    fits, errors = {}, {}
    for name in _fitted(_rt.FIRST_LOADING, wanted):
        rec = calibration_form(_rt.FIRST_LOADING, name)
        fits[name] = rec.fit(p, alpha, ctx)
        if heldout:
            errors[name] = rec.heldout(p, alpha, fits[name], ctx)
    return _branch_law(_rt.FIRST_LOADING, wanted, fits, errors)


def reload_law(scene, curves, ctx, *, heldout=True):
    """The reload forms of ``scene.reload_form`` fitted to ``curves`` on ``ctx``'s first loading.

    Returns a :class:`BranchLaw`; the paper's Eq. 25 is always fitted (``fits["paper"]``: the
    file's ``C2, n2``). ``heldout=False`` as :func:`first_loading_law`.
    """
    wanted = scene.reload_form
    _check_heldout(wanted, heldout)
    fits, errors = {}, {}
    for name in _fitted(_rt.RELOAD, wanted):
        rec = calibration_form(_rt.RELOAD, name)
        fits[name] = rec.fit(curves, ctx)
        if heldout:
            errors[name] = rec.heldout(curves, fits[name], ctx)
    return _branch_law(_rt.RELOAD, wanted, fits, errors)


@dataclass(frozen=True)
class FittedLaw:
    """Both branches fitted: the first loading, then the reload on its ``alpha1(p_hist)``."""

    first: BranchLaw
    reload: BranchLaw
    ctx: FitContext

    @property
    def eq24(self):
        """Eq. 24's fit (the file's ``C1, n1``)."""
        return self.first.fits["eq24"]

    @property
    def paper(self):
        """The paper's Eq. 25 fit (the file's ``C2, n2``)."""
        return self.reload.fits["paper"]

    @property
    def table(self):
        """The tabulated reload form's fit, or ``None``."""
        return self.reload.fits.get("tabulated")

    @property
    def errors(self):
        """Every form's :class:`~.heldout.BranchErrors` by key (:class:`BranchLaw`)."""
        return {**self.first.errors, **self.reload.errors}

    def apply(self, base):
        """``base`` (a ``FrictionParams``) running this law: its parameters, forms and tables."""
        first, first_data = self.first.runtime()
        reload, reload_data = self.reload.runtime()
        return base.replace(
            C1=self.eq24.C1,
            n1=self.eq24.n1,
            C2=self.paper.C2,
            n2=self.paper.n2,
            continuous_reload=self.ctx.continuous,
            first_loading_form=first,
            first_loading_table=first_data,
            reload_form=reload,
            reload_table=reload_data,
        )


def fit_law(scene, p, alpha, curves, *, heldout=True):
    """Fit both branches as ``scene`` asks: a :class:`FittedLaw`.

    The first-loading forms first (:func:`first_loading_law`); the reload forms then on
    ``alpha1(p_hist)`` of the first-loading form that runs (:func:`reload_law`). Used by a
    calibration and by the pooled law of several samples. ``heldout=False``: the fits alone,
    without their held-out refits (named forms only; the errors are then empty).
    """
    first = first_loading_law(scene, p, alpha, heldout=heldout)
    eq24 = first.fits["eq24"]
    ctx = dataclasses.replace(
        FitContext.of(scene),
        C1=eq24.C1,
        n1=eq24.n1,
        first=None if first.form == "eq24" else first.runtime(),
        dip_range=(float(min(c.p_hist for c in curves)), float(max(p))),
    )
    return FittedLaw(first, reload_law(scene, curves, ctx, heldout=heldout), ctx)


# -- the built-in forms -------------------------------------------------------------------


def _eq24_predict(fit, p, ctx):
    return alpha_first(p, _fit._law(ctx.H, fit.C1, fit.n1))


def _table_predict(fit, p, ctx):
    return alpha_first(p, _fit._law(ctx.H, 1.0, 1.0, first=("tabulated", fit.table)))


def _table_heldout(p, alpha, fit, ctx):
    def refit_predict(keep, p_out):
        return _table_predict(fit_first_loading_table(p[keep], alpha[keep], ctx.H), p_out, ctx)

    return _held.level_errors(p, alpha, fit.residuals, refit_predict, "tabulated")


def _paper_predict(fit, curve, ctx):
    return alpha_reload(curve.p, curve.p_hist, ctx.law(fit.C2, fit.n2))


def _reload_table_predict(fit, curve, ctx):
    return table_alpha(
        curve.p, curve.p_hist, fit.table, ctx.H, ctx.C1, ctx.n1, ctx.continuous, ctx.first
    )


register(
    FormCalibration(
        "eq24",
        _rt.FIRST_LOADING,
        fit=lambda p, alpha, ctx: _fit.fit_first_loading(p, alpha, ctx.H, floor_to=ctx.floor_to),
        predict=_eq24_predict,
        heldout=lambda p, alpha, fit, ctx: _held.first_loading_errors(
            p, alpha, ctx.H, fit, ctx.floor_to
        ),
        runtime=lambda fit: None,
    )
)
register(
    FormCalibration(
        "tabulated",
        _rt.FIRST_LOADING,
        fit=lambda p, alpha, ctx: fit_first_loading_table(p, alpha, ctx.H),
        predict=_table_predict,
        heldout=_table_heldout,
        runtime=lambda fit: fit.table,
    )
)
register(
    FormCalibration(
        "paper",
        _rt.RELOAD,
        fit=lambda curves, ctx: _fit.fit_reload(
            curves,
            ctx.H,
            ctx.C1,
            ctx.n1,
            continuous=ctx.continuous,
            first=ctx.first,
            dip_range=ctx.dip_range,
        ),
        predict=_paper_predict,
        heldout=lambda curves, fit, ctx: _held.reload_errors(
            curves,
            ctx.H,
            ctx.C1,
            ctx.n1,
            fit,
            ctx.continuous,
            first=ctx.first,
            dip_range=ctx.dip_range,
        ),
        runtime=lambda fit: None,
    )
)
_LAST_TABLE: dict = {}


def cached_reload_table(curves, ctx):
    """The tabulated reload form's fit of ``curves`` on ``ctx``, the last one kept.

    The adaptive levels' last round fits the calibration's own curves on its own context
    (:mod:`.levels`): the calibration's fit is then that one (0.7 s at 5 levels).
    """
    try:
        key = (tuple((c.p_hist, c.p.tobytes(), c.alpha.tobytes()) for c in curves), ctx)
        hit = _LAST_TABLE.get(key)
    except (AttributeError, TypeError):  # curves as dicts, an unhashable form's data: no cache
        hit, key = None, None
    if hit is None:
        hit = fit_reload_table(
            curves, ctx.H, ctx.C1, ctx.n1, continuous=ctx.continuous, first=ctx.first
        )
        if key is not None:
            _LAST_TABLE.clear()
            _LAST_TABLE[key] = hit
    return hit


register(
    FormCalibration(
        "tabulated",
        _rt.RELOAD,
        fit=cached_reload_table,
        predict=_reload_table_predict,
        heldout=lambda curves, fit, ctx: _held.reload_table_errors(fit),
        runtime=lambda fit: fit.table,
    )
)
