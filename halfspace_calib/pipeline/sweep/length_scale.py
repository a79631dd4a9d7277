"""The calibration's short-wavelength cut-off ``lambda_s``: its default and the grid it needs.

See docs/measured_surfaces.md: the S-filter's nesting index is a physical parameter of the
calibration (the user's choice, with a default from the scan's sampling and the grid budget);
the grid is a numerical choice that must resolve it with :data:`ELEMENTS_PER_LAMBDA_S` elements.
"""

from __future__ import annotations

import math

__all__ = [
    "ELEMENTS_PER_LAMBDA_S",
    "ISO_NESTING_INDICES",
    "ISO_SAMPLING_RATIO",
    "MIN_ELEMENTS_PER_LAMBDA_S",
    "MIN_PATCH_LAMBDA_S",
    "check_lambda_s",
    "check_patch_size",
    "default_lambda_s",
]

#: the S-filter nesting indices of ISO 25178-3 (m), from which the default ``lambda_s`` is taken
ISO_NESTING_INDICES = tuple(float(f"{v}e{e}") for e in range(-7, -1) for v in (1, 2, 2.5, 5, 8))
#: ISO 25178-3 pairs each S-filter nesting index with a largest sampling distance of about a
#: third of it: the default ``lambda_s`` is at least this many pixel pitches of the scan
ISO_SAMPLING_RATIO = 3.0
#: elements per ``lambda_s`` of the default grid (measured, docs/measured_surfaces.md)
ELEMENTS_PER_LAMBDA_S = 16
#: fewest elements per ``lambda_s`` that sample the filtered surface at all (below: warned)
MIN_ELEMENTS_PER_LAMBDA_S = 2.0
#: smallest patch edge, in ``lambda_s``, that represents a surface: measured
#: (``benchmarks/patch_size.py``, docs/measured_surfaces.md "Patch size"), the smallest patch
#: size at which ``mu_eff`` and ``C1`` of patches of one scan (metropro-1) scatter by at most the
#: resolution check's 10 % (coefficient of variation 9.2 % at 16, 14.7 % at 8, 19.5 % at 4).
#: Necessary, not sufficient: mnt-1 still scatters by 40 % at 32 ``lambda_s``; scans at the
#: Bowden-Tabor limit (``C1`` close to 1) scatter by under 1 % from 4 on.
MIN_PATCH_LAMBDA_S = 16
#: the measured scatter quoted in the warning
PATCH_SCATTER_NOTE = (
    "on patches of one scan, mu_eff and C1 scattered between patches by 15 % (metropro-1) to "
    "72 % (mnt-1) at 8 lambda_s (coefficient of variation; docs/measured_surfaces.md, "
    "'Patch size')"
)


def default_lambda_s(side, pitch, max_grid):
    """The default S-filter nesting index of measured files (m), see docs/measured_surfaces.md.

    The smallest of :data:`ISO_NESTING_INDICES` that is (a) at least
    :data:`ISO_SAMPLING_RATIO` times the scans' coarser pixel pitch ``pitch`` (ISO 25178-3's
    sampling for that nesting index: the scan resolves it) and (b) at least
    ``ELEMENTS_PER_LAMBDA_S * side / max_grid`` (the default grid, at most ``max_grid``,
    resolves it on the ``side`` square: the time budget).
    """
    need = max(ISO_SAMPLING_RATIO * pitch, ELEMENTS_PER_LAMBDA_S * side / max_grid)
    for v in ISO_NESTING_INDICES:
        if v >= need * (1 - 1e-9):
            return float(v)
    return float(need)


def check_lambda_s(lambda_s, element, grid, side):
    """The warning (a note, the run goes on) for a grid coarse for ``lambda_s``.

    Below :data:`MIN_ELEMENTS_PER_LAMBDA_S` the grid does not sample the filtered surface;
    below :data:`ELEMENTS_PER_LAMBDA_S` the contact area is not converged in the grid (measured,
    docs/measured_surfaces.md). Not refused: the run does what was asked, and the resolution
    check says by how much the answer moves.
    """
    if not lambda_s:
        return ()
    k = lambda_s / element
    if k >= ELEMENTS_PER_LAMBDA_S * (1 - 1e-9):
        return ()
    good = 8 * math.ceil(ELEMENTS_PER_LAMBDA_S * side / lambda_s / 8)
    what = (
        "does not sample the filtered surface"
        if k < MIN_ELEMENTS_PER_LAMBDA_S
        else "leaves the contact area unconverged in the grid"
    )
    return (
        f"grid {grid} has {k:.3g} elements per lambda_s = {lambda_s * 1e6:.4g} um, fewer than "
        f"the {ELEMENTS_PER_LAMBDA_S} of the default rule: it {what}; use --grid {good} "
        "or a larger --lambda-s",
    )


def check_patch_size(side, lambda_s):
    """The warning (a note, the run goes on) for a patch too small to represent the surface.

    Below :data:`MIN_PATCH_LAMBDA_S` ``lambda_s`` across, a patch's ``mu_eff`` and ``C1`` are
    one draw of a wide scatter, not the surface's (measured, docs/measured_surfaces.md "Patch
    size"). ``()`` without an S-filter (``lambda_s`` 0).
    """
    if not lambda_s:
        return ()
    k = side / lambda_s
    if k >= MIN_PATCH_LAMBDA_S * (1 - 1e-9):
        return ()
    return (
        f"the patch is {side * 1e6:.4g} um = {k:.3g} lambda_s across, fewer than "
        f"{MIN_PATCH_LAMBDA_S} lambda_s, below which one patch does not represent the surface: "
        f"{PATCH_SCATTER_NOTE}; measure a larger area, or cut a large scan into several "
        "patches with --patches N and read the band over them",
    )
