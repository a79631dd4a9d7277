"""Normal contact: ours vs Tamaas and ContactMechanics on the same surfaces, in one run.

Self-affine periodic random surface (Hurst 0.8, 2.11 mm square, Rq 1 um), E = 210 GPa and
nu = 0.3 on both bodies (E* = 115.4 GPa), periodic, elastic and capped (H = 800 MPa). For each
grid size and load: alpha from each code (agreement within 1e-3 is checked), the relative L2
difference of the pressure fields to ours, iterations, wall time, ratio ours/peer, and the cost
of one of our iterations against one forward + one inverse real FFT of the same grid measured in
the same run (the baseline).

Run (defaults are short: 256 and 512 squared, 300 MPa):
    python benchmarks/bench_normal_peers.py
    python benchmarks/bench_normal_peers.py --sizes 256 512 1024 --loads 100e6 300e6 600e6
    python benchmarks/bench_normal_peers.py --ours-only 2048
Writes benchmarks/results/normal_peers.json and .md, prints the table.
Peers that are not installed (`pip install tamaas contactmechanics`, the `peers` extra) are
skipped and marked as such.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import platform
import re
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import scipy.fft as sfft

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _provenance import run_record

from halfspace_calib.contact.influence import normal_operator  # noqa: E402
from halfspace_calib.contact.normal import composite_modulus, solve_normal  # noqa: E402

L = 2.11e-3
E_STAR = composite_modulus(210e9, 0.3, 210e9, 0.3)
H = 800e6
RESULTS = Path(__file__).resolve().parent / "results"


def self_affine(n, seed=1, rq=1e-6, hurst=0.8, kmax=None):
    """Periodic self-affine Gaussian surface, PSD ~ q^-(2 + 2 Hurst) down to the grid scale
    (or, with ``kmax``, band-limited to at most ``kmax`` wavelengths per patch side)."""
    rng = np.random.default_rng(seed)
    qx = np.fft.fftfreq(n)[:, None]
    qy = np.fft.rfftfreq(n)[None, :]
    q = np.hypot(qx, qy)
    amp = np.where(q > 0, np.where(q > 0, q, 1.0) ** (-(1 + hurst)), 0.0)
    if kmax is not None:
        amp[q * n > kmax] = 0.0
    spec = amp * (rng.standard_normal(q.shape) + 1j * rng.standard_normal(q.shape))
    h = np.fft.irfft2(spec, s=(n, n))
    return h * (rq / h.std())


def fft_pair_time(shape, workers, repeat=5):
    x = np.random.default_rng(0).random(shape)
    sfft.irfft2(sfft.rfft2(x, workers=workers), s=shape, workers=workers)
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        sfft.irfft2(sfft.rfft2(x, workers=workers), s=shape, workers=workers)
        best = min(best, time.perf_counter() - t0)
    return best


def run_ours(h, p_mean, capped, tol, workers, precondition=True):
    n = h.shape[0]
    t0 = time.perf_counter()
    op = normal_operator(h.shape, L / n, E_STAR, periodic=True, workers=workers)
    t1 = time.perf_counter()
    r = solve_normal(
        h,
        L / n,
        E_STAR,
        p_mean,
        H=H if capped else None,
        tol=tol,
        operator=op,
        precondition=precondition,
    )
    t2 = time.perf_counter()
    return dict(
        p=r.pressure, alpha=r.alpha, nit=r.nit, wall=t2 - t0, solve=t2 - t1, converged=r.converged
    )


@contextlib.contextmanager
def capture_output():
    """Capture Python- and C-level stdout and stderr (Tamaas logs its iterations there)."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    buf = io.StringIO()
    with tempfile.TemporaryFile(mode="w+") as f:
        os.dup2(f.fileno(), 1)
        os.dup2(f.fileno(), 2)
        out = {"text": ""}
        try:
            with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
                yield out
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])
            f.seek(0)
            out["text"] = f.read() + buf.getvalue()


