!> Failure paths, repeated, for the checked and memcheck legs
!>: every way CVODE can fail (step budget, illegal error weight,
!> repeated error-test failures, events truncated or cut short by a failure)
!> and the RK4 refusals; every public array routine called with wrong sizes (it must
!> report PENDULA_ERR_SIZE, not write out of bounds: valgrind sees any overrun); the
!> elliptic functions at the extreme inputs that once crashed (|m| near huge(),
!> NaN parameters for plans).  Each path runs REPEAT times, so a leak on it shows up
!> under valgrind as REPEAT lost blocks; every failure must come back as a
!> status with a message and finite (zeroed) outputs, never a stop or a NaN.
!> PENDULA_TEST_QUICK=1 (set by tools/memcheck.sh) lowers REPEAT.
program test_failure_paths
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use, intrinsic :: ieee_exceptions, only: ieee_usual, ieee_get_halting_mode, ieee_set_halting_mode
  use pendula
  use pendula_rk4_kernel, only: rk4_grid
  use pendula_status, only: check_alloc
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
    call wrong_sizes(r == 1)
    call elliptic_extremes(r == 1)
    call rk4_refusals(r == 1)
    if (cvode_available()) call cvode_failures(r == 1)
  end do
  if (.not. cvode_available()) call cvode_unavailable()
  call memory_refusal()
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
      call tc%check_true(st%code == code, label//': status '//code_name(st%code)// &
                         ' (expected '//code_name(code)//'): '//trim(st%message))
      call tc%check_true(len_trim(st%message) > 10, label//': a message says why')
    end if
  end subroutine expect_failure

  !> Every public routine with array arguments, one array too short or too long.
  subroutine wrong_sizes(first)
    logical, intent(in) :: first
    real(wp) :: m(10), k(3), u(10), sn(10), cn(10), dn(10), am(10), short(4), th(10), om(10), t(10)
    real(wp) :: et(4), eth(4), eom(4)
    integer :: ek(3), n_ev, i, bad
    integer(i8) :: steps, fast
    logical :: trunc
    type(ellipj_plan_t) :: plan
    type(undamped_motion_t) :: motion
    type(linear_damped_t) :: sol
    type(ode_stats_t) :: s
    type(status_t) :: st
    m = 0.5_wp; u = 0.25_wp; t = [(0.1_wp*i, i=0, 9)]
    call ellipk_array(m, k, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'ellipk_array k(3) for m(10)', first)
    call ellipe_array(m(1:2), k, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'ellipe_array e(3) for m(2)', first)
    call ellipj_array(u, m, short, cn, dn, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'ellipj_array short sn', first)
    call ellipj_array(u, m, sn, cn, dn, st, short)
    call expect_failure(st, PENDULA_ERR_SIZE, 'ellipj_array short am', first)
    call ellipj_array(u, m(1:4), sn, cn, dn, st, am)
    call expect_failure(st, PENDULA_ERR_SIZE, 'ellipj_array short m', first)
    call ellipjm1_array(u, m, sn, short, dn, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'ellipjm1_array short cn', first)
    call ellipjm1_array(u(1:4), m, short, short, short, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'ellipjm1_array long mc', first)
    plan = ellipj_plan(0.7_wp)
    call ellipj_eval_array(plan, u, sn, cn, short, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'ellipj_eval_array short dn', first)
    call ellipj_eval_array(plan, u(1:4), short, short, short, st, am)
    call expect_failure(st, PENDULA_ERR_SIZE, 'ellipj_eval_array long am', first)
    call undamped_init(motion, 1.0_wp, 0.0_wp, 2.0_wp, st)
    call undamped_eval_many(motion, t, th, short, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'undamped_eval_many short omega', first)
    call undamped_solve(t, 1.0_wp, 0.0_wp, 2.0_wp, short, om, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'undamped_solve short theta', first)
    call small_angle_solve(t, 1.0_wp, 0.0_wp, 2.0_wp, th, short, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'small_angle_solve short omega', first)
    call linear_damped_init(sol, 1.0_wp, 0.0_wp, 2.0_wp, 0.1_wp, st)
    call linear_damped_eval(sol, t, short, om, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'linear_damped_eval short theta', first)
    call linear_damped_arrays(t, m, m, m(1:4), m, th, om, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'linear_damped_arrays short w0', first)
    call rk4_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 0.05_wp, th, short, s, st)
    call expect_failure(st, PENDULA_ERR_SIZE, 'rk4_solve short omega', first)
    call rk4_grid(t, 4.0_wp, 0.1_wp, 0.05_wp, th, short, steps, fast, bad)
    if (first .or. bad /= huge(bad)) call tc%check_true(bad == huge(bad) .and. steps == 0, 'rk4_grid short omega: bad = huge')
    call cvode_solve(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, PENDULA_CVODE_ADAMS, &
                     1000_i8, short, om, s, st)
    call tc%check_true(st%code == PENDULA_ERR_SIZE .or. st%code == PENDULA_ERR_UNAVAILABLE, &
                       'cvode_solve short theta: '//trim(st%message))
    call cvode_solve_events(t, 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, PENDULA_CVODE_ADAMS, &
                            1000_i8, th, om, et, ek, eth, eom, n_ev, trunc, s, st)
    call tc%check_true(st%code == PENDULA_ERR_SIZE .or. st%code == PENDULA_ERR_UNAVAILABLE, &
                       'cvode_solve_events event_kind(3) for event_t(4): '//trim(st%message))
  end subroutine wrong_sizes

  !> Elliptic functions at the inputs that once crashed: |m| near huge() (the plan's
  !> double-double set-up overflowed, then a table index was formed from NaN).
  subroutine elliptic_extremes(first)
    logical, intent(in) :: first
    real(wp) :: ms(6), u(40), sn(40), cn(40), dn(40), am(40), mm(40), x
    type(ellipj_plan_t) :: plan
    type(status_t) :: st
    integer :: i, j
    logical :: ok
    ms = [1.0e308_wp, -1.0e308_wp, huge(1.0_wp), -huge(1.0_wp), 1.4e300_wp, -1.4e300_wp]
    u = [(0.7_wp*3.0_wp**(i - 20), i=1, 40)]
    ok = .true.
    do j = 1, size(ms)
      call ellipj(0.7_wp, ms(j), sn(1), cn(1), dn(1), am(1))
      ok = ok .and. all(ieee_is_finite([sn(1), cn(1), dn(1), am(1)]))
      call ellipjm1(0.7_wp, ms(j), sn(1), cn(1), dn(1), am(1))
      ok = ok .and. all(ieee_is_finite([sn(1), cn(1), dn(1), am(1)]))
      plan = ellipj_plan(ms(j))
      call ellipj_eval_array(plan, u, sn, cn, dn, st, am)
      ok = ok .and. all_finite(sn) .and. all_finite(cn) .and. all_finite(dn) .and. all_finite(am)
      plan = ellipj_planm1(ms(j))
      call ellipj_eval_array(plan, u, sn, cn, dn, st)
      ok = ok .and. all_finite(sn) .and. all_finite(cn) .and. all_finite(dn)
      mm = ms(j)
      mm(7) = 0.5_wp                     ! one ordinary element among the extreme ones
      call ellipj_array(u, mm, sn, cn, dn, st, am)
      ok = ok .and. all_finite(sn) .and. all_finite(cn) .and. all_finite(dn) .and. all_finite(am)
      x = ellipf(1.0e-160_wp, ms(j)) + ellipfm1(1.0e-160_wp, ms(j))
      ok = ok .and. ieee_is_finite(x)
    end do
    if (first .or. .not. ok) call tc%check_true(ok, 'elliptic functions at |m| up to huge(): finite')
    ! phi near huge() and at the doubles nearest odd multiples of pi/2 with m -> 1
    x = ellipf(huge(1.0_wp)/3, 0.5_wp) + ellipfm1(1.5707963267948966_wp, 1.0e-300_wp) &
        + ellipf(-4.71238898038469_wp, 0.999_wp)
    if (first .or. .not. ieee_is_finite(x)) call tc%check_true(ieee_is_finite(x), 'ellipf extreme phi: finite')
  end subroutine elliptic_extremes

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
    call tc%check_true(st%code /= PENDULA_OK, 'rk4 tiny h refused: '//trim(st%message))
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
    ! the choice takes the Taylor series here (a few dozen steps, fewer than
    ! its poll interval): a set flag stops it before it starts
    call scene_init(sc, 1.0_wp, 0.0_wp, [0.0_wp, 1.0_wp, 3.0_wp, 40.0_wp], 1.4_wp, 0.1_wp, 1.0e-10_wp, &
                    SCENE_WANT_STATE, st)
    control = [1_i8, 0_i8]
    call scene_solve(sc, res, st, control)
    call expect_failure(st, PENDULA_ERR_CANCELLED, 'scene_solve (taylor) cancelled', first)
    call scene_init(sc, 1.0_wp, 0.0_wp, [0.0_wp, 1.0_wp, 3.0_wp, 40.0_wp], 1.4_wp, 0.1_wp, 1.0e-10_wp, &
                    SCENE_WANT_STATE, st, SCENE_MODEL_RK4)
    call tc%check_true(st%code == PENDULA_OK, 'scene for the cancel test: '//trim(st%message))
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
    ! 3. tolerances below double precision: CVODE refuses (CV_TOO_MUCH_ACC)
    call cvode_solve(t, 0.0_wp, 1.0_wp, 1.4_wp, 0.1_wp, 1.0e-30_wp, 1.0e-30_wp, PENDULA_CVODE_ADAMS, 100000_i8, &
                     th, om, s, st)
    call expect_failure(st, PENDULA_ERR_SOLVER, 'cvode too much accuracy', first)
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
                       'cvode w0 = 1e154 fails cleanly: '//trim(st%message))
    ! 4b. w0 = 1e300: w0**2 overflows, the right-hand side is not finite and
    ! reports an unrecoverable failure (CV_RHSFUNC_FAIL) -- its cleanup path.
    call ieee_set_halting_mode(ieee_usual, .false.)
    call cvode_solve([0.0_wp, 1.0_wp], 0.1_wp, 0.0_wp, 1.0e300_wp, 0.0_wp, 1.0e-8_wp, 1.0e-10_wp, &
                     PENDULA_CVODE_BDF, 100000_i8, th(1:2), om(1:2), s, st)
    call ieee_set_halting_mode(ieee_usual, halting)
    call tc%check_true(st%code /= PENDULA_OK, 'cvode w0 = 1e300 fails cleanly: '//trim(st%message))
    call tc%check_true(all_finite(th(1:2)) .and. all_finite(om(1:2)), 'cvode w0 = 1e300: outputs finite')
    call tc%check_true(all_finite(th(1:2)) .and. all_finite(om(1:2)), 'cvode w0 = 1e154: outputs finite')
    ! 5. more events than room: truncated, not an error
    call cvode_solve_events([0.0_wp, 100.0_wp], 0.0_wp, 2.0_wp, 1.4_wp, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, &
                            PENDULA_CVODE_ADAMS, 1000000_i8, th(1:2), om(1:2), et, ek, eth, eom, n_ev, trunc, s, st)
    if (first .or. st%code /= PENDULA_OK .or. .not. trunc) then
      call tc%check_true(st%code == PENDULA_OK .and. trunc .and. n_ev == size(et), &
                         'cvode events truncated at the array size: '//trim(st%message))
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

  !> An allocation the machine cannot satisfy (2**58 reals, 2 EiB: refused at
  !> once, nothing touched; below 2**63 bytes, which valgrind calls a fishy size) comes back through check_alloc as
  !> PENDULA_ERR_MEMORY naming what and how much, never as a crash; a
  !> successful one (stat 0) leaves the status alone.
  subroutine memory_refusal()
    real(wp), allocatable :: huge_block(:)
    type(status_t) :: st
    integer :: ist
    integer(i8) :: n
    n = 2_i8**58
    allocate (huge_block(n), stat=ist)
    call tc%check_true(ist /= 0, 'a 2 EiB allocation is refused (stat /= 0)')
    if (ist == 0) return
    call check_alloc(ist, 'the test block', n, 8, st)
    call tc%check_true(st%code == PENDULA_ERR_MEMORY .and. code_name(st%code) == 'out of memory', &
                       'memory: status PENDULA_ERR_MEMORY, '//code_name(st%code))
    call tc%check_true(index(st%message, 'out of memory: the test block need') == 1 .and. &
                       index(st%message, ' GiB (288230376151711744 values of 8 bytes)') > 0, 'memory: message '//trim(st%message))
    st = status_t()
    call check_alloc(0, 'nothing', 1_i8, 8, st)
    call tc%check_true(st%code == PENDULA_OK, 'memory: stat 0 is no error')
  end subroutine memory_refusal

end program test_failure_paths
