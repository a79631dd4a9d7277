"""The flattening law against the FE asperity truth (issue 43): nothing fitted to it.

Reads part B's table of the contact fraction against bulk strain at constant pressure
(``benchmarks/asperity_flattening.py``'s CSV: wedges of 3-10 deg and a measured row, pressures
0.05-0.6 H, strains 0-0.5, a plane-strain elastic-perfectly plastic strip under a rigid
frictionless flat) and puts the law's ``frictionlaw.flattening_curve`` beside it. The law of
each profile is built from the truth's inputs only:

- ``H``: the truth's hardness, ``(2 + pi) k`` with ``k = sigma_y / sqrt(3)`` (its von Mises
  material); the law's ``k`` the same ``sigma_y / sqrt(3)``, so the layer's ``s0 = 2 k`` is the
  strip's plane-strain flow stress;
- ``alpha1``: the truth's own contact fraction after pressing alone (its strain-0 column) as the
  tabulated first loading, so that the comparison measures the flattening model and not the
  first loading (the law equals the truth at zero strain by construction);
- the flattening block: ``tan(theta)`` the wedge's flank slope (the measured row: its RMS slope),
  ``beta = 1``, the model's default. Nothing is fitted to the truth's strain columns;
- the strain: the truth's is the plane-strain stretch ``ln(L / L0)`` across the ridges; the law
  takes what a host passes, the equivalent (von Mises) plastic strain, ``2 / sqrt(3)`` of the
  stretch (:func:`law_strain`; the stretch's elastic part, at most about 8e-4, is counted as
  plastic).

Run: python benchmarks/flattening_truth.py [--truth CSV]
Writes benchmarks/results/flattening_truth.csv, .md and .png.
"""

import argparse
import csv
import math
from pathlib import Path

import numpy as np
from _provenance import run_record

import frictionlaw as fl
from frictionlaw.first_loading import FirstLoadingTable

RESULTS = Path(__file__).parent / "results"
BAR = 0.05  # the bar on |alpha_law - alpha_truth|
#: a plane-strain stretch's von Mises equivalent strain per unit stretch
EQUIVALENT_PER_STRETCH = 2.0 / math.sqrt(3.0)


def curve_misses(sel, column, key=("profile", "p_over_H")):
    """Misses of ``column`` against ``alpha_truth`` over the rows ``sel`` (dicts), a curve being
    the rows sharing ``key``: ``(largest, RMS over the rows, curves whose largest is within
    BAR, curves)``."""
    worst = {}
    for r in sel:
        k = tuple(r[f] for f in key)
        worst[k] = max(worst.get(k, 0.0), abs(r[column] - r["alpha_truth"]))
    rms = math.sqrt(np.mean([(r[column] - r["alpha_truth"]) ** 2 for r in sel]))
    return max(worst.values()), rms, sum(w <= BAR for w in worst.values()), len(worst)


def law_strain(stretch):
    """The equivalent plastic strain a host passes for the truth's plane-strain ``stretch``."""
    return EQUIVALENT_PER_STRETCH * np.asarray(stretch, dtype=float)


def read_truth(path):
    """``{(profile, slope_deg): {p_over_H: {strain: alpha}}}`` and the material's ``sigma_y``."""
    out = {}
    for r in csv.DictReader(Path(path).open(encoding="utf-8")):
        key = (r["profile"], float(r["slope_deg"]))
        row = out.setdefault(key, {}).setdefault(float(r["p_over_H"]), {})
        row[float(r["strain"])] = float(r["alpha"])
        H = float(r["p_Pa"]) / float(r["p_over_H"])
    return out, H


def law_of(table, slope_deg, H):
    """The law built from the truth's inputs (module text); nothing from its strain columns."""
    sigma_y = H * math.sqrt(3) / (2 + math.pi)
    ps = sorted(table)
    first = FirstLoadingTable(p=tuple(p * H for p in ps), alpha=tuple(table[p][0.0] for p in ps))
    return fl.FrictionParams(
        m=1.0,
        sigma_y=sigma_y,
        H=H,
        k=sigma_y / math.sqrt(3),
        C1=1.0,
        n1=2.0,
        C2=3.0,
        n2=1.0,
        first_loading_form="tabulated",
        first_loading_table=first,
        flattening=fl.Flattening(slope=math.tan(math.radians(slope_deg))),
    )


def truth_args(doc, out_stem, argv=None):
    """``--truth`` and ``--out`` parsed, the truth read and the law of each profile built.

    Returns ``(args, truth, H, laws)``, ``laws`` keyed as ``truth`` (``law_of`` of each profile).
    """
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--truth", default=str(RESULTS / "asperity_flattening.csv"))
    ap.add_argument("--out", default=str(RESULTS / out_stem))
    args = ap.parse_args(argv)
    truth, H = read_truth(args.truth)
    return args, truth, H, {key: law_of(table, key[1], H) for key, table in truth.items()}


