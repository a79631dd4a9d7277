"""Workpiece and tool from different instruments: the 25 default calibrations of five files.

Every pair (workpiece x tool) of the five files of SurfaceTopography's public test set
(``metropro-1.dat``, ``mnt-1.mnt``, ``x3p-2.x3p``, ``sur-3.sur``, ``matrix-3.txt``; the
diagonal is a scan against itself) is calibrated with the command's defaults::

    halfspace-calib --workpiece W --tool T --workers 1 --no-progress --out TMP
                    [--max-undefined 0.95 where sur-3.sur is one of them]

and the table reports, per pair: the default ``lambda_s`` and grid, the elements per
``lambda_s``, the grid the default rule gave before the coarser scan was interpolated
(capped by its pixel: ``side / coarser pixel``), how the coarser scan was resampled, the
resolution check's changes of ``mu_eff`` and ``C1`` (grid against half of it; target at most
10 %), the wall time of the command and its exit status.

Writes ``benchmarks/results/two_instruments.csv`` and ``.md`` and prints the table. Run from
the repository root::

    python benchmarks/two_instruments.py --folder /work/shared/surfaces [--only A B ...]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _provenance import RESULTS, commit, pct, write_rows

FILES = ["metropro-1.dat", "mnt-1.mnt", "x3p-2.x3p", "sur-3.sur", "matrix-3.txt"]
FIELDS = [
    "workpiece",
    "tool",
    "exit",
    "lambda_s_um",
    "side_um",
    "grid",
    "elements_per_lambda_s",
    "grid_pixel_capped",
    "elements_per_lambda_s_pixel_capped",
    "resampled",
    "mu_eff",
    "C1",
    "mu_eff_change",
    "C1_change",
    "n1_change",
    "check_warns",
    "reload_in_sample_max",
    "reload_heldout_max",
    "reload_heldout_rms",
    "paper_heldout_max",
    "first_in_sample_max",
    "full_contact_from_MPa",
    "periodic",
    "boundary",
    "wall_s",
    "message",
]


def _one(folder, wp, tl, timeout):
    extra = ["--max-undefined", "0.95"] if "sur-3" in wp + tl else []
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "cal"
        cmd = [
            sys.executable,
            "-m",
            "halfspace_calib",
            "--workpiece",
            str(Path(folder) / wp),
            "--tool",
            str(Path(folder) / tl),
            "--workers",
            "1",
            "--no-progress",
            "--out",
            str(out),
            *extra,
        ]
        t0 = time.perf_counter()
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
            code, err = p.returncode, p.stderr
        except subprocess.TimeoutExpired:
            code, err = "timeout", f"not finished in {timeout} s"
        wall = time.perf_counter() - t0
        row = dict.fromkeys(FIELDS, "")
        row.update(workpiece=wp, tool=tl, exit=code, wall_s=round(wall, 1))
        lines = [ln.strip() for ln in err.splitlines() if ln.strip()]
        row["message"] = " | ".join(lines)[:400]
        summ = out / "summary.json"
        par = out / "params.json"
        if not par.is_file():
            par = out / "params.failed.json"
        if not summ.is_file():
            return row
        s = json.loads(summ.read_text())
        ls = json.loads(par.read_text())["provenance"]["extra"]["length_scale"]
        side = s["files"][0]["crop_size"]
        pitch = max(max(f["pitch"]) for f in s["files"])
        lam = ls["lambda_s"] or 0.0
        old = max(8, min(int(side / pitch * (1 + 1e-9)), s["grid"]))
        rc = s["resolution_check"] or {}
        prm = rc.get("params") or {}
        row.update(
            lambda_s_um=lam * 1e6,
            side_um=side * 1e6,
            grid=s["grid"],
            elements_per_lambda_s=ls["elements_per_lambda_s"],
            grid_pixel_capped=old,
            elements_per_lambda_s_pixel_capped=lam * old / side if lam else "",
            resampled="; ".join(
                f"{f['role']}: "
                + ("interpolated" if any("interpolated" in st for st in f["steps"]) else "averaged")
                for f in s["files"]
            ),
            mu_eff=s["mu_eff"],
            C1=s["C1"],
            mu_eff_change=prm.get("mu_eff", [None, None, math.nan])[2],
            C1_change=prm.get("C1", [None, None, math.nan])[2],
            n1_change=prm.get("n1", [None, None, math.nan])[2],
            check_warns=bool(rc.get("warning")),
            **_errors(s),
            periodic=s["periodic"],
            boundary=s.get("boundary", "periodic" if s["periodic"] else "isolated"),
        )
        return row


def _errors(s):
    """The reload branch's measured errors from ``summary.json`` (issue 31)."""
    err = s.get("errors") or {}
    rel, pap, first = (
        err.get("reload", {}),
        err.get("reload_paper", {}),
        err.get("first_loading", {}),
    )
    full = s.get("full_contact_from_pressure")
    return {
        "reload_in_sample_max": rel.get("in_sample_max", ""),
        "reload_heldout_max": rel.get("heldout_max", ""),
        "reload_heldout_rms": rel.get("heldout_rms", ""),
        "paper_heldout_max": pap.get("heldout_max", ""),
        "first_in_sample_max": first.get("in_sample_max", ""),
        "full_contact_from_MPa": full / 1e6 if full else "",
    }


