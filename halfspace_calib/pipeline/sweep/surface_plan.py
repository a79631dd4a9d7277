"""The plan of a scene's surfaces: every choice of their preparation, made once before it runs.

:func:`plan_surfaces` reads the scene's files (cached) and decides, by the policy of
``docs/measured_surfaces.md``, before any stage of the chain
(:mod:`halfspace_calib.topography.chain`) runs:

1. the files and how they are read (:class:`Scan`): instrument files bring their own
   height unit and lateral size; plain files need ``unit`` and ``size`` (or a text header that
   gives them); undefined points are filled with the harmonic interpolant
   (:func:`~halfspace_calib.topography.chain.fill_holes`) when their fraction is at most
   ``max_undefined``, refused above;
2. the square patch: the files' largest common square, or ``crop_size``;
3. the filters: the ISO 16610-61 S-filter's nesting index ``lambda_s`` (the short-wavelength
   cut-off of the calibration; default :func:`default_lambda_s`) and where it came from, and,
   if asked, the L-filter ``lambda_c``;
4. the solver grid (``grid``, or :func:`_default_grid`: :data:`ELEMENTS_PER_LAMBDA_S` elements
   per ``lambda_s``) and the block of measured points per element (the inclined effect's
   measured grid is ``grid * block`` points a side);
5. the checks that refuse a plan before any work: each scan's field and RMS slope
   (:func:`~.lateral_scale.check_scan`: a lateral size in the wrong unit), the filters' range on
   each scan, the memory of one normal solve, ``Rq`` of each levelled scan in :data:`RQ_RANGE`,
   the element edge
   between :data:`ELEMENT_PER_PIXEL` times the scan's coarser pixel pitch; and the notes that
   warn (a grid with fewer than :data:`ELEMENTS_PER_LAMBDA_S` elements per ``lambda_s``, a patch
   fewer than :data:`~.length_scale.MIN_PATCH_LAMBDA_S` ``lambda_s`` across).

The result is a frozen :class:`SurfacePlan`. :func:`~.scene_surfaces.run_plan` runs it (the
files through the chain, the synthetic surfaces through their generator);
:meth:`SurfacePlan.with_grid` is the same plan on another grid, its grid-dependent choices and
checks made again (the sample patches are prepared on ``k`` times the patch grid).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
from dataclasses import dataclass, field

from sbmf_cli import ParameterError

from ... import topography as _surf
from ...contact.normal import estimate_memory
from ...topography import chain
from .lateral_scale import ScanScale, check_scan, scan_slope
from .length_scale import (
    ELEMENTS_PER_LAMBDA_S,
    ISO_SAMPLING_RATIO,
    check_lambda_s,
    check_patch_size,
    default_lambda_s,
)

__all__ = [
    "MAX_UNDEFINED",
    "RQ_RANGE",
    "ELEMENT_PER_PIXEL",
    "SYNTHETIC_GRID",
    "MAX_DEFAULT_GRID",
    "MAX_MEMORY",
    "ROLES",
    "Scan",
    "SyntheticSource",
    "SurfacePlan",
    "check_memory",
    "plan_surfaces",
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
#: the two surfaces of a scene, in the order of every plan and record
ROLES = ("workpiece", "tool")


@dataclass(frozen=True)
class Scan:
    """One measured file of a scene: how it was read (the key of the cached read) and what.

    Two scans are equal when they read the same file the same way (``surface`` and ``steps``
    are not compared), so that the chain's whole-scan stages are cached per file.

    Attributes
    ----------
    role : str
        ``"workpiece"`` or ``"tool"``.
    path : str
        The file, as the scene names it.
    stamp : int or None
        Its modification time (ns) when read; a file changed since is read again.
    unit : str or None
        Height unit of the option (the role's or the scene's), for files that have none.
    size : float, tuple or None
        Lateral size of the option (m), for files that have none.
    own_size : float, tuple or None
        The role's size (``<role>_size``, m), which overrides the file's own.
    max_undefined : float
        Largest fraction of undefined points that is filled.
    surface : Surface
        The scan as read, its undefined points filled (``rq_scan`` and ``rms_slope_scan`` in
        its provenance).
    steps : tuple of str
        What was done to it (the fill), in words.
    """

    role: str
    path: str
    stamp: int | None
    unit: str | None
    size: float | tuple | None
    own_size: float | tuple | None
    max_undefined: float
    surface: _surf.Surface = field(compare=False, repr=False)
    steps: tuple = field(compare=False)

    @classmethod
    def read(cls, scene, role):
        """The scene's file of ``role``, read (unit: ``<role>_unit``, else ``unit``; ``<role>_size``)."""
        path = str(getattr(scene, role))
        try:
            stamp = os.stat(path).st_mtime_ns
        except OSError:
            stamp = None
        unit = getattr(scene, f"{role}_unit") or scene.unit
        own = getattr(scene, f"{role}_size")
        key = (role, path, stamp, unit, scene.size, own, scene.max_undefined)
        return cls(*key, *_read_scan(*key))


