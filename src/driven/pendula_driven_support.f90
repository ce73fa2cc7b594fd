!> What every batch procedure of the driven pendulum shares: the checks of a
!> call and of each state, the lanes of a block, and the call's summary
!> status.  A batch takes n states: theta0(n) and omega0, w0, gamma and the
!> drive's amplitude, frequency and phase each with n elements or one
!> (shared); the drive kind and the steps per period are the call's.
module pendula_driven_support
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
  use pendula_kinds, only: wp
  use pendula_constants, only: pi
  use pendula_format, only: format_int, format_general
  use, intrinsic :: iso_fortran_env, only: int64
  use pendula_kinds, only: i8
  use pendula_control, only: CONTROL_SIZE, cancel_requested
  use pendula_status, only: status_t, set_error, check_finite, check_alloc, PENDULA_OK, PENDULA_ERR_SIZE, &
                            PENDULA_ERR_DOMAIN, PENDULA_ERR_CANCELLED, PENDULA_ERR_UNSTABLE, PENDULA_ERR_MEMORY
  use pendula_drive, only: drive_t, check_driven, check_drive_kind
  use pendula_batch_support, only: set_batch_error
  use pendula_driven_kernel, only: DRIVEN_LANES, lanes_t, lanes_setup
  implicit none
  private
  public :: driven_params_t, params_check, params_state, params_prepare, params_lanes, block_open, &
            params_summary, wrap_angle, pick

  !> The parameters of a batch call (pointers-free copies of the caller's arrays).
  type :: driven_params_t
    integer :: kind = 1, nsteps = 0, n = 0
    real(wp), allocatable :: theta0(:), omega0(:), w0(:), gamma(:), amp(:), freq(:), phase(:)
  end type driven_params_t

contains

  !> Element i of a batch array of one element or n.
  pure real(wp) function pick(a, i)
    real(wp), intent(in) :: a(:)  !< batch array of one element or n
    integer, intent(in) :: i  !< state index
    pick = a(merge(i, 1, size(a) > 1))
  end function pick

  !> theta wrapped to (-pi, pi] [rad].
  elemental real(wp) function wrap_angle(theta)
    real(wp), intent(in) :: theta  !< angle [rad], finite
    wrap_angle = theta - 2*pi*anint(theta/(2*pi))
    if (wrap_angle <= -pi) wrap_angle = wrap_angle + 2*pi
    if (wrap_angle > pi) wrap_angle = wrap_angle - 2*pi
  end function wrap_angle

  !> Check the call as a whole (sizes, kind, threads) and copy its parameters.
  pure subroutine params_check(kind, nsteps, theta0, omega0, w0, gamma, amp, freq, phase, threads, p, status)
    integer, intent(in) :: kind  !< DRIVE_TORQUE or DRIVE_PIVOT
    integer, intent(in) :: nsteps  !< RK4 steps per drive period
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad], n = size(theta0) >= 0
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], n or 1
    real(wp), intent(in) :: w0(:)  !< small-angle angular frequencies [1/s], n or 1
    real(wp), intent(in) :: gamma(:)  !< damping rates [1/s], n or 1
    real(wp), intent(in) :: amp(:)  !< drive amplitudes, n or 1
    real(wp), intent(in) :: freq(:)  !< drive frequencies [rad/s], n or 1
    real(wp), intent(in) :: phase(:)  !< drive phases [rad], n or 1
    integer, intent(in), optional :: threads  !< the caller's OpenMP threads (0 or absent: the OpenMP default), >= 0
    type(driven_params_t), intent(out) :: p  !< the parameters
    type(status_t), intent(inout) :: status  !< receives the first error
    integer :: n, sz(6)
    character(len=6), parameter :: names(6) = ['omega0', 'w0    ', 'gamma ', 'amp   ', 'freq  ', 'phase ']
    integer :: i
    n = size(theta0)   ! 0: an empty batch, nothing to do
    call check_drive_kind(kind, status)
    if (status%code /= PENDULA_OK) return
    sz = [size(omega0), size(w0), size(gamma), size(amp), size(freq), size(phase)]
    do i = 1, 6
      if (sz(i) /= 1 .and. sz(i) /= n) then
        call set_error(status, PENDULA_ERR_SIZE, trim(names(i))//' has '//format_int(sz(i))// &
                       ' element(s): it must have one or as many as theta0 ('//format_int(n)//')')
        return
      end if
    end do
    if (present(threads)) then
      if (threads < 0) call set_error(status, PENDULA_ERR_DOMAIN, 'threads = '//format_int(threads)// &
                                      ' is out of range: it must be >= 0 (0: the OpenMP default)')
    end if
    if (status%code /= PENDULA_OK) return
    p%kind = kind
    p%nsteps = nsteps
    p%n = n
    p%theta0 = theta0
    p%omega0 = omega0
    p%w0 = w0
    p%gamma = gamma
    p%amp = amp
    p%freq = freq
    p%phase = phase
  end subroutine params_check

  !> Check state i alone: its initial state, w0, gamma, drive and the steps
  !> per period (pendula_drive's check_driven).
  pure subroutine params_state(p, i, status)
    type(driven_params_t), intent(in) :: p  !< the call's parameters
    integer, intent(in) :: i  !< state index
    type(status_t), intent(out) :: status  !< OK, or the state's first error
    real(wp) :: h
    call check_finite('theta0', p%theta0(i), status)
    call check_finite('omega0', pick(p%omega0, i), status)
    call check_driven(pick(p%w0, i), pick(p%gamma, i), state_drive(p, i), p%nsteps, status)
    if (status%code /= PENDULA_OK) return
    ! the kernels' sine takes |theta| < 1e15 (pendula_driven_kernel); a start
    ! that turns by more than 1.5 rad in one step is not resolved
    if (.not. abs(p%theta0(i)) < 1.0e15_wp) call set_error(status, PENDULA_ERR_DOMAIN, 'theta0 = '// &
                                                   format_general(p%theta0(i), 15)//' is out of range: |theta0| must be < 1e15 rad')
    h = 2*pi/(pick(p%freq, i)*p%nsteps)
    if (.not. abs(pick(p%omega0, i))*h <= 1.5_wp) call set_error(status, PENDULA_ERR_UNSTABLE, 'omega0 = '// &
                             format_general(pick(p%omega0, i), 15)//' is too fast for steps_per_period = '//format_int(p%nsteps)// &
                                   ': |omega0| h must be <= 1.5 (h = 2 pi/(Omega steps_per_period) = '//format_general(h, 6)//' s)')
  end subroutine params_state

  !> Check every state: codes(i) = its status code (PENDULA_ERR_CANCELLED for
  !> a valid state, until its block finishes), live(1:nlive) = the valid
  !> states; first_bad and bad_msg: the first invalid state and its message.
  !> When the list of live states cannot be allocated, every state gets
  !> PENDULA_ERR_MEMORY (nlive = 0, first_bad = 1, bad_msg the reason with
  !> the size) and status (optional) receives it.
  pure subroutine params_prepare(p, codes, live, nlive, first_bad, bad_msg, status)
    type(driven_params_t), intent(in) :: p  !< the call's parameters
    integer, intent(out) :: codes(:)  !< status code of each state, size p%n
    integer, allocatable, intent(out) :: live(:)  !< the valid states (first nlive elements)
    integer, intent(out) :: nlive  !< number of valid states
    integer, intent(out) :: first_bad  !< first invalid state (0: none)
    character(len=*), intent(out) :: bad_msg  !< its message
    type(status_t), intent(inout), optional :: status  !< receives PENDULA_ERR_MEMORY when live cannot be allocated
    type(status_t) :: st
    integer :: i, ist
    nlive = 0
    first_bad = 0
    bad_msg = ''
    allocate (live(p%n), stat=ist)
    if (ist /= 0) then
      call check_alloc(ist, 'the batch''s list of live states', int(p%n, i8), 4, st)
      codes = st%code
      if (p%n > 0) first_bad = 1
      bad_msg = st%message
      if (present(status)) call check_alloc(ist, 'the batch''s list of live states', int(p%n, i8), 4, status)
      return
    end if
    do i = 1, p%n
      call params_state(p, i, st)
      codes(i) = st%code
      if (st%code == PENDULA_OK) then
        nlive = nlive + 1
        live(nlive) = i
        codes(i) = PENDULA_ERR_CANCELLED
      else if (first_bad == 0) then
        first_bad = i
        bad_msg = st%message
      end if
    end do
  end subroutine params_prepare

  !> The message for the call's summary: bad_msg when the first failed state
  !> is the first invalid one, else '' (a state that failed while running).
  pure function first_message(codes, first_bad, bad_msg) result(msg)
    integer, intent(in) :: codes(:)  !< status code of each state
    integer, intent(in) :: first_bad  !< first invalid state (0: none)
    character(len=*), intent(in) :: bad_msg  !< its message
    character(len=len(bad_msg)) :: msg
    integer :: i
    msg = ''
    if (first_bad == 0) return
    do i = 1, first_bad - 1
      if (codes(i) /= PENDULA_OK) return
    end do
    msg = bad_msg
  end function first_message

  ! state i's drive
  pure type(drive_t) function state_drive(p, i) result(d)
    type(driven_params_t), intent(in) :: p
    integer, intent(in) :: i
    d = drive_t(p%kind, pick(p%amp, i), pick(p%freq, i), pick(p%phase, i))
  end function state_drive

  !> A block of lanes for the states idx(:) (at most DRIVEN_LANES; lanes past
  !> size(idx) repeat the first state), started at time t0 [s]; their initial
  !> angles and angular velocities in y, u.  When the block's drive tables
  !> cannot be allocated (lanes_setup), status (optional) gets
  !> PENDULA_ERR_MEMORY with the size and y, u are NaN (a caller without
  !> status then sees its lanes fail as non-finite instead of crashing).
  pure subroutine params_lanes(p, idx, t0, b, y, u, nsteps, status)
    type(driven_params_t), intent(in) :: p  !< the call's parameters
    integer, intent(in) :: idx(:)  !< the block's states (valid ones)
    real(wp), intent(in) :: t0  !< start time [s]
    type(lanes_t), intent(inout) :: b  !< the block
    real(wp), intent(out) :: y(DRIVEN_LANES)  !< initial angles [rad]
    real(wp), intent(out) :: u(DRIVEN_LANES)  !< initial angular velocities [rad/s]
    integer, intent(in), optional :: nsteps  !< steps per period other than p%nsteps
    type(status_t), intent(inout), optional :: status  !< receives PENDULA_ERR_MEMORY when the tables cannot be allocated
    real(wp), dimension(DRIVEN_LANES) :: w0, gam, amp, freq, ph
    type(status_t) :: st
    integer :: l, s
    do l = 1, DRIVEN_LANES
      s = idx(min(l, size(idx)))
      y(l) = p%theta0(s)
      u(l) = pick(p%omega0, s)
      w0(l) = pick(p%w0, s)
      gam(l) = pick(p%gamma, s)
      amp(l) = pick(p%amp, s)
      freq(l) = pick(p%freq, s)
      ! the drive phase at t0, reduced to [0, 2 pi) (the tables add integer steps to it)
      ph(l) = modulo(freq(l)*t0 + pick(p%phase, s), 2*pi)
    end do
    if (present(nsteps)) then
      call lanes_setup(b, p%kind, nsteps, w0, gam, amp, freq, ph, st)
    else
      call lanes_setup(b, p%kind, p%nsteps, w0, gam, amp, freq, ph, st)
    end if
    if (st%code /= PENDULA_OK) then
      y = ieee_value(y, ieee_quiet_nan)
      u = y
      if (present(status)) call set_error(status, st%code, st%message)
    end if
  end subroutine params_lanes

  !> Open a block of lanes as params_lanes does, or say there is nothing to run
  !> (go = .false.): no states, the call cancelled, or the block's drive tables
  !> could not be allocated (then its states' codes are PENDULA_ERR_MEMORY).
  subroutine block_open(p, idx, t0, b, y, u, codes, go, control, nsteps)
    type(driven_params_t), intent(in) :: p  !< the call's parameters
    integer, intent(in) :: idx(:)  !< the state of each lane (valid ones; may repeat)
    real(wp), intent(in) :: t0  !< start time [s]
    type(lanes_t), intent(inout) :: b  !< the block
    real(wp), intent(out) :: y(DRIVEN_LANES)  !< initial angles [rad]
    real(wp), intent(out) :: u(DRIVEN_LANES)  !< initial angular velocities [rad/s]
    integer, intent(inout) :: codes(:)  !< status code of each state of the call
    logical, intent(out) :: go  !< whether the block runs
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< cancel flag and progress
    integer, intent(in), optional :: nsteps  !< steps per period other than p%nsteps
    type(status_t) :: st
    integer :: l
    go = .false.
    if (size(idx) == 0) return
    if (present(control)) then
      if (cancel_requested(control)) return
    end if
    call params_lanes(p, idx, t0, b, y, u, nsteps, st)
    if (st%code /= PENDULA_OK) then
      do l = 1, size(idx)   ! idx may repeat a state: no vector-subscript assignment
        codes(idx(l)) = st%code
      end do
      return
    end if
    go = .true.
  end subroutine block_open

  !> The call's status from its per-state codes: OK; cancelled; or the first
  !> failed state's code with its message (bad_msg when it is the first
  !> invalid state, first_bad, of params_prepare).  A state whose block could
  !> not allocate its drive tables has PENDULA_ERR_MEMORY; its message
  !> (memory_msg, optional) is then the summary's.  first_failed (the
  !> caller's optional argument): the first failed state (0: none).
  pure subroutine params_summary(codes, first_bad, bad_msg, status, first_failed, memory_msg)
    integer, intent(in) :: codes(:)  !< status code of each state
    integer, intent(in) :: first_bad  !< first invalid state (params_prepare; 0: none)
    character(len=*), intent(in) :: bad_msg  !< its message
    type(status_t), intent(inout) :: status  !< receives the summary
    integer, intent(out), optional :: first_failed  !< the caller's first failed state (0: none)
    character(len=*), intent(in), optional :: memory_msg  !< message of a failed table allocation
    character(len=len(bad_msg)) :: first_msg
    integer :: i, first
    first = 0
    do i = 1, size(codes)
      if (codes(i) /= PENDULA_OK) then
        first = i
        exit
      end if
    end do
    if (present(first_failed)) first_failed = first
    if (first == 0) return
    first_msg = first_message(codes, first_bad, bad_msg)
    if (len_trim(first_msg) > 0 .or. any(codes == PENDULA_ERR_CANCELLED)) then
      call set_batch_error(status, codes, first, first_msg)
    else if (codes(first) == PENDULA_ERR_MEMORY .and. present(memory_msg)) then
      call set_batch_error(status, codes, first, memory_msg)
    else if (codes(first) == PENDULA_ERR_MEMORY) then
      call set_batch_error(status, codes, first, &
                           'out of memory: the drive tables of its block of lanes could not be allocated')
    else
      call set_batch_error(status, codes, first, 'the state became non-finite or left |theta| < 1e15 rad')
    end if
  end subroutine params_summary

end module pendula_driven_support
