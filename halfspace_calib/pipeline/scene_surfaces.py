"""One loader for a scene's surfaces: the solver grid and the measured grid from one call.

:func:`load_scene_surfaces` is what the sweeps and every effect use. For measured files it
applies the policy of ``docs/measured_surfaces.md``:

1. read the file (:func:`halfspace_calib.topography.read_raw`): instrument files bring their own
   height unit and lateral size; plain files need ``unit`` and ``size`` (or a text header that
   gives them);
2. undefined points: counted; filled with the harmonic interpolant
   (:func:`~halfspace_calib.topography.fill_harmonic`) when their fraction is at most
   ``max_undefined``, refused above;
3. filter: the scan is levelled and filtered with the ISO 16610-61 areal Gaussian S-filter of
   nesting index ``lambda_s`` (the short-wavelength cut-off of the calibration; default
   :func:`default_lambda_s`) and, if asked, the L-filter ``lambda_c``
   (:mod:`halfspace_calib.topography.filters`);
4. crop: both files to the largest common square (or ``crop_size``), centred on each scan;
5. resample: the square patch is area-averaged onto square elements (exact integration of the
   piecewise-constant pixels, :func:`area_resample`); non-square pixels end as square elements;
   the default grid resolves ``lambda_s`` with :data:`ELEMENTS_PER_LAMBDA_S` elements. A scan
   whose pixel is coarser than the element (two instruments: the coarser scan of the pair) is
   S-filtered and so band-limited: its elements are the exact cell means of the filter's own
   cosine series (:func:`band_limited_resample`), so the grid is not capped by its pixel;
6. level: the least-squares plane over the patch is removed;
7. plausibility: ``Rq`` of each levelled patch in :data:`RQ_RANGE`, the element edge between
   :data:`ELEMENT_PER_PIXEL` times the scan's coarser pixel pitch, the grid within memory;
   a grid with fewer than :data:`ELEMENTS_PER_LAMBDA_S` elements per ``lambda_s`` and a patch
   fewer than :data:`MIN_PATCH_LAMBDA_S` ``lambda_s`` across are warned.

Each step is recorded in a :class:`FileRecord` (the parameter file's provenance).
"""

from __future__ import annotations

import functools
import math
import os
from dataclasses import asdict, dataclass

from sbmf_cli import ParameterError

from .. import topography as _surf
from ..contact.normal import estimate_memory
from ..topography import chain
from ..topography.chain import SQUARE_PIXEL_RTOL
from ..topography.resample import area_resample, band_limited_resample
from ..topography.synthesis import measured_surfaces
from .length_scale import (
    ELEMENTS_PER_LAMBDA_S,
    ISO_NESTING_INDICES,
    ISO_SAMPLING_RATIO,
    MIN_ELEMENTS_PER_LAMBDA_S,
    MIN_PATCH_LAMBDA_S,
    check_lambda_s,
    check_patch_size,
    default_lambda_s,
)

__all__ = [
    "MAX_UNDEFINED",
    "RQ_RANGE",
    "ELEMENT_PER_PIXEL",
    "SQUARE_PIXEL_RTOL",
    "SYNTHETIC_GRID",
    "MAX_DEFAULT_GRID",
    "MAX_MEMORY",
    "ISO_NESTING_INDICES",
    "ISO_SAMPLING_RATIO",
    "ELEMENTS_PER_LAMBDA_S",
    "MIN_ELEMENTS_PER_LAMBDA_S",
    "MIN_PATCH_LAMBDA_S",
    "FileRecord",
    "SceneSurfaces",
    "area_resample",
    "band_limited_resample",
    "check_memory",
    "default_lambda_s",
    "load_scene_surfaces",
]

#: default largest fraction of undefined points that is filled (above: refused)
MAX_UNDEFINED = 0.05
#: plausible areal Rq of a metal surface (m); outside: most likely a wrong height unit
RQ_RANGE = (1e-9, 1e-3)
#: allowed element edge / coarser pixel pitch of a scan: below 0.5 the solver would invent
#: detail the scan does not hold; above 64 it averages the roughness away
ELEMENT_PER_PIXEL = (0.5, 64.0)
#: solver grid of synthetic scenes
SYNTHETIC_GRID = 128
#: largest grid the default for measured files picks (the time budget: about 1 min per
#: calibration on one core with the isolated boundary it was set for; the mirror boundary
#: costs 1.5-3.9x less, see docs/measured_surfaces.md)
MAX_DEFAULT_GRID = 256
#: memory limit of one normal solve (bytes), as :func:`halfspace_calib.contact.normal.solve_normal`
MAX_MEMORY = 8 * 2**30


