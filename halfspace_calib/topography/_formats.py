"""Topography file readers and writers behind :func:`halfspace_calib.topography.read_surface`.

Plain formats are read with NumPy only; instrument formats (Keyence ``.vk4``/``.vk6``,
ISO 25178 ``.x3p``, Digital Surf ``.sur``, Zygo ``.datx``, Sensofar ``.plu`` and the
other formats of SurfaceTopography) go through the optional ``SurfaceTopography``
package, installed with the ``topography`` extra.

Every loader returns ``(heights, dx, dy, info)``: heights in m as a float64 array
indexed ``[i, j]`` with ``x = i dx`` along axis 0 and ``y = j dy`` along axis 1,
spacings in m, and a dict for the provenance.
"""

import hashlib
import re
import warnings
from pathlib import Path

import numpy as np

__all__ = [
    "UNITS",
    "PLAIN_LAYOUTS",
    "FileScaleError",
    "UnitRequired",
    "UnitContradiction",
    "SizeRequired",
    "SizeContradiction",
    "TOPOGRAPHY_EXTRA_HINT",
    "unit_factor",
    "file_sha256",
    "layout_for",
    "text_export_line",
    "matrix_header",
    "load_npy",
    "load_matrix",
    "load_xyz",
    "load_instrument",
    "import_surface_topography",
    "write_plain",
]

#: length units accepted by the readers, as factors to metres
UNITS = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6, "nm": 1e-9}

#: file suffix -> plain layout read without optional packages
PLAIN_LAYOUTS = {
    ".npy": "npy",
    ".txt": "matrix",
    ".csv": "matrix",
    ".dat": "matrix",
    ".asc": "matrix",
    ".xyz": "xyz",
}

TOPOGRAPHY_EXTRA_HINT = (
    "instrument formats (.vk4, .vk6, .x3p, .sur, .datx, .plu, ...) need the optional "
    "SurfaceTopography package: pip install 'SurfaceTopography>=1.27' (from a clone of this "
    "project: pip install -e '.[topography]')"
)


class FileScaleError(ValueError):
    """A file's scale (its height unit, its lateral size) is missing, or the options contradict it.

    The family of errors a caller can tell apart by type: a plain file needs the options the
    instrument files carry themselves. Each is a ``ValueError``; the message names the file
    where it is known.
    """


class UnitRequired(FileScaleError):
    """The file does not say its height unit and no ``unit`` was given."""


class UnitContradiction(FileScaleError):
    """The ``unit`` given is not the unit the file (or its header) states."""


class SizeRequired(FileScaleError):
    """The file has no lateral calibration and neither ``dx`` nor ``size`` was given.

    ``note``: what the file's header says of its size when it says half of it (``"its header
    gives '# Width: 10 um' but no '# Height:' line ..."``), else empty.
    """

    def __init__(self, message, note=""):
        super().__init__(message)
        self.note = note


class SizeContradiction(FileScaleError):
    """``dx``, ``dy`` or ``size`` given for a file that carries its own lateral calibration."""


def unit_factor(unit, name="unit"):
    """Factor from ``unit`` to metres.

    :class:`UnitRequired` naming ``name`` for ``None``, ``ValueError`` for an unknown unit.
    """
    if unit is None:
        raise UnitRequired(f"{name} is required for this file: one of {sorted(set(UNITS))}")
    try:
        return UNITS[str(unit).strip()]
    except KeyError:
        raise ValueError(f"{name} must be one of {sorted(set(UNITS))}, got {unit!r}") from None


