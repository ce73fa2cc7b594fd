!> SUNDIALS CVODE (Hindmarsh et al., ACM TOMS 31 (2005) 363; SUNDIALS 6.4)
!> for the nonlinear damped pendulum theta'' + gamma theta' + w0**2 sin(theta) = 0
!> (text eq. 2.2): variable-step, variable-order Adams (non-stiff) or BDF
!> (stiff), Newton iteration with a dense linear solver and the analytic
!> Jacobian, scalar relative/absolute tolerances, output at requested times and
!> root finding for turning points (Omega = 0) and zero crossings (theta = 0 mod 2 pi).
!>
!> Built only when the build found the SUNDIALS Fortran 2003 modules (meson and
!> CMake define PENDULA_WITH_SUNDIALS then; fpm users pass it in their flags);
!> otherwise pendula_cvode_unavailable.inc provides this module with the same
!> API, whose procedures return PENDULA_ERR_UNAVAILABLE.  One file defines the
!> module on both paths (the stand-in comes in by #include) because fpm finds
!> modules by scanning source text and rejects two files naming one module.
!>
!> The state vector is a SUNDIALS serial vector whose arithmetic operations
!> are replaced by length-2 kernels (pendula_cvode_vector; same results bit
!> for bit, about half the time per step).
!>
!> Thread safety: the parameters reach the callbacks through CVODE's user_data
!> (a pointer to the solver's own data); there is no module state.  cvode_solve
!> creates and frees its SUNDIALS objects inside one call, on every path; a
!> batch keeps one solver per thread (cvode_work_t) and restarts it for each
!> problem with CVodeReInit, through the same code as cvode_solve.  CVODE's own
!> error messages are captured (never printed) and returned in the status.
#ifdef PENDULA_WITH_SUNDIALS
module pendula_cvode
  use, intrinsic :: iso_c_binding
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_sci, format_int
  use pendula_status, only: status_t, set_error, check_positive, check_nonnegative, check_same_size, PENDULA_OK, &
                            check_alloc, PENDULA_ERR_SOLVER, PENDULA_ERR_MAXSTEPS, PENDULA_ERR_CANCELLED
  use pendula_control, only: CONTROL_SIZE
  use pendula_ode, only: ode_stats_t, check_problem, check_cvode_options, check_span, &
                         PENDULA_CVODE_ADAMS, PENDULA_CVODE_BDF, PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO
  use fsundials_context_mod, only: FSUNContext_Create, FSUNContext_Free
  use fsundials_nvector_mod, only: N_Vector, FN_VGetArrayPointer, FN_VDestroy
  use fsundials_matrix_mod, only: SUNMatrix, FSUNMatDestroy
  use fsundials_linearsolver_mod, only: SUNLinearSolver, FSUNLinSolFree
  use fnvector_serial_mod, only: FN_VNew_Serial
  use fsunmatrix_dense_mod, only: FSUNDenseMatrix
  use fsunlinsol_dense_mod, only: FSUNLinSol_Dense
  use fcvode_mod
  use pendula_cvode_vector, only: specialise_pair_ops
  use pendula_constants, only: pi
  use pendula_drive, only: drive_t, check_drive, DRIVE_PIVOT
  use pendula_cvode_glue, only: cv_data_t, rhs, jacobian, relative_weights, root_functions, capture_error, &
                                failed, collect_stats, poll, CV_POLL_EVALS
  implicit none
  private
  public :: cvode_solve, cvode_solve_events, cvode_available
  ! one solver reused for many problems (pendula_cvode_batch)
  public :: cvode_work_t, cvode_work_open, cvode_work_solve, cvode_work_close
  public :: PENDULA_CVODE_ADAMS, PENDULA_CVODE_BDF, PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO

  !> A CVODE solver that outlives one problem (see cvode_work_open): the
  !> SUNDIALS context, state vector, solver memory, dense matrix and linear
  !> solver, and the callbacks' data (allocated, so that the address CVODE
  !> holds as user_data stays valid wherever the work is copied).
  type :: cvode_work_t
    private
    type(c_ptr) :: ctx = c_null_ptr
    type(c_ptr) :: mem = c_null_ptr
    type(N_Vector), pointer :: y => null()
    type(SUNMatrix), pointer :: amat => null()
    type(SUNLinearSolver), pointer :: ls => null()
    type(cv_data_t), pointer :: data => null()
    integer :: method = 0
    logical :: roots = .false.
  end type cvode_work_t

contains

  !> True: this build includes SUNDIALS CVODE.
  pure logical function cvode_available()
    cvode_available = .true.
  end function cvode_available

  !> Integrate theta'' + gamma theta' + w0**2 sin(theta) = 0 with CVODE and
  !> return theta(i) [rad], omega(i) [rad/s] at the output times t(i) [s].
  !>
  !> t: strictly increasing, finite, size >= 1; t(1) is the initial time of
  !> (theta0, omega0); t(n) - t(1) must not overflow.  w0 > 0, gamma >= 0 [1/s].
  !> rtol > 0, atol >= 0: CVODE keeps each step's local error below
  !> rtol |y| + atol (the global error is typically 1-100x that); atol = 0 is
  !> pure relative control, normwise (see relative_weights).  method: PENDULA_CVODE_ADAMS (non-stiff) or
  !> PENDULA_CVODE_BDF (stiff, e.g. gamma >> w0).  max_steps >= 1: total step
  !> budget for the whole run.  theta, omega: size(t).  stats: all counters of
  !> ode_stats_t.  Errors: bad arguments (outputs zero); CVODE failures
  !> (PENDULA_ERR_SOLVER) and exhausted budget (PENDULA_ERR_MAXSTEPS) with
  !> CVODE's reason, outputs before the failure time kept, later ones zero.
  !> control (optional, see pendula_control): its cancel flag is polled every
  !> 256 right-hand-side evaluations (tens of microseconds); a cancelled run
  !> returns PENDULA_ERR_CANCELLED like a failure (outputs reached kept, the
  !> solver memory freed).  Progress counts right-hand-side evaluations.
  !> drive (optional, pendula_drive): the driven pendulum instead, with the
  !> drive phase psi0 + Omega (t - t(1)) (psi0 = Omega t(1) + phi reduced
  !> once), as exact as CVODE's time however many periods run.
  subroutine cvode_solve(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, &
                         theta, omega, stats, status, control, drive)
    real(wp), intent(in) :: t(:)
    !< output times [s]: finite, strictly increasing, size >= 1; t(1) is the initial time
    real(wp), intent(in) :: theta0  !< initial angle theta(t(1)) [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity Omega(t(1)) [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency sqrt(g/l) [1/s], finite, > 0
    real(wp), intent(in) :: gamma  !< damping rate b/m [1/s], finite, >= 0
    real(wp), intent(in) :: rtol  !< relative tolerance, > 0
    real(wp), intent(in) :: atol  !< absolute tolerance [rad, rad/s], >= 0 (0: pure relative control)
    integer, intent(in) :: method  !< PENDULA_CVODE_ADAMS (non-stiff) or PENDULA_CVODE_BDF (stiff)
    integer(i8), intent(in) :: max_steps  !< step budget for the whole run, >= 1
    real(wp), intent(out) :: theta(:)  !< angle theta(t(i)) [rad], size(t) elements
    real(wp), intent(out) :: omega(:)  !< angular velocity Omega(t(i)) [rad/s], size(t) elements
    type(ode_stats_t), intent(out) :: stats  !< solver counters of the run (ode_stats_t)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    integer(i8), intent(inout), volatile, optional, target :: control(CONTROL_SIZE)
    !< optional cancel flag (polled every 256 rhs evaluations) and progress counter (see
    !< pendula_control)
    type(drive_t), intent(in), optional :: drive  !< optional drive (pendula_drive): the driven pendulum
    real(wp) :: et(0), eth(0), eom(0)
    integer :: ek(0), n_events
    logical :: truncated
    call solve(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, .false., &
               theta, omega, et, ek, eth, eom, n_events, truncated, stats, status, control, drive)
  end subroutine cvode_solve

  !> As cvode_solve, and also locate the events: turning points (Omega = 0,
  !> kind PENDULA_EVENT_TURNING) and zero crossings (theta = 0 mod 2 pi, kind
  !> PENDULA_EVENT_ZERO) in (t(1), t(n)], in time order, with the state there
  !> (event_theta, event_omega).  A root exactly at t(1) (e.g. theta0 = 0) is
  !> not reported.  The event arrays (all of one size, the maximum number of
  !> events kept, may be 0) receive the first n_events; truncated is true when
  !> more occurred.  Event times are accurate to about the integration error.
  !> control, drive: as for cvode_solve.
  subroutine cvode_solve_events(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, &
                                theta, omega, event_t, event_kind, event_theta, event_omega, n_events, truncated, stats, status, &
                                control, drive)
    real(wp), intent(in) :: t(:)  !< output times [s], as for cvode_solve
    real(wp), intent(in) :: theta0  !< initial angle [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    real(wp), intent(in) :: rtol  !< relative tolerance, > 0
    real(wp), intent(in) :: atol  !< absolute tolerance, >= 0
    integer, intent(in) :: method  !< PENDULA_CVODE_ADAMS (non-stiff) or PENDULA_CVODE_BDF (stiff)
    integer(i8), intent(in) :: max_steps  !< step budget for the whole run, >= 1
    real(wp), intent(out) :: theta(:)  !< theta(t(i)) [rad], size(t)
    real(wp), intent(out) :: omega(:)  !< Omega(t(i)) [rad/s], size(t)
    real(wp), intent(out) :: event_t(:)  !< event times [s] (the first n_events are set)
    real(wp), intent(out) :: event_theta(:)  !< theta at each event [rad]
    real(wp), intent(out) :: event_omega(:)  !< Omega at each event [rad/s]
    integer, intent(out) :: event_kind(:)  !< PENDULA_EVENT_TURNING or PENDULA_EVENT_ZERO per event
    integer, intent(out) :: n_events  !< number of events stored
    logical, intent(out) :: truncated  !< true when more events occurred than the arrays hold
    type(ode_stats_t), intent(out) :: stats  !< solver counters of the run (ode_stats_t)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    integer(i8), intent(inout), volatile, optional, target :: control(CONTROL_SIZE)
    !< optional cancel flag (polled every 256 rhs evaluations) and progress counter (see
    !< pendula_control)
    type(drive_t), intent(in), optional :: drive  !< optional drive (pendula_drive): the driven pendulum
    call solve(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, .true., &
               theta, omega, event_t, event_kind, event_theta, event_omega, n_events, truncated, stats, status, control, drive)
  end subroutine cvode_solve_events

  subroutine solve(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, with_events, &
                   theta, omega, event_t, event_kind, event_theta, event_omega, n_events, truncated, stats, status, control, drive)
    real(wp), intent(in) :: t(:), theta0, omega0, w0, gamma, rtol, atol
    integer, intent(in) :: method
    integer(i8), intent(in) :: max_steps
    logical, intent(in) :: with_events
    real(wp), intent(out) :: theta(:), omega(:)
    real(wp), intent(out) :: event_t(:), event_theta(:), event_omega(:)
    integer, intent(out) :: event_kind(:)
    integer, intent(out) :: n_events
    logical, intent(out) :: truncated
    type(ode_stats_t), intent(out) :: stats
    type(status_t), intent(out) :: status
    integer(i8), intent(inout), volatile, optional, target :: control(CONTROL_SIZE)
    type(drive_t), intent(in), optional :: drive
    type(cvode_work_t) :: work

    theta = 0
    omega = 0
    event_t = 0
    event_kind = 0
    event_theta = 0
    event_omega = 0
    n_events = 0
    truncated = .false.
    call check_call(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, size(theta), size(omega), status)
    ! event_t's size is the maximum number of events kept
    call check_same_size('event_kind', size(event_kind), 'event_t', size(event_t), status)
    call check_same_size('event_theta', size(event_theta), 'event_t', size(event_t), status)
    call check_same_size('event_omega', size(event_omega), 'event_t', size(event_t), status)
    call check_span(t, status)
    if (present(drive)) call check_drive(drive, status)
    if (status%code /= PENDULA_OK) return
    theta(1) = theta0
    omega(1) = omega0
    if (size(t) == 1) return
    ! A solver of its own for this one call, freed on every path.
    call cvode_work_open(work, method, status)
    if (status%code == PENDULA_OK) call run(work, t, theta0, omega0, w0, gamma, rtol, atol, max_steps, &
                            with_events, .true., theta, omega, event_t, event_kind, event_theta, event_omega, n_events, truncated, &
                                            stats, status, control, drive)
    call cvode_work_close(work, status)
  end subroutine solve

  ! The argument checks of solve and cvode_work_solve, in this order: the
  ! problem, the tolerances, method and budget, the outputs' sizes
  ! (n_theta, n_omega) against t.
  pure subroutine check_call(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, n_theta, n_omega, status)
    real(wp), intent(in) :: t(:), theta0, omega0, w0, gamma, rtol, atol
    integer, intent(in) :: method, n_theta, n_omega
    integer(i8), intent(in) :: max_steps
    type(status_t), intent(inout) :: status
    call check_problem(t, theta0, omega0, w0, gamma, status)
    call check_positive('rtol', rtol, status)
    call check_nonnegative('atol', atol, status)
    call check_cvode_options(method, max_steps, status)
    call check_same_size('theta', n_theta, 't', size(t), status)
    call check_same_size('omega', n_omega, 't', size(t), status)
  end subroutine check_call

  !> Create a CVODE solver for `method` (PENDULA_CVODE_ADAMS or
  !> PENDULA_CVODE_BDF) in `work`, to be used for any number of problems by
  !> cvode_work_solve and released by cvode_work_close (also after a failed
  !> open).  Its set-up (SUNDIALS context, state vector, solver memory, dense
  !> linear solver, about 29 us) is paid here once.  A work belongs to one
  !> thread at a time; works share nothing.  Errors: method out of range
  !> (PENDULA_ERR_DOMAIN), `work` already open or a SUNDIALS allocation
  !> failure (PENDULA_ERR_SOLVER).
  subroutine cvode_work_open(work, method, status)
    type(cvode_work_t), intent(inout) :: work
    !< the work to open (must not be open; cvode_work_close releases it)
    integer, intent(in) :: method  !< PENDULA_CVODE_ADAMS or PENDULA_CVODE_BDF, fixed for the work
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    real(c_double), pointer :: yv(:)
    integer(c_int) :: ierr, lmm
    logical :: ok
    call check_cvode_options(method, 1_i8, status)
    if (status%code /= PENDULA_OK) return
    if (associated(work%data)) then
      call set_error(status, PENDULA_ERR_SOLVER, 'CVODE: this work is already open (close it first)')
      return
    end if
    allocate (work%data, stat=ierr)
    call check_alloc(int(ierr), 'the CVODE work''s data', 1_i8, int(storage_size(work%data)/8), status)
    if (status%code /= PENDULA_OK) return
    work%method = method
    ! One pass through the set-up; the first failure skips the rest (the
    ! `block` exits) and cvode_work_close frees whatever was made.
    setup: block
      ierr = FSUNContext_Create(c_null_ptr, work%ctx)
      if (fail(ierr, 'SUNContext_Create')) exit setup
      work%y => FN_VNew_Serial(2_c_int64_t, work%ctx)
      if (.not. associated(work%y)) then
        call set_error(status, PENDULA_ERR_SOLVER, 'CVODE: N_VNew_Serial could not allocate the state vector')
        exit setup
      end if
      ! Length-2 arithmetic kernels instead of the generic serial ones (the
      ! vector operations are most of CVODE's work for N = 2); CVODE's work
      ! vectors, cloned from y in CVodeInit, inherit them.
      call specialise_pair_ops(work%y, ok)
      if (.not. ok) then
        call set_error(status, PENDULA_ERR_SOLVER, 'CVODE: the state vector is not a serial vector of length 2')
        exit setup
      end if
      yv => FN_VGetArrayPointer(work%y)
      yv = 0   ! each problem sets its own initial state (run: CVodeReInit)
      lmm = CV_ADAMS
      if (method == PENDULA_CVODE_BDF) lmm = CV_BDF
      work%mem = FCVodeCreate(lmm, work%ctx)
      if (.not. c_associated(work%mem)) then
        call set_error(status, PENDULA_ERR_SOLVER, 'CVODE: CVodeCreate could not allocate the solver memory')
        exit setup
      end if
      ! From here on every CVODE message goes to capture_error, never to stderr
      ! (SUNDIALS would fprintf it): no stdio from threads, and the text is kept.
      ierr = FCVodeSetErrHandlerFn(work%mem, c_funloc(capture_error), c_loc(work%data))
      if (fail(ierr, 'CVodeSetErrHandlerFn')) exit setup
      ierr = FCVodeInit(work%mem, c_funloc(rhs), 0.0_c_double, work%y)
      if (fail(ierr, 'CVodeInit')) exit setup
      ierr = FCVodeSetUserData(work%mem, c_loc(work%data))
      if (fail(ierr, 'CVodeSetUserData')) exit setup
      work%amat => FSUNDenseMatrix(2_c_int64_t, 2_c_int64_t, work%ctx)
      if (.not. associated(work%amat)) then
        call set_error(status, PENDULA_ERR_SOLVER, 'CVODE: SUNDenseMatrix could not allocate the Jacobian')
        exit setup
      end if
      work%ls => FSUNLinSol_Dense(work%y, work%amat, work%ctx)
      if (.not. associated(work%ls)) then
        call set_error(status, PENDULA_ERR_SOLVER, 'CVODE: SUNLinSol_Dense could not create the linear solver')
        exit setup
      end if
      ierr = FCVodeSetLinearSolver(work%mem, work%ls, work%amat)
      if (fail(ierr, 'CVodeSetLinearSolver')) exit setup
      ierr = FCVodeSetJacFn(work%mem, c_funloc(jacobian))
      if (fail(ierr, 'CVodeSetJacFn')) exit setup
    end block setup
    if (status%code /= PENDULA_OK) call cvode_work_close(work, status)
  contains
    logical function fail(flag, what)
      integer(c_int), intent(in) :: flag
      character(len=*), intent(in) :: what
      fail = failed(flag, what, work%data%errmsg, status)
    end function fail
  end subroutine cvode_work_open

  !> Free everything cvode_work_open made (safe on a work never opened or
  !> already closed); a SUNDIALS failure to free is recorded in status unless
  !> it already holds an error.
  subroutine cvode_work_close(work, status)
    type(cvode_work_t), intent(inout) :: work  !< reusable CVODE solver state (opened by cvode_work_open)
    type(status_t), intent(inout) :: status  !< receives an error if freeing fails; left as it is otherwise
    integer(c_int) :: ierr
    if (c_associated(work%mem)) call FCVodeFree(work%mem)
    work%mem = c_null_ptr
    if (associated(work%ls)) then
      ierr = FSUNLinSolFree(work%ls)
      if (ierr /= 0) call set_error(status, PENDULA_ERR_SOLVER, 'CVODE: SUNLinSolFree failed with flag '// &
                                    format_int(ierr))
    end if
    if (associated(work%amat)) call FSUNMatDestroy(work%amat)
    if (associated(work%y)) call FN_VDestroy(work%y)
    nullify (work%ls, work%amat, work%y)
    if (c_associated(work%ctx)) then
      ierr = FSUNContext_Free(work%ctx)
      if (ierr /= 0) call set_error(status, PENDULA_ERR_SOLVER, 'CVODE: SUNContext_Free failed with flag '// &
                                    format_int(ierr))
    end if
    work%ctx = c_null_ptr
    if (associated(work%data)) deallocate (work%data)
    work%method = 0
    work%roots = .false.
  end subroutine cvode_work_close

  !> cvode_solve for one problem on an open work (the work's method; no
  !> events): the same checks, results, stats and status as cvode_solve, bit
  !> for bit, without the solver set-up (CVodeReInit restarts the solver
  !> memory from scratch).  control: its cancel flag is polled as in
  !> cvode_solve, but progress is not counted (a batch counts states).
  !> Errors: as cvode_solve; a work that is not open: PENDULA_ERR_SOLVER
  !> (after the argument checks, which need no solver).  drive: as cvode_solve.
  !> reached (optional): how many leading outputs hold the solution (size(t)
  !> on success, those before the failure time on a failure, 0 when refused).
  subroutine cvode_work_solve(work, t, theta0, omega0, w0, gamma, rtol, atol, max_steps, &
                              theta, omega, stats, status, control, drive, reached)
    type(cvode_work_t), intent(inout) :: work  !< reusable CVODE solver state (opened by cvode_work_open)
    real(wp), intent(in) :: t(:)  !< output times [s], as for cvode_solve
    real(wp), intent(in) :: theta0, omega0  !< theta0, omega0: initial state [rad], [rad/s], finite
    real(wp), intent(in) :: w0, gamma  !< w0, gamma: frequency > 0 and damping rate >= 0 [1/s]
    real(wp), intent(in) :: rtol, atol  !< rtol, atol: tolerances as for cvode_solve (rtol > 0, atol >= 0)
    integer(i8), intent(in) :: max_steps  !< step budget for the whole run, >= 1
    real(wp), intent(out) :: theta(:)  !< theta(t(i)) [rad], size(t)
    real(wp), intent(out) :: omega(:)  !< Omega(t(i)) [rad/s], size(t)
    type(ode_stats_t), intent(out) :: stats  !< solver counters of the run (ode_stats_t)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    integer(i8), intent(inout), volatile, optional, target :: control(CONTROL_SIZE)
    !< optional cancel flag (polled every 256 rhs evaluations) and progress counter (see
    !< pendula_control)
    type(drive_t), intent(in), optional :: drive  !< optional drive (pendula_drive): the driven pendulum
    integer, intent(out), optional :: reached  !< optional: leading outputs that hold the solution
    real(wp) :: et(0), eth(0), eom(0)
    integer :: ek(0), n_events
    logical :: truncated
    theta = 0
    omega = 0
    if (present(reached)) reached = 0
    call check_call(t, theta0, omega0, w0, gamma, rtol, atol, PENDULA_CVODE_ADAMS, max_steps, size(theta), &
                    size(omega), status)
    call check_span(t, status)
    if (present(drive)) call check_drive(drive, status)
    if (status%code /= PENDULA_OK) return
    theta(1) = theta0
    omega(1) = omega0
    if (present(reached)) reached = 1
    if (size(t) == 1) return
    if (.not. associated(work%data)) then
      call set_error(status, PENDULA_ERR_SOLVER, 'CVODE: the work is not open (call cvode_work_open first)')
      theta(1) = 0
      omega(1) = 0
      if (present(reached)) reached = 0
      return
    end if
    call run(work, t, theta0, omega0, w0, gamma, rtol, atol, max_steps, .false., .false., &
             theta, omega, et, ek, eth, eom, n_events, truncated, stats, status, control, drive, reached)
  end subroutine cvode_work_solve

  !> One problem on an open work, arguments already checked and size(t) >= 2:
  !> CVodeReInit at (theta0, omega0), this problem's tolerances, stop time and
  !> event functions, then the output loop.  eval_progress: count
  !> right-hand-side evaluations as progress in control (else only poll its
  !> cancel flag).  reached: the leading outputs that hold the solution.
  subroutine run(work, t, theta0, omega0, w0, gamma, rtol, atol, max_steps, with_events, eval_progress, &
                 theta, omega, event_t, event_kind, event_theta, event_omega, n_events, truncated, stats, status, control, drive, &
                 reached)
    type(cvode_work_t), intent(inout) :: work
    real(wp), intent(in) :: t(:), theta0, omega0, w0, gamma, rtol, atol
    integer(i8), intent(in) :: max_steps
    logical, intent(in) :: with_events, eval_progress
    real(wp), intent(inout) :: theta(:), omega(:)
    real(wp), intent(inout) :: event_t(:), event_theta(:), event_omega(:)
    integer, intent(inout) :: event_kind(:)
    integer, intent(inout) :: n_events
    logical, intent(inout) :: truncated
    type(ode_stats_t), intent(inout) :: stats
    type(status_t), intent(inout) :: status
    integer(i8), intent(inout), volatile, optional, target :: control(CONTROL_SIZE)
    type(drive_t), intent(in), optional :: drive
    integer, intent(out), optional :: reached

    type(cv_data_t), pointer :: cb   ! what the callbacks see
    real(c_double), pointer :: yv(:)
    real(c_double) :: tret(1)
    integer(c_int) :: ierr, roots(2)
    integer(c_long) :: nst(1)
    integer :: i, k, nt
    logical :: ok
    real(c_double) :: span, tau_end

    nt = size(t)
    span = t(nt) - t(1)
    ! Everything the callbacks see is set afresh: nothing of the previous
    ! problem on this work survives (its message, counters, cancel state).
    cb => work%data
    cb = cv_data_t()
    cb%w0sq = w0*w0
    cb%gamma = gamma
    cb%w0 = w0
    cb%rtol = rtol
    cb%tscale = 0
    if (span < 2.0_wp**(-64)) cb%tscale = exponent(span)
    cb%eval_progress = eval_progress
    if (present(drive)) then
      cb%driven = .true.
      cb%pivot = drive%kind == DRIVE_PIVOT
      cb%amp = drive%amplitude
      cb%freq = drive%frequency
      ! the phase at t(1), reduced once; the callbacks add Omega (t - t(1))
      cb%psi0 = modulo(drive%frequency*t(1) + drive%phase, 2*pi)
    end if
    tau_end = tau(t(nt))
    if (present(control)) cb%control = c_loc(control)
    yv => FN_VGetArrayPointer(work%y)
    yv(1) = theta0
    yv(2) = omega0
    i = 2

    steps: block
      ! CVodeReInit resets the history, step size, order and counters; the
      ! per-problem settings follow (tstop is cleared when CVODE reaches it).
      ierr = FCVodeReInit(work%mem, 0.0_c_double, work%y)
      if (fail(ierr, 'CVodeReInit')) exit steps
      if (atol > 0) then
        ierr = FCVodeSStolerances(work%mem, rtol, atol)
        if (fail(ierr, 'CVodeSStolerances')) exit steps
      else
        ! pure relative control, normwise (see relative_weights)
        ierr = FCVodeWFtolerances(work%mem, c_funloc(relative_weights))
        if (fail(ierr, 'CVodeWFtolerances')) exit steps
      end if
      ! Stop exactly at the last output instead of stepping past it.
      ierr = FCVodeSetStopTime(work%mem, tau_end)
      if (fail(ierr, 'CVodeSetStopTime')) exit steps
      if (with_events) then
        ierr = FCVodeRootInit(work%mem, 2_c_int, c_funloc(root_functions))
        if (fail(ierr, 'CVodeRootInit')) exit steps
        work%roots = .true.
        ! theta0 = 0 or omega0 = 0 makes a root function vanish at t(1);
        ! CVODE then deactivates it until it moves away: not a warning here.
        ierr = FCVodeSetNoInactiveRootWarn(work%mem)
        if (fail(ierr, 'CVodeSetNoInactiveRootWarn')) exit steps
      else if (work%roots) then
        ierr = FCVodeRootInit(work%mem, 0_c_int, c_null_funptr)
        if (fail(ierr, 'CVodeRootInit')) exit steps
        work%roots = .false.
      end if

      do while (i <= nt)
        ! The budget is for the whole run; CVODE's mxstep counts per call.
        ierr = FCVodeGetNumSteps(work%mem, nst)
        if (fail(ierr, 'CVodeGetNumSteps')) exit steps
        if (int(nst(1), i8) >= max_steps) then
          call set_error(status, PENDULA_ERR_MAXSTEPS, 'CVODE used the whole step budget max_steps = '// &
                         format_int(max_steps)//' before t = '//format_sci(t(i), 8)//': raise max_steps, loosen rtol/atol,'// &
                         ' or use method BDF if the problem is stiff')
          exit steps
        end if
        ierr = FCVodeSetMaxNumSteps(work%mem, int(max_steps - int(nst(1), i8), c_long))
        if (fail(ierr, 'CVodeSetMaxNumSteps')) exit steps
        ierr = FCVode(work%mem, merge(tau_end, tau(t(i)), i == nt), work%y, tret, CV_NORMAL)
        if (ierr < 0 .and. cb%cancelled) then
          call set_error(status, PENDULA_ERR_CANCELLED, 'CVODE cancelled before t = '//format_sci(t(i), 8)// &
                         ' (interrupted by the caller)')
          exit steps
        end if
        if (ierr == CV_ROOT_RETURN) then
          ierr = FCVodeGetRootInfo(work%mem, roots)
          if (fail(ierr, 'CVodeGetRootInfo')) exit steps
          do k = 1, 2
            if (roots(k) == 0) cycle
            if (n_events < size(event_t)) then
              n_events = n_events + 1
              event_t(n_events) = min(t(1) + scale(tret(1), cb%tscale), t(nt))
              event_kind(n_events) = merge(PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO, k == 1)
              event_theta(n_events) = yv(1)
              event_omega(n_events) = yv(2)
            else
              truncated = .true.
            end if
          end do
          cycle
        end if
        if (ierr == CV_TOO_MUCH_WORK) then
          call set_error(status, PENDULA_ERR_MAXSTEPS, 'CVODE used the whole step budget max_steps = '// &
                         format_int(max_steps)//' before t = '//format_sci(t(i), 8)//': raise max_steps, loosen rtol/atol,'// &
                         ' or use method BDF if the problem is stiff')
          exit steps
        end if
        if (ierr /= CV_SUCCESS .and. ierr /= CV_TSTOP_RETURN) then
          if (fail(ierr, 'CVode')) exit steps
        end if
        theta(i) = yv(1)
        omega(i) = yv(2)
        i = i + 1
      end do
    end block steps
    ! progress: the evaluations since the last poll
    if (c_associated(cb%control)) &
      call poll(cb%control, merge(mod(cb%evals, CV_POLL_EVALS), 0_i8, eval_progress), ok)

    call collect_stats(work%mem, with_events, stats, status)
    if (status%code /= PENDULA_OK) then
      ! Keep the outputs reached before the failure; zero the rest.
      theta(i:) = 0
      omega(i:) = 0
    end if
    if (present(reached)) reached = merge(nt, i - 1, status%code == PENDULA_OK)

  contains

    logical function fail(flag, what)
      integer(c_int), intent(in) :: flag
      character(len=*), intent(in) :: what
      fail = failed(flag, what, cb%errmsg, status)
    end function fail

    !> An output time in CVODE's time tau (exact for t within a factor 2 of t(1)).
    pure real(c_double) function tau(tt)
      real(wp), intent(in) :: tt
      tau = scale(tt - t(1), -cb%tscale)
    end function tau

  end subroutine run

end module pendula_cvode
#else
#include "pendula_cvode_unavailable.inc"
#endif
