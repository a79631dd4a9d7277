"""``halfspace-calib``: calibrate the friction law; with no arguments, the built-in default scene.

Exit codes: 0 success; 1 the run failed (a load level or solve failed or did not converge, a
degenerate fit, a failed effect solve); 2 bad input (refused before any sweep, no traceback).
Outputs are written into a temporary folder beside ``--out`` and moved into place at the end,
replacing an earlier calibration's whole output set.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

from .output.hardness import hardness_table, write_hardness_fit
from .output.report import write_outputs
from .pipeline.calibration import Scene, calibrate, load_scene, load_scene_surfaces
from .pipeline.hardness import fit_hardness, read_after_contact
from .pipeline.scene_surfaces import (
    ELEMENTS_PER_LAMBDA_S,
    ISO_SAMPLING_RATIO,
    MAX_DEFAULT_GRID,
)

#: files that mark a folder as a calibration output (a rerun may replace it)
_OUTPUT_MARKERS = ("params.json", "summary.json")


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
    )
    ap.add_argument("--out", default="out/calibration", help="output folder (default: %(default)s)")
    ap.add_argument(
        "--scene", help="scene file (TOML, keys as the Scene fields); options override it"
    )
    g = ap.add_argument_group("surfaces")
    g.add_argument(
        "--workpiece",
        nargs="+",
        help="workpiece topography file(s) (default: synthetic DC04 EDT); several files: a "
        "multi-sample calibration with a band (each against the one --tool, or paired in order)",
    )
    g.add_argument(
        "--tool",
        nargs="+",
        help="tool topography file(s) (default: synthetic hardened tool): one for all "
        "workpieces, or one per workpiece",
    )
    g.add_argument(
        "--unit",
        help="height unit of plain files: m, mm, um, nm (instrument files and text matrices with "
        "a '# Value units:' header carry their own)",
    )
    g.add_argument("--workpiece-unit", help="height unit of the workpiece file (default --unit)")
    g.add_argument("--tool-unit", help="height unit of the tool file (default --unit)")
    g.add_argument(
        "--size",
        type=float,
        nargs="+",
        metavar=("LX", "LY"),
        help="physical size of plain height matrices (m): one value (square) or two (rows, "
        "columns)",
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
        "interpolation; above it a file is refused (default 0.05)",
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
        help="synthetic rough tool (Ra 0.240 um) instead of the smooth one",
    )
    g.add_argument(
        "--grid",
        type=int,
        help="solver grid: N x N elements (default 128 for synthetic surfaces; for files "
        f"{ELEMENTS_PER_LAMBDA_S} elements per lambda_s, at most the scans' sampling on the "
        f"common square and {MAX_DEFAULT_GRID})",
    )
    g = ap.add_argument_group("materials (Pa)")
    g.add_argument("--E-workpiece", type=float)
    g.add_argument("--nu-workpiece", type=float)
    g.add_argument("--E-tool", type=float)
    g.add_argument("--nu-tool", type=float)
    g.add_argument(
        "--H", type=float, help="hardness (default 800e6; 2.8 sigma_y if only --sigma-y)"
    )
    g.add_argument(
        "--after-contact",
        metavar="FILE",
        help="fit H to the workpiece's measured roughness after pressing (Sec. 3.1, Figs. 3-4): "
        "a text table 'p_mean [MPa], Ra [um], Rq [um]', one row per sample, >= 2 loads, a "
        "p_mean = 0 row for before contact; then calibrate with that H (default: no fit, H as "
        "given); writes hardness_fit.{csv,json,md,png}",
    )
    g.add_argument("--sigma-y", type=float, help="yield stress (default H / 2.8)")
    g.add_argument("--m", type=float, help="Tresca friction factor in [0, 1] (default 0.5)")
    g = ap.add_argument_group("sweeps and solver")
    g.add_argument(
        "--pressures", type=_floats, help="first-loading p_mean list in Pa, comma separated"
    )
    g.add_argument(
        "--reload-fractions", type=_floats, help="reload pressures as fractions of p_hist"
    )
    g.add_argument("--reload-from", type=float, help="smallest p_hist with a reload curve (Pa)")
    g.add_argument("--tol", type=float, help="solver tolerance (default 1e-8)")
    g.add_argument(
        "--periodic",
        dest="periodic",
        action="store_true",
        default=None,
        help="periodic (FFT) solve; default for synthetic surfaces",
    )
    g.add_argument(
        "--no-periodic",
        dest="periodic",
        action="store_false",
        help="non-periodic (DC-FFT) solve; default for measured files",
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
        "--no-volume-conservation", dest="volume_conservation", action="store_false", default=None
    )
    g.add_argument("--reload-surface", choices=["plastic", "volume_conserving"])
    g.add_argument(
        "--continuous-reload",
        action="store_true",
        default=None,
        help="fit the continuous Eq. 25 (no jump at p_hist)",
    )
    g.add_argument(
        "--workers", type=int, help="processes (default: 2 from 362^2 FFT elements, else 1; 0: per CPU)"
    )
    g.add_argument("--scheduler", help="Dask scheduler address, e.g. tcp://host:8786")
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
        help="mean tau_geo / tau_adh above which Eq. 26's term is fitted (default 0.05)",
    )
    g.add_argument(
        "--sliding",
        action="store_true",
        help="same as adding 'sliding' to --effects: the sliding study of Sec. 3.3 (W_def / W_adh "
        "at 100-600 MPa on a 3x longer synthetic strip, Ra 0.989 um) into <out>/sliding/",
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
    ap.add_argument("--quiet", action="store_true", help="no progress bar")
    return ap


def sample_spec(args, scene):
    """The :class:`SampleSpec` of the options and the scene file's ``[samples]`` table."""
    from .pipeline.samples import SampleSpec, read_samples_table

    kw = read_samples_table(args.scene) if args.scene else {}
    wps, tls = args.workpiece or [], args.tool or []
    if len(wps) > 1 or len(tls) > 1:
        kw["workpieces"], kw["tools"] = tuple(wps), tuple(tls)
    else:  # one file on the command line replaces the scene file's list of that role
        if wps:
            kw.pop("workpieces", None)
        if tls:
            kw.pop("tools", None)
    for key, opt in (("patches", "patches"), ("level", "band_level"), ("n_bootstrap", "bootstrap")):
        if getattr(args, opt) is not None:
            kw[key] = getattr(args, opt)
    spec = SampleSpec(**kw)
    if spec.multi and args.resolution_check:
        raise ValueError(
            "--resolution-check does not run per sample in a multi-sample calibration: "
            "calibrate one sample alone for it"
        )
    if spec.patches > 1 and args.periodic:
        raise ValueError(
            "--periodic: a patch is not one period of a surface, patches are non-periodic"
        )
    if not spec.multi and (args.band_level is not None or args.bootstrap is not None):
        raise ValueError(
            "--band-level and --bootstrap apply to several samples: give several --workpiece "
            "files or --patches N"
        )
    return spec


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
            "periodic",
            "resolution_check",
            "volume_conservation",
            "reload_surface",
            "continuous_reload",
            "workers",
            "scheduler",
            "effects",
            "geo_threshold",
        )
    }
    for role in ("workpiece", "tool"):  # several files: the first here, all in sample_spec
        if over[role] is not None:
            over[role] = over[role][0]
    if over["size"] is not None:
        if len(over["size"]) > 2:
            raise ValueError(f"--size takes one or two lengths (m), got {len(over['size'])}")
        over["size"] = over["size"][0] if len(over["size"]) == 1 else tuple(over["size"])
    if args.sliding:
        from .pipeline.effects import check_effects

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
    if over["geo_threshold"] is not None and "inclined" not in scene.effects:
        raise ValueError("--geo-threshold applies to the inclined effect: add --effects inclined")
    return scene


