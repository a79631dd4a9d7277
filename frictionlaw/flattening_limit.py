"""The two-state flattening law, model ``limit-analysis`` of the ``flattening`` block (issue 43).

The default model (``layer-yield``, :mod:`frictionlaw.flattening`) grows a node's contact
fraction at a rate of the fraction alone. This model carries a second state per node, its
asperities' current flank slope ``s``, and takes both rates from the rigid-perfectly plastic
optimum of the wedge cell stretched across its ridges, computed once by the project's limit
analysis and shipped as a table over ``p / H_P`` (``H_P = (2 + pi) k``, the bulk's Prandtl
hardness; 0.02-0.6), ``A`` and ``s`` (0.01-0.2): at low pressure the optimum turns a steep
flank before it grows the contact, which no rate of the fraction alone can do. Against the
project's FE asperity truth, nothing fitted, it misses by at most 0.134 at 0.05-0.6 ``H`` and
0.138 at 0.02 ``H`` where the default model misses by 0.264 and 0.643, but a hardening sheet
(DC04) by 0.648 at 0.05-0.45 ``H`` and 0.837 at 0.02 ``H`` where the default with the hardening
modulus misses by 0.195 and 0.105 (docs/flattening.md, "The two-state model" and "Below the
table").

* a node starts from ``A0 = max(alpha_f, alpha1(max(p, p_hist)))`` (as Eq. F6 starts from the
  largest of ``p_f``, ``p_hist`` and ``p``) and the block's ``slope`` (a state of 0: never
  flattened);
* with the block's ``edge_slope`` (the workpiece's edge slope ``E(A)``, from its surface) the
  flank slope is ``r E(A)``: the node's turn ``r = slope_f / E(alpha_f)`` (1 never flattened)
  is what the table's ``d ln s / d eps`` turns, and the slope follows the surface's own edges
  as the contact grows (docs/flattening.md, "The edge slope");
* the stretch across the ridges is ``beta r_s d_eps`` (``r_s = sqrt(3) / 2`` of the host's
  equivalent plastic strain, Eq. F1b; ``beta`` scales it, 1 unless fitted);
* ``(A, s)`` follow the table's rates at the current ``p`` (``frictionlaw._limit_table``); the
  contact fraction is then read through Eq. F5 (:func:`frictionlaw.flattening.flattened_alpha`),
  so that at zero strain the law is exactly the calibrated one.

The table is perfectly plastic: a hardening modulus is refused (the default model's F2c has no
counterpart here: tried on this model's rate it lowers the miss on the hardening truth only to
0.572), and a hardening flow stress enters only through ``H_P``.
NumPy, vectorised, float64; the kernels of ``_kernels_limit.py`` follow it node by node.
"""

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._flattening_block import (
    FLOW_CURVE_STEPS,
    LIMIT_MODEL,
    LIMIT_SLOPE_RANGE,
    P_MIN_RATIO,
    STRETCH_PER_EQUIVALENT_STRAIN,
    Flattening,
)
from ._flattening_rates import host_flow_stress
from ._flattening_runs import running_max, strain_runs
from ._limit_table import (
    PRANDTL_FACTOR,
    edge_at,
    integrate,
    integrate_shared,
    rate_table,
    table_rates,
)
from .law import alpha_first, as_float_array, broadcast_named

if TYPE_CHECKING:
    from .flow_curve import FlowCurve
    from .params import FrictionParams

__all__ = [
    "LIMIT_MODEL",
    "LIMIT_SLOPE_RANGE",
    "limit_rates",
    "limit_update",
    "edge_slope_at",
    "prandtl_ratio",
    "table_pressures",
]


def _limit_block(params: "FrictionParams") -> Flattening:
    flat = getattr(params, "flattening", None)
    if flat is None or flat.model != LIMIT_MODEL:
        have = "no flattening block" if flat is None else f"model {flat.model!r}"
        raise ValueError(
            f"these parameters have {have}; the two-state law needs a flattening block of model "
            f"{LIMIT_MODEL!r} (Flattening(slope=..., model={LIMIT_MODEL!r}))"
        )
    return flat


def _prandtl_hardness(
    params: "FrictionParams", sigma_y: ArrayLike | None, shape: tuple
) -> float | NDArray[np.float64]:
    """``H_P = (2 + pi) k``, the bulk's Prandtl hardness.

    ``k`` is the file's, scaled by ``sigma_y / params.sigma_y`` (broadcast to ``shape``) when a
    flow stress is given.
    """
    k: float | NDArray[np.float64] = float(params.k)  # type: ignore[arg-type]
    if sigma_y is not None:
        k = k * (host_flow_stress(sigma_y, shape) / params.sigma_y)
    return PRANDTL_FACTOR * k


