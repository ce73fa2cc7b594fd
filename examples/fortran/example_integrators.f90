!> Example: RK4 vs CVODE vs exact solutions on the text's scenarios (§2.2, figs 14-15).
!>
!> 1. The text's nonlinear damped scene: g = 9.8 m/s^2, l = 4.9 m, m = 0.1 kg,
!>    b = 0.01 and 0.05 kg/s (gamma = b/m), theta0 = 0, Omega0 = 2 rad/s, t <= 30 s.
!>    Max |theta error| [rad] over t = 0, 1, ..., 30 s of RK4 at the text's h = 0.05 s,
!>    of CVODE (Adams, rtol 1e-8) and of the text's listing AS PRINTED (line 67 reads
!>    m2 = m1 * h * k1 / 2.0 for m1 + h * k1 / 2.0), against CVODE BDF at rtol 1e-12
!>    (RK4 at h = 1e-4 s when SUNDIALS is not built).
!> 2. gamma = 0: both integrators against the exact elliptic solution.
!> 3. Small amplitude with damping: both against the linear closed form.
program example_integrators
  use pendula
  use example_support, only: require
  implicit none
  integer, parameter :: n = 31
  real(wp) :: t(n), w0, gamma, b(2) = [0.01_wp, 0.05_wp]
  real(wp) :: th_ref(n), om_ref(n), th(n), om(n), th_txt(n), om_txt(n)
  type(ode_stats_t) :: stats
  type(status_t) :: st
  type(undamped_motion_t) :: exact
  type(linear_damped_t) :: lin
  integer :: i
  logical :: have_cvode

  have_cvode = cvode_available()
  t = [(real(i, wp), i=0, n - 1)]
  call natural_frequency(9.8_wp, 4.9_wp, w0, st)
  call require(st)
  write (*, '(a, l1)') 'CVODE (SUNDIALS) built: ', have_cvode

  write (*, '(/, a)') '1. The text''s scene, theta0 = 0, Omega0 = 2 rad/s, t in [0, 30] s: max |theta - reference| [rad]'
  write (*, '(a)') '   b [kg/s]  gamma [1/s]   RK4 h=0.05 s   CVODE Adams 1e-8   text listing (as printed)   RK4 steps'
  do i = 1, 2
    call damping_rate(b(i), 0.1_wp, gamma, st)
    call require(st)
    call reference(0.0_wp, 2.0_wp, gamma, th_ref, om_ref)
    call rk4_solve(t, 0.0_wp, 2.0_wp, w0, gamma, 0.05_wp, th, om, stats, st)
    call require(st)
    call text_listing(0.0_wp, 2.0_wp, gamma, 0.05_wp, th_txt, om_txt)
    write (*, '(f10.2, f12.3, es15.3, a19, es22.3, i18)', advance='no') b(i), gamma, &
      maxval(abs(th - th_ref)), cvode_error(0.0_wp, 2.0_wp, gamma, th_ref), &
      maxval(abs(th_txt - th_ref)), stats%steps
    write (*, *)
  end do

  write (*, '(/, a)') '2. Undamped (gamma = 0), theta0 = 0.9 pi, Omega0 = 0: max |theta - exact elliptic| [rad]'
  call undamped_init(exact, 0.9_wp*pi, 0.0_wp, w0, st)
  call require(st)
  call undamped_eval(exact, t, th_ref, om_ref)
  call rk4_solve(t, 0.9_wp*pi, 0.0_wp, w0, 0.0_wp, 0.01_wp, th, om, stats, st)
  call require(st)
  write (*, '(a, es10.3, a, a)') '   RK4 h = 0.01 s: ', maxval(abs(th - th_ref)), &
    '   CVODE Adams 1e-8:', cvode_error(0.9_wp*pi, 0.0_wp, 0.0_wp, th_ref)

  write (*, '(/, a)') '3. Small amplitude, theta0 = 1e-3 rad, gamma = 0.5 1/s: max |theta - linear closed form| [rad]'
  write (*, '(a)') '   (the nonlinearity itself is ~theta0^3/16 ~ 6e-11 rad)'
  call linear_damped_init(lin, 1.0e-3_wp, 0.0_wp, w0, 0.5_wp, st)
  call require(st)
  call linear_damped_state(lin, t, th_ref, om_ref)
  call rk4_solve(t, 1.0e-3_wp, 0.0_wp, w0, 0.5_wp, 0.01_wp, th, om, stats, st)
  call require(st)
  write (*, '(a, es10.3, a, a)') '   RK4 h = 0.01 s: ', maxval(abs(th - th_ref)), &
    '   CVODE Adams 1e-8:', cvode_error(1.0e-3_wp, 0.0_wp, 0.5_wp, th_ref)

