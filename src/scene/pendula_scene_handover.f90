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
module pendula_scene_handover
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_sci
  use pendula_status, only: status_t, PENDULA_OK
  use pendula_constants, only: pi
  use pendula_linear_damped, only: linear_damped_t, linear_damped_init, linear_damped_state
  use pendula_control, only: CONTROL_SIZE
  use pendula_scene_codes, only: SCENE_MODEL_AUTO, SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_WANT_STATE, &
      SCENE_WANT_THETA, SCENE_WANT_FINAL, SCENE_WANT_ENERGY
  use pendula_scene_types, only: scene_t, scene_result_t, scene_cost_t
  use pendula_scene_setup, only: alloc_outputs, finish_outputs
  use pendula_scene_estimates, only: choose_model, linear_estimate
  use pendula_scene_integrated, only: solve_rk4, solve_cvode
  implicit none
  private

  public :: solve_integrated, add_cost, decay_time, slow_rate, MAX_PART, SUB_TOL_REL, AREF

  !> A hand-over is tried only when it spares at least this part of the window.
  real(wp), parameter :: MAX_PART = 0.75_wp
  !> Hand-over points tried before integrating the whole window.
  integer, parameter :: MAX_TRIES = 3
  !> Loosest tolerance of the integrated part, relative to the motion's size
  !> (the swing modulo 2 pi, at most pi), when the carried error decays
  !> before the first output: the integrators' a posteriori estimates
  !> (Richardson, two CVODE tolerances) assume errors well below the motion.
  real(wp), parameter :: SUB_TOL_REL = 1.0e-2_wp
  !> Swing [rad] whose linear-model nonlinearity decay_time scales from.
  real(wp), parameter :: AREF = 0.1_wp

