"""The flattening block of a calibration (``halfspace-calib --flattening``, docs/flattening.md).

The model's inputs come from the calibration's own surfaces and half-space run, and no
parameter is fitted to friction:

* the asperity flank slope ``tan(theta)``: the RMS profile slope of the workpiece on the solver
  grid (the surface the half-space model contacts), the quadratic mean of the x and y profiles;
  for the two-state model also its edge slope at 51 contact fractions (``flattening_edges``),
  the flank slope that law reads as the contact grows;
* the zero-strain asperity hardness: the computed first loading itself (the law's ``alpha1``,
  fitted to it, is what the model reads; its ``p / alpha`` is reported);
* the asperity half-spacing ``l`` is reported for the FE asperity model and the reader, from the
  profiles' mean-line crossings and from the contact patches of one extra solve where the law
  gives ``alpha1 = 0.2``; the model does not use it (``l`` cancels, docs/flattening.md, F3).

With a user's measured contact fraction against strain (:func:`read_flattening_data`), the one
factor ``beta`` (on the plateaus' sinking rate of Eq. F3) is fitted to it by least
squares in ``ln beta``, with a Student-t band from the linearised residuals (:func:`fit_beta`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from frictionlaw import Flattening, alpha_first, flattening_curve
from frictionlaw.flattening import BETA_RANGE, LIMIT_MODEL, SLOPE_RANGE, equivalent_strain
from frictionlaw.flattening_curves import FlatteningCurves, FlatteningPaths
from frictionlaw.flattening_limit import LIMIT_SLOPE_RANGE

from ...contact.normal import solve_normal_pair
from .flattening_edges import EDGE_POINTS, edge_slope_table
from .flattening_sheet import FlatteningData, read_flattening_data

__all__ = [
    "BAND_LEVEL",
    "FlatteningData",
    "read_flattening_data",
    "profile_slopes",
    "rms_slope",
    "crossing_half_spacing",
    "patch_half_spacing",
    "fit_beta",
    "derive_flattening",
    "check_data_pressures",
]

#: two-sided level of the band of a fitted ``beta``
BAND_LEVEL = 0.9
#: the law's contact fraction at which the contact patches are counted
PATCH_ALPHA = 0.2
#: pressures (in H) and strains of the summary's table of the flattened contact fraction
TABLE_P = (0.05, 0.1, 0.3, 0.6)
TABLE_EPS = (0.005, 0.01, 0.02, 0.05)
#: version of the fit's record (``provenance.flattening.fit``): 2 keeps the rows (``strain``,
#: ``alpha``, ``p_Pa``) only up to :data:`ROWS_KEPT` and adds ``data`` (the file's SHA-256,
#: ranges and residuals); 1, without the key, kept every row
FIT_RECORD_VERSION = 2
#: the most rows of a measurement the fit's record keeps (a larger sheet: its digest and summary)
ROWS_KEPT = 1000
#: the most distinct pressures listed in the record (``pressures_Pa``, the residuals by pressure)
PRESSURES_KEPT = 64
#: bins of equal row count of the residuals by strain (and by pressure beyond PRESSURES_KEPT)
RESIDUAL_BINS = 8


def check_data_pressures(data: FlatteningData, H: float) -> None:
    """``ValueError`` when a measured pressure is below ``1e-4 H`` or at ``H`` or above.

    Every one below: most likely pressures in MPa under ``p_Pa``; one below where the others are
    not: a typo, whose point would dominate the fit; the strain such pressures need to flatten
    the surface exceeds any forming process. At ``H`` or above the surface is in full contact
    under the pressure alone (the half-space model's limit), so the point says nothing of
    flattening: most likely another hardness than the calibration's ``--H``, or another unit.
    """

    def line(k):
        return f"line {data.lines[k]}, " if data.lines else f"row {k + 1}, "

    low = data.p < 1e-4 * H
    if np.all(low):
        raise ValueError(
            f"{data.path}: every pressure is below 1e-4 H ({data.p.max():g} Pa at most, H = "
            f"{H:g} Pa): pressures in MPa under p_Pa? Name the column p_MPa, or give Pa"
        )
    if np.any(low):  # one row: a typo, whose point would dominate the fit
        k = int(np.argmax(low))
        raise ValueError(
            f"{data.path}: {line(k)}pressure {data.p[k]:g} Pa is below 1e-4 H (H = {H:g} Pa), "
            f"where the others are {np.median(data.p[~low]):g} Pa typically: a typo or another "
            "unit?"
        )
    if np.any(data.p >= H):
        k = int(np.argmax(data.p >= H))
        raise ValueError(
            f"{data.path}: {line(k)}a pressure of {data.p[k]:g} Pa is at or above the hardness "
            f"H = {H:g} Pa, where the surface is in full contact by the pressure alone: give the "
            "calibration the workpiece's hardness (--H), or check the pressures' unit"
        )


def profile_slopes(surface) -> tuple[float, float]:
    """RMS slopes of the x and y profiles of a :class:`Surface` (central differences)."""
    h = np.asarray(surface.heights, dtype=float)
    if surface.periodic:
        gx = (np.roll(h, -1, 0) - np.roll(h, 1, 0)) / (2 * surface.dx)
        gy = (np.roll(h, -1, 1) - np.roll(h, 1, 1)) / (2 * surface.dy)
    else:
        gx, gy = np.gradient(h, surface.dx, surface.dy)
    return float(np.sqrt(np.mean(gx * gx))), float(np.sqrt(np.mean(gy * gy)))


def rms_slope(surface) -> tuple[float, float, float]:
    """``(tan(theta), x, y)``: the slope the flattening block takes, and its two parts.

    The quadratic mean of the x and y profiles' RMS slopes (:func:`profile_slopes`).
    """
    sx, sy = profile_slopes(surface)
    return math.sqrt(0.5 * (sx * sx + sy * sy)), sx, sy


def crossing_half_spacing(surface) -> tuple[float | None, float | None]:
    """Half the mean spacing of the upward mean-line crossings of the x and of the y profiles (m).

    The width of a profile element (a peak and the valley beside it) is the spacing of two
    upward crossings of the mean line; the wedge model's period is ``2 l``. ``None`` for a
    direction without crossings.
    """
    h = np.asarray(surface.heights, dtype=float)
    h = h - h.mean()
    out = []
    for arr, step in ((h, surface.dx), (h.T, surface.dy)):
        count = int(((arr[:-1] < 0) & (arr[1:] >= 0)).sum())
        length = (arr.shape[0] - 1) * step * arr.shape[1]
        out.append(None if count == 0 else 0.5 * length / count)
    return out[0], out[1]


def patch_half_spacing(pressure, dx, dy, periodic) -> tuple[float | None, int]:
    """Half the mean spacing ``sqrt(A0 / N)`` of the ``N`` contact patches of a pressure map (m)."""
    from scipy import ndimage

    contact = np.asarray(pressure) > 0
    labels, n = ndimage.label(contact)
    if periodic and n:  # patches joined across the period's edges count once
        for a, b in ((labels[0], labels[-1]), (labels[:, 0], labels[:, -1])):
            for u, v in zip(a, b, strict=True):
                if u and v and u != v:
                    labels[labels == v] = u
        n = len(np.unique(labels[labels > 0]))
    if n == 0:
        return None, 0
    area = contact.shape[0] * dx * contact.shape[1] * dy
    return 0.5 * math.sqrt(area / n), n


def _half_grid_slope(surface) -> float | None:
    """The RMS profile slope at half the grid (2 x 2 block averages): how resolved it is."""
    from ...topography.surface import block_average

    nx, ny = surface.shape
    if min(nx, ny) < 4:
        return None
    return rms_slope(block_average(surface, (nx // 2, ny // 2), trim=True))[0]


def _alpha_pressure(params, alpha, p_lo, p_hi):
    """The pressure in ``[p_lo, p_hi]`` where the law's ``alpha1`` is ``alpha`` (bisection)."""
    lo, hi = p_lo, p_hi
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if alpha_first(mid, params) < alpha else (lo, mid)
    return 0.5 * (lo + hi)


def fit_beta(params, data: FlatteningData, level: float = BAND_LEVEL) -> dict:
    """Fit ``beta`` of ``params.flattening`` to a measured ``alpha`` against strain.

    The model's strain scales as ``1 / beta`` (Eq. F4), so ``alpha(eps; beta)`` is the curve of
    ``beta = 1`` at ``beta eps``: least squares in ``ln beta`` over ``BETA_RANGE`` (bounded
    scalar search, then the band from the linearised residuals: ``ln beta -+ t s / |g|``,
    ``g = d alpha / d ln beta``, ``s^2`` the residual variance, Student t of ``n - 1``).
    The curves are evaluated once per distinct pressure
    (:class:`frictionlaw.flattening_curves.FlatteningCurves`: the table of Eq. F4 built once,
    each trial ``beta`` a few polynomial evaluations a point), what
    :func:`frictionlaw.flattening_curve` gives point by point to rounding.
    With the sheet's flow curve (``data.flow_curve``) each distinct pressure is integrated along
    its strains at the curve's flow stress and hardening modulus
    (:class:`~frictionlaw.flattening_curves.FlatteningPaths`), as a host passing both runs the
    law; ``beta`` then no longer scales the strain axis, and each trial ``beta`` integrates anew
    (the first grid's 25 side by side). Without it the sheet is perfectly plastic at the
    calibration's ``sigma_y`` and ``beta`` absorbs its hardening.
    Raises ``ValueError`` when the points do not constrain ``beta`` (all at zero strain or at
    full contact) or the best ``beta`` lies on the range's bound.
    """
    fc, model = data.flow_curve, params.flattening.model
    unfitted = dataclasses.replace(params.flattening, beta=1.0, beta_band=None, band_level=None)
    base = params.replace(flattening=unfitted)
    if model == LIMIT_MODEL:  # the two-state law: its curves integrated at each trial beta

        def models(ln_beta):
            return np.stack(
                [
                    flattening_curve(
                        data.p,
                        data.strain,
                        params.replace(flattening=dataclasses.replace(unfitted, beta=_in_range(b))),
                        flow_curve=fc,
                    )
                    for b in np.atleast_1d(ln_beta)
                ]
            )

    elif fc is None:
        curves = FlatteningCurves(data.p, base)

        def models(ln_beta):
            return np.stack([curves.alpha(data.strain, beta=math.exp(b)) for b in ln_beta])
    else:
        paths = FlatteningPaths(data.p, data.strain, base, fc)

        def models(ln_beta):
            return paths.alpha(np.exp(np.asarray(ln_beta, dtype=float)))

    return _fit(models, data, level)


def _in_range(ln_beta: float) -> float:
    """``exp(ln_beta)`` within :data:`BETA_RANGE`.

    The fit's grid ends on the range's bounds, and its difference steps may pass them by 1e-5 in
    ``ln beta``; the record of a block refuses a ``beta`` outside.
    """
    return min(max(math.exp(ln_beta), BETA_RANGE[0]), BETA_RANGE[1])


def _fit(models, data: FlatteningData, level: float) -> dict:
    """:func:`fit_beta` for ``models(ln_betas)``: the model's ``alpha`` per ``ln beta``, a row each."""
    from scipy import optimize, stats

    fc = data.flow_curve

    def model(ln_beta):
        return models([ln_beta])[0]

    def cost(ln_beta):
        return float(np.sum((model(ln_beta) - data.alpha) ** 2))

    lo, hi = math.log(BETA_RANGE[0]), math.log(BETA_RANGE[1])
    grid = np.linspace(lo, hi, 25)
    k = int(np.argmin(np.sum((models(grid) - data.alpha[None, :]) ** 2, axis=1)))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    res = optimize.minimize_scalar(cost, bounds=(a, b), method="bounded", options={"xatol": 1e-10})
    ln_b = float(res.x)
    if ln_b <= lo + 1e-6 or ln_b >= hi - 1e-6:
        raise ValueError(
            f"{data.path}: the best beta lies on the bound of [{BETA_RANGE[0]:g}, "
            f"{BETA_RANGE[1]:g}]: the measurement cannot be described by the model with this slope"
        )
    h = 1e-5
    m0, mp, mm = models([ln_b, ln_b + h, ln_b - h])
    r = m0 - data.alpha
    g = (mp - mm) / (2 * h)
    gg = float(np.sum(g * g))
    if gg <= 1e-20:
        raise ValueError(
            f"{data.path}: the points do not constrain beta (zero strain or full contact)"
        )
    n = data.strain.size
    s2 = float(np.sum(r * r)) / max(n - 1, 1)
    t = float(stats.t.ppf(0.5 + level / 2, max(n - 1, 1)))
    half = t * math.sqrt(s2 / gg)
    if ln_b - half <= lo or ln_b + half >= hi:
        raise ValueError(
            f"{data.path}: beta = {math.exp(ln_b):.4g}, but its {100 * level:g} % band reaches the "
            f"bound of [{BETA_RANGE[0]:g}, {BETA_RANGE[1]:g}]: the measurement does not determine "
            "it within the range"
            + (
                " (a strain column in per cent gives a beta 100 times too small)"
                if ln_b < math.log(0.05)
                else ""
            )
        )
    band = tuple(math.exp(ln_b + sgn * half) for sgn in (-1, 1))
    at_zero = data.strain == 0
    rms = float(np.sqrt(np.mean(r * r)))
    notes = []
    if not 0.05 <= math.exp(ln_b) <= 20.0:
        notes.append(
            f"beta = {math.exp(ln_b):.3g} is far from the derived 1 (0.5-2 against our FE "
            "truth): check the strain column's unit (per cent gives 100 times too small), the "
            "pressures' unit and the slope's resolution"
        )
    if rms > 0.1:
        notes.append(
            f"the fit misses the measurement by {rms:.3f} RMS in alpha (largest "
            f"{float(np.max(np.abs(r))):.3f}): the model with this slope describes it poorly"
        )
    levels = np.unique(data.p)
    n_rows = data.strain.size
    return {
        "record_version": FIT_RECORD_VERSION,
        "beta": math.exp(ln_b),
        "band": list(band),
        "level": level,
        "points": int(n),
        "rms": rms,
        "notes": notes,
        "max_abs": float(np.max(np.abs(r))),
        "zero_strain_misfit": float(np.max(np.abs(r[at_zero]))) if at_zero.any() else None,
        "pressures_Pa": levels.tolist() if levels.size <= PRESSURES_KEPT else None,
        "flow_curve": None if fc is None else fc.describe(),
        "flow_curve_record": None if fc is None else fc.to_dict(),
        "flow_curve_sigma_y0_Pa": None if fc is None else float(fc.sigma_y(0.0)),
        "file": data.path,
        "data": _data_summary(data, levels, r),
        # the rows themselves up to ROWS_KEPT: a lab sheet's rows stay in its file (sha256)
        **(
            {"strain": data.strain.tolist(), "alpha": data.alpha.tolist(), "p_Pa": data.p.tolist()}
            if n_rows <= ROWS_KEPT
            else {}
        ),
    }


def _data_summary(data: FlatteningData, levels, r) -> dict:
    """The fit record's ``data``: which file, its size and digest, its ranges, the residuals.

    The residuals ``model - measured`` by pressure (each distinct pressure while there are at
    most :data:`PRESSURES_KEPT`, else :data:`RESIDUAL_BINS` bins of equal row count in pressure)
    and by strain (bins of equal row count): a rerun on the same file reproduces them.
    """

    def stats(rr):
        return {
            "rows": int(rr.size),
            "rms": float(np.sqrt(np.mean(rr * rr))),
            "mean": float(np.mean(rr)),
            "max_abs": float(np.max(np.abs(rr))),
        }

    def bins(key):
        order = np.argsort(key, kind="stable")
        return [
            {"from": float(key[idx].min()), "to": float(key[idx].max()), **stats(r[idx])}
            for idx in np.array_split(order, min(RESIDUAL_BINS, key.size))
        ]

    if levels.size <= PRESSURES_KEPT:
        by_p = [{"p_Pa": float(v), **stats(r[data.p == v])} for v in levels]
    else:
        by_p = bins(data.p)
    n = int(data.strain.size)
    return {
        "sha256": data.sha256,
        "size_bytes": data.size_bytes,
        "rows": n,
        "rows_at_zero_strain": int(np.count_nonzero(data.strain == 0)),
        "rows_kept": n <= ROWS_KEPT,
        "rows_kept_up_to": ROWS_KEPT,
        "pressures": int(levels.size),
        "p_Pa": [float(data.p.min()), float(data.p.max())],
        "strain": [float(data.strain.min()), float(data.strain.max())],
        "alpha": [float(data.alpha.min()), float(data.alpha.max())],
        "residual_mean": float(np.mean(r)),
        "residuals_by_pressure": by_p,
        "residuals_by_strain": bins(data.strain),
    }


_MODEL_TEXT = {
    "layer-yield": "layer-yield with the slip-line lattice (docs/flattening.md, Eqs. F1-F6)",
    LIMIT_MODEL: "limit-analysis: two states per node, the rigid-plastic optimum's rates "
    "(docs/flattening.md, the two-state law)",
}


def _full_contact_strain(params, p: float) -> float | None:
    """The equivalent strain at which a virgin surface reaches full contact at ``p``.

    Eq. F4's finite strain for the one-state model; for the two-state law the first of
    0.001-steps up to 5 where its curve is 1 (None if it does not get there).
    """
    if params.flattening.model != LIMIT_MODEL:
        return float(equivalent_strain(p, 2**40 * p, params))
    eps = np.arange(0.0, 5.0 + 5e-4, 1e-3)
    full = np.flatnonzero(flattening_curve(p, eps, params) >= 1.0)
    return float(eps[full[0]]) if full.size else None


def derive_flattening(
    cal, data: FlatteningData | None = None, model: str = "layer-yield"
) -> tuple[Flattening, dict]:
    """The flattening block of a calibration and the record of what it was derived from.

    Returns ``(block, record)``; the record goes into ``summary.json``, ``report.html`` and the
    parameter file's provenance (``provenance.flattening``).
    """
    scene, P = cal.scene, cal.params
    wp, tl = cal.sweeps.surfaces["workpiece"], cal.sweeps.surfaces["tool"]
    slope, sx, sy = rms_slope(wp)
    if not SLOPE_RANGE[0] <= slope <= SLOPE_RANGE[1]:
        raise ValueError(
            f"the workpiece's RMS profile slope {slope:.3g} is outside [{SLOPE_RANGE[0]:g}, "
            f"{SLOPE_RANGE[1]:g}]: check the scan's lateral size and height unit"
        )
    if model == LIMIT_MODEL and not LIMIT_SLOPE_RANGE[0] <= slope <= LIMIT_SLOPE_RANGE[1]:
        raise ValueError(
            f"the workpiece's RMS profile slope {slope:.3g} is outside the two-state law's table "
            f"[{LIMIT_SLOPE_RANGE[0]:g}, {LIMIT_SLOPE_RANGE[1]:g}]: calibrate the one-state "
            "model (layer-yield) for this surface"
        )
    edges = edge_slope_table(wp) if model == LIMIT_MODEL else None
    block = Flattening(slope=slope, model=model, edge_slope=edges)
    p, a = cal.sweeps.loading
    p_patch = _alpha_pressure(P, PATCH_ALPHA, float(p.min()) * 1e-3, 0.99 * scene.H)
    res = solve_normal_pair(
        np.asarray(wp.heights),
        np.asarray(tl.heights),
        wp.dx,
        scene.E_star,
        p_patch,
        volume_conservation=scene.volume_conservation,
        H=scene.H,
        dy=wp.dy,
        **scene.solver.normal_kwargs(),
    )
    l_patch, n_patch = patch_half_spacing(res.pressure, wp.dx, wp.dy, scene.periodic)
    record = {
        "model": _MODEL_TEXT[model],
        "slope": slope,
        "slope_x": sx,
        "slope_y": sy,
        "slope_half_grid": _half_grid_slope(wp),
        "slope_source": (
            "RMS profile slope of the workpiece on the solver grid "
            f"({wp.shape[0]} x {wp.shape[1]}, element {wp.dx:.4g} m), quadratic mean of x and y"
        ),
        "edge_slope_source": None
        if edges is None
        else (
            f"the workpiece's edge slope at {EDGE_POINTS} contact fractions: the mean |dz/dx| of "
            "the x and of the y profiles where their bearing level crosses them (binned over "
            "the fractions, their quadratic mean); the flank slope the two-state law reads"
        ),
        "zero_strain_hardness": {
            "source": "the computed first loading: p / alpha of the half-space model; the law's "
            "alpha1 (fitted to it) is what the model reads",
            "p_Pa": p.tolist(),
            "p_over_alpha_Pa": (p / a).tolist(),
            "law_small_p_Pa": P.H / P.C1,
        },
        "half_spacing": {
            "from_crossings_m": list(crossing_half_spacing(wp)),
            "from_patches_m": l_patch,
            "patches": n_patch,
            "patch_pressure_Pa": p_patch,
            "patch_solve_converged": bool(res.converged),
            "note": "information for the FE asperity model; the model does not use it (l cancels)",
        },
        "beta": 1.0,
        "beta_source": "default: the rates of "
        + ("the table" if model == LIMIT_MODEL else "Eq. F2")
        + " unscaled",
        "fit": None,
        "problem": None
        if res.converged
        else f"the patch-count solve did not converge: {res.message}",
    }
    if data is not None:
        try:
            fit = fit_beta(P.replace(flattening=block), data)
        except ValueError as exc:  # a measurement the model cannot describe: the run fails
            why = f"the fit of beta to {data.path} failed: {exc}"
            record["problem"] = "; ".join(filter(None, (record["problem"], why)))
        else:
            block = dataclasses.replace(
                block, beta=fit["beta"], beta_band=tuple(fit["band"]), band_level=fit["level"]
            )
            record["beta"] = fit["beta"]
            record["beta_source"] = f"fitted to {fit['points']} measured points of {data.path}"
            record["fit"] = fit
    Pf = P.replace(flattening=block)
    table = {}
    for f in TABLE_P:
        table[f"{f:g}H"] = flattening_curve(f * scene.H, np.array((0.0, *TABLE_EPS)), Pf).tolist()
    record["table"] = {"strains": [0.0, *TABLE_EPS], "alpha_at_p_over_H": table}
    record["full_contact"] = {"p_over_H": 0.3, "strain": _full_contact_strain(Pf, 0.3 * scene.H)}
    return block, record
