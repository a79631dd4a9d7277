"""Host emulation: compile a generated routine with a C-callable shim, call it as its host does.

Each target's record names its :class:`Harness` (``frictionlaw.export.target(name).harness``):
an ISO_C_BINDING shim (a Fortran file shipped in ``frictionlaw/export/shims/``) that calls the
generated entry point exactly as the host's documentation describes (argument list, state passed
in as at the start of the increment) for many contact points per call, and a driver class that
calls the shim through ``ctypes`` with NumPy arrays, so that one compile serves thousands of
cases. ``ABA_PARAM.INC`` and ``vaba_param.inc`` are replaced by stubs with Abaqus' documented
content (implicit double precision), LS-DYNA's ``iounits.inc`` by a stub with its output units.
The hosts' message and exit routines are emulated too (Abaqus' ``STDB_ABQERR``/``XIT`` and
``XPLB_ABQERR``/``XPLB_EXIT``, LS-DYNA's output units): a driver's :meth:`~FricLib.log` returns
what the routine's guards wrote, :meth:`~FricLib.exits` how often it ended the analysis;
:meth:`FricLib.increment` emulates Abaqus' automatic incrementation, acting on ``PNEWDT``. The
deck's unit system (the routines' unit property, docs/fe_codes.md "Guards") is the driver's
``deck_units``: by default the one the routine was exported for. Needs ``gfortran``.

This module is public, not test support, because users need it too: it lets anyone check a
routine written for their parameter file against the Python runtime on their own machine before
giving it to a solver (the gallery example does), and a new host target brings its harness in
its record. The test suite (``tests/test_export_*.py``), ``benchmarks/bench_fortran_law.py`` and
the gallery use it; nothing in the export itself does, and ``import frictionlaw`` never loads
it.
"""

import ctypes
import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._harness_base import _f, _Host, _name80, _ptr
from ._harness_lsdyna import UsrfrcLib, UsrfrcMppLib
from ._host_increment import Attempt, Increment, run_increment
from ._law import UNIT_SYSTEMS, StiffnessSpec, core_context
from ._templates import render_template, template_path

