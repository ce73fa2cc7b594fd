!> Classic RK4 (pendula_rk4) for many pendulums in one call: each state i has
!> its own theta0(i), omega0(i), w0(i), gamma(i) and step h(i); the output
!> grid t is shared.  Results are bit-identical to rk4_solve for the same
!> state, so a batch answer never depends on which other states came with it.
!>
!> Why a separate kernel: rk4_grid's step is a dependent chain (two chained
!> stage sines per recurrence) and so bound by latency.  Here the
!> states run in structure-of-arrays blocks of RK4_BATCH_LANES lanes (128 on
!> x86-64-v4: pendula_dispatch's rk4_lanes_width); one
!> step of a block is a loop over lanes with no dependence between them, which
!> gcc vectorises and whose independent chains fill the pipeline.  The block
!> kernel lives in pendula_rk4_lanes.F90, compiled for each instruction set
!> (SSE2, AVX2, AVX-512 on x86-64) and chosen at load time from the CPU
!> (pendula_dispatch).  Each lane performs exactly the operations of rk4_grid
!> in the same order (the same text, included; no reassociation, since
!> pendula never uses -ffast-math, and no FMA contraction: meson.build passes
!> -ffp-contract=off), so every path gives the same bits.  A lane whose stage
!> offsets leave the table's range takes rk4_grid's plain libm step, alone.
!>
!> Blocks are spread over OpenMP threads (when built with -Dopenmp); a cancel
!> flag (pendula_control) is polled about every 0.25 ms of work.
module pendula_rk4_batch
  use, intrinsic :: iso_fortran_env, only: int64
  use, intrinsic :: iso_c_binding, only: c_int
  use pendula_kinds, only: wp, i8
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use pendula_format, only: format_int
  use pendula_status, only: status_t, set_error, check_alloc, PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_NONFINITE, &
                            PENDULA_ERR_SOLVER, PENDULA_ERR_CANCELLED, PENDULA_ERR_SIZE
  use pendula_control, only: CONTROL_SIZE, CONTROL_CANCEL, add_progress
  use pendula_ode, only: check_problem, check_batch_shapes, at => batch_index
  use pendula_rk4, only: rk4_solve, check_step, RK4_DEFAULT_MAX_STEPS, check_driven_step, driven_step_count
  use pendula_drive, only: drive_t
  use pendula_driven, only: driven_batch_solve
  use pendula_ode, only: ode_stats_t
  use pendula_batch_support, only: batch_threads, set_batch_error, failed_output, nan_failed
  use pendula_rk4_kernel, only: RK4_BATCH_LANES
  use pendula_dispatch, only: rk4_lanes, rk4_lanes_width
  implicit none
  private
  public :: rk4_batch_solve, rk4_batch_openmp, RK4_BATCH_LANES

contains

  !> True when this build runs batch blocks on OpenMP threads.
  logical function rk4_batch_openmp()
    rk4_batch_openmp = .false.
!$  rk4_batch_openmp = .true.
  end function rk4_batch_openmp

  !> RK4 for n = size(theta0) states over the shared output grid t [s]
  !> (strictly increasing, finite, size >= 1).  State i starts at
  !> (theta0(i) [rad], omega0(i) [rad/s]) at t(1) with w0(i) > 0, gamma(i) >= 0
  !> [1/s] and step h(i) > 0 [s]; omega0, w0, gamma and h have n elements or
  !> one (then shared by all states).  Outputs theta(:, i), omega(:, i) (shape
  !> (size(t), n): each state's series is contiguous, as rk4_solve's) and
  !> steps(i) are bit-identical to rk4_solve for that state alone; accuracy
  !> as rk4_solve (O(h**4)).
  !>
  !> codes(i) is state i's status code (PENDULA_OK, or what rk4_solve would
  !> return: bad argument, unstable h, non-finite state); a failed state's
  !> theta and omega are NaN (failed_output, pendula_batch_support: never a
  !> plausible number), its steps 0, and the others are unaffected.  status: OK when every
  !> state succeeded; PENDULA_ERR_CANCELLED when the call was cancelled (see
  !> control); otherwise the first failed state's code, with its index and
  !> rk4_solve's message for it.  first_failed: the first failed state.  When the
  !> call itself is refused (bad t, array sizes, threads < 0), first_failed = 0,
  !> every codes(i) holds status%code and every output is NaN.
  !>
  !> threads: OpenMP threads (0 = the OpenMP default, which honours
  !> OMP_NUM_THREADS; ignored in a build without OpenMP).  GNU OpenMP is not
  !> fork-safe: a process forked after a call with more than one thread must
  !> pass threads = 1 (more would hang in the stale thread pool).  control (optional,
  !> pendula_control): control(CONTROL_CANCEL) /= 0 stops the call within
  !> about 0.25 ms per thread; finished states keep their results and the
  !> unfinished ones get PENDULA_ERR_CANCELLED; control(CONTROL_PROGRESS)
  !> counts finished states.  max_steps (optional, >= 1): each state's step
  !> budget, as rk4_solve's (default RK4_DEFAULT_MAX_STEPS); a state that needs
  !> more is refused before any work, with rk4_solve's code.
  !>
  !> drive (optional, pendula_drive; one element or n, like the other
  !> parameters): the driven pendulum, each state bit-identical to rk4_solve
  !> with its drive.  The states run on the driven block kernel
  !> (pendula_driven), in one call per drive kind and steps per period (a
  !> sweep over the drive frequency at a fixed h runs one call per distinct
  !> N = ceiling(T/h)); progress counts finished states as without a drive.
  subroutine rk4_batch_solve(t, theta0, omega0, w0, gamma, h, theta, omega, codes, steps, status, &
                             threads, control, first_failed, max_steps, drive)
    real(wp), intent(in) :: t(:)  !< shared output times [s]: finite, strictly increasing, size >= 1
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad], one per state (n = size(theta0))
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], n elements or one
    real(wp), intent(in) :: w0(:)  !< small-angle angular frequencies [1/s], > 0, n elements or one
    real(wp), intent(in) :: gamma(:)  !< damping rates [1/s], >= 0, n elements or one
    real(wp), intent(in) :: h(:)  !< RK4 step bounds [s], > 0, n elements or one
    real(wp), intent(out) :: theta(:, :)  !< theta(:, i) of state i [rad], shape (size(t), n)
    real(wp), intent(out) :: omega(:, :)  !< Omega(:, i) of state i [rad/s], shape (size(t), n)
    integer, intent(out) :: codes(:)  !< status code of each state, n elements
    integer(i8), intent(out) :: steps(:)  !< RK4 steps taken by each state, n elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    integer, intent(in), optional :: threads
    !< optional OpenMP thread count (0 or absent: the OpenMP default)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag and progress counter (finished states) shared with another thread
    integer, intent(out), optional :: first_failed
    !< optional: 1-based index of the first failed state (0: none)
    integer(i8), intent(in), optional :: max_steps  !< step budget per state, >= 1
    type(drive_t), intent(in), optional :: drive(:)  !< optional drives, one element or n: the driven pendulum
    integer, allocatable :: live(:)
    real(wp), allocatable :: th(:, :), om(:, :)
    integer :: n, i, nlive, nthreads, first, ncancel, ist
    integer(i8) :: budget
    type(status_t) :: st
    n = size(theta0)
    budget = RK4_DEFAULT_MAX_STEPS
    if (present(max_steps)) budget = max_steps
    if (present(first_failed)) first_failed = 0
    call check_call(t, n, omega0, w0, gamma, h, theta, omega, codes, steps, threads, status)
    if (status%code == PENDULA_OK .and. budget < 1) call set_error(status, PENDULA_ERR_DOMAIN, &
                                                            'max_steps = '//format_int(budget)//' is out of range: it must be >= 1')
    if (status%code /= PENDULA_OK) then
      call refuse_all(status%code, theta, omega, codes, steps)
      return
    end if
    nthreads = batch_threads(threads)
    if (present(drive)) then
      if (size(drive) /= 1 .and. size(drive) /= n) then
        call set_error(status, PENDULA_ERR_SIZE, 'drive has '//format_int(size(drive))// &
                       ' element(s): it must have one or one per state (size(theta0) = '//format_int(n)//')')
        call refuse_all(status%code, theta, omega, codes, steps)
        return
      end if
      call driven_batch(t, theta0, omega0, w0, gamma, h, drive, budget, theta, omega, codes, steps, status, &
                        nthreads, control, first_failed)
      return
    end if

    ! Per-state checks, in rk4_solve's order (t is already known to be good),
    ! with the step budget per state (rk4_solve's default unless max_steps).
    allocate (live(n), stat=ist)
    call check_alloc(ist, 'the batch''s list of live states', int(n, i8), 4, status)
    if (status%code /= PENDULA_OK) then
      call refuse_all(status%code, theta, omega, codes, steps)
      return
    end if
    call state_codes(t, theta0, omega0, w0, gamma, h, budget, codes)
    nlive = 0
    do i = 1, n
      steps(i) = 0
      ! outputs are written by the blocks, and NaN below for failed states
      if (codes(i) == PENDULA_OK) then
        nlive = nlive + 1
        live(nlive) = i
        theta(1, i) = theta0(i)
        omega(1, i) = omega0(at(omega0, i))
        codes(i) = PENDULA_ERR_CANCELLED   ! until its block finishes
      end if
    end do

    ! The kernel writes the outputs in place, so it needs them contiguous
    ! (a strided section from a Fortran caller goes through a copy, made
    ! here once rather than per block and thread).
    if (is_contiguous(theta) .and. is_contiguous(omega)) then
      call run_blocks(t, live(1:nlive), w0, gamma, h, size(t), n, theta, omega, codes, steps, nthreads, control)
    else
      allocate (th(size(theta, 1), size(theta, 2)), om(size(omega, 1), size(omega, 2)), stat=ist)
      call check_alloc(ist, 'the contiguous copies of theta and omega', 2_i8*size(theta, kind=i8), 8, status)
      if (status%code /= PENDULA_OK) then
        call refuse_all(status%code, theta, omega, codes, steps)
        return
      end if
      th(1, :) = theta(1, :)
      om(1, :) = omega(1, :)
      call run_blocks(t, live(1:nlive), w0, gamma, h, size(t), n, th, om, codes, steps, nthreads, control)
      theta = th
      omega = om
    end if

    ! Summary: the first failed state, with rk4_solve's own message for it.
    first = 0
    ncancel = 0
    do i = n, 1, -1
      if (codes(i) /= PENDULA_OK) then
        first = i
        if (codes(i) == PENDULA_ERR_CANCELLED) ncancel = ncancel + 1
        theta(:, i) = failed_output()
        omega(:, i) = failed_output()
        steps(i) = 0
      end if
    end do
    if (first == 0) return
    if (present(first_failed)) first_failed = first
    ! rk4_solve's message for the first failed state (run again: only when it is shown)
    if (ncancel == 0) st = state_status(t, theta0(first), omega0(at(omega0, first)), w0(at(w0, first)), &
                                        gamma(at(gamma, first)), h(at(h, first)), codes(first), budget)
    call set_batch_error(status, codes, first, st%message)
  end subroutine rk4_batch_solve

  !> The code of each state's checks (check_problem, then check_step), as
  !> rk4_solve would report it.  Finite theta0 and omega0 pass check_problem
  !> whatever their values, so w0, gamma and h are checked once per run of
  !> equal values (all of a batch that shares them): check_step's stability
  !> and budget test costs ~10 times a short window's integration.
  pure subroutine state_codes(t, theta0, omega0, w0, gamma, h, budget, codes)
    real(wp), intent(in) :: t(:)  !< output times [s], already checked
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad], one per state
    real(wp), intent(in) :: omega0(:), w0(:), gamma(:), h(:)  !< per state or one for all
    integer(i8), intent(in) :: budget  !< step budget per state
    integer, intent(out) :: codes(:)  !< status code of each state
    type(status_t) :: st
    integer :: i, pcode
    real(wp) :: pw, pg, ph
    pcode = -1
    pw = 0
    pg = 0
    ph = 0
    do i = 1, size(theta0)
      if (.not. (ieee_is_finite(theta0(i)) .and. ieee_is_finite(omega0(at(omega0, i))))) then
        codes(i) = PENDULA_ERR_NONFINITE
        cycle
      end if
      ! (compared by value: a NaN parameter never equals, and is checked each time)
      if (pcode < 0 .or. .not. (w0(at(w0, i)) == pw .and. gamma(at(gamma, i)) == pg .and. h(at(h, i)) == ph)) then
        pw = w0(at(w0, i))
        pg = gamma(at(gamma, i))
        ph = h(at(h, i))
        st = status_t()
        call check_problem(t(1:1), 0.0_wp, 0.0_wp, pw, pg, st)
        call check_step(t, pw, pg, ph, real(budget, wp), st)
        pcode = st%code
      end if
      codes(i) = pcode
    end do
  end subroutine state_codes

  !> A call refused as a whole: every state gets its code and no result.
  pure subroutine refuse_all(code, theta, omega, codes, steps)
    integer, intent(in) :: code  !< the call's status code
    real(wp), intent(out) :: theta(:, :), omega(:, :)  !< NaN: the codes say there is no result
    integer, intent(out) :: codes(:)  !< code, for every state
    integer(i8), intent(out) :: steps(:)  !< 0, for every state
    theta = failed_output()
    omega = failed_output()
    codes = code
    steps = 0
  end subroutine refuse_all

  !> Checks of the call as a whole: sizes, t, threads.
  subroutine check_call(t, n, omega0, w0, gamma, h, theta, omega, codes, steps, threads, status)
    real(wp), intent(in) :: t(:), omega0(:), w0(:), gamma(:), h(:), theta(:, :), omega(:, :)
    integer, intent(in) :: n, codes(:)
    integer(i8), intent(in) :: steps(:)
    integer, intent(in), optional :: threads
    type(status_t), intent(inout) :: status
    ! t alone (neutral state values): size, order, finiteness
    call check_problem(t, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, status)
    if (status%code /= PENDULA_OK) return
    call check_batch_shapes(size(t), n, all([size(omega0), size(w0), size(gamma), size(h)] == 1 .or. &
                                    [size(omega0), size(w0), size(gamma), size(h)] == n), 'omega0, w0, gamma and h', theta, omega, &
                            size(codes), size(steps), 'steps', threads, status)
  end subroutine check_call

  !> rk4_solve's status for one state (its message for the batch summary).
  function state_status(t, theta0, omega0, w0, gamma, h, code, budget, drive) result(st)
    real(wp), intent(in) :: t(:), theta0, omega0, w0, gamma, h
    integer, intent(in) :: code
    integer(i8), intent(in) :: budget
    type(drive_t), intent(in), optional :: drive
    type(status_t) :: st
    real(wp), allocatable :: th(:), om(:)
    type(ode_stats_t) :: s
    integer :: ist
    allocate (th(size(t)), om(size(t)), stat=ist)
    call check_alloc(ist, 'the failed state''s rerun', 2_i8*size(t), 8, st)
    if (st%code /= PENDULA_OK) return
    call rk4_solve(t, theta0, omega0, w0, gamma, h, th, om, s, st, max_steps=budget, drive=drive)
    if (st%code == PENDULA_OK) call set_error(st, code, 'failed in the batch')   ! cannot happen: same kernel
  end function state_status

  !> The blocks of live(:) (as many states each as the running kernel path's
  !> lanes), spread over nthreads OpenMP threads.
  !> theta and omega are explicit-shape (nt, ldn): gfortran 12 copies an
  !> assumed-shape actual argument into a temporary for a `contiguous`
  !> assumed-shape dummy even when it is contiguous (two extra passes over the
  !> outputs and a fresh temporary per call, measured at half the kernel's
  !> time), while an explicit-shape dummy receives a contiguous array as it is.
  subroutine run_blocks(t, live, w0, gamma, h, nt, ldn, theta, omega, codes, steps, nthreads, control)
    real(wp), intent(in) :: t(:), w0(:), gamma(:), h(:)
    integer, intent(in) :: live(:)
    integer, intent(in) :: nt, ldn
    real(wp), intent(inout) :: theta(nt, ldn), omega(nt, ldn)
    integer, intent(inout) :: codes(:)
    integer(i8), intent(inout) :: steps(:)
    integer, intent(in) :: nthreads
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    integer :: nblocks, b, nlive, nl
    nl = int(rk4_lanes_width())   ! the running path's block width
    nlive = size(live)
    nblocks = (nlive + nl - 1)/nl
    !$omp parallel do schedule(dynamic) num_threads(nthreads) if(nthreads > 1 .and. nblocks > 1) default(shared)
    do b = 1, nblocks
      call run_block(t, live((b - 1)*nl + 1:min(b*nl, nlive)), w0, gamma, h, nt, ldn, theta, omega, &
                     codes, steps, control)
    end do
    !$omp end parallel do
  end subroutine run_blocks

  !> Integrate the states idx(:) (at most rk4_lanes_width(), all valid) as one block of lanes
  !> with the kernel path of this process (pendula_dispatch), and set their
  !> codes and steps.  theta and omega are the whole call's (nt, ldn) outputs.
  subroutine run_block(t, idx, w0, gamma, h, nt, ldn, theta, omega, codes, steps, control)
    real(wp), intent(in) :: t(:), w0(:), gamma(:), h(:)
    integer, intent(in) :: idx(:)
    integer, intent(in) :: nt, ldn
    real(wp), intent(inout) :: theta(nt, ldn), omega(nt, ldn)
    integer, intent(inout) :: codes(:)
    integer(i8), intent(inout) :: steps(:)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    integer(int64) :: nsteps(size(idx)), no_control(CONTROL_SIZE)
    integer(c_int) :: dead(size(idx)), done, nb
    integer :: l
    nb = int(size(idx), c_int)
    if (nb == 0) return
    if (present(control)) then
      call rk4_lanes(int(size(t), c_int), t, nb, idx, int(size(w0), c_int), w0, int(size(gamma), c_int), gamma, &
                     int(size(h), c_int), h, int(ldn, c_int), theta, omega, nsteps, dead, 1_c_int, &
                     int(CONTROL_SIZE, c_int), control, int(CONTROL_CANCEL, c_int), done)
    else
      no_control = 0
      call rk4_lanes(int(size(t), c_int), t, nb, idx, int(size(w0), c_int), w0, int(size(gamma), c_int), gamma, &
                     int(size(h), c_int), h, int(ldn, c_int), theta, omega, nsteps, dead, 0_c_int, &
                     int(CONTROL_SIZE, c_int), no_control, int(CONTROL_CANCEL, c_int), done)
    end if
    if (done == 0) return   ! cancelled: codes stay PENDULA_ERR_CANCELLED
    do l = 1, nb
      steps(idx(l)) = nsteps(l)
      codes(idx(l)) = merge(PENDULA_ERR_SOLVER, PENDULA_OK, dead(l) /= 0)
    end do
    if (present(control)) call add_progress(control, int(nb, int64))
  end subroutine run_block

  !> rk4_batch_solve with drives (the call's checks done, drive of one
  !> element or n): per-state checks as rk4_solve's (check_driven_step), then
  !> the valid states on pendula_driven's block kernel, one call per drive
  !> kind and steps per period (all states at once when they share both).
  subroutine driven_batch(t, theta0, omega0, w0, gamma, h, drive, budget, theta, omega, codes, steps, status, &
                          nthreads, control, first_failed)
    real(wp), intent(in) :: t(:), theta0(:), omega0(:), w0(:), gamma(:), h(:)
    type(drive_t), intent(in) :: drive(:)
    integer(i8), intent(in) :: budget
    real(wp), intent(out) :: theta(:, :), omega(:, :)
    integer, intent(out) :: codes(:)
    integer(i8), intent(out) :: steps(:)
    type(status_t), intent(inout) :: status
    integer, intent(in) :: nthreads
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    integer, intent(out), optional :: first_failed
    integer, allocatable :: nst(:), idx(:), gcodes(:)
    real(wp), allocatable :: g(:, :), gth(:, :), gom(:, :)
    logical, allocatable :: todo(:)
    integer :: n, i, j, m, k, first, ist
    type(status_t) :: st, gst
    type(drive_t) :: d
    n = size(theta0)
    theta = 0
    omega = 0
    steps = 0
    allocate (nst(n), todo(n), stat=ist)
    call check_alloc(ist, 'the batch''s steps per period', 2_i8*n, 4, status)
    if (status%code /= PENDULA_OK) then
      codes = status%code
      theta = failed_output()
      omega = failed_output()
      return
    end if
    do i = 1, n
      st = status_t()
      call check_problem(t(1:1), theta0(i), omega0(at(omega0, i)), w0(at(w0, i)), gamma(at(gamma, i)), st)
      call check_driven_step(t, theta0(i), omega0(at(omega0, i)), w0(at(w0, i)), gamma(at(gamma, i)), &
                             drive(min(i, size(drive))), h(at(h, i)), real(budget, wp), nst(i), st)
      codes(i) = st%code
      todo(i) = st%code == PENDULA_OK .and. size(t) > 1
      if (st%code == PENDULA_OK .and. size(t) == 1) then
        theta(1, i) = theta0(i)
        omega(1, i) = omega0(at(omega0, i))
      end if
    end do
    do i = 1, n
      if (.not. todo(i)) cycle
      d = drive(min(i, size(drive)))
      k = nst(i)
      m = 0
      do j = i, n
        if (todo(j) .and. nst(j) == k .and. drive(min(j, size(drive)))%kind == d%kind) m = m + 1
      end do
      if (m == n) then
        ! one group: every state at once, the caller's arrays as they are
        call driven_batch_solve(t, theta0, omega0, w0, gamma, d%kind, drive%amplitude, drive%frequency, drive%phase, k, &
                                theta, omega, codes, gst, threads=nthreads, control=control)
        todo = .false.
        exit
      end if
      allocate (idx(m), gcodes(m), g(m, 7), gth(size(t), m), gom(size(t), m), stat=ist)
      st = status_t()
      call check_alloc(ist, 'a drive group''s states and outputs', int(m, i8)*(9 + 2*size(t)), 8, st)
      if (st%code /= PENDULA_OK) then
        ! this group fails alone; the others still run
        do j = i, n
          if (todo(j) .and. nst(j) == k .and. drive(min(j, size(drive)))%kind == d%kind) then
            codes(j) = st%code
            todo(j) = .false.
          end if
        end do
        if (allocated(idx)) deallocate (idx)
        if (allocated(gcodes)) deallocate (gcodes)
        if (allocated(g)) deallocate (g)
        if (allocated(gth)) deallocate (gth)
        if (allocated(gom)) deallocate (gom)
        cycle
      end if
      m = 0
      do j = i, n
        if (todo(j) .and. nst(j) == k .and. drive(min(j, size(drive)))%kind == d%kind) then
          m = m + 1
          idx(m) = j
          todo(j) = .false.
          g(m, :) = [theta0(j), omega0(at(omega0, j)), w0(at(w0, j)), gamma(at(gamma, j)), &
                     drive(min(j, size(drive)))%amplitude, drive(min(j, size(drive)))%frequency, &
                     drive(min(j, size(drive)))%phase]
        end if
      end do
      call driven_batch_solve(t, g(:, 1), g(:, 2), g(:, 3), g(:, 4), d%kind, g(:, 5), g(:, 6), g(:, 7), k, &
                              gth, gom, gcodes, gst, threads=nthreads, control=control)
      do j = 1, m
        codes(idx(j)) = gcodes(j)
        theta(:, idx(j)) = gth(:, j)
        omega(:, idx(j)) = gom(:, j)
      end do
      deallocate (idx, gcodes, g, gth, gom)
    end do
    do i = 1, n
      if (codes(i) == PENDULA_OK) steps(i) = driven_step_count(t, drive(min(i, size(drive))), nst(i))
    end do
    ! Summary: the first failed state, with rk4_solve's own message for it.
    first = findloc(codes /= PENDULA_OK, .true., dim=1)
    if (first == 0) return
    if (present(first_failed)) first_failed = first
    call nan_failed(codes, theta)
    call nan_failed(codes, omega)
    st = status_t()
    if (count(codes == PENDULA_ERR_CANCELLED) == 0) st = state_status(t, theta0(first), omega0(at(omega0, first)), &
                                                        w0(at(w0, first)), gamma(at(gamma, first)), h(at(h, first)), codes(first), &
                                                                      budget, drive(min(first, size(drive))))
    call set_batch_error(status, codes, first, st%message)
  end subroutine driven_batch

end module pendula_rk4_batch
