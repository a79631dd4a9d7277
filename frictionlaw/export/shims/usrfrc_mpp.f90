subroutine h_usrfrc_mpp(n, nh, nuc, uc_in, prs, uh, mu, nosl_in) bind(c, name='h_usrfrc_mpp')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n, nh, nuc, nosl_in
  real, intent(in) :: uc_in(max(nuc, 1))
  real, intent(in) :: prs(n)
  real, intent(inout) :: uh(max(nh, 1), n)
  real, intent(out) :: mu(2, n)
  integer :: i, nc, nhd, nnp(1), nosl, ictype, ncycle, lsv, insv, ix, ne
  integer*8 :: idele8
  real :: uc(max(nuc, 1)), ue(1), crv(1), fs, fd, z
  nc = nuc; nhd = nh; nnp = 1; nosl = nosl_in; ictype = 4; ncycle = 1; lsv = 1; insv = 1; ix = 1
  ne = 0; idele8 = 1; uc = uc_in; ue = 0.; crv = 0.; z = 0.
  do i = 1, n
    call usrfrc(fs, fd, uc, nc, prs(i), z, z, uh(1, i), nhd, crv, nnp, nosl, ictype, &
                'master', z, ncycle, z, z, z, z, z, lsv, idele8, z, z, insv, z, z, z, ix, &
                ix, ix, ix, z, z, z, z, ue, ne)
    mu(1, i) = fs
    mu(2, i) = fd
  end do
end subroutine h_usrfrc_mpp
