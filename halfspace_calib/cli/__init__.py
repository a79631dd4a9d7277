"""``halfspace-calib``: calibrate the friction law; with no arguments, the built-in default scene.

Exit codes: 0 success; 1 the run failed (a load level or solve failed or did not converge, a
degenerate fit, a failed effect solve); 2 bad input (refused before any sweep, no traceback).
Outputs are written into a temporary folder beside ``--out`` and moved into place at the end,
replacing an earlier calibration's whole output set (:class:`sbmf_cli.OutputFolder`).
The summary goes to stdout (hidden by ``--quiet``), warnings and errors to stderr.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import fields
from pathlib import Path

from sbmf_cli import (
    Console,
    HelpFormatter,
    OutputFolder,
    add_common_options,
    add_version,
    file_path,
    flags_of,
    interruptible,
    parse,
    process_seconds,
    refuse_repeats,
)

from ..output.hardness import write_hardness_fit
from ..output.report import write_outputs
from ..pipeline.calibration import Scene, calibrate, load_scene, load_scene_surfaces
from ..pipeline.sweep.lateral_scale import FIRST_LEVEL_P, SLOPE_RANGE
from ..pipeline.sweep.scene import BOUNDARIES, MIN_TOL, PAPER_PRESSURES
from ..pipeline.sweep.scene_surfaces import (
    ELEMENTS_PER_LAMBDA_S,
    ISO_SAMPLING_RATIO,
    MAX_DEFAULT_GRID,
)
from ._flattening import (
    add_flattening_options,
    check_flattening_slope,
    flattening_input,
    flattening_lines,
    with_flattening,
)
from ._law import add_law_options, law_lines
from ._paths import (
    after_contact,
    exit_code,
    fit_h,
    main_samples,
    mark_failed,
    run_inputs,
    sample_spec,
)
from ._report import print_effects, print_input, print_resolution, ran

#: files that mark a folder as a calibration output (a rerun may replace it)
#: the Scene's defaults, shown in --help
_D = {f.name: f.default for f in fields(Scene)}


def _pressures(text):
    """``--pressures``: a comma-separated list in Pa, or ``paper`` (the paper's 10-600 MPa)."""
    if text.strip().lower() == "paper":
        return PAPER_PRESSURES
    return _floats(text)


def _floats(text):
    try:
        return tuple(float(v) for v in text.split(",") if v.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected comma-separated numbers, got {text!r}"
        ) from None


def build_parser():
    """The argument parser (SI units: Pa, m)."""
    ap = argparse.ArgumentParser(
        prog="halfspace-calib",
        description="Calibrate the SBMF friction law (Eqs. 24-25) from elasto-plastic half-space "
        "contact of a workpiece and a tool surface. With no arguments: the paper's Table 1 "
        "materials and roughness on synthetic surfaces at 128 x 128.",
        formatter_class=HelpFormatter,
    )
    add_version(ap)
    ap.add_argument("--out", default="out/calibration", help="output folder")
    ap.add_argument(
        "--scene",
        type=file_path,
        help="scene file (TOML, keys as the Scene fields); options override it (default: none)",
    )
    g = ap.add_argument_group("surfaces")
    g.add_argument(
        "--workpiece",
        nargs="+",
        type=file_path,
        help="workpiece topography file(s) (default: synthetic DC04 EDT); several files: a "
        "multi-sample calibration with a band (each against the one --tool, or paired in order)",
    )
    g.add_argument(
        "--tool",
        nargs="+",
        type=file_path,
        help="tool topography file(s) (default: synthetic hardened tool): one for all "
        "workpieces, or one per workpiece",
    )
    g.add_argument(
        "--unit",
        help="height unit of plain files: m, mm, um, nm (instrument files and text matrices with "
        "a '# Value units:' header carry their own; default: none, required for plain files)",
    )
    g.add_argument("--workpiece-unit", help="height unit of the workpiece file (default --unit)")
    g.add_argument("--tool-unit", help="height unit of the tool file (default --unit)")
    g.add_argument(
        "--size",
        type=float,
        nargs="+",
        metavar=("LX", "LY"),
        help="physical size of plain height matrices (m): one value (square) or two (rows, "
        "columns); default: none, required for plain matrices",
    )
    for role in ("workpiece", "tool"):
        g.add_argument(
            f"--{role}-size",
            type=float,
            nargs="+",
            metavar=("LX", "LY"),
            help=f"physical size of every {role} file (m; one value: square, two: rows, columns), "
            "overriding the size the file carries (a wrong header or instrument calibration; "
            "the file's own size is recorded beside it); default: none, the file's own",
        )
    g.add_argument(
        "--smooth-pair",
        action="store_true",
        default=None,
        help="state that the pair is truly this smooth: an RMS slope below "
        f"{SLOPE_RANGE[0]:g} is not refused and full contact at a first load level below "
        f"{FIRST_LEVEL_P:g} H does not fail the run (default: off; both most likely mean a "
        "lateral size in the wrong unit)",
    )
    g.add_argument(
        "--crop-size",
        type=float,
        help="edge of the square patch used from the files (m; default: the largest common "
        "square of workpiece and tool)",
    )
    g.add_argument(
        "--max-undefined",
        type=float,
        help="largest fraction of undefined (unmeasured) points filled by harmonic "
        f"interpolation; above it a file is refused (default {_D['max_undefined']:g})",
    )
    g.add_argument(
        "--lambda-s",
        type=float,
        help="short-wavelength cut-off of the files (m): nesting index of the ISO 16610-61 "
        "Gaussian S-filter applied after levelling, before resampling; 0: no filter (default: "
        f"the smallest ISO 25178-3 index >= {ISO_SAMPLING_RATIO:g} pixel pitches and >= "
        f"{ELEMENTS_PER_LAMBDA_S} elements of the square at grid {MAX_DEFAULT_GRID})",
    )
    g.add_argument(
        "--lambda-c",
        type=float,
        help="long-wavelength cut-off of the files (m): ISO 16610-61 Gaussian L-filter, "
        "removes waviness beyond the plane (default: none, only the plane is removed)",
    )
    g.add_argument(
        "--rough-tool",
        action="store_true",
        default=None,
        help="synthetic rough tool (Ra 0.240 um) instead of the smooth one (default: smooth)",
    )
    g.add_argument(
        "--grid",
        type=int,
        help="solver grid: N x N elements (default 128 for synthetic surfaces; for files "
        f"{ELEMENTS_PER_LAMBDA_S} elements per lambda_s, at most {MAX_DEFAULT_GRID}; the "
        "coarser scan is interpolated (band-limited) where its pixel is larger than the "
        "element; with --lambda-s 0 at most the scans' sampling on the common square)",
    )
    g = ap.add_argument_group("materials (Pa)")
    g.add_argument(
        "--E-workpiece",
        type=float,
        help=f"workpiece Young's modulus (default {_D['E_workpiece']:g})",
    )
    g.add_argument(
        "--nu-workpiece",
        type=float,
        help=f"workpiece Poisson ratio (default {_D['nu_workpiece']:g})",
    )
    g.add_argument("--E-tool", type=float, help=f"tool Young's modulus (default {_D['E_tool']:g})")
    g.add_argument("--nu-tool", type=float, help=f"tool Poisson ratio (default {_D['nu_tool']:g})")
    g.add_argument(
        "--H", type=float, help=f"hardness (default {_D['H']:g}; 2.8 sigma_y if only --sigma-y)"
    )
    g.add_argument(
        "--after-contact",
        metavar="FILE",
        type=file_path,
        help="fit H to the workpiece's measured roughness after pressing (Sec. 3.1, Figs. 3-4): "
        "a text table 'p_mean [MPa], Ra [um], Rq [um]', one row per sample, >= 2 loads, a "
        "p_mean = 0 row for before contact; or a table 'p_mean [MPa], file' naming surfaces "
        "scanned after unloading, measured with the calibration's crop, levelling, filters and "
        "grid; then calibrate with that H (default: no fit, H as given); writes "
        "hardness_fit.{csv,json,md,png} with H's standard error",
    )
    g.add_argument("--sigma-y", type=float, help="yield stress (default H / 2.8)")
    g.add_argument(
        "--m", type=float, help=f"Tresca friction factor in [0, 1] (default {_D['m']:g})"
    )
    g = ap.add_argument_group("sweeps and solver")
    g.add_argument(
        "--pressures",
        type=_pressures,
        help="first-loading p_mean list in Pa, comma separated, or 'paper' for the paper's "
        "10-600 MPa: computed as given, no refinement (default: the range "
        + f"{min(_D['pressures']) / 1e6:g}-{max(_D['pressures']) / 1e6:g} MPa"
        + " for H = 800 MPa, for another H up to 0.95 H, its levels placed where alpha changes: "
        "the ends and --reload-from first, then each interval's midpoint while the law "
        "interpolated from the other levels misses it by more than 0.1 --heldout-tol in first "
        "loading or 0.3 --heldout-tol in a reload curve; not where both ends are in full "
        "contact, alpha >= 0.995)",
    )
    g.add_argument(
        "--reload-fractions",
        type=_floats,
        help="reload pressures as fractions of p_hist (default: "
        + ",".join(f"{f:g}" for f in _D["reload_fractions"])
        + ")",
    )
    g.add_argument(
        "--reload-from",
        type=float,
        help=f"smallest p_hist with a reload curve (Pa; default {_D['reload_from']:g})",
    )
    g.add_argument(
        "--tol",
        type=float,
        help=f"solver tolerance, in [{MIN_TOL:g}, 1) (default {_D['tol']:g})",
    )
    g.add_argument(
        "--boundary",
        choices=BOUNDARIES,
        help="how the solver closes the patch: mirror (one quarter of the period of the patch's "
        "mirror-symmetric extension: no seam, no patch edge), periodic (the patch is one period, "
        "its opposite edges joined) or isolated (a finite body on a half-space, zero-padded "
        "DC-FFT: the default for files before the mirror, whose nearly conforming patches act as "
        "flat punches) (default: periodic for synthetic surfaces, mirror for files)",
    )
    g.add_argument(
        "--periodic",
        dest="periodic",
        action="store_true",
        default=None,
        help="the older spelling of --boundary periodic (default: off)",
    )
    g.add_argument(
        "--no-periodic",
        dest="periodic",
        action="store_false",
        help="the older spelling of --boundary isolated (the zero-padded DC-FFT solve; "
        "default: off)",
    )
    g.add_argument(
        "--no-resolution-check",
        dest="resolution_check",
        action="store_false",
        default=None,
        help="skip the check at half the grid (default: on for files)",
    )
    g.add_argument(
        "--resolution-check",
        dest="resolution_check",
        action="store_true",
        help="run the check at half the grid also for synthetic surfaces",
    )
    g.add_argument(
        "--no-volume-conservation",
        dest="volume_conservation",
        action="store_false",
        default=None,
        help="let plastic flow lose volume (default: the flowed volume is conserved)",
    )
    g.add_argument(
        "--reload-surface",
        choices=["plastic", "volume_conserving"],
        help="surface the reloads start from (default: " + _D["reload_surface"] + ")",
    )
    g.add_argument(
        "--contact-area",
        choices=["count", "perimeter"],
        help="contact ratio of the fits: element count, or the count corrected with the contact "
        "perimeter (Yastrebov et al. 2017; default: count)",
    )
    add_law_options(g, _D)
    g.add_argument(
        "--workers",
        type=int,
        help="local processes of the normal sweeps (1: in this process, 0: one per CPU; default: "
        "2 from 362^2 FFT elements per solve on 2 or more CPUs, else 1)",
    )
    g.add_argument(
        "--scheduler", help="Dask scheduler address, e.g. tcp://host:8786 (default: none)"
    )
    g = ap.add_argument_group("effects")
    g.add_argument(
        "--effects",
        help="comma-separated effects to model: normal (always on), tangential (pre-sliding "
        "stiffness k_t per pressure, into <out>/tangential/), inclined (tau_geo of inclined "
        "patches, Eq. 23, and Eq. 26's geo_ratio if significant, into <out>/geometric/), sliding "
        "(W_def / W_adh of Sec. 3.3, into <out>/sliding/); default: the scene's, else normal",
    )
    g.add_argument(
        "--geo-threshold",
        type=float,
        help=f"mean tau_geo / tau_adh above which Eq. 26's term is fitted (default {_D['geo_threshold']:g})",
    )
    g.add_argument(
        "--sliding",
        action="store_true",
        help="same as adding 'sliding' to --effects: the sliding study of Sec. 3.3 (W_def / W_adh "
        "at 100-600 MPa on a 3x longer synthetic strip, Ra 0.989 um) into <out>/sliding/ "
        "(default: off)",
    )
    g = ap.add_argument_group("several samples (docs/uncertainty.md)")
    g.add_argument(
        "--patches",
        type=int,
        help="cut every workpiece/tool pair into N non-overlapping square patches, each a sample "
        "(default 1; synthetic surfaces: patches of one larger synthetic surface)",
    )
    g.add_argument(
        "--band-level",
        type=float,
        help="two-sided level of the bootstrap band over the samples (default 0.9)",
    )
    g.add_argument(
        "--bootstrap",
        type=int,
        help="bootstrap resamples of the band (default 400, at least 50)",
    )
    g.add_argument(
        "--band-method",
        choices=("t", "percentile"),
        help="the band from the resamples: t (pooled value -+ Student t x bootstrap standard "
        "error, the small-sample correction) or percentile (default t)",
    )
    add_flattening_options(ap)
    add_common_options(ap)
    return refuse_repeats(ap)  # a value option given twice is refused, not the last kept


def scene_from_args(args):
    """A :class:`Scene` from parsed arguments (scene file first, then the options)."""
    over = {
        k: getattr(args, k)
        for k in (
            "workpiece",
            "tool",
            "unit",
            "workpiece_unit",
            "tool_unit",
            "size",
            "workpiece_size",
            "tool_size",
            "smooth_pair",
            "crop_size",
            "max_undefined",
            "lambda_s",
            "lambda_c",
            "rough_tool",
            "grid",
            "E_workpiece",
            "nu_workpiece",
            "E_tool",
            "nu_tool",
            "H",
            "sigma_y",
            "m",
            "pressures",
            "reload_fractions",
            "reload_from",
            "tol",
            "boundary",
            "resolution_check",
            "volume_conservation",
            "reload_surface",
            "contact_area",
            "continuous_reload",
            "first_loading_form",
            "reload_form",
            "heldout_tol",
            "workers",
            "scheduler",
            "effects",
            "geo_threshold",
        )
    }
    if args.pressures is not None:  # given levels are computed as given, even the default's
        over["adaptive_levels"] = False
    if args.periodic is not None:  # the older spelling of --boundary
        if args.boundary is not None:
            flag = "--periodic" if args.periodic else "--no-periodic"
            raise ValueError(f"give --boundary or {flag}, not both")
        over["boundary"] = "periodic" if args.periodic else "isolated"
    for role in ("workpiece", "tool"):  # several files: the first here, all in sample_spec
        if over[role] is not None:
            over[role] = over[role][0]
    for name in ("size", "workpiece_size", "tool_size"):
        v = over[name]
        if v is not None:
            flag = "--" + name.replace("_", "-")
            if len(v) > 2:
                raise ValueError(f"{flag} takes one or two lengths (m), got {len(v)}")
            over[name] = v[0] if len(v) == 1 else tuple(v)
    if args.sliding:
        from ..pipeline.sweep.effects import check_effects

        if over["effects"] is None:  # add to the scene file's effects, or to the default
            base = load_scene(args.scene).effects if args.scene else ("normal",)
        else:
            base = check_effects(over["effects"])
        over["effects"] = tuple(base) + ("sliding",)
    if over["H"] is None and over["sigma_y"] is not None and not args.scene:
        over["H"] = 2.8 * over["sigma_y"]
    if args.scene:
        scene = load_scene(args.scene, **over)
    else:
        scene = Scene(**{k: v for k, v in over.items() if v is not None})
    if over["max_undefined"] is not None and not scene.from_files:
        raise ValueError(
            "--max-undefined applies to surface files only; no workpiece or tool file was given"
        )
    if over["geo_threshold"] is not None and "inclined" not in scene.effects:
        raise ValueError("--geo-threshold applies to the inclined effect: add --effects inclined")
    return scene


@interruptible("halfspace-calib", "the calibration")
def main(argv=None):
    """Entry point of ``halfspace-calib``; returns the exit code (0, 1, 2; 130/143 interrupted)."""
    parser = build_parser()
    args, code = parse(parser, argv)
    if args is None:
        return code
    con = Console("halfspace-calib", quiet=args.quiet, flags=flags_of(parser))
    hfit = None
    try:
        scene = scene_from_args(args)
        spec = sample_spec(args, scene)
        flat = flattening_input(args, spec, scene)
        if spec.multi:
            if args.after_contact is not None:
                raise ValueError(
                    "--after-contact fits H on one workpiece/tool pair; with several samples "
                    "fit H first on one pair and give it as --H"
                )
            return main_samples(con, args, scene, spec)
        surfaces = load_scene_surfaces(scene)  # every file check before any sweep
        check_flattening_slope(flat, surfaces)
        data = after_contact(args, scene)
        folder = OutputFolder(
            args.out,
            command="halfspace-calib",
            what="calibration output",
            inputs=run_inputs(args, scene),
        )
    except FileNotFoundError as exc:
        msg = str(exc) if "not found" in str(exc) else f"file not found: {exc.filename}"
        return con.error(msg, 2)
    except (ValueError, ImportError, OSError) as exc:
        return con.error(exc, 2)
    with folder:
        try:
            print_input(con, scene, surfaces, derived=scene.grid is None)
            if data is not None:
                try:
                    hfit, scene = fit_h(con, args, scene, surfaces, data)
                except ValueError as exc:
                    return con.error(exc, 2)
            progress = not (args.quiet or args.no_progress)
            cal = with_flattening(calibrate(scene, progress=progress, surfaces=surfaces), *flat)
            write_outputs(cal, folder.tmp, clock=process_seconds)
            run_seconds = json.loads((folder.tmp / "summary.json").read_text())["command_seconds"]
            if hfit is not None:
                write_hardness_fit(hfit, folder.tmp)
            mark_failed(folder.tmp, cal.problems())
            folder.commit()
        except (RuntimeError, MemoryError, ValueError) as exc:  # input was checked: the run failed
            return con.error(f"the run failed: {con.text(exc) or type(exc).__name__}", 1)
        except OSError as exc:  # writing the outputs (disk full, permissions changed meanwhile)
            return con.error(f"the outputs could not be written, {args.out} is unchanged: {exc}", 1)
    out = Path(args.out)
    P = cal.params
    s = cal.summary()
    say = con.result
    say(ran(run_seconds, cal.seconds, out, cal.problems()))
    for line in law_lines(cal, s):
        say(line)
    say(f"  Coulomb slope mu_eff = {P.mu_eff:.4f}, cap m k = {P.tau_max / 1e6:.1f} MPa")
    say(
        f"  bound alpha >= p/H: largest violation by Eq. 24 {s['alpha_bound_violation_to_p_max']:.4f} "
        f"up to p_max, {s['alpha_bound_violation_to_H']:.4f} up to H (alpha1(H) = "
        f"{s['alpha1_at_H']:.4f}); R^2 given up for it {s['alpha_bound_r2_cost'] or 0:.2g}"
    )
    say(
        f"  reloads: largest local pressure {s['max_reload_pressure_over_H']:.3f} H, "
        f"plastic fraction {s['max_reload_plastic_fraction']:.4f}"
    )
    print_effects(con, cal, out)
    for line in flattening_lines(cal):
        say(line)
    print_resolution(con, cal.resolution)
    for note in cal.notes:  # what calibrate() decided on its own: stderr
        con.warn(f"halfspace-calib: note: {note}")
    return exit_code(con, cal.problems())


if __name__ == "__main__":
    sys.exit(main())
