!> Kernel of the Jacobi functions sn, cn, dn, am at a transformed parameter (see
!> pendula_elliptic_modulus): Maclaurin series at u/2^N followed by N duplications,
!> first on the complements 1 - cn, 1 - dn and then on cn, dn written without
!> cancellation (cn(2u) = (cn^2 dn^2 - mc sn^2)/D, dn(2u) = (mc + m cn^4)/D,
!> D = cn^2 + sn^2 dn^2), after the idea of Fukushima's conditional duplication
!> (Numer. Math. 2012); the complement steps run on fractions without division.
!> u is reduced modulo 2K with K and 1 - m in double-double and [K/2, K] is mapped
!> to [0, K/2] by u -> K - u (DLMF 22.4.3), which keeps cn and dn relatively accurate
!> when mc is tiny.  am = 2 atan(sn/(1 + cn)) by a polynomial.  Also the Taylor rows
!> of the plans' tables (degree 8 from the ODEs, DLMF 22.13).
module pendula_jacobi_kernel
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_is_finite
  use, intrinsic :: iso_c_binding, only: c_int
  use pendula_kinds, only: wp
  use pendula_dispatch, only: core_block_lanes
  use pendula_constants, only: pi, half_pi, quiet_nan
  use pendula_double_double, only: two_prod, veltkamp_split
  use pendula_elliptic_tables, only: atan_poly
  use pendula_status, only: status_t
  use pendula_elliptic_ke, only: k_double_double, ellipk_array, ellipkm1_array
  use pendula_elliptic_k_block, only: k_double_double_block
  use pendula_elliptic_modulus, only: jacobi_param_t, jacobi_param, MODULUS_INVALID, MODULUS_CORE, MODULUS_ONE, &
                                      MODULUS_RECIPROCAL, MODULUS_IMAGINARY
  implicit none
  private

  public :: eval_at_param, eval_table_array, ellipj_points, ellipj_point, taylor_row_at
  public :: ntay, tab_step, tab_inv_step, khi_tab_max

  !> Tabulated plans: Taylor polynomials of degree ntay about a grid of step 1/32 in the core
  !> argument; |delta| <= 1/64 and the nearest singularity is >= K' >= pi/2 away, so the
  !> truncation is below ~ (1/64 / (pi/2))**9 ~ 1e-18 relative.
  integer, parameter :: ntay = 8
  real(wp), parameter :: tab_step = 0.03125_wp, tab_inv_step = 32.0_wp
  !> Largest core K a plan tabulates (the core K is at most 374, at mc = 5e-324).
  real(wp), parameter :: khi_tab_max = 400.0_wp

  real(wp), parameter :: tan_pi8 = 0.41421356237309503_wp
  !> Points per block of unit_block (its work arrays live on the stack).
  integer, parameter :: jblock = 64

