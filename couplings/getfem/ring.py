"""Ring compression in GetFEM with the ``frictionlaw`` runtime at the die-contact nodes.

GetFEM (Debian's ``python3-getfem``) supplies the mesh, the finite elements, the
finite-strain J2 plasticity (its ``Simo_Miehe`` brick, displacement / plastic
multiplier / pressure formulation) and the assembly of the bulk tangent and
residual. This script supplies what a host code's contact algorithm does around
a friction user routine: a rigid flat die, a nodal penalty for the normal
pressure, and per contact node a call of :func:`frictionlaw.traction_update` with
the node's :class:`frictionlaw.HistoryState` (``p_hist``). The Newton loop is ours
(GetFEM's ``Model.solve`` cannot call back into Python per iteration): each
iteration GetFEM assembles, the contact terms are added to its tangent and
residual, and the linear system is solved with SciPy.

GetFEM has no axisymmetric finite-strain plasticity, so the ring is a 3D wedge
(one element over ``--sector`` degrees) with symmetry conditions on both cut
faces: ``u_y = 0`` on the ``theta = 0`` face (removed dofs) and a penalty on the
normal displacement of the ``theta = sector`` face. The half height is modelled
(``u_z = 0`` on the mid-plane), as in ``fe-demo ring``.

``p_hist`` lives in one ``HistoryState`` over the candidate nodes (every boundary
node off the mid-plane and the cut faces, as in ``fe-demo``): every Newton
iteration proposes a trial from the committed history; ``commit()`` runs only
after the increment converged (together with GetFEM's
``finite_strain_elastoplasticity_next_iter``), ``rollback()`` on a cut-back, which
also restores every GetFEM variable.

Run it with a Python in which ``import getfem`` works (Debian's ``/usr/bin/python3``
with ``python3-getfem python3-numba python3-scipy``) and the repository root on
``PYTHONPATH``::

    PYTHONPATH=$PWD /usr/bin/python3 couplings/getfem/ring.py --law tresca --m 0.3

It writes ``history.csv`` (``height_reduction, force, inner_diameter_change`` first,
as ``fe-demo ring``; ``stage`` last) and ``summary.json`` (with the die-face ``p_hist``
after each stage) into ``--out``. ``--first-reduction R1`` runs press-lift-press
(``fe-demo multistage``'s schedule, :func:`schedule`): Eq. 25 acts on the reload. Exit status 0 when every
increment converged, 1 when the run stopped on a failed increment, 2 for bad input.
"""

import argparse
import json
import math
import os
import shutil
import sys
import tempfile
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["Material", "RingSetup", "run", "main", "HISTORY_COLUMNS"]

HISTORY_COLUMNS = (
    "height_reduction",
    "force",
    "inner_diameter_change",
    "stroke",
    "contact_radius",
    "n_stick",
    "n_slip",
    "n_open",
    "n_reload_eq25",
    "max_p_hist",
    "nit",
    "cutbacks",
    "min_plastic_multiplier",
    "stage",
)

_EXAMPLE_PARAMS = Path(__file__).resolve().parents[2] / "fe_demo" / "data" / "sbmf_example.json"


@dataclass(frozen=True)
class Material:
    """Swift-hardening J2 material (SI); the defaults are ``fe-demo``'s DC04-like set."""

    E: float = 210e9
    nu: float = 0.3
    K: float = 530e6
    eps0: float = 0.006
    n: float = 0.24

    def flow_stress(self, eps_p):
        """Swift flow stress ``K (eps0 + eps_p) ** n`` (Pa)."""
        return self.K * (self.eps0 + eps_p) ** self.n


