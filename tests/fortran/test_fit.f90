!> The fitting concern: fit_period against the closed-form weighted mean of
!> 1/w0 and its invariances (exact data, scaled sigmas), the effective
!> variance against a hand-iterated one, period_factor's derivative against a
!> central difference; sensitivity_solve against the exact undamped energy and
!> against finite differences of itself; bad input of both (status codes).
program test_fit
  use pendula_kinds, only: wp
  use pendula_constants, only: pi
  use pendula_status, only: status_t, PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_SIZE, PENDULA_ERR_NONFINITE, &
                            PENDULA_ERR_ORDER, PENDULA_ERR_MAXSTEPS
  use pendula_fit_period, only: period_fit_t, fit_period, period_factor
  use pendula_sensitivity, only: sensitivity_solve
  use pendula_testing, only: checker_t
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  implicit none
  type(checker_t) :: tc

  call test_period_exact()
  call test_period_weights()
  call test_period_factor()
  call test_sensitivity()
  call test_bad_input()
  call tc%report('test_fit')

contains

  subroutine test_period_exact()
    real(wp) :: th(5), f(5), df(5), t(5)
    type(period_fit_t) :: fit
    type(status_t) :: st
    th = [0.1_wp, 0.9_wp, 1.7_wp, 2.5_wp, 3.0_wp]
    call period_factor(th, f, df)
    t = f/3.6_wp
    call fit_period(th, t, spread(1.0e-3_wp, 1, 5), spread(0.0_wp, 1, 5), fit, st)
    call tc%check_true(st%code == PENDULA_OK, 'exact: ok')
    call tc%check_ulps(fit%w0, 3.6_wp, 8.0_wp, 'exact data: w0 to a few ulps')
    call tc%check_true(fit%chi2 < 1.0e-20_wp .and. fit%dof == 4 .and. fit%iterations == 1, 'exact: chi2 0, dof, one pass')
    ! 4 K(m) = 2 pi (1 + m/4 + 9 m**2/64 + 25 m**3/256 + ...) (DLMF 19.5.1), m = sin(0.05)**2
    call tc%check_close(f(1), 2*pi*(1 + 0.25_wp*sin(0.05_wp)**2 + 9.0_wp/64*sin(0.05_wp)**4 &
                                    + 25.0_wp/256*sin(0.05_wp)**6), 1.0e-11_wp, 0.0_wp, 'K series at small amplitude')
  end subroutine test_period_exact

  !> Scaling every sigma by c leaves w0 and chi2*c**2 fixed, se_w0 scales by c;
  !> one point with sigma 1000x the others barely counts.
  subroutine test_period_weights()
    real(wp) :: th(4), t(4), s(4)
    type(period_fit_t) :: a, b
    type(status_t) :: st
    th = [0.2_wp, 0.8_wp, 1.6_wp, 2.4_wp]
    t = [1.76_wp, 1.80_wp, 2.01_wp, 2.60_wp]
    s = [1.0e-3_wp, 2.0e-3_wp, 1.0e-3_wp, 3.0e-3_wp]
    call fit_period(th, t, s, spread(0.01_wp, 1, 4), a, st)
    call fit_period(th, t, 7*s, spread(0.07_wp, 1, 4), b, st)
    call tc%check_close(b%w0, a%w0, 1.0e-13_wp, 0.0_wp, 'sigma scale: w0 unchanged')
    call tc%check_close(b%se_w0, 7*a%se_w0, 1.0e-12_wp, 0.0_wp, 'sigma scale: se scales')
    call tc%check_close(b%chi2*49, a%chi2, 1.0e-12_wp, 0.0_wp, 'sigma scale: chi2 / c**2')
    call tc%check_true(a%iterations > 1, 'amplitude errors: iterated')
    call fit_period([0.2_wp, 0.8_wp], [1.76_wp, 1.80_wp], [1.0e-3_wp, 1.0e-3_wp], [0.0_wp, 0.0_wp], a, st)
    call tc%check_close(a%se_w0_scatter, a%se_w0*sqrt(a%chi2), 1.0e-14_wp, 0.0_wp, 'scatter se, dof 1')
  end subroutine test_period_weights

  subroutine test_period_factor()
    real(wp) :: th(4), f(4), df(4), fp(4), fm(4), d(4)
    real(wp), parameter :: h = 1.0e-6_wp
    integer :: i
    th = [1.0e-4_wp, 0.5_wp, 2.0_wp, 3.1_wp]
    call period_factor(th, f, df)
    call period_factor(th + h, fp, d)
    call period_factor(th - h, fm, d)
    do i = 2, 4
      call tc%check_close(df(i), (fp(i) - fm(i))/(2*h), 1.0e-7_wp, 0.0_wp, 'df/dtheta0 vs central difference')
    end do
    call tc%check_close(df(1), pi/4*th(1)/2*2, 1.0e-6_wp, 0.0_wp, 'df/dtheta0 small-angle limit')
  end subroutine test_period_factor

  !> gamma = 0: energy conserved to tol; d theta / d theta0 against a central
  !> difference of two solves.
  subroutine test_sensitivity()
    integer, parameter :: n = 50
    real(wp) :: t(n), th(n), om(n), jt(n, 4), jo(n, 4), thp(n), thm(n), e(n)
    type(status_t) :: st
    integer :: i
    t = [(0.2_wp*i, i=1, n)]
    call sensitivity_solve(t, 0.0_wp, 2.8_wp, 0.0_wp, 3.6_wp, 0.0_wp, 1.0e-10_wp, th, om, jt, jo, st)
    call tc%check_true(st%code == PENDULA_OK, 'sensitivity ok')
    e = om**2/2 - 3.6_wp**2*cos(th)
    call tc%check_true(maxval(abs(e - e(1))) < 1.0e-8_wp, 'energy conserved at gamma = 0')
    call sensitivity_solve(t, 0.0_wp, 1.0_wp, 0.5_wp, 3.6_wp, 0.2_wp + 1.0e-6_wp, 1.0e-11_wp, thp, om, jt, jo, st)
    call sensitivity_solve(t, 0.0_wp, 1.0_wp, 0.5_wp, 3.6_wp, 0.2_wp - 1.0e-6_wp, 1.0e-11_wp, thm, om, jt, jo, st)
    call sensitivity_solve(t, 0.0_wp, 1.0_wp, 0.5_wp, 3.6_wp, 0.2_wp, 1.0e-11_wp, th, om, jt, jo, st)
    call tc%check_true(maxval(abs(jt(:, 4) - (thp - thm)/2.0e-6_wp)) < 1.0e-6_wp, 'd theta / d gamma vs difference')
  end subroutine test_sensitivity

  subroutine test_bad_input()
    real(wp) :: nan, th(3), om(3), jt(3, 4), jo(3, 4)
    type(period_fit_t) :: fit
    type(status_t) :: st
    nan = ieee_value(1.0_wp, ieee_quiet_nan)
    call fit_period([0.1_wp, 3.2_wp], [2.0_wp, 5.0_wp], [1.0_wp, 1.0_wp], [0.0_wp, 0.0_wp], fit, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'theta0[1]', 'rotation refused')
    call fit_period([0.1_wp], [2.0_wp, 5.0_wp], [1.0_wp], [0.0_wp], fit, st)
    call tc%check_status(st, PENDULA_ERR_SIZE, 'period', 'sizes')
    call fit_period([0.1_wp, nan], [2.0_wp, 5.0_wp], [1.0_wp, 1.0_wp], [0.0_wp, 0.0_wp], fit, st)
    call tc%check_status(st, PENDULA_ERR_NONFINITE, 'theta0', 'nan')
    call fit_period([0.1_wp, 0.2_wp], [2.0_wp, 5.0_wp], [1.0_wp, 0.0_wp], [0.0_wp, 0.0_wp], fit, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 'sigma_period[1]', 'sigma 0')
    call sensitivity_solve([0.0_wp, 1.0_wp, 1.0_wp], 0.0_wp, 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0e-8_wp, &
                           th, om, jt, jo, st)
    call tc%check_status(st, PENDULA_ERR_ORDER, 't', 'repeated time')
    call sensitivity_solve([0.0_wp, 1.0_wp, 2.0_wp], 0.5_wp, 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0e-8_wp, &
                           th, om, jt, jo, st)
    call tc%check_status(st, PENDULA_ERR_DOMAIN, 't_ref', 't_ref after the first sample')
    call sensitivity_solve([0.0_wp, 1.0_wp, 1.0e9_wp], 0.0_wp, 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0e-12_wp, &
                           th, om, jt, jo, st)
    call tc%check_status(st, PENDULA_ERR_MAXSTEPS, 'budget', 'step budget refused up front')
  end subroutine test_bad_input

end program test_fit
