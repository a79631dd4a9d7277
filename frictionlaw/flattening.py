"""Flattening of the workpiece's asperities under in-plane bulk plastic strain (issue 43).

The paper's law makes the real contact fraction a function of the pressure alone. When the
workpiece flows plastically under the tool, its asperities flatten far more easily than under
pressure alone: their effective hardness drops (Wilson and Sheu 1988, whose abstract states it;
the equations of the papers could not be read here, see ``docs/flattening.md``). This module
carries that flattening as one more history variable per node, the *flattening pressure*
``p_f``: the first-loading pressure whose contact fraction equals the flattened one,
``alpha1(p_f) = A``. Every equation below is derived in ``docs/flattening.md`` ("Derivation"),
numbered F1-F6 there and in the docstrings:

* F1, kinematics: plateaus sinking at ``v_b`` into wedge flanks of slope ``tan(theta)`` grow as
  ``dA/d eps = c / tan(theta)``, ``c = v_b / (l eps_dot)`` the sinking rate per half-spacing;
* F2, two mechanisms whose rates add: the slip-line lattice of a rigid-plastic strip stretched
  at its yield, whose plateau wedges sink at no extra dissipation under any pressure,
  ``c_L = 1 + tan(theta) (1 - A)`` (no constant), and a surface layer (thickness ``beta l``)
  yielding under the asperity pressure ``p / A`` and the bulk's in-plane stress ``s`` on the
  ellipse ``(p / p_f)^2 + (s / s0)^2 = 1`` (``s0 = 2 k``, ``p_f / A`` the zero-strain asperity
  hardness read from the law's own ``alpha1``), ``c_E = (s0 / p_f) r / sqrt(1 - r^2)``,
  ``r = p / p_f``;
* F3, the rate: ``dA/d eps = beta (c_L + c_E) / tan(theta)`` (``beta`` 1 unless fitted);
* F4, its integral at constant ``p``: ``eps = tan(theta) J(p, p_f) / (beta s0 p)``, ``eps`` the
  stretch across the ridges, ``sqrt(3)/2`` of the host's equivalent plastic strain (F1b),
  ``J = int_p^p_f alpha1'(t) t sqrt(t^2 - p^2) / W dt``, ``W = 1 + c_L t sqrt(t^2 - p^2) / (s0 p)``;
* F5, the contact fraction of a node with history ``p_hist`` and flattening ``p_f``;
* F6, the update of ``p_f`` over a strain increment at the current pressure.

At zero strain ``p_f`` is never above the pressure history and F5 is the calibrated law itself;
strain rate enters only through ``s0`` (the file's ``k``, scaled by the host's flow stress when
it passes one), which sets the layer's share of the rate against the lattice's. NumPy, vectorised,
float64; F6 is written per node so that it ports to a kernel.
"""

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _codes as K
from ._flattening_block import (
    BETA_RANGE,
    FLATTENING_MODEL,
    FLATTENING_MODELS,
    FLATTENING_VERSION,
    FLOW_CURVE_STEPS,
    HARDENING_SINK,
    LIMIT_MODEL,
    P_MIN_RATIO,
    SLOPE_RANGE,
    STRETCH_PER_EQUIVALENT_STRAIN,
    Flattening,
    beta_absorbs_hardening,
)
from ._flattening_j import _j_integral, _panels, _solve_j
from ._flattening_rates import (
    contact_growth_rate,
    hardening_sinking_limit,
    host_flow_stress,
    lattice_hardening_factor,
    lattice_hardening_limit,
    lattice_sink_rate,
    layer_sink_rate,
)
from ._flattening_runs import running_max, strain_runs
from .flattening_limit import limit_curve
from .law import (
    alpha_first,
    alpha_reload,
    as_float_array,
    broadcast_named,
    evaluate,
    sbmf_coeffs,
)

if TYPE_CHECKING:
    from .flow_curve import FlowCurve
    from .params import FrictionParams

__all__ = [
    "Flattening",
    "FLATTENING_MODEL",
    "FLATTENING_MODELS",
    "LIMIT_MODEL",
    "FLATTENING_VERSION",
    "SLOPE_RANGE",
    "STRETCH_PER_EQUIVALENT_STRAIN",
    "HARDENING_SINK",
    "BETA_RANGE",
    "lattice_sink_rate",
    "lattice_hardening_limit",
    "hardening_sinking_limit",
    "layer_sink_rate",
    "contact_growth_rate",
    "equivalent_strain",
    "flattened_alpha",
    "flattening_update",
    "flattening_curve",
    "flattening_pressure",
    "flattening_data",
    "beta_absorbs_hardening",
]


