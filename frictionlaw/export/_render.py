"""What :func:`render` and :func:`export` do with a target's record (private).

First decide (:func:`plan`): the target's record, the unit system, the parameter file, its
sha256, the stick stiffness or the table; all bad input is refused there, before any file is
rendered. Then run: the generated file (provenance header + the target's template), the README
(the form's frame with the target's sections) and the extra files, each from the record alone.
"""

from dataclasses import dataclass
from pathlib import Path

from sbmf_cli import OutputFolder, ParameterError

from .. import __version__
from ..params import FrictionParams
from . import _targets
from ._flat import flat_states, flow_spec
from ._law import UNIT_SYSTEMS, StiffnessSpec, UnitSystem, core_context, header_lines
from ._tables import TABLE_TOL, FrictionTable
from ._templates import check_columns, comment_block, render_template, template_path
from ._zones import (
    ZoneTable,
    check_zone_names,
    plan_laws,
    unknown_message,
    zone_header,
    zoned_context,
    zoned_messages,
)

__all__ = ["Job", "plan", "texts", "render", "export", "ExportResult"]


@dataclass(frozen=True)
class ExportResult:
    """What :func:`export` wrote: the folder, its files, and the table (table targets).

    ``removed``: what a later step had added to the earlier export in the folder (the target's
    ``products``, CalculiX's ``ccx`` that ``build.sh`` linked) and the replacement removed.
    """

    out: Path
    files: tuple
    table: object = None
    removed: tuple = ()


@dataclass(frozen=True)
class Job:
    """One export, decided: everything its files are rendered from.

    Attributes
    ----------
    target : Target
        The target's record.
    params : FrictionParams
    units : UnitSystem
        The host's units.
    sha : str
        sha256 of the parameter file.
    kt : StiffnessSpec or None
        The stick stiffness source (None for a table).
    table : FrictionTable or None
        The first loading's friction-coefficient table (table targets).
    header : tuple of str
        The provenance lines every generated file starts with.
    law : dict
        The values the law core is rendered with (:func:`frictionlaw.export._law.core_context`,
        or :func:`frictionlaw.export._zones.zoned_context` for a zoned export).
    laws : tuple of ExportLaw
        Every law of the export (one, or the zones and the default), each with its file,
        sha256 and origin of ``m``.
    zones : ZoneTable or None
        How a zoned routine chooses its law (None: one law everywhere).
    """

    target: _targets.Target
    params: FrictionParams
    units: UnitSystem
    sha: str
    kt: StiffnessSpec | None
    table: FrictionTable | None
    header: tuple
    law: dict
    laws: tuple = ()
    zones: ZoneTable | None = None


#: the message of status -8 of the host-neutral SBMF_FRICTION_V (the interface version)
VERSION_MESSAGE = (
    "SBMF friction: SBMF_FRICTION_V was called for interface version IVERS = ",
    ", but this routine implements version 2 (the argument list of its header): call it as "
    "the README says, or export the routine again for the caller's version",
)


def _check_exportable(params, path):
    """``ValueError`` if a form the file runs has no law-core template (it would export wrong)."""
    for form in params.branch_forms():
        if form.export_template is None:
            other = "eq24" if form.branch == "first_loading" else "paper"
            raise ValueError(
                f"{path}: its {form.branch.replace('_', ' ')} form {form.name!r} ({form.equation}) "
                "is not carried by the Fortran law core yet, and an export would run another "
                f"law: run the file in the Python runtime, or switch the form to {other!r} "
                f"(FrictionParams.replace({form.branch}_form={other!r}) keeps the calibration's "
                "table in the file) and export that"
            )


def _strain_targets(test):
    """The names of the routine targets whose form passes ``test`` (the hosts giving a strain)."""
    forms = {name: _targets.target(name).form for name in _targets.TARGETS}
    return [n for n, f in forms.items() if isinstance(f, _targets.Routine) and test(f)]


