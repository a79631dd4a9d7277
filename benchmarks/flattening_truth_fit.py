"""The flattening law's one factor ``beta`` fitted to the FE asperity truth and tested held out.

``docs/flattening.md`` allows ``beta`` (the yielding layer's thickness in half-spacings, default
1) to be fitted to a measured contact fraction against strain (``halfspace-calib
--flattening-data``). This script treats part B's FE asperity table as such a measurement and
fits ``beta`` with the command's own ``fit_beta`` (least squares in ``ln beta``) on some curves,
then predicts the others, held out. The law of each profile is ``flattening_truth.law_of`` (the
truth's pressing-alone alpha as ``alpha1``, the profile's ``tan(theta)``); only ``beta`` changes.

- **pressure split** (the ``--flattening-data`` workflow: one surface measured at some pressures):
  per profile, ``beta`` fitted on the pressures of one fold, the other fold predicted; two folds,
  p / H {0.1, 0.3, 0.6} and {0.05, 0.2, 0.45}, each held out once;
- **slope split** (a measurement on one surface used for another): ``beta`` fitted on one profile
  (all pressures), every other profile predicted;
- **per curve**: the best ``beta`` of each (profile, pressure) curve alone and its miss, the
  floor that no ``beta`` depending on slope or pressure can go below, and how ``beta`` varies;
- **pressure-dependent beta** (a model finding, not a default): ``ln beta`` linear in ``p / H``
  fitted to the per-curve ``beta`` of one pressure fold (all profiles), the other fold predicted.

Run: python benchmarks/flattening_truth_fit.py [--truth CSV]
Writes benchmarks/results/flattening_truth_fit.csv and .md.
"""

import math
from pathlib import Path

import numpy as np
from _provenance import run_record, write_rows
from flattening_truth import BAR, law_strain, truth_args

import frictionlaw as fl
from halfspace_calib.pipeline.sweep.flattening import FlatteningData, fit_beta

FOLDS = ((0.1, 0.3, 0.6), (0.05, 0.2, 0.45))


def curve(P, p, strains, beta):
    """The law's contact fraction at ``p`` after ``strains`` with the factor ``beta``."""
    return fl.flattening_curve(p, beta * law_strain(strains), P)  # strain scales as 1 / beta


def data_of(table, H, pressures, name):
    """The truth's points at ``pressures`` (in H) as ``--flattening-data`` (equivalent strains)."""
    e, a, p = [], [], []
    for pH in pressures:
        for s, al in sorted(table[pH].items()):
            e.append(float(law_strain(s)))
            a.append(al)
            p.append(pH * H)
    return FlatteningData(name, np.array(e), np.array(a), np.array(p))


def miss(P, table, H, pressures, beta):
    """Largest and RMS ``|alpha_law - alpha_truth|`` over ``pressures``' curves."""
    d = []
    for pH in pressures:
        s = sorted(table[pH])
        d.append(curve(P, pH * H, s, beta) - np.array([table[pH][x] for x in s]))
    d = np.concatenate(d)
    return float(np.abs(d).max()), float(np.sqrt(np.mean(d * d)))


def main(argv=None):
    args, truth, H, laws = truth_args(__doc__, "flattening_truth_fit", argv)
    rows = []

    def add(split, trained_on, profile, held_out, beta, P, table):
        mx, rms = miss(P, table, H, held_out, beta)
        m1, r1 = miss(P, table, H, held_out, 1.0)
        rows.append(
            {
                "split": split,
                "trained_on": trained_on,
                "profile": profile,
                "held_out_p_over_H": " ".join(f"{p:g}" for p in held_out),
                "beta": beta,
                "max_abs_miss": mx,
                "rms_miss": rms,
                "max_abs_miss_beta1": m1,
                "rms_miss_beta1": r1,
            }
        )

    # per curve: the best beta of each curve alone
    per_curve = {}
    for (name, deg), table in truth.items():
        for pH in sorted(table):
            f = fit_beta(laws[(name, deg)], data_of(table, H, [pH], name))
            per_curve[(name, pH)] = (f["beta"], deg)
            add("per curve", f"{name} p/H {pH:g}", name, [pH], f["beta"], laws[(name, deg)], table)
    # pressure split: per profile, fitted on one fold
    for train, test in (FOLDS, FOLDS[::-1]):
        for (name, deg), table in truth.items():
            f = fit_beta(laws[(name, deg)], data_of(table, H, train, name))
            tag = "p/H " + " ".join(f"{p:g}" for p in train)
            add("pressure", tag, name, test, f["beta"], laws[(name, deg)], table)
    # slope split: fitted on one profile, the others predicted
    for (tname, tdeg), ttable in truth.items():
        f = fit_beta(laws[(tname, tdeg)], data_of(ttable, H, sorted(ttable), tname))
        for (name, deg), table in truth.items():
            if name != tname:
                add("slope", tname, name, sorted(table), f["beta"], laws[(name, deg)], table)
    # pressure-dependent beta: ln beta = c0 + c1 p / H from the training fold's per-curve betas
    for train, test in (FOLDS, FOLDS[::-1]):
        x = [pH for (n, pH) in per_curve if pH in train]
        y = [math.log(b) for (n, pH), (b, _) in per_curve.items() if pH in train]
        c1, c0 = np.polyfit(x, y, 1)
        for (name, deg), table in truth.items():
            for pH in test:
                beta = math.exp(c0 + c1 * pH)
                tag = f"ln beta = {c0:.3f} {c1:+.3f} p/H from p/H " + " ".join(
                    f"{p:g}" for p in train
                )
                add("beta(p)", tag, name, [pH], beta, laws[(name, deg)], table)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_rows(out.with_suffix(".csv"), rows)
    lines = report(rows, per_curve, Path(args.truth).name, H)
    out.with_suffix(".md").write_text("\n".join(lines) + "\n", encoding="utf-8")
    print("\n".join(lines))


