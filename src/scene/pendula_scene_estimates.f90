!> Model choice and error models of the scenes: the a priori error estimate
!> of each model over a window (the closed forms' bounds from
!> pendula_scene_bounds, the small-angle bound), the a priori RK4 step, the
!> rounding floor of an integration, and the choice of the cheapest model
!> whose estimate meets tol.
module pendula_scene_estimates
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_is_finite
  use pendula_kinds, only: wp
  use pendula_format, only: format_sci, format_int
  use pendula_status, only: status_t, set_error, PENDULA_OK, PENDULA_ERR_DOMAIN
  use pendula_constants, only: pi
  use pendula_undamped, only: undamped_motion_t, undamped_init
  use pendula_small_angle, only: small_angle_bound
  use pendula_linear_damped, only: DAMPING_UNDERDAMPED
  use pendula_integrators, only: rk4_max_stable_step, cvode_available
  use pendula_taylor, only: taylor_step_tolerance
  use pendula_taylor_series, only: taylor_order
  use pendula_scene_codes, only: SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR, &
                                 SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_MODEL_TAYLOR, SCENE_WANT_PERIOD, SCENE_WANT_ENERGY, &
                                 SCENE_WANT_EVENTS, SCENE_RK4_STEP_LIMIT, SCENE_TAYLOR_STEP_COST, SCENE_CVODE_STEP_COST, &
                                 SCENE_STIFF_RK4_STEPS, SCENE_LINEAR_SAFETY, scene_want_name
  use pendula_scene_types, only: scene_t, window_end, is_stiff, swing
  use pendula_scene_setup, only: check_scene
  use pendula_scene_bounds, only: energy_rounding, period_small_angle_error, exact_estimate, linear_estimate
  implicit none
  private

  public :: scene_estimate, model_estimate, choose_model, rk4_apriori_step, integrator_rounding
  public :: cvode_min_steps, slow_rate, linear_answers, integrator_rule, cvode_first_rtol
  public :: integrator_pick, taylor_steps

  real(wp), parameter :: eps = epsilon(1.0_wp)

