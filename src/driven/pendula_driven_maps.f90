!> Stroboscopic tools of the driven pendulum, every one a batch (many states
!> or parameter values per call, blocks of lanes on OpenMP threads):
!>
!> - driven_poincare: Poincare (stroboscopic) sections at a chosen drive
!>   phase after a transient, and the mean angular velocity (rotation number
!>   times Omega) over the recorded periods;
!> - driven_bifurcation: sections over an array of values of one parameter;
!> - driven_lyapunov: both Lyapunov exponents from the variational equations,
!>   re-orthonormalised (Gram-Schmidt) every drive period (Benettin, Galgani,
!>   Giorgilli & Strelcyn, Meccanica 15 (1980) 9), averaged over an ensemble
!>   of copies in the SIMD lanes, with a 95 % error bound from block means.
!>
!> Sections are taken on the RK4 grid (pendula_driven_kernel): the section
!> phase is rounded to the nearest of the N grid phases of a period.
module pendula_driven_maps
  use, intrinsic :: iso_fortran_env, only: int64
  use pendula_kinds, only: wp, i8
  use pendula_constants, only: pi
  use pendula_format, only: format_int
  use pendula_status, only: status_t, set_error, check_alloc, check_finite, check_same_size, PENDULA_OK, PENDULA_ERR_DOMAIN, &
                            PENDULA_ERR_SOLVER, PENDULA_ERR_CANCELLED
  use pendula_control, only: CONTROL_SIZE, cancel_requested, add_progress
  use pendula_batch_support, only: batch_threads, failed_output, nan_failed
  use pendula_driven_kernel, only: DRIVEN_LANES, lanes_t, lanes_steps, lanes_steps_tangent, lanes_finite
  use pendula_driven_support, only: driven_params_t, params_check, params_prepare, block_open, &
                                    params_summary, wrap_angle, pick
  implicit none
  private
  public :: driven_poincare, driven_bifurcation, driven_lyapunov, LYAPUNOV_BLOCKS, LYAPUNOV_ORBITS, LYAPUNOV_PARTED, &
            LYAPUNOV_SPREAD, LYAPUNOV_DEFAULT_STEPS, LYAPUNOV_DEFAULT_PERIODS, &
            PARAM_AMPLITUDE, PARAM_FREQUENCY, PARAM_PHASE, PARAM_GAMMA, PARAM_W0

  integer, parameter :: nl = DRIVEN_LANES
  !> Blocks of the measured periods whose means give the Lyapunov error estimate.
  integer, parameter :: LYAPUNOV_BLOCKS = 16
  !> Distance [rad] in (theta mod 2 pi, omega/Omega) beyond which the copies of a Lyapunov
  !> ensemble count as parted (independent samples of the attractor).
  real(wp), parameter :: LYAPUNOV_PARTED = 0.01_wp
  !> Copies of each state in a Lyapunov ensemble by default: the SIMD lanes of a block, which cost no more than one.
  integer, parameter :: LYAPUNOV_ORBITS = DRIVEN_LANES
  !> Start offset in theta [rad] between the copies of a Lyapunov ensemble.
  real(wp), parameter :: LYAPUNOV_SPREAD = 1.0e-6_wp
  !> RK4 steps per drive period of a Lyapunov run by default: its bias on the Baker-Gollub exponent is
  !> well below the error bound of the default run (benchmarks/bench_driven.py measures it by step halving).
  integer, parameter :: LYAPUNOV_DEFAULT_STEPS = 64
  !> Drive periods each copy measures by default (the Python and command-line default): with
  !> LYAPUNOV_ORBITS copies, the Baker-Gollub exponent to +-0.0005 1/s (95 %).
  integer, parameter :: LYAPUNOV_DEFAULT_PERIODS = 50000
  !> Parameter codes of driven_bifurcation.
  integer, parameter :: PARAM_AMPLITUDE = 1, PARAM_FREQUENCY = 2, PARAM_PHASE = 3, PARAM_GAMMA = 4, PARAM_W0 = 5

