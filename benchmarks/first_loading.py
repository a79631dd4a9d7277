"""The first-loading form chosen by measurement, and what the continuous reload branch costs (issue 37).

For each case (the default synthetic scene at 128^2 and, with ``--folder``, each file of the
shared set against the synthetic default tool, as ``benchmarks/reload_law.py`` and
``benchmarks/measured_surfaces.py`` run them) the default sweep is solved, and then the same
scene at first-loading pressures and reload fractions the calibration never sees (15, 35, 75,
150, 350, 550, 650, 730 MPa times ``H / 800 MPa``; reloads below the last five at the fractions
0.03-0.95; asserted unseen). Each candidate first-loading form is fitted to the default sweep
and judged three ways: in sample, the run's own leave-one-level-out estimate (each interior level
left out, refitted, predicted) and held out (the second sweep's points):

* ``eq24``: the paper's Eq. 24 (two parameters, the bound ``alpha1 >= p / H`` to 0.99 H);
* ``eq24-power``: a richer parametric family, Eq. 24 with an exponent on the pressure,
  ``g(C (p / H)**s; n)`` (three parameters; no Coulomb limit unless ``s = 1``);
* ``tabulated``: the form that runs (monotone cubic Hermite of ``ln alpha`` over ``ln p``, its
  own end slope at the lowest level, Coulomb below, power law above);
* ``tabulated-C1``: the same with the first slope ``min(1, 3 x secant)`` (a smooth joint with
  the Coulomb line: the lead's first proposal);
* ``pchip-alpha``: a monotone cubic of ``alpha`` itself over ``ln p``.

The nearly conforming scans against themselves (``--self-files``: metropro-1, mnt-1) run too:
there the curve already bends at the lowest level and the forms differ most.

Then the reload branch on the tabulated first loading, continuous (the default) and with the
jump, against the earlier default's forms (Eq. 24 with the jump; the paper's Eq. 25 is now kept
from dipping below the first loading, which the earlier code did not do): run-own and held-out
max ``|d alpha|``,
the largest drop of ``tau`` at ``p_hist`` and the largest dip of a reload curve below first
loading (both on the dense grid of ``pipeline.law.law_checks``).

Run: python benchmarks/first_loading.py [--grid 128] [--folder DIR] [--files a,b]
Writes benchmarks/results/first_loading.csv and .md and prints the tables.
"""

import argparse
import dataclasses
import time
import warnings
from pathlib import Path

import numpy as np
from _provenance import RESULTS, run_record, write_rows
from reload_law import FILES, _check_unseen, _held_scene
from scipy.interpolate import CubicHermiteSpline, PchipInterpolator
from scipy.optimize import least_squares

from frictionlaw import _reference as ref
from frictionlaw import alpha_first, alpha_reload
from frictionlaw.reload_form import pchip_slopes
from halfspace_calib.pipeline.calibration import Scene, run_sweeps
from halfspace_calib.pipeline.law import forms as FM
from halfspace_calib.pipeline.law.law_checks import law_checks
from halfspace_calib.pipeline.law.params import make_params
from halfspace_calib.pipeline.sweep.scene_surfaces import load_scene_surfaces

FORMS = ("eq24", "eq24-power", "tabulated", "tabulated-C1", "pchip-alpha")
SELF_FILES = ("metropro-1.dat", "mnt-1.mnt")
VARIANTS = (
    ("tabulated + continuous (default)", dict(first_loading_form="auto", continuous_reload=True)),
    ("tabulated + jump", dict(first_loading_form="auto", continuous_reload=False)),
    ("Eq. 24 + jump", dict(first_loading_form="eq24", continuous_reload=False)),
)


