!> The integrator path of the scenes: RK4 with its step from tol and the
!> window, verified by a run at 2h (Richardson), and CVODE with rtol from tol
!> and the number of periods, verified by a run ten times tighter; both
!> refined until the estimate meets tol.  Events come from the integrated
!> trajectory on a sample grid (pendula_scene_events).  The Taylor series
!> (pendula_taylor) runs once at the scene's tol: its own error estimate at
!> every output is the answer's, and its events come from its step
!> polynomials.
module pendula_scene_integrated
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_sci, format_int
  use pendula_status, only: status_t, set_error, check_alloc, PENDULA_OK, PENDULA_ERR_MAXSTEPS, PENDULA_ERR_CANCELLED
  use pendula_constants, only: pi
  use pendula_integrators, only: ode_stats_t, rk4_solve, rk4_final_state, rk4_max_stable_step, &
                                 cvode_solve, PENDULA_CVODE_ADAMS, PENDULA_CVODE_BDF, taylor_solve, taylor_solve_events
  use pendula_control, only: CONTROL_SIZE, cancel_requested
  use pendula_scene_codes, only: SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_WANT_FINAL, SCENE_WANT_EVENTS, &
                                 SCENE_CVODE_STEP_COST, SCENE_STEP_CAP, SCENE_TAYLOR_STEP_COST
  use pendula_scene_types, only: scene_t, scene_result_t, scene_cost_t, is_stiff, add_stats, window_end
  use pendula_scene_setup, only: alloc_outputs, finish_outputs, empty_outputs
  use pendula_scene_estimates, only: rk4_apriori_step, integrator_rounding, cvode_min_steps, cvode_first_rtol
  use pendula_scene_events, only: event_grid, grid_events, event_time_error, event_interp_error, scene_event_bound
  implicit none
  private

  public :: solve_rk4, solve_cvode, solve_taylor, integrate, run_fixed

  !> Richardson: |y_h - y_2h| / 15 estimates the error of y_h when the error
  !> goes like h^4 and the two runs' errors point the same way.  On the
  !> benchmark grid the fine run's true error was up to 3.8 times d / 15: a
  !> rotation decaying to rest at h w0 = 0.09 (the two errors in different
  !> directions; e_2h / e_h = 4.3), and 2.0 times for a 0.25 rad swing over
  !> ~170 periods at h w0 = 0.19 (e_2h / e_h = 8.2); a third run at 4h gave
  !> the ratios 16 and 227 there, so it cannot tell.  The factor covers both.
  real(wp), parameter :: RK4_SAFETY = 4.0_wp
  !> A posteriori refinements before giving up on meeting tol.
  integer, parameter :: MAX_REFINE = 4
  !> The first RK4 pair starts at this multiple of the a priori step (which
  !> assumes the worst error growth, often far too small on decaying or short
  !> windows), within the asymptotic regime h w0 <= 1/2.  When it fails by
  !> less than a halving, its fine run checks the halved one: the detour costs
  !> 0.75 of the final run's steps, the win when the a priori step was 2x too
  !> small is half of them.
  real(wp), parameter :: OPTIMISM = 2

