"""The ``flattening`` block of a parameter file: the inputs of the flattening model.

Numpy-light and free of the law, so that :mod:`frictionlaw.params` can read and write it; the
model itself is :mod:`frictionlaw.flattening` (docs/flattening.md).
"""

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "Flattening",
    "FLATTENING_MODEL",
    "FLATTENING_MODELS",
    "LIMIT_MODEL",
    "LIMIT_SLOPE_RANGE",
    "EDGE_POINTS_RANGE",
    "FLATTENING_VERSION",
    "SLOPE_RANGE",
    "BETA_RANGE",
    "STRETCH_PER_EQUIVALENT_STRAIN",
    "HARDENING_SINK",
    "P_MIN_RATIO",
    "FLOW_CURVE_STEPS",
    "beta_absorbs_hardening",
]

#: the model a ``flattening`` block names (the surface-layer yield model of docs/flattening.md)
FLATTENING_MODEL = "layer-yield"
#: the models a block may name: the one-state model of Eqs. F1-F6 (the default) and the
#: two-state law whose rates are the tabulated rigid-plastic optimum (``frictionlaw.
#: flattening_limit``), with the same inputs
LIMIT_MODEL = "limit-analysis"
FLATTENING_MODELS = (FLATTENING_MODEL, LIMIT_MODEL)
#: the flank slopes the two-state law's table covers (its ``slope`` must lie in them)
LIMIT_SLOPE_RANGE = (0.01, 0.2)
#: how many contact fractions an ``edge_slope`` table may hold (equally spaced over [0, 1])
EDGE_POINTS_RANGE = (2, 1001)
#: version of the ``flattening`` object inside a parameter file: 2 added the slip-line lattice's
#: rate to the layer's (docs/flattening.md, Eq. F2); 3 reads the host's strain as the equivalent
#: plastic strain, stretching the asperities by :data:`STRETCH_PER_EQUIVALENT_STRAIN` of it.
#: Versions 1 and 2 (never released) are refused, since the same inputs now give another rate
FLATTENING_VERSION = 3
#: the plane-strain stretch across the ridges per unit equivalent (von Mises) plastic strain,
#: ``sqrt(3) / 2``: exact for plane strain across the ridges, and the stretch doing the same
#: plastic work as the bulk's equivalent strain on any other path (docs/flattening.md, F1)
STRETCH_PER_EQUIVALENT_STRAIN = math.sqrt(3.0) / 2.0
#: the plateaus' sinking per half-spacing a hardening bulk holds, times ``h / p`` (Eq. F2d): the
#: plane-strain columns under and between the contacts differ in stretch by ``3 p / (4 h)``
#: (``d (2 k) / d eps_x = 4 h / 3``) over a depth of one half-spacing (docs/flattening.md)
HARDENING_SINK = 0.75
#: below this ``p / H`` a node does not flatten, in either model and in the kernels: a numerical
#: floor (the one-state integrals' ``acosh(p_f / p)`` grows without bound); the lattice's rate
#: itself does not vanish with ``p`` (docs/flattening.md, F6)
P_MIN_RATIO = 1e-12
#: strain steps per point of ``flattening_curve`` with a flow curve (midpoint rule), both models
FLOW_CURVE_STEPS = 64
#: validated range of the asperity flank slope ``tan(theta)``
SLOPE_RANGE = (1e-8, 10.0)
#: validated range of the rate factor ``beta``
BETA_RANGE = (1e-3, 1e3)


def _number(name: str, value: Any, lo: float, hi: float) -> float:
    """``float(value)`` in ``[lo, hi]`` or ``ValueError`` naming ``name`` and the range.

    A number only: a string (a JSON ``"0.05"``) or a boolean is refused, not converted.
    """
    if isinstance(value, (str, bytes)):
        raise ValueError(
            f"{name} must be a real number in [{lo:g}, {hi:g}], got the string {value!r} "
            "(a number, not text)"
        )
    if isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be a real number in [{lo:g}, {hi:g}], got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(
            f"{name} must be a real number in [{lo:g}, {hi:g}], got {value!r}"
        ) from None
    if not (math.isfinite(v) and lo <= v <= hi):
        raise ValueError(f"{name} must be in [{lo:g}, {hi:g}], got {value!r}")
    return v


