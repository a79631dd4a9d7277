"""Scenes: cylinder upsetting, ring compression and upset-unload-reload, with their records.

Each scene returns a :class:`SceneResult` whose ``history`` holds one row per accepted
increment; ``converged`` is False (with ``message``) when an increment failed after
all cut-backs, in which case the history ends at the last accepted state.
"""

import math
import time
from dataclasses import dataclass, field

import numpy as np

from frictionlaw import OPEN, SLIP, STICK

from .calibrated_range import range_columns, range_summary
from .laws import law_parameters, make_law_factory
from .material import DC04
from .mesh import cylinder_mesh, ring_mesh
from .model import FormingModel, SolverOptions
from .remesh import block_corners, element_quality, remesh
from .slab import slab_pressure_coulomb, slab_pressure_law, slab_pressure_tresca

__all__ = [
    "SceneResult",
    "run_upsetting",
    "run_ring",
    "run_multistage",
    "contact_profile",
]


@dataclass
class SceneResult:
    """Outcome of a scene.

    Attributes
    ----------
    converged : bool
        True if every increment was accepted.
    message : str
    history : dict of str -> ndarray
        One entry per accepted increment (see the scene functions for columns).
    model : FormingModel
        The model at its last accepted state.
    wall_time : float
        Seconds.
    snapshots : list of dict
        Nodal/element fields at selected increments (for VTU output).
    """

    converged: bool
    message: str
    history: dict
    model: FormingModel
    wall_time: float
    snapshots: list = field(default_factory=list)
    info: dict = field(default_factory=dict)

    def figures(self, title=None):
        """The run's figures, for a notebook (nothing written; not held by pyplot).

        ``{"force_stroke.png": Figure, "die_profile.png": Figure}`` (the force-stroke plot only
        with an accepted increment): the files ``fe-demo`` writes for a run.
        """
        from .output import die_profile_figure, force_stroke_figure

        title = title or str(self.info.get("scene", "run"))
        figs = {}
        if self.history:
            figs["force_stroke.png"] = force_stroke_figure([self.history], [title], title=title)
        figs["die_profile.png"] = die_profile_figure(contact_profile(self.model), title=title)
        return figs


def contact_profile(model):
    """Die-contact data of the accepted state, sorted by radius.

    Returns a dict with ``r`` (m), ``p``, ``tau`` (Pa, shear on the workpiece
    opposing outward flow is positive), ``p_hist`` (committed, Pa), ``status``.
    """
    ev = model.accepted
    nodes = model.contact.nodes
    r = model.x[nodes, 0]
    if ev is None:
        z = np.zeros(nodes.size)
        return {"r": r, "p": z, "tau": z, "p_hist": z, "status": z.astype(np.int8)}
    order = np.argsort(r)
    return {
        "r": r[order],
        "p": ev.p[order],
        "tau": ev.tau[order],
        "p_hist": np.asarray(model.contact.state.p_hist)[order],
        "status": ev.status[order],
    }


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


def _record(model, law_name, mu, m):
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
    law = model.contact.law
    if law_name == "tresca":
        slab = float(slab_pressure_tresca(sf, m, d, h))
    elif law_name == "coulomb":
        slab = float(slab_pressure_coulomb(sf, mu, d, h, form="exact"))
    elif law is not None:  # cap, sbmf (first loading): integrate the slab equation
        slab = float(slab_pressure_law(sf, lambda p: law.shear_limit(p, 0.0)[0], d, h))
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
    return row


