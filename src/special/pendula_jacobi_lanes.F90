!> The block kernel of the Jacobi array forms (unit_block of pendula_jacobi_kernel, behind
!> ellipj_array, ellipjm1_array and undamped_states): sn, cn, dn at the core arguments of
!> a block of points -- the Maclaurin start in one vectorised pass and the duplications --
!> core_block of pendula_jacobi_core_block.inc.
!>
!> Why a file of its own, compiled several times: the Maclaurin start's loop (the series
!> coefficients in m and the series in w for every point) is set by the vector width of
!> the instruction set it may use.  meson compiles this file once per target (baseline
!> x86-64 = SSE2, x86-64-v3 = AVX2, x86-64-v4 = AVX-512; elsewhere only the portable
!> build), each with its own module and entry name given by the preprocessor
!> (PENDULA_JCORE_MODULE, PENDULA_JCORE_ENTRY), and pendula_kernel_path.c picks one at load
!> time, as for the K and E block kernel (pendula_elliptic_ke_lanes.F90).  The module uses
!> no pendula module, so each variant is a leaf of the build; the procedures are the same
!> text as pendula_jacobi_kernel's (pendula_jacobi_series.inc, pendula_jacobi_core_block.inc).
!>
!> Bit-identity: pendula compiles everything with -ffp-contract=off and without
!> -ffast-math, and the block uses only +, -, *, / (no libm call), so every variant returns
!> the bits of the scalar ellipj/ellipjm1 (test_elliptic compares the array forms with
!> them; tests/python/test_kernel_paths.py runs it, and compares undamped states, on every
!> path the machine has).
! meson defines the names per variant; a build that compiles the file once (fpm) gets the
! portable one, which pendula_kernel_path.c always has.
#ifndef PENDULA_JCORE_MODULE
#define PENDULA_JCORE_MODULE pendula_jacobi_lanes_baseline_m
#define PENDULA_JCORE_ENTRY pendula_jacobi_core_block_baseline
#endif
module PENDULA_JCORE_MODULE
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use, intrinsic :: iso_fortran_env, only: wp => real64
  implicit none
  private
  public :: PENDULA_JCORE_ENTRY

contains

  !> sn, cn, dn at the nb core arguments 0 <= v(j) <= K(m(j))/2, 0 <= m(j) <= 1, mc(j) =
  !> 1 - m(j) accurate: the bits of core_block in pendula_jacobi_kernel.
  pure subroutine PENDULA_JCORE_ENTRY(nb, v, m, mc, s, c, d) bind(C)
    integer(c_int), intent(in) :: nb  !< points, >= 0 (a few dozen: the work arrays live on the stack)
    real(c_double), intent(in) :: v(nb)  !< core arguments, 0 <= v <= K/2
    real(c_double), intent(in) :: m(nb)  !< parameters m in [0, 1]
    real(c_double), intent(in) :: mc(nb)  !< 1 - m
    real(c_double), intent(out) :: s(nb)  !< sn(v|m)
    real(c_double), intent(out) :: c(nb)  !< cn(v|m)
    real(c_double), intent(out) :: d(nb)  !< dn(v|m)
    call core_block(int(nb), v, m, mc, s, c, d)
  end subroutine PENDULA_JCORE_ENTRY

  include 'pendula_jacobi_series.inc'

  include 'pendula_jacobi_core_block.inc'

end module PENDULA_JCORE_MODULE
