"""``frictionlaw-export``: the calibrated law as FE user subroutines and friction tables.

Imported only on demand (``import frictionlaw`` does not load it). From a parameter file it writes
self-contained sources with the constants baked in as double-precision literals, a provenance
header (the file's sha256, the fit summary, the unit system) and a README saying how to compile
and activate them. See ``docs/fe_codes.md``.

Targets: ``abaqus-fric``, ``abaqus-vfric``, ``abaqus-vfriction``, ``lsdyna-usrfrc``,
``lsdyna-usrfrc-mpp``, ``lsdyna``, ``ansys-userfric`` (Fortran), ``calculix`` (the ``abaqus-fric``
routine with a patch for CalculiX 2.20 and the script that builds ``ccx`` with both),
``abaqus-table``, ``lsdyna-table`` (Eq. 24 as a friction-coefficient table; no history).
"""

import argparse
import hashlib
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..clitools import (
    Console,
    HelpFormatter,
    OutputFolder,
    add_common_options,
    add_version,
    interruptible,
    parse,
)
from ..params import FrictionParams, fit_failure
from . import _fortran, _readme, _tables

__all__ = [
    "TARGETS",
    "UNIT_SYSTEMS",
    "UnitSystem",
    "StiffnessSpec",
    "ExportResult",
    "export",
    "render",
    "stiffness_spec",
    "law_constants",
    "main",
]

TARGETS = (
    "abaqus-fric",
    "abaqus-vfric",
    "abaqus-vfriction",
    "lsdyna-usrfrc",
    "lsdyna-usrfrc-mpp",
    "lsdyna",
    "ansys-userfric",
    "calculix",
    "abaqus-table",
    "lsdyna-table",
)


@dataclass(frozen=True)
class UnitSystem:
    """A host unit system: host value = SI value times the factor."""

    name: str
    stress: float  # Pa -> host stress unit
    length: float  # m -> host length unit
    stress_unit: str
    length_unit: str

    @property
    def stiffness(self):
        """Factor for a tangential stiffness (stress per length)."""
        return self.stress / self.length


