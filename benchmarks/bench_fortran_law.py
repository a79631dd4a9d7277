"""Per-node cost of the generated Fortran law vs a plain Coulomb routine vs frictionlaw's numba.

One run, one process, one machine: the host-neutral entry ``SBMF_FRICTION`` (what every
generated target calls per contact point; gfortran -O2) on the loading branch (Eq. 24), the
reloading branch (Eq. 25) and a mix of both (``--reload-fraction`` of the nodes reloading, the
rest loading, in random order), with and without the ``alpha1(p_hist)`` cache in the second
state variable, against a Coulomb routine with the same entry, return map and calling loop (the
floor a host pays for any friction law), and against ``frictionlaw.traction_update`` (numba,
serial, with ``out=`` buffers) on the same data. Both reload forms: the paper's Eq. 25 and the
tabulated form (8 levels from 100 to 760 MPa, C2 4.5..84, n2 0.95..0.29, s2 0.7), each compiled
from its own parameter file and timed on the same nodes; ``tab_over_paper`` is the ratio of
their best times, ``tab_over_paper_median`` the median over the rounds of the ratio within a
round (the two timed one after the other, so that a slow phase of the machine hits both).
Both first-loading forms (issue 37): Eq. 24 and the tabulated first loading (11 levels from 10 to
760 MPa, the default sweep's; the contact ratios of the same Eq. 24 there, so that only the
form differs), under either reload form: ``first_over_eq24`` (paper reload) and
``first_over_eq24_tab`` (tabulated reload) are the medians over the rounds of the ratio within
a round, each form with the committed cache its own routine writes for ``p_hist``.
2 tangential directions; best of several rounds, the variants timed in turn in every round, in
CPU time of the calling thread (``time.thread_time``: the routines run in that thread; on the
shared 2-core machine the wall clock also counts the time the thread waits for a core, which
inflated every figure by up to 4x).

The guards' cost (docs/fe_codes.md, "Guards"): the shipped routines (guards in) against the same
routines rendered without them (``frictionlaw.export._render.texts(job, guards=False)``, never
shipped), timed in turn in the same rounds: the host-neutral ``SBMF_FRICTION`` (paper form) and
Abaqus' ``FRIC`` (its shim calls it per point as Abaqus does). The parameter file records its
calibrated range (up to 760 MPa), so the loading nodes above it take the range check's slow
path (the once-per-process flag read) at every call. ``guard_cost_*`` is the median over the
rounds of guarded / unguarded - 1.

The cost of choosing a zone's law (issue 42): ``FRIC`` and the host-neutral ``SBMF_FRICTION_V``
exported with four zones of equal name length (``ZONE1`` .. ``ZONE4``, each the paper form's law,
so that only the choosing differs), called with ``zone4`` (the last compared: the worst of the
four) and ``STATEV(4)``/``STATE(4)`` holding the zone (the cache is read), against the one-law
routine of the same law in the same rounds: ``zoned_over_one_fric``, ``zoned_over_one_v``, the
medians over the rounds of the ratio within a round.

Run: python benchmarks/bench_fortran_law.py [--nodes 200000] [--repeat 5] [--reload-fraction 0.5]
[--out benchmarks/results/fortran_law.csv]. Writes the CSV and prints a table.
"""

import argparse
import csv
import dataclasses
import tempfile
import time
from pathlib import Path

import numpy as np
from _provenance import run_record

import frictionlaw as fl
from frictionlaw import export as exp
from frictionlaw.export import harness
from frictionlaw.export._render import plan, texts
from frictionlaw.first_loading import FirstLoadingTable
from frictionlaw.reload_form import ReloadTable

