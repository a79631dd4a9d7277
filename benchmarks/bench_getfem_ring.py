"""Ring compression (6:3:2) in GetFEM with the runtime law vs ``fe-demo ring``.

Cases: Tresca m = 0.3 and the calibrated SBMF law (``params.json`` of the default
calibration, ``halfspace-calib``'s main job, run here first; or ``--params``), on the
same r-z mesh (``--nr`` across the wall, near-square elements) and the same 50
increments to 50 %. Writes benchmarks/results/getfem_ring.csv/.md (at 30 and 50 %),
getfem_ring_stroke.csv/.md (force and inner-diameter differences over every GetFEM
increment beyond 5 %), the GetFEM runs' history.csv and summary.json under
getfem_ring_<law>/, and prints the tables. ``--sector-study``: the wedge-angle knob only
(getfem_ring_sector.csv/.md).
Run: python benchmarks/bench_getfem_ring.py [--nr 16] [--params FILE]
"""

import argparse
import csv
import json
import shutil
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from couplings.getfem.compare import (  # noqa: E402
    at_reductions,
    getfem_missing,
    read_history,
    run_getfem_ring,
)
from fe_demo.scenes import run_ring  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"
AT = (0.3, 0.5)


def default_calibration(out):
    """``params.json`` of the default calibration (the README's main job)."""
    from halfspace_calib.cli import main as calib_main

    if calib_main(["--out", str(out)]) != 0:
        raise RuntimeError("the default calibration failed")
    return out / "params.json"


def one_case(law, m, params, nr, n_inc, work):
    args = ["--law", law, "--nr", str(nr), "--increments", str(n_inc)]
    args += ["--m", str(m)] if law == "tresca" else ["--params", params]
    rc, wall_g, log = run_getfem_ring(work / f"getfem_{law}", args)
    if rc != 0:
        raise RuntimeError(f"GetFEM ring ({law}) failed with exit {rc}:\n{log[-2000:]}")
    hg = read_history(work / f"getfem_{law}" / "history.csv")
    summary = json.loads((work / f"getfem_{law}" / "summary.json").read_text())
    keep = OUT / f"getfem_ring_{law}"
    keep.mkdir(parents=True, exist_ok=True)
    for name in ("history.csv", "summary.json"):
        shutil.copyfile(work / f"getfem_{law}" / name, keep / name)
    t0 = time.perf_counter()
    res = run_ring(law, m=m, params=params or None, nr=nr, n_increments=n_inc, reduction=0.5)
    wall_f = time.perf_counter() - t0
    if not res.converged:
        raise RuntimeError(f"fe-demo ring ({law}) failed: {res.message}")
    fg, dg = at_reductions(hg, AT)
    ff, df = at_reductions(res.history, AT)
    red = hg["height_reduction"]
    fe_f, fe_d = at_reductions(res.history, list(red))
    on = red > 0.05
    rel = hg["force"][on] / fe_f[on] - 1
    stroke = {
        "case": "tresca m=0.3" if law == "tresca" else "sbmf",
        "force_diff_median_pct": round(100 * float(np.median(rel)), 2),
        "force_diff_min_pct": round(100 * float(rel.min()), 2),
        "force_diff_max_pct": round(100 * float(rel.max()), 2),
        "increments_beyond_3pct": int(np.sum(np.abs(rel) > 0.03)),
        "increments_compared": int(on.sum()),
        "dDi_max_abs_diff_pct_points": round(
            100 * float(np.abs(hg["inner_diameter_change"] - fe_d).max()), 2
        ),
    }
    rows = []
    fg, dg, ff, df = (np.asarray(x, float).tolist() for x in (fg, dg, ff, df))
    for a, fg_, dg_, ff_, df_ in zip(AT, fg, dg, ff, df, strict=True):
        rows.append(
            {
                "case": "tresca m=0.3" if law == "tresca" else "sbmf",
                "reduction": a,
                "getfem_force_kN": round(fg_ / 1e3, 2),
                "fe_demo_force_kN": round(ff_ / 1e3, 2),
                "force_diff_pct": round(100 * (fg_ - ff_) / ff_, 2),
                "getfem_dDi_pct": round(100 * dg_, 2),
                "fe_demo_dDi_pct": round(100 * df_, 2),
                "dDi_diff_pct_points": round(100 * (dg_ - df_), 2),
                "getfem_wall_s": round(wall_g, 1),
                "fe_demo_wall_s": round(wall_f, 1),
                "getfem_increments": int(hg["height_reduction"].size),
                "getfem_newton_its": int(summary["newton_iterations"]),
                "getfem_cutbacks": len(summary["cutback_log"]),
                "fe_demo_newton_its": int(res.info["newton_iterations"]),
            }
        )
    return rows, stroke


def sector_study(work, sectors=(2.5, 5.0, 10.0, 20.0), nr=8, n_inc=15):
    """The wedge angle knob: Tresca m = 0.3 to 30 % on an ``nr``-wide grid."""
    rows = []
    for sec in sectors:
        args = ["--law", "tresca", "--m", "0.3", "--nr", str(nr), "--increments", str(n_inc)]
        args += ["--reduction", "0.3", "--sector", str(sec)]
        rc, wall, log = run_getfem_ring(work / f"sector_{sec:g}", args)
        if rc != 0:
            raise RuntimeError(f"GetFEM ring (sector {sec}) failed with exit {rc}:\n{log[-2000:]}")
        h = read_history(work / f"sector_{sec:g}" / "history.csv")
        f, d = at_reductions(h, [0.3])
        rows.append(
            {
                "sector_deg": sec,
                "force_kN_at_0.3": round(float(f[0]) / 1e3, 2),
                "dDi_pct_at_0.3": round(100 * float(d[0]), 2),
                "increments": int(h["height_reduction"].size),
                "wall_s": round(wall, 1),
            }
        )
        print(rows[-1], flush=True)
    return rows


def write_table(stem, rows):
    with open(OUT / f"{stem}.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    cols = list(rows[0])
    md = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    md += ["| " + " | ".join(str(r[c]) for c in cols) + " |" for r in rows]
    text = "\n".join(md) + "\n"
    (OUT / f"{stem}.md").write_text(text)
    print(text)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nr", type=int, default=16)
    ap.add_argument("--increments", type=int, default=50)
    ap.add_argument("--params", default="")
    ap.add_argument(
        "--sector-study",
        action="store_true",
        help="only the wedge-angle table (8-wide grid, 30 %%)",
    )
    a = ap.parse_args(argv)
    why = getfem_missing()
    if why:
        print(f"skipped: {why}")
        return 1
    if a.sector_study:
        OUT.mkdir(exist_ok=True)
        with tempfile.TemporaryDirectory() as tmp:
            write_table("getfem_ring_sector", sector_study(Path(tmp)))
        return 0
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        params = a.params or default_calibration(Path(tmp) / "calibration")
        keep = OUT / "getfem_ring_sbmf"
        keep.mkdir(parents=True, exist_ok=True)
        if Path(params).resolve() != (keep / "params.json").resolve():
            shutil.copyfile(params, keep / "params.json")
        strokes = []
        for law in ("tresca", "sbmf"):
            r, st = one_case(law, 0.3, str(params), a.nr, a.increments, Path(tmp))
            rows += r
            strokes.append(st)
            print(*r, st, sep="\n", flush=True)
    OUT.mkdir(exist_ok=True)
    write_table("getfem_ring", rows)
    write_table("getfem_ring_stroke", strokes)
    return 0


if __name__ == "__main__":
    sys.exit(main())
