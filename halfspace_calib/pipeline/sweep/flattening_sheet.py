"""A measured contact fraction against strain: the lab sheet of ``--flattening-data``.

The sheet is read as spreadsheets write it (:func:`frictionlaw._table.read_rows`: ``#``
comments, a byte-order mark, commas, semicolons or tabs, decimal commas where the separator is
no comma). Its three columns are found by name, in English or German, with the unit the header
gives (``alpha [%]``, ``p [MPa]``, ``p_kPa``, ``strain [-]``, :data:`NAMES`, :data:`UNITS`); a
unit the reader does not know is refused naming the column and the units it takes, never
guessed; a second header row of units (``-; %; MPa``, ``[%]``, as lab software writes it) is
read as the header's units. The strain is the host's equivalent plastic strain, a true
(logarithmic) strain: a column headed as an engineering strain is refused with the conversion.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from frictionlaw._table import (
    STRAIN_SHOWN,
    STRAIN_UNITS,
    STRESS_SHOWN,
    STRESS_UNITS,
    find_columns,
    header_and_rows,
    known_names,
    number,
    plain,
    read_rows,
)
from frictionlaw.flow_curve import FlowCurve

from ...topography._formats import file_sha256

__all__ = ["FlatteningData", "read_flattening_data", "NAMES", "UNITS", "STRAIN_MAX"]


@dataclass(frozen=True)
class FlatteningData:
    """A measured contact fraction against bulk strain (``--flattening-data``).

    ``strain`` (equivalent plastic strain, a true strain, >= 0), ``alpha`` (contact fraction in
    [0, 1]) and ``p`` (the contact pressure of each point, Pa, > 0), one value per row of the
    file; ``flow_curve`` the sheet's flow curve when it was given (the fit then runs the law at
    its flow stress and hardening modulus, :func:`~.flattening.fit_beta`).
    """

    path: str
    strain: np.ndarray
    alpha: np.ndarray
    p: np.ndarray
    #: the measured sheet's flow curve (``--flow-curve``), or ``None``: a perfectly plastic sheet
    flow_curve: "FlowCurve | None" = None
    #: the file's line of each row (for the messages; empty for data made in code)
    lines: tuple = ()
    #: SHA-256 of the file's bytes and their number (``None`` for data made in code)
    sha256: str | None = None
    size_bytes: int | None = None


#: the largest equivalent plastic strain a flattening measurement is read with (a strip drawn or
#: upset to it would have failed long before); above it the column is most likely in per cent
STRAIN_MAX = 2.0

#: the column names of each quantity (compared in lower case, umlauts spelt out, ``_``, ``-``
#: and ``.`` as spaces)
NAMES = {
    "strain": (
        "strain",
        "eps",
        "epsilon",
        "\u03b5",
        "equivalent plastic strain",
        "plastic strain",
        "true strain",
        "Dehnung",
        "Vergleichsdehnung",
        "Umformgrad",
    ),
    "alpha": ("alpha", "\u03b1", "contact fraction", "real contact fraction", "Traganteil"),
    "p": ("p", "pressure", "contact pressure", "Druck", "Kontaktdruck", "Flächenpressung"),
}
#: the units a header may give each quantity (compared in lower case) -> factor to the fraction
#: or to Pa; a pressure needs one
UNITS = {
    "strain": STRAIN_UNITS,
    "alpha": {"": 1.0, "-": 1.0, "1": 1.0, "%": 0.01},
    "p": STRESS_UNITS,
}
#: the units as the messages show them
_SHOWN = {
    "strain": STRAIN_SHOWN,
    "alpha": "none, -, 1, %",
    "p": STRESS_SHOWN,
}
#: headers of an engineering strain (refused: the law's strain is a true strain)
_ENGINEERING = ("engineering strain", "eng strain", "strain eng", "technische dehnung")
_KNOWN = known_names(NAMES)


def _engineering(written: str) -> str | None:
    """The message for a column headed as an engineering strain (``None`` for another)."""
    if plain(written) not in _ENGINEERING:
        return None
    return (
        f"the column {written!r} is an engineering strain: the law's strain is the host's "
        "equivalent plastic strain, a true (logarithmic) strain; convert each value e to "
        "ln(1 + e) and name the column strain"
    )


def _columns(path: Path, line: int, head: list[str]) -> dict[str, tuple[int, float, str]]:
    """``{quantity: (index, factor, header as written)}``; ``ValueError`` for a bad header."""
    named = {"p": ("pressure", "p_MPa, p [MPa] or p_Pa")}
    found = find_columns(path, line, head, _KNOWN, UNITS, _SHOWN, named=named, refuse=_engineering)
    missing = [q for q in ("strain", "alpha", "p") if q not in found]
    if missing:
        shown = ", ".join(repr(h.strip()) for h in head) or "nothing"
        raise ValueError(
            f"{path}: the first row must name the columns strain, alpha and p with its unit "
            "(strain: equivalent plastic strain, a true strain; alpha: contact fraction in "
            "[0, 1] or in per cent as 'alpha [%]'; p: the pressure of each point, as p_Pa, "
            "p_MPa, 'p [kPa]', ...), separated by commas, semicolons or tabs; missing "
            f"{', '.join(missing)}, found {shown}; names read: "
            + "; ".join(f"{q}: {', '.join(n)}" for q, n in NAMES.items())
        )
    return found


def read_flattening_data(path) -> FlatteningData:
    """Read a CSV with a strain, a contact fraction and a pressure column (any order).

    What spreadsheets write is read as it comes: ``#`` comment lines, a UTF-8 byte-order mark,
    comma, semicolon or tab as the separator (the header row decides), decimal commas where the
    separator is no comma, column names in any case with their unit (``strain``, ``alpha [%]``,
    ``p_MPa``, ``p [kPa]``, :data:`NAMES`, :data:`UNITS`). At least two rows with a strain above
    0 are needed to fit ``beta``. ``ValueError`` naming the file, the line and the column for
    anything else, with the likely cause where the numbers show it (a contact fraction or a
    strain in per cent, a decimal comma, a sheet not saved as UTF-8).
    """
    path = Path(path)
    line_of, rows, sep = read_rows(path)
    head, line_of, rows = header_and_rows(path, line_of, rows, sep, _KNOWN, UNITS, _SHOWN)
    cols = _columns(path, line_of[0] if line_of else 1, head)
    vals: dict[str, list[float]] = {c: [] for c in cols}
    for i, r in zip(line_of[1:], rows[1:], strict=True):
        for c, (j, factor, written) in cols.items():
            cell = r[j].strip() if j < len(r) else ""
            if not cell:
                raise ValueError(f"{path}: line {i}, column {written}: empty")
            try:
                v = number(cell, sep)
            except ValueError:
                hint = " (a decimal comma? write 0.5, not 0,5)" if "," in cell else ""
                if _THOUSANDS.match(cell):
                    hint = " (thousands separators are not read: write the digits alone)"
                raise ValueError(
                    f"{path}: line {i}, column {written}: not a number{hint}"
                ) from None
            if not math.isfinite(v):
                raise ValueError(f"{path}: line {i}, column {written}: not finite")
            vals[c].append(v * factor)
    data = FlatteningData(
        str(path),
        np.array(vals["strain"]),
        np.array(vals["alpha"]),
        np.array(vals["p"]),
        lines=tuple(line_of[1:]),
        sha256=file_sha256(path),  # what a rerun checks the file against
        size_bytes=path.stat().st_size,
    )
    _check_values(path, data, line_of, {c: w for c, (_, _, w) in cols.items()})
    return data


#: a number written with thousands separators (``1,234.5``, ``12.000.000``, ``1'234``)
_THOUSANDS = re.compile(r"^[+-]?\d{1,3}(?:([,.' \u00a0\u202f])\d{3})(?:\1\d{3})*(?:[.,]\d*)?$")


def _check_values(path: Path, data: FlatteningData, line_of: list[int], name: dict) -> None:
    """``ValueError`` naming the line and column of a value out of its range."""
    if np.any(data.strain < 0):
        i = line_of[1 + int(np.argmin(data.strain))]
        raise ValueError(
            f"{path}: line {i}, column {name['strain']}: strain must be >= 0 (the equivalent "
            "plastic strain; a thickness strain is negative: give its equivalent, e.g. "
            "2 / sqrt(3) |e_t| in plane strain)"
        )
    if np.any(data.strain > STRAIN_MAX):
        i = line_of[1 + int(np.argmax(data.strain))]
        raise ValueError(
            f"{path}: line {i}, column {name['strain']}: {data.strain.max():g} is above "
            f"{STRAIN_MAX:g}, beyond any flattening measurement: the column is the equivalent "
            "plastic strain, not per cent (it looks like per cent: divide by 100, or head the "
            "column 'strain [%]')"
        )
    bad = (data.alpha < 0) | (data.alpha > 1)
    if np.any(bad):
        i = line_of[1 + int(np.argmax(bad))]
        pct = np.all(data.alpha >= 0) and np.all(data.alpha <= 100) and data.alpha.max() > 1.5
        hint = " (it looks like per cent: divide by 100, or head the column 'alpha [%]')"
        raise ValueError(
            f"{path}: line {i}, column {name['alpha']}: {data.alpha[np.argmax(bad)]:g} is not a "
            f"contact fraction in [0, 1]{hint if pct else ''}"
        )
    if np.any(data.p <= 0):
        i = line_of[1 + int(np.argmax(data.p <= 0))]
        raise ValueError(f"{path}: line {i}, column {name['p']}: must be > 0")
    if np.count_nonzero(data.strain > 0) < 2:
        raise ValueError(f"{path}: at least two rows with strain > 0 are needed to fit beta")
