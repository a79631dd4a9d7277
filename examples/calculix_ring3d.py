"""
Ring compression in 3D with CalculiX and the calibrated law
===========================================================

The whole chain for a CalculiX user, as a script (it builds CalculiX, so the documentation build
shows it without running it):

1. calibrate the law (``halfspace-calib``, the built-in default scene), or take ``--params``;
2. export it for CalculiX (``frictionlaw-export calculix --units mm-t-s``);
3. build ``ccx`` with the routine (the export's ``build.sh``; the first build takes minutes, then
   relinking takes seconds);
4. compress a quarter of the 6:3:2 ring (18 x 9 x 6 mm, DC04, to 50 %) in 3D: linear
   reduced-integration bricks, the upper half (symmetry at the mid-plane and on the two cut
   planes), a stiff flat die, ``*FRICTION, USER`` on node-to-surface contact (``--contact f2f``:
   face-to-face), the die force and the inner diameter at the mid-plane printed every
   increment, and ``p_hist`` (``*CONTACT FILE, CSDV``) in the ``.frd`` file for CGX;
5. run ``fe-demo ring`` (axisymmetric, the same law, material and schedule) and compare: the die
   force and the inner-diameter change over the stroke, in a table and ``ring3d_<contact>.png``.

Measured on a 2-core machine, node-to-surface, against ``fe-demo ring`` at 50 %: with the
default calibration's law, force -0.01 % and inner diameter 0.75 points off (72 s with the
library built); with the shipped example law (``--params fe_demo/data/sbmf_example.json``),
-0.72 % and 0.77 points; face-to-face, -1.07 % and 2.14 points (docs/fe_codes.md, "CalculiX",
says why).

Run it from a clone with the package installed and CalculiX's build dependencies present
(docs/fe_codes.md, "CalculiX")::

    python examples/calculix_ring3d.py --out out/ring3d

Every step writes into ``--out``; the CalculiX build tree is the export's default (outside
``--out``, shared by every export). Exit status 0 when both runs finished, 1 when one failed.
"""

import argparse
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

#: the ring (mm) and the die's stiffness factor over steel's
OD, ID, H = 18.0, 9.0, 6.0
DIE_STIFFNESS = 1000.0


def _swift_rows(points=60, eps_max=3.0):
    """``*PLASTIC`` rows (MPa, plastic strain) of fe_demo's DC04 Swift curve."""
    from fe_demo import DC04

    ep = np.concatenate([[0.0], np.geomspace(1e-4, eps_max, points - 1)])
    return [f"{DC04.flow_stress(e) / 1e6:.8g}, {e:.8g}" for e in ep]


