!> The nonlinear damped pendulum theta'' + gamma theta' + w0**2 sin(theta) = 0
!> (text eq. 2.2) by an adaptive Taylor-series method (Jorba & Zou, Exp.
!> Math. 14 (2005) 99): series by automatic differentiation
!> (pendula_taylor_series), order and step from a tolerance, dense output and
!> events from the step polynomial, backward integration for decreasing t.
!>
!> `tol` is the absolute accuracy asked for at the outputs (theta in rad,
!> Omega/w0 in rad), not a per-step tolerance.  Three things keep it honest
!> over long windows:
!> - the per-step truncation target is tol divided by the expected number of
!>   steps and by the phase shear over the window, that of the decaying
!>   energy for a damped swing (see taylor_step_tolerance);
!> - the state and the time are carried as double-doubles (the first term
!>   theta' h exactly, by two_prod), so rounding grows with the size of the
!>   increments, not as n eps |theta| over n steps;
!> - every output carries an error estimate: the sum A of the local
!>   truncation and rounding bounds, plus their growth D' = G A (linear in
!>   time, G the energy-frequency shear of taylor_shear), capped by the
!>   Gronwall bound D' = L (A + D), L = 1 + gamma/w0 (max norm of the scaled
!>   Jacobian); estimate = TAYLOR_SAFETY (sqrt(2) (A + D) + the truncation
!>   and rounding bounds of the whole step the output lies in) + the output's
!>   own rounding.  Calibrated against mpmath and the exact elliptic solution
!>   (tests/python/test_taylor.py).
module pendula_taylor
  use pendula_kinds, only: wp, i8
  use pendula_constants, only: two_pi, two_pi_lo
  use pendula_format, only: format_short
  use pendula_status, only: status_t, set_error, check_finite, check_positive, check_nonnegative, check_size, &
                         check_same_size, check_all_finite, PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_ORDER, PENDULA_ERR_SOLVER, &
                            PENDULA_ERR_MAXSTEPS, PENDULA_ERR_CANCELLED
  use pendula_control, only: CONTROL_SIZE, cancel_requested, add_progress
  use pendula_ode, only: ode_stats_t, PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO
  use pendula_double_double, only: two_sum, two_prod
  use pendula_drive, only: drive_t, DRIVE_PIVOT, check_drive
  use pendula_taylor_series, only: TAYLOR_MAX_ORDER, taylor_coefficients, taylor_coefficients_driven, taylor_drive_series, &
                                   taylor_order, taylor_step, &
                                   taylor_shear
  implicit none
  private
  public :: taylor_solve, taylor_solve_events, taylor_run, taylor_check, taylor_outcome
  public :: taylor_step_tolerance, TAYLOR_DEFAULT_MAX_STEPS, TAYLOR_SAFETY

  !> Default step budget of one call (~10 min of CPU at ~0.5 us a step).
  integer(i8), parameter :: TAYLOR_DEFAULT_MAX_STEPS = 1000000000_i8
  !> Factor on the propagated error bound (calibrated: the measured error
  !> stays below the estimate with this margin in every test case).
  real(wp), parameter :: TAYLOR_SAFETY = 2
  ! Per-step rounding: this many ulps of the sum of absolute terms.
  real(wp), parameter :: ROUND_ULPS = 2
  ! Largest step in w0 t: below half a small-swing period (pi), so a step holds
  ! at most one turning point and one pass through the bottom per level.
  real(wp), parameter :: MAX_STEP_TAU = 2
  ! Smallest per-step tolerance: below it truncation is far under rounding.
  real(wp), parameter :: EPS_FLOOR = 1.0e-18_wp
  real(wp), parameter :: ULP = epsilon(1.0_wp)/2
  integer, parameter :: POLL_STEPS = 128
  ! Outputs evaluated side by side (series_sums_lanes).
  integer, parameter :: OUT_LANES = 4

