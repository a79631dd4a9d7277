"""How a scene runs: its specification (law, settings) and the increment driver.

A scene builds a :class:`Run` (the model, the :class:`LawSpec` of its friction law, the
:class:`RunSettings` of progress, VTU snapshots and remeshing, and the scene's own history
columns) and hands it to :func:`drive` with its stages, a list of ``(target die position,
increments)``.
"""

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from frictionlaw import OPEN, SLIP, STICK
from frictionlaw.flattening import LIMIT_MODEL
from frictionlaw.flattening_limit import table_pressures

from ..solver.model import FormingModel
from ..solver.remesh import block_corners, element_quality, remesh
from .calibrated_range import range_columns, range_summary
from .laws import law_parameters, make_law_factory
from .result import SceneResult
from .slab import slab_pressure_coulomb, slab_pressure_law, slab_pressure_tresca
from .zones import radial_zones

__all__ = ["LawSpec", "ProgressBar", "RunSettings", "Run", "drive", "press"]


@dataclass(frozen=True)
class LawSpec:
    """The friction law of a run: its name and the options that law reads.

    ``name`` in ``none, coulomb, tresca, cap, sbmf``; ``mu`` (Coulomb, cap), ``m`` (Tresca,
    cap's default cap), ``tau_max`` (cap, Pa), ``params`` (sbmf: a ``FrictionParams``, a JSON
    path, or ``None`` for the shipped illustrative set); see :mod:`fe_demo.scenes.laws`.
    ``flattening`` (issue 43): ``True`` passes the die nodes' bulk plastic strain to a law with
    a flattening block, ``False`` is the same law without it in a comparison (both record the
    contact fraction against the strain at the die), ``None`` (default) neither.
    """

    name: str = "sbmf"
    mu: float = 0.1
    m: float = 0.3
    tau_max: float | None = None
    params: object = None
    zones: tuple = ()
    flattening: bool | None = None

    def factory(self):
        """``factory(model) -> law`` for the model (:func:`fe_demo.scenes.laws.make_law_factory`).

        With ``zones`` (``(name, params, radius)`` each; law ``sbmf`` only) the die's
        :class:`fe_demo.scenes.zones.RadialZones`: this law inside, each zone's from its radius.
        """
        base = make_law_factory(
            self.name, mu=self.mu, m=self.m, tau_max=self.tau_max, params=self.params
        )
        if not self.zones:
            return base
        if self.name != "sbmf":
            raise ValueError(f"zones need the law sbmf (the die's default law), got {self.name!r}")
        die = radial_zones(base(None), self.zones)  # sbmf: a fixed law, whatever the model
        return lambda model: die

    def check_flattening(self):
        """``ValueError`` unless a flattening run has a law with a flattening block."""
        if not self.flattening:
            return
        law = self.factory()(None) if self.name == "sbmf" else None
        law = getattr(law, "law", law)  # a zoned die: its ZonedLaw
        if not getattr(law, "uses_flattening", False):
            raise ValueError(
                "flattening needs the law sbmf with a parameter file that carries a flattening "
                "block (a calibration run with the flattening on; docs/flattening.md)"
            )

    def parameters(self):
        """The law's parameters as ``summary.json`` records them (and the die's zones)."""
        out = law_parameters(
            self.name, mu=self.mu, m=self.m, tau_max=self.tau_max, params=self.params
        )
        if self.zones:
            out["zones"] = self.factory()(None).describe()
        if self.flattening is not None:
            out["flattening_run"] = bool(self.flattening)
        return out


@dataclass(frozen=True)
class RunSettings:
    """How a run is driven and what it keeps besides its history.

    ``progress``: a progress bar over the increments; ``snapshot_every``: a VTU snapshot every
    that many increments (0: none); ``remesh_below``: remesh after an accepted increment whose
    worst element corner sine is below it (0: never).
    """

    progress: bool = False
    snapshot_every: int = 0
    remesh_below: float = 0.0


@dataclass
class Run:
    """One scene's run: its model, law, settings, and the scene's extra history columns.

    ``extra(model) -> dict`` adds columns to each accepted increment's row (the ring's
    inner-diameter change, the multistage stage).
    """

    model: FormingModel
    law: LawSpec = field(default_factory=LawSpec)
    settings: RunSettings = field(default_factory=RunSettings)
    extra: Callable | None = None


def _snapshot(model):
    nodes = model.contact.nodes
    n = model.n_nodes
    p = np.zeros(n)
    tau = np.zeros(n)
    ph = np.zeros(n)
    if model.accepted is not None:
        p[nodes] = model.accepted.p
        tau[nodes] = model.accepted.tau
        ph[nodes] = model.contact.state.p_hist
    return {
        "x": model.x.copy(),
        "u": model.x - model.X0,
        "sigma": model.sigma.mean(1),
        "eps_p": model.eps_p.mean(1),
        "p": p,
        "tau": tau,
        "p_hist": ph,
        "height_reduction": model.height_reduction,
    }


