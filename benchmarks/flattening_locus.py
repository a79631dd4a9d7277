"""Which sinking rate can meet the FE asperity truth? (issue 43, a study)

The flattening law's first rate (docs/flattening.md, Eqs. F1-F3) came from a surface layer that
yields on an ellipse in (asperity pressure, in-plane stress) alone. Against part B's FE asperity
truth it flattens too slowly, most at low pressure, and no constant ``beta`` closes the miss
(``flattening_truth_fit.py``). This script puts alternative rates beside it, each derived in
docs/flattening_studies.md ("Other rates against the truth") and each keeping the calibrated first loading
``alpha1`` as its zero-strain limit exactly. F1's kinematics are common to all:
``dA/d eps = c / tan(theta)``, ``c = v_b / (l eps_dot)`` the plateaus' sinking rate per
half-spacing and unit strain; the loci differ in ``c``:

- ``E`` (today's law, Eq. F3): ``c = beta (s0 / p_f) r / sqrt(1 - r^2)``, ``r = p / p_f``;
- ``T`` (a straight, Tresca-like side, Eq. T3): ``c = beta s0 / p_f``;
- ``C`` (series columns, Eq. C3): ``c = beta (1 - A)``;
- ``C+E`` (the columns beside the pressure-alone ellipse, Eq. CE3): ``c = beta (1 - A) + c_E``
  with ``c_E`` Eq. F3 at its default ``beta = 1``;
- ``L`` (the slip-line lattice of a rigid-plastic strip at its yield, Eq. F2's
  ``c_L = 1 + tan(theta) (1 - A)``), times ``beta``;
- ``L+E`` (the runtime's rate since the lattice was added, Eq. F3): ``beta (c_L + c_E)``;
- ``L+AE`` (a candidate, not the runtime's): the layer as deep as the plateau's half-width
  ``a = A l`` instead of one half-spacing, ``beta (c_L + A c_E)``;
- ``max(L,E)`` (a candidate): the two mechanisms as alternatives, not superposed: the one that
  sinks faster, ``beta max(c_L, c_E)``;
- ``L|E`` (a candidate): the alternative that saves more power against uniform flow for the
  stretch, by the upper-bound functional (dissipation less the pressure's work): the lattice
  saves ``p c_L`` (the pressure's work on its sinking), the layer ``s0 (1 - sqrt(1 - r^2))``
  (its in-plane stress below the bulk's), per ``2 l^2 eps_dot``; ``beta`` times that one's ``c``;
- ``sL+E`` (a candidate read from the truth's velocity field, ``flattening_flank.py --field``):
  the line at the plateau's edge carries only a share of the lattice's rise at low pressure, the
  rest turning the flank (which grows no contact): ``beta (min(1, 2 p / k) c_L + c_E)``, the
  share in F2c's form with ``k`` for the hardening ``h_k`` (an observed share, not derived).

``p_f`` is the first-loading pressure of the current fraction (``alpha1(p_f) = A``), ``s0 = 2 k``.
Each curve is integrated as ``eps(A) = tan(theta) int dA / c`` on a grid in ``A`` (no closed form
needed; checked against ``frictionlaw.flattening_curve`` for ``L+E`` and against ``C``'s closed form
``A = 1 - (1 - alpha1(p)) exp(-beta eps / tan(theta))``), then read at the truth's strains.

Evaluated (a) with nothing fitted (each locus's default ``beta = 1``) and (b) with ``beta``
fitted (least squares in ``alpha`` over ``ln beta``) on the held-out splits of
``flattening_truth_fit.py``: per profile on one pressure fold predicting the other, and on one
profile predicting the other four. A check: ``E`` with the convected slope (``tan(theta)
exp(-2 eps)``, F1's exact geometry for plane strain across the ridges), nothing fitted.

Run: python benchmarks/flattening_locus.py [--truth CSV]
Writes benchmarks/results/flattening_locus.csv and .md (run record: .run.json).
"""

import math
from pathlib import Path

import numpy as np
from _provenance import run_record, write_rows
from flattening_truth import BAR, law_strain, truth_args
from flattening_truth_fit import FOLDS
from scipy.optimize import minimize_scalar

import frictionlaw as fl
from frictionlaw.flattening import flattening_pressure
from halfspace_calib.pipeline.sweep.flattening import fit_beta

LOCI = ("E", "T", "C", "C+E", "L", "L+E", "L+AE", "max(L,E)", "L|E", "sL+E")
#: points of the ``A`` grid from ``alpha1(p)`` to full contact (cosine-clustered at both ends)
_GRID = 4001
#: the bounds of a fitted ``beta`` (the block's own range, docs/flattening.md)
BETA_BOUNDS = (1e-3, 1e3)


