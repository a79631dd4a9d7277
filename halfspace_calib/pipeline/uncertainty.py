"""Pooled law and bootstrap bands of a calibration from several samples.

Every sample (a scan, or a patch of one) gives its first-loading curve ``alpha(p)`` and its
reload curves. The law in ``params.json`` is the *pooled* fit: Eqs. 24-25 fitted to all samples'
points at once (:func:`pooled_fit`), i.e. the law of the population's mean curve with every
sample weighted equally. How sure that law is, is measured by the bootstrap over samples
(:func:`bootstrap_uncertainty`): ``n_bootstrap`` times, draw ``N`` of the ``N`` samples with
replacement and fit the pooled law again (as a fit to all samples weighted by how often each was
drawn). The band at ``level`` (default 90 %) is, pointwise, made from those laws by one of
:data:`BAND_METHODS` (:func:`band_limits`):

* ``"t"`` (the default): the pooled value plus and minus Student's ``t`` quantile at ``N - 1``
  degrees of freedom times the bootstrap standard error, rescaled by ``sqrt(N / (N - 1))``. For
  the mean of ``N`` values the (ideal) bootstrap variance is ``(N - 1) / N`` times the usual
  ``s^2 / N``, so this band is then exactly the classical ``t`` interval: the small-sample
  correction of the "expanded" bootstrap intervals (Hesterberg, "What teachers should know
  about the bootstrap", The American Statistician 69 (2015) 371-386, Sec. 4; the bootstrap
  standard error with a ``t`` quantile as in Efron and Tibshirani, "An Introduction to the
  Bootstrap", 1993, Sec. 12.2). Parameters ``C, n > 0`` get it in their logarithms.
* ``"percentile"``: the 5 % and 95 % quantiles of the resampled laws (the method before issue
  26): too narrow with few samples (it resamples only the ``N`` it saw and uses no ``t``).

Either gives

* the interval of ``C1, n1, C2, n2`` and ``mu_eff``,
* pointwise bands of ``alpha(p)`` and ``tau(p)`` on first loading and on the reload branch at
  every reload level ``p_hist``,
* two edge laws (``lower``, ``upper``): Eqs. 24-25 fitted to the band's lower and upper edges.

That is a confidence band of the population's law (where the law of many more patches of the
same sheet would lie), not a prediction band for one further patch: the per-sample laws, also
recorded, show that spread. The measured coverage of both methods at 3, 5, 10 and 16 samples is
in ``docs/uncertainty.md`` (``benchmarks/uncertainty_coverage.py``).

The refits start from the pooled optimum and use scipy's ``least_squares`` (the same residuals
as :mod:`.fit`, looser tolerances: a resample moves the optimum little), so a thousand resamples
take seconds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares
from scipy.stats import t as student_t

from frictionlaw import alpha_first, alpha_reload
from frictionlaw.uncertainty import Band, Interval, SampleLaw, Uncertainty

from ..common.blas import serial_blas
from . import fit as _fit
from . import heldout as _held
from .alpha_bound import floor_fit, floor_violation

__all__ = [
    "BAND_LEVEL",
    "BAND_METHOD",
    "BAND_METHODS",
    "REPORT_PRESSURES",
    "N_BOOTSTRAP",
    "SampleCurves",
    "curves_of",
    "pooled_fit",
    "pooled_curves",
    "pooled_reload_law",
    "band_limits",
    "bootstrap_uncertainty",
]

#: default two-sided level of the bands
BAND_LEVEL = 0.9
#: how a band is made from the resampled laws (:func:`band_limits`)
BAND_METHODS = ("t", "percentile")
#: the default band method
BAND_METHOD = "t"
#: default bootstrap resamples
N_BOOTSTRAP = 400
#: pressures per band curve
_BAND_POINTS = 60
#: pressures at which the band is reported (Pa): on the first-loading band's grid exactly
REPORT_PRESSURES = (100e6, 300e6, 600e6)


@dataclass(frozen=True)
class SampleCurves:
    """One sample's converged curves: first loading ``(p, alpha)`` and its reload curves."""

    name: str
    p: np.ndarray
    alpha: np.ndarray
    reload: tuple  # of fit.ReloadCurve