def _record(model, law):
    ev = model.accepted
    h = model.height
    red = model.height_reduction
    F = model.die_force()
    active = ev.p > 0
    r_nodes = model.x[model.contact.nodes, 0]
    rc = float(r_nodes[active].max()) if active.any() else 0.0
    p_avg = F / (math.pi * rc**2) if rc > 0 else 0.0
    eps_hom = math.log(model.h0 / h)
    sf = float(model.mat.flow_stress(eps_hom))
    d = 2.0 * rc if rc > 0 else 2.0 * float(model.x[:, 0].max())
    fe_law = model.contact.law
    if law.name == "tresca":
        slab = float(slab_pressure_tresca(sf, law.m, d, h))
    elif law.name == "coulomb":
        slab = float(slab_pressure_coulomb(sf, law.mu, d, h, form="exact"))
    elif fe_law is not None:  # cap, sbmf (first loading): integrate the slab equation
        one = fe_law.default_law() if hasattr(fe_law, "zone_at") else fe_law  # zones: the die's
        slab = float(slab_pressure_law(sf, lambda p: one.shear_limit(p, 0.0)[0], d, h))
    else:
        slab = sf
    ph = np.asarray(model.contact.state.p_hist)
    below = active & (ev.p < ph * (1 - 1e-9))
    top = model.x[:, 1] >= model.z_die - 1e-9 * model.h0
    r_top = float(model.x[top, 0].max()) if top.any() else 0.0
    row = {
        "height_reduction": red,
        "stroke": model.h0 - h,
        "force": F,
        "contact_radius": rc,
        "avg_pressure": p_avg,
        "flow_stress_hom": sf,
        "slab_pressure": slab,
        "max_radius": float(model.x[:, 0].max()),
        "top_radius": r_top,
        "n_stick": int(np.sum(ev.status == STICK)),
        "n_slip": int(np.sum(ev.status == SLIP)),
        "n_open": int(np.sum(ev.status == OPEN)),
        "n_reload_eq25": int(below.sum()),
    }
    row.update(range_columns(model))
    if law.flattening is not None:  # a flattening comparison: fraction against strain at the die
        row.update(_die_fraction(model, active))
    zone = model.contact.zone
    if hasattr(fe_law, "zone_at") and zone is not None:  # contact nodes per zone of the die
        for i, name in enumerate(fe_law.law.names):
            row[f"n_contact_{name}"] = int(np.count_nonzero(active & (zone == i)))
    return row


def _die_fraction(model, active):
    """Area-weighted means over the die's contact nodes: contact fraction and plastic strain.

    With a two-state flattening block also ``n_below_flattening_table``: the die's contact
    nodes whose pressure lies below the block's rate table (0.02 ``H_P`` at the node's flow
    stress, :func:`frictionlaw.flattening_limit.table_pressures`), where the law reads the
    table's lowest rates, an upper bound of the flattening.
    """
    c = model.contact
    params = getattr(c.law, "params", None)
    flat = getattr(params, "flattening", None)
    two = flat is not None and flat.model == LIMIT_MODEL
    extra = {"n_below_flattening_table": 0} if two else {}
    if not active.any():
        return {"alpha_die_mean": 0.0, "eps_p_die_mean": 0.0, "alpha_f_max": 0.0, **extra}
    from ..solver.contact import nodal_areas

    area = nodal_areas(model.x, model.axi.boundary_edges, c.nodes)[active]
    eps = model.surface_plastic_strain()[active]
    if two:
        lo = table_pressures(params, sigma_y=model.mat.flow_stress(eps))[0]
        extra["n_below_flattening_table"] = int(np.count_nonzero(model.accepted.p[active] < lo))
    return {
        "alpha_die_mean": float(np.average(c.alpha[active], weights=area)),
        "eps_p_die_mean": float(np.average(eps, weights=area)),
        "alpha_f_max": float(c.state.alpha_f.max()),
        **extra,
    }


def _row(run, res, partial):
    """The history row of an accepted state (``partial``: the sub-steps before a failure)."""
    model = run.model
    row = _record(model, run.law)
    row.update(partial=int(partial), nit=res.nit, cutbacks=res.cutbacks)
    row["min_quality"] = float(element_quality(model.x, model.t, block_corners(model.axi)).min())
    row["remeshed"] = 0
    return row


def _remesh_if_needed(run, row, remesh_below):
    """Remesh when the row's worst element is below ``remesh_below``; log what happened."""
    model = run.model
    if not (remesh_below > 0 and row["min_quality"] < remesh_below):
        return
    try:
        q = remesh(model)
    except RuntimeError as exc:
        model.log.append(f"remesh skipped: {exc}")
        return
    row["remeshed"] = 1
    model.log.append(
        f"remeshed at reduction {model.height_reduction:.4f}: quality "
        f"{row['min_quality']:.3f} -> {q:.3f}"
    )


