"""The CalculiX cross-check of the asperity truth (used by ``asperity_flattening.py --ccx``).

One case in stock CalculiX 2.20 (``ccx_reference``, which ``frictionlaw/export/calculix/build.sh
--lib-only`` builds from Debian's source without the friction patch) against ``fe_demo.asperity`` on the same nodes: the 5 degree wedge at
``p = 0.3 H``, pressed, then stretched to a bulk strain of 0.02.

The deck (units mm, N, MPa), written from the keywords CalculiX documents in its user's manual
(``*NODE``, ``*ELEMENT`` ``TYPE=C3D8I``, ``*SURFACE``, ``*RIGID BODY``, ``*SURFACE INTERACTION``
with ``*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR``, ``*CONTACT PAIR, TYPE=NODE TO SURFACE``,
``*STEP, NLGEOM``, ``*STATIC``, ``*BOUNDARY``, ``*CLOAD``, ``*NODE PRINT`` and
``*CONTACT PRINT`` with ``TIME POINTS``):

- the strip: the structured mesh of ``fe_demo.asperity.strip_mesh`` extruded one element layer
  deep in ``y`` (C3D8I: incompatible modes, which do not lock in the isochoric plastic flow as
  the fully integrated C3D8 does); ``u_y = 0`` on every node (plane strain), ``u_x = 0`` on the
  left side, ``u_x`` prescribed on the right side, ``u_z = 0`` on the bottom;
- elastic-perfectly plastic (``*PLASTIC`` with one point), the same E, nu, sigma_y;
- the flat: an elastic block (one element layer, any stiffness: it is made rigid) whose nodes
  form a ``*RIGID BODY``; its reference node carries the load ``P = p L t`` (``*CLOAD``, ramped:
  in the stretch ``L`` grows linearly with the side's displacement, so ``P`` ramped from ``p L0
  t`` to ``p L1 t`` holds ``p`` on the current length), its rotation node is fixed, and a weak
  spring (force below 1e-4 of ``P``) keeps the flat's equation regular before the first
  contact; frictionless (no ``*FRICTION``);
- node-to-surface penalty contact, the strip's top faces the slave, the block's bottom the master,
  the penalty slope ``10 E / h`` (h the top element's width) as in fe_demo;
- the contact fraction: top nodes (``y = 0``) with a contact pressure (``CSTR``), each with its
  tributary ``x`` length on the deformed configuration, over the current length: fe_demo's
  measure.
"""

import math
import re
import subprocess
import time

import numpy as np
from _provenance import write_rows

from fe_demo.asperity import (
    AsperityMesh,
    asperity_contact_fraction,
    prandtl_hardness,
    strip_mesh,
    wedge_profile,
)

SLOPE, P_OVER_H = 5.0, 0.3
NX, NZ = 64, 32
STRAINS = (0.0, 0.005, 0.01, 0.02)
L_MM = 0.05  # one flank of the 100 um spacing
DEPTH = 8  # strip thickness / flank length, as in the table
THICK = 0.005  # the extrusion (mm)


