"""Fit the law's parameters to half-space contact-ratio curves (Sec. 4).

* :func:`fit_first_loading`: ``C1, n1`` of Eq. 24's ``alpha1(p)`` from the first-loading
  curve ``alpha_rc(p_mean)``.
* :func:`fit_reload`: ``C2, n2`` of Eq. 25's ``alpha2(p)`` from all un-/reloading curves
  together (each measured at ``p < p_hist`` on the surface deformed at ``p_hist``), with
  the first loading fixed (``C1, n1`` of Eq. 24, or ``first``: the first-loading form that
  runs, whose ``alpha1(p_hist)`` scales the branch); ``continuous=True`` fits the runtime's
  continuous variant
  (``FrictionParams(continuous_reload=True)``), whose reload branch meets Eq. 24 at
  ``p_hist``: the fit constrained to have no jump.
* :func:`make_params`: the :class:`frictionlaw.FrictionParams` with the calibration's
  provenance, ready for ``to_json``.
* :func:`floor_violation`: the largest violation of the half-space model's exact bound
  ``alpha >= p / H`` by a fitted Eq. 24 (every local pressure is at most ``H``, so the real
  contact area is at least ``p_mean A0 / H``). ``fit_first_loading(..., floor_to=p_top)``
  imposes the bound on ``0 < p <= p_top``: Eq. 24 can meet it only below ``H``, since
  ``alpha1(H) = tanh(C1**n1)**(1/n1) < 1`` for every finite ``C1, n1``.

The law is evaluated by :mod:`frictionlaw` itself, so the fitted parameters mean exactly
what the runtime will compute. Both fits are bounded nonlinear least squares
(:func:`scipy.optimize.least_squares`, trust-region reflective) on ``alpha`` residuals, in
the logarithms of ``C`` and ``n`` (well scaled, and keeps them positive), started from the
best point of a coarse grid around the small-pressure slope ``C ~ alpha H / p``.
"""

import math
from dataclasses import dataclass, field

import numpy as np

from frictionlaw import FrictionParams, alpha_first, alpha_reload, reload_jump
from frictionlaw.params import C_RANGE, N_RANGE

from ...common.blas import serial_blas
from ...common.checks import positive
from .alpha_bound import bound_record, eq24_model, floor_fit, floor_violation
from .fit_data import ReloadCurve, _bounds, _curve, _data
from .law_checks import DIP_TOL
from .lsq import R2_MIN, _degenerate, _fit_c_n, _fit_fields, _r_squared, _solve, _weights

__all__ = [
    "C_BOUNDS",
    "N_BOUNDS",
    "R2_MIN",
    "FitResult",
    "FirstLoadingFit",
    "ReloadFit",
    "ReloadCurve",
    "fit_first_loading",
    "fit_reload",
    "floor_violation",
]

#: default bounds of C1, C2 (dimensionless): C > 0, far outside any measured value
C_BOUNDS = (1e-3, 1e3)
#: default bounds of n1, n2: from a very round to a sharp corner of the smooth minimum
N_BOUNDS = (0.2, 50.0)