contains

  !> Per-step truncation tolerance for a run of tau = w0 |t(n) - t(1)| with
  !> initial scaled energy e0: tol / ((1 + n_est) (1 + Gbar tau/2)), n_est =
  !> 3 tau (1 + gamma/w0) the expected steps, Gbar tau/2 the mean growth by
  !> the shear (the initial shear G(e0); for the long steps of a damped swing,
  !> G along an upper bound of the decaying energy); never below EPS_FLOOR (1e-18, where
  !> rounding dominates) nor above tol.
  pure real(wp) function taylor_step_tolerance(tol, tau, gamma_over_w0, e0) result(eps)
    real(wp), intent(in) :: tol  !< accuracy asked at the outputs, > 0
    real(wp), intent(in) :: tau  !< window length in units of 1/w0, >= 0
    real(wp), intent(in) :: gamma_over_w0  !< gamma/w0, >= 0
    real(wp), intent(in) :: e0  !< initial scaled energy Omega**2/(2 w0**2) + 1 - cos(theta)
    logical :: short
    call step_plan(tol, tau, gamma_over_w0, e0, 0.0_wp, eps, short)
  end function taylor_step_tolerance

  ! taylor_step_tolerance's eps, and short: whether the window is
  ! rounding-limited yet tol is within reach, so that it takes taylor_order's
  ! short steps (the accumulated rounding grows like the square root of the
  ! step).  The rounding estimate of short steps is 1-9 times
  ! r = 0.1 epsilon sqrt(n_est) (1 + G tau/2) (measured at 30 and 1000 s and
  ! near the separatrix), that of long steps ~2 times more: short when
  ! 20 r > tol (rounding may matter) and r <= 2 tol (tol may be reached).
  ! With the long steps of the default order the omitted tail is ~0.6 eps a
  ! step instead of ~0.3 eps: eps is halved.
  ! lip > 0 (a driven run): the growth is Gronwall's, the mean of
  ! exp(lip (tau - s)) over the window, in place of the shear's.
  pure subroutine step_plan(tol, tau, gamma_over_w0, e0, lip, eps, short)
    real(wp), intent(in) :: tol, tau, gamma_over_w0, e0, lip
    real(wp), intent(out) :: eps
    logical, intent(out) :: short
    real(wp) :: n_est, growth, growth0, r
    n_est = 1 + 3*tau*(1 + gamma_over_w0)
    ! the error estimate is ~ TAYLOR_SAFETY sqrt(2) 0.3 eps per step (the
    ! omitted tail at the optimal order), grown on average by G tau/2
    if (lip > 0) then
      growth = min(lip*tau, 40.0_wp)
      if (growth > 0) growth = (exp(growth) - 1)/growth
      growth = max(growth, 1.0_wp)
    else
      growth = 1 + min(shear_growth(tau, gamma_over_w0, e0), 1.0e12_wp)
    end if
    growth0 = growth
    if (.not. lip > 0) growth0 = 1 + min(taylor_shear(e0)*tau/2, 1.0e12_wp)
    ! rounding, and the short steps' tolerance, from the initial shear (their
    ! calibration); the long steps' from the decaying shear (shear_growth)
    r = 0.1_wp*epsilon(1.0_wp)*sqrt(n_est)*growth0
    short = 20*r > tol .and. r <= 2*tol
    if (short) then
      eps = tol/(n_est*growth0)
    else
      eps = tol/(n_est*growth)/2
    end if
    eps = min(tol, max(EPS_FLOOR, eps))
    if (.not. eps >= EPS_FLOOR) eps = EPS_FLOOR   ! NaN-proof
  end subroutine step_plan

  ! (1/tau) int_0^tau G(e(s)) s ds: the mean growth of an error committed at
  ! a steady rate, by the shear G of the energy e(s) at time s (the estimate
  ! of taylor_run grows its committed error A by D' = G A, G refreshed as e
  ! moves).  Undamped, or a rotation (e0 >= 2, whose decay leads to the
  ! separatrix), or a damping that barely moves e over the window: G(e0)
  ! tau/2.  A damped swing loses energy, de/ds = -(gamma/w0) <u**2>, and G
  ! falls with it: <u**2> = kappa e over a swing, kappa = 2 (E/K - (1 - m))/m
  ! (m = e/2: the action over the period), bounded below by
  ! 4/(4 + ln(1/(1 - m))) (1 as m -> 0, its 4/ln(16/(1 - m)) as m -> 1),
  ! which makes e an upper bound; G grows with e, so G at the start of each
  ! of NSHEAR pieces bounds it over the piece: an upper bound of the growth.
  pure real(wp) function shear_growth(tau, gamma_over_w0, e0) result(gr)
    real(wp), intent(in) :: tau, gamma_over_w0, e0
    integer, parameter :: NSHEAR = 8
    real(wp) :: e, ds, s0, kappa
    integer :: j
    if (.not. (gamma_over_w0*tau > 0.05_wp .and. e0 < 2 .and. tau <= 1.0e12_wp)) then
      gr = taylor_shear(e0)*tau/2
      return
    end if
    ds = tau/NSHEAR
    e = e0
    gr = 0
    do j = 0, NSHEAR - 1
      s0 = j*ds
      ! int over [s0, s0 + ds] of s ds, G held at its value at s0
      gr = gr + min(taylor_shear(e), 1.0e50_wp)*ds*(s0 + ds/2)
      kappa = 4/(4 - log(max(1 - e/2, tiny(1.0_wp))))
      e = e*exp(-gamma_over_w0*kappa*ds)
    end do
    gr = gr/tau
  end function shear_growth

  !> Argument checks of taylor_solve: t finite and strictly monotonic
  !> (decreasing integrates backwards), size >= 1, with a finite span; theta0,
  !> omega0 finite; w0 > 0; gamma >= 0; 0 < tol <= 1; max_steps >= 1.
  pure subroutine taylor_check(t, theta0, omega0, w0, gamma, tol, max_steps, status)
    real(wp), intent(in) :: t(:)  !< output times [s]
    real(wp), intent(in) :: theta0  !< initial angle [rad]
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s]
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s]
    real(wp), intent(in) :: gamma  !< damping rate [1/s]
    real(wp), intent(in) :: tol  !< absolute accuracy asked at the outputs
    integer(i8), intent(in) :: max_steps  !< step budget
    type(status_t), intent(inout) :: status
    !< the first error of the call is kept: set here only if nothing failed before
    integer :: i, n
    real(wp) :: dir
    n = size(t)
    call check_size('t', n, 1, status)
    call check_all_finite('t', t, status)
    if (status%code == PENDULA_OK .and. n >= 2) then
      dir = sign(1.0_wp, t(2) - t(1))
      do i = 2, n
        if (.not. dir*(t(i) - t(i - 1)) > 0) then
          call set_error(status, PENDULA_ERR_ORDER, 't must be strictly monotonic (increasing, or decreasing to '// &
                         'integrate backwards), but t['//format_short(real(i - 1, wp))//'] = '//format_short(t(i))// &
                         ' does not continue from t['//format_short(real(i - 2, wp))//'] = '//format_short(t(i - 1)))
          exit
        end if
      end do
      if (status%code == PENDULA_OK .and. abs(t(n)/2 - t(1)/2) > huge(1.0_wp)/2) &
        call set_error(status, PENDULA_ERR_DOMAIN, 't spans more than the largest double (t[-1] - t[0] '// &
                       'overflows): no integration can cover that window')
    end if
    call check_finite('theta0', theta0, status)
    call check_finite('omega0', omega0, status)
    call check_positive('w0', w0, status)
    call check_nonnegative('gamma', gamma, status)
    call check_positive('tol', tol, status)
    if (status%code == PENDULA_OK .and. tol > 1) call set_error(status, PENDULA_ERR_DOMAIN, 'tol = '// &
                                             format_short(tol)//' is out of range: it must be in (0, 1] (absolute accuracy in rad)')
    if (status%code == PENDULA_OK .and. max_steps < 1) call set_error(status, PENDULA_ERR_DOMAIN, &
                                             'max_steps = '//format_short(real(max_steps, wp))//' is out of range: it must be >= 1')
  end subroutine taylor_check

  !> The status of a taylor_run outcome (PENDULA_OK, PENDULA_ERR_SOLVER,
  !> PENDULA_ERR_MAXSTEPS or PENDULA_ERR_CANCELLED) reached at time t_fail [s].
  pure subroutine taylor_outcome(outcome, t_fail, max_steps, status)
    integer, intent(in) :: outcome  !< taylor_run's outcome code
    real(wp), intent(in) :: t_fail  !< time the run stopped at [s]
    integer(i8), intent(in) :: max_steps  !< the step budget of the run
    type(status_t), intent(inout) :: status
    !< the first error of the call is kept: set here only if nothing failed before
    select case (outcome)
    case (PENDULA_ERR_SOLVER)
      call set_error(status, outcome, 'the Taylor integrator produced a non-finite state or a step lost in '// &
                     'rounding at t = '//format_short(t_fail)//' (the state or the parameters are too large for '// &
                     'double precision)')
    case (PENDULA_ERR_MAXSTEPS)
      call set_error(status, outcome, 'the Taylor integrator needs more than max_steps = '// &
                     format_short(real(max_steps, wp))//' steps (stopped at t = '//format_short(t_fail)// &
                     '): raise max_steps, loosen tol or shorten the window')
    case (PENDULA_ERR_CANCELLED)
      call set_error(status, outcome, 'Taylor integration cancelled at t = '//format_short(t_fail)// &
                     ' (interrupted by the caller)')
    end select
  end subroutine taylor_outcome

  !> Integrate theta'' + gamma theta' + w0**2 sin(theta) = 0 by the Taylor
  !> method to the absolute accuracy tol and return theta(i) [rad],
  !> omega(i) [rad/s] and an error estimate err(i) (bound on the error of
  !> theta(i) [rad] and of omega(i)/w0 [rad], whichever is larger) at the
  !> output times t(i) [s].  t: finite, strictly monotonic (decreasing
  !> integrates backwards in time), size >= 1; t(1) is where (theta0, omega0)
  !> holds.  w0 > 0, gamma >= 0 [1/s]; 0 < tol <= 1.  The output grid costs
  !> no steps (dense output from the step polynomials).  Errors (status /=
  !> OK, outputs zero): bad arguments; more than max_steps steps (optional,
  !> default TAYLOR_DEFAULT_MAX_STEPS = 1e9); a non-finite state; the caller's
  !> cancel flag (control, polled every 128 steps, progress counts steps).
  !> order (optional): the series order used.  Accuracy: err(i) <= tol
  !> wherever rounding and the problem's conditioning allow (about 1e-15 over
  !> tens of periods; near the separatrix the estimate grows with the phase
  !> sensitivity and tells).
  subroutine taylor_solve(t, theta0, omega0, w0, gamma, tol, theta, omega, err, stats, status, order, &
                          control, max_steps, drive)
    real(wp), intent(in) :: t(:)
    !< output times [s]: finite, strictly increasing or decreasing, size >= 1; t(1) is the initial time
    real(wp), intent(in) :: theta0  !< initial angle theta(t(1)) [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity Omega(t(1)) [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], finite, > 0
    real(wp), intent(in) :: gamma  !< damping rate b/m [1/s], finite, >= 0
    real(wp), intent(in) :: tol  !< absolute accuracy asked at the outputs [rad], in (0, 1]
    real(wp), intent(out) :: theta(:)  !< theta(t(i)) [rad], size(t) elements
    real(wp), intent(out) :: omega(:)  !< Omega(t(i)) [rad/s], size(t) elements
    real(wp), intent(out) :: err(:)  !< error estimate of each output [rad], size(t) elements
    type(ode_stats_t), intent(out) :: stats  !< steps; rhs_evals = steps * order (series terms)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    integer, intent(out), optional :: order  !< optional: the series order used
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag (polled every 128 steps) and progress counter in steps (pendula_control)
    integer(i8), intent(in), optional :: max_steps  !< optional step budget, >= 1 (default 1e9)
    type(drive_t), intent(in), optional :: drive
    !< optional periodic drive (pendula_drive: a torque or a vertically driven pivot), phase at t = 0
    real(wp) :: ev_t(1), ev_th(1), ev_om(1)
    integer :: ev_k(1), nev
    logical :: trunc
    call solve(t, theta0, omega0, w0, gamma, tol, .false., theta, omega, err, ev_t, ev_k, ev_th, ev_om, nev, trunc, &
               stats, status, order, control, max_steps, drive)
  end subroutine taylor_solve

  !> taylor_solve that also locates the events after t(1) (in the direction of
  !> integration): turning points (Omega = 0, PENDULA_EVENT_TURNING) and passes
  !> through the bottom (theta = 2 pi k, PENDULA_EVENT_ZERO), by root finding
  !> on the step polynomials to machine precision in time.  The first
  !> size(event_t) events are kept (truncated tells whether more occurred).
  subroutine taylor_solve_events(t, theta0, omega0, w0, gamma, tol, theta, omega, err, &
                                 event_t, event_kind, event_theta, event_omega, n_events, truncated, stats, status, order, &
                                 control, max_steps, drive)
    real(wp), intent(in) :: t(:)  !< output times [s], as for taylor_solve
    real(wp), intent(in) :: theta0  !< initial angle [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    real(wp), intent(in) :: tol  !< absolute accuracy asked at the outputs [rad], in (0, 1]
    real(wp), intent(out) :: theta(:)  !< theta(t(i)) [rad], size(t)
    real(wp), intent(out) :: omega(:)  !< Omega(t(i)) [rad/s], size(t)
    real(wp), intent(out) :: err(:)  !< error estimate of each output [rad], size(t)
    real(wp), intent(out) :: event_t(:)  !< event times [s] (the first n_events are set)
    integer, intent(out) :: event_kind(:)  !< PENDULA_EVENT_TURNING or PENDULA_EVENT_ZERO, size(event_t)
    real(wp), intent(out) :: event_theta(:)  !< theta at each event [rad], size(event_t)
    real(wp), intent(out) :: event_omega(:)  !< Omega at each event [rad/s], size(event_t)
    integer, intent(out) :: n_events  !< number of events stored
    logical, intent(out) :: truncated  !< true when more events occurred than the arrays hold
    type(ode_stats_t), intent(out) :: stats  !< steps; rhs_evals = steps * order
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    integer, intent(out), optional :: order  !< optional: the series order used
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag and progress counter in steps (pendula_control)
    integer(i8), intent(in), optional :: max_steps  !< optional step budget, >= 1 (default 1e9)
    type(drive_t), intent(in), optional :: drive  !< optional periodic drive (as for taylor_solve)
    call check_same_size('event_kind', size(event_kind), 'event_t', size(event_t), status)
    call check_same_size('event_theta', size(event_theta), 'event_t', size(event_t), status)
    call check_same_size('event_omega', size(event_omega), 'event_t', size(event_t), status)
    if (status%code /= PENDULA_OK) then
      theta = 0
      omega = 0
      err = 0
      event_t = 0
      event_kind = 0
      event_theta = 0
      event_omega = 0
      n_events = 0
      truncated = .false.
      return
    end if
    call solve(t, theta0, omega0, w0, gamma, tol, .true., theta, omega, err, event_t, event_kind, event_theta, &
               event_omega, n_events, truncated, stats, status, order, control, max_steps, drive)
  end subroutine taylor_solve_events

  subroutine solve(t, theta0, omega0, w0, gamma, tol, with_events, theta, omega, err, ev_t, ev_k, ev_th, ev_om, &
                   nev, trunc, stats, status, order, control, max_steps, drive)
    real(wp), intent(in) :: t(:), theta0, omega0, w0, gamma, tol
    logical, intent(in) :: with_events
    real(wp), intent(out) :: theta(:), omega(:), err(:), ev_t(:), ev_th(:), ev_om(:)
    integer, intent(out) :: ev_k(:), nev
    logical, intent(out) :: trunc
    type(ode_stats_t), intent(out) :: stats
    type(status_t), intent(inout) :: status
    integer, intent(out), optional :: order
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    integer(i8), intent(in), optional :: max_steps
    type(drive_t), intent(in), optional :: drive
    integer(i8) :: budget, steps
    integer :: outcome, p
    real(wp) :: t_fail
    budget = TAYLOR_DEFAULT_MAX_STEPS
    if (present(max_steps)) budget = max_steps
    if (present(order)) order = 0
    nev = 0
    trunc = .false.
    call taylor_check(t, theta0, omega0, w0, gamma, tol, budget, status)
    call check_same_size('theta', size(theta), 't', size(t), status)
    call check_same_size('omega', size(omega), 't', size(t), status)
    call check_same_size('err', size(err), 't', size(t), status)
    if (present(drive)) call check_drive(drive, status)
    if (status%code /= PENDULA_OK) then
      theta = 0
      omega = 0
      err = 0
      return
    end if
    call taylor_run(t, theta0, omega0, w0, gamma, tol, with_events, budget, theta, omega, err, &
                    ev_t, ev_k, ev_th, ev_om, nev, trunc, steps, p, outcome, t_fail, control, drive)
    stats%steps = steps
    stats%rhs_evals = steps*p
    if (present(order)) order = p
    call taylor_outcome(outcome, t_fail, budget, status)
    if (status%code /= PENDULA_OK) then
      theta = 0
      omega = 0
      err = 0
      nev = 0
    end if
  end subroutine solve

  !> The integration itself, on checked arguments (taylor_check), for
  !> taylor_solve and the batch driver: fills theta, omega, err at every t(i),
  !> the events when with_events, steps, the order p, and outcome
  !> (PENDULA_OK, or PENDULA_ERR_SOLVER / _MAXSTEPS / _CANCELLED at t_fail,
  !> the outputs from there on unset).  No allocation; the same arithmetic
  !> for every caller, so a batch state is bit-identical to the scalar call.
  subroutine taylor_run(t, theta0, omega0, w0, gamma, tol, with_events, max_steps, theta, omega, err, &
                        ev_t, ev_k, ev_th, ev_om, nev, trunc, steps, p, outcome, t_fail, control, drive)
    real(wp), intent(in) :: t(:)  !< output times [s], checked
    real(wp), intent(in) :: theta0  !< initial angle [rad]
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s]
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s]
    real(wp), intent(in) :: gamma  !< damping rate [1/s]
    real(wp), intent(in) :: tol  !< absolute accuracy asked at the outputs
    logical, intent(in) :: with_events  !< whether to locate events
    integer(i8), intent(in) :: max_steps  !< step budget
    real(wp), intent(inout) :: theta(:)  !< theta at t [rad]
    real(wp), intent(inout) :: omega(:)  !< Omega at t [rad/s]
    real(wp), intent(inout) :: err(:)  !< error estimates [rad]
    real(wp), intent(inout) :: ev_t(:)  !< event times [s]
    integer, intent(inout) :: ev_k(:)  !< event kinds
    real(wp), intent(inout) :: ev_th(:)  !< theta at the events [rad]
    real(wp), intent(inout) :: ev_om(:)  !< Omega at the events [rad/s]
    integer, intent(out) :: nev  !< events stored
    logical, intent(out) :: trunc  !< more events than the arrays hold
    integer(i8), intent(out) :: steps  !< steps taken
    integer, intent(out) :: p  !< series order
    integer, intent(out) :: outcome  !< PENDULA_OK or the failure code
    real(wp), intent(out) :: t_fail  !< time of the failure [s]
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag and progress counter (pendula_control)
    type(drive_t), intent(in), optional :: drive
    !< optional periodic drive, checked (check_drive); its phase phi holds at t = 0
    real(wp) :: x(0:TAYLOR_MAX_ORDER), v(0:TAYLOR_MAX_ORDER), dc(0:TAYLOR_MAX_ORDER), amp, lip, pc, ps
    real(wp) :: xh, xl, vh, vl, th, tl, h, habs, rem, rs, re, d, ds, de, inv_w0, w0sq, eps_s
    real(wp) :: big_a, big_d, g, ec, es, loc, lgr, s0abs, sn, cs, xe, ve, xel, vel, tau, s, e
    real(wp) :: r0, r1, r2, gam, ga, lt, rnd, trc, committed, ol1, ol2, dl(OUT_LANES), rl(OUT_LANES), rvl(OUT_LANES)
    logical :: short
    integer :: n, i, nl, l
    n = size(t)
    theta(1) = theta0
    omega(1) = omega0
    err(1) = 0
    nev = 0
    trunc = .false.
    steps = 0
    outcome = PENDULA_OK
    t_fail = t(1)
    inv_w0 = 1/max(w0, 1.0e-300_wp)   ! w0 = 5e-324: no overflow (the window is then one step)
    w0sq = w0*w0
    tau = 0
    if (n > 1) tau = w0*abs(t(n)/2 - t(1)/2)*2
    ! (ratios clamped to 1e150 each: no overflow for any finite input)
    ! a drive: the error grows by Gronwall's bound with the Lipschitz constant
    ! of the scaled system, 1 + gamma/w0 + |pivot amplitude|/w0**2 (no shear
    ! model: the driven pendulum may be chaotic)
    lip = 0
    amp = 0
    if (present(drive)) then
      amp = drive%amplitude
      if (drive%kind == DRIVE_PIVOT) amp = drive%amplitude*drive%frequency**2
      lip = 1 + min(gamma*inv_w0, 1.0e150_wp)
      if (drive%kind == DRIVE_PIVOT) lip = lip + min(abs(amp), 1.0e150_wp)*min(inv_w0*inv_w0, 1.0e150_wp)
    end if
    call step_plan(tol, min(tau, 1.0e150_wp), min(gamma, 1.0e150_wp)*min(inv_w0, 1.0e150_wp), &
                   scaled_energy(theta0, sign(min(abs(omega0), 1.0e150_wp), omega0)*min(inv_w0, 1.0e150_wp)), lip, eps_s, short)
    p = taylor_order(eps_s, short)
    if (n == 1) return
    ! Steps are at most 2/w0 and, with damping, ~2/gamma long: a window that
    ! needs more than max_steps is refused before any work.
    if (tau/MAX_STEP_TAU > real(max_steps, wp) .or. (abs(theta0) + abs(omega0) > 0 .and. &
                                                     gamma*abs(t(n)/2 - t(1)/2) > real(max_steps, wp))) then
      outcome = PENDULA_ERR_MAXSTEPS
      return
    end if
    lgr = 1 + min(gamma*inv_w0, 1.0e300_wp)
    if (present(drive)) lgr = lip
    xh = theta0
    xl = 0
    vh = omega0
    vl = 0
    th = t(1)
    tl = 0
    big_a = 0
    big_d = 0
    r0 = 0
    r1 = 0
    r2 = 0
    gam = 0
    lt = 0
    ec = -1
    g = 0
    i = 2
    do
      if (present(drive)) then
        call drive_phase(drive, th, tl, pc, ps)
        call taylor_drive_series(pc, ps, drive%frequency, p, dc)
        call taylor_coefficients_driven(xh, xl, vh, w0sq, gamma, drive%kind, amp, dc, p, x, v, s0abs, sn, cs)
      else
        call taylor_coefficients(xh, xl, vh, w0sq, gamma, p, x, v, s0abs, sn, cs)
        es = scaled_energy_sc(sn, cs, vh*inv_w0)
      end if
      call two_sum(t(n), -th, rs, re)
      rem = rs + (re - tl)
      habs = taylor_step(x, v, p, inv_w0, eps_s, min(abs(rem), MAX_STEP_TAU*inv_w0))
      ! a non-finite series (an overflowing state) or a step lost in the time's rounding
      if (.not. (abs(x(p + 1)) + abs(v(p + 1)) <= huge(1.0_wp) .and. habs > 0) .or. &
          (th + sign(habs, rem) == th .and. habs < abs(rem))) then
        outcome = PENDULA_ERR_SOLVER
        t_fail = th
        return
      end if
      if (habs >= abs(rem)) then
        h = rem
      else
        h = sign(habs, rem)
      end if
      ! the full step first: the state it ends at, and its truncation and
      ! rounding bounds, which bound those of every output inside the step too
      ! (both grow with |d|): the outputs cost one Horner pass each
      call dense_error(h, xe, xel, ve, vel, trc, rnd)
      ! the outputs inside this step, from its polynomial (what was committed
      ! before the step is the same for all of them: formed once)
      committed = -1
      do while (i <= n)
        ! up to OUT_LANES outputs at once: their sums side by side (independent
        ! chains; each output's arithmetic is the one-output sum's)
        nl = 0
        dl = 0
        do while (i + nl <= n .and. nl < OUT_LANES)
          call two_sum(t(i + nl), -th, ds, de)
          d = ds + (de - tl)
          if (abs(d) > abs(h) .and. h /= rem) exit
          nl = nl + 1
          dl(nl) = d
        end do
        if (nl == 0) exit
        if (committed < 0) committed = sqrt(2.0_wp)*(big_a + big_d + rounding_part()) + trc + rnd
        call series_sums_lanes(dl, rl, rvl)
        do l = 1, nl
          call dense_finish(dl(l), rl(l), rvl(l), theta(i), ol1, omega(i), ol2)
          err(i) = TAYLOR_SAFETY*committed + ULP*max(abs(theta(i)), abs(omega(i))*inv_w0)
          i = i + 1
        end do
        if (nl < OUT_LANES) exit
      end do
      if (with_events) call events_in_step(h)
      if (h == rem) exit
      ! advance the double-double state and time by the full step
      if (.not. (abs(xe) <= huge(1.0_wp) .and. abs(ve) <= huge(1.0_wp))) then
        outcome = PENDULA_ERR_SOLVER
        t_fail = th
        return
      end if
      ! error model: growth of what was committed so far, then this step's share
      ! G varies like log|2 - e| and 1/|2 - e|: refreshed when e has moved by
      ! 5% of its distance to 0 or to the separatrix, with a 10% margin
      if (present(drive)) then
        g = 1.0e50_wp   ! no shear model: Gronwall's bound (lgr) decides
      else if (abs(es - ec) > 0.05_wp*min(es, abs(2 - es)) .or. ec < 0) then
        ec = es
        g = 1.1_wp*min(taylor_shear(es), 1.0e50_wp)   ! capped: no inf - inf below
      end if
      big_d = big_d + w0*habs*min(g*big_a, lgr*(big_a + big_d))
      big_a = big_a + trc
      ! rounding: independent from step to step, so summed in quadrature, each
      ! share grown by the integrated shear since it was made (gam)
      gam = min(gam + g*w0*habs, 1.0e100_wp)
      lt = lt + lgr*w0*habs
      r0 = r0 + rnd*rnd
      r1 = r1 + rnd*rnd*gam
      r2 = r2 + rnd*rnd*gam*gam
      xh = xe
      xl = xel
      vh = ve
      vl = vel
      call two_sum(th, h, s, e)
      e = e + tl
      th = s + e
      tl = e - (th - s)
      steps = steps + 1
      ! the budget: spent, or (checked every POLL_STEPS steps) certain to be at this pace
      if (steps >= max_steps .or. (mod(steps, int(POLL_STEPS, i8)) == 0 .and. &
                                   abs(rem)/max(abs(th - t(1)) + abs(tl), tiny(1.0_wp)) > real(max_steps, wp)/real(steps, wp))) then
        outcome = PENDULA_ERR_MAXSTEPS
        t_fail = th
        return
      end if
      if (present(control) .and. mod(steps, int(POLL_STEPS, i8)) == 0) then
        call add_progress(control, int(POLL_STEPS, i8))
        if (cancel_requested(control)) then
          outcome = PENDULA_ERR_CANCELLED
          t_fail = th
          return
        end if
      end if
    end do
    ! the steps since the last poll, so that the progress ends at the step count
    if (present(control)) call add_progress(control, mod(steps, int(POLL_STEPS, i8)))

  contains

    ! The state at offset dd from the step's start, as double-doubles: the
    ! term theta' dd exactly (two_prod), the rest by Horner.
    subroutine dense(dd, xo, xol, vo, vol)
      real(wp), intent(in) :: dd
      real(wp), intent(out) :: xo, xol, vo, vol
      real(wp) :: rest, rv
      call series_sums(dd, rest, rv)
      call dense_finish(dd, rest, rv, xo, xol, vo, vol)
    end subroutine dense

    ! The state at offset dd from the series sums rest and rv (series_sums).
    subroutine dense_finish(dd, rest, rv, xo, xol, vo, vol)
      real(wp), intent(in) :: dd, rest, rv
      real(wp), intent(out) :: xo, xol, vo, vol
      real(wp) :: p1, e1, s1, e2, lo, bb
      call two_prod(vh, dd, p1, e1)
      ! two_sum(xh, p1) and two_sum(vh, rv), written out
      s1 = xh + p1
      bb = s1 - xh
      e2 = (xh - (s1 - bb)) + (p1 - bb)
      lo = e2 + (e1 + vl*dd + xl + rest)
      xo = s1 + lo
      xol = lo - (xo - s1)
      s1 = vh + rv
      bb = s1 - vh
      e2 = (vh - (s1 - bb)) + (rv - bb)
      lo = e2 + vl
      vo = s1 + lo
      vol = lo - (vo - s1)
    end subroutine dense_finish

    ! rest = sum_{k=2..p} x(k) dd**k and rv = sum_{k=1..p} v(k) dd**k by
    ! Horner in dd**2 over the even and the odd k apart: four independent
    ! chains of p/2 multiply-adds instead of two of p (an output's cost is
    ! the latency of these chains).  Rounding as Horner's: a few ulps of the
    ! absolute terms (the terms decay geometrically).  Needs p >= 3.
    subroutine series_sums(dd, rest, rv)
      real(wp), intent(in) :: dd
      real(wp), intent(out) :: rest, rv
      real(wp) :: q, xev, xod, vev, vod
      integer :: k, ke, ko
      q = dd*dd
      ke = p - mod(p, 2)
      ko = p - 1 + mod(p, 2)
      xev = x(ke)
      vev = v(ke)
      xod = x(ko)
      vod = v(ko)
      do k = ke - 2, 2, -2
        xev = xev*q + x(k)
        vev = vev*q + v(k)
      end do
      do k = ko - 2, 3, -2
        xod = xod*q + x(k)
        vod = vod*q + v(k)
      end do
      vod = vod*q + v(1)
      rest = q*(xev + dd*xod)
      rv = q*vev + dd*vod
    end subroutine series_sums

    ! series_sums at OUT_LANES offsets at once, lane by lane the same arithmetic.
    subroutine series_sums_lanes(dd, rest, rv)
      real(wp), intent(in) :: dd(OUT_LANES)
      real(wp), intent(out) :: rest(OUT_LANES), rv(OUT_LANES)
      real(wp) :: q(OUT_LANES), xev(OUT_LANES), xod(OUT_LANES), vev(OUT_LANES), vod(OUT_LANES)
      integer :: k, ke, ko
      q = dd*dd
      ke = p - mod(p, 2)
      ko = p - 1 + mod(p, 2)
      xev = x(ke)
      vev = v(ke)
      xod = x(ko)
      vod = v(ko)
      do k = ke - 2, 2, -2
        xev = xev*q + x(k)
        vev = vev*q + v(k)
      end do
      do k = ko - 2, 3, -2
        xod = xod*q + x(k)
        vod = vod*q + v(k)
      end do
      vod = vod*q + v(1)
      rest = q*(xev + dd*xod)
      rv = q*vev + dd*vod
    end subroutine series_sums_lanes

    ! The state at offset dd (as dense) and the local error bounds of the
    ! polynomial there, in the max norm of (theta, Omega/w0), in one pass over
    ! the coefficients: trc, twice the first omitted term (the tail of a
    ! series decaying at least by 1/2 a term; ~e**-2 at the optimal order),
    ! and rnd, ROUND_ULPS ulps of the absolute terms.
    subroutine dense_error(dd, xo, xol, vo, vol, trc_, rnd_)
      real(wp), intent(in) :: dd
      real(wp), intent(out) :: xo, xol, vo, vol, trc_, rnd_
      real(wp) :: p1, e1, s1, e2, lo, rest, rv, bb, a, sx, sv, ap, q, xev, xod, vev, vod
      integer :: k, ke, ko
      call two_prod(vh, dd, p1, e1)
      call series_sums(dd, rest, rv)
      ! the absolute terms, sum_{k=2..p} |x(k)| a**k and |v(k)| a**k, split
      ! into even and odd k as in series_sums
      a = abs(dd)
      q = a*a
      ke = p - mod(p, 2)
      ko = p - 1 + mod(p, 2)
      xev = abs(x(ke))
      vev = abs(v(ke))
      xod = abs(x(ko))
      vod = abs(v(ko))
      do k = ke - 2, 2, -2
        xev = xev*q + abs(x(k))
        vev = vev*q + abs(v(k))
      end do
      do k = ko - 2, 3, -2
        xod = xod*q + abs(x(k))
        vod = vod*q + abs(v(k))
      end do
      ap = a**(p + 1)
      sx = q*(xev + a*xod) + abs(x(p + 1))*ap
      sv = q*(vev + a*vod) + abs(v(p + 1))*ap
      trc_ = 2*max(abs(x(p + 1)), abs(v(p + 1))*inv_w0)*ap
      rnd_ = ROUND_ULPS*ULP*(sx + (s0abs*a + sv)*inv_w0 + abs(xl) + abs(vl)*inv_w0)
      s1 = xh + p1
      bb = s1 - xh
      e2 = (xh - (s1 - bb)) + (p1 - bb)
      lo = e2 + (e1 + vl*dd + xl + rest)
      xo = s1 + lo
      xol = lo - (xo - s1)
      s1 = vh + rv
      bb = s1 - vh
      e2 = (vh - (s1 - bb)) + (rv - bb)
      lo = e2 + vl
      vo = s1 + lo
      vol = lo - (vo - s1)
    end subroutine dense_error

    ! The rounding so far, grown by the shear: sqrt(sum r_i**2 (1 + Gamma -
    ! Gamma_i)**2) with Gamma the integrated shear, capped by the Gronwall
    ! factor exp(L tau) (near the separatrix the shear model breaks down).
    real(wp) function rounding_part() result(r)
      real(wp) :: q
      q = r0*(1 + gam)**2 - 2*(1 + gam)*r1 + r2
      r = sqrt(max(q, r0))
      r = min(r, sqrt(r0)*exp(min(lt, 700.0_wp)))
    end function rounding_part

    ! Events in (0, hh] of the current step, in time order.
    subroutine events_in_step(hh)
      real(wp), intent(in) :: hh
      real(wp) :: f0, f1, dt_turn, xend, xendl, dummy, lev_h, lev_l, dz, fs, fe
      integer :: j, j1, j2, jstep
      logical :: pending
      ! turning point: Omega changes sign
      pending = .false.
      dt_turn = 0
      f0 = vh
      if (f0 == 0) f0 = v(1)*hh   ! starts at a turning point: the sign just after
      if (f0 == 0) f0 = v(2)*hh*hh
      call dense(hh, xend, xendl, f1, dummy)
      if (f0 /= 0 .and. (f1 == 0 .or. (f1 > 0) .neqv. (f0 > 0))) then
        dt_turn = root(v, vh + vl, hh)
        pending = .true.
      end if
      ! bottom passes: theta crosses a level 2 pi j (monotonic within a step:
      ! a step is shorter than half a swing)
      if (xend > xh) then
        j1 = floor(xh/two_pi) + 1
        j2 = floor(xend/two_pi)
        jstep = 1
      else
        j1 = ceiling(xh/two_pi) - 1
        j2 = ceiling(xend/two_pi)
        jstep = -1
      end if
      do j = j1, j2, jstep
        lev_h = two_pi*j
        lev_l = two_pi_lo*j + (two_pi*real(j, wp) - lev_h)
        fs = (xh - lev_h) + (xl - lev_l)
        fe = (xend - lev_h) + (xendl - lev_l)
        if (fs == 0 .or. .not. (fe == 0 .or. (fe > 0) .neqv. (fs > 0))) cycle
        dz = root(x, fs, hh)
        if (pending .and. abs(dt_turn) < abs(dz)) then
          call emit(dt_turn, PENDULA_EVENT_TURNING)
          pending = .false.
        end if
        call emit(dz, PENDULA_EVENT_ZERO)
      end do
      if (pending) call emit(dt_turn, PENDULA_EVENT_TURNING)
    end subroutine events_in_step

    subroutine emit(dd, kind)
      real(wp), intent(in) :: dd
      integer, intent(in) :: kind
      real(wp) :: xo, vo, dummy
      if (nev >= size(ev_t)) then
        trunc = .true.
        return
      end if
      nev = nev + 1
      call dense(dd, xo, dummy, vo, dummy)
      ev_t(nev) = th + (tl + dd)
      ev_k(nev) = kind
      ev_th(nev) = xo
      ev_om(nev) = vo
    end subroutine emit

    ! Root in (0, hh] of c0 + sum_{k=1..p} a(k) d**k (a sign change between
    ! 0 and hh is known): bracketed Newton with bisection, to a few ulps of d.
    real(wp) function root(a, c0, hh) result(dr)
      real(wp), intent(in) :: a(0:TAYLOR_MAX_ORDER), c0, hh
      real(wp) :: lo, hi, flo, f, df, dn
      integer :: it, k
      lo = 0
      hi = hh
      flo = c0
      dr = hh/2
      if (a(1) /= 0) then
        dn = -c0/a(1)
        if ((dn - lo)*(dn - hi) < 0) dr = dn
      end if
      do it = 1, 100
        f = a(p)
        df = p*a(p)
        do k = p - 1, 1, -1
          f = f*dr + a(k)
          df = df*dr + k*a(k)
        end do
        f = f*dr + c0
        if (f == 0) return
        if ((f > 0) .eqv. (flo > 0)) then
          lo = dr
          flo = f
        else
          hi = dr
        end if
        dn = dr - f/df
        if (.not. ((dn - lo)*(dn - hi) < 0)) dn = (lo + hi)/2
        if (abs(dn - dr) <= 2*ULP*abs(dr) .or. dn == lo .or. dn == hi) then
          dr = dn
          return
        end if
        dr = dn
      end do
    end function root

  end subroutine taylor_run

  ! cos and sin of the drive phase Omega t + phi at the double-double time
  ! th + tl: Omega th exactly (two_prod), reduced by 2 pi in double-double,
  ! so that the phase keeps ~1e-16 absolute accuracy over long windows.
  pure subroutine drive_phase(drive, th, tl, c, s)
    type(drive_t), intent(in) :: drive
    real(wp), intent(in) :: th, tl
    real(wp), intent(out) :: c, s
    real(wp) :: ph, pe, s1, e1, kk, a, b, psi
    call two_prod(drive%frequency, th, ph, pe)
    call two_sum(ph, pe + drive%frequency*tl + drive%phase, s1, e1)
    kk = anint(s1/two_pi)
    call two_prod(kk, two_pi, a, b)
    psi = (((s1 - a) - b) + e1) - kk*two_pi_lo
    c = cos(psi)
    s = sin(psi)
  end subroutine drive_phase

  ! Scaled energy u**2/2 + 1 - cos(x) (u = Omega/w0), 1 - cos(x) as
  ! 2 sin(x/2)**2 (no cancellation for small swings).
  pure real(wp) function scaled_energy(xx, u) result(e)
    real(wp), intent(in) :: xx, u
    e = u*u/2 + 2*sin(xx/2)**2
  end function scaled_energy

  ! The same from sin(x), cos(x): 1 - cos = sin**2/(1 + cos) for cos > 0.
  pure real(wp) function scaled_energy_sc(sn, cs, u) result(e)
    real(wp), intent(in) :: sn, cs, u
    if (cs > 0) then
      e = u*u/2 + sn*sn/(1 + cs)
    else
      e = u*u/2 + (1 - cs)
    end if
  end function scaled_energy_sc

end module pendula_taylor