def _deck(strip, mat, p_mpa):
    n = strip.x.shape[0]
    x = strip.x * 1e3  # m -> mm
    length = strip.length * 1e3
    e_top = length / strip.nx
    lines = ["*HEADING", "asperity truth: wedge pressed and stretched (fe_demo cross-check)"]
    lines.append("*NODE")
    for k in range(n):
        lines.append(f"{k + 1}, {x[k, 0]:.12g}, 0, {x[k, 1]:.12g}")
        lines.append(f"{k + 1 + n}, {x[k, 0]:.12g}, {THICK:.12g}, {x[k, 1]:.12g}")
    # the flat block: 4 x 1 x 1 elements above the highest point, wider than the stretched strip
    ztop = float(x[strip.top, 1].max())
    bx = np.linspace(-0.2 * length, 1.4 * length, 5)  # covers the strip stretched by 0.02
    b0 = 2 * n + 1
    bnode = {}
    for i, xx in enumerate(bx):
        for j, yy in enumerate((0.0, THICK)):
            for k, zz in enumerate((ztop, ztop + 0.2 * length)):
                bnode[i, j, k] = b0 + len(bnode)
                lines.append(f"{bnode[i, j, k]}, {xx:.12g}, {yy:.12g}, {zz:.12g}")
    ref, rot = b0 + len(bnode), b0 + len(bnode) + 1
    lines.append(f"{ref}, {0.5 * length:.12g}, 0, {ztop + 0.1 * length:.12g}")
    lines.append(f"{rot}, {0.5 * length:.12g}, 0, {ztop + 0.1 * length:.12g}")
    lines.append("*ELEMENT, TYPE=C3D8I, ELSET=ESTRIP")
    t = strip.t
    for e in range(t.shape[1]):
        a, b, c, d = (int(v) + 1 for v in t[:, e])  # counter-clockwise in (x, z)
        # y = 0 face a-d-c-b (normal +y: towards the y = THICK face), then the same at y = THICK
        lines.append(f"{e + 1}, {a}, {d}, {c}, {b}, {a + n}, {d + n}, {c + n}, {b + n}")
    lines.append("*ELEMENT, TYPE=C3D8, ELSET=EBLOCK")
    eb0 = t.shape[1] + 1
    for i in range(len(bx) - 1):
        c = [bnode[i + di, j, k] for k in (0, 1) for (di, j) in ((0, 0), (1, 0), (1, 1), (0, 1))]
        lines.append(f"{eb0 + i}, " + ", ".join(map(str, c)))
    lines.append("*ELEMENT, TYPE=SPRING1, ELSET=ESPRING")
    lines.append(f"{eb0 + len(bx)}, {ref}")
    # top faces of the strip: local nodes 2 (d), 6, 7, 3 (c): face S4
    top_el = [e + 1 for e in range(t.shape[1]) if (e % strip.nz) == strip.nz - 1]
    lines += ["*SURFACE, NAME=SSTRIP"] + [f"{e}, S4" for e in top_el]
    # block bottom faces: nodes 1-2-3-4 at z = ztop: S1
    lines += ["*SURFACE, NAME=SBLOCK"] + [f"{eb0 + i}, S1" for i in range(len(bx) - 1)]
    lines += ["*NSET, NSET=NBLOCK"] + [f"{v}," for v in bnode.values()]
    lines += ["*NSET, NSET=NALL"] + [f"{k + 1}," for k in range(2 * n)]
    lines += ["*NSET, NSET=NLEFT"] + [f"{k + 1},\n{k + 1 + n}," for k in strip.left]
    lines += ["*NSET, NSET=NRIGHT"] + [f"{k + 1},\n{k + 1 + n}," for k in strip.right]
    lines += ["*NSET, NSET=NBOTTOM"] + [f"{k + 1},\n{k + 1 + n}," for k in strip.bottom]
    lines += ["*NSET, NSET=NTOP"] + [f"{k + 1}," for k in strip.top]
    sy = mat.sigma_y0 / 1e6
    load0 = p_mpa * length * THICK
    lines += [
        "*MATERIAL, NAME=STRIP",
        "*ELASTIC",
        f"{mat.E / 1e6:.10g}, {mat.nu:.10g}",
        "*PLASTIC",
        f"{sy:.10g}, 0.0",
        "*MATERIAL, NAME=BLOCK",
        "*ELASTIC",
        f"{mat.E / 1e6:.10g}, 0.3",
        "*SOLID SECTION, ELSET=ESTRIP, MATERIAL=STRIP",
        "*SOLID SECTION, ELSET=EBLOCK, MATERIAL=BLOCK",
        "*SPRING, ELSET=ESPRING",
        "3",
        f"{1e-4 * load0 / (0.1 * length):.6g}",
        f"*RIGID BODY, NSET=NBLOCK, REF NODE={ref}, ROT NODE={rot}",
        "*SURFACE INTERACTION, NAME=SI",
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
        f"{10 * mat.E / 1e6 / e_top:.6g}, {1e-3 * sy:.6g}",
        "*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE",
        "SSTRIP, SBLOCK",
        "*BOUNDARY",
        "NALL, 2, 2, 0.",
        "NLEFT, 1, 1, 0.",
        "NBOTTOM, 3, 3, 0.",
        f"{ref}, 1, 2, 0.",
        f"{rot}, 1, 3, 0.",
    ]
    emax = STRAINS[-1]
    u_end = length * (math.exp(emax) - 1)
    times = [(math.exp(e) - 1) / (math.exp(emax) - 1) for e in STRAINS[1:]]
    lines += ["*TIME POINTS, NAME=TP"] + [f"{v:.10g}," for v in times]
    for step, (u, load, tp) in enumerate(
        ((0.0, load0, None), (u_end, p_mpa * (length + u_end) * THICK, "TP")), 1
    ):
        lines += [
            "*STEP, NLGEOM, INC=2000",
            "*STATIC",
            "0.02, 1.0, 1e-7, 0.05" if step == 1 else "0.005, 1.0, 1e-7, 0.02",
            "*BOUNDARY",
            f"NRIGHT, 1, 1, {u:.12g}",
            "*CLOAD",
            f"{ref}, 3, {-load:.12g}",
            "*NODE PRINT, NSET=NTOP" + (f", TIME POINTS={tp}" if tp else ""),
            "U",
            "*NODE PRINT, NSET=NBLOCK" + (f", TIME POINTS={tp}" if tp else ""),
            "U",
            "*CONTACT PRINT" + (f", TIME POINTS={tp}" if tp else ""),
            "CSTR",
            "*END STEP",
        ]
    return "\n".join(lines) + "\n"


