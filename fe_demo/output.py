"""Writers: history CSV, VTU time series (meshio, with a ParaView ``.pvd`` index) and PNG plots.

Each plot has a ``*_figure`` function that returns the matplotlib Figure (not held by pyplot, for
notebooks) and a ``plot_*`` wrapper that writes it as PNG; ``SceneResult.figures()`` gives a run's.
"""

import csv
import math
from pathlib import Path

import numpy as np

from .material import von_mises

__all__ = [
    "HISTORY_UNITS",
    "csv_header",
    "write_history_csv",
    "write_vtu_series",
    "force_stroke_figure",
    "die_profile_figure",
    "law_comparison_figure",
    "ring_chart_figure",
    "recontact_figure",
    "plot_force_stroke",
    "plot_die_profile",
    "plot_law_comparison",
    "plot_ring_chart",
    "plot_recontact",
    "summary_table",
]

_FIRST = ("height_reduction", "force", "inner_diameter_change")

#: SI unit of every history column ("1": dimensionless fraction, ratio, count or flag)
HISTORY_UNITS = {
    "height_reduction": "1",
    "stroke": "m",
    "force": "N",
    "contact_radius": "m",
    "avg_pressure": "Pa",
    "flow_stress_hom": "Pa",
    "slab_pressure": "Pa",
    "max_radius": "m",
    "top_radius": "m",
    "n_stick": "1",
    "n_slip": "1",
    "n_open": "1",
    "n_reload_eq25": "1",
    "nit": "1",
    "cutbacks": "1",
    "partial": "1",
    "min_quality": "1",
    "remeshed": "1",
    "inner_diameter_change": "1",
    "inner_diameter_min_change": "1",
    "stage": "1",
    "tau_diff_eq25": "Pa",
    "n_above_range": "1",
    "n_hist_above_range": "1",
    "n_below_range": "1",
    "p_peak": "Pa",
    "p_hist_peak": "Pa",
    "p_peak_over_p_max": "1",
    "n_above_H": "1",
    "n_hist_above_H": "1",
}


def csv_header(key):
    """CSV column name of history column ``key``: ``key_<unit>`` (``force_N``), bare if unitless.

    Raises ``ValueError`` for a column without a declared unit in :data:`HISTORY_UNITS`.
    """
    try:
        unit = HISTORY_UNITS[key]
    except KeyError:
        raise ValueError(f"history column {key!r} has no unit in HISTORY_UNITS") from None
    return key if unit == "1" else f"{key}_{unit}"


def write_history_csv(path, history):
    """One row per accepted increment; ``height_reduction`` and ``force_N`` first.

    Headers carry the SI unit of dimensional columns (``force_N``, ``stroke_m``,
    ``avg_pressure_Pa``); bare names are dimensionless (see :data:`HISTORY_UNITS`).
    """
    path = Path(path)
    keys = [k for k in _FIRST if k in history] + [k for k in history if k not in _FIRST]
    header = [csv_header(k) for k in keys]
    n = len(history[keys[0]]) if keys else 0
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for i in range(n):
            w.writerow([_fmt(history[k][i]) for k in keys])
    return path


def _fmt(v):
    if isinstance(v, (int, np.integer)):
        return int(v)
    return f"{float(v):.10g}"


def write_vtu_series(folder, t, snapshots, name="step"):
    """Write one ``.vtu`` per snapshot and a ``.pvd`` index (open the ``.pvd`` in ParaView).

    Point data: ``displacement`` (m), ``contact_pressure``, ``shear``, ``p_hist`` (Pa).
    Cell data: ``stress_rr/zz/tt/rz``, ``von_mises`` (Pa), ``eps_p``.
    """
    import meshio

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    entries = []
    for i, s in enumerate(snapshots):
        pts = np.column_stack([s["x"], np.zeros(len(s["x"]))])
        u = np.column_stack([s["u"], np.zeros(len(s["u"]))])
        sig = s["sigma"]
        cell_data = {
            "stress_rr": [sig[:, 0]],
            "stress_zz": [sig[:, 1]],
            "stress_tt": [sig[:, 2]],
            "stress_rz": [sig[:, 3]],
            "von_mises": [von_mises(sig)],
            "eps_p": [s["eps_p"]],
        }
        mesh = meshio.Mesh(
            pts,
            [("quad", np.ascontiguousarray(t.T))],
            point_data={
                "displacement": u,
                "contact_pressure": s["p"],
                "shear": s["tau"],
                "p_hist": s["p_hist"],
            },
            cell_data=cell_data,
        )
        fname = f"{name}_{i:04d}.vtu"
        meshio.write(folder / fname, mesh, binary=True)
        entries.append((s["height_reduction"], fname))
    lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1">', "<Collection>"]
    lines += [f'  <DataSet timestep="{tt:.8g}" file="{f}"/>' for tt, f in entries]
    lines += ["</Collection>", "</VTKFile>"]
    pvd = folder / f"{name}.pvd"
    pvd.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return pvd