def ring_deck(*, nr=12, nth=12, nz=8, reduction=0.5, n_inc=50, contact="n2f", slope=1e6, n_die=10):
    """The CalculiX deck of the quarter ring (mm, t, s): a string.

    Ring nodes ``(i, j, k)`` over radius, angle (0 to 90 degrees) and height (0 to H/2) are
    numbered ``1 + i + (nr + 1) (j + (nth + 1) k)``; node 1 is on the inner surface at the
    mid-plane. NDIE: the die's top nodes (the die force); NINNER: the inner nodes at the
    mid-plane (the inner diameter).
    """
    from fe_demo import DC04

    ri, ro, hh = ID / 2, OD / 2, H / 2
    rs = np.linspace(ri, ro, nr + 1)
    th = np.linspace(0.0, np.pi / 2, nth + 1)
    zs = np.linspace(0.0, hh, nz + 1)

    def nid(i, j, k):
        return 1 + i + (nr + 1) * (j + (nth + 1) * k)

    out = ["*HEADING", "quarter ring compression in 3D, *FRICTION, USER", "*NODE"]
    for k, z in enumerate(zs):
        for j, t in enumerate(th):
            for i, r in enumerate(rs):
                x, y = r * np.cos(t), r * np.sin(t)
                out.append(f"{nid(i, j, k)}, {x:.10g}, {y:.10g}, {z:.10g}")
    # the die: a plate over the quarter (1.5 outer radii), 1 mm thick, n_die x n_die elements
    nd, d0 = n_die, 100001
    side = 1.5 * ro
    grid = np.linspace(0.0, side, nd + 1)

    def did(i, j, k):
        return d0 + i + (nd + 1) * (j + (nd + 1) * k)

    for k, z in enumerate((hh, hh + 1.0)):
        for j, y in enumerate(grid):
            for i, x in enumerate(grid):
                out.append(f"{did(i, j, k)}, {x:.10g}, {y:.10g}, {z:.10g}")
    out.append("*ELEMENT, TYPE=C3D8R, ELSET=ERING")
    faces = []  # top face and the inner and outer sides, which fold onto the die
    e = 1
    for k in range(nz):
        for j in range(nth):
            for i in range(nr):
                c = [nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k), nid(i, j + 1, k)]
                c += [nid(i, j, k + 1), nid(i + 1, j, k + 1)]
                c += [nid(i + 1, j + 1, k + 1), nid(i, j + 1, k + 1)]
                out.append(f"{e}, " + ", ".join(map(str, c)))
                # C3D8 faces: S2 = 5-6-7-8 (top), S4 = 2-3-7-6 (outer), S6 = 4-1-5-8 (inner)
                if k == nz - 1:
                    faces.append(f"{e}, S2")
                if i == nr - 1:
                    faces.append(f"{e}, S4")
                if i == 0:
                    faces.append(f"{e}, S6")
                e += 1
    out.append("*ELEMENT, TYPE=C3D8, ELSET=EDIE")
    e = 100001
    bottom = []
    for j in range(nd):
        for i in range(nd):
            c = [did(i, j, 0), did(i + 1, j, 0), did(i + 1, j + 1, 0), did(i, j + 1, 0)]
            c += [did(i, j, 1), did(i + 1, j, 1), did(i + 1, j + 1, 1), did(i, j + 1, 1)]
            out.append(f"{e}, " + ", ".join(map(str, c)))
            bottom.append(f"{e}, S1")
            e += 1

    def nset(name, ids):
        return [f"*NSET, NSET={name}", *[f"{v}," for v in ids]]

    mid = [nid(i, j, 0) for j in range(nth + 1) for i in range(nr + 1)]
    ycut = [nid(i, 0, k) for k in range(nz + 1) for i in range(nr + 1)]
    xcut = [nid(i, nth, k) for k in range(nz + 1) for i in range(nr + 1)]
    out += ["*SURFACE, NAME=SRING", *faces, "*SURFACE, NAME=SDIE", *bottom]
    out += nset("NMID", mid) + nset("NYCUT", ycut) + nset("NXCUT", xcut)
    out += nset("NDIE", [did(i, j, 1) for j in range(nd + 1) for i in range(nd + 1)])
    out += nset("NINNER", [nid(0, j, 0) for j in range(nth + 1)])
    e_mpa = DC04.E / 1e6
    out += [
        "*MATERIAL, NAME=DC04",
        "*ELASTIC",
        f"{e_mpa:g}, {DC04.nu:g}",
        "*PLASTIC",
        *_swift_rows(),
        "*MATERIAL, NAME=DIE",
        "*ELASTIC",
        f"{DIE_STIFFNESS * e_mpa:g}, 0.3",
        "*SOLID SECTION, ELSET=ERING, MATERIAL=DC04",
        "*SOLID SECTION, ELSET=EDIE, MATERIAL=DIE",
        # the law: as docs/fe_codes.md prints it
        "*SURFACE INTERACTION, NAME=SBMF",
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
        f"{slope:g}, 0.01",
        # DEPVAR: p_hist, its cache, the status; the one property: the deck's unit system by
        # name, MM-T-S (PROPS(1) = 2., which the routine checks against the units it was
        # exported for; a ccx without the patch cannot read the name and stops)
        "*FRICTION, USER, DEPVAR=3, PROPERTIES=1",
        "MM-T-S",
        "*CONTACT PAIR, INTERACTION=SBMF, TYPE="
        + ("SURFACE TO SURFACE" if contact == "f2f" else "NODE TO SURFACE"),
        "SRING, SDIE",
        "*BOUNDARY",
        "NMID, 3, 3, 0.",
        "NYCUT, 2, 2, 0.",
        "NXCUT, 1, 1, 0.",
        "NDIE, 1, 2, 0.",
        f"*STEP, NLGEOM, INC={10 * n_inc}",
        "*STATIC",
        f"{1.0 / n_inc:.10g}, 1.0, 1e-5, {1.0 / n_inc:.10g}",
        "*BOUNDARY",
        f"NDIE, 3, 3, {-reduction * hh:.10g}",
        "*NODE PRINT, NSET=NDIE, TOTALS=ONLY",
        "RF",
        "*NODE PRINT, NSET=NINNER",
        "U",
        "*NODE FILE",
        "U",
        "*EL FILE",
        "S, PEEQ",
        "*CONTACT FILE",
        "CDIS, CSTR, CSDV",
        "*END STEP",
    ]
    return "\n".join(out) + "\n"