class ProgressBar:
    """A progress bar over ``total`` steps (tqdm, on stderr), or nothing when not ``show``."""

    def __init__(self, show, total, desc="increments", unit="inc"):
        self.bar = None
        if show:
            from tqdm import tqdm

            self.bar = tqdm(total=total, desc=desc, unit=unit, leave=False)

    def update(self):
        if self.bar is not None:
            self.bar.update(1)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def drive(run, stages, *, progress=None):
    """Run ``stages`` (a list of ``(target z_die, n_increments)``): ``(ok, msg, history, snaps)``.

    ``progress`` overrides the run's setting (the multistage scene's unloading shows none).
    After an accepted increment whose worst element quality (smallest corner sine) is below the
    run's ``remesh_below`` the mesh is rebuilt and the fields transferred.
    """
    model, cfg = run.model, run.settings
    rows, snaps = [], [_snapshot(model)]
    bar = ProgressBar(cfg.progress if progress is None else progress, sum(n for _, n in stages))
    ok, msg = True, "converged"
    k = 0
    try:
        for z_target, n_inc in stages:
            dz = (z_target - model.z_die) / n_inc
            for _ in range(n_inc):
                res = model.increment(dz)
                if not res.converged:
                    ok = False
                    msg = (
                        f"increment failed at height reduction {model.height_reduction:.4f} "
                        f"after {res.cutbacks} cut-backs: {res.message}"
                    )
                    if res.dz != 0.0 and model.accepted is not None:
                        # sub-steps before the failure were accepted: record where it stopped
                        rows.append(_row(run, res, partial=True) | _extra(run))
                    break
                row = _row(run, res, partial=False)
                _remesh_if_needed(run, row, cfg.remesh_below)
                rows.append(row | _extra(run))
                k += 1
                if cfg.snapshot_every and k % cfg.snapshot_every == 0:
                    snaps.append(_snapshot(model))
                bar.update()
            if not ok:
                break
    finally:
        bar.close()
    if cfg.snapshot_every and snaps[-1]["height_reduction"] != model.height_reduction:
        snaps.append(_snapshot(model))
    hist = {key: np.array([r[key] for r in rows]) for key in (rows[0] if rows else {})}
    return ok, msg, hist, snaps


def _extra(run):
    return run.extra(run.model) if run.extra is not None else {}


def _check_reduction(reduction):
    red = float(reduction)
    if not (0.0 < red < 0.9):
        raise ValueError(f"reduction must be in (0, 0.9), got {reduction!r}")
    return red


def _check_inc(n):
    n = int(n)
    if n < 1:
        raise ValueError(f"n_increments must be >= 1, got {n}")
    return n


def _solver_info(model, hist):
    """The solver's part of a scene's ``info`` (summary.json): iterations, timings, solvers."""
    lin = model.linear
    return {
        "newton_iterations": model.n_newton,
        "cutback_log": list(model.log),
        "timings": model.timings.as_dict(),
        "kernels": model.opt.kernels,
        "linear_solver": {
            "backend": lin.backend,
            "factorisations": lin.n_factor,
            "symmetric_factorisations": lin.n_factor_symmetric,
            "krylov_solves": lin.n_krylov_solves,
            "krylov_iterations": lin.n_krylov_iterations,
        },
        "tangential_stiffness": model.contact.stiffness_record(),
        "frozen_branch_evaluations": model.contact.n_frozen,
        "calibrated_range": range_summary(model, hist),
    }


def setup_info(axi, model, billet):
    """The billet, its mesh and material as ``summary.json`` records them (SI units).

    ``billet``: the scene's geometry (``{"shape": "cylinder", "diameter_m": ..., ...}``).
    """
    nr, nz = (int(n) - 1 for n in np.shape(axi.grid)) if axi.grid is not None else (None, None)
    mat = model.mat
    return {
        "billet": dict(billet),
        "mesh": {
            "elements_radial": nr,
            "elements_axial": nz,
            "n_elements": axi.n_elements,
            "n_nodes": model.n_nodes,
            "element": "4-node axisymmetric quad, B-bar",
        },
        "material": {
            "E_Pa": float(mat.E),
            "nu": float(mat.nu),
            "K_Pa": float(mat.K),
            "eps0": float(mat.eps0),
            "n": float(mat.n),
            "flow_curve": "Swift: sigma_f = K (eps0 + eps_p)^n",
        },
    }


def press(scene, run, axi, reduction, n_increments, billet=None):
    """A one-stage scene: the die pressed to ``(1 - reduction)`` of its height."""
    t0 = time.perf_counter()
    z_end = run.model.z_die * (1.0 - reduction)
    ok, msg, hist, snaps = drive(run, [(z_end, n_increments)])
    wall = time.perf_counter() - t0
    model = run.model
    info = {
        "scene": scene,
        "n_remesh": model.n_remesh,
        "law": run.law.name,
        "law_parameters": run.law.parameters(),
        "n_elements": axi.n_elements,
        "n_dof": 2 * model.n_nodes,
        **setup_info(axi, model, billet or {"shape": scene}),
        **_solver_info(model, hist),
    }
    return SceneResult(ok, msg, hist, model, wall, snaps, info)
