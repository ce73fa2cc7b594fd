!> Complete elliptic integrals K(m) and E(m) for every real m <= 1, their complement
!> forms of mc = 1 - m, and K in double-double (for the period reductions of F and of
!> the Jacobi functions).
!>
!> K, E: degree-12 polynomials (Chebyshev interpolants at 40 digits) on 17 intervals
!> of m in [0, 0.85) and, for mc <= 0.15, the logarithmic form K = P(mc) - ln(mc) Q(mc),
!> E = Pe(mc) - ln(mc) mc Qe1(mc) (structure of DLMF 19.12.1), exact as mc -> 0 down
!> to the smallest subnormal (the logarithm inlined, log_pos; the array loops take the
!> logarithmic forms in one vectorised pass).  m < 0 by the imaginary-modulus transformation
!> (DLMF 19.7.5).  Measured <= 2.4 ulps against mpmath.  K in double-double by the AGM
!> in double-double arithmetic (DLMF 19.8.5).
module pendula_elliptic_ke
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_is_nan, ieee_is_finite
  use, intrinsic :: iso_fortran_env, only: int32, int64
  use pendula_kinds, only: wp
  use pendula_constants, only: half_pi, half_pi_lo, quiet_nan
  use pendula_status, only: status_t, set_error, PENDULA_ERR_SIZE
  use pendula_elliptic_tables, only: k_poly, e_poly, ke_log_poly
  implicit none
  private

  public :: ellipk, ellipkm1, ellipe, ellipem1, ellipk_array, ellipe_array, ellipkm1_array, ellipem1_array
  ! for the other modules of the elliptic concern
  public :: k_unit, k_from_mc, k_double_double, k_unit_many

