!> The Taylor integrator (pendula_taylor, pendula_taylor_batch): against the
!> exact undamped motion (libration, rotation, tiny swing), the error estimate
!> bounding the true error and meeting tol, backward integration returning to
!> the start, events at the exact quarter periods, the batch bit-identical to
!> the scalar call, and refused arguments naming themselves.
program test_taylor
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use pendula_kinds, only: wp, i8
  use pendula_status, only: status_t, PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_ORDER, PENDULA_ERR_NONFINITE, &
                            PENDULA_ERR_MAXSTEPS, PENDULA_ERR_CANCELLED
  use pendula_control, only: CONTROL_SIZE, CONTROL_CANCEL, CONTROL_PROGRESS
  use pendula_ode, only: ode_stats_t, PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO
  use pendula, only: taylor_solve, taylor_solve_events, taylor_batch_solve, undamped_solve
  use pendula_testing, only: checker_t, time_grid
  implicit none
  type(checker_t) :: tc
  integer, parameter :: nt = 61
  real(wp) :: t(nt)

  t = time_grid(0.0_wp, 0.5_wp, nt)   ! 0 .. 30 s
  call test_exact()
  call test_backward()
  call test_events()
  call test_batch_identity()
  call test_refused()
  call test_cancel_and_progress()
  call tc%report('test_taylor')

