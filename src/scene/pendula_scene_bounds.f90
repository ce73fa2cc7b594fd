!> Error bounds of the closed-form models over a scene's window: the exact
!> solution's rounding and time error, the small-angle period error, and the
!> linear model's nonlinearity estimate (with or without a drive's steady
!> oscillation).  Pure functions of the motion; the scene-level choice of a
!> model (pendula_scene_estimates) asks them.
module pendula_scene_bounds
  use pendula_kinds, only: wp
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_is_finite
  use pendula_status, only: status_t, PENDULA_OK
  use pendula_constants, only: pi
  use pendula_elliptic, only: ellipkm1
  use pendula_undamped, only: undamped_motion_t, REGIME_LIBRATION, REGIME_SEPARATRIX
  use pendula_undamped_motion, only: M_TINY
  use pendula_linear_damped, only: linear_damped_t, linear_damped_init, linear_damped_state, DAMPING_UNDERDAMPED
  use pendula_scene_codes, only: SCENE_LINEAR_SAFETY
  implicit none
  private

  public :: energy_rounding, period_small_angle_error, exact_estimate, exact_time_error, linear_estimate

  real(wp), parameter :: eps = epsilon(1.0_wp)

contains

  !> Rounding of the energy per unit m l^2 of a state, divided by w0^2 [rad^2]: each
  !> of the two terms Omega^2/2 and w0^2 (1 - cos theta) rounds by a few eps.
  pure real(wp) function energy_rounding(theta, omega, w0) result(e)
    real(wp), intent(in) :: theta  !< angle [rad]
    real(wp), intent(in) :: omega  !< angular velocity [rad/s]
    real(wp), intent(in) :: w0  !< natural frequency [1/s], > 0
    e = 4*eps*((omega/w0)**2/2 + (1 - cos(theta)) + eps)
  end function energy_rounding

  !> Error of the small-angle period T0 = 2 pi/w0 as a phase w0 |T - T0| [rad],
  !> from the exact period (itself good to 16 eps (1 + |ln mc|) relative) and
  !> the rounding of 2 pi/w0 (a few eps); +inf for a motion that is not a libration.
  pure real(wp) function period_small_angle_error(motion) result(e)
    type(undamped_motion_t), intent(in) :: motion  !< the undamped motion (undamped_init)
    if (motion%regime /= REGIME_LIBRATION) then
      e = ieee_value(1.0_wp, ieee_positive_inf)
    else
      e = abs(motion%w0*motion%period - 2*pi) + 2*pi*eps*(20 + 16*abs(log(max(abs(motion%mc), &
                                                                              tiny(1.0_wp)))))
    end if
  end function period_small_angle_error

  !> Rounding estimate [rad] of the exact elliptic solution over [0, tend] at the
  !> given (exact double) inputs: the phase w0 t is rounded (theta moves by
  !> ~eps Omega_max t), and the energy parameter carries an error delta_m that
  !> shifts the frequency by t |d ln T/d m| delta_m (T ~ ln(16/mc) near the
  !> separatrix); theta moves by the phase error times max|Omega|/w.
  pure real(wp) function exact_estimate(motion, tend) result(e)
    type(undamped_motion_t), intent(in) :: motion  !< the undamped motion (undamped_init)
    real(wp), intent(in) :: tend  !< end of the window [s], >= 0
    real(wp) :: omax, span
    if (motion%theta_r == 0 .and. motion%omega0 == 0) then
      e = 0                                    ! at rest at the bottom: exactly 2 pi N
      return
    end if
    omax = 2*sqrt(motion%m)*motion%w0          ! max |Omega| (libration and rotation)
    if (motion%m < M_TINY) omax = 2*motion%k*motion%w0   ! m lost to the subnormal range: k from its parts
    ! the angles the evaluation handles besides theta0: a libration's centre 2 pi N and
    ! swing (so a tiny swing about 0 gets a tiny estimate), or a whole turn
    span = 2*pi
    if (motion%regime == REGIME_LIBRATION) span = abs(motion%center) + motion%amplitude
    e = 4*eps*(abs(motion%theta0) + span + omax/motion%w0) &
        + 4*omax*tend*frequency_error(motion)
    e = min(e, 2*(omax/motion%w0 + 2*pi))
  end function exact_estimate

  !> Error [s] of the event times of the exact elliptic solution over
  !> [0, tend]: the event times are where its phase w0 t + u0 takes known
  !> values (multiples of K), so they move by the phase error over w0, not
  !> by the state error over the speed (which vanishes at a turning point at
  !> the top, where a start at fl(pi) turns): the frequency error over the
  !> window (exact_estimate), the rounding of the initial phase u0 (a few eps
  !> of K, and eps pi/2 through F's slope 1/cos(theta_r/2) when a libration
  !> starts with Omega0 /= 0 near the top), the root finding (4 eps t), and
  !> the spacing of theta's doubles about a far centre 2 pi N over the speed
  !> at the bottom (a swing of 1e-7 rad about 4 pi: ~2e-8 s at w0 = 3).
  pure real(wp) function exact_time_error(motion, tend) result(dt)
    type(undamped_motion_t), intent(in) :: motion  !< the exact motion set up from the scene's initial state
    real(wp), intent(in) :: tend  !< end of the window [s], >= 0
    real(wp) :: du
    du = 8*eps*(1 + motion%rate*tend)
    if (motion%regime == REGIME_LIBRATION .and. motion%q /= 0) du = du + 2*eps/max(abs(motion%ch), eps)
    dt = du/motion%rate + 4*tend*frequency_error(motion) + 8*eps*tend
    ! a crossing is located on theta = center + theta_r, whose doubles are spaced
    ! ~eps |center| apart: that resolution over the speed at the bottom, 2 k w0
    dt = dt + 2*eps*abs(motion%center)/max(2*motion%k*motion%w0, tiny(1.0_wp))
  end function exact_time_error

  ! Relative error of the exact solution's frequency: the rounding of w0 t
  ! (eps) and the error delta_m of the energy parameter times |d ln T/d m|.
  ! pendula_undamped forms 1 - m as (c - q)(c + q) with c = cos(theta_r/2)
  ! and q carried to ~2 doubles, so mc is known to a few eps RELATIVE to
  ! itself plus what c and q carry absolutely: the double-double sum and
  ! cos_dd (~eps^2 c) and the reduction theta_r = theta0 - 2 pi N (2^-100
  ! |2 pi N|; ~1 ulp of pi beyond 2^40), each times c + |q|.  At a start
  ! fl(pi) c is pi_lo/2 ~ 6e-17 and mc ~ 4e-33 is still known to a few eps.
  pure real(wp) function frequency_error(motion) result(f)
    type(undamped_motion_t), intent(in) :: motion
    real(wp) :: dm, mc, dlnt, h, big, dr
    mc = motion%mc
    big = max(abs(motion%ch), abs(motion%q))
    dr = 2.0_wp**(-98)*abs(motion%center)
    if (abs(motion%theta0) > 2.0_wp**40) dr = 4*eps*pi
    dm = 4*eps*abs(mc) + 2*big*(8*eps**2*big + dr)
    if (motion%regime == REGIME_SEPARATRIX .or. mc == 0) then
      dlnt = 1/max(abs(mc), dm)
    else
      h = 1.0e-4_wp*abs(mc)
      dlnt = abs(log(turn_time(mc + h)/turn_time(mc - h)))/(2*h)
    end if
    f = eps + min(dlnt*dm, 1.0_wp)
  contains
    pure real(wp) function turn_time(c)
      real(wp), intent(in) :: c
      if (c > 0) then
        turn_time = 4*ellipkm1(c)
      else
        turn_time = 2*ellipkm1(-c/(1 - c))/sqrt(1 - c)
      end if
    end function turn_time
  end function frequency_error

  !> Nonlinearity error of the linear model theta'' + gamma theta' + w0^2 theta
  !> = 0 against eq. 2.2 over [0, tend], as sup max(|d theta|, |d Omega|/w0).
  !> Two estimates, the smaller is used (times SCENE_LINEAR_SAFETY), plus rounding:
  !>  (a) underdamped, phase drift: an oscillation of amplitude A is slower by
  !>      dw = w0^2 A^2/(16 w_d) (the pendulum's A^2/16 shift, eq. 1.53 expanded);
  !>      with A(t) = A0 e^(-gamma t/2) the phase lag is
  !>      phi(t) = w0^2 A0^2 (1 - e^(-gamma t))/(16 w_d gamma), so the error is
  !>      about A(t) min(2, phi(t)) (1 + gamma/(2 w0)) plus the harmonics A^3/16;
  !>      its sup over the window is taken in closed form (drift_sup);
  !>  (b) any regime, Green's function: the error d solves the linear equation
  !>      forced by w0^2 (theta - sin theta) <= w0^2 |theta|^3/6, so
  !>      |d| <= w0^2 B^3/6 int_0^tend |G|, B = max |theta_lin|, and the same with
  !>      |G'|/w0 for Omega; G(s) = e^(-gamma s/2) sin(w_d s)/w_d (sinh, s).
  !>      Over-damped or critical, B and max G are taken at their humps, whose
  !>      times are closed forms (hump_time).
  !> Cost: a few exp/log and at most two evaluations of the closed form, no
  !> sampling (the scenes call this several times per solve).
  !> steady (optional): a driven linear motion (pendula_scene_driven) is the
  !> free motion from (theta0, omega0) -- then the transient's start, the
  !> initial state minus the steady state's -- plus a steady oscillation of
  !> amplitude `steady` [rad]: B gets that amplitude added, and only (b) is
  !> used (the drive, not the amplitude, sets the steady state's frequency,
  !> so (a)'s phase drift does not describe it); the drive itself cancels
  !> from the error equation, which is (b)'s forced linear equation again.
  pure real(wp) function linear_estimate(theta0, omega0, w0, gamma, tend, steady) result(e)
    real(wp), intent(in) :: theta0  !< initial angle [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s], finite
    real(wp), intent(in) :: w0  !< natural frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    real(wp), intent(in) :: tend  !< end of the window [s], >= 0
    real(wp), intent(in), optional :: steady  !< amplitude of a steady driven oscillation added [rad], >= 0
    type(linear_damped_t) :: lin, gl
    type(status_t) :: st
    real(wp) :: bmax, ig, igp, eg, ep, wd, a, scale, round, gt, gpt, gmax, jmin, beta, d, th, om, t, amp
    amp = 0
    if (present(steady)) amp = steady
    call linear_damped_init(lin, theta0, omega0, w0, gamma, st)
    if (st%code /= PENDULA_OK) then
      e = ieee_value(1.0_wp, ieee_positive_inf)
      return
    end if
    scale = abs(theta0) + abs(omega0)/w0 + amp
    if (tend <= 0 .or. scale == 0) then
      e = 0
      return
    end if
    a = gamma/2
    if (lin%info%regime == DAMPING_UNDERDAMPED) then
      wd = lin%info%omega_d
      ! |theta| <= R e^(-a t) <= R, but R ~ 1/w_d blows up towards critical
      ! damping; with |sin(w_d t)/w_d| <= t also |theta| <= e^(-a t) (|theta0|
      ! + |Omega0 + a theta0| t) <= |theta0| + |Omega0 + a theta0| min(T, 1/(a e)),
      ! which is the critical-damping bound: the smaller keeps the estimate
      ! seamless across gamma = 2 w0
      if (a > 0) then
        bmax = min(lin%amplitude, abs(theta0) + abs(omega0 + a*theta0)*min(tend, 1/(a*exp(1.0_wp))))
      else   ! gamma = 0 (a driven scene only): no decay
        bmax = min(lin%amplitude, abs(theta0) + abs(omega0)*tend)
      end if
      ! |G(s)| <= e^(-a s) min(s, 1/w_d), |G'(s)| <= e^(-a s) (1 + a min(s, 1/w_d))
      jmin = min(int_exp_s(a, tend), int_exp(a, tend)/wd)
      ig = jmin
      igp = int_exp(a, tend) + a*jmin
      ep = ieee_value(1.0_wp, ieee_positive_inf)
      if (.not. present(steady)) ep = drift_sup(lin%amplitude, max(1.0_wp, (wd + a)/w0), (w0*lin%amplitude)**2/(16*wd))
    else
      ! over-damped or critical (beta = 0): Omega = e^(-a t) (Omega0 C - d S)
      ! with C = cosh(beta t), S = sinh(beta t)/beta, so theta has at most one
      ! hump, where tanh(beta t)/beta = Omega0/d; without one (or with one
      ! beyond the window) |theta| is largest at t = 0 or at tend
      beta = lin%info%beta
      d = w0*(w0*theta0) + a*omega0
      bmax = abs(theta0)
      if (omega0 /= 0 .and. (d > 0 .eqv. omega0 > 0) .and. beta*abs(omega0) < abs(d)) then
        t = tend    ! the hump lies beyond Omega0/d, so past tend when that is
        if (abs(omega0) < abs(d)*tend) &
          t = min(tend, hump_time(beta, abs(omega0), abs(d), abs(d) - beta*abs(omega0)))
        call linear_damped_state(lin, t, th, om)
        bmax = max(bmax, abs(th))
      end if
      ! G >= 0: int G = (1 - G'(T) - gamma G(T))/w0^2 from the equation itself;
      ! G' changes sign once, at the hump tanh(beta t)/beta = 1/a, where
      ! sinh(beta t) = beta/w0, so max G = e^(-a t)/w0 (or G(T) before it);
      ! int |G'| <= 2 max G.
      call linear_damped_init(gl, 0.0_wp, 1.0_wp, w0, gamma, st)   ! G: theta0 = 0, Omega0 = 1
      call linear_damped_state(gl, tend, gt, gpt)
      ig = max(0.0_wp, (1 - gpt - gamma*gt)/w0**2)
      t = hump_time(beta, 1.0_wp, a, lin%info%decay_slow)
      gmax = gt
      if (t < tend) gmax = max(gt, exp(-a*t)/w0)
      igp = 2*gmax
      ep = ieee_value(1.0_wp, ieee_positive_inf)
    end if
    ! (b) Green's function bound, any regime
    bmax = bmax + amp
    eg = w0**2*bmax**3/6*max(ig, igp/w0)
    round = 16*eps*scale*(1 + (w0 + gamma)*tend)
    e = SCENE_LINEAR_SAFETY*min(eg, ep) + round
  contains
    ! int_0^T e^(-a s) ds and int_0^T s e^(-a s) ds, without cancellation
    pure real(wp) function int_exp(a, t) result(r)
      real(wp), intent(in) :: a, t
      if (a*t < 1.0e-8_wp) then
        r = t
      else
        r = -expm1(-a*t)/a
      end if
    end function int_exp
    pure real(wp) function int_exp_s(a, t) result(r)
      real(wp), intent(in) :: a, t
      real(wp) :: x
      x = a*t
      if (x < 1.0e-3_wp) then
        r = t**2*(0.5_wp - x/3 + x**2/8)
      else
        r = (-expm1(-x) - x*exp(-x))/a**2
      end if
    end function int_exp_s
    ! sup over t in [0, tend] of the phase-drift error (a), the sup itself,
    ! not a sample of it, so that it bounds every t in the window.  In u =
    ! e^(-a t) (from 1 down to u_T) with phi = p (1 - u^2)/gamma (p = w0^2
    ! A0^2/(16 w_d)) it is f = A0 u c min(2, phi) + (A0 u)^3/16: where phi >= 2
    ! f grows with u, so that part peaks where phi reaches 2 (u^2 = 1 - 2
    ! gamma/p); where phi < 2 it is the cubic A0 c (p/gamma) u (1 - u^2) +
    ! (A0 u)^3/16, stationary only at u^2 = 1/(3 (1 - q)), q = A0^2 gamma/
    ! (16 c p).  The sup is the largest of f at u = 1, u_T and those two
    ! points where they lie in the window.  gamma = 0: u = 1, phi = p t grows.
    pure real(wp) function drift_sup(a0, c, p) result(f)
      real(wp), intent(in) :: a0  !< amplitude R of the linear motion [rad]
      real(wp), intent(in) :: c  !< factor max(1, (w_d + gamma/2)/w0) on the drift
      real(wp), intent(in) :: p  !< w0^2 A0^2/(16 w_d) [1/s]
      real(wp) :: phi, q, s
      if (.not. ieee_is_finite(a0) .or. .not. ieee_is_finite(p)) then
        f = ieee_value(1.0_wp, ieee_positive_inf)
        return
      end if
      f = a0**3/16                                         ! t = 0
      phi = p*int_exp(gamma, tend)                         ! t = tend
      f = max(f, drift(a0, c, exp(-a*tend), phi))
      if (phi > 2) f = max(f, drift(a0, c, sqrt(max(0.0_wp, 1 - 2*gamma/p)), 2.0_wp))
      if (3*a0**2*gamma < 32*c*p) then
        q = a0**2*gamma/(16*c*p)
        s = (2 - 3*q)/(3*(1 - q))                       ! 1 - u^2 at the stationary point
        if (s*p < 2*gamma .and. s <= -expm1(-gamma*tend)) &
          f = max(f, drift(a0, c, sqrt(1/(3*(1 - q))), s*p/gamma))
      end if
    end function drift_sup
    ! the phase-drift error at u = e^(-a t) with phase lag phi
    pure real(wp) function drift(a0, c, u, phi) result(y)
      real(wp), intent(in) :: a0, c, u, phi
      y = a0*u*min(2.0_wp, phi)*c + (a0*u)**3/16
    end function drift
    ! The t > 0 where w C(t) = v S(t), i.e. tanh(beta t)/beta = w/v (for
    ! 0 <= beta w < v): the hump of a motion whose velocity is e^(-a t) (w C -
    ! v S).  vm = v - beta w, from the caller without cancellation where it
    ! can.  atanh(x)/beta with x = beta w/v, by its series for small x (no 0/0
    ! at beta = 0, critical damping, where t = w/v: seamless across it).
    pure real(wp) function hump_time(beta, w, v, vm) result(t)
      real(wp), intent(in) :: beta, w, v, vm
      real(wp) :: x, x2
      x = beta*(w/v)
      if (x < 1.0e-3_wp) then
        x2 = x*x
        t = (w/v)*(1 + x2*(1.0_wp/3 + x2*(1.0_wp/5 + x2/7)))
      else
        t = 0.5_wp*(log(v + beta*w) - log(vm))/beta
      end if
    end function hump_time
  end function linear_estimate

  ! e^x - 1 without cancellation for small |x| (accurate to ~1e-11 relative,
  ! ample for error estimates).  Kept here, next to its only caller,
  ! linear_estimate (its integrals of e^(-a s) and the phase drift's window).
  elemental real(wp) function expm1(x) result(r)
    real(wp), intent(in) :: x
    if (abs(x) < 1.0e-5_wp) then
      r = x*(1 + x*(0.5_wp + x/6))
    else
      r = exp(x) - 1
    end if
  end function expm1

end module pendula_scene_bounds