@dataclass(frozen=True)
class SyntheticSource:
    """The generator of a scene's synthetic surfaces (Table 1): seeds and the tool's roughness."""

    rough_tool: bool
    seed_workpiece: int | None
    seed_tool: int | None
    measured_n: int | None = None

    @classmethod
    def of(cls, scene):
        """The scene's seeds, tool roughness and measured grid."""
        return cls(scene.rough_tool, scene.seed_workpiece, scene.seed_tool, scene.measured_n)

    def surface(self, role, n, size, measured_n=None):
        """The ``role``'s synthetic surface on ``n x n`` elements of a ``size`` square (m)."""
        if role == "workpiece":
            return _surf.dc04_edt_like(
                n, size=size, seed=self.seed_workpiece, measured_n=measured_n
            )
        return _surf.tool_like(
            n, rough=self.rough_tool, size=size, seed=self.seed_tool, measured_n=measured_n
        )


@dataclass(frozen=True)
class SurfacePlan:
    """Every choice of a scene's surface preparation, decided before any of it runs (SI units).

    Attributes
    ----------
    scans : tuple of Scan
        The measured files, in :data:`ROLES` order; ``()``: both surfaces synthetic. A role
        without a file gets the synthetic surface of :attr:`synthetic` on the file's patch.
    side : float
        Edge of the square patch (m): the files' largest common square or ``crop_size``
        (synthetic: the paper's 2.11 mm).
    grid : int
        Solver elements a side.
    block : int
        Measured points per element edge: the measured grid is ``grid * block`` a side.
    measured : bool
        Keep the measured grid (the inclined effect fits its patches on it).
    boundary : str or bool
        The solve's boundary (for the memory of one solve).
    synthetic : SyntheticSource
        The generator of the synthetic surfaces.
    pitch : float or None
        The scans' coarser pixel pitch (m); ``None`` without files.
    lambda_s, lambda_c : float or None
        The S- and L-filters' nesting indices (m; ``0.0`` / ``None``: none; ``None`` without
        files).
    lambda_s_source : str
        Where ``lambda_s`` came from (the option, or the default rule in words).
    check_sampling : bool
        The element edge was checked against the scans' pixel (off for the resolution
        check's half grid, which coarsens on purpose).
    notes : tuple of str
        Warnings for the user (grid coarse for ``lambda_s``, patch small in ``lambda_s``).
    """

    scans: tuple
    side: float
    grid: int
    block: int
    measured: bool
    boundary: str | bool
    synthetic: SyntheticSource
    pitch: float | None = None
    lambda_s: float | None = None
    lambda_s_source: str = ""
    lambda_c: float | None = None
    check_sampling: bool = True
    notes: tuple = ()

    @property
    def element(self):
        """Edge of one solver element (m)."""
        return self.side / self.grid

    @property
    def chain(self):
        """The chain's plan of each file: the filters, the square, ``grid * block`` elements."""
        return chain.ChainPlan(
            self.lambda_s or 0.0, self.lambda_c, self.side, self.grid * self.block
        )

    def with_grid(self, grid, *, check_sampling=True):
        """The same plan on ``grid`` elements a side: block, notes and checks made again."""
        return _on_grid(dataclasses.replace(self, grid=grid, check_sampling=check_sampling))


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


