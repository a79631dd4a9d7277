"""How the FE asperity truth's flanks move under stretch (issue 43, a study of the truth).

The flattening law's kinematics (docs/flattening.md, Eq. F1) keep the flank rigid: the contact
edge advances because the flank block rises against the plateau, at ``c`` half-spacings per unit
stretch (the slip-line lattice, F2a: ``c = 1`` with a rigid flank, whatever the pressure). This
script reruns a few of the truth's cases (``fe_demo.asperity``, the same strip, mesh, material
and profiles as ``asperity_flattening.py``) with small strain steps and records the free flank
itself: its slope (a line fitted to the free top nodes between 10 % and 90 % of the flank,
against the profile's initial ``tan(theta)``), the valley's rise towards the tool, and the
contact fraction. For a straight flank of slope ``s`` and a valley ``d_v`` below the tool on a
half-spacing ``l``, ``A = 1 - d_v / (s l)`` (exact), so

``dA / d eps = R / s + (1 - A) (1 + d ln s / d eps)``,  ``R = -d d_v / (l d eps)``:

the valley's rise ``R`` grows the contact, a flank flattening faster than the stretch's own
convection (``d ln s / d eps = -2``, under which ``A`` does not change) shrinks it. Nothing is
fitted; the table shows which of the two terms carries the truth at each pressure.

Writes ``benchmarks/results/flattening_flank.csv`` and ``.md``. Run: python
benchmarks/flattening_flank.py [--quick] (six cases, about 6 min on the shared 2-core machine).
``--young-factor F`` instead reruns the 10 deg wedge at 0.05 and 0.15 H with Young's modulus
times ``F`` beside the truth's own and writes ``flattening_flank_young.md``: whether the flank's
flattening and the valley's slowing are elastic (about 5 min at ``F = 10``). ``--field`` reruns
the 10 deg wedge at 0.03-0.15 H and the 3 and 5 deg wedges at 0.05 H to a stretch of 0.06
keeping every node and writes ``flattening_field.md``: the velocity field beyond the homogeneous
stretch, which shows the mechanism at each pressure (about 7 min).
"""

import argparse
import math

import numpy as np
from _provenance import RESULTS, run_record, write_rows

from fe_demo.asperity import (
    AsperityMesh,
    asperity_contact_fraction,
    perfectly_plastic,
    prandtl_hardness,
    wedge_profile,
)
from fe_demo.asperity.flattening import AsperityOptions

SPACING = 100e-6  # as asperity_flattening.py: 2 l
DEPTH = 8 * SPACING / 2
CASES = ((3.0, 0.05), (3.0, 0.15), (10.0, 0.05), (10.0, 0.15), (10.0, 0.3), (5.0, 0.05))
REPORT = np.round(np.arange(0.0, 0.1201, 0.01), 3)  # strains of the table's rows
WINDOW = 0.005  # half-width of the strain window the rates are taken over


def flank_state(top, tool, length):
    """``(s, d_v)`` of a top surface: the free flank's fitted slope and the valley's depth."""
    x, z = top[:, 0], top[:, 1]
    free = z <= tool
    if free.sum() < 4:
        return math.nan, max(tool - z[-1], 0.0)
    edge = x[free].min()
    span = length - edge
    use = free & (x > edge + 0.1 * span) & (x < length - 0.1 * span)
    if use.sum() < 3:
        use = free
    s = -np.polyfit(x[use], z[use], 1)[0]
    return float(s), float(tool - z[-1])


def truth_run(deg, p_over_h, e_max, nx=64, nz=32, young=1.0, record_nodes=False):
    """The truth's case stretched in steps of at most 0.002 (its ``AsperityResult``).

    ``young`` multiplies the truth's Young's modulus (the yield stress, and so ``H``, unchanged).
    """
    mat = perfectly_plastic(E=perfectly_plastic().E * young)
    H = prandtl_hardness(mat.sigma_y0)
    x, z = wedge_profile(deg, SPACING)
    opt = AsperityOptions(max_strain_step=0.002, record_nodes=record_nodes)
    mesh = AsperityMesh(nx, nz, DEPTH)
    return asperity_contact_fraction(x, z, p_over_h * H, [0.0, e_max], mat, mesh, opt)


