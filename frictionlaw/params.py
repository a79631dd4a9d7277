"""Parameters of the SBMF friction law (Sec. 4) and their JSON file.

Nomenclature
------------
m : Tresca friction factor, ``0 <= m <= 1``
sigma_y : yield stress of the softer body (Pa)
H : hardness of the softer body (Pa), ``H ~ 2.8 sigma_y`` (Bowden and Tabor)
k : shear flow stress (Pa), ``sigma_y / 2`` in the paper (Tresca); allowed ``[1/2, 2/3] sigma_y``
C1, n1 : first-loading parameters of Eq. 24
C2, n2 : un-/reloading parameters of Eq. 25
continuous_reload : normalise Eq. 25 so that it meets Eq. 24 at ``p_hist``
reload_form : ``"paper"`` (Eq. 25 with one ``C2, n2``) or ``"tabulated"`` (Eq. 25 with ``C2, n2``
    per calibrated ``p_hist`` and an exponent ``s2``, :mod:`frictionlaw.reload_form`)
reload_table : the tabulated form's levels (:class:`~frictionlaw.reload_form.ReloadTable`)
first_loading_form : ``"eq24"`` (the paper's Eq. 24 with ``C1, n1``) or ``"tabulated"`` (the
    computed first loading interpolated, :mod:`frictionlaw.first_loading`)
first_loading_table : the tabulated form's points
    (:class:`~frictionlaw.first_loading.FirstLoadingTable`)
geo_ratio : Eq. 26's geometric share, ``f(p) = geo_ratio k alpha(p)`` (0: Eqs. 24-25 alone)
p_range : mean contact pressures (Pa) the calibration covered on first loading, ``(p_min, p_max)``
k_t : calibrated tangential interface stiffness ``k_t(p)`` (Pa/m) as a table over ``p`` (Pa)
"""

import json
import math
import os
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, cast

import numpy as np

from ._flattening_block import Flattening
from ._io import atomic_write
from ._shear_flow import check_k_against_sigma_y
from ._stiffness import K_T_FORMAT_VERSION, TangentialStiffness
from .first_loading import FirstLoadingTable
from .forms import BRANCH_KEYS, FIRST_LOADING, RELOAD, BranchForm, branch_form, read_branch
from .reload_form import ReloadTable
from .uncertainty import LAW_KEYS, Uncertainty

__all__ = [
    "FrictionParams",
    "TangentialStiffness",
    "FORMAT_NAME",
    "FORMAT_VERSION",
    "K_T_FORMAT_VERSION",
    "check_range",
    "fit_failure",
    "N_RANGE",
    "C_RANGE",
    "STRESS_RANGE",
    "K_RANGE",
]

FORMAT_NAME = "sbmf-friction-params"
#: the newest version: 3 when the file carries a ``first_loading_law`` object, 2 when it carries
#: a ``reload_law`` object only, 1 with neither (the paper's Eqs. 24-25, which every earlier
#: runtime reads): a file is written in the lowest version that expresses its content
FORMAT_VERSION = 3
_READ_VERSIONS = (1, 2, 3)
#: the first version that may carry each optional object
_SINCE = {"reload_law": 2, "first_loading_law": 3, "flattening": 3}
#: objects planned for a version that this runtime cannot read yet: refused, never ignored
#: (each changes the physics of the law); none at present
_UNREAD: dict[str, str] = {}

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


def check_range(
    name: str,
    value: Any,
    lo: float,
    hi: float,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    note: str = "",
) -> float:
    """Return ``float(value)`` or raise ``ValueError`` naming ``name`` and the allowed range.

    ``note`` (e.g. why the range is what it is) is appended to the message.
    """
    lb = "(" if lo_open else "["
    rb = ")" if hi_open else "]"
    rng = f"{lb}{lo:g}, {hi:g}{rb}"
    if isinstance(value, (str, bytes, bool, np.bool_)):  # a JSON "8e8" or true is no number
        raise ValueError(f"{name} must be a real number in {rng}, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number in {rng}, got {value!r}") from None
    ok = math.isfinite(v) or (math.isinf(hi) and v == hi and not hi_open)
    ok = ok and (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)
    if not ok:
        raise ValueError(f"{name} must be in {rng}, got {value!r}{note}")
    return v


