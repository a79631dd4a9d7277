"""Parameters of the SBMF friction law (Sec. 4) and their JSON file.

Nomenclature
------------
m : Tresca friction factor, ``0 <= m <= 1``
sigma_y : yield stress of the softer body (Pa)
H : hardness of the softer body (Pa), ``H ~ 2.8 sigma_y`` (Bowden and Tabor)
k : shear flow stress (Pa), ``sigma_y / 2`` in the paper (Tresca)
C1, n1 : first-loading parameters of Eq. 24
C2, n2 : un-/reloading parameters of Eq. 25
continuous_reload : normalise Eq. 25 so that it meets Eq. 24 at ``p_hist``
geo_ratio : Eq. 26's geometric share, ``f(p) = geo_ratio k alpha(p)`` (0: Eqs. 24-25 alone)
"""

import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ._io import atomic_write

__all__ = [
    "FrictionParams",
    "FORMAT_NAME",
    "FORMAT_VERSION",
    "check_range",
    "N_RANGE",
    "C_RANGE",
    "STRESS_RANGE",
    "K_RANGE",
]

FORMAT_NAME = "sbmf-friction-params"
FORMAT_VERSION = 1

_UNITS = {
    "m": "1",
    "sigma_y": "Pa",
    "H": "Pa",
    "k": "Pa",
    "C1": "1",
    "n1": "1",
    "C2": "1",
    "n2": "1",
    "geo_ratio": "1",
}

#: Validated ranges. Physical values sit far inside them (n ~ 0.2-50, C ~ 0.1-100,
#: H, sigma_y ~ 1e7-1e10 Pa); within them the law is finite for any pressure and history
#: (``n -> 0`` or ``C1 / C2 -> inf`` would make the continuous reload branch's slope
#: overflow a double, a stress below 1 kPa or above 10 TPa describes no solid).
N_RANGE = (1e-3, 1e6)
C_RANGE = (1e-6, 1e6)
STRESS_RANGE = (1e3, 1e13)
K_RANGE = (1e2, 1e13)
_RANGE_NOTE = (
    " (the validated range: physical values lie well inside it, and within it the law stays "
    "finite for every pressure and history)"
)


def check_range(name, value, lo, hi, *, lo_open=False, hi_open=False, note=""):
    """Return ``float(value)`` or raise ``ValueError`` naming ``name`` and the allowed range.

    ``note`` (e.g. why the range is what it is) is appended to the message.
    """
    lb = "(" if lo_open else "["
    rb = ")" if hi_open else "]"
    rng = f"{lb}{lo:g}, {hi:g}{rb}"
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number in {rng}, got {value!r}") from None
    ok = math.isfinite(v) or (math.isinf(hi) and v == hi and not hi_open)
    ok = ok and (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)
    if not ok:
        raise ValueError(f"{name} must be in {rng}, got {value!r}{note}")
    return v


