"""Cost of a calibration in FFT pairs: the figure of merit of the normal solver's speed (issue 16).

Unit: one FFT pair is the fastest ``rfft2`` + ``irfft2`` of the solver's transform size on this
machine (scipy.fft with 1 thread or all threads, best of 9), timed in the same run as the
calibration (a ``--before-tree`` run is costed with the same unit). Per case the table gives
the wall time, that time in FFT pairs of the case's grid
(periodic and mirror: the grid; isolated: the zero-padded DC-FFT grid), the transforms the run
actually
made (counted, as pairs of the case's grid: other sizes, e.g. the resolution check's half grid,
weighted by their own unit), the fine-grid CG iterations per solve (first loading and reload)
and the time per phase (first loading, reloads, resolution check, the rest: surfaces, fits).

Cases: the default synthetic scene at ``--grids`` (periodic) and ``--files`` from ``--surfaces``
as workpiece and tool, with the default boundary for files (mirror: cosine transforms of the
grid, counted as FFTs of its size; isolated before issue 31) at ``--file-grids``; each
calibration runs as a user's would, ``calibrate(scene)`` after a JIT warm-up, one process.

``--before-tree DIR`` runs the cases of ``--before`` also with the package found in ``DIR``
(e.g. ``git archive <commit> | tar -x -C DIR``), in a child process that times its own unit:
the ratio of the two costs is the speed-up. ``--parallel`` compares, on the default scene at the
first of ``--grids``, one process with 1 or all FFT threads against two processes (load levels
in parallel) with one thread each.

Run: python benchmarks/bench_calibration_cost.py [--grids 256,512,1024] [--file-grids 256,512]
     [--files mnt-1.mnt,metropro-1.dat] [--surfaces DIR] [--before-tree DIR]
     [--before default-256,default-512,mnt-1.mnt-256] [--parallel]
Writes benchmarks/results/bench_calibration_cost.csv / .md and prints the table.
"""

import argparse
import csv
import json
import os
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np
import scipy.fft as sfft
from _provenance import run_record, write_rows

from sbmf_cli import available_cpus

RESULTS = Path(__file__).parent / "results"
HERE = Path(__file__).resolve()

# ----------------------------------------------------------------------------- FFT accounting
COUNTS = Counter()
_rfft2, _irfft2 = sfft.rfft2, sfft.irfft2
_dctn, _idctn = sfft.dctn, sfft.idctn


def _counting_rfft2(x, s=None, *args, **kw):
    COUNTS[("r", tuple(s) if s is not None else np.shape(x))] += 1
    return _rfft2(x, s, *args, **kw)


def _counting_irfft2(x, s=None, *args, **kw):
    COUNTS[("i", tuple(s) if s is not None else None)] += 1
    return _irfft2(x, s, *args, **kw)


def _counting_dctn(x, *args, **kw):
    COUNTS[("r", np.shape(x))] += 1
    return _dctn(x, *args, **kw)


def _counting_idctn(x, *args, **kw):
    COUNTS[("i", np.shape(x))] += 1
    return _idctn(x, *args, **kw)


def install_counters():
    """Count the solver's transforms (it calls ``scipy.fft.rfft2 / irfft2`` and, for the
    mirror boundary, ``dctn / idctn`` by attribute; a cosine transform counts as an FFT of its
    size)."""
    sfft.rfft2, sfft.irfft2 = _counting_rfft2, _counting_irfft2
    sfft.dctn, sfft.idctn = _counting_dctn, _counting_idctn


def pair_seconds(shape, repeats=9):
    """Best ``rfft2`` + ``irfft2`` time of a real field of ``shape`` (1 thread or all)."""
    x = np.random.default_rng(0).random(shape)
    xh = _rfft2(x)
    best = np.inf
    for w in sorted({1, available_cpus()}):
        _irfft2(_rfft2(x, workers=w), s=shape, workers=w)
        for _ in range(repeats):
            t0 = time.perf_counter()
            _rfft2(x, workers=w)
            t1 = time.perf_counter()
            _irfft2(xh, s=shape, workers=w)
            best = min(best, t1 - t0 + time.perf_counter() - t1)
    return best