@dataclass(frozen=True)
class FitResult:
    """Outcome of a least-squares fit of a contact-ratio law.

    Attributes
    ----------
    params : dict
        Fitted parameters by name (``C1``, ``n1`` or ``C2``, ``n2``).
    stderr : dict
        Asymptotic standard errors (from the Jacobian at the optimum and the residual
        variance); ``inf`` where the data do not determine a parameter.
    residuals : ndarray
        ``alpha_model - alpha`` at each data point (stacked over curves for reload).
    r_squared : float
        Coefficient of determination ``1 - SS_res / SS_tot`` (0 if ``alpha`` is constant).
    rmse : float
        Root mean square residual.
    success : bool
        The optimiser converged (:attr:`scipy.optimize.OptimizeResult.success`).
    message : str
        The optimiser's message, plus a note for parameters stopped at a bound.
    nfev : int
        Residual evaluations of the least-squares stage.
    at_bound : tuple of str
        Parameters that ended on a bound.
    H : float
        Hardness used (Pa).
    degenerate : str
        ``""`` when the fit is usable, else why not: a parameter ended on its bound (the data
        do not fix it), or ``R^2 < R2_MIN`` (the law explains too little of the data).
    """

    params: dict
    stderr: dict
    residuals: np.ndarray
    r_squared: float
    rmse: float
    success: bool
    message: str
    nfev: int
    at_bound: tuple
    H: float
    degenerate: str

    @property
    def converged(self):
        """The optimiser converged and the fit is not degenerate."""
        return self.success and not self.degenerate

    def summary(self):
        """JSON-ready dict of the fit quality (for the provenance)."""
        return {
            "params": dict(self.params),
            "stderr": {k: _finite_or_none(v) for k, v in self.stderr.items()},
            "r_squared": self.r_squared,
            "rmse": self.rmse,
            "max_abs_residual": float(np.max(np.abs(self.residuals))),
            "n_points": int(self.residuals.size),
            "success": self.success,
            "degenerate": self.degenerate,
            "converged": self.converged,
            "message": self.message,
            "nfev": self.nfev,
            "at_bound": list(self.at_bound),
        }


@dataclass(frozen=True)
class FirstLoadingFit(FitResult):
    """:class:`FitResult` of Eq. 24 with ``C1``, ``n1`` as attributes.

    Attributes
    ----------
    floor_to : float or None
        ``alpha1(p) >= p / H`` was imposed on ``0 < p <= floor_to`` (Pa); ``None``: not imposed.
    floor_active : bool
        The unconstrained optimum violated the bound, so the constrained one was taken.
    r_squared_unconstrained : float
        ``R^2`` of the unconstrained fit (equal to ``r_squared`` when the bound is inactive):
        the constraint's cost is the difference.
    p_max : float
        The largest pressure of the data (Pa).
    """

    floor_to: float | None = None
    floor_active: bool = False
    r_squared_unconstrained: float = math.nan
    p_max: float = math.nan

    def floor_record(self):
        """JSON-ready record of the bound ``alpha1 >= p / H`` (:func:`.alpha_bound.bound_record`)."""
        return bound_record(self)

    def summary(self):
        """JSON-ready dict of the fit quality and the bound ``alpha1 >= p / H``."""
        d = super().summary()
        d["alpha_floor"] = self.floor_record()
        return d

    @property
    def C1(self):
        """Fitted ``C1``."""
        return self.params["C1"]

    @property
    def n1(self):
        """Fitted ``n1``."""
        return self.params["n1"]


@dataclass(frozen=True)
class ReloadFit(FitResult):
    """:class:`FitResult` of Eq. 25 with the jump of the law at each ``p_hist``.

    Attributes
    ----------
    C1, n1 : float
        The first-loading parameters held fixed.
    continuous : bool
        Fitted the continuous variant (``FrictionParams.continuous_reload``).
    first : tuple or None
        ``(form, data)`` of the first-loading form whose ``alpha1(p_hist)`` scaled the branch
        (``FrictionParams.first_loading_form`` and ``first_loading_table``); ``None``: Eq. 24.
    p_hist : ndarray
        The curves' ``p_hist`` (Pa).
    jump : ndarray
        Eq. 25's jump in contact ratio at each ``p_hist``,
        ``alpha1(p_hist) - alpha2(p_hist)`` (``tau`` jumps by ``m k`` times this).
    """

    C1: float = math.nan
    n1: float = math.nan
    continuous: bool = False
    p_hist: np.ndarray = field(default_factory=lambda: np.zeros(0))
    jump: np.ndarray = field(default_factory=lambda: np.zeros(0))
    first: tuple | None = None
    dip_constrained: bool = False

    @property
    def C2(self):
        """Fitted ``C2``."""
        return self.params["C2"]

    @property
    def n2(self):
        """Fitted ``n2``."""
        return self.params["n2"]

    @property
    def jump_relative(self):
        """Jump relative to ``alpha1(p_hist)`` (the shear's relative drop at ``p_hist``)."""
        a1 = alpha_first(self.p_hist, _law(self.H, self.C1, self.n1, first=self.first))
        return self.jump / a1

    def summary(self):
        """JSON-ready dict of the fit quality and the jumps."""
        d = super().summary()
        d["continuous"] = self.continuous
        d["dip_constrained"] = self.dip_constrained
        d["jump"] = [
            {"p_hist": float(ph), "jump_alpha": float(j), "jump_relative": float(r)}
            for ph, j, r in zip(self.p_hist, self.jump, self.jump_relative, strict=True)
        ]
        return d


