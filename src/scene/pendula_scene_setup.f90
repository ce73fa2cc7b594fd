!> Building and checking scenes: the text's parameters to (w0, gamma), the
!> construction of a scene with every rule on its fields, the rules on a
!> model for a scene, the work budget, and the result arrays a want needs.
!> Each rule is stated here once; Python passes its arguments through.
module pendula_scene_setup
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_sci, format_int
  use pendula_status, only: status_t, set_error, check_finite, check_positive, check_nonnegative, &
                check_increasing, check_size, check_alloc, PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_UNAVAILABLE, PENDULA_ERR_SIZE
  use pendula_physics, only: natural_frequency, damping_rate
  use pendula_double_double, only: dd_div_d, dd_sqrt
  use pendula_undamped, only: pendulum_energy
  use pendula_integrators, only: cvode_available
  use pendula_scene_codes, only: SCENE_MODEL_AUTO, SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, &
                  SCENE_MODEL_CVODE, SCENE_MODEL_TAYLOR, SCENE_WANT_STATE, SCENE_WANT_FINAL, SCENE_WANT_ENERGY, SCENE_WANT_PERIOD, &
                                 SCENE_WANT_EVENTS, SCENE_STEP_CAP, scene_model_name, scene_model_list, scene_want_list
  use pendula_scene_types, only: scene_t, scene_result_t
  use pendula_drive, only: drive_t, DRIVE_TORQUE, check_drive
  use pendula_scene_codes, only: SCENE_MODEL_LINEAR, SCENE_MODEL_RK4
  implicit none
  private

  public :: scene_physics, scene_init, check_scene, check_model_gamma, check_model_built, get_budget
  public :: alloc_outputs, finish_outputs, empty_outputs, check_driven_model

