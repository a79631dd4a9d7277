"""The asperity truth of issue 43: contact fraction against bulk strain at constant pressure.

A plane-strain elastic-perfectly plastic strip (DC04's elasticity and initial yield, 155.3 MPa;
``H = (2 + pi) sigma_y / sqrt(3)``, the slip-line flat-punch pressure) whose top is a profile is
pressed by a rigid frictionless flat to ``p`` and stretched between its symmetry sides to bulk
strains up to 0.5 at that ``p`` (``fe_demo.asperity.asperity_contact_fraction``; nothing fitted).
Profiles: regular wedges of slopes 3, 5, 7 and 10 degrees (peak to valley: one flank of
``l = 50 um``, spacing 100 um; strip ``8 l = 400 um`` thick) and a line of a real scan,
``tests/data/matrix-3.txt``, levelled and S-filtered as the calibration does (ISO 16610-61, its
default ``lambda_s``), its middle row over the scan's width ``L = 10 um`` (strip ``4 L`` thick).
The strip is thick against the cell's width so that the perfectly plastic strip cannot neck
within the cell (a neck needs a wavelength of the order of the thickness; ``--depth`` measures
the effect of the thickness).

Parts (each writes its files under ``benchmarks/results/``):

- the table (default): ``asperity_flattening.csv``, ``.md``, ``.png``: alpha(p, strain) for every
  profile at ``p / H`` in 0.05 .. 0.6, mesh ``--nx`` x ``--nz`` (64 x 32);
- ``--convergence``: ``asperity_convergence.csv``, ``.md``: three cases on 32 x 16, 64 x 32 and
  128 x 48 elements, the differences and the first-order (Richardson) extrapolation;
- ``--depth``: ``asperity_depth.csv``, ``.md``: the 5 degree wedge at 0.1 H with the strip 1, 2,
  4, 8 and 16 flanks thick (64 x 32);
- ``--ccx``: ``asperity_ccx.csv``, ``.md``: one case against stock CalculiX 2.20
  (``ccx_reference``; C3D8I, one layer, plane strain by ``u_y = 0``, NLGEOM, node-to-surface
  penalty contact with a stiff elastic flat block loaded by a force on its rigid-body reference
  node); needs ``--ccx-work`` (or ``SBMF_CCX_WORK``) naming the CalculiX build;
- ``--punch``: ``asperity_punch.csv``: the flat punch's limit pressure against H on three meshes;
- ``--refine``: ``asperity_refined.csv``, ``.md``: every profile at the lowest and a high
  pressure (p/H 0.05 and 0.45, strains to 0.3) on the convergence study's fine mesh (128 x 48),
  beside the table's 64 x 32, with the first-order extrapolation; ``--workers`` processes (2);
- ``--rows``: ``asperity_rows.csv``, ``.md``: rows of the scan on meshes that resolve their
  samples (the table's 64 columns take every fourth): the middle row on 128 x 48 and 256 x 64 at
  every pressure, rows 64 and 192 on 256 x 64 at 0.05 and 0.1 H (169 min of one core) and,
  added later, at 0.2-0.6 H (8 jobs of 12-14 min each, two workers).
- ``--held-out``: ``asperity_rows_heldout.csv``, ``.md``: rows 32, 96, 160 and 224 on 256 x 64
  at 0.05, 0.1, 0.2, 0.3, 0.45 and 0.6 H, the rows fixed before any was run: the held-out test
  of a row's map to the wedge table (``flattening_limit_rows.py``).
- ``--stiff``: ``asperity_stiff.csv``, ``.md``: every profile at 0.05 and 0.1 H on the table's
  mesh with Young's modulus times 10 and 100 (yield and H unchanged): whether elasticity parts
  the truth from the rigid-plastic limit analysis (37 min of one core, sharing it).

Run: python benchmarks/asperity_flattening.py [--quick] [--convergence] [--ccx] [--punch]
[--depth] [--refine] [--rows] [--held-out] [--stiff] [--no-table]. On the shared 2-core machine the table took 38 min, the convergence study
32 min (the 128 x 48 runs), the thickness study 4 min, the flat punch 1 min, the CalculiX case
29 min (``asperity_flattening.run.json``: 105 min in all); ``--refine`` 29 min with two
workers (``asperity_refined.run.json``).
"""

import argparse
import math
import os
import time
from pathlib import Path

