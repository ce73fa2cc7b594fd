!> The nonlinear damped pendulum theta'' + gamma theta' + w0**2 sin(theta) = 0
!> (text eq. 2.2) together with its variational equations: the derivatives of
!> theta(t) and omega(t) with respect to the parameters p = (theta0, omega0,
!> w0, gamma), the Jacobian a least-squares fit of a recorded swing needs.
!>
!> With y = (theta, omega) and S = dy/dp (2 x 4), S' = A(t) S + df/dp, where
!> A = [[0, 1], [-w0**2 cos(theta), -gamma]] and df/dp has one non-zero row,
!> (0, 0, -2 w0 sin(theta), -omega); S(t_ref) = [[1, 0, 0, 0], [0, 1, 0, 0]]
!> (Hairer, Norsett & Wanner, "Solving ODEs I", section I.14).  The ten
!> equations are integrated together by the classic RK4 method with a fixed
!> step chosen from the tolerance, so derivatives and values come from the
!> same discrete flow.  This is the one interface of a sensitivity integrator
!> (sensitivity_solve); a higher-order integrator may replace the body
!> without changing its callers.
module pendula_sensitivity
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_general
  use pendula_status, only: status_t, set_error, check_positive, check_nonnegative, check_finite, &
                            check_increasing, check_same_size, check_size, PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_MAXSTEPS
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private
  public :: sensitivity_solve, sensitivity_step, SENSITIVITY_NPARAMS, SENSITIVITY_MAX_STEPS

  !> Number of parameters differentiated: theta0, omega0, w0, gamma (columns in this order).
  integer, parameter :: SENSITIVITY_NPARAMS = 4
  !> Step budget of one call (about 20 s of CPU): a longer window is refused up front.
  integer(i8), parameter :: SENSITIVITY_MAX_STEPS = 200000000_i8
  integer, parameter :: NY = 2 + 2*SENSITIVITY_NPARAMS

