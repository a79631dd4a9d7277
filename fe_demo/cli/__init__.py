"""``fe-demo``: command-line runner for the upsetting, ring and multistage scenes.

Examples
--------
``fe-demo upsetting`` (SBMF law with the shipped illustrative parameters),
``fe-demo upsetting --law sbmf --params calibrated.json --out out/ups``,
``fe-demo upsetting --law all`` (every law side by side),
``fe-demo ring`` (Tresca m in {0, 0.1, 0.2, 0.3, 0.5, 1} over the upper-bound chart;
``--m 0.3`` runs that m alone, ``--m-list 0,0.3`` sweeps those),
``fe-demo multistage`` (upset, unload, reload; with and without ``p_hist``).
An option the chosen law does not use is refused (exit 2), never silently ignored.

The output folder appears whole (:class:`sbmf_cli.OutputFolder`): the run writes into a
temporary folder beside ``--out`` that replaces an earlier ``fe-demo`` output as a whole, so no
file of a longer earlier run (``vtu/step_0005.vtu``) survives beside a new ``.pvd``. A run that
did not converge still writes its results (up to the failure) and exits 1. The summary goes to
stdout (hidden by ``--quiet``), warnings and errors to stderr.
"""

import argparse
import re
import sys
from pathlib import Path

from frictionlaw import FrictionParams
from sbmf_cli import (
    Console,
    HelpFormatter,
    OutputFolder,
    add_common_options,
    add_version,
    flags_of,
    interruptible,
    parse,
    refuse_repeats,
)

from ..analysis.band import band_laws
from ..analysis.ring_chart import CHART_M
from ..scenes.laws import EXAMPLE_FLATTENING_PATH, LAW_OPTIONS, LAWS
from ..scenes.zones import check_radial_zones
from . import ring_fit
from .runs import cmd_band, cmd_multistage, cmd_ring, cmd_upsetting, material_file, path_arg

__all__ = ["main", "build_parser"]

_LAWS_ALL = (*LAWS, "all")
_MU, _M = 0.1, 0.3  # defaults of --mu, --m where the law uses them


def _positive_int(name):
    def conv(s):
        v = int(s)
        if v < 1:
            raise argparse.ArgumentTypeError(f"{name} must be >= 1, got {s}")
        return v

    return conv


def _add_common(p, *, law, nr, increments, reduction, out):
    p.add_argument(
        "--law",
        choices=_LAWS_ALL,
        default=None,
        help=f"friction law (default: {law}; sbmf when --params is given)",
    )
    p.set_defaults(default_law=law)
    p.add_argument(
        "--mu", type=float, default=None, help=f"Coulomb coefficient (coulomb, cap; default {_MU})"
    )
    p.add_argument(
        "--m", type=float, default=None, help=f"Tresca friction factor (tresca, cap; default {_M})"
    )
    p.add_argument(
        "--tau-max",
        type=float,
        default=None,
        help="cap of 'cap' in Pa (default: m sigma_f / sqrt(3), updated like Tresca's)",
    )
    p.add_argument(
        "--params",
        type=path_arg,
        default=None,
        help="SBMF parameter JSON (FrictionParams file; default: the shipped illustrative set)",
    )
    p.add_argument(
        "--accept-failed-fit",
        action="store_true",
        help="run a --params file whose calibration failed or whose fit did not converge "
        "(refused otherwise; a warning is printed)",
    )
    p.add_argument(
        "--material",
        type=path_arg,
        default=None,
        help="material JSON (E, nu, K, eps0, n; default: DC04)",
    )
    p.add_argument("--nr", type=_positive_int("nr"), default=nr, help="elements across the radius")
    p.add_argument(
        "--nz",
        type=_positive_int("nz"),
        default=None,
        help="elements over h/2 (default: square elements from --nr)",
    )
    p.add_argument(
        "--increments",
        type=_positive_int("increments"),
        default=increments,
        help="load increments",
    )
    p.add_argument("--reduction", type=float, default=reduction, help="final height reduction")
    p.add_argument("--out", type=Path, default=Path(out), help="output folder")
    ring_fit.add_force(p)
    p.add_argument(
        "--vtu-every", type=int, default=5, help="VTU snapshot every N increments (0: none)"
    )
    add_common_options(p)
    p.add_argument(
        "--flattening",
        action="store_true",
        help="flattening of the asperities under bulk strain (law sbmf; docs/flattening.md): run "
        "the law with and without the die nodes' plastic strain passed to the --params file's "
        "flattening block (without --params: the shipped params.json of halfspace-calib "
        "--flattening with its defaults) "
        "and compare the contact fraction at the die and the force (default: off)",
    )
    g = p.add_mutually_exclusive_group()
    g.add_argument(
        "--band",
        action="store_true",
        help="law sbmf with a multi-sample --params file: run the central law and the band's "
        "two edge laws; history.csv, plot, summary.json and report.html give the band",
    )
    g.add_argument(
        "--samples",
        action="store_true",
        help="as --band, but the central law and every sample's own law (their spread)",
    )


