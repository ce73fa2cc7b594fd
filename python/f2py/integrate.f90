! f2py-facing layer for the integrators concern (pendula_rk4, pendula_cvode).
! Plain subroutines, c_double/c_int arguments, explicit-shape arrays, a status
! code + message.  Counters (int64 in Fortran) travel as doubles: exact up to
! 2**53, and f2py handles them without kind trouble.  No numerics here.
! control: the caller's int64 [cancel flag, progress] array (pendula_control),
! passed in place so that another Python thread can set the flag.

subroutine rk4_f2py(n, t, theta0, omega0, w0, gamma, h, max_steps, control, theta, omega, stats, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_ode, only: ode_stats_t, ode_stats_values, step_budget
  use pendula_rk4, only: rk4_solve
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, gamma, h, max_steps
  integer(8), intent(inout) :: control(2)   ! int64 (f2py mistypes c_int64_t as an undeclared long_long)
  real(c_double), intent(out) :: theta(n), omega(n), stats(7)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(ode_stats_t) :: s
  ! max_steps arrives as a double (Python int of any size); step_budget clamps it to int64.
  call rk4_solve(t, theta0, omega0, w0, gamma, h, theta, omega, s, st, control, step_budget(max_steps))
  stats = ode_stats_values(s)
  call status_unpack(st, code, msg)
end subroutine rk4_f2py

subroutine rk4_max_stable_step_f2py(w0, gamma, h_max, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_rk4, only: rk4_max_stable_step
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  real(c_double), intent(in) :: w0, gamma
  real(c_double), intent(out) :: h_max
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  call rk4_max_stable_step(w0, gamma, h_max, st)
  call status_unpack(st, code, msg)
end subroutine rk4_max_stable_step_f2py

subroutine cvode_f2py(n, t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, m, control, &
                      theta, omega, stats, ev_t, ev_kind, ev_theta, ev_omega, n_events, truncated, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, status_unpack
  use pendula_ode, only: ode_stats_t, ode_stats_values, step_budget
  use pendula_cvode, only: cvode_solve, cvode_solve_events
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, method, m
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, gamma, rtol, atol, max_steps
  integer(8), intent(inout) :: control(2)   ! int64 (f2py mistypes c_int64_t as an undeclared long_long)
  real(c_double), intent(out) :: theta(n), omega(n), stats(7)
  real(c_double), intent(out) :: ev_t(m), ev_theta(m), ev_omega(m)
  integer(c_int), intent(out) :: ev_kind(m), n_events, truncated
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(ode_stats_t) :: s
  integer :: nev
  logical :: trunc
  integer(i8) :: budget
  ! integer(c_int) is the default integer of gfortran, so ev_kind goes straight
  ! to the library (no automatic array: max_events can be 1e7).
  ! max_steps arrives as a double (Python int of any size); step_budget clamps it to int64.
  budget = step_budget(max_steps)
  if (m > 0) then
    call cvode_solve_events(t, theta0, omega0, w0, gamma, rtol, atol, int(method), budget, &
                            theta, omega, ev_t, ev_kind, ev_theta, ev_omega, nev, trunc, s, st, control)
  else
    call cvode_solve(t, theta0, omega0, w0, gamma, rtol, atol, int(method), budget, theta, omega, s, st, control)
    nev = 0
    trunc = .false.
    ev_kind = 0
  end if
  n_events = nev
  truncated = merge(1, 0, trunc)
  stats = ode_stats_values(s)
  call status_unpack(st, code, msg)
end subroutine cvode_f2py

subroutine cvode_available_f2py(flag)
  use, intrinsic :: iso_c_binding, only: c_int
  use pendula_cvode, only: cvode_available
  implicit none
  integer(c_int), intent(out) :: flag
  flag = merge(1, 0, cvode_available())
end subroutine cvode_available_f2py

! rk4_f2py with a drive (pendula_drive): kind (DRIVE_TORQUE or DRIVE_PIVOT),
! amplitude, frequency [rad/s] and phase [rad].  A routine of its own so that
! the undriven call keeps its argument list (and its cost).
subroutine rk4_drive_f2py(n, t, theta0, omega0, w0, gamma, h, max_steps, dkind, amp, freq, phase, control, &
                          theta, omega, stats, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_ode, only: ode_stats_t, ode_stats_values, step_budget
  use pendula_rk4, only: rk4_solve
  use pendula_drive, only: drive_t
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, dkind
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, gamma, h, max_steps, amp, freq, phase
  integer(8), intent(inout) :: control(2)   ! int64 (f2py mistypes c_int64_t as an undeclared long_long)
  real(c_double), intent(out) :: theta(n), omega(n), stats(7)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(ode_stats_t) :: s
  call rk4_solve(t, theta0, omega0, w0, gamma, h, theta, omega, s, st, control, step_budget(max_steps), &
                 drive_t(int(dkind), amp, freq, phase))
  stats = ode_stats_values(s)
  call status_unpack(st, code, msg)
end subroutine rk4_drive_f2py

! cvode_f2py with a drive (as rk4_drive_f2py).
subroutine cvode_drive_f2py(n, t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, m, dkind, amp, freq, phase, &
                            control, theta, omega, stats, ev_t, ev_kind, ev_theta, ev_omega, n_events, truncated, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, status_unpack
  use pendula_ode, only: ode_stats_t, ode_stats_values, step_budget
  use pendula_cvode, only: cvode_solve, cvode_solve_events
  use pendula_drive, only: drive_t
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, method, m, dkind
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, gamma, rtol, atol, max_steps, amp, freq, phase
  integer(8), intent(inout) :: control(2)   ! int64 (f2py mistypes c_int64_t as an undeclared long_long)
  real(c_double), intent(out) :: theta(n), omega(n), stats(7)
  real(c_double), intent(out) :: ev_t(m), ev_theta(m), ev_omega(m)
  integer(c_int), intent(out) :: ev_kind(m), n_events, truncated
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(ode_stats_t) :: s
  type(drive_t) :: d
  integer :: nev
  logical :: trunc
  integer(i8) :: budget
  budget = step_budget(max_steps)
  d = drive_t(int(dkind), amp, freq, phase)
  if (m > 0) then
    call cvode_solve_events(t, theta0, omega0, w0, gamma, rtol, atol, int(method), budget, &
                            theta, omega, ev_t, ev_kind, ev_theta, ev_omega, nev, trunc, s, st, control, d)
  else
    call cvode_solve(t, theta0, omega0, w0, gamma, rtol, atol, int(method), budget, theta, omega, s, st, control, d)
    nev = 0
    trunc = .false.
    ev_kind = 0
  end if
  n_events = nev
  truncated = merge(1, 0, trunc)
  stats = ode_stats_values(s)
  call status_unpack(st, code, msg)
end subroutine cvode_drive_f2py
