"""What ``halfspace-calib`` prints of a calibration: its input, resolution check and effects."""

from __future__ import annotations

from ._paths import FAILED_PARAMS

#: the boundaries in words (the input summary)
_KIND = {
    "periodic": "the patch is one period, FFT",
    "mirror": "the patch's mirror-symmetric extension, cosine transforms; the default for files",
    "isolated": "a finite body, zero-padded DC-FFT",
}


def ran(run_seconds, solve_seconds, out, problems):
    """The first summary line: how long, and which parameter file (only the one written)."""
    took = f"{run_seconds:.1f} s ({solve_seconds:.1f} s of it solving and fitting)"
    if problems:
        return f"calibration FAILED after {took} -> {out / FAILED_PARAMS} (marked failed)"
    return f"calibrated in {took} -> {out / 'params.json'}"


def print_input(con, scene, surfaces, derived=False):
    """What was read and done to each file, the grid and the periodicity."""
    for f in surfaces.files:
        con.result(
            f"  {f.role}: {f.path} [{f.format}], {f.native_shape[0]} x {f.native_shape[1]} points, "
            f"{f.native_size[0] * 1e6:.4g} x {f.native_size[1] * 1e6:.4g} um ({_size_source(f)}), "
            f"RMS slope {f.rms_slope_scan:.3g}, heights in "
            f"{f.unit} ({f.unit_source}), undefined {f.undefined_points} "
            f"({100 * f.undefined_fraction:.2f} %), Rq {f.rq_scan * 1e9:.4g} nm (levelled scan), "
            f"{f.rq_patch * 1e9:.4g} nm on the {f.crop_size * 1e6:.4g} um patch at the grid's "
            "elements"
        )
        for step in f.steps:
            con.result(f"    - {step}")
    if surfaces.files:
        lam = surfaces.lambda_s
        con.result(
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
        con.warn(f"halfspace-calib: warning: {note}")
    w = surfaces.workpiece
    con.result(
        f"  solver grid {surfaces.grid} x {surfaces.grid}"
        + (" (default rule for files)" if derived else "")
        + f", element {w.dx * 1e6:.4g} um, boundary {scene.boundary} ({_KIND[scene.boundary]})"
    )


def print_resolution(con, rc):
    """The resolution check: the law the file runs at both grids, the other forms labelled."""
    if rc is None:
        return
    if rc.skipped:
        con.result(f"  resolution check skipped: {rc.skipped}")
        return

    def moved(d):
        return ", ".join(f"{k} {a:.4g} -> {b:.4g} ({100 * c:.1f} %)" for k, (a, b, c) in d.items())

    con.result(
        f"  resolution check (grid {rc.grid} against {rc.half_grid}, {rc.seconds:.1f} s), the law "
        f"that runs ({rc.forms['first_loading']} + {rc.forms['reload']}): {moved(rc.params)}; "
        + ", ".join(
            f"{k.replace('_', '-')} alpha of the law up to {100 * v:.1f} %"
            for k, v in rc.law_alpha.items()
        )
        + f"; computed alpha up to {100 * rc.alpha_change:.1f} %"
    )
    if rc.beside:
        con.result(f"    beside it, not run (Eq. 24 / Eq. 25 fitted again): {moved(rc.beside)}")
    if rc.warning:
        con.warn(f"halfspace-calib: WARNING: {rc.warning}")


def print_effects(con, cal, out):
    """One block per modelled effect besides the normal sweeps (through the effects registry).

    The registry's ``WARNING`` lines (a failed effect solve) go to stderr, the rest to stdout.
    """
    con.result(f"  effects modelled: {', '.join(cal.scene.effects)}")
    for line in cal.effect_lines(out):
        if line.lstrip().startswith("WARNING"):
            con.warn(f"halfspace-calib: {line.strip()}")
        else:
            con.result(line)


def _size_source(f):
    """Where a file's size came from; for a corrected one, with the size the file carries."""
    if f.size_source != "override":
        return f.size_source
    own = f.file_size
    said = "it has none" if own is None else f"it says {own[0] * 1e6:.4g} x {own[1] * 1e6:.4g} um"
    return f"--{f.role}-size, overriding the file's own: {said}"