contains

  !> A priori error estimate [rad] of a closed-form model over the scene's
  !> window (sup of max(|d theta|, |d Omega|/w0)): the small-angle bound, the
  !> linear model's nonlinearity estimate, or the exact solution's rounding
  !> estimate.  For rk4, cvode and taylor the value is scene%tol: their settings are
  !> chosen from it and verified a posteriori by scene_solve.  +inf where the
  !> model does not apply (small angle over the top, closed forms with the
  !> wrong gamma).
  pure subroutine scene_estimate(scene, model, estimate, status)
    type(scene_t), intent(in) :: scene  !< the scene (checked here)
    integer, intent(in) :: model  !< SCENE_MODEL_SMALL_ANGLE .. SCENE_MODEL_TAYLOR
    real(wp), intent(out) :: estimate  !< a priori error estimate [rad], >= 0; +inf where the model does not apply
    type(status_t), intent(out) :: status  !< PENDULA_OK, or the error code and a message naming the argument
    estimate = ieee_value(1.0_wp, ieee_positive_inf)
    call check_scene(scene, status)
    if (status%code /= PENDULA_OK) return
    call model_estimate(scene, model, estimate, status)
  end subroutine scene_estimate

  !> scene_estimate for a scene already checked (no second check).
  pure subroutine model_estimate(scene, model, estimate, status)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    integer, intent(in) :: model  !< SCENE_MODEL_SMALL_ANGLE .. SCENE_MODEL_TAYLOR
    real(wp), intent(out) :: estimate  !< a priori error estimate [rad], >= 0; +inf where the model does not apply
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    type(undamped_motion_t) :: motion
    real(wp) :: tend, dth, dom
    estimate = ieee_value(1.0_wp, ieee_positive_inf)
    tend = window_end(scene)
    select case (model)
    case (SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT)
      if (scene%gamma > 0) return
      ! a light motion: the estimates need its parameter and period, not a Jacobi plan
      call undamped_init(motion, scene%theta0, scene%omega0, scene%w0, status, plan=.false., w0lo=scene%w0lo)
      if (status%code /= PENDULA_OK) return
      if (model == SCENE_MODEL_SMALL_ANGLE) then
        call small_angle_bound(motion, tend, dth, dom)
        estimate = max(dth, dom/scene%w0)
        if (scene%want == SCENE_WANT_PERIOD) estimate = period_small_angle_error(motion)
      else if (scene%want == SCENE_WANT_ENERGY) then
        ! conserved: only the rounding of E = Omega0^2/2 + w0^2 (1 - cos theta0)
        ! (a few eps of its terms, scaled by w0^2), not the trajectory's error
        estimate = energy_rounding(scene%theta0, scene%omega0, scene%w0)
      else
        estimate = exact_estimate(motion, tend)
        ! the period's error as a phase w0 |dT| [rad] (as the small-angle
        ! period's): 16 eps (1 + |ln mc|) relative (K near the separatrix and
        ! the rounding of w0; the benchmark grid's periods are off by up to
        ! ~11 eps), times w0 T (an infinite period, the separatrix, is exact)
        if (scene%want == SCENE_WANT_PERIOD) then
          dth = 1
          if (ieee_is_finite(motion%period)) dth = max(1.0_wp, motion%w0*motion%period)
          estimate = 16*eps*(1 + abs(log(max(abs(motion%mc), tiny(1.0_wp)))))*dth
        end if
      end if
    case (SCENE_MODEL_LINEAR)
      estimate = linear_estimate(scene%theta0, scene%omega0, scene%w0, scene%gamma, tend)
    case (SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_MODEL_TAYLOR)
      estimate = scene%tol
    case default
      call set_error(status, PENDULA_ERR_DOMAIN, 'model = '//format_int(model)//' is unknown')
    end select
  end subroutine model_estimate

  !> The choice: cheapest model whose estimate meets tol (model, its
  !> estimate, and why in words).
  subroutine choose_model(scene, tend, model, est, why, status)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tend  !< end of the window [s], t(n) (window_end), >= 0
    integer, intent(out) :: model  !< the chosen model, SCENE_MODEL_SMALL_ANGLE .. SCENE_MODEL_TAYLOR
    real(wp), intent(out) :: est  !< its a priori error estimate [rad] (tol for rk4/cvode)
    character(len=:), allocatable, intent(out) :: why  !< the reason for the choice, in words
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    real(wp) :: e_sa, e_ex, e_ev, e_lin, hmax, nsteps, rk4_round
    type(status_t) :: st
    if (scene%gamma == 0) then
      call model_estimate(scene, SCENE_MODEL_SMALL_ANGLE, e_sa, status)
      call model_estimate(scene, SCENE_MODEL_EXACT, e_ex, status)
      if (status%code /= PENDULA_OK) return
      e_ev = small_angle_event_error(scene, e_sa)
      if (scene%want == SCENE_WANT_PERIOD .and. e_sa <= scene%tol) then
        model = SCENE_MODEL_SMALL_ANGLE
        est = e_sa
        why = 'gamma = 0, want = period and the small-angle period 2 pi/w0 is off by w0 |T - T0| = '// &
              format_sci(e_sa, 4)//' rad <= tol'
      else if (scene%want == SCENE_WANT_PERIOD .or. scene%want == SCENE_WANT_ENERGY) then
        ! K (or the conserved energy, one evaluation) comes with the motion's
        ! set-up: nothing cheaper exists.
        model = SCENE_MODEL_EXACT
        est = e_ex
        why = 'gamma = 0 and want = '//scene_want_name(scene%want)// &
              ': the exact value costs one set-up (K once), no time series'
      else if (e_sa <= scene%tol .and. e_ev > scene%tol) then
        ! an event's time is off by the state bound over the rate there (as
        ! pendula_scene_events measures it once the events are found)
        model = SCENE_MODEL_EXACT
        est = e_ex
        why = 'gamma = 0, want = events: the small-angle bound '//format_sci(e_sa, 4)// &
              ' rad moves its event times by ~'//format_sci(e_ev, 4)//' > tol: exact elliptic solution'
      else if (e_sa <= scene%tol) then
        model = SCENE_MODEL_SMALL_ANGLE
        est = e_sa
        why = 'gamma = 0 and the small-angle bound over the window, '//format_sci(e_sa, 4)// &
              ' rad, is <= tol'
      else
        model = SCENE_MODEL_EXACT
        est = e_ex
        why = 'gamma = 0 and the small-angle bound '//format_sci(e_sa, 4)//' rad exceeds tol: exact '// &
              'elliptic solution'
      end if
      return
    end if
    if (scene%want == SCENE_WANT_EVENTS .and. no_events(scene)) then
      model = SCENE_MODEL_LINEAR
      est = 0
      why = 'gamma >= 2 w0 and the start lies in the sector 0 <= -Omega sign(theta) <= lambda |theta|, '// &
            'which the pendulum never leaves: no event after t = 0 (the linear closed form, exact here)'
      return
    end if
    e_lin = linear_estimate(scene%theta0, scene%omega0, scene%w0, scene%gamma, tend)
    if (e_lin <= scene%tol) then
      model = SCENE_MODEL_LINEAR
      est = e_lin
      why = 'gamma > 0 and the nonlinearity estimate of the linear closed form over the window, '// &
            format_sci(e_lin, 4)//' rad, is <= tol'
      return
    end if
    est = scene%tol
    call rk4_max_stable_step(scene%w0, scene%gamma, hmax, st)
    nsteps = tend/min(0.9_wp*hmax, rk4_apriori_step(scene, tend))
    call integrator_pick(scene, tend, nsteps, scene%tol, model, rk4_round)
    if (model == SCENE_MODEL_TAYLOR) then
      why = 'gamma > 0, linear off by ~'//format_sci(e_lin, 2)//' rad; RK4 ~'//format_sci(nsteps, 2)// &
            ' steps (rounding ~'//format_sci(rk4_round, 2)//' rad), Taylor ~'// &
            format_sci(taylor_steps(scene, tend, scene%tol), 2)//': Taylor series'
    else if (model == SCENE_MODEL_CVODE) then
      why = 'gamma > 0, the linear model is off by ~'//format_sci(e_lin, 4)//' rad; RK4 would need ~'// &
            format_sci(nsteps, 4)//' steps (rounding ~'//format_sci(rk4_round, 4)//' rad): CVODE ('// &
            trim(merge('BDF  ', 'Adams', is_stiff(scene)))// &
            '), rtol from tol and the window, verified by a run 10x tighter'
    else
      why = 'gamma > 0, the linear model is off by ~'//format_sci(e_lin, 4)//' rad: RK4 with h from '// &
            'tol and the window (C h^4 T), verified by a run at 2h'
    end if
  end subroutine choose_model

  ! The event-time error the small-angle model will report for want = events
  ! (pendula_scene_events: the state bound e_sa over the rate at each event,
  ! w0 A at a zero crossing and w0 sin A at a turning point, A its
  ! amplitude): 0 for other wants or a window shorter than a quarter period
  ! (events are a quarter period apart, so a longer window holds one).
  pure real(wp) function small_angle_event_error(scene, e_sa) result(e)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: e_sa
    real(wp) :: a
    e = 0
    if (scene%want /= SCENE_WANT_EVENTS .or. window_end(scene) < 0.5_wp*pi/scene%w0) return
    a = hypot(scene%theta0, scene%omega0/scene%w0)
    e = e_sa/(scene%w0*max(min(a, sin(min(a, pi/2))), tiny(1.0_wp)))
  end function small_angle_event_error

  !> Whether choose_model answers a damped scene with the linear closed form
  !> (its nonlinearity estimate over the window meets tol, or want = events
  !> and no event can follow t = 0): the rule itself, for predictions.
  pure logical function linear_answers(scene, tend) result(yes)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene), gamma > 0
    real(wp), intent(in) :: tend  !< end of the window [s], t(n) (window_end), >= 0
    yes = scene%want == SCENE_WANT_EVENTS .and. no_events(scene)
    if (.not. yes) yes = linear_estimate(scene%theta0, scene%omega0, scene%w0, scene%gamma, tend) <= scene%tol
  end function linear_answers

  ! Whether the damped pendulum has no event (zero crossing, turning point)
  ! after t = 0, proved for gamma >= 2 w0 and a start (theta, Omega with
  ! |theta| < pi) in the sector 0 <= -Omega sign(theta) <=
  ! lambda |theta|, lambda = gamma/2 + sqrt(gamma^2/4 - w0^2) (a root of
  ! lambda^2 - gamma lambda + w0^2 = 0).  For theta > 0, f = Omega + lambda
  ! theta has f' = (gamma lambda - lambda^2) theta - w0^2 sin(theta) =
  ! w0^2 (theta - sin(theta)) >= 0 where f = 0, and Omega' = -w0^2
  ! sin(theta) < 0 where Omega = 0: the motion stays in the sector, so theta
  ! decreases for t > 0 (no turning point) and theta >= theta0 e^(-lambda t) >
  ! 0 (no crossing); the linear closed form (where f' = 0 on the edge) has
  ! no event either.  The sector's edge is kept 1e-12 inside for rounding.
  pure logical function no_events(scene)
    type(scene_t), intent(in) :: scene
    real(wp) :: x, half, lam
    no_events = .false.
    half = scene%gamma/2
    if (half < scene%w0) return
    ! about the bottom theta = 0 only: the linear closed form that answers
    ! (no event either) is the one about 0
    x = scene%theta0
    if (.not. abs(x) < pi) return
    lam = half + sqrt(half - scene%w0)*sqrt(half + scene%w0)
    no_events = scene%omega0*x <= 0 .and. abs(scene%omega0) <= lam*abs(x)*(1 - 1.0e-12_wp)
  end function no_events

  !> The integrator for an integrated span [0, span] of nsteps RK4 steps at
  !> tol: CVODE (when built) for a very long RK4 run, a stiff scene beyond a
  !> short one, or where RK4's rounding floor would eat tol; it grows like
  !> sqrt(steps) times max|theta|, and the unwrapped angle of a rotation grows
  !> only while the pendulum goes over the top: at most max|Omega| =
  !> sqrt(Omega0^2 + 4 w0^2) times the span, or the time damping needs to
  !> bring the energy E0 = m E_sep below the separatrix.  One rule for
  !> choose_model and for the work prediction (pendula_scene_work).
  pure subroutine integrator_rule(scene, span, nsteps, tol, use_cvode, rk4_round)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene), gamma > 0
    real(wp), intent(in) :: span  !< integrated span [s], >= 0
    real(wp), intent(in) :: nsteps  !< RK4 steps over it
    real(wp), intent(in) :: tol  !< tolerance of the integration [rad], > 0
    logical, intent(out) :: use_cvode  !< CVODE rather than RK4
    real(wp), intent(out) :: rk4_round  !< RK4's predicted rounding floor [rad]
    real(wp) :: big, msep
    big = abs(scene%theta0) + 2*pi
    msep = sin(scene%theta0/2)**2 + (scene%omega0/(2*scene%w0))**2
    if (msep >= 1) big = big + hypot(scene%omega0, 2*scene%w0)*min(span, 2*(1 + log(msep))/scene%gamma)
    rk4_round = integrator_rounding(scene, [big], nsteps)
    use_cvode = cvode_available() .and. (nsteps > SCENE_RK4_STEP_LIMIT .or. rk4_round > tol/4 .or. &
                                         (is_stiff(scene) .and. nsteps > SCENE_STIFF_RK4_STEPS))
  end subroutine integrator_rule

  !> The integrator for an integrated span [0, span] of nsteps RK4 steps at
  !> tol, by their predicted work [RK4 steps]: RK4 (a pair and a refinement,
  !> 2 nsteps) or CVODE as integrator_rule says, unless the Taylor series is
  !> cheaper (taylor_steps times SCENE_TAYLOR_STEP_COST) or the only one that
  !> can meet tol: RK4's rounding floor over tol/4 and CVODE's rtol below
  !> its floor 1e-14 (or CVODE not built).  A stiff scene keeps CVODE (BDF
  !> needs a few hundred steps whatever gamma; Taylor steps shrink as 1/gamma)
  !> unless it cannot meet tol.  One rule for choose_model and the work
  !> prediction (pendula_scene_work).
  pure subroutine integrator_pick(scene, span, nsteps, tol, model, rk4_round)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene), gamma > 0
    real(wp), intent(in) :: span  !< integrated span [s], >= 0
    real(wp), intent(in) :: nsteps  !< RK4 steps over it
    real(wp), intent(in) :: tol  !< tolerance of the integration [rad], > 0
    integer, intent(out) :: model  !< SCENE_MODEL_RK4, SCENE_MODEL_CVODE or SCENE_MODEL_TAYLOR
    real(wp), intent(out) :: rk4_round  !< RK4's predicted rounding floor [rad]
    logical :: use_cvode, floored
    real(wp) :: w_taylor, w_other, rtol, periods, scale
    call integrator_rule(scene, span, nsteps, tol, use_cvode, rk4_round)
    model = merge(SCENE_MODEL_CVODE, SCENE_MODEL_RK4, use_cvode)
    periods = 1 + scene%w0*span/(2*pi)
    scale = max(abs(scene%theta0) + abs(scene%omega0)/scene%w0, 1.0e-6_wp)
    floored = rk4_round > tol/4 .and. (.not. cvode_available() .or. 0.1_wp*tol/(periods*scale) < 1.0e-14_wp)
    w_taylor = SCENE_TAYLOR_STEP_COST*taylor_steps(scene, span, tol)
    if (use_cvode) then
      rtol = cvode_first_rtol(scene, span, tol)
      w_other = 3*SCENE_CVODE_STEP_COST*(cvode_min_steps(scene, span, rtol) + cvode_min_steps(scene, span, &
                                                                                              rtol/10))
      if (is_stiff(scene)) w_other = 0
    else
      w_other = 2*nsteps
    end if
    if (floored .or. w_taylor < w_other) model = SCENE_MODEL_TAYLOR
  end subroutine integrator_pick

  !> Predicted steps of the Taylor series (pendula_taylor) over [0, span] at
  !> tol, from how it sets order p and steps (taylor_order at
  !> taylor_step_tolerance; a step is at most 2/w0 and ends where the series'
  !> last terms reach the per-step tolerance):
  !>   1 + tau max(1/2, 2.3 (gamma/w0)/p) + max(0, s(m) - that) tau_osc,
  !> tau = w0 span.  1/2 a radian of w0 t is the longest step; 2.3 gamma/(w0 p)
  !> the series' limit set by the damping rate (its terms grow as
  !> gamma**j/j!: a BDF-like stiffness of the series); s(m) = 0.65 + 0.9
  !> min(1, 3 m) (0.65 + 0.9 sqrt(m) for a rotation, m > 1) the steps per
  !> radian of a swing at the motion's parameter m = sin^2(theta0/2) +
  !> (Omega0/(2 w0))^2, which last while it decays: tau_osc = tau_d (1 -
  !> exp(-tau/tau_d)), tau_d = 3 w0/gamma (tau when gamma = 0).  Measured
  !> against taylor_solve's steps over 200 random scenes (tol 1e-12 .. 1e-3,
  !> gamma/w0 0 .. 20, w0 t 3 .. 500, swings and rotations): median 0.98 of
  !> them, 80 % within 0.78 .. 1.09, all within 0.48 .. 1.7; the lowest are
  !> rounding-limited windows (tol ~1e-12 over hundreds of radians), where the
  !> integrator takes the short steps of a lower order (about twice as many).
  pure real(wp) function taylor_steps(scene, span, tol) result(n)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: span  !< integrated span [s], >= 0
    real(wp), intent(in) :: tol  !< tolerance of the run [rad], > 0
    real(wp) :: m, tau, ratio, e0, s_osc, base, tau_d, tau_osc
    integer :: p
    m = sin(scene%theta0/2)**2 + (scene%omega0/(2*scene%w0))**2
    tau = min(scene%w0*span, 1.0e150_wp)
    ratio = min(scene%gamma/scene%w0, 1.0e150_wp)
    e0 = 2*min(m, 1.0e150_wp)
    p = taylor_order(taylor_step_tolerance(min(tol, 1.0_wp), tau, ratio, e0), .false.)
    if (m <= 1) then
      s_osc = 0.65_wp + 0.9_wp*min(1.0_wp, 3*m)
    else
      s_osc = 0.65_wp + 0.9_wp*sqrt(min(m, 1.0e150_wp))
    end if
    base = max(0.5_wp, 2.3_wp*ratio/p)
    tau_osc = tau
    if (ratio > 0) then
      tau_d = 3/ratio
      tau_osc = tau_d*(1 - exp(-tau/tau_d))
    end if
    n = 1 + tau*base + max(0.0_wp, s_osc - base)*tau_osc
  end function taylor_steps

  !> CVODE's first rtol for tol over [0, tend]: a local tolerance is not a
  !> global error, so tol/10 over the periods in the window and the state's
  !> scale |theta0| + |Omega0|/w0 (at least 1e-14).
  pure real(wp) function cvode_first_rtol(scene, tend, tol) result(rtol)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tend  !< end of the integrated span [s], >= 0
    real(wp), intent(in) :: tol  !< tolerance [rad], > 0
    real(wp) :: periods, scale
    periods = 1 + scene%w0*tend/(2*pi)
    scale = max(abs(scene%theta0) + abs(scene%omega0)/scene%w0, 1.0e-6_wp)
    rtol = max(0.1_wp*tol/(periods*scale), 1.0e-14_wp)
  end function cvode_first_rtol

  !> A priori RK4 step for the window: global error ~ C A (w0 h)^4 w0 T_eff
  !> with C = 1/120 for the harmonic oscillator (the phase error of one step is
  !> (w0 h)^5/120), doubled for the nonlinear pendulum.  With damping the error
  !> is the amplitude A e^(-slow t) times a phase error growing like t, which
  !> peaks at t = 1/slow: T_eff is the window or 2/slow.  A is
  !> the swing |theta0 mod 2 pi| + |Omega0|/w0 (capped at 2 pi), not |theta0|.  The
  !> a posteriori check (run at 2h) catches what this misjudges.
  pure real(wp) function rk4_apriori_step(scene, tend) result(h)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tend  !< end of the window [s], > 0
    real(wp) :: a, teff, c, slow
    ! the motion's size, not the raw angle: theta0 + 2 pi k is the same motion
    a = swing(scene)
    a = min(max(a, 1.0e-3_wp), 2*pi)
    teff = tend
    if (scene%gamma > 0) then
      slow = slow_rate(scene%w0, scene%gamma)
      ! the phase error accumulates for ever, but it moves theta by the
      ! amplitude times it: A0 e^(-slow t) t peaks at t = 1/slow (value
      ! A0/(e slow)); 2/slow leaves room for the slower decay of a large swing
      teff = min(tend, 2/slow)
    end if
    c = 2.0_wp/120
    h = (scene%tol/(c*a*max(scene%w0*teff, 1.0_wp)))**0.25_wp/scene%w0
    h = min(h, 0.5_wp/scene%w0)
  end function rk4_apriori_step

  !> Decay rate [1/s] of the slowest mode of the linear damped equation:
  !> gamma/2 up to critical damping, then w0^2/(gamma/2 + sqrt(gamma^2/4 - w0^2))
  !> (the smaller root, without cancellation).
  pure real(wp) function slow_rate(w0, gamma) result(rate)
    real(wp), intent(in) :: w0  !< natural frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    real(wp) :: half
    half = gamma/2
    if (half > w0) then
      rate = w0**2/(half + sqrt(half - w0)*sqrt(half + w0))
    else
      rate = half
    end if
  end function slow_rate

  !> Lower bound on the steps of one CVODE (Adams) run of an underdamped,
  !> non-stiff scene over [0, tend] at rtol (atol = rtol/100 times the state's
  !> size, as pendula_scene_integrated sets it), for refusing work beyond the
  !> budget up front.  Adams takes at least 4 steps per small-angle period
  !> 2 pi/w0 however decayed the motion, and while a swing is resolved to rtol
  !> (until its amplitude has decayed to ~sqrt(rtol) of its start, t = ln(1/rtol)/gamma)
  !> at least 12 (1e-3/rtol)^(1/12) (measured, rtol 1e-3 .. 1e-14, swings from
  !> 1e-3 rad to pi - 1e-6 and gamma/w0 from 1e-6 to 1.9: 20 .. 270 steps per
  !> period, never below this bound).  A start within 1e4 rtol of the top is
  !> not resolved at all (CVODE may stay there: no bound), and a rotation only
  !> by the first part.  0 for stiff or over-damped scenes (BDF, few steps).
  pure real(wp) function cvode_min_steps(scene, tend, rtol) result(n)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tend  !< end of the window [s], >= 0
    real(wp), intent(in) :: rtol  !< CVODE relative tolerance of the run, > 0
    real(wp) :: xr, d0, msep, per, tres
    n = 0
    if (is_stiff(scene) .or. scene%gamma >= 2*scene%w0 .or. .not. rtol > 0) return
    xr = abs(modulo(scene%theta0 + pi, 2*pi) - pi)
    d0 = hypot(pi - xr, scene%omega0/scene%w0)
    if (d0 < 1.0e4_wp*rtol) return
    per = scene%w0/(2*pi)
    n = 4*per*tend
    msep = sin(scene%theta0/2)**2 + (scene%omega0/(2*scene%w0))**2
    if (msep >= 1) return
    tres = tend
    if (scene%gamma > 0) tres = min(tend, log(1/min(rtol, 0.5_wp))/scene%gamma)
    n = n + max(0.0_wp, 12*(1.0e-3_wp/rtol)**(1.0_wp/12) - 4)*per*tres
  end function cvode_min_steps

  !> Rounding floor of an integration that the comparison of two runs cannot
  !> see: each of n steps rounds theta by ~eps |theta|, a random walk ~ sqrt(n)
  !> while it swings, a biased sum ~ n for the unwrapped angle of a rotation
  !> (max|theta| beyond 2 pi); and a start near the unstable
  !> equilibrium (pi, 0) amplifies any perturbation by ~1/d0 while the
  !> pendulum hangs there (growth e^(w0 t) until it leaves, t ~ ln(1/d0)/w0),
  !> d0 the distance of the initial state from the top in (theta, Omega/w0).
  !> The near-top term's factor 16: RK4 runs in double against the same runs
  !> in 80-bit long double (so the difference is rounding only) from d0 = 1e-2
  !> to 1e-7, gamma/w0 = 0.05 to 1, h w0 = 2e-3 and 5e-3, over 15/w0 lost up to
  !> 3.6x what 4 eps pi/d0 (with the swing term) predicted.
  pure real(wp) function integrator_rounding(scene, theta, nsteps) result(r)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: theta(:)  !< angles [rad] of the run (for its largest |theta|); may be empty
    real(wp), intent(in) :: nsteps  !< number of steps of the run (values below 1 count as 1)
    real(wp) :: big, d0, xr, swing
    swing = abs(scene%theta0) + abs(scene%omega0)/scene%w0 + 2*pi   ! size of a swing
    big = swing
    if (size(theta) > 0) big = max(big, maxval(abs(theta)))
    xr = abs(modulo(scene%theta0 + pi, 2*pi) - pi)          ! |theta0| reduced to [0, pi]
    d0 = hypot(pi - xr, scene%omega0/scene%w0)
    ! a rotation's unwrapped angle (beyond a swing) grows steadily: adding nearly
    ! equal increments to it rounds with a bias, so that part grows like n
    r = 4*eps*swing*sqrt(max(nsteps, 1.0_wp)) &
        + eps*(big - swing)*max(nsteps, 1.0_wp)/2 + 16*eps*pi/max(d0, eps)
  end function integrator_rounding

end module pendula_scene_estimates
