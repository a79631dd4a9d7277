"""Pooled law and bootstrap bands of a calibration from several samples.

Every sample (a scan, or a patch of one) gives its first-loading curve ``alpha(p)`` and its
reload curves. The law in ``params.json`` is the *pooled* fit: the law fitted to all samples'
points at once, in the forms a single calibration would choose (:func:`pooled_law`), i.e. the
law of the population's mean curve with every sample weighted equally. How sure that law is, is measured by the bootstrap over samples
(:func:`bootstrap_uncertainty`): ``n_bootstrap`` times, draw ``N`` of the ``N`` samples with
replacement and fit the pooled law again in the forms it runs (as a fit to all samples weighted
by how often each was drawn, :mod:`.band_laws`). The band at ``level`` (default 90 %) is, pointwise, made from those laws by one of
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

* the interval of ``C1, n1, C2, n2`` (the file's header: Eq. 24 and the paper's Eq. 25, refitted
  on every resample) and ``mu_eff`` (of the first-loading form that runs),
* pointwise bands of ``alpha(p)`` and ``tau(p)`` of the law the file runs, on first loading and
  on the reload branch at every reload level ``p_hist``,
* two edge laws (``lower``, ``upper``): the law, in its forms, fitted to the band's lower and
  upper edges.

That is a confidence band of the population's law (where the law of many more patches of the
same sheet would lie), not a prediction band for one further patch: the per-sample laws, also
recorded, show that spread. The measured coverage of both methods at 3, 5, 10 and 16 samples is
in ``docs/uncertainty.md`` (``benchmarks/uncertainty_coverage.py``).

The refits start from the pooled optimum and use scipy's ``least_squares`` (the same residuals
as :mod:`.fit`, looser tolerances: a resample moves the optimum little).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.stats import t as student_t

from frictionlaw import alpha_first, alpha_reload
from frictionlaw.uncertainty import Band, Interval, Uncertainty

from ...common.blas import serial_blas
from ..law import fit as _fit
from ..law import forms as _forms
from .band_laws import Stacked, check_band_forms, edge_law, resample_law, sample_law

__all__ = [
    "BAND_LEVEL",
    "BAND_METHOD",
    "BAND_METHODS",
    "REPORT_PRESSURES",
    "N_BOOTSTRAP",
    "SampleCurves",
    "curves_of",
    "pooled_law",
    "pooled_curves",
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
def pooled_law(scene, samples, *, heldout=True):
    """The pooled law: both branches fitted as ``scene`` asks to all samples' points at once.

    A :class:`~.forms.FittedLaw` (:func:`~.forms.fit_law`): the first loading to every point,
    the reload forms to every sample's points pooled per load level (:func:`pooled_curves`), on
    ``alpha1(p_hist)`` of the first-loading form that runs; each form's errors against all
    points, in sample and with each interior level left out. ``FittedLaw.apply`` gives the
    parameter set. ``heldout=False``: the fits alone (the scene's forms named, not ``auto``).
    """
    p = np.concatenate([s.p for s in samples])
    a = np.concatenate([s.alpha for s in samples])
    return _forms.fit_law(scene, p, a, pooled_curves(samples), heldout=heldout)


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
def bootstrap_laws(samples, central, *, n_bootstrap=N_BOOTSTRAP, seed=0, floor_to=None):
    """The pooled law refitted on ``n_bootstrap`` resamples: a list of ``FrictionParams``.

    Each resample draws ``N`` of the ``N`` samples with replacement (seeded by ``seed``) and
    refits ``central`` in the forms it runs (:func:`.band_laws.resample_law`; ``floor_to``: the
    bound of the pooled fit).
    """
    check_band_forms(central)
    st = Stacked(samples)
    rng = np.random.default_rng(seed)
    n = len(samples)
    out = []
    for _ in range(n_bootstrap):
        counts = np.bincount(rng.integers(0, n, n), minlength=n)
        out.append(resample_law(st, counts, central, floor_to))
    return out


@serial_blas
def bootstrap_uncertainty(
    samples,
    central,
    *,
    level=BAND_LEVEL,
    n_bootstrap=N_BOOTSTRAP,
    seed=0,
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
        the first-loading band's pressures); the band, the edge laws and the sample laws run
        its forms (:mod:`.band_laws`), its variant of the reload branch included.
    level : float
        Two-sided level in ``(0, 1)``.
    n_bootstrap : int
        Resamples, ``>= 50``.
    seed : int
        Seed of the resampling.
    method : str
        How the band is made from the resampled laws, one of :data:`BAND_METHODS`
        (:func:`band_limits`).
    floor_to : float, optional
        The bound ``alpha1(p) >= p / H`` up to ``floor_to`` (Pa) on every refit of Eq. 24, the
        edge laws and the per-sample laws, as on the pooled fit (``Scene.alpha_floor``).
    """
    if len(samples) < 3:
        raise ValueError(f"a band needs at least 3 samples, got {len(samples)}")
    if not (0.0 < level < 1.0):
        raise ValueError(f"level must be in (0, 1), got {level!r}")
    if not (isinstance(n_bootstrap, int) and n_bootstrap >= 50):
        raise ValueError(f"n_bootstrap must be an integer >= 50, got {n_bootstrap!r}")
    check_band_method(method)
    n = len(samples)
    boot = bootstrap_laws(samples, central, n_bootstrap=n_bootstrap, seed=seed, floor_to=floor_to)
    p1 = np.concatenate([s.p for s in samples])
    p_range = central.p_range or (float(p1.min()), float(p1.max()))
    grid1, grid2 = _band_grids(samples, p_range)
    curves = [_curves(law, grid1, grid2) for law in boot]
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
    edge_laws = {k: edge_law(central, grid1, grid2, v, floor_to) for k, v in edges.items()}
    return Uncertainty(
        level=float(level),
        method=(
            f"bootstrap over the {n} samples ({_METHOD_WORDS[method]}, {n_bootstrap} resamples, "
            f"seed {seed}): the pooled law refitted on each resample in the forms it runs "
            f"(first loading {central.first_loading_form}, reload {central.reload_form}); bands "
            "pointwise; edge laws fitted to the band edges; a confidence band of the "
            "population's law, not a prediction band for one further sample (see samples)"
        ),
        n_bootstrap=int(n_bootstrap),
        seed=int(seed),
        samples=tuple(sample_law(s, central, floor_to) for s in samples),
        parameters=_intervals(central, boot, n, level, method),
        edge_laws=edge_laws,
        bands=tuple(bands),
    )


def _intervals(central, boot, n, level, method):
    """The pooled ``C1, n1, C2, n2, mu_eff`` with their intervals (in logs: all are > 0)."""
    keys = ("C1", "n1", "C2", "n2", "mu_eff")
    start = np.array([getattr(central, k) for k in keys])
    stack = np.array([[getattr(law, k) for k in keys] for law in boot])
    lo, hi = band_limits(np.log(stack), np.log(start), n, level, method)
    return {
        k: Interval(float(start[i]), float(np.exp(lo[i])), float(np.exp(hi[i])))
        for i, k in enumerate(keys)
    }


_METHOD_WORDS = {
    "t": "t band: pooled value -+ Student t(N-1) x bootstrap standard error x sqrt(N/(N-1))",
    "percentile": "percentile",
}
