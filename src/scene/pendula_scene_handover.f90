!> Integrated scenes, part by part: a damped motion that has decayed into the
!> regime the linear closed form covers needs no integrator for the rest of
!> the window.  The integrator (RK4 or CVODE, verified as in
!> pendula_scene_integrated) runs over [0, ts] only; from its state at ts the
!> linear damped closed form answers t > ts.  ts is predicted from the decay
!> rate and the amplitude at which the linear model's nonlinearity estimate
!> (linear_estimate) fits the tolerance, and checked a posteriori from the
!> integrated state; a later ts is tried when the check fails.
!>
!> Error of the hand-over: after ts the answer differs from the pendulum by
!> the linear model's nonlinearity from the true state at ts (linear_estimate
!> from the integrated state), plus the integrator's error at ts carried by
!> the linear equation.  That equation does not amplify: its energy
!> Omega^2 + w0^2 theta^2 never grows (d/dt = -2 gamma Omega^2), so the
!> carried error is at most sqrt(2) times the integrator's estimate (in
!> max(|d theta|, |d Omega|/w0)); at the outputs after ts it is at most the
!> gain of the linear propagator from ts to them (carry_gain), which decays
!> like e^(-gamma (t - ts)/2).  Both are inside the reported estimate.  When
!> no output precedes ts (want = final, or a grid that starts late) the state
!> at ts is needed only to tol / gain: the integrator's part then runs at that
!> looser tolerance (at most SUB_TOL_REL of the motion's size, where its own
!> estimate is still in the asymptotic regime), so a long decayed window
!> costs a coarse run.
!>
!> want = events: the integrator's part is sampled on the event grid of
!> [0, ts] and gives the events there; the linear closed form gives those
!> after ts.  Each of its events is off by the linear model's nonlinearity AT
!> that time (linear_error_at of pendula_scene_events, which decays with the
!> swing) plus the carried error, over the event's rate: late in a decay both
!> shrink like the rate, so the time error stays a phase error where a
!> whole-window run's state error over the vanishing rates grew without bound.
module pendula_scene_handover
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_sci
  use pendula_status, only: status_t, check_alloc, PENDULA_OK, PENDULA_ERR_CANCELLED
  use pendula_constants, only: pi
  use pendula_linear_damped, only: linear_damped_t, linear_damped_init, linear_damped_state
  use pendula_control, only: CONTROL_SIZE
  use pendula_scene_codes, only: SCENE_LINEAR_SAFETY, SCENE_MODEL_AUTO, SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_MODEL_TAYLOR, &
                                 SCENE_MODEL_LINEAR, &
                                 SCENE_WANT_STATE, SCENE_WANT_THETA, SCENE_WANT_FINAL, SCENE_WANT_ENERGY, SCENE_WANT_EVENTS
  use pendula_scene_types, only: scene_t, scene_result_t, scene_cost_t, swing, scene_like
  use pendula_scene_setup, only: alloc_outputs, finish_outputs
  use pendula_scene_estimates, only: choose_model, slow_rate, taylor_steps
  use pendula_scene_bounds, only: linear_estimate
  use pendula_scene_integrated, only: solve_rk4, solve_cvode, solve_taylor
  use pendula_scene_closed, only: solve_closed
  use pendula_scene_events, only: event_grid, grid_events, event_time_error, event_interp_error, linear_error_at, &
                                  event_rate, event_grid_intervals
  implicit none
  private

  public :: solve_integrated, add_cost, handover_time, loosened_tol, MAX_PART

  !> A hand-over is tried only when it spares at least this part of the window.
  real(wp), parameter :: MAX_PART = 0.75_wp
  !> For want = events the hand-over also spares the integrator the late
  !> events, whose time errors are its state error over tiny rates: tried
  !> while it leaves at least this part of the window to the closed form.
  real(wp), parameter :: MAX_PART_EVENTS = 0.9_wp
  !> The linear part's events are found this many tol [s] past the window's
  !> end, to see those whose time error straddles it.
  real(wp), parameter :: END_MARGIN = 10.0_wp
  !> Hand-over points tried before integrating the whole window.
  integer, parameter :: MAX_TRIES = 3
  !> The same for want = events, where a try may also tighten the integrated part.
  integer, parameter :: MAX_TRIES_EVENTS = 5
  !> Loosest tolerance of the integrated part, relative to the motion's size
  !> (the swing modulo 2 pi, at most pi), when the carried error decays
  !> before the first output: the integrators' a posteriori estimates
  !> (Richardson, two CVODE tolerances) assume errors well below the motion.
  real(wp), parameter :: SUB_TOL_REL = 1.0e-2_wp
  !> want = events with the Taylor series: its whole-window run comes before
  !> the hand-over when the part's event grid has more than this many
  !> samples per predicted step (a sample costs ~0.4 of a step).
  real(wp), parameter :: WHOLE_FIRST = 8
  !> Swing [rad] whose linear-model nonlinearity handover_time scales from.
  real(wp), parameter :: AREF = 0.1_wp

