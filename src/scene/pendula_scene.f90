!> Scenes: answer a question about a pendulum with the cheapest model whose
!> error fits a tolerance, say which model and why, and back the answer with
!> an error estimate.
!>
!> A scene is the text's parameters (w0 = sqrt(g/l), gamma = b/m; see
!> scene_physics), an initial state (theta0, Omega0) at t = 0, a window of
!> output times t(:) >= 0, what is wanted (SCENE_WANT_*) and a tolerance tol:
!> an ABSOLUTE bound on theta [rad] over the whole window, with Omega scaled by
!> w0, i.e. the error measure is sup_t max(|d theta|, |d Omega|/w0).
!>
!> Models, cheapest first (SCENE_MODEL_*):
!>  * small_angle (gamma = 0): theta0 cos w0t + (Omega0/w0) sin w0t; its
!>    rigorous bound over the window (pendula_small_angle, phase drift
!>    ~ (m/4) w0 t) decides;
!>  * linear damped closed form (gamma > 0): error of dropping sin(theta) -
!>    theta, estimated a priori (see linear_estimate: amplitude^2 frequency
!>    shift accumulated over the decaying window, and a Green's-function bound);
!>  * exact undamped (gamma = 0): elliptic closed form, error a few eps times
!>    the problem's condition number (exact_estimate);
!>  * rk4: step chosen from tol and the window length (global error ~ C h^4 T),
!>    verified a posteriori by a second run at 2h (Richardson: the difference
!>    over the output grid / 15 estimates the error of the h run); refined
!>    until the estimate meets tol;
!>  * cvode: rtol/atol chosen from tol and the number of periods in the window
!>    (a local tolerance is not a global error), verified by a second run ten
!>    times tighter; the tighter run is returned and the difference is its
!>    (conservative) error estimate.
!> Only what the scene asks for is computed: SCENE_WANT_PERIOD evaluates K once
!> (no time series), SCENE_WANT_FINAL keeps no history (RK4 final-state mode),
!> SCENE_WANT_ENERGY with gamma = 0 is the constant energy of the initial state.
module pendula_scene
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_is_finite
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_sci, format_int
  use pendula_status, only: status_t, set_error, check_finite, check_positive, check_nonnegative, &
      check_increasing, check_size, PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_UNAVAILABLE, &
      PENDULA_ERR_SIZE, PENDULA_MSG_LEN, PENDULA_ERR_MAXSTEPS, PENDULA_ERR_CANCELLED
  use pendula_physics, only: natural_frequency, damping_rate, pi
  use pendula_elliptic, only: ellipkm1
  use pendula_undamped, only: undamped_motion_t, undamped_init, undamped_eval, pendulum_energy, &
      REGIME_LIBRATION, REGIME_SEPARATRIX, REGIME_ROTATION
  use pendula_small_angle, only: small_angle_eval, small_angle_bound
  use pendula_linear_damped, only: linear_damped_t, linear_damped_init, linear_damped_state, &
      DAMPING_UNDERDAMPED
  use pendula_integrators, only: ode_stats_t, rk4_solve, rk4_final_state, rk4_max_stable_step, &
      cvode_solve, cvode_solve_events, cvode_available, PENDULA_CVODE_ADAMS, PENDULA_CVODE_BDF, &
      PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO
  use pendula_control, only: CONTROL_SIZE, cancel_requested
  implicit none
  private

  public :: scene_t, scene_result_t, scene_cost_t
  public :: scene_init, scene_physics, scene_solve, scene_run_model, scene_estimate
  public :: scene_model_name, scene_model_code, scene_want_name, scene_want_code
  public :: SCENE_MODEL_AUTO, SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR, &
            SCENE_MODEL_RK4, SCENE_MODEL_CVODE
  public :: SCENE_WANT_STATE, SCENE_WANT_THETA, SCENE_WANT_FINAL, SCENE_WANT_ENERGY, &
            SCENE_WANT_PERIOD, SCENE_WANT_EVENTS
  public :: PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO

  !> Model codes (0 = let scene_solve choose).
  integer, parameter :: SCENE_MODEL_AUTO = 0, SCENE_MODEL_SMALL_ANGLE = 1, SCENE_MODEL_EXACT = 2, &
      SCENE_MODEL_LINEAR = 3, SCENE_MODEL_RK4 = 4, SCENE_MODEL_CVODE = 5
  !> What a scene asks for: theta and Omega at t(:); theta only; the state at
  !> t(n) only; the energy per unit m l^2 [1/s^2] at t(:); the period (or time
  !> per revolution) [s]; turning points (Omega = 0) and zero crossings
  !> (theta = 0) in (0, t(n)].
  integer, parameter :: SCENE_WANT_STATE = 1, SCENE_WANT_THETA = 2, SCENE_WANT_FINAL = 3, &
      SCENE_WANT_ENERGY = 4, SCENE_WANT_PERIOD = 5, SCENE_WANT_EVENTS = 6

  real(wp), parameter :: eps = epsilon(1.0_wp)
  !> Safety factor on the a priori nonlinearity estimate of the linear model
  !> (calibrated: the estimate is within 3 % of the true error where tight).
  real(wp), parameter :: LINEAR_SAFETY = 1.5_wp
  !> Richardson: |y_h - y_2h| / 15 estimates the error of y_h; doubled for safety.
  real(wp), parameter :: RK4_SAFETY = 2.0_wp
  !> RK4 runs longer than this many steps are left to CVODE when it is built.
  !> Measured (benchmarks/bench_tradeoff.py): an RK4 step costs ~0.02-0.1 us
  !> and CVODE Adams is 10-20x slower than RK4 at equal sup error on
  !> non-stiff scenes, 1000-period runs included; so RK4 runs until its
  !> rounding floor bites (see choose_model) or the run is very long.  Stiff
  !> runs (gamma > 20 w0) switch at 1e4 RK4 steps, since BDF needs only a few
  !> hundred steps whatever gamma.
  real(wp), parameter :: RK4_STEP_LIMIT = 2.0e8_wp
  !> Default work budget of one solve, in RK4 steps (about a minute of CPU);
  !> a CVODE step counts as CVODE_STEP_COST of them.  Work predicted beyond
  !> it is refused before it starts (the caller may raise it: max_steps).
  real(wp), parameter :: RK4_STEP_CAP = 2.0e9_wp
  real(wp), parameter :: CVODE_STEP_COST = 20
  !> Fewest CVODE (Adams) steps per small-angle period of an underdamped
  !> scene, decayed or not (measured ~7 at tol 1e-10 over 1e5 s): the lower
  !> bound of the up-front CVODE cost prediction.
  real(wp), parameter :: CVODE_MIN_STEPS_PER_PERIOD = 4
  !> A posteriori refinements before giving up on meeting tol.
  integer, parameter :: MAX_REFINE = 4

  !> A scene; build it with scene_init (which checks every field).
  type :: scene_t
    real(wp) :: theta0 = 0        !< initial angle [rad] at t = 0
    real(wp) :: omega0 = 0        !< initial angular velocity [rad/s] at t = 0
    real(wp) :: w0 = 1            !< natural frequency sqrt(g/l) [1/s]
    real(wp) :: gamma = 0         !< damping rate b/m [1/s]
    real(wp) :: tol = 1.0e-6_wp   !< absolute tolerance on theta [rad] (Omega/w0 too)
    integer :: want = SCENE_WANT_STATE
    integer :: model = SCENE_MODEL_AUTO   !< forced model, or AUTO
    real(wp), allocatable :: t(:) !< output times [s], >= 0, strictly increasing
  end type scene_t

  !> What an answer cost.
  type :: scene_cost_t
    integer(i8) :: closed_form_evals = 0  !< points at which a closed form was evaluated
    integer(i8) :: rhs_evals = 0          !< right-hand-side evaluations (integrators)
    integer(i8) :: steps = 0              !< integrator steps
    integer :: runs = 0                   !< integrator runs, verification included
    real(wp) :: wall_time = 0             !< seconds spent in scene_solve
  end type scene_cost_t

  !> The answer: which model, why, its error estimate, the asked quantities.
  type :: scene_result_t
    integer :: model = SCENE_MODEL_AUTO
    character(len=PENDULA_MSG_LEN) :: reason = ''
    !> Estimated sup over the window of max(|d theta| [rad], |d Omega|/w0).
    real(wp) :: error_estimate = 0
    !> error_estimate <= tol.
    logical :: tol_met = .false.
    !> RK4 step h [s] or CVODE rtol of the returned run; 0 for closed forms.
    real(wp) :: setting = 0
    integer :: want = SCENE_WANT_STATE
    !> Output times and the state there (want = state, theta, final, energy).
    real(wp), allocatable :: t(:), theta(:), omega(:)
    !> Energy per unit m l^2 [1/s^2] at t (want = energy).
    real(wp), allocatable :: energy(:)
    !> Period or time per revolution [s] (want = period); +inf on the separatrix.
    real(wp) :: period = 0
    !> Events (want = events): times [s], kinds (PENDULA_EVENT_*), state there.
    real(wp), allocatable :: event_t(:), event_theta(:), event_omega(:)
    integer, allocatable :: event_kind(:)
    !> Estimated error of the event times [s].
    real(wp) :: event_time_error = 0
    type(scene_cost_t) :: cost
  end type scene_result_t

  ! A closed form ready to evaluate (private).
  type :: closed_t
    integer :: model = SCENE_MODEL_EXACT
    type(undamped_motion_t) :: motion
    type(linear_damped_t) :: lin
    real(wp) :: w0 = 1, gamma = 0
  end type closed_t

contains

  ! ------------------------------------------------------------------ names

  !> 'auto', 'small_angle', 'exact', 'linear', 'rk4', 'cvode' ('unknown' otherwise).
  pure function scene_model_name(code) result(name)
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    select case (code)
    case (SCENE_MODEL_AUTO); name = 'auto'
    case (SCENE_MODEL_SMALL_ANGLE); name = 'small_angle'
    case (SCENE_MODEL_EXACT); name = 'exact'
    case (SCENE_MODEL_LINEAR); name = 'linear'
    case (SCENE_MODEL_RK4); name = 'rk4'
    case (SCENE_MODEL_CVODE); name = 'cvode'
    case default; name = 'unknown'
    end select
  end function scene_model_name

  !> Model code of a name (as scene_model_name; 'linear_damped' is accepted
  !> for 'linear'); -1 for an unknown name.
  pure integer function scene_model_code(name) result(code)
    character(len=*), intent(in) :: name
    select case (trim(adjustl(name)))
    case ('auto'); code = SCENE_MODEL_AUTO
    case ('small_angle'); code = SCENE_MODEL_SMALL_ANGLE
    case ('exact'); code = SCENE_MODEL_EXACT
    case ('linear', 'linear_damped'); code = SCENE_MODEL_LINEAR
    case ('rk4'); code = SCENE_MODEL_RK4
    case ('cvode'); code = SCENE_MODEL_CVODE
    case default; code = -1
    end select
  end function scene_model_code

  !> 'state', 'theta', 'final', 'energy', 'period', 'events' ('unknown' otherwise).
  pure function scene_want_name(code) result(name)
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    select case (code)
    case (SCENE_WANT_STATE); name = 'state'
    case (SCENE_WANT_THETA); name = 'theta'
    case (SCENE_WANT_FINAL); name = 'final'
    case (SCENE_WANT_ENERGY); name = 'energy'
    case (SCENE_WANT_PERIOD); name = 'period'
    case (SCENE_WANT_EVENTS); name = 'events'
    case default; name = 'unknown'
    end select
  end function scene_want_name

  !> Want code of a name (as scene_want_name); -1 for an unknown name.
  pure integer function scene_want_code(name) result(code)
    character(len=*), intent(in) :: name
    integer :: i
    code = -1
    do i = SCENE_WANT_STATE, SCENE_WANT_EVENTS
      if (trim(adjustl(name)) == scene_want_name(i)) code = i
    end do
  end function scene_want_code

  ! ------------------------------------------------------------ construction

  !> The text's parameters to (w0, gamma): w0 = sqrt(g/l) (eq. 1.7) with g,
  !> length > 0 [m/s^2, m]; the damping either as gamma [1/s] >= 0 directly, or
  !> as mass [kg] > 0 and b [kg/s] >= 0 (gamma = b/m, eq. 2.1), or both when
  !> they agree to 1e-12 relative; none gives gamma = 0.  Errors name the
  !> argument: b without mass, mass without b, gamma and b/mass disagreeing.
  pure subroutine scene_physics(g, length, w0, gamma, status, gamma_in, mass, b)
    real(wp), intent(in) :: g, length
    real(wp), intent(out) :: w0, gamma
    type(status_t), intent(out) :: status
    real(wp), intent(in), optional :: gamma_in, mass, b
    real(wp) :: gb
    type(status_t) :: st
    w0 = 0
    gamma = 0
    call natural_frequency(g, length, w0, status)
    if (status%code /= PENDULA_OK) return
    if (present(gamma_in)) then
      call check_nonnegative('gamma', gamma_in, status)
      if (status%code /= PENDULA_OK) return
      gamma = gamma_in
    end if
    if (present(mass) .neqv. present(b)) then
      if (present(mass)) then
        call set_error(status, PENDULA_ERR_DOMAIN, 'mass is given without b: give both mass and b ' // &
            '(gamma = b/mass, eq. 2.1), or gamma alone')
      else
        call set_error(status, PENDULA_ERR_DOMAIN, 'b is given without mass: give both mass and b ' // &
            '(gamma = b/mass, eq. 2.1), or gamma alone')
      end if
      return
    end if
    if (present(mass)) then
      call damping_rate(b, mass, gb, st)
      if (st%code /= PENDULA_OK) then
        status = st
        return
      end if
      if (present(gamma_in)) then
        if (abs(gb - gamma_in) > 1.0e-12_wp * max(gb, gamma_in)) then
          call set_error(status, PENDULA_ERR_DOMAIN, 'gamma = ' // format_sci(gamma_in, 4) // &
              ' and b/mass = ' // format_sci(gb, 4) // ' disagree: give gamma, or mass and b, not both')
          return
        end if
      end if
      gamma = gb
    end if
  end subroutine scene_physics

  !> Build a scene.  theta0 [rad], omega0 [rad/s] finite (state at t = 0);
  !> t(:) [s] output times, finite, >= 0, strictly increasing, at least one
  !> (may be empty only for want = SCENE_WANT_PERIOD); w0 > 0, gamma >= 0
  !> [1/s]; tol > 0 [rad]; want one of SCENE_WANT_*; model (optional) one of
  !> SCENE_MODEL_* (default AUTO).  On bad input status names the argument.
  pure subroutine scene_init(scene, theta0, omega0, t, w0, gamma, tol, want, status, model)
    type(scene_t), intent(out) :: scene
    real(wp), intent(in) :: theta0, omega0, t(:), w0, gamma, tol
    integer, intent(in) :: want
    type(status_t), intent(out) :: status
    integer, intent(in), optional :: model
    integer :: mdl
    mdl = SCENE_MODEL_AUTO
    if (present(model)) mdl = model
    call check_finite('theta0', theta0, status)
    call check_finite('omega0', omega0, status)
    call check_positive('w0', w0, status)
    call check_nonnegative('gamma', gamma, status)
    call check_positive('tol', tol, status)
    if (status%code /= PENDULA_OK) return
    if (want < SCENE_WANT_STATE .or. want > SCENE_WANT_EVENTS) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'want = ' // format_int(want) // ' is unknown: it must be ' // &
          'one of state (1), theta (2), final (3), energy (4), period (5), events (6)')
      return
    end if
    if (mdl < SCENE_MODEL_AUTO .or. mdl > SCENE_MODEL_CVODE) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'model = ' // format_int(mdl) // ' is unknown: it must be ' // &
          'one of auto (0), small_angle (1), exact (2), linear (3), rk4 (4), cvode (5)')
      return
    end if
    if (want /= SCENE_WANT_PERIOD) call check_size('t', size(t), 1, status)
    call check_increasing('t', t, status)
    if (status%code /= PENDULA_OK) return
    if (size(t) > 0) then
      if (t(1) < 0) then
        call set_error(status, PENDULA_ERR_DOMAIN, 't[0] = ' // format_sci(t(1), 4) // &
            ' is out of range: output times must be >= 0 (the initial state holds at t = 0)')
        return
      end if
    end if
    if (want == SCENE_WANT_PERIOD .and. gamma > 0) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'want = period needs gamma = 0 (gamma = ' // format_sci(gamma, 4) // &
          ': the damped motion is not periodic); use want = events for its turning points')
      return
    end if
    if (gamma > 0 .and. (mdl == SCENE_MODEL_SMALL_ANGLE .or. mdl == SCENE_MODEL_EXACT)) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'model = ' // scene_model_name(mdl) // &
          ' needs gamma = 0 (gamma = ' // format_sci(gamma, 4) // '): use linear, rk4 or cvode')
      return
    end if
    scene%theta0 = theta0
    scene%omega0 = omega0
    scene%w0 = w0
    scene%gamma = gamma
    scene%tol = tol
    scene%want = want
    scene%model = mdl
    scene%t = t
  end subroutine scene_init

  ! ------------------------------------------------------------------ solve

  !> Answer the scene with the cheapest model whose error estimate is <= tol
  !> (or with scene%model when forced).  result%model, %reason,
  !> %error_estimate, %tol_met and %cost say which, why, how good and how
  !> expensive.  When no model meets tol (e.g. tol below the rounding floor of
  !> the exact solution) the most accurate one is used, tol_met is false and
  !> the reason says so.  Errors: an invalid scene (use scene_init), CVODE
  !> forced but not built (PENDULA_ERR_UNAVAILABLE), integrator failures.
  !> max_steps (optional, default 2e9): the work budget in RK4 steps (a CVODE
  !> step counts as 20); a solve predicted to need more is refused up front
  !> (PENDULA_ERR_MAXSTEPS, naming the window, tol and max_steps).  control
  !> (optional, see pendula_control): cancel flag polled throughout the
  !> integrations (PENDULA_ERR_CANCELLED), progress in steps / evaluations.
  subroutine scene_solve(scene, result, status, control, max_steps)
    type(scene_t), intent(in) :: scene
    type(scene_result_t), intent(out) :: result
    type(status_t), intent(out) :: status
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    integer(i8), intent(in), optional :: max_steps
    integer(i8) :: c0, c1, rate
    integer :: model
    real(wp) :: est, tend, budget
    character(len=:), allocatable :: why
    call system_clock(c0, rate)
    call check_scene(scene, status)
    call get_budget(budget, status, max_steps)
    if (status%code /= PENDULA_OK) return
    tend = window_end(scene)
    model = scene%model
    if (model == SCENE_MODEL_AUTO) then
      call choose_model(scene, tend, model, est, why, status)
    else
      call scene_estimate(scene, model, est, status)
      why = 'forced by the caller'
      if (model == SCENE_MODEL_CVODE .and. .not. cvode_available()) call set_error(status, &
          PENDULA_ERR_UNAVAILABLE, 'model = cvode is not available: this build has no SUNDIALS CVODE')
    end if
    if (status%code /= PENDULA_OK) return
    select case (model)
    case (SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR)
      call solve_closed(scene, model, est, result, status)
    case (SCENE_MODEL_RK4)
      call solve_rk4(scene, tend, budget, result, status, control)
    case (SCENE_MODEL_CVODE)
      call solve_cvode(scene, tend, budget, result, status, control)
    end select
    if (status%code /= PENDULA_OK) return
    result%model = model
    result%want = scene%want
    result%tol_met = result%error_estimate <= scene%tol
    if (.not. result%tol_met) then
      why = why // '; tol NOT met: error estimate ' // format_sci(result%error_estimate, 4) // ' > tol'
    end if
    result%reason = why
    call system_clock(c1)
    result%cost%wall_time = real(c1 - c0, wp) / real(max(rate, 1_i8), wp)
  end subroutine scene_solve

  !> Run one model at a fixed setting, with no verification and no choice:
  !> setting is the RK4 step h [s] or the CVODE rtol (atol = rtol/100 * the
  !> state scale; Adams, BDF when stiff); ignored for closed forms.  Meant for
  !> work-precision studies (pendula.tradeoff).  result%error_estimate is the a
  !> priori estimate for closed forms and 0 (unknown) for the integrators.
  !> control and max_steps: as for scene_solve (an RK4 run needing more than
  !> max_steps steps is refused up front; CVODE stops after max_steps/20).
  subroutine scene_run_model(scene, model, setting, result, status, control, max_steps)
    type(scene_t), intent(in) :: scene
    integer, intent(in) :: model
    real(wp), intent(in) :: setting
    type(scene_result_t), intent(out) :: result
    type(status_t), intent(out) :: status
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    integer(i8), intent(in), optional :: max_steps
    integer(i8) :: c0, c1, rate
    real(wp) :: est, tend, budget
    type(ode_stats_t) :: stats
    call system_clock(c0, rate)
    call check_scene(scene, status)
    call get_budget(budget, status, max_steps)
    if (model < SCENE_MODEL_SMALL_ANGLE .or. model > SCENE_MODEL_CVODE) call set_error(status, &
        PENDULA_ERR_DOMAIN, 'model = ' // format_int(model) // ' is unknown: it must be small_angle (1), ' // &
        'exact (2), linear (3), rk4 (4) or cvode (5)')
    if (status%code /= PENDULA_OK) return
    if (scene%gamma > 0 .and. (model == SCENE_MODEL_SMALL_ANGLE .or. model == SCENE_MODEL_EXACT)) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'model = ' // scene_model_name(model) // &
          ' needs gamma = 0')
      return
    end if
    tend = window_end(scene)
    select case (model)
    case (SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR)
      call scene_estimate(scene, model, est, status)
      if (status%code /= PENDULA_OK) return
      call solve_closed(scene, model, est, result, status)
    case (SCENE_MODEL_RK4, SCENE_MODEL_CVODE)
      call check_positive('setting', setting, status)
      if (status%code /= PENDULA_OK) return
      if (model == SCENE_MODEL_RK4 .and. tend / setting > budget) then
        call set_error(status, PENDULA_ERR_DOMAIN, 'setting = ' // format_sci(setting, 4) // ' is too small: ' // &
            'the RK4 step h would need more than max_steps = ' // format_sci(budget, 4) // ' steps over t = 0 .. ' // &
            format_sci(tend, 4) // ' (raise max_steps to allow it)')
        return
      end if
      call alloc_outputs(scene, result)
      call integrate(scene, model, setting, budget, result%t, result%theta, result%omega, stats, status, &
          control)
      if (status%code /= PENDULA_OK) return
      call add_stats(result%cost, stats)
      result%setting = setting
      result%error_estimate = 0
      call finish_outputs(scene, result)
    end select
    if (status%code /= PENDULA_OK) return
    result%model = model
    result%want = scene%want
    result%reason = 'forced by the caller at a fixed setting (no verification)'
    call system_clock(c1)
    result%cost%wall_time = real(c1 - c0, wp) / real(max(rate, 1_i8), wp)
  end subroutine scene_run_model

  !> A priori error estimate [rad] of a closed-form model over the scene's
  !> window (sup of max(|d theta|, |d Omega|/w0)): the small-angle bound, the
  !> linear model's nonlinearity estimate, or the exact solution's rounding
  !> estimate.  For rk4 and cvode the value is scene%tol: their settings are
  !> chosen from it and verified a posteriori by scene_solve.  +inf where the
  !> model does not apply (small angle over the top, closed forms with the
  !> wrong gamma).
  pure subroutine scene_estimate(scene, model, estimate, status)
    type(scene_t), intent(in) :: scene
    integer, intent(in) :: model
    real(wp), intent(out) :: estimate
    type(status_t), intent(out) :: status
    type(undamped_motion_t) :: motion
    real(wp) :: tend, dth, dom
    estimate = ieee_value(1.0_wp, ieee_positive_inf)
    call check_scene(scene, status)
    if (status%code /= PENDULA_OK) return
    tend = window_end(scene)
    select case (model)
    case (SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT)
      if (scene%gamma > 0) return
      call undamped_init(motion, scene%theta0, scene%omega0, scene%w0, status)
      if (status%code /= PENDULA_OK) return
      if (model == SCENE_MODEL_SMALL_ANGLE) then
        call small_angle_bound(motion, tend, dth, dom)
        estimate = max(dth, dom / scene%w0)
        if (scene%want == SCENE_WANT_PERIOD) estimate = period_small_angle_error(motion)
      else
        estimate = exact_estimate(motion, tend)
        if (scene%want == SCENE_WANT_PERIOD) estimate = 8 * eps * (1 + abs(log(max(abs(motion%mc), &
            tiny(1.0_wp)))))
      end if
    case (SCENE_MODEL_LINEAR)
      estimate = linear_estimate(scene%theta0, scene%omega0, scene%w0, scene%gamma, tend)
    case (SCENE_MODEL_RK4, SCENE_MODEL_CVODE)
      estimate = scene%tol
    case default
      call set_error(status, PENDULA_ERR_DOMAIN, 'model = ' // format_int(model) // ' is unknown')
    end select
  end subroutine scene_estimate

  ! ------------------------------------------------------------- internals

  ! The work budget [RK4 steps] from the optional max_steps (>= 1).
  pure subroutine get_budget(budget, status, max_steps)
    real(wp), intent(out) :: budget
    type(status_t), intent(inout) :: status
    integer(i8), intent(in), optional :: max_steps
    budget = RK4_STEP_CAP
    if (.not. present(max_steps)) return
    budget = real(max_steps, wp)
    if (max_steps < 1) call set_error(status, PENDULA_ERR_DOMAIN, 'max_steps = ' // format_sci(budget, 4) // &
        ' is out of range: it must be >= 1')
  end subroutine get_budget

  pure subroutine check_scene(scene, status)
    type(scene_t), intent(in) :: scene
    type(status_t), intent(inout) :: status
    type(scene_t) :: copy
    if (.not. allocated(scene%t)) then
      call set_error(status, PENDULA_ERR_SIZE, 'the scene has no output times: build it with scene_init')
      return
    end if
    call scene_init(copy, scene%theta0, scene%omega0, scene%t, scene%w0, scene%gamma, scene%tol, &
        scene%want, status, scene%model)
  end subroutine check_scene

  pure real(wp) function window_end(scene) result(tend)
    type(scene_t), intent(in) :: scene
    tend = 0
    if (size(scene%t) > 0) tend = scene%t(size(scene%t))
  end function window_end

  ! The choice: cheapest model whose estimate meets tol.
  subroutine choose_model(scene, tend, model, est, why, status)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tend
    integer, intent(out) :: model
    real(wp), intent(out) :: est
    character(len=:), allocatable, intent(out) :: why
    type(status_t), intent(inout) :: status
    real(wp) :: e_sa, e_ex, e_lin, hmax, nsteps, rk4_round, big, msep
    type(status_t) :: st
    if (scene%gamma == 0) then
      call scene_estimate(scene, SCENE_MODEL_SMALL_ANGLE, e_sa, status)
      call scene_estimate(scene, SCENE_MODEL_EXACT, e_ex, status)
      if (status%code /= PENDULA_OK) return
      if (scene%want == SCENE_WANT_PERIOD .or. scene%want == SCENE_WANT_ENERGY) then
        ! K (or the energy) comes with the motion's set-up: nothing cheaper exists.
        model = SCENE_MODEL_EXACT
        est = e_ex
        why = 'gamma = 0 and want = ' // scene_want_name(scene%want) // &
            ': the exact value costs one set-up (K once), no time series'
      else if (e_sa <= scene%tol) then
        model = SCENE_MODEL_SMALL_ANGLE
        est = e_sa
        why = 'gamma = 0 and the small-angle bound over the window, ' // format_sci(e_sa, 4) // &
            ' rad, is <= tol'
      else
        model = SCENE_MODEL_EXACT
        est = e_ex
        why = 'gamma = 0 and the small-angle bound ' // format_sci(e_sa, 4) // ' rad exceeds tol: exact ' // &
            'elliptic solution'
      end if
      return
    end if
    e_lin = linear_estimate(scene%theta0, scene%omega0, scene%w0, scene%gamma, tend)
    if (e_lin <= scene%tol) then
      model = SCENE_MODEL_LINEAR
      est = e_lin
      why = 'gamma > 0 and the nonlinearity estimate of the linear closed form over the window, ' // &
          format_sci(e_lin, 4) // ' rad, is <= tol'
      return
    end if
    est = scene%tol
    model = SCENE_MODEL_RK4
    call rk4_max_stable_step(scene%w0, scene%gamma, hmax, st)
    nsteps = tend / min(0.9_wp * hmax, rk4_apriori_step(scene, tend))
    ! RK4's rounding floor grows like sqrt(steps) times max|theta| (unwrapped
    ! rotations): when it would eat tol, CVODE's fewer, longer steps do better
    ! (the angle grows without bound only while the pendulum goes over the top:
    ! at most max|Omega| = sqrt(Omega0^2 + 4 w0^2) times the window, or the
    ! time damping needs to bring the energy E0 = m E_sep below the separatrix)
    big = abs(scene%theta0) + 2 * pi
    msep = sin(scene%theta0 / 2)**2 + (scene%omega0 / (2 * scene%w0))**2
    if (msep >= 1) big = big + hypot(scene%omega0, 2 * scene%w0) * &
        min(tend, 2 * (1 + log(msep)) / scene%gamma)
    rk4_round = integrator_rounding(scene, [big], nsteps)
    if (cvode_available() .and. (nsteps > RK4_STEP_LIMIT .or. rk4_round > scene%tol / 4 .or. &
        (is_stiff(scene) .and. nsteps > 1.0e4_wp))) then
      model = SCENE_MODEL_CVODE
      why = 'gamma > 0, the linear model is off by ~' // format_sci(e_lin, 4) // ' rad; RK4 would need ~' // &
          format_sci(nsteps, 4) // ' steps (rounding ~' // format_sci(rk4_round, 4) // ' rad), so CVODE (' // &
          trim(merge('BDF  ', 'Adams', is_stiff(scene))) // &
          ') with tolerances from tol and the window, verified by a run 10x tighter'
    else
      why = 'gamma > 0, the linear model is off by ~' // format_sci(e_lin, 4) // ' rad: RK4 with h from ' // &
          'tol and the window (C h^4 T), verified by a run at 2h'
    end if
  end subroutine choose_model

  pure logical function is_stiff(scene)
    type(scene_t), intent(in) :: scene
    is_stiff = scene%gamma > 20 * scene%w0
  end function is_stiff

  ! Error of the small-angle period T0 = 2 pi/w0 as a phase w0 |T - T0| [rad].
  pure real(wp) function period_small_angle_error(motion) result(e)
    type(undamped_motion_t), intent(in) :: motion
    if (motion%regime /= REGIME_LIBRATION) then
      e = ieee_value(1.0_wp, ieee_positive_inf)
    else
      e = abs(motion%w0 * motion%period - 2 * pi)
    end if
  end function period_small_angle_error

  ! Rounding estimate of the exact elliptic solution over [0, tend] at the
  ! given (exact double) inputs: the phase w0 t is rounded (theta moves by
  ! ~eps Omega_max t), and the energy parameter carries an error delta_m that
  ! shifts the frequency by t |d ln T/d m| delta_m (T ~ ln(16/mc) near the
  ! separatrix); theta moves by the phase error times max|Omega|/w.
  pure real(wp) function exact_estimate(motion, tend) result(e)
    type(undamped_motion_t), intent(in) :: motion
    real(wp), intent(in) :: tend
    real(wp) :: omax, dm, mc, dlnt, h
    if (motion%m == 0) then
      e = 0
      return
    end if
    omax = 2 * sqrt(motion%m) * motion%w0          ! max |Omega| (libration and rotation)
    mc = motion%mc
    ! pendula_undamped forms 1 - m as (c - q)(c + q) with c, q carried to ~2
    ! doubles, so mc is known to a few eps RELATIVE to itself: near the
    ! separatrix the energy error is that small, not eps * m
    dm = 4 * eps * abs(mc) + eps**2 * (1 + abs(motion%center))
    if (motion%regime == REGIME_SEPARATRIX .or. mc == 0) then
      dlnt = 1 / max(abs(mc), dm)
    else
      h = 1.0e-4_wp * abs(mc)
      dlnt = abs(log(turn_time(mc + h) / turn_time(mc - h))) / (2 * h)
    end if
    e = 4 * eps * (abs(motion%theta0) + 2 * pi + omax / motion%w0) &
        + 4 * omax * tend * (eps + min(dlnt * dm, 1.0_wp))
    e = min(e, 2 * (omax / motion%w0 + 2 * pi))
  contains
    pure real(wp) function turn_time(c)
      real(wp), intent(in) :: c
      if (c > 0) then
        turn_time = 4 * ellipkm1(c)
      else
        turn_time = 2 * ellipkm1(-c / (1 - c)) / sqrt(1 - c)
      end if
    end function turn_time
  end function exact_estimate

  !> Nonlinearity error of the linear model theta'' + gamma theta' + w0^2 theta
  !> = 0 against eq. 2.2 over [0, tend], as sup max(|d theta|, |d Omega|/w0).
  !> Two estimates, the smaller is used (times LINEAR_SAFETY), plus rounding:
  !>  (a) underdamped, phase drift: an oscillation of amplitude A is slower by
  !>      dw = w0^2 A^2/(16 w_d) (the pendulum's A^2/16 shift, eq. 1.53 expanded);
  !>      with A(t) = A0 e^(-gamma t/2) the phase lag is
  !>      phi(t) = w0^2 A0^2 (1 - e^(-gamma t))/(16 w_d gamma), so the error is
  !>      about A(t) min(2, phi(t)) (1 + gamma/(2 w0)) plus the harmonics A^3/16;
  !>  (b) any regime, Green's function: the error d solves the linear equation
  !>      forced by w0^2 (theta - sin theta) <= w0^2 |theta|^3/6, so
  !>      |d| <= w0^2 B^3/6 int_0^tend |G|, B = max |theta_lin|, and the same with
  !>      |G'|/w0 for Omega; G(s) = e^(-gamma s/2) sin(w_d s)/w_d (sinh, s).
  pure real(wp) function linear_estimate(theta0, omega0, w0, gamma, tend) result(e)
    real(wp), intent(in) :: theta0, omega0, w0, gamma, tend
    integer, parameter :: n = 400
    type(linear_damped_t) :: lin, gl
    type(status_t) :: st
    real(wp) :: tt(0:n), th(0:n), om(0:n), bmax, ig, igp, eg, ep, wd, a0, a, amp, phi, scale, &
        round, t0, gt, gpt, gmax, jmin
    integer :: i
    call linear_damped_init(lin, theta0, omega0, w0, gamma, st)
    if (st%code /= PENDULA_OK) then
      e = ieee_value(1.0_wp, ieee_positive_inf)
      return
    end if
    scale = abs(theta0) + abs(omega0) / w0
    if (tend <= 0 .or. scale == 0) then
      e = 0
      return
    end if
    a = gamma / 2
    call linear_damped_init(gl, 0.0_wp, 1.0_wp, w0, gamma, st)   ! G: theta0 = 0, Omega0 = 1
    call linear_damped_state(gl, tend, gt, gpt)
    if (lin%info%regime == DAMPING_UNDERDAMPED) then
      wd = lin%info%omega_d
      bmax = lin%amplitude                      ! |theta| <= R e^(-gamma t/2) <= R
      ! |G(s)| <= e^(-a s) min(s, 1/w_d), |G'(s)| <= e^(-a s) (1 + a min(s, 1/w_d))
      jmin = min(int_exp_s(a, tend), int_exp(a, tend) / wd)
      ig = jmin
      igp = int_exp(a, tend) + a * jmin
      ! (a) phase drift, sampled on a uniform grid (A(t) phi(t) is smooth)
      a0 = lin%amplitude
      ep = 0
      do i = 0, n
        tt(i) = tend * (real(i, wp) / n)
        amp = a0 * exp(-a * tt(i))
        if (gamma > 0) then
          phi = w0**2 * a0**2 * (-expm1(-gamma * tt(i))) / (16 * wd * gamma)
        else
          phi = w0**2 * a0**2 * tt(i) / (16 * wd)
        end if
        ep = max(ep, amp * min(2.0_wp, phi) * max(1.0_wp, (wd + a) / w0) + amp**3 / 16)
      end do
    else
      ! over-damped or critical: theta has at most one hump; sample it on a
      ! geometric grid that resolves the fast time scale 1/|lambda1|
      t0 = min(tend, 1.0e-3_wp / max(w0, gamma))
      tt(0) = 0
      do i = 1, n
        tt(i) = t0 * (tend / t0)**(real(i - 1, wp) / (n - 1))
      end do
      call linear_damped_state(lin, tt, th, om)
      bmax = maxval(abs(th)) * (1 + 1.0e-2_wp)
      ! G >= 0: int G = (1 - G'(T) - gamma G(T))/w0^2 from the equation itself;
      ! G' changes sign once (at the hump of G), so int |G'| <= 2 max G.
      ig = max(0.0_wp, (1 - gpt - gamma * gt) / w0**2)
      call linear_damped_state(gl, tt, th, om)
      gmax = maxval(th) * (1 + 1.0e-2_wp)
      igp = 2 * gmax
      ep = ieee_value(1.0_wp, ieee_positive_inf)
    end if
    ! (b) Green's function bound, any regime
    eg = w0**2 * bmax**3 / 6 * max(ig, igp / w0)
    round = 16 * eps * scale * (1 + (w0 + gamma) * tend)
    e = LINEAR_SAFETY * min(eg, ep) + round
  contains
    ! int_0^T e^(-a s) ds and int_0^T s e^(-a s) ds, without cancellation
    pure real(wp) function int_exp(a, t) result(r)
      real(wp), intent(in) :: a, t
      if (a * t < 1.0e-8_wp) then
        r = t
      else
        r = -expm1(-a * t) / a
      end if
    end function int_exp
    pure real(wp) function int_exp_s(a, t) result(r)
      real(wp), intent(in) :: a, t
      real(wp) :: x
      x = a * t
      if (x < 1.0e-3_wp) then
        r = t**2 * (0.5_wp - x / 3 + x**2 / 8)
      else
        r = (-expm1(-x) - x * exp(-x)) / a**2
      end if
    end function int_exp_s
  end function linear_estimate

  ! A priori RK4 step for the window: global error ~ C A (w0 h)^4 w0 T_eff
  ! with C = 1/120 for the harmonic oscillator (the phase error of one step is
  ! (w0 h)^5/120), doubled for the nonlinear pendulum.  With damping the error
  ! stops growing once the motion has decayed below tol, so T_eff is the
  ! window or the time the slowest mode needs to decay from A to tol.  The
  ! a posteriori check (run at 2h) catches what this misjudges.
  pure real(wp) function rk4_apriori_step(scene, tend) result(h)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tend
    real(wp) :: a, teff, c, slow, half
    a = max(abs(scene%theta0) + abs(scene%omega0) / scene%w0, 1.0e-3_wp)
    a = min(a, 2 * pi)
    teff = tend
    if (scene%gamma > 0) then
      half = scene%gamma / 2
      if (half > scene%w0) then
        slow = scene%w0**2 / (half + sqrt(half - scene%w0) * sqrt(half + scene%w0))
      else
        slow = half
      end if
      teff = min(tend, (1 + log(max(exp(1.0_wp), a / scene%tol))) / slow)
    end if
    c = 2.0_wp / 120
    h = (scene%tol / (c * a * max(scene%w0 * teff, 1.0_wp)))**0.25_wp / scene%w0
    h = min(h, 0.5_wp / scene%w0)
  end function rk4_apriori_step

  ! ------------------------------------------------------ closed-form path

  pure subroutine closed_init(scene, model, cf, status)
    type(scene_t), intent(in) :: scene
    integer, intent(in) :: model
    type(closed_t), intent(out) :: cf
    type(status_t), intent(inout) :: status
    cf%model = model
    cf%w0 = scene%w0
    cf%gamma = scene%gamma
    if (model == SCENE_MODEL_LINEAR) then
      call linear_damped_init(cf%lin, scene%theta0, scene%omega0, scene%w0, scene%gamma, status)
    else
      call undamped_init(cf%motion, scene%theta0, scene%omega0, scene%w0, status)
    end if
  end subroutine closed_init

  elemental subroutine closed_eval(cf, t, theta, omega)
    type(closed_t), intent(in) :: cf
    real(wp), intent(in) :: t
    real(wp), intent(out) :: theta, omega
    select case (cf%model)
    case (SCENE_MODEL_SMALL_ANGLE)
      call small_angle_eval(cf%motion, t, theta, omega)
    case (SCENE_MODEL_LINEAR)
      call linear_damped_state(cf%lin, t, theta, omega)
    case default
      call undamped_eval(cf%motion, t, theta, omega)
    end select
  end subroutine closed_eval

  subroutine solve_closed(scene, model, est, result, status)
    type(scene_t), intent(in) :: scene
    integer, intent(in) :: model
    real(wp), intent(in) :: est
    type(scene_result_t), intent(inout) :: result
    type(status_t), intent(inout) :: status
    type(closed_t) :: cf
    call closed_init(scene, model, cf, status)
    if (status%code /= PENDULA_OK) return
    result%error_estimate = est
    select case (scene%want)
    case (SCENE_WANT_PERIOD)
      if (model == SCENE_MODEL_SMALL_ANGLE) then
        result%period = 2 * pi / scene%w0
      else
        result%period = cf%motion%period
      end if
      allocate (result%t(0), result%theta(0), result%omega(0))
    case (SCENE_WANT_ENERGY)
      call alloc_outputs(scene, result)
      if (model == SCENE_MODEL_EXACT) then
        ! conserved: the energy of the initial state, no time series
        result%theta = 0
        result%omega = 0
        result%energy = pendulum_energy(scene%theta0, scene%omega0, scene%w0)
        result%error_estimate = max(est, 4 * eps * result%energy(1) / scene%w0**2)
        result%cost%closed_form_evals = 1
        deallocate (result%theta, result%omega)
        allocate (result%theta(0), result%omega(0))
        return
      end if
      call closed_eval(cf, result%t, result%theta, result%omega)
      result%cost%closed_form_evals = size(result%t)
      call finish_outputs(scene, result)
    case (SCENE_WANT_EVENTS)
      call closed_events(cf, window_end(scene), result)
      allocate (result%t(0), result%theta(0), result%omega(0))
      result%event_time_error = event_time_error(result, est, scene%w0)
    case default
      call alloc_outputs(scene, result)
      call closed_eval(cf, result%t, result%theta, result%omega)
      result%cost%closed_form_evals = size(result%t)
      call finish_outputs(scene, result)
    end select
  end subroutine solve_closed

  ! Output arrays for the want: every t, or only t(n) for want = final.
  pure subroutine alloc_outputs(scene, result)
    type(scene_t), intent(in) :: scene
    type(scene_result_t), intent(inout) :: result
    integer :: n
    n = size(scene%t)
    if (scene%want == SCENE_WANT_FINAL) then
      result%t = scene%t(n:n)
    else if (scene%want == SCENE_WANT_PERIOD .or. scene%want == SCENE_WANT_EVENTS) then
      allocate (result%t(0))
    else
      result%t = scene%t
    end if
    allocate (result%theta(size(result%t)), result%omega(size(result%t)))
    if (scene%want == SCENE_WANT_ENERGY) allocate (result%energy(size(result%t)))
  end subroutine alloc_outputs

  ! Energies from the state; theta-only scenes drop Omega.
  pure subroutine finish_outputs(scene, result)
    type(scene_t), intent(in) :: scene
    type(scene_result_t), intent(inout) :: result
    if (scene%want == SCENE_WANT_ENERGY) &
        result%energy = pendulum_energy(result%theta, result%omega, scene%w0)
    if (.not. allocated(result%event_t)) then
      allocate (result%event_t(0), result%event_theta(0), result%event_omega(0), result%event_kind(0))
    end if
  end subroutine finish_outputs

  ! Event times from a closed form: scan (0, tend] at 16 samples per period
  ! (geometric steps for motions that do not oscillate), then refine each sign
  ! change of theta (zero crossing) or Omega (turning point) by the Illinois
  ! variant of regula falsi to a few ulps of t.
  subroutine closed_events(cf, tend, result)
    type(closed_t), intent(in) :: cf
    real(wp), intent(in) :: tend
    type(scene_result_t), intent(inout) :: result
    real(wp) :: step, growth, stepmax, ta, tb, tha, oma, thb, omb, te(2), per
    integer :: kinds(2), ne, nev
    integer(i8) :: nevals
    allocate (result%event_t(0), result%event_theta(0), result%event_omega(0), result%event_kind(0))
    per = ieee_value(1.0_wp, ieee_positive_inf)
    select case (cf%model)
    case (SCENE_MODEL_SMALL_ANGLE)
      per = 2 * pi / cf%w0
    case (SCENE_MODEL_EXACT)
      if (cf%motion%regime /= REGIME_SEPARATRIX) per = cf%motion%period
    case (SCENE_MODEL_LINEAR)
      if (cf%lin%info%regime == DAMPING_UNDERDAMPED) per = cf%lin%info%damped_period
    end select
    if (ieee_is_finite(per)) then
      step = per / 16
      growth = 1
      stepmax = step
    else
      ! no oscillation: at most one root of each; resolve the fast time scale first
      step = 1 / (8 * max(cf%w0, cf%gamma))
      growth = 1.05_wp
      stepmax = max(tend / 64, step)
    end if
    nevals = 1
    ta = 0
    call closed_eval(cf, ta, tha, oma)
    nev = 0
    do while (ta < tend)
      tb = min(tend, ta + step)
      call closed_eval(cf, tb, thb, omb)
      nevals = nevals + 1
      ne = 0
      if (tha * thb < 0 .or. (thb == 0 .and. tha /= 0)) then
        ne = ne + 1
        kinds(ne) = PENDULA_EVENT_ZERO
        te(ne) = refine(1, ta, tb, tha, thb)
      end if
      if (oma * omb < 0 .or. (omb == 0 .and. oma /= 0)) then
        ne = ne + 1
        kinds(ne) = PENDULA_EVENT_TURNING
        te(ne) = refine(2, ta, tb, oma, omb)
      end if
      if (ne == 2) then
        if (te(2) < te(1)) then
          te = te([2, 1])
          kinds = kinds([2, 1])
        end if
      end if
      if (ne > 0) call append_events(result, te(1:ne), kinds(1:ne), nev)
      ta = tb
      tha = thb
      oma = omb
      step = min(stepmax, step * growth)
    end do
    call trim_events(result, nev)
    call closed_eval(cf, result%event_t, result%event_theta, result%event_omega)
    result%cost%closed_form_evals = nevals + size(result%event_t)
  contains
    real(wp) function refine(which, a0, b0, fa0, fb0) result(r)
      integer, intent(in) :: which
      real(wp), intent(in) :: a0, b0, fa0, fb0
      real(wp) :: a, b, fa, fb, c, fc, th, om
      integer :: it, side
      a = a0; b = b0; fa = fa0; fb = fb0
      r = b
      if (fb == 0) return
      side = 0
      do it = 1, 200
        c = (a * fb - b * fa) / (fb - fa)
        if (.not. (c > a .and. c < b)) c = 0.5_wp * (a + b)
        call closed_eval(cf, c, th, om)
        nevals = nevals + 1
        fc = merge(th, om, which == 1)
        if (fc == 0) then
          r = c
          return
        end if
        if (sign(1.0_wp, fc) == sign(1.0_wp, fa)) then
          a = c; fa = fc
          if (side == -1) fb = fb / 2
          side = -1
        else
          b = c; fb = fc
          if (side == 1) fa = fa / 2
          side = 1
        end if
        if (b - a <= 4 * eps * max(abs(b), tiny(1.0_wp))) exit
      end do
      r = merge(a, b, abs(fa) < abs(fb))
    end function refine
  end subroutine closed_events

  pure subroutine append_events(result, te, kinds, nev)
    type(scene_result_t), intent(inout) :: result
    real(wp), intent(in) :: te(:)
    integer, intent(in) :: kinds(:)
    integer, intent(inout) :: nev
    real(wp), allocatable :: tmp(:)
    integer, allocatable :: itmp(:)
    integer :: cap
    if (nev + size(te) > size(result%event_t)) then
      cap = max(16, 2 * (nev + size(te)))
      allocate (tmp(cap), itmp(cap))
      tmp(1:nev) = result%event_t(1:nev)
      itmp(1:nev) = result%event_kind(1:nev)
      call move_alloc(tmp, result%event_t)
      call move_alloc(itmp, result%event_kind)
    end if
    result%event_t(nev+1:nev+size(te)) = te
    result%event_kind(nev+1:nev+size(te)) = kinds
    nev = nev + size(te)
  end subroutine append_events

  pure subroutine trim_events(result, nev)
    type(scene_result_t), intent(inout) :: result
    integer, intent(in) :: nev
    result%event_t = result%event_t(1:nev)
    result%event_kind = result%event_kind(1:nev)
    if (allocated(result%event_theta)) deallocate (result%event_theta)
    if (allocated(result%event_omega)) deallocate (result%event_omega)
    allocate (result%event_theta(nev), result%event_omega(nev))
  end subroutine trim_events

  ! Event time error from the state error: dt = d theta/|Omega| at a zero
  ! crossing, d Omega/|Omega'| = w0 d/(w0^2 |sin theta| + gamma |Omega|) at a turning point.
  pure real(wp) function event_time_error(result, est, w0) result(e)
    type(scene_result_t), intent(in) :: result
    real(wp), intent(in) :: est, w0
    integer :: i
    real(wp) :: rate
    e = 0
    do i = 1, size(result%event_t)
      if (result%event_kind(i) == PENDULA_EVENT_ZERO) then
        rate = abs(result%event_omega(i))
      else
        rate = w0 * abs(sin(result%event_theta(i)))
      end if
      e = max(e, est / max(rate, tiny(1.0_wp)))
    end do
  end function event_time_error

  ! ------------------------------------------------------ integrator path

  pure subroutine add_stats(cost, stats)
    type(scene_cost_t), intent(inout) :: cost
    type(ode_stats_t), intent(in) :: stats
    cost%rhs_evals = cost%rhs_evals + stats%rhs_evals
    cost%steps = cost%steps + stats%steps
    cost%runs = cost%runs + 1
  end subroutine add_stats

  ! One integrator run over the scene's window, output at tout (the times of
  ! the result, which may be only t(n)).  The integrators start at tout(1),
  ! so 0 is prepended when the first output time is later.  setting: h (RK4)
  ! or rtol (CVODE; atol = rtol * scale / 100 with scale the state's size).
  ! budget: RK4 steps allowed (CVODE: budget / CVODE_STEP_COST steps).
  subroutine integrate(scene, model, setting, budget, tout, theta, omega, stats, status, control)
    type(scene_t), intent(in) :: scene
    integer, intent(in) :: model
    real(wp), intent(in) :: setting, budget, tout(:)
    real(wp), intent(out) :: theta(:), omega(:)
    type(ode_stats_t), intent(out) :: stats
    type(status_t), intent(inout) :: status
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    real(wp), allocatable :: tt(:), th(:), om(:)
    integer :: off, n, method
    real(wp) :: scale
    n = size(tout)
    if (scene%want == SCENE_WANT_FINAL .and. model == SCENE_MODEL_RK4) then
      call rk4_final_state(0.0_wp, tout(n), scene%theta0, scene%omega0, scene%w0, scene%gamma, &
          setting, theta(n), omega(n), stats, status, control, int(min(budget, 9.0e18_wp), i8))
      return
    end if
    off = 0
    if (tout(1) > 0) off = 1
    allocate (tt(n + off), th(n + off), om(n + off))
    tt(1) = 0
    tt(1+off:) = tout
    if (model == SCENE_MODEL_RK4) then
      call rk4_solve(tt, scene%theta0, scene%omega0, scene%w0, scene%gamma, setting, th, om, stats, status, &
          control, int(min(budget, 9.0e18_wp), i8))
    else
      method = merge(PENDULA_CVODE_BDF, PENDULA_CVODE_ADAMS, is_stiff(scene))
      scale = max(abs(scene%theta0) + abs(scene%omega0) / scene%w0, 1.0e-6_wp)
      call cvode_solve(tt, scene%theta0, scene%omega0, scene%w0, scene%gamma, setting, &
          setting * scale / 100, method, max(int(budget / CVODE_STEP_COST, i8), 1_i8), th, om, stats, status, &
          control)
    end if
    theta = th(1+off:)
    omega = om(1+off:)
  end subroutine integrate

  ! sup over the outputs of max(|d theta|, |d Omega|/w0)
  pure real(wp) function state_diff(th1, om1, th2, om2, w0) result(d)
    real(wp), intent(in) :: th1(:), om1(:), th2(:), om2(:), w0
    d = 0
    if (size(th1) > 0) d = max(maxval(abs(th1 - th2)), maxval(abs(om1 - om2)) / w0)
  end function state_diff

  ! Rounding floor of an integration that the comparison of two runs cannot
  ! see: each of n steps rounds theta by ~eps |theta|, a random walk ~ sqrt(n)
  ! while it swings, a biased sum ~ n for the unwrapped angle of a rotation
  ! (max|theta| beyond 2 pi); and a start near the unstable
  ! equilibrium (pi, 0) amplifies any perturbation by ~1/d0 while the
  ! pendulum hangs there (growth e^(w0 t) until it leaves, t ~ ln(1/d0)/w0),
  ! d0 the distance of the initial state from the top in (theta, Omega/w0).
  pure real(wp) function integrator_rounding(scene, theta, nsteps) result(r)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: theta(:), nsteps
    real(wp) :: big, d0, xr, swing
    swing = abs(scene%theta0) + abs(scene%omega0) / scene%w0 + 2 * pi   ! size of a swing
    big = swing
    if (size(theta) > 0) big = max(big, maxval(abs(theta)))
    xr = abs(modulo(scene%theta0 + pi, 2 * pi) - pi)          ! |theta0| reduced to [0, pi]
    d0 = hypot(pi - xr, scene%omega0 / scene%w0)
    ! a rotation's unwrapped angle (beyond a swing) grows steadily: adding nearly
    ! equal increments to it rounds with a bias, so that part grows like n
    r = 4 * eps * swing * sqrt(max(nsteps, 1.0_wp)) &
        + eps * (big - swing) * max(nsteps, 1.0_wp) / 2 + 4 * eps * pi / max(d0, eps)
  end function integrator_rounding

  ! RK4 with h from tol and the window, verified by a run at 2h; refined
  ! from the observed error (which scales like h^4) until it meets tol.
  subroutine solve_rk4(scene, tend, budget, result, status, control)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tend, budget
    type(scene_result_t), intent(inout) :: result
    type(status_t), intent(inout) :: status
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    real(wp) :: h, hmax, est, d, round
    real(wp), allocatable :: th2(:), om2(:), tgrid(:)
    type(status_t) :: st
    integer :: it
    logical :: ev
    ev = scene%want == SCENE_WANT_EVENTS
    call rk4_max_stable_step(scene%w0, scene%gamma, hmax, st)
    hmax = 0.9_wp * hmax
    h = min(rk4_apriori_step(scene, tend), hmax / 2)
    if (ev) then
      ! events: sample on a grid of 32 points per small-angle period, refine by Hermite cubic
      call event_grid(scene, tend, tgrid)
    else
      call alloc_outputs(scene, result)
      tgrid = result%t
    end if
    allocate (th2(size(tgrid)), om2(size(tgrid)))
    if (.not. allocated(result%theta)) allocate (result%theta(size(tgrid)), result%omega(size(tgrid)))
    if (size(result%theta) /= size(tgrid)) then
      deallocate (result%theta, result%omega)
      allocate (result%theta(size(tgrid)), result%omega(size(tgrid)))
    end if
    est = ieee_value(1.0_wp, ieee_positive_inf)
    do it = 1, MAX_REFINE
      ! the run at h and its check at 2h: 1.5 tend/h steps
      if (1.5_wp * tend / h > budget) then
        call set_error(status, PENDULA_ERR_MAXSTEPS, 'rk4 needs ~' // format_sci(1.5_wp * tend / h, 4) // &
            ' steps for tol = ' // format_sci(scene%tol, 4) // ' over t = 0 .. ' // format_sci(tend, 4) // &
            ', over max_steps = ' // format_sci(budget, 4) // ' (2e9 ~ 1 min): use cvode, a larger tol,' // &
            ' a shorter window, or raise max_steps')
        return
      end if
      call rk4_run(scene, tgrid, h, 1, result%theta, result%omega, result%cost, status, control)
      if (status%code /= PENDULA_OK) return
      call rk4_run(scene, tgrid, h, 2, th2, om2, result%cost, status, control)
      if (status%code /= PENDULA_OK) return
      d = state_diff(result%theta, result%omega, th2, om2, scene%w0)
      round = integrator_rounding(scene, result%theta, tend / h)
      est = RK4_SAFETY * d / 15 + round
      if (est <= scene%tol) exit
      if (it == MAX_REFINE .or. round > 0.5_wp * est) exit   ! a smaller h only adds rounding
      ! e ~ C h^4: step for tol/4, at least halved, at most /16
      h = h * max(1.0_wp / 16, min(0.5_wp, 0.8_wp * (scene%tol / (4 * est))**0.25_wp))
    end do
    result%setting = h
    result%error_estimate = est
    if (ev) then
      call grid_events(scene, tgrid, result%theta, result%omega, result)
      deallocate (result%theta, result%omega)
      allocate (result%t(0), result%theta(0), result%omega(0))
      result%event_time_error = event_time_error(result, est, scene%w0)
    else
      call finish_outputs(scene, result)
    end if
  end subroutine solve_rk4

  ! RK4 from t = 0 through the outputs tg(:) with, on every interval dt_i
  ! between consecutive times (0 first), n_i = 2 ceil(dt_i/(2 h)) equal
  ! substeps (factor = 1) or exactly half as many (factor = 2).  Both runs
  ! thus halve the step on EVERY interval, so that their difference / 15 is
  ! the Richardson estimate of the fine run's error even when the outputs are
  ! denser than h.  A uniform grid goes to rk4_solve in one call (the step
  ! dt/n makes it take exactly n substeps); otherwise one rk4_final_state
  ! call per interval.  Final-state scenes integrate one interval.
  subroutine rk4_run(scene, tg, h, factor, th, om, cost, status, control)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tg(:), h
    integer, intent(in) :: factor
    real(wp), intent(out) :: th(:), om(:)
    type(scene_cost_t), intent(inout) :: cost
    type(status_t), intent(inout) :: status
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    real(wp), allocatable :: tt(:), th1(:), om1(:)
    real(wp) :: dt, x, v, t0, x1, v1
    real(wp) :: nsub
    type(ode_stats_t) :: stats
    integer :: i, off, n
    logical :: uniform
    n = size(tg)
    off = merge(1, 0, tg(1) > 0)
    allocate (tt(n + off))
    tt(1) = 0
    tt(1+off:) = tg
    uniform = .true.
    dt = tt(min(2, size(tt))) - tt(1)
    do i = 2, size(tt)
      if (abs((tt(i) - tt(i-1)) - dt) > 1.0e-12_wp * dt) uniform = .false.
    end do
    if (size(tt) >= 2 .and. uniform) then
      nsub = substeps(dt)
      allocate (th1(size(tt)), om1(size(tt)))
      call rk4_solve(tt, scene%theta0, scene%omega0, scene%w0, scene%gamma, dt / nsub, th1, om1, &
          stats, status, control, huge(1_i8))
      call add_stats(cost, stats)
      th = th1(1+off:)
      om = om1(1+off:)
      return
    end if
    x = scene%theta0
    v = scene%omega0
    t0 = 0
    do i = 1, n
      ! each short run polls only every 4096 steps of its own: look between runs too
      if (present(control)) then
        if (cancel_requested(control)) then
          call set_error(status, PENDULA_ERR_CANCELLED, 'RK4 cancelled at t = ' // format_sci(t0, 4) // &
              ' (interrupted by the caller)')
          return
        end if
      end if
      if (tg(i) > t0) then
        dt = tg(i) - t0
        call rk4_final_state(t0, tg(i), x, v, scene%w0, scene%gamma, dt / substeps(dt), x1, v1, &
            stats, status, control, huge(1_i8))
        x = x1
        v = v1
        call add_stats(cost, stats)
        cost%runs = cost%runs - 1
        if (status%code /= PENDULA_OK) return
      end if
      th(i) = x
      om(i) = v
      t0 = tg(i)
    end do
    cost%runs = cost%runs + 1
  contains
    pure real(wp) function substeps(d) result(ns)
      real(wp), intent(in) :: d
      ns = 2 * ceiling(d / (2 * h), i8)
      ns = ns / factor
    end function substeps
  end subroutine rk4_run

  ! CVODE with rtol from tol and the number of periods in the window, checked
  ! by a run 10x tighter; the tighter run is returned, and the difference of
  ! the two (an estimate of the looser run's error, which bounds the tighter
  ! one's) is its error estimate.
  subroutine solve_cvode(scene, tend, budget, result, status, control)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tend, budget
    type(scene_result_t), intent(inout) :: result
    type(status_t), intent(inout) :: status
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    real(wp) :: rtol, est, periods, scale, predicted
    real(wp), allocatable :: th1(:), om1(:), tgrid(:)
    type(ode_stats_t) :: stats
    integer :: it
    logical :: ev
    ev = scene%want == SCENE_WANT_EVENTS
    if (ev) then
      call event_grid(scene, tend, tgrid)
    else
      call alloc_outputs(scene, result)
      tgrid = result%t
    end if
    if (allocated(result%theta)) deallocate (result%theta, result%omega)
    allocate (result%theta(size(tgrid)), result%omega(size(tgrid)), th1(size(tgrid)), om1(size(tgrid)))
    periods = 1 + scene%w0 * tend / (2 * pi)
    ! Up front: an underdamped, non-stiff scene costs CVODE (Adams) at least a
    ! few steps per period however loose tol (or decayed the swing), in each of
    ! the two runs.
    if (.not. is_stiff(scene) .and. scene%gamma < 2 * scene%w0) then
      predicted = 2 * CVODE_MIN_STEPS_PER_PERIOD * periods * CVODE_STEP_COST
      if (predicted > budget) then
        call set_error(status, PENDULA_ERR_MAXSTEPS, 'window t = 0 .. ' // format_sci(tend, 4) // ' spans ~' // &
            format_sci(periods, 4) // ' periods: CVODE needs > ~' // format_sci(predicted / CVODE_STEP_COST, 4) // &
            ' steps, over the budget max_steps = ' // format_sci(budget, 4) // ' (RK4 steps, a CVODE step counts' // &
            ' 20; 2e9 ~ 1 min): shorten the window or raise max_steps')
        return
      end if
    end if
    scale = max(abs(scene%theta0) + abs(scene%omega0) / scene%w0, 1.0e-6_wp)
    rtol = max(0.1_wp * scene%tol / (periods * scale), 1.0e-14_wp)
    est = ieee_value(1.0_wp, ieee_positive_inf)
    do it = 1, MAX_REFINE
      call integrate(scene, SCENE_MODEL_CVODE, rtol, budget, tgrid, th1, om1, stats, status, control)
      call add_stats(result%cost, stats)
      if (status%code /= PENDULA_OK) return
      call integrate(scene, SCENE_MODEL_CVODE, rtol / 10, budget, tgrid, result%theta, result%omega, stats, &
          status, control)
      call add_stats(result%cost, stats)
      if (status%code /= PENDULA_OK) return
      est = state_diff(th1, om1, result%theta, result%omega, scene%w0) &
          + integrator_rounding(scene, result%theta, real(stats%steps, wp))
      if (est <= scene%tol .or. rtol <= 1.0e-14_wp .or. it == MAX_REFINE) exit
      rtol = max(rtol * max(1.0e-3_wp, 0.3_wp * scene%tol / est), 1.0e-14_wp)
    end do
    result%setting = rtol / 10
    result%error_estimate = est
    if (ev) then
      call grid_events(scene, tgrid, result%theta, result%omega, result)
      deallocate (result%theta, result%omega)
      allocate (result%t(0), result%theta(0), result%omega(0))
      result%event_time_error = event_time_error(result, est, scene%w0)
    else
      call finish_outputs(scene, result)
    end if
  end subroutine solve_cvode

  ! Sample grid for events found from an integrated trajectory: spacing d
  ! with (w0 d)^4/384 * A <= tol/10, so that the cubic Hermite interpolant
  ! used to place the events (error d^4/384 max|theta''''|, and
  ! |theta''''| ~ w0^4 A for the swinging pendulum) is ten times more
  ! accurate than tol; at least 64 samples per small-angle period, and the
  ! fast time scale 1/gamma resolved when over-damped (capped at 4e6 samples).
  pure subroutine event_grid(scene, tend, tg)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tend
    real(wp), allocatable, intent(out) :: tg(:)
    integer :: n, i
    real(wp) :: a, d, per
    a = max(abs(scene%theta0) + abs(scene%omega0) / scene%w0, 1.0e-3_wp)
    d = (384 * scene%tol / (10 * a))**0.25_wp / scene%w0
    per = max(64.0_wp, 2 * pi / (scene%w0 * d))
    n = int(min(4.0e6_wp, max(64.0_wp, per * scene%w0 * tend / (2 * pi) + 1)))
    if (scene%gamma > scene%w0) n = max(n, min(4000000, ceiling(8 * scene%gamma * tend) + 1))
    allocate (tg(n + 1))
    do i = 0, n
      tg(i+1) = tend * (real(i, wp) / n)
    end do
  end subroutine event_grid

  ! Events from samples of an integrated trajectory: a sign change of theta
  ! or Omega between samples is refined on the cubic Hermite interpolant,
  ! built from (theta, Omega) and (Omega, Omega') at both ends, whose error
  ! (h^4/384 max|theta''''|) is below tol/10 on the grid of event_grid.
  pure subroutine grid_events(scene, tg, th, om, result)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tg(:), th(:), om(:)
    type(scene_result_t), intent(inout) :: result
    integer :: i, nev, ne, kinds(2)
    real(wp) :: te(2), h, da, db
    if (allocated(result%event_t)) deallocate (result%event_t, result%event_kind)
    allocate (result%event_t(0), result%event_kind(0))
    nev = 0
    do i = 1, size(tg) - 1
      h = tg(i+1) - tg(i)
      ne = 0
      if (th(i) * th(i+1) < 0 .or. (th(i+1) == 0 .and. th(i) /= 0)) then
        ne = ne + 1
        kinds(ne) = PENDULA_EVENT_ZERO
        te(ne) = tg(i) + h * hermite_root(th(i), th(i+1), h * om(i), h * om(i+1))
      end if
      if (om(i) * om(i+1) < 0 .or. (om(i+1) == 0 .and. om(i) /= 0)) then
        da = h * accel(th(i), om(i))
        db = h * accel(th(i+1), om(i+1))
        ne = ne + 1
        kinds(ne) = PENDULA_EVENT_TURNING
        te(ne) = tg(i) + h * hermite_root(om(i), om(i+1), da, db)
      end if
      if (ne == 2) then
        if (te(2) < te(1)) then
          te = te([2, 1])
          kinds = kinds([2, 1])
        end if
      end if
      if (ne > 0) call append_events(result, te(1:ne), kinds(1:ne), nev)
    end do
    call trim_events(result, nev)
    do i = 1, nev
      call hermite_state(result%event_t(i), result%event_theta(i), result%event_omega(i))
    end do
  contains
    pure real(wp) function accel(x, v)
      real(wp), intent(in) :: x, v
      accel = -scene%gamma * v - scene%w0**2 * sin(x)
    end function accel
    pure subroutine hermite_state(tq, x, v)
      real(wp), intent(in) :: tq
      real(wp), intent(out) :: x, v
      integer :: j
      real(wp) :: s, hh
      j = max(1, min(size(tg) - 1, count(tg <= tq)))
      hh = tg(j+1) - tg(j)
      s = (tq - tg(j)) / hh
      x = hermite(th(j), th(j+1), hh * om(j), hh * om(j+1), s)
      v = hermite(om(j), om(j+1), hh * accel(th(j), om(j)), hh * accel(th(j+1), om(j+1)), s)
    end subroutine hermite_state
  end subroutine grid_events

  pure real(wp) function hermite(f0, f1, d0, d1, s) result(f)
    real(wp), intent(in) :: f0, f1, d0, d1, s
    f = (2 * s**3 - 3 * s**2 + 1) * f0 + (s**3 - 2 * s**2 + s) * d0 + (-2 * s**3 + 3 * s**2) * f1 &
        + (s**3 - s**2) * d1
  end function hermite

  ! Root in (0, 1] of the cubic Hermite interpolant (f0, f1 of opposite
  ! signs, or f1 = 0) by safeguarded bisection/regula falsi.
  pure real(wp) function hermite_root(f0, f1, d0, d1) result(s)
    real(wp), intent(in) :: f0, f1, d0, d1
    real(wp) :: a, b, fa, fb, c, fc
    integer :: it
    s = 1
    if (f1 == 0) return
    a = 0; b = 1; fa = f0; fb = f1
    do it = 1, 100
      c = 0.5_wp * (a + b)
      fc = hermite(f0, f1, d0, d1, c)
      if (fc == 0) exit
      if (sign(1.0_wp, fc) == sign(1.0_wp, fa)) then
        a = c; fa = fc
      else
        b = c; fb = fc
      end if
      if (b - a < 4 * eps) exit
    end do
    s = c
  end function hermite_root

  ! e^x - 1 without cancellation for small |x| (accurate to ~1e-11 relative,
  ! ample for error estimates).
  elemental real(wp) function expm1(x) result(r)
    real(wp), intent(in) :: x
    if (abs(x) < 1.0e-5_wp) then
      r = x * (1 + x * (0.5_wp + x / 6))
    else
      r = exp(x) - 1
    end if
  end function expm1

end module pendula_scene
