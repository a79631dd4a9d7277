"""Run records as files: the history CSV (with units), the VTU series and the console table.

Every column and field states its unit in its name (:func:`sbmf_cli.column_name`): ``force_N``,
``stroke_m``, ``avg_pressure_Pa``, ``height_reduction_fraction`` (fractions, never percent, in
files); counts, flags and ratios named as such keep bare names. :func:`read_history_csv` reads
a history with the names of this version or of the versions before the units were in every name.
"""

import csv
import math
from pathlib import Path

import numpy as np

from sbmf_cli import column_key, column_name

from ..solver.material import von_mises

__all__ = [
    "HISTORY_UNITS",
    "VTU_FIELDS",
    "csv_header",
    "read_history_csv",
    "write_history_csv",
    "write_vtu_series",
    "summary_table",
]

_FIRST = ("height_reduction", "force", "inner_diameter_change")

#: SI unit of every history column ("fraction": of a reference, 0.5 for 50 %; "1": a count,
#: a flag, the stage number or a ratio named as one)
HISTORY_UNITS = {
    "height_reduction": "fraction",
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
    "inner_diameter_change": "fraction",
    "inner_diameter_min_change": "fraction",
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
    "alpha_die_mean": "fraction",
    "alpha_f_max": "fraction",
    "n_below_flattening_table": "1",
    "eps_p_die_mean": "1",
}


def csv_header(key):
    """CSV column name of history column ``key``: ``force_N``, ``height_reduction_fraction``.

    Counts, flags and named ratios keep their bare names.

    Raises ``ValueError`` for a column without a declared unit in :data:`HISTORY_UNITS`;
    ``n_contact_<zone>`` (contact nodes per zone of a zoned die) is a count.
    """
    if key.startswith("n_contact_"):  # contact nodes per zone of the die (a count)
        return key
    try:
        unit = HISTORY_UNITS[key]
    except KeyError:
        raise ValueError(f"history column {key!r} has no unit in HISTORY_UNITS") from None
    return column_name(key, unit)


def read_history_csv(path):
    """``{column: array}`` of a ``history.csv``, keyed without units (``force``, not ``force_N``).

    Reads the names of this version (``height_reduction_fraction``) and of earlier ones
    (``height_reduction``).
    """
    with Path(path).open(newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    if not rows:
        return {}
    return {column_key(k): np.array([float(r[k]) for r in rows]) for k in rows[0]}


def write_history_csv(path, history):
    """One row per accepted increment; ``height_reduction_fraction`` and ``force_N`` first.

    Every header states its unit (``force_N``, ``stroke_m``, ``avg_pressure_Pa``,
    ``height_reduction_fraction``); bare names are counts, flags and named ratios (see
    :data:`HISTORY_UNITS`).
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


#: the unit of every VTU field (its name states it: ``contact_pressure_Pa``)
VTU_FIELDS = {
    "displacement": "m",
    "contact_pressure": "Pa",
    "shear": "Pa",
    "p_hist": "Pa",
    "stress_rr": "Pa",
    "stress_zz": "Pa",
    "stress_tt": "Pa",
    "stress_rz": "Pa",
    "von_mises": "Pa",
    "eps_p": "1",
}


def write_vtu_series(folder, t, snapshots, name="step"):
    """Write one ``.vtu`` per snapshot and a ``.pvd`` index (open the ``.pvd`` in ParaView).

    Field names state their units (:data:`VTU_FIELDS`): point data ``displacement_m``,
    ``contact_pressure_Pa``, ``shear_Pa``, ``p_hist_Pa``; cell data ``stress_rr_Pa`` (``zz``,
    ``tt``, ``rz``), ``von_mises_Pa`` and ``eps_p`` (equivalent plastic strain, dimensionless).
    """
    import meshio

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    entries = []
    for i, s in enumerate(snapshots):
        pts = np.column_stack([s["x"], np.zeros(len(s["x"]))])
        u = np.column_stack([s["u"], np.zeros(len(s["u"]))])
        sig = s["sigma"]
        cells = {
            "stress_rr": sig[:, 0],
            "stress_zz": sig[:, 1],
            "stress_tt": sig[:, 2],
            "stress_rz": sig[:, 3],
            "von_mises": von_mises(sig),
            "eps_p": s["eps_p"],
        }
        points = {"displacement": u, "contact_pressure": s["p"], "shear": s["tau"]}
        points["p_hist"] = s["p_hist"]
        mesh = meshio.Mesh(
            pts,
            [("quad", np.ascontiguousarray(t.T))],
            point_data={column_name(k, VTU_FIELDS[k]): v for k, v in points.items()},
            cell_data={column_name(k, VTU_FIELDS[k]): [v] for k, v in cells.items()},
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