def curves_of(name, sweeps):
    """The :class:`SampleCurves` of a sample's :class:`~.sweeps.SweepResult`."""
    p, a = sweeps.loading
    return SampleCurves(name, p, a, tuple(sweeps.reload_curves()))


@serial_blas
def pooled_fit(samples, H, *, continuous=False, alpha_floor=None):
    """``(FirstLoadingFit, ReloadFit)`` of Eqs. 24-25 to all samples' points at once.

    ``alpha_floor``: Eq. 24 subject to ``alpha1(p) >= p / H`` up to ``alpha_floor H`` (as a
    single calibration, ``Scene.alpha_floor``; ``None``: unconstrained); give the bootstrap the
    same bound (:func:`bootstrap_uncertainty`'s ``floor_to``).
    """
    p = np.concatenate([s.p for s in samples])
    a = np.concatenate([s.alpha for s in samples])
    floor_to = None if alpha_floor is None else alpha_floor * H
    first = _fit.fit_first_loading(p, a, H, floor_to=floor_to)
    curves = [c for s in samples for c in s.reload]
    reload = _fit.fit_reload(curves, H, first.C1, first.n1, continuous=continuous)
    return first, reload


def pooled_curves(samples):
    """Every sample's reload points pooled per load level: one curve per ``p_hist``.

    What the tabulated reload form is fitted to (one ``C2, n2`` per level) when the samples share
    their load levels, as the samples of one scene do.
    """
    by_level = {}
    for s in samples:
        for c in s.reload:
            by_level.setdefault(float(c.p_hist), []).append(c)
    out = []
    for ph in sorted(by_level):
        cs = by_level[ph]
        p = np.concatenate([c.p for c in cs])
        a = np.concatenate([c.alpha for c in cs])
        order = np.argsort(p, kind="stable")
        out.append(_fit.ReloadCurve(ph, p[order], a[order]))
    return out


def pooled_reload_law(scene, curves, first, reload):
    """The pooled reload law: ``(form, table fit or None, errors)``, as a single calibration's.

    Both forms are fitted to every sample's points pooled per load level (:func:`pooled_curves`)
    and chosen as ``scene.reload_form`` says (:func:`.heldout.reload_law`); the errors are the
    pooled law's against all points, in sample and with each interior level left out.
    """
    p = np.concatenate([c.p for c in curves])
    alpha = np.concatenate([c.alpha for c in curves])
    return _held.reload_law(scene, p, alpha, pooled_curves(curves), first, reload)


class _Stacked:
    """All samples' points as flat arrays with each point's sample index (for weighted refits)."""

    def __init__(self, samples):
        self.p1 = np.concatenate([s.p for s in samples])
        self.a1 = np.concatenate([s.alpha for s in samples])
        self.i1 = np.concatenate([np.full(s.p.size, i) for i, s in enumerate(samples)])
        rc = [(i, c) for i, s in enumerate(samples) for c in s.reload]
        self.p2 = np.concatenate([c.p for _, c in rc])
        self.h2 = np.concatenate([np.full(c.p.size, c.p_hist) for _, c in rc])
        self.a2 = np.concatenate([c.alpha for _, c in rc])
        self.i2 = np.concatenate([np.full(c.p.size, i) for i, c in rc])


def _refit(model, alpha, w, x0, lb, ub):
    """Weighted least squares in log-parameters from ``x0``: the fitted ``(C, n)``."""

    def residual(x):
        return (model(*np.exp(x)) - alpha) * w

    x0 = np.clip(np.log(x0), np.log(lb) + 1e-9, np.log(ub) - 1e-9)
    sol = least_squares(residual, x0, bounds=(np.log(lb), np.log(ub)), method="trf")
    return np.exp(sol.x)


