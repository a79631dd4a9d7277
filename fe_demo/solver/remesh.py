"""Remeshing with field transfer for the structured axisymmetric meshes.

When free-surface nodes fold onto the die, the corner elements degenerate (a corner
angle near 180 degrees). :func:`remesh` rebuilds the mesh with the same topology: the
current boundary is split into four sides with the die-contact zone as the top side
(folded nodes become top nodes), each side is resampled uniformly by arc length, and
the interior is filled by transfinite (Coons) interpolation. The element connectivity
and every node set stay the same; only positions change. Fields move with it:

- stress and equivalent plastic strain per quadrature point: piecewise-linear
  interpolation over the old quadrature points (nearest point outside their hull);
- ``p_hist``, the friction traction and the last pressure (where ``k_t(p)`` is read) per
  contact node: from the nearest old contact node through
  :meth:`frictionlaw.HistoryState.remap` (so the history is never lost nor invented).
"""

import numpy as np
from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator
from scipy.spatial import cKDTree

from .element import kinematics

__all__ = ["element_quality", "block_corners", "remesh"]


def element_quality(x, t, skip_nodes=None):
    """Smallest corner sine of each quadrilateral (1 for a rectangle, <= 0 degenerate).

    Angles at ``skip_nodes`` (the four corners of the structured block, whose angle the
    boundary shape dictates) are left out.
    """
    xe = x[t]  # (4, ne, 2)
    q = np.full(t.shape[1], np.inf)
    skip = np.zeros(x.shape[0], bool)
    if skip_nodes is not None:
        skip[np.asarray(skip_nodes)] = True
    for a in range(4):
        e1 = xe[(a + 1) % 4] - xe[a]
        e2 = xe[(a + 3) % 4] - xe[a]
        cr = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
        s = cr / (np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1))
        q = np.minimum(q, np.where(skip[t[a]], np.inf, s))
    return q


def block_corners(axi):
    """The four corner nodes of the structured block."""
    g = axi.grid
    return np.array([g[0, 0], g[-1, 0], g[0, -1], g[-1, -1]])


def _resample(poly, n):
    """``n`` points uniformly by arc length along the polyline ``poly`` (m, 2)."""
    seg = np.hypot(*np.diff(poly, axis=0).T)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    u = np.linspace(0.0, s[-1], n)
    return np.column_stack([np.interp(u, s, poly[:, 0]), np.interp(u, s, poly[:, 1])])


def _sides(x, grid, on_die):
    """Bottom, top (inner -> outer) and inner, outer (bottom -> top) polylines."""
    nr1, nz1 = grid.shape
    outer_up = grid[-1, :]
    top_in = grid[::-1, -1]  # outer -> inner along the top
    inner_down = grid[0, ::-1]
    loop = np.concatenate([outer_up, top_in[1:], inner_down[1:]])  # bottom-outer ... bottom-inner
    die = on_die[loop]
    if not die.any():
        raise RuntimeError("no node on the die: nothing to remesh against")
    first = int(np.argmax(die))
    last = int(loop.size - 1 - np.argmax(die[::-1]))
    pts = x[loop]
    outer = pts[: first + 1]
    top = pts[first : last + 1][::-1]  # inner -> outer
    inner = pts[last:][::-1]  # bottom -> top
    bottom = x[grid[:, 0]]
    if outer.shape[0] < 2 or inner.shape[0] < 2 or top.shape[0] < 2:
        raise RuntimeError("die contact covers a whole side: cannot split the boundary")
    return bottom, _resample(top, nr1), _resample(inner, nz1), _resample(outer, nz1)


def _coons(bottom, top, inner, outer):
    nr1, nz1 = bottom.shape[0], inner.shape[0]
    xi = np.linspace(0.0, 1.0, nr1)[:, None, None]
    eta = np.linspace(0.0, 1.0, nz1)[None, :, None]
    B, T = bottom[:, None, :], top[:, None, :]
    L, R = inner[None, :, :], outer[None, :, :]
    return (
        (1 - eta) * B
        + eta * T
        + (1 - xi) * L
        + xi * R
        - (1 - xi) * (1 - eta) * bottom[0]
        - xi * (1 - eta) * bottom[-1]
        - (1 - xi) * eta * top[0]
        - xi * eta * top[-1]
    )


def _interp(points, values, targets):
    lin = LinearNDInterpolator(points, values)(targets)
    bad = ~np.isfinite(lin).all(axis=-1) if lin.ndim > 1 else ~np.isfinite(lin)
    if bad.any():
        lin[bad] = NearestNDInterpolator(points, values)(targets[bad])
    return lin


def remesh(model):
    """Rebuild ``model``'s node positions and transfer its fields (in place).

    Returns the smallest element quality after remeshing. Raises ``RuntimeError``
    (the model is then unchanged) if the new mesh would have an inverted element or
    would not raise the worst element quality.
    """
    axi = model.axi
    x_old = model.x
    on_die = np.zeros(x_old.shape[0], bool)
    if model.accepted is None:
        raise RuntimeError("no accepted increment: nothing to remesh against")
    on_die[model.contact.nodes[model.accepted.p > 0]] = True
    on_die[axi.sym_nodes] = False
    sides = _sides(x_old, axi.grid, on_die)
    new = _coons(*sides)
    x_new = np.empty_like(x_old)
    x_new[axi.grid.ravel()] = new.reshape(-1, 2)
    # symmetry and axis nodes stay on their planes
    x_new[axi.sym_nodes, 1] = 0.0
    if axi.axis_nodes.size:
        x_new[axi.axis_nodes, 0] = 0.0
    kin_new = kinematics(x_new, model.t)
    if not kin_new.valid:
        raise RuntimeError("remeshed grid has an inverted element")
    corners = block_corners(axi)
    qual_old = float(element_quality(x_old, model.t, corners).min())
    qual_new = float(element_quality(x_new, model.t, corners).min())
    if qual_new <= qual_old:
        raise RuntimeError(
            f"remeshing would not improve the quality ({qual_old:.3f} -> {qual_new:.3f})"
        )
    # quadrature-point fields
    kin_old = kinematics(x_old, model.t)
    z_old = np.einsum("aq,ae->eq", kin_old.N, x_old[model.t, 1])
    z_new = np.einsum("aq,ae->eq", kin_new.N, x_new[model.t, 1])
    q_old = np.column_stack([kin_old.r.ravel(), z_old.ravel()])
    q_new = np.column_stack([kin_new.r.ravel(), z_new.ravel()])
    vals = np.column_stack([model.sigma.reshape(-1, 4), model.eps_p.reshape(-1, 1)])
    tr = _interp(q_old, vals, q_new)
    model.sigma = tr[:, :4].reshape(model.sigma.shape)
    model.eps_p = np.maximum(tr[:, 4].reshape(model.eps_p.shape), 0.0)
    # reference positions for displacement output
    model.X0 = _interp(x_old, model.X0, x_new)
    # contact nodes: nearest old contact node keeps its p_hist and traction
    cn = model.contact.nodes
    idx = cKDTree(x_old[cn]).query(x_new[cn])[1].astype(np.int64)
    model.contact.state.remap(idx)
    model.contact.tau_old = model.contact.tau_old[idx]
    model.contact.p_old = model.contact.p_old[idx]
    model.x = x_new
    model.du_last = None
    model.dz_last = None
    model.n_remesh += 1
    return qual_new