H = 800e6
PARAMS = fl.FrictionParams(
    m=0.5,
    sigma_y=285714285.71428573,
    H=H,
    C1=1.0466452593966644,
    n1=2.8674798599724576,
    C2=7.443848731746356,
    n2=0.5753816933748891,
    p_range=(10e6, 760e6),  # the loading nodes run to 1.2 H: a third are beyond p_max
)
#: the tabulated reload form: the shape of the default scene's reload curves (issue 31)
TABULATED = dataclasses.replace(
    PARAMS,
    reload_form="tabulated",
    reload_table=ReloadTable(
        p_hist=(100e6, 200e6, 300e6, 400e6, 500e6, 600e6, 700e6, 760e6),
        C2=(4.5, 4.8, 5.1, 5.6, 7.0, 10.0, 20.8, 83.6),
        n2=(0.95, 0.84, 0.75, 0.71, 0.61, 0.51, 0.40, 0.29),
        s2=0.7,
    ),
)
#: the tabulated first loading: Eq. 24 of PARAMS at the default sweep's levels (issue 37)
_LEVELS = (10e6, 25e6, 50e6, 100e6, 200e6, 300e6, 400e6, 500e6, 600e6, 700e6, 760e6)
FIRST = {
    name: dataclasses.replace(
        law,
        first_loading_form="tabulated",
        first_loading_table=FirstLoadingTable(
            p=_LEVELS, alpha=tuple(fl.alpha_first(np.array(_LEVELS), PARAMS))
        ),
    )
    for name, law in (("first", PARAMS), ("first_tab", TABULATED))
}
KT = 1e13


def interleaved(calls, repeat):
    """``{name: CPU time of each round}``, the variants timed in turn in every round (so that a
    slow phase of the shared machine hits all of them, not one)."""
    for fn in calls.values():
        fn()
    rounds = {k: [] for k in calls}
    for _ in range(repeat):
        for k, fn in calls.items():
            t0 = time.thread_time()
            fn()
            rounds[k].append(time.thread_time() - t0)
    return {k: np.asarray(v) for k, v in rounds.items()}


def median_ratio(rounds, num, den):
    """The median over the rounds of ``num / den`` timed in the same round."""
    return float(np.median(rounds[num] / rounds[den]))


def libraries(workdir):
    """The host-neutral ``SBMF_FRICTION`` of each reload form, the Coulomb floor, and the
    guards' pairs: ``SBMF_FRICTION`` and ``FRIC`` of the paper form with and without guards."""
    entry = exp.target("lsdyna").harness  # the host-neutral SBMF_FRICTION
    libs = {}
    forms = (("paper", PARAMS), ("tab", TABULATED), *FIRST.items())
    for name, params in forms:
        params.to_json(workdir / f"params_{name}.json")
        files, _ = exp.render("lsdyna", workdir / f"params_{name}.json")
        libs[name], _ = entry.load(files, workdir / name, name=f"sbmf_{name}")
    coulomb = {"coulomb.f": harness.coulomb_source(PARAMS)}
    libs["coulomb"], _ = entry.load(coulomb, workdir / "coul", name="coul")
    for target, key in (("lsdyna", "paper_noguard"), ("abaqus-fric", "fric_noguard")):
        job = plan(target, workdir / "params_paper.json")
        record = exp.target(target)
        files = texts(job, guards=False)
        assert ".GT. SBMFPU" not in files[record.file]  # no guard in it
        libs[key], _ = record.harness.load(files, workdir / key, name=key)
    files, _ = exp.render("abaqus-fric", workdir / "params_paper.json")
    libs["fric"], _ = exp.target("abaqus-fric").harness.load(files, workdir / "fric", name="fric")
    zones = [(f"ZONE{i}", workdir / "params_paper.json") for i in range(1, 5)]
    for target, key in (("abaqus-fric", "fric_zoned"), ("lsdyna", "v_zoned")):
        files, _ = exp.render(target, None, zones=zones)
        libs[key], _ = exp.target(target).harness.load(files, workdir / key, name=key)
    return libs


