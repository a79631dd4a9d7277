"""ISO 16610-61 areal Gaussian filters: the S-filter (``lambda_s``) and the L-filter (``lambda_c``).

The linear areal Gaussian filter of ISO 16610-61 weights the surface with

    s(x, y) = 1 / (alpha^2 lambda^2) exp(-pi (x^2 + y^2) / (alpha lambda)^2),
    alpha = sqrt(ln 2 / pi),

whose amplitude transmission for a wavelength ``w`` is ``exp(-pi (alpha lambda / w)^2)``:
50 % at the nesting index ``w = lambda``. The S-filter keeps the smoothed surface (it removes the
wavelengths shorter than ``lambda_s``); the L-filter removes the smoothed surface of nesting index
``lambda_c`` (the waviness longer than ``lambda_c``).

The filter is applied in Fourier space with :func:`scipy.ndimage.fourier_gaussian` (the
transform of the Gaussian, so the transmission is the ISO one at every frequency of the grid,
also when ``lambda`` is a few pixels, where a sampled spatial kernel is off by several percent).
Periodic maps are filtered as one period; other maps are mirrored at their edges first (the
even extension, as :func:`scipy.ndimage.gaussian_filter`'s ``mode="reflect"``), so a scan's edge
is not joined to the opposite one.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import fft as sfft
from scipy import ndimage

__all__ = [
    "ISO_ALPHA",
    "MIN_CUTOFF_PIXELS",
    "check_cutoff",
    "gaussian_transmission",
    "l_filter",
    "s_filter",
]

#: the ISO 16610-61 constant of the Gaussian weighting function, ``sqrt(ln 2 / pi)``
ISO_ALPHA = math.sqrt(math.log(2.0) / math.pi)
#: smallest nesting index in pixel pitches: a shorter cut-off would act above the grid's Nyquist
#: wavelength (two pixels), where there is nothing left to filter
MIN_CUTOFF_PIXELS = 2.0


def gaussian_transmission(wavelength, cutoff):
    """Amplitude transmission of the ISO 16610-61 Gaussian low-pass at ``wavelength``.

    ``exp(-pi (alpha cutoff / wavelength)^2)`` with ``alpha = sqrt(ln 2 / pi)``: 0.5 at
    ``wavelength == cutoff``. The L-filter's (high-pass) transmission is one minus this.
    """
    w = np.asarray(wavelength, dtype=float)
    return np.exp(-math.pi * (ISO_ALPHA * cutoff / w) ** 2)


def check_cutoff(name, value, surface):
    """The nesting index ``value`` (m) of filter ``name`` as a float, if ``surface`` allows it.

    ``ValueError`` naming ``name`` and the range: at least :data:`MIN_CUTOFF_PIXELS` pixel
    pitches, at most the map's shorter side. Both filters check their cut-off with it.
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a length > 0 (m), got {value!r}") from None
    lo = MIN_CUTOFF_PIXELS * max(surface.dx, surface.dy)
    hi = min(surface.size)
    if not (math.isfinite(v) and lo <= v <= hi):
        raise ValueError(
            f"{name} = {value!r} m is outside the allowed range [{lo:.3g}, {hi:.3g}] m: at least "
            f"{MIN_CUTOFF_PIXELS:g} pixel pitches ({max(surface.dx, surface.dy):.3g} m) and at "
            "most the map's shorter side"
        )
    return v


def _smooth(surface, cutoff):
    """The Gaussian-smoothed heights (ISO weighting, nesting index ``cutoff``)."""
    h = surface.heights
    nx, ny = h.shape
    # standard deviation of the ISO weighting: exp(-pi x^2 / (alpha l)^2) = exp(-x^2 / 2 s^2)
    s = ISO_ALPHA * cutoff / math.sqrt(2.0 * math.pi)
    sigma = (s / surface.dx, s / surface.dy)  # in pixels, per axis (non-square pixels)
    if not surface.periodic:  # even extension: period 2 nx x 2 ny, no seam at the edges
        h = np.concatenate([h, h[::-1]], axis=0)
        h = np.concatenate([h, h[:, ::-1]], axis=1)
    f = ndimage.fourier_gaussian(sfft.rfft2(h), sigma, n=h.shape[1])
    return sfft.irfft2(f, s=h.shape)[:nx, :ny]


def s_filter(surface, lambda_s):
    """ISO 16610-61 areal Gaussian S-filter: the wavelengths shorter than ``lambda_s`` removed.

    Parameters
    ----------
    surface : Surface
        Heights without undefined points (fill them first), levelled if it is a scan.
    lambda_s : float
        Nesting index (m): 50 % amplitude transmission. At least :data:`MIN_CUTOFF_PIXELS`
        pixel pitches, at most the map's shorter side.

    Returns
    -------
    Surface
        The filtered surface; the operation is recorded in its provenance.
    """
    lam = check_cutoff("lambda_s", lambda_s, surface)
    out = _smooth(surface, lam)
    op = {"op": "s_filter", "standard": "ISO 16610-61 Gaussian", "lambda_s": lam}
    return surface.derive(out, op)


def l_filter(surface, lambda_c):
    """ISO 16610-61 areal Gaussian L-filter: the wavelengths longer than ``lambda_c`` removed.

    The surface minus its Gaussian-smoothed self (nesting index ``lambda_c``, m; range as
    :func:`s_filter`). The operation is recorded in the provenance.
    """
    lam = check_cutoff("lambda_c", lambda_c, surface)
    out = surface.heights - _smooth(surface, lam)
    op = {"op": "l_filter", "standard": "ISO 16610-61 Gaussian", "lambda_c": lam}
    return surface.derive(out, op)
