"""Updated-Lagrangian incremental Newton solver for axisymmetric forming between flat dies.

Per increment the die moves by ``dz`` and the displacement increment ``du`` is found
by Newton's method with a backtracking line search. Kinematics: the strain increment
is the symmetric gradient of ``du`` on the mid-increment configuration (second-order
accurate logarithmic strain increment), the stress of the last increment is rotated
by the mid-increment spin (Hughes-Winget, in the r-z plane), and equilibrium is
written on the end-of-increment configuration. The tangent is the consistent
material tangent on the end configuration (geometric stiffness omitted, so the
convergence is fast-linear rather than quadratic).

Failed increments (no convergence in ``max_iter``, an inverted element, a stalled
line search) are rolled back, the increment is cut back and retried; every cut-back
is logged with its reason. When the step falls below ``min_step`` the run stops with
``converged = False`` and a message; nothing is silently accepted.
"""

import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .contact import DieContact, nodal_areas, surface_projection
from .element import (
    Assembler,
    check_kernels,
    internal_force,
    kinematics,
    stiffness,
    strain_increment,
)
from .linsolve import TangentSolver, _norm
from .material import DC04, radial_return

__all__ = ["SolverOptions", "IncrementResult", "FormingModel", "Timings"]


@dataclass
class SolverOptions:
    """Newton and increment-control settings.

    Attributes
    ----------
    rtol : float
        Residual tolerance relative to the internal-force norm.
    max_iter : int
        Newton iterations per increment attempt.
    max_cutbacks : int
        Successive halvings of one increment before the run is declared failed.
    line_search : bool
        Backtracking line search on the residual norm.
    penalty_factor : float
        Contact penalty ``eps_n = penalty_factor * E / h_min`` (Pa/m), also used for stick.
    reuse_factorisation : bool
        Solve each tangent by iterative refinement with the last sparse LU, refactorising only
        when that misses ``linear_rtol`` (:class:`~fe_demo.solver.linsolve.TangentSolver`); ``False``:
        a fresh LU per Newton iteration (the reference; same results to ``linear_rtol``). SuperLU
        only: PARDISO factorises every tangent (cheaper than refinement there).
    linear_rtol : float
        Relative residual of the linear solve, ``|K d - b| <= linear_rtol |b|``.
    kernels : {"numba", "numpy"}
        The element loops and the return map: numba kernels (:mod:`fe_demo.solver._kernels`) or the
        vectorised NumPy reference; the same results to rounding.
    linear_solver : {"auto", "superlu", "pardiso"}
        Direct solver of :class:`~fe_demo.solver.linsolve.TangentSolver`: ``"pardiso"`` needs the
        optional extra ``pardiso`` (pypardiso, MKL), ``"auto"`` uses it when installed and
        SuperLU otherwise.
    linear_threads : int
        MKL threads for PARDISO (1 or 2).
    """

    rtol: float = 1e-6
    max_iter: int = 25
    max_cutbacks: int = 6
    line_search: bool = True
    penalty_factor: float = 10.0
    reuse_factorisation: bool = True
    linear_rtol: float = 1e-10
    kernels: str = "numba"
    linear_solver: str = "auto"
    linear_threads: int = 1

    def __post_init__(self):
        check_kernels(self.kernels)


@dataclass
class IncrementResult:
    """Outcome of one increment (after any cut-backs)."""

    converged: bool
    nit: int
    message: str
    cutbacks: int = 0
    dz: float = 0.0


@dataclass
class _Trial:
    du: np.ndarray
    sigma: np.ndarray
    eps_p: np.ndarray
    contact: object
    norm: float
    ref: float
    valid: bool
    kin: object = None
    D: object = None


@dataclass
class Timings:
    """Seconds spent per phase (kinematics+material, assembly, solve, contact)."""

    kinematics: float = 0.0
    material: float = 0.0
    assembly: float = 0.0
    solve: float = 0.0
    contact: float = 0.0
    other: dict = field(default_factory=dict)

    def as_dict(self):
        return {
            "kinematics": self.kinematics,
            "material": self.material,
            "assembly": self.assembly,
            "solve": self.solve,
            "contact": self.contact,
        }


