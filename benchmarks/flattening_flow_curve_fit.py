"""``beta`` fitted to a hardening sheet, with and without its flow curve, tested held out.

``halfspace-calib --flattening-data`` fits the flattening's one factor ``beta`` to a measured
contact fraction against strain. Measured on a hardening sheet, the fit either treats the sheet
as perfectly plastic at the calibration's ``sigma_y`` (``beta`` then absorbs the hardening's
slowing at the measured pressures) or, with ``--flow-curve``, integrates each point along the
sheet's flow curve (the law at the flow stress and hardening modulus of its strain, Eq. F2c), as
a host passing both runs it. This script measures which transfers to pressures and surfaces not
measured: the FE asperity truth with DC04's hardening (``flattening_hardening.py``'s CSV, the
3-10 deg wedges and the measured row at 0.05 / 0.2 / 0.45 H, strains to 0.2) treated as the
lab sheet, ``beta`` fitted with the command's own ``fit_beta`` and each prediction made the way
the fit was made (with the curve: ``flattening_curve(..., flow_curve=)``; without: perfectly
plastic). The law of each profile is ``flattening_hardening.py``'s (the hardening truth's own
pressing-alone fractions as ``alpha1``, the profile's slope).

- **pressure split**: per profile, ``beta`` fitted on two pressures, the third predicted (each
  held out once);
- **slope split**: ``beta`` fitted on one profile (all three pressures), every other predicted.

Run: python benchmarks/flattening_flow_curve_fit.py (about 3 min on the shared 2-core machine).
Reads benchmarks/results/flattening_hardening.csv and asperity_flattening.csv; writes
benchmarks/results/flattening_flow_curve_fit.csv and .md (run record: .run.json).
"""

import csv
import time
from collections import defaultdict

import numpy as np
from _provenance import RESULTS, run_record, write_rows
from flattening_truth import BAR, law_of, law_strain, read_truth

import frictionlaw as fl
from frictionlaw.flattening_curves import FlatteningPaths
from frictionlaw.flow_curve import SwiftCurve
from halfspace_calib.pipeline.sweep.flattening import FlatteningData, fit_beta

#: DC04, fe_demo's sheet and the hardening truth's (K 530 MPa, eps0 0.006, n 0.24)
DC04 = SwiftCurve(530e6, 0.006, 0.24)


def read_hardening_truth():
    """``{profile: {p/H: (stretches, alpha)}}`` of the hardening truth (converged runs only)."""
    out = defaultdict(dict)
    rows = defaultdict(list)
    with (RESULTS / "flattening_hardening.csv").open(encoding="utf-8") as f:
        for r in csv.DictReader(f):
            if r["converged"] == "True":
                rows[(r["profile"], float(r["p_over_H"]))].append(
                    (float(r["strain"]), float(r["alpha_hardening"]))
                )
    for (name, ph), pts in rows.items():
        s, a = zip(*sorted(pts), strict=True)
        out[name][ph] = (np.array(s), np.array(a))
    return out


def predict(P, p, strains, beta, with_curve):
    """The law with ``beta`` at ``p`` after the equivalent ``strains``, as the fit made it."""
    law = P.replace(flattening=fl.Flattening(slope=P.flattening.slope, beta=beta))
    if with_curve:
        return FlatteningPaths(p, strains, law, DC04).alpha()
    return fl.flattening_curve(p, strains, law)


def data_of(curves, H, pressures, name, with_curve):
    """The truth's points at ``pressures`` (in H) as ``--flattening-data`` (equivalent strains)."""
    e = np.concatenate([law_strain(curves[ph][0]) for ph in pressures])
    a = np.concatenate([curves[ph][1] for ph in pressures])
    p = np.concatenate([np.full(curves[ph][0].size, ph * H) for ph in pressures])
    return FlatteningData(name, e, a, p, flow_curve=DC04 if with_curve else None)


def main():
    t0 = time.time()
    pp, H = read_truth(RESULTS / "asperity_flattening.csv")
    hard = read_hardening_truth()
    laws = {}
    for name, curves in hard.items():
        key = next(k for k in pp if k[0] == name)
        table = {ph: {0.0: float(a[0])} for ph, (_, a) in curves.items()}
        laws[name] = law_of(table, key[1], H)
    rows, summary = [], {}
    for with_curve in (False, True):
        tag = "flow curve" if with_curve else "perfectly plastic"
        for split in ("pressure", "slope"):
            misses, betas = [], []
            for name, curves in hard.items():
                P = laws[name]
                if split == "pressure":
                    folds = [([q for q in curves if q != ph], [(name, ph)]) for ph in curves]
                else:
                    others = [(n, q) for n in hard if n != name for q in hard[n]]
                    folds = [(list(curves), others)]
                for fit_on, held in folds:
                    fit = fit_beta(P, data_of(curves, H, fit_on, name, with_curve))
                    betas.append(fit["beta"])
                    for n2, ph in held:
                        s, a = hard[n2][ph]
                        got = predict(laws[n2], ph * H, law_strain(s), fit["beta"], with_curve)
                        d = float(np.abs(got - a).max())
                        misses.append(d)
                        rows.append(
                            {
                                "fit": tag,
                                "split": split,
                                "fitted_on": f"{name} {'/'.join(f'{q:g}' for q in fit_on)}",
                                "predicted": f"{n2} {ph:g}",
                                "beta": fit["beta"],
                                "largest_miss": d,
                            }
                        )
            summary[(tag, split)] = (min(betas), max(betas), max(misses), misses)
    write_rows(RESULTS / "flattening_flow_curve_fit.csv", rows)
    lines = [
        "# beta fitted to a hardening sheet, with and without its flow curve (held out)",
        "",
        "`benchmarks/flattening_flow_curve_fit.py`; the lab sheet: the FE asperity truth with "
        "DC04's hardening (`flattening_hardening.csv`); `fit_beta` of `halfspace-calib "
        f"--flattening-data`; the bar {BAR:g}.",
        "",
        "| fit | split | fitted beta | held-out largest miss | median of the held-out curves' "
        "largest misses | curves within the bar |",
        "|---|---|---|---|---|---|",
    ]
    for (tag, split), (lo, hi, worst, ms) in summary.items():
        within = sum(m <= BAR for m in ms)
        lines.append(
            f"| {tag} | {split} | {lo:.3g}-{hi:.3g} | {worst:.3f} | {np.median(ms):.3f} | "
            f"{within} of {len(ms)} |"
        )
    secs = time.time() - t0
    lines += ["", f"{secs:.0f} s."]
    text = "\n".join(lines) + "\n"
    (RESULTS / "flattening_flow_curve_fit.md").write_text(text, encoding="utf-8")
    print(text)
    return 0


if __name__ == "__main__":
    with run_record(__file__):
        main()
