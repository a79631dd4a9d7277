"""The one-press scenes: cylinder upsetting and ring compression."""

from ..solver.material import DC04
from ..solver.mesh import cylinder_mesh, ring_mesh
from ..solver.model import FormingModel, SolverOptions
from .drive import LawSpec, Run, RunSettings, _check_inc, _check_reduction, press

__all__ = ["run_upsetting", "run_ring"]


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
    zones=(),
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
    :data:`fe_demo.scenes.calibrated_range.RANGE_COLUMNS`. ``info`` holds ``tangential_stiffness``
    (the stick stiffness used) and ``calibrated_range``
    (:func:`fe_demo.scenes.calibrated_range.range_summary`).

    ``zones``: zones of the die (issue 42), ``(name, params, radius)`` each: from ``radius``
    (m) outward the die runs that zone's parameter file, inside it ``params`` (law ``sbmf``;
    :mod:`fe_demo.scenes.zones`); the history gets ``n_contact_<zone>`` (contact nodes per
    zone, ``die`` the inner one), the slab column stays the inner law's, and the
    calibrated-range columns are left out (each zone has its own range).
    """
    red = _check_reduction(reduction)
    n_inc = _check_inc(n_increments)
    spec = LawSpec(law, mu, m, tau_max, params, tuple(zones))
    axi = cylinder_mesh(diameter, height, nr, nz)
    model = FormingModel(axi, material, spec.factory(), options or SolverOptions())
    settings = RunSettings(progress, snapshot_every, remesh_below)
    billet = {"shape": "cylinder", "diameter_m": float(diameter), "height_m": float(height)}
    return press("upsetting", Run(model, spec, settings), axi, red, n_inc, billet)


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
    zones=(),
):
    """Ring compression (standard 6:3:2 ring by default).

    ``remesh_below > 0`` remeshes (:func:`fe_demo.solver.remesh.remesh`) whenever the worst
    element's smallest corner sine falls below it.

    Adds the column ``inner_diameter_change``: ``(D_i - D_i0) / D_i0`` of the inner
    surface at the mid-plane. ``zones`` as in :func:`run_upsetting`.
    """
    red = _check_reduction(reduction)
    n_inc = _check_inc(n_increments)
    spec = LawSpec(law, mu, m, tau_max, params, tuple(zones))
    axi = ring_mesh(outer_diameter, inner_diameter, height, nr, nz)
    model = FormingModel(axi, material, spec.factory(), options or SolverOptions())
    node = axi.inner_mid_node
    r0 = float(model.X0[node, 0])

    def extra(mdl):
        return {
            "inner_diameter_change": (mdl.x[node, 0] - r0) / r0,
            "inner_diameter_min_change": (mdl.x[:, 0].min() - r0) / r0,
        }

    settings = RunSettings(progress, snapshot_every, remesh_below)
    billet = {
        "shape": "ring",
        "outer_diameter_m": float(outer_diameter),
        "inner_diameter_m": float(inner_diameter),
        "height_m": float(height),
    }
    return press("ring", Run(model, spec, settings, extra), axi, red, n_inc, billet)