def _table_model(p, a, H, c1_joint):
    law = FM.calibration_form("first_loading", "tabulated").fit(p, a, FM.FitContext(H))
    t = law.table
    u, v = np.log(np.asarray(t.p) / H), np.log(np.asarray(t.alpha))
    d = pchip_slopes(u, v)
    if c1_joint:
        d[0] = min(1.0, 3.0 * (v[1] - v[0]) / (u[1] - u[0]))

    def f(q):
        uq = np.log(np.asarray(q, float) / H)
        inner = CubicHermiteSpline(u, v, d)(np.clip(uq, u[0], u[-1]))
        out = np.where(uq < u[0], v[0] + uq - u[0], inner)
        out = np.where(uq > u[-1], v[-1] + d[-1] * (uq - u[-1]), out)
        return np.exp(np.minimum(out, 0.0))

    return f


def _pchip_alpha(p, a, H):
    law = FM.calibration_form("first_loading", "tabulated").fit(p, a, FM.FitContext(H))
    f = PchipInterpolator(np.log(law.table.p), law.table.alpha, extrapolate=True)
    return lambda q: np.clip(f(np.log(np.asarray(q, float))), 0.0, 1.0)


def _eq24(p, a, H):
    rec = FM.calibration_form("first_loading", "eq24")
    fit = rec.fit(p, a, FM.FitContext(H, floor_to=0.99 * H))
    return lambda q: rec.predict(fit, np.asarray(q, float), FM.FitContext(H))


def _eq24_power(p, a, H):
    def model(x, q):
        c, n, s = np.exp(x)
        return np.exp(ref.ln_smooth_min(np.log(c) + s * np.log(q / H), n))

    best = None
    lb, ub = np.log([1e-3, 0.1, 0.2]), np.log([1e4, 50.0, 3.0])
    for x0 in np.log(
        [[c, n, s] for c in (0.5, 2, 10) for n in (0.5, 2, 10) for s in (0.7, 1, 1.3)]
    ):
        r = least_squares(lambda x: model(x, p) - a, x0, bounds=(lb, ub))
        if best is None or r.cost < best.cost:
            best = r
    return lambda q: model(best.x, np.asarray(q, float))


def _model(name, p, a, H):
    if name == "eq24":
        return _eq24(p, a, H)
    if name == "eq24-power":
        return _eq24_power(p, a, H)
    if name == "pchip-alpha":
        return _pchip_alpha(p, a, H)
    return _table_model(p, a, H, c1_joint=name == "tabulated-C1")


def _loo(name, p, a, H):
    out = 0.0
    for i in range(1, p.size - 1):
        keep = np.arange(p.size) != i
        out = max(out, abs(float(_model(name, p[keep], a[keep], H)(p[i : i + 1])[0]) - a[i]))
    return out


def first_rows(case, scene, sw, hw):
    p, a = sw.loading
    o = np.argsort(p)
    p, a = p[o], a[o]
    hp, ha = hw.loading
    rows = []
    for name in FORMS:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            f = _model(name, p, a, scene.H)
            rows.append(
                {
                    "case": case,
                    "form": name,
                    "in_sample": float(np.max(np.abs(f(p) - a))),
                    "run_loo": _loo(name, p, a, scene.H),
                    "held_out": float(np.max(np.abs(f(hp) - ha))),
                    "held_out_low": float(np.max(np.abs(f(hp[:3]) - ha[:3]))),
                }
            )
    return rows


def reload_rows(case, scene, sw, hw):
    p, a = sw.loading
    rows = []
    for label, kw in VARIANTS:
        sc = dataclasses.replace(scene, **kw)
        t0 = time.perf_counter()
        law = FM.fit_law(sc, p, a, sw.reload_curves())
        secs = time.perf_counter() - t0
        P = make_params(
            law.eq24, law.paper, m=sc.m, sigma_y=sc.sigma_y, law=law, p_range=(p.min(), p.max())
        )
        hp, ha = hw.loading
        e2 = max(
            float(np.max(np.abs(alpha_reload(c.p, c.p_hist, P) - c.alpha)))
            for c in hw.reload_curves()
        )
        ch = law_checks(P, sw.reload_curves())
        rows.append(
            {
                "case": case,
                "variant": label,
                "forms": f"{law.first.form} + {law.reload.form}",
                "first_run_loo": law.errors["first_loading"].heldout_max,
                "first_held_out": float(np.max(np.abs(alpha_first(hp, P) - ha))),
                "reload_run_loo": law.errors["reload"].heldout_max,
                "reload_held_out": e2,
                "max_jump_pct": 100 * ch["max_jump_relative"],
                "max_dip": ch["reload_below_first"]["max"],
                "fit_seconds": secs,
            }
        )
    return rows


