"""Host emulation: compile a generated routine with a C-callable shim, call it as its host does.

Each target's record names its :class:`Harness` (``frictionlaw.export.target(name).harness``):
an ISO_C_BINDING shim (a Fortran file shipped in ``frictionlaw/export/shims/``) that calls the
generated entry point exactly as the host's documentation describes (argument list, state passed
in as at the start of the increment) for many contact points per call, and a driver class that
calls the shim through ``ctypes`` with NumPy arrays, so that one compile serves thousands of
cases. ``ABA_PARAM.INC`` and ``vaba_param.inc`` are replaced by stubs with Abaqus' documented
content (implicit double precision). Needs ``gfortran``.

This module is public, not test support, because users need it too: it lets anyone check a
routine written for their parameter file against the Python runtime on their own machine before
giving it to a solver (the gallery example does), and a new host target brings its harness in
its record. The test suite (``tests/test_export_*.py``), ``benchmarks/bench_fortran_law.py`` and
the gallery use it; nothing in the export itself does, and ``import frictionlaw`` never loads
it.
"""

import ctypes
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._law import UNIT_SYSTEMS, StiffnessSpec, core_context
from ._templates import render_template, template_path

__all__ = [
    "Harness",
    "gfortran",
    "build",
    "coulomb_source",
    "FricLib",
    "VfricLib",
    "VfrictionLib",
    "UsrfrcLib",
    "UsrfrcMppLib",
    "GenericLib",
    "FRIC",
    "VFRIC",
    "VFRICTION",
    "USRFRC",
    "USRFRC_MPP",
    "SBMF_FRICTION",
    "HOST_PRECISION_FLAGS",
]

#: gfortran flags of the LS-DYNA host precisions: SP as is; DP as ifort's ``-r8 -i8`` (LSTC's
#: user-object makefiles), i.e. default REAL, DOUBLE PRECISION and INTEGER all 8 bytes
HOST_PRECISION_FLAGS = {
    "SP": (),
    "DP": ("-fdefault-real-8", "-fdefault-double-8", "-fdefault-integer-8"),
}


def gfortran():
    """Path of ``gfortran`` or None."""
    return shutil.which("gfortran")


def build(sources, workdir, name, shim, *, flags=("-O2",)):
    """Compile generated ``sources`` (``{file: text}``) with ``shim`` into ``workdir/name.so``.

    Parameters
    ----------
    sources : dict
        ``{file name: text}`` as :func:`frictionlaw.export.render` returns them; the ``.f``
        files are compiled (with ``-Wall``), the others ignored.
    workdir : path
        Build folder (made if needed); the ``ABA_PARAM.INC`` and ``vaba_param.inc`` stubs go
        there.
    name : str
        Name of the shared library (and a suffix of the object files).
    shim : str or path
        The shim's Fortran file: a path below ``frictionlaw/export`` (``"shims/fric.f90"``) or
        an absolute path.
    flags : tuple of str
        gfortran flags for every file (e.g. :data:`HOST_PRECISION_FLAGS`, ``-fopenmp``).

    Returns
    -------
    (ctypes.CDLL, str)
        The library and gfortran's warnings on the generated files (the shim is compiled
        separately, without ``-Wall``).
    """
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    for stub in ("abaqus/ABA_PARAM.INC", "shims/vaba_param.inc"):
        (workdir / Path(stub).name).write_text(template_path(stub).read_text(encoding="utf-8"))
    fc = gfortran()
    if fc is None:
        raise RuntimeError("gfortran not found")
    objs, warnings = [], []
    for fname, text in sources.items():
        if not fname.endswith(".f"):
            continue  # READMEs
        src = workdir / fname
        src.write_text(text)
        obj = workdir / (src.stem + f"_{name}.o")
        r = subprocess.run(
            [fc, "-Wall", "-fPIC", *flags, "-I", str(workdir), "-c", str(src), "-o", str(obj)],
            capture_output=True,
            text=True,
        )
        if r.returncode != 0:
            raise RuntimeError(f"gfortran failed on {fname}:\n{r.stderr}")
        warnings.append(r.stderr)
        objs.append(obj)
    shim_src = workdir / f"shim_{name}.f90"
    shim_src.write_text(template_path(shim).read_text(encoding="utf-8"))
    shim_obj = workdir / f"shim_{name}.o"
    subprocess.run(
        [fc, "-fPIC", *flags, "-c", str(shim_src), "-o", str(shim_obj)], check=True, text=True
    )
    lib = workdir / f"{name}.so"
    subprocess.run(
        [fc, "-shared", *flags, *map(str, objs), str(shim_obj), "-o", str(lib)], check=True
    )
    return ctypes.CDLL(str(lib)), "".join(warnings)


