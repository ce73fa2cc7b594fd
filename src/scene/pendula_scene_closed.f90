!> The closed-form path of the scenes: small-angle, exact elliptic and linear
!> damped solutions evaluated at the outputs, their period and energy, and
!> their events (sign changes on a scan, refined to a few ulps of t).
module pendula_scene_closed
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_is_finite
  use pendula_kinds, only: wp, i8
  use pendula_status, only: status_t, check_alloc, PENDULA_OK
  use pendula_constants, only: pi
  use pendula_numeric, only: bracket_t, bracket_start, bracket_update, ROOT_ILLINOIS
  use pendula_undamped, only: undamped_motion_t, undamped_init, undamped_eval, pendulum_energy, &
                              undamped_plan_pays, undamped_add_plan, REGIME_SEPARATRIX
  use pendula_small_angle, only: small_angle_eval
  use pendula_linear_damped, only: linear_damped_t, linear_damped_init, linear_damped_state, &
                                   DAMPING_UNDERDAMPED
  use pendula_integrators, only: PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO
  use pendula_scene_codes, only: SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR, &
                                 SCENE_WANT_PERIOD, SCENE_WANT_ENERGY, SCENE_WANT_EVENTS
  use pendula_scene_types, only: scene_t, scene_result_t, window_end
  use pendula_scene_setup, only: alloc_outputs, finish_outputs, empty_outputs
  use pendula_scene_bounds, only: exact_time_error
  use pendula_scene_events, only: append_events, trim_events, event_time_error, sign_change, bottom_sign
  implicit none
  private

  public :: solve_closed

  real(wp), parameter :: eps = epsilon(1.0_wp)

  ! A closed form ready to evaluate.
  type :: closed_t
    integer :: model = SCENE_MODEL_EXACT
    type(undamped_motion_t) :: motion
    type(linear_damped_t) :: lin
    real(wp) :: w0 = 1, gamma = 0
  end type closed_t

