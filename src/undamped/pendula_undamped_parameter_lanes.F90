!> The block kernel of the elliptic parameter of undamped states (parameter_lanes of
!> pendula_undamped_parameter): sin and cos of theta0/2, Omega0/(2 w0) and 1 - m of a
!> block of states as set_geometry (pendula_undamped_motion) forms them for |theta0| < pi,
!> with the half-angle sine and cosine and the double-double cosine near the separatrix
!> of pendula_angle_dd_block.inc.
!>
!> Why a file of its own, compiled several times: the loops (two Taylor series per state,
!> a Dekker product and a double-double sum; a double-double Horner chain near the
!> separatrix) are set by the vector width of the instruction set they may use.  meson
!> compiles this file once per target (baseline x86-64 = SSE2, x86-64-v3 = AVX2,
!> x86-64-v4 = AVX-512; elsewhere only the portable build), each with its own module and
!> entry name given by the preprocessor (PENDULA_PARAM_MODULE, PENDULA_PARAM_ENTRY), and
!> pendula_kernel_path.c picks one at load time, as for the librations of undamped_states
!> (pendula_undamped_lanes.F90).  The module uses no pendula module, so each variant is a
!> leaf of the build; pi/2 comes from the caller (pendula_constants).
!>
!> Bit-identity: pendula compiles everything with -ffp-contract=off and without
!> -ffast-math, and the loops use only +, -, *, /, abs, sign and merges (no libm call), so
!> every variant returns the same bits (tests/python/test_kernel_paths.py compares
!> elliptic_parameter, amplitude, regime, period and undamped states on every path the
!> machine has; the one-state state_parameter gives the same numbers, test_undamped.py).
! meson defines the names per variant; a build that compiles the file once (fpm) gets the
! portable one, which pendula_kernel_path.c always has.
#ifndef PENDULA_PARAM_MODULE
#define PENDULA_PARAM_MODULE pendula_undamped_parameter_lanes_baseline_m
#define PENDULA_PARAM_ENTRY pendula_parameter_block_baseline
#endif
module PENDULA_PARAM_MODULE
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use, intrinsic :: iso_fortran_env, only: wp => real64
  implicit none
  private
  public :: PENDULA_PARAM_ENTRY

