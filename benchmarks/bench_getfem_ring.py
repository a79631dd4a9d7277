"""Ring compression (6:3:2) in GetFEM with the runtime law vs ``fe-demo ring``.

Cases: Tresca m = 0.3 and the calibrated SBMF law (``params.json`` of the default
calibration, ``halfspace-calib``'s main job, run here first; or ``--params``), on the
same r-z mesh (``--nr`` across the wall, near-square elements) and the same 50
increments to 50 %. Writes benchmarks/results/getfem_ring.csv/.md (at 30 and 50 %),
getfem_ring_stroke.csv/.md (force and inner-diameter differences over every GetFEM
increment beyond 5 %), the GetFEM runs' history.csv and summary.json under
getfem_ring_<law>/, and prints the tables. ``--sector-study``: the wedge-angle knob only
(getfem_ring_sector.csv/.md). ``--multistage``: press-lift-press only (Eq. 25 on the reload;
``fe-demo multistage``'s schedule: 30 %, lift, 45 %, 30 increments, on the ring), GetFEM against
fe-demo with and without ``p_hist``, with the SBMF parameter file of the ring case
(getfem_ring_multistage.csv/.md, getfem_ring_multistage_phist.csv, the GetFEM run under
getfem_ring_multistage/).
Run: python benchmarks/bench_getfem_ring.py [--nr 16] [--params FILE] [--multistage]
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
    SEGMENTS,
    at_reductions,
    fe_demo_ring_multistage,
    getfem_missing,
    multistage_agreement,
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


def multistage(params, nr, work, first=0.3, reduction=0.45, n_inc=30, n_unload=4):
    """Press-lift-press in both codes; returns (summary rows, p_hist rows)."""
    args = ["--law", "sbmf", "--params", str(params), "--nr", str(nr)]
    args += ["--increments", str(n_inc), "--reduction", str(reduction)]
    args += ["--first-reduction", str(first), "--unload", str(n_unload)]
    rc, wall_g, log = run_getfem_ring(work / "ms", args)
    if rc != 0:
        raise RuntimeError(f"GetFEM press-lift-press failed with exit {rc}:\n{log[-2000:]}")
    keep = OUT / "getfem_ring_multistage"
    keep.mkdir(parents=True, exist_ok=True)
    for name in ("history.csv", "summary.json"):
        shutil.copyfile(work / "ms" / name, keep / name)
    hg = read_history(work / "ms" / "history.csv")
    info = json.loads((work / "ms" / "summary.json").read_text())
    kw = dict(nr=nr, first_reduction=first, reduction=reduction, increments=n_inc)
    t0 = time.perf_counter()
    hf, pf = fe_demo_ring_multistage(params, n_unload=n_unload, **kw)
    wall_f = time.perf_counter() - t0
    hr, pr = fe_demo_ring_multistage(params, n_unload=n_unload, reset_history=True, **kw)
    a = multistage_agreement(hg, info["p_hist_profiles"], hf, pf)
    b = multistage_agreement(hg, info["p_hist_profiles"], hr, pr)
    rows = []
    for k, what in ((1, "first press"), (3, "re-contact + reload")):
        for tag, res in (("fe-demo (p_hist)", a), ("fe-demo (p_hist wiped)", b)):
            rel = res[f"force_rel_stage{k}"]
            rows.append(
                {
                    "stage": what,
                    "GetFEM against": tag,
                    "positions": int(rel.size),
                    "force_diff_median_pct": round(100 * float(np.median(rel)), 2),
                    "force_diff_max_abs_pct": round(100 * float(np.abs(rel).max()), 2),
                }
            )
    ph = []
    for name in SEGMENTS:
        d = a[f"p_hist_rel_{name}"]
        mx = a[f"p_hist_max_{name}"]
        ph.append(
            {
                "after": name,
                "max_p_hist_getfem_MPa": round(float(mx[0]) / 1e6, 1),
                "max_p_hist_fe_demo_MPa": round(float(mx[1]) / 1e6, 1),
                "p_hist_diff_max_abs_pct_of_max": round(100 * float(np.abs(d).max()), 2),
                "p_hist_diff_median_abs_pct_of_max": round(100 * float(np.median(np.abs(d))), 2),
            }
        )
    n_gf, n_fd = a["n_eq25_stage3"]
    print(
        f"Eq. 25 nodes in stage 3: GetFEM {int(n_gf)} (2 wedge faces), fe-demo {int(n_fd)}; "
        f"wall GetFEM {wall_g:.0f} s, fe-demo {wall_f:.1f} s; GetFEM cut-backs "
        f"{len(info['cutback_log'])}, Newton iterations {info['newton_iterations']}"
    )
    return rows, ph


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
    ap.add_argument(
        "--multistage",
        action="store_true",
        help="only press-lift-press (Eq. 25 on the reload), GetFEM against fe-demo",
    )
    a = ap.parse_args(argv)
    why = getfem_missing()
    if why:
        print(f"skipped: {why}")
        return 1
    if a.multistage:
        OUT.mkdir(exist_ok=True)
        params = a.params or OUT / "getfem_ring_sbmf" / "params.json"
        with tempfile.TemporaryDirectory() as tmp:
            rows, ph = multistage(params, a.nr, Path(tmp))
        write_table("getfem_ring_multistage", rows)
        write_table("getfem_ring_multistage_phist", ph)
        return 0
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