def fft_shape(grid, boundary):
    if boundary in ("periodic", "mirror", True):
        return (grid, grid)
    m = sfft.next_fast_len(2 * grid - 1, real=True)
    return (m, m)


# ----------------------------------------------------------------------------- one case
def scene_of(case, surfaces):
    from halfspace_calib.pipeline.calibration import Scene

    kind, grid = case.rsplit("-", 1)
    if kind == "default":
        return Scene(grid=int(grid))
    path = str(Path(surfaces) / kind)
    return Scene(workpiece=path, tool=path, grid=int(grid))


def run_case(case, surfaces, workers=1):
    """Calibrate one case; its wall time, counted transforms, iterations and phases."""
    import dataclasses

    from halfspace_calib.pipeline.calibration import calibrate

    scene = dataclasses.replace(scene_of(case, surfaces), workers=workers)
    COUNTS.clear()
    t0 = time.perf_counter()
    cal = calibrate(scene, progress=False)
    seconds = time.perf_counter() - t0
    lv = cal.sweeps.levels
    load_nit = [x.loading.nit for x in lv]
    reload_nit = [r.nit for x in lv for r in x.reload]
    res = cal.resolution
    by_shape = Counter()
    for (_, shape), k in COUNTS.items():
        by_shape[shape] += k
    return {
        "case": case,
        "grid": cal.scene.grid,
        "periodic": bool(cal.scene.periodic),
        "boundary": getattr(
            cal.scene, "boundary", "periodic" if cal.scene.periodic else "isolated"
        ),
        "seconds": seconds,
        "transforms": {f"{s[0]}x{s[1]}": k for s, k in by_shape.items() if s is not None},
        "loading_nit": load_nit,
        "reload_nit": reload_nit,
        "loading_seconds": sum(getattr(x, "loading_seconds", np.nan) for x in lv),
        "reload_seconds": sum(getattr(x, "reload_seconds", np.nan) for x in lv),
        "sweeps_seconds": cal.sweeps.seconds,
        "check_seconds": res.seconds if res is not None else 0.0,
        "problems": len(cal.problems()),
        "mu_eff": float(cal.params.mu_eff),
    }


def costs(rec):
    """Add the units and the costs in FFT pairs of the case's grid to a case record."""
    main = fft_shape(rec["grid"], rec.get("boundary", rec["periodic"]))
    unit = pair_seconds(main)
    counted = 0.0
    for key, k in rec["transforms"].items():
        shape = tuple(int(v) for v in key.split("x"))
        w = 1.0 if shape == main else pair_seconds(shape) / unit
        counted += 0.5 * k * w
    main_key = f"{main[0]}x{main[1]}"
    nit = sum(rec["loading_nit"]) + sum(rec["reload_nit"])
    rec.update(
        fft_shape=main_key,
        unit_ms=1e3 * unit,
        cost_pairs=rec["seconds"] / unit,
        counted_pairs=counted,
        pairs_per_iteration=0.5 * rec["transforms"].get(main_key, 0) / max(nit, 1),
    )
    return rec


def child(case, surfaces, workers=1):
    """``--child``: one case with whatever package is importable here (a ``--before-tree``).

    ``workers``: the sweeps' processes (``0``: the scene's default, ``None``: 2 at 512^2 here).
    The unit is the best pair timed just before and just after the calibration.
    """
    from halfspace_calib.pipeline.calibration import Scene, calibrate

    install_counters()
    calibrate(Scene(grid=16), progress=False)  # JIT warm-up
    main = fft_shape(int(case.rsplit("-", 1)[1]), "periodic")
    before = pair_seconds(main)
    rec = costs(run_case(case, surfaces, workers=None if workers == 0 else workers))
    # the unit with glibc's heap kept as the solver keeps it (halfspace_calib.common.heap): with
    # glibc's defaults each transform's output arrives as fresh pages, and the pair's time
    # depends on the process's allocation history (1.2-2.1 ms at 512^2 in one run)
    _keep_heap_for_unit()
    unit = min(before, pair_seconds(main), 1e-3 * rec["unit_ms"])
    rec.update(unit_ms=1e3 * unit, cost_pairs=rec["seconds"] / unit, workers=workers)
    print(json.dumps(rec))


