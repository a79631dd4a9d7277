"""Host emulation for the generated Fortran: C-callable shims, gfortran build, ctypes calls.

Used by the tests and ``benchmarks/bench_fortran_law.py``. Each shim calls the generated entry
point exactly as the host's documentation describes (argument list, state passed in as at the
start of the increment), for many contact points per call, so that one compile serves thousands
of cases. ``ABA_PARAM.INC`` and ``vaba_param.inc`` are replaced by stubs with Abaqus' documented
content (implicit double precision).
"""

import ctypes
import shutil
import subprocess
from pathlib import Path

import numpy as np

from ._fortran import ABA_PARAM_INC

__all__ = [
    "gfortran",
    "build",
    "FricLib",
    "VfricLib",
    "VfrictionLib",
    "UsrfrcLib",
    "UsrfrcMppLib",
    "GenericLib",
    "COULOMB_SOURCE",
    "HOST_PRECISION_FLAGS",
]

#: gfortran flags of the LS-DYNA host precisions: SP as is; DP as ifort's ``-r8 -i8`` (LSTC's
#: user-object makefiles), i.e. default REAL, DOUBLE PRECISION and INTEGER all 8 bytes
HOST_PRECISION_FLAGS = {
    "SP": (),
    "DP": ("-fdefault-real-8", "-fdefault-double-8", "-fdefault-integer-8"),
}

_VABA_PARAM = (
    "      implicit real*8 (a-h,o-z)\n"
    "      parameter (j_sys_Dimension = 2)\n"
    "      parameter (n_vec_Length = 136)\n"
    "      parameter (maxblk = n_vec_Length)\n"
)

_SHIM_FRIC = """
subroutine h_fric(n, nd, nstatv, press, dgam, tau_in, sv_in, chr, tau_out, dtdg, dtdp, &
                  dslip, sv_out, lm_out, sed, sfd) bind(c, name='h_fric')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n, nd, nstatv
  real(c_double), intent(in) :: press(n), dgam(nd, n), tau_in(nd, n), sv_in(nstatv, n), chr(n)
  real(c_double), intent(out) :: tau_out(nd, n), dtdg(nd, nd, n), dtdp(nd, n), dslip(nd, n)
  real(c_double), intent(out) :: sv_out(nstatv, n), sed(n), sfd(n)
  integer(c_int), intent(out) :: lm_out(n)
  integer :: i, lm, kstep, kinc, noel, npt, node, npatch, mcrd, npred, nprops
  double precision :: tau(nd), dd(nd, nd), ddp(nd), ds(nd), ddtddt(nd, 2), statev(nstatv)
  double precision :: dg(nd), taulm(nd), slip(nd), time(2), coords(3), rcoord(3), drot(2, 2)
  double precision :: temp(2), predef(2, 1), props(1), pnewdt, dpress, ddpddh, dtime, sedv, sfdv
  character(len=80) :: ciname, slname, msname
  kstep = 1; kinc = 1; noel = 1; npt = 1; node = 1; npatch = 1; mcrd = 3; npred = 0
  nprops = 0; time = 0d0; dtime = 1d0; coords = 0d0; rcoord = 0d0; drot = 0d0; temp = 0d0
  predef = 0d0; props = 0d0; taulm = 0d0; slip = 0d0; dpress = 0d0; ddpddh = 0d0
  ciname = 'CP'; slname = 'SLAVE'; msname = 'MASTER'
  do i = 1, n
    lm = 0
    pnewdt = 1d0
    tau = tau_in(:, i)
    statev = sv_in(:, i)
    dg = dgam(:, i)
    call fric(lm, tau, dd, ddp, ds, sedv, sfdv, ddtddt, pnewdt, statev, dg, taulm, press(i), &
              dpress, ddpddh, slip, kstep, kinc, time, dtime, noel, ciname, slname, msname, &
              npt, node, npatch, coords, rcoord, drot, temp, predef, nd, mcrd, npred, nstatv, &
              chr(i), props, nprops)
    tau_out(:, i) = tau
    dtdg(:, :, i) = dd
    dtdp(:, i) = ddp
    dslip(:, i) = ds
    sv_out(:, i) = statev
    lm_out(i) = lm
    sed(i) = sedv
    sfd(i) = sfdv
  end do
end subroutine h_fric
"""

