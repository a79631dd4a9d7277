"""What the host drivers of :mod:`frictionlaw.export.harness` share (private).

Conversions of NumPy arrays and names for the shims, and :class:`_Host`: the emulated deck's
unit value and the host's message log.
"""

import ctypes

import numpy as np

__all__ = ["_f", "_name80", "_ptr", "_host", "_Host"]


def _f(a):
    return np.ascontiguousarray(a, dtype=np.float64)


def _name80(name):
    """A host's CHARACTER*80 name: ``name`` blank-padded to 80 bytes (ValueError if longer)."""
    b = str(name).encode("ascii")
    if len(b) > 80:
        raise ValueError(f"a host name has at most 80 characters, got {len(b)}: {name!r}")
    return ctypes.create_string_buffer(b.ljust(80), 80)


def _ptr(a):
    return a.ctypes.data_as(ctypes.c_void_p)


class _Host:
    """What every driver shares: the emulated deck's unit value and the host's message log.

    ``deck_units`` is the value the emulated deck states its unit system with (the routines'
    unit property: 1 SI, 2 mm-t-s, any other number to test the guard; None: the deck states
    none, e.g. ``NPROPS = 0``).
    """

    def __init__(self, lib, deck_units=None):
        self._lib = lib
        self.deck_units = deck_units
        lib.h_log_read.restype = ctypes.c_int
        lib.h_log_exits.restype = ctypes.c_int

    def _props(self, dtype=np.float64):
        """``(count, array)`` of the unit property as the shim passes it.

        A sequence ``deck_units`` passes all its values (a deck with more properties than the
        unit's, to test the guard that refuses them).
        """
        if self.deck_units is None:
            return 0, np.zeros(1, dtype)
        values = np.atleast_1d(np.asarray(self.deck_units, dtype))
        return values.size, values

    def log(self):
        """What the routine wrote through the host's message routine since the last call.

        A list of ``(LOP, text)`` (Abaqus' ``LOP``: -3 error, -1 warning, 1 information).
        """
        buf = ctypes.create_string_buffer(200_000)
        n = self._lib.h_log_read(buf, len(buf))
        out = []
        for line in buf.raw[:n].decode().splitlines():
            lop, text = line.split("|", 1)
            out.append((int(lop), text))
        return out

    def exits(self, reset=True):
        """How often the routine called the host's error exit (since the last reset)."""
        return int(self._lib.h_log_exits(ctypes.c_int(1 if reset else 0)))


def _host(a, dtype):
    return np.ascontiguousarray(a, dtype=dtype)