def _add_zones(p):
    """``--zone NAME=PARAMS.json`` and ``--zone-from-radius NAME=R``: a zoned die (upsetting, ring)."""
    p.add_argument(
        "--zone",
        action="append",
        default=None,
        metavar="NAME=PARAMS.json",
        help="a zone of the die with its own SBMF parameter file (repeatable; law sbmf): from "
        "its --zone-from-radius outward the die runs it, inside the run's --params "
        "(default: none, one law on the whole die)",
    )
    p.add_argument(
        "--zone-from-radius",
        action="append",
        default=None,
        metavar="NAME=R",
        help="the radius R (m) from which zone NAME applies outward, one per --zone "
        "(a rough rim: --zone rim=rim.json --zone-from-radius rim=0.012; default: none)",
    )


def _pairs(values, flag):
    """``{name: value}`` of ``NAME=VALUE`` options; ValueError naming ``flag``."""
    out = {}
    for v in values or ():
        name, sep, value = str(v).partition("=")
        name = name.strip()
        if not sep or not value.strip() or not re.fullmatch(r"[A-Za-z0-9_-]+", name):
            raise ValueError(
                f"{flag} takes NAME=VALUE with NAME of letters, digits, '_' or '-', got {v!r}"
            )
        if name.lower() in {k.lower() for k in out}:
            raise ValueError(f"{flag}: zone {name!r} is given twice")
        out[name] = value.strip()
    return out


def _check_zones(args):
    """The die's zones, read and checked before any run.

    ``args.zones_loaded``: ``[(name, FrictionParams, radius)]``; refused where the run would
    not use them.
    """
    args.zones_loaded = ()
    files = _pairs(getattr(args, "zone", None), "--zone")
    radii = _pairs(getattr(args, "zone_from_radius", None), "--zone-from-radius")
    if not files and not radii:
        return
    if args.law != "sbmf":
        raise ValueError(f"--zone needs --law sbmf (the die's default law), got --law {args.law}")
    if args.band or args.samples:
        raise ValueError("--zone is not used with --band or --samples")
    if {k.lower() for k in files} != {k.lower() for k in radii}:
        raise ValueError(
            "every --zone needs its --zone-from-radius and every --zone-from-radius its --zone "
            f"(zones {sorted(files)}, radii {sorted(radii)})"
        )
    radius = {k.lower(): v for k, v in radii.items()}
    zones = []
    for name, path in files.items():
        try:
            r = float(radius[name.lower()])
        except ValueError:
            raise ValueError(
                f"--zone-from-radius {name}: a radius in m, got {radius[name.lower()]!r}"
            ) from None
        if not Path(path).exists():
            raise ValueError(f"--zone {name}: parameter file {path} does not exist")
        params = FrictionParams.from_json(path, accept_failed=args.accept_failed_fit)
        if params.flattening is not None and not args.flattening:  # as --params's block
            print(
                f"fe-demo: WARNING: --zone {name}: {path} carries a flattening block; this run "
                "evaluates the zone's law without flattening (zero bulk strain; --flattening "
                "passes the die's plastic strain to it)",
                file=sys.stderr,
            )
        zones.append((name, params, r))
    args.zones_loaded = tuple(check_radial_zones(zones))  # before any run


