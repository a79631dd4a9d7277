"""J2 (von Mises) elasto-plasticity with isotropic Swift hardening, vectorised over points.

Stress and strain are stored as axisymmetric Voigt vectors ``[rr, zz, tt, rz]``;
strains carry the engineering shear ``gamma_rz = 2 eps_rz``. The return map is the
classic radial return (Wilkins; Simo and Hughes, *Computational Inelasticity*,
Box 3.2) with the consistent (algorithmic) tangent of Simo and Taylor (1985).

Default material (DC04-like)
----------------------------
``E = 210 GPa``, ``nu = 0.3``, Swift flow curve ``sigma_f = K (eps0 + eps_p) ** n``
with ``K = 530 MPa``, ``eps0 = 0.006``, ``n = 0.24`` (initial yield about 155 MPa).
These are illustrative values inside the range reported for the deep-drawing steel
DC04 (EN 10130) in the sheet-forming literature (K about 500-560 MPa, n about
0.2-0.26, R_p0.2 about 140-210 MPa as specified by EN 10130); they are not a
certified data set. Give a measured curve with :meth:`Material.from_json`.
"""

import json
import math
from dataclasses import asdict, dataclass
from functools import cached_property
from pathlib import Path

import numpy as np

from frictionlaw.flow_curve import SwiftCurve

from . import _kernels
from .element import check_kernels

__all__ = ["Material", "DC04", "radial_return", "elastic_matrix", "von_mises"]

#: Voigt helpers: trace vector and the deviatoric projector (engineering shear)
_ONE = np.array([1.0, 1.0, 1.0, 0.0])
_IDEV = np.diag([1.0, 1.0, 1.0, 0.5]) - np.outer(_ONE, _ONE) / 3.0


def _check_pos(name, v):
    v = float(v)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be finite and > 0, got {v!r}")
    return v


@dataclass(frozen=True)
class Material:
    """Isotropic elasto-plastic material with a Swift flow curve.

    Parameters
    ----------
    E : float
        Young's modulus (Pa), ``> 0``.
    nu : float
        Poisson's ratio in ``(-1, 0.5)``.
    K : float
        Swift strength coefficient (Pa), ``> 0``.
    eps0 : float
        Swift pre-strain, ``> 0`` (sets the initial yield stress ``K eps0**n``).
    n : float
        Hardening exponent in ``[0, 1]``.
    """

    E: float = 210e9
    nu: float = 0.3
    K: float = 530e6
    eps0: float = 0.006
    n: float = 0.24

    def __post_init__(self):
        _check_pos("E", self.E)
        _check_pos("K", self.K)
        _check_pos("eps0", self.eps0)
        if not (-1.0 < float(self.nu) < 0.5):
            raise ValueError(f"nu must be in (-1, 0.5), got {self.nu!r}")
        if not (0.0 <= float(self.n) <= 1.0):
            raise ValueError(f"n must be in [0, 1], got {self.n!r}")

    @property
    def G(self):
        """Shear modulus (Pa)."""
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def bulk(self):
        """Bulk modulus (Pa)."""
        return self.E / (3.0 * (1.0 - 2.0 * self.nu))

    @property
    def sigma_y0(self):
        """Initial yield stress ``K eps0**n`` (Pa)."""
        return self.flow_stress(0.0)

    @cached_property
    def flow_curve(self):
        """The Swift curve as :class:`frictionlaw.flow_curve.SwiftCurve`.

        One definition of it: the flattening's fits and exports take the same record.
        """
        return SwiftCurve(float(self.K), float(self.eps0), float(self.n))

    def flow_stress(self, eps_p):
        """Swift flow curve ``sigma_f = K (eps0 + eps_p)**n`` (Pa)."""
        return self.flow_curve.sigma_y(np.maximum(eps_p, 0.0))

    def hardening(self, eps_p):
        """Slope ``d sigma_f / d eps_p`` (Pa)."""
        return self.flow_curve.hardening(np.maximum(eps_p, 0.0))

    @classmethod
    def from_json(cls, path):
        """Read ``{"E": .., "nu": .., "K": .., "eps0": .., "n": ..}`` (SI units)."""
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
        if not isinstance(doc, dict):
            raise ValueError(f"{path}: material file must hold a JSON object")
        unknown = set(doc) - {"E", "nu", "K", "eps0", "n", "name", "source"}
        if unknown:
            raise ValueError(f"{path}: unknown material keys {sorted(unknown)}")
        return cls(**{k: doc[k] for k in ("E", "nu", "K", "eps0", "n") if k in doc})

    def to_dict(self):
        """The material as a JSON-ready dict."""
        return asdict(self)


DC04 = Material()


def elastic_matrix(mat):
    """Isotropic elastic matrix (4x4, Voigt with engineering shear)."""
    return mat.bulk * np.outer(_ONE, _ONE) + 2.0 * mat.G * _IDEV


def _norm(s):
    return np.sqrt(s[..., 0] ** 2 + s[..., 1] ** 2 + s[..., 2] ** 2 + 2.0 * s[..., 3] ** 2)


