!> K(m) in double-double for a block of points at once (the Jacobi array loops' long
!> arguments, beyond a few half periods, need K to ~1e-31): pendula_elliptic_ke's
!> compensated AGM (k_double_double) stepped for every point of the block side by side,
!> in the variant of the block kernel (pendula_elliptic_k_lanes.F90) that the runtime
!> dispatch chose for this CPU.
module pendula_elliptic_k_block
  use, intrinsic :: iso_c_binding, only: c_int
  use pendula_kinds, only: wp
  use pendula_constants, only: half_pi, half_pi_lo
  use pendula_dispatch, only: k_dd_block_lanes
  implicit none
  private

  public :: k_double_double_block

contains

  !> K in double-double for nb points, mc = mch + mcl > 0 each: the compensated
  !> AGM of pendula_elliptic_ke's k_double_double, operation for operation (the same bits),
  !> with its steps taken for the whole block in turn, a point that has converged
  !> (t <= 2**-27) keeping its values by merge.  One point's AGM is a chain of dependent
  !> square roots; the block's points side by side fill the pipeline (and vectorise),
  !> where one call per point waited on each root in turn.  A point that needs no K
  !> passes mch = 1 (no step).
  pure subroutine k_double_double_block(nb, mch, mcl, khi, klo)
    integer, intent(in) :: nb  !< points, >= 0 (a few dozen: the work arrays live on the stack)
    real(wp), intent(in) :: mch(nb)  !< 1 - m, high part, > 0 (1: no K wanted)
    real(wp), intent(in) :: mcl(nb)  !< 1 - m, low part
    real(wp), intent(out) :: khi(nb)  !< K, high part
    real(wp), intent(out) :: klo(nb)  !< K, low part
    call k_dd_block_lanes(int(nb, c_int), mch, mcl, half_pi, half_pi_lo, khi, klo)
  end subroutine k_double_double_block

end module pendula_elliptic_k_block
