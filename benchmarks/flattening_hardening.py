"""The asperity truth with a hardening bulk beside the perfectly plastic one and the law (issue 43).

The flattening law's lattice rate (docs/flattening.md, Eq. F2a) is derived for a rigid-perfectly
plastic strip: any pressure selects the flow that sinks the plateaus at one half-spacing per unit
strain, at no extra dissipation. A hardening bulk makes that choice cost work, so the lattice's
rate is an upper limit there. This study measures by how much: part B's FE asperity model
(``fe_demo.asperity``, the same meshes and loading as ``asperity_flattening.py``) with fe_demo's
DC04 Swift curve (``K = 530 MPa``, ``eps0 = 0.006``, ``n = 0.24``: the same initial yield stress
155.3 MPa as the perfectly plastic truth, so the same ``H``) beside the perfectly plastic truth's
curves, and the law given each increment's current flow stress as the host would
(``flattening_update(..., sigma_y=K (eps0 + eps)^n)``), its ``alpha1`` the hardening truth's own
pressing-alone fractions (as ``flattening_truth.py`` builds it from the perfectly plastic truth's),
so that the flattening is compared, not the first loading. Nothing is fitted.

Beside it the law given the hardening modulus too (docs/flattening.md, Eq. F2c: the lattice's
sinking limited by the hardening its uneven split costs, ``min(c_L, 6 p (1 - A) / h)``; Eq. F2d:
the flattening beyond the pressing held at the sinking the hardening holds, ``3 p / (4 h)``
half-spacings), computed by an independent ODE in ``A`` (:func:`candidate_curve`, F2d in closed
form), checked against the runtime's ``flattening_update(..., hardening=)`` with and without the
limits (the run prints both differences), and the ODE with F2c alone, as the runtime was before
F2d.

Held out: ``--material K,eps0,n`` runs another Swift curve of the same initial yield stress
(so the same ``H``), into ``flattening_hardening_<tag>.*``: F2d's depth of one half-spacing was
written down with DC04's truth in view, the ``n`` 0.1 and 0.4 curves were run after it was
fixed, and the ``n`` 0.2 and 0.3 curves (tags ``n02``, ``n03``) after F2c's factor ``1 - A``
was. A mesh study: ``--nx 128 --nz 48 --tag fine``.

Run: python benchmarks/flattening_hardening.py [--profiles "wedge 5 deg,wedge 10 deg"] [--reuse]
[--workers 2] [--material K,eps0,n --tag NAME] (default: every profile of
``asperity_flattening.py`` at p/H 0.05, 0.2 and 0.45, DC04; ``--reuse``: the hardening truth's
columns of the CSV a previous run wrote, the law evaluated again). 78 s with two workers on the
shared 2-core machine. Writes benchmarks/results/flattening_hardening[_NAME].csv and .md (run
record: .run.json).
"""

import argparse
import math
from pathlib import Path

import numpy as np
from _provenance import RESULTS, run_record, write_rows
from asperity_flattening import profiles, run_cases
from flattening_truth import EQUIVALENT_PER_STRETCH, law_of, law_strain, read_truth

import frictionlaw as fl
from fe_demo.solver.material import Material
from frictionlaw.flattening import flattening_pressure, flattening_update

P_OVER_H = (0.05, 0.2, 0.45)
STRAINS = (0.0, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2)
#: the default results' name
STEM = "flattening_hardening"
#: sub-steps of the law's integration between two reported strains (the flow stress per step)
SUBSTEPS = 50
#: depths of F2d's sinking zone in half-spacings beside its estimate (1), to show what it weighs
DEPTHS = (0.5, 2.0 / 3.0, 1.5, 2.0)


def miss_summary(misses):
    """The report's line of ``{law: [law - truth of each curve]}``: the largest miss, the RMS
    over the points and the curves within 0.05, per law."""
    return (
        "Over the curves, the largest miss / RMS over their points / curves within 0.05: "
        + "; ".join(
            f"{k} {max(np.abs(d).max() for d in v):.3f} / "
            f"{math.sqrt(np.mean(np.concatenate(v) ** 2)):.3f} / "
            f"{sum(np.abs(d).max() <= 0.05 for d in v)} of {len(v)}"
            for k, v in misses.items()
        )
        + "."
    )