def _coeffs(params: "FrictionParams") -> NDArray[np.float64]:
    return sbmf_coeffs(params, 1.0)  # tau_max = 1: the kernel's tau is alpha1


def _kinks(params: "FrictionParams", cap: float) -> NDArray[np.float64] | None:
    """The kinks of a tabulated ``alpha1``'s slope, pressures in units of ``H``.

    Its levels, the pressure where the top level's power law reaches 1 (the kernels split there
    too) and ``cap``; None for Eq. 24 (smooth).
    """
    table = params.first_loading_table
    if params.first_loading_form != "tabulated" or table is None:
        return None
    k = table.knots(params.H)
    levels = np.asarray(table.p, dtype=float)
    if k["d"][-1] > 0.0:  # alpha_top (p / p_top)^d_top = 1
        levels = np.append(levels, params.H * math.exp(k["u"][-1] - k["v"][-1] / k["d"][-1]))
    return np.append(np.sort(levels[levels < cap]), cap) / params.H


def _p_cap(params: "FrictionParams", coeffs: NDArray) -> float:
    """The pressure from which ``alpha1`` is 1 to rounding (at most ``2^40 H``): the largest ``p_f``."""
    cap = params.H
    for _ in range(40):
        if evaluate(K.CODE_SBMF, coeffs, cap, 0.0)[0] >= 1.0:
            break
        cap *= 2.0
    return cap


def _s0(params: "FrictionParams", sigma_y: ArrayLike | None, shape: tuple) -> NDArray[np.float64]:
    """The layer's in-plane flow stress ``s0 = 2 k`` (plane strain), broadcast to ``shape``.

    The host's flow stress (one value or per node) scales it when it passes one.
    """
    s0 = 2.0 * float(params.k)  # type: ignore[arg-type]
    if sigma_y is None:
        return np.full(shape, s0)
    return s0 * host_flow_stress(sigma_y, shape) / params.sigma_y


def _strain_scale(flat: Flattening, H: float, s0: NDArray[np.float64]) -> NDArray[np.float64]:
    """Eq. F4's equivalent strain per unit ``J / (p / H)``: ``tan(theta) H / (r_s beta s0)``."""
    return flat.slope * H / (flat.beta * STRETCH_PER_EQUIVALENT_STRAIN * s0)


def _hardening(hardening: ArrayLike | None, shape: tuple) -> NDArray[np.float64]:
    """The hardening modulus broadcast to ``shape`` (0 for ``None``); ``ValueError`` naming it."""
    if hardening is None:
        return np.zeros(shape)
    h = as_float_array("hardening", hardening)
    if not (np.all(np.isfinite(h)) and np.all(h >= 0)):
        raise ValueError(
            "hardening must be finite and >= 0 (Pa, d sigma_y / d eps_eq; 0: perfectly plastic)"
        )
    try:
        return np.broadcast_to(h, shape)
    except ValueError:
        raise ValueError(f"hardening has shape {h.shape}, the nodes {shape}") from None


def _flattening_of(params: "FrictionParams", one_state: bool = True) -> Flattening:
    flat = getattr(params, "flattening", None)
    if flat is None:
        raise ValueError(
            "these parameters have no flattening block (FrictionParams.flattening is None): "
            "give FrictionParams(..., flattening=Flattening(slope=...)), or calibrate with the "
            "flattening block (docs/flattening.md)"
        )
    if one_state and flat.model == LIMIT_MODEL:
        raise ValueError(
            f"the block's model {LIMIT_MODEL!r} has two states per node; this is the "
            "one-state model's: use flattening_curve or frictionlaw.flattening_limit"
        )
    return flat


