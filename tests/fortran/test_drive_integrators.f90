!> rk4_solve, rk4_batch_solve, cvode_solve and cvode_batch_solve with a drive
!> (pendula_drive): RK4 equals driven_solve with N = ceiling(T/h) steps per
!> period bit for bit; a batch (one drive per state, mixed kinds and steps
!> per period, and one drive for all) equals the scalar calls bit for bit;
!> CVODE agrees with the RK4 run refined by Richardson to its tolerance;
!> the linear closed form at small amplitude; a refused step names h; a
!> failed state of a driven batch is NaN.
program test_drive_integrators
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_value, ieee_quiet_nan
  use pendula_kinds, only: wp, i8
  use pendula_status, only: status_t, PENDULA_OK, PENDULA_ERR_UNSTABLE, PENDULA_ERR_SIZE, PENDULA_ERR_DOMAIN
  use pendula_ode, only: ode_stats_t, PENDULA_CVODE_ADAMS
  use pendula_rk4, only: rk4_solve, rk4_final_state
  use pendula_rk4_batch, only: rk4_batch_solve
  use pendula_cvode, only: cvode_solve, cvode_available
  use pendula_cvode_batch, only: cvode_batch_solve
  use pendula_drive, only: drive_t, DRIVE_TORQUE, DRIVE_PIVOT
  use pendula_driven, only: driven_solve
  use pendula_driven_linear, only: driven_linear_solve
  use pendula_testing, only: checker_t, time_grid
  implicit none
  type(checker_t) :: tc
  type(drive_t), parameter :: torque = drive_t(DRIVE_TORQUE, 1.15_wp, 2.0_wp/3, 0.3_wp)
  type(drive_t), parameter :: pivot = drive_t(DRIVE_PIVOT, 0.1_wp, 20.0_wp, 0.7_wp)
  call test_rk4_is_the_driven_kernel()
  call test_batches()
  call test_cvode()
  call test_linear()
  call test_refused()
  call tc%report('test_drive_integrators')