def plan_surfaces(scene, *, grid=None, check_sampling=True):
    """The plan of ``scene``'s surfaces, decided from the scene and its files.

    Parameters
    ----------
    scene : Scene
        Its ``workpiece``/``tool`` (paths or ``None`` for synthetic), units, ``size``,
        ``crop_size``, ``max_undefined``, ``lambda_s``, ``lambda_c``, ``grid`` (``None``:
        derived from the scan, see :func:`_default_grid`) and ``effects`` (``"inclined"``
        needs the measured grid).
    grid : int, optional
        Override the scene's grid.
    check_sampling : bool
        Refuse an element edge outside :data:`ELEMENT_PER_PIXEL` times the pixel pitch, and
        note a grid coarse for ``lambda_s`` (off for the resolution check).

    Returns
    -------
    SurfacePlan

    Raises
    ------
    ValueError
        Bad input, naming the file and the option: unreadable file, missing unit or size,
        too many undefined points, a filter out of range, implausible roughness or element
        size, too much memory.
    """
    n = scene.grid if grid is None else grid
    roles = [r for r in ROLES if getattr(scene, r) is not None]
    if roles:
        plan = _files_plan(scene, roles, n, check_sampling)
    else:
        plan = _plan(scene, check_sampling, scans=(), side=_surf.PAPER_SIZE, grid=n)
    return _on_grid(plan)


def _files_plan(scene, roles, n, check_sampling):
    """The choices made from the files of ``roles``, before the grid's (``n``: given or ``None``)."""
    _check_pair(roles, "inclined" in scene.effects)
    scans = tuple(Scan.read(scene, r) for r in roles)
    raw = [scan.surface for scan in scans]
    _check_size_option(scene.size, scans, raw)
    for scan, s in zip(scans, raw, strict=True):  # the height unit, then the lateral scale
        _check_rq(s.provenance["path"], scan.role, s.provenance["rq_scan"])
        slope = s.provenance["rms_slope_scan"]
        check_scan(
            ScanScale(f"{scan.role} {scan.path}", scan.role, s.size, slope), scene.smooth_pair
        )
    side = _side(scene.crop_size, raw)
    pitch = max(v for s in raw for v in (s.dx, s.dy))
    lam, lam_source = _lambda_s(scene.lambda_s, raw, side, pitch)
    _check_filters(scans, raw, lam, scene.lambda_c)
    if n is None:
        n = _default_grid(side, pitch, "inclined" in scene.effects, lam)
    return _plan(
        scene,
        check_sampling,
        scans=scans,
        side=side,
        pitch=pitch,
        lambda_s=lam,
        lambda_s_source=lam_source,
        lambda_c=scene.lambda_c,
        grid=n,
    )


def _plan(scene, check_sampling, **decided):
    """A :class:`SurfacePlan` of ``scene`` with the choices ``decided``, before its grid's."""
    return SurfacePlan(
        check_sampling=check_sampling,
        block=1,
        measured="inclined" in scene.effects,
        boundary=scene.boundary,
        synthetic=SyntheticSource.of(scene),
        **decided,
    )


