!> Core concern: physical parameters and the status table.
program test_core
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf
  use pendula
  use pendula_testing, only: checker_t
  implicit none
  type(checker_t) :: t
  type(status_t) :: st
  real(wp) :: w0, gamma, t0
  real(wp) :: nan, inf

  ! ieee_value, not 0/0 or huge*2: the checked build traps invalid and overflow.
  nan = ieee_value(nan, ieee_quiet_nan)
  inf = ieee_value(inf, ieee_positive_inf)

  call natural_frequency(9.8_wp, 4.9_wp, w0, st)
  call t%check_true(status_ok(st), 'w0 status ok')
  call t%check_ulps(w0, sqrt(2.0_wp), 1.0_wp, 'text w0 = sqrt(2)')

  call small_angle_period(w0, t0, st)
  call t%check_ulps(t0, 2*pi/sqrt(2.0_wp), 1.0_wp, 'T0 = 2 pi / w0 (eq. 1.8)')

  call damping_rate(0.01_wp, 0.1_wp, gamma, st)
  call t%check_ulps(gamma, 0.1_wp, 1.0_wp, 'gamma = b/m')

  ! Bad input: a status naming the argument and the range, never a stop.
  call natural_frequency(-9.8_wp, 4.9_wp, w0, st)
  call t%check_true(st%code == PENDULA_ERR_DOMAIN, 'g < 0 -> domain error')
  call t%check_true(index(st%message, 'g =') == 1 .and. index(st%message, '> 0') > 0, &
                    'message names g and its range: '//trim(st%message))
  call natural_frequency(9.8_wp, nan, w0, st)
  call t%check_true(st%code == PENDULA_ERR_NONFINITE .and. index(st%message, 'length =') == 1, &
                    'NaN length -> non-finite error: '//trim(st%message))
  call damping_rate(-1.0_wp, 0.1_wp, gamma, st)
  call t%check_true(st%code == PENDULA_ERR_DOMAIN .and. index(st%message, 'b =') == 1, 'b < 0 rejected')
  call damping_rate(0.1_wp, 0.0_wp, gamma, st)
  call t%check_true(st%code == PENDULA_ERR_DOMAIN .and. index(st%message, 'mass =') == 1, 'mass = 0 rejected')
  call small_angle_period(inf, t0, st)
  call t%check_true(st%code == PENDULA_ERR_NONFINITE, 'w0 = Inf rejected')

  call t%report('test_core')
end program test_core
