"""Numba kernels of a zoned law (private): several laws, one per tool zone, chosen per node.

A :class:`frictionlaw.zones.ZonedLaw` packs its laws as one coefficient array: law ``z`` is
``coeffs[offsets[z]:offsets[z + 1]]`` with the law code ``codes[z]`` (the layout of each law is
that of :mod:`frictionlaw._kernels`). Each node carries its zone ``zone[i]``; the kernels run
that zone's law with the node's own ``p_hist`` through the one-law scalar kernels
(:func:`frictionlaw._kernels.shear_scalar`, :func:`frictionlaw._kernels.traction_row`), so a
node evaluates exactly what the one-law kernels give for its law. Explicit signatures,
``cache=True``, no ``fastmath``; serial and ``prange`` variants are separate functions (numba's
cache is keyed by the Python function). The NumPy oracle is :mod:`frictionlaw._reference`.
"""

import numba as nb
from numba import float64, int8, int64, types

from ._kernels import shear_scalar, traction_row
from ._kernels_branches import _RO, _RO2, _opts

__all__ = [
    "zone_coeffs",
    "zone_shear_scalar",
    "shear_array_zoned",
    "shear_array_zoned_parallel",
    "traction_array_zoned",
    "traction_array_zoned_parallel",
]

_ROI = types.Array(int64, 1, "C", readonly=True)


@nb.jit(_RO(_ROI, _RO, int64), **_opts)
def zone_coeffs(offsets, coeffs, z):
    """The coefficient array of zone ``z`` (a view of ``coeffs``)."""
    return coeffs[offsets[z] : offsets[z + 1]]


@nb.jit(types.UniTuple(float64, 2)(_ROI, _ROI, _RO, int64, float64, float64), **_opts)
def zone_shear_scalar(codes, offsets, coeffs, z, p, p_hist):
    """``(tau, dtau/dp)`` of zone ``z``'s law at ``p`` after ``p_hist``."""
    return shear_scalar(codes[z], zone_coeffs(offsets, coeffs, z), p, p_hist)


_shear_sig = types.void(_ROI, _ROI, _RO, _ROI, _RO, _RO, float64[::1], float64[::1])


@nb.jit(_shear_sig, **_opts)
def shear_array_zoned(codes, offsets, coeffs, zone, p, p_hist, tau, dtau):
    """``tau[i], dtau[i]`` of node ``i``'s zone law, serial."""
    for i in range(p.shape[0]):
        tau[i], dtau[i] = zone_shear_scalar(codes, offsets, coeffs, zone[i], p[i], p_hist[i])


@nb.jit(_shear_sig, parallel=True, **_opts)
def shear_array_zoned_parallel(codes, offsets, coeffs, zone, p, p_hist, tau, dtau):
    """As :func:`shear_array_zoned`, threads over the nodes."""
    for i in nb.prange(p.shape[0]):
        tau[i], dtau[i] = zone_shear_scalar(codes, offsets, coeffs, zone[i], p[i], p_hist[i])


_traction_sig = types.void(
    _ROI,
    _ROI,
    _RO,
    _ROI,
    _RO,
    _RO,
    _RO2,
    _RO2,
    _RO,
    float64[:, ::1],
    int8[::1],
    float64[:, :, ::1],
    float64[:, ::1],
    float64[::1],
)


@nb.jit(_traction_sig, **_opts)
def traction_array_zoned(
    codes, offsets, coeffs, zone, p, p_hist, du, t_old, k_t, t_new, status, dt_ddu, dt_dp, p_trial
):
    """The return map of node ``i``'s zone law, and the trial history ``max(p_hist, p)``."""
    for i in range(p.shape[0]):
        z = zone[i]
        status[i] = traction_row(
            codes[z],
            zone_coeffs(offsets, coeffs, z),
            p[i],
            p_hist[i],
            du,
            t_old,
            k_t[i],
            t_new,
            dt_ddu,
            dt_dp,
            i,
        )
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]


@nb.jit(_traction_sig, parallel=True, **_opts)
def traction_array_zoned_parallel(
    codes, offsets, coeffs, zone, p, p_hist, du, t_old, k_t, t_new, status, dt_ddu, dt_dp, p_trial
):
    """As :func:`traction_array_zoned`, threads over the nodes."""
    for i in nb.prange(p.shape[0]):
        z = zone[i]
        status[i] = traction_row(
            codes[z],
            zone_coeffs(offsets, coeffs, z),
            p[i],
            p_hist[i],
            du,
            t_old,
            k_t[i],
            t_new,
            dt_ddu,
            dt_dp,
            i,
        )
        p_trial[i] = max(p_hist[i], p[i]) if p[i] > 0.0 else p_hist[i]
