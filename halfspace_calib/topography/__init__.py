"""Rough surfaces (Sec. 3.1): the :class:`Surface` type, roughness metrics and PSD, synthesis, files.

- :mod:`.surface`: :class:`Surface`, roughness (``Ra``, ``Rq``, ...), PSD, levelling, cropping,
  block averaging
- :mod:`.synthesis`: the self-affine generator, the paper's presets (Table 1) and the measured
  maps of the geometric study
- :mod:`.files`: reading plain and instrument files, filling undefined points, writing; a file
  whose unit or size is missing or contradicted raises one of :class:`FileScaleError`'s kinds
- :mod:`.filters`: the ISO 16610-61 Gaussian S- and L-filters
- :mod:`.resample`: area averaging and band-limited interpolation onto square elements
- :mod:`.chain`: the preparation of a measured surface as a chain of stages (fill holes, level,
  filter, crop and resample, level), each returning the surface and its lines of provenance
"""

from . import chain
from .files import (
    FileScaleError,
    SizeContradiction,
    SizeRequired,
    UnitContradiction,
    UnitRequired,
    fill_harmonic,
    read_raw,
    read_surface,
    write_surface,
)
from .surface import (
    Roughness,
    Surface,
    block_average,
    crop,
    level,
    psd_radial,
    ra,
    rku,
    rms_slope,
    roughness,
    rq,
    rsk,
)
from .synthesis import (
    PAPER_SIZE,
    RA_RQ_RANGE,
    TABLE1,
    dc04_edt_like,
    measured_surfaces,
    self_affine,
    tool_like,
)

__all__ = [
    "chain",
    "PAPER_SIZE",
    "RA_RQ_RANGE",
    "TABLE1",
    "FileScaleError",
    "SizeContradiction",
    "SizeRequired",
    "UnitContradiction",
    "UnitRequired",
    "Roughness",
    "Surface",
    "block_average",
    "crop",
    "dc04_edt_like",
    "fill_harmonic",
    "level",
    "measured_surfaces",
    "psd_radial",
    "ra",
    "read_raw",
    "read_surface",
    "rku",
    "rms_slope",
    "roughness",
    "rq",
    "rsk",
    "self_affine",
    "tool_like",
    "write_surface",
]