def run(deg, p_over_h, nx=64, nz=32, e_max=0.12, young=1.0):
    """One case: the history at every increment, ``(strain, alpha, s, d_v, l)`` arrays."""
    res = truth_run(deg, p_over_h, e_max, nx, nz, young)
    h = res.history
    e = np.array(h.strain)
    L = SPACING / 2 * np.exp(e)
    s, dv = np.array([flank_state(t, w, le) for t, w, le in zip(h.top, h.tool, L, strict=True)]).T
    return res, e, np.array(h.alpha), s, dv, L


def rows_of(deg, p_over_h, e, A, s, dv, L):
    """The table's rows: values at the report strains, rates over +-WINDOW."""
    t0 = math.tan(math.radians(deg))
    out = []
    for ek in REPORT:
        if ek > e[-1] + 1e-12:
            break
        lo, hi = max(ek - WINDOW, 0.0), min(ek + WINDOW, e[-1])

        def at(v, q):
            return float(np.interp(q, e, v))

        d = hi - lo
        a_k = at(A, ek)
        s_k = at(s, ek)
        R = -(at(dv, hi) - at(dv, lo)) / (at(L, ek) * d)
        dln_s = (math.log(at(s, hi)) - math.log(at(s, lo))) / d
        dA = (at(A, hi) - at(A, lo)) / d
        out.append(
            {
                "slope_deg": deg,
                "p_over_H": p_over_h,
                "strain": float(ek),
                "alpha": round(a_k, 4),
                "alpha_of_flank": round(1.0 - at(dv, ek) / (s_k * at(L, ek)), 4),
                "slope_ratio": round(s_k / t0, 4),
                "convected_ratio": round(math.exp(-2.0 * ek), 4),
                "dln_s_de": round(dln_s, 3),
                "valley_rise": round(R, 3),
                "c_truth": round(t0 * dA, 3),
                "c_rise": round(t0 * R / s_k, 3),
                "c_flank": round(t0 * (1.0 - a_k) * (1.0 + dln_s), 3),
                "c_lattice": round(1.0 + t0 * (1.0 - a_k), 3),
            }
        )
    return out


