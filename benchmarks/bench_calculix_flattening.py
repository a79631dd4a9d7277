"""Cost and effect of the flattening under bulk strain inside CalculiX (issue 43).

The same deck (tests/ccx_decks.py's elastic-plastic block on a plate of 18 x 12 elements,
face-to-face contact: pressed to 200, then 350 MPa, then slid by 0.3 mm, increments of 0.1 of a
step) run by the patched ccx with three routines exported from one calibration
(fe_demo/data/sbmf_example_flattening.json, mm-t-s): ``plain``, the law without its flattening
block (``DEPVAR=3``), ``flat``, with it (``DEPVAR=5``; the slave element's PEEQ passed as
predefined field 1), and ``two``, with the same block as the two-state model ``limit-analysis``
(``DEPVAR=6``). The three are timed in turn, one and two threads, ``--repeat`` rounds; each
ratio is the routine over plain of the same round, the median over rounds. Also the friction force at
the end of the slide (the block's top reaction along the slide) and ccx's increments and
iterations (its .sta file).

Needs the patched library: ``SBMF_CCX_WORK`` (or build/ccx-build) as tests/test_calculix.py.
Run: python benchmarks/bench_calculix_flattening.py [--repeat 3]
Writes benchmarks/results/calculix_flattening.csv and prints a table.
"""

import argparse
import dataclasses
import os
import subprocess
import sys
import time
from pathlib import Path
from tempfile import TemporaryDirectory

import numpy as np
from _provenance import RESULTS, ROOT, run_record, write_rows

import frictionlaw as fl
from frictionlaw.export.cli import main as export_main

sys.path.insert(0, str(ROOT / "tests"))
from ccx_decks import plastic_block, read_blocks  # noqa: E402

FLAT = ROOT / "fe_demo" / "data" / "sbmf_example_flattening.json"
BUILD = ROOT / "frictionlaw" / "export" / "calculix" / "build.sh"
STEPS = [(200.0, 0.0), (350.0, 0.0), (350.0, 0.3)]


def _lines(depvar):
    return [
        "*SURFACE INTERACTION, NAME=SBMF",
        f"*FRICTION, USER, DEPVAR={depvar}, PROPERTIES=1",
    ] + ["MM-T-S"]


def _binary(work, params, folder):
    code = export_main(
        ["calculix", "--params", str(params), "--out", str(folder), "--units", "mm-t-s", "--quiet"]
    )
    assert code == 0
    cmd = ["bash", str(BUILD), "--work", str(work), "--routine", str(folder / "sbmf_fric.f")]
    subprocess.run([*cmd, "--out", str(folder / "ccx")], check=True, capture_output=True)
    return folder / "ccx"


def _run(binary, deck, folder, threads):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "job.inp").write_text(deck)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), NUMBER_OF_CPUS=str(threads))
    t = time.perf_counter()
    proc = subprocess.run(
        [str(binary), "-i", "job"], cwd=folder, capture_output=True, text=True, env=env
    )
    t = time.perf_counter() - t
    if proc.returncode != 0 or "Job finished" not in proc.stdout:
        raise SystemExit(f"ccx failed in {folder}:\n{proc.stdout[-1500:]}")
    force = read_blocks(folder / "job.dat")[-1][1]["total"][0][0]
    sta = [ln.split() for ln in (folder / "job.sta").read_text().splitlines()[2:] if ln.strip()]
    iterations = sum(int(r[3]) for r in sta if len(r) >= 4 and r[3].isdigit())
    return t, force, len(sta), iterations


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="rounds (default 3)")
    args = ap.parse_args()
    work = Path(os.environ.get("SBMF_CCX_WORK", ROOT / "build" / "ccx-build"))
    if not (work / "patched.sha256").is_file():
        raise SystemExit(f"no patched CalculiX build in {work}: run {BUILD} --lib-only")
    P = fl.FrictionParams.from_json(FLAT)
    rows = []
    with TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        plain = dataclasses.replace(P, flattening=None).to_json(tmp / "plain.json")
        flat = P.flattening
        two = dataclasses.replace(
            P, flattening=fl.Flattening(flat.slope, flat.beta, model="limit-analysis")
        ).to_json(tmp / "two.json")
        binaries = {
            "plain": (_binary(work, plain, tmp / "plain"), 3),
            "flat": (_binary(work, FLAT, tmp / "flat"), 5),
            "two": (_binary(work, two, tmp / "two"), 6),
        }
        for threads in (1, 2):
            times = {name: [] for name in binaries}
            info = {}
            for r in range(args.repeat):
                for name, (binary, depvar) in binaries.items():
                    deck = plastic_block(
                        STEPS, _lines(depvar), static="0.1, 1., 1e-6, 0.1", plate=(18, 12)
                    )
                    t, force, inc, it = _run(binary, deck, tmp / f"{name}_{threads}_{r}", threads)
                    times[name].append(t)
                    info[name] = (force, inc, it)
            base = np.array(times["plain"])
            for name in binaries:
                ratio = float(np.median(np.array(times[name]) / base))
                force, inc, it = info[name]
                rows.append(
                    {
                        "routine": name,
                        "threads": threads,
                        "median_s": round(float(np.median(times[name])), 3),
                        "ratio_to_plain": round(ratio, 3),
                        "friction_force_N": round(abs(force), 1),
                        "increments": inc,
                        "iterations": it,
                    }
                )
    RESULTS.mkdir(exist_ok=True)
    write_rows(RESULTS / "calculix_flattening.csv", rows)
    print(
        f"{'routine':8} {'threads':>7} {'median s':>9} {'ratio':>6} {'force N':>9} {'inc':>4} {'it':>4}"
    )
    for r in rows:
        print(
            f"{r['routine']:8} {r['threads']:7d} {r['median_s']:9.2f} {r['ratio_to_plain']:6.2f} "
            f"{r['friction_force_N']:9.1f} {r['increments']:4d} {r['iterations']:4d}"
        )


if __name__ == "__main__":
    with run_record(__file__):
        main()
