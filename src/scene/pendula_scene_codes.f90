!> The facts of the scenes concern, each stated once: model and want codes
!> with their names (and the accepted alias), the limits of a solve, and the
!> layout of the result's number array that crosses to Python.  Python reads
!> them from pendula/_codes.py, which tools/gen/gen_codes.f90 writes from this
!> module at build time.
module pendula_scene_codes
  use pendula_kinds, only: wp
  use pendula_format, only: format_int, code_text
  implicit none
  private

  public :: scene_model_name, scene_model_code, scene_want_name, scene_want_code
  public :: scene_model_list, scene_want_list
  public :: SCENE_MODEL_AUTO, SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR, &
            SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_MODEL_TAYLOR, SCENE_MODEL_NAMES
  public :: SCENE_MODEL_ALIAS_NAMES, SCENE_MODEL_ALIAS_CODES
  public :: SCENE_WANT_STATE, SCENE_WANT_THETA, SCENE_WANT_FINAL, SCENE_WANT_ENERGY, &
            SCENE_WANT_PERIOD, SCENE_WANT_EVENTS, SCENE_WANT_NAMES
  public :: SCENE_LINEAR_SAFETY
  public :: SCENE_RK4_STEP_LIMIT, SCENE_STEP_CAP, SCENE_CVODE_STEP_COST, SCENE_STIFF_RATIO, &
            SCENE_STIFF_RK4_STEPS, SCENE_TAYLOR_STEP_COST
  public :: SCENE_INFO_ERROR_ESTIMATE, SCENE_INFO_SETTING, SCENE_INFO_PERIOD, SCENE_INFO_WALL_TIME, &
            SCENE_INFO_CLOSED_FORM_EVALS, SCENE_INFO_RHS_EVALS, SCENE_INFO_STEPS, SCENE_INFO_RUNS, &
            SCENE_INFO_TOL_MET, SCENE_INFO_EVENT_TIME_ERROR, SCENE_INFO_STEP, SCENE_INFO_RTOL, &
            SCENE_INFO_SIZE, SCENE_INFO_NAMES

  !> Model codes (0 = let scene_solve choose).
  integer, parameter :: SCENE_MODEL_AUTO = 0, SCENE_MODEL_SMALL_ANGLE = 1, SCENE_MODEL_EXACT = 2, &
                        SCENE_MODEL_LINEAR = 3, SCENE_MODEL_RK4 = 4, SCENE_MODEL_CVODE = 5, SCENE_MODEL_TAYLOR = 6
  !> Model names, indexed by code.
  character(len=*), parameter :: SCENE_MODEL_NAMES(0:6) = [character(len=11) :: &
                                                           'auto', 'small_angle', 'exact', 'linear', 'rk4', 'cvode', 'taylor']
  !> Other names accepted for a model (scene_model_code), and their codes.
  character(len=*), parameter :: SCENE_MODEL_ALIAS_NAMES(1) = [character(len=13) :: 'linear_damped']
  integer, parameter :: SCENE_MODEL_ALIAS_CODES(1) = [SCENE_MODEL_LINEAR]

  !> What a scene asks for: theta and Omega at t(:); theta only; the state at
  !> t(n) only; the energy per unit m l^2 [1/s^2] at t(:); the period (or time
  !> per revolution) [s]; turning points (Omega = 0) and zero crossings
  !> (theta = 0) in (0, t(n)].
  integer, parameter :: SCENE_WANT_STATE = 1, SCENE_WANT_THETA = 2, SCENE_WANT_FINAL = 3, &
                        SCENE_WANT_ENERGY = 4, SCENE_WANT_PERIOD = 5, SCENE_WANT_EVENTS = 6
  !> Want names, indexed by code.
  character(len=*), parameter :: SCENE_WANT_NAMES(6) = [character(len=6) :: &
                                                        'state', 'theta', 'final', 'energy', 'period', 'events']
  ! The codes in the order of the name tables, and room for a list of them.
  integer, parameter :: MODEL_CODES(0:6) = [SCENE_MODEL_AUTO, SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, &
                                            SCENE_MODEL_LINEAR, SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_MODEL_TAYLOR]
  integer, parameter :: WANT_CODES(6) = [SCENE_WANT_STATE, SCENE_WANT_THETA, SCENE_WANT_FINAL, &
                                         SCENE_WANT_ENERGY, SCENE_WANT_PERIOD, SCENE_WANT_EVENTS]
  integer, parameter :: LIST_MAX = 200

  !> RK4 runs longer than this many steps are left to CVODE when it is built.
  !> RK4 is several times cheaper than CVODE (Adams) at equal sup error on
  !> non-stiff scenes (benchmarks/bench_tradeoff.py measures it), so RK4 runs
  !> until its rounding floor bites (see choose_model) or the run is very long.
  real(wp), parameter :: SCENE_RK4_STEP_LIMIT = 2.0e8_wp
  !> Stiff scenes (gamma > SCENE_STIFF_RATIO w0) switch to CVODE (BDF) above
  !> this many RK4 steps, since BDF needs only a few hundred steps whatever gamma.
  real(wp), parameter :: SCENE_STIFF_RATIO = 20, SCENE_STIFF_RK4_STEPS = 1.0e4_wp
  !> Default work budget of one solve, in RK4 steps (about a minute of CPU);
  !> a CVODE step counts as SCENE_CVODE_STEP_COST of them.  Work predicted
  !> beyond it is refused before it starts (the caller may raise it: max_steps).
  real(wp), parameter :: SCENE_STEP_CAP = 2.0e9_wp
  real(wp), parameter :: SCENE_CVODE_STEP_COST = 20
  !> A Taylor step (pendula_taylor) counts as SCENE_TAYLOR_STEP_COST RK4 steps
  !> of the budget and of the work prediction: its series of order p costs
  !> ~0.55 p of them (measured, best of 9 interleaved runs of 1500-7000 steps:
  !> 12 at order 22 .. 20 at order 35, the orders of tol 1e-4 .. 1e-11 over
  !> long windows; 0.53-0.58 p at every order measured).
  real(wp), parameter :: SCENE_TAYLOR_STEP_COST = 16
  !> Safety factor on the linear model's a priori nonlinearity estimates
  !> (pendula_scene_estimates, and the per-event bound of pendula_scene_events;
  !> calibrated: within 3 % of the true error where tight).
  real(wp), parameter :: SCENE_LINEAR_SAFETY = 1.5_wp

  !> Layout of the number array of a solved scene that crosses to Python
  !> (python/f2py/scene.f90 fills it, pendula/_scene_call.py reads it by these
  !> names): the estimate, the setting (RK4 h or CVODE rtol; 0 for closed
  !> forms), the period, the cost counters, tol_met (0 or 1), the event-time
  !> error, and the setting again as step (RK4) and rtol (CVODE), 0 where
  !> the model has none.
  integer, parameter :: SCENE_INFO_ERROR_ESTIMATE = 1, SCENE_INFO_SETTING = 2, SCENE_INFO_PERIOD = 3, &
                        SCENE_INFO_WALL_TIME = 4, SCENE_INFO_CLOSED_FORM_EVALS = 5, SCENE_INFO_RHS_EVALS = 6, &
                        SCENE_INFO_STEPS = 7, SCENE_INFO_RUNS = 8, SCENE_INFO_TOL_MET = 9, SCENE_INFO_EVENT_TIME_ERROR = 10, &
                        SCENE_INFO_STEP = 11, SCENE_INFO_RTOL = 12, SCENE_INFO_SIZE = 12
  !> Names of the slots, indexed as above.
  character(len=*), parameter :: SCENE_INFO_NAMES(SCENE_INFO_SIZE) = [character(len=17) :: &
                                             'error_estimate', 'setting', 'period', 'wall_time', 'closed_form_evals', 'rhs_evals', &
                                                                     'steps', 'runs', 'tol_met', 'event_time_error', 'step', 'rtol']