def _keep_heap_for_unit():
    """glibc's ``mallopt`` thresholds as ``halfspace_calib.common.heap`` sets them (also for an
    old tree without that module), so that the unit is the transforms' own time."""
    import ctypes

    try:
        libc = ctypes.CDLL("libc.so.6")
        libc.mallopt(-3, 64 << 20)  # M_MMAP_THRESHOLD
        libc.mallopt(-1, 256 << 20)  # M_TRIM_THRESHOLD
    except (OSError, AttributeError):
        pass


def _child_run(case, surfaces, tree, workers):
    """One ``--child`` run in a fresh process (``tree``: a package folder first on the path)."""
    env = dict(os.environ)
    if tree:
        env["PYTHONPATH"] = str(Path(tree).resolve())
    cmd = [sys.executable, str(HERE), "--child", case, "--child-workers", str(workers)]
    if surfaces:
        cmd += ["--surfaces", str(surfaces)]
    out = subprocess.run(cmd, env=env, cwd=HERE.parent, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def alternate(case, surfaces, before_tree, repeats):
    """``--alternate N``: ``case`` N times, each run in a fresh process, the code of this tree
    and (with ``--before-tree``) the old code in turn, on 1 process and on the default processes;
    each run's cost in its own unit (the best pair timed next to it). Returns the rows and a
    Markdown table of the medians and ranges."""
    rows = []
    trees = [("new", None)] + ([("before", before_tree)] if before_tree else [])
    for i in range(repeats):
        for workers in (1, 0):
            for tag, tree in trees:
                rec = _child_run(case, surfaces, tree, workers)
                rec.update(code=tag, run=i + 1, mode="1 process" if workers == 1 else "default")
                rows.append(rec)
                print(
                    f"{case} {tag} {rec['mode']} run {i + 1}: {rec['seconds']:.2f} s, "
                    f"unit {rec['unit_ms']:.2f} ms, {rec['cost_pairs']:.0f} pairs",
                    flush=True,
                )
    md = [
        "| case | code | processes | runs | wall s (median, range) | unit ms (median) "
        "| cost in FFT pairs (median, range) | counted pairs | CG iterations |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for tag, _ in trees:
        for mode in ("1 process", "default"):
            sel = [r for r in rows if r["code"] == tag and r["mode"] == mode]
            sec = np.array([r["seconds"] for r in sel])
            cost = np.array([r["cost_pairs"] for r in sel])
            nit = sum(sel[0]["loading_nit"]) + sum(sel[0]["reload_nit"])
            md.append(
                f"| {case} | {tag} | {mode} | {len(sel)} | {np.median(sec):.2f} "
                f"({sec.min():.2f}-{sec.max():.2f}) | "
                f"{np.median([r['unit_ms'] for r in sel]):.2f} | {np.median(cost):.0f} "
                f"({cost.min():.0f}-{cost.max():.0f}) | {sel[0]['counted_pairs']:.0f} | {nit} |"
            )
    return rows, "\n".join(md) + "\n"


# ----------------------------------------------------------------------------- table
COLUMNS = [
    ("case", "case", "{}"),
    ("fft", "fft_shape", "{}"),
    ("pair ms", "unit_ms", "{:.2f}"),
    ("seconds", "seconds", "{:.1f}"),
    ("cost (pairs)", "cost_pairs", "{:.0f}"),
    ("counted pairs", "counted_pairs", "{:.0f}"),
    ("pairs/iter", "pairs_per_iteration", "{:.2f}"),
    ("nit load mean/max", "nit_load", "{}"),
    ("nit reload mean/max", "nit_reload", "{}"),
    ("load s", "loading_seconds", "{:.1f}"),
    ("reload s", "reload_seconds", "{:.1f}"),
    ("check s", "check_seconds", "{:.1f}"),
    ("other s", "other_seconds", "{:.1f}"),
]


def _finish_row(rec, tag):
    rec = dict(rec)
    rec["code"] = tag
    ln, rn = rec["loading_nit"], rec["reload_nit"]
    rec["nit_load"] = f"{np.mean(ln):.1f}/{max(ln)}"
    rec["nit_reload"] = f"{np.mean(rn):.1f}/{max(rn)}" if rn else "-"
    rec["other_seconds"] = rec["seconds"] - rec["sweeps_seconds"] - rec["check_seconds"]
    return rec


def table(rows):
    cols = [("code", "code", "{}"), *COLUMNS]
    out = ["| " + " | ".join(c[0] for c in cols) + " |", "|" + "---|" * len(cols)]
    for r in rows:
        cells = []
        for _, key, fmt in cols:
            v = r.get(key)
            cells.append(
                "-" if v is None or (isinstance(v, float) and np.isnan(v)) else fmt.format(v)
            )
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--grids", default="256,512,1024", help="default scene grids (default %(default)s)"
    )
    ap.add_argument(
        "--file-grids", default="256,512", help="grids of the files (default %(default)s)"
    )
    ap.add_argument(
        "--files", default="mnt-1.mnt,metropro-1.dat", help="measured files (default %(default)s)"
    )
    ap.add_argument(
        "--surfaces",
        default=None,
        help="folder holding --files (default none: the measured-file cases are left out)",
    )
    ap.add_argument(
        "--before-tree", default=None, help="package tree of the old code (default none)"
    )
    ap.add_argument(
        "--before",
        default="default-256,default-512,mnt-1.mnt-256",
        help="cases also run with --before-tree (default %(default)s)",
    )
    ap.add_argument("--parallel", action="store_true", help="processes against FFT threads")
    ap.add_argument(
        "--alternate",
        type=int,
        default=0,
        help="run the first of --grids this many times in fresh processes, this tree and "
        "--before-tree in turn, on 1 process and the default processes; writes "
        "bench_calibration_cost_alternate.csv/.md (default %(default)s: off)",
    )
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--child-workers", type=int, default=1, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        child(args.child, args.surfaces, args.child_workers)
        return
    if args.alternate:
        case = f"default-{args.grids.split(',')[0]}"
        load0 = os.getloadavg()[0]
        rows, md = alternate(case, args.surfaces, args.before_tree, args.alternate)
        load1 = os.getloadavg()[0]
        head = (
            "# Cost of the default scene's calibration, runs alternated\n\n"
            f"`python benchmarks/bench_calibration_cost.py --grids {args.grids.split(',')[0]} "
            f"--alternate {args.alternate}` (+ `--before-tree` for the old code). Machine: "
            f"{available_cpus()} CPUs, load average {load0:.1f} at the start, {load1:.1f} at the "
            "end. Each run is a fresh process (JIT warm-up, then `calibrate(Scene(grid=...))`); "
            "its unit is the fastest rfft2 + irfft2 pair of the grid (1 thread or all) timed "
            "just before it and, with glibc's heap kept as the solver keeps it, after it; "
            "'default' processes: 2 at 512^2 on 2 CPUs.\n\n"
        )
        RESULTS.mkdir(exist_ok=True)
        keys = ["code", "mode", "run", "seconds", "unit_ms", "cost_pairs", "counted_pairs"]
        write_rows(
            RESULTS / "bench_calibration_cost_alternate.csv",
            [{k: r.get(k) for k in keys} for r in rows],
            keys,
        )
        (RESULTS / "bench_calibration_cost_alternate.md").write_text(head + md)
        print(head + md)
        return

    from halfspace_calib.common import jobs
    from halfspace_calib.pipeline.calibration import Scene, calibrate

    install_counters()
    calibrate(Scene(grid=16), progress=False)  # JIT warm-up
    load0 = os.getloadavg()[0]
    cases = [f"default-{g}" for g in args.grids.split(",") if g]
    if args.surfaces:
        files = [f for f in args.files.split(",") if f]
        cases += [f"{f}-{g}" for f in files for g in args.file_grids.split(",") if g]
    else:
        print("no --surfaces folder: the measured-file cases are left out", file=sys.stderr)
    rows = []
    for case in cases:
        rec = _finish_row(costs(run_case(case, args.surfaces)), "new")
        rows.append(rec)
        print(f"{case}: {rec['seconds']:.1f} s, {rec['cost_pairs']:.0f} pairs", flush=True)
        if args.before_tree and case in args.before.split(","):
            env = dict(os.environ, PYTHONPATH=str(Path(args.before_tree).resolve()))
            out = subprocess.run(
                [sys.executable, str(HERE), "--child", case, "--surfaces", str(args.surfaces)],
                env=env,
                cwd=HERE.parent,
                capture_output=True,
                text=True,
                check=True,
            )
            old = _finish_row(json.loads(out.stdout.strip().splitlines()[-1]), "before")
            # the unit of this process, timed next to the new run: the child's own best pair
            # (kept as child_unit_ms) can be far off when other jobs load the cores meanwhile
            old["child_unit_ms"] = old["unit_ms"]
            old["unit_ms"] = rec["unit_ms"]
            old["cost_pairs"] = old["seconds"] / (1e-3 * rec["unit_ms"])
            rows.append(old)
            print(
                f"{case} before: {old['seconds']:.1f} s, {old['cost_pairs']:.0f} pairs", flush=True
            )
    par = []
    if args.parallel:
        case = cases[0]
        cpus = available_cpus()
        for label, workers, threads in (
            ("1 process, 1 FFT thread", 1, 1),
            (f"1 process, {cpus} FFT threads", 1, cpus),
            (f"{cpus} processes, 1 FFT thread each", cpus, 1),
        ):
            jobs._init_worker(threads)  # the serial path's FFT threads (pool workers set theirs)
            t0 = time.perf_counter()
            run_case(case, args.surfaces, workers=workers)
            par.append({"case": case, "mode": label, "seconds": time.perf_counter() - t0})
            print(f"{case} {label}: {par[-1]['seconds']:.1f} s", flush=True)
        jobs._init_worker(None)
    load1 = os.getloadavg()[0]
    RESULTS.mkdir(exist_ok=True)
    keys = (
        ["code"]
        + [c[1] for c in COLUMNS]
        + ["counted_pairs", "grid", "periodic", "problems", "mu_eff", "child_unit_ms"]
    )
    tmp = RESULTS / "bench_calibration_cost.csv.tmp"
    with open(tmp, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(dict.fromkeys(keys)), extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    tmp.replace(RESULTS / "bench_calibration_cost.csv")
    text = [
        "# Cost of a calibration in FFT pairs",
        "",
        f"Machine: {available_cpus()} CPUs, load average {load0:.1f} at the start, "
        f"{load1:.1f} at the end (other processes share the cores: compare ratios, not seconds).",
        "",
        table(rows),
    ]
    if par:
        text += ["", "| case | mode | seconds |", "|---|---|---|"]
        text += [f"| {p['case']} | {p['mode']} | {p['seconds']:.1f} |" for p in par]
    md = "\n".join(text) + "\n"
    tmp = RESULTS / "bench_calibration_cost.md.tmp"
    tmp.write_text(md)
    tmp.replace(RESULTS / "bench_calibration_cost.md")
    print(md)


if __name__ == "__main__":
    if "--child" in sys.argv:
        main()
    else:
        with run_record(__file__):
            main()
