!> Driven scenes: a scene with a drive (pendula_drive) of nonzero amplitude,
!>   theta'' + gamma theta' + w0^2 sin(theta) = F cos(Omega t + phi)   (torque), or
!>   theta'' + gamma theta' + (w0^2 + (a/l) Omega^2 cos(Omega t + phi)) sin(theta) = 0   (pivot),
!> answered by the cheapest of two models whose estimate meets tol:
!>  * linear (torque drive): the linearised driven damped oscillator in closed
!>    form (pendula_driven_linear: transient plus steady state), its error of
!>    dropping sin(theta) - theta bounded as the undriven linear model's is
!>    (linear_estimate of pendula_scene_estimates, Green's-function bound over
!>    the motion's amplitude: transient plus steady amplitude, one home);
!>  * rk4: the driven RK4 kernel (pendula_driven, an integer number N of
!>    steps per drive period, the drive phase exact at every step), N from
!>    tol and the window, verified by a run at N/2 (Richardson, as the
!>    undriven scene's RK4: twice the difference / 15) and refined until the
!>    estimate (plus the rounding floor, integrator_rounding) meets tol.
!> CVODE and the Taylor series take no drive here.  want = period and
!> want = events are refused with a drive (pendula_scene_setup,
!> check_scene_drive): the driven kernel samples the output times only.
!> A drive of amplitude 0 never reaches this module: the scene is the
!> undriven one (has_drive).
module pendula_scene_driven
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf
  use pendula_kinds, only: wp, i8
  use pendula_constants, only: pi
  use pendula_format, only: format_sci, format_int
  use pendula_status, only: status_t, set_error, check_alloc, check_positive, PENDULA_OK, PENDULA_ERR_MAXSTEPS, &
                            PENDULA_ERR_DOMAIN
  use pendula_control, only: CONTROL_SIZE
  use pendula_drive, only: DRIVE_TORQUE, DRIVE_PIVOT, drive_period, check_driven, DRIVEN_MIN_STEPS, DRIVEN_MAX_STEPS
  use pendula_driven, only: driven_batch_solve
  use pendula_driven_linear, only: driven_linear_response, driven_linear_solve
  use pendula_scene_codes, only: SCENE_MODEL_AUTO, SCENE_MODEL_LINEAR, SCENE_MODEL_RK4, SCENE_WANT_FINAL
  use pendula_scene_types, only: scene_t, scene_result_t, window_end, swing
  use pendula_scene_setup, only: alloc_outputs, finish_outputs, check_driven_model
  use pendula_scene_estimates, only: integrator_rounding, slow_rate
  use pendula_scene_bounds, only: linear_estimate
  implicit none
  private

  public :: driven_model_estimate, driven_linear_estimate, driven_scene_solve, driven_scene_run, driven_work

  !> Refinements of the steps per drive period before giving up on tol.
  integer, parameter :: MAX_REFINE = 5
  real(wp), parameter :: eps = epsilon(1.0_wp)

contains

  !> A priori error estimate [rad] of `model` for a driven scene (sup of
  !> max(|d theta|, |d Omega|/w0) over the window): the linear model's
  !> nonlinearity bound (driven_linear_estimate), tol for rk4 (its steps are
  !> chosen from tol and verified), +inf for a model that does not apply.
  pure subroutine driven_model_estimate(scene, model, estimate, status)
    type(scene_t), intent(in) :: scene  !< the scene, checked, with a drive (has_drive)
    integer, intent(in) :: model  !< SCENE_MODEL_SMALL_ANGLE .. SCENE_MODEL_TAYLOR
    real(wp), intent(out) :: estimate  !< a priori error estimate [rad], >= 0; +inf where the model does not apply
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    estimate = ieee_value(1.0_wp, ieee_positive_inf)
    if (status%code /= PENDULA_OK) return
    if (model == SCENE_MODEL_LINEAR) estimate = driven_linear_estimate(scene, window_end(scene))
    if (model == SCENE_MODEL_RK4) estimate = scene%tol
  end subroutine driven_model_estimate

  !> Nonlinearity error [rad] of the linearised driven oscillator over
  !> [0, tend] (sup of max(|d theta|, |d Omega|/w0)): linear_estimate's
  !> Green's-function bound with the transient's start (theta0, Omega0) minus
  !> the steady state's and the steady amplitude |F| gain added to the
  !> motion's size.  +inf for a pivot drive (no closed form) or the undamped
  !> resonance (no bounded steady state).
  pure real(wp) function driven_linear_estimate(scene, tend) result(e)
    type(scene_t), intent(in) :: scene  !< the scene, checked, with a drive (has_drive)
    real(wp), intent(in) :: tend  !< end of the window [s], >= 0
    real(wp) :: a, ys, us
    logical :: ok
    e = ieee_value(1.0_wp, ieee_positive_inf)
    call steady_state(scene, a, ys, us, ok)
    if (.not. ok) return
    e = linear_estimate(scene%theta0 - ys, scene%omega0 - us, scene%w0, scene%gamma, tend, steady=a)
  end function driven_linear_estimate

  ! The steady state of the linearised torque drive at t = 0: amplitude
  ! a = |F| gain [rad], theta ys and Omega us; ok false for a pivot drive or
  ! the undamped resonance.
  pure subroutine steady_state(scene, a, ys, us, ok)
    type(scene_t), intent(in) :: scene
    real(wp), intent(out) :: a, ys, us
    logical, intent(out) :: ok
    real(wp) :: gain, lag
    a = 0
    ys = 0
    us = 0
    ok = scene%drive%kind == DRIVE_TORQUE
    ! the undamped resonance: no bounded steady state (and no 1/0 to trap on)
    if (scene%gamma == 0 .and. scene%drive%frequency == scene%w0) ok = .false.
    if (.not. ok) return
    call driven_linear_response(scene%w0, scene%gamma, scene%drive%frequency, gain, lag)
    ok = gain <= huge(gain)
    if (.not. ok) return
    ys = scene%drive%amplitude*gain*cos(scene%drive%phase - lag)
    us = -scene%drive%amplitude*gain*scene%drive%frequency*sin(scene%drive%phase - lag)
    a = abs(scene%drive%amplitude)*gain
  end subroutine steady_state

  !> Answer a driven scene (has_drive): the linear closed form when its
  !> estimate meets tol (torque drive), else the driven RK4 kernel with a
  !> Richardson check (or scene%model when forced: linear or rk4).  Sets
  !> result%model, %reason, %error_estimate, %tol_met and the outputs.
  subroutine driven_scene_solve(scene, budget, result, status, control)
    type(scene_t), intent(in) :: scene  !< the scene, checked (check_scene), with a drive
    real(wp), intent(in) :: budget  !< work budget [RK4 steps]
    type(scene_result_t), intent(inout) :: result  !< gets the answer
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag, progress (pendula_control)
    real(wp) :: e_lin, tend
    character(len=:), allocatable :: why
    integer :: model
    if (status%code /= PENDULA_OK) return
    tend = window_end(scene)
    e_lin = driven_linear_estimate(scene, tend)
    model = scene%model
    if (model == SCENE_MODEL_AUTO) then
      if (e_lin <= scene%tol) then
        model = SCENE_MODEL_LINEAR
        why = 'driven, and the nonlinearity estimate of the linearised driven oscillator (closed form: '// &
              'transient + steady state) over the window, '//format_sci(e_lin, 4)//' rad, is <= tol'
      else
        model = SCENE_MODEL_RK4
        if (scene%drive%kind == DRIVE_TORQUE .and. .not. e_lin <= huge(e_lin)) then
          why = 'driven at the undamped resonance (no bounded steady state, no closed form): the driven '// &
                'RK4 kernel, N steps per drive period from tol, verified by a run at N/2'
        else if (scene%drive%kind == DRIVE_TORQUE) then
          why = 'driven, the linearised driven oscillator is off by ~'//format_sci(e_lin, 4)// &
                ' rad: the driven RK4 kernel, N steps per drive period from tol, verified by a run at N/2'
        else
          why = 'driven by the pivot (no closed form): the driven RK4 kernel, N steps per drive period '// &
                'from tol, verified by a run at N/2'
        end if
      end if
    else
      why = 'forced by the caller (driven)'
    end if
    if (model == SCENE_MODEL_LINEAR) then
      call solve_driven_linear(scene, e_lin, result, status)
    else
      call solve_driven_rk4(scene, tend, budget, 0, result, status, control)
    end if
    if (status%code /= PENDULA_OK) return
    result%model = model
    result%tol_met = result%error_estimate <= scene%tol
    if (.not. result%tol_met) why = 'tol NOT met, error estimate '//format_sci(result%error_estimate, 4)// &
                                    ' > tol: '//why
    result%reason = why
  end subroutine driven_scene_solve

  !> Run one model on a driven scene at a fixed setting, no choice and no
  !> verification: linear (its a priori estimate) or rk4 at step `setting`
  !> [s], rounded down to an integer number of steps per drive period (error
  !> estimate 0: unknown).  Other models are errors (check_driven_model).
  subroutine driven_scene_run(scene, model, setting, budget, result, status, control)
    type(scene_t), intent(in) :: scene  !< the scene, checked (check_scene), with a drive
    integer, intent(in) :: model  !< SCENE_MODEL_LINEAR or SCENE_MODEL_RK4
    real(wp), intent(in) :: setting  !< RK4 step h [s], > 0 (ignored for linear)
    real(wp), intent(in) :: budget  !< work budget [RK4 steps]
    type(scene_result_t), intent(inout) :: result  !< gets the answer
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag, progress (pendula_control)
    real(wp) :: tend, nper
    type(status_t) :: st
    call check_driven_model(model, scene%drive, status)
    if (status%code /= PENDULA_OK) return
    tend = window_end(scene)
    if (model == SCENE_MODEL_LINEAR) then
      call solve_driven_linear(scene, driven_linear_estimate(scene, tend), result, status)
      result%reason = 'forced by the caller: the linearised driven oscillator (closed form)'
    else
      call check_positive('setting', setting, status)
      if (status%code /= PENDULA_OK) return
      nper = drive_period(scene%drive)/setting
      if (.not. nper <= DRIVEN_MAX_STEPS) then
        call set_error(status, PENDULA_ERR_DOMAIN, 'setting = '//format_sci(setting, 4)//' is too small: '// &
                       'the driven RK4 kernel takes at most '//format_int(DRIVEN_MAX_STEPS)//' steps per drive period '// &
                       format_sci(drive_period(scene%drive), 4)//' s')
        return
      end if
      call check_driven(scene%w0, scene%gamma, scene%drive, max(DRIVEN_MIN_STEPS, ceiling(nper)), st)
      if (st%code /= PENDULA_OK) then
        call set_error(status, st%code, 'setting = '//format_sci(setting, 4)//' is too large, '// &
                       trim(st%message)//' (steps per drive period: ceiling(period/setting))')
        return
      end if
      call solve_driven_rk4(scene, tend, budget, max(DRIVEN_MIN_STEPS, ceiling(nper)), result, status, control)
      result%reason = 'forced by the caller at a fixed setting (driven RK4, no verification)'
    end if
    if (status%code /= PENDULA_OK) return
    result%model = model
    result%tol_met = result%error_estimate <= scene%tol
  end subroutine driven_scene_run

  ! The linearised driven oscillator at the outputs (every t, or t(n) for
  ! want = final), with the a priori estimate est.
  subroutine solve_driven_linear(scene, est, result, status)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: est
    type(scene_result_t), intent(inout) :: result
    type(status_t), intent(inout) :: status
    type(status_t) :: st
    call alloc_outputs(scene, result, status)
    if (status%code /= PENDULA_OK) return
    call driven_linear_solve(result%t, scene%theta0, scene%omega0, scene%w0, scene%gamma, scene%drive, &
                             result%theta, result%omega, st)
    if (st%code /= PENDULA_OK) then
      status = st
      return
    end if
    result%error_estimate = est
    result%cost%closed_form_evals = size(result%t)
    call finish_outputs(scene, result, status)
  end subroutine solve_driven_linear

  ! A priori steps per drive period for tol: RK4's global error ~ C A (w h)^4 w T_eff
  ! (as rk4_apriori_step of pendula_scene_estimates, C = 2/120) with w the
  ! fastest of w0, Omega and the pivot's rate, A the swing plus F/w^2 (capped
  ! at 2 pi), at least what check_driven asks for stability (h rate <= 1.5).
  pure integer function apriori_steps(scene, tend) result(n)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tend
    real(wp) :: w, a, h, per, rate, teff
    w = max(scene%w0, scene%drive%frequency)
    rate = scene%w0**2
    if (scene%drive%kind == DRIVE_PIVOT) rate = rate + abs(scene%drive%amplitude)*scene%drive%frequency**2
    rate = max(sqrt(rate), scene%gamma)
    w = max(w, rate)
    a = swing(scene)
    if (scene%drive%kind == DRIVE_TORQUE) a = a + abs(scene%drive%amplitude)/w**2
    a = min(max(a, 1.0e-3_wp), 2*pi)
    ! with damping the error of a step decays with the motion's memory of it: as
    ! rk4_apriori_step, the window counts up to 2/slow_rate (a chaotic orbit that
    ! keeps amplifying it is caught by the check and refined)
    teff = tend
    if (scene%gamma > 0) teff = min(tend, 2/slow_rate(scene%w0, scene%gamma))
    h = (scene%tol/(2.0_wp/120*a*max(w*teff, 1.0_wp)))**0.25_wp/w
    per = drive_period(scene%drive)
    ! the coarse run of the pair takes n/2: it too must be within the kernel's limits
    n = int(min(real(DRIVEN_MAX_STEPS, wp), max(2.0_wp*DRIVEN_MIN_STEPS, per/h, 2*(per*rate/1.5_wp + 1))))
  end function apriori_steps

  ! The driven RK4 kernel over [0, tend] at the outputs.  fixed > 0: one run
  ! at fixed steps per period, estimate 0 (unknown); fixed = 0: a pair of
  ! runs at N/2 and N steps per period (N even, from tol: apriori_steps),
  ! the finer one returned with the scene's Richardson estimate of it, twice
  ! the difference over the output grid / 15 (as pendula_scene_integrated's
  ! RK4: the factor 2 covers what the asymptotic 1/15 misjudges, e.g. the
  ! growth of errors on a chaotic orbit), plus the rounding floor
  ! (integrator_rounding); N raised until the estimate meets tol (at most
  ! MAX_REFINE pairs, within the budget).
  subroutine solve_driven_rk4(scene, tend, budget, fixed, result, status, control)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: tend, budget
    integer, intent(in) :: fixed
    type(scene_result_t), intent(inout) :: result
    type(status_t), intent(inout) :: status
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    real(wp), allocatable :: tg(:), th(:, :), om(:, :), th2(:, :), om2(:, :)
    real(wp) :: per, grid, used, est, r, d
    integer :: m, off, it, ist, codes(1), nsteps
    call alloc_outputs(scene, result, status)
    if (status%code /= PENDULA_OK) return
    m = size(result%t)
    ! the kernel starts at its first time: t = 0 first unless it is an output
    off = 1
    if (m > 0) then
      if (result%t(1) == 0) off = 0
    end if
    allocate (tg(m + off), th(m + off, 1), om(m + off, 1), th2(m + off, 1), om2(m + off, 1), stat=ist)
    call check_alloc(ist, 'the driven runs'' times and states', 5_i8*(m + off), 8, status)
    if (status%code /= PENDULA_OK) return
    if (off == 1) tg(1) = 0
    tg(off + 1:) = result%t
    per = drive_period(scene%drive)
    nsteps = fixed
    if (fixed == 0) nsteps = 2*((apriori_steps(scene, tend) + 1)/2)
    used = 0
    est = ieee_value(1.0_wp, ieee_positive_inf)
    do it = 1, merge(1, MAX_REFINE, fixed > 0)
      grid = tend/per*nsteps*merge(1.0_wp, 1.5_wp, fixed > 0)   ! the pair: N/2 and N steps per period
      if (grid > budget - used) then
        if (it > 1) exit
        call set_error(status, PENDULA_ERR_MAXSTEPS, 'the driven RK4 kernel needs ~'//format_sci(grid, 4)// &
                       ' steps over t = 0 .. '//format_sci(tend, 4)//' ('//format_int(nsteps)// &
                       ' per drive period), more than max_steps = '//format_sci(budget, 4)// &
                       ': shorten the window, loosen tol or raise max_steps')
        return
      end if
      call run(nsteps, th, om)
      if (fixed == 0) call run(nsteps/2, th2, om2)
      if (status%code /= PENDULA_OK) return
      used = used + grid
      result%cost%steps = result%cost%steps + int(grid, i8)
      result%cost%rhs_evals = 4*result%cost%steps
      result%cost%runs = result%cost%runs + merge(1, 2, fixed > 0)
      result%theta = th(off + 1:, 1)
      result%omega = om(off + 1:, 1)
      result%step = per/nsteps
      result%setting = result%step
      if (fixed > 0) then
        est = 0
        exit
      end if
      d = max(maxval(abs(th(:, 1) - th2(:, 1))), maxval(abs(om(:, 1) - om2(:, 1)))/scene%w0)
      est = 2*d/15 + integrator_rounding(scene, th(:, 1), tend/per*nsteps)
      if (est <= scene%tol .or. nsteps >= DRIVEN_MAX_STEPS) exit
      r = min(8.0_wp, max(1.25_wp, 1.1_wp*(est/scene%tol)**0.25_wp))
      nsteps = 2*int(min(real(DRIVEN_MAX_STEPS/2, wp), nsteps*r/2))
    end do
    result%error_estimate = est
    call finish_outputs(scene, result, status)
  contains
    subroutine run(n, x, v)
      integer, intent(in) :: n
      real(wp), intent(out) :: x(:, :), v(:, :)
      type(status_t) :: st
      call driven_batch_solve(tg, [scene%theta0], [scene%omega0], [scene%w0], [scene%gamma], scene%drive%kind, &
                              [scene%drive%amplitude], [scene%drive%frequency], [scene%drive%phase], n, x, v, codes, &
                              st, threads=1, control=control)
      ! the batch's 'state 1 of 1 (1 failed, see codes): ' prefix is noise for one scene
      if (index(st%message, 'state 1 of 1 ') == 1) st%message = st%message(index(st%message, ': ') + 2:)
      if (st%code /= PENDULA_OK .and. status%code == PENDULA_OK) status = st
    end subroutine run
  end subroutine solve_driven_rk4

  !> Predicted work [RK4 steps] of a driven scene's solve (model AUTO or
  !> forced) or fixed-setting run (fixed, model and setting as for
  !> scene_run_model): the closed form's evaluations, or the driven RK4
  !> runs (N/2 and N, 1.5 N steps per drive period; N at setting when fixed).
  !> A prediction to decide how to run the call.
  pure real(wp) function driven_work(scene, model, fixed, setting) result(work)
    type(scene_t), intent(in) :: scene  !< the scene, checked, with a drive (has_drive)
    integer, intent(in) :: model  !< the model (AUTO: the choice)
    logical, intent(in) :: fixed  !< a fixed-setting run (scene_run_model)
    real(wp), intent(in) :: setting  !< RK4 step h [s] of a fixed run
    real(wp) :: tend, per
    integer :: m
    tend = window_end(scene)
    per = drive_period(scene%drive)
    m = model
    if (m == SCENE_MODEL_AUTO) m = merge(SCENE_MODEL_LINEAR, SCENE_MODEL_RK4, &
                                         driven_linear_estimate(scene, tend) <= scene%tol)
    work = 0.1_wp*size(scene%t)
    if (scene%want == SCENE_WANT_FINAL) work = 0.1_wp
    if (m /= SCENE_MODEL_RK4) return
    if (fixed) then
      if (.not. (setting > 0 .and. setting <= huge(1.0_wp))) return
      work = work + tend/per*max(real(DRIVEN_MIN_STEPS, wp), per/setting)
    else
      work = work + 1.5_wp*tend/per*apriori_steps(scene, tend)
    end if
  end function driven_work

end module pendula_scene_driven
