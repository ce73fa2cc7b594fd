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
!> take each kind in one branch-free vectorised pass, in the block kernel compiled per
!> instruction set and chosen at load time (pendula_elliptic_ke_lanes.F90, runtime CPU
!> dispatch; the same bits on every path).  m < 0 by the imaginary-modulus
!> transformation (DLMF 19.7.5).  Measured <= 2.4 ulps against mpmath.  K in double-double
!> by the AGM in double-double arithmetic (DLMF 19.8.5), its steps in pendula_agm_dd.inc,
!> which the block form (pendula_elliptic_k_lanes.F90) includes too.
module pendula_elliptic_ke
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_is_nan, ieee_is_finite
  use, intrinsic :: iso_fortran_env, only: int32, int64
  use pendula_kinds, only: wp
  use pendula_constants, only: half_pi, half_pi_lo, quiet_nan
  use pendula_status, only: status_t, set_error, PENDULA_ERR_SIZE
  use pendula_dispatch, only: ke_block_lanes
  implicit none
  private

  public :: ellipk, ellipkm1, ellipe, ellipem1, ellipk_array, ellipe_array, ellipkm1_array, ellipem1_array
  ! for the other modules of the elliptic concern
  public :: k_unit, k_from_mc, k_double_double, k_unit_many

  ! the tables and block size (generated: tools/gen/gen_elliptic_tables.py), the same text
  ! as each compiled variant of the block kernel includes
  include 'pendula_elliptic_ke_tables.inc'

contains

  ! ke_block, its passes, log_pos and ke_subnormal: the scalar forms below run the passes
  ! here (baseline code); the array forms call the variant the runtime dispatch chose
  ! (ke_block_lanes, pendula_elliptic_ke_lanes.F90), compiled from this same text.
  include 'pendula_elliptic_ke_block.inc'

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
    real(wp) :: ah, al, bh, bl, nah, nal, nbh, nbl
    integer :: i
    call agm_start(mch, mcl, ah, al, bh, bl)
    do i = 1, 80
      if (.not. agm_live(ah, bh)) exit
      call agm_step(ah, al, bh, bl, nah, nal, nbh, nbl)
      ah = nah; al = nal; bh = nbh; bl = nbl
    end do
    call agm_finish(ah, al, bh, bl, half_pi, half_pi_lo, khi, klo)
  end subroutine k_double_double

  ! The AGM's steps (agm_start, agm_live, agm_step, agm_finish, prod_err, sq_err):
  ! k_double_double runs them here for one point; k_double_double_block calls the variant
  ! the runtime dispatch chose (k_dd_block_lanes, pendula_elliptic_k_lanes.F90), which
  ! steps a block's points with this same text.
  include 'pendula_agm_dd.inc'

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
  ! ke_block (the variant the runtime dispatch chose); the others (NaN, m < 0, m >= 1) get
  ! a harmless stand-in there and are then taken by the elemental function.  what: the
  ! size message.
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
      call ke_block_lanes(n, m, mc, merge(1, 0, second), y(i0:i0 + n - 1))
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
      call ke_block_lanes(n, m, c, 0, k(i0:i0 + n - 1))
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
