! f2py-facing layer for the undamped concern (pendula_undamped,
! pendula_small_angle, pendula_equilibria).  Plain subroutines over flat
! broadcast arrays, c_double/c_int arguments, a status code + message.  No
! numerics and no decisions: each routine is one call into pendula_undamped
! (or a plain loop over elements).

subroutine undamped_f2py(n, t, theta0, omega0, w0, theta, omega, code, msg, nt, n0, n1, n2)
  ! Element i: the state (theta0, omega0, w0)(i) at t(i); inputs of size n or 1.
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_undamped, only: undamped_states
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, nt, n0, n1, n2
  real(c_double), intent(in) :: t(nt), theta0(n0), omega0(n1), w0(n2)
  real(c_double), intent(out) :: theta(n), omega(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  call undamped_states(t, theta0, omega0, w0, theta, omega, st)
  call status_unpack(st, code, msg)
end subroutine undamped_f2py

subroutine small_angle_f2py(which, n, x, theta0, omega0, w0, a, b, code, msg)
  ! Element i of the small-angle model of the state (theta0, omega0, w0)(i):
  ! which = GLUE_SMALL_ANGLE_MOTION: (a, b) = (theta, omega) at time x(i) [s];
  ! GLUE_SMALL_ANGLE_BOUND: (a, b) = bounds on its error in theta and omega over
  ! abs(t) <= abs(x(i)).
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack, check_finite, PENDULA_OK
  use pendula_undamped, only: undamped_motion_t, undamped_init
  use pendula_small_angle, only: small_angle_solve, small_angle_bound
  implicit none
  include 'pendula_msg_len.inc'
  include 'pendula_glue_codes.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: which, n
  real(c_double), intent(in) :: x(n), theta0(n), omega0(n), w0(n)
  real(c_double), intent(out) :: a(n), b(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(undamped_motion_t) :: motion
  type(status_t) :: st
  integer :: i
  a = 0
  b = 0
  if (which == GLUE_SMALL_ANGLE_MOTION) then
    do i = 1, n
      call small_angle_solve(x(i:i), theta0(i), omega0(i), w0(i), a(i:i), b(i:i), st)
      if (st%code /= PENDULA_OK) exit
    end do
  else
    do i = 1, n
      call undamped_init(motion, theta0(i), omega0(i), w0(i), st, plan=.false.)
      if (st%code /= PENDULA_OK) exit
      call check_finite('tmax', x(i), st)
      if (st%code /= PENDULA_OK) exit
      call small_angle_bound(motion, x(i), a(i), b(i))
    end do
  end if
  call status_unpack(st, code, msg)
end subroutine small_angle_f2py

subroutine period_amplitude_f2py(n, which, theta0, omega0, w0, x, code, msg, n0, n1, n2)
  ! which = GLUE_PERIOD: the period [s] of each of n states, GLUE_AMPLITUDE: its
  ! amplitude [rad]; the property routines take inputs of size n or 1.
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_undamped, only: undamped_properties
  implicit none
  include 'pendula_msg_len.inc'
  include 'pendula_glue_codes.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, which, n0, n1, n2
  real(c_double), intent(in) :: theta0(n0), omega0(n1), w0(n2)
  real(c_double), intent(out) :: x(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  if (which == GLUE_PERIOD) then
    call undamped_properties(theta0, omega0, w0, st, period=x)
  else
    call undamped_properties(theta0, omega0, w0, st, amplitude=x)
  end if
  call status_unpack(st, code, msg)
end subroutine period_amplitude_f2py

subroutine parameter_f2py(n, theta0, omega0, w0, m, mc, code, msg, n0, n1, n2)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_undamped, only: undamped_properties
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, n0, n1, n2
  real(c_double), intent(in) :: theta0(n0), omega0(n1), w0(n2)
  real(c_double), intent(out) :: m(n), mc(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  call undamped_properties(theta0, omega0, w0, st, m=m, mc=mc)
  call status_unpack(st, code, msg)
end subroutine parameter_f2py

subroutine regime_f2py(n, theta0, omega0, w0, regime, code, msg, n0, n1, n2)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_undamped, only: undamped_properties
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, n0, n1, n2
  real(c_double), intent(in) :: theta0(n0), omega0(n1), w0(n2)
  integer(c_int), intent(out) :: regime(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  call undamped_properties(theta0, omega0, w0, st, regime=regime)
  call status_unpack(st, code, msg)
end subroutine regime_f2py

subroutine pendulum_energy_f2py(n, theta, omega, w0, energy, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack, check_finite, check_positive, PENDULA_OK
  use pendula_undamped, only: pendulum_energy
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: theta(n), omega(n), w0(n)
  real(c_double), intent(out) :: energy(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer :: i
  energy = 0
  do i = 1, n
    call check_finite('theta', theta(i), st)
    call check_finite('omega', omega(i), st)
    call check_positive('w0', w0(i), st)
    if (st%code /= PENDULA_OK) exit
    energy(i) = pendulum_energy(theta(i), omega(i), w0(i))
  end do
  call status_unpack(st, code, msg)
end subroutine pendulum_energy_f2py

subroutine equilibria_f2py(n, idx, w0, theta, lam_re, lam_im, kind, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: wp
  use pendula_status, only: status_t, status_unpack, PENDULA_OK
  use pendula_equilibria, only: equilibrium
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  integer(c_int), intent(in) :: idx(n)
  real(c_double), intent(in) :: w0(n)
  real(c_double), intent(out) :: theta(n), lam_re(n), lam_im(n)
  integer(c_int), intent(out) :: kind(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  complex(wp) :: l1, l2
  integer :: i, k
  theta = 0; lam_re = 0; lam_im = 0; kind = 0
  do i = 1, n
    call equilibrium(int(idx(i)), w0(i), theta(i), l1, l2, k, st)
    if (st%code /= PENDULA_OK) exit
    lam_re(i) = real(l1, wp)
    lam_im(i) = aimag(l1)
    kind(i) = k
  end do
  call status_unpack(st, code, msg)
end subroutine equilibria_f2py

subroutine undamped_one_f2py(n, t, theta0, omega0, w0, theta, omega, code, msg)
  ! One initial state at n times (the common case: no broadcast copies of the state).
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_undamped, only: undamped_solve
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: t(n), theta0, omega0, w0
  real(c_double), intent(out) :: theta(n), omega(n)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  call undamped_solve(t, theta0, omega0, w0, theta, omega, st)
  call status_unpack(st, code, msg)
end subroutine undamped_one_f2py
