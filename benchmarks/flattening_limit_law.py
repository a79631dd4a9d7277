"""The limit analysis as a law: two states per node, rates from a table (issue 43, a study).

``flattening_limit.py`` showed that the rigid-perfectly plastic optimum of the half cell, given a
state's geometry and nothing of the truth, gives the truth's sinking rate at 0.15-0.3 H, and that
at low pressure it turns the flank, which no rate of ``A`` alone can carry. This script makes that
optimum a law and holds it to the truth's 30 curves (24 wedges, the measured row as a wedge of its
RMS slope), nothing fitted:

- **the state** of a node is the contact fraction ``A`` and the flank's current slope ``s`` (both
  invariant under the homogeneous stretch, which only scales the period: the cell is the half
  period with ``l = 1`` at every state);
- **the rates** ``dA / d eps`` and ``ds / d eps`` come from the optimum's field on the free
  flank: ``u`` and ``w`` fitted by straight lines over the flank beyond its first two elements
  (the continuous field smears the lattice's line from the plateau's edge over them), the lines
  extrapolated to the edge for the contact's growth, ``dA / d eps = (w_f(A) - W) / s + u_f(A) -
  A``, and their slopes for the flank's turn, ``ds / d eps = -(dw_f / dx + s du_f / dx)`` (the
  homogeneous stretch alone gives ``-2 s``, its convection);
- **the table**: the rates on a grid of ``A`` and ``ln s`` at each of the truth's pressures,
  computed once (they depend on ``p / k``, ``A`` and ``s`` alone: a property of the wedge cell,
  not of a surface); the curves integrate them by the explicit midpoint rule in strain, bilinear in
  (``A``, ``ln s``), from the truth's pressing-alone fraction and the wedge's initial slope (as the
  runtime starts from ``alpha1``).

``--converge`` shows what the table's mesh does at a few states (the readings against the mesh);
the default run computes the table (cached in ``results/flattening_limit_table.csv``; ``--fresh``
recomputes it) on two worker processes and writes ``flattening_limit_law.md`` / ``.csv``.

Run: python benchmarks/flattening_limit_law.py [--mesh NX NZ SIDES] [--converge] [--fresh]
"""

import argparse
import csv
import math
import multiprocessing
import os

import numpy as np
import scipy.sparse as sp
from _provenance import RESULTS, run_record, write_rows
from flattening_limit import H, curve, limit_field, solve

PRESSURES = (0.05, 0.1, 0.2, 0.3, 0.45, 0.6)  # the truth's p / H
A_GRID = (0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.96)
S_GRID = (0.01, 0.02, 0.035, 0.055, 0.08, 0.115, 0.16, 0.2)
TABLE = RESULTS / "flattening_limit_table.csv"
_SKIP = 2  # flank elements left out of the fit next to the edge (the smeared line)
STEP = 0.0005  # the curves' strain step (0.0005 and 0.0001 agree to 8e-4 in alpha; 0.0025: 0.017)
TIME_LIMIT = 120.0  # s a state may take (the published table's slowest: 28 s); then it is filled


#: the table's meshes (nx, nz, yield polygon's sides): above and below 0.15 H (:func:`mesh_of`)
MESH, LOW_MESH = (12, 16, 48), (16, 24, 48)


def collapse_fraction(ph):
    """The table's smallest ``A`` at ``p / H``: ``1.01 p / H``, just above the plateau at the
    hardness ``H`` (:func:`a_grid`)."""
    return 1.01 * ph


def a_grid(ph, grid=A_GRID):
    """The table's ``A`` at ``p / H``: from just above ``p / H`` (the plateau at the hardness
    ``H``, where pressing alone collapses the asperity and the rates grow without bound: the
    truth's pressing-alone fractions are 1.02-1.29 ``p / H``), denser there, then ``grid``."""
    a0 = collapse_fraction(ph)
    near = [a0 * f for f in (1.0, 1.03, 1.1, 1.25)]
    return tuple(near + [A for A in grid if A > 1.35 * a0])


