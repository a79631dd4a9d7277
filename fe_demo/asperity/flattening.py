"""The contact fraction of a profile pressed by a rigid flat and stretched: the asperity truth.

:func:`asperity_contact_fraction` presses the strip under a profile (:mod:`.mesh`) with a rigid,
frictionless flat to the nominal pressure ``p`` (load control), then stretches it between its
symmetry sides, plane strain, to the requested in-plane bulk strains at constant ``p``, and
reports the real contact fraction ``alpha`` (contact length / apparent length) at each. Nothing
in it is fitted: it is the reference the flattening law (issue 43) is judged against.

How the contact fraction is measured (:func:`contact_fraction`): a top node inside the flat
(carrying a pressure) counts with its tributary length, half the ``x`` extent of each of its top
edges, and the sum is divided by the current apparent length ``L``. The contact edge so lies
half-way between the last node in contact and the first one out, which resolves ``alpha`` to
``1 / (2 nx)`` (the node-based contact area of FE codes); placing it by the linear gap between
those two nodes would put it at the last node in contact (its gap is the penalty's tiny
penetration) and bias ``alpha`` low by half an element on average.

The hardness ``H`` the pressures are quoted against is the slip-line value of a rigid flat punch
on a rigid-perfectly plastic half-space in plane strain (Prandtl): ``H = (2 + pi) k`` with
``k = sigma_y / sqrt(3)`` (J2), ``H = 2.97 sigma_y`` (:func:`prandtl_hardness`);
:func:`flat_punch_pressure` measures it in the model.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from sbmf_cli import ParameterError

from ..solver.element import check_kernels, kinematics
from ..solver.material import DC04, Material
from .mesh import check_profile, strip_mesh
from .model import StripModel

__all__ = [
    "AsperityMesh",
    "AsperityOptions",
    "AsperityHistory",
    "AsperityResult",
    "asperity_contact_fraction",
    "contact_fraction",
    "perfectly_plastic",
    "prandtl_hardness",
    "flat_punch_pressure",
    "PunchResult",
]


def perfectly_plastic(sigma_y=None, E=DC04.E, nu=DC04.nu):
    """An elastic-perfectly plastic J2 material (fe_demo's :class:`Material` with ``n = 0``).

    ``sigma_y`` defaults to the initial yield stress of fe_demo's DC04 (155.3 MPa); ``E`` and
    ``nu`` to DC04's (210 GPa, 0.3).
    """
    sy = DC04.sigma_y0 if sigma_y is None else float(sigma_y)
    return Material(E=E, nu=nu, K=sy, eps0=1.0, n=0.0)


def prandtl_hardness(sigma_y):
    """``H = (2 + pi) sigma_y / sqrt(3)`` (Pa): the plane-strain flat-punch pressure (Prandtl)."""
    return (2.0 + math.pi) * float(sigma_y) / math.sqrt(3.0)


@dataclass(frozen=True)
class AsperityMesh:
    """The strip's mesh.

    ``nx`` elements along the profile, ``nz`` through the thickness, the mean thickness
    ``depth`` (m; ``None``: the profile's length).
    """

    nx: int = 64
    nz: int = 24
    depth: float | None = None

    def __post_init__(self):
        if int(self.nx) < 2 or int(self.nz) < 2:
            raise ParameterError(f"nx and nz must be >= 2, got nx={self.nx}, nz={self.nz}")
        if self.depth is not None and not (math.isfinite(self.depth) and self.depth > 0):
            raise ParameterError(f"depth must be finite and > 0 (m), got {self.depth!r}")


@dataclass(frozen=True)
class AsperityOptions:
    """Increment control.

    Attributes
    ----------
    press_increments : int
        Load steps to ``p``, geometric from ``p / 100``.
    first_strain_step, max_strain_step : float
        The stretch's first and largest strain increment; between them the step grows by 1.5
        after an increment of at most 6 Newton iterations and halves after one of more than 15.
    rtol : float
        Newton tolerance (relative residual).
    kernels : {"numba", "numpy"}
    record_nodes : bool
        Keep every node's position at each increment in the history (``nodes``; a study of the
        velocity field reads them), not only the top surface's.
    """

    press_increments: int = 8
    first_strain_step: float = 5e-4
    max_strain_step: float = 0.01
    rtol: float = 1e-6
    kernels: str = "numba"
    record_nodes: bool = False

    def __post_init__(self):
        if int(self.press_increments) != self.press_increments or self.press_increments < 1:
            raise ParameterError(
                f"press_increments must be an integer >= 1, got {self.press_increments!r}"
            )
        if not (0 < self.first_strain_step <= self.max_strain_step <= 0.1):
            raise ParameterError(
                "first_strain_step and max_strain_step must satisfy 0 < first <= max <= 0.1, got "
                f"{self.first_strain_step!r}, {self.max_strain_step!r}"
            )
        if not (0 < self.rtol <= 1e-3):
            raise ParameterError(f"rtol must be in (0, 1e-3], got {self.rtol!r}")
        check_kernels(self.kernels)


@dataclass
class AsperityHistory:
    """Per accepted increment (the pressing's end first)."""

    strain: list = field(default_factory=list)  # in-plane bulk strain ln(L / L0)
    alpha: list = field(default_factory=list)  # contact fraction
    p_nominal: list = field(default_factory=list)  # sum of contact forces / L (Pa)
    lateral_stress: list = field(default_factory=list)  # side force / side height (Pa)
    nit: list = field(default_factory=list)  # Newton iterations of the increment
    top: list = field(default_factory=list)  # the top surface's nodes (x, z) (m), (n, 2) each
    tool: list = field(default_factory=list)  # the flat's height (m)
    #: every node's (x, z) (m), (n, 2) each, with ``AsperityOptions(record_nodes=True)``; the
    #: mesh's node numbering (:func:`.strip_mesh`: column by column, ``nz + 1`` nodes a column)
    nodes: list = field(default_factory=list)


@dataclass
class AsperityResult:
    """The contact fraction against bulk strain at constant nominal pressure.

    Attributes
    ----------
    p, H, sigma_y : float
        Nominal pressure, the slip-line hardness :func:`prandtl_hardness` of the material's
        initial yield stress, that yield stress (Pa).
    strains, alpha : ndarray
        The requested strains reached and the contact fraction at each (the same length; shorter
        than requested when the run stopped, then ``converged`` is False).
    alpha_press : float
        Contact fraction after pressing, before any stretch.
    converged : bool
    message : str
    volume_change : float
        ``ln(V / V0)`` of the strip at the end.
    elastic_dilatation : float
        The volume average of ``tr(sigma) / (3 K_bulk)`` at the end: what ``ln(V / V0)`` must
        equal, the plastic flow being isochoric.
    force_balance : float
        ``|sum of bottom reactions - p L| / (p L)`` at the end.
    history : AsperityHistory
    n_increments, n_newton : int
    seconds : float
        Wall time of the run.
    mesh : AsperityMesh
    """

    p: float
    H: float
    sigma_y: float
    strains: np.ndarray
    alpha: np.ndarray
    alpha_press: float
    converged: bool
    message: str
    volume_change: float
    elastic_dilatation: float
    force_balance: float
    history: AsperityHistory
    n_increments: int
    n_newton: int
    seconds: float
    mesh: AsperityMesh


def contact_fraction(model):
    """The contact fraction ``alpha`` of a :class:`StripModel`'s current state (see the module)."""
    touching = (model.x[model.top, 1] > model.w) & model.candidate
    return float(model.tributary()[touching].sum() / model.length)


def _volume_terms(model):
    kin = kinematics(model.x, model.t, model.kernels, plane_strain=True)
    v = float(kin.dV.sum())
    mean = model.sigma[..., :3].sum(-1) / 3.0
    dil = float((mean * kin.dV).sum() / v / model.mat.bulk)
    return v, dil


def _check_inputs(p, strains, material):
    p = float(p)
    if not (math.isfinite(p) and p > 0):
        raise ParameterError(f"p must be finite and > 0 (Pa), got {p!r}")
    e = np.atleast_1d(np.asarray(strains, dtype=float))
    if e.ndim != 1 or e.size < 1 or not np.isfinite(e).all():
        raise ParameterError("strains must be a non-empty 1-D array of finite bulk strains")
    if (e < 0).any() or (e > 1.0).any() or (np.diff(e) < 0).any():
        raise ParameterError("strains must be non-decreasing, in [0, 1]")
    if not isinstance(material, Material):
        raise ParameterError(f"material must be a fe_demo Material, got {type(material).__name__}")
    H = prandtl_hardness(material.sigma_y0)
    if p >= H:
        raise ParameterError(f"p must be below the hardness H = {H:.4g} Pa, got {p!r}")
    return p, e, H


class _Controller:
    """The increment size and count.

    Grown by 1.5 after an easy increment (at most 6 Newton iterations), halved after a hard one
    (more than 15, or a cut-back).
    """

    def __init__(self):
        self.n = 0

    @staticmethod
    def next(d, r, largest, smallest):
        per = r.nit / (1 + r.cutbacks)
        if r.cutbacks or per > 15:
            return max(0.5 * d, smallest)
        if per <= 6:
            return min(1.5 * d, largest)
        return d


def _press(model, p, opt, ctl):
    """Press to ``p`` under load control: ``(ok, message)``.

    Steps of ``ln(p_step)`` from ``p / 100``, the first ``opt.press_increments``-th of that
    range, then adapted.
    """
    span = math.log(100.0)
    d = span / max(int(opt.press_increments), 1)
    done = -span
    while done < 0.0:
        nxt = min(done + d, 0.0)
        if nxt > -0.2 * d:
            nxt = 0.0
        r = model.step(0.0, p=p * math.exp(nxt))
        ctl.n += 1
        if not r.converged:
            return False, f"pressing to {p * math.exp(nxt):.4g} Pa failed: {r.message}"
        done = nxt
        d = ctl.next(d, r, span / 2, span / 400)
    return True, "converged"


def asperity_contact_fraction(
    profile_x, profile_z, p, strains, material=None, mesh=None, options=None
):
    """The contact fraction of ``profile`` at nominal pressure ``p`` after each bulk strain.

    Parameters
    ----------
    profile_x, profile_z : array_like
        The profile (m): strictly increasing ``x``, heights levelled to mean zero here. Its
        ends are symmetry planes (a regular profile: peak to valley, :func:`.wedge_profile`).
    p : float
        Nominal pressure (Pa) on the current apparent length, in ``(0, H)``.
    strains : array_like
        In-plane bulk strains ``ln(L / L0)``, non-decreasing in ``[0, 1]`` (0: pressing alone).
    material : fe_demo.solver.Material, optional
        Default :func:`perfectly_plastic` (elastic-perfectly plastic, DC04's elasticity and
        initial yield).
    mesh : AsperityMesh, optional
    options : AsperityOptions, optional

    Returns
    -------
    AsperityResult
        ``converged`` False (with the reason in ``message``) when an increment could not be
        completed; ``strains`` and ``alpha`` then hold the strains reached.
    """
    t0 = time.perf_counter()
    material = perfectly_plastic() if material is None else material
    mesh = AsperityMesh() if mesh is None else mesh
    opt = AsperityOptions() if options is None else options
    p, targets, H = _check_inputs(p, strains, material)
    if not isinstance(mesh, AsperityMesh):
        raise ParameterError(f"mesh must be an AsperityMesh, got {type(mesh).__name__}")
    if not isinstance(opt, AsperityOptions):
        raise ParameterError(f"options must be an AsperityOptions, got {type(opt).__name__}")
    px, pz = check_profile(profile_x, profile_z)
    depth = float(px[-1]) if mesh.depth is None else mesh.depth
    strip = strip_mesh(px, pz, depth, mesh.nx, mesh.nz)
    model = StripModel(strip, material, rtol=opt.rtol, kernels=opt.kernels)
    v0, _ = _volume_terms(model)
    hist = AsperityHistory()

    def record(nit):
        hist.strain.append(model.bulk_strain)
        hist.alpha.append(contact_fraction(model))
        hist.p_nominal.append(float(model.force.sum()) / model.length)
        side = model.x[strip.right, 1].max()
        hist.lateral_stress.append(float(model.reactions[2 * strip.right].sum()) / side)
        hist.nit.append(nit)
        hist.top.append(model.x[strip.top].copy())
        hist.tool.append(float(model.w))
        if opt.record_nodes:
            hist.nodes.append(model.x.copy())

    ctl = _Controller()
    ok, message = _press(model, p, opt, ctl)
    record(0)
    alpha_press = hist.alpha[0]
    reached_e, reached_a = [], []
    d = opt.first_strain_step
    for target in targets:
        while ok and model.bulk_strain < target - 1e-12:
            e1 = min(model.bulk_strain + d, target)
            if e1 > target - 0.2 * d:
                e1 = target  # no sliver of a step before a target
            r = model.step(strip.length * (math.exp(e1) - 1.0), p=p)
            ctl.n += 1
            if not r.converged:
                ok = False
                message = f"stretch to strain {e1:.4g} failed: {r.message}"
                break
            record(r.nit)
            d = ctl.next(d, r, opt.max_strain_step, 0.125 * opt.first_strain_step)
        if not ok:
            break
        reached_e.append(float(target))
        reached_a.append(contact_fraction(model))
    v, dil = _volume_terms(model)
    bottom = float(model.reactions[2 * strip.bottom + 1].sum())
    load = float(model.force.sum())
    return AsperityResult(
        p=p,
        H=H,
        sigma_y=float(material.sigma_y0),
        strains=np.array(reached_e),
        alpha=np.array(reached_a),
        alpha_press=alpha_press,
        converged=ok,
        message=message,
        volume_change=math.log(v / v0),
        elastic_dilatation=dil,
        force_balance=abs(bottom - load) / load if load > 0 else 0.0,
        history=hist,
        n_increments=ctl.n,
        n_newton=model.n_newton,
        seconds=time.perf_counter() - t0,
        mesh=mesh,
    )


@dataclass
class PunchResult:
    """A rigid flat punch pressed into the flat strip (plane strain, frictionless).

    Attributes
    ----------
    depth : ndarray
        Punch displacement (m) of each increment.
    pressure : ndarray
        Mean pressure under the punch (Pa): the punch force over its half-width.
    H : float
        The slip-line value :func:`prandtl_hardness` (Pa).
    converged : bool
    message : str
    """

    depth: np.ndarray
    pressure: np.ndarray
    H: float
    converged: bool
    message: str

    @property
    def limit_pressure(self):
        """The pressure at the knee of the curve (Pa), the limit load's.

        The first step that raises it by less than 5 % of the first step's rise (beyond it the
        curve rises slowly with the geometry's change: the surface heaves beside the punch); the
        last pressure if there is no knee.
        """
        rise = np.diff(np.concatenate([[0.0], self.pressure]))
        if rise.size == 0:
            return 0.0
        knee = np.flatnonzero(rise < 0.05 * rise[0])
        return float(self.pressure[knee[0]] if knee.size else self.pressure[-1])


def flat_punch_pressure(material=None, *, nx=64, nz=24, half_width=10e-6, depth=0.04, steps=40):
    """The mean pressure of a flat punch on the strip: the model's own hardness check.

    A punch of half-width ``a = half_width`` (its edge at ``x = a``, the left side its
    symmetry plane) on a flat strip ``8 a`` wide and ``8 a`` thick, pushed ``depth a`` down in
    ``steps`` equal displacement increments. Fully plastic, the mean pressure approaches the
    slip-line value ``(2 + pi) k`` (Prandtl); ``nx`` must be a multiple of 8 (a node at the edge).
    """
    material = perfectly_plastic() if material is None else material
    a = float(half_width)
    if not (math.isfinite(a) and a > 0):
        raise ParameterError(f"half_width must be finite and > 0 (m), got {half_width!r}")
    if int(nx) % 8:
        raise ParameterError(f"nx must be a multiple of 8 (a node at the punch edge), got {nx}")
    if not (0 < depth <= 0.5):
        raise ParameterError(f"depth must be in (0, 0.5] (a fraction of half_width), got {depth!r}")
    strip = strip_mesh([0.0, 8 * a], [0.0, 0.0], 8 * a, int(nx), int(nz))
    model = StripModel(strip, material, punch_half_width=a)
    w0 = model.w
    d, pr = [], []
    message, ok = "converged", True
    for k in range(1, int(steps) + 1):
        r = model.step(0.0, w=w0 - k * depth * a / steps)
        if not r.converged:
            ok, message = False, f"punch step {k} failed: {r.message}"
            break
        d.append(w0 - model.w)
        pr.append(float(model.force.sum()) / a)
    return PunchResult(np.array(d), np.array(pr), prandtl_hardness(material.sigma_y0), ok, message)