contains

  !> sn, cn, dn at 0 <= v <= K(m)/2 for 0 <= m <= 1 (mc = 1 - m accurate).
  pure subroutine sncndn_duplication(v, m, mc, s, c, d)
    real(wp), intent(in) :: v, m, mc
    real(wp), intent(out) :: s, c, d
    real(wp) :: sa(1), ca(1), da(1)
    call core_block(1, [v], [m], [mc], sa, ca, da)
    s = sa(1); c = ca(1); d = da(1)
  end subroutine sncndn_duplication

  !> cd = cn/dn without the cancellation of two nearly equal small numbers when m -> 1:
  !> dn^2 - cn^2 = mc sn^2, so cd = 1 - mc sn^2 / (dn (dn + cn)) (cn >= 0 here).
  pure elemental real(wp) function cd_ratio(s, c, d, mc) result(cd)
    real(wp), intent(in) :: s, c, d, mc
    real(wp) :: t
    t = mc*(s*s)/(d*(d + c))
    if (t <= 0.5_wp) then
      cd = 1 - t
    else
      cd = c/d
    end if
  end function cd_ratio

  !> Amplitude atan2(sn, cn) for normalized sn**2 + cn**2 = 1 and cn >= 0 (always the case
  !> on the core interval [0, K]): am = 2 atan(sn/(1 + cn)) by the half-angle identity,
  !> atan by a polynomial; no libm call (glibc atan2 dominated the cost).
  pure elemental real(wp) function am_from_sn_cn(s, c) result(am)
    real(wp), intent(in) :: s, c
    real(wp) :: as, c1, w, t, t2, t4, p, base, big
    ! x = |s|/(1 + c) in [0, 1]; above tan(pi/8) use atan x = pi/4 + atan((x - 1)/(x + 1)),
    ! formed directly from s and c with a single division
    as = abs(s)
    c1 = 1 + c
    ! merge, not a branch: the test is unpredictable; a real flag, not a logical variable,
    ! which kept gcc from vectorising the loops that inline this
    big = merge(1.0_wp, 0.0_wp, as > tan_pi8*c1)
    w = merge(as - c1, as, big > 0)/merge(as + c1, c1, big > 0)
    base = merge(0.25_wp*pi, 0.0_wp, big > 0)
    t = w*w
    t2 = t*t
    t4 = t2*t2
    p = ((atan_poly(0) + atan_poly(1)*t) + (atan_poly(2) + atan_poly(3)*t)*t2) &
        + ((atan_poly(4) + atan_poly(5)*t) + (atan_poly(6) + atan_poly(7)*t)*t2)*t4 &
        + ((atan_poly(8) + atan_poly(9)*t) + atan_poly(10)*t2)*(t4*t4)
    am = sign(2*(base + (w + w*t*p)), s)
  end function am_from_sn_cn

  !> Core functions at 0 <= t <= K (+ one table step): s, c, d of the core parameter.
  pure subroutine core_sncndn_at(plan, t, s, c, d)
    type(jacobi_param_t), intent(in) :: plan
    real(wp), intent(in) :: t
    real(wp), intent(out) :: s, c, d
    call core_sncndn(plan%m, plan%mc, plan%khi, plan%klo, t, s, c, d)
  end subroutine core_sncndn_at

  !> sn, cn, dn of the core parameter (m, mc, K = khi + klo) at 0 <= t <= K (+ one table step).
  pure subroutine core_sncndn(m, mc, khi, klo, t, s, c, d)
    real(wp), intent(in) :: m, mc, khi, klo, t
    real(wp), intent(out) :: s, c, d
    real(wp) :: w
    if (t > 0.5_wp*khi) then
      ! sn(K - w) = cd(w), cn(K - w) = sqrt(mc) sd(w), dn(K - w) = sqrt(mc) nd(w) (DLMF 22.4.3)
      w = (khi - t) + klo
      call sncndn_duplication(abs(w), m, mc, s, c, d)
      if (w < 0) s = -s
      call reflect_half(mc, s, c, d)
    else
      call sncndn_duplication(t, m, mc, s, c, d)
    end if
  end subroutine core_sncndn

  !> sn, cn, dn at K - w from s, c, d at w (DLMF 22.4.3): sn(K - w) = cd(w),
  !> cn(K - w) = sqrt(mc) sd(w), dn(K - w) = sqrt(mc) nd(w); without branches (a block's
  !> points take it together, unit_block).
  pure elemental subroutine reflect_half(mc, s, c, d)
    real(wp), intent(in) :: mc
    real(wp), intent(inout) :: s, c, d
    real(wp) :: w, w1, w2, rd, sq
    ! one division: rd = 1/(d (d + c)) gives 1/d = rd (d + c) and the cancellation-free
    ! cd = 1 - mc s^2 rd (see cd_ratio)
    rd = 1/(d*(d + c))
    sq = sqrt(mc)
    w = mc*(s*s)*rd
    w1 = 1 - w
    w2 = c*(d + c)*rd
    w = merge(w1, w2, w <= 0.5_wp)
    rd = rd*(d + c)
    c = sq*s*rd
    d = sq*rd
    s = w
  end subroutine reflect_half

  !> The final sn, cn, dn, am of the caller's parameter at core argument t >= 0
  !> (no half-period shift), from the core values by the modulus transformations.
  pure subroutine final_values_at(plan, t, want_am, fs, fc, fd, fa)
    type(jacobi_param_t), intent(in) :: plan
    real(wp), intent(in) :: t
    logical, intent(in) :: want_am
    real(wp), intent(out) :: fs, fc, fd, fa
    real(wp) :: s, c, d
    call core_sncndn_at(plan, t, s, c, d)
    call apply_modulus(plan, s, c, d, want_am, fs, fc, fd, fa)
  end subroutine final_values_at

  !> The modulus transformations from core s, c, d to the caller's sn, cn, dn, am.
  pure subroutine apply_modulus(plan, s, c, d, want_am, fs, fc, fd, fa)
    type(jacobi_param_t), intent(in) :: plan
    real(wp), intent(in) :: s, c, d
    logical, intent(in) :: want_am
    real(wp), intent(out) :: fs, fc, fd, fa
    fa = 0
    select case (plan%kind)
    case (MODULUS_RECIPROCAL)   ! m > 1 (DLMF 22.6.11): sn = sn'/k, cn = dn', dn = cn'; am on the asin branch
      fs = s*plan%oscale; fc = d; fd = c
    case (MODULUS_IMAGINARY)   ! m < 0 (DLMF 22.6.12): sn = k1' sd', cn = cd', dn = nd'
      fs = plan%oscale*s/d
      fc = cd_ratio(s, c, d, plan%mc)
      fd = 1/d
    case default
      fs = s; fc = c; fd = d
    end select
    if (want_am) fa = am_from_sn_cn(fs, fc)
  end subroutine apply_modulus

  !> Taylor coefficients (degree ntay) of the final sn, cn, dn, am about t, from the
  !> ODEs sn' = cn dn, cn' = -sn dn, dn' = -m sn cn of the core (DLMF 22.13).
  pure subroutine taylor_row_at(plan, t, tab)
    type(jacobi_param_t), intent(in) :: plan  !< transformed parameter (jacobi_param)
    real(wp), intent(in) :: t  !< expansion point (core argument)
    real(wp), intent(out) :: tab(0:ntay, 4)  !< Taylor coefficients of sn, cn, dn, am
    real(wp) :: s(0:ntay), c(0:ntay), d(0:ntay), r(0:ntay), fs, fc, fd, fa, acc1, acc2, acc3
    integer :: k, i
    call core_sncndn_at(plan, t, s(0), c(0), d(0))
    do k = 0, ntay - 1
      acc1 = 0; acc2 = 0; acc3 = 0
      do i = 0, k
        acc1 = acc1 + c(i)*d(k - i)
        acc2 = acc2 + s(i)*d(k - i)
        acc3 = acc3 + s(i)*c(k - i)
      end do
      s(k + 1) = acc1/(k + 1)
      c(k + 1) = -acc2/(k + 1)
      d(k + 1) = -plan%m*acc3/(k + 1)
    end do
    call apply_modulus(plan, s(0), c(0), d(0), .true., fs, fc, fd, fa)
    select case (plan%kind)
    case (MODULUS_RECIPROCAL)
      tab(:, 1) = plan%oscale*s
      tab(:, 2) = d
      tab(:, 3) = c
      tab(1:, 4) = plan%oscale*c(0:ntay - 1)/[(real(k, wp), k=1, ntay)]
    case (MODULUS_IMAGINARY)
      r(0) = 1/d(0)
      do k = 1, ntay
        acc1 = 0
        do i = 1, k
          acc1 = acc1 + d(i)*r(k - i)
        end do
        r(k) = -acc1*r(0)
      end do
      do k = 0, ntay
        acc1 = 0; acc2 = 0
        do i = 0, k
          acc1 = acc1 + s(i)*r(k - i)
          acc2 = acc2 + c(i)*r(k - i)
        end do
        tab(k, 1) = plan%oscale*acc1
        tab(k, 2) = acc2
      end do
      tab(:, 3) = r
      tab(1:, 4) = plan%oscale*r(0:ntay - 1)/[(real(k, wp), k=1, ntay)]
    case default
      tab(:, 1) = s
      tab(:, 2) = c
      tab(:, 3) = d
      tab(1:, 4) = d(0:ntay - 1)/[(real(k, wp), k=1, ntay)]
    end select
    ! the values themselves from the accurate path (cancellation-free cd etc.)
    tab(0, 1) = fs; tab(0, 2) = fc; tab(0, 3) = fd; tab(0, 4) = fa
  end subroutine taylor_row_at

  !> sn, cn, dn, am at u for a transformed parameter: reduction modulo 2K (K in
  !> double-double when exact_k, else refined to it for |u| > 9 K), then the table
  !> (if given) or the duplication kernel, then the modulus transformation.
  pure subroutine eval_at_param(plan, u, exact_k, want_am, sn, cn, dn, am, tab, ntab)
    type(jacobi_param_t), intent(in) :: plan  !< transformed parameter (jacobi_param)
    real(wp), intent(in), optional :: tab(0:, :, 0:)  !< Taylor table of the plan
    integer, intent(in), optional :: ntab  !< last row of the table
    real(wp), intent(in) :: u  !< argument u (real, any value)
    logical, intent(in) :: exact_k  !< true: K in double-double for the reduction
    logical, intent(in) :: want_am  !< whether am is computed
    real(wp), intent(out) :: sn  !< sn(u|m)
    real(wp), intent(out) :: cn  !< cn(u|m)
    real(wp), intent(out) :: dn  !< dn(u|m)
    real(wp), intent(out) :: am  !< am(u|m) [rad] (when want_am)
    real(wp) :: v, vl, n, khi, klo, p, e, r, t, ex, fs, fc, fd, fa, del
    integer :: j, parity
    if (plan%kind == MODULUS_INVALID .or. ieee_is_nan(u)) then
      sn = quiet_nan(); cn = sn; dn = sn; am = sn
      return
    end if
    if (plan%kind == MODULUS_ONE) then
      ! m = 1: sn = tanh, cn = dn = sech, am = gd(u)
      sn = tanh(u)
      if (abs(u) < 20) then
        cn = 1/cosh(u)
      else
        ex = exp(-abs(u))      ! sech without overflow, subnormal tail kept
        cn = 2*ex/(1 + ex*ex)
      end if
      dn = cn
      am = 0
      if (want_am) am = am_from_sn_cn(sn, cn)
      return
    end if
    if (.not. ieee_is_finite(u)) then
      sn = quiet_nan(); cn = sn; dn = sn; am = sn
      return
    end if
    ! |u| * uscale may exceed huge(): test before multiplying (an overflowing
    ! product would raise the overflow flag, which the checked build traps)
    if (plan%uscale > 1) then
      v = huge(v)
      if (abs(u) <= huge(v)/plan%uscale) v = abs(u)*plan%uscale
    else
      v = abs(u)*plan%uscale
    end if
    khi = plan%khi; klo = plan%klo
    n = 0
    parity = 0
    r = v
    if (v == huge(v)) then
      ! |u| sqrt(|m|) or |u| sqrt(1 - m) overflows (|m| > ~1e300, |u| > ~1e150): the
      ! phase u mod 2K is far below the resolution of u (the condition number is ~ |u|
      ! sqrt|m| there), so any point of the period is within eps*cond; take r = 0
      r = 0
    else if (v > khi) then
      ! u * scale and n * 2K both in extra precision: large u keeps its digits
      vl = 0
      if (plan%kind /= MODULUS_CORE) then
        call two_prod(abs(u), plan%uscale, v, vl)
        vl = vl + abs(u)*plan%uscale_lo
      end if
      n = anint(v/(2*khi))
      if (.not. exact_k .and. n > 4) then
        call k_double_double(plan%mc, plan%mcl, khi, klo)
        n = anint(v/(2*khi))
      end if
      if (n < 2.0_wp**26) then
        ! Cody-Waite: 2K = c1 + c2 + 2 klo with c1, c2 of 26 bits, so n*c1, n*c2 are exact
        call veltkamp_split(2*khi, p, e)
        r = (((v - n*p) - n*e) + vl) - n*(2*klo)
      else
        call two_prod(n, 2*khi, p, e)
        r = (((v - p) - e) + vl) - n*(2*klo)
      end if
      if (n < 1.0e15_wp) then
        parity = int(mod(int(n, kind=8), 2_8))
      else
        parity = merge(1, 0, mod(n, 2.0_wp) /= 0)
      end if
    end if
    if (.not. (abs(r) <= 1.5_wp*khi)) then
      ! only when n*2K outruns the double-double K (|u| > ~1e15 K): the phase is then
      ! below the resolution of u itself (error within eps*cond); keep r in range
      r = modulo(r, 2*khi)
      if (r > khi) r = r - 2*khi
      if (.not. (abs(r) <= 1.5_wp*khi)) r = 0
    end if
    t = abs(r)
    if (present(tab)) then
      j = tab_index(t, ntab)
      del = t - j*tab_step
      fs = estrin8(tab(:, 1, j), del)
      fc = estrin8(tab(:, 2, j), del)
      fd = estrin8(tab(:, 3, j), del)
      fa = 0
      if (want_am) fa = estrin8(tab(:, 4, j), del)
    else
      call final_values_at(plan, t, want_am, fs, fc, fd, fa)
    end if
    fs = sign(fs, r)
    fa = sign(fa, r)
    if (parity /= 0) then
      select case (plan%kind)
      case (MODULUS_RECIPROCAL)
        fs = -fs; fd = -fd; fa = -fa
      case default
        fs = -fs; fc = -fc
      end select
    end if
    if (plan%kind /= MODULUS_RECIPROCAL) fa = fa + n*pi
    if (u < 0) then
      fs = -fs
      fa = -fa
    end if
    sn = fs; cn = fc; dn = fd; am = fa
  end subroutine eval_at_param

  !> The loop of ellipj_array (m1 = .false.: x is m) and ellipjm1_array (m1 = .true.: x is
  !> mc = 1 - m): sn, cn, dn and, if want_am, am at the points (u(i), x(i)).  Blocks of
  !> jblock points go through unit_block; the few it leaves (m outside [0, 1), NaN, Inf,
  !> |u| beyond 2**26 half periods) through the general path, point by point.
  pure subroutine ellipj_points(n, u, x, m1, want_am, sn, cn, dn, am)
    integer, intent(in) :: n  !< number of points
    real(wp), intent(in) :: u(n)  !< arguments u, n elements
    real(wp), intent(in) :: x(n)  !< parameters m (m1 false) or mc = 1 - m (m1 true), n elements
    logical, intent(in) :: m1  !< whether x holds mc = 1 - m
    logical, intent(in) :: want_am  !< whether am is computed
    real(wp), intent(out) :: sn(n)  !< sn at each point
    real(wp), intent(out) :: cn(n)  !< cn at each point
    real(wp), intent(out) :: dn(n)  !< dn at each point
    real(wp), intent(inout) :: am(*)  !< am [rad] at each point (written when want_am)
    logical :: done(jblock)
    integer :: i, i0, nb
    real(wp) :: a
    do i0 = 1, n, jblock
      nb = min(jblock, n - i0 + 1)
      if (want_am) then
        call unit_block(nb, u(i0:), x(i0:), m1, .true., sn(i0:), cn(i0:), dn(i0:), am(i0), done)
      else
        call unit_block(nb, u(i0:), x(i0:), m1, .false., sn(i0:), cn(i0:), dn(i0:), sn(i0:), done)
      end if
      if (all(done(1:nb))) cycle
      do i = i0, i0 + nb - 1
        if (done(i - i0 + 1)) cycle
        call general_point(u(i), x(i), m1, want_am, sn(i), cn(i), dn(i), a)
        if (want_am) am(i) = a
      end do
    end do
  end subroutine ellipj_points

  !> One point of ellipj (m1 false: x is m) or ellipjm1 (m1 true: x is mc): unit_block's
  !> path when it takes the point, else the general one; the same numbers as ellipj_points.
  pure subroutine ellipj_point(u, x, m1, want_am, sn, cn, dn, am)
    real(wp), intent(in) :: u  !< argument u (any real)
    real(wp), intent(in) :: x  !< parameter m (m1 false) or mc = 1 - m (m1 true), any real
    logical, intent(in) :: m1  !< whether x holds mc
    logical, intent(in) :: want_am  !< whether am is computed
    real(wp), intent(out) :: sn  !< sn(u|m)
    real(wp), intent(out) :: cn  !< cn(u|m)
    real(wp), intent(out) :: dn  !< dn(u|m)
    real(wp), intent(out) :: am  !< am(u|m) [rad] (when want_am, else 0)
    real(wp) :: s(1), c(1), d(1), a(1)
    logical :: done(1)
    a = 0
    call unit_block(1, [u], [x], m1, want_am, s, c, d, a, done)
    if (done(1)) then
      sn = s(1); cn = c(1); dn = d(1); am = a(1)
    else
      call general_point(u, x, m1, want_am, sn, cn, dn, am)
    end if
  end subroutine ellipj_point

  !> The general path of one point (any real u, m): the modulus transformation
  !> (jacobi_param; mc exact when m1) and eval_at_param with K refined as needed.
  pure subroutine general_point(u, x, m1, want_am, sn, cn, dn, am)
    real(wp), intent(in) :: u, x
    logical, intent(in) :: m1, want_am
    real(wp), intent(out) :: sn, cn, dn, am
    if (m1) then
      call eval_at_param(jacobi_param(1 - x, x, .true., .false.), u, .false., want_am, sn, cn, dn, am)
    else
      call eval_at_param(jacobi_param(x, 1 - x, .false., .false.), u, .false., want_am, sn, cn, dn, am)
    end if
    if (.not. want_am) am = 0
  end subroutine general_point

  !> ellipj for 0 <= m < 1 and |u| < 2**26 K (the common case) on a block of nb <= jblock
  !> points, done(j) = .false. for a point left to the general path (m outside [0, 1) or
  !> (0, 1] for mc, NaN, |u| beyond 2**26 half periods or infinite; its outputs are then
  !> placeholders).  The steps of jacobi_param + eval_at_param, in passes over the block so
  !> that the branch-free ones vectorise: (1) K, the half periods n and the residue r
  !> (K's interval and logarithmic forms branch); (2) the series coefficients and the
  !> Maclaurin start at the core argument; (3) the duplications, whose step counts depend
  !> on the point; (4) the reflection about K/2, the signs and am.  Beyond |u| ~ 9 K the
  !> reduction takes K in double-double (k_double_double, a compensated AGM), as
  !> eval_at_param does.  With m1, x is mc = 1 - m, exact (the low part of 1 - m is then 0,
  !> as jacobi_param takes it when usemc); else x is m and mc = fl(1 - m) with low part
  !> (1 - mc) - m.
  pure subroutine unit_block(nb, u, x, m1, want_am, sn, cn, dn, am, done)
    integer, intent(in) :: nb
    real(wp), intent(in) :: u(nb), x(nb)
    logical, intent(in) :: m1, want_am
    real(wp), intent(out) :: sn(nb), cn(nb), dn(nb)
    real(wp), intent(inout) :: am(nb)
    logical, intent(out) :: done(nb)
    real(wp), parameter :: nmax = 2.0_wp**26   ! n c1, n c2 exact below (Cody-Waite)
    real(wp), dimension(jblock) :: m, mc, k, hn, r, w, aw, su, s, c, d, mch, mcl, kh, kl
    integer :: j
    real(wp) :: v, c1, c2, t, ps, half
    logical :: ok, need(jblock)
    type(status_t) :: status
    ! (1) the domain; a point left to the general path gets the harmless core point m = 0,
    ! r = 0 for the passes below (no NaN or overflow reaches them)
    do j = 1, nb
      ok = .not. (ieee_is_nan(x(j)) .or. ieee_is_nan(u(j)))
      if (ok) then
        if (m1) then
          ok = x(j) > 0 .and. x(j) <= 1
        else
          ok = x(j) >= 0 .and. x(j) < 1
        end if
      end if
      if (m1) then
        mc(j) = merge(x(j), 1.0_wp, ok); m(j) = 1 - mc(j)
      else
        m(j) = merge(x(j), 0.0_wp, ok); mc(j) = 1 - m(j)
      end if
      done(j) = ok
    end do
    ! K of the block: the array forms give k_unit(m, mc) (their logarithmic forms gathered
    ! into one vectorised loop)
    if (m1) then
      call ellipkm1_array(mc(1:nb), k(1:nb), status)
    else
      call ellipk_array(m(1:nb), k(1:nb), status)
    end if
    ! the half periods n and the residue r; beyond 4 half periods n 2K takes K in
    ! double-double, for the block's points at once (k_double_double_block) after this pass
    do j = 1, nb
      hn(j) = 0; r(j) = 0; su(j) = 1; need(j) = .false.; mch(j) = 1; mcl(j) = 0
      if (.not. done(j)) cycle
      v = abs(u(j))
      ! no branch on v > K: n = 0 leaves r = v exactly (random u makes that test unpredictable)
      hn(j) = anint(v/(2*k(j)))
      if (hn(j) <= 4) then
        call veltkamp_split(2*k(j), c1, c2)
        r(j) = (v - hn(j)*c1) - hn(j)*c2
      else if (hn(j) < nmax) then
        ! 1 - m exact as mc + mcl
        need(j) = .true.
        mch(j) = mc(j)
        if (.not. m1) mcl(j) = (1 - mc(j)) - m(j)
      else
        ! beyond 2**26 half periods, or u = +-Inf
        done(j) = .false.
        m(j) = 0; mc(j) = 1; hn(j) = 0; r(j) = 0
        cycle
      end if
      su(j) = merge(-1.0_wp, 1.0_wp, u(j) < 0)
    end do
    if (any(need(1:nb))) then
      call k_double_double_block(nb, mch, mcl, kh, kl)
      do j = 1, nb
        if (.not. need(j)) cycle
        ! n 2K with K in double-double: large u keeps its digits
        v = abs(u(j))
        hn(j) = anint(v/(2*kh(j)))
        call veltkamp_split(2*kh(j), c1, c2)
        r(j) = ((v - hn(j)*c1) - hn(j)*c2) - hn(j)*(2*kl(j))
      end do
    end if
    ! (2) the core argument t <= K/2 or K - t (DLMF 22.4.3) and its Maclaurin start
    do j = 1, nb
      t = abs(r(j))
      w(j) = merge(k(j) - t, t, t > 0.5_wp*k(j))
      aw(j) = abs(w(j))
    end do
    ! and (3) the duplications: the block kernel of the running path (pendula_jacobi_lanes.F90)
    call core_block_lanes(int(nb, c_int), aw, m, mc, s, c, d)
    ! (4) back from K - w, the signs by merge (blends, not branches: the parity of n and the
    ! sign of u are random) and am
    do j = 1, nb
      ! half: 1 where the point was reflected (a real flag: see am_from_sn_cn)
      half = merge(1.0_wp, 0.0_wp, abs(r(j)) > 0.5_wp*k(j))
      t = merge(-s(j), s(j), w(j) < 0); v = c(j); c1 = d(j)
      call reflect_half(mc(j), t, v, c1)
      s(j) = merge(t, s(j), half > 0); c(j) = merge(v, c(j), half > 0); d(j) = merge(c1, d(j), half > 0)
    end do
    if (want_am) then
      do j = 1, nb
        am(j) = (sign(am_from_sn_cn(s(j), c(j)), r(j)) + hn(j)*pi)*su(j)
      end do
    end if
    do j = 1, nb
      ps = merge(-1.0_wp, 1.0_wp, iand(int(hn(j)), 1) /= 0)
      sn(j) = sign(s(j), r(j))*(ps*su(j)); cn(j) = c(j)*ps; dn(j) = d(j)
    end do
  end subroutine unit_block

  !> Table row 0..ntab nearest to the core argument t >= 0; t beyond the table or NaN
  !> gives ntab (the compare comes before int(), so no NaN or huge value is converted).
  pure elemental integer function tab_index(t, ntab) result(j)
    real(wp), intent(in) :: t
    integer, intent(in) :: ntab
    real(wp) :: x
    x = t*tab_inv_step + 0.5_wp
    if (x >= 0 .and. x < ntab) then
      j = int(x)
    else if (x >= 0) then
      j = ntab
    else
      j = 0
    end if
  end function tab_index

  !> Degree-ntay (8) polynomial p at x by Estrin's scheme.
  pure real(wp) function estrin8(p, x) result(y)
    real(wp), intent(in) :: p(0:ntay), x
    real(wp) :: x2, x4
    x2 = x*x
    x4 = x2*x2
    y = ((p(0) + p(1)*x) + (p(2) + p(3)*x)*x2) + ((p(4) + p(5)*x) + (p(6) + p(7)*x)*x2)*x4 &
        + p(8)*(x4*x4)
  end function estrin8

  !> The loop of ellipj_eval_array for tabulated plans (here, next to the polynomial and
  !> index helpers, so that the compiler inlines them).  Points the fast reduction
  !> cannot take (NaN, Inf, n >= 2**26 half periods) go through eval_at_param.
  pure subroutine eval_table_array(par, tab, ntab, n, u, want_am, sn, cn, dn, am)
    type(jacobi_param_t), intent(in) :: par  !< transformed parameter (jacobi_param)
    integer, intent(in) :: ntab  !< last row of the table
    integer, intent(in) :: n  !< number of points
    real(wp), intent(in) :: tab(0:ntay, 4, 0:ntab)  !< Taylor table of the plan
    real(wp), intent(in) :: u(n)  !< arguments u, n elements
    logical, intent(in) :: want_am  !< whether am is computed
    real(wp), intent(out) :: sn(n)  !< sn at each point
    real(wp), intent(out) :: cn(n)  !< cn at each point
    real(wp), intent(out) :: dn(n)  !< dn at each point
    real(wp), intent(inout) :: am(*)  !< am [rad] at each point (written when want_am)
    real(wp) :: c1, c2, c3, inv2k, vmax, v, vl, q, r, t, del, fs, fc, fd, fa, a
    integer :: i, j, parity
    logical :: big
    call veltkamp_split(2*par%khi, c1, c2)
    c3 = 2*par%klo
    inv2k = 1/(2*par%khi)
    vmax = 2.0_wp**25*(2*par%khi)
    do i = 1, n
      v = abs(u(i))*par%uscale
      big = ieee_is_nan(v)
      if (.not. big) big = v >= vmax
      if (big) then
        call eval_at_param(par, u(i), .true., want_am, sn(i), cn(i), dn(i), a, tab, ntab)
        if (want_am) am(i) = a
        cycle
      end if
      vl = 0
      if (par%kind /= MODULUS_CORE) then
        call two_prod(abs(u(i)), par%uscale, v, vl)
        vl = vl + abs(u(i))*par%uscale_lo
      end if
      q = anint(v*inv2k)
      r = (((v - q*c1) - q*c2) + vl) - q*c3
      t = abs(r)
      j = tab_index(t, ntab)
      del = t - j*tab_step
      fs = sign(estrin8(tab(:, 1, j), del), r)
      fc = estrin8(tab(:, 2, j), del)
      fd = estrin8(tab(:, 3, j), del)
      parity = iand(int(q), 1)
      if (par%kind == MODULUS_RECIPROCAL) then
        if (parity /= 0) then
          fs = -fs; fd = -fd
        end if
      else if (parity /= 0) then
        fs = -fs; fc = -fc
      end if
      if (u(i) < 0) fs = -fs
      sn(i) = fs; cn(i) = fc; dn(i) = fd
      if (want_am) then
        fa = sign(estrin8(tab(:, 4, j), del), r)
        if (par%kind == MODULUS_RECIPROCAL) then
          if (parity /= 0) fa = -fa
        else
          fa = fa + q*pi
        end if
        if (u(i) < 0) fa = -fa
        am(i) = fa
      end if
    end do
  end subroutine eval_table_array

  ! series_coeffs, generated (tools/gen/gen_elliptic_tables.py); included here so that the
  ! compiler inlines it into the short path (no inlining across modules without LTO)
  include 'pendula_jacobi_series.inc'

  ! maclaurin_start, duplication_steps and core_block: the scalar paths run them here
  ! (baseline code); unit_block calls the variant the runtime dispatch chose
  ! (core_block_lanes, pendula_jacobi_lanes.F90), compiled from this same text.
  include 'pendula_jacobi_core_block.inc'

end module pendula_jacobi_kernel