def n_flank(A, nx):
    """The flank's columns: its share of ``nx``, at least half and at least 2 + 3 for the fit."""
    return min(nx - 1, max(round(nx * (1.0 - A)), nx // 2, _SKIP + 3))


def _flank_weights(x, A, he):
    """Weights of the free top's nodes (at ``x``) that give the flank line's value at the edge
    and its slope: least squares over the flank beyond its first ``_SKIP`` elements."""
    flank = x > A + _SKIP * he - 1e-9
    xi = x - A
    xb = xi[flank].mean()
    slope = np.where(flank, xi - xb, 0.0) / ((xi[flank] - xb) ** 2).sum()
    return np.where(flank, 1.0 / flank.sum(), 0.0) - xb * slope, slope


def flank_rates(f, A, s):
    """``(dA / d eps, ds / d eps)`` of a solved field ``f`` (:func:`flattening_limit.limit_field`)
    at state (``A``, ``s``), from the lines fitted to its flank (module text)."""
    x, u, w = f["surface"].T
    edge, slope = _flank_weights(x, A, f["flank_element"])
    return (edge @ w - f["W"]) / s + edge @ u - A, -(slope @ w + s * (slope @ u))


def rates(p_over_H, A, s, nx, nz, sides):
    """``dA / d eps`` and ``ds / d eps`` of the state from the optimum's flank; the edge readings."""
    f = limit_field(p_over_H * H, A, s, nx, nz, sides, n_flank(A, nx), time_limit=TIME_LIMIT)
    dA, ds = flank_rates(f, A, s)
    return {
        "dA_de": dA,
        "ds_de": ds,
        "dA_de_1": f["dA_de_1"],
        "dA_de_2": f["dA_de_2"],
        "dissipation_ratio": f["dissipation_ratio"],
        "seconds": f["seconds"],
    }


def band(p_over_H, A, s, nx, nz, sides, delta):
    """Both rates at the optimum (as linear functionals of its solution, the weights of
    ``rates``) and their range over the fields that dissipate at most ``delta`` times the uniform
    stretch's ``2 k`` per area more than the optimum (less the pressure's work): how sharply the
    rigid-plastic problem decides them. Four more programmes, the optimum's cost a new row."""
    f = limit_field(p_over_H * H, A, s, nx, nz, sides, n_flank(A, nx), time_limit=TIME_LIMIT)
    lp, x = f["program"], f["x"]
    n, idx = lp["n"], lp["idx"]
    edge, slope = _flank_weights(f["surface"][:, 0], A, f["flank_element"])
    f_A, f_s = np.zeros(len(x)), np.zeros(len(x))
    f_A[n + idx], f_A[idx], f_A[2 * n] = edge / s, edge, -1.0 / s  # dA/d eps + A
    f_s[n + idx], f_s[idx] = -slope, -s * slope
    cap = sp.csr_matrix(lp["cost"][None, :]), [lp["cost"] @ x + delta * 2 * lp["area"].sum()]
    lo_hi = [solve(lp, sign * g, TIME_LIMIT, *cap).x @ g for g in (f_A, f_s) for sign in (1, -1)]
    return {
        "dA_de": f_A @ x - A,
        "dA_de_lo": lo_hi[0] - A,
        "dA_de_hi": lo_hi[1] - A,
        "ds_de": f_s @ x,
        "ds_de_lo": lo_hi[2],
        "ds_de_hi": lo_hi[3],
        "dissipation_ratio": f["dissipation_ratio"],
    }


def _row(job):
    ph, A, s, mesh = job
    try:
        r = rates(ph, A, s, *mesh)
    except RuntimeError as exc:  # HiGHS's failure at a state: recorded, filled from its neighbours
        r = dict.fromkeys(("dA_de", "ds_de", "dA_de_1", "dA_de_2", "dissipation_ratio"), math.nan)
        r["seconds"] = math.nan
        print(f"p/H {ph:g}, A {A:.4g}, s {s:g}: {exc}", flush=True)
    return {
        "p_over_H": ph,
        "A": round(A, 6),
        "s": s,
        **{k: round(float(v), 6) for k, v in r.items()},
    }


def mesh_of(ph, mesh, low_mesh):
    """The table's mesh at ``p / H``: ``low_mesh`` below 0.15 H (``--converge``: 12 x 16 is not
    converged there; ``--polygon``: the flat optimum needs 48 sides), ``mesh`` above (it is, to
    0.035 in ``c``; from 12 to 48 sides ``c`` moves by at most 0.11 there)."""
    return tuple(low_mesh if ph < 0.15 else mesh)


def _read(path):
    """Table rows from a CSV: the mesh as written, every other column a float."""
    with open(path, encoding="utf-8") as fh:
        return [
            {k: (v if k == "mesh" else float(v)) for k, v in r.items()} for r in csv.DictReader(fh)
        ]


def table(mesh, low_mesh, fresh, pressures=PRESSURES, path=TABLE, grid_a=A_GRID, workers=2):
    """The rates on the grid at ``pressures`` (cached in ``path``): the cached states computed on
    these meshes are kept, the grid's other states computed (all of them with ``fresh``)."""
    tag = {ph: "x".join(map(str, mesh_of(ph, mesh, low_mesh))) for ph in pressures}
    grid = {  # a state's key as the CSV holds it: its job
        (tag[ph], ph, round(A, 6), s): (ph, A, s, mesh_of(ph, mesh, low_mesh))
        for ph in pressures
        for A in a_grid(ph, grid_a)
        for s in S_GRID
    }
    partial = path.with_suffix(".partial.csv")  # rows so far: a stopped run resumes from them
    done = {}
    for src in (path, partial):
        if src.exists() and not fresh:
            for r in _read(src):
                key = (r["mesh"], r["p_over_H"], r["A"], r["s"])
                if key in grid:  # computed on the asked mesh, on the grid
                    done[key] = r
    todo = [job for key, job in grid.items() if key not in done]
    if not todo:
        return sorted(done.values(), key=lambda r: (r["p_over_H"], r["A"], r["s"]))
    os.environ["OMP_NUM_THREADS"] = "1"
    rows = list(done.values())
    with multiprocessing.get_context("spawn").Pool(workers) as pool:
        for k, r in enumerate(pool.imap(_row, todo, chunksize=1)):
            rows.append({"mesh": tag[r["p_over_H"]], **r})
            write_rows(partial, rows)
            if k % 20 == 0:
                print(f"{k + 1} / {len(todo)}: {rows[-1]}", flush=True)
    rows.sort(key=lambda r: (r["p_over_H"], r["A"], r["s"]))
    write_rows(path, rows)
    partial.unlink()
    return rows


def _fill(t, a):
    """A state where HiGHS failed (NaN) takes its neighbours' values along ``A`` at its ``s``."""
    t = t.copy()
    for j in range(t.shape[1]):
        ok = np.isfinite(t[:, j])
        if not ok.all():
            t[~ok, j] = np.interp(a[~ok], a[ok], t[ok, j])
    return t


class Rates:
    """Bilinear interpolation of the table at one pressure, in ``A`` and ``ln s`` (clamped), on
    the flank slopes ``s_grid`` (the table's, or fewer: below its smallest the rates are held)."""

    def __init__(self, rows, ph, s_grid=S_GRID):
        mine = [r for r in rows if r["p_over_H"] == ph]
        self.a = np.array(sorted({r["A"] for r in mine}))
        self.ls = np.log(s_grid)
        grid = {(r["A"], r["s"]): r for r in mine}
        self.dA, self.ds = (
            _fill(np.array([[grid[(A, s)][key] for s in s_grid] for A in self.a]), self.a)
            for key in ("dA_de", "ds_de")
        )

    def __call__(self, A, s):
        i = int(np.clip(np.searchsorted(self.a, A) - 1, 0, len(self.a) - 2))
        j = int(np.clip(np.searchsorted(self.ls, math.log(s)) - 1, 0, len(self.ls) - 2))
        ta = float(np.clip((A - self.a[i]) / (self.a[i + 1] - self.a[i]), 0.0, 1.0))
        ts = float(np.clip((math.log(s) - self.ls[j]) / (self.ls[j + 1] - self.ls[j]), 0.0, 1.0))

        def lerp(t):
            return (1 - ta) * ((1 - ts) * t[i, j] + ts * t[i, j + 1]) + ta * (
                (1 - ts) * t[i + 1, j] + ts * t[i + 1, j + 1]
            )

        return lerp(self.dA), lerp(self.ds)


CONVERGE = (  # (wedge deg, p/H, A, s / tan(theta)): states of flattening_flank.csv
    (10.0, 0.05, 0.1687, 0.9023),
    (10.0, 0.05, 0.3038, 0.7686),
    (3.0, 0.05, 0.4874, 0.8238),
    (10.0, 0.15, 0.3981, 0.9915),
    (10.0, 0.3, 0.5396, 1.0493),
)
MESHES = ((12, 16, 12), (16, 24, 16), (24, 32, 16))


def converge(meshes):
    """``--converge``: the readings at a few of the truth's states against the mesh."""
    rows = []
    for deg, ph, A, ratio in CONVERGE:
        t0 = math.tan(math.radians(deg))
        for mesh in meshes:
            r = rates(ph, A, ratio * t0, *mesh)
            rows.append(
                {
                    "slope_deg": deg,
                    "p_over_H": ph,
                    "alpha": A,
                    "slope_ratio": ratio,
                    "mesh": "x".join(map(str, mesh)),
                    "c_fit": round(t0 * r["dA_de"], 3),
                    "dln_s_de": round(r["ds_de"] / (ratio * t0), 2),
                    "c_edge_1": round(t0 * r["dA_de_1"], 3),
                    "c_edge_2": round(t0 * r["dA_de_2"], 3),
                    "dissipation_ratio": round(r["dissipation_ratio"], 4),
                    "seconds": round(r["seconds"], 1),
                }
            )
            print(rows[-1], flush=True)
    return rows


SIDES = (12, 24, 48)
BAND_SIDES = 48  # the table's polygon below 0.15 H
BAND = 1e-4  # the band's dissipation above the optimum, of the uniform stretch's


def polygon(nx, nz):
    """``--polygon``: the readings at the converge states against the yield polygon's sides, and
    the band of both rates within ``BAND`` of the optimum on the table's polygon (48 sides).

    The polygon is inscribed in von Mises' circle: it takes up to ``1 - cos(pi / sides)`` off
    the dissipation of a strain rate between its directions (3.4 % at 12 sides, 0.2 % at 48)."""
    rows = []
    for deg, ph, A, ratio in CONVERGE:
        t0 = math.tan(math.radians(deg))
        s = ratio * t0
        for sides in SIDES:
            spread = dict.fromkeys(("c_lo", "c_hi", "dln_s_lo", "dln_s_hi"), math.nan)
            if sides == BAND_SIDES:  # the band's optimum gives the readings too: one solve
                r = band(ph, A, s, nx, nz, sides, BAND)
                spread = {
                    "c_lo": round(t0 * r["dA_de_lo"], 3),
                    "c_hi": round(t0 * r["dA_de_hi"], 3),
                    "dln_s_lo": round(r["ds_de_lo"] / s, 2),
                    "dln_s_hi": round(r["ds_de_hi"] / s, 2),
                }
            else:
                r = rates(ph, A, s, nx, nz, sides)
            rows.append(
                {
                    "slope_deg": deg,
                    "p_over_H": ph,
                    "alpha": A,
                    "slope_ratio": ratio,
                    "sides": sides,
                    "c_fit": round(t0 * r["dA_de"], 3),
                    "dln_s_de": round(r["ds_de"] / s, 2),
                    "dissipation_ratio": round(r["dissipation_ratio"], 5),
                    **spread,
                }
            )
            print(rows[-1], flush=True)
    return rows


def compare(rows):
    """The table's curves beside the truth's 30 and the runtime's law (``flattening_truth.csv``).

    The measured row enters as a wedge of its RMS slope, as the runtime's law takes it."""
    with open(RESULTS / "flattening_truth.csv", encoding="utf-8") as fh:
        truth = list(csv.DictReader(fh))
    profiles = sorted({(r["profile"], float(r["slope_deg"])) for r in truth}, key=lambda k: k[1])
    out = []
    for ph in PRESSURES:
        rate = Rates(rows, ph)
        for name, deg in profiles:
            pts = sorted(
                (float(r["strain"]), float(r["alpha_truth"]), float(r["alpha_law"]))
                for r in truth
                if r["profile"] == name and float(r["p_over_H"]) == ph
            )
            strains = [e for e, _, _ in pts]
            alpha = curve(rate, pts[0][1], math.tan(math.radians(deg)), strains, STEP)
            out += [
                {
                    "profile": name,
                    "slope_deg": deg,
                    "p_over_H": ph,
                    "strain": e,
                    "alpha_truth": at,
                    "alpha_limit": round(a, 4),
                    "slope_ratio_limit": round(sl / math.tan(math.radians(deg)), 4),
                    "alpha_law": round(al, 4),
                }
                for (e, at, al), (a, sl) in zip(pts, alpha, strict=True)
            ]
    return out


def summary(out):
    """Largest misses per pressure band and overall, for the table and the runtime's law."""
    lines = ["| p/H | largest miss: limit-analysis law | runtime's law (L+E) |", "|---|---|---|"]
    for ph in (*PRESSURES, None):
        sel = [r for r in out if ph is None or r["p_over_H"] == ph]
        m1 = max(abs(r["alpha_limit"] - r["alpha_truth"]) for r in sel)
        m2 = max(abs(r["alpha_law"] - r["alpha_truth"]) for r in sel)
        lines.append(f"| {'all' if ph is None else f'{ph:g}'} | {m1:.3f} | {m2:.3f} |")
    rms1 = math.sqrt(np.mean([(r["alpha_limit"] - r["alpha_truth"]) ** 2 for r in out]))
    rms2 = math.sqrt(np.mean([(r["alpha_law"] - r["alpha_truth"]) ** 2 for r in out]))
    keys = sorted({(r["profile"], r["p_over_H"]) for r in out})
    worst = {
        k: [
            max(abs(r[c] - r["alpha_truth"]) for r in out if (r["profile"], r["p_over_H"]) == k)
            for c in ("alpha_limit", "alpha_law")
        ]
        for k in keys
    }
    within = [sum(w[i] <= 0.05 for w in worst.values()) for i in (0, 1)]
    lines.append("")
    lines.append(
        f"RMS {rms1:.3f} (the runtime's law {rms2:.3f}); curves within 0.05: {within[0]} of "
        f"{len(keys)} ({within[1]})."
    )
    lines += [
        "",
        "| profile | p/H | largest miss: limit-analysis law | runtime's law |",
        "|---|---|---|---|",
    ]
    lines += [f"| {k[0]} | {k[1]:g} | {w[0]:.3f} | {w[1]:.3f} |" for k, w in worst.items()]
    return lines


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--mesh", nargs=3, type=int, default=MESH, help="nx nz sides (default 12 16 48)"
    )
    ap.add_argument(
        "--low-mesh",
        nargs=3,
        type=int,
        default=LOW_MESH,
        help="nx nz sides below 0.15 H (default 16 24 48)",
    )
    ap.add_argument("--converge", action="store_true", help="the readings against the mesh")
    ap.add_argument(
        "--polygon",
        action="store_true",
        help="the readings against the yield polygon's sides, and their band, on 16 x 24",
    )
    ap.add_argument("--fresh", action="store_true", help="recompute the cached table")
    return ap.parse_args()


def main(args):
    if args.converge:
        rows = converge(MESHES)
        write_rows(RESULTS / "flattening_limit_converge.csv", rows)
        lines = [
            "# The limit analysis's flank reading against the mesh",
            "",
            "`benchmarks/flattening_limit_law.py --converge`: at states of the truth "
            "(`flattening_flank.csv`), `c = tan(theta) dA / d eps` from the flank's fitted field "
            "(the law's reading) and one / two elements beyond the edge (`flattening_limit.py`'s), "
            "and the flank's turn `d ln s / d eps`; mesh nx x nz x the yield polygon's sides.",
            "",
            "| wedge, p/H | alpha | slope / initial | mesh | c: flank fit | c: edge 1 / 2 "
            "| d ln s / d eps | dissipation / uniform | s |",
            "|---|---|---|---|---|---|---|---|---|",
        ]
        lines += [
            f"| {r['slope_deg']:g} deg, {r['p_over_H']:g} | {r['alpha']:.3f} | "
            f"{r['slope_ratio']:.3f} | {r['mesh']} | {r['c_fit']:.3f} | {r['c_edge_1']:.3f} / "
            f"{r['c_edge_2']:.3f} | {r['dln_s_de']:.2f} | {r['dissipation_ratio']:.4f} | "
            f"{r['seconds']:.0f} |"
            for r in rows
        ]
        (RESULTS / "flattening_limit_converge.md").write_text("\n".join(lines) + "\n", "utf-8")
        print("\n".join(lines))
        return
    if args.polygon:
        rows = polygon(16, 24)
        write_rows(RESULTS / "flattening_limit_polygon.csv", rows)
        lines = [
            "# The limit analysis's flank reading against the yield polygon",
            "",
            "`benchmarks/flattening_limit_law.py --polygon`: at the converge states, on 16 x 24 "
            "triangles, `c = tan(theta) dA / d eps` and `d ln s / d eps` from the flank's fitted "
            "field against the sides of the polygon that linearises von Mises' dissipation "
            "(inscribed: it takes up to `1 - cos(pi / sides)` off a strain rate between its "
            f"directions); at {BAND_SIDES} sides the range of both over every field that "
            f"dissipates at most {BAND:g} of the uniform stretch's more than the optimum.",
            "",
            "| wedge, p/H | alpha | slope / initial | sides | c | d ln s / d eps "
            "| dissipation / uniform | c: band | d ln s / d eps: band |",
            "|---|---|---|---|---|---|---|---|---|",
        ]
        lines += [
            f"| {r['slope_deg']:g} deg, {r['p_over_H']:g} | {r['alpha']:.3f} | "
            f"{r['slope_ratio']:.3f} | {r['sides']} | {r['c_fit']:.3f} | {r['dln_s_de']:.2f} | "
            f"{r['dissipation_ratio']:.5f} | "
            + (
                f"{r['c_lo']:.3f} to {r['c_hi']:.3f} | {r['dln_s_lo']:.2f} to {r['dln_s_hi']:.2f} |"
                if math.isfinite(r["c_lo"])
                else " | |"
            )
            for r in rows
        ]
        (RESULTS / "flattening_limit_polygon.md").write_text("\n".join(lines) + "\n", "utf-8")
        print("\n".join(lines))
        return
    rows = table(args.mesh, args.low_mesh, args.fresh)
    out = compare(rows)
    write_rows(RESULTS / "flattening_limit_law.csv", out)
    meshes = sorted({(r["p_over_H"], r["mesh"]) for r in rows})
    failed = sum(not math.isfinite(r["dA_de"]) for r in rows)
    lines = [
        "# The limit analysis as a law, against the FE asperity truth",
        "",
        "`benchmarks/flattening_limit_law.py`: the contact fraction and the flank's slope as two "
        "states, their rates from the rigid-plastic optimum's flank tabulated at "
        f"{len(rows)} states ({failed} where HiGHS gave no answer, filled along A), meshes "
        + ", ".join(f"{m} at {ph:g} H" for ph, m in meshes)
        + "; integrated from the truth's pressing-alone fraction and the profile's slope "
        "(`flattening_truth.csv`), nothing fitted; the runtime's law (L+E) beside it.",
        "",
        *summary(out),
    ]
    (RESULTS / "flattening_limit_law.md").write_text("\n".join(lines) + "\n", "utf-8")
    print("\n".join(lines))


if __name__ == "__main__":
    cli = parse_args()
    with run_record(
        __file__,
        "flattening_limit_converge"
        if cli.converge
        else "flattening_limit_polygon"
        if cli.polygon
        else "flattening_limit_law",
    ):
        main(cli)
