"""The law's values in a host's units, and their provenance (private).

What every target bakes in, decided from the parameter file before any template is rendered:
the unit system, the stick stiffness source, the law's constants, :func:`core_context` (the
values the law core ``core/sbmf_core.f`` is rendered with: a new law form changes that function
and the template, nothing per target) and the provenance header's lines. The public names are
re-exported by :mod:`frictionlaw.export`.
"""

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from sbmf_cli import ParameterError

from .. import __version__
from .._codes import FIRST_EQ24, FIRST_TABULATED, Q_START
from ..reload_form import LN_C2_MAX, top_slope
from ._flat import FlatSpec, flat_spec
from ._origin import m_origin

__all__ = [
    "UnitSystem",
    "UNIT_SYSTEMS",
    "StiffnessSpec",
    "stiffness_spec",
    "law_constants",
    "ReloadSpec",
    "reload_spec",
    "FirstSpec",
    "first_spec",
    "GuardSpec",
    "guard_spec",
    "CUT_FACTOR",
    "CUT_FLOOR",
    "CoreLaw",
    "core_law",
    "core_context",
    "shared_constants",
    "law_lines",
    "header_lines",
]


@dataclass(frozen=True)
class UnitSystem:
    """A host unit system: host value = SI value times the factor.

    ``code`` is the number a deck states it with (the routines' unit property: 1 SI,
    2 mm-t-s; docs/fe_codes.md, "Guards").
    """

    name: str
    stress: float  # Pa -> host stress unit
    length: float  # m -> host length unit
    stress_unit: str
    length_unit: str
    code: int = 0

    @property
    def stiffness(self):
        """Factor for a tangential stiffness (stress per length)."""
        return self.stress / self.length

    def describe(self):
        """``SI (Pa, m)``: the name with its stress and length units."""
        return f"{self.name} ({self.stress_unit}, {self.length_unit})"


UNIT_SYSTEMS = {
    "SI": UnitSystem("SI", 1.0, 1.0, "Pa", "m", 1),
    "mm-t-s": UnitSystem("mm-t-s", 1e-6, 1e3, "MPa", "mm", 2),
}


@dataclass(frozen=True)
class StiffnessSpec:
    """Where the generated routine takes the tangential stick stiffness ``k_t`` from.

    ``kind`` is ``"table"`` (the parameter file's calibrated ``k_t(p)``, log-log interpolated),
    ``"constant"`` (``--k-t``) or ``"host"`` (the host's own penalty: for Abaqus FRIC an elastic
    slip of 0.005 x CHRLNGTH). Values are in the host's units.
    """

    kind: str
    p: tuple = ()
    k: tuple = ()
    log_p: tuple = ()
    log_k: tuple = ()
    value: float = 0.0

    def describe(self, units):
        """One line for headers and READMEs."""
        k_unit = f"{units.stress_unit}/{units.length_unit}"
        if self.kind == "table":
            return (
                f"calibrated k_t(p) table from the parameter file ({len(self.p)} points, "
                f"{self.k[0]:.4g}..{self.k[-1]:.4g} {k_unit}, log-log, constant beyond the ends)"
            )
        if self.kind == "constant":
            return f"constant k_t = {self.value:.6g} {k_unit} (--k-t)"
        return "the host's penalty (no calibrated k_t in the parameter file, no --k-t)"


def stiffness_spec(params, units, k_t=None):
    """The stiffness source: ``k_t`` (Pa/m) if given, else the file's table, else the host's."""
    if k_t is not None:
        v = float(k_t)
        if not (math.isfinite(v) and v > 0):
            raise ParameterError(
                f"{{k_t}} must be a finite stiffness > 0 in Pa/m, got {k_t!r}", "k_t"
            )
        return StiffnessSpec("constant", value=v * units.stiffness)
    table = getattr(params, "k_t", None)
    if table is None:
        return StiffnessSpec("host")
    p = tuple(float(v) * units.stress for v in table.p)
    k = tuple(float(v) * units.stiffness for v in table.k_t)
    return StiffnessSpec(
        "table", p=p, k=k, log_p=tuple(np.log(p).tolist()), log_k=tuple(np.log(k).tolist())
    )


