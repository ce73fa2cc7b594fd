! f2py-facing layer for the core concern (pendula_physics). Plain subroutines,
! c_double/c_int arguments, explicit-shape arrays, and a status code + message
! that the Python side turns into an exception.  No numerics here.

subroutine physics_rate_f2py(which, a, b, x, code, msg)
  ! which = GLUE_W0: x = w0 from (a, b) = (g, length); GLUE_GAMMA: x = gamma from
  ! (a, b) = (b, mass).
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_physics, only: natural_frequency, damping_rate
  implicit none
  include 'pendula_msg_len.inc'
  include 'pendula_glue_codes.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: which
  real(c_double), intent(in) :: a, b
  real(c_double), intent(out) :: x
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  if (which == GLUE_W0) then
    call natural_frequency(a, b, x, st)
  else
    call damping_rate(a, b, x, st)
  end if
  call status_unpack(st, code, msg)
end subroutine physics_rate_f2py

subroutine period_series_f2py(n, m, w0, t, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack, PENDULA_OK
  use pendula_physics, only: period_series
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: m(n), w0(n)
  real(c_double), intent(out) :: t(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer :: i
  do i = 1, n
    call period_series(m(i), w0(i), t(i), st)
    if (st%code /= PENDULA_OK) exit
  end do
  call status_unpack(st, code, msg)
end subroutine period_series_f2py

subroutine small_angle_period_f2py(n, w0, t0, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack, PENDULA_OK
  use pendula_physics, only: small_angle_period
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: w0(n)
  real(c_double), intent(out) :: t0(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer :: i
  do i = 1, n
    call small_angle_period(w0(i), t0(i), st)
    if (st%code /= PENDULA_OK) exit
  end do
  call status_unpack(st, code, msg)
end subroutine small_angle_period_f2py
