! f2py-facing layer for the fitting concern (pendula_sensitivity,
! pendula_fit_period).  Plain subroutines, c_double/c_int arguments, a status
! code + message; no numerics: each routine is one call into the library.

subroutine sensitivity_f2py(n, t, t_ref, theta0, omega0, w0, gamma, tol, theta, omega, &
                            jac_theta, jac_omega, steps, code, msg)
  ! theta, omega and their derivatives with respect to (theta0, omega0, w0,
  ! gamma) at the n sample times t of the damped pendulum started at t_ref.
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, status_unpack
  use pendula_sensitivity, only: sensitivity_solve
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: t(n), t_ref, theta0, omega0, w0, gamma, tol
  real(c_double), intent(out) :: theta(n), omega(n), jac_theta(n, 4), jac_omega(n, 4)
  real(c_double), intent(out) :: steps
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer(i8) :: nsteps
  call sensitivity_solve(t, t_ref, theta0, omega0, w0, gamma, tol, theta, omega, jac_theta, jac_omega, &
                         st, nsteps)
  steps = real(nsteps, c_double)
  call status_unpack(st, code, msg)
end subroutine sensitivity_f2py

subroutine fit_period_f2py(n, theta0, period, sigma_period, sigma_theta0, w0, se_w0, chi2, &
                           iterations, w0_small_angle, code, msg)
  ! The weighted period fit: w0, its standard error from the given sigmas,
  ! chi-square, iterations and the small-angle model's w0.
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_fit_period, only: period_fit_t, fit_period
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: theta0(n), period(n), sigma_period(n), sigma_theta0(n)
  real(c_double), intent(out) :: w0, se_w0, chi2, w0_small_angle
  integer(c_int), intent(out) :: iterations, code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(period_fit_t) :: fit
  type(status_t) :: st
  call fit_period(theta0, period, sigma_period, sigma_theta0, fit, st)
  w0 = fit%w0
  se_w0 = fit%se_w0
  chi2 = fit%chi2
  iterations = fit%iterations
  w0_small_angle = fit%w0_small_angle
  call status_unpack(st, code, msg)
end subroutine fit_period_f2py

subroutine period_factor_f2py(n, theta0, f, dfdtheta)
  ! f = 4 K(sin(theta0/2)**2) and df/dtheta0 for each amplitude (|theta0| < pi).
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_fit_period, only: period_factor
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: theta0(n)
  real(c_double), intent(out) :: f(n), dfdtheta(n)
  call period_factor(theta0, f, dfdtheta)
end subroutine period_factor_f2py
