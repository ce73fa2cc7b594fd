!> Example: the exact undamped motion for each regime (text §1.2-1.3, eqs 1.52, 1.66,
!> generalised to any initial state): libration, near-separatrix, separatrix, rotation.
!>
!> For each state it prints theta [rad], Omega [rad/s] and the energy drift at a few
!> times (t in s), then checks the text's own expression (1.52),
!> theta = 2 asin(k sn(K - w0 t | k^2)), against the library for theta0 = 0.9 pi.
program example_exact_motion
  use pendula
  use example_support, only: require
  implicit none
  type(status_t) :: st
  real(wp) :: w0

  call natural_frequency(9.8_wp, 4.9_wp, w0, st)
  call require(st)
  write (*, '(a, f0.12, a)') 'Undamped pendulum, w0 = ', w0, ' 1/s (g = 9.8 m/s^2, l = 4.9 m)'

  call show('libration, the text''s fig 7: theta0 = 0.9 pi, Omega0 = 0', 0.9_wp*pi, 0.0_wp)
  call show('libration, the text''s fig 9: theta0 = 0, v0 = 1.9 w0 l', 0.0_wp, 1.9_wp*w0)
  call show('near the top: theta0 = pi - 1e-10, Omega0 = 0', pi - 1.0e-10_wp, 0.0_wp)
  call show('separatrix: theta0 = 0, Omega0 = 2 w0 (creeps to the top)', 0.0_wp, 2*w0)
  call show('rotation: theta0 = 0, Omega0 = 2.5 w0 (over the top, theta unwrapped)', 0.0_wp, 2.5_wp*w0)
  call show('rotation backwards: theta0 = 1, Omega0 = -4 rad/s', 1.0_wp, -4.0_wp)
  call text_formula_check()

contains

  subroutine show(title, theta0, omega0)
    character(len=*), intent(in) :: title
    real(wp), intent(in) :: theta0, omega0
    type(undamped_motion_t) :: motion
    real(wp) :: t(7), theta(7), omega(7), tp, e0, drift
    integer :: i
    call undamped_init(motion, theta0, omega0, w0, st)
    call require(st)
    tp = undamped_period(motion)
    if (tp > huge(tp)) tp = 8/w0   ! separatrix: infinite period, show a few 1/w0
    t = tp*[0.0_wp, 0.125_wp, 0.25_wp, 0.5_wp, 0.75_wp, 1.0_wp, 10.0_wp]
    call undamped_eval(motion, t, theta, omega)
    e0 = undamped_energy(motion)
    write (*, '(/, a)') title
    write (*, '(a, a, a, es23.16, a, es11.4)') '  regime ', undamped_regime_name(undamped_regime(motion)), &
      ', period or time per turn [s] = ', undamped_period(motion), ', E/E_sep = ', motion%m
    write (*, '(a)') '        t [s]             theta [rad]             Omega [rad/s]     rel. energy drift'
    do i = 1, size(t)
      drift = (pendulum_energy(theta(i), omega(i), w0) - e0)/e0
      write (*, '(f14.6, 2es24.15, es12.2)') t(i), theta(i), omega(i), drift
    end do
  end subroutine show

  subroutine text_formula_check()
    type(undamped_motion_t) :: motion
    real(wp) :: theta0, k, kk, sn, cn, dn, t, theta_text, theta_lib, worst
    integer :: i
    theta0 = 0.9_wp*pi
    k = sin(theta0/2)
    kk = ellipk(k*k)
    call undamped_init(motion, theta0, 0.0_wp, w0, st)
    call require(st)
    worst = 0
    do i = 0, 100
      t = i*0.1_wp
      call ellipj(kk - w0*t, k*k, sn, cn, dn)
      theta_text = 2*asin(k*sn)                    ! eq. 1.52
      theta_lib = undamped_theta(motion, t)
      worst = max(worst, abs(theta_text - theta_lib))
    end do
    write (*, '(/, a, es10.3, a)') 'Text eq. 1.52 vs pendula for theta0 = 0.9 pi, t in [0, 10] s: max |diff| = ', &
      worst, ' rad'
    if (worst > 1.0e-12_wp) then
      write (*, '(a)') 'error: eq. 1.52 and the general solution disagree'
      error stop 1
    end if
  end subroutine text_formula_check

end program example_exact_motion
