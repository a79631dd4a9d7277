"""Benchmark of the uncoupled tangential solver (Sec. 2.2): MPRGP vs the paper's Gauss-Seidel.

Three tables, written to ``benchmarks/results/bench_tangential.md`` (and ``.csv``):

1. MPRGP against projected Gauss-Seidel (the paper's method) on the same problems (Cattaneo-Mindlin
   Hertz contact with a Coulomb bound, and a patchy "rough" pressure field with the Tresca cap of
   Eq. 18), displacement control, same tolerance: wall time, iterations (MPRGP: operator
   applications; GS: sweeps), the ratio, and the difference of the tractions.
2. MPRGP scaling with the grid (Cattaneo-Mindlin, force control, ``Q = 0.5 mu P``): time,
   iterations, and the errors against the Cattaneo-Mindlin theory (the resolution knob).
3. The tolerance knob: error of ``delta`` and of the traction against a tight reference, and time.

Also writes ``bench_tangential_mindlin.png`` (traction along the x axis against theory).

Run: ``python benchmarks/bench_tangential.py [--quick]``.
"""

from __future__ import annotations

import argparse
import csv
import pathlib
import time

import numpy as np
from _provenance import run_record

from halfspace_calib.contact.cerruti import E_prime, shear_modulus_composite
from halfspace_calib.contact.tangential import _CerrutiOperator, solve_tangential, tangential_bound

E, NU = 210e9, 0.3
E_STAR = 1.0 / (2 * (1 - NU**2) / E)
E_PR = E_prime(E, NU, E, NU)
G_STAR = shear_modulus_composite(E, NU, E, NU)
MU = 0.3
OUT = pathlib.Path(__file__).resolve().parent / "results"


def hertz(n, p0=1e9, a=1e-4, box=2.2):
    dx = box * a / n
    x = (np.arange(n) - (n - 1) / 2) * dx
    X, Y = np.meshgrid(x, x, indexing="ij")
    r2 = X**2 + Y**2
    p = np.where(r2 < a * a, p0 * np.sqrt(np.clip(1 - r2 / a**2, 0, None)), 0.0)
    return p, dx, X, Y, a, p0


def rough(n, seed=3):
    rng = np.random.default_rng(seed)
    k = np.hypot(*np.meshgrid(np.fft.fftfreq(n), np.fft.rfftfreq(n), indexing="ij"))
    f = np.fft.irfft2(np.fft.rfft2(rng.normal(size=(n, n))) * np.exp(-((k / 0.08) ** 2)), s=(n, n))
    f = (f - f.mean()) / f.std()
    return np.where(f > 0.6, 8e8 * np.sqrt(np.clip(f - 0.6, 0, None)), 0.0), 1e-6


def timed(fun, repeat=1):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fun()
        best = min(best, time.perf_counter() - t0)
    return out, best


def mindlin_theory(p, dx, X, Y, a, p0, ratio):
    P = p.sum() * dx * dx
    c = a * (1 - ratio) ** (1 / 3)
    r2 = X**2 + Y**2
    q = MU * p - np.where(
        r2 < c * c, MU * p0 * c / a * np.sqrt(np.clip(1 - r2 / c**2, 0, None)), 0.0
    )
    delta = 3 * MU * P / (16 * a * G_STAR) * (1 - (1 - ratio) ** (2 / 3))
    return P, c, q, delta


def table_gs(sizes):
    rows = []
    for case in ("hertz-coulomb", "rough-tresca"):
        for n in sizes:
            if case == "hertz-coulomb":
                p, dx, *_ = hertz(n)
                kw = dict(mu=MU)
                g = tangential_bound(p, mu=MU)
            else:
                p, dx = rough(n)
                kw = dict(m=0.6, sigma_y=300e6)
                g = tangential_bound(p, **kw)
            u = _CerrutiOperator(p.shape, dx, dx, E_STAR, E_PR, False)(g)
            delta = 0.6 * u[g > 0].max()
            rm, tm = timed(
                lambda p=p, dx=dx, kw=kw, d=delta: solve_tangential(
                    p, dx, E_STAR, E_PR, delta=d, tol=1e-8, **kw
                ),
                repeat=3,
            )
            rg, tg = timed(
                lambda p=p, dx=dx, kw=kw, d=delta: solve_tangential(
                    p,
                    dx,
                    E_STAR,
                    E_PR,
                    delta=d,
                    tol=1e-8,
                    method="gauss-seidel",
                    maxiter=20000,
                    **kw,
                )
            )
            rows.append(
                dict(
                    case=case,
                    n=n,
                    n_contact=int((g > 0).sum()),
                    mprgp_s=tm,
                    mprgp_it=rm.nit,
                    gs_s=tg,
                    gs_sweeps=rg.nit,
                    speedup=tg / tm,
                    dq_rel=float(np.abs(rm.q - rg.q).max() / g.max()),
                    same_stick=bool(np.array_equal(rm.stick, rg.stick)),
                    converged=bool(rm.converged and rg.converged),
                )
            )
            print_row(rows[-1])
    return rows


