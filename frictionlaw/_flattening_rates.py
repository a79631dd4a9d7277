"""The flattening's sinking rates and bound (Eqs. F2a-F2d) and the growth rate (Eq. F3).

Private: :mod:`frictionlaw.flattening` is their public home (docs/flattening.md). Each checks
its domain and names the argument. The host's flow stress, which scales the flow stress of
both models' rates, is checked here once (:func:`host_flow_stress`).
"""

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._flattening_block import HARDENING_SINK, STRETCH_PER_EQUIVALENT_STRAIN, _number
from .law import as_float_array, broadcast_named

__all__ = [
    "host_flow_stress",
    "layer_sink_rate",
    "lattice_sink_rate",
    "lattice_hardening_limit",
    "lattice_hardening_factor",
    "limit_at",
    "hardening_sinking_limit",
    "contact_growth_rate",
]


def host_flow_stress(sigma_y: ArrayLike, shape: tuple) -> NDArray[np.float64]:
    """The host's flow stress broadcast to ``shape``.

    Pa, one value or per node, in ``[1e3, 1e13]``; ``ValueError`` naming ``sigma_y`` otherwise.
    """
    if np.ndim(sigma_y) == 0:
        sy = np.asarray(_number("sigma_y", sigma_y, 1e3, 1e13))
    else:
        sy = as_float_array("sigma_y", sigma_y)
        if not (np.all(np.isfinite(sy)) and np.all((sy >= 1e3) & (sy <= 1e13))):
            raise ValueError("sigma_y must be in [1000, 1e+13] (Pa) at every node")
    try:
        return np.broadcast_to(sy, shape)
    except ValueError:
        raise ValueError(f"sigma_y has shape {np.shape(sy)}, the nodes {shape}") from None


def layer_sink_rate(r: ArrayLike, s0_over_pf: ArrayLike) -> NDArray[np.float64]:
    """Sinking rate of the plateaus per half-spacing and strain in the yielding layer (Eq. F2).

    ``c_E = v_b / (l eps_dot)`` of the layer (docs/flattening.md): normality on the layer's
    yield ellipse ``(p / p_f)^2 + (s / s0)^2 = 1`` gives ``(s0 / p_f) r / sqrt(1 - r^2)`` with ``r = p / p_f``
    in ``[0, 1)``; ``inf`` at ``r = 1`` (pressure alone at the zero-strain hardness).
    """
    r = _checked("r", r, 0.0, 1.0, "in [0, 1] (p / p_f)")
    s = _checked("s0_over_pf", s0_over_pf, 0.0, math.inf, "finite and >= 0")
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(r < 1.0, s * r / np.sqrt(np.maximum(1.0 - r * r, 0.0)), np.inf)


def lattice_sink_rate(alpha: ArrayLike, slope: float) -> NDArray[np.float64]:
    """Sinking rate of the plateaus per half-spacing and strain in the slip-line lattice (Eq. F2).

    ``c_L = v_b / (l eps_dot) = 1 + tan(theta) (1 - A)``: a rigid-plastic strip stretched at its
    yield deforms on 45-degree slip lines through the plateaus' edges; under any pressure on the
    plateaus the lines that sink them carry the whole stretch at no more dissipation than the
    uniform flow, so the plateau wedges sink by ``l eps_dot`` against the flanks while the flanks
    move apart by ``l eps_dot``, which adds ``tan(theta) (1 - A)`` (docs/flattening.md).
    """
    a = _checked("alpha", alpha, 0.0, 1.0, "a contact fraction in [0, 1]")
    return 1.0 + float(_checked("slope", slope, 0.0, math.inf, "finite and >= 0")) * (1.0 - a)


def _checked(name: str, value: ArrayLike, lo: float, hi: float, allowed: str) -> NDArray:
    """``value`` as a float array, every entry finite and in ``[lo, hi]``; else ``ValueError``."""
    a = as_float_array(name, value)
    if not (np.all(np.isfinite(a)) and np.all((a >= lo) & (a <= hi))):
        raise ValueError(f"{name} must be {allowed}")
    return a


def lattice_hardening_limit(
    p: ArrayLike, hardening: ArrayLike | None, alpha: ArrayLike
) -> NDArray[np.float64]:
    """The lattice's sinking rate a hardening bulk allows (Eq. F2c): ``6 p (1 - A) / h``.

    The lattice sinks the plateaus by an uneven split of the slip between its two families; in a
    hardening bulk the side that slipped more is stronger and the pressure pays for it. Material
    carried through the sinking zone by the stretch gains the extra shear ``v_b / (l eps_dot)``
    and on average half the flow stress ``h_k`` times it, ``h_k = dk/dgamma = h / 3`` (von Mises,
    ``h = d sigma_y / d eps_eq``). The pressure works on the split only through the plateaus'
    descent against the surface's mean, ``(1 - A) v_b`` (the valleys, ``1 - A`` of the period,
    rise by ``A v_b``: the split leaves the mean surface where the uniform thinning puts it), so
    its work equals that dissipation at ``v_b / (l eps_dot) = 2 p (1 - A) / h_k = 6 p (1 - A) /
    h``. The lattice's rate is ``min(c_L, 6 p (1 - A) / h)`` at the contact fraction ``alpha``:
    ``inf`` (no limit) for a perfectly plastic bulk, ``h = 0`` or ``None``
    (docs/flattening.md, "A hardening bulk").
    """
    if hardening is None:
        p, a = broadcast_named(p=p, alpha=alpha)
    else:
        p, hardening, a = broadcast_named(p=p, hardening=hardening, alpha=alpha)
    a = _checked("alpha", a, 0.0, 1.0, "a contact fraction in [0, 1]")
    return limit_at(lattice_hardening_factor(p, hardening), a)


