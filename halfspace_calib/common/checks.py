"""Input checks shared by the package: one rule per kind of value, one wording of the error.

Every public function validates its arguments through these helpers before doing any work, so
that bad input gets a ``ValueError`` that names the parameter and the allowed range (a
:class:`sbmf_cli.ParameterError`: the command that called words it with its flag). Checks that
belong to one function only (a grid that must divide another, a file's header) stay with it.
"""

import math

import numpy as np

from sbmf_cli import ParameterError

__all__ = [
    "count",
    "in_range",
    "pair",
    "positive",
    "real",
    "text_file",
    "tolerance",
    "tresca_factor",
]


def _bad(name, text):
    """The error of a check: ``"<name> <text>"``, ``name`` a parameter the command maps to its flag."""
    return ParameterError("{" + name + "} " + text, name)


def real(name, v):
    """``v`` as a float; ``ValueError`` naming ``name`` for a bool, a string or a non-number."""
    if isinstance(v, (bool, np.bool_, str, bytes)):
        raise _bad(name, f"must be a number, got {v!r}")
    try:
        return float(v)
    except (TypeError, ValueError):
        raise _bad(name, f"must be a number, got {v!r}") from None


def positive(name, v, unit=None):
    """``v`` as a finite float > 0; ``ValueError`` naming ``name`` (and ``unit``) otherwise."""
    u = f" ({unit})" if unit else ""
    try:
        f = real(name, v)
    except ValueError:
        raise _bad(name, f"must be a finite number > 0{u}, got {v!r}") from None
    if not (math.isfinite(f) and f > 0):
        raise _bad(name, f"must be a finite number > 0{u}, got {v!r}")
    return f


def in_range(name, v, lo, hi, *, lo_open=False, hi_open=False, why=""):
    """``v`` as a float in the interval from ``lo`` to ``hi`` (closed unless ``*_open``).

    The error reads ``"{name} must be in [lo, hi]{why}, got v"`` with the interval's brackets.
    """
    interval = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
    try:
        f = real(name, v)
    except ValueError:
        f = math.nan
    above = f > lo if lo_open else f >= lo
    below = f < hi if hi_open else f <= hi
    if not (above and below):
        raise _bad(name, f"must be in {interval}{why}, got {v!r}")
    return f


def tresca_factor(m, *, allow_zero=True, why=""):
    """Tresca's friction factor ``m`` in ``[0, 1]`` (``(0, 1]`` where ``m = 0`` means nothing)."""
    return in_range("m", m, 0, 1, lo_open=not allow_zero, why=why)


def tolerance(tol, name="tol"):
    """A solver's relative tolerance in ``(0, 1)``."""
    return in_range(name, tol, 0, 1, lo_open=True, hi_open=True)


def pair(name, v, conv):
    """``v`` or ``(v, v)`` as a validated pair."""
    if np.ndim(v) == 0:
        a = conv(name, v)
        return a, a
    vals = list(v)
    if len(vals) != 2:
        raise _bad(name, f"must be a scalar or a pair (x, y), got {v!r}")
    return conv(name, vals[0]), conv(name, vals[1])


def count(name, v, lo=2):
    """``v`` as an integer >= ``lo``; ``ValueError`` naming ``name`` otherwise."""
    try:
        i = int(v)
    except (TypeError, ValueError):
        raise _bad(name, f"must be an integer >= {lo}, got {v!r}") from None
    if i != v or i < lo:
        raise _bad(name, f"must be an integer >= {lo}, got {v!r}")
    return i


def text_file(path, what):
    """The UTF-8 text of the user's file ``path`` (a ``Path``).

    ``ValueError`` naming ``what`` and the file when it is missing (``"<what> not found:
    <path>"``) or unreadable.
    """
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ValueError(f"{what} not found: {path}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read the {what} ({exc})") from None
