"""A rigid-plastic limit analysis of the truth's states (issue 43, a study of the mechanism).

The FE asperity truth (``asperity_flattening.py``) flattens its wedges by the slip-line lattice
of Eq. F2a at 0.1-0.3 H (a line from the plateau's edge, the flank block rigid) and by a turning
flank below (``flattening_flank.py --field``), with or without ten times its Young's modulus: the
choice is the rigid-plastic problem's. This script asks the rigid-perfectly plastic problem
directly, with nothing of the truth but its geometry: the instantaneous velocity field of the
half cell (peak to valley, half-spacing ``l = 1``, depth ``4 l``, symmetry planes at both ends,
the right one moving at the stretch rate 1, the bottom held vertically) under a flat frictionless
tool loaded by ``p`` on the plateau ``0 <= x <= A``, the flank straight at slope ``s`` down to the
valley. By the kinematic theorem the field minimises the dissipation less the pressure's work; it
is found as a linear programme (an upper-bound limit analysis: 6-node triangles with straight
sides, incompressibility at the vertices, which makes it exact in each element, von Mises' plane-
strain dissipation ``k sqrt((d_xx - d_zz)^2 + (2 d_xz)^2)`` linearised by a polygon of
``sides`` directions at each vertex and integrated by the vertices' mean, an upper bound of a
convex integrand; SciPy's HiGHS; ``k = 1``, ``H = (2 + pi) k``). The polygon is inscribed in the
circle: it takes up to ``1 - cos(pi / sides)`` off the dissipation of a strain rate between its
directions (3.4 % at 12 sides, 0.2 % at 48), so the programme is an upper bound only to that
tolerance, and where the optimum is flat (low pressure) that error picks the field.

Read off: the dissipation over the uniform stretch's ``2 k`` times the cell's area (below 1: the
asperity above the valleys is spared part of the stretch), the plateau's sinking beyond the
homogeneous flow, and the contact's growth ``dA / d eps = (w - W) / s + (u - x)`` at the first
flank nodes beyond the edge (the field is continuous: the lattice's line is smeared over an
element, so the rate is read one and two elements out), as ``c = tan(theta) dA / d eps`` beside the
truth's ``c_truth`` at the same state (``flattening_flank.csv``: its ``alpha`` and flank slope).
A check: with ``p = 0`` on a flat strip the uniform stretch is the minimum, ratio 1.

Run: python benchmarks/flattening_limit.py [--mesh NX NZ] [--sides N] [--cases 10:0.05,...]
[--strains 0.02,...] [--out STEM] [--integrate] (about 5 min at the default mesh; a 16 x 24 state about 2.5 min)
Writes benchmarks/results/flattening_limit.csv and .md (or STEM's).
"""

import argparse
import csv
import math
import time

import numpy as np
import scipy.sparse as sp
from _provenance import RESULTS, run_record, write_rows
from scipy.optimize import linprog

DEPTH = 4.0  # the cell's depth (l); the truth's strips of 4-16 l agree within 0.016
H = 2.0 + math.pi  # the hardness in units of k (k = 1): prandtl_hardness
STRAINS = (0.01, 0.02, 0.03, 0.05)
_EDGES = ((0, 1), (1, 2), (2, 0))


def cell(A, s, nx, nz, n_flank=None, top_of=None):
    """Vertices (graded to the top), 6-node triangles and the top's x of the half cell.

    The plateau takes ``round(nx A)`` of the ``nx`` columns, or ``nx - n_flank`` if ``n_flank``
    (the flank's columns) is given. ``top_of(x)``, when given, is the free flank's height below
    the tool (``<= 0``) at ``A < x <= 1`` instead of the straight ``-s (x - A)`` (a deformed
    flank: ``flattening_limit_geometry.py``).
    """
    if n_flank is not None:
        na = nx - n_flank
    else:
        na = max(1, round(nx * A)) if A > 0 else 0
    xs = np.r_[np.linspace(0.0, A, na + 1)[:-1], np.linspace(A, 1.0, nx - na + 1)]
    eta = 1.0 - (1.0 - np.linspace(0.0, 1.0, nz + 1)) ** 2
    flank = -s * (xs - A) if top_of is None else np.minimum(top_of(xs), 0.0)
    top = np.where(xs <= A, 0.0, flank)
    pts = np.empty((xs.size, nz + 1, 2))
    pts[..., 0] = xs[:, None]
    pts[..., 1] = -DEPTH + eta[None, :] * (DEPTH + top[:, None])
    vid = np.arange(pts.shape[0] * pts.shape[1]).reshape(pts.shape[:2])
    tris = []
    for i in range(xs.size - 1):
        for j in range(nz):
            q = vid[i, j], vid[i + 1, j], vid[i + 1, j + 1], vid[i, j + 1]
            alt = (i + j) % 2
            tris += [(q[0], q[1], q[3]), (q[1], q[2], q[3])] if alt else [q[:3], (q[0], q[2], q[3])]
    pts = pts.reshape(-1, 2)
    mids, six = {}, []
    for t in tris:
        m = []
        for i, j in _EDGES:
            key = (min(t[i], t[j]), max(t[i], t[j]))
            mids.setdefault(key, len(pts) + len(mids))
            m.append(mids[key])
        six.append([*t, *m])
    mid_xy = np.array([(pts[i] + pts[j]) / 2 for i, j in mids])
    return np.vstack([pts, mid_xy]), np.array(six), xs, top