import numpy as np
from _asperity_ccx import ccx_case
from _provenance import RESULTS, ROOT, read_rows, run_record, write_report, write_rows

from fe_demo.asperity import (
    AsperityMesh,
    asperity_contact_fraction,
    flat_punch_pressure,
    perfectly_plastic,
    prandtl_hardness,
    wedge_profile,
)
from halfspace_calib.pipeline.sweep.length_scale import default_lambda_s
from halfspace_calib.pipeline.sweep.surface_plan import MAX_DEFAULT_GRID
from halfspace_calib.topography import chain, read_surface

SLOPES = (3.0, 5.0, 7.0, 10.0)
SPACING = 100e-6  # wedge asperity spacing 2 l (m); the strip models one flank, l = 50 um
P_OVER_H = (0.05, 0.1, 0.2, 0.3, 0.45, 0.6)
STRAINS = (0.0, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5)
MEASURED = ROOT / "tests" / "data" / "matrix-3.txt"
CONVERGENCE_MESHES = ((32, 16), (64, 32), (128, 48))
REFINE_P_OVER_H = (0.05, 0.45)  # the lowest pressure and a high one, every profile
REFINE_STRAINS = (0.0, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.3)
WEDGE_DEPTH = 8  # strip thickness / flank length
MEASURED_DEPTH = 4  # strip thickness / profile length
DEPTHS = (1, 2, 4, 8, 16)


