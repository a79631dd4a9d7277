"""The parameter file: :class:`frictionlaw.FrictionParams` from the fits, with the provenance."""

import math

import numpy as np

import frictionlaw
from frictionlaw import FrictionParams

from ...common.checks import positive
from .fit import FirstLoadingFit, ReloadFit

__all__ = ["fit_record", "make_params", "timeless", "timings_of"]


def _is_timing(key):
    """A record's key that holds a wall time (``seconds``, ``sweep_seconds``, ``timings``)."""
    return key in ("seconds", "timings") or key.endswith("_seconds")


def timeless(record):
    """``record`` without its wall times, at any depth: what a parameter file may hold.

    The same inputs (the same files at the same paths, the same options) give the same
    parameter file, byte for byte, so that its sha256 (which ``ring-fit`` and the exports
    record) names the calibration and not the run; the times are ``summary.json``'s
    (:func:`timings_of`).
    """
    if isinstance(record, dict):
        return {k: timeless(v) for k, v in record.items() if not _is_timing(str(k))}
    if isinstance(record, (list, tuple)):
        return [timeless(v) for v in record]
    return record


def timings_of(record, where=""):
    """``{dotted path: seconds}`` of every wall time :func:`timeless` leaves out of ``record``."""
    out = {}
    items = (
        record.items()
        if isinstance(record, dict)
        else enumerate(record)
        if isinstance(record, (list, tuple))
        else ()
    )
    for k, v in items:
        path = f"{where}.{k}" if where else str(k)
        if isinstance(k, str) and _is_timing(k):
            out.update(_numbers(v, path))
        else:
            out.update(timings_of(v, path))
    return out


def _numbers(value, path):
    """Every number in ``value`` by its dotted path (the leaves of a timing record)."""
    if isinstance(value, bool):
        return {}
    if isinstance(value, (int, float, np.integer, np.floating)):
        return {path: float(value)}
    if isinstance(value, dict):
        return {q: v for k, x in value.items() for q, v in _numbers(x, f"{path}.{k}").items()}
    return {}


def _plain(obj, where="provenance"):
    """Deep copy of ``obj`` with NumPy and path objects as JSON types; ``ValueError`` if not."""
    from pathlib import PurePath

    if obj is None or isinstance(obj, (bool, str)):
        return obj
    if isinstance(obj, (int, np.integer)) and not isinstance(obj, bool):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        f = float(obj)
        return f if math.isfinite(f) else None
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.ndarray):
        return _plain(obj.tolist(), where)
    if isinstance(obj, PurePath):
        return str(obj)
    if isinstance(obj, dict):
        return {str(k): _plain(v, f"{where}.{k}") for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v, f"{where}[{i}]") for i, v in enumerate(obj)]
    if hasattr(obj, "provenance") and hasattr(obj, "heights"):  # a Surface
        d = dict(obj.provenance)
        try:
            d["roughness"] = obj.roughness().as_dict()
        except (AttributeError, ValueError):
            pass
        d["grid_shape"] = list(obj.heights.shape)
        d["dx"], d["dy"] = float(obj.dx), float(obj.dy)
        return _plain(d, where)
    raise ValueError(f"{where}: {type(obj).__name__} cannot be written to the JSON file")


def _input_notes(k, p_range):
    """The ``provenance["inputs"]`` notes: what the file's numbers are and where they came from."""
    notes = {
        "m": "input, not fitted: Tresca friction factor of the interface, measured separately "
        "(e.g. ring compression); the roughness calibration cannot determine it",
        "sigma_y": "input: yield stress of the softer body (Pa)",
        "H": "input: hardness of the softer body (Pa), the half-space model's local pressure limit",
        "k": (
            "derived: sigma_y / 2 (Tresca, as in the paper); the law uses k, so change sigma_y "
            "and k together (k / sigma_y must stay in [1/2, 2/3])"
            if k is None
            else "input: shear flow stress given explicitly (Pa); the law uses k, sigma_y only "
            "bounds it (k / sigma_y in [1/2, 2/3])"
        ),
        "fitted": "C1, n1 (Eq. 24) and C2, n2 (Eq. 25) from the half-space contact ratios, and "
        "the tabulated forms (first_loading_law, reload_law) when fitted; geo_ratio and k_t "
        "when those effects ran",
    }
    if p_range is not None:
        notes["calibrated_range"] = (
            "first-loading mean pressures the fit saw; beyond p_max the law is extrapolated "
            "(frictionlaw.check_pressure_range counts such nodes)"
        )
    return notes


def _summaries(fits, names):
    out = {}
    for name in names:
        fit = fits[name]
        rec = fit.summary() if hasattr(fit, "summary") else {}
        rec["converged"] = bool(getattr(fit, "success", True))
        out[name] = rec
    return out


def fit_record(first, reload, table, form=None, law=None):
    """``provenance["fit"]``: each branch's fit summary.

    ``converged`` is the optimiser's verdict (what :func:`frictionlaw.params.fit_failure` refuses a
    file on); whether the law was accepted is the measured error's (``provenance["errors"]``, and
    ``run.status`` when the command failed). ``first_loading`` and ``reload`` are the forms the
    file runs; every other form fitted is beside them (``first_loading_eq24``,
    ``reload_paper``, ``reload_tabulated``).
    """
    firsts = {"eq24": first} if law is None else law.first.fits
    reloads = {"paper": reload, **({} if table is None else {"tabulated": table})}
    if law is not None:
        reloads = law.reload.fits
    run = {"first_loading": "eq24" if law is None else law.first.form}
    run["reload"] = (
        (form or ("paper" if table is None else "tabulated")) if law is None else law.reload.form
    )
    rec = {}
    for branch, fits in (("first_loading", firsts), ("reload", reloads)):
        summ = _summaries(fits, fits)
        rec[branch] = summ.pop(run[branch])
        rec.update({f"{branch}_{name}": v for name, v in summ.items()})
    return rec


