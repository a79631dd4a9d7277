"""Per-node cost of the generated Fortran law vs a plain Coulomb routine vs frictionlaw's numba.

One run, one process, one machine: the host-neutral entry ``SBMF_FRICTION`` (what every
generated target calls per contact point; gfortran -O2) on the loading branch (Eq. 24) and the
reloading branch (Eq. 25) with and without the ``alpha1(p_hist)`` cache in the second state
variable, against a Coulomb routine with the same entry, return map and calling loop (the floor a
host pays for any friction law), and against ``frictionlaw.traction_update`` (numba, serial, with
``out=`` buffers) on the same data. 2 tangential directions; best of several rounds, the
variants timed in turn in every round, in CPU time of the calling thread (``time.thread_time``:
the routines run in that thread; on the shared 2-core machine the wall clock also counts the
time the thread waits for a core, which inflated every figure by up to 4x).

Run: python benchmarks/bench_fortran_law.py [--nodes 200000] [--repeat 5]
Writes benchmarks/results/fortran_law.csv and prints a table.
"""

import argparse
import csv
import tempfile
import time
from pathlib import Path

import numpy as np

import frictionlaw as fl
from frictionlaw import export as exp
from frictionlaw.export import harness

H = 800e6
PARAMS = fl.FrictionParams(
    m=0.5,
    sigma_y=285714285.71428573,
    H=H,
    C1=1.0466452593966644,
    n1=2.8674798599724576,
    C2=7.443848731746356,
    n2=0.5753816933748891,
)
KT = 1e13


def interleaved(calls, repeat):
    """``{name: best CPU time}``, the variants timed in turn in every round (so that a slow
    phase of the shared machine hits all of them, not one)."""
    for fn in calls.values():
        fn()
    best_t = {k: float("inf") for k in calls}
    for _ in range(repeat):
        for k, fn in calls.items():
            t0 = time.thread_time()
            fn()
            best_t[k] = min(best_t[k], time.thread_time() - t0)
    return best_t


def libraries(workdir, params_path):
    files, _ = exp.render("lsdyna", params_path)
    entry = exp.target("lsdyna").harness  # the host-neutral SBMF_FRICTION
    sbmf, _ = entry.load(files, workdir / "sbmf", name="sbmf")
    coulomb = {"coulomb.f": harness.coulomb_source(PARAMS)}
    coul, _ = entry.load(coulomb, workdir / "coul", name="coul")
    return sbmf, coul


def cases(n, rng):
    du = rng.normal(size=(n, 2)) * 1e-6
    t_old = rng.normal(size=(n, 2)) * 3e7
    p_load = rng.uniform(0.05, 1.2, n) * H
    p_hist_rel = rng.uniform(0.3, 1.2, n) * H
    p_rel = p_hist_rel * rng.uniform(0.05, 0.95, n)
    return (
        {
            "loading": (p_load, np.zeros(n)),
            "reloading": (p_rel, p_hist_rel),
        },
        du,
        t_old,
    )


def cache_of(host, p_hist, n):
    """The committed cache value the host would hold for ``p_hist`` (one loading call)."""
    out = host(p_hist, np.zeros(n), -np.ones(n), np.zeros((n, 2)), np.zeros((n, 2)), KT)
    return out["g1h"].copy()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", type=int, default=200_000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--reps", type=int, default=5, help="sweeps over the nodes per timed call")
    args = ap.parse_args(argv)
    n, reps = args.nodes, args.reps
    rng = np.random.default_rng(0)
    law = fl.SBMFLaw(PARAMS)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        PARAMS.to_json(tmp / "params.json")
        sbmf, coul = libraries(tmp, tmp / "params.json")
        data, du, t_old = cases(n, rng)
        buf = sbmf(data["loading"][0], data["loading"][1], -np.ones(n), du, t_old, KT)
        cbuf = coul(data["loading"][0], data["loading"][1], -np.ones(n), du, t_old, KT)
        ref = fl.traction_update(law, data["loading"][0], du, t_old, KT, fl.HistoryState(n))
        for branch, (p, ph) in data.items():
            state = fl.HistoryState(n, ph)
            g1 = cache_of(sbmf, ph, n) if branch == "reloading" else np.zeros(n)
            calls = {
                "fortran_sbmf": lambda g=g1, p=p, ph=ph: sbmf(
                    p, ph, g, du, t_old, KT, reps=reps, out=buf
                ),
                "fortran_coulomb": lambda p=p, ph=ph: coul(
                    p, ph, -np.ones(n), du, t_old, KT, reps=reps, out=cbuf
                ),
            }
            if branch == "reloading":
                calls["fortran_sbmf_nocache"] = lambda p=p, ph=ph: sbmf(
                    p, ph, -np.ones(n), du, t_old, KT, reps=reps, out=buf
                )

            def numba_run(p=p, state=state):
                for _ in range(reps):
                    fl.traction_update(law, p, du, t_old, KT, state, parallel=False, out=ref)

            calls["numba_serial"] = numba_run
            times = interleaved(calls, args.repeat)
            times = {k: v / (n * reps) for k, v in times.items()}
            row = {"branch": branch, "nodes": n}
            row.update({k: v * 1e9 for k, v in times.items()})
            row["sbmf_over_coulomb"] = times["fortran_sbmf"] / times["fortran_coulomb"]
            row["numba_over_fortran"] = times["numba_serial"] / times["fortran_sbmf"]
            if "fortran_sbmf_nocache" in times:
                row["cache_gain"] = times["fortran_sbmf_nocache"] / times["fortran_sbmf"]
            rows.append(row)
    cols = [
        "branch",
        "nodes",
        "fortran_coulomb",
        "fortran_sbmf",
        "fortran_sbmf_nocache",
        "numba_serial",
        "sbmf_over_coulomb",
        "numba_over_fortran",
        "cache_gain",
    ]
    out = Path(__file__).parent / "results" / "fortran_law.csv"
    out.parent.mkdir(exist_ok=True)
    with open(out, "w", newline="") as fh:
        w = csv.DictWriter(fh, cols)
        w.writeheader()
        for r in rows:
            w.writerow(
                {c: (f"{r[c]:.4g}" if isinstance(r.get(c), float) else r.get(c, "")) for c in cols}
            )
    print("ns per node (2 directions); ratios are time ratios")
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for r in rows:
        cells = [f"{r[c]:.3g}" if isinstance(r.get(c), float) else str(r.get(c, "")) for c in cols]
        print("| " + " | ".join(cells) + " |")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
