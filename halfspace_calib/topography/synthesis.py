"""Synthetic self-affine surfaces (Sec. 3.1): the generator and the paper's presets (Table 1)."""

import math

import numpy as np
from scipy import fft as sfft
from scipy.optimize import brentq

from ..common.checks import count, pair, positive
from .surface import Surface, block_average, ra, rq

__all__ = [
    "TABLE1",
    "PAPER_SIZE",
    "RA_RQ_RANGE",
    "self_affine",
    "dc04_edt_like",
    "tool_like",
    "measured_surfaces",
]


#: Table 1 of the paper: areal roughness of the simulated surfaces (m)
TABLE1 = {
    "workpiece": {"Ra": 1.034e-6, "Rq": 1.267e-6},
    "tool": {"Ra": 0.102e-6, "Rq": 0.160e-6},
    "rough_tool": {"Ra": 0.240e-6, "Rq": 0.303e-6},
}

#: side of the paper's square surface portion (m), Sec. 3.1
PAPER_SIZE = 2.11e-3

#: Ra/Rq ratios that :func:`self_affine` reaches by reshaping the height distribution
RA_RQ_RANGE = (0.5, 0.95)


# -- synthetic surfaces ---------------------------------------------------------------


def _gaussian_field(shape, size, hurst, rolloff_wavelength, cutoff_wavelength, seed):
    """Zero-mean periodic Gaussian field with a self-affine PSD (unscaled)."""
    nx, ny = shape
    lx, ly = size
    dx, dy = lx / nx, ly / ny
    qx = 2 * np.pi * sfft.fftfreq(nx, dx)
    qy = 2 * np.pi * sfft.rfftfreq(ny, dy)
    q = np.hypot(qx[:, None], qy[None, :])
    qr = 2 * np.pi / rolloff_wavelength
    qs = 2 * np.pi / cutoff_wavelength
    expo = -1.0 - hurst  # amplitude ~ sqrt(C) ~ q^(-1 - H)
    amp = np.empty_like(q)
    low = q < qr
    amp[low] = qr**expo
    amp[~low] = q[~low] ** expo
    amp[q > qs * (1 + 1e-12)] = 0.0
    amp[0, 0] = 0.0
    rng = np.random.default_rng(seed)
    white = rng.standard_normal((nx, ny))
    return sfft.irfft2(sfft.rfft2(white) * amp, s=(nx, ny))


def _transform(z, s):
    """Monotone height map, the identity at ``s = 0``.

    ``s > 0``: deeper valleys, ``z -> -expm1(-s z) / s`` for ``z < 0`` (peaks kept): a
    heavy lower tail (``Rsk < 0``, ``Rku > 3``) as on polished tools with pits and
    scratches. ``s < 0``: lighter tails on both sides, ``tanh(|s| z) / |s|``.
    """
    if s > 0:
        return np.where(z < 0, -np.expm1(-s * np.minimum(z, 0.0)) / s, z)
    if s < 0:
        return np.tanh(-s * z) / -s
    return z


def _ratio(h):
    z = h - h.mean()
    z = z / np.abs(z).max()  # scale-free; keeps z**2 finite after a strong map
    return np.mean(np.abs(z)) / np.sqrt(np.mean(z**2))


def _shape_ra_rq(h, target):
    """Find ``s`` so that ``transform(h, s)`` has ``Ra / Rq = target``; return both."""
    z = (h - h.mean()) / np.sqrt(np.mean((h - h.mean()) ** 2))
    zmax = np.abs(z).max()

    def f(s):
        return _ratio(_transform(z, s)) - target

    f0 = f(0.0)
    if f0 == 0.0:
        return z, 0.0
    sign = 1.0 if f0 > 0 else -1.0  # ratio too high -> heavier tails (s > 0)
    s_lim = 300.0 / zmax  # expm1 stays far from overflow
    lo, hi = 0.0, sign * min(0.5, s_lim)
    while f(hi) * f0 > 0:
        if abs(hi) >= s_lim:
            raise ValueError(
                f"Ra/Rq = {target:.4g} cannot be reached from this field "
                f"(a Gaussian surface has about 0.798)"
            )
        lo, hi = hi, sign * min(2 * abs(hi), s_lim)
    a, b = sorted((lo, hi))
    s = brentq(f, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=500)
    return _transform(z, s), s