def law_constants(params, units):
    """The constants baked into the Fortran core, in the host's units."""
    return {
        "TMAX": params.tau_max * units.stress,
        "H": params.H * units.stress,
        "C1": params.C1,
        "XN1": params.n1,
        "C2": params.C2,
        "XN2": params.n2,
    }


@dataclass(frozen=True)
class ReloadSpec:
    """The tabulated reload form as the Fortran core bakes it in (:mod:`frictionlaw.reload_form`).

    ``z``, ``lnC2``, ``dlnC2``, ``lnn2``, ``dlnn2`` are the interpolant's knots and slopes exactly
    as the runtime's coefficient array carries them (:func:`frictionlaw.law.sbmf_coeffs`); they
    are dimensionless (``z = -ln(1 - p_hist/H)``), so no unit system changes them. ``p_hist``
    holds the levels in the host's stress unit (for the provenance and the README), ``C2``,
    ``n2``, ``s2`` the calibrated values.
    """

    s2: float
    p_hist: tuple
    C2: tuple
    n2: tuple
    z: tuple
    lnC2: tuple
    dlnC2: tuple
    lnn2: tuple
    dlnn2: tuple
    top_slope: float = 0.0
    ln_c2_max: float = 0.0

    def describe(self, units):
        """Lines for the provenance header: the form, s2, the levels, the rule between them."""
        s = units.stress_unit
        return [
            "reload form: tabulated (Eq. 25 with C2, n2 per calibrated load level; "
            f"x2 = x2h (p/p_hist)**s2, x2h = p_hist C2/(H alpha1(p_hist)), s2={self.s2!r})",
            f"reload levels p_hist ({s}): " + ", ".join(f"{v!r}" for v in self.p_hist),
            "reload C2: " + ", ".join(f"{v!r}" for v in self.C2),
            "reload n2: " + ", ".join(f"{v!r}" for v in self.n2),
            "reload interpolation: monotone cubic Hermite (Fritsch-Carlson) of ln C2 and ln n2 "
            "over z=-ln(1-p_hist/H); C2, n2 of the first level below it; above the last level "
            f"n2 held and ln C2 rising as {self.top_slope!r} z (the last two levels' secant, at "
            "least 0), at most ln 1e6 (p_hist >= H included)",
        ]


def reload_spec(params, units):
    """The tabulated reload form's :class:`ReloadSpec` in ``units``; None for the paper form."""
    if params.reload_form != "tabulated":
        return None
    table = params.reload_table
    kn = table.knots(params.H)  # what frictionlaw.law.sbmf_coeffs gives the kernels, in SI
    return ReloadSpec(
        table.s2,
        tuple(v * units.stress for v in table.p_hist),
        tuple(table.C2),
        tuple(table.n2),
        z=tuple(kn["z"].tolist()),
        lnC2=tuple(kn["lnC2"].tolist()),
        dlnC2=tuple(kn["dlnC2"].tolist()),
        lnn2=tuple(kn["lnn2"].tolist()),
        dlnn2=tuple(kn["dlnn2"].tolist()),
        top_slope=top_slope(kn["z"], kn["lnC2"]),
        ln_c2_max=LN_C2_MAX,
    )


