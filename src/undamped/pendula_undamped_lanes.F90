!> The block kernel of undamped_states' librations (libration_lanes of
!> pendula_undamped_eval): theta and Omega of a block of librations from sn, cn, dn by the
!> addition theorem and a polynomial atan, libration_block of pendula_libration_block.inc.
!>
!> Why a file of its own, compiled several times: the loop (a dozen products, two
!> divisions and the atan polynomial per state) is set by the vector width of the
!> instruction set it may use.  meson compiles this file once per target (baseline x86-64 =
!> SSE2, x86-64-v3 = AVX2, x86-64-v4 = AVX-512; elsewhere only the portable build), each
!> with its own module and entry name given by the preprocessor (PENDULA_LIBR_MODULE,
!> PENDULA_LIBR_ENTRY), and pendula_kernel_path.c picks one at load time, as for the K and
!> E block kernel (special/pendula_elliptic_ke_lanes.F90).  The module uses no pendula
!> module, so each variant is a leaf of the build; pi/2 and the atan coefficients come from
!> the caller.
!>
!> Bit-identity: pendula compiles everything with -ffp-contract=off and without
!> -ffast-math, and the loop uses only +, -, *, / (atan2, a libm call, only where x <= 0,
!> the same function on every path), so every variant returns the bits of the one-state
!> evaluation (tests/python/test_kernel_paths.py compares undamped states on every path
!> the machine has).
! meson defines the names per variant; a build that compiles the file once (fpm) gets the
! portable one, which pendula_kernel_path.c always has.
#ifndef PENDULA_LIBR_MODULE
#define PENDULA_LIBR_MODULE pendula_undamped_lanes_baseline_m
#define PENDULA_LIBR_ENTRY pendula_libration_block_baseline
#endif
module PENDULA_LIBR_MODULE
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use, intrinsic :: iso_fortran_env, only: wp => real64
  implicit none
  private
  public :: PENDULA_LIBR_ENTRY

contains

  !> theta - 2 pi N and Omega of the first n of 64 librations: the bits of libration_block
  !> in pendula_undamped_eval.
  pure subroutine PENDULA_LIBR_ENTRY(n, q, ch, sh, w0, sa, ca, da, hp, hp_lo, atanp, theta, omega) bind(C)
    integer(c_int), intent(in) :: n  !< number of points, <= 64
    real(c_double), intent(in) :: q(64)  !< Omega0/(2 w0) = k cn(u0|m)
    real(c_double), intent(in) :: ch(64)  !< cos(theta_r/2) = dn(u0|m)
    real(c_double), intent(in) :: sh(64)  !< sin(theta_r/2) = k sn(u0|m)
    real(c_double), intent(in) :: w0(64)  !< small-angle angular frequencies [1/s]
    real(c_double), intent(in) :: sa(64)  !< sn(a)
    real(c_double), intent(in) :: ca(64)  !< cn(a)
    real(c_double), intent(in) :: da(64)  !< dn(a)
    real(c_double), intent(in) :: hp  !< pi/2, high part
    real(c_double), intent(in) :: hp_lo  !< pi/2, low part
    real(c_double), intent(in) :: atanp(0:10)  !< the atan polynomial's coefficients
    real(c_double), intent(out) :: theta(64)  !< theta - 2 pi N [rad]
    real(c_double), intent(out) :: omega(64)  !< angular velocities [rad/s]
    call libration_block(int(n), q, ch, sh, w0, sa, ca, da, hp, hp_lo, atanp, theta, omega)
  end subroutine PENDULA_LIBR_ENTRY

  include 'pendula_libration_block.inc'

end module PENDULA_LIBR_MODULE
