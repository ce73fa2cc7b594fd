!> The SUNDIALS side of pendula_cvode: the data CVODE hands its callbacks
!> (cv_data_t through user_data), the callbacks themselves (right-hand side,
!> analytic Jacobian, relative error weights, event functions, error capture)
!> and the translation of CVODE's flags and counters into status_t and
!> ode_stats_t.  pendula_cvode does the solver work on top of it.  Built, like
!> pendula_cvode_vector, only with SUNDIALS (PENDULA_WITH_SUNDIALS).
#ifdef PENDULA_WITH_SUNDIALS
module pendula_cvode_glue
  use, intrinsic :: iso_c_binding
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use pendula_kinds, only: i8
  use pendula_format, only: format_int, code_text
  use pendula_status, only: status_t, set_error, PENDULA_ERR_SOLVER
  use pendula_control, only: CONTROL_SIZE, cancel_requested, add_progress
  use pendula_ode, only: ode_stats_t, bottom_sign
  use fsundials_nvector_mod, only: N_Vector, FN_VGetArrayPointer
  use fsundials_matrix_mod, only: SUNMatrix
  use fsunmatrix_dense_mod, only: FSUNDenseMatrix_Data
  use fcvode_mod
  use pendula_cvode_vector, only: pair_t, pair_of
  implicit none
  private
  public :: cv_data_t, rhs, jacobian, relative_weights, root_functions, capture_error, failed, collect_stats, poll
  public :: CV_POLL_EVALS

  !> What the callbacks see through user_data: the parameters, the time
  !> scale, the tolerances of the pure relative mode (atol = 0), and room for
  !> the last error message CVODE reports, and the caller's control array
  !> (c_null_ptr: none) with the right-hand-side evaluations counted so far.
  !>
  !> CVODE integrates in tau = (t - t(1)) / T, T = 2**tscale: the undriven
  !> problem is autonomous, so moving the origin to t(1) costs nothing and lets a window
  !> of a few ulps at t(1) = 1e300 be resolved; T = 1 except for windows
  !> shorter than 2**-64 s, where CVODE's products of two times (e.g.
  !> (tstop - t) h) would underflow (t = [0, 1e-300] was refused).  The
  !> state stays (theta, Omega) in rad, rad/s; d/dtau = T d/dt, and T is a
  !> power of 2, so the scaling itself is exact.  With a drive (driven =
  !> .true., pendula_drive) the drive phase at time t is psi0 + Omega (t - t(1)),
  !> psi0 = Omega t(1) + phi reduced to [0, 2 pi) once per call: the phase
  !> is as exact as CVODE's own time tau, over any number of periods.
  type :: cv_data_t
    real(c_double) :: w0sq = 0
    real(c_double) :: gamma = 0
    integer :: tscale = 0
    real(c_double) :: w0 = 1
    real(c_double) :: rtol = 0
    character(len=200) :: errmsg = ''
    type(c_ptr) :: control = c_null_ptr
    integer(i8) :: evals = 0
    logical :: cancelled = .false.
    logical :: eval_progress = .true.
    logical :: driven = .false.
    logical :: pivot = .false.
    real(c_double) :: amp = 0
    real(c_double) :: freq = 0
    real(c_double) :: psi0 = 0
  end type cv_data_t

  !> Right-hand-side evaluations between two looks at the cancel flag (a few
  !> tens of microseconds of CVODE work); progress is counted in evaluations.
  integer(i8), parameter :: CV_POLL_EVALS = 256

  ! The names and meanings of CVODE's failure flags, for messages.
  integer, parameter :: FLAG_CODES(21) = [integer :: CV_TOO_MUCH_WORK, CV_TOO_MUCH_ACC, CV_ERR_FAILURE, &
                                                  CV_CONV_FAILURE, CV_LINIT_FAIL, CV_LSETUP_FAIL, CV_LSOLVE_FAIL, CV_RHSFUNC_FAIL, &
                                                 CV_FIRST_RHSFUNC_ERR, CV_REPTD_RHSFUNC_ERR, CV_UNREC_RHSFUNC_ERR, CV_RTFUNC_FAIL, &
                                         CV_NLS_INIT_FAIL, CV_NLS_SETUP_FAIL, CV_NLS_FAIL, CV_MEM_FAIL, CV_MEM_NULL, CV_ILL_INPUT, &
                                                                                             CV_NO_MALLOC, CV_BAD_T, CV_TOO_CLOSE]
  character(len=20), parameter :: FLAG_NAMES(21) = [character(len=20) :: 'CV_TOO_MUCH_WORK', &
                                                                                              'CV_TOO_MUCH_ACC', 'CV_ERR_FAILURE', &
                                        'CV_CONV_FAILURE', 'CV_LINIT_FAIL', 'CV_LSETUP_FAIL', 'CV_LSOLVE_FAIL', 'CV_RHSFUNC_FAIL', &
                                         'CV_FIRST_RHSFUNC_ERR', 'CV_REPTD_RHSFUNC_ERR', 'CV_UNREC_RHSFUNC_ERR', 'CV_RTFUNC_FAIL', &
                             'CV_NLS_INIT_FAIL', 'CV_NLS_SETUP_FAIL', 'CV_NLS_FAIL', 'CV_MEM_FAIL', 'CV_MEM_NULL', 'CV_ILL_INPUT', &
                                                                                         'CV_NO_MALLOC', 'CV_BAD_T', 'CV_TOO_CLOSE']
  integer, parameter :: MEANING_CODES(5) = [integer :: CV_TOO_MUCH_ACC, CV_ERR_FAILURE, CV_CONV_FAILURE, &
                                                                                                 CV_MEM_FAIL, CV_ILL_INPUT]
  character(len=60), parameter :: MEANINGS(5) = [character(len=60) :: 'the requested accuracy could not be met', &
                                                                   'repeated error-test failures (the step size hit its minimum)', &
                                                                'repeated nonlinear-solver convergence failures', 'out of memory', &
                                                                                                    'an input to CVODE was invalid']
  character(len=*), parameter :: MEANING_FALLBACK = 'see the SUNDIALS CVODE documentation'

