"""Time each effect adds to the default calibration (128 x 128, Table 1, nine pressures).

Runs the default scene with ``effects = ("normal",)`` and then with each of ``tangential``,
``inclined`` and ``sliding`` added (one run each), writes
``benchmarks/results/effects_timing.csv`` and the default scene's tangential stiffness table
(``effects_tangential.csv``), and prints both as markdown.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/effects_timing.py [--grid 128] [--skip-sliding]``
"""

import argparse
import csv
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _provenance import run_record

from halfspace_calib.output.effects import write_stiffness_csv  # noqa: E402
from halfspace_calib.pipeline.calibration import Scene, calibrate  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--grid", type=int, default=128)
    ap.add_argument("--skip-sliding", action="store_true")
    args = ap.parse_args()
    sets = [("normal",), ("normal", "tangential"), ("normal", "inclined")]
    if not args.skip_sliding:
        sets.append(("normal", "sliding"))
    rows, cals = [], {}
    for eff in sets:
        t0 = time.perf_counter()
        cal = calibrate(Scene(grid=args.grid, effects=eff), progress=False)
        secs = time.perf_counter() - t0
        cals[eff[-1]] = cal
        outcome = cal.effects.get(eff[-1])
        inner = outcome.seconds if outcome is not None else 0.0
        rows.append(["+".join(eff), round(secs, 2), round(inner, 2)])
        print(f"{'+'.join(eff)}: {secs:.1f} s (effect itself {inner:.1f} s)", flush=True)
    base = rows[0][1]
    with open(OUT / "effects_timing.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                "effects",
                "seconds",
                "effect_seconds",
                "added_seconds",
                "grid",
                "OPENBLAS_NUM_THREADS",
                "load_avg_1min",
            ]
        )
        for r in rows:
            w.writerow(
                r
                + [
                    round(r[1] - base, 2),
                    args.grid,
                    os.environ.get("OPENBLAS_NUM_THREADS", ""),
                    os.getloadavg()[0],
                ]
            )
    print("\n| effects | calibration (s) | the effect's own time (s) | added to normal only (s) |")
    print("|---|---|---|---|")
    for r in rows:
        print(f"| {r[0]} | {r[1]:.1f} | {r[2]:.1f} | {r[1] - base:+.1f} |")

    t = cals["tangential"].effects["tangential"].summary
    write_stiffness_csv(t, OUT / "effects_tangential.csv")
    print(
        "\n| p_mean (MPa) | alpha | tau_adh = q at full sliding (MPa) | delta_stick (nm) | "
        "delta_full (nm) | k_t0 (Pa/m) | k_eq (Pa/m) | k_sec (Pa/m) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for r in t["rows"]:
        print(
            f"| {r['p_mean'] / 1e6:.0f} | {r['alpha']:.3f} | {r['q_limit'] / 1e6:.2f} | "
            f"{r['delta_stick'] * 1e9:.2f} | {r['delta_full'] * 1e9:.1f} | {r['k_t0']:.3e} | "
            f"{r['k_eq']:.3e} | {r['k_sec']:.3e} |"
        )
    for k in ("k_t0_fit", "k_eq_fit", "k_sec_fit"):
        f = t[k]
        print(
            f"{k}: {f['k_ref']:.3e} (p / 100 MPa)^{f['exponent']:.3f}, max error "
            f"{100 * f['max_rel_error']:.0f} %"
        )
    print(f"full sliding vs shortcut: max rel. diff {t['full_sliding_max_rel_diff']:.1e}")
    inc = cals["inclined"].effects["inclined"].decision
    print(f"inclined (default scene, smooth tool): {inc.reason}")
    print(f"recommendation: {t['recommendation']}")


if __name__ == "__main__":
    with run_record(__file__):
        main()
