"""The limit analysis on the truth's own deformed flank (issue 43, a study of the mechanism).

The two-state law (``flattening_limit_law.py``) describes a state by its contact fraction ``A``
and one flank slope ``s``: a straight flank. The truth's flank does not stay straight. This
script asks whether that reduction, or the rigid-plastic optimum itself, parts the law from the
truth where it misses most: it reruns truth cases with small steps (``flattening_flank.run``:
64 x 32, steps of at most 0.002), and at a few strains solves the limit analysis of
``flattening_limit.py`` on two cells of the same ``A`` (the table's meshes: 16 x 24 triangles
below 0.15 H, 12 x 16 above, 48 sides):

- **straight**: the flank straight at the truth's fitted slope ``s`` (``flattening_flank``'s fit
  between 10 % and 90 % of the free flank), as the table's state has it;
- **deformed**: the flank the truth's free top nodes draw at that strain (scaled by the
  half-spacing, measured down from the tool).

Read off, beside the truth's own rates (central differences over ``flattening_flank.WINDOW``):
the contact's growth ``dA / d eps`` by the table's flank fit and by the first flank element
beyond the edge with the cell's own slope there, and the flank's turn ``d ln s / d eps`` by the
table's fit. Nothing is fitted. Writes ``results/flattening_limit_geometry.md`` / ``.csv``.

Run: python benchmarks/flattening_limit_geometry.py (14 min on the shared 2-core machine)
"""

import math

import numpy as np
from _provenance import run_record, write_report
from flattening_flank import WINDOW, run
from flattening_limit import H, limit_field
from flattening_limit_law import LOW_MESH, MESH, flank_rates, mesh_of, n_flank

#: (wedge deg, p/H, strains): where the two-state law runs ahead of the truth at low pressure
#: and where the optimum sinks faster than the truth near collapse
CASES = (
    (3.0, 0.05, (0.01, 0.02, 0.03)),
    (10.0, 0.05, (0.03, 0.06, 0.09)),
    (10.0, 0.45, (0.005, 0.01)),
)


def readings(ph, A, s, top_of=None):
    """The limit analysis's rates at state (``A``, ``s``), the flank straight or ``top_of``'s."""
    nx, nz, sides = mesh_of(ph, MESH, LOW_MESH)
    f = limit_field(ph * H, A, s, nx, nz, sides, n_flank(A, nx), time_limit=600, top_of=top_of)
    x, u, w = f["surface"].T
    he = f["flank_element"]
    dA, ds = flank_rates(f, A, s)
    s_edge = s if top_of is None else -float(min(top_of(np.array([A + he]))[0], 0.0)) / he
    xe = A + he
    return {
        "dA_fit": dA,
        "dA_edge": (np.interp(xe, x, w) - f["W"]) / s_edge + np.interp(xe, x, u) - xe,
        "dln_s": ds / s,
        "s_edge_over_s": s_edge / s,
    }


def case_rows(deg, ph, strains):
    res, e, A, s, _, L = run(deg, ph, e_max=max(strains) + WINDOW + 0.002)
    h = res.history
    out = []
    for ek in strains:
        k = int(np.argmin(np.abs(e - ek)))
        top, tool = np.asarray(h.top[k]), h.tool[k]
        order = np.argsort(top[:, 0])
        xn, zn = top[order, 0] / L[k], np.minimum((top[order, 1] - tool) / L[k], 0.0)

        def top_of(x, xn=xn, zn=zn):
            return np.interp(x, xn, zn)

        lo, hi = e[k] - WINDOW, e[k] + WINDOW
        straight = readings(ph, A[k], s[k])
        deformed = readings(ph, A[k], s[k], top_of)
        out.append(
            {
                "slope_deg": deg,
                "p_over_H": ph,
                "strain": round(float(e[k]), 4),
                "alpha": round(float(A[k]), 4),
                "slope_ratio": round(float(s[k]) / math.tan(math.radians(deg)), 4),
                "dA_de_truth": round(
                    float((np.interp(hi, e, A) - np.interp(lo, e, A)) / (hi - lo)), 3
                ),
                "dln_s_de_truth": round(
                    float(math.log(np.interp(hi, e, s) / np.interp(lo, e, s)) / (hi - lo)), 3
                ),
                **{
                    f"{k2}_straight": round(float(v), 3)
                    for k2, v in straight.items()
                    if k2 != "s_edge_over_s"
                },
                **{f"{k2}_deformed": round(float(v), 3) for k2, v in deformed.items()},
            }
        )
        print(out[-1], flush=True)
    return out


def main():
    rows = [r for deg, ph, strains in CASES for r in case_rows(deg, ph, strains)]
    lines = [
        "# The limit analysis on the truth's own deformed flank",
        "",
        "`benchmarks/flattening_limit_geometry.py`: truth states (64 x 32, steps of at most "
        f"0.002); the limit analysis on the table's meshes ({LOW_MESH[0]} x {LOW_MESH[1]} "
        f"triangles below 0.15 H, {MESH[0]} x {MESH[1]} above, {MESH[2]} sides), on the straight "
        "flank of the truth's fitted slope and on the truth's deformed flank. "
        "`dA/de`: the contact's growth per unit stretch (fit: the table's flank fit; edge: the "
        "first flank element with the cell's slope there); `dln s/de`: the flank's turn; "
        "`s edge / s`: the deformed flank's slope at the edge over the fitted one.",
        "",
        "| wedge, p/H | strain | alpha | s / s0 | dA/de: truth | straight: fit / edge | "
        "deformed: fit / edge | dln s/de: truth | straight | deformed | s edge / s |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['slope_deg']:g} deg, {r['p_over_H']:g} | {r['strain']:g} | {r['alpha']:.3f} | "
            f"{r['slope_ratio']:.3f} | {r['dA_de_truth']:.2f} | {r['dA_fit_straight']:.2f} / "
            f"{r['dA_edge_straight']:.2f} | {r['dA_fit_deformed']:.2f} / "
            f"{r['dA_edge_deformed']:.2f} | {r['dln_s_de_truth']:.2f} | "
            f"{r['dln_s_straight']:.2f} | {r['dln_s_deformed']:.2f} | "
            f"{r['s_edge_over_s_deformed']:.2f} |"
        )
    write_report("flattening_limit_geometry", rows, lines)


if __name__ == "__main__":
    with run_record(__file__):
        main()
