"""Calibration pipeline (Sec. 3.1 and 4): surfaces in, sweeps, fit, ``FrictionParams`` out.

A :class:`Scene` holds everything a calibration needs (surfaces, materials, pressures, solver
settings). :func:`run_sweeps` runs the first-loading and un-/reloading sweeps as independent jobs
(one per load level ``p_hist``: load, record, then reload the deformed workpiece at pressures below
``p_hist`` with warm starts between neighbouring pressures). :func:`calibrate` fits Eqs. 24-25 to
the curves and returns the parameters with their provenance; :func:`write_outputs` writes the
parameter file, CSV tables and plots.

Reading of the paper for the reload surface: the plastically flattened workpiece (``h - u_pl``) is
what is contacted again. The Pullen-Williamson volume conservation lifts every out-of-contact
element by ``V_removed / A_out``; at high loads that lift exceeds the flattened plateau, so a
reload on that surface is *not* elastic, against the paper's own statement that it is. The lifted
surface is therefore used for the roughness after unloading (Figs. 3-4) and, on request
(``reload_surface="volume_conserving"``), for the reload; the report states which one ran and the
largest reload pressure against ``H``.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field

from frictionlaw import FrictionParams
from frictionlaw.describe import describe_law
from sbmf_cli import Worded

from .law import forms as _forms
from .law import heldout as _held
from .law.fit import FirstLoadingFit, ReloadFit
from .law.law_checks import DIP_TOL, JUMP_TOL, law_checks
from .law.params import make_params, timings_of
from .law.reload_table import ReloadTableFit
from .sweep import effects as _eff
from .sweep.conformity import punch_edge_problem
from .sweep.lateral_scale import full_contact_problem, scale_record
from .sweep.registry import REGISTRY
from .sweep.resolution import ResolutionCheck, check_sweeps, resolution_check
from .sweep.scene import MIN_TOL, Scene, load_scene
from .sweep.scene_surfaces import SceneSurfaces, load_scene_surfaces
from .sweep.sweeps import SweepResult, run_sweeps, scene_surfaces

__all__ = [
    "Scene",
    "SweepResult",
    "Calibration",
    "ResolutionCheck",
    "SceneSurfaces",
    "load_scene",
    "load_scene_surfaces",
    "scene_surfaces",
    "run_sweeps",
    "calibrate",
]

#: R^2 below this is reported (information only since issue 31: the held-out error decides)
R2_MIN = 0.9
#: the forms of the first-loading branch in the console's words
_FORM_WORDS = {"tabulated": "tabulated: the computed points, monotone cubic in ln p"}


#: why a scene's boundary is what it is (the defaults; any other combination was chosen)
_BOUNDARY_REASON = {
    (False, "periodic"): "synthetic surfaces are generated periodic",
    (True, "mirror"): (
        "measured files: a scan is a patch of a larger surface, not one period of it; solved as "
        "one quarter of the period of its mirror-symmetric extension (no seam, no patch edge)"
    ),
}


# ----------------------------------------------------------------------------- calibration
@dataclass
class Calibration:
    """Result of :func:`calibrate`: the parameters, the fits and the sweeps behind them.

    ``first`` is the fit of the paper's Eq. 24 (``C1, n1``) and ``reload`` of its Eq. 25 (one
    ``C2, n2``, on ``alpha1(p_hist)`` of the first-loading form that runs), both made in every
    calibration; ``first_loading_form`` / ``reload_form`` the forms the parameter file runs
    (:mod:`.forms`), ``first_fits`` every first-loading form's fit by name and ``reload_table``
    the tabulated reload form's (``None`` when not fitted); ``errors`` the measured errors of
    each branch (:mod:`.heldout`): ``"first_loading"`` and ``"reload"`` (the forms the file
    runs) and each other form's beside them (``"first_loading_eq24"``, ``"reload_paper"``, ...);
    ``checks`` the law's drop at ``p_hist`` and its reload curves below first loading
    (:func:`.law_checks.law_checks`).
    """

    params: FrictionParams
    first: FirstLoadingFit
    reload: ReloadFit
    sweeps: SweepResult
    scene: Scene
    seconds: float
    effects: dict = field(default_factory=dict)  # name -> EffectOutcome
    files: tuple = ()
    resolution: ResolutionCheck | None = None
    notes: tuple = ()  # what calibrate() decided on its own (printed as notes; none at present)
    warnings: tuple = ()  # the surfaces' warnings (grid coarse for lambda_s, patch too small)
    reload_table: ReloadTableFit | None = None
    errors: dict = field(default_factory=dict)  # branch -> heldout.BranchErrors
    reload_form: str = "paper"  # the reload form the parameter file runs
    first_loading_form: str = "eq24"  # the first-loading form the parameter file runs
    first_fits: dict = field(default_factory=dict)  # name -> fit of each first-loading form
    checks: dict = field(default_factory=dict)  # law_checks: jump at p_hist, reload below first
    flattening: dict | None = None  # what the flattening block was derived from (--flattening)
    #: the measurement beta was fitted to (--flattening-data), for the plot; not in any record
    flattening_data: object = None

    def __repr__(self):
        """One line a notebook can show: the law, the fit quality, the sweep and the time."""
        P = self.params
        levels = len(self.sweeps.levels)
        state = "FAILED" if self.problems() else "ok"
        return (
            f"Calibration({state}: C1={P.C1:.4g}, n1={P.n1:.4g}, C2={P.C2:.4g}, n2={P.n2:.4g}, "
            f"mu_eff={P.mu_eff:.4g}, R2={self.first.r_squared:.4f}/{self.reload.r_squared:.4f}, "
            f"{levels} load levels on {self.scene.grid}^2, {self.seconds:.1f} s)"
        )

    def problems(self):
        """Why the run failed, one sentence each (empty if it did not).

        A failed or non-converged load level or solve; a branch whose held-out error exceeds
        ``scene.heldout_tol`` (:mod:`.heldout`: one acceptance for both branches; R^2 is
        reported, it does not decide), with the
        parameters that ended on a bound named, since the bound then keeps the law from the
        data; a fit whose optimiser did not converge; why a reload fit failed on a nearly
        conforming isolated patch (:func:`~.conformity.punch_edge_problem`); full contact at
        the first load level below 0.05 H (:func:`~.lateral_scale.full_contact_problem`: most
        likely a lateral size in the wrong unit; not with ``scene.smooth_pair``); failed
        effect solves. A parameter on a bound with the error within the tolerance is a note
        (:meth:`fit_notes`), not a failure: the data are described with it there.
        """
        out = [f"load level {f.p_hist:g} Pa failed" for f in self.sweeps.failed]
        out += [
            Worded(
                f"not converged, left out of the fit: p_hist {nc.p_hist:g} Pa, p_mean "
                f"{nc.p_mean:g} Pa: {nc.message}; raise {{tol}} (now {self.scene.tol:g}; the "
                f"residual stalls at rounding below about {MIN_TOL:g})",
                "tol",
            )
            for nc in self.sweeps.not_converged()
        ]
        tol = self.scene.heldout_tol
        for key, name, fit in self._branches():
            err = self.errors.get(key)
            if err is not None and err.exceeds(tol):
                msg = err.problem(tol, name)
                if getattr(fit, "at_bound", ()):
                    msg += f" ({', '.join(fit.at_bound)} on a bound)"
                out.append(msg)
            if not getattr(fit, "success", True):
                out.append(f"{name} fit did not converge: {fit.message}")
        why = punch_edge_problem(self)
        if why:
            out.append(why)
        if self.flattening and self.flattening.get("problem"):
            out.append(f"flattening: {self.flattening['problem']}")
        flat = full_contact_problem(self)  # a lateral size in the wrong unit (issue 38)
        if flat:
            out.append(flat)
        for name, outcome in self.effects.items():
            out += REGISTRY[name].problems(outcome)
        return out

    def _branches(self):
        """``(errors key, name, fit)`` of the branches the parameter file runs."""
        first = ("first_loading", "first loading (Eq. 24)", self.first)
        if self.first_loading_form != "eq24":
            name = f"first loading ({_FORM_WORDS.get(self.first_loading_form, self.first_loading_form)})"
            first = ("first_loading", name, self.first_fits[self.first_loading_form])
        reload = ("reload", "reload (Eq. 25)", self.reload)
        if self.reload_form == "tabulated":
            reload = ("reload", "reload (Eq. 25 tabulated over p_hist)", self.reload_table)
        return [first, reload]

    def fit_notes(self):
        """What the fits report without failing: parameters on a bound, R^2, full contact."""
        out = []
        tol = self.scene.heldout_tol
        for key, name, fit in self._branches():
            err = self.errors.get(key)
            if getattr(fit, "at_bound", ()) and not (err is not None and err.exceeds(tol)):
                out.append(
                    f"{name}: {', '.join(fit.at_bound)} ended on a bound; the measured error "
                    f"stays within {tol:g}, so the data are described with it there"
                )
        for name, fit in (("first loading", self.first), ("reload (paper form)", self.reload)):
            if fit.r_squared < R2_MIN:
                out.append(
                    f"{name}: R^2 = {fit.r_squared:.3g} (information: R^2 does not judge a "
                    "curve with little variance; the measured error does)"
                )
        jump = self.checks.get("max_jump_relative", 0.0)
        if jump > JUMP_TOL:
            out.append(
                f"the law drops by {100 * jump:.2g} % of tau just below p_hist "
                f"({self.checks['jump_at_p_hist'] / 1e6:.4g} MPa), where the model's reload "
                "curve meets first loading: the continuous variant has no drop"
            )
        below = self.checks.get("reload_below_first") or {}
        if below.get("max", 0.0) > DIP_TOL:
            where = (
                "below the lowest reload level, where the reload branch is extrapolated"
                if below.get("calibrated_max", 0.0) <= DIP_TOL
                else "within the calibrated histories"
            )
            out.append(
                f"a reload curve of the law lies {below['max']:.3g} in alpha below its first "
                f"loading (p_hist {below['p_hist'] / 1e6:.4g} MPa, p {below['p'] / 1e6:.4g} MPa, "
                f"{where}); the model's lie above it"
            )
        p_full = _held.full_contact_pressure(*self.sweeps.loading, self.scene.H)
        if p_full is not None:
            out.append(
                f"full contact from low pressure: alpha >= {_held.FULL_CONTACT_ALPHA:g} at "
                f"{p_full / 1e6:.4g} MPa (<= {_held.FULL_CONTACT_P:g} H): the law is Tresca's "
                "from there on; if that is not expected, check the scan's lateral size and "
                "height unit (--size, --workpiece-size, --tool-size, --unit: a scan too wide for "
                "its heights is nearly flat)"
            )
        return out

    @property
    def degenerate(self):
        """``""`` when both fits are usable, else why not (see ``FitResult.degenerate``)."""
        parts = [
            f"{name}: {fit.degenerate}"
            for name, fit in (("first loading", self.first), ("reload", self.reload))
            if fit.degenerate
        ]
        return "; ".join(parts)

    def write_effects(self, out):
        """Each effect's files under ``out`` (``tangential/``, ``geometric/``, ``sliding/``)."""
        for name, outcome in self.effects.items():
            if outcome.skipped is None:
                REGISTRY[name].write(outcome, self, out)

    def print_effects(self, out):
        """The command's report lines of each effect, through the registry."""
        for name, outcome in self.effects.items():
            REGISTRY[name].print(outcome, out)

    def effect_lines(self, out):
        """The report lines of each effect (``print_effects`` prints them), through the registry."""
        return [line for n, o in self.effects.items() for line in REGISTRY[n].lines(o, out)]

    def summary(self):
        """JSON-ready summary (``summary.json``, ``report.html``).

        ``law`` describes the law ``params.json`` runs (:func:`frictionlaw.describe.describe_law`:
        each branch's form with its parameters or table and measured errors, the other form
        beside it); ``C1, n1, C2, n2``, ``first_loading_r2`` and ``reload_r2`` (the paper's
        Eq. 25, whichever form runs) are kept for the readers of earlier summaries.
        """
        P = self.params
        floor = self.first.floor_record()
        return {
            "law": describe_law(P).to_dict(),
            "C1": P.C1,
            "n1": P.n1,
            "C2": P.C2,
            "n2": P.n2,
            "m": P.m,
            "sigma_y": P.sigma_y,
            "H": P.H,
            "mu_eff": P.mu_eff,
            "tau_max": P.tau_max,
            "first_loading_form": P.first_loading_form,
            "reload_form": P.reload_form,
            "continuous_reload": P.continuous_reload,
            "s2": P.reload_table.s2 if P.reload_table is not None else None,
            "errors": {k: e.summary() for k, e in self.errors.items()},
            "heldout_tol": self.scene.heldout_tol,
            "fit_notes": self.fit_notes(),
            "full_contact_from_pressure": _held.full_contact_pressure(
                *self.sweeps.loading, self.scene.H
            ),
            "first_loading_r2": self.first.r_squared,
            "reload_r2": self.reload.r_squared,
            # the half-space model's exact bound alpha >= p / H against the fitted Eq. 24
            "alpha_bound_violation_to_p_max": floor["max_violation_to_p_max"],
            "alpha_bound_violation_to_H": floor["max_violation_to_H"],
            "alpha1_at_H": floor["alpha1_at_H"],
            "alpha_bound_r2_cost": floor["r_squared_cost"],
            "alpha_floor": floor,
            "fit_degenerate": {
                "first_loading": self.first.degenerate,
                "reload": self.reload.degenerate,
            },
            "max_jump_relative": self.checks.get("max_jump_relative", 0.0),
            "reload_below_first": self.checks.get("reload_below_first"),
            "failed_levels": [dataclasses.asdict(f) for f in self.sweeps.failed],
            "levels": None if self.sweeps.plan is None else self.sweeps.plan.as_dict(),
            "not_converged": [dataclasses.asdict(nc) for nc in self.sweeps.not_converged()],
            "max_reload_pressure_over_H": self.sweeps.max_reload_pressure() / self.scene.H,
            "max_reload_plastic_fraction": self.sweeps.max_reload_plastic_fraction(),
            "geo_ratio": P.geo_ratio,
            "effects": list(self.scene.effects),
            "effect_results": _effects_record(self.effects),
            "grid": self.scene.grid,
            "periodic": self.scene.periodic,
            "boundary": self.scene.boundary,
            "notes": list(self.notes),
            # warnings do not fail the run (problems do: exit 1, params.failed.json)
            "warnings": list(self.warnings),
            "files": [f.as_dict() for f in self.files],
            "resolution_check": None if self.resolution is None else self.resolution.as_dict(),
            "problems": self.problems(),
            "seconds": self.seconds,
            "flattening": self.flattening,
            "timings": self.timings(),
        }

    def timings(self):
        """``{what: seconds}``: the run's wall times, which ``params.json`` does not hold.

        The calibration's whole time, its sweeps', and every time its records carry (the
        tabulated reload fit, each effect, the resolution check) by their path in the
        parameter file's provenance (:func:`~.params.timeless` leaves them out of it).
        """
        out = {"calibration": self.seconds, "sweeps": self.sweeps.seconds}
        records = {
            "fit": {
                "reload_tabulated": None
                if self.reload_table is None
                else self.reload_table.summary()
            },
            "extra": {
                "effects": _effects_record(self.effects),
                "resolution_check": None if self.resolution is None else self.resolution.as_dict(),
            },
        }
        out.update(timings_of(records))
        return out