def table_scaling(sizes, ratio=0.5):
    rows = []
    for n in sizes:
        p, dx, X, Y, a, p0 = hertz(n)
        P, c, q_th, d_th = mindlin_theory(p, dx, X, Y, a, p0, ratio)
        L2 = (n * dx) ** 2
        r, t = timed(
            lambda p=p, dx=dx, q=ratio * MU * P / L2: solve_tangential(
                p, dx, E_STAR, E_PR, q_mean=q, mu=MU, periodic=False
            )
        )
        rd, td = timed(
            lambda p=p, dx=dx, d=r.delta: solve_tangential(
                p, dx, E_STAR, E_PR, delta=d, mu=MU, periodic=False
            )
        )
        c_num = np.sqrt(r.stick.sum() * dx * dx / np.pi)
        rows.append(
            dict(
                n=n,
                a_over_dx=a / dx,
                force_ctrl_s=t,
                force_ctrl_matvec=r.nit,
                disp_ctrl_s=td,
                disp_ctrl_matvec=rd.nit,
                err_c=abs(c_num / c - 1),
                err_delta=abs(r.delta / d_th - 1),
                err_q_max=float(np.abs(r.q - q_th).max() / (MU * p0)),
                err_q_l2=float(np.sqrt(((r.q - q_th) ** 2).sum() / (q_th**2).sum())),
                converged=bool(r.converged),
            )
        )
        print_row(rows[-1])
    return rows


def table_tol(n, tols):
    p, dx, *_ = hertz(n)
    g = tangential_bound(p, mu=MU)
    ref = solve_tangential(
        p, dx, E_STAR, E_PR, q_mean=0.5 * MU * p.mean(), mu=MU, tol=1e-12, periodic=False
    )
    rows = []
    for tol in tols:
        r, t = timed(
            lambda tol=tol: solve_tangential(
                p, dx, E_STAR, E_PR, q_mean=0.5 * MU * p.mean(), mu=MU, tol=tol, periodic=False
            )
        )
        rows.append(
            dict(
                n=n,
                tol=tol,
                time_s=t,
                matvec=r.nit,
                err_delta=abs(r.delta / ref.delta - 1),
                err_q=float(np.abs(r.q - ref.q).max() / g.max()),
                stick_diff=int((r.stick != ref.stick).sum()),
            )
        )
        print_row(rows[-1])
    return rows


def plot_profile(n=256, ratio=0.5):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.6))
    p, dx, X, Y, a, p0 = hertz(n)
    for ratio in (0.3, 0.6, 0.9):
        P, c, q_th, _ = mindlin_theory(p, dx, X, Y, a, p0, ratio)
        r = solve_tangential(p, dx, E_STAR, E_PR, q_mean=ratio * MU * P / (n * dx) ** 2, mu=MU)
        j = n // 2
        ax.plot(X[:, j] / a, r.q[:, j] / (MU * p0), ".", ms=3, label=f"solver Q/muP={ratio}")
        ax.plot(X[:, j] / a, q_th[:, j] / (MU * p0), "k-", lw=0.8)
    ax.set_xlabel("x / a")
    ax.set_ylabel("q_x / (mu p0)")
    ax.set_title(f"Cattaneo-Mindlin, {n}x{n} non-periodic (lines: theory)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(OUT / "bench_tangential_mindlin.png", dpi=120)
    plt.close(fig)


def print_row(row):
    print("  ".join(f"{k}={_fmt(v)}" for k, v in row.items()), flush=True)


def _fmt(v):
    if isinstance(v, float):
        return f"{v:.3g}"
    return str(v)


def markdown(title, rows):
    keys = list(rows[0])
    lines = [f"### {title}", "", "| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    lines += ["| " + " | ".join(_fmt(r[k]) for k in keys) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes only (smoke run)")
    args = ap.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    gs_sizes = [16, 24] if args.quick else [16, 24, 32, 48]
    sc_sizes = [32, 64] if args.quick else [32, 64, 128, 256, 512]
    print("== MPRGP vs Gauss-Seidel (displacement control, tol 1e-8)")
    t1 = table_gs(gs_sizes)
    print("== MPRGP scaling, Cattaneo-Mindlin Q = 0.5 mu P (force control)")
    t2 = table_scaling(sc_sizes)
    print("== tolerance knob (Cattaneo-Mindlin, 128 x 128)")
    t3 = table_tol(64 if args.quick else 128, [1e-4, 1e-6, 1e-8, 1e-10])
    if not args.quick:
        plot_profile()
    md = (
        markdown("MPRGP vs projected Gauss-Seidel", t1)
        + "\n"
        + markdown("MPRGP scaling and accuracy vs Cattaneo-Mindlin", t2)
        + "\n"
        + markdown("Tolerance knob", t3)
    )
    (OUT / "bench_tangential.md").write_text(md)
    with open(OUT / "bench_tangential.csv", "w", newline="") as fh:
        for name, rows in (("gs", t1), ("scaling", t2), ("tol", t3)):
            w = csv.DictWriter(fh, fieldnames=["table", *rows[0]])
            w.writeheader()
            for r in rows:
                w.writerow({"table": name, **r})
    print(md)


if __name__ == "__main__":
    with run_record(__file__):
        main()
