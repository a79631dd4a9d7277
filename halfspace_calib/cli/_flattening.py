"""``halfspace-calib --flattening``: the flattening block of a calibration (docs/flattening.md)."""

from __future__ import annotations

from dataclasses import replace

from frictionlaw.flattening import FLATTENING_MODEL, FLATTENING_MODELS, LIMIT_MODEL
from frictionlaw.flattening_limit import LIMIT_SLOPE_RANGE, table_pressures
from frictionlaw.flow_curve import read_flow_curve
from sbmf_cli import existing_file, file_path

from ..pipeline.sweep.flattening import (
    BAND_LEVEL,
    check_data_pressures,
    derive_flattening,
    read_flattening_data,
    rms_slope,
)

__all__ = [
    "add_flattening_options",
    "flattening_input",
    "check_flattening_slope",
    "with_flattening",
    "flattening_lines",
]


def add_flattening_options(ap):
    """The options of the flattening block."""
    g = ap.add_argument_group("flattening under bulk strain (docs/flattening.md)")
    g.add_argument(
        "--flattening",
        action="store_true",
        help="add the flattening block to params.json: the asperities' slope from the workpiece "
        "surface, the zero-strain hardness from the computed first loading, the rate factor "
        "beta = 1; nothing is fitted to friction (default: off)",
    )
    g.add_argument(
        "--flattening-model",
        choices=FLATTENING_MODELS,
        default=None,
        help="the block's model: layer-yield, one state per node (Eqs. F1-F6), or "
        "limit-analysis, two states per node (contact fraction and flank slope) at the "
        "tabulated rigid-plastic optimum's rates, which follows the FE asperity truth closer "
        "at low pressure (docs/flattening.md; its RMS slope must lie in [0.01, 0.2]; the "
        "exported routines carry layer-yield only); implies --flattening (default: "
        "layer-yield)",
    )
    g.add_argument(
        "--flattening-data",
        metavar="CSV",
        type=file_path,
        help="measured contact fraction against bulk strain, columns strain, alpha, p_Pa (or "
        "p_MPa), separated by commas, semicolons or tabs: fits "
        f"beta with its {100 * BAND_LEVEL:g} %% band (implies --flattening; default: none)",
    )
    g.add_argument(
        "--flow-curve",
        metavar="SPEC",
        type=file_path,
        help="the measured sheet's flow curve, for the fit of --flattening-data: swift:K,eps0,n "
        "(K in Pa, e.g. swift:530e6,0.006,0.24) or a CSV with a strain and a flow stress column "
        "with its unit (strain and sigma_y_MPa, phi and kf [MPa], ...), not extrapolated; each "
        "point is then integrated at the flow stress and hardening modulus of its strain, as a "
        "host passing both runs the law (default: none: a perfectly plastic sheet at the "
        "calibration's sigma_y, beta absorbing its hardening)",
    )


def flattening_input(args, spec, scene):
    """``(on, data, model)``: whether the block is made, the measured data and the model.

    The data are read and checked now, before any sweep, their pressures against the scene's ``H``.
    """
    model = args.flattening_model or FLATTENING_MODEL
    on = bool(args.flattening) or args.flattening_data is not None or args.flattening_model
    if args.flow_curve is not None and args.flattening_data is None:
        raise ValueError(
            "--flow-curve is the measured sheet's, for the fit of --flattening-data: give the "
            "measurement too (the block itself carries no flow curve: the host passes its own)"
        )
    if not on:
        return False, None, model
    if spec.multi:
        raise ValueError(
            "--flattening derives the block from one workpiece/tool pair; with several samples "
            "calibrate one pair with --flattening"
        )
    data = None if args.flattening_data is None else _read_data(args.flattening_data)
    if data is not None:
        check_data_pressures(data, scene.H)
        if args.flow_curve is not None:
            fc = read_flow_curve(args.flow_curve)
            top = float(data.strain.max())
            if top > fc.strain_max:
                raise ValueError(
                    f"--flow-curve ends at strain {fc.strain_max:g}; {data.path} reaches "
                    f"{top:g}: extend the flow curve (it is not extrapolated)"
                )
            data = replace(data, flow_curve=fc)
    return True, data, model


def check_flattening_slope(flat, surfaces):
    """Refuse the two-state model before any sweep for a workpiece outside its table.

    The workpiece's RMS profile slope on the solver grid (what the block takes) must lie in the
    table's slopes; ``flat`` is :func:`flattening_input`'s triple.
    """
    on, _, model = flat
    if not on or model != LIMIT_MODEL:
        return
    slope = rms_slope(surfaces.workpiece)[0]
    lo, hi = LIMIT_SLOPE_RANGE
    if not lo <= slope <= hi:
        raise ValueError(
            f"--flattening-model {LIMIT_MODEL}: the workpiece's RMS profile slope on the solver "
            f"grid is {slope:.3g}, outside the two-state law's table [{lo:g}, {hi:g}]: use "
            "--flattening-model layer-yield for this surface"
        )


def _read_data(path):
    """``--flattening-data``'s measurement; a path that is no file is named with the option."""
    return read_flattening_data(existing_file("--flattening-data", path, "a CSV file"))