contains

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
      ! the Jacobi plan only where its table pays for itself: near the
      ! separatrix it costs ~20x more than at small swings
      call undamped_init(cf%motion, scene%theta0, scene%omega0, scene%w0, status, plan=.false., w0lo=scene%w0lo)
      if (status%code == PENDULA_OK .and. model == SCENE_MODEL_EXACT) then
        if (undamped_plan_pays(cf%motion, closed_times(scene, cf%motion))) call undamped_add_plan(cf%motion)
      end if
    end if
  end subroutine closed_init

  ! How many times the closed form will be evaluated: the outputs, or for
  ! events the scan (16 per period) and each event's refinement (~20).
  pure integer function closed_times(scene, motion) result(n)
    type(scene_t), intent(in) :: scene
    type(undamped_motion_t), intent(in) :: motion
    real(wp) :: periods
    select case (scene%want)
    case (SCENE_WANT_EVENTS)
      periods = 1
      if (ieee_is_finite(motion%period) .and. motion%period > 0) periods = 1 + window_end(scene)/motion%period
      n = int(min(periods*(16 + 4*20), 1.0e9_wp))
    case (SCENE_WANT_PERIOD, SCENE_WANT_ENERGY)
      n = 0
    case default
      n = size(scene%t)
    end select
  end function closed_times

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

  !> Answer a checked scene with closed-form model (small_angle, exact or
  !> linear) whose a priori estimate is est [rad]: the wanted quantities,
  !> the estimate, and the closed-form evaluations in result%cost.
  subroutine solve_closed(scene, model, est, result, status)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    integer, intent(in) :: model  !< SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT or SCENE_MODEL_LINEAR
    real(wp), intent(in) :: est  !< the model's a priori error estimate [rad] (model_estimate), >= 0
    type(scene_result_t), intent(inout) :: result  !< gets the wanted quantities, the estimate and the cost
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    type(closed_t) :: cf
    integer :: ist
    call closed_init(scene, model, cf, status)
    if (status%code /= PENDULA_OK) return
    result%error_estimate = est
    select case (scene%want)
    case (SCENE_WANT_PERIOD)
      if (model == SCENE_MODEL_SMALL_ANGLE) then
        result%period = 2*pi/scene%w0
      else
        result%period = cf%motion%period
      end if
      call empty_outputs(result, status)
    case (SCENE_WANT_ENERGY)
      call alloc_outputs(scene, result, status)
      if (status%code /= PENDULA_OK) return
      if (model == SCENE_MODEL_EXACT) then
        ! conserved: the energy of the initial state, no time series
        result%theta = 0
        result%omega = 0
        result%energy = pendulum_energy(scene%theta0, scene%omega0, scene%w0)
        result%error_estimate = max(est, 4*eps*result%energy(1)/scene%w0**2)
        result%cost%closed_form_evals = 1
        deallocate (result%theta, result%omega)
        allocate (result%theta(0), result%omega(0), stat=ist)
        call check_alloc(ist, 'the (empty) outputs', 0_i8, 8, status)
        return
      end if
      call closed_eval(cf, result%t, result%theta, result%omega)
      result%cost%closed_form_evals = size(result%t)
      call finish_outputs(scene, result, status)
    case (SCENE_WANT_EVENTS)
      call closed_events(cf, window_end(scene), result, status)
      call empty_outputs(result, status)
      if (status%code /= PENDULA_OK) return
      ! (an infinite error from closed_events, a scan cut short, stays)
      result%event_time_error = max(result%event_time_error, event_time_error(result, est, scene%w0))
      ! the exact solution's events sit at known phases: their times are
      ! off by its phase error, also at a turning point at the top
      if (model == SCENE_MODEL_EXACT) result%event_time_error = min(result%event_time_error, &
                                                                    exact_time_error(cf%motion, window_end(scene)))
    case default
      call alloc_outputs(scene, result, status)
      if (status%code /= PENDULA_OK) return
      call closed_eval(cf, result%t, result%theta, result%omega)
      result%cost%closed_form_evals = size(result%t)
      call finish_outputs(scene, result, status)
    end select
  end subroutine solve_closed

  ! Event times from a closed form: scan (0, tend] at 16 samples per period
  ! (geometric steps for motions that do not oscillate), then refine each sign
  ! change of theta (zero crossing) or Omega (turning point) by the Illinois
  ! variant of regula falsi to a few ulps of t.  result%event_time_error is
  ! set to +inf when the scan had to stop early (0 otherwise, as on entry).
  subroutine closed_events(cf, tend, result, status)
    type(closed_t), intent(in) :: cf
    real(wp), intent(in) :: tend
    type(scene_result_t), intent(inout) :: result
    type(status_t), intent(inout) :: status
    real(wp) :: step, growth, stepmax, ta, tb, tha, oma, thb, omb, te(2), per
    integer :: kinds(2), ne, nev, ist
    integer(i8) :: nevals
    logical :: cut
    cut = .false.
    allocate (result%event_t(0), result%event_theta(0), result%event_omega(0), result%event_kind(0), stat=ist)
    call check_alloc(ist, 'the (empty) event lists', 0_i8, 8, status)
    if (status%code /= PENDULA_OK) return
    per = ieee_value(1.0_wp, ieee_positive_inf)
    select case (cf%model)
    case (SCENE_MODEL_SMALL_ANGLE)
      per = 2*pi/cf%w0
    case (SCENE_MODEL_EXACT)
      if (cf%motion%regime /= REGIME_SEPARATRIX) per = cf%motion%period
    case (SCENE_MODEL_LINEAR)
      if (cf%lin%info%regime == DAMPING_UNDERDAMPED) per = cf%lin%info%damped_period
    end select
    if (ieee_is_finite(per)) then
      step = per/16
      growth = 1
      stepmax = step
    else
      ! no oscillation: at most one root of each; resolve the fast time scale first
      step = 1/(8*max(cf%w0, cf%gamma))
      growth = 1.05_wp
      stepmax = max(tend/64, step)
    end if
    nevals = 1
    ta = 0
    call closed_eval(cf, ta, tha, oma)
    nev = 0
    do while (ta < tend)
      tb = min(tend, ta + step)
      call closed_eval(cf, tb, thb, omb)
      nevals = nevals + 1
      ! a damped motion decayed to subnormal size: its values are rounding
      ! (one flushed to 0 would count as an event), the scan stops there.  An
      ! over-damped or critical one has no events left (at most one of each
      ! kind, the last passed); an oscillating one has, uncounted: the event
      ! count is then unverified (an infinite time error)
      if (cf%model == SCENE_MODEL_LINEAR .and. max(abs(thb), abs(omb)/cf%w0) < tiny(1.0_wp)/eps) then
        if (ieee_is_finite(per)) cut = next_linear_event(tha, oma) <= tend - ta
        exit
      end if
      ne = 0
      if (sign_change(bottom_sign(tha), bottom_sign(thb))) then
        ne = ne + 1
        kinds(ne) = PENDULA_EVENT_ZERO
        te(ne) = refine(1, ta, tb, bottom_sign(tha), bottom_sign(thb))
      end if
      if (sign_change(oma, omb)) then
        ne = ne + 1
        kinds(ne) = PENDULA_EVENT_TURNING
        te(ne) = refine(2, ta, tb, oma, omb)
      end if
      if (ne > 0) call append_events(result, te(1:ne), kinds(1:ne), nev, status)
      if (status%code /= PENDULA_OK) return
      ta = tb
      tha = thb
      oma = omb
      step = min(stepmax, step*growth)
    end do
    call trim_events(result, nev, status)
    if (status%code /= PENDULA_OK) return
    call closed_eval(cf, result%event_t, result%event_theta, result%event_omega)
    result%cost%closed_form_evals = nevals + size(result%event_t)
    if (cut) result%event_time_error = ieee_value(1.0_wp, ieee_positive_inf)
  contains
    ! Under-damped linear motion from (x, v) at the last sample still of
    ! normal size: e^(a tau) theta = x cos(w_d tau) + c2 sin(w_d tau) and
    ! e^(a tau) Omega = v cos(w_d tau) + c3 sin(w_d tau) vanish at phases
    ! known in closed form, whatever the size, so the time [s] to the next
    ! event (zero crossing or turning point) is exact to rounding: when it lies
    ! past the window's end (a few ulps of margin) the count is verified.
    pure real(wp) function next_linear_event(x, v) result(tau)
      real(wp), intent(in) :: x, v
      real(wp) :: a, wd
      a = cf%gamma/2
      wd = cf%lin%info%omega_d
      tau = min(first_zero(x, (v + a*x)/wd), first_zero(v, -(cf%w0**2*x + a*v)/wd))/wd
      tau = tau*(1 - 64*eps)
    end function next_linear_event
    ! smallest phase p > 0 with c cos(p) + s sin(p) = 0 (c, s not both 0)
    pure real(wp) function first_zero(c, s) result(p)
      real(wp), intent(in) :: c, s
      p = modulo(atan2(s, c) + pi/2, pi)
      if (.not. p > 0) p = pi
    end function first_zero
    real(wp) function refine(which, a0, b0, fa0, fb0) result(r)
      integer, intent(in) :: which
      real(wp), intent(in) :: a0, b0, fa0, fb0
      real(wp) :: th, om
      type(bracket_t) :: br
      call bracket_start(br, a0, b0, fa0, fb0, ROOT_ILLINOIS, 200, 4*eps*tiny(1.0_wp), 4*eps)
      do while (.not. br%done)
        call closed_eval(cf, br%c, th, om)
        nevals = nevals + 1
        call bracket_update(br, merge(bottom_sign(th), om, which == 1))
      end do
      r = br%root
    end function refine
  end subroutine closed_events

end module pendula_scene_closed
