!> Stand-in for pendula_cvode in builds without SUNDIALS: the same module
!> name, constants and procedures (so `pendula`, the f2py layer and callers
!> build unchanged), each returning PENDULA_ERR_UNAVAILABLE with a message
!> saying how to get CVODE.  cvode_available() is .false. here.
module pendula_cvode
  use pendula_kinds, only: wp, i8
  use pendula_status, only: status_t, set_error, PENDULA_ERR_UNAVAILABLE
  use pendula_control, only: CONTROL_SIZE
  use pendula_ode, only: ode_stats_t, &
      PENDULA_CVODE_ADAMS, PENDULA_CVODE_BDF, PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO
  implicit none
  private
  public :: cvode_solve, cvode_solve_events, cvode_available
  public :: PENDULA_CVODE_ADAMS, PENDULA_CVODE_BDF, PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO

  character(len=*), parameter :: why = 'CVODE is not available: this pendula was built without ' // &
      'SUNDIALS (install libsundials-dev and libsundials-fortran-dev, then rebuild with ' // &
      '-Dsundials=enabled); use the RK4 integrator instead'

contains

  !> False: this build has no SUNDIALS CVODE.
  pure logical function cvode_available()
    cvode_available = .false.
  end function cvode_available

  !> Not built: outputs zero, status PENDULA_ERR_UNAVAILABLE.  See the
  !> SUNDIALS build of this module for the arguments.
  subroutine cvode_solve(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, &
      theta, omega, stats, status, control)
    real(wp), intent(in) :: t(:), theta0, omega0, w0, gamma, rtol, atol
    integer, intent(in) :: method
    integer(i8), intent(in) :: max_steps
    real(wp), intent(out) :: theta(:), omega(:)
    type(ode_stats_t), intent(out) :: stats
    type(status_t), intent(out) :: status
    integer(i8), intent(inout), volatile, optional, target :: control(CONTROL_SIZE)
    theta = 0
    omega = 0
    stats = ode_stats_t()
    call set_error(status, PENDULA_ERR_UNAVAILABLE, why)
  end subroutine cvode_solve

  !> Not built: outputs zero, no events, status PENDULA_ERR_UNAVAILABLE.
  subroutine cvode_solve_events(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, &
      theta, omega, event_t, event_kind, event_theta, event_omega, n_events, truncated, stats, status, control)
    real(wp), intent(in) :: t(:), theta0, omega0, w0, gamma, rtol, atol
    integer, intent(in) :: method
    integer(i8), intent(in) :: max_steps
    real(wp), intent(out) :: theta(:), omega(:)
    real(wp), intent(out) :: event_t(:), event_theta(:), event_omega(:)
    integer, intent(out) :: event_kind(:)
    integer, intent(out) :: n_events
    logical, intent(out) :: truncated
    type(ode_stats_t), intent(out) :: stats
    type(status_t), intent(out) :: status
    integer(i8), intent(inout), volatile, optional, target :: control(CONTROL_SIZE)
    call cvode_solve(t, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, theta, omega, stats, status)
    event_t = 0
    event_kind = 0
    event_theta = 0
    event_omega = 0
    n_events = 0
    truncated = .false.
  end subroutine cvode_solve_events

end module pendula_cvode