def _g(v, fmt):
    return format(v, fmt) if isinstance(v, (int, float)) and not isinstance(v, bool) else "-"


def table(rows):
    lines = [
        "| workpiece | tool | lambda_s (um) | grid | elements / lambda_s | before: grid, "
        "elements / lambda_s | mu_eff | change of mu_eff / C1 at half the grid | check warns "
        "| reload max in sample / held out (RMS) | paper Eq. 25 held out | Eq. 24 in sample "
        "| time (s) | exit |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        before = (
            f"{r['grid_pixel_capped']}, {_g(r['elements_per_lambda_s_pixel_capped'], '.3g')}"
            if r["grid_pixel_capped"] != ""
            else "-"
        )
        lines.append(
            f"| {r['workpiece']} | {r['tool']} | {_g(r['lambda_s_um'], '.4g')} | "
            f"{r['grid'] or '-'} | {_g(r['elements_per_lambda_s'], '.3g')} | {before} | "
            f"{_g(r['mu_eff'], '.4g')} | {pct(r['mu_eff_change'])} / {pct(r['C1_change'])} | "
            f"{'yes' if r['check_warns'] is True else ('no' if r['check_warns'] is False else '-')}"
            f" | {_g(r['reload_in_sample_max'], '.3f')} / {_g(r['reload_heldout_max'], '.3f')} "
            f"({_g(r['reload_heldout_rms'], '.3f')}) | {_g(r['paper_heldout_max'], '.3f')} | "
            f"{_g(r['first_in_sample_max'], '.3f')} | {r['wall_s']} | {r['exit']} |"
        )
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--folder", required=True, help="folder holding the five files")
    ap.add_argument("--only", nargs="*", help="workpiece files to run (default: all five)")
    ap.add_argument("--timeout", type=float, default=900.0, help="seconds per calibration")
    a = ap.parse_args()
    rev = commit()
    rows = []
    RESULTS.mkdir(exist_ok=True)
    csv_path = RESULTS / "two_instruments.csv"
    for wp in a.only or FILES:
        for tl in FILES:
            r = _one(a.folder, wp, tl, a.timeout)
            rows.append(r)
            print(
                f"{wp} x {tl}: exit {r['exit']}, grid {r['grid']}, "
                f"mu_eff change {pct(r['mu_eff_change'])}, {r['wall_s']} s",
                flush=True,
            )
            write_rows(csv_path, rows, FIELDS)  # after each run: partial results kept
    head = (
        f"commit {rev}, {platform.machine()}, Python {platform.python_version()}; "
        f"halfspace-calib with its defaults, --workers 1; load average at the end "
        f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs\n\n"
    )
    text = head + table(rows) + "\n"
    (RESULTS / "two_instruments.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
