"""The optional ``uncertainty`` block of a parameter file: how sure the calibrated law is.

A calibration from several surface samples (patches or scans of one sheet) writes, besides the
pooled law, a versioned ``uncertainty`` object into ``params.json``:

* ``samples``: every sample's own fitted law (the spread of the next patch): ``C1, n1, C2, n2``
  and, where the file runs a tabulated form, that form's data (``first_loading_law``,
  ``reload_law``, as in the parameter file);
* ``parameters``: the pooled value of ``C1, n1, C2, n2, mu_eff`` and its bootstrap interval;
* ``bands``: pointwise bootstrap bands (at ``level``, default 90 %) of ``alpha(p)`` and
  ``tau(p)`` on first loading and on the reload branch at a few ``p_hist``;
* ``edge_laws``: two laws (``lower``, ``upper``) in the forms the file runs, fitted to the
  band's lower and upper edges, so that an FE code can run the band's edges as laws.

The band is a *confidence* band of the pooled (population-mean) law: bootstrap over the samples
with replacement, the pooled fit redone on every resample, percentile interval. The spread of a
single next sample is wider; it is in ``samples``.

:class:`Uncertainty` reads and writes that block; :class:`~frictionlaw.FrictionParams` carries
one (or ``None``) and gives the edge and sample laws as parameter sets. Version 2 carries the
tabulated forms' data of each law (:class:`BandLaw`); it is written only when a law has some, so
that a band of the paper's equations stays version 1. A file whose block has a newer
``version`` is read without it (the law itself is unchanged).
"""

import math
from dataclasses import dataclass
from typing import Any

from .forms import BRANCH_KEYS, read_branch

__all__ = [
    "UNCERTAINTY_FORMAT",
    "UNCERTAINTY_VERSION",
    "LAW_KEYS",
    "BandLaw",
    "Band",
    "Interval",
    "SampleLaw",
    "Uncertainty",
]

UNCERTAINTY_FORMAT = "sbmf-friction-uncertainty"
UNCERTAINTY_VERSION = 2
_READ_VERSIONS = (1, 2)
#: the fitted parameters of one law (Eqs. 24-25)
LAW_KEYS = ("C1", "n1", "C2", "n2")
#: quantities a band may describe, with their unit
BAND_QUANTITIES = {"alpha_first": "1", "tau_first": "Pa", "alpha_reload": "1", "tau_reload": "Pa"}


def _num(source, name, v, *, positive=False):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ValueError(f"{source}: uncertainty {name} must be a finite number, got {v!r}")
    if positive and v <= 0:
        raise ValueError(f"{source}: uncertainty {name} must be > 0, got {v!r}")
    return float(v)


def _law(source, where, d):
    if not isinstance(d, dict):
        raise ValueError(f"{source}: uncertainty {where} must be an object with {LAW_KEYS}")
    missing = [k for k in LAW_KEYS if k not in d]
    if missing:
        raise ValueError(f"{source}: uncertainty {where} is missing {missing}")
    out: dict[str, Any] = {k: _num(source, f"{where}.{k}", d[k], positive=True) for k in LAW_KEYS}
    for branch, key in BRANCH_KEYS.items():
        if key in d:
            out[branch] = read_branch(branch, d[key], f"{source}: uncertainty {where}")
    return out


def _branches_dict(law):
    out = {}
    for branch, key in BRANCH_KEYS.items():
        form = getattr(law, branch)
        if form is not None and form[1] is not None:
            out[key] = form[1].to_dict(form[0])
    return out


@dataclass(frozen=True)
class BandLaw:
    """One law of a band (an edge law): ``C1, n1, C2, n2`` and the tabulated forms' data.

    ``first_loading`` / ``reload``: ``(form, data)`` of the branch's form, as
    ``FrictionParams``'s ``first_loading_form, first_loading_table`` (``reload_form,
    reload_table``); ``None``: the branch is the file's own (a block of version 1, or the
    paper's equation).
    """

    C1: float
    n1: float
    C2: float
    n2: float
    first_loading: tuple | None = None
    reload: tuple | None = None

    def to_dict(self):
        """JSON-ready dict."""
        return {**{k: getattr(self, k) for k in LAW_KEYS}, **_branches_dict(self)}