@dataclass(frozen=True)
class FrictionParams:
    """Validated parameter set of the law of Eqs. 24-25.

    Parameters
    ----------
    m : float
        Tresca friction factor in ``[0, 1]``.
    sigma_y : float
        Yield stress of the softer body in Pa, in ``[1e3, 1e13]``.
    H : float
        Hardness in Pa, in ``[1e3, 1e13]``.
    C1, n1 : float
        Eq. 24 parameters, ``C1`` in ``[1e-6, 1e6]``, ``n1`` in ``[1e-3, 1e6]``.
    C2, n2 : float
        Eq. 25 parameters, same ranges as ``C1``, ``n1``.
    k : float, optional
        Shear flow stress in Pa, in ``[1e2, 1e13]``; defaults to ``sigma_y / 2`` as in the paper.
    continuous_reload : bool
        Use the normalised Eq. 25 that equals Eq. 24 at ``p = p_hist``
        (see :func:`frictionlaw.reload_jump`). Default ``False`` (the paper's form).
    geo_ratio : float
        Eq. 26's extra term for rough tools in ``[0, 10]``: ``tau = m [k alpha + f]`` with
        ``f = geo_ratio k alpha`` (the calibration finds ``tau_geo / tau_adh`` nearly independent
        of the pressure, Sec. 3.2), i.e. ``tau = m k (1 + geo_ratio) alpha``. Applied on both
        branches. Default 0: the paper's Eqs. 24-25.
    provenance : dict
        Free mapping recorded in the file (calibration inputs, fit quality).
    """

    m: float
    sigma_y: float
    H: float
    C1: float
    n1: float
    C2: float
    n2: float
    k: float | None = None
    continuous_reload: bool = False
    geo_ratio: float = 0.0
    provenance: dict = field(default_factory=dict, compare=False, hash=False, repr=False)

    def __post_init__(self):
        set_ = object.__setattr__
        set_(self, "m", check_range("m", self.m, 0.0, 1.0))
        for name, rng in (("sigma_y", STRESS_RANGE), ("H", STRESS_RANGE)):
            set_(self, name, check_range(name, getattr(self, name), *rng, note=_RANGE_NOTE))
        for name, rng in (("C1", C_RANGE), ("C2", C_RANGE), ("n1", N_RANGE), ("n2", N_RANGE)):
            set_(self, name, check_range(name, getattr(self, name), *rng, note=_RANGE_NOTE))
        k = self.sigma_y / 2.0 if self.k is None else self.k
        set_(self, "k", check_range("k", k, *K_RANGE, note=_RANGE_NOTE))
        if not isinstance(self.continuous_reload, (bool, np.bool_)):
            raise ValueError(
                f"continuous_reload must be True or False, got {self.continuous_reload!r}"
            )
        set_(self, "continuous_reload", bool(self.continuous_reload))
        set_(self, "geo_ratio", check_range("geo_ratio", self.geo_ratio, 0.0, 10.0))
        if not isinstance(self.provenance, dict):
            raise ValueError("provenance must be a dict (a JSON object)")

    @property
    def tau_max(self):
        """Large-pressure limit (Pa): the Tresca cap ``m k``, times ``1 + geo_ratio`` (Eq. 26)."""
        return self.m * self.k * (1.0 + self.geo_ratio)

    @property
    def mu_eff(self):
        """Small-pressure Coulomb slope of Eq. 24, ``m k C1 / H`` (times ``1 + geo_ratio``)."""
        return self.tau_max * self.C1 / self.H

    def replace(self, **changes):
        """Return a copy with ``changes`` applied (validated again)."""
        d = {f: getattr(self, f) for f in self.__dataclass_fields__}
        d.update(changes)
        return FrictionParams(**d)

    # -- file -----------------------------------------------------------------
    def to_dict(self):
        """The JSON document as a dict."""
        d = asdict(self)
        prov = d.pop("provenance")
        cont = d.pop("continuous_reload")
        return {
            "format": FORMAT_NAME,
            "version": FORMAT_VERSION,
            "units": dict(_UNITS),
            "parameters": d,
            "options": {"continuous_reload": cont},
            "provenance": prov,
        }

    def to_json(self, path):
        """Write the versioned parameter file atomically; returns the path."""
        text = json.dumps(self.to_dict(), indent=2, sort_keys=False, default=_json_default)
        return atomic_write(path, lambda fh: fh.write(text.encode("utf-8") + b"\n"))

    @classmethod
    def from_dict(cls, doc, *, source="<dict>"):
        """Build from a document made by :meth:`to_dict`; raises ``ValueError`` if malformed."""
        if not isinstance(doc, dict):
            raise ValueError(f"{source}: not a JSON object")
        if doc.get("format") != FORMAT_NAME:
            raise ValueError(
                f"{source}: 'format' must be {FORMAT_NAME!r}, got {doc.get('format')!r}"
            )
        version = doc.get("version")
        if type(version) is not int or version != FORMAT_VERSION:  # not 1.0, not true
            raise ValueError(
                f"{source}: unsupported version {version!r}; this runtime reads version "
                f"{FORMAT_VERSION} (an integer)"
            )
        for key in ("units", "options", "provenance"):
            if not isinstance(doc.get(key, {}), dict):
                raise ValueError(f"{source}: {key!r} must be a JSON object, got {doc[key]!r}")
        units = doc.get("units", {})
        for key, unit in _UNITS.items():
            if key in units and units[key] != unit:
                raise ValueError(
                    f"{source}: {key} must be given in {unit!r}, file says {units[key]!r}"
                )
        par = doc.get("parameters")
        if not isinstance(par, dict):
            raise ValueError(f"{source}: missing 'parameters' object")
        missing = [k for k in ("m", "sigma_y", "H", "C1", "n1", "C2", "n2") if k not in par]
        if missing:
            raise ValueError(f"{source}: missing parameters {missing}")
        unknown = set(par) - set(_UNITS)
        if unknown:
            raise ValueError(f"{source}: unknown parameters {sorted(unknown)}")
        opts = doc.get("options", {})
        unknown = set(opts) - {"continuous_reload"}
        if unknown:
            raise ValueError(f"{source}: unknown options {sorted(unknown)}")
        try:
            return cls(
                **par,
                continuous_reload=opts.get("continuous_reload", False),
                provenance=doc.get("provenance", {}),
            )
        except ValueError as exc:
            raise ValueError(f"{source}: {exc}") from None

    @classmethod
    def from_json(cls, path):
        """Read a parameter file written by :meth:`to_json`."""
        path = Path(path)
        try:
            doc = json.loads(path.read_text(encoding="utf-8"))
        except json.JSONDecodeError as exc:
            raise ValueError(f"{path}: not valid JSON ({exc})") from None
        except UnicodeDecodeError as exc:
            raise ValueError(f"{path}: not a UTF-8 text file ({exc})") from None
        except RecursionError:
            raise ValueError(f"{path}: JSON nested too deeply to be a parameter file") from None
        return cls.from_dict(doc, source=str(path))


def _json_default(obj):
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")
