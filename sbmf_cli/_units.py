"""How every output states a column's unit: in its name, one convention for every command.

A column (CSV header, VTU field) is named ``<quantity>_<unit>``: ``force_N``, ``stroke_m``,
``avg_pressure_Pa``, ``k_t_Pa_per_m``; a fraction of a reference (a height reduction, a change of
a diameter, a residual of one) is ``<quantity>_fraction`` (0.5 for 50 %; never percent in a
file); a count, a flag (0/1), a stage number or a ratio named as one (``p_peak_over_p_max``)
keeps its bare name. Readers take the name with or without its unit (:func:`column_key`), so the
files written before the units were in every name are still read.
"""

from __future__ import annotations

__all__ = ["UNIT_SUFFIXES", "column_key", "column_name"]

#: unit -> its suffix in a column name ("1": dimensionless counts, flags, ratios: no suffix)
UNIT_SUFFIXES = {
    "N": "N",
    "m": "m",
    "Pa": "Pa",
    "Pa/m": "Pa_per_m",
    "s": "s",
    "fraction": "fraction",
    "1": "",
}


def column_name(key, unit):
    """The name of column ``key`` in unit ``unit`` (a key of :data:`UNIT_SUFFIXES`)."""
    try:
        suffix = UNIT_SUFFIXES[unit]
    except KeyError:
        raise ValueError(
            f"unit {unit!r} of column {key!r} is none of {', '.join(UNIT_SUFFIXES)}"
        ) from None
    return f"{key}_{suffix}" if suffix else key


def column_key(name):
    """The quantity a column name stands for: ``force_N`` -> ``force``; a bare name as it is."""
    for suffix in sorted((s for s in UNIT_SUFFIXES.values() if s), key=len, reverse=True):
        if name.endswith("_" + suffix) and len(name) > len(suffix) + 1:
            return name[: -len(suffix) - 1]
    return name
