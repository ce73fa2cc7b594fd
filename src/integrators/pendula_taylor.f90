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
  use pendula_format, only: format_short
  use pendula_status, only: status_t, set_error, check_finite, check_positive, check_nonnegative, check_size, &
                         check_same_size, check_all_finite, PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_ORDER, PENDULA_ERR_SOLVER, &
                            PENDULA_ERR_MAXSTEPS, PENDULA_ERR_CANCELLED
  use pendula_control, only: CONTROL_SIZE, add_progress
  use pendula_ode, only: ode_stats_t
  use pendula_drive, only: drive_t, DRIVE_PIVOT, check_drive
  use pendula_taylor_series, only: taylor_order, taylor_shear
  use pendula_taylor_walk, only: taylor_walk_t, taylor_walk_run, TAYLOR_SAFETY, MAX_STEP_TAU, POLL_STEPS
  implicit none
  private
  public :: taylor_solve, taylor_solve_events, taylor_run, taylor_start, taylor_check, taylor_outcome
  public :: taylor_step_tolerance, TAYLOR_DEFAULT_MAX_STEPS, TAYLOR_SAFETY

  !> Default step budget of one call (~10 min of CPU at ~0.5 us a step).
  integer(i8), parameter :: TAYLOR_DEFAULT_MAX_STEPS = 1000000000_i8
  ! Smallest per-step tolerance: below it truncation is far under rounding.
  real(wp), parameter :: EPS_FLOOR = 1.0e-18_wp

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
    type(taylor_walk_t) :: w
    nev = 0
    trunc = .false.
    call taylor_start(t, theta0, omega0, w0, gamma, tol, max_steps, theta, omega, err, w, drive)
    steps = 0
    p = w%p
    outcome = w%outcome
    t_fail = w%t_fail
    if (size(t) == 1 .or. outcome /= PENDULA_OK) return
    call taylor_walk_run(w, t, with_events, max_steps, theta, omega, err, ev_t, ev_k, ev_th, ev_om, nev, trunc, control, drive)
    steps = w%steps
    outcome = w%outcome
    t_fail = w%t_fail
    ! the steps since the last poll, so that the progress ends at the step count
    if (present(control) .and. outcome == PENDULA_OK) call add_progress(control, mod(steps, int(POLL_STEPS, i8)))
  end subroutine taylor_run

  !> The start of an integration on checked arguments (taylor_check): theta,
  !> omega, err at t(1), and the walk w (pendula_taylor_walk) at (theta0,
  !> omega0) with its per-step tolerance and order (step_plan, taylor_order).
  !> w%outcome: PENDULA_OK, or PENDULA_ERR_MAXSTEPS when the window certainly
  !> needs more than max_steps steps.  For taylor_run and the batch kernel.
  subroutine taylor_start(t, theta0, omega0, w0, gamma, tol, max_steps, theta, omega, err, w, drive)
    real(wp), intent(in) :: t(:)  !< output times [s], checked
    real(wp), intent(in) :: theta0  !< initial angle [rad]
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s]
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s]
    real(wp), intent(in) :: gamma  !< damping rate [1/s]
    real(wp), intent(in) :: tol  !< absolute accuracy asked at the outputs
    integer(i8), intent(in) :: max_steps  !< step budget
    real(wp), intent(inout) :: theta(:)  !< theta at t [rad]: theta(1) set
    real(wp), intent(inout) :: omega(:)  !< Omega at t [rad/s]: omega(1) set
    real(wp), intent(inout) :: err(:)  !< error estimates [rad]: err(1) set
    type(taylor_walk_t), intent(out) :: w  !< the walk, ready for its first step
    type(drive_t), intent(in), optional :: drive
    !< optional periodic drive, checked (check_drive); its phase phi holds at t = 0
    real(wp) :: inv_w0, tau, lip, eps_s
    logical :: short
    integer :: n
    n = size(t)
    theta(1) = theta0
    omega(1) = omega0
    err(1) = 0
    w%outcome = PENDULA_OK
    w%t_fail = t(1)
    inv_w0 = 1/max(w0, 1.0e-300_wp)   ! w0 = 5e-324: no overflow (the window is then one step)
    w%inv_w0 = inv_w0
    w%w0 = w0
    w%w0sq = w0*w0
    w%gamma = gamma
    tau = 0
    if (n > 1) tau = w0*abs(t(n)/2 - t(1)/2)*2
    ! (ratios clamped to 1e150 each: no overflow for any finite input)
    ! a drive: the error grows by Gronwall's bound with the Lipschitz constant
    ! of the scaled system, 1 + gamma/w0 + |pivot amplitude|/w0**2 (no shear
    ! model: the driven pendulum may be chaotic)
    lip = 0
    w%amp = 0
    w%driven = present(drive)
    if (present(drive)) then
      w%amp = drive%amplitude
      if (drive%kind == DRIVE_PIVOT) w%amp = drive%amplitude*drive%frequency**2
      lip = 1 + min(gamma*inv_w0, 1.0e150_wp)
      if (drive%kind == DRIVE_PIVOT) lip = lip + min(abs(w%amp), 1.0e150_wp)*min(inv_w0*inv_w0, 1.0e150_wp)
    end if
    call step_plan(tol, min(tau, 1.0e150_wp), min(gamma, 1.0e150_wp)*min(inv_w0, 1.0e150_wp), &
                   scaled_energy(theta0, sign(min(abs(omega0), 1.0e150_wp), omega0)*min(inv_w0, 1.0e150_wp)), lip, eps_s, short)
    w%eps_s = eps_s
    w%p = taylor_order(eps_s, short)
    if (n == 1) return
    ! Steps are at most 2/w0 and, with damping, ~2/gamma long: a window that
    ! needs more than max_steps is refused before any work.
    if (tau/MAX_STEP_TAU > real(max_steps, wp) .or. (abs(theta0) + abs(omega0) > 0 .and. &
                                                     gamma*abs(t(n)/2 - t(1)/2) > real(max_steps, wp))) then
      w%outcome = PENDULA_ERR_MAXSTEPS
      return
    end if
    w%lgr = 1 + min(gamma*inv_w0, 1.0e300_wp)
    if (present(drive)) w%lgr = lip
    w%xh = theta0
    w%xl = 0
    w%vh = omega0
    w%vl = 0
    w%th = t(1)
    w%tl = 0
  end subroutine taylor_start

  ! Scaled energy u**2/2 + 1 - cos(x) (u = Omega/w0), 1 - cos(x) as
  ! 2 sin(x/2)**2 (no cancellation for small swings).
  pure real(wp) function scaled_energy(xx, u) result(e)
    real(wp), intent(in) :: xx, u
    e = u*u/2 + 2*sin(xx/2)**2
  end function scaled_energy

end module pendula_taylor
