"""Vectorised axisymmetric bilinear-quadrilateral kernels with mean-dilatation B-bar.

Reference shape functions and the 2x2 Gauss rule come from scikit-fem
(``ElementQuad1``, ``get_quadrature``); the isoparametric map, the B matrices and
the element matrices are evaluated for all elements and quadrature points at once
with ``numpy.einsum``. The volumetric part of B is replaced by its element
average (Hughes 1980, mean dilatation), which removes volumetric locking of the
plastically incompressible flow.

Each function takes ``kernels="numpy"`` (the vectorised NumPy code of this module, the
reference) or ``"numba"`` (the element loops of :mod:`fe_demo.solver._kernels`, the same results to
rounding, ``tests/test_fe_kernels.py``).

Strain components are ``[rr, zz, tt, rz]`` with engineering shear; element dofs
are ordered ``(node0 r, node0 z, node1 r, ...)``.

Plane strain (``plane_strain=True``, used by :mod:`fe_demo.asperity`) is the same element without
the hoop terms: ``(r, z)`` read as ``(x, z)``, the third strain component is the out-of-plane
``eps_yy`` (zero but for the B-bar's volumetric correction), ``N / r`` is dropped from B and the
volume weight is ``detJ w`` per unit thickness (m^2) instead of ``2 pi r detJ w``.
"""

import numpy as np
import scipy.sparse as sp
from skfem import ElementQuad1
from skfem.quadrature import get_quadrature
from skfem.refdom import RefQuad

from . import _kernels

__all__ = [
    "Kinematics",
    "reference_basis",
    "kinematics",
    "Assembler",
    "ReducedPattern",
    "internal_force",
    "strain_increment",
    "stiffness",
    "KERNELS",
]

#: the element-loop implementations: vectorised NumPy (the reference) and numba
KERNELS = ("numpy", "numba")


def check_kernels(kernels):
    """``kernels`` if it names an implementation in :data:`KERNELS`, else ``ValueError``."""
    if kernels not in KERNELS:
        raise ValueError(f"kernels must be one of {KERNELS}, got {kernels!r}")
    return kernels


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


def kinematics(x, t, kernels="numpy", plane_strain=False):
    """B-bar matrices and volume weights in configuration ``x``.

    Parameters
    ----------
    x : ndarray, shape (n_nodes, 2)
        Nodal coordinates (r, z) in m.
    t : ndarray, shape (4, n_el)
        Element connectivity.
    kernels : {"numpy", "numba"}
        Implementation (:data:`KERNELS`).
    plane_strain : bool
        Plane strain (no hoop terms, ``dV = detJ w`` per unit thickness) instead of the
        axisymmetric element.

    Returns
    -------
    Kinematics
        ``B`` (n_el, nq, 4, 8), ``dV = 2 pi r detJ w`` (n_el, nq; plane strain ``detJ w``),
        ``r`` (n_el, nq), ``dNdx`` (n_el, nq, 4, 2); ``valid`` is False if any Jacobian is not
        positive.
    """
    if check_kernels(kernels) == "numba":
        return _kinematics_numba(x, t, bool(plane_strain))
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
    ne, nq = r.shape
    if plane_strain:
        dV = det * _W[None, :]
        Nr = np.zeros((ne, nq, 4))
    else:
        dV = 2.0 * np.pi * r * det * _W[None, :]
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


def _c(a):
    """``a`` as a C-contiguous float64 array (no copy when it is one)."""
    return np.ascontiguousarray(a, dtype=float)


def _kinematics_numba(x, t, plane_strain=False):
    ne, nq = t.shape[1], _W.size
    B = np.empty((ne, nq, 4, 8))
    dV = np.empty((ne, nq))
    r = np.empty((ne, nq))
    dNdx = np.empty((ne, nq, 4, 2))
    t = np.ascontiguousarray(t, dtype=np.int64)
    min_det = _kernels.kinematics(_c(x), t, _N, _DN, _W, not plane_strain, B, dV, r, dNdx)
    return Kinematics(B, dV, r, dNdx, min_det > 0, min_det)


def rotate(sig, w):
    """Rotate Voigt stresses ``[rr, zz, tt, rz]`` by the angle ``w`` in the r-z plane."""
    c, s = np.cos(w), np.sin(w)
    a, b, d = sig[..., 0], sig[..., 1], sig[..., 3]
    out = sig.copy()
    out[..., 0] = c * c * a + 2 * c * s * d + s * s * b
    out[..., 1] = s * s * a - 2 * c * s * d + c * c * b
    out[..., 3] = -c * s * a + (c * c - s * s) * d + c * s * b
    return out