class FormingModel:
    """Axisymmetric half-model pressed by a rigid flat die from above.

    Parameters
    ----------
    axi : fe_demo.solver.mesh.AxiMesh
        Mesh and node sets.
    material : fe_demo.solver.material.Material
    law_factory : callable or None
        ``law_factory(model) -> law`` is called at the start of every increment
        (so that Tresca's ``k`` can follow the current flow stress); ``None`` for
        frictionless dies.
    options : SolverOptions
    flattening : bool
        Pass each die node's bulk plastic strain increment and flow stress to the law (its
        flattening block, issue 43; :class:`~fe_demo.solver.contact.DieContact`).
    """

    def __init__(self, axi, material=DC04, law_factory=None, options=None, flattening=False):
        self.axi = axi
        self.mat = material
        self.opt = options or SolverOptions()
        self.law_factory = law_factory
        mesh = axi.mesh
        self.t = mesh.t
        self.X0 = mesh.p.T.copy()
        self.x = self.X0.copy()
        self.n_nodes = self.x.shape[0]
        self.asm = Assembler(self.t, self.n_nodes)
        ne = self.t.shape[1]
        self.sigma = np.zeros((ne, 4, 4))
        self.eps_p = np.zeros((ne, 4))
        fixed = np.zeros(2 * self.n_nodes, bool)
        fixed[2 * axi.axis_nodes] = True
        fixed[2 * axi.sym_nodes + 1] = True
        self.free = ~fixed
        self.z_die = float(self.x[:, 1].max())
        self.h0 = 2.0 * self.z_die
        kin = kinematics(self.x, self.t)
        if not kin.valid:
            raise ValueError("mesh has inverted elements")
        h_min = float(np.sqrt((kin.dV / (2 * np.pi * np.maximum(kin.r, 1e-30))).sum(1).min()))
        eps = self.opt.penalty_factor * material.E / h_min
        self.f_floor = 1e-3 * material.sigma_y0 * np.pi * float(self.x[:, 0].max()) ** 2
        self.contact = DieContact(axi.contact_nodes, None, eps, eps, flattening)
        self.du_last = None
        self.dz_last = None
        self.accepted = None
        self.log = []
        self.timings = Timings()
        self.linear = TangentSolver(
            self.opt.reuse_factorisation,
            self.opt.linear_rtol,
            backend=self.opt.linear_solver,
            threads=self.opt.linear_threads,
        )
        self._pattern = None  # the free-dof tangent's pattern (numba kernels), built when needed
        self.n_newton = 0
        self.n_remesh = 0

    # ------------------------------------------------------------------ state
    @property
    def height(self):
        """Current height of the full workpiece (m), from the die position."""
        return 2.0 * self.z_die

    @property
    def height_reduction(self):
        """``(h0 - h) / h0``."""
        return 1.0 - self.height / self.h0

    def mean_flow_stress(self):
        """Flow stress at the volume-averaged equivalent plastic strain (Pa)."""
        kin = kinematics(self.x, self.t)
        ep = float((self.eps_p * kin.dV).sum() / kin.dV.sum())
        return float(self.mat.flow_stress(ep))

    def flow_stress_hom(self):
        """Flow stress at the homogeneous-compression strain ``ln(h0 / h)`` (Pa).

        The slab method's and the ring charts' ``sigma_f``; Tresca's ``k`` in the demo.
        """
        return float(self.mat.flow_stress(max(math.log(self.h0 / self.height), 0.0)))

    def die_force(self):
        """Die force (N) of the last accepted increment."""
        ev = self.accepted
        return 0.0 if ev is None else float(ev.fz.sum())

    # ------------------------------------------------------------------ kernel
    def _evaluate(self, du, z_die, area):
        tm = self.timings
        t0 = time.perf_counter()
        x1 = self.x + du.reshape(-1, 2)
        xm = self.x + 0.5 * du.reshape(-1, 2)
        kern = self.opt.kernels
        kin1 = kinematics(x1, self.t, kern)
        kinm = kinematics(xm, self.t, kern)
        t1 = time.perf_counter()
        tm.kinematics += t1 - t0
        if not (kin1.valid and kinm.valid):
            return None
        deps, sig0 = strain_increment(kinm, self.asm.edofs, du, self.sigma, kern)
        sig, ep, D, _ = radial_return(self.mat, sig0, self.eps_p, deps, kernels=kern)
        t2 = time.perf_counter()
        tm.material += t2 - t1
        R = self.asm.vector(internal_force(kin1, sig, kern))
        ref = float(_norm(R[self.free]))
        nodes = self.contact.nodes
        ev = self.contact.evaluate(
            x1[nodes, 1], z_die, du[2 * nodes], area, self.x[nodes, 0], **self._bulk(kin1, ep)
        )
        R[2 * nodes + 1] += ev.fz
        R[2 * nodes] += ev.fr
        R[~self.free] = 0.0
        tm.contact += time.perf_counter() - t2
        # force scale: internal forces, floored at 1e-3 of the initial yield force so that
        # a fully unloaded (self-equilibrated) body can still converge
        trial = _Trial(du, sig, ep, ev, float(_norm(R)), max(ref, self.f_floor), True)
        trial.kin = kin1
        trial.D = D
        return trial, R

    def _bulk(self, kin, ep):
        """``d_eps``, ``sigma_y``, ``hardening`` at the die nodes for a flattening run (else ``{}``).

        The increment's equivalent plastic strain (trial ``ep`` less the committed), and the
        flow stress and hardening modulus ``d sigma_y / d eps_p`` at the trial strain (the
        latter limits the lattice's rate, docs/flattening.md Eq. F2c; not passed where the
        law's ``beta`` was fitted to a sheet taken as perfectly plastic, which absorbs the
        hardening already: :attr:`DieContact.pass_hardening`), each carried from the
        Gauss points of the node's elements by :func:`~fe_demo.solver.contact.surface_projection`.
        """
        if not self.contact.flattening:
            return {}
        nodes = self.contact.nodes
        d_eps = surface_projection(self.t, kin.N, kin.dV, ep - self.eps_p, nodes)
        eps = surface_projection(self.t, kin.N, kin.dV, ep, nodes)
        out = {"d_eps": np.maximum(d_eps, 0.0), "sigma_y": self.mat.flow_stress(eps)}
        if self.contact.pass_hardening:
            out["hardening"] = self.mat.hardening(eps)
        return out

    def surface_plastic_strain(self):
        """Equivalent plastic strain at the die nodes (accepted state), projected as :meth:`_bulk`."""
        kin = kinematics(self.x, self.t)
        return surface_projection(self.t, kin.N, kin.dV, self.eps_p, self.contact.nodes)

    def _tangent(self, trial):
        """Global tangent at ``trial``: material part plus the contact terms."""
        t0 = time.perf_counter()
        ev = trial.contact
        nodes = self.contact.nodes
        ke = stiffness(trial.kin, trial.D, self.opt.kernels)
        zi, ri = 2 * nodes + 1, 2 * nodes
        if self.opt.kernels == "numba":
            # straight into the free-dof matrix's data through a pattern built once
            if self._pattern is None:
                fmt = "csr" if self.linear.backend == "pardiso" else "csc"
                rows = np.concatenate([zi, ri, ri])
                cols = np.concatenate([zi, ri, zi])
                self._pattern = self.asm.reduced(self.free, rows, cols, fmt)
            K = self._pattern.matrix(ke, ev.kzz, ev.krr, ev.krz)
            self.timings.assembly += time.perf_counter() - t0
            return K
        K = self.asm.matrix(ke)
        Kc = sp.coo_matrix(
            (
                np.concatenate([ev.kzz, ev.krr, ev.krz]),
                (np.concatenate([zi, ri, ri]), np.concatenate([zi, ri, zi])),
            ),
            shape=K.shape,
        )
        K = (K + Kc.tocsr())[self.free][:, self.free].tocsc()
        self.timings.assembly += time.perf_counter() - t0
        return K

    def _predictor(self, dz):
        """Initial guess for the increment ``dz``.

        The last accepted increment scaled to ``dz``; without one a vertical compression
        that slightly penetrates the die (every top node starts active and sticking,
        which keeps Tresca-type laws from chattering).
        """
        if self.du_last is not None and self.dz_last:
            return self.du_last * (dz / self.dz_last)
        h = self.z_die
        du = np.zeros(2 * self.n_nodes)
        du[1::2] = 0.99 * dz * self.x[:, 1] / h
        du[~self.free] = 0.0
        return du

    def _newton(self, dz):
        """One increment attempt; returns (trial or None, nit, message)."""
        z_die = self.z_die + dz
        area = nodal_areas(self.x, self.axi.boundary_edges, self.contact.nodes)
        du = self._predictor(dz)
        out = self._evaluate(du, z_die, area)
        if out is None:
            return None, 0, "inverted element at the predictor"
        trial, R = out
        free = self.free
        for it in range(1, self.opt.max_iter + 1):
            self.n_newton += 1
            Kff = self._tangent(trial)
            t0 = time.perf_counter()
            try:
                d = self.linear.solve(Kff, -R[free])
            except RuntimeError as exc:  # singular factor
                return None, it, f"linear solve failed: {exc}"
            self.timings.solve += time.perf_counter() - t0
            if not np.all(np.isfinite(d)):
                return None, it, "linear solve gave non-finite values"
            step = np.zeros_like(du)
            step[free] = d
            s = 1.0
            best = None
            for _ in range(6 if self.opt.line_search else 1):
                cand = self._evaluate(du + s * step, z_die, area)
                if cand is not None:
                    if best is None or cand[0].norm < best[0].norm:
                        best = cand
                    if cand[0].norm <= (1.0 - 1e-4 * s) * trial.norm:
                        break
                s *= 0.5
            if best is None:
                return None, it, "every line-search step inverts an element"
            trial, R = best
            du = trial.du
            if trial.norm <= self.opt.rtol * trial.ref:
                if cand is not best and self.contact.flattening:
                    # the state's trial alpha_f is the last evaluation's: evaluate the accepted
                    # candidate again (p_hist's trial has the same lag without flattening, where
                    # it is left as it was: max(p_hist, p) of a neighbouring line-search step)
                    trial, R = self._evaluate(du, z_die, area)
                return trial, it, "converged"
        return (
            None,
            self.opt.max_iter,
            (
                f"no convergence in {self.opt.max_iter} iterations "
                f"(|R|/|f_int| = {trial.norm / trial.ref:.2e})"
            ),
        )

    def _commit(self, trial, dz):
        self.x = self.x + trial.du.reshape(-1, 2)
        self.sigma = trial.sigma
        self.eps_p = trial.eps_p
        self.z_die += dz
        self.contact.commit(trial.contact)
        self.accepted = trial.contact
        self.du_last = trial.du
        self.dz_last = dz

    def increment(self, dz):
        """Move the die by ``dz`` (m, negative = down), cutting back as needed.

        Sub-steps after a cut-back are taken at the reduced size until ``dz`` is
        covered. Returns an :class:`IncrementResult`; on failure the model is left
        at the last accepted state.
        """
        if not math.isfinite(dz):
            raise ValueError(f"dz must be finite, got {dz!r}")
        remaining = dz
        sub = dz
        nit_total = 0
        cutbacks = 0
        while abs(remaining) > 1e-12 * abs(dz):
            if self.law_factory is not None:
                self.contact.law = self.law_factory(self)
            step = sub if abs(sub) < abs(remaining) else remaining
            trial, nit, msg = self._newton(step)
            nit_total += nit
            if trial is None:
                self.contact.rollback()
                cutbacks += 1
                self.log.append(
                    f"cut-back at reduction {self.height_reduction:.4f}: dz={step:.3e} m: {msg}"
                )
                if cutbacks > self.opt.max_cutbacks:
                    return IncrementResult(False, nit_total, msg, cutbacks, dz - remaining)
                sub = 0.5 * step
                continue
            self._commit(trial, step)
            remaining -= step
        return IncrementResult(True, nit_total, "converged", cutbacks, dz)
