!> SUNDIALS CVODE (pendula_cvode) for many pendulums in one call: each state
!> i has its own theta0(i), omega0(i), w0(i), gamma(i), rtol(i), atol(i);
!> the output grid t, the method and the step budget are shared.
!>
!> Why: CVODE's set-up (SUNDIALS context, vectors, solver memory, dense
!> linear solver: about 29 us) costs a sizeable part of a short run.  Here
!> each thread opens one solver (cvode_work_t) and restarts it for every
!> state with CVodeReInit, through the very code cvode_solve runs
!> (cvode_work_solve), so every state's outputs, counters and status are
!> bit-identical to cvode_solve for that state alone, whichever states came
!> before it on the same solver.  States are spread over OpenMP threads (when
!> built with -Dopenmp), one solver per thread; threads share nothing but the
!> output arrays, each state written by one thread.
!>
!> No SUNDIALS symbol is used here, so this module builds unchanged without
!> SUNDIALS; the stand-in pendula_cvode then makes every call report
!> PENDULA_ERR_UNAVAILABLE.  Events are not supported in batch mode (call
!> cvode_solve_events per state).
module pendula_cvode_batch
  use, intrinsic :: iso_fortran_env, only: int64
  use pendula_kinds, only: wp, i8
  use pendula_status, only: status_t, set_error, PENDULA_OK, PENDULA_ERR_CANCELLED, PENDULA_ERR_SIZE, PENDULA_MSG_LEN
  use pendula_format, only: format_int
  use pendula_drive, only: drive_t
  use pendula_control, only: CONTROL_SIZE, cancel_requested, add_progress
  use pendula_ode, only: ode_stats_t, check_problem, check_span, check_cvode_options, check_batch_shapes, &
                         at => batch_index
  use pendula_batch_support, only: batch_threads, set_batch_error, failed_output
  use pendula_cvode, only: cvode_available, cvode_work_t, cvode_work_open, cvode_work_solve, cvode_work_close
  implicit none
  private
  public :: cvode_batch_solve

