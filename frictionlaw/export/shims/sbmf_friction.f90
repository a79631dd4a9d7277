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