def _drive(model, stages, law_name, mu, m, progress, snapshot_every, extra=None, remesh_below=0.0):
    """Run ``stages`` (a list of (target_z_die, n_increments)); returns (ok, msg, rows, snaps).

    After an accepted increment whose worst element quality (smallest corner sine)
    is below ``remesh_below``, the mesh is rebuilt and the fields transferred.
    """
    rows, snaps = [], [_snapshot(model)]
    bar = None
    total = sum(n for _, n in stages)
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=total, desc="increments", unit="inc", leave=False)
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
                        row = _record(model, law_name, mu, m)
                        row.update(nit=res.nit, cutbacks=res.cutbacks, partial=1)
                        row["min_quality"] = float(
                            element_quality(model.x, model.t, block_corners(model.axi)).min()
                        )
                        row["remeshed"] = 0
                        if extra is not None:
                            row.update(extra(model))
                        rows.append(row)
                    break
                row = _record(model, law_name, mu, m)
                row["partial"] = 0
                row["nit"] = res.nit
                row["cutbacks"] = res.cutbacks
                row["min_quality"] = float(
                    element_quality(model.x, model.t, block_corners(model.axi)).min()
                )
                row["remeshed"] = 0
                if remesh_below > 0 and row["min_quality"] < remesh_below:
                    try:
                        q = remesh(model)
                        row["remeshed"] = 1
                        model.log.append(
                            f"remeshed at reduction {model.height_reduction:.4f}: quality "
                            f"{row['min_quality']:.3f} -> {q:.3f}"
                        )
                    except RuntimeError as exc:
                        model.log.append(f"remesh skipped: {exc}")
                if extra is not None:
                    row.update(extra(model))
                rows.append(row)
                k += 1
                if snapshot_every and k % snapshot_every == 0:
                    snaps.append(_snapshot(model))
                if bar is not None:
                    bar.update(1)
            if not ok:
                break
    finally:
        if bar is not None:
            bar.close()
    if snapshot_every and (not snaps or snaps[-1]["height_reduction"] != model.height_reduction):
        snaps.append(_snapshot(model))
    hist = {key: np.array([r[key] for r in rows]) for key in (rows[0] if rows else {})}
    return ok, msg, hist, snaps


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


def _press(
    scene,
    model,
    axi,
    red,
    n_inc,
    law,
    mu,
    m,
    progress,
    snapshot_every,
    extra,
    remesh_below,
    law_params,
):
    """One-stage scene: press the die to ``(1 - red)`` of its height in ``n_inc`` increments."""
    t0 = time.perf_counter()
    z_end = model.z_die * (1.0 - red)
    ok, msg, hist, snaps = _drive(
        model, [(z_end, n_inc)], law, mu, m, progress, snapshot_every, extra, remesh_below
    )
    wall = time.perf_counter() - t0
    info = {
        "scene": scene,
        "n_remesh": model.n_remesh,
        "law": law,
        "law_parameters": law_params,
        "n_elements": axi.n_elements,
        "n_dof": 2 * model.n_nodes,
        **_solver_info(model, hist),
    }
    return SceneResult(ok, msg, hist, model, wall, snaps, info)


def run_upsetting(
    law="sbmf",
    *,
    mu=0.1,
    m=0.3,
    tau_max=None,
    params=None,
    diameter=20e-3,
    height=10e-3,
    nr=64,
    nz=None,
    reduction=0.5,
    n_increments=50,
    material=DC04,
    options=None,
    progress=False,
    snapshot_every=0,
    remesh_below=0.0,
):
    """Cylinder upsetting between flat dies (``remesh_below`` as in :func:`run_ring`).

    The default law is the one ``fe-demo upsetting`` runs: ``sbmf`` with ``params`` (the shipped
    illustrative parameters when ``params`` is None); ``fe-demo ring`` and :func:`run_ring`
    default to ``tresca`` (the ring chart's law), ``multistage`` to ``sbmf``.

    History columns: ``height_reduction`` (fraction of h0), ``stroke`` (m), ``force``
    (N), ``contact_radius`` (m), ``avg_pressure`` (force over contact area, Pa),
    ``flow_stress_hom`` (flow stress at ``ln(h0/h)``), ``slab_pressure`` (slab-method
    average pressure of the same law, Pa), ``max_radius``, ``top_radius`` (m),
    counts of stick/slip/open contact nodes, ``n_reload_eq25`` (nodes in contact with
    ``p < p_hist``, i.e. on Eq. 25), ``nit``, ``cutbacks``, ``partial`` (1 for the last row of
    a run that stopped on a failed increment: the sub-steps it accepted before failing); with a
    parameter file that records its calibrated range,
    :data:`fe_demo.calibrated_range.RANGE_COLUMNS`. ``info`` holds ``tangential_stiffness``
    (the stick stiffness used) and ``calibrated_range``
    (:func:`fe_demo.calibrated_range.range_summary`).
    """
    red = _check_reduction(reduction)
    n_inc = _check_inc(n_increments)
    factory = make_law_factory(law, mu=mu, m=m, tau_max=tau_max, params=params)
    axi = cylinder_mesh(diameter, height, nr, nz)
    model = FormingModel(axi, material, factory, options or SolverOptions())
    return _press(
        "upsetting",
        model,
        axi,
        red,
        n_inc,
        law,
        mu,
        m,
        progress,
        snapshot_every,
        None,
        remesh_below,
        law_parameters(law, mu=mu, m=m, tau_max=tau_max, params=params),
    )


