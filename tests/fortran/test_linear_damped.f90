!> Linear damped pendulum: the text's parameter sets against the
!> text's own formulas (eqs 2.27-2.29, 2.45-2.47), gamma = 0 against the
!> small-angle solution bit for bit, continuity through gamma = 2 w0, no
!> overflow for gamma t up to 1e300, regime numbers, bad input, and agreement
!> with the values the Python package returned (table written by
!> tools/gen/gen_linear_table.py).  High-precision (mpmath) accuracy is in
!> tests/python/test_linear_damped.py.
program test_linear_damped
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_positive_inf, ieee_quiet_nan
  use pendula
  use pendula_testing, only: checker_t, ulps_between
  implicit none
  type(checker_t) :: chk
  real(wp), parameter :: eps = epsilon(1.0_wp)
  real(wp) :: w0

  w0 = sqrt(9.8_wp/4.9_wp)
  call text_overdamped()
  call text_critical()
  call undamped_exact()
  call continuity_through_critical()
  call no_overflow()
  call regime_numbers()
  call envelope_bounds()
  call array_paths_agree()
  call bad_input()
  call python_table()
  call chk%report('test_linear_damped')

contains

  ! Figs 10, 11, 12: gamma = 3 w0, 5 w0 with the listing's A, B (eq. 2.29) and
  ! theta = A e^{l1 t} + B e^{l2 t} (eq. 2.27), t on the listing's grid.
  ! Well conditioned there (beta >= 1.1 w0), so they agree to a few eps.
  subroutine text_overdamped()
    real(wp) :: gam, beta, l1, l2, om0s(3), a, b, tt, dt, t, th_text, om_text, th, om, err, worst
    real(wp) :: facs(2), th0s(2)
    type(linear_damped_t) :: sol
    type(status_t) :: st
    integer :: i, j, k, m
    om0s = [0.0_wp, 0.5_wp, -0.5_wp]
    facs = [3.0_wp, 5.0_wp]
    th0s = [0.1_wp, 0.0_wp]
    worst = 0
    do m = 1, 2
      do k = 1, 2
        gam = facs(k)*w0
        beta = sqrt(gam**2/4 - w0**2)
        l1 = -gam/2 - beta
        l2 = -gam/2 + beta
        do j = 1, 3
          if (m == 2 .and. (k /= 1 .or. j /= 2)) cycle   ! fig 12: theta0 = 0, Omega0 = 0.5, 3 w0
          a = (th0s(m)*l2 - om0s(j))/(l2 - l1)
          b = (om0s(j) - th0s(m)*l1)/(l2 - l1)
          call linear_damped_init(sol, th0s(m), om0s(j), w0, gam, st)
          call chk%check_true(st%code == PENDULA_OK, 'init text overdamped')
          tt = 2*2*pi/w0
          dt = tt/1000
          do i = 0, 999
            t = i*dt
            th_text = a*exp(l1*t) + b*exp(l2*t)
            om_text = a*l1*exp(l1*t) + b*l2*exp(l2*t)
            call linear_damped_state(sol, t, th, om)
            err = max(abs(th - th_text), abs(om - om_text)/gam)/ &
                  (eps*(abs(th_text) + abs(om_text)/gam + abs(th0s(m))*1e-3_wp + abs(om0s(j))/gam*1e-3_wp))
            worst = max(worst, err)
          end do
        end do
      end do
    end do
    ! The text's lambda2 = -gamma/2 + beta loses ~2 bits at 3 w0; 64 eps is ample.
    call chk%check_true(worst <= 64, 'figs 10-12 against eqs 2.27-2.29 (worst in eps units printed below)')
    write (*, '(a, f8.2)') '  figs 10-12 vs text eq. 2.27-2.29: worst error / eps =', worst
  end subroutine text_overdamped

  ! Fig 13: gamma = 2 w0, theta = e^{lt}(A_c + B t), Omega = e^{lt}(C_c + D t), eqs 2.45-2.47.
  subroutine text_critical()
    real(wp) :: gam, l, om0s(3), ac, b, cc, d, tt, dt, t, th_text, om_text, th, om, err, worst
    type(linear_damped_t) :: sol
    type(status_t) :: st
    integer :: i, j
    om0s = [0.0_wp, 0.5_wp, -0.5_wp]
    gam = 2*w0
    l = -gam/2
    worst = 0
    do j = 1, 3
      ac = 0.1_wp
      b = om0s(j) - 0.1_wp*l
      cc = om0s(j)
      d = om0s(j)*l - 0.1_wp*l**2
      call linear_damped_init(sol, 0.1_wp, om0s(j), w0, gam, st)
      call chk%check_true(sol%info%regime == DAMPING_CRITICAL, 'gamma = 2 w0 is critical')
      tt = 2*2*pi/w0
      dt = tt/1000
      do i = 0, 999
        t = i*dt
        th_text = exp(l*t)*(ac + b*t)
        om_text = exp(l*t)*(cc + d*t)
        call linear_damped_state(sol, t, th, om)
        err = max(abs(th - th_text), abs(om - om_text)/gam)/ &
              (eps*(abs(th_text) + abs(om_text)/gam + 1e-4_wp))
        worst = max(worst, err)
      end do
    end do
    call chk%check_true(worst <= 64, 'fig 13 against eqs 2.45-2.47')
    write (*, '(a, f8.2)') '  fig 13 vs text eq. 2.45-2.47: worst error / eps =', worst
  end subroutine text_critical

  ! gamma = 0 is the small-angle solution, bit for bit.
  subroutine undamped_exact()
    real(wp) :: t, th, om, ws(3), ics(2, 3)
    type(linear_damped_t) :: sol
    type(status_t) :: st
    integer :: i, j, k, bad
    ws = [w0, 1.0_wp, 37.5_wp]
    ics = reshape([0.1_wp, 0.0_wp, 0.1_wp, 0.5_wp, -0.3_wp, -0.5_wp], [2, 3])
    bad = 0
    do k = 1, 3
      do j = 1, 3
        call linear_damped_init(sol, ics(1, j), ics(2, j), ws(k), 0.0_wp, st)
        do i = 0, 400
          t = 0.037_wp*i**1.5_wp
          call linear_damped_state(sol, t, th, om)
          if (th /= ics(1, j)*cos(ws(k)*t) + (ics(2, j)/ws(k))*sin(ws(k)*t)) bad = bad + 1
          if (om /= ics(2, j)*cos(ws(k)*t) - (ws(k)*ics(1, j))*sin(ws(k)*t)) bad = bad + 1
        end do
      end do
    end do
    call chk%check_true(bad == 0, 'gamma = 0 equals theta0 cos(w0 t) + (Omega0/w0) sin(w0 t) bit for bit')
  end subroutine undamped_exact

  ! theta is analytic in gamma: across 2 w0 (1 -+ 1e-15) the values move by a
  ! few eps only, and 2 w0 (1 -+ 1e-9) stays within 1e-8 of the critical value.
  subroutine continuity_through_critical()
    real(wp) :: t, thc, omc, th, om, d, worst_close, worst_far
    real(wp) :: rel(4)
    type(linear_damped_t) :: crit, sol
    type(status_t) :: st
    integer :: i, k
    rel = [-1e-15_wp, 1e-15_wp, -1e-9_wp, 1e-9_wp]
    call linear_damped_init(crit, 0.1_wp, 0.5_wp, w0, 2*w0, st)
    worst_close = 0
    worst_far = 0
    do k = 1, 4
      call linear_damped_init(sol, 0.1_wp, 0.5_wp, w0, 2*w0*(1 + rel(k)), st)
      do i = 0, 300
        t = 0.05_wp*i
        call linear_damped_state(crit, t, thc, omc)
        call linear_damped_state(sol, t, th, om)
        d = max(abs(th - thc), abs(om - omc)/(2*w0))/(abs(thc) + abs(omc)/(2*w0) + 1e-300_wp)
        if (k <= 2) worst_close = max(worst_close, d)
        if (k > 2) worst_far = max(worst_far, d)
      end do
    end do
    call chk%check_true(worst_close <= 64*eps*(1 + 0.05_wp*300*w0), &
                        'continuous through gamma = 2 w0 (1 -+ 1e-15)')
    call chk%check_true(worst_far <= 1e-6_wp .and. worst_far > 0, 'smooth at 2 w0 (1 -+ 1e-9)')
  end subroutine continuity_through_critical

  ! gamma t up to 1e300 in every regime: finite, and 0 once below the double range.
  subroutine no_overflow()
    real(wp) :: gs(7), ws(4), ts(9), th, om
    type(linear_damped_t) :: sol
    type(status_t) :: st
    integer :: i, j, k, bad, zero_far
    gs = [1e-300_wp, 1e-8_wp, 1.0_wp, 2.0_wp, 3.0_wp, 1e150_wp, 1e300_wp]
    ws = [1e-150_wp, 1e-3_wp, 1.0_wp, 1e100_wp]
    ts = [0.0_wp, 1e-300_wp, 1.0_wp, 1e3_wp, 1e10_wp, 1e100_wp, 1e150_wp, 1e200_wp, 1e300_wp]
    bad = 0
    zero_far = 0
    do k = 1, size(ws)
      do j = 1, size(gs)
        if (log10(gs(j)) + log10(ws(k)) > 300) cycle      ! gamma itself beyond 1e300
        call linear_damped_init(sol, 0.1_wp, -0.5_wp, ws(k), gs(j)*ws(k), st)
        if (st%code /= PENDULA_OK) bad = bad + 1
        do i = 1, size(ts)
          call linear_damped_state(sol, ts(i), th, om)
          if (.not. (ieee_is_finite(th) .and. ieee_is_finite(om))) then
            bad = bad + 1
            write (*, '(a, 3es12.3, 2es12.3)') '  non-finite at w0, gamma, t =', ws(k), gs(j)*ws(k), ts(i), th, om
          end if
          if (ts(i) > 0 .and. log10(gs(j)) + log10(ws(k)) + log10(max(ts(i), tiny(1.0_wp))) >= 5 .and. &
              gs(j) >= 1e-8_wp .and. gs(j) <= 3 .and. &
              (th /= 0 .or. om /= 0)) zero_far = zero_far + 1
        end do
      end do
    end do
    call chk%check_true(bad == 0, 'no overflow, NaN or Inf for gamma t up to 1e300')
    call chk%check_true(zero_far == 0, 'underflows to exactly 0 for gamma t >= 1e5 (moderate gamma/w0)')
  end subroutine no_overflow

  subroutine regime_numbers()
    type(damping_regime_t) :: r
    type(status_t) :: st
    real(wp) :: gs(6)
    integer :: k
    gs = [0.0_wp, 0.5_wp, 2.0_wp, 3.0_wp, 5.0_wp, 1e6_wp]
    do k = 1, size(gs)
      call damping_regime(w0, gs(k)*w0, r, st)
      call chk%check_true(st%code == PENDULA_OK, 'damping_regime ok')
      ! Vieta (eq. 2.14): lambda1 + lambda2 = -gamma, lambda1 lambda2 = w0^2.
      call chk%check_true(abs(r%lambda1 + r%lambda2 + gs(k)*w0) <= 4*eps*gs(k)*w0 + 4*eps*w0, &
                          'lambda1 + lambda2 = -gamma')
      call chk%check_true(abs(r%lambda1*r%lambda2 - w0**2) <= 8*eps*w0**2, 'lambda1 lambda2 = w0^2')
      call chk%check_ulps(r%gamma_critical, 2*w0, 0.0_wp, 'gamma_c = 2 w0')
      call chk%check_ulps(r%damping_ratio, gs(k)*w0/(2*w0), 1.0_wp, 'zeta')
    end do
    call damping_regime(w0, 0.5_wp*w0, r, st)
    call chk%check_true(r%regime == DAMPING_UNDERDAMPED .and. regime_name(r%regime) == 'underdamped', 'under')
    call chk%check_ulps(r%omega_d, w0*sqrt(1 - 0.0625_wp), 4.0_wp, 'omega_d = w0 sqrt(1 - zeta^2)')
    call chk%check_ulps(r%quality_factor, 2.0_wp, 2.0_wp, 'Q = w0/gamma')
    call chk%check_ulps(r%log_decrement, pi*0.5_wp*w0/r%omega_d, 2.0_wp, 'decrement = pi gamma/omega_d')
    call chk%check_ulps(r%damped_period, 2*pi/r%omega_d, 2.0_wp, 'T_d = 2 pi/omega_d')
    call damping_regime(w0, 3*w0, r, st)
    call chk%check_true(r%regime == DAMPING_OVERDAMPED .and. regime_name(r%regime) == 'overdamped', 'over')
    call chk%check_ulps(r%beta, w0*sqrt(1.25_wp), 4.0_wp, 'beta = sqrt(gamma^2/4 - w0^2)')
    call chk%check_true(.not. ieee_is_finite(r%log_decrement), 'no decrement when over-damped')
    ! gamma >> w0: lambda2 = -w0^2/(gamma/2 + beta) keeps its digits (-a + beta would give 0 or garbage).
    call damping_regime(1.0_wp, 1e10_wp, r, st)
    call chk%check_ulps(real(r%lambda2, wp), -1e-10_wp, 4.0_wp, 'slow eigenvalue at gamma = 1e10 w0')
    call damping_regime(1.0_wp, 0.0_wp, r, st)
    call chk%check_true(.not. ieee_is_finite(r%quality_factor) .and. r%log_decrement == 0 .and. &
                        r%omega_d == 1, 'gamma = 0: Q = Inf, decrement 0, omega_d = w0')
  end subroutine regime_numbers

  ! Under-damped: |theta| <= R e^{-gamma t/2}, touching it; successive maxima
  ! one damped period apart have ratio e^{decrement}.
  subroutine envelope_bounds()
    type(linear_damped_t) :: sol
    type(status_t) :: st
    real(wp) :: t, th, env, worst_over, closest, t1, r
    integer :: i
    call linear_damped_init(sol, 0.1_wp, 0.5_wp, w0, 0.3_wp*w0, st)
    worst_over = 0
    closest = 1
    do i = 0, 5000
      t = 0.004_wp*i
      th = linear_damped_theta(sol, t)
      env = sol%envelope(t)
      worst_over = max(worst_over, abs(th) - env*(1 + 8*eps))
      closest = min(closest, (env - abs(th))/env)
    end do
    call chk%check_true(worst_over <= 0, 'underdamped |theta| <= envelope')
    call chk%check_true(closest < 1e-4_wp, 'envelope is touched')
    t1 = 1.3_wp
    r = linear_damped_theta(sol, t1)/linear_damped_theta(sol, t1 + sol%info%damped_period)
    call chk%check_close(log(r), sol%info%log_decrement, 1e-13_wp, 0.0_wp, 'log decrement = ln(theta(t)/theta(t+T_d))')
  end subroutine envelope_bounds

  ! Elemental, type-bound, linear_damped_eval and linear_damped_arrays give
  ! identical bits.
  subroutine array_paths_agree()
    integer, parameter :: n = 200
    real(wp) :: t(n), th1(n), om1(n), th2(n), om2(n), th3(n), om3(n), th4(n)
    real(wp) :: p(n)
    type(linear_damped_t) :: sol
    type(status_t) :: st
    integer :: i
    do i = 1, n
      t(i) = 0.03_wp*(i - 1)
    end do
    call linear_damped_init(sol, 0.1_wp, -0.5_wp, w0, 2*w0*(1 + 1e-6_wp), st)
    call linear_damped_state(sol, t, th1, om1)
    call linear_damped_eval(sol, t, th2, om2, st)
    call chk%check_true(st%code == PENDULA_OK, 'eval ok')
    p = 0.1_wp
    call linear_damped_arrays(t, p, p*0 - 0.5_wp, p*0 + w0, p*0 + 2*w0*(1 + 1e-6_wp), th3, om3, st)
    call chk%check_true(st%code == PENDULA_OK, 'arrays ok')
    th4 = sol%theta(t)
    call chk%check_true(all(th1 == th2) .and. all(om1 == om2) .and. all(th1 == th3) .and. &
                        all(om1 == om3) .and. all(th1 == th4) .and. all(om1 == sol%omega(t)), 'all array paths agree bit for bit')
  end subroutine array_paths_agree

  subroutine bad_input()
    type(linear_damped_t) :: sol
    type(status_t) :: st
    type(damping_regime_t) :: r
    real(wp) :: nan, t(2), th(2), om(2), x(2)
    nan = ieee_value(1.0_wp, ieee_quiet_nan)
    call linear_damped_init(sol, 0.1_wp, 0.0_wp, 1.0_wp, -1.0_wp, st)
    call chk%check_true(st%code == PENDULA_ERR_DOMAIN .and. index(st%message, 'gamma =') == 1, &
                        'gamma < 0: '//trim(st%message))
    call linear_damped_init(sol, 0.1_wp, 0.0_wp, 0.0_wp, 1.0_wp, st)
    call chk%check_true(st%code == PENDULA_ERR_DOMAIN .and. index(st%message, 'w0 =') == 1, &
                        'w0 = 0: '//trim(st%message))
    call linear_damped_init(sol, nan, 0.0_wp, 1.0_wp, 1.0_wp, st)
    call chk%check_true(st%code == PENDULA_ERR_NONFINITE .and. index(st%message, 'theta0 =') == 1, &
                        'theta0 NaN: '//trim(st%message))
    call linear_damped_init(sol, 0.1_wp, ieee_value(1.0_wp, ieee_positive_inf), 1.0_wp, 1.0_wp, st)
    call chk%check_true(st%code == PENDULA_ERR_NONFINITE .and. index(st%message, 'omega0 =') == 1, &
                        'omega0 Inf: '//trim(st%message))
    call damping_regime(1.0_wp, nan, r, st)
    call chk%check_true(st%code == PENDULA_ERR_NONFINITE .and. index(st%message, 'gamma =') == 1, 'gamma NaN')
    call linear_damped_init(sol, 0.1_wp, 0.0_wp, 1.0_wp, 1.0_wp, st)
    t = [1.0_wp, -1.0_wp]
    call linear_damped_eval(sol, t, th, om, st)
    call chk%check_true(st%code == PENDULA_ERR_DOMAIN .and. index(st%message, 't[1] =') == 1, &
                        't < 0: '//trim(st%message))
    t = [nan, 1.0_wp]
    call linear_damped_eval(sol, t, th, om, st)
    call chk%check_true(st%code == PENDULA_ERR_NONFINITE .and. index(st%message, 't[0] =') == 1, 't NaN')
    t = [1.0_wp, 2.0_wp]
    x = [1.0_wp, 1.0_wp]
    call linear_damped_arrays(t, x, x, [1.0_wp, -2.0_wp], x, th, om, st)
    call chk%check_true(st%code == PENDULA_ERR_DOMAIN .and. index(st%message, 'w0 =') == 1 .and. &
                        index(st%message, '(element 1)') > 0 .and. all(th == 0), 'arrays: bad w0 element: '//trim(st%message))
    call linear_damped_arrays(t, x, x, x(1:1), x, th, om, st)
    call chk%check_true(st%code == PENDULA_ERR_SIZE, 'arrays: size mismatch')
  end subroutine bad_input

  ! The values pendula.linear_damped (Python, f2py) returned for the same
  ! inputs when tools/gen/gen_linear_table.py wrote the table: the native
  ! evaluation must agree within 1 ulp (0 expected).
  subroutine python_table()
    include 'linear_damped_table.inc'
    type(linear_damped_t) :: sol
    type(status_t) :: st
    real(wp) :: th, om, worst, ulps_th, ulps_om
    integer :: i, nbits
    worst = 0
    nbits = 0
    do i = 1, size(tab, 2)
      call linear_damped_init(sol, tab(2, i), tab(3, i), tab(4, i), tab(5, i), st)
      call linear_damped_state(sol, tab(1, i), th, om)
      ulps_th = merge(0.0_wp, ulps_between(th, tab(6, i)), th == tab(6, i))
      ulps_om = merge(0.0_wp, ulps_between(om, tab(7, i)), om == tab(7, i))
      worst = max(worst, ulps_th, ulps_om)
      if (th /= tab(6, i) .or. om /= tab(7, i)) nbits = nbits + 1
    end do
    call chk%check_true(worst <= 1, 'Fortran and Python agree within 1 ulp')
    write (*, '(a, i0, a, i0, a, f6.2)') '  Python table: ', size(tab, 2), ' points, ', nbits, &
      ' not bit-identical, worst ulps ', worst
  end subroutine python_table

end program test_linear_damped
