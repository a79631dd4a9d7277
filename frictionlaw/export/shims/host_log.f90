! The emulated hosts' message log (frictionlaw.export.harness): what a generated routine's
! guards wrote through the host's message routine, and how often it called the host's error
! exit. Compiled into every harness library; the drivers read it through h_log_read and
! h_log_exits. Test support: its SAVEd state is the emulated host's, not the routine's.
module sbmf_host_log
  use iso_c_binding
  implicit none
  integer, parameter :: cap = 200000
  character(len=cap), save :: text = ''
  integer, save :: used = 0, exits = 0
contains
  subroutine log_line(level, line)
    integer, intent(in) :: level
    character(len=*), intent(in) :: line
    character(len=16) :: head
    integer :: n
    write (head, '(I0, A)') level, '|'
    !$omp critical (sbmf_host_log)
    n = len_trim(head) + len(line) + 1
    if (used + n <= cap) then
      text(used + 1:used + n) = trim(head) // line // achar(10)
      used = used + n
    end if
    !$omp end critical (sbmf_host_log)
  end subroutine log_line

  subroutine log_exit()
    !$omp critical (sbmf_host_log)
    exits = exits + 1
    !$omp end critical (sbmf_host_log)
  end subroutine log_exit
end module sbmf_host_log

! Copy the log into buf (at most n characters), clear it; returns the length copied.
integer(c_int) function h_log_read(buf, n) bind(c, name='h_log_read')
  use sbmf_host_log
  implicit none
  integer(c_int), value :: n
  character(kind=c_char), intent(out) :: buf(n)
  integer :: i, m
  m = min(used, int(n))
  do i = 1, m
    buf(i) = text(i:i)
  end do
  used = 0
  h_log_read = m
end function h_log_read

! The error exits called so far (and reset them when reset /= 0).
integer(c_int) function h_log_exits(reset) bind(c, name='h_log_exits')
  use sbmf_host_log
  implicit none
  integer(c_int), value :: reset
  h_log_exits = exits
  if (reset /= 0) exits = 0
end function h_log_exits