@dataclass(frozen=True)
class Interval:
    """A pooled value and its bootstrap interval ``[lower, upper]`` at the block's level."""

    central: float
    lower: float
    upper: float

    def to_dict(self):
        """JSON-ready dict."""
        return {"central": self.central, "lower": self.lower, "upper": self.upper}


@dataclass(frozen=True)
class SampleLaw:
    """One sample's own fit: its name (file, patch) and its law (as :class:`BandLaw`)."""

    name: str
    C1: float
    n1: float
    C2: float
    n2: float
    first_loading: tuple | None = None
    reload: tuple | None = None

    def to_dict(self):
        """JSON-ready dict."""
        return {
            "name": self.name,
            **{k: getattr(self, k) for k in LAW_KEYS},
            **_branches_dict(self),
        }


@dataclass(frozen=True)
class Band:
    """A pointwise band of one curve: ``quantity`` (:data:`BAND_QUANTITIES`) over ``p`` (Pa).

    ``p_hist`` (Pa) is the load level of a reload band, ``None`` on first loading;
    ``central`` is the pooled law, ``lower`` / ``upper`` the band's edges.
    """

    quantity: str
    p_hist: float | None
    p: tuple
    central: tuple
    lower: tuple
    upper: tuple

    @property
    def unit(self):
        """``"1"`` for ``alpha``, ``"Pa"`` for ``tau``."""
        return BAND_QUANTITIES[self.quantity]

    def at(self, p):
        """``(central, lower, upper)`` linearly interpolated at the pressure ``p`` (Pa)."""
        ps = self.p
        if not ps[0] <= p <= ps[-1]:
            raise ValueError(f"p = {p:g} Pa is outside the band's range [{ps[0]:g}, {ps[-1]:g}] Pa")
        for i in range(len(ps) - 1):
            if ps[i] <= p <= ps[i + 1]:
                t = 0.0 if ps[i + 1] == ps[i] else (p - ps[i]) / (ps[i + 1] - ps[i])
                return tuple(
                    (1 - t) * arr[i] + t * arr[i + 1]
                    for arr in (self.central, self.lower, self.upper)
                )
        return (self.central[-1], self.lower[-1], self.upper[-1])

    def to_dict(self):
        """JSON-ready dict."""
        return {
            "quantity": self.quantity,
            "unit": self.unit,
            "p_hist": self.p_hist,
            "p": list(self.p),
            "central": list(self.central),
            "lower": list(self.lower),
            "upper": list(self.upper),
        }