# -- validation (the checks live in .fit_data) ------------------------------------------


def _finite_or_none(v):
    return float(v) if math.isfinite(v) else None


# -- model --------------------------------------------------------------------------------


def _law(H, C1, n1, C2=1.0, n2=1.0, continuous=False, first=None):
    """A FrictionParams for evaluating alpha (``m``, ``sigma_y``, ``k`` do not enter alpha).

    ``first``: ``(form, data)`` of the first-loading form that runs (``None``: Eq. 24).
    """
    kw = {} if first is None else {"first_loading_form": first[0], "first_loading_table": first[1]}
    return FrictionParams(
        m=1.0, sigma_y=H, H=H, C1=C1, n1=n1, C2=C2, n2=n2, continuous_reload=continuous, **kw
    )


@serial_blas
def fit_first_loading(
    p,
    alpha,
    H,
    *,
    relative=False,
    C_bounds=C_BOUNDS,
    n_bounds=N_BOUNDS,
    floor_to=None,
):
    """Fit ``C1, n1`` of the first-loading ratio ``alpha1(p) = tanh((p C1 / H)**n1)**(1/n1)``.

    This is Eq. 24.

    Parameters
    ----------
    p : array_like
        Mean contact pressures ``p_mean`` of the first-loading sweep (Pa), ``> 0``.
    alpha : array_like
        Contact ratios ``alpha_rc = A_real / A0`` at ``p``, in ``[0, 1]``.
    H : float
        Hardness (Pa) used in the half-space model.
    relative : bool
        Minimise relative residuals ``(alpha_model - alpha) / alpha`` (for scatter
        proportional to ``alpha``; needs ``alpha > 0``) instead of absolute ones.
    C_bounds, n_bounds : (float, float)
        Bounds of ``C1`` and ``n1``.
    floor_to : float, optional
        Impose the half-space model's bound ``alpha1(p) >= p / H`` on ``0 < p <= floor_to``
        (Pa, at most ``H``; at ``H`` itself Eq. 24 cannot reach 1, so a value below ``H``,
        e.g. the data's largest pressure). If the unconstrained optimum already satisfies it,
        that optimum is returned; else the constrained one (SLSQP), with
        ``r_squared_unconstrained`` recording the cost.

    Returns
    -------
    FirstLoadingFit
        ``C1``, ``n1``, standard errors, residuals, ``r_squared``, ``success``, ``message``.

    Raises
    ------
    ValueError
        For mismatched lengths, fewer than 3 points, NaN, ``p <= 0``, ``alpha`` outside
        ``[0, 1]`` or bad bounds (the message names the argument).
    """
    p, alpha = _data(p, alpha)
    H = positive("H", H)
    cb, nb = _bounds("C_bounds", C_bounds, C_RANGE), _bounds("n_bounds", n_bounds, N_RANGE)
    if p.size < 3:
        raise ValueError(f"p needs at least 3 points to fit C1 and n1, got {p.size}")
    w = _weights(alpha, relative)

    if floor_to is not None:
        floor_to = positive("floor_to", floor_to)
        if floor_to > H:
            raise ValueError(f"floor_to must be <= H = {H:g} Pa, got {floor_to:g}")

    model = eq24_model(p, H)
    fit = _fit_c_n(model, p, alpha, w, H, cb, nb, ("C1", "n1"))
    r2u = fit["r_squared"]
    p_max = float(p.max())
    if floor_to is None:
        return FirstLoadingFit(**fit, r_squared_unconstrained=r2u, p_max=p_max)
    c1, n1 = fit["params"]["C1"], fit["params"]["n1"]
    if floor_violation(c1, n1, H, floor_to)[0] <= 1e-12:
        return FirstLoadingFit(**fit, floor_to=floor_to, r_squared_unconstrained=r2u, p_max=p_max)

    def residual(x):
        return (model(*np.exp(x)) - alpha) * w

    lb, ub = np.array([cb[0], nb[0]]), np.array([cb[1], nb[1]])
    x0 = np.clip(np.log([c1, n1]), np.log(lb) + 1e-9, np.log(ub) - 1e-9)
    params, stderr, ok, msg, nfev = floor_fit(residual, H, floor_to, x0, lb, ub, ("C1", "n1"))
    res = model(params["C1"], params["n1"]) - alpha
    r2 = _r_squared(res, alpha)
    at = tuple(
        nm
        for i, nm in enumerate(("C1", "n1"))
        if np.isclose(params[nm], (lb[i], ub[i]), rtol=1e-6).any()
    )
    fit.update(
        params=params,
        stderr=stderr,
        residuals=res,
        r_squared=r2,
        rmse=float(np.sqrt(np.mean(res**2))),
        success=ok,
        message=msg,
        nfev=fit["nfev"] + nfev,
        at_bound=at,
        degenerate=_degenerate(params, at, lb, ub, r2, alpha),
    )
    return FirstLoadingFit(
        **fit, floor_to=floor_to, floor_active=True, r_squared_unconstrained=r2u, p_max=p_max
    )


