!> Failure paths of the integrators, repeated, for the checked and memcheck legs
!> (issue 9): every way CVODE can fail (step budget, illegal error weight,
!> repeated error-test failures, events truncated or cut short by a failure)
!> and the RK4 refusals.  Each path runs REPEAT times, so a leak on it shows up
!> under valgrind as REPEAT lost blocks; every failure must come back as a
!> status with a message and finite (zeroed) outputs, never a stop or a NaN.
!> PENDULA_TEST_QUICK=1 (set by tools/memcheck.sh) lowers REPEAT.
program test_failure_paths
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use, intrinsic :: ieee_exceptions, only: ieee_usual, ieee_get_halting_mode, ieee_set_halting_mode
  use pendula
  use pendula_testing, only: checker_t
  implicit none
  type(checker_t) :: tc
  integer :: repeat, r
  character(len=8) :: quick
  integer :: qlen, qstat

  call get_environment_variable('PENDULA_TEST_QUICK', quick, qlen, qstat)
  repeat = 20
  if (qstat == 0 .and. qlen > 0) then
    if (quick(1:1) /= '0') repeat = 3
  end if

  do r = 1, repeat
    call rk4_refusals(r == 1)
    if (cvode_available()) call cvode_failures(r == 1)
  end do
  if (.not. cvode_available()) call cvode_unavailable()
  call tc%report('test_failure_paths')

