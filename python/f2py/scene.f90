! f2py-facing layer for the scenes concern (pendula_scene).  Plain
! subroutines, c_double/c_int arguments, explicit-shape arrays, a status code
! + message.  Counters (int64 in Fortran) travel as doubles (exact to 2**53).
! No numerics here: the choice of model, the estimates and the solve are all
! in pendula_scene.

subroutine scene_physics_f2py(g, length, gamma_in, mass, b, has_gamma, has_mass, has_b, &
                              w0, gamma, w0lo, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: wp
  use pendula_status, only: status_t, status_unpack
  use pendula_scene, only: scene_physics
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  real(c_double), intent(in) :: g, length, gamma_in, mass, b
  integer(c_int), intent(in) :: has_gamma, has_mass, has_b
  real(c_double), intent(out) :: w0, gamma, w0lo   ! w0lo: w0's rounding residual (scene_physics)
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  real(wp) :: w, gm, wl
  ! every combination of present arguments, so that scene_physics sees them as Fortran optionals
  if (has_gamma /= 0 .and. has_mass /= 0 .and. has_b /= 0) then
    call scene_physics(g, length, w, gm, st, w0lo=wl, gamma_in=gamma_in, mass=mass, b=b)
  else if (has_gamma /= 0 .and. has_mass /= 0) then
    call scene_physics(g, length, w, gm, st, w0lo=wl, gamma_in=gamma_in, mass=mass)
  else if (has_gamma /= 0 .and. has_b /= 0) then
    call scene_physics(g, length, w, gm, st, w0lo=wl, gamma_in=gamma_in, b=b)
  else if (has_gamma /= 0) then
    call scene_physics(g, length, w, gm, st, w0lo=wl, gamma_in=gamma_in)
  else if (has_mass /= 0 .and. has_b /= 0) then
    call scene_physics(g, length, w, gm, st, w0lo=wl, mass=mass, b=b)
  else if (has_mass /= 0) then
    call scene_physics(g, length, w, gm, st, w0lo=wl, mass=mass)
  else if (has_b /= 0) then
    call scene_physics(g, length, w, gm, st, w0lo=wl, b=b)
  else
    call scene_physics(g, length, w, gm, st, w0lo=wl)
  end if
  w0 = w
  gamma = gm
  w0lo = wl
  call status_unpack(st, code, msg)
end subroutine scene_physics_f2py

! The drive of a scene travels as has_drive (0: none) and the drive's kind
! code (pendula_drive), amplitude, frequency and phase.
subroutine scene_check_f2py(n, t, theta0, omega0, w0, gamma, tol, want, model, has_drive, dkind, damp, dfreq, dphase, &
                            code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, status_unpack
  use pendula_scene, only: scene_t, scene_init
  use pendula_drive, only: drive_t
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, want, model, has_drive, dkind
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, gamma, tol, damp, dfreq, dphase
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(scene_t) :: scene
  if (has_drive /= 0) then
    call scene_init(scene, theta0, omega0, t, w0, gamma, tol, int(want), st, int(model), &
                    drive=drive_t(int(dkind), damp, dfreq, dphase))
  else
    call scene_init(scene, theta0, omega0, t, w0, gamma, tol, int(want), st, int(model))
  end if
  call status_unpack(st, code, msg)
end subroutine scene_check_f2py

! Most events the scene's motion can have in (0, t_end] (scene_event_bound):
! the capacity of the event slots of scene_solve_f2py.
subroutine scene_event_bound_f2py(w0, t_end, theta0, omega0, bound)
  use, intrinsic :: iso_c_binding, only: c_double
  use pendula_scene, only: scene_event_bound
  implicit none
  !f2py threadsafe
  real(c_double), intent(in) :: w0, t_end, theta0, omega0
  real(c_double), intent(out) :: bound
  bound = real(scene_event_bound(w0, t_end, theta0, omega0), c_double)
end subroutine scene_event_bound_f2py

! Solve a scene (fixed = 0: choose and verify; fixed = 1: run `model` at
! `setting` with no verification).  The scene is checked once, by
! scene_solve / scene_run_model.  Outputs: nout of the n slots of
! tout/theta/omega/energy are used; events go into the m slots of ev_*
! (m from scene_event_bound_f2py), n_events the number found.  info: the
! numbers of the result, at the SCENE_INFO_* slots of pendula_scene_codes
! (ninfo = SCENE_INFO_SIZE, which Python reads from pendula/_codes.py).
subroutine scene_solve_f2py(n, t, theta0, omega0, w0, w0lo, gamma, tol, want, model, fixed, setting, m, ninfo, &
                            max_steps, control, has_drive, dkind, damp, dfreq, dphase, nout, tout, theta, omega, energy, &
                            ev_t, ev_kind, ev_theta, ev_omega, n_events, model_out, info, reason, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_ode, only: step_budget
  use pendula_status, only: status_t, status_unpack, set_error, check_alloc, PENDULA_OK, PENDULA_ERR_SIZE
  use pendula_format, only: format_int
  use pendula_scene, only: scene_t, scene_result_t, scene_solve, scene_run_model
  use pendula_drive, only: drive_t
  use pendula_scene_codes, only: SCENE_INFO_SIZE, SCENE_INFO_ERROR_ESTIMATE, SCENE_INFO_SETTING, &
                                 SCENE_INFO_PERIOD, SCENE_INFO_WALL_TIME, SCENE_INFO_CLOSED_FORM_EVALS, SCENE_INFO_RHS_EVALS, &
                              SCENE_INFO_STEPS, SCENE_INFO_RUNS, SCENE_INFO_TOL_MET, SCENE_INFO_EVENT_TIME_ERROR, SCENE_INFO_STEP, &
                                 SCENE_INFO_RTOL
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: n, want, model, fixed, m, ninfo
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, w0lo, gamma, tol, setting, max_steps
  integer(8), intent(inout) :: control(2)   ! int64 [cancel flag, progress] (pendula_control), in place
  integer(c_int), intent(in) :: has_drive, dkind   ! the drive (scene_check_f2py)
  real(c_double), intent(in) :: damp, dfreq, dphase
  integer(c_int), intent(out) :: nout, n_events, model_out
  real(c_double), intent(out) :: tout(n), theta(n), omega(n), energy(n)
  real(c_double), intent(out) :: ev_t(m), ev_theta(m), ev_omega(m)
  integer(c_int), intent(out) :: ev_kind(m)
  real(c_double), intent(out) :: info(ninfo)
  character(len=PENDULA_MSG_LEN), intent(out) :: reason
  integer(c_int), intent(out) :: code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(scene_t) :: scene
  type(scene_result_t) :: res
  integer :: k, ist
  integer(i8) :: budget
  ! max_steps arrives as a double (Python int of any size); step_budget clamps it to int64.
  budget = step_budget(max_steps)
  nout = 0
  n_events = 0
  model_out = 0
  tout = 0
  theta = 0
  omega = 0
  energy = 0
  ev_t = 0
  ev_theta = 0
  ev_omega = 0
  ev_kind = 0
  info = 0
  reason = ''
  if (ninfo /= SCENE_INFO_SIZE) call set_error(st, PENDULA_ERR_SIZE, 'info has '//format_int(ninfo)// &
                                    ' slots, the result has '//format_int(SCENE_INFO_SIZE)//': pendula/_codes.py is stale, rebuild')
  call status_unpack(st, code, msg)
  if (st%code /= PENDULA_OK) return
  ! the times copied into a checked allocation (not by the constructor)
  scene = scene_t(theta0=theta0, omega0=omega0, w0=w0, w0lo=w0lo, gamma=gamma, tol=tol, want=int(want), &
                  model=merge(0, int(model), fixed /= 0))
  scene%driven = has_drive /= 0
  scene%drive = drive_t(int(dkind), damp, dfreq, dphase)
  allocate (scene%t(n), stat=ist)
  call check_alloc(ist, 'the output times t', int(n, i8), 8, st)
  call status_unpack(st, code, msg)
  if (st%code /= PENDULA_OK) return
  scene%t(:) = t
  if (fixed /= 0) then
    call scene_run_model(scene, int(model), setting, res, st, control, budget)
  else
    call scene_solve(scene, res, st, control, budget)
  end if
  call status_unpack(st, code, msg)
  if (st%code /= PENDULA_OK) return
  nout = size(res%t)
  tout(1:nout) = res%t
  if (size(res%theta) == nout) theta(1:nout) = res%theta
  if (size(res%omega) == nout) omega(1:nout) = res%omega
  if (allocated(res%energy)) energy(1:size(res%energy)) = res%energy
  if (allocated(res%energy)) nout = size(res%energy)
  if (allocated(res%event_t)) then
    n_events = size(res%event_t)
    k = min(n_events, int(m))
    ev_t(1:k) = res%event_t(1:k)
    ev_kind(1:k) = res%event_kind(1:k)
    ev_theta(1:k) = res%event_theta(1:k)
    ev_omega(1:k) = res%event_omega(1:k)
  end if
  model_out = res%model
  info(SCENE_INFO_ERROR_ESTIMATE) = res%error_estimate
  info(SCENE_INFO_SETTING) = res%setting
  info(SCENE_INFO_STEP) = res%step
  info(SCENE_INFO_RTOL) = res%rtol
  info(SCENE_INFO_PERIOD) = res%period
  info(SCENE_INFO_WALL_TIME) = res%cost%wall_time
  info(SCENE_INFO_CLOSED_FORM_EVALS) = real(res%cost%closed_form_evals, c_double)
  info(SCENE_INFO_RHS_EVALS) = real(res%cost%rhs_evals, c_double)
  info(SCENE_INFO_STEPS) = real(res%cost%steps, c_double)
  info(SCENE_INFO_RUNS) = real(res%cost%runs, c_double)
  info(SCENE_INFO_TOL_MET) = merge(1.0_c_double, 0.0_c_double, res%tol_met)
  info(SCENE_INFO_EVENT_TIME_ERROR) = res%event_time_error
  reason = res%reason
end subroutine scene_solve_f2py

! Predicted work of scene_solve_f2py with the same arguments [RK4 steps]
! (scene_solve_work, or scene_run_work when fixed /= 0): Python runs a call
! predicted long in a worker thread that Ctrl-C can stop.  0 for an invalid
! scene (the solve refuses it at once).
subroutine scene_work_f2py(n, t, theta0, omega0, w0, w0lo, gamma, tol, want, model, fixed, setting, has_drive, dkind, &
                           damp, dfreq, dphase, work)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_scene, only: scene_t
  use pendula_scene_work, only: scene_solve_work, scene_run_work
  use pendula_drive, only: drive_t
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n, want, model, fixed, has_drive, dkind
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, w0lo, gamma, tol, setting, damp, dfreq, dphase
  real(c_double), intent(out) :: work
  type(scene_t) :: scene
  integer :: ist
  scene = scene_t(theta0=theta0, omega0=omega0, w0=w0, w0lo=w0lo, gamma=gamma, tol=tol, want=int(want), &
                  model=merge(0, int(model), fixed /= 0))
  scene%driven = has_drive /= 0
  scene%drive = drive_t(int(dkind), damp, dfreq, dphase)
  ! times that cannot be copied: predicted short (0), so that the solve runs
  ! inline and reports PENDULA_ERR_MEMORY itself
  allocate (scene%t(n), stat=ist)
  work = 0
  if (ist /= 0) return
  scene%t(:) = t
  if (fixed /= 0) then
    work = scene_run_work(scene, int(model), setting)
  else
    work = scene_solve_work(scene)
  end if
end subroutine scene_work_f2py