def _figure(figsize, ncols=1):
    """A new figure (not registered with pyplot, so nothing to close) and its axes."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize)
    return fig, fig.subplots(1, ncols)


def _save(fig, path):
    """Write the (laid-out) figure as PNG at 120 dpi; returns ``path``."""
    fig.savefig(path, dpi=120)
    return path


def force_stroke_figure(histories, labels, title="Cylinder upsetting"):
    """Force against height reduction for one or more runs."""
    fig, ax = _figure((6, 4))
    for h, lab in zip(histories, labels, strict=True):
        ax.plot(100 * h["height_reduction"], h["force"] / 1e3, label=lab)
    ax.set_xlabel("height reduction (%)")
    ax.set_ylabel("die force (kN)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return fig


def die_profile_figure(profile, title="Along the die"):
    """Contact pressure, shear and ``p_hist`` against radius at the end of a run."""
    fig, ax = _figure((6, 4))
    r = 1e3 * profile["r"]
    on = profile["p"] > 0
    ax.plot(r[on], profile["p"][on] / 1e6, "o-", ms=3, label="pressure p")
    ax.plot(r[on], np.abs(profile["tau"][on]) / 1e6, "s-", ms=3, label="|shear| tau")
    ax.plot(r[on], profile["p_hist"][on] / 1e6, "--", label="p_hist")
    ax.set_xlabel("r (mm)")
    ax.set_ylabel("MPa")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return fig


def recontact_figure(profile, title="Re-contact: friction limit with and without p_hist"):
    """Pressure, ``p_hist`` and the shear limit of Eq. 25 vs first loading along the die."""
    fig, (a1, a2) = _figure((11, 4), 2)
    r = 1e3 * profile["r"]
    on = profile["p"] > 0
    a1.plot(r[on], profile["p"][on] / 1e6, "o-", ms=3, label="p")
    a1.plot(r[on], profile["p_hist"][on] / 1e6, "--", label="p_hist")
    a1.set_ylabel("MPa")
    a2.plot(r[on], profile["tau_limit"][on] / 1e6, "o-", ms=3, label="tau limit with p_hist")
    a2.plot(
        r[on],
        profile["tau_limit_first_loading"][on] / 1e6,
        "s--",
        ms=3,
        label="tau limit without history (Eq. 24)",
    )
    a2.set_ylabel("MPa")
    for a in (a1, a2):
        a.set_xlabel("r (mm)")
        a.grid(alpha=0.3)
        a.legend()
    fig.suptitle(f"{title} (height reduction {100 * profile['height_reduction']:.2f} %)")
    fig.tight_layout()
    return fig


def law_comparison_figure(results, title="Friction laws side by side"):
    """Force-stroke curves and end-of-run die profiles of several laws."""
    fig, (a1, a2) = _figure((11, 4), 2)
    for lab, (h, prof) in results.items():
        a1.plot(100 * h["height_reduction"], h["force"] / 1e3, label=lab)
        on = prof["p"] > 0
        a2.plot(1e3 * prof["r"][on], np.abs(prof["tau"][on]) / 1e6, label=lab)
    a1.set_xlabel("height reduction (%)")
    a1.set_ylabel("die force (kN)")
    a2.set_xlabel("r (mm)")
    a2.set_ylabel("|shear| on the die (MPa)")
    for a in (a1, a2):
        a.grid(alpha=0.3)
        a.legend()
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def ring_chart_figure(chart, fe_curves=None, title="Ring compression calibration chart"):
    """Upper-bound chart (lines) with FE results (markers) on top.

    ``chart``: dict ``m -> (reduction, inner_diameter_change)``;
    ``fe_curves``: dict ``label -> (reduction, inner_diameter_change)``.
    """
    fig, ax = _figure((6, 4.5))
    for m, (red, dch) in chart.items():
        ax.plot(100 * red, 100 * dch, "k-", lw=0.8)
        ax.annotate(f"m={m:g}", (100 * red[-1], 100 * dch[-1]), fontsize=7)
    markers = "osd^v<>"
    for i, (lab, (red, dch)) in enumerate((fe_curves or {}).items()):
        ax.plot(100 * red, 100 * dch, markers[i % len(markers)], ms=3, label=lab)
    ax.axhline(0, color="0.5", lw=0.5)
    ax.set_xlabel("height reduction (%)")
    ax.set_ylabel("change of inner diameter (%)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    if fe_curves:
        ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def plot_force_stroke(path, histories, labels, title="Cylinder upsetting"):
    """Write :func:`force_stroke_figure` as a PNG file at ``path``; returns ``path``."""
    return _save(force_stroke_figure(histories, labels, title=title), path)


def plot_die_profile(path, profile, title="Along the die"):
    """Write :func:`die_profile_figure` as a PNG file at ``path``; returns ``path``."""
    return _save(die_profile_figure(profile, title=title), path)


def plot_recontact(path, profile, title="Re-contact: friction limit with and without p_hist"):
    """Write :func:`recontact_figure` as a PNG file at ``path``; returns ``path``."""
    return _save(recontact_figure(profile, title=title), path)


def plot_law_comparison(path, results, title="Friction laws side by side"):
    """Write :func:`law_comparison_figure` as a PNG file at ``path``; returns ``path``."""
    return _save(law_comparison_figure(results, title=title), path)


def plot_ring_chart(path, chart, fe_curves=None, title="Ring compression calibration chart"):
    """Write :func:`ring_chart_figure` as a PNG file at ``path``; returns ``path``."""
    return _save(ring_chart_figure(chart, fe_curves=fe_curves, title=title), path)


def summary_table(rows):
    """Plain-text table from a list of dicts (same keys)."""
    if not rows:
        return ""
    keys = list(rows[0])
    cells = [[_cell(r[k]) for k in keys] for r in rows]
    widths = [max(len(k), *(len(c[i]) for c in cells)) for i, k in enumerate(keys)]
    line = "  ".join(k.ljust(w) for k, w in zip(keys, widths, strict=True))
    out = [line, "-" * len(line)]
    out += ["  ".join(c.ljust(w) for c, w in zip(row, widths, strict=True)) for row in cells]
    return "\n".join(out)


def _cell(v):
    if isinstance(v, float):
        if v == 0 or (1e-3 <= abs(v) < 1e5):
            return f"{v:.4g}"
        return f"{v:.3e}" if math.isfinite(v) else str(v)
    return str(v)