@dataclass(frozen=True)
class FirstSpec:
    """A first-loading form other than Eq. 24 as the Fortran core bakes it in.

    The form's record (:class:`frictionlaw.forms.BranchForm`) lowers its data to the kernels'
    block (:mod:`frictionlaw._kernels`, "Coefficient layout"); the core runs that block, so
    ``u = ln(p_j / H)``, ``v = ln alpha_j`` and the slopes ``d = dv/du`` are exactly the
    runtime's (dimensionless: no unit system changes them). ``template`` is the record's
    ``export_template`` (``core/sbmf_first_table.f``), ``name`` and ``equation`` its words;
    ``p`` (the levels in the host's stress unit) and ``alpha`` are read back from the knots for
    the provenance and the README; ``mu`` is the Coulomb slope below the lowest level,
    ``tau_max exp(v_0 - u_0) / H`` formed as the kernel forms it from ``tau_max`` and ``H`` in
    the host's unit.
    """

    name: str
    equation: str
    template: str
    p: tuple
    alpha: tuple
    u: tuple
    v: tuple
    d: tuple
    mu: float

    def describe(self, units):
        """Lines for the provenance header: the form, its levels and the rule between them."""
        s = units.stress_unit
        return [
            f"first-loading form: {self.name} ({self.equation})",
            f"first-loading levels p ({s}): " + ", ".join(f"{v:.10g}" for v in self.p),
            "first-loading alpha: " + ", ".join(f"{v:.10g}" for v in self.alpha),
            "first-loading interpolation: monotone cubic Hermite (Fritsch-Carlson) of ln alpha "
            "over ln(p/H) between the levels; below the first level the Coulomb line "
            "alpha_0 p/p_0; above the last level the power law of the end slope "
            f"(d ln alpha/d ln p = {self.d[-1]:.6g}), capped at alpha = 1",
        ]


def first_spec(params, units):
    """The first-loading form's :class:`FirstSpec` in ``units``; None for Eq. 24.

    ``ValueError`` if the form lowers to a kernel form the Fortran core does not carry.
    """
    form = params.branch_forms()[0]
    code, block = form.lower(params.first_loading_table, params.H)
    if code == FIRST_EQ24:
        return None
    nj = int(block[0]) if block.size else 0
    if code != FIRST_TABULATED or nj < 2 or form.export_template is None:
        raise ValueError(
            f"the first-loading form {form.name!r} has no Fortran law core (kernel form {code}, "
            f"{nj} levels, template {form.export_template!r})"
        )
    u, v, d = (tuple(block[1 + i * nj : 1 + (i + 1) * nj].tolist()) for i in range(3))
    tm = params.tau_max * units.stress
    h = params.H * units.stress
    return FirstSpec(
        form.name,
        form.equation,
        form.export_template,
        tuple(h * math.exp(x) for x in u),
        tuple(math.exp(x) for x in v),
        u,
        v,
        d,
        tm * math.exp(v[0] - u[0]) / h,
    )


#: a pressure above this multiple of H cannot be the model's (the deck's units are not the
#: routine's); contact pressures stay below a few H in any forming model
UNIT_LIMIT_H = 100.0


#: the PNEWDT a routine called on Newton iterates (FRIC) returns for an iterate above 100 H: the
#: host retries the increment at this fraction of its size (Abaqus' and ccx's own cut-back factor)
CUT_FACTOR = 0.25
#: at this fraction of the size at which the increment first had an iterate above 100 H, the
#: routine asks for no further cut-back (three cut-backs by CUT_FACTOR take it to 1/64, within the
#: five the hosts allow per increment, Abaqus' IA and ccx's ia): the increment may converge, and
#: a converged pressure above 100 H then stops the run
CUT_FLOOR = 1.0 / 32.0