@dataclass(frozen=True)
class Uncertainty:
    """The ``uncertainty`` block (see the module docstring); SI units.

    Attributes
    ----------
    level : float
        Two-sided level of the intervals and bands, in ``(0, 1)`` (0.9: 5 % and 95 %).
    method : str
        How the bands were made, in words.
    n_bootstrap : int
        Bootstrap resamples.
    seed : int
        Seed of the resampling (reproducible bands).
    samples : tuple of SampleLaw
        Every sample's own parameters.
    parameters : dict
        ``C1, n1, C2, n2, mu_eff`` -> :class:`Interval`.
    edge_laws : dict
        ``"lower"`` / ``"upper"`` -> :class:`BandLaw`: the laws fitted to the band's edges (a
        dict ``{C1, n1, C2, n2}`` is taken as one).
    bands : tuple of Band
        First-loading and reload bands of ``alpha`` and ``tau``.
    """

    level: float
    method: str
    n_bootstrap: int
    seed: int
    samples: tuple
    parameters: dict
    edge_laws: dict
    bands: tuple

    def __post_init__(self):
        if not (isinstance(self.level, float) and 0.0 < self.level < 1.0):
            raise ValueError(f"uncertainty level must be in (0, 1), got {self.level!r}")
        if set(self.edge_laws) != {"lower", "upper"}:
            raise ValueError("uncertainty edge_laws must hold 'lower' and 'upper'")
        edges = {
            k: v if isinstance(v, BandLaw) else BandLaw(**v) for k, v in self.edge_laws.items()
        }
        object.__setattr__(self, "edge_laws", edges)

    @property
    def version(self):
        """The block's version: 2 when a law carries a tabulated form's data, else 1."""
        laws = [*self.samples, *self.edge_laws.values()]
        return 2 if any(_branches_dict(x) for x in laws) else 1

    def band(self, quantity, p_hist=None):
        """The :class:`Band` of ``quantity`` (at ``p_hist`` for a reload band)."""
        for b in self.bands:
            if b.quantity == quantity and (
                b.p_hist == p_hist
                or (
                    p_hist is not None
                    and b.p_hist is not None
                    and math.isclose(b.p_hist, p_hist, rel_tol=1e-9)
                )
            ):
                return b
        have = sorted({(b.quantity, b.p_hist) for b in self.bands}, key=str)
        raise KeyError(f"no band {quantity!r} at p_hist={p_hist!r}; have {have}")

    def to_dict(self):
        """JSON-ready dict (the block as written into ``params.json``)."""
        return {
            "format": UNCERTAINTY_FORMAT,
            "version": self.version,
            "level": self.level,
            "method": self.method,
            "n_bootstrap": self.n_bootstrap,
            "seed": self.seed,
            "n_samples": len(self.samples),
            "samples": [s.to_dict() for s in self.samples],
            "parameters": {k: v.to_dict() for k, v in self.parameters.items()},
            "edge_laws": {k: v.to_dict() for k, v in self.edge_laws.items()},
            "bands": [b.to_dict() for b in self.bands],
        }

    @classmethod
    def from_dict(cls, doc, *, source="<dict>"):
        """The block of a parameter file; ``None`` for a newer version (ignored, law unchanged).

        Raises ``ValueError`` naming the field for a malformed block of a known version.
        """
        if not isinstance(doc, dict) or doc.get("format") != UNCERTAINTY_FORMAT:
            raise ValueError(
                f"{source}: 'uncertainty' must be an object with format {UNCERTAINTY_FORMAT!r}"
            )
        version = doc.get("version")
        if type(version) is not int or version < 1:
            raise ValueError(f"{source}: uncertainty version must be an integer >= 1")
        if version not in _READ_VERSIONS:
            return None
        try:
            level = _num(source, "level", doc["level"], positive=True)
            samples = tuple(
                SampleLaw(str(s.get("name", i)), **_law(source, f"samples[{i}]", s))
                for i, s in enumerate(doc["samples"])
            )
            params = {}
            for k, v in doc["parameters"].items():
                if not isinstance(v, dict):
                    raise ValueError(f"{source}: uncertainty parameters.{k} must be an object")
                params[k] = Interval(
                    *(
                        _num(source, f"parameters.{k}.{f}", v[f])
                        for f in ("central", "lower", "upper")
                    )
                )
            edges = {
                k: BandLaw(**_law(source, f"edge_laws.{k}", v)) for k, v in doc["edge_laws"].items()
            }
            bands = []
            for i, b in enumerate(doc["bands"]):
                q = b["quantity"]
                if q not in BAND_QUANTITIES:
                    raise ValueError(
                        f"{source}: uncertainty bands[{i}].quantity must be one of "
                        f"{sorted(BAND_QUANTITIES)}, got {q!r}"
                    )
                arrs = [
                    tuple(_num(source, f"bands[{i}].{f}", x) for x in b[f])
                    for f in ("p", "central", "lower", "upper")
                ]
                if len({len(a) for a in arrs}) != 1 or len(arrs[0]) < 2:
                    raise ValueError(
                        f"{source}: uncertainty bands[{i}]: p, central, lower, upper must have "
                        "one common length >= 2"
                    )
                ph = b.get("p_hist")
                ph = None if ph is None else _num(source, f"bands[{i}].p_hist", ph, positive=True)
                bands.append(Band(q, ph, *arrs))
            return cls(
                level=level,
                method=str(doc.get("method", "")),
                n_bootstrap=int(doc.get("n_bootstrap", 0)),
                seed=int(doc.get("seed", 0)),
                samples=samples,
                parameters=params,
                edge_laws=edges,
                bands=tuple(bands),
            )
        except KeyError as exc:
            raise ValueError(f"{source}: uncertainty block is missing {exc.args[0]!r}") from None
        except (TypeError, AttributeError) as exc:
            raise ValueError(f"{source}: malformed uncertainty block ({exc})") from None
