!> The scene, its answer and its cost (see pendula_scene for what a scene
!> is), and the few quantities every part of the solve derives from a scene.
module pendula_scene_types
  use pendula_kinds, only: wp, i8
  use pendula_constants, only: pi
  use pendula_status, only: PENDULA_MSG_LEN, status_t, check_alloc, PENDULA_OK
  use pendula_integrators, only: ode_stats_t
  use pendula_scene_codes, only: SCENE_MODEL_AUTO, SCENE_WANT_STATE, SCENE_STIFF_RATIO
  use pendula_drive, only: drive_t
  implicit none
  private

  public :: scene_t, scene_result_t, scene_cost_t
  public :: window_end, is_stiff, add_stats, swing, scene_like, has_drive

  !> A scene; build it with scene_init (which checks every field).
  type :: scene_t
    real(wp) :: theta0 = 0        !< initial angle [rad] at t = 0
    real(wp) :: omega0 = 0        !< initial angular velocity [rad/s] at t = 0
    real(wp) :: w0 = 1            !< natural frequency sqrt(g/l) [1/s]
    !> Rounding residual of w0 [1/s] when it was rounded from g and l
    !> (scene_physics): the data's frequency is w0 + w0lo; 0 when w0 is the datum.
    real(wp) :: w0lo = 0
    real(wp) :: gamma = 0         !< damping rate b/m [1/s]
    real(wp) :: tol = 1.0e-6_wp   !< absolute tolerance on theta [rad] (Omega/w0 too)
    integer :: want = SCENE_WANT_STATE
    integer :: model = SCENE_MODEL_AUTO   !< forced model, or AUTO
    real(wp), allocatable :: t(:) !< output times [s], >= 0, strictly increasing
    !> Whether the scene is driven by `drive` (pendula_scene_driven); a drive of
    !> amplitude 0 leaves the scene exactly the undriven one.
    logical :: driven = .false.
    type(drive_t) :: drive  !< the drive (pendula_drive), used when driven
  end type scene_t

  !> What an answer cost.
  type :: scene_cost_t
    integer(i8) :: closed_form_evals = 0  !< points at which a closed form was evaluated
    integer(i8) :: rhs_evals = 0          !< right-hand-side evaluations (integrators)
    integer(i8) :: steps = 0              !< integrator steps
    integer :: runs = 0                   !< integrator runs, verification included
    real(wp) :: wall_time = 0             !< seconds spent in scene_solve
  end type scene_cost_t

  !> The answer: which model, why, its error estimate, the asked quantities.
  type :: scene_result_t
    integer :: model = SCENE_MODEL_AUTO
    character(len=PENDULA_MSG_LEN) :: reason = ''
    !> Estimated sup over the window of max(|d theta| [rad], |d Omega|/w0).
    real(wp) :: error_estimate = 0
    !> error_estimate <= tol.
    logical :: tol_met = .false.
    !> RK4 step h [s] or CVODE rtol of the returned run; 0 for closed forms
    !> (kept for compatibility: step and rtol say which).
    real(wp) :: setting = 0
    !> RK4 step h [s] of the returned run (model rk4), else 0.
    real(wp) :: step = 0
    !> CVODE rtol of the returned run (model cvode), else 0.
    real(wp) :: rtol = 0
    integer :: want = SCENE_WANT_STATE
    !> Output times and the state there (want = state, theta, final, energy).
    real(wp), allocatable :: t(:), theta(:), omega(:)
    !> Energy per unit m l^2 [1/s^2] at t (want = energy).
    real(wp), allocatable :: energy(:)
    !> Period or time per revolution [s] (want = period); +inf on the separatrix.
    real(wp) :: period = 0
    !> Events (want = events): times [s], kinds (PENDULA_EVENT_*), state there.
    real(wp), allocatable :: event_t(:), event_theta(:), event_omega(:)
    integer, allocatable :: event_kind(:)
    !> Estimated error of the event times [s].
    real(wp) :: event_time_error = 0
    type(scene_cost_t) :: cost
  end type scene_result_t

contains

  !> A scene with the fields of `scene` and room for n output times (left for
  !> the caller to fill): a part of a scene, built without copying its times
  !> first.  PENDULA_ERR_MEMORY in status when the times cannot be allocated.
  pure subroutine scene_like(scene, sub, n, status)
    type(scene_t), intent(in) :: scene  !< the scene whose parameters and initial state are taken
    type(scene_t), intent(out) :: sub  !< the new scene, sub%t of size n (unset)
    integer, intent(in) :: n  !< number of output times, >= 0
    type(status_t), intent(inout) :: status  !< set when the times cannot be allocated, else left unchanged
    integer :: ist
    sub%theta0 = scene%theta0
    sub%omega0 = scene%omega0
    sub%w0 = scene%w0
    sub%w0lo = scene%w0lo
    sub%gamma = scene%gamma
    sub%tol = scene%tol
    sub%want = scene%want
    sub%model = scene%model
    sub%driven = scene%driven
    sub%drive = scene%drive
    allocate (sub%t(n), stat=ist)
    call check_alloc(ist, 'the output times of a part of the scene', int(n, i8), 8, status)
  end subroutine scene_like

  !> Whether the scene has a drive of nonzero amplitude (pendula_scene_driven
  !> answers it); false for an undriven scene or a drive of amplitude 0.
  pure logical function has_drive(scene)
    type(scene_t), intent(in) :: scene  !< the scene
    has_drive = scene%driven .and. scene%drive%amplitude /= 0
  end function has_drive

  !> End of the window [s]: t(n), or 0 without output times.
  pure real(wp) function window_end(scene) result(tend)
    type(scene_t), intent(in) :: scene  !< the scene (t may be empty)
    tend = 0
    if (size(scene%t) > 0) tend = scene%t(size(scene%t))
  end function window_end

  !> Stiff for the integrators: gamma > SCENE_STIFF_RATIO w0.
  pure logical function is_stiff(scene)
    type(scene_t), intent(in) :: scene  !< the scene (w0 > 0, gamma >= 0)
    is_stiff = scene%gamma > SCENE_STIFF_RATIO*scene%w0
  end function is_stiff

  !> The motion's size [rad]: |theta0| about the nearest bottom 2 pi k (in
  !> [0, pi]) plus |Omega0|/w0, so theta0 + 2 pi k is the same motion.
  pure real(wp) function swing(scene)
    type(scene_t), intent(in) :: scene  !< the scene (w0 > 0)
    swing = abs(modulo(scene%theta0 + pi, 2*pi) - pi) + abs(scene%omega0)/scene%w0
  end function swing

  !> Add one integrator run's counters to a cost.
  pure subroutine add_stats(cost, stats)
    type(scene_cost_t), intent(inout) :: cost  !< cost to add to (one more run)
    type(ode_stats_t), intent(in) :: stats  !< counters of the run: rhs evaluations, steps
    cost%rhs_evals = cost%rhs_evals + stats%rhs_evals
    cost%steps = cost%steps + stats%steps
    cost%runs = cost%runs + 1
  end subroutine add_stats

end module pendula_scene_types
