"""What :func:`render` and :func:`export` do with a target's record (private).

First decide (:func:`plan`): the target's record, the unit system, the parameter file, its
sha256, the stick stiffness or the table; all bad input is refused there, before any file is
rendered. Then run: the generated file (provenance header + the target's template), the README
(the form's frame with the target's sections) and the extra files, each from the record alone.
"""

import hashlib
from dataclasses import dataclass
from pathlib import Path

from sbmf_cli import OutputFolder, ParameterError

from ..params import FrictionParams
from . import _targets
from ._law import UNIT_SYSTEMS, StiffnessSpec, UnitSystem, core_context, header_lines
from ._origin import m_origin
from ._tables import FrictionTable
from ._templates import check_columns, comment_block, render_template, template_path

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
        The values the law core is rendered with (:func:`frictionlaw.export._law.core_context`).
    """

    target: _targets.Target
    params: FrictionParams
    units: UnitSystem
    sha: str
    kt: StiffnessSpec | None
    table: FrictionTable | None
    header: tuple
    law: dict


def _sha256(path):
    with open(path, "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


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
    if params.flattening is not None:
        raise ValueError(
            f"{path}: the file carries a flattening block (issue 43) and no host routine "
            "evaluates flattening under bulk strain yet: an export would run the law without it; "
            "export a calibration made without --flattening"
        )


def plan(target, params_path, *, units="SI", k_t=None, table_tol=1e-3, accept_failed=False):
    """Decide an export (:class:`Job`); raises ValueError (or FileNotFoundError) on bad input.

    The options are checked before the parameter file is read; a table that cannot meet
    ``table_tol`` is a RuntimeError.
    """
    record = _targets.target(target)
    if units not in UNIT_SYSTEMS:
        raise ValueError(f"units must be one of {', '.join(UNIT_SYSTEMS)}; got {units!r}")
    if not (1e-6 <= float(table_tol) <= 0.1):
        raise ParameterError(
            f"{{table_tol}} must be in [1e-6, 0.1], got {table_tol!r}", "table_tol"
        )
    if k_t is not None and not record.form.takes_k_t:
        raise ParameterError(
            "{k_t} applies to the Fortran targets only (a table has no stiffness)", "k_t"
        )
    params_path = Path(params_path)
    params = FrictionParams.from_json(params_path, accept_failed=accept_failed)
    _check_exportable(params, params_path)
    sha = _sha256(params_path)
    us = UNIT_SYSTEMS[units]
    kt, table = record.form.decide(params, us, k_t, table_tol)
    header = tuple(header_lines(record.name, params, params_path, sha, us, kt))
    return Job(record, params, us, sha, kt, table, header, core_context(params, us, kt))


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
        "origin": m_origin(job.params),
        **job.law,
    }
    if "guard" in context:
        context["guard_text"] = context["guard"].messages(*words)
    text = comment_block(job.header, t.style.comment, t.style.columns)
    text += render_template(t.template, **context)
    files = {
        t.file: check_columns(text, t.style.columns, t.file),
        "README.md": render_template(t.form.frame, **context),
    }
    for extra in t.extras:
        files[extra.name] = template_path(extra.template).read_text(encoding="utf-8")
    return files


def render(target, params_path, *, units="SI", k_t=None, table_tol=1e-3, accept_failed=False):
    """The files of ``target`` as ``{name: text}`` plus the table (or None); writes nothing.

    The arguments are those of :func:`export`.
    """
    job = plan(
        target,
        params_path,
        units=units,
        k_t=k_t,
        table_tol=table_tol,
        accept_failed=accept_failed,
    )
    return texts(job), job.table


def export(
    target,
    params_path,
    out,
    *,
    units="SI",
    k_t=None,
    table_tol=1e-3,
    force=False,
    accept_failed=False,
):
    """Write ``target``'s files for the parameter file ``params_path`` into the folder ``out``.

    Parameters
    ----------
    target : str
        A registered target's name (:data:`TARGETS`: the shipped ones).
    params_path : path
        ``params.json`` written by the calibration (or :meth:`FrictionParams.to_json`).
    out : path
        Output folder; it appears whole or not at all. An earlier export there is replaced only
        with ``force``, and only if the folder holds nothing but that export; any other
        non-empty folder, or one holding ``params_path``, is refused.
    units : {"SI", "mm-t-s"}
        Unit system of the host model (Pa, m or MPa, mm).
    k_t : float, optional
        Constant tangential stick stiffness in Pa/m (overrides the file's calibrated table).
    table_tol : float
        Table targets: bound on ``|tau_table - tau| / tau_max`` on first loading.
    force : bool
        Replace an earlier export in ``out`` (never files the export did not write, but for
        the target's products, such as the ``ccx`` CalculiX's ``build.sh`` links there: they
        are removed with it and listed in ``ExportResult.removed``).
    accept_failed : bool
        Export a parameter file whose calibration failed or whose fit did not converge (refused
        otherwise, :func:`frictionlaw.params.fit_failure`).

    Returns
    -------
    ExportResult
    """
    out = Path(out)
    products = _targets.target(target).products
    with OutputFolder(
        out,
        command="frictionlaw-export",
        what="export",
        force=force,
        require_force=True,
        inputs=(params_path,),
        products=products,
    ) as folder:
        # checked replaceable: what a later step added is removed with the earlier export
        removed = tuple(out / name for name in products if (out / name).exists())
        files, table = render(
            target,
            params_path,
            units=units,
            k_t=k_t,
            table_tol=table_tol,
            accept_failed=accept_failed,
        )
        executable = {e.name for e in _targets.target(target).extras if e.executable}
        for name, text in files.items():
            (folder.tmp / name).write_text(text, encoding="utf-8")
            if name in executable:
                (folder.tmp / name).chmod(0o755)
        folder.commit()
    return ExportResult(out, tuple(sorted(files)), table, removed)