contains

  logical function all_finite(x)
    real(wp), intent(in) :: x(:)
    all_finite = all(ieee_is_finite(x))
  end function all_finite

  subroutine expect_failure(st, code, label, first)
    type(status_t), intent(in) :: st
    integer, intent(in) :: code
    character(len=*), intent(in) :: label
    logical, intent(in) :: first
    ! Counted once (first repetition) so the totals do not depend on REPEAT;
    ! later repetitions still fail the run if the behaviour changes.
    if (first .or. st%code /= code .or. len_trim(st%message) == 0) then
      call tc%check_true(st%code == code, label // ': status ' // code_name(st%code) // &
          ' (expected ' // code_name(code) // '): ' // trim(st%message))
      call tc%check_true(len_trim(st%message) > 10, label // ': a message says why')
    end if
  end subroutine expect_failure

  subroutine rk4_refusals(first)
    logical, intent(in) :: first
    real(wp) :: th(3), om(3), t(3)
    type(ode_stats_t) :: s
    type(status_t) :: st
    t = [0.0_wp, 50.0_wp, 100.0_wp]
    ! h beyond the stability limit (2.06 s here) over a long spacing: refused.
    call rk4_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 50.0_wp, th, om, s, st)
    call expect_failure(st, PENDULA_ERR_UNSTABLE, 'rk4 unstable h', first)
    ! h so small the window needs > 2e9 steps (the default budget): refused up front.
    call rk4_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-300_wp, th, om, s, st)
    call tc%check_true(st%code /= PENDULA_OK, 'rk4 tiny h refused: ' // trim(st%message))
    call tc%check_true(all_finite(th) .and. all_finite(om), 'rk4 refused: outputs finite')
    ! times not increasing
    call rk4_solve([0.0_wp, 2.0_wp, 1.0_wp], 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 0.05_wp, th, om, s, st)
    call expect_failure(st, PENDULA_ERR_ORDER, 'rk4 t decreasing', first)
    ! output arrays of the wrong size
    call rk4_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 0.05_wp, th(1:2), om, s, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'rk4 output size', first)
    ! an explicit budget below the window's 2000 steps: refused; 2000 is enough
    call rk4_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 0.05_wp, th, om, s, st, max_steps=1999_i8)
    call expect_failure(st, PENDULA_ERR_DOMAIN, 'rk4 max_steps below the window', first)
    call rk4_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 0.05_wp, th, om, s, st, max_steps=2000_i8)
    call tc%check_true(st%code == PENDULA_OK .and. s%steps == 2000, 'rk4 max_steps = steps: runs')
    call rk4_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 0.05_wp, th, om, s, st, max_steps=0_i8)
    call expect_failure(st, PENDULA_ERR_DOMAIN, 'rk4 max_steps = 0', first)
    call cancelled_runs(first)
  end subroutine rk4_refusals

  !> The cancel flag of pendula_control, set before the call (as another
  !> thread would): each integrator stops at its first poll with
  !> PENDULA_ERR_CANCELLED, zero or kept outputs, and its progress counted;
  !> a clear flag changes nothing (bit-identical to the call without control).
  subroutine cancelled_runs(first)
    logical, intent(in) :: first
    real(wp) :: th(2), om(2), th0(2), om0(2), t(2), e, f
    integer(i8) :: control(CONTROL_SIZE)
    type(ode_stats_t) :: s
    type(status_t) :: st
    t = [0.0_wp, 100.0_wp]
    control = 0
    call rk4_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-3_wp, th, om, s, st, control)
    call rk4_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-3_wp, th0, om0, s, st)
    call tc%check_true(st%code == PENDULA_OK .and. all(th == th0) .and. all(om == om0), &
        'rk4 with a clear control: same results bit for bit')
    call tc%check_true(control(CONTROL_PROGRESS) == 100000, 'rk4 progress counts every step')
    control = [1_i8, 0_i8]
    call rk4_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-3_wp, th, om, s, st, control)
    call expect_failure(st, PENDULA_ERR_CANCELLED, 'rk4 cancelled', first)
    call tc%check_true(all(th == 0) .and. all(om == 0) .and. control(CONTROL_PROGRESS) == 4096, &
        'rk4 cancelled: outputs zero, stopped at the first poll (4096 steps)')
    control = [1_i8, 0_i8]
    call rk4_final_state(0.0_wp, 100.0_wp, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-3_wp, e, f, s, st, control)
    call expect_failure(st, PENDULA_ERR_CANCELLED, 'rk4_final_state cancelled', first)
    call scene_cancelled(first)
    if (.not. cvode_available()) return
    control = [1_i8, 0_i8]
    call cvode_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-10_wp, 1.0e-12_wp, PENDULA_CVODE_BDF, &
        1000000_i8, th, om, s, st, control)
    call expect_failure(st, PENDULA_ERR_CANCELLED, 'cvode cancelled', first)
    call tc%check_true(all_finite(th) .and. all_finite(om) .and. control(CONTROL_PROGRESS) == 256, &
        'cvode cancelled: outputs finite, stopped at the first poll (256 evaluations)')
  end subroutine cancelled_runs

  !> The scene solver (RK4 over an uneven grid: one short run per interval)
  !> answers a set cancel flag, a clear one changes nothing, and a budget
  !> below the predicted work is refused up front.
  subroutine scene_cancelled(first)
    logical, intent(in) :: first
    integer(i8) :: control(CONTROL_SIZE)
    type(scene_t) :: sc
    type(scene_result_t) :: res, res0
    type(status_t) :: st
    call scene_init(sc, 1.0_wp, 0.0_wp, [0.0_wp, 1.0_wp, 3.0_wp, 40.0_wp], 1.4_wp, 0.1_wp, 1.0e-10_wp, &
        SCENE_WANT_STATE, st)
    call tc%check_true(st%code == PENDULA_OK, 'scene for the cancel test: ' // trim(st%message))
    control = [1_i8, 0_i8]
    call scene_solve(sc, res, st, control)
    call expect_failure(st, PENDULA_ERR_CANCELLED, 'scene_solve cancelled', first)
    control = 0
    call scene_solve(sc, res, st, control)
    call scene_solve(sc, res0, st)
    call tc%check_true(st%code == PENDULA_OK .and. res%model == SCENE_MODEL_RK4, 'scene_solve with control: rk4 runs')
    call tc%check_true(all(res%theta == res0%theta) .and. all(res%omega == res0%omega) .and. &
        control(CONTROL_PROGRESS) == res%cost%steps, 'scene_solve: same results, progress = steps')
    call scene_solve(sc, res, st, max_steps=1000_i8)
    call expect_failure(st, PENDULA_ERR_MAXSTEPS, 'scene_solve over its budget', first)
  end subroutine scene_cancelled

  subroutine cvode_failures(first)
    logical, intent(in) :: first
    real(wp) :: th(3), om(3), t(3), et(4), eth(4), eom(4)
    integer :: ek(4), n_ev
    logical :: trunc, halting(size(ieee_usual))
    type(ode_stats_t) :: s
    type(status_t) :: st
    t = [0.0_wp, 500.0_wp, 1000.0_wp]
    ! 1. step budget exhausted (CV_TOO_MUCH_WORK or our own budget)
    call cvode_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, PENDULA_CVODE_ADAMS, 10_i8, &
        th, om, s, st)
    call expect_failure(st, PENDULA_ERR_MAXSTEPS, 'cvode step budget', first)
    call tc%check_true(all_finite(th) .and. all_finite(om), 'cvode budget: outputs finite')
    ! 2. the same with BDF and events on
    call cvode_solve_events(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, PENDULA_CVODE_BDF, &
        10_i8, th, om, et, ek, eth, eom, n_ev, trunc, s, st)
    call expect_failure(st, PENDULA_ERR_MAXSTEPS, 'cvode events step budget', first)
    ! 3. atol = 0 with a zero state component: CVODE rejects the error weight
    call cvode_solve(t, 0.0_wp, 1.0_wp, 1.4_wp, 0.1_wp, 1.0e-8_wp, 0.0_wp, PENDULA_CVODE_ADAMS, 100000_i8, &
        th, om, s, st)
    call expect_failure(st, PENDULA_ERR_SOLVER, 'cvode zero error weight', first)
    ! 4. a stiff fast oscillation CVODE cannot follow: repeated error-test
    ! failures.  SUNDIALS' own C code overflows on the way (reported to the
    ! integrators concern); halting is switched off around this one call so
    ! that the checked leg still runs the path's cleanup, which is the point here.
    call ieee_get_halting_mode(ieee_usual, halting)
    call ieee_set_halting_mode(ieee_usual, .false.)
    call cvode_solve([0.0_wp, 1.0_wp], 0.0_wp, 2.0_wp, 1.0e154_wp, 0.0_wp, 1.0e-8_wp, 1.0e-10_wp, &
        PENDULA_CVODE_ADAMS, 100000_i8, th(1:2), om(1:2), s, st)
    call ieee_set_halting_mode(ieee_usual, halting)
    call tc%check_true(st%code == PENDULA_ERR_SOLVER .or. st%code == PENDULA_ERR_MAXSTEPS, &
        'cvode w0 = 1e154 fails cleanly: ' // trim(st%message))
    ! 4b. w0 = 1e300: w0**2 overflows, the right-hand side is not finite and
    ! reports an unrecoverable failure (CV_RHSFUNC_FAIL) -- its cleanup path.
    call ieee_set_halting_mode(ieee_usual, .false.)
    call cvode_solve([0.0_wp, 1.0_wp], 0.1_wp, 0.0_wp, 1.0e300_wp, 0.0_wp, 1.0e-8_wp, 1.0e-10_wp, &
        PENDULA_CVODE_BDF, 100000_i8, th(1:2), om(1:2), s, st)
    call ieee_set_halting_mode(ieee_usual, halting)
    call tc%check_true(st%code /= PENDULA_OK, 'cvode w0 = 1e300 fails cleanly: ' // trim(st%message))
    call tc%check_true(all_finite(th(1:2)) .and. all_finite(om(1:2)), 'cvode w0 = 1e300: outputs finite')
    call tc%check_true(all_finite(th(1:2)) .and. all_finite(om(1:2)), 'cvode w0 = 1e154: outputs finite')
    ! 5. more events than room: truncated, not an error
    call cvode_solve_events([0.0_wp, 100.0_wp], 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, &
        PENDULA_CVODE_ADAMS, 1000000_i8, th(1:2), om(1:2), et, ek, eth, eom, n_ev, trunc, s, st)
    if (first .or. st%code /= PENDULA_OK .or. .not. trunc) then
      call tc%check_true(st%code == PENDULA_OK .and. trunc .and. n_ev == size(et), &
          'cvode events truncated at the array size: ' // trim(st%message))
    end if
    ! 6. argument errors before any SUNDIALS object exists
    call cvode_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, -1.0_wp, 1.0e-10_wp, PENDULA_CVODE_ADAMS, 100_i8, &
        th, om, s, st)
    call expect_failure(st, PENDULA_ERR_DOMAIN, 'cvode rtol < 0', first)
  end subroutine cvode_failures

  subroutine cvode_unavailable()
    real(wp) :: th(2), om(2)
    type(ode_stats_t) :: s
    type(status_t) :: st
    call cvode_solve([0.0_wp, 1.0_wp], 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, &
        PENDULA_CVODE_ADAMS, 100_i8, th, om, s, st)
    call expect_failure(st, PENDULA_ERR_UNAVAILABLE, 'cvode not built', .true.)
  end subroutine cvode_unavailable

end program test_failure_paths