def _check_flattening(record, laws, zones, without_flattening=False):
    """``ValueError`` where a file's flattening block (issue 43) would be lost without a word.

    A routine whose host passes the bulk strain runs it; a routine whose host passes none
    (Abaqus FRIC, VFRIC, VFRICTION) runs the law without it only when the user says so
    (``without_flattening``; the routine then also says it once at run time), and so does a
    table (a law of the pressure alone; its header says so). A zoned routine runs each zone's
    own block. ``without_flattening``
    where nothing would be dropped is refused too (no option silently ignored).
    """
    flat = [law for law in laws if law.params.flattening is not None]
    if not flat:
        if without_flattening:
            raise ParameterError(
                "{without_flattening} applies to a parameter file with a flattening block "
                "(a calibration run with the flattening on); this one has none: leave it out",
                "without_flattening",
            )
        return
    path = flat[0].path
    if not isinstance(record.form, _targets.Routine):
        if without_flattening:
            return  # the table of the law without it; its header says so
        raise ParameterError(
            f"{path}: the file carries a flattening block (issue 43): {record.name} writes a "
            "table of the pressure alone, which cannot carry it: give {without_flattening} to "
            "export the law without it, or export a routine target whose host passes the "
            f"strain ({', '.join(_strain_targets(lambda f: f.bulk_strain))})",
            "without_flattening",
        )
    if record.form.bulk_strain and without_flattening:
        raise ParameterError(
            f"{{without_flattening}}: {record.name} runs the flattening (its host passes the "
            "bulk strain); leave the option out",
            "without_flattening",
        )
    if not record.form.bulk_strain and not without_flattening:
        raise ParameterError(
            f"{path}: the file carries a flattening block (issue 43), but {record.name}'s host "
            "passes no bulk plastic strain to the routine, so the law would run without it: "
            "give {without_flattening} to export it that way, or export for a host that "
            f"passes the strain ({', '.join(_strain_targets(lambda f: f.bulk_strain))})",
            "without_flattening",
        )


def _flow_curve(record, laws, flow_curve):
    """The flow curve to bake in (``--flow-curve``), or None; ParameterError where it is not read.

    Only a routine whose host passes the total plastic strain but not the flow stress and
    hardening modulus (LS-DYNA's ``usrfrc``, the patched CalculiX) reads one, and only for a law with a flattening
    block.
    """
    if flow_curve is None:
        return None
    if not (isinstance(record.form, _targets.Routine) and record.form.total_strain):
        how = (
            "its caller passes the flow stress (SIGY) and the hardening modulus (STATE(6))"
            if isinstance(record.form, _targets.Routine) and record.form.bulk_strain
            else "its host passes no bulk plastic strain"
        )
        raise ParameterError(
            f"{{flow_curve}} applies to {', '.join(_strain_targets(lambda f: f.total_strain))}, "
            "whose host passes the element's plastic strain but not its flow stress and "
            f"hardening; {record.name}: {how}",
            "flow_curve",
        )
    if not any(law.params.flattening is not None for law in laws):
        raise ParameterError(
            "{flow_curve} is read by the flattening under bulk strain: this parameter file has "
            "no flattening block (a calibration with the flattening on); leave it out",
            "flow_curve",
        )
    if isinstance(flow_curve, str):
        from ..flow_curve import read_flow_curve

        return read_flow_curve(flow_curve)
    return flow_curve


def _zone_key(record, zones, zone_by):
    """The :class:`ZoneKey` a zoned export of ``record`` chooses by (ParameterError if none)."""
    if not zones:
        if zone_by is not None:
            raise ParameterError("{zone_by} applies with {zones} only", "zone_by", "zones")
        return None
    keys = record.form.zone_keys
    if not keys:
        raise ParameterError(f"{{zones}}: {record.name} {record.form.zone_refusal}", "zones")
    if zone_by is None:
        return keys[0]
    for key in keys:
        if key.name == zone_by:
            return key
    raise ParameterError(
        f"{{zone_by}} must be one of {', '.join(k.name for k in keys)} for {record.name} "
        f"(the host passes {', '.join(k.argument for k in keys)}), got {zone_by!r}",
        "zone_by",
    )