_SHIM_VFRIC = """
subroutine h_vfric(n, nsv, fnormal, fstick, area, statev, ftang) bind(c, name='h_vfric')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n, nsv
  real(c_double), intent(in) :: fnormal(n), fstick(n), area(n)
  real(c_double), intent(inout) :: statev(nsv, n)
  real(c_double), intent(out) :: ftang(2, n)
  integer :: i, jsec(n), jmain(1), jcons(n), jconm(1, n)
  double precision :: dslip(3, n), fprev(3, n), fwork(n), shp(1, n), csec(3, n), cmain(3, 1)
  double precision :: dcs(3, n), dcn(3, n), props(1), tsec(n), pdsec(n, 1), tmain(1), pdmain(1, 1)
  character(len=80) :: sint, ssec, smain
  do i = 1, n
    jsec(i) = i
    jcons(i) = i
    jconm(1, i) = 1
  end do
  jmain = 1
  dslip = 0d0; fprev = 0d0; fwork = 0d0; shp = 1d0; csec = 0d0; cmain = 0d0; dcs = 0d0
  dcn = 0d0; props = 0d0; tsec = 0d0; pdsec = 0d0; tmain = 0d0; pdmain = 0d0
  sint = 'SBMF'; ssec = 'SEC'; smain = 'MAIN'
  call vfric(ftang, statev, 1, 1, n, 1, n, 1, 2, 3, nsv, 0, 0, 1, 1, jsec, jmain, jcons, jconm, &
             1d-6, 0d0, 1d-6, sint, ssec, smain, 1, dslip, fstick, fprev, fnormal, fwork, shp, &
             csec, cmain, dcs, dcn, props, area, tsec, pdsec, tmain, pdmain)
end subroutine h_vfric
"""

_SHIM_GENERIC = """
subroutine h_generic(n, nd, reps, p, ph, g1h, du, told, khost, tnew, dtddu, dtdp, istat, &
                     phnew, g1new) bind(c, name='h_generic')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n, nd, reps
  real(c_double), intent(in) :: p(n), ph(n), g1h(n), du(nd, n), told(nd, n), khost(n)
  real(c_double), intent(out) :: tnew(nd, n), dtddu(nd, nd, n), dtdp(nd, n), phnew(n), g1new(n)
  integer(c_int), intent(out) :: istat(n)
  integer :: i, r, ist
  do r = 1, reps
    do i = 1, n
      call sbmf_friction(nd, p(i), ph(i), g1h(i), du(1, i), told(1, i), khost(i), tnew(1, i), &
                         dtddu(1, 1, i), dtdp(1, i), ist, phnew(i), g1new(i))
      istat(i) = ist
    end do
  end do
end subroutine h_generic
"""

_SHIM_VFRICTION = """
subroutine h_vfriction(n, nns, nsv, fnormal, fstick, area, state, ftang) bind(c, name='h_vfriction')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n, nns, nsv
  real(c_double), intent(in) :: fnormal(n), fstick(n), area(n)
  real(c_double), intent(inout) :: state(nsv, nns, n)
  real(c_double), intent(out) :: ftang(2, n)
  integer :: jflags(3), jslv(nns, n), jmst(4, n)
  double precision :: rdata(4), props(1), dslip(3, n), fprev(3, n), dcn(3, n), dcs(3, n)
  double precision :: shs(nns, n), shm(4, n), cs(3, nns, n), cm(3, 4, n), vs(3, nns, n)
  double precision :: vm(3, 4, n), ts(n), tm(n), fs(1, n), fm(1, n)
  character(len=80) :: sint, sslv, smst
  jflags = 1; rdata = 0d0; props = 0d0; dslip = 0d0; fprev = 0d0; dcn = 0d0; dcs = 0d0
  jslv = 1; jmst = 1; shs = 1d0; shm = 0.25d0; cs = 0d0; cm = 0d0; vs = 0d0; vm = 0d0
  ts = 0d0; tm = 0d0; fs = 0d0; fm = 0d0
  sint = 'SBMF'; sslv = ' '; smst = ' '
  call vfriction(ftang, state, n, n, n, nns, nns, 4, 2, 3, nsv, 0, 0, 1, jflags, rdata, &
                 sint, sslv, smst, jslv, jmst, props, dslip, fstick, fprev, fnormal, area, &
                 dcn, dcs, shs, shm, cs, cm, vs, vm, ts, tm, fs, fm)
end subroutine h_vfriction
"""

