! f2py-facing layer for the linear damped pendulum (pendula_linear_damped).
! Plain subroutines, c_double/c_int arguments, explicit-shape arrays, and a
! status code + message that the Python side turns into an exception.
! No numerics here.

subroutine linear_damped_f2py(n, t, theta0, omega0, w0, gamma, theta, omega, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_linear_damped, only: linear_damped_arrays
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: t(n), theta0(n), omega0(n), w0(n), gamma(n)
  real(c_double), intent(out) :: theta(n), omega(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  call linear_damped_arrays(t, theta0, omega0, w0, gamma, theta, omega, st)
  call status_unpack(st, code, msg)
end subroutine linear_damped_f2py

subroutine linear_damped_envelope_f2py(n, t, theta0, omega0, w0, gamma, env, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack, check_nonnegative, PENDULA_OK
  use pendula_linear_damped, only: linear_damped_t, linear_damped_init, linear_damped_envelope
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: t(n), theta0(n), omega0(n), w0(n), gamma(n)
  real(c_double), intent(out) :: env(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(linear_damped_t) :: sol
  integer :: i
  env = 0
  do i = 1, n
    call check_nonnegative('t', t(i), st)
    if (st%code == PENDULA_OK) call linear_damped_init(sol, theta0(i), omega0(i), w0(i), gamma(i), st)
    if (st%code /= PENDULA_OK) exit
    env(i) = linear_damped_envelope(sol, t(i))
  end do
  if (st%code /= PENDULA_OK) env = 0
  call status_unpack(st, code, msg)
end subroutine linear_damped_envelope_f2py

subroutine damping_regime_f2py(w0, gamma, regime, lambda1, lambda2, omega_d, beta, &
                               decay_slow, decay_fast, quality_factor, log_decrement, damped_period, &
                               gamma_critical, damping_ratio, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_linear_damped, only: damping_regime_t, damping_regime
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  real(c_double), intent(in) :: w0, gamma
  integer(c_int), intent(out) :: regime
  real(c_double), intent(out) :: lambda1(2), lambda2(2)
  real(c_double), intent(out) :: omega_d, beta, decay_slow, decay_fast, quality_factor, &
                                 log_decrement, damped_period, gamma_critical, damping_ratio
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(damping_regime_t) :: info
  call damping_regime(w0, gamma, info, st)
  regime = info%regime
  lambda1 = [info%lambda1%re, info%lambda1%im]
  lambda2 = [info%lambda2%re, info%lambda2%im]
  omega_d = info%omega_d
  beta = info%beta
  decay_slow = info%decay_slow
  decay_fast = info%decay_fast
  quality_factor = info%quality_factor
  log_decrement = info%log_decrement
  damped_period = info%damped_period
  gamma_critical = info%gamma_critical
  damping_ratio = info%damping_ratio
  call status_unpack(st, code, msg)
end subroutine damping_regime_f2py

subroutine linear_damped_one_f2py(n, t, theta0, omega0, w0, gamma, theta, omega, code, msg)
  ! One trajectory (scalar parameters) at n times: set up once, no per-point
  ! parameter arrays.
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack, PENDULA_OK
  use pendula_linear_damped, only: linear_damped_t, linear_damped_init, linear_damped_eval
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, gamma
  real(c_double), intent(out) :: theta(n), omega(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(linear_damped_t) :: sol
  theta = 0
  omega = 0
  call linear_damped_init(sol, theta0, omega0, w0, gamma, st)
  if (st%code == PENDULA_OK) call linear_damped_eval(sol, t, theta, omega, st)
  call status_unpack(st, code, msg)
end subroutine linear_damped_one_f2py