def with_flattening(cal, on, data, model=FLATTENING_MODEL):
    """The calibration with the flattening block in its parameters and its record (or as is)."""
    if not on:
        return cal
    block, record = derive_flattening(cal, data, model)
    if model != FLATTENING_MODEL:
        lo, hi = table_pressures(cal.params)
        cal.notes = (
            *cal.notes,
            f"the flattening model {model} is perfectly plastic: against our FE asperity truth "
            "it misses a hardening sheet (DC04) by up to 0.65 in the contact fraction at "
            "0.05-0.45 H and 0.84 at 0.02 H, where layer-yield with the host's hardening "
            "modulus misses by 0.195 and 0.105; prefer layer-yield for a sheet that hardens "
            "over the process's strains (docs/flattening.md)",
            f"the flattening model {model}'s table covers contact pressures "
            f"{lo / 1e6:.3g}-{hi / 1e6:.3g} MPa at this sigma_y ({cal.params.sigma_y / 1e6:.4g} "
            f"MPa; they scale with the host's flow stress): below {lo / 1e6:.3g} MPa it reads "
            "the rates there, an upper bound of the flattening (its optimum slows at lower "
            "pressure on steep flanks)",
        )
    fit = record.get("fit")
    if fit:
        cal.notes = (*cal.notes, *fit.get("notes", ()))
    if fit and fit["flow_curve"] is not None:
        ratio = fit["flow_curve_sigma_y0_Pa"] / cal.params.sigma_y
        if not 0.8 <= ratio <= 1.25:
            cal.notes = (
                *cal.notes,
                f"the flow curve's initial flow stress {fit['flow_curve_sigma_y0_Pa'] / 1e6:.4g} "
                f"MPa is {ratio:.3g} times the calibration's sigma_y "
                f"{cal.params.sigma_y / 1e6:.4g} MPa: are they the same sheet?",
            )
    prov = dict(cal.params.provenance)
    prov["flattening"] = record
    cal.params = cal.params.replace(flattening=block, provenance=prov)
    cal.flattening = record
    cal.flattening_data = data if fit else None
    return cal


def flattening_lines(cal):
    """The console lines: the block and what each input was derived from."""
    r = cal.flattening
    if not r:
        return []
    f = cal.params.flattening
    hs = r["half_spacing"]
    zs = r["zero_strain_hardness"]
    um = 1e6
    lines = [
        f"  flattening (docs/flattening.md): slope tan(theta) = {f.slope:.4g} ({r['slope_source']}; "
        f"x {r['slope_x']:.4g}, y {r['slope_y']:.4g}; at half the grid {r['slope_half_grid'] or 0:.4g})",
        f"    model {r['model']}",
        f"    zero-strain asperity hardness p / alpha from the computed first loading "
        f"{min(zs['p_over_alpha_Pa']) / 1e6:.4g}-{max(zs['p_over_alpha_Pa']) / 1e6:.4g} MPa "
        f"(the law's H / C1 = {zs['law_small_p_Pa'] / 1e6:.4g} MPa): read through alpha1",
    ]
    if f.beta_band is None:
        lines.append(f"    beta = {f.beta:g} ({r['beta_source']})")
    else:
        fit = r["fit"]
        lines.append(
            f"    beta = {f.beta:.4g} [{f.beta_band[0]:.4g}, {f.beta_band[1]:.4g}] "
            f"({100 * f.band_level:g} %), {r['beta_source']}: |d alpha| rms {fit['rms']:.4f}, "
            f"max {fit['max_abs']:.4f}"
        )
        d = fit["data"]
        lines.append(
            f"    the measurement: {d['rows']} rows at {d['pressures']} pressures, sha256 "
            f"{d['sha256']}; "
            + (
                "its rows kept in params.json"
                if d["rows_kept"]
                else f"params.json keeps its digest and residuals, not its rows (kept up to "
                f"{d['rows_kept_up_to']})"
            )
        )
        if fit["flow_curve"] is None:
            lines.append(
                "    fitted as a perfectly plastic sheet: beta absorbs its hardening; run the "
                "host without the hardening modulus (or fit with --flow-curve)"
            )
        else:
            lines.append(
                f"    fitted with the sheet's flow curve ({fit['flow_curve']}): pass the "
                "bulk's flow stress and hardening modulus in the host"
            )
    cross, patch = hs["from_crossings_m"], hs["from_patches_m"]
    lines.append(
        "    asperity half-spacing (not used by the model): "
        + " / ".join("-" if c is None else f"{c * um:.4g}" for c in cross)
        + " um (x / y) from the profiles' mean-line crossings"
        + (
            f", {patch * um:.4g} um from {hs['patches']} contact patches at "
            f"{hs['patch_pressure_Pa'] / 1e6:.4g} MPa"
            if patch
            else ""
        )
    )
    t = r["table"]
    for key, alphas in t["alpha_at_p_over_H"].items():
        lines.append(
            f"    alpha at {key.replace('H', ' H')}: "
            + ", ".join(f"{a:.3f} (eps {e:g})" for e, a in zip(t["strains"], alphas, strict=True))
        )
    return lines