contains

  !> A tight solution: CVODE BDF at rtol 1e-12 when built, else RK4 at h = 1e-4 s.
  subroutine reference(theta0, omega0, gam, theta, omega)
    real(wp), intent(in) :: theta0, omega0, gam
    real(wp), intent(out) :: theta(:), omega(:)
    type(ode_stats_t) :: s
    type(status_t) :: stat
    if (have_cvode) then
      call cvode_solve(t, theta0, omega0, w0, gam, 1.0e-12_wp, 1.0e-14_wp, PENDULA_CVODE_BDF, &
                       10000000_i8, theta, omega, s, stat)
    else
      call rk4_solve(t, theta0, omega0, w0, gam, 1.0e-4_wp, theta, omega, s, stat)
    end if
    call require(stat)
  end subroutine reference

  !> Max |theta - ref| of CVODE Adams at rtol 1e-8, as text ('not built' without SUNDIALS).
  function cvode_error(theta0, omega0, gam, ref) result(text)
    real(wp), intent(in) :: theta0, omega0, gam, ref(:)
    character(len=19) :: text
    real(wp) :: theta(n), omega(n)
    type(ode_stats_t) :: s
    type(status_t) :: stat
    if (.not. have_cvode) then
      text = '          not built'
      return
    end if
    call cvode_solve(t, theta0, omega0, w0, gam, 1.0e-8_wp, 1.0e-10_wp, PENDULA_CVODE_ADAMS, &
                     10000000_i8, theta, omega, s, stat)
    call require(stat)
    write (text, '(es19.3)') maxval(abs(theta - ref))
  end function cvode_error

  !> The text's §2.2 listing as printed (with its line-67 typo), sampled at t(:).
  !> Kept here only to show how far it drifts; the library's RK4 is correct.
  subroutine text_listing(theta0, omega0, gam, h, theta, omega)
    real(wp), intent(in) :: theta0, omega0, gam, h
    real(wp), intent(out) :: theta(:), omega(:)
    real(wp) :: y, u, m1, m2, m3, m4, k1, k2, k3, k4, tt
    integer :: j, step, per_output
    y = theta0
    u = omega0
    tt = 0
    theta(1) = y
    omega(1) = u
    per_output = nint((t(2) - t(1))/h)
    do j = 2, size(t)
      do step = 1, per_output
        m1 = u
        k1 = -gam*u - w0**2*sin(y)
        m2 = m1*h*k1/2          ! the typo: should be m1 + h * k1 / 2
        k2 = -gam*m2 - w0**2*sin(y + h*m1/2)
        m3 = m1 + h*k2/2
        k3 = -gam*m3 - w0**2*sin(y + h*m2/2)
        m4 = m1 + h*k3
        k4 = -gam*m4 - w0**2*sin(y + h*m3)
        y = y + h*(m1 + 2*m2 + 2*m3 + m4)/6
        u = u + h*(k1 + 2*k2 + 2*k3 + k4)/6
        tt = tt + h
      end do
      theta(j) = y
      omega(j) = u
    end do
  end subroutine text_listing

end program example_integrators
