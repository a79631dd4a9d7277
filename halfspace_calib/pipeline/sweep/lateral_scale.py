"""Plausible lateral scales of a measured surface: the field's size and its RMS slope (issue 38).

The height unit of a file is checked through ``Rq`` (:data:`~.surface_plan.RQ_RANGE`). Its lateral
scale is checked here, in two places:

1. **before any sweep** (:func:`check_scan`, called by the plan of a scene's surfaces for every
   file as read): the field (the scan's longer edge) must lie in :data:`FIELD_RANGE` and the RMS
   slope of the levelled scan at its own pixel (ISO 25178-2 ``Sdq``, :func:`scan_slope`) in
   :data:`SLOPE_RANGE`. A size typed in m instead of mm makes a scan 1000x wider and 1000x
   flatter; a header whose pixel is read in the wrong unit can make it 160 m wide. Such a file
   is refused (exit 2), naming its size, its slope and the likely mistake;
2. **after the sweeps** (:func:`full_contact_problem`, one of
   :meth:`~.calibration.Calibration.problems`): full contact (``alpha >=``
   :data:`FULL_CONTACT_ALPHA`) at the first load level, when that level is below
   :data:`FIRST_LEVEL_P` ``H``, fails the run (exit 1, ``params.failed.json``) with the same
   words. A scan that passed the first check can still be this flat at the solver's scale (the
   S-filter removes the short, steep wavelengths); the law would be Tresca's from the lowest
   pressure on, from a typo.

Both are lifted for a pair the user states is that smooth (``Scene.smooth_pair``, the CLI's
``--smooth-pair``): the slope's lower bound and the full-contact failure, not the field's range.

**The bounds** (docs/measured_surfaces.md, "Plausible lateral scales", has the sources):

- The five shipped instrument files span fields of 10 um (matrix-3, AFM) to 151 mm (sur-3) and
  RMS slopes of 0.0018 (metropro-1, a nanometre-smooth optical flat) to 0.17 (matrix-3); the
  synthetic presets 0.010-0.099 on 2.11 mm. :data:`FIELD_RANGE` ``(1 um, 1 m)`` leaves the
  10 um AFM scan and the 151 mm scan a factor 10 and 6.6 inside: no roughness measurement of a
  forming contact is wider than a metre or narrower than a micrometre.
- The slope's floor, ``5e-4``, is set by what a scan 1000x too wide looks like: optical
  instruments return no height beyond about 30 degrees of local slope (``tan`` 0.58), so a
  measured scan has ``Sdq`` below about 0.5 and, 1000x too wide, below ``5e-4``. The smoothest
  shipped file stays 3.7x above the floor (a floor of 0.002 would refuse it), a polished surface
  of ``Sdq`` 0.2 degrees (0.0035) 7x. The ceiling, 3 (``tan`` 72 degrees, the acceptance
  angle of an NA 0.95 objective), is 18x the steepest file; a scan beyond it is most likely
  1000x too narrow.
- A lateral scaling keeps every ratio of a scan, so no check of one file can tell a size 1000x
  too large from a smoother surface at a coarser pixel but by these absolute ranges: a scan
  steeper than about 0.5 at its own pixel (an AFM scan can be) passes the floor 1000x too wide
  and, unless its contact is full at the first level, calibrates (measured in
  docs/measured_surfaces.md: matrix-3's heights x 4 as a 10 mm scan, exit 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sbmf_cli import ParameterError, Worded

from ... import topography as _surf

__all__ = [
    "FIELD_RANGE",
    "SLOPE_RANGE",
    "FULL_CONTACT_ALPHA",
    "FIRST_LEVEL_P",
    "ScanScale",
    "scan_slope",
    "check_scan",
    "full_contact_problem",
    "scale_record",
]

#: plausible field of a roughness measurement (m): the scan's longer edge
FIELD_RANGE = (1e-6, 1.0)
#: plausible RMS slope (ISO 25178-2 Sdq) of a levelled metal scan at its own pixel
SLOPE_RANGE = (5e-4, 3.0)
#: a first load level with alpha at or above this is in full contact
FULL_CONTACT_ALPHA = 0.95
#: full contact at a first level below this fraction of H fails the run (unless smooth_pair)
FIRST_LEVEL_P = 0.05
#: the typical RMS slope a suggested correction aims at (the shipped files' geometric middle)
_TYPICAL_SLOPE = 0.02
_PY = {"smooth_pair": "smooth_pair=True"}


@dataclass(frozen=True)
class ScanScale:
    """The lateral scale of one surface: what the checks read and name (SI units).

    Attributes
    ----------
    label : str
        The role and the file (or ``"synthetic"``), as the messages name it.
    role : str
        ``"workpiece"`` or ``"tool"``.
    size : tuple of float
        ``(Lx, Ly)`` of the scan (m).
    slope : float
        RMS slope of the levelled scan at its own pixel (:func:`scan_slope`).
    """

    label: str
    role: str
    size: tuple
    slope: float

    @property
    def field(self):
        """The scan's longer edge (m)."""
        return max(self.size)

    def words(self):
        """``"workpiece a.txt: 160 x 120 m, RMS slope 1.2e-07"``."""
        lx, ly = self.size
        return f"{self.label}: {_length(lx, ly)}, RMS slope {self.slope:.3g}"

    def implausible(self, smooth_pair=False):
        """What is out of range (``"field"``, ``"slope"``), ``()`` if nothing."""
        out = ()
        if not FIELD_RANGE[0] <= self.field <= FIELD_RANGE[1]:
            out += ("field",)
        if self.slope > SLOPE_RANGE[1] or (self.slope < SLOPE_RANGE[0] and not smooth_pair):
            out += ("slope",)
        return out

    def factor(self, flat=False):
        """The power of 1000 by which the size is most likely off (> 1: too wide, < 1: too narrow).

        ``flat``: the scan is known to be too flat (its contact is full at the first level).
        """
        too_wide = flat or self.field > FIELD_RANGE[1] or self.slope < SLOPE_RANGE[0]
        too_narrow = self.field < FIELD_RANGE[0] or self.slope > SLOPE_RANGE[1]
        n = round(math.log10(_TYPICAL_SLOPE / max(self.slope, 1e-300)) / 3)
        if too_wide:
            n = max(n, 1)
        elif too_narrow:
            n = min(n, -1)
        return 1000.0**n