def _markdown(rows, path):
    lines = [
        "# How the FE asperity truth's flanks move under stretch",
        "",
        "`benchmarks/flattening_flank.py`: the truth's strip (64 x 32, perfectly plastic), each "
        "case stretched in steps of at most 0.002. `c` is the contact's growth in half-spacings "
        "per unit stretch, `tan(theta) dA / d eps`; `c_rise` and `c_flank` its two parts "
        "(`tan(theta) R / s` and `tan(theta) (1 - A)(1 + d ln s / d eps)`); `c_lattice` the "
        "rigid-flank lattice of Eq. F2a. Rates over a strain window of +-0.005.",
        "",
        "| wedge, p/H | strain | alpha (from the flank) | flank slope / initial (convected) | "
        "d ln s / d eps | valley rise R | c: truth = rise + flank | c_lattice |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r["alpha"] > 0.97:
            continue
        lines.append(
            f"| {r['slope_deg']:g} deg, {r['p_over_H']:g} | {r['strain']:.2f} | "
            f"{r['alpha']:.3f} ({r['alpha_of_flank']:.3f}) | {r['slope_ratio']:.3f} "
            f"({r['convected_ratio']:.3f}) | {r['dln_s_de']:.2f} | {r['valley_rise']:.2f} | "
            f"{r['c_truth']:.2f} = {r['c_rise']:.2f} + {r['c_flank']:.2f} | "
            f"{r['c_lattice']:.2f} |"
        )
    path.write_text("\n".join(lines) + "\n")


def young_study(factor):
    """The 10 deg wedge at 0.05 and 0.15 H with Young's modulus times ``factor`` beside the truth."""
    t0 = math.tan(math.radians(10.0))
    lines = [
        "# Is the truth's flank elastic? Young's modulus times " + f"{factor:g}",
        "",
        "`benchmarks/flattening_flank.py --young-factor`: the 10 deg wedge, the truth's strip "
        "(64 x 32, perfectly plastic, the same yield stress and `H`), steps of at most 0.002; "
        "alpha and the free flank's slope over its initial, the truth's modulus / times "
        f"{factor:g}.",
        "",
        "| p/H | strain | alpha | flank slope / initial | valley depth / l |",
        "|---|---|---|---|---|",
    ]
    worst = {"alpha": 0.0, "slope": 0.0}
    for ph in (0.05, 0.15):
        runs = [run(10.0, ph, e_max=0.1, young=y) for y in (1.0, factor)]
        for ek in REPORT[REPORT <= 0.1 + 1e-12]:
            v = [
                [float(np.interp(ek, e, q)) for q in (A, s / t0, dv / L)]
                for _, e, A, s, dv, L in runs
            ]
            worst["alpha"] = max(worst["alpha"], abs(v[0][0] - v[1][0]))
            worst["slope"] = max(worst["slope"], abs(v[0][1] - v[1][1]))
            lines.append(
                f"| {ph:g} | {ek:.2f} | "
                + " | ".join(f"{v[0][k]:.3f} / {v[1][k]:.3f}" for k in range(3))
                + " |"
            )
    lines += [
        "",
        f"Largest difference: {worst['alpha']:.3f} in alpha, {worst['slope']:.3f} in the flank's "
        "slope ratio.",
    ]
    path = RESULTS / "flattening_flank_young.md"
    path.write_text("\n".join(lines) + "\n")
    print(path.read_text())


FIELD_STRAINS = (0.006, 0.03, 0.055)


def field_rows(deg, p_over_h, e_max=0.06, nx=64, nz=32):
    """The velocity beyond the homogeneous stretch at :data:`FIELD_STRAINS` (a dict each).

    Between two increments about 0.004 apart: the vertical velocity per unit stretch in
    half-spacings, less the homogeneous flow's ``-(z - z_bottom)``, relative to the peak's top
    node, on every 4th column and the rows to a depth of ``1.3 l``; on the free top surface the
    jump at the contact edge and the line fitted to the rest of the flank (its slope, ``d w /
    d x``, turns the flank: ``-(d w / d x) / s`` adds to the convected ``d ln s / d eps = -2``);
    the jump is taken from the last node in contact to the third free one (the edge advances by
    one or two nodes over the interval).
    """
    h = truth_run(deg, p_over_h, e_max, nx, nz, record_nodes=True).history
    e = np.array(h.strain)
    out = []
    for ek in FIELD_STRAINS:
        i = int(np.argmin(abs(e - ek)))
        j = min(i + 1 + int(np.searchsorted(e[i + 1 :], e[i] + 0.0035)), len(e) - 1)
        x0, x1 = h.nodes[i], h.nodes[j]
        length = float(x0[:, 0].max())
        v = (x1[:, 1] - x0[:, 1]) / (e[j] - e[i]) / length
        w = (v + (x0[:, 1] - x0[:, 1].min()) / length).reshape(nx + 1, nz + 1)
        grid = x0.reshape(nx + 1, nz + 1, 2) / length
        w = w - w[0, -1]
        top_x, top_z = grid[:, -1, 0], grid[:, -1, 1]
        free = top_z * length <= h.tool[i] * (1 - 1e-12) - 1e-15
        first = int(np.argmax(free))
        flank = np.arange(first + 3, nx + 1)  # free through the interval (the edge advances)
        ramp = float(np.polyfit(top_x[flank], w[flank, -1], 1)[0]) if flank.size > 2 else math.nan
        s_now = -float(np.polyfit(top_x[flank], top_z[flank], 1)[0])
        depth = grid[0, -1, 1] - grid[0, :, 1]
        rows = [r for r in range(nz, -1, -1) if depth[r] <= 1.3]
        out.append(
            {
                "slope_deg": deg,
                "p_over_H": p_over_h,
                "strain": float(e[i]),
                "alpha": float(h.alpha[i]),
                "edge_x": float(top_x[first]),
                "edge_jump": float(w[first + 3, -1] - w[first - 1, -1]),
                "flank_ramp": ramp,
                "flank_turn": -ramp / s_now,
                "valley_rise": float(w[-1, -1]),
                "columns": top_x[::4],
                "depths": depth[rows],
                "w": w[::4][:, rows].T,
            }
        )
    return out


FIELD_CASES = ((10.0, 0.03), (10.0, 0.05), (10.0, 0.075), (10.0, 0.1), (10.0, 0.15))
FIELD_CASES += ((5.0, 0.05), (3.0, 0.05))
FIELD_MAPS = ((10.0, 0.05), (10.0, 0.15))


def field_study():
    """``--field``: the edge's share of the rise over pressures and slopes, two maps."""
    k_over_h = 1.0 / (2.0 + math.pi)  # k / H of prandtl_hardness
    lines = [
        "# The truth's velocity field under stretch",
        "",
        "`benchmarks/flattening_flank.py --field`: the truth's strip (64 x 32, perfectly plastic), "
        "steps of at most 0.002, every node kept. Vertical velocity per unit stretch in "
        "half-spacings beyond the homogeneous flow, relative to the peak's top node, over about "
        "0.004 of stretch. On the free surface: the jump at the contact edge (the slip-line "
        "lattice, Eq. F2a: all of the rise, the flank block rigid) and the fitted rise along the "
        "rest of the flank, `d w / d x` (0 for a rigid flank; it turns the flank by "
        "`-(d w / d x) / s` per unit stretch beyond the convected -2); the edge's share is the "
        "jump over the valley's rise.",
        "",
        "| wedge, p/H (p/k) | strain | alpha | edge x / l | jump at the edge | flank's rise "
        "d w / d x | its turn -(dw/dx)/s | valley's rise | edge's share |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    maps = []
    for deg, ph in FIELD_CASES:
        for r in field_rows(deg, ph):
            lines.append(
                f"| {deg:g} deg, {ph:g} ({ph / k_over_h:.2f}) | {r['strain']:.3f} | "
                f"{r['alpha']:.3f} | {r['edge_x']:.2f} | {r['edge_jump']:.2f} | "
                f"{r['flank_ramp']:.2f} | {r['flank_turn']:.1f} | {r['valley_rise']:.2f} | "
                f"{r['edge_jump'] / r['valley_rise']:.2f} |"
            )
            if (deg, ph) not in FIELD_MAPS:
                continue
            maps += [
                "",
                f"**{deg:g} deg, {ph:g} H, strain {r['strain']:.3f}, alpha {r['alpha']:.3f}** "
                "(rows: depth / l below the peak's top; columns: x / l)",
                "",
                "| depth | " + " | ".join(f"{c:.2f}" for c in r["columns"]) + " |",
                "|---" * (len(r["columns"]) + 1) + "|",
            ]
            maps += [
                f"| {d:.2f} | " + " | ".join(f"{v:+.2f}" for v in row) + " |"
                for d, row in zip(r["depths"], r["w"], strict=True)
            ]
        print(f"wedge {deg:g} deg, p/H {ph:g}: done", flush=True)
    path = RESULTS / "flattening_field.md"
    path.write_text("\n".join(lines + maps) + "\n")
    print("\n".join(lines))


def parse_args():
    """The command line (parsed before the run record, which is named by the mode)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one case (10 deg at 0.05 H)")
    ap.add_argument(
        "--young-factor",
        type=float,
        default=None,
        help="rerun 10 deg at 0.05 and 0.15 H with Young's modulus times this (default: off)",
    )
    ap.add_argument(
        "--field",
        action="store_true",
        help="write the velocity field over pressures (flattening_field.md) instead",
    )
    return ap.parse_args()


def record_stem(args):
    """The run record's stem: a mode's own, so the default run's record is kept."""
    if args.field:
        return "flattening_flank_field"
    return "flattening_flank_young" if args.young_factor is not None else None


def main(args):
    if args.field:
        field_study()
        return
    if args.young_factor is not None:
        young_study(args.young_factor)
        return
    cases = CASES[2:3] if args.quick else CASES
    rows = []
    for deg, ph in cases:
        res, e, A, s, dv, L = run(deg, ph)
        status = "ok" if res.converged else f"STOPPED: {res.message}"
        print(f"wedge {deg:g} deg, p/H {ph:g}: {len(e)} increments, {res.seconds:.0f} s, {status}")
        rows += rows_of(deg, ph, e, A, s, dv, L)
    write_rows(RESULTS / "flattening_flank.csv", rows)
    _markdown(rows, RESULTS / "flattening_flank.md")
    print((RESULTS / "flattening_flank.md").read_text())


if __name__ == "__main__":
    cli = parse_args()
    with run_record(__file__, record_stem(cli)):
        main(cli)
