"""The reload branch's form: the paper's Eq. 25, or Eq. 25 tabulated over ``p_hist``.

The paper's Eq. 25 has one pair ``(C2, n2)`` for every history. The half-space model's reload
curves change shape with ``p_hist / H`` (near ``H`` the flattened surface keeps most of its
contact down to low pressures), so over a calibrated range that reaches ``H`` one pair cannot
follow them (docs/runtime.md, "The reload law"). The ``"tabulated"`` form keeps Eq. 25's shape
and lets its parameters follow the history:

``alpha2(p; p_hist) = alpha1(p_hist) g(x2; n2(p_hist))``, with
``x2 = x2h (p / p_hist) ** s2`` and ``x2h = p_hist C2(p_hist) / (H alpha1(p_hist))``

(``x2h`` is Eq. 25's argument at ``p = p_hist``; with ``s2 = 1`` and constant ``C2, n2`` this
is Eq. 25 exactly). Below ``p / p_hist = q0 = 0.01`` (``frictionlaw._codes.Q_START``) ``x2``
starts as the quadratic ``x2h q0**s2 (a t + b t**2)``, ``t = p / (q0 p_hist)``, ``a = 2 - s2``,
``b = s2 - 1``, which meets ``q**s2`` at ``q0`` with its slope: ``d tau / dp`` stays finite at
``p -> 0`` (``q**s2`` alone has an infinite slope there for ``s2 < 1``, and GetFEM's Newton stalled
on the re-contact of a press-lift-press with it: 28 cut-backs against 17 with this start, the
paper form's count). For ``s2 = 1`` and ``2`` the start is ``q**s2`` itself. ``C2`` and ``n2`` are calibrated per load level and interpolated between
the levels by a monotone cubic Hermite interpolant (Fritsch and Carlson 1980, the slopes of
SciPy's ``PchipInterpolator``) of ``ln C2`` and ``ln n2`` over
``z = -ln(1 - p_hist / H)``, which stretches the range near ``H`` where the shape changes
fastest; beyond the first and the last level they are held constant. ``s2`` is one exponent
for the whole law: the contact of the flattened, sprung-back asperities grows like a power of
the pressure below one (about ``2/3``, Hertz's exponent, in the calibrations measured).

The interpolant's slopes are computed here, in NumPy, because :mod:`frictionlaw` depends on
NumPy and numba only; the tests check them against SciPy's ``PchipInterpolator``.
"""

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._io import read_versioned

__all__ = [
    "RELOAD_FORMS",
    "RELOAD_TABLE_VERSION",
    "S2_RANGE",
    "ReloadTable",
    "pchip_slopes",
    "hermite",
    "history_coordinate",
    "top_slope",
    "INTERPOLATION",
    "LN_C2_MAX",
]

#: the reload forms a parameter file may name: the paper's Eq. 25, or Eq. 25 tabulated
RELOAD_FORMS = ("paper", "tabulated")
#: version of the ``reload_law`` object inside a parameter file
RELOAD_TABLE_VERSION = 1
#: validated range of the exponent ``s2`` of ``p / p_hist``
S2_RANGE = (1e-2, 1e2)
#: validated ranges of the tabulated C2 and n2 (those of the paper's C2, n2)
_C_RANGE = (1e-6, 1e6)
_N_RANGE = (1e-3, 1e6)
#: the largest ``ln C2`` the extrapolation above the last level reaches (the range's top)
LN_C2_MAX = float(np.log(_C_RANGE[1]))
#: how the table reads between and beyond its levels (written into the parameter file)
INTERPOLATION = (
    "monotone cubic Hermite (Fritsch-Carlson) of ln C2 and ln n2 over z = -ln(1 - p_hist/H); "
    "the first level's values below it; above the last level ln n2 constant and ln C2 linear in "
    "z with the secant slope of the last two levels (at least 0; 0 for one level), at most "
    "ln 1e6, so that the reload curve meets alpha1(p_hist) as p_hist -> H"
)


def top_slope(z: ArrayLike, lnC2: ArrayLike) -> float:
    """``d ln C2 / dz`` above the last level: the last two levels' secant, at least 0.

    As ``p_hist -> H`` (``z -> inf``) a surface flattened to full contact conforms to the tool and
    recontacts at once: the reload curve tends to ``alpha1(p_hist)`` at every ``p``, which Eq. 25
    gives as ``C2 -> inf``. Holding the last level's ``C2`` (the rule before) leaves the curve's
    low-pressure part where the last level had it, 0.2 below the model 60 MPa above a top level
    of 700 MPa (H = 800 MPa, docs/runtime.md); the secant carries the trend of the levels up
    to the limit. A falling secant (noise) gives 0: the last level's values.
    """
    z = np.asarray(z, dtype=float)
    c = np.asarray(lnC2, dtype=float)
    if z.size < 2:
        return 0.0
    return max(0.0, float((c[-1] - c[-2]) / (z[-1] - z[-2])))