@dataclass(frozen=True)
class FileRecord:
    """What was read from one measured file and what was done to it (SI units).

    Attributes
    ----------
    role : str
        ``"workpiece"`` or ``"tool"``.
    path, sha256, format, layout : str
        The file, its SHA-256, the instrument format (reader) and the layout.
    unit, unit_source : str
        Height unit and where it came from (``"file"``, ``"file header"``, ``"option"``).
    native_shape : tuple of int
        Points of the scan ``(nx, ny)``.
    native_size : tuple of float
        Physical size of the scan ``(Lx, Ly)`` in m.
    pitch : tuple of float
        Pixel pitch ``(dx, dy)`` in m.
    undefined_points : int
        Undefined (unmeasured) points in the scan.
    undefined_fraction : float
        Their fraction of all points.
    steps : tuple of str
        What was done, in order (fill, crop, resample, level), in words.
    crop_size : float
        Edge of the square patch used (m).
    rq_patch : float
        ``Rq`` of the levelled patch on the measured grid (m); the solver grid's when the
        measured grid is the solver grid (no inclined effect).
    rq_scan : float
        ``Rq`` of the whole scan, levelled, at its own sampling (m): against ``rq_patch`` it
        shows how much roughness the crop and the element size leave out.
    rq_filtered : float
        ``Rq`` of the whole scan, levelled and filtered (``lambda_s``, ``lambda_c``), at its
        own sampling (m): against ``rq_scan``, the roughness below the cut-off.
    """

    role: str
    path: str
    sha256: str
    format: str
    layout: str
    unit: str
    unit_source: str
    native_shape: tuple
    native_size: tuple
    pitch: tuple
    undefined_points: int
    undefined_fraction: float
    steps: tuple
    crop_size: float
    rq_patch: float
    rq_scan: float
    rq_filtered: float = math.nan

    def as_dict(self):
        """JSON-ready dict."""
        d = asdict(self)
        for k in ("native_shape", "native_size", "pitch", "steps"):
            d[k] = list(d[k])
        return d


@dataclass(frozen=True)
class SceneSurfaces:
    """A scene's surfaces on the solver grid and (for measured files) on the measured grid.

    ``measured_*`` are the prepared fine maps (``grid * block`` points a side) whose block
    averages are the solver surfaces; ``None`` for synthetic surfaces unless
    ``Scene.measured_n`` asked for them. ``lambda_s`` / ``lambda_c`` are the filters' nesting
    indices applied to the files (m; ``0.0`` / ``None``: none), ``lambda_s_source`` says where
    ``lambda_s`` came from, ``notes`` are warnings for the user (grid coarse for ``lambda_s``, patch
    fewer than :data:`MIN_PATCH_LAMBDA_S` ``lambda_s`` across).
    """

    workpiece: object
    tool: object
    measured_workpiece: object
    measured_tool: object
    block: int
    grid: int
    files: tuple
    lambda_s: float | None = None
    lambda_s_source: str = ""
    lambda_c: float | None = None
    notes: tuple = ()

    def records(self):
        """The file records as JSON-ready dicts."""
        return [f.as_dict() for f in self.files]

    def scale_record(self):
        """The calibration's length scales (params.json provenance): cut-offs, grid, element."""
        e = float(self.workpiece.dx)
        lam = self.lambda_s or None
        return {
            "lambda_s": lam,
            "lambda_s_source": self.lambda_s_source,
            "lambda_c": self.lambda_c,
            "filter": "ISO 16610-61 areal Gaussian" if (lam or self.lambda_c) else None,
            "grid": self.grid,
            "element": e,
            "elements_per_lambda_s": lam / e if lam else None,
            "notes": list(self.notes),
        }


def check_memory(grid, boundary, name="grid"):
    """``ValueError`` naming ``name`` if a ``grid x grid`` normal solve needs over :data:`MAX_MEMORY`.

    ``boundary``: the solve's boundary (or ``True`` / ``False`` for periodic / isolated), as
    :func:`~halfspace_calib.contact.normal.estimate_memory` takes it.
    """
    need = estimate_memory((grid, grid), boundary)
    if need > MAX_MEMORY:
        what = boundary if isinstance(boundary, str) else ("periodic" if boundary else "isolated")
        raise ValueError(
            f"{name}={grid} needs about {need / 2**30:.1f} GiB per normal solve "
            f"(boundary {what}), more than the {MAX_MEMORY / 2**30:.0f} GiB limit; "
            "use a smaller grid"
        )


