!> Periodic orbits and basins of attraction of the driven pendulum's
!> stroboscopic map P (one drive period, from t = k T), every one a batch
!> (blocks of lanes on OpenMP threads):
!>
!> - driven_orbits: after a transient, detect the period n <= nmax of the
!>   attractor the state settles on (its strobe points repeat within tol,
!>   theta modulo 2 pi), then locate the orbit by Newton's method on
!>   P**n(x) - x - (2 pi m, 0) (m: the turns made in n periods, 0 for an
!>   oscillation) with the monodromy matrix from the variational equations;
!>   report its point, winding m, Floquet multipliers (the monodromy's
!>   eigenvalues) and stability.  With a period given, Newton starts from
!>   the initial state itself (unstable orbits too).
!> - driven_basins: for each initial state, the attractor it settles on, as a
!>   label into a table of the distinct periodic attractors found (matched by
!>   period, winding and strobe points), or BASIN_UNSETTLED.
module pendula_driven_orbits
  use, intrinsic :: iso_fortran_env, only: int64
  use pendula_kinds, only: wp, i8
  use pendula_constants, only: pi
  use pendula_format, only: format_int
  use pendula_status, only: status_t, set_error, check_alloc, check_positive, check_same_size, PENDULA_OK, PENDULA_ERR_DOMAIN, &
                            PENDULA_ERR_SOLVER, PENDULA_ERR_CANCELLED, PENDULA_ERR_SIZE, PENDULA_ERR_MEMORY
  use pendula_control, only: CONTROL_SIZE, cancel_requested, add_progress
  use pendula_batch_support, only: batch_threads, failed_output, nan_failed
  use pendula_driven_kernel, only: DRIVEN_LANES, lanes_t, lanes_steps, lanes_steps_tangent, lanes_finite
  use pendula_driven_support, only: driven_params_t, params_check, params_prepare, block_open, &
                                    params_summary, wrap_angle
  implicit none
  private
  public :: driven_orbits, driven_basins, basin_table, BASIN_UNSETTLED, BASIN_UNLISTED, &
            ORBIT_NEWTON_TOL, ORBIT_MAX_PERIOD

  integer, parameter :: nl = DRIVEN_LANES
  !> Basin label of a state that settled on no periodic attractor of period <= nmax (chaotic or slow).
  integer, parameter :: BASIN_UNSETTLED = 0
  !> Basin label of a state whose attractor did not fit in the attractor table.
  integer, parameter :: BASIN_UNLISTED = -1
  !> Newton stops when max(|theta residual|, |omega residual|) <= this.
  real(wp), parameter :: ORBIT_NEWTON_TOL = 1.0e-10_wp
  !> Largest period (drive periods) searched.
  integer, parameter :: ORBIT_MAX_PERIOD = 64
  integer, parameter :: max_newton = 40

