!> The driven pendulum (src/driven): F = 0 against the exact undamped motion
!> and against RK4 of the damped one; fourth-order convergence; batch equal
!> to one state bit for bit; the Lyapunov sum rule (sum = -gamma); the
!> Baker-Gollub chaotic case (largest exponent > 0) and a periodic one whose
!> exponents are ln|mu|/T of the Newton orbit's Floquet multipliers;
!> Kapitza's inverted pendulum stable above a**2 Omega**2/(2 l**2) = w0**2
!> and unstable below; the linear closed form at small amplitude; basins;
!> refused input; NaN (never zero) in every real output of a failed state.
program test_driven
  use, intrinsic :: iso_fortran_env, only: int64
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use pendula_kinds, only: wp
  use pendula_constants, only: pi
  use pendula_status, only: status_t, PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_UNSTABLE, PENDULA_ERR_CANCELLED
  use pendula_control, only: CONTROL_SIZE, CONTROL_CANCEL, CONTROL_PROGRESS
  use pendula_undamped, only: undamped_solve
  use pendula_ode, only: ode_stats_t
  use pendula_rk4, only: rk4_solve
  use pendula_drive, only: drive_t, DRIVE_TORQUE, DRIVE_PIVOT
  use pendula_driven_kernel, only: lane_sincos
  use pendula_driven, only: driven_solve, driven_batch_solve
  use pendula_driven_maps, only: driven_poincare, driven_bifurcation, driven_lyapunov, PARAM_AMPLITUDE
  use pendula_driven_orbits, only: driven_orbits, driven_basins, basin_table, BASIN_UNSETTLED
  use pendula_driven_linear, only: driven_linear_solve, driven_linear_response
  use pendula_testing, only: checker_t, time_grid
  implicit none
  type(checker_t) :: tc
  call test_sincos()
  call test_free()
  call test_order()
  call test_batch_identity()
  call test_lyapunov()
  call test_kapitza()
  call test_linear()
  call test_sections_basins()
  call test_refused()
  call test_cancel()
  call test_failed_states_nan()
  call tc%report('test_driven')

