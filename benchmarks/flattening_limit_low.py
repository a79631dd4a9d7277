"""The two-state law below its table: 0.02 H against the truth there (issue 43, a study).

``flattening_limit_law.py`` tabulates the rigid-plastic optimum's rates at the truth's six
pressures, 0.05-0.6 H. ``asperity_low.py`` ran the FE truth at 0.02 H, where the runtime's law
is too fast by up to 0.64. This script tabulates the same rates at 0.02 H (the table's low mesh,
16 x 24 triangles and 48 sides; ``A`` from the collapse at ``1.01 p / H`` up to 0.96, with 0.035,
0.05 and 0.07 added below 0.1, where the truth's contact stays at this pressure) and integrates
them from each truth's own pressing-alone fraction, as ``flattening_limit_law.py`` does: the
wedges by their slope, the measured row as a wedge of its RMS slope and by its own edge slope
(``flattening_limit_rows.py``). Nothing is fitted. The runtime's law beside them (its ``alpha1``
the truth's pressing-alone fractions, as ``flattening_truth.py``'s section "Below the table").

The table also holds 0.035 and 0.07 H (``BETWEEN_PRESSURES``, no truth there), for
``flattening_limit_pressure.py`` to read 0.05 and 0.1 H from closer neighbours, and for the
runtime's shipped table (``flattening_limit_ship.py``). It is cached in
``results/flattening_limit_table_low.csv`` (a stopped run resumes from its partial file); the
comparison is ``results/flattening_limit_low.md`` / ``.csv``.

Run: python benchmarks/flattening_limit_low.py [--workers N]
"""

import argparse
import math

import numpy as np
from _provenance import RESULTS, run_record, write_report
from asperity_flattening import measured_profile
from flattening_limit import curve
from flattening_limit_law import (
    A_GRID,
    LOW_MESH,
    MESH,
    STEP,
    Rates,
    table,
)
from flattening_limit_rows import DA_MAX, edge_slopes
from flattening_truth import law_strain, low_curves, low_law, read_truth

import frictionlaw as fl

LOW_PRESSURES = (0.02,)  # below the table: the truth of asperity_low.py
#: the low table's pressures without a truth: between 0.02 and 0.1 H, so that the table read
#: between pressures (flattening_limit_pressure.py) can hold 0.05 and 0.1 H out from closer
#: neighbours, and the runtime's table has pressures about 1.5 times apart below 0.1 H
BETWEEN_PRESSURES = (0.035, 0.07)
LOW_A_GRID = (0.035, 0.05, 0.07)  # between the collapse and A_GRID's 0.1
LOW_TABLE = RESULTS / "flattening_limit_table_low.csv"
LOW_TRUTH = RESULTS / "asperity_low.csv"
REPORT = (0.005, 0.01, 0.02, 0.05, 0.1, 0.2)


def compare(rows):
    """Each of the low truth's curves (profile, mesh) beside the two-state law's and the
    runtime's, at the truth's strains."""
    table_truth, H = read_truth(RESULTS / "asperity_flattening.csv")
    shape, rates = None, {}  # the measured row's edge slope and each pressure's rates, once
    out = []
    for name, deg, ph, nx, nz, col in low_curves(LOW_TRUTH):
        strains = sorted(col)
        if ph not in rates:
            rates[ph] = Rates(rows, ph)
        rate = rates[ph]
        a0 = col[0.0]
        wedge = curve(rate, a0, math.tan(math.radians(deg)), strains, STEP)
        if name.startswith("matrix-3"):
            if shape is None:
                shape = edge_slopes(*measured_profile()[:2])
            edges = curve(rate, a0, None, strains, STEP, slope_of=shape, dA_max=DA_MAX)
        else:
            edges = [(math.nan, math.nan)] * len(strains)
        law = low_law(table_truth, H, name, deg, ph, col)
        runtime = fl.flattening_curve(ph * H, law_strain(strains), law)
        out += [
            {
                "profile": name,
                "slope_deg": deg,
                "p_over_H": ph,
                "mesh": f"{nx}x{nz}",
                "strain": e,
                "alpha_truth": col[e],
                "alpha_limit": round(w[0], 4),
                "alpha_edges": round(g[0], 4) if math.isfinite(g[0]) else "",
                "alpha_law": round(float(a), 4),
            }
            for e, w, g, a in zip(strains, wedge, edges, runtime, strict=True)
        ]
    return out


