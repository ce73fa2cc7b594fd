!> Batch RK4 (pendula_rk4_batch): every state's result bit-identical to
!> rk4_solve alone (table path, libm fallback, rotations, gamma = 0, heavy
!> damping, per-state h, partial blocks), per-state failures that leave the
!> other states intact, parameters shared by all states, the empty batch, the
!> cancel flag and progress counter, thread counts 1 and 2, refused calls.
program test_rk4_batch
  use, intrinsic :: iso_fortran_env, only: int64
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
  use pendula_kinds, only: wp, i8
  use pendula_status, only: status_t, PENDULA_OK, PENDULA_ERR_UNSTABLE, PENDULA_ERR_DOMAIN, &
                            PENDULA_ERR_NONFINITE, PENDULA_ERR_ORDER, PENDULA_ERR_SIZE, PENDULA_ERR_CANCELLED
  use pendula_control, only: CONTROL_SIZE, CONTROL_CANCEL, CONTROL_PROGRESS
  use pendula_ode, only: ode_stats_t
  use pendula_rk4, only: rk4_solve
  use pendula_rk4_batch, only: rk4_batch_solve, RK4_BATCH_LANES
  use pendula_testing, only: checker_t, time_grid
  implicit none
  type(checker_t) :: tc
  integer, parameter :: nt = 121
  real(wp) :: t(nt)

  t = time_grid(0.0_wp, 0.25_wp, nt)   ! 0 .. 30 s
  call test_identity()
  call test_failures()
  call test_shared_parameters()
  call test_empty_and_single_time()
  call test_cancel_and_progress()
  call test_refused_calls()
  call tc%report('test_rk4_batch')

