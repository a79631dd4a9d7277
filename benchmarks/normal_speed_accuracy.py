"""Speed against accuracy of the normal contact solver: resolution and tolerance.

One physical surface (self-affine, Hurst 0.8, 2.11 mm square, Rq 1 um at the finest grid),
block-averaged from the finest grid to 64, 128, ... squared, solved periodic at p_mean with the
hardness cap H = 800 MPa (the calibration case; --elastic adds the elastic case) for tolerances
1e-4 ... 1e-10. Reports alpha, the mean pressure in contact (p_mean / alpha), iterations and
wall time, with alpha's relative deviation from the finest grid at the tightest tolerance.

Run:  python benchmarks/normal_speed_accuracy.py                 (finest 512, 300 MPa)
      python benchmarks/normal_speed_accuracy.py --finest 1024 --loads 100e6 300e6 600e6
Writes benchmarks/results/normal_speed_accuracy.{json,md,png} and prints the table.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from _provenance import run_record
from bench_normal_peers import E_STAR, H, L, self_affine  # noqa: E402

from halfspace_calib.contact.normal import solve_normal  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"


def block_average(h, n):
    f = h.shape[0] // n
    return h.reshape(n, f, n, f).mean(axis=(1, 3))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--finest", type=int, default=512)
    ap.add_argument("--coarsest", type=int, default=64)
    ap.add_argument("--tols", type=float, nargs="+", default=[1e-4, 1e-6, 1e-8, 1e-10])
    ap.add_argument("--loads", type=float, nargs="+", default=[300e6])
    ap.add_argument("--elastic", action="store_true", help="also the elastic case")
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument(
        "--single", action="store_true", help="also run every case with single-precision FFTs"
    )
    ap.add_argument(
        "--kmax",
        type=int,
        default=None,
        help="band-limit the surface to kmax wavelengths per side (default: "
        "roughness down to the finest grid)",
    )
    ap.add_argument("--out", default="normal_speed_accuracy")
    args = ap.parse_args(argv)

    fine = self_affine(args.finest, kmax=args.kmax)
    sizes = []
    n = args.coarsest
    while n <= args.finest:
        sizes.append(n)
        n *= 2
    solve_normal(block_average(fine, sizes[0]), L / sizes[0], E_STAR, 1e8)  # JIT warm-up
    rows = []
    for capped in [True, False] if args.elastic else [True]:
        for p_mean in args.loads:
            for n in sizes:
                h = block_average(fine, n)
                for tol, single in [
                    (t, s)
                    for t in sorted(args.tols, reverse=True)
                    for s in ([False, True] if args.single else [False])
                    if not (s and t < 1e-6)
                ]:  # below single roundoff
                    t0 = time.perf_counter()
                    r = solve_normal(
                        h,
                        L / n,
                        E_STAR,
                        p_mean,
                        H=H if capped else None,
                        tol=tol,
                        workers=args.workers,
                        maxiter=20000,
                        single=single,
                    )
                    wall = time.perf_counter() - t0
                    rows.append(
                        dict(
                            capped=capped,
                            p_mean_MPa=p_mean / 1e6,
                            n=n,
                            tol=tol,
                            single=single,
                            alpha=r.alpha,
                            p_contact_MPa=p_mean / r.alpha / 1e6,
                            nit=r.nit,
                            wall_s=wall,
                            converged=r.converged,
                            rq_um=float(h.std() * 1e6),
                        )
                    )
                    print(json.dumps(rows[-1]), flush=True)
    # deviation from the finest grid at the tightest tolerance, per case
    for r in rows:
        ref = [
            q
            for q in rows
            if q["capped"] == r["capped"]
            and q["p_mean_MPa"] == r["p_mean_MPa"]
            and q["n"] == sizes[-1]
            and q["tol"] == min(args.tols)
            and not q["single"]
        ][0]
        same_n = [
            q
            for q in rows
            if q["capped"] == r["capped"]
            and q["p_mean_MPa"] == r["p_mean_MPa"]
            and q["n"] == r["n"]
            and q["tol"] == min(args.tols)
            and not q["single"]
        ][0]
        r["alpha_rel_dev_finest"] = r["alpha"] / ref["alpha"] - 1.0
        r["alpha_rel_dev_tol"] = r["alpha"] / same_n["alpha"] - 1.0

    RESULTS.mkdir(exist_ok=True)
    (RESULTS / f"{args.out}.json").write_text(
        json.dumps(dict(args=vars(args), rows=rows), indent=1)
    )
    lines = [
        "| case | p_mean MPa | N | tol | FFT | Rq um | alpha | dev vs finest "
        "| dev vs tightest tol | p in contact MPa | nit | wall s |",
        "|" + "---|" * 12,
    ]
    for r in rows:
        lines.append(
            f"| {'H' if r['capped'] else 'el'} | {r['p_mean_MPa']:.0f} | {r['n']} | {r['tol']:.0e} "
            f"| {'single' if r['single'] else 'double'} "
            f"| {r['rq_um']:.3f} | {r['alpha']:.4f} | {100 * r['alpha_rel_dev_finest']:+.2f}% "
            f"| {100 * r['alpha_rel_dev_tol']:+.3f}% | {r['p_contact_MPa']:.1f} | {r['nit']} "
            f"| {r['wall_s']:.3f} |"
        )
    table = "\n".join(lines)
    (RESULTS / f"{args.out}.md").write_text(table + "\n")
    print(table)
    plot(rows, sizes, args, RESULTS / f"{args.out}.png")


def plot(rows, sizes, args, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for capped in sorted({r["capped"] for r in rows}):
        for p_mean in args.loads:
            for tol in sorted(args.tols):
                sel = [
                    r
                    for r in rows
                    if r["capped"] == capped
                    and r["tol"] == tol
                    and r["p_mean_MPa"] == p_mean / 1e6
                    and not r["single"]
                ]
                lab = f"{'H' if capped else 'el'} {p_mean / 1e6:.0f} MPa tol {tol:.0e}"
                ax[0].plot([r["n"] for r in sel], [r["alpha"] for r in sel], "o-", label=lab)
                ax[1].loglog([r["n"] for r in sel], [r["wall_s"] for r in sel], "o-", label=lab)
    for a in ax:
        a.set_xscale("log", base=2)
        a.set_xlabel("N (grid N x N, same 2.11 mm surface)")
        a.grid(True, which="both", alpha=0.3)
    ax[0].set_ylabel("alpha = A_real / A0")
    ax[1].set_ylabel("wall time [s]")
    ax[0].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    with run_record(__file__):
        main()