def equivalent_strain(
    p: ArrayLike,
    p_f: ArrayLike,
    params: "FrictionParams",
    *,
    sigma_y: float | None = None,
    hardening: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """Equivalent plastic strain that flattens a virgin surface at constant ``p`` up to ``p_f``.

    Eq. F4: the stretch ``eps = tan(theta) J(p, p_f) / (beta s0 p)``, returned as the equivalent
    strain ``eps / r_s`` (``r_s`` = :data:`STRETCH_PER_EQUIVALENT_STRAIN`, F1b),
    ``J = int_p^p_f alpha1'(t) t sqrt(t^2 - p^2) / W dt`` (module text): 0 for ``p_f <= p``;
    grows with ``p_f``, proportional to ``1 / beta``. ``hardening`` (``d sigma_y / d eps_eq``,
    Pa, at a constant value) limits the lattice's rate (Eq. F2c), and no strain flattens
    beyond ``alpha1(p) + 3 p / (4 h tan(theta))`` (Eq. F2d: ``inf`` there).
    """
    flat = _flattening_of(params)
    p, p_f = broadcast_named(p=p, p_f=p_f)
    h = _hardening(hardening, p.shape)
    s0 = _s0(params, sigma_y, p.shape).ravel()
    if not (np.all(np.isfinite(p)) and np.all(p > 0) and np.all(np.isfinite(p_f))):
        raise ValueError("p must be finite and > 0 and p_f finite")
    H, coeffs = params.H, _coeffs(params)
    # below 1e-12 H nothing flattens (flattening_update's cutoff): no strain reaches p_f > p
    tiny = p.ravel() <= P_MIN_RATIO * H
    p = np.where(tiny.reshape(p.shape), P_MIN_RATIO * H, p)
    ph = (p / H).ravel()
    cap = _p_cap(params, coeffs)
    top = np.minimum(p_f.ravel(), cap)  # alpha1 is 1 beyond: J is complete
    u = np.arccosh(np.maximum(top / p.ravel(), 1.0))
    c_max = lattice_hardening_factor(p, h).ravel()
    kinks = _kinks(params, cap)
    vc = _switch(p.ravel(), c_max, params, cap)
    J = _j_integral(ph, u, coeffs, H, p.ravel() / s0, flat.slope, c_max, kinks=kinks, vc=vc)
    kappa = _strain_scale(flat, H, s0)
    out = kappa * J / ph
    out[tiny & (p_f.ravel() > p.ravel())] = np.inf
    out[tiny & (p_f.ravel() <= p.ravel())] = 0.0
    if hardening is not None:  # Eq. F2d: beyond the sinking a constant modulus holds, none
        a_eq = _sinking_bound(p, p, h, params)
        out[(alpha_first(top, params) > a_eq.ravel()) & (a_eq.ravel() < 1.0)] = np.inf
    return out.reshape(p.shape)


def flattened_alpha(
    p: ArrayLike, p_hist: ArrayLike, p_f: ArrayLike, params: "FrictionParams"
) -> NDArray[np.float64]:
    """Contact fraction of a node with pressure history ``p_hist`` and flattening ``p_f`` (Eq. F5).

    With ``h = max(p_hist, p_f)``: at ``p >= p_hist``, ``alpha1(max(p, p_f))``; below ``p_hist``
    the law's own reload branch of the level ``h`` at the same ratio ``p / p_hist``,
    ``alpha2(p h / p_hist; h)``. For ``p_f <= p_hist`` this is the calibrated law itself (Eqs.
    24-25, any reload form); flattening moves the level the reload shape is read at.
    """
    p, p_hist, p_f = broadcast_named(p=p, p_hist=p_hist, p_f=p_f)
    if not (np.all(np.isfinite(p)) and np.all(np.isfinite(p_hist)) and np.all(np.isfinite(p_f))):
        raise ValueError("p, p_hist and p_f must be finite (Pa)")
    if (p_hist < 0).any() or (p_f < 0).any():
        raise ValueError("p_hist and p_f must be >= 0")
    h = np.maximum(p_hist, p_f)
    out = np.zeros(p.shape)
    load = (p > 0) & (p >= p_hist)
    if load.any():
        out[load] = alpha_first(np.maximum(p[load], p_f[load]), params)
    rel = (p > 0) & (p < p_hist)
    if rel.any():
        pr, hr, phr = p[rel], h[rel], p_hist[rel]
        # p h / p_hist as (p / p_hist) h, which cannot overflow; p itself where h = p_hist, so
        # that without flattening this is today's reload branch bit for bit
        q = np.where(hr == phr, pr, (pr / phr) * hr)
        out[rel] = alpha_reload(q, hr, params)
    return out


def flattening_update(
    p_f: ArrayLike,
    p_hist: ArrayLike,
    p: ArrayLike,
    d_eps: ArrayLike,
    params: "FrictionParams",
    *,
    sigma_y: ArrayLike | None = None,
    hardening: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """The flattening pressure after a bulk plastic strain increment ``d_eps`` at pressure ``p``.

    This is Eq. F6. Per node: from ``P0 = max(p_f, p_hist, p)`` (the committed flattening, the
    increment's trial history and the pressure) the equivalent strain of Eq. F4 at the current
    ``p`` grows by ``d_eps``, ``J(p, P) = J(p, P0) + r_s d_eps beta s0 p / tan(theta)`` (F4,
    ``r_s`` = :data:`STRETCH_PER_EQUIVALENT_STRAIN`), solved for
    ``P``. The result never falls below ``p_f``; ``d_eps = 0``, ``p <= 0`` (open) and ``p``
    below ``1e-12 H`` leave ``p_f`` unchanged; it stops at the pressure where ``alpha1`` is 1.
    Like ``p_hist``, call it from the committed ``p_f`` in every iteration and commit once.

    Parameters
    ----------
    p_f, p_hist, p : array_like
        Committed flattening pressure (0 for a new node), trial history and pressure (Pa).
    d_eps : array_like
        Equivalent plastic strain increment of the bulk under the node (``>= 0``).
    sigma_y : float or array_like, optional
        The host's current flow stress (Pa, one value or per node, in ``[1e3, 1e13]``); the
        file's ``sigma_y`` by default.
    hardening : array_like, optional
        The bulk's hardening modulus ``d sigma_y / d eps_eq`` under the node (Pa, ``>= 0``):
        it limits the lattice's rate (Eq. F2c) and the flattening beyond the pressing,
        ``alpha1(p_f) <= alpha1(max(p_hist, p)) + 3 p / (4 h tan(theta))`` (Eq. F2d, never
        below the committed ``p_f``). ``None`` or 0: a perfectly plastic bulk.
    """
    flat = _flattening_of(params)
    p_f, p_hist, p, d_eps = broadcast_named(p_f=p_f, p_hist=p_hist, p=p, d_eps=d_eps)
    h = _hardening(hardening, p.shape)
    s0_all = _s0(params, sigma_y, p.shape)
    for name, a in (("p_f", p_f), ("p_hist", p_hist), ("p", p), ("d_eps", d_eps)):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name} must be finite")
    if (p_f < 0).any() or (p_hist < 0).any():
        raise ValueError("p_f and p_hist must be >= 0")
    if (d_eps < 0).any():
        raise ValueError("d_eps must be >= 0 (a plastic strain increment)")
    H, coeffs = params.H, _coeffs(params)
    cap = _p_cap(params, coeffs)
    out = np.array(p_f, dtype=float)
    go = (d_eps > 0) & (p > P_MIN_RATIO * H) & (p < cap)
    if not go.any():
        return out
    ph = p[go] / H
    p0 = np.minimum(np.maximum(np.maximum(p_f[go], p_hist[go]), p[go]), cap)
    s0 = s0_all[go]
    kappa = _strain_scale(flat, H, s0)
    c_max = lattice_hardening_factor(p[go], h[go])
    kinks = _kinks(params, cap)
    vc = _switch(p[go], c_max, params, cap)
    jx = (coeffs, H, p[go] / s0, flat.slope, c_max, kinks, vc)  # what J needs but p / H and u
    u0 = np.arccosh(np.maximum(p0 / p[go], 1.0))
    ucap = np.arccosh(cap / p[go])
    panels = _panels(float(ucap.max()), kinks is not None)
    with np.errstate(over="ignore"):  # a strain beyond any forming: full contact
        target = _j_integral(ph, u0, *jx[:5], panels, kinks, vc) + d_eps[go] * (ph / kappa)
    u = _solve_j(ph, target, u0, ucap, jx, panels)
    P = np.minimum(p[go] * np.cosh(u), cap)
    if hardening is not None:  # Eq. F2d: no further than the sinking the hardening holds
        a_eq = _sinking_bound(np.maximum(p_hist[go], p[go]), p[go], h[go], params)
        held = (a_eq < 1.0) & (alpha_first(P, params) > a_eq)
        P = np.where(held, flattening_pressure(np.where(held, a_eq, 0.0), params), P)
    out[go] = np.maximum(P, p_f[go])
    return out


def _switch(p, c_max, params, cap):
    """``v`` where Eq. F2c's limit starts to act along ``t = p cosh v`` (``inf``: nowhere).

    ``c_max (1 - A)`` falls below ``c_L = 1 + tan(theta) (1 - A)`` above ``A_c = 1 - 1 / (c_max -
    tan(theta))``; where that lies above ``alpha1(p)`` and below the cap, ``acosh(t_c / p)`` with
    ``alpha1(t_c) = A_c``: the ``J`` sum is split there (a kink), as the kernels split.
    """
    k = c_max - _flattening_of(params).slope
    out = np.full(p.shape, np.inf)
    some = np.flatnonzero(np.isfinite(k) & (k > 1.0))  # elsewhere no limit, or it acts throughout
    if some.size == 0:
        return out
    ac = 1.0 - 1.0 / k[some]
    go = some[ac > alpha_first(p[some], params)]
    if go.size:
        t = flattening_pressure(1.0 - 1.0 / k[go], params)
        out[go] = np.where(t < cap, np.arccosh(t / p[go]), np.inf)
    return out


def _sinking_bound(base, p, h, params):
    """Eq. F2d's bound on the flattened fraction: ``alpha1(base) + 3 p / (4 h tan(theta))``.

    ``inf`` where the modulus is 0.
    """
    with np.errstate(over="ignore"):  # a modulus of 1e-300: no bound (inf)
        lim = hardening_sinking_limit(p, h) / _flattening_of(params).slope
    return alpha_first(base, params) + lim


def flattening_pressure(alpha: ArrayLike, params: "FrictionParams") -> NDArray[np.float64]:
    """The flattening pressure ``p_f`` of a flattened contact fraction: ``alpha1(p_f) = alpha``.

    The runtime's state is the fraction (``HistoryState.alpha_f``, the workpiece's whatever law
    runs); Eqs. F5 and F6 read it as this pressure of the law at hand. 0 for ``alpha <= 0``;
    the pressure from which ``alpha1`` is 1 to rounding (the largest ``p_f`` of Eq. F6) where
    ``alpha`` reaches ``alpha1`` there. Bisection in ``ln p`` to 1e-15, NumPy, vectorised.
    """
    a = as_float_array("alpha", alpha)
    if not (np.all(np.isfinite(a)) and np.all(a >= 0) and np.all(a <= 1)):
        raise ValueError("alpha must be a contact fraction in [0, 1]")
    coeffs = _coeffs(params)
    cap = _p_cap(params, coeffs)
    flat = a.ravel()
    out = np.zeros(flat.size)
    top = np.asarray(evaluate(K.CODE_SBMF, coeffs, cap, 0.0)[0])
    full = flat >= top
    out[full] = cap
    go = (flat > 0) & ~full
    if go.any():
        lo = np.full(go.sum(), math.log(1e-300))
        hi = np.full(go.sum(), math.log(cap))
        target = flat[go]
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            below = np.asarray(evaluate(K.CODE_SBMF, coeffs, np.exp(mid), 0.0)[0]) < target
            lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
            if np.all(hi - lo <= 1e-15 * np.maximum(1.0, np.abs(hi))):
                break
        out[go] = np.exp(0.5 * (lo + hi))
    return out.reshape(a.shape)


def flattening_data(params: "FrictionParams") -> NDArray[np.float64]:
    """The flattening data the runtime's kernels read (layout in ``_kernels_flattening``).

    ``[tan(theta), beta, s0 = 2 k, sigma_y, p_cap, *coeffs]`` with the law's coefficients at
    ``tau_max = 1``; an empty array for a law without a ``flattening`` block.
    """
    flat = getattr(params, "flattening", None)
    if flat is None:
        return np.zeros(0)
    coeffs = _coeffs(params)
    head = [
        flat.slope,
        flat.beta,
        float(_s0(params, None, ())),
        float(params.sigma_y),
        _p_cap(params, coeffs),
    ]
    return np.concatenate([head, coeffs]).astype(np.float64)


def flattening_curve(
    p: ArrayLike,
    strains: ArrayLike,
    params: "FrictionParams",
    *,
    sigma_y: float | None = None,
    hardening: float | None = None,
    flow_curve: "FlowCurve | None" = None,
    steps: int | None = None,
) -> NDArray[np.float64]:
    """Contact fraction of a virgin surface after bulk strain ``strains`` at constant ``p``.

    Eq. F4 solved for ``p_f`` and read through Eq. F5: ``alpha1(p)`` at zero strain (the
    calibrated law exactly), never falling with strain, at most 1, reaching 1 at the finite
    equivalent strain ``tan(theta) J(p, inf) / (r_s beta s0 p)`` (with a ``hardening``
    modulus at most ``alpha1(p) + 3 p / (4 h tan(theta))``, Eq. F2d). For plots, checks and the fit
    of ``beta`` to a measured sheet. A block of the two-state model (``limit-analysis``) gives
    that law's curves (:func:`frictionlaw.flattening_limit.limit_curve`; no ``hardening``).

    Parameters
    ----------
    p : float or array_like
        Contact pressure (Pa), ``> 0``; broadcast against ``strains``.
    strains : float or array_like
        Equivalent bulk plastic strains (``>= 0``).
    params : FrictionParams
        A law with a ``flattening`` block.
    sigma_y : float, optional
        Flow stress of the bulk (Pa) if not the file's ``sigma_y``.
    hardening : float, optional
        A constant hardening modulus ``d sigma_y / d eps_eq`` of the bulk (Pa), limiting the
        lattice's rate and the sinking (Eqs. F2c, F2d); ``None``: a perfectly plastic bulk.
    flow_curve : SwiftCurve or TabulatedCurve, optional
        The bulk's flow curve (:mod:`frictionlaw.flow_curve`) from zero strain, instead of
        ``sigma_y`` and ``hardening``: each point is integrated over ``steps`` equal strain steps
        (Eq. F6 per step), each at the flow stress and modulus of its middle, as an FE host
        passes them increment by increment.
    steps : int, optional
        Strain steps per point with ``flow_curve`` (midpoint rule: the error falls as
        ``1 / steps^2``; 64 is within 1.4e-6 of 1024 on DC04's Swift curve at 0.05 and 0.3
        ``H``, strains to 0.2), in ``[1, 100000]``; ``None``: 64 (:data:`FLOW_CURVE_STEPS`).
        Given without ``flow_curve`` it is refused: there each point is solved exactly at once.
    """
    if steps is not None and (
        isinstance(steps, bool)
        or not isinstance(steps, (int, np.integer))
        or not (1 <= steps <= 100_000)
    ):
        raise ValueError(f"steps must be an integer in [1, 100000], got {steps!r}")
    if steps is not None and flow_curve is None:
        raise ValueError(
            f"steps applies with flow_curve only, got steps={steps!r} without one (at a "
            "constant flow stress and hardening each point is solved exactly in one step)"
        )
    p, eps = broadcast_named(p=p, strains=strains)
    if not (np.all(np.isfinite(p)) and np.all(p > 0)):
        raise ValueError("p must be finite and > 0 (Pa)")
    if not (np.all(np.isfinite(eps)) and np.all(eps >= 0)):
        raise ValueError("strains must be finite and >= 0")
    pf, ef = p.ravel(), eps.ravel()
    if flow_curve is not None and (sigma_y is not None or hardening is not None):
        raise ValueError("give flow_curve or sigma_y / hardening, not both (the curve gives both)")
    if flow_curve is not None and ef.size and float(ef.max()) > flow_curve.strain_max:
        raise ValueError(
            f"strains reach {float(ef.max()):.4g}, beyond the flow curve's last strain "
            f"{flow_curve.strain_max:g}: extend the table (it is not extrapolated)"
        )
    if _flattening_of(params, one_state=False).model == LIMIT_MODEL:  # the two-state law
        return limit_curve(pf, ef, params, sigma_y, hardening, flow_curve, steps).reshape(p.shape)
    if flow_curve is None:
        p_f = flattening_update(pf, pf, pf, ef, params, sigma_y=sigma_y, hardening=hardening)
    else:
        n_steps = FLOW_CURVE_STEPS if steps is None else int(steps)
        p_f = np.array(pf, dtype=float)
        de = ef / n_steps
        for j in range(n_steps):
            mid = (j + 0.5) * de
            p_f = flattening_update(
                p_f,
                pf,
                pf,
                de,
                params,
                sigma_y=flow_curve.sigma_y(mid),
                hardening=flow_curve.hardening(mid),
            )
    alpha = flattened_alpha(pf, pf, p_f, params)
    return running_max(alpha, strain_runs(pf, ef)).reshape(p.shape)
