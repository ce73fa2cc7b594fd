!> What the integrators share: the nonlinear damped pendulum (text eq. 2.2)
!>   theta'' + gamma theta' + w0**2 sin(theta) = 0
!> as a first-order system y = (theta, Omega), its Jacobian, the statistics
!> record every integrator fills, the event and method codes, and the argument
!> checks common to RK4 and CVODE.
module pendula_ode
  use pendula_kinds, only: wp, i8
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use pendula_format, only: format_int
  use pendula_status, only: status_t, set_error, check_finite, check_positive, &
                            check_nonnegative, check_size, check_increasing, PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_SIZE
  implicit none
  private
  public :: ode_stats_t, pendulum_rhs, pendulum_jacobian, check_problem, &
            linear_eigenvalues, check_cvode_options, check_span
  ! shared by the batch integrators (pendula_rk4_batch, pendula_cvode_batch)
  public :: check_batch_shapes, batch_index
  ! for the f2py glue: counters and budgets as the doubles Python passes
  public :: ode_stats_values, step_budget
  public :: PENDULA_CVODE_ADAMS, PENDULA_CVODE_BDF, PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO
  public :: bottom_sign

  !> CVODE linear multistep families: Adams-Moulton (non-stiff, orders 1-12)
  !> and BDF (stiff, orders 1-5).
  integer, parameter :: PENDULA_CVODE_ADAMS = 1
  integer, parameter :: PENDULA_CVODE_BDF = 2
  !> Event kinds: a turning point (Omega = 0, theta at an extremum) and a zero
  !> crossing (theta = 0 mod 2 pi, the pendulum passes the bottom; see bottom_sign).
  integer, parameter :: PENDULA_EVENT_TURNING = 1
  integer, parameter :: PENDULA_EVENT_ZERO = 2

  !> Work counters of one integration.  RK4 fills steps and rhs_evals; CVODE
  !> fills all of them (root_evals counts evaluations of the event functions).
  type :: ode_stats_t
    integer(i8) :: steps = 0
    integer(i8) :: rhs_evals = 0
    integer(i8) :: jac_evals = 0
    integer(i8) :: err_test_fails = 0
    integer(i8) :: nonlin_iters = 0
    integer(i8) :: nonlin_fails = 0
    integer(i8) :: root_evals = 0
  end type ode_stats_t

