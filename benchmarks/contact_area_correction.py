"""Does the perimeter correction of the contact area (Yastrebov et al. 2017) converge alpha faster?

The solver's contact ratio counts the elements with ``p > 0``; the correction of Yastrebov,
Anciaux and Molinari (2017, Tribology International, arXiv:1701.02727) subtracts
``(pi - 1 + ln 2) / 24`` element areas per contact/non-contact element edge
(``halfspace_calib.contact.area.corrected_contact_ratio``). Two measurements:

1. **Hertz** (exact area ``pi a^2``): a sphere on a flat, non-periodic, on grids of 16 to 128
   elements over the patch, at five loads (contact radius ``a`` from 0.15 to 0.35 of the patch
   side, i.e. 2.4 to 45 elements). The error of ``alpha`` against ``pi a^2 / L^2`` per grid,
   averaged (absolute) over the five loads, raw and corrected.
2. **Self-affine surfaces** (no exact area): one periodic surface (Hurst 0.8, cut-off
   wavelength ``L / 8``, seeds 1-3) generated on 1024^2 and area-averaged onto 512 ... 32 (128
   to 4 elements per cut-off wavelength), elasto-plastic with the calibration's Table 1
   materials (``H`` = 800 MPa) at 10, 50, 200 and 600 MPa. The table gives the relative
   deviation of raw and corrected ``alpha`` per grid from the raw ``alpha`` at 1024, and of the
   corrected one from the corrected one at 1024 (each estimator's own convergence), averaged
   (absolute) over seeds and pressures.

3. **The five shared files** (``--files FOLDER``, the scan against itself as in
   ``benchmarks/length_scale.py``): the default calibration with the resolution check, once with
   each estimator (``Scene(contact_area=...)``): ``mu_eff``, ``C1`` and the change of the five
   parameters at half the grid. Writes ``contact_area_correction_files.md`` (about 4 min).

Writes ``benchmarks/results/contact_area_correction.md`` and ``.csv`` and prints the tables.
Run from the repository root: ``python benchmarks/contact_area_correction.py [--files FOLDER]``
(about 2 min on one core of the shared 2-core machine, plus 4 min with ``--files``).
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path

import numpy as np
from _provenance import RESULTS, run_record

from halfspace_calib import topography as S
from halfspace_calib.contact.area import contact_perimeter, corrected_contact_ratio
from halfspace_calib.contact.normal import solve_normal
from halfspace_calib.contact.reference import hertz
from halfspace_calib.pipeline.calibration import calibrate
from halfspace_calib.pipeline.sweep.scene import Scene

HERTZ_GRIDS = (16, 24, 32, 48, 64, 96, 128)
HERTZ_A = (0.15, 0.2, 0.25, 0.3, 0.35)  # contact radius / patch side
SA_GRIDS = (1024, 512, 256, 128, 64, 32)
SA_PRESSURES = (10e6, 50e6, 200e6, 600e6)
SA_SEEDS = (1, 2, 3)
L = 1e-3


def hertz_rows():
    E = Scene().E_star
    R = 5e-3
    rows = []
    for n in HERTZ_GRIDS:
        dx = L / n
        x = (np.arange(n) - (n - 1) / 2) * dx
        X, Y = np.meshgrid(x, x, indexing="ij")
        h = -(X**2 + Y**2) / (2 * R)
        for af in HERTZ_A:
            a = af * L
            F = 4 * E * a**3 / (3 * R)
            exact = math.pi * hertz(F, R, E).a ** 2 / L**2
            res = solve_normal(h, dx, E, F / L**2, periodic=False)
            if not res.converged:
                raise RuntimeError(f"Hertz n={n} a={af}: {res.message}")
            cor = corrected_contact_ratio(res.pressure, periodic=False)
            rows.append(
                dict(
                    case="hertz",
                    grid=n,
                    a_elements=a / dx,
                    alpha_exact=exact,
                    alpha_raw=res.alpha,
                    alpha_corrected=cor,
                    err_raw=res.alpha / exact - 1,
                    err_corrected=cor / exact - 1,
                    perimeter=contact_perimeter(res.pressure, periodic=False),
                )
            )
    return rows


def self_affine_rows():
    sc = Scene()
    rows = []
    for seed in SA_SEEDS:
        fine = S.self_affine(
            (SA_GRIDS[0],) * 2, (L, L), hurst=0.8, cutoff_wavelength=L / 8, rq=1e-6, seed=seed
        )
        ref = {}
        for n in SA_GRIDS:
            s = fine if n == SA_GRIDS[0] else S.block_average(fine, n)
            for p in SA_PRESSURES:
                res = solve_normal(np.array(s.heights), s.dx, sc.E_star, p, H=sc.H, periodic=True)
                if not res.converged:
                    raise RuntimeError(f"seed {seed} n={n} p={p:g}: {res.message}")
                cor = corrected_contact_ratio(res.pressure, periodic=True)
                if n == SA_GRIDS[0]:
                    ref[p] = res.alpha
                    ref["c", p] = cor
                rows.append(
                    dict(
                        case="self_affine",
                        seed=seed,
                        grid=n,
                        elements_per_cutoff=n / 8,
                        p_MPa=p / 1e6,
                        alpha_ref=ref[p],
                        alpha_raw=res.alpha,
                        alpha_corrected=cor,
                        err_raw=res.alpha / ref[p] - 1,
                        err_corrected=cor / ref[p] - 1,
                        err_corrected_self=cor / ref["c", p] - 1,
                    )
                )
            print(f"  seed {seed} grid {n} done", flush=True)
    return rows


def _mean_abs(rows, key):
    return 100 * float(np.mean([abs(r[key]) for r in rows]))


def _max_abs(rows, key):
    return 100 * float(np.max([abs(r[key]) for r in rows]))


def tables(h_rows, s_rows):
    out = ["## Hertz (non-periodic, exact area pi a^2; mean and largest |error| over 5 loads)", ""]
    out += [
        "| grid | a (elements) | raw: mean / max error (%) | corrected: mean / max error (%) |",
        "|---|---|---|---|",
    ]
    for n in HERTZ_GRIDS:
        rs = [r for r in h_rows if r["grid"] == n]
        a_lo, a_hi = rs[0]["a_elements"], rs[-1]["a_elements"]
        out.append(
            f"| {n} | {a_lo:.3g}-{a_hi:.3g} | {_mean_abs(rs, 'err_raw'):.2f} / "
            f"{_max_abs(rs, 'err_raw'):.2f} | {_mean_abs(rs, 'err_corrected'):.2f} / "
            f"{_max_abs(rs, 'err_corrected'):.2f} |"
        )
    out += [
        "",
        "## Self-affine, elasto-plastic (H = 800 MPa), periodic; reference: the finest grid",
        "",
        "Mean |deviation| over 3 seeds x 4 pressures (10, 50, 200, 600 MPa); alpha at the finest grid ranges "
        f"{min(r['alpha_ref'] for r in s_rows):.3g}-{max(r['alpha_ref'] for r in s_rows):.3g}.",
        "",
        "| grid | elements per cut-off | raw vs raw(1024): mean / max (%) | corrected vs raw(1024) "
        "| corrected vs corrected(1024) |",
        "|---|---|---|---|---|",
    ]
    for n in SA_GRIDS:
        rs = [r for r in s_rows if r["grid"] == n]
        out.append(
            f"| {n} | {n / 8:g} | {_mean_abs(rs, 'err_raw'):.2f} / {_max_abs(rs, 'err_raw'):.2f} | "
            f"{_mean_abs(rs, 'err_corrected'):.2f} / {_max_abs(rs, 'err_corrected'):.2f} | "
            f"{_mean_abs(rs, 'err_corrected_self'):.2f} / {_max_abs(rs, 'err_corrected_self'):.2f} |"
        )
    return "\n".join(out) + "\n"


FILES = ["metropro-1.dat", "mnt-1.mnt", "x3p-2.x3p", "sur-3.sur", "matrix-3.txt"]
KEYS = ("mu_eff", "C1", "n1", "C2", "n2")


def files_table(folder):
    """Default calibration of each shared file with each estimator, resolution check on."""
    lines = [
        "| file | solve | mu_eff count / perimeter | C1 count / perimeter | change at half the "
        "grid, count: mu_eff / C1 / n1 / C2 / n2 (%) | perimeter (%) | problems count / "
        "perimeter | time count / perimeter (s) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for name in FILES:
        f = str(Path(folder) / name)
        kw = dict(max_undefined=0.95) if name == "sur-3.sur" else {}
        cals, secs = {}, {}
        for est in ("count", "perimeter"):
            t0 = time.perf_counter()
            cals[est] = calibrate(
                Scene(workpiece=f, tool=f, contact_area=est, **kw), progress=False
            )
            secs[est] = time.perf_counter() - t0
        c, p = cals["count"], cals["perimeter"]

        def change(cal):
            d = cal.resolution.as_dict()["params"]
            return " / ".join(f"{100 * d[k][2]:.1f}" for k in KEYS)

        solve = c.scene.boundary
        lines.append(
            f"| {name} | {solve} | {c.params.mu_eff:.4g} / {p.params.mu_eff:.4g} | "
            f"{c.params.C1:.4g} / {p.params.C1:.4g} | {change(c)} | {change(p)} | "
            f"{len(c.problems())} / {len(p.problems())} | {secs['count']:.1f} / "
            f"{secs['perimeter']:.1f} |"
        )
        print(lines[-1], flush=True)
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--files", metavar="FOLDER", help="also run the five shared files in FOLDER")
    args = ap.parse_args()
    if args.files:
        text = files_table(args.files)
        RESULTS.mkdir(exist_ok=True)
        (RESULTS / "contact_area_correction_files.md").write_text(
            "# Contact-area estimators on the five shared files (default calibration)\n\n"
            f"`python benchmarks/contact_area_correction.py --files FOLDER`\n\n{text}"
        )
        print(text)
    print("Hertz ...", flush=True)
    h = hertz_rows()
    print("self-affine ...", flush=True)
    s = self_affine_rows()
    text = tables(h, s)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "contact_area_correction.md").write_text(
        "# Contact-area correction (Yastrebov et al. 2017): measured\n\n"
        "`python benchmarks/contact_area_correction.py`\n\n" + text
    )
    keys = sorted({k for r in h + s for k in r})
    with open(RESULTS / "contact_area_correction.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(h + s)
    print(text)


if __name__ == "__main__":
    with run_record(__file__):
        main()