@serial_blas
def fit_reload(
    curves,
    H,
    C1,
    n1,
    *,
    continuous=False,
    relative=False,
    C_bounds=C_BOUNDS,
    n_bounds=N_BOUNDS,
    first=None,
    dip_range=None,
):
    """Fit ``C2, n2`` of the reload contact ratio to all un-/reloading curves together.

    This is Eq. 25.

    ``alpha2(p) = alpha1(p_hist) tanh(x2**n2)**(1/n2)``, ``x2 = p C2 / (H alpha1(p_hist))``,
    with ``alpha1`` from Eq. 24 and the given ``C1, n1`` (as the runtime evaluates it).

    Parameters
    ----------
    curves : sequence
        Each a :class:`ReloadCurve`, a dict with ``p_hist``, ``p``, ``alpha``, or a tuple
        ``(p_hist, p, alpha)``: contact ratios at pressures ``0 < p < p_hist`` (Pa) on the
        surface deformed by loading to ``p_hist``.
    H : float
        Hardness (Pa).
    C1, n1 : float
        First-loading parameters (from :func:`fit_first_loading`).
    first : tuple, optional
        ``(form, data)`` of the first-loading form that runs (``FrictionParams``'s
        ``first_loading_form``, ``first_loading_table``): its ``alpha1(p_hist)`` scales the
        branch. ``None``: Eq. 24 with ``C1, n1``.
    continuous : bool
        Fit the continuous variant (``FrictionParams(continuous_reload=True)``): Eq. 25
        normalised to meet Eq. 24 at ``p_hist``, i.e. the fit constrained to zero jump.
    relative : bool
        Minimise relative residuals (see :func:`fit_first_loading`).
    C_bounds, n_bounds : (float, float)
        Bounds of ``C2`` and ``n2``.
    dip_range : (float, float), optional
        ``(p_min, p_max)`` (Pa) of the histories on which no reload curve of the law may lie
        below the first loading by more than :data:`~.law_checks.DIP_TOL` in ``alpha``: if the
        fit's curves do (checked on 24 histories x 19 pressures), it is refitted with that as a
        penalty (``dip_constrained``); ``None``: not checked.

    Returns
    -------
    ReloadFit
        ``C2``, ``n2``, residuals (curves stacked in order), ``r_squared``, ``success``,
        ``message`` and ``jump``, Eq. 25's drop of ``alpha`` at each ``p_hist``.
    """
    if isinstance(curves, (ReloadCurve, dict)) or not hasattr(curves, "__len__"):
        raise ValueError("curves must be a sequence of reload curves")
    if len(curves) == 0:
        raise ValueError("curves must hold at least one reload curve")
    cs = [_curve(i, c) for i, c in enumerate(curves)]
    H = positive("H", H)
    C1, n1 = positive("C1", C1), positive("n1", n1)
    cb, nb = _bounds("C_bounds", C_bounds, C_RANGE), _bounds("n_bounds", n_bounds, N_RANGE)
    p = np.concatenate([c.p for c in cs])
    ph = np.concatenate([np.full(c.p.size, c.p_hist) for c in cs])
    alpha = np.concatenate([c.alpha for c in cs])
    if p.size < 3:
        raise ValueError(f"curves need at least 3 points in all to fit C2 and n2, got {p.size}")
    cont = bool(continuous)
    w = _weights(alpha, relative)

    def model(c, n):
        return alpha_reload(p, ph, _law(H, C1, n1, c, n, cont, first))

    fit = _fit_c_n(model, p, alpha, w, H, cb, nb, ("C2", "n2"))
    dip = None
    if dip_range is not None:
        dip = _Dip(H, C1, n1, cont, first, dip_range)
        if dip.worst(**fit["params"]) > DIP_TOL:
            fit = _fit_no_dip(fit, model, alpha, w, cb, nb, dip)
    params = fit["params"]
    p_hist = np.array([c.p_hist for c in cs])
    law = _law(H, C1, n1, params["C2"], params["n2"], cont, first)
    jump = np.atleast_1d(reload_jump(law, p_hist)) / law.tau_max  # the jump in alpha
    return ReloadFit(
        **fit,
        C1=C1,
        n1=n1,
        continuous=cont,
        p_hist=p_hist,
        jump=jump,
        first=first,
        dip_constrained=dip is not None and dip.used,
    )


