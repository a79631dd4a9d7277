"""Which modulus holds the plateaus' sinking in a hardening bulk? A study of the truths (issue 43).

Eq. F2d bounds the sinking of the plateaus against the valleys in a hardening bulk by
``delta / l = 3 p / (4 h)``: columns under and between the contacts, in series along the
stretch, differ in flow stress by ``p`` and so in stretch by ``p`` over the tangent modulus ``h``
(in plane strain ``4 h / 3``), over a depth of one half-spacing. At 0.02 H the law given the
modulus errs both ways with the hardening exponent (docs/flattening.md, "Below the table"), so
this script asks the hardening FE truths (``flattening_hardening[_low][_tag].csv``: DC04 and
four other Swift curves of its initial yield) which modulus their sinking follows. For each
wedge at 0.02 and 0.05 H and the stretches 0.1 and 0.2 it reads the truth's sinking per
half-spacing, ``(A - alpha_0) tan(theta)`` (exact for a straight flank), and divides it

- by F2d's ``3 p / (4 h_t)``, ``h_t`` the curve's tangent modulus at the equivalent strain, and
- by ``3 p / (4 sqrt(h_t h_s))``, ``h_s = sigma_y / eps_p`` its secant modulus.

The second is what a linear comparison solid gives whose normal-difference modulus is the
tangent one and whose shear modulus is the secant one (J2 deformation theory's incremental
moduli, ``mu_1 = h_t / 3``, ``mu_2 = h_s / 3``): the surface of an incompressible orthotropic
half-space under a normal traction ``q cos(k x)`` moves by ``q / (2 k sqrt(mu_1 mu_2))``
whatever the ratio ``mu_1 / mu_2`` (:func:`orthotropic_compliance` solves the half-space's
fourth-order equation and the script prints its check against that closed form). Where the
quotient is the same on all five curves, the modulus is the right one; its value is the depth
factor that the column model sets to one half-spacing. Nothing is in the runtime: the runtime
has no secant modulus (the host passes the flow stress and the tangent modulus, not the total
plastic strain).

Second, what such a bound would do to the law (:func:`bound_curve`: the one-state law's ODE of
``flattening_hardening.candidate_curve``, F2c's rate, F2d's bound replaced by ``delta / l <=
DEPTH 3 p / (4 sqrt(h_t h_s))``) on every curve of the five hardening truths (0.02-0.45 H, all
five profiles), beside the runtime's law. ``DEPTH`` = 2 is read off the first table, so this
part is not a test of the law: it says what the modulus alone could change. Beside it the same
bound with the comparison half-space's own depth factor at each ``A``
(:func:`half_space_depth`), which nothing was read off.

Run: python benchmarks/flattening_sinking_modulus.py (40 s). Writes
benchmarks/results/flattening_sinking_modulus.md and .csv (run record: .run.json).
"""

import math

import flattening_hardening as fh
import numpy as np
from _provenance import RESULTS, read_rows, run_record, write_report
from flattening_hardening import _material
from flattening_truth import EQUIVALENT_PER_STRETCH, law_of, read_truth

import frictionlaw as fl
from frictionlaw.flattening import flattening_pressure

#: the hardening truths: results tag, the Swift curve (None: DC04) and a label
CURVES = (
    ("_n01", "259e6,0.006,0.1", "n 0.1"),
    ("_n02", "496144200,0.003,0.2", "n 0.2"),
    ("", None, "DC04 (n 0.24)"),
    ("_n03", "585164264,0.012,0.3", "n 0.3"),
    ("_n04", "742e6,0.02,0.4", "n 0.4"),
)
P_OVER_H = (0.02, 0.05)
STRETCHES = (0.1, 0.2)
#: the depth factor of the tangent-secant bound, read off this study's table (not derived)
DEPTH = 2.0


def half_space_depth(A, terms=2000):
    """The depth factor of the comparison half-space: the sinking of the contacts' centres
    against the valleys' under the contact pressure ``p / A`` on the fraction ``A`` of each
    period, in units of ``3 p l / (4 sqrt(h_t h_s))``: ``sum over odd n of 8 sin(n pi A) / (n^2
    pi^2 A)`` (1.485 at ``A = 0.5``, without bound as ``A -> 0``)."""
    n = 2.0 * np.arange(terms)[:, None] + 1.0
    a = np.atleast_1d(np.asarray(A, dtype=float))[None, :]
    return (8.0 * np.sin(n * np.pi * a) / (n * n * np.pi**2 * a)).sum(axis=0)