def read_ring_dat(path, reduction, nth):
    """Per output time of the ``.dat`` file: (height reduction, die force in N over the whole
    ring, inner-diameter change at the mid-plane: the mean over the inner nodes)."""
    text = Path(path).read_text()
    force = re.findall(
        r"total force \(fx,fy,fz\) for set NDIE and time\s+(\S+)\s*\n\s*\n\s*\S+\s+\S+\s+(\S+)",
        text,
    )
    disp = re.findall(
        r"displacements \(vx,vy,vz\) for set NINNER and time\s+(\S+)\s*\n\s*\n((?:[ \t]+\d+.*\n)+)",
        text,
    )
    ri = ID / 2
    th = np.linspace(0.0, np.pi / 2, nth + 1)
    x0, y0 = ri * np.cos(th), ri * np.sin(th)
    inner = {}
    for t, block in disp:
        u = np.array([[float(v) for v in line.split()] for line in block.strip().splitlines()])
        r = np.hypot(x0 + u[:, 1], y0 + u[:, 2])  # NINNER in angle order (node numbers)
        inner[float(t)] = float(np.mean(r) - ri) / ri
    # the die's reaction (its top nodes are pulled down): the force on a quarter of the ring
    return np.array([(float(t) * reduction, -4.0 * float(fz), inner[float(t)]) for t, fz in force])