# The LS-DYNA shims use the host's default REAL/INTEGER (compiled with the same precision
# flags as the routine); the C side passes float32 or float64 arrays accordingly.
_SHIM_USRFRC = """
subroutine h_usrfrc(n, nact, nhv, iact, ilb, fni, areas, stfk, sfac, d, rn, fdat, fxyz, &
                    ufhist) bind(c, name='h_usrfrc')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n, nact, nhv
  integer(c_int), intent(in) :: iact(nact), ilb(n)
  real, intent(in) :: fni(n), areas(n), stfk(n), sfac(1), d(3, n), rn(3, n)
  real, intent(inout) :: fdat(5, n), fxyz(3, n), ufhist(max(nhv, 1), n)
  integer :: iisv5(nact), ilbsv(n), insv(n), lsv(n), iseg(n), ix(n), npc(1), lcf(1), isurf(1)
  integer :: nosl, ncycle, ninput, niisv5, numnp, nhvd, neps, i
  real :: dx(n), dy(n), dz(n), rn1(n), rn2(n), rn3(n), fx(n), fy(n), fz(n), ss(n), tt(n)
  real :: xs(n), aream(n), xx(4 * n), stfn(n), stf(n), ua(1), frc(2, n), pld(2, 1), temp(1)
  real :: ufeps(1), time, dt2, fdt2, fric1, fric2, fric3, fric4, bignum, sfacn3
  do i = 1, nact
    iisv5(i) = iact(i)
  end do
  do i = 1, n
    ilbsv(i) = ilb(i)
    insv(i) = i
    lsv(i) = i
    ix(i) = i
    dx(i) = d(1, i)
    dy(i) = d(2, i)
    dz(i) = d(3, i)
    rn1(i) = rn(1, i)
    rn2(i) = rn(2, i)
    rn3(i) = rn(3, i)
    fx(i) = fxyz(1, i)
    fy(i) = fxyz(2, i)
    fz(i) = fxyz(3, i)
    ss(i) = 0.5
    tt(i) = -0.5
  end do
  xs = 0.; aream = 1.; xx = 0.; stfn = 1.; stf = 1.; ua = 0.; frc = 1.; pld = 0.; temp = 0.
  ufeps = 0.; time = 0.; dt2 = 1.e-6; fdt2 = 1.e6; fric1 = 0.1; fric2 = 0.1; fric3 = 0.
  fric4 = 0.; bignum = 0.; npc = 1; lcf = 0; isurf = 0; iseg = 0
  nosl = 1; ncycle = 1; ninput = 0; niisv5 = nact; numnp = n; nhvd = nhv; neps = 1
  sfacn3 = sfac(1)
  call usrfrc(nosl, time, ncycle, dt2, insv, areas, xs, xs, xs, lsv, ix, ix, ix, ix, aream, &
              xx, xx, xx, stfn, stf, fni, dx, dy, dz, fdt2, ninput, ua, 'master', iisv5, &
              niisv5, rn1, rn2, rn3, fric1, fric2, fric3, fric4, bignum, fdat, iseg, fx, fy, &
              fz, ss, tt, ilbsv, stfk, frc, numnp, npc, pld, lcf, lcf, temp, temp, temp, &
              isurf, nhvd, ufhist, neps, ufeps, sfacn3)
  ! copy back the active nodes only: threads may share these arrays over disjoint node sets
  do i = 1, nact
    fxyz(1, iact(i)) = fx(iact(i))
    fxyz(2, iact(i)) = fy(iact(i))
    fxyz(3, iact(i)) = fz(iact(i))
  end do
end subroutine h_usrfrc
"""

