"""The runs of ``fe-demo upsetting|ring|multistage`` and of their ``--band`` / ``--samples``.

Each scene run, its files in the output folder and its console lines; ``cmd_*`` return the exit
code (0, or 1 when a run did not converge).
"""

import hashlib
import json
from pathlib import Path

import numpy as np

from sbmf_cli import existing_file, file_path

from ..analysis.band import band_result
from ..analysis.ring_chart import CHART_M, ring_chart
from ..output import (
    plot_force_stroke,
    plot_law_comparison,
    plot_recontact,
    plot_ring_chart,
    summary_table,
    write_history_csv,
    write_vtu_series,
)
from ..output.band import write_band_outputs
from ..output.flattening import flattening_record, plot_flattening
from ..output.reports import range_lines, write_run_report
from ..scenes import contact_profile, run_multistage, run_ring, run_upsetting
from ..scenes.laws import LAWS
from ..solver.material import DC04, Material

__all__ = [
    "cmd_band",
    "cmd_multistage",
    "cmd_ring",
    "cmd_upsetting",
    "material_file",
    "path_arg",
    "write_run",
]


def _material(args):
    loaded = getattr(args, "material_loaded", None)  # read before the run (material_file)
    return loaded or material_file(args.material)


def path_arg(text):
    """The argparse ``type`` of a file option: a :class:`~pathlib.Path`, an empty one refused.

    ``Path("")`` is the working folder: without this, ``--material ""`` read as ``.``.
    """
    return Path(file_path(text))


def material_file(path):
    """The :class:`Material` of ``--material`` (DC04 without one), read before any run.

    A missing, unreadable or malformed file is bad input (``ValueError``) naming the option and
    the path.
    """
    if path is None:
        return DC04
    path = existing_file("--material", path, "a material JSON file")
    try:
        return Material.from_json(path)
    except json.JSONDecodeError as exc:
        raise ValueError(f"--material {path}: not valid JSON ({exc})") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"--material {path}: cannot be read ({exc})") from None
    except (TypeError, ValueError) as exc:
        text = str(exc).removeprefix(f"{path}: ")
        raise ValueError(f"--material {path}: {text}") from None


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


def _zone_kw(args, law):
    """``{"zones": ...}`` of a zoned die (``--zone``, upsetting and ring), else ``{}``."""
    zones = getattr(args, "zones_loaded", ())
    return {"zones": zones} if zones and law == "sbmf" else {}


def _variants(args):
    """The flattening variants of each run: ``[None]``, or without and with (``--flattening``)."""
    return [False, True] if getattr(args, "flattening", False) else [None]


def _flat_name(variant):
    """A run's label suffix and subfolder for its flattening variant (``None``: none)."""
    if variant is None:
        return "", None
    return (
        (" with flattening", "with_flattening")
        if variant
        else (
            " without flattening",
            "without_flattening",
        )
    )


def write_flattening(con, out, pairs):
    """A flattening comparison's files: ``flattening.png`` in ``out``, each pair's record.

    ``pairs``: ``[(label, (folder, result) without, (folder, result) with)]``; each run's
    ``summary.json`` and ``report.html`` get the pair's ``flattening`` record, the console a line.
    """
    curves = {}
    for label, (f0, r0), (f1, r1) in pairs:
        rec = flattening_record(r0.history, r1.history)
        for folder, res, lab in ((f0, r0, " without"), (f1, r1, " with")):
            curves[label + lab] = res.history
            path = folder / "summary.json"
            if path.is_file():
                info = json.loads(path.read_text()) | {"flattening": rec}
                path.write_text(json.dumps(info, indent=2, default=_jd) + "\n")
        if rec["force_end_with_N"] is not None and rec["force_end_without_N"]:
            con.result(
                f"[{label}] flattening: die force at the end {rec['force_end_without_N'] / 1e3:.4g} kN "
                f"without, {rec['force_end_with_N'] / 1e3:.4g} kN with "
                f"({100 * rec['force_change_fraction']:+.2f} %); mean contact fraction at the die "
                f"{rec['alpha_die_mean_end_without']:.3f} -> {rec['alpha_die_mean_end_with']:.3f} at "
                f"a mean plastic strain of {rec['eps_p_die_mean_end_with']:.3f} there"
            )
        if rec.get("n_below_flattening_table_max_with"):
            con.warn(
                f"[{label}] flattening: up to {rec['n_below_flattening_table_max_with']} die "
                "contact nodes pressed below the two-state table's lowest pressure (0.02 H_P at "
                "their flow stress), where the law reads its lowest rates: an upper bound of the "
                f"flattening there ({rec['n_below_flattening_table_end_with']} at the end)"
            )
    out.mkdir(parents=True, exist_ok=True)
    plot_flattening(out / "flattening.png", curves)
    for label, (f0, _), (f1, _) in pairs:  # the reports again, now with the figure
        for folder, lab in ((f0, label + " without flattening"), (f1, label + " with flattening")):
            if (folder / "summary.json").is_file():
                write_run_report(folder, json.loads((folder / "summary.json").read_text()), lab)


