!> Damped scenes that start at or near an unstable equilibrium theta = k pi
!> (k odd): the hang there integrated in top-centred coordinates.
!>
!> The data as given is exact: theta0 = fl(pi) is pi - 1.2246e-16, and its
!> distance to the top phi0 = k pi - theta0 is known to eps relative with pi
!> carried in three doubles (pendula_constants).  In theta the integrators
!> store that distance as a difference of numbers near k pi, so each step
!> rounds it by eps k pi: relative to phi0 = 1e-16 that is everything, and
!> the hang amplifies it by ~1/phi0 (estimates of radians, or CVODE at
!> hundreds of times the cost).  Here phi = k pi - theta obeys
!>     phi'' = -gamma phi' + w0^2 sin(phi)
!> (sin(k pi - phi) = sin(phi) for odd k).  While |phi| is small the hang is
!> the saddle's linear motion phi = a e^(lp t) + b e^(lm t) in closed form
!> (closed_hang: sin(phi) - phi bounded by |phi|**3/6 through the variation
!> of constants), up to |phi| ~ sqrt(tol); from there RK4 in phi
!> until the motion has left the top (|phi| ~ PHI_EXIT, predicted from the
!> saddle's unstable rate lambda = sqrt(w0^2 + gamma^2/4) - gamma/2), with
!> the step from the error target and a Richardson check at 2h.  From there
!> the ordinary path (pendula_scene_handover: RK4 or CVODE, then the linear
!> form about the bottom) answers the rest of the window at tol/2.
!>
!> Error: outputs during the hang carry the RK4 estimate of phi; the state
!> handed over carries that estimate and the rounding of theta = k pi - phi
!> (eps |theta|), which the later motion amplifies at most by the gain of a
!> shift along it (max speed / speed at the hand-over, in (theta, Omega/w0))
!> times the sensitivity of the next approach to the top (small damping
!> brings it back near -pi, at a distance ~ sqrt(4 gamma/w0) of the
!> separatrix energy): an a priori bound, TOP_SAFETY on top.  The part of
!> the RK4 error along the flow at the hand-over (most of it: RK4 errs on
!> the growing mode's rate, a shift in time) carries only the first factor.
module pendula_scene_top
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_sci
  use pendula_status, only: status_t, PENDULA_OK, set_error, check_alloc, PENDULA_ERR_CANCELLED
  use pendula_constants, only: pi, pi_lo, pi_lo2
  use pendula_double_double, only: two_prod
  use pendula_control, only: CONTROL_SIZE, cancel_requested
  use pendula_scene_codes, only: scene_model_name, SCENE_MODEL_LINEAR, SCENE_MODEL_AUTO, SCENE_WANT_PERIOD, &
                                 SCENE_WANT_EVENTS
  use pendula_scene_types, only: scene_t, scene_result_t, scene_like
  use pendula_scene_setup, only: alloc_outputs, finish_outputs
  use pendula_scene_estimates, only: choose_model
  use pendula_scene_closed, only: solve_closed
  use pendula_scene_handover, only: solve_integrated, add_cost
  implicit none
  private

  public :: top_start, solve_top, top_hang_work

  !> A start within this distance of k pi (in (theta, Omega/w0)) hangs.
  real(wp), parameter :: TOP_NEAR = 0.05_wp
  !> |phi| at which the motion has left the top (the hand-over).
  real(wp), parameter :: PHI_EXIT = 0.5_wp
  !> Safety on the a priori gain of the motion after the hand-over.
  real(wp), parameter :: TOP_SAFETY = 4
  !> Refinements of the RK4 step in phi.
  integer, parameter :: MAX_REFINE = 4
  real(wp), parameter :: eps = epsilon(1.0_wp)

contains

  !> is_top: whether a checked scene starts near an unstable equilibrium k pi (k odd)
  !> with damping (gamma > 0) and wants state, theta, final or energy: then
  !> solve_top answers it.  k: the odd integer (as a real); phi0, v0: the
  !> top-centred start k pi - theta0 (to eps relative) and -Omega0.
  pure subroutine top_start(scene, is_top, k, phi0, v0)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    logical, intent(out) :: is_top  !< true when solve_top answers the scene
    real(wp), intent(out) :: k  !< the odd integer of the nearest top k pi (0 when none applies)
    real(wp), intent(out) :: phi0  !< distance k pi - theta0 [rad], to eps relative
    real(wp), intent(out) :: v0  !< top-centred start rate -Omega0 [rad/s]
    real(wp) :: p, e
    is_top = .false.
    k = 0
    phi0 = 0
    v0 = -scene%omega0
    if (.not. scene%gamma > 0 .or. abs(scene%theta0) > 2.0_wp**40) return
    if (scene%want == SCENE_WANT_PERIOD) return
    k = anint(scene%theta0/pi)
    if (modulo(k, 2.0_wp) /= 1) return
    ! k pi = p + e + k pi_lo + k pi_lo2 exactly to ~1e-32 |k pi|; p - theta0 is exact
    call two_prod(k, pi, p, e)
    phi0 = (p - scene%theta0) + (e + (k*pi_lo + k*pi_lo2))
    is_top = hypot(phi0, v0/scene%w0) < TOP_NEAR
    ! events: a turning point in the hang (a start towards the top that falls
    ! back, phi' = lp a e^(lp t) + lm b e^(lm t) = 0) is left to the ordinary path
    if (is_top .and. scene%want == SCENE_WANT_EVENTS) is_top = no_turn(scene, phi0, v0)
  end subroutine top_start

  ! The saddle's rates (lp > 0 > lm) and the modes phi = a e^(lp t) + b e^(lm t).
  pure subroutine saddle(scene, phi0, v0, lp, lm, a, b)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: phi0, v0
    real(wp), intent(out) :: lp, lm, a, b
    lm = -(scene%gamma/2 + hypot(scene%gamma/2, scene%w0))
    lp = scene%w0**2/(-lm)
    a = (v0 - lm*phi0)/(lp - lm)
    b = phi0 - a
  end subroutine saddle

  ! No sign change of phi' = lp a e^(lp t) + lm b e^(lm t) for t > 0 in the
  ! linear motion about the top (e^((lp - lm) t) = -lm b/(lp a) has no root t > 0).
  pure logical function no_turn(scene, phi0, v0)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: phi0, v0
    real(wp) :: lp, lm, a, b
    call saddle(scene, phi0, v0, lp, lm, a, b)
    ! phi' = 0 at e^((lp - lm) t) = -lm b/(lp a): a root t > 0 needs the ratio > 1
    ! a start at rest turns at t = 0 only (no event); otherwise a root exists
    ! when a b > 0 and |lm b| > lp |a| (taken from half of that, a margin)
    no_turn = v0 == 0 .or. .not. (a*b > 0 .and. abs(lm*b) >= 0.5_wp*lp*abs(a))
  end function no_turn

  ! The hang from the top-centred start (phi0, v0): the time tx [s] at which
  ! the growing mode reaches PHI_EXIT (at most tend), the gain of the motion
  ! after tx on an error of the state handed over across the flow there, the
  ! largest speed vmax [rad/s] after it, and the a priori target [rad] of the
  ! hang (the error along the flow, a time shift, has the gain without the
  ! sensitivity factor; the part across it, frac, was 0.4 % .. 18 % on the
  ! benchmark grid, growing with gamma/w0): a guess for the first step only,
  ! solve_top checks the carried error measured at tx.
  pure subroutine hang_plan(scene, phi0, v0, tend, tx, gain, vmax, target)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: phi0, v0, tend
    real(wp), intent(out) :: tx, gain, vmax, target
    real(wp) :: lp, lm, a, b, near, frac
    ! the saddle's rates, and the growing mode's amplitude a
    call saddle(scene, phi0, v0, lp, lm, a, b)
    tx = tend
    if (abs(a) > 0) tx = min(tend, max(0.0_wp, log(PHI_EXIT/abs(a))/lp))
    vmax = max(2*scene%w0, 2*scene%gamma + scene%w0)
    near = min(1.0_wp, sqrt(4*scene%gamma/scene%w0))
    gain = TOP_SAFETY*vmax/(lp*PHI_EXIT)*(1 + 2/near)
    frac = min(0.5_wp, 0.05_wp + 0.1_wp*scene%gamma/scene%w0)
    target = scene%tol/(4*(TOP_SAFETY*vmax/(lp*PHI_EXIT) + frac*gain))
  end subroutine hang_plan

  ! The first RK4 step of the hang over [0, T] for an error target [rad].
  ! The motion there is phi = a e^(lp t) + b e^(lm t) (plus the cubic of
  ! sin, small for |phi| <= PHI_EXIT).  RK4 follows the growing mode with a
  ! relative error ~ (lp h)^4/120 per unit lp t, i.e. an absolute one of that
  ! times the largest |phi| reached, phimax (the predicted size, not
  ! PHI_EXIT: a start 1e-16 from the top under heavy damping stays ~1e-8 over
  ! a short window), doubled.  Its accuracy scale is lp, not the decaying
  ! rate -lm (which is >> lp when overdamped): the decaying mode, of
  ! amplitude |b| <= the start's, only needs stability of the run at 2h
  ! (-lm 2h <= 2 < 2.78, RK4's real-axis limit); the Richardson pair checks
  ! what the model leaves out.
  ! The run covers [t_from, t_end] (t_from > 0: after the closed-form start).
  pure real(wp) function hang_step(scene, phi0, target, t_from, t_end) result(h)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: phi0, target, t_from, t_end
    real(wp) :: lp, lm, a, b, phimax
    call saddle(scene, phi0, -scene%omega0, lp, lm, a, b)
    phimax = max(abs(phi0), min(PHI_EXIT, abs(a)*exp(min(lp*t_end, 700.0_wp))) + abs(b), tiny(1.0_wp))
    h = min((120*target/(2*phimax*max(1.0_wp, lp*(t_end - t_from))))**0.25_wp, 0.5_wp)/lp
    h = min(h, 1/(-lm))
  end function hang_step

  !> Predicted work [RK4 steps] of the hang of a damped scene that starts near
  !> the top (solve_top; 0 for any other scene): the first pair of RK4 runs
  !> in phi (at h and 2h) up to where the motion leaves the top, or to t(n)
  !> when that comes first.  A prediction from closed formulas (refinements
  !> are not counted), for deciding how to run the call.
  pure real(wp) function top_hang_work(scene) result(work)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene), auto model
    real(wp) :: k, phi0, v0, tend, tx, gain, vmax, target, h, ts, rho, c2, c2o
    logical :: is_top
    work = 0
    call top_start(scene, is_top, k, phi0, v0)
    if (.not. is_top .or. scene%model /= SCENE_MODEL_AUTO) return
    tend = scene%t(size(scene%t))
    call hang_plan(scene, phi0, v0, tend, tx, gain, vmax, target)
    ! as solve_top: the hang's own outputs at tol/2, all of them when it
    ! covers the window
    if (scene%want /= SCENE_WANT_EVENTS) target = min(target, scene%tol/2)
    if (scene%want /= SCENE_WANT_EVENTS .and. tend <= tx) target = scene%tol/2
    call closed_hang(scene, phi0, v0, tx, vmax, ts, rho, c2, c2o)
    h = hang_step(scene, phi0, target, ts, tx)
    ! at most 1.5e300 (no overflow: a start exactly at the top hangs for ever)
    work = 1.5e300_wp
    if ((tx - ts)/1.0e300_wp <= h) work = 1.5_wp*(tx - ts)/h
  end function top_hang_work

  ! The closed-form start of the hang: the linear motion about the top,
  ! phi = a e^(lp t) + b e^(lm t), answers [0, ts]; RK4 in phi takes over at
  ! ts, where |a| e^(lp ts) = plin.  The omitted w0^2 (sin(phi) - phi), at
  ! most w0^2 |phi|**3/6, enters the modes by the variation of constants:
  ! c1(t) = int e^(lp (t-s)) w0^2 r(s) ds/(lp - lm) (growing mode) and c2 the
  ! same with lm (decaying mode); with |phi| <= |a| e^(lp s) + |b| e^(lm s),
  ! (x + y)**3 <= 4 (x**3 + y**3), and a factor 2 for the true motion's own
  ! size: |c1(ts)| <= rho |a| e^(lp ts) with
  !   rho = kk ((a e^(lp ts))**2/(2 lp) + |b|**3/(|a| (lp + 3|lm|))),
  ! kk = 4 w0^2/(3 (lp - lm)), and |c2| <= kk ((a e^(lp ts))**3/(3 lp + |lm|)
  ! + |b|**3 e^(lm ts)/(2|lm|)) = c2 (c2o: the same for any t <= ts).  The
  ! growing mode's part is a relative error rho of the motion: a shift in time
  ! by rho/lp, which moves the later motion by at most vmax rho/lp.  plin
  ! keeps rho (PHI_EXIT + TOP_SAFETY vmax/lp) near tol/16.  ts = 0 (RK4 from
  ! the start, as without it) when the start is not deep in the hang or
  ! when the decaying mode still matters at ts.
  pure subroutine closed_hang(scene, phi0, v0, tx, vmax, ts, rho, c2, c2o)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: phi0, v0, tx, vmax
    real(wp), intent(out) :: ts, rho, c2, c2o
    real(wp) :: lp, lm, a, b, plin, kk, pa
    ts = 0
    rho = 0
    c2 = 0
    c2o = 0
    call saddle(scene, phi0, v0, lp, lm, a, b)
    if (.not. (abs(a) > 0 .and. lp > 0)) return
    kk = 4*scene%w0**2/(3*(lp - lm))
    ! rho ~ kk plin**2/(2 lp) at most tol/(16 (PHI_EXIT + TOP_SAFETY vmax/lp))
    plin = min(1.0e-2_wp, sqrt(lp*scene%tol/(8*kk*(PHI_EXIT + TOP_SAFETY*vmax/lp))))
    if (abs(a) >= plin/16) return
    ts = min(tx, log(plin/abs(a))/lp)
    pa = abs(a)*exp(lp*ts)
    if (abs(b)*exp(lm*ts) > 1.0e-3_wp*pa) then
      ts = 0
      return
    end if
    rho = kk*(pa**2/(2*lp) + abs(b)**3/(abs(a)*(lp - 3*lm)))
    c2 = kk*(pa**3/(3*lp - lm) + abs(b)**3*exp(lm*ts)/(2*(-lm)))
    c2o = kk*(pa**3/(3*lp - lm) + abs(b)**3/(2*(-lm)))
    if (.not. rho <= 1.0e-3_wp) then
      ts = 0
      rho = 0
      c2 = 0
      c2o = 0
    end if
  end subroutine closed_hang

  !> Answer a damped scene that starts near the top (top_start): RK4 in phi
  !> over the hang, then `model`'s ordinary path from the state where the
  !> motion has left the top.  why is replaced.  done is false (nothing
  !> computed) when the hang alone would exceed the budget; status carries
  !> any error of the parts (budget, cancel).
  subroutine solve_top(scene, tend, budget, why, result, done, status, control)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tend  !< end of the window [s], t(n) (window_end), >= 0
    real(wp), intent(in) :: budget  !< work budget [RK4 steps] (a CVODE step costs SCENE_CVODE_STEP_COST)
    logical, intent(out) :: done  !< false when nothing was computed (the hang exceeds the budget)
    character(len=:), allocatable, intent(inout) :: why  !< the reason, replaced when done
    type(scene_result_t), intent(inout) :: result  !< gets the answer, its error estimate and cost when done
    type(status_t), intent(inout) :: status  !< set on an error (code, message naming the argument), else left unchanged
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag, progress (pendula_control)
    real(wp) :: k, phi0, v0, tx, tshift, gain, target, h, est, d, p, e, thx, omx, eround
    real(wp) :: vmax, carried, r, ts, rho, c2, c2o, lp, lm, ca, cb, us, ws, e_closed, e_lin, c_lin
    real(wp), allocatable :: tg(:), ph(:), vp(:), ph2(:), vp2(:)
    type(scene_t) :: sub
    type(scene_result_t) :: rest, fresh
    character(len=:), allocatable :: why2
    integer :: nk, n, it, sub_model, ist
    integer(i8) :: steps
    real(wp) :: sub_est
    logical :: is_top, handover
    done = .false.
    call top_start(scene, is_top, k, phi0, v0)
    if (.not. is_top) return
    call hang_plan(scene, phi0, v0, tend, tx, gain, vmax, target)
    ! the outputs in the hang (nk of the result's, up to tx), then tx
    call alloc_outputs(scene, result, status)
    if (status%code /= PENDULA_OK) return
    n = size(result%t)
    nk = count(result%t <= tx)
    handover = nk < n .or. (scene%want == SCENE_WANT_EVENTS .and. tx < tend)
    allocate (tg(merge(1, min(nk + 1, n), scene%want == SCENE_WANT_EVENTS)), stat=ist)
    call check_alloc(ist, 'the times of the run from the top', int(nk + 1, i8), 8, status)
    if (status%code /= PENDULA_OK) return
    if (scene%want == SCENE_WANT_EVENTS) then
      tg(1) = tx
    else if (nk == n) then
      tg(:) = result%t
      target = scene%tol/2
    else
      tg(1:nk) = result%t(1:nk)
      tg(nk + 1) = tx
      target = min(target, scene%tol/2)
    end if
    allocate (ph(size(tg)), vp(size(tg)), ph2(size(tg)), vp2(size(tg)), stat=ist)
    call check_alloc(ist, 'the runs from the top', 4_i8*size(tg), 8, status)
    if (status%code /= PENDULA_OK) return
    ! the closed-form start (closed_hang): its error in the (phi, phi'/w0)
    ! max norm on the outputs up to ts (e_closed) and after it (e_lin: rho of
    ! the motion plus the decaying mode's part), and what it adds to the state
    ! handed over (c_lin: the time shift rho/lp and the decaying part)
    call closed_hang(scene, phi0, v0, tg(size(tg)), vmax, ts, rho, c2, c2o)
    call saddle(scene, phi0, v0, lp, lm, ca, cb)
    us = phi0
    ws = v0
    e_closed = 0
    if (ts > 0) then
      call closed_state(ts, us, ws)
      e_closed = max(1.0_wp, lp/scene%w0)*rho*abs(us) + max(1.0_wp, -lm/scene%w0)*c2o + &
                 4*eps*(1 + lp*ts - lm*ts)*max(abs(us), abs(ws)/scene%w0)
    end if
    e_lin = max(1.0_wp, -lm/scene%w0)*c2 + 4*eps*(1 + lp*ts - lm*ts)*max(abs(us), abs(ws)/scene%w0)
    c_lin = TOP_SAFETY*vmax*rho/lp + gain*max(1.0_wp, -lm/scene%w0)*c2
    h = hang_step(scene, phi0, target, ts, tg(size(tg)))
    steps = 0
    est = huge(1.0_wp)
    do it = 1, MAX_REFINE
      if (1.5_wp*(tg(size(tg)) - ts)/h > budget) exit
      call run(h, 1_i8, ph, vp)
      call run(h, 2_i8, ph2, vp2)
      if (status%code /= PENDULA_OK) return
      d = max(maxval(abs(ph - ph2)), maxval(abs(vp - vp2))/scene%w0)
      est = 2*d/15 + 4*eps*maxval(abs(ph))
      if (ts > 0) est = est + max(e_closed, rho*max(maxval(abs(ph)), maxval(abs(vp))/scene%w0) + e_lin)
      carried = carried_error(ph(size(ph)), vp(size(ph)), ph2(size(ph)), vp2(size(ph))) + c_lin
      ! the hang's outputs at tol/2, the state handed over to tol/4 after the gain
      ! (events too: the estimate of the hang's state is the answer's when
      ! the window ends in the hang)
      r = scene%tol/(2*max(est, tiny(1.0_wp)))
      if (handover) r = min(r, scene%tol/(4*max(carried, tiny(1.0_wp))))
      if (r >= 1) exit
      h = h*max(1.0_wp/16, 0.9_wp*r**0.25_wp)
    end do
    if (est == huge(1.0_wp)) return   ! over the budget: the ordinary path
    done = .true.
    ! theta = k pi - phi (rounded once), Omega = -phi'
    call two_prod(k, pi, p, e)
    result%theta(1:nk) = p - (ph(1:nk) - (e + k*pi_lo))
    result%omega(1:nk) = -vp(1:nk)
    result%error_estimate = est + eps*abs(p)
    result%cost%steps = steps
    result%cost%rhs_evals = 4*steps
    result%cost%runs = 2*it
    result%step = h
    result%setting = h
    why = 'gamma > 0, start '//format_sci(hypot(phi0, v0/scene%w0), 3)//' rad from a top: '
    ! (short: the reason has 256 characters, the hand-over's part follows)
    if (ts > 0) why = why//'closed form to t = '//format_sci(ts, 3)//' s, '
    why = why//'RK4 in phi = k pi - theta'
    if (handover) then
      thx = p - (ph(size(ph)) - (e + k*pi_lo))
      omx = -vp(size(vp))
      eround = eps*abs(thx)
      call scene_like(scene, sub, merge(1, n - nk, scene%want == SCENE_WANT_EVENTS), status)
      if (status%code /= PENDULA_OK) return
      sub%theta0 = thx
      sub%omega0 = omx
      sub%tol = scene%tol/2
      sub%model = SCENE_MODEL_AUTO
      if (scene%want == SCENE_WANT_EVENTS) then
        sub%t(1) = tend - tx
      else
        sub%t(:) = max(0.0_wp, result%t(nk + 1:n) - tx)
      end if
      call choose_model(sub, sub%t(size(sub%t)), sub_model, sub_est, why2, status)
      if (status%code /= PENDULA_OK) return
      why2 = scene_model_name(sub_model)
      do it = 1, 2
        rest = fresh
        if (sub_model == SCENE_MODEL_LINEAR) then
          call solve_closed(sub, sub_model, sub_est, rest, status)
        else
          call solve_integrated(sub, sub_model, sub%t(size(sub%t)), budget - 1.5_wp*steps, why2, rest, &
                                status, control)
        end if
        if (status%code /= PENDULA_OK) return
        ! events: the times' error is the state's over the speed there, which
        ! the state's tol does not bound: once more with tol scaled to it
        if (scene%want /= SCENE_WANT_EVENTS .or. .not. rest%event_time_error > sub%tol) exit
        if (it == 1) call add_cost(result%cost, rest%cost)
        sub%tol = sub%tol*max(1.0e-3_wp, 0.5_wp*sub%tol/rest%event_time_error)
      end do
      if (scene%want == SCENE_WANT_EVENTS) then
        ! the handed-over error shifts the later motion in time by at most
        ! its size over the speed at tx (carried_error without the max speed)
        tshift = (carried + gain*eround)/vmax
        result%event_t = rest%event_t + tx
        result%event_kind = rest%event_kind
        result%event_theta = rest%event_theta
        result%event_omega = rest%event_omega
        result%event_time_error = rest%event_time_error + tshift + 4*eps*tend
      else
        result%theta(nk + 1:) = rest%theta
        result%omega(nk + 1:) = rest%omega
      end if
      result%error_estimate = max(result%error_estimate, rest%error_estimate + carried + gain*eround + &
                                  4*eps*tend*(scene%w0 + scene%gamma))
      call add_cost(result%cost, rest%cost)
      result%rtol = rest%rtol
      why = why//' to t = '//format_sci(tx, 4)//' s, then '//why2
    end if
    call finish_outputs(scene, result, status)
  contains
    ! RK4 in (phi, v = phi') from (phi0, v0) at 0 through the times tg,
    ! 2 ceil(dt/(2 hh)) / factor equal substeps on each interval dt: the
    ! check (factor 2) halves the substeps of the run (factor 1) on EVERY
    ! interval, also where the outputs are denser than hh (else both take
    ! one substep there, agree exactly, and the estimate is void)
    ! The times up to ts take the closed form, the run starts there.
    subroutine run(hh, factor, x, y)
      real(wp), intent(in) :: hh
      integer(i8), intent(in) :: factor
      real(wp), intent(out) :: x(:), y(:)
      real(wp) :: t0, u, w, dt, k1u, k1w, k2u, k2w, k3u, k3w, k4u, k4w
      integer :: i
      integer(i8) :: j, ns
      t0 = ts
      u = us
      w = ws
      do i = 1, size(tg)
        if (ts > 0 .and. tg(i) <= ts) then
          call closed_state(tg(i), x(i), y(i))
          cycle
        end if
        if (present(control)) then
          if (cancel_requested(control)) then
            call set_error(status, PENDULA_ERR_CANCELLED, 'cancelled by the caller')
            return
          end if
        end if
        ns = 2*ceiling((tg(i) - t0)/(2*hh), i8)/factor
        ns = max(1_i8, ns)
        dt = (tg(i) - t0)/real(ns, wp)
        do j = 1, ns
          ! a hang may take millions of substeps in one interval: poll there too
          if (present(control) .and. iand(j, 4095_i8) == 0) then
            if (cancel_requested(control)) then
              call set_error(status, PENDULA_ERR_CANCELLED, 'cancelled by the caller')
              return
            end if
          end if
          k1u = w
          k1w = f(u, w)
          k2u = w + dt/2*k1w
          k2w = f(u + dt/2*k1u, k2u)
          k3u = w + dt/2*k2w
          k3w = f(u + dt/2*k2u, k3u)
          k4u = w + dt*k3w
          k4w = f(u + dt*k3u, k4u)
          u = u + dt/6*(k1u + 2*k2u + 2*k3u + k4u)
          w = w + dt/6*(k1w + 2*k2w + 2*k3w + k4w)
        end do
        if (tg(i) > t0) steps = steps + ns
        t0 = tg(i)
        x(i) = u
        y(i) = w
      end do
    end subroutine run
    ! The error the state handed over at tx carries to the outputs after it,
    ! from the Richardson difference of the runs there (x, y at h; x2, y2 at
    ! 2h) split along the flow f at tx and across it, in (phi, phi'/w0).
    ! Along the flow it is a shift in time by its size over |f| (to first
    ! order the perturbed motion is the same one, shifted), which moves later
    ! states by at most that times vmax; across it the a priori gain applies,
    ! also to the rounding of phi there.  TOP_SAFETY on both.
    pure real(wp) function carried_error(x, y, x2, y2) result(c)
      real(wp), intent(in) :: x, y, x2, y2
      real(wp) :: dx, dy, fx, fy, fn
      dx = 2*(x - x2)/15
      dy = 2*(y - y2)/(15*scene%w0)
      fx = y
      fy = f(x, y)/scene%w0
      fn = hypot(fx, fy)
      if (.not. fn > 0) then
        c = gain*(hypot(dx, dy) + 4*eps*abs(x))
      else
        c = TOP_SAFETY*vmax/fn*abs(dx*fx + dy*fy)/fn + &
            gain*(abs(dx*fy - dy*fx)/fn + 4*eps*abs(x))
      end if
    end function carried_error
    ! The saddle's linear motion at time tt [s]: phi and phi'.
    pure subroutine closed_state(tt, x, y)
      real(wp), intent(in) :: tt
      real(wp), intent(out) :: x, y
      real(wp) :: gp, gm
      gp = ca*exp(lp*tt)
      gm = cb*exp(lm*tt)
      x = gp + gm
      y = lp*gp + lm*gm
    end subroutine closed_state
    pure real(wp) function f(u, w)
      real(wp), intent(in) :: u, w
      f = -scene%gamma*w + scene%w0**2*sin(u)
    end function f
  end subroutine solve_top

end module pendula_scene_top