def prandtl_ratio(
    p: ArrayLike, params: "FrictionParams", sigma_y: ArrayLike | None = None
) -> NDArray[np.float64]:
    """``p / H_P``, ``H_P = (2 + pi) k`` the bulk's Prandtl hardness: the table's pressure.

    ``k`` is the file's, scaled by ``sigma_y / params.sigma_y`` when the host passes its flow
    stress (Pa, in ``[1e3, 1e13]``, one value or per node).
    """
    p = as_float_array("p", p)
    return p / _prandtl_hardness(params, sigma_y, p.shape)


def table_pressures(
    params: "FrictionParams", sigma_y: ArrayLike | None = None
) -> tuple[float | NDArray[np.float64], float | NDArray[np.float64]]:
    """The contact pressures (Pa) the rate table covers for ``params``: ``(p_lo, p_hi)``.

    The table's lowest and highest ``p / H_P`` (0.02 and 0.6) times ``H_P = (2 + pi) k``, ``k``
    the file's, scaled by ``sigma_y / params.sigma_y`` for a flow stress ``sigma_y`` (Pa, one
    value or per node: then per node). Below ``p_lo`` the law reads the rates at ``p_lo`` (the
    optimum slows further at lower pressure on steep flanks: an upper bound of the flattening
    there), above ``p_hi`` those at ``p_hi``.
    """
    lo, hi = (float(v) for v in rate_table().pressures[[0, -1]])
    hp = _prandtl_hardness(params, sigma_y, () if sigma_y is None else np.shape(sigma_y))
    return lo * hp, hi * hp


def _edge(flat: Flattening) -> NDArray[np.float64] | None:
    return None if flat.edge_slope is None else np.asarray(flat.edge_slope, dtype=float)


def edge_slope_at(A: ArrayLike, params: "FrictionParams") -> NDArray[np.float64]:
    """The block's flank slope of a virgin surface at contact fraction ``A`` (in [0, 1]).

    Its ``edge_slope`` table read linearly between its equally spaced fractions, or its one
    ``slope`` where it has none.
    """
    flat = _limit_block(params)
    a = as_float_array("A", A)
    if not (np.all(np.isfinite(a)) and np.all((a >= 0) & (a <= 1))):
        raise ValueError("A must be a contact fraction in [0, 1]")
    e = _edge(flat)
    if e is None:
        return np.full(a.shape, flat.slope)
    return np.asarray(edge_at(e, a), dtype=float)


def limit_rates(
    p_over_HP: ArrayLike, A: ArrayLike, s: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The table's ``(dA / d eps, ds / d eps)`` per unit stretch across the ridges.

    At ``p / H_P`` (linear in ``ln p`` between the tabulated pressures 0.02-0.6, clamped
    beyond), contact fraction ``A`` and flank slope ``s`` (bilinear in ``A`` and ``ln s``,
    clamped to the grid); ``dA / d eps`` held at ``>= 0``.
    """
    x, a, s = broadcast_named(p_over_HP=p_over_HP, A=A, s=s)
    if not (np.all(np.isfinite(x)) and np.all(x > 0)):
        raise ValueError("p_over_HP must be finite and > 0")
    if not (np.all(np.isfinite(a)) and np.all((a >= 0) & (a <= 1))):
        raise ValueError("A must be a contact fraction in [0, 1]")
    if not (np.all(np.isfinite(s)) and np.all(s > 0)):
        raise ValueError("s must be a flank slope, finite and > 0")
    return table_rates(x, a, s, rate_table())


def limit_update(
    alpha_f: ArrayLike,
    slope_f: ArrayLike,
    p_hist: ArrayLike,
    p: ArrayLike,
    d_eps: ArrayLike,
    params: "FrictionParams",
    *,
    sigma_y: ArrayLike | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Both states after a bulk plastic strain increment ``d_eps`` at pressure ``p``.

    The two-state counterpart of Eq. F6 (module text): from the committed fraction ``alpha_f``
    and slope ``slope_f`` (0: never flattened, the block's ``slope``), the trial history
    ``p_hist`` and the pressure ``p`` (Pa), ``d_eps`` the equivalent plastic strain increment of
    the bulk under the node (``>= 0``). With the block's ``edge_slope`` the node's turn is
    ``slope_f / E(alpha_f)`` (1 never flattened) and its slope ``r E(A)`` at the end.
    Returns ``(alpha_f', slope_f')``: the fraction never
    below ``alpha_f``, at most 1; ``d_eps = 0``, ``p <= 1e-12 H`` (open) and full contact
    leave both as they are. Like ``p_hist``, call it from the committed states in every
    iteration and commit once.
    """
    flat = _limit_block(params)
    alpha_f, slope_f, p_hist, p, d_eps = broadcast_named(
        alpha_f=alpha_f, slope_f=slope_f, p_hist=p_hist, p=p, d_eps=d_eps
    )
    for name, a in (("p_hist", p_hist), ("p", p), ("d_eps", d_eps), ("slope_f", slope_f)):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name} must be finite")
    if not np.all((alpha_f >= 0) & (alpha_f <= 1)):
        raise ValueError("alpha_f must be contact fractions in [0, 1]")
    if (p_hist < 0).any() or (slope_f < 0).any():
        raise ValueError("p_hist and slope_f must be >= 0 (slope_f 0: never flattened)")
    if (d_eps < 0).any():
        raise ValueError("d_eps must be >= 0 (a plastic strain increment)")
    x_all = prandtl_ratio(p, params, sigma_y)
    a_out, s_out = np.array(alpha_f, dtype=float), np.array(slope_f, dtype=float)
    go = (d_eps > 0) & (p > P_MIN_RATIO * params.H) & (alpha_f < 1.0)
    if not go.any():
        return a_out, s_out
    a0 = np.maximum(alpha_f[go], alpha_first(np.maximum(p[go], p_hist[go]), params))
    e = _edge(flat)
    if e is None:
        s0 = np.where(slope_f[go] > 0, slope_f[go], flat.slope)
    else:  # the flank's turn r = s / E(A) at the committed fraction
        s0 = np.where(slope_f[go] > 0, slope_f[go] / edge_at(e, alpha_f[go]), 1.0)
    stretch = STRETCH_PER_EQUIVALENT_STRAIN * flat.beta * d_eps[go]
    a, s = integrate(a0, s0, x_all[go], stretch, rate_table(), e)
    a_out[go] = np.maximum(a, alpha_f[go])
    s_out[go] = s
    return a_out, s_out


