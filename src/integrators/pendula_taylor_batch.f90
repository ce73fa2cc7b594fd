!> The Taylor integrator (pendula_taylor) for many pendulums in one call: each
!> state i has its own theta0(i), omega0(i), w0(i), gamma(i) and tol(i) (and
!> so its own order and steps); the output grid t is shared.  Without a drive
!> the states run in blocks of TAYLOR_LANES (pendula_taylor_lanes: their
!> series formed side by side, each step taken by the scalar integrator's own
!> step code); with a drive each state runs taylor_run.  Either way a state's
!> results are bit-identical to taylor_solve for the same state whatever else
!> is in the batch.  Chunks of states are spread over OpenMP threads (dynamic
!> schedule: adaptive steps make their costs differ); the cancel flag is
!> polled before each state starts and when it ends.
module pendula_taylor_batch
  use, intrinsic :: iso_fortran_env, only: int64
  use pendula_kinds, only: wp, i8
  use pendula_status, only: status_t, set_error, check_same_size, check_alloc, PENDULA_OK, PENDULA_ERR_CANCELLED
  use pendula_control, only: CONTROL_SIZE, cancel_requested, add_progress
  use pendula_ode, only: check_batch_shapes, at => batch_index
  use pendula_batch_support, only: batch_threads, set_batch_error, failed_output, nan_failed
  use pendula_taylor, only: taylor_check, taylor_run, taylor_outcome, TAYLOR_DEFAULT_MAX_STEPS
  use pendula_taylor_lanes, only: taylor_lanes_run, taylor_lanes_list, TAYLOR_LANES
  use pendula_drive, only: drive_t, check_drive
  implicit none
  private
  public :: taylor_batch_solve

