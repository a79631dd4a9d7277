"""Surface files: read a measured map (plain or instrument file), fill undefined points, write one.

Plain files are handled by :mod:`._formats`; instrument files go through SurfaceTopography.
"""

from pathlib import Path

import numpy as np

from ..common.checks import pair, positive
from . import _formats as _io
from ._formats import (
    FileScaleError,
    SizeContradiction,
    SizeRequired,
    UnitContradiction,
    UnitRequired,
)
from .surface import Surface

__all__ = [
    "read_surface",
    "read_raw",
    "fill_harmonic",
    "write_surface",
    "FileScaleError",
    "UnitRequired",
    "UnitContradiction",
    "SizeRequired",
    "SizeContradiction",
]


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
    override_size=None,
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
    override_size : float or (float, float), optional
        Physical size ``(Lx, Ly)`` in m that replaces the size the file carries (an instrument
        file's calibration, a text header, a point list's columns): the correction of a file
        whose size is wrong. The file's own size is kept in the provenance as ``file_size``
        (``None`` for a plain file without one, for which it is the size); not with ``dx``,
        ``dy`` or ``size``.

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
        points that are not gridded; a unit or size that is missing or contradicted is one
        of the :class:`FileScaleError` kinds (as :func:`read_raw`).
    ImportError
        For an instrument format when SurfaceTopography is not installed (the
        message names the ``topography`` extra).
    """
    h, fdx, fdy, prov = read_raw(
        path,
        unit=unit,
        dx=dx,
        dy=dy,
        size=size,
        xy_unit=xy_unit,
        layout=layout,
        override_size=override_size,
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


def read_raw(
    path,
    *,
    unit=None,
    dx=None,
    dy=None,
    size=None,
    xy_unit=None,
    layout=None,
    override_size=None,
):
    """Heights of a topography file with undefined points kept as NaN.

    The reading half of :func:`read_surface` (same parameters but ``fill_undefined``):
    returns ``(heights, dx, dy, provenance)`` with heights in m (NaN where the instrument
    measured nothing), spacings in m and the provenance dict (``path``, ``sha256``,
    ``layout``, ``format``, ``unit`` and where it came from, ``shape``, ``dx``, ``dy``, the
    size's source ``size_source`` and, with ``override_size``, the file's own ``file_size``).

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    UnitRequired, SizeRequired
        A file that does not carry its height unit or its lateral size, and no option gives it.
    UnitContradiction, SizeContradiction
        An option that contradicts what the file (or its header) carries.
    ValueError
        The base of the four above; also a file that cannot be read in its layout.
    """
    path = Path(path)
    if override_size is not None:
        return _overridden(path, unit, (dx, dy, size), xy_unit, layout, override_size)
    layout = _layout(path, layout)
    if size is not None and (dx is not None or dy is not None):
        raise ValueError("give either size or dx (and dy), not both")
    header = _io.matrix_header(path) if layout == "matrix" else {}
    if "half_size" in header:
        _half_size(path, header["half_size"], size, dx)
    unit, unit_source = _header_unit(path, header, unit)
    size = _header_size(path, header, size, dx, dy)
    h, fdx, fdy, info = _load(path, layout, unit, xy_unit, (dx, dy, size))
    if info.get("file_unit") is not None:
        unit, unit_source = info["file_unit"], "file"
    fdx, fdy, size_source = _lateral(path, h.shape, (fdx, fdy), (dx, dy, size), header)
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


def _overridden(path, unit, lateral, xy_unit, layout, override_size):
    """:func:`read_raw` with ``override_size`` replacing the file's own size (kept as ``file_size``)."""
    if any(v is not None for v in lateral):
        raise ValueError("override_size replaces the file's size: give no dx, dy or size with it")
    lx, ly = pair("override_size", override_size, positive)
    try:
        h, fdx, fdy, prov = read_raw(path, unit=unit, xy_unit=xy_unit, layout=layout)
        own = [h.shape[0] * fdx, h.shape[1] * fdy]
    except SizeRequired:  # a plain file without a size (or half of one): the override is its size
        h, fdx, fdy, prov = read_raw(path, unit=unit, dx=1.0, layout=layout)  # dx replaced
        own = None
    nx, ny = h.shape
    prov.update(dx=lx / nx, dy=ly / ny, size_source="override", file_size=own)
    return h, lx / nx, ly / ny, prov