@dataclass
class RingSetup:
    """Geometry, mesh and solver settings of the ring run (SI units)."""

    law: str = "tresca"
    m: float = 0.3
    params: str = ""
    outer_diameter: float = 18e-3
    inner_diameter: float = 9e-3
    height: float = 6e-3
    nr: int = 16
    nz: int = 0  # 0: near-square elements, round(nr * (h/2) / wall) as in fe-demo
    sector_deg: float = 5.0
    reduction: float = 0.5
    increments: int = 50
    penalty_factor: float = 10.0
    rtol: float = 1e-6
    max_iter: int = 25
    max_cutbacks: int = 6
    first_reduction: float = 0.0  # > 0: press to it, lift, press again (Eq. 25 on reload)
    n_unload: int = 4
    lift_factor: float = 3.0
    material: Material = field(default_factory=Material)


def _check(setup):
    """Bad input: a clear error naming the parameter, before any work."""
    if setup.law not in ("none", "tresca", "sbmf"):
        raise ValueError(f"law must be one of 'none', 'tresca', 'sbmf', got {setup.law!r}")
    if not 0.0 <= setup.m <= 1.0:
        raise ValueError(f"m must be in [0, 1], got {setup.m!r}")
    if not 0.0 < setup.reduction < 0.9:
        raise ValueError(f"reduction must be in (0, 0.9), got {setup.reduction!r}")
    if int(setup.nz) < 0:
        raise ValueError(f"nz must be >= 0 (0: near-square elements), got {setup.nz!r}")
    for name in ("nr", "increments"):
        if int(getattr(setup, name)) < 1:
            raise ValueError(f"{name} must be >= 1, got {getattr(setup, name)!r}")
    if not 0.0 < setup.sector_deg <= 30.0:
        raise ValueError(f"sector_deg must be in (0, 30], got {setup.sector_deg!r}")
    if not 0.0 < setup.inner_diameter < setup.outer_diameter:
        raise ValueError("inner_diameter must be in (0, outer_diameter)")
    if not 0.0 <= setup.first_reduction < setup.reduction:
        raise ValueError(
            f"first_reduction must be in [0, reduction = {setup.reduction!r}) (0: one press), "
            f"got {setup.first_reduction!r}"
        )
    if int(setup.n_unload) < 1:
        raise ValueError(f"n_unload must be >= 1, got {setup.n_unload!r}")
    if setup.law == "sbmf" and setup.params and not Path(setup.params).is_file():
        raise ValueError(f"params: no such file {setup.params!r}")


# ---------------------------------------------------------------------- mesh
def _wedge_mesh(gf, s):
    """Hexahedral wedge: ``nr`` x 1 x ``nz`` elements over (r, theta, z)."""
    ri, ro, hh = s.inner_diameter / 2, s.outer_diameter / 2, s.height / 2
    r = np.linspace(ri, ro, s.nr + 1)
    z = np.linspace(0.0, hh, _nz(s) + 1)
    mesh = gf.Mesh("cartesian Q1", r, np.array([0.0, 1.0]), z)
    p = mesh.pts()
    th = math.radians(s.sector_deg) * p[1]
    mesh.set_pts(np.vstack([p[0] * np.cos(th), p[0] * np.sin(th), p[2]]))
    return mesh, r, z


def _nz(s):
    """Elements over the half height; ``nz = 0`` picks near-square elements."""
    if s.nz:
        return int(s.nz)
    return max(1, round(s.nr * (s.height / 2) / ((s.outer_diameter - s.inner_diameter) / 2)))


def _h_el(s):
    return min((s.outer_diameter - s.inner_diameter) / 2 / s.nr, s.height / 2 / _nz(s))


@dataclass
class _Regions:
    mid: int = 1  # z = 0, u_z = 0
    cut0: int = 2  # theta = 0, u_y = 0
    cut1: int = 3  # theta = sector, u . n = 0 (penalty)
    free: int = 4  # top, inner, outer: die-contact candidates


