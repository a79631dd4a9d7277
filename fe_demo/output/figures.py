"""The runs' PNG plots.

Each plot has a ``*_figure`` function that returns the matplotlib Figure (not held by pyplot, for
notebooks) and a ``plot_*`` wrapper that writes it as PNG; ``SceneResult.figures()`` gives a run's.
"""

import numpy as np

__all__ = [
    "robust_limit",
    "force_stroke_figure",
    "die_profile_figure",
    "law_comparison_figure",
    "ring_chart_figure",
    "recontact_figure",
    "plot_force_stroke",
    "plot_die_profile",
    "plot_law_comparison",
    "plot_ring_chart",
    "plot_recontact",
]


def _figure(figsize, ncols=1, nrows=1):
    """A new figure (not registered with pyplot, so nothing to close) and its axes."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize)
    return fig, fig.subplots(nrows, ncols, sharex=nrows > 1)


def _save(fig, path):
    """Write the (laid-out) figure as PNG at 120 dpi; returns ``path``."""
    fig.savefig(path, dpi=120)
    return path


def force_stroke_figure(histories, labels, title="Cylinder upsetting"):
    """Force against height reduction for one or more runs."""
    fig, ax = _figure((6, 4))
    for h, lab in zip(histories, labels, strict=True):
        ax.plot(100 * h["height_reduction"], h["force"] / 1e3, label=lab)
    ax.set_xlabel("height reduction (%)")
    ax.set_ylabel("die force (kN)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return fig


#: the percentile of a die profile's values that sets its axis (an edge spike lies beyond it)
AXIS_PERCENTILE = 95.0
#: headroom above that percentile before a value counts as a spike and is clipped
AXIS_HEADROOM = 1.5


def robust_limit(values):
    """Upper axis limit that shows the bulk of ``values`` and leaves an edge spike out.

    ``AXIS_HEADROOM`` times the :data:`AXIS_PERCENTILE` percentile, or the maximum (with 5 %
    headroom) where nothing lies beyond that: the contact pressure at the die's edge can be 3-4
    times the rest (a corner singularity of the FE model), which on a linear axis would flatten
    everything else. Returns ``(limit, clipped)``, ``clipped`` the indices of values above it.
    """
    v = np.asarray(values, float)
    if v.size == 0 or not np.isfinite(v).any():
        return 1.0, np.zeros(0, int)
    top = float(np.nanmax(v))
    limit = AXIS_HEADROOM * float(np.nanpercentile(v, AXIS_PERCENTILE))
    if top <= limit or limit <= 0:
        return max(1.05 * top, 1e-12), np.zeros(0, int)
    return limit, np.flatnonzero(v > limit)


def _mark_clipped(ax, r, v, limit, clipped, name, colour):
    """Mark values beyond the axis at its top edge, with the largest one's value."""
    if clipped.size == 0:
        return
    ax.plot(r[clipped], np.full(clipped.size, 0.97 * limit), "^", color=colour, ms=6)
    k = clipped[np.argmax(v[clipped])]
    ax.annotate(
        f"{name} {v[k]:.0f} MPa (edge spike, off the axis)",
        (r[k], 0.97 * limit),
        xytext=(-6, -14),
        textcoords="offset points",
        ha="right",
        fontsize=7,
        color=colour,
    )


def die_profile_figure(profile, title="Along the die"):
    """Contact pressure and ``p_hist`` (top), shear (bottom) against radius, at one reduction.

    The title names the height reduction the profile is taken at (``profile["height_reduction"]``,
    the end of a run). Each panel's axis is set by the bulk of its values
    (:func:`robust_limit`): a spike at the die's edge is drawn at the top edge and labelled with
    its value, so that the shear (tens of MPa) and the pressure (hundreds) are both readable.
    """
    fig, (a1, a2) = _figure((6.4, 5.6), nrows=2)
    r = 1e3 * profile["r"]
    on = profile["p"] > 0
    p = profile["p"][on] / 1e6
    ph = profile["p_hist"][on] / 1e6
    tau = np.abs(profile["tau"][on]) / 1e6
    lim, clipped = robust_limit(np.concatenate([p, ph]))
    a1.plot(r[on], np.minimum(p, lim), "o-", ms=3, label="pressure p")
    a1.plot(r[on], np.minimum(ph, lim), "--", label="p_hist")
    _mark_clipped(a1, r[on], p, lim, clipped[clipped < p.size], "p", "C0")
    a1.set_ylim(0, lim)
    a1.set_ylabel("p, p_hist (MPa)")
    lim_t, clip_t = robust_limit(tau)
    a2.plot(r[on], np.minimum(tau, lim_t), "s-", ms=3, color="C1", label="|shear| tau")
    _mark_clipped(a2, r[on], tau, lim_t, clip_t, "tau", "C1")
    a2.set_ylim(0, lim_t)
    a2.set_ylabel("|tau| (MPa)")
    a2.set_xlabel("r (mm)")
    for a in (a1, a2):
        a.grid(alpha=0.3)
        a.legend(fontsize=8, loc="lower left")
    red = profile.get("height_reduction")
    at = f"at height reduction {100 * red:.1f} %" if red is not None else ""
    fig.suptitle(f"{title}\nalong the die {at}".strip(), fontsize=10)
    fig.tight_layout()
    return fig


