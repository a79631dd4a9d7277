"""Ring compression with the flattening in CalculiX against fe-demo, both flattening models.

The 6:3:2 ring of DC04 to 50 % in 50 increments (axisymmetric CAX4R, node-to-surface contact,
12 x 8 elements; tests/ccx_decks.py's ring), the shipped calibration with its flattening block
(fe_demo/data/sbmf_example_flattening.json) as the one-state model (``layer-yield``, its
default) and as the two-state model (``limit-analysis``, the same slope and ``beta``), each
exported for CalculiX with DC04's flow curve baked in (``--flow-curve``: the patched ccx passes
the slave elements' PEEQ, the routine reads the flow stress and, one-state, the hardening
modulus off the curve), against ``fe-demo ring --flattening`` with the same block (its J2
solver passing each die node's surface strain, DC04's flow stress and, one-state, its modulus).
Also both codes without the flattening. Two FE codes, one law: the die force and the ring's
inner-diameter change at the end, ccx's wall time and Newton iterations.

Needs the patched library: ``SBMF_CCX_WORK`` (or build/ccx-build) as tests/test_calculix.py.
Run: python benchmarks/calculix_ring_flattening.py
Writes benchmarks/results/calculix_ring_flattening.csv and prints a table.
"""

import os
import re
import subprocess
import sys
import time
from pathlib import Path
from tempfile import TemporaryDirectory

from _provenance import RESULTS, ROOT, run_record, write_rows

import frictionlaw as fl
from frictionlaw.export.cli import main as export_main

sys.path.insert(0, str(ROOT / "tests"))
from ccx_decks import ring  # noqa: E402

FLAT = ROOT / "fe_demo" / "data" / "sbmf_example_flattening.json"
BUILD = ROOT / "frictionlaw" / "export" / "calculix" / "build.sh"
SWIFT = "swift:530e6,0.006,0.24"
KW = {"nr": 12, "reduction": 0.5}
N_INC = 50


def _lines(depvar):
    return [
        "*SURFACE INTERACTION, NAME=SBMF",
        f"*FRICTION, USER, DEPVAR={depvar}, PROPERTIES=1",
    ] + ["MM-T-S"]


def _ccx(work, params_path, folder, depvar, flow):
    args = ["calculix", "--params", str(params_path), "--out", str(folder / "exp")]
    args += ["--units", "mm-t-s", "--quiet"] + (["--flow-curve", SWIFT] if flow else [])
    if export_main(args) != 0:
        raise SystemExit(f"export failed for {params_path}")
    exe = folder / "exp" / "ccx"
    cmd = ["bash", str(BUILD), "--work", str(work), "--routine", str(folder / "exp/sbmf_fric.f")]
    subprocess.run([*cmd, "--out", str(exe)], check=True, capture_output=True)
    run = folder / "run"
    run.mkdir()
    (run / "job.inp").write_text(ring(_lines(depvar), n_inc=N_INC, **KW))
    env = dict(os.environ, OMP_NUM_THREADS="1", NUMBER_OF_CPUS="1")
    t = time.perf_counter()
    proc = subprocess.run([str(exe), "-i", "job"], cwd=run, capture_output=True, text=True, env=env)
    t = time.perf_counter() - t
    if proc.returncode != 0 or "Job finished" not in proc.stdout:
        raise SystemExit(f"ccx failed in {run}:\n{proc.stdout[-1500:]}")
    text = (run / "job.dat").read_text()
    force = re.findall(r"total force \(fx,fy,fz\) for set NDIE.*\n\s*\n\s*(\S+)\s+(\S+)", text)
    disp = re.findall(r"displacements \(vx,vy,vz\) for set NINNER.*\n\s*\n\s*1\s+(\S+)", text)
    sta = [ln.split() for ln in (run / "job.sta").read_text().splitlines()[2:] if ln.strip()]
    iterations = sum(int(r[3]) for r in sta if len(r) >= 4 and r[3].isdigit())
    # CalculiX's axisymmetric elements carry the forces of a 2-degree segment
    return -float(force[-1][1]) * 180.0, float(disp[-1]) / 4.5, t, iterations


def main():
    from fe_demo.scenes import run_ring

    work = Path(os.environ.get("SBMF_CCX_WORK", ROOT / "build" / "ccx-build"))
    if not (work / "patched.sha256").is_file():
        raise SystemExit(f"no patched CalculiX build in {work}: run {BUILD} --lib-only")
    P = fl.FrictionParams.from_json(FLAT)
    models = {
        "without": P.replace(flattening=None),
        "layer-yield": P,
        "limit-analysis": P.replace(
            flattening=fl.Flattening(P.flattening.slope, P.flattening.beta, model="limit-analysis")
        ),
    }
    rows = []
    with TemporaryDirectory() as tmp:
        for name, params in models.items():
            folder = Path(tmp) / name
            folder.mkdir()
            path = params.to_json(folder / "law.json")
            flat = params.flattening is not None
            depvar = {"without": 3, "layer-yield": 5, "limit-analysis": 6}[name]
            force, d_in, secs, its = _ccx(work, path, folder, depvar, flat)
            ref = run_ring("sbmf", params=params, flattening=flat, n_increments=N_INC, **KW)
            if not ref.converged:
                raise SystemExit(f"fe-demo ring did not converge ({name})")
            f_ref = float(ref.history["force"][-1])
            d_ref = float(ref.history["inner_diameter_change"][-1])
            rows.append(
                {
                    "flattening": name,
                    "ccx_force_kN": round(force / 1e3, 2),
                    "fe_demo_force_kN": round(f_ref / 1e3, 2),
                    "force_difference": round(force / f_ref - 1.0, 4),
                    "ccx_inner_diameter_change": round(d_in, 4),
                    "fe_demo_inner_diameter_change": round(d_ref, 4),
                    "ccx_seconds": round(secs, 1),
                    "ccx_iterations": its,
                }
            )
    RESULTS.mkdir(exist_ok=True)
    write_rows(RESULTS / "calculix_ring_flattening.csv", rows)
    print(
        f"{'flattening':15} {'ccx kN':>8} {'fe-demo kN':>10} {'diff':>7} {'ccx d_in':>9} "
        f"{'fe-demo d_in':>12} {'ccx s':>6} {'it':>4}"
    )
    for r in rows:
        print(
            f"{r['flattening']:15} {r['ccx_force_kN']:8.2f} {r['fe_demo_force_kN']:10.2f} "
            f"{r['force_difference']:+7.2%} {r['ccx_inner_diameter_change']:+9.2%} "
            f"{r['fe_demo_inner_diameter_change']:+12.2%} {r['ccx_seconds']:6.1f} "
            f"{r['ccx_iterations']:4d}"
        )


if __name__ == "__main__":
    with run_record(__file__):
        main()
