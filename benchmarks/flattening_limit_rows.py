"""The limit analysis as a law on measured rows: a profile's own edge slope (issue 43, a study).

``flattening_limit_law.py`` holds the table's law to the truth's wedges and takes the measured row
as a wedge of its RMS slope. A row is not a wedge: its contact grows over many flanks of many
slopes. This script gives the law the row's own geometry, nothing fitted:

- **the edge slope** at contact fraction ``A`` is the harmonic mean of ``|dz / dx|`` where the
  level that leaves the share ``A`` of the row above it (its bearing level) crosses the row. A
  wedge lattice's contact grows by ``dA / dh = 1 / (l s)`` per level ``dh`` (half cell ``l``, flank
  slope ``s``), the row's by ``(1 / L) sum 1 / |z'_i|`` over its ``n`` edges; with ``l = L / n``
  the two agree at this ``s``. A wedge gives its own slope at every ``A`` (tested);
- **the curve** carries ``A`` and the flank's turn ``r = s / s_edge(A)``: the table's
  ``d ln s / d eps`` turns it, and ``s = r s_edge(A)`` follows the row as the contact grows
  (``flattening_limit.curve`` with ``slope_of``, its steps short enough to resolve the row:
  ``DA_MAX``);
- **the truth**: the rows of ``asperity_flattening.py --rows`` (the scan's rows on meshes that
  resolve their samples; the table's 64 x 32 takes every fourth), each on its finest mesh, and,
  held out, the four rows of ``--held-out``.

Writes ``results/flattening_limit_rows.md`` / ``.csv``: the row as a wedge of its RMS slope, by
its edge slope, and the runtime's law (L+E, built as ``flattening_truth.py`` builds it); and the
runtime's two-state law with the block's ``edge_slope`` as a calibration writes it (51 contact
fractions, ``halfspace_calib.pipeline.sweep.flattening_edges``; the runtime's own steps, no cap
on ``A``), column ``alpha_runtime_edges``.

Run: python benchmarks/flattening_limit_rows.py [--s-min 0.02] (after asperity_flattening.py
--no-table --rows, and --held-out for the held-out rows)
"""

import math

import numpy as np
from _provenance import RESULTS, read_rows, run_record, write_rows
from asperity_flattening import (
    HELD_OUT_ROWS,
    ROWS,
    measured_profile,
    profile_rms_slope,
    row_name,
)
from flattening_limit import curve
from flattening_limit_law import S_GRID, STEP, TABLE, Rates, _read
from flattening_truth import curve_misses, law_of, law_strain

import frictionlaw as fl
from halfspace_calib.pipeline.sweep.flattening_edges import EDGE_POINTS, profile_edge_slopes

ROWS_TRUTH = RESULTS / "asperity_rows.csv"
HELD_OUT_TRUTH = RESULTS / "asperity_rows_heldout.csv"  # asperity_flattening.py --held-out
# A row's edge slope varies on the scale of its samples: the curve's step keeps A within 0.001
# a step (beside STEP in strain), and the edge slope is tabulated on 1600 contact fractions. The
# steps of STEP alone were off by up to 0.10 (row 192 at 0.05 H: 0.456 against 0.355 after a
# strain of 0.005); 0.00025 a step and 6400 fractions move the 30 curves by at most 0.004.
DA_MAX = 0.001


def bearing_level(x, z, A):
    """The level ``h`` above which the piecewise-linear profile (``x``, ``z``) holds the share
    ``A`` of its length (the flat's plateau when the contact fraction is ``A``; bisection)."""
    z1, z2, dx = z[:-1], z[1:], np.diff(x)
    lo_z, hi_z = np.minimum(z1, z2), np.maximum(z1, z2)

    def share(h):
        part = np.clip((hi_z - h) / np.maximum(hi_z - lo_z, 1e-300), 0.0, 1.0)
        return float((dx * part).sum() / (x[-1] - x[0]))

    lo, hi = float(z.min()), float(z.max())
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if share(mid) > A else (lo, mid)
    return 0.5 * (lo + hi)


def edge_slope(x, z, A):
    """The edge slope of the wedge that stands for the profile (``x``, ``z``) at contact fraction
    ``A``: the harmonic mean of ``|dz / dx|`` where the level :func:`bearing_level` crosses the
    profile. A wedge lattice's contact grows by ``dA / dh = 1 / (l s)`` per level ``dh`` (half
    cell ``l``, flank slope ``s``); the profile's by ``(1 / L) sum 1 / |z'_i|`` over its ``n``
    edges; with ``l = L / n`` the two agree at this ``s``. A wedge gives its own slope at every
    ``A``; ``nan`` where the level crosses nothing."""
    h = bearing_level(x, z, A)
    d = z - h
    cross = d[:-1] * d[1:] < 0
    if not cross.any():
        return math.nan
    slopes = np.abs(np.diff(z) / np.diff(x))[cross]
    return float(cross.sum() / (1.0 / slopes).sum())


