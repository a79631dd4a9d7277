"""One record per host target, and the registry :func:`frictionlaw.export.render` reads (private).

A :class:`Target` says everything the export writes for a target and how it is tested: the
host, the generated file and its template, the README's host section, the file's comment style,
the extra files, and the harness that drives the routine as the host does. Its ``form`` says
what the file carries: a :class:`Routine` (the law with its history as a Fortran user routine;
its entry template includes the law core ``core/sbmf_core.f``) or a :class:`Table` (the first
loading as a friction-coefficient table). Templates are named by their path below ``frictionlaw/export``
(see :mod:`frictionlaw.export._templates`) or by an absolute path.

Adding a target is one record here (or a :func:`register` call) and its templates; a new law
form for every target is ``core/sbmf_core.f`` and ``_law.core_context``.
"""

from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

from ._law import stiffness_spec
from ._tables import build_table
from ._templates import template_path
from ._zones import ZoneKey
from .harness import FRIC, SBMF_FRICTION, USRFRC, USRFRC_MPP, VFRIC, VFRICTION, Harness

__all__ = [
    "Host",
    "Style",
    "Extra",
    "Routine",
    "Table",
    "Target",
    "REGISTRY",
    "register",
    "target",
    "TARGETS",
    "CALCULIX_DIR",
]


@dataclass(frozen=True)
class Host:
    """A host FE code as the generated routines meet it.

    Attributes
    ----------
    name : str
        The host (program and solver) as the docs name it.
    exit_routine : str
        The host's own error exit: the routine a generated routine calls to end the analysis
        with an error (Abaqus/Standard ``XIT``).
    message_routine : str
        The host's message routine: how a generated routine writes a warning or the reason of
        an error exit into the host's own log (Abaqus/Standard ``STDB_ABQERR``).
    reference : str
        Where the host documents both.
    guards : str or None
        Template of ``SBMF_GUARD``, the one routine through which the generated routines'
        guards (state-variable count, unit system, pressure range; docs/fe_codes.md,
        "Guards") reach the host, written with the two routines above (Abaqus, CalculiX) or
        with what the host offers instead (LS-DYNA: its output units, no error exit). None:
        the host's routines are not generated (ANSYS: the host-neutral entry returns a
        status its caller reports).
    """

    name: str
    exit_routine: str
    message_routine: str
    reference: str
    guards: str | None = None


@dataclass(frozen=True)
class Style:
    """The generated file's comment marker (of the provenance header) and line length."""

    comment: str
    columns: int


#: fixed-form Fortran: comments from column 1, statements up to column 72
FIXED_FORM = Style("C", 72)


@dataclass(frozen=True)
class Extra:
    """A file written beside the generated one, copied verbatim from ``template``."""

    name: str
    template: str
    executable: bool = False


