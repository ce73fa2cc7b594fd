!> Mathematical constants shared by every concern: pi and its simple multiples as the
!> nearest doubles, and the double-double (and triple) splits of pi used where an
!> argument is reduced by multiples of pi exactly (F(phi|m), the angle reduction of the
!> undamped pendulum, the equilibria n pi); and the quiet NaN that the elemental
!> special functions return for arguments outside their domain.
module pendula_constants
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use pendula_kinds, only: wp
  implicit none
  private
  public :: pi, half_pi, two_pi, pi_lo, pi_lo2, half_pi_lo, two_pi_lo, quiet_nan

  !> The double nearest pi.
  real(wp), parameter :: pi = 3.141592653589793238462643383279502884_wp
  !> pi/2 and 2 pi as doubles (exact multiples of the double pi).
  real(wp), parameter :: half_pi = 0.5_wp*pi, two_pi = 2*pi
  !> pi - pi(double): pi = pi + pi_lo to ~1e-32 relative.
  real(wp), parameter :: pi_lo = 1.2246467991473532e-16_wp
  !> pi - pi(double) - pi_lo: the third part, pi = pi + pi_lo + pi_lo2 to ~1e-48.
  real(wp), parameter :: pi_lo2 = -2.9947698097183397e-33_wp
  !> Low parts of pi/2 and 2 pi (exact scalings of pi_lo).
  real(wp), parameter :: half_pi_lo = 0.5_wp*pi_lo, two_pi_lo = 2*pi_lo
contains

  !> A quiet NaN (the value of an elemental function outside its domain).
  pure elemental real(wp) function quiet_nan()
    quiet_nan = ieee_value(1.0_wp, ieee_quiet_nan)
  end function quiet_nan

end module pendula_constants