contains

  ! Floquet multipliers of a 2x2 monodromy matrix m: mult = [re1, im1, re2,
  ! im2], the larger modulus first.
  pure subroutine floquet_multipliers(m, mult)
    real(wp), intent(in) :: m(2, 2)  !< monodromy matrix
    real(wp), intent(out) :: mult(4)  !< eigenvalues (real and imaginary parts), largest modulus first
    real(wp) :: tr, det, disc, mu1, mu2
    tr = m(1, 1) + m(2, 2)
    det = m(1, 1)*m(2, 2) - m(1, 2)*m(2, 1)
    disc = tr*tr - 4*det
    if (disc >= 0) then
      mu1 = 0.5_wp*(tr + sign(sqrt(disc), tr))
      mu2 = 0
      if (mu1 /= 0) mu2 = det/mu1
      mult = [mu1, 0.0_wp, mu2, 0.0_wp]
      if (abs(mu2) > abs(mu1)) mult = [mu2, 0.0_wp, mu1, 0.0_wp]
    else
      mult = [0.5_wp*tr, 0.5_wp*sqrt(-disc), 0.5_wp*tr, -0.5_wp*sqrt(-disc)]
    end if
  end subroutine floquet_multipliers

  ! Check transient >= 0, 1 <= nmax <= ORBIT_MAX_PERIOD, tol > 0.
  pure subroutine check_search(transient, nmax, tol, status)
    integer, intent(in) :: transient, nmax
    real(wp), intent(in) :: tol
    type(status_t), intent(inout) :: status
    if (status%code /= PENDULA_OK) return
    if (transient < 0) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'transient = '//format_int(transient)// &
                     ' is out of range: it must be >= 0 (drive periods)')
    else if (nmax < 1 .or. nmax > ORBIT_MAX_PERIOD) then
      call set_error(status, PENDULA_ERR_DOMAIN, 'nmax = '//format_int(nmax)// &
                     ' is out of range: it must be in [1, '//format_int(ORBIT_MAX_PERIOD)//']')
    end if
    call check_positive('tol', tol, status)
  end subroutine check_search

  ! After `transient` periods, 2 nmax strobe points; per lane the smallest
  ! period n whose points repeat within tol over the last nmax (0: none),
  ! the winding m, and the last n points (wrapped) in cyc.  y, u end at the
  ! last strobe point.
  subroutine detect(b, nb, y, u, transient, nmax, tol, period, winding, cyc, dead, codes, idx, control, cancelled)
    type(lanes_t), intent(in) :: b
    integer, intent(in) :: nb, transient, nmax, idx(:)
    real(wp), intent(inout) :: y(nl), u(nl)
    real(wp), intent(in) :: tol
    integer, intent(out) :: period(nl), winding(nl)
    real(wp), intent(out) :: cyc(2, nmax, nl)
    logical, intent(inout) :: dead(nl)
    integer, intent(inout) :: codes(:)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    logical, intent(out) :: cancelled
    real(wp) :: ry(2*nmax, nl), ru(2*nmax, nl), d
    integer :: k, l, n, i, kk
    logical :: ok(nl), good
    cancelled = .false.
    kk = 2*nmax
    do k = 1, transient + kk
      call lanes_steps(b, 0, b%nsteps, y, u)
      ok = lanes_finite(y, u)
      do l = 1, nb
        if (.not. ok(l) .and. .not. dead(l)) then
          dead(l) = .true.
          codes(idx(l)) = PENDULA_ERR_SOLVER
        end if
      end do
      where (.not. ok)
        y = 0
        u = 0
      end where
      if (k > transient) then
        ry(k - transient, :) = y
        ru(k - transient, :) = u
      end if
      if (present(control) .and. mod(k, 16) == 0) then
        if (cancel_requested(control)) then
          cancelled = .true.
          return
        end if
      end if
    end do
    period = 0
    winding = 0
    cyc = 0
    do l = 1, nb
      if (dead(l)) cycle
      do n = 1, nmax
        good = .true.
        do i = kk - nmax + 1, kk
          d = max(abs(wrap_angle(ry(i, l) - ry(i - n, l))), abs(ru(i, l) - ru(i - n, l)))
          if (.not. d <= tol) then
            good = .false.
            exit
          end if
        end do
        if (good) then
          period(l) = n
          winding(l) = nint((ry(kk, l) - ry(kk - n, l))/(2*pi))
          do i = 1, n
            cyc(1, i, l) = wrap_angle(ry(kk - n + i, l))
            cyc(2, i, l) = ru(kk - n + i, l)
          end do
          exit
        end if
      end do
    end do
  end subroutine detect

  !> Periodic orbits of n driven pendulums (parameters as pendula_driven_maps'
  !> driven_poincare, from t = 0).  period_in(i) = 0: detect the attractor
  !> state i settles on after `transient` periods (period <= nmax, strobe
  !> points repeating within tol); period_in(i) > 0: Newton from
  !> (theta0(i), omega0(i)) for an orbit of that period (any stability).
  !> Outputs: period(i) (0: none found or Newton failed), winding(i) (turns
  !> per period(i) drive periods), the orbit's strobe point theta_p(i) in
  !> (-pi, pi] [rad] and omega_p(i) [rad/s] at t = k T, its Floquet
  !> multipliers mult(:, i) = [re1, im1, re2, im2] (largest modulus first;
  !> stable when that modulus is < 1) and Newton's final residual(i).
  !> period_in has n elements or one.  codes, status, threads, control
  !> (progress = finished states) and first_failed as driven_poincare: a
  !> failed state's period and winding are 0 and its real outputs NaN (every
  !> output of a refused call too).
  subroutine driven_orbits(theta0, omega0, w0, gamma, kind, amp, freq, phase, nsteps, period_in, transient, &
                        nmax, tol, period, winding, theta_p, omega_p, mult, residual, codes, status, threads, control, first_failed)
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad] at t = 0, n = size(theta0)
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], n or 1
    real(wp), intent(in) :: w0(:)  !< small-angle angular frequencies [1/s], > 0, n or 1
    real(wp), intent(in) :: gamma(:)  !< damping rates [1/s], >= 0, n or 1
    integer, intent(in) :: kind  !< DRIVE_TORQUE or DRIVE_PIVOT
    real(wp), intent(in) :: amp(:)  !< drive amplitudes (F in rad/s**2, or a/l), n or 1
    real(wp), intent(in) :: freq(:)  !< drive frequencies Omega [rad/s], > 0, n or 1
    real(wp), intent(in) :: phase(:)  !< drive phases phi [rad], n or 1
    integer, intent(in) :: nsteps  !< RK4 steps per drive period
    integer, intent(in) :: period_in(:)  !< 0: detect; > 0: this period, Newton from the initial state; n or 1
    integer, intent(in) :: transient  !< drive periods before detection, >= 0
    integer, intent(in) :: nmax  !< largest period searched, in [1, ORBIT_MAX_PERIOD]
    real(wp), intent(in) :: tol  !< detection tolerance on strobe points [rad, rad/s], > 0
    integer, intent(out) :: period(:)  !< period found (drive periods; 0: none), n
    integer, intent(out) :: winding(:)  !< turns per period(i) drive periods, n
    real(wp), intent(out) :: theta_p(:)  !< the orbit's strobe angle in (-pi, pi] [rad], n
    real(wp), intent(out) :: omega_p(:)  !< the orbit's strobe angular velocity [rad/s], n
    real(wp), intent(out) :: mult(:, :)  !< Floquet multipliers [re1, im1, re2, im2], shape (4, n)
    real(wp), intent(out) :: residual(:)  !< Newton's final residual, n
    integer, intent(out) :: codes(:)  !< status code of each state, n
    type(status_t), intent(out) :: status  !< error code and message (PENDULA_OK on success)
    integer, intent(in), optional :: threads  !< OpenMP threads (0 or absent: the OpenMP default)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag and progress counter (finished states)
    integer, intent(out), optional :: first_failed  !< first failed state (0: none)
    type(driven_params_t) :: p
    integer, allocatable :: live(:)
    integer :: nlive, nblocks, b, first_bad, nth, n
    character(len=len(status%message)) :: msg
    if (present(first_failed)) first_failed = 0
    period = 0
    winding = 0
    theta_p = 0
    omega_p = 0
    mult = 0
    residual = 0
    n = size(theta0)
    call params_check(kind, nsteps, theta0, omega0, w0, gamma, amp, freq, phase, threads, p, status)
    call check_search(transient, nmax, tol, status)
    if (status%code == PENDULA_OK .and. size(period_in) /= 1 .and. size(period_in) /= n) call set_error(status, &
                                                                 PENDULA_ERR_SIZE, 'period_in has '//format_int(size(period_in))// &
                                                         ' element(s): it must have one or as many as theta0 ('//format_int(n)//')')
    if (status%code == PENDULA_OK .and. (minval(period_in) < 0 .or. maxval(period_in) > ORBIT_MAX_PERIOD)) &
      call set_error(status, PENDULA_ERR_DOMAIN, 'period = '//format_int(maxval(abs(period_in)))// &
                     ' is out of range: it must be in [0, '//format_int(ORBIT_MAX_PERIOD)//'] (0: detect)')
    call check_same_size('codes', size(codes), 'theta0', n, status)
    call check_same_size('period', size(period), 'theta0', n, status)
    call check_same_size('winding', size(winding), 'theta0', n, status)
    call check_same_size('theta_p', size(theta_p), 'theta0', n, status)
    call check_same_size('omega_p', size(omega_p), 'theta0', n, status)
    call check_same_size('residual', size(residual), 'theta0', n, status)
    call check_same_size('mult', size(mult), '4 * size(theta0)', 4*n, status)
    if (status%code /= PENDULA_OK) then
      codes = status%code
      theta_p = failed_output()
      omega_p = failed_output()
      mult = failed_output()
      residual = failed_output()
      return
    end if
    nth = batch_threads(threads)
    call params_prepare(p, codes, live, nlive, first_bad, msg)
    nblocks = (nlive + nl - 1)/nl
    !$omp parallel do schedule(dynamic) num_threads(nth) if(nth > 1 .and. nblocks > 1) default(shared)
    do b = 1, nblocks
      call orbit_block(p, live((b - 1)*nl + 1:min(b*nl, nlive)), period_in, transient, nmax, tol, period, &
                       winding, theta_p, omega_p, mult, residual, codes, control)
    end do
    !$omp end parallel do
    where (codes /= PENDULA_OK)
      period = 0
      winding = 0
    end where
    call nan_failed(codes, theta_p)
    call nan_failed(codes, omega_p)
    call nan_failed(codes, mult)
    call nan_failed(codes, residual)
    call params_summary(codes, first_bad, msg, status, first_failed)
  end subroutine driven_orbits

  subroutine orbit_block(p, idx, period_in, transient, nmax, tol, period, winding, theta_p, omega_p, mult, &
                         residual, codes, control)
    type(driven_params_t), intent(in) :: p
    integer, intent(in) :: idx(:), period_in(:), transient, nmax
    real(wp), intent(in) :: tol
    integer, intent(inout) :: period(:), winding(:), codes(:)
    real(wp), intent(inout) :: theta_p(:), omega_p(:), mult(:, :), residual(:)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    type(lanes_t) :: b
    logical :: go
    real(wp) :: y(nl), u(nl), xs(nl), us(nl), v(nl, 4), fy(nl), fu(nl), mm(2, 2, nl), cyc(2, nmax, nl)
    real(wp) :: r1, r2, a, bb, c, d, det, d1, d2, res(nl)
    integer :: nb, l, k, it, per(nl), wnd(nl), kmax, m
    logical :: dead(nl), conv(nl), given(nl), cancelled
    nb = size(idx)
    call block_open(p, idx, 0.0_wp, b, y, u, codes, go, control)
    if (.not. go) return
    dead = .false.
    dead(nb + 1:) = .true.
    do l = 1, nl
      given(l) = period_in(merge(idx(min(l, nb)), 1, size(period_in) > 1)) > 0
    end do
    per = 0
    wnd = 0
    if (.not. all(given(1:nb))) then
      ! lanes with a given period wait at their initial state meanwhile
      xs = y
      us = u
      call detect(b, nb, y, u, transient, nmax, tol, per, wnd, cyc, dead, codes, idx, control, cancelled)
      if (cancelled) return
      where (given)
        y = xs
        u = us
      end where
    end if
    do l = 1, nb
      if (given(l)) per(l) = period_in(merge(idx(l), 1, size(period_in) > 1))
    end do
    conv = per == 0 .or. dead
    res = huge(1.0_wp)
    do it = 1, max_newton
      if (all(conv(1:nb))) exit
      kmax = max(1, maxval(per(1:nb)))
      xs = y
      us = u
      v = 0
      v(:, 1) = 1
      v(:, 4) = 1
      do k = 1, kmax
        call lanes_steps_tangent(b, 0, b%nsteps, xs, us, v)
        do l = 1, nb
          if (per(l) == k) then
            fy(l) = xs(l)
            fu(l) = us(l)
            mm(:, :, l) = reshape(v(l, :), [2, 2])
          end if
        end do
        if (present(control)) then
          if (cancel_requested(control)) return
        end if
      end do
      do l = 1, nb
        if (conv(l)) cycle
        m = nint((fy(l) - y(l))/(2*pi))
        if (given(l) .and. it == 1) wnd(l) = m
        r1 = fy(l) - y(l) - 2*pi*wnd(l)
        r2 = fu(l) - u(l)
        res(l) = max(abs(r1), abs(r2))
        if (.not. res(l) < huge(1.0_wp)) then
          conv(l) = .true.
          per(l) = 0
          cycle
        end if
        call floquet_multipliers(mm(:, :, l), mult(:, idx(l)))
        if (res(l) <= ORBIT_NEWTON_TOL) then
          conv(l) = .true.
          cycle
        end if
        ! (M - I) d = -r
        a = mm(1, 1, l) - 1
        bb = mm(1, 2, l)
        c = mm(2, 1, l)
        d = mm(2, 2, l) - 1
        det = a*d - bb*c
        if (det == 0) then
          conv(l) = .true.
          per(l) = 0
          cycle
        end if
        d1 = -(d*r1 - bb*r2)/det
        d2 = -(a*r2 - c*r1)/det
        y(l) = y(l) + d1
        u(l) = u(l) + d2
      end do
    end do
    do l = 1, nb
      if (dead(l)) cycle
      if (.not. (conv(l) .and. res(l) <= ORBIT_NEWTON_TOL)) per(l) = 0
      period(idx(l)) = per(l)
      residual(idx(l)) = merge(res(l), 0.0_wp, per(l) > 0)
      if (per(l) > 0) then
        winding(idx(l)) = wnd(l)
        theta_p(idx(l)) = wrap_angle(y(l))
        omega_p(idx(l)) = u(l)
      else
        mult(:, idx(l)) = 0
      end if
      if (codes(idx(l)) == PENDULA_ERR_CANCELLED) codes(idx(l)) = PENDULA_OK
    end do
    if (present(control)) call add_progress(control, int(nb, int64))
  end subroutine orbit_block

  !> Basins of attraction: for each of n initial states (parameters as
  !> driven_orbits, from t = 0) the periodic attractor of period <= nmax it
  !> settles on after `transient` periods (strobe points repeating within
  !> tol, theta modulo 2 pi).  The distinct attractors found (same period
  !> and winding, a strobe point within 10 tol of one of the other's) form
  !> a table of at most size(att_period) entries in order of first
  !> appearance: labels(i) in 1..natt is state i's attractor,
  !> BASIN_UNSETTLED (0) a state with no periodic attractor of period <= nmax
  !> (chaotic, or still settling), BASIN_UNLISTED (-1) one whose attractor
  !> did not fit in the table.  Per attractor: period, winding (turns per
  !> period), the strobe point of smallest wrapped angle and the mean
  !> angular velocity 2 pi winding/(period T) [rad/s].  period(i),
  !> winding(i): state i's.  codes, status, threads, control and
  !> first_failed as driven_poincare; a failed state has period 0 and label
  !> BASIN_UNSETTLED (it is in no basin: its code says why) and its cycles
  !> are NaN.
  subroutine driven_basins(theta0, omega0, w0, gamma, kind, amp, freq, phase, nsteps, transient, nmax, tol, &
                           labels, period, winding, natt, att_period, att_winding, att_theta, att_omega, att_mean_omega, codes, &
                           status, threads, control, first_failed, cycles)
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad] at t = 0, n = size(theta0)
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], n or 1
    real(wp), intent(in) :: w0(:)  !< small-angle angular frequencies [1/s], > 0, n or 1
    real(wp), intent(in) :: gamma(:)  !< damping rates [1/s], >= 0, n or 1
    integer, intent(in) :: kind  !< DRIVE_TORQUE or DRIVE_PIVOT
    real(wp), intent(in) :: amp(:)  !< drive amplitudes (F in rad/s**2, or a/l), n or 1
    real(wp), intent(in) :: freq(:)  !< drive frequencies Omega [rad/s], > 0, n or 1
    real(wp), intent(in) :: phase(:)  !< drive phases phi [rad], n or 1
    integer, intent(in) :: nsteps  !< RK4 steps per drive period
    integer, intent(in) :: transient  !< drive periods before detection, >= 0
    integer, intent(in) :: nmax  !< largest period searched, in [1, ORBIT_MAX_PERIOD]
    real(wp), intent(in) :: tol  !< settling tolerance on strobe points [rad, rad/s], > 0
    integer, intent(out) :: labels(:)  !< attractor label of each state (see above), n
    integer, intent(out) :: period(:)  !< period of each state's attractor (0: unsettled), n
    integer, intent(out) :: winding(:)  !< its winding (turns per period), n
    integer, intent(out) :: natt  !< attractors in the table
    integer, intent(out) :: att_period(:)  !< period of each attractor (table capacity = size >= 1)
    integer, intent(out) :: att_winding(:)  !< winding of each attractor
    real(wp), intent(out) :: att_theta(:)  !< strobe angle of each attractor in (-pi, pi] [rad]
    real(wp), intent(out) :: att_omega(:)  !< strobe angular velocity of each attractor [rad/s]
    real(wp), intent(out) :: att_mean_omega(:)  !< mean angular velocity of each attractor [rad/s]
    integer, intent(out) :: codes(:)  !< status code of each state, n
    type(status_t), intent(out) :: status  !< error code and message (PENDULA_OK on success)
    integer, intent(in), optional :: threads  !< OpenMP threads (0 or absent: the OpenMP default)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag and progress counter (finished states)
    integer, intent(out), optional :: first_failed  !< first failed state (0: none)
    real(wp), intent(out), optional :: cycles(:, :, :)
    !< each state's strobe cycle (2, nmax, n): the input of basin_table, which builds the
    !< same table from the states of several calls (chunks of a sweep)
    type(driven_params_t) :: p
    integer, allocatable :: live(:)
    real(wp), allocatable :: cyc(:, :, :)
    integer :: nlive, nblocks, b, first_bad, nth, i, n, cap, ist
    character(len=len(status%message)) :: msg
    if (present(first_failed)) first_failed = 0
    labels = BASIN_UNSETTLED
    period = 0
    winding = 0
    natt = 0
    att_period = 0
    att_winding = 0
    att_theta = 0
    att_omega = 0
    att_mean_omega = 0
    n = size(theta0)
    cap = size(att_period)
    call params_check(kind, nsteps, theta0, omega0, w0, gamma, amp, freq, phase, threads, p, status)
    call check_search(transient, nmax, tol, status)
    call check_same_size('codes', size(codes), 'theta0', n, status)
    call check_same_size('labels', size(labels), 'theta0', n, status)
    call check_same_size('period', size(period), 'theta0', n, status)
    call check_same_size('winding', size(winding), 'theta0', n, status)
    if (status%code == PENDULA_OK .and. cap < 1) call set_error(status, PENDULA_ERR_SIZE, &
                                                                'att_period has 0 elements: the attractor table needs at least 1')
    call check_same_size('att_winding', size(att_winding), 'att_period', cap, status)
    call check_same_size('att_theta', size(att_theta), 'att_period', cap, status)
    call check_same_size('att_omega', size(att_omega), 'att_period', cap, status)
    call check_same_size('att_mean_omega', size(att_mean_omega), 'att_period', cap, status)
    if (status%code /= PENDULA_OK) then
      codes = status%code
      return
    end if
    nth = batch_threads(threads)
    call params_prepare(p, codes, live, nlive, first_bad, msg)
    allocate (cyc(2, nmax, n), stat=ist)
    call check_alloc(ist, 'the basins'' strobe cycles', 2_i8*nmax*n, 8, status)
    if (status%code /= PENDULA_OK) then
      codes = status%code
      return
    end if
    cyc = 0
    nblocks = (nlive + nl - 1)/nl
    !$omp parallel do schedule(dynamic) num_threads(nth) if(nth > 1 .and. nblocks > 1) default(shared)
    do b = 1, nblocks
      call basin_block(p, live((b - 1)*nl + 1:min(b*nl, nlive)), transient, nmax, tol, period, winding, cyc, &
                       codes, control)
    end do
    !$omp end parallel do
    where (codes /= PENDULA_OK)
      period = 0
      winding = 0
    end where
    if (present(cycles)) call check_same_size('cycles', size(cycles), 'cyc', size(cyc), status)
    if (status%code /= PENDULA_OK) then
      codes = status%code
      return
    end if
    if (present(cycles)) then
      cycles = cyc
      do i = 1, n
        if (codes(i) /= PENDULA_OK) cycles(:, :, i) = failed_output()
      end do
    end if
    call basin_table(period, winding, cyc, freq, tol, labels, natt, att_period, att_winding, att_theta, &
                     att_omega, att_mean_omega, status)
    if (status%code /= PENDULA_OK) then
      codes = status%code
      return
    end if
    call params_summary(codes, first_bad, msg, status, first_failed)
  end subroutine driven_basins

  !> The attractor table of a basin map from its states' periods, windings and
  !> strobe cycles (2, nmax, n), in state order: a state of period > 0 gets the
  !> label of the first attractor of its period and winding with a cycle point
  !> within 10 tol of its first strobe point, else a new one (BASIN_UNLISTED when
  !> the table is full); period 0 leaves BASIN_UNSETTLED.  Serial, so the labels
  !> depend neither on the threads nor on how the states were split into calls.
  pure subroutine basin_table(period, winding, cyc, freq, tol, labels, natt, att_period, att_winding, att_theta, &
                              att_omega, att_mean_omega, status)
    integer, intent(in) :: period(:)  !< period of each state's attractor (0: none), n
    integer, intent(in) :: winding(:)  !< its winding, n
    real(wp), intent(in) :: cyc(:, :, :)  !< strobe cycles (2, nmax, n) [rad, rad/s]
    real(wp), intent(in) :: freq(:)  !< drive frequencies Omega [rad/s], n or 1
    real(wp), intent(in) :: tol  !< settling tolerance [rad, rad/s]
    integer, intent(out) :: labels(:)  !< attractor label of each state, n
    integer, intent(out) :: natt  !< attractors in the table
    integer, intent(out) :: att_period(:)  !< period of each attractor (capacity = size)
    integer, intent(out) :: att_winding(:)  !< winding of each attractor
    real(wp), intent(out) :: att_theta(:)  !< strobe angle of smallest angle [rad]
    real(wp), intent(out) :: att_omega(:)  !< its angular velocity [rad/s]
    real(wp), intent(out) :: att_mean_omega(:)  !< mean angular velocity [rad/s]
    type(status_t), intent(out) :: status  !< PENDULA_OK, or PENDULA_ERR_MEMORY (the table's index not allocated)
    integer, allocatable :: first(:)   ! the state that opened each attractor
    real(wp) :: dmin
    integer :: i, a, k, j, cap, ios
    cap = size(att_period)
    labels = BASIN_UNSETTLED
    natt = 0
    att_period = 0
    att_winding = 0
    att_theta = 0
    att_omega = 0
    att_mean_omega = 0
    allocate (first(cap), stat=ios)
    if (ios /= 0) then
      call set_error(status, PENDULA_ERR_MEMORY, 'out of memory: the attractor table of '//format_int(cap)// &
                     ' entries could not be allocated')
      return
    end if
    do i = 1, size(period)
      if (period(i) == 0) cycle
      labels(i) = BASIN_UNLISTED
      do a = 1, natt
        if (att_period(a) /= period(i) .or. att_winding(a) /= winding(i)) cycle
        dmin = huge(1.0_wp)
        do k = 1, period(i)
          dmin = min(dmin, max(abs(wrap_angle(cyc(1, k, first(a)) - cyc(1, 1, i))), &
                               abs(cyc(2, k, first(a)) - cyc(2, 1, i))))
        end do
        if (dmin <= 10*tol) then
          labels(i) = a
          exit
        end if
      end do
      if (labels(i) == BASIN_UNLISTED .and. natt < cap) then
        natt = natt + 1
        labels(i) = natt
        att_period(natt) = period(i)
        att_winding(natt) = winding(i)
        first(natt) = i
        j = minloc(cyc(1, 1:period(i), i), 1)
        att_theta(natt) = cyc(1, j, i)
        att_omega(natt) = cyc(2, j, i)
        att_mean_omega(natt) = 2*pi*winding(i)*pick1(freq, i)/(2*pi*period(i))
      end if
    end do
  contains
    pure real(wp) function pick1(a, i)
      real(wp), intent(in) :: a(:)
      integer, intent(in) :: i
      pick1 = a(merge(i, 1, size(a) > 1))
    end function pick1
  end subroutine basin_table

  subroutine basin_block(p, idx, transient, nmax, tol, period, winding, cyc, codes, control)
    type(driven_params_t), intent(in) :: p
    integer, intent(in) :: idx(:), transient, nmax
    real(wp), intent(in) :: tol
    integer, intent(inout) :: period(:), winding(:), codes(:)
    real(wp), intent(inout) :: cyc(:, :, :)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    type(lanes_t) :: b
    logical :: go
    real(wp) :: y(nl), u(nl), c(2, nmax, nl)
    integer :: nb, l, per(nl), wnd(nl)
    logical :: dead(nl), cancelled
    nb = size(idx)
    call block_open(p, idx, 0.0_wp, b, y, u, codes, go, control)
    if (.not. go) return
    dead = .false.
    call detect(b, nb, y, u, transient, nmax, tol, per, wnd, c, dead, codes, idx, control, cancelled)
    if (cancelled) return
    do l = 1, nb
      if (dead(l)) cycle
      period(idx(l)) = per(l)
      winding(idx(l)) = wnd(l)
      cyc(:, :, idx(l)) = c(:, :, l)
      if (codes(idx(l)) == PENDULA_ERR_CANCELLED) codes(idx(l)) = PENDULA_OK
    end do
    if (present(control)) call add_progress(control, int(nb, int64))
  end subroutine basin_block

end module pendula_driven_orbits