@dataclass(frozen=True)
class Routine:
    """The law with its history as a user routine (fixed-form Fortran, the law core included).

    Attributes
    ----------
    stick : str
        Template of the README's paragraph on the stick stiffness (it reads ``kt``).
    state : tuple of str
        How the README names state variable ``i``: ``state[0] + i + state[1]``.
    tested : str
        Template of the README's last paragraph: how the routine was tested.
    state_name : str
        The deck's (or caller's) count of state variables, as the guards' message names it.
    units_input : tuple of str
        ``(name, where)`` of the value by which the deck states its unit system (1 SI,
        2 mm-t-s), as the guards' message and the README name it.
    status : bool
        The routine returns its guards' status to its caller (``IERR`` of the host-neutral
        ``SBMF_FRICTION``) instead of reaching the host through ``Host.guards``.
    implicit : bool
        The host calls the routine on every Newton iterate and keeps its state only when the
        increment converges (Abaqus/Standard ``FRIC``, CalculiX): its guards act on the
        committed ``p_hist`` and ask for a cut-back (``PNEWDT``) where an iterate's pressure is
        above ``100 H`` (docs/fe_codes.md, "Guards"). False: every call commits (explicit
        hosts), or the caller decides (``SBMF_FRICTION``).
    zone_keys : tuple of ZoneKey
        The names by which a zoned routine (``--zone``) can choose its law, the default first
        (``--zone-by`` chooses another); empty: the target takes no zones.
    zone_refusal : str
        Why the target takes no zones (the message of a zoned export it refuses).
    bulk_strain : str
        How the host gives the routine the bulk plastic strain under a contact point, which a
        parameter file's flattening block reads (issue 43; the README says it); empty: it
        gives none.
    no_strain : str
        The warning (the guards' kind 9, once per process) of a routine whose law has a
        flattening block but whose host, or deck, gives it no bulk strain: the law then runs
        without flattening.
    bulk_strain_two, no_strain_two : str
        ``bulk_strain`` and ``no_strain`` for the two-state model (``"model":
        "limit-analysis"``), which keeps one more state (its flank slope) and reads no
        hardening modulus; empty: the one-state texts.
    total_strain : bool
        The host passes the point's total equivalent plastic strain but neither its flow
        stress nor its hardening modulus (LS-DYNA's ``usrfrc``, the patched CalculiX): a flow
        curve baked in at export (``--flow-curve``) gives both from the strain.
    """

    stick: str
    state: tuple = ("STATEV(", ")")
    tested: str = "readme/tested.md"
    state_name: str = "DEPVAR"
    units_input: tuple = ("PROPS(1)", "the data line of *FRICTION, USER, PROPERTIES=1")
    status: bool = False
    implicit: bool = False
    zone_keys: tuple = ()
    zone_refusal: str = "takes no zones"
    bulk_strain: str = ""
    total_strain: bool = False
    no_strain: str = ""
    bulk_strain_two: str = ""
    no_strain_two: str = ""
    #: the README's frame (it includes ``stick``, the target's section and ``tested``)
    frame: ClassVar[str] = "readme/routine.md"
    #: ``--k-t`` applies
    takes_k_t: ClassVar[bool] = True
    #: ``--table-tol`` applies
    takes_table_tol: ClassVar[bool] = False

    def decide(self, params, units, k_t, table_tol):
        """``(stiffness, table)``: the stick stiffness source; a routine has no table."""
        return stiffness_spec(params, units, k_t), None

    def templates(self):
        """The templates this form reads besides the target's own."""
        return (self.frame, self.stick, self.tested)


@dataclass(frozen=True)
class Table:
    """The first-loading law as a friction-coefficient table, a function of the pressure alone.

    The first loading of the form the parameter file runs (Eq. 24 or the tabulated first
    loading): a table carries no history.
    """

    frame: ClassVar[str] = "readme/table.md"
    takes_k_t: ClassVar[bool] = False
    takes_table_tol: ClassVar[bool] = True
    zone_keys: ClassVar[tuple] = ()
    zone_refusal: ClassVar[str] = (
        "writes a friction table, one law of the pressure alone for the contact it is "
        "assigned to: export one table per zone's parameter file instead"
    )

    def decide(self, params, units, k_t, table_tol):
        """``(stiffness, table)``: no stiffness; the table (RuntimeError if ``table_tol`` fails)."""
        return None, build_table(params, table_tol)

    def templates(self):
        """The templates this form reads besides the target's own."""
        return (self.frame,)