contains

  subroutine test_sincos()
    real(wp) :: x, s, c, worst
    integer :: i
    worst = 0
    do i = -20000, 20000
      x = i*0.0173_wp + 1.0e-3_wp*sin(real(i, wp))
      call lane_sincos(x, s, c)
      worst = max(worst, abs(s - sin(x)), abs(c - cos(x)))
    end do
    call tc%check_true(worst <= 4*epsilon(1.0_wp), 'lane_sincos within 4 eps of libm on |x| < 350')
  end subroutine test_sincos

  ! F = 0: the exact undamped motion (gamma = 0) and RK4 (gamma > 0)
  subroutine test_free()
    real(wp) :: t(41), th(41), om(41), te(41), oe(41), tr(41), orr(41)
    type(status_t) :: st
    type(ode_stats_t) :: s
    t = time_grid(0.0_wp, 0.5_wp, 41)
    call driven_solve(t, 2.0_wp, 0.3_wp, 1.3_wp, 0.0_wp, drive_t(DRIVE_TORQUE, 0.0_wp, 0.7_wp, 0.2_wp), th, om, &
                      st, nsteps=8000)
    call tc%check_true(st%code == PENDULA_OK, 'F = 0 solve ok')
    call undamped_solve(t, 2.0_wp, 0.3_wp, 1.3_wp, te, oe, st)
    call tc%check_true(maxval(abs(th - te)) < 2.0e-12_wp .and. maxval(abs(om - oe)) < 2.0e-12_wp, &
                       'F = 0, gamma = 0 is the exact undamped pendulum to 2e-12 (h**4 error)')
    call driven_solve(t, 2.0_wp, 0.3_wp, 1.3_wp, 0.4_wp, drive_t(DRIVE_PIVOT, 0.0_wp, 0.7_wp, 0.2_wp), th, om, &
                      st, nsteps=8000)
    call rk4_solve(t, 2.0_wp, 0.3_wp, 1.3_wp, 0.4_wp, 1.0e-3_wp, tr, orr, s, st)
    call tc%check_true(maxval(abs(th - tr)) < 1.0e-11_wp .and. maxval(abs(om - orr)) < 1.0e-11_wp, &
                       'a = 0 pivot, gamma = 0.4 is the damped pendulum (vs pendula rk4) to 1e-11')
  end subroutine test_free

  ! error at N, 2N against 16N: ratio 16 (order 4); the Richardson estimate covers the error
  subroutine test_order()
    real(wp) :: t(3), a(3), b(3), c(3), r(3), o(3), et(3), eo(3), e1, e2
    type(status_t) :: st
    type(drive_t) :: d
    t = [0.0_wp, 7.3_wp, 20.0_wp]
    d = drive_t(DRIVE_TORQUE, 1.15_wp, 2.0_wp/3, 0.3_wp)
    call driven_solve(t, 0.2_wp, 0.0_wp, 1.0_wp, 0.5_wp, d, a, o, st, nsteps=40, err_theta=et, err_omega=eo)
    call driven_solve(t, 0.2_wp, 0.0_wp, 1.0_wp, 0.5_wp, d, b, o, st, nsteps=80)
    call driven_solve(t, 0.2_wp, 0.0_wp, 1.0_wp, 0.5_wp, d, r, o, st, nsteps=1280)
    e1 = maxval(abs(a - r))
    e2 = maxval(abs(b - r))
    call tc%check_true(e1/e2 > 13 .and. e1/e2 < 19, 'driven RK4 converges at order 4 (error ratio ~16)')
    ! (from t(2): at the start both the error and its estimate are 0)
    call tc%check_true(all(abs(a(2:) - r(2:))/et(2:) > 0.7_wp) .and. all(abs(a(2:) - r(2:))/et(2:) < 1.3_wp), &
                       'Richardson estimate within 30% of the true error')
    call driven_solve(t, 0.2_wp, 0.0_wp, 1.0_wp, 0.5_wp, d, c, o, st, nsteps=1280)
    call tc%check_true(all(c == r), 'repeatable bit for bit')
  end subroutine test_order

  subroutine test_batch_identity()
    integer, parameter :: n = 13
    real(wp) :: t(5), th0(n), th(5, n), om(5, n), a(5), b(5), fr(n)
    integer :: codes(n), i
    type(status_t) :: st
    logical :: same
    t = [0.0_wp, 1.0_wp, 9.5_wp, 30.0_wp, 31.0_wp]
    do i = 1, n
      th0(i) = -3 + 0.5_wp*i
      fr(i) = 0.5_wp + 0.1_wp*i
    end do
    call driven_batch_solve(t, th0, [0.1_wp], [1.0_wp], [0.3_wp], DRIVE_TORQUE, [1.2_wp], fr, [0.0_wp], 64, &
                            th, om, codes, st, threads=2)
    call tc%check_true(st%code == PENDULA_OK, 'batch ok')
    same = .true.
    do i = 1, n
      call driven_solve(t, th0(i), 0.1_wp, 1.0_wp, 0.3_wp, drive_t(DRIVE_TORQUE, 1.2_wp, fr(i), 0.0_wp), a, b, st, &
                        nsteps=64)
      same = same .and. all(a == th(:, i)) .and. all(b == om(:, i))
    end do
    call tc%check_true(same, 'batch (2 threads, mixed frequencies) == one state, bit for bit')
  end subroutine test_batch_identity

  subroutine test_lyapunov()
    real(wp) :: ly(2, 3), le(2, 3), tp(1), op(1), mu(4, 1), res(1), tper, ly1(2, 1), le1(2, 1)
    integer :: codes(3), per(1), wnd(1), c1(1)
    type(status_t) :: st
    ! sum rule with fine steps (the RK4 map's log det differs from -gamma T by O(h**4))
    call driven_lyapunov([0.2_wp, 1.0_wp, -2.0_wp], [0.0_wp], [1.0_wp], [0.5_wp], DRIVE_TORQUE, [1.15_wp], &
                         [2.0_wp/3], [0.0_wp], 2000, 0, 32, ly, le, codes, st)
    call tc%check_true(st%code == PENDULA_OK, 'lyapunov ok')
    call tc%check_true(maxval(abs(ly(1, :) + ly(2, :) + 0.5_wp)) < 1.0e-10_wp, 'exponents sum to -gamma (1e-10)')
    ! Baker & Gollub, Chaotic Dynamics (1996): q = 2, g = 1.15, omega_D = 2/3 is chaotic
    call driven_lyapunov([0.2_wp], [0.0_wp], [1.0_wp], [0.5_wp], DRIVE_TORQUE, [1.15_wp], [2.0_wp/3], [0.0_wp], &
                         128, 100, 4000, ly1, le1, c1, st)
    call tc%check_true(ly1(1, 1) > 0.05_wp .and. ly1(1, 1) < 0.2_wp, 'Baker-Gollub g = 1.15: largest exponent in (0.05, 0.2)')
    call tc%check_true(le1(1, 1) > 0 .and. le1(1, 1) < 0.02_wp, 'its error estimate is positive and < 0.02')
    ! g = 0.9: a stable period-1 orbit; exponents = ln|mu|/T
    call driven_orbits([0.2_wp], [0.0_wp], [1.0_wp], [0.5_wp], DRIVE_TORQUE, [0.9_wp], [2.0_wp/3], [0.0_wp], 128, &
                       [0], 200, 8, 1.0e-6_wp, per, wnd, tp, op, mu, res, c1, st)
    call tc%check_true(st%code == PENDULA_OK .and. per(1) == 1, 'g = 0.9: period-1 attractor found')
    call tc%check_true(res(1) <= 1.0e-10_wp .and. hypot(mu(1, 1), mu(2, 1)) < 1, 'Newton converged, stable')
    call driven_lyapunov([0.2_wp], [0.0_wp], [1.0_wp], [0.5_wp], DRIVE_TORQUE, [0.9_wp], [2.0_wp/3], [0.0_wp], &
                         128, 200, 2000, ly1, le1, c1, st)
    tper = 3*pi
    call tc%check_close(ly1(1, 1), log(hypot(mu(1, 1), mu(2, 1)))/tper, 0.0_wp, 1.0e-4_wp, &
                        'periodic: lambda1 = ln|mu1|/T')
    call tc%check_close(ly1(2, 1), log(hypot(mu(3, 1), mu(4, 1)))/tper, 0.0_wp, 1.0e-4_wp, &
                        'periodic: lambda2 = ln|mu2|/T')
  end subroutine test_lyapunov

  ! inverted equilibrium (pi, 0) under a fast pivot: stable iff (a/l)**2 Omega**2 / 2 > w0**2 (Kapitza)
  subroutine test_kapitza()
    real(wp) :: tp(2), op(2), mu(4, 2), res(2)
    integer :: per(2), wnd(2), codes(2)
    type(status_t) :: st
    call driven_orbits([pi, pi], [0.0_wp], [1.0_wp], [0.1_wp], DRIVE_PIVOT, [0.1_wp, 0.05_wp], [20.0_wp], [0.0_wp], &
                       128, [1], 0, 1, 1.0e-6_wp, per, wnd, tp, op, mu, res, codes, st)
    call tc%check_true(st%code == PENDULA_OK .and. all(per == 1), 'Kapitza: the inverted state is a period-1 orbit')
    call tc%check_true(hypot(mu(1, 1), mu(2, 1)) < 1, 'Kapitza: a/l = 0.1, Omega = 20 (2 > 1): inverted stable')
    call tc%check_true(hypot(mu(1, 2), mu(2, 2)) > 1, 'Kapitza: a/l = 0.05, Omega = 20 (0.5 < 1): inverted unstable')
  end subroutine test_kapitza

  subroutine test_linear()
    real(wp) :: t(50), a(50), b(50), c(50), d(50), gain, lag
    type(status_t) :: st
    type(drive_t) :: dr
    t = time_grid(0.0_wp, 0.4_wp, 50)
    dr = drive_t(DRIVE_TORQUE, 1.0e-5_wp, 1.3_wp, 0.4_wp)
    call driven_linear_solve(t, 2.0e-5_wp, 0.0_wp, 1.0_wp, 0.2_wp, dr, a, b, st)
    call tc%check_true(st%code == PENDULA_OK, 'linear ok')
    call driven_solve(t, 2.0e-5_wp, 0.0_wp, 1.0_wp, 0.2_wp, dr, c, d, st, nsteps=1000)
    ! the nonlinearity: relative O(theta**2) ~ 1e-9
    call tc%check_true(maxval(abs(a - c)) < 1.0e-13_wp, 'linear closed form = integration at 1e-5 rad')
    call driven_linear_response(1.0_wp, 0.2_wp, 1.0_wp, gain, lag)
    call tc%check_close(gain, 5.0_wp, 1.0e-15_wp, 0.0_wp, 'gain at resonance 1/(gamma w0)')
    call tc%check_close(lag, pi/2, 1.0e-15_wp, 0.0_wp, 'lag at resonance pi/2')
  end subroutine test_linear

  subroutine test_sections_basins()
    integer, parameter :: n = 24
    real(wp) :: ts(5, 3), os(5, 3), mo(3), th0(n), om0(n), at(8), ao(8), am(8)
    integer :: codes(3), lab(n), per(n), wnd(n), natt, ap(8), aw(8), cn(n), i
    integer :: lab2(n), per2(n), wnd2(n), natt2, ap2(8), aw2(8)
    real(wp) :: cyc(2, 8, n), at2(8), ao2(8), am2(8)
    type(status_t) :: st
    call driven_bifurcation(PARAM_AMPLITUDE, [0.9_wp, 1.07_wp, 1.15_wp], 0.2_wp, 0.0_wp, 1.0_wp, 0.5_wp, &
                            DRIVE_TORQUE, 0.0_wp, 2.0_wp/3, 0.0_wp, 128, 0.0_wp, 300, 5, ts, os, mo, codes, st)
    call tc%check_true(st%code == PENDULA_OK, 'bifurcation ok')
    call tc%check_true(maxval(abs(ts(:, 1) - ts(1, 1))) < 1.0e-8_wp, 'g = 0.9: one section point (period 1)')
    call tc%check_true(abs(ts(3, 2) - ts(1, 2)) < 1.0e-6_wp .and. abs(ts(2, 2) - ts(1, 2)) > 1.0e-3_wp, &
                       'g = 1.07: period 2 (Baker & Gollub)')
    call tc%check_true(all(abs(ts) <= pi), 'section angles wrapped to (-pi, pi]')
    do i = 1, n
      th0(i) = -pi + 2*pi*(i - 0.5_wp)/n
      om0(i) = 0.5_wp*modulo(i, 3)
    end do
    call driven_basins(th0, om0, [1.0_wp], [0.5_wp], DRIVE_TORQUE, [0.9_wp], [2.0_wp/3], [0.0_wp], 128, 200, 8, &
                       1.0e-6_wp, lab, per, wnd, natt, ap, aw, at, ao, am, cn, st)
    call tc%check_true(st%code == PENDULA_OK .and. natt >= 1, 'basins ok')
    call tc%check_true(all(lab /= BASIN_UNSETTLED .eqv. per > 0), 'unsettled exactly where no period was found')
    ! the same map in two calls (chunks), its table built from their cycles: identical
    call driven_basins(th0(:n/2), om0(:n/2), [1.0_wp], [0.5_wp], DRIVE_TORQUE, [0.9_wp], [2.0_wp/3], &
                       [0.0_wp], 128, 200, 8, 1.0e-6_wp, lab2(:n/2), per2(:n/2), wnd2(:n/2), natt2, ap2(1:1), aw2(1:1), &
                       at2(1:1), ao2(1:1), am2(1:1), cn(:n/2), st, cycles=cyc(:, :, :n/2))
    call driven_basins(th0(n/2 + 1:), om0(n/2 + 1:), [1.0_wp], [0.5_wp], DRIVE_TORQUE, [0.9_wp], [2.0_wp/3], &
                       [0.0_wp], 128, 200, 8, 1.0e-6_wp, lab2(n/2 + 1:), per2(n/2 + 1:), wnd2(n/2 + 1:), natt2, ap2(1:1), &
                       aw2(1:1), at2(1:1), ao2(1:1), am2(1:1), cn(n/2 + 1:), st, cycles=cyc(:, :, n/2 + 1:))
    call basin_table(per2, wnd2, cyc, [2.0_wp/3], 1.0e-6_wp, lab2, natt2, ap2, aw2, at2, ao2, am2, st)
    call tc%check_true(st%code == PENDULA_OK .and. natt2 == natt .and. all(lab2 == lab) .and. &
                       all(at2(:natt) == at(:natt)) .and. all(am2(:natt) == am(:natt)), 'basin_table of two chunks = one call')
  end subroutine test_sections_basins

  subroutine test_refused()
    real(wp) :: t(3), a(3), b(3)
    type(status_t) :: st
    t = [0.0_wp, 1.0_wp, 2.0_wp]
    call driven_solve(t, 0.0_wp, 0.0_wp, 1.0_wp, 0.1_wp, drive_t(DRIVE_TORQUE, 1.0_wp, -1.0_wp, 0.0_wp), a, b, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'frequency', 'frequency <= 0')
    call driven_solve(t, 0.0_wp, 0.0_wp, 1.0_wp, 0.1_wp, drive_t(7, 1.0_wp, 1.0_wp, 0.0_wp), a, b, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'drive kind', 'unknown kind')
    call driven_solve(t, 0.0_wp, 0.0_wp, 1.0_wp, 0.1_wp, drive_t(DRIVE_TORQUE, 1.0_wp, 0.01_wp, 0.0_wp), a, b, st, &
                      nsteps=8)
    call tc%check_status(st, PENDULA_ERR_UNSTABLE, 'steps_per_period', 'too few steps')
    call driven_solve(t, 0.0_wp, 0.0_wp, -1.0_wp, 0.1_wp, drive_t(), a, b, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'w0', 'w0 < 0')
    call driven_solve([0.0_wp, 0.0_wp], 0.0_wp, 0.0_wp, 1.0_wp, 0.1_wp, drive_t(), a(1:2), b(1:2), st)
    call tc%check_true(st%code /= PENDULA_OK .and. index(st%message, 't') > 0, 't not increasing refused')
  end subroutine test_refused

  ! a cancel flag raised before the call: every state unfinished, status says so, progress 0
  subroutine test_cancel()
    real(wp) :: ly(2, 9), le(2, 9), th0(9)
    integer :: codes(9), i
    integer(int64) :: control(CONTROL_SIZE)
    type(status_t) :: st
    th0 = [(0.1_wp*i, i=1, 9)]
    control = 0
    control(CONTROL_CANCEL) = 1
    call driven_lyapunov(th0, [0.0_wp], [1.0_wp], [0.5_wp], DRIVE_TORQUE, &
                         [1.15_wp], [2.0_wp/3], [0.0_wp], 32, 0, 64, ly, le, codes, st, control=control)
    call tc%check_status(st, PENDULA_ERR_CANCELLED, 'cancelled', 'cancelled lyapunov')
    call tc%check_true(all(codes == PENDULA_ERR_CANCELLED) .and. control(CONTROL_PROGRESS) == 0, &
                       'every state unfinished, no progress')
    control = 0
    call driven_lyapunov(th0, [0.0_wp], [1.0_wp], [0.5_wp], DRIVE_TORQUE, &
                         [1.15_wp], [2.0_wp/3], [0.0_wp], 32, 0, 64, ly, le, codes, st, control=control, threads=2)
    call tc%check_true(st%code == PENDULA_OK .and. control(CONTROL_PROGRESS) == 9, 'progress counts the 9 states')
  end subroutine test_cancel

  ! A state refused among good ones (w0 = -1), a cancelled call and a refused
  ! call: every real output of a failed state is NaN (a caller who ignores the
  ! codes reads no plausible number), the good states' outputs are finite.
  subroutine test_failed_states_nan()
    real(wp) :: t(4), th(4, 3), om(4, 3), et(4, 3), eo(4, 3), ts(5, 3), os(5, 3), mo(3), ly(2, 3), le(2, 3)
    real(wp) :: tp(3), op(3), mu(4, 3), res(3), w0(3)
    integer :: codes(3), per(3), wnd(3), i
    integer(int64) :: control(CONTROL_SIZE)
    type(status_t) :: st
    t = [0.0_wp, 1.0_wp, 2.0_wp, 3.0_wp]
    w0 = [1.0_wp, -1.0_wp, 1.0_wp]
    call driven_batch_solve(t, [0.1_wp, 0.2_wp, 0.3_wp], [0.0_wp], w0, [0.3_wp], DRIVE_TORQUE, [1.2_wp], [0.7_wp], &
                            [0.0_wp], 64, th, om, codes, st, err_theta=et, err_omega=eo)
    call tc%check_true(st%code == PENDULA_ERR_DOMAIN .and. all(codes == [PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_OK]), &
                       'nan: batch with a refused state')
    call tc%check_true(all(ieee_is_nan(th(:, 2))) .and. all(ieee_is_nan(om(:, 2))) .and. all(ieee_is_nan(et(:, 2))) &
                       .and. all(ieee_is_nan(eo(:, 2))), 'nan: the refused state''s series and errors are NaN')
    call tc%check_true(.not. any(ieee_is_nan(th(:, [1, 3]))) .and. .not. any(ieee_is_nan(om(:, [1, 3]))), &
                       'nan: the good states are numbers')
    call driven_poincare([0.1_wp, 0.2_wp, 0.3_wp], [0.0_wp], w0, [0.3_wp], DRIVE_TORQUE, [1.2_wp], [0.7_wp], [0.0_wp], &
                         64, 0.0_wp, 2, 5, ts, os, mo, codes, st)
    call tc%check_true(codes(2) == PENDULA_ERR_DOMAIN .and. all(ieee_is_nan(ts(:, 2))) .and. all(ieee_is_nan(os(:, 2))) &
                       .and. ieee_is_nan(mo(2)) .and. .not. any(ieee_is_nan(ts(:, [1, 3]))) .and. .not. ieee_is_nan(mo(1)), &
                       'nan: poincare section of the refused state')
    call driven_lyapunov([0.1_wp, 0.2_wp, 0.3_wp], [0.0_wp], w0, [0.3_wp], DRIVE_TORQUE, [1.2_wp], [0.7_wp], [0.0_wp], &
                         32, 0, 16, ly, le, codes, st)
    call tc%check_true(codes(2) == PENDULA_ERR_DOMAIN .and. all(ieee_is_nan(ly(:, 2))) .and. all(ieee_is_nan(le(:, 2))) &
                       .and. .not. any(ieee_is_nan(ly(:, [1, 3]))), 'nan: lyapunov exponents of the refused state')
    call driven_orbits([0.1_wp, 0.2_wp, 0.3_wp], [0.0_wp], w0, [0.3_wp], DRIVE_TORQUE, [0.2_wp], [0.7_wp], [0.0_wp], &
                       64, [0], 50, 4, 1.0e-6_wp, per, wnd, tp, op, mu, res, codes, st)
    call tc%check_true(codes(2) == PENDULA_ERR_DOMAIN .and. per(2) == 0 .and. wnd(2) == 0 .and. ieee_is_nan(tp(2)) .and. &
                       ieee_is_nan(op(2)) .and. all(ieee_is_nan(mu(:, 2))) .and. ieee_is_nan(res(2)) .and. &
                       .not. ieee_is_nan(tp(1)) .and. per(1) == 1, 'nan: orbit outputs of the refused state')
    ! cancelled before the start: every state unfinished, every output NaN
    control = 0
    control(CONTROL_CANCEL) = 1
    call driven_batch_solve(t, [0.1_wp, 0.2_wp, 0.3_wp], [0.0_wp], [1.0_wp], [0.3_wp], DRIVE_TORQUE, [1.2_wp], [0.7_wp], &
                            [0.0_wp], 64, th, om, codes, st, control=control)
    call tc%check_true(all(codes == PENDULA_ERR_CANCELLED) .and. all(ieee_is_nan(th)) .and. all(ieee_is_nan(om)), &
                       'nan: cancelled states')
    ! refused call (t not increasing): every state's code is the call's, every output NaN
    call driven_batch_solve([(1.0_wp, i=1, 4)], [0.1_wp, 0.2_wp, 0.3_wp], [0.0_wp], [1.0_wp], [0.3_wp], DRIVE_TORQUE, &
                            [1.2_wp], [0.7_wp], [0.0_wp], 64, th, om, codes, st)
    call tc%check_true(st%code /= PENDULA_OK .and. all(codes == st%code) .and. all(ieee_is_nan(th)) .and. &
                       all(ieee_is_nan(om)), 'nan: refused call')
  end subroutine test_failed_states_nan

end program test_driven
