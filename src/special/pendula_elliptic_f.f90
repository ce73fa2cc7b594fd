!> Incomplete elliptic integral of the first kind F(phi|m) for any real phi and m with
!> m sin^2(phi) <= 1: Carlson's R_F by duplication (DLMF 19.36.1, Carlson 1995) on the
!> residue of phi modulo pi, F(phi + n pi) = F(phi) + 2 n K with n pi subtracted in
!> double-double.  Measured <= 3.4 ulps against mpmath.
module pendula_elliptic_f
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_is_nan, ieee_is_finite
  use pendula_kinds, only: wp
  use pendula_constants, only: pi, pi_lo, pi_lo2, half_pi, half_pi_lo, quiet_nan
  use pendula_double_double, only: two_sum, two_prod, dd_div
  use pendula_status, only: status_t, set_error, PENDULA_ERR_SIZE
  use pendula_elliptic_modulus, only: jacobi_param_t, jacobi_param, MODULUS_INVALID, MODULUS_CORE, MODULUS_ONE
  implicit none
  private

  public :: ellipf, ellipfm1, ellipf_array, ellipfm1_array, carlson_rf

  !> Points per block of the array loop (f_points, rf_block).
  integer, parameter :: fblock = 64

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
    rf = (1 - e2*c10 + e3*c14 + e2*e2*c24 - e2*e3*c44 - (e2*e2)*e2*c208 &
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
    real(wp) :: n1, n2, s, c, d2, rf(1)
    logical :: need_rf, final
    call f_start(phi, m, mc, usemc, n1, n2, s, c, d2, f, need_rf, final)
    if (final) return
    if (need_rf) then
      call rf_block(1, [c], [d2], rf)
      f = s*rf(1)
    end if
    if (n1 /= 0 .or. n2 /= 0) f = add_periods(f, n1, n2, m, mc, usemc)
  end function ellipf_general

  !> The start of F: phi reduced to r in [-pi/2, pi/2] (phi = (n1 + n2) pi + r), s = sin r,
  !> c = cos r and d2 = 1 - m s^2.  need_rf: F(r) = s R_F(c^2, d2, 1), else f holds F(r);
  !> final: f is F(phi) itself (NaN in or out of the domain, phi infinite).
  pure elemental subroutine f_start(phi, m, mc, usemc, n1, n2, s, c, d2, f, need_rf, final)
    real(wp), intent(in) :: phi, m, mc
    logical, intent(in) :: usemc
    real(wp), intent(out) :: n1, n2, s, c, d2, f
    logical, intent(out) :: need_rf, final
    real(wp) :: rh, rl, w
    n1 = 0; n2 = 0; s = 0; c = 1; d2 = 1
    need_rf = .false.
    final = .true.
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
    final = .false.
    f = 0
    if (d2 == 0 .and. c == 0) then
      f = sign(ieee_value(1.0_wp, ieee_positive_inf), s)
    else if (s == 0) then
      f = rh
    else
      need_rf = .true.
    end if
  end subroutine f_start

  !> F(phi) = F(r) + 2 (n1 + n2) K(m) with K in double-double (the sum may cancel: phi in
  !> (-pi, -pi/2) etc.); f = F(r).
  pure elemental real(wp) function add_periods(f, n1, n2, m, mc, usemc) result(g)
    real(wp), intent(in) :: f, n1, n2, m, mc
    logical, intent(in) :: usemc
    real(wp) :: kh, kl, p, e, p2, e2, t, ps
    type(jacobi_param_t) :: par
    g = f
    par = jacobi_param(m, mc, usemc, .true.)
    if (par%kind == MODULUS_ONE) then
      if (n1 + n2 /= 0) g = f + sign(ieee_value(1.0_wp, ieee_positive_inf), n1 + n2)
    else if (par%kind == MODULUS_INVALID) then
      g = quiet_nan()
    else
      kh = par%khi; kl = par%klo
      if (par%kind /= MODULUS_CORE) then
        ! Re K(m) = K(core)/k for m > 1 (DLMF 19.7.3); K(m) = K(mu)/sqrt(1-m) for m < 0
        call dd_div(par%khi, par%klo, par%uscale, par%uscale_lo, kh, kl)
      end if
      if (beyond_half_huge(abs(n1 + n2), kh)) then
        ! |F| = 2 |n| K + O(K) > huge (|phi| near huge): +-Inf, the rounded value, formed
        ! without an overflowing operation (the checked build traps overflow)
        g = sign(ieee_value(1.0_wp, ieee_positive_inf), n1 + n2)
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
      g = p + (f + e)
    end if
  end function add_periods

  !> ellipf over rank-1 arrays phi, m of one size (f of that size): the same numbers as
  !> the elemental function.  A size mismatch sets status (PENDULA_ERR_SIZE) and f = NaN.
  pure subroutine ellipf_array(phi, m, f, status)
    real(wp), intent(in) :: phi(:)  !< amplitudes phi [rad]
    real(wp), intent(in) :: m(:)  !< parameters m = k**2, size(phi) elements
    real(wp), intent(out) :: f(:)  !< F(phi(i)|m(i)), size(phi) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    if (size(m) /= size(phi) .or. size(f) /= size(phi)) then
      f = quiet_nan()
      call set_error(status, PENDULA_ERR_SIZE, 'ellipf_array: m and f must have the size of phi')
      return
    end if
    call f_points(size(phi), phi, m, .false., f)
  end subroutine ellipf_array

  !> ellipfm1 over rank-1 arrays (same numbers as the elemental function); sizes as
  !> ellipf_array.
  pure subroutine ellipfm1_array(phi, mc, f, status)
    real(wp), intent(in) :: phi(:)  !< amplitudes phi [rad]
    real(wp), intent(in) :: mc(:)  !< complementary parameters mc = 1 - m, size(phi) elements
    real(wp), intent(out) :: f(:)  !< F(phi(i)|1 - mc(i)), size(phi) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    if (size(mc) /= size(phi) .or. size(f) /= size(phi)) then
      f = quiet_nan()
      call set_error(status, PENDULA_ERR_SIZE, 'ellipfm1_array: mc and f must have the size of phi')
      return
    end if
    call f_points(size(phi), phi, mc, .true., f)
  end subroutine ellipfm1_array

  ! The loop of ellipf_array (m1 = .false.: x is m) and ellipfm1_array (x is mc): blocks
  ! of fblock points, each (1) reduced with its sine and cosine (f_start, libm), (2) R_F
  ! for the whole block in rf_block (vectorised, the duplications of every point in step),
  ! (3) the periods added where phi was reduced.
  pure subroutine f_points(n, phi, x, m1, f)
    integer, intent(in) :: n
    real(wp), intent(in) :: phi(n), x(n)
    logical, intent(in) :: m1
    real(wp), intent(out) :: f(n)
    real(wp), dimension(fblock) :: n1, n2, s, c, d2, m, mc, rf
    logical, dimension(fblock) :: need_rf, final
    integer :: i0, nb, j
    do i0 = 1, n, fblock
      nb = min(fblock, n - i0 + 1)
      do j = 1, nb
        if (m1) then
          m(j) = 1 - x(i0 + j - 1); mc(j) = x(i0 + j - 1)
        else
          m(j) = x(i0 + j - 1); mc(j) = 1 - x(i0 + j - 1)
        end if
        call f_start(phi(i0 + j - 1), m(j), mc(j), m1, n1(j), n2(j), s(j), c(j), d2(j), f(i0 + j - 1), &
                     need_rf(j), final(j))
        if (.not. need_rf(j)) then
          c(j) = 1; d2(j) = 1    ! a harmless point for rf_block
        end if
      end do
      call rf_block(nb, c, d2, rf)
      do j = 1, nb
        if (need_rf(j)) f(i0 + j - 1) = s(j)*rf(j)
      end do
      do j = 1, nb
        if (final(j)) cycle
        if (n1(j) /= 0 .or. n2(j) /= 0) f(i0 + j - 1) = add_periods(f(i0 + j - 1), n1(j), n2(j), m(j), mc(j), m1)
      end do
    end do
  end subroutine f_points

  ! R_F(c^2, d2, 1) at nb <= fblock points (F's integral; c, d2 finite, d2 > 0): carlson_rf's steps
  ! with the first step's square roots of c^2 and 1 known (|c| and 1, exact; one square
  ! root instead of three there), every point's duplications in step (a point that has
  ! converged keeps its x, y, z) so that the loop over the points vectorises, then the
  ! series at each point.
  pure subroutine rf_block(nb, c, d2, rf)
    integer, intent(in) :: nb
    real(wp), intent(in) :: c(nb), d2(nb)
    real(wp), intent(out) :: rf(nb)
    real(wp), dimension(fblock) :: x, y, z, a, dx, dy, dz, sx, sy, sz, lam, conv
    real(wp) :: f1, f2
    integer :: i
    ! whole-array statements over the block (each a short loop that vectorises)
    x(1:nb) = c*c; y(1:nb) = d2; z(1:nb) = 1
    do i = 1, 200
      a(1:nb) = (x(1:nb) + y(1:nb) + z(1:nb))*(1.0_wp/3)
      dx(1:nb) = a(1:nb) - x(1:nb); dy(1:nb) = a(1:nb) - y(1:nb); dz(1:nb) = a(1:nb) - z(1:nb)
      ! three tests, not max(): gfortran's max branches on NaN; a point that has converged
      ! keeps its x, y, z, hence stays converged
      ! (a real flag, 1 when converged: a logical array beside reals kept gcc from vectorising)
      conv(1:nb) = merge(1.0_wp, 0.0_wp, abs(dx(1:nb)) <= 5.0e-3_wp*a(1:nb)) &
                   *merge(1.0_wp, 0.0_wp, abs(dy(1:nb)) <= 5.0e-3_wp*a(1:nb)) &
                   *merge(1.0_wp, 0.0_wp, abs(dz(1:nb)) <= 5.0e-3_wp*a(1:nb))
      if (all(conv(1:nb) > 0)) exit
      ! the first step takes the square roots of c^2 and 1 as |c| and 1: f1, f2 pick them
      ! by exact products (0 or 1 times a finite number) rather than a branch
      f1 = merge(1.0_wp, 0.0_wp, i == 1); f2 = 1 - f1
      sx(1:nb) = f1*abs(c) + f2*sqrt(x(1:nb))
      sz(1:nb) = f1 + f2*sqrt(z(1:nb))
      sy(1:nb) = sqrt(y(1:nb))
      lam(1:nb) = sx(1:nb)*(sy(1:nb) + sz(1:nb)) + sy(1:nb)*sz(1:nb)
      x(1:nb) = merge(x(1:nb), 0.25_wp*(x(1:nb) + lam(1:nb)), conv(1:nb) > 0)
      y(1:nb) = merge(y(1:nb), 0.25_wp*(y(1:nb) + lam(1:nb)), conv(1:nb) > 0)
      z(1:nb) = merge(z(1:nb), 0.25_wp*(z(1:nb) + lam(1:nb)), conv(1:nb) > 0)
    end do
    rf = rf_series(a(1:nb), dx(1:nb), dy(1:nb))
  end subroutine rf_block

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
