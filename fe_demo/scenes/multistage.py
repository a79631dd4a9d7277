"""The multistage scene: upset, unload (springback, contact opens), reload (Eq. 25 acts)."""

import time

import numpy as np

from ..solver.material import DC04
from ..solver.mesh import cylinder_mesh
from ..solver.model import FormingModel, SolverOptions
from .drive import (
    LawSpec,
    Run,
    RunSettings,
    _check_inc,
    _check_reduction,
    _solver_info,
    drive,
    setup_info,
)
from .result import SceneResult, contact_profile

__all__ = ["run_multistage"]


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
    spec = LawSpec(law, mu, m, tau_max, params)
    axi = cylinder_mesh(diameter, height, nr, nz)
    model = FormingModel(axi, material, spec.factory(), options or SolverOptions())
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
    run = Run(model, spec, RunSettings(progress, snapshot_every), extra)
    ok, msg, h1, snaps = drive(run, [(z0 * (1 - r1), n1)])
    hists = [h1]
    z_loaded = model.z_die
    if ok:
        # unload: elastic springback of the height is about sigma_f h / E; lift 3x that
        stage["k"] = 2
        sf = float(material.flow_stress(model.eps_p.max()))
        lift = 3.0 * sf / material.E * model.z_die
        ok, msg, h2, s2 = drive(run, [(model.z_die + lift, n_unload)], progress=False)
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
        ok, msg, h3, s3 = drive(run, [(z_loaded, 2 * n_unload), (z0 * (1 - r2), n3)])
        hists.append(h3)
        snaps += s3
    wall = time.perf_counter() - t0
    hists = [h for h in hists if h]
    hist = {k: np.concatenate([h[k] for h in hists]) for k in hists[0]} if hists else {}
    info = {
        "scene": "multistage",
        "law": law,
        "law_parameters": spec.parameters(),
        "reset_history": reset_history,
        "recontact_profile": best["profile"],
        "n_elements": axi.n_elements,
        **setup_info(
            axi,
            model,
            {"shape": "cylinder", "diameter_m": float(diameter), "height_m": float(height)},
        ),
        **_solver_info(model, hist),
    }
    return SceneResult(ok, msg, hist, model, wall, snaps, info)
