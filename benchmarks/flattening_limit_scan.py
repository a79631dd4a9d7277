"""The calibration's two-state block against the surface's truth (issue 43).

``flattening_limit_rows.py`` gives the law each row's own geometry. A calibration writes one
block for the whole workpiece: its RMS slope and its edge-slope table (``edge_slope``,
``halfspace_calib.pipeline.sweep.flattening_edges``) from the scan on its grid. This script
takes the scan the truth rows come from (matrix-3, levelled and S-filtered as
``asperity_flattening.measured_profile`` does), builds both blocks with the calibration's own
functions (``rms_slope``, ``edge_slope_table``) and runs the runtime's two-state law
(``flattening_curve``) with each, ``alpha1`` each row's pressing-alone fractions as
``flattening_truth.law_of`` builds it, nothing fitted. It compares

- **the surface**: the mean over the rows run at a pressure (7 at 0.05 and 0.1 ``H``: rows 32,
  64, 96, 128, 160, 192, 224; 5 at 0.2-0.6 ``H``: 32, 96, 128, 160, 224) of the truth's contact
  fraction against the mean of the law's, at each reported strain: what one block per surface
  is for;
- **each row**: the same curves against each row's truth, where the rows' spread (RMS slopes
  1.5-3.8 deg about the scan's 3.1) is part of the miss.

Writes ``results/flattening_limit_scan.md`` / ``.csv`` / ``.png`` (a panel per pressure: each
row's truth, faint; the rows' mean; the law's mean with each block).

Run: python benchmarks/flattening_limit_scan.py (after asperity_flattening.py --no-table --rows
and --held-out)
"""

import collections
import math

import numpy as np
from _provenance import RESULTS, run_record, write_rows
from asperity_flattening import MEASURED
from flattening_limit_rows import truth_rows
from flattening_truth import curve_misses, law_strain

import frictionlaw as fl
from halfspace_calib.pipeline.sweep.flattening import rms_slope
from halfspace_calib.pipeline.sweep.flattening_edges import edge_slope_table
from halfspace_calib.pipeline.sweep.length_scale import default_lambda_s
from halfspace_calib.pipeline.sweep.surface_plan import MAX_DEFAULT_GRID
from halfspace_calib.topography import chain, read_surface

BLOCKS = ("edge_slope", "rms_slope")


def scan_surface():
    """The scan levelled and S-filtered as the truth's rows are (``measured_profile``)."""
    scan = read_surface(MEASURED)
    side = min(scan.heights.shape[0] * scan.dx, scan.heights.shape[1] * scan.dy)
    lam = default_lambda_s(side, max(scan.dx, scan.dy), MAX_DEFAULT_GRID)
    levelled, _ = chain.level_scan(scan)
    filtered, _ = chain.filter_scan(levelled, lam, None)
    return filtered


def blocks(surface):
    """The two blocks a calibration would write for ``surface``: with and without the table."""
    slope = rms_slope(surface)[0]
    edge = edge_slope_table(surface)
    return {
        "edge_slope": fl.Flattening(slope, model="limit-analysis", edge_slope=edge),
        "rms_slope": fl.Flattening(slope, model="limit-analysis"),
    }


def row_curves(curves_at, digits=None):
    """One row per (truth row, p/H, strain): ``curves_at(law, x, z, p, eps)`` gives ``{name:
    alpha at eps}`` for the row's law (``truth_rows``), its profile and each pressure; written
    as ``alpha_<name>`` beside the truth (rounded to ``digits`` when given)."""
    out = []
    for held, name, x, z, _, H_row, cols, law, _ in truth_rows():
        for ph in sorted(cols):
            strains = sorted(cols[ph])
            got = curves_at(law, x, z, ph * H_row, law_strain(strains))
            out += [
                {
                    "profile": name,
                    "held_out": held,
                    "p_over_H": ph,
                    "strain": e,
                    "alpha_truth": cols[ph][e],
                    **{
                        f"alpha_{k}": float(v[i]) if digits is None else round(float(v[i]), digits)
                        for k, v in got.items()
                    },
                }
                for i, e in enumerate(strains)
            ]
    return out


def curves(flats):
    """Every truth row's curves with each block: one row per (row, p/H, strain)."""

    def at(law, x, z, p, eps):
        return {k: fl.flattening_curve(p, eps, law.replace(flattening=f)) for k, f in flats.items()}

    return row_curves(at, digits=5)


def surface_means(out):
    """``{p/H: (rows, strains, truth mean, {block: law mean})}`` over the rows of a pressure, at
    the strains every one of them reports."""
    by_p = collections.defaultdict(lambda: collections.defaultdict(dict))
    for r in out:
        by_p[r["p_over_H"]][r["profile"]][r["strain"]] = r
    res = {}
    for ph, rows in sorted(by_p.items()):
        strains = sorted(set.intersection(*(set(v) for v in rows.values())))
        truth = np.array([[rows[n][e]["alpha_truth"] for e in strains] for n in rows]).mean(0)
        law = {
            k: np.array([[rows[n][e][f"alpha_{k}"] for e in strains] for n in rows]).mean(0)
            for k in BLOCKS
        }
        res[ph] = (len(rows), strains, truth, law)
    return res