def _gradients(x):
    """Each node's basis gradient at each vertex of a straight 6-node triangle, (3, 6, 2)."""
    J = np.array([x[1] - x[0], x[2] - x[0]]).T
    inv = np.linalg.inv(J)
    b = np.array([-inv[0] - inv[1], inv[0], inv[1]])
    g = np.zeros((3, 6, 2))
    for v in range(3):
        lam = np.eye(3)[v]
        g[v, :3] = (4 * lam - 1)[:, None] * b
        for m, (i, j) in enumerate(_EDGES):
            g[v, 3 + m] = 4 * (lam[j] * b[i] + lam[i] * b[j])
    return g, abs(np.linalg.det(J)) / 2


def program(p, A, s, nx=12, nz=16, sides=12, n_flank=None, unilateral=False, top_of=None):
    """The linear programme of the state: a dict of ``cost``, ``a_in``, ``a_eq``, ``bounds`` (both
    right-hand sides are zero), the mesh (``P``, ``xs``, ``n`` nodes, the triangles' ``area``) and
    the free top's node indices ``idx`` in x's order. The unknowns: u, w at the ``n`` nodes, the plateau's W, a bound
    per vertex. ``top_of``: a deformed flank (:func:`cell`)."""
    P, six, xs, top = cell(A, s, nx, nz, n_flank, top_of)
    n, ne = len(P), len(six)
    nv = 2 * n + 1 + 3 * ne  # u, w, the plateau's W, a bound t per vertex
    phi = np.linspace(0.0, 2 * math.pi, sides, endpoint=False)
    eq_r, eq_c, eq_v, in_r, in_c, in_v = [], [], [], [], [], []
    area = np.empty(ne)
    for e, t in enumerate(six):
        g, area[e] = _gradients(P[t[:3]])
        for v in range(3):
            row = 3 * e + v  # incompressibility: du/dx + dw/dz = 0 (linear: exact in the element)
            eq_r += [row] * 12
            eq_c += list(t) + [n + i for i in t]
            eq_v += list(g[v, :, 0]) + list(g[v, :, 1])
            for j, (c, sn) in enumerate(zip(np.cos(phi), np.sin(phi), strict=True)):
                r = (3 * e + v) * sides + j  # c (du/dx - dw/dz) + s (du/dz + dw/dx) <= t
                in_r += [r] * 13
                in_c += list(t) + [n + i for i in t] + [2 * n + 1 + 3 * e + v]
                in_v += list(c * g[v, :, 0] + sn * g[v, :, 1])
                in_v += list(-c * g[v, :, 1] + sn * g[v, :, 0]) + [-1.0]
    surface = np.abs(P[:, 1] - np.interp(P[:, 0], xs, top)) < 1e-9
    plate = np.flatnonzero(surface & (P[:, 0] <= A + 1e-9))
    row0, rin = 3 * ne, 3 * ne * sides
    # the tool is flat: the plateau sinks as one (w_i = W), or, unilateral, may sink away from
    # the tool but not into it (w_i <= W)
    rows, cols, vals, base = (in_r, in_c, in_v, rin) if unilateral else (eq_r, eq_c, eq_v, row0)
    for k, i in enumerate(plate):
        rows += [base + k] * 2
        cols += [n + i, 2 * n]
        vals += [1.0, -1.0]
    n_eq = row0 + (0 if unilateral else len(plate))
    a_eq = sp.csr_matrix((eq_v, (eq_r, eq_c)), shape=(n_eq, nv))
    a_in = sp.csr_matrix((in_v, (in_r, in_c)), shape=(rin + (len(plate) if unilateral else 0), nv))
    cost = np.zeros(nv)
    cost[2 * n + 1 :] = np.repeat(area / 3, 3)
    cost[2 * n] = p  # minus the pressure's work p l (-W), l = 1
    bounds = [(None, None)] * (2 * n + 1) + [(0, None)] * (3 * ne)
    for i, (x, z) in enumerate(P):
        if x < 1e-12:
            bounds[i] = (0, 0)
        elif x > 1 - 1e-12:
            bounds[i] = (1, 1)  # the stretch rate
        if z < -DEPTH + 1e-12:
            bounds[n + i] = (0, 0)
    idx = np.flatnonzero(surface)
    idx = idx[np.argsort(P[idx, 0])]
    return {
        "cost": cost,
        "a_in": a_in,
        "a_eq": a_eq,
        "bounds": bounds,
        "P": P,
        "xs": xs,
        "n": n,
        "area": area,
        "idx": idx,
    }