def _impose(h, ra_target, rq_target):
    """Scale (and, if both targets are given, reshape) ``h``; returns heights and info."""
    h = h - h.mean()
    info = {"height_transform": 0.0}
    if ra_target is not None and rq_target is not None:
        h, s = _shape_ra_rq(h, ra_target / rq_target)
        h = h - h.mean()
        info["height_transform"] = s
    if rq_target is not None:
        h = h * (rq_target / rq(h))
    else:
        h = h * (ra_target / ra(h))
    return h, info


def _check_targets(ra_target, rq_target):
    if ra_target is None and rq_target is None:
        raise ValueError("give rq and/or ra (m), the target roughness")
    r_a = None if ra_target is None else positive("ra", ra_target)
    r_q = None if rq_target is None else positive("rq", rq_target)
    if r_a is not None and r_q is not None:
        lo, hi = RA_RQ_RANGE
        if not r_a < r_q:
            raise ValueError(f"ra must be < rq (Ra <= Rq always), got ra={r_a!r}, rq={r_q!r}")
        if not lo <= r_a / r_q <= hi:
            raise ValueError(
                f"Ra/Rq must be in [{lo}, {hi}] when both are given (a Gaussian surface has "
                f"0.798; beyond this range the heights degenerate into isolated pits or two "
                f"levels), got {r_a / r_q:.4g}"
            )
    return r_a, r_q


def _spectrum_settings(shape, size, hurst, rolloff_wavelength, cutoff_wavelength, strict=True):
    nx, ny = pair("shape", shape, count)
    lx, ly = pair("size", size, positive)
    try:
        hu = float(hurst)
    except (TypeError, ValueError):
        hu = math.nan
    if not (0.0 < hu <= 1.0):
        raise ValueError(f"hurst must be in (0, 1], got {hurst!r}")
    lmax = max(lx, ly)
    nyq = 2 * max(lx / nx, ly / ny)
    lr = lmax if rolloff_wavelength is None else positive("rolloff_wavelength", rolloff_wavelength)
    ls = nyq if cutoff_wavelength is None else positive("cutoff_wavelength", cutoff_wavelength)
    if not nyq <= ls * (1 + 1e-12):
        raise ValueError(
            f"cutoff_wavelength must be >= 2 * grid spacing = {nyq:g} m (Nyquist), got {ls!r}"
        )
    if strict and not ls < lr:
        raise ValueError(f"rolloff_wavelength ({lr:g} m) must exceed cutoff_wavelength ({ls:g} m)")
    return (nx, ny), (lx, ly), hu, lr, ls


def self_affine(
    shape,
    size,
    *,
    hurst=0.8,
    rolloff_wavelength=None,
    cutoff_wavelength=None,
    rq=None,
    ra=None,
    seed=0,
):
    """Periodic self-affine random surface (FFT-filtered Gaussian noise).

    The power spectrum is ``C(q) ~ q^(-2 - 2 H)`` between the roll-off wavenumber
    ``2 pi / rolloff_wavelength`` (flat below) and the cut-off ``2 pi /
    cutoff_wavelength`` (zero above); white noise from ``numpy.random.default_rng(seed)``
    is filtered by ``sqrt(C)``, so a seed always gives the same surface.

    Parameters
    ----------
    shape : int or (int, int)
        Grid points ``(nx, ny)``.
    size : float or (float, float)
        Physical size ``(Lx, Ly)`` in m.
    hurst : float
        Hurst exponent ``H`` in ``(0, 1]``.
    rolloff_wavelength, cutoff_wavelength : float, optional
        In m; default: the surface size (no roll-off) and twice the grid spacing
        (Nyquist).
    rq, ra : float, optional
        Target roughness in m. With one target the Gaussian field is scaled to hit
        it exactly. With both, the heights first pass through a monotone odd map
        (``sinh(s z)/s`` for heavier tails, ``tanh(s z)/s`` for lighter ones, ``s``
        found by root finding) so that ``Ra/Rq`` matches, then are scaled: both hit
        to rounding, at the price of a non-Gaussian height distribution (the map also
        moves some power to higher wavenumbers; see ``docs/surfaces_and_fit.md``).
    seed : int
        Seed of the random generator.

    Returns
    -------
    Surface
        Periodic, with the generator settings in its provenance.
    """
    r_a, r_q = _check_targets(ra, rq)
    shp, sz, hu, lr, ls = _spectrum_settings(
        shape, size, hurst, rolloff_wavelength, cutoff_wavelength
    )
    seed = count("seed", seed, 0)
    h, info = _impose(_gaussian_field(shp, sz, hu, lr, ls, seed), r_a, r_q)
    prov = {
        "source": "generator",
        "generator": "halfspace_calib.topography.self_affine",
        "shape": list(shp),
        "size": list(sz),
        "hurst": hu,
        "rolloff_wavelength": lr,
        "cutoff_wavelength": ls,
        "rq": r_q,
        "ra": r_a,
        "seed": seed,
        **info,
    }
    return Surface(h, sz[0] / shp[0], sz[1] / shp[1], provenance=prov, periodic=True)


