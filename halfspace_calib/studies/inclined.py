"""Inclined surface patches and the geometric shear stress (Sec. 3.2, Eqs. 19-23).

Each solver element ``k`` (a ``2a x 2b`` patch) covers a block of ``s = sx * sy`` measured points
``(x_i, y_i, z_i)``. Its least-squares plane ``z = alpha_k x + beta_k y + gamma_k`` (Eq. 19) minimises
Eq. 20; the normal equations (Eq. 21) are assembled for all elements at once from block sums of the
fine height map and solved as one batch of 3 x 3 systems (missing points, NaN, are left out of the
sums). Local coordinates are centred on each element, so ``gamma_k`` is the plane's height at the
element centre (the element's mean height when all its points are present).

Conventions
-----------
* Arrays are indexed ``[ix, iy]`` (``indexing="ij"``); ``x`` (axis 0) is the sliding direction.
* Normal vectors point up, out of the workpiece and into the tool:
  ``nv = (-alpha, -beta, 1) / sqrt(alpha^2 + beta^2 + 1)``, so ``nv_z > 0`` and
  ``nv_x / nv_z = -alpha``.
* The tool's height map is given as measured, heights positive towards the workpiece (the composite
  topography is the sum of both maps, as in Fig. 2). Seen in the workpiece's frame its surface is
  ``z = const - h_tool``, so the tool patch's upward normal (into the tool) is
  ``(alpha_t, beta_t, 1) / norm``.
* Entering flanks: the tool slides in ``+x`` relative to the workpiece (``direction=+1``). A workpiece
  patch rising in ``+x`` (``alpha > 0``) faces the oncoming tool: its normal has ``nv_x < 0``. The
  paper neglects patches with ``nv_x > 0`` (exiting flanks); for ``direction=-1`` the roles swap.
* ``tau_geo`` is returned as a non-negative stress (Pa), the magnitude of the resistance against the
  sliding direction: ``tau_geo = sum_entering p_k |nv_x,k| / nv_z,k / (Nx Ny)`` (Eq. 23).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "PatchPlanes",
    "fit_patch_planes",
    "patch_normals",
    "contact_normals",
    "tau_geo",
    "tau_geo_from_surfaces",
]


@dataclass(frozen=True)
class PatchPlanes:
    """Least-squares planes of the solver elements (Eq. 19), arrays of shape ``(Nx, Ny)``.

    Attributes
    ----------
    alpha, beta : ndarray
        Slopes ``dz/dx`` and ``dz/dy`` (dimensionless).
    gamma : ndarray
        Plane height at the element centre (m).
    n_points : ndarray of int
        Number of measured points that entered each fit (``s``, fewer where points are NaN).
    """

    alpha: np.ndarray
    beta: np.ndarray
    gamma: np.ndarray
    n_points: np.ndarray


def fit_patch_planes(z, block, dx, dy=None):
    """Least-squares plane of every solver element over its measured points, Eqs. 19-21.

    Parameters
    ----------
    z : array_like, shape (Nx * sx, Ny * sy)
        Measured heights (m) on a regular grid, ``[ix, iy]``; NaN marks a missing point.
    block : int or (int, int)
        ``(sx, sy)``: measured points per solver element along ``x`` and ``y``.
    dx, dy : float
        Spacing of the measured points (m); ``dy`` defaults to ``dx``. The element size is
        ``sx dx x sy dy``.

    Returns
    -------
    PatchPlanes
        ``alpha``, ``beta``, ``gamma`` and ``n_points`` of shape ``(Nx, Ny)``.

    Raises
    ------
    ValueError
        Bad shapes or spacings, or an element whose valid points do not span a plane (fewer than
        three, or all on one line).
    """
    z = np.asarray(z, dtype=float)
    sx, sy = _check_block(block)
    dy = dx if dy is None else dy
    for name, v in (("dx", dx), ("dy", dy)):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite positive spacing in m, got {v!r}")
    if z.ndim != 2 or z.shape[0] % sx or z.shape[1] % sy or z.size == 0:
        raise ValueError(
            f"z must be 2-D with a shape divisible by block=({sx}, {sy}), got shape {z.shape}"
        )
    if np.any(np.isinf(z)):
        raise ValueError("z must not contain inf (NaN marks missing points)")
    nx, ny = z.shape[0] // sx, z.shape[1] // sy
    zb = z.reshape(nx, sx, ny, sy)
    w = np.isfinite(zb).astype(float)
    zb = np.where(w > 0, zb, 0.0)
    # local coordinates centred on the element, in units of the spacing (well conditioned)
    xl = (np.arange(sx) - (sx - 1) / 2)[None, :, None, None]
    yl = (np.arange(sy) - (sy - 1) / 2)[None, None, None, :]

    def bsum(f):
        return np.sum(np.broadcast_to(f, zb.shape), axis=(1, 3))

    s1, sx_, sy_ = bsum(w), bsum(w * xl), bsum(w * yl)
    sxx, syy, sxy = bsum(w * xl * xl), bsum(w * yl * yl), bsum(w * xl * yl)
    sxz, syz, sz = bsum(w * xl * zb), bsum(w * yl * zb), bsum(zb)
    M = np.stack(
        [
            np.stack([sxx, sxy, sx_], -1),
            np.stack([sxy, syy, sy_], -1),
            np.stack([sx_, sy_, s1], -1),
        ],
        -2,
    )
    rhs = np.stack([sxz, syz, sz], -1)
    _check_spans_plane(M, s1)
    sol = np.linalg.solve(M, rhs[..., None])[..., 0]
    return PatchPlanes(
        alpha=sol[..., 0] / dx, beta=sol[..., 1] / dy, gamma=sol[..., 2], n_points=s1.astype(int)
    )


def patch_normals(alpha, beta):
    """Upward unit normals ``nv = (-alpha, -beta, 1) / sqrt(alpha^2 + beta^2 + 1)`` of Eq. 19's planes.

    Parameters
    ----------
    alpha, beta : array_like
        Plane slopes ``dz/dx`` and ``dz/dy``.

    Returns
    -------
    ndarray, shape (..., 3)
        ``(nv_x, nv_y, nv_z)`` with ``nv_z > 0``.
    """
    alpha, beta = np.broadcast_arrays(np.asarray(alpha, float), np.asarray(beta, float))
    if not (np.all(np.isfinite(alpha)) and np.all(np.isfinite(beta))):
        raise ValueError("alpha and beta must be finite")
    nv = np.stack([-alpha, -beta, np.ones_like(alpha)], -1)
    return nv / np.linalg.norm(nv, axis=-1, keepdims=True)


def contact_normals(nv_workpiece, nv_tool, plastic):
    """Normal of each contact patch by the paper's rule (Sec. 3.2, after Eq. 23).

    Elastic patch: the mean of the workpiece's and the tool's normals (``E`` and ``nu`` of both
    bodies are equal). Plastic patch: the tool's normal (the workpiece takes the tool's shape).

    Parameters
    ----------
    nv_workpiece : array_like, shape (Nx, Ny, 3)
        Upward unit normals of the workpiece patches (:func:`patch_normals`).
    nv_tool : array_like, shape (Nx, Ny, 3)
        Upward unit normals of the tool patches in the workpiece's frame, i.e.
        ``patch_normals(-alpha_t, -beta_t)`` for the tool's measured slopes (heights positive
        towards the workpiece), see the module docstring.
    plastic : array_like of bool, shape (Nx, Ny)
        Elements in the plastic set of the normal solution (``p = H``).

    Returns
    -------
    ndarray, shape (Nx, Ny, 3)
        Unit normals of the contact patches, ``nv_z > 0``.
    """
    nw = np.asarray(nv_workpiece, dtype=float)
    nt = np.asarray(nv_tool, dtype=float)
    plastic = np.asarray(plastic, dtype=bool)
    if nw.shape != nt.shape or nw.shape[-1:] != (3,) or plastic.shape != nw.shape[:-1]:
        raise ValueError(
            "nv_workpiece and nv_tool must have equal shapes (..., 3) and plastic their leading "
            f"shape; got {nw.shape}, {nt.shape}, {plastic.shape}"
        )
    if not (np.all(nw[..., 2] > 0) and np.all(nt[..., 2] > 0)):
        raise ValueError("normals must point up (nv_z > 0), see patch_normals")
    mean = 0.5 * (
        nw / np.linalg.norm(nw, axis=-1, keepdims=True)
        + nt / np.linalg.norm(nt, axis=-1, keepdims=True)
    )
    mean /= np.linalg.norm(mean, axis=-1, keepdims=True)
    return np.where(plastic[..., None], nt / np.linalg.norm(nt, axis=-1, keepdims=True), mean)


def tau_geo(p, nv, direction=1):
    """Geometric shear stress of the inclined patches, Eq. 23, entering flanks only.

    ``tau_geo = sum_k p_k |nv_x,k| / nv_z,k / (Nx Ny)`` over the entering flanks: ``nv_x < 0`` for
    sliding of the tool in ``+x`` (``direction=1``), ``nv_x > 0`` for ``direction=-1``; exiting flanks
    are neglected as in the paper (Eq. 22: ``tan phi_k = |nv_x,k| / nv_z,k = tau_x,k / p_k``).

    Parameters
    ----------
    p : array_like, shape (Nx, Ny)
        Contact pressure (Pa), ``>= 0``.
    nv : array_like, shape (Nx, Ny, 3)
        Unit normals of the contact patches (:func:`contact_normals` or :func:`patch_normals`).
    direction : {1, -1}
        Sliding direction of the tool relative to the workpiece along ``x``.

    Returns
    -------
    float
        ``tau_geo`` in Pa, non-negative (resistance against the sliding direction).
    """
    p = np.asarray(p, dtype=float)
    nv = np.asarray(nv, dtype=float)
    if not np.all(np.isfinite(p)) or np.any(p < 0):
        raise ValueError("p must be finite and >= 0")
    if nv.shape != p.shape + (3,) or not np.all(np.isfinite(nv)):
        raise ValueError(f"nv must be finite with shape {p.shape + (3,)}, got {nv.shape}")
    if np.any(nv[..., 2] <= 0):
        raise ValueError("nv must point up (nv_z > 0)")
    if direction not in (1, -1):
        raise ValueError(f"direction must be +1 or -1, got {direction!r}")
    if p.size == 0:
        raise ValueError("p must not be empty")
    tan_phi = -direction * nv[..., 0] / nv[..., 2]  # > 0 on entering flanks
    entering = tan_phi > 0
    return float(np.sum(np.where(entering, p * tan_phi, 0.0)) / p.size)


def tau_geo_from_surfaces(p, z_workpiece, z_tool, block, dx, dy=None, plastic=None, direction=1):
    """Eq. 23 from the measured height maps of both bodies (Eqs. 19-23 in one call).

    Fits the patch planes of both bodies (:func:`fit_patch_planes`), forms their upward normals
    (the tool's in the workpiece's frame), applies the elastic/plastic rule
    (:func:`contact_normals`) and sums the entering flanks (:func:`tau_geo`).

    Parameters
    ----------
    p : array_like, shape (Nx, Ny)
        Contact pressure of the normal solution (Pa).
    z_workpiece, z_tool : array_like, shape (Nx * sx, Ny * sy)
        Measured heights (m) on the same ``x, y`` grid; the tool's heights are positive towards the
        workpiece (as in the composite topography ``h = z_workpiece + z_tool``).
    block : int or (int, int)
        Measured points per solver element ``(sx, sy)``.
    dx, dy : float
        Spacing of the measured points (m).
    plastic : array_like of bool, shape (Nx, Ny), optional
        Plastic set of the normal solution; default: all elastic.
    direction : {1, -1}
        Sliding direction of the tool relative to the workpiece along ``x``.

    Returns
    -------
    float
        ``tau_geo`` in Pa.
    """
    pw = fit_patch_planes(z_workpiece, block, dx, dy)
    pt = fit_patch_planes(z_tool, block, dx, dy)
    p = np.asarray(p, dtype=float)
    if p.shape != pw.alpha.shape or pt.alpha.shape != pw.alpha.shape:
        raise ValueError(
            f"p {p.shape} must match the element grid of both surfaces "
            f"{pw.alpha.shape}, {pt.alpha.shape}"
        )
    plastic = np.zeros(p.shape, bool) if plastic is None else plastic
    nv = contact_normals(
        patch_normals(pw.alpha, pw.beta), patch_normals(-pt.alpha, -pt.beta), plastic
    )
    return tau_geo(p, nv, direction)


def _check_block(block):
    b = (block, block) if np.isscalar(block) else tuple(block)
    if len(b) != 2 or not all(isinstance(v, (int, np.integer)) and v >= 1 for v in b):
        raise ValueError(f"block must be a positive int or a pair of positive ints, got {block!r}")
    if b[0] * b[1] < 3:
        raise ValueError(f"block={b}: a plane needs at least 3 measured points per element")
    return int(b[0]), int(b[1])


def _check_spans_plane(M, s1):
    # Determinant of the centred 2x2 block (weighted covariance of x, y times s1^2) must not vanish.
    with np.errstate(divide="ignore", invalid="ignore"):
        cxx = M[..., 0, 0] - M[..., 0, 2] ** 2 / s1
        cyy = M[..., 1, 1] - M[..., 1, 2] ** 2 / s1
        cxy = M[..., 0, 1] - M[..., 0, 2] * M[..., 1, 2] / s1
        det = cxx * cyy - cxy**2
        scale = np.maximum(cxx * cyy, 1e-300)
    bad = (s1 < 3) | ~(det > 1e-10 * scale)
    if np.any(bad):
        k = tuple(int(i) for i in np.argwhere(bad)[0])
        raise ValueError(
            f"z: element {k} (and {int(bad.sum()) - 1} more) has too few valid points to fit a plane "
            "(need 3 not on one line)"
        )
