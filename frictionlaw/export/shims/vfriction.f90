subroutine h_vfriction(n, nns, nsv, nprops, props, fnormal, fstick, area, state, ftang, si, &
                       ss, sm) bind(c, name='h_vfriction')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n, nns, nsv, nprops
  real(c_double), intent(in) :: props(max(nprops, 1))
  real(c_double), intent(in) :: fnormal(n), fstick(n), area(n)
  real(c_double), intent(inout) :: state(nsv, nns, n)
  real(c_double), intent(out) :: ftang(2, n)
  character(kind=c_char), intent(in) :: si(80), ss(80), sm(80)  ! surfInt, surfSlv, surfMst
  integer :: j, jflags(3), jslv(nns, n), jmst(4, n)
  double precision :: rdata(4), pr(max(nprops, 1)), dslip(3, n), fprev(3, n), dcn(3, n), dcs(3, n)
  double precision :: shs(nns, n), shm(4, n), cs(3, nns, n), cm(3, 4, n), vs(3, nns, n)
  double precision :: vm(3, 4, n), ts(n), tm(n), fs(1, n), fm(1, n)
  character(len=80) :: sint, sslv, smst
  jflags = 1; rdata = 0d0; pr = props; dslip = 0d0; fprev = 0d0; dcn = 0d0; dcs = 0d0
  jslv = 1; jmst = 1; shs = 1d0; shm = 0.25d0; cs = 0d0; cm = 0d0; vs = 0d0; vm = 0d0
  ts = 0d0; tm = 0d0; fs = 0d0; fm = 0d0
  do j = 1, 80
    sint(j:j) = si(j); sslv(j:j) = ss(j); smst(j:j) = sm(j)
  end do
  call vfriction(ftang, state, n, n, n, nns, nns, 4, 2, 3, nsv, nprops, 0, 1, jflags, rdata, &
                 sint, sslv, smst, jslv, jmst, pr, dslip, fstick, fprev, fnormal, area, &
                 dcn, dcs, shs, shm, cs, cm, vs, vm, ts, tm, fs, fm)
end subroutine h_vfriction