def _preset(name, kind, n, size, seed, measured_n, hurst, rolloff, match):
    n = count("n", n, 2)
    size = positive("size", size)
    if match not in ("both", "rq", "ra"):
        raise ValueError(f"match must be 'both', 'rq' or 'ra', got {match!r}")
    target = dict(TABLE1[kind])
    if match == "rq":
        target["Ra"] = None
    elif match == "ra":
        target["Rq"] = None
    m = n if measured_n is None else count("measured_n", measured_n, 2)
    if m % n:
        raise ValueError(f"measured_n must be a multiple of n={n}, got {measured_n!r}")
    seed = count("seed", seed, 0)
    # a grid too coarse for the roll-off gives band-limited white noise (strict=False)
    shp, sz, hu, lr, ls = _spectrum_settings(m, size, hurst, rolloff, None, strict=False)
    h = _gaussian_field(shp, sz, hu, lr, ls, seed)
    if m > n:
        s = m // n
        h = h.reshape(n, s, n, s).mean(axis=(1, 3))
    h, info = _impose(h, target["Ra"], target["Rq"])
    prov = {
        "source": "generator",
        "generator": "halfspace_calib.topography.dc04_edt_like/tool_like",
        "preset": name,
        "match": match,
        "shape": [n, n],
        "measured_shape": [m, m],
        "size": [size, size],
        "hurst": hu,
        "rolloff_wavelength": lr,
        "cutoff_wavelength": ls,
        "rq": target["Rq"],
        "ra": target["Ra"],
        "seed": seed,
        **info,
    }
    return Surface(h, size / n, size / n, provenance=prov, periodic=True)


def dc04_edt_like(n=128, *, size=PAPER_SIZE, seed=1, measured_n=None, match="both"):
    """Synthetic stand-in for the paper's DC04 EDT sheet (Table 1: Ra 1.034 um, Rq 1.267 um).

    Isotropic self-affine, ``H = 0.8``, roll-off at 100 um (the scale of EDT craters),
    ``match="both"`` (default) hits Ra and Rq (see :func:`self_affine`); ``"rq"`` or
    ``"ra"`` keeps a Gaussian height distribution and hits that one only.
    ``measured_n`` (a multiple of ``n``) generates the field on that finer "measurement"
    grid and block-averages it to ``n`` before the roughness is imposed, so that one
    seed gives the same surface at every solver resolution.
    """
    return _preset("dc04_edt_like", "workpiece", n, size, seed, measured_n, 0.8, 100e-6, match)


def tool_like(n=128, *, rough=False, size=PAPER_SIZE, seed=2, measured_n=None, match="both"):
    """Synthetic stand-in for the paper's hardened tool (Table 1).

    Ra 0.102 um / Rq 0.160 um, or with ``rough=True`` Ra 0.240 um / Rq 0.303 um;
    self-affine with ``H = 0.8`` and a 50 um roll-off. The smooth tool's low
    ``Ra/Rq = 0.64`` means a heavy-tailed (high ``Rku``) height distribution, as on
    ground and polished tools with isolated scratches (``match="both"``; the
    deep-valley map keeps the peaks Gaussian). See :func:`dc04_edt_like` for
    ``measured_n`` and ``match``.
    """
    kind = "rough_tool" if rough else "tool"
    return _preset(
        "tool_like_rough" if rough else "tool_like",
        kind,
        n,
        size,
        seed,
        measured_n,
        0.8,
        50e-6,
        match,
    )


# -- measured maps for the geometric study ---------------------------------------------