contains

  !> CVODE for n = size(theta0) states over the shared output grid t [s]
  !> (strictly increasing, finite, size >= 1, t(n) - t(1) finite).  State i
  !> starts at (theta0(i) [rad], omega0(i) [rad/s]) at t(1) with w0(i) > 0,
  !> gamma(i) >= 0 [1/s], tolerances rtol(i) > 0, atol(i) >= 0 (as
  !> cvode_solve); omega0, w0, gamma, rtol and atol have n elements or one
  !> (then shared).  method (PENDULA_CVODE_ADAMS or PENDULA_CVODE_BDF) and the
  !> per-state step budget max_steps >= 1 are shared.  Outputs theta(:, i),
  !> omega(:, i) (shape (size(t), n): each state's series contiguous), stats(i)
  !> and codes(i) are bit-identical to cvode_solve for that state, except
  !> that a failed state (bad argument, CVODE failure, exhausted budget) is NaN
  !> (failed_output, pendula_batch_support) where cvode_solve returns zero:
  !> it keeps the outputs before its failure time and is NaN from there on
  !> (all NaN for a refused argument); the other states are unaffected.
  !>
  !> status: OK when every state succeeded; PENDULA_ERR_CANCELLED when the
  !> call was cancelled; otherwise the first failed state's code, with its
  !> index and cvode_solve's message for it.  first_failed: that state (0:
  !> none).  When the call itself is refused (bad t, method, max_steps, array
  !> sizes, threads < 0, or no CVODE in this build), first_failed = 0,
  !> every codes(i) holds status%code and every output is NaN.
  !>
  !> threads: OpenMP threads (0 = the OpenMP default, which honours
  !> OMP_NUM_THREADS; ignored without OpenMP); each opens one solver.  GNU
  !> OpenMP is not fork-safe: a process forked after a call with more than one
  !> thread must pass threads = 1.  control (optional, pendula_control):
  !> control(CONTROL_CANCEL) /= 0 stops the call within about 0.1 ms per
  !> thread (the solver polls it every 256 right-hand-side evaluations);
  !> finished states keep their results, unfinished ones get NaN outputs
  !> and PENDULA_ERR_CANCELLED; control(CONTROL_PROGRESS) counts finished states.
  !> drive (optional, pendula_drive; one element or n): the driven pendulum,
  !> each state bit-identical to cvode_solve with its drive.
  subroutine cvode_batch_solve(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, &
                               theta, omega, codes, stats, status, threads, control, first_failed, drive)
    real(wp), intent(in) :: t(:)  !< shared output times [s]: finite, strictly increasing, size >= 1
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad], one per state (n = size(theta0))
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], n elements or one
    real(wp), intent(in) :: w0(:)  !< small-angle angular frequencies [1/s], > 0, n elements or one
    real(wp), intent(in) :: gamma(:)  !< damping rates [1/s], >= 0, n elements or one
    real(wp), intent(in) :: rtol(:)  !< relative tolerances, > 0 (n elements or one)
    real(wp), intent(in) :: atol(:)  !< absolute tolerances [rad, rad/s], >= 0 (n elements or one)
    integer, intent(in) :: method  !< PENDULA_CVODE_ADAMS (non-stiff) or PENDULA_CVODE_BDF (stiff)
    integer(i8), intent(in) :: max_steps  !< step budget per state, >= 1
    real(wp), intent(out) :: theta(:, :)  !< theta(:, i) of state i [rad], shape (size(t), n)
    real(wp), intent(out) :: omega(:, :)  !< Omega(:, i) of state i [rad/s], shape (size(t), n)
    integer, intent(out) :: codes(:)  !< status code of each state, n elements
    type(ode_stats_t), intent(out) :: stats(:)  !< solver counters of each state, n elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    integer, intent(in), optional :: threads
    !< optional OpenMP thread count (0 or absent: the OpenMP default)
    integer(int64), intent(inout), volatile, optional, target :: control(CONTROL_SIZE)
    !< optional cancel flag and progress counter (finished states) shared with another thread
    integer, intent(out), optional :: first_failed
    !< optional: 1-based index of the first failed state (0: none)
    type(drive_t), intent(in), optional :: drive(:)  !< optional drives, one element or n: the driven pendulum
    type(cvode_work_t) :: probe
    character(len=PENDULA_MSG_LEN) :: first_msg
    integer :: n, i, nthreads, first
    n = size(theta0)
    if (present(first_failed)) first_failed = 0
    theta = 0
    omega = 0
    call check_call(t, n, omega0, w0, gamma, rtol, atol, method, max_steps, theta, omega, codes, stats, &
                    threads, status)
    if (present(drive) .and. status%code == PENDULA_OK) then
      if (size(drive) /= 1 .and. size(drive) /= n) call set_error(status, PENDULA_ERR_SIZE, 'drive has '// &
                                      format_int(size(drive))//' element(s): it must have one or one per state (size(theta0) = '// &
                                                                  format_int(n)//')')
    end if
    if (status%code == PENDULA_OK .and. .not. cvode_available()) then
      call cvode_work_open(probe, method, status)   ! the stand-in's explanation
      call cvode_work_close(probe, status)
    end if
    if (status%code /= PENDULA_OK) then
      codes = status%code
      theta = failed_output()
      omega = failed_output()
      return
    end if
    nthreads = batch_threads(threads)

    codes = PENDULA_ERR_CANCELLED   ! until its state is done
    first = n + 1
    first_msg = ''
    !$omp parallel num_threads(nthreads) if(nthreads > 1 .and. n > 1) default(shared)
    call run_states(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, theta, omega, codes, stats, &
                    first, first_msg, control, drive)
    !$omp end parallel

    ! Summary: the first failed state, with cvode_solve's own message for it.
    if (all(codes == PENDULA_OK)) return
    do i = 1, n
      if (codes(i) == PENDULA_ERR_CANCELLED) then
        theta(:, i) = failed_output()
        omega(:, i) = failed_output()
        stats(i) = ode_stats_t()
      end if
    end do
    if (present(first_failed)) first_failed = findloc(codes /= PENDULA_OK, .true., dim=1)
    call set_batch_error(status, codes, first, first_msg)
  end subroutine cvode_batch_solve

  !> One thread's share: open a solver (when some state needs one), take
  !> states from the shared loop, close it.  first/first_msg: the lowest failed
  !> state so far and its message (updated under a critical section).
  subroutine run_states(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, theta, omega, codes, &
                        stats, first, first_msg, control, drive)
    real(wp), intent(in) :: t(:), theta0(:), omega0(:), w0(:), gamma(:), rtol(:), atol(:)
    integer, intent(in) :: method
    integer(i8), intent(in) :: max_steps
    real(wp), intent(inout) :: theta(:, :), omega(:, :)
    integer, intent(inout) :: codes(:)
    type(ode_stats_t), intent(inout) :: stats(:)
    integer, intent(inout) :: first
    character(len=*), intent(inout) :: first_msg
    integer(int64), intent(inout), volatile, optional, target :: control(CONTROL_SIZE)
    type(drive_t), intent(in), optional :: drive(:)
    type(cvode_work_t) :: work
    type(status_t) :: opened, st
    integer :: i, reached
    ! A one-point grid needs no solver (cvode_solve returns the start).
    if (size(t) > 1) call cvode_work_open(work, method, opened)
    !$omp do schedule(dynamic)
    do i = 1, size(theta0)
      if (present(control)) then
        if (cancel_requested(control)) cycle   ! code stays PENDULA_ERR_CANCELLED
      end if
      reached = 0
      if (opened%code == PENDULA_OK .and. present(drive)) then
        call cvode_work_solve(work, t, theta0(i), omega0(at(omega0, i)), w0(at(w0, i)), gamma(at(gamma, i)), &
                              rtol(at(rtol, i)), atol(at(atol, i)), max_steps, theta(:, i), omega(:, i), stats(i), st, control, &
                              drive(min(i, size(drive))), reached=reached)
      else if (opened%code == PENDULA_OK) then
        call cvode_work_solve(work, t, theta0(i), omega0(at(omega0, i)), w0(at(w0, i)), gamma(at(gamma, i)), &
                              rtol(at(rtol, i)), atol(at(atol, i)), max_steps, theta(:, i), omega(:, i), stats(i), st, control, &
                              reached=reached)
      else
        st = opened   ! this thread has no solver: its states carry the reason
      end if
      if (st%code == PENDULA_ERR_CANCELLED) cycle
      codes(i) = st%code
      if (st%code /= PENDULA_OK) then
        ! cvode_solve's zeros after the failure time become NaN (no plausible number)
        theta(reached + 1:, i) = failed_output()
        omega(reached + 1:, i) = failed_output()
        !$omp critical (pendula_cvode_batch_first)
        if (i < first) then
          first = i
          first_msg = st%message
        end if
        !$omp end critical (pendula_cvode_batch_first)
      end if
      if (present(control)) call add_progress(control, 1_int64)
    end do
    !$omp end do
    call cvode_work_close(work, st)
  end subroutine run_states

  !> Checks of the call as a whole: t, method, max_steps, sizes, threads.
  subroutine check_call(t, n, omega0, w0, gamma, rtol, atol, method, max_steps, theta, omega, codes, stats, &
                        threads, status)
    real(wp), intent(in) :: t(:), omega0(:), w0(:), gamma(:), rtol(:), atol(:), theta(:, :), omega(:, :)
    integer, intent(in) :: n, method, codes(:)
    integer(i8), intent(in) :: max_steps
    type(ode_stats_t), intent(in) :: stats(:)
    integer, intent(in), optional :: threads
    type(status_t), intent(inout) :: status
    ! t alone (neutral state values): size, order, finiteness, span
    call check_problem(t, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, status)
    call check_span(t, status)
    call check_cvode_options(method, max_steps, status)
    if (status%code /= PENDULA_OK) return
    call check_batch_shapes(size(t), n, all([size(omega0), size(w0), size(gamma), size(rtol), size(atol)] == 1 &
                                            .or. [size(omega0), size(w0), size(gamma), size(rtol), size(atol)] == n), &
                            'omega0, w0, gamma, rtol and atol', theta, omega, size(codes), size(stats), 'stats', threads, status)
  end subroutine check_call

end module pendula_cvode_batch
