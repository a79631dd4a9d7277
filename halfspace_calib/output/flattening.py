"""Files of the flattening block (``--flattening``, docs/flattening.md).

``flattening.csv``, ``flattening.png`` and its section of ``report.html``, from the
calibration's record.
"""

from __future__ import annotations

import html
import math
from pathlib import Path

import numpy as np

from sbmf_cli.htmlpage import figure, number_cell

from ._files import write_csv

__all__ = ["FLATTENING_PNG", "write_flattening", "flattening_section"]

FLATTENING_PNG = "flattening.png"
#: pressures (in H) of the written curves
CURVE_P = (0.05, 0.1, 0.3, 0.6)
#: the most measured points the plot marks (every k-th row of a larger sheet)
MAX_MARKERS = 2000
#: the most measured pressures the plot draws the fit at (spread over their range beyond)
MAX_FIT_LINES = 8


def write_flattening(cal, out):
    """``flattening.csv`` (p_Pa, strain, alpha) and ``flattening.png`` of the calibrated block."""
    from frictionlaw import flattening_curve

    P, rec = cal.params, cal.flattening
    out = Path(out)
    eps = np.unique(np.r_[0.0, np.geomspace(1e-4, 0.6, 80)])
    curves = {f: flattening_curve(f * P.H, eps, P) for f in CURVE_P}
    write_csv(
        out / "flattening.csv",
        ["p_Pa", "strain", "alpha"],
        [[f * P.H, e, a] for f, al in curves.items() for e, a in zip(eps, al, strict=True)],
    )
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6, 4.2))
    ax = fig.subplots()
    for i, (f, al) in enumerate(curves.items()):
        ax.plot(eps, al, "-", color=f"C{i}", label=f"p = {f:g} H = {f * P.H / 1e6:.0f} MPa")
    fit = rec.get("fit")
    if fit:
        _plot_measurement(ax, P, fit, getattr(cal, "flattening_data", None))
    f = P.flattening
    ax.set(
        xlabel="bulk plastic strain",
        ylabel="contact fraction alpha",
        ylim=(0, 1.02),
        title=f"Flattening: tan(theta) = {f.slope:.3g}, beta = {f.beta:.3g}",
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / FLATTENING_PNG, dpi=120)


def _plot_measurement(ax, P, fit, data):
    """The measured points beta was fitted to and the fit at their pressures.

    The points from the run's measurement (``data``) or, for a record alone, its rows where it
    kept them; at most :data:`MAX_MARKERS` (every k-th row beyond, said in the legend). The
    fit's curves at each measured pressure while there are at most :data:`MAX_FIT_LINES`, else
    at that many of them spread over their range; by the fit's own model (one curve per
    pressure: :mod:`frictionlaw.flattening_curves`).
    """
    from frictionlaw import flattening_curve
    from frictionlaw.flattening import LIMIT_MODEL
    from frictionlaw.flattening_curves import FlatteningCurves, FlatteningPaths
    from frictionlaw.flow_curve import flow_curve_from_dict

    if data is not None:
        strain, alpha, p = data.strain, data.alpha, data.p
    elif "strain" in fit:
        strain, alpha, p = (np.asarray(fit[k], dtype=float) for k in ("strain", "alpha", "p_Pa"))
    else:  # a record without its rows: the curves over its strain range only
        strain = alpha = None
        p = np.asarray(fit.get("pressures_Pa") or fit["data"]["p_Pa"], dtype=float)
    if strain is not None:
        step = max(1, math.ceil(strain.size / MAX_MARKERS))
        label = "measured (beta fitted to it)" + (
            f", every {step}th of {strain.size} rows" if step > 1 else ""
        )
        ax.plot(strain[::step], alpha[::step], "ko", ms=4 if step == 1 else 1.5, label=label)
        top = float(strain.max())
    else:
        top = float(fit["data"]["strain"][1])
    levels = measured = np.unique(p)
    if levels.size > MAX_FIT_LINES:
        levels = np.unique(np.quantile(levels, np.linspace(0, 1, MAX_FIT_LINES), method="nearest"))
    line = np.linspace(0.0, top, 41)
    pp, ee = np.repeat(levels, line.size), np.tile(line, levels.size)
    fc = fit.get("flow_curve_record")
    if P.flattening.model == LIMIT_MODEL:  # the two-state law's own curves
        curves = flattening_curve(
            pp, ee, P, flow_curve=None if fc is None else flow_curve_from_dict(fc)
        )
    elif fc is None:
        curves = FlatteningCurves(pp, P).alpha(ee)
    else:
        curves = FlatteningPaths(pp, ee, P, flow_curve_from_dict(fc)).alpha()
    shown = "" if levels.size == measured.size else f" ({levels.size} of {measured.size})"
    for k, a in enumerate(curves.reshape(levels.size, line.size)):
        ax.plot(
            line,
            a,
            "k--",
            lw=0.8,
            label=None
            if k
            else f"the fit at the measured pressures{shown}"
            + ("" if fc is None else " (the sheet's flow curve)"),
        )


