"""The preparation of a measured surface, as one chain of stages (docs/measured_surfaces.md).

    read -> fill holes -> level -> L-filter -> S-filter -> crop and resample -> level

Each stage is one function here. It takes a :class:`~.surface.Surface` (``fill_holes`` takes the
raw heights) and returns ``(result, steps)``: the result and the lines of provenance the run
prints and ``params.json`` keeps ("what was done, in order"; empty when the stage changed
nothing). The stages decide nothing. Their parameters are decided once, before the chain runs,
by the plan of a scene's surfaces (:func:`halfspace_calib.pipeline.sweep.surface_plan.plan_surfaces`),
which also reads the files (:func:`~.files.read_raw`, units and sizes of files and options),
fills their holes (:func:`fill_holes`) and checks the filters' cut-offs on each scan
(:func:`check_filter`). The rest of the chain runs from a :class:`ChainPlan` (``lambda_s`` and
``lambda_c``, the centred square ``side``, the grid ``m``) in :func:`run`.

The chain serves:

- the calibration's files, where the scene decides the plan;
- the sample patches of ``--patches``, cut from the files prepared on ``k`` times the patch grid
  (the same plan on another grid) and levelled again by :func:`level_patch`;
- the after-contact scans of ``--after-contact``, planned with the calibration's choices fixed.

Synthetic surfaces do not go through it. They are generated on the solver grid with their
spectrum cut at two elements (``synthesis``), so there is nothing to fill, filter, crop or
resample, and they are periodic, so there is no plane to level.

Crop and resample are one stage. The resamplers place the centred square with sub-pixel accuracy
(:func:`~.resample.area_resample` averages exact partial pixels,
:func:`~.resample.band_limited_resample` integrates the cosine series over the cells). Cropping
to whole pixels first would move the square by up to half a pixel.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from sbmf_cli import ParameterError

from .files import fill_harmonic
from .filters import check_cutoff, l_filter, s_filter
from .resample import area_resample, band_limited_resample
from .surface import level

__all__ = [
    "ChainPlan",
    "run",
    "fill_holes",
    "level_scan",
    "filter_scan",
    "check_filter",
    "crop_resample",
    "level_patch",
    "SQUARE_PIXEL_RTOL",
]

#: pixels whose two pitches differ by less than this (relative) count as square
SQUARE_PIXEL_RTOL = 0.01


@dataclass(frozen=True)
class ChainPlan:
    """The parameters of the stages after the read, decided before the chain runs (SI units).

    Attributes
    ----------
    lambda_s : float
        S-filter nesting index (m); ``0.0``: no S-filter.
    lambda_c : float or None
        L-filter nesting index (m); ``None``: no L-filter.
    side : float
        Edge of the centred square (m).
    m : int
        Square elements a side of the resampled patch.
    """

    lambda_s: float
    lambda_c: float | None
    side: float
    m: int


def run(surface, plan, steps=()):
    """The chain after the read, from ``plan``: ``(whole, patch, steps)``.

    ``surface``: a read scan, its holes filled; ``steps``: what was done to it so far.
    ``whole`` is the whole scan levelled and filtered (:func:`level_scan`, :func:`filter_scan`;
    ``surface`` itself without a filter), ``patch`` the centred square resampled and levelled
    (:func:`crop_resample`, :func:`level_patch`), ``steps`` all lines of provenance in order.
    The whole-scan stages are kept for the last few scans and cut-offs (the resolution check and
    the sample patches prepare the same scan on another grid).
    """
    whole, done = _whole_scan(surface, plan.lambda_s, plan.lambda_c)
    patch, resampled = crop_resample(whole, plan.side, plan.m, plan.lambda_s)
    patch, levelled = level_patch(patch)
    return whole, patch, tuple(steps) + done + resampled + levelled


@functools.lru_cache(maxsize=4)  # keyed by the scan object: a scan read again is filtered again
def _whole_scan(surface, lambda_s, lambda_c):
    """The whole-scan stages: levelled and filtered, or ``surface`` itself without a filter."""
    if not lambda_s and lambda_c is None:
        return surface, ()
    f, levelled = level_scan(surface)
    f, filtered = filter_scan(f, lambda_s, lambda_c)
    return f, levelled + filtered


def fill_holes(heights, max_undefined, path):
    """Fill undefined (NaN) points with the harmonic interpolant: ``(heights, steps, n_filled)``.

    Raises
    ------
    ValueError
        More than ``max_undefined`` (a fraction) of the points are undefined, naming the file
        and ``max_undefined`` (a :class:`sbmf_cli.ParameterError`).
    """
    bad = int(np.count_nonzero(np.isnan(heights)))
    frac = bad / heights.size
    if frac > max_undefined:
        raise ParameterError(
            f"{path}: {100 * frac:.1f} % of the points are undefined (not measured), more "
            f"than {{max_undefined}} = {100 * max_undefined:g} %; fill them yourself, "
            "crop the scan, or raise {max_undefined} (a fraction in [0, 1])",
            "max_undefined",
        )
    if not bad:
        return heights, (), 0
    step = f"filled {bad} undefined points ({100 * frac:.2f} %) with the harmonic interpolant"
    return fill_harmonic(heights), (step,), bad


def level_scan(surface):
    """The least-squares plane removed over the whole scan (before filtering)."""
    return level(surface), ("levelled: least-squares plane removed over the whole scan",)


def filter_scan(surface, lambda_s, lambda_c):
    """ISO 16610-61 L-filter (``lambda_c``, m or ``None``) then S-filter (``lambda_s``, m or 0).

    On the whole levelled scan, before the crop. ``ValueError`` (from the filters) for a cut-off
    out of range.
    """
    steps = []
    if lambda_c is not None:
        surface = l_filter(surface, lambda_c)
        steps.append(
            f"L-filter (ISO 16610-61 Gaussian), lambda_c = {lambda_c * 1e6:.4g} um: "
            "longer wavelengths removed"
        )
    if lambda_s:
        surface = s_filter(surface, lambda_s)
        steps.append(
            f"S-filter (ISO 16610-61 Gaussian), lambda_s = {lambda_s * 1e6:.4g} um: "
            "shorter wavelengths removed (50 % amplitude at lambda_s)"
        )
    return surface, tuple(steps)


def check_filter(surface, lambda_s, lambda_c):
    """Refuse the cut-offs that :func:`filter_scan` would refuse on ``surface``, filtering nothing.

    The plan checks them before any stage runs. ``ValueError`` (the filters' own check) for a
    ``lambda_c`` (if given) or a ``lambda_s`` (if not 0) outside the range the scan allows.
    """
    if lambda_c is not None:
        check_cutoff("lambda_c", lambda_c, surface)
    if lambda_s:
        check_cutoff("lambda_s", lambda_s, surface)


def crop_resample(surface, side, m, lambda_s):
    """The centred ``side`` square onto ``m x m`` square elements.

    A scan whose pixel is coarser than the element is interpolated band-limited (only after an
    S-filter, ``lambda_s > 0``: then the scan is its cosine series); otherwise the elements are
    area averages of the pixels.
    """
    steps = []
    lx, ly = surface.size
    if not (math.isclose(lx, side, rel_tol=1e-9) and math.isclose(ly, side, rel_tol=1e-9)):
        steps.append(
            f"cropped from {lx * 1e6:.4g} x {ly * 1e6:.4g} um to the centred "
            f"{side * 1e6:.4g} x {side * 1e6:.4g} um square"
        )
    if not math.isclose(surface.dx, surface.dy, rel_tol=SQUARE_PIXEL_RTOL):
        steps.append(
            f"non-square pixels {surface.dx * 1e6:.4g} x {surface.dy * 1e6:.4g} um resampled to "
            "square elements (area average)"
        )
    nx, ny = surface.shape
    if lambda_s and max(surface.dx, surface.dy) > side / m * (1 + 1e-9):
        out = band_limited_resample(surface, side, m)
        steps.append(
            f"interpolated (band-limited: exact cell means of the S-filtered scan's cosine "
            f"series) from {nx} x {ny} points of {surface.dx * 1e6:.4g} x "
            f"{surface.dy * 1e6:.4g} um to {m} x {m} ({side / m * 1e6:.4g} um square elements)"
        )
        return out, tuple(steps)
    out = area_resample(surface, side, m)
    if out is not surface:
        steps.append(
            f"area-averaged from {nx} x {ny} points to {m} x {m} "
            f"({side / m * 1e6:.4g} um square elements)"
        )
    return out, tuple(steps)


def level_patch(surface, what="the patch"):
    """The least-squares plane ``a + b x + c y`` removed over the prepared patch."""
    return level(surface), (f"levelled: least-squares plane a + b x + c y removed over {what}",)