def solve(lp, cost, time_limit=None, a_in=None, b_in=None):
    """HiGHS's interior-point method on ``lp`` with ``cost`` (and extra rows ``a_in x <= b_in``)."""
    a, b = lp["a_in"], np.zeros(lp["a_in"].shape[0])
    if a_in is not None:
        a, b = sp.vstack([a, a_in]).tocsr(), np.r_[b, b_in]
    res = linprog(
        cost,
        a,
        b,
        lp["a_eq"],
        np.zeros(lp["a_eq"].shape[0]),
        lp["bounds"],
        method="highs-ipm",
        options={} if time_limit is None else {"time_limit": time_limit},
    )
    if res.status != 0:
        raise RuntimeError(f"the limit analysis did not solve: {res.message}")
    return res


def limit_field(
    p, A, s, nx=12, nz=16, sides=12, n_flank=None, unilateral=False, time_limit=None, top_of=None
):
    """The minimiser of dissipation less the pressure's work; a dict of what it shows.

    Besides the readings, ``surface`` holds the free top's nodes (x, u, w) in x's order, ``W``
    the plateau's vertical velocity, ``program`` the programme and ``x`` its solution. HiGHS's interior-point method with its crossover (the same
    optimum as the dual simplex to its tolerance, 5.7 times faster at 12 x 16). ``time_limit``
    (s) makes a state that HiGHS cannot finish an error instead of a stall. ``top_of``: a
    deformed flank (:func:`cell`); ``s`` is then the slope the edge readings divide by.
    """
    lp = program(p, A, s, nx, nz, sides, n_flank, unilateral, top_of)
    P, xs, n, area, idx = lp["P"], lp["xs"], lp["n"], lp["area"], lp["idx"]
    t0 = time.perf_counter()
    res = solve(lp, lp["cost"], time_limit)
    u, w, W = res.x[:n], res.x[n : 2 * n], res.x[2 * n]
    he = (1 - A) / np.count_nonzero(xs > A + 1e-12)
    rate = []
    for m in (1, 2):
        xe = A + m * he
        dw = np.interp(xe, P[idx, 0], w[idx]) - W
        du = np.interp(xe, P[idx, 0], u[idx]) - xe
        rate.append(dw / s + du if s > 0 else math.nan)
    dissipation = float(res.fun - p * W)
    return {
        "dissipation_ratio": dissipation / (2 * (area.sum())),
        "extra_sinking": -(W + DEPTH),
        "dA_de_1": rate[0],
        "dA_de_2": rate[1],
        "seconds": time.perf_counter() - t0,
        "surface": np.column_stack([P[idx, 0], u[idx], w[idx]]),
        "W": float(W),
        "flank_element": float(he),
        "program": lp,
        "x": res.x,
    }


