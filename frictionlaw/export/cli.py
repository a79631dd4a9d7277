"""The ``frictionlaw-export`` command: options, messages and exit codes around :func:`export`.

Exit codes: 0 written, 1 the export failed (a table that cannot meet its tolerance), 2 bad input
(unknown target or unit system, unreadable parameter file, out-of-range option, an option that
does not apply to the target, a zone the target cannot carry or a bad zone name), 130/143
interrupted. The library raises ``ValueError`` (and
``FileNotFoundError``, ``IsADirectoryError``) for bad input and ``RuntimeError`` for a failed
export; this module alone turns them into exit codes and one line on stderr.
"""

import argparse
import json
from pathlib import Path

from sbmf_cli import (
    Console,
    HelpFormatter,
    add_common_options,
    add_version,
    flags_of,
    interruptible,
    parse,
    refuse_repeats,
)

from ..params import fit_failure
from . import TARGETS, export
from ._tables import TABLE_TOL
from ._zones import parse_zone

__all__ = ["build_parser", "main"]


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


def build_parser():
    """The argument parser of ``frictionlaw-export``."""
    ap = argparse.ArgumentParser(
        prog="frictionlaw-export",
        description="Write the calibrated friction law as an FE user subroutine or friction table.",
        formatter_class=HelpFormatter,
    )
    add_version(ap)
    ap.add_argument("target", help="one of: " + ", ".join(TARGETS))
    ap.add_argument(
        "--params",
        default=None,
        help="params.json from the calibration: the law (with --zone: the default law for every "
        "name no zone gives; left out, such a name stops the run; default: none, then --zone "
        "must give the laws)",
    )
    ap.add_argument(
        "--zone",
        action="append",
        default=None,
        metavar="NAME=PARAMS.json",
        help="a tool zone's own calibration (repeatable): the routine runs it where the host "
        "passes NAME (trimmed, case-insensitive; LS-DYNA: the interface number, --zone 3=FILE); "
        "routine targets but ansys-userfric (default: none, one law everywhere)",
    )
    ap.add_argument(
        "--zone-by",
        default=None,
        help="which name a zoned routine compares: interaction (Abaqus CINAME, surfInt; "
        "CalculiX CINAME), slave or master (Abaqus: the surfaces' names); LS-DYNA: interface "
        "(NOSL) only (default: the target's first, interaction or interface)",
    )
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
        default=None,
        help="table targets (abaqus-table, lsdyna-table): max |tau_table - tau| / tau_max on "
        f"first loading (default: {TABLE_TOL:g}; refused for the routine targets)",
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
    ap.add_argument(
        "--without-flattening",
        action="store_true",
        help="export a parameter file with a flattening block (halfspace-calib --flattening) for "
        "a host that passes no bulk strain (abaqus-fric, abaqus-vfric, abaqus-vfriction): the "
        "routine runs the law without the flattening and says so once; or as a table "
        "(abaqus-table, lsdyna-table: the law of the pressure alone, its header says so); "
        "refused for the targets that run the flattening and for a file without the block "
        "(default: off)",
    )
    ap.add_argument(
        "--flow-curve",
        metavar="SPEC",
        help="the workpiece's flow curve, for lsdyna-usrfrc, lsdyna-usrfrc-mpp and calculix "
        "with a flattening block (their hosts pass the plastic strain, not the flow stress): "
        "swift:K,eps0,n (K in Pa, e.g. swift:530e6,0.006,0.24) or a CSV with a strain "
        "and a flow stress column with its unit (strain and sigma_y_MPa, phi and kf [MPa], "
        "...); the routine reads the flow stress "
        "and hardening modulus off it at the element's plastic strain (default: none: the "
        "file's sigma_y and the perfectly plastic rate, an upper limit for a hardening metal)",
    )
    add_common_options(ap, progress=False)
    return refuse_repeats(ap)  # a value option given twice is refused, not the last kept


@interruptible("frictionlaw-export", "the export")
def main(argv=None):
    """Console entry point; returns 0 on success, 1 if the export failed, 2 on bad input."""
    ap = build_parser()
    args, code = parse(ap, argv)
    if args is None:
        return code
    con = Console(
        "frictionlaw-export",
        quiet=args.quiet,
        flags=flags_of(ap, params_path="--params", zones="--zone"),
    )
    try:
        zones = [parse_zone(z) for z in args.zone or ()]
        res = export(
            args.target,
            args.params,
            args.out,
            zones=zones,
            zone_by=args.zone_by,
            units=args.units,
            k_t=args.k_t,
            table_tol=args.table_tol,
            force=args.force,
            accept_failed=args.accept_failed_fit,
            without_flattening=args.without_flattening,
            flow_curve=args.flow_curve,
        )
    except (ValueError, FileNotFoundError, IsADirectoryError) as exc:
        return con.error(exc, 2)
    except RuntimeError as exc:
        return con.error(f"the export failed: {exc}", 1)
    for path in (args.params, *(path for _, path in zones)):
        if path is not None:
            _warn_failed(con, path, args.accept_failed_fit)
    for path in res.removed:
        con.warn(
            f"frictionlaw-export: removed {path}, built from the export it replaced; build it "
            "again for the new one (build.sh in the folder)"
        )
    con.result(f"wrote {', '.join(res.files)} to {res.out}")
    if args.flow_curve is not None and args.params is not None:
        from ..flattening import beta_absorbs_hardening
        from ..params import FrictionParams

        P = FrictionParams.from_json(args.params, accept_failed=True)
        if beta_absorbs_hardening(P):
            con.warn(
                f"frictionlaw-export: warning: {args.params}'s beta was fitted to a sheet taken "
                "as perfectly plastic (no --flow-curve in the calibration): it absorbs the "
                "sheet's hardening, which the flow curve's modulus now limits again; refit beta "
                "with halfspace-calib --flow-curve, or export without --flow-curve"
            )
    if res.table is not None:
        con.result(
            f"table: {len(res.table.p)} pressures, measured max |tau_table - tau| = "
            f"{res.table.max_error:.3g} tau_max (tolerance {res.table.tol:g})"
        )
    return 0