@dataclass(frozen=True)
class Target:
    """One host target of ``frictionlaw-export``.

    Attributes
    ----------
    name : str
        The target's name on the command line (``abaqus-fric``).
    host : Host
        The FE code and its error exit and message routine.
    file : str
        Name of the generated file (``sbmf_fric.f``).
    template : str
        Its template (a Fortran entry point that includes the law core, or a table deck); the
        provenance header is written above it in ``style``.
    readme : str
        Template of the README's host section (how to compile and activate).
    form : Routine or Table
        What the file carries, and the README frame that goes with it.
    style : Style
        Comment marker and line length of the generated file (every line is checked).
    extras : tuple of Extra
        Files copied beside it (CalculiX: the patch, its build script, ``ABA_PARAM.INC``).
    harness : frictionlaw.export.harness.Harness or None
        How the tests call the routine as the host does (None: a table).
    products : tuple of str
        Files a later step adds to the export folder (CalculiX: the ``ccx`` that ``build.sh``
        links there); they count as the export's own when ``--force`` replaces the folder.
    """

    name: str
    host: Host
    file: str
    template: str
    readme: str
    form: Routine | Table
    style: Style = FIXED_FORM
    extras: tuple = ()
    harness: Harness | None = None
    products: tuple = ()

    def templates(self):
        """Every template file this target reads (its includes aside), as absolute paths."""
        names = (self.template, self.readme, *self.form.templates())
        names += (self.host.guards,) if self.host.guards else ()
        names += tuple(e.template for e in self.extras)
        names += (self.harness.shim, *self.harness.support) if self.harness is not None else ()
        return tuple(template_path(n) for n in names)


#: every target by name, in the order the command lists them
REGISTRY: dict[str, Target] = {}


def register(record):
    """Add ``record`` to the targets :func:`frictionlaw.export.render` knows; returns it."""
    if record.name in REGISTRY:
        raise ValueError(f"a target named {record.name!r} is registered already")
    REGISTRY[record.name] = record
    return record


def target(name):
    """The record of target ``name`` (ValueError naming the known ones if there is none)."""
    try:
        return REGISTRY[name]
    except (KeyError, TypeError):
        raise ValueError(f"target must be one of {', '.join(REGISTRY)}; got {name!r}") from None


# -- the hosts ---------------------------------------------------------------------------------
_ABAQUS_GUARDS = "abaqus/guards.f"
ABAQUS_STANDARD = Host(
    "Abaqus/Standard",
    "XIT",
    "STDB_ABQERR",
    "Abaqus User Subroutines Reference, utility routines: terminating an analysis (XIT), "
    "printing messages to the message or status file (STDB_ABQERR)",
    _ABAQUS_GUARDS,
)
ABAQUS_EXPLICIT = Host(
    "Abaqus/Explicit",
    "XPLB_EXIT",
    "XPLB_ABQERR",
    "Abaqus User Subroutines Reference, utility routines: terminating an analysis (XPLB_EXIT), "
    "printing messages to the status file (XPLB_ABQERR)",
    _ABAQUS_GUARDS,
)
LSDYNA = Host(
    "LS-DYNA",
    "none documented (the law is refused: no friction)",
    "WRITE to LS-DYNA's output units IOTTY, IOHSP, IOMSG (iounits.inc)",
    "LSTC's user-routine file dyn21.f: its sample routines write their messages to the "
    "terminal, d3hsp and messag units of iounits.inc; an error exit for user code is not "
    "documented (older samples call ADIOS(2), the current ones LSTC's own message catalogue)",
    "lsdyna/guards.f",
)
ANSYS = Host(
    "ANSYS Mechanical APDL",
    "ERHANDLER (error level)",
    "ERHANDLER",
    "ANSYS Programmer's Reference, 'Subroutine erhandler (Displays Program Errors)'",
)
CALCULIX = Host(
    "CalculiX 2.20 (patched ccx)",
    "XIT",
    "STDB_ABQERR",
    "the user-friction patch (xit.f, stdb_abqerr.f): Abaqus' utility routines for CalculiX; "
    "an error closes ccx's files and exits with status 201, as ccx's own errors do",
    _ABAQUS_GUARDS,
)

#: CalculiX: the patch and its build script ship with the package (frictionlaw/export/calculix)
CALCULIX_DIR = Path(template_path("calculix"))