contains

  ! 'names(1) (codes(1)), names(2) (codes(2)), ...', blank-padded.
  pure function list_text(names, codes) result(list)
    character(len=*), intent(in) :: names(:)
    integer, intent(in) :: codes(:)
    character(len=LIST_MAX) :: list
    character(len=:), allocatable :: work
    integer :: i
    work = ''
    do i = 1, size(names)
      work = work//merge(', ', '  ', i > 1)//trim(names(i))//' ('//format_int(codes(i))//')'
    end do
    list = adjustl(work)
  end function list_text

  !> 'auto', 'small_angle', 'exact', 'linear', 'rk4', 'cvode', 'taylor' ('unknown' otherwise).
  pure function scene_model_name(code) result(name)
    integer, intent(in) :: code  !< model code, SCENE_MODEL_* (0 .. 6); any other value gives 'unknown'
    ! explicit lengths here (not deferred): see pendula_format on gfortran's static lengths
    character(len=len(code_text(code, MODEL_CODES, SCENE_MODEL_NAMES, 'unknown'))) :: name
    name = code_text(code, MODEL_CODES, SCENE_MODEL_NAMES, 'unknown')
  end function scene_model_name

  !> Model code of a name (as scene_model_name, or one of
  !> SCENE_MODEL_ALIAS_NAMES); -1 for an unknown name.
  pure integer function scene_model_code(name) result(code)
    character(len=*), intent(in) :: name  !< model name or alias, lower case; surrounding blanks ignored
    integer :: i
    code = -1
    do i = lbound(SCENE_MODEL_NAMES, 1), ubound(SCENE_MODEL_NAMES, 1)
      if (trim(adjustl(name)) == trim(SCENE_MODEL_NAMES(i))) code = i
    end do
    do i = 1, size(SCENE_MODEL_ALIAS_NAMES)
      if (trim(adjustl(name)) == trim(SCENE_MODEL_ALIAS_NAMES(i))) code = SCENE_MODEL_ALIAS_CODES(i)
    end do
  end function scene_model_code

  !> 'state', 'theta', 'final', 'energy', 'period', 'events' ('unknown' otherwise).
  pure function scene_want_name(code) result(name)
    integer, intent(in) :: code  !< want code, SCENE_WANT_* (1 .. 6); any other value gives 'unknown'
    character(len=len(code_text(code, WANT_CODES, SCENE_WANT_NAMES, 'unknown'))) :: name
    name = code_text(code, WANT_CODES, SCENE_WANT_NAMES, 'unknown')
  end function scene_want_name

  !> Want code of a name (as scene_want_name); -1 for an unknown name.
  pure integer function scene_want_code(name) result(code)
    character(len=*), intent(in) :: name  !< want name, lower case; surrounding blanks ignored
    integer :: i
    code = -1
    do i = 1, size(SCENE_WANT_NAMES)
      if (trim(adjustl(name)) == trim(SCENE_WANT_NAMES(i))) code = i
    end do
  end function scene_want_code

  !> The model names with their codes from code first on, for messages:
  !> 'auto (0), small_angle (1), ..., taylor (6)'.
  pure function scene_model_list(first) result(list)
    integer, intent(in) :: first  !< first model code listed, SCENE_MODEL_AUTO (0) .. SCENE_MODEL_TAYLOR (6)
    character(len=len_trim(list_text(SCENE_MODEL_NAMES(max(first, 0):), MODEL_CODES(max(first, 0):)))) :: list
    list = list_text(SCENE_MODEL_NAMES(max(first, 0):), MODEL_CODES(max(first, 0):))
  end function scene_model_list

  !> The want names with their codes, for messages: 'state (1), ..., events (6)'.
  pure function scene_want_list() result(list)
    character(len=len_trim(list_text(SCENE_WANT_NAMES, WANT_CODES))) :: list
    list = list_text(SCENE_WANT_NAMES, WANT_CODES)
  end function scene_want_list

end module pendula_scene_codes