def _set_regions(mesh, th):
    faces = mesh.outer_faces()
    nrm = mesh.normal_of_faces(faces)
    n1 = np.array([-math.sin(th), math.cos(th), 0.0])
    is_mid = nrm[2] < -0.99
    is_cut0 = nrm[1] < -0.99
    is_cut1 = np.abs(n1 @ nrm - 1.0) < 1e-6
    rg = _Regions()
    mesh.set_region(rg.mid, faces[:, is_mid])
    mesh.set_region(rg.cut0, faces[:, is_cut0])
    mesh.set_region(rg.cut1, faces[:, is_cut1])
    mesh.set_region(rg.free, faces[:, ~(is_mid | is_cut0 | is_cut1)])
    return rg, faces[:, ~(is_mid | is_cut0 | is_cut1)]


def _face_nodes(mesh, faces):
    """Node ids (4 per quadrilateral face, in cyclic order) of boundary faces."""
    out = []
    for cv, f in faces.T:
        pid = mesh.pid_in_faces(np.array([[cv], [f]]))
        xyz = mesh.pts(pid)
        c = xyz.mean(1)
        nrm = mesh.normal_of_face(int(cv), int(f))
        a = xyz[:, 0] - c
        b = np.cross(nrm, a)
        ang = np.arctan2((xyz - c[:, None]).T @ b, (xyz - c[:, None]).T @ a)
        out.append(pid[np.argsort(ang)])
    return np.array(out)


def _quad_areas(x, quads):
    """Area of each (possibly warped) quadrilateral: half the cross product of its diagonals."""
    d1 = x[quads[:, 2]] - x[quads[:, 0]]
    d2 = x[quads[:, 3]] - x[quads[:, 1]]
    return 0.5 * np.linalg.norm(np.cross(d1, d2), axis=1)


# ---------------------------------------------------------------------- model
@dataclass
class _Model:
    gf: object
    md: object
    mesh: object
    mim: object
    dof: np.ndarray  # (n_nodes, 3) global model index of each node's u components, -1 if fixed
    X: np.ndarray  # (n_nodes, 3) reference coordinates
    plast_args: tuple
    n_total: int
    keep: tuple  # GetFEM objects the model refers to (freed with their Python wrappers)


def _build_model(gf, s, mesh, rg):
    mat = s.material
    N = 3
    mfN = gf.MeshFem(mesh, N)
    mfN.set_classical_fem(1)
    d0 = mfN.basic_dof_on_region(rg.mid)[2::N]
    d1 = mfN.basic_dof_on_region(rg.cut0)[1::N]
    kept = np.setdiff1d(np.arange(mfN.nb_basic_dof()), np.union1d(d0, d1))
    mfu = gf.MeshFem("partial", mfN, kept)
    mfp = gf.MeshFem(mesh, 1)
    mfp.set_classical_discontinuous_fem(0)
    mfksi = gf.MeshFem(mesh, 1)
    mfksi.set_classical_discontinuous_fem(
        0
    )  # per-element multiplier: a continuous one stalls Newton
    mim = gf.MeshIm(mesh, 3)
    mimd1 = gf.MeshImData(mim, -1, [1])
    mimd6 = gf.MeshImData(mim, -1, [6])

    md = gf.Model("real")
    md.add_fem_variable("u", mfu)
    md.add_fem_variable("p", mfp)
    md.add_fem_variable("ksi", mfksi)
    md.add_im_data("gamma0", mimd1)
    md.add_im_data("invCp0", mimd6)
    md.set_variable("invCp0", np.tile([1.0, 1, 1, 0, 0, 0], mimd6.nbpts()))
    # GetFEM's Simo-Miehe law takes Frobenius norms: yield limit sqrt(2/3) sigma_f(eps_p),
    # hardening variable t = sqrt(3/2) eps_p.
    c = math.sqrt(2.0 / 3.0)
    gf.asm_define_function(
        "swift_hardening",
        1,
        f"{c!r}*{mat.K!r}*pow({mat.eps0!r}+{c!r}*t,{mat.n!r})",
    )
    bulk = mat.E / (3.0 * (1.0 - 2.0 * mat.nu))
    shear = mat.E / (2.0 * (1.0 + mat.nu))
    plast_args = (
        mim,
        "Simo_Miehe",
        "displacement_and_plastic_multiplier_and_pressure",
        "u",
        "ksi",
        "p",
        "gamma0",
        "invCp0",
        repr(bulk),
        repr(shear),
        "swift_hardening",
    )
    md.add_finite_strain_elastoplasticity_brick(*plast_args)
    th = math.radians(s.sector_deg)
    h_el = _h_el(s)
    md.add_initialized_data("n_cut", [-math.sin(th), math.cos(th), 0.0])
    md.add_linear_term(mim, f"{1e3 * mat.E / h_el!r}*(u.n_cut)*(Test_u.n_cut)", rg.cut1)

    # node -> model dof index of each displacement component
    n_nodes = mesh.nbpts()
    X = mesh.pts().T.copy()
    dofx = mfN.basic_dof_nodes()[:, 0::N].T
    node_of = _match_points(X, dofx)
    inv = np.full(mfN.nb_basic_dof(), -1)
    inv[kept] = np.arange(kept.size)
    off = md.interval_of_variable("u")[0]
    dof = np.full((n_nodes, N), -1)
    for c_ in range(N):
        loc = inv[N * np.arange(dofx.shape[0]) + c_]
        dof[node_of, c_] = np.where(loc >= 0, loc + off, -1)
    n_total = int(md.nbdof())
    keep = (mfN, mfu, mfp, mfksi, mimd1, mimd6)
    return _Model(gf, md, mesh, mim, dof, X, plast_args, n_total, keep)