def run_ring(
    law="tresca",
    *,
    mu=0.1,
    m=0.3,
    tau_max=None,
    params=None,
    outer_diameter=18e-3,
    inner_diameter=9e-3,
    height=6e-3,
    nr=24,
    nz=None,
    reduction=0.5,
    n_increments=50,
    material=DC04,
    options=None,
    progress=False,
    snapshot_every=0,
    remesh_below=0.0,
):
    """Ring compression (standard 6:3:2 ring by default).

    ``remesh_below > 0`` remeshes (:func:`fe_demo.remesh.remesh`) whenever the worst
    element's smallest corner sine falls below it.

    Adds the column ``inner_diameter_change``: ``(D_i - D_i0) / D_i0`` of the inner
    surface at the mid-plane.
    """
    red = _check_reduction(reduction)
    n_inc = _check_inc(n_increments)
    factory = make_law_factory(law, mu=mu, m=m, tau_max=tau_max, params=params)
    axi = ring_mesh(outer_diameter, inner_diameter, height, nr, nz)
    model = FormingModel(axi, material, factory, options or SolverOptions())
    node = axi.inner_mid_node
    r0 = float(model.X0[node, 0])

    def extra(mdl):
        return {
            "inner_diameter_change": (mdl.x[node, 0] - r0) / r0,
            "inner_diameter_min_change": (mdl.x[:, 0].min() - r0) / r0,
        }

    return _press(
        "ring",
        model,
        axi,
        red,
        n_inc,
        law,
        mu,
        m,
        progress,
        snapshot_every,
        extra,
        remesh_below,
        law_parameters(law, mu=mu, m=m, tau_max=tau_max, params=params),
    )