@dataclass(frozen=True)
class Flattening:
    """Inputs of the flattening model (the ``flattening`` block of ``params.json``).

    Parameters
    ----------
    slope : float
        ``tan(theta)``, the flank slope of the workpiece's asperities, in ``[1e-8, 10]`` (a polished
        sheet, about 1e-4 on a coarse grid, flattens at strains of that order); a calibration
        takes the RMS profile slope of the measured (or synthetic) workpiece.
    beta : float
        Factor on the plateaus' sinking rate of Eq. F3 (the lattice's and the layer's), in
        ``[1e-3, 1e3]``; 1 unless fitted to a measured contact fraction against strain.
    beta_band : (float, float), optional
        ``(lower, upper)`` of ``beta`` at ``band_level`` when it was fitted, else ``None``.
    band_level : float, optional
        Two-sided level of ``beta_band`` in ``(0, 1)``; given with the band, else ``None``.
    model : str, optional
        ``"layer-yield"`` (default): the one-state model of Eqs. F1-F6; ``"limit-analysis"``:
        the two-state law (contact fraction and flank slope per node) whose rates are the
        tabulated rigid-plastic optimum of the wedge cell, ``slope`` then in ``[0.01, 0.2]``,
        the table's (docs/flattening.md).
    edge_slope : sequence of float, optional
        Model ``limit-analysis`` only: the workpiece's edge slope at the contact fractions
        ``A = i / (n - 1)``, ``i = 0 .. n - 1`` (``n`` in ``[2, 1001]``, each in ``[1e-8, 10]``):
        the mean ``|dz/dx|`` of the profiles where the level that leaves the share ``A`` of the
        surface above it crosses them. The law then reads the flank slope as ``r * edge(A)``
        (``r`` the flank's turn) instead of one ``slope``; ``None``: the constant ``slope``.
    """

    slope: float
    beta: float = 1.0
    beta_band: tuple[float, float] | None = None
    band_level: float | None = None
    model: str = FLATTENING_MODEL
    edge_slope: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        if self.edge_slope is not None:
            set_(self, "edge_slope", _edge_table(self.edge_slope, self.model))
        if self.model not in FLATTENING_MODELS:
            raise ValueError(
                f"flattening.model must be one of {list(FLATTENING_MODELS)}, got {self.model!r}"
            )
        lo_hi = LIMIT_SLOPE_RANGE if self.model == LIMIT_MODEL else SLOPE_RANGE
        where = "flattening.slope" + ("" if self.model == FLATTENING_MODEL else f" ({self.model})")
        set_(self, "slope", _number(where, self.slope, *lo_hi))
        set_(self, "beta", _number("flattening.beta", self.beta, *BETA_RANGE))
        if (self.beta_band is None) != (self.band_level is None):
            raise ValueError("flattening.beta_band and flattening.band_level come together")
        if self.beta_band is not None:
            try:
                lo, hi = self.beta_band
            except (TypeError, ValueError):
                raise ValueError(
                    f"flattening.beta_band must be [lower, upper], got {self.beta_band!r}"
                ) from None
            lo = _number("flattening.beta_band lower", lo, *BETA_RANGE)
            hi = _number("flattening.beta_band upper", hi, *BETA_RANGE)
            if not lo <= self.beta <= hi:
                raise ValueError(
                    f"flattening.beta_band [{lo:g}, {hi:g}] must contain beta = {self.beta:g}"
                )
            set_(self, "beta_band", (lo, hi))
            level = _number("flattening.band_level", self.band_level, 1e-6, 1 - 1e-6)
            set_(self, "band_level", level)

    @property
    def fitted(self) -> bool:
        """``True`` when ``beta`` was fitted to a measurement (it then carries a band)."""
        return self.beta_band is not None

    def to_dict(self) -> dict[str, Any]:
        """The ``flattening`` JSON object (with its own model name, version and units).

        ``edge_slope`` is written only when the block has one (files without it stay readable
        by runtimes that do not know the field).
        """
        doc = {
            "model": self.model,
            "version": FLATTENING_VERSION,
            "units": {"slope": "1", "beta": "1"},
            "slope": self.slope,
            "beta": self.beta,
            "beta_band": None if self.beta_band is None else list(self.beta_band),
            "band_level": self.band_level,
        }
        if self.edge_slope is not None:
            doc["edge_slope"] = list(self.edge_slope)
        return doc

    @classmethod
    def from_dict(cls, doc: object, *, source: str = "<dict>") -> "Flattening":
        """Build from :meth:`to_dict`'s object; ``ValueError`` naming the field if malformed."""
        where = f"{source}: flattening"
        if not isinstance(doc, dict):
            raise ValueError(f"{where} must be a JSON object")
        if doc.get("model") not in FLATTENING_MODELS:
            raise ValueError(
                f"{where}.model must be one of {list(FLATTENING_MODELS)}, got {doc.get('model')!r}"
            )
        version = doc.get("version")
        if version == 1:
            raise ValueError(
                f"{where}.version 1 is the layer-alone rate of an unreleased development version; "
                f"this runtime reads {FLATTENING_VERSION} (the lattice's rate added, "
                "docs/flattening.md): calibrate the flattening block again"
            )
        if version == 2:
            raise ValueError(
                f"{where}.version 2 read the bulk strain as the stretch across the ridges; this "
                f"runtime reads {FLATTENING_VERSION}: the host's equivalent plastic strain, of which "
                "sqrt(3)/2 stretches the asperities (docs/flattening.md, F1), so the same block "
                "flattens 13 % slower per unit strain: calibrate the flattening block again"
            )
        if type(version) is not int or version != FLATTENING_VERSION:
            raise ValueError(
                f"{where}.version: unsupported {version!r}; this runtime reads {FLATTENING_VERSION}"
            )
        units = doc.get("units", {})
        if not isinstance(units, dict) or any(units.get(k, "1") != "1" for k in ("slope", "beta")):
            raise ValueError(f"{where}.units: slope and beta are dimensionless ('1')")
        unknown = set(doc) - {
            "model",
            "version",
            "units",
            "slope",
            "beta",
            "beta_band",
            "band_level",
            "edge_slope",
        }
        if unknown:
            raise ValueError(f"{where}: unknown fields {sorted(unknown)}")
        if "slope" not in doc:
            raise ValueError(f"{where}: missing 'slope'")
        band = doc.get("beta_band")
        try:
            return cls(
                slope=doc["slope"],
                beta=doc.get("beta", 1.0),
                beta_band=None if band is None else tuple(band),
                band_level=doc.get("band_level"),
                model=doc["model"],
                edge_slope=doc.get("edge_slope"),
            )
        except TypeError:
            raise ValueError(f"{where}.beta_band must be [lower, upper], got {band!r}") from None
        except ValueError as exc:
            raise ValueError(f"{source}: {exc}") from None


