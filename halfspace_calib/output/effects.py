"""Files of the optional effects: ``tangential/``, ``geometric/`` and ``sliding/`` folders."""

from pathlib import Path

import numpy as np

from ._files import new_axes, save_png, write_csv

__all__ = [
    "STIFFNESS_COLUMNS",
    "STIFFNESS_HEADERS",
    "write_stiffness_csv",
    "write_tangential_outputs",
    "plot_tangential",
    "write_effect_outputs",
]


#: columns of the tangential stiffness table (one row per first-loading pressure)
STIFFNESS_COLUMNS = (
    "p_mean",
    "alpha",
    "q_limit",
    "delta_full",
    "delta_stick",
    "k_t0",
    "k_eq",
    "k_sec",
    "converged",
)


#: CSV header of each stiffness column, with its SI unit
STIFFNESS_HEADERS = {
    "p_mean": "p_mean_Pa",
    "alpha": "alpha",
    "q_limit": "q_limit_Pa",
    "delta_full": "delta_full_m",
    "delta_stick": "delta_stick_m",
    "k_t0": "k_t0_Pa_per_m",
    "k_eq": "k_eq_Pa_per_m",
    "k_sec": "k_sec_Pa_per_m",
    "converged": "converged",
}


def write_stiffness_csv(summary, path):
    """Write the tangential stiffness table of :func:`summarize_tangential`'s ``summary``."""
    rows = [[r[k] for k in STIFFNESS_COLUMNS] for r in summary["rows"]]
    write_csv(path, [STIFFNESS_HEADERS[k] for k in STIFFNESS_COLUMNS], rows)
    return path


def write_tangential_outputs(levels, summary, out_dir):
    """``tangential.csv`` (curves), ``tangential_stiffness.csv`` and two PNGs into ``out_dir``."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    curves = [(lv.p_hist, lv.tangential) for lv in levels if lv.tangential is not None]
    write_csv(
        out / "tangential.csv",
        ["p_mean_Pa", "delta_m", "q_mean_Pa", "q_over_q_limit", "slip_fraction"],
        [
            [p, d, q, q / t.q_limit, s]
            for p, t in curves
            for d, q, s in zip(
                t.delta.tolist(), t.q_mean.tolist(), t.slip_fraction.tolist(), strict=True
            )
        ],
    )
    write_stiffness_csv(summary, out / "tangential_stiffness.csv")
    if curves:
        plot_tangential(curves, summary, out)
    return out


def plot_tangential(curves, summary, out):
    """``tangential_curves.png`` and ``tangential_stiffness.png``: ``{file name: Figure}``.

    ``curves``: ``[(p_mean, PreslidingCurve), ...]``; ``summary``: the stiffness summary.
    ``out=None``: the figures only (for a notebook), nothing written.
    """
    figs = {}

    fig, ax = new_axes((6, 4.2))
    for i, (p, t) in enumerate(curves):
        ax.plot(
            np.asarray(t.delta) * 1e9,
            np.asarray(t.q_mean) / 1e6,
            "-o",
            ms=3,
            color=f"C{i % 10}",
            label=f"{p / 1e6:g} MPa",
        )
    ax.set(
        xlabel="rigid shift delta [nm]",
        ylabel="q_mean [MPa]",
        title="Pre-sliding: mean tangential traction (Tresca cap, Eq. 18)",
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    figs["tangential_curves.png"] = save_png(fig, _path(out, "tangential_curves.png"))

    rows = summary["rows"]
    fig, ax = new_axes((6, 4.2))
    p = np.array([r["p_mean"] for r in rows]) / 1e6
    ax.loglog(p, [r["k_t0"] for r in rows], "o-", label="k_t0 (initial)")
    ax.loglog(p, [r["k_eq"] for r in rows], "^-", label="k_eq (energy-equivalent, recommended)")
    ax.loglog(p, [r["k_sec"] for r in rows], "s-", label="k_sec (secant to full sliding)")
    ax.set(
        xlabel="p_mean [MPa]",
        ylabel="tangential stiffness [Pa/m]",
        title="Interface tangential stiffness (penalty k_t)",
    )
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    figs["tangential_stiffness.png"] = save_png(fig, _path(out, "tangential_stiffness.png"))
    return figs


def write_effect_outputs(cal, out):
    """Each modelled effect's CSV and PNG into ``out/tangential``, ``out/geometric``, ``out/sliding``.

    Through the calibration's effects registry (``cal.write_effects``), which calls the writers
    of this package.
    """
    cal.write_effects(Path(out))


def _path(out, name):
    """``out / name``, or ``None`` (figures only, nothing written) for ``out=None``."""
    return None if out is None else out / name