def bound_curve(P, p, slope, strains, mat, depth=DEPTH, grid=2001):
    """The one-state law (F2c's rate, F1-F3) with the sinking bounded by ``depth 3 p / (4
    sqrt(h_t h_s))`` in place of F2d's ``3 p / (4 h_t)``, integrated in ``A`` (Heun, as
    ``flattening_hardening.candidate_curve``); the bound read the other way on a stretch grid.
    ``depth`` None: the comparison half-space's own factor at each ``A``
    (:func:`half_space_depth`)."""
    a0 = float(fl.alpha_first(p, P))
    w = 0.5 - 0.5 * np.cos(np.pi * np.linspace(0.0, 1.0, grid))
    A = a0 + (1.0 - 1e-9 - a0) * w
    p_f = np.maximum(flattening_pressure(A, P), p)
    st = np.logspace(-7.0, 1.0, 4000)
    eq = EQUIVALENT_PER_STRETCH * st
    ht = np.array([float(mat.hardening(e)) for e in eq])
    hs = np.array([float(mat.flow_stress(e)) for e in eq]) / eq
    held = np.maximum.accumulate(0.75 * p / np.sqrt(ht * hs))
    factor = half_space_depth(A) if depth is None else depth
    reach = np.interp((A - a0) * slope / factor, held, st)  # beyond the grid: a stretch of 10

    def dstretch_dA(j, stretch):
        e = EQUIVALENT_PER_STRETCH * stretch
        s0 = 2.0 * float(mat.flow_stress(e)) / math.sqrt(3.0)
        c = min(1.0 + slope * (1.0 - A[j]), 6.0 * p * (1.0 - A[j]) / float(mat.hardening(e)))
        r = min(p / p_f[j], 1.0)
        return 0.0 if r >= 1.0 else slope / (c + (s0 / p_f[j]) * r / math.sqrt(1.0 - r * r))

    out = np.zeros_like(A)
    for i in range(1, A.size):
        dA = A[i] - A[i - 1]
        k1 = dstretch_dA(i - 1, out[i - 1])
        k2 = dstretch_dA(i, out[i - 1] + k1 * dA)
        out[i] = max(out[i - 1] + 0.5 * (k1 + k2) * dA, reach[i])
    return np.interp(np.asarray(strains, dtype=float), out, A)


def law_misses(pp, H):
    """``{label: (runtime's misses, the bound's (DEPTH), the bound's (the half-space's depth),
    pressures)}``: each curve's largest miss and its ``p / H``."""
    out = {}
    for tag, material, label in CURVES:
        mat = _material(material)
        src = read_rows(RESULTS / f"flattening_hardening{tag}.csv") + read_rows(
            RESULTS / f"flattening_hardening_low{tag}.csv"
        )
        now, new, half, at = [], [], [], []
        for name in dict.fromkeys(r["profile"] for r in src):
            deg = next(k for k in pp if k[0] == name)[1]
            mine = [r for r in src if r["profile"] == name]
            start = {float(r["p_over_H"]): r for r in mine if float(r["strain"]) == 0.0}
            P = law_of({q: {0.0: float(r["alpha_hardening"])} for q, r in start.items()}, deg, H)
            for ph in sorted(start):
                sel = [r for r in mine if float(r["p_over_H"]) == ph]
                t = np.array([float(r["alpha_hardening"]) for r in sel])
                law = np.array([float(r["alpha_law_with_hardening_modulus"]) for r in sel])
                b = bound_curve(P, ph * H, math.tan(math.radians(deg)), fh.STRAINS, mat)
                now.append(float(np.abs(law - t).max()))
                new.append(float(np.abs(b - t).max()))
                b = bound_curve(P, ph * H, math.tan(math.radians(deg)), fh.STRAINS, mat, None)
                half.append(float(np.abs(b - t).max()))
                at.append(ph)
        out[label] = (now, new, half, at)
    return out


def orthotropic_compliance(mu1, mu2, k=1.0):
    """Surface displacement amplitude of an incompressible orthotropic half-space (plane strain)
    under the normal traction ``cos(k x)``, shear-free: ``sigma_x - sigma_z = 4 mu1 eps_x``,
    ``tau = mu2 gamma``. The stream function's decaying roots of ``mu2 lam^4 - (4 mu1 - 2 mu2)
    lam^2 + mu2 = 0`` and the two boundary conditions, solved as a 2 x 2 system."""
    r = mu1 / mu2
    disc = complex(r * r - r) ** 0.5
    roots = [s * complex((2 * r - 1) + 2 * t * disc) ** 0.5 for t in (1, -1) for s in (1, -1)]
    lams = [lam for lam in roots if lam.real > 0][:2]
    rows, ws = [], []
    for lam in lams:
        dx, dz = 1j * k, -k * lam
        pi = (2 * mu1 * dx**2 * dz + mu2 * (dz**3 - dx**2 * dz)) / dx
        rows.append((-pi - 2 * mu1 * dx * dz, mu2 * (dz**2 - dx**2)))
        ws.append(-dx)
    c = np.linalg.solve(np.array(rows).T, np.array([-1.0, 0.0]))
    return float(np.real(np.dot(ws, c)))