def limit_curve(
    p: NDArray[np.float64],
    strains: NDArray[np.float64],
    params: "FrictionParams",
    sigma_y: float | None = None,
    hardening: float | None = None,
    flow_curve: "FlowCurve | None" = None,
    steps: int | None = None,
) -> NDArray[np.float64]:
    """The two-state law's contact fraction of a virgin surface after ``strains`` at ``p``.

    Flat arrays, checked by :func:`frictionlaw.flattening.flattening_curve` (which also refuses
    ``flow_curve`` beside ``sigma_y``), which calls it for this model: ``alpha1(p)`` at zero strain, never falling, at most 1 (Eq. F5 at
    ``p = p_hist``: the larger of ``alpha1(p)`` and the state ``A``). With a ``flow_curve`` the
    table's pressure ``p / H_P`` follows the curve's flow stress over ``steps`` equal strain
    steps per point (``FLOW_CURVE_STEPS`` by default; each at its middle's). ``hardening`` is refused: the table
    is perfectly plastic.
    """
    if hardening is not None:
        raise ValueError(
            f"hardening does not apply to model {LIMIT_MODEL!r}: its table is perfectly plastic "
            "(give the sheet's flow_curve for its flow stress; docs/flattening.md)"
        )
    steps = FLOW_CURVE_STEPS if steps is None else int(steps)
    flat = _limit_block(params)
    a0 = np.asarray(alpha_first(p, params), dtype=float)
    e = _edge(flat)
    s0 = np.full(p.shape, flat.slope if e is None else 1.0)  # with a table: the turn r
    go = p > P_MIN_RATIO * params.H
    a, s = a0.copy(), s0
    if flow_curve is None:  # the points of a pressure share their start: one integration each
        a[go], _ = integrate_shared(
            a0[go],
            s0[go],
            prandtl_ratio(p[go], params, sigma_y),
            STRETCH_PER_EQUIVALENT_STRAIN * flat.beta * strains[go],
            rate_table(),
            e,
        )
    else:
        de = strains / steps
        for j in range(steps):
            x = prandtl_ratio(p, params, flow_curve.sigma_y((j + 0.5) * de))
            a[go], s[go] = integrate(
                a[go],
                s[go],
                x[go],
                STRETCH_PER_EQUIVALENT_STRAIN * flat.beta * de[go],
                rate_table(),
                e,
            )
            if e is not None:  # the next step starts from the turn, not the slope
                s[go] = s[go] / edge_at(e, a[go])
    # Eq. F5 at p = p_hist reads alpha1(max(p, p_f)) = max(alpha1(p), A): the state itself
    return running_max(np.maximum(a, a0), strain_runs(p, strains))