@dataclass(frozen=True)
class GuardSpec:
    """What every generated routine checks before it runs the law (docs/fe_codes.md, "Guards").

    Attributes
    ----------
    code : int
        The unit system the routine was exported for, as the deck states it (1 SI, 2 mm-t-s).
    units : str
        Its description, ``mm-t-s (MPa, mm)``.
    codes : str
        Every code with its unit system, for the messages (``1 = SI (Pa, m), 2 = ...``).
    p_unit : float
        ``100 H`` in the host's stress unit: a larger pressure stops the run (the deck's units
        are not the routine's).
    p_max : float or None
        The top of the calibrated pressure range in the host's unit (None: the parameter file
        records none, and no range warning is compiled in).
    other : str
        The unit system a pressure above ``p_unit`` points to (mm-t-s routine: SI).
    cut_factor, cut_floor : float
        A routine called on Newton iterates (``FRIC``): the ``PNEWDT`` it returns for an iterate
        above ``p_unit``, and the fraction of the increment's size at which it asks for no
        further cut-back (:data:`CUT_FACTOR`, :data:`CUT_FLOOR`).
    """

    code: int
    units: str
    codes: str
    p_unit: float
    p_max: float | None
    other: str
    cut_factor: float = CUT_FACTOR
    cut_floor: float = CUT_FLOOR

    def messages(self, state_name, units_input, implicit=False, zone=None):
        """The messages of the guards, ``{kind: (text before the value, text after it)}``.

        Kinds (the ``KIND`` of the routines' ``SBMF_MESSAGE``): 1 too few state variables
        (value: their number), 2 no unit system stated (no value: the second text is None),
        3 a stated unit system other than the routine's (value: the stated number), 4 a
        pressure above ``100 H`` in the call (value: the pressure; the explicit hosts and
        ``SBMF_FRICTION``), 5 a pressure beyond the calibrated range (the one warning; value:
        the pressure), 6 a converged pressure, the committed ``p_hist``, above ``100 H``
        (``FRIC``), 10 more properties than the unit system's (value: their number; ``FRIC``).
        ``state_name`` names the deck's state count (``DEPVAR``), ``units_input`` is ``(name,
        where)`` of its unit value
        (``PROPS(1)``, ``the data line of *FRICTION, USER, PROPERTIES=1``): the fields of
        :class:`frictionlaw.export.Routine`. ``implicit``: the routine's host calls it on
        Newton iterates and commits its state on convergence (``Routine.implicit``), so its
        range warning names the committed ``p_hist``. ``zone``: the label of the law in a
        zoned export (``zone 'rim' (rim.json)``), which its messages name (``""``: a zoned
        routine's deck-wide messages), and the state count that keeps the cache's law (4).
        """
        s = self.units.split("(")[1].split(",")[0]
        name, where = units_input
        pre = f"SBMF friction: {zone}: " if zone else "SBMF friction: "
        n_state = (
            "3 (p_hist, its cache, the status)"
            if zone is None
            else ("4 (p_hist, its cache, the status, the law that wrote the cache)")
        )
        top = "none" if self.p_max is None else f"{self.p_max:.6g} {s}"
        units = f"this routine was exported for {self.units} and the model {self.other}"
        limit = f" {s} > 100 H = {self.p_unit:.6g} {s}"
        only = f"its unit system {name} = {self.code} ({self.codes}): give only that value, {where}"
        seen = (
            "converged contact pressure (p_hist at the start of an increment) "
            if implicit
            else "contact pressure "
        )
        return {
            1: (
                f"{pre}{state_name} = ",
                ", but the routine needs at least 1 state variable (1: p_hist); set "
                f"{state_name} to {n_state}",
            ),
            2: (
                f"{pre}the deck does not state its unit system; this routine was exported "
                f"for {self.units}: set {name} = {self.code}, {where} ({self.codes})",
                None,
            ),
            3: (
                f"{pre}the deck states the unit system {name} = ",
                f", but this routine was exported for {self.units}, {name} = {self.code} "
                f"({self.codes}): export the routine for the deck's units "
                "(frictionlaw-export --units) or correct the deck",
            ),
            4: (f"{pre}contact pressure ", f"{limit}: {units}"),
            10: (f"{pre}the deck gives ", f" properties, but the routine takes one, {only}"),
            5: (
                f"{pre}{seen}",
                f" {s} is beyond the calibrated range (p_max = {top}): the law is "
                "extrapolated there. Written once per process; the largest pressure each "
                "contact point carried is its p_hist (state variable 1)",
            ),
            6: (
                f"{pre}converged contact pressure (p_hist, state variable 1) ",
                f"{limit}: {units}",
            ),
        }


