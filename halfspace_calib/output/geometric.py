"""Files of the geometric study (Figs. 9-10): ``geometric.csv`` and two plots."""

from pathlib import Path

from ..studies.geometric import GeometricResult, GeometricStudy
from ._files import new_axes, save_png, write_csv

__all__ = ["plot_geometric", "write_geometric_outputs"]

CSV_COLUMNS = [
    "label",
    "p_mean_Pa",
    "alpha",
    "tau_adh_Pa",
    "tau_geo_Pa",
    "ratio",
    "plastic_fraction",
    "converged",
]


def write_geometric_outputs(result, out_dir):
    """Write ``geometric.csv``, ``fig9_tau.png`` and ``fig10_ratio.png`` into ``out_dir``.

    Parameters
    ----------
    result : GeometricResult, GeometricStudy or list of GeometricResult
    out_dir : str or Path
        Created if missing.

    Returns
    -------
    pathlib.Path
        ``out_dir``.
    """
    if isinstance(result, GeometricStudy):
        results = result.results
    elif isinstance(result, GeometricResult):
        results = [result]
    else:
        results = list(result)
    if not all(isinstance(r, GeometricResult) for r in results):
        raise ValueError("result must be a GeometricResult, a GeometricStudy or a list of them")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(
        out / "geometric.csv",
        CSV_COLUMNS,
        [
            [
                r.label,
                repr(float(r.p_mean[i])),
                repr(float(r.alpha[i])),
                repr(float(r.tau_adh[i])),
                repr(float(r.tau_geo[i])),
                repr(float(r.ratio[i])),
                repr(float(r.plastic_fraction[i])),
                int(r.converged[i]),
            ]
            for r in results
            for i in range(r.p_mean.size)
        ],
    )
    plot_geometric(results, out)
    return out


def plot_geometric(results, out):
    """``fig9_tau.png`` and ``fig10_ratio.png`` into ``out``: ``{file name: Figure}``.

    ``out=None``: the figures only (for a notebook), nothing written.
    """
    figs = {}

    marks = ["*", "o", "s", "^", "v", "D"]
    fig, ax = new_axes((6, 4.2))
    for i, r in enumerate(results):
        mk = marks[i % len(marks)]
        ax.plot(
            r.p_mean / 1e6, r.tau_adh / 1e6, "-" + mk, color=f"C{i}", label=f"tau_adh, {r.label}"
        )
        ax.plot(
            r.p_mean / 1e6, r.tau_geo / 1e6, "--" + mk, color=f"C{i}", label=f"tau_geo, {r.label}"
        )
    ax.set(
        xlabel="p_mean [MPa]",
        ylabel="shear stress [MPa]",
        title="Fig. 9: adhesive and geometric shear",
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    figs["fig9_tau.png"] = save_png(fig, _path(out, "fig9_tau.png"))

    fig, ax = new_axes((6, 4.2))
    for i, r in enumerate(results):
        ax.plot(
            r.p_mean / 1e6,
            r.ratio,
            "-" + marks[i % len(marks)],
            color=f"C{i}",
            label=f"{r.label} (mean {r.ratio_mean:.4f})",
        )
    ax.set(
        xlabel="p_mean [MPa]",
        ylabel="tau_geo / tau_adh",
        title="Fig. 10: share of the geometric shear",
    )
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    figs["fig10_ratio.png"] = save_png(fig, _path(out, "fig10_ratio.png"))
    return figs


def _path(out, name):
    """``out / name``, or ``None`` (figures only, nothing written) for ``out=None``."""
    return None if out is None else out / name
