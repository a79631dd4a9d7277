"""Files of the sliding study (Figs. 11-15): ``sliding.csv``, its summary and the plots."""

from pathlib import Path

import numpy as np

from ..studies.sliding import SlidingResult
from ..studies.sliding_study import SlidingStudy
from ._files import new_axes, save_png, write_csv

__all__ = ["plot_sliding", "write_sliding_outputs"]

#: ``sliding.csv``: SI units in the names (no suffix: dimensionless or a count)
CSV_COLUMNS = [
    "position",
    "x_m",
    "p_mean_Pa",
    "u0_m",
    "alpha",
    "W_def_J",
    "W_adh_J",
    "ratio",
    "separation_m",
    "displaced_volume_m3",
    "converged",
    "nit",
]

#: ``sliding_summary.csv`` columns: the keys of ``SlidingResult.steady`` and their units
SUMMARY_COLUMNS = {
    "p_mean": "p_mean_Pa",
    "positions": "positions",
    "ratio_mean": "ratio_mean",
    "ratio_max": "ratio_max",
    "W_def_mean": "W_def_mean_J",
    "W_adh_mean": "W_adh_mean_J",
    "alpha_mean": "alpha_mean",
    "first_ratio": "first_ratio",
    "converged": "converged",
    "seconds": "seconds_s",
}


def _results_of(result):
    if isinstance(result, SlidingResult):
        return [result]
    if isinstance(result, SlidingStudy):
        return result.ok
    raise ValueError(f"result must be a SlidingResult or SlidingStudy, got {type(result).__name__}")


def write_sliding_outputs(result, out_dir):
    """Write ``sliding.csv`` and the plots of Figs. 11-15 into ``out_dir``.

    Parameters
    ----------
    result : SlidingResult or SlidingStudy
    out_dir : str or Path
        Created if missing.

    Returns
    -------
    pathlib.Path
        ``out_dir``. Files: ``sliding.csv`` (:data:`CSV_COLUMNS`, units in the names),
        ``sliding_summary.csv`` (steady sliding per pressure, :data:`SUMMARY_COLUMNS`),
        ``fig11_u0.png``, ``fig12_alpha.png``, ``fig13_W_adh.png``, ``fig14_W_def.png``,
        ``fig15_ratio.png``.
    """
    results = _results_of(result)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(
        out / "sliding.csv",
        CSV_COLUMNS,
        [
            [
                int(r.position[i]),
                repr(float(r.x[i])),
                repr(r.p_mean),
                repr(float(r.u0[i])),
                repr(float(r.alpha[i])),
                repr(float(r.W_def[i])),
                repr(float(r.W_adh[i])),
                repr(float(r.ratio[i])),
                repr(float(r.separation[i])),
                repr(float(r.displaced_volume[i])),
                int(r.converged[i]),
                int(r.nit[i]),
            ]
            for r in results
            for i in range(r.position.size)
        ],
    )
    write_csv(
        out / "sliding_summary.csv",
        list(SUMMARY_COLUMNS.values()),
        [[r.steady[k] for k in SUMMARY_COLUMNS] for r in results],
    )
    if results:
        plot_sliding(results, out)
    return out


def plot_sliding(results, out):
    """Figs. 11-15 into ``out``: ``{file name: Figure}``.

    ``out=None``: the figures only (for a notebook), nothing written.
    """
    made = {}
    figs = [
        ("fig11_u0.png", "u0", 1e6, "global approach u0 (um)", "Fig. 11", False),
        ("fig12_alpha.png", "alpha", 1.0, "A_real / A0", "Fig. 12", False),
        ("fig13_W_adh.png", "W_adh", 1e3, "W_adh per position (mJ)", "Fig. 13", False),
        ("fig14_W_def.png", "W_def", 1e3, "W_def per position (mJ)", "Fig. 14", True),
        ("fig15_ratio.png", "ratio", 1.0, "W_def / W_adh", "Fig. 15", True),
    ]
    for name, attr, scale, ylabel, title, log in figs:
        fig, ax = new_axes((6, 4))
        for r in results:
            y = getattr(r, attr) * scale
            x = r.x * 1e3
            if log:  # position 0 (first indentation) dwarfs the sliding values: leave it out
                x, y = x[1:], y[1:]
                y = np.where(y > 0, y, np.nan)
            ax.plot(x, y, lw=1, label=f"{r.p_mean / 1e6:g} MPa")
        if log:
            ax.set_yscale("log")
        if attr == "ratio":
            ax.axhline(0.008, color="k", ls="--", lw=0.8, label="paper: 0.008")
        ax.set_xlabel("sliding distance x (mm)")
        ax.set_ylabel(ylabel)
        ax.set_title(f"{title} (sliding, Sec. 3.3)")
        ax.legend(fontsize=7)
        made[name] = save_png(fig, None if out is None else out / name)
    return made
