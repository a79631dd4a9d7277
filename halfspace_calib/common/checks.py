"""Input checks shared by the package: one rule per kind of value, one wording of the error.

Every public function validates its arguments through these helpers before doing any work, so
that bad input gets a ``ValueError`` that names the parameter and the allowed range.
"""

import math

import numpy as np

__all__ = ["positive", "pair", "count"]


def positive(name, v):
    """``v`` as a finite float > 0; ``ValueError`` naming ``name`` otherwise."""
    try:
        f = float(v)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number > 0, got {v!r}") from None
    if not (math.isfinite(f) and f > 0):
        raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
    return f


def pair(name, v, conv):
    """``v`` or ``(v, v)`` as a validated pair."""
    if np.ndim(v) == 0:
        a = conv(name, v)
        return a, a
    vals = list(v)
    if len(vals) != 2:
        raise ValueError(f"{name} must be a scalar or a pair (x, y), got {v!r}")
    return conv(name, vals[0]), conv(name, vals[1])


def count(name, v, lo=2):
    """``v`` as an integer >= ``lo``; ``ValueError`` naming ``name`` otherwise."""
    try:
        i = int(v)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an integer >= {lo}, got {v!r}") from None
    if i != v or i < lo:
        raise ValueError(f"{name} must be an integer >= {lo}, got {v!r}")
    return i
