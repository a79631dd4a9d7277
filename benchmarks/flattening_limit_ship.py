"""The two-state law's rate table as the runtime ships it (issue 43).

``flattening_limit_law.py`` (0.05-0.6 H) and ``flattening_limit_low.py`` (0.02, 0.035 and 0.07 H)
tabulate the rigid-plastic optimum's rates of the wedge cell, ``dA / d eps`` and ``ds / d eps``,
over ``A`` and the flank slope ``s`` at each pressure. This script gathers both caches into the
one file ``frictionlaw`` reads, ``frictionlaw/data/limit_rates.csv`` (model ``limit-analysis``
of docs/flattening.md): the states where HiGHS gave no answer take their neighbours' values along
``A`` as in the studies (``filled`` 1), everything else as computed. No state is computed here:
run the two table scripts first.

Run: python benchmarks/flattening_limit_ship.py
"""

from pathlib import Path

import numpy as np
from flattening_limit_law import S_GRID, TABLE, Rates, _read
from flattening_limit_low import LOW_TABLE

SHIPPED = Path(__file__).resolve().parent.parent / "frictionlaw" / "data" / "limit_rates.csv"
HEADER = """\
# The two-state flattening law's rate table (model limit-analysis, docs/flattening.md).
# The rigid-perfectly plastic optimum of the wedge cell (plane strain, half period l = 1) stretched
# across its ridges at pressure p: its contact fraction A and flank slope s grow at dA_de and
# ds_de per unit stretch. p_over_H is p over the Prandtl hardness (2 + pi) k of the bulk.
# Computed by benchmarks/flattening_limit_law.py and flattening_limit_low.py (meshes in column
# mesh: triangles nx x nz, yield polygon's sides); filled 1: HiGHS gave no answer there and the
# state takes its neighbours' values along A. Written by benchmarks/flattening_limit_ship.py.
"""


def shipped_rows():
    """Every state of both caches, NaN-filled along ``A`` at each pressure and slope."""
    rows = _read(TABLE) + _read(LOW_TABLE)
    mesh = {r["p_over_H"]: r["mesh"] for r in rows}
    out = []
    for ph in sorted(mesh):
        rates = Rates(rows, ph)
        raw = {(r["A"], r["s"]): r for r in rows if r["p_over_H"] == ph}
        for i, A in enumerate(rates.a):
            for j, s in enumerate(S_GRID):
                out.append(
                    (
                        mesh[ph],
                        ph,
                        A,
                        s,
                        rates.dA[i, j],
                        rates.ds[i, j],
                        int(not np.isfinite(raw[(A, s)]["dA_de"])),
                    )
                )
    return out


def main():
    rows = shipped_rows()
    lines = [HEADER + "mesh,p_over_H,A,s,dA_de,ds_de,filled"]
    lines += [f"{m},{ph:g},{A:.6g},{s:g},{dA:.6f},{ds:.6f},{f}" for m, ph, A, s, dA, ds, f in rows]
    tmp = SHIPPED.with_suffix(".tmp")
    tmp.write_text("\n".join(lines) + "\n", encoding="utf-8")
    tmp.replace(SHIPPED)
    pressures = sorted({r[1] for r in rows})
    print(
        f"{SHIPPED}: {len(rows)} states at p/H {', '.join(f'{p:g}' for p in pressures)}; "
        f"{sum(r[-1] for r in rows)} filled"
    )


if __name__ == "__main__":
    main()