def limit_at(factor: ArrayLike, alpha: ArrayLike) -> NDArray[np.float64]:
    """Eq. F2c's limit at the fraction ``alpha`` from its factor: ``factor (1 - A)``.

    An infinite factor (no limit) stays infinite at full contact (``inf 0`` would be NaN).
    Unchecked: the callers have checked both.
    """
    k, a = np.asarray(factor, dtype=float), np.asarray(alpha, dtype=float)
    with np.errstate(invalid="ignore"):
        return np.where(np.isinf(k), np.inf, k * (1.0 - a))


def lattice_hardening_factor(p: ArrayLike, hardening: ArrayLike | None) -> NDArray[np.float64]:
    """Eq. F2c's limit per unit ``1 - A``: ``6 p / h`` (``inf`` for ``h = 0`` or ``None``).

    What a node's update carries: the limit itself is this times ``1 - A`` at the fraction the
    integral of Eq. F4 has reached (:func:`lattice_hardening_limit`).
    """
    return _per_modulus(6.0, p, hardening)


def hardening_sinking_limit(p: ArrayLike, hardening: ArrayLike | None) -> NDArray[np.float64]:
    """The plateaus' sinking per half-spacing a hardening bulk holds at pressure ``p`` (Eq. F2d).

    ``delta / l = 3 p / (4 h)``. Stretched in plane strain, the material under a contact carries
    ``sigma_z = -p`` and reaches the stretching stress ``sigma_x`` at ``2 k - p``; the columns
    under and between the contacts lie in series along the stretch, carry one ``sigma_x``, and
    so differ in flow stress by ``p`` and in stretch by ``p / (d (2 k) / d eps_x) = 3 p /
    (4 h)`` (``2 k = 2 sigma_y / sqrt 3``, ``eps_eq = 2 eps_x / sqrt 3``). Over the depth of one
    half-spacing, where the contacts' pressure has spread, that is the plateaus' sinking
    against the valleys: an equilibrium, not a rate, growing as ``h`` falls with strain and
    never undone. ``inf`` (no limit) for a perfectly plastic bulk, ``h = 0`` or ``None``
    (docs/flattening.md, "A hardening bulk").
    """
    return _per_modulus(HARDENING_SINK, p, hardening)


def _per_modulus(factor: float, p: ArrayLike, hardening: ArrayLike | None) -> NDArray[np.float64]:
    """``factor p / h``, each argument checked and named; ``inf`` for ``h = 0`` or ``None``."""
    p = _checked("p", p, 0.0, math.inf, "finite and >= 0 (Pa)")
    if hardening is None:
        return np.full(p.shape, np.inf)
    why = "finite and >= 0 (Pa, d sigma_y / d eps_eq; 0: perfectly plastic)"
    h = _checked("hardening", hardening, 0.0, math.inf, why)
    with np.errstate(divide="ignore", over="ignore"):  # a modulus of 1e-300: no limit (inf)
        return np.where(h > 0, factor * p / np.where(h > 0, h, 1.0), np.inf)


def contact_growth_rate(
    p: ArrayLike, p_f: ArrayLike, alpha: ArrayLike, slope: float, beta: float, s0: float
) -> NDArray[np.float64]:
    """``dA / d eps`` of Eq. F3 per unit equivalent plastic strain ``eps``, ``A = alpha1(p_f)``.

    F1's kinematics with F2's two rates, ``r_s beta (c_L + c_E) / tan(theta)``, with ``c_L`` of
    :func:`lattice_sink_rate` at ``alpha``, ``c_E`` of :func:`layer_sink_rate` at ``p / p_f``
    and ``r_s`` = :data:`STRETCH_PER_EQUIVALENT_STRAIN` (the stretch across the ridges per unit
    ``eps``); the spacing ``l`` cancels.
    """
    p = _checked("p", p, 0.0, math.inf, "finite and >= 0 (Pa)")
    p_f = _checked("p_f", p_f, 0.0, math.inf, "finite and > 0 (Pa)")
    if np.any(p_f <= 0) or np.any(p > p_f):
        raise ValueError("p_f must be > 0 and >= p (the flattening pressure, Pa)")
    for name, v in (("slope", slope), ("beta", beta), ("s0", s0)):
        _checked(name, v, 0.0, math.inf, "finite and > 0")
        if not float(v) > 0:
            raise ValueError(f"{name} must be finite and > 0")
    c_e = layer_sink_rate(p / p_f, s0 / p_f)
    rate = beta * (lattice_sink_rate(alpha, slope) + c_e) / slope
    return STRETCH_PER_EQUIVALENT_STRAIN * rate