def _error(msg, code):
    print(f"halfspace-calib: error: {msg}", file=sys.stderr)
    return code


def _temp_out(out):
    """A fresh temporary folder beside ``out``; ``ValueError`` if ``out`` cannot be written."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {out} exists and is not a folder")
    if out.is_dir() and any(out.iterdir()):
        if not any((out / m).is_file() for m in _OUTPUT_MARKERS):
            raise ValueError(
                f"--out {out} is a non-empty folder that holds no calibration output "
                "(params.json); a run replaces its whole output folder, so give a new or "
                "an earlier output folder"
            )
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        return Path(tempfile.mkdtemp(prefix=f".{out.name}.tmp-", dir=out.parent))
    except OSError as exc:
        raise ValueError(f"--out {out} is not writable ({exc.strerror or exc})") from None


def _move_into_place(tmp, out):
    """Replace ``out`` by ``tmp`` (the whole set): rename the old one aside, then delete it."""
    out = Path(out)
    old = None
    if out.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old-", dir=out.parent))
        os.replace(out, old / "set")
    os.replace(tmp, out)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def main(argv=None):
    """Entry point of ``halfspace-calib``; returns the exit code (0, 1 or 2)."""
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as exc:  # argparse: 2 for a bad option, 0 for --help
        return exc.code if isinstance(exc.code, int) else 2
    t0 = time.perf_counter()
    hfit = None
    try:
        scene = scene_from_args(args)
        spec = sample_spec(args, scene)
        if spec.multi:
            if args.after_contact is not None:
                raise ValueError(
                    "--after-contact fits H on one workpiece/tool pair; with several samples "
                    "fit H first on one pair and give it as --H"
                )
            return _main_samples(args, scene, spec, t0)
        surfaces = load_scene_surfaces(scene)  # every file check before any sweep
        data = _after_contact(args, scene)
        tmp = _temp_out(args.out)
    except FileNotFoundError as exc:
        return _error(str(exc) if "not found" in str(exc) else f"file not found: {exc.filename}", 2)
    except (ValueError, ImportError, OSError) as exc:
        return _error(str(exc), 2)
    try:
        _print_input(scene, surfaces, derived=scene.grid is None)
        if data is not None:
            try:
                hfit, scene = _fit_hardness(args, scene, surfaces, data)
            except ValueError as exc:
                return _error(str(exc), 2)
        cal = calibrate(scene, progress=not args.quiet, surfaces=surfaces)
        write_outputs(cal, tmp)
        if hfit is not None:
            write_hardness_fit(hfit, tmp)
        _move_into_place(tmp, args.out)
    except (RuntimeError, MemoryError) as exc:
        return _error(f"the run failed: {exc or type(exc).__name__}", 1)
    except OSError as exc:  # writing the outputs (disk full, permissions changed meanwhile)
        return _error(f"the outputs could not be written, {args.out} is unchanged: {exc}", 1)
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
    out = Path(args.out)
    P = cal.params
    s = cal.summary()
    print(f"calibrated in {time.perf_counter() - t0:.1f} s -> {out / 'params.json'}")
    print(f"  Eq. 24: C1 = {P.C1:.4g}, n1 = {P.n1:.4g}  (R^2 = {s['first_loading_r2']:.5f})")
    print(
        f"  Eq. 25: C2 = {P.C2:.4g}, n2 = {P.n2:.4g}  (R^2 = {s['reload_r2']:.5f}, "
        f"largest jump at p_hist {100 * s['max_jump_relative']:.2f} % of tau)"
    )
    print(f"  Coulomb slope mu_eff = {P.mu_eff:.4f}, cap m k = {P.tau_max / 1e6:.1f} MPa")
    print(
        f"  reloads: largest local pressure {s['max_reload_pressure_over_H']:.3f} H, "
        f"plastic fraction {s['max_reload_plastic_fraction']:.4f}"
    )
    _print_effects(cal, out)
    _print_resolution(cal.resolution)
    problems = cal.problems()
    if problems:
        print("  RUN FAILED (exit code 1):")
        for p in problems:
            print(f"    - {p}")
        return 1
    return 0


def _main_samples(args, scene, spec, t0):
    """A calibration from several samples (docs/uncertainty.md); returns the exit code."""
    from .output.uncertainty import write_sample_outputs
    from .pipeline.samples import calibrate_samples, load_samples

    try:
        samples = load_samples(scene, spec)  # every file and sample check before any sweep
        tmp = _temp_out(args.out)
    except FileNotFoundError as exc:
        return _error(f"file not found: {exc.filename or exc}", 2)
    except (ValueError, ImportError, OSError) as exc:
        return _error(str(exc), 2)
    try:
        print(
            f"  {len(samples)} samples ({spec.patches} patch(es) per pair), solver grid "
            f"{samples[0].surfaces.grid} x {samples[0].surfaces.grid}, element "
            f"{samples[0].surfaces.workpiece.dx * 1e6:.4g} um, non-periodic"
        )
        mc = calibrate_samples(scene, spec, samples=samples, progress=not args.quiet)
        write_sample_outputs(mc, tmp)
        _move_into_place(tmp, args.out)
    except (RuntimeError, MemoryError) as exc:
        return _error(f"the run failed: {exc or type(exc).__name__}", 1)
    except OSError as exc:
        return _error(f"the outputs could not be written, {args.out} is unchanged: {exc}", 1)
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
    u = mc.uncertainty
    print(
        f"calibrated {len(mc.calibrations)} of {len(samples)} samples in "
        f"{time.perf_counter() - t0:.1f} s -> {Path(args.out) / 'params.json'}"
    )
    print(f"  pooled law and {100 * u.level:g} % bootstrap band ({u.n_bootstrap} resamples):")
    for k, v in u.parameters.items():
        print(f"    {k} = {v.central:.4g}  [{v.lower:.4g}, {v.upper:.4g}]")
    b = u.band("tau_first")
    for p in (100e6, 300e6, 600e6):
        if b.p[0] <= p <= b.p[-1]:
            c, lo, hi = b.at(p)
            print(f"    tau({p / 1e6:g} MPa) = {c / 1e6:.3f} MPa  [{lo / 1e6:.3f}, {hi / 1e6:.3f}]")
    problems = mc.problems()
    if problems:
        print("  RUN FAILED (exit code 1):")
        for p in problems:
            print(f"    - {p}")
        return 1
    return 0


def _after_contact(args, scene):
    """The measured after-contact roughness of ``--after-contact`` (``None`` without it)."""
    if args.after_contact is None:
        return None
    if args.H is not None or (args.scene and _scene_gives(args, "H")):
        raise ValueError(
            "H is given (--H or the scene file) and --after-contact fits it: give one of them"
        )
    return read_after_contact(args.after_contact)


def _fit_hardness(args, scene, surfaces, data):
    """Fit H (Sec. 3.1) on the scene's solver surfaces; the scene calibrated with it."""
    t0 = time.perf_counter()
    fit = fit_hardness(surfaces.workpiece, surfaces.tool, scene.materials, scene.solver, data)
    print(
        f"  H fitted to the after-contact roughness in {time.perf_counter() - t0:.1f} s "
        f"({fit.evaluations} trial H): {fit.message}"
    )
    print("  " + hardness_table(fit).replace("\n", "\n  ").rstrip())
    if not fit.converged:
        raise RuntimeError(f"the fit of H failed: {fit.message}")
    over = {"H": fit.H, "sigma_y": args.sigma_y, "H_source": fit.data.source}
    if args.sigma_y is None and args.scene and _scene_gives(args, "sigma_y"):
        over["sigma_y"] = scene.sigma_y  # the scene file's own yield stress; else H / 2.8
    return fit, dataclasses.replace(scene, **over)


