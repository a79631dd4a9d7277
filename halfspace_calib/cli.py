"""``halfspace-calib``: calibrate the friction law; with no arguments, the built-in default scene."""

from __future__ import annotations

import argparse
import sys
import time

from .calibrate import Scene, calibrate, load_scene
from .report import write_outputs


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
    g.add_argument("--workpiece", help="workpiece topography file (default: synthetic DC04 EDT)")
    g.add_argument("--tool", help="tool topography file (default: synthetic hardened tool)")
    g.add_argument("--unit", help="height unit of plain files: m, mm, um, nm (default um)")
    g.add_argument("--workpiece-unit", help="height unit of the workpiece file (default --unit)")
    g.add_argument("--tool-unit", help="height unit of the tool file (default --unit)")
    g.add_argument("--size", type=float, help="physical edge length of plain height matrices (m)")
    g.add_argument(
        "--rough-tool",
        action="store_true",
        default=None,
        help="synthetic rough tool (Ra 0.240 um) instead of the smooth one",
    )
    g.add_argument("--grid", type=int, help="solver grid: N x N elements (default 128)")
    g = ap.add_argument_group("materials (Pa)")
    g.add_argument("--E-workpiece", type=float)
    g.add_argument("--nu-workpiece", type=float)
    g.add_argument("--E-tool", type=float)
    g.add_argument("--nu-tool", type=float)
    g.add_argument(
        "--H", type=float, help="hardness (default 800e6; 2.8 sigma_y if only --sigma-y)"
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
    g.add_argument("--periodic", dest="periodic", action="store_true", default=None)
    g.add_argument("--no-periodic", dest="periodic", action="store_false")
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
        "--workers", type=int, help="local processes (1: in this process, 0: one per CPU)"
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
    ap.add_argument("--quiet", action="store_true", help="no progress bar")
    return ap


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
            "volume_conservation",
            "reload_surface",
            "continuous_reload",
            "workers",
            "scheduler",
            "effects",
            "geo_threshold",
        )
    }
    if args.sliding:
        from .effects import check_effects

        if over["effects"] is None:  # add to the scene file's effects, or to the default
            base = load_scene(args.scene).effects if args.scene else ("normal",)
        else:
            base = check_effects(over["effects"])
        over["effects"] = tuple(base) + ("sliding",)
    if over["H"] is None and over["sigma_y"] is not None and not args.scene:
        over["H"] = 2.8 * over["sigma_y"]
    if args.scene:
        return load_scene(args.scene, **over)
    return Scene(**{k: v for k, v in over.items() if v is not None})


def main(argv=None):
    """Entry point of ``halfspace-calib``."""
    args = build_parser().parse_args(argv)
    try:
        scene = scene_from_args(args)
    except ValueError as exc:
        print(f"halfspace-calib: error: {exc}", file=sys.stderr)
        return 2
    t0 = time.perf_counter()
    cal = calibrate(scene, progress=not args.quiet)
    out = write_outputs(cal, args.out)
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
    if cal.sweeps.failed:
        print(
            f"  WARNING: {len(cal.sweeps.failed)} load levels failed: "
            + "; ".join(f"{f['p_hist']:g} Pa" for f in cal.sweeps.failed)
        )
    for nc in s["not_converged"]:
        print(
            f"  WARNING: not converged, left out of the fit: p_hist {nc['p_hist']:g} Pa, "
            f"p_mean {nc['p_mean']:g} Pa: {nc['message']}"
        )
    return 0


def _print_effects(cal, out):
    """One block per modelled effect besides the normal sweeps."""
    eff = cal.effects
    print(f"  effects modelled: {', '.join(cal.scene.effects)}")
    for name in ("tangential", "inclined", "sliding"):
        e = eff.get(name)
        if e is None:
            continue
        if "skipped" in e:
            label = {
                "tangential": "tangential (pre-sliding)",
                "inclined": "inclined patches",
                "sliding": "sliding (Sec. 3.3)",
            }[name]
            print(f"  {label} skipped: {e['skipped']}")
            continue
        getattr(sys.modules[__name__], f"_print_{name}")(e, out)


def _print_tangential(e, out):
    s = e["summary"]
    print(f"  tangential (pre-sliding, {e['seconds']:.1f} s) -> {out / 'tangential'}")
    for r in s["rows"]:
        print(
            f"    {r['p_mean'] / 1e6:5.0f} MPa: k_t0 = {r['k_t0']:.3e}, k_eq = {r['k_eq']:.3e}, "
            f"k_sec = {r['k_sec']:.3e} Pa/m, full sliding at {r['delta_full'] * 1e9:.1f} nm"
            + ("" if r["converged"] else "  [NOT converged]")
        )
    for err in s["errors"]:
        print(f"    WARNING: tangential at {err['p_mean']:g} Pa failed: {err['error']}")
    print(f"    {s['recommendation']}")


def _print_inclined(e, out):
    d = e["decision"]
    print(f"  inclined patches (Eqs. 19-23, {e['seconds']:.1f} s) -> {out / 'geometric'}")
    print(f"    {d['reason']}")


def _print_sliding(e, out):
    study = e["study"]
    s = study.summary()
    print(f"  sliding (Sec. 3.3, {e['seconds']:.1f} s) -> {out / 'sliding' / 'sliding.csv'}")
    for row in s["rows"]:
        print(
            f"    {row['p_mean'] / 1e6:5.0f} MPa: W_def / W_adh mean {row['ratio_mean']:.4f}, "
            f"max {row['ratio_max']:.4f} (positions >= 1; paper: < 0.008)"
            + ("" if row["converged"] else "  [NOT all positions converged]")
        )
    for p, err in study.errors.items():
        print(f"    WARNING: sliding at {p:g} Pa failed: {err.splitlines()[0]}")


if __name__ == "__main__":
    sys.exit(main())