UNIT_SYSTEMS = {
    "SI": UnitSystem("SI", 1.0, 1.0, "Pa", "m"),
    "mm-t-s": UnitSystem("mm-t-s", 1e-6, 1e3, "MPa", "mm"),
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
            raise ValueError(f"--k-t must be a finite stiffness > 0 in Pa/m, got {k_t!r}")
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
class ExportResult:
    """What :func:`export` wrote: the folder, its files, and the table (table targets)."""

    out: Path
    files: tuple
    table: object = None


def _sha256(path):
    with open(path, "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


def _fit_summary(params):
    fit = params.provenance.get("fit", {}) if isinstance(params.provenance, dict) else {}
    out = []
    for key in ("first_loading", "reload"):
        f = fit.get(key)
        if isinstance(f, dict):
            r2 = f.get("r_squared")
            rmse = f.get("rmse")
            npts = f.get("n_points")
            out.append(f"fit {key}: R^2={r2:.6g}, rmse={rmse:.3g}, points={npts}")
    return out or ["fit summary: none recorded in the parameter file"]


def header_lines(target, params, params_path, sha, units, kt):
    """Provenance lines (without comment markers)."""
    from .. import __version__

    s = units.stress_unit
    lines = [
        f"SBMF friction law (Eqs. 24-26), target {target}",
        f"generated by frictionlaw-export {__version__}; do not edit by hand",
        f"parameter file: {Path(params_path).name}",
        f"sha256: {sha}",
        f"units: {units.name} (stress {s}, length {units.length_unit})",
        f"m={params.m!r} k={params.k * units.stress!r} {s}",
        f"H={params.H * units.stress!r} {s} geo_ratio={params.geo_ratio!r}",
        f"C1={params.C1!r} n1={params.n1!r}",
        f"C2={params.C2!r} n2={params.n2!r}",
        f"continuous_reload={params.continuous_reload}",
        f"tau_max=m k (1+geo_ratio)={params.tau_max * units.stress!r} {s}",
        f"mu_eff=tau_max C1/H={params.mu_eff!r}",
    ]
    if params.p_range is not None:
        lo, hi = (v * units.stress for v in params.p_range)
        lines.append(f"calibrated pressures: {lo:.6g}..{hi:.6g} {s}")
    lines += _fit_summary(params)
    if kt is not None:
        lines.append("stick stiffness: " + kt.describe(units))
    return lines


def _wrap(lines, width):
    out = []
    for line in lines:
        while len(line) > width:
            cut = line.rfind(" ", 0, width)
            cut = cut if cut > 0 else width
            out.append(line[:cut])
            line = "  " + line[cut:].lstrip()
        out.append(line)
    return out


def _comment(lines, marker, width):
    return "".join(f"{marker} {line}\n" for line in _wrap(lines, width - len(marker) - 1))


_FORTRAN = {
    "abaqus-fric": ("sbmf_fric.f", _fortran.fric_source),
    "abaqus-vfric": ("sbmf_vfric.f", _fortran.vfric_source),
    "abaqus-vfriction": ("sbmf_vfriction.f", _fortran.vfriction_source),
    "lsdyna-usrfrc": ("sbmf_usrfrc_smp.f", _fortran.usrfrc_smp_source),
    "lsdyna-usrfrc-mpp": ("sbmf_usrfrc_mpp.f", _fortran.usrfrc_mpp_source),
    "lsdyna": ("sbmf_lsdyna.f", _fortran.generic_source),
    "ansys-userfric": ("sbmf_userfric.f", _fortran.generic_source),
    "calculix": ("sbmf_fric.f", _fortran.fric_source),
}

#: CalculiX: the patch and its build script ship with the package (frictionlaw/export/calculix)
CALCULIX_DIR = Path(__file__).resolve().parent / "calculix"
CALCULIX_FILES = ("calculix-2.20-user-friction.patch", "build.sh")
#: what build.sh adds to the export folder (its build tree is elsewhere): replaced with --force
CALCULIX_PRODUCTS = ("ccx",)


def _check_args(target, units, table_tol):
    if target not in TARGETS:
        raise ValueError(f"target must be one of {', '.join(TARGETS)}; got {target!r}")
    if units not in UNIT_SYSTEMS:
        raise ValueError(f"units must be one of {', '.join(UNIT_SYSTEMS)}; got {units!r}")
    if not (1e-6 <= float(table_tol) <= 0.1):
        raise ValueError(f"--table-tol must be in [1e-6, 0.1], got {table_tol!r}")


def render(target, params_path, *, units="SI", k_t=None, table_tol=1e-3, accept_failed=False):
    """The files of ``target`` as ``{name: text}`` plus the table (or None); writes nothing."""
    _check_args(target, units, table_tol)
    if k_t is not None and target.endswith("-table"):
        raise ValueError("--k-t applies to the Fortran targets only (a table has no stiffness)")
    params_path = Path(params_path)
    params = FrictionParams.from_json(params_path, accept_failed=accept_failed)
    sha = _sha256(params_path)
    us = UNIT_SYSTEMS[units]
    if target in _FORTRAN:
        name, make = _FORTRAN[target]
        kt = stiffness_spec(params, us, k_t)
        head = _comment(header_lines(target, params, params_path, sha, us, kt), "C", 72)
        src = make(head, law_constants(params, us), params.continuous_reload, kt)
        readme = _readme.fortran_readme(target, name, params, us, kt, sha)
        files = {name: src, "README.md": readme}
        if target == "calculix":
            files["ABA_PARAM.INC"] = _fortran.ABA_PARAM_INC
            for extra in CALCULIX_FILES:
                files[extra] = (CALCULIX_DIR / extra).read_text(encoding="utf-8")
        return files, None
    table = _tables.build_table(params, table_tol)
    head_lines = header_lines(target, params, params_path, sha, us, None)
    if target == "abaqus-table":
        name = "sbmf_friction_table.inp"
        text = _comment(head_lines, "**", 100) + _readme.abaqus_table(table, us)
    else:
        name = "sbmf_friction_table.k"
        text = _comment(head_lines, "$", 80) + _readme.lsdyna_table(table, us)
    readme = _readme.table_readme(target, name, params, us, table, sha)
    return {name: text, "README.md": readme}, table


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
        One of :data:`TARGETS`.
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
        Replace an earlier export in ``out`` (never files the export did not write).
    accept_failed : bool
        Export a parameter file whose calibration failed or whose fit did not converge (refused
        otherwise, :func:`frictionlaw.params.fit_failure`).

    Returns
    -------
    ExportResult
    """
    out = Path(out)
    with OutputFolder(
        out,
        command="frictionlaw-export",
        what="export",
        force=force,
        require_force=True,
        inputs=(params_path,),
        products=CALCULIX_PRODUCTS if target == "calculix" else (),
    ) as folder:
        files, table = render(
            target,
            params_path,
            units=units,
            k_t=k_t,
            table_tol=table_tol,
            accept_failed=accept_failed,
        )
        for name, text in files.items():
            (folder.tmp / name).write_text(text, encoding="utf-8")
            if name.endswith(".sh"):
                (folder.tmp / name).chmod(0o755)
        folder.commit()
    return ExportResult(out, tuple(sorted(files)), table)


def _warn_failed(con, params_path, accepted):
    """The warning that goes with an accepted failed fit."""
    if not accepted:
        return
    try:
        reason = fit_failure(json.loads(Path(params_path).read_text(encoding="utf-8")))
    except (OSError, ValueError):
        return
    if reason:
        con.warn(f"frictionlaw-export: WARNING: {params_path}: {reason}; exported as asked")


def _parser():
    ap = argparse.ArgumentParser(
        prog="frictionlaw-export",
        description="Write the calibrated friction law as an FE user subroutine or friction table.",
        formatter_class=HelpFormatter,
    )
    add_version(ap)
    ap.add_argument("target", help="one of: " + ", ".join(TARGETS))
    ap.add_argument("--params", required=True, help="params.json from the calibration")
    ap.add_argument("--out", required=True, help="output folder (must not exist unless --force)")
    ap.add_argument("--units", default="SI", help="SI (Pa, m) or mm-t-s (MPa, mm)")
    ap.add_argument(
        "--k-t",
        type=float,
        default=None,
        help="constant tangential stick stiffness in Pa/m (Fortran targets; overrides the "
        "parameter file's calibrated k_t table; default: the file's table, else none)",
    )
    ap.add_argument(
        "--table-tol",
        type=float,
        default=1e-3,
        help="table targets: max |tau_table - tau| / tau_max on first loading",
    )
    ap.add_argument(
        "--force",
        action="store_true",
        help="replace an earlier export in --out (never other files, never the --params file)",
    )
    ap.add_argument(
        "--accept-failed-fit",
        action="store_true",
        help="export a parameter file whose calibration failed or whose fit did not converge "
        "(refused otherwise; a warning is printed)",
    )
    add_common_options(ap, progress=False)
    return ap


@interruptible("frictionlaw-export", "the export")
def main(argv=None):
    """Console entry point; returns 0 on success, 1 if the export failed, 2 on bad input."""
    ap = _parser()
    args, code = parse(ap, argv)
    if args is None:
        return code
    con = Console("frictionlaw-export", quiet=args.quiet)
    try:
        res = export(
            args.target,
            args.params,
            args.out,
            units=args.units,
            k_t=args.k_t,
            table_tol=args.table_tol,
            force=args.force,
            accept_failed=args.accept_failed_fit,
        )
    except (ValueError, FileNotFoundError, IsADirectoryError) as exc:
        return con.error(str(exc), 2)
    except RuntimeError as exc:
        return con.error(f"the export failed: {exc}", 1)
    _warn_failed(con, args.params, args.accept_failed_fit)
    con.result(f"wrote {', '.join(res.files)} to {res.out}")
    if res.table is not None:
        con.result(
            f"table: {len(res.table.p)} pressures, measured max |tau_table - tau| = "
            f"{res.table.max_error:.3g} tau_max (tolerance {res.table.tol:g})"
        )
    return 0
