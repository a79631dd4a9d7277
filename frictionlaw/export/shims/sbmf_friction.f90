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