# -- the names a zoned routine chooses by (frictionlaw-export --zone, --zone-by) ---------------
_INTERACTION = "the contact interaction's name"
_FRIC_KEYS = (
    ZoneKey("interaction", "CINAME", _INTERACTION),
    ZoneKey("slave", "SLNAME", "the slave surface's name"),
    ZoneKey("master", "MSNAME", "the master surface's name"),
)
_EXPLICIT_KEYS = (
    ZoneKey("interaction", "surfInt", _INTERACTION),
    ZoneKey("slave", "surfSec", "the secondary (slave) surface's name"),
    ZoneKey("master", "surfMain", "the main (master) surface's name"),
)
_LSDYNA_KEYS = (ZoneKey("interface", "NOSL", "the contact interface's number", number=True),)
_NEUTRAL_KEYS = (ZoneKey("caller", "ZONE", "the zone name the caller passes"),)
_CALCULIX_KEYS = (
    ZoneKey("interaction", "CINAME", "the surface interaction's name, which the patch passes"),
)

# -- the targets -------------------------------------------------------------------------------
_NOT_RUN = "the parameter file's flattening block (issue 43) is not run: "
_CCX_STRAIN = (
    "PREDEF(1, 1) and PREDEF(2, 1) (NPRED = 1), the equivalent plastic "
    "strain under the contact point (CalculiX's PEEQ averaged over a solid element's "
    "integration points: face-to-face, the slave point's element; node-to-surface, the "
    "elements of the slave node's faces, weighted as its area) at the iterate and its "
    "increment over the increment, which the patched ccx passes; "
)


def _usrfrc_strain(passes, slots, count, strain_count):
    """The bulk-strain texts of an LS-DYNA usrfrc target (``Routine`` keywords), both models.

    ``passes``: the argument that gives the element's plastic strain; ``slots``: the history
    slots 5.. (``{}`` their last); ``count``: the deck's history count; ``strain_count``: the
    count of strain values. The one-state model keeps 5-7, the two-state model 5-8.
    """
    one = "the flattened fraction, the plastic strain and the cycle of the last call"
    two = "the flattened fraction, the plastic strain, the cycle of the last call and the {}slope"
    run = f"{passes}; its increment between consecutive cycles in contact, "
    few = f"the deck gives no element plastic strain ({strain_count} = 0) or too few history "
    slope = two.format("two-state model's flank ")
    return {
        "bulk_strain": f"{run}{slots.format(7)} holding {one} ({count} >= 7)",
        "bulk_strain_two": f"{run}{slots.format(8)} holding {two.format('flank ')} ({count} >= 8)",
        "no_strain": f"{_NOT_RUN}{few}variables ({count} < 7; 5-7 hold {one}){_WITHOUT}",
        "no_strain_two": f"{_NOT_RUN}{few}variables ({count} < 8; 5-8 hold {slope}){_WITHOUT}",
    }


_NEUTRAL_TWO = (
    "DEPS and SIGY, the arguments of SBMF_FRICTION_V (the caller's bulk plastic strain "
    "increment and flow stress under the point), STATE(5) the flattened fraction and STATE(7) "
    "the flank slope (NSTATE >= 7; STATE(6), the one-state model's hardening modulus, is not "
    "read)"
)
_WITHOUT = ": the law runs without flattening under bulk strain (written once per process)"
_ABAQUS_NO_STRAIN = (
    "{routine} receives no plastic strain of the underlying element (its arguments carry "
    "the contact point's pressure, slip, temperature and predefined fields; GETVRM, which "
    "reads material points, is callable from USDFLD and UVARM only)"
)
_CHRLNGTH = "abaqus/stick_chrlngth.md"
_STICK_FORCE = "abaqus/stick_force.md"
_KHOST = "neutral/stick_khost.md"

