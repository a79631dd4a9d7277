"""Friction laws for the FE demo, built from command-line style options.

Which shear flow stress ``k`` each law uses
-------------------------------------------
- ``tresca``: ``tau = m k`` with ``k = sigma_f / sqrt(3)`` (von Mises), where
  ``sigma_f`` is the workpiece flow stress at the homogeneous-compression strain
  ``ln(h0 / h)``, updated at the start of every increment. This is the ``k`` of
  the ring charts and of the slab method.
- ``cap``: ``tau = min(mu p, tau_max)``; ``tau_max = m sigma_f / sqrt(3)`` (updated
  like Tresca's) unless ``tau_max`` is given in Pa.
- ``coulomb``: ``tau = mu p``, no ``k``.
- ``sbmf``: the paper's law (Eqs. 24-25) with ``k`` from the parameter file, by
  default ``sigma_y / 2`` (Tresca), fixed during the run.
"""

import math
from pathlib import Path

from frictionlaw import LAW_NAMES, FrictionParams, law_from_name

__all__ = [
    "LAWS",
    "LAW_OPTIONS",
    "make_law_factory",
    "law_parameters",
    "example_params",
    "EXAMPLE_PARAMS_PATH",
    "EXAMPLE_FLATTENING_PATH",
]

LAWS = ("none", *LAW_NAMES)

#: the options each law uses (``all`` runs every law, so it uses every option)
LAW_OPTIONS = {
    "none": (),
    "coulomb": ("mu",),
    "tresca": ("m",),
    "cap": ("mu", "m", "tau_max"),
    "sbmf": ("params",),
    "all": ("mu", "m", "tau_max", "params"),
}

#: illustrative (not calibrated) SBMF parameter file shipped with the demo
EXAMPLE_PARAMS_PATH = Path(__file__).parents[1] / "data" / "sbmf_example.json"
#: ``fe-demo ... --flattening`` without ``--params``: the ``params.json`` of ``halfspace-calib
#: --flattening`` with every other option at its default (the synthetic DC04-like surfaces),
#: byte for byte as that command writes it
EXAMPLE_FLATTENING_PATH = Path(__file__).parents[1] / "data" / "sbmf_example_flattening.json"


def example_params():
    """The shipped illustrative SBMF parameters (``FrictionParams.from_json``)."""
    return FrictionParams.from_json(EXAMPLE_PARAMS_PATH)


def make_law_factory(law="tresca", *, mu=0.1, m=0.3, tau_max=None, params=None):
    """Return ``factory(model) -> law`` (or ``None`` for frictionless dies).

    Parameters
    ----------
    law : {"none", "coulomb", "tresca", "cap", "sbmf"}
    mu : float
        Coulomb coefficient (coulomb, cap), ``>= 0``.
    m : float
        Friction factor in ``[0, 1]`` (tresca, cap's default cap).
    tau_max : float, optional
        Cap in Pa for ``cap``.
    params : FrictionParams or str or Path, optional
        Parameters for ``sbmf`` (object or JSON file); the shipped example otherwise.
    """
    if law not in LAWS:
        raise ValueError(f"law must be one of {LAWS}, got {law!r}")
    if law == "none":
        return None
    if law in ("coulomb", "cap") and not (math.isfinite(float(mu)) and float(mu) >= 0):
        raise ValueError(f"mu must be finite and >= 0, got {mu!r}")
    if law in ("tresca", "cap") and not (0.0 <= float(m) <= 1.0):
        raise ValueError(f"m must be in [0, 1], got {m!r}")
    if law == "sbmf":
        if params is None:
            params = example_params()
        elif not isinstance(params, FrictionParams):
            params = FrictionParams.from_json(params)
    if law in ("tresca", "cap") and not (law == "cap" and tau_max is not None):
        # k of the ring charts and the slab method: the current flow stress / sqrt(3)
        return lambda model: law_from_name(
            law, mu=mu, m=m, k=model.flow_stress_hom() / math.sqrt(3.0)
        )
    fixed = law_from_name(law, mu=mu, m=m, tau_max=tau_max, params=params)
    return lambda model: fixed


def law_parameters(law, *, mu=0.1, m=0.3, tau_max=None, params=None):
    """The parameters the law of a run uses, as a JSON-ready dict (for ``summary.json``).

    ``coulomb``: ``mu``; ``tresca``: ``m``; ``cap``: ``mu`` and ``tau_max`` (Pa) or ``m``;
    ``sbmf``: the parameter file (``params_file``, its ``sha256``), its parameters and options,
    the reload form it runs and ``law``, the description of the law that runs
    (:func:`frictionlaw.describe.describe_law`: each branch's form with its parameters or table
    and its measured errors, the form beside it); ``none``: nothing.
    """
    if law == "coulomb":
        return {"mu": float(mu)}
    if law == "tresca":
        return {"m": float(m)}
    if law == "cap":
        if tau_max is not None:
            return {"mu": float(mu), "tau_max": float(tau_max)}
        return {"mu": float(mu), "m": float(m)}
    if law == "sbmf":
        from frictionlaw.describe import LawSource, describe_law

        source = None
        if params is None:
            src, params = str(EXAMPLE_PARAMS_PATH), example_params()
            source = LawSource.of(EXAMPLE_PARAMS_PATH)
        elif isinstance(params, FrictionParams):
            src = "FrictionParams object"
        else:
            src, params = str(params), FrictionParams.from_json(params)
            source = LawSource.of(src)
        doc = params.to_dict()
        return {
            "params_file": src,
            "sha256": None if source is None else source.sha256,
            **doc["parameters"],
            **doc["options"],
            "reload_form": params.reload_form,
            "law": describe_law(params, source).to_dict(),
            # the flattening block as the file has it (its model, slope and beta), or None
            "flattening": doc.get("flattening"),
        }
    return {}
