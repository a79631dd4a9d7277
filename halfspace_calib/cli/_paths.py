"""The two calibration paths of ``halfspace-calib`` besides the plain one.

Several samples with a band (``--workpiece A B C``, ``--patches N``; docs/uncertainty.md) and the
hardness fitted to the after-contact roughness (``--after-contact``, the paper's Sec. 3.1).
"""

from __future__ import annotations

import dataclasses
import json
import re
import time
from pathlib import Path

from sbmf_cli import OutputFolder, process_seconds

from ..output.hardness import hardness_table
from ..pipeline.sweep.hardness import (
    AfterContactScans,
    fit_hardness,
    read_after_contact,
    roughness_of_scans,
)

#: files that mark a folder as a calibration output (a rerun may replace it)


def run_inputs(args, scene=None):
    """The files a calibration reads (its output folder may not hold any of them)."""
    files = [args.scene, args.after_contact, getattr(args, "flattening_data", None)]
    curve = getattr(args, "flow_curve", None)
    if isinstance(curve, str) and not curve.strip().lower().startswith("swift:"):
        files.append(curve)
    files += [*(args.workpiece or ()), *(args.tool or ())]
    if scene is not None:
        files += [scene.workpiece, scene.tool]
    return tuple(f for f in files if isinstance(f, str | Path))


def sample_spec(args, scene):
    """The :class:`SampleSpec` of the options and the scene file's ``[samples]`` table."""
    from ..pipeline.band.samples import SampleSpec, read_samples_table

    kw = read_samples_table(args.scene) if args.scene else {}
    wps, tls = args.workpiece or [], args.tool or []
    if len(wps) > 1 or len(tls) > 1:
        kw["workpieces"], kw["tools"] = tuple(wps), tuple(tls)
    else:  # one file on the command line replaces the scene file's list of that role
        if wps:
            kw.pop("workpieces", None)
        if tls:
            kw.pop("tools", None)
    for key, opt in (
        ("patches", "patches"),
        ("level", "band_level"),
        ("n_bootstrap", "bootstrap"),
        ("band_method", "band_method"),
    ):
        if getattr(args, opt) is not None:
            kw[key] = getattr(args, opt)
    spec = SampleSpec(**kw)
    if spec.multi and args.resolution_check:
        raise ValueError(
            "--resolution-check does not run per sample in a multi-sample calibration: "
            "calibrate one sample alone for it"
        )
    if spec.patches > 1 and (args.periodic or args.boundary == "periodic"):
        raise ValueError(
            "--boundary periodic: a patch is not one period of a surface; patches are solved "
            "with --boundary mirror (default) or isolated"
        )
    if not spec.multi and any(
        getattr(args, o) is not None for o in ("band_level", "bootstrap", "band_method")
    ):
        raise ValueError(
            "--band-level, --bootstrap and --band-method apply to several samples: give several "
            "--workpiece files or --patches N"
        )
    return spec


def main_samples(con, args, scene, spec):
    """A calibration from several samples (docs/uncertainty.md); returns the exit code."""
    from ..output.uncertainty import write_sample_outputs
    from ..pipeline.band.samples import calibrate_samples, load_samples

    try:
        samples = load_samples(scene, spec)  # every file and sample check before any sweep
        folder = OutputFolder(
            args.out,
            command="halfspace-calib",
            what="calibration output",
            inputs=run_inputs(args, scene),
        )
    except FileNotFoundError as exc:
        return con.error(f"file not found: {exc.filename or exc}", 2)
    except (ValueError, ImportError, OSError) as exc:
        return con.error(exc, 2)
    with folder:
        try:
            con.result(
                f"  {len(samples)} samples ({spec.patches} patch(es) per pair), solver grid "
                f"{samples[0].surfaces.grid} x {samples[0].surfaces.grid}, element "
                f"{samples[0].surfaces.workpiece.dx * 1e6:.4g} um, boundary "
                f"{samples[0].scene.boundary}"
            )
            progress = not (args.quiet or args.no_progress)
            mc = calibrate_samples(scene, spec, samples=samples, progress=progress)
            write_sample_outputs(mc, folder.tmp, clock=process_seconds)
            run_seconds = json.loads((folder.tmp / "summary.json").read_text())["command_seconds"]
            mark_failed(folder.tmp, mc.problems())
            folder.commit()
        except (RuntimeError, MemoryError, ValueError) as exc:  # input was checked: the run failed
            return con.error(f"the run failed: {con.text(exc) or type(exc).__name__}", 1)
        except OSError as exc:
            return con.error(f"the outputs could not be written, {args.out} is unchanged: {exc}", 1)
    u = mc.uncertainty
    written = FAILED_PARAMS + " (marked failed)" if mc.problems() else "params.json"
    con.result(
        f"calibrated {len(mc.calibrations)} of {len(samples)} samples in {run_seconds:.1f} s"
        f"{' (FAILED)' if mc.problems() else ''} -> {Path(args.out) / written}"
    )
    con.result(
        f"  pooled law and {100 * u.level:g} % bootstrap band ({u.n_bootstrap} resamples, "
        f"{mc.spec.band_method} band):"
    )
    for k, v in u.parameters.items():
        con.result(f"    {k} = {v.central:.4g}  [{v.lower:.4g}, {v.upper:.4g}]")
    b = u.band("tau_first")
    for p in (100e6, 300e6, 600e6):
        if b.p[0] <= p <= b.p[-1]:
            c, lo, hi = b.at(p)
            con.result(
                f"    tau({p / 1e6:g} MPa) = {c / 1e6:.3f} MPa  [{lo / 1e6:.3f}, {hi / 1e6:.3f}]"
            )
    return exit_code(con, mc.problems())


