!> Example: the period of the pendulum, exact against small-angle and the usual
!> approximations (text §1.2, eqs 1.8 and 1.53; fig 4).
!>
!> For amplitudes theta0 from 1 to 179.9 degrees (released from rest, Omega0 = 0;
!> g = 9.8 m/s^2, l = 4.9 m as in the text) it prints the exact period
!> T = 4 K(k^2)/w0, k = sin(theta0/2), and the relative error of
!>   small angle      T0 = 2 pi/w0                              (eq. 1.8)
!>   series           T0 (1 + k^2/4 + 9 k^4/64)                 (first terms of 2K/pi)
!>   Kidd-Fogg        T0 / sqrt(cos(theta0/2))
!>   Lima-Arun        -T0 ln(c)/(1 - c), c = cos(theta0/2)
!> then the period of a few states the text cannot handle (Omega0 /= 0, rotation).
program example_period_table
  use pendula
  use example_support, only: require
  implicit none
  real(wp), parameter :: degrees(14) = [1.0_wp, 5.0_wp, 10.0_wp, 20.0_wp, 30.0_wp, 45.0_wp, &
                                        60.0_wp, 90.0_wp, 120.0_wp, 150.0_wp, 170.0_wp, 179.0_wp, 179.9_wp, 179.999_wp]
  type(status_t) :: st
  type(undamped_motion_t) :: motion
  real(wp) :: w0, t0, theta0, k, c, t_exact, t_series, t_kf, t_la
  integer :: i

  call natural_frequency(9.8_wp, 4.9_wp, w0, st)
  call require(st)
  call small_angle_period(w0, t0, st)
  call require(st)
  write (*, '(a, f0.12, a, f0.12, a)') 'w0 = ', w0, ' 1/s, small-angle period T0 = ', t0, ' s'
  write (*, '(a)') 'Released from rest (Omega0 = 0); errors are (approximation - exact)/exact.'
  write (*, '(a)') ' theta0[deg]  k=sin(th0/2)   T exact [s]     T/T0    small-angle    series'// &
    '    Kidd-Fogg   Lima-Arun'
  do i = 1, size(degrees)
    theta0 = degrees(i)*pi/180
    call undamped_init(motion, theta0, 0.0_wp, w0, st)
    call require(st)
    t_exact = undamped_period(motion)
    k = sin(theta0/2)
    c = cos(theta0/2)
    call period_series(k**2, w0, t_series, st)
    call require(st)
    t_kf = t0/sqrt(c)
    t_la = -t0*log(c)/(1 - c)
    write (*, '(f11.3, f13.8, f15.9, f9.4, 4es12.3)') degrees(i), k, t_exact, t_exact/t0, &
      (t0 - t_exact)/t_exact, (t_series - t_exact)/t_exact, (t_kf - t_exact)/t_exact, &
      (t_la - t_exact)/t_exact
  end do

  write (*, '(/, a)') 'Any initial state (the text covers only Omega0 = 0 and theta0 = 0):'
  write (*, '(a)') '  theta0 [rad]  Omega0 [rad/s]   E/E_sep     motion        period or time per turn [s]'
  call show(0.5_wp, 1.0_wp)
  call show(0.0_wp, 1.999_wp*w0)
  call show(0.0_wp, 2.0_wp*w0)
  call show(0.0_wp, 2.001_wp*w0)
  call show(1.0_wp, 4.0_wp)
  call show(pi - 1.0e-10_wp, 0.0_wp)

contains

  subroutine show(th0, om0)
    real(wp), intent(in) :: th0, om0
    type(undamped_motion_t) :: mo
    type(status_t) :: s
    call undamped_init(mo, th0, om0, w0, s)
    call require(s)
    write (*, '(f14.10, f14.8, f13.8, 3x, a12, es26.16)') th0, om0, mo%m, &
      undamped_regime_name(undamped_regime(mo)), undamped_period(mo)
  end subroutine show

end program example_period_table