# ----------------------------------------------------------------------------- reading
@functools.lru_cache(maxsize=2)  # workpiece and tool
def _read_scan(role, path, stamp, unit, size, own_size, max_undefined):
    """``(surface, steps)`` of :meth:`Scan.read`: holes filled, ``rq_scan`` in the provenance.

    ``rms_slope_scan`` too (the RMS slope of the levelled scan,
    :func:`~.lateral_scale.scan_slope`). Cached per file and options: the resolution check and the sample patches read again.
    """
    unit_opt = f"{{{role}_unit}} or {{unit}}"
    unit_names = (f"{role}_unit", "unit")
    try:
        h, dx, dy, prov = _read_sized(path, unit, size, own_size)
    except _surf.UnitRequired:
        raise ParameterError(
            f"{path}: a plain file does not say its height unit: give {unit_opt} (m, mm, um, nm)",
            *unit_names,
        ) from None
    except _surf.UnitContradiction as exc:
        raise ParameterError(f"{exc} (the option is {unit_opt})", *unit_names) from None
    except _surf.SizeRequired as exc:
        said = f"{exc.note}; add it, or" if exc.note else "a plain file does not say its size:"
        raise ParameterError(
            f"{path}: {said} give {{size}} or {{{role}_size}} (LX [LY] in m)",
            "size",
            f"{role}_size",
        ) from None
    except OSError as exc:
        raise ValueError(f"{path}: cannot read the file ({exc.strerror or exc})") from None
    h, steps, bad = chain.fill_holes(h, max_undefined, path)
    prov["undefined_points"] = bad
    scan = _surf.Surface(h, dx, dy, periodic=False)
    prov["rq_scan"] = _surf.rq(_surf.level(scan))
    prov["rms_slope_scan"] = scan_slope(scan)
    return _surf.Surface(h, dx, dy, provenance=prov, periodic=False), steps


def _read_sized(path, unit, size, own_size):
    """:func:`~halfspace_calib.topography.read_raw` with the scene's sizes.

    ``size`` only for a file without its own; ``own_size`` (the role's) over whatever the file
    carries.
    """
    if own_size is not None:
        return _surf.read_raw(path, unit=unit, override_size=own_size)
    try:
        return _surf.read_raw(path, unit=unit)
    except _surf.SizeRequired:
        if size is None:
            raise
        return _surf.read_raw(path, unit=unit, size=size)


# ----------------------------------------------------------------------------- decisions
def _check_pair(roles, inclined):
    """The inclined effect needs both surfaces measured (``roles``: those with a file)."""
    if inclined and len(roles) == 1:
        missing = "tool" if roles == ["workpiece"] else "workpiece"
        raise ValueError(
            f"the inclined effect needs both surfaces measured: give the {missing} as a file "
            "too (a synthetic map has no measured points of its own)"
        )


def _check_size_option(size, scans, raw):
    """``size`` applies to plain files without a size of their own or of their role's option."""
    if size is not None and all(s.provenance["size_source"] != "option" for s in raw):
        raise ParameterError(
            "{size} applies to plain files without their own size; the files carry theirs or "
            f"take {{workpiece_size}} / {{tool_size}} ({', '.join(scan.path for scan in scans)})",
            "size",
            "workpiece_size",
            "tool_size",
        )


def _side(crop_size, raw):
    """The square patch's edge (m): the files' largest common square, or ``crop_size``."""
    side = min(v for s in raw for v in s.size)
    if crop_size is None:
        return side
    if crop_size > side * (1 + 1e-9):
        raise ParameterError(
            f"{{crop_size}} {crop_size:g} m exceeds the largest common square of the "
            f"files, {side:g} m",
            "crop_size",
        )
    return float(crop_size)


def _lambda_s(lambda_s, raw, side, pitch):
    """``(lambda_s, where it came from)``: the option (``0``: no S-filter) or the default."""
    if lambda_s is not None:
        return (lambda_s, "option") if lambda_s else (0.0, "option: no S-filter")
    lam = default_lambda_s(side, pitch, MAX_DEFAULT_GRID)
    if lam > side * (1 + 1e-9):  # e.g. a scan of millimetre pixels with a 0.1 mm scan
        coarse = max(raw, key=lambda s: max(s.dx, s.dy))
        raise ParameterError(
            f"{coarse.provenance['path']} has pixels of {max(coarse.dx, coarse.dy):.3g} m: "
            f"the default lambda_s (>= {ISO_SAMPLING_RATIO:g} of its pixels) is {lam:.3g} m, "
            f"more than the files' common square of {side:.3g} m, so the scans cannot be "
            "paired at the coarser one's resolution; give {lambda_s} (m, at least 2 pixel "
            "pitches of each file and at most the common square) or a scan of finer pixels",
            "lambda_s",
        )
    return lam, (
        f"default: smallest ISO 25178-3 nesting index >= {ISO_SAMPLING_RATIO:g} pixel "
        f"pitches and >= {ELEMENTS_PER_LAMBDA_S} elements of the {side:.4g} m square at "
        f"grid {MAX_DEFAULT_GRID}"
    )