def plan(
    target,
    params_path=None,
    *,
    zones=(),
    zone_by=None,
    units="SI",
    k_t=None,
    table_tol=None,
    accept_failed=False,
    without_flattening=False,
    flow_curve=None,
):
    """Decide an export (:class:`Job`); raises ValueError (or FileNotFoundError) on bad input.

    The options are checked before any parameter file is read, and every file (each zone's
    and the default) before anything is rendered; a table that cannot meet ``table_tol`` is a
    RuntimeError.
    """
    record = _targets.target(target)
    if units not in UNIT_SYSTEMS:
        raise ValueError(f"units must be one of {', '.join(UNIT_SYSTEMS)}; got {units!r}")
    if table_tol is not None and not record.form.takes_table_tol:
        raise ParameterError(
            "{table_tol} applies to the table targets only (a routine runs the law itself)",
            "table_tol",
        )
    table_tol = TABLE_TOL if table_tol is None else table_tol
    if not (1e-6 <= float(table_tol) <= 0.1):
        raise ParameterError(
            f"{{table_tol}} must be in [1e-6, 0.1], got {table_tol!r}", "table_tol"
        )
    if k_t is not None and not record.form.takes_k_t:
        raise ParameterError(
            "{k_t} applies to the Fortran targets only (a table has no stiffness)", "k_t"
        )
    zones = list(zones.items()) if isinstance(zones, dict) else list(zones)
    key = _zone_key(record, zones, zone_by)
    if params_path is None and not zones:
        raise ParameterError(
            "give {params_path} (the law) or {zones} (a law per zone)", "params_path", "zones"
        )
    if zones:
        check_zone_names(zones, key)
    us = UNIT_SYSTEMS[units]
    laws, table = plan_laws(
        params_path, zones, key, us, k_t, accept_failed=accept_failed, check=_check_exportable
    )
    _check_flattening(record, laws, zones, without_flattening)
    curve = _flow_curve(record, laws, flow_curve)
    params, sha = laws[0].params, laws[0].sha
    if table is None:
        kt, ftable = record.form.decide(params, us, k_t, table_tol)
        header = tuple(header_lines(record.name, params, laws[0].path, sha, us, kt))
        if params.flattening is not None and not isinstance(record.form, _targets.Routine):
            header += (
                "the file's flattening block (issue 43) is not carried (--without-flattening): "
                "a table is a law of the pressure alone",
            )
        ctx = core_context(params, us, kt)
        ctx["flow"] = None if curve is None else flow_spec(curve, us)
        if curve is not None:
            header += (
                f"flow curve of the workpiece (--flow-curve): {curve.describe()}: its flow "
                "stress and hardening modulus at the element's plastic strain",
            )
        return Job(record, params, us, sha, kt, ftable, header, ctx, laws)
    header = (
        f"SBMF friction law (Eqs. 24-26), target {record.name}, {len(laws)} laws by zone",
        f"generated by frictionlaw-export {__version__}; do not edit by hand",
        f"units: {us.name} (stress {us.stress_unit}, length {us.length_unit})",
        *zone_header(table, us),
    )
    ctx = zoned_context(table)
    ctx["flow"] = None
    return Job(record, params, us, sha, ctx["kt"], None, header, ctx, laws, table)


def texts(job, *, guards=True):
    """``{file name: text}`` of a decided export: its file, README.md, then the extra files.

    The generated file is the provenance header in the target's comment style, then its
    template; each of its lines is checked against the style's column limit (ValueError).
    ``guards=False`` leaves the routines' guards out (docs/fe_codes.md, "Guards"): only for
    ``benchmarks/bench_fortran_law.py``, which times their cost; never shipped.
    """
    t = job.target
    words = (
        (t.form.state_name, t.form.units_input, t.form.implicit)
        if isinstance(t.form, _targets.Routine)
        else ("", ("", ""))
    )
    context = {
        "target": t,
        "host": t.host,
        "name": t.file,
        "params": job.params,
        "units": job.units,
        "sha": job.sha,
        "table": job.table,
        "guards": guards,
        "origin": job.laws[0].origin,
        "export_laws": job.laws,
        **job.law,
    }
    if context.get("flat") is not None and isinstance(t.form, _targets.Routine):
        context["flat_states"] = flat_states(t.form, context["flat"])
    if job.zones is not None:
        context["guard_text"] = zoned_messages(job.zones, *words)
        context["zone_text"] = unknown_message(job.zones)
    elif "guard" in context:
        context["guard_text"] = context["guard"].messages(*words)
    if "guard_text" in context:
        if isinstance(t.form, _targets.Routine) and t.form.status:
            context["guard_text"][8] = VERSION_MESSAGE
        if context.get("flat") is not None and isinstance(t.form, _targets.Routine):
            # kind 9: the law runs without its flattening
            two = context["flat"].limit is not None and t.form.no_strain_two
            text = t.form.no_strain_two if two else t.form.no_strain
            context["guard_text"][9] = ("SBMF friction: " + text, None)
        context["guard_kinds"] = max(*context["guard_text"], 7 if job.zones else 6)
    text = comment_block(job.header, t.style.comment, t.style.columns)
    text += render_template(t.template, **context)
    files = {
        t.file: check_columns(text, t.style.columns, t.file),
        "README.md": render_template(t.form.frame, **context),
    }
    for extra in t.extras:
        files[extra.name] = template_path(extra.template).read_text(encoding="utf-8")
    return files


