"""The forms of the law's two branches as records: the runtime side.

The calibration's side is :mod:`halfspace_calib.pipeline.law.forms`. Each branch of the law (first loading, and un-/reloading below ``p_hist``) runs one of several
forms. A :class:`BranchForm` says everything the runtime needs of one form: its name (as
``params.json`` spells it), the record type of its calibrated data on
:class:`~frictionlaw.FrictionParams` (``None``: the form runs from the file's parameters
``C1, n1`` or ``C2, n2`` alone), how that data lowers to the kernels' coefficient block (the
layout in :mod:`frictionlaw._kernels`), the small-pressure slope ``alpha1 / p`` (first
loading: ``mu_eff = tau_max`` times it) and the template of the Fortran law core that exports
it (``None``: not exported yet; ``frictionlaw-export`` refuses such a file), and its
description for reports: its label, its equation in words and its symbols and table for a
parameter set (:class:`Quantity`, :class:`FormTable`; :mod:`frictionlaw.describe` reads them
from here, so there is one registry of forms).

The four built-in forms:

===============  =========  ================================  ===========================
branch           name       data                              kernel form
===============  =========  ================================  ===========================
first_loading    eq24       (``C1, n1``)                      ``FIRST_EQ24``
first_loading    tabulated  :class:`FirstLoadingTable`        ``FIRST_TABULATED``
reload           paper      (``C2, n2``)                      ``FORM_PAPER``
reload           tabulated  :class:`ReloadTable`              ``FORM_TABULATED``
===============  =========  ================================  ===========================

A new form is one :func:`register` call (tests/test_branch_forms.py registers one that lowers
to the tabulated kernel form, and runs and describes it from a calibration through
``params.json``).
"""

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import _codes as K
from .first_loading import FirstLoadingTable
from .reload_form import ReloadTable

__all__ = [
    "FIRST_LOADING",
    "RELOAD",
    "BRANCH_KEYS",
    "BranchForm",
    "FormTable",
    "Quantity",
    "register",
    "unregister",
    "branch_form",
    "form_names",
    "read_branch",
]

#: the branch names
FIRST_LOADING = "first_loading"
RELOAD = "reload"
#: the JSON object of each branch in a parameter file
BRANCH_KEYS = {FIRST_LOADING: "first_loading_law", RELOAD: "reload_law"}
#: the data type a branch object holds when the form that runs has none (a table kept beside
#: the paper's form, so that a calibration can be switched)
_KEPT: dict[str, type[Any]] = {FIRST_LOADING: FirstLoadingTable, RELOAD: ReloadTable}
_EMPTY = np.zeros(0)
MPa = 1e6