def _check_filters(scans, raw, lambda_s, lambda_c):
    """The filters' cut-offs against each scan, before any filtering (``ParameterError``)."""
    for scan, s in zip(scans, raw, strict=True):
        try:
            chain.check_filter(s, lambda_s, lambda_c)
        except ValueError as exc:
            raise ParameterError(
                f"{scan.path}: {exc} ({{lambda_s}} / {{lambda_c}})",
                "lambda_s",
                "lambda_c",
            ) from None


def _default_grid(side, pitch, inclined, lambda_s=None):
    """The default solver grid of measured files (``pitch``: the scans' coarser pixel pitch).

    With an S-filter: :data:`ELEMENTS_PER_LAMBDA_S` elements per ``lambda_s`` (a multiple of 8),
    at most :data:`MAX_DEFAULT_GRID`; not capped by the scans' pixel, because the filtered scans
    are band-limited and a scan coarser than the element is interpolated exactly
    (:func:`~halfspace_calib.topography.resample.band_limited_resample`), except with the
    inclined effect, whose patch planes need two measured points per element edge. Without a
    filter: the native sampling on the common square (the coarser scan's pixel), at most
    :data:`MAX_DEFAULT_GRID`.
    """
    native = int(side / pitch * (1 + 1e-9))
    if inclined:
        native //= 2  # two measured points per element edge for the patch planes
    n = native
    if lambda_s:
        n = 8 * math.ceil(ELEMENTS_PER_LAMBDA_S * side / lambda_s / 8 - 1e-9)
        if inclined:
            n = min(native, n)
    return max(8, min(n, MAX_DEFAULT_GRID))


# ----------------------------------------------------------------------------- the grid
def _on_grid(plan):
    """``plan`` with the choices and checks that depend on its grid made: block, notes."""
    check_memory(plan.grid, plan.boundary)
    if not plan.scans:
        return dataclasses.replace(plan, block=_synthetic_block(plan))
    notes = ()
    if plan.check_sampling:  # not for the resolution check's half grid
        notes = check_lambda_s(plan.lambda_s, plan.element, plan.grid, plan.side)
        notes += check_patch_size(plan.side, plan.lambda_s)
    block = _block(plan)
    for scan in plan.scans:
        s = scan.surface
        path = s.provenance["path"]
        if plan.check_sampling:
            _check_element(path, plan.element, (s.dx, s.dy), plan.grid, plan.lambda_s)
    return dataclasses.replace(plan, block=block, notes=notes)


def _block(plan):
    """Measured points per element edge: 1, or with the inclined effect at least 2."""
    if not plan.measured:
        return 1
    block = max(1, int(plan.element / plan.pitch + 1e-9))
    if block < 2:
        raise ParameterError(
            f"the inclined effect needs >= 2 measured points per element edge; "
            f"grid={plan.grid} gives elements of {plan.element:.3g} m on scans sampled at "
            f"{plan.pitch:.3g} m: use {{grid}} <= {int(plan.side / plan.pitch) // 2}",
            "grid",
        )
    return block


def _synthetic_block(plan):
    """The inclined effect's measured grid of synthetic surfaces: ``measured_n // grid``."""
    if not plan.measured:
        return 1
    n, measured_n = plan.grid, plan.synthetic.measured_n
    fine = measured_n if measured_n is not None else 4 * n
    if fine % n or fine // n < 2:
        raise ValueError(
            f"measured_n must be a multiple >= 2 of grid={n} for the inclined "
            f"patches, got {measured_n!r}"
        )
    return fine // n


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
    (:func:`~halfspace_calib.topography.resample.band_limited_resample`), down to ``lambda_s``
    / (2 :data:`ELEMENTS_PER_LAMBDA_S`): one grid doubling beyond the default rule, for a
    convergence check.
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
