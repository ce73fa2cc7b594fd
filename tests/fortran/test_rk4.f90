!> RK4 for the nonlinear damped pendulum: order 4, the text's section 2.2
!> scenario against an mpmath (30-digit Taylor series) reference, energy for
!> gamma = 0, the linear damped closed form for small amplitude, the stability
!> refusal and its limits, the final-state mode and bad input.
program test_rk4
  use pendula_kinds, only: wp, i8
  use pendula_status, only: status_t, PENDULA_OK, PENDULA_ERR_UNSTABLE, PENDULA_ERR_DOMAIN, &
                            PENDULA_ERR_NONFINITE, PENDULA_ERR_ORDER, PENDULA_ERR_SIZE
  use pendula_ode, only: ode_stats_t, linear_eigenvalues
  use pendula_rk4, only: rk4_solve, rk4_final_state, rk4_max_stable_step, rk4_stability_function
  use pendula_linear_damped, only: linear_damped_t, linear_damped_init, linear_damped_eval
  use pendula_testing, only: checker_t
  use pendula_test_data, only: w0 => text_w0, ref_th => text_ref_theta, ref_om => text_ref_omega
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  implicit none
  type(checker_t) :: tc

  call test_order()
  call test_text_scenario()
  call test_energy_undamped()
  call test_linear_small_amplitude()
  call test_stability()
  call test_final_state()
  call test_bad_input()
  call tc%report('test_rk4')

contains

  !> Error at t = 10 against the mpmath value for h = 0.1 ... 0.001; the
  !> least-squares slope of log(err) vs log(h) must be 4 +- 0.1.
  subroutine test_order()
    real(wp), parameter :: hs(7) = [0.1_wp, 0.05_wp, 0.02_wp, 0.01_wp, 0.005_wp, 0.002_wp, 0.001_wp]
    real(wp) :: th(2), om(2), err(7), x(7), y(7), slope
    type(ode_stats_t) :: s
    type(status_t) :: st
    integer :: k
    character(len=80) :: line
    do k = 1, size(hs)
      call rk4_solve([0.0_wp, 10.0_wp], 0.0_wp, 2.0_wp, w0, 0.01_wp/0.1_wp, hs(k), th, om, s, st)
      call tc%check_true(st%code == PENDULA_OK, 'order: solve ok')
      err(k) = max(abs(th(2) - ref_th(1, 1)), abs(om(2) - ref_om(1, 1)))
      call tc%check_true(s%steps == nint(10/hs(k), i8), 'order: steps = 10/h')
      write (line, '(a, f6.3, a, es10.3)') '  h = ', hs(k), '  error at t=10: ', err(k)
      write (*, '(a)') trim(line)
    end do
    x = log(hs)
    y = log(err)
    slope = sum((x - sum(x)/7)*(y - sum(y)/7))/sum((x - sum(x)/7)**2)
    write (*, '(a, f7.4)') '  order-of-convergence slope: ', slope
    call tc%check_true(abs(slope - 4) < 0.1_wp, 'order: slope within 0.1 of 4')
  end subroutine test_order

  !> The text's scenario (g = 9.8, l = 4.9, m = 0.1, b = 0.01 and 0.05,
  !> theta0 = 0, Omega0 = 2, h = 0.05, t <= 30) within 1e-5 rad of mpmath.
  subroutine test_text_scenario()
    real(wp) :: t(601), th(601), om(601), gam
    type(ode_stats_t) :: s
    type(status_t) :: st
    integer :: i, ib, k
    do i = 1, 601
      t(i) = (i - 1)*0.05_wp
    end do
    do ib = 1, 2
      gam = merge(0.01_wp, 0.05_wp, ib == 1)/0.1_wp
      call rk4_solve(t, 0.0_wp, 2.0_wp, w0, gam, 0.05_wp, th, om, s, st)
      call tc%check_true(st%code == PENDULA_OK, 'text scenario: ok')
      call tc%check_true(s%steps == 600 .and. s%rhs_evals == 2400, 'text scenario: 600 steps, 2400 rhs')
      do k = 1, 3
        i = 200*k + 1
        call tc%check_close(th(i), ref_th(k, ib), 0.0_wp, 1.0e-5_wp, 'text scenario theta vs mpmath')
        call tc%check_close(om(i), ref_om(k, ib), 0.0_wp, 1.0e-5_wp, 'text scenario omega vs mpmath')
      end do
    end do
  end subroutine test_text_scenario

  !> gamma = 0: the energy Omega**2/2 + w0**2 (1 - cos theta) is conserved by
  !> the flow; RK4 at h = 0.01 keeps it to ~1e-9 (relative) over 100 s (also near the
  !> separatrix and over the top).
  subroutine test_energy_undamped()
    real(wp) :: t(1001), th(1001), om(1001), e(1001), om0
    real(wp), parameter :: om0s(3) = [1.0_wp, 2.8_wp, 3.5_wp]
    type(ode_stats_t) :: s
    type(status_t) :: st
    integer :: i, k
    do i = 1, 1001
      t(i) = (i - 1)*0.1_wp
    end do
    do k = 1, 3
      om0 = om0s(k)
      call rk4_solve(t, 0.3_wp, om0, w0, 0.0_wp, 0.01_wp, th, om, s, st)
      call tc%check_true(st%code == PENDULA_OK, 'energy: ok')
      e = om**2/2 + w0**2*(1 - cos(th))
      call tc%check_true(maxval(abs(e - e(1))) < 1.0e-8_wp*e(1), 'energy conserved (gamma = 0)')
    end do
  end subroutine test_energy_undamped

  !> theta0 = 1e-4: the nonlinear motion is the linear damped one (text
  !> section 2.1) up to theta0**3/16 ~ 1e-13 rad; with RK4's error at h = 0.01
