! f2py-facing layer for the ensemble (batch) kernels (pendula_rk4_batch,
! pendula_cvode_batch).
! Plain subroutines, c_double/c_int explicit-shape arguments, a status code +
! message.  Its own extension (pendula._ensemble) so that the batch glue does
! not grow the single-state integrate extension.  threadsafe: f2py releases
! the GIL for the call, so other Python threads (a watcher raising the cancel
! flag in `control`, other batch calls) run meanwhile.  No numerics here.

subroutine rk4_batch_f2py(nt, n, no, nw, ng, nh, t, theta0, omega0, w0, gamma, h, max_steps, threads, control, &
                          theta, omega, codes, steps, first_failed, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, status_unpack, check_alloc
  use pendula_rk4_batch, only: rk4_batch_solve
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: nt, n, no, nw, ng, nh, threads
  real(c_double), intent(in) :: t(nt), theta0(n), omega0(no), w0(nw), gamma(ng), h(nh)
  ! the per-state step budget as a double (rk4_f2py's convention), already >= 1
  real(c_double), intent(in) :: max_steps
  ! int64: the cancel flag and progress counter (pendula_control), shared with
  ! the caller's thread while the call runs
  integer(8), intent(inout) :: control(2)
  ! inout: the caller allocates them uninitialised (numpy.empty) and every
  ! element is written here; f2py would zero-fill an intent(out) array, one
  ! more pass over memory that then faults in on the calling thread alone
  real(c_double), intent(inout) :: theta(nt, n), omega(nt, n)
  real(c_double), intent(out) :: steps(n)
  integer(c_int), intent(out) :: codes(n), first_failed, code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer(i8), allocatable :: nsteps(:)   ! heap: n may be 1e7
  integer :: first, ist
  allocate (nsteps(n), stat=ist)
  if (ist /= 0) then
    ! the whole call is refused (first_failed = 0): Python raises MemoryError
    call check_alloc(ist, 'the step counts', int(n, i8), 8, st)
    theta = 0
    omega = 0
    codes = st%code
    steps = 0
    first_failed = 0
    call status_unpack(st, code, msg)
    return
  end if
  call rk4_batch_solve(t, theta0, omega0, w0, gamma, h, theta, omega, codes, nsteps, st, &
                       threads=int(threads), control=control, first_failed=first, max_steps=int(max_steps, i8))
  steps = real(nsteps, c_double)
  first_failed = first
  call status_unpack(st, code, msg)
end subroutine rk4_batch_f2py

subroutine rk4_batch_openmp_f2py(flag)
  use, intrinsic :: iso_c_binding, only: c_int
  use pendula_rk4_batch, only: rk4_batch_openmp
  implicit none
  !f2py threadsafe
  integer(c_int), intent(out) :: flag
  flag = merge(1, 0, rk4_batch_openmp())
end subroutine rk4_batch_openmp_f2py

! The kernel path this process runs (pendula_dispatch: 0 baseline, 1 v3,
! 2 v4) and which paths this build and CPU offer (available(p+1) = 1).
subroutine kernel_path_f2py(path, available)
  use, intrinsic :: iso_c_binding, only: c_int
  use pendula_dispatch, only: kernel_path, kernel_path_available, KERNEL_BASELINE, KERNEL_V4
  implicit none
  !f2py threadsafe
  integer(c_int), intent(out) :: path, available(3)
  integer :: p
  path = kernel_path()
  do p = KERNEL_BASELINE, KERNEL_V4
    available(p + 1) = merge(1, 0, kernel_path_available(p))
  end do
end subroutine kernel_path_f2py

subroutine cvode_batch_f2py(nt, n, no, nw, ng, nr, na, t, theta0, omega0, w0, gamma, rtol, atol, method, &
                            max_steps, threads, control, theta, omega, codes, stats, first_failed, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, status_unpack, check_alloc
  use pendula_ode, only: ode_stats_t, ode_stats_values, step_budget
  use pendula_cvode_batch, only: cvode_batch_solve
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: nt, n, no, nw, ng, nr, na, method, threads
  real(c_double), intent(in) :: t(nt), theta0(n), omega0(no), w0(nw), gamma(ng), rtol(nr), atol(na), max_steps
  integer(8), intent(inout) :: control(2)   ! cancel flag and progress (pendula_control)
  real(c_double), intent(out) :: theta(nt, n), omega(nt, n), stats(7, n)
  integer(c_int), intent(out) :: codes(n), first_failed, code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(ode_stats_t), allocatable :: s(:)   ! heap: n may be 1e7
  integer(i8) :: budget
  integer :: first, i, ist
  allocate (s(n), stat=ist)
  if (ist /= 0) then
    ! the whole call is refused (first_failed = 0): Python raises MemoryError
    call check_alloc(ist, 'the CVODE counters', 7_i8*n, 8, st)
    theta = 0
    omega = 0
    codes = st%code
    stats = 0
    first_failed = 0
    call status_unpack(st, code, msg)
    return
  end if
  ! max_steps arrives as a double (Python int of any size); step_budget clamps it to int64.
  budget = step_budget(max_steps)
  call cvode_batch_solve(t, theta0, omega0, w0, gamma, rtol, atol, int(method), budget, theta, omega, codes, &
                         s, st, threads=int(threads), control=control, first_failed=first)
  do i = 1, n
    stats(:, i) = ode_stats_values(s(i))
  end do
  first_failed = first
  call status_unpack(st, code, msg)
end subroutine cvode_batch_f2py

! rk4_batch_f2py with drives: kind, amp, freq and phase (pendula_drive) each
! with nd elements, nd = 1 (one drive for all) or n (one per state).
subroutine rk4_batch_drive_f2py(nt, n, no, nw, ng, nh, nd, t, theta0, omega0, w0, gamma, h, dkind, amp, freq, phase, &
                                max_steps, threads, control, theta, omega, codes, steps, first_failed, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, status_unpack, check_alloc
  use pendula_rk4_batch, only: rk4_batch_solve
  use pendula_drive, only: drive_t
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: nt, n, no, nw, ng, nh, nd, threads
  real(c_double), intent(in) :: t(nt), theta0(n), omega0(no), w0(nw), gamma(ng), h(nh)
  integer(c_int), intent(in) :: dkind(nd)
  real(c_double), intent(in) :: amp(nd), freq(nd), phase(nd), max_steps
  integer(8), intent(inout) :: control(2)   ! cancel flag and progress (pendula_control)
  real(c_double), intent(inout) :: theta(nt, n), omega(nt, n)   ! as rk4_batch_f2py's
  real(c_double), intent(out) :: steps(n)
  integer(c_int), intent(out) :: codes(n), first_failed, code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  integer(i8), allocatable :: nsteps(:)
  type(drive_t), allocatable :: d(:)
  integer :: first, ist, i
  allocate (nsteps(n), d(nd), stat=ist)
  if (ist /= 0) then
    call check_alloc(ist, 'the step counts and drives', int(n, i8) + 4_i8*nd, 8, st)
    theta = 0
    omega = 0
    codes = st%code
    steps = 0
    first_failed = 0
    call status_unpack(st, code, msg)
    return
  end if
  do i = 1, nd
    d(i) = drive_t(int(dkind(i)), amp(i), freq(i), phase(i))
  end do
  call rk4_batch_solve(t, theta0, omega0, w0, gamma, h, theta, omega, codes, nsteps, st, &
                       threads=int(threads), control=control, first_failed=first, max_steps=int(max_steps, i8), drive=d)
  steps = real(nsteps, c_double)
  first_failed = first
  call status_unpack(st, code, msg)
end subroutine rk4_batch_drive_f2py

! cvode_batch_f2py with drives (as rk4_batch_drive_f2py).
subroutine cvode_batch_drive_f2py(nt, n, no, nw, ng, nr, na, nd, t, theta0, omega0, w0, gamma, rtol, atol, dkind, amp, &
                                  freq, phase, method, max_steps, threads, control, theta, omega, codes, stats, &
                                  first_failed, code, msg)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, status_unpack, check_alloc
  use pendula_ode, only: ode_stats_t, ode_stats_values, step_budget
  use pendula_cvode_batch, only: cvode_batch_solve
  use pendula_drive, only: drive_t
  implicit none
  include 'pendula_msg_len.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: nt, n, no, nw, ng, nr, na, nd, method, threads
  real(c_double), intent(in) :: t(nt), theta0(n), omega0(no), w0(nw), gamma(ng), rtol(nr), atol(na), max_steps
  integer(c_int), intent(in) :: dkind(nd)
  real(c_double), intent(in) :: amp(nd), freq(nd), phase(nd)
  integer(8), intent(inout) :: control(2)   ! cancel flag and progress (pendula_control)
  real(c_double), intent(out) :: theta(nt, n), omega(nt, n), stats(7, n)
  integer(c_int), intent(out) :: codes(n), first_failed, code
  character(len=PENDULA_MSG_LEN), intent(out) :: msg
  type(status_t) :: st
  type(ode_stats_t), allocatable :: s(:)
  type(drive_t), allocatable :: d(:)
  integer(i8) :: budget
  integer :: first, i, ist
  allocate (s(n), d(nd), stat=ist)
  if (ist /= 0) then
    call check_alloc(ist, 'the CVODE counters and drives', 7_i8*n + 4_i8*nd, 8, st)
    theta = 0
    omega = 0
    codes = st%code
    stats = 0
    first_failed = 0
    call status_unpack(st, code, msg)
    return
  end if
  do i = 1, nd
    d(i) = drive_t(int(dkind(i)), amp(i), freq(i), phase(i))
  end do
  budget = step_budget(max_steps)
  call cvode_batch_solve(t, theta0, omega0, w0, gamma, rtol, atol, int(method), budget, theta, omega, codes, &
                         s, st, threads=int(threads), control=control, first_failed=first, drive=d)
  do i = 1, n
    stats(:, i) = ode_stats_values(s(i))
  end do
  first_failed = first
  call status_unpack(st, code, msg)
end subroutine cvode_batch_drive_f2py