contains

  !> Integrate n = size(theta0) states over the shared grid t [s] (finite,
  !> strictly monotonic: decreasing integrates backwards) to the absolute
  !> accuracies tol; omega0 [rad/s], w0 [1/s], gamma [1/s] and tol have n
  !> elements or one (broadcast).  theta(:, i) [rad], omega(:, i) [rad/s] and
  !> the error estimates err(:, i) [rad] of state i, as taylor_solve returns
  !> them; steps(i) and order(i) its work.  codes(i): state i's status code
  !> (PENDULA_OK, or taylor_solve's code: bad argument, max_steps exhausted,
  !> non-finite state); a failed state's theta, omega and err are quiet NaN
  !> (failed_output: never a plausible number), the others are unaffected.  status: OK when every state succeeded, PENDULA_ERR_CANCELLED
  !> when cancelled, else the first failed state's code and message; when the
  !> call itself is refused (t, sizes, threads < 0), first_failed = 0 and every
  !> code is status%code.  threads: OpenMP threads (0: the OpenMP default).
  !> control (optional, pendula_control): cancel flag (finished states keep
  !> their results, the rest get PENDULA_ERR_CANCELLED) and progress
  !> (finished states).  max_steps: per-state step budget (default 1e9).
  !> drive (optional): one periodic drive for every state (as taylor_solve's).
  subroutine taylor_batch_solve(t, theta0, omega0, w0, gamma, tol, theta, omega, err, codes, steps, order, &
                                status, threads, control, first_failed, max_steps, drive)
    real(wp), intent(in) :: t(:)  !< shared output times [s]: finite, strictly monotonic, size >= 1
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad], one per state (n = size(theta0))
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], n elements or one
    real(wp), intent(in) :: w0(:)  !< small-angle angular frequencies [1/s], > 0, n elements or one
    real(wp), intent(in) :: gamma(:)  !< damping rates [1/s], >= 0, n elements or one
    real(wp), intent(in) :: tol(:)  !< absolute accuracies [rad], in (0, 1], n elements or one
    real(wp), intent(out) :: theta(:, :)  !< theta(:, i) of state i [rad], shape (size(t), n)
    real(wp), intent(out) :: omega(:, :)  !< Omega(:, i) of state i [rad/s], shape (size(t), n)
    real(wp), intent(out) :: err(:, :)  !< error estimates of state i [rad], shape (size(t), n)
    integer, intent(out) :: codes(:)  !< status code of each state, n elements
    integer(i8), intent(out) :: steps(:)  !< steps taken by each state, n elements
    integer, intent(out) :: order(:)  !< series order of each state, n elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    integer, intent(in), optional :: threads  !< optional OpenMP thread count (0 or absent: the default)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag and progress counter (finished states) shared with another thread
    integer, intent(out), optional :: first_failed  !< optional: 1-based index of the first failed state (0: none)
    integer(i8), intent(in), optional :: max_steps  !< optional step budget per state, >= 1
    type(drive_t), intent(in), optional :: drive  !< optional periodic drive of every state (pendula_drive)
    integer :: n, i, nthreads, first, chunk, nchunks, c, ist
    integer, allocatable :: list(:), keys(:)   ! the states in the order the blocks take them, their orders
    integer(i8) :: budget
    type(status_t) :: st
    character(len=len(st%message)) :: first_message
    n = size(theta0)
    budget = TAYLOR_DEFAULT_MAX_STEPS
    if (present(max_steps)) budget = max_steps
    if (present(first_failed)) first_failed = 0
    call taylor_check(t, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0_wp, budget, status)
    if (status%code == PENDULA_OK) call check_batch_shapes(size(t), n, all([size(omega0), size(w0), size(gamma), &
                         size(tol)] == 1 .or. [size(omega0), size(w0), size(gamma), size(tol)] == n), 'omega0, w0, gamma and tol', &
                                                           theta, omega, size(codes), size(steps), 'steps', threads, status)
    call check_same_size('err', size(err), 'theta', size(theta), status)
    call check_same_size('order', size(order), 'steps', size(steps), status)
    if (present(drive)) call check_drive(drive, status)
    if (status%code == PENDULA_OK .and. .not. present(drive)) then
      allocate (list(n), keys(n), stat=ist)
      call check_alloc(ist, 'the order of the states', 2*int(n, i8), 4, status)
    end if
    if (status%code /= PENDULA_OK) then
      theta = failed_output()
      omega = failed_output()
      err = failed_output()
      codes = status%code
      steps = 0
      order = 0
      return
    end if
    nthreads = batch_threads(threads)
    if (present(drive)) then
      !$omp parallel do schedule(dynamic) num_threads(nthreads) if(nthreads > 1 .and. n > 1) default(shared) private(st)
      do i = 1, n
        call one_state(i, st)
        codes(i) = st%code
      end do
      !$omp end parallel do
    else
      ! chunks of a few blocks per thread and more than that: a lane that
      ! finishes takes the chunk's next state, so only a chunk's end idles lanes
      chunk = max(4*TAYLOR_LANES, min(64*TAYLOR_LANES, n/(4*nthreads) + 1))
      if (nthreads == 1) chunk = n
      nchunks = (n + chunk - 1)/chunk
      call taylor_lanes_list(t, theta0, omega0, w0, gamma, tol, budget, keys, list)
      !$omp parallel do schedule(dynamic) num_threads(nthreads) if(nthreads > 1 .and. nchunks > 1) default(shared)
      do c = 1, nchunks
        call taylor_lanes_run(t, list((c - 1)*chunk + 1:min(n, c*chunk)), theta0, omega0, w0, gamma, tol, budget, &
                              theta, omega, err, codes, steps, order, control)
      end do
      !$omp end parallel do
    end if
    first = 0
    do i = n, 1, -1
      if (codes(i) /= PENDULA_OK) first = i
    end do
    if (first == 0) return
    if (present(first_failed)) first_failed = first
    ! the first failed state's own message (computed again: only that one is shown)
    call one_state(first, st)
    first_message = st%message
    if (codes(first) == PENDULA_ERR_CANCELLED) first_message = ''
    call set_batch_error(status, codes, first, first_message)
    ! (after the message's rerun of the first failed state, which writes its outputs)
    call nan_failed(codes, theta)
    call nan_failed(codes, omega)
    call nan_failed(codes, err)

  contains

    subroutine one_state(k, sk)
      integer, intent(in) :: k
      type(status_t), intent(out) :: sk
      real(wp) :: ev1(1), ev2(1), ev3(1), t_fail
      integer :: evk(1), nev, outcome
      logical :: trunc
      theta(:, k) = failed_output()
      omega(:, k) = failed_output()
      err(:, k) = failed_output()
      steps(k) = 0
      order(k) = 0
      if (present(control)) then
        if (cancel_requested(control)) then
          sk%code = PENDULA_ERR_CANCELLED
          return
        end if
      end if
      call taylor_check(t(1:1), theta0(k), omega0(at(omega0, k)), w0(at(w0, k)), gamma(at(gamma, k)), &
                        tol(at(tol, k)), budget, sk)
      if (sk%code /= PENDULA_OK) return
      call taylor_run(t, theta0(k), omega0(at(omega0, k)), w0(at(w0, k)), gamma(at(gamma, k)), tol(at(tol, k)), &
                      .false., budget, theta(:, k), omega(:, k), err(:, k), ev1, evk, ev2, ev3, nev, trunc, steps(k), order(k), &
                      outcome, t_fail, drive=drive)
      if (present(control)) then
        if (cancel_requested(control)) outcome = PENDULA_ERR_CANCELLED
        call add_progress(control, 1_i8)
      end if
      call taylor_outcome(outcome, t_fail, budget, sk)
      if (sk%code /= PENDULA_OK) steps(k) = 0  ! its outputs: NaN below (nan_failed)
    end subroutine one_state

  end subroutine taylor_batch_solve

end module pendula_taylor_batch
