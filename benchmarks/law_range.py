"""The law's range up to H (issue 26, item 5): the extended default sweep against the paper's.

For the default scene (synthetic Table 1 surfaces, H = 800 MPa) at ``--grid``:

1. the normal solver near full contact: every first-loading level of the default sweep
   (10-760 MPa = 0.95 H) with its iterations, whether it converged, and the half-space model's
   exact bound ``alpha >= p / H`` (every local pressure is at most H);
2. the fits of Eqs. 24-25 to the default sweep and to the paper's 10-600 MPa, each without and
   with the bound ``alpha1(p) >= p / H`` imposed up to 0.99 H (the default): parameters, R^2
   (the bound's cost), the largest violation of the bound up to the data's ``p_max`` and up to
   H, and ``alpha1(H)`` (Eq. 24 cannot reach 1 at H: ``tanh(C1**n1)**(1/n1) < 1``);
3. Fig. 16's shape with either sweep: ``alpha_rc`` rises linearly at small load (slope C1 / H),
   saturates towards 1, and the reload curves lie above first loading below ``p_hist``; the
   two laws compared at 10-600 MPa, and the figure ``law_range_fig16.png``.

Run: python benchmarks/law_range.py [--grid 128]
Writes benchmarks/results/law_range.md / .csv / _fig16.png and prints the tables.
"""

import argparse
import csv
import time
from pathlib import Path

import numpy as np
from _provenance import run_record

from frictionlaw import alpha_first, alpha_reload
from halfspace_calib.pipeline.calibration import Scene, calibrate
from halfspace_calib.pipeline.law import fit as F
from halfspace_calib.pipeline.sweep.scene import ALPHA_FLOOR, PAPER_PRESSURES

RESULTS = Path(__file__).parent / "results"
PROBES = (10e6, 100e6, 300e6, 600e6)


def _fits(cal, floor):
    """``(first, reload)`` refitted from ``cal``'s sweeps with the bound up to ``floor H``."""
    p, a = cal.sweeps.loading
    H = cal.scene.H
    first = F.fit_first_loading(p, a, H, floor_to=None if floor is None else floor * H)
    rel = F.fit_reload(cal.sweeps.reload_curves(), H, first.C1, first.n1)
    return first, rel


def _reload_above(law, curves):
    """Smallest ``alpha2(p) - alpha1(p)`` of the law on the curves' pressures (> 0: above)."""
    d = [float(np.min(alpha_reload(c.p, c.p_hist, law) - alpha_first(c.p, law))) for c in curves]
    return min(d)