contains

  !> The RK4 step [s] that keeps the global error in theta and in its scaled
  !> derivatives below about tol [rad] over a window of length span [s].  RK4's
  !> global error on an oscillation of rate lam over a window span is about
  !> (h lam)**4 (1 + lam span) / 120 (the leading term of the local error,
  !> (h lam)**5 / 120, summed over the steps); lam = max(w0, gamma) bounds the
  !> rates of the linearised problem, and a factor 1/2 covers the harmonics of a
  !> large swing.  Never above 2 / lam (well inside RK4's stability region).
  elemental real(wp) function sensitivity_step(w0, gamma, span, tol) result(h)
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    real(wp), intent(in) :: span  !< window length [s], >= 0
    real(wp), intent(in) :: tol  !< absolute error target on theta [rad], > 0
    real(wp) :: lam
    lam = max(w0, gamma)
    h = 0.5_wp*(120*tol/(1 + lam*span))**0.25_wp/lam
    h = min(h, 2/lam)
  end function sensitivity_step

  !> theta, omega and their derivatives with respect to (theta0, omega0, w0,
  !> gamma) at the sample times t (increasing, >= t_ref) of the damped pendulum
  !> started at (theta0, omega0) at time t_ref.  jac_theta(i, :) =
  !> d theta(t(i)) / d(theta0, omega0, w0, gamma), jac_omega likewise.
  !> Error in every output about tol or less (see sensitivity_step); cost about
  !> 10 (t(n) - t_ref) max(w0, gamma) tol**(-1/4) right-hand sides.
  pure subroutine sensitivity_solve(t, t_ref, theta0, omega0, w0, gamma, tol, theta, omega, &
                                    jac_theta, jac_omega, status, steps)
    real(wp), intent(in) :: t(:)  !< sample times [s], finite, strictly increasing, t(1) >= t_ref
    real(wp), intent(in) :: t_ref  !< time [s] at which the state is (theta0, omega0), finite
    real(wp), intent(in) :: theta0  !< angle at t_ref [rad], finite
    real(wp), intent(in) :: omega0  !< angular velocity at t_ref [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], finite, > 0
    real(wp), intent(in) :: gamma  !< linear damping rate [1/s], finite, >= 0
    real(wp), intent(in) :: tol  !< absolute error target [rad], finite, > 0
    real(wp), intent(out) :: theta(:)  !< theta(t(i)) [rad], size(t)
    real(wp), intent(out) :: omega(:)  !< omega(t(i)) [rad/s], size(t)
    real(wp), intent(out) :: jac_theta(:, :)  !< d theta(t(i)) / d p, shape (size(t), 4)
    real(wp), intent(out) :: jac_omega(:, :)  !< d omega(t(i)) / d p, shape (size(t), 4)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    integer(i8), intent(out), optional :: steps  !< RK4 steps taken
    real(wp) :: y(NY), h, dt, hh, span
    integer(i8) :: nsub, total, k
    integer :: i, n

    n = size(t)
    theta = 0
    omega = 0
    jac_theta = 0
    jac_omega = 0
    if (present(steps)) steps = 0
    call check_size('t', n, 1, status)
    call check_increasing('t', t, status)
    call check_finite('t_ref', t_ref, status)
    call check_finite('theta0', theta0, status)
    call check_finite('omega0', omega0, status)
    call check_positive('w0', w0, status)
    call check_nonnegative('gamma', gamma, status)
    call check_positive('tol', tol, status)
    call check_same_size('theta', size(theta), 't', n, status)
    call check_same_size('omega', size(omega), 't', n, status)
    call check_same_size('jac_theta', size(jac_theta, 1), 't', n, status)
    call check_same_size('jac_omega', size(jac_omega, 1), 't', n, status)
    call check_same_size('jac_theta columns', size(jac_theta, 2), 'the parameters', SENSITIVITY_NPARAMS, status)
    call check_same_size('jac_omega columns', size(jac_omega, 2), 'the parameters', SENSITIVITY_NPARAMS, status)
    if (status%code /= PENDULA_OK) return
    if (t(1) < t_ref) then
      call set_error(status, PENDULA_ERR_DOMAIN, 't_ref = '//format_general(t_ref, 17)// &
                     ' must not exceed the first sample time t[0] = '//format_general(t(1), 17))
      return
    end if
    span = t(n) - t_ref
    h = sensitivity_step(w0, gamma, span, tol)
    ! The step count, before any work: a window that needs more than the
    ! budget is refused rather than run for minutes.
    if (span/h > real(SENSITIVITY_MAX_STEPS, wp)) then
      call set_error(status, PENDULA_ERR_MAXSTEPS, 'the window t[-1] - t_ref = '//format_general(span, 6)// &
                     ' s needs about '//format_general(span/h, 3)//' RK4 steps at tol = '//format_general(tol, 3)// &
                     ' rad, over the budget of '//format_general(real(SENSITIVITY_MAX_STEPS, wp), 3)//': raise tol')
      return
    end if
    y = 0
    y(1) = theta0
    y(2) = omega0
    y(3) = 1    ! d theta / d theta0
    y(8) = 1    ! d omega / d omega0
    total = 0
    do i = 1, n
      dt = t(i) - merge(t_ref, t(max(i - 1, 1)), i == 1)
      if (dt > 0) then
        nsub = max(1_i8, ceiling(dt/h, i8))
        hh = dt/real(nsub, wp)
        do k = 1, nsub
          call rk4_step(y, hh, w0, gamma)
        end do
        total = total + nsub
      end if
      theta(i) = y(1)
      omega(i) = y(2)
      jac_theta(i, :) = y(3:6)
      jac_omega(i, :) = y(7:10)
    end do
    if (present(steps)) steps = total
    if (.not. all(ieee_is_finite(y))) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'the variational solution overflowed: w0 = '// &
                     format_general(w0, 6)//' 1/s, gamma = '//format_general(gamma, 6)//' 1/s')
    end if
  end subroutine sensitivity_solve

  ! One classic RK4 step of the ten equations.
  pure subroutine rk4_step(y, h, w0, gamma)
    real(wp), intent(inout) :: y(NY)
    real(wp), intent(in) :: h, w0, gamma
    real(wp), dimension(NY) :: k1, k2, k3, k4
    k1 = rhs(y, w0, gamma)
    k2 = rhs(y + 0.5_wp*h*k1, w0, gamma)
    k3 = rhs(y + 0.5_wp*h*k2, w0, gamma)
    k4 = rhs(y + h*k3, w0, gamma)
    y = y + (h/6)*(k1 + 2*(k2 + k3) + k4)
  end subroutine rk4_step

  ! The pendulum and its variational equations: y = (theta, omega, S_theta(1:4), S_omega(1:4)).
  pure function rhs(y, w0, gamma) result(f)
    real(wp), intent(in) :: y(NY), w0, gamma
    real(wp) :: f(NY)
    real(wp) :: s, c, w2
    s = sin(y(1))
    c = cos(y(1))
    w2 = w0*w0
    f(1) = y(2)
    f(2) = -gamma*y(2) - w2*s
    f(3:6) = y(7:10)
    f(7:10) = -gamma*y(7:10) - w2*c*y(3:6)
    f(9) = f(9) - 2*w0*s       ! d f / d w0
    f(10) = f(10) - y(2)           ! d f / d gamma
  end function rhs

end module pendula_sensitivity