contains

  !> Record a failed SUNDIALS call (flag < 0) with CVODE's own explanation
  !> (errmsg: the last error CVODE reported, if any).
  logical function failed(flag, what, errmsg, status)
    integer(c_int), intent(in) :: flag  !< return flag of the SUNDIALS call, < 0
    character(len=*), intent(in) :: what  !< name of the failed SUNDIALS call
    character(len=*), intent(in) :: errmsg  !< the last error message CVODE reported (may be blank)
    type(status_t), intent(inout) :: status
    !< the first error of the call is kept: set here only if nothing failed before
    character(len=:), allocatable :: why
    failed = flag < 0
    if (.not. failed) return
    why = trim(errmsg)
    if (len(why) == 0) why = flag_meaning(flag)
    if (flag == CV_TOO_MUCH_ACC) why = why//' (rtol/atol are below what double precision can deliver)'
    call set_error(status, PENDULA_ERR_SOLVER, 'CVODE: '//what//' failed with flag '// &
                   format_int(flag)//' ('//flag_name(flag)//'): '//why)
  end function failed

  !> Copy CVODE's counters into stats; a failing getter is itself an error.
  subroutine collect_stats(mem, with_events, stats, status)
    type(c_ptr), intent(in) :: mem  !< CVODE memory
    logical, intent(in) :: with_events  !< whether the root counters are read too
    type(ode_stats_t), intent(inout) :: stats  !< receives the counters
    type(status_t), intent(inout) :: status
    !< the first error of the call is kept: set here only if nothing failed before
    integer(c_long) :: v(1)
    integer(c_int) :: ierr
    ierr = FCVodeGetNumSteps(mem, v); call take(ierr, 'CVodeGetNumSteps', stats%steps)
    ierr = FCVodeGetNumRhsEvals(mem, v); call take(ierr, 'CVodeGetNumRhsEvals', stats%rhs_evals)
    ierr = FCVodeGetNumJacEvals(mem, v); call take(ierr, 'CVodeGetNumJacEvals', stats%jac_evals)
    ierr = FCVodeGetNumErrTestFails(mem, v); call take(ierr, 'CVodeGetNumErrTestFails', stats%err_test_fails)
    ierr = FCVodeGetNumNonlinSolvIters(mem, v); call take(ierr, 'CVodeGetNumNonlinSolvIters', stats%nonlin_iters)
    ierr = FCVodeGetNumNonlinSolvConvFails(mem, v)
    call take(ierr, 'CVodeGetNumNonlinSolvConvFails', stats%nonlin_fails)
    if (with_events) then
      ierr = FCVodeGetNumGEvals(mem, v); call take(ierr, 'CVodeGetNumGEvals', stats%root_evals)
    end if
  contains
    subroutine take(flag, what, dest)
      integer(c_int), intent(in) :: flag
      character(len=*), intent(in) :: what
      integer(i8), intent(out) :: dest
      dest = 0
      if (flag < 0) then
        call set_error(status, PENDULA_ERR_SOLVER, 'CVODE: '//what//' failed with flag '// &
                       format_int(flag)//' ('//flag_name(flag)//')')
      else
        dest = int(v(1), i8)
      end if
    end subroutine take
  end subroutine collect_stats

  ! ---- callbacks (C calling convention; parameters arrive in user_data) ----
  ! name='': no global C symbol, so no clash with a same-named C function of
  ! another library in the process (they were plain `rhs`, `jacobian`, ...).

  !> theta' = Omega, Omega' = -gamma Omega - w0**2 sin(theta)  (eq. 2.2); with
  !> a drive Omega' = -gamma Omega - P(t) sin(theta) + Q(t) (pendula_drive).
  integer(c_int) function rhs(tt, sunvec_y, sunvec_f, user_data) result(ierr) bind(C, name='')
    real(c_double), value :: tt  !< CVODE's time tau (used by a drive only: the undriven problem is autonomous)
    type(N_Vector) :: sunvec_y  !< the state (theta, Omega) as a SUNDIALS vector
    type(N_Vector) :: sunvec_f  !< output: the derivative (theta', Omega')
    type(c_ptr), value :: user_data  !< address of the call's cv_data_t (w0, gamma, control, counters)
    type(cv_data_t), pointer :: p
    type(pair_t), pointer :: yy, ff
    real(c_double) :: pp, qq
    call c_f_pointer(user_data, p)
    ! Every vector CVODE hands us is a length-2 serial vector (cloned from y).
    yy => pair_of(sunvec_y)
    ff => pair_of(sunvec_f)
    ff%v(1) = yy%v(2)
    if (p%driven) then
      call drive_pq(p, tt, pp, qq)
      ff%v(2) = (qq - p%gamma*yy%v(2)) - pp*sin(yy%v(1))
    else
      ff%v(2) = -p%gamma*yy%v(2) - p%w0sq*sin(yy%v(1))
    end if
    if (p%tscale /= 0) ff%v = scale(ff%v, p%tscale)   ! d/dtau = T d/dt
    ! A non-finite state is unrecoverable here; tell CVODE so (flag -1).
    ierr = 0
    if (.not. (ieee_is_finite(ff%v(1)) .and. ieee_is_finite(ff%v(2)))) ierr = -1
    ! A cancel request is answered the same way: CVODE stops at once and
    ! solve() turns the failure into PENDULA_ERR_CANCELLED.
    if (c_associated(p%control)) then
      p%evals = p%evals + 1
      if (mod(p%evals, CV_POLL_EVALS) == 0) then
        call poll(p%control, merge(CV_POLL_EVALS, 0_i8, p%eval_progress), p%cancelled)
        if (p%cancelled) ierr = -1
      end if
    end if
  end function rhs

  !> P and Q of the drive (pendula_drive's drive_coefficients) at CVODE's
  !> time tau: t - t(1) = tau 2**tscale, phase psi0 + Omega (t - t(1)).
  pure subroutine drive_pq(p, tau, pp, qq)
    type(cv_data_t), intent(in) :: p  !< the callbacks' data, with a drive
    real(c_double), intent(in) :: tau  !< CVODE's time
    real(c_double), intent(out) :: pp  !< coefficient of sin(theta) [1/s**2]
    real(c_double), intent(out) :: qq  !< torque term [rad/s**2]
    real(c_double) :: c
    c = cos(p%psi0 + p%freq*scale(tau, p%tscale))
    if (p%pivot) then
      pp = p%w0sq + p%amp*p%freq**2*c
      qq = 0
    else
      pp = p%w0sq
      qq = p%amp*c
    end if
  end subroutine drive_pq

  !> Add n to the progress of the control array at address `control`;
  !> cancelled: whether its cancel flag is set.
  subroutine poll(control, n, cancelled)
    type(c_ptr), intent(in) :: control  !< address of the control array (may be null)
    integer(i8), intent(in) :: n  !< progress units to add
    logical, intent(out) :: cancelled  !< whether the cancel flag is set
    integer(i8), pointer, volatile :: ctl(:)
    call c_f_pointer(control, ctl, [CONTROL_SIZE])
    call add_progress(ctl, n)
    cancelled = cancel_requested(ctl)
  end subroutine poll

  !> Analytic Jacobian [[0, 1], [-w0**2 cos(theta), -gamma]], column-major
  !> (with a drive, P(t) in place of w0**2).
  integer(c_int) function jacobian(tt, sunvec_y, sunvec_f, sunmat_j, user_data, tmp1, tmp2, tmp3) &
    result(ierr) bind(C, name='')
    real(c_double), value :: tt  !< CVODE's time tau (used by a drive only)
    type(N_Vector) :: sunvec_y  !< the state (theta, Omega) as a SUNDIALS vector
    type(N_Vector) :: sunvec_f  !< output: the derivative (theta', Omega')
    type(N_Vector) :: tmp1  !< CVODE work vector (unused)
    type(N_Vector) :: tmp2  !< CVODE work vector (unused)
    type(N_Vector) :: tmp3  !< CVODE work vector (unused)
    type(SUNMatrix) :: sunmat_j  !< output: the 2x2 dense Jacobian
    type(c_ptr), value :: user_data  !< address of the call's cv_data_t (w0, gamma, control, counters)
    type(cv_data_t), pointer :: p
    real(c_double), pointer :: yy(:), first(:), jd(:)
    real(c_double) :: pp, qq
    call c_f_pointer(user_data, p)
    yy => FN_VGetArrayPointer(sunvec_y)
    ! The SWIG wrapper returns the data as a 1-element array; view all 4.
    first => FSUNDenseMatrix_Data(sunmat_j)
    call c_f_pointer(c_loc(first(1)), jd, [4])
    jd(1) = 0
    if (p%driven) then
      call drive_pq(p, tt, pp, qq)
      jd(2) = -pp*cos(yy(1))
    else
      jd(2) = -p%w0sq*cos(yy(1))
    end if
    jd(3) = 1
    jd(4) = -p%gamma
    if (p%tscale /= 0) jd = scale(jd, p%tscale)
    ierr = 0
  end function jacobian

  !> Error weights for atol = 0 (pure relative control).  CVODE's own weights
  !> 1/(rtol |y_i|) are infinite where a component is zero, and theta and
  !> Omega both pass through zero every half period (theta0 = 0 is the text's
  !> own start: CVODE refused it).  The tolerance is relative to the size of
  !> the whole state instead, S = max(|theta|, |Omega|/w0) (Omega measured in
  !> theta's units, as in the scenes): each step's local error in theta is
  !> kept below rtol S and in Omega below rtol w0 S.  S is zero only at rest
  !> at theta = 0, where the solution is exactly zero; the weights are kept
  !> finite and positive there.
  integer(c_int) function relative_weights(sunvec_y, sunvec_w, user_data) result(ierr) bind(C, name='')
    type(N_Vector) :: sunvec_y  !< the state (theta, Omega) as a SUNDIALS vector
    type(N_Vector) :: sunvec_w  !< output: the error weights
    type(c_ptr), value :: user_data  !< address of the call's cv_data_t (w0, gamma, control, counters)
    type(cv_data_t), pointer :: p
    type(pair_t), pointer :: yy, ww
    real(c_double) :: tol(2)
    call c_f_pointer(user_data, p)
    yy => pair_of(sunvec_y)
    ww => pair_of(sunvec_w)
    tol(1) = p%rtol*max(abs(yy%v(1)), abs(yy%v(2))/p%w0)
    tol(2) = p%rtol*max(p%w0*abs(yy%v(1)), abs(yy%v(2)))
    ww%v = 1/min(max(tol, tiny(tol)), huge(tol))
    ierr = 0
  end function relative_weights

  !> Event functions: g1 = Omega (turning point), g2 = bottom_sign(theta) (zero
  !> crossing: a pass through the bottom, theta = 0 mod 2 pi).
  integer(c_int) function root_functions(tt, sunvec_y, gout, user_data) result(ierr) bind(C, name='')
    real(c_double), value :: tt  !< time [s] (unused: the problem is autonomous)
    type(N_Vector) :: sunvec_y  !< the state (theta, Omega) as a SUNDIALS vector
    real(c_double) :: gout(2)  !< output: g1 = Omega, g2 = bottom_sign(theta)
    type(c_ptr), value :: user_data  !< address of the call's cv_data_t (w0, gamma, control, counters)
    real(c_double), pointer :: yy(:)
    yy => FN_VGetArrayPointer(sunvec_y)
    gout(1) = yy(2)
    gout(2) = bottom_sign(yy(1))
    ierr = 0
  end function root_functions

  !> CVODE error handler: keep the message of errors (flag < 0) in user data
  !> instead of printing it; warnings are dropped.
  subroutine capture_error(error_code, module_name, function_name, msg, eh_data) bind(C, name='')
    integer(c_int), value :: error_code  !< CVODE's error code (< 0 error, > 0 warning)
    type(c_ptr), value :: module_name  !< C string: SUNDIALS module
    type(c_ptr), value :: function_name  !< C string: SUNDIALS function
    type(c_ptr), value :: msg  !< C string: the message
    type(c_ptr), value :: eh_data  !< address of the call's cv_data_t
    type(cv_data_t), pointer :: p
    character(kind=c_char), pointer :: chars(:)
    integer :: j, nmax
    if (error_code >= 0 .or. .not. c_associated(eh_data) .or. .not. c_associated(msg)) return
    call c_f_pointer(eh_data, p)
    nmax = len(p%errmsg)
    call c_f_pointer(msg, chars, [nmax])
    p%errmsg = ''
    do j = 1, nmax
      if (chars(j) == c_null_char) exit
      p%errmsg(j:j) = chars(j)
    end do
  end subroutine capture_error

  ! ---- small helpers for messages ----

  ! explicit lengths (not deferred): see pendula_format on gfortran's static lengths
  pure function flag_name(flag) result(s)
    integer(c_int), intent(in) :: flag
    character(len=len(code_text(int(flag), FLAG_CODES, FLAG_NAMES, 'flag '//format_int(flag)))) :: s
    s = code_text(int(flag), FLAG_CODES, FLAG_NAMES, 'flag '//format_int(flag))
  end function flag_name

  pure function flag_meaning(flag) result(s)
    integer(c_int), intent(in) :: flag
    character(len=len(code_text(int(flag), MEANING_CODES, MEANINGS, MEANING_FALLBACK))) :: s
    s = code_text(int(flag), MEANING_CODES, MEANINGS, MEANING_FALLBACK)
  end function flag_meaning

end module pendula_cvode_glue
#endif