# ----------------------------------------------------------------------------- reading
def _file_key(scene, role):
    """The cache key of a role's file: ``(path, modification stamp, role, unit, size, max_undefined)``."""
    path = getattr(scene, role)
    unit = getattr(scene, f"{role}_unit") or scene.unit
    try:
        stamp = os.stat(path).st_mtime_ns
    except OSError:
        stamp = None
    return str(path), stamp, role, unit, scene.size, scene.max_undefined


def _read(scene, role):
    """Read one file: ``(Surface with holes filled, steps done)``; cached per file and options."""
    return _read_cached(*_file_key(scene, role))


@functools.lru_cache(maxsize=2)  # workpiece and tool
def _read_cached(path, stamp, role, unit, size, max_undefined):
    """:func:`_read` for hashable arguments (the resolution check reads the files again)."""
    unit_opt = f"{{{role}_unit}} or {{unit}}"
    unit_names = (f"{role}_unit", "unit")
    try:
        h, dx, dy, prov = _read_sized(path, unit, size)
    except _surf.UnitRequired:
        raise ParameterError(
            f"{path}: a plain file does not say its height unit: give {unit_opt} (m, mm, um, nm)",
            *unit_names,
        ) from None
    except _surf.UnitContradiction as exc:
        raise ParameterError(f"{exc} (the option is {unit_opt})", *unit_names) from None
    except _surf.SizeRequired:
        raise ParameterError(
            f"{path}: a plain file does not say its size: give {{size}} (LX [LY] in m)", "size"
        ) from None
    except OSError as exc:
        raise ValueError(f"{path}: cannot read the file ({exc.strerror or exc})") from None
    h, steps, bad = chain.fill_holes(h, max_undefined, path)
    prov["undefined_points"] = bad
    s = _surf.Surface(h, dx, dy, provenance=prov, periodic=False)
    prov["rq_scan"] = _surf.rq(_surf.level(s))
    s = _surf.Surface(h, dx, dy, provenance=prov, periodic=False)
    return s, steps


def _read_sized(path, unit, size):
    """:func:`~halfspace_calib.topography.read_raw`; ``size`` only for a file without its own."""
    try:
        return _surf.read_raw(path, unit=unit)
    except _surf.SizeRequired:
        if size is None:
            raise
        return _surf.read_raw(path, unit=unit, size=size)


@functools.lru_cache(maxsize=4)
def _filtered_cached(path, stamp, role, unit, size, max_undefined, lambda_s, lambda_c):
    """The read scan levelled, then L- and S-filtered (on the whole scan, before the crop)."""
    s, steps = _read_cached(path, stamp, role, unit, size, max_undefined)
    if not lambda_s and lambda_c is None:
        return s, steps
    f, levelled = chain.level_scan(s)
    try:
        f, filtered = chain.filter_scan(f, lambda_s, lambda_c)
    except ValueError as exc:
        raise ParameterError(
            f"{path}: {exc} ({{lambda_s}} / {{lambda_c}})", "lambda_s", "lambda_c"
        ) from None
    return f, steps + levelled + filtered


def _default_grid(side, pitches, inclined, lambda_s=None):
    """The default solver grid of measured files.

    With an S-filter: :data:`ELEMENTS_PER_LAMBDA_S` elements per ``lambda_s`` (a multiple of 8),
    at most :data:`MAX_DEFAULT_GRID`; not capped by the scans' pixel, because the filtered scans
    are band-limited and a scan coarser than the element is interpolated exactly
    (:func:`band_limited_resample`), except with the inclined effect, whose patch planes need
    two measured points per element edge. Without a filter: the native sampling on the common
    square (the coarser scan's pixel), at most :data:`MAX_DEFAULT_GRID`.
    """
    native = int(side / max(pitches) * (1 + 1e-9))
    if inclined:
        native //= 2  # two measured points per element edge for the patch planes
    n = native
    if lambda_s:
        n = 8 * math.ceil(ELEMENTS_PER_LAMBDA_S * side / lambda_s / 8 - 1e-9)
        if inclined:
            n = min(native, n)
    return max(8, min(n, MAX_DEFAULT_GRID))


def _check_rq(path, role, rq):
    lo, hi = RQ_RANGE
    if not lo <= rq <= hi:
        hint = "too small" if rq < lo else "too large"
        raise ParameterError(
            f"{path}: Rq = {rq:.3g} m (levelled scan) is {hint} for a metal surface (plausible: "
            f"{lo:g} .. {hi:g} m); the height unit is most likely wrong: check {{{role}_unit}} / "
            "{unit} (m, mm, um, nm) or the file",
            f"{role}_unit",
            "unit",
        )