def make_params(
    first,
    reload,
    *,
    m,
    sigma_y,
    H=None,
    k=None,
    surfaces=None,
    grid=None,
    tolerance=None,
    pressures=None,
    material=None,
    extra=None,
    p_range=None,
    k_t=None,
    reload_table=None,
    errors=None,
    heldout_tol=None,
    reload_form=None,
    law=None,
):
    """Assemble the calibrated :class:`frictionlaw.FrictionParams` with its provenance.

    Parameters
    ----------
    first : FirstLoadingFit
        Result of :func:`fit_first_loading`.
    reload : ReloadFit
        Result of :func:`fit_reload` (its ``C1, n1`` must be ``first``'s); its
        ``continuous`` flag becomes ``continuous_reload``.
    m : float
        Tresca friction factor in ``[0, 1]`` (measured, e.g. ring compression).
    sigma_y : float
        Yield stress of the softer body (Pa).
    H : float, optional
        Hardness (Pa); defaults to the fits' ``H`` and must equal it if given.
    k : float, optional
        Shear flow stress (Pa); default ``sigma_y / 2``.
    surfaces : dict, optional
        Name -> :class:`~halfspace_calib.topography.Surface` (its provenance, grid and
        roughness are recorded) or a dict.
    grid, tolerance, pressures, material, extra : optional
        JSON-able records of the solver grid, solver tolerance, the pressure lists, the
        material data and anything else; NumPy values are converted.
    p_range : (float, float), optional
        Mean contact pressures (Pa) covered by the first-loading data, ``(p_min, p_max)``.
    k_t : frictionlaw.TangentialStiffness, optional
        Calibrated tangential stiffness table (from the tangential effect).
    reload_table : ReloadTableFit, optional
        The tabulated reload form's fit (:func:`~.reload_table.fit_reload_table`, same ``C1, n1,
        H`` and ``continuous``): the parameters then run that form (``reload_form =
        "tabulated"``), and ``reload`` (the paper's Eq. 25) is kept beside it.
    reload_form : {"tabulated", "paper"}, optional
        The form the parameters run (default: ``"tabulated"`` with a ``reload_table``, else
        ``"paper"``); a table is kept with the paper's form, so that a user can switch.
    errors : dict, optional
        Branch -> :class:`~.heldout.BranchErrors`, recorded under ``provenance["errors"]``.
    law : FittedLaw, optional
        Both branches' fitted forms (:func:`~.forms.fit_law`): the file runs the forms it chose
        (``reload_table``, ``reload_form`` and ``errors`` are taken from it), with the tables
        fitted beside kept.
    heldout_tol : float, optional
        The tolerance the errors were judged against (recorded with them).

    Returns
    -------
    FrictionParams
        With ``provenance = {"software", "surfaces", "grid", "tolerance", "pressures",
        "material", "fit": {"first_loading", "reload"}, "inputs", ...}``; ``"inputs"`` says
        in words which parameters are the user's inputs (``m``, ``sigma_y``, ``H``, ``k``)
        and which the roughness calibration fitted.
    """
    if not isinstance(first, FirstLoadingFit):
        raise ValueError("first must be the FirstLoadingFit returned by fit_first_loading")
    if not isinstance(reload, ReloadFit):
        raise ValueError("reload must be the ReloadFit returned by fit_reload")
    if (reload.C1, reload.n1) != (first.C1, first.n1) or reload.H != first.H:
        raise ValueError(
            "reload was fitted with other C1, n1 or H than first: refit it with first's values"
        )
    if reload_table is not None and (
        (reload_table.C1, reload_table.n1, reload_table.H) != (first.C1, first.n1, first.H)
        or reload_table.continuous != reload.continuous
    ):
        raise ValueError(
            "reload_table was fitted with other C1, n1, H or continuous than first and reload"
        )
    first_loading = ("eq24", None)
    if law is not None:
        reload_table, reload_form, errors = law.table, law.reload.form, law.errors
        first_loading = law.first.runtime()
    if H is None:
        H = first.H
    elif positive("H", H) != first.H:
        raise ValueError(f"H = {H!r} differs from the fits' H = {first.H!r}")
    import scipy

    prov = {
        "software": {
            "sbmf-friction": frictionlaw.__version__,
            "numpy": np.__version__,
            "scipy": scipy.__version__,
        },
        "surfaces": _plain(surfaces or {}, "surfaces"),
        "grid": _plain(grid, "grid"),
        "tolerance": _plain(tolerance, "tolerance"),
        "pressures": _plain(pressures, "pressures"),
        "material": _plain(material, "material"),
        "fit": fit_record(first, reload, reload_table, reload_form, law),
        "inputs": _input_notes(k, p_range),
    }
    if errors is not None:
        prov["errors"] = {
            "heldout_tol": heldout_tol,
            **{key: e.summary() for key, e in errors.items()},
        }
    if extra is not None:
        prov["extra"] = _plain(extra, "extra")
    return FrictionParams(
        m=m,
        sigma_y=sigma_y,
        H=H,
        C1=first.C1,
        n1=first.n1,
        C2=reload.C2,
        n2=reload.n2,
        k=k,
        continuous_reload=reload.continuous,
        reload_form=reload_form or ("paper" if reload_table is None else "tabulated"),
        reload_table=None if reload_table is None else reload_table.table,
        first_loading_form=first_loading[0],
        first_loading_table=first_loading[1],
        p_range=p_range,
        k_t=k_t,
        provenance=timeless(_plain(prov)),
    )