def build_parser():
    """The argument parser of ``fe-demo``."""
    ap = argparse.ArgumentParser(
        prog="fe-demo",
        description="Command-line runner for the upsetting, ring and multistage scenes.",
        formatter_class=HelpFormatter,
    )
    add_version(ap)
    sub = ap.add_subparsers(dest="scene", required=True)
    kw = {"formatter_class": HelpFormatter}
    p = sub.add_parser("upsetting", help="cylinder upsetting D0=20 mm, h0=10 mm", **kw)
    _add_common(p, law="sbmf", nr=64, increments=50, reduction=0.5, out="fe_out/upsetting")
    _add_zones(p)
    p.add_argument("--remesh-below", type=float, default=0.0, help="remesh threshold (0: off)")
    p.add_argument("--diameter", type=float, default=20e-3, help="D0 in m")
    p.add_argument("--height", type=float, default=10e-3, help="h0 in m")
    p = sub.add_parser("ring", help="ring compression 6:3:2 (OD 18, ID 9, h 6 mm)", **kw)
    _add_common(p, law="tresca", nr=16, increments=50, reduction=0.5, out="fe_out/ring")
    p.add_argument(
        "--m-list",
        type=str,
        default=None,
        help=(
            "Tresca factors to sweep over the chart (law tresca only); without --m or --m-list "
            "tresca sweeps " + ",".join(f"{m:g}" for m in CHART_M) + " (default: none)"
        ),
    )
    _add_zones(p)
    p.add_argument(
        "--remesh-below",
        type=float,
        default=0.3,
        help="remesh when the worst element corner sine falls below this (0: off)",
    )
    p = sub.add_parser("multistage", help="upset, unload, reload (Eq. 25)", **kw)
    _add_common(p, law="sbmf", nr=24, increments=30, reduction=0.45, out="fe_out/multistage")
    p.add_argument("--first-reduction", type=float, default=0.3, help="reduction of stage 1")
    ring_fit.add_parser(sub, HelpFormatter)
    return refuse_repeats(ap)  # a value option given twice is refused, not the last kept


def _check_options(args):
    """Refuse options the requested runs would not use; fill in the defaults of the rest."""
    if args.law is None:  # a parameter file is only used by the law that reads it
        zoned = any(getattr(args, k, None) is not None for k in ("zone", "zone_from_radius"))
        given = args.params is not None or zoned or args.flattening
        args.law = "sbmf" if given else args.default_law
    _check_law_options(args)
    _check_flattening(args)
    _check_sweep_and_band(args)
    _check_zones(args)
    args.material_loaded = material_file(args.material)
    args.m_given = args.m is not None
    args.mu = _MU if args.mu is None else args.mu
    args.m = _M if args.m is None else args.m
    if args.params is not None:
        _load_params(args)


def _check_flattening(args):
    """``--flattening`` runs the law sbmf alone; without ``--params``, the shipped example's."""
    if not args.flattening:
        return
    if args.law != "sbmf":
        raise ValueError(
            f"--flattening needs --law sbmf (the law that flattens), got --law {args.law}"
        )
    if args.band or args.samples:
        raise ValueError(f"--flattening is not used with {'--band' if args.band else '--samples'}")
    if args.params is None:
        args.params = EXAMPLE_FLATTENING_PATH


def _check_law_options(args):
    """An option the chosen law does not use is refused."""
    used = LAW_OPTIONS[args.law]
    for name in ("mu", "m", "tau_max", "params"):
        if getattr(args, name) is not None and name not in used:
            flag = "--" + name.replace("_", "-")
            hint = " (add --law sbmf to run the parameter file's law)" if name == "params" else ""
            raise ValueError(f"{flag} is not used by --law {args.law}{hint}")
    if args.law == "cap" and args.tau_max is not None and args.m is not None:
        raise ValueError("--m is not used by --law cap when --tau-max gives the cap")


