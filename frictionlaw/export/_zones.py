"""Zones of an export (issue 42): several parameter files in one routine, chosen by name (private).

``frictionlaw-export TARGET --zone NAME=FILE ...`` writes one routine that carries each zone's
whole calibration (its ``m``, its forms, its range, its guards' ``H``) and chooses the law per
call by the name its host passes: a :class:`ZoneKey` of the target's record says which argument
(Abaqus/Standard ``CINAME``, or ``SLNAME`` / ``MSNAME``; Abaqus/Explicit ``surfInt``, or
``surfSec`` / ``surfMain``; LS-DYNA ``NOSL``; CalculiX ``CINAME``, the surface interaction's name
the patch passes; the host-neutral entry's ``ZONE``). Names are compared trimmed and
case-insensitive (:func:`frictionlaw.zone_key`); ``--params`` is the default law for every name
no zone gives. A name that no zone gives and no default covers stops the run (the host's error
exit; LS-DYNA: no friction there and the message, as its guards do).

Everything is decided here before any template is rendered: every zone's file is read and
checked, the names are checked against the target (:func:`plan_laws`); :func:`zoned_context` is
what the law core is rendered with (one :class:`frictionlaw.export._law.CoreLaw` per law, routine
prefixes ``SZ01_``, ``SZ02_``, ...), :func:`zoned_messages` the guards' texts, each zone's
numbers in its own messages, and :func:`zone_header` the provenance header's lines.
"""

import hashlib
from dataclasses import dataclass, replace
from pathlib import Path

from sbmf_cli import ParameterError

from ..params import FrictionParams
from ..zones import zone_key
from ._law import CoreLaw, core_law, law_lines, shared_constants, stiffness_spec
from ._origin import MOrigin, m_origin

__all__ = [
    "ZoneKey",
    "ExportLaw",
    "ZoneTable",
    "MAX_ZONES",
    "MAX_NAME",
    "parse_zone",
    "check_zone_names",
    "plan_laws",
    "zoned_context",
    "zoned_messages",
    "zone_header",
]

#: zones an export carries at most (the law's routine prefixes SZ01_ .. SZ99_, the default one
#: of them)
MAX_ZONES = 98
#: the longest zone name (the hosts' names: Abaqus' and CalculiX's are 80 characters)
MAX_NAME = 80


@dataclass(frozen=True)
class ZoneKey:
    """How a target's routine learns which zone a contact point is in.

    Attributes
    ----------
    name : str
        The value of ``--zone-by`` (``interaction``, ``slave``, ``master``, ``interface``,
        ``caller``).
    argument : str
        The host's argument the routine compares (``CINAME``, ``surfInt``, ``NOSL``, ``ZONE``).
    what : str
        What the argument is, for the README and the messages.
    number : bool
        The host passes a number (LS-DYNA's interface number ``NOSL``): zone names must be
        integers.
    """

    name: str
    argument: str
    what: str
    number: bool = False