def recontact_figure(profile, title="Re-contact: friction limit with and without p_hist"):
    """Pressure, ``p_hist`` and the shear limit of Eq. 25 vs first loading along the die."""
    fig, (a1, a2) = _figure((11, 4), 2)
    r = 1e3 * profile["r"]
    on = profile["p"] > 0
    a1.plot(r[on], profile["p"][on] / 1e6, "o-", ms=3, label="p")
    a1.plot(r[on], profile["p_hist"][on] / 1e6, "--", label="p_hist")
    a1.set_ylabel("MPa")
    a2.plot(r[on], profile["tau_limit"][on] / 1e6, "o-", ms=3, label="tau limit with p_hist")
    a2.plot(
        r[on],
        profile["tau_limit_first_loading"][on] / 1e6,
        "s--",
        ms=3,
        label="tau limit without history (Eq. 24)",
    )
    a2.set_ylabel("MPa")
    for a in (a1, a2):
        a.set_xlabel("r (mm)")
        a.grid(alpha=0.3)
        a.legend()
    fig.suptitle(f"{title} (height reduction {100 * profile['height_reduction']:.2f} %)")
    fig.tight_layout()
    return fig


def law_comparison_figure(results, title="Friction laws side by side"):
    """Force-stroke curves and end-of-run die profiles of several laws."""
    fig, (a1, a2) = _figure((11, 4), 2)
    for lab, (h, prof) in results.items():
        a1.plot(100 * h["height_reduction"], h["force"] / 1e3, label=lab)
        on = prof["p"] > 0
        a2.plot(1e3 * prof["r"][on], np.abs(prof["tau"][on]) / 1e6, label=lab)
    a1.set_xlabel("height reduction (%)")
    a1.set_ylabel("die force (kN)")
    a2.set_xlabel("r (mm)")
    a2.set_ylabel("|shear| on the die (MPa)")
    for a in (a1, a2):
        a.grid(alpha=0.3)
        a.legend()
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def ring_chart_figure(chart, fe_curves=None, title="Ring compression calibration chart"):
    """Upper-bound chart (lines) with FE results (markers) on top.

    ``chart``: dict ``m -> (reduction, inner_diameter_change)``;
    ``fe_curves``: dict ``label -> (reduction, inner_diameter_change)``.
    """
    fig, ax = _figure((6, 4.5))
    for m, (red, dch) in chart.items():
        ax.plot(100 * red, 100 * dch, "k-", lw=0.8)
        ax.annotate(f"m={m:g}", (100 * red[-1], 100 * dch[-1]), fontsize=7)
    markers = "osd^v<>"
    for i, (lab, (red, dch)) in enumerate((fe_curves or {}).items()):
        ax.plot(100 * red, 100 * dch, markers[i % len(markers)], ms=3, label=lab)
    ax.axhline(0, color="0.5", lw=0.5)
    ax.set_xlabel("height reduction (%)")
    ax.set_ylabel("change of inner diameter (%)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    if fe_curves:
        ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def plot_force_stroke(path, histories, labels, title="Cylinder upsetting"):
    """Write :func:`force_stroke_figure` as a PNG file at ``path``; returns ``path``."""
    return _save(force_stroke_figure(histories, labels, title=title), path)


def plot_die_profile(path, profile, title="Along the die"):
    """Write :func:`die_profile_figure` as a PNG file at ``path``; returns ``path``."""
    return _save(die_profile_figure(profile, title=title), path)


def plot_recontact(path, profile, title="Re-contact: friction limit with and without p_hist"):
    """Write :func:`recontact_figure` as a PNG file at ``path``; returns ``path``."""
    return _save(recontact_figure(profile, title=title), path)


def plot_law_comparison(path, results, title="Friction laws side by side"):
    """Write :func:`law_comparison_figure` as a PNG file at ``path``; returns ``path``."""
    return _save(law_comparison_figure(results, title=title), path)


def plot_ring_chart(path, chart, fe_curves=None, title="Ring compression calibration chart"):
    """Write :func:`ring_chart_figure` as a PNG file at ``path``; returns ``path``."""
    return _save(ring_chart_figure(chart, fe_curves=fe_curves, title=title), path)
