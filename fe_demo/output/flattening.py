"""A flattening comparison's files (issue 43): the same scene with and without the flattening.

``fe-demo upsetting|ring|multistage --flattening`` runs the law twice: with the die nodes' bulk
plastic strain passed to its flattening block and without. Both runs record, per accepted
increment, the area-weighted mean contact fraction over the die's contact nodes against their
mean equivalent plastic strain (``alpha_die_mean``, ``eps_p_die_mean``). This module writes the
figure of both (``flattening.png``), the comparison record that goes into each run's
``summary.json`` (``flattening``) and the report section that shows it.
"""

import html

import numpy as np

from sbmf_cli.htmlpage import figure, number_cell

from .figures import _figure, _save

__all__ = ["flattening_record", "flattening_figure", "plot_flattening", "flattening_section"]


def flattening_record(without, with_):
    """The comparison of the runs' histories: forces and die means at the end of each (SI)."""

    def end(h, key):
        return float(h[key][-1]) if h and len(h.get(key, ())) else None

    f0, f1 = end(without, "force"), end(with_, "force")
    return {
        "force_end_without_N": f0,
        "force_end_with_N": f1,
        "force_change_fraction": (f1 / f0 - 1.0) if f0 and f1 is not None else None,
        "alpha_die_mean_end_without": end(without, "alpha_die_mean"),
        "alpha_die_mean_end_with": end(with_, "alpha_die_mean"),
        "eps_p_die_mean_end_with": end(with_, "eps_p_die_mean"),
        "alpha_f_max_end_with": end(with_, "alpha_f_max"),
        # the two-state block: die contact nodes below its rate table (upper-bound rates there)
        "n_below_flattening_table_end_with": _count(with_, "n_below_flattening_table", -1),
        "n_below_flattening_table_max_with": _count(with_, "n_below_flattening_table", None),
        "height_reduction_end_without": end(without, "height_reduction"),
        "height_reduction_end_with": end(with_, "height_reduction"),
    }


def _count(h, key, at):
    """The history's count ``key`` at row ``at`` (None: the largest over the run).

    None without the column (a one-state block).
    """
    if not h or not len(h.get(key, ())):
        return None
    v = np.asarray(h[key])
    return int(v.max() if at is None else v[at])


def flattening_figure(runs, title="Flattening under bulk strain"):
    """Contact fraction against the die's plastic strain, and the force, of each run.

    ``runs``: ``{label: history}`` (histories with the flattening columns).
    """
    fig, (ax1, ax2) = _figure((10, 4), ncols=2)
    for lab, h in runs.items():
        if not h:
            continue
        on = np.asarray(h["alpha_die_mean"]) > 0
        ax1.plot(
            np.asarray(h["eps_p_die_mean"])[on], np.asarray(h["alpha_die_mean"])[on], label=lab
        )
        ax2.plot(100 * np.asarray(h["height_reduction"]), np.asarray(h["force"]) / 1e3, label=lab)
    ax1.set_xlabel("mean equivalent plastic strain at the die (1)")
    ax1.set_ylabel("mean contact fraction at the die (1)")
    ax1.set_ylim(0, 1.02)
    ax2.set_xlabel("height reduction (%)")
    ax2.set_ylabel("die force (kN)")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def plot_flattening(path, runs, title="Flattening under bulk strain"):
    """Write :func:`flattening_figure` as PNG."""
    return _save(flattening_figure(runs, title), path)


def flattening_section(info, image):
    """The report's section of a run with a ``flattening`` record (else an empty string)."""
    rec = info.get("flattening")
    if not rec:
        return ""
    rows = []
    for what, key, unit, scale in (
        ("die force at the end, without flattening", "force_end_without_N", "kN", 1e-3),
        ("die force at the end, with flattening", "force_end_with_N", "kN", 1e-3),
        ("change of the force", "force_change_fraction", "%", 100.0),
        (
            "mean contact fraction at the die at the end, without",
            "alpha_die_mean_end_without",
            "",
            None,
        ),
        ("mean contact fraction at the die at the end, with", "alpha_die_mean_end_with", "", None),
        ("mean plastic strain at the die at the end", "eps_p_die_mean_end_with", "", None),
        ("largest flattened fraction alpha_f", "alpha_f_max_end_with", "", None),
        (
            "die contact nodes below the two-state table, at the end",
            "n_below_flattening_table_end_with",
            "",
            None,
        ),
        (
            "die contact nodes below the two-state table, most over the run",
            "n_below_flattening_table_max_with",
            "",
            None,
        ),
    ):
        if rec.get(key) is None and key.startswith("n_below"):
            continue  # a one-state block: no table
        cell = number_cell(rec.get(key), f"flattening.{key}", ".4g", scale)
        rows.append(
            f"<tr><td class='t'>{html.escape(what)}</td>{cell}<td class='t'>{unit}</td></tr>"
        )
    table = "<table><tr><th>quantity</th><th>value</th><th>unit</th></tr>" + "".join(rows)
    block = (info.get("law_parameters") or {}).get("flattening") or {}
    model = f" (model {html.escape(str(block['model']))})" if block.get("model") else ""
    return (
        "<h2>Flattening under bulk strain</h2><p>The same run with the die nodes' bulk plastic "
        f"strain passed to the law's flattening block{model} (docs/flattening.md) and "
        "without.</p>"
        + table
        + "</table>"
        + figure(image, "contact fraction against the plastic strain at the die, and the force")
    )
