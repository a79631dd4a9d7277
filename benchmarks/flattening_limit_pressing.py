"""The pressing's flank from the limit analysis (issue 43, a study of the mechanism).

``flattening_limit_pressed.py`` found that the two-state law started from the flank slope the
truth's pressing leaves (1.00 times the virgin slope at 0.05-0.1 ``H``, 1.03-1.04 at 0.2, 1.10-
1.14 at 0.3, 1.19-1.32 at 0.45, 1.17-1.37 at 0.6) meets the bar on every wedge at 0.1-0.6 ``H``,
and that no runtime has that slope. This script asks the rigid-perfectly plastic problem for it,
nothing of the truth but its geometry: the half cell of ``flattening_limit.py`` pressed without
stretch (its far symmetry plane held, ``u = 0``), the plateau sinking at the unit rate (``W =
-1``), the dissipation minimised: the pressing's collapse mechanism at the state ``(A, s)``, whose
flank lines (``flattening_limit_law.flank_rates``' reading, without the stretch's term) give the
contact's growth ``dA / d delta = (w_f - W) / s + u_f`` and the flank's turn ``ds / d delta``
per unit sinking, so that along the pressing ``d ln s / dA = (ds / d delta) / (s dA / d delta)``;
the collapse pressure on the plateau is the dissipation over ``A``.

Tabulated at ``A`` 0.05-0.7 and the wedges' slopes (3, 5, 7, 10 deg; 12 x 16 triangles, 48
sides, as the rate table above 0.15 ``H``), integrated from ``A = 0`` (below 0.05 the turn of
0.05) to the truth's pressing-alone fraction at each pressure: the pressed slope over the virgin
one, beside the truth's (``flattening_limit_pressed.csv``); then the two-state law's curves from
that slope against the truth's 24 wedge curves (the study's integrator and table, as
``flattening_limit_pressed.py``). Nothing fitted.

Then the same turn on the measured rows, through the runtime's two-state law
(``frictionlaw.flattening_limit.limit_update`` started from the pressed flank: ``alpha_f`` the pressing-alone
fraction, ``slope_f`` the turned edge slope): each row with its own edge-slope table, and the
scan's one block against the mean of the rows (``flattening_limit_rows.py``,
``flattening_limit_scan.py``), with and without the turn. Not adopted in the runtime: it
makes the rows given their own geometry too slow (docs/flattening_studies.md).

Writes ``results/flattening_limit_pressing.md`` / ``.csv`` and the table
``results/flattening_pressing_table.csv`` (reused; ``--fresh`` solves it again).

Run: python benchmarks/flattening_limit_pressing.py [--fresh] (about 6 min with two workers)
"""

import argparse
import math
import os
from concurrent.futures import ProcessPoolExecutor

import flattening_limit_scan as S
import numpy as np
from _provenance import RESULTS, read_rows, run_record, write_report, write_rows
from flattening_limit import curve, program, solve
from flattening_limit_law import PRESSURES, STEP, TABLE, Rates, _flank_weights, _read, n_flank
from flattening_limit_pressed import wedge_truth
from flattening_limit_rows import block_edges
from flattening_limit_scan import blocks, row_curves, scan_surface
from flattening_truth import curve_misses

import frictionlaw as fl
from frictionlaw._limit_table import edge_at
from frictionlaw.flattening_limit import limit_update

A_PRESS = (0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7)
SLOPES = (3.0, 5.0, 7.0, 10.0)
MESH = (12, 16, 48)
PRESS_TABLE = RESULTS / "flattening_pressing_table.csv"


def pressing(A, s, nx=MESH[0], nz=MESH[1], sides=MESH[2]):
    """The pressing's collapse mechanism at ``(A, s)``: ``(dA / d delta, ds / d delta, p_c / k)``
    per unit sinking of the plateau (module text)."""
    lp = program(0.0, A, s, nx, nz, sides, n_flank(A, nx))
    n, P = lp["n"], lp["P"]
    bounds = list(lp["bounds"])
    for i, (x, _) in enumerate(P):
        if x > 1 - 1e-12:
            bounds[i] = (0, 0)  # no stretch: the far symmetry plane held
    bounds[2 * n] = (-1.0, -1.0)  # the plateau sinks at the unit rate
    lp = {**lp, "bounds": bounds}
    res = solve(lp, lp["cost"], 300.0)
    u, w, W = res.x[:n], res.x[n : 2 * n], res.x[2 * n]
    idx = lp["idx"]
    he = (1 - A) / np.count_nonzero(lp["xs"] > A + 1e-12)
    edge, slope = _flank_weights(P[idx, 0], A, he)
    dA = (edge @ w[idx] - W) / s + edge @ u[idx]
    ds = -(slope @ w[idx] + s * (slope @ u[idx]))
    return float(dA), float(ds), float(res.fun / A)


def _job(args):
    A, deg = args
    s = math.tan(math.radians(deg))
    dA, ds, pc = pressing(A, s)
    return {"A": A, "slope_deg": deg, "dA_dd": dA, "ds_dd": ds, "dlns_dA": ds / (s * dA),
            "p_collapse_over_k": pc}  # fmt: skip


