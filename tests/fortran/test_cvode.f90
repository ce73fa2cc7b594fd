!> CVODE for the nonlinear damped pendulum.  With SUNDIALS: the text's scenario
!> against mpmath, agreement with RK4 at h = 1e-3, stiff damping with BDF
!> against the slow-manifold solution, events against the exact undamped
!> period, failures (step budget, tolerances CVODE refuses) and bad input.
!> Without SUNDIALS: every entry point reports PENDULA_ERR_UNAVAILABLE.
program test_cvode
  use pendula_kinds, only: wp, i8
  use pendula_status, only: status_t, PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_ORDER, &
                            PENDULA_ERR_SOLVER, PENDULA_ERR_MAXSTEPS, PENDULA_ERR_UNAVAILABLE, PENDULA_ERR_SIZE
  use pendula_ode, only: ode_stats_t
  use pendula_rk4, only: rk4_solve
  use pendula_cvode, only: cvode_solve, cvode_solve_events, cvode_available, &
                           PENDULA_CVODE_ADAMS, PENDULA_CVODE_BDF, PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO
  use pendula_testing, only: checker_t
  use pendula_test_data, only: w0 => text_w0, ref_th => text_ref_theta, ref_om => text_ref_omega
  implicit none
  type(checker_t) :: tc
  real(wp), parameter :: pi = acos(-1.0_wp)
  integer(i8), parameter :: budget = 1000000_i8

  if (cvode_available()) then
    write (*, '(a)') '  CVODE built: full tests'
    call test_text_scenario()
    call test_vs_rk4()
    call test_stiff_bdf()
    call test_events()
    call test_failures()
    call test_bad_input()
    call test_event_array_sizes()
  else
    write (*, '(a)') '  CVODE not built: checking the unavailable status'
    call test_unavailable()
  end if
  call tc%report('test_cvode')