contains

  !> Poincare sections of n = size(theta0) driven pendulums (parameters as
  !> pendula_driven's driven_batch_solve, started at t = 0): after
  !> `transient` whole drive periods, the states at the nrec drive phases
  !> Omega t + phi = section_phase (mod 2 pi, rounded to the RK4 grid) that
  !> follow: theta_s(k, i) wrapped to (-pi, pi] [rad], omega_s(k, i) [rad/s].
  !> mean_omega(i): the mean angular velocity over the nrec periods from the
  !> first recorded point [rad/s] (mean_omega/Omega is the rotation number:
  !> turns per drive period).  codes, status, threads, control (progress =
  !> finished states) and first_failed as driven_batch_solve; a failed
  !> state's outputs are NaN (every output of a refused call too).
  subroutine driven_poincare(theta0, omega0, w0, gamma, kind, amp, freq, phase, nsteps, section_phase, &
                             transient, nrec, theta_s, omega_s, mean_omega, codes, status, threads, control, first_failed)
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad] at t = 0, n = size(theta0)
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], n or 1
    real(wp), intent(in) :: w0(:)  !< small-angle angular frequencies [1/s], > 0, n or 1
    real(wp), intent(in) :: gamma(:)  !< damping rates [1/s], >= 0, n or 1
    integer, intent(in) :: kind  !< DRIVE_TORQUE or DRIVE_PIVOT
    real(wp), intent(in) :: amp(:)  !< drive amplitudes (F in rad/s**2, or a/l), n or 1
    real(wp), intent(in) :: freq(:)  !< drive frequencies Omega [rad/s], > 0, n or 1
    real(wp), intent(in) :: phase(:)  !< drive phases phi [rad], n or 1
    integer, intent(in) :: nsteps  !< RK4 steps per drive period
    real(wp), intent(in) :: section_phase  !< drive phase of the section [rad], finite
    integer, intent(in) :: transient  !< drive periods discarded first, >= 0
    integer, intent(in) :: nrec  !< section points recorded per state, >= 1
    real(wp), intent(out) :: theta_s(:, :)  !< section angles in (-pi, pi] [rad], shape (nrec, n)
    real(wp), intent(out) :: omega_s(:, :)  !< section angular velocities [rad/s], shape (nrec, n)
    real(wp), intent(out) :: mean_omega(:)  !< mean angular velocity over the recorded periods [rad/s], n
    integer, intent(out) :: codes(:)  !< status code of each state, n
    type(status_t), intent(out) :: status  !< error code and message (PENDULA_OK on success)
    integer, intent(in), optional :: threads  !< OpenMP threads (0 or absent: the OpenMP default)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag and progress counter (finished states)
    integer, intent(out), optional :: first_failed  !< first failed state (0: none)
    type(driven_params_t) :: p
    integer, allocatable :: live(:)
    integer :: nlive, nblocks, b, first_bad, nth
    character(len=len(status%message)) :: msg
    if (present(first_failed)) first_failed = 0
    theta_s = 0
    omega_s = 0
    mean_omega = 0
    call params_check(kind, nsteps, theta0, omega0, w0, gamma, amp, freq, phase, threads, p, status)
    call check_finite('section_phase', section_phase, status)
    call check_counts(transient, nrec, 1, 'nrec', status)
    call check_same_size('codes', size(codes), 'theta0', size(theta0), status)
    call check_same_size('mean_omega', size(mean_omega), 'theta0', size(theta0), status)
    call check_same_size('theta_s', size(theta_s), 'nrec * size(theta0)', nrec*size(theta0), status)
    call check_same_size('omega_s', size(omega_s), 'nrec * size(theta0)', nrec*size(theta0), status)
    if (status%code /= PENDULA_OK) then
      codes = status%code
      theta_s = failed_output()
      omega_s = failed_output()
      mean_omega = failed_output()
      return
    end if
    nth = batch_threads(threads)
    call params_prepare(p, codes, live, nlive, first_bad, msg)
    nblocks = (nlive + nl - 1)/nl
    !$omp parallel do schedule(dynamic) num_threads(nth) if(nth > 1 .and. nblocks > 1) default(shared)
    do b = 1, nblocks
      call section_block(p, live((b - 1)*nl + 1:min(b*nl, nlive)), section_phase, transient, nrec, &
                         theta_s, omega_s, mean_omega, codes, control)
    end do
    !$omp end parallel do
    call nan_failed(codes, theta_s)
    call nan_failed(codes, omega_s)
    call nan_failed(codes, mean_omega)
    call params_summary(codes, first_bad, msg, status, first_failed)
  end subroutine driven_poincare

  ! transient >= 0, count >= least
  pure subroutine check_counts(transient, count, least, name, status)
    integer, intent(in) :: transient, count, least
    character(len=*), intent(in) :: name
    type(status_t), intent(inout) :: status
    if (status%code /= PENDULA_OK) return
    if (transient < 0) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'transient = '//format_int(transient)// &
                     ' is out of range: it must be >= 0 (drive periods)')
    else if (count < least) then
      call set_error(status, PENDULA_ERR_DOMAIN, name//' = '//format_int(count)// &
                     ' is out of range: it must be >= '//format_int(least))
    end if
  end subroutine check_counts

  ! One block of sections: the lanes step the grid together; lane l records
  ! at its grid phase j0(l) once `transient` periods have passed.
  subroutine section_block(p, idx, section_phase, transient, nrec, theta_s, omega_s, mean_omega, codes, control)
    type(driven_params_t), intent(in) :: p
    integer, intent(in) :: idx(:), transient, nrec
    real(wp), intent(in) :: section_phase
    real(wp), intent(inout) :: theta_s(:, :), omega_s(:, :), mean_omega(:)
    integer, intent(inout) :: codes(:)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    type(lanes_t) :: b
    logical :: go
    real(wp) :: y(nl), u(nl), yfirst(nl)
    integer :: j0(nl), rec(nl), nb, l, j, k
    integer(i8) :: work
    logical :: ok(nl)
    nb = size(idx)
    call block_open(p, idx, 0.0_wp, b, y, u, codes, go, control)
    if (.not. go) return
    do l = 1, nl
      j0(l) = modulo(nint(p%nsteps*(modulo(section_phase - b%phase(l), 2*pi)/(2*pi))), p%nsteps)
    end do
    rec = 0
    yfirst = 0
    work = 0
    k = 0
    do
      do j = 0, p%nsteps - 1
        if (k >= transient) then
          do l = 1, nb
            if (j == j0(l) .and. rec(l) <= nrec) then
              if (rec(l) < nrec) then
                theta_s(rec(l) + 1, idx(l)) = wrap_angle(y(l))
                omega_s(rec(l) + 1, idx(l)) = u(l)
              end if
              if (rec(l) == 0) yfirst(l) = y(l)
              if (rec(l) == nrec) mean_omega(idx(l)) = (y(l) - yfirst(l))/(nrec*b%h(l)*p%nsteps)
              rec(l) = rec(l) + 1
            end if
          end do
          if (all(rec(1:nb) > nrec)) exit
        end if
        call lanes_steps(b, j, j + 1, y, u)
      end do
      if (all(rec(1:nb) > nrec)) exit
      k = k + 1
      ok = lanes_finite(y, u)
      do l = 1, nb
        if (.not. ok(l) .and. codes(idx(l)) == PENDULA_ERR_CANCELLED) then
          codes(idx(l)) = PENDULA_ERR_SOLVER
          rec(l) = nrec + 1
        end if
      end do
      where (.not. ok)
        y = 0
        u = 0
      end where
      if (all(rec(1:nb) > nrec)) exit
      work = work + p%nsteps
      if (present(control) .and. work >= 4096) then
        work = 0
        if (cancel_requested(control)) return
      end if
    end do
    do l = 1, nb
      if (codes(idx(l)) == PENDULA_ERR_CANCELLED) codes(idx(l)) = PENDULA_OK
    end do
    if (present(control)) call add_progress(control, int(nb, int64))
  end subroutine section_block

  !> A bifurcation diagram: driven_poincare over size(values) values of one
  !> parameter, `which` = PARAM_AMPLITUDE, PARAM_FREQUENCY, PARAM_PHASE,
  !> PARAM_GAMMA or PARAM_W0, the others fixed (scalars); every value starts
  !> from the same (theta0, omega0).  Outputs as driven_poincare with
  !> n = size(values).
  subroutine driven_bifurcation(which, values, theta0, omega0, w0, gamma, kind, amp, freq, phase, nsteps, &
                        section_phase, transient, nrec, theta_s, omega_s, mean_omega, codes, status, threads, control, first_failed)
    integer, intent(in) :: which  !< the parameter varied (PARAM_* code)
    real(wp), intent(in) :: values(:)  !< its values, size >= 1
    real(wp), intent(in) :: theta0  !< initial angle [rad] at t = 0
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s]
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    integer, intent(in) :: kind  !< DRIVE_TORQUE or DRIVE_PIVOT
    real(wp), intent(in) :: amp  !< drive amplitude (F in rad/s**2, or a/l)
    real(wp), intent(in) :: freq  !< drive frequency Omega [rad/s], > 0
    real(wp), intent(in) :: phase  !< drive phase phi [rad]
    integer, intent(in) :: nsteps  !< RK4 steps per drive period
    real(wp), intent(in) :: section_phase  !< drive phase of the section [rad]
    integer, intent(in) :: transient  !< drive periods discarded first, >= 0
    integer, intent(in) :: nrec  !< section points recorded per value, >= 1
    real(wp), intent(out) :: theta_s(:, :)  !< section angles [rad], shape (nrec, size(values))
    real(wp), intent(out) :: omega_s(:, :)  !< section angular velocities [rad/s], shape (nrec, size(values))
    real(wp), intent(out) :: mean_omega(:)  !< mean angular velocities [rad/s], size(values)
    integer, intent(out) :: codes(:)  !< status code of each value
    type(status_t), intent(out) :: status  !< error code and message (PENDULA_OK on success)
    integer, intent(in), optional :: threads  !< OpenMP threads (0 or absent: the OpenMP default)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag and progress counter (finished values)
    integer, intent(out), optional :: first_failed  !< first failed value (0: none)
    real(wp), allocatable :: th0(:)
    integer :: n, ist
    n = size(values)
    if (which < PARAM_AMPLITUDE .or. which > PARAM_W0) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'parameter = '//format_int(which)// &
                     ' is out of range: it must be in [1, 5] (amplitude, frequency, phase, gamma, w0)')
      codes = status%code
      theta_s = failed_output()
      omega_s = failed_output()
      mean_omega = failed_output()
      if (present(first_failed)) first_failed = 0
      return
    end if
    allocate (th0(n), stat=ist)
    call check_alloc(ist, 'the bifurcation''s start angles', int(n, i8), 8, status)
    if (status%code /= PENDULA_OK) then
      codes = status%code
      theta_s = failed_output()
      omega_s = failed_output()
      mean_omega = failed_output()
      if (present(first_failed)) first_failed = 0
      return
    end if
    th0 = theta0
    call driven_poincare(th0, [omega0], sel(PARAM_W0, w0), sel(PARAM_GAMMA, gamma), kind, &
                         sel(PARAM_AMPLITUDE, amp), sel(PARAM_FREQUENCY, freq), sel(PARAM_PHASE, phase), nsteps, section_phase, &
                         transient, nrec, theta_s, omega_s, mean_omega, codes, status, threads, control, first_failed)
  contains
    pure function sel(code, base) result(a)
      integer, intent(in) :: code
      real(wp), intent(in) :: base
      real(wp), allocatable :: a(:)
      if (code == which) then
        a = values
      else
        a = [base]
      end if
    end function sel
  end subroutine driven_bifurcation

  !> Both Lyapunov exponents [1/s] of n driven pendulums (parameters as
  !> driven_poincare, started at t = 0), largest first.  Each state is
  !> followed as an ensemble of `orbits` copies in the SIMD lanes of one
  !> block (copy c starts at theta0 + c*LYAPUNOV_SPREAD, c = 0..orbits-1;
  !> on a chaotic attractor the copies part within the transient and
  !> sample it independently, on a stable periodic orbit they meet): after
  !> `transient` periods, two tangent vectors per copy follow the RK4 map's
  !> derivative over `periods` drive periods and are re-orthonormalised
  !> (Gram-Schmidt) at the end of each (Benettin et al.); lyap(:, i) = the
  !> mean log stretching per unit time over the copies.  These are the
  !> exponents of the RK4 map (O(h**4) from the flow's): they sum to -gamma
  !> up to the RK4 error of log det, and on a stable periodic orbit they are
  !> ln|mu|/(n T) of its Floquet multipliers mu (pendula_driven_orbits).
  !> lyap_err(:, i): a 95 % error bound: the periods are cut into
  !> LYAPUNOV_BLOCKS blocks; copies that have not parted by the end of the
  !> transient (closer than LYAPUNOV_PARTED) are grouped, and each block's
  !> mean over a group is one sample; the bound is Student's t times the
  !> standard error of the samples' mean, combined (root sum of squares) with
  !> the part of half the gap between the means of the two halves that this
  !> noise does not explain (a running average still drifting); periods >=
  !> LYAPUNOV_BLOCKS.  Its coverage is checked against a long reference in
  !> the tests.  codes, status, threads, control and first_failed as
  !> driven_poincare (a failed state's lyap and lyap_err are NaN).
  subroutine driven_lyapunov(theta0, omega0, w0, gamma, kind, amp, freq, phase, nsteps, transient, periods, &
                             lyap, lyap_err, codes, status, threads, control, first_failed, orbits)
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad] at t = 0, n = size(theta0)
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], n or 1
    real(wp), intent(in) :: w0(:)  !< small-angle angular frequencies [1/s], > 0, n or 1
    real(wp), intent(in) :: gamma(:)  !< damping rates [1/s], >= 0, n or 1
    integer, intent(in) :: kind  !< DRIVE_TORQUE or DRIVE_PIVOT
    real(wp), intent(in) :: amp(:)  !< drive amplitudes (F in rad/s**2, or a/l), n or 1
    real(wp), intent(in) :: freq(:)  !< drive frequencies Omega [rad/s], > 0, n or 1
    real(wp), intent(in) :: phase(:)  !< drive phases phi [rad], n or 1
    integer, intent(in) :: nsteps  !< RK4 steps per drive period
    integer, intent(in) :: transient  !< drive periods before the measurement, >= 0
    integer, intent(in) :: periods  !< drive periods measured per copy, >= LYAPUNOV_BLOCKS
    real(wp), intent(out) :: lyap(:, :)  !< exponents [1/s], shape (2, n), largest first
    real(wp), intent(out) :: lyap_err(:, :)  !< their 95 % error bounds [1/s], shape (2, n)
    integer, intent(out) :: codes(:)  !< status code of each state, n
    type(status_t), intent(out) :: status  !< error code and message (PENDULA_OK on success)
    integer, intent(in), optional :: threads  !< OpenMP threads (0 or absent: the OpenMP default)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag and progress counter (finished states)
    integer, intent(out), optional :: first_failed  !< first failed state (0: none)
    integer, intent(in), optional :: orbits
    !< copies per state in [1, DRIVEN_LANES] (absent: LYAPUNOV_ORBITS); 1 follows exactly (theta0, omega0)
    type(driven_params_t) :: p
    integer, allocatable :: live(:)
    integer :: nlive, nblocks, b, first_bad, nth, ncopy, per_block
    character(len=len(status%message)) :: msg
    if (present(first_failed)) first_failed = 0
    ncopy = LYAPUNOV_ORBITS
    if (present(orbits)) ncopy = orbits
    lyap = 0
    lyap_err = 0
    call params_check(kind, nsteps, theta0, omega0, w0, gamma, amp, freq, phase, threads, p, status)
    call check_counts(transient, periods, LYAPUNOV_BLOCKS, 'periods', status)
    if (status%code == PENDULA_OK .and. (ncopy < 1 .or. ncopy > nl)) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'orbits = '//format_int(ncopy)// &
                     ' is out of range: it must be in [1, '//format_int(nl)//'] (copies per state)')
    end if
    call check_same_size('codes', size(codes), 'theta0', size(theta0), status)
    call check_same_size('lyap', size(lyap), '2 * size(theta0)', 2*size(theta0), status)
    call check_same_size('lyap_err', size(lyap_err), '2 * size(theta0)', 2*size(theta0), status)
    if (status%code /= PENDULA_OK) then
      codes = status%code
      lyap = failed_output()
      lyap_err = failed_output()
      return
    end if
    nth = batch_threads(threads)
    call params_prepare(p, codes, live, nlive, first_bad, msg)
    per_block = nl/ncopy
    nblocks = (nlive + per_block - 1)/per_block
    !$omp parallel do schedule(dynamic) num_threads(nth) if(nth > 1 .and. nblocks > 1) default(shared)
    do b = 1, nblocks
      call lyapunov_block(p, live((b - 1)*per_block + 1:min(b*per_block, nlive)), ncopy, transient, periods, &
                          lyap, lyap_err, codes, control)
    end do
    !$omp end parallel do
    call nan_failed(codes, lyap)
    call nan_failed(codes, lyap_err)
    call params_summary(codes, first_bad, msg, status, first_failed)
  end subroutine driven_lyapunov

  ! One block: the states idx(:), ncopy lanes each (lane l is copy
  ! mod(l - 1, ncopy) of state idx((l - 1)/ncopy + 1)); lanes past
  ! size(idx)*ncopy are padding.
  subroutine lyapunov_block(p, idx, ncopy, transient, periods, lyap, lyap_err, codes, control)
    type(driven_params_t), intent(in) :: p
    integer, intent(in) :: idx(:), ncopy, transient, periods
    real(wp), intent(inout) :: lyap(:, :), lyap_err(:, :)
    integer, intent(inout) :: codes(:)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    integer, parameter :: nbk = LYAPUNOV_BLOCKS
    type(lanes_t) :: b
    logical :: go
    real(wp) :: y(nl), u(nl), v(nl, 4), r11, r22, r12, bsum(2, nbk, nl), tper
    integer :: nb, nlane, l, k, kb, e, cnt(nbk), st(nl), s, c0
    integer(i8) :: work
    integer :: group(nl)
    logical :: ok(nl), dead(nl)
    nb = size(idx)
    if (nb == 0) return
    nlane = nb*ncopy
    do l = 1, nl
      st(l) = min((l - 1)/ncopy + 1, nb)
    end do
    call block_open(p, idx(st), 0.0_wp, b, y, u, codes, go, control)
    if (.not. go) return
    do l = 1, nl
      y(l) = y(l) + mod(l - 1, ncopy)*LYAPUNOV_SPREAD
    end do
    dead = .false.
    work = 0
    do k = 1, transient
      call lanes_steps(b, 0, p%nsteps, y, u)
      if (.not. poll()) return
    end do
    do s = 1, nb
      c0 = (s - 1)*ncopy
      call copy_groups(y(c0 + 1:c0 + ncopy), u(c0 + 1:c0 + ncopy)/b%freq(c0 + 1), group(c0 + 1:c0 + ncopy))
    end do
    v = 0
    v(:, 1) = 1
    v(:, 4) = 1
    bsum = 0
    cnt = 0
    do k = 0, periods - 1
      call lanes_steps_tangent(b, 0, p%nsteps, y, u, v)
      kb = min(k*nbk/periods + 1, nbk)
      cnt(kb) = cnt(kb) + 1
      do l = 1, nl
        ! Gram-Schmidt (QR): v1 <- v1/r11; v2 <- (v2 - r12 v1)/r22
        r11 = hypot(v(l, 1), v(l, 2))
        if (.not. r11 > 0) r11 = 1   ! a degenerate lane (dead or padding): flagged below
        v(l, 1) = v(l, 1)/r11
        v(l, 2) = v(l, 2)/r11
        r12 = v(l, 1)*v(l, 3) + v(l, 2)*v(l, 4)
        v(l, 3) = v(l, 3) - r12*v(l, 1)
        v(l, 4) = v(l, 4) - r12*v(l, 2)
        r22 = hypot(v(l, 3), v(l, 4))
        if (.not. r22 > 0) r22 = 1
        v(l, 3) = v(l, 3)/r22
        v(l, 4) = v(l, 4)/r22
        bsum(1, kb, l) = bsum(1, kb, l) + log(r11)
        bsum(2, kb, l) = bsum(2, kb, l) + log(r22)
      end do
      if (.not. poll()) return
    end do
    do s = 1, nb
      c0 = (s - 1)*ncopy
      if (any(dead(c0 + 1:c0 + ncopy))) cycle
      tper = b%h(c0 + 1)*p%nsteps
      do e = 1, 2
        lyap(e, idx(s)) = sum(bsum(e, :, c0 + 1:c0 + ncopy))/(ncopy*periods*tper)
        lyap_err(e, idx(s)) = block_bound(bsum(e, :, c0 + 1:c0 + ncopy)/tper, cnt, group(c0 + 1:c0 + ncopy))
      end do
      if (codes(idx(s)) == PENDULA_ERR_CANCELLED) codes(idx(s)) = PENDULA_OK
    end do
    if (present(control)) call add_progress(control, int(nb, int64))
  contains
    ! finiteness of the lanes and the cancel flag, once a period; false: cancelled
    logical function poll()
      integer :: m
      poll = .true.
      ok = lanes_finite(y, u)
      do m = 1, nlane
        if (.not. ok(m) .and. .not. dead(m)) then
          dead(m) = .true.
          codes(idx(st(m))) = PENDULA_ERR_SOLVER
        end if
      end do
      where (.not. ok)
        y = 0
        u = 0
      end where
      work = work + p%nsteps
      if (present(control) .and. work >= 2048) then
        work = 0
        if (cancel_requested(control)) poll = .false.
      end if
    end function poll
  end subroutine lyapunov_block

  ! The copies of one state grouped by whether they have parted: copies closer than
  ! LYAPUNOV_PARTED in (theta mod 2 pi, omega/Omega) [rad], directly or through others, share
  ! a group.  Copies of a chaotic orbit that have parted are independent samples of its
  ! attractor; copies that have not (a periodic orbit, weak chaos, a short transient) count
  ! as one sample.
  pure subroutine copy_groups(y, w, group)
    real(wp), intent(in) :: y(:)  !< the copies' angles [rad]
    real(wp), intent(in) :: w(:)  !< their angular velocities over Omega [rad]
    integer, intent(out) :: group(:)  !< group of each copy (the least copy index in it)
    integer :: i, j, gi, gj
    group = [(i, i=1, size(y))]
    do i = 1, size(y)
      do j = i + 1, size(y)
        if (.not. hypot(wrap_angle(y(i) - y(j)), w(i) - w(j)) >= LYAPUNOV_PARTED) then
          gi = min(group(i), group(j))
          gj = max(group(i), group(j))
          where (group == gj) group = gi
        end if
      end do
    end do
  end subroutine copy_groups

  ! The 95 % error bound of an exponent from its log stretchings x(k, c) [per unit time] summed
  ! over the cnt(k) periods of block k of copy c: Student's t times the standard error of the
  ! samples' mean, a sample being a block's mean over one group of copies (copy_groups),
  ! combined (root sum of squares) with the part of half the gap between the means of the two
  ! halves that this noise does not explain (a running average still drifting, e.g. the
  ! approach to a periodic orbit).
  pure real(wp) function block_bound(x, cnt, group) result(bound)
    real(wp), intent(in) :: x(:, :)  !< summed log stretchings per unit time, (blocks, copies)
    integer, intent(in) :: cnt(:)  !< periods per block
    integer, intent(in) :: group(:)  !< group of each copy
    real(wp) :: m(size(x, 1), size(x, 2)), se, m1, m2, excess, t
    integer :: nbk, nc, ng, ns, half, c, j
    nbk = size(x, 1)
    nc = size(x, 2)
    half = nbk/2
    ! m(:, g): the block means of group g's copies, for the ng groups
    ng = 0
    do c = 1, nc
      if (group(c) /= c) cycle
      ng = ng + 1
      m(:, ng) = sum(x(:, pack([(j, j=1, nc)], group == c)), dim=2)/(count(group == c)*cnt)
    end do
    ns = nbk*ng
    ! (the exponent weighs the groups by their sizes; here they count as equal samples)
    se = sqrt(sum((m(:, 1:ng) - sum(m(:, 1:ng))/ns)**2)/(ns - 1)/ns)
    t = student_t95(ns - 1)
    m1 = sum(x(1:half, :))/(nc*sum(cnt(1:half)))
    m2 = sum(x(half + 1:nbk, :))/(nc*sum(cnt(half + 1:nbk)))
    ! (m2 - m1)/2 has the standard error se of the whole mean (equal halves)
    excess = max(0.0_wp, 0.5_wp*abs(m2 - m1) - t*se)
    bound = hypot(t*se, excess)
  end function block_bound

  ! Student's t quantile of a two-sided 95 % interval with nu >= 15 degrees of freedom
  ! (Cornish-Fisher expansion about the normal quantile, Abramowitz & Stegun 26.7.5: error
  ! below 1e-5 at nu = 15).
  pure real(wp) function student_t95(nu) result(t)
    integer, intent(in) :: nu  !< degrees of freedom
    real(wp), parameter :: z = 1.959963984540054_wp
    real(wp) :: r
    r = 1.0_wp/nu
    t = z + r*((z**3 + z)/4 + r*((5*z**5 + 16*z**3 + 3*z)/96 + r*((3*z**7 + 19*z**5 + 17*z**3 - 15*z)/384 &
                                                                  + r*(79*z**9 + 776*z**7 + 1482*z**5 - 1920*z**3 - 945*z)/92160)))
  end function student_t95

end module pendula_driven_maps