def table(fresh=False, workers=2):
    """The pressing's turn ``d ln s / dA`` on ``A_PRESS`` x ``SLOPES`` (cached)."""
    if PRESS_TABLE.exists() and not fresh:
        return [{k: float(v) for k, v in r.items()} for r in read_rows(PRESS_TABLE)]
    jobs = [(A, d) for d in SLOPES for A in A_PRESS]
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    with ProcessPoolExecutor(workers) as ex:
        rows = list(ex.map(_job, jobs))
    write_rows(PRESS_TABLE, rows)
    return rows


class Turn:
    """``d ln s / dA`` along the pressing: bilinear in ``A`` and ``ln s``, clamped."""

    def __init__(self, rows):
        self.a = np.array(A_PRESS)
        self.ls = np.log(np.tan(np.radians(SLOPES)))
        g = {(r["A"], r["slope_deg"]): r["dlns_dA"] for r in rows}
        self.g = np.array([[g[(A, d)] for d in SLOPES] for A in A_PRESS])

    def __call__(self, A, s):
        i = int(np.clip(np.searchsorted(self.a, A) - 1, 0, len(self.a) - 2))
        j = int(np.clip(np.searchsorted(self.ls, math.log(s)) - 1, 0, len(self.ls) - 2))
        ta = float(np.clip((A - self.a[i]) / (self.a[i + 1] - self.a[i]), 0.0, 1.0))
        ts = float(np.clip((math.log(s) - self.ls[j]) / (self.ls[j + 1] - self.ls[j]), 0.0, 1.0))
        g = self.g
        return (1 - ta) * ((1 - ts) * g[i, j] + ts * g[i, j + 1]) + ta * (
            (1 - ts) * g[i + 1, j] + ts * g[i + 1, j + 1]
        )

    def ratio(self, A_end, s0, dA=0.005):
        """The pressed slope over ``s0`` after pressing from ``A = 0`` to ``A_end`` (midpoint
        rule in ``A``, steps of ``dA``)."""
        q, A = 0.0, 0.0
        while A < A_end - 1e-12:
            h = min(dA, A_end - A)
            qm = q + 0.5 * h * self(A, s0 * math.exp(q))
            q += h * self(A + 0.5 * h, s0 * math.exp(qm))
            A += h
        return math.exp(q)


def compare(turn, rows):
    """The truth's 24 wedge curves: the law from the virgin slope, the truth's pressed slope and
    the limit analysis's pressed slope."""
    truth = read_rows(RESULTS / "flattening_truth.csv")
    measured = {
        (float(r["slope_deg"]), float(r["p_over_H"])): float(r["pressed_slope_ratio"])
        for r in read_rows(RESULTS / "flattening_limit_pressed.csv")
    }
    out = []
    for ph in PRESSURES:
        rate = Rates(rows, ph)
        for deg in SLOPES:
            pts = wedge_truth(truth, deg, ph)
            strains = [e for e, _ in pts]
            t = math.tan(math.radians(deg))
            a0 = pts[0][1]
            ratio = turn.ratio(a0, t)
            virgin = curve(rate, a0, t, strains, STEP)
            limit = curve(rate, a0, ratio * t, strains, STEP)
            true_p = curve(rate, a0, measured[(deg, ph)] * t, strains, STEP)
            out += [
                {
                    "slope_deg": deg,
                    "p_over_H": ph,
                    "alpha0": a0,
                    "ratio_truth": measured[(deg, ph)],
                    "ratio_limit": round(ratio, 4),
                    "strain": e,
                    "alpha_truth": at,
                    "alpha_virgin": round(v[0], 4),
                    "alpha_pressed_truth": round(q[0], 4),
                    "alpha_pressed_limit": round(m[0], 4),
                }
                for (e, at), v, q, m in zip(pts, virgin, true_p, limit, strict=True)
            ]
    return out


COLS = ("alpha_virgin", "alpha_pressed_truth", "alpha_pressed_limit")


def summary(out):
    lines = [
        "| p/H | pressed slope / virgin (3, 5, 7, 10 deg): truth | limit analysis | largest miss: "
        "virgin | truth's pressed slope | limit analysis's | within 0.05 (of 4): virgin / truth's "
        "/ limit analysis's |",
        "|---|---|---|---|---|---|---|",
    ]
    for ph in (*PRESSURES, None):
        sel = [r for r in out if ph is None or r["p_over_H"] == ph]
        m = {c: curve_misses(sel, c, ("slope_deg", "p_over_H")) for c in COLS}
        rt = rl = ""
        if ph is not None:
            first = {r["slope_deg"]: r for r in sel}
            rt = ", ".join(f"{first[d]['ratio_truth']:.2f}" for d in SLOPES)
            rl = ", ".join(f"{first[d]['ratio_limit']:.2f}" for d in SLOPES)
        lines.append(
            f"| {'all' if ph is None else f'{ph:g}'} | {rt} | {rl} | "
            + " | ".join(f"{m[c][0]:.3f}" for c in COLS)
            + " | "
            + " / ".join(str(m[c][2]) for c in COLS)
            + " |"
        )
    rms = {c: curve_misses(out, c, ("slope_deg", "p_over_H"))[1] for c in COLS}
    lines += ["", "RMS: " + ", ".join(f"{c} {v:.3f}" for c, v in rms.items()) + "."]
    return lines