def _blocks(dat):
    """``{time: {"U": {node: (ux, uy, uz)}, "CSTR": {node: (p, t1, t2)}}}`` of a ``.dat``."""
    out = {}
    kind = cur = None
    for line in dat.read_text().splitlines():
        m = re.match(r"\s*(displacements|contact stress).*time\s+([-+.\dEe]+)", line)
        if m:
            kind = "U" if m.group(1) == "displacements" else "CSTR"
            cur = out.setdefault(float(m.group(2)), {}).setdefault(kind, {})
            continue
        parts = line.split()
        if cur is not None and len(parts) >= 4 and parts[0].isdigit():
            cur[int(parts[0])] = tuple(float(v) for v in parts[1:4])
        elif not parts:
            continue
        elif not parts[0].isdigit():
            cur = None
    return out


def _alpha(strip, block):
    """fe_demo's measure on the ccx state: nodes with contact pressure, tributary x lengths."""
    x0 = strip.x[strip.top, 0] * 1e3
    ux = np.array([block["U"][int(k) + 1][0] for k in strip.top])
    xt = x0 + ux
    dx = np.abs(np.diff(xt))
    trib = np.zeros(xt.size)
    trib[:-1] += 0.5 * dx
    trib[1:] += 0.5 * dx
    press = block.get("CSTR", {})
    touch = np.array([press.get(int(k) + 1, (0.0,))[0] > 0 for k in strip.top])
    return float(trib[touch].sum() / (xt[-1] - xt[0]))


def ccx_case(binary, mat, results):
    """Run the case in CalculiX and in fe_demo; write ``asperity_ccx.csv`` and ``.md``."""
    H = prandtl_hardness(mat.sigma_y0)
    px, pz = wedge_profile(SLOPE, 2 * L_MM * 1e-3)
    strip = strip_mesh(px, pz, DEPTH * L_MM * 1e-3, NX, NZ)
    folder = results / "asperity_ccx"
    folder.mkdir(exist_ok=True)
    (folder / "job.inp").write_text(_deck(strip, mat, P_OVER_H * H / 1e6))
    t0 = time.perf_counter()
    proc = subprocess.run(
        [str(binary), "-i", "job"],
        cwd=folder,
        capture_output=True,
        text=True,
        timeout=7200,
        env={"OMP_NUM_THREADS": "1", "NUMBER_OF_CPUS": "1", "PATH": "/usr/bin:/bin"},
    )
    t_ccx = time.perf_counter() - t0
    (folder / "ccx.log").write_text(proc.stdout[-20000:] + proc.stderr[-5000:])
    if proc.returncode != 0 or "Job finished" not in proc.stdout:
        raise SystemExit(f"ccx failed (exit {proc.returncode}); see {folder / 'ccx.log'}")
    blocks = _blocks(folder / "job.dat")
    # kept: the deck, the increments (.sta) and the log; the numbers are in the CSV
    for big in ("job.dat", "job.frd", "job.12d", "job.cvg", "spooles.out"):
        (folder / big).unlink(missing_ok=True)
    # step 1 prints every increment (its end is t = 1), step 2 its time points (t = 1 + fraction)
    times = [t for t in sorted(blocks) if t >= 1.0 - 1e-9]
    t0 = time.perf_counter()
    fe = asperity_contact_fraction(
        px, pz, P_OVER_H * H, STRAINS, mat, AsperityMesh(NX, NZ, DEPTH * L_MM * 1e-3)
    )
    t_fe = time.perf_counter() - t0
    rows = []
    for e, a_fe, t in zip(STRAINS, fe.alpha, times, strict=True):
        a_ccx = _alpha(strip, blocks[t])
        rows.append(
            {
                "strain": e,
                "ccx_time": t,
                "alpha_ccx": round(a_ccx, 4),
                "alpha_fe_demo": round(float(a_fe), 4),
                "difference": round(a_ccx - float(a_fe), 4),
            }
        )
        print(rows[-1], flush=True)
    write_rows(results / "asperity_ccx.csv", rows)
    md = [
        "# Asperity truth: fe_demo against stock CalculiX 2.20 (ccx_reference)",
        "",
        f"Wedge {SLOPE:g} deg (flank 50 um), p = {P_OVER_H:g} H, mesh {NX} x {NZ} (the same "
        "nodes; CalculiX: C3D8I one layer, u_y = 0), frictionless rigid flat, load control. "
        f"CalculiX {t_ccx:.0f} s, fe_demo {t_fe:.0f} s.",
        "",
        "| bulk strain | alpha CalculiX | alpha fe_demo | difference |",
        "|---|---|---|---|",
    ] + [
        f"| {r['strain']:g} | {r['alpha_ccx']:.3f} | {r['alpha_fe_demo']:.3f} | "
        f"{r['difference']:+.3f} |"
        for r in rows
    ]
    (results / "asperity_ccx.md").write_text("\n".join(md) + "\n")
