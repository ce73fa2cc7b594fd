!> Cancellation and progress of long calls.
!>
!> A long-running procedure takes `control`, an int64 array of CONTROL_SIZE
!> elements that another thread may read and write while the call runs (the
!> Python layer runs long calls in a worker thread and forwards Ctrl-C here).
!> `control(CONTROL_CANCEL) /= 0` asks the call to stop: it polls the flag at
!> least every millisecond or so of work and returns PENDULA_ERR_CANCELLED with
!> everything finished so far intact.  `control(CONTROL_PROGRESS)` counts the
!> work units done (steps, or states for batch calls), for progress bars.
!> The array is VOLATILE in the procedures that poll it, so every read goes to
!> memory; no lock is taken.
module pendula_control
  use, intrinsic :: iso_fortran_env, only: int64
  implicit none
  private

  public :: CONTROL_SIZE, CONTROL_CANCEL, CONTROL_PROGRESS, cancel_requested, add_progress

  integer, parameter :: CONTROL_SIZE = 2
  integer, parameter :: CONTROL_CANCEL = 1
  integer, parameter :: CONTROL_PROGRESS = 2

contains

  !> True when another thread has asked the call holding `control` to stop.
  logical function cancel_requested(control)
    integer(int64), intent(inout), volatile :: control(:)  ! size CONTROL_SIZE; VOLATILE excludes intent(in)
    !< control array of CONTROL_SIZE elements: cancel flag and progress counter (see module doc)
    cancel_requested = control(CONTROL_CANCEL) /= 0
  end function cancel_requested

  !> Add `n` work units to the progress counter (atomic under OpenMP).
  subroutine add_progress(control, n)
    integer(int64), intent(inout), volatile :: control(:)  ! size CONTROL_SIZE
    !< control array of CONTROL_SIZE elements: cancel flag and progress counter (see module doc)
    integer(int64), intent(in) :: n  !< work units to add to the progress counter, >= 0
    !$omp atomic update
    control(CONTROL_PROGRESS) = control(CONTROL_PROGRESS) + n
  end subroutine add_progress

end module pendula_control