def guard_spec(params, units):
    """The :class:`GuardSpec` of ``params`` exported in ``units``."""
    codes = ", ".join(f"{u.code} = {u.describe()}" for u in UNIT_SYSTEMS.values())
    others = [u for u in UNIT_SYSTEMS.values() if u.stress > units.stress]
    other = (
        "looks " + " or ".join(u.describe() for u in others)
        if others
        else f"does not use {units.stress_unit}: check the deck's units"
    )
    p_max = None if params.p_range is None else params.p_range[1] * units.stress
    return GuardSpec(
        units.code,
        units.describe(),
        codes,
        UNIT_LIMIT_H * params.H * units.stress,
        p_max,
        other,
    )


@dataclass(frozen=True)
class CoreLaw:
    """One law as ``core/sbmf_law.f`` renders it: its routines' prefix and its values.

    Attributes
    ----------
    prefix : str
        The prefix of its routines' names, five characters (``SBMF_`` for an export's one law:
        ``SBMF_SHEAR``; ``SZ01_``, ``SZ02_``, ... for the laws of a zoned export).
    law : dict
        ``TMAX, H, C1, XN1, C2, XN2`` in the host's units (:func:`law_constants`).
    continuous : bool
        ``params.continuous_reload``.
    reload, first : ReloadSpec or None, FirstSpec or None
        The tabulated forms (None: Eq. 25 of the paper, Eq. 24).
    kt : StiffnessSpec
        The stick stiffness source.
    ln_h : float
        ``ln H`` in the host's unit, as the runtime's ``log(H)`` gives it.
    guard : GuardSpec
        What the routine checks for this law (its ``100 H``, its ``p_max``).
    flat : FlatSpec or None
        The flattening block (``core/sbmf_flat.f``, issue 43); None without one.
    """

    prefix: str
    law: dict
    continuous: bool
    reload: "ReloadSpec | None"
    first: "FirstSpec | None"
    kt: StiffnessSpec
    ln_h: float
    guard: GuardSpec
    flat: "FlatSpec | None" = None


def core_law(params, units, kt, prefix="SBMF_"):
    """The :class:`CoreLaw` of ``params`` in ``units`` with the stick stiffness ``kt``."""
    law = law_constants(params, units)
    return CoreLaw(
        prefix,
        law,
        params.continuous_reload,
        reload_spec(params, units),
        first_spec(params, units),
        kt,
        math.log(law["H"]),
        guard_spec(params, units),
        flat_spec(params, units),
    )


def core_context(params, units, kt):
    """The values ``core/sbmf_core.f`` (the law core of every Fortran target) is rendered with.

    Parameters
    ----------
    params : FrictionParams
    units : UnitSystem
        The host's units (the constants are converted at export time).
    kt : StiffnessSpec or None
        The stick stiffness source (None for a table target, which renders no core).

    Returns
    -------
    dict
        ``laws``: the one :class:`CoreLaw` (``core/sbmf_law.f`` is rendered once per law;
        a zoned export has several, :func:`frictionlaw.export._zones.zoned_context`);
        ``zones``: None (one law everywhere); the law's values at the top level too (the
        entry templates and READMEs read them): ``law`` (``TMAX, H, C1, XN1, C2, XN2`` in the
        host's units), ``continuous`` (``params.continuous_reload``), ``reload`` (the tabulated
        reload form's :class:`ReloadSpec`, None for the paper's Eq. 25), ``first`` (the
        first-loading form's :class:`FirstSpec`, None for Eq. 24), ``kt``, ``ln_h`` (``ln H``
        in the host's unit, as the runtime's ``log(H)`` gives it, for the tabulated forms'
        ``ln(p_hist/H)`` and ``ln(p/H)`` where the quotient is not a normal double),
        ``guard``, the :class:`GuardSpec` (the unit system, ``100 H``, ``p_max``) every
        routine checks; and the shared constants :func:`shared_constants`.
    """
    one = core_law(params, units, kt)
    return {
        "laws": (one,),
        "zones": None,
        "law": one.law,
        "continuous": one.continuous,
        "reload": one.reload,
        "first": one.first,
        "kt": kt,
        "ln_h": one.ln_h,
        "guard": one.guard,
        "flat": one.flat,
        **shared_constants(),
    }


