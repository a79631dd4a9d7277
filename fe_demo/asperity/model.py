"""The plane-strain strip pressed by a rigid flat and stretched between its symmetry sides.

The FE core is fe_demo's (:mod:`fe_demo.solver`): the bilinear B-bar element in its plane-strain
form (``kinematics(..., plane_strain=True)``), the J2 radial return with its consistent tangent,
the updated-Lagrangian increment (mid-increment strain increment, Hughes-Winget rotation,
equilibrium on the end configuration) and the linear solve with a reused factorisation. What
this module adds is the problem:

- **Boundary conditions.** ``u_z = 0`` on the bottom (frictionless support), ``u_x = 0`` on the
  left side, ``u_x = u_side`` on the right side (both sides are symmetry planes: the strip is
  one cell of a surface mirrored about them). The bulk strain is ``ln(L / L0)``.
- **The flat.** A rigid, frictionless plane ``z = w`` above the strip. Every top node is a
  candidate; a node above the plane carries the penalty pressure ``eps_n (z - w)`` over its
  tributary length (the ``x``-projected half lengths of its top edges at the start of the
  increment). The flat's position ``w`` is a dof: its equation is the load, the sum of the
  nodal forces equal to ``P = p L`` (load control, ``p`` the nominal pressure on the current
  apparent length); or ``w`` is prescribed (displacement control, for the flat punch).
  A punch of half-width ``a`` (its edge at ``x = a``) is the flat acting only on the top nodes
  that start at ``x <= a``.

Newton iterations with a backtracking line search, cut-backs by halving (logged), as in
:class:`fe_demo.solver.FormingModel`; a step that cannot be completed says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..solver.element import (
    Assembler,
    ReducedPattern,
    internal_force,
    kinematics,
    stiffness,
    strain_increment,
)
from ..solver.linsolve import TangentSolver
from ..solver.material import radial_return

__all__ = ["StripModel", "StepResult"]


@dataclass
class StepResult:
    """Outcome of one load step (after any cut-backs)."""

    converged: bool
    nit: int
    cutbacks: int
    message: str


@dataclass
class _Trial:
    du: np.ndarray
    w: float
    sigma: np.ndarray
    eps_p: np.ndarray
    D: np.ndarray
    kin: object
    force: np.ndarray  # contact force per top node (N/m)
    active: np.ndarray
    R: np.ndarray  # residual over all dofs (reactions included), contact included
    r_w: float  # the load equation's residual (N/m); 0 under displacement control
    norm: float  # residual norm (N/m) over the free dofs and the load equation
    ref: float  # internal-force norm (N/m), floored: the scale of the convergence test


def geometric_stiffness(kin, sigma):
    """The derivative of ``int B^T sigma dv`` with the stress held, by the nodal positions.

    fe_demo's forming model leaves it out (its dies confine the flow and DC04 hardens); a
    perfectly plastic asperity has no material stiffness along its flow, and there this term
    (order ``sigma``) is what the tangent has. With it the tangent agrees with finite
    differences of the residual to 1e-3 (``tests/test_fe_asperity.py``).

    ``K[(a, i), (b, m)] = int (sigma_ij N_a,j N_b,m - sigma_ij N_b,j N_a,m) dv`` (plane strain,
    in-plane Cauchy stress of ``sigma (n_el, nq, 4)``; the B-bar's volumetric average left out):
    the change of the gradients and of the volume with the end configuration. Returns
    ``(n_el, 8, 8)``.
    """
    s2 = np.empty(sigma.shape[:2] + (2, 2))
    s2[..., 0, 0] = sigma[..., 0]
    s2[..., 1, 1] = sigma[..., 1]
    s2[..., 0, 1] = s2[..., 1, 0] = sigma[..., 3]
    g = kin.dNdx  # (ne, nq, 4, 2)
    ne, nq = kin.dV.shape
    sg = np.matmul(g, s2)  # (sigma grad N_a)_i, sigma symmetric: (ne, nq, 4, 2)
    gw = (g * kin.dV[..., None, None]).reshape(ne, nq, 8).transpose(0, 2, 1)  # (ne, 8, nq)
    # t1[(a, i), (b, m)] = sum_q dv (sigma grad N_a)_i N_b,m
    t1 = np.matmul(
        (sg * kin.dV[..., None, None]).reshape(ne, nq, 8).transpose(0, 2, 1), g.reshape(ne, nq, 8)
    )
    # t2[(a, i), (b, m)] = sum_q dv N_a,m (sigma grad N_b)_i: [(a, m), (b, i)] transposed
    t2 = np.matmul(gw, sg.reshape(ne, nq, 8)).reshape(ne, 4, 2, 4, 2).transpose(0, 1, 4, 3, 2)
    return t1 - t2.reshape(ne, 8, 8)


class StripModel:
    """The strip of a :class:`~fe_demo.asperity.mesh.StripMesh` under a rigid flat.

    Parameters
    ----------
    mesh : StripMesh
    material : fe_demo.solver.Material
    punch_half_width : float or None
        The flat acts on the top nodes that start at ``x <= punch_half_width`` only (a flat
        punch centred on the left symmetry side); ``None``: the whole top.
    penalty_factor : float
        ``eps_n = penalty_factor E / h`` (Pa/m), ``h`` the top elements' width.
    rtol : float
        Newton tolerance: residual norm over the free dofs and the load equation, relative to
        the norm of the internal forces over all dofs.
    max_iter, max_cutbacks : int
    kernels : {"numba", "numpy"}
    """

    def __init__(
        self,
        mesh,
        material,
        *,
        punch_half_width=None,
        penalty_factor=10.0,
        rtol=1e-7,
        max_iter=30,
        max_cutbacks=8,
        kernels="numba",
    ):
        self.mesh = mesh
        self.mat = material
        self.t = mesh.t
        self.x = mesh.x.copy()
        self.X0 = mesh.x.copy()
        n = self.x.shape[0]
        self.n_nodes = n
        self.asm = Assembler(self.t, n)
        ne = self.t.shape[1]
        self.sigma = np.zeros((ne, 4, 4))
        self.eps_p = np.zeros((ne, 4))
        fixed = np.zeros(2 * n, bool)
        fixed[2 * mesh.left] = True
        fixed[2 * mesh.right] = True
        fixed[2 * mesh.bottom + 1] = True
        self.fixed = fixed
        self.free = ~fixed
        self.top = mesh.top
        self.candidate = np.ones(self.top.size, bool)
        if punch_half_width is not None:
            self.candidate = self.X0[self.top, 0] <= punch_half_width * (1 + 1e-12)
        self.eps_n = penalty_factor * material.E / (mesh.length / mesh.nx)
        self.w = float(self.x[self.top, 1].max())
        self.u_side = 0.0
        self.load = 0.0  # P (N/m) of the last accepted state
        self.rtol = rtol
        self.max_iter = max_iter
        self.max_cutbacks = max_cutbacks
        self.kernels = kernels

        # the strip is numbered column by column: its natural order is banded (fill as small as
        # MMD_AT_PLUS_A gives, half its ordering time)
        self.linear = TangentSolver(True, 1e-10, permc_spec="NATURAL", backend="superlu")
        self.force = np.zeros(self.top.size)
        self.reactions = np.zeros(2 * n)
        self._patterns = {}
        self.last = None  # (du, dw, d u_side, d load) of the last accepted increment
        self.w_old = self.u_old = self.load_old = 0.0
        self.log = []
        self.n_newton = 0
        self.f_floor = 1e-3 * material.sigma_y0 * mesh.length

    # ---------------------------------------------------------------- state
    @property
    def length(self):
        """Current apparent length ``L`` (m)."""
        return self.mesh.length + self.u_side

    @property
    def bulk_strain(self):
        """In-plane bulk strain ``ln(L / L0)``."""
        return math.log(self.length / self.mesh.length)

    def tributary(self, x=None):
        """The top nodes' tributary lengths (m): half the ``x`` extent of each adjacent edge."""
        xt = (self.x if x is None else x)[self.top, 0]
        dx = np.abs(np.diff(xt))
        a = np.zeros(xt.size)
        a[:-1] += 0.5 * dx
        a[1:] += 0.5 * dx
        return a

    # ---------------------------------------------------------------- kernel
    def _evaluate(self, du, w, load, area):
        x1 = self.x + du.reshape(-1, 2)
        xm = self.x + 0.5 * du.reshape(-1, 2)
        kin1 = kinematics(x1, self.t, self.kernels, plane_strain=True)
        kinm = kinematics(xm, self.t, self.kernels, plane_strain=True)
        if not (kin1.valid and kinm.valid):
            return None
        deps, sig0 = strain_increment(kinm, self.asm.edofs, du, self.sigma, self.kernels)
        sig, ep, D, _ = radial_return(self.mat, sig0, self.eps_p, deps, kernels=self.kernels)
        R = self.asm.vector(internal_force(kin1, sig, self.kernels))
        ref = max(float(np.linalg.norm(R)), self.f_floor)
        g = x1[self.top, 1] - w
        active = (g > 0) & self.candidate
        force = np.where(active, self.eps_n * g * area, 0.0)
        R[2 * self.top + 1] += force
        r_w = float(force.sum() - load) if load is not None else 0.0
        norm = math.hypot(float(np.linalg.norm(R[self.free])), r_w)
        return _Trial(du, w, sig, ep, D, kin1, force, active, R, r_w, norm, ref)

    def _pattern(self, load_control):
        """The free-dof tangent's fixed pattern (:class:`ReducedPattern`).

        The element matrices, the contact diagonal of the top nodes' ``z`` and, under load
        control, the flat's row and column (its dof last).
        """
        if load_control not in self._patterns:
            nf = int(self.free.sum())
            index = np.full(2 * self.n_nodes, -1, dtype=np.int64)
            index[self.free] = np.arange(nf)
            zi = index[2 * self.top + 1]
            if load_control:
                w = np.full(zi.size, nf)
                rows = np.concatenate([zi, zi, w, [nf]])
                cols = np.concatenate([zi, w, zi, [nf]])
            else:
                rows, cols = zi, zi
            edofs = self.asm.edofs
            rows = np.concatenate([index[np.repeat(edofs, 8, axis=1).ravel()], rows])
            cols = np.concatenate([index[np.tile(edofs, (1, 8)).ravel()], cols])
            self._patterns[load_control] = ReducedPattern(rows, cols, nf + int(load_control), "csc")
        return self._patterns[load_control]

    def _tangent(self, trial, area, load_control):
        """The free-dof tangent, bordered by the flat's dof under load control."""
        ke = stiffness(trial.kin, trial.D, self.kernels) + geometric_stiffness(
            trial.kin, trial.sigma
        )
        act = trial.active
        if load_control and not act.any():
            # no node touches: keep the highest candidate's penalty in the tangent, so that the
            # flat's equation has a pivot (the residual keeps the true, open contact)
            act = np.zeros_like(act)
            zt = np.where(self.candidate, self.x[self.top, 1], -np.inf)
            act[int(np.argmax(zt))] = True
        kn = np.where(act, self.eps_n * area, 0.0)
        pattern = self._pattern(load_control)
        if not load_control:
            return pattern.matrix(ke, kn)
        # d R_z / d w = -eps_n A, d r_w / d z = eps_n A, d r_w / d w = -sum eps_n A
        return pattern.matrix(ke, kn, -kn, kn, [-kn.sum()])

    def _newton(self, du, w, u_side, load):
        """One attempt to reach ``u_side`` with ``load`` (or the flat at ``w``)."""
        load_control = load is not None
        area = self.tributary()
        du = du.copy()
        du[2 * self.mesh.right] = u_side - self.u_side
        du[2 * self.mesh.left] = 0.0
        du[2 * self.mesh.bottom + 1] = 0.0
        trial = self._evaluate(du, w, load, area)
        if trial is None:
            return None, 0, "inverted element at the predictor"
        for it in range(1, self.max_iter + 1):
            self.n_newton += 1
            K = self._tangent(trial, area, load_control)
            b = -trial.R[self.free]
            if load_control:
                b = np.concatenate([b, [-trial.r_w]])
            try:
                d = self.linear.solve(K, b)
            except RuntimeError as exc:
                return None, it, f"linear solve failed: {exc}"
            if not np.all(np.isfinite(d)):
                return None, it, "linear solve gave non-finite values"
            step = np.zeros_like(du)
            step[self.free] = d[: int(self.free.sum())]
            dw = float(d[-1]) if load_control else 0.0
            s, best = self._entry_limit(trial, step, dw), None
            if s < 1.0:
                # a node enters: take the limited step whatever the residual (the next tangent
                # holds the node), unless it inverts an element
                best = self._evaluate(trial.du + s * step, trial.w + s * dw, load, area)
            for _ in range(8 if best is None else 0):
                cand = self._evaluate(trial.du + s * step, trial.w + s * dw, load, area)
                if cand is not None:
                    if best is None or cand.norm < best.norm:
                        best = cand
                    if cand.norm <= (1.0 - 1e-4 * s) * trial.norm:
                        break
                s *= 0.5
            if best is None:
                return None, it, "every line-search step inverts an element"
            trial = best
            if trial.norm <= self.rtol * trial.ref:
                return trial, it, "converged"
        return None, self.max_iter, f"no convergence in {self.max_iter} iterations"

    def _entry_limit(self, trial, step, dw):
        """The largest step fraction (at most 1) that lets no open node enter the flat deeply.

        Deeply: beyond ``3 sigma_y / eps_n`` (the penetration of a hardness-like pressure).

        A perfectly plastic asperity under a load-controlled flat has almost no stiffness until
        the next node touches: the full Newton step then drives the flat far down and many open
        nodes deep into it. Limited, each new node enters gently and the next tangent holds it.
        """
        z = self.x[self.top, 1] + trial.du[2 * self.top + 1]
        g = z - trial.w
        dg = step[2 * self.top + 1] - dw
        open_ = self.candidate & (g <= 0) & (dg > 0)
        if not open_.any():
            return 1.0
        allow = 3.0 * self.mat.sigma_y0 / self.eps_n
        s = (allow - g[open_]) / dg[open_]
        return float(min(1.0, max(s.min(), 1e-3)))

    def _commit(self, trial, u_side, load):
        self.w_old, self.u_old, self.load_old = self.w, self.u_side, self.load
        self.x = self.x + trial.du.reshape(-1, 2)
        self.sigma = trial.sigma
        self.eps_p = trial.eps_p
        self.w = trial.w
        self.u_side = u_side
        self.load = float(trial.force.sum()) if load is None else load
        self.force = trial.force
        self.last = (trial.du, trial.w - self.w_old, u_side - self.u_old, self.load - self.load_old)
        self.reactions = trial.R.copy()

    def step(self, u_side, *, p=None, w=None):
        """Go to the side displacement ``u_side`` (m) at the pressure ``p`` or the flat at ``w``.

        ``p``: the nominal pressure (Pa), ``w``: the flat's position (m); linearly from the
        current state, cutting back as needed.

        Under load control the load at a point of the step is ``p_step L``, ``p_step`` linear
        between the last accepted nominal pressure and ``p``.
        """
        if (p is None) == (w is None):
            raise ValueError("give exactly one of p (load control) and w (flat position)")
        u0, w0 = self.u_side, self.w
        p0 = self.load / self.length
        frac, sub, nit, cutbacks = 0.0, 1.0, 0, 0
        while frac < 1.0 - 1e-12:
            h = min(sub, 1.0 - frac)
            f1 = frac + h
            us = u0 + f1 * (u_side - u0)
            length = self.mesh.length + us
            if p is not None:
                load = (p0 + f1 * (p - p0)) * length
                du, wt = self._predictor(us, load)
            else:
                load, wt = None, w0 + f1 * (w - w0)
                du, _ = self._predictor(us, None, wt - self.w)
            trial, k, msg = self._newton(du, wt, us, load)
            nit += k
            if trial is None:
                cutbacks += 1
                self.log.append(
                    f"cut-back at strain {self.bulk_strain:.5f}, load {self.load:.4g} N/m: {msg}"
                )
                if cutbacks > self.max_cutbacks:
                    return StepResult(False, nit, cutbacks, msg)
                sub = 0.5 * h
                continue
            self._commit(trial, us, load)
            frac = f1
        return StepResult(True, nit, cutbacks, "converged")

    def _predictor(self, us, load, dw=None):
        """Initial ``(du, w)`` of an increment: the last accepted increment scaled to this one.

        Scaled by the side displacement's increment when the strip is stretched, else by the
        load's (pressing) or the flat's (displacement control) increment. Without a last
        increment: no displacement and the flat lowered until the highest candidate node carries
        the load on its penalty alone.
        """
        zero = np.zeros(2 * self.n_nodes)
        if self.last is None:
            if load is None:
                return zero, self.w + dw
            zt = np.where(self.candidate, self.x[self.top, 1], -np.inf)
            k = int(np.argmax(zt))
            return zero, float(zt[k]) - load / (self.eps_n * self.tributary()[k])
        du_l, dw_l, dside_l, dload_l = self.last
        d_side = us - self.u_side
        if abs(dside_l) > 0 and abs(d_side) > 0:
            f = d_side / dside_l
        elif load is not None and abs(dload_l) > 0:
            f = (load - self.load) / dload_l
        elif dw is not None and abs(dw_l) > 0:
            f = dw / dw_l
        else:
            f = 0.0
        return du_l * f, self.w + (dw_l * f if dw is None else dw)
