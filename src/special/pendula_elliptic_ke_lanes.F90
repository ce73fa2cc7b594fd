!> The block kernel of the array forms of K and E (ellipk_array and the others,
!> k_unit_many): ke_block of pendula_elliptic_ke, up to nb = 256 elements per call, each
!> kind of evaluation (interval polynomial, logarithmic form) in one branch-free loop over
!> the block that gcc vectorises.
!>
!> Why a file of its own, compiled several times: the loops' speed is set by the vector
!> width of the instruction set they may use.  meson compiles this file once per target
!> (baseline x86-64 = SSE2, x86-64-v3 = AVX2, x86-64-v4 = AVX-512; elsewhere only the
!> portable build), each with its own module and entry name given by the preprocessor
!> (PENDULA_KE_MODULE, PENDULA_KE_ENTRY), and pendula_kernel_path.c picks one at load time
!> from the CPU's features (or from PENDULA_KERNEL), as for the batch RK4 kernel.  The
!> module uses no other pendula module, so each variant is a leaf of the build; the tables
!> and the block's procedures are the same text as pendula_elliptic_ke's
!> (pendula_elliptic_ke_tables.inc, pendula_elliptic_ke_block.inc).
!>
!> Bit-identity: pendula compiles everything with -ffp-contract=off and without
!> -ffast-math, and the block calls no libm function (its logarithm is inlined), so no
!> variant fuses a multiply and an add, reorders a sum or calls a different routine:
!> every variant returns the bits of the scalar ellipk/ellipe
!> (tests/python/test_kernel_paths.py compares them on every path the machine has).
! meson defines the names per variant; a build that compiles the file once (fpm) gets the
! portable one, which pendula_kernel_path.c always has.
#ifndef PENDULA_KE_MODULE
#define PENDULA_KE_MODULE pendula_elliptic_ke_lanes_baseline_m
#define PENDULA_KE_ENTRY pendula_ke_block_baseline
#endif
module PENDULA_KE_MODULE
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use, intrinsic :: iso_fortran_env, only: wp => real64, int32, int64
  implicit none
  private
  public :: PENDULA_KE_ENTRY

  include 'pendula_elliptic_ke_tables.inc'

contains

  !> K (second = 0) or E (second /= 0) of the n pairs (m(j), mc(j)), 1 <= n <= 256,
  !> 0 <= m(j) < 1, mc(j) = 1 - m(j) as k_unit takes them (m accurate when m < 1/2, mc
  !> when m > 1/2): x(j), the bits of k_unit/e_unit.
  pure subroutine PENDULA_KE_ENTRY(n, m, mc, second, x) bind(C)
    integer(c_int), intent(in) :: n  !< elements, 1 to 256
    real(c_double), intent(in) :: m(n)  !< parameters m in [0, 1)
    real(c_double), intent(in) :: mc(n)  !< 1 - m
    integer(c_int), intent(in) :: second  !< 0: K, otherwise E
    real(c_double), intent(out) :: x(n)  !< K(m(j)) or E(m(j))
    call ke_block(int(n), m, mc, second /= 0, x)
  end subroutine PENDULA_KE_ENTRY

  include 'pendula_elliptic_ke_block.inc'

end module PENDULA_KE_MODULE
