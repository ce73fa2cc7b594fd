!> Linear damped pendulum theta'' + gamma theta' + w0^2 theta = 0 (text eq. 2.4)
!> in closed form, for every regime, as ONE evaluation:
!>
!>   theta(t) = e^{-a t} [ theta0 C(t) + (Omega0 + a theta0) S(t) ]
!>   Omega(t) = e^{-a t} [ Omega0 C(t) - (w0^2 theta0 + a Omega0) S(t) ]
!>
!> with a = gamma/2, D = a^2 - w0^2 (= beta^2 of eq. 2.15), C = cosh(sqrt(D) t)
!> and S = sinh(sqrt(D) t)/sqrt(D).  C and S/t are entire functions of
!> z = D t^2 (cos/sin for z < 0, cosh/sinh for z > 0, 1 and t at z = 0), so the
!> over-, critically and under-damped solutions of §2.1.1, §2.1.2 and §2.1.3 are
!> one analytic family.  Numerically:
!>  * |z| <= 1/4: Taylor series of C and S/t in z (no case split, no 0/0 and no
!>    loss of digits as gamma -> 2 w0, where the text's eq. 2.29 divides by
!>    lambda2 - lambda1 = 2 beta);
!>  * z < -1/4 (under-damped): cos and sin of omega_d t, no cancellation;
!>  * z > +1/4 (over-damped): the modal form of eq. 2.27 with the constants of
!>    eq. 2.29 rewritten without cancellation, lambda2 = -w0^2/(a + beta) (the
!>    text's -a + beta cancels when gamma >> w0), and e^{-a t} folded into
!>    e^{lambda1 t}, e^{lambda2 t} so that nothing overflows: for gamma t up to
!>    1e300 the answer underflows gracefully to 0.
!> gamma = 0 is evaluated as the small-angle solution theta0 cos(w0 t) +
!> (Omega0/w0) sin(w0 t) itself, so the two agree bit for bit.
!> Units: t [s], theta [rad], Omega [rad/s], w0 and gamma [1/s].
module pendula_linear_damped
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_is_finite
  use pendula_kinds, only: wp
  use pendula_format, only: format_int, code_text
  use pendula_status, only: status_t, set_error, check_finite, check_positive, &
                            check_nonnegative, check_same_size, PENDULA_OK
  use pendula_constants, only: pi
  use pendula_small_angle, only: harmonic_state
  implicit none
  private

  public :: damping_regime_t, linear_damped_t
  public :: DAMPING_UNDERDAMPED, DAMPING_CRITICAL, DAMPING_OVERDAMPED
  public :: damping_regime, regime_name
  public :: linear_damped_init, linear_damped_state, linear_damped_theta, &
            linear_damped_omega, linear_damped_envelope, linear_damped_eval, linear_damped_arrays

  !> Regime codes: gamma < 2 w0, gamma == 2 w0 (exactly, in floating point), gamma > 2 w0.
  integer, parameter :: DAMPING_UNDERDAMPED = 1
  integer, parameter :: DAMPING_CRITICAL = 2
  integer, parameter :: DAMPING_OVERDAMPED = 3
  ! regime_name's table
  integer, parameter :: REGIME_CODES(3) = [DAMPING_UNDERDAMPED, DAMPING_CRITICAL, DAMPING_OVERDAMPED]
  character(len=11), parameter :: REGIME_NAMES(3) = [character(len=11) :: 'underdamped', 'critical', 'overdamped']

  !> Beyond |z| = |D| t^2 > 1/4, i.e. x = sqrt|D| t > X_SERIES, the closed
  !> forms replace the series.
  real(wp), parameter :: X_SERIES = 0.5_wp
  !> exp(x) is normal for x >= X_NORMAL; c exp(x) underflows to 0 for every
  !> double c when x < X_ZERO.
  real(wp), parameter :: X_NORMAL = -708.0_wp, X_ZERO = -1500.0_wp
  !> split_exp's floor: below it c exp(x) 2^ns is 0 for every double c and
  !> every state scaling ns <= NS_MAX.
  real(wp), parameter :: X_SPLIT = -4000.0_wp
  integer, parameter :: NS_MAX = 3000
  !> ln 2 = LN2_HI + LN2_LO, LN2_HI with trailing zero bits so n LN2_HI is exact
  !> for |n| < 2^20 (Cody and Waite's argument reduction).
  real(wp), parameter :: LN2_HI = 6.93147180369123816490e-01_wp, &
                         LN2_LO = 1.90821492927058770002e-10_wp
  ! C(z) = cosh(sqrt z) = sum_{k<=8} z^k/(2k)!, S(z)/t = sinh(sqrt z)/sqrt z =
  ! sum_{k<=8} z^k/(2k+1)!: truncation < 1e-18 for |z| <= 1/4; Horner with the
  ! reciprocal factorials (each within half an ulp) keeps the sum within ~1 ulp.
  real(wp), parameter :: C_COEF(0:8) = [1.0_wp, 1.0_wp/2, 1.0_wp/24, 1.0_wp/720, &
                                        1.0_wp/40320, 1.0_wp/3628800, 1.0_wp/479001600, 1.0_wp/87178291200.0_wp, &
                                        1.0_wp/20922789888000.0_wp]
  real(wp), parameter :: S_COEF(0:8) = [1.0_wp, 1.0_wp/6, 1.0_wp/120, 1.0_wp/5040, &
                                        1.0_wp/362880, 1.0_wp/39916800, 1.0_wp/6227020800.0_wp, 1.0_wp/1307674368000.0_wp, &
                                        1.0_wp/355687428096000.0_wp]

  !> The numbers of a regime (all rates in 1/s, times in s).
  type :: damping_regime_t
    !> DAMPING_UNDERDAMPED, DAMPING_CRITICAL or DAMPING_OVERDAMPED.
    integer :: regime = DAMPING_UNDERDAMPED
    real(wp) :: w0 = 0, gamma = 0
    !> Eigenvalues of eq. 2.15, lambda1 <= lambda2 (real parts; conjugate pair
    !> -gamma/2 -+ i omega_d when under-damped).  lambda2 = -w0^2/(gamma/2 + beta).
    complex(wp) :: lambda1 = (0, 0), lambda2 = (0, 0)
    !> Damped angular frequency omega_d = sqrt(w0^2 - gamma^2/4) (under-damped; 0 otherwise).
    real(wp) :: omega_d = 0
    !> beta = sqrt(gamma^2/4 - w0^2) of eq. 2.15 (over-damped; 0 otherwise).
    real(wp) :: beta = 0
    !> Decay rates -Re(lambda2) (slow) and -Re(lambda1) (fast); both gamma/2
    !> unless over-damped.
    real(wp) :: decay_slow = 0, decay_fast = 0
    !> Quality factor Q = w0/gamma (+Inf when gamma = 0).
    real(wp) :: quality_factor = 0
    !> Logarithmic decrement ln(theta(t)/theta(t + T_d)) = pi gamma/omega_d
    !> (under-damped; +Inf when the motion does not oscillate).
    real(wp) :: log_decrement = 0
    !> Damped period T_d = 2 pi/omega_d (under-damped; +Inf otherwise).
    real(wp) :: damped_period = 0
    !> Critical damping rate gamma_c = 2 w0 and damping ratio zeta = gamma/(2 w0).
    real(wp) :: gamma_critical = 0, damping_ratio = 0
  end type damping_regime_t

  !> One trajectory, set up once by linear_damped_init and evaluated at any
  !> t >= 0 by the elemental linear_damped_state / _theta / _omega.
  type :: linear_damped_t
    type(damping_regime_t) :: info
    real(wp) :: theta0 = 0, omega0 = 0, w0 = 1, gamma = 0
    !> Envelope amplitude R: theta = R e^{-gamma t/2} cos(omega_d t - phi)
    !> when under-damped (0 otherwise).
    real(wp) :: amplitude = 0
    ! Private set-up of the evaluation (see the module comment).
    real(wp), private :: a = 0           ! gamma/2
    real(wp), private :: kappa = 0       ! sqrt(|D|): beta or omega_d
    real(wp), private :: zsign = 0       ! sign of D
    logical, private :: undamped = .false.
    ! The set-up below holds the state scaled by 2^-ns (ns > 0 only when an
    ! intermediate would overflow: the solution is linear in the state, so
    ! results are scaled back by 2^ns at the very end).
    integer, private :: ns = 0
    real(wp), private :: th0 = 0, om0 = 0          ! theta0 2^-ns, Omega0 2^-ns
    real(wp), private :: amp = 0                   ! amplitude 2^-ns
    real(wp), private :: b = 0, w0th = 0, aom = 0   ! Omega0 + a theta0, w0 theta0, a Omega0
    ! under-damped: theta = e^{-at}(theta0 cos + bs sin), Omega = e^{-at}(Omega0 cos - ds sin)
    real(wp), private :: bs = 0, ds = 0
    ! over-damped: theta = ca e^{l1 t} + cb e^{l2 t}, Omega = l1 ca e^{l1 t} + l2 cb e^{l2 t}
    real(wp), private :: l1 = 0, l2 = 0, ca = 0, cb = 0, l1ca = 0, l2cb = 0
  contains
    procedure :: state => linear_damped_state
    procedure :: theta => linear_damped_theta
    procedure :: omega => linear_damped_omega
    procedure :: envelope => linear_damped_envelope
  end type linear_damped_t

contains

  !> Regime of theta'' + gamma theta' + w0^2 theta = 0 and its numbers
  !> (eq. 2.15 and §2.1.3).  w0 > 0 and gamma >= 0, finite [1/s]; otherwise
  !> status is set and info holds defaults.  Critical means gamma == 2 w0
  !> exactly; nearness to it is damping_ratio - 1.  Every number is within a
  !> few ulps of its exact value at the given inputs.
  pure subroutine damping_regime(w0, gamma, info, status)
    real(wp), intent(in) :: w0  !< small-angle angular frequency sqrt(g/l) [1/s], finite, > 0
    real(wp), intent(in) :: gamma  !< damping rate b/m [1/s], finite, >= 0
    type(damping_regime_t), intent(out) :: info
    !< regime code, damping ratio, eigenvalues and time scales (defaults on error)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    real(wp) :: a, inf, kappa
    call check_positive('w0', w0, status)
    call check_nonnegative('gamma', gamma, status)
    if (status%code /= PENDULA_OK) return
    inf = ieee_value(1.0_wp, ieee_positive_inf)
    a = gamma/2
    info%w0 = w0
    info%gamma = gamma
    info%gamma_critical = 2*w0
    info%damping_ratio = a/w0
    ! Q = w0/gamma, +Inf when gamma = 0 or when w0/gamma exceeds the double range.
    if (gamma > w0/huge(1.0_wp)) then
      info%quality_factor = w0/gamma
    else
      info%quality_factor = inf
    end if
    ! sqrt|a - w0| sqrt(a + w0) is sqrt|a^2 - w0^2| without cancellation
    ! (a - w0 is exact near the critical point) and without overflow.
    if (gamma == 0) then
      kappa = w0
    else if (max(a, w0) < 0.25_wp*huge(1.0_wp)) then
      kappa = sqrt(abs(a - w0))*sqrt(a + w0)
    else
      ! a + w0 could overflow: halve both (exact at this size)
      kappa = 2*(sqrt(abs(0.5_wp*a - 0.5_wp*w0))*sqrt(0.5_wp*a + 0.5_wp*w0))
    end if
    if (a < w0) then
      info%regime = DAMPING_UNDERDAMPED
      info%omega_d = kappa
      info%lambda1 = cmplx(-a, -kappa, wp)
      info%lambda2 = cmplx(-a, kappa, wp)
      info%decay_slow = a
      info%decay_fast = a
      info%log_decrement = pi*(gamma/kappa)
      info%damped_period = 2*pi/kappa
    else if (a == w0) then
      info%regime = DAMPING_CRITICAL
      info%lambda1 = cmplx(-a, 0, wp)
      info%lambda2 = cmplx(-a, 0, wp)
      info%decay_slow = a
      info%decay_fast = a
      info%log_decrement = inf
      info%damped_period = inf
    else
      info%regime = DAMPING_OVERDAMPED
      info%beta = kappa
      ! lambda2 = -a + beta cancels for gamma >> w0; lambda1 lambda2 = w0^2.
      info%lambda1 = cmplx(-(a + kappa), 0, wp)
      info%lambda2 = cmplx(-(w0*(w0/(a + kappa))), 0, wp)
      info%decay_slow = w0*(w0/(a + kappa))
      info%decay_fast = a + kappa
      info%log_decrement = inf
      info%damped_period = inf
    end if
  end subroutine damping_regime

  !> 'underdamped', 'critical' or 'overdamped' (or 'unknown').
  pure function regime_name(regime) result(name)
    integer, intent(in) :: regime  !< DAMPING_UNDERDAMPED, DAMPING_CRITICAL or DAMPING_OVERDAMPED
    ! explicit length (not deferred): see pendula_format on gfortran's static lengths
    character(len=len(code_text(regime, REGIME_CODES, REGIME_NAMES, 'unknown'))) :: name
    name = code_text(regime, REGIME_CODES, REGIME_NAMES, 'unknown')
  end function regime_name

  !> Set up the trajectory with theta(0) = theta0 [rad], Omega(0) = omega0
  !> [rad/s] (finite), w0 > 0 and gamma >= 0 [1/s] (finite).  On bad input
  !> status names the argument and sol is left at its defaults.
  pure subroutine linear_damped_init(sol, theta0_in, omega0_in, w0, gamma, status)
    type(linear_damped_t), intent(out) :: sol  !< the trajectory (defaults on error)
    real(wp), intent(in) :: theta0_in  !< initial angle theta(0) [rad], finite
    real(wp), intent(in) :: omega0_in  !< initial angular velocity Omega(0) [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency sqrt(g/l) [1/s], finite, > 0
    real(wp), intent(in) :: gamma  !< damping rate b/m [1/s], finite, >= 0
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    real(wp) :: a, k, inv2k, theta0, omega0
    call check_finite('theta0', theta0_in, status)
    call check_finite('omega0', omega0_in, status)
    if (status%code /= PENDULA_OK) return
    call damping_regime(w0, gamma, sol%info, status)
    if (status%code /= PENDULA_OK) return
    sol%theta0 = theta0_in
    sol%omega0 = omega0_in
    sol%ns = state_scaling(sol%info, theta0_in, omega0_in)
    theta0 = scale(theta0_in, -sol%ns)
    omega0 = scale(omega0_in, -sol%ns)
    sol%th0 = theta0
    sol%om0 = omega0
    sol%w0 = w0
    sol%gamma = gamma
    a = gamma/2
    sol%a = a
    sol%undamped = gamma == 0
    sol%b = omega0 + a*theta0
    sol%w0th = w0*theta0
    sol%aom = a*omega0
    select case (sol%info%regime)
    case (DAMPING_UNDERDAMPED)
      k = sol%info%omega_d
      sol%kappa = k
      sol%zsign = -1
      sol%bs = omega0/k + theta0*(a/k)
      sol%ds = sol%w0th*(w0/k) + omega0*(a/k)
      if (sol%undamped) then
        sol%bs = omega0/w0
        sol%ds = w0*theta0
      end if
      ! theta = R e^{-at} cos(omega_d t - phi) with R = |(theta0, b/omega_d)|.
      sol%amp = hypot(theta0, sol%bs)
      sol%amplitude = scale_sat(sol%amp, sol%ns)
    case (DAMPING_OVERDAMPED)
      k = sol%info%beta
      sol%kappa = k
      sol%zsign = 1
      sol%l1 = real(sol%info%lambda1, wp)
      sol%l2 = real(sol%info%lambda2, wp)
      ! Eq. 2.29 with lambda2 - lambda1 = 2 beta, each term formed without
      ! cancellation or overflow: A = (theta0 l2 - Omega0)/(2 beta),
      ! B = (Omega0 - theta0 l1)/(2 beta) = Omega0/(2 beta) + theta0 (a + beta)/(2 beta).
      inv2k = 0.5_wp/k
      sol%ca = theta0*(sol%l2*inv2k) - omega0*inv2k
      sol%cb = omega0*inv2k + theta0*((a + k)*inv2k)
      sol%l1ca = sol%l1*sol%ca
      sol%l2cb = sol%l2*sol%cb
    case default
      sol%kappa = 0
      sol%zsign = 0
    end select
  end subroutine linear_damped_init

  ! Power of 2 (>= 0) to divide the state by so that no intermediate of the
  ! set-up or the evaluation overflows: those are at most the angle scale
  ! max(|theta0|, |Omega0|/w0) times the square of the largest rate (a Omega0,
  ! w0^2 theta0; when > 1) times the largest rate over sqrt|D| (when > 1),
  ! times a margin of 2^16 (w0 t <= 1500 in the series form).  0 for every
  ! ordinary state.
  pure integer function state_scaling(info, theta0, omega0) result(ns)
    type(damping_regime_t), intent(in) :: info
    real(wp), intent(in) :: theta0, omega0
    integer :: e_state, e_rate, e_ratio
    real(wp) :: k
    e_state = max(exponent(theta0), exponent(omega0) - exponent(info%w0))
    e_rate = max(exponent(info%w0), exponent(info%gamma))
    k = max(info%omega_d, info%beta)
    e_ratio = 0
    if (k > 0) e_ratio = max(0, e_rate - exponent(k))
    ns = min(NS_MAX, max(0, e_state + 2*max(0, e_rate) + e_ratio + 16 - maxexponent(1.0_wp)))
  end function state_scaling

  ! x 2^n, +-inf when beyond the double range (without raising overflow:
  ! the checked build traps it); gradual underflow as scale().
  elemental real(wp) function scale_sat(x, n) result(y)
    real(wp), intent(in) :: x
    integer, intent(in) :: n
    if (x /= 0 .and. exponent(x) + n > maxexponent(1.0_wp)) then
      y = sign(ieee_value(1.0_wp, ieee_positive_inf), x)
    else
      y = scale(x, n)
    end if
  end function scale_sat

  ! sum_k coef(k) z^k by Horner (C(z) and S(z)/t with C_COEF, S_COEF).
  pure real(wp) function horner(coef, z) result(p)
    real(wp), intent(in) :: coef(0:), z
    integer :: k
    p = coef(ubound(coef, 1))
    do k = ubound(coef, 1) - 1, 0, -1
      p = coef(k) + z*p
    end do
  end function horner

  ! exp(x) = m 2^n with m in (1/2, 1], for X_SPLIT <= x <= 0 (m = 0 below), so
  ! that c exp(x) = scale(c m, n) never underflows before the last step.
  elemental subroutine split_exp(x, m, n)
    real(wp), intent(in) :: x
    real(wp), intent(out) :: m
    integer, intent(out) :: n
    real(wp) :: r
    m = 0
    n = 0
    if (x < X_SPLIT) return
    n = ceiling(x/LN2_HI)
    r = (x - n*LN2_HI) - n*LN2_LO
    m = exp(r)
  end subroutine split_exp

  ! r * t for r, t >= 0, saturated at huge() instead of overflowing (the
  ! checked build traps overflow; exp(-huge) is 0 and cos(huge) finite).
  elemental real(wp) function mul_sat(r, t) result(x)
    real(wp), intent(in) :: r, t
    if (r > 1) then
      if (t > huge(1.0_wp)/r) then
        x = huge(1.0_wp)
        return
      end if
    end if
    x = r*t
  end function mul_sat

  !> theta(t) [rad] and Omega(t) [rad/s] at t >= 0 [s] for a trajectory set up
  !> by linear_damped_init.  Error within a few eps of (|theta| + |Omega|/max(w0,
  !> gamma) + condition of the problem); never overflows for t >= 0 (values
  !> below the double range come out as 0).  t < 0 is outside the contract.
  elemental subroutine linear_damped_state(sol, t, theta, omega)
    class(linear_damped_t), intent(in) :: sol  !< linear damped trajectory set up by linear_damped_init
    real(wp), intent(in) :: t  !< time [s], >= 0
    real(wp), intent(out) :: theta  !< theta(t) [rad]
    real(wp), intent(out) :: omega  !< Omega(t) [rad/s]
    real(wp) :: x, z, xe, e, et, s, c, p, q, m1, m2
    integer :: n1, n2
    theta = 0
    omega = 0
    if (sol%undamped) then
      ! The small-angle solution itself (gamma = 0), unscaled.
      call harmonic_state(0.0_wp, sol%theta0, sol%omega0, sol%w0, t, theta, omega)
      return
    end if
    x = mul_sat(sol%kappa, t)
    if (x <= X_SERIES .or. sol%zsign < 0) then
      ! theta = e^{-at} p, Omega = e^{-at} q, with the series (near critical,
      ! small t) or cos/sin (under-damped) in the brackets p and q.
      xe = -mul_sat(sol%a, t)
      if (xe < X_ZERO - LN2_HI*sol%ns) return
      if (x <= X_SERIES) then
        if (sol%zsign == 0) then     ! critical: C = 1, S = t exactly (eq. 2.45)
          c = 1
          s = 1
        else
          z = sol%zsign*(x*x)
          c = horner(C_COEF, z)
          s = horner(S_COEF, z)      ! S(t)/t
        end if
        ! b t would overflow only for extreme b, t: then fold e^{-at} into t first.
        if (t > 1) then
          if (abs(sol%b) > huge(1.0_wp)/t) then
            e = exp(xe)
            et = e*t
            theta = scale_sat(sol%th0*(e*c) + sol%b*(et*s), sol%ns)
            omega = scale_sat(sol%om0*(e*c) - (sol%w0th*(sol%w0*et) + sol%aom*et)*s, sol%ns)
            return
          end if
        end if
        p = sol%th0*c + (sol%b*t)*s
        q = sol%om0*c - (sol%w0th*(sol%w0*t) + sol%aom*t)*s
      else
        ! Under-damped (§2.1.3).
        c = cos(x)
        s = sin(x)
        p = sol%th0*c + sol%bs*s
        q = sol%om0*c - sol%ds*s
      end if
      if (xe >= X_NORMAL .and. sol%ns == 0) then
        e = exp(xe)
        theta = e*p
        omega = e*q
      else
        ! e^{-at} itself would be subnormal: multiply by its significand and
        ! scale by its power of 2 last, so a representable answer keeps its digits.
        call split_exp(xe, m1, n1)
        theta = scale_sat(m1*p, n1 + sol%ns)
        omega = scale_sat(m1*q, n1 + sol%ns)
      end if
    else
      ! Over-damped (eq. 2.27): e^{lambda t} never overflows for t >= 0.
      xe = -mul_sat(-sol%l2, t)      ! lambda2 t, the slow mode
      if (xe < X_ZERO - LN2_HI*sol%ns) return
      x = -mul_sat(-sol%l1, t)       ! lambda1 t <= lambda2 t
      if (xe >= X_NORMAL .and. x >= X_NORMAL .and. sol%ns == 0) then
        m1 = exp(x)
        m2 = exp(xe)
        theta = sol%ca*m1 + sol%cb*m2
        omega = sol%l1ca*m1 + sol%l2cb*m2
      else
        call split_exp(x, m1, n1)
        call split_exp(xe, m2, n2)
        ! sum at the larger power of 2 (n2 >= n1: lambda1 t <= lambda2 t), scale once:
        ! two overflowing terms of opposite sign must not give inf - inf
        theta = scale_sat(scale(sol%ca*m1, n1 - n2) + sol%cb*m2, n2 + sol%ns)
        omega = scale_sat(scale(sol%l1ca*m1, n1 - n2) + sol%l2cb*m2, n2 + sol%ns)
      end if
    end if
  end subroutine linear_damped_state

  !> theta(t) [rad] at t >= 0 [s]; see linear_damped_state.
  elemental real(wp) function linear_damped_theta(sol, t) result(theta)
    class(linear_damped_t), intent(in) :: sol  !< linear damped trajectory set up by linear_damped_init
    real(wp), intent(in) :: t  !< time [s], >= 0
    real(wp) :: omega
    call linear_damped_state(sol, t, theta, omega)
  end function linear_damped_theta

  !> Omega(t) = theta'(t) [rad/s] at t >= 0 [s]; see linear_damped_state.
  elemental real(wp) function linear_damped_omega(sol, t) result(omega)
    class(linear_damped_t), intent(in) :: sol  !< linear damped trajectory set up by linear_damped_init
    real(wp), intent(in) :: t  !< time [s], >= 0
    real(wp) :: theta
    call linear_damped_state(sol, t, theta, omega)
  end function linear_damped_omega

  !> Under-damped envelope R e^{-gamma t/2} [rad] (|theta(t)| <= envelope,
  !> touching it once per half period, §2.1.3); 0 for the other regimes.
  elemental real(wp) function linear_damped_envelope(sol, t) result(env)
    class(linear_damped_t), intent(in) :: sol  !< linear damped trajectory set up by linear_damped_init
    real(wp), intent(in) :: t  !< time [s], >= 0
    real(wp) :: m
    integer :: n
    env = 0
    if (sol%info%regime /= DAMPING_UNDERDAMPED .or. .not. sol%amp > 0) return
    if (sol%ns == 0) then
      env = sol%amp*exp(-mul_sat(sol%a, t))
    else
      call split_exp(-mul_sat(sol%a, t), m, n)
      env = scale_sat(sol%amp*m, n + sol%ns)
    end if
  end function linear_damped_envelope

  !> Evaluate a set-up trajectory at times t(:) >= 0 [s] (any order) into
  !> theta(:), omega(:) of the same size.  Non-finite or negative t, or a size
  !> mismatch, sets status (outputs are then 0).
  pure subroutine linear_damped_eval(sol, t, theta, omega, status)
    type(linear_damped_t), intent(in) :: sol  !< linear damped trajectory set up by linear_damped_init
    real(wp), intent(in) :: t(:)  !< times [s], finite, >= 0, any order
    real(wp), intent(out) :: theta(:)  !< theta(t(i)) [rad], size(t) elements
    real(wp), intent(out) :: omega(:)  !< Omega(t(i)) [rad/s], size(t) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    theta = 0
    omega = 0
    call check_same_size('theta', size(theta), 't', size(t), status)
    call check_same_size('omega', size(omega), 't', size(t), status)
    call check_times(t, status)
    if (status%code /= PENDULA_OK) return
    call linear_damped_state(sol, t, theta, omega)
  end subroutine linear_damped_eval

  !> Elementwise over equal-size arrays: theta(i), omega(i) of the trajectory
  !> (theta0(i), omega0(i), w0(i), gamma(i)) at t(i) >= 0.  Consecutive equal
  !> parameter sets share one set-up.  The first bad element sets status with
  !> its (0-based) index; outputs are then 0.
  pure subroutine linear_damped_arrays(t, theta0, omega0, w0, gamma, theta, omega, status)
    real(wp), intent(in) :: t(:)  !< times [s], finite, >= 0
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad], size(t)
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], size(t)
    real(wp), intent(in) :: w0(:)  !< angular frequencies [1/s], > 0, size(t)
    real(wp), intent(in) :: gamma(:)  !< damping rates [1/s], >= 0, size(t)
    real(wp), intent(out) :: theta(:)  !< theta(t(i)) [rad], size(t)
    real(wp), intent(out) :: omega(:)  !< Omega(t(i)) [rad/s], size(t)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    type(linear_damped_t) :: sol
    integer :: i, n
    logical :: fresh
    theta = 0
    omega = 0
    n = size(t)
    call check_same_size('theta0', size(theta0), 't', n, status)
    call check_same_size('omega0', size(omega0), 't', n, status)
    call check_same_size('w0', size(w0), 't', n, status)
    call check_same_size('gamma', size(gamma), 't', n, status)
    call check_same_size('theta', size(theta), 't', n, status)
    call check_same_size('omega', size(omega), 't', n, status)
    call check_times(t, status)
    if (status%code /= PENDULA_OK) return
    fresh = .true.
    do i = 1, n
      if (i > 1) fresh = theta0(i) /= theta0(i - 1) .or. omega0(i) /= omega0(i - 1) .or. &
                         w0(i) /= w0(i - 1) .or. gamma(i) /= gamma(i - 1)
      if (fresh) then
        call linear_damped_init(sol, theta0(i), omega0(i), w0(i), gamma(i), status)
        if (status%code /= PENDULA_OK) then
          if (n > 1) then
            status%message = trim(status%message)//' (element '//format_int(i - 1)//')'
          end if
          theta = 0
          omega = 0
          return
        end if
      end if
      call linear_damped_state(sol, t(i), theta(i), omega(i))
    end do
  end subroutine linear_damped_arrays

  ! Every t finite and >= 0; the message names the first bad (0-based) index.
  pure subroutine check_times(t, status)
    real(wp), intent(in) :: t(:)
    type(status_t), intent(inout) :: status
    integer :: i
    if (status%code /= PENDULA_OK) return
    do i = 1, size(t)
      ! ieee_is_finite first: an ordered comparison with NaN may trap.
      if (.not. ieee_is_finite(t(i))) then
        call check_finite('t['//format_int(i - 1)//']', t(i), status)
        return
      else if (t(i) < 0) then
        call check_nonnegative('t['//format_int(i - 1)//']', t(i), status)
        return
      end if
    end do
  end subroutine check_times

end module pendula_linear_damped
