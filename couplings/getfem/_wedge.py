"""The GetFEM side of the ring coupling: the wedge mesh and model, the die contact, Newton.

GetFEM assembles the bulk (finite-strain J2 plasticity, ``Simo_Miehe``); this module adds what a
host code's contact algorithm does around a friction user routine: a nodal penalty for the die
pressure and, per candidate node, :func:`frictionlaw.traction_update` with the node's
``HistoryState``, into GetFEM's tangent and residual; and the Newton loop with a line search.
``s`` is a :class:`couplings.getfem.ring.RingSetup` (read by attribute).
"""

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = [
    "Contact",
    "build_model",
    "element_size",
    "elements_over_half_height",
    "face_nodes",
    "nodal_areas",
    "newton",
    "node_displacements",
    "set_regions",
    "wedge_mesh",
]


# ---------------------------------------------------------------------- mesh
def wedge_mesh(gf, s):
    """Hexahedral wedge: ``nr`` x 1 x ``nz`` elements over (r, theta, z)."""
    ri, ro, hh = s.inner_diameter / 2, s.outer_diameter / 2, s.height / 2
    r = np.linspace(ri, ro, s.nr + 1)
    z = np.linspace(0.0, hh, elements_over_half_height(s) + 1)
    mesh = gf.Mesh("cartesian Q1", r, np.array([0.0, 1.0]), z)
    p = mesh.pts()
    th = math.radians(s.sector_deg) * p[1]
    mesh.set_pts(np.vstack([p[0] * np.cos(th), p[0] * np.sin(th), p[2]]))
    return mesh, r, z


def elements_over_half_height(s):
    """Elements over the half height; ``nz = 0`` picks near-square elements."""
    if s.nz:
        return int(s.nz)
    return max(1, round(s.nr * (s.height / 2) / ((s.outer_diameter - s.inner_diameter) / 2)))


def element_size(s):
    return min(
        (s.outer_diameter - s.inner_diameter) / 2 / s.nr,
        s.height / 2 / elements_over_half_height(s),
    )


@dataclass
class _Regions:
    mid: int = 1  # z = 0, u_z = 0
    cut0: int = 2  # theta = 0, u_y = 0
    cut1: int = 3  # theta = sector, u . n = 0 (penalty)
    free: int = 4  # top, inner, outer: die-contact candidates


def set_regions(mesh, th):
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


def face_nodes(mesh, faces):
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


def build_model(gf, s, mesh, rg):
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
    h_el = element_size(s)
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
class Contact:
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


def nodal_areas(model, ct, u_all):
    """Lumped area (a quarter of each adjacent candidate face) at the current configuration."""
    x = model.X + u_all
    a = _quad_areas(x, ct.quads)
    area = np.zeros(model.X.shape[0])
    np.add.at(area, ct.quads.ravel(), np.repeat(a / 4.0, 4))
    return area[ct.nodes]


# ---------------------------------------------------------------------- solve
def node_displacements(model, v):
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
    u_all = node_displacements(model, v)
    terms = _contact_terms(model, ct, u_all[ct.nodes], u_start_nodes, z_die, area)
    md.assembly(option)
    rhs = np.array(md.rhs())
    dc = model.dof[ct.nodes]
    ok = dc >= 0
    np.add.at(rhs, dc[ok], terms[0][ok])
    return rhs, terms


def newton(model, ct, s, z_die, u_start_nodes, area, f_ref):
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
