"""CalculiX node-to-surface contact: the C3D8I press with and without ccx's controls lines.

tests/ccx_decks.py's elastic C3D8I block (12 x 8 x 4 mm, 6 x 4 x 2 elements) pressed to 200,
then 350 MPa in increments of 0.1 on C3D8 plates of several meshes, node-to-surface contact,
one thread. Each deck is run by the patched ccx with the routine of ``frictionlaw-export
calculix`` (fe_demo/data/sbmf_example.json, mm-t-s, its default stick: elastic slip 0.005
CHRLNGTH) and with ccx's own Coulomb friction at about the routine's stick (``0.2, 7000.``:
mu and stick slope of the law at the centre node near 340 MPa), each without and with
``*CONTROLS, PARAMETERS=TIME INCREMENTATION`` / ``4,9`` in each step (docs/fe_codes.md,
"CalculiX"). Recorded: whether ccx finished, its converged increments, attempts given up,
iterations (its .sta file), the wall time, and the bounce: the largest correction of the block's
bottom centre node (on the plate's edge at y = 4 mm where the plate has one) over ccx's 1 %
limit, 0.01 times the largest displacement increment, in the increments of the deck's size
(above 1: ccx does not accept the iterate).

Needs the patched library: ``SBMF_CCX_WORK`` (or build/ccx-build) as tests/test_calculix.py.
Run: python benchmarks/bench_calculix_n2f.py
Writes benchmarks/results/calculix_n2f.csv and prints a table.
"""

import argparse
import os
import re
import subprocess
import sys
import time
from pathlib import Path
from tempfile import TemporaryDirectory

from _provenance import RESULTS, ROOT, run_record, write_rows

from frictionlaw.export.cli import main as export_main

sys.path.insert(0, str(ROOT / "tests"))
from ccx_decks import SLAVE0, plastic_block  # noqa: E402

EXAMPLE = ROOT / "fe_demo" / "data" / "sbmf_example.json"
BUILD = ROOT / "frictionlaw" / "export" / "calculix" / "build.sh"
PRESS = [(200.0, 0.0), (350.0, 0.0)]
PLATES = [(4, 4), (6, 4), (7, 4), (8, 4), (6, 3), (6, 7)]
FRICTION = {
    "routine": ["*SURFACE INTERACTION, NAME=SBMF", "*FRICTION, USER, DEPVAR=3, PROPERTIES=1"]
    + ["MM-T-S"],
    "coulomb": ["*SURFACE INTERACTION, NAME=SBMF", "*FRICTION", "0.2, 7000."],
}
CONTROLS = "*CONTROLS, PARAMETERS=TIME INCREMENTATION\n4,9\n"
CENTRE = SLAVE0 + 17


def _binary(work, folder):
    args = ["calculix", "--params", str(EXAMPLE), "--out", str(folder), "--units", "mm-t-s"]
    assert export_main([*args, "--quiet"]) == 0
    cmd = ["bash", str(BUILD), "--work", str(work), "--routine", str(folder / "sbmf_fric.f")]
    subprocess.run([*cmd, "--out", str(folder / "ccx")], check=True, capture_output=True)
    return folder / "ccx"


def _run(binary, deck, folder):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "job.inp").write_text(deck)
    env = dict(os.environ, OMP_NUM_THREADS="1", NUMBER_OF_CPUS="1")
    t = time.perf_counter()
    proc = subprocess.run(
        [str(binary), "-i", "job"], cwd=folder, capture_output=True, text=True, env=env
    )
    t = time.perf_counter() - t
    sta = [ln.split() for ln in (folder / "job.sta").read_text().splitlines()[2:] if ln.strip()]
    sta = [r for r in sta if len(r) == 7]
    pairs = re.findall(
        r"largest increment of disp= (\S+)\s+largest correction to disp= (\S+) in node (\d+)",
        proc.stdout,
    )
    # increments of the deck's size only (a cut-back shrinks the increment, not the bounce)
    full = 0.5 * max((float(u) for u, _, _ in pairs), default=0.0)
    bounce = max(
        (
            float(c) / (0.01 * float(u))
            for u, c, n in pairs
            if int(n) == CENTRE and c != u and float(u) >= full
        ),
        default=0.0,
    )
    return {
        "finished": proc.returncode == 0 and "Job finished" in proc.stdout,
        "increments": sum(1 for r in sta if r[2].isdigit()),
        "given_up": sum(1 for r in sta if not r[2].isdigit()),
        "iterations": sum(int(r[3]) for r in sta),
        "wall_s": round(t, 2),
        "bounce_over_limit": round(bounce, 3),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.parse_args()
    work = Path(os.environ.get("SBMF_CCX_WORK", ROOT / "build" / "ccx-build"))
    if not (work / "patched.sha256").is_file():
        raise SystemExit(f"no patched CalculiX build in {work}: run {BUILD} --lib-only")
    rows = []
    with TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        binary = _binary(work, tmp / "export")
        for plate in PLATES:
            for friction, lines in FRICTION.items():
                for controls in (False, True):
                    deck = plastic_block(
                        PRESS,
                        lines,
                        contact="NODE TO SURFACE",
                        static="0.1, 1., 1e-6, 0.1",
                        element="C3D8I",
                        plastic=False,
                        plate=plate,
                    )
                    if controls:
                        deck = deck.replace("*STATIC\n", CONTROLS + "*STATIC\n")
                    name = f"{plate[0]}x{plate[1]}_{friction}_{int(controls)}"
                    out = _run(binary, deck, tmp / name)
                    rows.append(
                        {
                            "plate": f"{plate[0]}x{plate[1]}",
                            "friction": friction,
                            "controls_4_9": controls,
                            **out,
                        }
                    )
                    r = rows[-1]
                    print(
                        f"{r['plate']:5} {friction:8} {'4,9' if controls else '-':4} "
                        f"{'finished' if r['finished'] else 'stopped':8} {r['increments']:3d} "
                        f"{r['given_up']:3d} {r['iterations']:4d} {r['wall_s']:6.2f} "
                        f"{r['bounce_over_limit']:6.3f}",
                        flush=True,
                    )
    RESULTS.mkdir(exist_ok=True)
    write_rows(RESULTS / "calculix_n2f.csv", rows)


if __name__ == "__main__":
    with run_record(__file__):
        main()