def _row_misses(sel, key):
    """``largest / RMS / n of m`` curves (row, p/H) within 0.05, of column ``key``."""
    worst, rms, within, n = curve_misses(sel, key)
    return f"{worst:.3f} / {rms:.3f} / {within} of {n}"


def report(flats, out):
    means = surface_means(out)
    e = flats["edge_slope"].edge_slope
    lines = [
        "# The calibration's two-state block against the surface's truth",
        "",
        "`benchmarks/flattening_limit_scan.py`: the blocks a calibration writes for the scan the "
        "truth rows come from (RMS slope "
        f"{flats['rms_slope'].slope:.4f}; edge slope {min(e):.4f}-{max(e):.4f}, mean "
        f"{np.mean(e):.4f}, at {len(e)} contact fractions), the runtime's two-state law with "
        "each, `alpha1` each row's pressing-alone fractions; nothing fitted.",
        "",
        "## The surface: mean over the rows",
        "",
        "| p/H | rows | strains | largest miss: with `edge_slope` | with the RMS slope only |",
        "|---|---|---|---|---|",
    ]
    tot = {k: [] for k in BLOCKS}
    for ph, (n, strains, truth, law) in means.items():
        d = {k: np.abs(law[k] - truth) for k in BLOCKS}
        for k in BLOCKS:
            tot[k].append(d[k])
        lines.append(
            f"| {ph:g} | {n} | {len(strains)} | {d['edge_slope'].max():.3f} | "
            f"{d['rms_slope'].max():.3f} |"
        )
    for k in BLOCKS:
        v = np.concatenate(tot[k])
        lines.append(
            f"| all | | | {k}: largest {v.max():.3f}, RMS {math.sqrt(np.mean(v * v)):.3f} | |"
        )
    lines += [
        "",
        "## Each row (largest miss / RMS / curves within 0.05)",
        "",
        "| rows | with `edge_slope` | with the RMS slope only |",
        "|---|---|---|",
    ]
    for label, sel in (
        ("of --rows (64, 128, 192)", [r for r in out if not r["held_out"]]),
        ("held out (32, 96, 160, 224)", [r for r in out if r["held_out"]]),
        ("all", out),
    ):
        lines.append(
            f"| {label} | {_row_misses(sel, 'alpha_edge_slope')} | "
            f"{_row_misses(sel, 'alpha_rms_slope')} |"
        )
    return lines


def figure(out, path):
    """A panel per pressure: each row's truth (faint), the rows' mean (dots), the law's mean with
    the scan's edge table (solid) and with its RMS slope only (dashed)."""
    from matplotlib.figure import Figure

    means = surface_means(out)
    fig = Figure(figsize=(13, 6.4))
    axes = fig.subplots(2, 3, sharey=True).ravel()
    for ax, (ph, (n, strains, truth, law)) in zip(axes, means.items(), strict=False):
        for name in dict.fromkeys(r["profile"] for r in out if r["p_over_H"] == ph):
            sel = [r for r in out if r["profile"] == name and r["p_over_H"] == ph]
            ax.plot([r["strain"] for r in sel], [r["alpha_truth"] for r in sel], "-",
                    color="0.8", lw=0.8)  # fmt: skip
        ax.plot(strains, truth, "ko", ms=4, label=f"truth, mean of {n} rows")
        ax.plot(strains, law["edge_slope"], "C0-", label="law, edge_slope")
        ax.plot(strains, law["rms_slope"], "C1--", label="law, RMS slope only")
        ax.set_xscale("symlog", linthresh=0.005)
        ax.set_title(f"p/H {ph:g}", fontsize=9)
        ax.set_xlabel("bulk strain (1)")
        ax.grid(alpha=0.3)
    for ax in axes[::3]:
        ax.set_ylabel("contact fraction alpha (1)")
    axes[0].legend(fontsize=7)
    fig.suptitle(
        "matrix-3: the FE truth's rows (grey) and their mean (dots) against the runtime's "
        "two-state law with the scan's one block, nothing fitted"
    )
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def main():
    flats = blocks(scan_surface())
    out = curves(flats)
    write_rows(RESULTS / "flattening_limit_scan.csv", out)
    figure(out, RESULTS / "flattening_limit_scan.png")
    lines = report(flats, out)
    (RESULTS / "flattening_limit_scan.md").write_text("\n".join(lines) + "\n", "utf-8")
    print("\n".join(lines))


if __name__ == "__main__":
    with run_record(__file__):
        main()
