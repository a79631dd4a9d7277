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
from dataclasses import dataclass, field

import numpy as np
from scipy import fft as sfft

from ..common.checks import count, pair, positive

__all__ = [
    "Surface",
    "Roughness",
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
        object.__setattr__(self, "dx", positive("dx", self.dx))
        object.__setattr__(self, "dy", positive("dy", self.dy))
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
    nbins = count("nbins", nbins, 2)
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
    cx, cy = pair("shape", shape, count)
    i0, j0 = pair("origin", origin, lambda n, v: count(n, v, 0))
    if i0 + cx > nx or j0 + cy > ny:
        raise ValueError(
            f"origin + shape = ({i0 + cx}, {j0 + cy}) exceeds the surface's shape {(nx, ny)}"
        )
    out = surface.heights[i0 : i0 + cx, j0 : j0 + cy]
    whole = (cx, cy) == (nx, ny)
    op = {"op": "crop", "origin": [i0, j0], "shape": [cx, cy]}
    return surface.derive(out, op, periodic=surface.periodic and whole)


def block_average(surface, shape, *, trim=False):
    """Coarsen to ``shape``: each element is the mean of the ``s`` points it covers.

    This is the coarsening of the paper's Sec. 3.1.

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
    cx, cy = pair("shape", shape, lambda n, v: count(n, v, 1))
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
