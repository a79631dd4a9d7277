"""The two records every solve, sweep and study shares: the bodies' materials and the solver settings.

:class:`Materials` holds what the paper's Table 1 gives for the two bodies (elastic constants,
hardness, yield stress) and the interface's Tresca factor ``m``; :class:`SolverSettings` holds the
normal solver's knobs. :func:`sigma_y_from_hardness` is the one place of Bowden and Tabor's
``H = 2.8 sigma_y``.
"""

from dataclasses import dataclass

from ..common.checks import positive, tolerance, tresca_factor
from .cerruti import E_prime
from .influence import boundary_of
from .normal import composite_modulus

__all__ = [
    "BOWDEN_TABOR",
    "Materials",
    "SolverSettings",
    "records",
    "sigma_y_from_hardness",
]

#: Bowden and Tabor's ratio of indentation hardness to yield stress, ``H = 2.8 sigma_y``
BOWDEN_TABOR = 2.8


def sigma_y_from_hardness(H):
    """Yield stress of the softer body from its hardness: ``sigma_y = H / 2.8`` (Bowden and Tabor).

    The paper gives ``H``; the law needs ``sigma_y`` (through ``k = sigma_y / 2``). This is the
    default wherever ``sigma_y`` is not given.

    Parameters
    ----------
    H : float
        Hardness in Pa, finite and > 0.

    Returns
    -------
    float
        ``sigma_y`` in Pa.
    """
    return positive("H", H, "Pa") / BOWDEN_TABOR


@dataclass(frozen=True)
class Materials:
    """Elastic constants of both bodies, hardness and yield stress of the softer one, Tresca ``m``.

    Defaults: the paper's Table 1 (DC04 workpiece and hardened tool, 210 GPa, 0.3, H = 800 MPa),
    ``sigma_y = H / 2.8`` (:func:`sigma_y_from_hardness`) and ``m = 0.5``. Validated on
    construction; change a field with :func:`dataclasses.replace`.
    """

    E_workpiece: float = 210e9
    nu_workpiece: float = 0.3
    E_tool: float = 210e9
    nu_tool: float = 0.3
    H: float = 800e6
    sigma_y: float | None = None
    m: float = 0.5

    def __post_init__(self):
        for name in ("E_workpiece", "E_tool", "H"):
            positive(name, getattr(self, name), "Pa")
        if self.sigma_y is None:
            object.__setattr__(self, "sigma_y", sigma_y_from_hardness(self.H))
        positive("sigma_y", self.sigma_y, "Pa")
        for name in ("nu_workpiece", "nu_tool"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and -1.0 < v <= 0.5):
                raise ValueError(f"{name} must be in (-1, 0.5], got {v!r}")
        tresca_factor(self.m)

    @property
    def E_star(self):
        """Composite modulus of the two bodies, Eq. 2 (Pa)."""
        return composite_modulus(self.E_workpiece, self.nu_workpiece, self.E_tool, self.nu_tool)

    @property
    def E_prime(self):
        """Composite modulus of the tangential problem, Eq. 17 (Pa)."""
        return E_prime(self.E_workpiece, self.nu_workpiece, self.E_tool, self.nu_tool)


@dataclass(frozen=True)
class SolverSettings:
    """Settings of the normal solver shared by every sweep and study.

    ``tol``: relative residual in ``(0, 1)``; ``boundary``: the patch as one period of a
    periodic surface (``"periodic"``, spectral operator), as one quarter of the period of its
    mirror-symmetric extension (``"mirror"``) or as an isolated body (``"isolated"``, DC-FFT);
    ``periodic``: the older switch (True: ``"periodic"``, False: ``"isolated"``; both ``None``:
    ``"periodic"``), resolved on construction so that ``periodic`` says whether the patch's
    opposite edges are joined; ``volume_conservation``: lift the plastically removed volume
    into the valleys; ``maxiter``: iteration limit (``None``: the solver's own default).
    """

    tol: float = 1e-8
    periodic: bool | None = None
    volume_conservation: bool = True
    maxiter: int | None = None
    boundary: str | None = None

    def __post_init__(self):
        tolerance(self.tol)
        b = boundary_of(self.periodic, self.boundary)
        object.__setattr__(self, "boundary", b)
        object.__setattr__(self, "periodic", b == "periodic")
        if not isinstance(self.volume_conservation, bool):
            raise ValueError(
                f"volume_conservation must be True or False, got {self.volume_conservation!r}"
            )
        mi = self.maxiter
        if mi is not None and (isinstance(mi, bool) or not isinstance(mi, int) or mi < 1):
            raise ValueError(f"maxiter must be an integer >= 1 or None, got {mi!r}")

    def normal_kwargs(self):
        """Keyword arguments of :func:`~halfspace_calib.contact.normal.solve_normal`."""
        kw = {"tol": self.tol, "boundary": self.boundary}
        if self.maxiter is not None:
            kw["maxiter"] = self.maxiter
        return kw


def records(materials=None, solver=None):
    """``(materials, solver)`` with the defaults filled in; ``ValueError`` for anything else.

    ``None`` means the paper's Table 1 (:class:`Materials`) and the default
    :class:`SolverSettings`; every sweep and study takes its inputs through this.
    """
    materials = Materials() if materials is None else materials
    solver = SolverSettings() if solver is None else solver
    if not isinstance(materials, Materials):
        raise ValueError(f"materials must be a Materials record, got {type(materials).__name__}")
    if not isinstance(solver, SolverSettings):
        raise ValueError(f"solver must be a SolverSettings record, got {type(solver).__name__}")
    return materials, solver