def run_multistage(
    law="sbmf",
    *,
    mu=0.1,
    m=0.3,
    tau_max=None,
    params=None,
    diameter=20e-3,
    height=10e-3,
    nr=24,
    nz=None,
    first_reduction=0.3,
    reduction=0.45,
    n_increments=30,
    n_unload=4,
    reset_history=False,
    material=DC04,
    options=None,
    progress=False,
    snapshot_every=0,
):
    """Upset to ``first_reduction``, unload (springback, contact opens), reload to ``reduction``.

    The unload lifts the die until every node has left contact; the reload first
    returns to the stage-1 die position in ``2 n_unload`` fine increments (where the
    nodes come back below their ``p_hist`` and Eq. 25 applies), then goes on. With
    ``reset_history=True`` the committed ``p_hist`` is wiped after unloading (a law
    without history), for comparison. Adds the columns ``stage`` (1 load, 2 unload,
    3 reload) and ``tau_diff_eq25`` (largest ``|tau(p, p_hist) - tau(p, 0)|`` over the
    contact nodes, Pa: how much Eq. 25 changes the friction limit).
    """
    r1 = _check_reduction(first_reduction)
    r2 = _check_reduction(reduction)
    if r2 <= r1:
        raise ValueError("reduction must exceed first_reduction")
    n_inc = _check_inc(n_increments)
    factory = make_law_factory(law, mu=mu, m=m, tau_max=tau_max, params=params)
    axi = cylinder_mesh(diameter, height, nr, nz)
    model = FormingModel(axi, material, factory, options or SolverOptions())
    stage = {"k": 1}
    best = {"n": -1, "profile": None}

    def extra(mdl):
        ev = mdl.accepted
        law_obj = mdl.contact.law
        diff = 0.0
        n25 = 0
        if law_obj is not None and ev is not None and (ev.p > 0).any():
            ph = np.asarray(mdl.contact.state.p_hist)
            act = ev.p > 0
            t_h = law_obj.shear_limit(ev.p[act], ph[act])[0]
            t_0 = law_obj.shear_limit(ev.p[act], 0.0)[0]
            diff = float(np.max(np.abs(t_h - t_0)))
            n25 = int(np.sum(ev.p[act] < ph[act]))
            if stage["k"] == 3 and n25 > best["n"]:
                prof = contact_profile(mdl)
                order = np.argsort(mdl.x[mdl.contact.nodes, 0])
                on = ev.p[order] > 0
                lim_h = np.zeros(on.size)
                lim_0 = np.zeros(on.size)
                lim_h[on] = law_obj.shear_limit(ev.p[order][on], ph[order][on])[0]
                lim_0[on] = law_obj.shear_limit(ev.p[order][on], 0.0)[0]
                prof.update(
                    tau_limit=lim_h,
                    tau_limit_first_loading=lim_0,
                    height_reduction=mdl.height_reduction,
                )
                best.update(n=n25, profile=prof)
        return {"stage": stage["k"], "tau_diff_eq25": diff}

    t0 = time.perf_counter()
    z0 = model.z_die
    n1 = max(1, round(n_inc * r1 / r2))
    ok, msg, h1, snaps = _drive(
        model, [(z0 * (1 - r1), n1)], law, mu, m, progress, snapshot_every, extra
    )
    hists = [h1]
    z_loaded = model.z_die
    if ok:
        # unload: elastic springback of the height is about sigma_f h / E; lift 3x that
        stage["k"] = 2
        sf = float(material.flow_stress(model.eps_p.max()))
        lift = 3.0 * sf / material.E * model.z_die
        ok, msg, h2, s2 = _drive(
            model, [(model.z_die + lift, n_unload)], law, mu, m, False, snapshot_every, extra
        )
        hists.append(h2)
        snaps += s2
        if ok and model.accepted is not None and (model.accepted.p > 0).any():
            ok, msg = False, "contact did not open during unloading"
    if ok:
        if reset_history:
            model.contact.reset_history()
        stage["k"] = 3
        n3 = max(1, n_inc - n1)
        # re-contact back to the stage-1 die position in fine steps (Eq. 25 acts here), then on
        ok, msg, h3, s3 = _drive(
            model,
            [(z_loaded, 2 * n_unload), (z0 * (1 - r2), n3)],
            law,
            mu,
            m,
            progress,
            snapshot_every,
            extra,
        )
        hists.append(h3)
        snaps += s3
    wall = time.perf_counter() - t0
    hists = [h for h in hists if h]
    hist = {k: np.concatenate([h[k] for h in hists]) for k in hists[0]} if hists else {}
    info = {
        "scene": "multistage",
        "law": law,
        "law_parameters": law_parameters(law, mu=mu, m=m, tau_max=tau_max, params=params),
        "reset_history": reset_history,
        "recontact_profile": best["profile"],
        "n_elements": axi.n_elements,
        **_solver_info(model, hist),
    }
    return SceneResult(ok, msg, hist, model, wall, snaps, info)
