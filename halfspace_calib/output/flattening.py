"""Files of the flattening block (``--flattening``, docs/flattening.md).

``flattening.csv``, ``flattening.png`` and its section of ``report.html``, from the
calibration's record.
"""

from __future__ import annotations

import html
from pathlib import Path

import numpy as np

from sbmf_cli.htmlpage import figure, number_cell

from ._files import write_csv

__all__ = ["FLATTENING_PNG", "write_flattening", "flattening_section"]

FLATTENING_PNG = "flattening.png"
#: pressures (in H) of the written curves
CURVE_P = (0.05, 0.1, 0.3, 0.6)


def write_flattening(cal, out):
    """``flattening.csv`` (p_Pa, strain, alpha) and ``flattening.png`` of the calibrated block."""
    from frictionlaw import flattening_curve
    from frictionlaw.flow_curve import flow_curve_from_dict

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
        ax.plot(fit["strain"], fit["alpha"], "ko", ms=4, label="measured (beta fitted to it)")
        fc = fit.get("flow_curve_record")
        fc = None if fc is None else flow_curve_from_dict(fc)
        top = max(fit["strain"])
        line = np.linspace(0.0, top, 41)
        for k, p in enumerate(fit["pressures_Pa"]):
            ax.plot(
                line,
                flattening_curve(p, line, P, flow_curve=fc),
                "k--",
                lw=0.8,
                label=None
                if k
                else "the fit at the measured pressures"
                + ("" if fc is None else " (the sheet's flow curve)"),
            )
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
        ("full_contact.strain", "strain to full contact at 0.3 H (Eq. F4)"),
    ]
    body = ["<h2>Flattening under bulk strain</h2><table><tr><th>quantity</th><th>value</th>"]
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
    if r.get("problem"):
        body.append(f"<p class='bad'>{html.escape(r['problem'])}</p>")
    png = Path(out) / FLATTENING_PNG
    if png.is_file():
        body.append(figure(png, "Contact fraction against bulk strain at constant pressure"))
    return "".join(body)
