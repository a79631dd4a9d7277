"""The files of a band run (``fe-demo ... --band`` / ``--samples``).

The top folder's history, plots, summary.json and report.html; the band itself is computed by
:mod:`fe_demo.analysis.band`.
"""

from __future__ import annotations

import json
from pathlib import Path

from sbmf_cli import column_name

from .reports import write_band_report

__all__ = ["write_band_outputs"]


def write_band_outputs(out, result, mode, level):
    """history.csv, the band plots, summary.json and report.html of a band run.

    ``result``: the :class:`fe_demo.analysis.band.BandResult` of the runs. Returns its summary
    record.
    """
    out = Path(out)
    band, keys = result.band, result.keys
    cols = ["height_reduction", "stage"] + [
        f"{k}{s}" for k, _ in keys for s in ("", "_lower", "_upper")
    ]
    header = [column_name("height_reduction", "fraction"), "stage"] + [
        column_name(f"{k}{s}", unit) for k, unit in keys for s in ("", "_lower", "_upper")
    ]
    lines = [",".join(header)]
    for i in range(band["height_reduction"].size):
        lines.append(",".join(f"{band[c][i]:.10g}" for c in cols))
    (out / "history.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    images = _plots(out, band, result.histories, keys, mode, level)
    rec = result.record
    (out / "summary.json").write_text(json.dumps(rec, indent=2) + "\n", encoding="utf-8")
    write_band_report(out, rec, images)
    return rec


def _plots(out, band, hist, keys, mode, level):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    what = f"{100 * level:g} % band of the law" if mode == "band" else "spread of the samples"
    images = []
    for key, _ in keys:
        scale, ylab, fname = (
            (1e-3, "die force (kN)", "force_band.png")
            if key == "force"
            else (100.0, "change of inner diameter (%)", "ring_band.png")
        )
        fig, ax = plt.subplots(figsize=(6, 4))
        r = 100 * band["height_reduction"]
        ax.fill_between(
            r,
            band[f"{key}_lower"] * scale,
            band[f"{key}_upper"] * scale,
            color="C0",
            alpha=0.3,
            lw=0,
            label=what,
        )
        for name, h in hist.items():
            if name != "central" and mode == "samples":
                ax.plot(100 * h["height_reduction"], h[key] * scale, "-", color="0.6", lw=0.6)
        ax.plot(r, band[key] * scale, "C0-", lw=1.5, label="central (pooled) law")
        ax.set(xlabel="height reduction (%)", ylabel=ylab)
        ax.grid(alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(out / fname, dpi=120)
        plt.close(fig)
        images.append((fname, f"{ylab} with the {what}"))
    return images