def _signed(rows, col):
    """The miss of largest magnitude in ``col``, with its sign, and its strain."""
    d = [(float(r[col]) - r["alpha_truth"], r["strain"]) for r in rows if r[col] != ""]
    if not d:
        return "-"
    m = max(d, key=lambda t: abs(t[0]))
    return f"{m[0]:+.3f} ({m[1]:g})"


def report(rows, out):
    counts = ", ".join(
        f"{sum(r['p_over_H'] == ph for r in rows)} at {ph:g} H"
        for ph in LOW_PRESSURES + BETWEEN_PRESSURES
    )
    failed = sum(not math.isfinite(r["dA_de"]) for r in rows)
    lines = [
        "# The two-state law below its table: 0.02 H",
        "",
        f"`benchmarks/flattening_limit_low.py`: the rigid-plastic optimum's rates at {counts} "
        f"(the latter for `flattening_limit_pressure.py`; {failed} where HiGHS gave no answer, "
        f"filled along A; mesh {'x'.join(map(str, LOW_MESH))}), the 0.02 H states integrated from "
        "each truth's pressing-alone "
        "fraction (`asperity_low.csv`), nothing fitted: the wedge (the row as a wedge of its RMS "
        "slope), the row by its own edge slope, and the runtime's law.",
        "",
        "alpha truth / two-state law / runtime's law after each strain (the row's edge-slope "
        "curve in the last column but one).",
        "",
        "| profile | mesh | "
        + " | ".join(f"{e:g}" for e in REPORT)
        + " | largest miss (strain): two-state | row by its edge slope | runtime's law |",
        "|---|---|" + "---|" * len(REPORT) + "---|---|---|",
    ]
    curves = list(dict.fromkeys((r["profile"], r["mesh"]) for r in out))
    for name, mesh in curves:
        mine = [r for r in out if (r["profile"], r["mesh"]) == (name, mesh)]
        by = {r["strain"]: r for r in mine}
        lines.append(
            f"| {name} | {mesh.replace('x', ' x ')} | "
            + " | ".join(
                f"{by[e]['alpha_truth']:.3f} / {by[e]['alpha_limit']:.3f} / "
                f"{by[e]['alpha_law']:.3f}"
                for e in REPORT
            )
            + f" | {_signed(mine, 'alpha_limit')} | {_signed(mine, 'alpha_edges')} | "
            f"{_signed(mine, 'alpha_law')} |"
        )

    def nx(r):
        return int(r["mesh"].split("x")[0])

    top = {}
    for r in out:
        top[r["profile"]] = max(top.get(r["profile"], 0), nx(r))
    finest = [r for r in out if nx(r) == top[r["profile"]]]
    for col, what in (("alpha_limit", "the two-state law"), ("alpha_law", "the runtime's law")):
        d = np.array([float(r[col]) - r["alpha_truth"] for r in finest])
        lines.append("")
        lines.append(
            f"Each profile on its finest mesh, {what}: largest miss {np.abs(d).max():.3f}, "
            f"RMS {math.sqrt(np.mean(d**2)):.3f}."
        )
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2, help="processes for the table (2)")
    args = ap.parse_args()
    rows = table(
        MESH,
        LOW_MESH,
        False,
        pressures=LOW_PRESSURES + BETWEEN_PRESSURES,
        path=LOW_TABLE,
        grid_a=tuple(sorted(A_GRID + LOW_A_GRID)),
        workers=args.workers,
    )
    out = compare(rows)
    write_report("flattening_limit_low", out, report(rows, out))


if __name__ == "__main__":
    with run_record(__file__, "flattening_limit_low"):
        main()
