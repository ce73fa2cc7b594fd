!> The classic four-stage Runge-Kutta method (Kutta 1901; Hairer, Norsett &
!> Wanner, "Solving ODEs I", table II.1.2) for the nonlinear damped pendulum
!> theta'' + gamma theta' + w0**2 sin(theta) = 0 (text eq. 2.2, section 2.2).
!>
!> This is the scheme the text's section 2.2 listing means to implement, without
!> its line-67 typo (`m2 = m1 * h * k1 / 2.0` for `m2 = m1 + h * k1 / 2.0`).
!> Fixed step: between consecutive output times the interval is cut into the
!> smallest number of equal substeps that are at most h.  Global error O(h**4).
!>
!> Before integrating, the step is compared with RK4's absolute-stability
!> region for the eigenvalues of the problem linearised about theta = 0
!> (text eqs. 2.4-2.18); a step outside it is refused with the largest stable
!> step in the message, instead of returning an exploding solution.
module pendula_rk4
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_short
  use pendula_status, only: status_t, set_error, check_positive, check_nonnegative, check_finite, check_same_size, &
                            PENDULA_OK, &
                            PENDULA_ERR_UNSTABLE, PENDULA_ERR_DOMAIN, PENDULA_ERR_SOLVER, PENDULA_ERR_ORDER, PENDULA_ERR_CANCELLED
  use pendula_control, only: CONTROL_SIZE
  use pendula_ode, only: ode_stats_t, check_problem, linear_eigenvalues
  use pendula_rk4_kernel, only: rk4_grid, substeps
  use pendula_constants, only: pi
  use pendula_drive, only: drive_t, check_drive, check_driven, drive_period, DRIVE_PIVOT, DRIVEN_MIN_STEPS, DRIVEN_MAX_STEPS
  ! the driven block kernel itself (no OpenMP: a program that integrates single
  ! states links no OpenMP runtime), not pendula_driven's batch driver
  use pendula_driven_kernel, only: DRIVEN_LANES, lanes_t, lanes_setup, lanes_steps, lanes_partial, lanes_finite
  use pendula_control, only: cancel_requested, add_progress
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private
  public :: rk4_solve, rk4_final_state, rk4_max_stable_step, rk4_stability_function, RK4_DEFAULT_MAX_STEPS
  public :: check_step   ! the batch driver (pendula_rk4_batch) validates each state's h with it
  ! with a drive: the steps per period, the per-state checks and the grid steps taken (pendula_rk4_batch uses them)
  public :: driven_steps, check_driven_step, driven_step_count

  !> Default step budget of one call: about a minute of CPU at ~25 ns a step.
  !> A window that needs more is refused up front (the caller may raise it
  !> with max_steps); the same budget as the scene solver's RK4.
  integer(i8), parameter :: RK4_DEFAULT_MAX_STEPS = 2000000000_i8

