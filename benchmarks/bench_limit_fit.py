"""Cost of fitting ``beta`` of the two-state flattening law to a lab sheet, point by point and shared.

``fit_beta`` with a block of model ``limit-analysis`` evaluates the two-state curves
(``frictionlaw.flattening_curve``) at every row for each trial ``beta``. Each row's integration
from the virgin surface (``_limit_table.integrate``, the runtime's rule point by point) is timed
against the points of one pressure sharing one integration (``integrate_shared``, what the
curves use: equal to rounding), on synthetic sheets made with the law at ``beta = 1.5`` plus
noise of 0.02 (strains 0-0.3, slope 0.08, Eq. 24 at H = 800 MPa), rows cycling through 3 or 20
pressures (0.03-0.4 H), in one run.

Run: python benchmarks/bench_limit_fit.py [--sizes 100,1000,10000]
Writes benchmarks/results/bench_limit_fit.csv and .md and prints the table.
"""

import argparse
import time

import numpy as np
from _provenance import run_record, write_report

import frictionlaw.flattening_limit as FLM
from frictionlaw import Flattening, FrictionParams, flattening_curve
from frictionlaw._limit_table import integrate
from halfspace_calib.pipeline.sweep.flattening import FlatteningData, fit_beta

H = 8e8
BETA = 1.5


def law(beta=1.0):
    block = Flattening(0.08, beta, model="limit-analysis")
    return FrictionParams(
        m=0.5, sigma_y=H / 2.8, H=H, C1=1.05, n1=2.87, C2=7.44, n2=0.575, flattening=block
    )


def sheet(n, pressures, seed=0):
    rng = np.random.default_rng(seed)
    p = np.resize(np.linspace(0.03, 0.4, pressures), n) * H
    eps = rng.uniform(0.0, 0.3, n)
    alpha = flattening_curve(p, eps, law(BETA))
    return FlatteningData(f"{n} rows", eps, np.clip(alpha + rng.normal(0, 0.02, n), 0, 1), p)


def timed_fit(data, shared):
    saved = FLM.integrate_shared
    if not shared:
        FLM.integrate_shared = integrate  # every row on its own: the same rule, point by point
    try:
        t0 = time.perf_counter()
        fit = fit_beta(law(), data)
        return time.perf_counter() - t0, fit
    finally:
        FLM.integrate_shared = saved


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="100,1000,10000")
    args = ap.parse_args()
    rows = []
    lines = [
        "# Fitting beta of the two-state law: each row on its own against shared integrations",
        "",
        "`benchmarks/bench_limit_fit.py` (sheets at beta 1.5 with noise 0.02; the same run).",
        "",
        "| rows | pressures | point by point s | shared s | ratio | fitted beta (both) |",
        "|---|---|---|---|---|---|",
    ]
    for n in (int(v) for v in args.sizes.split(",")):
        for k in (3, 20):
            data = sheet(n, k)
            t_one, f_one = timed_fit(data, False)
            t_sh, f_sh = timed_fit(data, True)
            rows.append(
                {
                    "rows": n,
                    "pressures": k,
                    "point_by_point_s": round(t_one, 3),
                    "shared_s": round(t_sh, 3),
                    "ratio": round(t_one / t_sh, 2),
                    "beta_point_by_point": f_one["beta"],
                    "beta_shared": f_sh["beta"],
                }
            )
            lines.append(
                f"| {n} | {k} | {t_one:.2f} | {t_sh:.2f} | {t_one / t_sh:.1f} | "
                f"{f_one['beta']:.6f} / {f_sh['beta']:.6f} |"
            )
    write_report("bench_limit_fit", rows, lines)


if __name__ == "__main__":
    with run_record(__file__):
        main()