def _fit_weighted(st, counts, H, continuous, start, floor_to=None):
    """Pooled ``C1, n1, C2, n2`` with sample ``i`` counted ``counts[i]`` times.

    ``floor_to``: Eq. 24 subject to ``alpha1(p) >= p / H`` up to it (as the pooled fit).
    """
    lb = np.array([_fit.C_BOUNDS[0], _fit.N_BOUNDS[0]])
    ub = np.array([_fit.C_BOUNDS[1], _fit.N_BOUNDS[1]])
    w1 = np.sqrt(counts[st.i1].astype(float))

    def model1(c, n):
        return alpha_first(st.p1, _fit._law(H, c, n))

    c1, n1 = _refit(model1, st.a1, w1, start[:2], lb, ub)
    if floor_to is not None and floor_violation(c1, n1, H, floor_to)[0] > 1e-12:
        x0 = np.clip(np.log([c1, n1]), np.log(lb) + 1e-9, np.log(ub) - 1e-9)
        par = floor_fit(
            lambda x: (model1(*np.exp(x)) - st.a1) * w1, H, floor_to, x0, lb, ub, ("C1", "n1")
        )[0]
        c1, n1 = par["C1"], par["n1"]
    w2 = np.sqrt(counts[st.i2].astype(float))
    c2, n2 = _refit(
        lambda c, n: alpha_reload(st.p2, st.h2, _fit._law(H, c1, n1, c, n, continuous)),
        st.a2,
        w2,
        start[2:],
        lb,
        ub,
    )
    return np.array([c1, n1, c2, n2])


def check_band_method(method):
    """``method`` if it is one of :data:`BAND_METHODS`, else ``ValueError`` naming them."""
    if method not in BAND_METHODS:
        raise ValueError(f"band method must be one of {', '.join(BAND_METHODS)}, got {method!r}")
    return method


def band_limits(stack, central, n, level=BAND_LEVEL, method=BAND_METHOD):
    """Pointwise two-sided limits ``(lower, upper)`` at ``level`` from bootstrap replicates.

    Parameters
    ----------
    stack : array_like, shape (B, ...)
        The statistic on each of ``B`` bootstrap resamples (``B >= 2``).
    central : array_like, shape (...)
        The statistic on the samples themselves (the pooled value).
    n : int
        Number of samples resampled (``>= 2``): the ``t`` quantile's ``n - 1`` degrees of freedom.
    level : float
        Two-sided level in ``(0, 1)``.
    method : str
        ``"t"``: ``central -+ t_{n-1} sqrt(n / (n - 1)) sd(stack)``; ``"percentile"``: the
        ``(1 -+ level) / 2`` quantiles of ``stack`` (module docstring).

    Returns
    -------
    (ndarray, ndarray)
        The limits, widened where needed so that ``lower <= central <= upper``.
    """
    check_band_method(method)
    stack = np.asarray(stack, dtype=float)
    central = np.asarray(central, dtype=float)
    if not (isinstance(n, (int, np.integer)) and n >= 2):
        raise ValueError(f"n must be an integer >= 2 (samples), got {n!r}")
    if stack.ndim < 1 or stack.shape[0] < 2 or stack.shape[1:] != central.shape:
        raise ValueError(
            f"stack must have shape (B >= 2, *central.shape), got {stack.shape} and {central.shape}"
        )
    if not (0.0 < level < 1.0):
        raise ValueError(f"level must be in (0, 1), got {level!r}")
    if method == "percentile":
        lo, hi = np.quantile(stack, (0.5 * (1 - level), 0.5 * (1 + level)), axis=0)
    else:
        se = np.std(stack, axis=0, ddof=1) * math.sqrt(n / (n - 1))
        half = float(student_t.ppf(0.5 * (1 + level), n - 1)) * se
        lo, hi = central - half, central + half
    return np.minimum(lo, central), np.maximum(hi, central)


