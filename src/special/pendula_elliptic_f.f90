!> Incomplete elliptic integral of the first kind F(phi|m) for any real phi and m with
!> m sin^2(phi) <= 1: Carlson's R_F by duplication (DLMF 19.36.1, Carlson 1995) on the
!> residue of phi modulo pi, F(phi + n pi) = F(phi) + 2 n K with n pi subtracted in
!> double-double.  Measured <= 3.4 ulps against mpmath.
module pendula_elliptic_f
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_is_nan, ieee_is_finite
  use pendula_kinds, only: wp
  use pendula_constants, only: pi, pi_lo, pi_lo2, half_pi, half_pi_lo, quiet_nan
  use pendula_double_double, only: two_sum, two_prod, dd_div
  use pendula_elliptic_modulus, only: jacobi_param_t, jacobi_param, MODULUS_INVALID, MODULUS_CORE, MODULUS_ONE
  implicit none
  private

  public :: ellipf, ellipfm1, carlson_rf

contains

  !> Carlson's symmetric integral R_F(x, y, z), x, y, z >= 0, at most one zero
  !> (DLMF 19.36.1 with the 7th-order series of Carlson 1995).
  pure elemental real(wp) function carlson_rf(x0, y0, z0) result(rf)
    real(wp), intent(in) :: x0  !< first argument of R_F, >= 0
    real(wp), intent(in) :: y0  !< second argument of R_F, >= 0
    real(wp), intent(in) :: z0  !< third argument of R_F, >= 0 (at most one of them zero)
    real(wp) :: x, y, z, a, lam, sx, sy, sz, dx, dy, dz
    integer :: i
    x = x0; y = y0; z = z0
    ! the series below is exact through degree 7 in the deviations, so stopping at
    ! |dev| <= 5e-3 leaves a truncation ~ (5e-3)**8 ~ 4e-19 (Carlson 1995, DLMF 19.36.1)
    do i = 1, 200
      a = (x + y + z)*(1.0_wp/3)
      dx = (a - x); dy = (a - y); dz = (a - z)
      if (max(abs(dx), abs(dy), abs(dz)) <= 5.0e-3_wp*a) exit
      sx = sqrt(x); sy = sqrt(y); sz = sqrt(z)
      lam = sx*(sy + sz) + sy*sz
      x = 0.25_wp*(x + lam); y = 0.25_wp*(y + lam); z = 0.25_wp*(z + lam)
    end do
    rf = rf_series(a, dx, dy)
  end function carlson_rf

  !> R_F(c^2, d2, 1) as carlson_rf, with the first step's square roots of c^2 and 1 known
  !> (|c| and 1, exact; one square root instead of three there).  F's integral.
  pure elemental real(wp) function rf_c2_d2_1(c, d2) result(rf)
    real(wp), intent(in) :: c, d2
    real(wp) :: x, y, z, a, lam, sx, sy, sz, dx, dy, dz
    integer :: i
    x = c*c; y = d2; z = 1
    sx = abs(c); sz = 1
    do i = 1, 200
      a = (x + y + z)*(1.0_wp/3)
      dx = (a - x); dy = (a - y); dz = (a - z)
      if (max(abs(dx), abs(dy), abs(dz)) <= 5.0e-3_wp*a) exit
      if (i > 1) then
        sx = sqrt(x); sz = sqrt(z)
      end if
      sy = sqrt(y)
      lam = sx*(sy + sz) + sy*sz
      x = 0.25_wp*(x + lam); y = 0.25_wp*(y + lam); z = 0.25_wp*(z + lam)
    end do
    rf = rf_series(a, dx, dy)
  end function rf_c2_d2_1

  !> The end of carlson_rf: Carlson's series at the mean a of x, y, z (deviations
  !> dx = a - x, dy = a - y).  The coefficients as products with their reciprocals: the
  !> terms are below 1e-5 of the sum, so their roundings do not reach it, and six
  !> divisions were a fifth of the cost.
  pure elemental real(wp) function rf_series(a, dx0, dy0) result(rf)
    real(wp), intent(in) :: a, dx0, dy0
    real(wp), parameter :: c10 = 1/10.0_wp, c14 = 1/14.0_wp, c24 = 1/24.0_wp, c44 = 3/44.0_wp, &
                           c208 = 5/208.0_wp, c104 = 3/104.0_wp, c16 = 1/16.0_wp
    real(wp) :: dx, dy, dz, e2, e3, ra
    ra = 1/a
    dx = dx0*ra; dy = dy0*ra; dz = -(dx + dy)
    e2 = dx*dy - dz*dz
    e3 = dx*dy*dz
    rf = (1 - e2*c10 + e3*c14 + e2*e2*c24 - e2*e3*c44 - e2**3*c208 &
          + e3*e3*c104 + e2*e2*e3*c16)/sqrt(a)
  end function rf_series

  !> (rh, rl) = (xh + xl) - n pi as a double-double, pi in three parts (pi, pi_lo, pi_lo2);
  !> n*pi and n*pi_lo are exact products, so the residue is right to ~1e-32 |r| + n 1e-49.
  pure subroutine subtract_n_pi(xh, xl, n, rh, rl)
    real(wp), intent(in) :: xh, xl, n
    real(wp), intent(out) :: rh, rl
    real(wp) :: p, e, q, f, a, b, t1, t2
    call two_prod(n, pi, p, e)
    call two_prod(n, pi_lo, q, f)
    call two_sum(xh, -p, a, t1)         ! exact (Sterbenz) when n pi is within 2x of x
    call two_sum(a, -q, b, t2)
    call two_sum(b, (((t1 + t2) - e) - f) + (xl - n*pi_lo2), rh, rl)
  end subroutine subtract_n_pi

  !> Reduce phi to r = rh + rl in [-pi/2, pi/2] with phi = (n1 + n2) pi + r exactly up
  !> to double-double rounding.  The rounded quotient anint(phi/pi) misses by one when
  !> phi is the double nearest an odd multiple of pi/2 (fl(pi/2)/fl(pi) = 0.5 exactly
  !> rounds up) and by many when |phi| > 2**53 pi (n not representable); further
  !> multiples, decided on the double-double residue, correct both (one step, or up to
  !> ~20 for |phi| near huge(), where each step removes ~52 bits).
  pure elemental subroutine reduce_pi(phi, n1, n2, rh, rl)
    real(wp), intent(in) :: phi
    real(wp), intent(out) :: n1, n2, rh, rl
    real(wp) :: q, xh, xl
    integer :: i
    n1 = anint(phi/pi)
    if (abs(phi) > 2.0_wp**1022) n1 = anint(0.5_wp*(phi/pi))   ! n1*pi must not overflow
    n2 = 0
    if (n1 == 0) then
      rh = phi; rl = 0
    else
      call subtract_n_pi(phi, 0.0_wp, n1, rh, rl)
    end if
    do i = 1, 40
      if (abs(rh) < 1.5_wp) exit                   ! cheap screen: pi/2 = 1.5708
      if (half_pi_minus(rh, rl) >= 0) exit
      q = anint(rh/pi)
      if (q == 0) q = sign(1.0_wp, rh)
      xh = rh; xl = rl
      call subtract_n_pi(xh, xl, q, rh, rl)
      n2 = n2 + q
    end do
  end subroutine reduce_pi

  !> pi/2 - |rh + rl| for a double-double; exact first difference for |rh| >= pi/4.
  pure elemental real(wp) function half_pi_minus(rh, rl) result(w)
    real(wp), intent(in) :: rh, rl
    w = (half_pi - abs(rh)) + (half_pi_lo - sign(1.0_wp, rh)*rl)
  end function half_pi_minus

  !> Incomplete elliptic integral of the first kind F(phi|m) for any real phi (rad)
  !> and any real m with m sin^2(phi) <= 1 (including m > 1; there, like K, the
  !> quasi-period uses Re K(m) = K(1/m)/sqrt(m)); NaN outside or for NaN input.
  !> F(phi + n pi) = F(phi) + 2 n K(m).  A few ulps (Carlson R_F).
  elemental real(wp) function ellipf(phi, m) result(f)
    real(wp), intent(in) :: phi  !< amplitude phi [rad], any real
    real(wp), intent(in) :: m  !< parameter m = k**2, m sin^2(phi) <= 1
    f = ellipf_general(phi, m, 1 - m, .false.)
  end function ellipf

  !> F(phi|m) with the complementary parameter mc = 1 - m (accurate near m = 1).
  elemental real(wp) function ellipfm1(phi, mc) result(f)
    real(wp), intent(in) :: phi  !< amplitude phi [rad], any real
    real(wp), intent(in) :: mc  !< complementary parameter mc = 1 - m
    f = ellipf_general(phi, 1 - mc, mc, .true.)
  end function ellipfm1

  !> F for m given with its complement mc (usemc: mc is the accurate one).
  pure elemental real(wp) function ellipf_general(phi, m, mc, usemc) result(f)
    real(wp), intent(in) :: phi, m, mc
    logical, intent(in) :: usemc
    real(wp) :: n1, n2, rh, rl, s, c, w, d2, kh, kl, p, e, p2, e2, t, ps
    type(jacobi_param_t) :: par
    if (ieee_is_nan(phi) .or. ieee_is_nan(m) .or. ieee_is_nan(mc)) then
      f = quiet_nan(); return
    end if
    if (.not. ieee_is_finite(phi)) then
      if (m <= 1 .and. (mc > 0 .or. .not. usemc .and. m < 1)) then
        f = phi           ! F grows linearly in phi without bound
      else
        f = quiet_nan()
      end if
      return
    end if
    call reduce_pi(phi, n1, n2, rh, rl)
    ! sin and cos of the double-double residue; near +-pi/2 cos r = sin(pi/2 - |r|) from
    ! the exact difference, so cos keeps its relative accuracy down to the 6e-17 of fl(pi/2)
    if (abs(rh) <= 0.79_wp) then
      s = sin(rh); c = cos(rh)
      s = s + c*rl
    else
      w = half_pi_minus(rh, rl)
      s = sign(cos(w), rh); c = sin(w)
    end if
    ! 1 - m sin^2 = cos^2 + mc sin^2: no cancellation near m = 1 (mc = 1 - m is exact for
    ! m in [0.5, 2], and for other m the sum does not cancel or cancels as 1 - m sin^2 does)
    d2 = c*c + mc*(s*s)
    if (d2 < 0 .or. ieee_is_nan(d2)) then
      f = quiet_nan(); return
    end if
    if (d2 == 0 .and. c == 0) then
      f = sign(ieee_value(1.0_wp, ieee_positive_inf), s)
    else if (s == 0) then
      f = rh
    else
      f = s*rf_c2_d2_1(c, d2)
    end if
    if (n1 /= 0 .or. n2 /= 0) then
      ! F + 2 n K with K in double-double: the sum may cancel (phi in (-pi, -pi/2) etc.)
      par = jacobi_param(m, mc, usemc, .true.)
      if (par%kind == MODULUS_ONE) then
        if (n1 + n2 /= 0) f = f + sign(ieee_value(1.0_wp, ieee_positive_inf), n1 + n2)
      else if (par%kind == MODULUS_INVALID) then
        f = quiet_nan()
      else
        kh = par%khi; kl = par%klo
        if (par%kind /= MODULUS_CORE) then
          ! Re K(m) = K(core)/k for m > 1 (DLMF 19.7.3); K(m) = K(mu)/sqrt(1-m) for m < 0
          call dd_div(par%khi, par%klo, par%uscale, par%uscale_lo, kh, kl)
        end if
        if (beyond_half_huge(abs(n1 + n2), kh)) then
          ! |F| = 2 |n| K + O(K) > huge (|phi| near huge): +-Inf, the rounded value, formed
          ! without an overflowing operation (the checked build traps overflow)
          f = sign(ieee_value(1.0_wp, ieee_positive_inf), n1 + n2)
          return
        end if
        call two_prod(2*n1, kh, p, e)
        e = e + 2*n1*kl
        if (n2 /= 0) then
          call two_prod(2*n2, kh, p2, e2)
          call two_sum(p, p2, ps, t)
          p = ps
          e = e + (t + (e2 + 2*n2*kl))
        end if
        f = p + (f + e)
      end if
    end if
  end function ellipf_general

  !> a * b >= huge/2 for a, b >= 0, decided without an operation that can
  !> overflow or divide by zero (huge/b overflows for b < 1).
  pure elemental logical function beyond_half_huge(a, b) result(beyond)
    real(wp), intent(in) :: a, b
    if (a == 0 .or. b == 0) then
      beyond = .false.
    else if (exponent(a) + exponent(b) > maxexponent(b) + 1) then
      beyond = .true.
    else
      beyond = scale(a, -8)*b >= scale(0.5_wp*huge(b), -8)
    end if
  end function beyond_half_huge

end module pendula_elliptic_f
