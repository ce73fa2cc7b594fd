!> The elliptic parameter of undamped states without building a motion: 1 - m, m and
!> the regime of one state (state_parameter) or of a block of states side by side
!> (parameter_lanes, a block kernel compiled per instruction set: runtime CPU dispatch),
!> and the period's parts from them.  The same numbers as set_geometry (pendula_undamped_motion) forms, step for step; used by
!> undamped_states and undamped_properties (pendula_undamped_many).
module pendula_undamped_parameter
  use, intrinsic :: iso_c_binding, only: c_int
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf
  use pendula_kinds, only: wp
  use pendula_constants, only: pi, half_pi, half_pi_lo
  use pendula_elliptic, only: ellipkm1
  use pendula_double_double, only: two_prod, dd_add_fast
  use pendula_angle_dd, only: cos_dd, cos_half, reduce_angle_2pi, sincos_half
  use pendula_dispatch, only: parameter_block_lanes
  use pendula_undamped_motion, only: REGIME_LIBRATION, REGIME_SEPARATRIX, REGIME_ROTATION
  implicit none
  private

  public :: state_parameter, parameter_lanes, period_parts

contains

  !> 1 - m of the states k = 1..n with fast(k) true on entry and |q| <= 1e150 (fast is
  !> cleared for the others, which get harmless numbers), as set_geometry forms it for
  !> |theta0| < pi (the caller's mask must imply it): sh = sin(theta0/2), ch =
  !> cos(theta0/2) (its high part in double-double near the separatrix), q =
  !> Omega0/(2 w0) and mc = 1 - m without cancellation, in passes over the block, by the
  !> variant of the block kernel (pendula_undamped_parameter_lanes.F90) that the runtime
  !> dispatch chose for this CPU.
  pure subroutine parameter_lanes(n, th, om, w, fast, sh, ch, q, mc)
    integer, intent(in) :: n  !< states in the block
    real(wp), intent(in) :: th(:)  !< initial angles [rad], finite (n of them)
    real(wp), intent(in) :: om(:)  !< initial angular velocities [rad/s], finite
    real(wp), intent(in) :: w(:)  !< angular frequencies [1/s], > 0
    logical, intent(inout) :: fast(:)  !< the states to set up (|theta0| < pi); cleared where |q| > 1e150
    real(wp), intent(out) :: sh(:)  !< sin(theta0/2)
    real(wp), intent(out) :: ch(:)  !< cos(theta0/2), high part
    real(wp), intent(out) :: q(:)  !< Omega0/(2 w0)
    real(wp), intent(out) :: mc(:)  !< 1 - m
    integer(c_int) :: flag(n)
    integer :: k
    do k = 1, n
      flag(k) = merge(1_c_int, 0_c_int, fast(k))
    end do
    call parameter_block_lanes(int(n, c_int), th, om, w, flag, half_pi, half_pi_lo, sh, ch, q, mc)
    do k = 1, n
      fast(k) = flag(k) /= 0
    end do
  end subroutine parameter_lanes

  !> 1 - m, the regime and (when want_m) m of a checked state: the numbers
  !> set_geometry (pendula_undamped_motion) gives, step for step, without building a motion
  !> (cos of theta_r/2 by cos_half, or with the sine by sincos_half where the sine is
  !> needed -- for m or a reduced angle; cos in double-double only near the separatrix).  m is left 0 when not wanted; a free rotor (|q| > 1e150) has
  !> m = +inf, mc = -inf and regime REGIME_ROTATION.
  elemental subroutine state_parameter(theta0, omega0, w0, want_m, m, mc, regime)
    real(wp), intent(in) :: theta0  !< initial angle [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], > 0 (checked)
    logical, intent(in) :: want_m  !< also m (else m = 0 unless the regime needs it)
    real(wp), intent(out) :: m  !< k^2 = E / E_separatrix (0 when not wanted)
    real(wp), intent(out) :: mc  !< 1 - m without cancellation
    integer, intent(out) :: regime  !< REGIME_LIBRATION, REGIME_SEPARATRIX or REGIME_ROTATION
    real(wp) :: n, r_hi, r_lo, h, hlo, sh, ch, chlo, sh0, ch0, q, qlo, p, e, w2, d, dlo, a
    logical :: near, need_sin
    if (abs(theta0) < pi) then
      ! what reduce_angle_2pi returns for these angles, without the call
      h = 0.5_wp*theta0
      hlo = 0
    else
      call reduce_angle_2pi(theta0, n, r_hi, r_lo)
      h = 0.5_wp*r_hi
      hlo = 0.5_wp*r_lo
    end if
    w2 = omega0/w0
    q = 0.5_wp*w2
    m = 0
    if (abs(q) > 1.0e150_wp) then
      m = ieee_value(1.0_wp, ieee_positive_inf)
      mc = -m
      regime = REGIME_ROTATION
      return
    end if
    ! the sine only where it is needed; cos_half has sincos_half's cosine bits
    need_sin = want_m .or. hlo /= 0
    if (need_sin) then
      call sincos_half(h, sh0, ch0)
    else
      ch0 = cos_half(h)
      sh0 = 0
    end if
    near = abs(q) >= 0.875_wp*ch0 .and. abs(q) <= (8.0_wp/7)*ch0
    if (near) then
      call cos_dd(h, hlo, ch, chlo)
    else
      ch = ch0 - sh0*hlo      ! ch0 exactly when hlo = 0
      chlo = 0
    end if
    qlo = 0
    if (w2 /= 0 .and. max(abs(w2), w0) < 1.0e290_wp) then
      call two_prod(w2, w0, p, e)
      qlo = 0.5_wp*(((omega0 - p) - e)/w0)
    end if
    a = ch + abs(q)
    if (chlo == 0 .and. qlo == 0) then
      mc = (ch - abs(q))*a
    else
      call dd_add_fast(ch, chlo, -abs(q), -sign(1.0_wp, q)*qlo, d, dlo)
      mc = (d + dlo)*a
    end if
    if (mc > 0) then
      regime = REGIME_LIBRATION
    else if (mc < 0) then
      regime = REGIME_ROTATION
    else
      regime = REGIME_SEPARATRIX
    end if
    if (want_m .or. regime == REGIME_ROTATION) then
      if (.not. need_sin) call sincos_half(h, sh0, ch0)
      sh = sh0 + ch0*hlo
      m = sh*sh + q*q
    end if
  end subroutine state_parameter

  !> The period of a state from its regime, m and 1 - m (state_parameter) as
  !> num / den: the numbers of set_period -- 4 K(m) / w0, 2 K(1/m) / (k w0),
  !> 2 pi / |Omega0| for the free rotor (m = +inf), +inf / 1 on the separatrix.
  elemental subroutine period_parts(regime, m, mc, omega0, w0, num, den)
    integer, intent(in) :: regime  !< REGIME_LIBRATION, REGIME_SEPARATRIX or REGIME_ROTATION
    real(wp), intent(in) :: m  !< elliptic parameter (+inf for the free rotor)
    real(wp), intent(in) :: mc  !< 1 - m
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s]
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s]
    real(wp), intent(out) :: num  !< the period's numerator
    real(wp), intent(out) :: den  !< its denominator [1/s]
    select case (regime)
    case (REGIME_LIBRATION)
      num = 4*ellipkm1(mc)
      den = w0
    case (REGIME_ROTATION)
      if (m > huge(m)) then
        num = 2*pi
        den = abs(omega0)
      else
        num = 2*ellipkm1(-mc/m)
        den = sqrt(m)*w0
      end if
    case default
      num = ieee_value(1.0_wp, ieee_positive_inf)
      den = 1
    end select
  end subroutine period_parts

end module pendula_undamped_parameter
