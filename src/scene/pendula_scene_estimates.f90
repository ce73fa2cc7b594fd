!> Model choice and error models of the scenes: the a priori error estimate
!> of each closed form over a window (small-angle bound, linear model's
!> nonlinearity, exact solution's rounding), the a priori RK4 step, the
!> rounding floor of an integration, and the choice of the cheapest model
!> whose estimate meets tol.
module pendula_scene_estimates
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_is_finite
  use pendula_kinds, only: wp
  use pendula_format, only: format_sci, format_int
  use pendula_status, only: status_t, set_error, PENDULA_OK, PENDULA_ERR_DOMAIN
  use pendula_constants, only: pi
  use pendula_elliptic, only: ellipkm1
  use pendula_undamped, only: undamped_motion_t, undamped_init, REGIME_LIBRATION, REGIME_SEPARATRIX
  use pendula_small_angle, only: small_angle_bound
  use pendula_linear_damped, only: linear_damped_t, linear_damped_init, linear_damped_state, &
                                   DAMPING_UNDERDAMPED
  use pendula_integrators, only: rk4_max_stable_step, cvode_available
  use pendula_taylor, only: taylor_step_tolerance
  use pendula_taylor_series, only: taylor_order
  use pendula_scene_codes, only: SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR, &
                                 SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_MODEL_TAYLOR, SCENE_WANT_PERIOD, SCENE_WANT_ENERGY, &
                                 SCENE_WANT_EVENTS, SCENE_RK4_STEP_LIMIT, SCENE_TAYLOR_STEP_COST, SCENE_CVODE_STEP_COST, &
                                 SCENE_STIFF_RK4_STEPS, SCENE_LINEAR_SAFETY, scene_want_name
  use pendula_scene_types, only: scene_t, window_end, is_stiff, swing
  use pendula_scene_setup, only: check_scene
  implicit none
  private

  public :: scene_estimate, model_estimate, choose_model, rk4_apriori_step, integrator_rounding, linear_estimate
  public :: cvode_min_steps, exact_time_error, slow_rate, linear_answers, integrator_rule, cvode_first_rtol
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

  ! Rounding of the energy per unit m l^2 of a state, divided by w0^2: each
  ! of the two terms Omega^2/2 and w0^2 (1 - cos theta) rounds by a few eps.
  pure real(wp) function energy_rounding(theta, omega, w0) result(e)
    real(wp), intent(in) :: theta, omega, w0
    e = 4*eps*((omega/w0)**2/2 + (1 - cos(theta)) + eps)
  end function energy_rounding

  ! Error of the small-angle period T0 = 2 pi/w0 as a phase w0 |T - T0| [rad],
  ! from the exact period (itself good to 16 eps (1 + |ln mc|) relative) and
  ! the rounding of 2 pi/w0 (a few eps).
  pure real(wp) function period_small_angle_error(motion) result(e)
    type(undamped_motion_t), intent(in) :: motion
    if (motion%regime /= REGIME_LIBRATION) then
      e = ieee_value(1.0_wp, ieee_positive_inf)
    else
      e = abs(motion%w0*motion%period - 2*pi) + 2*pi*eps*(20 + 16*abs(log(max(abs(motion%mc), &
                                                                              tiny(1.0_wp)))))
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
    real(wp) :: omax
    if (motion%m == 0) then
      e = 0
      return
    end if
    omax = 2*sqrt(motion%m)*motion%w0          ! max |Omega| (libration and rotation)
    e = 4*eps*(abs(motion%theta0) + 2*pi + omax/motion%w0) &
        + 4*omax*tend*frequency_error(motion)
    e = min(e, 2*(omax/motion%w0 + 2*pi))
  end function exact_estimate

  !> Error [s] of the event times of the exact elliptic solution over
  !> [0, tend]: the event times are where its phase w0 t + u0 takes known
  !> values (multiples of K), so they move by the phase error over w0, not
  !> by the state error over the speed (which vanishes at a turning point at
  !> the top, where a start at fl(pi) turns): the frequency error over the
  !> window (exact_estimate), the rounding of the initial phase u0 (a few eps
  !> of K, and eps pi/2 through F's slope 1/cos(theta_r/2) when a libration
  !> starts with Omega0 /= 0 near the top), the root finding (4 eps t), and
  !> the spacing of theta's doubles about a far centre 2 pi N over the speed
  !> at the bottom (a swing of 1e-7 rad about 4 pi: ~2e-8 s at w0 = 3).
  pure real(wp) function exact_time_error(motion, tend) result(dt)
    type(undamped_motion_t), intent(in) :: motion  !< the exact motion set up from the scene's initial state
    real(wp), intent(in) :: tend  !< end of the window [s], >= 0
    real(wp) :: du
    du = 8*eps*(1 + motion%rate*tend)
    if (motion%regime == REGIME_LIBRATION .and. motion%q /= 0) du = du + 2*eps/max(abs(motion%ch), eps)
    dt = du/motion%rate + 4*tend*frequency_error(motion) + 8*eps*tend
    ! a crossing is located on theta = center + theta_r, whose doubles are spaced
    ! ~eps |center| apart: that resolution over the speed at the bottom, 2 k w0
    dt = dt + 2*eps*abs(motion%center)/max(2*motion%k*motion%w0, tiny(1.0_wp))
  end function exact_time_error

  ! Relative error of the exact solution's frequency: the rounding of w0 t
  ! (eps) and the error delta_m of the energy parameter times |d ln T/d m|.
  ! pendula_undamped forms 1 - m as (c - q)(c + q) with c = cos(theta_r/2)
  ! and q carried to ~2 doubles, so mc is known to a few eps RELATIVE to
  ! itself plus what c and q carry absolutely: the double-double sum and
  ! cos_dd (~eps^2 c) and the reduction theta_r = theta0 - 2 pi N (2^-100
  ! |2 pi N|; ~1 ulp of pi beyond 2^40), each times c + |q|.  At a start
  ! fl(pi) c is pi_lo/2 ~ 6e-17 and mc ~ 4e-33 is still known to a few eps.
  pure real(wp) function frequency_error(motion) result(f)
    type(undamped_motion_t), intent(in) :: motion
    real(wp) :: dm, mc, dlnt, h, big, dr
    mc = motion%mc
    big = max(abs(motion%ch), abs(motion%q))
    dr = 2.0_wp**(-98)*abs(motion%center)
    if (abs(motion%theta0) > 2.0_wp**40) dr = 4*eps*pi
    dm = 4*eps*abs(mc) + 2*big*(8*eps**2*big + dr)
    if (motion%regime == REGIME_SEPARATRIX .or. mc == 0) then
      dlnt = 1/max(abs(mc), dm)
    else
      h = 1.0e-4_wp*abs(mc)
      dlnt = abs(log(turn_time(mc + h)/turn_time(mc - h)))/(2*h)
    end if
    f = eps + min(dlnt*dm, 1.0_wp)
  contains
    pure real(wp) function turn_time(c)
      real(wp), intent(in) :: c
      if (c > 0) then
        turn_time = 4*ellipkm1(c)
      else
        turn_time = 2*ellipkm1(-c/(1 - c))/sqrt(1 - c)
      end if
    end function turn_time
  end function frequency_error

  !> Nonlinearity error of the linear model theta'' + gamma theta' + w0^2 theta
  !> = 0 against eq. 2.2 over [0, tend], as sup max(|d theta|, |d Omega|/w0).
  !> Two estimates, the smaller is used (times SCENE_LINEAR_SAFETY), plus rounding:
  !>  (a) underdamped, phase drift: an oscillation of amplitude A is slower by
  !>      dw = w0^2 A^2/(16 w_d) (the pendulum's A^2/16 shift, eq. 1.53 expanded);
  !>      with A(t) = A0 e^(-gamma t/2) the phase lag is
  !>      phi(t) = w0^2 A0^2 (1 - e^(-gamma t))/(16 w_d gamma), so the error is
  !>      about A(t) min(2, phi(t)) (1 + gamma/(2 w0)) plus the harmonics A^3/16;
  !>      its sup over the window is taken in closed form (drift_sup);
  !>  (b) any regime, Green's function: the error d solves the linear equation
  !>      forced by w0^2 (theta - sin theta) <= w0^2 |theta|^3/6, so
  !>      |d| <= w0^2 B^3/6 int_0^tend |G|, B = max |theta_lin|, and the same with
  !>      |G'|/w0 for Omega; G(s) = e^(-gamma s/2) sin(w_d s)/w_d (sinh, s).
  !>      Over-damped or critical, B and max G are taken at their humps, whose
  !>      times are closed forms (hump_time).
  !> Cost: a few exp/log and at most two evaluations of the closed form, no
  !> sampling (the scenes call this several times per solve).
  !> steady (optional): a driven linear motion (pendula_scene_driven) is the
  !> free motion from (theta0, omega0) -- then the transient's start, the
  !> initial state minus the steady state's -- plus a steady oscillation of
  !> amplitude `steady` [rad]: B gets that amplitude added, and only (b) is
  !> used (the drive, not the amplitude, sets the steady state's frequency,
  !> so (a)'s phase drift does not describe it); the drive itself cancels
  !> from the error equation, which is (b)'s forced linear equation again.
  pure real(wp) function linear_estimate(theta0, omega0, w0, gamma, tend, steady) result(e)
    real(wp), intent(in) :: theta0  !< initial angle [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s], finite
    real(wp), intent(in) :: w0  !< natural frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    real(wp), intent(in) :: tend  !< end of the window [s], >= 0
    real(wp), intent(in), optional :: steady  !< amplitude of a steady driven oscillation added [rad], >= 0
    type(linear_damped_t) :: lin, gl
    type(status_t) :: st
    real(wp) :: bmax, ig, igp, eg, ep, wd, a, scale, round, gt, gpt, gmax, jmin, beta, d, th, om, t, amp
    amp = 0
    if (present(steady)) amp = steady
    call linear_damped_init(lin, theta0, omega0, w0, gamma, st)
    if (st%code /= PENDULA_OK) then
      e = ieee_value(1.0_wp, ieee_positive_inf)
      return
    end if
    scale = abs(theta0) + abs(omega0)/w0 + amp
    if (tend <= 0 .or. scale == 0) then
      e = 0
      return
    end if
    a = gamma/2
    if (lin%info%regime == DAMPING_UNDERDAMPED) then
      wd = lin%info%omega_d
      ! |theta| <= R e^(-a t) <= R, but R ~ 1/w_d blows up towards critical
      ! damping; with |sin(w_d t)/w_d| <= t also |theta| <= e^(-a t) (|theta0|
      ! + |Omega0 + a theta0| t) <= |theta0| + |Omega0 + a theta0| min(T, 1/(a e)),
      ! which is the critical-damping bound: the smaller keeps the estimate
      ! seamless across gamma = 2 w0
      if (a > 0) then
        bmax = min(lin%amplitude, abs(theta0) + abs(omega0 + a*theta0)*min(tend, 1/(a*exp(1.0_wp))))
      else   ! gamma = 0 (a driven scene only): no decay
        bmax = min(lin%amplitude, abs(theta0) + abs(omega0)*tend)
      end if
      ! |G(s)| <= e^(-a s) min(s, 1/w_d), |G'(s)| <= e^(-a s) (1 + a min(s, 1/w_d))
      jmin = min(int_exp_s(a, tend), int_exp(a, tend)/wd)
      ig = jmin
      igp = int_exp(a, tend) + a*jmin
      ep = ieee_value(1.0_wp, ieee_positive_inf)
      if (.not. present(steady)) ep = drift_sup(lin%amplitude, max(1.0_wp, (wd + a)/w0), (w0*lin%amplitude)**2/(16*wd))
    else
      ! over-damped or critical (beta = 0): Omega = e^(-a t) (Omega0 C - d S)
      ! with C = cosh(beta t), S = sinh(beta t)/beta, so theta has at most one
      ! hump, where tanh(beta t)/beta = Omega0/d; without one (or with one
      ! beyond the window) |theta| is largest at t = 0 or at tend
      beta = lin%info%beta
      d = w0*(w0*theta0) + a*omega0
      bmax = abs(theta0)
      if (omega0 /= 0 .and. (d > 0 .eqv. omega0 > 0) .and. beta*abs(omega0) < abs(d)) then
        t = tend    ! the hump lies beyond Omega0/d, so past tend when that is
        if (abs(omega0) < abs(d)*tend) &
          t = min(tend, hump_time(beta, abs(omega0), abs(d), abs(d) - beta*abs(omega0)))
        call linear_damped_state(lin, t, th, om)
        bmax = max(bmax, abs(th))
      end if
      ! G >= 0: int G = (1 - G'(T) - gamma G(T))/w0^2 from the equation itself;
      ! G' changes sign once, at the hump tanh(beta t)/beta = 1/a, where
      ! sinh(beta t) = beta/w0, so max G = e^(-a t)/w0 (or G(T) before it);
      ! int |G'| <= 2 max G.
      call linear_damped_init(gl, 0.0_wp, 1.0_wp, w0, gamma, st)   ! G: theta0 = 0, Omega0 = 1
      call linear_damped_state(gl, tend, gt, gpt)
      ig = max(0.0_wp, (1 - gpt - gamma*gt)/w0**2)
      t = hump_time(beta, 1.0_wp, a, lin%info%decay_slow)
      gmax = gt
      if (t < tend) gmax = max(gt, exp(-a*t)/w0)
      igp = 2*gmax
      ep = ieee_value(1.0_wp, ieee_positive_inf)
    end if
    ! (b) Green's function bound, any regime
    bmax = bmax + amp
    eg = w0**2*bmax**3/6*max(ig, igp/w0)
    round = 16*eps*scale*(1 + (w0 + gamma)*tend)
    e = SCENE_LINEAR_SAFETY*min(eg, ep) + round
  contains
    ! int_0^T e^(-a s) ds and int_0^T s e^(-a s) ds, without cancellation
    pure real(wp) function int_exp(a, t) result(r)
      real(wp), intent(in) :: a, t
      if (a*t < 1.0e-8_wp) then
        r = t
      else
        r = -expm1(-a*t)/a
      end if
    end function int_exp
    pure real(wp) function int_exp_s(a, t) result(r)
      real(wp), intent(in) :: a, t
      real(wp) :: x
      x = a*t
      if (x < 1.0e-3_wp) then
        r = t**2*(0.5_wp - x/3 + x**2/8)
      else
        r = (-expm1(-x) - x*exp(-x))/a**2
      end if
    end function int_exp_s
    ! sup over t in [0, tend] of the phase-drift error (a), the sup itself,
    ! not a sample of it, so that it bounds every t in the window.  In u =
    ! e^(-a t) (from 1 down to u_T) with phi = p (1 - u^2)/gamma (p = w0^2
    ! A0^2/(16 w_d)) it is f = A0 u c min(2, phi) + (A0 u)^3/16: where phi >= 2
    ! f grows with u, so that part peaks where phi reaches 2 (u^2 = 1 - 2
    ! gamma/p); where phi < 2 it is the cubic A0 c (p/gamma) u (1 - u^2) +
    ! (A0 u)^3/16, stationary only at u^2 = 1/(3 (1 - q)), q = A0^2 gamma/
    ! (16 c p).  The sup is the largest of f at u = 1, u_T and those two
    ! points where they lie in the window.  gamma = 0: u = 1, phi = p t grows.
    pure real(wp) function drift_sup(a0, c, p) result(f)
      real(wp), intent(in) :: a0  !< amplitude R of the linear motion [rad]
      real(wp), intent(in) :: c  !< factor max(1, (w_d + gamma/2)/w0) on the drift
      real(wp), intent(in) :: p  !< w0^2 A0^2/(16 w_d) [1/s]
      real(wp) :: phi, q, s
      if (.not. ieee_is_finite(a0) .or. .not. ieee_is_finite(p)) then
        f = ieee_value(1.0_wp, ieee_positive_inf)
        return
      end if
      f = a0**3/16                                         ! t = 0
      phi = p*int_exp(gamma, tend)                         ! t = tend
      f = max(f, drift(a0, c, exp(-a*tend), phi))
      if (phi > 2) f = max(f, drift(a0, c, sqrt(max(0.0_wp, 1 - 2*gamma/p)), 2.0_wp))
      if (3*a0**2*gamma < 32*c*p) then
        q = a0**2*gamma/(16*c*p)
        s = (2 - 3*q)/(3*(1 - q))                       ! 1 - u^2 at the stationary point
        if (s*p < 2*gamma .and. s <= -expm1(-gamma*tend)) &
          f = max(f, drift(a0, c, sqrt(1/(3*(1 - q))), s*p/gamma))
      end if
    end function drift_sup
    ! the phase-drift error at u = e^(-a t) with phase lag phi
    pure real(wp) function drift(a0, c, u, phi) result(y)
      real(wp), intent(in) :: a0, c, u, phi
      y = a0*u*min(2.0_wp, phi)*c + (a0*u)**3/16
    end function drift
    ! The t > 0 where w C(t) = v S(t), i.e. tanh(beta t)/beta = w/v (for
    ! 0 <= beta w < v): the hump of a motion whose velocity is e^(-a t) (w C -
    ! v S).  vm = v - beta w, from the caller without cancellation where it
    ! can.  atanh(x)/beta with x = beta w/v, by its series for small x (no 0/0
    ! at beta = 0, critical damping, where t = w/v: seamless across it).
    pure real(wp) function hump_time(beta, w, v, vm) result(t)
      real(wp), intent(in) :: beta, w, v, vm
      real(wp) :: x, x2
      x = beta*(w/v)
      if (x < 1.0e-3_wp) then
        x2 = x*x
        t = (w/v)*(1 + x2*(1.0_wp/3 + x2*(1.0_wp/5 + x2/7)))
      else
        t = 0.5_wp*(log(v + beta*w) - log(vm))/beta
      end if
    end function hump_time
  end function linear_estimate

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

  ! e^x - 1 without cancellation for small |x| (accurate to ~1e-11 relative,
  ! ample for error estimates).  Kept here, next to its only caller,
  ! linear_estimate (its integrals of e^(-a s) and the phase drift's window).
  elemental real(wp) function expm1(x) result(r)
    real(wp), intent(in) :: x
    if (abs(x) < 1.0e-5_wp) then
      r = x*(1 + x*(0.5_wp + x/6))
    else
      r = exp(x) - 1
    end if
  end function expm1

end module pendula_scene_estimates