contains

  !> RK4 stability function R(z) = 1 + z + z**2/2 + z**3/6 + z**4/24: one step
  !> multiplies a mode of y' = lambda y by R(h lambda).
  elemental complex(wp) function rk4_stability_function(z) result(r)
    complex(wp), intent(in) :: z  !< h lambda (step times eigenvalue)
    r = 1 + z*(1 + z*(0.5_wp + z*(1.0_wp/6 + z/24)))
  end function rk4_stability_function

  !> Largest step h_max [s] for which RK4 is absolutely stable on the pendulum
  !> linearised about theta = 0: |R(h lambda)| <= 1 for both eigenvalues
  !> lambda = -gamma/2 +- sqrt(gamma**2/4 - w0**2) and every step in (0, h_max].
  !> On the negative real axis this is h |lambda| = 2.7853 (overdamped), on the
  !> imaginary axis h w0 = 2 sqrt(2) (gamma = 0).  Relative accuracy ~1e-14
  !> (bisection along the ray).  w0 > 0 [1/s], gamma >= 0 [1/s], both finite.
  pure subroutine rk4_max_stable_step(w0, gamma, h_max, status)
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], finite, > 0
    real(wp), intent(in) :: gamma  !< damping rate b/m [1/s], finite, >= 0
    real(wp), intent(out) :: h_max  !< largest stable step [s]
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    complex(wp) :: lam1, lam2
    h_max = 0
    call check_positive('w0', w0, status)
    call check_nonnegative('gamma', gamma, status)
    if (status%code /= PENDULA_OK) return
    call linear_eigenvalues(w0, gamma, lam1, lam2)
    ! One ray suffices: complex eigenvalues are conjugate (|R| is symmetric),
    ! real ones share the direction -1 and lam1 has the larger modulus.
    h_max = ray_limit(lam1)
    if (aimag(lam2) == 0 .and. abs(lam2) > abs(lam1)) h_max = ray_limit(lam2)
  end subroutine rk4_max_stable_step

  !> First exit of the ray h -> h lambda from RK4's stability region, as a step.
  !> The region lies inside |z| < 3 (its extent is 2.785 on the real axis and
  !> 2.828 on the imaginary one), so a scan of |z| in (0, 3.5] finds the first
  !> sample outside and bisection refines the crossing.  64 samples agree with
  !> 3500 to 2e-15 over 20001 directions of the left half-plane.
  pure real(wp) function ray_limit(lam) result(h)
    complex(wp), intent(in) :: lam
    integer, parameter :: nscan = 64
    real(wp), parameter :: smax = 3.5_wp
    complex(wp) :: d
    real(wp) :: a, b, m, mod_lam
    integer :: i, it
    mod_lam = abs(lam)
    d = lam/mod_lam
    a = 0
    b = smax
    do i = 1, nscan
      if (.not. inside(d*(smax*i/nscan))) then
        b = smax*i/nscan
        exit
      end if
      a = smax*i/nscan
    end do
    do it = 1, 200
      m = (a + b)/2
      if (m <= a .or. m >= b) exit
      if (inside(d*m)) then
        a = m
      else
        b = m
      end if
    end do
    ! a is a stable |z|; dividing by a tiny |lambda| may overflow: cap at huge.
    if (mod_lam < a/huge(1.0_wp)) then
      h = huge(1.0_wp)
    else
      h = a/mod_lam
    end if
  contains
    pure logical function inside(z)
      complex(wp), intent(in) :: z
      complex(wp) :: r
      r = rk4_stability_function(z)
      ! 4 eps: on the imaginary axis |R|**2 = 1 - y**6/72 + y**8/576 is 1 to
      ! rounding for small y; that is stable, not an exit.
      inside = real(r)**2 + aimag(r)**2 <= 1 + 4*epsilon(1.0_wp)
    end function inside
  end function ray_limit

  !> Validate h against the window t(1)..t(n): positive, not so small that the
  !> run needs more than max_total_steps steps, and stable (see rk4_max_stable_step).
  pure subroutine check_step(t, w0, gamma, h, max_total_steps, status)
    real(wp), intent(in) :: t(:)  !< output times [s] (already checked)
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], finite, > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    real(wp), intent(in) :: h  !< largest step [s], > 0 (the substeps are equal and at most h)
    real(wp), intent(in) :: max_total_steps  !< most steps the run may take
    type(status_t), intent(inout) :: status
    !< the first error of the call is kept: set here only if nothing failed before
    real(wp) :: total, h_used, h_max, dt, hinv
    complex(wp) :: lam1, lam2
    type(status_t) :: st2
    integer :: i
    integer(i8) :: n
    call check_positive('h', h, status)
    if (status%code /= PENDULA_OK) return
    if (size(t) == 1) return
    ! O(1) acceptance of the common case: with t finite and increasing, a
    ! finite span bounds every spacing; the sum of dt/h is span/h; and every
    ! substep is <= h (1 + 1e-9) (substeps), so a stable h settles stability.
    ! Anything else takes the exact per-interval pass below (for its message).
    total = (t(size(t)) - t(1))/h
    if (total <= max_total_steps) then
      call linear_eigenvalues(w0, gamma, lam1, lam2)
      if (h*(1 + 1.0e-9_wp)*max(abs(lam1), abs(lam2)) <= 2.6_wp) return
    end if
    total = 0
    h_used = 0
    hinv = 1/h
    do i = 1, size(t) - 1
      dt = t(i + 1) - t(i)
      if (.not. ieee_is_finite(dt)) then
        call set_error(status, PENDULA_ERR_ORDER, 't spans more than the largest real: '// &
                       'consecutive output times must differ by a finite amount')
        return
      end if
      total = total + dt*hinv   ! a bound only: no need for the division
      if (total > max_total_steps) then
        call set_error(status, PENDULA_ERR_DOMAIN, 'h = '//format_short(h)//' is too small for the window t = '// &
                       format_short(t(1))//' .. '//format_short(t(size(t)))//': RK4 needs more than max_steps = '// &
                       format_short(max_total_steps)//' steps (2e9 ~ 1 min of CPU); use a larger h, a shorter window,'// &
                       ' or raise max_steps')
        return
      end if
      n = substeps(dt, h)
      h_used = max(h_used, dt/real(n, wp))
    end do
    if (size(t) == 1) return
    ! Every ray of the left half-plane leaves RK4's stability region at
    ! |z| >= 2.6156 (minimum near arg z = 122.7 deg; 20001 directions), so
    ! h |lambda| <= 2.6 is stable without the bisection of ray_limit.
    call linear_eigenvalues(w0, gamma, lam1, lam2)
    if (h_used*max(abs(lam1), abs(lam2)) <= 2.6_wp) return
    call rk4_max_stable_step(w0, gamma, h_max, st2)
    if (h_used > h_max) then
      call set_error(status, PENDULA_ERR_UNSTABLE, 'h = '//format_short(h)//' is unstable for RK4 with w0 = '// &
                     format_short(w0)//', gamma = '//format_short(gamma)//' (substep '//format_short(h_used)// &
                     '): h*lambda leaves the stability region for the eigenvalues lambda of the linearisation'// &
                     ' about theta = 0; the largest stable h is '//format_short(h_max)//' (or use CVODE BDF)')
    end if
  end subroutine check_step

  !> Integrate theta'' + gamma theta' + w0**2 sin(theta) = 0 with classic RK4
  !> and return theta(i) [rad], omega(i) [rad/s] at the output times t(i) [s].
  !>
  !> t: strictly increasing, finite, size >= 1; t(1) is the initial time where
  !> (theta0, omega0) holds.  Between t(i) and t(i+1) RK4 takes the fewest
  !> equal substeps of at most h [s] (h > 0).  w0 > 0 and gamma >= 0 [1/s].
  !> theta and omega must have size(t) elements.  stats: steps and rhs_evals
  !> (4 per step).  Errors (status /= OK, outputs zero): bad arguments; a step
  !> outside RK4's stability region (PENDULA_ERR_UNSTABLE, the message gives
  !> the largest stable h); more than max_steps steps (optional, >= 1; default
  !> RK4_DEFAULT_MAX_STEPS = 2e9), refused before any work.  control
  !> (optional, see pendula_control): another thread may set its cancel flag;
  !> it is polled every 4096 steps (~0.1 ms) and the call then returns
  !> PENDULA_ERR_CANCELLED with the outputs zero; progress counts steps.
  !> Global error O(h**4): about 2.5e-6 rad for the text's scenario (b = 0.01,
  !> t <= 30 s, h = 0.05 s).
  !>
  !> drive (optional, pendula_drive): integrate the driven pendulum
  !> theta'' + gamma theta' + w0**2 sin(theta) = F cos(Omega t + phi) (or the
  !> vertically driven pivot) instead.  The steps are then T/N for the fewest
  !> N >= DRIVEN_MIN_STEPS with T/N <= h (T = 2 pi/Omega, N <= DRIVEN_MAX_STEPS),
  !> taken on the grid t(1) + (k + j/N) T of pendula_driven, whose drive phase
  !> comes from integers (no phase is lost over any number of periods); an
  !> output between grid times is one shorter step from the grid.  Checks:
  !> check_driven_step; progress counts the finished state (1).
  subroutine rk4_solve(t, theta0, omega0, w0, gamma, h, theta, omega, stats, status, control, max_steps, drive)
    real(wp), intent(in) :: t(:)
    !< output times [s]: finite, strictly increasing, size >= 1; t(1) is the initial time
    real(wp), intent(in) :: theta0  !< initial angle theta(t(1)) [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity Omega(t(1)) [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], finite, > 0
    real(wp), intent(in) :: gamma  !< damping rate b/m [1/s], finite, >= 0
    real(wp), intent(in) :: h  !< largest step [s], > 0 (the substeps are equal and at most h)
    real(wp), intent(out) :: theta(:)  !< angle theta(t(i)) [rad], size(t) elements
    real(wp), intent(out) :: omega(:)  !< angular velocity Omega(t(i)) [rad/s], size(t) elements
    type(ode_stats_t), intent(out) :: stats  !< steps and rhs_evals (4 per step)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag (polled every 4096 steps) and progress counter in steps (see
    !< pendula_control)
    integer(i8), intent(in), optional :: max_steps
    !< optional step budget, >= 1 (default RK4_DEFAULT_MAX_STEPS)
    type(drive_t), intent(in), optional :: drive  !< optional drive (pendula_drive): the driven pendulum
    integer(i8) :: steps, fast
    integer :: bad
    real(wp) :: budget
    budget = real(RK4_DEFAULT_MAX_STEPS, wp)
    if (present(max_steps)) then
      budget = real(max_steps, wp)
      if (max_steps < 1) call set_error(status, PENDULA_ERR_DOMAIN, 'max_steps = '//format_short(budget)// &
                                        ' is out of range: it must be >= 1')
    end if
    call check_problem(t, theta0, omega0, w0, gamma, status)
    call check_same_size('theta', size(theta), 't', size(t), status)
    call check_same_size('omega', size(omega), 't', size(t), status)
    if (present(drive)) then
      call driven_solve_rk4(t, theta0, omega0, w0, gamma, h, drive, budget, theta, omega, stats, status, control)
      return
    end if
    call check_step(t, w0, gamma, h, budget, status)
    if (status%code /= PENDULA_OK) then
      ! zeroed only here: on success the kernel writes every element
      theta = 0
      omega = 0
      return
    end if
    theta(1) = theta0
    omega(1) = omega0
    call rk4_grid(t, w0*w0, gamma, h, theta, omega, steps, fast, bad, control)
    stats%steps = steps
    stats%rhs_evals = 4*steps
    if (bad < 0) then
      call set_error(status, PENDULA_ERR_CANCELLED, 'RK4 cancelled at t = '//format_short(t(-bad))// &
                     ' (interrupted by the caller)')
      theta = 0
      omega = 0
    else if (bad > 0) then
      call set_error(status, PENDULA_ERR_SOLVER, 'RK4 produced a non-finite state at t = '//format_short(t(bad)))
      theta = 0
      omega = 0
    end if
  end subroutine rk4_solve

  !> Final state only: integrate from (t0, theta0, omega0) to t_end >= t0 [s]
  !> with the fewest equal RK4 steps of at most h and return theta_end [rad],
  !> omega_end [rad/s].  No history is kept: memory is O(1) however long the
  !> run (e.g. 1e5 periods).  Same checks, errors, accuracy, control and
  !> max_steps as rk4_solve.
  !> drive (optional): the driven pendulum, as in rk4_solve.
  subroutine rk4_final_state(t0, t_end, theta0, omega0, w0, gamma, h, theta_end, omega_end, &
                             stats, status, control, max_steps, drive)
    real(wp), intent(in) :: t0  !< initial time [s], finite
    real(wp), intent(in) :: t_end  !< final time [s], >= t0
    real(wp), intent(in) :: theta0  !< initial angle theta(t(1)) [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity Omega(t(1)) [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], finite, > 0
    real(wp), intent(in) :: gamma  !< damping rate b/m [1/s], finite, >= 0
    real(wp), intent(in) :: h  !< largest step [s], > 0 (the substeps are equal and at most h)
    real(wp), intent(out) :: theta_end  !< theta(t_end) [rad]
    real(wp), intent(out) :: omega_end  !< Omega(t_end) [rad/s]
    type(ode_stats_t), intent(out) :: stats  !< steps and rhs_evals (4 per step)
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag (polled every 4096 steps) and progress counter in steps (see
    !< pendula_control)
    integer(i8), intent(in), optional :: max_steps
    !< optional step budget, >= 1 (default RK4_DEFAULT_MAX_STEPS)
    type(drive_t), intent(in), optional :: drive  !< optional drive (pendula_drive): the driven pendulum
    real(wp) :: th(2), om(2)
    theta_end = 0
    omega_end = 0
    call check_finite('t0', t0, status)
    call check_finite('t_end', t_end, status)
    if (status%code /= PENDULA_OK) return
    if (t_end == t0) then
      call check_problem([t0], theta0, omega0, w0, gamma, status)
      call check_positive('h', h, status)
      if (present(drive)) call check_drive(drive, status)
      if (status%code /= PENDULA_OK) return
      theta_end = theta0
      omega_end = omega0
      return
    end if
    if (t_end < t0) then
      call set_error(status, PENDULA_ERR_ORDER, 't_end = '//format_short(t_end)//' must not precede t0 = '//format_short(t0))
      return
    end if
    call rk4_solve([t0, t_end], theta0, omega0, w0, gamma, h, th, om, stats, status, control, max_steps, drive)
    if (status%code /= PENDULA_OK) return
    theta_end = th(2)
    omega_end = om(2)
  end subroutine rk4_final_state

  !> RK4 steps per drive period for the step bound h [s] (> 0): the fewest
  !> N >= DRIVEN_MIN_STEPS with T/N <= h, T = 2 pi/Omega the drive period (a
  !> period that is a multiple of h up to rounding counts as that multiple);
  !> 0 when that needs more than DRIVEN_MAX_STEPS.
  elemental integer function driven_steps(drive, h) result(n)
    type(drive_t), intent(in) :: drive  !< the drive (frequency > 0)
    real(wp), intent(in) :: h  !< largest step [s], > 0
    real(wp) :: r
    n = 0
    r = drive_period(drive)/h
    r = r*(1 - 4*epsilon(r))
    if (.not. r <= DRIVEN_MAX_STEPS) return
    n = max(DRIVEN_MIN_STEPS, ceiling(r))
  end function driven_steps

  !> The checks of one driven state for RK4 (t, theta0, omega0, w0, gamma
  !> already checked by check_problem): h > 0, the drive (check_drive), at
  !> most DRIVEN_MAX_STEPS steps per period, the step T/N small enough for
  !> w0, gamma, the drive and omega0 (h max(sqrt(w0**2 + |a/l| Omega**2),
  !> gamma) <= 1.5 and |omega0| h <= 1.5, as pendula_drive's check_driven),
  !> |theta0| < 1e15 rad, and the window within the step budget (at most
  !> min(max_total_steps, RK4_DEFAULT_MAX_STEPS) grid steps: 2e9, the limit of
  !> pendula_driven's batch driver too).  nsteps: the
  !> steps per period (driven_steps).  A one-point t takes no step: only h,
  !> the drive and theta0 are checked then.
  pure subroutine check_driven_step(t, theta0, omega0, w0, gamma, drive, h, max_total_steps, nsteps, status)
    real(wp), intent(in) :: t(:)  !< output times [s] (already checked)
    real(wp), intent(in) :: theta0  !< initial angle [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    type(drive_t), intent(in) :: drive  !< the drive
    real(wp), intent(in) :: h  !< largest step [s], > 0
    real(wp), intent(in) :: max_total_steps  !< most steps the run may take
    integer, intent(out) :: nsteps  !< RK4 steps per drive period (0 when refused)
    type(status_t), intent(inout) :: status
    !< the first error of the call is kept: set here only if nothing failed before
    type(status_t) :: st
    real(wp) :: rate, hs, grid, cap
    nsteps = 0
    call check_positive('h', h, status)
    call check_drive(drive, status)
    if (status%code /= PENDULA_OK) return
    if (.not. abs(theta0) < 1.0e15_wp) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'theta0 = '//format_short(theta0)// &
                     ' is out of range: with a drive |theta0| must be < 1e15 rad')
      return
    end if
    ! a one-point window takes no step (as without a drive: h is checked against a window)
    if (size(t) == 1) then
      nsteps = max(driven_steps(drive, h), DRIVEN_MIN_STEPS)
      return
    end if
    nsteps = driven_steps(drive, h)
    if (nsteps == 0) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'h = '//format_short(h)//' is too small for the drive period T = '// &
                     format_short(drive_period(drive))//' s: RK4 with a drive takes at most 1e6 steps per period '// &
                     '(h >= T/1e6)')
      return
    end if
    call check_driven(w0, gamma, drive, nsteps, st)
    if (st%code /= PENDULA_OK) then
      rate = w0*w0
      if (drive%kind == DRIVE_PIVOT) rate = rate + abs(drive%amplitude)*drive%frequency**2
      rate = max(sqrt(rate), gamma)
      call set_error(status, st%code, 'h = '//format_short(h)//' is too large for RK4 with this drive (w0 = '// &
                     format_short(w0)//', gamma = '//format_short(gamma)//', step T/N = '// &
                     format_short(drive_period(drive)/nsteps)//' s): the step times max(sqrt(w0**2 + |a/l| Omega**2), '// &
                     'gamma) must be <= 1.5, i.e. h <= '//format_short(1.5_wp/rate))
      nsteps = 0
      return
    end if
    hs = 2*pi/(drive%frequency*nsteps)   ! as pendula_driven_support's check of omega0
    if (.not. abs(omega0)*hs <= 1.5_wp) then
      call set_error(status, PENDULA_ERR_UNSTABLE, 'omega0 = '//format_short(omega0)//' is too fast for h = '// &
                     format_short(h)//' with this drive: |omega0| times the step T/N = '//format_short(hs)// &
                     ' s must be <= 1.5')
      nsteps = 0
      return
    end if
    ! the same expression as pendula_driven's budget check
    grid = (t(size(t)) - t(1))*drive%frequency/(2*pi)*nsteps
    cap = min(max_total_steps, real(RK4_DEFAULT_MAX_STEPS, wp))
    if (.not. grid <= cap) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'h = '//format_short(h)//' is too small for the window t = '// &
                     format_short(t(1))//' .. '//format_short(t(size(t)))//': RK4 with a drive needs more than '// &
                     format_short(cap)//' steps (max_steps, at most 2e9); use a larger h, a shorter window,'// &
                     ' or raise max_steps')
      nsteps = 0
    end if
  end subroutine check_driven_step

  !> RK4 steps a driven state takes over the output times t [s] with nsteps
  !> steps per period of the drive: the grid steps to the last output and
  !> one shorter step for each output between grid times.
  pure integer(i8) function driven_step_count(t, drive, nsteps) result(steps)
    real(wp), intent(in) :: t(:)  !< output times [s]
    type(drive_t), intent(in) :: drive  !< the drive
    integer, intent(in) :: nsteps  !< RK4 steps per drive period
    real(wp) :: hs, r
    integer :: i
    hs = (2*pi/drive%frequency)/nsteps   ! pendula_driven_kernel's step
    steps = 0
    do i = 2, size(t)
      r = (t(i) - t(1))/hs
      if (r - real(int(r, i8), wp) > 0) steps = steps + 1
    end do
    if (size(t) > 1) steps = steps + int((t(size(t)) - t(1))/hs, i8)
  end function driven_step_count

  ! rk4_solve with a drive, the problem and sizes checked (status holds their verdict).
  subroutine driven_solve_rk4(t, theta0, omega0, w0, gamma, h, drive, budget, theta, omega, stats, status, control)
    real(wp), intent(in) :: t(:), theta0, omega0, w0, gamma, h, budget
    type(drive_t), intent(in) :: drive
    real(wp), intent(out) :: theta(:), omega(:)
    type(ode_stats_t), intent(out) :: stats
    type(status_t), intent(inout) :: status
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    integer :: nsteps, bad
    theta = 0
    omega = 0
    call check_driven_step(t, theta0, omega0, w0, gamma, drive, h, budget, nsteps, status)
    if (status%code /= PENDULA_OK) return
    if (size(t) == 1) then
      theta(1) = theta0
      omega(1) = omega0
      return
    end if
    call driven_run(t, theta0, omega0, w0, gamma, drive, nsteps, theta, omega, bad, status, control)
    if (status%code /= PENDULA_OK) return
    if (bad == 0) then
      stats%steps = driven_step_count(t, drive, nsteps)
      stats%rhs_evals = 4*stats%steps
      if (present(control)) call add_progress(control, 1_i8)
      return
    end if
    theta = 0
    omega = 0
    if (bad < 0) then
      call set_error(status, PENDULA_ERR_CANCELLED, 'RK4 cancelled (interrupted by the caller)')
    else
      call set_error(status, PENDULA_ERR_SOLVER, 'RK4 with a drive produced a non-finite state (or |theta| >= 1e15 rad)')
    end if
  end subroutine driven_solve_rk4

  ! One driven state as pendula_driven's run_block runs a block's lane (the
  ! same grid steps and partial steps on the same kernel, whose lanes never
  ! mix: the same bits as driven_batch_solve and rk4_batch_solve).  bad: 0,
  ! 1 (the state became non-finite: checked at each period's end and at the
  ! end) or -1 (cancelled: the flag is polled every 4096 grid steps).
  subroutine driven_run(t, theta0, omega0, w0, gamma, drive, nsteps, theta, omega, bad, status, control)
    real(wp), intent(in) :: t(:), theta0, omega0, w0, gamma
    type(drive_t), intent(in) :: drive
    integer, intent(in) :: nsteps
    real(wp), intent(inout) :: theta(:), omega(:)
    integer, intent(out) :: bad
    type(status_t), intent(inout) :: status
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    integer, parameter :: nl = DRIVEN_LANES
    type(lanes_t) :: b
    real(wp) :: y(nl), u(nl), fr
    logical :: ok(nl)
    integer(i8) :: cnt, mk, work
    integer :: j, nxt, nt, chunk
    bad = 0
    ! the drive phase at t(1), reduced to [0, 2 pi) (pendula_driven_support's params_lanes)
    call lanes_setup(b, drive%kind, nsteps, spread(w0, 1, nl), spread(gamma, 1, nl), spread(drive%amplitude, 1, nl), &
                     spread(drive%frequency, 1, nl), spread(modulo(drive%frequency*t(1) + drive%phase, 2*pi), 1, nl), status)
    if (status%code /= PENDULA_OK) return
    y = theta0
    u = omega0
    nt = size(t)
    nxt = 1
    cnt = 0
    j = 0
    work = 0
    call next_output()
    do
      do while (nxt <= nt .and. mk == cnt)
        call lanes_partial(b, 1, j, fr, y(1), u(1), theta(nxt), omega(nxt))
        nxt = nxt + 1
        call next_output()
      end do
      if (nxt > nt) exit
      chunk = int(min(int(nsteps - j, i8), mk - cnt))
      call lanes_steps(b, j, j + chunk, y, u)
      cnt = cnt + chunk
      j = j + chunk
      if (j == nsteps) then
        j = 0
        ok = lanes_finite(y, u)
        if (.not. ok(1)) then
          bad = 1
          return
        end if
      end if
      work = work + chunk
      if (present(control) .and. work >= 4096) then
        work = 0
        if (cancel_requested(control)) then
          bad = -1
          return
        end if
      end if
    end do
    ok = lanes_finite(y, u)
    if (.not. ok(1)) bad = 1
  contains
    ! grid step count mk and step fraction fr of the next output
    subroutine next_output()
      real(wp) :: r
      if (nxt > nt) return
      r = (t(nxt) - t(1))/b%h(1)
      mk = int(r, i8)
      fr = r - real(mk, wp)
    end subroutine next_output
  end subroutine driven_run

end module pendula_rk4
