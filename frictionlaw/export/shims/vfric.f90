subroutine h_vfric(n, nsv, nprops, props, fnormal, fstick, area, statev, ftang, si, ss, sm) &
    bind(c, name='h_vfric')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n, nsv, nprops
  real(c_double), intent(in) :: props(max(nprops, 1))
  real(c_double), intent(in) :: fnormal(n), fstick(n), area(n)
  real(c_double), intent(inout) :: statev(nsv, n)
  real(c_double), intent(out) :: ftang(2, n)
  character(kind=c_char), intent(in) :: si(80), ss(80), sm(80)  ! surfInt, surfSec, surfMain
  integer :: i, j, jsec(n), jmain(1), jcons(n), jconm(1, n)
  double precision :: dslip(3, n), fprev(3, n), fwork(n), shp(1, n), csec(3, n), cmain(3, 1)
  double precision :: dcs(3, n), dcn(3, n), pr(max(nprops, 1)), tsec(n), pdsec(n, 1)
  double precision :: tmain(1), pdmain(1, 1)
  character(len=80) :: sint, ssec, smain
  do i = 1, n
    jsec(i) = i
    jcons(i) = i
    jconm(1, i) = 1
  end do
  jmain = 1
  dslip = 0d0; fprev = 0d0; fwork = 0d0; shp = 1d0; csec = 0d0; cmain = 0d0; dcs = 0d0
  dcn = 0d0; pr = props; tsec = 0d0; pdsec = 0d0; tmain = 0d0; pdmain = 0d0
  do j = 1, 80
    sint(j:j) = si(j); ssec(j:j) = ss(j); smain(j:j) = sm(j)
  end do
  call vfric(ftang, statev, 1, 1, n, 1, n, 1, 2, 3, nsv, nprops, 0, 1, 1, jsec, jmain, jcons, &
             jconm, 1d-6, 0d0, 1d-6, sint, ssec, smain, 1, dslip, fstick, fprev, fnormal, &
             fwork, shp, csec, cmain, dcs, dcn, pr, area, tsec, pdsec, tmain, pdmain)
end subroutine h_vfric