def _check_element(path, element, pitch, grid, lambda_s=0.0):
    """Refuse an element far from the scan's pixel (``ParameterError`` naming ``grid``).

    With an S-filter the scan is band-limited and may be interpolated below its pixel
    (:func:`band_limited_resample`), down to ``lambda_s`` / (2 :data:`ELEMENTS_PER_LAMBDA_S`):
    one grid doubling beyond the default rule, for a convergence check.
    """
    lo, hi = ELEMENT_PER_PIXEL
    p = max(pitch)
    if lambda_s:
        lo = min(lo, lambda_s / (2 * ELEMENTS_PER_LAMBDA_S) / p)
    r = element / p
    if not lo * (1 - 1e-9) <= r <= hi:
        raise ParameterError(
            f"{path}: grid={grid} gives elements of {element:.3g} m, {r:.3g} times the scan's "
            f"pixel pitch {p:.3g} m (allowed {lo:.3g} .. {hi:g}"
            + (
                f"; below 0.5 down to lambda_s / {2 * ELEMENTS_PER_LAMBDA_S}, the filtered "
                "scan being band-limited"
                if lambda_s
                else ""
            )
            + "); choose {grid} so that the element is close to the scan's sampling (or check "
            "{size}, {lambda_s})",
            "grid",
            "size",
            "lambda_s",
        )


def load_scene_surfaces(scene, *, grid=None, check_sampling=True):
    """The scene's workpiece and tool on the solver grid and, for files, on the measured grid.

    Parameters
    ----------
    scene : Scene
        Its ``workpiece``/``tool`` (paths or ``None`` for synthetic), units, ``size``,
        ``crop_size``, ``max_undefined``, ``grid`` (``None``: derived from the scan, see
        :func:`_default_grid`) and ``effects`` (``"inclined"`` needs the measured grid).
    grid : int, optional
        Override the scene's grid (the resolution check runs at half of it).
    check_sampling : bool
        Refuse an element edge outside :data:`ELEMENT_PER_PIXEL` times the pixel pitch (off
        for the resolution check, which coarsens on purpose).

    Returns
    -------
    SceneSurfaces

    Raises
    ------
    ValueError
        Bad input, naming the file and the option: unreadable file, missing unit or size,
        too many undefined points, implausible roughness or element size, too much memory.
    """
    n = scene.grid if grid is None else grid
    roles = [r for r in ("workpiece", "tool") if getattr(scene, r) is not None]
    inclined = "inclined" in scene.effects
    if not roles:
        return _synthetic(scene, n, inclined)
    if inclined and len(roles) == 1:
        missing = "tool" if roles == ["workpiece"] else "workpiece"
        raise ValueError(
            f"the inclined effect needs both surfaces measured: give the {missing} as a file "
            "too (a synthetic map has no measured points of its own)"
        )
    raw = {r: _read(scene, r) for r in roles}
    if scene.size is not None and all(
        s.provenance["size_source"] != "option" for s, _ in raw.values()
    ):
        raise ParameterError(
            "{size} applies to plain files without their own size; the files carry theirs "
            f"({', '.join(str(getattr(scene, r)) for r in roles)})",
            "size",
        )
    sides = [v for s, _ in raw.values() for v in s.size]
    side = min(sides)
    if scene.crop_size is not None:
        if scene.crop_size > side * (1 + 1e-9):
            raise ParameterError(
                f"{{crop_size}} {scene.crop_size:g} m exceeds the largest common square of the "
                f"files, {side:g} m",
                "crop_size",
            )
        side = float(scene.crop_size)
    pitches = [v for s, _ in raw.values() for v in (s.dx, s.dy)]
    lam, lam_source = scene.lambda_s, "option"
    if lam is None:
        lam = default_lambda_s(side, max(pitches), MAX_DEFAULT_GRID)
        lam_source = (
            f"default: smallest ISO 25178-3 nesting index >= {ISO_SAMPLING_RATIO:g} pixel "
            f"pitches and >= {ELEMENTS_PER_LAMBDA_S} elements of the {side:.4g} m square at "
            f"grid {MAX_DEFAULT_GRID}"
        )
        if lam > side * (1 + 1e-9):  # e.g. a scan of millimetre pixels with a 0.1 mm scan
            coarse = max(raw.values(), key=lambda v: max(v[0].dx, v[0].dy))[0]
            raise ParameterError(
                f"{coarse.provenance['path']} has pixels of {max(coarse.dx, coarse.dy):.3g} m: "
                f"the default lambda_s (>= {ISO_SAMPLING_RATIO:g} of its pixels) is {lam:.3g} m, "
                f"more than the files' common square of {side:.3g} m, so the scans cannot be "
                "paired at the coarser one's resolution; give {lambda_s} (m, at least 2 pixel "
                "pitches of each file and at most the common square) or a scan of finer pixels",
                "lambda_s",
            )
    elif not lam:
        lam, lam_source = 0.0, "option: no S-filter"
    read = {r: _filtered(scene, r, lam) for r in roles}
    if n is None:
        n = _default_grid(side, pitches, inclined, lam)
    check_memory(n, scene.boundary)
    element = side / n
    notes = ()
    if check_sampling:  # not for the resolution check's half grid
        notes = check_lambda_s(lam, element, n, side) + check_patch_size(side, lam)
    block = max(1, min(int(element / max(s.dx, s.dy) + 1e-9) for s, _ in read.values()))
    if inclined and block < 2:
        raise ParameterError(
            f"the inclined effect needs >= 2 measured points per element edge; grid={n} "
            f"gives elements of {element:.3g} m on scans sampled at {max(pitches):.3g} m: use "
            f"{{grid}} <= {int(side / max(pitches)) // 2}",
            "grid",
        )
    if not inclined:
        block = 1
    fine, records = {}, []
    for role, (s, steps) in read.items():
        if check_sampling:
            _check_element(s.provenance["path"], element, (s.dx, s.dy), n, lam)
        lx, ly = s.size
        r, resampled = chain.crop_resample(s, side, n * block, lam)
        r, levelled = chain.level_patch(r)
        steps = steps + resampled + levelled
        rq = _surf.rq(r)
        _check_rq(s.provenance["path"], role, s.provenance["rq_scan"])
        rq_filtered = _surf.rq(_surf.level(s))  # the whole scan as it is resampled
        fine[role] = r
        p = s.provenance
        records.append(
            FileRecord(
                role=role,
                path=p["path"],
                sha256=p["sha256"],
                format=p["format"],
                layout=p["layout"],
                unit=str(p["unit"]),
                unit_source=p["unit_source"],
                native_shape=tuple(p["shape"]),
                native_size=(float(lx), float(ly)),
                pitch=(float(s.dx), float(s.dy)),
                undefined_points=int(p["undefined_points"]),
                undefined_fraction=p["undefined_points"] / (s.shape[0] * s.shape[1]),
                steps=tuple(steps),
                crop_size=float(side),
                rq_patch=rq,
                rq_scan=float(p["rq_scan"]),
                rq_filtered=float(rq_filtered),
            )
        )
    solver = {k: _surf.block_average(v, n) if block > 1 else v for k, v in fine.items()}
    for role in ("workpiece", "tool"):
        if role not in solver:  # a synthetic partner on the file's patch
            solver[role] = _synthetic_one(scene, role, n, side)
            fine[role] = None
    return SceneSurfaces(
        solver["workpiece"],
        solver["tool"],
        fine["workpiece"] if inclined else None,
        fine["tool"] if inclined else None,
        block,
        n,
        tuple(records),
        lambda_s=lam,
        lambda_s_source=lam_source,
        lambda_c=scene.lambda_c,
        notes=notes,
    )


