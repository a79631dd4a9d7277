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
import json
import sys
from pathlib import Path

import numpy as np

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
)

from . import ringfit_cmd
from .band import band_laws, write_band_outputs, write_run_report
from .calibrated_range import range_lines
from .laws import LAW_OPTIONS, LAWS
from .material import DC04, Material
from .output import (
    plot_force_stroke,
    plot_law_comparison,
    plot_recontact,
    plot_ring_chart,
    summary_table,
    write_history_csv,
    write_vtu_series,
)
from .ring_chart import CHART_M, ring_chart
from .scenes import contact_profile, run_multistage, run_ring, run_upsetting

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
        type=Path,
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
        type=Path,
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
    p.add_argument(
        "--vtu-every", type=int, default=5, help="VTU snapshot every N increments (0: none)"
    )
    add_common_options(p)
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
    p.add_argument(
        "--remesh-below",
        type=float,
        default=0.3,
        help="remesh when the worst element corner sine falls below this (0: off)",
    )
    p = sub.add_parser("multistage", help="upset, unload, reload (Eq. 25)", **kw)
    _add_common(p, law="sbmf", nr=24, increments=30, reduction=0.45, out="fe_out/multistage")
    p.add_argument("--first-reduction", type=float, default=0.3, help="reduction of stage 1")
    ringfit_cmd.add_parser(sub, HelpFormatter)
    return ap


def _material(args):
    return Material.from_json(args.material) if args.material else DC04


def _common_kw(args, law):
    return {
        "mu": args.mu,
        "m": args.m,
        "tau_max": args.tau_max,
        "params": getattr(args, "params_loaded", None) or args.params,
        "nr": args.nr,
        "nz": args.nz,
        "n_increments": args.increments,
        "material": _material(args),
        "progress": not (args.no_progress or args.quiet),
        "snapshot_every": max(0, args.vtu_every),
    }


def _label(law, args):
    if law == "tresca":
        return f"tresca m={args.m:g}"
    if law == "coulomb":
        return f"coulomb mu={args.mu:g}"
    if law == "cap":
        return f"cap mu={args.mu:g}"
    if law == "sbmf":
        return "sbmf " + (args.params.name if args.params else "(example params)")
    return "frictionless"


def _write_run(folder, res, title):
    folder.mkdir(parents=True, exist_ok=True)
    if res.history:
        write_history_csv(folder / "history.csv", res.history)
    for name, fig in res.figures(title).items():
        fig.savefig(folder / name, dpi=120)
    if res.snapshots and len(res.snapshots) > 1:
        write_vtu_series(folder / "vtu", res.model.t, res.snapshots)
    info = dict(res.info)
    info.update(
        converged=res.converged,
        message=res.message,
        stopped_at_height_reduction=res.model.height_reduction,
        wall_time_s=res.wall_time,
    )
    h = res.history
    if h and "inner_diameter_change" in h:  # a ring: what a ring test measures, at the end
        info["inner_diameter_change"] = float(h["inner_diameter_change"][-1])
        info["inner_diameter_min_change"] = float(h["inner_diameter_min_change"][-1])
    (folder / "summary.json").write_text(json.dumps(info, indent=2, default=_jd) + "\n")
    write_run_report(folder, json.loads(json.dumps(info, default=_jd)), title)


