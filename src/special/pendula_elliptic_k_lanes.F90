!> K(m) in double-double for a block of points at once: pendula_elliptic_ke's compensated
!> AGM (k_double_double) stepped for every point of the block side by side, behind
!> k_double_double_block (pendula_elliptic_k_block), which the Jacobi array loops call
!> for their long arguments (beyond a few half periods they need K to ~1e-31).  The AGM's
!> arithmetic (start, step, finish) is pendula_agm_dd.inc, the text k_double_double runs
!> too; this file adds only the loops over the block.
!>
!> Why a file of its own, compiled several times: the AGM of one point is a chain of
!> dependent square roots; the block's points side by side fill the pipeline and
!> vectorise, so the speed is set by the vector width (it was ~30 % of the time of
!> undamped_states over distinct states at one time each in 0..100 s).  meson compiles
!> this file once per target (baseline x86-64 = SSE2, x86-64-v3 = AVX2, x86-64-v4 =
!> AVX-512; elsewhere only the portable build), each with its own module and entry name
!> given by the preprocessor (PENDULA_KDD_MODULE, PENDULA_KDD_ENTRY), and
!> pendula_kernel_path.c picks one at load time, as for the K and E block kernel
!> (pendula_elliptic_ke_lanes.F90).  The module uses no pendula module, so each variant is
!> a leaf of the build: pi/2 in double-double comes from the caller (pendula_constants).
!>
!> Bit-identity: pendula compiles everything with -ffp-contract=off and without
!> -ffast-math, and the AGM uses only +, -, *, / and sqrt (correctly rounded in every
!> instruction set), so every variant returns the same bits, those of the scalar
!> k_double_double, which runs the same included steps (tests/fortran/test_elliptic.f90
!> compares them; test_kernel_paths.py runs it on every path the machine has).
! meson defines the names per variant; a build that compiles the file once (fpm) gets the
! portable one, which pendula_kernel_path.c always has.
#ifndef PENDULA_KDD_MODULE
#define PENDULA_KDD_MODULE pendula_elliptic_k_lanes_baseline_m
#define PENDULA_KDD_ENTRY pendula_k_dd_block_baseline
#endif
module PENDULA_KDD_MODULE
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use, intrinsic :: iso_fortran_env, only: wp => real64
  implicit none
  private
  public :: PENDULA_KDD_ENTRY

contains

  !> K in double-double for nb points, mc = mch + mcl > 0 each: the compensated AGM of
  !> pendula_elliptic_ke's k_double_double, its steps (pendula_agm_dd.inc, the same bits)
  !> taken for the whole block in turn, a point that has converged (t <= 2**-27) keeping
  !> its values by merge.  A point that needs no K passes mch = 1 (no step).
  pure subroutine PENDULA_KDD_ENTRY(nb, mch, mcl, hp, hp_lo, khi, klo) bind(C)
    integer(c_int), intent(in) :: nb  !< points, >= 0 (a few dozen: the work arrays live on the stack)
    real(c_double), intent(in) :: mch(nb)  !< 1 - m, high part, > 0 (1: no K wanted)
    real(c_double), intent(in) :: mcl(nb)  !< 1 - m, low part
    real(c_double), intent(in) :: hp  !< pi/2, high part
    real(c_double), intent(in) :: hp_lo  !< pi/2, low part
    real(c_double), intent(out) :: khi(nb)  !< K, high part
    real(c_double), intent(out) :: klo(nb)  !< K, low part
    real(wp), dimension(nb) :: ah, al, bh, bl, ah2, al2, bh2, bl2
    integer :: i, j, nlive
    do j = 1, nb
      call agm_start(mch(j), mcl(j), ah(j), al(j), bh(j), bl(j))
    end do
    ! steps in pairs, (ah, al, bh, bl) -> the second set -> back; a step where no point
    ! moved leaves both sets equal (up to 80 steps, as k_double_double)
    do i = 1, 40
      call agm_steps(int(nb), ah, al, bh, bl, ah2, al2, bh2, bl2, nlive)
      if (nlive == 0) exit
      call agm_steps(int(nb), ah2, al2, bh2, bl2, ah, al, bh, bl, nlive)
      if (nlive == 0) exit
    end do
    do j = 1, nb
      call agm_finish(ah(j), al(j), bh(j), bl(j), hp, hp_lo, khi(j), klo(j))
    end do
  end subroutine PENDULA_KDD_ENTRY

  !> One step of the block's compensated AGM, from (ah, al, bh, bl) into (ah2, al2, bh2,
  !> bl2), at each of nb points where t > 2**-27 still (the others copy their values);
  !> nlive counts the points stepped.  A real flag and separate outputs: the forms in
  !> which gcc vectorises the loop.
  pure subroutine agm_steps(nb, ah, al, bh, bl, ah2, al2, bh2, bl2, nlive)
    integer, intent(in) :: nb
    real(wp), intent(in) :: ah(nb), al(nb), bh(nb), bl(nb)
    real(wp), intent(out) :: ah2(nb), al2(nb), bh2(nb), bl2(nb)
    integer, intent(out) :: nlive
    real(wp) :: nah, nal, nbh, nbl, live
    integer :: j
    nlive = 0
    do j = 1, nb
      live = merge(1.0_wp, 0.0_wp, agm_live(ah(j), bh(j)))
      call agm_step(ah(j), al(j), bh(j), bl(j), nah, nal, nbh, nbl)
      ah2(j) = merge(nah, ah(j), live > 0); al2(j) = merge(nal, al(j), live > 0)
      bh2(j) = merge(nbh, bh(j), live > 0); bl2(j) = merge(nbl, bl(j), live > 0)
      nlive = nlive + merge(1, 0, live > 0)
    end do
  end subroutine agm_steps

  ! agm_start, agm_live, agm_step, agm_finish, prod_err and sq_err: the same text as
  ! pendula_elliptic_ke's k_double_double runs for one point.
  include 'pendula_agm_dd.inc'

end module PENDULA_KDD_MODULE
