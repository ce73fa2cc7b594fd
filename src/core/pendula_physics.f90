!> Physical parameters of the pendulum as the text writes them (§1, §2):
!> g [m/s^2], l [m], mass m [kg], damping coefficient b [kg/s], and the
!> derived rates w0 = sqrt(g/l) [1/s] and gamma = b/m [1/s].
module pendula_physics
  use pendula_kinds, only: wp
  use pendula_constants, only: pi   ! re-exported: user code has used pendula_physics' pi
  use pendula_status, only: status_t, check_positive, check_nonnegative, check_range, set_error, PENDULA_OK, &
                            PENDULA_ERR_DOMAIN
  implicit none
  private
  public :: natural_frequency, damping_rate, small_angle_period, period_series, pi
  public :: PENDULA_G_DEFAULT, PENDULA_LENGTH_DEFAULT, PENDULA_PARAM_RTOL

  !> The text's pendulum (§1.2-1.3, §2.2): g [m/s^2] and length [m], so that
  !> w0 = sqrt(g/length) = sqrt(2) 1/s.  The one default pendulum of the library:
  !> every interface that needs a pendulum and is given none uses these.
  real(wp), parameter :: PENDULA_G_DEFAULT = 9.8_wp, PENDULA_LENGTH_DEFAULT = 4.9_wp
  !> Relative tolerance within which a redundant description of the pendulum
  !> must agree with itself (gamma with b/mass, w0 with sqrt(g/length)): about
  !> 4500 ulps, so values computed along different roundings still agree.
  real(wp), parameter :: PENDULA_PARAM_RTOL = 1.0e-12_wp

contains

  !> Natural angular frequency w0 = sqrt(g/length) [1/s] (eq. 1.7; the text's l).
  !> g > 0 and length > 0, finite; otherwise status is set and w0 = 0.  Within
  !> 1 ulp, nonzero, and finite whenever sqrt(g/l) is (g/l itself may leave
  !> the double range: it is never formed then); status is set where
  !> w0 would exceed the largest double (g/l > about 3e616).
  pure subroutine natural_frequency(g, length, w0, status)
    real(wp), intent(in) :: g  !< gravitational acceleration [m/s^2], finite, > 0
    real(wp), intent(in) :: length  !< pendulum length [m], finite, > 0
    real(wp), intent(out) :: w0  !< sqrt(g/length) [1/s] (0 on error)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    real(wp) :: fq
    integer :: e
    w0 = 0
    call check_positive('g', g, status)
    call check_positive('length', length, status)
    if (status%code /= PENDULA_OK) return
    e = exponent(g) - exponent(length)
    if (abs(e) < 1000 .and. exponent(g) > -1000 .and. exponent(length) > -1000) then
      w0 = sqrt(g/length)
    else
      ! g/l would overflow or lose bits below the normal range: divide the
      ! significands, take the root and put half the (even) exponent back.
      fq = fraction(g)/fraction(length)
      if (modulo(e, 2) /= 0) then
        fq = 2*fq
        e = e - 1
      end if
      fq = sqrt(fq)
      if (exponent(fq) + e/2 > maxexponent(fq)) then   ! before scale(): no overflow flag
        call set_error(status, PENDULA_ERR_DOMAIN, 'g and length are out of range together: w0 = sqrt(g/length) '// &
                       'would exceed the largest double; need sqrt(g)/sqrt(length) <= 1.8e308')
      else
        w0 = scale(fq, e/2)
      end if
    end if
  end subroutine natural_frequency

  !> Damping rate gamma = b/m [1/s] (eq. 2.1). b >= 0 and m > 0, finite, with
  !> b/m finite; otherwise status is set and gamma = 0.
  pure subroutine damping_rate(b, mass, gamma, status)
    real(wp), intent(in) :: b  !< damping coefficient b [kg/s] (gamma = b/mass), finite, >= 0
    real(wp), intent(in) :: mass  !< mass [kg], finite, > 0
    real(wp), intent(out) :: gamma  !< damping rate b/mass [1/s] (0 on error)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    gamma = 0
    call check_nonnegative('b', b, status)
    call check_positive('mass', mass, status)
    if (status%code /= PENDULA_OK) return
    ! b/mass > huge only when mass < 1; decided before dividing, since the
    ! overflowing division would trap in the checked build
    if (mass < 1) then
      if (b > huge(b)*mass) then
        call set_error(status, PENDULA_ERR_DOMAIN, 'b and mass are out of range together: gamma = b/mass '// &
                       'exceeds the largest double')
        return
      end if
    end if
    gamma = b/mass
  end subroutine damping_rate

  !> Small-angle period T0 = 2 pi / w0 [s] (eq. 1.8). w0 finite and at least
  !> 2 pi / DBL_MAX (3.5e-308), below which T0 overflows; otherwise status is
  !> set and T0 = 0.  Correctly rounded up to the division: 1 ulp.
  pure subroutine small_angle_period(w0, t0, status)
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], finite, >= 2 pi / huge
    real(wp), intent(out) :: t0  !< small-angle period 2 pi/w0 [s] (0 on error)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    t0 = 0
    call check_range('w0', w0, 2*pi/huge(w0), huge(w0), &
                     '[3.5e-308, 1.8e308] (T0 = 2 pi/w0 exceeds the largest double below)', status)
    if (status%code /= PENDULA_OK) return
    t0 = 2*pi/w0
  end subroutine small_angle_period

  !> The textbook's amplitude correction to the period, T0 (1 + m/4 + 9 m^2/64)
  !> [s], T0 = 2 pi/w0 (eq. 1.8): the first three terms of T = T0 2K(m)/pi
  !> (DLMF 19.5.1) for a libration of parameter m = k^2 (m = sin^2(theta0/2)
  !> released from rest).  A model, not the period: its relative error is
  !> 25 m^3/256 + O(m^4) (the exact period: undamped_period).  m in [0, 1] and w0
  !> as for small_angle_period; otherwise status is set and t = 0.  The one
  !> home of this series (examples, figures and the command line call it).
  pure subroutine period_series(m, w0, t, status)
    real(wp), intent(in) :: m  !< elliptic parameter m = k**2, in [0, 1] (sin^2(theta0/2) from rest)
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], finite, >= 2 pi / huge
    real(wp), intent(out) :: t  !< series period T0 (1 + m/4 + 9 m^2/64) [s] (0 on error)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    t = 0
    call check_range('m', m, 0.0_wp, 1.0_wp, '[0, 1]', status)
    if (status%code /= PENDULA_OK) return
    call small_angle_period(w0, t, status)
    if (status%code /= PENDULA_OK) return
    t = t*(1 + m/4 + 9*m**2/64)
  end subroutine period_series

end module pendula_physics