def _match_points(X, Y):
    """Index ``i`` of the row of ``X`` equal to each row of ``Y``."""
    from scipy.spatial import cKDTree

    d, i = cKDTree(X).query(Y)
    if d.max() > 1e-9 * np.abs(X).max():
        raise RuntimeError("dof/node matching failed")
    return i


# ---------------------------------------------------------------------- contact
@dataclass
class _Contact:
    nodes: np.ndarray
    quads: np.ndarray  # candidate faces, node ids
    law: object
    eps_n: float
    state: object
    t_old: np.ndarray


def _contact_terms(model, ct, u_nodes, u_start, z_die, area):
    """Penalty normal force and friction from ``frictionlaw`` at the candidate nodes.

    Returns the forces on the workpiece (n, 3), the tangent blocks and the evaluation.
    """
    from frictionlaw import traction_update

    x = model.X[ct.nodes] + u_nodes
    g = x[:, 2] - z_die
    active = g > 0
    p = np.where(active, ct.eps_n * g, 0.0)
    n = ct.nodes.size
    force = np.zeros((n, 3))
    force[:, 2] = -p * area
    kzz = np.where(active, ct.eps_n * area, 0.0)
    if ct.law is None:
        ct.state.propose(p)
        t = np.zeros((n, 2))
        status = np.where(active, 2, 0).astype(np.int8)
        ktt = np.zeros((n, 2, 2))
        ktz = np.zeros((n, 2))
    else:
        slip = u_nodes[:, :2] - u_start[:, :2]
        res = traction_update(ct.law, p, slip, ct.t_old, ct.eps_n, ct.state)
        if not getattr(ct.law, "uses_history", False):
            ct.state.propose(p)  # p_hist tracked for output whatever the law
        t, status = res.traction, res.status
        force[:, :2] = -t * area[:, None]
        ktt = res.dt_dslip * area[:, None, None]
        ktz = np.where(active[:, None], res.dt_dp * ct.eps_n * area[:, None], 0.0)
    return force, kzz, ktt, ktz, p, t, status


def _contact_matrix(model, ct, kzz, ktt, ktz):
    """Tangent of minus the contact force, in the model's global numbering."""
    d = model.dof[ct.nodes]
    rows, cols, vals = [], [], []

    def put(i, j, v):
        ok = (i >= 0) & (j >= 0) & (v != 0)
        rows.append(i[ok])
        cols.append(j[ok])
        vals.append(v[ok])

    put(d[:, 2], d[:, 2], kzz)
    for a in range(2):
        put(d[:, a], d[:, 2], ktz[:, a])
        for b in range(2):
            put(d[:, a], d[:, b], ktt[:, a, b])
    n = model.n_total
    return sp.csc_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    )