def law_curve(P, p, strains, mat, hardening=False):
    """The law's contact fraction after the stretches ``strains`` at ``p``, each step at the
    current flow stress (of the equivalent plastic strain, ``2 / sqrt(3)`` of the stretch, which
    is also what the law is given)."""
    out, pf, e = [], p, 0.0
    for target in law_strain(strains):
        while e < target - 1e-15:
            de = min(target / SUBSTEPS, target - e)
            sy = float(mat.flow_stress(e + 0.5 * de))
            h = float(mat.hardening(e + 0.5 * de)) if hardening else None
            pf = float(flattening_update(pf, p, p, de, P, sigma_y=sy, hardening=h))
            e += de
        out.append(float(fl.alpha_first(max(pf, p), P)))
    return np.array(out)


def held_stretch(sink, p, mat, depth=1.0):
    """The stretch at which the sinking a hardening bulk holds (Eq. F2d) reaches ``sink``, the
    plateaus' sinking per half-spacing that a fraction needs (``(A - a0) tan(theta)`` on a
    straight flank): its Swift modulus ``h = n K (eps0 + eps_eq)^(n - 1)`` equal to ``3 p / (4
    sink)`` (0 where the initial modulus holds it already); ``depth``: the sinking zone's depth in
    half-spacings (F2d's estimate: 1)."""
    h = 0.75 * depth * p / sink
    eq = (h / (mat.n * mat.K)) ** (1.0 / (mat.n - 1.0)) - mat.eps0
    return np.maximum(eq, 0.0) / EQUIVALENT_PER_STRETCH


def candidate_curve(P, p, slope, strains, mat, limited=True, held=True, grid=4001, depth=1.0):
    """The contact fraction after the stretches ``strains`` at ``p`` with the lattice's rate
    limited by the hardening and the sinking it holds (module text; ``limited=False``: the
    runtime's perfectly plastic rate; ``held=False``: F2c alone; ``mat`` None: a perfectly
    plastic bulk at the file's flow stress, neither limit).

    ``d eps / dA = tan(theta) / (c_L,h + c_E)`` from ``alpha1(p)`` to full contact, Heun's
    method on a grid in ``A`` clustered at both ends, the flow stress and ``h`` at the
    equivalent strain ``2 / sqrt(3)`` of the stretch reached; ``c_E`` infinite at the start
    (``d eps / dA = 0`` there). With ``held`` no ``A`` is reached before the stretch at which
    the Swift modulus holds it (Eq. F2d, :func:`held_stretch`: ``A <= alpha1(p) + 3 p / (4 h
    tan(theta))`` read the other way, in closed form; ``depth`` half-spacings deep). ``slope``
    a function of ``A`` (a profile's edge slope, ``flattening_hardening_edges.py``): the flank
    at the contact edge, F2d's sinking the trapezoidal integral of it from ``alpha1(p)``.
    """
    a0 = float(fl.alpha_first(p, P))
    w = 0.5 - 0.5 * np.cos(np.pi * np.linspace(0.0, 1.0, grid))
    A = a0 + (1.0 - 1e-9 - a0) * w
    p_f = np.maximum(flattening_pressure(A, P), p)
    if callable(slope):
        E = np.array([slope(a) for a in A])
        sink = np.concatenate([[0.0], np.cumsum(0.5 * (E[1:] + E[:-1]) * np.diff(A))])
    else:
        E, sink = np.full(A.shape, float(slope)), (A - a0) * slope
    limited, held = limited and mat is not None, held and mat is not None

    def slope_of(j, stretch):
        eq = EQUIVALENT_PER_STRETCH * stretch
        sy = P.sigma_y if mat is None else float(mat.flow_stress(eq))
        s0 = 2.0 * sy / math.sqrt(3.0)
        c = 1.0 + E[j] * (1.0 - A[j])
        if limited:  # Eq. F2c: 2 p (1 - A) / h_k, h_k = h / 3
            c = min(c, 2.0 * p * (1.0 - A[j]) / (float(mat.hardening(eq)) / 3.0))
        r = min(p / p_f[j], 1.0)
        if r >= 1.0:
            return 0.0
        return E[j] / (c + (s0 / p_f[j]) * r / math.sqrt(1.0 - r * r))

    eps = np.zeros_like(A)
    for i in range(1, A.size):
        dA = A[i] - A[i - 1]
        k1 = slope_of(i - 1, eps[i - 1])
        k2 = slope_of(i, eps[i - 1] + k1 * dA)
        eps[i] = eps[i - 1] + 0.5 * (k1 + k2) * dA
        if limited and held:
            eps[i] = max(eps[i], float(held_stretch(sink[i], p, mat, depth)))
    return np.interp(np.asarray(strains, dtype=float), eps, A)


