! f2py-facing layer for the Taylor integrator (pendula_taylor,
! pendula_taylor_batch).  Plain subroutines, c_double/c_int explicit-shape
! arguments, a status code + message; counters travel as doubles (exact up to
! 2**53).  threadsafe: the GIL is released during the call.  No numerics here.

! dkind: 0 no drive, else pendula_drive's kind code with damp, dfreq, dphase.
subroutine taylor_f2py(n, t, theta0, omega0, w0, gamma, tol, max_steps, m, control, dkind, damp, dfreq, dphase, &
                       theta, omega, err, stats, order, ev_t, ev_kind, ev_theta, ev_omega, n_events, truncated, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_ode, only: ode_stats_t, ode_stats_values, step_budget
  use pendula_taylor, only: taylor_solve, taylor_solve_events
  use pendula_drive, only: drive_t
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, m, dkind
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, gamma, tol, max_steps, damp, dfreq, dphase
  integer(8), intent(inout) :: control(2)   ! int64 cancel flag and progress (pendula_control)
  real(c_double), intent(out) :: theta(n), omega(n), err(n), stats(7)
  integer(c_int), intent(out) :: order
  real(c_double), intent(out) :: ev_t(m), ev_theta(m), ev_omega(m)
  integer(c_int), intent(out) :: ev_kind(m), n_events, truncated
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(ode_stats_t) :: s
  integer :: nev, p
  logical :: trunc
  type(drive_t) :: d
  d = drive_t(kind=int(dkind), amplitude=damp, frequency=dfreq, phase=dphase)
  if (m > 0 .and. dkind /= 0) then
    call taylor_solve_events(t, theta0, omega0, w0, gamma, tol, theta, omega, err, ev_t, ev_kind, ev_theta, &
                             ev_omega, nev, trunc, s, st, p, control, step_budget(max_steps), d)
  else if (m > 0) then
    call taylor_solve_events(t, theta0, omega0, w0, gamma, tol, theta, omega, err, ev_t, ev_kind, ev_theta, &
                             ev_omega, nev, trunc, s, st, p, control, step_budget(max_steps))
  else if (dkind /= 0) then
    call taylor_solve(t, theta0, omega0, w0, gamma, tol, theta, omega, err, s, st, p, control, step_budget(max_steps), d)
    nev = 0
    trunc = .false.
    ev_kind = 0
  else
    call taylor_solve(t, theta0, omega0, w0, gamma, tol, theta, omega, err, s, st, p, control, step_budget(max_steps))
    nev = 0
    trunc = .false.
    ev_kind = 0
  end if
  order = p
  n_events = nev
  truncated = merge(1, 0, trunc)
  stats = ode_stats_values(s)
  call status_unpack(st, code, msg)
end subroutine taylor_f2py

! dkind: 0 no drive, else one drive for every state (as taylor_f2py).
subroutine taylor_batch_f2py(nt, n, no, nw, ng, nr, t, theta0, omega0, w0, gamma, tol, max_steps, threads, control, &
                             dkind, damp, dfreq, dphase, theta, omega, err, codes, steps, order, first_failed, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, status_unpack, check_alloc
  use pendula_ode, only: step_budget
  use pendula_taylor_batch, only: taylor_batch_solve
  use pendula_drive, only: drive_t
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: nt, n, no, nw, ng, nr, threads, dkind
  real(c_double), intent(in) :: t(nt), theta0(n), omega0(no), w0(nw), gamma(ng), tol(nr), max_steps, damp, dfreq, dphase
  integer(8), intent(inout) :: control(2)   ! cancel flag and progress in states (pendula_control)
  real(c_double), intent(out) :: theta(nt, n), omega(nt, n), err(nt, n), steps(n)
  integer(c_int), intent(out) :: codes(n), order(n), first_failed, code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer(i8), allocatable :: nsteps(:)   ! heap: n may be 1e7
  integer :: first
  integer :: ist
  allocate (nsteps(n), stat=ist)
  call check_alloc(ist, 'the steps per state', int(n, i8), 8, st)
  if (st%code /= 0) then
    codes = st%code
    first_failed = 0
    call status_unpack(st, code, msg)
    return
  end if
  if (dkind /= 0) then
    call taylor_batch_solve(t, theta0, omega0, w0, gamma, tol, theta, omega, err, codes, nsteps, order, st, &
                            threads=int(threads), control=control, first_failed=first, max_steps=step_budget(max_steps), &
                            drive=drive_t(kind=int(dkind), amplitude=damp, frequency=dfreq, phase=dphase))
  else
    call taylor_batch_solve(t, theta0, omega0, w0, gamma, tol, theta, omega, err, codes, nsteps, order, st, &
                            threads=int(threads), control=control, first_failed=first, max_steps=step_budget(max_steps))
  end if
  steps = real(nsteps, c_double)
  first_failed = first
  call status_unpack(st, code, msg)
end subroutine taylor_batch_f2py

! taylor_f2py for the common call, one state without events: fewer arguments
! to convert and arrays to allocate (a short call's cost is mostly these).
! work(1) = steps, work(2) = series order.
subroutine taylor_plain_f2py(n, t, theta0, omega0, w0, gamma, tol, max_steps, control, theta, omega, err, work, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_ode, only: ode_stats_t, step_budget
  use pendula_taylor, only: taylor_solve
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, gamma, tol, max_steps
  integer(8), intent(inout) :: control(2)   ! int64 cancel flag and progress (pendula_control)
  real(c_double), intent(out) :: theta(n), omega(n), err(n), work(2)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(ode_stats_t) :: s
  integer :: p
  call taylor_solve(t, theta0, omega0, w0, gamma, tol, theta, omega, err, s, st, p, control, step_budget(max_steps))
  work(1) = real(s%steps, c_double)
  work(2) = real(p, c_double)
  call status_unpack(st, code, msg)
end subroutine taylor_plain_f2py