#: the penalty starts at this fraction of DIP_TOL (the dense grid of the law's checks lies between
#: the fit's grid points)
_DIP_MARGIN = 0.25


class _Dip:
    """How far the reload curves of Eq. 25 lie below the first loading, on a grid of histories."""

    def __init__(self, H, C1, n1, cont, first, dip_range):
        ph = np.geomspace(*dip_range, 24)
        q = np.concatenate(
            [np.geomspace(1e-3, 0.02, 5, endpoint=False), np.linspace(0.02, 0.99, 14)]
        )
        self.PH = np.repeat(ph, q.size)
        self.P = self.PH * np.tile(q, ph.size)
        self.a1 = alpha_first(self.P, _law(H, C1, n1, first=first))
        self.law = lambda c, n: _law(H, C1, n1, c, n, cont, first)
        self.used = False

    def below(self, C2, n2):
        """``alpha1 - alpha2`` at every grid point."""
        return self.a1 - alpha_reload(self.P, self.PH, self.law(C2, n2))

    def worst(self, C2, n2):
        return float(np.max(self.below(C2, n2)))


def _fit_no_dip(fit, model, alpha, w, cb, nb, dip):
    """The fit again with the reload curves' dip below first loading as a penalty.

    Residuals ``10 max(0, alpha1 - alpha2 - DIP_TOL / 4)`` on the grid are appended to the
    data's, from the unconstrained optimum; the data's residuals and R^2 are reported.
    """
    dip.used = True

    def residual(x):
        c, n = np.exp(x)
        pen = 10.0 * np.maximum(dip.below(c, n) - _DIP_MARGIN * DIP_TOL, 0.0)
        return np.concatenate([(model(c, n) - alpha) * w, pen])

    lb, ub = np.array([cb[0], nb[0]]), np.array([cb[1], nb[1]])
    start = np.array([fit["params"]["C2"], fit["params"]["n2"]])
    names = ("C2", "n2")
    out = _fit_fields(model, alpha, fit["H"], lb, ub, names, _solve(residual, start, lb, ub, names))
    worst = dip.worst(out["params"]["C2"], out["params"]["n2"])
    out["message"] += (
        f" Constrained: its reload curves below first loading by at most {worst:.3g} in alpha "
        f"(unconstrained: R^2 {fit['r_squared']:.4g})."
    )
    out["nfev"] += fit["nfev"]
    return out