contains

  subroutine test_rk4_is_the_driven_kernel()
    real(wp) :: t(7), th(7), om(7), tr(7), orr(7), te, oe
    type(ode_stats_t) :: s
    type(status_t) :: st, st2
    t = time_grid(0.0_wp, 1.7_wp, 7)
    ! h = T/100 exactly: N = 100 steps per period
    call rk4_solve(t, 0.2_wp, 0.1_wp, 1.0_wp, 0.5_wp, (2*acos(-1.0_wp)/torque%frequency)/100, th, om, s, st, drive=torque)
    call driven_solve(t, 0.2_wp, 0.1_wp, 1.0_wp, 0.5_wp, torque, tr, orr, st2, nsteps=100)
    call tc%check_status(st, PENDULA_OK, '', 'rk4_solve with a torque drive')
    call tc%check_true(all(th == tr) .and. all(om == orr), 'rk4_solve(drive) == driven_solve(N = T/h) bit for bit')
    call tc%check_true(s%steps > 0 .and. s%rhs_evals == 4*s%steps, 'rk4_solve(drive) counts its steps')
    call rk4_final_state(0.0_wp, t(7), 0.2_wp, 0.1_wp, 1.0_wp, 0.5_wp, (2*acos(-1.0_wp)/torque%frequency)/100, te, oe, s, &
                         st, drive=torque)
    call tc%check_true(te == th(7) .and. oe == om(7), 'rk4_final_state(drive) == rk4_solve(drive)')
  end subroutine test_rk4_is_the_driven_kernel

  subroutine test_batches()
    integer, parameter :: n = 5
    real(wp) :: t(6), th(6, n), om(6, n), th1(6), om1(6), h(n), th0(n)
    integer :: codes(n), i
    integer(i8) :: steps(n)
    type(drive_t) :: d(n)
    type(ode_stats_t) :: s, sc(n)
    type(status_t) :: st
    logical :: same
    t = time_grid(0.0_wp, 2.1_wp, 6)
    d = [torque, pivot, drive_t(DRIVE_TORQUE, 0.5_wp, 1.3_wp, 0.0_wp), torque, pivot]
    h = [0.02_wp, 0.01_wp, 0.02_wp, 0.05_wp, 0.01_wp]
    th0 = [0.2_wp, -1.0_wp, 3.0_wp, 0.2_wp, 0.4_wp]
    call rk4_batch_solve(t, th0, [0.1_wp], [1.0_wp], [0.4_wp], h, th, om, codes, steps, st, threads=2, drive=d)
    call tc%check_status(st, PENDULA_OK, '', 'rk4_batch_solve with mixed drives')
    same = .true.
    do i = 1, n
      call rk4_solve(t, th0(i), 0.1_wp, 1.0_wp, 0.4_wp, h(i), th1, om1, s, st, drive=d(i))
      same = same .and. all(th1 == th(:, i)) .and. all(om1 == om(:, i)) .and. s%steps == steps(i)
    end do
    call tc%check_true(same, 'rk4_batch_solve(drive(n)) == rk4_solve per state bit for bit')
    call rk4_batch_solve(t, th0, [0.1_wp], [1.0_wp], [0.4_wp], [0.02_wp], th, om, codes, steps, st, drive=[torque])
    call rk4_solve(t, th0(3), 0.1_wp, 1.0_wp, 0.4_wp, 0.02_wp, th1, om1, s, st, drive=torque)
    call tc%check_true(all(th1 == th(:, 3)), 'rk4_batch_solve(drive(1)) == rk4_solve bit for bit')
    call rk4_batch_solve(t, th0, [0.1_wp], [1.0_wp], [0.4_wp], [0.02_wp], th, om, codes, steps, st, drive=d(1:2))
    call tc%check_status(st, PENDULA_ERR_SIZE, 'drive has 2', 'rk4_batch_solve: drive of neither 1 nor n elements')
    call tc%check_true(all(ieee_is_nan(th)) .and. all(ieee_is_nan(om)) .and. all(codes == PENDULA_ERR_SIZE), &
                       'rk4_batch_solve: a refused driven call is NaN')
    ! state 2 refused (a NaN theta0): NaN outputs, no steps; the others as alone
    th0(2) = ieee_value(1.0_wp, ieee_quiet_nan)
    call rk4_batch_solve(t, th0, [0.1_wp], [1.0_wp], [0.4_wp], h, th, om, codes, steps, st, drive=d)
    call tc%check_true(codes(2) /= PENDULA_OK .and. st%code == codes(2) .and. all(ieee_is_nan(th(:, 2))) .and. &
                       all(ieee_is_nan(om(:, 2))) .and. steps(2) == 0 .and. all(codes([1, 3, 4, 5]) == PENDULA_OK) .and. &
                       .not. any(ieee_is_nan(th(:, [1, 3, 4, 5]))), 'rk4_batch_solve(drive): a failed state is NaN')
    th0(2) = -1
    if (.not. cvode_available()) return
    call cvode_batch_solve(t, th0, [0.1_wp], [1.0_wp], [0.4_wp], [1.0e-9_wp], [1.0e-12_wp], PENDULA_CVODE_ADAMS, 100000_i8, &
                           th, om, codes, sc, st, threads=2, drive=d)
    call tc%check_status(st, PENDULA_OK, '', 'cvode_batch_solve with mixed drives')
    same = .true.
    do i = 1, n
      call cvode_solve(t, th0(i), 0.1_wp, 1.0_wp, 0.4_wp, 1.0e-9_wp, 1.0e-12_wp, PENDULA_CVODE_ADAMS, 100000_i8, th1, om1, &
                       s, st, drive=d(i))
      same = same .and. all(th1 == th(:, i)) .and. all(om1 == om(:, i)) .and. s%steps == sc(i)%steps
    end do
    call tc%check_true(same, 'cvode_batch_solve(drive(n)) == cvode_solve per state bit for bit')
  end subroutine test_batches

  ! CVODE at rtol 1e-12 against RK4 with N = 4000 (error ~1e-13 here)
  subroutine test_cvode()
    real(wp) :: t(5), th(5), om(5), tr(5), orr(5)
    type(ode_stats_t) :: s
    type(status_t) :: st
    type(drive_t) :: d(2)
    integer :: k
    if (.not. cvode_available()) return
    t = time_grid(0.0_wp, 0.5_wp, 5)
    d = [torque, pivot]
    do k = 1, 2
      call cvode_solve(t, 0.2_wp, 0.1_wp, 1.0_wp, 0.5_wp, 1.0e-12_wp, 1.0e-14_wp, PENDULA_CVODE_ADAMS, 1000000_i8, th, om, &
                       s, st, drive=d(k))
      call driven_solve(t, 0.2_wp, 0.1_wp, 1.0_wp, 0.5_wp, d(k), tr, orr, st, nsteps=4000)
      call tc%check_true(maxval(abs(th - tr)) <= 1.0e-9_wp, 'cvode_solve(drive) theta against fine RK4')
      call tc%check_true(maxval(abs(om - orr)) <= 1.0e-9_wp, 'cvode_solve(drive) omega against fine RK4')
    end do
  end subroutine test_cvode

  ! F = 1e-6: theta ~ 1e-6 rad, the nonlinearity ~1e-18
  subroutine test_linear()
    real(wp) :: t(9), th(9), om(9), tl(9), ol(9)
    type(ode_stats_t) :: s
    type(status_t) :: st
    type(drive_t), parameter :: small = drive_t(DRIVE_TORQUE, 1.0e-6_wp, 0.8_wp, 0.4_wp)
    t = time_grid(0.0_wp, 5.0_wp, 9)
    call driven_linear_solve(t, 0.0_wp, 0.0_wp, 1.0_wp, 0.5_wp, small, tl, ol, st)
    call rk4_solve(t, 0.0_wp, 0.0_wp, 1.0_wp, 0.5_wp, (2*acos(-1.0_wp)/small%frequency)/2000, th, om, s, st, drive=small)
    call tc%check_true(maxval(abs(th - tl)) <= 1.0e-14_wp, 'rk4_solve(drive) at small amplitude: the linear closed form')
    if (.not. cvode_available()) return
    call cvode_solve(t, 0.0_wp, 0.0_wp, 1.0_wp, 0.5_wp, 1.0e-12_wp, 1.0e-20_wp, PENDULA_CVODE_ADAMS, 1000000_i8, th, om, &
                     s, st, drive=small)
    call tc%check_true(maxval(abs(th - tl)) <= 1.0e-14_wp, 'cvode_solve(drive) at small amplitude: the linear closed form')
  end subroutine test_linear

  subroutine test_refused()
    real(wp) :: th(2), om(2)
    type(ode_stats_t) :: s
    type(status_t) :: st
    call rk4_solve([0.0_wp, 10.0_wp], 0.2_wp, 0.0_wp, 10.0_wp, 0.0_wp, 1.0_wp, th, om, s, st, drive=torque)
    call tc%check_status(st, PENDULA_ERR_UNSTABLE, 'h = ', 'rk4_solve(drive): a step too large names h')
    call rk4_solve([0.0_wp, 10.0_wp], 0.2_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0e-9_wp, th, om, s, st, drive=torque)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'too small for the drive period', 'rk4_solve(drive): more than 1e6 steps a period')
  end subroutine test_refused

end program test_drive_integrators