def calibrate(scene=None, *, progress=True, surfaces=None):
    """Run the sweeps of ``scene`` (default: the built-in scene) and fit the law.

    ``surfaces``: the scene's :class:`SceneSurfaces` if already loaded (the CLI loads them
    first, to refuse bad input before any sweep). For files, ``scene.grid=None`` becomes the
    loader's grid and, with ``scene.resolution_check``, the normal sweeps run again at half
    the grid (:func:`resolution_check`). The patch's boundary is ``scene.boundary`` (files:
    the mirror-symmetric extension; docs/measured_surfaces.md, "The patch's boundary").

    Raises ``RuntimeError`` if too few load levels converged for a fit (the sweep's
    failures are in the message).
    """
    return _calibrate(Scene() if scene is None else scene, progress, surfaces)


def _calibrate(scene, progress, surfaces):
    """One calibration of ``scene`` (the body of :func:`calibrate`)."""
    t0 = time.perf_counter()
    surfs = load_scene_surfaces(scene) if surfaces is None else surfaces
    if scene.grid != surfs.grid:
        scene = dataclasses.replace(scene, grid=surfs.grid)
    if scene.from_files and scene.lambda_s is None:  # the resolution check keeps this lambda_s
        scene = dataclasses.replace(scene, lambda_s=surfs.lambda_s)
    sweeps = run_sweeps(scene, progress=progress, surfaces=surfs)
    p, alpha = check_sweeps(sweeps)
    law = _forms.fit_law(scene, p, alpha, sweeps.reload_curves())
    first, reload = law.eq24, law.paper
    wp, tl = sweeps.surfaces["workpiece"], sweeps.surfaces["tool"]
    effects = _run_effects(scene, sweeps, surfs, progress)
    resolution = (
        resolution_check(scene, law, sweeps, progress=progress) if scene.resolution_check else None
    )
    params = make_params(
        first,
        reload,
        m=scene.m,
        sigma_y=scene.sigma_y,
        H=scene.H,
        surfaces={"workpiece": wp, "tool": tl},
        grid={
            "shape": list(wp.shape),
            "dx": wp.dx,
            "dy": wp.dy,
            "periodic": scene.periodic,
            "boundary": scene.boundary,
            "boundary_reason": _BOUNDARY_REASON.get((scene.from_files, scene.boundary), "chosen"),
        },
        tolerance=scene.tol,
        pressures={
            "loading": [lv.p_hist for lv in sweeps.levels],
            "range": [min(scene.pressures), max(scene.pressures)],
            "adaptive_levels": scene.adaptive_levels,
            "reload_fractions": list(scene.reload_fractions),
            "reload_from": scene.reload_from,
        },
        material={
            "E_workpiece": scene.E_workpiece,
            "nu_workpiece": scene.nu_workpiece,
            "E_tool": scene.E_tool,
            "nu_tool": scene.nu_tool,
            "E_star": scene.E_star,
            "H": scene.H,
            "sigma_y": scene.sigma_y,
            "m": scene.m,
        },
        extra={
            "model": {
                "volume_conservation": scene.volume_conservation,
                "reload_surface": scene.reload_surface,
                "contact_area": scene.contact_area,
                "effects": list(scene.effects),
                "max_reload_pressure_over_H": sweeps.max_reload_pressure() / scene.H,
                "max_reload_plastic_fraction": sweeps.max_reload_plastic_fraction(),
                "failed_levels": [dataclasses.asdict(f) for f in sweeps.failed],
                "geo_threshold": scene.geo_threshold,
            },
            "effects": _effects_record(effects),
            "files": surfs.records(),
            "length_scale": surfs.scale_record(),
            "hardness": {"H": scene.H, "source": scene.hardness_source},
            "lateral_scale": scale_record(scene.smooth_pair),
            "resolution_check": None if resolution is None else resolution.as_dict(),
        },
        p_range=(float(p.min()), float(p.max())),
        k_t=_eff.stiffness_table(effects.get("tangential")),
        law=law,
        heldout_tol=scene.heldout_tol,
    )
    if "inclined" in effects:
        params = params.replace(geo_ratio=REGISTRY["inclined"].geo_ratio(effects["inclined"]))
    return Calibration(
        params,
        first,
        reload,
        sweeps,
        scene,
        time.perf_counter() - t0,
        effects,
        surfs.files,
        resolution,
        warnings=tuple(surfs.notes),
        reload_table=law.table,
        errors=law.errors,
        reload_form=law.reload.form,
        first_loading_form=law.first.form,
        first_fits=dict(law.first.fits),
        checks=law_checks(params, sweeps.reload_curves()),
    )


def _run_effects(scene, sweeps, surfs, progress):
    """Run every effect of the scene but ``"normal"``, through :data:`.registry.REGISTRY`."""
    return {
        name: REGISTRY[name].run(scene, sweeps, surfs, progress)
        for name in scene.effects
        if name != "normal"
    }


def _effects_record(effects):
    """JSON-ready record of the effects' key results (provenance and ``summary.json``)."""
    return {name: REGISTRY[name].record(outcome) for name, outcome in effects.items()}