def strain_at(strains, alpha, level):
    """The strain at which ``alpha`` first reaches ``level`` (linear between points; nan if never)."""
    for i in range(1, len(strains)):
        if alpha[i] >= level > alpha[i - 1]:
            w = (level - alpha[i - 1]) / (alpha[i] - alpha[i - 1])
            return strains[i - 1] + w * (strains[i] - strains[i - 1])
    return math.nan


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--truth", default=str(RESULTS / "asperity_flattening.csv"))
    ap.add_argument("--out", default=str(RESULTS / "flattening_truth"))
    args = ap.parse_args(argv)
    truth, H = read_truth(args.truth)
    rows, summary = [], []
    for (name, deg), table in truth.items():
        P = law_of(table, deg, H)
        for p_over_H, col in sorted(table.items()):
            strains = sorted(col)
            a_true = np.array([col[e] for e in strains])
            a_law = fl.flattening_curve(p_over_H * H, law_strain(strains), P)
            for e, t, w in zip(strains, a_true, a_law, strict=True):
                rows.append(
                    {
                        "profile": name,
                        "slope_deg": deg,
                        "p_over_H": p_over_H,
                        "strain": e,
                        "alpha_truth": t,
                        "alpha_law": float(w),
                        "difference": float(w - t),
                    }
                )
            d = a_law - a_true
            k = int(np.argmax(np.abs(d)))
            summary.append(
                {
                    "profile": name,
                    "p_over_H": p_over_H,
                    "max_abs_difference": float(np.abs(d).max()),
                    "at_strain": strains[k],
                    "strain_to_half_truth": strain_at(strains, a_true, 0.5),
                    "strain_to_half_law": strain_at(strains, a_law, 0.5),
                    "strain_to_0.9_truth": strain_at(strains, a_true, 0.9),
                    "strain_to_0.9_law": strain_at(strains, a_law, 0.9),
                }
            )
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.with_suffix(".csv").open("w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    worst = max(s["max_abs_difference"] for s in summary)
    n_pass = sum(s["max_abs_difference"] <= BAR for s in summary)
    lines = [
        "# The flattening law against the FE asperity truth (nothing fitted)",
        "",
        f"`benchmarks/flattening_truth.py`, truth `{Path(args.truth).name}`; H = {H / 1e6:.1f} MPa;"
        f" the law: the truth's pressing-alone alpha as alpha1, tan(theta) of the profile, beta = 1.",
        "",
        f"**Largest |alpha_law - alpha_truth|: {worst:.3f}** (the bar: {BAR}); "
        f"{n_pass} of {len(summary)} pressure-profile curves within it.",
        "",
        "| profile | p / H | max abs difference | at strain | strain to alpha 0.5: truth | law "
        "| strain to 0.9: truth | law |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for s in summary:
        lines.append(
            f"| {s['profile']} | {s['p_over_H']:g} | {s['max_abs_difference']:.3f} | "
            f"{s['at_strain']:g} | {s['strain_to_half_truth']:.4f} | {s['strain_to_half_law']:.4f} | "
            f"{s['strain_to_0.9_truth']:.4f} | {s['strain_to_0.9_law']:.4f} |"
        )
    refined = Path(args.truth).with_name("asperity_refined.csv")
    if refined.exists():
        lines += _against_refined(truth, H, refined)
    low = Path(args.truth).with_name("asperity_low.csv")
    if low.exists():
        lines += _against_low(truth, H, low)
    out.with_suffix(".md").write_text("\n".join(lines) + "\n", encoding="utf-8")
    _figure(truth, rows, out.with_suffix(".png"))
    print("\n".join(lines))


def _against_refined(truth, H, path):
    """The law's miss against the fine-mesh truth where it was run (``--refine``), beside its miss
    against the table's mesh at the same strains; the law as above (the table's alpha1)."""
    fine, _ = read_truth(path)
    lines = [
        "",
        f"## Against the fine mesh ({path.name}: 128 x 48, the table 64 x 32)",
        "",
        "The law unchanged (alpha1 from the table's pressing); the fine truth's own zero-strain "
        "alpha differs from the table's by its first column's change.",
        "",
        "| profile | p / H | fine - table, largest | law - table, largest | law - fine, largest |",
        "|---|---|---|---|---|",
    ]
    for key, ftab in fine.items():
        if key not in truth:
            continue
        P = law_of(truth[key], key[1], H)
        for ph, col in sorted(ftab.items()):
            e = [x for x in sorted(col) if x in truth[key][ph]]
            a_f = np.array([col[x] for x in e])
            a_t = np.array([truth[key][ph][x] for x in e])
            a_l = fl.flattening_curve(ph * H, law_strain(e), P)
            lines.append(
                f"| {key[0]} | {ph:g} | {_signed(a_f - a_t)} | {_signed(a_l - a_t)} | "
                f"{_signed(a_l - a_f)} |"
            )
    return lines


LOW_REPORT = (0.005, 0.01, 0.02, 0.05, 0.1)


def low_curves(path):
    """The curves of ``asperity_low.py``'s CSV at ``path``: ``(profile, slope_deg, p/H, nx, nz,
    {strain: alpha})``, in the file's order."""
    low = list(csv.DictReader(Path(path).open(encoding="utf-8")))
    keys = dict.fromkeys(
        (r["profile"], float(r["slope_deg"]), float(r["p_over_H"]), r["nx"], r["nz"]) for r in low
    )
    return [
        (
            *k,
            {
                float(r["strain"]): float(r["alpha"])
                for r in low
                if (r["profile"], float(r["p_over_H"]), r["nx"]) == (k[0], k[2], k[3])
            },
        )
        for k in keys
    ]


def low_law(truth, H, name, deg, ph, col):
    """The law for a curve below the table: ``alpha1`` the table's pressing-alone fractions
    (``truth``, :func:`read_truth`) and the curve's own ``col[0]`` at ``ph``; nothing from its
    strain columns."""
    table = dict(truth[(name, deg)])
    table[ph] = col
    return law_of(table, deg, H)


def _against_low(truth, H, path):
    """The law's miss below the table (``asperity_low.py``: 0.02 H on finer meshes): ``alpha1``
    the table's pressing fractions and the low run's own (each mesh its own), nothing fitted."""
    lines = [
        "",
        f"## Below the table ({path.name})",
        "",
        "The law's alpha1: the table's pressing-alone fractions and the low run's own at its "
        "pressure and mesh; tan(theta) and beta as above. alpha truth / law after each strain.",
        "",
        "| profile | p / H | mesh | "
        + " | ".join(f"{e:g}" for e in LOW_REPORT)
        + " | largest miss | at strain |",
        "|---|---|---|" + "---|" * len(LOW_REPORT) + "---|---|",
    ]
    for name, deg, ph, nx, nz, col in low_curves(path):
        strains = sorted(col)
        a_t = np.array([col[e] for e in strains])
        a_l = fl.flattening_curve(
            ph * H, law_strain(strains), low_law(truth, H, name, deg, ph, col)
        )
        k = int(np.argmax(np.abs(a_l - a_t)))
        by = dict(zip(strains, zip(a_t, a_l, strict=True), strict=True))
        lines.append(
            f"| {name} | {ph:g} | {nx} x {nz} | "
            + " | ".join(f"{by[e][0]:.3f} / {by[e][1]:.3f}" for e in LOW_REPORT)
            + f" | {a_l[k] - a_t[k]:+.3f} | {strains[k]:g} |"
        )
    return lines


def _signed(d):
    """The entry of largest magnitude, with its sign."""
    return f"{float(d[int(np.argmax(np.abs(d)))]):+.3f}"


def _figure(truth, rows, path):
    from matplotlib.figure import Figure

    keys = list(truth)
    ncol = 3
    nrow = -(-len(keys) // ncol)
    fig = Figure(figsize=(12, 3.4 * nrow))
    axes = np.atleast_1d(fig.subplots(nrow, ncol, sharey=True)).ravel()
    for ax in axes[len(keys) :]:
        ax.set_visible(False)
    for ax, (name, deg) in zip(axes, keys, strict=False):
        for i, p in enumerate(sorted(truth[(name, deg)])):
            sel = [r for r in rows if r["profile"] == name and r["p_over_H"] == p]
            e = [r["strain"] for r in sel]
            c = f"C{i}"
            ax.plot(e, [r["alpha_truth"] for r in sel], "o", color=c, ms=3)
            ax.plot(e, [r["alpha_law"] for r in sel], "-", color=c, label=f"p/H {p:g}")
        ax.set_xscale("symlog", linthresh=0.005)
        ax.set_xlabel("bulk strain (1)")
        ax.set_title(f"{name}", fontsize=9)
        ax.grid(alpha=0.3)
    for ax in axes[::ncol]:
        ax.set_ylabel("contact fraction alpha (1)")
    axes[0].legend(fontsize=7)
    fig.suptitle("FE asperity truth (dots) and the flattening law (lines), nothing fitted")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    with run_record(__file__):
        main()