contains

  !> The event function of a zero crossing, for every event finder (CVODE's
  !> root function, the scenes' closed forms and sampled trajectories):
  !> sin(theta/2), zero exactly at theta = 2 pi k and of one sign between, so
  !> that a pass through the bottom counts whatever the unwrapped angle (a
  !> rotation counts one per turn).
  elemental real(wp) function bottom_sign(theta) result(f)
    real(wp), intent(in) :: theta  !< angle [rad]
    f = sin(theta/2)
  end function bottom_sign

  !> Right-hand side of eq. 2.2 as a system: theta' = Omega,
  !> Omega' = -gamma Omega - w0**2 sin(theta); w0sq = w0**2 [1/s^2], gamma [1/s].
  elemental subroutine pendulum_rhs(theta, omega, w0sq, gamma, dtheta, domega)
    real(wp), intent(in) :: theta  !< angle [rad]
    real(wp), intent(in) :: omega  !< angular velocity [rad/s]
    real(wp), intent(in) :: w0sq  !< w0**2 [1/s^2]
    real(wp), intent(in) :: gamma  !< damping rate [1/s]
    real(wp), intent(out) :: dtheta  !< theta' = Omega [rad/s]
    real(wp), intent(out) :: domega  !< Omega' [rad/s^2]
    dtheta = omega
    domega = -gamma*omega - w0sq*sin(theta)
  end subroutine pendulum_rhs

  !> Jacobian d(theta', Omega')/d(theta, Omega) = [[0, 1], [-w0**2 cos(theta), -gamma]].
  pure subroutine pendulum_jacobian(theta, w0sq, gamma, jac)
    real(wp), intent(in) :: theta  !< angle [rad]
    real(wp), intent(in) :: w0sq  !< w0**2 [1/s^2]
    real(wp), intent(in) :: gamma  !< damping rate [1/s]
    real(wp), intent(out) :: jac(2, 2)  !< the Jacobian [[0, 1], [-w0sq cos(theta), -gamma]]
    jac(1, 1) = 0
    jac(1, 2) = 1
    jac(2, 1) = -w0sq*cos(theta)
    jac(2, 2) = -gamma
  end subroutine pendulum_jacobian

  !> Eigenvalues of the problem linearised about theta = 0 (text eqs. 2.4-2.18):
  !> lambda = -gamma/2 +- sqrt(gamma**2/4 - w0**2), as (re, im) pairs; the first
  !> has the larger modulus.  Written without gamma**2 so that it neither
  !> overflows nor cancels (the small real root comes from lambda1 lambda2 = w0**2).
  pure subroutine linear_eigenvalues(w0, gamma, lam1, lam2)
    real(wp), intent(in) :: w0  !< angular frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    complex(wp), intent(out) :: lam1  !< eigenvalue of the larger modulus [1/s]
    complex(wp), intent(out) :: lam2  !< the other eigenvalue [1/s]
    real(wp) :: half, s
    half = gamma/2
    if (half >= w0) then
      s = sqrt(half - w0)*sqrt(half + w0)
      lam1 = cmplx(-(half + s), 0, wp)
      lam2 = cmplx((w0/(half + s))*(-w0), 0, wp)
    else
      s = sqrt(w0 - half)*sqrt(w0 + half)
      lam1 = cmplx(-half, s, wp)
      lam2 = cmplx(-half, -s, wp)
    end if
  end subroutine linear_eigenvalues

  !> Checks shared by every integrator: t strictly increasing, finite, at least
  !> one element (t(1) is the initial time); finite theta0, omega0; w0 > 0;
  !> gamma >= 0.
  pure subroutine check_problem(t, theta0, omega0, w0, gamma, status)
    real(wp), intent(in) :: t(:)  !< output times [s]: finite, strictly increasing, size >= 1
    real(wp), intent(in) :: theta0  !< initial angle theta(t(1)) [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity Omega(t(1)) [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency sqrt(g/l) [1/s], finite, > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s]
    type(status_t), intent(inout) :: status
    !< the first error of the call is kept: set here only if nothing failed before
    call check_size('t', size(t), 1, status)
    call check_increasing('t', t, status)
    call check_finite('theta0', theta0, status)
    call check_finite('omega0', omega0, status)
    call check_positive('w0', w0, status)
    call check_nonnegative('gamma', gamma, status)
  end subroutine check_problem

  !> CVODE's settings that a batch shares: method PENDULA_CVODE_ADAMS or
  !> PENDULA_CVODE_BDF, step budget max_steps >= 1.
  pure subroutine check_cvode_options(method, max_steps, status)
    integer, intent(in) :: method  !< PENDULA_CVODE_ADAMS (non-stiff) or PENDULA_CVODE_BDF (stiff)
    integer(i8), intent(in) :: max_steps  !< per-state step budget, >= 1
    type(status_t), intent(inout) :: status
    !< the first error of the call is kept: set here only if nothing failed before
    if (status%code == PENDULA_OK .and. method /= PENDULA_CVODE_ADAMS .and. method /= PENDULA_CVODE_BDF) &
      call set_error(status, PENDULA_ERR_DOMAIN, 'method = '//format_int(method)// &
                     ' is out of range: it must be PENDULA_CVODE_ADAMS (1) or PENDULA_CVODE_BDF (2)')
    if (status%code == PENDULA_OK .and. max_steps < 1) &
      call set_error(status, PENDULA_ERR_DOMAIN, 'max_steps = '//format_int(max_steps)// &
                     ' is out of range: it must be >= 1')
  end subroutine check_cvode_options

  !> Require t(n) - t(1) to be finite (t already checked by check_problem).
  pure subroutine check_span(t, status)
    real(wp), intent(in) :: t(:)  !< output times [s] to check
    type(status_t), intent(inout) :: status
    !< the first error of the call is kept: set here only if nothing failed before
    if (status%code /= PENDULA_OK) return
    ! t(n) - t(1) overflows only for t(1) < 0 < t(n); decided without
    ! forming it (the overflow would trap in the checked build)
    if (t(1) < 0 .and. t(size(t)) > huge(t) + t(1)) &
      call set_error(status, PENDULA_ERR_DOMAIN, 't spans more than the largest double (t(n) - t(1) '// &
                     'overflows): no integration can cover that window')
  end subroutine check_span

  !> The size and threads checks of a batch call (rk4_batch, cvode_batch) over
  !> n states and nt times, after the caller's own checks of t: params_ok
  !> (each per-state parameter named in params has one element or n), theta
  !> and omega of shape (nt, n), n_codes and n_counts (the array named in
  !> counts) equal to n, threads >= 0.  The first failed check sets status.
  pure subroutine check_batch_shapes(nt, n, params_ok, params, theta, omega, n_codes, n_counts, counts, &
                                     threads, status)
    integer, intent(in) :: nt  !< number of output times
    integer, intent(in) :: n  !< number of states
    integer, intent(in) :: n_codes  !< size of the codes array
    integer, intent(in) :: n_counts  !< size of the array named counts
    logical, intent(in) :: params_ok  !< whether every per-state parameter has one element or n
    character(len=*), intent(in) :: params  !< names of the per-state parameters, for the message
    character(len=*), intent(in) :: counts  !< name of the per-state counter array, for the message
    real(wp), intent(in) :: theta(:, :)  !< output angles, shape (nt, n)
    real(wp), intent(in) :: omega(:, :)  !< output angular velocities, shape (nt, n)
    integer, intent(in), optional :: threads  !< optional thread count, >= 0
    type(status_t), intent(inout) :: status
    !< the first error of the call is kept: set here only if nothing failed before
    if (.not. params_ok) then
      call set_error(status, PENDULA_ERR_SIZE, params//' must each have one '// &
                     'element or one per state (size(theta0) = '//format_int(n)//')')
    else if (any(shape(theta) /= [nt, n]) .or. any(shape(omega) /= [nt, n])) then
      call set_error(status, PENDULA_ERR_SIZE, 'theta and omega must have shape (size(t), size(theta0)) = ('// &
                     format_int(nt)//', '//format_int(n)//')')
    else if (n_codes /= n .or. n_counts /= n) then
      call set_error(status, PENDULA_ERR_SIZE, 'codes and '//counts//' must have one element per state ('// &
                     format_int(n)//')')
    else if (present(threads)) then
      if (threads < 0) call set_error(status, PENDULA_ERR_DOMAIN, 'threads = '//format_int(threads)// &
                                      ' is out of range: it must be >= 0 (0: the OpenMP default)')
    end if
  end subroutine check_batch_shapes

  !> Index of state i's value in a batch parameter array of one element or n.
  pure integer function batch_index(a, i) result(at)
    real(wp), intent(in) :: a(:)  !< a batch parameter array of one element or n
    integer, intent(in) :: i  !< state index, 1..n
    at = merge(i, 1, size(a) > 1)
  end function batch_index

  !> The counters of `stats` as doubles (exact up to 2**53), in the order steps,
  !> rhs_evals, jac_evals, err_test_fails, nonlin_iters, nonlin_fails, root_evals.
  pure function ode_stats_values(stats) result(v)
    type(ode_stats_t), intent(in) :: stats  !< the counters
    real(wp) :: v(7)
    v = [real(stats%steps, wp), real(stats%rhs_evals, wp), real(stats%jac_evals, wp), &
         real(stats%err_test_fails, wp), real(stats%nonlin_iters, wp), real(stats%nonlin_fails, wp), &
         real(stats%root_evals, wp)]
  end function ode_stats_values

  !> A step budget given as a double (a Python int of any size) as int64,
  !> clamped to +-9e18 (inside the int64 range).
  elemental integer(i8) function step_budget(max_steps) result(budget)
    real(wp), intent(in) :: max_steps  !< step budget as a double (any size)
    budget = int(min(max(max_steps, -9.0e18_wp), 9.0e18_wp), i8)
  end function step_budget

end module pendula_ode