def _sha256(path):
    with open(path, "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


@dataclass(frozen=True)
class ExportLaw:
    """One law of an export: a zone's parameter file, or the default one.

    ``index`` is the law's number in the routine (1 .. number of laws: the zones in the order
    given, the default last): the tag the state keeps beside the cache (state variable 4), and
    the prefix of its routines (``core.prefix``).
    """

    index: int
    name: str | None
    path: Path
    params: FrictionParams
    sha: str
    core: CoreLaw
    origin: MOrigin
    #: the file as the README and the messages name it: its name, with as many parent folders
    #: as tell it from the export's other files (every calibration writes ``params.json``)
    shown: str = ""

    @property
    def label(self):
        """``zone 'rim' (rim.json)``, or ``the default law (params.json)``."""
        if self.name is None:
            return f"the default law ({self.shown})"
        return f"zone '{self.name}' ({self.shown})"

    @property
    def key(self):
        """The name as the routine compares it: trimmed, upper case ('' for the default)."""
        return "" if self.name is None else zone_key(self.name)


@dataclass(frozen=True)
class ZoneTable:
    """The laws of a zoned export and how its routine chooses between them.

    ``laws``: the zones (in the order given), then the default law if there is one;
    ``default``: the default law's index (0: none, an unknown name stops the run).
    """

    key: ZoneKey
    laws: tuple
    default: int

    @property
    def zones(self):
        """The named laws."""
        return tuple(law for law in self.laws if law.name is not None)

    def names(self):
        """The zones' names as given, for messages: ``rim, flank``."""
        return ", ".join(law.name for law in self.zones)

    def by_length(self):
        """``[(length, [(KEY, index), ...]), ...]``: the names grouped by their trimmed length."""
        out: dict = {}
        for law in self.zones:
            out.setdefault(len(law.key), []).append((law.key, law.index))
        return sorted(out.items())


def parse_zone(text):
    """``(name, path)`` of a ``--zone NAME=FILE`` value; ParameterError naming ``zones``."""
    name, sep, path = str(text).partition("=")
    if not sep or not path.strip():
        raise ParameterError(
            f"{{zones}} takes NAME=PARAMS.json (a zone's name and its parameter file), got "
            f"{text!r}",
            "zones",
        )
    return name, path


def check_zone_names(zones, key):
    """Check the zones' names for ``key``'s host (ParameterError naming ``zones``).

    Every name trimmed non-empty, printable ASCII without quotes (the routine compares it as a
    Fortran string), at most :data:`MAX_NAME` characters, integers for a numbered key (LS-DYNA's
    ``NOSL``); no two the same when trimmed and compared case-insensitive; at most
    :data:`MAX_ZONES`.
    """
    if len(zones) > MAX_ZONES:
        raise ParameterError(f"{{zones}}: at most {MAX_ZONES} zones, got {len(zones)}", "zones")
    seen: dict[str, str] = {}
    for name, _ in zones:
        k = zone_key(name)
        if not k:
            raise ParameterError(f"{{zones}}: a zone's name is empty in {name!r}=...", "zones")
        if len(k) > MAX_NAME or any(not (32 <= ord(c) < 127) or c in "'\"" for c in k):
            raise ParameterError(
                f"{{zones}}: zone name {name!r} must be at most {MAX_NAME} printable ASCII "
                "characters without quotes (the host passes names of that kind)",
                "zones",
            )
        if key.number and not (k.isdigit() and 1 <= int(k) <= 2**31 - 1):
            raise ParameterError(
                f"{{zones}}: zone name {name!r} must be an integer >= 1: the routine chooses by "
                f"{key.argument}, {key.what}",
                "zones",
            )
        norm = str(int(k)) if key.number else k
        if norm in seen:
            raise ParameterError(
                f"{{zones}}: zone names {seen[norm]!r} and {name!r} are the same when trimmed and "
                "compared case-insensitive",
                "zones",
            )
        seen[norm] = name


def shown_names(paths):
    """Each file's name with the fewest parent folders that tell different files apart.

    ``calibration/params.json`` and ``mnt-1/params.json`` where both are ``params.json``; the
    same file given twice keeps one name.
    """
    full = [Path(p).resolve() for p in paths]
    depth = max(len(p.parts) for p in full)
    for k in range(1, depth + 1):
        names = ["/".join(p.parts[-k:]) for p in full]
        if len(set(names)) == len(set(full)):
            return names
    return [str(p) for p in full]


def plan_laws(params_path, zones, key, units, k_t, *, accept_failed, check):
    """Read and check every law of an export: ``(laws, table)``.

    ``zones``: ``[(name, path), ...]`` (empty: one law, ``params_path``, and ``table`` None);
    ``key``: the :class:`ZoneKey` the routine chooses by; ``check(params, path)`` refuses a
    file the export cannot carry (ValueError). Every file is read before any is used, so a bad
    one stops the export before anything is written.
    """
    entries = [(name, Path(path)) for name, path in zones]
    if params_path is not None:
        entries.append((None, Path(params_path)))
    laws = []
    for i, (name, path) in enumerate(entries, 1):
        params = FrictionParams.from_json(path, accept_failed=accept_failed)
        check(params, path)
        kt = stiffness_spec(params, units, k_t)
        prefix = "SBMF_" if not zones else f"SZ{i:02d}_"
        laws.append(
            ExportLaw(
                i,
                name,
                path,
                params,
                _sha256(path),
                core_law(params, units, kt, prefix),
                m_origin(params),
            )  # fmt: skip
        )
    shown = shown_names([law.path for law in laws])
    laws = [replace(law, shown=name) for law, name in zip(laws, shown, strict=True)]
    if not zones:
        return tuple(laws), None
    default = len(laws) if params_path is not None else 0
    return tuple(laws), ZoneTable(key, tuple(laws), default)


def zoned_context(table):
    """The values a zoned routine is rendered with (the keys of ``_law.core_context``).

    ``laws`` (one :class:`CoreLaw` per law), ``zones`` (the :class:`ZoneTable`), and, for the
    texts every law shares, the first law's ``guard`` (its unit system: the same for every law)
    and ``kt``; ``law``, ``first``, ``reload``, ``continuous`` and ``ln_h`` are the first
    law's (the README names each zone's own).
    """
    first = table.laws[0].core
    return {
        "laws": tuple(law.core for law in table.laws),
        "zones": table,
        "law": first.law,
        "continuous": first.continuous,
        "reload": first.reload,
        "first": first.first,
        "kt": first.kt,
        "ln_h": first.ln_h,
        "guard": first.guard,
        # the first flattening block of the zones (None without one): the templates declare and
        # run the flattening where it is set, each zone's law its own (SBMF_ZFSHR)
        # (a two-state one first: its slot counts are the routine's, flat_states)
        "flat": next(
            (law.core.flat for law in table.laws if law.core.flat and law.core.flat.limit),
            next((law.core.flat for law in table.laws if law.core.flat), None),
        ),
        **shared_constants(),
    }


def zoned_messages(table, state_name, units_input, implicit=False):
    """The guards' messages of a zoned routine, ``{kind: (before, after)}``.

    Kinds 1-3 and 10 (the deck: state variables, unit system, properties) once; kinds 4-6 (a pressure above
    ``100 H``, beyond the calibrated range, a committed ``p_hist`` above ``100 H``) once per law
    as ``kind + 10 i`` (law ``i``), each naming its zone and its own ``100 H`` and ``p_max``.
    The unknown name (kind 7) is ``SBMF_ZMESSAGE``'s, which names it.
    """
    deck = table.laws[0].core.guard.messages(state_name, units_input, implicit, zone="")
    out = {k: deck[k] for k in (1, 2, 3, 10)}
    for law in table.laws:
        text = law.core.guard.messages(state_name, units_input, implicit, zone=law.label)
        for k in (4, 5, 6):
            out[k + 10 * law.index] = text[k]
    return out


def unknown_message(table):
    """``(before, after)`` of the unknown-name message (kind 7; the name goes between)."""
    key = table.key
    return (
        f"SBMF friction: {key.argument} = '",
        f"' ({key.what}) is none of this routine's zones ({table.names()}) and the export has "
        "no default law: this contact would run no law. Export the routine with a zone of that "
        "name (frictionlaw-export --zone NAME=FILE) or a default law (--params), or correct the "
        "deck's name",
    )


def zone_header(table, units):
    """The provenance header's lines on the zones: how the routine chooses, then each law."""
    key = table.key
    default = (
        f"a name no zone gives runs the default law ({table.laws[table.default - 1].shown})"
        if table.default
        else "a name no zone gives stops the run (no default law)"
    )
    lines = [
        f"zones: {len(table.zones)}, chosen by {key.argument} ({key.what}), compared trimmed "
        f"and case-insensitive; {default}",
        "state variable 4: the law (zone number) that wrote the cache of state variable 2",
    ]
    for law in table.laws:
        head = f"zone {law.index} '{law.name}'" if law.name else f"law {law.index}, the default"
        lines += [
            f"{head}: parameter file {law.shown}",
            f"  sha256: {law.sha}",
            *(f"  {line}" for line in law_lines(law.params, units, law.core.kt)),
        ]
        if law.params.p_range is None:
            lines.append("  calibrated pressures: none recorded in the parameter file")
    return lines
