! f2py-facing layer for the driven pendulum (src/driven): plain subroutines,
! c_double/c_int explicit-shape arguments, a status code + message.  Batch
! parameters arrive with n elements or one (the Fortran broadcasts them).
! threadsafe: f2py releases the GIL, so a watcher thread can raise the cancel
! flag in `control` (pendula_control).  No numerics here.

subroutine driven_f2py(nt, n, no, nw, ng, na, nf, np, t, theta0, omega0, w0, gamma, kind, amp, freq, phase, &
                       nsteps, richardson, threads, control, theta, omega, err_theta, err_omega, codes, first_failed, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_driven, only: driven_batch_solve
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: nt, n, no, nw, ng, na, nf, np, kind, nsteps, richardson, threads
  real(c_double), intent(in) :: t(nt), theta0(n), omega0(no), w0(nw), gamma(ng), amp(na), freq(nf), phase(np)
  integer(8), intent(inout) :: control(2)
  real(c_double), intent(out) :: theta(nt, n), omega(nt, n), err_theta(nt, n), err_omega(nt, n)
  integer(c_int), intent(out) :: codes(n), first_failed, code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer :: ff
  if (richardson /= 0) then
    call driven_batch_solve(t, theta0, omega0, w0, gamma, int(kind), amp, freq, phase, int(nsteps), theta, omega, &
                        codes, st, threads=int(threads), control=control, first_failed=ff, err_theta=err_theta, err_omega=err_omega)
  else
    call driven_batch_solve(t, theta0, omega0, w0, gamma, int(kind), amp, freq, phase, int(nsteps), theta, omega, &
                            codes, st, threads=int(threads), control=control, first_failed=ff)
    err_theta = 0
    err_omega = 0
  end if
  first_failed = ff
  call status_unpack(st, code, msg)
end subroutine driven_f2py

subroutine poincare_f2py(n, no, nw, ng, na, nf, np, theta0, omega0, w0, gamma, kind, amp, freq, phase, nsteps, &
                     section_phase, transient, nrec, threads, control, theta_s, omega_s, mean_omega, codes, first_failed, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_driven_maps, only: driven_poincare
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, no, nw, ng, na, nf, np, kind, nsteps, transient, nrec, threads
  real(c_double), intent(in) :: theta0(n), omega0(no), w0(nw), gamma(ng), amp(na), freq(nf), phase(np)
  real(c_double), intent(in) :: section_phase
  integer(8), intent(inout) :: control(2)
  real(c_double), intent(out) :: theta_s(nrec, n), omega_s(nrec, n), mean_omega(n)
  integer(c_int), intent(out) :: codes(n), first_failed, code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer :: ff
  call driven_poincare(theta0, omega0, w0, gamma, int(kind), amp, freq, phase, int(nsteps), section_phase, &
                       int(transient), int(nrec), theta_s, omega_s, mean_omega, codes, st, threads=int(threads), control=control, &
                       first_failed=ff)
  first_failed = ff
  call status_unpack(st, code, msg)
end subroutine poincare_f2py

subroutine lyapunov_f2py(n, no, nw, ng, na, nf, np, theta0, omega0, w0, gamma, kind, amp, freq, phase, nsteps, &
                         transient, periods, orbits, threads, control, lyap, lyap_err, codes, first_failed, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_driven_maps, only: driven_lyapunov
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, no, nw, ng, na, nf, np, kind, nsteps, transient, periods, orbits, threads
  real(c_double), intent(in) :: theta0(n), omega0(no), w0(nw), gamma(ng), amp(na), freq(nf), phase(np)
  integer(8), intent(inout) :: control(2)
  real(c_double), intent(out) :: lyap(2, n), lyap_err(2, n)
  integer(c_int), intent(out) :: codes(n), first_failed, code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer :: ff
  call driven_lyapunov(theta0, omega0, w0, gamma, int(kind), amp, freq, phase, int(nsteps), int(transient), &
                       int(periods), lyap, lyap_err, codes, st, threads=int(threads), control=control, first_failed=ff, &
                       orbits=int(orbits))
  first_failed = ff
  call status_unpack(st, code, msg)
end subroutine lyapunov_f2py

subroutine orbits_f2py(n, no, nw, ng, na, nf, np, npi, theta0, omega0, w0, gamma, kind, amp, freq, phase, nsteps, &
                      period_in, transient, nmax, tol, threads, control, period, winding, theta_p, omega_p, mult, residual, codes, &
                       first_failed, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, status_unpack, check_alloc
  use pendula_driven_orbits, only: driven_orbits
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, no, nw, ng, na, nf, np, npi, kind, nsteps, transient, nmax, threads
  integer(c_int), intent(in) :: period_in(npi)
  real(c_double), intent(in) :: theta0(n), omega0(no), w0(nw), gamma(ng), amp(na), freq(nf), phase(np), tol
  integer(8), intent(inout) :: control(2)
  integer(c_int), intent(out) :: period(n), winding(n)
  real(c_double), intent(out) :: theta_p(n), omega_p(n), mult(4, n), residual(n)
  integer(c_int), intent(out) :: codes(n), first_failed, code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer :: ff
  integer, allocatable :: per(:), wnd(:), cds(:)
  integer :: ist
  allocate (per(n), wnd(n), cds(n), stat=ist)
  call check_alloc(ist, 'the orbits'' periods, windings and codes', 3_i8*n, 4, st)
  if (st%code /= 0) then
    codes = st%code
    first_failed = 0
    call status_unpack(st, code, msg)
    return
  end if
  call driven_orbits(theta0, omega0, w0, gamma, int(kind), amp, freq, phase, int(nsteps), int(period_in), &
                     int(transient), int(nmax), tol, per, wnd, theta_p, omega_p, mult, residual, cds, st, threads=int(threads), &
                     control=control, first_failed=ff)
  period = per
  winding = wnd
  codes = cds
  first_failed = ff
  call status_unpack(st, code, msg)
end subroutine orbits_f2py

subroutine basins_f2py(n, no, nw, ng, na, nf, np, cap, ncyc, theta0, omega0, w0, gamma, kind, amp, freq, phase, &
                       nsteps, transient, nmax, tol, threads, control, labels, period, winding, natt, att_period, att_winding, &
                       att_theta, att_omega, att_mean_omega, cyc, codes, first_failed, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, status_unpack, check_alloc
  use pendula_driven_orbits, only: driven_basins
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, no, nw, ng, na, nf, np, cap, ncyc, kind, nsteps, transient, nmax, threads
  real(c_double), intent(in) :: theta0(n), omega0(no), w0(nw), gamma(ng), amp(na), freq(nf), phase(np), tol
  integer(8), intent(inout) :: control(2)
  integer(c_int), intent(out) :: labels(n), period(n), winding(n), natt, att_period(cap), att_winding(cap)
  real(c_double), intent(out) :: att_theta(cap), att_omega(cap), att_mean_omega(cap)
  ! each state's strobe cycle when ncyc = n (a chunk of a sweep; basin_table_f2py joins them), else unused
  real(c_double), intent(out) :: cyc(2, nmax, ncyc)
  integer(c_int), intent(out) :: codes(n), first_failed, code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer :: ff, na_
  integer, allocatable :: lab(:), per(:), wnd(:), cds(:), ap(:), aw(:)
  integer :: ist
  allocate (lab(n), per(n), wnd(n), cds(n), ap(cap), aw(cap), stat=ist)
  call check_alloc(ist, 'the basins'' labels, periods, windings and codes', 4_i8*n + 2_i8*cap, 4, st)
  if (st%code /= 0) then
    codes = st%code
    first_failed = 0
    call status_unpack(st, code, msg)
    return
  end if
  cyc = 0
  if (ncyc == n) then
    call driven_basins(theta0, omega0, w0, gamma, int(kind), amp, freq, phase, int(nsteps), int(transient), &
                       int(nmax), tol, lab, per, wnd, na_, ap, aw, att_theta, att_omega, att_mean_omega, cds, st, &
                       threads=int(threads), control=control, first_failed=ff, cycles=cyc)
  else
    call driven_basins(theta0, omega0, w0, gamma, int(kind), amp, freq, phase, int(nsteps), int(transient), &
                       int(nmax), tol, lab, per, wnd, na_, ap, aw, att_theta, att_omega, att_mean_omega, cds, st, &
                       threads=int(threads), control=control, first_failed=ff)
  end if
  labels = lab
  period = per
  winding = wnd
  natt = na_
  att_period = ap
  att_winding = aw
  codes = cds
  first_failed = ff
  call status_unpack(st, code, msg)
end subroutine basins_f2py

subroutine basin_table_f2py(n, nmax, nf, cap, period, winding, cyc, freq, tol, labels, natt, att_period, &
                            att_winding, att_theta, att_omega, att_mean_omega, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, status_unpack, check_alloc
  use pendula_driven_orbits, only: basin_table
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, nmax, nf, cap, period(n), winding(n)
  real(c_double), intent(in) :: cyc(2, nmax, n), freq(nf), tol
  integer(c_int), intent(out) :: labels(n), natt, att_period(cap), att_winding(cap)
  real(c_double), intent(out) :: att_theta(cap), att_omega(cap), att_mean_omega(cap)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer, allocatable :: per(:), wnd(:), lab(:), ap(:), aw(:)
  integer :: na_, ist
  allocate (per(n), wnd(n), lab(n), ap(cap), aw(cap), stat=ist)
  call check_alloc(ist, 'the basin table''s labels', 3_i8*n + 2_i8*cap, 4, st)
  if (st%code /= 0) then
    call status_unpack(st, code, msg)
    return
  end if
  per = period
  wnd = winding
  call basin_table(per, wnd, cyc, freq, tol, lab, na_, ap, aw, att_theta, att_omega, att_mean_omega, st)
  labels = lab
  natt = na_
  att_period = ap
  att_winding = aw
  call status_unpack(st, code, msg)
end subroutine basin_table_f2py

subroutine driven_linear_f2py(nt, t, theta0, omega0, w0, gamma, amp, freq, phase, theta, omega, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_drive, only: drive_t, DRIVE_TORQUE
  use pendula_driven_linear, only: driven_linear_solve
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: nt
  real(c_double), intent(in) :: t(nt), theta0, omega0, w0, gamma, amp, freq, phase
  real(c_double), intent(out) :: theta(nt), omega(nt)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  call driven_linear_solve(t, theta0, omega0, w0, gamma, drive_t(DRIVE_TORQUE, amp, freq, phase), theta, omega, st)
  call status_unpack(st, code, msg)
end subroutine driven_linear_f2py

subroutine driven_response_f2py(n, w0, gamma, freq, gain, lag)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_driven_linear, only: driven_linear_response
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: w0(n), gamma(n), freq(n)
  real(c_double), intent(out) :: gain(n), lag(n)
  call driven_linear_response(w0, gamma, freq, gain, lag)
end subroutine driven_response_f2py
