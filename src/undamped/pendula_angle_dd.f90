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

  public :: cos_dd, cos_dd_lanes, cos_half, reduce_angle_2pi, sincos_half, sincos_half_array

contains

  !> sin(x) and cos(x) for |x| <= pi/2 (a half angle theta/2, |theta| <= pi), each within
  !> 0.75 ulp (measured against mpmath); c has cos_half's bits.  One Taylor series of sin
  !> and one of cos (cos_half's, with 1 - y/2 compensated) at z = |x| for |x| <= pi/4, else
  !> at z = pi/2 - |x| (exact) with the low part of pi/2 as a first-order term, the two
  !> then swapped: no libm call and no branch (libm's sin and a mispredicted side of the
  !> interval were a fifth of a state's set-up).
  pure elemental subroutine sincos_half(x, s, c)
    real(wp), intent(in) :: x  !< angle [rad], |x| <= pi/2
    real(wp), intent(out) :: s  !< sin(x)
    real(wp), intent(out) :: c  !< cos(x)
    real(wp), parameter :: split = 134217729.0_wp   ! 2**27 + 1 (Veltkamp)
    real(wp), parameter :: c4 = 1/24.0_wp, c6 = -1/720.0_wp, c8 = 1/40320.0_wp, c10 = -1/3628800.0_wp, &
                           c12 = 1/479001600.0_wp, c14 = -1/87178291200.0_wp, c16 = 1/20922789888000.0_wp, &
                           c18 = -1/6402373705728000.0_wp, c20 = 1/2432902008176640000.0_wp
    real(wp), parameter :: s3 = -1/6.0_wp, s5 = 1/120.0_wp, s7 = -1/5040.0_wp, s9 = 1/362880.0_wp, &
                           s11 = -1/39916800.0_wp, s13 = 1/6227020800.0_wp, s15 = -1/1307674368000.0_wp, &
                           s17 = 1/355687428096000.0_wp, s19 = -1/121645100408832000.0_wp
    real(wp) :: a, z, lo, zh, zl, y, ylo, hy, w, cz, sz, big
    a = abs(x)
    ! a real flag, not a logical: the form gcc keeps branch-free
    big = merge(1.0_wp, 0.0_wp, a > 0.25_wp*pi)
    z = merge(half_pi - a, a, big > 0)
    lo = merge(half_pi_lo, 0.0_wp, big > 0)
    y = z*z
    ! sin(z + lo)
    sz = z + (lo*(1 - 0.5_wp*y) + (z*y)*(s3 + y*(s5 + y*(s7 + y*(s9 + y*(s11 + y*(s13 + y*(s15 + y*(s17 &
                                                                                                    + y*s19)))))))))
    ! cos(z + lo): y + ylo = z^2 exactly, (1 - y/2) compensated, - sin(z) lo ~ - z lo
    zh = split*z
    zh = zh - (zh - z)
    zl = z - zh
    ylo = ((zh*zh - y) + 2*(zh*zl)) + zl*zl
    hy = 0.5_wp*y
    w = 1 - hy
    cz = w + ((((1 - w) - hy) - 0.5_wp*ylo - z*lo) &
              + (y*y)*(c4 + y*(c6 + y*(c8 + y*(c10 + y*(c12 + y*(c14 + y*(c16 + y*(c18 + y*c20)))))))))
    s = sign(merge(cz, sz, big > 0), x)
    c = merge(sz, cz, big > 0)
  end subroutine sincos_half

  !> sincos_half over arrays of n angles, in a loop that inlines it and vectorises (the
  !> same bits as the elemental calls).
  pure subroutine sincos_half_array(n, x, s, c)
    integer, intent(in) :: n  !< number of angles
    real(wp), intent(in) :: x(n)  !< angles [rad], |x| <= pi/2
    real(wp), intent(out) :: s(n)  !< sin(x)
    real(wp), intent(out) :: c(n)  !< cos(x)
    integer :: i
    do i = 1, n
      call sincos_half(x(i), s(i), c(i))
    end do
  end subroutine sincos_half_array

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

  !> cos_dd at n points, in blocks whose points take each Horner step side by side: one
  !> point's double-double Horner chain is latency-bound, a block's points fill the
  !> pipeline (and vectorise).  The side of pi/4 picks the coefficients per point by merge.
  pure subroutine cos_dd_lanes(n, xh, xl, ch, cl)
    integer, intent(in) :: n  !< number of points
    real(wp), intent(in) :: xh(n)  !< high parts of x [rad], |x| <= pi/2
    real(wp), intent(in) :: xl(n)  !< low parts of x [rad]
    real(wp), intent(out) :: ch(n)  !< high parts of cos(x)
    real(wp), intent(out) :: cl(n)  !< low parts of cos(x)
    integer, parameter :: nb = 64
    real(wp), parameter :: cos_hi(0:8) = [1.0_wp, 0.5_wp, 0.041666666666666664_wp, 0.001388888888888889_wp, &
                            2.48015873015873e-05_wp, 2.755731922398589e-07_wp, 2.08767569878681e-09_wp, 1.1470745597729725e-11_wp, &
                                          4.779477332387385e-14_wp]
    real(wp), parameter :: cos_lo(0:8) = [0.0_wp, 0.0_wp, 2.3129646346357427e-18_wp, -5.300543954373577e-20_wp, &
                        2.1511947866775882e-23_wp, 2.3767714622250297e-23_wp, -1.20734505911326e-25_wp, 2.0655512752830745e-28_wp, &
                                          4.399205485834081e-31_wp]
    real(wp), parameter :: sin_hi(0:8) = [1.0_wp, 0.16666666666666666_wp, 0.008333333333333333_wp, &
                                          0.0001984126984126984_wp, 2.7557319223985893e-06_wp, 2.505210838544172e-08_wp, &
                                          1.6059043836821613e-10_wp, 7.647163731819816e-13_wp, 2.8114572543455206e-15_wp]
    real(wp), parameter :: sin_lo(0:8) = [0.0_wp, 9.25185853854297e-18_wp, 1.1564823173178714e-19_wp, &
                                          1.7209558293420705e-22_wp, -1.858393274046472e-22_wp, -1.448814070935912e-24_wp, &
                                          1.2585294588752098e-26_wp, 7.03872877733453e-30_wp, 1.6508842730861433e-31_wp]
    ! (-1)^j/(2j)! and (-1)^j/(2j+1)!, j = 9..16, in double (mpmath; their rounding is ~1e-31 of cos)
    real(wp), parameter :: cos_tail(9:16) = [-1.5619206968586225e-16_wp, &
                                             4.110317623312165e-19_wp, -8.896791392450574e-22_wp, 1.6117375710961184e-24_wp, &
                        -2.4795962632247976e-27_wp, 3.279889237069838e-30_wp, -3.7699876288159054e-33_wp, 3.8003907548547434e-36_wp]
    real(wp), parameter :: sin_tail(9:16) = [-8.22063524662433e-18_wp, &
                                             1.9572941063391263e-20_wp, -3.868170170630684e-23_wp, 6.446950284384474e-26_wp, &
                          -9.183689863795546e-29_wp, 1.1309962886447716e-31_wp, -1.216125041553518e-34_wp, 1.151633562077195e-37_wp]
    real(wp), dimension(nb) :: yh, yl, y2h, y2l, th, tl, sside
    real(wp) :: ah, al, uh, ul, sgn, chi, clo, xk, xlk, nth, ntl, s_hi, s_lo, c_hi, c_lo
    integer :: i0, m, k, j
    do i0 = 1, n, nb
      m = min(nb, n - i0 + 1)
      do k = 1, m
        ! sside: 1 on the sine side (a real flag: the form gcc vectorises)
        xk = xh(i0 + k - 1)
        xlk = xl(i0 + k - 1)
        sside(k) = merge(1.0_wp, 0.0_wp, abs(xk) > 0.25_wp*pi)
        call add_fast(half_pi, half_pi_lo, -abs(xk), -sign(1.0_wp, xk)*xlk, ah, al)
        yh(k) = merge(ah, xk, sside(k) > 0)
        yl(k) = merge(al, xlk, sside(k) > 0)
        call mul(yh(k), yl(k), yh(k), yl(k), y2h(k), y2l(k))
        th(k) = 0
        tl(k) = 0
      end do
      do j = 16, 9, -1
        s_hi = sin_tail(j); c_hi = cos_tail(j)
        do k = 1, m
          th(k) = merge(s_hi, c_hi, sside(k) > 0) + y2h(k)*th(k)
        end do
      end do
      do j = 8, 0, -1
        ! t <- (-1)^j c_j + y^2 t
        sgn = 1 - 2*modulo(j, 2)
        s_hi = sgn*sin_hi(j); s_lo = sgn*sin_lo(j); c_hi = sgn*cos_hi(j); c_lo = sgn*cos_lo(j)
        do k = 1, m
          call mul(y2h(k), y2l(k), th(k), tl(k), uh, ul)
          call add_fast(merge(s_hi, c_hi, sside(k) > 0), merge(s_lo, c_lo, sside(k) > 0), uh, ul, nth, ntl)
          th(k) = nth
          tl(k) = ntl
        end do
      end do
      do k = 1, m
        call mul(yh(k), yl(k), th(k), tl(k), chi, clo)
        ch(i0 + k - 1) = merge(chi, th(k), sside(k) > 0)
        cl(i0 + k - 1) = merge(clo, tl(k), sside(k) > 0)
      end do
    end do
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

  ! dd_add_fast and dd_mul of pendula_double_double, operation for operation (the
  ! same bits), here so that cos_dd's 20 of them are inlined rather than called;
  ! mul is two_prod's Dekker product without its range scaling, which cos_dd's
  ! operands (|y| <= pi/2, |t| <= 2) never need.
  elemental subroutine add_fast(ah, al, bh, bl, ch, cl)
    real(wp), intent(in) :: ah, al, bh, bl
    real(wp), intent(out) :: ch, cl
    real(wp) :: s, e, bb
    s = ah + bh
    bb = s - ah
    e = (ah - (s - bb)) + (bh - bb)
    e = e + (al + bl)
    ch = s + e
    cl = e - (ch - s)
  end subroutine add_fast

  elemental subroutine mul(ah, al, bh, bl, ch, cl)
    real(wp), intent(in) :: ah, al, bh, bl
    real(wp), intent(out) :: ch, cl
    real(wp), parameter :: split = 134217729.0_wp   ! 2**27 + 1
    real(wp) :: p, e, t, a1, a2, b1, b2, bb
    p = ah*bh
    t = split*ah
    a1 = t - (t - ah)
    a2 = ah - a1
    t = split*bh
    b1 = t - (t - bh)
    b2 = bh - b1
    e = ((a1*b1 - p) + a1*b2 + a2*b1) + a2*b2
    e = e + (ah*bl + al*bh)
    ch = p + e
    bb = ch - p
    cl = (p - (ch - bb)) + (e - bb)
  end subroutine mul

end module pendula_angle_dd