def _check_p_range(p_range: Any) -> tuple[float, float] | None:
    if p_range is None:
        return None
    try:
        if any(isinstance(v, (str, bytes, bool, np.bool_)) for v in p_range):
            raise TypeError
        lo, hi = (float(v) for v in p_range)
    except (TypeError, ValueError):
        raise ValueError(f"p_range must be (p_min, p_max) in Pa, got {p_range!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo <= hi):
        raise ValueError(f"p_range must satisfy 0 < p_min <= p_max < inf (Pa), got {p_range!r}")
    return (lo, hi)


@dataclass(frozen=True)
class FrictionParams:
    """Validated parameter set of the paper's friction law, first loading and reload.

    It is the law of Eqs. 24-25.

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
        Shear flow stress in Pa (the law's ``k``), in ``[1e2, 1e13]``; defaults to
        ``sigma_y / 2`` as in the paper. Given explicitly, ``k / sigma_y`` must lie in
        ``[1/2, 2/3]`` (Tresca to twin shear, von Mises ``1/sqrt(3)`` inside), else
        ``ValueError`` naming both values.
    continuous_reload : bool
        Use the normalised Eq. 25 that equals Eq. 24 at ``p = p_hist``
        (see :func:`frictionlaw.reload_jump`), in either reload form. Default ``False`` (the
        paper's Eq. 25 as printed).
    reload_form : {"paper", "tabulated"}
        The reload branch (:mod:`frictionlaw.reload_form`): ``"paper"``, Eq. 25 with the one
        pair ``C2, n2`` (the default, and the reading of every file written before the table
        existed), or ``"tabulated"``, Eq. 25 with ``C2, n2`` following ``p_hist`` through
        ``reload_table``.
    reload_table : ReloadTable, optional
        The calibrated levels of the tabulated form (required by it; kept, unused, with
        ``reload_form="paper"`` so that a calibration can be switched to the paper's form).
    first_loading_form : str
        The first-loading branch (:mod:`frictionlaw.forms`): ``"eq24"``, the paper's Eq. 24 with
        ``C1, n1`` (the default, and the reading of every file written before the table
        existed), or ``"tabulated"``, the computed first loading ``first_loading_table``
        interpolated (:mod:`frictionlaw.first_loading`). The reload branch is scaled by
        ``alpha1(p_hist)`` of the form that runs.
    first_loading_table : FirstLoadingTable, optional
        The computed first loading (required by ``"tabulated"``; kept, unused, with ``"eq24"``).
    geo_ratio : float
        Eq. 26's extra term for rough tools in ``[0, 10]``: ``tau = m [k alpha + f]`` with
        ``f = geo_ratio k alpha`` (the calibration finds ``tau_geo / tau_adh`` nearly independent
        of the pressure, Sec. 3.2), i.e. ``tau = m k (1 + geo_ratio) alpha``. Applied on both
        branches. Default 0: the paper's Eqs. 24-25.
    p_range : (float, float), optional
        ``(p_min, p_max)`` in Pa: the mean contact pressures the calibration covered on first
        loading. Beyond ``p_max`` the law is extrapolated (Eq. 24 saturates towards ``m k``).
        ``None`` when unknown (hand-made parameter sets).
    k_t : TangentialStiffness, optional
        Calibrated tangential stiffness ``k_t(p)`` (written when the calibration ran the
        tangential effect); ``None`` otherwise.
    provenance : dict
        Free mapping recorded in the file (calibration inputs, fit quality).
    uncertainty : Uncertainty, optional
        The multi-sample calibration's bands and per-sample laws (see
        :mod:`frictionlaw.uncertainty`); ``None`` otherwise. :meth:`edge_laws` and
        :meth:`sample_laws` give them as parameter sets.
    flattening : Flattening, optional
        Flattening of the asperities under bulk strain (:mod:`frictionlaw.flattening`);
        ``None``: the law of the pressure alone.
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
    reload_form: str = "paper"
    reload_table: ReloadTable | None = None
    first_loading_form: str = "eq24"
    first_loading_table: FirstLoadingTable | None = None
    geo_ratio: float = 0.0
    p_range: tuple | None = None
    k_t: TangentialStiffness | None = None
    provenance: dict = field(default_factory=dict, compare=False, hash=False, repr=False)
    uncertainty: Uncertainty | None = field(default=None, compare=False, hash=False, repr=False)
    flattening: Flattening | None = None

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "m", check_range("m", self.m, 0.0, 1.0))
        for name, rng in (("sigma_y", STRESS_RANGE), ("H", STRESS_RANGE)):
            set_(self, name, check_range(name, getattr(self, name), *rng, note=_RANGE_NOTE))
        for name, rng in (("C1", C_RANGE), ("C2", C_RANGE), ("n1", N_RANGE), ("n2", N_RANGE)):
            set_(self, name, check_range(name, getattr(self, name), *rng, note=_RANGE_NOTE))
        k = self.sigma_y / 2.0 if self.k is None else self.k
        set_(self, "k", check_range("k", k, *K_RANGE, note=_RANGE_NOTE))
        check_k_against_sigma_y(self.k, self.sigma_y)
        if not isinstance(self.continuous_reload, (bool, np.bool_)):
            raise ValueError(
                f"continuous_reload must be True or False, got {self.continuous_reload!r}"
            )
        set_(self, "continuous_reload", bool(self.continuous_reload))
        for branch in (RELOAD, FIRST_LOADING):
            form = branch_form(branch, getattr(self, f"{branch}_form"))
            form.check(getattr(self, f"{branch}_table"), self.H)
        set_(self, "geo_ratio", check_range("geo_ratio", self.geo_ratio, 0.0, 10.0))
        set_(self, "p_range", _check_p_range(self.p_range))
        if self.k_t is not None and not isinstance(self.k_t, TangentialStiffness):
            raise ValueError(
                f"k_t must be a TangentialStiffness table or None, got {type(self.k_t).__name__}"
            )
        if not isinstance(self.provenance, dict):
            raise ValueError("provenance must be a dict (a JSON object)")
        if self.uncertainty is not None and not isinstance(self.uncertainty, Uncertainty):
            raise ValueError("uncertainty must be an Uncertainty block or None")
        if self.flattening is not None and not isinstance(self.flattening, Flattening):
            raise ValueError("flattening must be a Flattening block or None")

    def _with_law(self, law: Any) -> "FrictionParams":
        """A copy running a band law (:class:`~frictionlaw.uncertainty.BandLaw`, ``SampleLaw``)."""
        kw: dict[str, Any] = {k: getattr(law, k) for k in LAW_KEYS}
        for branch in (FIRST_LOADING, RELOAD):
            form = getattr(law, branch)
            if form is not None:
                kw[f"{branch}_form"], kw[f"{branch}_table"] = form
        return self.replace(**kw, uncertainty=None)

    def branch_forms(self) -> tuple[BranchForm, BranchForm]:
        """The records of the forms that run, ``(first loading, reload)``.

        Each a :class:`frictionlaw.forms.BranchForm`.
        """
        return (
            branch_form(FIRST_LOADING, self.first_loading_form),
            branch_form(RELOAD, self.reload_form),
        )

    def edge_laws(self) -> dict[str, "FrictionParams"]:
        """``{"lower": FrictionParams, "upper": FrictionParams}``: the band's edge laws.

        Same ``m, sigma_y, H, k`` and options, the law (``C1, n1, C2, n2`` and the tabulated
        forms the file runs) fitted to the lower and upper edge of the uncertainty band.
        ``ValueError`` if the file has no uncertainty block.
        """
        if self.uncertainty is None:
            raise ValueError(
                "these parameters have no uncertainty block: calibrate from several samples "
                "(halfspace-calib --workpiece A B C ... or --patches N)"
            )
        return {k: self._with_law(v) for k, v in self.uncertainty.edge_laws.items()}

    def sample_laws(self) -> dict[str, "FrictionParams"]:
        """``{sample name: FrictionParams}``: every sample's own law (uncertainty block)."""
        if self.uncertainty is None:
            raise ValueError("these parameters have no uncertainty block (one sample)")
        return {s.name: self._with_law(s) for s in self.uncertainty.samples}

    @property
    def tau_max(self) -> float:
        """Large-pressure limit (Pa): the Tresca cap ``m k``, times ``1 + geo_ratio`` (Eq. 26)."""
        k = cast(float, self.k)  # set to sigma_y / 2 in __post_init__ when not given
        return self.m * k * (1.0 + self.geo_ratio)

    @property
    def failure(self) -> str | None:
        """Why this fit is no law to run (:func:`fit_failure` of its provenance), or ``None``."""
        return fit_failure({"provenance": self.provenance})

    @property
    def mu_eff(self) -> float:
        """Small-pressure Coulomb slope ``tau / p`` at ``p -> 0`` of the first loading that runs.

        Eq. 24: ``m k C1 / H``; the tabulated form: ``m k alpha_0 / p_0`` (its Coulomb line
        below the lowest level); times ``1 + geo_ratio`` (Eq. 26).
        """
        slope0 = self.branch_forms()[0].slope0
        assert slope0 is not None  # every first-loading form has one (BranchForm checks)
        return self.tau_max * slope0(self)

    def replace(self, **changes: Any) -> "FrictionParams":
        """Return a copy with ``changes`` applied (validated again)."""
        d = {f: getattr(self, f) for f in self.__dataclass_fields__}
        d.update(changes)
        return FrictionParams(**d)

    # -- file -----------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The JSON document as a dict."""
        d = asdict(self)
        prov = d.pop("provenance")
        cont = d.pop("continuous_reload")
        p_range = d.pop("p_range")
        for key in ("reload_form", "reload_table", "first_loading_form", "first_loading_table"):
            d.pop(key)
        d.pop("k_t")
        d.pop("uncertainty")
        d.pop("flattening")
        laws = {}
        for branch, key in BRANCH_KEYS.items():
            data = getattr(self, f"{branch}_table")
            if data is not None:
                laws[key] = data.to_dict(getattr(self, f"{branch}_form"))
        doc = {
            "format": FORMAT_NAME,
            "version": max(
                [1, *(_SINCE[k] for k in laws)]
                + ([_SINCE["flattening"]] if self.flattening else [])
            ),
            "units": dict(_UNITS),
            "parameters": d,
            "options": {"continuous_reload": cont},
        }
        for key in ("reload_law", "first_loading_law"):
            if key in laws:
                doc[key] = laws[key]
        if p_range is not None:
            doc["calibrated_range"] = {"p_min": p_range[0], "p_max": p_range[1], "unit": "Pa"}
        if self.k_t is not None:
            doc["tangential_stiffness"] = self.k_t.to_dict()
        doc["provenance"] = prov
        if self.uncertainty is not None:
            doc["uncertainty"] = self.uncertainty.to_dict()
        if self.flattening is not None:
            doc["flattening"] = self.flattening.to_dict()
        return doc

    def to_json(self, path: str | os.PathLike[str]) -> Path:
        """Write the versioned parameter file atomically; returns the path."""
        text = json.dumps(self.to_dict(), indent=2, sort_keys=False, default=_json_default)
        return atomic_write(path, lambda fh: fh.write(text.encode("utf-8") + b"\n"))

    @classmethod
    def from_dict(
        cls, doc: object, *, source: str = "<dict>", accept_failed: bool = False
    ) -> "FrictionParams":
        """Build from a document made by :meth:`to_dict`; raises ``ValueError`` if malformed.

        A document whose calibration failed or whose fit did not converge (:func:`fit_failure`)
        is refused too, naming the reason, unless ``accept_failed``.
        """
        if not isinstance(doc, dict):
            raise ValueError(f"{source}: not a JSON object")
        reason = fit_failure(doc)
        if reason is not None and not accept_failed:
            raise ValueError(
                f"{source}: {reason}; a failed fit is no law to run: recalibrate, or accept it "
                "knowingly (accept_failed=True; --accept-failed-fit on the command lines)"
            )
        if doc.get("format") != FORMAT_NAME:
            raise ValueError(
                f"{source}: 'format' must be {FORMAT_NAME!r}, got {doc.get('format')!r}"
            )
        version = doc.get("version")
        if type(version) is not int or version not in _READ_VERSIONS:  # not 1.0, not true
            raise ValueError(
                f"{source}: unsupported version {version!r}; this runtime reads versions "
                f"{', '.join(map(str, _READ_VERSIONS))} (an integer)"
            )
        for key, since in _SINCE.items():
            if key in doc and version < since:
                raise ValueError(
                    f"{source}: {key!r} needs version {since} or later, the file says version "
                    f"{version}"
                )
        for key, what in _UNREAD.items():
            if key in doc:
                raise ValueError(
                    f"{source}: {key!r} ({what}) is not read by this runtime; it changes the "
                    "law, so the file is refused rather than run without it: use a runtime that "
                    "reads it"
                )
        for key in ("units", "options", "provenance"):
            if not isinstance(doc.get(key, {}), dict):
                raise ValueError(f"{source}: {key!r} must be a JSON object, got {doc[key]!r}")
        if "units" not in doc:
            raise ValueError(
                f"{source}: no 'units' block: a parameter file states its units "
                f"({dict(_UNITS)}); add it, or rewrite the file with FrictionParams.to_json"
            )
        units = doc["units"]
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
        p_range = _read_range(doc.get("calibrated_range"), source)
        k_doc = doc.get("tangential_stiffness")
        k_t = None if k_doc is None else TangentialStiffness.from_dict(k_doc, source=source)
        u_doc = doc.get("uncertainty")
        unc = None if u_doc is None else Uncertainty.from_dict(u_doc, source=source)
        f_doc = doc.get("flattening")
        flat = None if f_doc is None else Flattening.from_dict(f_doc, source=source)
        branches: dict[str, Any] = {}  # version 1: the paper's Eqs. 24-25
        for branch, key in BRANCH_KEYS.items():
            if key in doc:
                form, data = read_branch(branch, doc[key], source)
                branches[f"{branch}_form"], branches[f"{branch}_table"] = form, data
        try:
            return cls(
                **par,
                continuous_reload=opts.get("continuous_reload", False),
                **branches,
                p_range=p_range,
                k_t=k_t,
                provenance=doc.get("provenance", {}),
                uncertainty=unc,
                flattening=flat,
            )
        except ValueError as exc:
            raise ValueError(f"{source}: {exc}") from None

    @classmethod
    def from_json(
        cls, path: str | os.PathLike[str], *, accept_failed: bool = False
    ) -> "FrictionParams":
        """Read a parameter file written by :meth:`to_json`.

        A file from a failed calibration or with an unconverged fit is refused (``ValueError``
        naming the reason) unless ``accept_failed`` (see :func:`fit_failure`).
        """
        path = Path(path)
        try:
            doc = json.loads(path.read_text(encoding="utf-8"))
        except json.JSONDecodeError as exc:
            raise ValueError(f"{path}: not valid JSON ({exc})") from None
        except UnicodeDecodeError as exc:
            raise ValueError(f"{path}: not a UTF-8 text file ({exc})") from None
        except RecursionError:
            raise ValueError(f"{path}: JSON nested too deeply to be a parameter file") from None
        return cls.from_dict(doc, source=str(path), accept_failed=accept_failed)


def fit_failure(doc: object) -> str | None:
    """Why a parameter document is no law to run, or ``None`` when its fit is good.

    Two reasons: the calibration that wrote it failed (``provenance.run.status == "failed"``,
    written by ``halfspace-calib`` when it exits 1, with the run's problems), or the fit of Eq. 24
    or Eq. 25 did not converge (``provenance.fit.<branch>.converged`` is false).
    """
    prov = doc.get("provenance") if isinstance(doc, dict) else None
    if not isinstance(prov, dict):
        return None
    run = prov.get("run")
    if isinstance(run, dict) and run.get("status") == "failed":
        problems = "; ".join(str(p) for p in run.get("problems") or ()) or "no reason recorded"
        return f"the calibration that wrote it failed ({problems[:400]})"
    fit = prov.get("fit")
    if isinstance(fit, dict):
        for branch, eq in (("first_loading", "Eq. 24"), ("reload", "Eq. 25")):
            rec = fit.get(branch)
            if isinstance(rec, dict) and rec.get("converged") is False:
                return f"its fit of {eq} ({branch}) did not converge ({rec.get('message', '')})"
    return None


def _read_range(doc: object, source: str) -> tuple[float, float] | None:
    if doc is None:
        return None
    if not isinstance(doc, dict) or doc.get("unit", "Pa") != "Pa":
        raise ValueError(f"{source}: calibrated_range must be an object {{p_min, p_max}} in Pa")
    try:
        return _check_p_range((doc["p_min"], doc["p_max"]))
    except KeyError as exc:
        raise ValueError(f"{source}: calibrated_range is missing {exc.args[0]!r}") from None
    except ValueError as exc:
        raise ValueError(f"{source}: calibrated_range: {exc}") from None


def _json_default(obj: object) -> object:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")
