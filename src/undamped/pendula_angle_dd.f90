!> Angles in double-double for the exact undamped motion: reduction about the
!> nearest stable equilibrium 2 pi n (2 pi carried in two doubles), cos of a
!> double-double angle, and cos_half, the cosine of a half angle by polynomials
!> (no libm call), which loops over many states vectorise.  Used by pendula_undamped_motion (set-up of a state) and
!> pendula_small_angle (reduce_angle_2pi).
module pendula_angle_dd
  use pendula_kinds, only: wp
  use pendula_constants, only: pi, half_pi, half_pi_lo, two_pi, two_pi_lo
  use pendula_double_double, only: two_prod
  implicit none
  private

  public :: cos_dd, cos_dd_lanes, cos_half, reduce_angle_2pi, sincos_half

contains

  !> sin(x) and cos(x) for |x| <= pi/2 (a half angle theta/2, |theta| <= pi), each within
  !> 0.75 ulp (measured against mpmath); c has cos_half's bits: sincos_half_core
  !> (pendula_angle_dd_block.inc) with pendula_constants' pi/2.
  pure elemental subroutine sincos_half(x, s, c)
    real(wp), intent(in) :: x  !< angle [rad], |x| <= pi/2
    real(wp), intent(out) :: s  !< sin(x)
    real(wp), intent(out) :: c  !< cos(x)
    call sincos_half_core(x, half_pi, half_pi_lo, s, c)
  end subroutine sincos_half

  !> cos(x) for |x| <= pi/2 (a half angle theta/2, |theta| <= pi), within 0.6 ulp
  !> (measured against mpmath), relatively accurate up to x = +-pi/2: for |x| <= pi/4 the
  !> Taylor series 1 - y/2 + y^2 (1/4! - y/6! + ... + y^8/20!), y = x^2 formed exactly
  !> (Dekker) and 1 - y/2 with its rounding error (as fdlibm's kernel cosine); above,
  !> sin(pi/2 - |x|) by its Taylor series to the 19th power, pi/2 in two parts.  Plain
  !> arithmetic and merges, no libm call and no branch: a loop over it vectorises with
  !> the same bits as the scalar call (the many-state loops rely on that).
  pure elemental real(wp) function cos_half(x) result(c)
    real(wp), intent(in) :: x  !< angle [rad], |x| <= pi/2
    real(wp), parameter :: split = 134217729.0_wp   ! 2**27 + 1 (Veltkamp)
    ! (-1)^k / (2k)!, k = 2..10, and (-1)^k / (2k+1)!, k = 1..9 (n! exact in double for n <= 20)
    real(wp), parameter :: c4 = 1/24.0_wp, c6 = -1/720.0_wp, c8 = 1/40320.0_wp, c10 = -1/3628800.0_wp, &
                           c12 = 1/479001600.0_wp, c14 = -1/87178291200.0_wp, c16 = 1/20922789888000.0_wp, &
                           c18 = -1/6402373705728000.0_wp, c20 = 1/2432902008176640000.0_wp
    real(wp), parameter :: s3 = -1/6.0_wp, s5 = 1/120.0_wp, s7 = -1/5040.0_wp, s9 = 1/362880.0_wp, &
                           s11 = -1/39916800.0_wp, s13 = 1/6227020800.0_wp, s15 = -1/1307674368000.0_wp, &
                           s17 = 1/355687428096000.0_wp, s19 = -1/121645100408832000.0_wp
    real(wp) :: a, ah, al, y, ylo, hy, w, cc, v, vy, ss
    a = abs(x)
    ! cos side: y + ylo = a^2 exactly, cos = (1 - y/2) + y^2 P(y) with 1 - y/2 compensated
    y = a*a
    ah = split*a
    ah = ah - (ah - a)
    al = a - ah
    ylo = ((ah*ah - y) + 2*(ah*al)) + al*al
    hy = 0.5_wp*y
    w = 1 - hy
    cc = w + ((((1 - w) - hy) - 0.5_wp*ylo) + (y*y)*(c4 + y*(c6 + y*(c8 + y*(c10 + y*(c12 + y*(c14 + y*(c16 &
                                                                                                        + y*(c18 + y*c20)))))))))
    ! sin side: v = pi/2 - a exact (Sterbenz) for a >= pi/4, plus the low part of pi/2
    v = half_pi - a
    vy = v*v
    ss = v + (half_pi_lo*(1 - 0.5_wp*vy) + (v*vy)*(s3 + vy*(s5 + vy*(s7 + vy*(s9 + vy*(s11 + vy*(s13 + vy*(s15 &
                                                                                                         + vy*(s17 + vy*s19)))))))))
    c = merge(ss, cc, a > 0.25_wp*pi)
  end function cos_half

  !> cos(x) in double-double for x = xh + xl, |x| <= pi/2 (+ rounding), to
  !> ~1e-31 relative: the Taylor series of cos x (|x| <= pi/4) or of
  !> sin(pi/2 - |x|), in powers of y = x^2 up to y^16: the terms j >= 9 (below
  !> 3e-18) by Horner in double, the first nine by Horner in double-double
  !> with the coefficients 1/(2j)! (1/(2j+1)!) as double-double constants
  !> (mpmath; 1/n! = hi + lo), so no division.  One lane of cos_dd_lanes (the same bits).
  elemental subroutine cos_dd(xh, xl, ch, cl)
    real(wp), intent(in) :: xh  !< high part of x [rad], |x| <= pi/2
    real(wp), intent(in) :: xl  !< low part of x [rad]
    real(wp), intent(out) :: ch  !< high part of cos(x)
    real(wp), intent(out) :: cl  !< low part of cos(x)
    real(wp) :: h(1), l(1)
    call cos_dd_lanes(1, [xh], [xl], h, l)
    ch = h(1)
    cl = l(1)
  end subroutine cos_dd

  !> cos_dd at n points (cos_dd_block of pendula_angle_dd_block.inc with pendula_constants'
  !> pi/2, baseline code): a block's points take each Horner step side by side.
  pure subroutine cos_dd_lanes(n, xh, xl, ch, cl)
    integer, intent(in) :: n  !< number of points
    real(wp), intent(in) :: xh(n)  !< high parts of x [rad], |x| <= pi/2
    real(wp), intent(in) :: xl(n)  !< low parts of x [rad]
    real(wp), intent(out) :: ch(n)  !< high parts of cos(x)
    real(wp), intent(out) :: cl(n)  !< low parts of cos(x)
    call cos_dd_block(n, xh, xl, half_pi, half_pi_lo, ch, cl)
  end subroutine cos_dd_lanes

  !> Reduce an angle x [rad] about the nearest stable equilibrium 2 pi n:
  !> x = 2 pi n + (r_hi + r_lo) with |r_hi| <= pi, 2 pi carried in two doubles
  !> (error ~2^-100 |2 pi n|) for |x| <= 2^40; beyond, r_hi = atan2(sin x, cos x)
  !> (libm's exact reduction, ~1 ulp of pi) and r_lo = 0.  Returns n as a real.
  elemental subroutine reduce_angle_2pi(x, n, r_hi, r_lo)
    real(wp), intent(in) :: x  !< angle [rad]
    real(wp), intent(out) :: n  !< index of the nearest stable equilibrium 2 pi n (as a real)
    real(wp), intent(out) :: r_hi  !< high part of x - 2 pi n [rad], |r_hi| <= pi
    real(wp), intent(out) :: r_lo  !< low part of x - 2 pi n [rad]
    if (abs(x) < pi) then
      ! already reduced (what the general path below returns for these x)
      n = 0
      r_hi = x
      r_lo = 0
      return
    end if
    if (abs(x) > 2.0_wp**40) then
      ! beyond |n| ~ 2^37 the two-double 2 pi is not enough: let libm's exact
      ! (Payne-Hanek) reduction inside sin and cos do it; |r| to ~1 ulp of pi
      r_hi = atan2(sin(x), cos(x))
      r_lo = 0
      n = anint((x - r_hi)/two_pi)
      return
    end if
    n = anint(x/two_pi)
    if (n == 0) then
      r_hi = x
      r_lo = 0
      return
    end if
    call reduce_angle_fixed(x, n, r_hi, r_lo)
    ! anint may leave |r| marginally above pi; that is harmless (reduction is
    ! only about the nearest equilibrium) but keep the contract |r_hi| <= pi.
    if (abs(r_hi) > pi) then
      n = n + sign(1.0_wp, r_hi)
      call reduce_angle_fixed(x, n, r_hi, r_lo)
    end if
  end subroutine reduce_angle_2pi

  ! x - 2 pi n = r_hi + r_lo for a given n /= 0 near x / (2 pi).
  elemental subroutine reduce_angle_fixed(x, n, r_hi, r_lo)
    real(wp), intent(in) :: x, n
    real(wp), intent(out) :: r_hi, r_lo
    real(wp) :: p, e, d, t
    call two_prod(n, two_pi, p, e)
    d = x - p                      ! exact (Sterbenz: x/p in [1/2, 2] for n /= 0)
    t = -(e + n*two_pi_lo)
    r_hi = d + t
    r_lo = t - (r_hi - d)           ! fast two-sum (|d| >= |t|)
  end subroutine reduce_angle_fixed

  include 'pendula_angle_dd_block.inc'

end module pendula_angle_dd
