"""LS-DYNA's host drivers of :mod:`frictionlaw.export.harness` (private; re-exported there).

``usrfrc`` in its SMP form (one call per cycle for the active slave nodes) and its MPP form (one
call per slave node), with LS-DYNA's output units as files.
"""

import ctypes
import tempfile
from pathlib import Path

import numpy as np

from ._harness_base import _Host, _host, _ptr

__all__ = ["UsrfrcLib", "UsrfrcMppLib"]


class _LsdynaHost(_Host):
    """LS-DYNA's output units (``IOTTY``, ``IOHSP``, ``IOMSG``) as files in a folder of its own."""

    def __init__(self, lib, dtype, deck_units=None):
        super().__init__(lib, deck_units)
        self.dtype = dtype
        self.units_dir = Path(tempfile.mkdtemp(prefix="sbmf_lsdyna_"))
        self._read = {"tty": 0, "d3hsp": 0, "messag": 0}
        path = str(self.units_dir).encode()
        lib.h_lsdyna_open(ctypes.c_char_p(path), ctypes.c_int(len(path)))

    def log(self):
        """What the routine wrote to LS-DYNA's output units since the last call.

        ``{"tty": lines, "d3hsp": lines, "messag": lines}`` (the files stay in ``units_dir``).
        """
        self._lib.h_lsdyna_flush()
        out = {}
        for k, done in self._read.items():
            lines = (self.units_dir / f"{k}.txt").read_text().splitlines()
            out[k] = lines[done:]
            self._read[k] = len(lines)
        return out


class UsrfrcLib(_LsdynaHost):
    """LS-DYNA SMP ``usrfrc``: one call per cycle for the active slave nodes.

    ``dtype`` is the host REAL (``np.float32`` for SP, ``np.float64`` for DP builds). The unit
    property is ``UA(1)`` (``NINPUT = 0`` when ``deck_units`` is None).
    """

    def __init__(self, lib, dtype, deck_units=None):
        super().__init__(lib, dtype, deck_units)
        self._fn = lib.h_usrfrc
        self._fn.restype = None

    def __call__(
        self, active, ilbsv, fni, areas, stfk, sfacn3, d, rn, fdat, fxyz, ufhist, *, nosl=1
    ):
        """``fdat`` (n, 5), ``fxyz`` (n, 3), ``ufhist`` (n_hist, nhv) are updated in place.

        ``active``: 0-based indices of the active slave nodes (LS-DYNA's ``iisv5``);
        ``ilbsv``: 0-based history row of each slave node; ``nosl``: the interface number.
        """
        dt = self.dtype
        for a in (fdat, fxyz, ufhist):
            if not (a.flags.c_contiguous and a.dtype == dt):
                raise ValueError(f"fdat, fxyz, ufhist must be C-contiguous {np.dtype(dt)}")
        n = fdat.shape[0]
        nhv = ufhist.shape[1]
        iact = np.ascontiguousarray(np.asarray(active) + 1, dtype=np.int32)
        ilb = np.ascontiguousarray(np.asarray(ilbsv) + 1, dtype=np.int32)
        ins = [_host(v, dt) for v in (fni, areas, stfk, [sfacn3], d, rn)]
        nua, ua = self._props(dt)
        self._fn(
            ctypes.c_int(n),
            ctypes.c_int(iact.size),
            ctypes.c_int(nhv),
            ctypes.c_int(nua),
            _ptr(ua),
            _ptr(iact),
            _ptr(ilb),
            *map(_ptr, ins),
            _ptr(fdat),
            _ptr(fxyz),
            _ptr(ufhist),
            ctypes.c_int(nosl),
        )


class UsrfrcMppLib(_LsdynaHost):
    """LS-DYNA MPP ``usrfrc``: one call per slave node; returns ``(fstt, fdyn)`` per node.

    The unit property is ``UC(1)`` (``NC = 0`` when ``deck_units`` is None).
    """

    def __init__(self, lib, dtype, deck_units=None):
        super().__init__(lib, dtype, deck_units)
        self._fn = lib.h_usrfrc_mpp
        self._fn.restype = None

    def __call__(self, prs, uh, *, nosl=1):
        """``uh`` (n, nh) of the host REAL is updated in place; returns (n, 2) (``FSTT, FDYN``).

        ``nosl``: the interface number every call passes.
        """
        dt = self.dtype
        if not (uh.flags.c_contiguous and uh.dtype == dt):
            raise ValueError(f"uh must be a C-contiguous {np.dtype(dt)} array")
        prs = _host(prs, dt)
        n, nh = uh.shape
        mu = np.empty((n, 2), dt)
        nuc, uc = self._props(dt)
        self._fn(
            ctypes.c_int(n),
            ctypes.c_int(nh),
            ctypes.c_int(nuc),
            _ptr(uc),
            _ptr(prs),
            _ptr(uh),
            _ptr(mu),
            ctypes.c_int(nosl),
        )
        return mu


#: Abaqus/Standard ``FRIC`` (``abaqus-fric``, ``calculix``)
