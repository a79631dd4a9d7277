"""Cost of the flattening under bulk strain in the runtime: the traction update with and without.

The same SBMF law (with a ``flattening`` block), the same nodes (pressures 0.05-0.6 H, half of
them below a history, 2 slip directions, a HistoryState) and the same output buffers, timed in
turn in one run, best of ``--repeat`` rounds, serial and parallel kernels. Cases:

- ``without``: ``traction_update`` without ``d_eps`` (today's law, the baseline);
- ``zero strain``: ``d_eps = 0`` on a virgin surface (the law bit for bit);
- ``flattened, no strain``: ``d_eps = 0`` on surfaces flattened beyond their pressure;
- ``strain, virgin``: ``d_eps = 0.002`` (an FE increment's strain) on a virgin surface;
- ``strain, flattened``: ``d_eps = 0.002`` on flattened surfaces (the steady state of a run);
- ``strain, virgin, hardening``: as ``strain, virgin`` with a hardening modulus of 2 GPa (the
  lattice's rate limited, Eq. F2c, at the lower pressures of the set);
- ``two-state, ...``: the same law and cases with the block's two-state model
  (``limit-analysis``: the tabulated rates integrated in steps of 0.0005 of stretch, the
  tangent carried through the same steps on first loading), its flattened state after 0.005
  of strain;
- ``strain 0.02, virgin`` for both models: an increment ten times larger (the two-state law's
  steps of 0.0005 of stretch grow in number with it; the one-state solve does not).

Ratios are the case's time over the baseline's in the same round, the median over rounds.
Run: python benchmarks/bench_flattening_runtime.py [--nodes 100000] [--repeat 7]
Writes benchmarks/results/flattening_runtime.csv and prints a table.
"""

import argparse
import time
from pathlib import Path

import numba
import numpy as np
from _provenance import run_record, write_rows

import frictionlaw as fl

H = 800e6
P = fl.FrictionParams(
    m=0.7,
    sigma_y=H / 2.8,
    H=H,
    C1=1.05,
    n1=2.87,
    C2=7.44,
    n2=0.575,
    flattening=fl.Flattening(slope=0.05),
)
#: the same law with the two-state model
P2 = P.replace(flattening=fl.Flattening(slope=0.05, model="limit-analysis"))
#: ... with an edge-slope table of 51 contact fractions (as halfspace-calib writes it)
P3 = P.replace(
    flattening=fl.Flattening(
        slope=0.05,
        model="limit-analysis",
        edge_slope=tuple(float(v) for v in 0.03 + 0.04 * np.linspace(0.0, 1.0, 51) ** 1.5),
    )
)


#: the hardening modulus of the hardening case (Pa): 6 p (1 - A) / h below the lattice's rate up
#: to 0.4 H
HARDENING = 2e9


def cases(n, rng):
    p = rng.uniform(0.05, 0.6, n) * H
    ph = np.where(rng.random(n) < 0.5, p * rng.uniform(1.0, 1.5, n), 0.0)
    law, law2, law3 = fl.SBMFLaw(P), fl.SBMFLaw(P2), fl.SBMFLaw(P3)
    # flattened surfaces: the state after 0.005 of strain at the node's pressure (partly
    # flattened: with the lattice's rate 0.05 reaches full contact, where the update returns at once)
    s = fl.HistoryState(p_hist=ph)
    fl.traction_update(law, p, np.ones(n), np.zeros(n), 1e20, s, d_eps=0.005)
    a_flat = s.alpha_f_trial.copy()
    s2 = fl.HistoryState(p_hist=ph)
    fl.traction_update(law2, p, np.ones(n), np.zeros(n), 1e20, s2, d_eps=0.005)
    a2, s_2 = s2.alpha_f_trial.copy(), s2.slope_f_trial.copy()
    print(
        f"flattened state: alpha_f {a_flat.min():.3f}-{a_flat.max():.3f}, "
        f"{np.mean(a_flat >= 1.0):.1%} of the nodes in full contact"
    )
    zero = np.zeros(n)
    inc = np.full(n, 0.002)
    big = np.full(n, 0.02)  # ten times the increment: the two-state law's steps grow with it
    return (
        p,
        ph,
        {
            "without": (None, zero, zero, law),
            "zero strain": (zero, zero, zero, law),
            "flattened, no strain": (zero, a_flat, zero, law),
            "strain, virgin": (inc, zero, zero, law),
            "strain, flattened": (inc, a_flat, zero, law),
            "strain, virgin, hardening": (inc, zero, zero, law),
            "strain 0.02, virgin": (big, zero, zero, law),
            "two-state, flattened, no strain": (zero, a2, s_2, law2),
            "two-state, strain, virgin": (inc, zero, zero, law2),
            "two-state, strain, flattened": (inc, a2, s_2, law2),
            "two-state, strain 0.02, virgin": (big, zero, zero, law2),
            "two-state edges, strain, virgin": (inc, zero, zero, law3),
            "two-state edges, strain 0.02, virgin": (big, zero, zero, law3),
        },
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument(
        "--out", default=str(Path(__file__).parent / "results" / "flattening_runtime.csv")
    )
    args = ap.parse_args(argv)
    rng = np.random.default_rng(0)
    n = args.nodes
    p, ph, runs = cases(n, rng)
    law = fl.SBMFLaw(P)
    du = rng.normal(size=(n, 2)) * 1e-6
    t_old = rng.normal(size=(n, 2)) * 3e7
    kt = np.full(n, 1e13)
    out = fl.traction_update(law, p, du, t_old, kt)
    rows = []
    print(f"threads: numba {numba.get_num_threads()}; {n} nodes, best of {args.repeat}")
    for parallel in (False, True):
        states = {
            k: fl.HistoryState(p_hist=ph, alpha_f=a, slope_f=sl)
            for k, (_, a, sl, _) in runs.items()
        }

        def call(key, parallel=parallel, states=states):
            d_eps, _, _, law = runs[key]
            kw = {"hardening": HARDENING} if key.endswith("hardening") else {}
            t0 = time.perf_counter()
            fl.traction_update(
                law, p, du, t_old, kt, states[key], parallel=parallel, out=out, d_eps=d_eps, **kw
            )
            return time.perf_counter() - t0

        for key in runs:  # warm-up (JIT)
            call(key)
        times = {k: [] for k in runs}
        for _ in range(args.repeat):
            for key in runs:
                times[key].append(call(key))
        base = np.array(times["without"])
        for key, t in times.items():
            t = np.array(t)
            row = {
                "kernels": "parallel" if parallel else "serial",
                "case": key,
                "nodes": n,
                "ns_per_node": 1e9 * t.min() / n,
                "ratio_to_without": float(np.median(t / base)),
            }
            rows.append(row)
            print(
                f"{row['kernels']:8} {key:37} {row['ns_per_node']:9.1f} ns/node "
                f"{row['ratio_to_without']:7.2f}x"
            )
    path = Path(args.out)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_rows(path, rows)
    print(f"wrote {path}")


if __name__ == "__main__":
    with run_record(__file__):
        main()