contains

  !> One integrator run over the scene's window, output at tout (the times of
  !> the result, which may be only t(n)).  The integrators start at tout(1),
  !> so 0 is prepended when the first output time is later.  setting: h (RK4)
  !> or rtol (CVODE; atol = rtol * scale / 100 with scale the state's size).
  !> budget: RK4 steps allowed (CVODE: budget / SCENE_CVODE_STEP_COST steps).
  subroutine integrate(scene, model, setting, budget, tout, theta, omega, stats, status, control)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    integer, intent(in) :: model  !< SCENE_MODEL_RK4 or SCENE_MODEL_CVODE
    real(wp), intent(in) :: setting  !< RK4 step h [s] or CVODE rtol, > 0
    real(wp), intent(in) :: budget  !< work budget [RK4 steps] (a CVODE step costs SCENE_CVODE_STEP_COST)
    real(wp), intent(in) :: tout(:)  !< output times [s], >= 0, increasing
    real(wp), intent(out) :: theta(:)  !< theta [rad] at tout; size(tout)
    real(wp), intent(out) :: omega(:)  !< Omega [rad/s] at tout; size(tout)
    type(ode_stats_t), intent(out) :: stats  !< counters of the run: rhs evaluations, steps
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag, progress (pendula_control)
    real(wp), allocatable :: tt(:), th(:), om(:)
    integer :: off, n, method, ist
    real(wp) :: scale
    n = size(tout)
    if (scene%want == SCENE_WANT_FINAL .and. model == SCENE_MODEL_RK4) then
      call rk4_final_state(0.0_wp, tout(n), scene%theta0, scene%omega0, scene%w0, scene%gamma, &
                           setting, theta(n), omega(n), stats, status, control, int(min(budget, 9.0e18_wp), i8))
      return
    end if
    off = 0
    if (tout(1) > 0) off = 1
    allocate (tt(n + off), th(n + off), om(n + off), stat=ist)
    call check_alloc(ist, 'the integrator''s times and states', 3_i8*(n + off), 8, status)
    if (status%code /= PENDULA_OK) return
    tt(1) = 0
    tt(1 + off:) = tout
    if (model == SCENE_MODEL_RK4) then
      call rk4_solve(tt, scene%theta0, scene%omega0, scene%w0, scene%gamma, setting, th, om, stats, status, &
                     control, int(min(budget, 9.0e18_wp), i8))
    else
      method = merge(PENDULA_CVODE_BDF, PENDULA_CVODE_ADAMS, is_stiff(scene))
      scale = max(abs(scene%theta0) + abs(scene%omega0)/scene%w0, 1.0e-6_wp)
      call cvode_solve(tt, scene%theta0, scene%omega0, scene%w0, scene%gamma, setting, &
                       setting*scale/100, method, max(int(budget/SCENE_CVODE_STEP_COST, i8), 1_i8), th, om, stats, status, &
                       control)
    end if
    theta = th(1 + off:)
    omega = om(1 + off:)
  end subroutine integrate

  ! sup over the outputs of max(|d theta|, |d Omega|/w0)
  pure real(wp) function state_diff(th1, om1, th2, om2, w0) result(d)
    real(wp), intent(in) :: th1(:), om1(:), th2(:), om2(:), w0
    d = 0
    if (size(th1) > 0) d = max(maxval(abs(th1 - th2)), maxval(abs(om1 - om2))/w0)
  end function state_diff

  !> RK4 with h from tol and the window, verified by a run at 2h; refined
  !> from the observed error (which scales like h^4) until it meets tol.
  subroutine solve_rk4(scene, tend, budget, result, status, control)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tend  !< end of the window [s], t(n) (window_end), >= 0
    real(wp), intent(in) :: budget  !< work budget [RK4 steps] (a CVODE step costs SCENE_CVODE_STEP_COST)
    type(scene_result_t), intent(inout) :: result  !< gets the run at h, its Richardson error estimate, step and cost
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag, progress (pendula_control)
    real(wp) :: h, hb, f, q, hmax, est, d, round, nrun
    real(wp), allocatable :: th2(:), om2(:), tgrid(:)
    type(status_t) :: st
    integer :: it, ist
    logical :: reuse
    call rk4_max_stable_step(scene%w0, scene%gamma, hmax, st)
    hmax = 0.9_wp*hmax
    ! the runs take the substeps of step hb on every interval times 1/f:
    ! h = hb f is the fine run's step, and halving f halves it exactly
    hb = min(OPTIMISM*rk4_apriori_step(scene, tend), 0.5_wp/scene%w0, hmax/2)
    f = 1
    reuse = .false.
    call sample_grid(scene, tend, result, tgrid, status)
    if (status%code /= PENDULA_OK) return
    if (allocated(result%theta)) then
      if (size(result%theta) /= size(tgrid)) deallocate (result%theta, result%omega)
    end if
    ist = 0
    if (.not. allocated(result%theta)) allocate (result%theta(size(tgrid)), result%omega(size(tgrid)), stat=ist)
    if (ist == 0) allocate (th2(size(tgrid)), om2(size(tgrid)), stat=ist)
    call check_alloc(ist, 'the RK4 runs'' states', 4_i8*size(tgrid), 8, status)
    if (status%code /= PENDULA_OK) return
    est = ieee_value(1.0_wp, ieee_positive_inf)
    do it = 1, MAX_REFINE
      ! the run at h and its check at 2h (1.5 tend/h steps), or only the run
      ! at h when the previous run at 2h is its check
      h = hb*f
      nrun = merge(1.0_wp, 1.5_wp, reuse)*tend/h
      if (nrun > budget) then
        call set_error(status, PENDULA_ERR_MAXSTEPS, 'rk4 needs ~'//format_sci(nrun, 4)// &
                       ' steps for tol = '//format_sci(scene%tol, 4)//' over t = 0 .. '//format_sci(tend, 4)// &
                       ', over max_steps = '//format_sci(budget, 4)//' ('//format_sci(SCENE_STEP_CAP, 4)// &
                       ' ~ 1 min): use cvode, a larger tol,'// &
                       ' a shorter window, or raise max_steps')
        return
      end if
      if (reuse) then
        th2 = result%theta
        om2 = result%omega
      end if
      call rk4_run(scene, tgrid, hb, f, result%theta, result%omega, result%cost, status, control)
      if (status%code /= PENDULA_OK) return
      if (.not. reuse) call rk4_run(scene, tgrid, hb, 2*f, th2, om2, result%cost, status, control)
      if (status%code /= PENDULA_OK) return
      ! the step the fine run took (dense outputs may have set it below h)
      h = used_step(tgrid, hb, f)
      d = state_diff(result%theta, result%omega, th2, om2, scene%w0)
      round = integrator_rounding(scene, result%theta, tend/h)
      est = RK4_SAFETY*d/15 + round
      if (est <= scene%tol) exit
      if (it == MAX_REFINE .or. round > 0.5_wp*est) exit   ! a smaller h only adds rounding
      ! e ~ C h^4: the step for 0.6 tol, at most /16.  When that is about one
      ! halving, halve exactly: the run just made checks the next, and one run
      ! at h/2 (2 units of the run at h) costs less than a new pair at q h
      ! (1.5/q units) for q <= 3/4.
      q = (0.6_wp*scene%tol/est)**0.25_wp
      reuse = q >= 0.45_wp .and. q <= 0.75_wp
      if (reuse) then
        f = f/2
      else
        hb = h*max(1.0_wp/16, q)
        f = 1
      end if
    end do
    result%setting = h
    result%step = h
    result%error_estimate = est
    call finish_run(scene, tgrid, est, result, status)
  end subroutine solve_rk4

  ! RK4 from t = 0 through the outputs tg(:) with, on every interval dt_i
  ! between consecutive times (0 first), n_i = 2 ceil(dt_i/(2 h)) equal
  ! substeps times 1/factor (factor = 1 or 2 for a run and its check; 1/2,
  ! 1/4 ... for the exact halvings of a refinement).  Both runs of a pair
  ! thus halve the step on EVERY interval, so that their difference / 15 is
  ! the Richardson estimate of the fine run's error even when the outputs are
  ! denser than h.  A uniform grid goes to rk4_solve in one call (the step
  ! dt/n makes it take exactly n substeps); otherwise one rk4_final_state
  ! call per interval.  Final-state scenes integrate one interval.
  subroutine rk4_run(scene, tg, h, factor, th, om, cost, status, control)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tg(:), h, factor
    real(wp), intent(out) :: th(:), om(:)
    type(scene_cost_t), intent(inout) :: cost
    type(status_t), intent(inout) :: status
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    real(wp), allocatable :: tt(:), th1(:), om1(:)
    real(wp) :: dt, x, v, t0, x1, v1
    real(wp) :: nsub
    type(ode_stats_t) :: stats
    integer :: i, off, n, ist
    logical :: uniform
    n = size(tg)
    off = merge(1, 0, tg(1) > 0)
    allocate (tt(n + off), stat=ist)
    call check_alloc(ist, 'the RK4 run''s times', int(n + off, i8), 8, status)
    if (status%code /= PENDULA_OK) return
    tt(1) = 0
    tt(1 + off:) = tg
    uniform = .true.
    dt = tt(min(2, size(tt))) - tt(1)
    do i = 2, size(tt)
      if (abs((tt(i) - tt(i - 1)) - dt) > 1.0e-12_wp*dt) uniform = .false.
    end do
    if (size(tt) >= 2 .and. uniform) then
      nsub = substep_count(dt, h, factor)
      allocate (th1(size(tt)), om1(size(tt)), stat=ist)
      call check_alloc(ist, 'the RK4 run''s states', 2_i8*size(tt), 8, status)
      if (status%code /= PENDULA_OK) return
      call rk4_solve(tt, scene%theta0, scene%omega0, scene%w0, scene%gamma, dt/nsub, th1, om1, &
                     stats, status, control, huge(1_i8))
      call add_stats(cost, stats)
      th = th1(1 + off:)
      om = om1(1 + off:)
      return
    end if
    x = scene%theta0
    v = scene%omega0
    t0 = 0
    do i = 1, n
      ! each short run polls only every 4096 steps of its own: look between runs too
      if (present(control)) then
        if (cancel_requested(control)) then
          call set_error(status, PENDULA_ERR_CANCELLED, 'RK4 cancelled at t = '//format_sci(t0, 4)// &
                         ' (interrupted by the caller)')
          return
        end if
      end if
      if (tg(i) > t0) then
        dt = tg(i) - t0
        call rk4_final_state(t0, tg(i), x, v, scene%w0, scene%gamma, dt/substep_count(dt, h, factor), x1, v1, &
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
  end subroutine rk4_run

  ! rk4_run's substeps on an interval of length d: 2 ceil(d/(2 h)) / factor.
  pure real(wp) function substep_count(d, h, factor) result(ns)
    real(wp), intent(in) :: d, h, factor
    ns = 2*ceiling(d/(2*h), i8)
    ns = anint(ns/factor)
  end function substep_count

  ! The longest substep rk4_run takes on the grid tg (0 first when tg(1) > 0)
  ! at (h, factor): h itself, or shorter where every interval is shorter
  ! than 2 h (dense outputs set the step, and a smaller h changes nothing
  ! until it is below half an interval).
  pure real(wp) function used_step(tg, h, factor) result(hu)
    real(wp), intent(in) :: tg(:), h, factor
    real(wp) :: t0, d
    integer :: i
    hu = 0
    t0 = 0
    do i = 1, size(tg)
      d = tg(i) - t0
      if (d > 0) hu = max(hu, d/substep_count(d, h, factor))
      t0 = tg(i)
    end do
    if (.not. hu > 0) hu = h
  end function used_step

  !> CVODE with rtol from tol and the number of periods in the window, checked
  !> by a run 10x tighter; the tighter run is returned, and the difference of
  !> the two (an estimate of the looser run's error, which bounds the tighter
  !> one's) is its error estimate.
  subroutine solve_cvode(scene, tend, budget, result, status, control)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tend  !< end of the window [s], t(n) (window_end), >= 0
    real(wp), intent(in) :: budget  !< work budget [RK4 steps] (a CVODE step costs SCENE_CVODE_STEP_COST)
    type(scene_result_t), intent(inout) :: result  !< gets the tighter run, the two runs' difference as estimate, rtol, cost
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag, progress (pendula_control)
    real(wp) :: rtol, est, periods, predicted
    real(wp), allocatable :: th1(:), om1(:), tgrid(:)
    type(ode_stats_t) :: stats
    integer :: it, ist
    call sample_grid(scene, tend, result, tgrid, status)
    if (status%code /= PENDULA_OK) return
    if (allocated(result%theta)) deallocate (result%theta, result%omega)
    allocate (result%theta(size(tgrid)), result%omega(size(tgrid)), th1(size(tgrid)), om1(size(tgrid)), stat=ist)
    call check_alloc(ist, 'the CVODE runs'' states', 4_i8*size(tgrid), 8, status)
    if (status%code /= PENDULA_OK) return
    periods = 1 + scene%w0*tend/(2*pi)
    rtol = cvode_first_rtol(scene, tend, scene%tol)
    ! Up front: the two runs (rtol and rtol/10) need at least cvode_min_steps
    ! each (an underdamped, non-stiff scene; 0 otherwise)
    predicted = (cvode_min_steps(scene, tend, rtol) + cvode_min_steps(scene, tend, rtol/10))*SCENE_CVODE_STEP_COST
    if (predicted > budget) then
      call set_error(status, PENDULA_ERR_MAXSTEPS, 'window t = 0 .. '//format_sci(tend, 4)//' spans ~'// &
                     format_sci(periods, 4)//' periods: CVODE needs > ~'//format_sci(predicted/SCENE_CVODE_STEP_COST, 4)// &
                     ' steps for tol = '//format_sci(scene%tol, 4)//', over the budget max_steps = '// &
                     format_sci(budget, 4)//' (RK4 steps, a CVODE step counts '//format_int(nint(SCENE_CVODE_STEP_COST))// &
                     '; '//format_sci(SCENE_STEP_CAP, 4)//' ~ 1 min): use a larger tol, shorten the window or raise max_steps')
      return
    end if
    est = ieee_value(1.0_wp, ieee_positive_inf)
    do it = 1, MAX_REFINE
      call integrate(scene, SCENE_MODEL_CVODE, rtol, budget, tgrid, th1, om1, stats, status, control)
      call add_stats(result%cost, stats)
      if (status%code /= PENDULA_OK) return
      call integrate(scene, SCENE_MODEL_CVODE, rtol/10, budget, tgrid, result%theta, result%omega, stats, &
                     status, control)
      call add_stats(result%cost, stats)
      if (status%code /= PENDULA_OK) return
      est = state_diff(th1, om1, result%theta, result%omega, scene%w0) &
            + integrator_rounding(scene, result%theta, real(stats%steps, wp))
      if (est <= scene%tol .or. rtol <= 1.0e-14_wp .or. it == MAX_REFINE) exit
      rtol = max(rtol*max(1.0e-3_wp, 0.3_wp*scene%tol/est), 1.0e-14_wp)
    end do
    result%setting = rtol/10
    result%rtol = rtol/10
    result%error_estimate = est
    call finish_run(scene, tgrid, est, result, status)
  end subroutine solve_cvode

  !> The Taylor series over [0, tend] at the scene's tol, in one run: the
  !> outputs with the largest of its error estimates (each bounds its
  !> output's error; see pendula_taylor) as the answer's, or for want =
  !> events the events it locates on its step polynomials (their time error
  !> is that estimate over the rate at each event).  The budget counts a step
  !> as SCENE_TAYLOR_STEP_COST RK4 steps.
  subroutine solve_taylor(scene, tend, budget, result, status, control)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tend  !< end of the window [s], t(n) (window_end), >= 0
    real(wp), intent(in) :: budget  !< work budget [RK4 steps] (a Taylor step costs SCENE_TAYLOR_STEP_COST)
    type(scene_result_t), intent(inout) :: result  !< gets the run's outputs (or events), its estimate and cost
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag, progress (pendula_control)
    real(wp), allocatable :: tt(:), th(:), om(:), er(:), ev_t(:), ev_th(:), ev_om(:)
    integer, allocatable :: ev_k(:)
    integer :: n, off, ist, nev
    integer(i8) :: nmax, steps
    logical :: trunc
    type(ode_stats_t) :: stats
    type(status_t) :: st
    real(wp) :: est, nrun
    ! a short run polls the cancel flag only every 128 steps: look before it too
    if (present(control)) then
      if (cancel_requested(control)) then
        call set_error(status, PENDULA_ERR_CANCELLED, 'Taylor cancelled at t = 0 (interrupted by the caller)')
        return
      end if
    end if
    ! up front: the series takes at least one step per 2/w0 (its largest step)
    nrun = scene%w0*tend/2
    if (nrun*SCENE_TAYLOR_STEP_COST > budget) then
      call set_error(status, PENDULA_ERR_MAXSTEPS, 'the Taylor series needs > ~'//format_sci(nrun, 4)// &
                     ' steps for tol = '//format_sci(scene%tol, 4)//' over t = 0 .. '//format_sci(tend, 4)// &
                     ', over max_steps = '//format_sci(budget, 4)//' (RK4 steps, a Taylor step counts '// &
                     format_int(nint(SCENE_TAYLOR_STEP_COST))//'; '//format_sci(SCENE_STEP_CAP, 4)// &
                     ' ~ 1 min): use a larger tol, shorten the window or raise max_steps')
      return
    end if
    steps = max(int(min(budget/SCENE_TAYLOR_STEP_COST, 9.0e18_wp), i8), 1_i8)
    if (scene%want == SCENE_WANT_EVENTS) then
      if (allocated(result%theta)) deallocate (result%theta, result%omega)
      nmax = min(scene_event_bound(scene%w0, tend, scene%theta0, scene%omega0) + 1, int(huge(1), i8)/2)
      allocate (tt(2), th(2), om(2), er(2), ev_t(nmax), ev_th(nmax), ev_om(nmax), ev_k(nmax), stat=ist)
      call check_alloc(ist, 'the Taylor run''s events', 4_i8*nmax, 8, status)
      if (status%code /= PENDULA_OK) return
      tt = [0.0_wp, max(tend, tiny(1.0_wp))]
      call taylor_solve_events(tt, scene%theta0, scene%omega0, scene%w0, scene%gamma, min(scene%tol, 1.0_wp), &
                               th, om, er, ev_t, ev_k, ev_th, ev_om, nev, trunc, stats, st, control=control, max_steps=steps)
      if (st%code /= PENDULA_OK) then
        status = st
        return
      end if
      call add_stats(result%cost, stats)
      ! events after 0 and at most tend (the run ends at tend; tiny when the window is empty)
      nev = count(ev_t(1:nev) <= tend)
      result%event_t = ev_t(1:nev)
      result%event_kind = ev_k(1:nev)
      result%event_theta = ev_th(1:nev)
      result%event_omega = ev_om(1:nev)
      est = maxval(er)
      result%error_estimate = est
      call empty_outputs(result, status)
      if (status%code /= PENDULA_OK) return
      result%event_time_error = event_time_error(result, est, scene%w0)
      return
    end if
    call alloc_outputs(scene, result, status)
    if (status%code /= PENDULA_OK) return
    n = size(result%t)
    off = 0
    if (n == 0) then
      result%error_estimate = 0
      call finish_outputs(scene, result, status)
      return
    end if
    if (result%t(1) > 0) off = 1
    allocate (tt(n + off), th(n + off), om(n + off), er(n + off), stat=ist)
    call check_alloc(ist, 'the Taylor run''s times and states', 4_i8*(n + off), 8, status)
    if (status%code /= PENDULA_OK) return
    tt(1) = 0
    tt(1 + off:) = result%t
    if (size(tt) == 1) then
      ! one output at t = 0: the initial state itself
      th = scene%theta0
      om = scene%omega0
      er = 0
      stats = ode_stats_t()
    else
      call taylor_solve(tt, scene%theta0, scene%omega0, scene%w0, scene%gamma, min(scene%tol, 1.0_wp), th, om, &
                        er, stats, st, control=control, max_steps=steps)
      if (st%code /= PENDULA_OK) then
        status = st
        return
      end if
    end if
    call add_stats(result%cost, stats)
    if (allocated(result%theta)) deallocate (result%theta, result%omega)
    result%theta = th(1 + off:)
    result%omega = om(1 + off:)
    result%error_estimate = maxval(er(1 + off:))
    call finish_outputs(scene, result, status)
  end subroutine solve_taylor

  !> One run of rk4 (setting = h) or cvode (setting = rtol) at a fixed
  !> setting with no verification (scene_run_model): the outputs, or for
  !> want = events the events of the run on the event grid; the error
  !> estimate is 0 (unknown).  want = period is the caller's to refuse.
  subroutine run_fixed(scene, model, setting, budget, result, status, control)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    integer, intent(in) :: model  !< SCENE_MODEL_RK4 or SCENE_MODEL_CVODE
    real(wp), intent(in) :: setting  !< RK4 step h [s] or CVODE rtol, > 0
    real(wp), intent(in) :: budget  !< work budget [RK4 steps] (a CVODE step costs SCENE_CVODE_STEP_COST)
    type(scene_result_t), intent(inout) :: result  !< gets the run's outputs (or events), setting and cost
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag, progress (pendula_control)
    real(wp), allocatable :: tgrid(:)
    type(ode_stats_t) :: stats
    integer :: ist
    call sample_grid(scene, window_end(scene), result, tgrid, status)
    if (status%code /= PENDULA_OK) return
    if (allocated(result%theta)) deallocate (result%theta, result%omega)
    allocate (result%theta(size(tgrid)), result%omega(size(tgrid)), stat=ist)
    call check_alloc(ist, 'the run''s states', 2_i8*size(tgrid), 8, status)
    if (status%code /= PENDULA_OK) return
    call integrate(scene, model, setting, budget, tgrid, result%theta, result%omega, stats, status, control)
    if (status%code /= PENDULA_OK) return
    call add_stats(result%cost, stats)
    result%setting = setting
    if (model == SCENE_MODEL_RK4) result%step = setting
    if (model == SCENE_MODEL_CVODE) result%rtol = setting
    result%error_estimate = 0
    call finish_run(scene, tgrid, 0.0_wp, result, status)
  end subroutine run_fixed

  ! The times an integrator run samples: the outputs of the result
  ! (allocated here), or for events a grid fine enough for Hermite
  ! interpolation (event_grid).
  pure subroutine sample_grid(scene, tend, result, tgrid, status)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tend
    type(scene_result_t), intent(inout) :: result
    real(wp), allocatable, intent(out) :: tgrid(:)
    type(status_t), intent(inout) :: status
    integer :: ist
    if (scene%want == SCENE_WANT_EVENTS) then
      call event_grid(scene, tend, tgrid, status)
    else
      call alloc_outputs(scene, result, status)
      if (status%code /= PENDULA_OK) return
      allocate (tgrid(size(result%t)), stat=ist)
      call check_alloc(ist, 'the sample times', int(size(result%t), i8), 8, status)
      if (status%code /= PENDULA_OK) return
      tgrid(:) = result%t
    end if
  end subroutine sample_grid

  ! The wanted quantities from the trajectory on tgrid (in result%theta,
  ! result%omega) with error estimate est: the events on the grid (and no
  ! time series), or the outputs themselves.
  pure subroutine finish_run(scene, tgrid, est, result, status)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tgrid(:), est
    type(scene_result_t), intent(inout) :: result
    type(status_t), intent(inout) :: status
    if (status%code /= PENDULA_OK) return
    if (scene%want == SCENE_WANT_EVENTS) then
      call grid_events(scene, tgrid, result%theta, result%omega, result, status)
      if (status%code /= PENDULA_OK) return
      call empty_outputs(result, status)
      if (status%code /= PENDULA_OK) return
      result%event_time_error = event_time_error(result, est + event_interp_error(scene, tgrid), scene%w0)
    else
      call finish_outputs(scene, result, status)
    end if
  end subroutine finish_run

end module pendula_scene_integrated