@dataclasses.dataclass
class _Seen:
    """What ``reload_law._check_unseen`` reads of a calibration: its scene."""

    scene: object = None


def run_case(case, scene):
    surfs = load_scene_surfaces(scene)
    scene = dataclasses.replace(scene, grid=surfs.grid)
    if scene.from_files and scene.lambda_s is None:
        scene = dataclasses.replace(scene, lambda_s=surfs.lambda_s)
    sw = run_sweeps(scene, progress=False, surfaces=surfs)
    held = _held_scene(scene)
    _check_unseen(dataclasses.replace(_Seen(), scene=scene), held)
    hw = run_sweeps(held, progress=False, surfaces=surfs)
    return first_rows(case, scene, sw, hw), reload_rows(case, scene, sw, hw)


def _fmt(v):
    return f"{v:.4f}" if isinstance(v, float) else str(v)


def _table(rows, keys):
    lines = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    lines += ["| " + " | ".join(_fmt(r[k]) for k in keys) + " |" for r in rows]
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--grid", type=int, default=128, help="grid of the default scene (default 128)")
    ap.add_argument("--folder", default=None, help="folder of measured files (default: none)")
    ap.add_argument("--files", default=",".join(FILES), help="files of --folder to run")
    ap.add_argument(
        "--self-files",
        default=",".join(SELF_FILES),
        help="files of --folder also run against themselves (the nearly conforming pairs, where "
        "the first-loading forms differ most; default: " + ",".join(SELF_FILES) + ")",
    )
    a = ap.parse_args(argv)
    cases = [(f"default-{a.grid}", Scene(grid=a.grid, workers=1))]
    if a.folder:
        for name in a.files.split(","):
            kw = {"max_undefined": 0.95} if name.startswith("sur-3") else {}
            f = str(Path(a.folder) / name)
            cases.append((f"{name} x tool", Scene(workpiece=f, workers=1, **kw)))
        for name in (n for n in a.self_files.split(",") if n):
            f = str(Path(a.folder) / name)
            cases.append((f"{name} x itself", Scene(workpiece=f, tool=f, workers=1)))
    first, reload = [], []
    for case, scene in cases:
        r1, r2 = run_case(case, scene)
        first += r1
        reload += r2
        print(case, flush=True)
    RESULTS.mkdir(exist_ok=True)
    write_rows(RESULTS / "first_loading.csv", first)
    write_rows(RESULTS / "first_loading_reload.csv", reload)
    text = (
        "First-loading forms: max |d alpha| in sample, in the run's own leave-one-level-out, "
        "held out (a second sweep at unseen levels) and held out at 15-75 MPa\n\n"
        + _table(first, ["case", "form", "in_sample", "run_loo", "held_out", "held_out_low"])
        + "\n\nReload branch on the first loading that runs: max |d alpha|, drop at p_hist, "
        "dip below first loading\n\n"
        + _table(
            reload,
            [
                "case",
                "variant",
                "forms",
                "first_run_loo",
                "first_held_out",
                "reload_run_loo",
                "reload_held_out",
                "max_jump_pct",
                "max_dip",
                "fit_seconds",
            ],
        )
        + "\n"
    )
    (RESULTS / "first_loading.md").write_text(text)
    print(text)


if __name__ == "__main__":
    with run_record(__file__):
        main()