# ------------------------------------------------------------------------------- rates
def rate_ellipse(p, p_f, s0):
    """``c`` of Eq. F3 per unit ``beta``: ``(s0 / p_f) r / sqrt(1 - r^2)``, ``r = p / p_f``."""
    r = np.minimum(p / p_f, 1.0)
    with np.errstate(divide="ignore"):
        return np.where(r < 1.0, (s0 / p_f) * r / np.sqrt(np.maximum(1.0 - r * r, 0.0)), np.inf)


def rate_straight(p_f, s0):
    """``c`` of Eq. T3 per unit ``beta``: normality on the straight side, ``s0 / p_f``."""
    return s0 / p_f


def rate_columns(A):
    """``c`` of Eq. C3 per unit ``beta``: full localisation under the plateaus, ``1 - A``."""
    return 1.0 - A


def rate_lattice(A, slope):
    """``c`` of the slip-line lattice (Eq. F2's ``c_L``) per unit ``beta``: ``1 + tan(theta) (1 - A)``."""
    return 1.0 + slope * (1.0 - A)


def edge_share(p, s0):
    """``min(1, 2 p / k)``, ``k = s0 / 2``: the share of the rise at the plateau's edge (``sL+E``)."""
    return min(1.0, 4.0 * p / s0)


def rate(locus, A, p, p_f, s0, beta, slope):
    """The sinking rate ``c = v_b / (l eps_dot)`` of ``locus`` (module text) on the ``A`` grid."""
    if locus == "E":
        return beta * rate_ellipse(p, p_f, s0)
    if locus == "T":
        return beta * rate_straight(p_f, s0)
    if locus == "C":
        return beta * rate_columns(A)
    if locus == "C+E":
        return beta * rate_columns(A) + rate_ellipse(p, p_f, s0)
    if locus == "L":
        return beta * rate_lattice(A, slope)
    if locus == "L+E":
        return beta * (rate_lattice(A, slope) + rate_ellipse(p, p_f, s0))
    if locus == "L+AE":
        return beta * (rate_lattice(A, slope) + A * rate_ellipse(p, p_f, s0))
    if locus == "max(L,E)":
        return beta * np.maximum(rate_lattice(A, slope), rate_ellipse(p, p_f, s0))
    if locus == "sL+E":
        return beta * (edge_share(p, s0) * rate_lattice(A, slope) + rate_ellipse(p, p_f, s0))
    if locus == "L|E":
        c_l, c_e = rate_lattice(A, slope), rate_ellipse(p, p_f, s0)
        r = np.minimum(p / p_f, 1.0)
        layer_saves = s0 * (1.0 - np.sqrt(np.maximum(1.0 - r * r, 0.0))) > p * c_l
        return beta * np.where(layer_saves, c_e, c_l)
    raise ValueError(f"locus must be one of {LOCI}, got {locus!r}")


class Curve:
    """One (profile, pressure) curve of a law: its ``A`` grid and ``p_f(A)``, made once."""

    def __init__(self, law, p, slope):
        self.law, self.p, self.slope = law, p, slope
        self.s0 = 2.0 * law.k
        self.a0 = float(fl.flattening_curve(p, [0.0], law)[0])  # alpha1(p), the zero-strain limit
        w = 0.5 - 0.5 * np.cos(np.pi * np.linspace(0.0, 1.0, _GRID))
        self.A = self.a0 + (1.0 - 1e-9 - self.a0) * w
        self.p_f = np.maximum(flattening_pressure(self.A, law), p)

    def strain_of(self, locus, beta):
        """``eps(A) = tan(theta) int_{alpha1(p)}^A dA / c`` (trapezoid on the grid)."""
        c = rate(locus, self.A, self.p, self.p_f, self.s0, beta, self.slope)
        with np.errstate(divide="ignore"):
            g = np.where(c > 0, self.slope / c, np.inf)
        g[~np.isfinite(c)] = 0.0  # the ellipse's start (r = 1): dA/d eps unbounded, d eps/dA = 0
        return np.concatenate([[0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * np.diff(self.A))])

    def alpha(self, locus, strains, beta, convected=False):
        """The contact fraction after ``strains`` (at constant ``p``) under ``locus``.

        ``convected``: the flank slope falls as ``exp(-2 eps)`` (F1's exact geometry); since
        ``dA/d eps`` is then ``c exp(2 eps) / tan(theta)``, the law at the strain
        ``(exp(2 eps) - 1) / 2`` with the initial slope.
        """
        e = np.asarray(strains, dtype=float)
        if convected:
            e = np.expm1(2.0 * e) / 2.0
        return np.interp(e, self.strain_of(locus, beta), self.A)


