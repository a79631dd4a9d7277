"""The workpiece's flow curve, for flattening runs that no FE host drives (docs/flattening.md).

The flattening rate depends on the bulk's current flow stress (the layer's ``s0``) and, in a
hardening bulk, on its hardening modulus ``d sigma_y / d eps_eq`` (Eqs. F2c, F2d). An FE host passes
both at each node. Where no host does (a curve at constant pressure, the fit of ``beta`` to a
sheet measured in the lab) they come from the sheet's flow curve against the equivalent plastic
strain, given in one of the two forms sheet-metal data sheets use:

* :class:`SwiftCurve`, ``sigma_y = K (eps0 + eps)^n``;
* :class:`TabulatedCurve`, points ``(eps, sigma_y)`` joined by straight lines (a tensile test's
  true stress against true plastic strain), not extrapolated beyond its last strain.

:func:`read_flow_curve` reads either from the text a command line takes. SI units (Pa).
"""

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._table import (
    STRAIN_SHOWN,
    STRAIN_UNITS,
    STRESS_SHOWN,
    STRESS_UNITS,
    find_columns,
    header_and_rows,
    known_names,
    number,
    plain,
    read_rows,
)

__all__ = ["SwiftCurve", "TabulatedCurve", "FlowCurve", "read_flow_curve", "flow_curve_from_dict"]

#: validated range of a flow stress (Pa), as the runtime validates a host's sigma_y
STRESS_RANGE = (1e3, 1e13)


def _strain(eps: ArrayLike, top: float) -> NDArray[np.float64]:
    e = np.asarray(eps, dtype=float)
    if not (np.all(np.isfinite(e)) and np.all(e >= 0)):
        raise ValueError("eps must be finite and >= 0 (equivalent plastic strain)")
    if np.any(e > top):
        raise ValueError(
            f"eps reaches {float(np.max(e)):.4g}, beyond the flow curve's last strain {top:g}: "
            "extend the table (it is not extrapolated)"
        )
    return e


@dataclass(frozen=True)
class SwiftCurve:
    """Swift's flow curve ``sigma_y = K (eps0 + eps)^n``.

    Parameters
    ----------
    K : float
        Strength coefficient (Pa), in ``[1e3, 1e13]``.
    eps0 : float
        Prestrain, in ``(0, 1]`` (``> 0``: the modulus at zero strain is finite).
    n : float
        Hardening exponent, in ``[0, 1]`` (0: perfectly plastic).
    """

    K: float
    eps0: float
    n: float

    def __post_init__(self) -> None:
        for name, lo, hi, open_lo in (
            ("K", *STRESS_RANGE, False),
            ("eps0", 0.0, 1.0, True),
            ("n", 0.0, 1.0, False),
        ):
            v = getattr(self, name)
            ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            if not ok or v > hi or v < lo or (open_lo and v <= lo):
                side = "(" if open_lo else "["
                unit = " (Pa)" if name == "K" else ""
                raise ValueError(
                    f"Swift flow curve: {name}{unit} must be in {side}{lo:g}, {hi:g}], got {v!r}"
                )
            object.__setattr__(self, name, float(v))

    #: the largest strain the curve is defined to
    @property
    def strain_max(self) -> float:
        return math.inf

    def sigma_y(self, eps: ArrayLike) -> NDArray[np.float64]:
        """Flow stress (Pa) at the equivalent plastic strain ``eps``."""
        return self.K * (self.eps0 + _strain(eps, math.inf)) ** self.n

    def hardening(self, eps: ArrayLike) -> NDArray[np.float64]:
        """Hardening modulus ``d sigma_y / d eps`` (Pa) at ``eps``."""
        return self.n * self.K * (self.eps0 + _strain(eps, math.inf)) ** (self.n - 1.0)

    def describe(self) -> str:
        return f"Swift: K {self.K / 1e6:.6g} MPa, eps0 {self.eps0:g}, n {self.n:g}"

    def to_dict(self) -> dict:
        return {"form": "swift", "K_Pa": self.K, "eps0": self.eps0, "n": self.n}