contains

  subroutine text_grid(t)
    real(wp), intent(out) :: t(601)
    integer :: i
    do i = 1, 601
      t(i) = (i - 1)*0.05_wp
    end do
  end subroutine text_grid

  !> rtol = 1e-10: within 1e-7 rad of mpmath at t = 10, 20, 30 (Adams and BDF).
  subroutine test_text_scenario()
    real(wp) :: t(601), th(601), om(601), gam, tol
    type(ode_stats_t) :: s
    type(status_t) :: st
    integer :: ib, k, method
    call text_grid(t)
    do method = PENDULA_CVODE_ADAMS, PENDULA_CVODE_BDF
      do ib = 1, 2
        gam = merge(0.01_wp, 0.05_wp, ib == 1)/0.1_wp
        call cvode_solve(t, 0.0_wp, 2.0_wp, w0, gam, 1.0e-10_wp, 1.0e-12_wp, method, budget, th, om, s, st)
        call tc%check_true(st%code == PENDULA_OK, 'text scenario ok: '//trim(st%message))
        call tc%check_true(s%steps > 0 .and. s%rhs_evals >= s%steps .and. s%jac_evals > 0, 'stats filled')
        tol = merge(1.0e-7_wp, 1.0e-6_wp, method == PENDULA_CVODE_ADAMS)
        do k = 1, 3
          call tc%check_close(th(200*k + 1), ref_th(k, ib), 0.0_wp, tol, 'cvode theta vs mpmath')
          call tc%check_close(om(200*k + 1), ref_om(k, ib), 0.0_wp, tol, 'cvode omega vs mpmath')
        end do
        call tc%check_true(th(1) == 0 .and. om(1) == 2, 'initial state returned at t(1)')
      end do
    end do
  end subroutine test_text_scenario

  !> CVODE (rtol = 1e-10) and RK4 (h = 1e-3) agree on the text's scenario
  !> over the whole output grid.
  subroutine test_vs_rk4()
    real(wp) :: t(601), th(601), om(601), rt(601), ro(601), d
    type(ode_stats_t) :: s
    type(status_t) :: st, st2
    integer :: ib
    call text_grid(t)
    do ib = 1, 2
      call cvode_solve(t, 0.0_wp, 2.0_wp, w0, merge(0.1_wp, 0.5_wp, ib == 1), 1.0e-10_wp, 1.0e-12_wp, &
                       PENDULA_CVODE_ADAMS, budget, th, om, s, st)
      call rk4_solve(t, 0.0_wp, 2.0_wp, w0, merge(0.1_wp, 0.5_wp, ib == 1), 1.0e-3_wp, rt, ro, s, st2)
      d = max(maxval(abs(th - rt)), maxval(abs(om - ro)))
      write (*, '(a, es10.3)') '  sup |CVODE(rtol 1e-10) - RK4(h 1e-3)| = ', d
      call tc%check_true(st%code == PENDULA_OK .and. st2%code == PENDULA_OK .and. d < 1.0e-7_wp, &
                         'CVODE vs RK4 on the text scenario')
    end do
  end subroutine test_vs_rk4

  !> gamma = 1e4 w0 (RK4 would need h < 2e-4): BDF follows the slow manifold
  !> theta' = -(w0**2/gamma) sin(theta), i.e. tan(theta/2) = tan(theta0/2)
  !> exp(-w0**2 t/gamma), up to O((w0/gamma)**2) = 1e-8, in a few hundred steps.
  subroutine test_stiff_bdf()
    real(wp) :: t(5), th(5), om(5), gam, slow(5)
    type(ode_stats_t) :: s
    type(status_t) :: st
    integer :: i
    gam = 1.0e4_wp*w0
    t = [0.0_wp, 100.0_wp, 1000.0_wp, 5000.0_wp, 20000.0_wp]
    call cvode_solve(t, 0.5_wp, 0.0_wp, w0, gam, 1.0e-9_wp, 1.0e-12_wp, PENDULA_CVODE_BDF, budget, &
                     th, om, s, st)
    call tc%check_true(st%code == PENDULA_OK, 'stiff BDF ok: '//trim(st%message))
    slow = 2*atan(tan(0.25_wp)*exp(-w0**2*t/gam))
    do i = 2, 5
      call tc%check_close(th(i), slow(i), 1.0e-6_wp, 1.0e-12_wp, 'stiff BDF vs slow manifold')
    end do
    write (*, '(a, i0, a)') '  stiff gamma = 1e4 w0, BDF: ', s%steps, ' steps'
    call tc%check_true(s%steps < 3000, 'stiff BDF: few steps')
    ! Adams on the same problem needs h ~ 1/gamma: it exhausts a small budget.
    call cvode_solve(t, 0.5_wp, 0.0_wp, w0, gam, 1.0e-9_wp, 1.0e-12_wp, PENDULA_CVODE_ADAMS, 2000_i8, &
                     th, om, s, st)
    call tc%check_true(st%code == PENDULA_ERR_MAXSTEPS, 'stiff Adams: budget exhausted reported')
    call tc%check_true(index(st%message, 'max_steps = 2000') > 0, 'stiff Adams: message names max_steps')
    call tc%check_true(s%steps <= 2000, 'stiff Adams: budget respected')
  end subroutine test_stiff_bdf

  !> gamma = 0, theta0 = 0.5, Omega0 = 0: turning points at t = k T/2 and zero
  !> crossings at T/4 + k T/2, T = 4 K(sin(theta0/2)**2)/w0 (text eq. 1.53).
  subroutine test_events()
    real(wp) :: t(2), th(2), om(2), et(40), eth(40), eom(40), period, want, a, b, an
    integer :: ek(40), n, k, j, nturn, nzero
    logical :: trunc
    type(ode_stats_t) :: s
    type(status_t) :: st
    ! K(m) = pi / (2 AGM(1, sqrt(1 - m)))
    a = 1
    b = sqrt(1 - sin(0.25_wp)**2)
    do j = 1, 10
      an = (a + b)/2
      b = sqrt(a*b)
      a = an
    end do
    period = 4*(pi/(2*a))/w0
    t = [0.0_wp, 3.2_wp*period]
    call cvode_solve_events(t, 0.5_wp, 0.0_wp, w0, 0.0_wp, 1.0e-11_wp, 1.0e-13_wp, PENDULA_CVODE_ADAMS, budget, &
                            th, om, et, ek, eth, eom, n, trunc, s, st)
    call tc%check_true(st%code == PENDULA_OK, 'events ok: '//trim(st%message))
    ! 6 turning points (T/2 .. 3T; the one at t = 0 is not reported), 6 zero crossings
    ! (T/4 .. 11T/4)
    nturn = count(ek(1:n) == PENDULA_EVENT_TURNING)
    nzero = count(ek(1:n) == PENDULA_EVENT_ZERO)
    call tc%check_true(nturn == 6 .and. nzero == 6 .and. .not. trunc, 'events: counts')
    call tc%check_true(s%root_evals > 0, 'events: root evaluations counted')
    nturn = 0
    nzero = 0
    do k = 1, n
      if (ek(k) == PENDULA_EVENT_TURNING) then
        nturn = nturn + 1
        want = nturn*period/2
        call tc%check_close(abs(eth(k)), 0.5_wp, 0.0_wp, 1.0e-8_wp, 'turning point amplitude')
      else
        want = period/4 + nzero*period/2
        nzero = nzero + 1
        call tc%check_close(abs(eom(k)), 2*w0*sin(0.25_wp), 0.0_wp, 1.0e-8_wp, 'zero crossing speed')
      end if
      call tc%check_close(et(k), want, 0.0_wp, 1.0e-8_wp, 'event time vs exact period')
    end do
    ! Truncation: room for 3 events only
    call cvode_solve_events(t, 0.5_wp, 0.0_wp, w0, 0.0_wp, 1.0e-11_wp, 1.0e-13_wp, PENDULA_CVODE_ADAMS, budget, &
                            th, om, et(1:3), ek(1:3), eth(1:3), eom(1:3), n, trunc, s, st)
    call tc%check_true(st%code == PENDULA_OK .and. n == 3 .and. trunc, 'events: truncation reported')
    ! Zero-size event arrays are allowed (count only the truncation)
    call cvode_solve_events(t, 0.5_wp, 0.0_wp, w0, 0.0_wp, 1.0e-8_wp, 1.0e-10_wp, PENDULA_CVODE_BDF, budget, &
                            th, om, et(1:0), ek(1:0), eth(1:0), eom(1:0), n, trunc, s, st)
    call tc%check_true(st%code == PENDULA_OK .and. n == 0 .and. trunc, 'events: zero room')
  end subroutine test_events

  !> CVODE refusals become PENDULA_ERR_SOLVER with CVODE's reason.
  subroutine test_failures()
    real(wp) :: t(3), th(3), om(3)
    type(ode_stats_t) :: s
    type(status_t) :: st
    t = [0.0_wp, 1.0_wp, 2.0_wp]
    ! atol = 0 and theta0 = 0 (the text's start): pure relative control works
    call cvode_solve(t, 0.0_wp, 1.0_wp, w0, 0.1_wp, 1.0e-8_wp, 0.0_wp, PENDULA_CVODE_ADAMS, budget, th, om, s, st)
    call tc%check_true(st%code == PENDULA_OK, 'atol = 0 with a zero component: ok '//trim(st%message))
    ! tolerances below double precision: CV_TOO_MUCH_ACC, with CVODE's reason
    call cvode_solve(t, 0.1_wp, 0.1_wp, w0, 0.1_wp, 1.0e-30_wp, 1.0e-30_wp, PENDULA_CVODE_BDF, budget, th, om, s, st)
    call tc%check_true(st%code == PENDULA_ERR_SOLVER .and. index(st%message, 'CV_TOO_MUCH_ACC') > 0, &
                       'too much accuracy: '//trim(st%message))
    call tc%check_true(index(st%message, 'CVODE') > 0 .and. len_trim(st%message) > 30, &
                       'solver error message: '//trim(st%message))
    call tc%check_true(th(1) == 0.1_wp .and. om(2) == 0 .and. om(3) == 0, 'failed outputs zeroed')
    ! atol = 0 is fine when no component vanishes... until theta crosses 0
    call cvode_solve([0.0_wp, 0.1_wp], 0.5_wp, 0.1_wp, w0, 0.1_wp, 1.0e-8_wp, 0.0_wp, PENDULA_CVODE_BDF, budget, &
                     th(1:2), om(1:2), s, st)
    call tc%check_true(st%code == PENDULA_OK, 'atol = 0 on a short non-vanishing stretch ok')
  end subroutine test_failures

  subroutine test_bad_input()
    real(wp) :: th(3), om(3)
    type(ode_stats_t) :: s
    type(status_t) :: st
    real(wp), parameter :: t(3) = [0.0_wp, 1.0_wp, 2.0_wp]
    call cvode_solve(t, 0.1_wp, 0.0_wp, w0, 0.1_wp, 0.0_wp, 1.0e-10_wp, 1, budget, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'rtol = 0', 'rtol = 0')
    call cvode_solve(t, 0.1_wp, 0.0_wp, w0, 0.1_wp, 1.0e-8_wp, -1.0_wp, 1, budget, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'atol = -1', 'atol < 0')
    call cvode_solve(t, 0.1_wp, 0.0_wp, w0, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, 3, budget, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'method = 3', 'method')
    call cvode_solve(t, 0.1_wp, 0.0_wp, w0, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, 1, 0_i8, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'max_steps = 0', 'max_steps')
    call cvode_solve([0.0_wp, 2.0_wp, 1.0_wp], 0.1_wp, 0.0_wp, w0, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, 1, budget, &
                     th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_ORDER, 'strictly increasing', 't decreasing')
    call cvode_solve(t, 0.1_wp, 0.0_wp, -2.0_wp, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, 1, budget, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'w0 = -2', 'w0 < 0')
    call cvode_solve(t, 0.1_wp, 0.0_wp, w0, -1.0_wp, 1.0e-8_wp, 1.0e-10_wp, 1, budget, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'gamma = -1', 'gamma < 0')
  end subroutine test_bad_input

  subroutine test_event_array_sizes()
    ! three event kinds but two event times: refused before integrating
    real(wp) :: th(3), om(3), et(2), eth(2), eom(2)
    integer :: ek(3), n
    logical :: trunc
    type(ode_stats_t) :: s
    type(status_t) :: st
    call cvode_solve_events([0.0_wp, 1.0_wp, 2.0_wp], 0.1_wp, 0.0_wp, w0, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, 1, &
                            budget, th, om, et, ek, eth, eom, n, trunc, s, st)
    call tc%check_status(st, PENDULA_ERR_SIZE, 'same size', 'event array sizes')
  end subroutine test_event_array_sizes

  subroutine test_unavailable()
    real(wp) :: th(2), om(2), et(1), eth(1), eom(1)
    integer :: ek(1), n
    logical :: trunc
    type(ode_stats_t) :: s
    type(status_t) :: st
    call cvode_solve([0.0_wp, 1.0_wp], 0.1_wp, 0.0_wp, w0, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, PENDULA_CVODE_BDF, &
                     budget, th, om, s, st)
    call tc%check_status(st, PENDULA_ERR_UNAVAILABLE, 'CVODE is not available', 'cvode_solve unavailable')
    call tc%check_true(all(th == 0) .and. all(om == 0) .and. s%steps == 0, 'unavailable: outputs zero')
    call cvode_solve_events([0.0_wp, 1.0_wp], 0.1_wp, 0.0_wp, w0, 0.1_wp, 1.0e-8_wp, 1.0e-10_wp, &
                            PENDULA_CVODE_ADAMS, budget, th, om, et, ek, eth, eom, n, trunc, s, st)
    call tc%check_status(st, PENDULA_ERR_UNAVAILABLE, 'SUNDIALS', 'cvode_solve_events unavailable')
    call tc%check_true(n == 0 .and. .not. trunc, 'unavailable: no events')
  end subroutine test_unavailable

end program test_cvode