def _nodal_areas(model, ct, u_all):
    """Lumped area (a quarter of each adjacent candidate face) at the current configuration."""
    x = model.X + u_all
    a = _quad_areas(x, ct.quads)
    area = np.zeros(model.X.shape[0])
    np.add.at(area, ct.quads.ravel(), np.repeat(a / 4.0, 4))
    return area[ct.nodes]


# ---------------------------------------------------------------------- solve
def _node_disp(model, v):
    u = np.zeros(model.dof.shape)
    ok = model.dof >= 0
    u[ok] = v[model.dof[ok]]
    return u


def _to_scipy(K):
    jc, ir = K.csc_ind()
    return sp.csc_matrix((K.csc_val(), ir, jc), shape=K.size())


@dataclass
class _Increment:
    converged: bool
    nit: int
    message: str
    p: np.ndarray = None
    t: np.ndarray = None
    status: np.ndarray = None
    force: np.ndarray = None


def _residual(model, ct, v, z_die, u_start_nodes, area, option):
    """GetFEM's assembly plus the contact forces at ``v``; returns (rhs, contact terms)."""
    md = model.md
    md.to_variables(v)
    u_all = _node_disp(model, v)
    terms = _contact_terms(model, ct, u_all[ct.nodes], u_start_nodes, z_die, area)
    md.assembly(option)
    rhs = np.array(md.rhs())
    dc = model.dof[ct.nodes]
    ok = dc >= 0
    np.add.at(rhs, dc[ok], terms[0][ok])
    return rhs, terms


def _newton(model, ct, s, z_die, u_start_nodes, area, f_ref):
    """Newton iterations with a backtracking line search on the residual norm."""
    md = model.md
    v = md.from_variables()
    rhs, terms = _residual(model, ct, v, z_die, u_start_nodes, area, "build_all")
    res = np.linalg.norm(rhs)
    for it in range(1, s.max_iter + 1):
        if not np.isfinite(res):
            return _Increment(False, it, "non-finite residual")
        force, kzz, ktt, ktz = terms[:4]
        K = _to_scipy(md.tangent_matrix()) + _contact_matrix(model, ct, kzz, ktt, ktz)
        try:
            dv = spla.spsolve(K.tocsc(), rhs)
        except RuntimeError as exc:  # singular factor
            return _Increment(False, it, f"linear solve failed: {exc}")
        if not np.all(np.isfinite(dv)):
            return _Increment(False, it, "linear solve gave non-finite values")
        alpha = 1.0
        while True:
            rhs1, terms1 = _residual(
                model, ct, v + alpha * dv, z_die, u_start_nodes, area, "build_rhs"
            )
            res1 = np.linalg.norm(rhs1)
            if res1 < res or alpha < 1e-2:
                break
            alpha *= 0.5
        v = v + alpha * dv
        force, _, _, _, p, t, status = terms1
        if np.isfinite(res1) and res1 <= s.rtol * max(f_ref, np.linalg.norm(force)):
            return _Increment(True, it, "converged", p, t, status, force)
        rhs, terms, res = rhs1, terms1, res1  # the line search evaluated the residual at v
        md.assembly("build_matrix")
    return _Increment(False, s.max_iter, f"no convergence in {s.max_iter} iterations")


def _law(s, model_height_ratio):
    import frictionlaw as fl

    if s.law == "none":
        return None
    if s.law == "tresca":
        eps = max(math.log(model_height_ratio), 0.0)
        return fl.Tresca(s.m, float(s.material.flow_stress(eps)) / math.sqrt(3.0))
    path = s.params or str(_EXAMPLE_PARAMS)
    return fl.SBMFLaw(fl.FrictionParams.from_json(path))


