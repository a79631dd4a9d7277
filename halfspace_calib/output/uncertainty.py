"""Files of a calibration from several samples: the pooled set, per-sample table, bands, plots.

Reads a multi-sample calibration duck-typed (``pooled``, ``uncertainty``, ``calibrations``,
``summary()``); never imports :mod:`halfspace_calib.pipeline`.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from frictionlaw import alpha_first

from ._files import pyplot, save_png, write_csv
from .html import write_report
from .report import REPORT_IMAGES, write_outputs

__all__ = ["write_sample_outputs", "write_band_plots", "BAND_IMAGES"]

MPa = 1e6
#: the band plots and their captions in report.html
BAND_IMAGES = [
    ("band_alpha_first.png", "First loading: per-sample curves, pooled law (Eq. 24) and band"),
    ("band_tau_first.png", "Shear tau(p) on first loading with the band"),
    ("band_reload.png", "Reload branches (Eq. 25) at every p_hist with their bands"),
]


def _fill(ax, band, scale, color, label=None):
    p = np.array(band.p) / MPa
    ax.fill_between(
        p,
        np.array(band.lower) / scale,
        np.array(band.upper) / scale,
        color=color,
        alpha=0.3,
        lw=0,
        label=label,
    )
    ax.plot(p, np.array(band.central) / scale, "-", color=color, lw=1.5)


def write_band_plots(mc, out):
    """The band plots of :data:`BAND_IMAGES`; returns ``{file: Figure}``."""
    plt = pyplot()
    u = mc.uncertainty
    lv = f"{100 * u.level:g} %"
    figs = {}
    cals = mc.calibrations
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for c in cals.values():
        p, a = c.sweeps.loading
        ax.plot(p / MPa, a, "-", color="0.6", lw=0.7)
    _fill(ax, u.band("alpha_first"), 1.0, "C0", f"{lv} band of the pooled law")
    ax.plot([], [], "-", color="0.6", lw=0.7, label=f"{len(cals)} samples")
    ax.plot([], [], "-", color="C0", label="pooled Eq. 24")
    ax.set(xlabel="p_mean [MPa]", ylabel="alpha_rc", title="First loading over the samples")
    ax.grid(alpha=0.3)
    ax.legend()
    figs["band_alpha_first.png"] = save_png(fig, out / "band_alpha_first.png")

    fig, (ax, aw) = plt.subplots(
        2, 1, figsize=(6, 5.6), sharex=True, gridspec_kw={"height_ratios": [3, 1.3]}
    )
    _fill(ax, u.band("tau_first"), MPa, "C1", f"{lv} band")
    bt = u.band("tau_first")
    aw.plot(
        np.array(bt.p) / MPa,
        100 * (np.array(bt.upper) - np.array(bt.lower)) / np.array(bt.central),
        "C1-",
    )
    aw.set(xlabel="p [MPa]", ylabel="band width / tau [%]")
    aw.grid(alpha=0.3)
    for e, style in (("lower", ":"), ("upper", "--")):
        law = mc.params.edge_laws()[e]
        b = u.band("tau_first")
        ax.plot(
            np.array(b.p) / MPa,
            law.tau_max * alpha_first(np.array(b.p), law) / MPa,
            style,
            color="k",
            lw=1,
            label=f"{e} edge law",
        )
    ax.set(ylabel="tau [MPa]", title="Shear on first loading (Eq. 24)")
    ax.grid(alpha=0.3)
    ax.legend()
    figs["band_tau_first.png"] = save_png(fig, out / "band_tau_first.png")

    fig, ax = plt.subplots(figsize=(6, 4.2))
    for i, b in enumerate(x for x in u.bands if x.quantity == "alpha_reload"):
        _fill(ax, b, 1.0, f"C{i % 10}", f"p_hist {b.p_hist / MPa:g} MPa")
    for c in cals.values():
        for rc in c.sweeps.reload_curves():
            ax.plot(rc.p / MPa, rc.alpha, ".", color="0.5", ms=2)
    ax.set(xlabel="p_mean [MPa]", ylabel="alpha_rc", title=f"Reload branches, {lv} bands")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    figs["band_reload.png"] = save_png(fig, out / "band_reload.png")
    return figs


def write_sample_outputs(mc, out, *, clock=None):
    """Write a multi-sample calibration's files into ``out``.

    The pooled set (as one calibration: ``params.json`` with the uncertainty block, tables,
    plots), ``samples.csv``, ``bands.csv``, the band plots, ``summary.json`` and
    ``report.html`` (with the band). ``clock``: as in :func:`write_outputs`.
    """
    out = Path(out)
    write_outputs(mc.pooled, out)
    u = mc.uncertainty
    rows = []
    for s in u.samples:
        c = mc.calibrations[s.name]
        rows.append(
            [
                s.name,
                s.C1,
                s.n1,
                s.C2,
                s.n2,
                c.params.mu_eff,
                c.first.r_squared,
                c.reload.r_squared,
                c.seconds,
            ]
        )
    write_csv(
        out / "samples.csv",
        ["sample", "C1", "n1", "C2", "n2", "mu_eff", "first_loading_r2", "reload_r2", "seconds"],
        rows,
    )
    write_csv(
        out / "bands.csv",
        ["quantity", "unit", "p_hist_Pa", "p_Pa", "central", "lower", "upper"],
        [
            [b.quantity, b.unit, "" if b.p_hist is None else b.p_hist, p, c, lo, hi]
            for b in u.bands
            for p, c, lo, hi in zip(b.p, b.central, b.lower, b.upper, strict=True)
        ],
    )
    write_band_plots(mc, out)
    summary = mc.summary()
    if clock is not None:
        summary["command_seconds"] = clock()
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=float) + "\n")
    write_report(
        summary,
        out,
        BAND_IMAGES + REPORT_IMAGES,
        title=f"Friction law calibration from {len(mc.calibrations)} samples",
    )
    return out
