"""Resolution knob of the tangential effect: stiffness of the default contact at grid 64-256.

The same synthetic surfaces at every grid (generated on 512 x 512 and block-averaged,
``measured_n=512``); normal solve at 100 and 400 MPa, then the pre-sliding curve. Writes
``benchmarks/results/presliding_resolution.csv`` and prints a markdown table.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/presliding_resolution.py``
"""

import csv
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _provenance import run_record

from halfspace_calib import topography as S  # noqa: E402
from halfspace_calib.contact.materials import Materials  # noqa: E402
from halfspace_calib.contact.normal import solve_normal_pair  # noqa: E402
from halfspace_calib.studies.presliding import presliding_curve  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "presliding_resolution.csv"


def main():
    es = Materials().E_star  # Table 1
    rows = []
    for n in (64, 128, 256):
        wp, tl = S.dc04_edt_like(n, measured_n=512), S.tool_like(n, measured_n=512)
        for p in (100e6, 400e6):
            r = solve_normal_pair(wp.heights, tl.heights, wp.dx, es, p, H=800e6)
            t0 = time.perf_counter()
            c = presliding_curve(r.pressure, wp.dx, materials=Materials(m=0.5))
            rows.append(
                [
                    n,
                    p,
                    r.alpha,
                    c.k_t0,
                    c.k_eq,
                    c.k_sec,
                    c.delta_full,
                    c.converged,
                    c.nit,
                    round(time.perf_counter() - t0, 2),
                ]
            )
    with open(OUT, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                "grid",
                "p_mean",
                "alpha",
                "k_t0",
                "k_eq",
                "k_sec",
                "delta_full",
                "converged",
                "nit",
                "seconds",
            ]
        )
        w.writerows(rows)
    print(
        "| grid | p_mean (MPa) | alpha | k_t0 (Pa/m) | k_eq (Pa/m) | k_sec (Pa/m) | "
        "delta_full (nm) | MPRGP iterations | time (s) |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r[0]} | {r[1] / 1e6:.0f} | {r[2]:.3f} | {r[3]:.3e} | {r[4]:.3e} | {r[5]:.3e} | "
            f"{r[6] * 1e9:.1f} | {r[8]} | {r[9]:.1f} |"
        )


if __name__ == "__main__":
    with run_record(__file__):
        main()