_SHIM_USRFRC_MPP = """
subroutine h_usrfrc_mpp(n, nh, prs, uh, mu) bind(c, name='h_usrfrc_mpp')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n, nh
  real, intent(in) :: prs(n)
  real, intent(inout) :: uh(max(nh, 1), n)
  real, intent(out) :: mu(2, n)
  integer :: i, nc, nhd, nnp(1), nosl, ictype, ncycle, lsv, insv, ix, ne
  integer*8 :: idele8
  real :: uc(1), ue(1), crv(1), fs, fd, z
  nc = 0; nhd = nh; nnp = 1; nosl = 1; ictype = 4; ncycle = 1; lsv = 1; insv = 1; ix = 1
  ne = 0; idele8 = 1; uc = 0.; ue = 0.; crv = 0.; z = 0.
  do i = 1, n
    call usrfrc(fs, fd, uc, nc, prs(i), z, z, uh(1, i), nhd, crv, nnp, nosl, ictype, &
                'master', z, ncycle, z, z, z, z, z, lsv, idele8, z, z, insv, z, z, z, ix, &
                ix, ix, ix, z, z, z, z, ue, ne)
    mu(1, i) = fs
    mu(2, i) = fd
  end do
end subroutine h_usrfrc_mpp
"""

#: plain Coulomb routine with the same entry, return map and calling cost (the benchmark floor)
COULOMB_SOURCE = """\
      SUBROUTINE SBMF_FRICTION(ND, P, PH, G1H, DU, TOLD, KHOST, TNEW,
     &                         DTDDU, DTDP, ISTAT, PHNEW, G1NEW)
      IMPLICIT NONE
      INTEGER ND, ISTAT, A, B
      DOUBLE PRECISION P, PH, G1H, DU(ND), TOLD(ND), KHOST, TNEW(ND)
      DOUBLE PRECISION DTDDU(ND, ND), DTDP(ND), PHNEW, G1NEW, TLIM, XMU
      PARAMETER (XMU = 0.1D0)
      PHNEW = PH
      G1NEW = G1H
      IF (.NOT. (P .GT. 0.0D0)) THEN
        DO A = 1, ND
          TNEW(A) = 0.0D0
          DTDP(A) = 0.0D0
          DO B = 1, ND
            DTDDU(A, B) = 0.0D0
          END DO
        END DO
        ISTAT = 0
        RETURN
      END IF
      TLIM = XMU*P
      CALL SBMF_RMAP(ND, TLIM, XMU, DU, TOLD, KHOST, TNEW, DTDDU, DTDP,
     &               ISTAT)
      RETURN
      END
"""


def gfortran():
    """Path of ``gfortran`` or None."""
    return shutil.which("gfortran")


def build(sources, workdir, name, shim, *, flags=("-O2",)):
    """Compile generated ``sources`` (``{file: text}``) with ``shim`` into ``workdir/name.so``.

    Returns ``(ctypes.CDLL, warnings)`` where ``warnings`` is gfortran's ``-Wall`` output for
    the generated files (the shim is compiled separately).
    """
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "ABA_PARAM.INC").write_text(ABA_PARAM_INC)
    (workdir / "vaba_param.inc").write_text(_VABA_PARAM)
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
    shim_src.write_text(
        {
            "fric": _SHIM_FRIC,
            "vfric": _SHIM_VFRIC,
            "generic": _SHIM_GENERIC,
            "vfriction": _SHIM_VFRICTION,
            "usrfrc": _SHIM_USRFRC,
            "usrfrc_mpp": _SHIM_USRFRC_MPP,
        }[shim]
    )
    shim_obj = workdir / f"shim_{name}.o"
    subprocess.run(
        [fc, "-fPIC", *flags, "-c", str(shim_src), "-o", str(shim_obj)], check=True, text=True
    )
    lib = workdir / f"{name}.so"
    subprocess.run(
        [fc, "-shared", *flags, *map(str, objs), str(shim_obj), "-o", str(lib)], check=True
    )
    return ctypes.CDLL(str(lib)), "".join(warnings)


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
