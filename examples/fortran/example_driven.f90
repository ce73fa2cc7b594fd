!> Example: the driven damped pendulum (src/driven).
!>
!> Baker & Gollub's pendulum, theta'' + theta'/2 + sin(theta) = F cos(2t/3):
!> a small bifurcation table (the period of the attractor found from
!> theta0 = 0.2 for F = 0.9 ... 1.5, by driven_orbits: 0 means no period
!> <= 8, i.e. chaos), the Lyapunov exponents at F = 1.15 (chaotic: the
!> largest > 0, the sum -gamma) and at F = 0.9 against the Floquet
!> multipliers of its periodic orbit, and Kapitza's inverted pendulum made
!> stable by a fast vertical pivot.
program example_driven
  use pendula
  use example_support, only: require
  implicit none
  integer, parameter :: nf = 7
  real(wp) :: f(nf), tp(nf), op(nf), mu(4, nf), res(nf), ly(2, 1), le(2, 1), tp1(1), op1(1), mu1(4, 1), r1(1)
  integer :: per(nf), wnd(nf), codes(nf), i, c1(1), p1(1), w1(1)
  type(status_t) :: st

  f = [0.9_wp, 1.0_wp, 1.07_wp, 1.15_wp, 1.35_wp, 1.45_wp, 1.5_wp]
  call driven_orbits([(0.2_wp, i=1, nf)], [0.0_wp], [1.0_wp], [0.5_wp], DRIVE_TORQUE, f, [2.0_wp/3], [0.0_wp], 128, [0], &
                     300, 8, 1.0e-6_wp, per, wnd, tp, op, mu, res, codes, st)
  call require(st)
  write (*, '(a)') '     F   period  winding   |mu1|'
  do i = 1, nf
    write (*, '(f6.2, i8, i9, f9.4)') f(i), per(i), wnd(i), hypot(mu(1, i), mu(2, i))
  end do

  call driven_lyapunov([0.2_wp], [0.0_wp], [1.0_wp], [0.5_wp], DRIVE_TORQUE, [1.15_wp], [2.0_wp/3], [0.0_wp], &
                       128, 100, 4000, ly, le, c1, st)
  call require(st)
  write (*, '(a, f8.4, a, f7.4, a, f8.4, a, es9.2)') 'F = 1.15: lambda1 = ', ly(1, 1), ' +- ', le(1, 1), &
    ' 1/s, lambda2 = ', ly(2, 1), ', sum + gamma = ', ly(1, 1) + ly(2, 1) + 0.5_wp

  call driven_lyapunov([0.2_wp], [0.0_wp], [1.0_wp], [0.5_wp], DRIVE_TORQUE, [0.9_wp], [2.0_wp/3], [0.0_wp], &
                       128, 200, 2000, ly, le, c1, st)
  call require(st)
  write (*, '(a, 2f9.5, a, 2f9.5)') 'F = 0.90: lambda = ', ly(:, 1), '; ln|mu|/T = ', &
    log(hypot(mu(1, 1), mu(2, 1)))/(3*pi), log(hypot(mu(3, 1), mu(4, 1)))/(3*pi)

  ! Kapitza: (a/l)**2 Omega**2 / 2 = 2 > w0**2 = 1, so theta = pi is stable
  call driven_orbits([pi], [0.0_wp], [1.0_wp], [0.1_wp], DRIVE_PIVOT, [0.1_wp], [20.0_wp], [0.0_wp], 128, [1], &
                     0, 1, 1.0e-6_wp, p1, w1, tp1, op1, mu1, r1, c1, st)
  call require(st)
  write (*, '(a, f7.4, a, l1)') 'Kapitza, a/l = 0.1, Omega = 20 w0: |mu1| = ', hypot(mu1(1, 1), mu1(2, 1)), &
    ', inverted state stable: ', hypot(mu1(1, 1), mu1(2, 1)) < 1
end program example_driven