def _filtered(scene, role, lambda_s):
    """:func:`_read`, levelled and filtered with ``lambda_s`` and ``scene.lambda_c``."""
    return _filtered_cached(*_file_key(scene, role), lambda_s, scene.lambda_c)


def _synthetic_one(scene, role, n, size, measured_n=None):
    if role == "workpiece":
        return _surf.dc04_edt_like(n, size=size, seed=scene.seed_workpiece, measured_n=measured_n)
    return _surf.tool_like(
        n, rough=scene.rough_tool, size=size, seed=scene.seed_tool, measured_n=measured_n
    )


def _synthetic(scene, n, inclined):
    """Both surfaces synthetic (Table 1); the measured grid of the inclined effect if asked."""
    check_memory(n, scene.boundary)
    wp = _synthetic_one(scene, "workpiece", n, _surf.PAPER_SIZE, scene.measured_n)
    tl = _synthetic_one(scene, "tool", n, _surf.PAPER_SIZE, scene.measured_n)
    mw = mt = None
    block = 1
    if inclined:
        fine = scene.measured_n if scene.measured_n is not None else 4 * n
        if fine % n or fine // n < 2:
            raise ValueError(
                f"measured_n must be a multiple >= 2 of grid={n} for the inclined "
                f"patches, got {scene.measured_n!r}"
            )
        block = fine // n
        mw, mt = measured_surfaces(
            n,
            block,
            rough_tool=scene.rough_tool,
            seed_workpiece=scene.seed_workpiece,
            seed_tool=scene.seed_tool,
        )
    return SceneSurfaces(wp, tl, mw, mt, block, n, ())