def mean_edge_slope(x, z, n=400):
    """The arithmetic mean of :func:`edge_slope` over the contact fractions ``(0, 1)`` (``n - 1``
    inner points; where no level crosses, left out): one constant slope that takes a profile to
    full contact at the same strain as its edge slope does where the rate is that of a shallow
    flank, ``dA / d eps = c / s`` (the table's within 0.5 % at ``s`` 0.01-0.02): the strain to
    full contact is ``int s(A) dA / c``. A study of a constant map (the column
    ``alpha_edge_mean``)."""
    s = np.array([edge_slope(x, z, A) for A in np.linspace(0.0, 1.0, n + 1)[1:-1]])
    return float(np.mean(s[np.isfinite(s)]))


def edge_slopes(x, z, n=1600):
    """:func:`edge_slope` tabulated on ``n + 1`` contact fractions, as a function of ``A``
    (linear between them; the RMS slope where no level crosses)."""
    a = np.linspace(0.0, 1.0, n + 1)
    rms = profile_rms_slope(x, z)
    s = np.array([edge_slope(x, z, A) for A in a])
    s = np.where(np.isfinite(s), s, rms)
    return lambda A: float(np.interp(A, a, s))


def block_edges(x, z):
    """The block's ``edge_slope`` of the profile (``x``, ``z``) as a calibration tabulates it:
    :func:`profile_edge_slopes` at ``EDGE_POINTS`` fractions, a bin without crossings taking its
    nearest neighbour's value (as ``edge_slope_table`` does)."""
    e = profile_edge_slopes(np.asarray(z)[:, None], float(x[1] - x[0]), False, EDGE_POINTS)
    ok = np.flatnonzero(np.isfinite(e))
    near = ok[np.abs(np.arange(e.size)[:, None] - ok[None, :]).argmin(axis=1)]
    return tuple(float(v) for v in e[near])


def _truth(path, rows, mode):
    """``{row index: (name, profile x, z, its rows of the truth file on its finest mesh)}``."""
    truth = read_rows(path)
    out = {}
    for i in rows:
        x, z, lam, _ = measured_profile(row=i)
        name = row_name(i, lam)
        mine = [r for r in truth if r["profile"] == name]
        if not mine:
            raise SystemExit(f"{name} is not in {path}: run asperity_flattening.py {mode}")
        nx = max(int(r["nx"]) for r in mine)
        out[i] = (name, x, z, [r for r in mine if int(r["nx"]) == nx])
    return out


def truth_rows(held_out=None):
    """Each truth row as ``(held_out, name, x, z, deg, H_row, cols, law, mesh)``: its profile,
    RMS slope (deg), hardness, ``cols`` ``{p/H: {strain: alpha}}`` on its finest mesh, the law
    ``flattening_truth.law_of`` builds from its pressing-alone fractions and that mesh
    (``"256x64"``). ``held_out``: only
    the rows of ``--rows`` (False) or of ``--held-out`` (True); ``None`` both."""
    sets = (
        (False, ROWS_TRUTH, ROWS, "--rows"),
        (True, HELD_OUT_TRUTH, HELD_OUT_ROWS, "--held-out"),
    )
    for held, path, rows, mode in sets:
        if held_out is not None and held != held_out:
            continue
        for name, x, z, mine in _truth(path, rows, mode).values():
            deg = float(mine[0]["slope_deg"])
            H_row = float(mine[0]["p_Pa"]) / float(mine[0]["p_over_H"])
            cols = {}
            for r in mine:
                cols.setdefault(float(r["p_over_H"]), {})[float(r["strain"])] = float(r["alpha"])
            mesh = f"{mine[0]['nx']}x{mine[0]['nz']}"
            yield held, name, x, z, deg, H_row, cols, law_of(cols, deg, H_row), mesh


def compare_rows(rows, held_out=False, s_grid=S_GRID):
    """The table's curves (``rows``, on the flank slopes ``s_grid``) against each resolved row at
    each of its pressures: the row as a wedge of its RMS slope, by its edge slope, and the
    runtime's law. ``held_out``: the rows of ``asperity_flattening.py --held-out``
    (``HELD_OUT_ROWS``) instead of ``ROWS``."""
    out, rates = [], {}
    for _, name, x, z, deg, H_row, cols, law, mesh in truth_rows(held_out):
        two = law.replace(
            flattening=fl.Flattening(
                law.flattening.slope, model="limit-analysis", edge_slope=block_edges(x, z)
            )
        )
        shape = edge_slopes(x, z)
        s_mean = mean_edge_slope(x, z)
        for ph in sorted(cols):
            strains = sorted(cols[ph])
            a0 = cols[ph][0.0]
            rate = rates.setdefault(ph, Rates(rows, ph, s_grid))
            wedge = curve(rate, a0, math.tan(math.radians(deg)), strains, STEP)
            edges = curve(rate, a0, None, strains, STEP, slope_of=shape, dA_max=DA_MAX)
            mean = curve(rate, a0, s_mean, strains, STEP)
            runtime = fl.flattening_curve(ph * H_row, law_strain(strains), law)
            run_edges = fl.flattening_curve(ph * H_row, law_strain(strains), two)
            out += [
                {
                    "profile": name,
                    "held_out": held_out,
                    "mesh": mesh,
                    "slope_deg": deg,
                    "p_over_H": ph,
                    "strain": e,
                    "alpha_truth": cols[ph][e],
                    "alpha_rms": round(w[0], 4),
                    "alpha_edges": round(g[0], 4),
                    "alpha_law": round(float(a), 4),
                    "alpha_edge_mean": round(m[0], 4),
                    "edge_mean_deg": round(math.degrees(math.atan(s_mean)), 3),
                    "alpha_runtime_edges": round(float(r2), 4),
                }
                for e, w, g, a, m, r2 in zip(
                    strains, wedge, edges, runtime, mean, run_edges, strict=True
                )
            ]
    return out


