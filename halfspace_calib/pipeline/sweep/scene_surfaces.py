"""One loader for a scene's surfaces: the solver grid and the measured grid from one call.

:func:`load_scene_surfaces` is what the sweeps and every effect use. It runs in two steps:

1. **plan** (:func:`~.surface_plan.plan_surfaces`): from the scene and its files, every choice
   of the preparation is made once and every check of the input runs, by the policy of
   ``docs/measured_surfaces.md``: the files read with their units and sizes and their
   undefined points filled, the square patch, ``lambda_s`` (and where it came from) and
   ``lambda_c``, the grid and the block of measured points per element; the result is a frozen
   :class:`~.surface_plan.SurfacePlan`;
2. **run** (:func:`run_plan`): each file through the rest of the preparation chain
   (:func:`halfspace_calib.topography.chain.run`) with the plan's parameters: the scan
   levelled and filtered (ISO 16610-61, :mod:`halfspace_calib.topography.filters`), the square
   patch cropped and resampled onto square elements (:func:`area_resample`; a scan whose pixel
   is coarser than the element is S-filtered and so band-limited: its elements are the exact
   cell means of the filter's own cosine series, :func:`band_limited_resample`), the patch
   levelled; synthetic surfaces from their generator.

Each step done to a file is recorded in a :class:`FileRecord` (the parameter file's
provenance), built from the plan and the chain's lines of provenance.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from ... import topography as _surf
from ...topography import chain
from ...topography.chain import SQUARE_PIXEL_RTOL
from ...topography.resample import area_resample, band_limited_resample
from ...topography.synthesis import measured_surfaces
from .length_scale import (
    ELEMENTS_PER_LAMBDA_S,
    ISO_NESTING_INDICES,
    ISO_SAMPLING_RATIO,
    MIN_ELEMENTS_PER_LAMBDA_S,
    MIN_PATCH_LAMBDA_S,
    default_lambda_s,
)
from .surface_plan import (
    ELEMENT_PER_PIXEL,
    MAX_DEFAULT_GRID,
    MAX_MEMORY,
    MAX_UNDEFINED,
    ROLES,
    RQ_RANGE,
    SYNTHETIC_GRID,
    SurfacePlan,
    check_memory,
    plan_surfaces,
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
    "SurfacePlan",
    "area_resample",
    "band_limited_resample",
    "check_memory",
    "default_lambda_s",
    "load_scene_surfaces",
    "plan_surfaces",
    "run_plan",
]


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
        Physical size of the scan ``(Lx, Ly)`` in m, as used: the file's own, or the role's
        size option that overrides it (:attr:`size_source`, :attr:`file_size`).
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
    rms_slope_scan : float
        RMS slope of the whole scan, levelled, at its own sampling (ISO 25178-2 ``Sdq``), which
        the plan checks (:mod:`.lateral_scale`).
    size_source : str
        Where :attr:`native_size` came from: ``"file"``, ``"file header"``, ``"option"`` (the
        scene's ``size`` for a plain file) or ``"override"`` (``<role>_size``).
    file_size : tuple of float or None
        With ``"override"``: the size the file itself carries (m), ``None`` if it has none.
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
    rms_slope_scan: float = math.nan
    size_source: str = "file"
    file_size: tuple | None = None

    def as_dict(self):
        """JSON-ready dict."""
        d = asdict(self)
        for k in ("native_shape", "native_size", "pitch", "steps"):
            d[k] = list(d[k])
        if d["file_size"] is not None:
            d["file_size"] = list(d["file_size"])
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


def load_scene_surfaces(scene, *, grid=None, check_sampling=True):
    """The scene's workpiece and tool on the solver grid and, for files, on the measured grid.

    The plan of the scene (:func:`~.surface_plan.plan_surfaces`), run (:func:`run_plan`).

    Parameters
    ----------
    scene : Scene
        Its ``workpiece``/``tool`` (paths or ``None`` for synthetic), units, ``size``,
        ``crop_size``, ``max_undefined``, ``grid`` (``None``: derived from the scan) and
        ``effects`` (``"inclined"`` needs the measured grid).
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
        too many undefined points, implausible roughness or element size, too much memory;
        all raised by the plan, before any stage of the chain runs.
    """
    plan = plan_surfaces(scene, grid=grid, check_sampling=check_sampling)
    return run_plan(plan)


def run_plan(plan):
    """The surfaces of ``plan``: each file through the preparation chain, synthetic ones generated.

    A role without a file gets the synthetic surface on the file's patch. Decides nothing:
    every parameter comes from the plan (:class:`~.surface_plan.SurfacePlan`).
    """
    if not plan.scans:
        return _run_synthetic(plan)
    fine, records = {}, []
    for scan in plan.scans:
        whole, patch, steps = chain.run(scan.surface, plan.chain, scan.steps)
        fine[scan.role] = patch
        records.append(_file_record(scan.role, whole, patch, steps, plan.side))
    solver = {
        k: _surf.block_average(v, plan.grid) if plan.block > 1 else v for k, v in fine.items()
    }
    for role in ROLES:
        if role not in solver:  # a synthetic partner on the file's patch
            solver[role] = plan.synthetic.surface(role, plan.grid, plan.side)
            fine[role] = None
    return SceneSurfaces(
        solver["workpiece"],
        solver["tool"],
        fine["workpiece"] if plan.measured else None,
        fine["tool"] if plan.measured else None,
        plan.block,
        plan.grid,
        tuple(records),
        lambda_s=plan.lambda_s,
        lambda_s_source=plan.lambda_s_source,
        lambda_c=plan.lambda_c,
        notes=plan.notes,
    )


def _file_record(role, whole, patch, steps, side):
    """The :class:`FileRecord` of one file: what was read (``whole``'s provenance) and done."""
    p = whole.provenance
    lx, ly = whole.size
    return FileRecord(
        role=role,
        path=p["path"],
        sha256=p["sha256"],
        format=p["format"],
        layout=p["layout"],
        unit=str(p["unit"]),
        unit_source=p["unit_source"],
        native_shape=tuple(p["shape"]),
        native_size=(float(lx), float(ly)),
        pitch=(float(whole.dx), float(whole.dy)),
        undefined_points=int(p["undefined_points"]),
        undefined_fraction=p["undefined_points"] / (whole.shape[0] * whole.shape[1]),
        steps=tuple(steps),
        crop_size=float(side),
        rq_patch=_surf.rq(patch),
        rq_scan=float(p["rq_scan"]),
        rq_filtered=float(_surf.rq(_surf.level(whole))),  # the whole scan as it is resampled
        rms_slope_scan=float(p["rms_slope_scan"]),
        size_source=str(p["size_source"]),
        file_size=None if p.get("file_size") is None else tuple(map(float, p["file_size"])),
    )


def _run_synthetic(plan):
    """Both surfaces synthetic (Table 1); the measured grid of the inclined effect if asked."""
    n, gen = plan.grid, plan.synthetic
    wp = gen.surface("workpiece", n, plan.side, gen.measured_n)
    tl = gen.surface("tool", n, plan.side, gen.measured_n)
    mw = mt = None
    if plan.measured:
        mw, mt = measured_surfaces(
            n,
            plan.block,
            rough_tool=gen.rough_tool,
            seed_workpiece=gen.seed_workpiece,
            seed_tool=gen.seed_tool,
        )
    return SceneSurfaces(wp, tl, mw, mt, plan.block, n, ())