@dataclass(frozen=True)
class TabulatedCurve:
    """A flow curve given by points ``(eps, sigma_y)`` joined by straight lines.

    Parameters
    ----------
    strain : tuple of float
        Equivalent plastic strains, the first 0, strictly increasing (at least two).
    sigma_y : tuple of float
        Flow stresses (Pa) at them, in ``[1e3, 1e13]``, never falling (a softening bulk is
        outside the model, Eq. F2c).
    """

    strain: tuple[float, ...]
    sigma_y_points: tuple[float, ...]

    def __post_init__(self) -> None:
        e = np.asarray(self.strain, dtype=float)
        s = np.asarray(self.sigma_y_points, dtype=float)
        if e.ndim != 1 or e.shape != s.shape or e.size < 2:
            raise ValueError("tabulated flow curve: strain and sigma_y need the same length >= 2")
        if not (np.all(np.isfinite(e)) and e[0] == 0.0 and np.all(np.diff(e) > 0)):
            raise ValueError(
                "tabulated flow curve: the strains must start at 0 and increase strictly"
            )
        lo, hi = STRESS_RANGE
        if not (np.all(np.isfinite(s)) and np.all((s >= lo) & (s <= hi))):
            raise ValueError(f"tabulated flow curve: sigma_y must be in [{lo:g}, {hi:g}] Pa")
        if np.any(np.diff(s) < 0):
            raise ValueError(
                "tabulated flow curve: sigma_y falls with strain (a softening bulk is outside "
                "the flattening model)"
            )
        object.__setattr__(self, "strain", tuple(float(v) for v in e))
        object.__setattr__(self, "sigma_y_points", tuple(float(v) for v in s))

    @property
    def strain_max(self) -> float:
        return self.strain[-1]

    def sigma_y(self, eps: ArrayLike) -> NDArray[np.float64]:
        """Flow stress (Pa) at ``eps``, linear between the points."""
        return np.interp(_strain(eps, self.strain_max), self.strain, self.sigma_y_points)

    def hardening(self, eps: ArrayLike) -> NDArray[np.float64]:
        """Hardening modulus (Pa) at ``eps``: the slope of the segment holding it.

        At a point, the segment above it; at the last point, the last segment.
        """
        e = _strain(eps, self.strain_max)
        x, y = np.asarray(self.strain), np.asarray(self.sigma_y_points)
        slope = np.diff(y) / np.diff(x)
        k = np.clip(np.searchsorted(x, e, side="right") - 1, 0, slope.size - 1)
        return slope[k]

    def describe(self) -> str:
        return (
            f"tabulated: {len(self.strain)} points to strain {self.strain_max:g}, "
            f"{self.sigma_y_points[0] / 1e6:.6g}-{self.sigma_y_points[-1] / 1e6:.6g} MPa"
        )

    def to_dict(self) -> dict:
        return {
            "form": "table",
            "strain": list(self.strain),
            "sigma_y_Pa": list(self.sigma_y_points),
        }


FlowCurve = SwiftCurve | TabulatedCurve


def flow_curve_from_dict(d: dict) -> "FlowCurve":
    """The curve of its ``to_dict()`` record (a calibration's provenance keeps it)."""
    if d.get("form") == "swift":
        return SwiftCurve(d["K_Pa"], d["eps0"], d["n"])
    if d.get("form") == "table":
        return TabulatedCurve(tuple(d["strain"]), tuple(d["sigma_y_Pa"]))
    raise ValueError(f"a flow curve record has the form 'swift' or 'table', got {d.get('form')!r}")


#: a flow curve CSV's column names (compared as :func:`~._table.plain` does: any case, umlauts
#: spelt out, ``_``, ``-``, ``.`` as spaces), in English and German, each with its unit
FLOW_NAMES = {
    "strain": (
        "strain",
        "eps",
        "epsilon",
        "\u03b5",
        "true strain",
        "log strain",
        "logarithmic strain",
        "phi",
        "\u03c6",
        "Umformgrad",
        "Vergleichsumformgrad",
    ),
    # read in place of a total strain column beside it (a tensile test's export gives both)
    "plastic_strain": (
        "plastic strain",
        "true plastic strain",
        "equivalent plastic strain",
        "eps_p",
        "peeq",
        "plastische Dehnung",
    ),
    "sigma_y": (
        "sigma_y",
        "sigma",
        "\u03c3",
        "flow stress",
        "yield stress",
        "true stress",
        "stress",
        "kf",
        "k_f",
        "Fließspannung",
        "Fliesspannung",
    ),
}
#: the units each column takes (lower case) -> factor to 1 or to Pa; a stress needs one
FLOW_UNITS = {"strain": STRAIN_UNITS, "plastic_strain": STRAIN_UNITS, "sigma_y": STRESS_UNITS}
_FLOW_SHOWN = {"strain": STRAIN_SHOWN, "plastic_strain": STRAIN_SHOWN, "sigma_y": STRESS_SHOWN}
_FLOW_KNOWN = known_names(FLOW_NAMES)
#: how an engineering (nominal) column starts: a flow curve is true stress against true strain
_NOMINAL = ("engineering ", "eng ", "nominal ", "technische ")


