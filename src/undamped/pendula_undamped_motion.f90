!> The undamped pendulum's motion for one initial state: undamped_motion_t,
!> undamped_init (the set-up: regime, parameter, phase, period) and the
!> regime/period/energy accessors; evaluation at times is pendula_undamped_eval.
!> Users `use pendula_undamped` (the facade); the theory is told there.
module pendula_undamped_motion
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf
  use pendula_kinds, only: wp
  use pendula_format, only: code_text
  use pendula_status, only: status_t, check_finite, check_positive, PENDULA_OK
  use pendula_constants, only: pi, two_pi, two_pi_lo, half_pi, half_pi_lo
  use pendula_elliptic_tables, only: atan_poly
  use pendula_double_double, only: two_prod, dd_add_fast
  use pendula_elliptic, only: ellipkm1, ellipfm1, ellipj_plan_t, ellipj_planm1
  use pendula_angle_dd, only: cos_dd, reduce_angle_2pi, sincos_half
  implicit none
  private

  public :: undamped_motion_t, undamped_init, undamped_period, undamped_amplitude, undamped_energy, &
            undamped_regime, pendulum_energy, undamped_regime_name, undamped_plan_pays, undamped_add_plan
  ! for pendula_undamped_eval, pendula_undamped_many, pendula_small_angle and
  ! pendula_scene_bounds only (not re-exported by pendula_undamped):
  public :: check_state, set_geometry, set_period, motion_amplitude, period_needed, M_TINY
  public :: REGIME_LIBRATION, REGIME_SEPARATRIX, REGIME_ROTATION, UNDAMPED_PLAN_MIN_TIMES

  !> The pendulum swings about theta = 2 pi N (m < 1).
  integer, parameter :: REGIME_LIBRATION = 1
  !> Exactly the separatrix energy (m = 1): it creeps towards the top forever.
  integer, parameter :: REGIME_SEPARATRIX = 2
  !> It goes over the top and keeps turning (m > 1).
  integer, parameter :: REGIME_ROTATION = 3
  ! undamped_regime_name's table
  integer, parameter :: REGIME_CODES(3) = [REGIME_LIBRATION, REGIME_SEPARATRIX, REGIME_ROTATION]
  character(len=10), parameter :: REGIME_NAMES(3) = [character(len=10) :: 'libration', 'separatrix', 'rotation']

  !> Below this m (2**-968), m = sin^2(theta_r/2) + (Omega0/(2 w0))^2 has lost bits to
  !> the subnormal range: set_geometry then takes k = sqrt(m) from its two parts.
  real(wp), parameter :: M_TINY = 2.0_wp**(-968)

  !> A state evaluated at this many times or more gets a Jacobi plan (~13 us
  !> once, then ~40 ns per time); below, each time costs ~0.3-0.7 us of
  !> ellipjm1, so the plan pays for itself from about 30 times on (measured on
  !> this project's 2-core machine).
  integer, parameter :: UNDAMPED_PLAN_MIN_TIMES = 32

  !> Everything about one initial state that does not depend on t; build it once
  !> with `undamped_init` and evaluate it at any number of times with
  !> `undamped_eval` (elemental in t, pure, thread-safe: read-only).
  type :: undamped_motion_t
    real(wp) :: theta0 = 0        !< initial angle as given [rad]
    real(wp) :: omega0 = 0        !< initial angular velocity [rad/s]
    real(wp) :: w0 = 1            !< natural frequency sqrt(g/l) [1/s]
    integer :: regime = REGIME_LIBRATION
    real(wp) :: m = 0             !< k^2 = E / E_separatrix
    real(wp) :: mc = 1            !< 1 - m, computed without cancellation
    real(wp) :: k = 0             !< sqrt(m)
    real(wp) :: s = 0             !< direction of turning, sign(Omega0) (rotation, separatrix)
    real(wp) :: center = 0        !< 2 pi N, the stable equilibrium theta0 is reduced to
    real(wp) :: theta_r = 0       !< theta0 - 2 pi N in [-pi, pi]
    real(wp) :: h = 0, hlo = 0    !< theta_r/2 = h + hlo (double-double; hlo /= 0 for |theta0| > pi)
    real(wp) :: rate = 1          !< d(argument)/dt: w0, or k w0 for rotation [1/s]
    real(wp) :: phase = 0         !< u0 (libration), v0 (rotation) or c (separatrix)
    real(wp) :: sh = 0            !< sin(theta_r/2) = k sn(u0|m) = sn(v0|1/m)
    real(wp) :: ch = 1            !< cos(theta_r/2) = dn(u0|m) = cn(v0|1/m)
    real(wp) :: q = 0             !< Omega0/(2 w0) = k cn(u0|m) = s k dn(v0|1/m)
    real(wp) :: dnb = 1           !< dn(v0|1/m) = |q|/k (rotation)
    logical :: free = .false.     !< |Omega0/(2 w0)| > 1e150: gravity below 1e-300 relative, free rotor
    logical :: planned = .false.  !< plan holds a Jacobi plan (else ellipjm1 per point)
    real(wp) :: pmc = 1           !< complement of the Jacobi parameter in use: 1 - m, or 1 - 1/m
    real(wp) :: kk = 0            !< K of the elliptic parameter in use: K(m) or K(1/m)
    real(wp) :: period = 0        !< 4K(m)/w0, 2K(1/m)/(k w0) per turn, or +inf [s]
    real(wp) :: amplitude = 0     !< max |theta - center| (libration), pi, or +inf [rad]
    real(wp) :: energy = 0        !< E/(m l^2) = 2 w0^2 m [1/s^2]
    type(ellipj_plan_t) :: plan   !< Jacobi-function plan for the parameter m or 1/m (if planned)
  end type undamped_motion_t

contains

  !> Build the motion for the initial state theta0 [rad], Omega0 [rad/s] and
  !> w0 = sqrt(g/l) [1/s]: theta0, Omega0 finite, w0 finite and > 0 (otherwise
  !> status names the argument and `motion` is the resting pendulum).
  !> Cost: one K, one F and one Jacobi plan (~ a few hundred ns).
  pure subroutine undamped_init(motion, theta0, omega0, w0, status, plan, w0lo)
    type(undamped_motion_t), intent(out) :: motion  !< the motion (the resting pendulum on error)
    real(wp), intent(in) :: theta0  !< initial angle [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency sqrt(g/l) [1/s], finite, > 0
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    !> Build a Jacobi plan (default .true.): ~13 us once, then ~40 ns per time;
    !> .false. gives a light motion (~1 us) that costs ~0.3-0.7 us per time
    !> (ellipjm1), for states evaluated at fewer than UNDAMPED_PLAN_MIN_TIMES
    !> times or only queried.  Both give the same accuracy.
    logical, intent(in), optional :: plan
    !> The rounding residual of w0 when w0 is itself rounded from the data
    !> (w0 = fl(sqrt(g/l)): the data's frequency is w0 + w0lo, |w0lo| <= ulp(w0)).
    !> Near the separatrix 1 - m is ill-conditioned in w0 (a relative 4e-17
    !> moved it by 0.25 %), so it is formed for w0 + w0lo; the time scale, whose
    !> rounding costs only ~eps w0 t of phase, stays w0.  Default 0.
    real(wp), intent(in), optional :: w0lo
    logical :: want_plan

    call check_state(theta0, omega0, w0, status)
    want_plan = .true.
    if (present(plan)) want_plan = plan
    if (status%code /= PENDULA_OK) then
      motion%period = 2*pi
      return
    end if
    call set_geometry(motion, theta0, omega0, w0, w0lo)
    call set_period(motion)
    motion%amplitude = motion_amplitude(motion)
    if (motion%free) return
    select case (motion%regime)
    case (REGIME_LIBRATION)
      motion%phase = ellipfm1(atan2(motion%sh, motion%q), motion%mc)
    case (REGIME_ROTATION)
      ! dF/dphi = 1/sqrt(1 - sin^2(phi)/m) = k/|q| carries the r_lo correction
      motion%phase = ellipfm1(motion%s*motion%h, motion%pmc) + motion%s*motion%hlo*motion%k/abs(motion%q)
    end select
    if (want_plan) call undamped_add_plan(motion)
  end subroutine undamped_init

  !> Whether a Jacobi plan pays for itself on `times` evaluations of this
  !> motion: its table has ~32 K rows (one Taylor row ~0.25 us each), a point
  !> without it costs ~0.3-0.7 us of ellipjm1 and ~40 ns with it, so the plan
  !> pays from ~16 K times on (UNDAMPED_PLAN_MIN_TIMES at K ~ 2; near the
  !> separatrix K ~ 40 makes the table ~20x dearer).  Never for the
  !> separatrix or a free rotor (no plan there).
  pure logical function undamped_plan_pays(motion, times) result(pays)
    type(undamped_motion_t), intent(in) :: motion  !< a motion from undamped_init (planned or light)
    integer, intent(in) :: times  !< number of times it will be evaluated at, >= 0
    pays = motion%regime /= REGIME_SEPARATRIX .and. .not. motion%free .and. &
           real(times, wp) >= max(real(UNDAMPED_PLAN_MIN_TIMES, wp), 16*motion%kk)
  end function undamped_plan_pays

  !> Give a light motion (undamped_init with plan = .false.) its Jacobi plan;
  !> a motion already planned, the separatrix and a free rotor are left as
  !> they are.  The same numbers as undamped_init with plan = .true.
  pure subroutine undamped_add_plan(motion)
    type(undamped_motion_t), intent(inout) :: motion  !< a motion from undamped_init
    if (motion%planned .or. motion%free .or. motion%regime == REGIME_SEPARATRIX) return
    motion%plan = ellipj_planm1(motion%pmc)
    motion%planned = .true.
  end subroutine undamped_add_plan

  !> The checks of undamped_init: theta0, Omega0 finite, w0 finite and > 0.
  pure subroutine check_state(theta0, omega0, w0, status)
    real(wp), intent(in) :: theta0  !< initial angle [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], finite, > 0
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    call check_finite('theta0', theta0, status)
    call check_finite('omega0', omega0, status)
    call check_positive('w0', w0, status)
  end subroutine check_state

  !> Everything of a checked state that needs no elliptic function: the
  !> reduction about 2 pi N, sin and cos of theta_r/2, q, m, 1 - m, the regime
  !> and its rate (the separatrix phase too: it is elementary).  Leaves the
  !> period, amplitude, the phases u0, v0 and the plan unset (period = 0): a
  !> light motion evaluates at moderate t without them (undamped_eval needs
  !> the period only beyond |rate t| ~ 5e11).
  pure subroutine set_geometry(motion, theta0, omega0, w0, w0lo)
    type(undamped_motion_t), intent(out) :: motion  !< the motion (the resting pendulum on error)
    real(wp), intent(in) :: theta0  !< initial angle [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], > 0 (checked)
    real(wp), intent(in), optional :: w0lo   ! see undamped_init
    !< optional low part of w0 when w0 is a double-double
    real(wp) :: n, r_hi, r_lo, h, hlo, sh, ch, chlo, sh0, ch0, q, qlo, p, e, w2, d, dlo, a

    motion%theta0 = theta0
    motion%omega0 = omega0
    motion%w0 = w0
    call reduce_angle_2pi(theta0, n, r_hi, r_lo)
    if (abs(theta0) > 2.0_wp**40) then
      motion%center = theta0 - r_hi           ! 2 pi n to the rounding of theta0
    else if (n /= 0) then
      call two_prod(n, two_pi, p, e)
      motion%center = p + (e + n*two_pi_lo)   ! the double nearest 2 pi n
    end if
    motion%theta_r = r_hi
    h = 0.5_wp*r_hi
    hlo = 0.5_wp*r_lo
    motion%h = h
    motion%hlo = hlo
    call sincos_half(h, sh0, ch0)   ! no libm call; ch0 has the bits of the many-state loops' cos_half
    sh = sh0 + ch0*hlo            ! sin(theta_r/2), first-order correction for r_lo
    ! q = Omega0/(2 w0) with its rounding error qlo (exact residual by two_prod)
    w2 = omega0/w0                  ! Omega0/w0, halved below (exact); no 2 w0 overflow
    q = 0.5_wp*w2
    motion%sh = sh
    motion%q = q
    if (abs(q) > 1.0e150_wp) then
      ! m = q^2 would overflow; the pull of gravity is below 1e-300 of the
      ! motion, so the free rotor theta0 + Omega0 t is exact in double.
      motion%ch = ch0 - sh0*hlo
      motion%regime = REGIME_ROTATION
      motion%free = .true.
      motion%s = sign(1.0_wp, q)
      motion%k = abs(q)
      motion%m = ieee_value(1.0_wp, ieee_positive_inf)
      motion%mc = -motion%m
      motion%rate = abs(omega0)
      motion%energy = 0.5_wp*omega0*omega0
      return
    end if
    if (abs(q) >= 0.875_wp*ch0 .and. abs(q) <= (8.0_wp/7)*ch0) then
      ! cos(theta_r/2) in double-double: the separatrix distance 1 - m below
      ! cancels it against |q|, and over 100 periods its error is multiplied by
      ! ~t/(T (1-m) K); a double-double c keeps 1 - m relatively exact.
      call cos_dd(h, hlo, ch, chlo)
    else
      ! c - |q| loses at most three bits: sincos_half (< 1 ulp) keeps 1 - m to a
      ! few ulps (a few eps times its condition number in Omega0), at a twentieth
      ! of the cost of cos_dd
      ch = ch0 - sh0*hlo
      chlo = 0
    end if
    motion%ch = ch
    qlo = 0
    if (w2 /= 0 .and. max(abs(w2), w0) < 1.0e290_wp) then   ! the Veltkamp split would overflow beyond
      call two_prod(w2, w0, p, e)
      qlo = 0.5_wp*(((omega0 - p) - e)/w0)
    end if
    ! Omega0/(2 (w0 + w0lo)) = q (1 - w0lo/w0) + O(eps^2 q)
    if (present(w0lo)) qlo = qlo - q*(w0lo/w0)
    motion%m = sh*sh + q*q
    motion%k = sqrt(motion%m)
    ! sh**2 + q**2 has lost bits to the subnormal range, or underflowed to 0 (|theta0|
    ! and |Omega0/w0| below ~1e-146): k by hypot, which does not square, so that the
    ! amplitude 2 asin(k) and the energy stay accurate
    if (motion%m < M_TINY) motion%k = hypot(sh, q)
    ! 1 - m = cos^2 - q^2 = (c - |q|)(c + |q|), c - |q| in double-double
    a = ch + abs(q)
    if (chlo == 0 .and. qlo == 0) then
      motion%mc = (ch - abs(q))*a             ! what the double-double sum gives then
    else
      call dd_add_fast(ch, chlo, -abs(q), -sign(1.0_wp, q)*qlo, d, dlo)
      motion%mc = (d + dlo)*a
    end if
    motion%energy = 2*(w0*motion%k)**2

    if (motion%mc > 0) then
      motion%regime = REGIME_LIBRATION
      motion%rate = w0
      motion%pmc = motion%mc
    else if (motion%mc < 0) then
      motion%regime = REGIME_ROTATION
      motion%s = sign(1.0_wp, q)
      motion%rate = motion%k*w0
      motion%pmc = -motion%mc/motion%m      ! complement of the parameter 1/m
      motion%dnb = abs(q)/motion%k
    else
      motion%regime = REGIME_SEPARATRIX
      motion%rate = w0
      if (q == 0) then
        ! 1 - m == 0 with Omega0 = 0 would be the upright equilibrium; cos of a
        ! double never rounds to 0, so this is unreachable, but stay at rest.
        motion%s = 0
        motion%phase = 0
      else
        motion%s = sign(1.0_wp, q)
        ! gd^-1(x) = asinh(tan x); d/dx gd^-1 = 1/cos x carries r_lo
        motion%phase = asinh(tan(motion%s*h)) + motion%s*hlo/ch
      end if
    end if
  end subroutine set_geometry

  !> K of the parameter in use and the period (set_geometry first): 4 K(m)/w0,
  !> 2 K(1/m)/(k w0) per turn, 2 pi/|Omega0| for the free rotor, +inf on the separatrix.
  elemental subroutine set_period(motion)
    type(undamped_motion_t), intent(inout) :: motion  !< a motion with its geometry set
    if (motion%free) then
      motion%period = 2*pi/abs(motion%omega0)
      return
    end if
    select case (motion%regime)
    case (REGIME_LIBRATION)
      motion%kk = ellipkm1(motion%mc)
      motion%period = 4*motion%kk/motion%w0
    case (REGIME_ROTATION)
      motion%kk = ellipkm1(motion%pmc)
      motion%period = 2*motion%kk/motion%rate
    case default
      motion%period = ieee_value(1.0_wp, ieee_positive_inf)
      motion%kk = ieee_value(1.0_wp, ieee_positive_inf)
    end select
  end subroutine set_period

  !> Amplitude [rad] of a motion with its geometry set (see undamped_amplitude).
  elemental real(wp) function motion_amplitude(motion) result(amplitude)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init (or set_geometry)
    select case (motion%regime)
    case (REGIME_LIBRATION)
      amplitude = 2*atan_ratio(motion%k, sqrt(motion%mc), half_pi, half_pi_lo, atan_poly)
    case (REGIME_SEPARATRIX)
      amplitude = pi
    case default
      amplitude = ieee_value(1.0_wp, ieee_positive_inf)
    end select
  end function motion_amplitude

  !> Whether undamped_eval at t takes whole periods out (and so needs the period).
  elemental logical function period_needed(motion, t) result(needed)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init (or set_geometry)
    real(wp), intent(in) :: t  !< time [s]
    needed = .not. motion%free .and. motion%regime /= REGIME_SEPARATRIX &
             .and. exponent(t) > 40 - exponent(motion%rate)
  end function period_needed

  !> Period [s]: 4 K(m)/w0 for libration (eq. 1.53 generalised to any state),
  !> the time of one full turn 2 K(1/m)/(k w0) for rotation (the period of
  !> Omega), +inf on the separatrix.
  elemental real(wp) function undamped_period(motion) result(period)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init (or set_geometry)
    period = motion%period
  end function undamped_period

  !> Amplitude [rad]: max |theta - 2 pi N| = 2 asin(k) for libration (computed
  !> as 2 atan(k/sqrt(1-m)) by atan_ratio, within ~1 ulp up to the separatrix), pi on the
  !> separatrix (approached, never reached), +inf for rotation.
  elemental real(wp) function undamped_amplitude(motion) result(amplitude)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init (or set_geometry)
    amplitude = motion%amplitude
  end function undamped_amplitude

  !> Energy per unit m l^2 [1/s^2]: Omega^2/2 + w0^2 (1 - cos theta) = 2 w0^2 m
  !> (zero at the bottom, 2 w0^2 on the separatrix); constant along the motion.
  elemental real(wp) function undamped_energy(motion) result(energy)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init (or set_geometry)
    energy = motion%energy
  end function undamped_energy

  !> Regime code: REGIME_LIBRATION, REGIME_SEPARATRIX or REGIME_ROTATION.
  elemental integer function undamped_regime(motion) result(regime)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init (or set_geometry)
    regime = motion%regime
  end function undamped_regime

  !> Energy of a state per unit m l^2 [1/s^2]: Omega^2/2 + 2 w0^2 sin^2(theta/2)
  !> (= Omega^2/2 + w0^2 (1 - cos theta), eq. 1.2, without the cancellation of
  !> 1 - cos near theta = 0).  Relative accuracy a few eps.
  elemental real(wp) function pendulum_energy(theta, omega, w0) result(energy)
    real(wp), intent(in) :: theta  !< angle [rad]
    real(wp), intent(in) :: omega  !< angular velocity [rad/s]
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s]
    real(wp) :: sh
    sh = sin(0.5_wp*theta)
    energy = 0.5_wp*omega*omega + 2*(w0*sh)*(w0*sh)
  end function pendulum_energy

  !> 'libration', 'separatrix' or 'rotation' for a regime code ('unknown' otherwise).
  pure function undamped_regime_name(regime) result(name)
    integer, intent(in) :: regime  !< REGIME_LIBRATION, REGIME_SEPARATRIX or REGIME_ROTATION
    ! explicit length (not deferred): see pendula_format on gfortran's static lengths
    character(len=len(code_text(regime, REGIME_CODES, REGIME_NAMES, 'unknown'))) :: name
    name = code_text(regime, REGIME_CODES, REGIME_NAMES, 'unknown')
  end function undamped_regime_name

  ! atan_ratio: the amplitude's atan, the same text as pendula_undamped_many's
  include 'pendula_atan_ratio.inc'

end module pendula_undamped_motion