def run(setup, progress=False):
    """Run the ring; returns ``(converged, message, rows, info)``."""
    _check(setup)
    import getfem as gf

    import frictionlaw as fl

    gf.util_trace_level(0)
    s = setup
    t0 = time.perf_counter()
    mesh, r, z = _wedge_mesh(gf, s)
    rg, cand_faces = _set_regions(mesh, math.radians(s.sector_deg))
    model = _build_model(gf, s, mesh, rg)
    quads = _face_nodes(mesh, cand_faces)
    nodes = np.unique(quads)
    h_el = _h_el(s)
    eps_n = s.penalty_factor * s.material.E / h_el
    ct = _Contact(nodes, quads, None, eps_n, fl.HistoryState(nodes.size), np.zeros((nodes.size, 2)))
    hh0 = s.height / 2
    ri = s.inner_diameter / 2
    inner_mid = int(np.flatnonzero((np.abs(model.X[:, 0] - ri) < 1e-12) & (model.X[:, 2] == 0))[0])
    scale = 2.0 * math.pi / math.radians(s.sector_deg)
    top_area = 0.5 * math.radians(s.sector_deg) * ((s.outer_diameter / 2) ** 2 - ri**2)
    f_ref = 1e-3 * s.material.flow_stress(0.0) * top_area
    z_die = hh0
    rows, log, profiles = [], [], []
    ok, message = True, "converged"
    n_newton = 0
    iu = model.md.interval_of_variable("u")
    iu = slice(iu[0], iu[0] + iu[1])
    for z_end, n_seg, stage in schedule(s):
        dz0 = (z_end - z_die) / n_seg
        sgn = -1.0 if dz0 < 0 else 1.0
        dz = dz0
        du_prev, dz_prev = None, None  # no predictor across a change of direction
        while sgn * (z_end - z_die) > 1e-12 * hh0:
            backup = model.md.from_variables()
            u_start = _node_disp(model, backup)
            area = _nodal_areas(model, ct, u_start)
            ct.law = _law(s, hh0 / z_die)
            cut = 0
            while True:
                target = z_die + dz
                target = max(target, z_end) if sgn < 0 else min(target, z_end)
                if du_prev is not None and cut == 0:  # predictor: the last increment's rate
                    guess = backup.copy()
                    guess[iu] += du_prev * ((target - z_die) / dz_prev)
                    model.md.to_variables(guess)
                inc = _newton(model, ct, s, target, u_start[ct.nodes], area, f_ref)
                n_newton += inc.nit
                if inc.converged:
                    break
                model.md.to_variables(backup)
                ct.state.rollback()
                cut += 1
                log.append(f"cut-back at die z {target:.6e} m: {inc.message}")
                if cut > s.max_cutbacks:
                    ok = False
                    message = (
                        f"increment failed at height reduction {1 - z_die / hh0:.4f} "
                        f"(stage {stage}) after {s.max_cutbacks} cut-backs: {inc.message}"
                    )
                    break
                dz *= 0.5
            if not ok:
                break
            model.md.finite_strain_elastoplasticity_next_iter(*model.plast_args)
            ct.state.commit()
            ct.t_old = np.where(inc.p[:, None] > 0, inc.t, 0.0)
            v = model.md.from_variables()
            du_prev, dz_prev = v[iu] - backup[iu], target - z_die
            z_die = target
            if cut == 0:  # grow back to at most the nominal step
                dz = sgn * min(2.0 * abs(dz), abs(dz0))
            u_all = _node_disp(model, v)
            row = _row(s, model, ct, inc, u_all, z_die, hh0, inner_mid, scale, cut)
            row["stage"] = stage
            rows.append(row)
            if progress:
                print(
                    f"stage {stage} reduction {row['height_reduction']:.3f} force "
                    f"{row['force']:.4e} N inner {row['inner_diameter_change']:+.4f} "
                    f"nit {inc.nit}",
                    file=sys.stderr,
                )
        if not ok:
            break
        if stage == 2 and rows and rows[-1]["n_open"] < ct.nodes.size:
            ok, message = False, "contact did not open during the lift (raise lift_factor)"
            break
        profiles.append(_profile(model, ct, _node_disp(model, model.md.from_variables()), rows))
    info = {
        "code": "GetFEM",
        "getfem_version": _getfem_version(),
        "setup": _jsonable(asdict(s)),
        "n_hexahedra": int(s.nr * _nz(s)),
        "n_dof": int(model.n_total),
        "n_contact_candidates": int(nodes.size),
        "newton_iterations": int(n_newton),
        "cutback_log": log,
        "wall_time_s": time.perf_counter() - t0,
        "converged": ok,
        "message": message,
        "schedule": [[z, n, st] for z, n, st in schedule(s)],
    }
    info["p_hist_profiles"] = profiles
    return ok, message, rows, info


