! LS-DYNA's output units for the harness (frictionlaw.export.harness): the terminal, d3hsp and
! messag units of LS-DYNA's iounits.inc (IOTTY, IOHSP, IOMSG), opened as the files tty.txt,
! d3hsp.txt and messag.txt in a folder the driver names; the generated routine's guards write
! there as LSTC's sample routines do.
subroutine h_lsdyna_open(path, n) bind(c, name='h_lsdyna_open')
  use iso_c_binding
  implicit none
  include 'iounits.inc'
  integer(c_int), value :: n
  character(kind=c_char), intent(in) :: path(n)
  character(len=n) :: dir
  integer :: i
  do i = 1, n
    dir(i:i) = path(i)
  end do
  open (newunit=iotty, file=dir // '/tty.txt', status='replace', action='write')
  open (newunit=iohsp, file=dir // '/d3hsp.txt', status='replace', action='write')
  open (newunit=iomsg, file=dir // '/messag.txt', status='replace', action='write')
end subroutine h_lsdyna_open

subroutine h_lsdyna_flush() bind(c, name='h_lsdyna_flush')
  implicit none
  include 'iounits.inc'
  flush (iotty)
  flush (iohsp)
  flush (iomsg)
end subroutine h_lsdyna_flush