def curve(rate, A0, s0, strains, step, slope_of=None, dA_max=None):
    """(``A``, ``s``) at ``strains`` by the explicit midpoint rule from (``A0``, ``s0``), ``rate``
    giving (``dA / d eps``, ``ds / d eps``); full contact ends it, ``s`` stays above 1e-3.
    Steps of ``step`` in strain, and where ``dA_max`` is given, short enough that ``A`` moves by
    at most about ``dA_max`` in one (a profile's edge slope varies on the scale of its samples).

    ``slope_of(A)``, when given, is a profile's own edge slope at contact fraction ``A``
    (:func:`flattening_limit_rows.edge_slope`; ``s0`` is then ignored): the state is then ``A``
    and the flank's turn ``r = s / slope_of(A)``, which the rate's ``d ln s / d eps`` turns
    (integrated in ``ln r``: the turn stays positive), and ``s = r slope_of(A)`` follows the
    profile as the contact grows. A constant ``slope_of`` is the wedge's curve."""
    shape = (lambda A: s0) if slope_of is None else slope_of

    def step_rates(A, q):  # q = ln r
        s = max(math.exp(q) * shape(A), 1e-3)
        dA, ds = rate(A, s)
        return dA, ds / s

    A, q, e, out = A0, 0.0, 0.0, []
    for target in strains:
        while e < target - 1e-12 and A < 1.0:
            dA, dq = step_rates(A, q)
            h = min(step, target - e)
            if dA_max is not None and dA > 0:
                h = min(h, dA_max / dA)
            Am, qm = min(A + 0.5 * h * dA, 1.0), q + 0.5 * h * dq
            dA, dq = step_rates(Am, qm)
            A, q, e = min(A + h * dA, 1.0), q + h * dq, e + h
        out.append((A, max(math.exp(q) * shape(A), 1e-3)))
    return out


INTEGRATE = ((10.0, 0.2), (10.0, 0.3))
REPORT = (0.005, 0.01, 0.02, 0.05)


def integrate(nx, nz, sides, step=0.005):
    """``--integrate``: alpha against strain from the limit analysis's rate, nothing fitted.

    From the truth's pressing-alone fraction (as the law starts from ``alpha1``), the flank kept
    at its initial slope (the truth's is rigid at these pressures, ``flattening_flank.md``), the
    explicit midpoint rule in steps of ``step`` with the rate the mean of the one- and
    two-element readings; beside the truth and the runtime's law (``flattening_truth.csv``).
    """
    with open(RESULTS / "flattening_truth.csv", encoding="utf-8") as fh:
        table = {
            (float(r["slope_deg"]), float(r["p_over_H"]), float(r["strain"])): r
            for r in csv.DictReader(fh)
            if r["profile"].startswith("wedge")
        }
    rows = []
    for deg, ph in INTEGRATE:
        s = math.tan(math.radians(deg))

        def rate(A, deg=deg, ph=ph, s=s):
            if A >= 0.999:
                return 0.0
            f = limit_field(ph * H, A, s, nx, nz, sides)
            return 0.5 * (f["dA_de_1"] + f["dA_de_2"])

        A0 = float(table[(deg, ph, 0.0)]["alpha_truth"])
        alphas = curve(lambda A, s: (rate(A), 0.0), A0, s, REPORT, step)
        for target, (A, _) in zip(REPORT, alphas, strict=True):
            r = table[(deg, ph, target)]
            rows.append(
                {
                    "slope_deg": deg,
                    "p_over_H": ph,
                    "strain": target,
                    "alpha_limit": round(A, 4),
                    "alpha_truth": float(r["alpha_truth"]),
                    "alpha_law": round(float(r["alpha_law"]), 4),
                }
            )
            print(rows[-1], flush=True)
    write_rows(RESULTS / "flattening_limit_integrated.csv", rows)
    lines = [
        "# alpha from the limit analysis's rate, nothing fitted",
        "",
        f"`benchmarks/flattening_limit.py --integrate`: {nx} x {nz} triangles, {sides} sides; from "
        "the truth's pressing-alone fraction, the flank at its initial slope, midpoint steps of "
        f"{0.005:g}; the truth and the runtime's law (L+E, `flattening_truth.csv`) beside it.",
        "",
        "| wedge, p/H | strain | alpha: limit analysis | truth | law |",
        "|---|---|---|---|---|",
    ]
    lines += [
        f"| {r['slope_deg']:g} deg, {r['p_over_H']:g} | {r['strain']:g} | {r['alpha_limit']:.3f} | "
        f"{r['alpha_truth']:.3f} | {r['alpha_law']:.3f} |"
        for r in rows
    ]
    (RESULTS / "flattening_limit_integrated.md").write_text("\n".join(lines) + "\n", "utf-8")
    print("\n".join(lines))