for _record in (
    Target(
        "abaqus-fric",
        ABAQUS_STANDARD,
        "sbmf_fric.f",
        "abaqus/fric.f",
        "abaqus/fric.md",
        Routine(
            stick=_CHRLNGTH,
            implicit=True,
            zone_keys=_FRIC_KEYS,
            no_strain=_NOT_RUN + _ABAQUS_NO_STRAIN.format(routine="FRIC") + _WITHOUT,
        ),
        harness=FRIC,
    ),
    Target(
        "abaqus-vfric",
        ABAQUS_EXPLICIT,
        "sbmf_vfric.f",
        "abaqus/vfric.f",
        "abaqus/vfric.md",
        Routine(
            stick=_STICK_FORCE,
            state_name="DEPVAR (nStateVar)",
            units_input=("props(1)", "the data line of *FRICTION, USER=VFRIC, PROPERTIES=1"),
            zone_keys=_EXPLICIT_KEYS,
            no_strain=_NOT_RUN + _ABAQUS_NO_STRAIN.format(routine="VFRIC") + _WITHOUT,
        ),
        harness=VFRIC,
    ),
    Target(
        "abaqus-vfriction",
        ABAQUS_EXPLICIT,
        "sbmf_vfriction.f",
        "abaqus/vfriction.f",
        "abaqus/vfriction.md",
        Routine(
            stick=_STICK_FORCE,
            state=("state(", ", j, k)"),
            state_name="DEPVAR (nStates)",
            units_input=("props(1)", "the data line of *FRICTION, USER=VFRICTION, PROPERTIES=1"),
            zone_keys=_EXPLICIT_KEYS,
            no_strain=_NOT_RUN + _ABAQUS_NO_STRAIN.format(routine="VFRICTION") + _WITHOUT,
        ),
        harness=VFRICTION,
    ),
    Target(
        "lsdyna-usrfrc",
        LSDYNA,
        "sbmf_usrfrc_smp.f",
        "lsdyna/usrfrc_smp.f",
        "lsdyna/usrfrc_smp.md",
        Routine(
            stick="lsdyna/stick_penalty.md",
            state=("UFHIST(", ", ILBSV(II))"),
            state_name="NHV (user friction history variables)",
            units_input=("UA(1)", "the first user parameter of *USER_INTERFACE_FRICTION"),
            zone_keys=_LSDYNA_KEYS,
            total_strain=True,
            **_usrfrc_strain(
                "UFEPS(1, ILBSV(II)), the plastic strain of the slave node's element that "
                "LS-DYNA passes (NEPS >= 1)",
                "UFHIST(5..{}, .)",
                "NHV",
                "NEPS",
            ),
        ),
        harness=USRFRC,
    ),
    Target(
        "lsdyna-usrfrc-mpp",
        LSDYNA,
        "sbmf_usrfrc_mpp.f",
        "lsdyna/usrfrc_mpp.f",
        "lsdyna/usrfrc_mpp.md",
        Routine(
            stick="lsdyna/stick_coefficient.md",
            state=("UH(", ")"),
            state_name="NH (user friction history variables)",
            units_input=("UC(1)", "the first user parameter of *USER_INTERFACE_FRICTION"),
            zone_keys=_LSDYNA_KEYS,
            total_strain=True,
            **_usrfrc_strain(
                "UE(1), the plastic strain of the slave node's element that LS-DYNA passes "
                "(NE >= 1; LSTC's sample: not for SOFT = 4)",
                "UH(5..{})",
                "NH",
                "NE",
            ),
        ),
        harness=USRFRC_MPP,
    ),
    Target(
        "lsdyna",
        LSDYNA,
        "sbmf_lsdyna.f",
        "neutral/sbmf_friction.f",
        "lsdyna/lsdyna.md",
        Routine(
            stick=_KHOST,
            state=("history variable ", ""),
            state_name="the history variables",
            units_input=("IUNIT", "SBMF_FRICTION's argument, from the deck's user parameters"),
            status=True,
            zone_keys=_NEUTRAL_KEYS,
            bulk_strain="DEPS and SIGY, the arguments of SBMF_FRICTION_V (the caller's bulk "
            "plastic strain increment and flow stress under the point), STATE(5) the "
            "flattened fraction (NSTATE >= 5), STATE(6) the bulk's hardening modulus, an input "
            "the caller sets (NSTATE >= 6; without it the perfectly plastic rate, an upper limit "
            "for a hardening metal)",
            bulk_strain_two=_NEUTRAL_TWO,
            no_strain=_NOT_RUN + "NSTATE < 5 leaves no state slot for the flattened fraction "
            "(STATE(5))" + _WITHOUT + " (IERR = 9)",
            no_strain_two=_NOT_RUN + "NSTATE < 7 leaves no state slots for the two-state "
            "model's flattened fraction and flank slope (STATE(5), STATE(7))"
            + _WITHOUT
            + " (IERR = 9)",
        ),
        harness=SBMF_FRICTION,
    ),
    Target(
        "ansys-userfric",
        ANSYS,
        "sbmf_userfric.f",
        "neutral/sbmf_friction.f",
        "ansys/userfric.md",
        Routine(
            stick=_KHOST,
            state=("state variable ", ""),
            state_name="NSVR",
            units_input=("IUNIT", "SBMF_FRICTION's argument, from the TB,FRIC user constants"),
            status=True,
            zone_refusal="takes no zones: the argument list of ANSYS' userfric is not public, so "
            "which name of the contact the host could pass is not known (docs/fe_codes.md, "
            "ANSYS); export one routine per parameter file",
            bulk_strain="DEPS and SIGY, the arguments of SBMF_FRICTION_V (the caller's bulk "
            "plastic strain increment and flow stress under the point), STATE(5) the "
            "flattened fraction (NSTATE >= 5), STATE(6) the bulk's hardening modulus, an input "
            "the caller sets (NSTATE >= 6; without it the perfectly plastic rate, an upper limit "
            "for a hardening metal)",
            bulk_strain_two=_NEUTRAL_TWO,
            no_strain=_NOT_RUN + "NSTATE < 5 leaves no state slot for the flattened fraction "
            "(STATE(5))" + _WITHOUT + " (IERR = 9)",
            no_strain_two=_NOT_RUN + "NSTATE < 7 leaves no state slots for the two-state "
            "model's flattened fraction and flank slope (STATE(5), STATE(7))"
            + _WITHOUT
            + " (IERR = 9)",
        ),
        harness=SBMF_FRICTION,
    ),
    Target(
        "calculix",
        CALCULIX,
        "sbmf_fric.f",
        "abaqus/fric.f",  # the abaqus-fric routine (but for the flattening's PREDEF field)
        "calculix/calculix.md",
        Routine(
            stick=_CHRLNGTH,
            tested="calculix/tested.md",
            units_input=(
                "PROPS(1)",
                "the data line of *FRICTION, USER, PROPERTIES=1, in a ccx deck the name "
                "MM-T-S (2.) or SI (1.)",
            ),
            implicit=True,
            zone_keys=_CALCULIX_KEYS,
            total_strain=True,
            bulk_strain=_CCX_STRAIN + "STATEV(5) the flattened fraction (DEPVAR >= 5)",
            bulk_strain_two=_CCX_STRAIN + "STATEV(5) the flattened fraction and STATEV(6) the "
            "flank slope (DEPVAR >= 6)",
            no_strain="the parameter file's flattening block (issue 43) does not grow here: "
            "the patched ccx passes no plastic strain for layered (composite) or beam-derived "
            "slave elements; the law runs with the flattened fraction it has (written once "
            "per process)",
        ),
        extras=(
            Extra("ABA_PARAM.INC", "abaqus/ABA_PARAM.INC"),
            Extra(
                "calculix-2.20-user-friction.patch", "calculix/calculix-2.20-user-friction.patch"
            ),
            Extra("build.sh", "calculix/build.sh", executable=True),
        ),
        harness=FRIC,
        products=("ccx",),  # build.sh links it here; its build tree is elsewhere
    ),
    Target(
        "abaqus-table",
        ABAQUS_STANDARD,
        "sbmf_friction_table.inp",
        "abaqus/table.inp",
        "abaqus/table.md",
        Table(),
        style=Style("**", 100),
    ),
    Target(
        "lsdyna-table",
        LSDYNA,
        "sbmf_friction_table.k",
        "lsdyna/table.k",
        "lsdyna/table.md",
        Table(),
        style=Style("$", 80),
    ),
):
    register(_record)

#: the targets shipped with the package, in the command's order
TARGETS = tuple(REGISTRY)