def history_coordinate(p_hist: ArrayLike, H: float) -> NDArray[np.float64]:
    """The interpolation coordinate ``z = -ln(1 - p_hist / H)`` of the tabulated form.

    ``z`` is ``p_hist / H`` near 0 and grows without bound as ``p_hist -> H``, so that equal
    steps in ``z`` are small steps in pressure where the reload curves change fastest. Only
    defined for ``p_hist < H`` (the kernels hold the last level's values from the last level on).
    """
    x = np.asarray(p_hist, dtype=float) / float(H)
    if np.any(x >= 1.0) or np.any(x < 0.0):
        raise ValueError(f"p_hist / H must be in [0, 1) for the reload table, got {x!r}")
    return -np.log1p(-x)


def pchip_slopes(x: ArrayLike, y: ArrayLike) -> NDArray[np.float64]:
    """Slopes ``dy/dx`` at the knots of the monotone cubic Hermite interpolant (Fritsch-Carlson).

    The interior slope is the weighted harmonic mean of the neighbouring secants (0 where they
    differ in sign or one is 0), the end slopes the shape-preserving three-point formula; two
    knots give the straight line. The same slopes as :class:`scipy.interpolate.PchipInterpolator`.
    The interpolant does not overshoot: between two knots it stays within their values.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    n = x.size
    if n == 1:
        return np.zeros(1)
    h = np.diff(x)
    m = np.diff(y) / h
    if n == 2:
        return np.array([m[0], m[0]])
    d = np.zeros(n)
    for k in range(1, n - 1):
        if m[k - 1] * m[k] > 0.0:
            w1 = 2.0 * h[k] + h[k - 1]
            w2 = h[k] + 2.0 * h[k - 1]
            # (w1 + w2) / (w1 / m0 + w2 / m1), in a form whose division cannot overflow
            d[k] = (w1 + w2) * m[k - 1] * m[k] / (w1 * m[k] + w2 * m[k - 1])
    d[0] = _end_slope(h[0], h[1], m[0], m[1])
    d[-1] = _end_slope(h[-1], h[-2], m[-1], m[-2])
    return d


def _end_slope(h0: float, h1: float, m0: float, m1: float) -> float:
    d = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
    if np.sign(d) != np.sign(m0):
        return 0.0
    if np.sign(m0) != np.sign(m1) and abs(d) > 3.0 * abs(m0):
        return 3.0 * m0
    return float(d)


def hermite(x: ArrayLike, knots: ArrayLike, y: ArrayLike, d: ArrayLike) -> NDArray[np.float64]:
    """The cubic Hermite interpolant through ``(knots, y)`` with slopes ``d``, constant beyond.

    NumPy form of what the kernels evaluate per node (for tables, plots and the tests).
    """
    xq = np.asarray(x, dtype=float)
    k = np.asarray(knots, dtype=float)
    y = np.asarray(y, dtype=float)
    d = np.asarray(d, dtype=float)
    if k.size == 1:
        return np.full(xq.shape, y[0])
    xc = np.clip(xq, k[0], k[-1])
    j = np.clip(np.searchsorted(k, xc, side="right") - 1, 0, k.size - 2)
    h = k[j + 1] - k[j]
    t = (xc - k[j]) / h
    h00 = (1.0 + 2.0 * t) * (1.0 - t) ** 2
    h10 = t * (1.0 - t) ** 2
    h01 = t * t * (3.0 - 2.0 * t)
    h11 = t * t * (t - 1.0)
    return h00 * y[j] + h10 * h * d[j] + h01 * y[j + 1] + h11 * h * d[j + 1]


def _levels(name: str, values: object, lo: float, hi: float) -> tuple[float, ...]:
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"reload table {name} must be a list of real numbers") from None
    if arr.ndim != 1 or arr.size < 1:
        raise ValueError(f"reload table {name} must be a non-empty 1-D list, got shape {arr.shape}")
    bad = ~np.isfinite(arr) | (arr < lo) | (arr > hi)
    if bad.any():
        raise ValueError(
            f"reload table {name} must hold finite values in [{lo:g}, {hi:g}], got "
            f"{float(arr[bad][0])!r} at level {int(np.flatnonzero(bad)[0])}"
        )
    return tuple(float(v) for v in arr)


@dataclass(frozen=True)
class ReloadTable:
    """The tabulated reload form's parameters: ``C2``, ``n2`` per calibrated load level and ``s2``.

    Parameters
    ----------
    p_hist : sequence of float
        The calibrated load levels (Pa), strictly increasing, ``> 0`` (and below ``H``, which
        :class:`~frictionlaw.FrictionParams` checks).
    C2, n2 : sequence of float
        Eq. 25's ``C2`` and ``n2`` fitted to the reload curve of each level (same length).
    s2 : float
        The exponent of ``p / p_hist`` in ``x2`` (one for the whole law), in ``[0.01, 100]``.
    """

    p_hist: tuple
    C2: tuple
    n2: tuple
    s2: float = 1.0

    def __post_init__(self) -> None:
        ph = _levels("p_hist", self.p_hist, 1e-300, math.inf)
        c2 = _levels("C2", self.C2, *_C_RANGE)
        n2 = _levels("n2", self.n2, *_N_RANGE)
        if not (len(ph) == len(c2) == len(n2)):
            raise ValueError(
                f"reload table: p_hist, C2 and n2 need one value per level, got {len(ph)}, "
                f"{len(c2)} and {len(n2)}"
            )
        if any(b <= a for a, b in zip(ph, ph[1:], strict=False)):
            raise ValueError(f"reload table p_hist must be strictly increasing (Pa), got {ph}")
        try:
            s2 = float(self.s2)
        except (TypeError, ValueError):
            raise ValueError(f"reload table s2 must be a real number, got {self.s2!r}") from None
        if not (math.isfinite(s2) and S2_RANGE[0] <= s2 <= S2_RANGE[1]):
            raise ValueError(
                f"reload table s2 must be in [{S2_RANGE[0]:g}, {S2_RANGE[1]:g}], got {self.s2!r}"
            )
        object.__setattr__(self, "p_hist", ph)
        object.__setattr__(self, "C2", c2)
        object.__setattr__(self, "n2", n2)
        object.__setattr__(self, "s2", s2)

    def check_hardness(self, H: float) -> None:
        """``ValueError`` unless every level lies below the hardness ``H`` (Pa)."""
        if self.p_hist[-1] >= H:
            raise ValueError(
                f"reload table p_hist must lie below H = {H:g} Pa (a mean pressure cannot reach "
                f"the hardness), got {self.p_hist[-1]:g} Pa"
            )

    def knots(self, H: float) -> dict[str, NDArray[np.float64]]:
        """The interpolant's data: ``z``, ``ln C2``, ``ln n2`` at the levels and their slopes."""
        z = history_coordinate(self.p_hist, H)
        lc, ln = np.log(self.C2), np.log(self.n2)
        return {
            "z": z,
            "lnC2": lc,
            "dlnC2": pchip_slopes(z, lc),
            "lnn2": ln,
            "dlnn2": pchip_slopes(z, ln),
        }

    def at(self, p_hist: ArrayLike, H: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(C2, n2)`` of the tabulated form at the histories ``p_hist`` (Pa)."""
        kn = self.knots(H)
        x = np.asarray(p_hist, dtype=float) / H
        with np.errstate(divide="ignore"):
            z = np.where(x < 1.0, -np.log1p(-np.minimum(x, 1.0)), np.inf)
        lnc = hermite(z, kn["z"], kn["lnC2"], kn["dlnC2"])
        above = z > kn["z"][-1]
        s = top_slope(kn["z"], kn["lnC2"])
        if s > 0.0 and np.any(above):  # the rule above the last level (INTERPOLATION)
            with np.errstate(invalid="ignore"):
                up = np.minimum(kn["lnC2"][-1] + s * (z - kn["z"][-1]), LN_C2_MAX)
            lnc = np.where(above, up, lnc)
        n2 = np.exp(hermite(z, kn["z"], kn["lnn2"], kn["dlnn2"]))
        return np.exp(lnc), n2

    def to_dict(self, form: str) -> dict[str, Any]:
        """The ``reload_law`` JSON object of a parameter file (with its own version and units)."""
        return {
            "form": form,
            "version": RELOAD_TABLE_VERSION,
            "interpolation": INTERPOLATION,
            "units": {"p_hist": "Pa", "C2": "1", "n2": "1", "s2": "1"},
            "s2": self.s2,
            "p_hist": list(self.p_hist),
            "C2": list(self.C2),
            "n2": list(self.n2),
        }

    @classmethod
    def from_dict(cls, doc: dict, *, source: str = "<dict>") -> "ReloadTable":
        """The table of a ``reload_law`` object; ``ValueError`` naming the field.

        The object's ``form`` is read by :func:`frictionlaw.forms.read_branch`.
        """
        return read_versioned(
            doc,
            f"{source}: reload_law",
            RELOAD_TABLE_VERSION,
            {"p_hist": "Pa"},
            lambda d: cls(p_hist=d["p_hist"], C2=d["C2"], n2=d["n2"], s2=d.get("s2", 1.0)),
        )