def _run(cmd, **kw):
    print("+", " ".join(str(c) for c in cmd), flush=True)
    return subprocess.run([str(c) for c in cmd], check=True, **kw)


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="calculix_ring3d",
        description="Calibrate, export, build ccx, compress a quarter ring in 3D, compare with "
        "fe-demo ring (axisymmetric).",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    ap.add_argument("--out", type=Path, default=Path("out/ring3d"), help="working folder")
    ap.add_argument("--params", type=Path, help="a params.json (default: calibrate one)")
    ap.add_argument("--contact", choices=("n2f", "f2f"), default="n2f", help="contact type")
    ap.add_argument("--nr", type=int, default=12, help="elements across the wall")
    ap.add_argument("--nth", type=int, default=12, help="elements over the 90 degrees")
    ap.add_argument("--reduction", type=float, default=0.5, help="height reduction")
    ap.add_argument("--increments", type=int, default=50, help="fixed increments")
    ap.add_argument("--die", type=int, default=10, help="die elements along each side")
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1, help="ccx threads")
    args = ap.parse_args(argv)
    if not (2 <= args.nr <= 48 and 2 <= args.nth <= 96 and 0 < args.reduction < 0.8):
        ap.error("--nr in [2, 48], --nth in [2, 96], --reduction in (0, 0.8)")
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    py = sys.executable
    nz = max(1, round(args.nr * (H / 2) / ((OD - ID) / 2)))

    # 1. calibrate (the built-in default scene) unless a parameter file is given
    params = args.params
    if params is None:
        # Eq. 24 on first loading: the Fortran law core does not carry the tabulated form yet
        # (frictionlaw-export refuses such a file, naming the form)
        calib = ["--first-loading-form", "eq24", "--out", out / "calibration", "--quiet"]
        _run([py, "-m", "halfspace_calib", *calib])
        params = out / "calibration" / "params.json"
    params = Path(params).resolve()

    # 2. export for CalculiX (mm, t, s: the deck's units)
    export = out / "export"
    _run(
        [py, "-m", "frictionlaw.export", "calculix", "--params", params, "--out", export]
        + ["--units", "mm-t-s", "--force", "--quiet"]
    )

    # 3. build ccx with the routine (build tree: SBMF_CCX_WORK, else a cache folder)
    t0 = time.perf_counter()
    ccx = _run(["bash", export / "build.sh"], capture_output=True, text=True).stdout.strip()
    print(f"ccx: {ccx} ({time.perf_counter() - t0:.0f} s)")

    # 4. the 3D quarter ring in ccx
    run = out / f"ccx_{args.contact}"
    run.mkdir(exist_ok=True)
    deck = ring_deck(
        nr=args.nr,
        nth=args.nth,
        nz=nz,
        reduction=args.reduction,
        n_inc=args.increments,
        contact=args.contact,
        n_die=args.die,
    )
    (run / "ring3d.inp").write_text(deck)
    env = dict(os.environ, OMP_NUM_THREADS=str(args.threads))
    t0 = time.perf_counter()
    proc = subprocess.run([ccx, "-i", "ring3d"], cwd=run, env=env, capture_output=True, text=True)
    t_ccx = time.perf_counter() - t0
    (run / "ccx.log").write_text(proc.stdout + proc.stderr)
    if proc.returncode != 0 or "Job finished" not in proc.stdout:
        print(f"ccx failed (exit {proc.returncode}): see {run / 'ccx.log'}", file=sys.stderr)
        return 1
    ccx_rows = read_ring_dat(run / "ring3d.dat", args.reduction, args.nth)

    # 5. fe-demo ring, axisymmetric, the same law, material and schedule
    from fe_demo.scenes import run_ring
    from frictionlaw import FrictionParams

    t0 = time.perf_counter()
    ref = run_ring(
        "sbmf",
        params=FrictionParams.from_json(params),
        nr=args.nr,
        reduction=args.reduction,
        n_increments=args.increments,
    )
    t_fe = time.perf_counter() - t0
    if not ref.converged:
        print("fe-demo ring did not converge", file=sys.stderr)
        return 1
    red = np.asarray(ref.history["height_reduction"], dtype=float)
    f_ref = np.asarray(ref.history["force"], dtype=float)
    d_ref = np.asarray(ref.history["inner_diameter_change"], dtype=float)

    f3, d3 = ccx_rows[-1, 1], ccx_rows[-1, 2]
    print(
        f"\nat {args.reduction:.0%} height reduction ({args.contact}; ccx {t_ccx:.0f} s, "
        f"fe-demo {t_fe:.0f} s):"
    )
    print(
        f"  die force:            ccx 3D {f3 / 1e3:9.2f} kN   fe-demo {f_ref[-1] / 1e3:9.2f} kN"
        f"   ({(f3 - f_ref[-1]) / f_ref[-1]:+.2%})"
    )
    print(
        f"  inner diameter change: ccx 3D {d3:+9.2%}      fe-demo {d_ref[-1]:+9.2%}"
        f"      ({(d3 - d_ref[-1]) * 100:+.2f} points)"
    )
    np.savetxt(
        out / f"ring3d_{args.contact}.csv",
        ccx_rows,
        delimiter=",",
        header="height_reduction_fraction,force_N,inner_diameter_change_fraction",
        comments="",
    )

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    a1.plot(red * 100, f_ref / 1e3, "k-", label="fe-demo ring (axisymmetric)")
    a1.plot(
        ccx_rows[:, 0] * 100, ccx_rows[:, 1] / 1e3, "C0--", label=f"ccx 3D quarter ({args.contact})"
    )
    a1.set_xlabel("height reduction (%)")
    a1.set_ylabel("die force (kN)")
    a1.legend()
    a2.plot(red * 100, d_ref * 100, "k-", label="fe-demo ring")
    a2.plot(ccx_rows[:, 0] * 100, ccx_rows[:, 2] * 100, "C0--", label="ccx 3D quarter")
    a2.set_xlabel("height reduction (%)")
    a2.set_ylabel("inner diameter change (%)")
    a2.legend()
    fig.tight_layout()
    fig.savefig(out / f"ring3d_{args.contact}.png", dpi=120)
    print(f"wrote {out / f'ring3d_{args.contact}.png'} and the .csv; the .frd (CGX) is in {run}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