def _flow_columns(path: Path, line: int, head: list[str]) -> dict[str, tuple[int, float, str]]:
    """``{"strain" or "sigma_y": (index, factor, header as written)}`` of a flow curve's header.

    Engineering (nominal) columns are not read; a header with no true column of a quantity but
    an engineering one is refused with the conversion. A plastic strain column is read in place
    of a total strain column beside it.
    """
    named = {"sigma_y": ("flow stress", "sigma_y_MPa or 'sigma_y [MPa]'")}
    found = find_columns(path, line, head, _FLOW_KNOWN, FLOW_UNITS, _FLOW_SHOWN, named=named)
    if "plastic_strain" in found:
        found["strain"] = found.pop("plastic_strain")
    if len(found) != 2:
        nominal = [h.strip() for h in head if plain(h).startswith(_NOMINAL)]
        if nominal:
            raise ValueError(
                f"{path}: line {line}: the column {nominal[0]!r} is an engineering (nominal) "
                "value: a flow curve is the true stress against the true (logarithmic) plastic "
                "strain; convert a nominal strain e to ln(1 + e) and its stress s to s (1 + e), "
                "take the elastic part off the strain, and head the columns strain and sigma_y "
                "with its unit"
            )
        shown = ", ".join(repr(h.strip()) for h in head) or "nothing"
        raise ValueError(
            f"{path}: the first row must name the columns strain and sigma_y with its unit, e.g. "
            f"strain and sigma_y_MPa or 'sigma_y [MPa]' (true stress against equivalent plastic "
            f"strain); found {shown}; names read: "
            + "; ".join(f"{q.replace('_', ' ')}: {', '.join(n)}" for q, n in FLOW_NAMES.items())
        )
    return found


def _read_table(path: Path) -> TabulatedCurve:
    """A CSV with a strain and a flow stress column.

    Named and with units as :data:`FLOW_NAMES` and :data:`FLOW_UNITS` say; a second header row
    may give the units.
    """
    try:
        line_of, rows, sep = read_rows(path)
    except OSError as exc:
        raise ValueError(f"flow curve: cannot read {path}: {exc.strerror or exc}") from None
    head, line_of, rows = header_and_rows(
        path, line_of, rows, sep, _FLOW_KNOWN, FLOW_UNITS, _FLOW_SHOWN
    )
    cols = _flow_columns(path, line_of[0] if line_of else 1, head)
    (je, fe, _), (js, fs, ws) = cols["strain"], cols["sigma_y"]
    eps, sig = [], []
    for i, row in zip(line_of[1:], rows[1:], strict=True):
        try:
            e, s = number(row[je], sep) * fe, number(row[js], sep) * fs
        except (IndexError, ValueError):
            cells = "".join(row[j] for j in (je, js) if j < len(row))
            hint = " (a decimal comma? write 0.5, not 0,5)" if "," in cells else ""
            raise ValueError(f"{path}: line {i}: strain and {ws} must be numbers{hint}") from None
        eps.append(e)
        sig.append(s)
    try:
        return TabulatedCurve(tuple(eps), tuple(sig))
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None


def read_flow_curve(spec: str) -> "FlowCurve":
    """The flow curve of a command line's text.

    ``swift:K,eps0,n`` (``K`` in Pa, e.g. ``swift:530e6,0.006,0.24``), or the path of a CSV
    with a strain and a flow stress column with its unit (``strain`` and ``sigma_y_MPa``,
    ``phi; kf [MPa]``, ``true strain, true stress (psi)``, :data:`FLOW_NAMES`, :data:`FLOW_UNITS`;
    commas, semicolons or tabs; ``#`` comment lines; a second header row of units). ``ValueError``
    naming what is wrong.
    """
    text = str(spec).strip()
    if text.lower().startswith("swift:"):
        parts = text[6:].split(",")
        try:
            K, eps0, n = (float(v) for v in parts)
        except ValueError:
            raise ValueError(
                f"flow curve {spec!r}: swift takes three numbers K,eps0,n (K in Pa), e.g. "
                "swift:530e6,0.006,0.24"
            ) from None
        return SwiftCurve(K, eps0, n)
    path = Path(text)
    if not path.is_file():
        raise ValueError(f"flow curve {spec!r}: neither swift:K,eps0,n nor an existing CSV file")
    return _read_table(path)
