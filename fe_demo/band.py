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

import html
import json
from pathlib import Path

import numpy as np

from sbmf_cli import ParameterError
from sbmf_cli.htmlpage import figure, number_cell, page

__all__ = [
    "band_laws",
    "combine",
    "write_band_outputs",
    "write_run_report",
    "REPORT_REDUCTIONS",
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


def write_band_outputs(out, scene, mode, level, results, keys):
    """history.csv, the band plots, summary.json and report.html of a band run.

    ``results``: ``{name: (history or None, run summary dict)}``; ``keys``:
    ``[(history column, unit)]`` (``force`` in N; the ring's ``inner_diameter_change`` in 1).
    Returns the summary record.
    """
    out = Path(out)
    hist = {n: h for n, (h, _) in results.items() if h}
    if "central" not in hist:
        raise RuntimeError("the central law's run gave no accepted increment")
    band = combine(hist, [k for k, _ in keys])
    cols = ["height_reduction", "stage"] + [
        f"{k}{s}" for k, _ in keys for s in ("", "_lower", "_upper")
    ]
    units = {k: u for k, u in keys}
    header = ["height_reduction", "stage"] + [
        f"{k}{s}" + ("" if units[k] == "1" else f"_{units[k]}")
        for k, _ in keys
        for s in ("", "_lower", "_upper")
    ]
    lines = [",".join(header)]
    for i in range(band["height_reduction"].size):
        lines.append(",".join(f"{band[c][i]:.10g}" for c in cols))
    (out / "history.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    images = _plots(out, band, hist, keys, mode, level)
    runs = {n: s for n, (_, s) in results.items()}
    rec = summary_record(scene, mode, level, runs, band, keys)
    (out / "summary.json").write_text(json.dumps(rec, indent=2) + "\n", encoding="utf-8")
    write_report(out, rec, images)
    return rec


def _plots(out, band, hist, keys, mode, level):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    what = f"{100 * level:g} % band of the law" if mode == "band" else "spread of the samples"
    images = []
    for key, _ in keys:
        scale, ylab, fname = (
            (1e-3, "die force (kN)", "force_band.png")
            if key == "force"
            else (100.0, "change of inner diameter (%)", "ring_band.png")
        )
        fig, ax = plt.subplots(figsize=(6, 4))
        r = 100 * band["height_reduction"]
        ax.fill_between(
            r,
            band[f"{key}_lower"] * scale,
            band[f"{key}_upper"] * scale,
            color="C0",
            alpha=0.3,
            lw=0,
            label=what,
        )
        for name, h in hist.items():
            if name != "central" and mode == "samples":
                ax.plot(100 * h["height_reduction"], h[key] * scale, "-", color="0.6", lw=0.6)
        ax.plot(r, band[key] * scale, "C0-", lw=1.5, label="central (pooled) law")
        ax.set(xlabel="height reduction (%)", ylabel=ylab)
        ax.grid(alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(out / fname, dpi=120)
        plt.close(fig)
        images.append((fname, f"{ylab} with the {what}"))
    return images


def write_run_report(folder, info, title):
    """``report.html`` of one ordinary run from its summary.json record ``info``.

    Run status, end of run, the calibrated-range report and the run's plots (force-stroke,
    die profile; the ring chart where the folder has one).
    """
    from .calibrated_range import range_lines

    folder = Path(folder)
    rows = [
        ("converged", info.get("converged")),
        ("stopped_at_height_reduction", info.get("stopped_at_height_reduction")),
        ("wall_time_s", info.get("wall_time_s")),
    ]
    if "inner_diameter_change" in info:  # a ring test's measured quantities, at the end
        rows.insert(2, ("inner_diameter_change", info["inner_diameter_change"]))
        rows.insert(3, ("inner_diameter_min_change", info["inner_diameter_min_change"]))
    body = ["<table><tr><th>quantity</th><th>value</th></tr>"]
    for k, v in rows:
        cell = number_cell(v, k) if isinstance(v, float) else f"<td>{html.escape(str(v))}</td>"
        body.append(f"<tr><td>{k}</td>{cell}</tr>")
    body.append("</table>")
    body.append(f"<p>{html.escape(str(info.get('message', '')))}</p>")
    body.append("<h2>Calibrated range</h2>")
    lines = range_lines(title, info.get("calibrated_range")) or ["law without parameters"]
    body.append("<ul>" + "".join(f"<li>{html.escape(x)}</li>" for x in lines) + "</ul>")
    for fname, cap in (
        ("force_stroke.png", "force against height reduction"),
        ("die_profile.png", "pressure, shear and p_hist along the die"),
        ("../ring_chart.png", "ring chart"),
        ("ring_chart.png", "ring chart"),
    ):
        body.append(figure(folder / fname, cap))
    (folder / "report.html").write_text(page(f"fe-demo: {title}", body), encoding="utf-8")


def write_report(out, rec, images):
    """``report.html`` from the summary record (numbers carry their summary.json path)."""
    out = Path(out)
    body = [
        f"<p>scene {html.escape(rec['scene'])}, {html.escape(rec['meaning'])}"
        + (f" at {100 * rec['level']:g} %" if rec["mode"] == "band" else "")
        + "</p>"
    ]
    for key in [k for k in rec if k.endswith("_at")]:
        body.append(
            f"<h2>{html.escape(key[:-3])} [{html.escape(next(iter(rec[key].values()))['unit'])}]"
            "</h2><table><tr><th>height reduction</th><th>central</th><th>lower</th>"
            "<th>upper</th><th>+-</th></tr>"
        )
        for red, v in rec[key].items():
            body.append(
                f"<tr><td>{html.escape(red)}</td>"
                + "".join(
                    number_cell(v[f], f"{key}.{red}.{f}")
                    for f in ("central", "lower", "upper", "plus_minus")
                )
                + "</tr>"
            )
        body.append("</table>")
    body += [figure(out / fname, cap) for fname, cap in images]
    body.append(
        "<h2>Runs</h2><table><tr><th>run</th><th>converged</th><th>message</th>"
        "<th>calibrated range</th></tr>"
    )
    from .calibrated_range import range_lines

    for name, s in rec["runs"].items():
        rng = "; ".join(range_lines(name, s.get("calibrated_range"))) or "-"
        body.append(
            f"<tr><td>{html.escape(name)}</td><td>{s['converged']}</td>"
            f"<td>{html.escape(str(s.get('message', '')))}</td><td>{html.escape(rng)}</td></tr>"
        )
    body.append("</table>")
    title = f"fe-demo {rec['scene']}: the friction law's band carried to the FE result"
    doc = page(title, body)
    (out / "report.html").write_text(doc, encoding="utf-8")
