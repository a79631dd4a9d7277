"""Coverage of the multi-sample band at 3, 5, 10 and 16 samples (issue 26, item 4).

Population: one synthetic Table 1 workpiece and tool, ``k x 2.11`` mm a side, cut into ``k^2``
patches of ``grid`` elements, each calibrated once (non-periodic, the scene's pressures). Truth:
the pooled law of all patches (what the band estimates: the law of the population's mean curve).
For each sample size ``n``, ``repeats`` times: draw ``n`` patches at random *with replacement*
(independent draws from the population, so the truth is exactly the estimand; without
replacement a draw of 16 of 16 patches would be the truth itself), fit the pooled law, refit it
on ``boot`` bootstrap resamples (:func:`~halfspace_calib.pipeline.band.uncertainty.bootstrap_laws`)
and make the 90 % band from the same resamples by every method of
:data:`~halfspace_calib.pipeline.band.uncertainty.BAND_METHODS`; count how often the truth's ``tau``
at 100, 300 and 600 MPa (first loading) and the reload ``tau`` at half the top ``p_hist`` lie
inside. The per-patch calibrations are reused by every draw: a draw costs ``boot`` refits.
The coverage's own standard error is ``sqrt(c (1 - c) / repeats)``.

``--whole`` adds the comparison of the pooled law with one calibration of the whole surface
(non-periodic as the patches, and periodic).

Run: python benchmarks/uncertainty_coverage.py [--k 6] [--grid 32] [--sizes 3,5,10,16]
     [--repeats 300] [--boot 100] [--whole]
Writes benchmarks/results/uncertainty_coverage.csv / .md and prints the table.
"""

import argparse
import csv
import dataclasses
import math
import time
from pathlib import Path

import numpy as np
from _provenance import run_record

from frictionlaw import alpha_first, alpha_reload
from halfspace_calib.pipeline.band.samples import (
    SampleSpec,
    calibrate_samples,
    load_samples,
    synthetic_population,
)
from halfspace_calib.pipeline.band.uncertainty import (
    BAND_METHODS,
    band_limits,
    bootstrap_laws,
    curves_of,
    pooled_law,
)
from halfspace_calib.pipeline.calibration import Scene, calibrate

RESULTS = Path(__file__).parent / "results"
PROBES = (100e6, 300e6, 600e6)