!> the agreement is 5e-7 relative to theta0 in each regime.
  subroutine test_linear_small_amplitude()
    real(wp) :: t(201), th(201), om(201), lt(201), lo(201), gam
    real(wp), parameter :: ratio(3) = [0.3_wp, 2.0_wp, 5.0_wp]
    type(linear_damped_t) :: sol
    type(ode_stats_t) :: s
    type(status_t) :: st, st2
    integer :: i, k
    do i = 1, 201
      t(i) = (i - 1)*0.1_wp
    end do
    do k = 1, 3
      gam = ratio(k)*w0
      call rk4_solve(t, 1.0e-4_wp, -2.0e-4_wp, w0, gam, 0.01_wp, th, om, s, st)
      call linear_damped_init(sol, 1.0e-4_wp, -2.0e-4_wp, w0, gam, st2)
      call linear_damped_eval(sol, t, lt, lo, st2)
      call tc%check_true(st%code == PENDULA_OK .and. st2%code == PENDULA_OK, 'small amplitude: ok')
      call tc%check_true(maxval(abs(th - lt)) < 5.0e-11_wp, 'small amplitude theta vs linear closed form')
      call tc%check_true(maxval(abs(om - lo)) < 5.0e-11_wp, 'small amplitude omega vs linear closed form')
    end do
  end subroutine test_linear_small_amplitude

  !> Largest stable step: 2.78529356 / |lambda| on the real axis, 2 sqrt(2)/w0
  !> on the imaginary one; |R| = 1 there and > 1 just beyond; refusal above it.
  subroutine test_stability()
    real(wp) :: hmax, th(3), om(3), gam
    complex(wp) :: l1, l2
    type(ode_stats_t) :: s
    type(status_t) :: st
    call rk4_max_stable_step(w0, 0.0_wp, hmax, st)
    call tc%check_close(hmax*w0, 2*sqrt(2.0_wp), 1.0e-13_wp, 0.0_wp, 'h_max w0 = 2 sqrt 2 (gamma = 0)')
    gam = 1.0e4_wp*w0
    call rk4_max_stable_step(w0, gam, hmax, st)
    call linear_eigenvalues(w0, gam, l1, l2)
    call tc%check_close(hmax*abs(l1), 2.785293563405281624_wp, 1.0e-12_wp, 0.0_wp, &
                        'h_max |lambda| = 2.7853 (real axis)')
    call tc%check_close(abs(rk4_stability_function(hmax*l1)), 1.0_wp, 1.0e-12_wp, 0.0_wp, '|R| = 1 at h_max')
    call tc%check_true(abs(rk4_stability_function(1.001_wp*hmax*l1)) > 1, '|R| > 1 beyond h_max')
    ! underdamped: check on the complex ray
    call rk4_max_stable_step(w0, 0.5_wp*w0, hmax, st)
    call linear_eigenvalues(w0, 0.5_wp*w0, l1, l2)
    call tc%check_close(abs(rk4_stability_function(hmax*l1)), 1.0_wp, 1.0e-12_wp, 0.0_wp, &
                        '|R| = 1 at h_max (complex lambda)')
    call tc%check_true(abs(rk4_stability_function(0.999_wp*hmax*l1)) <= 1, '|R| <= 1 below h_max')
    ! stiff damping gamma = 1e4 w0: h = 0.05 is refused with the limit in the message
    call rk4_solve([0.0_wp, 0.05_wp, 0.1_wp], 0.1_wp, 0.0_wp, w0, gam, 0.05_wp, th, om, s, st)
    call tc%check_true(st%code == PENDULA_ERR_UNSTABLE, 'stiff: unstable refused')
    call tc%check_true(index(st%message, 'largest stable h is 1.96950E-04') > 0, 'stiff: message gives h_max')
    call tc%check_true(all(th == 0) .and. all(om == 0), 'stiff: no garbage returned')
    ! just below the limit it runs and decays
    call rk4_max_stable_step(w0, gam, hmax, st)
    call rk4_solve([0.0_wp, 1000*hmax], 0.1_wp, 0.0_wp, w0, gam, 0.999_wp*hmax, th(1:2), om(1:2), s, st)
    call tc%check_true(st%code == PENDULA_OK .and. abs(th(2)) <= 0.1_wp, 'stiff: h below limit ok')
  end subroutine test_stability

  !> Final-state mode equals the last output of rk4_solve, bit for bit.
  subroutine test_final_state()
    real(wp) :: t(2), th(2), om(2), the, ome
    type(ode_stats_t) :: s1, s2
    type(status_t) :: st1, st2
    t = [1.0_wp, 101.0_wp]
    call rk4_solve(t, 0.5_wp, 0.1_wp, w0, 0.1_wp, 0.05_wp, th, om, s1, st1)
    call rk4_final_state(1.0_wp, 101.0_wp, 0.5_wp, 0.1_wp, w0, 0.1_wp, 0.05_wp, the, ome, s2, st2)
    call tc%check_true(st1%code == PENDULA_OK .and. st2%code == PENDULA_OK, 'final state: ok')
    call tc%check_true(the == th(2) .and. ome == om(2) .and. s2%steps == 2000, 'final state = last output')
    call rk4_final_state(1.0_wp, 1.0_wp, 0.5_wp, 0.1_wp, w0, 0.1_wp, 0.05_wp, the, ome, s2, st2)
    call tc%check_true(st2%code == PENDULA_OK .and. the == 0.5_wp .and. s2%steps == 0, 'final state: empty window')
    call rk4_final_state(1.0_wp, 0.0_wp, 0.5_wp, 0.1_wp, w0, 0.1_wp, 0.05_wp, the, ome, s2, st2)
    call tc%check_true(st2%code == PENDULA_ERR_ORDER, 'final state: t_end < t0 refused')
  end subroutine test_final_state

  subroutine test_bad_input()
    real(wp) :: th(3), om(3), nan, th2(2)
    type(ode_stats_t) :: s
    type(status_t) :: st
    real(wp), parameter :: t(3) = [0.0_wp, 1.0_wp, 2.0_wp]
    nan = ieee_value(1.0_wp, ieee_quiet_nan)
    call rk4_solve(t, 0.1_wp, 0.0_wp, w0, 0.1_wp, 0.0_wp, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'h = 0', 'h = 0')
    call rk4_solve(t, 0.1_wp, 0.0_wp, w0, 0.1_wp, -1.0_wp, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'h = -1', 'h < 0')
    call rk4_solve(t, 0.1_wp, 0.0_wp, w0, 0.1_wp, nan, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_NONFINITE, 'h = NaN', 'h NaN')
    call rk4_solve([0.0_wp, 1.0_wp, 1.0_wp], 0.1_wp, 0.0_wp, w0, 0.1_wp, 0.1_wp, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_ORDER, 't must be strictly increasing', 't repeated')
    call rk4_solve([0.0_wp, nan, 2.0_wp], 0.1_wp, 0.0_wp, w0, 0.1_wp, 0.1_wp, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_NONFINITE, 't[1] = NaN', 't NaN')
    call rk4_solve(t, 0.1_wp, 0.0_wp, 0.0_wp, 0.1_wp, 0.1_wp, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'w0 = 0', 'w0 = 0')
    call rk4_solve(t, 0.1_wp, 0.0_wp, w0, -0.1_wp, 0.1_wp, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'gamma = -0.1', 'gamma < 0')
    call rk4_solve(t, nan, 0.0_wp, w0, 0.1_wp, 0.1_wp, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_NONFINITE, 'theta0', 'theta0 NaN')
    call rk4_solve(t, 0.1_wp, 0.0_wp, w0, 0.1_wp, 0.1_wp, th2, om, s, st)
    call tc%check_status(st, PENDULA_ERR_SIZE, 'theta has 2', 'theta size')
    call rk4_solve([0.0_wp, 1.0e300_wp], 0.1_wp, 0.0_wp, w0, 0.1_wp, 0.1_wp, th2, om(1:2), s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'too small for the window', 'too many steps')
    call rk4_max_stable_step(-1.0_wp, 0.1_wp, th(1), st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'w0 = -1', 'max stable step w0 < 0')
  end subroutine test_bad_input

end program test_rk4