contains

  !> A mixed set of 61 states (7 full blocks and a partial one): small and
  !> large amplitudes, rotations in both directions, |theta| > 2**20 (the libm
  !> path throughout), an Omega so large that the a priori bound sends every
  !> step to libm, gamma = 0, overdamped gamma = 8 w0, and steps from 0.01 to
  !> 0.3 s, some dividing the output spacing and some not (so a block mixes
  !> substep counts).  Compared bit for bit with rk4_solve, for 1 and 2 threads.
  subroutine test_identity()
    integer, parameter :: n = 61
    real(wp) :: th0(n), om0(n), w0(n), gam(n), h(n)
    integer :: k, threads
    do k = 1, n
      th0(k) = -3.1_wp + 6.2_wp*mod(k*7, n)/real(n, wp)
      om0(k) = -4.0_wp + 8.0_wp*mod(k*13, n)/real(n, wp)
      w0(k) = 0.5_wp + 2.5_wp*mod(k*5, n)/real(n, wp)
      gam(k) = 0.4_wp*mod(k*11, n)/real(n, wp)
      h(k) = 0.05_wp
    end do
    gam(1:5) = 0                        ! undamped
    gam(6:8) = 8*w0(6:8)              ! heavily overdamped (h stays stable: 0.05 * 8 * 3 < 2.78)
    th0(9) = 3.0e6_wp                   ! beyond stage_xmax: libm steps
    om0(10) = 40.0_wp                   ! fast rotation: bound fails, libm steps
    om0(11) = -9.0_wp                   ! rotation the other way
    th0(12) = 3.14159_wp                ! near the upper equilibrium
    om0(12) = 0
    h(20:30) = [0.01_wp, 0.02_wp, 0.03_wp, 0.07_wp, 0.1_wp, 0.125_wp, 0.3_wp, 0.25_wp, 0.0333_wp, 0.2_wp, 0.06_wp]
    h(40) = 1.0e-3_wp
    do threads = 1, 2
      call compare_with_scalar(th0, om0, w0, gam, h, threads, 'identity')
    end do
  end subroutine test_identity

  !> Run the batch and rk4_solve per state; everything must match exactly.
  subroutine compare_with_scalar(th0, om0, w0, gam, h, threads, label)
    real(wp), intent(in) :: th0(:), om0(:), w0(:), gam(:), h(:)
    integer, intent(in) :: threads
    character(len=*), intent(in) :: label
    real(wp) :: th(nt, size(th0)), om(nt, size(th0)), ths(nt), oms(nt)
    integer :: codes(size(th0)), k, bad_th, bad_code
    integer(i8) :: steps(size(th0))
    type(status_t) :: st, sts
    type(ode_stats_t) :: s
    character(len=8) :: tag
    call rk4_batch_solve(t, th0, om0, w0, gam, h, th, om, codes, steps, st, threads=threads)
    write (tag, '(a, i0)') ' thr=', threads
    call tc%check_true(st%code == PENDULA_OK, label//': summary ok'//trim(tag))
    bad_th = 0
    bad_code = 0
    do k = 1, size(th0)
      call rk4_solve(t, th0(k), om0(k), w0(k), gam(k), h(k), ths, oms, s, sts)
      if (codes(k) /= sts%code) bad_code = bad_code + 1
      if (any(th(:, k) /= ths) .or. any(om(:, k) /= oms) .or. steps(k) /= s%steps) bad_th = bad_th + 1
    end do
    call tc%check_true(bad_code == 0, label//': every code equals rk4_solve''s'//trim(tag))
    call tc%check_true(bad_th == 0, label//': every state bit-identical to rk4_solve (theta, omega, steps)' &
                       //trim(tag))
  end subroutine compare_with_scalar

  !> Failing states among good ones: an unstable h, w0 = 0, a NaN theta0,
  !> gamma < 0.  Each gets rk4_solve's code and NaN outputs; the good states
  !> are bit-identical to rk4_solve; the summary names the first failure.
  subroutine test_failures()
    integer, parameter :: n = 20
    real(wp) :: th0(n), om0(n), w0(n), gam(n), h(n), th(nt, n), om(nt, n), ths(nt), oms(nt)
    integer :: codes(n), k, threads, nbad
    integer(i8) :: steps(n)
    type(status_t) :: st, sts
    type(ode_stats_t) :: s
    integer :: first
    th0 = [(0.1_wp*k, k=1, n)]
    om0 = 0.5_wp
    w0 = sqrt(2.0_wp)
    gam = 0.1_wp
    h = 0.05_wp
    w0(4) = 100                                     ! unstable: h w0 > 2 sqrt(2)
    w0(9) = 0                                       ! domain
    th0(13) = ieee_value(1.0_wp, ieee_quiet_nan)    ! non-finite
    gam(17) = -1                                    ! domain
    do threads = 1, 2
      call rk4_batch_solve(t, th0, om0, w0, gam, h, th, om, codes, steps, st, threads=threads, first_failed=first)
      call tc%check_true(st%code == PENDULA_ERR_UNSTABLE .and. first == 4, 'failures: summary is state 4''s code')
      call tc%check_true(index(st%message, 'state 4 of 20 (4 failed') == 1, 'failures: summary names state and count')
      call tc%check_true(index(st%message, 'largest stable h') > 0, 'failures: summary carries rk4_solve''s message')
      call tc%check_true(all(codes([4, 9, 13, 17]) == [PENDULA_ERR_UNSTABLE, PENDULA_ERR_DOMAIN, &
                                                       PENDULA_ERR_NONFINITE, PENDULA_ERR_DOMAIN]), 'failures: per-state codes')
      call tc%check_true(all(ieee_is_nan(th(:, [4, 9, 13, 17]))) .and. all(ieee_is_nan(om(:, [4, 9, 13, 17]))) .and. &
                         all(steps([4, 9, 13, 17]) == 0), 'failures: failed states have NaN outputs, no steps')
      nbad = 0
      do k = 1, n
        if (any(k == [4, 9, 13, 17])) cycle
        call rk4_solve(t, th0(k), om0(k), w0(k), gam(k), h(k), ths, oms, s, sts)
        if (codes(k) /= PENDULA_OK .or. any(th(:, k) /= ths) .or. any(om(:, k) /= oms)) nbad = nbad + 1
      end do
      call tc%check_true(nbad == 0, 'failures: the other 16 states are intact and bit-identical')
    end do
  end subroutine test_failures

  !> omega0, w0, gamma, h of one element are shared by every state.
  subroutine test_shared_parameters()
    integer, parameter :: n = 11
    real(wp) :: th0(n), th(nt, n), om(nt, n), th2(nt, n), om2(nt, n)
    integer :: codes(n), codes2(n), k
    integer(i8) :: steps(n), steps2(n)
    type(status_t) :: st, st2
    th0 = [(0.3_wp*k - 1.5_wp, k=1, n)]
    call rk4_batch_solve(t, th0, [0.2_wp], [1.3_wp], [0.05_wp], [0.04_wp], th, om, codes, steps, st)
    call rk4_batch_solve(t, th0, spread(0.2_wp, 1, n), spread(1.3_wp, 1, n), spread(0.05_wp, 1, n), &
                         spread(0.04_wp, 1, n), th2, om2, codes2, steps2, st2)
    call tc%check_true(st%code == PENDULA_OK .and. st2%code == PENDULA_OK, 'shared: both ok')
    call tc%check_true(all(th == th2) .and. all(om == om2) .and. all(steps == steps2), &
                       'shared: one-element parameters equal full arrays')
  end subroutine test_shared_parameters

  !> No states: success and nothing written.  One output time: the initial state.
  subroutine test_empty_and_single_time()
    real(wp) :: th(nt, 0), om(nt, 0), th1(1, 2), om1(1, 2)
    integer :: codes(0), codes1(2)
    integer(i8) :: steps(0), steps1(2)
    type(status_t) :: st
    real(wp) :: empty(0)
    call rk4_batch_solve(t, empty, empty, [1.0_wp], [0.1_wp], [0.05_wp], th, om, codes, steps, st, threads=2)
    call tc%check_true(st%code == PENDULA_OK, 'empty batch: ok')
    call rk4_batch_solve([2.0_wp], [0.5_wp, -0.5_wp], [1.0_wp, 2.0_wp], [1.0_wp], [0.1_wp], [0.05_wp], &
                         th1, om1, codes1, steps1, st)
    call tc%check_true(st%code == PENDULA_OK .and. all(th1(1, :) == [0.5_wp, -0.5_wp]) .and. &
                       all(om1(1, :) == [1.0_wp, 2.0_wp]) .and. all(steps1 == 0), 'single output time: initial state')
  end subroutine test_empty_and_single_time

  !> A raised cancel flag stops the call: every state PENDULA_ERR_CANCELLED
  !> with NaN outputs.  Without it, the progress counter ends at n.
  subroutine test_cancel_and_progress()
    integer, parameter :: n = 3*RK4_BATCH_LANES + 1
    real(wp) :: th0(n), th(nt, n), om(nt, n)
    integer :: codes(n), first
    integer(i8) :: steps(n)
    integer(int64) :: control(CONTROL_SIZE)
    type(status_t) :: st
    th0 = 0.3_wp
    control = 0
    control(CONTROL_CANCEL) = 1
    call rk4_batch_solve(t, th0, [0.0_wp], [1.0_wp], [0.1_wp], [0.05_wp], th, om, codes, steps, st, &
                         threads=2, control=control, first_failed=first)
    call tc%check_true(st%code == PENDULA_ERR_CANCELLED .and. first == 1, 'cancel: summary cancelled')
    call tc%check_true(all(codes == PENDULA_ERR_CANCELLED) .and. all(ieee_is_nan(th)) .and. all(ieee_is_nan(om)), &
                       'cancel: every state cancelled, NaN outputs')
    call tc%check_true(control(CONTROL_PROGRESS) == 0, 'cancel: no progress')
    ! a cancelled call reports the cancel first, even when a state failed before it
    th0(2) = ieee_value(1.0_wp, ieee_quiet_nan)
    call rk4_batch_solve(t, th0, [0.0_wp], [1.0_wp], [0.1_wp], [0.05_wp], th, om, codes, steps, st, &
                         threads=1, control=control, first_failed=first)
    call tc%check_true(st%code == PENDULA_ERR_CANCELLED .and. first == 1 .and. codes(2) == PENDULA_ERR_NONFINITE &
                       .and. count(codes == PENDULA_ERR_CANCELLED) == n - 1, 'cancel: reported before a failed state')
    th0(2) = 0.3_wp
    control = 0
    call rk4_batch_solve(t, th0, [0.0_wp], [1.0_wp], [0.1_wp], [0.05_wp], th, om, codes, steps, st, &
                         threads=1, control=control)
    call tc%check_true(st%code == PENDULA_OK .and. all(codes == PENDULA_OK), 'progress: ok')
    call tc%check_true(control(CONTROL_PROGRESS) == n, 'progress: counts every state')
  end subroutine test_cancel_and_progress

  !> Bad t, shapes or threads refuse the whole call: first_failed = 0 and every
  !> code is the call's.
  subroutine test_refused_calls()
    real(wp) :: th(nt, 2), om(nt, 2), th3(nt, 3)
    integer :: codes(2), first
    integer(i8) :: steps(2)
    type(status_t) :: st
    real(wp) :: t_bad(nt)
    t_bad = t
    t_bad(5) = t_bad(4)
    call rk4_batch_solve(t_bad, [0.1_wp, 0.2_wp], [0.0_wp], [1.0_wp], [0.1_wp], [0.05_wp], th, om, codes, steps, st, &
                         first_failed=first)
    call tc%check_true(st%code == PENDULA_ERR_ORDER .and. first == 0 .and. all(codes == PENDULA_ERR_ORDER) .and. &
                       all(ieee_is_nan(th)) .and. all(ieee_is_nan(om)), 'refused: t not increasing, NaN outputs')
    call rk4_batch_solve(t, [0.1_wp, 0.2_wp], [0.0_wp, 1.0_wp, 2.0_wp], [1.0_wp], [0.1_wp], [0.05_wp], th, om, &
                         codes, steps, st, first_failed=first)
    call tc%check_true(st%code == PENDULA_ERR_SIZE .and. first == 0, 'refused: omega0 of a third size')
    call tc%check_true(index(st%message, 'omega0') > 0, 'refused: message names omega0')
    call rk4_batch_solve(t, [0.1_wp, 0.2_wp], [0.0_wp], [1.0_wp], [0.1_wp], [0.05_wp], th3(:, 1:2), om, codes, &
                         steps, st, threads=-1, first_failed=first)
    call tc%check_true(st%code == PENDULA_ERR_DOMAIN .and. index(st%message, 'threads = -1') == 1, &
                       'refused: threads = -1')
    call rk4_batch_solve(t, [0.1_wp, 0.2_wp], [0.0_wp], [1.0_wp], [0.1_wp], [0.05_wp], th(1:nt - 1, :), &
                         om(1:nt - 1, :), codes, steps, st)
    call tc%check_true(st%code == PENDULA_ERR_SIZE .and. index(st%message, 'theta and omega') == 1, &
                       'refused: theta shape')
  end subroutine test_refused_calls

end program test_rk4_batch
