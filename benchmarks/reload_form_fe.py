"""What the reload law's form changes in FE: press, lift, press with the tabulated and the paper form.

One calibration (the default scene, or ``--params``) gives both laws: the tabulated reload form
the parameter file runs, and the paper's Eq. 25 fitted beside it
(``params.replace(reload_form="paper")``); first loading (Eq. 24) is the same in both. Each runs
the press-lift-press of ``fe-demo multistage`` (upset to 30 %, lift until every node has left the
die, reload to 45 %):

- fe-demo's cylinder (``fe_demo.scenes.run_multistage``),
- fe-demo's 6:3:2 ring (``couplings.getfem.compare.fe_demo_ring_multistage``),
- and, where Debian's python3-getfem is installed, the GetFEM ring (``couplings/getfem``).

For each the table gives the force difference between the forms, ``(F_tab - F_paper) / F_paper``,
largest and median over the increments of each stage with the die carrying at least 1 % of the
largest force, and the largest nodal ``|tau(p, p_hist) - tau(p, 0)|`` of each form on the reload
(how much the history changes the friction limit).

Run: python benchmarks/reload_form_fe.py [--params FILE] [--nr 24] [--no-getfem]
Writes benchmarks/results/reload_form_fe.csv and .md and prints the table.
"""

import argparse
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
from _provenance import RESULTS, run_record, write_rows  # noqa: E402

from couplings.getfem.compare import (  # noqa: E402
    fe_demo_ring_multistage,
    getfem_missing,
    read_history,
    run_getfem_ring,
)
from fe_demo.scenes import run_multistage  # noqa: E402
from frictionlaw import FrictionParams  # noqa: E402
from halfspace_calib.pipeline.calibration import Scene, calibrate  # noqa: E402

STAGES = {1: "first press", 2: "lift", 3: "re-contact + reload"}


def _forces(hist):
    key = "force" if "force" in hist else "force_N"
    return np.asarray(hist[key], float), np.asarray(hist["stage"], int)


def _stage_curve(hist, k):
    """``(height_reduction, force)`` of stage ``k``, sorted by reduction (the lift runs back)."""
    f, st = _forces(hist)
    red = np.asarray(hist["height_reduction"], float)
    sel = st == k
    order = np.argsort(red[sel], kind="stable")
    return red[sel][order], f[sel][order]


def compare(case, ha, hb, tau_a, tau_b):
    """Rows of the force difference per stage between the tabulated (a) and paper (b) runs.

    The runs are matched by height reduction within each stage: only the reductions both runs
    reached are compared (a cut-back in one run adds increments the other lacks, and
    interpolating across them on the steep elastic start would be an error of the comparison).
    """
    rows = []
    fmax = _forces(hb)[0].max()
    for k, what in STAGES.items():
        ra, fa = _stage_curve(ha, k)
        rb, fb = _stage_curve(hb, k)
        if ra.size == 0 or rb.size < 2:
            continue
        j = np.clip(np.searchsorted(rb, ra), 0, rb.size - 1)
        both = np.abs(rb[j] - ra) <= 1e-9
        fbi = np.where(both, fb[j], np.nan)
        sel = both & (fbi > 0.01 * fmax)
        if not sel.any():
            continue
        rel = (fa[sel] - fbi[sel]) / fbi[sel]
        rows.append(
            {
                "scene": case,
                "stage": what,
                "increments": int(sel.sum()),
                "force_diff_max_abs_pct": round(100 * float(np.abs(rel).max()), 3),
                "force_diff_median_pct": round(100 * float(np.median(rel)), 3),
                "tau_hist_effect_tab_MPa": round(tau_a / 1e6, 2) if k == 3 else "",
                "tau_hist_effect_paper_MPa": round(tau_b / 1e6, 2) if k == 3 else "",
            }
        )
    return rows


def _tau_effect(hist):
    st = np.asarray(hist["stage"], int)
    key = "tau_diff_eq25" if "tau_diff_eq25" in hist else "tau_diff_eq25_Pa"
    if key not in hist:
        return float("nan")
    return float(np.max(np.asarray(hist[key], float)[st == 3]))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--params", default=None, help="a tabulated params.json (default: calibrate)")
    ap.add_argument("--nr", type=int, default=24, help="elements across the radius (default 24)")
    ap.add_argument("--ring-nr", type=int, default=12, help="ring: elements across the wall")
    ap.add_argument("--no-getfem", action="store_true", help="skip the GetFEM ring")
    a = ap.parse_args(argv)
    work = Path(tempfile.mkdtemp(prefix="reload_form_fe_"))
    if a.params is None:
        P = calibrate(Scene(workers=1), progress=False).params
    else:
        P = FrictionParams.from_json(a.params)
    if P.reload_form != "tabulated":
        raise SystemExit(
            "--params must run the tabulated reload form (a calibration since issue 31)"
        )
    files = {"tabulated": work / "tab.json", "paper": work / "paper.json"}
    P.to_json(files["tabulated"])
    P.replace(reload_form="paper").to_json(files["paper"])
    rows = []
    runs = {f: run_multistage("sbmf", params=str(p), nr=a.nr) for f, p in files.items()}
    for r in runs.values():
        if not r.converged:
            raise RuntimeError(f"fe-demo multistage did not converge: {r.message}")
    h = {f: r.history for f, r in runs.items()}
    rows += compare("fe-demo cylinder", h["tabulated"], h["paper"], *map(_tau_effect, h.values()))
    kw = dict(nr=a.ring_nr, first_reduction=0.3, reduction=0.45, increments=30)
    ring = {f: fe_demo_ring_multistage(str(p), **kw)[0] for f, p in files.items()}
    rows += compare(
        "fe-demo ring", ring["tabulated"], ring["paper"], *map(_tau_effect, ring.values())
    )
    why = getfem_missing()
    if not a.no_getfem and why is None:
        hg = {}
        for f, p in files.items():
            args = ["--law", "sbmf", "--params", str(p), "--nr", str(a.ring_nr)]
            args += ["--increments", "30", "--reduction", "0.45", "--first-reduction", "0.3"]
            rc, _, log = run_getfem_ring(work / f, args)
            if rc != 0:
                raise RuntimeError(f"GetFEM ({f}) failed with exit {rc}:\n{log[-2000:]}")
            hg[f] = read_history(work / f / "history.csv")
        rows += compare("GetFEM ring", hg["tabulated"], hg["paper"], *map(_tau_effect, hg.values()))
    elif not a.no_getfem:
        print(f"GetFEM skipped: {why}")
    RESULTS.mkdir(exist_ok=True)
    write_rows(RESULTS / "reload_form_fe.csv", rows)
    cols = list(rows[0])
    md = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    md += ["| " + " | ".join(str(r[c]) for c in cols) + " |" for r in rows]
    text = "\n".join(md) + "\n"
    (RESULTS / "reload_form_fe.md").write_text(text)
    print(text)


if __name__ == "__main__":
    with run_record(__file__):
        main()