def radial_return(mat, sigma_old, eps_p_old, d_eps, *, tol=1e-12, max_iter=50, kernels="numpy"):
    """Radial return at every point, with the consistent tangent.

    ``kernels="numpy"`` runs the local Newton iteration on all plastic points at once (until
    the slowest has converged), ``"numba"`` point by point
    (:func:`fe_demo.solver._kernels.radial_return_row`); the results agree to rounding.

    Parameters
    ----------
    mat : Material
    sigma_old : ndarray, shape (..., 4)
        Stress at the start of the increment (already rotated), Pa.
    eps_p_old : ndarray, shape (...)
        Equivalent plastic strain at the start of the increment.
    d_eps : ndarray, shape (..., 4)
        Strain increment (engineering shear).
    tol : float
        Relative tolerance of the yield check and the local Newton iteration.
    max_iter : int
        Local Newton iterations allowed.
    kernels : {"numpy", "numba"}
        Implementation.

    Returns
    -------
    sigma : ndarray, shape (..., 4)
    eps_p : ndarray, shape (...)
    D : ndarray, shape (..., 4, 4)
        Consistent tangent ``d sigma / d d_eps``.
    plastic : ndarray of bool, shape (...)

    Raises
    ------
    RuntimeError
        The local Newton iteration did not converge at some point.
    """
    if check_kernels(kernels) == "numba":
        return _radial_return_numba(mat, sigma_old, eps_p_old, d_eps, tol, max_iter)
    G, Kb = mat.G, mat.bulk
    De = elastic_matrix(mat)
    sig_tr = sigma_old + np.einsum("ij,...j->...i", De, d_eps)
    p_tr = sig_tr[..., :3].sum(-1) / 3.0
    s_tr = sig_tr - p_tr[..., None] * _ONE
    snorm = _norm(s_tr)
    q_tr = math.sqrt(1.5) * snorm
    f_tr = q_tr - mat.flow_stress(eps_p_old)
    plastic = f_tr > tol * mat.sigma_y0
    sigma = sig_tr.copy()
    eps_p = np.array(eps_p_old, dtype=float, copy=True)
    D = np.broadcast_to(De, sig_tr.shape[:-1] + (4, 4)).copy()
    if not plastic.any():
        return sigma, eps_p, D, plastic
    q = q_tr[plastic]
    ep0 = eps_p_old[plastic]
    dg = np.zeros_like(q)
    for _ in range(max_iter):
        res = q - 3.0 * G * dg - mat.flow_stress(ep0 + dg)
        dres = -3.0 * G - mat.hardening(ep0 + dg)
        step = -res / dres
        dg = np.maximum(dg + step, 0.0)
        if np.all(np.abs(res) <= tol * q):
            break
    else:
        raise RuntimeError("radial return did not converge (flow curve too steep?)")
    Nhat = s_tr[plastic] / snorm[plastic][:, None]
    fac = 1.0 - 3.0 * G * dg / q
    s_new = fac[:, None] * s_tr[plastic]
    sigma[plastic] = s_new + p_tr[plastic][:, None] * _ONE
    eps_p[plastic] = ep0 + dg
    Hs = mat.hardening(ep0 + dg)
    c1 = 2.0 * G * fac
    c2 = 6.0 * G * G * (dg / q - 1.0 / (3.0 * G + Hs))
    Dp = (
        Kb * np.outer(_ONE, _ONE)[None]
        + c1[:, None, None] * _IDEV[None]
        + c2[:, None, None] * np.einsum("pi,pj->pij", Nhat, Nhat)
    )
    D[plastic] = Dp
    return sigma, eps_p, D, plastic


def _radial_return_numba(mat, sigma_old, eps_p_old, d_eps, tol, max_iter):
    shape = np.broadcast_shapes(np.shape(sigma_old), np.shape(d_eps))[:-1]
    so = np.ascontiguousarray(np.broadcast_to(sigma_old, shape + (4,)), dtype=float).reshape(-1, 4)
    de = np.ascontiguousarray(np.broadcast_to(d_eps, shape + (4,)), dtype=float).reshape(-1, 4)
    ep0 = np.ascontiguousarray(np.broadcast_to(eps_p_old, shape), dtype=float).reshape(-1)
    prm = np.array(
        [mat.G, mat.bulk, mat.K, mat.eps0, mat.n, tol, max_iter, mat.sigma_y0], dtype=float
    )
    n = so.shape[0]
    sigma, eps_p = np.empty((n, 4)), np.empty(n)
    D, plastic = np.empty((n, 4, 4)), np.empty(n, dtype=bool)
    bad = _kernels.radial_return(elastic_matrix(mat), prm, so, ep0, de, sigma, eps_p, D, plastic)
    if bad:
        raise RuntimeError("radial return did not converge (flow curve too steep?)")
    return (
        sigma.reshape(shape + (4,)),
        eps_p.reshape(shape),
        D.reshape(shape + (4, 4)),
        plastic.reshape(shape),
    )


def von_mises(sigma):
    """Equivalent (von Mises) stress of Voigt stress vectors (Pa)."""
    p = sigma[..., :3].sum(-1) / 3.0
    return math.sqrt(1.5) * _norm(sigma - p[..., None] * _ONE)