def _data_above(cal):
    """Smallest reload ``alpha`` minus first-loading ``alpha`` (interpolated) in the data."""
    p, a = cal.sweeps.loading
    return min(float(np.min(c.alpha - np.interp(c.p, p, a))) for c in cal.sweeps.reload_curves())


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grid", type=int, default=128, help="grid (default %(default)s)")
    a = ap.parse_args(argv)
    cals, secs = {}, {}
    for name, kw in (("default", {}), ("paper", {"pressures": PAPER_PRESSURES})):
        t0 = time.perf_counter()
        cals[name] = calibrate(Scene(grid=a.grid, **kw), progress=False)
        secs[name] = time.perf_counter() - t0
    cal = cals["default"]
    H = cal.scene.H
    lines = [
        f"# The law's range up to H: synthetic Table 1 scene, {a.grid}^2, H = {H / 1e6:g} MPa",
        "",
        "## Normal solver near full contact (default sweep, first loading)",
        "",
        "| p_mean (MPa) | p/H | alpha | alpha - p/H | iterations | converged | max local p / H "
        "| seconds |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for lv in cal.sweeps.levels:
        r = lv.loading
        lines.append(
            f"| {lv.p_hist / 1e6:g} | {lv.p_hist / H:.3f} | {r.alpha:.4f} | "
            f"{r.alpha - lv.p_hist / H:+.4f} | {r.nit} | {r.converged} | "
            f"{r.max_pressure / H:.4f} | {lv.loading_seconds:.3f} |"
        )
    rows = []
    for name in ("paper", "default"):
        c = cals[name]
        for floor in (None, ALPHA_FLOOR):
            first, rel = _fits(c, floor)
            rec = first.floor_record()
            law = c.params.replace(C1=first.C1, n1=first.n1, C2=rel.C2, n2=rel.n2)
            rows.append(
                {
                    "sweep": name,
                    "p_max_MPa": first.p_max / 1e6,
                    "bound_to": "none" if floor is None else f"{floor:g} H",
                    "C1": first.C1,
                    "n1": first.n1,
                    "C2": rel.C2,
                    "n2": rel.n2,
                    "r2_first": first.r_squared,
                    "r2_reload": rel.r_squared,
                    "viol_to_p_max": rec["max_violation_to_p_max"],
                    "viol_to_H": rec["max_violation_to_H"],
                    "alpha1_H": rec["alpha1_at_H"],
                    "mu_eff": law.mu_eff,
                    "reload_above_first": _reload_above(law, c.sweeps.reload_curves()),
                    **{
                        f"tau_{p / 1e6:g}_MPa": law.tau_max * float(alpha_first(p, law)) / 1e6
                        for p in PROBES
                    },
                    "_law": law,
                }
            )
    RESULTS.mkdir(exist_ok=True)
    keys = [k for k in rows[0] if not k.startswith("_")]
    with open(RESULTS / "law_range.csv", "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(keys)
        wr.writerows([[r[k] for k in keys] for r in rows])
    lines += [
        "",
        "## Fits: the bound alpha1(p) >= p/H, its cost in R^2, and its violation",
        "",
        "| sweep | bound imposed up to | C1 | n1 | C2 | n2 | R^2 first | R^2 reload | largest "
        "p/H - alpha1 up to p_max | up to H | alpha1(H) | mu_eff |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['sweep']} (10-{r['p_max_MPa']:g} MPa) | {r['bound_to']} | {r['C1']:.4f} | "
            f"{r['n1']:.3f} | {r['C2']:.3f} | {r['n2']:.4f} | {r['r2_first']:.5f} | "
            f"{r['r2_reload']:.4f} | {r['viol_to_p_max']:.4f} | {r['viol_to_H']:.4f} | "
            f"{r['alpha1_H']:.4f} | {r['mu_eff']:.4f} |"
        )
    # Fig. 16's shape: the defaults (bound to 0.99 H) of both sweeps
    pa = next(r for r in rows if r["sweep"] == "paper" and r["bound_to"] != "none")
    de = next(r for r in rows if r["sweep"] == "default" and r["bound_to"] != "none")
    lines += [
        "",
        "## Fig. 16's shape with either sweep (bound up to 0.99 H)",
        "",
        "| quantity | paper sweep | default sweep | default vs paper |",
        "|---|---|---|---|",
    ]
    for p in PROBES:
        k = f"tau_{p / 1e6:g}_MPa"
        lines.append(
            f"| tau at {p / 1e6:g} MPa (MPa) | {pa[k]:.3f} | {de[k]:.3f} | "
            f"{100 * (de[k] / pa[k] - 1):+.2f} % |"
        )
    lines += [
        f"| initial slope C1 (Coulomb-like rise, alpha ~ C1 p / H) | {pa['C1']:.4f} | "
        f"{de['C1']:.4f} | {100 * (de['C1'] / pa['C1'] - 1):+.2f} % |",
        f"| reload above first loading: min alpha2 - alpha1 of the law | "
        f"{pa['reload_above_first']:+.4f} | {de['reload_above_first']:+.4f} | |",
        f"| reload above first loading: min in the half-space data | "
        f"{_data_above(cals['paper']):+.4f} | {_data_above(cals['default']):+.4f} | |",
        "",
        f"Time (wall, shared 2-core machine under load): default sweep {secs['default']:.1f} s, "
        f"paper sweep {secs['paper']:.1f} s (calibration incl. fits).",
    ]
    _figure(cals, pa["_law"], de["_law"], H)
    text = "\n".join(lines) + "\n"
    (RESULTS / "law_range.md").write_text(text)
    print(text)


def _figure(cals, law_paper, law_default, H):
    """Fig. 16 with both sweeps: half-space points, the two laws, reload curves."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 4.5))
    ax = fig.add_subplot()
    pp = np.linspace(1e6, 1.1 * H, 400)
    c = cals["default"]
    p, al = c.sweeps.loading
    ax.plot(p / 1e6, al, "ko", label="half-space, first loading (default sweep)")
    for cur in c.sweeps.reload_curves():
        ax.plot(cur.p / 1e6, cur.alpha, "k.", ms=4)
        q = np.linspace(cur.p.min(), cur.p_hist, 50)
        ax.plot(q / 1e6, alpha_reload(q, cur.p_hist, law_default), "C0-", lw=0.8)
    ax.plot(pp / 1e6, alpha_first(pp, law_default), "C0-", label="Eq. 24-25, default sweep")
    ax.plot(pp / 1e6, alpha_first(pp, law_paper), "C1--", label="Eq. 24, paper sweep (10-600 MPa)")
    ax.plot(pp / 1e6, np.minimum(pp / H, 1), "k:", lw=0.8, label="bound p / H")
    ax.axvline(H / 1e6, color="0.6", lw=0.8)
    ax.set_xlabel("p_mean (MPa)")
    ax.set_ylabel("alpha_rc = A_real / A0")
    ax.legend(fontsize=8, loc="lower right")
    fig.savefig(RESULTS / "law_range_fig16.png", dpi=110)


if __name__ == "__main__":
    with run_record(__file__):
        main()