def _label(law, args):
    """The run's name in tables, legends and titles: the law and what tells its runs apart."""
    if law == "tresca":
        return f"tresca m={args.m:g}"
    if law == "coulomb":
        return f"coulomb mu={args.mu:g}"
    if law == "cap":
        return f"cap mu={args.mu:g}"
    if law == "sbmf":
        lab = sbmf_label(args.params)
        for name, _, r in getattr(args, "zones_loaded", ()):
            lab += f" + {name} from r={r * 1e3:g} mm"
        return lab
    return "frictionless"


def sbmf_label(path):
    """``sbmf <folder>/<file> [sha256 prefix]``: two calibrations' ``params.json`` differ.

    The shipped illustrative set is ``sbmf example law (illustrative)``.
    """
    if path is None:
        return "sbmf example law (illustrative)"
    path = Path(path)
    digest = hashlib.sha256(path.read_bytes()).hexdigest()[:8]
    where = f"{path.parent.name}/{path.name}" if path.parent.name else path.name
    return f"sbmf {where} [{digest}]"


def _folder_name(label):
    """A run's subfolder, from its label (an sbmf run's is ``sbmf``)."""
    if label.startswith("sbmf"):
        return "sbmf"
    return label.replace(" ", "_").replace("=", "")


#: the units of summary.json's numbers whose names do not state one (fractions: 0.5 for 50 %)
SUMMARY_UNITS = {
    "stopped_at_height_reduction": "fraction",
    "inner_diameter_change": "fraction",
    "inner_diameter_min_change": "fraction",
    "force_end_N": "N",
    "wall_time_s": "s",
}


def write_run(folder, res, title):
    """A run's files in ``folder``: history.csv, its plots, VTU series, summary.json, report.html."""
    folder.mkdir(parents=True, exist_ok=True)
    if res.history:
        write_history_csv(folder / "history.csv", res.history)
    for name, fig in res.figures(title).items():
        fig.savefig(folder / name, dpi=120)
    if res.snapshots and len(res.snapshots) > 1:
        write_vtu_series(folder / "vtu", res.model.t, res.snapshots)
    info = dict(res.info)
    h = res.history
    info.update(
        run=title,
        converged=res.converged,
        message=res.message,
        stopped_at_height_reduction=res.model.height_reduction,
        force_end_N=float(h["force"][-1]) if h else None,
        increments_accepted=len(h["force"]) if h else 0,
        wall_time_s=res.wall_time,
    )
    if h and "inner_diameter_change" in h:  # a ring: what a ring test measures, at the end
        info["inner_diameter_change"] = float(h["inner_diameter_change"][-1])
        info["inner_diameter_min_change"] = float(h["inner_diameter_min_change"][-1])
    info["units"] = {k: u for k, u in SUMMARY_UNITS.items() if k in info}
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
    h = res.history
    zones = res.info.get("law_parameters", {}).get("zones", ())
    if zones and h:
        con.result(
            f"[{label}] contact nodes per die zone at the end: "
            + ", ".join(
                f"{z['zone']} (from r = {z['from_radius_m'] * 1e3:g} mm) "
                f"{int(h['n_contact_' + z['zone']][-1])}"
                for z in zones
            )
        )
    kt = res.info.get("tangential_stiffness", {})
    if kt.get("k_t_min_Pa_per_m") is not None:
        con.result(
            f"[{label}] stick stiffness k_t(p) from the parameter file: "
            f"{kt['k_t_min_Pa_per_m']:.3g} .. {kt['k_t_max_Pa_per_m']:.3g} Pa/m"
        )


def _summary_row(label, res, *, ring=False):
    """One row of the console table: the reduction and a ring's inner-diameter change in %.

    A person reads the table: percent, said in the header (``reduction_%``, ``ID_change_%``);
    the files give fractions (``history.csv``: ``height_reduction_fraction``).
    """
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
        "reduction_%": 100.0 * float(h["height_reduction"][-1]) if h else 0.0,
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


def cmd_upsetting(args, con):
    """``fe-demo upsetting``: one run per law (``--law all``: every law side by side)."""
    laws = [w for w in LAWS if w != "none"] if args.law == "all" else [args.law]
    results, rows, flat = {}, [], {}
    ok = True
    for law in laws:
        for variant in _variants(args):
            kw = _common_kw(args, law) | _zone_kw(args, law)
            res = run_upsetting(
                law,
                diameter=args.diameter,
                height=args.height,
                reduction=args.reduction,
                remesh_below=args.remesh_below,
                flattening=variant,
                **kw,
            )
            suffix, sub = _flat_name(variant)
            lab = _label(law, args) + suffix
            folder = args.out / law if len(laws) > 1 else args.out
            folder = folder / sub if sub else folder
            write_run(folder, res, lab)
            results[lab] = (res.history, contact_profile(res.model)) if res.history else None
            rows.append(_summary_row(lab, res))
            ok &= res.converged
            _report_run(con, lab, res)
            flat.setdefault(_label(law, args), []).append((folder, res))
    if getattr(args, "flattening", False):
        write_flattening(con, args.out, [(k, *v) for k, v in flat.items()])
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