COLUMNS = ("alpha_rms", "alpha_edges", "alpha_law", "alpha_edge_mean", "alpha_runtime_edges")


def _misses(sel):
    """Per column: the largest miss, the RMS miss and the curves (row, p/H) within 0.05."""
    return [curve_misses(sel, c) for c in COLUMNS]


def summary(out):
    """Largest misses per row and pressure, and over the rows the map was set on, the held-out
    rows and all, for the two maps and the runtime's law."""
    keys = list(dict.fromkeys((r["held_out"], r["profile"], r["p_over_H"]) for r in out))
    lines = [
        "| row | p/H | mesh | largest miss: wedge of the RMS slope | edge slope | runtime's law "
        "| wedge of the mean edge slope | runtime's two-state law, block's edge_slope |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for k in keys:
        sel = [r for r in out if (r["held_out"], r["profile"], r["p_over_H"]) == k]
        m = [v[0] for v in _misses(sel)]
        name = k[1] + (", held out" if k[0] else "")
        lines.append(
            f"| {name} | {k[2]:g} | {sel[0]['mesh']} | " + " | ".join(f"{v:.3f}" for v in m) + " |"
        )
    lines += [
        "",
        "| curves | largest miss / RMS / within 0.05: wedge of the RMS slope | edge slope | "
        "runtime's law | wedge of the mean edge slope | runtime's two-state law, block's "
        "edge_slope |",
        "|---|---|---|---|---|---|",
    ]
    groups = [
        ("the rows of --rows", False),
        ("the held-out rows (--held-out)", True),
        ("all", None),
    ]
    for label, flag in groups:
        sel = [r for r in out if flag is None or r["held_out"] == flag]
        if not sel or (flag is None and len({r["held_out"] for r in out}) < 2):
            continue
        m = _misses(sel)
        lines.append(
            f"| {label} ({m[0][3]}) | "
            + " | ".join(f"{a:.3f} / {b:.3f} / {n}" for a, b, n, _ in m)
            + " |"
        )
    return lines


def main(s_min=None):
    """The comparison, written to ``results/``; with ``s_min`` the table's flank slopes below it
    are left out (its rates held at ``s_min``'s below it, as the table that ended at 0.02 did)
    and the summary is printed only."""
    s_grid = S_GRID if s_min is None else tuple(v for v in S_GRID if v >= s_min)
    table_rows = _read(TABLE)
    out = compare_rows(table_rows, s_grid=s_grid)
    if HELD_OUT_TRUTH.exists():
        out += compare_rows(table_rows, held_out=True, s_grid=s_grid)
    if s_min is not None:
        print(f"# the table's flank slopes from {s_min:g}", *summary(out), sep="\n")
        return
    write_rows(RESULTS / "flattening_limit_rows.csv", out)
    lines = [
        "# The limit analysis as a law, against resolved measured rows",
        "",
        "`benchmarks/flattening_limit_rows.py`: the table's curves (as `flattening_limit_law.md`, "
        "its cached table) against the rows of `asperity_rows.csv` and, held out, of "
        "`asperity_rows_heldout.csv`, each on its finest mesh, "
        "from the row's pressing-alone fraction; the row as a wedge of its RMS slope, and by its "
        "edge slope (the harmonic mean of the slopes where the level that leaves the share `A` "
        "above it crosses the row), the flank's turn from the table in both; the runtime's law "
        "(L+E) from the row's pressing-alone fractions and RMS slope; and the row as a wedge of "
        "its mean edge slope over the contact fractions (one constant, `mean_edge_slope`); the "
        "runtime's two-state law (`flattening_curve`) with the block's `edge_slope` as a "
        "calibration tabulates it (51 fractions, binned), alpha1 the row's pressing-alone "
        "fractions. Nothing fitted.",
        "",
        *summary(out),
    ]
    (RESULTS / "flattening_limit_rows.md").write_text("\n".join(lines) + "\n", "utf-8")
    print("\n".join(lines))


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--s-min",
        type=float,
        default=None,
        help="leave out the table's flank slopes below this one; print the summary only "
        "(default: the whole table, results written)",
    )
    cli = ap.parse_args()
    if cli.s_min is None:
        with run_record(__file__):
            main()
    else:
        main(cli.s_min)
