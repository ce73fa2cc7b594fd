!> scene_solve_work / scene_run_work (pendula_scene_work): the predicted work
!> of a solve or fixed run [RK4 steps] against the work scene_solve and
!> scene_run_model report (cost%steps, a CVODE step counting
!> SCENE_CVODE_STEP_COST), and its edges: an invalid scene predicts 0, and
!> extreme but valid scenes give a finite prediction >= 0 (the checked leg
!> traps overflow, division by zero and invalid operations).
program test_scene_work
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_sci
  use pendula_status, only: status_t, PENDULA_OK
  use pendula, only: scene_t, scene_result_t, scene_init, scene_solve, scene_run_model, scene_solve_work, &
                     scene_run_work, SCENE_MODEL_AUTO, SCENE_MODEL_RK4, SCENE_MODEL_EXACT, SCENE_WANT_STATE, SCENE_WANT_FINAL, &
                     SCENE_WANT_ENERGY, SCENE_WANT_EVENTS, SCENE_MODEL_TAYLOR, SCENE_MODEL_CVODE
  use pendula_scene_codes, only: SCENE_TAYLOR_STEP_COST, SCENE_CVODE_STEP_COST
  use pendula_testing, only: checker_t, time_grid
  implicit none
  type(checker_t) :: t
  type(scene_t) :: sc
  type(scene_result_t) :: res
  type(status_t) :: st
  real(wp) :: work, done
  integer :: i
  real(wp), parameter :: TH0(6) = [1.0e-300_wp, 1.0_wp, 3.14159265358979_wp, 1.0e6_wp, 1.0_wp, 3.14159265358979_wp]
  real(wp), parameter :: TEND(6) = [1.0e12_wp, 1.0e100_wp, 1.0e-300_wp, 1.0e-50_wp, 1.0e100_wp, 1.0e100_wp]
  real(wp), parameter :: W0S(6) = [1.0e-3_wp, 1.0_wp, 1.0e50_wp, 1.0e50_wp, 1.0e-3_wp, 1.0_wp]
  real(wp), parameter :: GAMMAS(6) = [1.0e-6_wp, 0.5_wp, 1.0e52_wp, 1.0e51_wp, 1.0e-5_wp, 1.0e-300_wp]
  real(wp), parameter :: TOLS(6) = [1.0e-15_wp, 1.0e-15_wp, 1.0_wp, 1.0e-3_wp, 1.0e100_wp, 1.0e-15_wp]
  integer, parameter :: WANTS(6) = [SCENE_WANT_STATE, SCENE_WANT_FINAL, SCENE_WANT_EVENTS, SCENE_WANT_ENERGY, &
                                    SCENE_WANT_STATE, SCENE_WANT_FINAL]

  ! scene 287 of the benchmark grid: ~50 periods, decayed within a few; the
  ! solve does a few dozen RK4 steps, then the linear form
  call scene_init(sc, 1.7430472705210027_wp, -2.1978054335978863_wp, [285.52142322049934_wp], &
                  sqrt(21.476_wp/7.368_wp), 3.4145374878121144_wp, 3.97e-9_wp, SCENE_WANT_ENERGY, st)
  call scene_solve(sc, res, st)
  work = scene_solve_work(sc)
  done = real(res%cost%steps, wp)*reported_cost(res%model)
  call t%check_true(st%code == PENDULA_OK .and. done < 1000, 'decayed scene: few steps ('//format_sci(done, 3)//')')
  call t%check_true(work >= done/3 .and. work <= 10*done + 100, 'decayed scene: predicted '// &
                    format_sci(work, 3)//' vs '//format_sci(done, 3))

  ! an undecayed window: within a factor 10 of the reported steps
  call scene_init(sc, 1.0_wp, 0.0_wp, time_grid(0.0_wp, 25.0_wp, 21), 3.0_wp, 1.0e-3_wp, 1.0e-8_wp, &
                  SCENE_WANT_STATE, st)
  call scene_solve(sc, res, st)
  work = scene_solve_work(sc)
  done = real(res%cost%steps, wp)*reported_cost(res%model)
  call t%check_true(st%code == PENDULA_OK .and. done > 1.0e3_wp, 'undecayed scene solved')
  call t%check_true(work >= done/10 .and. work <= 10*done, 'undecayed scene: predicted '// &
                    format_sci(work, 3)//' vs '//format_sci(done, 3))

  ! a fixed RK4 run: its steps, plus its outputs
  call scene_init(sc, 1.0_wp, 0.0_wp, time_grid(0.0_wp, 1.0_wp, 11), 3.0_wp, 0.1_wp, 1.0e-6_wp, SCENE_WANT_STATE, st)
  call scene_run_model(sc, SCENE_MODEL_RK4, 1.0e-3_wp, res, st)
  work = scene_run_work(sc, SCENE_MODEL_RK4, 1.0e-3_wp)
  call t%check_true(res%cost%steps == 10000_i8 .and. work >= 1.0e4_wp .and. work <= 1.0e4_wp + 1100, &
                    'fixed RK4 run: predicted '//format_sci(work, 3))
  ! a closed form: its outputs only, however long the window
  call scene_init(sc, 2.0_wp, 0.0_wp, time_grid(0.0_wp, 1.0e2_wp, 101), 3.0_wp, 0.0_wp, 1.0e-8_wp, &
                  SCENE_WANT_STATE, st)
  call t%check_true(scene_solve_work(sc) <= 1000 .and. scene_run_work(sc, SCENE_MODEL_EXACT, 0.0_wp) <= 1000, &
                    'closed form: outputs only')

  ! invalid: 0 (the solve refuses it at once)
  sc%tol = -1
  call t%check_true(scene_solve_work(sc) == 0 .and. scene_run_work(sc, SCENE_MODEL_RK4, 1.0e-3_wp) == 0, &
                    'invalid scene: 0')
  sc%tol = 1.0e-8_wp
  call t%check_true(scene_run_work(sc, SCENE_MODEL_RK4, 0.0_wp) == 0 .and. &
                    scene_run_work(sc, SCENE_MODEL_RK4, ieee_value(1.0_wp, ieee_positive_inf)) == 0, 'invalid setting: 0')

  ! extreme valid scenes (gamma/w0 <= 1e6): a finite prediction >= 0 (the
  ! checked leg traps overflow, division by zero and invalid operations)
  do i = 1, size(TH0)
    call scene_init(sc, TH0(i), 1.0_wp, [TEND(i)], W0S(i), GAMMAS(i), TOLS(i), WANTS(i), st, SCENE_MODEL_AUTO)
    call t%check_true(st%code == PENDULA_OK, 'extreme scene accepted '//format_sci(real(i, wp), 2))
    if (st%code /= PENDULA_OK) cycle
    work = scene_solve_work(sc)
    call t%check_true(work >= 0 .and. work <= huge(1.0_wp), 'extreme scene '//format_sci(real(i, wp), 2))
    work = scene_run_work(sc, SCENE_MODEL_RK4, 1.0e-3_wp)
    call t%check_true(work >= 0 .and. work <= huge(1.0_wp), 'extreme fixed run '//format_sci(real(i, wp), 2))
  end do
  call t%report('test_scene_work')
contains

  ! The work a solve reports, in RK4 steps per step of its model.
  pure real(wp) function reported_cost(model) result(c)
    integer, intent(in) :: model
    c = 1
    if (model == SCENE_MODEL_CVODE) c = SCENE_CVODE_STEP_COST
    if (model == SCENE_MODEL_TAYLOR) c = SCENE_TAYLOR_STEP_COST
  end function reported_cost

end program test_scene_work