def _scene_gives(args, key):
    """True if the scene file sets ``key`` itself."""
    import tomllib

    data = tomllib.loads(Path(args.scene).read_text(encoding="utf-8"))
    return key in data.get("scene", data)


def _print_input(scene, surfaces, derived=False):
    """What was read and done to each file, the grid and the periodicity."""
    for f in surfaces.files:
        print(
            f"  {f.role}: {f.path} [{f.format}], {f.native_shape[0]} x {f.native_shape[1]} points, "
            f"{f.native_size[0] * 1e6:.4g} x {f.native_size[1] * 1e6:.4g} um, heights in "
            f"{f.unit} ({f.unit_source}), undefined {f.undefined_points} "
            f"({100 * f.undefined_fraction:.2f} %), Rq {f.rq_scan * 1e9:.4g} nm (levelled scan), "
            f"{f.rq_patch * 1e9:.4g} nm on the {f.crop_size * 1e6:.4g} um patch at the grid's "
            "elements"
        )
        for step in f.steps:
            print(f"    - {step}")
    if surfaces.files:
        lam = surfaces.lambda_s
        print(
            "  short-wavelength cut-off "
            + (
                f"lambda_s = {lam * 1e6:.4g} um ({surfaces.lambda_s_source}), "
                f"{lam / surfaces.workpiece.dx:.3g} elements per lambda_s"
                if lam
                else "none (lambda_s = 0: the scan's pixel and the grid set it)"
            )
            + (
                f"; L-filter lambda_c = {surfaces.lambda_c * 1e6:.4g} um"
                if surfaces.lambda_c
                else ""
            )
        )
    for note in surfaces.notes:
        print(f"halfspace-calib: warning: {note}", file=sys.stderr)
    w = surfaces.workpiece
    kind = "periodic (FFT)" if scene.periodic else "non-periodic (DC-FFT)"
    print(
        f"  solver grid {surfaces.grid} x {surfaces.grid}"
        + (" (default rule for files)" if derived else "")
        + f", element {w.dx * 1e6:.4g} um, {kind}"
        + (", measured files default to non-periodic" if scene.from_files else "")
    )


def _print_resolution(rc):
    if rc is None:
        return
    if rc.skipped:
        print(f"  resolution check skipped: {rc.skipped}")
        return
    print(
        f"  resolution check (grid {rc.grid} against {rc.half_grid}, {rc.seconds:.1f} s): "
        + ", ".join(
            f"{k} {a:.4g} -> {b:.4g} ({100 * d:.1f} %)" for k, (a, b, d) in rc.params.items()
        )
        + f"; alpha up to {100 * rc.alpha_change:.1f} %"
    )
    if rc.warning:
        print(f"  WARNING: {rc.warning}")


def _print_effects(cal, out):
    """One block per modelled effect besides the normal sweeps (through the effects registry)."""
    print(f"  effects modelled: {', '.join(cal.scene.effects)}")
    cal.print_effects(out)


if __name__ == "__main__":
    sys.exit(main())
