!> The linearised torque-driven damped pendulum in closed form:
!>   theta'' + gamma theta' + w0**2 theta = F cos(Omega t + phi),
!> the small-swing limit of pendula_drive's torque drive.  Its solution is the
!> steady state A cos(Omega t + phi - delta), with the gain
!> A/F = 1/sqrt((w0**2 - Omega**2)**2 + (gamma Omega)**2) and the phase lag
!> delta = atan2(gamma Omega, w0**2 - Omega**2) in [0, pi] (Taylor, Classical
!> Mechanics, eqs. 5.64-5.65), plus the free motion (pendula_linear_damped)
!> that carries the initial state's difference from the steady state: the
!> transient.  Its error as a model of the pendulum is that of the small-angle
!> approximation (relative O(theta**2/8)).
module pendula_driven_linear
  use pendula_kinds, only: wp
  use pendula_status, only: status_t, set_error, check_finite, check_all_finite, check_same_size, PENDULA_OK, &
                            PENDULA_ERR_DOMAIN
  use pendula_linear_damped, only: linear_damped_t, linear_damped_init, linear_damped_state
  use pendula_drive, only: drive_t, DRIVE_TORQUE, check_drive
  implicit none
  private
  public :: driven_linear_response, driven_linear_solve

contains

  !> Steady-state response of the linear oscillator to a unit torque
  !> cos(Omega t): the gain A/F [s**2] and the phase lag delta in [0, pi]
  !> [rad].  w0 > 0, gamma >= 0, freq > 0 (not checked: elemental; at
  !> gamma = 0 and Omega = w0 the gain is +Infinity, the resonance).
  elemental subroutine driven_linear_response(w0, gamma, freq, gain, lag)
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s]
    real(wp), intent(in) :: gamma  !< damping rate [1/s]
    real(wp), intent(in) :: freq  !< drive frequency Omega [rad/s]
    real(wp), intent(out) :: gain  !< steady amplitude per unit torque amplitude [s**2]
    real(wp), intent(out) :: lag  !< phase lag of the response behind the drive [rad]
    real(wp) :: re, im
    re = (w0 - freq)*(w0 + freq)
    im = gamma*freq
    gain = 1/hypot(re, im)
    lag = atan2(im, re)
  end subroutine driven_linear_response

  !> theta(t) [rad] and Omega(t) [rad/s] of the linear driven oscillator at
  !> times t(:) >= 0 [s] from (theta0, omega0) at t = 0: steady state plus
  !> transient (module doc).  The drive must be a torque (a pivot drive's
  !> linearisation is Mathieu's equation, with no closed form).
  subroutine driven_linear_solve(t, theta0, omega0, w0, gamma, drive, theta, omega, status)
    real(wp), intent(in) :: t(:)  !< times [s], finite, >= 0
    real(wp), intent(in) :: theta0  !< initial angle [rad]
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s]
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    type(drive_t), intent(in) :: drive  !< a torque drive
    real(wp), intent(out) :: theta(:)  !< theta(t) [rad], size(t)
    real(wp), intent(out) :: omega(:)  !< Omega(t) [rad/s], size(t)
    type(status_t), intent(out) :: status  !< error code and message (PENDULA_OK on success)
    type(linear_damped_t) :: free
    real(wp) :: gain, lag, a, ys, us
    integer :: i
    theta = 0
    omega = 0
    call check_drive(drive, status)
    if (status%code == PENDULA_OK .and. drive%kind /= DRIVE_TORQUE) call set_error(status, PENDULA_ERR_DOMAIN, &
                                                       'drive kind is pivot: the linear closed form exists for a torque drive only')
    call check_all_finite('t', t, status)
    if (status%code == PENDULA_OK .and. size(t) > 0) then
      if (minval(t) < 0) call set_error(status, PENDULA_ERR_DOMAIN, 't has a negative time: every time must be >= 0')
    end if
    call check_same_size('theta', size(theta), 't', size(t), status)
    call check_same_size('omega', size(omega), 't', size(t), status)
    call check_finite('theta0', theta0, status)
    call check_finite('omega0', omega0, status)
    if (status%code /= PENDULA_OK) return
    call linear_damped_init(free, 0.0_wp, 0.0_wp, w0, gamma, status)   ! checks w0 and gamma
    if (status%code /= PENDULA_OK) return
    call driven_linear_response(w0, gamma, drive%frequency, gain, lag)
    if (.not. gain <= huge(gain)) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'frequency equals w0 with gamma = 0: the undamped resonance '// &
                     'has no bounded steady state')
      return
    end if
    a = drive%amplitude*gain
    ys = a*cos(drive%phase - lag)
    us = -a*drive%frequency*sin(drive%phase - lag)
    call linear_damped_init(free, theta0 - ys, omega0 - us, w0, gamma, status)
    if (status%code /= PENDULA_OK) return
    do i = 1, size(t)
      call linear_damped_state(free, t(i), theta(i), omega(i))
      theta(i) = theta(i) + a*cos(drive%frequency*t(i) + drive%phase - lag)
      omega(i) = omega(i) - a*drive%frequency*sin(drive%frequency*t(i) + drive%phase - lag)
    end do
  end subroutine driven_linear_solve

end module pendula_driven_linear