def _check_sweep_and_band(args):
    """``--m-list`` sweeps Tresca's m alone; ``--band`` / ``--samples`` need a band's file."""
    m_list = getattr(args, "m_list", None)
    if m_list is not None:
        if args.law != "tresca":
            raise ValueError(f"--m-list is not used by --law {args.law} (it sweeps Tresca's m)")
        if args.m is not None:
            raise ValueError("give --m or --m-list, not both")
    if args.band or args.samples:
        flag = "--band" if args.band else "--samples"
        if args.law != "sbmf" or args.params is None:
            raise ValueError(f"{flag} needs --law sbmf and a --params file from several samples")
        if m_list is not None:
            raise ValueError(f"--m-list is not used with {flag}")


def _load_params(args):
    """Read ``--params`` before any run: unreadable files and failed fits are bad input."""
    if not args.params.exists():
        raise ValueError(f"--params file {args.params} does not exist")
    P = FrictionParams.from_json(args.params, accept_failed=args.accept_failed_fit)
    reason = P.failure
    if reason:  # accepted: the run uses the object, and says so
        args.params_loaded = P
        print(f"fe-demo: WARNING: {args.params}: {reason}; run as asked", file=sys.stderr)
    if P.flattening is None and args.flattening:
        raise ValueError(
            f"--flattening: {args.params} has no flattening block (calibrate with "
            "halfspace-calib --flattening, docs/flattening.md)"
        )
    from frictionlaw.flattening import beta_absorbs_hardening

    if P.flattening is not None and args.flattening and beta_absorbs_hardening(P):
        print(
            f"fe-demo: note: {args.params}'s beta was fitted to a sheet taken as perfectly "
            "plastic (halfspace-calib --flattening-data without --flow-curve): it absorbs the "
            "sheet's hardening, so this run passes the die's flow stress but no hardening "
            "modulus (docs/flattening.md, Eq. F2c); fit with --flow-curve to pass it",
            file=sys.stderr,
        )
    if P.flattening is not None and not args.flattening:
        print(
            f"fe-demo: WARNING: {args.params} carries a flattening block; this run evaluates the "
            "law without flattening (zero bulk strain; --flattening passes the die's plastic "
            "strain to it)",
            file=sys.stderr,
        )
    if args.band or args.samples:
        args.band_laws = band_laws(P, "band" if args.band else "samples", args.params)
        args.band_level = P.uncertainty.level


def _flags(parser, scene):
    """``{Python name: flag}`` of the chosen subcommand (the library's names included)."""
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return flags_of(sub.choices[scene], n_increments="--increments", paths="--measured")


@interruptible("fe-demo", "the FE run")
def main(argv=None):
    """Entry point of ``fe-demo``: 0, 1 (a run failed), 2 (bad input), 130/143 (interrupted)."""
    parser = build_parser()
    args, code = parse(parser, argv)
    if args is None:
        return code
    con = Console("fe-demo", quiet=args.quiet, flags=_flags(parser, args.scene))
    if args.scene == "ring-fit":
        return ring_fit.run(args, con)
    if not (0.0 < args.reduction < 0.9):
        return con.error("--reduction must be in (0, 0.9)", 2)
    try:
        _check_options(args)
        folder = OutputFolder(
            args.out,
            command="fe-demo",
            subcommand=args.scene,
            what="fe-demo output",
            force=args.force,
            inputs=(
                args.params,
                args.material,
                *_pairs(getattr(args, "zone", None), "--zone").values(),
            ),
        )
    except (ValueError, OSError) as exc:
        return con.error(exc, 2)
    out, args.out = args.out, folder.tmp
    cmd = {"upsetting": cmd_upsetting, "ring": cmd_ring}.get(args.scene, cmd_multistage)
    if args.band or args.samples:
        cmd = cmd_band
    with folder:
        try:
            code = cmd(args, con)
            con.write_summary(folder.tmp)
            folder.commit()
        except ValueError as exc:
            return con.error(exc, 2)
        except OSError as exc:  # writing the outputs (disk full, permissions changed meanwhile)
            return con.error(f"the outputs could not be written, {out} is unchanged: {exc}", 1)
    con.result(f"output in {out}")
    return code