contains

  !> K(m) in double-double from mc = 1 - m = mch + mcl > 0 given in double-double (any
  !> mc > 0, also mc > 1 for m < 0): K = (pi/2) / AGM(1, sqrt(mc)) (DLMF 19.8.5), to
  !> ~1e-31 relative (measured against mpmath for mc from 5e-324 to 1e6).
  !>
  !> A compensated AGM: the high parts are the plain double AGM, and the low parts carry
  !> the exact rounding errors of each step (error-free sum and product), propagated to
  !> first order (their products, ~1e-32, are dropped).  The high chain does not wait for
  !> the low parts, so a step costs about one double AGM step.  The iteration stops at
  !> t = (a - b)/(a + b) <= 2**-27 and finishes with the series
  !> AGM(1 + t, 1 - t) = 1 - t^2/4 - 5 t^4/64 - O(t^6): the t^2 term (~1e-17) is then
  !> needed only to a few digits, so its rounding stays ~1e-32 (at t ~ 2**-16 it was 1e-26).
  pure subroutine k_double_double(mch, mcl, khi, klo)
    real(wp), intent(in) :: mch  !< high part of mc = 1 - m, > 0
    real(wp), intent(in) :: mcl  !< low part of mc
    real(wp), intent(out) :: khi  !< high part of K
    real(wp), intent(out) :: klo  !< low part of K
    real(wp), parameter :: tiny_mc = 2.0_wp**(-900), up = 2.0_wp**1000, down = 2.0_wp**(-500)
    real(wp) :: ah, al, bh, bl, x, xl, s, se, p, t, corr
    integer :: i
    ! b = sqrt(mc) with its residual; tiny mc is scaled so that the residual stays exact
    x = mch; xl = mcl
    if (mch < tiny_mc) then
      x = mch*up; xl = mcl*up
    end if
    bh = sqrt(x)
    bl = ((x - bh*bh) - sq_err(bh) + xl)/(2*bh)
    if (mch < tiny_mc) then
      bh = bh*down; bl = bl*down
    end if
    ah = 1; al = 0
    do i = 1, 80
      if (abs(ah - bh) <= 2.0_wp**(-26)*ah) exit     ! t <= 2**-27
      ! a' = (a + b)/2 (halving exact), b' = sqrt(a b): b'h = fl(sqrt(fl(a b))) and
      ! b'l = (a b - b'h^2) / (2 b'h) to first order, every residual exact
      s = ah + bh
      se = (ah - (s - (s - ah))) + (bh - (s - ah))
      p = ah*bh
      x = (prod_err(ah, bh, p) + ah*bl) + al*bh
      ah = 0.5_wp*s
      al = 0.5_wp*((se + al) + bl)
      bh = sqrt(p)
      bl = (((p - bh*bh) - sq_err(bh)) + x)/(2*bh)
    end do
    ! A = (a + b)/2 and the series in t (a - b is exact: a and b agree to 26 bits)
    s = ah + bh
    se = (ah - (s - (s - ah))) + (bh - (s - ah))
    t = ((ah - bh) + (al - bl))/s
    t = t*t
    corr = t*(0.25_wp + t*(5.0_wp/64))
    ah = 0.5_wp*s
    al = 0.5_wp*((se + al) + bl) - ah*corr
    ! M = ah + al normalised, then K = (pi/2)/M with one correction of the quotient
    s = ah + al
    al = al - (s - ah)
    ah = s
    khi = half_pi/ah
    p = khi*ah
    klo = (((half_pi - p) - prod_err(khi, ah, p)) + (half_pi_lo - khi*al))/ah
    s = khi + klo
    klo = klo - (s - khi)
    khi = s
  end subroutine k_double_double

  !> Exact error a*b - p of p = fl(a*b) (Dekker; |a|, |b| <= 2**996, no underflow).  The
  !> AGM of k_double_double needs it twice per step: here, where the compiler inlines it,
  !> rather than a call to pendula_double_double per product.
  pure elemental real(wp) function prod_err(a, b, p) result(e)
    real(wp), intent(in) :: a, b, p
    real(wp), parameter :: split = 134217729.0_wp   ! 2**27 + 1 (Veltkamp)
    real(wp) :: ah, al, bh, bl
    ah = split*a; ah = ah - (ah - a); al = a - ah
    bh = split*b; bh = bh - (bh - b); bl = b - bh
    e = ((ah*bh - p) + ah*bl + al*bh) + al*bl
  end function prod_err

  !> Exact error s*s - fl(s*s) of a square (prod_err with a = b = s).
  pure elemental real(wp) function sq_err(s) result(e)
    real(wp), intent(in) :: s
    e = prod_err(s, s, s*s)
  end function sq_err

  !> Degree-12 polynomial p at y by Estrin's scheme.
  pure real(wp) function estrin12(p, y) result(r)
    real(wp), intent(in) :: p(0:12), y
    real(wp) :: y2, y4
    ! Estrin's scheme: a short dependency chain, the same accuracy for these small |y|
    y2 = y*y
    y4 = y2*y2
    r = ((p(0) + p(1)*y) + (p(2) + p(3)*y)*y2) + ((p(4) + p(5)*y) + (p(6) + p(7)*y)*y2)*y4 &
        + (((p(8) + p(9)*y) + (p(10) + p(11)*y)*y2) + p(12)*y4)*(y4*y4)
  end function estrin12

  !> ln(x) for 0 < x < +Inf (subnormal x included), within 1 ulp: x = 2^k (1 + f) with
  !> 1 + f in [sqrt(2)/2, sqrt(2)) read from the bits, ln(1 + f) = f - f^2/2 + s (f^2/2 + R)
  !> with s = f/(2 + f), R = 2 s^2/3 + 2 s^4/5 + ... + 2 s^20/21 (the series of
  !> 2 atanh(s), |s| <= 0.172), and k ln 2 with ln 2 in two parts (the scheme of fdlibm's
  !> log, here with the series' own coefficients).  Plain arithmetic inlined into K and E
  !> near m = 1: libm's log call took half of their time there.
  pure elemental real(wp) function log_pos(x) result(y)
    real(wp), intent(in) :: x  !< argument, 0 < x < +Inf
    integer(int64), parameter :: mant = int(z'000FFFFFFFFFFFFF', int64), bump = int(z'00095F6400000000', int64), &
                                 bit52 = int(z'0010000000000000', int64), one_bits = int(z'3FF0000000000000', int64)
    real(wp), parameter :: ln2_hi = 6.93147180369123816490e-01_wp, ln2_lo = 1.90821492927058770002e-10_wp
    real(wp), parameter :: r1 = 2/3.0_wp, r2 = 2/5.0_wp, r3 = 2/7.0_wp, r4 = 2/9.0_wp, r5 = 2/11.0_wp, &
                           r6 = 2/13.0_wp, r7 = 2/15.0_wp, r8 = 2/17.0_wp, r9 = 2/19.0_wp, r10 = 2/21.0_wp
    integer(int64) :: ix, ix0, i, k
    real(wp) :: xs, f, s, z, z2, z4, r, hfsq, dk
    logical :: sub
    sub = x < tiny(x)
    xs = merge(x*2.0_wp**54, x, sub)
    ix = transfer(xs, ix)
    ix0 = ix
    ix = iand(ix, mant)
    ! mantissa >= sqrt(2) - 1: take 1 + f in [sqrt(2)/2, 1) and k + 1 (fdlibm's test)
    i = iand(ix + bump, bit52)
    f = transfer(ior(ix, ieor(one_bits, i)), f) - 1
    k = shiftr(ix0, 52) + shiftr(i, 52) - merge(1077_int64, 1023_int64, sub)
    dk = real(int(k, int32), wp)      ! through int32: a vector conversion on every x86-64
    hfsq = 0.5_wp*f*f
    s = f/(2 + f)
    z = s*s
    z2 = z*z
    z4 = z2*z2
    ! Estrin's scheme (a short dependency chain; z <= 0.03, so the order of the sums is harmless)
    r = z*(((r1 + z*r2) + z2*(r3 + z*r4)) + z4*((r5 + z*r6) + z2*(r7 + z*r8)) + (z4*z4)*(r9 + z*r10))
    y = dk*ln2_hi - ((hfsq - (s*(hfsq + r) + dk*ln2_lo)) - f)
  end function log_pos

  !> Index i in 0..16 of the interval [i/20, (i+1)/20) holding m, for ANY m (NaN gives 0:
  !> the polynomial then returns NaN); the test comes before int() so that no
  !> out-of-range or NaN value is ever converted.
  pure elemental integer function interval20(m) result(i)
    real(wp), intent(in) :: m
    real(wp) :: t
    t = m*20
    if (t >= 0 .and. t < 16) then
      i = int(t)
    else if (t >= 16) then
      i = 16
    else
      i = 0
    end if
  end function interval20

  !> K(m) for 0 <= m < 1 given m and mc = 1 - m (mc accurate when m > 0.85).
  pure elemental real(wp) function k_unit(m, mc) result(k)
    real(wp), intent(in) :: m  !< parameter m in [0, 1)
    real(wp), intent(in) :: mc  !< 1 - m (accurate when m > 0.85)
    integer :: i
    if (mc <= 0.15_wp) then
      k = estrin12(ke_log_poly(:, 0), mc) - log_pos(mc)*estrin12(ke_log_poly(:, 1), mc)
    else
      i = interval20(m)
      k = estrin12(k_poly(:, i), m - (0.025_wp + 0.05_wp*i))
    end if
  end function k_unit

  !> E(m) for 0 <= m < 1 given m and mc = 1 - m (mc accurate when m > 0.85).
  pure elemental real(wp) function e_unit(m, mc) result(e)
    real(wp), intent(in) :: m, mc
    integer :: i
    if (mc <= 0.15_wp) then
      e = estrin12(ke_log_poly(:, 2), mc) - log_pos(mc)*mc*estrin12(ke_log_poly(:, 3), mc)
    else
      i = interval20(m)
      e = estrin12(e_poly(:, i), m - (0.025_wp + 0.05_wp*i))
    end if
  end function e_unit

  !> Complete elliptic integral of the first kind K(m), m = k**2 <= 1.
  !> K(1) = +Inf, K(-Inf) = 0; NaN for m > 1 or NaN.  Accuracy: <= 2.4 ulps measured.
  elemental real(wp) function ellipk(m) result(k)
    real(wp), intent(in) :: m  !< parameter m = k**2, <= 1 (NaN above)
    if (ieee_is_nan(m)) then     ! before any ordered comparison (quiet under -ffpe-trap)
      k = m
    else if (m >= 0 .and. m < 1) then
      k = k_unit(m, 1 - m)
    else if (m < 0) then
      k = k_from_mc(1 - m)
    else if (m == 1) then
      k = ieee_value(1.0_wp, ieee_positive_inf)
    else
      k = quiet_nan()
    end if
  end function ellipk

  !> K as a function of the complementary parameter mc = 1 - m >= 0 (mc = 0 gives +Inf,
  !> NaN for mc < 0).  Exact to a few ulps down to the smallest subnormal mc.
  elemental real(wp) function ellipkm1(mc) result(k)
    real(wp), intent(in) :: mc  !< complementary parameter mc = 1 - m, >= 0
    if (ieee_is_nan(mc)) then
      k = mc
    else if (mc > 0) then
      k = k_from_mc(mc)
    else if (mc == 0) then
      k = ieee_value(1.0_wp, ieee_positive_inf)
    else
      k = quiet_nan()
    end if
  end function ellipkm1

  !> K from mc = 1 - m > 0 alone (m < 0 when mc > 1, by DLMF 19.7.5).
  pure elemental real(wp) function k_from_mc(mc) result(k)
    real(wp), intent(in) :: mc  !< complementary parameter mc = 1 - m, > 0
    if (mc <= 1) then
      k = k_unit(1 - mc, mc)
    else if (mc > huge(1.0_wp)) then   ! m = -Inf
      k = 0
    else
      ! imaginary modulus: K(m) = K(mu)/sqrt(1-m), mu = -m/(1-m), 1 - mu = 1/(1-m)
      k = k_unit((mc - 1)/mc, 1/mc)/sqrt(mc)
    end if
  end function k_from_mc

  !> ellipk over a rank-1 array (k of the size of m): the same numbers as the
  !> elemental function, with the polynomial evaluation inlined in one loop.
  !> A size mismatch sets status (PENDULA_ERR_SIZE) and k = NaN; nothing else is written.
  pure subroutine ellipk_array(m, k, status)
    real(wp), intent(in) :: m(:)  !< parameters m = k**2
    real(wp), intent(out) :: k(:)  !< K(m(i)), size(m) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    call ke_array(m, k, .false., 'ellipk_array: k', status)
  end subroutine ellipk_array

  !> ellipe over a rank-1 array (same numbers as the elemental function); e must have
  !> the size of m (status PENDULA_ERR_SIZE and e = NaN otherwise).
  pure subroutine ellipe_array(m, e, status)
    real(wp), intent(in) :: m(:)  !< parameters m = k**2
    real(wp), intent(out) :: e(:)  !< E(m(i)), size(m) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    call ke_array(m, e, .true., 'ellipe_array: e', status)
  end subroutine ellipe_array

  ! The loop of ellipk_array (second = .false.) and ellipe_array (.true.):
  ! m in [0, 1) straight to the unit-interval kernel, the rest through the
  ! elemental function.  what: the routine and output for the size message.
  pure subroutine ke_array(m, x, second, what, status)
    real(wp), intent(in) :: m(:)
    real(wp), intent(out) :: x(:)
    logical, intent(in) :: second
    character(len=*), intent(in) :: what
    type(status_t), intent(out) :: status
    integer, parameter :: nb = 256
    real(wp) :: mcs(nb), v(nb)
    integer :: idx(nb), i, i0, i1, j, nl
    if (size(x) /= size(m)) then
      x = quiet_nan()
      call set_error(status, PENDULA_ERR_SIZE, what//' must have the size of m')
      return
    end if
    do i0 = 1, size(m), nb
      i1 = min(size(m), i0 + nb - 1)
      if (all(log_form_m(m(i0:i1)))) then
        ! a block near m = 1 (all in the logarithmic forms): one vectorised loop, no gathering
        call ke_log_forms(i1 - i0 + 1, 1 - m(i0:i1), second, x(i0:i1))
        cycle
      end if
      ! the logarithmic forms (mc <= 0.15, k_unit's and e_unit's test) are gathered and
      ! taken in one vectorised loop below; the rest here
      nl = 0
      do i = i0, i1
        if (ieee_is_nan(m(i))) then     ! before any ordered comparison (quiet under -ffpe-trap)
          x(i) = m(i)
        else if (m(i) >= 0 .and. m(i) < 1) then
          if (1 - m(i) <= 0.15_wp) then
            nl = nl + 1
            idx(nl) = i
            mcs(nl) = 1 - m(i)
          else if (second) then
            x(i) = poly_at(e_poly, m(i))   ! = e_unit(m(i), 1 - m(i))
          else
            x(i) = poly_at(k_poly, m(i))   ! = k_unit(m(i), 1 - m(i))
          end if
        else if (second) then
          x(i) = ellipe(m(i))   ! m < 0, m >= 1
        else
          x(i) = ellipk(m(i))
        end if
      end do
      if (nl == i1 - i0 + 1) then
        call ke_log_forms(nl, mcs, second, x(i0:i1))   ! the whole block (m near 1): no scatter
      else
        call ke_log_forms(nl, mcs, second, v)
        do j = 1, nl
          x(idx(j)) = v(j)
        end do
      end if
    end do
  end subroutine ke_array

  !> Whether K and E of m take the logarithmic form in k_unit / e_unit (0 <= m < 1 and
  !> 1 - m <= 0.15); false for NaN, without an ordered comparison of a NaN (quiet under
  !> -ffpe-trap) and without a branch (the test of a whole block vectorises).
  pure elemental logical function log_form_m(m) result(yes)
    real(wp), intent(in) :: m
    real(wp) :: x
    x = merge(m, 0.0_wp, m == m)
    yes = x < 1 .and. 1 - x <= 0.15_wp
  end function log_form_m

  !> Whether K and E of the complement p take the logarithmic form (0 < p <= 0.15), as
  !> log_form_m (NaN false, no branch).
  pure elemental logical function log_form_p(p) result(yes)
    real(wp), intent(in) :: p
    real(wp) :: x
    x = merge(p, 0.0_wp, p == p)
    yes = x > 0 .and. x <= 0.15_wp
  end function log_form_p

  !> ellipkm1 over a rank-1 array (k of the size of p): the same numbers as the elemental
  !> function, the logarithmic forms (p <= 0.15) in one vectorised loop.  A size mismatch
  !> sets status (PENDULA_ERR_SIZE) and k = NaN.
  pure subroutine ellipkm1_array(p, k, status)
    real(wp), intent(in) :: p(:)  !< complementary parameters p = 1 - m, >= 0
    real(wp), intent(out) :: k(:)  !< K(1 - p(i)), size(p) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    call ke_m1_array(p, k, .false., 'ellipkm1_array: k', status)
  end subroutine ellipkm1_array

  !> ellipem1 over a rank-1 array (same numbers as the elemental function); sizes as
  !> ellipkm1_array.
  pure subroutine ellipem1_array(p, e, status)
    real(wp), intent(in) :: p(:)  !< complementary parameters p = 1 - m, >= 0
    real(wp), intent(out) :: e(:)  !< E(1 - p(i)), size(p) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    call ke_m1_array(p, e, .true., 'ellipem1_array: e', status)
  end subroutine ellipem1_array

  ! The loop of ellipkm1_array (second = .false.) and ellipem1_array (.true.): 0 < p <= 0.15
  ! gathered for ke_log_forms, 0.15 < p <= 1 by the interval polynomial at m = 1 - p (what
  ! k_from_mc / e_from_m_mc take), the rest through the elemental function.
  pure subroutine ke_m1_array(p, x, second, what, status)
    real(wp), intent(in) :: p(:)
    real(wp), intent(out) :: x(:)
    logical, intent(in) :: second
    character(len=*), intent(in) :: what
    type(status_t), intent(out) :: status
    integer, parameter :: nb = 256
    real(wp) :: mcs(nb), v(nb)
    integer :: idx(nb), i, i0, i1, j, nl
    if (size(x) /= size(p)) then
      x = quiet_nan()
      call set_error(status, PENDULA_ERR_SIZE, what//' must have the size of p')
      return
    end if
    do i0 = 1, size(p), nb
      i1 = min(size(p), i0 + nb - 1)
      if (all(log_form_p(p(i0:i1)))) then
        call ke_log_forms(i1 - i0 + 1, p(i0:i1), second, x(i0:i1))
        cycle
      end if
      nl = 0
      do i = i0, i1
        if (ieee_is_nan(p(i))) then     ! before any ordered comparison
          x(i) = p(i)
        else if (p(i) > 0 .and. p(i) <= 0.15_wp) then
          nl = nl + 1
          idx(nl) = i
          mcs(nl) = p(i)
        else if (p(i) > 0 .and. p(i) <= 1) then
          if (second) then
            x(i) = poly_at(e_poly, 1 - p(i))
          else
            x(i) = poly_at(k_poly, 1 - p(i))
          end if
        else if (second) then
          x(i) = ellipem1(p(i))
        else
          x(i) = ellipkm1(p(i))
        end if
      end do
      call ke_log_forms(nl, mcs, second, v)
      do j = 1, nl
        x(idx(j)) = v(j)
      end do
    end do
  end subroutine ke_m1_array

  !> The interval polynomial of k_unit / e_unit (table k_poly or e_poly) at 0 <= m < 0.85,
  !> estrin12 written out on the table's column (the same operations): the call with a
  !> column argument was not inlined into the array loop.
  pure real(wp) function poly_at(tab, m) result(r)
    real(wp), intent(in) :: tab(0:12, 0:16), m
    real(wp) :: y, y2, y4
    integer :: i
    i = interval20(m)
    y = m - (0.025_wp + 0.05_wp*i)
    y2 = y*y
    y4 = y2*y2
    r = ((tab(0, i) + tab(1, i)*y) + (tab(2, i) + tab(3, i)*y)*y2) &
        + ((tab(4, i) + tab(5, i)*y) + (tab(6, i) + tab(7, i)*y)*y2)*y4 &
        + (((tab(8, i) + tab(9, i)*y) + (tab(10, i) + tab(11, i)*y)*y2) + tab(12, i)*y4)*(y4*y4)
  end function poly_at

  !> K (second = .false.) or E of 0 < mc <= 0.15 by the logarithmic forms of k_unit and
  !> e_unit, the same numbers, in a loop without branches or calls (it vectorises).
  pure subroutine ke_log_forms(n, mc, second, x)
    integer, intent(in) :: n
    real(wp), intent(in) :: mc(:)
    logical, intent(in) :: second
    real(wp), intent(out) :: x(:)
    ! the columns as named constants and estrin12 written out (operation for operation):
    ! a call with an array argument kept the loop from vectorising
    real(wp), parameter :: pk(0:12) = ke_log_poly(:, 0), qk(0:12) = ke_log_poly(:, 1), &
                           pe(0:12) = ke_log_poly(:, 2), qe(0:12) = ke_log_poly(:, 3)
    real(wp) :: y, y2, y4, p, q
    integer :: j
    if (second) then
      do j = 1, n
        y = mc(j)
        y2 = y*y
        y4 = y2*y2
        p = (((pe(0) + pe(1)*y) + (pe(2) + pe(3)*y)*y2) + ((pe(4) + pe(5)*y) + (pe(6) + pe(7)*y)*y2)*y4 &
             + (((pe(8) + pe(9)*y) + (pe(10) + pe(11)*y)*y2) + pe(12)*y4)*(y4*y4))
        q = (((qe(0) + qe(1)*y) + (qe(2) + qe(3)*y)*y2) + ((qe(4) + qe(5)*y) + (qe(6) + qe(7)*y)*y2)*y4 &
             + (((qe(8) + qe(9)*y) + (qe(10) + qe(11)*y)*y2) + qe(12)*y4)*(y4*y4))
        x(j) = p - log_pos(y)*y*q
      end do
    else
      do j = 1, n
        y = mc(j)
        y2 = y*y
        y4 = y2*y2
        p = (((pk(0) + pk(1)*y) + (pk(2) + pk(3)*y)*y2) + ((pk(4) + pk(5)*y) + (pk(6) + pk(7)*y)*y2)*y4 &
             + (((pk(8) + pk(9)*y) + (pk(10) + pk(11)*y)*y2) + pk(12)*y4)*(y4*y4))
        q = (((qk(0) + qk(1)*y) + (qk(2) + qk(3)*y)*y2) + ((qk(4) + qk(5)*y) + (qk(6) + qk(7)*y)*y2)*y4 &
             + (((qk(8) + qk(9)*y) + (qk(10) + qk(11)*y)*y2) + qk(12)*y4)*(y4*y4))
        x(j) = p - log_pos(y)*q
      end do
    end if
  end subroutine ke_log_forms

  !> K of many complementary parameters 0 < mc(i) <= 1 (the caller has checked them):
  !> k(i) = ellipkm1(mc(i)), the same numbers, with the logarithmic forms (mc <= 0.15)
  !> gathered into one vectorised loop.  For the period over many amplitudes.
  pure subroutine k_unit_many(mc, k)
    real(wp), intent(in) :: mc(:)  !< complementary parameters, 0 < mc <= 1
    real(wp), intent(out) :: k(:)  !< K(1 - mc(i)), size(mc) elements
    integer, parameter :: nb = 256
    real(wp) :: mcs(nb), v(nb)
    integer :: idx(nb), i, i0, i1, j, nl
    do i0 = 1, size(mc), nb
      i1 = min(size(mc), i0 + nb - 1)
      nl = 0
      do i = i0, i1
        if (mc(i) <= 0.15_wp) then
          nl = nl + 1
          idx(nl) = i
          mcs(nl) = mc(i)
        else
          k(i) = poly_at(k_poly, 1 - mc(i))   ! = k_unit(1 - mc(i), mc(i))
        end if
      end do
      call ke_log_forms(nl, mcs, .false., v)
      do j = 1, nl
        k(idx(j)) = v(j)
      end do
    end do
  end subroutine k_unit_many

  !> Complete elliptic integral of the second kind E(m), m <= 1 (E(1) = 1,
  !> E(-Inf) = +Inf); NaN for m > 1 or NaN.  A few ulps.
  elemental real(wp) function ellipe(m) result(e)
    real(wp), intent(in) :: m  !< parameter m = k**2, <= 1 (NaN above)
    if (ieee_is_nan(m)) then
      e = m
    else if (m <= 1) then
      e = e_from_m_mc(m, 1 - m)
    else
      e = quiet_nan()
    end if
  end function ellipe

  !> E as a function of mc = 1 - m >= 0 (mc = 0 gives 1); NaN for mc < 0 or NaN.
  elemental real(wp) function ellipem1(mc) result(e)
    real(wp), intent(in) :: mc  !< complementary parameter mc = 1 - m, >= 0
    if (ieee_is_nan(mc)) then
      e = mc
    else if (mc >= 0) then
      e = e_from_m_mc(1 - mc, mc)
    else
      e = quiet_nan()
    end if
  end function ellipem1

  !> E(m) given both m and mc = 1 - m (mc accurate), m <= 1.
  pure elemental real(wp) function e_from_m_mc(m, mc) result(e)
    real(wp), intent(in) :: m, mc
    real(wp) :: mu, muc, r
    if (mc == 0) then
      e = 1
    else if (m >= 0) then
      e = e_unit(m, mc)
    else if (.not. ieee_is_finite(mc)) then
      e = mc
    else
      ! imaginary modulus: E(m) = sqrt(1-m) E(-m/(1-m)) (DLMF 19.7.5)
      r = sqrt(mc)
      muc = 1/mc
      mu = -m/mc
      e = r*e_unit(mu, muc)
    end if
  end function e_from_m_mc

end module pendula_elliptic_ke
