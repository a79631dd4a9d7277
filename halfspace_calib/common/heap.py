"""Keep freed grid-sized arrays in the process's heap instead of giving them back (glibc).

A normal solve allocates a few arrays of the grid's size per CG iteration (the outputs of
``scipy.fft``'s transforms and their temporaries: 2 MB each at 512^2). glibc's ``malloc`` serves
such blocks by ``mmap`` and returns them to the system on ``free`` (or trims them off the top of
the heap), so each new block arrives as fresh pages, each page one fault, which a virtual machine
makes expensive. Measured on the 2-core machine of the benchmarks, a calibration of the default
scene at 512^2 on one process: 537,000 minor page faults and 1.5 s of system time with glibc's
defaults, 23,000 faults and 0.34 s with the blocks kept (the same peak memory, 281 MB); an
``irfft2`` of 512^2 took 2.6-2.8 ms against 0.6-1.0 ms.

:func:`keep_heap` sets glibc's thresholds once per process (``mallopt``): blocks below
:data:`MMAP_THRESHOLD` come from the heap, and the heap's free top is given back only above
:data:`TRIM_THRESHOLD`. The normal and tangential solvers call it; elsewhere (another C library,
another system) it does nothing. The environment variable ``SBMF_KEEP_HEAP=0`` turns it off.
No library does this for a running process (``MALLOC_MMAP_THRESHOLD_`` and
``MALLOC_TRIM_THRESHOLD_`` do it for a process started with them), hence this small module.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import sys

__all__ = ["MMAP_THRESHOLD", "TRIM_THRESHOLD", "keep_heap"]

#: blocks below this many bytes come from the heap (a 2048^2 float64 grid is 32 MiB)
MMAP_THRESHOLD = 64 << 20
#: the heap's free top is given back to the system above this many bytes
TRIM_THRESHOLD = 256 << 20

# glibc's mallopt parameters (malloc.h)
_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3

_DONE: bool | None = None


def keep_heap() -> bool:
    """Set the thresholds once (glibc only); True when they are set in this process.

    Idempotent and cheap after the first call. Returns False without changing anything on
    systems other than Linux with glibc, when ``SBMF_KEEP_HEAP=0``, or when ``mallopt`` refuses.
    A forked worker inherits the setting.
    """
    global _DONE
    if _DONE is not None:
        return _DONE
    _DONE = False
    if os.environ.get("SBMF_KEEP_HEAP", "1") == "0" or not sys.platform.startswith("linux"):
        return False
    try:
        name = ctypes.util.find_library("c") or "libc.so.6"
        libc = ctypes.CDLL(name)
        mallopt = libc.mallopt
        libc.gnu_get_libc_version  # noqa: B018 - glibc only (musl has no mallopt thresholds)
    except (OSError, AttributeError):
        return False
    mallopt.argtypes = [ctypes.c_int, ctypes.c_int]
    mallopt.restype = ctypes.c_int
    # setting either threshold also ends glibc's own adjustment of the mmap threshold
    ok = mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD) == 1
    ok = mallopt(_M_TRIM_THRESHOLD, TRIM_THRESHOLD) == 1 and ok
    _DONE = ok
    return ok