def _length(lx, ly):
    """``"160 x 120 m"`` in the unit that reads best (m, mm, um)."""
    big = max(lx, ly)
    unit, f = ("m", 1.0) if big >= 0.1 else ("mm", 1e3) if big >= 1e-4 else ("um", 1e6)
    return f"{lx * f:.4g} x {ly * f:.4g} {unit}"


def scan_slope(surface):
    """RMS slope of ``surface`` levelled (ISO 25178-2 ``Sdq``; central differences at its pixel)."""
    return _surf.rms_slope(_surf.level(surface))


def _mistake(scale, flat=False):
    """``(text, names)``: the likely unit mistake of ``scale`` in words, and what corrects it.

    ``flat``: the contact says the surfaces are too flat (:func:`full_contact_problem`); the
    scan itself may look plausible, so no factor is guessed.
    """
    k = scale.factor(flat)
    role = scale.role
    lx, ly = scale.size
    wide = k > 1
    times = f"{max(k, 1 / k):.0f}x " if scale.implausible() else ""
    text = (
        f"most likely a lateral size {times}too {'large' if wide else 'small'} (a size typed in "
        f"{'m instead of mm' if wide else 'mm instead of um'}, or a header whose pixel is read in "
        f"the wrong unit), or heights in the wrong unit"
    )
    if times:
        text += (
            f"; with the size {'divided' if wide else 'multiplied'} by {times.strip()[:-1]} the "
            f"scan would be {_length(lx / k, ly / k)} with RMS slope {scale.slope * k:.3g}"
        )
    text += (
        f". Correct the size with {{{role}_size}} (LX [LY] in m; it overrides the file's own) "
        f"or check the height unit ({{{role}_unit}} / {{unit}})"
    )
    return text, (f"{role}_size", f"{role}_unit", "unit")