contains

  !> Answer a checked, damped or undamped scene with the integrator `model`
  !> (RK4 or CVODE), handing over to the linear closed form once the motion
  !> has decayed enough (gamma > 0; want state, theta, final or energy).  why:
  !> the reason so far; the hand-over, when made, is appended.
  subroutine solve_integrated(scene, model, tend, budget, why, result, status, control)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    integer, intent(in) :: model  !< SCENE_MODEL_RK4 or SCENE_MODEL_CVODE
    real(wp), intent(in) :: tend  !< end of the window [s], t(n) (window_end), >= 0
    real(wp), intent(in) :: budget  !< work budget [RK4 steps] (a CVODE step costs SCENE_CVODE_STEP_COST)
    character(len=:), allocatable, intent(inout) :: why  !< the reason so far; the hand-over is appended
    type(scene_result_t), intent(inout) :: result  !< gets the answer, its error estimate and cost
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag, progress (pendula_control)
    type(scene_t) :: sub
    type(scene_result_t) :: part, fresh
    type(scene_cost_t) :: spent
    real(wp) :: ts, xs, vs, e1, elin, est, center, gain, swing
    integer :: it, k, sub_model
    if (scene%gamma > 0 .and. (scene%want == SCENE_WANT_STATE .or. scene%want == SCENE_WANT_THETA .or. &
        scene%want == SCENE_WANT_FINAL .or. scene%want == SCENE_WANT_ENERGY)) then
      ts = handover_time(scene%theta0, scene%omega0, scene%w0, scene%gamma, scene%tol, tend)
      swing = min(abs(modulo(scene%theta0 + pi, 2 * pi) - pi) + abs(scene%omega0) / scene%w0, pi)
      do it = 1, MAX_TRIES
        if (.not. ts < MAX_PART * tend) exit
        call sub_scene(scene, ts, sub, k)
        gain = carry_gain(scene, ts, k)
        if (k == 0) sub%tol = max(sub%tol, min(sub%tol / max(gain, tiny(1.0_wp)), SUB_TOL_REL * swing))
        part = fresh
        sub_model = model
        if (scene%model == SCENE_MODEL_AUTO) call pick_integrator(sub, ts, model, sub_model, status)
        if (status%code /= PENDULA_OK) return
        call run(sub, sub_model, ts, part)
        if (status%code /= PENDULA_OK) return
        call add_cost(spent, part%cost)
        ! the linear model about the equilibrium the motion has settled to,
        ! 2 pi k (to its rounding, eps |2 pi k|, added to its estimate)
        center = 2 * pi * anint(part%theta(size(part%theta)) / (2 * pi))
        xs = part%theta(size(part%theta)) - center
        vs = part%omega(size(part%omega))
        e1 = part%error_estimate
        elin = linear_estimate(xs, vs, scene%w0, scene%gamma, tend - ts) + 2 * epsilon(1.0_wp) * abs(center)
        ! e1 bounds the outputs before ts too (when there are any)
        est = elin + gain * e1
        if (k > 0) est = max(e1, est)
        if (est <= scene%tol) then
          call assemble(scene, part, k, ts, center, xs, vs, est, result)
          call add_cost(spent, result%cost)
          result%cost = spent
          result%setting = part%setting
          result%step = part%step
          result%rtol = part%rtol
          why = why // '; the motion has decayed by t = ' // format_sci(ts, 4) // ' s: ' // &
              trim(merge('RK4  ', 'CVODE', sub_model == SCENE_MODEL_RK4)) // ' up to there, then the linear ' // &
              'closed form from that state (nonlinearity ~' // format_sci(elin, 4) // ' rad, carried error ~' // &
              format_sci(gain * e1, 4) // ' rad)'
          return
        end if
        if (elin <= scene%tol / 4) exit   ! the integrator's part is what fails: no later ts helps
        ts = ts + max(0.5_wp * ts, handover_time(xs, vs, scene%w0, scene%gamma, scene%tol, tend - ts))
      end do
    end if
    call run(scene, model, tend, result)
    call add_cost(result%cost, spent)
  contains
    subroutine run(sc, mdl, t_end, res)
      type(scene_t), intent(in) :: sc
      integer, intent(in) :: mdl
      real(wp), intent(in) :: t_end
      type(scene_result_t), intent(inout) :: res
      if (mdl == SCENE_MODEL_RK4) then
        call solve_rk4(sc, t_end, budget, res, status, control)
      else
        call solve_cvode(sc, t_end, budget, res, status, control)
      end if
    end subroutine run
  end subroutine solve_integrated

  ! The first part of the scene: the outputs before ts, then ts itself (or
  ! ts alone for want = final), at tol/2; k of the scene's outputs lie before ts.
  pure subroutine sub_scene(scene, ts, sub, k)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: ts
    type(scene_t), intent(out) :: sub
    integer, intent(out) :: k
    sub = scene
    sub%tol = scene%tol / 2
    k = count(scene%t < ts)
    if (scene%want == SCENE_WANT_FINAL) k = 0
    sub%t = [scene%t(1:k), ts]
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
    type(linear_damped_t) :: ua, ub
    type(status_t) :: st
    real(wp), allocatable :: tau(:), xa(:), va(:), xb(:), vb(:)
    integer :: n
    n = size(scene%t)
    if (scene%want == SCENE_WANT_FINAL) then
      tau = [scene%t(n) - ts]
    else
      tau = scene%t(k+1:n) - ts
    end if
    allocate (xa(size(tau)), va(size(tau)), xb(size(tau)), vb(size(tau)))
    call linear_damped_init(ua, 1.0_wp, 0.0_wp, scene%w0, scene%gamma, st)
    call linear_damped_init(ub, 0.0_wp, scene%w0, scene%w0, scene%gamma, st)
    call linear_damped_state(ua, tau, xa, va)
    call linear_damped_state(ub, tau, xb, vb)
    gain = 0
    if (size(tau) > 0) gain = max(maxval(abs(xa) + abs(xb)), maxval(abs(va) + abs(vb)) / scene%w0)
    ! a few ulps of the evaluation
    gain = min(sqrt(2.0_wp), gain * (1 + 64 * epsilon(1.0_wp)))
  end function carry_gain

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
    if (sub_model /= SCENE_MODEL_RK4 .and. sub_model /= SCENE_MODEL_CVODE) sub_model = model
  end subroutine pick_integrator

  ! The answer from the integrated part (outputs 1..k, state at ts last) and
  ! the linear closed form about center from (center + xs, vs) at ts for the
  ! outputs after it.
  pure subroutine assemble(scene, part, k, ts, center, xs, vs, est, result)
    type(scene_t), intent(in) :: scene
    type(scene_result_t), intent(in) :: part
    integer, intent(in) :: k
    real(wp), intent(in) :: ts, center, xs, vs, est
    type(scene_result_t), intent(inout) :: result
    type(linear_damped_t) :: lin
    type(status_t) :: st
    integer :: n
    call alloc_outputs(scene, result)
    n = size(result%t)
    result%theta(1:k) = part%theta(1:k)
    result%omega(1:k) = part%omega(1:k)
    call linear_damped_init(lin, xs, vs, scene%w0, scene%gamma, st)
    call linear_damped_state(lin, result%t(k+1:n) - ts, result%theta(k+1:n), result%omega(k+1:n))
    result%theta(k+1:n) = result%theta(k+1:n) + center
    result%cost%closed_form_evals = n - k
    result%error_estimate = est
    call finish_outputs(scene, result)
  end subroutine assemble

  pure subroutine add_cost(total, c)
    type(scene_cost_t), intent(inout) :: total  !< cost added to
    type(scene_cost_t), intent(in) :: c  !< cost to add (wall_time is not added)
    total%closed_form_evals = total%closed_form_evals + c%closed_form_evals
    total%rhs_evals = total%rhs_evals + c%rhs_evals
    total%steps = total%steps + c%steps
    total%runs = total%runs + c%runs
  end subroutine add_cost

  ! Predicted time [s] after which the linear model's nonlinearity over the
  ! rest of a window of length span fits tol/4, for a motion from (x0, v0)
  ! (decay_time, with the nonlinearity of a swing AREF over span from
  ! linear_estimate).  A prediction only: the integrated state at that time decides.
  pure real(wp) function handover_time(x0, v0, w0, gamma, tol, span) result(ts)
    real(wp), intent(in) :: x0, v0, w0, gamma, tol, span
    ts = decay_time(x0, v0, w0, gamma, tol, linear_estimate(AREF, 0.0_wp, w0, gamma, span))
  end function handover_time

  !> Predicted time [s] after which the linear model's nonlinearity, eref [rad]
  !> for a swing of AREF [rad] and growing like the swing cubed, fits tol/4,
  !> for a motion from (x0, v0): a rotation first loses its excess energy (m
  !> decays at least like e^(-gamma t) while it goes over the top), a start at
  !> distance d0 from the top first hangs there for ~ln(pi/d0)/lambda (lambda
  !> = sqrt(gamma^2/4 + w0^2) - gamma/2, the growth rate of the linearization
  !> about the top: without it a start 1e-6 rad below the top was predicted to
  !> have decayed while still up, and every try failed), then the swing A
  !> decays at the slowest rate of the linear modes (slow_rate) down to the
  !> amplitude A_h where the nonlinearity is tol/4.  0 when eref is not > 0.
  pure real(wp) function decay_time(x0, v0, w0, gamma, tol, eref) result(ts)
    real(wp), intent(in) :: x0  !< initial angle [rad]
    real(wp), intent(in) :: v0  !< initial angular velocity [rad/s]
    real(wp), intent(in) :: w0  !< natural frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], > 0
    real(wp), intent(in) :: tol  !< tolerance [rad], > 0
    real(wp), intent(in) :: eref  !< the linear model's nonlinearity [rad] for a swing of AREF (0.1 rad) over the rest of the window
    real(wp) :: xr, msep, a0, ah, trot, thang, d0
    xr = abs(modulo(x0 + pi, 2 * pi) - pi)
    msep = sin(xr / 2)**2 + (v0 / (2 * w0))**2
    trot = 0
    if (msep >= 1) trot = (1 + log(msep)) / gamma
    d0 = hypot(pi - xr, v0 / w0)
    thang = 0
    if (msep < 1 .and. d0 < pi) thang = log(pi / max(d0, epsilon(1.0_wp))) / (hypot(gamma / 2, w0) - gamma / 2)
    a0 = min(xr + abs(v0) / w0, pi)
    if (msep >= 1) a0 = pi
    if (.not. eref > 0) then
      ts = 0
      return
    end if
    ah = 0.8_wp * AREF * (0.25_wp * tol / eref)**(1.0_wp / 3)
    ts = trot + thang + max(0.0_wp, log(a0 / ah)) / slow_rate(w0, gamma)
    ts = max(ts, 1 / max(w0, gamma))
  end function decay_time

  !> Decay rate [1/s] of the slowest mode of the linear damped equation:
  !> gamma/2 up to critical damping, w0^2/(gamma/2 + sqrt(gamma^2/4 - w0^2))
  !> (the slow real root, without cancellation) beyond.
  pure real(wp) function slow_rate(w0, gamma) result(rate)
    real(wp), intent(in) :: w0  !< natural frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    real(wp) :: half
    half = gamma / 2
    if (half > w0) then
      rate = w0**2 / (half + sqrt(half - w0) * sqrt(half + w0))
    else
      rate = half
    end if
  end function slow_rate

end module pendula_scene_handover