def render(target, params_path=None, **options):
    """The files of ``target`` as ``{name: text}`` plus the table (or None); writes nothing.

    The arguments are those of :func:`export` (``options``: its keyword arguments but ``force``).
    """
    job = plan(target, params_path, **options)
    return texts(job), job.table


def export(
    target,
    params_path,
    out,
    *,
    zones=(),
    zone_by=None,
    units="SI",
    k_t=None,
    table_tol=None,
    force=False,
    accept_failed=False,
    without_flattening=False,
    flow_curve=None,
):
    """Write ``target``'s files for the parameter file ``params_path`` into the folder ``out``.

    Parameters
    ----------
    target : str
        A registered target's name (:data:`TARGETS`: the shipped ones).
    params_path : path or None
        ``params.json`` written by the calibration (or :meth:`FrictionParams.to_json`); with
        ``zones``, the default law for every name no zone gives (None: an unknown name stops
        the run).
    out : path
        Output folder; it appears whole or not at all. An earlier export there is replaced only
        with ``force``, and only if the folder holds nothing but that export; any other
        non-empty folder, or one holding a parameter file of the export, is refused.
    zones : sequence of (name, path), or dict
        A law per tool zone (issue 42): the routine chooses the zone's law by the name its host
        passes (``zone_by``), compared trimmed and case-insensitive. Routine targets only (not
        ANSYS, whose argument list is not public, nor the tables).
    zone_by : str, optional
        Which name the routine compares: the target's first key by default (the contact
        interaction's name; LS-DYNA: the interface number ``NOSL``); ``slave`` or ``master``
        for the Abaqus targets (the surfaces' names).
    units : {"SI", "mm-t-s"}
        Unit system of the host model (Pa, m or MPa, mm).
    k_t : float, optional
        Constant tangential stick stiffness in Pa/m (overrides the files' calibrated tables).
    table_tol : float, optional
        Table targets: bound on ``|tau_table - tau| / tau_max`` on first loading (default
        :data:`TABLE_TOL`); refused for the routine targets.
    force : bool
        Replace an earlier export in ``out`` (never files the export did not write, but for
        the target's products, such as the ``ccx`` CalculiX's ``build.sh`` links there: they
        are removed with it and listed in ``ExportResult.removed``).
    accept_failed : bool
        Export a parameter file whose calibration failed or whose fit did not converge (refused
        otherwise, :func:`frictionlaw.params.fit_failure`).
    without_flattening : bool
        Export a file with a flattening block (issue 43) for a host that passes no bulk strain
        (Abaqus FRIC, VFRIC, VFRICTION, CalculiX): the routine runs the law without the
        flattening and says so once. Refused without it, and refused where nothing is dropped.
    flow_curve : str or SwiftCurve or TabulatedCurve, optional
        The workpiece's flow curve (:mod:`frictionlaw.flow_curve`; text as
        :func:`~frictionlaw.flow_curve.read_flow_curve` reads it) for LS-DYNA's ``usrfrc``
        (SMP and MPP), whose host passes the element's plastic strain but neither its flow
        stress nor its hardening modulus: the routine reads both off the curve at the strain
        (docs/fe_codes.md), so the flattening's layer follows the hardening and its lattice and
        sinking are limited by it (Eqs. F2c, F2d). Without it the routine runs the file's
        ``sigma_y`` and the perfectly plastic rate. Refused for other targets and files without
        a flattening block.

    Returns
    -------
    ExportResult
    """
    out = Path(out)
    products = _targets.target(target).products
    zone_list = list(zones.items()) if isinstance(zones, dict) else list(zones)
    inputs = tuple(p for p in (params_path, *(path for _, path in zone_list)) if p is not None)
    with OutputFolder(
        out,
        command="frictionlaw-export",
        what="export",
        force=force,
        require_force=True,
        inputs=inputs,
        products=products,
    ) as folder:
        # checked replaceable: what a later step added is removed with the earlier export
        removed = tuple(out / name for name in products if (out / name).exists())
        files, table = render(
            target,
            params_path,
            zones=zone_list,
            zone_by=zone_by,
            units=units,
            k_t=k_t,
            table_tol=table_tol,
            accept_failed=accept_failed,
            without_flattening=without_flattening,
            flow_curve=flow_curve,
        )
        executable = {e.name for e in _targets.target(target).extras if e.executable}
        for name, text in files.items():
            (folder.tmp / name).write_text(text, encoding="utf-8")
            if name in executable:
                (folder.tmp / name).chmod(0o755)
        folder.commit()
    return ExportResult(out, tuple(sorted(files)), table, removed)
