"""Rough surfaces for the half-space model (Sec. 3.1): read, generate, prepare, characterise.

A :class:`Surface` holds heights in m on a regular grid, ``heights[i, j]`` at
``x = i dx``, ``y = j dy`` (axis 0 is ``x``), and a provenance dict (file path and
SHA-256, or generator settings, plus every preparation step) that the calibration
writes into the parameter file.

Roughness parameters are the paper's areal ``Ra`` (centre-line average) and ``Rq``
(root mean square) taken about the mean height over the whole map (ISO 25178 calls
them ``Sa``, ``Sq``); level the surface first if it carries a tilt.
"""

import copy
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import fft as sfft
from scipy.optimize import brentq

from . import _io_topography as _io

__all__ = [
    "Surface",
    "Roughness",
    "TABLE1",
    "PAPER_SIZE",
    "RA_RQ_RANGE",
    "read_surface",
    "read_raw",
    "fill_harmonic",
    "write_surface",
    "self_affine",
    "dc04_edt_like",
    "tool_like",
    "level",
    "crop",
    "block_average",
    "roughness",
    "ra",
    "rq",
    "rsk",
    "rku",
    "rms_slope",
    "psd_radial",
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


def _positive(name, v):
    try:
        f = float(v)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number > 0, got {v!r}") from None
    if not (math.isfinite(f) and f > 0):
        raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
    return f


def _pair(name, v, conv):
    """``v`` or ``(v, v)`` as a validated pair."""
    if np.ndim(v) == 0:
        a = conv(name, v)
        return a, a
    vals = list(v)
    if len(vals) != 2:
        raise ValueError(f"{name} must be a scalar or a pair (x, y), got {v!r}")
    return conv(name, vals[0]), conv(name, vals[1])


def _count(name, v, lo=2):
    try:
        i = int(v)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an integer >= {lo}, got {v!r}") from None
    if i != v or i < lo:
        raise ValueError(f"{name} must be an integer >= {lo}, got {v!r}")
    return i


@dataclass(frozen=True, eq=False)
class Surface:
    """Height map on a regular grid.

    Parameters
    ----------
    heights : array_like, shape (nx, ny)
        Heights in m, finite, at least 2 x 2; stored as a read-only float64 copy.
    dx, dy : float
        Grid spacing in m along axis 0 (``x``) and axis 1 (``y``).
    provenance : dict
        Where the surface came from: ``{"source": "file", "path", "sha256", ...}`` or
        ``{"source": "generator", ...settings}``, and ``"operations"``, the list of
        preparation steps applied since.
    periodic : bool
        True if the map is one period of a periodic surface (synthetic surfaces).
    """

    heights: np.ndarray
    dx: float
    dy: float
    provenance: dict = field(default_factory=dict)
    periodic: bool = False

    def __post_init__(self):
        h = np.array(self.heights, dtype=np.float64, copy=True)
        if h.ndim != 2 or min(h.shape) < 2:
            raise ValueError(
                f"heights must be a 2-D array with at least 2 x 2 points, got shape {h.shape}"
            )
        bad = int(np.count_nonzero(~np.isfinite(h)))
        if bad:
            raise ValueError(f"heights must be finite; {bad} values are NaN or infinite")
        h.setflags(write=False)
        object.__setattr__(self, "heights", h)
        object.__setattr__(self, "dx", _positive("dx", self.dx))
        object.__setattr__(self, "dy", _positive("dy", self.dy))
        if not isinstance(self.provenance, dict):
            raise ValueError("provenance must be a dict")
        object.__setattr__(self, "provenance", copy.deepcopy(self.provenance))
        object.__setattr__(self, "periodic", bool(self.periodic))

    @property
    def shape(self):
        """Grid points ``(nx, ny)``."""
        return self.heights.shape

    @property
    def size(self):
        """Physical size ``(Lx, Ly) = (nx dx, ny dy)`` in m."""
        return self.shape[0] * self.dx, self.shape[1] * self.dy

    @property
    def x(self):
        """Coordinates of the grid points along axis 0 (m)."""
        return np.arange(self.shape[0]) * self.dx

    @property
    def y(self):
        """Coordinates of the grid points along axis 1 (m)."""
        return np.arange(self.shape[1]) * self.dy

    def derive(self, heights, operation, **changes):
        """New surface with ``heights``, ``operation`` appended to the provenance."""
        prov = copy.deepcopy(self.provenance)
        prov.setdefault("operations", []).append(operation)
        kw = {"dx": self.dx, "dy": self.dy, "periodic": self.periodic}
        kw.update(changes)
        return Surface(heights, provenance=prov, **kw)

    def roughness(self):
        """:class:`Roughness` of this surface."""
        return roughness(self)


# -- files ----------------------------------------------------------------------------


def read_surface(
    path,
    *,
    unit=None,
    dx=None,
    dy=None,
    size=None,
    xy_unit=None,
    layout=None,
    fill_undefined=False,
):
    """Read a measured topography.

    Parameters
    ----------
    path : path-like
        ``.npy`` (2-D array), ``.txt``/``.csv``/``.dat``/``.asc`` (height matrix,
        whitespace or comma separated, row ``i`` -> ``x_i``; a binary file with one of
        these suffixes, e.g. a Zygo MetroPro ``.dat``, goes to the instrument readers),
        ``.xyz`` (``x y z`` point list, gridded onto its regular grid), or any instrument
        format that SurfaceTopography reads (``.vk4``, ``.vk6``, ``.x3p``, ``.sur``,
        ``.datx``, ``.plu``, ...; needs the ``topography`` extra).
    unit : str
        Unit of the heights in the file: ``m``, ``mm``, ``um`` (``µm``) or ``nm``.
        Required for plain files unless a text matrix names it in its header
        (``# Value units: m``); for instrument files only if the file has none.
    dx, dy : float, optional
        Grid spacing in m (``dy`` defaults to ``dx``). Plain matrices need ``dx`` or
        ``size`` unless a text matrix gives ``# Width:`` and ``# Height:`` in its header;
        point lists and calibrated instrument files carry their own.
    size : float or (float, float), optional
        Physical size ``(Lx, Ly)`` in m instead of ``dx``, ``dy``.
    xy_unit : str, optional
        Unit of the ``x``, ``y`` columns of a point list (defaults to ``unit``).
    layout : {"npy", "matrix", "xyz", "instrument"}, optional
        Override the layout chosen from the file (:func:`._io_topography.layout_for`).
    fill_undefined : bool
        Fill undefined (unmeasured, NaN) points with :func:`fill_harmonic`; otherwise
        such files are refused.

    Returns
    -------
    Surface
        Non-periodic, with provenance ``{"source": "file", "path", "sha256", ...}``.

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        For a file that cannot be read in its layout, missing units or spacing, or
        points that are not gridded.
    ImportError
        For an instrument format when SurfaceTopography is not installed (the
        message names the ``topography`` extra).
    """
    h, fdx, fdy, prov = read_raw(
        path, unit=unit, dx=dx, dy=dy, size=size, xy_unit=xy_unit, layout=layout
    )
    bad = int(np.count_nonzero(np.isnan(h)))
    if bad:
        if not fill_undefined:
            raise ValueError(
                f"{path}: the topography has {bad} undefined (unmeasured) points; pass "
                "fill_undefined=True to interpolate them, or crop them away"
            )
        h = fill_harmonic(h)
    prov["undefined_points"] = bad
    prov["filled_undefined"] = bool(bad)
    return Surface(h, fdx, fdy, provenance=prov, periodic=False)


def read_raw(path, *, unit=None, dx=None, dy=None, size=None, xy_unit=None, layout=None):
    """Heights of a topography file with undefined points kept as NaN.

    The reading half of :func:`read_surface` (same parameters but ``fill_undefined``):
    returns ``(heights, dx, dy, provenance)`` with heights in m (NaN where the instrument
    measured nothing), spacings in m and the provenance dict (``path``, ``sha256``,
    ``layout``, ``format``, ``unit`` and where it came from, ``shape``, ``dx``, ``dy``).
    """
    path = Path(path)
    layouts = ("npy", "matrix", "xyz", "instrument")
    if layout is not None and layout not in layouts:
        raise ValueError(f"layout must be one of {layouts}, got {layout!r}")
    if not path.is_file():
        raise FileNotFoundError(f"surface file not found: {path}")
    if layout is None:
        layout = _io.layout_for(path)
    if size is not None and (dx is not None or dy is not None):
        raise ValueError("give either size or dx (and dy), not both")
    header = _io.matrix_header(path) if layout == "matrix" else {}
    unit_source = "option"
    if "unit" in header:
        if unit is not None and _io.unit_factor(unit) != _io.UNITS[header["unit"]]:
            raise ValueError(
                f"{path}: unit={unit!r} contradicts the file's header unit "
                f"{header['unit']!r}; leave unit unset"
            )
        unit, unit_source = header["unit"], "file header"
    if "size" in header:
        if size is not None or dx is not None or dy is not None:
            raise ValueError(
                f"{path}: the file's header gives its size "
                f"{header['size'][0]:g} x {header['size'][1]:g} m; do not pass dx, dy or size"
            )
        size = header["size"]
    if layout in ("npy", "matrix"):
        _io.unit_factor(unit)
        if dx is None and size is None:
            raise ValueError(f"{path}: the file has no lateral calibration; pass dx or size (m)")
    info = {}
    if layout == "npy":
        h = _io.load_npy(path, unit, allow_undefined=True)
        fdx = fdy = None
    elif layout == "matrix":
        h = _io.load_matrix(path, unit, allow_undefined=True)
        fdx = fdy = None
    elif layout == "xyz":
        if dx is not None or dy is not None or size is not None:
            raise ValueError("dx, dy and size come from the x, y columns of a point list")
        h, fdx, fdy = _io.load_xyz(path, unit, xy_unit)
    else:
        h, fdx, fdy, info = _io.load_instrument(path, unit, keep_undefined=True)
        if fdx is not None and (dx is not None or dy is not None or size is not None):
            raise ValueError(
                f"{path}: the file carries its lateral calibration; do not pass dx, dy or size"
            )
        if info.get("file_unit") is not None:
            unit, unit_source = info["file_unit"], "file"
    if fdx is None:
        if size is not None:
            lx, ly = _pair("size", size, _positive)
            fdx, fdy = lx / h.shape[0], ly / h.shape[1]
            size_source = "file header" if "size" in header else "option"
        elif dx is not None:
            fdx = _positive("dx", dx)
            fdy = fdx if dy is None else _positive("dy", dy)
            size_source = "option"
        else:
            raise ValueError(f"{path}: the file has no lateral calibration; pass dx or size (m)")
    else:
        size_source = "file"
    prov = {
        "source": "file",
        "path": str(path.resolve()),
        "sha256": _io.file_sha256(path),
        "layout": layout,
        "format": info.get(
            "format", {"npy": "NumPy .npy", "matrix": "text matrix"}.get(layout, "x y z point list")
        ),
        "unit": unit,
        "unit_source": unit_source,
        "size_source": size_source,
        "shape": list(h.shape),
        "dx": fdx,
        "dy": fdy,
    }
    prov.update({k: v for k, v in info.items() if k not in ("format", "filled_undefined")})
    return h, fdx, fdy, prov


def fill_harmonic(heights):
    """Fill the NaN points of a height map with the harmonic (Laplace) interpolant.

    Each undefined point gets the mean of its 4 neighbours (fewer on the border), defined
    neighbours fixed: the discrete Laplace equation on the holes, with the measured rim
    as boundary values (the method SurfaceTopography's ``interpolate_undefined_data``
    uses). A plane is reproduced exactly; a hole gets no extremum of its own.

    Parameters
    ----------
    heights : ndarray, shape (nx, ny)
        Heights with NaN at the undefined points; at least one defined point.

    Returns
    -------
    ndarray
        A finite copy.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.linalg import spsolve

    h = np.array(heights, dtype=np.float64, copy=True)
    hole = np.isnan(h)
    n = int(hole.sum())
    if n == 0:
        return h
    if n == h.size:
        raise ValueError("every height is undefined: nothing to interpolate from")
    idx = -np.ones(h.shape, dtype=np.int64)
    idx[hole] = np.arange(n)
    rows, cols, vals = [], [], []
    diag = np.zeros(n)
    rhs = np.zeros(n)
    nx, ny = h.shape
    ii, jj = np.nonzero(hole)
    me = idx[ii, jj]
    for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        ni, nj = ii + di, jj + dj
        inside = (ni >= 0) & (ni < nx) & (nj >= 0) & (nj < ny)
        src, ni, nj = me[inside], ni[inside], nj[inside]
        diag[src] += 1.0
        other = idx[ni, nj]
        unk = other >= 0
        rows.append(src[unk])
        cols.append(other[unk])
        vals.append(-np.ones(int(unk.sum())))
        np.add.at(rhs, src[~unk], h[ni[~unk], nj[~unk]])
    rows.append(np.arange(n))
    cols.append(np.arange(n))
    vals.append(diag)
    a = coo_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    ).tocsr()
    h[hole] = spsolve(a, rhs)
    return h


def write_surface(surface, path, unit="um"):
    """Write ``surface`` as ``.npy``, a text matrix (``.txt``, ``.csv``, ...) or ``.xyz``.

    Heights (and, for ``.xyz``, coordinates) are written in ``unit``. Read back with
    :func:`read_surface` and the same ``unit`` (plus ``dx``/``size`` except for ``.xyz``).
    """
    return _io.write_plain(surface.heights, surface.dx, surface.dy, path, unit)


# -- roughness ------------------------------------------------------------------------


def _h(surface):
    if isinstance(surface, Surface):
        return surface.heights
    h = np.asarray(surface, dtype=np.float64)
    if h.ndim != 2 or h.size < 4 or not np.isfinite(h).all():
        raise ValueError("surface must be a Surface or a finite 2-D array of heights")
    return h


def ra(surface):
    """Centre-line average ``Ra = mean |h - mean(h)|`` (m)."""
    h = _h(surface)
    return float(np.mean(np.abs(h - h.mean())))


def rq(surface):
    """Root mean square roughness ``Rq = sqrt(mean (h - mean(h))^2)`` (m)."""
    h = _h(surface)
    return float(np.sqrt(np.mean((h - h.mean()) ** 2)))


def _moment(surface, k, name):
    h = _h(surface)
    z = h - h.mean()
    s = np.sqrt(np.mean(z**2))
    if s == 0.0 or s <= 1e-14 * np.abs(h).max():
        raise ValueError(f"{name} is undefined for a flat surface (Rq = 0)")
    return float(np.mean((z / s) ** k))


def rsk(surface):
    """Skewness ``Rsk = mean(z^3) / Rq^3`` (``ValueError`` for a flat surface)."""
    return _moment(surface, 3, "Rsk")


def rku(surface):
    """Kurtosis ``Rku = mean(z^4) / Rq^4`` (3 for a Gaussian; ``ValueError`` if flat)."""
    return _moment(surface, 4, "Rku")


def rms_slope(surface):
    """Root mean square slope ``sqrt(mean |grad h|^2)`` (dimensionless).

    Central differences; periodic surfaces wrap around, others use one-sided
    differences at the edges (:func:`numpy.gradient`).
    """
    if not isinstance(surface, Surface):
        raise ValueError("rms_slope needs a Surface (the grid spacing matters)")
    h = surface.heights
    if surface.periodic:
        gx = (np.roll(h, -1, 0) - np.roll(h, 1, 0)) / (2 * surface.dx)
        gy = (np.roll(h, -1, 1) - np.roll(h, 1, 1)) / (2 * surface.dy)
    else:
        gx, gy = np.gradient(h, surface.dx, surface.dy)
    return float(np.sqrt(np.mean(gx**2 + gy**2)))


@dataclass(frozen=True)
class Roughness:
    """Areal roughness parameters (m, except the dimensionless ``Rsk``, ``Rku``, ``Rdq``).

    ``Rsk`` and ``Rku`` are ``None`` for a flat surface, where they are undefined.
    """

    Ra: float
    Rq: float
    Rsk: float | None
    Rku: float | None
    Rdq: float

    def as_dict(self):
        """Plain dict (for CSV rows and the provenance)."""
        return {"Ra": self.Ra, "Rq": self.Rq, "Rsk": self.Rsk, "Rku": self.Rku, "Rdq": self.Rdq}


def roughness(surface):
    """``Ra``, ``Rq``, ``Rsk``, ``Rku`` and the rms slope ``Rdq`` of a :class:`Surface`."""
    q = rq(surface)
    try:
        sk, ku = rsk(surface), rku(surface)
    except ValueError:
        sk = ku = None
    return Roughness(Ra=ra(surface), Rq=q, Rsk=sk, Rku=ku, Rdq=rms_slope(surface))


def psd_radial(surface, nbins=32):
    """Radially averaged 2-D power spectral density ``C(q)``.

    Normalised so that ``sum C(q) dqx dqy / (2 pi)^2 = Rq^2`` over the full
    spectrum (Parseval); a self-affine surface has ``C ~ q^(-2 - 2 H)``.

    Returns
    -------
    q, C : ndarray
        Bin centres (rad/m, logarithmic bins from the smallest non-zero wavenumber
        to the Nyquist wavenumber) and the mean PSD in each non-empty bin (m^4).
    """
    nbins = _count("nbins", nbins, 2)
    h = surface.heights - surface.heights.mean()
    nx, ny = h.shape
    c = np.abs(sfft.fft2(h)) ** 2 * surface.dx * surface.dy / (nx * ny)
    qx = 2 * np.pi * sfft.fftfreq(nx, surface.dx)
    qy = 2 * np.pi * sfft.fftfreq(ny, surface.dy)
    q = np.hypot(qx[:, None], qy[None, :])
    qmin = 2 * np.pi / max(surface.size)
    qmax = np.pi / max(surface.dx, surface.dy)
    edges = np.geomspace(qmin, qmax, nbins + 1)
    which = np.digitize(q.ravel(), edges) - 1
    ok = (which >= 0) & (which < nbins) & (q.ravel() > 0)
    sums = np.bincount(which[ok], weights=c.ravel()[ok], minlength=nbins)
    counts = np.bincount(which[ok], minlength=nbins)
    keep = counts > 0
    centres = np.sqrt(edges[:-1] * edges[1:])
    return centres[keep], sums[keep] / counts[keep]


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
    r_a = None if ra_target is None else _positive("ra", ra_target)
    r_q = None if rq_target is None else _positive("rq", rq_target)
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
    nx, ny = _pair("shape", shape, _count)
    lx, ly = _pair("size", size, _positive)
    try:
        hu = float(hurst)
    except (TypeError, ValueError):
        hu = math.nan
    if not (0.0 < hu <= 1.0):
        raise ValueError(f"hurst must be in (0, 1], got {hurst!r}")
    lmax = max(lx, ly)
    nyq = 2 * max(lx / nx, ly / ny)
    lr = lmax if rolloff_wavelength is None else _positive("rolloff_wavelength", rolloff_wavelength)
    ls = nyq if cutoff_wavelength is None else _positive("cutoff_wavelength", cutoff_wavelength)
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
    seed = _count("seed", seed, 0)
    h, info = _impose(_gaussian_field(shp, sz, hu, lr, ls, seed), r_a, r_q)
    prov = {
        "source": "generator",
        "generator": "halfspace_calib.surfaces.self_affine",
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
    n = _count("n", n, 2)
    size = _positive("size", size)
    if match not in ("both", "rq", "ra"):
        raise ValueError(f"match must be 'both', 'rq' or 'ra', got {match!r}")
    target = dict(TABLE1[kind])
    if match == "rq":
        target["Ra"] = None
    elif match == "ra":
        target["Rq"] = None
    m = n if measured_n is None else _count("measured_n", measured_n, 2)
    if m % n:
        raise ValueError(f"measured_n must be a multiple of n={n}, got {measured_n!r}")
    seed = _count("seed", seed, 0)
    # a grid too coarse for the roll-off gives band-limited white noise (strict=False)
    shp, sz, hu, lr, ls = _spectrum_settings(m, size, hurst, rolloff, None, strict=False)
    h = _gaussian_field(shp, sz, hu, lr, ls, seed)
    if m > n:
        s = m // n
        h = h.reshape(n, s, n, s).mean(axis=(1, 3))
    h, info = _impose(h, target["Ra"], target["Rq"])
    prov = {
        "source": "generator",
        "generator": "halfspace_calib.surfaces.dc04_edt_like/tool_like",
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


# -- preparation ----------------------------------------------------------------------


def level(surface):
    """Remove the least-squares plane ``a + b x + c y`` (the result is not periodic)."""
    h = surface.heights
    x, y = np.meshgrid(surface.x, surface.y, indexing="ij")
    xc, yc = x - x.mean(), y - y.mean()
    a_mat = np.column_stack([np.ones(h.size), xc.ravel(), yc.ravel()])
    coef, *_ = np.linalg.lstsq(a_mat, h.ravel(), rcond=None)
    out = h - (coef[0] + coef[1] * xc + coef[2] * yc)
    op = {
        "op": "level",
        "mean": float(coef[0]),
        "slope_x": float(coef[1]),
        "slope_y": float(coef[2]),
    }
    return surface.derive(out, op, periodic=False)


def crop(surface, shape, origin=(0, 0)):
    """Window of ``shape`` grid points starting at index ``origin``."""
    nx, ny = surface.shape
    cx, cy = _pair("shape", shape, _count)
    i0, j0 = _pair("origin", origin, lambda n, v: _count(n, v, 0))
    if i0 + cx > nx or j0 + cy > ny:
        raise ValueError(
            f"origin + shape = ({i0 + cx}, {j0 + cy}) exceeds the surface's shape {(nx, ny)}"
        )
    out = surface.heights[i0 : i0 + cx, j0 : j0 + cy]
    whole = (cx, cy) == (nx, ny)
    op = {"op": "crop", "origin": [i0, j0], "shape": [cx, cy]}
    return surface.derive(out, op, periodic=surface.periodic and whole)


def block_average(surface, shape, *, trim=False):
    """Coarsen to ``shape``: each element is the mean of the ``s`` points it covers (Sec. 3.1).

    Parameters
    ----------
    surface : Surface
    shape : int or (int, int)
        Solver grid ``(Nx, Ny)``; each must divide the surface's grid.
    trim : bool
        If the grid does not divide, drop the remainder rows/columns evenly from both
        ends first (recorded as a crop) instead of raising.
    """
    nx, ny = surface.shape
    cx, cy = _pair("shape", shape, lambda n, v: _count(n, v, 1))
    if cx > nx or cy > ny:
        raise ValueError(f"shape {(cx, cy)} must not exceed the surface's shape {(nx, ny)}")
    if nx % cx or ny % cy:
        if not trim:
            raise ValueError(
                f"shape {(cx, cy)} must divide the surface's shape {(nx, ny)}; crop first or "
                "pass trim=True"
            )
        mx, my = (nx // cx) * cx, (ny // cy) * cy
        surface = crop(surface, (mx, my), ((nx - mx) // 2, (ny - my) // 2))
        nx, ny = mx, my
    sx, sy = nx // cx, ny // cy
    out = surface.heights.reshape(cx, sx, cy, sy).mean(axis=(1, 3))
    op = {"op": "block_average", "shape": [cx, cy], "points_per_element": sx * sy}
    return surface.derive(out, op, dx=surface.dx * sx, dy=surface.dy * sy)
