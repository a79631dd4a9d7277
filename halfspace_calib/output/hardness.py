"""The hardness fit's files: table, record and the plot in the style of the paper's Figs. 3-4."""

from __future__ import annotations

import json

import numpy as np

from ._files import pyplot, save_png, write_csv

__all__ = ["hardness_table", "write_hardness_fit"]


def hardness_table(fit):
    """Markdown table: measured against simulated ``Ra``/``Rq`` (um) per row of the data."""
    d = fit.data
    lines = [
        "| p_mean (MPa) | Ra measured (um) | Ra simulated (um) | Rq measured (um) "
        "| Rq simulated (um) |",
        "|---|---|---|---|---|",
    ]
    lines.append(
        f"| 0 (before) | {'-' if d.initial is None else f'{d.initial[0] * 1e6:.4g}'} | "
        f"{fit.Ra_initial * 1e6:.4g} | "
        f"{'-' if d.initial is None else f'{d.initial[1] * 1e6:.4g}'} | {fit.Rq_initial * 1e6:.4g} |"
    )
    for p, a, b, sa, sb in zip(
        d.p_mean, d.Ra, d.Rq, fit.Ra_simulated, fit.Rq_simulated, strict=True
    ):
        lines.append(
            f"| {p / 1e6:.4g} | {a * 1e6:.4g} | {sa * 1e6:.4g} | {b * 1e6:.4g} | {sb * 1e6:.4g} |"
        )
    return "\n".join(lines) + "\n"


def write_hardness_fit(fit, out):
    """Write ``hardness_fit.csv``, ``.json``, ``.md`` and ``.png`` into the folder ``out``.

    Returns the plot's matplotlib Figure (closed; its artists keep the data).
    """
    d = fit.data
    write_csv(
        out / "hardness_fit.csv",
        ["p_mean_Pa", "Ra_measured_m", "Rq_measured_m", "Ra_simulated_m", "Rq_simulated_m"],
        [
            list(r)
            for r in zip(d.p_mean, d.Ra, d.Rq, fit.Ra_simulated, fit.Rq_simulated, strict=True)
        ],
    )
    (out / "hardness_fit.json").write_text(json.dumps(fit.as_dict(), indent=2))
    head = f"Effective hardness H = {fit.H / 1e6:.4g} MPa ({fit.message}).\n\n"
    (out / "hardness_fit.md").write_text(head + hardness_table(fit))
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.8))
    p = np.asarray(d.p_mean) / 1e6
    order = np.argsort(p)
    for ax, name, meas, sim, s0 in (
        (axes[0], "Ra", d.Ra, fit.Ra_simulated, fit.Ra_initial),
        (axes[1], "Rq", d.Rq, fit.Rq_simulated, fit.Rq_initial),
    ):
        i0 = 0 if name == "Ra" else 1
        ax.plot(p, np.asarray(meas) * 1e6, "o", label="measured")
        ps = np.concatenate([[0.0], p[order]])
        ss = np.concatenate([[s0], np.asarray(sim)[order]]) * 1e6
        ax.plot(ps, ss, "s-", label=f"half-space model, H = {fit.H / 1e6:.0f} MPa")
        if d.initial is not None:
            ax.plot([0.0], [d.initial[i0] * 1e6], "o", color="C0")
        ax.set(xlabel="p_mean [MPa]", ylabel=f"{name} after contact [um]", ylim=(0, None))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"H from after-contact roughness: rms relative residual {fit.residual:.3g}")
    return save_png(fig, out / "hardness_fit.png")
