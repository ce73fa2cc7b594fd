!> Complete elliptic integrals K(m) and E(m) for every real m <= 1, their complement
!> forms of mc = 1 - m, and K in double-double (for the period reductions of F and of
!> the Jacobi functions).
!>
!> K, E: degree-8 polynomials (Chebyshev interpolants at 40 digits) on 81 intervals of
!> mc = 1 - m >= 2**-5 read from mc's bits (each binade of mc in 16 pieces: every interval
!> at least 33 of its half-widths from the singularity at m = 1, so one short degree serves
!> all; truncation < 0.02 ulp),
!> and for mc < 2**-5 the logarithmic form K = P(mc) - ln(mc) Q(mc),
!> E = Pe(mc) - ln(mc) mc Qe1(mc) (structure of DLMF 19.12.1, degree 7), exact as mc -> 0
!> down to the smallest subnormal (the logarithm inlined, log_pos).  The array forms
!> take each kind in one branch-free vectorised pass.  m < 0 by the imaginary-modulus
!> transformation (DLMF 19.7.5).  Measured <= 2.4 ulps against mpmath.  K in double-double
!> by the AGM in double-double arithmetic (DLMF 19.8.5).
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

  integer, parameter :: ke_emin = -5   ! the table holds mc >= 2**ke_emin (gen_elliptic_tables.py)
  integer, parameter :: ke_top = ubound(k_poly, 2)   ! its last interval (mc in [1, 1 + 1/16))
  real(wp), parameter :: mc_log = 2.0_wp**ke_emin   ! below: the logarithmic forms
  integer, parameter :: nb = 256   ! block of the array forms (its scratch stays in L1)

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

  !> ln(x) + e0 ln 2 for normal 0 < x < +Inf (subnormal x: log_pos(x 2**54, -54)): x = 2^k (1 + f)
  !> with 1 + f in [sqrt(2)/2, sqrt(2)) read from the bits, ln(1 + f) = 2 atanh(s) = 2 s + s R(s^2),
  !> s = f/(2 + f), R the minimax polynomial of degree 7 of fdlibm's e_log.c (|error| <
  !> 2**-58.45 on |s| <= 0.1716), and (k + e0) ln 2 with ln 2 in two parts.  Without fdlibm's
  !> f - f^2/2 arrangement, which keeps ln(1 + f) exact when k + e0 = 0: here x < 2**-5, so
  !> |ln x| >= 3.4 and the rounding of 2 s (<= 0.35) stays under 0.1 ulp of the result.
  !> Plain arithmetic, inlined into the vectorised logarithmic forms of K and E (a subnormal
  !> test there cost a quarter of their time).
  pure elemental real(wp) function log_pos(x, e0) result(y)
    real(wp), intent(in) :: x  !< argument, tiny(x) <= x < 2**-5 (so |ln x| >= 3.4)
    integer, intent(in) :: e0  !< power of 2 added (-54 for x scaled by 2**54)
    integer(int64), parameter :: mant = int(z'000FFFFFFFFFFFFF', int64), bump = int(z'00095F6400000000', int64), &
                                 bit52 = int(z'0010000000000000', int64), one_bits = int(z'3FF0000000000000', int64)
    real(wp), parameter :: ln2_hi = 6.93147180369123816490e-01_wp, ln2_lo = 1.90821492927058770002e-10_wp
    real(wp), parameter :: lg1 = 6.666666666666735130e-01_wp, lg2 = 3.999999999940941908e-01_wp, &
                           lg3 = 2.857142874366239149e-01_wp, lg4 = 2.222219843214978396e-01_wp, &
                           lg5 = 1.818357216161805012e-01_wp, lg6 = 1.531383769920937332e-01_wp, &
                           lg7 = 1.479819860511658591e-01_wp
    integer(int64) :: ix, ix0, i, k
    real(wp) :: f, s, z, w, r, dk
    ix = transfer(x, ix)
    ix0 = ix
    ix = iand(ix, mant)
    ! mantissa >= sqrt(2) - 1: take 1 + f in [sqrt(2)/2, 1) and k + 1 (fdlibm's test)
    i = iand(ix + bump, bit52)
    f = transfer(ior(ix, ieor(one_bits, i)), f) - 1
    k = shiftr(ix0, 52) + shiftr(i, 52) - 1023 + e0
    dk = real(int(k, int32), wp)      ! through int32: a vector conversion on every x86-64
    s = f/(2 + f)
    z = s*s
    w = z*z
    ! fdlibm's two interleaved chains in w = s^4
    r = z*(lg1 + w*(lg3 + w*(lg5 + w*lg7))) + w*(lg2 + w*(lg4 + w*lg6))
    y = dk*ln2_hi + (dk*ln2_lo + (2*s + s*r))
  end function log_pos

  !> K (second = .false.) or E at a subnormal mc: the logarithmic forms reduce to
  !> P(0) - ln(mc) Q(0) and Pe(0) (the other terms are below the last bit), ln(mc) from the
  !> normal mc 2**54.
  pure elemental real(wp) function ke_subnormal(mc, second) result(x)
    real(wp), intent(in) :: mc
    logical, intent(in) :: second
    if (second) then
      x = ke_log_poly(0, 2)
    else
      x = ke_log_poly(0, 0) - log_pos(mc*2.0_wp**54, -54)*ke_log_poly(0, 1)
    end if
  end function ke_subnormal

  !> K(m) for 0 <= m < 1 given m and mc = 1 - m (m accurate when m < 1/2, mc when m > 1/2).
  !> Through the passes of the array forms with one element: their loops are the one home
  !> of the formulas, so the scalar and array forms agree to the bit.
  pure elemental real(wp) function k_unit(m, mc) result(k)
    real(wp), intent(in) :: m  !< parameter m in [0, 1)
    real(wp), intent(in) :: mc  !< 1 - m (accurate when m > 1/2)
    real(wp) :: x(1)
    if (mc < tiny(mc)) then
      x = ke_subnormal(mc, .false.)
    else if (mc < mc_log) then
      call pass_log(1, [mc], .false., x)
    else
      call pass_table(1, [m], [mc], .false., x)
    end if
    k = x(1)
  end function k_unit

  !> E(m) for 0 <= m < 1 given m and mc = 1 - m, as k_unit.
  pure elemental real(wp) function e_unit(m, mc) result(e)
    real(wp), intent(in) :: m, mc
    real(wp) :: x(1)
    if (mc < tiny(mc)) then
      x = ke_subnormal(mc, .true.)
    else if (mc < mc_log) then
      call pass_log(1, [mc], .true., x)
    else
      call pass_table(1, [m], [mc], .true., x)
    end if
    e = x(1)
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
  !> elemental function, each kind of evaluation in one vectorised pass (ke_block).
  !> A size mismatch sets status (PENDULA_ERR_SIZE) and k = NaN; nothing else is written.
  pure subroutine ellipk_array(m, k, status)
    real(wp), intent(in) :: m(:)  !< parameters m = k**2
    real(wp), intent(out) :: k(:)  !< K(m(i)), size(m) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    call ke_array(m, k, .false., .false., 'ellipk_array: k must have the size of m', status)
  end subroutine ellipk_array

  !> ellipe over a rank-1 array (same numbers as the elemental function); e must have
  !> the size of m (status PENDULA_ERR_SIZE and e = NaN otherwise).
  pure subroutine ellipe_array(m, e, status)
    real(wp), intent(in) :: m(:)  !< parameters m = k**2
    real(wp), intent(out) :: e(:)  !< E(m(i)), size(m) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    call ke_array(m, e, .false., .true., 'ellipe_array: e must have the size of m', status)
  end subroutine ellipe_array

  !> ellipkm1 over a rank-1 array (k of the size of p): the same numbers as the elemental
  !> function, as ellipk_array.  A size mismatch sets status (PENDULA_ERR_SIZE) and k = NaN.
  pure subroutine ellipkm1_array(p, k, status)
    real(wp), intent(in) :: p(:)  !< complementary parameters p = 1 - m, >= 0
    real(wp), intent(out) :: k(:)  !< K(1 - p(i)), size(p) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    call ke_array(p, k, .true., .false., 'ellipkm1_array: k must have the size of p', status)
  end subroutine ellipkm1_array

  !> ellipem1 over a rank-1 array (same numbers as the elemental function); sizes as
  !> ellipkm1_array.
  pure subroutine ellipem1_array(p, e, status)
    real(wp), intent(in) :: p(:)  !< complementary parameters p = 1 - m, >= 0
    real(wp), intent(out) :: e(:)  !< E(1 - p(i)), size(p) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    call ke_array(p, e, .true., .true., 'ellipem1_array: e must have the size of p', status)
  end subroutine ellipem1_array

  ! The loop of the four array forms: x holds m (m1 = .false.) or p = 1 - m (.true.), y gets
  ! K (second = .false.) or E.  Per block, the elements in the unit interval (0 <= m < 1)
  ! become (m, mc) pairs exactly as ellipk/ellipkm1 (ellipe/ellipem1) form them and go to
  ! ke_block; the others (NaN, m < 0, m >= 1) get a harmless stand-in there and are then
  ! taken by the elemental function.  what: the size message.
  pure subroutine ke_array(x, y, m1, second, what, status)
    real(wp), intent(in) :: x(:)
    real(wp), intent(out) :: y(:)
    logical, intent(in) :: m1, second
    character(len=*), intent(in) :: what
    type(status_t), intent(out) :: status
    real(wp) :: m(nb), mc(nb)
    integer :: i0, n, j, nbad
    if (size(y) /= size(x)) then
      y = quiet_nan()
      call set_error(status, PENDULA_ERR_SIZE, what)
      return
    end if
    do i0 = 1, size(x), nb
      n = min(nb, size(x) - i0 + 1)
      nbad = 0
      if (m1) then
        do j = 1, n
          mc(j) = merge(x(i0 + j - 1), 0.5_wp, in_unit(x(i0 + j - 1), m1))
          m(j) = 1 - mc(j)
          nbad = nbad + merge(0, 1, in_unit(x(i0 + j - 1), m1))
        end do
      else
        do j = 1, n
          m(j) = merge(x(i0 + j - 1), 0.5_wp, in_unit(x(i0 + j - 1), m1))
          mc(j) = 1 - m(j)
          nbad = nbad + merge(0, 1, in_unit(x(i0 + j - 1), m1))
        end do
      end if
      call ke_block(n, m, mc, second, y(i0:i0 + n - 1))
      if (nbad == 0) cycle
      do j = i0, i0 + n - 1
        if (in_unit(x(j), m1)) cycle
        if (m1 .and. second) then
          y(j) = ellipem1(x(j))
        else if (m1) then
          y(j) = ellipkm1(x(j))
        else if (second) then
          y(j) = ellipe(x(j))
        else
          y(j) = ellipk(x(j))
        end if
      end do
    end do
  end subroutine ke_array

  !> Whether x is in the unit interval of ke_array: 0 <= x < 1 (m1 false: x = m) or
  !> 0 < x <= 1 (m1: x = p = 1 - m).  NaN gives false without an ordered comparison of a
  !> NaN (quiet under -ffpe-trap), and without a branch.
  pure elemental logical function in_unit(x, m1) result(yes)
    real(wp), intent(in) :: x
    logical, intent(in) :: m1
    real(wp) :: v
    v = merge(x, -1.0_wp, x == x)
    yes = merge(v > 0 .and. v <= 1, v >= 0 .and. v < 1, m1)
  end function in_unit

  ! K (second = .false.) or E of the n <= nb pairs (m(j), mc(j)), 0 <= m < 1, mc = 1 - m as
  ! k_unit takes them, the same numbers as k_unit/e_unit.  Each kind (interval polynomial,
  ! logarithmic form) is taken in one branch-free vectorised pass: over the whole block
  ! when the block is all of one kind or mostly of it (the few others get a finite value
  ! there, replaced after), the other kind gathered into its own pass and scattered back;
  ! subnormal mc (not in log_pos's range) last, by ke_subnormal.
  ! Gathers are branch-free too (random m made the test of each element unpredictable).
  pure subroutine ke_block(n, m, mc, second, x)
    integer, intent(in) :: n
    real(wp), intent(in) :: m(n), mc(n)
    logical, intent(in) :: second
    real(wp), intent(out) :: x(n)
    real(wp) :: g(nb), gc(nb), v(nb)
    integer :: idx(nb + 1), j, nl, ng, ns
    nl = count(mc < mc_log)
    ns = count(mc < tiny(mc))
    if (2*nl < n) then   ! mostly (or all) interval polynomials
      call pass_table(n, m, mc, second, x)
      if (nl == 0) return   ! (then ns = 0 too)
      ng = 0
      do j = 1, n
        idx(ng + 1) = j
        ng = ng + merge(1, 0, mc(j) < mc_log)
      end do
      do j = 1, ng
        gc(j) = mc(idx(j))
      end do
      call pass_log(ng, gc, second, v)
      do j = 1, ng
        x(idx(j)) = v(j)
      end do
    else   ! mostly (or all) logarithmic forms
      call pass_log(n, mc, second, x)
      if (nl < n) then
        ng = 0
        do j = 1, n
          idx(ng + 1) = j
          ng = ng + merge(0, 1, mc(j) < mc_log)
        end do
        do j = 1, ng
          g(j) = m(idx(j))
          gc(j) = mc(idx(j))
        end do
        call pass_table(ng, g, gc, second, v)
        do j = 1, ng
          x(idx(j)) = v(j)
        end do
      end if
    end if
    if (ns == 0) return
    do j = 1, n
      if (mc(j) < tiny(mc)) x(j) = ke_subnormal(mc(j), second)
    end do
  end subroutine ke_block

  ! K (second = .false.) or E by the interval polynomials (degree 8, Estrin's scheme) at
  ! m(j), mc(j) = 1 - m(j) >= mc_log, j = 1..n, in one vectorised loop (the table columns
  ! gathered element by element).  The interval i and its centre cmc in mc come from mc's
  ! exponent and top 4 mantissa bits (smaller mc give i = 0, larger than 1 + 1/16 i = ke_top:
  ! finite values no caller keeps); the polynomial's variable t = m - (1 - cmc) is formed
  ! as cmc - mc (exact, Sterbenz) for mc <= 1/2, where mc is the accurate one, and from m
  ! above, where m is (1 - cmc has at most 10 bits: exact).  The formulas are written
  ! into the loop (a call to an elemental function there was not inlined, and the loop
  ! then not vectorised); k_unit and e_unit come here with one element.
  pure subroutine pass_table(n, m, mc, second, x)
    integer, intent(in) :: n
    real(wp), intent(in) :: m(n), mc(n)
    logical, intent(in) :: second
    real(wp), intent(out) :: x(n)
    integer(int64), parameter :: low48 = int(z'0000FFFFFFFFFFFF', int64), half48 = int(z'0000800000000000', int64)
    integer, parameter :: first = (1023 + ke_emin)*16   ! the bits of 2**ke_emin shifted right by 48
    integer(int64) :: ix
    real(wp) :: cmc, t, tm, t2, t4
    integer :: i, j
    if (second) then
      do j = 1, n
        ix = transfer(mc(j), ix)
        i = min(max(int(shiftr(ix, 48), int32) - first, 0), ke_top)   ! int32: vectorises on x86-64
        cmc = transfer(ior(iand(ix, not(low48)), half48), cmc)
        t = cmc - mc(j)
        tm = m(j) - (1 - cmc)
        t = merge(t, tm, mc(j) <= 0.5_wp)   ! both formed first: a merge of expressions was a branch
        t2 = t*t
        t4 = t2*t2
        x(j) = (((e_poly(0, i) + e_poly(1, i)*t) + (e_poly(2, i) + e_poly(3, i)*t)*t2) &
                + ((e_poly(4, i) + e_poly(5, i)*t) + (e_poly(6, i) + e_poly(7, i)*t)*t2)*t4) + e_poly(8, i)*(t4*t4)
      end do
    else
      do j = 1, n
        ix = transfer(mc(j), ix)
        i = min(max(int(shiftr(ix, 48), int32) - first, 0), ke_top)   ! int32: vectorises on x86-64
        cmc = transfer(ior(iand(ix, not(low48)), half48), cmc)
        t = cmc - mc(j)
        tm = m(j) - (1 - cmc)
        t = merge(t, tm, mc(j) <= 0.5_wp)   ! both formed first: a merge of expressions was a branch
        t2 = t*t
        t4 = t2*t2
        x(j) = (((k_poly(0, i) + k_poly(1, i)*t) + (k_poly(2, i) + k_poly(3, i)*t)*t2) &
                + ((k_poly(4, i) + k_poly(5, i)*t) + (k_poly(6, i) + k_poly(7, i)*t)*t2)*t4) + k_poly(8, i)*(t4*t4)
      end do
    end if
  end subroutine pass_table

  ! K (second = .false.) or E by the logarithmic forms K = P(mc) - ln(mc) Q(mc),
  ! E = Pe(mc) - ln(mc) mc Qe1(mc) (degree 7, Estrin's scheme) at 0 < mc(j) <= 1, j = 1..n:
  ! one vectorised loop without branches or calls (log_pos inlined).  Subnormal mc give
  ! finite values, replaced by ke_subnormal's.  k_unit and e_unit come here with one element.
  pure subroutine pass_log(n, mc, second, x)
    integer, intent(in) :: n
    real(wp), intent(in) :: mc(n)
    logical, intent(in) :: second
    real(wp), intent(out) :: x(n)
    real(wp), parameter :: pk(0:7) = ke_log_poly(:, 0), qk(0:7) = ke_log_poly(:, 1), &
                           pe(0:7) = ke_log_poly(:, 2), qe(0:7) = ke_log_poly(:, 3)
    real(wp) :: y, y2, y4, p, q
    integer :: j
    if (second) then
      do j = 1, n
        y = mc(j)
        y2 = y*y
        y4 = y2*y2
        p = ((pe(0) + pe(1)*y) + (pe(2) + pe(3)*y)*y2) + ((pe(4) + pe(5)*y) + (pe(6) + pe(7)*y)*y2)*y4
        q = ((qe(0) + qe(1)*y) + (qe(2) + qe(3)*y)*y2) + ((qe(4) + qe(5)*y) + (qe(6) + qe(7)*y)*y2)*y4
        x(j) = p - log_pos(y, 0)*y*q
      end do
    else
      do j = 1, n
        y = mc(j)
        y2 = y*y
        y4 = y2*y2
        p = ((pk(0) + pk(1)*y) + (pk(2) + pk(3)*y)*y2) + ((pk(4) + pk(5)*y) + (pk(6) + pk(7)*y)*y2)*y4
        q = ((qk(0) + qk(1)*y) + (qk(2) + qk(3)*y)*y2) + ((qk(4) + qk(5)*y) + (qk(6) + qk(7)*y)*y2)*y4
        x(j) = p - log_pos(y, 0)*q
      end do
    end if
  end subroutine pass_log

  !> K of many complementary parameters 0 < mc(i) <= 1 (the caller has checked them):
  !> k(i) = ellipkm1(mc(i)), the same numbers, by the passes of the array forms.  For the
  !> period over many amplitudes.
  pure subroutine k_unit_many(mc, k)
    real(wp), intent(in) :: mc(:)  !< complementary parameters, 0 < mc <= 1
    real(wp), intent(out) :: k(:)  !< K(1 - mc(i)), size(mc) elements
    real(wp) :: m(nb), c(nb)
    integer :: i0, n
    do i0 = 1, size(mc), nb
      n = min(nb, size(mc) - i0 + 1)
      c(1:n) = mc(i0:i0 + n - 1)
      m(1:n) = 1 - c(1:n)
      call ke_block(n, m, c, .false., k(i0:i0 + n - 1))
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
