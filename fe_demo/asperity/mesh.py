"""Profiles and the structured plane-strain mesh of a strip whose top is a profile.

The strip spans ``0 <= x <= L`` (the apparent length: the profile's length) and
``0 <= z <= D + h(x)``: a mean thickness ``D`` below a levelled profile ``h`` (mean zero). Its
``nx`` columns of elements share the profile's top nodes, spaced evenly in ``x``; its ``nz``
layers are graded so that the top layer's elements are about square and grow geometrically
towards the bottom. Every node of column ``i`` lies on the vertical ``x = x_i``, at the fraction
``s_j`` of the local height ``D + h(x_i)``, so the profile fades linearly to the flat bottom.

The two sides are symmetry planes (the model mirrors the strip about them): a profile need not be
periodic, and a regular profile is modelled from a peak to a valley (:func:`wedge_profile`,
:func:`sine_profile`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sbmf_cli import ParameterError

__all__ = ["StripMesh", "strip_mesh", "wedge_profile", "sine_profile", "check_profile"]


@dataclass(frozen=True)
class StripMesh:
    """A structured quadrilateral mesh of the strip and its node sets.

    Attributes
    ----------
    x : ndarray, shape (n_nodes, 2)
        Node coordinates ``(x, z)`` (m), node ``i (nz + 1) + j`` at column ``i``, layer ``j``.
    t : ndarray of int, shape (4, n_el)
        Connectivity, counter-clockwise in ``(x, z)``.
    nx, nz : int
        Elements along the profile and through the thickness.
    top, bottom, left, right : ndarray of int
        Node sets: the profile (left to right), ``z = 0``, ``x = 0``, ``x = L``.
    length, depth : float
        Apparent length ``L`` and mean thickness ``D`` (m).
    """

    x: np.ndarray
    t: np.ndarray
    nx: int
    nz: int
    top: np.ndarray
    bottom: np.ndarray
    left: np.ndarray
    right: np.ndarray
    length: float
    depth: float

    @property
    def n_elements(self):
        """Number of elements."""
        return self.nx * self.nz


def check_profile(profile_x, profile_z):
    """The profile as float arrays ``(x - x[0], z - mean)``, or ``ParameterError``.

    ``profile_x`` must be finite and strictly increasing (at least 2 points), ``profile_z``
    finite and of the same length. The heights are levelled to mean zero (trapezoidal mean over
    the length).
    """
    px = np.asarray(profile_x, dtype=float)
    pz = np.asarray(profile_z, dtype=float)
    if px.ndim != 1 or px.size < 2:
        raise ParameterError(f"profile_x must be a 1-D array of >= 2 points, got shape {px.shape}")
    if pz.shape != px.shape:
        raise ParameterError(
            f"profile_z must have the shape of profile_x {px.shape}, got {pz.shape}"
        )
    if not (np.isfinite(px).all() and np.isfinite(pz).all()):
        raise ParameterError("profile_x and profile_z must be finite")
    if not (np.diff(px) > 0).all():
        raise ParameterError("profile_x must be strictly increasing")
    px = px - px[0]
    mean = float(np.sum(0.5 * (pz[1:] + pz[:-1]) * np.diff(px)) / px[-1])
    return px, pz - mean


def wedge_profile(slope_deg, spacing, n=2):
    """A regular triangular (wedge) profile from a peak to a valley: ``(x, z)`` in m.

    Parameters
    ----------
    slope_deg : float
        Flank slope ``theta`` (degrees), in ``(0, 45]``.
    spacing : float
        Asperity spacing ``2 l`` (m): peak to peak; the profile is its half, one flank of
        length ``l``, peak at ``x = 0``.
    n : int
        Points of the flank (a straight line needs 2).
    """
    theta = _in_range("slope_deg", slope_deg, 0.0, 45.0, lo_open=True)
    lam = _positive("spacing", spacing)
    x = np.linspace(0.0, lam / 2, max(int(n), 2))
    return x, -math.tan(math.radians(theta)) * x


def sine_profile(amplitude, wavelength, n=257):
    """Half a period of ``amplitude cos(2 pi x / wavelength)``, peak at ``x = 0``: ``(x, z)``."""
    a = _positive("amplitude", amplitude)
    lam = _positive("wavelength", wavelength)
    x = np.linspace(0.0, lam / 2, max(int(n), 3))
    return x, a * np.cos(2 * np.pi * x / lam)


def _positive(name, v):
    v = float(v)
    if not (math.isfinite(v) and v > 0):
        raise ParameterError(f"{name} must be finite and > 0, got {v!r}")
    return v


def _in_range(name, v, lo, hi, lo_open=False):
    v = float(v)
    ok = math.isfinite(v) and (v > lo if lo_open else v >= lo) and v <= hi
    if not ok:
        raise ParameterError(
            f"{name} must be in {'(' if lo_open else '['}{lo:g}, {hi:g}], got {v!r}"
        )
    return v


def _layers(nz, top_height, depth):
    """Fractions ``s_0 = 0 < ... < s_nz = 1`` of the height with a top layer of ``top_height``.

    Geometric growth ``r`` towards the bottom, ``top_height (r^nz - 1)/(r - 1) = depth``;
    uniform layers when ``nz`` top-sized layers already fill the depth.
    """
    if nz * top_height >= depth:
        return np.linspace(0.0, 1.0, nz + 1)
    lo, hi = 1.0, 2.0
    while top_height * (hi**nz - 1) / (hi - 1) < depth:
        hi *= 2.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if top_height * (mid**nz - 1) / (mid - 1) < depth:
            lo = mid
        else:
            hi = mid
    r = 0.5 * (lo + hi)
    h = top_height * r ** np.arange(nz)[::-1]  # bottom layer first
    s = np.concatenate([[0.0], np.cumsum(h)])
    return s / s[-1]


def strip_mesh(profile_x, profile_z, depth, nx, nz):
    """The strip under ``profile`` with ``nx x nz`` elements (see the module docstring).

    Parameters
    ----------
    profile_x, profile_z : array_like
        The profile (m), :func:`check_profile`; linearly interpolated at the ``nx + 1`` top nodes.
    depth : float
        Mean thickness ``D`` (m), ``> 0``; the lowest valley must stay above ``0.1 D``.
    nx, nz : int
        Elements along the profile (``>= 2``) and through the thickness (``>= 2``).
    """
    px, pz = check_profile(profile_x, profile_z)
    d = _positive("depth", depth)
    nx, nz = int(nx), int(nz)
    if nx < 2:
        raise ParameterError(f"nx must be >= 2, got {nx}")
    if nz < 2:
        raise ParameterError(f"nz must be >= 2, got {nz}")
    if d + pz.min() < 0.1 * d:
        raise ParameterError(
            f"depth must exceed the deepest valley ({-pz.min():.3g} m) by 10 %, got {d!r}"
        )
    length = float(px[-1])
    xs = np.linspace(0.0, length, nx + 1)
    h = d + np.interp(xs, px, pz)
    s = _layers(nz, length / nx, d)
    x = np.empty(((nx + 1) * (nz + 1), 2))
    x[:, 0] = np.repeat(xs, nz + 1)
    x[:, 1] = (h[:, None] * s[None, :]).ravel()
    node = np.arange((nx + 1) * (nz + 1)).reshape(nx + 1, nz + 1)
    t = np.stack(
        [
            node[:-1, :-1].ravel(),
            node[1:, :-1].ravel(),
            node[1:, 1:].ravel(),
            node[:-1, 1:].ravel(),
        ]
    )
    return StripMesh(
        x=x,
        t=t,
        nx=nx,
        nz=nz,
        top=node[:, -1].copy(),
        bottom=node[:, 0].copy(),
        left=node[0, :].copy(),
        right=node[-1, :].copy(),
        length=length,
        depth=d,
    )