def schedule(s):
    """Die targets ``[(z_die, n_increments, stage), ...]`` of a run (half height model).

    One press: ``[(h/2 (1 - reduction), increments, 1)]``. With ``first_reduction > 0``,
    ``fe-demo multistage``'s schedule: press to ``first_reduction`` (stage 1, the share
    ``first_reduction / reduction`` of the increments), lift the die by ``lift_factor``
    times the elastic springback ``sigma_f h / E`` (stage 2, ``n_unload`` increments; every
    node must open), come back to the stage-1 position in ``2 n_unload`` increments and
    press on to ``reduction`` (stage 3: Eq. 25 acts where ``p < p_hist``).
    """
    hh0 = s.height / 2
    z_end = hh0 * (1.0 - s.reduction)
    if not s.first_reduction:
        return [(z_end, int(s.increments), 1)]
    z1 = hh0 * (1.0 - s.first_reduction)
    n1 = max(1, round(s.increments * s.first_reduction / s.reduction))
    sf = float(s.material.flow_stress(math.log(hh0 / z1)))
    lift = s.lift_factor * sf / s.material.E * z1
    n3 = max(1, int(s.increments) - n1)
    n_un = int(s.n_unload)
    return [(z1, n1, 1), (z1 + lift, n_un, 2), (z1, 2 * n_un, 3), (z_end, n3, 3)]


def _profile(model, ct, u_all, rows):
    """Committed ``p_hist`` of the die-face nodes after a stage: reference and current radius."""
    x = model.X[ct.nodes] + u_all[ct.nodes]
    top = model.X[ct.nodes, 2] >= model.X[:, 2].max() - 1e-12
    ph = np.asarray(ct.state.p_hist)
    order = np.argsort(model.X[ct.nodes, 0][top])
    r0 = np.hypot(model.X[ct.nodes, 0], model.X[ct.nodes, 1])[top][order]
    r = np.hypot(x[:, 0], x[:, 1])[top][order]
    return {
        "stage": int(rows[-1]["stage"]) if rows else 0,
        "height_reduction": float(rows[-1]["height_reduction"]) if rows else 0.0,
        "r0": r0.tolist(),
        "r": r.tolist(),
        "p_hist": ph[top][order].tolist(),
    }


def _row(s, model, ct, inc, u_all, z_die, hh0, inner_mid, scale, cut):
    x = model.X + u_all
    active = inc.p > 0
    xc = x[ct.nodes]
    rc = float(np.hypot(xc[active, 0], xc[active, 1]).max()) if active.any() else 0.0
    ph = np.asarray(ct.state.p_hist)
    r0 = model.X[inner_mid, 0]
    return {
        "height_reduction": 1.0 - z_die / hh0,
        "force": float(-inc.force[:, 2].sum() * scale),
        "inner_diameter_change": float((np.hypot(x[inner_mid, 0], x[inner_mid, 1]) - r0) / r0),
        "stroke": 2.0 * (hh0 - z_die),
        "contact_radius": rc,
        "n_stick": int(np.sum(inc.status == 1)),
        "n_slip": int(np.sum(inc.status == 2)),
        "n_open": int(np.sum(inc.status == 0)),
        "n_reload_eq25": int(np.sum(active & (inc.p < ph * (1 - 1e-9)))),
        "max_p_hist": float(ph.max()),
        "nit": inc.nit,
        "cutbacks": cut,
        "min_plastic_multiplier": float(np.min(model.md.variable("ksi"))),
    }


