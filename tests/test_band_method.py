"""The band methods of several samples on cases with a known answer (issue 26, item 4).

The statistic is the mean of ``n`` normal values: the classical Student ``t`` interval
``mean -+ t_{n-1} s / sqrt(n)`` has exactly the nominal coverage. The ideal bootstrap variance
of the mean is ``(n - 1) / n`` times ``s^2 / n``, so the ``"t"`` band (bootstrap standard error
rescaled by ``sqrt(n / (n - 1))``, ``t`` quantile) is that interval up to the Monte Carlo error
of the resampling, while the percentile band is too narrow at small ``n``.
"""

import math

import numpy as np
import pytest
from scipy.stats import t as student_t

from halfspace_calib.pipeline.band.uncertainty import BAND_METHODS, band_limits


def _boot_means(x, B, rng):
    """``(B, draws)`` bootstrap means of each column of ``x`` (``n x draws``)."""
    n, d = x.shape
    idx = rng.integers(0, n, size=(B, n, d))
    return np.take_along_axis(x[None, :, :].repeat(B, 0), idx, axis=1).mean(axis=1)


def test_t_band_is_the_student_interval_for_the_mean():
    rng = np.random.default_rng(3)
    n, B = 5, 20000
    x = rng.normal(2.0, 0.5, size=(n, 3))
    stack = _boot_means(x, B, rng)
    lo, hi = band_limits(stack, x.mean(0), n, 0.9, "t")
    half = student_t.ppf(0.95, n - 1) * x.std(0, ddof=1) / math.sqrt(n)
    # the bootstrap standard error from 20000 resamples: within about 1 % of the ideal one
    assert hi - x.mean(0) == pytest.approx(half, rel=0.02)
    assert x.mean(0) - lo == pytest.approx(half, rel=0.02)


@pytest.mark.parametrize("n", [3, 5, 10])
def test_coverage_of_normal_means(n):
    """4000 draws: the t band covers 90 % (standard error 0.5 %), the percentile one less."""
    rng = np.random.default_rng(n)
    draws, B, mu = 4000, 200, 1.0
    x = rng.normal(mu, 1.0, size=(n, draws))
    stack = _boot_means(x, B, rng)
    cov = {}
    for m in BAND_METHODS:
        lo, hi = band_limits(stack, x.mean(0), n, 0.9, m)
        cov[m] = float(np.mean((lo <= mu) & (mu <= hi)))
    # the t band: the exact t interval's 0.90, less a little for the resampled standard error
    assert 0.87 <= cov["t"] <= 0.92, cov
    # the percentile band's known shortfall (measured 0.63 / 0.78 / 0.83 at n = 3 / 5 / 10)
    assert cov["percentile"] < cov["t"] - 0.02, cov


def test_band_limits_hold_the_central_value_and_refuse_bad_input():
    stack = np.array([[1.0, 2.0], [1.2, 2.1], [1.1, 2.2]])
    cen = np.array([5.0, 2.1])  # far outside the resamples: the band is widened to hold it
    for m in BAND_METHODS:
        lo, hi = band_limits(stack, cen, 3, 0.9, m)
        assert (lo <= cen).all() and (cen <= hi).all()
    with pytest.raises(ValueError, match="band method must be one of t, percentile"):
        band_limits(stack, cen, 3, 0.9, "bca")
    with pytest.raises(ValueError, match="n must be an integer >= 2"):
        band_limits(stack, cen, 1, 0.9, "t")
    with pytest.raises(ValueError, match="level must be in"):
        band_limits(stack, cen, 3, 1.0, "t")
    with pytest.raises(ValueError, match="stack must have shape"):
        band_limits(stack[:, :1], cen, 3, 0.9, "t")
