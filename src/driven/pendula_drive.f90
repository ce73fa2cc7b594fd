!> The drive of the driven damped pendulum, one derived type for both kinds:
!>
!>   torque: theta'' + gamma theta' + w0**2 sin(theta) = F cos(Omega t + phi)
!>           (F = amplitude in rad/s**2);
!>   pivot:  theta'' + gamma theta' + (w0**2 + (a/l) Omega**2 cos(Omega t + phi)) sin(theta) = 0
!>           (a vertically oscillating pivot, amplitude = a/l, dimensionless:
!>           Kapitza's pendulum, Landau & Lifshitz, Mechanics, section 30).
!>
!> Both are written as theta'' = -gamma theta' - P(t) sin(theta) + Q(t) with
!> P = w0**2 + (pivot term) and Q = (torque term); the integrators tabulate P
!> and Q at the stage times of one drive period (pendula_driven_kernel).
module pendula_drive
  use pendula_kinds, only: wp
  use pendula_constants, only: pi
  use pendula_format, only: format_int
  use pendula_status, only: status_t, set_error, check_finite, check_positive, check_nonnegative, &
                            PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_UNSTABLE
  implicit none
  private
  public :: drive_t, DRIVE_TORQUE, DRIVE_PIVOT, check_drive, check_driven, check_drive_kind, &
            drive_period, drive_coefficients, DRIVEN_MIN_STEPS, DRIVEN_MAX_STEPS, DRIVEN_DEFAULT_STEPS

  !> A torque F cos(Omega t + phi) [rad/s**2] on the bob.
  integer, parameter :: DRIVE_TORQUE = 1
  !> A vertically oscillating pivot, a cos(Omega t + phi) (Kapitza).
  integer, parameter :: DRIVE_PIVOT = 2
  !> Fewest RK4 steps per drive period accepted.
  integer, parameter :: DRIVEN_MIN_STEPS = 8
  !> Most RK4 steps per drive period accepted (the stage tables hold 2 N + 1 values).
  integer, parameter :: DRIVEN_MAX_STEPS = 1000000
  !> Default RK4 steps per drive period.
  integer, parameter :: DRIVEN_DEFAULT_STEPS = 128

  !> A periodic drive: kind (DRIVE_TORQUE or DRIVE_PIVOT), amplitude (F in
  !> rad/s**2 for a torque, a/l for a pivot), frequency Omega [rad/s] > 0 and
  !> phase phi [rad].
  type :: drive_t
    integer :: kind = DRIVE_TORQUE
    real(wp) :: amplitude = 0
    real(wp) :: frequency = 1
    real(wp) :: phase = 0
  end type drive_t

contains

  !> Check a drive kind code (DRIVE_TORQUE or DRIVE_PIVOT).
  pure subroutine check_drive_kind(kind, status)
    integer, intent(in) :: kind  !< drive kind code
    type(status_t), intent(inout) :: status  !< receives the error unless one is set already
    if (status%code /= PENDULA_OK) return
    if (kind /= DRIVE_TORQUE .and. kind /= DRIVE_PIVOT) call set_error(status, PENDULA_ERR_DOMAIN, &
                                    'drive kind = '//format_int(kind)//' is out of range: it must be '//format_int(DRIVE_TORQUE)// &
                                                                       ' (torque) or '//format_int(DRIVE_PIVOT)//' (pivot)')
  end subroutine check_drive_kind

  !> Check a drive: a known kind, finite amplitude and phase, frequency > 0.
  pure subroutine check_drive(drive, status)
    type(drive_t), intent(in) :: drive  !< the drive to check
    type(status_t), intent(inout) :: status  !< receives the error unless one is set already
    call check_drive_kind(drive%kind, status)
    call check_finite('amplitude', drive%amplitude, status)
    call check_positive('frequency', drive%frequency, status)
    call check_finite('phase', drive%phase, status)
  end subroutine check_drive

  !> Check one driven problem: w0 > 0 [1/s], gamma >= 0 [1/s], the drive, and
  !> nsteps RK4 steps per drive period in [DRIVEN_MIN_STEPS, DRIVEN_MAX_STEPS]
  !> with a step h = 2 pi/(Omega nsteps) that resolves the motion near rest:
  !> h max(sqrt(w0**2 + |P - w0**2|), gamma) <= 1.5 (RK4 is stable to 2.78 on
  !> the imaginary axis; 1.5 keeps its error meaningful), else PENDULA_ERR_UNSTABLE.
  pure subroutine check_driven(w0, gamma, drive, nsteps, status)
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    type(drive_t), intent(in) :: drive  !< the drive
    integer, intent(in) :: nsteps  !< RK4 steps per drive period
    type(status_t), intent(inout) :: status  !< receives the error unless one is set already
    real(wp) :: h, rate
    call check_positive('w0', w0, status)
    call check_nonnegative('gamma', gamma, status)
    call check_drive(drive, status)
    if (status%code /= PENDULA_OK) return
    if (nsteps < DRIVEN_MIN_STEPS .or. nsteps > DRIVEN_MAX_STEPS) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'steps_per_period = '//format_int(nsteps)// &
                     ' is out of range: it must be in ['//format_int(DRIVEN_MIN_STEPS)//', '// &
                     format_int(DRIVEN_MAX_STEPS)//']')
      return
    end if
    h = drive_period(drive)/nsteps
    rate = w0*w0
    if (drive%kind == DRIVE_PIVOT) rate = rate + abs(drive%amplitude)*drive%frequency**2
    rate = max(sqrt(rate), gamma)
    if (.not. h*rate <= 1.5_wp) call set_error(status, PENDULA_ERR_UNSTABLE, 'steps_per_period = '// &
                                           format_int(nsteps)//' is too few for these w0, gamma and drive: it must be at least '// &
                                               format_int(int(min(2*pi/drive%frequency*rate/1.5_wp, 1.0e9_wp)) + 1))
  end subroutine check_driven

  !> The drive period 2 pi/Omega [s].
  elemental real(wp) function drive_period(drive)
    type(drive_t), intent(in) :: drive  !< the drive (frequency > 0)
    drive_period = 2*pi/drive%frequency
  end function drive_period

  !> P(t) and Q(t) of theta'' = -gamma theta' - P sin(theta) + Q at drive phase
  !> psi = Omega t + phi [rad] (see the module doc).
  elemental subroutine drive_coefficients(drive, w0, psi, p, q)
    type(drive_t), intent(in) :: drive  !< the drive
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s]
    real(wp), intent(in) :: psi  !< drive phase Omega t + phi [rad]
    real(wp), intent(out) :: p  !< coefficient of sin(theta) [1/s**2]
    real(wp), intent(out) :: q  !< torque term [rad/s**2]
    p = w0*w0
    q = 0
    if (drive%kind == DRIVE_PIVOT) then
      p = p + drive%amplitude*drive%frequency**2*cos(psi)
    else
      q = drive%amplitude*cos(psi)
    end if
  end subroutine drive_coefficients

end module pendula_drive
