!> Example: the linear damped pendulum (text §2.1, eqs 2.4-2.47) in each regime.
!>
!> For the text's w0 = sqrt(2) 1/s and gamma = 0.5, 2, 3, 5 x w0 (under-, critically
!> and over-damped; the text's figs 10, 11, 13 use 3, 5 and 2, and its §2.1.3 on the
!> under-damped case is empty) it prints the regime and its numbers, then theta [rad]
!> and Omega [rad/s] at a few times for theta0 = 0.1 rad and Omega0 = 0, 0.5, -0.5 rad/s.
!> A last block shows the closed form is continuous through gamma = 2 w0, where
!> the text's eq. 2.29 divides by lambda2 - lambda1 -> 0.
program example_linear_damping
  use pendula
  use example_support, only: require
  implicit none
  real(wp), parameter :: ratios(4) = [0.5_wp, 2.0_wp, 3.0_wp, 5.0_wp]
  real(wp), parameter :: omega0s(3) = [0.0_wp, 0.5_wp, -0.5_wp]
  real(wp), parameter :: times(5) = [0.0_wp, 0.5_wp, 1.0_wp, 2.0_wp, 5.0_wp]
  real(wp), parameter :: theta0 = 0.1_wp
  type(status_t) :: st
  type(damping_regime_t) :: info
  type(linear_damped_t) :: sol
  real(wp) :: w0, gamma, th, om, eps_rel
  integer :: i, j, k

  call natural_frequency(9.8_wp, 4.9_wp, w0, st)
  call require(st)
  write (*, '(a, f0.12, a)') 'Linear damped pendulum, w0 = sqrt(g/l) = ', w0, ' 1/s (g = 9.8 m/s^2, l = 4.9 m)'

  do i = 1, size(ratios)
    gamma = ratios(i)*w0
    call damping_regime(w0, gamma, info, st)
    call require(st)
    write (*, '(/, a, f4.1, a, f8.6, a, a)') 'gamma = ', ratios(i), ' w0 = ', gamma, ' 1/s: ', &
      regime_name(info%regime)
    write (*, '(a, 2(" (", es12.5, ",", es12.5, ")"))') '  eigenvalues lambda1, lambda2 [1/s]:', &
      info%lambda1, info%lambda2
    write (*, '(a, es12.5, a, es12.5, a, es12.5)') '  Q = ', info%quality_factor, &
      '   omega_d [1/s] = ', info%omega_d, '   log decrement = ', info%log_decrement
    write (*, '(a, es12.5, a, es12.5)') '  decay rates slow/fast [1/s] = ', info%decay_slow, ' / ', info%decay_fast
    write (*, '(a)') '    Omega0 [rad/s]     t [s]      theta [rad]    Omega [rad/s]'
    do j = 1, size(omega0s)
      call linear_damped_init(sol, theta0, omega0s(j), w0, gamma, st)
      call require(st)
      do k = 1, size(times)
        call linear_damped_state(sol, times(k), th, om)
        write (*, '(4x, f10.3, 4x, f8.3, 2(3x, es14.6))') omega0s(j), times(k), th, om
      end do
    end do
  end do

  ! Continuity through critical damping: gamma = 2 w0 (1 + eps_rel).
  write (*, '(/, a)') 'Through critical damping (theta0 = 0.1 rad, Omega0 = 0.5 rad/s, t = 2 s):'
  write (*, '(a)') '   gamma/(2 w0) - 1     regime          theta [rad]'
  do k = -3, 3
    eps_rel = sign(10.0_wp**(-4*(4 - abs(k))), real(k, wp))
    if (k == 0) eps_rel = 0
    gamma = 2*w0*(1 + eps_rel)
    call linear_damped_init(sol, theta0, 0.5_wp, w0, gamma, st)
    call require(st)
    write (*, '(3x, es12.3, 4x, a12, 4x, es22.15)') eps_rel, regime_name(sol%info%regime), sol%theta(2.0_wp)
  end do

end program example_linear_damping
