"""Coverage of the multi-sample band, and the pooled law against the whole surface.

Population: one synthetic Table 1 workpiece and tool, ``k x 2.11`` mm a side, cut into ``k^2``
patches of ``grid`` elements (the samples). Truth: the pooled law of all patches (what the
band estimates). Repeatedly draw ``n`` of the patches without replacement, make the
bootstrap band at 90 % and count how often the truth's ``tau`` at 100, 300, 600 MPa (first
loading) and the reload ``tau`` at half the top ``p_hist`` lie inside it. Also: the pooled law of
all patches against one calibration of the whole surface (non-periodic, as the patches; the
periodic one for comparison), and the band widths.

Run: python benchmarks/uncertainty_coverage.py [--k 4] [--grid 32] [--n 5] [--repeats 60]
Writes benchmarks/results/uncertainty_coverage.csv / .md and prints the table.
"""

import argparse
import csv
import time
from pathlib import Path

import numpy as np
from _provenance import run_record

from frictionlaw import alpha_reload
from halfspace_calib.pipeline.calibration import Scene, calibrate
from halfspace_calib.pipeline.samples import (
    SampleSpec,
    calibrate_samples,
    load_samples,
    synthetic_population,
)
from halfspace_calib.pipeline.uncertainty import bootstrap_uncertainty, curves_of, pooled_fit

RESULTS = Path(__file__).parent / "results"
PROBES = (100e6, 300e6, 600e6)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--k", type=int, default=4, help="patches per side (default %(default)s)")
    ap.add_argument("--grid", type=int, default=32, help="patch grid (default %(default)s)")
    ap.add_argument("--n", type=int, default=5, help="samples per draw (default %(default)s)")
    ap.add_argument("--repeats", type=int, default=60, help="draws (default %(default)s)")
    ap.add_argument("--boot", type=int, default=200, help="resamples (default %(default)s)")
    ap.add_argument("--level", type=float, default=0.9, help="band level (default %(default)s)")
    a = ap.parse_args(argv)
    scene = Scene(grid=a.grid)
    t0 = time.perf_counter()
    spec = SampleSpec(patches=a.k * a.k, n_bootstrap=a.boot, level=a.level)
    mc = calibrate_samples(scene, spec, samples=load_samples(scene, spec), progress=False)
    t_pop = time.perf_counter() - t0
    truth = mc.params
    curves = [curves_of(n, c.sweeps) for n, c in mc.calibrations.items()]
    t0 = time.perf_counter()
    big = synthetic_population(scene, a.k, a.grid)
    whole = calibrate(Scene(grid=a.k * a.grid, periodic=False), surfaces=big, progress=False)
    t_whole = time.perf_counter() - t0
    whole_p = calibrate(Scene(grid=a.k * a.grid), surfaces=big, progress=False)
    ph = max(c.p_hist for c in curves[0].reload)
    pr = 0.5 * ph

    def taus(P):
        return [P.tau_max * v for v in _alpha1(P)] + [P.tau_max * float(alpha_reload(pr, ph, P))]

    t_truth, t_whole_tau = taus(truth), taus(whole.params)
    t_whole_p = taus(whole_p.params)
    rng = np.random.default_rng(1)
    hits = np.zeros(len(PROBES) + 1)
    widths = []
    t0 = time.perf_counter()
    for r in range(a.repeats):
        pick = rng.choice(len(curves), a.n, replace=False)
        sub = [curves[i] for i in pick]
        f, rl = pooled_fit(sub, truth.H)
        cen = truth.replace(C1=f.C1, n1=f.n1, C2=rl.C2, n2=rl.n2, uncertainty=None)
        u = bootstrap_uncertainty(sub, cen, level=a.level, n_bootstrap=a.boot, seed=r)
        b1, b2 = u.band("tau_first"), u.band("tau_reload", ph)
        row = [b1.at(p) for p in PROBES] + [b2.at(pr)]
        hits += [lo <= t <= hi for t, (_, lo, hi) in zip(t_truth, row, strict=True)]
        widths.append([(hi - lo) / c for c, lo, hi in row])
    t_cov = time.perf_counter() - t0
    cov = hits / a.repeats
    w = np.median(np.array(widths), axis=0)
    names = [f"tau_first({p / 1e6:g} MPa)" for p in PROBES] + [
        f"tau_reload({pr / 1e6:g} MPa after {ph / 1e6:g})"
    ]
    rows = []
    for i, nm in enumerate(names):
        rows.append(
            [
                nm,
                t_truth[i] / 1e6,
                t_whole_tau[i] / 1e6,
                100 * (t_truth[i] / t_whole_tau[i] - 1),
                t_whole_p[i] / 1e6,
                cov[i],
                100 * w[i],
            ]
        )
    u = truth.uncertainty
    RESULTS.mkdir(exist_ok=True)
    hdr = [
        "quantity",
        "pooled_all_MPa",
        "whole_surface_MPa",
        "pooled_vs_whole_percent",
        "whole_periodic_MPa",
        f"coverage_n{a.n}",
        "median_band_width_percent",
    ]
    with open(RESULTS / "uncertainty_coverage.csv", "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(hdr)
        wr.writerows(rows)
    lines = [
        f"# Band coverage: {a.k * a.k} patches of {a.grid}^2 ({a.k} x 2.11 mm synthetic "
        f"Table 1 surface), draws of {a.n}, {a.repeats} repeats, {a.boot} resamples, "
        f"nominal {100 * a.level:g} %",
        "",
        "| " + " | ".join(hdr) + " |",
        "|" + "---|" * len(hdr),
    ]
    lines += [
        f"| {r[0]} | {r[1]:.3f} | {r[2]:.3f} | {r[3]:+.2f} | {r[4]:.3f} | {r[5]:.2f} | {r[6]:.2f} |"
        for r in rows
    ]
    lines += [
        "",
        f"All {a.k * a.k} patches: "
        + ", ".join(
            f"{k} {v.central:.4g} [{v.lower:.4g}, {v.upper:.4g}]" for k, v in u.parameters.items()
        ),
        f"Whole surface ({a.k * a.grid}^2, non-periodic as the patches): C1 {whole.params.C1:.4g}, n1 "
        f"{whole.params.n1:.4g}, C2 {whole.params.C2:.4g}, n2 {whole.params.n2:.4g}",
        f"Time: {a.k * a.k} patch calibrations + band {t_pop:.1f} s, whole surface "
        f"{t_whole:.1f} s, coverage draws {t_cov:.1f} s",
    ]
    text = "\n".join(lines) + "\n"
    (RESULTS / "uncertainty_coverage.md").write_text(text)
    print(text)


def _alpha1(P):
    from frictionlaw import alpha_first

    return [float(alpha_first(p, P)) for p in PROBES]


if __name__ == "__main__":
    with run_record(__file__):
        main()
