subroutine h_fric(n, nd, nstatv, reps, nprops, props, kstep_in, kinc_in, dtime_in, press, &
                  dgam, tau_in, sv_in, chr, tau_out, dtdg, dtdp, dslip, sv_out, lm_out, sed, &
                  sfd, pnewdt_out, ci, sl, ms, npred_in, predef_in) bind(c, name='h_fric')
  use iso_c_binding
  use sbmf_host_log, only: exits
  implicit none
  integer(c_int), value :: n, nd, nstatv, reps, nprops, kstep_in, kinc_in, npred_in
  real(c_double), value :: dtime_in
  real(c_double), intent(in) :: props(max(nprops, 1))
  real(c_double), intent(in) :: press(n), dgam(nd, n), tau_in(nd, n), sv_in(nstatv, n), chr(n)
  real(c_double), intent(out) :: tau_out(nd, n), dtdg(nd, nd, n), dtdp(nd, n), dslip(nd, n)
  real(c_double), intent(out) :: sv_out(nstatv, n), sed(n), sfd(n), pnewdt_out(n)
  integer(c_int), intent(out) :: lm_out(n)
  character(kind=c_char), intent(in) :: ci(80), sl(80), ms(80)  ! CINAME, SLNAME, MSNAME
  real(c_double), intent(in) :: predef_in(2, n)  ! field 1 per point (read where npred_in = 1)
  integer :: i, j, r, lm, kstep, kinc, noel, npt, node, npatch, mcrd, npred, np
  double precision :: tau(nd), dd(nd, nd), ddp(nd), ds(nd), ddtddt(nd, 2), statev(nstatv)
  double precision :: dg(nd), taulm(nd), slip(nd), time(2), coords(3), rcoord(3), drot(2, 2)
  double precision :: temp(2), predef(2, 1), pr(max(nprops, 1)), pnewdt, dpress, ddpddh
  double precision :: dtime, sedv, sfdv
  character(len=80) :: ciname, slname, msname
  kstep = kstep_in; kinc = kinc_in; noel = 1; npt = 1; node = 1; npatch = 1; mcrd = 3
  npred = npred_in; np = nprops; time = 0d0; dtime = dtime_in; coords = 0d0; rcoord = 0d0
  drot = 0d0; temp = 0d0; predef = 0d0; pr = props; taulm = 0d0; slip = 0d0; dpress = 0d0; ddpddh = 0d0
  do j = 1, 80
    ciname(j:j) = ci(j); slname(j:j) = sl(j); msname(j:j) = ms(j)
  end do
  do r = 1, reps  ! reps > 1: the same points again (benchmarks/bench_fortran_law.py)
  do i = 1, n
    lm = 0
    pnewdt = 1d30  ! Abaqus sets PNEWDT to a large value before each call
    tau = tau_in(:, i)
    statev = sv_in(:, i)
    dg = dgam(:, i)
    if (npred >= 1) predef(:, 1) = predef_in(:, i)
    call fric(lm, tau, dd, ddp, ds, sedv, sfdv, ddtddt, pnewdt, statev, dg, taulm, press(i), &
              dpress, ddpddh, slip, kstep, kinc, time, dtime, noel, ciname, slname, msname, &
              npt, node, npatch, coords, rcoord, drot, temp, predef, nd, mcrd, npred, nstatv, &
              chr(i), pr, np)
    if (exits > 0) return  ! the host's error exit ended the analysis
    tau_out(:, i) = tau
    dtdg(:, :, i) = dd
    dtdp(:, i) = ddp
    dslip(:, i) = ds
    sv_out(:, i) = statev
    lm_out(i) = lm
    sed(i) = sedv
    sfd(i) = sfdv
    pnewdt_out(i) = pnewdt
  end do
  end do
end subroutine h_fric

! Abaqus/Standard's utility routines, as the harness emulates them: the message is logged with
! its LOP (%I, %R, %S are not substituted), XIT counts an error exit and returns.
subroutine stdb_abqerr(lop, string, intv, realv, charv)
  use sbmf_host_log, only: log_line
  implicit none
  integer :: lop, intv(*)
  character(len=*) :: string
  double precision :: realv(*)
  character(len=8) :: charv(*)
  if (.false.) print *, intv(1), realv(1), charv(1)
  call log_line(lop, string)
end subroutine stdb_abqerr

subroutine xit()
  use sbmf_host_log, only: log_exit
  implicit none
  call log_exit()
end subroutine xit
