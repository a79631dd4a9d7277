"""The effective hardness H from the roughness after contact (Sec. 3.1, Figs. 3-4).

The paper tunes H (800 MPa for DC04) so that the simulated ``Ra``/``Rq`` of the sheet after
pressing at 100-600 MPa match the measured ones. :func:`fit_hardness` does that in least squares:
for a trial H, the workpiece is pressed against the tool at each measured ``p_mean`` (first
loading, volume-conserving plastic flattening as in Sec. 2.1), unloaded, and its ``Ra``/``Rq``
(about the mean, as ``roughness.csv``) compared with the measured ones; H minimises the sum of
squared relative differences over all loads and both parameters. :func:`read_after_contact`
reads the measured values (a small text table, units in the header), or a table of
``p_mean, file`` rows naming surfaces scanned after unloading (:class:`AfterContactScans`), whose
``Ra``/``Rq`` :func:`roughness_of_scans` takes through the calibration's own preparation chain (the
same crop, levelling, filters and grid). :class:`HardnessFit` carries H's standard error from the
curvature of the least-squares cost.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.optimize import minimize_scalar
from scipy.stats import t as student_t

from frictionlaw._table import STRESS_UNITS, number
from sbmf_cli import ParameterError

from ...common.checks import text_file
from ...contact.normal import solve_normal_pair
from ...topography import chain
from ...topography.filters import MIN_CUTOFF_PIXELS
from .scene_surfaces import load_scene_surfaces

__all__ = [
    "AfterContact",
    "AfterContactScans",
    "roughness_of_scans",
    "HardnessFit",
    "after_contact_roughness",
    "fit_hardness",
    "read_after_contact",
]

_LENGTH_UNITS = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "\u00b5m": 1e-6, "\u03bcm": 1e-6, "nm": 1e-9}
#: the fitted H is searched in ``(H_LOW * max p_mean, H_HIGH * max p_mean)``
H_LOW, H_HIGH = 1.02, 100.0
#: points of the coarse scan of log H before the bounded search
SCAN_POINTS = 13
#: after-contact roughness above GUARD times the model's before contact is refused as bad data
GUARD = 1.5


@dataclass(frozen=True)
class AfterContact:
    """Measured roughness of the workpiece after pressing (SI: Pa, m).

    ``p_mean``, ``Ra``, ``Rq``: one entry per measured sample (several samples per load are
    fitted as they are); ``initial``: ``(Ra, Rq)`` before contact if the table has a
    ``p_mean = 0`` row (their mean), else ``None``; ``source``: where the values came from;
    ``lambda_s`` / ``lambda_c``: the S- and L-filter the measured surfaces went through after
    contact (m; 0 / ``None``: none known), applied to the model's deformed surfaces too.
    """

    p_mean: tuple
    Ra: tuple
    Rq: tuple
    initial: tuple | None = None
    source: str = "given"
    lambda_s: float = 0.0
    lambda_c: float | None = None

    def __post_init__(self):
        p, ra, rq = (np.asarray(v, dtype=float) for v in (self.p_mean, self.Ra, self.Rq))
        if not (p.ndim == ra.ndim == rq.ndim == 1 and p.size == ra.size == rq.size):
            raise ValueError("p_mean, Ra and Rq must be 1-D sequences of one length")
        if not (np.all(np.isfinite(p)) and np.all(p > 0)):
            raise ValueError("p_mean must be finite and > 0 (Pa) after contact")
        for name, v in (("Ra", ra), ("Rq", rq)):
            if not (np.all(np.isfinite(v)) and np.all(v > 0)):
                raise ValueError(f"{name} after contact must be finite and > 0 (m)")
        if np.unique(p).size < 2:
            raise ValueError(
                f"after-contact roughness at {np.unique(p).size} load(s): the fit of H needs "
                "at least two different p_mean"
            )
        if np.any(ra > rq * (1 + 1e-9)):
            raise ValueError("Ra exceeds Rq in a row: Ra <= Rq for every surface (check columns)")
        if self.initial is not None:
            ra0, rq0 = self.initial
            high = [float(q) for q, a, b in zip(p, ra, rq, strict=True) if a > ra0 or b > rq0]
            if high:
                raise ValueError(
                    f"after-contact roughness above the initial (Ra {ra0:.4g} m, Rq {rq0:.4g} m)"
                    f" at p_mean {high} Pa: pressing flattens a surface (check the rows)"
                )
        for k, v in (("p_mean", p), ("Ra", ra), ("Rq", rq)):
            object.__setattr__(self, k, tuple(float(x) for x in v))


def _unit(header, allowed, what):
    m = re.fullmatch(r"\s*([A-Za-z_]+)\s*[\[(]\s*([^\])]+?)\s*[\])]\s*", header)
    if not m:
        raise ValueError(
            f"column '{header.strip()}' gives no unit: write it as NAME [UNIT], e.g. "
            f"'{what} [{next(iter(allowed))}]'"
        )
    name, unit = m.group(1), m.group(2)
    if unit.lower() not in allowed and unit not in allowed:
        raise ValueError(
            f"unknown unit '{unit}' of column {name}: allowed {', '.join(sorted(set(allowed)))}"
        )
    return name, allowed.get(unit.lower(), allowed.get(unit))


@dataclass(frozen=True)
class AfterContactScans:
    """Surfaces of the workpiece scanned after pressing at ``p_mean`` and unloading (SI: Pa).

    ``files``: one path per row (relative paths in the table are relative to the table's
    folder); ``source``: the table's path and sha256. :func:`roughness_of_scans` turns them into
    an :class:`AfterContact` of measured ``Ra``/``Rq``.
    """

    p_mean: tuple
    files: tuple
    source: str = "given"


def roughness_of_scans(scans, scene, surfaces):
    """``Ra``/``Rq`` of after-contact scans, prepared exactly as the calibration's workpiece.

    Each scan goes through :func:`~halfspace_calib.pipeline.sweep.scene_surfaces.load_scene_surfaces`
    with the calibration's resolved choices fixed: the same units, workpiece size correction
    (``workpiece_size``: the scans are the workpiece's) and undefined-point limit, the
    crop of the calibration's patch (``crop_size``), the S- and L-filters (``lambda_s``,
    ``lambda_c``) and the solver grid; ``Ra``/``Rq`` are taken about the mean of the levelled
    solver-grid map, as the model's after-contact roughness. Returns the :class:`AfterContact`
    (and the per-scan file records, for the provenance).

    Raises
    ------
    ValueError
        A scan that cannot be read or prepared, naming its row and file.
    """
    crop = next((f.crop_size for f in surfaces.files if f.role == "workpiece"), None)
    lambda_s = surfaces.lambda_s or 0.0
    ra, rq, records = [], [], []
    for row, (p, path) in enumerate(zip(scans.p_mean, scans.files, strict=True), start=1):
        scan_scene = dataclasses.replace(
            scene,
            workpiece=str(path),
            tool=None,
            tool_size=None,
            grid=surfaces.grid,
            crop_size=crop,
            lambda_s=lambda_s,
            lambda_c=surfaces.lambda_c,
            effects=(),
            resolution_check=False,
        )
        try:
            prepared = load_scene_surfaces(scan_scene)
        except (ValueError, OSError) as exc:
            raise ParameterError(
                f"{{after_contact}} row {row} (p_mean {p / 1e6:g} MPa, {path}): "
                + (exc.template if isinstance(exc, ParameterError) else str(exc)),
                "after_contact",
                *(exc.names if isinstance(exc, ParameterError) else ()),
            ) from None
        a, q = _ra_rq(prepared.workpiece.heights)
        ra.append(a)
        rq.append(q)
        records.append(prepared.files[0].as_dict())
    data = AfterContact(
        tuple(scans.p_mean),
        tuple(ra),
        tuple(rq),
        None,
        scans.source,
        lambda_s=lambda_s,
        lambda_c=surfaces.lambda_c,
    )
    return data, records


def _read_scans(path, lines, split, heads, sep):
    """The ``p_mean [unit], file`` form of :func:`read_after_contact`."""
    try:
        name, factor = _unit(heads[0], STRESS_UNITS, "p_mean")
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    if name.lower() != "p_mean" or heads[1].strip().lower() != "file":
        raise ValueError(f"{path}: the columns must be 'p_mean [MPa], file'")
    p_mean, files = [], []
    for i, ln in enumerate(lines[1:], start=2):
        cells = [c.strip() for c in split(ln)]
        if len(cells) != 2:
            raise ValueError(f"{path}: row {i} is not 'p_mean, file': {ln.strip()!r}")
        try:
            p = number(cells[0], sep) * factor
        except ValueError:
            raise ValueError(f"{path}: row {i}: p_mean {cells[0]!r} is not a number") from None
        if not (math.isfinite(p) and p > 0):
            raise ValueError(f"{path}: row {i}: p_mean must be > 0 after contact, got {cells[0]}")
        f = Path(cells[1])
        f = f if f.is_absolute() else path.parent / f
        if not f.is_file():
            raise ValueError(f"{path}: row {i}: the scan {cells[1]!r} is not a file ({f})")
        p_mean.append(p)
        files.append(str(f))
    if len(set(p_mean)) < 2:
        raise ValueError(
            f"{path}: scans at {len(set(p_mean))} load(s): the fit of H needs at least two "
            "different p_mean"
        )
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    return AfterContactScans(
        tuple(p_mean), tuple(files), f"fitted to the scans of {path} (sha256 {digest})"
    )


def read_after_contact(path):
    """Read measured after-contact roughness: a text table with a header naming the units.

    Lines starting with ``#`` are comments; the first other line is the header
    ``p_mean [MPa], Ra [um], Rq [um]`` (pressure units Pa, kPa, MPa, GPa, N/mm², psi, ksi;
    lengths m, mm, um or µm, nm), then one row per sample, separated by commas, semicolons, tabs
    or whitespace (the header decides; with semicolons or tabs a decimal comma is read, as
    German or French spreadsheets write numbers; a UTF-8 byte-order mark is dropped). A
    ``p_mean = 0`` row is the roughness before contact (checked against, not fitted).

    With the header ``p_mean [MPa], file`` the rows name surfaces scanned after unloading
    (instrument files, as the workpiece's; relative to the table's folder) and an
    :class:`AfterContactScans` is returned; :func:`roughness_of_scans` measures them.

    Raises
    ------
    ValueError
        Missing file, missing or unknown units, fewer than two loads, roughness above the
        initial, non-numeric cells: the message names the file and what to fix.
    """
    path = Path(path)
    text = text_file(path, "after-contact roughness file").lstrip("\ufeff")
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise ValueError(f"{path}: no header and no rows")
    # semicolons or tabs (and then decimal commas), commas, or whitespace: the header decides
    sep = next((d for d in (";", "\t", ",") if d in lines[0]), " ")
    split = (lambda s: s.split(sep)) if sep != " " else (lambda s: s.split())
    heads = re.findall(r"[A-Za-z_]+\s*[\[(][^\])]*[\])]", lines[0])
    if len(heads) != 3:
        heads = split(lines[0])
    if len(heads) == 2:  # 'p_mean [MPa], file'
        return _read_scans(path, lines, split, heads, sep)
    if len(heads) != 3:
        raise ValueError(
            f"{path}: the header must be 'p_mean [MPa], Ra [um], Rq [um]' or 'p_mean [MPa], file'"
        )
    try:
        cols = [
            _unit(heads[0], STRESS_UNITS, "p_mean"),
            _unit(heads[1], _LENGTH_UNITS, "Ra"),
            _unit(heads[2], _LENGTH_UNITS, "Rq"),
        ]
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    names = [c[0].lower() for c in cols]
    if names != ["p_mean", "ra", "rq"]:
        raise ValueError(f"{path}: the columns must be p_mean, Ra, Rq in this order")
    rows = []
    for i, ln in enumerate(lines[1:], start=2):
        cells = split(ln)
        try:
            vals = [number(c, sep) * f for c, (_, f) in zip(cells, cols, strict=True)]
        except ValueError:
            raise ValueError(f"{path}: row {i} is not three numbers: {ln.strip()!r}") from None
        rows.append(vals)
    before = [r for r in rows if r[0] == 0]
    after = [r for r in rows if r[0] != 0]
    if not after:
        raise ValueError(f"{path}: no row after contact (p_mean > 0)")
    initial = None
    if before:
        initial = (float(np.mean([r[1] for r in before])), float(np.mean([r[2] for r in before])))
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    try:
        return AfterContact(
            tuple(r[0] for r in after),
            tuple(r[1] for r in after),
            tuple(r[2] for r in after),
            initial,
            f"fitted to {path} (sha256 {digest})",
        )
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None


def _ra_rq(heights):
    """``(Ra, Rq)`` of a height map about its mean (m), as ``roughness.csv``."""
    h = heights - heights.mean()
    return float(np.mean(np.abs(h))), float(np.sqrt(np.mean(h * h)))


def _as_measured(surface, heights, lambda_s, lambda_c):
    """``heights`` on ``surface``'s grid as a scan of it goes through the preparation chain.

    The chain's levelling and filter stages (:mod:`~halfspace_calib.topography.chain`), without
    the S-filter where ``lambda_s`` is shorter than the filters allow on this grid.
    """
    if not lambda_s and lambda_c is None:
        return heights
    if lambda_s < MIN_CUTOFF_PIXELS * max(surface.dx, surface.dy):
        lambda_s = 0.0
    f, _ = chain.level_scan(surface.derive(heights, {"op": "after_contact_simulated"}))
    f, _ = chain.filter_scan(f, lambda_s, lambda_c)
    return f.heights


def after_contact_roughness(
    workpiece, tool, materials, solver, H, pressures, *, lambda_s=0.0, lambda_c=None
):
    """``(Ra, Rq)`` arrays (m) of the unloaded workpiece after pressing at each ``p_mean``.

    First loading of ``workpiece`` (softer body, hardness ``H``) against ``tool``
    (:class:`~halfspace_calib.topography.Surface` s on one grid) with volume conservation
    (Sec. 2.1); the roughness about the mean of the deformed workpiece, as the sweeps'
    ``Ra_after``/``Rq_after``. With ``lambda_s`` / ``lambda_c`` the deformed surface is first
    levelled and filtered as a scan of it would be (the after-contact scans are filtered after
    the contact; filtering and plastic flattening do not commute). ``RuntimeError`` if a solve
    does not converge.
    """
    ra, rq = [], []
    for p in pressures:
        res = solve_normal_pair(
            workpiece.heights,
            tool.heights,
            workpiece.dx,
            materials.E_star,
            p,
            H=H,
            dy=workpiece.dy,
            volume_conservation=True,
            **solver.normal_kwargs(),
        )
        if not res.converged:
            raise RuntimeError(f"the solve at {p:g} Pa with H = {H:g} Pa: {res.message}")
        a, q = _ra_rq(_as_measured(workpiece, res.deformed_workpiece, lambda_s, lambda_c))
        ra.append(a)
        rq.append(q)
    return np.array(ra), np.array(rq)


@dataclass(frozen=True)
class HardnessFit:
    """The effective hardness fitted to after-contact roughness.

    Attributes
    ----------
    H : float
        Fitted hardness (Pa).
    residual : float
        Root mean square of the relative differences ``(sim - meas) / meas`` over every row
        and both ``Ra`` and ``Rq``.
    data : AfterContact
        The measured values.
    Ra_simulated, Rq_simulated : tuple
        The model's values at ``H`` for each row (m).
    Ra_initial, Rq_initial : float
        The model workpiece's roughness before contact (m).
    bounds : tuple
        The searched interval of H (Pa).
    evaluations : int
        Trial hardnesses computed.
    H_std : float
        Standard error of H (Pa): ``H`` times that of ``log H``, from the least-squares
        curvature ``s^2 / (J.J)`` with ``J`` the derivative of the relative residuals by
        ``log H`` (central differences) and ``s^2`` the residual variance on ``2 rows - 1``
        degrees of freedom (``nan`` with fewer than 2 residuals or a flat cost).
    H_interval : tuple
        ``H exp(-+ t_0.95 se(log H))``: the 90 % interval (Student's t, ``2 rows - 1`` degrees
        of freedom).
    converged : bool
        False if H ended on a bound (the data do not fix it) or the search did not converge.
    message : str
        What happened, in words.
    """

    H: float
    residual: float
    data: AfterContact
    Ra_simulated: tuple
    Rq_simulated: tuple
    Ra_initial: float
    Rq_initial: float
    bounds: tuple
    evaluations: int
    converged: bool
    message: str
    H_std: float = math.nan
    H_interval: tuple = (math.nan, math.nan)

    def as_dict(self):
        """JSON-ready record (params.json provenance, ``hardness_fit.json``)."""
        return {
            "H": self.H,
            "source": self.data.source,
            "residual_rms_relative": self.residual,
            "p_mean": list(self.data.p_mean),
            "Ra_measured": list(self.data.Ra),
            "Rq_measured": list(self.data.Rq),
            "Ra_simulated": list(self.Ra_simulated),
            "Rq_simulated": list(self.Rq_simulated),
            "initial_measured": None if self.data.initial is None else list(self.data.initial),
            "initial_simulated": [self.Ra_initial, self.Rq_initial],
            "bounds": list(self.bounds),
            "H_std": self.H_std,
            "H_interval_90": list(self.H_interval),
            "evaluations": self.evaluations,
            "converged": self.converged,
            "message": self.message,
        }


def fit_hardness(workpiece, tool, materials, solver, data, *, xtol=1e-4):
    """Fit the effective hardness H to measured after-contact ``Ra``/``Rq`` (Sec. 3.1).

    Minimises ``sum_i ((Ra_sim - Ra_i) / Ra_i)^2 + ((Rq_sim - Rq_i) / Rq_i)^2`` over ``log H``
    in ``(1.02, 100) * max(p_mean)``: a scan of :data:`SCAN_POINTS` values of ``log H``, then a
    bounded Brent search between the neighbours of the best (the cost is not always unimodal).
    ``workpiece``/``tool`` are the solver-grid surfaces of the scene (same filters and grid as
    the calibration), ``materials`` and ``solver`` its records (the materials' own H is not
    used).

    Raises
    ------
    ValueError
        After-contact roughness above the model workpiece's initial roughness (no H can
        produce it: check the data, the surfaces or the units).
    RuntimeError
        A solve did not converge.
    """
    p = np.asarray(data.p_mean)
    ra_m, rq_m = np.asarray(data.Ra), np.asarray(data.Rq)
    ra0, rq0 = _ra_rq(_as_measured(workpiece, workpiece.heights, data.lambda_s, data.lambda_c))
    # the guard against impossible data (units, rows): more than GUARD times the roughness
    # before contact and before any filtering after contact. Not 1: a filtered scan of a
    # flattened surface can keep more of its long waves than the filtered model surface before
    # contact, and a non-periodic patch pressed beyond about 0.5 H gets rougher at its edges
    # (docs/measured_surfaces.md, "H from after-contact scans")
    ra_w, rq_w = _ra_rq(workpiece.heights)
    ra_raw, rq_raw = max(ra0, ra_w), max(rq0, rq_w)
    high = sorted(
        {
            float(q)
            for q, a, b in zip(p, ra_m, rq_m, strict=True)
            if a > GUARD * ra_raw or b > GUARD * rq_raw
        }
    )
    if high:
        raise ValueError(
            f"after-contact roughness at p_mean {high} Pa is above the initial roughness of the "
            f"model workpiece (Ra {ra_raw:.4g} m, Rq {rq_raw:.4g} m, at the calibration's grid and "
            f"lambda_s) by more than {GUARD:g} x: pressing flattens it, so no H fits; check the "
            "units, the rows and that the data belong to this workpiece"
        )
    loads, inv = np.unique(p, return_inverse=True)
    lo, hi = H_LOW * loads.max(), H_HIGH * loads.max()
    seen = {}

    def simulate(logH):
        if logH not in seen:
            ra, rq = after_contact_roughness(
                workpiece,
                tool,
                materials,
                solver,
                math.exp(logH),
                loads,
                lambda_s=data.lambda_s,
                lambda_c=data.lambda_c,
            )
            seen[logH] = (ra[inv], rq[inv])
        return seen[logH]

    def cost(logH):
        ra, rq = simulate(logH)
        return float(np.sum(((ra - ra_m) / ra_m) ** 2 + ((rq - rq_m) / rq_m) ** 2))

    # the cost need not be unimodal in H (a pressed non-periodic patch roughens at its edges
    # beyond about 0.5 H): scan log H on a coarse grid, then refine around the best point
    grid = np.linspace(math.log(lo), math.log(hi), SCAN_POINTS)
    best = int(np.argmin([cost(x) for x in grid]))
    bracket = (grid[max(best - 1, 0)], grid[min(best + 1, grid.size - 1)])
    opt = minimize_scalar(cost, bounds=bracket, method="bounded", options={"xatol": xtol})
    H = math.exp(opt.x)
    ra, rq = simulate(opt.x)
    res = math.sqrt(opt.fun / (2 * p.size))
    # above some H nothing yields: the cost is flat there, and a minimum in that flat part (as
    # good as the purely elastic answer at the upper bound) does not fix H
    flat = opt.x < math.log(hi) and opt.fun >= cost(math.log(hi)) * (1 - 1e-9)
    on_bound = H < lo * 1.01 or H > hi / 1.01 or flat
    ok = bool(opt.success) and not on_bound
    if flat:
        msg = (
            f"H is not fixed by the data: the roughness after contact is as large as without "
            f"any plastic flattening, matched equally by every H above about {H:.4g} Pa"
        )
    elif on_bound:
        msg = (
            f"H = {H:.4g} Pa ended on a bound of ({lo:.4g}, {hi:.4g}) Pa: the after-contact "
            "roughness does not fix H (too little flattening, or more than any H gives)"
        )
    elif not opt.success:
        msg = f"the search for H did not converge: {opt.message}"
    else:
        msg = f"H = {H:.4g} Pa, rms relative residual {res:.3g} over {p.size} rows x (Ra, Rq)"
    h_std, h_int = math.nan, (math.nan, math.nan)
    if ok:
        h_std, h_int = _h_uncertainty(opt.x, simulate, ra_m, rq_m)
        if math.isfinite(h_std):
            msg += f", standard error {h_std:.3g} Pa (90 %: {h_int[0]:.4g}-{h_int[1]:.4g} Pa)"
    return HardnessFit(
        H=H,
        residual=res,
        data=data,
        Ra_simulated=tuple(float(v) for v in ra),
        Rq_simulated=tuple(float(v) for v in rq),
        Ra_initial=ra0,
        Rq_initial=rq0,
        bounds=(lo, hi),
        evaluations=len(seen),
        converged=ok,
        message=msg,
        H_std=h_std,
        H_interval=h_int,
    )


def _h_uncertainty(log_h, simulate, ra_m, rq_m, step=0.02):
    """``(se(H), 90 % interval)`` from the curvature of the least-squares cost at ``log_h``."""

    def resid(x):
        ra, rq = simulate(x)
        return np.concatenate([(ra - ra_m) / ra_m, (rq - rq_m) / rq_m])

    r0 = resid(log_h)
    jac = (resid(log_h + step) - resid(log_h - step)) / (2 * step)
    dof = r0.size - 1
    jj = float(jac @ jac)
    if dof < 1 or not jj > 0:
        return math.nan, (math.nan, math.nan)
    se = math.sqrt(float(r0 @ r0) / dof / jj)
    h = math.exp(log_h)
    q = float(student_t.ppf(0.95, dof))
    return h * se, (h * math.exp(-q * se), h * math.exp(q * se))
