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
!>    (conservative) error estimate;
!>  * taylor: the Taylor series (pendula_taylor), order and step from tol,
!>    one run whose own error estimate at every output is the answer's; it
!>    reaches ~1e-15 where RK4 and CVODE stop at their rounding floors, and
!>    is cheaper than both on long windows and at tight tolerances
!>    (integrator_pick weighs the predicted work).
!> Only what the scene asks for is computed: SCENE_WANT_PERIOD evaluates K once
!> (no time series), SCENE_WANT_FINAL keeps no history (RK4 final-state mode),
!> SCENE_WANT_ENERGY with gamma = 0 is the constant energy of the initial state.
!>
!> The concern's files: pendula_scene_codes (codes, names, limits),
!> pendula_scene_types (scene_t and its result), pendula_scene_setup
!> (construction and rules), pendula_scene_estimates (model choice and error
!> models), pendula_scene_closed (closed forms and their events),
!> pendula_scene_integrated (RK4/CVODE runs and their verification),
!> pendula_scene_events (event bound, Hermite events), pendula_scene_handover
!> (an integrator only until a damped motion has decayed, then the linear
!> closed form, also for events), pendula_scene_top (a damped start at the
!> top: the hang in top-centred coordinates), pendula_scene_work (the
!> predicted work of a call, from closed formulas), pendula_scene_driven (a
!> scene with a drive: the linearised driven oscillator in closed form or the
!> driven RK4 kernel); this module is the public face and the two entry
!> points that run a scene.
!>
!> A drive (scene_init's optional drive, pendula_drive) of nonzero amplitude
!> makes the models linear (the linearised driven damped oscillator, torque
!> drive only, with the nonlinearity bound of the undriven linear model) and
!> rk4 (the driven RK4 kernel, Richardson-checked); small_angle, exact,
!> cvode and taylor do not apply, and want = period or events is refused.
!> A drive of amplitude 0 leaves every answer exactly the undriven one.
module pendula_scene
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_sci, format_int
  use pendula_status, only: status_t, set_error, check_positive, PENDULA_OK, PENDULA_ERR_DOMAIN, &
                            PENDULA_ERR_SOLVER, PENDULA_ERR_CANCELLED
  use pendula_integrators, only: PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO
  use pendula_control, only: CONTROL_SIZE
  use pendula_scene_codes, only: scene_model_name, scene_model_code, scene_want_name, scene_want_code, &
                               scene_model_list, SCENE_MODEL_AUTO, SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR, &
                                 SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_MODEL_TAYLOR, SCENE_WANT_STATE, SCENE_WANT_THETA, &
                                 SCENE_WANT_FINAL, &
                                 SCENE_WANT_ENERGY, SCENE_WANT_PERIOD, SCENE_WANT_EVENTS, SCENE_CVODE_STEP_COST
  use pendula_scene_types, only: scene_t, scene_result_t, scene_cost_t, window_end, add_stats, swing, has_drive
  use pendula_scene_setup, only: scene_physics, scene_init, check_scene, check_model_gamma, check_model_built, &
                                 get_budget, alloc_outputs, finish_outputs
  use pendula_scene_estimates, only: undriven_estimate => scene_estimate, model_estimate, choose_model, &
                                     integrator_rounding
  use pendula_scene_driven, only: driven_model_estimate, driven_scene_solve, driven_scene_run
  use pendula_scene_closed, only: solve_closed
  use pendula_scene_integrated, only: solve_rk4, solve_cvode, solve_taylor, run_fixed, integrate
  use pendula_scene_handover, only: solve_integrated, add_cost
  use pendula_scene_events, only: scene_event_bound
  use pendula_scene_top, only: top_start, solve_top
  implicit none
  private

  public :: scene_t, scene_result_t, scene_cost_t
  public :: scene_init, scene_physics, scene_solve, scene_run_model, scene_estimate, scene_event_bound
  public :: scene_model_name, scene_model_code, scene_want_name, scene_want_code
  public :: SCENE_MODEL_AUTO, SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR, &
            SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_MODEL_TAYLOR
  public :: SCENE_WANT_STATE, SCENE_WANT_THETA, SCENE_WANT_FINAL, SCENE_WANT_ENERGY, &
            SCENE_WANT_PERIOD, SCENE_WANT_EVENTS
  public :: PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO

contains

  !> Answer the scene with the cheapest model whose error estimate is <= tol
  !> (or with scene%model when forced).  result%model, %reason,
  !> %error_estimate, %tol_met and %cost say which, why, how good and how
  !> expensive.  When no model meets tol (e.g. tol below the rounding floor of
  !> the exact solution) the most accurate one is used, tol_met is false and
  !> the reason says so.  Errors: an invalid scene (use scene_init), CVODE
  !> forced but not built (PENDULA_ERR_UNAVAILABLE), integrator failures.
  !> max_steps (optional, default SCENE_STEP_CAP of pendula_scene_codes): the
  !> work budget in RK4 steps (a CVODE step counts as SCENE_CVODE_STEP_COST); a solve predicted to need more is refused up front
  !> (PENDULA_ERR_MAXSTEPS, naming the window, tol and max_steps).  control
  !> (optional, see pendula_control): cancel flag polled throughout the
  !> integrations (PENDULA_ERR_CANCELLED), progress in steps / evaluations.
  subroutine scene_solve(scene, result, status, control, max_steps)
    type(scene_t), intent(in) :: scene  !< the scene (build it with scene_init; checked again here)
    type(scene_result_t), intent(out) :: result  !< the answer: model, reason, estimate, wanted quantities, cost
    type(status_t), intent(out) :: status  !< PENDULA_OK, or the error code and a message naming the argument
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag, progress (pendula_control)
    integer(i8), intent(in), optional :: max_steps  !< work budget [RK4 steps], >= 1; default SCENE_STEP_CAP
    integer(i8) :: c0, c1, rate
    integer :: model, used_model
    real(wp) :: est, tend, budget, k, phi0, v0
    logical :: is_top, done
    character(len=:), allocatable :: why
    call system_clock(c0, rate)
    call check_scene(scene, status)
    call get_budget(budget, status, max_steps)
    if (status%code /= PENDULA_OK) return
    if (has_drive(scene)) then
      call driven_scene_solve(scene, budget, result, status, control)
      result%want = scene%want
      call system_clock(c1)
      result%cost%wall_time = real(c1 - c0, wp)/real(max(rate, 1_i8), wp)
      return
    end if
    tend = window_end(scene)
    model = scene%model
    if (model == SCENE_MODEL_AUTO) then
      call choose_model(scene, tend, model, est, why, status)
    else
      call model_estimate(scene, model, est, status)
      why = 'forced by the caller'
      call check_model_built(model, status)
    end if
    if (status%code /= PENDULA_OK) return
    select case (model)
    case (SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR)
      call solve_closed(scene, model, est, result, status)
      if (scene%model == SCENE_MODEL_AUTO) call exact_after_small_angle(scene, model, why, result, status)
    case (SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_MODEL_TAYLOR)
      call top_start(scene, is_top, k, phi0, v0)
      done = .false.
      ! the hang at the top in top-centred coordinates (pendula_scene_top)
      if (scene%model == SCENE_MODEL_AUTO .and. is_top) call solve_top(scene, tend, budget, why, result, done, &
                                                                       status, control)
      if (done) then
        model = SCENE_MODEL_RK4
      else if (status%code == PENDULA_OK) then
        ! the model that made the answer (a hand-over's part picks its own)
        call solve_integrated(scene, model, tend, budget, why, result, status, control, used_model)
        model = used_model
        call fold_event_time(scene, result)
        if (scene%model == SCENE_MODEL_AUTO) call second_try(scene, tend, budget, model, why, result, status, &
                                                             control)
      end if
    end select
    call check_event_count(scene, tend, result, status)
    if (status%code /= PENDULA_OK) return
    result%model = model
    result%want = scene%want
    call fold_event_time(scene, result)
    result%tol_met = result%error_estimate <= scene%tol
    if (.not. result%tol_met) then
      ! first, so that a long reason cut to a message's length keeps it
      if (model == SCENE_MODEL_TAYLOR) why = 'the floor reached is '//format_sci(result%error_estimate/ &
                                     max(swing(scene), tiny(1.0_wp)), 3)//' of the motion''s size '//format_sci(swing(scene), 3)// &
                                             ' rad (rounding and the problem''s conditioning); '//why
      why = 'tol NOT met, error estimate '//format_sci(result%error_estimate, 4)//' > tol: '//why
    end if
    result%reason = why
    call system_clock(c1)
    result%cost%wall_time = real(c1 - c0, wp)/real(max(rate, 1_i8), wp)
  end subroutine scene_solve

  !> Run one model at a fixed setting, with no verification and no choice:
  !> setting is the RK4 step h [s] or the CVODE rtol (atol = rtol/100 * the
  !> state scale; Adams, BDF when stiff); ignored for closed forms and for
  !> taylor, which runs once at the scene's tol (its error estimate is then
  !> the run's own, not 0).  Meant for
  !> work-precision studies (pendula.tradeoff).  result%error_estimate is the a
  !> priori estimate for closed forms and 0 (unknown) for the integrators.
  !> want = events with rk4/cvode: the events of the run sampled on the
  !> event grid (pendula_scene_events); want = period with rk4/cvode is an
  !> error (PENDULA_ERR_DOMAIN: only the exact closed form gives a period).
  !> control and max_steps: as for scene_solve (an RK4 run needing more than
  !> max_steps steps is refused up front; CVODE stops after max_steps/20).
  subroutine scene_run_model(scene, model, setting, result, status, control, max_steps)
    type(scene_t), intent(in) :: scene  !< the scene (build it with scene_init; checked again here)
    integer, intent(in) :: model  !< SCENE_MODEL_SMALL_ANGLE .. SCENE_MODEL_TAYLOR (not AUTO)
    real(wp), intent(in) :: setting  !< RK4 step h [s] or CVODE rtol, > 0; ignored for closed forms and taylor
    type(scene_result_t), intent(out) :: result  !< the run's answer (error_estimate 0 for rk4/cvode: unknown)
    type(status_t), intent(out) :: status  !< PENDULA_OK, or the error code and a message naming the argument
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag, progress (pendula_control)
    integer(i8), intent(in), optional :: max_steps  !< work budget [RK4 steps], >= 1; default SCENE_STEP_CAP
    integer(i8) :: c0, c1, rate
    real(wp) :: est, tend, budget
    call system_clock(c0, rate)
    call check_scene(scene, status)
    call get_budget(budget, status, max_steps)
    if (model < SCENE_MODEL_SMALL_ANGLE .or. model > SCENE_MODEL_TAYLOR) call set_error(status, &
                                            PENDULA_ERR_DOMAIN, 'model = '//format_int(model)//' is unknown: it must be one of '// &
                                                                                        scene_model_list(SCENE_MODEL_SMALL_ANGLE))
    if (status%code /= PENDULA_OK) return
    if (has_drive(scene)) then
      call driven_scene_run(scene, model, setting, budget, result, status, control)
      result%want = scene%want
      call system_clock(c1)
      result%cost%wall_time = real(c1 - c0, wp)/real(max(rate, 1_i8), wp)
      return
    end if
    call check_model_gamma(model, scene%gamma, status)
    call check_model_built(model, status)
    if (status%code /= PENDULA_OK) return
    tend = window_end(scene)
    select case (model)
    case (SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR)
      call model_estimate(scene, model, est, status)
      if (status%code /= PENDULA_OK) return
      call solve_closed(scene, model, est, result, status)
    case (SCENE_MODEL_RK4, SCENE_MODEL_CVODE)
      call check_positive('setting', setting, status)
      if (scene%want == SCENE_WANT_PERIOD) call set_error(status, PENDULA_ERR_DOMAIN, 'want = period with '// &
                                       'model = '//scene_model_name(model)//': a fixed-setting run gives no period; the period '// &
                                                          'comes from the exact closed form (model exact, or solve)')
      if (status%code /= PENDULA_OK) return
      if (model == SCENE_MODEL_RK4 .and. tend/setting > budget) then
        call set_error(status, PENDULA_ERR_DOMAIN, 'setting = '//format_sci(setting, 4)//' is too small: '// &
                       'the RK4 step h would need more than max_steps = '//format_sci(budget, 4)//' steps over t = 0 .. '// &
                       format_sci(tend, 4)//' (raise max_steps to allow it)')
        return
      end if
      call run_fixed(scene, model, setting, budget, result, status, control)
    case (SCENE_MODEL_TAYLOR)
      if (scene%want == SCENE_WANT_PERIOD) call set_error(status, PENDULA_ERR_DOMAIN, 'want = period with '// &
                                  'model = taylor: an integration gives no period; the period comes from the exact closed form '// &
                                                          '(model exact, or solve)')
      if (status%code /= PENDULA_OK) return
      call solve_taylor(scene, tend, budget, result, status, control)
      if (status%code == PENDULA_OK) call fold_event_time(scene, result)
      result%tol_met = result%error_estimate <= scene%tol
    end select
    call check_event_count(scene, tend, result, status)
    if (status%code /= PENDULA_OK) return
    result%model = model
    result%want = scene%want
    result%reason = 'forced by the caller at a fixed setting (no verification)'
    if (model == SCENE_MODEL_TAYLOR) result%reason = 'forced by the caller: the Taylor series at the '// &
                                                     'scene''s tol, with its own error estimate'
    call system_clock(c1)
    result%cost%wall_time = real(c1 - c0, wp)/real(max(rate, 1_i8), wp)
  end subroutine scene_run_model

  !> A priori error estimate [rad] of a model over the scene's window (sup of
  !> max(|d theta|, |d Omega|/w0)): for an undriven scene the small-angle
  !> bound, the linear model's nonlinearity estimate or the exact solution's
  !> rounding estimate (pendula_scene_estimates); for a driven scene the
  !> linearised driven oscillator's nonlinearity bound (pendula_scene_driven).
  !> For the integrators the value is scene%tol: their settings are chosen
  !> from it and verified a posteriori by scene_solve.  +inf where the model
  !> does not apply.
  pure subroutine scene_estimate(scene, model, estimate, status)
    type(scene_t), intent(in) :: scene  !< the scene (checked here)
    integer, intent(in) :: model  !< SCENE_MODEL_SMALL_ANGLE .. SCENE_MODEL_TAYLOR
    real(wp), intent(out) :: estimate  !< a priori error estimate [rad], >= 0; +inf where the model does not apply
    type(status_t), intent(out) :: status  !< PENDULA_OK, or the error code and a message naming the argument
    call undriven_estimate(scene, model, estimate, status)
    if (status%code == PENDULA_OK .and. has_drive(scene)) call driven_model_estimate(scene, model, estimate, status)
  end subroutine scene_estimate

  ! Events: tol bounds the event times [s] too (the state estimate only
  ! places them), so the reported estimate is the larger of the two.
  pure subroutine fold_event_time(scene, result)
    type(scene_t), intent(in) :: scene
    type(scene_result_t), intent(inout) :: result
    if (scene%want == SCENE_WANT_EVENTS) result%error_estimate = max(result%error_estimate, &
                                                                     result%event_time_error)
  end subroutine fold_event_time

  ! The small-angle closed form was chosen from its state bound, but its
  ! answer does not verify tol: for want = events the event times' error is
  ! that bound over the rate at each event (slow turning points magnify it),
  ! which is known only once the events are found.  The exact elliptic
  ! solution (off by rounding only) answers instead when its estimate is the
  ! smaller; the costs of both are counted.
  subroutine exact_after_small_angle(scene, model, why, result, status)
    type(scene_t), intent(in) :: scene
    integer, intent(inout) :: model
    character(len=:), allocatable, intent(inout) :: why
    type(scene_result_t), intent(inout) :: result
    type(status_t), intent(inout) :: status
    type(scene_result_t) :: alt
    type(status_t) :: st
    real(wp) :: est
    if (model /= SCENE_MODEL_SMALL_ANGLE .or. status%code /= PENDULA_OK) return
    call fold_event_time(scene, result)
    if (.not. result%error_estimate > scene%tol) return
    call model_estimate(scene, SCENE_MODEL_EXACT, est, st)
    if (st%code == PENDULA_OK) call solve_closed(scene, SCENE_MODEL_EXACT, est, alt, st)
    if (st%code /= PENDULA_OK) return
    call fold_event_time(scene, alt)
    call add_cost(alt%cost, result%cost)
    if (alt%error_estimate < result%error_estimate) then
      why = why//'; but its answer is off by up to '//format_sci(result%error_estimate, 4)// &
            ' (event times from the bound over the rates) > tol: exact elliptic solution instead'
      result = alt
      model = SCENE_MODEL_EXACT
    else
      result%cost = alt%cost
    end if
  end subroutine exact_after_small_angle

  ! The integrator chosen first did not verify tol (its estimate is over
  ! it): the Taylor series after RK4 or CVODE (it goes on where their
  ! rounding floors stop them) with the budget that is left, and the answer
  ! with the smaller estimate is kept (costs of both).  Not tried after
  ! Taylor itself, nor where the rounding floor that all share (a start near
  ! the top) already exceeds tol; the second integrator failing or refusing
  ! leaves the first answer.
  subroutine second_try(scene, tend, budget, model, why, result, status, control)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tend, budget
    integer, intent(inout) :: model
    character(len=:), allocatable, intent(inout) :: why
    type(scene_result_t), intent(inout) :: result
    type(status_t), intent(inout) :: status
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    type(scene_result_t) :: alt
    type(status_t) :: st
    character(len=:), allocatable :: why2
    integer :: other
    real(wp) :: used, floor(0)
    if (status%code /= PENDULA_OK .or. .not. result%error_estimate > scene%tol) return
    if (model == SCENE_MODEL_TAYLOR .or. integrator_rounding(scene, floor, 1.0_wp) > scene%tol/2) return
    other = SCENE_MODEL_TAYLOR
    used = real(result%cost%steps, wp)*merge(SCENE_CVODE_STEP_COST, 1.0_wp, model == SCENE_MODEL_CVODE)
    if (used >= budget) return
    why2 = ''
    call solve_integrated(scene, other, tend, budget - used, why2, alt, st, control)
    if (st%code == PENDULA_ERR_CANCELLED) status = st
    if (st%code /= PENDULA_OK) return
    call fold_event_time(scene, alt)
    call add_cost(alt%cost, result%cost)
    why = why//'; '//scene_model_name(model)//' did not verify tol (estimate '// &
          format_sci(result%error_estimate, 4)//'): '//scene_model_name(other)//' '// &
          trim(merge('did better ', 'did no good', alt%error_estimate < result%error_estimate))//why2
    if (alt%error_estimate < result%error_estimate) then
      result = alt
      model = other
    else
      result%cost = alt%cost
    end if
  end subroutine second_try

  ! More events than the motion can have (scene_event_bound) means the
  ! sampled trajectory was not resolved: an error, never a silent answer.
  pure subroutine check_event_count(scene, tend, result, status)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tend
    type(scene_result_t), intent(in) :: result
    type(status_t), intent(inout) :: status
    integer(i8) :: nmax
    if (status%code /= PENDULA_OK .or. scene%want /= SCENE_WANT_EVENTS) return
    if (.not. allocated(result%event_t)) return
    nmax = scene_event_bound(scene%w0, tend, scene%theta0, scene%omega0)
    if (size(result%event_t, kind=i8) > nmax) call set_error(status, PENDULA_ERR_SOLVER, 'found '// &
                                                   format_int(size(result%event_t))//' events in t = 0 .. '//format_sci(tend, 4)// &
                                           ', more than the '//format_int(nmax)//' the motion can have (2 floor(w0 t/pi) + 3 + '// &
                                                             'floor(Omega_max t/(2 pi))): '// &
                                                             'the sampled trajectory is not resolved; give a smaller tol')
  end subroutine check_event_count

end module pendula_scene
