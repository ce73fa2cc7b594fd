!> Example: scenes -- describe the pendulum, the window and a tolerance; the library
!> picks the cheapest model whose error fits, says which and why, and estimates the error.
!>
!> Six scenes with the text's g = 9.8 m/s^2, l = 4.9 m (w0 = sqrt(2) 1/s), from a small
!> undamped swing to the text's §2.2 run (m = 0.1 kg, b = 0.01 kg/s) and a stiffly
!> damped large swing; plus one scene that asks only for the period (no time series).
!> For undamped scenes the true error against the exact solution is printed too.
program example_scene
  use pendula
  use example_support, only: require
  implicit none
  integer, parameter :: n = 201
  real(wp) :: w0, gamma, t0, t(n)
  type(status_t) :: st
  integer :: i

  call natural_frequency(9.8_wp, 4.9_wp, w0, st)
  call require(st)
  t0 = 2*pi/w0
  write (*, '(a)') 'scene                                   tol [rad]  model         estimate    true error'// &
    '  cost (closed-form points, rhs evals)'

  call run('small swing, undamped, 10 periods', 0.05_wp, 0.0_wp, 0.0_wp, 10*t0, 1.0e-3_wp)
  call run('large swing 0.9 pi, undamped', 0.9_wp*pi, 0.0_wp, 0.0_wp, 10*t0, 1.0e-8_wp)
  call run('small swing, gamma = 0.1 1/s', 0.01_wp, 0.0_wp, 0.1_wp, 10*t0, 1.0e-6_wp)
  call scene_physics(9.8_wp, 4.9_wp, w0, gamma, st, mass=0.1_wp, b=0.01_wp)
  call require(st)
  call run('text 2.2: m = 0.1 kg, b = 0.01 kg/s', 0.0_wp, 2.0_wp, gamma, 30.0_wp, 1.0e-6_wp)
  call run('near-separatrix rotation', 0.0_wp, 2.0001_wp*w0, 0.0_wp, 5*t0, 1.0e-9_wp)
  call run('large swing, gamma = 50 1/s (stiff)', 2.0_wp, 0.0_wp, 50.0_wp, 20.0_wp, 1.0e-6_wp)
  call period_only()

contains

  subroutine run(title, theta0, omega0, gam, window, tol)
    character(len=*), intent(in) :: title
    real(wp), intent(in) :: theta0, omega0, gam, window, tol
    type(scene_t) :: scene
    type(scene_result_t) :: res
    type(undamped_motion_t) :: exact
    real(wp) :: th(n), om(n)
    character(len=10) :: true_err
    t = [(window*(i - 1)/(n - 1), i=1, n)]
    call scene_init(scene, theta0, omega0, t, w0, gam, tol, SCENE_WANT_STATE, st)
    call require(st)
    call scene_solve(scene, res, st)
    call require(st)
    true_err = '         -'
    if (gam == 0) then
      call undamped_init(exact, theta0, omega0, w0, st)
      call require(st)
      call undamped_eval(exact, t, th, om)
      write (true_err, '(es10.2)') maxval(max(abs(res%theta - th), abs(res%omega - om)/w0))
    end if
    write (*, '(a40, es9.1, 2x, a12, es10.2, 2x, a10, 2x, i8, i10)') title, tol, &
      scene_model_name(res%model), res%error_estimate, true_err, res%cost%closed_form_evals, &
      res%cost%rhs_evals
    write (*, '(4x, a)') 'why: '//trim(res%reason)
    if (.not. res%tol_met) then
      write (*, '(a)') 'error: the tolerance was not met'
      error stop 1
    end if
  end subroutine run

  subroutine period_only()
    type(scene_t) :: scene
    type(scene_result_t) :: res
    real(wp) :: none(0)
    call scene_init(scene, 0.9_wp*pi, 0.0_wp, none, w0, 0.0_wp, 1.0e-12_wp, SCENE_WANT_PERIOD, st)
    call require(st)
    call scene_solve(scene, res, st)
    call require(st)
    write (*, '(/, a, es23.16, a, a)') 'period only, theta0 = 0.9 pi: T = ', res%period, ' s by ', &
      scene_model_name(res%model)
    write (*, '(4x, a)') 'why: '//trim(res%reason)
  end subroutine period_only

end program example_scene