def cmd_ring(args, con):
    """``fe-demo ring``: the runs (a Tresca sweep, or the laws) over the upper-bound chart."""
    m_list = _m_list(args)
    runs = []
    if m_list:
        for m in m_list:
            runs.append(("tresca" if m > 0 else "none", m, f"FE m={m:g}"))
    elif args.law == "all":
        runs = [(law, args.m, _label(law, args)) for law in LAWS if law != "none"]
    else:
        runs.append((args.law, args.m, _label(args.law, args)))
    rows, fe, flat, folders = [], {}, {}, []
    ok = True
    for law, m, base in runs:
        for variant in _variants(args):
            kw = _common_kw(args, law) | _zone_kw(args, law)
            kw["m"] = m
            res = run_ring(
                law,
                reduction=args.reduction,
                remesh_below=args.remesh_below,
                flattening=variant,
                **kw,
            )
            suffix, sub = _flat_name(variant)
            lab = base + suffix
            folder = args.out / _folder_name(base) if len(runs) > 1 else args.out
            folder = folder / sub if sub else folder
            write_run(folder, res, lab)
            folders.append((folder, lab))
            if res.history:
                fe[lab] = (res.history["height_reduction"], res.history["inner_diameter_change"])
            rows.append(_summary_row(lab, res, ring=True))
            ok &= res.converged
            _report_run(con, lab, res)
            flat.setdefault(base, []).append((folder, res))
    args.out.mkdir(parents=True, exist_ok=True)
    chart, notes = _chart(args.reduction)
    plot_ring_chart(args.out / "ring_chart.png", chart, fe)
    with (args.out / "ring_chart_upper_bound.csv").open("w", encoding="utf-8") as fh:
        fh.write("m,height_reduction_fraction,inner_diameter_change_fraction\n")
        for m, (red, d) in chart.items():
            for a, b in zip(red, d, strict=True):
                fh.write(f"{m:g},{a:.6g},{b:.6g}\n")
    for folder, lab in folders:  # the runs' reports again, now with the chart
        if (folder / "summary.json").is_file():
            write_run_report(folder, json.loads((folder / "summary.json").read_text()), lab)
    if getattr(args, "flattening", False):
        write_flattening(con, args.out, [(k, *v) for k, v in flat.items()])
    con.result(summary_table(rows))
    for note in notes:
        con.result(note)
    return 0 if ok else 1


def cmd_multistage(args, con):
    """``fe-demo multistage``: each law with and without ``p_hist``."""
    laws = [w for w in LAWS if w != "none"] if args.law == "all" else [args.law]
    rows, curves, flat = [], {}, {}
    ok = True
    runs = [(w, r, v) for w in laws for v in _variants(args) for r in (False, True)]
    for law, reset, variant in runs:
        kw = _common_kw(args, law)
        res = run_multistage(
            law,
            first_reduction=args.first_reduction,
            reduction=args.reduction,
            reset_history=reset,
            flattening=variant,
            **kw,
        )
        suffix, fsub = _flat_name(variant)
        hist_lab = " without p_hist" if reset else " with p_hist"
        lab = _label(law, args) + hist_lab + suffix
        sub = args.out / law if len(laws) > 1 else args.out
        sub = sub / fsub if fsub else sub
        folder = sub / ("no_history" if reset else "with_history")
        write_run(folder, res, lab)
        flat.setdefault(_label(law, args) + hist_lab, []).append((folder, res))
        prof = res.info.get("recontact_profile")
        if prof is not None and not reset:
            plot_recontact(sub / "recontact_friction.png", prof)
        if res.history:
            curves[lab] = res.history
        rows.append(_summary_row(lab, res))
        ok &= res.converged
        _report_run(con, lab, res)
    if getattr(args, "flattening", False):
        write_flattening(con, args.out, [(k, *v) for k, v in flat.items()])
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


def cmd_band(args, con):
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
        write_run(args.out / name, res, f"sbmf {name}")
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
    keys = [("force", "N")] + (
        [("inner_diameter_change", "fraction")] if args.scene == "ring" else []
    )
    mode = "band" if args.band else "samples"
    rec = write_band_outputs(
        args.out,
        band_result(args.scene, mode, args.band_level, results, keys),
        mode,
        args.band_level,
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
