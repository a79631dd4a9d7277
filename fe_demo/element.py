"""Vectorised axisymmetric bilinear-quadrilateral kernels with mean-dilatation B-bar.

Reference shape functions and the 2x2 Gauss rule come from scikit-fem
(``ElementQuad1``, ``get_quadrature``); the isoparametric map, the B matrices and
the element matrices are evaluated for all elements and quadrature points at once
with ``numpy.einsum``. The volumetric part of B is replaced by its element
average (Hughes 1980, mean dilatation), which removes volumetric locking of the
plastically incompressible flow.

Strain components are ``[rr, zz, tt, rz]`` with engineering shear; element dofs
are ordered ``(node0 r, node0 z, node1 r, ...)``.
"""

import numpy as np
import scipy.sparse as sp
from skfem import ElementQuad1
from skfem.quadrature import get_quadrature
from skfem.refdom import RefQuad

__all__ = [
    "Kinematics",
    "reference_basis",
    "kinematics",
    "Assembler",
    "internal_force",
    "stiffness",
]


def reference_basis():
    """Shape functions ``N (4, nq)``, derivatives ``dN (4, 2, nq)`` and weights ``w (nq,)``."""
    X, w = get_quadrature(RefQuad, 2)
    el = ElementQuad1()
    N = np.empty((4, X.shape[1]))
    dN = np.empty((4, 2, X.shape[1]))
    for a in range(4):
        phi, dphi = el.lbasis(X, a)
        N[a] = phi
        dN[a] = dphi
    return N, dN, w


_N, _DN, _W = reference_basis()


class Kinematics:
    """Geometry at one configuration: ``B`` (B-bar), ``dV``, radius, gradient operators."""

    __slots__ = ("B", "dV", "r", "dNdx", "N", "valid", "min_detJ")

    def __init__(self, B, dV, r, dNdx, valid, min_detJ):
        self.B = B
        self.dV = dV
        self.r = r
        self.dNdx = dNdx
        self.N = _N
        self.valid = valid
        self.min_detJ = min_detJ


def kinematics(x, t):
    """B-bar matrices and volume weights in configuration ``x``.

    Parameters
    ----------
    x : ndarray, shape (n_nodes, 2)
        Nodal coordinates (r, z) in m.
    t : ndarray, shape (4, n_el)
        Element connectivity.

    Returns
    -------
    Kinematics
        ``B`` (n_el, nq, 4, 8), ``dV = 2 pi r detJ w`` (n_el, nq), ``r`` (n_el, nq),
        ``dNdx`` (n_el, nq, 4, 2); ``valid`` is False if any Jacobian is not positive.
    """
    xe = x[t]  # (4, ne, 2)
    J = np.einsum("aei,ajq->eqij", xe, _DN)  # dx_i / dxi_j
    det = J[..., 0, 0] * J[..., 1, 1] - J[..., 0, 1] * J[..., 1, 0]
    min_det = float(det.min())
    valid = min_det > 0
    det_s = np.where(det > 0, det, 1.0)
    inv = np.empty_like(J)
    inv[..., 0, 0] = J[..., 1, 1] / det_s
    inv[..., 1, 1] = J[..., 0, 0] / det_s
    inv[..., 0, 1] = -J[..., 0, 1] / det_s
    inv[..., 1, 0] = -J[..., 1, 0] / det_s
    dNdx = np.einsum("ajq,eqji->eqai", _DN, inv)  # (ne, nq, 4, 2)
    r = np.einsum("aq,ae->eq", _N, xe[..., 0])
    r_s = np.where(r > 0, r, 1.0)
    dV = 2.0 * np.pi * r * det * _W[None, :]
    ne, nq = r.shape
    Nr = _N.T[None, :, :] / r_s[..., None]  # (ne, nq, 4)
    B = np.zeros((ne, nq, 4, 8))
    B[..., 0, 0::2] = dNdx[..., 0]
    B[..., 1, 1::2] = dNdx[..., 1]
    B[..., 2, 0::2] = Nr
    B[..., 3, 0::2] = dNdx[..., 1]
    B[..., 3, 1::2] = dNdx[..., 0]
    # mean dilatation: replace the volumetric row by its element average
    bvol = B[..., 0, :] + B[..., 1, :] + B[..., 2, :]  # (ne, nq, 8)
    vol = dV.sum(1)
    vol_s = np.where(np.abs(vol) > 0, vol, 1.0)
    bbar = np.einsum("eq,eqk->ek", dV, bvol) / vol_s[:, None]
    corr = (bbar[:, None, :] - bvol) / 3.0
    B[..., 0:3, :] += corr[..., None, :]
    return Kinematics(B, dV, r, dNdx, valid, min_det)


class Assembler:
    """Scatter element vectors and matrices into global arrays (scipy.sparse CSR)."""

    def __init__(self, t, n_nodes):
        self.n_dof = 2 * n_nodes
        edofs = np.empty((t.shape[1], 8), dtype=np.int64)
        edofs[:, 0::2] = 2 * t.T
        edofs[:, 1::2] = 2 * t.T + 1
        self.edofs = edofs
        rows = np.repeat(edofs, 8, axis=1).ravel()
        cols = np.tile(edofs, (1, 8)).ravel()
        # precompute the COO -> CSR permutation once
        key = rows * self.n_dof + cols
        uniq, inv = np.unique(key, return_inverse=True)
        self._inv = inv
        self._nnz = uniq.size
        self._indices = (uniq % self.n_dof).astype(np.int32)
        counts = np.bincount(uniq // self.n_dof, minlength=self.n_dof)
        self._indptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int32)

    def vector(self, fe):
        """Assemble element vectors ``fe (n_el, 8)``."""
        return np.bincount(self.edofs.ravel(), weights=fe.ravel(), minlength=self.n_dof)

    def matrix(self, ke):
        """Assemble element matrices ``ke (n_el, 8, 8)`` into a CSR matrix."""
        data = np.bincount(self._inv, weights=ke.ravel(), minlength=self._nnz)
        return sp.csr_matrix((data, self._indices, self._indptr), shape=(self.n_dof, self.n_dof))


def _weighted_bt(kin):
    """``B^T dV`` stacked over the Gauss points, (n_el, 8, nq * 4)."""
    ne = kin.B.shape[0]
    return (kin.B * kin.dV[..., None, None]).reshape(ne, -1, 8).transpose(0, 2, 1)


def internal_force(kin, sigma):
    """Element internal force vectors ``int B^T sigma dV`` (n_el, 8).

    Batched ``matmul`` over the elements (a three-operand ``einsum`` is several times slower).
    """
    ne = kin.B.shape[0]
    return np.matmul(_weighted_bt(kin), sigma.reshape(ne, -1, 1))[..., 0]


def stiffness(kin, D):
    """Element tangent matrices ``int B^T D B dV`` (n_el, 8, 8), by batched ``matmul``."""
    ne = kin.B.shape[0]
    DB = np.matmul(D, kin.B)  # (ne, nq, 4, 8)
    return np.matmul(_weighted_bt(kin), DB.reshape(ne, -1, 8))
