subroutine h_usrfrc(n, nact, nhv, nua, ua_in, iact, ilb, fni, areas, stfk, sfac, d, rn, fdat, &
                    fxyz, ufhist, nosl_in) bind(c, name='h_usrfrc')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n, nact, nhv, nua, nosl_in
  real, intent(in) :: ua_in(max(nua, 1))
  integer(c_int), intent(in) :: iact(nact), ilb(n)
  real, intent(in) :: fni(n), areas(n), stfk(n), sfac(1), d(3, n), rn(3, n)
  real, intent(inout) :: fdat(5, n), fxyz(3, n), ufhist(max(nhv, 1), n)
  integer :: iisv5(nact), ilbsv(n), insv(n), lsv(n), iseg(n), ix(n), npc(1), lcf(1), isurf(1)
  integer :: nosl, ncycle, ninput, niisv5, numnp, nhvd, neps, i
  real :: dx(n), dy(n), dz(n), rn1(n), rn2(n), rn3(n), fx(n), fy(n), fz(n), ss(n), tt(n)
  real :: xs(n), aream(n), xx(4 * n), stfn(n), stf(n), ua(max(nua, 1)), frc(2, n), pld(2, 1), temp(1)
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
  xs = 0.; aream = 1.; xx = 0.; stfn = 1.; stf = 1.; ua = ua_in; frc = 1.; pld = 0.; temp = 0.
  ufeps = 0.; time = 0.; dt2 = 1.e-6; fdt2 = 1.e6; fric1 = 0.1; fric2 = 0.1; fric3 = 0.
  fric4 = 0.; bignum = 0.; npc = 1; lcf = 0; isurf = 0; iseg = 0
  nosl = nosl_in; ncycle = 1; ninput = nua; niisv5 = nact; numnp = n; nhvd = nhv; neps = 1
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
