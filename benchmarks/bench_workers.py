"""Load levels in parallel processes or threaded FFTs in one process: the CLI's wall time.

On a machine with ``c`` CPUs (``os.sched_getaffinity``), a calibration can run its load levels
in one process whose FFTs use ``c`` threads (``--workers 1``), or in ``w`` processes with
``c // w`` FFT threads each (``--workers w``). This script times what a user of
``halfspace-calib`` sees, the wall time of the whole command (interpreter start-up, imports, the
numba cache loaded in every process, the sweeps, the resolution check for files, the outputs),
for both choices on the same cases, interleaved (round ``r`` runs ``1, w`` for even ``r`` and
``w, 1`` for odd ``r``), so that the ratio of the two compares runs made under the same load.

Cases: the default scene at 128^2 (the README's main job), 256^2 and 512^2; one measured file
pressed against itself at its default ``lambda_s`` and grid (default boundary, resolution check
on).
One untimed run first fills the numba cache, as a user's second run finds it.

Writes ``benchmarks/results/bench_workers.csv`` and ``.md`` and prints the table. Run from the
repository root::

    python benchmarks/bench_workers.py --surfaces DIR [--rounds 2] [--workers 2]
"""

from __future__ import annotations

import argparse
import csv
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _provenance import run_record

from sbmf_cli import available_cpus

RESULTS = Path(__file__).resolve().parent / "results"
CLI = [sys.executable, "-m", "halfspace_calib.cli"]


def _cases(surfaces, file):
    out = [
        ("default scene 128^2", ["--grid", "128"]),
        ("default scene 256^2", ["--grid", "256"]),
        ("default scene 512^2", ["--grid", "512"]),
    ]
    if surfaces is not None:
        path = str(Path(surfaces) / file)
        out.append((f"{file} (default lambda_s and grid)", ["--workpiece", path, "--tool", path]))
    return out


def _run(args, workers, tmp):
    out = Path(tmp) / f"out{workers}"
    cmd = [*CLI, *args, "--workers", str(workers), "--out", str(out)]
    t0 = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if r.returncode not in (0, 1):  # 1: a fit problem of the file, still a whole run
        raise RuntimeError(f"{' '.join(cmd)} exited {r.returncode}:\n{r.stderr}")
    params = (out / "params.json").read_text()
    return dt, params, r.returncode


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--surfaces", help="folder with the measured file (default: none)")
    ap.add_argument("--file", default="mnt-1.mnt", help="measured file (default: mnt-1.mnt)")
    ap.add_argument("--rounds", type=int, default=2, help="rounds per case (default: 2)")
    ap.add_argument(
        "--workers", type=int, default=2, help="processes of the parallel runs (default: 2)"
    )
    a = ap.parse_args()
    cpus = available_cpus()
    w = a.workers
    cases = _cases(a.surfaces, a.file)
    times = {(c, k): [] for c, _ in cases for k in (1, w)}
    same = {c: True for c, _ in cases}
    load = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        _run(["--grid", "32"], 1, tmp)  # fills the numba cache
        for r in range(a.rounds):
            for name, args in cases:
                order = (1, w) if r % 2 == 0 else (w, 1)
                got = {}
                for k in order:
                    dt, params, rc = _run(args, k, tmp)
                    times[(name, k)].append(dt)
                    got[k] = _strip_timing(params)
                    print(f"round {r} {name}: workers {k}: {dt:.1f} s (exit {rc})", flush=True)
                same[name] &= got[1] == got[w]
            load.append(os.getloadavg()[0])
    rows = []
    for name, _ in cases:
        t1, tw = times[(name, 1)], times[(name, w)]
        ratios = [x / y for x, y in zip(t1, tw, strict=True)]
        rows.append(
            {
                "case": name,
                "cpus": cpus,
                "seconds_1_process": statistics.median(t1),
                f"seconds_{w}_processes": statistics.median(tw),
                "all_1_process": " ".join(f"{x:.1f}" for x in t1),
                f"all_{w}_processes": " ".join(f"{x:.1f}" for x in tw),
                "ratio_median": statistics.median(ratios),
                "ratio_min": min(ratios),
                "ratio_max": max(ratios),
                "params_identical": same[name],
            }
        )
    write(rows, w, cpus, load, a.rounds)


def _strip_timing(params):
    """params.json without the lines that hold wall times, dates or the workers count."""
    keep = []
    for line in params.splitlines():
        low = line.lower()
        if any(k in low for k in ("second", "time", "date", "workers", '"out', "wall")):
            continue
        keep.append(line)
    return "\n".join(keep)


def write(rows, w, cpus, load, rounds):
    RESULTS.mkdir(exist_ok=True)
    with open(RESULTS / "bench_workers.csv", "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=list(rows[0]))
        wr.writeheader()
        wr.writerows(rows)
    head = (
        f"`halfspace-calib` wall time, {cpus} CPUs, {rounds} interleaved rounds per case; "
        f"1 process x {cpus} FFT threads against {w} processes x {max(1, cpus // w)} FFT "
        f"thread(s); load average during the run {min(load):.1f}-{max(load):.1f}\n\n"
    )
    lines = [
        f"| case | 1 process (s, median) | {w} processes (s, median) | ratio 1 / {w} "
        "(median, min-max) | all runs 1 / "
        f"{w} (s) | params.json identical |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['case']} | {r['seconds_1_process']:.1f} | {r[f'seconds_{w}_processes']:.1f} | "
            f"{r['ratio_median']:.2f} ({r['ratio_min']:.2f}-{r['ratio_max']:.2f}) | "
            f"{r['all_1_process']} / {r[f'all_{w}_processes']} | "
            f"{'yes' if r['params_identical'] else 'NO'} |"
        )
    text = head + "\n".join(lines) + "\n"
    (RESULTS / "bench_workers.md").write_text(text)
    print(text)


if __name__ == "__main__":
    with run_record(__file__):
        main()