@dataclass(frozen=True)
class Harness:
    """How a target's routine is driven as its host drives it: a shim and a Python driver.

    Attributes
    ----------
    shim : str
        The ISO_C_BINDING shim (Fortran, ``bind(c)``) that calls the routine's documented entry
        point for many contact points: a path below ``frictionlaw/export`` or an absolute path.
    driver : type
        Called as ``driver(lib, **options)`` with the compiled library; its instances call the
        shim with NumPy arrays (e.g. :class:`FricLib`).
    """

    shim: str
    driver: type

    def load(self, sources, workdir, *, name="routine", flags=("-O2",), **options):
        """Compile ``sources`` with this shim (:func:`build`) and wrap the library.

        Returns ``(driver instance, gfortran's warnings)``; ``options`` go to the driver (the
        LS-DYNA drivers take the host REAL as ``dtype``).
        """
        lib, warnings = build(sources, workdir, name, self.shim, flags=flags)
        return self.driver(lib, **options), warnings


def coulomb_source(params):
    """The benchmark's floor: a plain Coulomb ``SBMF_FRICTION`` (``mu = 0.1``), core included.

    The same entry, return map and calling cost as the law's host-neutral entry, above the law
    core of ``params`` in SI; driven by :data:`SBMF_FRICTION`.
    """
    context = core_context(params, UNIT_SYSTEMS["SI"], StiffnessSpec("host"))
    return render_template("shims/coulomb.f", **context)


def _f(a):
    return np.ascontiguousarray(a, dtype=np.float64)


def _ptr(a):
    return a.ctypes.data_as(ctypes.c_void_p)


class FricLib:
    """Abaqus/Standard ``FRIC`` called per contact point as Abaqus does."""

    def __init__(self, lib):
        self._fn = lib.h_fric
        self._fn.restype = None

    def __call__(self, press, dgam, tau_start, statev_start, chrlngth):
        """One iteration: every point gets the start-of-increment ``TAU`` and ``STATEV``.

        Arrays are (n,), (n, nd), (n, nd), (n, nstatv), (n,); returns a dict of outputs.
        """
        press, dgam, tau_start, sv = map(_f, (press, dgam, tau_start, statev_start))
        chr_ = _f(np.broadcast_to(chrlngth, press.shape))
        n, nd = dgam.shape
        nsv = sv.shape[1]
        out = {
            "tau": np.empty((n, nd)),
            "ddtddg": np.empty((n, nd, nd)),
            "ddtddp": np.empty((n, nd)),
            "dslip": np.empty((n, nd)),
            "statev": np.empty((n, nsv)),
            "lm": np.empty(n, np.int32),
            "sed": np.empty(n),
            "sfd": np.empty(n),
        }
        self._fn(
            ctypes.c_int(n),
            ctypes.c_int(nd),
            ctypes.c_int(nsv),
            *map(_ptr, (press, dgam, tau_start, sv, chr_)),
            *map(_ptr, out.values()),
        )
        # Fortran DDTDDG(a, b) -> row-major [b, a] in memory: transpose to [a, b]
        out["ddtddg"] = np.ascontiguousarray(out["ddtddg"].transpose(0, 2, 1))
        return out


class VfricLib:
    """Abaqus/Explicit ``VFRIC`` called once per increment for all contact points."""

    def __init__(self, lib):
        self._fn = lib.h_vfric
        self._fn.restype = None

    def __call__(self, f_normal, f_stick, area, statev):
        """``statev`` (n, nstatev) is updated in place; returns ``fTangential`` (n, 2)."""
        f_normal, f_stick, area = map(_f, (f_normal, f_stick, area))
        if not (statev.flags.c_contiguous and statev.dtype == np.float64):
            raise ValueError("statev must be a C-contiguous float64 array")
        n, nsv = statev.shape
        ft = np.empty((n, 2))
        self._fn(
            ctypes.c_int(n),
            ctypes.c_int(nsv),
            *map(_ptr, (f_normal, f_stick, area)),
            _ptr(statev),
            _ptr(ft),
        )
        return ft


class GenericLib:
    """The host-neutral ``SBMF_FRICTION`` over many contact points (LS-DYNA, ANSYS glue)."""

    def __init__(self, lib):
        self._fn = lib.h_generic
        self._fn.restype = None

    def __call__(self, p, p_hist, g1h, du, t_old, k_host, reps=1, out=None):
        """Returns a dict: ``t``, ``dt_ddu``, ``dt_dp``, ``status``, ``p_hist``, ``g1h``."""
        p, p_hist, g1h, du, t_old = map(_f, (p, p_hist, g1h, du, t_old))
        kh = _f(np.broadcast_to(k_host, p.shape))
        n, nd = du.shape
        if out is None:
            out = {
                "t": np.empty((n, nd)),
                "dt_ddu": np.empty((n, nd, nd)),
                "dt_dp": np.empty((n, nd)),
                "status": np.empty(n, np.int32),
                "p_hist": np.empty(n),
                "g1h": np.empty(n),
            }
        self._fn(
            ctypes.c_int(n),
            ctypes.c_int(nd),
            ctypes.c_int(reps),
            *map(_ptr, (p, p_hist, g1h, du, t_old, kh)),
            *map(_ptr, out.values()),
        )
        return out

    @staticmethod
    def tangent(out):
        """``dt_ddu`` as [node, a, b] (the Fortran array is column-major per node)."""
        return out["dt_ddu"].transpose(0, 2, 1)