# ----------------------------------------------------------------------------- fitting
def misses(curves, truth_cols, locus, beta, convected=False):
    """``alpha_law - alpha_truth`` at every point of the given curves (one array per curve)."""
    out = []
    for cv, col in zip(curves, truth_cols, strict=True):
        s = sorted(col)
        out.append(cv.alpha(locus, s, beta, convected) - np.array([col[x] for x in s]))
    return out


def fit(curves, truth_cols, locus):
    """``beta`` minimising the squared ``alpha`` misses (bounded search in ``ln beta``)."""

    def loss(lb):
        return sum(float(np.sum(d * d)) for d in misses(curves, truth_cols, locus, math.exp(lb)))

    # the loss is not convex in ln beta where curves reach full contact: a grid first (61 points
    # over the bounds), then Brent's bounded search between the best point's neighbours
    grid = np.linspace(*(math.log(b) for b in BETA_BOUNDS), 61)
    k = int(np.argmin([loss(x) for x in grid]))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    res = minimize_scalar(loss, bounds=(lo, hi), method="bounded", options={"xatol": 1e-6})
    return math.exp(res.x)


# ------------------------------------------------------------------------------ checks
def self_checks(truth, H, laws):
    """The integration against the runtime (``E``) and ``C``'s closed form; ``fit`` against ``fit_beta``."""
    key = next(k for k in truth if k[0].startswith("wedge 5"))
    law, table = laws[key], truth[key]
    slope = math.tan(math.radians(key[1]))
    strains = sorted(table[0.1])
    worst_e = worst_c = 0.0
    for pH in sorted(table):
        cv = Curve(law, pH * H, slope)
        ref = fl.flattening_curve(pH * H, law_strain(strains), law)  # loci: in the stretch
        worst_e = max(worst_e, float(np.abs(cv.alpha("L+E", strains, 1.0) - ref).max()))
        closed = 1.0 - (1.0 - cv.a0) * np.exp(-2.0 * np.asarray(strains) / slope)
        worst_c = max(worst_c, float(np.abs(cv.alpha("C", strains, 2.0) - closed).max()))
    # the fit against the command's own fit_beta (least squares in ln beta), one curve
    from flattening_truth_fit import data_of

    ours = fit([Curve(law, 0.3 * H, slope)], [table[0.3]], "L+E")
    theirs = fit_beta(law, data_of(table, H, [0.3], key[0]))["beta"]
    return {
        "L+E against flattening_curve (max |d alpha|, wedge 5 deg, all p/H)": worst_e,
        "C against its closed form (max |d alpha|, beta 2)": worst_c,
        "fitted beta of L+E: this script / fit_beta (wedge 5 deg, p/H 0.3)": ours / theirs,
    }


# -------------------------------------------------------------------------------- main
def main(argv=None):
    args, truth, H, laws = truth_args(__doc__, "flattening_locus", argv)
    curves = {
        (key, pH): Curve(laws[key], pH * H, math.tan(math.radians(key[1])))
        for key, table in truth.items()
        for pH in table
    }
    rows = []

    def add(locus, mode, trained_on, key, pressures, beta, convected=False):
        cvs = [curves[(key, pH)] for pH in pressures]
        cols = [truth[key][pH] for pH in pressures]
        for pH, d in zip(pressures, misses(cvs, cols, locus, beta, convected), strict=True):
            rows.append(
                {
                    "locus": locus + (" convected" if convected else ""),
                    "mode": mode,
                    "trained_on": trained_on,
                    "profile": key[0],
                    "p_over_H": pH,
                    "beta": beta,
                    "max_abs_miss": float(np.abs(d).max()),
                    "sum_sq_miss": float(np.sum(d * d)),
                    "points": len(d),
                }
            )

    for locus in LOCI:
        for key, table in truth.items():  # (a) nothing fitted
            add(locus, "default", "-", key, sorted(table), 1.0)
            if locus == "E":
                add(locus, "default", "-", key, sorted(table), 1.0, convected=True)
        for train, test in (FOLDS, FOLDS[::-1]):  # (b) pressure split, per profile
            for key, table in truth.items():
                beta = fit([curves[(key, p)] for p in train], [table[p] for p in train], locus)
                add(locus, "pressure", "p/H " + " ".join(f"{p:g}" for p in train), key, test, beta)
        for tkey, ttable in truth.items():  # (b) slope split: one profile predicts the others
            ps = sorted(ttable)
            beta = fit([curves[(tkey, p)] for p in ps], [ttable[p] for p in ps], locus)
            for key, table in truth.items():
                if key != tkey:
                    add(locus, "slope", tkey[0], key, sorted(table), beta)
        for key, table in truth.items():  # the floor: each curve's own best beta
            for pH in sorted(table):
                beta = fit([curves[(key, pH)]], [table[pH]], locus)
                add(locus, "per curve", f"{key[0]} p/H {pH:g}", key, [pH], beta)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_rows(out.with_suffix(".csv"), rows)
    checks = self_checks(truth, H, laws)
    lines = report(rows, checks, Path(args.truth).name, H)
    out.with_suffix(".md").write_text("\n".join(lines) + "\n", encoding="utf-8")
    print("\n".join(lines))