contains

  !> gamma = 0 against undamped_solve (exact to a few ulps): error <= estimate
  !> (plus the reference's own 4 ulps) and estimate <= tol.
  subroutine test_exact()
    real(wp), parameter :: th0(4) = [2.5_wp, 1.0e-6_wp, 0.0_wp, -1.0_wp]
    real(wp), parameter :: om0(4) = [0.0_wp, 0.0_wp, 3.0_wp, 0.5_wp]
    real(wp), parameter :: tols(4) = [1.0e-12_wp, 1.0e-14_wp, 1.0e-11_wp, 1.0e-9_wp]
    real(wp) :: th(nt), om(nt), er(nt), the(nt), ome(nt), w0, e, slack
    type(ode_stats_t) :: s
    type(status_t) :: st
    integer :: k, i, p
    w0 = sqrt(2.0_wp)
    do k = 1, 4
      call taylor_solve(t, th0(k), om0(k), w0, 0.0_wp, tols(k), th, om, er, s, st, order=p)
      call tc%check_true(st%code == PENDULA_OK, 'exact: status')
      call undamped_solve(t, th0(k), om0(k), w0, the, ome, st)
      do i = 1, nt
        slack = 4*epsilon(1.0_wp)*max(abs(the(i)), abs(ome(i))/w0)
        e = max(abs(th(i) - the(i)), abs(om(i) - ome(i))/w0)
        call tc%check_true(e <= er(i) + slack, 'exact: error within the estimate')
        call tc%check_true(er(i) <= tols(k), 'exact: estimate within tol')
      end do
      call tc%check_true(p >= 8 .and. s%steps > 0 .and. s%steps < 1000, 'exact: order and steps')
    end do
  end subroutine test_exact

  !> Forward over 30 s, then backward from the end state over the reversed
  !> grid: back to the start within the two estimates.
  subroutine test_backward()
    real(wp) :: th(nt), om(nt), er(nt), thb(nt), omb(nt), erb(nt), tb(nt)
    type(ode_stats_t) :: s
    type(status_t) :: st
    tb = t(nt:1:-1)
    call taylor_solve(t, 2.0_wp, 0.5_wp, 1.3_wp, 0.2_wp, 1.0e-13_wp, th, om, er, s, st)
    call taylor_solve(tb, th(nt), om(nt), 1.3_wp, 0.2_wp, 1.0e-13_wp, thb, omb, erb, s, st)
    call tc%check_true(st%code == PENDULA_OK, 'backward: status')
    call tc%check_true(abs(thb(nt) - 2.0_wp) <= er(nt) + erb(nt), 'backward: theta returns')
    call tc%check_true(abs(omb(nt) - 0.5_wp) <= 1.3_wp*(er(nt) + erb(nt)), 'backward: omega returns')
    call tc%check_true(abs(thb(31) - th(31)) <= er(31) + er(nt) + erb(31), 'backward: midpoint')
  end subroutine test_backward

  !> theta0 = 1, Omega0 = 0, gamma = 0: turning points at k T/2, passes
  !> through the bottom at T/4 + k T/2 (T the exact period).
  subroutine test_events()
    real(wp) :: th(2), om(2), er(2), et(20), eth(20), eom(20), period
    integer :: ek(20), nev, i, nz, ntp
    logical :: trunc
    type(ode_stats_t) :: s
    type(status_t) :: st
    period = 6.699975664370452712701211_wp   ! 4 K(sin(1/2)**2), mpmath at 30 digits
    call taylor_solve_events([0.0_wp, 20.0_wp], 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0e-13_wp, th, om, er, &
                             et, ek, eth, eom, nev, trunc, s, st)
    call tc%check_true(st%code == PENDULA_OK .and. .not. trunc, 'events: status')
    call tc%check_true(nev == 2*floor(20/(period/2)) + merge(1, 0, mod(20.0_wp, period/2) > period/4), &
                       'events: count')
    nz = 0
    ntp = 0
    do i = 1, nev
      if (ek(i) == PENDULA_EVENT_TURNING) then
        ntp = ntp + 1
        call tc%check_close(et(i), ntp*period/2, 0.0_wp, 1.0e-12_wp, 'events: turning time')
        call tc%check_close(abs(eth(i)), 1.0_wp, 0.0_wp, 1.0e-12_wp, 'events: amplitude')
      else
        call tc%check_true(ek(i) == PENDULA_EVENT_ZERO, 'events: kind')
        call tc%check_close(et(i), period/4 + nz*period/2, 0.0_wp, 1.0e-12_wp, 'events: bottom time')
        nz = nz + 1
      end if
      if (i > 1) call tc%check_true(et(i) > et(i - 1), 'events: in time order')
    end do
  end subroutine test_events

  !> A batch of mixed states and tolerances: each state bit-identical to
  !> taylor_solve, for 1 and 2 threads; a bad state fails alone.
  subroutine test_batch_identity()
    integer, parameter :: n = 7
    real(wp), parameter :: th0(n) = [0.1_wp, 2.5_wp, 3.1_wp, -1.0_wp, 0.0_wp, 1.0e-8_wp, 1.0_wp]
    real(wp), parameter :: om0(n) = [0.0_wp, 0.0_wp, 0.0_wp, 2.0_wp, 4.0_wp, 0.0_wp, 0.0_wp]
    real(wp), parameter :: gam(n) = [0.0_wp, 0.1_wp, 0.01_wp, 1.0_wp, 0.0_wp, 5.0_wp, -1.0_wp]
    real(wp), parameter :: tols(n) = [1.0e-8_wp, 1.0e-12_wp, 1.0e-10_wp, 1.0e-14_wp, 1.0e-6_wp, 1.0e-12_wp, 1.0e-9_wp]
    real(wp) :: th(nt, n), om(nt, n), er(nt, n), th1(nt), om1(nt), er1(nt)
    integer :: codes(n), ord(n), threads, i, first, p
    integer(i8) :: steps(n)
    type(ode_stats_t) :: s
    type(status_t) :: st
    do threads = 1, 2
      call taylor_batch_solve(t, th0, om0, [1.4_wp], gam, tols, th, om, er, codes, steps, ord, st, &
                              threads=threads, first_failed=first)
      call tc%check_true(st%code == PENDULA_ERR_DOMAIN .and. first == n, 'batch: the bad state is reported')
      call tc%check_true(index(st%message, 'gamma') > 0, 'batch: message names gamma')
      do i = 1, n - 1
        call taylor_solve(t, th0(i), om0(i), 1.4_wp, gam(i), tols(i), th1, om1, er1, s, st, order=p)
        call tc%check_true(codes(i) == PENDULA_OK, 'batch: state ok')
        call tc%check_true(all(th(:, i) == th1) .and. all(om(:, i) == om1) .and. all(er(:, i) == er1), &
                           'batch: bit-identical to the scalar call')
        call tc%check_true(steps(i) == s%steps .and. ord(i) == p, 'batch: same steps and order')
      end do
      call tc%check_true(all(ieee_is_nan(th(:, n))) .and. all(ieee_is_nan(om(:, n))) .and. all(ieee_is_nan(er(:, n))), &
                         'batch: failed state NaN')
    end do
  end subroutine test_batch_identity

  subroutine test_refused()
    real(wp) :: th(3), om(3), er(3)
    type(ode_stats_t) :: s
    type(status_t) :: st
    call taylor_solve([0.0_wp, 1.0_wp, 2.0_wp], 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, th, om, er, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'tol', 'refused: tol = 0')
    call taylor_solve([0.0_wp, 1.0_wp, 2.0_wp], 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 2.0_wp, th, om, er, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'tol', 'refused: tol > 1')
    call taylor_solve([0.0_wp, 1.0_wp, 0.5_wp], 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0e-9_wp, th, om, er, s, st)
    call tc%check_status(st, PENDULA_ERR_ORDER, 'monotonic', 'refused: t turns back')
    call taylor_solve([0.0_wp, 1.0_wp, 2.0_wp], 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0e-9_wp, th, om, er, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'w0', 'refused: w0 = 0')
    call tc%check_true(all(th == 0) .and. all(er == 0), 'refused: outputs zero')
    call taylor_solve([0.0_wp, 1.0e3_wp, 2.0e3_wp], 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0e-9_wp, th, om, er, s, st, &
                      max_steps=5_i8)
    call tc%check_status(st, PENDULA_ERR_MAXSTEPS, 'max_steps', 'refused: step budget')
  end subroutine test_refused

  !> A raised cancel flag stops the scalar call within 128 steps and every
  !> state of a batch; progress counts steps (scalar) and finished states (batch).
  subroutine test_cancel_and_progress()
    real(wp) :: th(2), om(2), er(2), thb(2, 3), omb(2, 3), erb(2, 3)
    integer(i8) :: control(CONTROL_SIZE), steps(3)
    integer :: codes(3), ord(3)
    type(ode_stats_t) :: s
    type(status_t) :: st
    control = 0
    call taylor_solve([0.0_wp, 1.0e3_wp], 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0e-9_wp, th, om, er, s, st, &
                      control=control)
    call tc%check_true(st%code == PENDULA_OK .and. control(CONTROL_PROGRESS) > 0 .and. &
                       control(CONTROL_PROGRESS) <= s%steps, 'control: progress counts steps')
    control = 0
    control(CONTROL_CANCEL) = 1
    call taylor_solve([0.0_wp, 1.0e3_wp], 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0e-9_wp, th, om, er, s, st, &
                      control=control)
    call tc%check_status(st, PENDULA_ERR_CANCELLED, 'cancelled', 'control: scalar cancel')
    call tc%check_true(all(th == 0) .and. all(er == 0), 'control: cancelled outputs zero')
    control = 0
    call taylor_batch_solve([0.0_wp, 1.0_wp], [0.1_wp, 0.2_wp, 0.3_wp], [0.0_wp], [1.0_wp], [0.0_wp], [1.0e-9_wp], &
                            thb, omb, erb, codes, steps, ord, st, control=control)
    call tc%check_true(st%code == PENDULA_OK .and. control(CONTROL_PROGRESS) == 3, 'control: batch progress')
    control(CONTROL_CANCEL) = 1
    call taylor_batch_solve([0.0_wp, 1.0_wp], [0.1_wp, 0.2_wp, 0.3_wp], [0.0_wp], [1.0_wp], [0.0_wp], [1.0e-9_wp], &
                            thb, omb, erb, codes, steps, ord, st, control=control)
    call tc%check_true(st%code == PENDULA_ERR_CANCELLED .and. all(codes == PENDULA_ERR_CANCELLED), &
                       'control: batch cancel')
    call tc%check_true(all(ieee_is_nan(thb)) .and. all(ieee_is_nan(omb)) .and. all(ieee_is_nan(erb)), &
                       'control: cancelled batch outputs NaN')
    ! a refused call (t not strictly monotonic): every output NaN, every code the call's
    call taylor_batch_solve([1.0_wp, 1.0_wp], [0.1_wp, 0.2_wp, 0.3_wp], [0.0_wp], [1.0_wp], [0.0_wp], [1.0e-9_wp], &
                            thb, omb, erb, codes, steps, ord, st)
    call tc%check_true(st%code == PENDULA_ERR_ORDER .and. all(codes == PENDULA_ERR_ORDER), 'refused batch: codes')
    call tc%check_true(all(ieee_is_nan(thb)) .and. all(ieee_is_nan(omb)) .and. all(ieee_is_nan(erb)), &
                       'refused batch: outputs NaN')
  end subroutine test_cancel_and_progress

end program test_taylor