def shared_constants():
    """The constants every law's routines share.

    ``ln_small``, ``ln_sat`` (the smooth minimum's branch points ``ln(1e-4)``, ``ln(350)`` of ``frictionlaw._kernels``), ``ln_d_max`` (the
    tabulated form's bound 700 on ``ln(dtau/dp)`` where it is formed in logs), ``ln_q_start``
    (``ln Q_START``, below which the tabulated branch starts quadratically).
    """
    return {
        "ln_small": math.log(1e-4),
        "ln_sat": math.log(350.0),
        "ln_d_max": 700.0,
        "ln_q_start": math.log(Q_START),
    }


def _fit_summary(params):
    fit = params.provenance.get("fit", {}) if isinstance(params.provenance, dict) else {}
    out = []
    for key in ("first_loading", "reload"):
        f = fit.get(key)
        if isinstance(f, dict):
            r2, npts = f.get("r_squared"), f.get("n_points")
            # a tabulated form is judged by its error (no R^2; the first loading's table passes
            # through its points: no rmse either); a value the record lacks is left out
            parts = [
                f"{name}={v:{fmt}}"
                for name, v, fmt in (
                    ("R^2", r2, ".6g"),
                    ("rmse", f.get("rmse"), ".3g"),
                    ("max |d alpha|", None if r2 is not None else f.get("max_abs_residual"), ".3g"),
                )
                if isinstance(v, int | float)
            ]
            form = "" if r2 is not None else f"{f.get('form', '?')} form, "
            out.append(f"fit {key}: {form}{', '.join([*parts, f'points={npts}'])}")
    err = params.provenance.get("errors") if isinstance(params.provenance, dict) else None
    if isinstance(err, dict):
        held = [
            f"{k} {v['heldout_max']:.3g}"
            for k, v in err.items()
            if isinstance(v, dict) and isinstance(v.get("heldout_max"), (int, float))
        ]
        if held:
            out.append(
                "held-out max |d alpha|: "
                + ", ".join(held)
                + f" (tolerance {err.get('heldout_tol')})"
            )
    return out or ["fit summary: none recorded in the parameter file"]


def header_lines(target, params, params_path, sha, units, kt):
    """Provenance lines (without comment markers)."""
    return [
        f"SBMF friction law (Eqs. 24-26), target {target}",
        f"generated by frictionlaw-export {__version__}; do not edit by hand",
        f"parameter file: {Path(params_path).name}",
        f"sha256: {sha}",
        f"units: {units.name} (stress {units.stress_unit}, length {units.length_unit})",
        *law_lines(params, units, kt),
    ]


def law_lines(params, units, kt):
    """The provenance lines of one law: its parameters, forms, origin, range and fit."""
    s = units.stress_unit
    lines = [
        f"m={params.m!r} k={params.k * units.stress!r} {s}",
        *m_origin(params).header(),
        f"H={params.H * units.stress!r} {s} geo_ratio={params.geo_ratio!r}",
    ]
    first = first_spec(params, units)
    if first is None:
        lines += [
            "first-loading form: eq24 (Eq. 24, alpha1 = g(p C1/H; n1))",
            f"C1={params.C1!r} n1={params.n1!r}",
        ]
    else:
        lines += first.describe(units)
    spec = reload_spec(params, units)
    if spec is None:
        lines += [
            "reload form: paper (Eq. 25, one C2, n2 for every p_hist)",
            f"C2={params.C2!r} n2={params.n2!r}",
        ]
    else:
        lines += spec.describe(units)
    lines += [
        f"continuous_reload={params.continuous_reload}",
        f"tau_max=m k (1+geo_ratio)={params.tau_max * units.stress!r} {s}",
        f"mu_eff={'tau_max C1/H' if first is None else 'tau_max alpha_0/p_0'}={params.mu_eff!r}",
    ]
    if params.p_range is not None:
        lo, hi = (v * units.stress for v in params.p_range)
        lines.append(f"calibrated pressures: {lo:.6g}..{hi:.6g} {s}")
    lines += _fit_summary(params)
    if kt is not None:
        lines.append("stick stiffness: " + kt.describe(units))
    return lines
