!> Predicted work of a scene's solve (scene_solve) or fixed run
!> (scene_run_model), in RK4 steps (a CVODE step counts
!> SCENE_CVODE_STEP_COST of them, as in the work budget), from the scene
!> alone and cheaply: closed formulas only, no sampling and no integration,
!> so that a caller can ask it before every call.  The Python layer runs a
!> call predicted long (> ~50 ms, RK4_LONG_STEPS of pendula/_longcall.py) in
!> a worker thread that Ctrl-C can stop, and a short one inline.
!>
!> The prediction follows the solve: the model the choice would take (a
!> closed form when gamma = 0; an integrator when gamma > 0: the cheaper
!> linear form is left out, its check samples the window, and where it
!> applies the motion is small, so the integrator's predicted part is short
!> anyway), the integrator's span (the window, or the predicted hand-over
!> time of a decaying motion, pendula_scene_handover; before it the hang of
!> a start near the top, pendula_scene_top), RK4's runs at its a priori step
!> or CVODE's lower bound on its steps (where the choice would take CVODE),
!> or the Taylor series' predicted steps (where it would take Taylor),
!> each times a measured factor, the event grid, and the outputs.  Short
!> calls should come out short (over-predicting costs a thread start, ~0.1
!> ms), long ones long (under-predicting delays Ctrl-C until the call ends).
module pendula_scene_work
  use pendula_kinds, only: wp
  use pendula_status, only: status_t, PENDULA_OK
  use pendula_constants, only: pi
  use pendula_scene_codes, only: SCENE_MODEL_AUTO, SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_LINEAR, &
                                 SCENE_MODEL_EXACT, SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_MODEL_TAYLOR, SCENE_WANT_STATE, &
                                 SCENE_WANT_THETA, SCENE_TAYLOR_STEP_COST, &
                                 SCENE_WANT_FINAL, SCENE_WANT_ENERGY, SCENE_WANT_PERIOD, SCENE_WANT_EVENTS, SCENE_CVODE_STEP_COST, &
                                 SCENE_RK4_STEP_LIMIT, SCENE_STIFF_RK4_STEPS
  use pendula_scene_types, only: scene_t, window_end, is_stiff, has_drive
  use pendula_scene_driven, only: driven_work
  use pendula_scene_setup, only: check_scene
  use pendula_scene_estimates, only: rk4_apriori_step, cvode_min_steps, slow_rate, linear_answers, &
                                     integrator_pick, cvode_first_rtol, taylor_steps
  use pendula_scene_events, only: scene_event_bound, event_grid_intervals
  use pendula_scene_top, only: top_hang_work
  use pendula_scene_handover, only: handover_time, loosened_tol, MAX_PART
  implicit none
  private

  public :: scene_solve_work, scene_run_work

  !> Work of one output of a closed form [RK4 steps] (measured: 50-85 ns an
  !> output for small_angle, linear and exact, an RK4 step ~31 ns).
  real(wp), parameter :: CLOSED_OUTPUT_WORK = 2
  !> Work of one output of an integrated solve (stored by each run, compared
  !> with the check run) [RK4 steps] (measured: ~450 ns an output of an RK4
  !> pair with 3 steps an output).
  real(wp), parameter :: SAMPLE_WORK = 10
  !> Work of one point of the event grid of an integrated solve (also
  !> searched for events, Hermite-refined) [RK4 steps] (measured on the
  !> benchmark grid: 0.12-0.87 us a point, 3-8 us where the first integrator
  !> fails its check and the other one runs too).
  real(wp), parameter :: EVENT_SAMPLE_WORK = 40
  !> Work of one event of the exact closed form (its root finding) [RK4
  !> steps] (measured: 0.7-1.5 us an event), counted on scene_event_bound.
  real(wp), parameter :: CLOSED_EVENT_WORK = 20
  !> RK4 runs of a solve, in runs at the a priori step (rk4_apriori_step,
  !> within h w0 <= 1/2 and half the stable step): the first pair (at twice
  !> that step and its check at 4 times) is 0.75 of them, and a pair that
  !> fails its check is refined; measured 0.2-1 of what solve reports on
  !> undecayed windows at 3, more on short decaying ones.
  real(wp), parameter :: RK4_RUNS = 3
  !> CVODE steps of a solve's runs at rtol and rtol/10 over their lower
  !> bounds (cvode_min_steps): measured 3.3-6 times them.
  real(wp), parameter :: CVODE_OVER_BOUND = 3

