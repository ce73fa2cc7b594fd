!> Writes pendula/_codes.py to standard output at build time (meson runs it
!> and captures the output): the status codes, scene models and wants with
!> their names and aliases, event kinds, CVODE methods, the limits of a solve,
!> the layout of a solved scene's number array and the f2py glue's selector
!> codes, each taken from the Fortran module (or include) that defines it, so
!> that Python never holds a second copy.
program gen_codes
  use pendula_kinds, only: wp, i8
  use pendula_status, only: PENDULA_OK, PENDULA_ERR_NONFINITE, PENDULA_ERR_DOMAIN, PENDULA_ERR_SIZE, &
      PENDULA_ERR_ORDER, PENDULA_ERR_UNSTABLE, PENDULA_ERR_SOLVER, PENDULA_ERR_UNAVAILABLE, &
      PENDULA_ERR_MAXSTEPS, PENDULA_ERR_CANCELLED, PENDULA_ERR_MEMORY, PENDULA_MSG_LEN
  use pendula_integrators, only: PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO, PENDULA_CVODE_ADAMS, &
      PENDULA_CVODE_BDF
  use pendula_scene_codes, only: SCENE_MODEL_NAMES, SCENE_MODEL_ALIAS_NAMES, SCENE_MODEL_ALIAS_CODES, &
      SCENE_WANT_NAMES, SCENE_INFO_NAMES, SCENE_INFO_SIZE, SCENE_RK4_STEP_LIMIT, SCENE_STEP_CAP, &
      SCENE_CVODE_STEP_COST, SCENE_TAYLOR_STEP_COST, SCENE_STIFF_RATIO, SCENE_STIFF_RK4_STEPS, SCENE_LINEAR_SAFETY
  use pendula_physics, only: PENDULA_G_DEFAULT, PENDULA_LENGTH_DEFAULT, PENDULA_PARAM_RTOL
  use pendula_drive, only: DRIVE_TORQUE, DRIVE_PIVOT, DRIVEN_MIN_STEPS, DRIVEN_MAX_STEPS, DRIVEN_DEFAULT_STEPS
  use pendula_driven_maps, only: LYAPUNOV_BLOCKS, LYAPUNOV_ORBITS, LYAPUNOV_DEFAULT_STEPS, &
                                 LYAPUNOV_DEFAULT_PERIODS
  use pendula_driven_orbits, only: BASIN_UNSETTLED, BASIN_UNLISTED, ORBIT_MAX_PERIOD
  implicit none
  include 'pendula_glue_codes.inc'
  integer :: i

  call put('"""Codes, names and limits of the Fortran core, for the Python layer.')
  call put('')
  call put('GENERATED at build time by tools/gen/gen_codes.f90 from the Fortran modules')
  call put('(pendula_status, pendula_ode, pendula_scene_codes, pendula_physics and the glue''s')
  call put('python/f2py/pendula_glue_codes.inc): do not edit, change the Fortran.  Index names')
  call put('of INFO are 0-based positions in the number array of a solved scene')
  call put('(python/f2py/scene.f90).')
  call put('"""')
  call put('')
  call put('# status codes (pendula_status)')
  call int_line('OK', PENDULA_OK)
  call int_line('ERR_NONFINITE', PENDULA_ERR_NONFINITE)
  call int_line('ERR_DOMAIN', PENDULA_ERR_DOMAIN)
  call int_line('ERR_SIZE', PENDULA_ERR_SIZE)
  call int_line('ERR_ORDER', PENDULA_ERR_ORDER)
  call int_line('ERR_UNSTABLE', PENDULA_ERR_UNSTABLE)
  call int_line('ERR_SOLVER', PENDULA_ERR_SOLVER)
  call int_line('ERR_UNAVAILABLE', PENDULA_ERR_UNAVAILABLE)
  call int_line('ERR_MAXSTEPS', PENDULA_ERR_MAXSTEPS)
  call int_line('ERR_CANCELLED', PENDULA_ERR_CANCELLED)
  call int_line('ERR_MEMORY', PENDULA_ERR_MEMORY)
  call int_line('MSG_LEN', PENDULA_MSG_LEN)
  call put('')
  call put('# event kinds and CVODE methods (pendula_ode)')
  call int_line('EVENT_TURNING', PENDULA_EVENT_TURNING)
  call int_line('EVENT_ZERO', PENDULA_EVENT_ZERO)
  call int_line('CVODE_ADAMS', PENDULA_CVODE_ADAMS)
  call int_line('CVODE_BDF', PENDULA_CVODE_BDF)
  call put('')
  call put('# selector codes of the f2py glue (python/f2py/pendula_glue_codes.inc)')
  call int_line('GLUE_ELLIPK', GLUE_ELLIPK)
  call int_line('GLUE_ELLIPKM1', GLUE_ELLIPKM1)
  call int_line('GLUE_ELLIPE', GLUE_ELLIPE)
  call int_line('GLUE_ELLIPEM1', GLUE_ELLIPEM1)
  call int_line('GLUE_PARAM_M', GLUE_PARAM_M)
  call int_line('GLUE_PARAM_P', GLUE_PARAM_P)
  call int_line('GLUE_JACOBI_AUTO', GLUE_JACOBI_AUTO)
  call int_line('GLUE_JACOBI_PLAN', GLUE_JACOBI_PLAN)
  call int_line('GLUE_SMALL_ANGLE_MOTION', GLUE_SMALL_ANGLE_MOTION)
  call int_line('GLUE_SMALL_ANGLE_BOUND', GLUE_SMALL_ANGLE_BOUND)
  call int_line('GLUE_PERIOD', GLUE_PERIOD)
  call int_line('GLUE_AMPLITUDE', GLUE_AMPLITUDE)
  call int_line('GLUE_W0', GLUE_W0)
  call int_line('GLUE_GAMMA', GLUE_GAMMA)
  call put('')
  call put('# the default pendulum, the text''s: g [m/s^2], length [m] (pendula_physics); relative')
  call put('# tolerance within which w0 and sqrt(g/length), or gamma and b/mass, must agree')
  call real_line('G_DEFAULT', PENDULA_G_DEFAULT)
  call real_line('LENGTH_DEFAULT', PENDULA_LENGTH_DEFAULT)
  call real_line('PARAM_RTOL', PENDULA_PARAM_RTOL)
  call put('')
  call put('# scene models: name -> code (pendula_scene_codes); "auto" lets the library choose')
  call put('MODEL_CODES = {')
  do i = lbound(SCENE_MODEL_NAMES, 1), ubound(SCENE_MODEL_NAMES, 1)
    call put('    "' // trim(SCENE_MODEL_NAMES(i)) // '": ' // itoa(i) // ',')
  end do
  call put('}')
  call put('# other accepted names: alias -> model name')
  call put('MODEL_ALIASES = {')
  do i = 1, size(SCENE_MODEL_ALIAS_NAMES)
    call put('    "' // trim(SCENE_MODEL_ALIAS_NAMES(i)) // '": "' // &
        trim(SCENE_MODEL_NAMES(SCENE_MODEL_ALIAS_CODES(i))) // '",')
  end do
  call put('}')
  call put('# scene wants: name -> code')
  call put('WANT_CODES = {')
  do i = 1, size(SCENE_WANT_NAMES)
    call put('    "' // trim(SCENE_WANT_NAMES(i)) // '": ' // itoa(i) // ',')
  end do
  call put('}')
  call put('')
  call put('# limits of a solve (pendula_scene_codes): RK4 steps beyond which CVODE takes over')
  call put('# (when built); stiff ratio gamma/w0 and the RK4 steps beyond which a stiff scene')
  call put('# goes to CVODE; the default work budget max_steps [RK4 steps]; the cost of a CVODE')
  call put('# step in RK4 steps')
  call real_line('RK4_STEP_LIMIT', SCENE_RK4_STEP_LIMIT)
  call real_line('STIFF_RATIO', SCENE_STIFF_RATIO)
  call real_line('STIFF_RK4_STEPS', SCENE_STIFF_RK4_STEPS)
  call put('STEP_CAP = ' // itoa(nint(SCENE_STEP_CAP, i8)))
  call real_line('CVODE_STEP_COST', SCENE_CVODE_STEP_COST)
  call real_line('TAYLOR_STEP_COST', SCENE_TAYLOR_STEP_COST)
  call put('# safety factor of the linear model''s a priori nonlinearity estimates')
  call real_line('LINEAR_SAFETY', SCENE_LINEAR_SAFETY)
  call put('')
  call put('# the number array of a solved scene: field name -> 0-based position')
  call put('INFO = {')
  do i = 1, SCENE_INFO_SIZE
    call put('    "' // trim(SCENE_INFO_NAMES(i)) // '": ' // itoa(i - 1) // ',')
  end do
  call put('}')
  call int_line('INFO_SIZE', SCENE_INFO_SIZE)
  call put('')
  call put('# the driven pendulum (pendula_drive, pendula_driven_maps, pendula_driven_orbits)')
  call int_line('DRIVE_TORQUE', DRIVE_TORQUE)
  call int_line('DRIVE_PIVOT', DRIVE_PIVOT)
  call int_line('DRIVEN_MIN_STEPS', DRIVEN_MIN_STEPS)
  call int_line('DRIVEN_MAX_STEPS', DRIVEN_MAX_STEPS)
  call int_line('DRIVEN_DEFAULT_STEPS', DRIVEN_DEFAULT_STEPS)
  call int_line('LYAPUNOV_BLOCKS', LYAPUNOV_BLOCKS)
  call int_line('LYAPUNOV_ORBITS', LYAPUNOV_ORBITS)
  call int_line('LYAPUNOV_DEFAULT_STEPS', LYAPUNOV_DEFAULT_STEPS)
  call int_line('LYAPUNOV_DEFAULT_PERIODS', LYAPUNOV_DEFAULT_PERIODS)
  call int_line('BASIN_UNSETTLED', BASIN_UNSETTLED)
  call int_line('BASIN_UNLISTED', BASIN_UNLISTED)
  call int_line('ORBIT_MAX_PERIOD', ORBIT_MAX_PERIOD)

contains

  subroutine put(line)
    character(len=*), intent(in) :: line
    write (*, '(a)') line
  end subroutine put

  function itoa(k) result(s)
    class(*), intent(in) :: k
    character(len=:), allocatable :: s
    character(len=24) :: buf
    select type (k)
    type is (integer)
      write (buf, '(i0)') k
    type is (integer(i8))
      write (buf, '(i0)') k
    end select
    s = trim(buf)
  end function itoa

  subroutine int_line(name, k)
    character(len=*), intent(in) :: name
    integer, intent(in) :: k
    call put(name // ' = ' // itoa(k))
  end subroutine int_line

  subroutine real_line(name, x)
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: x
    character(len=40) :: buf
    write (buf, '(es24.17e3)') x
    call put(name // ' = ' // trim(adjustl(buf)))
  end subroutine real_line

end program gen_codes
