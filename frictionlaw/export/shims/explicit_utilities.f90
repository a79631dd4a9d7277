! Abaqus/Explicit's utility routines, as the harness emulates them (VFRIC, VFRICTION): the
! message is logged with its LOP (%I, %R, %S are not substituted), XPLB_EXIT counts an error
! exit and returns.
subroutine xplb_abqerr(lop, string, intv, realv, charv)
  use sbmf_host_log, only: log_line
  implicit none
  integer :: lop, intv(*)
  character(len=*) :: string
  double precision :: realv(*)
  character(len=8) :: charv(*)
  if (.false.) print *, intv(1), realv(1), charv(1)
  call log_line(lop, string)
end subroutine xplb_abqerr

subroutine xplb_exit()
  use sbmf_host_log, only: log_exit
  implicit none
  call log_exit()
end subroutine xplb_exit
