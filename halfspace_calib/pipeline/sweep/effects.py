"""Which friction effects a calibration models, how each runs, and what it reports (Sec. 2.2, 3.2-3.3).

A :class:`~halfspace_calib.pipeline.calibration.Scene` names its effects (``Scene.effects``):

``"normal"`` (always on)
    the normal-contact sweeps and the fit of Eqs. 24-25. Under full sliding every contact element
    is at the Tresca cap, so ``tau_adh = m (sigma_y / 2) alpha_rc`` needs no tangential solve.
``"tangential"``
    partial slip (pre-sliding) at every first-loading pressure on the loaded contact:
    ``q_mean(delta)`` up to full sliding and the interface's tangential stiffness, the penalty
    ``k_t`` of :func:`frictionlaw.traction_update` (:mod:`halfspace_calib.studies.presliding`).
``"inclined"``
    the geometric shear of inclined patches (Eqs. 19-23, :mod:`halfspace_calib.studies.geometric`) for the
    scene's workpiece and tool over the scene's pressures; if the mean ``tau_geo / tau_adh``
    exceeds ``Scene.geo_threshold``, Eq. 26's term is fitted into ``FrictionParams.geo_ratio``
    (least squares of ``f(p) = geo_ratio k alpha(p)``, :func:`halfspace_calib.studies.geometric.fit_geo_ratio`),
    otherwise ``geo_ratio`` stays 0 and the record says why.
``"sliding"``
    the sliding study of Sec. 3.3 (:func:`halfspace_calib.studies.sliding_study.sliding_study`), ``W_def / W_adh``
    at 100-600 MPa; it is reported, it does not change the parameters (the paper: below 0.008).

An effect that cannot run for the scene (e.g. ``m = 0``: no adhesive shear) is skipped and its
record carries ``skipped`` with the reason.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

from frictionlaw import TangentialStiffness

from ...studies.geometric import GeometricResult, fit_geo_ratio, geometric_sweep
from ...studies.presliding import stiffness_power_law
from ...studies.sliding_study import SlidingStudy
from .scene_surfaces import load_scene_surfaces

__all__ = [
    "EFFECTS",
    "check_effects",
    "scene_measured_surfaces",
    "run_inclined",
    "GeoDecision",
    "geo_decision",
    "run_sliding",
    "summarize_tangential",
    "stiffness_table",
    "EffectOutcome",
    "TangentialOutcome",
    "InclinedOutcome",
    "SlidingOutcome",
]

#: the effects a scene can select, in the order they run
EFFECTS = ("normal", "tangential", "inclined", "sliding")


def check_effects(effects):
    """Validated effects as a tuple in :data:`EFFECTS` order, ``"normal"`` always included.

    Parameters
    ----------
    effects : str or iterable of str
        Names from :data:`EFFECTS`; a string may list them comma separated.

    Raises
    ------
    ValueError
        An unknown name (the message lists the allowed ones).
    """
    if isinstance(effects, str):
        names = [e.strip() for e in effects.split(",") if e.strip()]
    else:
        try:
            names = list(effects)
        except TypeError:
            raise ValueError(
                f"effects must be a list of names from {list(EFFECTS)}, got {effects!r}"
            ) from None
    bad = [e for e in names if not isinstance(e, str) or e not in EFFECTS]
    if bad:
        raise ValueError(f"effects must be names from {list(EFFECTS)}, got unknown {bad}")
    chosen = set(names) | {"normal"}
    return tuple(e for e in EFFECTS if e in chosen)


# ----------------------------------------------------------------------------- outcomes
@dataclass
class EffectOutcome:
    """What one effect produced. ``skipped``: why it did not run (``None`` if it ran)."""

    name: str
    skipped: str | None = None
    seconds: float = 0.0


@dataclass
class TangentialOutcome(EffectOutcome):
    """The tangential effect: ``summary`` of :func:`summarize_tangential` (stiffness table)."""

    summary: dict | None = None


@dataclass
class InclinedOutcome(EffectOutcome):
    """The inclined-patch effect: the sweep and the ``geo_ratio`` decision (:func:`geo_decision`)."""

    result: GeometricResult | None = None
    decision: GeoDecision | None = None


@dataclass
class SlidingOutcome(EffectOutcome):
    """The sliding effect: the study of Sec. 3.3."""

    study: SlidingStudy | None = None


# ----------------------------------------------------------------------------- inclined
def scene_measured_surfaces(scene):
    """The scene's workpiece and tool as measured (fine) maps: ``(workpiece, tool, block)``.

    From the one scene loader (:func:`halfspace_calib.pipeline.sweep.scene_surfaces.load_scene_surfaces`):
    synthetic surfaces on ``scene.measured_n`` points a side (default ``4 scene.grid``); files
    cropped, resampled onto ``grid * block`` square points a side (``block >= 2`` measured
    points per element edge, otherwise a ``ValueError``) and levelled, in their own units
    (``workpiece_unit`` / ``tool_unit`` honoured).
    """
    if "inclined" not in scene.effects:
        scene = dataclasses.replace(scene, effects=tuple(scene.effects) + ("inclined",))
    s = load_scene_surfaces(scene)
    return s.measured_workpiece, s.measured_tool, s.block


@dataclass(frozen=True)
class GeoDecision:
    """Whether Eq. 26's geometric term goes into the parameters, and why.

    ``geo_ratio`` is 0 unless ``applied``; ``fit`` is :func:`fit_geo_ratio`'s record.
    """

    geo_ratio: float
    applied: bool
    ratio_mean: float
    threshold: float
    fit: dict
    method: str
    m: float
    reason: str

    def as_dict(self):
        """JSON-ready record (the parameter file's provenance and ``summary.json``)."""
        return dataclasses.asdict(self)


def geo_decision(result, threshold, m):
    """Whether Eq. 26's geometric term goes into the parameters, and why.

    Parameters
    ----------
    result : GeometricResult
        The inclined-patch sweep of the scene.
    threshold : float
        Significance threshold on the mean ``tau_geo / tau_adh`` (``Scene.geo_threshold``).
    m : float
        Tresca factor (only recorded).

    Returns
    -------
    GeoDecision
        ``geo_ratio`` (0 unless applied), ``applied``, ``ratio_mean``, ``threshold``, ``fit``
        (:func:`~halfspace_calib.studies.geometric.fit_geo_ratio`), ``method`` and ``reason``.
    """
    fit = fit_geo_ratio(result)
    mean = fit["ratio_mean"]
    applied = bool(mean > threshold)
    if applied:
        reason = (
            f"mean tau_geo / tau_adh = {mean:.4f} > geo_threshold = {threshold:g}: Eq. 26's "
            f"f(p) = geo_ratio k alpha(p) fitted, geo_ratio = {fit['geo_ratio']:.4f} "
            f"(RMS misfit {100 * fit['rms_misfit']:.1f} % of tau_geo)"
        )
    else:
        reason = (
            f"mean tau_geo / tau_adh = {mean:.4f} <= geo_threshold = {threshold:g}: "
            "the geometric shear is not significant, Eq. 26's term is left out (geo_ratio = 0)"
        )
    return GeoDecision(
        geo_ratio=fit["geo_ratio"] if applied else 0.0,
        applied=applied,
        ratio_mean=mean,
        threshold=float(threshold),
        fit=fit,
        method="least squares of tau_geo(p) = geo_ratio * tau_adh(p) = geo_ratio m k alpha(p) "
        "over the scene's pressures (alpha of the inclined-patch normal solves)",
        m=float(m),
        reason=reason,
    )


def run_inclined(scene, *, measured=None):
    """The inclined-patch sweep for the scene's surfaces and pressures, and the ``geo_ratio`` decision.

    ``measured``: the result of :func:`scene_measured_surfaces` if already made.

    Returns
    -------
    InclinedOutcome
        With ``result`` (GeometricResult) and ``decision``, or ``skipped`` when ``m = 0``.
    """
    if scene.m == 0:
        return InclinedOutcome(
            "inclined",
            skipped="m = 0: no adhesive shear, tau_geo / tau_adh undefined and Eq. 26 "
            "(m [k alpha + f]) vanishes; geo_ratio = 0",
        )
    t0 = time.perf_counter()
    wp, tl, s = scene_measured_surfaces(scene) if measured is None else measured
    res = geometric_sweep(
        wp,
        tl,
        scene.pressures,
        block=s,
        materials=scene.materials,
        solver=scene.solver,
        label="rough tool" if scene.rough_tool else "scene tool",
    )
    return InclinedOutcome(
        "inclined",
        seconds=time.perf_counter() - t0,
        result=res,
        decision=geo_decision(res, scene.geo_threshold, scene.m),
    )


# ----------------------------------------------------------------------------- sliding
def run_sliding(scene, *, progress=True, tool=None):
    """The sliding study of Sec. 3.3 with the scene's tool and materials.

    ``tool``: the scene's tool on the solver grid if already loaded.

    Returns
    -------
    SlidingOutcome
        With ``study`` (SlidingStudy), or ``skipped`` when the study cannot run (``m = 0``,
        ``H`` at or below 100 MPa).
    """
    from ...studies.sliding import SLIDING_PRESSURES, sliding_workpiece
    from ...studies.sliding_study import sliding_study

    if tool is None:
        tool = load_scene_surfaces(scene).tool
    n = tool.shape[0]
    wp = sliding_workpiece((3 * n, n), (3 * n * tool.dx, n * tool.dy), seed=scene.seed_workpiece)
    t0 = time.perf_counter()
    try:
        study = sliding_study(
            tuple(p for p in SLIDING_PRESSURES if p < scene.H),
            workpiece=wp,
            tool=tool,
            materials=scene.materials,
            solver=scene.solver,
            workers=scene.workers,
            scheduler=scene.scheduler,
            progress=progress,
        )
    except ValueError as exc:  # e.g. m = 0 (no adhesive work) or H below 100 MPa
        return SlidingOutcome("sliding", skipped=str(exc))
    return SlidingOutcome("sliding", seconds=time.perf_counter() - t0, study=study)


# ----------------------------------------------------------------------------- tangential
def summarize_tangential(levels):
    """Stiffness table, power-law fits and the FE recommendation from the sweeps' curves.

    Parameters
    ----------
    levels : list of LevelResult
        ``SweepResult.levels`` of a sweep run with the tangential effect (each with its
        ``tangential`` curve or ``tangential_error``).

    Returns
    -------
    dict
        ``rows`` (per pressure: ``p_mean``, ``alpha``, ``q_limit``, ``delta_full``,
        ``delta_stick``, ``k_t0``, ``k_sec``, ``k_eq``, ``converged``), ``errors``, ``k_t0_fit``,
        ``k_sec_fit``, ``k_eq_fit`` (:func:`~halfspace_calib.studies.presliding.stiffness_power_law`),
        ``full_sliding_max_rel_diff`` (solve against the shortcut) and ``recommendation``.
    """
    rows, errors = [], []
    max_diff = 0.0
    for lv in levels:
        if lv.tangential_error is not None:
            errors.append({"p_mean": lv.p_hist, "error": lv.tangential_error})
            continue
        t = lv.tangential
        if t is None:
            continue
        rows.append(
            {
                "p_mean": lv.p_hist,
                "alpha": lv.loading.alpha,
                "q_limit": t.q_limit,
                "delta_full": t.delta_full,
                "delta_stick": t.delta_stick,
                "k_t0": t.k_t0,
                "k_sec": t.k_sec,
                "k_eq": t.k_eq,
                "converged": t.converged,
            }
        )
        full = [
            q
            for d, q in zip(t.delta.tolist(), t.q_mean.tolist(), strict=True)
            if d >= t.delta_full * (1 - 1e-12)
        ]
        for q in full:
            max_diff = max(max_diff, abs(q - t.q_limit) / t.q_limit)
    out = {"rows": rows, "errors": errors, "full_sliding_max_rel_diff": max_diff}
    ok = [r for r in rows if r["converged"]]
    if len(ok) >= 2:
        p = [r["p_mean"] for r in ok]
        out["k_t0_fit"] = stiffness_power_law(p, [r["k_t0"] for r in ok])
        out["k_sec_fit"] = stiffness_power_law(p, [r["k_sec"] for r in ok])
        out["k_eq_fit"] = stiffness_power_law(p, [r["k_eq"] for r in ok])
        f = out["k_eq_fit"]
        out["recommendation"] = (
            "penalty k_t of frictionlaw.traction_update (Pa/m, per node at its pressure): k_eq, "
            "the bilinear stick/slip law with the rough contact's complementary energy up to full "
            "sliding, interpolated log-log in the table (tangential/tangential_stiffness.csv); as "
            f"a rough summary k_eq(p) = {f['k_ref']:.3e} * (p / {f['p_ref']:.3g} Pa)^"
            f"{f['exponent']:.3f} (max error {100 * f['max_rel_error']:.0f} % on the table). "
            "k_t0 (the initial "
            "slope) is the stiffest and k_sec (secant to full sliding) the softest physically "
            "meaningful value. All are the roughness layer's stiffness only (periodic half-space: "
            "delta from the mean surface displacement); the bulk compliance is in the FE model."
        )
    elif ok:
        out["recommendation"] = (
            f"penalty k_t of frictionlaw.traction_update: k_eq = "
            f"{ok[0]['k_eq']:.3e} Pa/m at {ok[0]['p_mean']:.3g} Pa"
        )
    else:
        out["recommendation"] = "no converged tangential curve: no stiffness recommendation"
    return out


def stiffness_table(outcome):
    """The calibrated ``k_t(p)`` table for the parameter file, or ``None``.

    Parameters
    ----------
    outcome : TangentialOutcome or None
        The tangential effect's outcome, ``None`` when the effect did not run.

    Returns
    -------
    frictionlaw.TangentialStiffness or None
        ``k_eq`` at the pressures whose tangential solve converged (the recommended penalty),
        ``None`` if there is none.
    """
    rows = [] if outcome is None or outcome.summary is None else outcome.summary["rows"]
    ok = sorted((r["p_mean"], r["k_eq"]) for r in rows if r["converged"])
    if not ok:
        return None
    return TangentialStiffness(p=[a for a, _ in ok], k_t=[b for _, b in ok])
