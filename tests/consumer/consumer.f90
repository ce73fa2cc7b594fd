! A user's program: compiled against an installed pendula with
!   gfortran consumer.f90 $(pkg-config --cflags --libs pendula)
program consumer
  use pendula
  implicit none
  type(status_t) :: st
  real(wp) :: w0, t0
  call natural_frequency(9.8_wp, 4.9_wp, w0, st)
  if (.not. status_ok(st)) error stop 'natural_frequency failed'
  call small_angle_period(w0, t0, st)
  if (abs(w0 - sqrt(2.0_wp)) > 4 * epsilon(w0)) error stop 'w0 wrong'
  if (abs(t0 - 2 * pi / sqrt(2.0_wp)) > 8 * epsilon(t0)) error stop 'T0 wrong'
  call natural_frequency(-1.0_wp, 4.9_wp, w0, st)
  if (st%code /= PENDULA_ERR_DOMAIN) error stop 'bad g not rejected'
  print '(a, f0.15, a, f0.15)', 'w0 = ', w0, '  T0 = ', t0
  print '(a)', 'consumer: 4 passed, 0 failed'
end program consumer