contains

  !> Answer a checked, damped or undamped scene with the integrator `model`
  !> (RK4 or CVODE), handing over to the linear closed form once the motion
  !> has decayed enough (gamma > 0; want state, theta, final, energy or events).  why:
  !> the reason so far; the hand-over, when made, is appended.
  subroutine solve_integrated(scene, model, tend, budget, why, result, status, control, used)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    integer, intent(in) :: model  !< SCENE_MODEL_RK4, SCENE_MODEL_CVODE or SCENE_MODEL_TAYLOR
    real(wp), intent(in) :: tend  !< end of the window [s], t(n) (window_end), >= 0
    real(wp), intent(in) :: budget  !< work budget [RK4 steps] (a CVODE step costs SCENE_CVODE_STEP_COST)
    character(len=:), allocatable, intent(inout) :: why  !< the reason so far; the hand-over is appended
    type(scene_result_t), intent(inout) :: result  !< gets the answer, its error estimate and cost
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag, progress (pendula_control)
    !> optional: the integrator that made the answer (a hand-over's part picks
    !> its own for its length: it may differ from model)
    integer, intent(out), optional :: used
    type(scene_t) :: sub
    type(scene_result_t) :: part, fresh
    type(scene_cost_t) :: spent
    real(wp) :: ts, xs, vs, e1, elin, est, center, gain
    integer :: it, k, sub_model
    logical :: early
    type(scene_result_t) :: best
    real(wp) :: best_ts
    integer :: best_model
    logical :: done, whole_run
    type(scene_result_t) :: whole
    type(status_t) :: st0
    best%event_time_error = ieee_value(1.0_wp, ieee_positive_inf)   ! none yet
    best_ts = 0
    best_model = model
    if (present(used)) used = model
    whole_run = .false.
    if (scene%gamma > 0 .and. scene%want == SCENE_WANT_EVENTS) then
      ! the Taylor series finds the events on its step polynomials, with no
      ! sample grid: where the hand-over's part would be sampled on an event
      ! grid far denser than the series' steps (strong damping: 8 gamma
      ! samples a second), its one run over the whole window first, the
      ! hand-over only if that run's events miss tol (slow events near rest)
      ts = handover_time(scene%theta0, scene%omega0, scene%w0, scene%gamma, scene%tol*scene%w0, tend)
      if (model == SCENE_MODEL_TAYLOR .and. event_grid_intervals(scene, min(ts, tend)) > &
          WHOLE_FIRST*taylor_steps(scene, tend, scene%tol)) then
        st0 = status_t()
        call solve_taylor(scene, tend, budget, whole, st0, control)
        if (st0%code == PENDULA_OK .and. max(whole%error_estimate, whole%event_time_error) <= scene%tol) then
          result = whole
          return
        end if
        if (st0%code == PENDULA_ERR_CANCELLED) then
          status = st0
          return
        end if
        whole_run = st0%code == PENDULA_OK
        if (.not. whole_run) whole = fresh
        call add_cost(spent, whole%cost)
      end if
      call events_handover(done)
      if (done .and. present(used)) used = sub_model
      if (done .or. status%code /= PENDULA_OK) return
    else if (scene%gamma > 0 .and. (scene%want == SCENE_WANT_STATE .or. scene%want == SCENE_WANT_THETA .or. &
                                    scene%want == SCENE_WANT_FINAL .or. scene%want == SCENE_WANT_ENERGY)) then
      ts = handover_time(scene%theta0, scene%omega0, scene%w0, scene%gamma, scene%tol, tend)
      do it = 1, MAX_TRIES
        if (.not. ts < MAX_PART*tend) exit
        call sub_scene(scene, ts, sub, k, status)
        if (status%code /= PENDULA_OK) return
        gain = carry_gain(scene, ts, k)
        ! outputs at t = 0 are the initial state itself, exact: only later
        ! ones before ts need the part at tol
        early = count(scene%t(1:k) > 0) > 0
        if (.not. early) sub%tol = loosened_tol(scene, sub%tol, gain)
        call run_part()
        if (status%code /= PENDULA_OK) return
        ! the linear model about the equilibrium the motion has settled to,
        ! 2 pi k (to its rounding, eps |2 pi k|, added to its estimate)
        center = 2*pi*anint(part%theta(size(part%theta))/(2*pi))
        xs = part%theta(size(part%theta)) - center
        vs = part%omega(size(part%omega))
        e1 = part%error_estimate
        elin = linear_estimate(xs, vs, scene%w0, scene%gamma, tend - ts) + 2*epsilon(1.0_wp)*abs(center)
        ! e1 bounds the outputs before ts too (when there are any)
        est = elin + gain*e1
        if (early) est = max(e1, est)
        if (est <= scene%tol) then
          call assemble(scene, part, k, ts, center, xs, vs, est, result, status)
          if (status%code /= PENDULA_OK) return
          call add_cost(spent, result%cost)
          result%cost = spent
          result%setting = part%setting
          result%step = part%step
          result%rtol = part%rtol
          if (present(used)) used = sub_model
          why = why//'; the motion has decayed by t = '//format_sci(ts, 4)//' s: '// &
                trim(integrator_label(sub_model))//' up to there, then the linear '// &
                'closed form from that state (nonlinearity ~'//format_sci(elin, 4)//' rad, carried error ~'// &
                format_sci(gain*e1, 4)//' rad)'
          return
        end if
        if (elin <= scene%tol/4) exit   ! the integrator's part is what fails: no later ts helps
        ts = ts + max(0.5_wp*ts, handover_time(xs, vs, scene%w0, scene%gamma, scene%tol, tend - ts))
      end do
    end if
    if (whole_run) then
      ! the whole window's Taylor run is already done (its cost is in spent)
      result = whole
      result%cost = spent
    else
      call run(scene, model, tend, result)
      call add_cost(result%cost, spent)
    end if
    ! events: a hand-over that fell short of tol may still beat the whole window
    if (status%code == PENDULA_OK .and. scene%want == SCENE_WANT_EVENTS .and. &
        best%event_time_error < result%event_time_error) then
      spent = result%cost
      result = best
      result%cost = spent
      if (present(used)) used = best_model
      call append_handover_why()
    end if
  contains
    ! want = events: the integrator over [0, ts] sampled on the event grid of
    ! that part, its events there (each off by its state estimate plus the
    ! interpolation's, over the rate); the linear closed form's events over
    ! (ts, tend] from the integrated state at ts, about the bottom 2 pi k the
    ! motion has settled to, each off by the linear model's nonlinearity AT
    ! that time (linear_error_at, which decays with the swing) plus the
    ! integrator's error at ts carried there (propagator_gain), over the rate.
    ! The sign of theta and Omega at ts is the one both parts see, so no
    ! event is lost or counted twice at the junction.  done: the answer meets
    ! tol; otherwise a later ts, or a tighter integrated part when that is
    ! what fails; after MAX_TRIES the whole window is integrated.
    subroutine events_handover(done)
      logical, intent(out) :: done
      type(scene_t) :: ls
      type(scene_result_t) :: lres, evs, cand
      type(status_t) :: st
      real(wp), allocatable :: tg(:), each(:), elev(:)
      real(wp) :: eint, e, dts, wd, c, rh, sw
      integer :: n, ni, nl, ist
      logical :: unverified
      done = .false.
      ts = handover_time(scene%theta0, scene%omega0, scene%w0, scene%gamma, scene%tol*scene%w0, tend)
      call scene_like(scene, sub, 0, status)
      if (status%code /= PENDULA_OK) return
      sub%want = SCENE_WANT_STATE
      sub%tol = scene%tol/2
      if (scene%gamma < scene%w0) then
        ! clearly under-damped: the linear part's time errors are its phase
        ! drift, ~ c rh^2 for a swing rh at ts (linear_error_at's estimate
        ! over the rate w_d rh); ts where the swing, decaying at gamma/2, is
        ! that rh; the integrated part's last events (rates ~ w0 rh) need a
        ! state error of about tol w0 rh (its estimate is often well below its
        ! tol: no more margin than that)
        wd = sqrt(scene%w0 - scene%gamma/2)*sqrt(scene%w0 + scene%gamma/2)
        c = SCENE_LINEAR_SAFETY*scene%w0**2*max(1.0_wp, (wd + scene%gamma/2)/scene%w0)/(16*wd**2*scene%gamma)
        rh = sqrt(0.25_wp*scene%tol/c)
        sw = min(swing(scene), pi)
        ts = max(ts, log(max(1.0_wp, sw/rh))/(scene%gamma/2))
        sub%tol = min(sub%tol, scene%tol*scene%w0*rh)
      end if
      do it = 1, MAX_TRIES_EVENTS
        if (.not. ts < MAX_PART_EVENTS*tend) exit
        call event_grid(sub, ts, tg, status)
        if (status%code /= PENDULA_OK) return
        deallocate (sub%t)
        allocate (sub%t(size(tg)), stat=ist)
        call check_alloc(ist, 'the event sample grid', int(size(tg), i8), 8, status)
        if (status%code /= PENDULA_OK) return
        sub%t(:) = tg
        call run_part()
        if (status%code /= PENDULA_OK) return
        n = size(tg)
        e1 = part%error_estimate
        ! the integrator did not reach the part's tol (a rounding floor): no
        ! tighter part or later ts would
        if (e1 > sub%tol) exit
        evs = fresh
        call grid_events(sub, tg, part%theta, part%omega, evs, status)
        if (status%code /= PENDULA_OK) return
        ni = size(evs%event_t)
        eint = event_time_error(evs, e1 + event_interp_error(sub, tg), scene%w0)
        center = 2*pi*anint(part%theta(n)/(2*pi))
        xs = part%theta(n) - center
        vs = part%omega(n)
        call scene_like(scene, ls, 1, status)
        if (status%code /= PENDULA_OK) return
        ls%theta0 = xs
        ls%omega0 = vs
        ! past the window's end too: an event within its time error of the
        ! end may be in or out (the count is unverified)
        ls%t = [tend - ts + END_MARGIN*scene%tol]
        lres = fresh
        st = status_t()
        call solve_closed(ls, SCENE_MODEL_LINEAR, 0.0_wp, lres, st)
        if (st%code /= PENDULA_OK) exit
        call add_cost(spent, lres%cost)
        elev = linear_error_at(xs, vs, scene%w0, scene%gamma, lres%event_t) + &
               propagator_gain(scene%w0, scene%gamma, lres%event_t)*(e1 + 2*epsilon(1.0_wp)*abs(center))
        unverified = .not. lres%event_time_error < huge(1.0_wp) .or. any(abs(ts + lres%event_t - tend) <= &
                                                     elev/event_rate(lres%event_kind, lres%event_theta, lres%event_omega, scene%w0))
        nl = count(ts + lres%event_t <= tend)
        cand = fresh
        cand%event_t = [evs%event_t, ts + lres%event_t(1:nl)]
        cand%event_kind = [evs%event_kind, lres%event_kind(1:nl)]
        cand%event_theta = [evs%event_theta, lres%event_theta(1:nl) + center]
        cand%event_omega = [evs%event_omega, lres%event_omega(1:nl)]
        ! the integrated part's events at its own estimate; the linear part's
        ! (lres%event_t measured from ts) at theirs
        each = [spread(e1 + event_interp_error(sub, tg), 1, ni), elev(1:nl)]
        ! ts + tau rounds to eps (ts + tau)
        e = event_time_error(cand, 0.0_wp, scene%w0, each) + 4*epsilon(1.0_wp)*tend
        if (unverified) e = ieee_value(1.0_wp, ieee_positive_inf)
        if (e < best%event_time_error) then
          best = cand
          best%event_time_error = e
          best%error_estimate = e1
          best%t = [real(wp) ::]
          best%theta = [real(wp) ::]
          best%omega = [real(wp) ::]
          best%setting = part%setting
          best%step = part%step
          best%rtol = part%rtol
          best_model = sub_model
          best_ts = ts
        end if
        if (e <= scene%tol) then
          result = best
          result%cost = spent
          call append_handover_why()
          done = .true.
          return
        end if
        ! the integrated part's events (eint) and the linear part's (what
        ! exceeds eint) each get what fails: a tighter integrated part, a later
        ! ts (the linear part's time errors scale like the swing at ts squared,
        ! which decays at the slowest linear rate; the integrated part's late
        ! events then have rates smaller by about that decay, its tol with them)
        dts = 0
        if (e > eint .and. e < huge(1.0_wp)) then
          dts = max(0.1_wp*ts, log(e/(0.5_wp*scene%tol))/(2*slow_rate(scene%w0, scene%gamma)))
        else if (e > eint) then
          dts = max(0.5_wp*ts, 1/max(scene%w0, scene%gamma))
        end if
        sub%tol = sub%tol*max(1.0e-3_wp, min(1.0_wp, 0.25_wp*scene%tol/eint)* &
                              exp(-slow_rate(scene%w0, scene%gamma)*dts))
        ts = ts + dts
      end do
    end subroutine events_handover

    ! The reason's part for an events hand-over kept (best), appended to why
    ! (a subroutine: no function returns a deferred-length text here).
    subroutine append_handover_why()
      why = why//'; events: the motion has decayed by t = '//format_sci(best_ts, 4)//' s: '// &
            trim(integrator_label(best_model))//' up to there, then the linear '// &
            'closed form from that state (event times off by up to '//format_sci(best%event_time_error, 4)//' s)'
    end subroutine append_handover_why

    ! The integrated part: sub over [0, ts] into part, with the integrator
    ! picked for that length; its cost added to spent (none on an error).
    subroutine run_part()
      part = fresh
      sub_model = model
      if (scene%model == SCENE_MODEL_AUTO) call pick_integrator(sub, ts, model, sub_model, status)
      if (status%code /= PENDULA_OK) return
      call run(sub, sub_model, ts, part)
      if (status%code /= PENDULA_OK) return
      call add_cost(spent, part%cost)
    end subroutine run_part

    subroutine run(sc, mdl, t_end, res)
      type(scene_t), intent(in) :: sc
      integer, intent(in) :: mdl
      real(wp), intent(in) :: t_end
      type(scene_result_t), intent(inout) :: res
      if (mdl == SCENE_MODEL_RK4) then
        call solve_rk4(sc, t_end, budget, res, status, control)
      else if (mdl == SCENE_MODEL_TAYLOR) then
        call solve_taylor(sc, t_end, budget, res, status, control)
      else
        call solve_cvode(sc, t_end, budget, res, status, control)
      end if
    end subroutine run
  end subroutine solve_integrated

  !> Tolerance [rad] of the integrated part when no output precedes the
  !> hand-over: the state there is needed only to tol over the gain [-] of
  !> the linear propagator to the outputs after it, but at most SUB_TOL_REL
  !> of the motion's size (where the integrators' a posteriori estimates
  !> stay asymptotic); never below tol, and no overflow when gain underflows.
  pure real(wp) function loosened_tol(scene, tol, gain) result(loose)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tol  !< the part's tolerance before loosening [rad], > 0
    real(wp), intent(in) :: gain  !< gain of the linear propagator after the hand-over, in [0, sqrt(2)]
    loose = SUB_TOL_REL*min(swing(scene), pi)
    if (tol < loose*gain) loose = tol/gain
    loose = max(tol, loose)
  end function loosened_tol

  ! The first part of the scene: the outputs before ts, then ts itself (or
  ! ts alone for want = final), at tol/2; k of the scene's outputs lie before ts.
  pure subroutine sub_scene(scene, ts, sub, k, status)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: ts
    type(scene_t), intent(out) :: sub
    integer, intent(out) :: k
    type(status_t), intent(inout) :: status
    k = count(scene%t < ts)
    if (scene%want == SCENE_WANT_FINAL) k = 0
    call scene_like(scene, sub, k + 1, status)
    if (status%code /= PENDULA_OK) return
    sub%tol = scene%tol/2
    sub%t(1:k) = scene%t(1:k)
    sub%t(k + 1) = ts
    if (scene%want /= SCENE_WANT_FINAL) sub%want = SCENE_WANT_STATE
  end subroutine sub_scene

  ! Gain of the linear propagator from ts to the outputs after it: the largest,
  ! over those outputs, of its induced norm in max(|theta|, |Omega|/w0)
  ! (from the states (1, 0) and (0, w0) it maps), and never above sqrt(2)
  ! (its energy does not grow).  k outputs precede ts (final: only t(n) follows).
  pure real(wp) function carry_gain(scene, ts, k) result(gain)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: ts
    integer, intent(in) :: k
    ! blocks of the outputs: propagator_gain's work arrays live on the stack,
    ! and the outputs may be millions (no heap copy of them either)
    integer, parameter :: BLOCK = 512
    integer :: n, i0
    n = size(scene%t)
    gain = 0
    if (scene%want == SCENE_WANT_FINAL) then
      gain = maxval(propagator_gain(scene%w0, scene%gamma, [scene%t(n) - ts]))
      return
    end if
    do i0 = k + 1, n, BLOCK
      gain = max(gain, maxval(propagator_gain(scene%w0, scene%gamma, scene%t(i0:min(n, i0 + BLOCK - 1)) - ts)))
    end do
  end function carry_gain

  ! Induced norm in max(|theta|, |Omega|/w0) of the linear damped propagator
  ! over each time tau(i) >= 0 [s] (from the states (1, 0) and (0, w0) it
  ! maps), to a few ulps of the evaluation, never above sqrt(2) (its energy
  ! does not grow).
  pure function propagator_gain(w0, gamma, tau) result(gain)
    real(wp), intent(in) :: w0, gamma, tau(:)
    real(wp) :: gain(size(tau))
    type(linear_damped_t) :: ua, ub
    type(status_t) :: st
    real(wp) :: xa(size(tau)), va(size(tau)), xb(size(tau)), vb(size(tau))
    call linear_damped_init(ua, 1.0_wp, 0.0_wp, w0, gamma, st)
    call linear_damped_init(ub, 0.0_wp, w0, w0, gamma, st)
    call linear_damped_state(ua, tau, xa, va)
    call linear_damped_state(ub, tau, xb, vb)
    gain = min(sqrt(2.0_wp), max(abs(xa) + abs(xb), (abs(va) + abs(vb))/w0)*(1 + 64*epsilon(1.0_wp)))
  end function propagator_gain

  ! The integrator for the part [0, ts] (the choice for the whole window may
  ! have taken CVODE for a length RK4 now need not cover); a closed form is
  ! not an option there (it was not for the whole window).
  subroutine pick_integrator(sub, ts, model, sub_model, status)
    type(scene_t), intent(in) :: sub
    real(wp), intent(in) :: ts
    integer, intent(in) :: model
    integer, intent(out) :: sub_model
    type(status_t), intent(inout) :: status
    real(wp) :: e
    character(len=:), allocatable :: w
    call choose_model(sub, ts, sub_model, e, w, status)
    if (sub_model /= SCENE_MODEL_RK4 .and. sub_model /= SCENE_MODEL_CVODE .and. sub_model /= SCENE_MODEL_TAYLOR) &
      sub_model = model
  end subroutine pick_integrator

  ! The answer from the integrated part (outputs 1..k, state at ts last) and
  ! the linear closed form about center from (center + xs, vs) at ts for the
  ! outputs after it.
  pure subroutine assemble(scene, part, k, ts, center, xs, vs, est, result, status)
    type(scene_t), intent(in) :: scene
    type(scene_result_t), intent(in) :: part
    integer, intent(in) :: k
    real(wp), intent(in) :: ts, center, xs, vs, est
    type(scene_result_t), intent(inout) :: result
    type(status_t), intent(inout) :: status
    type(linear_damped_t) :: lin
    type(status_t) :: st
    integer :: n
    call alloc_outputs(scene, result, status)
    if (status%code /= PENDULA_OK) return
    n = size(result%t)
    result%theta(1:k) = part%theta(1:k)
    result%omega(1:k) = part%omega(1:k)
    call linear_damped_init(lin, xs, vs, scene%w0, scene%gamma, st)
    call linear_damped_state(lin, result%t(k + 1:n) - ts, result%theta(k + 1:n), result%omega(k + 1:n))
    result%theta(k + 1:n) = result%theta(k + 1:n) + center
    result%cost%closed_form_evals = n - k
    result%error_estimate = est
    call finish_outputs(scene, result, status)
  end subroutine assemble

  pure subroutine add_cost(total, c)
    type(scene_cost_t), intent(inout) :: total  !< cost added to
    type(scene_cost_t), intent(in) :: c  !< cost to add (wall_time is not added)
    total%closed_form_evals = total%closed_form_evals + c%closed_form_evals
    total%rhs_evals = total%rhs_evals + c%rhs_evals
    total%steps = total%steps + c%steps
    total%runs = total%runs + c%runs
  end subroutine add_cost

  !> Predicted time [s] after which the linear model's nonlinearity over the
  !> rest of a window of length span fits tol/4, for a motion from (x0, v0):
  !> a rotation first loses its excess energy (m decays at least like
  !> e^(-gamma t) while it goes over the top), a start at distance d0 from
  !> the top first hangs there for ~ln(pi/d0)/lambda (lambda = sqrt(gamma^2/4
  !> + w0^2) - gamma/2, the growth rate of the linearization about the top:
  !> without it a start 1e-6 rad below the top was predicted to have decayed
  !> while still up, and every try failed), then the swing A decays at the
  !> slowest rate of the linear modes (slow_rate) down to the amplitude A_h
  !> where linear_estimate (which grows like A^3) is tol/4.  A prediction
  !> only: the integrated state at that time decides (solve_integrated), or
  !> the work a solve will do (pendula_scene_work).
  pure real(wp) function handover_time(x0, v0, w0, gamma, tol, span) result(ts)
    real(wp), intent(in) :: x0  !< initial angle [rad]
    real(wp), intent(in) :: v0  !< initial angular velocity [rad/s]
    real(wp), intent(in) :: w0  !< natural frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], > 0
    real(wp), intent(in) :: tol  !< tolerance [rad], > 0
    real(wp), intent(in) :: span  !< the rest of the window [s], >= 0
    real(wp) :: xr, msep, a0, ah, trot, thang, d0, el, half, rate, cap, x, eref
    integer :: i
    xr = abs(modulo(x0 + pi, 2*pi) - pi)
    msep = sin(xr/2)**2 + (v0/(2*w0))**2
    trot = 0
    if (msep >= 1) trot = (1 + log(msep))/gamma
    d0 = hypot(pi - xr, v0/w0)
    thang = 0
    if (msep < 1 .and. d0 < pi) thang = log(pi/max(d0, epsilon(1.0_wp)))/(hypot(gamma/2, w0) - gamma/2)
    a0 = min(xr + abs(v0)/w0, pi)
    if (msep >= 1) a0 = pi
    rate = slow_rate(w0, gamma)
    eref = linear_estimate(AREF, 0.0_wp, w0, gamma, span)
    if (.not. eref > 0) then
      ts = 0
      return
    end if
    ah = 0.8_wp*AREF*(0.25_wp*tol/eref)**(1.0_wp/3)
    ! near critical damping the two modes' rates meet and the decay is
    ! (1 + rate t) e^(-rate t) until t ~ 1/delta, delta the rates' gap
    ! (theta0 + t (Omega0 + gamma theta0/2) at gamma = 2 w0): a few fixed-
    ! point steps of rate t = L + ln(1 + min(rate t, rate/delta))
    el = max(0.0_wp, log(a0/ah))
    half = gamma/2
    cap = rate/max(sqrt(abs(half - w0))*sqrt(half + w0), tiny(1.0_wp))
    x = el
    do i = 1, 3
      x = el + log(1 + min(x, cap))
    end do
    ts = trot + thang + x/rate
    ts = max(ts, 1/max(w0, gamma))
  end function handover_time

  ! The integrator's name in a reason: 'RK4', 'CVODE' or 'Taylor'.
  pure function integrator_label(model) result(label)
    integer, intent(in) :: model
    character(len=6) :: label
    label = 'CVODE'
    if (model == SCENE_MODEL_RK4) label = 'RK4'
    if (model == SCENE_MODEL_TAYLOR) label = 'Taylor'
  end function integrator_label

end module pendula_scene_handover
