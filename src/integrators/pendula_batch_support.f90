!> What the two batch integrators (pendula_rk4_batch, pendula_cvode_batch)
!> share beyond pendula_ode (the driven blocks use it too): the thread count
!> of a call, the value of a failed state's real outputs and the status of a
!> call with failed states.  A module of its own because it uses OpenMP: a
!> program that integrates single states (pendula_ode) then needs no OpenMP
!> runtime at link time.
module pendula_batch_support
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use pendula_kinds, only: wp
  use pendula_format, only: format_int
  use pendula_status, only: status_t, set_error, PENDULA_OK, PENDULA_ERR_CANCELLED
!$ use omp_lib, only: omp_get_max_threads
  implicit none
  private
  public :: batch_threads, set_batch_error, failed_output, nan_failed

  !> failed_output in every real output of a failed state: a(i) or a(:, i) where codes(i) /= PENDULA_OK.
  interface nan_failed
    module procedure nan_failed_1, nan_failed_2
  end interface nan_failed

contains

  !> OpenMP threads for a batch call: `threads` when present and > 0, else the
  !> OpenMP default (which honours OMP_NUM_THREADS); 1 without OpenMP.
  integer function batch_threads(threads) result(nthreads)
    integer, intent(in), optional :: threads  !< optional requested thread count (> 0 to use it)
    nthreads = 1
!$  nthreads = omp_get_max_threads()
    if (present(threads)) then
      if (threads > 0) nthreads = threads
    end if
  end function batch_threads

  !> The value every batch call writes into the real outputs of a state that
  !> failed (and of every state of a refused call): a quiet NaN, so that a
  !> caller who ignores the state's code reads no plausible number (zero is a
  !> pendulum at rest); the state's code says why it failed.
  pure real(wp) function failed_output() result(x)
    x = ieee_value(1.0_wp, ieee_quiet_nan)
  end function failed_output

  !> a(i) = failed_output() where codes(i) /= PENDULA_OK (one value per state).
  pure subroutine nan_failed_1(codes, a)
    integer, intent(in) :: codes(:)  !< status code of each state
    real(wp), intent(inout) :: a(:)  !< one output per state, size(codes)
    where (codes /= PENDULA_OK) a = failed_output()
  end subroutine nan_failed_1

  !> a(:, i) = failed_output() where codes(i) /= PENDULA_OK (a column per state).
  pure subroutine nan_failed_2(codes, a)
    integer, intent(in) :: codes(:)  !< status code of each state
    real(wp), intent(inout) :: a(:, :)  !< the outputs of state i in column i, size(codes) columns
    integer :: i
    do i = 1, size(codes)
      if (codes(i) /= PENDULA_OK) a(:, i) = failed_output()
    end do
  end subroutine nan_failed_2

  !> The status of a batch call from its per-state codes (some not
  !> PENDULA_OK): a cancelled call says so first (how many states are
  !> unfinished), whatever else failed; otherwise state `first` (the first
  !> failed one; not read when states were cancelled), its code and `message`.
  pure subroutine set_batch_error(status, codes, first, message)
    type(status_t), intent(inout) :: status
    !< the first error of the call is kept: set here only if nothing failed before
    integer, intent(in) :: codes(:)  !< status code of each state
    integer, intent(in) :: first  !< 1-based index of the first failed state
    character(len=*), intent(in) :: message  !< message of that state
    integer :: n, nfail, ncancel
    n = size(codes)
    nfail = count(codes /= PENDULA_OK)
    ncancel = count(codes == PENDULA_ERR_CANCELLED)
    if (ncancel > 0) then
      call set_error(status, PENDULA_ERR_CANCELLED, 'cancelled: '//format_int(ncancel)//' of '// &
                     format_int(n)//' states unfinished (codes = PENDULA_ERR_CANCELLED), the others are complete')
    else
      call set_error(status, codes(first), 'state '//format_int(first)//' of '//format_int(n)//' ('// &
                     format_int(nfail)//' failed, see codes): '//trim(message))
    end if
  end subroutine set_batch_error

end module pendula_batch_support