contains

  !> The text's parameters to (w0, gamma): w0 = sqrt(g/l) (eq. 1.7) with g,
  !> length > 0 [m/s^2, m]; the damping either as gamma [1/s] >= 0 directly, or
  !> as mass [kg] > 0 and b [kg/s] >= 0 (gamma = b/m, eq. 2.1), or both when
  !> they agree to 1e-12 relative; none gives gamma = 0.  Errors name the
  !> argument: b without mass, mass without b, gamma and b/mass disagreeing.
  !> w0lo (optional): the rounding residual of w0, sqrt(g/l) - w0 to ~eps^2 w0
  !> (0 where g/l leaves the double range), for scene_init.
  pure subroutine scene_physics(g, length, w0, gamma, status, gamma_in, mass, b, w0lo)
    real(wp), intent(in) :: g  !< gravitational acceleration [m/s^2], > 0
    real(wp), intent(in) :: length  !< pendulum length [m], > 0
    real(wp), intent(out) :: w0  !< natural frequency sqrt(g/length) [1/s] (0 on error)
    real(wp), intent(out) :: gamma  !< damping rate [1/s], >= 0 (0 without damping)
    type(status_t), intent(out) :: status  !< PENDULA_OK, or the error code and a message naming the argument
    real(wp), intent(in), optional :: gamma_in  !< damping rate gamma [1/s], >= 0 (optional)
    real(wp), intent(in), optional :: mass  !< bob mass [kg], > 0 (optional, with b)
    real(wp), intent(in), optional :: b  !< linear damping coefficient [kg/s], >= 0 (optional, with mass)
    real(wp), intent(out), optional :: w0lo  !< rounding residual sqrt(g/length) - w0 [1/s] (optional)
    real(wp) :: gb
    type(status_t) :: st
    w0 = 0
    gamma = 0
    if (present(w0lo)) w0lo = 0
    call natural_frequency(g, length, w0, status)
    if (status%code /= PENDULA_OK) return
    if (present(w0lo)) w0lo = w0_residual(g, length, w0)
    if (present(gamma_in)) then
      call check_nonnegative('gamma', gamma_in, status)
      if (status%code /= PENDULA_OK) return
      gamma = gamma_in
    end if
    if (present(mass) .neqv. present(b)) then
      if (present(mass)) then
        call set_error(status, PENDULA_ERR_DOMAIN, 'mass is given without b: give both mass and b '// &
                       '(gamma = b/mass, eq. 2.1), or gamma alone')
      else
        call set_error(status, PENDULA_ERR_DOMAIN, 'b is given without mass: give both mass and b '// &
                       '(gamma = b/mass, eq. 2.1), or gamma alone')
      end if
      return
    end if
    if (present(mass)) then
      call damping_rate(b, mass, gb, st)
      if (st%code /= PENDULA_OK) then
        status = st
        return
      end if
      if (present(gamma_in)) then
        if (abs(gb - gamma_in) > 1.0e-12_wp*max(gb, gamma_in)) then
          call set_error(status, PENDULA_ERR_DOMAIN, 'gamma = '//format_sci(gamma_in, 4)// &
                         ' and b/mass = '//format_sci(gb, 4)//' disagree: give gamma, or mass and b, not both')
          return
        end if
      end if
      gamma = gb
    end if
  end subroutine scene_physics

  ! sqrt(g/l) - w0 from g/l and its root in double-double (w0 = fl(sqrt(g/l))
  ! is off by up to half an ulp; near the separatrix that moves 1 - m by a
  ! large fraction of itself).  0 where g/l would leave the normal range.
  pure real(wp) function w0_residual(g, length, w0) result(lo)
    real(wp), intent(in) :: g, length, w0
    real(wp) :: rh, rl, sh, sl
    lo = 0
    if (abs(exponent(g) - exponent(length)) > 900 .or. abs(exponent(g)) > 900 .or. &
        abs(exponent(length)) > 900) return
    call dd_div_d(g, 0.0_wp, length, rh, rl)
    call dd_sqrt(rh, rl, sh, sl)
    lo = (sh - w0) + sl
  end function w0_residual

  !> Build a scene.  theta0 [rad], omega0 [rad/s] finite (state at t = 0);
  !> t(:) [s] output times, finite, >= 0, strictly increasing, at least one
  !> (may be empty only for want = SCENE_WANT_PERIOD); w0 > 0, gamma >= 0
  !> [1/s]; tol > 0 [rad]; want one of SCENE_WANT_*; model (optional) one of
  !> SCENE_MODEL_* (default AUTO); w0lo (optional, default 0): w0's rounding
  !> residual from scene_physics, |w0lo| <= eps w0, so that the closed forms
  !> use the energy of the data g, l as given; drive (optional): a drive
  !> (pendula_drive) of the pendulum, see check_scene_drive for its rules.  On
  !> bad input status names the argument.
  pure subroutine scene_init(scene, theta0, omega0, t, w0, gamma, tol, want, status, model, w0lo, drive)
    type(scene_t), intent(out) :: scene  !< the scene built (default fields on error)
    real(wp), intent(in) :: theta0  !< initial angle [rad] at t = 0, finite
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s] at t = 0, finite
    real(wp), intent(in) :: t(:)  !< output times [s], finite, >= 0, strictly increasing; >= 1 unless want = period
    real(wp), intent(in) :: w0  !< natural frequency sqrt(g/l) [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate b/m [1/s], >= 0 (0 for want = period)
    real(wp), intent(in) :: tol  !< absolute tolerance on theta [rad] and Omega/w0 over the window, > 0
    integer, intent(in) :: want  !< what is asked: one of SCENE_WANT_*
    type(status_t), intent(out) :: status  !< PENDULA_OK, or the error code and a message naming the argument
    integer, intent(in), optional :: model  !< forced model, one of SCENE_MODEL_* (default SCENE_MODEL_AUTO)
    real(wp), intent(in), optional :: w0lo  !< rounding residual of w0 [1/s], |w0lo| <= eps w0 (default 0)
    type(drive_t), intent(in), optional :: drive  !< the drive (optional; none: undriven)
    integer :: mdl, ist
    real(wp) :: lo
    mdl = SCENE_MODEL_AUTO
    if (present(model)) mdl = model
    lo = 0
    if (present(w0lo)) lo = w0lo
    call check_fields(theta0, omega0, t, w0, gamma, tol, want, mdl, status)
    call check_w0lo(w0, lo, status)
    if (present(drive)) call drive_first(.true., drive, want, mdl, status)
    if (status%code /= PENDULA_OK) return
    if (present(drive)) then
      scene%driven = .true.
      scene%drive = drive
    end if
    scene%theta0 = theta0
    scene%omega0 = omega0
    scene%w0 = w0
    scene%w0lo = lo
    scene%gamma = gamma
    scene%tol = tol
    scene%want = want
    scene%model = mdl
    allocate (scene%t(size(t)), stat=ist)
    call check_alloc(ist, 'the output times t', int(size(t), i8), 8, status)
    if (status%code /= PENDULA_OK) return
    scene%t(:) = t
  end subroutine scene_init

  !> Check a scene's fields in place (no copy): the rules of scene_init, for
  !> a scene_t built or changed by hand.  status names the first bad field.
  pure subroutine check_scene(scene, status)
    type(scene_t), intent(in) :: scene  !< scene to check, built or changed by hand
    type(status_t), intent(inout) :: status  !< the first bad field is reported here; else left unchanged
    if (.not. allocated(scene%t)) then
      call set_error(status, PENDULA_ERR_SIZE, 'the scene has no output times: build it with scene_init')
      return
    end if
    call check_fields(scene%theta0, scene%omega0, scene%t, scene%w0, scene%gamma, scene%tol, scene%want, &
                      scene%model, status)
    call check_w0lo(scene%w0, scene%w0lo, status)
    call drive_first(scene%driven, scene%drive, scene%want, scene%model, status)
  end subroutine check_scene

  ! The drive's rules (check_scene_drive) take precedence over the undriven
  ! scene's on want and model: with a drive, 'period needs gamma = 0' or
  ! 'exact needs gamma = 0' would name the wrong cure.
  pure subroutine drive_first(driven, drive, want, model, status)
    logical, intent(in) :: driven
    type(drive_t), intent(in) :: drive
    integer, intent(in) :: want, model
    type(status_t), intent(inout) :: status
    type(status_t) :: st
    call check_scene_drive(driven, drive, want, model, st)
    if (st%code /= PENDULA_OK) status = st
  end subroutine drive_first

  !> The rules on a scene's drive (pendula_scene_driven): a valid drive
  !> (check_drive); with amplitude 0 the scene is the undriven one, every rule
  !> of it applies and nothing more.  Otherwise want = period (a driven motion
  !> has no period of its own) and want = events (the driven integrator
  !> samples the output times only: no dense output to place events) are
  !> errors, and a forced model must be linear (torque drive only: the
  !> linearised pivot drive is Mathieu's equation, no closed form) or rk4.
  pure subroutine check_scene_drive(driven, drive, want, model, status)
    logical, intent(in) :: driven  !< whether the scene has a drive
    type(drive_t), intent(in) :: drive  !< the drive (ignored when not driven)
    integer, intent(in) :: want  !< the scene's want, SCENE_WANT_*
    integer, intent(in) :: model  !< the scene's model, SCENE_MODEL_* (AUTO: the choice)
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    if (status%code /= PENDULA_OK .or. .not. driven) return
    call check_drive(drive, status)
    if (status%code /= PENDULA_OK .or. drive%amplitude == 0) return
    if (want == SCENE_WANT_PERIOD .or. want == SCENE_WANT_EVENTS) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'want = '//trim(merge('period', 'events', want == SCENE_WANT_PERIOD))// &
                     ' is not offered with a drive (amplitude '//format_sci(drive%amplitude, 4)// &
                     '): a driven scene answers want = state, theta, final or energy')
      return
    end if
    call check_driven_model(model, drive, status)
  end subroutine check_scene_drive

  !> The models of a driven scene (drive amplitude /= 0): auto, linear (the
  !> linearised driven oscillator, torque drive only) or rk4 (the driven RK4
  !> kernel); any other is an error naming them.
  pure subroutine check_driven_model(model, drive, status)
    integer, intent(in) :: model  !< model code, SCENE_MODEL_*
    type(drive_t), intent(in) :: drive  !< the drive (amplitude /= 0)
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    if (status%code /= PENDULA_OK) return
    if (model == SCENE_MODEL_LINEAR .and. drive%kind /= DRIVE_TORQUE) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'model = linear needs a torque drive: the linearised pivot '// &
                     'drive is Mathieu''s equation, with no closed form; use rk4')
    else if (model /= SCENE_MODEL_AUTO .and. model /= SCENE_MODEL_LINEAR .and. model /= SCENE_MODEL_RK4) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'model = '//scene_model_name(model)// &
                     ' does not apply with a drive: a driven scene is answered by linear (torque drive) or rk4')
    end if
  end subroutine check_driven_model

  ! w0lo is a rounding residual: finite, |w0lo| <= eps w0.
  pure subroutine check_w0lo(w0, w0lo, status)
    real(wp), intent(in) :: w0, w0lo
    type(status_t), intent(inout) :: status
    if (status%code /= PENDULA_OK) return
    if (.not. abs(w0lo) <= epsilon(w0)*w0) call set_error(status, PENDULA_ERR_DOMAIN, 'w0lo = '// &
                                   format_sci(w0lo, 4)//' is out of range: the rounding residual of w0 must be within eps w0 = '// &
                                                     format_sci(epsilon(w0)*w0, 4)//' (from scene_physics; 0 when w0 is the datum)')
  end subroutine check_w0lo

  ! The rules on a scene's fields (scene_init).
  pure subroutine check_fields(theta0, omega0, t, w0, gamma, tol, want, mdl, status)
    real(wp), intent(in) :: theta0, omega0, t(:), w0, gamma, tol
    integer, intent(in) :: want, mdl
    type(status_t), intent(out) :: status
    call check_finite('theta0', theta0, status)
    call check_finite('omega0', omega0, status)
    call check_positive('w0', w0, status)
    call check_nonnegative('gamma', gamma, status)
    call check_positive('tol', tol, status)
    if (status%code /= PENDULA_OK) return
    if (want < SCENE_WANT_STATE .or. want > SCENE_WANT_EVENTS) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'want = '//format_int(want)//' is unknown: it must be '// &
                     'one of '//scene_want_list())
      return
    end if
    if (mdl < SCENE_MODEL_AUTO .or. mdl > SCENE_MODEL_TAYLOR) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'model = '//format_int(mdl)//' is unknown: it must be '// &
                     'one of '//scene_model_list(SCENE_MODEL_AUTO))
      return
    end if
    if (want /= SCENE_WANT_PERIOD) call check_size('t', size(t), 1, status)
    call check_increasing('t', t, status)
    if (status%code /= PENDULA_OK) return
    if (size(t) > 0) then
      if (t(1) < 0) then
        call set_error(status, PENDULA_ERR_DOMAIN, 't[0] = '//format_sci(t(1), 4)// &
                       ' is out of range: output times must be >= 0 (the initial state holds at t = 0)')
        return
      end if
    end if
    if (want == SCENE_WANT_PERIOD .and. gamma > 0) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'want = period needs gamma = 0 (gamma = '//format_sci(gamma, 4)// &
                     ': the damped motion is not periodic); use want = events for its turning points')
      return
    end if
    call check_model_gamma(mdl, gamma, status)
  end subroutine check_fields

  !> The closed forms small_angle and exact describe the undamped pendulum
  !> only: model one of them with gamma > 0 is an error naming both.
  pure subroutine check_model_gamma(model, gamma, status)
    integer, intent(in) :: model  !< model code, SCENE_MODEL_*
    real(wp), intent(in) :: gamma  !< damping rate of the scene [1/s], >= 0
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    if (gamma > 0 .and. (model == SCENE_MODEL_SMALL_ANGLE .or. model == SCENE_MODEL_EXACT)) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'model = '//scene_model_name(model)// &
                     ' needs gamma = 0 (gamma = '//format_sci(gamma, 4)//'): use linear, rk4 or cvode')
    end if
  end subroutine check_model_gamma

  !> model = cvode in a build without SUNDIALS is PENDULA_ERR_UNAVAILABLE.
  subroutine check_model_built(model, status)
    integer, intent(in) :: model  !< model code, SCENE_MODEL_*
    type(status_t), intent(inout) :: status  !< PENDULA_ERR_UNAVAILABLE for cvode without SUNDIALS, else left unchanged
    if (model == SCENE_MODEL_CVODE .and. .not. cvode_available()) call set_error(status, &
                                        PENDULA_ERR_UNAVAILABLE, 'model = cvode is not available: this build has no SUNDIALS CVODE')
  end subroutine check_model_built

  !> The work budget [RK4 steps] from the optional max_steps (>= 1; default SCENE_STEP_CAP).
  pure subroutine get_budget(budget, status, max_steps)
    real(wp), intent(out) :: budget  !< the work budget [RK4 steps]
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    integer(i8), intent(in), optional :: max_steps  !< budget asked [RK4 steps], >= 1 (optional)
    budget = SCENE_STEP_CAP
    if (.not. present(max_steps)) return
    budget = real(max_steps, wp)
    if (max_steps < 1) call set_error(status, PENDULA_ERR_DOMAIN, 'max_steps = '//format_sci(budget, 4)// &
                                      ' is out of range: it must be >= 1')
  end subroutine get_budget

  !> Output arrays for the want: every t, or only t(n) for want = final
  !> (PENDULA_ERR_MEMORY in status when they cannot be allocated).
  pure subroutine alloc_outputs(scene, result, status)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    type(scene_result_t), intent(inout) :: result  !< gets t and the state (and energy) arrays the want needs
    type(status_t), intent(inout) :: status  !< set when an allocation fails, else left unchanged
    integer :: n, m, ist, k
    n = size(scene%t)
    if (scene%want == SCENE_WANT_FINAL) then
      m = 1
    else if (scene%want == SCENE_WANT_PERIOD .or. scene%want == SCENE_WANT_EVENTS) then
      m = 0
    else
      m = n
    end if
    k = merge(4, 3, scene%want == SCENE_WANT_ENERGY)
    if (allocated(result%t)) deallocate (result%t)
    if (allocated(result%theta)) deallocate (result%theta)
    if (allocated(result%omega)) deallocate (result%omega)
    if (allocated(result%energy)) deallocate (result%energy)
    allocate (result%t(m), result%theta(m), result%omega(m), stat=ist)
    if (ist == 0 .and. scene%want == SCENE_WANT_ENERGY) allocate (result%energy(m), stat=ist)
    call check_alloc(ist, 'the outputs (t, theta, omega'//trim(merge(', energy', '        ', k == 4))//')', &
                     int(k, i8)*m, 8, status)
    if (status%code /= PENDULA_OK) return
    if (m > 0) result%t(:) = scene%t(n - m + 1:n)
  end subroutine alloc_outputs

  !> Empty output arrays t, theta, omega (a want with no time series).
  pure subroutine empty_outputs(result, status)
    type(scene_result_t), intent(inout) :: result  !< gets empty t, theta, omega (any old ones released)
    type(status_t), intent(inout) :: status  !< set when an allocation fails, else left unchanged
    integer :: ist
    if (allocated(result%t)) deallocate (result%t)
    if (allocated(result%theta)) deallocate (result%theta)
    if (allocated(result%omega)) deallocate (result%omega)
    allocate (result%t(0), result%theta(0), result%omega(0), stat=ist)
    call check_alloc(ist, 'the (empty) outputs', 0_i8, 8, status)
  end subroutine empty_outputs

  !> Energies from the state, and empty event arrays where no events were asked.
  pure subroutine finish_outputs(scene, result, status)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    type(scene_result_t), intent(inout) :: result  !< state filled in; gets energies and empty event arrays as needed
    type(status_t), intent(inout) :: status  !< set when an allocation fails, else left unchanged
    integer :: ist
    if (scene%want == SCENE_WANT_ENERGY) &
      result%energy(:) = pendulum_energy(result%theta, result%omega, scene%w0)
    if (.not. allocated(result%event_t)) then
      allocate (result%event_t(0), result%event_theta(0), result%event_omega(0), result%event_kind(0), stat=ist)
      call check_alloc(ist, 'the (empty) event lists', 0_i8, 8, status)
    end if
  end subroutine finish_outputs

end module pendula_scene_setup
