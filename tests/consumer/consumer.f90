! A user's program: compiled against an installed pendula with
!   gfortran consumer.f90 $(pkg-config --cflags --libs pendula)
! It touches every concern once, so a missing .mod or symbol in the installed
! copy fails here.
program consumer
  use pendula
  implicit none
  type(status_t) :: st
  type(undamped_motion_t) :: motion
  type(linear_damped_t) :: lin
  type(ode_stats_t) :: stats
  real(wp) :: w0, t0, th(3), om(3)
  integer :: passed

  passed = 0
  call natural_frequency(9.8_wp, 4.9_wp, w0, st)
  call require(status_ok(st) .and. abs(w0 - sqrt(2.0_wp)) <= 4 * epsilon(w0), 'w0 = sqrt(2)')
  call small_angle_period(w0, t0, st)
  call require(abs(t0 - 2 * pi / sqrt(2.0_wp)) <= 8 * epsilon(t0), 'T0 = 2 pi / w0')
  call natural_frequency(-1.0_wp, 4.9_wp, w0, st)
  call require(st%code == PENDULA_ERR_DOMAIN, 'bad g rejected')
  w0 = sqrt(2.0_wp)
  ! K(1/2) = 1.854074677301372 (DLMF 19.20.2 via Gamma(1/4)^2 / (4 sqrt(pi)))
  call require(abs(ellipk(0.5_wp) - 1.8540746773013719_wp) <= 4 * epsilon(1.0_wp) * 1.86_wp, 'K(1/2)')
  call undamped_init(motion, 0.5_wp * pi, 0.0_wp, w0, st)
  call require(status_ok(st) .and. &
      abs(undamped_period(motion) - 4 * ellipk(0.5_wp) / w0) <= 1e-14_wp * undamped_period(motion), &
      'period at 90 degrees = 4 K(1/2) / w0 (eq. 1.53)')
  call linear_damped_init(lin, 0.1_wp, 0.0_wp, w0, 0.0_wp, st)
  call require(status_ok(st) .and. abs(linear_damped_theta(lin, 1.0_wp) - 0.1_wp * cos(w0)) <= 1e-16_wp, &
      'gamma = 0 gives the small-angle solution')
  call rk4_solve([0.0_wp, 0.5_wp, 1.0_wp], 0.0_wp, 2.0_wp, w0, 0.1_wp, 0.01_wp, th, om, stats, st)
  call require(status_ok(st) .and. stats%steps == 100, 'rk4 on the text scene: 100 steps of 0.01 s')
  ! the route's scripts compare this with what the build was asked for
  print '(a, l1)', 'consumer: CVODE available: ', cvode_available()
  print '(a, i0, a)', 'consumer: ', passed, ' passed, 0 failed'

contains

  subroutine require(ok, what)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    if (.not. ok) then
      print '(a)', 'consumer: FAILED: ' // what
      print '(a, i0, a)', 'consumer: ', passed, ' passed, 1 failed'
      error stop 1
    end if
    passed = passed + 1
  end subroutine require

end program consumer