def _getfem_version():
    try:
        from importlib.metadata import version

        return version("getfem")
    except Exception:  # noqa: BLE001 - Debian's package has no metadata
        return "unknown (Debian python3-getfem)"


def _jsonable(d):
    return json.loads(json.dumps(d, default=str))


def write_history_csv(path, rows):
    """One row per accepted increment; ``height_reduction, force, inner_diameter_change`` first."""
    with open(path, "w") as f:
        f.write(",".join(HISTORY_COLUMNS) + "\n")
        for r in rows:
            f.write(",".join(_fmt(r[c]) for c in HISTORY_COLUMNS) + "\n")


def _fmt(v):
    return str(v) if isinstance(v, (int, np.integer)) else repr(float(v))


def _write_outputs(out, rows, info):
    """History and summary into ``out``, whole or not at all (temp folder, then move)."""
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=".ring_", dir=out.parent))
    write_history_csv(tmp / "history.csv", rows)
    (tmp / "summary.json").write_text(json.dumps(info, indent=2))
    if out.exists():
        shutil.rmtree(out)
    os.replace(tmp, out)


def _parser():
    ap = argparse.ArgumentParser(
        prog="couplings/getfem/ring.py",
        description="Ring compression (6:3:2) in GetFEM with frictionlaw at the contact nodes",
    )
    ap.add_argument("--law", choices=("none", "tresca", "sbmf"), default="tresca")
    ap.add_argument("--m", type=float, default=None, help="Tresca friction factor (default 0.3)")
    ap.add_argument(
        "--params", default=None, help="SBMF parameter JSON (default: fe-demo's example file)"
    )
    ap.add_argument("--nr", type=int, default=16, help="elements across the ring wall")
    ap.add_argument("--nz", type=int, default=0, help="elements over h/2 (0: near-square)")
    ap.add_argument("--sector", type=float, default=5.0, help="wedge angle in degrees")
    ap.add_argument("--increments", type=int, default=50)
    ap.add_argument("--reduction", type=float, default=0.5, help="final height reduction")
    ap.add_argument(
        "--first-reduction",
        type=float,
        default=0.0,
        help="press-lift-press (fe-demo multistage's schedule): press to this reduction, lift "
        "the die until every node opens, press again to --reduction (default 0: one press)",
    )
    ap.add_argument(
        "--unload", type=int, default=4, help="increments of the lift (press-lift-press; default 4)"
    )
    ap.add_argument("--out", default="getfem_out/ring", help="output folder")
    ap.add_argument("--progress", action="store_true", help="one line per increment on stderr")
    return ap


def main(argv=None):
    """Command line; exit 0 success, 1 failed run, 2 bad input."""
    a = _parser().parse_args(argv)
    if a.m is not None and a.law != "tresca":
        print(f"error: --m applies to --law tresca only, not {a.law!r}", file=sys.stderr)
        return 2
    if a.params is not None and a.law != "sbmf":
        print(f"error: --params applies to --law sbmf only, not {a.law!r}", file=sys.stderr)
        return 2
    setup = RingSetup(
        law=a.law,
        m=0.3 if a.m is None else a.m,
        params=a.params or "",
        nr=a.nr,
        nz=a.nz,
        sector_deg=a.sector,
        increments=a.increments,
        reduction=a.reduction,
        first_reduction=a.first_reduction,
        n_unload=a.unload,
    )
    try:
        _check(setup)
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    try:
        import getfem  # noqa: F401
    except ImportError as exc:
        print(f"error: GetFEM is not importable from {sys.executable}: {exc}", file=sys.stderr)
        return 2
    ok, message, rows, info = run(setup, progress=a.progress)
    _write_outputs(a.out, rows, info)
    print(f"{message}; {len(rows)} increments, {info['wall_time_s']:.1f} s -> {a.out}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
