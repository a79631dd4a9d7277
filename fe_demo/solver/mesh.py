"""Structured axisymmetric (r, z) quadrilateral meshes of the upper half of a cylinder or ring.

The workpiece is symmetric about its mid-plane ``z = 0``; only ``0 <= z <= h/2`` is
meshed. Meshes are scikit-fem ``MeshQuad`` objects (bilinear quadrilaterals).
"""

from dataclasses import dataclass

import numpy as np
from skfem import MeshQuad

__all__ = ["AxiMesh", "cylinder_mesh", "ring_mesh", "mesh_for_elements"]


@dataclass
class AxiMesh:
    """An axisymmetric half-model mesh and its node sets.

    Attributes
    ----------
    mesh : skfem.MeshQuad
        Mesh in the initial configuration, ``p[0] = r``, ``p[1] = z`` (m).
    axis_nodes : ndarray
        Nodes on ``r = 0`` (``u_r = 0``); empty for a ring.
    sym_nodes : ndarray
        Nodes on the mid-plane ``z = 0`` (``u_z = 0``).
    contact_nodes : ndarray
        Candidate nodes for die contact: every boundary node off the mid-plane
        (the top face and the free faces that may fold onto the die).
    boundary_edges : ndarray, shape (2, n)
        Boundary edges (node pairs) off the mid-plane, for nodal contact areas.
    inner_mid_node : int
        For a ring: the inner-surface node on the mid-plane (-1 otherwise).
    grid : ndarray, shape (nr + 1, nz + 1)
        Node number at radial index ``i`` and axial index ``j`` (for remeshing).
    """

    mesh: MeshQuad
    axis_nodes: np.ndarray
    sym_nodes: np.ndarray
    contact_nodes: np.ndarray
    boundary_edges: np.ndarray
    inner_mid_node: int = -1
    grid: np.ndarray = None

    @property
    def n_elements(self):
        return self.mesh.t.shape[1]


def _check(name, v, lo=0.0):
    v = float(v)
    if not (np.isfinite(v) and v > lo):
        raise ValueError(f"{name} must be finite and > {lo:g}, got {v!r}")
    return v


def _build(r, z, inner_free):
    m0 = MeshQuad.init_tensor(r, z)
    mesh = MeshQuad(m0.p, m0.t[[0, 3, 2, 1]])  # counter-clockwise in (r, z)
    p = mesh.p
    tol = 1e-9 * max(r[-1], z[-1])
    axis = np.flatnonzero(np.abs(p[0]) < tol) if not inner_free else np.array([], int)
    sym = np.flatnonzero(np.abs(p[1]) < tol)
    bf = mesh.facets[:, mesh.boundary_facets()]
    on_sym = (np.abs(p[1, bf[0]]) < tol) & (np.abs(p[1, bf[1]]) < tol)
    on_axis = (np.abs(p[0, bf[0]]) < tol) & (np.abs(p[0, bf[1]]) < tol) & (not inner_free)
    edges = bf[:, ~on_sym & ~on_axis]
    cand = np.unique(edges)
    inner_mid = -1
    if inner_free:
        inner_mid = int(np.flatnonzero((np.abs(p[0] - r[0]) < tol) & (np.abs(p[1]) < tol))[0])
    i = np.searchsorted(r, p[0] - tol)
    j = np.searchsorted(z, p[1] - tol)
    grid = np.full((r.size, z.size), -1)
    grid[i, j] = np.arange(p.shape[1])
    if (grid < 0).any():
        raise RuntimeError("structured grid numbering failed")
    return AxiMesh(mesh, axis, sym, cand, edges, inner_mid, grid)


def _grid(a, b, n):
    return np.linspace(a, b, int(n) + 1)


def cylinder_mesh(diameter=20e-3, height=10e-3, nr=40, nz=None):
    """Half-model mesh of a solid cylinder (``nr`` elements radially, ``nz`` over ``h/2``).

    ``nz`` defaults to a near-square element aspect.
    """
    d = _check("diameter", diameter)
    h = _check("height", height)
    nr = int(nr)
    if nr < 1:
        raise ValueError(f"nr must be >= 1, got {nr}")
    if nz is None:
        nz = max(1, round(nr * (h / 2) / (d / 2)))
    if int(nz) < 1:
        raise ValueError(f"nz must be >= 1, got {nz}")
    return _build(_grid(0.0, d / 2, nr), _grid(0.0, h / 2, nz), inner_free=False)


def ring_mesh(outer_diameter=18e-3, inner_diameter=9e-3, height=6e-3, nr=24, nz=None):
    """Half-model mesh of a ring (standard 6:3:2 by default: OD 18, ID 9, h 6 mm)."""
    do = _check("outer_diameter", outer_diameter)
    di = _check("inner_diameter", inner_diameter)
    h = _check("height", height)
    if di >= do:
        raise ValueError("inner_diameter must be < outer_diameter")
    nr = int(nr)
    if nr < 1:
        raise ValueError(f"nr must be >= 1, got {nr}")
    if nz is None:
        nz = max(1, round(nr * (h / 2) / ((do - di) / 2)))
    return _build(_grid(di / 2, do / 2, nr), _grid(0.0, h / 2, nz), inner_free=True)


def mesh_for_elements(n_elements, diameter=20e-3, height=10e-3):
    """Cylinder mesh with about ``n_elements`` near-square elements."""
    n = int(n_elements)
    if n < 1:
        raise ValueError(f"n_elements must be >= 1, got {n_elements!r}")
    aspect = (height / 2) / (diameter / 2)
    nr = max(1, round(np.sqrt(n / aspect)))
    return cylinder_mesh(diameter, height, nr, max(1, round(n / nr)))