def check_scan(scale, smooth_pair=False):
    """Refuse a scan whose field or RMS slope is implausible (``ParameterError``, exit 2).

    The message names the scan's size and slope, the plausible ranges, the likely unit mistake
    and the options that correct it; where only the slope is too small, also ``smooth_pair``,
    which states that the surface is truly that smooth.
    """
    bad = scale.implausible(smooth_pair)
    if not bad:
        return
    mistake, names = _mistake(scale)
    names = list(names)
    text = (
        f"{scale.words()}: implausible for a measured metal surface (plausible: a field of "
        f"{FIELD_RANGE[0]:g} .. {FIELD_RANGE[1]:g} m and an RMS slope of {SLOPE_RANGE[0]:g} .. "
        f"{SLOPE_RANGE[1]:g}); {mistake}"
    )
    if bad == ("slope",) and scale.slope < SLOPE_RANGE[0]:
        text += "; if the surface is truly this smooth, give {smooth_pair}"
        names.append("smooth_pair")
    raise ParameterError(text, *names, python=_PY)


def first_level_full_contact(p, alpha, H):
    """``(p, alpha)`` of the first load level if it is in full contact below ``FIRST_LEVEL_P H``."""
    p, alpha = np.asarray(p, float), np.asarray(alpha, float)
    if not p.size:
        return None
    i = int(np.argmin(p))
    if p[i] < FIRST_LEVEL_P * H and alpha[i] >= FULL_CONTACT_ALPHA:
        return float(p[i]), float(alpha[i])
    return None


def calibration_scales(cal):
    """The :class:`ScanScale` of each surface of a calibration: its files, else its solver maps."""
    scales = [
        ScanScale(f"{f.role} {f.path}", f.role, tuple(f.native_size), f.rms_slope_scan)
        for f in cal.files
    ]
    have = {s.role for s in scales}
    for role, s in cal.sweeps.surfaces.items():
        if role not in have:
            scales.append(ScanScale(f"{role} (synthetic)", role, tuple(s.size), scan_slope(s)))
    return scales


def full_contact_problem(cal):
    """The failure sentence (a :class:`~sbmf_cli.Worded`) of full contact at the first level, or ``""``.

    ``cal``: a :class:`~.calibration.Calibration` (its first-loading sweep, ``scene.H``,
    ``scene.smooth_pair``, its files or surfaces). ``""`` when the first level is not in full
    contact, is at or above :data:`FIRST_LEVEL_P` ``H``, or the pair is stated smooth.
    """
    if cal.scene.smooth_pair:
        return ""
    hit = first_level_full_contact(*cal.sweeps.loading, cal.scene.H)
    if hit is None:
        return ""
    p, alpha = hit
    scales = calibration_scales(cal)
    measured = [s for s in scales if not s.label.endswith("(synthetic)")]
    flattest = min(measured or scales, key=lambda s: s.slope)
    mistake, names = _mistake(flattest, flat=True)
    text = (
        f"full contact at the first load level: alpha = {alpha:.3f} at {p / 1e6:.4g} MPa, below "
        f"{FIRST_LEVEL_P:g} H: the law would be Tresca's from the lowest pressure on. The "
        f"surfaces: {'; '.join(s.words() for s in scales)}. For the flattest, {mistake}; if "
        "the pair is truly this smooth, give {smooth_pair}"
    )
    return Worded(text, *dict.fromkeys((*names, "smooth_pair")), python=_PY)


def scale_record(smooth_pair):
    """The checks' bounds and the user's statement, for the parameter file's provenance."""
    return {
        "field_range": list(FIELD_RANGE),
        "slope_range": list(SLOPE_RANGE),
        "first_level_full_contact": {"alpha": FULL_CONTACT_ALPHA, "p_over_H": FIRST_LEVEL_P},
        "smooth_pair": bool(smooth_pair),
    }
