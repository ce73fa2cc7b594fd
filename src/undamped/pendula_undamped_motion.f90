!> The undamped pendulum's motion for one initial state: undamped_motion_t,
!> undamped_init and undamped_eval(_many) with the regime/period/energy
!> accessors.  Users `use pendula_undamped` (the facade); the theory is told there.
module pendula_undamped_motion
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf
  use pendula_kinds, only: wp
  use pendula_status, only: status_t, check_finite, check_positive, check_same_size, &
      PENDULA_OK
  use pendula_constants, only: pi, half_pi, half_pi_lo, two_pi, two_pi_lo
  use pendula_double_double, only: two_prod, dd_add_fast, dd_mul
  use pendula_elliptic, only: ellipkm1, ellipfm1, ellipj_plan_t, ellipj_planm1, ellipj_eval, ellipj_eval_array, ellipjm1
  implicit none
  private

  public :: undamped_motion_t, undamped_init, undamped_eval, undamped_eval_many, undamped_theta, undamped_omega, &
            undamped_period, undamped_amplitude, undamped_energy, &
            undamped_regime, pendulum_energy, undamped_regime_name, reduce_angle_2pi
  ! for pendula_undamped_many only (not re-exported by pendula_undamped):
  public :: check_state, set_geometry, set_period, motion_amplitude, period_needed
  public :: REGIME_LIBRATION, REGIME_SEPARATRIX, REGIME_ROTATION, UNDAMPED_PLAN_MIN_TIMES

  !> The pendulum swings about theta = 2 pi N (m < 1).
  integer, parameter :: REGIME_LIBRATION = 1
  !> Exactly the separatrix energy (m = 1): it creeps towards the top forever.
  integer, parameter :: REGIME_SEPARATRIX = 2
  !> It goes over the top and keeps turning (m > 1).
  integer, parameter :: REGIME_ROTATION = 3

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

  !> cos(x) in double-double for x = xh + xl, |x| <= pi/2 (+ rounding), to
  !> ~1e-31 relative: the Taylor series of cos x (|x| <= pi/4) or of
  !> sin(pi/2 - |x|), in powers of y = x^2 up to y^16: the terms j >= 9 (below
  !> 3e-18) by Horner in double, the first nine by Horner in double-double
  !> with the coefficients 1/(2j)! (1/(2j+1)!) as double-double constants
  !> (mpmath; 1/n! = hi + lo), so no division.
  elemental subroutine cos_dd(xh, xl, ch, cl)
    real(wp), intent(in) :: xh, xl
    real(wp), intent(out) :: ch, cl
    integer :: j
    real(wp), parameter :: cos_hi(0:8) = [1.0_wp, 0.5_wp, 0.041666666666666664_wp, 0.001388888888888889_wp, &
        2.48015873015873e-05_wp, 2.755731922398589e-07_wp, 2.08767569878681e-09_wp, 1.1470745597729725e-11_wp, &
        4.779477332387385e-14_wp]
    real(wp), parameter :: cos_lo(0:8) = [0.0_wp, 0.0_wp, 2.3129646346357427e-18_wp, -5.300543954373577e-20_wp, &
        2.1511947866775882e-23_wp, 2.3767714622250297e-23_wp, -1.20734505911326e-25_wp, 2.0655512752830745e-28_wp, &
        4.399205485834081e-31_wp]
    real(wp), parameter :: sin_hi(0:8) = [1.0_wp, 0.16666666666666666_wp, 0.008333333333333333_wp, &
        0.0001984126984126984_wp, 2.7557319223985893e-06_wp, 2.505210838544172e-08_wp, &
        1.6059043836821613e-10_wp, 7.647163731819816e-13_wp, 2.8114572543455206e-15_wp]
    real(wp), parameter :: sin_lo(0:8) = [0.0_wp, 9.25185853854297e-18_wp, 1.1564823173178714e-19_wp, &
        1.7209558293420705e-22_wp, -1.858393274046472e-22_wp, -1.448814070935912e-24_wp, &
        1.2585294588752098e-26_wp, 7.03872877733453e-30_wp, 1.6508842730861433e-31_wp]
    ! (-1)^j/(2j)! and (-1)^j/(2j+1)!, j = 9..16, in double (mpmath; their rounding is ~1e-31 of cos)
    real(wp), parameter :: cos_tail(9:16) = [-1.5619206968586225e-16_wp, &
        4.110317623312165e-19_wp, -8.896791392450574e-22_wp, 1.6117375710961184e-24_wp, &
        -2.4795962632247976e-27_wp, 3.279889237069838e-30_wp, -3.7699876288159054e-33_wp, 3.8003907548547434e-36_wp]
    real(wp), parameter :: sin_tail(9:16) = [-8.22063524662433e-18_wp, &
        1.9572941063391263e-20_wp, -3.868170170630684e-23_wp, 6.446950284384474e-26_wp, &
        -9.183689863795546e-29_wp, 1.1309962886447716e-31_wp, -1.216125041553518e-34_wp, 1.151633562077195e-37_wp]
    real(wp) :: yh, yl, y2h, y2l, th, tl, uh, ul, sgn
    logical :: use_sin
    use_sin = abs(xh) > 0.25_wp * pi
    if (use_sin) then
      call dd_add_fast(half_pi, half_pi_lo, -abs(xh), -sign(1.0_wp, xh) * xl, yh, yl)
    else
      yh = xh
      yl = xl
    end if
    call dd_mul(yh, yl, yh, yl, y2h, y2l)
    th = 0
    do j = 16, 9, -1
      if (use_sin) then
        th = sin_tail(j) + y2h * th
      else
        th = cos_tail(j) + y2h * th
      end if
    end do
    tl = 0
    do j = 8, 0, -1
      ! t <- (-1)^j c_j + y^2 t
      call dd_mul(y2h, y2l, th, tl, uh, ul)
      sgn = 1 - 2 * modulo(j, 2)
      if (use_sin) then
        call dd_add_fast(sgn * sin_hi(j), sgn * sin_lo(j), uh, ul, th, tl)
      else
        call dd_add_fast(sgn * cos_hi(j), sgn * cos_lo(j), uh, ul, th, tl)
      end if
    end do
    if (use_sin) then
      call dd_mul(yh, yl, th, tl, ch, cl)
    else
      ch = th
      cl = tl
    end if
  end subroutine cos_dd

  !> Reduce an angle x [rad] about the nearest stable equilibrium 2 pi n:
  !> x = 2 pi n + (r_hi + r_lo) with |r_hi| <= pi, 2 pi carried in two doubles
  !> (error ~2^-100 |2 pi n|) for |x| <= 2^40; beyond, r_hi = atan2(sin x, cos x)
  !> (libm's exact reduction, ~1 ulp of pi) and r_lo = 0.  Returns n as a real.
  elemental subroutine reduce_angle_2pi(x, n, r_hi, r_lo)
    real(wp), intent(in) :: x
    real(wp), intent(out) :: n, r_hi, r_lo
    real(wp) :: p, e, d, t
    if (abs(x) < pi) then
      ! already reduced (what the general path below returns for these x)
      n = 0
      r_hi = x
      r_lo = 0
      return
    end if
    if (abs(x) > 2.0_wp**40) then
      ! beyond |n| ~ 2^37 the two-double 2 pi is not enough: let libm's exact
      ! (Payne-Hanek) reduction inside sin and cos do it; |r| to ~1 ulp of pi
      r_hi = atan2(sin(x), cos(x))
      r_lo = 0
      n = anint((x - r_hi) / two_pi)
      return
    end if
    n = anint(x / two_pi)
    if (n == 0) then
      r_hi = x
      r_lo = 0
      return
    end if
    call two_prod(n, two_pi, p, e)
    d = x - p                      ! exact (Sterbenz: x/p in [1/2, 2] for n /= 0)
    t = -(e + n * two_pi_lo)
    r_hi = d + t
    r_lo = t - (r_hi - d)           ! fast two-sum (|d| >= |t|)
    ! anint may leave |r| marginally above pi; that is harmless (reduction is
    ! only about the nearest equilibrium) but keep the contract |r_hi| <= pi.
    if (abs(r_hi) > pi) then
      n = n + sign(1.0_wp, r_hi)
      call reduce_angle_fixed(x, n, r_hi, r_lo)
    end if
  end subroutine reduce_angle_2pi

  elemental subroutine reduce_angle_fixed(x, n, r_hi, r_lo)
    real(wp), intent(in) :: x, n
    real(wp), intent(out) :: r_hi, r_lo
    real(wp) :: p, e, d, t
    call two_prod(n, two_pi, p, e)
    d = x - p
    t = -(e + n * two_pi_lo)
    r_hi = d + t
    r_lo = t - (r_hi - d)
  end subroutine reduce_angle_fixed

  !> Build the motion for the initial state theta0 [rad], Omega0 [rad/s] and
  !> w0 = sqrt(g/l) [1/s]: theta0, Omega0 finite, w0 finite and > 0 (otherwise
  !> status names the argument and `motion` is the resting pendulum).
  !> Cost: one K, one F and one Jacobi plan (~ a few hundred ns).
  pure subroutine undamped_init(motion, theta0, omega0, w0, status, plan, w0lo)
    type(undamped_motion_t), intent(out) :: motion
    real(wp), intent(in) :: theta0, omega0, w0
    type(status_t), intent(out) :: status
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
      motion%period = 2 * pi
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
      motion%phase = ellipfm1(motion%s * motion%h, motion%pmc) + motion%s * motion%hlo * motion%k / abs(motion%q)
    end select
    if (motion%regime /= REGIME_SEPARATRIX .and. want_plan) then
      motion%plan = ellipj_planm1(motion%pmc)
      motion%planned = .true.
    end if
  end subroutine undamped_init

  !> The checks of undamped_init: theta0, Omega0 finite, w0 finite and > 0.
  pure subroutine check_state(theta0, omega0, w0, status)
    real(wp), intent(in) :: theta0, omega0, w0
    type(status_t), intent(out) :: status
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
    type(undamped_motion_t), intent(out) :: motion
    real(wp), intent(in) :: theta0, omega0, w0
    real(wp), intent(in), optional :: w0lo   ! see undamped_init
    real(wp) :: n, r_hi, r_lo, h, hlo, sh, ch, chlo, sh0, ch0, q, qlo, p, e, w2, d, dlo, a

    motion%theta0 = theta0
    motion%omega0 = omega0
    motion%w0 = w0
    call reduce_angle_2pi(theta0, n, r_hi, r_lo)
    if (abs(theta0) > 2.0_wp**40) then
      motion%center = theta0 - r_hi           ! 2 pi n to the rounding of theta0
    else if (n /= 0) then
      call two_prod(n, two_pi, p, e)
      motion%center = p + (e + n * two_pi_lo)   ! the double nearest 2 pi n
    end if
    motion%theta_r = r_hi
    h = 0.5_wp * r_hi
    hlo = 0.5_wp * r_lo
    motion%h = h
    motion%hlo = hlo
    sh0 = sin(h)
    ch0 = cos(h)
    sh = sh0 + ch0 * hlo            ! sin(theta_r/2), first-order correction for r_lo
    ! q = Omega0/(2 w0) with its rounding error qlo (exact residual by two_prod)
    w2 = omega0 / w0                  ! Omega0/w0, halved below (exact); no 2 w0 overflow
    q = 0.5_wp * w2
    motion%sh = sh
    motion%q = q
    if (abs(q) > 1.0e150_wp) then
      ! m = q^2 would overflow; the pull of gravity is below 1e-300 of the
      ! motion, so the free rotor theta0 + Omega0 t is exact in double.
      motion%ch = ch0 - sh0 * hlo
      motion%regime = REGIME_ROTATION
      motion%free = .true.
      motion%s = sign(1.0_wp, q)
      motion%k = abs(q)
      motion%m = ieee_value(1.0_wp, ieee_positive_inf)
      motion%mc = -motion%m
      motion%rate = abs(omega0)
      motion%energy = 0.5_wp * omega0 * omega0
      return
    end if
    if (abs(q) >= 0.5_wp * ch0 .and. abs(q) <= 2 * ch0) then
      ! cos(theta_r/2) in double-double: the separatrix distance 1 - m below
      ! cancels it against |q|, and over 100 periods its error is multiplied by
      ! ~t/(T (1-m) K); a double-double c keeps 1 - m relatively exact.
      call cos_dd(h, hlo, ch, chlo)
    else
      ! c - |q| loses at most one bit: libm's cos (< 1 ulp) keeps 1 - m to a
      ! few ulps, at a twentieth of the cost of cos_dd
      ch = ch0 - sh0 * hlo
      chlo = 0
    end if
    motion%ch = ch
    qlo = 0
    if (w2 /= 0 .and. max(abs(w2), w0) < 1.0e290_wp) then   ! the Veltkamp split would overflow beyond
      call two_prod(w2, w0, p, e)
      qlo = 0.5_wp * (((omega0 - p) - e) / w0)
    end if
    ! Omega0/(2 (w0 + w0lo)) = q (1 - w0lo/w0) + O(eps^2 q)
    if (present(w0lo)) qlo = qlo - q * (w0lo / w0)
    motion%m = sh * sh + q * q
    motion%k = sqrt(motion%m)
    ! 1 - m = cos^2 - q^2 = (c - |q|)(c + |q|), c - |q| in double-double
    a = ch + abs(q)
    if (chlo == 0 .and. qlo == 0) then
      motion%mc = (ch - abs(q)) * a             ! what the double-double sum gives then
    else
      call dd_add_fast(ch, chlo, -abs(q), -sign(1.0_wp, q) * qlo, d, dlo)
      motion%mc = (d + dlo) * a
    end if
    motion%energy = 2 * (w0 * motion%k)**2

    if (motion%mc > 0) then
      motion%regime = REGIME_LIBRATION
      motion%rate = w0
      motion%pmc = motion%mc
    else if (motion%mc < 0) then
      motion%regime = REGIME_ROTATION
      motion%s = sign(1.0_wp, q)
      motion%rate = motion%k * w0
      motion%pmc = -motion%mc / motion%m      ! complement of the parameter 1/m
      motion%dnb = abs(q) / motion%k
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
        motion%phase = asinh(tan(motion%s * h)) + motion%s * hlo / ch
      end if
    end if
  end subroutine set_geometry

  !> K of the parameter in use and the period (set_geometry first): 4 K(m)/w0,
  !> 2 K(1/m)/(k w0) per turn, 2 pi/|Omega0| for the free rotor, +inf on the separatrix.
  elemental subroutine set_period(motion)
    type(undamped_motion_t), intent(inout) :: motion
    if (motion%free) then
      motion%period = 2 * pi / abs(motion%omega0)
      return
    end if
    select case (motion%regime)
    case (REGIME_LIBRATION)
      motion%kk = ellipkm1(motion%mc)
      motion%period = 4 * motion%kk / motion%w0
    case (REGIME_ROTATION)
      motion%kk = ellipkm1(motion%pmc)
      motion%period = 2 * motion%kk / motion%rate
    case default
      motion%period = ieee_value(1.0_wp, ieee_positive_inf)
      motion%kk = ieee_value(1.0_wp, ieee_positive_inf)
    end select
  end subroutine set_period

  !> Amplitude [rad] of a motion with its geometry set (see undamped_amplitude).
  elemental real(wp) function motion_amplitude(motion) result(amplitude)
    type(undamped_motion_t), intent(in) :: motion
    select case (motion%regime)
    case (REGIME_LIBRATION)
      amplitude = 2 * atan2(motion%k, sqrt(motion%mc))
    case (REGIME_SEPARATRIX)
      amplitude = pi
    case default
      amplitude = ieee_value(1.0_wp, ieee_positive_inf)
    end select
  end function motion_amplitude

  !> Whether undamped_eval at t takes whole periods out (and so needs the period).
  elemental logical function period_needed(motion, t) result(needed)
    type(undamped_motion_t), intent(in) :: motion
    real(wp), intent(in) :: t
    needed = .not. motion%free .and. motion%regime /= REGIME_SEPARATRIX &
        .and. exponent(t) > 40 - exponent(motion%rate)
  end function period_needed

  !> theta(t) [rad] and Omega(t) [rad/s] of the motion at any real time t [s]
  !> (negative, unsorted, arrays: elemental).  theta is continuous with theta0
  !> (rotation keeps counting turns).  Accuracy: a few eps times the condition
  !> number sum |x d theta/dx| over x in {theta0, Omega0, w0, t} (tested to
  !> 16 eps cond over 100 periods against mpmath).  Non-finite t gives NaN;
  !> use `undamped_solve` for a checked call.
  !>
  !> The phase u0 (or v0) is never added to w0 t: the Jacobi functions are taken
  !> at a = w0 t alone and combined with sn, cn, dn at the phase, which the
  !> initial state gives exactly (sin, cos of theta_r/2 and Omega0/(2 w0)), by
  !> the addition theorem (DLMF 22.8.1-3, denominator 1 - m sn^2 a sn^2 b written
  !> as cn^2 a + sn^2 a dn^2 b).  So u0 ~ K (large near the separatrix) costs no
  !> eps*K of the argument, and t = 0 returns the initial state to ~1 ulp.
  elemental subroutine undamped_eval(motion, t, theta, omega)
    type(undamped_motion_t), intent(in) :: motion
    real(wp), intent(in) :: t
    real(wp), intent(out) :: theta, omega
    real(wp) :: a, sa, ca, da, ama, y, x, z, den, sb, ss, cc, delta, ex, tt, turns
    tt = t
    turns = 0
    if (motion%free) then
      theta = motion%theta0 + motion%omega0 * t
      omega = motion%omega0
      return
    end if
    if (motion%regime == REGIME_SEPARATRIX) then
      ! |w0 t| ~> 1e301 would overflow; theta is pi to the last bit long before
      if (exponent(t) > 1000 - exponent(motion%rate)) tt = sign(1.0e300_wp, t) / motion%rate
    else if (period_needed(motion, t)) then
      ! |rate t| >~ 5e11: take whole periods out first (modulo is exact; the
      ! period's rounding moves t by ~eps |t|, inside the condition number).
      ! This also kept clear of an ellipj_eval bug of 03:12 UTC (|sn| > 1 from
      ! u ~ 1e17, a crash near 1e25-1e30), fixed in pendula_elliptic 495978f;
      ! it stays because it is exact and keeps rate t finite up to 1e308.
      tt = modulo(t, motion%period)
      turns = anint((t - tt) / motion%period)
    end if
    select case (motion%regime)
    case (REGIME_LIBRATION)
      a = motion%rate * tt
      if (motion%planned) then
        call ellipj_eval(motion%plan, a, sa, ca, da)
      else
        call ellipjm1(a, motion%pmc, sa, ca, da)
      end if
      ! k sn(a+b), dn(a+b), k cn(a+b), each times the denominator, with
      ! k sn b = sh, dn b = ch, k cn b = q.  cos(theta/2) = dn keeps theta
      ! accurate near the turning points (2 asin(k sn), eq. 1.52, does not).
      y = sa * motion%q * motion%ch + motion%sh * ca * da
      x = da * motion%ch - sa * ca * motion%sh * motion%q
      z = ca * motion%q - sa * motion%sh * da * motion%ch
      den = ca * ca + (sa * motion%ch)**2
      ! x = dn(a+b) D > 0 in exact arithmetic; atan(y/x) is cheaper than atan2
      ! (~1/4 of the evaluation time) and as accurate.  Rounding can make x <= 0
      ! only when 1 - m < eps^2 near a turning point: keep atan2 there.
      if (x > 0) then
        theta = motion%center + 2 * atan(y / x)
      else
        theta = motion%center + 2 * atan2(y, x)
      end if
      omega = 2 * (motion%w0 * (z / den))   ! w0 first: no spurious overflow
    case (REGIME_ROTATION)
      a = motion%rate * tt
      if (motion%planned) then
        call ellipj_eval(motion%plan, a, sa, ca, da, ama)
      else
        call ellipjm1(a, motion%pmc, sa, ca, da, ama)
      end if
      ! sn(a+b), cn(a+b) times the denominator, at parameter 1/m, with
      ! sn b = s sh, cn b = ch, dn b = dnb; then am(a+b) = am(a) + delta where
      ! delta = int_a^{a+b} dn lies in (0, pi) for b > 0 (|b| <= K), so the
      ! branch of the atan2 is fixed by the sign of b.
      sb = motion%s * motion%sh
      ss = sa * motion%ch * motion%dnb + sb * ca * da
      cc = ca * motion%ch - sa * sb * da * motion%dnb
      delta = atan2(ss * ca - cc * sa, cc * ca + ss * sa)
      if (sb > 0 .and. delta < -half_pi) delta = delta + 2 * pi
      if (sb < 0 .and. delta > half_pi) delta = delta - 2 * pi
      theta = motion%center + 2 * motion%s * (ama + delta)
      if (turns /= 0) theta = theta + motion%s * (2 * pi) * turns
      den = ca * ca + (sa * motion%dnb)**2
      omega = 2 * (motion%s * motion%rate * ((da * motion%dnb - sa * sb * ca * motion%ch / motion%m) / den))
    case default
      if (motion%s == 0) then
        theta = motion%center + motion%theta_r
        omega = 0
        return
      end if
      x = motion%w0 * tt + motion%phase
      ! gd(x) = 2 atan(tanh(x/2)), sech(x) = 2 e^-|x| / (1 + e^-2|x|): no overflow
      ex = exp(-abs(x))
      theta = motion%center + motion%s * 4 * atan(tanh(0.5_wp * x))
      omega = 2 * (motion%s * motion%w0 * (2 * ex / (1 + ex * ex)))
    end select
  end subroutine undamped_eval

  !> Same as `undamped_eval` for an array of times (results agree to a few
  !> ulps), organised for speed: blocks of times go through the Jacobi
  !> functions, the addition theorem and a vectorisable atan/atan2 loop
  !> (libmvec), which halves the cost per point.  theta and omega must have the
  !> size of t (status PENDULA_ERR_SIZE otherwise, outputs untouched); times are
  !> not checked for finiteness here (`undamped_solve` does that).
  pure subroutine undamped_eval_many(motion, t, theta, omega, status)
    type(undamped_motion_t), intent(in) :: motion
    real(wp), intent(in) :: t(:)
    real(wp), intent(inout) :: theta(:), omega(:)
    type(status_t), intent(out) :: status
    integer, parameter :: nb = 256
    real(wp) :: a(nb), sa(nb), ca(nb), da(nb), ama(nb), y(nb), x(nb), r(nb), sb
    integer :: i0, i1, nc, i, j
    call check_same_size('theta', size(theta), 't', size(t), status)
    call check_same_size('omega', size(omega), 't', size(t), status)
    if (status%code /= PENDULA_OK) return
    if (motion%free .or. (motion%regime /= REGIME_LIBRATION .and. motion%regime /= REGIME_ROTATION)) then
      call undamped_eval(motion, t, theta(1:size(t)), omega(1:size(t)))
      return
    end if
    sb = motion%s * motion%sh
    do i0 = 1, size(t), nb
      nc = min(nb, size(t) - i0 + 1)
      i1 = i0 + nc - 1
      if (any(period_needed(motion, t(i0:i1)))) then
        ! huge times need the period reduction of the scalar path
        call undamped_eval(motion, t(i0:i1), theta(i0:i1), omega(i0:i1))
        cycle
      end if
      a(1:nc) = motion%rate * t(i0:i1)
      if (motion%regime == REGIME_LIBRATION) then
        if (motion%planned) then
          call ellipj_eval_array(motion%plan, a(1:nc), sa(1:nc), ca(1:nc), da(1:nc), status)
        else
          call ellipjm1(a(1:nc), motion%pmc, sa(1:nc), ca(1:nc), da(1:nc))
        end if
        do i = 1, nc
          j = i0 + i - 1
          y(i) = sa(i) * motion%q * motion%ch + motion%sh * ca(i) * da(i)
          x(i) = da(i) * motion%ch - sa(i) * ca(i) * motion%sh * motion%q
          omega(j) = 2 * (motion%w0 * ((ca(i) * motion%q - sa(i) * motion%sh * da(i) * motion%ch) &
              / (ca(i) * ca(i) + (sa(i) * motion%ch)**2)))
          r(i) = y(i) / x(i)
        end do
        do i = 1, nc
          theta(i0 + i - 1) = motion%center + 2 * atan(r(i))
        end do
        do i = 1, nc
          if (.not. x(i) > 0) theta(i0 + i - 1) = motion%center + 2 * atan2(y(i), x(i))
        end do
      else
        if (motion%planned) then
          call ellipj_eval_array(motion%plan, a(1:nc), sa(1:nc), ca(1:nc), da(1:nc), status, ama(1:nc))
        else
          call ellipjm1(a(1:nc), motion%pmc, sa(1:nc), ca(1:nc), da(1:nc), ama(1:nc))
        end if
        do i = 1, nc
          j = i0 + i - 1
          ! ss, cc as in undamped_eval, kept in y, x; r <- the denominator
          y(i) = sa(i) * motion%ch * motion%dnb + sb * ca(i) * da(i)
          x(i) = ca(i) * motion%ch - sa(i) * sb * da(i) * motion%dnb
          r(i) = ca(i) * ca(i) + (sa(i) * motion%dnb)**2
          omega(j) = 2 * (motion%s * motion%rate * ((da(i) * motion%dnb - sa(i) * sb * ca(i) * motion%ch &
              / motion%m) / r(i)))
          r(i) = y(i) * ca(i) - x(i) * sa(i)
          x(i) = x(i) * ca(i) + y(i) * sa(i)
        end do
        do i = 1, nc
          y(i) = atan2(r(i), x(i))
        end do
        do i = 1, nc
          if (sb > 0 .and. y(i) < -half_pi) y(i) = y(i) + 2 * pi
          if (sb < 0 .and. y(i) > half_pi) y(i) = y(i) - 2 * pi
          theta(i0 + i - 1) = motion%center + 2 * motion%s * (ama(i) + y(i))
        end do
      end if
    end do
  end subroutine undamped_eval_many

  !> theta(t) [rad] alone (see undamped_eval).
  elemental real(wp) function undamped_theta(motion, t) result(theta)
    type(undamped_motion_t), intent(in) :: motion
    real(wp), intent(in) :: t
    real(wp) :: omega
    call undamped_eval(motion, t, theta, omega)
  end function undamped_theta

  !> Omega(t) [rad/s] alone (see undamped_eval).
  elemental real(wp) function undamped_omega(motion, t) result(omega)
    type(undamped_motion_t), intent(in) :: motion
    real(wp), intent(in) :: t
    real(wp) :: theta
    call undamped_eval(motion, t, theta, omega)
  end function undamped_omega


  !> Period [s]: 4 K(m)/w0 for libration (eq. 1.53 generalised to any state),
  !> the time of one full turn 2 K(1/m)/(k w0) for rotation (the period of
  !> Omega), +inf on the separatrix.
  elemental real(wp) function undamped_period(motion) result(period)
    type(undamped_motion_t), intent(in) :: motion
    period = motion%period
  end function undamped_period

  !> Amplitude [rad]: max |theta - 2 pi N| = 2 asin(k) for libration (computed
  !> as 2 atan2(k, sqrt(1-m)), accurate up to the separatrix), pi on the
  !> separatrix (approached, never reached), +inf for rotation.
  elemental real(wp) function undamped_amplitude(motion) result(amplitude)
    type(undamped_motion_t), intent(in) :: motion
    amplitude = motion%amplitude
  end function undamped_amplitude

  !> Energy per unit m l^2 [1/s^2]: Omega^2/2 + w0^2 (1 - cos theta) = 2 w0^2 m
  !> (zero at the bottom, 2 w0^2 on the separatrix); constant along the motion.
  elemental real(wp) function undamped_energy(motion) result(energy)
    type(undamped_motion_t), intent(in) :: motion
    energy = motion%energy
  end function undamped_energy

  !> Regime code: REGIME_LIBRATION, REGIME_SEPARATRIX or REGIME_ROTATION.
  elemental integer function undamped_regime(motion) result(regime)
    type(undamped_motion_t), intent(in) :: motion
    regime = motion%regime
  end function undamped_regime

  !> Energy of a state per unit m l^2 [1/s^2]: Omega^2/2 + 2 w0^2 sin^2(theta/2)
  !> (= Omega^2/2 + w0^2 (1 - cos theta), eq. 1.2, without the cancellation of
  !> 1 - cos near theta = 0).  Relative accuracy a few eps.
  elemental real(wp) function pendulum_energy(theta, omega, w0) result(energy)
    real(wp), intent(in) :: theta, omega, w0
    real(wp) :: sh
    sh = sin(0.5_wp * theta)
    energy = 0.5_wp * omega * omega + 2 * (w0 * sh) * (w0 * sh)
  end function pendulum_energy

  !> 'libration', 'separatrix' or 'rotation' for a regime code ('unknown' otherwise).
  pure function undamped_regime_name(regime) result(name)
    integer, intent(in) :: regime
    character(len=:), allocatable :: name
    select case (regime)
    case (REGIME_LIBRATION);  name = 'libration'
    case (REGIME_SEPARATRIX); name = 'separatrix'
    case (REGIME_ROTATION);   name = 'rotation'
    case default;             name = 'unknown'
    end select
  end function undamped_regime_name

end module pendula_undamped_motion
