"""The calibration's scene: what a calibration needs, validated once, and its scene file (TOML).

:class:`Scene` holds the surfaces (files or synthetic), materials, pressures, solver settings and
effects; :func:`load_scene` reads a scene file. Both are re-exported by
:mod:`halfspace_calib.pipeline.calibration`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

from ...common.checks import in_range, text_file, tresca_factor
from ...contact.influence import BOUNDARIES
from ...contact.materials import Materials, SolverSettings, sigma_y_from_hardness
from ...contact.normal import composite_modulus
from ..law.forms import form_names
from ..law.heldout import HELDOUT_TOL
from . import effects as _eff
from .scene_surfaces import MAX_UNDEFINED, SYNTHETIC_GRID, check_memory

__all__ = [
    "DEFAULT_PRESSURES",
    "MIN_TOL",
    "PAPER_PRESSURES",
    "ALPHA_FLOOR",
    "BOUNDARIES",
    "DEFAULT_RELOAD_FRACTIONS",
    "P_FLOOR",
    "default_pressures",
    "Scene",
    "load_scene",
]

MPa = 1e6
#: the paper's first-loading pressures (Sec. 3.1: up to 600 MPa = 0.75 H of DC04)
PAPER_PRESSURES = (10e6, 25e6, 50e6, 100e6, 200e6, 300e6, 400e6, 500e6, 600e6)
#: the default sweep: the paper's, extended to 0.95 H (of the default H = 800 MPa) so that the
#: law is calibrated up to near the half-space model's exact limit (alpha = 1 at p_mean = H)
#: instead of extrapolated from 0.75 H (issue 26); ``pressures=PAPER_PRESSURES`` (the CLI's
#: ``--pressures paper``) keeps the paper's range
DEFAULT_PRESSURES = PAPER_PRESSURES + (700e6, 760e6)


def default_pressures(H):
    """The default sweep for hardness ``H`` (Pa).

    The paper's pressures below 0.85 H, then 0.875 H and 0.95 H: for the default H = 800 MPa
    exactly :data:`DEFAULT_PRESSURES`. A scene whose pressures equal :data:`DEFAULT_PRESSURES`
    (the default) gets this sweep for its own ``H``.
    """
    return tuple(p for p in PAPER_PRESSURES if p < 0.85 * H) + (0.875 * H, 0.95 * H)


DEFAULT_RELOAD_FRACTIONS = (0.05, 0.1, 0.25, 0.5, 0.75, 0.9)
#: the bound alpha1(p) >= p / H is imposed on the fit of Eq. 24 up to this fraction of H
ALPHA_FLOOR = 0.99
#: smallest plausible mean pressure (Pa): below it the values were most likely typed in MPa
P_FLOOR = 1e3


#: the defaults of a scene's materials are the ``Materials`` record's (the paper's Table 1)
_TABLE1 = Materials()


#: the normal solves' tolerance of a calibration (issue 39): the preconditioned CG gains about a
#: factor 2 per iteration once the contact set has settled, so 1e-6 takes about 6 iterations
#: fewer per solve than 1e-8 (default scene at 512^2: 696 -> 477 iterations, 0.60x the
#: calibration's wall time against 0.83x) and moves a computed alpha by 1.1e-5 there and by at
#: most 1.8e-4 (3 elements of 16,384) on the shared files at 128^2
#: (``benchmarks/adaptive_levels.py``, rows "tol 1e-8"; docs/normal_contact.md's table: 0.001 %)
SCENE_TOL = 1e-6

#: the smallest solver tolerance a scene takes: the normal solve's relative residual stalls at
#: double-precision rounding below it (measured: at tol 1e-13 reload levels of the 32^2 default
#: scene end at residuals 1.2e-13 after 5000 iterations; 1e-12 converges)
MIN_TOL = 1e-12


def _periodic_switch(cls):
    """Let ``cls(periodic=...)`` and ``dataclasses.replace(scene, periodic=...)`` set ``boundary``.

    ``periodic`` is the switch scenes had before ``boundary``; it keeps its meaning: ``True``
    is ``boundary="periodic"``, ``False`` is ``boundary="isolated"`` (the zero-padded DC-FFT
    solve), and when given it decides over ``boundary``. It is no field (``Scene.periodic``
    reads the boundary), so ``dataclasses.replace`` passes it only when asked to.
    """
    init = cls.__init__

    @functools.wraps(init)
    def __init__(self, *args, periodic=None, **kwargs):
        if periodic is not None:
            if not isinstance(periodic, bool):
                raise ValueError(f"periodic must be True, False or None, got {periodic!r}")
            kwargs["boundary"] = "periodic" if periodic else "isolated"
        init(self, *args, **kwargs)

    cls.__init__ = __init__
    return cls


@_periodic_switch
@dataclass(frozen=True)
class Scene:
    """Everything a calibration needs; every field has the paper's default.

    The defaults are the paper's Table 1 and Sec. 3.1.

    Surfaces: ``workpiece`` / ``tool`` are file paths or ``None`` for the synthetic DC04-EDT-like
    sheet and tool of Table 1 (``rough_tool`` for the rough tool; ``measured_n``, a multiple of
    ``grid``, generates them on that finer grid and block-averages, so that one seed is the same
    physical surface at every ``grid``). Files are prepared by
    :func:`~halfspace_calib.pipeline.sweep.scene_surfaces.load_scene_surfaces` (see docs/measured_surfaces.md):
    instrument files bring their own units and sizes (``unit=None``); plain files need ``unit``
    (or ``workpiece_unit`` / ``tool_unit``) and ``size`` (``L`` or ``(Lx, Ly)`` in m);
    ``workpiece_size`` / ``tool_size`` (same form) override the size every file of that role
    carries (a wrong header or calibration; the file's own size is kept in the provenance); a
    field or RMS slope implausible for a metal scan is refused, and full contact at a first load
    level below 0.05 H fails the run, unless ``smooth_pair`` states that the pair is that smooth
    (:mod:`~halfspace_calib.pipeline.sweep.lateral_scale`); undefined
    points are filled up to the fraction ``max_undefined``; both files are cropped to the largest
    common square (or ``crop_size``), area-averaged onto square elements and levelled.
    Files are levelled and filtered with the ISO 16610-61 Gaussian S-filter of nesting index
    ``lambda_s`` (m; ``None``: the default of
    :func:`~halfspace_calib.pipeline.sweep.scene_surfaces.default_lambda_s`; ``0``: no filter) and,
    if given, the L-filter ``lambda_c`` (m) before resampling; synthetic surfaces keep their
    generated spectrum (cut off at two elements), so both are refused for them.
    ``grid=None`` means 128 for synthetic surfaces and, for files,
    ``ELEMENTS_PER_LAMBDA_S`` elements per ``lambda_s`` (at most the scan's native sampling
    and 256). ``boundary`` is how the solver closes the patch (one of :data:`BOUNDARIES`,
    docs/measured_surfaces.md, "The patch's boundary"): ``"periodic"`` (one period of a
    periodic surface, its opposite edges joined), ``"mirror"`` (one quarter of the period of
    its mirror-symmetric extension: no seam, no edge of a finite body) or ``"isolated"`` (an
    isolated body on a half-space, zero-padded DC-FFT: the default for files before the mirror
    existed, whose nearly conforming patches act as flat punches); ``None`` means
    ``"periodic"`` for synthetic surfaces, which are generated periodic, and ``"mirror"`` for
    files. ``periodic=True`` / ``False`` is the older switch, still accepted: it sets
    ``boundary`` to ``"periodic"`` / ``"isolated"``, and :attr:`periodic` says whether the
    patch's opposite edges are joined. ``resolution_check=None`` runs the check (the normal
    sweeps again at half the grid) for files only. ``contact_area``: the contact ratio the fits read, ``"count"``
    (elements with ``p > 0``, the default) or ``"perimeter"`` (the count corrected with the
    contact perimeter, Yastrebov et al. 2017; docs/normal_contact.md, "Contact-area estimators").
    ``workers=None`` chooses the processes of the normal
    sweeps by the solve's size (:func:`~halfspace_calib.common.jobs.default_workers`: 2 from
    about 362^2 FFT elements on a machine with 2 or more CPUs, else this process with threaded
    FFTs; the effects and samples run in this process); ``1`` in this process, ``0`` one per
    CPU. The answer is the same to the last digit whichever runs.
    Frozen and validated once, on construction: derive a changed scene with
    :func:`dataclasses.replace` (which validates again). :attr:`materials` and :attr:`solver` give
    the records the sweeps and studies take.
    Materials in Pa; ``sigma_y`` defaults to ``H / 2.8`` (Bowden and Tabor,
    :func:`~halfspace_calib.contact.materials.sigma_y_from_hardness`). ``m`` is Tresca's
    factor: it does not enter the half-space model, only the parameter file (measure it, e.g. by
    ring compression).

    ``tol``: the normal solves' relative residual (default :data:`SCENE_TOL` = 1e-6; the solver's
    own default, 1e-8, changes a computed ``alpha`` by at most 3 elements' worth and takes about
    45 % more CG iterations).

    ``pressures``: the first-loading ``p_mean`` (default :data:`DEFAULT_PRESSURES`, 10-760 MPa, up
    to 0.95 H of the default H; for another ``H`` the default follows it,
    :func:`default_pressures`; ``"paper"`` or :data:`PAPER_PRESSURES`: the paper's 10-600 MPa).
    ``alpha_floor``: fit Eq. 24 subject to the half-space model's exact bound
    ``alpha1(p) >= p / H`` on ``0 < p <= alpha_floor H`` (default :data:`ALPHA_FLOOR` = 0.99;
    Eq. 24 cannot reach 1 at ``H`` itself; ``None``: unconstrained, the fit before issue 26;
    :func:`~halfspace_calib.pipeline.law.fit.fit_first_loading`'s ``floor_to``).

    ``first_loading_form``: the first-loading branch the parameter file runs (:mod:`.forms`):
    ``"auto"`` (the default: every candidate fitted, the one with the smallest held-out error
    runs), ``"tabulated"`` (the computed first loading interpolated,
    :mod:`frictionlaw.first_loading`) or ``"eq24"`` (the paper's ``C1, n1``); Eq. 24 is fitted
    and its error reported either way. ``reload_form``: the reload branch, likewise: ``"auto"``,
    ``"tabulated"`` (Eq. 25 with ``C2, n2`` per load level, :mod:`frictionlaw.reload_form`) or
    ``"paper"`` (one ``C2, n2``); the reload forms are fitted on ``alpha1(p_hist)`` of the
    first-loading form that runs. ``continuous_reload`` (default ``True``): the reload branch
    meets the first loading at ``p_hist`` (no drop there), fitted in that variant.
    ``heldout_tol``: the largest held-out ``|d alpha|`` either branch may have
    (:mod:`~halfspace_calib.pipeline.law.heldout`); beyond it the run fails.
    ``adaptive_levels``: place the load levels where the computed ``alpha`` changes, within the
    range of ``pressures`` (:mod:`~halfspace_calib.pipeline.sweep.levels`: refined to
    ``0.1 heldout_tol`` in first loading and ``0.3 heldout_tol`` in reload); ``False`` computes
    ``pressures`` as given; ``None`` (the default) refines the default pressures and computes
    given ones as given.

    ``H_source`` says where ``H`` came from for the parameter file (``None``: Table 1's value
    or "given"; :mod:`halfspace_calib.pipeline.sweep.hardness` sets it when H is fitted to
    after-contact roughness).

    Effects (:mod:`halfspace_calib.pipeline.sweep.effects`): ``effects`` names what is modelled besides the
    always-on ``"normal"`` sweeps: ``"tangential"`` (pre-sliding stiffness), ``"inclined"``
    (Eq. 23 and, if the mean ``tau_geo / tau_adh`` exceeds ``geo_threshold``, Eq. 26's
    ``geo_ratio``), ``"sliding"`` (Sec. 3.3). With ``"inclined"`` on synthetic surfaces
    ``measured_n`` defaults to ``4 grid``: the inclined patches are fitted on that measured grid
    and the calibration's surfaces are block averages of the same random field.
    """

    workpiece: str | None = None
    tool: str | None = None
    unit: str | None = None
    workpiece_unit: str | None = None
    tool_unit: str | None = None
    size: float | tuple | None = None
    workpiece_size: float | tuple | None = None
    tool_size: float | tuple | None = None
    smooth_pair: bool = False
    crop_size: float | None = None
    max_undefined: float = MAX_UNDEFINED
    lambda_s: float | None = None
    lambda_c: float | None = None
    rough_tool: bool = False
    seed_workpiece: int = 1
    seed_tool: int = 2
    grid: int | None = None
    measured_n: int | None = None
    E_workpiece: float = _TABLE1.E_workpiece
    nu_workpiece: float = _TABLE1.nu_workpiece
    E_tool: float = _TABLE1.E_tool
    nu_tool: float = _TABLE1.nu_tool
    H: float = _TABLE1.H
    sigma_y: float | None = None
    m: float = _TABLE1.m
    H_source: str | None = None
    pressures: tuple = DEFAULT_PRESSURES
    reload_from: float = 100e6
    reload_fractions: tuple = DEFAULT_RELOAD_FRACTIONS
    tol: float = SCENE_TOL
    boundary: str | None = None
    resolution_check: bool | None = None
    volume_conservation: bool = True
    reload_surface: str = "plastic"
    contact_area: str = "count"
    continuous_reload: bool = True
    first_loading_form: str = "auto"
    reload_form: str = "auto"
    heldout_tol: float = HELDOUT_TOL
    alpha_floor: float | None = ALPHA_FLOOR
    adaptive_levels: bool | None = None
    workers: int | None = None
    scheduler: str | None = None
    effects: tuple = ("normal",)
    geo_threshold: float = 0.05

    @property
    def from_files(self):
        """True if at least one surface is a measured file."""
        return self.workpiece is not None or self.tool is not None

    def __post_init__(self):
        def put(name, value):  # the one place a frozen Scene's fields are set: defaults resolved
            object.__setattr__(self, name, value)

        put("effects", _eff.check_effects(self.effects))
        synthetic = not self.from_files
        if self.grid is None and synthetic:
            put("grid", SYNTHETIC_GRID)
        if self.boundary is None:
            put("boundary", "periodic" if synthetic else "mirror")
        if self.resolution_check is None:
            put("resolution_check", not synthetic)
        for name in ("size", "workpiece_size", "tool_size"):
            if isinstance(getattr(self, name), list):
                put(name, tuple(getattr(self, name)))
        if "inclined" in self.effects and synthetic and self.measured_n is None:
            # the inclined patches need the measured grid: calibrate on the same random field
            put("measured_n", 4 * self.grid if isinstance(self.grid, int) else None)
        if self.adaptive_levels is None:  # the default range is refined, given levels are not
            put("adaptive_levels", self.pressures == DEFAULT_PRESSURES)
        if self.pressures == DEFAULT_PRESSURES and isinstance(self.H, (int, float)) and self.H > 0:
            put("pressures", default_pressures(self.H))  # the default sweep follows H
        if isinstance(self.pressures, str):  # a scene file's pressures = "paper"
            if self.pressures.strip().lower() != "paper":
                raise ValueError(
                    f"pressures must be a list of mean pressures (Pa) or 'paper' (the paper's "
                    f"10-600 MPa), got {self.pressures!r}"
                )
            put("pressures", PAPER_PRESSURES)
        put("pressures", tuple(float(p) for p in self.pressures))
        put("reload_fractions", tuple(float(f) for f in self.reload_fractions))
        if self.sigma_y is None and isinstance(self.H, (int, float)) and self.H > 0:
            put("sigma_y", sigma_y_from_hardness(self.H))
        self._validate()

    @property
    def periodic(self):
        """The patch's opposite edges are joined (``boundary == "periodic"``)."""
        return self.boundary == "periodic"

    @property
    def materials(self):
        """The bodies' :class:`~halfspace_calib.contact.materials.Materials` of this scene."""
        return Materials(
            E_workpiece=self.E_workpiece,
            nu_workpiece=self.nu_workpiece,
            E_tool=self.E_tool,
            nu_tool=self.nu_tool,
            H=self.H,
            sigma_y=self.sigma_y,
            m=self.m,
        )

    @property
    def solver(self):
        """The normal solver's :class:`~halfspace_calib.contact.materials.SolverSettings`."""
        return SolverSettings(
            tol=self.tol,
            boundary=self.boundary,
            volume_conservation=bool(self.volume_conservation),
        )

    def _validate(self):
        """Raise ``ValueError`` naming the first bad field and its allowed range."""
        for name in ("E_workpiece", "E_tool", "H", "sigma_y"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be a finite number > 0 (Pa), got {v!r}")
        for name in ("nu_workpiece", "nu_tool"):
            v = getattr(self, name)
            if not (-1.0 < v <= 0.5):
                raise ValueError(f"{name} must be in (-1, 0.5], got {v!r}")
        tresca_factor(self.m)
        if self.boundary not in BOUNDARIES:
            raise ValueError(
                f"boundary must be one of {', '.join(BOUNDARIES)} (or None: periodic for "
                f"synthetic surfaces, mirror for files), got {self.boundary!r}"
            )
        if self.H_source is not None and not isinstance(self.H_source, str):
            raise ValueError(f"H_source must be a text or None, got {self.H_source!r}")
        if not (self.grid is None and self.from_files):
            if isinstance(self.grid, bool) or not isinstance(self.grid, int) or self.grid < 8:
                raise ValueError(f"grid must be an integer >= 8, got {self.grid!r}")
            check_memory(self.grid, self.boundary)
        if self.measured_n is not None and isinstance(self.measured_n, int):
            check_memory(self.measured_n, True, "measured_n")
        if self.H < 1e6:
            raise ValueError(
                f"H = {self.H:g} Pa is below 1 MPa, far below any metal's hardness: H is in Pa, "
                f"most likely MPa were typed as Pa (write {self.H:g}e6, not {self.H:g})"
            )
        if len(self.pressures) < 3:
            raise ValueError("pressures must hold at least 3 values (Pa) for the fit of C1, n1")
        low = [p for p in self.pressures if 0 < p < P_FLOOR]
        if low:
            raise ValueError(
                f"pressures {low} Pa are below {P_FLOOR:g} Pa, far below any forming pressure: "
                "pressures are in Pa, most likely MPa were typed as Pa (write 10e6, not 10)"
            )
        bad = [p for p in self.pressures if not (0 < p < self.H)]
        if bad:
            raise ValueError(f"pressures must be in (0, H) = (0, {self.H:g}) Pa, got {bad}")
        if not self.reload_levels:
            raise ValueError(
                f"reload_from = {self.reload_from:g} Pa is above every pressure: no reload curve "
                "for the fit of Eq. 25; give reload_from <= max(pressures)"
            )
        self._validate_surfaces()
        if any(not (0 < f < 1) for f in self.reload_fractions):
            raise ValueError("reload_fractions must be in (0, 1)")
        in_range(
            "tol",
            self.tol,
            MIN_TOL,
            1,
            hi_open=True,
            why=" (the normal solver's relative residual stalls at rounding below it)",
        )
        if self.reload_surface not in ("plastic", "volume_conserving"):
            raise ValueError("reload_surface must be 'plastic' or 'volume_conserving'")
        self._validate_reload_law()
        af = self.alpha_floor
        if af is not None and not (
            isinstance(af, (int, float)) and not isinstance(af, bool) and 0 < af < 1
        ):
            raise ValueError(
                f"alpha_floor must be a fraction of H in (0, 1) or None (no bound), got {af!r}"
            )
        if self.contact_area not in ("count", "perimeter"):
            raise ValueError(
                f"contact_area must be 'count' or 'perimeter', got {self.contact_area!r}"
            )
        w = self.workers
        if w is not None and (isinstance(w, bool) or not isinstance(w, int) or w < 0):
            raise ValueError(f"workers must be an integer >= 0 or None (automatic), got {w!r}")
        g = self.geo_threshold
        if not (isinstance(g, (int, float)) and math.isfinite(g) and g >= 0):
            raise ValueError(f"geo_threshold must be a finite number >= 0 (a ratio), got {g!r}")
        if "inclined" in self.effects and self.workpiece is None and self.tool is None:
            mn = self.measured_n
            if mn is not None and (not isinstance(mn, int) or mn % self.grid or mn < 2 * self.grid):
                raise ValueError(
                    f"measured_n must be a multiple >= 2 of grid={self.grid} for the inclined "
                    f"effect (measured points per element), got {mn!r}"
                )

    def _validate_reload_law(self):
        """The branches' forms (issues 31, 37) and the acceptance's tolerance."""
        for branch in ("first_loading", "reload"):
            forms = ("auto", *form_names(branch))
            value = getattr(self, f"{branch}_form")
            if value not in forms:
                raise ValueError(f"{branch}_form must be one of {', '.join(forms)}, got {value!r}")
        if not isinstance(self.adaptive_levels, bool):
            raise ValueError(
                f"adaptive_levels must be True, False or None (refine the default range), got "
                f"{self.adaptive_levels!r}"
            )
        if not isinstance(self.continuous_reload, bool):
            raise ValueError(
                f"continuous_reload must be True or False, got {self.continuous_reload!r}"
            )
        ht = self.heldout_tol
        if not (isinstance(ht, (int, float)) and not isinstance(ht, bool) and 1e-4 <= ht <= 1):
            raise ValueError(
                f"heldout_tol must be a contact-ratio error in [0.0001, 1], got {ht!r}"
            )

    def _validate_surfaces(self):
        """Options about files and synthetic surfaces: each honoured or refused."""
        m = self.max_undefined
        if not (isinstance(m, (int, float)) and 0 <= m <= 1):
            raise ValueError(f"max_undefined must be a fraction in [0, 1], got {m!r}")
        if self.crop_size is not None and not (
            isinstance(self.crop_size, (int, float))
            and math.isfinite(self.crop_size)
            and self.crop_size > 0
        ):
            raise ValueError(f"crop_size must be a length > 0 (m), got {self.crop_size!r}")
        for name, lo in (("lambda_s", ">= 0 (m; 0: no S-filter)"), ("lambda_c", "> 0 (m)")):
            v = getattr(self, name)
            if v is not None and not (
                isinstance(v, (int, float))
                and not isinstance(v, bool)
                and math.isfinite(v)
                and (v >= 0 if name == "lambda_s" else v > 0)
            ):
                raise ValueError(f"{name} must be a length {lo}, got {v!r}")
        if self.lambda_s and self.lambda_c is not None and self.lambda_c <= self.lambda_s:
            raise ValueError(
                f"lambda_c = {self.lambda_c:g} m must exceed lambda_s = {self.lambda_s:g} m "
                "(the L-filter keeps the wavelengths below lambda_c)"
            )
        for name in ("size", "workpiece_size", "tool_size"):
            v = getattr(self, name)
            vals = v if isinstance(v, tuple) else (v,)
            if v is not None and (
                len(vals) not in (1, 2)
                or not all(isinstance(x, (int, float)) and math.isfinite(x) and x > 0 for x in vals)
            ):
                raise ValueError(f"{name} must be one or two lengths > 0 (m), got {v!r}")
        if not isinstance(self.smooth_pair, bool):
            raise ValueError(f"smooth_pair must be True or False, got {self.smooth_pair!r}")
        if not self.from_files:
            given = [
                n
                for n in (
                    "unit",
                    "workpiece_unit",
                    "tool_unit",
                    "size",
                    "crop_size",
                    "lambda_s",
                    "lambda_c",
                )
                if getattr(self, n) is not None
            ]
            if given:
                raise ValueError(
                    f"{', '.join(given)} apply to surface files only; no workpiece or tool file "
                    "was given"
                )
        for role in ("workpiece", "tool"):
            for opt in ("unit", "size"):
                if getattr(self, role) is None and getattr(self, f"{role}_{opt}") is not None:
                    raise ValueError(f"{role}_{opt} is given but the {role} is synthetic (no file)")
        if self.tool is not None and self.rough_tool:
            raise ValueError("rough_tool selects the synthetic tool; a tool file was given")
        if self.from_files and self.measured_n is not None:
            raise ValueError(
                "measured_n applies to synthetic surfaces; a file's measured grid is the scan"
            )
        if self.scheduler is not None and self.workers not in (None, 1):
            raise ValueError(
                "workers applies to local processes; with a Dask scheduler the cluster decides "
                "(give one of them)"
            )
        if self.reload_surface == "volume_conserving" and not self.volume_conservation:
            raise ValueError("reload_surface='volume_conserving' needs volume_conservation=True")

    @property
    def hardness_source(self):
        """Where ``H`` came from, in words (the parameter file's provenance)."""
        if self.H_source:
            return self.H_source
        if self.H == _TABLE1.H:
            return "default: the paper's H = 800 MPa for DC04 (Sec. 3.1, Table 1)"
        return "given"

    @property
    def E_star(self):
        """Composite modulus, Eq. 2."""
        return composite_modulus(self.E_workpiece, self.nu_workpiece, self.E_tool, self.nu_tool)

    @property
    def reload_levels(self):
        """The ``p_hist`` values that get a reload curve."""
        return tuple(p for p in self.pressures if p >= self.reload_from)

    def as_dict(self):
        """Plain dict of the settings (for the provenance)."""
        return dataclasses.asdict(self)


def read_scene_toml(path):
    """The tables of a scene file (TOML) as a dict.

    ``ValueError`` naming the file when it is missing, unreadable or not TOML. Read by
    :func:`load_scene` and by the several samples' ``[samples]`` table.
    """
    path = Path(path)
    try:
        return tomllib.loads(text_file(path, "scene file"))
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not a valid TOML scene file ({exc})") from None


def load_scene(path, **overrides):
    """Read a scene file (TOML, keys as the :class:`Scene` fields, SI units) and apply overrides."""
    path = Path(path)
    data = read_scene_toml(path)
    data = data.get("scene", data)
    data.pop("samples", None)  # several samples: read by pipeline.band.samples.read_samples_table
    known = {f.name for f in dataclasses.fields(Scene)} | {"periodic"}  # the older switch
    unknown = set(data) - known
    if unknown:
        raise ValueError(f"{path}: unknown scene keys {sorted(unknown)}; known: {sorted(known)}")
    for key in ("workpiece", "tool"):  # relative paths are relative to the scene file
        if data.get(key) and not Path(data[key]).is_absolute():
            data[key] = str(path.parent / data[key])
    if "periodic" in data and "boundary" in data:
        raise ValueError(
            f"{path}: give boundary or periodic (its older spelling: true is boundary = "
            "'periodic', false boundary = 'isolated'), not both"
        )
    over = {k: v for k, v in overrides.items() if v is not None}
    if "boundary" in over or "periodic" in over:  # an option overrides the file's either key
        data.pop("periodic", None)
        data.pop("boundary", None)
    data.update(over)
    return Scene(**data)
