!> Events of a scene (turning points, Omega = 0, and zero crossings, passes
!> through the bottom theta = 0 mod 2 pi, bottom_sign of pendula_ode, the one
!> definition the integrators' root finding uses too, in (0, t(n)]): the rigorous bound on their number, the event
!> list of a result, the event-time error, and the events of an integrated
!> trajectory (a sample grid fine enough for cubic Hermite interpolation,
!> sign changes refined on the interpolant).
!>
!> The bound (scene_event_bound): for theta'' + gamma theta' + w0^2 sin(theta)
!> = 0 with gamma >= 0, Omega = theta' solves the LINEAR equation
!> Omega'' + gamma Omega' + w0^2 cos(theta(t)) Omega = 0, and v = Omega
!> e^(gamma t/2) solves v'' + (w0^2 cos(theta(t)) - gamma^2/4) v = 0, whose
!> coefficient is <= w0^2.  By Sturm's comparison with u'' + w0^2 u = 0,
!> consecutive zeros of Omega are at least pi/w0 apart, so (0, T] holds at
!> most floor(w0 T/pi) + 1 turning points.  Between two zero crossings of
!> theta, Omega vanishes (Rolle): at most one more zero crossing than turning
!> points.  Hence at most 2 floor(w0 T/pi) + 3 events while the pendulum
!> swings.  Zero crossings count passes through the bottom, theta = 2 pi k
!> for any integer k: two consecutive ones with no turning point between are
!> a full turn apart (theta is monotone there), which takes at least
!> 2 pi/Omega_max, Omega_max^2 = Omega0^2 + 2 w0^2 (1 - cos theta0) (the
!> energy does not grow, gamma >= 0): at most floor(Omega_max T/(2 pi)) more.
!> The same holds for every model a scene uses (the small-angle and linear
!> damped equations have the same form with cos(theta) replaced by 1, and
!> do not go over the top).
module pendula_scene_events
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf
  use pendula_kinds, only: wp, i8
  use pendula_constants, only: pi
  use pendula_numeric, only: bracket_t, bracket_start, bracket_update, ROOT_BISECT
  use pendula_integrators, only: PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO, bottom_sign
  use pendula_scene_types, only: scene_t, scene_result_t, swing
  use pendula_scene_codes, only: SCENE_LINEAR_SAFETY
  use pendula_status, only: status_t, check_alloc, PENDULA_OK
  implicit none
  private

  public :: scene_event_bound, sign_change, bottom_sign, bottom_level, append_events, trim_events, event_time_error, &
            event_grid, event_grid_intervals, grid_events, event_interp_error, linear_error_at, event_rate

  real(wp), parameter :: eps = epsilon(1.0_wp)

contains

  !> Most events (turning points and passes through the bottom) that the
  !> motion from (theta0 [rad], omega0 [rad/s]) with natural frequency w0 > 0
  !> [1/s] and any damping gamma >= 0 can have in (0, tend], tend >= 0 [s]:
  !> 2 floor(w0 tend/pi) + 3 + floor(Omega_max tend/(2 pi)) (derivation
  !> above); huge(1_i8) when that does not fit (or is not finite).
  elemental integer(i8) function scene_event_bound(w0, tend, theta0, omega0) result(n)
    real(wp), intent(in) :: w0  !< natural frequency [1/s], > 0
    real(wp), intent(in) :: tend  !< end of the window [s], >= 0
    real(wp), intent(in) :: theta0  !< initial angle [rad]
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s]
    real(wp) :: half_periods, turns
    half_periods = w0*tend/pi
    turns = sqrt(omega0**2 + 4*w0**2*sin(theta0/2)**2)*tend/(2*pi)
    if (half_periods >= 0 .and. half_periods < 2.0e18_wp .and. turns >= 0 .and. turns < 2.0e18_wp) then
      n = 2*int(half_periods, i8) + 3 + int(turns, i8)
    else
      n = huge(1_i8)
    end if
  end function scene_event_bound

  !> The multiple of 2 pi [rad] passed between two angles a and b (less than
  !> 2 pi apart) whose bottom_sign differs: it is within (b - a)/2 < pi of
  !> their midpoint, so the multiple nearest to the midpoint.
  elemental real(wp) function bottom_level(a, b) result(c)
    real(wp), intent(in) :: a  !< angle [rad] at the first sample
    real(wp), intent(in) :: b  !< angle [rad] at the next sample, |b - a| < 2 pi
    c = 2*pi*anint((a/2 + b/2)/(2*pi))
  end function bottom_level

  !> An event between samples with values fa then fb: a sign change, or fb
  !> reaching 0 from a nonzero fa (an event at a sample counts once).
  pure logical function sign_change(fa, fb)
    real(wp), intent(in) :: fa  !< value at the first sample
    real(wp), intent(in) :: fb  !< value at the next sample
    sign_change = fa*fb < 0 .or. (fb == 0 .and. fa /= 0)
  end function sign_change

  !> Append the events of one sample interval (te(:) [s], kinds(:) of
  !> PENDULA_EVENT_*, at most two: one of each kind) in time order to the
  !> first nev of result's event list, growing it geometrically (doubling,
  !> so that n events cost O(n) copies); PENDULA_ERR_MEMORY in status when
  !> the grown list cannot be allocated.
  pure subroutine append_events(result, te, kinds, nev, status)
    type(scene_result_t), intent(inout) :: result  !< event lists to append to (grown as needed)
    real(wp), intent(in) :: te(:)  !< times [s] of the interval's events, at most two
    integer, intent(in) :: kinds(:)  !< their kinds, PENDULA_EVENT_*; size(te)
    integer, intent(inout) :: nev  !< number of events in the lists, >= 0; increased
    type(status_t), intent(inout) :: status  !< set when an allocation fails, else left unchanged
    real(wp), allocatable :: tmp(:)
    integer, allocatable :: itmp(:)
    integer :: cap, ist
    if (status%code /= PENDULA_OK) return
    if (nev + size(te) > size(result%event_t)) then
      cap = int(min(max(16_i8, 2_i8*(nev + size(te))), int(huge(1), i8)))
      allocate (tmp(cap), itmp(cap), stat=ist)
      call check_alloc(ist, 'the event list', 3_i8*cap, 4, status)
      if (status%code /= PENDULA_OK) return
      tmp(1:nev) = result%event_t(1:nev)
      itmp(1:nev) = result%event_kind(1:nev)
      call move_alloc(tmp, result%event_t)
      call move_alloc(itmp, result%event_kind)
    end if
    result%event_t(nev + 1:nev + size(te)) = te
    result%event_kind(nev + 1:nev + size(te)) = kinds
    if (size(te) == 2) then
      if (te(2) < te(1)) then
        result%event_t(nev + 1:nev + 2) = te([2, 1])
        result%event_kind(nev + 1:nev + 2) = kinds([2, 1])
      end if
    end if
    nev = nev + size(te)
  end subroutine append_events

  !> Cut result's event list to its first nev events, with room for the
  !> state at each (PENDULA_ERR_MEMORY in status when that cannot be allocated).
  pure subroutine trim_events(result, nev, status)
    type(scene_result_t), intent(inout) :: result  !< event lists cut to nev; state arrays allocated to nev for the caller to fill
    integer, intent(in) :: nev  !< number of events kept, 0 .. size(result%event_t)
    type(status_t), intent(inout) :: status  !< set when an allocation fails, else left unchanged
    real(wp), allocatable :: tmp(:)
    integer, allocatable :: itmp(:)
    integer :: ist
    if (status%code /= PENDULA_OK) return
    allocate (tmp(nev), itmp(nev), stat=ist)
    if (ist == 0) then
      tmp(:) = result%event_t(1:nev)
      itmp(:) = result%event_kind(1:nev)
      call move_alloc(tmp, result%event_t)
      call move_alloc(itmp, result%event_kind)
      if (allocated(result%event_theta)) deallocate (result%event_theta)
      if (allocated(result%event_omega)) deallocate (result%event_omega)
      allocate (result%event_theta(nev), result%event_omega(nev), stat=ist)
    end if
    call check_alloc(ist, 'the event list', 7_i8*nev, 4, status)
  end subroutine trim_events

  !> Event time error from the state error est (the sup of |d theta| and
  !> |d Omega|/w0 where the events were placed, interpolation included):
  !> dt = d theta/|Omega| at a zero crossing, d Omega/|Omega'| =
  !> w0 d/(w0^2 |sin theta|) at a turning point.  +inf when it exceeds half
  !> the gap between two neighbouring events (the count is then unverified).
  !> With est_each, event i's state error is est_each(i) (a model whose
  !> error changes along the window: the linear closed form after a hand-over).
  pure real(wp) function event_time_error(result, est, w0, est_each) result(e)
    type(scene_result_t), intent(in) :: result  !< the events found, with their state
    real(wp), intent(in) :: est  !< state error where the events were placed [rad] (theta, Omega/w0), >= 0
    real(wp), intent(in) :: w0  !< natural frequency [1/s], > 0
    real(wp), intent(in), optional :: est_each(:)  !< state error [rad] at each event, >= 0; size(result%event_t)
    integer :: i
    real(wp) :: rate, ei
    e = 0
    do i = 1, size(result%event_t)
      rate = event_rate(result%event_kind(i), result%event_theta(i), result%event_omega(i), w0)
      ei = est
      if (present(est_each)) ei = max(est, est_each(i))
      e = max(e, ei/rate)
    end do
    ! Times this uncertain could swap or merge neighbouring events: their
    ! number and kinds are then unverified (a count off is an infinite error)
    do i = 2, size(result%event_t)
      if (e > (result%event_t(i) - result%event_t(i - 1))/2) e = ieee_value(1.0_wp, ieee_positive_inf)
    end do
  end function event_time_error

  !> Nonlinearity error [rad] of the linear damped model from (x0 [rad], v0
  !> [rad/s]) AT time tau >= 0 [s] (not the sup over [0, tau] of
  !> linear_estimate), in max(|d theta|, |d Omega|/w0); gamma > 0 [1/s].  It
  !> decays with the swing, so over an event's rate it stays a relative (phase)
  !> error however late the event.  Derivation: d = theta - theta_lin solves
  !> d'' + gamma d' + w0^2 d = w0^2 (theta - sin theta), |forcing| <= w0^2
  !> |theta|^3/6, so d(tau) = int_0^tau G(tau - s) f(s) ds with the Green's
  !> function G(u) = e^(-a u) sin(w_d u)/w_d (sinh, u past critical), a =
  !> gamma/2.  With rho = a - sqrt(a^2 - w0^2) (a when under-damped), |G(u)| <=
  !> e^(-rho u) min(u, 1/w_d) and |G'(u)| <= e^(-rho u) (1 + a min(u, 1/w_d)).
  !> An envelope |theta_lin(s)| <= R e^(-beta s), beta <= rho, then gives
  !> |d(tau)| <= w0^2 R^3/6 e^(-beta tau) min(tau, 1/w_d) int_0^tau e^(-2 beta s) ds
  !> (and (1 + a min(tau, 1/w_d)) for Omega).  Envelopes: the amplitude R at
  !> beta = a (under-damped), and, any regime, from e^(-rho s)(|x0| + |v0 + a
  !> x0| s): R = |x0| + 2 |v0 + a x0|/(rho e) at beta = rho/2; under-damped
  !> also linear_estimate's phase-drift estimate at tau; the smallest is used.  The forcing is
  !> taken on the linear solution (as linear_estimate
  !> does), hence the same safety factor SCENE_LINEAR_SAFETY; plus rounding, relative to the
  !> envelope.
  elemental real(wp) function linear_error_at(x0, v0, w0, gamma, tau) result(e)
    real(wp), intent(in) :: x0  !< angle [rad] about the bottom at the start
    real(wp), intent(in) :: v0  !< angular velocity [rad/s] at the start
    real(wp), intent(in) :: w0  !< natural frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], > 0
    real(wp), intent(in) :: tau  !< time since the start [s], >= 0
    real(wp) :: a, kap, rho, wd, c, g, e1, r2, env, amp, phi
    a = gamma/2
    c = abs(v0 + a*x0)
    if (a < w0) then
      wd = sqrt(w0 - a)*sqrt(w0 + a)
      rho = a
      g = min(tau, 1/wd)
    else
      kap = sqrt(a - w0)*sqrt(a + w0)
      rho = w0**2/(a + kap)
      g = tau
    end if
    r2 = abs(x0) + 2*c/(rho*exp(1.0_wp))
    e1 = bound(r2, rho/2)
    env = r2*exp(-rho*tau/2)
    if (a < w0) then
      amp = hypot(x0, c/wd)
      e1 = min(e1, bound(amp, a))
      env = min(env, amp*exp(-a*tau))
      ! phase drift (linear_estimate's (a)): the swing A(tau) = amp e^(-a tau)
      ! lags by phi = w0^2 amp^2 (1 - e^(-gamma tau))/(16 w_d gamma), off by
      ! A min(2, phi) max(1, (w_d + a)/w0) plus the harmonics A^3/16
      phi = w0**2*amp**2*(1 - exp(-gamma*tau))/(16*wd*gamma)
      if (gamma*tau < 1.0e-5_wp) phi = w0**2*amp**2*tau/(16*wd)
      e1 = min(e1, amp*exp(-a*tau)*min(2.0_wp, phi)*max(1.0_wp, (wd + a)/w0) + &
               (amp*exp(-a*tau))**3/16)
    end if
    ! the closed form's rounding is relative to the swing it evaluates
    ! (env bounds |theta_lin| and, with w0 + gamma, |Omega_lin|/w0)
    e = SCENE_LINEAR_SAFETY*e1 + 16*eps*env*(1 + (w0 + gamma)*tau)*(1 + gamma/w0)
  contains
    pure real(wp) function bound(r, beta)
      real(wp), intent(in) :: r, beta
      real(wp) :: i2, x
      ! int_0^tau e^(-2 beta s) ds (1 - e^(-x) cancels at most to eps/x relative)
      x = 2*beta*tau
      if (x < 1.0e-5_wp) then
        i2 = tau*(1 - x/2 + x**2/6)
      else
        i2 = (1 - exp(-x))/(2*beta)
      end if
      bound = w0**2*r**3/6*exp(-beta*tau)*i2*max(g, (1 + a*g)/w0)
    end function bound
  end function linear_error_at

  !> Rate [rad/s] at which an event's function crosses zero, in the units of
  !> the state error (theta, Omega/w0): |Omega| at a zero crossing, w0
  !> |sin theta| (= |Omega'|/w0 at rest) at a turning point; at least tiny.
  elemental real(wp) function event_rate(kind, theta, omega, w0) result(rate)
    integer, intent(in) :: kind  !< PENDULA_EVENT_ZERO or PENDULA_EVENT_TURNING
    real(wp), intent(in) :: theta  !< angle at the event [rad]
    real(wp), intent(in) :: omega  !< angular velocity at the event [rad/s]
    real(wp), intent(in) :: w0  !< natural frequency [1/s], > 0
    if (kind == PENDULA_EVENT_ZERO) then
      rate = abs(omega)
    else
      rate = w0*abs(sin(theta))
    end if
    rate = max(rate, tiny(1.0_wp))
  end function event_rate

  !> Sample grid for events found from an integrated trajectory: spacing d
  !> with interp_bound(d) <= tol/10, so that the cubic Hermite interpolant
  !> used to place the events is ten times more accurate than tol; at least
  !> 64 samples per small-angle period, and the fast time scale 1/gamma
  !> resolved when over-damped (capped at 4e6 samples; event_interp_error
  !> says what the grid achieves).
  pure subroutine event_grid(scene, tend, tg, status)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tend  !< end of the window [s], >= 0
    real(wp), allocatable, intent(out) :: tg(:)  !< sample times [s] from 0 to tend, increasing
    type(status_t), intent(inout) :: status  !< set when the grid cannot be allocated, else left unchanged
    integer :: n, i, ist
    n = event_grid_intervals(scene, tend)
    allocate (tg(n + 1), stat=ist)
    call check_alloc(ist, 'the event sample grid', int(n + 1, i8), 8, status)
    if (status%code /= PENDULA_OK) return
    do i = 0, n
      tg(i + 1) = tend*(real(i, wp)/n)
    end do
  end subroutine event_grid

  !> Intervals of the uniform sample grid of event_grid over [0, tend]: fine
  !> enough that cubic Hermite interpolation is within tol/10 (interp_bound),
  !> at least 64 and 8 gamma tend (fast decay), at most 4e6.
  pure integer function event_grid_intervals(scene, tend) result(n)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tend  !< end of the window [s], >= 0
    real(wp) :: d, per
    d = scene%tol/(10*interp_bound(scene, 1.0_wp))
    d = d**0.25_wp
    per = max(64.0_wp, 2*pi/(scene%w0*d))
    n = int(min(4.0e6_wp, max(64.0_wp, per*scene%w0*tend/(2*pi) + 1)))
    if (scene%gamma > scene%w0) n = max(n, min(4000000, ceiling(8*scene%gamma*tend) + 1))
  end function event_grid_intervals

  !> Bound on the error of the cubic Hermite interpolant between the samples
  !> tg(:) of the scene's trajectory (in theta, and Omega/w0), to be added
  !> to the state error at the samples where events are placed.
  pure real(wp) function event_interp_error(scene, tg) result(e)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tg(:)  !< sample times [s], increasing (event_grid)
    e = 0
    if (size(tg) > 1) e = interp_bound(scene, maxval(tg(2:) - tg(:size(tg) - 1)))
  end function event_interp_error

  ! h^4/384 max|theta''''| and h^4/384 max|Omega''''|/w0 for spacing h.
  ! The derivatives grow like w^k with w = max(w0, gamma): a heavily damped
  ! motion decays at rates up to gamma, and a critically damped one
  ! (t e^(-w0 t)) has |theta''''| up to 4 w0^4 A, within (2 w0)^4 A; Omega's
  ! fourth derivative carries one more factor w, over w0 in the scaled
  ! measure.  A rotation (A = |Omega0|/w0 > 1) has theta'''' ~ w0^2 Omega^2,
  ! hence A max(1, A).  A is the swing about the nearest bottom 2 pi k (the
  ! derivatives of theta do not see k): theta0 = 4 pi + 0.01 is a 0.01 rad
  ! swing, not a 12.6 rad one.
  pure real(wp) function interp_bound(scene, h) result(e)
    type(scene_t), intent(in) :: scene
    real(wp), intent(in) :: h
    real(wp) :: a, w
    a = max(swing(scene), 1.0e-3_wp)
    w = max(scene%w0, scene%gamma)
    e = (w*h)**4/384*a*max(1.0_wp, a)*(w/scene%w0)
  end function interp_bound

  !> Events from samples of an integrated trajectory: a sign change of theta
  !> or Omega between samples is refined on the cubic Hermite interpolant,
  !> built from (theta, Omega) and (Omega, Omega') at both ends, whose error
  !> (h^4/384 max|theta''''|) is below tol/10 on the grid of event_grid.
  pure subroutine grid_events(scene, tg, th, om, result, status)
    type(scene_t), intent(in) :: scene  !< the scene, checked (scene_init or check_scene)
    real(wp), intent(in) :: tg(:)  !< sample times [s], increasing (event_grid)
    real(wp), intent(in) :: th(:)  !< theta [rad] at tg; size(tg)
    real(wp), intent(in) :: om(:)  !< Omega [rad/s] at tg; size(tg)
    type(scene_result_t), intent(inout) :: result  !< gets the events in (tg(1), tg(n)]: times, kinds, state
    type(status_t), intent(inout) :: status  !< set when an allocation fails, else left unchanged
    integer :: i, nev, ne, kinds(2), ist
    real(wp) :: te(2), h, da, db, c
    if (allocated(result%event_t)) deallocate (result%event_t, result%event_kind)
    allocate (result%event_t(0), result%event_kind(0), stat=ist)
    call check_alloc(ist, 'the (empty) event list', 0_i8, 8, status)
    if (status%code /= PENDULA_OK) return
    nev = 0
    do i = 1, size(tg) - 1
      h = tg(i + 1) - tg(i)
      ne = 0
      if (sign_change(bottom_sign(th(i)), bottom_sign(th(i + 1)))) then
        ne = ne + 1
        kinds(ne) = PENDULA_EVENT_ZERO
        c = bottom_level(th(i), th(i + 1))
        te(ne) = tg(i) + h*hermite_root(th(i) - c, th(i + 1) - c, h*om(i), h*om(i + 1))
      end if
      if (sign_change(om(i), om(i + 1))) then
        da = h*accel(th(i), om(i))
        db = h*accel(th(i + 1), om(i + 1))
        ne = ne + 1
        kinds(ne) = PENDULA_EVENT_TURNING
        te(ne) = tg(i) + h*hermite_root(om(i), om(i + 1), da, db)
      end if
      if (ne > 0) call append_events(result, te(1:ne), kinds(1:ne), nev, status)
      if (status%code /= PENDULA_OK) return
    end do
    call trim_events(result, nev, status)
    if (status%code /= PENDULA_OK) return
    do i = 1, nev
      call hermite_state(result%event_t(i), result%event_theta(i), result%event_omega(i))
    end do
  contains
    pure real(wp) function accel(x, v)
      real(wp), intent(in) :: x, v
      accel = -scene%gamma*v - scene%w0**2*sin(x)
    end function accel
    pure subroutine hermite_state(tq, x, v)
      real(wp), intent(in) :: tq
      real(wp), intent(out) :: x, v
      integer :: j
      real(wp) :: s, hh
      j = max(1, min(size(tg) - 1, count(tg <= tq)))
      hh = tg(j + 1) - tg(j)
      s = (tq - tg(j))/hh
      x = hermite(th(j), th(j + 1), hh*om(j), hh*om(j + 1), s)
      v = hermite(om(j), om(j + 1), hh*accel(th(j), om(j)), hh*accel(th(j + 1), om(j + 1)), s)
    end subroutine hermite_state
  end subroutine grid_events

  pure real(wp) function hermite(f0, f1, d0, d1, s) result(f)
    real(wp), intent(in) :: f0, f1, d0, d1, s
    f = (2*s**3 - 3*s**2 + 1)*f0 + (s**3 - 2*s**2 + s)*d0 + (-2*s**3 + 3*s**2)*f1 &
        + (s**3 - s**2)*d1
  end function hermite

  ! Root in (0, 1] of the cubic Hermite interpolant (f0, f1 of opposite
  ! signs, or f1 = 0) by bisection (stops at a bracket of 2 eps: the bracket
  ! halves from 1 exactly, so that is a width below 4 eps).
  pure real(wp) function hermite_root(f0, f1, d0, d1) result(s)
    real(wp), intent(in) :: f0, f1, d0, d1
    type(bracket_t) :: br
    call bracket_start(br, 0.0_wp, 1.0_wp, f0, f1, ROOT_BISECT, 100, 2*eps, 0.0_wp)
    do while (.not. br%done)
      call bracket_update(br, hermite(f0, f1, d0, d1, br%c))
    end do
    s = br%root
  end function hermite_root

end module pendula_scene_events
