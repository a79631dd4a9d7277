"""Run records as files: the history CSV (with units), the VTU series and the console table."""

import csv
import math
from pathlib import Path

import numpy as np

from ..solver.material import von_mises

__all__ = [
    "HISTORY_UNITS",
    "csv_header",
    "write_history_csv",
    "write_vtu_series",
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

    Raises ``ValueError`` for a column without a declared unit in :data:`HISTORY_UNITS`;
    ``n_contact_<zone>`` (contact nodes per zone of a zoned die) is a count.
    """
    if key.startswith("n_contact_"):  # contact nodes per zone of the die (a count)
        return key
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