def after_contact(args, scene):
    """The measured after-contact roughness of ``--after-contact`` (``None`` without it)."""
    if args.after_contact is None:
        return None
    if args.H is not None or (args.scene and _scene_gives(args, "H")):
        raise ValueError(
            "H is given (--H or the scene file) and --after-contact fits it: give one of them"
        )
    return read_after_contact(args.after_contact)


def fit_h(con, args, scene, surfaces, data):
    """Fit H (Sec. 3.1) on the scene's solver surfaces; the scene calibrated with it."""
    t0 = time.perf_counter()
    if isinstance(data, AfterContactScans):
        data, records = roughness_of_scans(data, scene, surfaces)
        con.result(
            f"  after-contact scans ({len(records)}), prepared as the workpiece (grid "
            f"{surfaces.grid}, lambda_s {surfaces.lambda_s or 0:.3g} m):"
        )
        for p, ra, rq, rec in zip(data.p_mean, data.Ra, data.Rq, records, strict=True):
            con.result(
                f"    {p / 1e6:8.1f} MPa  Ra {ra * 1e6:.4f} um  Rq {rq * 1e6:.4f} um  {rec['path']}"
            )
    fit = fit_hardness(surfaces.workpiece, surfaces.tool, scene.materials, scene.solver, data)
    con.result(
        f"  H fitted to the after-contact roughness in {time.perf_counter() - t0:.1f} s "
        f"({fit.evaluations} trial H): {fit.message}"
    )
    con.result("  " + hardness_table(fit).replace("\n", "\n  ").rstrip())
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


FAILED_PARAMS = "params.failed.json"


def mark_failed(folder, problems):
    """A run that fails keeps its diagnosis but no ``params.json`` a consumer would read.

    The parameter file is written as ``params.failed.json`` with ``provenance.run`` = ``{"status":
    "failed", "problems": [...]}``; ``FrictionParams.from_json`` (and so ``fe-demo`` and
    ``frictionlaw-export``) refuse it unless told to accept a failed fit.
    """
    src = Path(folder) / "params.json"
    if not problems or not src.is_file():
        return
    doc = json.loads(src.read_text(encoding="utf-8"))
    doc.setdefault("provenance", {})["run"] = {
        "status": "failed",
        "problems": [str(p) for p in problems],
    }
    (Path(folder) / FAILED_PARAMS).write_text(json.dumps(doc, indent=2) + "\n", encoding="utf-8")
    src.unlink()


#: a branch that misses the model by this much in alpha has most likely been given a wrong input
#: (a size or unit typed wrong) rather than fitted poorly: the failure message names the likely
#: causes
COLLAPSED = 0.15


def failure_hint(problems):
    """Likely causes of a collapsed fit (a branch missing by >= 0.15 in alpha), for RUN FAILED."""
    text = " ".join(map(str, problems))
    miss = [float(v) for v in re.findall(r"\|d alpha\| = ([0-9.eE+-]+)", text)]
    if not miss or max(miss) < COLLAPSED:  # only a collapsed fit, not one that is merely poor
        return None
    return (
        "likely causes of a collapsed fit: a lateral --size in the wrong unit for the heights "
        "(mm typed as m makes the surface nearly flat), a height --unit off by 1000, or "
        "--pressures outside the contact's range (most likely MPa typed as Pa)"
    )


def exit_code(con, problems):
    """0, or 1 after the run's problems on stderr (``RUN FAILED``)."""
    if problems:
        con.warn("halfspace-calib: RUN FAILED (exit code 1):")
        for p in problems:
            con.warn(f"    - {con.text(p)}")
        hint = failure_hint(problems)
        if hint:
            con.warn(f"halfspace-calib: {hint}")
        con.warn(
            f"halfspace-calib: the parameters are kept as {FAILED_PARAMS} (marked failed), "
            "not as params.json"
        )
        return 1
    return 0