def _layout(path, layout):
    """The file's layout (``layout`` if given, checked); ``FileNotFoundError`` for no file."""
    layouts = ("npy", "matrix", "xyz", "instrument")
    if layout is not None and layout not in layouts:
        raise ValueError(f"layout must be one of {layouts}, got {layout!r}")
    if not path.is_file():
        raise FileNotFoundError(f"surface file not found: {path}")
    return _io.layout_for(path) if layout is None else layout


def _half_size(path, half, size, dx):
    """Check a header with ``# Width:`` but no ``# Height:`` (or the reverse) against the options.

    ``SizeRequired`` saying which line is missing when no size is given, ``SizeContradiction``
    where ``size`` gives the stated extent otherwise.
    """
    key, written, length = half
    other = "Height" if key == "Width" else "Width"
    if size is None and dx is None:
        note = f"its header gives '# {key}: {written}' but no '# {other}:' line (the extent " + (
            "over the lines, axis 0)" if other == "Height" else "along a line, axis 1)"
        )
        raise SizeRequired(f"{path}: {note}; add it, or pass size (m)", note=note)
    if size is not None:
        lx, ly = pair("size", size, positive)
        given = ly if key == "Width" else lx
        if abs(given - length) > 1e-6 * length:
            raise SizeContradiction(
                f"{path}: the size given makes the {key.lower()} {given:g} m where the file's "
                f"header says '# {key}: {written}' ({length:g} m)"
            )


def _header_unit(path, header, unit):
    """``(unit, where it came from)``: a text header's unit, which ``unit`` may only repeat."""
    if "unit" not in header:
        return unit, "option"
    if unit is not None and _io.unit_factor(unit) != _io.UNITS[header["unit"]]:
        raise UnitContradiction(
            f"{path}: unit={unit!r} contradicts the file's header unit "
            f"{header['unit']!r}; leave unit unset"
        )
    return header["unit"], "file header"


def _header_size(path, header, size, dx, dy):
    """``size``, or a text header's size, which no option may repeat."""
    if "size" not in header:
        return size
    if size is not None or dx is not None or dy is not None:
        raise SizeContradiction(
            f"{path}: the file's header gives its size "
            f"{header['size'][0]:g} x {header['size'][1]:g} m; do not pass dx, dy or size"
        )
    return header["size"]


def _load(path, layout, unit, xy_unit, lateral):
    """``(heights, dx, dy, info)`` of the layout's loader; ``dx``, ``dy`` ``None`` if unknown.

    ``lateral``: the options ``(dx, dy, size)``, refused where the file carries its own.
    """
    dx, _, size = lateral
    given = any(v is not None for v in lateral)
    if layout in ("npy", "matrix"):
        _io.unit_factor(unit)
        if dx is None and size is None:
            raise SizeRequired(f"{path}: the file has no lateral calibration; pass dx or size (m)")
        load = _io.load_npy if layout == "npy" else _io.load_matrix
        return load(path, unit, allow_undefined=True), None, None, {}
    if layout == "xyz":
        if given:
            raise SizeContradiction("dx, dy and size come from the x, y columns of a point list")
        return (*_io.load_xyz(path, unit, xy_unit), {})
    try:
        h, fdx, fdy, info = _io.load_instrument(path, unit, keep_undefined=True)
    except ImportError:
        line = _io.text_export_line(path) if path.suffix.lower() in _io.PLAIN_LAYOUTS else None
        if line is None:
            raise
        raise ImportError(
            f"{path}: its header line {line!r} is not the plain text matrix's (# Width, # Height, "
            "# Value units): the file is another program's export, read by SurfaceTopography's "
            f"text reader. {_io.TOPOGRAPHY_EXTRA_HINT}"
        ) from None
    if fdx is not None and given:
        raise SizeContradiction(
            f"{path}: the file carries its lateral calibration; do not pass dx, dy or size"
        )
    return h, fdx, fdy, info


def _lateral(path, shape, pitch, lateral, header):
    """``(dx, dy, where they came from)``: the file's own, else from ``size`` or ``dx``, ``dy``."""
    if pitch[0] is not None:
        return pitch[0], pitch[1], "file"
    dx, dy, size = lateral
    if size is not None:
        lx, ly = pair("size", size, positive)
        return lx / shape[0], ly / shape[1], "file header" if "size" in header else "option"
    if dx is not None:
        fdx = positive("dx", dx)
        return fdx, fdx if dy is None else positive("dy", dy), "option"
    raise SizeRequired(f"{path}: the file has no lateral calibration; pass dx or size (m)")


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