def _fe_runs(names, profs, args, mat, pressures=P_OVER_H):
    """The hardening truth of every (profile, pressure), ``--workers`` processes, on ``--nx`` x
    ``--nz`` elements: ``{(profile, p/H): (alpha at STRAINS, converged)}``."""
    keys = [(n, ph) for n in names for ph in pressures]
    jobs = [(n, profs[n], ph, STRAINS, args.nx, args.nz, mat) for n, ph in keys]
    runs = run_cases(jobs, args.workers)
    return {
        k: (np.array([r["alpha"] for r in fe]), fe[0]["converged"])
        for k, fe in zip(keys, runs, strict=True)
    }


def _stored_truth(stem=STEM):
    """``{(profile, p/H): (alpha_hardening, converged)}`` of the CSV a previous run wrote."""
    import csv

    out = {}
    with (RESULTS / f"{stem}.csv").open(encoding="utf-8") as f:
        for r in csv.DictReader(f):
            a, ok = out.setdefault((r["profile"], float(r["p_over_H"])), ([], r["converged"]))
            a.append(float(r["alpha_hardening"]))
    return {k: (np.array(a), ok == "True") for k, (a, ok) in out.items()}


def _material(text):
    """fe_demo's DC04, or the Swift curve ``K,eps0,n`` of the same initial yield stress."""
    dc04 = Material()
    if text is None:
        return dc04
    K, eps0, n = (float(v) for v in text.split(","))
    mat = Material(K=K, eps0=eps0, n=n)
    if abs(mat.sigma_y0 / dc04.sigma_y0 - 1.0) > 5e-3:
        raise SystemExit(
            f"--material: initial yield {mat.sigma_y0 / 1e6:.1f} MPa, not DC04's "
            f"{dc04.sigma_y0 / 1e6:.1f} MPa (the perfectly plastic truth's H)"
        )
    return mat


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--profiles",
        default=None,
        help="comma-separated profile names (default: all of asperity_flattening.py's)",
    )
    ap.add_argument("--workers", type=int, default=2, help="processes for the FE runs (2)")
    ap.add_argument("--nx", type=int, default=64)
    ap.add_argument("--nz", type=int, default=32)
    ap.add_argument(
        "--reuse", action="store_true", help="the hardening truth of the CSV a previous run wrote"
    )
    ap.add_argument(
        "--material",
        default=None,
        help="another Swift curve K,eps0,n (K in Pa) of DC04's initial yield (default: DC04)",
    )
    ap.add_argument(
        "--tag", default=None, help="results' name suffix (needed with --material; a mesh study)"
    )
    args = ap.parse_args(argv)
    if args.material and not args.tag:
        ap.error("--material needs --tag (the held-out curve's results by name)")
    stem = STEM + (f"_{args.tag}" if args.tag else "")
    stored = _stored_truth(stem) if args.reuse else None
    pp, H = read_truth(RESULTS / "asperity_flattening.csv")
    mat = _material(args.material)
    profs = profiles()
    names = list(profs) if args.profiles is None else args.profiles.split(",")
    if stored is None:
        stored = _fe_runs(names, profs, args, mat)
    rows, lines = [], []
    check = check_h = 0.0
    misses = {"without the modulus": [], "F2c alone": [], "F2c and F2d": []}
    depth_miss = {}
    for name in names:
        key = next(k for k in pp if k[0] == name)
        P = law_of(pp[key], key[1], H)
        hard = {}
        for ph in P_OVER_H:
            hard[ph] = stored[(name, ph)]
        # the law of the hardening truth's own pressing-alone fractions (as flattening_truth.py
        # builds it from the perfectly plastic truth's): the flattening compared, not alpha1
        Ph = law_of({ph: {0.0: float(a[0])} for ph, (a, _) in hard.items()}, key[1], H)
        for ph in P_OVER_H:
            a_h, ok = hard[ph]
            perfect = np.array([pp[key][ph][e] for e in STRAINS])
            law = fl.flattening_curve(ph * H, law_strain(STRAINS), P)  # perfectly plastic
            law_h = law_curve(Ph, ph * H, STRAINS, mat)
            slope = math.tan(math.radians(key[1]))
            cand = candidate_curve(Ph, ph * H, slope, STRAINS, mat)
            f2c = candidate_curve(Ph, ph * H, slope, STRAINS, mat, held=False)
            law_hh = law_curve(Ph, ph * H, STRAINS, mat, hardening=True)
            check_h = max(check_h, float(np.abs(law_hh - cand).max()))
            check = max(
                check,
                float(
                    np.abs(candidate_curve(Ph, ph * H, slope, STRAINS, mat, False) - law_h).max()
                ),
            )
            for key_m, curve in zip(misses, (law_h, f2c, cand), strict=True):
                misses[key_m].append(curve - a_h)
            for d in DEPTHS:
                c_d = candidate_curve(Ph, ph * H, slope, STRAINS, mat, depth=d)
                depth_miss[d] = max(depth_miss.get(d, 0.0), float(np.abs(c_d - a_h).max()))
            for i, e in enumerate(STRAINS):
                rows.append(
                    {
                        "profile": name,
                        "p_over_H": ph,
                        "strain": e,
                        "alpha_hardening": a_h[i],
                        "alpha_perfectly_plastic": perfect[i],
                        "alpha_law": law[i],
                        "alpha_law_hardening_start": law_h[i],
                        "alpha_law_with_hardening_modulus": cand[i],
                        "alpha_law_lattice_limit_only": f2c[i],
                        "flow_stress_MPa": float(mat.flow_stress(EQUIVALENT_PER_STRETCH * e)) / 1e6,
                        "converged": ok,
                    }
                )
            lines.append(
                f"| {name} | {ph:g} | "
                + " ".join(f"{v:.3f}" for v in a_h)
                + " | "
                + " ".join(f"{v:.3f}" for v in perfect)
                + " | "
                + " ".join(f"{v:.3f}" for v in law_h)
                + " | "
                + " ".join(f"{v:.3f}" for v in cand)
                + f" | {np.max(np.abs(law_h - a_h)):.3f} | {np.max(np.abs(f2c - a_h)):.3f} | "
                f"{np.max(np.abs(cand - a_h)):.3f} | {np.max(np.abs(law - perfect)):.3f} |"
            )
    write_rows(RESULTS / f"{stem}.csv", rows)
    head = [
        "# The asperity truth with a hardening bulk (issue 43 study)",
        "",
        f"`benchmarks/flattening_hardening.py`; mesh {args.nx} x {args.nz}; "
        f"{'DC04 ' if not args.material else ''}Swift "
        f"(K {mat.K / 1e6:.4g} MPa, eps0 {mat.eps0:g}, n {mat.n:g}; initial yield "
        f"{mat.sigma_y0 / 1e6:.1f} MPa), "
        f"H = {H / 1e6:.1f} MPa as the perfectly plastic truth's; strains "
        + ", ".join(f"{e:g}" for e in STRAINS)
        + ". The law: the truth's own pressing-alone alpha as alpha1 (the hardening truth's for "
        "the hardening columns), the profile's slope, beta = 1, each step at the current flow "
        "stress (the perfectly plastic law's miss is flattening_truth.py's, for comparison).",
        "",
        "| profile | p/H | alpha, hardening truth | alpha, perfectly plastic truth | alpha, law "
        "(hardening truth's alpha1, current flow stress) | alpha, law with the hardening "
        "modulus (F2c, F2d) | largest miss, hardening: law without the modulus | with the "
        "lattice's limit alone (F2c) | with both (F2c, F2d) | largest miss, perfectly plastic |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    lines.append("")
    lines.append(miss_summary(misses))
    lines.append("")
    lines.append(
        "F2d's sinking zone (one half-spacing deep) other depths, the largest miss with F2c: "
        + ", ".join(f"{d:g} half-spacings {m:.3f}" for d, m in depth_miss.items())
        + " (the ODE)."
    )
    lines.append("")
    lines.append(
        f"The ODE without the limit against the runtime's curve: {check:.1e} "
        f"largest difference in alpha; with the limit against the runtime given the hardening "
        f"modulus (`flattening_update(..., hardening=)`, {SUBSTEPS} steps between reported "
        f"strains): {check_h:.1e}."
    )
    text = "\n".join(head + lines) + "\n"
    Path(RESULTS / f"{stem}.md").write_text(text, encoding="utf-8")
    print(text)


def run_tagged(script, stem, main):
    """``main()`` under its run record, named ``stem`` or ``stem_<tag>`` as ``--tag`` says."""
    import sys

    tag = sys.argv[sys.argv.index("--tag") + 1] if "--tag" in sys.argv[:-1] else None
    with run_record(script, stem + (f"_{tag}" if tag else "")):
        main()


if __name__ == "__main__":
    run_tagged(__file__, STEM, main)
