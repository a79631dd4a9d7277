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