def file_sha256(path):
    """Hex SHA-256 of a file's bytes (recorded in the provenance)."""
    with open(path, "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


def _is_binary(path):
    """True if the first 4 KiB of ``path`` hold a NUL byte or are not UTF-8 text."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(4096)
    except OSError:
        return False
    if b"\x00" in head:
        return True
    try:
        head.decode("utf-8")
    except UnicodeDecodeError as exc:  # a multi-byte character cut at the 4 KiB edge is text
        return exc.start < len(head) - 4
    return False


def layout_for(path):
    """Layout of ``path``: ``npy``, ``matrix``, ``xyz`` or ``instrument``, routed by content.

    ``.npy`` and ``.xyz`` go by their suffix. A file with a text-matrix suffix (``.txt``,
    ``.csv``, ``.dat``, ``.asc``) is a matrix only if it is text and its header is the plain
    reader's own (:func:`text_export_line`): a binary file (a Zygo MetroPro ``.dat``, for
    instance) and a text export whose header carries keys of another program (a pixel size, a
    height conversion factor) go to the instrument readers (SurfaceTopography). Any other suffix
    is an instrument format.
    """
    layout = PLAIN_LAYOUTS.get(Path(path).suffix.lower(), "instrument")
    if layout == "matrix" and (_is_binary(path) or text_export_line(path) is not None):
        return "instrument"
    return layout


_HEADER = re.compile(r"^#\s*([A-Za-z][A-Za-z ]*?)\s*[:=]\s*(.+?)\s*$")
#: the header keys of the plain text matrix (:func:`matrix_header`; ``channel`` names the
#: instrument's channel and changes nothing)
PLAIN_HEADER_KEYS = frozenset(
    ("width", "height", "value units", "value unit", "z unit", "unit", "channel")
)
_KEY_VALUE = re.compile(r"^([^=:\uff1a]+?)\s*[=:\uff1a]\s*\S")
_NUMBER = re.compile(r"^[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$|^[-+]?(?:nan|inf)$", re.I)


def _is_data(line):
    """True for a line of numbers (a row of a matrix: whitespace, comma or semicolon separated)."""
    tokens = re.split(r"[\s,;]+", line.strip())
    return bool(tokens) and all(_NUMBER.match(t) for t in tokens if t)


def text_export_line(path):
    """The first header line of a text file that the plain matrix reader does not know, or ``None``.

    The header is the lines before the first line of numbers. The plain reader's own are
    ``#`` lines with one of :data:`PLAIN_HEADER_KEYS` (``# Width: 10 um``, ``# Value units: m``)
    and ``#`` comments that are no ``key: value`` / ``key = value`` pair (``# heights in um``, as
    :func:`write_plain` writes). Any other line (``# pixel size = 2e-06 m``, ``height
    conversion factor (-> m) = 5e-08``, a line without ``#``) is another program's metadata:
    such a file is an instrument export, read by SurfaceTopography's text reader (which
    understands the exports of Gwyddion, SPIP, Wyko, Nova, Attocube and their scale factors)
    rather than by a reader that would ignore its scale. ``None`` for a file that cannot be read.
    """
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            for n, line in enumerate(fh):
                s = line.strip()
                if not s:
                    continue
                if _is_data(s) or n > 1000:
                    return None
                if not s.startswith("#"):
                    return s
                m = _KEY_VALUE.match(s.lstrip("#").strip())
                if m and m.group(1).strip().lower() not in PLAIN_HEADER_KEYS:
                    return s
    except OSError:
        return None
    return None


def _length(path, key, text):
    """``"10.00 um"`` -> metres; ``ValueError`` naming the header line otherwise."""
    parts = text.split()
    try:
        value = float(parts[0])
        f = UNITS[parts[1]] if len(parts) == 2 else None
    except (ValueError, IndexError, KeyError):
        f = None
    if f is None or not (np.isfinite(value) and value > 0):
        raise ValueError(
            f"{path}: header '# {key}: {text}' is not a length > 0 with a unit of {sorted(UNITS)}"
        )
    return value * f


def matrix_header(path):
    """Units and sizes from the ``#`` header of a text matrix (as instrument exports write them).

    Recognised lines (case-insensitive keys): ``# Width: 10.00 um`` (the extent along a line,
    axis 1), ``# Height: 10.00 um`` (the extent over the lines, axis 0), ``# Value units: m``
    (the unit of the heights). Other header lines are ignored.

    Returns
    -------
    dict
        ``size`` ``(Lx, Ly)`` in m if both extents are given; ``half_size`` ``(key, as written,
        length in m)`` if only one is; ``unit`` if given; else empty.
    """
    found = {}
    with open(path, encoding="utf-8", errors="replace") as fh:
        for line in fh:
            s = line.strip()
            if not s:
                continue
            if not s.startswith("#"):
                break
            m = _HEADER.match(s)
            if m:
                found[m.group(1).strip().lower()] = m.group(2)
    out = {}
    if "width" in found and "height" in found:
        out["size"] = (
            _length(path, "Height", found["height"]),
            _length(path, "Width", found["width"]),
        )
    elif "width" in found or "height" in found:  # half a size: said, not dropped
        key = "Width" if "width" in found else "Height"
        out["half_size"] = (key, found[key.lower()], _length(path, key, found[key.lower()]))
    for key in ("value units", "value unit", "z unit", "unit"):
        if key in found:
            u = found[key].strip()
            if u not in UNITS:
                raise ValueError(
                    f"{path}: header '# {key}: {u}' names an unknown unit; one of {sorted(UNITS)}"
                )
            out["unit"] = u
            break
    return out


def _check_matrix(path, arr, allow_undefined=False):
    if arr.ndim != 2 or min(arr.shape) < 2:
        raise ValueError(
            f"{path}: expected a 2-D height matrix with at least 2 x 2 points, got shape {arr.shape}"
        )
    if np.isinf(arr).any():
        raise ValueError(f"{path}: holds infinite heights")
    bad = int(np.count_nonzero(np.isnan(arr)))
    if bad == arr.size:
        raise ValueError(f"{path}: every height is undefined (NaN); the file holds no surface")
    if bad and not allow_undefined:
        raise ValueError(
            f"{path}: {bad} missing or non-finite heights; fill or crop them before use"
        )
    return arr


def load_npy(path, unit, allow_undefined=False):
    """Heights (m) from a NumPy ``.npy`` 2-D array given in ``unit`` (NaN: undefined points)."""
    f = unit_factor(unit)
    try:
        arr = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as exc:
        raise ValueError(f"{path}: cannot read as a NumPy .npy array ({exc})") from None
    if not isinstance(arr, np.ndarray) or not np.issubdtype(arr.dtype, np.number):
        raise ValueError(f"{path}: the .npy file does not hold a numeric array")
    arr = _check_matrix(path, np.asarray(arr, dtype=np.float64), allow_undefined)
    return arr * f


def _separation(line):
    """``(delimiter for np.loadtxt, decimal comma)`` of a text file's first data line.

    Semicolons separate (a decimal comma then reads as a point, as European spreadsheets write
    numbers); whitespace separates where each value holds one comma and no point (``1,88e-08``
    and ``1,85e-08`` with tabs between: decimal commas); otherwise commas separate (a CSV). The lab-sheet reader
    (:func:`frictionlaw._table.number`) reads decimal commas by the same rule.
    """
    s = line.split("#", 1)[0].strip()
    if ";" in s:
        return ";", "," in s
    fields = s.split()
    if "," in s and len(fields) > 1 and "." not in s:
        if all(f.count(",") == 1 and f.strip(",") == f for f in fields):
            return None, True
    return ("," if "," in s else None), False


def _text_problem(lines, sep, comma, what):
    """The first line that keeps ``lines`` from being a table of numbers, in words, or ``None``."""
    first = width = 0
    for n, line in enumerate(lines, start=1):
        s = line.split("#", 1)[0].strip()
        if not s:
            continue
        cells = [c.strip() for c in (s.split(sep) if sep else s.split())]
        for k, c in enumerate(cells, start=1):
            try:
                float(c.replace(",", ".") if comma else c)
            except ValueError:
                hint = (
                    " (empty: a missing value or a separator at the end of the line)"
                    if not c
                    else " (a thousands separator? write 1234.5)"
                    if comma and "." in c
                    else " (a decimal comma in a comma-separated file? write 0.5 or separate the "
                    "values by semicolons)"
                    if sep == ","
                    else ""
                )
                return f"line {n}, value {k}: {c[:24]!r} is not a number{hint}"
        if not width:
            first, width = n, len(cells)
        elif len(cells) != width:
            return (
                f"line {n} holds {len(cells)} values where line {first} holds {width}: every row "
                f"of a {what} has as many values (a row cut short or run on?)"
            )
    return None


def _loadtxt(path, what):
    """The numbers of a text table, as an array with a row per line.

    ``#`` comments; whitespace, commas or semicolons between the values, decimal commas as
    :func:`_separation` reads them. ``ValueError`` naming the file's line and what is wrong there.
    """
    raw = Path(path).read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        if b"\0" in raw[:4096]:
            raise ValueError(f"{path}: cannot read as a text {what} (not a text file)") from None
        text = raw.decode("latin-1")  # a code page's degree sign or micro sign in a comment
    lines = text.splitlines()
    first = next((ln for ln in lines if ln.split("#", 1)[0].strip()), None)
    if first is None:
        raise ValueError(f"{path}: the file holds no data lines")
    sep, comma = _separation(first)
    rows = [ln.replace(",", ".") for ln in lines] if comma else lines
    try:
        return np.loadtxt(rows, delimiter=sep, comments="#", dtype=np.float64, ndmin=2)
    except ValueError as exc:
        problem = _text_problem(lines, sep, comma, what) or str(exc)
        raise ValueError(f"{path}: cannot read as a text {what}: {problem}") from None


def load_matrix(path, unit, allow_undefined=False):
    """Heights (m) from a whitespace-, comma- or semicolon-separated matrix in ``unit``.

    Row ``i`` of the file becomes ``heights[i, :]`` (``x`` along the rows). Lines starting
    with ``#`` are comments (see :func:`matrix_header` for the ones that carry units and
    sizes); ``nan`` marks an undefined point. Decimal commas are read where the values are
    separated by semicolons or whitespace (:func:`_separation`).
    """
    f = unit_factor(unit)
    arr = _check_matrix(path, _loadtxt(path, "height matrix"), allow_undefined)
    return arr * f


def _grid_axis(path, name, v):
    """Index of each coordinate on a regular axis, the step and the first value."""
    uniq = np.unique(v)
    n = uniq.size
    if n < 2:
        raise ValueError(f"{path}: all points share one {name} value; need a 2-D grid")
    step = (uniq[-1] - uniq[0]) / (n - 1)
    idx = np.rint((v - uniq[0]) / step).astype(np.int64)
    dev = np.abs(v - (uniq[0] + idx * step)).max()
    if dev > 0.05 * step or np.unique(idx).size != n:
        raise ValueError(
            f"{path}: the {name} values are not on a regular grid ({n} distinct values, "
            f"mean step {step:g}, largest deviation {dev:g}); resample the points onto a "
            "regular grid first"
        )
    return idx, n, step


def load_xyz(path, unit, xy_unit=None):
    """Grid an ``x y z`` point list (whitespace or comma separated) onto its regular grid.

    Parameters
    ----------
    path : path-like
        Three columns ``x y z``; row order is free.
    unit : str
        Unit of ``z``.
    xy_unit : str, optional
        Unit of ``x`` and ``y``; defaults to ``unit``.

    Returns
    -------
    heights, dx, dy : ndarray, float, float
        Heights in m on the grid, spacings in m.

    Raises
    ------
    ValueError
        If the points do not form a complete regular grid (missing, duplicate or
        irregularly spaced points).
    """
    fz = unit_factor(unit)
    fxy = unit_factor(unit if xy_unit is None else xy_unit, "xy_unit")
    data = _loadtxt(path, "x y z point list")
    if data.shape[1] != 3:
        raise ValueError(f"{path}: an x y z point list needs 3 columns, found {data.shape[1]}")
    if not np.isfinite(data).all():
        raise ValueError(f"{path}: the point list holds missing or non-finite values")
    ix, nx, dx = _grid_axis(path, "x", data[:, 0])
    iy, ny, dy = _grid_axis(path, "y", data[:, 1])
    if data.shape[0] != nx * ny:
        raise ValueError(
            f"{path}: {data.shape[0]} points do not fill a complete {nx} x {ny} grid; "
            "the point list is not gridded"
        )
    flat = ix * ny + iy
    if np.unique(flat).size != flat.size:
        raise ValueError(f"{path}: duplicate (x, y) points; the point list is not gridded")
    h = np.empty(nx * ny)
    h[flat] = data[:, 2]
    return h.reshape(nx, ny) * fz, dx * fxy, dy * fxy


def import_surface_topography():
    """Import SurfaceTopography quietly, or raise ``ImportError`` naming the extra."""
    try:
        with warnings.catch_warnings():
            # NuMPI warns when mpi4py is absent; the serial stub is what we want
            warnings.simplefilter("ignore", ImportWarning)
            import SurfaceTopography
    except ImportError as exc:
        raise ImportError(TOPOGRAPHY_EXTRA_HINT) from exc
    return SurfaceTopography


def load_instrument(path, unit=None, fill_undefined=False, keep_undefined=False):
    """Read an instrument file through SurfaceTopography.

    Returns ``(heights, dx, dy, info)``; ``dx``, ``dy`` are ``None`` if the file has
    no lateral calibration. ``unit`` is used only when the file has none.
    ``keep_undefined`` returns undefined points as NaN (the caller fills them).
    """
    st = import_surface_topography()
    caught = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            reader = st.open_topography(str(path))
            topo = reader.topography()
    except Exception as exc:  # the package raises many types for a bad file
        if type(exc).__name__ == "CannotDetectFileFormat":
            msg = "no SurfaceTopography reader recognises it: damaged or unsupported format"
        else:
            text = str(exc).strip()
            msg = f"{type(exc).__name__}: {text.splitlines()[0] if text else ''}"
        raise ValueError(f"{path}: cannot read this file as a topography ({msg})") from None
    if topo.dim != 2:
        raise ValueError(f"{path}: holds a line scan, not an areal topography")
    file_unit = topo.unit
    if file_unit is None:
        unit_factor(unit)
        f = UNITS[unit]
    else:
        f = unit_factor(file_unit, "the file's unit")
        if unit is not None and unit_factor(unit) != f:
            raise UnitContradiction(
                f"{path}: unit={unit!r} contradicts the file's own unit {file_unit!r}; "
                "leave unit unset"
            )
    had_holes = bool(topo.has_undefined_data)
    if had_holes and not keep_undefined:
        if not fill_undefined:
            raise ValueError(
                f"{path}: the topography has undefined (unmeasured) points; pass "
                "fill_undefined=True to interpolate them, or crop them away"
            )
        topo = topo.interpolate_undefined_data()
    raw = topo.heights()
    h = np.asarray(np.ma.getdata(raw), dtype=np.float64) * f
    if keep_undefined:
        h = np.where(np.ma.getmaskarray(raw) | ~np.isfinite(h), np.nan, h)
    _check_matrix(path, h, allow_undefined=keep_undefined)
    sizes = topo.physical_sizes
    if sizes is None or any(s is None for s in sizes):
        dx = dy = None
    else:
        dx = float(sizes[0]) * f / h.shape[0]
        dy = float(sizes[1]) * f / h.shape[1]
    info = {
        "reader": "SurfaceTopography " + str(getattr(st, "__version__", "?")),
        "format": type(reader).__name__,
        "file_unit": file_unit,
        "filled_undefined": had_holes and not keep_undefined,
    }
    if caught:
        info["reader_warnings"] = [str(w.message) for w in caught]
    return h, dx, dy, info


def write_plain(heights, dx, dy, path, unit="um"):
    """Write heights (m) as ``.npy``, a text matrix (``.txt``/``.csv``/...) or ``.xyz``.

    Values are written in ``unit`` with full precision (``%.17g``), so a round trip
    through the matching reader is exact up to the unit conversion's rounding.
    """
    path = Path(path)
    f = unit_factor(unit)
    layout = layout_for(path)
    h = np.asarray(heights, dtype=np.float64) / f
    if layout == "npy":
        np.save(path, h)
    elif layout == "matrix":
        delim = "," if path.suffix.lower() == ".csv" else " "
        np.savetxt(path, h, fmt="%.17g", delimiter=delim, header=f"heights in {unit}")
    elif layout == "xyz":
        nx, ny = h.shape
        x, y = np.meshgrid(np.arange(nx) * dx / f, np.arange(ny) * dy / f, indexing="ij")
        pts = np.column_stack([x.ravel(), y.ravel(), h.ravel()])
        np.savetxt(path, pts, fmt="%.17g", header=f"x y z in {unit}")
    else:
        raise ValueError(
            f"path must end in one of {sorted(PLAIN_LAYOUTS)} to be written, got {path.name!r}"
        )
    return path
