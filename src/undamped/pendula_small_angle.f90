!> The small-angle (harmonic) model of the pendulum and a rigorous bound on its
!> error against the exact motion.
!>
!> Model (eq. 1.18 generalised to Omega0 /= 0), linearised about the stable
!> equilibrium 2 pi N nearest to theta0 (theta_r = theta0 - 2 pi N):
!>   theta_sa(t) = 2 pi N + theta_r cos(w0 t) + (Omega0/w0) sin(w0 t),
!>   Omega_sa(t) = -theta_r w0 sin(w0 t) + Omega0 cos(w0 t).
!> For |theta0| < pi this is exactly theta0 cos(w0 t) + (Omega0/w0) sin(w0 t).
!>
!> Error bound (libration only).  The exact motion is the Fourier series
!>   theta - 2 pi N = sum_n a_n sin((2n+1)(w t + phi)),
!>   a_n = 8 q^(n+1/2) / ((2n+1)(1 + q^(2n+1))),  q = exp(-pi K'/K) (the nome),
!>   w = pi w0 / (2 K(m)),  phi = pi u0 / (2 K)
!> (the Fourier series of the pendulum angle, checked against mpmath in the
!> tests; for small m, q ~ m/16 and a_0 ~ 2k = theta_max), and
!> the model is A sin(w0 t + phi_sa), A = hypot(theta_r, Omega0/w0).  The
!> triangle inequality gives, for all |t| <= tmax,
!>   |theta - theta_sa| <= |a_0 - A| + 2 A sin(min(pi, |phi - phi_sa| + |w - w0| tmax)/2)
!>                          + sum_{n>=1} a_n,
!> with the harmonic tail sum_{n>=1} a_n <= 8 q^(3/2) / (3 (1 - q)), and the same
!> for Omega with a_0 w, A w0 and the tail 8 w q^(3/2)/(1 - q).  Both are capped
!> by the trivial bound (amplitude of the exact motion + A).  The phase drift
!> w0 - w = w0 (1 - pi/(2K)) ~ w0 m/4 = w0 theta_max^2/16 dominates long runs:
!> the model is good to delta over [0, tmax] roughly while A (m/4) w0 tmax < delta.
module pendula_small_angle
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf
  use pendula_kinds, only: wp
  use pendula_status, only: status_t, check_finite, check_positive, check_all_finite, &
                            check_same_size, PENDULA_OK
  use pendula_constants, only: pi
  use pendula_elliptic, only: ellipkm1
  use pendula_undamped, only: undamped_motion_t, REGIME_LIBRATION, reduce_angle_2pi
  use pendula_undamped_motion, only: M_TINY
  implicit none
  private
  public :: small_angle, harmonic_state, small_angle_solve, small_angle_eval, small_angle_bound, small_angle_phase_drift

contains

  !> Small-angle model at time t [s] for the initial state theta0 [rad],
  !> Omega0 [rad/s], w0 [1/s] > 0 (elemental; the caller checks the inputs, or
  !> use the motion form).  theta [rad], omega [rad/s] to a few ulps of the
  !> model (arguments w0 t rounded once).
  elemental subroutine small_angle(t, theta0, omega0, w0, theta, omega)
    real(wp), intent(in) :: t  !< time [s]
    real(wp), intent(in) :: theta0  !< initial angle theta(t(1)) [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity Omega(t(1)) [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], > 0 (not checked)
    real(wp), intent(out) :: theta  !< model angle [rad]
    real(wp), intent(out) :: omega  !< model angular velocity [rad/s]
    real(wp) :: n, r_hi, r_lo, center
    call reduce_angle_2pi(theta0, n, r_hi, r_lo)
    center = theta0 - r_hi   ! 2 pi n to the rounding of theta0 (exact when n = 0)
    call harmonic_state(center, r_hi, omega0, w0, t, theta, omega)
  end subroutine small_angle

  !> The harmonic motion center + r cos(w0 t) + (Omega0/w0) sin(w0 t) [rad]
  !> and its rate -r w0 sin(w0 t) + Omega0 cos(w0 t) [rad/s] at t [s], for
  !> w0 > 0 [1/s] (elemental, unchecked).  Finite whenever the true values are
  !> representable: Omega0/w0 and r w0 may overflow and w0 t may underflow, so
  !> those inputs take sin(w0 t)/w0 -> t and r (w0 sin) instead; the usual
  !> inputs take the plain formula (a few ulps).
  elemental subroutine harmonic_state(center, r, omega0, w0, t, theta, omega)
    real(wp), intent(in) :: center  !< equilibrium angle the motion is about [rad]
    real(wp), intent(in) :: r  !< initial offset from center [rad]
    real(wp), intent(in) :: omega0  !< initial angular velocity Omega(t(1)) [rad/s], finite
    real(wp), intent(in) :: w0  !< angular frequency [1/s], > 0
    real(wp), intent(in) :: t  !< time [s]
    real(wp), intent(out) :: theta  !< model angle [rad]
    real(wp), intent(out) :: omega  !< model angular velocity [rad/s]
    real(wp) :: c, s, x, sw
    x = phase(w0, t)
    c = cos(x)
    s = sin(x)
    if (abs(x) >= tiny(1.0_wp) .and. exponent(omega0) - exponent(w0) < 1000 &
        .and. exponent(r) + exponent(w0) < 1000) then
      theta = center + (r*c + (omega0/w0)*s)
      omega = -(r*w0)*s + omega0*c
    else
      ! sin(w0 t)/w0 = t (1 - (w0 t)^2/6 + ...): exactly t in double below 2^-26
      if (abs(x) < 2.0_wp**(-26)) then
        sw = t
      else
        sw = s/w0
      end if
      theta = center + (r*c + omega0*sw)
      omega = -r*(w0*s) + omega0*c
    end if
  end subroutine harmonic_state

  !> Checked array form of `small_angle`: theta(i), omega(i) at t(i) for one
  !> initial state; theta0, Omega0 and every t finite, w0 finite and > 0,
  !> equal sizes (status names the argument otherwise).
  pure subroutine small_angle_solve(t, theta0, omega0, w0, theta, omega, status)
    real(wp), intent(in) :: t(:)
    !< output times [s]: finite, strictly increasing, size >= 1; t(1) is the initial time
    real(wp), intent(in) :: theta0  !< initial angle theta(t(1)) [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity Omega(t(1)) [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency sqrt(g/l) [1/s], finite, > 0
    real(wp), intent(out) :: theta(:)  !< angle theta(t(i)) [rad], size(t) elements
    real(wp), intent(out) :: omega(:)  !< angular velocity Omega(t(i)) [rad/s], size(t) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    theta = 0
    omega = 0
    call check_finite('theta0', theta0, status)
    call check_finite('omega0', omega0, status)
    call check_positive('w0', w0, status)
    call check_all_finite('t', t, status)
    call check_same_size('theta', size(theta), 't', size(t), status)
    call check_same_size('omega', size(omega), 't', size(t), status)
    if (status%code /= PENDULA_OK) return
    call small_angle(t, theta0, omega0, w0, theta, omega)
  end subroutine small_angle_solve

  !> Small-angle model for a built motion (same formula; the motion holds the
  !> checked, reduced initial state).
  elemental subroutine small_angle_eval(motion, t, theta, omega)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init
    real(wp), intent(in) :: t  !< time [s]
    real(wp), intent(out) :: theta  !< model angle [rad]
    real(wp), intent(out) :: omega  !< model angular velocity [rad/s]
    call harmonic_state(motion%center, motion%theta_r, motion%omega0, motion%w0, t, theta, omega)
  end subroutine small_angle_eval

  !> w0 t, with whole periods 2 pi/w0 taken out first (exactly, by modulo) when
  !> w0 t would overflow.
  elemental real(wp) function phase(w0, t) result(x)
    real(wp), intent(in) :: w0, t
    if (exponent(t) > 1000 - exponent(w0)) then
      x = w0*modulo(t, 2*pi/w0)
    else
      x = w0*t
    end if
  end function phase

  !> Relative frequency defect 1 - w/w0 = 1 - pi/(2 K(m)) of the exact libration
  !> (~ m/4 for small m; the phase error of the model grows like this times
  !> w0 t).  +inf outside libration (no frequency to compare).
  elemental real(wp) function small_angle_phase_drift(motion) result(drift)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init
    real(wp) :: m
    if (motion%regime /= REGIME_LIBRATION) then
      drift = ieee_value(1.0_wp, ieee_positive_inf)
      return
    end if
    m = motion%m
    if (m < 1.0e-4_wp) then
      ! 2K/pi - 1 = m/4 + 9m^2/64 + 25m^3/256 + O(m^4) (DLMF 19.5.1) avoids 2K - pi cancelling
      drift = (m*(0.25_wp + m*(9.0_wp/64 + m*(25.0_wp/256))))/(2*motion%kk/pi)
    else
      drift = (2*motion%kk - pi)/(2*motion%kk)
    end if
  end function small_angle_phase_drift

  !> Rigorous bounds dtheta [rad] and domega [rad/s] on |theta_sa - theta| and
  !> |Omega_sa - Omega| (model minus exact motion) over all |t| <= |tmax| [s]
  !> (derivation in the module header; includes a few-eps allowance for
  !> rounding in both computed solutions).  Libration only: +inf for the
  !> separatrix and rotation (the model never describes going over the top).
  !> Non-decreasing in |tmax|; 0 for the pendulum at rest at the bottom.
  elemental subroutine small_angle_bound(motion, tmax, dtheta, domega)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init
    real(wp), intent(in) :: tmax  !< time span [s]: the bound holds for |t| <= |tmax|
    real(wp), intent(out) :: dtheta  !< bound on the angle error [rad]
    real(wp), intent(out) :: domega  !< bound on the angular velocity error [rad/s]
    real(wp), parameter :: eps = epsilon(1.0_wp)
    real(wp), parameter :: subnormal_steps = scale(1.0_wp, -1070)  ! 16 of the smallest subnormal
    real(wp) :: q, kp, w, a1, amp, x, tail, dphi, drift, w0, ph, slack
    if (motion%regime /= REGIME_LIBRATION) then
      dtheta = ieee_value(1.0_wp, ieee_positive_inf)
      domega = dtheta
      return
    end if
    if (motion%theta_r == 0 .and. motion%omega0 == 0) then
      ! at rest at the bottom: both models give 2 pi N and 0 exactly
      dtheta = 0
      domega = 0
      return
    end if
    w0 = motion%w0
    amp = hypot(motion%theta_r, motion%omega0/w0)
    ! rounding of both computed solutions: phases w0 t, amplitudes, 2 pi N
    slack = 16*eps*(abs(motion%center) + motion%amplitude + amp)*(1 + w0*abs(tmax))
    if (motion%m < M_TINY) then
      ! m lost to the subnormal range (|theta_r| and |Omega0/w0| below ~1e-146; the nome
      ! would underflow): the model's own error, A O(m) (1 + w0 tmax), is below 1e-290 of
      ! the rounding allowance; subnormal results also round to absolute steps
      dtheta = min(slack, (motion%amplitude + amp)*(1 + 1.0e-12_wp)) + subnormal_steps
      domega = min(w0*slack, (2*motion%k*w0 + amp*w0)*(1 + 1.0e-12_wp)) + subnormal_steps
      return
    end if
    kp = ellipkm1(motion%m)                 ! K'(m) = K(1 - m)
    q = exp(-pi*kp/motion%kk)
    drift = small_angle_phase_drift(motion)
    w = w0*(1 - drift)
    a1 = 8*sqrt(q)/(1 + q)
    dphi = pi*motion%phase/(2*motion%kk) - atan2(motion%theta_r, motion%omega0/w0)
    dphi = modulo(dphi + pi, 2*pi) - pi
    x = abs(dphi) + w0*drift*abs(tmax)
    ph = 2*sin(0.5_wp*min(pi, x))
    tail = 8*q*sqrt(q)/(1 - q)
    dtheta = abs(a1 - amp) + amp*ph + tail/3
    dtheta = min(dtheta, motion%amplitude + amp)*(1 + 1.0e-12_wp) + slack
    domega = abs(a1*w - amp*w0) + amp*w0*ph + w*tail
    domega = min(domega, 2*motion%k*w0 + amp*w0)*(1 + 1.0e-12_wp) + w0*slack
  end subroutine small_angle_bound

end module pendula_small_angle