contains

  !> Predicted work of scene_solve(scene) [RK4 steps], >= 0: the model the
  !> choice would take (or scene%model when forced), over the span it would
  !> integrate, and the outputs.  0 for an invalid scene (scene_solve refuses
  !> it at once).  A prediction to decide how to run the call, not a bound.
  pure real(wp) function scene_solve_work(scene) result(work)
    type(scene_t), intent(in) :: scene  !< the scene (checked here)
    type(status_t) :: st
    real(wp) :: tend, span, tol, gain
    integer :: model
    work = 0
    call check_scene(scene, st)
    if (st%code /= PENDULA_OK) return
    if (has_drive(scene)) then
      work = driven_work(scene, scene%model, .false., 0.0_wp)
      return
    end if
    tend = window_end(scene)
    model = scene%model
    if (model == SCENE_MODEL_AUTO .and. scene%gamma == 0) model = SCENE_MODEL_EXACT
    if (model == SCENE_MODEL_AUTO .and. scene%gamma > 0) then
      if (linear_answers(scene, tend)) model = SCENE_MODEL_LINEAR
    end if
    if (model == SCENE_MODEL_SMALL_ANGLE .or. model == SCENE_MODEL_EXACT .or. model == SCENE_MODEL_LINEAR) then
      work = closed_work(scene, tend)
      return
    end if
    span = tend
    tol = scene%tol
    if (scene%gamma > 0 .and. (scene%want == SCENE_WANT_STATE .or. scene%want == SCENE_WANT_THETA .or. &
                               scene%want == SCENE_WANT_FINAL .or. scene%want == SCENE_WANT_ENERGY)) then
      ! the hand-over to the linear form once decayed (pendula_scene_handover)
      span = handover_time(scene%theta0, scene%omega0, scene%w0, scene%gamma, scene%tol, tend)
      if (span < MAX_PART*tend) then
        tol = scene%tol/2
        ! no output before the hand-over: the state there is needed only to
        ! tol over the gain of the linear propagator to t(n) (about its decay)
        if (scene%want == SCENE_WANT_FINAL .or. .not. scene%t(1) < span) then
          gain = min(sqrt(2.0_wp), exp(-slow_rate(scene%w0, scene%gamma)*(tend - span)))
          tol = loosened_tol(scene, tol, gain)
        end if
      else
        span = tend
      end if
    end if
    ! a start near the top (auto): the hang in top-centred coordinates first
    work = top_hang_work(scene)
    if (model == SCENE_MODEL_AUTO) model = integrator_choice(scene, span, tol)
    work = work + integrator_work(scene, model, span, tol, 0.0_wp) + sampling_work(scene, tend, model)
  end function scene_solve_work

  !> Predicted work of scene_run_model(scene, model, setting) [RK4 steps],
  !> >= 0: the run at setting (RK4 step h [s], or CVODE rtol: its lower
  !> bound on the steps, cvode_min_steps), or the closed form, and the
  !> outputs.  0 for an invalid scene, model or setting (refused at once).
  pure real(wp) function scene_run_work(scene, model, setting) result(work)
    type(scene_t), intent(in) :: scene  !< the scene (checked here)
    integer, intent(in) :: model  !< SCENE_MODEL_SMALL_ANGLE .. SCENE_MODEL_TAYLOR
    real(wp), intent(in) :: setting  !< RK4 step h [s] or CVODE rtol, > 0; ignored for closed forms
    type(status_t) :: st
    real(wp) :: tend
    work = 0
    call check_scene(scene, st)
    if (st%code /= PENDULA_OK) return
    if (has_drive(scene)) then
      work = driven_work(scene, model, .true., setting)
      return
    end if
    tend = window_end(scene)
    select case (model)
    case (SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR)
      work = closed_work(scene, tend)
    case (SCENE_MODEL_RK4, SCENE_MODEL_CVODE)
      if (.not. (setting > 0 .and. setting <= huge(1.0_wp)) .or. scene%want == SCENE_WANT_PERIOD) return
      work = integrator_work(scene, model, tend, scene%tol, setting) + sampling_work(scene, tend, model)
    case (SCENE_MODEL_TAYLOR)
      if (scene%want == SCENE_WANT_PERIOD) return
      work = integrator_work(scene, model, tend, scene%tol, 0.0_wp) + sampling_work(scene, tend, model)
    end select
  end function scene_run_work

  ! A closed form: its outputs, or its events (root finding for each).
  pure real(wp) function closed_work(scene, tend) result(work)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tend
    if (scene%want == SCENE_WANT_EVENTS) then
      work = CLOSED_EVENT_WORK*real(scene_event_bound(scene%w0, tend, scene%theta0, scene%omega0), wp)
    else if (scene%want == SCENE_WANT_PERIOD) then
      work = 0
    else
      work = CLOSED_OUTPUT_WORK*size(scene%t)
    end if
  end function closed_work

  ! Work of the samples of an integrated run: its outputs (one for want =
  ! final), or the points of the event grid (the Taylor series finds its
  ! events on its step polynomials: an output's work per event).
  pure real(wp) function sampling_work(scene, tend, model) result(work)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tend
    integer, intent(in) :: model
    if (scene%want == SCENE_WANT_EVENTS .and. model == SCENE_MODEL_TAYLOR) then
      work = SAMPLE_WORK*real(scene_event_bound(scene%w0, tend, scene%theta0, scene%omega0), wp)
    else if (scene%want == SCENE_WANT_EVENTS) then
      work = EVENT_SAMPLE_WORK*(event_grid_intervals(scene, tend) + 1)
    else if (scene%want == SCENE_WANT_FINAL) then
      work = SAMPLE_WORK
    else
      work = SAMPLE_WORK*size(scene%t)
    end if
  end function sampling_work

  ! The integrator choose_model takes for an integrated span at tol
  ! (integrator_pick), with the prediction's RK4 step.
  pure integer function integrator_choice(scene, span, tol) result(model)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: span, tol
    real(wp) :: rk4_round
    call integrator_pick(scene, span, steps(span, rk4_step(scene, span, tol)), tol, model, rk4_round)
  end function integrator_choice

  ! Steps of the integrator over [0, span] [RK4 steps]: at setting (h or
  ! rtol) when > 0, else as the solve sets it from tol (RK4's runs, CVODE's
  ! two runs at rtol and rtol/10).  Events need RK4 substeps on every
  ! interval of their grid (two at h, one at 2h).  Taylor: its one run
  ! (taylor_steps, each SCENE_TAYLOR_STEP_COST), from tol alone.
  pure real(wp) function integrator_work(scene, model, span, tol, setting) result(work)
    type(scene_t), intent(in) :: scene
    integer, intent(in) :: model
    real(wp), intent(in) :: span, tol, setting
    real(wp) :: rtol, grid
    grid = 0
    if (scene%want == SCENE_WANT_EVENTS .and. model /= SCENE_MODEL_TAYLOR) grid = 2*real(event_grid_intervals(scene, span), wp)
    if (model == SCENE_MODEL_TAYLOR) then
      work = SCENE_TAYLOR_STEP_COST*taylor_steps(scene, span, tol)
    else if (model == SCENE_MODEL_RK4) then
      if (setting > 0) then
        work = max(steps(span, setting), grid)
      else
        work = RK4_RUNS*max(steps(span, rk4_step(scene, span, tol)), grid/2)
      end if
    else
      if (setting > 0) then
        work = cvode_min_steps(scene, span, setting)
      else
        rtol = cvode_first_rtol(scene, span, tol)
        work = CVODE_OVER_BOUND*(cvode_min_steps(scene, span, rtol) + cvode_min_steps(scene, span, rtol/10))
      end if
      work = work*SCENE_CVODE_STEP_COST
    end if
  end function integrator_work

  ! The RK4 step [s] for tol over [0, span]: the a priori step
  ! (rk4_apriori_step, of a scene with that tol), within h w0 <= 1/2 and
  ! 0.45 times the stable step.  The stable step from RK4's stability limit
  ! (2.78 on the real axis, 2.83 on the imaginary one) over the largest
  ! |eigenvalue| of the linearization at the bottom, not rk4_max_stable_step,
  ! whose search costs ~13 us (the whole prediction is ~1 us without it).
  pure real(wp) function rk4_step(scene, span, tol) result(h)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: span, tol
    type(scene_t) :: sub
    real(wp) :: lam
    ! one output time: rk4_apriori_step reads the motion, tol and gamma only
    sub = scene_t(theta0=scene%theta0, omega0=scene%omega0, w0=scene%w0, w0lo=scene%w0lo, gamma=scene%gamma, &
                  tol=tol, want=scene%want, model=scene%model, t=[span])
    lam = max(scene%w0, scene%gamma/2 + sqrt(max(0.0_wp, scene%gamma/2 - scene%w0))* &
              sqrt(scene%gamma/2 + scene%w0))
    h = min(rk4_apriori_step(sub, max(span, tiny(1.0_wp))), 0.5_wp/scene%w0, 0.45_wp*2.78_wp/lam)
  end function rk4_step

  ! span / h, at most 1e300 (a prediction has no use for more; no overflow).
  pure real(wp) function steps(span, h) result(n)
    real(wp), intent(in) :: span, h
    n = 1.0e300_wp
    if (span/n <= h) n = span/h
  end function steps

end module pendula_scene_work