@dataclass(frozen=True)
class Quantity:
    """One number of the law: its name, value (SI), unit (``"1"``: dimensionless), meaning."""

    name: str
    value: float
    unit: str
    meaning: str

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready record."""
        return {"value": self.value, "unit": self.unit, "meaning": self.meaning}

    def text(self) -> str:
        """``name = value`` with the unit a reader expects (Pa shown as MPa)."""
        if self.unit == "Pa":
            return f"{self.name} = {self.value / MPa:.4g} MPa"
        unit = "" if self.unit == "1" else f" {self.unit}"
        return f"{self.name} = {self.value:.4g}{unit}"


@dataclass(frozen=True)
class FormTable:
    """A form's table: one row per level, each column with its unit (SI)."""

    columns: tuple[tuple[str, str], ...]
    rows: tuple[tuple[float, ...], ...]
    interpolation: str

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready record."""
        return {
            "columns": [{"name": n, "unit": u} for n, u in self.columns],
            "rows": [list(r) for r in self.rows],
            "interpolation": self.interpolation,
        }

    def span(self, column: str) -> tuple[float, float]:
        """Smallest and largest value of ``column``."""
        i = [n for n, _ in self.columns].index(column)
        vals = [r[i] for r in self.rows]
        return min(vals), max(vals)


#: a form's description of a parameter set: its symbols (with their values) and its table
Description = tuple[tuple[Quantity, ...], FormTable | None]


@dataclass(frozen=True)
class BranchForm:
    """One form of one branch of the law, as the runtime runs it.

    Attributes
    ----------
    name : str
        The form's name (``params.json``'s ``first_loading_law.form`` / ``reload_law.form``).
    branch : str
        :data:`FIRST_LOADING` or :data:`RELOAD`.
    equation : str
        What it is, in words, for messages and reports.
    data : type or None
        The record type of its calibrated data (``FrictionParams.first_loading_table`` /
        ``reload_table``), with ``to_dict(form)``, ``from_dict(doc, source=...)`` and
        ``check_hardness(H)``; ``None``: the form runs from ``C1, n1`` / ``C2, n2``.
    lower : callable
        ``lower(data, H) -> (kernel form code, block)``: the coefficient block the kernels run
        (:mod:`frictionlaw._kernels`, "Coefficient layout").
    slope0 : callable or None
        First loading: ``slope0(params) -> lim alpha1(p) / p`` at ``p -> 0`` (1/Pa), the
        Coulomb slope ``mu_eff / tau_max``.
    export_template : str or None
        The Fortran law-core template that exports the form (``frictionlaw/export/core``);
        ``None``: no export target carries it yet.
    label : str
        Its name in reports (``"Eq. 24"``); empty: ``equation``.
    describe : callable or None
        ``describe(params) -> (symbols, table)``: its :class:`Quantity` values and its
        :class:`FormTable` (or ``None``) for a parameter set that carries it (reports,
        :mod:`frictionlaw.describe`); ``None``: no symbols, no table.
    """

    name: str
    branch: str
    equation: str
    data: type[Any] | None
    lower: Callable[[Any, float], tuple[int, NDArray[np.float64]]]
    slope0: Callable[[Any], float] | None = None  # of a FrictionParams (not imported: a circle)
    export_template: str | None = None
    label: str = ""
    describe: Callable[[Any], Description] | None = None

    def __post_init__(self) -> None:
        if not self.label:
            object.__setattr__(self, "label", self.equation)
        if self.branch not in BRANCH_KEYS:
            raise ValueError(f"branch must be one of {', '.join(BRANCH_KEYS)}, got {self.branch!r}")
        if self.branch == FIRST_LOADING and self.slope0 is None:
            raise ValueError(f"first-loading form {self.name!r} needs slope0 (mu_eff)")

    def carried(self, params: Any) -> bool:
        """Whether ``params`` can run this form: no data needed, or its table is of its type."""
        return self.data is None or isinstance(getattr(params, f"{self.branch}_table"), self.data)

    def description(self, params: Any) -> Description:
        """``(symbols, table)`` of this form in ``params`` (reports)."""
        return ((), None) if self.describe is None else self.describe(params)

    def switch(self, params: Any) -> Any:
        """The same parameters running this form (a comparison curve); needs :meth:`carried`."""
        kw: dict[str, Any] = {f"{self.branch}_form": self.name}
        data = getattr(params, f"{self.branch}_table")
        if self.data is None and data is not None and not isinstance(data, _KEPT[self.branch]):
            kw[f"{self.branch}_table"] = None  # another form's data, which this one cannot keep
        return params.replace(**kw)

    def check(self, data: Any, H: float) -> None:
        """``ValueError`` unless ``data`` is what this form runs (and lies below ``H``).

        A form without data accepts ``None`` or the branch's table kept beside it (so that a
        calibration can be switched to the tabulated form).
        """
        field = f"{self.branch}_table"
        if self.data is None:
            kept = _KEPT[self.branch]
            if data is not None and not isinstance(data, kept):
                raise ValueError(
                    f"{field} must be a {kept.__name__} or None, got {type(data).__name__}"
                )
            if data is not None:
                data.check_hardness(H)
            return
        if data is None:
            raise ValueError(
                f"{self.branch}_form={self.name!r} needs a {field} ({self.data.__name__})"
            )
        if not isinstance(data, self.data):
            raise ValueError(
                f"{field} of the {self.branch} form {self.name!r} must be a "
                f"{self.data.__name__}, got {type(data).__name__}"
            )
        data.check_hardness(H)


_REGISTRY: dict[tuple[str, str], BranchForm] = {}


def register(form: BranchForm, *, replace: bool = False) -> BranchForm:
    """Add ``form`` to the registry (``replace``: over a form of the same branch and name)."""
    key = (form.branch, form.name)
    if key in _REGISTRY and not replace:
        raise ValueError(f"the {form.branch} form {form.name!r} is registered already")
    _REGISTRY[key] = form
    return form


def unregister(branch: str, name: str) -> None:
    """Remove a registered form (a test's own); the built-in forms cannot be removed."""
    if name in _BUILTIN.get(branch, ()):
        raise ValueError(f"the built-in {branch} form {name!r} cannot be removed")
    _REGISTRY.pop((branch, name), None)


def form_names(branch: str) -> tuple[str, ...]:
    """The registered forms of ``branch``, built-in ones first."""
    return tuple(n for (b, n) in _REGISTRY if b == branch)


def branch_form(branch: str, name: object) -> BranchForm:
    """The registered form ``name`` of ``branch``; ``ValueError`` naming the known ones."""
    try:
        return _REGISTRY[(branch, name)]  # type: ignore[index]
    except (KeyError, TypeError):
        raise ValueError(
            f"{branch}_form must be one of {', '.join(form_names(branch))}, got {name!r}"
        ) from None


def read_branch(branch: str, doc: object, source: str) -> tuple[str, Any]:
    """``(form, data)`` of a branch object of a parameter file; ``ValueError`` naming the field."""
    key = BRANCH_KEYS[branch]
    where = f"{source}: {key}"
    if not isinstance(doc, dict):
        raise ValueError(f"{where} must be a JSON object")
    name = doc.get("form")
    try:
        form = branch_form(branch, name)
    except ValueError:
        raise ValueError(
            f"{where}.form must be one of {', '.join(form_names(branch))}; got {name!r}"
        ) from None
    kind = form.data or _KEPT[branch]
    if form.data is None and not _carries_data(branch, doc):
        return form.name, None
    return form.name, kind.from_dict(doc, source=source)


def _carries_data(branch: str, doc: dict) -> bool:
    return ("p_hist" if branch == RELOAD else "p") in doc


# -- the built-in forms -------------------------------------------------------------------


def _lower_none(code: int) -> Callable[[Any, float], tuple[int, NDArray[np.float64]]]:
    return lambda data, H: (code, _EMPTY)


def _lower_first_table(table: FirstLoadingTable, H: float) -> tuple[int, NDArray[np.float64]]:
    kn = table.knots(H)
    return K.FIRST_TABULATED, np.concatenate([[float(len(table.p))], kn["u"], kn["v"], kn["d"]])


def _lower_reload_table(table: ReloadTable, H: float) -> tuple[int, NDArray[np.float64]]:
    kn = table.knots(H)
    block = [kn["z"], kn["lnC2"], kn["dlnC2"], kn["lnn2"], kn["dlnn2"]]
    return K.FORM_TABULATED, np.concatenate([[table.s2, float(len(table.p_hist))], *block])


def _eq24_slope0(params: Any) -> float:
    return params.C1 / params.H


def _table_slope0(params: Any) -> float:
    table = params.first_loading_table
    return math.nan if table is None else float(table.slope0)


def _file_symbols(*symbols: tuple[str, str]) -> Callable[[Any], Description]:
    """The description of a form run from the file's own parameters, ``(name, meaning)`` each."""
    return lambda P: (tuple(Quantity(n, getattr(P, n), "1", m) for n, m in symbols), None)


def _first_table_symbols(P: Any) -> Description:
    t = P.first_loading_table
    return (
        Quantity("mu_eff", P.mu_eff, "1", "Coulomb slope below the lowest level (tau / p there)"),
    ), FormTable(
        (("p", "Pa"), ("alpha", "1")),
        tuple((float(p), float(a)) for p, a in zip(t.p, t.alpha, strict=True)),
        "monotone cubic Hermite of ln alpha over ln p; the Coulomb line below the lowest "
        "level, the power law of the end slope capped at 1 above the top one",
    )


def _reload_table_symbols(P: Any) -> Description:
    t = P.reload_table
    rows = tuple(
        (float(p), float(c), float(n)) for p, c, n in zip(t.p_hist, t.C2, t.n2, strict=True)
    )
    return (Quantity("s2", t.s2, "1", "exponent of p / p_hist in x2 (1: the paper's form)"),), (
        FormTable(
            (("p_hist", "Pa"), ("C2", "1"), ("n2", "1")),
            rows,
            "monotone cubic Hermite of ln C2, ln n2 over -ln(1 - p_hist / H); constant beyond "
            "the first and the last level",
        )
    )


_BUILTIN = {FIRST_LOADING: ("eq24", "tabulated"), RELOAD: ("paper", "tabulated")}

register(
    BranchForm(
        "eq24",
        FIRST_LOADING,
        "Eq. 24, alpha1 = g(p C1 / H; n1)",
        None,
        _lower_none(K.FIRST_EQ24),
        slope0=_eq24_slope0,
        export_template="core/sbmf_core.f",
        label="Eq. 24",
        describe=_file_symbols(
            ("C1", "Eq. 24: slope of alpha1 against p / H at small p"),
            ("n1", "Eq. 24: sharpness of the corner towards alpha1 = 1"),
        ),
    )
)
register(
    BranchForm(
        "tabulated",
        FIRST_LOADING,
        "the computed first loading, monotone cubic Hermite of ln alpha over ln p",
        FirstLoadingTable,
        _lower_first_table,
        slope0=_table_slope0,
        export_template="core/sbmf_first_table.f",
        label="the computed first loading, tabulated",
        describe=_first_table_symbols,
    )
)
register(
    BranchForm(
        "paper",
        RELOAD,
        "Eq. 25 with one C2, n2",
        None,
        _lower_none(K.FORM_PAPER),
        export_template="core/sbmf_core.f",
        label="the paper's Eq. 25",
        describe=_file_symbols(
            ("C2", "Eq. 25: one C2 for every p_hist"), ("n2", "Eq. 25: one n2 for every p_hist")
        ),
    )
)
register(
    BranchForm(
        "tabulated",
        RELOAD,
        "Eq. 25 with C2, n2 per load level and s2",
        ReloadTable,
        _lower_reload_table,
        export_template="core/sbmf_reload_table.f",
        label="Eq. 25 tabulated over p_hist",
        describe=_reload_table_symbols,
    )
)
