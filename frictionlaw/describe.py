"""The law a parameter file runs, described once for every report.

A parameter file runs one form per branch of the law (first loading: Eq. 24; un-/reloading:
the paper's Eq. 25 or Eq. 25 tabulated over ``p_hist``) and may carry another form of a branch
beside it (a calibration fits both reload forms, runs the one that predicts held-out load levels
better and keeps the other for comparison). Every report of the law (``halfspace-calib``'s
console, ``summary.json``, ``report.html`` and plot titles; ``fe-demo``'s ``summary.json``
``law_parameters`` and ``report.html``) is built from one :class:`LawDescription`
(:func:`describe_law`): per branch, the form that runs first, with its parameters or table and
its measured errors (in sample, held out, extrapolated; ``provenance.errors``), then the forms
beside it, each the same way.

The forms are the runtime's records (:class:`frictionlaw.forms.BranchForm`): each carries its
description (``label``, ``equation``, and ``describe``: its symbols and table for a parameter
set), so a new form registered once (:func:`frictionlaw.forms.register`) runs, is written and
is described with no other edit. A form is listed where the parameter set carries it (a form
without data always; one with data where the branch's table is of its type). The errors are
found by branch and form in the file's provenance (``provenance.errors.<branch...>.form``).

Standard library and :mod:`frictionlaw` only; nothing here is loaded by ``import frictionlaw``.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from . import forms as _forms
from .forms import FormTable, Quantity

__all__ = [
    "BRANCHES",
    "Branch",
    "BranchDescription",
    "FormDescription",
    "FormErrors",
    "FormTable",
    "LawDescription",
    "LawSource",
    "Quantity",
    "describe_law",
]

MPa = 1e6


@dataclass(frozen=True)
class FormErrors:
    """Measured ``|alpha_law - alpha_model|`` of a form (the calibration's ``provenance.errors``).

    ``heldout_max`` / ``heldout_rms``: each interior load level left out, refitted and predicted
    (``None`` with fewer than 3 levels); ``extrapolation``: ``(top level in Pa, max)`` predicted
    from the levels below it; ``extrapolation_below``: ``(lowest level in Pa, max)`` predicted
    from the levels above it (``None`` where not recorded).
    """

    in_sample_max: float
    in_sample_rms: float
    heldout_max: float | None
    heldout_rms: float | None
    extrapolation: tuple[float, float] | None
    n_points: int
    extrapolation_below: tuple[float, float] | None = None

    @classmethod
    def from_record(cls, rec: dict[str, Any]) -> FormErrors:
        """From a ``provenance.errors`` entry (``BranchErrors.summary()``)."""
        ext, low = rec.get("extrapolation"), rec.get("extrapolation_below")
        return cls(
            in_sample_max=float(rec["in_sample_max"]),
            in_sample_rms=float(rec["in_sample_rms"]),
            heldout_max=_opt(rec.get("heldout_max")),
            heldout_rms=_opt(rec.get("heldout_rms")),
            extrapolation=None if not ext else (float(ext["level"]), float(ext["max_abs"])),
            n_points=int(rec.get("n_points", 0)),
            extrapolation_below=None if not low else (float(low["level"]), float(low["max_abs"])),
        )

    @property
    def deciding(self) -> float:
        """The held-out maximum, or the in-sample one where nothing was held out."""
        return self.in_sample_max if self.heldout_max is None else self.heldout_max

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready record (``|d alpha|``, dimensionless)."""
        ext = self.extrapolation
        return {
            "unit": "1 (|d alpha|, contact ratio)",
            "heldout_max": self.heldout_max,
            "heldout_rms": self.heldout_rms,
            "in_sample_max": self.in_sample_max,
            "in_sample_rms": self.in_sample_rms,
            "extrapolation": None if ext is None else {"level_Pa": ext[0], "max_abs": ext[1]},
            "extrapolation_below": None
            if self.extrapolation_below is None
            else {"level_Pa": self.extrapolation_below[0], "max_abs": self.extrapolation_below[1]},
            "n_points": self.n_points,
        }

    def text(self) -> str:
        """``held out max 0.0138 (rms 0.0049), in sample 0.0133, top level extrapolated 0.194``."""
        held = (
            f"held out max {self.heldout_max:.4f} (rms {self.heldout_rms or 0.0:.4f})"
            if self.heldout_max is not None
            else "held out: fewer than 3 levels"
        )
        out = f"|d alpha| {held}, in sample max {self.in_sample_max:.4f}"
        if self.extrapolation is not None:
            lv, e = self.extrapolation
            out += f", top level {lv / MPa:.4g} MPa extrapolated {e:.4f}"
        if self.extrapolation_below is not None:
            lv, e = self.extrapolation_below
            out += f", lowest {lv / MPa:.4g} MPa {e:.4f}"
        return out


def _span(name: str, unit: str, lo: float, hi: float) -> str:
    """``C2 2.263-16.07``; a pressure in MPa: ``100-760 MPa``."""
    if unit == "Pa":
        return f"{name} {lo / MPa:.4g}-{hi / MPa:.4g} MPa"
    return f"{name} {lo:.4g}-{hi:.4g}" + ("" if unit == "1" else f" {unit}")


def _opt(v: Any) -> float | None:
    return None if v is None or not math.isfinite(float(v)) else float(v)


@dataclass(frozen=True)
class FormDescription:
    """One form of one branch as the file carries it."""

    branch: str
    form: str
    name: str
    runs: bool
    parameters: tuple[Quantity, ...]
    table: FormTable | None = None
    errors: FormErrors | None = None
    r_squared: float | None = None

    def label(self) -> str:
        """The form and its numbers on one line.

        For example ``Eq. 24: C1 = 1.024, n1 = 16.45``.
        """
        parts = [q.text() for q in self.parameters]
        if self.table is not None:
            (first, unit), *rest = self.table.columns
            spans = [_span(n, u, *self.table.span(n)) for n, u in rest]
            levels = _span("", unit, *self.table.span(first)).strip()
            parts = [f"{len(self.table.rows)} levels {levels}", *spans, *parts]
        return f"{self.name}: {', '.join(parts)}" if parts else self.name

    def error_text(self) -> str:
        """The measured errors in one phrase (``errors not recorded`` for a hand-made file)."""
        if self.errors is None:
            return "errors not recorded in the file"
        text = self.errors.text()
        if self.r_squared is not None:
            text += f", R^2 {self.r_squared:.4f}"
        return text

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready record."""
        return {
            "name": self.name,
            "runs": self.runs,
            "parameters": {q.name: q.to_dict() for q in self.parameters},
            "table": None if self.table is None else self.table.to_dict(),
            "errors": None if self.errors is None else self.errors.to_dict(),
            "r_squared": self.r_squared,
            "label": self.label(),
        }


@dataclass(frozen=True)
class BranchDescription:
    """A branch of the law: the form that runs (first), then the forms beside it."""

    branch: str
    title: str
    forms: tuple[FormDescription, ...]

    @property
    def running(self) -> FormDescription:
        """The form the file runs on this branch."""
        return self.forms[0]

    @property
    def others(self) -> tuple[FormDescription, ...]:
        """The forms the file carries beside it (for comparison)."""
        return self.forms[1:]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready record (``forms`` keyed by form, the running one first)."""
        return {
            "title": self.title,
            "runs": self.running.form,
            "forms": {f.form: f.to_dict() for f in self.forms},
        }


@dataclass(frozen=True)
class LawSource:
    """Where a law was read: the file's path and its sha256."""

    path: str
    sha256: str

    @classmethod
    def of(cls, path: str | Path) -> LawSource:
        """The source record of the file at ``path``."""
        return cls(str(path), hashlib.sha256(Path(path).read_bytes()).hexdigest())


@dataclass(frozen=True)
class LawDescription:
    """The law a parameter set runs, for reports (:func:`describe_law`)."""

    branches: tuple[BranchDescription, ...]
    inputs: tuple[Quantity, ...]
    derived: tuple[Quantity, ...]
    continuous_reload: bool
    calibrated_range: tuple[float, float] | None
    heldout_tol: float | None = None
    source: LawSource | None = None
    notes: tuple[str, ...] = field(default=())

    def branch(self, name: str) -> BranchDescription:
        """The branch ``name`` (``"first_loading"``, ``"reload"``)."""
        for b in self.branches:
            if b.branch == name:
                return b
        raise KeyError(name)

    def forms_label(self) -> str:
        """The forms that run, in a few words.

        For example ``Eq. 24 + Eq. 25 tabulated over p_hist``.
        """
        text = " + ".join(b.running.name for b in self.branches)
        return text + (" (continuous at p_hist)" if self.continuous_reload else "")

    def title(self, branch: str) -> str:
        """A plot title: the branch's running form, its held-out error, the other form's."""
        b = self.branch(branch)
        run = b.running
        lines = [f"{b.title[:1].upper()}{b.title[1:]}: {run.label()}"]
        err = _held(run)
        for other in b.others:
            err += f"; beside it {other.name}: {_held(other)}"
        lines.append(err)
        return "\n".join(_wrap(line, 70) for line in lines)

    def lines(self) -> list[str]:
        """The law in console lines: each branch's running form, then the forms beside it."""
        out = []
        for b in self.branches:
            out.append(f"{b.title}: {b.running.label()}")
            out.append(f"    {b.running.error_text()}")
            for other in b.others:
                out.append(f"  beside it, not run: {other.label()}")
                out.append(f"    {other.error_text()}")
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready record (``summary.json``'s ``law``, fe-demo's ``law_parameters.law``)."""
        rng = self.calibrated_range
        return {
            "forms": self.forms_label(),
            "source": None
            if self.source is None
            else {"path": self.source.path, "sha256": self.source.sha256},
            "inputs": {q.name: q.to_dict() for q in self.inputs},
            "derived": {q.name: q.to_dict() for q in self.derived},
            "continuous_reload": self.continuous_reload,
            "calibrated_range": None
            if rng is None
            else {"p_min": rng[0], "p_max": rng[1], "unit": "Pa"},
            "heldout_tol": self.heldout_tol,
            "branches": {b.branch: b.to_dict() for b in self.branches},
            "notes": list(self.notes),
        }


def _held(form: FormDescription) -> str:
    if form.errors is None:
        return "errors not recorded"
    e = form.errors
    if e.heldout_max is None:
        return f"in sample max |d alpha| {e.in_sample_max:.3g}"
    return f"held out max |d alpha| {e.heldout_max:.3g}"


def _wrap(text: str, width: int) -> str:
    """Break a title line at ``, `` / ``; `` so that it fits a plot."""
    out, line = [], ""
    for piece in text.replace("; ", ";\x00").replace(", ", ",\x00").split("\x00"):
        if line and len(line) + 1 + len(piece) > width:
            out.append(line)
            line = piece
        else:
            line = f"{line} {piece}" if line else piece
    out.append(line)
    return "\n".join(out)


# -- the branches ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class Branch:
    """A branch of the law as reports list it: its name and title.

    The form a parameter set runs on it is ``params.<branch>_form``; its forms are the runtime's
    records (:mod:`frictionlaw.forms`), each with its description.
    """

    branch: str
    title: str


#: the branches of the law, in the order reports list them
BRANCHES: dict[str, Branch] = {
    "first_loading": Branch("first_loading", "first loading (p >= p_hist)"),
    "reload": Branch("reload", "un-/reloading (p < p_hist)"),
}


# -- the description --------------------------------------------------------------------------------
def _records(prov: dict[str, Any], key: str, branch: str) -> list[tuple[str, dict[str, Any]]]:
    """``[(key, record)]`` of ``provenance[key]`` that belong to ``branch``."""
    block = prov.get(key)
    if not isinstance(block, dict):
        return []
    return [
        (k, v)
        for k, v in block.items()
        if isinstance(v, dict) and (k == branch or k.startswith(branch + "_"))
    ]


def _default_form(branch: str) -> str:
    """The form a branch's record means where it names none (the files before the forms)."""
    return "eq24" if branch == "first_loading" else "paper"


def _errors_of(prov: dict[str, Any], branch: str, form: str) -> FormErrors | None:
    for _, rec in _records(prov, "errors", branch):
        if rec.get("form", _default_form(branch)) == form:
            try:
                return FormErrors.from_record(rec)
            except (KeyError, TypeError, ValueError):
                return None
    return None


def _r_squared_of(prov: dict[str, Any], branch: str, form: str) -> float | None:
    for _, rec in _records(prov, "fit", branch):
        if rec.get("form", _default_form(branch)) == form and rec.get("r_squared") is not None:
            return float(rec["r_squared"])
    return None


def _inputs(P: Any) -> tuple[Quantity, ...]:
    notes = P.provenance.get("inputs", {}) if isinstance(P.provenance, dict) else {}

    def note(name: str, default: str) -> str:
        text = notes.get(name) if isinstance(notes, dict) else None
        return str(text) if text else default

    out = [
        Quantity("m", P.m, "1", note("m", "Tresca friction factor of the interface")),
        Quantity("sigma_y", P.sigma_y, "Pa", note("sigma_y", "yield stress of the softer body")),
        Quantity("H", P.H, "Pa", note("H", "hardness of the softer body")),
        Quantity("k", P.k, "Pa", note("k", "shear flow stress of the law")),
    ]
    if P.geo_ratio:
        out.append(Quantity("geo_ratio", P.geo_ratio, "1", "Eq. 26: tau_geo / tau_adh"))
    return tuple(out)


def describe_law(params: Any, source: LawSource | str | Path | None = None) -> LawDescription:
    """The :class:`LawDescription` of a :class:`~frictionlaw.FrictionParams`.

    Parameters
    ----------
    params : FrictionParams
        The law (its provenance supplies each form's measured errors and ``R^2`` where a
        calibration recorded them).
    source : LawSource or path, optional
        The file it was read from (a path is hashed).

    Returns
    -------
    LawDescription
    """
    if source is not None and not isinstance(source, LawSource):
        source = LawSource.of(source)
    prov = params.provenance if isinstance(params.provenance, dict) else {}
    branches = []
    for name, branch in BRANCHES.items():
        running = getattr(params, f"{name}_form")
        forms = []
        for form in (_forms.branch_form(name, n) for n in _forms.form_names(name)):
            if not form.carried(params):
                continue
            quantities, table = form.description(params)
            forms.append(
                FormDescription(
                    branch=name,
                    form=form.name,
                    name=form.label,
                    runs=form.name == running,
                    parameters=quantities,
                    table=table,
                    errors=_errors_of(prov, name, form.name),
                    r_squared=_r_squared_of(prov, name, form.name),
                )
            )
        forms.sort(key=lambda f: not f.runs)
        if not forms or not forms[0].runs:
            raise ValueError(f"{name}: no description of the form {running!r} that runs")
        branches.append(BranchDescription(name, branch.title, tuple(forms)))
    errors = prov.get("errors")
    tol = errors.get("heldout_tol") if isinstance(errors, dict) else None
    return LawDescription(
        branches=tuple(branches),
        inputs=_inputs(params),
        derived=(
            Quantity(
                "mu_eff",
                params.mu_eff,
                "1",
                "Coulomb slope tau / p at small p of the first loading that runs",
            ),
            Quantity("tau_max", params.tau_max, "Pa", "cap at large p: m k (1 + geo_ratio)"),
        ),
        continuous_reload=params.continuous_reload,
        calibrated_range=params.p_range,
        heldout_tol=None if tol is None else float(tol),
        source=source,
        notes=tuple(str(n) for n in [prov.get("note")] if n),
    )
