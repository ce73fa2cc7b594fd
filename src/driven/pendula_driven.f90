!> The driven damped pendulum (pendula_drive) by fixed-step RK4 with an
!> integer number N of steps per drive period: one state (driven_solve) or
!> many per call (driven_batch_solve: blocks of DRIVEN_LANES states on OpenMP
!> threads, bit-identical to driven_solve state by state).
!>
!> The grid times are t0 + (k + j/N) T with k and j integers, so the drive
!> phase at every stage is exact however many periods run; an output time
!> between grid times is reached by one shorter RK4 step from the grid
!> state before it (the grid itself is never moved).  Accuracy O(h**4),
!> h = T/N; the optional Richardson estimate runs the call again with 2 N
!> steps and reports |x_N - x_2N| * 16/15, the error of the N-step answer.
module pendula_driven
  use, intrinsic :: iso_fortran_env, only: int64
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_int, format_general
  use pendula_constants, only: pi
  use pendula_status, only: status_t, set_error, check_alloc, check_increasing, check_size, check_same_size, PENDULA_OK, &
                            PENDULA_ERR_SOLVER, PENDULA_ERR_CANCELLED, PENDULA_ERR_SIZE, PENDULA_ERR_DOMAIN
  use pendula_control, only: CONTROL_SIZE, cancel_requested, add_progress
  use pendula_batch_support, only: batch_threads, failed_output, nan_failed
  use pendula_drive, only: drive_t, DRIVEN_DEFAULT_STEPS
  use pendula_driven_kernel, only: DRIVEN_LANES, lanes_t, lanes_steps, lanes_partial, lanes_finite
  use pendula_driven_support, only: driven_params_t, params_check, params_prepare, &
                                    params_summary, block_open
  implicit none
  private
  public :: driven_solve, driven_batch_solve

  integer, parameter :: nl = DRIVEN_LANES
  !> Most RK4 grid steps one state of a call may take (the f2py glue's calls stay below a minute or so).
  real(wp), parameter, public :: DRIVEN_MAX_GRID_STEPS = 2.0e9_wp
  !> Lane steps between two polls of the cancel flag (~0.3 ms).
  integer(i8), parameter :: poll_every = 4096

contains

  !> theta(t) [rad] and Omega(t) [rad/s] of one driven pendulum at the output
  !> times t(:) [s] (finite, strictly increasing; t(1) is the start time t0,
  !> where theta(1) = theta0, omega(1) = omega0).  w0 > 0 and gamma >= 0
  !> [1/s]; nsteps RK4 steps per drive period (default DRIVEN_DEFAULT_STEPS,
  !> in [DRIVEN_MIN_STEPS, DRIVEN_MAX_STEPS]).  err_theta, err_omega
  !> (optional): Richardson estimates of the error of theta and omega (a
  !> second run with 2 nsteps).  status: bad argument, too few steps
  !> (PENDULA_ERR_UNSTABLE), or PENDULA_ERR_SOLVER when the state overflows.
  subroutine driven_solve(t, theta0, omega0, w0, gamma, drive, theta, omega, status, nsteps, err_theta, err_omega)
    real(wp), intent(in) :: t(:)  !< output times [s], finite, strictly increasing, size >= 1
    real(wp), intent(in) :: theta0  !< initial angle [rad] at t(1)
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s] at t(1)
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], > 0
    real(wp), intent(in) :: gamma  !< damping rate [1/s], >= 0
    type(drive_t), intent(in) :: drive  !< the drive
    real(wp), intent(out) :: theta(:)  !< theta at t [rad], size(t)
    real(wp), intent(out) :: omega(:)  !< Omega at t [rad/s], size(t)
    type(status_t), intent(out) :: status  !< error code and message (PENDULA_OK on success)
    integer, intent(in), optional :: nsteps  !< RK4 steps per drive period
    real(wp), intent(out), optional :: err_theta(:)  !< error estimate of theta [rad], size(t)
    real(wp), intent(out), optional :: err_omega(:)  !< error estimate of omega [rad/s], size(t)
    real(wp) :: th(size(theta), 1), om(size(omega), 1), et(size(theta), 1), eo(size(omega), 1)
    integer :: codes(1), n
    n = DRIVEN_DEFAULT_STEPS
    if (present(nsteps)) n = nsteps
    if (size(theta) /= size(t) .or. size(omega) /= size(t)) then
      call set_error(status, PENDULA_ERR_SIZE, 'theta and omega must have the size of t ('// &
                     format_int(size(t))//')')
      return
    end if
    if (present(err_theta) .or. present(err_omega)) then
      call driven_batch_solve(t, [theta0], [omega0], [w0], [gamma], drive%kind, [drive%amplitude], &
                              [drive%frequency], [drive%phase], n, th, om, codes, status, threads=1, err_theta=et, err_omega=eo)
      if (present(err_theta)) err_theta = et(:, 1)
      if (present(err_omega)) err_omega = eo(:, 1)
    else
      call driven_batch_solve(t, [theta0], [omega0], [w0], [gamma], drive%kind, [drive%amplitude], &
                              [drive%frequency], [drive%phase], n, th, om, codes, status, threads=1)
    end if
    theta = th(:, 1)
    omega = om(:, 1)
    if (index(status%message, 'state 1 of 1 ') == 1) then   ! the batch's 'state 1 of 1' prefix is noise here
      status%message = status%message(index(status%message, ': ') + 2:)
    end if
  end subroutine driven_solve

  !> driven_solve for n = size(theta0) states in one call: theta(:, i),
  !> omega(:, i) (shape (size(t), n)) of state i, bit-identical to
  !> driven_solve for that state alone.  omega0, w0, gamma, amp, freq and
  !> phase have n elements or one (shared); kind (DRIVE_TORQUE or
  !> DRIVE_PIVOT) and nsteps are shared.  codes(i): state i's status code (a
  !> failed state's outputs are NaN, failed_output of pendula_batch_support;
  !> every output of a refused call too); status: OK, cancelled, or the first
  !> failed state's code and message.  threads: OpenMP threads (0: default);
  !> control (optional, pendula_control): cancel flag, progress = finished
  !> states.  err_theta, err_omega (optional, shaped like theta): Richardson
  !> error estimates (a second pass with 2 nsteps).
  subroutine driven_batch_solve(t, theta0, omega0, w0, gamma, kind, amp, freq, phase, nsteps, theta, omega, &
                                codes, status, threads, control, first_failed, err_theta, err_omega)
    real(wp), intent(in) :: t(:)  !< output times [s], finite, strictly increasing, size >= 1
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad] at t(1), n = size(theta0)
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], n or 1
    real(wp), intent(in) :: w0(:)  !< small-angle angular frequencies [1/s], > 0, n or 1
    real(wp), intent(in) :: gamma(:)  !< damping rates [1/s], >= 0, n or 1
    integer, intent(in) :: kind  !< DRIVE_TORQUE or DRIVE_PIVOT
    real(wp), intent(in) :: amp(:)  !< drive amplitudes (F in rad/s**2, or a/l), n or 1
    real(wp), intent(in) :: freq(:)  !< drive frequencies Omega [rad/s], > 0, n or 1
    real(wp), intent(in) :: phase(:)  !< drive phases phi [rad], n or 1
    integer, intent(in) :: nsteps  !< RK4 steps per drive period
    real(wp), intent(out) :: theta(:, :)  !< angles [rad], shape (size(t), n)
    real(wp), intent(out) :: omega(:, :)  !< angular velocities [rad/s], shape (size(t), n)
    integer, intent(out) :: codes(:)  !< status code of each state, n elements
    type(status_t), intent(out) :: status  !< error code and message (PENDULA_OK on success)
    integer, intent(in), optional :: threads  !< OpenMP threads (0 or absent: the OpenMP default)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag and progress counter (finished states)
    integer, intent(out), optional :: first_failed  !< first failed state (0: none)
    real(wp), intent(out), optional :: err_theta(:, :)  !< Richardson error of theta [rad], like theta
    real(wp), intent(out), optional :: err_omega(:, :)  !< Richardson error of omega [rad/s], like omega
    type(driven_params_t) :: p
    integer, allocatable :: live(:)
    integer :: nlive, nblocks, b, first_bad, nth, i, ist
    character(len=len(status%message)) :: msg
    logical :: richardson
    real(wp), allocatable :: th2(:, :), om2(:, :)
    type(status_t) :: tables
    if (present(first_failed)) first_failed = 0
    richardson = present(err_theta) .or. present(err_omega)
    call params_check(kind, nsteps, theta0, omega0, w0, gamma, amp, freq, phase, threads, p, status)
    call check_increasing('t', t, status)
    call check_size('t', size(t), 1, status)
    call check_same_size('codes', size(codes), 'theta0', size(theta0), status)
    call check_same_size('theta columns', size(theta, 2), 'theta0', size(theta0), status)
    call check_same_size('omega columns', size(omega, 2), 'theta0', size(theta0), status)
    call check_same_size('theta rows', size(theta, 1), 't', size(t), status)
    call check_same_size('omega rows', size(omega, 1), 't', size(t), status)
    if (present(err_theta)) call check_same_size('err_theta', size(err_theta), 'theta', size(theta), status)
    if (present(err_omega)) call check_same_size('err_omega', size(err_omega), 'omega', size(omega), status)
    theta = 0
    omega = 0
    if (present(err_theta)) err_theta = 0
    if (present(err_omega)) err_omega = 0
    ! the step budget: at most DRIVEN_MAX_GRID_STEPS grid steps for any state
    if (status%code == PENDULA_OK .and. p%n > 0) then
      if (.not. (t(size(t)) - t(1))*maxval(freq)/(2*pi)*nsteps <= DRIVEN_MAX_GRID_STEPS) &
        call set_error(status, PENDULA_ERR_DOMAIN, 't spans '//format_general(t(size(t)) - t(1), 6)// &
                       ' s: more than '//format_general(DRIVEN_MAX_GRID_STEPS, 3)//' RK4 steps at '//format_int(nsteps)// &
                       ' steps per drive period; split the window')
    end if
    if (status%code /= PENDULA_OK) then
      call refuse_all()
      return
    end if
    if (richardson) then
      allocate (th2(size(t), p%n), om2(size(t), p%n), stat=ist)
      call check_alloc(ist, 'the Richardson half-step run''s theta and omega', 2_i8*size(t, kind=i8)*p%n, 8, status)
      if (status%code /= PENDULA_OK) then
        call refuse_all()
        return
      end if
      th2 = 0
      om2 = 0
    end if
    nth = batch_threads(threads)
    call params_prepare(p, codes, live, nlive, first_bad, msg, status)
    if (status%code /= PENDULA_OK) then
      call refuse_all()
      return
    end if
    nblocks = (nlive + nl - 1)/nl
    !$omp parallel do schedule(dynamic) num_threads(nth) if(nth > 1 .and. nblocks > 1) default(shared)
    do b = 1, nblocks
      call run_block(p, t, live((b - 1)*nl + 1:min(b*nl, nlive)), p%nsteps, theta, omega, codes, control)
      if (richardson) then
        where (codes(live((b - 1)*nl + 1:min(b*nl, nlive))) == PENDULA_OK) &
          codes(live((b - 1)*nl + 1:min(b*nl, nlive))) = PENDULA_ERR_CANCELLED
        call run_block(p, t, live((b - 1)*nl + 1:min(b*nl, nlive)), 2*p%nsteps, th2, om2, &
                       codes, control)
      end if
    end do
    !$omp end parallel do
    if (richardson) then
      do i = 1, p%n
        if (codes(i) /= PENDULA_OK) cycle
        if (present(err_theta)) err_theta(:, i) = abs(theta(:, i) - th2(:, i))*(16.0_wp/15)
        if (present(err_omega)) err_omega(:, i) = abs(omega(:, i) - om2(:, i))*(16.0_wp/15)
      end do
    end if
    call nan_failed(codes, theta)
    call nan_failed(codes, omega)
    if (present(err_theta)) call nan_failed(codes, err_theta)
    if (present(err_omega)) call nan_failed(codes, err_omega)
    ! the message of a block whose drive tables could not be allocated (run_block)
    tables = status_t()
    call check_alloc(1, 'the drive tables of a block of lanes', 2_i8*nl*(2_i8*p%nsteps + 1), 8, tables)
    call params_summary(codes, first_bad, msg, status, first_failed, tables%message)

  contains

    ! the call refused as a whole: every state gets its code, every output NaN
    subroutine refuse_all()
      if (status%code /= PENDULA_OK) codes = status%code
      theta = failed_output()
      omega = failed_output()
      if (present(err_theta)) err_theta = failed_output()
      if (present(err_omega)) err_omega = failed_output()
    end subroutine refuse_all
  end subroutine driven_batch_solve

  ! The states idx(:) as one block of lanes, stepping the grid and emitting
  ! each lane's outputs as the grid passes them.
  subroutine run_block(p, t, idx, nsteps, theta, omega, codes, control)
    type(driven_params_t), intent(in) :: p
    real(wp), intent(in) :: t(:)
    integer, intent(in) :: idx(:), nsteps
    real(wp), intent(inout) :: theta(:, :), omega(:, :)
    integer, intent(inout) :: codes(:)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    type(lanes_t) :: b
    real(wp) :: y(nl), u(nl), fr(nl)
    integer(i8) :: cnt, mk(nl), work
    integer :: nxt(nl), nb, l, j, nt, chunk
    logical :: alive(nl), go
    nb = size(idx)
    nt = size(t)
    call block_open(p, idx, t(1), b, y, u, codes, go, control, nsteps)
    if (.not. go) return
    nxt = 1
    alive = .false.
    alive(1:nb) = .true.
    cnt = 0
    j = 0
    work = 0
    do l = 1, nb
      call next_output(l)
    end do
    do
      ! emit every output on the current grid point (a partial step from it)
      do l = 1, nb
        do while (alive(l) .and. mk(l) == cnt)
          call lanes_partial(b, l, j, fr(l), y(l), u(l), theta(nxt(l), idx(l)), omega(nxt(l), idx(l)))
          nxt(l) = nxt(l) + 1
          call next_output(l)
        end do
      end do
      if (.not. any(alive)) exit
      ! step to the next output of any lane or the end of the period, whichever is first
      chunk = int(min(int(nsteps - j, i8), minval(mk(1:nb) - cnt, mask=alive(1:nb))))
      call lanes_steps(b, j, j + chunk, y, u)
      cnt = cnt + chunk
      j = j + chunk
      if (j == nsteps) then
        j = 0
        call check_lanes()
        if (.not. any(alive)) exit
      end if
      work = work + chunk
      if (present(control) .and. work >= poll_every) then
        work = 0
        if (cancel_requested(control)) return   ! codes stay PENDULA_ERR_CANCELLED
      end if
    end do
    call check_lanes()
    do l = 1, nb
      if (codes(idx(l)) == PENDULA_ERR_CANCELLED) codes(idx(l)) = PENDULA_OK
    end do
    if (present(control)) call add_progress(control, int(nb, int64))
  contains
    ! grid step count mk(l) and step fraction fr(l) of lane l's next output
    ! (none left: the lane is done)
    subroutine next_output(k)
      integer, intent(in) :: k
      real(wp) :: r
      if (nxt(k) > nt) then
        alive(k) = .false.
        mk(k) = huge(mk(k))
        return
      end if
      r = (t(nxt(k)) - t(1))/b%h(k)
      mk(k) = int(r, i8)
      fr(k) = r - real(mk(k), wp)
    end subroutine next_output
    subroutine check_lanes()
      logical :: ok(nl)
      integer :: k
      ok = lanes_finite(y, u)
      do k = 1, nb
        if (.not. ok(k) .and. codes(idx(k)) == PENDULA_ERR_CANCELLED) then
          codes(idx(k)) = PENDULA_ERR_SOLVER
          alive(k) = .false.
          mk(k) = huge(mk(k))
        end if
      end do
      where (.not. ok)
        y = 0
        u = 0
      end where
    end subroutine check_lanes
  end subroutine run_block

end module pendula_driven
