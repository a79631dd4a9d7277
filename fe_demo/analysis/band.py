"""The law's band carried to the FE result: ``fe-demo ... --band`` and ``--samples``.

A parameter file from a multi-sample calibration holds an ``uncertainty`` block
(:mod:`frictionlaw.uncertainty`). ``--band`` runs the scene three times, with the pooled
(central) law and the band's two edge laws; ``--samples`` runs it with the central law and every
sample's own law. Each run writes its usual files into a subfolder (``central/``,
``lower/``, ``upper/`` or ``sample_<name>/``); the top folder gets

* ``history.csv``: per increment of the central run, the height reduction, the central force
  and the band ``force_lower_N`` / ``force_upper_N`` (the least and greatest force of all runs
  at that reduction, linearly interpolated onto the central run's reductions); for the ring also
  the inner-diameter change and its band;
* ``force_band.png`` (and ``ring_band.png``): the curves with the band shaded;
* ``summary.json``: the runs, and ``force_at`` each reported reduction (25 %, 50 % where
  reached, and the end): ``central``, ``lower``, ``upper`` and ``plus_minus`` (half the band
  width), so that "the force at 50 % is F +- dF from surface variability alone" is one line;
* ``report.html``: the same record and plots in one self-contained page.

With ``--band`` the force band is the FE image of the law's confidence band (where the
population's law lies, at the calibration's level); with ``--samples`` it is the spread of the
single samples' laws (what one further patch could give), which is wider.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sbmf_cli import ParameterError

__all__ = [
    "BandResult",
    "REPORT_REDUCTIONS",
    "band_laws",
    "band_result",
    "combine",
    "summary_record",
]

#: height reductions at which summary.json reports the force band (where the runs reach them)
REPORT_REDUCTIONS = (0.25, 0.5)


def band_laws(P, mode, params_path):
    """``[(name, FrictionParams)]``: central first, then the edge laws or every sample's law.

    ``P`` is the parameter set read from ``params_path`` (named in the message). ``ValueError``
    (bad input) if it has no uncertainty block.
    """
    if P.uncertainty is None:
        raise ParameterError(
            f"{{{mode}}} needs a parameter file with an uncertainty block (a calibration from "
            "several samples: halfspace-calib with several workpiece files or patches, "
            f"docs/uncertainty.md); {params_path} has none",
            mode,
        )
    central = P.replace(uncertainty=None)
    if mode == "band":
        edges = P.edge_laws()
        return [("central", central), ("lower", edges["lower"]), ("upper", edges["upper"])]
    return [("central", central)] + [
        (f"sample_{_safe(n)}", law) for n, law in P.sample_laws().items()
    ]


def _safe(name):
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name)


def combine(histories, keys=("force",)):
    """Band of history columns over runs, on the central run's increments.

    ``histories``: ``{name: history}`` with ``"central"`` among them. Each other run is
    interpolated linearly in the height reduction onto the central run's, stage by stage (the
    multistage scene unloads and reloads: within a stage the reduction is monotone). Returns
    ``{"height_reduction": r, "stage": s, key: central, f"{key}_lower": min, f"{key}_upper":
    max}``. Where a run did not reach (it stopped early), it does not bound the band.
    """
    c = histories["central"]
    r = np.asarray(c["height_reduction"], dtype=float)
    st = np.asarray(c.get("stage", np.zeros(r.size)), dtype=float)
    out = {"height_reduction": r, "stage": st}
    for key in keys:
        vals = [np.asarray(c[key], dtype=float)]
        for name, h in histories.items():
            if name == "central" or not h:
                continue
            hr = np.asarray(h["height_reduction"], dtype=float)
            hs = np.asarray(h.get("stage", np.zeros(hr.size)), dtype=float)
            v = np.asarray(h[key], dtype=float)
            got = vals[0].copy()
            for stage in np.unique(st):
                mine, theirs = st == stage, hs == stage
                if not theirs.any():
                    continue
                order = np.argsort(hr[theirs], kind="stable")
                x, y = hr[theirs][order], v[theirs][order]
                inside = (r[mine] >= x[0]) & (r[mine] <= x[-1])
                got[np.flatnonzero(mine)[inside]] = np.interp(r[mine][inside], x, y)
            vals.append(got)
        stack = np.vstack(vals)
        out[key] = vals[0]
        out[f"{key}_lower"] = stack.min(axis=0)
        out[f"{key}_upper"] = stack.max(axis=0)
    return out


def _at(band, key, red):
    """``central, lower, upper, plus_minus`` of ``key`` where the reduction first reaches ``red``."""
    r = band["height_reduction"]
    hit = np.flatnonzero(r >= red - 1e-12)
    if hit.size == 0:
        return None
    i = int(hit[0])
    if i == 0 or r[i] == r[i - 1]:
        vals = [float(band[k][i]) for k in (key, f"{key}_lower", f"{key}_upper")]
    else:
        t = (red - r[i - 1]) / (r[i] - r[i - 1])
        vals = [
            float((1 - t) * band[k][i - 1] + t * band[k][i])
            for k in (key, f"{key}_lower", f"{key}_upper")
        ]
    return {
        "central": vals[0],
        "lower": vals[1],
        "upper": vals[2],
        "plus_minus": 0.5 * (vals[2] - vals[1]),
    }


def summary_record(scene, mode, level, runs, band, keys):
    """The ``summary.json`` record of a band run (also what report.html shows)."""
    r = band["height_reduction"]
    reds = [x for x in REPORT_REDUCTIONS if x <= r.max()]
    rec = {
        "scene": scene,
        "mode": mode,
        "level": level,
        "meaning": "confidence band of the population's law (edge laws)"
        if mode == "band"
        else "spread of the single samples' laws",
        "runs": runs,
        "ok": all(v["converged"] for v in runs.values()),
    }
    for key, unit in keys:
        rec[f"{key}_at"] = {f"{100 * x:g} %": {**_at(band, key, x), "unit": unit} for x in reds}
        if reds and abs(reds[-1] - r[-1]) < 1e-9:
            continue  # the run ends at the last reported reduction
        end = {k: float(band[k][-1]) for k in (key, f"{key}_lower", f"{key}_upper")}
        rec[f"{key}_at"][f"end ({100 * r[-1]:.4g} %)"] = {
            "central": end[key],
            "lower": end[f"{key}_lower"],
            "upper": end[f"{key}_upper"],
            "plus_minus": 0.5 * (end[f"{key}_upper"] - end[f"{key}_lower"]),
            "unit": unit,
        }
    return rec


@dataclass(frozen=True)
class BandResult:
    """A band run combined: the band per increment, each run's history, the summary record."""

    band: dict
    histories: dict
    record: dict
    keys: tuple


def band_result(scene, mode, level, results, keys):
    """Combine the runs of a band (``--band``, ``--samples``) into a :class:`BandResult`.

    ``results``: ``{name: (history or None, run summary dict)}``; ``keys``:
    ``[(history column, unit)]`` (``force`` in N; the ring's ``inner_diameter_change`` a fraction).
    ``RuntimeError`` when the central law's run gave no accepted increment.
    """
    hist = {n: h for n, (h, _) in results.items() if h}
    if "central" not in hist:
        raise RuntimeError("the central law's run gave no accepted increment")
    band = combine(hist, [k for k, _ in keys])
    runs = {n: s for n, (_, s) in results.items()}
    return BandResult(band, hist, summary_record(scene, mode, level, runs, band, keys), tuple(keys))