def strain_increment(kin, edofs, du, sigma, kernels="numpy"):
    """Strain increments of ``du`` and the stresses ``sigma`` rotated by its spin.

    Parameters
    ----------
    kin : Kinematics
        The configuration the increment is measured on (the mid-increment one).
    edofs : ndarray of int, shape (n_el, 8)
        Element dofs (:attr:`Assembler.edofs`).
    du : ndarray, shape (n_dof,)
        Displacement increment.
    sigma : ndarray, shape (n_el, nq, 4)
        Stresses of the last increment.
    kernels : {"numpy", "numba"}

    Returns
    -------
    d_eps, sigma_rotated : ndarray, shape (n_el, nq, 4)
        ``B du`` and ``sigma`` rotated (Hughes-Winget, r-z plane) by the spin
        ``w = (d du_r / dz - d du_z / dr) / 2`` at each point.
    """
    if check_kernels(kernels) == "numba":
        d_eps = np.empty(kin.B.shape[:3])
        sig_rot = np.empty(kin.B.shape[:3])
        _kernels.strain_spin_rotate(
            _c(kin.B),
            _c(kin.dNdx),
            np.ascontiguousarray(edofs, dtype=np.int64),
            _c(du),
            _c(sigma),
            d_eps,
            sig_rot,
        )
        return d_eps, sig_rot
    due = du[edofs]  # (ne, 8)
    d_eps = np.einsum("eqia,ea->eqi", kin.B, due)
    dur, duz = due[:, 0::2], due[:, 1::2]
    w = 0.5 * (
        np.einsum("eqa,ea->eq", kin.dNdx[..., 1], dur)
        - np.einsum("eqa,ea->eq", kin.dNdx[..., 0], duz)
    )
    return d_eps, rotate(sigma, w)


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

    def reduced(self, free, extra_rows, extra_cols, fmt="csc"):
        """:class:`ReducedPattern` of the element matrices and extra entries on the free dofs.

        Parameters
        ----------
        free : ndarray of bool, shape (n_dof,)
        extra_rows, extra_cols : ndarray of int
            Global dofs of entries added after the element matrices (the contact terms).
        fmt : {"csc", "csr"}

        The values given to :meth:`ReducedPattern.matrix` are ``ke`` followed by the extra
        entries' values.
        """
        index = np.full(self.n_dof, -1, dtype=np.int64)
        index[free] = np.arange(int(np.count_nonzero(free)))
        rows = np.concatenate([np.repeat(self.edofs, 8, axis=1).ravel(), extra_rows])
        cols = np.concatenate([np.tile(self.edofs, (1, 8)).ravel(), extra_cols])
        return ReducedPattern(index[rows], index[cols], int(np.count_nonzero(free)), fmt)

    def vector(self, fe):
        """Assemble element vectors ``fe (n_el, 8)``."""
        return np.bincount(self.edofs.ravel(), weights=fe.ravel(), minlength=self.n_dof)

    def matrix(self, ke):
        """Assemble element matrices ``ke (n_el, 8, 8)`` into a CSR matrix."""
        data = np.bincount(self._inv, weights=ke.ravel(), minlength=self._nnz)
        return sp.csr_matrix((data, self._indices, self._indptr), shape=(self.n_dof, self.n_dof))


class ReducedPattern:
    """The free-dof tangent's fixed sparsity pattern and a scatter map into its data array.

    Built once per mesh by :meth:`Assembler.reduced`: element matrices and extra entries (the
    contact terms) go straight into the ``data`` of the free-dof matrix, in CSC (SuperLU) or CSR
    (PARDISO) order, instead of assembling the full matrix, adding the extras and slicing out the
    free rows and columns. Entries that are zero stay stored, so the pattern never changes (a
    direct solver can keep its symbolic analysis).

    Attributes
    ----------
    fmt : {"csc", "csr"}
    n : int
        Free dofs.
    indices, indptr : ndarray of int32
    """

    def __init__(self, rows, cols, n, fmt):
        if fmt not in ("csc", "csr"):
            raise ValueError(f"fmt must be 'csc' or 'csr', got {fmt!r}")
        keep = (rows >= 0) & (cols >= 0)
        major, minor = (cols, rows) if fmt == "csc" else (rows, cols)
        key = major[keep] * n + minor[keep]
        uniq, inv = np.unique(key, return_inverse=True)
        pos = np.full(rows.size, -1, dtype=np.int64)
        pos[keep] = inv
        self.pos = pos
        self.fmt = fmt
        self.n = n
        self.nnz = uniq.size
        self.indices = (uniq % n).astype(np.int32)
        counts = np.bincount(uniq // n, minlength=n)
        self.indptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int32)

    def matrix(self, *parts):
        """The matrix of the values ``parts`` (concatenated, one per entry given to the constructor).

        Each part is scattered in turn (no concatenated copy of the element matrices is made).
        """
        data = np.zeros(self.nnz)
        start = 0
        for part in parts:
            v = np.ascontiguousarray(part, dtype=float).reshape(-1)
            _kernels.scatter_add(v, self.pos[start : start + v.size], data)
            start += v.size
        if start != self.pos.size:
            raise ValueError(f"{start} values for a pattern of {self.pos.size} entries")
        cls = sp.csc_matrix if self.fmt == "csc" else sp.csr_matrix
        return cls((data, self.indices, self.indptr), shape=(self.n, self.n))


def _weighted_bt(kin):
    """``B^T dV`` stacked over the Gauss points, (n_el, 8, nq * 4)."""
    ne = kin.B.shape[0]
    return (kin.B * kin.dV[..., None, None]).reshape(ne, -1, 8).transpose(0, 2, 1)


def internal_force(kin, sigma, kernels="numpy"):
    """Element internal force vectors ``int B^T sigma dV`` (n_el, 8).

    NumPy: batched ``matmul`` over the elements (a three-operand ``einsum`` is several times
    slower). ``sigma`` is (n_el, nq, 4).
    """
    ne = kin.B.shape[0]
    if check_kernels(kernels) == "numba":
        fe = np.empty((ne, 8))
        _kernels.internal_force(_c(kin.B), _c(kin.dV), _c(sigma), fe)
        return fe
    return np.matmul(_weighted_bt(kin), sigma.reshape(ne, -1, 1))[..., 0]


def stiffness(kin, D, kernels="numpy"):
    """Element tangent matrices ``int B^T D B dV`` (n_el, 8, 8); NumPy: batched ``matmul``."""
    ne = kin.B.shape[0]
    if check_kernels(kernels) == "numba":
        ke = np.empty((ne, 8, 8))
        _kernels.stiffness(_c(kin.B), _c(kin.dV), _c(D), ke)
        return ke
    DB = np.matmul(D, kin.B)  # (ne, nq, 4, 8)
    return np.matmul(_weighted_bt(kin), DB.reshape(ne, -1, 8))