def _edge_table(values: Any, model: str) -> tuple[float, ...]:
    """``edge_slope`` checked: a list of ``n`` numbers in ``SLOPE_RANGE``, model limit-analysis."""
    if model != LIMIT_MODEL:
        raise ValueError(
            f"flattening.edge_slope applies to model {LIMIT_MODEL!r} only (the one-state model "
            f"takes one slope), got model {model!r}"
        )
    if isinstance(values, (str, bytes, dict)) or not hasattr(values, "__len__"):
        raise ValueError(
            f"flattening.edge_slope must be a list of {EDGE_POINTS_RANGE[0]}-"
            f"{EDGE_POINTS_RANGE[1]} slopes at equally spaced contact fractions, got {values!r}"
        )
    n = len(values)
    if not EDGE_POINTS_RANGE[0] <= n <= EDGE_POINTS_RANGE[1]:
        raise ValueError(
            f"flattening.edge_slope must hold {EDGE_POINTS_RANGE[0]}-{EDGE_POINTS_RANGE[1]} "
            f"slopes (at A = 0 .. 1), got {n}"
        )
    return tuple(
        _number(f"flattening.edge_slope[{i}]", v, *SLOPE_RANGE) for i, v in enumerate(values)
    )


def beta_absorbs_hardening(params: Any) -> bool:
    """Whether the block's ``beta`` was fitted to a sheet taken as perfectly plastic.

    True when the calibration's record (``provenance.flattening.fit``) shows a fit to a
    measurement without the sheet's flow curve (``halfspace-calib --flattening-data`` without
    ``--flow-curve``): that ``beta`` absorbs the sheet's hardening at the measured pressures, so
    a host must then run the law without the hardening modulus (Eq. F2c), or the slowing counts
    twice. False for ``beta = 1`` (nothing fitted), a fit with the flow curve, and a file
    without the record.
    """
    prov = params.provenance if isinstance(params.provenance, dict) else {}
    rec = prov.get("flattening")
    fit = rec.get("fit") if isinstance(rec, dict) else None
    return isinstance(fit, dict) and fit.get("flow_curve") is None