def _slope_exponent(per_curve):
    """Least-squares ``d ln beta / d ln tan(theta)`` over the wedges, pressure by pressure."""
    out = {}
    for pH in sorted({p for (_, p) in per_curve}):
        pts = [
            (math.log(math.tan(math.radians(d))), math.log(b))
            for (n, p), (b, d) in per_curve.items()
            if p == pH and n.startswith("wedge")
        ]
        out[pH] = float(np.polyfit(*zip(*pts, strict=True), 1)[0])
    return out


def report(rows, per_curve, truth_name, H):
    """The Markdown summary of the splits."""

    def worst(split, key):
        return max(r[key] for r in rows if r["split"] == split)

    def n_in(split, key):
        sel = [r for r in rows if r["split"] == split]
        return sum(r[key] <= BAR for r in sel), len(sel)

    lines = [
        "# The flattening law's beta fitted to the FE asperity truth, held out",
        "",
        f"`benchmarks/flattening_truth_fit.py`, truth `{truth_name}`; H = {H / 1e6:.1f} MPa; "
        "`beta` fitted with `halfspace-calib --flattening-data`'s `fit_beta`; misses are "
        f"|alpha_law - alpha_truth| on held-out curves (the bar: {BAR}).",
        "",
        "| split | held-out largest miss, fitted beta | beta = 1 | held-out RMS, fitted | "
        "beta = 1 | rows within the bar, fitted | beta = 1 |",
        "|---|---|---|---|---|---|---|",
    ]
    for split in ("pressure", "slope", "beta(p)", "per curve"):
        a, n = n_in(split, "max_abs_miss")
        b, _ = n_in(split, "max_abs_miss_beta1")
        sel = [r for r in rows if r["split"] == split]
        rm = math.sqrt(np.mean([r["rms_miss"] ** 2 for r in sel]))
        r1 = math.sqrt(np.mean([r["rms_miss_beta1"] ** 2 for r in sel]))
        lines.append(
            f"| {split} | {worst(split, 'max_abs_miss'):.3f} | "
            f"{worst(split, 'max_abs_miss_beta1'):.3f} | {rm:.3f} | {r1:.3f} | {a} of {n} | "
            f"{b} of {n} |"
        )
    lines += ["", "## Pressure split (per profile: fitted on one fold, the other predicted)", ""]
    lines += [
        "| profile | fitted on | beta | held out | largest miss | beta = 1 |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r["split"] == "pressure":
            lines.append(
                f"| {r['profile']} | {r['trained_on']} | {r['beta']:.2f} | "
                f"{r['held_out_p_over_H']} | {r['max_abs_miss']:.3f} | "
                f"{r['max_abs_miss_beta1']:.3f} |"
            )
    lines += ["", "## Slope split (fitted on one profile, all pressures; the others predicted)", ""]
    lines += ["| fitted on | beta | predicted | largest miss | beta = 1 |", "|---|---|---|---|---|"]
    for r in rows:
        if r["split"] == "slope":
            lines.append(
                f"| {r['trained_on']} | {r['beta']:.2f} | {r['profile']} | "
                f"{r['max_abs_miss']:.3f} | {r['max_abs_miss_beta1']:.3f} |"
            )
    profiles = list(dict.fromkeys(n for (n, _) in per_curve))
    ps = sorted({p for (_, p) in per_curve})
    lines += ["", "## The best beta of each curve alone (and its miss)", ""]
    lines += ["| profile | " + " | ".join(f"p/H {p:g}" for p in ps) + " |"]
    lines += ["|---" * (len(ps) + 1) + "|"]
    best_miss = {
        (r["profile"], float(r["held_out_p_over_H"])): r["max_abs_miss"]
        for r in rows
        if r["split"] == "per curve"
    }
    for n in profiles:
        cells = [f"{per_curve[(n, p)][0]:.2f} ({best_miss[(n, p)]:.3f})" for p in ps]
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    ex = _slope_exponent(per_curve)
    lines += [
        "",
        "d ln beta / d ln tan(theta) over the wedges (3-10 deg), by p / H: "
        + ", ".join(f"{p:g}: {v:+.2f}" for p, v in ex.items()),
        "",
        "## Pressure-dependent beta (ln beta linear in p / H, fitted on one fold's per-curve betas)",
        "",
    ]
    for tag in dict.fromkeys(r["trained_on"] for r in rows if r["split"] == "beta(p)"):
        sel = [r for r in rows if r["trained_on"] == tag]
        lines.append(
            f"- {tag}: held-out largest miss {max(r['max_abs_miss'] for r in sel):.3f} "
            f"(beta = 1: {max(r['max_abs_miss_beta1'] for r in sel):.3f}), "
            f"{sum(r['max_abs_miss'] <= BAR for r in sel)} of {len(sel)} curves within the bar"
        )
    return lines


if __name__ == "__main__":
    with run_record(__file__):
        main()