def _stats(sel):
    """Largest miss, RMS over points, curves within the bar, curve count."""
    rms = math.sqrt(sum(r["sum_sq_miss"] for r in sel) / sum(r["points"] for r in sel))
    return (
        max(r["max_abs_miss"] for r in sel),
        rms,
        sum(r["max_abs_miss"] <= BAR for r in sel),
        len(sel),
    )


def report(rows, checks, truth_name, H):
    """The Markdown summary: nothing fitted, held out, per p/H band, the checks."""
    loci = list(dict.fromkeys(r["locus"] for r in rows))
    modes = ("default", "pressure", "slope", "per curve")
    bands = sorted({r["p_over_H"] for r in rows})
    lines = [
        "# Sinking rates against the FE asperity truth (issue 43 study)",
        "",
        f"`benchmarks/flattening_locus.py`, truth `{truth_name}`; H = {H / 1e6:.1f} MPa. "
        "Misses are |alpha_law - alpha_truth| over all strains of a curve (the bar: "
        f"{BAR}); 'default' is each locus with beta = 1 (nothing fitted), 'pressure' and "
        "'slope' the held-out splits of flattening_truth_fit.py (beta fitted on the other "
        "curves), 'per curve' each curve's own best beta (the floor of any beta(p, theta)).",
        "",
        "| locus | mode | beta (range) | largest miss | RMS | curves within the bar |",
        "|---|---|---|---|---|---|",
    ]
    for locus in loci:
        for mode in modes:
            sel = [r for r in rows if r["locus"] == locus and r["mode"] == mode]
            if not sel:
                continue
            mx, rms, n_in, n = _stats(sel)
            b = [r["beta"] for r in sel]
            br = f"{min(b):.2f}" if min(b) == max(b) else f"{min(b):.2f}-{max(b):.2f}"
            lines.append(f"| {locus} | {mode} | {br} | {mx:.3f} | {rms:.3f} | {n_in} of {n} |")
    lines += [
        "",
        "## Largest miss per p/H band (nothing fitted / pressure split / slope split)",
        "",
        "| locus | " + " | ".join(f"p/H {b:g}" for b in bands) + " |",
        "|---" * (len(bands) + 1) + "|",
    ]
    for locus in loci:
        cells = []
        for b in bands:
            vals = []
            for mode in ("default", "pressure", "slope"):
                sel = [
                    r
                    for r in rows
                    if r["locus"] == locus and r["mode"] == mode and r["p_over_H"] == b
                ]
                vals.append(f"{max(r['max_abs_miss'] for r in sel):.3f}" if sel else "-")
            cells.append(" / ".join(vals))
        lines.append(f"| {locus} | " + " | ".join(cells) + " |")
    lines += ["", "## The per-curve best beta (its spread is what a constant cannot follow)", ""]
    lines += ["| locus | " + " | ".join(f"p/H {b:g}" for b in bands) + " |"]
    lines += ["|---" * (len(bands) + 1) + "|"]
    for locus in loci:
        cells = []
        for b in bands:
            sel = [
                r["beta"]
                for r in rows
                if r["locus"] == locus and r["mode"] == "per curve" and r["p_over_H"] == b
            ]
            cells.append(f"{min(sel):.2f}-{max(sel):.2f}" if sel else "-")
        lines.append(f"| {locus} | " + " | ".join(cells) + " |")
    lines += ["", "## Checks", ""]
    lines += [f"- {k}: {v:.3g}" for k, v in checks.items()]
    return lines


if __name__ == "__main__":
    with run_record(__file__):
        main()