contains

  !> 1 - m of the states k = 1..n with fast(k) /= 0 on entry and |q| <= 1e150 (fast is set
  !> to 0 for the others, which get harmless numbers), as set_geometry forms it for
  !> |theta0| < pi (the caller's flags must imply it): sh = sin(theta0/2), ch =
  !> cos(theta0/2) (its high part in double-double near the separatrix), q = Omega0/(2 w0)
  !> and mc = 1 - m without cancellation, in passes over the block -- the half-angle sines
  !> and cosines in one vectorised loop, the cosines near the separatrix by one
  !> cos_dd_block call, 1 - m in one branch-free loop.
  pure subroutine PENDULA_PARAM_ENTRY(n, th, om, w, fast, hp, hp_lo, sh, ch, q, mc) bind(C)
    integer(c_int), intent(in) :: n  !< states in the block
    real(c_double), intent(in) :: th(n)  !< initial angles [rad], finite
    real(c_double), intent(in) :: om(n)  !< initial angular velocities [rad/s], finite
    real(c_double), intent(in) :: w(n)  !< angular frequencies [1/s], > 0
    integer(c_int), intent(inout) :: fast(n)  !< 1: a state to set up (|theta0| < pi); set to 0 where |q| > 1e150
    real(c_double), intent(in) :: hp  !< pi/2, high part
    real(c_double), intent(in) :: hp_lo  !< pi/2, low part
    real(c_double), intent(out) :: sh(n)  !< sin(theta0/2)
    real(c_double), intent(out) :: ch(n)  !< cos(theta0/2), high part
    real(c_double), intent(out) :: q(n)  !< Omega0/(2 w0)
    real(c_double), intent(out) :: mc(n)  !< 1 - m
    real(wp), dimension(n) :: a, sh0, ch0, w2, chlo, xn, xl, cn, cln, okr, nearr, qlov
    integer :: near(n), k, nn
    real(wp) :: h, hl, pi2, hlo, omk, chk, chlok, qlo, pp, e, d, dlo, s, ok, ok_q, wk, w2k, qk
    ! local copies: the loops' stores then cannot touch them (what lets gcc vectorise)
    h = hp; hl = hp_lo
    pi2 = 2*h   ! pi: pendula_constants' pi/2 is pi halved exactly
    do k = 1, n
      ! a harmless angle for the states left to the general path
      a(k) = merge(0.5_wp*th(k), 0.0_wp, abs(th(k)) < pi2)
    end do
    do k = 1, n
      call sincos_half_core(a(k), h, hl, sh0(k), ch0(k))
    end do
    ! set_geometry's steps for |theta0| < pi: reduce_angle_2pi gives n = 0, r = theta0
    ! exactly (hlo = 0), the centre is 0
    hlo = 0
    do k = 1, n
      sh(k) = sh0(k) + ch0(k)*hlo
      w2(k) = om(k)/w(k)
      q(k) = 0.5_wp*w2(k)
      ! real flags and nested merges, not integers and .and. (control flow): the forms
      ! gcc vectorises
      okr(k) = merge(merge(1.0_wp, 0.0_wp, abs(q(k)) <= 1.0e150_wp), 0.0_wp, fast(k) /= 0)
      ch(k) = ch0(k) - sh0(k)*hlo
      chlo(k) = 0
      nearr(k) = merge(merge(okr(k), 0.0_wp, abs(q(k)) <= (8.0_wp/7)*ch0(k)), 0.0_wp, abs(q(k)) >= 0.875_wp*ch0(k))
    end do
    nn = 0
    do k = 1, n
      fast(k) = merge(1_c_int, 0_c_int, okr(k) > 0)
      if (nearr(k) > 0) then
        nn = nn + 1
        near(nn) = k
        xn(nn) = a(k)
        xl(nn) = hlo
      end if
    end do
    if (nn > 0) then
      call cos_dd_block(nn, xn(1:nn), xl(1:nn), h, hl, cn(1:nn), cln(1:nn))
      do k = 1, nn
        ch(near(k)) = cn(k)
        chlo(near(k)) = cln(k)
      end do
    end if
    do k = 1, n
      ! 1 - m as set_geometry forms it, branch-free, in two loops gcc vectorises (one was
      ! too much for it): the low part of q by the exact product, then 1 - m.  The states
      ! left to the general path get harmless numbers (no overflow).  Every load is
      ! unconditional (a merge of array elements is a conditional load: control flow)
      ok = okr(k)
      wk = w(k); w2k = w2(k); omk = om(k)
      wk = merge(wk, 1.0_wp, ok > 0)
      w2k = merge(w2k, 0.0_wp, ok > 0)
      ok_q = merge(merge(1.0_wp, 0.0_wp, max(abs(w2k), wk) < 1.0e290_wp), 0.0_wp, w2k /= 0)
      call exact_product(merge(w2k, 0.0_wp, ok_q > 0), merge(wk, 0.0_wp, ok_q > 0), pp, e)
      qlov(k) = merge(0.5_wp*(((merge(omk, 0.0_wp, ok > 0) - pp) - e)/wk), 0.0_wp, ok_q > 0)
    end do
    do k = 1, n
      qk = q(k); chk = ch(k); chlok = chlo(k); qlo = qlov(k)
      qk = merge(qk, 0.0_wp, okr(k) > 0)
      s = chk + abs(qk)
      call sum_dd(chk, chlok, -abs(qk), -sign(1.0_wp, qk)*qlo, d, dlo)
      mc(k) = merge(merge((chk - abs(qk))*s, (d + dlo)*s, qlo == 0), (d + dlo)*s, chlok == 0)
    end do
  end subroutine PENDULA_PARAM_ENTRY

  ! pendula_double_double's dd_add_fast and two_prod (for |a|, |b| <= 2**996), operation
  ! for operation (the same bits), here so that the 1 - m loop inlines them.
  elemental subroutine sum_dd(ah, al, bh, bl, ch, cl)
    real(wp), intent(in) :: ah, al, bh, bl
    real(wp), intent(out) :: ch, cl
    real(wp) :: s, e, bb
    s = ah + bh
    bb = s - ah
    e = (ah - (s - bb)) + (bh - bb)
    e = e + (al + bl)
    ch = s + e
    cl = e - (ch - s)
  end subroutine sum_dd

  elemental subroutine exact_product(a, b, p, e)
    real(wp), intent(in) :: a, b
    real(wp), intent(out) :: p, e
    real(wp), parameter :: split = 134217729.0_wp   ! 2**27 + 1 (Veltkamp)
    real(wp) :: t, ah, al, bh, bl
    p = a*b
    t = split*a
    ah = t - (t - a)
    al = a - ah
    t = split*b
    bh = t - (t - b)
    bl = b - bh
    e = ((ah*bh - p) + ah*bl + al*bh) + al*bl
  end subroutine exact_product

  include 'pendula_angle_dd_block.inc'

end module PENDULA_PARAM_MODULE
