subroutine h_generic(n, nd, reps, iunit, p, ph, g1h, du, told, khost, tnew, dtddu, dtdp, &
                     istat, phnew, g1new, ierr) bind(c, name='h_generic')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n, nd, reps, iunit
  real(c_double), intent(in) :: p(n), ph(n), g1h(n), du(nd, n), told(nd, n), khost(n)
  real(c_double), intent(out) :: tnew(nd, n), dtddu(nd, nd, n), dtdp(nd, n), phnew(n), g1new(n)
  integer(c_int), intent(out) :: istat(n), ierr(n)
  integer :: i, r, ist, ie, iu
  iu = iunit
  do r = 1, reps
    do i = 1, n
      call sbmf_friction(nd, p(i), ph(i), g1h(i), du(1, i), told(1, i), khost(i), iu, &
                         tnew(1, i), dtddu(1, 1, i), dtdp(1, i), ist, phnew(i), g1new(i), ie)
      istat(i) = ist
      ierr(i) = ie
    end do
  end do
end subroutine h_generic

! SBMF_FRICTION_V (interface version ivers) for every point reps times, with the zone name
! zone(1:nz) and the state state(nstate, n) (the committed state in, the trial state out).
subroutine h_generic_v(n, nd, reps, iunit, ivers, zone, nz, nstate, p, du, told, khost, deps, &
                       sigy, state, tnew, dtddu, dtdp, istat, ierr) bind(c, name='h_generic_v')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n, nd, reps, iunit, ivers, nz, nstate
  character(kind=c_char), intent(in) :: zone(max(nz, 1))
  real(c_double), intent(in) :: p(n), du(nd, n), told(nd, n), khost(n), deps(n), sigy(n)
  real(c_double), intent(inout) :: state(nstate, n)
  real(c_double), intent(out) :: tnew(nd, n), dtddu(nd, nd, n), dtdp(nd, n)
  integer(c_int), intent(out) :: istat(n), ierr(n)
  double precision :: work(nstate)
  character(len=max(nz, 0)) :: name
  integer :: i, j, r, ist, ie, iu, iv, ns
  iu = iunit
  iv = ivers
  ns = nstate
  do j = 1, nz
    name(j:j) = zone(j)
  end do
  do r = 1, reps
    do i = 1, n
      work = state(:, i)
      call sbmf_friction_v(iv, name, nd, p(i), du(1, i), told(1, i), khost(i), iu, deps(i), &
                           sigy(i), ns, work, tnew(1, i), dtddu(1, 1, i), dtdp(1, i), ist, ie)
      if (r == reps) state(:, i) = work
      istat(i) = ist
      ierr(i) = ie
    end do
  end do
end subroutine h_generic_v

! SBMF_ZMESSAGE's text for the zone name zone(1:nz), into buf (n characters); returns its length.
integer(c_int) function h_zmessage(zone, nz, buf, n) bind(c, name='h_zmessage')
  use iso_c_binding
  implicit none
  integer(c_int), value :: nz, n
  character(kind=c_char), intent(in) :: zone(max(nz, 1))
  character(kind=c_char), intent(out) :: buf(n)
  character(len=400) :: msg
  character(len=max(nz, 0)) :: name
  integer :: i, m
  do i = 1, nz
    name(i:i) = zone(i)
  end do
  call sbmf_zmessage(name, msg, m)
  m = min(m, int(n))
  do i = 1, m
    buf(i) = msg(i:i)
  end do
  h_zmessage = m
end function h_zmessage

! SBMF_MESSAGE's text for kind k and value xv, into buf (n characters); returns its length.
integer(c_int) function h_message(k, xv, buf, n) bind(c, name='h_message')
  use iso_c_binding
  implicit none
  integer(c_int), value :: k, n
  real(c_double), value :: xv
  character(kind=c_char), intent(out) :: buf(n)
  character(len=400) :: msg
  integer :: i, m, kk
  double precision :: x
  kk = k
  x = xv
  call sbmf_message(kk, x, msg, m)
  m = min(m, int(n))
  do i = 1, m
    buf(i) = msg(i:i)
  end do
  h_message = m
end function h_message
