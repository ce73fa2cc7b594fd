! f2py-facing layer for the scenes concern (pendula_scene).  Plain
! subroutines, c_double/c_int arguments, explicit-shape arrays, a status code
! + message.  Counters (int64 in Fortran) travel as doubles (exact to 2**53).
! No numerics here: the choice of model, the estimates and the solve are all
! in pendula_scene.

subroutine scene_physics_f2py(g, length, gamma_in, mass, b, has_gamma, has_mass, has_b, &
    w0, gamma, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: wp
  use pendula_status, only: status_t
  use pendula_scene, only: scene_physics
  implicit none
  !f2py threadsafe
  real(c_double), intent(in) :: g, length, gamma_in, mass, b
  integer(c_int), intent(in) :: has_gamma, has_mass, has_b
  real(c_double), intent(out) :: w0, gamma
  integer(c_int), intent(out) :: code
  character(len=256), intent(out) :: msg
  type(status_t) :: st
  real(wp) :: w, gm
  ! every combination of present arguments, so that scene_physics sees them as Fortran optionals
  if (has_gamma /= 0 .and. has_mass /= 0 .and. has_b /= 0) then
    call scene_physics(g, length, w, gm, st, gamma_in=gamma_in, mass=mass, b=b)
  else if (has_gamma /= 0 .and. has_mass /= 0) then
    call scene_physics(g, length, w, gm, st, gamma_in=gamma_in, mass=mass)
  else if (has_gamma /= 0 .and. has_b /= 0) then
    call scene_physics(g, length, w, gm, st, gamma_in=gamma_in, b=b)
  else if (has_gamma /= 0) then
    call scene_physics(g, length, w, gm, st, gamma_in=gamma_in)
  else if (has_mass /= 0 .and. has_b /= 0) then
    call scene_physics(g, length, w, gm, st, mass=mass, b=b)
  else if (has_mass /= 0) then
    call scene_physics(g, length, w, gm, st, mass=mass)
  else if (has_b /= 0) then
    call scene_physics(g, length, w, gm, st, b=b)
  else
    call scene_physics(g, length, w, gm, st)
  end if
  w0 = w
  gamma = gm
  code = st%code
  msg = st%message
end subroutine scene_physics_f2py

subroutine scene_check_f2py(n, t, theta0, omega0, w0, gamma, tol, want, model, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t
  use pendula_scene, only: scene_t, scene_init
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n, want, model
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, gamma, tol
  integer(c_int), intent(out) :: code
  character(len=256), intent(out) :: msg
  type(status_t) :: st
  type(scene_t) :: scene
  call scene_init(scene, theta0, omega0, t, w0, gamma, tol, int(want), st, int(model))
  code = st%code
  msg = st%message
end subroutine scene_check_f2py

! Solve a scene (fixed = 0: choose and verify; fixed = 1: run `model` at
! `setting` with no verification).  Outputs: nout of the n slots of
! tout/theta/omega/energy are used; events go into the m slots of ev_*, with
! n_events the number found (more than m: call again with a larger m).
! info = [error_estimate, setting, period, wall_time, closed_form_evals,
!         rhs_evals, steps, runs, tol_met, event_time_error]
subroutine scene_solve_f2py(n, t, theta0, omega0, w0, gamma, tol, want, model, fixed, setting, m, &
    max_steps, control, nout, tout, theta, omega, energy, ev_t, ev_kind, ev_theta, ev_omega, n_events, model_out, &
    info, reason, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, PENDULA_OK
  use pendula_scene, only: scene_t, scene_result_t, scene_init, scene_solve, scene_run_model
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n, want, model, fixed, m
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, gamma, tol, setting, max_steps
  integer(8), intent(inout) :: control(2)   ! int64 [cancel flag, progress] (pendula_control), in place
  integer(c_int), intent(out) :: nout, n_events, model_out
  real(c_double), intent(out) :: tout(n), theta(n), omega(n), energy(n)
  real(c_double), intent(out) :: ev_t(m), ev_theta(m), ev_omega(m)
  integer(c_int), intent(out) :: ev_kind(m)
  real(c_double), intent(out) :: info(10)
  character(len=256), intent(out) :: reason
  integer(c_int), intent(out) :: code
  character(len=256), intent(out) :: msg
  type(status_t) :: st
  type(scene_t) :: scene
  type(scene_result_t) :: res
  integer :: k
  integer(i8) :: budget
  ! max_steps arrives as a double (Python int of any size); clamp to int64.
  budget = int(min(max(max_steps, -9.0e18_c_double), 9.0e18_c_double), i8)
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
  call scene_init(scene, theta0, omega0, t, w0, gamma, tol, int(want), st, &
      merge(0, int(model), fixed /= 0))
  if (st%code == PENDULA_OK) then
    if (fixed /= 0) then
      call scene_run_model(scene, int(model), setting, res, st, control, budget)
    else
      call scene_solve(scene, res, st, control, budget)
    end if
  end if
  code = st%code
  msg = st%message
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
  info = [res%error_estimate, res%setting, res%period, res%cost%wall_time, &
      real(res%cost%closed_form_evals, c_double), real(res%cost%rhs_evals, c_double), &
      real(res%cost%steps, c_double), real(res%cost%runs, c_double), merge(1.0_c_double, 0.0_c_double, &
      res%tol_met), res%event_time_error]
  reason = res%reason
end subroutine scene_solve_f2py

! A priori error estimate of one model for a scene (see scene_estimate).
subroutine scene_estimate_f2py(n, t, theta0, omega0, w0, gamma, tol, want, model, estimate, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_status, only: status_t, PENDULA_OK
  use pendula_scene, only: scene_t, scene_init, scene_estimate
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n, want, model
  real(c_double), intent(in) :: t(n), theta0, omega0, w0, gamma, tol
  real(c_double), intent(out) :: estimate
  integer(c_int), intent(out) :: code
  character(len=256), intent(out) :: msg
  type(status_t) :: st
  type(scene_t) :: scene
  estimate = 0
  call scene_init(scene, theta0, omega0, t, w0, gamma, tol, int(want), st)
  if (st%code == PENDULA_OK) call scene_estimate(scene, int(model), estimate, st)
  code = st%code
  msg = st%message
end subroutine scene_estimate_f2py
