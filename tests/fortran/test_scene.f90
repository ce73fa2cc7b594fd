!> Scenes concern: the model choice, its estimates against independent
!> references (the small-angle formula itself, energy conservation, K from
!> pendula_elliptic, a converged Richardson-extrapolated RK4), the wants, and
!> bad input.  The 240-scene honesty grid is in tests/python/test_scene.py.
program test_scene
  use pendula
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use pendula_testing, only: checker_t
  implicit none
  type(checker_t) :: tc
  type(scene_t) :: sc
  type(scene_result_t) :: res, res2
  type(status_t) :: st
  real(wp) :: w0, wx, gamma, tt(41), ref_th(41), ref_om(41), err, e0, kk, per
  real(wp), allocatable :: tz(:)
  integer :: i, nz
  ! the linear model's estimate at the ends of its ranges: theta0, Omega0/w0,
  ! gamma/w0 (critical, just off it, heavy, vanishing) and w0 tend (to 1e12)
  real(wp), parameter :: LIN_CASES(4, 10) = reshape([ &
                                                  1.0e-3_wp, 0.0_wp, 2.0_wp, 10.0_wp, 0.3_wp, -0.5_wp, 2.000000000002_wp, 10.0_wp, &
                                                    0.5_wp, -0.4_wp, 1.999999_wp, 7.0_wp, 0.3_wp, 0.0_wp, 2.0e8_wp, 10.0_wp, &
                                                    0.0_wp, 50.0_wp, 2.0e8_wp, 1.0e-6_wp, 0.2_wp, 0.1_wp, 1.0e-300_wp, 1.0e6_wp, &
                                                    0.2_wp, 0.1_wp, 1.0e-3_wp, 1.0e12_wp, 1.0e-300_wp, 0.0_wp, 0.5_wp, 100.0_wp, &
                                                    3.0_wp, 40.0_wp, 0.5_wp, 10.0_wp, 0.2_wp, -3.0_wp, 5.0_wp, 50.0_wp], [4, 10])

  w0 = sqrt(2.0_wp)
  tt = [(i*0.5_wp, i=0, 40)]

  ! --- small angle where it meets tol: the formula itself, no integrator
  call scene_init(sc, 1.0e-3_wp, 0.0_wp, tt, w0, 0.0_wp, 1.0e-6_wp, SCENE_WANT_STATE, st)
  call scene_solve(sc, res, st)
  call tc%check_true(status_ok(st), 'small-angle scene solves')
  call tc%check_true(res%model == SCENE_MODEL_SMALL_ANGLE, 'small angle chosen: '//trim(res%reason))
  call tc%check_true(res%cost%rhs_evals == 0 .and. res%cost%runs == 0, 'no integrator for small angle')
  call tc%check_true(res%tol_met .and. res%error_estimate <= 1.0e-6_wp, 'small-angle estimate <= tol')
  call tc%check_close(maxval(abs(res%theta - 1.0e-3_wp*cos(w0*tt))), 0.0_wp, 0.0_wp, 1.0e-15_wp, &
                      'small angle is theta0 cos(w0 t)')

  ! --- exact where small angle is not enough: energy conserved, no integrator
  call scene_init(sc, 2.0_wp, 0.3_wp, tt, w0, 0.0_wp, 1.0e-10_wp, SCENE_WANT_STATE, st)
  call scene_solve(sc, res, st)
  call tc%check_true(res%model == SCENE_MODEL_EXACT .and. res%cost%rhs_evals == 0, 'exact chosen')
  e0 = 0.5_wp*0.3_wp**2 + w0**2*(1 - cos(2.0_wp))
  err = maxval(abs(0.5_wp*res%omega**2 + w0**2*(1 - cos(res%theta)) - e0))
  call tc%check_close(err, 0.0_wp, 0.0_wp, 1.0e-13_wp, 'exact: energy conserved')
  call tc%check_true(res%error_estimate <= 1.0e-10_wp, 'exact: estimate <= tol')

  ! --- period: K once, no time series
  call scene_init(sc, 1.0_wp, 0.0_wp, [real(wp) ::], w0, 0.0_wp, 1.0e-12_wp, SCENE_WANT_PERIOD, st)
  call tc%check_true(status_ok(st), 'period scene needs no times')
  call scene_solve(sc, res, st)
  kk = ellipk(sin(0.5_wp)**2)
  call tc%check_ulps(res%period, 4*kk/w0, 4.0_wp, 'period = 4 K(sin^2(theta0/2))/w0 (eq. 1.53)')
  call tc%check_true(res%cost%closed_form_evals == 0 .and. size(res%theta) == 0, 'period: no time series')

  ! --- linear damped closed form where the nonlinearity estimate fits
  call scene_init(sc, 1.0e-3_wp, 0.0_wp, tt, w0, 0.3_wp, 1.0e-8_wp, SCENE_WANT_STATE, st)
  call scene_solve(sc, res, st)
  call tc%check_true(res%model == SCENE_MODEL_LINEAR .and. res%cost%rhs_evals == 0, 'linear chosen: '// &
                     trim(res%reason))
  call reference(1.0e-3_wp, 0.0_wp, 0.3_wp, ref_th, ref_om)
  err = max(maxval(abs(res%theta - ref_th)), maxval(abs(res%omega - ref_om))/w0)
  call tc%check_true(err <= res%error_estimate .and. res%error_estimate <= 1.0e-8_wp, &
                     'linear: true error <= estimate <= tol')

  ! --- the text's scenario (b = 0.01 kg/s, m = 0.1 kg): an integrator, verified
  call scene_physics(9.8_wp, 4.9_wp, w0, gamma, st, mass=0.1_wp, b=0.01_wp)
  call tc%check_ulps(gamma, 0.1_wp, 1.0_wp, 'gamma = b/m')
  call scene_init(sc, 0.0_wp, 2.0_wp, tt, w0, gamma, 1.0e-7_wp, SCENE_WANT_STATE, st)
  call scene_solve(sc, res, st)
  call tc%check_true(status_ok(st), 'text scene solves: '//trim(st%message))
  call tc%check_true(res%model == SCENE_MODEL_RK4 .or. res%model == SCENE_MODEL_CVODE .or. &
                     res%model == SCENE_MODEL_TAYLOR, 'integrator chosen: '//trim(res%reason))
  ! RK4 and CVODE verify by a second run; the Taylor series carries its own estimate
  call tc%check_true(res%cost%rhs_evals > 0 .and. (res%cost%runs >= 2 .or. (res%model == SCENE_MODEL_TAYLOR &
                                        .and. res%error_estimate <= 1.0e-7_wp)), 'verified by a second run, or the Taylor estimate')
  call reference(0.0_wp, 2.0_wp, gamma, ref_th, ref_om)
  err = max(maxval(abs(res%theta - ref_th)), maxval(abs(res%omega - ref_om))/w0)
  call tc%check_true(err <= 1.0e-7_wp, 'text scene: true error <= tol')

  ! --- final state only: same answer as the last point of the series
  call scene_init(sc, 0.0_wp, 2.0_wp, tt, w0, gamma, 1.0e-7_wp, SCENE_WANT_FINAL, st)
  call scene_solve(sc, res2, st)
  call tc%check_true(size(res2%theta) == 1, 'final: one output')
  call tc%check_close(res2%theta(1), ref_th(41), 0.0_wp, 1.0e-7_wp, 'final theta')

  ! --- events of the undamped libration from rest: zero crossings at T/4 + k T/2
  per = 4*ellipk(sin(0.75_wp)**2)/w0
  call scene_init(sc, 1.5_wp, 0.0_wp, [4.01_wp*per], w0, 0.0_wp, 1.0e-10_wp, SCENE_WANT_EVENTS, st)
  call scene_solve(sc, res, st)
  tz = pack(res%event_t, res%event_kind == PENDULA_EVENT_ZERO)
  nz = size(tz)
  call tc%check_true(nz == 8, 'eight zero crossings in four periods')
  if (nz == 8) call tc%check_close(maxval(abs(tz - [(per/4 + i*per/2, i=0, 7)])), 0.0_wp, 0.0_wp, &
                                   1.0e-9_wp*per, 'zero crossings at T/4 + k T/2')
  call tc%check_true(count(res%event_kind == PENDULA_EVENT_TURNING) == 8, 'eight turning points')
  deallocate (tz)   ! main-program allocatables are never freed at exit: keep memcheck clean

  ! --- forced models and names
  call scene_init(sc, 0.3_wp, 0.0_wp, tt, w0, 0.0_wp, 1.0e-9_wp, SCENE_WANT_STATE, st, model=SCENE_MODEL_RK4)
  call scene_solve(sc, res, st)
  call tc%check_true(res%model == SCENE_MODEL_RK4 .and. index(res%reason, 'forced') == 1, 'rk4 forced')
  call scene_init(sc, 0.3_wp, 0.0_wp, tt, w0, 0.0_wp, 1.0e-9_wp, SCENE_WANT_STATE, st)
  call scene_solve(sc, res2, st)
  err = max(maxval(abs(res%theta - res2%theta)), maxval(abs(res%omega - res2%omega))/w0)
  call tc%check_true(err <= 1.0e-9_wp, 'forced rk4 agrees with the exact choice')
  call tc%check_true(scene_model_code('cvode') == SCENE_MODEL_CVODE .and. scene_model_code('rk5') == -1, &
                     'model names')
  call tc%check_true(scene_want_code('events') == SCENE_WANT_EVENTS .and. scene_want_code('x') == -1, &
                     'want names')
  call scene_init(sc, 0.3_wp, 0.0_wp, tt, w0, 0.1_wp, 1.0e-9_wp, SCENE_WANT_STATE, st, model=SCENE_MODEL_CVODE)
  call scene_solve(sc, res, st)
  if (cvode_available()) then
    call tc%check_true(status_ok(st) .and. res%model == SCENE_MODEL_CVODE, 'cvode forced')
  else
    call tc%check_true(st%code == PENDULA_ERR_UNAVAILABLE, 'cvode forced without SUNDIALS: unavailable')
  end if

  ! --- the linear model's estimate at the ends of its ranges: a number >= 0
  ! (the checked build traps overflow and 0/0 on the way), and a longer
  ! window never lowers it (it is a sup over the window)
  do i = 1, size(LIN_CASES, 2)
    call scene_init(sc, LIN_CASES(1, i), LIN_CASES(2, i)*w0, [LIN_CASES(4, i)/w0], w0, LIN_CASES(3, i)*w0, &
                    1.0e-6_wp, SCENE_WANT_STATE, st)
    call scene_estimate(sc, SCENE_MODEL_LINEAR, e0, st)
    call scene_init(sc, LIN_CASES(1, i), LIN_CASES(2, i)*w0, [2*LIN_CASES(4, i)/w0], w0, &
                    LIN_CASES(3, i)*w0, 1.0e-6_wp, SCENE_WANT_STATE, st)
    call scene_estimate(sc, SCENE_MODEL_LINEAR, err, st)
    call tc%check_true(status_ok(st) .and. ieee_is_finite(e0) .and. e0 >= 0 .and. e0 <= err*(1 + 1.0e-12_wp), &
                       'linear estimate at an extreme: finite, >= 0, not lowered by a longer window')
  end do

  ! --- bad input: a status naming the argument
  call scene_physics(9.8_wp, 4.9_wp, wx, gamma, st, gamma_in=0.2_wp, mass=0.1_wp, b=0.01_wp)
  call tc%check_true(st%code == PENDULA_ERR_DOMAIN .and. index(st%message, 'disagree') > 0, &
                     'gamma and b/mass disagree: '//trim(st%message))
  call scene_physics(9.8_wp, 4.9_wp, wx, gamma, st, mass=0.1_wp)
  call tc%check_true(index(st%message, 'mass is given without b') == 1, 'mass without b')
  call scene_physics(9.8_wp, 4.9_wp, wx, gamma, st, b=0.1_wp)
  call tc%check_true(index(st%message, 'b is given without mass') == 1, 'b without mass')
  call scene_physics(9.8_wp, -1.0_wp, wx, gamma, st)
  call tc%check_true(index(st%message, 'length =') == 1, 'length <= 0: '//trim(st%message))
  call scene_init(sc, 0.3_wp, 0.0_wp, tt, w0, 0.0_wp, 0.0_wp, SCENE_WANT_STATE, st)
  call tc%check_true(index(st%message, 'tol =') == 1, 'tol = 0 rejected: '//trim(st%message))
  call scene_init(sc, 0.3_wp, 0.0_wp, tt, w0, 0.0_wp, 1.0e-6_wp, 9, st)
  call tc%check_true(index(st%message, 'want =') == 1, 'unknown want')
  call scene_init(sc, 0.3_wp, 0.0_wp, tt, w0, 0.0_wp, 1.0e-6_wp, 1, st, model=7)
  call tc%check_true(index(st%message, 'model =') == 1, 'unknown model')
  call scene_init(sc, 0.3_wp, 0.0_wp, tt, w0, 0.1_wp, 1.0e-6_wp, 1, st, model=SCENE_MODEL_EXACT)
  call tc%check_true(index(st%message, 'needs gamma = 0') > 0, 'exact with gamma > 0 rejected')
  call scene_init(sc, 0.3_wp, 0.0_wp, [-1.0_wp, 1.0_wp], w0, 0.0_wp, 1.0e-6_wp, 1, st)
  call tc%check_true(index(st%message, 't[0]') == 1, 'negative time rejected: '//trim(st%message))
  call scene_init(sc, 0.3_wp, 0.0_wp, [1.0_wp], w0, 0.1_wp, 1.0e-6_wp, SCENE_WANT_PERIOD, st)
  call tc%check_true(index(st%message, 'period needs gamma = 0') > 0, 'period of a damped scene rejected')
  call scene_solve(scene_t(), res, st)
  call tc%check_true(st%code == PENDULA_ERR_SIZE, 'an unbuilt scene is rejected, not a crash')

  ! --- driven scenes: the linearised driven oscillator for a small drive of a
  ! small swing (against driven_linear_solve itself), the driven RK4 kernel
  ! for a large one (against driven_solve at 4096 steps per period), a drive
  ! of amplitude 0 exactly the undriven scene, and the refusals
  call scene_init(sc, 3.0e-3_wp, 0.0_wp, tt, w0, 0.3_wp, 1.0e-6_wp, SCENE_WANT_STATE, st, &
                  drive=drive_t(DRIVE_TORQUE, 2.0e-3_wp, 1.2_wp, 0.3_wp))
  call scene_solve(sc, res, st)
  call tc%check_true(status_ok(st) .and. res%model == SCENE_MODEL_LINEAR, 'small drive: linear: '//trim(res%reason))
  call tc%check_true(res%tol_met .and. res%cost%steps == 0, 'small drive: tol met, no integration')
  call driven_linear_solve(tt, 3.0e-3_wp, 0.0_wp, w0, 0.3_wp, sc%drive, ref_th, ref_om, st)
  call tc%check_close(maxval(abs(res%theta - ref_th)), 0.0_wp, 0.0_wp, 0.0_wp, 'small drive: the closed form itself')
  call scene_estimate(sc, SCENE_MODEL_LINEAR, e0, st)
  call tc%check_close(e0, res%error_estimate, 0.0_wp, 0.0_wp, 'scene_estimate of a driven scene is the solve''s')
  call scene_init(sc, 0.2_wp, 0.0_wp, tt, 1.0_wp, 0.5_wp, 1.0e-6_wp, SCENE_WANT_STATE, st, &
                  drive=drive_t(DRIVE_TORQUE, 1.15_wp, 2.0_wp/3, 0.0_wp))
  call scene_solve(sc, res, st)
  call tc%check_true(status_ok(st) .and. res%model == SCENE_MODEL_RK4 .and. res%tol_met, 'large drive: rk4, tol met')
  call driven_solve(tt, 0.2_wp, 0.0_wp, 1.0_wp, 0.5_wp, sc%drive, ref_th, ref_om, st, nsteps=4096)
  err = max(maxval(abs(res%theta - ref_th)), maxval(abs(res%omega - ref_om)))
  call tc%check_true(err <= res%error_estimate, 'large drive: true error <= estimate')
  ! undamped: off resonance the closed form (no decay in its bound), at it the kernel
  call scene_init(sc, 2.0e-3_wp, 1.0e-3_wp, tt(1:9), w0, 0.0_wp, 1.0e-6_wp, SCENE_WANT_STATE, st, &
                  drive=drive_t(DRIVE_TORQUE, 1.0e-3_wp, 0.9_wp, 0.3_wp))
  call scene_solve(sc, res, st)
  call tc%check_true(status_ok(st) .and. res%model == SCENE_MODEL_LINEAR, 'undamped small drive: linear')
  call scene_init(sc, 2.0e-3_wp, 0.0_wp, tt(1:9), w0, 0.0_wp, 1.0e-6_wp, SCENE_WANT_STATE, st, &
                  drive=drive_t(DRIVE_TORQUE, 1.0e-3_wp, w0, 0.0_wp))
  call scene_solve(sc, res, st)
  call tc%check_true(status_ok(st) .and. res%model == SCENE_MODEL_RK4, 'undamped resonance: rk4: '//trim(res%reason))
  call scene_init(sc, 0.3_wp, 0.0_wp, tt, w0, 0.1_wp, 1.0e-6_wp, SCENE_WANT_STATE, st)
  call scene_solve(sc, res, st)
  call scene_init(sc, 0.3_wp, 0.0_wp, tt, w0, 0.1_wp, 1.0e-6_wp, SCENE_WANT_STATE, st, &
                  drive=drive_t(DRIVE_TORQUE, 0.0_wp, 1.2_wp, 0.3_wp))
  call scene_solve(sc, res2, st)
  call tc%check_true(res2%model == res%model .and. all(res2%theta == res%theta) .and. &
                     res2%error_estimate == res%error_estimate, 'a drive of amplitude 0 is the undriven scene')
  call scene_init(sc, 0.3_wp, 0.0_wp, tt, w0, 0.1_wp, 1.0e-6_wp, SCENE_WANT_EVENTS, st, &
                  drive=drive_t(DRIVE_TORQUE, 0.1_wp, 1.2_wp, 0.3_wp))
  call tc%check_true(index(st%message, 'want = events is not offered with a drive') == 1, 'driven events refused')
  call scene_init(sc, 0.3_wp, 0.0_wp, tt, w0, 0.1_wp, 1.0e-6_wp, SCENE_WANT_STATE, st, model=SCENE_MODEL_LINEAR, &
                  drive=drive_t(DRIVE_PIVOT, 0.1_wp, 30.0_wp, 0.0_wp))
  call tc%check_true(index(st%message, 'needs a torque drive') > 0, 'linear with a pivot refused: '//trim(st%message))

  call tc%report('test_scene')

contains

  ! Converged reference on tt: RK4 (the integrators module) at h and h/2,
  ! Richardson-extrapolated.
  subroutine reference(th0, om0, gam, th, om)
    real(wp), intent(in) :: th0, om0, gam
    real(wp), intent(out) :: th(:), om(:)
    real(wp) :: th1(41), om1(41), th2(41), om2(41)
    type(ode_stats_t) :: stats
    type(status_t) :: s
    call rk4_solve(tt, th0, om0, w0, gam, 2.0e-3_wp, th1, om1, stats, s)
    call rk4_solve(tt, th0, om0, w0, gam, 1.0e-3_wp, th2, om2, stats, s)
    th = th2 + (th2 - th1)/15
    om = om2 + (om2 - om1)/15
  end subroutine reference

end program test_scene