def main():
    pp, H = read_truth(RESULTS / "asperity_flattening.csv")
    check = max(
        abs(orthotropic_compliance(1.0, m2) * 2.0 * math.sqrt(m2) - 1.0)
        for m2 in (1.5, 3.0, 10.0, 100.0, 1000.0)
    )
    rows, cells = [], {}
    for tag, material, label in CURVES:
        mat = _material(material)
        for stem in (f"flattening_hardening_low{tag}", f"flattening_hardening{tag}"):
            src = read_rows(RESULTS / f"{stem}.csv")
            start = {
                (r["profile"], r["p_over_H"]): float(r["alpha_hardening"])
                for r in src
                if float(r["strain"]) == 0.0
            }
            for r in src:
                ph, e = float(r["p_over_H"]), float(r["strain"])
                if not r["profile"].startswith("wedge") or ph not in P_OVER_H or e not in STRETCHES:
                    continue
                deg = float(r["profile"].split()[1])
                sink = (float(r["alpha_hardening"]) - start[(r["profile"], r["p_over_H"])]) * (
                    math.tan(math.radians(deg))
                )
                eq = EQUIVALENT_PER_STRETCH * e
                ht = float(mat.hardening(eq))
                hs = float(mat.flow_stress(eq)) / eq
                column = 0.75 * ph * H / ht
                ortho = 0.75 * ph * H / math.sqrt(ht * hs)
                rows.append(
                    {
                        "curve": label,
                        "p_over_H": ph,
                        "slope_deg": deg,
                        "stretch": e,
                        "sinking_per_half_spacing": round(sink, 6),
                        "over_tangent": round(sink / column, 4),
                        "over_tangent_secant": round(sink / ortho, 4),
                    }
                )
                cells.setdefault((ph, deg, e), []).append(rows[-1])
    lines = [
        "The truth's sinking per half-spacing `(A - alpha_0) tan(theta)` of each wedge, divided "
        "by F2d's `3 p / (4 h_t)` and by `3 p / (4 sqrt(h_t h_s))` (tangent and secant moduli of "
        "each Swift curve at the equivalent strain); the range over the five curves and each "
        "curve's second quotient (n 0.1 / 0.2 / DC04 / 0.3 / 0.4). A modulus that holds the "
        "sinking gives the same quotient on every curve.",
        "",
        "| p/H | wedge | stretch | over `3 p / (4 h_t)` (F2d) | over `3 p / (4 sqrt(h_t h_s))` "
        "| each curve |",
        "|---|---|---|---|---|---|",
    ]
    spread = {"over_tangent": [], "over_tangent_secant": []}
    for (ph, deg, e), cs in sorted(cells.items()):
        t = [c["over_tangent"] for c in cs]
        o = [c["over_tangent_secant"] for c in cs]
        spread["over_tangent"].append(max(t) / min(t))
        spread["over_tangent_secant"].append(max(o) / min(o))
        lines.append(
            f"| {ph:g} | {deg:g} deg | {e:g} | {min(t):.2f}-{max(t):.2f} | "
            f"{min(o):.2f}-{max(o):.2f} | " + " / ".join(f"{v:.2f}" for v in o) + " |"
        )
    lines += [
        "",
        "Largest / smallest quotient over the five curves, the median over the cells: F2d's "
        f"{np.median(spread['over_tangent']):.2f}, tangent and secant "
        f"{np.median(spread['over_tangent_secant']):.2f}.",
        "",
        "The orthotropic half-space's surface compliance against `q / (2 k sqrt(mu1 mu2))` at "
        f"`mu2 / mu1` 1.5-1000: largest relative difference {check:.1e}.",
        "",
        f"The law with the sinking bounded by `{DEPTH:g} x 3 p / (4 sqrt(h_t h_s))` (the factor "
        "read off the table above: not a test) against the runtime's law (F2d), every curve of "
        "each hardening truth at 0.02-0.45 H (20 curves each): largest miss / curves within "
        "0.05; the largest miss at 0.02-0.05 H alone (10 curves) beside it. Last, the same bound "
        "with the comparison half-space's own depth factor at each `A` (`half_space_depth`, "
        "nothing read off the truth; it grows without bound at small `A`).",
        "",
        "| hardening truth | runtime's law (F2d) | tangent-secant bound | at 0.02-0.05 H: F2d "
        "| tangent-secant | with the half-space's depth | at 0.02-0.05 H |",
        "|---|---|---|---|---|---|---|",
    ]
    for label, (now, new, half, at) in law_misses(pp, H).items():
        low = [k for k, ph in enumerate(at) if ph <= 0.05]
        lines.append(
            f"| {label} | {max(now):.3f} / {sum(m <= 0.05 for m in now)} | "
            f"{max(new):.3f} / {sum(m <= 0.05 for m in new)} | "
            f"{max(now[k] for k in low):.3f} | {max(new[k] for k in low):.3f} | "
            f"{max(half):.3f} / {sum(m <= 0.05 for m in half)} | "
            f"{max(half[k] for k in low):.3f} |"
        )
    write_report(
        "flattening_sinking_modulus",
        rows,
        ["# Which modulus holds the plateaus' sinking in a hardening bulk (issue 43 study)", ""]
        + lines,
    )


if __name__ == "__main__":
    with run_record(__file__, "flattening_sinking_modulus"):
        main()