def measured_profile(path=MEASURED, row=None):
    """A row of the scan (the middle one by default), levelled and S-filtered as the calibration
    does.

    Returns ``(x, z, lambda_s, notes)`` (m).
    """
    scan = read_surface(path)
    side = min(scan.heights.shape[0] * scan.dx, scan.heights.shape[1] * scan.dy)
    lam = default_lambda_s(side, max(scan.dx, scan.dy), MAX_DEFAULT_GRID)
    levelled, s1 = chain.level_scan(scan)
    filtered, s2 = chain.filter_scan(levelled, lam, None)
    h = filtered.heights
    line = h[h.shape[0] // 2 if row is None else row]
    x = np.arange(line.size) * filtered.dy
    return x, line - line.mean(), lam, (*s1, *s2)


def profile_rms_slope(x, z):
    """The RMS of the profile's slope ``dz / dx`` over its segments (a tangent)."""
    return float(np.sqrt(np.mean((np.diff(z) / np.diff(x)) ** 2)))


def profiles(quick=False):
    """``{name: (x, z, slope_deg or rms slope, depth)}`` of the table's profiles."""
    out = {}
    for s in SLOPES if not quick else (5.0,):
        x, z = wedge_profile(s, SPACING)
        out[f"wedge {s:g} deg"] = (x, z, s, WEDGE_DEPTH * SPACING / 2)
    x, z, lam, _ = measured_profile()
    rms = math.degrees(math.atan(profile_rms_slope(x, z)))
    out[f"matrix-3 row (lambda_s {lam * 1e6:.3g} um)"] = (x, z, rms, MEASURED_DEPTH * float(x[-1]))
    return out


def run_case(name, prof, p_over_h, strains, nx, nz, mat):
    x, z, slope, depth = prof
    H = prandtl_hardness(mat.sigma_y0)
    t0 = time.perf_counter()
    res = asperity_contact_fraction(x, z, p_over_h * H, strains, mat, AsperityMesh(nx, nz, depth))
    dt = time.perf_counter() - t0
    rows = []
    for e, a in zip(res.strains, res.alpha, strict=True):
        rows.append(
            {
                "profile": name,
                "slope_deg": round(slope, 4),
                "p_over_H": p_over_h,
                "p_Pa": p_over_h * H,
                "strain": e,
                "alpha": round(float(a), 5),
                "nx": nx,
                "nz": nz,
                "converged": res.converged,
                "volume_error": f"{abs(res.volume_change - res.elastic_dilatation):.2e}",
                "force_balance": f"{res.force_balance:.2e}",
                "increments": res.n_increments,
                "newton": res.n_newton,
                "seconds": round(dt, 1),
            }
        )
    status = "ok" if res.converged else f"STOPPED: {res.message}"
    print(
        f"{name:32s} p/H {p_over_h:<5g} {nx}x{nz}: alpha "
        + " ".join(f"{a:.3f}" for a in res.alpha)
        + f"  ({dt:.0f} s, {res.n_increments} incr, {res.n_newton} Newton; {status})",
        flush=True,
    )
    return rows


def table(args, mat):
    rows = []
    profs = profiles(args.quick)
    pressures = (0.1, 0.3) if args.quick else P_OVER_H
    strains = (0.0, 0.01, 0.05) if args.quick else STRAINS
    for name, prof in profs.items():
        for ph in pressures:
            rows += run_case(name, prof, ph, strains, args.nx, args.nz, mat)
    write_rows(RESULTS / "asperity_flattening.csv", rows)
    _markdown(rows, RESULTS / "asperity_flattening.md", args)
    _figure(rows, RESULTS / "asperity_flattening.png")


def _markdown(rows, path, args):
    strains = sorted({r["strain"] for r in rows})
    lines = [
        "# Contact fraction alpha against bulk strain at constant pressure (asperity truth)",
        "",
        f"`benchmarks/asperity_flattening.py`; mesh {args.nx} x {args.nz}; elastic-perfectly "
        "plastic (E 210 GPa, nu 0.3, sigma_y 155.3 MPa), H = (2 + pi) sigma_y / sqrt(3) = "
        f"{prandtl_hardness(perfectly_plastic().sigma_y0) / 1e6:.1f} MPa; frictionless flat.",
        "",
    ]
    for name in dict.fromkeys(r["profile"] for r in rows):
        sub = [r for r in rows if r["profile"] == name]
        lines += [
            f"## {name} (rms slope / slope {sub[0]['slope_deg']:.3g} deg)",
            "",
            "| p / H | " + " | ".join(f"{e:g}" for e in strains) + " | s |",
            "|---|" + "---|" * (len(strains) + 1),
        ]
        for ph in sorted({r["p_over_H"] for r in sub}):
            by = {r["strain"]: r for r in sub if r["p_over_H"] == ph}
            cells = [f"{by[e]['alpha']:.3f}" if e in by else "-" for e in strains]
            secs = max(r["seconds"] for r in by.values())
            lines.append(f"| {ph:g} | " + " | ".join(cells) + f" | {secs:.0f} |")
        lines.append("")
    path.write_text("\n".join(lines))


def _figure(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(dict.fromkeys(r["profile"] for r in rows))
    fig, axes = plt.subplots(1, len(names), figsize=(3.2 * len(names), 3.4), sharey=True)
    axes = np.atleast_1d(axes)
    for ax, name in zip(axes, names, strict=True):
        sub = [r for r in rows if r["profile"] == name]
        for ph in sorted({r["p_over_H"] for r in sub}):
            pts = sorted((r["strain"], r["alpha"]) for r in sub if r["p_over_H"] == ph)
            e, a = np.array(pts).T
            ax.plot(e, a, marker="o", ms=3, label=f"{ph:g}")
        ax.set_xscale("symlog", linthresh=0.01, linscale=0.6)
        ax.set_xlim(0, 0.55)
        ticks = [0, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5]
        ax.set_xticks(ticks, [f"{v:g}" for v in ticks], fontsize=7)
        ax.minorticks_off()
        ax.set_ylim(0, 1.02)
        ax.set_title(name, fontsize=8)
        ax.set_xlabel("bulk strain ln(L/L0)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("contact fraction alpha")
    axes[-1].legend(title="p / H", fontsize=7, title_fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def convergence(args, mat):
    profs = profiles()
    measured = next(k for k in profs if k.startswith("matrix-3"))
    cases = (("wedge 5 deg", 0.1), ("wedge 5 deg", 0.3), (measured, 0.3))
    strains = (0.0, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2)
    rows = []
    for name, ph in cases:
        for nx, nz in CONVERGENCE_MESHES:
            rows += run_case(name, profs[name], ph, strains, nx, nz, mat)
    write_rows(RESULTS / "asperity_convergence.csv", rows)
    lines = [
        "# Mesh convergence of alpha(strain) (asperity truth)",
        "",
        "Columns: alpha on each mesh; the differences between successive meshes; the first-order "
        "(Richardson) extrapolation 2 alpha_fine - alpha_medium (the contact edge lies between "
        "two nodes: the error is of the order of the top element's width).",
        "",
        "| case | strain | "
        + " | ".join(f"{nx}x{nz}" for nx, nz in CONVERGENCE_MESHES)
        + " | medium - coarse | fine - medium | extrapolated |",
        "|---|---|" + "---|" * (len(CONVERGENCE_MESHES) + 3),
    ]
    for name, ph in cases:
        for e in strains:
            a = []
            for nx, _ in CONVERGENCE_MESHES:
                hit = [
                    r["alpha"]
                    for r in rows
                    if r["profile"] == name
                    and r["p_over_H"] == ph
                    and r["nx"] == nx
                    and r["strain"] == e
                ]
                a.append(hit[0] if hit else float("nan"))
            lines.append(
                f"| {name}, p/H {ph:g} | {e:g} | "
                + " | ".join(f"{v:.3f}" for v in a)
                + f" | {a[1] - a[0]:+.3f} | {a[2] - a[1]:+.3f} | {2 * a[2] - a[1]:.3f} |"
            )
    (RESULTS / "asperity_convergence.md").write_text("\n".join(lines) + "\n")


def _run_job(job):
    os.environ.setdefault("OMP_NUM_THREADS", "1")  # one thread a process
    return run_case(*job)


def each_case(jobs, workers):
    """:func:`run_case` of each ``(name, profile, p/H, strains, nx, nz, material)`` in ``jobs``,
    ``workers`` processes: ``(index in jobs, its rows)`` as each job ends (a core never waits
    for another's job)."""
    from concurrent.futures import ProcessPoolExecutor, as_completed

    with ProcessPoolExecutor(max_workers=max(1, workers)) as pool:
        futures = {pool.submit(_run_job, job): k for k, job in enumerate(jobs)}
        for done in as_completed(futures):
            yield futures[done], done.result()


def run_cases(jobs, workers):
    """:func:`each_case`'s rows of each job, in the jobs' order."""
    return [rows for _, rows in sorted(each_case(jobs, workers), key=lambda kr: kr[0])]


_INTS = ("nx", "nz", "increments", "newton")


def typed_row(r):
    """A row of a :func:`run_case` CSV as :func:`run_case` returns it (numbers, not strings)."""
    return {
        k: v
        if k == "profile"
        else (v == "True")
        if k == "converged"
        else int(v)
        if k in _INTS
        else float(v)
        for k, v in r.items()
    }


def _job_key(job):
    """A job's ``(profile, p/H, nx)``, as :func:`_row_key` reads it from its rows."""
    return (job[0], job[2], job[4])


def _row_key(r):
    return (r["profile"], r["p_over_H"], r["nx"])


def cached_cases(jobs, stem, workers):
    """The rows of ``jobs`` (as :func:`each_case` takes them) in ``results/<stem>.csv``, in the
    jobs' order: the jobs that file or its partial file already holds are kept, the others run
    (the slow high pressures last), each kept in the partial file as it ends, so that a stopped
    run resumes; then the file is written whole and the partial file removed. Rows typed."""
    out, partial = RESULTS / f"{stem}.csv", RESULTS / f"{stem}.partial.csv"
    order = {_job_key(j): n for n, j in enumerate(jobs)}
    rows = {}
    for r in map(typed_row, read_rows(out) + read_rows(partial)):  # from one file or the other
        if _row_key(r) in order:
            rows[(_row_key(r), r["strain"])] = r
    rows = list(rows.values())
    done = {_row_key(r) for r in rows}
    todo = sorted((j for j in jobs if _job_key(j) not in done), key=lambda j: j[2])
    for _, part in each_case(todo, workers):
        rows += part
        write_rows(partial, rows)
    rows.sort(key=lambda r: (order[_row_key(r)], r["strain"]))
    write_rows(out, rows)
    partial.unlink(missing_ok=True)
    return rows


def refine(args, mat):
    """The table's extreme pressures on the fine mesh, beside the table's own mesh."""
    profs = profiles()
    nx, nz = CONVERGENCE_MESHES[-1]
    jobs = [(n, profs[n], ph, REFINE_STRAINS, nx, nz, mat) for ph in REFINE_P_OVER_H for n in profs]
    jobs.sort(key=lambda j: -j[2])  # the slow high pressures first
    rows = [r for part in run_cases(jobs, args.workers) for r in part]
    write_rows(RESULTS / "asperity_refined.csv", rows)
    base = RESULTS / "asperity_flattening.csv"
    coarse = {
        (r["profile"], float(r["p_over_H"]), float(r["strain"])): float(r["alpha"])
        for r in read_rows(base)
    }
    nxc = args.nx
    lines = [
        "# The asperity truth refined: the lowest and a high pressure on the fine mesh",
        "",
        f"`benchmarks/asperity_flattening.py --refine`: every profile at p/H "
        f"{', '.join(f'{v:g}' for v in REFINE_P_OVER_H)} on {nx} x {nz} elements, "
        f"beside the table's {nxc} x {args.nz} (`asperity_flattening.csv`); 'extrapolated' is "
        "the first-order (Richardson) 2 alpha_fine - alpha_table, clipped to [0, 1] (the "
        "contact edge lies between two nodes: the error is of the order of the top element).",
        "",
        "| profile | p/H | strain | alpha, table mesh | alpha, fine mesh | fine - table | "
        "extrapolated |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        a1 = coarse.get((r["profile"], float(r["p_over_H"]), float(r["strain"])), float("nan"))
        a2 = float(r["alpha"])
        ex = min(1.0, max(0.0, 2 * a2 - a1))
        lines.append(
            f"| {r['profile']} | {r['p_over_H']:g} | {r['strain']:g} | {a1:.3f} | {a2:.3f} | "
            f"{a2 - a1:+.3f} | {ex:.3f} |"
        )
    (RESULTS / "asperity_refined.md").write_text("\n".join(lines) + "\n")


ROWS = (64, 128, 192)  # the measured scan's rows: the middle one (the table's) and two more
ROW_MESHES = ((128, 48), (256, 64))  # nx 256: a top node on each of the row's 256 samples
ROW_STRAINS = (0.0, 0.005, 0.01, 0.02, 0.05, 0.1)
ROW_P_OVER_H = (0.05, 0.1, 0.2, 0.3, 0.45, 0.6)  # the other rows (0.2-0.6 added later)
# Four more rows, evenly spread between the others and fixed before any of them was run: the
# held-out test of a row's map to the wedge table (``--held-out``), at ``HELD_OUT_P_OVER_H``.
HELD_OUT_ROWS = (32, 96, 160, 224)
HELD_OUT_P_OVER_H = (0.05, 0.1, 0.2, 0.3, 0.45, 0.6)


def row_name(i, lam):
    return f"matrix-3 row {i} (lambda_s {lam * 1e6:.3g} um)"


def rows_study(args, mat, held_out=False):
    """``--rows``: measured rows on meshes that resolve their samples (the table's 64 columns
    take every fourth): the middle row on ``ROW_MESHES`` at every pressure, the others on the
    finest at ``ROW_P_OVER_H``; ``held_out``: ``HELD_OUT_ROWS`` on the finest at
    ``HELD_OUT_P_OVER_H`` (``asperity_rows_heldout``). Jobs done are kept in a partial file, and a
    rerun computes only the jobs that neither it nor the finished file holds."""
    jobs = []
    for i in HELD_OUT_ROWS if held_out else ROWS:
        x, z, lam, _ = measured_profile(row=i)
        rms = math.degrees(math.atan(profile_rms_slope(x, z)))
        prof = (x, z, rms, MEASURED_DEPTH * float(x[-1]))
        mid = not held_out and i == ROWS[1]  # the table's
        for nx, nz in ROW_MESHES if mid else ROW_MESHES[-1:]:
            for ph in P_OVER_H if mid else HELD_OUT_P_OVER_H if held_out else ROW_P_OVER_H:
                jobs.append((row_name(i, lam), prof, ph, ROW_STRAINS, nx, nz, mat))
    stem = "asperity_rows_heldout" if held_out else "asperity_rows"
    rows = cached_cases(jobs, stem, args.workers)
    order = dict.fromkeys(_job_key(j) for j in jobs)
    what = (
        f"rows {', '.join(str(i) for i in HELD_OUT_ROWS)} (held out) on "
        f"{ROW_MESHES[-1][0]} x {ROW_MESHES[-1][1]} elements at p/H "
        if held_out
        else "the middle one on "
        + " and ".join(f"{nx} x {nz}" for nx, nz in ROW_MESHES)
        + " elements, the others on the finest at p/H "
    )
    lines = [
        "# Measured rows on meshes that resolve them (asperity truth"
        + (", held-out rows)" if held_out else ")"),
        "",
        f"`benchmarks/asperity_flattening.py --{'held-out' if held_out else 'rows'}`: rows of "
        "`tests/data/matrix-3.txt` (256 samples over 10 um, levelled and S-filtered as the "
        "table's), "
        + what
        + ", ".join(f"{v:g}" for v in (HELD_OUT_P_OVER_H if held_out else ROW_P_OVER_H))
        + "; the table's 64 x 32 takes every fourth sample.",
        "",
        "| row | RMS slope (deg) | p/H | mesh | "
        + " | ".join(f"{e:g}" for e in ROW_STRAINS)
        + " |",
        "|---|---|---|---|" + "---|" * len(ROW_STRAINS),
    ]
    for k in order:
        sel = [r for r in rows if _row_key(r) == k]
        by = {float(r["strain"]): float(r["alpha"]) for r in sel}
        lines.append(
            f"| {k[0]} | {float(sel[0]['slope_deg']):.2f} | {k[1]:g} | {k[2]} x "
            f"{sel[0]['nz']} | " + " | ".join(f"{by[e]:.3f}" for e in ROW_STRAINS) + " |"
        )
    (RESULTS / f"{stem}.md").write_text("\n".join(lines) + "\n")


# ``--stiff``: the wedges at the lowest pressures with Young's modulus scaled (the law's limit
# analysis is rigid-plastic, the truth elastic-plastic)
STIFF_FACTORS = (10.0, 100.0)
STIFF_P_OVER_H = (0.05, 0.1)


def stiff_study(args, mat):
    """``--stiff``: every wedge and the middle row (the table's mesh) at ``STIFF_P_OVER_H`` with
    ``E`` times each of ``STIFF_FACTORS`` (Poisson's ratio, yield and ``H`` unchanged), strains
    ``ROW_STRAINS``, beside the table's ``E`` (``asperity_flattening.csv``):
    ``asperity_stiff.csv``, ``.md``."""
    jobs = []
    for name, prof in profiles().items():
        for f in STIFF_FACTORS:
            m = perfectly_plastic(E=mat.E * f, nu=mat.nu)
            for ph in STIFF_P_OVER_H:
                jobs.append((f"{name}, E x {f:g}", prof, ph, ROW_STRAINS, args.nx, args.nz, m))
    rows = [r for part in run_cases(jobs, args.workers) for r in part]
    base = {
        (r["profile"], float(r["p_over_H"]), float(r["strain"])): float(r["alpha"])
        for r in read_rows(RESULTS / "asperity_flattening.csv")
    }
    lines = [
        "# The truth with a stiffer elasticity: wedges and the middle row at low pressure",
        "",
        f"`benchmarks/asperity_flattening.py --stiff`: {args.nx} x {args.nz} elements, Young's "
        f"modulus {mat.E / 1e9:g} GPa times 1 (the table, `asperity_flattening.csv`) and "
        + ", ".join(f"{f:g}" for f in STIFF_FACTORS)
        + "; yield, Poisson's ratio and H unchanged. alpha after each strain.",
        "",
        *stiff_table({name: STIFF_FACTORS for name in profiles()}, STIFF_P_OVER_H, rows, base),
    ]
    write_report("asperity_stiff", rows, lines)


def stiff_table(cases, pressures, rows, base):
    """The Markdown table of a stiffness study: each profile of ``cases`` (``{name: factors}``)
    at ``pressures``, alpha at ``ROW_STRAINS`` with the table's ``E`` (``base``: ``{(profile,
    p/H, strain): alpha}``) and then with each factor (``rows``, profiles named ``"<name>, E x
    <factor>"``)."""
    lines = [
        "| profile | p/H | E factor | " + " | ".join(f"{e:g}" for e in ROW_STRAINS) + " |",
        "|---|---|---|" + "---|" * len(ROW_STRAINS),
    ]
    for name, factors in cases.items():
        for ph in pressures:
            b = [base.get((name, ph, e)) for e in ROW_STRAINS]
            lines.append(
                f"| {name} | {ph:g} | 1 | "
                + " | ".join("-" if v is None else f"{v:.3f}" for v in b)
                + " |"
            )
            for f in factors:
                by = {
                    float(r["strain"]): float(r["alpha"])
                    for r in rows
                    if r["profile"] == f"{name}, E x {f:g}" and float(r["p_over_H"]) == ph
                }
                lines.append(
                    f"| {name} | {ph:g} | {f:g} | "
                    + " | ".join(f"{by[e]:.3f}" if e in by else "-" for e in ROW_STRAINS)
                    + " |"
                )
    return lines


def depth_study(args, mat):
    x, z = wedge_profile(5.0, SPACING)
    strains = (0.0, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2)
    rows = []
    for k in DEPTHS:
        name = f"wedge 5 deg, depth {k} l"
        rows += run_case(name, (x, z, 5.0, k * SPACING / 2), 0.1, strains, args.nx, args.nz, mat)
    write_rows(RESULTS / "asperity_depth.csv", rows)
    lines = [
        "# Strip thickness: the 5 degree wedge at p = 0.1 H (asperity truth)",
        "",
        f"Mesh {args.nx} x {args.nz}; thickness in flank lengths l = 50 um.",
        "",
        "| thickness | " + " | ".join(f"{e:g}" for e in strains) + " |",
        "|---|" + "---|" * len(strains),
    ]
    for k in DEPTHS:
        by = {r["strain"]: r["alpha"] for r in rows if r["profile"].endswith(f"depth {k} l")}
        lines.append(
            f"| {k} l | " + " | ".join(f"{by[e]:.3f}" if e in by else "-" for e in strains) + " |"
        )
    (RESULTS / "asperity_depth.md").write_text("\n".join(lines) + "\n")


def punch(args, mat):
    rows = []
    for nx, nz in CONVERGENCE_MESHES:
        t0 = time.perf_counter()
        res = flat_punch_pressure(mat, nx=nx, nz=nz)
        rows.append(
            {
                "nx": nx,
                "nz": nz,
                "limit_over_H": round(res.limit_pressure / res.H, 4),
                "pressure_at_4pct_over_H": round(res.pressure[-1] / res.H, 4),
                "converged": res.converged,
                "seconds": round(time.perf_counter() - t0, 1),
            }
        )
        print(rows[-1], flush=True)
    write_rows(RESULTS / "asperity_punch.csv", rows)


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nx", type=int, default=64, help="elements along the profile (table)")
    ap.add_argument("--nz", type=int, default=32, help="elements through the thickness (table)")
    ap.add_argument("--quick", action="store_true", help="one wedge, two pressures, 3 strains")
    ap.add_argument("--no-table", action="store_true", help="skip the table")
    ap.add_argument("--convergence", action="store_true", help="the mesh study")
    ap.add_argument("--punch", action="store_true", help="the flat punch on three meshes")
    ap.add_argument("--depth", action="store_true", help="the strip thickness study")
    ap.add_argument(
        "--refine", action="store_true", help="p/H 0.05 and 0.45 on the fine mesh (128 x 48)"
    )
    ap.add_argument(
        "--rows", action="store_true", help="measured rows on meshes that resolve their samples"
    )
    ap.add_argument(
        "--held-out",
        action="store_true",
        help="rows 32, 96, 160 and 224 on 256 x 64 at 0.05-0.6 H (the rows' held-out test)",
    )
    ap.add_argument(
        "--stiff",
        action="store_true",
        help="the wedges and the middle row at 0.05 and 0.1 H with E x 10 and x 100",
    )
    ap.add_argument(
        "--workers", type=int, default=2, help="processes for --refine, --rows, --held-out (2)"
    )
    ap.add_argument("--ccx", action="store_true", help="the CalculiX cross-check")
    ap.add_argument(
        "--ccx-work",
        default=os.environ.get("SBMF_CCX_WORK"),
        help="CalculiX build folder holding ccx_reference (default: $SBMF_CCX_WORK)",
    )
    return ap.parse_args()


def main(args):
    mat = perfectly_plastic()
    RESULTS.mkdir(exist_ok=True)
    if not args.no_table:
        table(args, mat)
    if args.punch:
        punch(args, mat)
    if args.depth:
        depth_study(args, mat)
    if args.convergence:
        convergence(args, mat)
    if args.refine:
        refine(args, mat)
    if args.rows:
        rows_study(args, mat)
    if args.held_out:
        rows_study(args, mat, held_out=True)
    if args.stiff:
        stiff_study(args, mat)
    if args.ccx:
        if not args.ccx_work:
            raise SystemExit("--ccx needs --ccx-work or SBMF_CCX_WORK")
        ccx_case(Path(args.ccx_work) / "ccx_reference", mat, RESULTS)


if __name__ == "__main__":
    cli = parse_args()
    stem = (
        "asperity_rows_heldout"
        if cli.held_out
        else "asperity_rows"
        if cli.rows
        else "asperity_stiff"
        if cli.stiff
        else None
    )
    with run_record(__file__, stem if cli.no_table else None):
        main(cli)