def flattening_section(s, out):
    """The ``report.html`` section of ``summary["flattening"]`` (empty without the block)."""
    r = s.get("flattening")
    if not r:
        return ""
    rows = [
        ("slope", "tan(theta): " + r["slope_source"]),
        ("slope_x", "RMS slope of the x profiles"),
        ("slope_y", "RMS slope of the y profiles"),
        ("slope_half_grid", "the same at half the grid (2 x 2 averages): its resolution"),
        ("beta", "rate factor: " + r["beta_source"]),
        ("zero_strain_hardness.law_small_p_Pa", "zero-strain asperity hardness H / C1 [Pa]"),
        ("half_spacing.from_crossings_m.0", "half-spacing from x crossings [m] (not used)"),
        ("half_spacing.from_crossings_m.1", "half-spacing from y crossings [m] (not used)"),
        ("half_spacing.from_patches_m", "half-spacing from contact patches [m] (not used)"),
        ("full_contact.strain", "strain to full contact at 0.3 H"),
    ]
    body = [
        f"<h2>Flattening under bulk strain</h2><p>model: {html.escape(str(r.get('model')))}</p>",
        "<table><tr><th>quantity</th><th>value</th>",
    ]
    body.append("<th>derived from</th></tr>")
    for key, what in rows:
        v = r
        for part in key.split("."):
            if isinstance(v, list):
                v = v[int(part)]
            else:
                v = v.get(part) if isinstance(v, dict) else None
        body.append(
            f"<tr><td class='t'>{html.escape(key)}</td>{number_cell(v, 'flattening.' + key)}"
            f"<td class='t'>{html.escape(what)}</td></tr>"
        )
    body.append("</table>")
    fit = r.get("fit")
    if fit:
        body.append(
            f"<p>beta fitted to {fit['points']} points of {html.escape(fit['file'])}: band "
            f"[{fit['band'][0]:.4g}, {fit['band'][1]:.4g}] at {100 * fit['level']:g} %, "
            f"|d alpha| rms {fit['rms']:.4f}, max {fit['max_abs']:.4f}; "
            + (
                "as a perfectly plastic sheet (beta absorbs its hardening: run the host without "
                "the hardening modulus)"
                if fit.get("flow_curve") is None
                else f"with the sheet's flow curve ({html.escape(fit['flow_curve'])}: pass the "
                "flow stress and hardening modulus in the host)"
            )
            + "</p>"
        )
        d = fit.get("data")
        if d:  # record version 2: the file's digest and what params.json keeps of it
            body.append(
                f"<p>The measurement: {d['rows']} rows at {d['pressures']} pressures "
                f"({d['p_Pa'][0] / 1e6:.4g}-{d['p_Pa'][1] / 1e6:.4g} MPa), strains "
                f"{d['strain'][0]:.4g}-{d['strain'][1]:.4g}, sha256 "
                f"<code>{html.escape(str(d['sha256']))}</code>; "
                + (
                    "its rows are in params.json (provenance.flattening.fit)"
                    if d["rows_kept"]
                    else f"params.json keeps its digest and residual summary, not its rows "
                    f"(kept up to {d['rows_kept_up_to']})"
                )
                + "</p>"
            )
    if r.get("problem"):
        body.append(f"<p class='bad'>{html.escape(r['problem'])}</p>")
    png = Path(out) / FLATTENING_PNG
    if png.is_file():
        body.append(figure(png, "Contact fraction against bulk strain at constant pressure"))
    return "".join(body)