def _jd(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    return str(o)


def _report_run(con, label, res):
    """Console lines after a run: a failure, the calibrated-range check, a k_t stick stiffness.

    A failure and an extrapolated law are warnings (stderr); the rest is summary (stdout).
    """
    if not res.converged:
        con.warn(f"fe-demo: [{label}] FAILED: {res.message}")
    for line in range_lines(label, res.info.get("calibrated_range")):
        if "EXTRAPOLATED" in line:
            con.warn(f"fe-demo: WARNING: {line}")
        else:
            con.result(line)
    kt = res.info.get("tangential_stiffness", {})
    if kt.get("k_t_min_Pa_per_m") is not None:
        con.result(
            f"[{label}] stick stiffness k_t(p) from the parameter file: "
            f"{kt['k_t_min_Pa_per_m']:.3g} .. {kt['k_t_max_Pa_per_m']:.3g} Pa/m"
        )


def _summary_row(label, res, *, ring=False):
    """One row of the console table (a ring's has the inner-diameter change in % after the force)."""
    h = res.history
    tm = res.info.get("timings", {})
    row = {
        "run": label,
        "ok": res.converged,
        "elements": res.info.get("n_elements", 0),
        "increments": len(h.get("force", [])),
        "newton": res.info.get("newton_iterations", 0),
        "cutbacks": sum("cut-back" in s for s in res.info.get("cutback_log", [])),
        "remesh": res.info.get("n_remesh", 0),
        "reduction": float(h["height_reduction"][-1]) if h else 0.0,
        "force_kN": float(h["force"][-1] / 1e3) if h else 0.0,
    }
    if ring:
        row["ID_change_%"] = 100.0 * float(h["inner_diameter_change"][-1]) if h else 0.0
    return row | {
        "wall_s": res.wall_time,
        "solve_s": tm.get("solve", 0.0),
        "assembly_s": tm.get("assembly", 0.0),
        "material_s": tm.get("material", 0.0) + tm.get("kinematics", 0.0),
        "contact_s": tm.get("contact", 0.0),
    }


def _cmd_upsetting(args, con):
    laws = [w for w in LAWS if w != "none"] if args.law == "all" else [args.law]
    results, rows = {}, []
    ok = True
    for law in laws:
        kw = _common_kw(args, law)
        res = run_upsetting(
            law,
            diameter=args.diameter,
            height=args.height,
            reduction=args.reduction,
            remesh_below=args.remesh_below,
            **kw,
        )
        lab = _label(law, args)
        folder = args.out / law if len(laws) > 1 else args.out
        _write_run(folder, res, lab)
        results[lab] = (res.history, contact_profile(res.model)) if res.history else None
        rows.append(_summary_row(lab, res))
        ok &= res.converged
        _report_run(con, lab, res)
    if len(laws) > 1:
        done = {k: v for k, v in results.items() if v is not None}
        if done:
            plot_law_comparison(args.out / "law_comparison.png", done)
    con.result(summary_table(rows))
    return 0 if ok else 1


def _chart(reduction):
    """Upper-bound chart curves for :data:`CHART_M`, and a note for those that end early."""
    chart, notes = {}, []
    for m in CHART_M:
        red, d = ring_chart(m, reduction)
        chart[m] = (red, d)
        if red[-1] < reduction - 1e-9:
            notes.append(
                f"note: the upper-bound chart for m={m:g} ends at height reduction "
                f"{red[-1]:.3f}, where the upper-bound hole closes (inner radius -> 0)"
            )
    return chart, notes


def _m_list(args):
    """Tresca factors to sweep: ``--m-list``, else the chart's when neither it nor ``--m``."""
    if args.law != "tresca":
        return []
    if args.m_list is not None:
        try:
            ms = [float(s) for s in args.m_list.split(",") if s.strip()]
        except ValueError:
            raise ValueError(
                f"--m-list must be comma-separated numbers, got {args.m_list!r}"
            ) from None
        if not ms:
            raise ValueError("--m-list is empty: give factors, or --m for a single run")
        return ms
    return [] if args.m_given else list(CHART_M)


def _cmd_ring(args, con):
    m_list = _m_list(args)
    runs = []
    if m_list:
        for m in m_list:
            runs.append(("tresca" if m > 0 else "none", m, f"FE m={m:g}"))
    elif args.law == "all":
        runs = [(law, args.m, _label(law, args)) for law in LAWS if law != "none"]
    else:
        runs.append((args.law, args.m, _label(args.law, args)))
    rows, fe = [], {}
    ok = True
    for law, m, lab in runs:
        kw = _common_kw(args, law)
        kw["m"] = m
        res = run_ring(law, reduction=args.reduction, remesh_below=args.remesh_below, **kw)
        folder = args.out / lab.replace(" ", "_").replace("=", "") if len(runs) > 1 else args.out
        _write_run(folder, res, lab)
        if res.history:
            fe[lab] = (res.history["height_reduction"], res.history["inner_diameter_change"])
        rows.append(_summary_row(lab, res, ring=True))
        ok &= res.converged
        _report_run(con, lab, res)
    args.out.mkdir(parents=True, exist_ok=True)
    chart, notes = _chart(args.reduction)
    plot_ring_chart(args.out / "ring_chart.png", chart, fe)
    with (args.out / "ring_chart_upper_bound.csv").open("w", encoding="utf-8") as fh:
        fh.write("m,height_reduction,inner_diameter_change\n")
        for m, (red, d) in chart.items():
            for a, b in zip(red, d, strict=True):
                fh.write(f"{m:g},{a:.6g},{b:.6g}\n")
    for _law, _, lab in runs:  # the runs' reports again, now with the chart
        folder = args.out / lab.replace(" ", "_").replace("=", "") if len(runs) > 1 else args.out
        if (folder / "summary.json").is_file():
            write_run_report(folder, json.loads((folder / "summary.json").read_text()), lab)
    con.result(summary_table(rows))
    for note in notes:
        con.result(note)
    return 0 if ok else 1


def _cmd_multistage(args, con):
    laws = [w for w in LAWS if w != "none"] if args.law == "all" else [args.law]
    rows, curves = [], {}
    ok = True
    for law, reset in ((w, r) for w in laws for r in (False, True)):
        kw = _common_kw(args, law)
        res = run_multistage(
            law,
            first_reduction=args.first_reduction,
            reduction=args.reduction,
            reset_history=reset,
            **kw,
        )
        lab = _label(law, args) + (" without p_hist" if reset else " with p_hist")
        sub = args.out / law if len(laws) > 1 else args.out
        _write_run(sub / ("no_history" if reset else "with_history"), res, lab)
        prof = res.info.get("recontact_profile")
        if prof is not None and not reset:
            plot_recontact(sub / "recontact_friction.png", prof)
        if res.history:
            curves[lab] = res.history
        rows.append(_summary_row(lab, res))
        ok &= res.converged
        _report_run(con, lab, res)
    if curves:
        plot_force_stroke(
            args.out / "multistage_force.png",
            list(curves.values()),
            list(curves),
            title="Upset - unload - reload",
        )
        zoom = {}
        for lab, h in curves.items():
            sel = (h["stage"] >= 2) & (h["height_reduction"] <= args.first_reduction + 0.02)
            if sel.any():
                zoom[lab] = {k: v[sel] for k, v in h.items()}
        if zoom:
            plot_force_stroke(
                args.out / "multistage_recontact.png",
                list(zoom.values()),
                list(zoom),
                title="Unload and re-contact (Eq. 25 region)",
            )
    con.result(summary_table(rows))
    for lab, h in curves.items():
        st = h["stage"]
        if (st == 3).any():
            n25 = h["n_reload_eq25"][st == 3]
            con.result(
                f"[{lab}] reload: contact nodes below p_hist (Eq. 25 for sbmf) per increment "
                f"max {int(n25.max())}, max |tau(p,p_hist)-tau(p,0)| = "
                f"{h['tau_diff_eq25'][st == 3].max() / 1e6:.2f} MPa"
            )
    return 0 if ok else 1


def _check_options(args):
    """Refuse options the requested runs would not use; fill in the defaults of the rest."""
    if args.law is None:  # a parameter file is only used by the law that reads it
        args.law = "sbmf" if args.params is not None else args.default_law
    used = LAW_OPTIONS[args.law]
    for name in ("mu", "m", "tau_max", "params"):
        if getattr(args, name) is not None and name not in used:
            flag = "--" + name.replace("_", "-")
            hint = " (add --law sbmf to run the parameter file's law)" if name == "params" else ""
            raise ValueError(f"{flag} is not used by --law {args.law}{hint}")
    if args.law == "cap" and args.tau_max is not None and args.m is not None:
        raise ValueError("--m is not used by --law cap when --tau-max gives the cap")
    if getattr(args, "m_list", None) is not None:
        if args.law != "tresca":
            raise ValueError(f"--m-list is not used by --law {args.law} (it sweeps Tresca's m)")
        if args.m is not None:
            raise ValueError("give --m or --m-list, not both")
    if args.band or args.samples:
        flag = "--band" if args.band else "--samples"
        if args.law != "sbmf" or args.params is None:
            raise ValueError(f"{flag} needs --law sbmf and a --params file from several samples")
        if getattr(args, "m_list", None) is not None:
            raise ValueError(f"--m-list is not used with {flag}")
    args.m_given = args.m is not None
    args.mu = _MU if args.mu is None else args.mu
    args.m = _M if args.m is None else args.m
    if args.params is not None:
        if not args.params.exists():
            raise ValueError(f"--params file {args.params} does not exist")
        # unreadable files and failed fits: bad input, before any run
        P = FrictionParams.from_json(args.params, accept_failed=args.accept_failed_fit)
        reason = P.failure
        if reason:  # accepted: the run uses the object, and says so
            args.params_loaded = P
            print(f"fe-demo: WARNING: {args.params}: {reason}; run as asked", file=sys.stderr)
        if args.band or args.samples:
            args.band_laws = band_laws(P, "band" if args.band else "samples", args.params)
            args.band_level = P.uncertainty.level


def _cmd_band(args, con):
    """The scene once per law of the band (or per sample); the band's files in ``args.out``."""
    results = {}
    for name, law in args.band_laws:
        kw = _common_kw(args, "sbmf")
        kw["params"] = law
        if args.scene == "upsetting":
            res = run_upsetting(
                "sbmf",
                diameter=args.diameter,
                height=args.height,
                reduction=args.reduction,
                remesh_below=args.remesh_below,
                **kw,
            )
        elif args.scene == "ring":
            res = run_ring("sbmf", reduction=args.reduction, remesh_below=args.remesh_below, **kw)
        else:
            res = run_multistage(
                "sbmf", first_reduction=args.first_reduction, reduction=args.reduction, **kw
            )
        _write_run(args.out / name, res, f"sbmf {name}")
        _report_run(con, name, res)
        results[name] = (
            res.history or None,
            {
                "converged": res.converged,
                "message": res.message,
                "calibrated_range": res.info.get("calibrated_range"),
                "law": {k: getattr(law, k) for k in ("C1", "n1", "C2", "n2")},
            },
        )
    keys = [("force", "N")] + ([("inner_diameter_change", "1")] if args.scene == "ring" else [])
    rec = write_band_outputs(
        args.out, args.scene, "band" if args.band else "samples", args.band_level, results, keys
    )
    for key, unit in keys:
        for red, v in rec[f"{key}_at"].items():
            s = 1e-3 if unit == "N" else 100.0
            u = "kN" if unit == "N" else "%"
            con.result(
                f"{key} at {red}: {v['central'] * s:.4g} {u} +- {v['plus_minus'] * s:.3g} {u} "
                f"[{v['lower'] * s:.4g}, {v['upper'] * s:.4g}]"
            )
    return 0 if rec["ok"] else 1


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
        return ringfit_cmd.run(args, con)
    if not (0.0 < args.reduction < 0.9):
        return con.error("--reduction must be in (0, 0.9)", 2)
    try:
        _check_options(args)
        folder = OutputFolder(
            args.out,
            command="fe-demo",
            what="fe-demo output",
            inputs=(args.params, args.material),
        )
    except (ValueError, OSError) as exc:
        return con.error(exc, 2)
    out, args.out = args.out, folder.tmp
    cmd = {"upsetting": _cmd_upsetting, "ring": _cmd_ring}.get(args.scene, _cmd_multistage)
    if args.band or args.samples:
        cmd = _cmd_band
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