def run_tamaas(h, p_mean, capped, tol):
    import tamaas as tm

    n = h.shape[0]
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [L, L], [n, n])
    model.E = E_STAR  # nu = 0: Tamaas' E_star = E / (1 - nu^2) equals ours
    model.nu = 0.0
    with capture_output() as out:
        if capped:
            solver = tm.KatoSaturated(model, h.copy(), tol, H)
        else:
            solver = tm.PolonskyKeerRey(model, h.copy(), tol)
        solver.setDumpFrequency(1)
        solver.setMaxIterations(100000)
        t0 = time.perf_counter()
        err = solver.solve(p_mean)
        wall = time.perf_counter() - t0
    its = [int(m) for m in re.findall(r"^\s*(\d+)\s+\S+\s+\S+\s*$", out["text"], re.M)]
    p = np.array(model.traction).reshape(n, n)
    return dict(
        p=p,
        alpha=float(np.mean(p > 0)),
        nit=max(its) if its else -1,
        wall=wall,
        converged=bool(err < tol),
    )


def run_cm(h, p_mean, capped, pentol_rel):
    from ContactMechanics import PeriodicFFTElasticHalfSpace
    from ContactMechanics.Optimization import constrained_conjugate_gradients

    n = h.shape[0]
    dx = L / n
    sub = PeriodicFFTElasticHalfSpace((n, n), E_STAR, physical_sizes=(L, L))
    t0 = time.perf_counter()
    res = constrained_conjugate_gradients(
        sub,
        h,
        hardness=H * dx * dx if capped else None,
        external_force=p_mean * L * L,
        pentol=pentol_rel * h.std(),
        maxiter=100000,
    )
    wall = time.perf_counter() - t0
    p = np.asarray(res.jac) / (dx * dx)
    return dict(
        p=p, alpha=float(np.mean(p > 0)), nit=int(res.nit), wall=wall, converged=bool(res.success)
    )


