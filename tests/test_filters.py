"""ISO 16610-61 areal Gaussian S- and L-filters against the ISO transmission characteristic."""

import math

import numpy as np
import pytest
from scipy import ndimage

from halfspace_calib.topography import Surface, rq
from halfspace_calib.topography.filters import (
    ISO_ALPHA,
    gaussian_transmission,
    l_filter,
    s_filter,
)


def _wave(n, dx, wavelength, *, periodic, dy=None, axis=0):
    dy = dx if dy is None else dy
    x = np.arange(n) * (dx if axis == 0 else dy)
    w = np.sin(2 * np.pi * x / wavelength + 0.3)
    h = w[:, None] * np.ones(n) if axis == 0 else np.ones(n)[:, None] * w[None, :]
    return Surface(h, dx, dy, periodic=periodic)


def _amplitude(h, periodic):
    """Amplitude of a sine map: in the middle half for non-periodic maps (away from the edges)."""
    n = h.shape[0]
    core = h if periodic else h[n // 4 : 3 * n // 4, n // 4 : 3 * n // 4]
    return math.sqrt(2) * float(np.sqrt(np.mean(core**2)))


def test_iso_constant_and_half_transmission_at_the_cutoff():
    assert ISO_ALPHA == pytest.approx(0.4697, abs=1e-4)  # ISO 16610-61: sqrt(ln 2 / pi)
    assert gaussian_transmission(25e-6, 25e-6) == pytest.approx(0.5, rel=1e-12)


@pytest.mark.parametrize("periodic", [True, False])
@pytest.mark.parametrize("ratio", [0.5, 0.75, 1.0, 1.5, 2.0])
def test_s_filter_follows_the_iso_transmission(periodic, ratio):
    """A sine of wavelength w keeps exp(-pi (alpha lambda_s / w)^2) of its amplitude."""
    n, dx = 256, 0.5e-6
    w = n * dx / 16  # 16 periods: periodic on the map
    s = _wave(n, dx, w, periodic=periodic)
    lam = ratio * w
    got = _amplitude(s_filter(s, lam).heights, periodic)
    want = math.exp(-math.pi * (ISO_ALPHA * lam / w) ** 2)
    assert got == pytest.approx(want, rel=2e-3, abs=2e-4)
    if ratio == 1.0:
        assert got == pytest.approx(0.5, rel=2e-3)


def test_l_filter_is_the_complement():
    n, dx = 128, 1e-6
    w = n * dx / 4
    s = _wave(n, dx, w, periodic=True)
    for lam in (0.5 * w, w, 2 * w):
        got = _amplitude(l_filter(s, lam).heights, True)
        assert got == pytest.approx(1 - float(gaussian_transmission(w, lam)), rel=1e-6, abs=1e-9)


def test_non_square_pixels_filter_in_physical_lengths():
    """The same physical wave along x and along y is damped alike on 0.2 x 0.5 um pixels."""
    n = 200
    dx, dy = 0.2e-6, 0.5e-6
    w = 10e-6  # 4 periods along x (40 um), 10 along y (100 um)
    lam = 8e-6
    ax = _amplitude(s_filter(_wave(n, dx, w, periodic=True, dy=dy, axis=0), lam).heights, True)
    ay = _amplitude(s_filter(_wave(n, dx, w, periodic=True, dy=dy, axis=1), lam).heights, True)
    want = float(gaussian_transmission(w, lam))
    assert ax == pytest.approx(want, rel=1e-6)
    assert ay == pytest.approx(want, rel=1e-6)


def test_matches_a_spatial_gaussian_oracle():
    """Independent oracle: scipy's spatial Gaussian of standard deviation alpha lambda / sqrt(2 pi)
    with mirrored edges, where the sampled kernel is accurate (sigma of several pixels)."""
    rng = np.random.default_rng(3)
    h = rng.standard_normal((96, 80))
    dx = 1e-6
    s = Surface(h, dx, dx, periodic=False)
    lam = 40e-6
    sigma = ISO_ALPHA * lam / math.sqrt(2 * math.pi) / dx
    ref = ndimage.gaussian_filter(h, sigma, mode="reflect", truncate=8.0)
    got = s_filter(s, lam).heights
    assert np.max(np.abs(got - ref)) < 1e-3 * np.max(np.abs(ref))


def test_non_periodic_map_keeps_a_plane_and_has_no_seam():
    """A tilted plane is not a periodic map: mirrored edges keep it (a wrap would bend its ends)."""
    n, dx = 64, 1e-6
    x = np.arange(n) * dx
    h = 1e-6 * (x[:, None] / x[-1]) + 0 * x[None, :]
    out = s_filter(Surface(h, dx, dx, periodic=False), 8e-6).heights
    core = slice(12, n - 12)
    assert np.max(np.abs(out[core] - h[core])) < 1e-6 * 1e-6
    assert abs(out.mean() - h.mean()) < 1e-12


def test_filters_split_the_surface_and_reduce_rq():
    rng = np.random.default_rng(1)
    s = Surface(rng.standard_normal((64, 64)) * 1e-7, 1e-6, 1e-6, periodic=True)
    lo, hi = s_filter(s, 8e-6), l_filter(s, 8e-6)
    assert np.allclose(lo.heights + hi.heights, s.heights, atol=1e-20)
    assert rq(lo) < 0.5 * rq(s)
    assert lo.provenance["operations"][-1]["lambda_s"] == 8e-6


@pytest.mark.parametrize("bad", [0.0, -1e-6, math.nan, math.inf, 1e-6, 1.0, "x", None])
def test_bad_cutoff_is_refused_naming_it_and_the_range(bad):
    s = Surface(np.zeros((32, 32)), 1e-6, 1e-6)
    with pytest.raises(ValueError, match=r"lambda_s.*allowed range|lambda_s must be a length"):
        s_filter(s, bad)
    with pytest.raises(ValueError, match=r"lambda_c"):
        l_filter(s, bad)