def cases(n, rng, reload_fraction):
    """``{branch: (p, p_hist)}``: first loading (``p_hist`` 0 or below ``p``), reloading
    (``p_hist`` 0.05 .. 1.2 H across the table's levels, ``p`` 5-95 % of it), and the mix."""
    du = rng.normal(size=(n, 2)) * 1e-6
    t_old = rng.normal(size=(n, 2)) * 3e7
    p_load = rng.uniform(0.05, 1.2, n) * H
    p_hist_load = np.where(rng.random(n) < 0.5, 0.0, p_load * rng.uniform(0.3, 1.0, n))
    p_hist_rel = rng.uniform(0.05, 1.2, n) * H
    p_rel = p_hist_rel * rng.uniform(0.05, 0.95, n)
    mix = rng.random(n) < reload_fraction
    return (
        {
            "loading": (p_load, p_hist_load),
            "reloading": (p_rel, p_hist_rel),
            "mix": (np.where(mix, p_rel, p_load), np.where(mix, p_hist_rel, p_hist_load)),
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
    ap.add_argument(
        "--reload-fraction", type=float, default=0.5, help="share of reloading nodes in the mix"
    )
    ap.add_argument(
        "--out",
        type=Path,
        default=Path(__file__).parent / "results" / "fortran_law.csv",
        help="CSV file written (default benchmarks/results/fortran_law.csv)",
    )
    args = ap.parse_args(argv)
    n, reps = args.nodes, args.reps
    rng = np.random.default_rng(0)
    law = fl.SBMFLaw(PARAMS)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        libs = libraries(Path(tmp))
        data, du, t_old = cases(n, rng, args.reload_fraction)
        p0, h0 = data["loading"]
        neutral = ("paper", "tab", "first", "first_tab", "coulomb", "paper_noguard")
        bufs = {k: libs[k](p0, h0, -np.ones(n), du, t_old, KT) for k in neutral}
        chr_ = np.full(n, 1e-3)
        sv0 = np.zeros((n, 3))
        for k in ("fric", "fric_noguard"):
            bufs[k] = libs[k](p0, du, t_old, sv0, chr_)
        bufs["fric_zoned"] = libs["fric_zoned"](
            p0, du, t_old, np.zeros((n, 4)), chr_, ciname="zone4"
        )
        ref = fl.traction_update(law, p0, du, t_old, KT, fl.HistoryState(n))
        for branch, (p, ph) in data.items():
            state = fl.HistoryState(n, ph)
            # the committed cache a host holds for p_hist (Eq. 24's, the same in both reload
            # forms; the tabulated first loading's its own)
            g1 = cache_of(libs["paper"], ph, n)
            g1f = cache_of(libs["first"], ph, n)
            calls = {
                "fortran_coulomb": lambda p=p, ph=ph: libs["coulomb"](
                    p, ph, -np.ones(n), du, t_old, KT, reps=reps, out=bufs["coulomb"]
                ),
            }
            for form, col, g1c in (
                ("paper", "fortran_sbmf", g1),
                ("tab", "fortran_sbmf_tab", g1),
                ("first", "fortran_first", g1f),
                ("first_tab", "fortran_first_tab", g1f),
            ):
                calls[col] = lambda g=g1c, p=p, ph=ph, f=form: libs[f](
                    p, ph, g, du, t_old, KT, reps=reps, out=bufs[f]
                )
                if branch != "loading":
                    calls[col + "_nocache"] = lambda p=p, ph=ph, f=form: libs[f](
                        p, ph, -np.ones(n), du, t_old, KT, reps=reps, out=bufs[f]
                    )

            # the guards' cost: the same routine with and without them, in the same rounds
            calls["fortran_sbmf_noguard"] = lambda g=g1, p=p, ph=ph: libs["paper_noguard"](
                p, ph, g, du, t_old, KT, reps=reps, out=bufs["paper_noguard"]
            )
            sv = np.stack([ph, g1, np.zeros(n)], 1)
            for key in ("fric", "fric_noguard"):
                calls[f"fortran_{key}"] = lambda p=p, sv=sv, k=key: libs[k](
                    p, du, t_old, sv, chr_, reps=reps, out=bufs[k]
                )

            # the cost of choosing a zone: four zones, the last one's name, its cache in use
            sv4 = np.stack([ph, g1, np.zeros(n), np.full(n, 4.0)], 1)
            calls["fortran_fric_zoned"] = lambda p=p, sv=sv4: libs["fric_zoned"](
                p, du, t_old, sv, chr_, reps=reps, out=bufs["fric_zoned"], ciname="zone4"
            )
            st5 = np.stack([ph, g1, np.zeros(n), np.full(n, 4.0), np.zeros(n)], 1)
            one5 = np.stack([ph, g1, np.zeros(n), np.ones(n), np.zeros(n)], 1)
            calls["fortran_v"] = lambda p=p, st=one5: libs["paper"].friction(
                "zone4", p, st.copy(), du, t_old, KT, reps=reps
            )
            calls["fortran_v_zoned"] = lambda p=p, st=st5: libs["v_zoned"].friction(
                "zone4", p, st.copy(), du, t_old, KT, reps=reps
            )

            def numba_run(p=p, state=state):
                for _ in range(reps):
                    fl.traction_update(law, p, du, t_old, KT, state, parallel=False, out=ref)

            calls["numba_serial"] = numba_run
            rounds = interleaved(calls, args.repeat)
            times = {k: v.min() / (n * reps) for k, v in rounds.items()}
            row = {"branch": branch, "nodes": n}
            row.update({k: v * 1e9 for k, v in times.items()})
            row["sbmf_over_coulomb"] = times["fortran_sbmf"] / times["fortran_coulomb"]
            row["tab_over_paper"] = times["fortran_sbmf_tab"] / times["fortran_sbmf"]
            row["tab_over_paper_median"] = median_ratio(rounds, "fortran_sbmf_tab", "fortran_sbmf")
            row["first_over_eq24"] = median_ratio(rounds, "fortran_first", "fortran_sbmf")
            row["first_over_eq24_tab"] = median_ratio(
                rounds, "fortran_first_tab", "fortran_sbmf_tab"
            )
            row["numba_over_fortran"] = times["numba_serial"] / times["fortran_sbmf"]
            row["guard_cost_sbmf"] = (
                median_ratio(rounds, "fortran_sbmf", "fortran_sbmf_noguard") - 1.0
            )
            row["guard_cost_fric"] = (
                median_ratio(rounds, "fortran_fric", "fortran_fric_noguard") - 1
            )
            row["beyond_p_max"] = float(np.mean(p > PARAMS.p_range[1]))
            row["zoned_over_one_fric"] = median_ratio(rounds, "fortran_fric_zoned", "fortran_fric")
            row["zoned_over_one_v"] = median_ratio(rounds, "fortran_v_zoned", "fortran_v")
            if "fortran_sbmf_nocache" in times:
                row["tab_over_paper_nocache"] = (
                    times["fortran_sbmf_tab_nocache"] / times["fortran_sbmf_nocache"]
                )
                row["cache_gain"] = times["fortran_sbmf_nocache"] / times["fortran_sbmf"]
                row["first_over_eq24_nocache"] = median_ratio(
                    rounds, "fortran_first_nocache", "fortran_sbmf_nocache"
                )
            rows.append(row)
    cols = [
        "branch",
        "nodes",
        "fortran_coulomb",
        "fortran_sbmf",
        "fortran_sbmf_nocache",
        "fortran_sbmf_tab",
        "fortran_sbmf_tab_nocache",
        "numba_serial",
        "sbmf_over_coulomb",
        "tab_over_paper",
        "tab_over_paper_median",
        "tab_over_paper_nocache",
        "fortran_first",
        "fortran_first_nocache",
        "fortran_first_tab",
        "first_over_eq24",
        "first_over_eq24_tab",
        "first_over_eq24_nocache",
        "numba_over_fortran",
        "cache_gain",
        "fortran_sbmf_noguard",
        "fortran_fric",
        "fortran_fric_noguard",
        "guard_cost_sbmf",
        "guard_cost_fric",
        "beyond_p_max",
        "fortran_fric_zoned",
        "zoned_over_one_fric",
        "fortran_v",
        "fortran_v_zoned",
        "zoned_over_one_v",
    ]
    out = args.out
    out.parent.mkdir(parents=True, exist_ok=True)
    with open(out, "w", newline="") as fh:
        w = csv.DictWriter(fh, cols)
        w.writeheader()
        for r in rows:
            w.writerow(
                {c: (f"{r[c]:.4g}" if isinstance(r.get(c), float) else r.get(c, "")) for c in cols}
            )
    print(
        f"ns per node (2 directions); ratios are time ratios; mix: {args.reload_fraction:g} reloading"
    )
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for r in rows:
        cells = [f"{r[c]:.3g}" if isinstance(r.get(c), float) else str(r.get(c, "")) for c in cols]
        print("| " + " | ".join(cells) + " |")
    print(f"wrote {out}")


if __name__ == "__main__":
    with run_record(__file__):
        main()