def parse_args():
    """The command line (parsed before the run record, which is named by the mode)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", nargs=2, type=int, default=(12, 16), help="nx nz (default 12 16)")
    ap.add_argument("--sides", type=int, default=12, help="the yield polygon's sides (default 12)")
    ap.add_argument(
        "--cases", default=None, help="only these 'deg:p/H' cases, comma-separated (default: all)"
    )
    ap.add_argument("--strains", default=None, help="only these strains, comma-separated")
    ap.add_argument("--out", default="flattening_limit", help="results' stem (default %(default)s)")
    ap.add_argument(
        "--integrate", action="store_true", help="alpha against strain on 10 deg at 0.2 and 0.3 H"
    )
    return ap.parse_args()


def main(args):
    if args.integrate:
        integrate(*args.mesh, args.sides)
        return
    only = {tuple(map(float, c.split(":"))) for c in args.cases.split(",")} if args.cases else None
    strains = tuple(map(float, args.strains.split(","))) if args.strains else STRAINS
    nx, nz = args.mesh
    check = limit_field(0.0, 0.0, 0.0, nx, nz, args.sides)
    rows = []
    with open(RESULTS / "flattening_flank.csv", encoding="utf-8") as fh:
        truth = [r for r in csv.DictReader(fh) if float(r["strain"]) in strains]
    if only is not None:
        truth = [r for r in truth if (float(r["slope_deg"]), float(r["p_over_H"])) in only]
    for r in truth:
        deg, ph, A = float(r["slope_deg"]), float(r["p_over_H"]), float(r["alpha"])
        t0 = math.tan(math.radians(deg))
        s = float(r["slope_ratio"]) * t0
        if A > 0.95 or not math.isfinite(s):
            continue
        f = limit_field(ph * H, A, s, nx, nz, args.sides)
        rows.append(
            {
                "slope_deg": deg,
                "p_over_H": ph,
                "strain": float(r["strain"]),
                "alpha": A,
                "slope_ratio": float(r["slope_ratio"]),
                "dissipation_ratio": round(f["dissipation_ratio"], 5),
                "extra_sinking": round(f["extra_sinking"], 3),
                "c_limit_1": round(t0 * f["dA_de_1"], 3),
                "c_limit_2": round(t0 * f["dA_de_2"], 3),
                "c_truth": float(r["c_truth"]),
                "c_lattice": float(r["c_lattice"]),
                "seconds": round(f["seconds"], 1),
            }
        )
        print(rows[-1], flush=True)
    write_rows(RESULTS / f"{args.out}.csv", rows)
    lines = [
        "# A rigid-plastic limit analysis of the truth's states",
        "",
        f"`benchmarks/flattening_limit.py`: the half cell of depth {DEPTH:g} l on {nx} x {nz} "
        f"6-node triangles, the yield polygon of {args.sides} sides; at each of the truth's states "
        "(`flattening_flank.csv`: its alpha and flank slope at the strain) the rigid-perfectly "
        "plastic field that minimises the dissipation less the pressure's work. `c = tan(theta) "
        "dA / d eps` read one / two elements beyond the contact edge, beside the truth's and the "
        "lattice's (Eq. F2a). Check: a flat strip stretched without pressure dissipates "
        f"{check['dissipation_ratio']:.6f} of the uniform stretch's 2 k per area (exact: 1).",
        "",
        "| wedge, p/H | strain | alpha | flank slope / initial | dissipation / uniform | "
        "plateau's extra sinking | c: limit analysis (1 / 2 el.) | c: truth | c: lattice |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['slope_deg']:g} deg, {r['p_over_H']:g} | {r['strain']:.2f} | {r['alpha']:.3f} | "
            f"{r['slope_ratio']:.3f} | {r['dissipation_ratio']:.4f} | {r['extra_sinking']:.2f} | "
            f"{r['c_limit_1']:.2f} / {r['c_limit_2']:.2f} | {r['c_truth']:.2f} | "
            f"{r['c_lattice']:.2f} |"
        )
    (RESULTS / f"{args.out}.md").write_text("\n".join(lines) + "\n", encoding="utf-8")
    print("\n".join(lines))


if __name__ == "__main__":
    cli = parse_args()
    stem = "flattening_limit_integrated" if cli.integrate else cli.out
    with run_record(__file__, stem):
        main(cli)