__all__ = [
    "Harness",
    "gfortran",
    "build",
    "coulomb_source",
    "FricLib",
    "Attempt",
    "Increment",
    "VfricLib",
    "VfrictionLib",
    "UsrfrcLib",
    "UsrfrcMppLib",
    "GenericLib",
    "routine_units",
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


#: the emulated hosts' message log, compiled into every harness library
_LOG = "shims/host_log.f90"
#: stubs of the hosts' include files, written into the build folder
_STUBS = ("abaqus/ABA_PARAM.INC", "shims/vaba_param.inc", "shims/iounits.inc")


def _compile(fc, src, obj, flags, workdir):
    subprocess.run(
        [
            fc,
            "-fPIC",
            *flags,
            "-J",
            str(workdir),
            "-I",
            str(workdir),
            "-c",
            str(src),
            "-o",
            str(obj),
        ],
        check=True,
        text=True,
    )


def build(sources, workdir, name, shim, *, flags=("-O2",), support=()):
    """Compile generated ``sources`` (``{file: text}``) with ``shim`` into ``workdir/name.so``.

    Parameters
    ----------
    sources : dict
        ``{file name: text}`` as :func:`frictionlaw.export.render` returns them; the ``.f``
        files are compiled (with ``-Wall``), the others ignored.
    workdir : path
        Build folder (made if needed); the ``ABA_PARAM.INC``, ``vaba_param.inc`` and
        ``iounits.inc`` stubs go there.
    name : str
        Name of the shared library (and a suffix of the object files).
    shim : str or path
        The shim's Fortran file: a path below ``frictionlaw/export`` (``"shims/fric.f90"``) or
        an absolute path.
    flags : tuple of str
        gfortran flags for every file (e.g. :data:`HOST_PRECISION_FLAGS`, ``-fopenmp``).
    support : tuple of str
        Further emulation files compiled with the shim (the host's utility routines); the
        message log ``shims/host_log.f90`` always is.

    Returns
    -------
    (ctypes.CDLL, str)
        The library and gfortran's warnings on the generated files (the shim is compiled
        separately, without ``-Wall``).
    """
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    for stub in _STUBS:
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
    for i, part in enumerate((_LOG, *support, shim)):
        src = workdir / f"shim{i}_{name}.f90"
        src.write_text(template_path(part).read_text(encoding="utf-8"))
        obj = src.with_suffix(".o")
        _compile(fc, src, obj, flags, workdir)
        objs.append(obj)
    lib = workdir / f"{name}.so"
    subprocess.run([fc, "-shared", *flags, *map(str, objs), "-o", str(lib)], check=True)
    return ctypes.CDLL(str(lib)), "".join(warnings)


def routine_units(sources):
    """The unit system code (1 SI, 2 mm-t-s) the generated ``sources`` were exported for.

    Read from the provenance header's ``units:`` line; None if no source carries one.
    """
    for text in sources.values():
        m = re.search(r"^\S+ units: (\S+) \(", text, flags=re.M)
        if m and m.group(1) in UNIT_SYSTEMS:
            return UNIT_SYSTEMS[m.group(1)].code
    return None


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
    support : tuple of str
        Further emulation files (the host's utility routines: ``XPLB_ABQERR``, LS-DYNA's
        output units).
    """

    shim: str
    driver: type
    support: tuple = ()

    def load(self, sources, workdir, *, name="routine", flags=("-O2",), **options):
        """Compile ``sources`` with this shim (:func:`build`) and wrap the library.

        Returns ``(driver instance, gfortran's warnings)``; ``options`` go to the driver (the
        LS-DYNA drivers take the host REAL as ``dtype``; every driver ``deck_units``, the unit
        system the emulated deck states, by default the routine's own).
        """
        lib, warnings = build(sources, workdir, name, self.shim, flags=flags, support=self.support)
        if issubclass(self.driver, _Host):
            options.setdefault("deck_units", routine_units(sources))
        return self.driver(lib, **options), warnings


def coulomb_source(params):
    """The benchmark's floor: a plain Coulomb ``SBMF_FRICTION`` (``mu = 0.1``), core included.

    The same entry, return map and calling cost as the law's host-neutral entry, above the law
    core of ``params`` in SI; driven by :data:`SBMF_FRICTION`.
    """
    context = core_context(params, UNIT_SYSTEMS["SI"], StiffnessSpec("host"))
    context["guard_text"] = context["guard"].messages("state variables", ("IUNIT", "its value"))
    context["guard_kinds"] = 6
    return render_template("shims/coulomb.f", guards=True, **context)


class FricLib(_Host):
    """Abaqus/Standard ``FRIC`` called per contact point as Abaqus does.

    The unit property is ``PROPS(1)`` (``NPROPS = 0`` when ``deck_units`` is None). After an
    error exit (``XIT``) the remaining points are not called: their outputs are NaN. ``PNEWDT``
    is set to a large value before each call (as Abaqus does) and returned per point;
    :meth:`increment` emulates the automatic incrementation that acts on it.
    """

    def __init__(self, lib, deck_units=None):
        super().__init__(lib, deck_units)
        self._fn = lib.h_fric
        self._fn.restype = None

    def __call__(
        self,
        press,
        dgam,
        tau_start,
        statev_start,
        chrlngth,
        reps=1,
        out=None,
        *,
        kstep=1,
        kinc=1,
        dtime=1.0,
        ciname="CP",
        slname="SLAVE",
        msname="MASTER",
        predef=None,
    ):
        """One iteration: every point gets the start-of-increment ``TAU`` and ``STATEV``.

        Arrays are (n,), (n, nd), (n, nd), (n, nstatv), (n,); returns a dict of outputs
        (``out``: a dict a former call returned, reused; ``reps``: the points called that many
        times, for timing). ``kstep``, ``kinc``, ``dtime``: the step, the increment and its
        size (``KSTEP``, ``KINC``, ``DTIME``) of every call; ``ciname``, ``slname``,
        ``msname``: the contact interaction's and the surfaces' names (``CHARACTER*80``) every
        call passes (a zoned routine chooses its law by one of them). ``predef``: (n, 2), each
        point's predefined field 1 (``PREDEF(1, 1)``, ``PREDEF(2, 1)``: the patched CalculiX's
        slave-element plastic strain and its increment), passed with ``NPRED = 1``; None:
        ``NPRED = 0``.
        """
        press, dgam, tau_start, sv = map(_f, (press, dgam, tau_start, statev_start))
        npred = 0 if predef is None else 1
        fields = _f(np.zeros((press.shape[0], 2)) if predef is None else predef)
        chr_ = _f(np.broadcast_to(chrlngth, press.shape))
        n, nd = dgam.shape
        nsv = sv.shape[1]
        if out is None:
            out = {
                "tau": np.full((n, nd), np.nan),
                "ddtddg": np.full((n, nd, nd), np.nan),
                "ddtddp": np.full((n, nd), np.nan),
                "dslip": np.full((n, nd), np.nan),
                "statev": np.full((n, nsv), np.nan),
                "lm": np.full(n, -1, np.int32),
                "sed": np.full(n, np.nan),
                "sfd": np.full(n, np.nan),
                "pnewdt": np.full(n, np.nan),
            }
        else:  # a former call's outputs: DDTDDG back to the Fortran layout (a view)
            out = {**out, "ddtddg": out["ddtddg"].transpose(0, 2, 1)}
            assert out["ddtddg"].flags.c_contiguous
        nprops, props = self._props()
        self._fn(
            ctypes.c_int(n),
            ctypes.c_int(nd),
            ctypes.c_int(nsv),
            ctypes.c_int(reps),
            ctypes.c_int(nprops),
            _ptr(props),
            ctypes.c_int(kstep),
            ctypes.c_int(kinc),
            ctypes.c_double(dtime),
            *map(_ptr, (press, dgam, tau_start, sv, chr_)),
            *map(_ptr, out.values()),
            *map(_name80, (ciname, slname, msname)),
            ctypes.c_int(npred),
            _ptr(fields),
        )
        # Fortran DDTDDG(a, b) -> row-major [b, a] in memory: transposed to [a, b] (a view)
        return {**out, "ddtddg": out["ddtddg"].transpose(0, 2, 1)}

    def increment(self, iterates, dgam, tau_start, statev_start, chrlngth, **options):
        """One increment of Abaqus' automatic incrementation, acting on ``PNEWDT``.

        ``iterates(dtime)`` gives the Newton iterates of an attempt of size ``dtime``: a
        sequence of pressure arrays (n,), the last one its converged state. Every iterate calls
        ``FRIC`` at every point with the start-of-increment ``TAU`` and ``STATEV``; a
        ``PNEWDT < 1`` abandons the attempt and retries it at ``PNEWDT`` times its size.
        ``options``: ``kstep``, ``kinc``, ``dtime`` (the first attempt's size; 1, 1, 1.0),
        ``max_cutbacks`` (5, Abaqus' ``IA``), ``names`` (``{"ciname": ...}``, the names every
        call passes). Returns an :class:`Increment` (its ``out``: the
        converged iterate's outputs, whose ``statev`` the host commits).
        """
        return run_increment(self, iterates, dgam, tau_start, statev_start, chrlngth, **options)


class VfricLib(_Host):
    """Abaqus/Explicit ``VFRIC`` called once per increment for all contact points.

    The unit property is ``props(1)``.
    """

    def __init__(self, lib, deck_units=None):
        super().__init__(lib, deck_units)
        self._fn = lib.h_vfric
        self._fn.restype = None

    def __call__(
        self, f_normal, f_stick, area, statev, *, surf_int="SBMF", surf_sec="SEC", surf_main="MAIN"
    ):
        """``statev`` (n, nstatev) is updated in place; returns ``fTangential`` (n, 2).

        ``surf_int``, ``surf_sec``, ``surf_main``: the names the call passes (``surfInt``, the
        contact pair's interaction; ``surfSec``, ``surfMain``, its surfaces).
        """
        f_normal, f_stick, area = map(_f, (f_normal, f_stick, area))
        if not (statev.flags.c_contiguous and statev.dtype == np.float64):
            raise ValueError("statev must be a C-contiguous float64 array")
        n, nsv = statev.shape
        ft = np.full((n, 2), np.nan)
        nprops, props = self._props()
        self._fn(
            ctypes.c_int(n),
            ctypes.c_int(nsv),
            ctypes.c_int(nprops),
            _ptr(props),
            *map(_ptr, (f_normal, f_stick, area)),
            _ptr(statev),
            _ptr(ft),
            *map(_name80, (surf_int, surf_sec, surf_main)),
        )
        return ft


class GenericLib(_Host):
    """The host-neutral entry over many contact points (LS-DYNA, ANSYS glue).

    :meth:`friction` calls ``SBMF_FRICTION_V`` (interface version 2: the zone's name, the bulk
    strain, the state array), calling the instance the deprecated ``SBMF_FRICTION`` (version 1,
    a wrapper of it). The unit property is the argument ``IUNIT`` (0 when ``deck_units`` is
    None); the guards' status comes back per point as ``ierr``.
    """

    def __init__(self, lib, deck_units=None):
        super().__init__(lib, deck_units)
        self._fn = lib.h_generic
        self._fn.restype = None
        lib.h_message.restype = ctypes.c_int
        lib.h_zmessage.restype = ctypes.c_int
        lib.h_generic_v.restype = None

    def message(self, kind, value=0.0):
        """``SBMF_MESSAGE``'s text for ``kind`` (``abs(ierr)``) and ``value``."""
        buf = ctypes.create_string_buffer(400)
        n = self._lib.h_message(ctypes.c_int(kind), ctypes.c_double(value), buf, len(buf))
        return buf.raw[:n].decode()

    def __call__(self, p, p_hist, g1h, du, t_old, k_host, reps=1, out=None):
        """Call ``SBMF_FRICTION`` for every point ``reps`` times.

        Returns a dict: ``t``, ``dt_ddu``, ``dt_dp``, ``status``, ``p_hist``, ``g1h``, ``ierr``.
        """
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
                "ierr": np.empty(n, np.int32),
            }
        iunit = 0 if self.deck_units is None else int(self.deck_units)
        self._fn(
            ctypes.c_int(n),
            ctypes.c_int(nd),
            ctypes.c_int(reps),
            ctypes.c_int(iunit),
            *map(_ptr, (p, p_hist, g1h, du, t_old, kh)),
            *map(_ptr, out.values()),
        )
        return out

    def friction(self, zone, p, state, du, t_old, k_host, *, deps=0.0, sigy=0.0, version=2, reps=1):
        """Call ``SBMF_FRICTION_V`` (interface version 2) for every point ``reps`` times.

        ``zone``: the name every call passes; ``state`` (n, nstate): the committed state,
        updated in place to the trial state; ``deps``, ``sigy``: the bulk plastic strain
        increment and flow stress per point (or scalars); ``version``: the ``IVERS`` passed.
        Returns a dict: ``t``, ``dt_ddu``, ``dt_dp``, ``status``, ``ierr``.
        """
        p, du, t_old = map(_f, (p, du, t_old))
        if not (state.flags.c_contiguous and state.dtype == np.float64 and state.ndim == 2):
            raise ValueError("state must be a C-contiguous float64 array (n, nstate)")
        kh, de, sy = (_f(np.broadcast_to(v, p.shape)) for v in (k_host, deps, sigy))
        n, nd = du.shape
        out = {
            "t": np.empty((n, nd)),
            "dt_ddu": np.empty((n, nd, nd)),
            "dt_dp": np.empty((n, nd)),
            "status": np.empty(n, np.int32),
            "ierr": np.empty(n, np.int32),
        }
        name = str(zone).encode("ascii")
        iunit = 0 if self.deck_units is None else int(self.deck_units)
        self._lib.h_generic_v(
            ctypes.c_int(n),
            ctypes.c_int(nd),
            ctypes.c_int(reps),
            ctypes.c_int(iunit),
            ctypes.c_int(version),
            ctypes.create_string_buffer(name, max(len(name), 1)),
            ctypes.c_int(len(name)),
            ctypes.c_int(state.shape[1]),
            *map(_ptr, (p, du, t_old, kh, de, sy, state)),
            *map(_ptr, out.values()),
        )
        return out

    def zone_message(self, zone):
        """``SBMF_ZMESSAGE``'s text for the zone name ``zone`` (status -7)."""
        name = str(zone).encode("ascii")
        buf = ctypes.create_string_buffer(400)
        n = self._lib.h_zmessage(
            ctypes.create_string_buffer(name, max(len(name), 1)), ctypes.c_int(len(name)), buf, 400
        )
        return buf.raw[:n].decode()

    @staticmethod
    def tangent(out):
        """``dt_ddu`` as [node, a, b] (the Fortran array is column-major per node)."""
        return out["dt_ddu"].transpose(0, 2, 1)


class VfrictionLib(_Host):
    """Abaqus/Explicit ``VFRICTION`` called once for a block of contact points.

    The unit property is ``props(1)``.
    """

    def __init__(self, lib, deck_units=None):
        super().__init__(lib, deck_units)
        self._fn = lib.h_vfriction
        self._fn.restype = None

    def __call__(
        self, f_normal, f_stick, area, state, *, surf_int="SBMF", surf_slv=" ", surf_mst=" "
    ):
        """``state`` (n, nNodState, nStates) is updated in place; returns ``fTangential`` (n, 2).

        ``surf_int``, ``surf_slv``, ``surf_mst``: the names the call passes (``surfInt``,
        ``surfSlv``, ``surfMst``).
        """
        f_normal, f_stick, area = map(_f, (f_normal, f_stick, area))
        if not (state.flags.c_contiguous and state.dtype == np.float64):
            raise ValueError("state must be a C-contiguous float64 array")
        n, nns, nsv = state.shape
        ft = np.full((n, 2), np.nan)
        nprops, props = self._props()
        self._fn(
            ctypes.c_int(n),
            ctypes.c_int(nns),
            ctypes.c_int(nsv),
            ctypes.c_int(nprops),
            _ptr(props),
            *map(_ptr, (f_normal, f_stick, area)),
            _ptr(state),
            _ptr(ft),
            *map(_name80, (surf_int, surf_slv, surf_mst)),
        )
        return ft


FRIC = Harness("shims/fric.f90", FricLib)
#: Abaqus/Explicit ``VFRIC`` (``abaqus-vfric``)
VFRIC = Harness("shims/vfric.f90", VfricLib, ("shims/explicit_utilities.f90",))
#: Abaqus/Explicit ``VFRICTION`` (``abaqus-vfriction``)
VFRICTION = Harness("shims/vfriction.f90", VfrictionLib, ("shims/explicit_utilities.f90",))
#: LS-DYNA SMP ``usrfrc`` (``lsdyna-usrfrc``); the driver takes ``dtype``
USRFRC = Harness("shims/usrfrc.f90", UsrfrcLib, ("shims/lsdyna_units.f90",))
#: LS-DYNA MPP ``usrfrc`` (``lsdyna-usrfrc-mpp``); the driver takes ``dtype``
USRFRC_MPP = Harness("shims/usrfrc_mpp.f90", UsrfrcMppLib, ("shims/lsdyna_units.f90",))
#: the host-neutral ``SBMF_FRICTION`` (``lsdyna``, ``ansys-userfric``, the Coulomb floor)
SBMF_FRICTION = Harness("shims/sbmf_friction.f90", GenericLib)