def _taus(P, pr, ph):
    """``tau`` of law ``P`` at the probes: first loading at PROBES, reload at ``pr`` after ``ph``."""
    t = [P.tau_max * float(alpha_first(p, P)) for p in PROBES]
    return np.array(t + [P.tau_max * float(alpha_reload(pr, ph, P))])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--k", type=int, default=6, help="patches per side (default %(default)s)")
    ap.add_argument("--grid", type=int, default=32, help="patch grid (default %(default)s)")
    ap.add_argument("--sizes", default="3,5,10,16", help="samples per draw (default %(default)s)")
    ap.add_argument("--repeats", type=int, default=300, help="draws per size (default %(default)s)")
    ap.add_argument("--boot", type=int, default=100, help="resamples (default %(default)s)")
    ap.add_argument("--level", type=float, default=0.9, help="band level (default %(default)s)")
    ap.add_argument(
        "--pressures",
        choices=("default", "paper"),
        default="default",
        help="the scene's default sweep or the paper's 10-600 MPa (default %(default)s)",
    )
    ap.add_argument(
        "--bound",
        choices=("default", "none"),
        default="default",
        help="Eq. 24 fitted with the bound alpha1 >= p/H up to 0.99 H (the scene's default) or "
        "without (default %(default)s)",
    )
    ap.add_argument("--whole", action="store_true", help="also calibrate the whole surface")
    ap.add_argument("--tag", default="", help="suffix of the result files (default none)")
    a = ap.parse_args(argv)
    sizes = [int(s) for s in a.sizes.split(",")]
    from halfspace_calib.pipeline.sweep.scene import PAPER_PRESSURES

    kw = {"pressures": PAPER_PRESSURES} if a.pressures == "paper" else {}
    if a.bound == "none":
        kw["alpha_floor"] = None
    scene = Scene(grid=a.grid, **kw)
    floor = None if scene.alpha_floor is None else scene.alpha_floor * scene.H
    t0 = time.perf_counter()
    spec = SampleSpec(patches=a.k * a.k, n_bootstrap=50, level=a.level)
    mc = calibrate_samples(scene, spec, samples=load_samples(scene, spec), progress=False)
    t_pop = time.perf_counter() - t0
    truth = mc.params
    curves = [curves_of(n, c.sweeps) for n, c in mc.calibrations.items()]
    ph = max(c.p_hist for c in curves[0].reload)
    pr = 0.5 * ph
    t_truth = _taus(truth, pr, ph)
    names = [f"tau_first({p / 1e6:g} MPa)" for p in PROBES] + [
        f"tau_reload({pr / 1e6:g} MPa after {ph / 1e6:g})"
    ]
    # every draw's pooled law in the truth's forms (issue 37: the band of the law the file runs)
    forms_scene = dataclasses.replace(
        mc.pooled.scene,
        first_loading_form=truth.first_loading_form,
        reload_form=truth.reload_form,
    )
    rng = np.random.default_rng(1)
    rows = []
    t_cov = {}
    for n in sizes:
        hits = {m: np.zeros(len(names)) for m in BAND_METHODS}
        widths = {m: [] for m in BAND_METHODS}
        t0 = time.perf_counter()
        for r in range(a.repeats):
            sub = [curves[i] for i in rng.choice(len(curves), n, replace=True)]
            cen = pooled_law(forms_scene, sub, heldout=False).apply(truth)
            cen = cen.replace(uncertainty=None)
            boot = bootstrap_laws(sub, cen, n_bootstrap=a.boot, seed=1000 * n + r, floor_to=floor)
            stack = np.array([_taus(law, pr, ph) for law in boot])
            c = _taus(cen, pr, ph)
            for m in BAND_METHODS:
                lo, hi = band_limits(stack, c, n, a.level, m)
                hits[m] += (lo <= t_truth) & (t_truth <= hi)
                widths[m].append((hi - lo) / c)
        t_cov[n] = time.perf_counter() - t0
        for m in BAND_METHODS:
            cov = hits[m] / a.repeats
            w = np.median(np.array(widths[m]), axis=0)
            for i, nm in enumerate(names):
                se = math.sqrt(cov[i] * (1 - cov[i]) / a.repeats)
                rows.append([n, m, nm, cov[i], se, 100 * w[i]])
    RESULTS.mkdir(exist_ok=True)
    hdr = ["samples", "method", "quantity", "coverage", "coverage_stderr", "median_width_pct"]
    stem = "uncertainty_coverage" + a.tag
    with open(RESULTS / f"{stem}.csv", "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(hdr)
        wr.writerows(rows)
    lines = [
        f"# Band coverage: population {a.k * a.k} patches of {a.grid}^2 ({a.k} x 2.11 mm "
        f"synthetic Table 1 surface, {a.pressures} pressures, bound alpha1 >= p/H: {a.bound}), "
        "draws with replacement, "
        f"{a.repeats} draws per size, {a.boot} resamples each, nominal {100 * a.level:g} %",
        "",
        "Coverage (its standard error) and median band width (% of the pooled value):",
        "",
        "| samples | method | " + " | ".join(names) + " |",
        "|---|---|" + "---|" * len(names),
    ]
    for n in sizes:
        for m in BAND_METHODS:
            cells = [
                f"{r[3]:.3f} ({r[4]:.3f}), {r[5]:.2f} %" for r in rows if r[0] == n and r[1] == m
            ]
            lines.append(f"| {n} | {m} | " + " | ".join(cells) + " |")
    lines += [
        "",
        f"Truth (pooled law of all {a.k * a.k} patches): C1 {truth.C1:.4g}, n1 {truth.n1:.4g}, "
        f"C2 {truth.C2:.4g}, n2 {truth.n2:.4g}; tau "
        + ", ".join(f"{t / 1e6:.3f}" for t in t_truth)
        + " MPa",
        f"Time (wall, shared 2-core machine under load): {a.k * a.k} patch calibrations "
        f"{t_pop:.1f} s; draws " + ", ".join(f"n={n}: {t_cov[n]:.0f} s" for n in sizes),
    ]
    if a.whole:
        lines += _whole(scene, a, truth, pr, ph, t_truth, names)
    text = "\n".join(lines) + "\n"
    (RESULTS / f"{stem}.md").write_text(text)
    print(text)


def _whole(scene, a, truth, pr, ph, t_truth, names):
    """Lines comparing the pooled law with one calibration of the whole surface."""
    big = synthetic_population(scene, a.k, a.grid)
    g = a.k * a.grid
    whole = calibrate(
        Scene(grid=g, periodic=False, pressures=scene.pressures), surfaces=big, progress=False
    )
    whole_p = calibrate(Scene(grid=g, pressures=scene.pressures), surfaces=big, progress=False)
    tw, tp = _taus(whole.params, pr, ph), _taus(whole_p.params, pr, ph)
    out = [
        "",
        f"| quantity | pooled of {a.k * a.k} (MPa) | whole {g}^2 non-periodic (MPa) | pooled vs "
        "whole | whole periodic (MPa) |",
        "|---|---|---|---|---|",
    ]
    for i, nm in enumerate(names):
        out.append(
            f"| {nm} | {t_truth[i] / 1e6:.3f} | {tw[i] / 1e6:.3f} | "
            f"{100 * (t_truth[i] / tw[i] - 1):+.2f} % | {tp[i] / 1e6:.3f} |"
        )
    return out


if __name__ == "__main__":
    with run_record(__file__):
        main()
