!> Error-free transformations and double-double arithmetic (a value is an unevaluated
!> sum hi + lo of two doubles, ~106 bits).  Used where a reduction or a cancellation
!> needs more than double precision: the periods in pendula_elliptic, the separatrix
!> distance 1 - m in pendula_undamped.  No FMA is assumed (Dekker/Veltkamp splitting),
!> so results are the same on every IEEE machine.
module pendula_double_double
  use pendula_kinds, only: wp
  implicit none
  private
  public :: two_sum, two_prod, veltkamp_split
  public :: dd_add, dd_add_fast, dd_mul, dd_div, dd_div_d, dd_sqrt

contains

  !> Error-free sum a + b = s + e with s = fl(a + b) (Knuth; any order of magnitude).
  pure elemental subroutine two_sum(a, b, s, e)
    real(wp), intent(in) :: a  !< first summand
    real(wp), intent(in) :: b  !< second summand
    real(wp), intent(out) :: s  !< fl(a + b)
    real(wp), intent(out) :: e  !< exact error a + b - s
    real(wp) :: bb
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
  end subroutine two_sum

  !> Exact product a*b = p + e (Dekker/Veltkamp, no fma needed) whenever p is finite and
  !> the error term does not underflow.  The Veltkamp split overflows above 2**996 (split*a,
  !> and the 26-bit head of a double near huge() rounds up to 2**1024): there the big factor
  !> is scaled by 2**-28 first, which scales p and e exactly; without this the split gives
  !> Inf - Inf = NaN for |a| >= 1.3e300.
  pure elemental subroutine two_prod(a, b, p, e)
    real(wp), intent(in) :: a  !< first factor
    real(wp), intent(in) :: b  !< second factor
    real(wp), intent(out) :: p  !< fl(a*b)
    real(wp), intent(out) :: e  !< exact error a*b - p
    real(wp), parameter :: big = 2.0_wp**996
    real(wp) :: ps
    p = a*b
    if (abs(a) <= big .and. abs(b) <= big) then
      e = prod_err(a, b, p)
    else if (abs(p) <= huge(p)) then      ! one factor big (both big would overflow p)
      if (abs(a) > big) then
        ps = scale(a, -28)*b
        e = scale(prod_err(scale(a, -28), b, ps), 28)
      else
        ps = a*scale(b, -28)
        e = scale(prod_err(a, scale(b, -28), ps), 28)
      end if
    else
      e = 0                               ! p = +-Inf or NaN: no error term
    end if
  end subroutine two_prod

  !> Error a*b - p of the rounded product p = fl(a*b), |a|, |b| <= 2**996 (Dekker).
  pure elemental real(wp) function prod_err(a, b, p) result(e)
    real(wp), intent(in) :: a, b, p
    real(wp) :: ah, al, bh, bl
    call veltkamp_split(a, ah, al)
    call veltkamp_split(b, bh, bl)
    e = ((ah*bh - p) + ah*bl + al*bh) + al*bl
  end function prod_err

  !> Veltkamp split a = hi + lo, each with at most 26 significant bits, so that products
  !> of a head by a small integer are exact (|a| <= 2**996, where split*a cannot overflow).
  pure elemental subroutine veltkamp_split(a, hi, lo)
    real(wp), intent(in) :: a  !< value to split, |a| <= 2**996
    real(wp), intent(out) :: hi  !< head (26 significant bits)
    real(wp), intent(out) :: lo  !< tail a - hi
    real(wp), parameter :: split = 134217729.0_wp   ! 2**27 + 1
    real(wp) :: t
    t = split*a
    hi = t - (t - a)
    lo = a - hi
  end subroutine veltkamp_split

  !> Double-double sum (ah + al) + (bh + bl) = ch + cl, accurate also under cancellation
  !> (both low parts summed error-free: the "IEEE" addition of Bailey's QD library).
  pure elemental subroutine dd_add(ah, al, bh, bl, ch, cl)
    real(wp), intent(in) :: ah, al  !< ah, al: high and low parts of the first summand
    real(wp), intent(in) :: bh, bl  !< bh, bl: high and low parts of the second summand
    real(wp), intent(out) :: ch, cl  !< ch, cl: high and low parts of the sum
    real(wp) :: s, e, t, f, f2
    call two_sum(ah, bh, s, e)
    call two_sum(al, bl, t, f)
    e = e + t
    call two_sum(s, e, t, f2)
    e = f2 + f
    call two_sum(t, e, ch, cl)
  end subroutine dd_add

  !> Double-double sum with the low parts added in double (QD's "sloppy" addition):
  !> cheaper, relative error ~1e-32 unless ah + bh cancels to far below al + bl.
  !> pendula_undamped's separatrix distance was calibrated with this form; the two
  !> forms differ in the last bits of cl, so callers keep the one they were measured with.
  pure elemental subroutine dd_add_fast(ah, al, bh, bl, ch, cl)
    real(wp), intent(in) :: ah, al  !< ah, al: high and low parts of the first summand
    real(wp), intent(in) :: bh, bl  !< bh, bl: high and low parts of the second summand
    real(wp), intent(out) :: ch, cl  !< ch, cl: high and low parts of the sum
    real(wp) :: s, e
    call two_sum(ah, bh, s, e)
    e = e + (al + bl)
    ch = s + e
    cl = e - (ch - s)
  end subroutine dd_add_fast

  !> Double-double product (ah + al)(bh + bl) = ch + cl (relative error ~1e-32).
  pure elemental subroutine dd_mul(ah, al, bh, bl, ch, cl)
    real(wp), intent(in) :: ah, al  !< ah, al: high and low parts of the first factor
    real(wp), intent(in) :: bh, bl  !< bh, bl: high and low parts of the second factor
    real(wp), intent(out) :: ch, cl  !< ch, cl: high and low parts of the product
    real(wp) :: p, e
    call two_prod(ah, bh, p, e)
    e = e + (ah*bl + al*bh)
    call two_sum(p, e, ch, cl)
  end subroutine dd_mul

  !> Double-double quotient (ah + al) / (bh + bl), bh /= 0 (one Newton correction).
  pure elemental subroutine dd_div(ah, al, bh, bl, ch, cl)
    real(wp), intent(in) :: ah, al  !< ah, al: high and low parts of the dividend
    real(wp), intent(in) :: bh, bl  !< bh, bl: high and low parts of the divisor (bh /= 0)
    real(wp), intent(out) :: ch, cl  !< ch, cl: high and low parts of the quotient
    real(wp) :: q1, q2, ph, pl, rh, rl
    q1 = ah/bh
    call dd_mul(q1, 0.0_wp, bh, bl, ph, pl)
    call dd_add(ah, al, -ph, -pl, rh, rl)
    q2 = rh/bh
    call two_sum(q1, q2, ch, cl)
  end subroutine dd_div

  !> Double-double quotient (ah + al) / b by a double b /= 0 (|q1 b| <= 2**996).
  pure elemental subroutine dd_div_d(ah, al, b, ch, cl)
    real(wp), intent(in) :: ah, al  !< ah, al: high and low parts of the dividend
    real(wp), intent(in) :: b  !< double divisor, /= 0
    real(wp), intent(out) :: ch, cl  !< ch, cl: high and low parts of the quotient
    real(wp) :: q1, p, e, q2
    q1 = ah/b
    call two_prod(q1, b, p, e)
    q2 = (((ah - p) - e) + al)/b
    ch = q1 + q2
    cl = q2 - (ch - q1)          ! |q2| << |q1|: the fast two-sum is exact
  end subroutine dd_div_d

  !> Double-double square root of ah + al (0 for ah <= 0), one Newton correction.
  pure elemental subroutine dd_sqrt(ah, al, ch, cl)
    real(wp), intent(in) :: ah, al  !< ah, al: high and low parts of the radicand (0 result for ah <= 0)
    real(wp), intent(out) :: ch, cl  !< ch, cl: high and low parts of the square root
    real(wp) :: s, p, e, r, xh, xl
    integer :: sh
    if (ah <= 0) then
      ch = 0; cl = 0
      return
    end if
    ! above 2**1000, s*s may round to +Inf: work on a / 2**100 and scale the root back
    sh = 0
    if (ah > 2.0_wp**1000) sh = 50
    xh = scale(ah, -2*sh); xl = scale(al, -2*sh)
    s = sqrt(xh)
    call two_prod(s, s, p, e)
    r = ((xh - p) - e + xl)/(2*s)
    call two_sum(s, r, ch, cl)
    ch = scale(ch, sh); cl = scale(cl, sh)
  end subroutine dd_sqrt

end module pendula_double_double