class VfrictionLib:
    """Abaqus/Explicit ``VFRICTION`` called once for a block of contact points."""

    def __init__(self, lib):
        self._fn = lib.h_vfriction
        self._fn.restype = None

    def __call__(self, f_normal, f_stick, area, state):
        """``state`` (n, nNodState, nStates) is updated in place; returns ``fTangential`` (n, 2)."""
        f_normal, f_stick, area = map(_f, (f_normal, f_stick, area))
        if not (state.flags.c_contiguous and state.dtype == np.float64):
            raise ValueError("state must be a C-contiguous float64 array")
        n, nns, nsv = state.shape
        ft = np.empty((n, 2))
        self._fn(
            ctypes.c_int(n),
            ctypes.c_int(nns),
            ctypes.c_int(nsv),
            *map(_ptr, (f_normal, f_stick, area)),
            _ptr(state),
            _ptr(ft),
        )
        return ft


def _host(a, dtype):
    a = np.ascontiguousarray(a, dtype=dtype)
    return a


class UsrfrcLib:
    """LS-DYNA SMP ``usrfrc``: one call per cycle for the active slave nodes.

    ``dtype`` is the host REAL (``np.float32`` for SP, ``np.float64`` for DP builds).
    """

    def __init__(self, lib, dtype):
        self._fn = lib.h_usrfrc
        self._fn.restype = None
        self.dtype = dtype

    def __call__(self, active, ilbsv, fni, areas, stfk, sfacn3, d, rn, fdat, fxyz, ufhist):
        """``fdat`` (n, 5), ``fxyz`` (n, 3), ``ufhist`` (n_hist, nhv) are updated in place.

        ``active``: 0-based indices of the active slave nodes (LS-DYNA's ``iisv5``);
        ``ilbsv``: 0-based history row of each slave node.
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
        self._fn(
            ctypes.c_int(n),
            ctypes.c_int(iact.size),
            ctypes.c_int(nhv),
            _ptr(iact),
            _ptr(ilb),
            *map(_ptr, ins),
            _ptr(fdat),
            _ptr(fxyz),
            _ptr(ufhist),
        )


class UsrfrcMppLib:
    """LS-DYNA MPP ``usrfrc``: one call per slave node; returns ``(fstt, fdyn)`` per node."""

    def __init__(self, lib, dtype):
        self._fn = lib.h_usrfrc_mpp
        self._fn.restype = None
        self.dtype = dtype

    def __call__(self, prs, uh):
        """``uh`` (n, nh) of the host REAL is updated in place; returns (n, 2)."""
        dt = self.dtype
        if not (uh.flags.c_contiguous and uh.dtype == dt):
            raise ValueError(f"uh must be a C-contiguous {np.dtype(dt)} array")
        prs = _host(prs, dt)
        n, nh = uh.shape
        mu = np.empty((n, 2), dt)
        self._fn(ctypes.c_int(n), ctypes.c_int(nh), _ptr(prs), _ptr(uh), _ptr(mu))
        return mu


#: Abaqus/Standard ``FRIC`` (``abaqus-fric``, ``calculix``)
FRIC = Harness("shims/fric.f90", FricLib)
#: Abaqus/Explicit ``VFRIC`` (``abaqus-vfric``)
VFRIC = Harness("shims/vfric.f90", VfricLib)
#: Abaqus/Explicit ``VFRICTION`` (``abaqus-vfriction``)
VFRICTION = Harness("shims/vfriction.f90", VfrictionLib)
#: LS-DYNA SMP ``usrfrc`` (``lsdyna-usrfrc``); the driver takes ``dtype``
USRFRC = Harness("shims/usrfrc.f90", UsrfrcLib)
#: LS-DYNA MPP ``usrfrc`` (``lsdyna-usrfrc-mpp``); the driver takes ``dtype``
USRFRC_MPP = Harness("shims/usrfrc_mpp.f90", UsrfrcMppLib)
#: the host-neutral ``SBMF_FRICTION`` (``lsdyna``, ``ansys-userfric``, the Coulomb floor)
SBMF_FRICTION = Harness("shims/sbmf_friction.f90", GenericLib)
