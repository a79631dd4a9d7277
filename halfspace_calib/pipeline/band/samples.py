"""Several samples in one calibration: files, pairing, patches, one job per sample, pooling.

What a sample is
----------------
One workpiece surface against one tool surface, calibrated as a scene of its own. The samples
come from

* several workpiece files and tool files (``--workpiece A B C --tool T`` or a scene file's
  ``[samples]`` table), paired by :func:`pair_files`:

  - no tool file: every workpiece against the synthetic tool of the scene;
  - one tool file: every workpiece against that tool (the usual case: one die, many sheet
    patches);
  - as many tool files as workpiece files: the i-th workpiece against the i-th tool (each
    sample measured with its own tool counterpart);
  - anything else is refused (exit 2): an all-against-all design would weight the tools by
    the number of workpieces and is not what a user measuring pairs means;

* and/or ``--patches N``: every pair is cut into ``N`` non-overlapping square patches on a
  ``k x k`` layout (``k = ceil(sqrt(N))``, the first ``N`` in row order) of the common square
  of workpiece and tool, the tool patch at the same place as the workpiece patch. Each patch
  has the same policy as a single file (crop, area average onto square elements, level): the
  files are prepared once on ``k`` times the patch grid and each patch levelled again. With
  synthetic surfaces, ``--patches`` cuts one ``k``-times larger synthetic surface
  (``k x 2.11`` mm, the same Table 1 roughness): the population of the tests.

The solver grid of a patch is ``--grid`` (default: the scan's sampling on the patch, at most
:data:`~.surface_plan.MAX_DEFAULT_GRID`); a patch below :data:`PATCH_MIN_GRID` elements a
side is refused. A patch is not one period of anything: patches are solved as one quarter of
the period of their mirror-symmetric extension (``boundary="mirror"``, no seam and no patch
edge), or isolated if the scene asks for ``boundary="isolated"``.

Refused before any work (``ValueError``, exit 2): fewer than :data:`MIN_SAMPLES` samples,
samples whose element sizes differ by more than :data:`ELEMENT_RTOL` after resampling, files
of one role in different height units, effects other than ``normal`` (their per-sample
pooling is not defined yet), a patch below the element guard.

Each sample is one job (:func:`~halfspace_calib.common.jobs.run_jobs`: this process, local
processes or Dask); a failed job is reported by the sample's name and the others are kept.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from sbmf_cli import ParameterError

from ... import topography as _surf
from ...common.jobs import run_jobs
from ...topography import chain
from ..calibration import Calibration, calibrate
from ..law.law_checks import law_checks
from ..law.params import fit_record, timeless
from ..sweep.scene import read_scene_toml
from ..sweep.scene_surfaces import SceneSurfaces, load_scene_surfaces, run_plan
from ..sweep.surface_plan import MAX_DEFAULT_GRID, SyntheticSource, plan_surfaces
from ..sweep.sweeps import FailedLevel, SweepResult
from .uncertainty import (
    BAND_LEVEL,
    BAND_METHOD,
    N_BOOTSTRAP,
    REPORT_PRESSURES,
    bootstrap_uncertainty,
    check_band_method,
    curves_of,
    pooled_curves,
    pooled_law,
)

__all__ = [
    "ELEMENT_RTOL",
    "MIN_SAMPLES",
    "PATCH_MIN_GRID",
    "Sample",
    "SampleSpec",
    "SampleOutcome",
    "pair_files",
    "read_samples_table",
    "load_samples",
    "cut_patches",
    "synthetic_population",
    "run_samples",
    "MultiCalibration",
    "calibrate_samples",
]

#: fewest samples for a bootstrap band
MIN_SAMPLES = 3
#: fewest elements a side of a patch (the fit needs alpha resolved down to ~1 / 256)
PATCH_MIN_GRID = 16
#: largest relative difference of the samples' element sizes
ELEMENT_RTOL = 0.01


@dataclass(frozen=True)
class SampleSpec:
    """Which samples a calibration runs and how their band is made (validated on creation).

    ``workpieces`` / ``tools``: file paths (empty: the scene's own ``workpiece`` / ``tool``);
    ``patches``: patches per pair (1: the whole common square); ``level``: the band's two-sided
    level in ``(0, 1)``; ``n_bootstrap``: resamples; ``seed``: of the resampling;
    ``band_method``: how the band is made from the resamples (``"t"`` or ``"percentile"``,
    :func:`~.uncertainty.band_limits`).
    """

    workpieces: tuple = ()
    tools: tuple = ()
    patches: int = 1
    level: float = BAND_LEVEL
    n_bootstrap: int = N_BOOTSTRAP
    seed: int = 0
    band_method: str = BAND_METHOD

    def __post_init__(self):
        object.__setattr__(self, "workpieces", tuple(str(w) for w in self.workpieces))
        object.__setattr__(self, "tools", tuple(str(t) for t in self.tools))
        p = self.patches
        if isinstance(p, bool) or not isinstance(p, int) or p < 1:
            raise ValueError(f"patches must be an integer >= 1, got {p!r}")
        lv = self.level
        if isinstance(lv, bool) or not isinstance(lv, (int, float)) or not 0.5 <= lv < 1:
            raise ValueError(f"band level must be a fraction in [0.5, 1), e.g. 0.9, got {lv!r}")
        nb = self.n_bootstrap
        if isinstance(nb, bool) or not isinstance(nb, int) or nb < 50:
            raise ValueError(f"n_bootstrap must be an integer >= 50, got {nb!r}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int):
            raise ValueError(f"seed must be an integer, got {self.seed!r}")
        check_band_method(self.band_method)

    @property
    def multi(self):
        """True if this is a multi-sample calibration."""
        return len(self.workpieces) > 1 or len(self.tools) > 1 or self.patches > 1


@dataclass(frozen=True)
class Sample:
    """One sample: its name, its scene (one pair of files) and its surfaces on the solver grid."""

    name: str
    scene: object
    surfaces: SceneSurfaces


@dataclass
class SampleOutcome:
    """What :func:`run_samples` returns: the calibrations that ran and the samples that failed."""

    samples: list  # Sample, in order
    calibrations: dict  # name -> Calibration
    failed: dict  # name -> error text
    seconds: float


def read_samples_table(path):
    """The ``[samples]`` table of a scene file as :class:`SampleSpec` keywords (``{}`` if none).

    Keys: ``workpieces``, ``tools`` (lists of paths, relative to the scene file), ``patches``,
    ``band_level``, ``bootstrap``, ``seed``, ``band_method``.
    """
    path = Path(path)
    data = read_scene_toml(path)
    table = data.get("samples", {})
    if not isinstance(table, dict):
        raise ValueError(f"{path}: 'samples' must be a table ([samples])")
    names = {
        "workpieces": "workpieces",
        "tools": "tools",
        "patches": "patches",
        "band_level": "level",
        "bootstrap": "n_bootstrap",
        "seed": "seed",
        "band_method": "band_method",
    }
    unknown = set(table) - set(names)
    if unknown:
        raise ValueError(
            f"{path}: unknown [samples] keys {sorted(unknown)}; known: {sorted(names)}"
        )
    kw = {names[k]: v for k, v in table.items()}
    for key in ("workpieces", "tools"):
        if key in kw:
            if not isinstance(kw[key], list) or not all(isinstance(x, str) for x in kw[key]):
                raise ValueError(f"{path}: [samples] {key} must be a list of file paths")
            kw[key] = tuple(x if Path(x).is_absolute() else str(path.parent / x) for x in kw[key])
    return kw


def pair_files(workpieces, tools):
    """``[(workpiece or None, tool or None)]`` by the pairing policy (module docstring)."""
    w, t = list(workpieces) or [None], list(tools) or [None]
    if len(t) == 1:
        return [(x, t[0]) for x in w]
    if len(w) == 1 and w[0] is None:
        return [(None, y) for y in t]
    if len(t) == len(w):
        return list(zip(w, t, strict=True))
    raise ValueError(
        f"{len(w)} workpiece files and {len(t)} tool files: give one tool file (every "
        "workpiece against it) or one tool file per workpiece file (paired in order)"
    )


def _name(wp, tl, many_tools, patch=None):
    base = Path(wp).stem if wp else "synthetic"
    if many_tools and tl:
        base += f"+{Path(tl).stem}"
    return base if patch is None else f"{base}#p{patch[0]}{patch[1]}"


def _layout(n):
    k = math.ceil(math.sqrt(n))
    return k, [(i, j) for i in range(k) for j in range(k)][:n]


def synthetic_population(scene, k, grid):
    """One synthetic workpiece and tool ``k`` times the paper's 2.11 mm a side at ``k grid``.

    Table 1's roughness on the large square; its ``k x k`` patches of ``grid`` elements are the
    samples of one population. Periodic (as every synthetic surface), for the whole-surface
    reference calibration.
    """
    size = k * _surf.PAPER_SIZE
    gen = SyntheticSource.of(scene)
    wp = gen.surface("workpiece", k * grid, size)
    tl = gen.surface("tool", k * grid, size)
    return SceneSurfaces(wp, tl, None, None, 1, k * grid, ())


def cut_patches(surfs, k, where, grid):
    """The patches ``where`` (``(i, j)`` of a ``k x k`` layout) of ``surfs``: levelled, non-periodic."""
    out = []
    side = grid * surfs.workpiece.dx
    for i, j in where:
        sl = (slice(i * grid, (i + 1) * grid), slice(j * grid, (j + 1) * grid))
        pair = []
        for s in (surfs.workpiece, surfs.tool):
            op = {"op": "patch", "index": [i, j], "layout": [k, k], "shape": [grid, grid]}
            cut = s.derive(np.array(s.heights[sl]), op, periodic=False)
            pair.append(chain.level_patch(cut)[0])  # the chain's last stage, on the patch
        recs = tuple(
            dataclasses.replace(
                r,
                steps=r.steps
                + (
                    f"patch ({i}, {j}) of a {k} x {k} layout: {side * 1e6:.4g} x "
                    f"{side * 1e6:.4g} um, levelled again",
                ),
                crop_size=float(side),
                rq_patch=float(_surf.rq(pair[0 if r.role == "workpiece" else 1])),
            )
            for r in surfs.files
        )
        out.append(SceneSurfaces(pair[0], pair[1], None, None, 1, grid, recs))
    return out


def _check_scene(scene):
    extra = [e for e in scene.effects if e != "normal"]
    if extra:
        raise ParameterError(
            f"effects {extra} are not available in a multi-sample calibration (their pooling "
            "over samples is not defined): calibrate one sample for them, or drop {effects}",
            "effects",
        )


def _load_pair(one, spec):
    """``(surfaces on k * patch grid or the solver grid, k, patch grid)`` of one pair's scene."""
    k, _ = _layout(spec.patches)
    if spec.patches == 1:
        s = load_scene_surfaces(one)
        return s, 1, s.grid
    if not one.from_files:
        _patch_guard(one.grid, f"{{grid}} {one.grid}")
        return synthetic_population(one, k, one.grid), k, one.grid
    plan = plan_surfaces(one, check_sampling=False)  # the square and lambda_s of every patch
    grid = one.grid
    if grid is None:  # the scans' sampling on one patch, at most MAX_DEFAULT_GRID
        grid = min(int(plan.side / k / plan.pitch + 1e-9), MAX_DEFAULT_GRID)
    _patch_guard(grid, f"{{patches}} {spec.patches}")
    return run_plan(plan.with_grid(k * grid)), k, grid


def _patch_guard(grid, what):
    if grid < PATCH_MIN_GRID:
        raise ParameterError(
            f"{what} gives patches of {grid} elements a side, below the guard of "
            f"{PATCH_MIN_GRID}: use fewer patches ({{patches}}) or a finer {{grid}}",
            "patches",
            "grid",
        )


def load_samples(scene, spec):
    """Every sample of ``spec`` on ``scene``, loaded and checked: a list of :class:`Sample`.

    Raises ``ValueError`` (bad input, before any sweep) for the refusals of the module
    docstring.
    """
    _check_scene(scene)
    wps = spec.workpieces or ((scene.workpiece,) if scene.workpiece else ())
    tls = spec.tools or ((scene.tool,) if scene.tool else ())
    pairs = pair_files(wps, tls)
    n = len(pairs) * spec.patches
    if n < MIN_SAMPLES:
        raise ParameterError(
            f"{n} sample(s): a band needs at least {MIN_SAMPLES} (give more files or "
            "{patches} N)",
            "patches",
        )
    many_tools = len(set(t for _, t in pairs)) > 1
    patched = spec.patches > 1
    samples = []
    for wp, tl in pairs:
        files = wp is not None or tl is not None
        one = dataclasses.replace(
            scene,
            workpiece=wp,
            tool=tl,
            resolution_check=False,
            workers=1,
            scheduler=None,
            boundary=("mirror" if scene.periodic else scene.boundary)
            if patched
            else scene.boundary,
            grid=scene.grid if (files or scene.grid is not None) else None,
        )
        surfs, k, grid = _load_pair(one, spec)
        sc = dataclasses.replace(one, grid=grid)
        if not patched:
            samples.append(Sample(_name(wp, tl, many_tools), sc, surfs))
            continue
        _, where = _layout(spec.patches)
        for ij, ps in zip(where, cut_patches(surfs, k, where, grid), strict=True):
            samples.append(Sample(_name(wp, tl, many_tools, ij), sc, ps))
    seen = {}
    for i, smp in enumerate(samples):  # two files of one name in different folders
        seen[smp.name] = seen.get(smp.name, 0) + 1
        if seen[smp.name] > 1:
            samples[i] = dataclasses.replace(smp, name=f"{smp.name}@{seen[smp.name]}")
    _check_consistent(samples)
    return samples


def _check_consistent(samples):
    """Same element size (within :data:`ELEMENT_RTOL`) and, per role, the same height unit."""
    for role in ("workpiece", "tool"):
        units = {}
        for s in samples:
            for r in s.surfaces.files:
                if r.role == role:
                    units.setdefault(r.unit, r.path)
        if len(units) > 1:
            raise ValueError(
                f"the {role} files are in different height units ("
                + ", ".join(f"{p}: {u}" for u, p in units.items())
                + "): samples of one law must be measured alike; convert them or calibrate "
                "them separately"
            )
    dx = [s.surfaces.workpiece.dx for s in samples]
    if max(dx) > min(dx) * (1 + ELEMENT_RTOL):
        what = ", ".join(f"{s.name}: {s.surfaces.workpiece.dx * 1e6:.4g} um" for s in samples)
        raise ParameterError(
            f"the samples' element sizes differ by more than {100 * ELEMENT_RTOL:g} % after "
            f"resampling ({what}): one law needs one element size; give {{grid}} and "
            "{crop_size} so that every file gives the same element",
            "grid",
            "crop_size",
        )


def _sample_job(sample):
    """One sample's calibration (run in a worker: serial sweeps, no progress bar)."""
    return calibrate(sample.scene, progress=False, surfaces=sample.surfaces)


def run_samples(samples, *, workers=1, scheduler=None, progress=True):
    """Calibrate every sample as one job; failures are kept by name, not raised.

    The samples share one set of load levels (the pooled curves group by ``p_hist``): with
    adaptive levels (:mod:`.levels`) the first sample is calibrated first, here, and its
    computed levels are given to the others (computed as given, no refinement).
    """
    import time

    t0 = time.perf_counter()
    samples = list(samples)
    first = []
    if samples and samples[0].scene.adaptive_levels:
        first = run_jobs(_sample_job, samples[:1], workers=1, progress=False)
        if first[0].ok:
            ps = tuple(lv.p_hist for lv in first[0].value.sweeps.levels)
            samples = samples[:1] + [
                dataclasses.replace(
                    s, scene=dataclasses.replace(s.scene, pressures=ps, adaptive_levels=False)
                )
                for s in samples[1:]
            ]
    results = first + run_jobs(
        _sample_job,
        samples[len(first) :],
        workers=workers,
        scheduler=scheduler,
        progress=progress,
        desc="samples",
    )
    cals, failed = {}, {}
    for s, r in zip(samples, results, strict=True):
        if r.ok:
            cals[s.name] = r.value
        else:
            failed[s.name] = r.error.splitlines()[0] if r.error else "failed"
    return SampleOutcome(list(samples), cals, failed, time.perf_counter() - t0)


@dataclass
class MultiCalibration:
    """A calibration from several samples: the pooled law with its band, and every sample's run.

    ``pooled`` is a :class:`~.calibration.Calibration` whose parameters are the pooled fit
    (with the ``uncertainty`` block), whose fits are the pooled fits and whose sweeps hold
    every sample's load levels (so the standard tables and plots show all points).
    """

    pooled: Calibration
    spec: SampleSpec
    samples: list
    calibrations: dict
    failed: dict
    uncertainty: object
    seconds: dict

    @property
    def params(self):
        """The pooled :class:`frictionlaw.FrictionParams` (with its uncertainty block)."""
        return self.pooled.params

    def problems(self):
        """Why the run failed: failed samples by name, each sample's own problems, the pooled fits'.

        The pooled fits' ``R^2`` and held-out errors are not criteria: they also measure the
        samples' spread (each sample's own acceptance is). A pooled fit that did not converge is;
        so is a pooled parameter on a bound of the paper's equation when the file runs it.
        """
        out = [f"sample {n} failed: {e}" for n, e in self.failed.items()]
        for n, c in self.calibrations.items():
            out += [f"sample {n}: {p}" for p in c.problems()]
        for _, name, fit in self.pooled._branches():
            paper = fit is self.pooled.first or fit is self.pooled.reload
            if paper and fit.at_bound:
                out.append(f"pooled {name} fit: {', '.join(fit.at_bound)} ended on a bound")
            elif not getattr(fit, "success", True):
                out.append(f"pooled {name} fit did not converge: {fit.message}")
        return out

    def summary(self):
        """JSON-ready summary: the pooled calibration's, the samples and the band."""
        s = self.pooled.summary()
        u = self.uncertainty
        s["problems"] = self.problems()
        s["samples"] = {
            "count": len(self.samples),
            "calibrated": len(self.calibrations),
            "failed": dict(self.failed),
            "patches": self.spec.patches,
            "names": [x.name for x in self.samples],
            "per_sample": [x.to_dict() for x in u.samples],
        }
        s["uncertainty"] = {
            "level": u.level,
            "n_bootstrap": u.n_bootstrap,
            "band_method": self.spec.band_method,
            "parameters": {k: v.to_dict() for k, v in u.parameters.items()},
            "tau_first_at": {
                f"{p / 1e6:g} MPa": dict(
                    zip(("central", "lower", "upper"), u.band("tau_first").at(p), strict=True)
                )
                for p in _report_pressures(u)
            },
            "edge_laws": {k: v.to_dict() for k, v in u.edge_laws.items()},
        }
        s["seconds"] = self.seconds["total"]
        per = {f"{n}.{k}": v for n, c in self.calibrations.items() for k, v in c.timings().items()}
        s["timings"] = dict(self.seconds) | {f"samples.{k}": v for k, v in per.items()}
        return s


def _report_pressures(u):
    """The pressures of the summary's ``tau`` table: 100, 300, 600 MPa within the band."""
    b = u.band("tau_first")
    return [p for p in REPORT_PRESSURES if b.p[0] <= p <= b.p[-1]]


def calibrate_samples(scene, spec, *, samples=None, progress=True):
    """Calibrate every sample of ``spec`` on ``scene``, pool them and make the band.

    ``samples``: already loaded by :func:`load_samples` (the CLI loads them first, to refuse
    bad input before any sweep). Samples that fail are reported by name and left out; fewer
    than :data:`MIN_SAMPLES` left raise ``RuntimeError``.

    Returns
    -------
    MultiCalibration
    """
    import time

    t0 = time.perf_counter()
    samples = load_samples(scene, spec) if samples is None else samples
    run = run_samples(samples, workers=scene.workers, scheduler=scene.scheduler, progress=progress)
    t1 = time.perf_counter()
    ok = [s for s in samples if s.name in run.calibrations]
    if len(ok) < MIN_SAMPLES:
        raise RuntimeError(
            f"only {len(ok)} of {len(samples)} samples calibrated, a band needs "
            f"{MIN_SAMPLES}; failed: " + "; ".join(f"{n}: {e}" for n, e in run.failed.items())
        )
    cals = [run.calibrations[s.name] for s in ok]
    curves = [curves_of(s.name, c.sweeps) for s, c in zip(ok, cals, strict=True)]
    ref = cals[0]
    law = pooled_law(ref.scene, curves)
    first, reload = law.eq24, law.paper
    p_all = np.concatenate([c.p for c in curves])
    prov = dict(ref.params.provenance)
    prov["fit"] = fit_record(law.eq24, law.paper, law.table, law=law)
    prov["errors"] = {
        "heldout_tol": ref.scene.heldout_tol,
        **{k: e.summary() for k, e in law.errors.items()},
    }
    prov["surfaces"] = {"note": "several samples: see samples and extra.files"}
    extra = dict(prov.get("extra", {}))
    extra["files"] = _records(samples)
    prov["extra"] = extra
    prov["samples"] = {
        "pairing": "each workpiece against the one tool, or the i-th workpiece against the "
        "i-th tool",
        "patches": spec.patches,
        "names": [s.name for s in samples],
        "failed": dict(run.failed),
        "pooled_fit": "the law fitted to all calibrated samples' points at once, in the forms a "
        "single calibration chooses",
    }
    central = law.apply(ref.params).replace(
        p_range=(float(p_all.min()), float(p_all.max())), provenance=timeless(prov)
    )
    unc = bootstrap_uncertainty(
        curves,
        central,
        level=spec.level,
        n_bootstrap=spec.n_bootstrap,
        seed=spec.seed,
        method=spec.band_method,
        floor_to=None if ref.scene.alpha_floor is None else ref.scene.alpha_floor * ref.scene.H,
    )
    t2 = time.perf_counter()
    params = central.replace(uncertainty=unc)
    levels = [lv for c in cals for lv in c.sweeps.levels]
    failed = [
        FailedLevel(f.p_hist, f"{s.name}: {f.error}")
        for s, c in zip(ok, cals, strict=True)
        for f in c.sweeps.failed
    ]
    sweeps = SweepResult(
        levels, failed, sum(c.sweeps.seconds for c in cals), dict(ref.sweeps.surfaces)
    )
    pooled = Calibration(
        params,
        first,
        reload,
        sweeps,
        ref.scene,
        time.perf_counter() - t0,
        {},
        tuple(r for c in cals for r in c.files),
        None,
        reload_table=law.table,
        errors=law.errors,
        reload_form=law.reload.form,
        first_loading_form=law.first.form,
        first_fits=dict(law.first.fits),
        checks=law_checks(params, pooled_curves(curves)),
    )
    secs = {"samples": t1 - t0, "bootstrap": t2 - t1, "total": time.perf_counter() - t0}
    return MultiCalibration(pooled, spec, list(samples), run.calibrations, run.failed, unc, secs)


def _records(samples):
    """Every sample's file records (JSON-ready), with the sample's name."""
    return [{"sample": s.name, **r.as_dict()} for s in samples for r in s.surfaces.files]