def available(mod):
    try:
        __import__(mod)
        return True
    except Exception as exc:  # pragma: no cover - depends on the environment
        print(f"peer {mod} unavailable: {exc!r}")
        return False


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 512])
    ap.add_argument(
        "--ours-only",
        type=int,
        nargs="*",
        default=[],
        help="extra sizes run with our solver only (e.g. 2048)",
    )
    ap.add_argument("--loads", type=float, nargs="+", default=[300e6])
    ap.add_argument("--tol", type=float, default=1e-8, help="our tolerance")
    ap.add_argument("--tamaas-tol", type=float, default=1e-10)
    ap.add_argument("--cm-pentol", type=float, default=1e-6, help="CM pentol / Rq")
    ap.add_argument(
        "--tamaas-capped-max",
        type=int,
        default=0,
        help="largest grid for Tamaas KatoSaturated (0: skip; >200 s at 128^2)",
    )
    ap.add_argument("--workers", type=int, default=1, help="threads for our FFTs")
    ap.add_argument(
        "--no-precondition",
        action="store_true",
        help="run ours as the plain Polonsky-Keer iteration",
    )
    ap.add_argument(
        "--cases",
        nargs="+",
        default=["el", "H"],
        choices=["el", "H"],
        help="elastic (el) and/or capped at H = 800 MPa (H)",
    )
    ap.add_argument(
        "--peers",
        nargs="*",
        default=["tamaas", "contactmechanics"],
        help="peers to run (default both)",
    )
    ap.add_argument("--out", default="normal_peers")
    args = ap.parse_args(argv)

    peers = {
        name: available({"tamaas": "tamaas", "contactmechanics": "ContactMechanics"}[name])
        for name in args.peers
    }
    solve_normal(self_affine(32), L / 32, E_STAR, 1e8, H=H)  # load the numba kernels
    rows = []
    for n in list(args.sizes) + list(args.ours_only):
        h = self_affine(n)
        pair = fft_pair_time((n, n), args.workers)
        for p_mean in args.loads:
            for capped in [c == "H" for c in args.cases]:
                ours = run_ours(h, p_mean, capped, args.tol, args.workers, not args.no_precondition)
                row = dict(
                    n=n,
                    p_mean_MPa=p_mean / 1e6,
                    capped=capped,
                    fft_pair_s=pair,
                    ours_alpha=ours["alpha"],
                    ours_nit=ours["nit"],
                    ours_wall_s=ours["wall"],
                    ours_converged=ours["converged"],
                    ours_iter_over_fft_pair=ours["solve"] / max(ours["nit"], 1) / pair,
                )
                if n in args.sizes:
                    for name, ok in peers.items():
                        if not ok:
                            continue
                        if name == "tamaas" and capped and n > args.tamaas_capped_max:
                            continue
                        r = (
                            run_tamaas(h, p_mean, capped, args.tamaas_tol)
                            if name == "tamaas"
                            else run_cm(h, p_mean, capped, args.cm_pentol)
                        )
                        row[f"{name}_alpha"] = r["alpha"]
                        row[f"{name}_dalpha"] = abs(r["alpha"] - ours["alpha"])
                        row[f"{name}_L2"] = float(
                            np.linalg.norm(r["p"] - ours["p"]) / np.linalg.norm(ours["p"])
                        )
                        row[f"{name}_nit"] = r["nit"]
                        row[f"{name}_wall_s"] = r["wall"]
                        row[f"{name}_converged"] = r["converged"]
                        row[f"ours_over_{name}"] = ours["wall"] / r["wall"]
                rows.append(row)
                print(
                    json.dumps(
                        {k: (round(v, 6) if isinstance(v, float) else v) for k, v in row.items()}
                    ),
                    flush=True,
                )

    RESULTS.mkdir(exist_ok=True)
    meta = dict(
        platform=platform.platform(),
        cpus=os.cpu_count(),
        args=vars(args),
        numpy=np.__version__,
        date=time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()),
    )
    (RESULTS / f"{args.out}.json").write_text(json.dumps(dict(meta=meta, rows=rows), indent=1))
    table = format_table(rows)
    (RESULTS / f"{args.out}.md").write_text(table + "\n")
    print(table)
    bad = [
        r
        for r in rows
        for k in ("tamaas_dalpha", "contactmechanics_dalpha")
        if r.get(k, 0.0) > 1e-3
    ]
    if bad:
        print("WARNING: alpha disagreement > 1e-3 in", len(bad), "rows")


def format_table(rows):
    head = (
        "| N | p_mean MPa | capped | alpha ours | nit ours | t ours s | iter/FFT-pair "
        "| alpha TM | nit TM | t TM s | L2 TM | ours/TM "
        "| alpha CM | nit CM | t CM s | L2 CM | ours/CM |"
    )
    sep = "|" + "---|" * 17
    lines = [head, sep]

    def f(r, k, fmt):
        return format(r[k], fmt) if k in r else "-"

    for r in rows:
        lines.append(
            f"| {r['n']} | {r['p_mean_MPa']:.0f} | {'H' if r['capped'] else 'el'} "
            f"| {r['ours_alpha']:.4f} | {r['ours_nit']} | {r['ours_wall_s']:.2f} "
            f"| {r['ours_iter_over_fft_pair']:.2f} "
            f"| {f(r, 'tamaas_alpha', '.4f')} | {f(r, 'tamaas_nit', 'd')} "
            f"| {f(r, 'tamaas_wall_s', '.2f')} | {f(r, 'tamaas_L2', '.1e')} "
            f"| {f(r, 'ours_over_tamaas', '.2f')} "
            f"| {f(r, 'contactmechanics_alpha', '.4f')} | {f(r, 'contactmechanics_nit', 'd')} "
            f"| {f(r, 'contactmechanics_wall_s', '.2f')} | {f(r, 'contactmechanics_L2', '.1e')} "
            f"| {f(r, 'ours_over_contactmechanics', '.2f')} |"
        )
    return "\n".join(lines)


if __name__ == "__main__":
    with run_record(__file__):
        main()