def _on_solver_grid(fine, coarse):
    """``fine`` with its block averages replaced by ``coarse``: ``fine - U(B(fine)) + U(coarse)``.

    ``B`` is the block average onto ``coarse``'s grid and ``U`` its piecewise-constant inverse,
    so ``B(result) == coarse`` exactly while every element keeps ``fine``'s points about their
    mean (its patch plane's slopes, Eqs. 19-21, are unchanged: a constant per element moves only
    the plane's height).
    """
    n = coarse.shape[0]
    s = fine.shape[0] // n
    mean = fine.heights.reshape(n, s, n, s).mean(axis=(1, 3))
    step = np.repeat(np.repeat(coarse.heights - mean, s, axis=0), s, axis=1)
    return fine.derive(
        fine.heights + step,
        {"op": "block means set to the solver-grid surface", "solver_shape": [n, n]},
    )


def _measured_map(preset, n, m, ra_target, seed, size, **kw):
    """The fine map whose block average is exactly the solver-grid surface of ``preset``.

    The solver-grid surface is ``preset(n, measured_n=m)`` (the one the sweeps use); the
    sub-element detail is ``preset(m)``'s (Table 1's height distribution on the measured grid),
    scaled so that its block averages would carry Table 1's ``Ra``.
    """
    coarse = preset(n, size=size, seed=seed, measured_n=m, **kw)
    fine = preset(m, size=size, seed=seed, **kw)
    c = ra_target / ra(block_average(fine, n))
    fine = fine.derive(
        fine.heights * c,
        {"op": "scale", "factor": float(c), "reason": "Table 1 Ra on the solver grid"},
    )
    return _on_solver_grid(fine, coarse)


def measured_surfaces(
    n=128,
    block=4,
    *,
    rough_tool=False,
    seed_workpiece=1,
    seed_tool=2,
    size=PAPER_SIZE,
    roughness_on="solver",
):
    """Synthetic measured DC04-like workpiece and tool on an ``n block`` grid: ``(workpiece, tool)``.

    Parameters
    ----------
    n : int
        Solver grid (elements a side), ``>= 2``.
    block : int
        Measured points per element edge (``s = block^2`` points per element), ``>= 2``.
    rough_tool : bool
        The rough tool (Table 1 ``Ra`` 0.240 um) instead of the smooth one (0.102 um).
    seed_workpiece, seed_tool : int
        Seeds of :func:`~halfspace_calib.topography.dc04_edt_like` and
        :func:`~halfspace_calib.topography.tool_like`.
    size : float
        Edge length in m (default 2.11 mm).
    roughness_on : {"solver", "measured"}
        ``"solver"`` (default): the block averages of the fine maps are exactly the solver-grid
        surfaces the sweeps use (``dc04_edt_like(n, measured_n=n block)``, ``tool_like``
        likewise, Table 1 ``Ra`` and ``Rq`` there: Table 1 lists the simulated surfaces), and
        the points inside each element carry the measured grid's own detail, scaled as if its
        block averages had Table 1's ``Ra``: one random field at both grids.
        ``"measured"``: Table 1 ``Ra`` and ``Rq`` on the fine maps, the solver surfaces smoother.

    Returns
    -------
    (Surface, Surface)
        Fine maps of shape ``(n block, n block)``; the tool's heights positive towards the
        workpiece (as everywhere in the package).
    """
    n = int(n)
    if n < 2:
        raise ValueError(f"n must be an integer >= 2, got {n!r}")
    if not isinstance(block, (int, np.integer)) or block < 2:
        raise ValueError(f"block must be an integer >= 2 (points per element edge), got {block!r}")
    if roughness_on not in ("solver", "measured"):
        raise ValueError(f"roughness_on must be 'solver' or 'measured', got {roughness_on!r}")
    m = n * int(block)
    if roughness_on == "measured":
        wp = dc04_edt_like(m, size=size, seed=seed_workpiece)
        tl = tool_like(m, rough=rough_tool, size=size, seed=seed_tool)
    else:
        tool_ra = TABLE1["rough_tool" if rough_tool else "tool"]["Ra"]
        wp = _measured_map(dc04_edt_like, n, m, TABLE1["workpiece"]["Ra"], seed_workpiece, size)
        tl = _measured_map(tool_like, n, m, tool_ra, seed_tool, size, rough=rough_tool)
    return wp, tl