def _pressed_curve(turn, P, p, eps):
    """The runtime's two-state curve at ``p`` from the pressed flank: the pressing-alone
    fraction ``alpha1(p)`` and the flank turned by :class:`Turn` to it (read at the block's
    slope), then ``limit_update`` over each strain (the edge table, if any, as the runtime
    reads it: the turn ``r = slope_f / E(alpha_f)``)."""
    f = P.flattening
    a0 = float(fl.alpha_first(p, P))
    base = float(edge_at(np.array(f.edge_slope), a0)) if f.edge_slope else f.slope
    n = len(eps)
    a, _ = limit_update(
        np.full(n, a0), np.full(n, turn.ratio(a0, f.slope) * base), np.zeros(n),
        np.full(n, p), np.asarray(eps, dtype=float), P,
    )  # fmt: skip
    return np.maximum(a, a0)


def rows_compare(turn):
    """Rows with their own edge table, and the scan's blocks, with and without the turn."""
    scan = blocks(scan_surface())

    def at(law, x, z, p, eps):
        own = fl.Flattening(
            law.flattening.slope, model="limit-analysis", edge_slope=block_edges(x, z)
        )
        got = {}
        for k, f in {"own": own, "scan": scan["edge_slope"]}.items():
            Pk = law.replace(flattening=f)
            got[k] = fl.flattening_curve(p, eps, Pk)
            got[k + "_pressed"] = _pressed_curve(turn, Pk, p, eps)
        return got

    return row_curves(at)


def rows_summary(out):
    def row_miss(sel, c):
        return S._row_misses(sel, c)

    lines = [
        "## The measured rows (the runtime's two-state law with edge-slope tables)",
        "",
        "| rows | own table | own table, pressed flank | scan's table | scan's table, pressed |",
        "|---|---|---|---|---|",
    ]
    cols = ("alpha_own", "alpha_own_pressed", "alpha_scan", "alpha_scan_pressed")
    for label, sel in (
        ("of --rows (64, 128, 192)", [r for r in out if not r["held_out"]]),
        ("held out (32, 96, 160, 224)", [r for r in out if r["held_out"]]),
        ("all", out),
    ):
        lines.append(f"| {label} | " + " | ".join(row_miss(sel, c) for c in cols) + " |")
    saved = S.BLOCKS
    S.BLOCKS = ("scan", "scan_pressed")
    means = S.surface_means(out)
    S.BLOCKS = saved
    lines += [
        "",
        "The surface (mean over the rows at each pressure), the scan's table: largest miss "
        "without / with the pressed flank:",
        "",
        "| p/H | rows | without | with |",
        "|---|---|---|---|",
    ]
    worst = {"scan": [], "scan_pressed": []}
    for ph, (n, _, truth, law) in means.items():
        d = {k: np.abs(law[k] - truth) for k in worst}
        for k in worst:
            worst[k].append(d[k])
        lines.append(f"| {ph:g} | {n} | {d['scan'].max():.3f} | {d['scan_pressed'].max():.3f} |")
    lines.append(
        "| all | | "
        + " | ".join(
            f"{np.concatenate(worst[k]).max():.3f} (RMS "
            f"{math.sqrt(np.mean(np.concatenate(worst[k]) ** 2)):.3f})"
            for k in worst
        )
        + " |"
    )
    return lines


def main(fresh=False):
    rows = table(fresh)
    turn = Turn(rows)
    out = compare(turn, _read(TABLE))
    lines = [
        "# The pressing's flank from the limit analysis",
        "",
        "`benchmarks/flattening_limit_pressing.py`: the pressing's collapse mechanism of the "
        "wedge cell (no stretch, the plateau sinking; 12 x 16 triangles, 48 sides) gives the "
        "flank's turn along the pressing, `d ln s / dA`; integrated from `A = 0` to the truth's "
        "pressing-alone fraction it gives the pressed slope. Beside it the truth's own pressed "
        "slope (`flattening_limit_pressed.csv`) and the two-state law's curves (the study's table) "
        "from the virgin, the truth's and the limit analysis's pressed slope. Nothing fitted.",
        "",
        "The turn `d ln s / dA` (rows `A`, columns 3, 5, 7, 10 deg):",
        "",
        "| A | " + " | ".join(f"{d:g} deg" for d in SLOPES) + " |",
        "|---|" + "---|" * len(SLOPES),
        *(
            f"| {A:g} | " + " | ".join(f"{turn.g[i, j]:.3f}" for j in range(len(SLOPES))) + " |"
            for i, A in enumerate(A_PRESS)
        ),
        "",
        *summary(out),
        "",
        *rows_summary(rows_compare(turn)),
    ]
    write_report("flattening_limit_pressing", out, lines)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fresh", action="store_true", help="solve the pressing table again")
    cli = ap.parse_args()
    with run_record(__file__):
        main(cli.fresh)