def _band_grids(samples, p_range):
    """Pressures of the first-loading band and ``{p_hist: pressures}`` of the reload bands."""
    lo, hi = p_range
    ps = np.concatenate([s.p for s in samples])  # the swept pressures and the report's exactly
    keep = [p for p in (*REPORT_PRESSURES, *ps) if lo <= p <= hi]
    grid1 = np.unique(np.concatenate([np.geomspace(lo, hi, _BAND_POINTS), keep]))
    levels = sorted({float(c.p_hist) for s in samples for c in s.reload})
    grid2 = {}
    for ph in levels:
        ps = [c.p for s in samples for c in s.reload if c.p_hist == ph]
        pmin, pmax = min(float(p.min()) for p in ps), max(float(p.max()) for p in ps)
        grid2[ph] = np.linspace(pmin, pmax, _BAND_POINTS // 2)
    return grid1, grid2


def _curves(law, grid1, grid2):
    """``alpha`` of one law on the band grids: first loading, then each reload level."""
    out = [alpha_first(grid1, law)]
    out += [alpha_reload(g, ph, law) for ph, g in grid2.items()]
    return out


@serial_blas
def bootstrap_laws(
    samples, central, *, n_bootstrap=N_BOOTSTRAP, seed=0, continuous=False, floor_to=None
):
    """``(n_bootstrap, 4)`` array of the pooled ``C1, n1, C2, n2`` refitted on resamples.

    Each resample draws ``N`` of the ``N`` samples with replacement (seeded by ``seed``); the
    refit starts from ``central``'s parameters (``floor_to``: the bound of the pooled fit).
    """
    st = _Stacked(samples)
    start = np.array([central.C1, central.n1, central.C2, central.n2])
    rng = np.random.default_rng(seed)
    n = len(samples)
    boot = np.empty((n_bootstrap, 4))
    for b in range(n_bootstrap):
        counts = np.bincount(rng.integers(0, n, n), minlength=n)
        boot[b] = _fit_weighted(st, counts, central.H, continuous, start, floor_to)
    return boot


@serial_blas
def bootstrap_uncertainty(
    samples,
    central,
    *,
    level=BAND_LEVEL,
    n_bootstrap=N_BOOTSTRAP,
    seed=0,
    continuous=False,
    method=BAND_METHOD,
    floor_to=None,
):
    """The :class:`frictionlaw.uncertainty.Uncertainty` block of a multi-sample calibration.

    Parameters
    ----------
    samples : sequence of SampleCurves
        At least 3 samples.
    central : frictionlaw.FrictionParams
        The pooled law (its ``m, sigma_y, H, k, geo_ratio`` scale ``tau``; ``p_range`` sets
        the first-loading band's pressures).
    level : float
        Two-sided level in ``(0, 1)``.
    n_bootstrap : int
        Resamples, ``>= 50``.
    seed : int
        Seed of the resampling.
    continuous : bool
        The reload fit's variant (as the pooled fit).
    method : str
        How the band is made from the resampled laws, one of :data:`BAND_METHODS`
        (:func:`band_limits`).
    floor_to : float, optional
        The bound ``alpha1(p) >= p / H`` up to ``floor_to`` (Pa) on every refit, the edge laws
        and the per-sample laws, as on the pooled fit (``Scene.alpha_floor``).
    """
    if len(samples) < 3:
        raise ValueError(f"a band needs at least 3 samples, got {len(samples)}")
    if not (0.0 < level < 1.0):
        raise ValueError(f"level must be in (0, 1), got {level!r}")
    if not (isinstance(n_bootstrap, int) and n_bootstrap >= 50):
        raise ValueError(f"n_bootstrap must be an integer >= 50, got {n_bootstrap!r}")
    check_band_method(method)
    H = central.H
    st = _Stacked(samples)
    start = np.array([central.C1, central.n1, central.C2, central.n2])
    n = len(samples)
    boot = bootstrap_laws(
        samples,
        central,
        n_bootstrap=n_bootstrap,
        seed=seed,
        continuous=continuous,
        floor_to=floor_to,
    )
    p_range = central.p_range or (float(st.p1.min()), float(st.p1.max()))
    grid1, grid2 = _band_grids(samples, p_range)
    curves = [
        _curves(central.replace(C1=c1, n1=n1, C2=c2, n2=n2, uncertainty=None), grid1, grid2)
        for c1, n1, c2, n2 in boot
    ]
    central_curves = _curves(central, grid1, grid2)
    tau_scale = central.tau_max  # tau = m k (1 + geo_ratio) alpha
    bands, edges = [], {"lower": [], "upper": []}
    grids = [(None, grid1)] + list(grid2.items())
    for j, (ph, g) in enumerate(grids):
        stack = np.array([c[j] for c in curves])
        cen = central_curves[j]
        lo, hi = band_limits(stack, cen, n, level, method)  # the pooled law lies in its band
        lo, hi = np.clip(lo, 0.0, 1.0), np.clip(hi, 0.0, 1.0)  # a contact ratio
        edges["lower"].append(lo)
        edges["upper"].append(hi)
        kind = "first" if ph is None else "reload"
        for quantity, scale in ((f"alpha_{kind}", 1.0), (f"tau_{kind}", tau_scale)):
            bands.append(
                Band(
                    quantity,
                    ph,
                    tuple(float(x) for x in g),
                    tuple(float(x) for x in cen * scale),
                    tuple(float(x) for x in lo * scale),
                    tuple(float(x) for x in hi * scale),
                )
            )
    edge_laws = {k: _edge_law(H, grid1, grid2, v, continuous, floor_to) for k, v in edges.items()}
    mu_scale = central.tau_max / H
    params = {}
    lo_p, hi_p = band_limits(np.log(boot), np.log(start), n, level, method)  # C, n > 0
    for i, k in enumerate(("C1", "n1", "C2", "n2")):
        params[k] = Interval(float(start[i]), float(np.exp(lo_p[i])), float(np.exp(hi_p[i])))
    c1 = params["C1"]
    params["mu_eff"] = Interval(c1.central * mu_scale, c1.lower * mu_scale, c1.upper * mu_scale)
    sample_laws = tuple(_sample_law(s, H, continuous, floor_to) for s in samples)
    return Uncertainty(
        level=float(level),
        method=(
            f"bootstrap over the {n} samples ({_METHOD_WORDS[method]}, {n_bootstrap} resamples, "
            f"seed {seed}): the pooled Eq. 24-25 fit redone on each resample; bands pointwise; "
            "edge laws "
            "fitted to the band edges; a confidence band of the population's law, not a "
            "prediction band for one further sample (see samples)"
        ),
        n_bootstrap=int(n_bootstrap),
        seed=int(seed),
        samples=sample_laws,
        parameters=params,
        edge_laws=edge_laws,
        bands=tuple(bands),
    )


_METHOD_WORDS = {
    "t": "t band: pooled value -+ Student t(N-1) x bootstrap standard error x sqrt(N/(N-1))",
    "percentile": "percentile",
}


def _edge_law(H, grid1, grid2, edge, continuous, floor_to=None):
    """``{C1, n1, C2, n2}`` fitted to one band edge (first loading, then the reload levels)."""
    first = _fit.fit_first_loading(grid1, np.clip(edge[0], 0.0, 1.0), H, floor_to=floor_to)
    curves = [
        _fit.ReloadCurve(ph, g, np.clip(a, 0.0, 1.0))
        for (ph, g), a in zip(grid2.items(), edge[1:], strict=True)
        if g[0] > 0
    ]
    rel = _fit.fit_reload(curves, H, first.C1, first.n1, continuous=continuous)
    return {"C1": first.C1, "n1": first.n1, "C2": rel.C2, "n2": rel.n2}


def _sample_law(s, H, continuous, floor_to=None):
    """One sample's own fit as a :class:`SampleLaw` (``nan`` never: a failed fit raises)."""
    first = _fit.fit_first_loading(s.p, s.alpha, H, floor_to=floor_to)
    rel = _fit.fit_reload(list(s.reload), H, first.C1, first.n1, continuous=continuous)
    vals = (first.C1, first.n1, rel.C2, rel.n2)
    if not all(math.isfinite(v) for v in vals):  # pragma: no cover - fits return finite values
        raise RuntimeError(f"sample {s.name}: the fit gave non-finite parameters {vals}")
    return SampleLaw(s.name, *vals)
