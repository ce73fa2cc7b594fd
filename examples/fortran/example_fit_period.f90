!> Example: g from periods timed at large amplitudes (the lab data set of
!> docs/guide/fitting.md, examples/data/periods.csv).
!>
!> A 0.750 m pendulum with a bob of radius 2.0 cm, timed by a photogate (2 ms
!> per period) at amplitudes read to 0.5 degree from 10 to 150 degrees.  The
!> exact period T = 4 K(sin(theta0/2)**2)/w0 (text eq. 1.53) is fitted by
!> weighted least squares (fit_period: closed form in 1/w0, iterated for the
!> amplitude errors), then g = w0**2 l_eff with l_eff = l + 2 r**2/(5 l) (the
!> finite bob).  Beside it: the g the small-angle formula T = 2 pi sqrt(l/g)
!> would give from the same periods.
program example_fit_period
  use pendula
  use example_support, only: require
  implicit none
  real(wp), parameter :: length = 0.750_wp, bob = 0.020_wp
  real(wp), parameter :: degrees(15) = [9.69_wp, 19.80_wp, 30.27_wp, 39.93_wp, 49.31_wp, 59.76_wp, &
                                     70.33_wp, 79.88_wp, 89.93_wp, 100.32_wp, 110.91_wp, 119.64_wp, 130.67_wp, 139.38_wp, 150.09_wp]
  real(wp), parameter :: periods(15) = [1.73928_wp, 1.75136_wp, 1.76401_wp, 1.79480_wp, 1.82533_wp, &
                                   1.86413_wp, 1.91441_wp, 1.97706_wp, 2.05037_wp, 2.14061_wp, 2.25216_wp, 2.38648_wp, 2.55376_wp, &
                                        2.77026_wp, 3.06224_wp]
  type(period_fit_t) :: fit
  type(status_t) :: st
  real(wp) :: l_eff, g, se_g
  integer :: i

  call fit_period(degrees*pi/180, periods, spread(0.002_wp, 1, 15), &
                  spread(0.5_wp*pi/180, 1, 15), fit, st)
  call require(st)
  l_eff = length + 2*bob**2/(5*length)
  g = fit%w0**2*l_eff
  se_g = 2*fit%w0*l_eff*fit%se_w0
  write (*, '(a, f0.6, a, es9.2, a)') 'w0 = ', fit%w0, ' +- ', fit%se_w0, ' 1/s'
  write (*, '(a, f0.5, a, f7.5, a)') 'g  = ', g, ' +- ', se_g, ' m/s^2  (l_eff = l + 2 r^2/(5 l))'
  write (*, '(a, f0.2, a, i0, a, i0)') 'chi-square = ', fit%chi2, ' for ', fit%dof, &
    ' degrees of freedom; effective-variance iterations: ', fit%iterations
  write (*, '(a, f0.4, a)') 'the small-angle formula fitted to the same periods: g = ', &
    fit%w0_small_angle**2*l_eff, ' m/s^2'
  write (*, '(a)') ' theta0[deg]   T [s]    small-angle g from this period alone [m/s^2]'
  do i = 1, size(degrees), 2
    write (*, '(f11.2, f9.5, f12.4)') degrees(i), periods(i), (2*pi/periods(i))**2*l_eff
  end do
  ! The data were made with g = 9.81 m/s^2: the estimate lies within 3 standard errors.
  if (abs(g - 9.81_wp) > 3*se_g) error stop 'the fit is off by more than 3 standard errors'
end program example_fit_period
