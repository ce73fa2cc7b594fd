!> Classic RK4 (pendula_rk4) for many pendulums in one call: each state i has
!> its own theta0(i), omega0(i), w0(i), gamma(i) and step h(i); the output
!> grid t is shared.  Results are bit-identical to rk4_solve for the same
!> state, so a batch answer never depends on which other states came with it.
!>
!> Why a separate kernel: rk4_grid's step is a dependent chain (two chained
!> stage sines per recurrence) and so bound by latency.  Here the
!> states run in structure-of-arrays blocks of RK4_BATCH_LANES lanes; one
!> step of a block is a loop over lanes with no dependence between them, which
!> gcc vectorises (SSE2 pairs by default, wider with -march) and whose
!> independent chains fill the pipeline.  Each lane performs exactly the
!> operations of rk4_grid in the same order (the same expressions, copied; no
!> reassociation, since pendula never uses -ffast-math, and no FMA contraction
!> difference: meson.build passes -ffp-contract=off).  A lane whose stage
!> offsets leave the table's range takes rk4_grid's plain libm step, alone.
!>
!> Blocks are spread over OpenMP threads (when built with -Dopenmp); a cancel
!> flag (pendula_control) is polled about every 0.25 ms of work.
module pendula_rk4_batch
  use, intrinsic :: iso_fortran_env, only: int64
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_int
  use pendula_status, only: status_t, set_error, check_alloc, PENDULA_OK, PENDULA_ERR_DOMAIN, &
      PENDULA_ERR_SOLVER, PENDULA_ERR_CANCELLED
  use pendula_control, only: CONTROL_SIZE, cancel_requested, add_progress
  use pendula_ode, only: check_problem, check_batch_shapes, at => batch_index
  use pendula_rk4, only: rk4_solve, check_step, RK4_DEFAULT_MAX_STEPS
  use pendula_ode, only: ode_stats_t
  use pendula_batch_support, only: batch_threads, set_batch_error
  use pendula_rk4_kernel, only: substeps, step_constants, plain_step, node_reduce, stage_rmax, stage_xmax, &
      nnodes, node_sin, node_cos, taylor, node_p1, node_p2, node_p3, nodes_per_radian
  implicit none
  private
  public :: rk4_batch_solve, rk4_batch_openmp, RK4_BATCH_LANES

  !> States per block (SIMD lanes of the kernel).  8 keeps four SSE2 pairs or
  !> two AVX quads of independent work in flight per instruction stream.
  integer, parameter :: RK4_BATCH_LANES = 8
  integer, parameter :: nl = RK4_BATCH_LANES
  !> Block steps (of nl lanes each) between two polls of the cancel flag (~0.25 ms).
  integer(i8), parameter :: poll_every = 2048

contains

  !> True when this build runs batch blocks on OpenMP threads.
  logical function rk4_batch_openmp()
    rk4_batch_openmp = .false.
    !$ rk4_batch_openmp = .true.
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
  !> outputs are zero and the others are unaffected.  status: OK when every
  !> state succeeded; PENDULA_ERR_CANCELLED when the call was cancelled (see
  !> control); otherwise the first failed state's code, with its index and
  !> rk4_solve's message for it.  first_failed: the first failed state.  When the
  !> call itself is refused (bad t, array sizes, threads < 0), first_failed = 0
  !> and every codes(i) holds status%code.
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
  subroutine rk4_batch_solve(t, theta0, omega0, w0, gamma, h, theta, omega, codes, steps, status, &
      threads, control, first_failed, max_steps)
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
    integer, allocatable :: live(:)
    integer :: n, i, nlive, nblocks, b, nthreads, first, ncancel, ist
    integer(i8) :: budget
    type(status_t) :: st
    n = size(theta0)
    budget = RK4_DEFAULT_MAX_STEPS
    if (present(max_steps)) budget = max_steps
    if (present(first_failed)) first_failed = 0
    call check_call(t, n, omega0, w0, gamma, h, theta, omega, codes, steps, threads, status)
    if (status%code == PENDULA_OK .and. budget < 1) call set_error(status, PENDULA_ERR_DOMAIN, &
        'max_steps = ' // format_int(budget) // ' is out of range: it must be >= 1')
    if (status%code /= PENDULA_OK) then
      theta = 0
      omega = 0
      codes = status%code
      steps = 0
      return
    end if
    nthreads = batch_threads(threads)

    ! Per-state checks, in rk4_solve's order (t is already known to be good),
    ! with the step budget per state (rk4_solve's default unless max_steps).
    allocate (live(n), stat=ist)
    call check_alloc(ist, 'the batch''s list of live states', int(n, i8), 4, status)
    if (status%code /= PENDULA_OK) then
      theta = 0
      omega = 0
      codes = status%code
      steps = 0
      return
    end if
    nlive = 0
    do i = 1, n
      st = status_t()
      call check_problem(t(1:1), theta0(i), omega0(at(omega0, i)), w0(at(w0, i)), gamma(at(gamma, i)), st)
      call check_step(t, w0(at(w0, i)), gamma(at(gamma, i)), h(at(h, i)), real(budget, wp), st)
      codes(i) = st%code
      steps(i) = 0
      ! outputs are written by the blocks, and zeroed below for failed states
      if (st%code == PENDULA_OK) then
        nlive = nlive + 1
        live(nlive) = i
        theta(1, i) = theta0(i)
        omega(1, i) = omega0(at(omega0, i))
        codes(i) = PENDULA_ERR_CANCELLED   ! until its block finishes
      end if
    end do

    nblocks = (nlive + nl - 1) / nl
    !$omp parallel do schedule(dynamic) num_threads(nthreads) if(nthreads > 1 .and. nblocks > 1) default(shared)
    do b = 1, nblocks
      call run_block(t, live((b - 1) * nl + 1:min(b * nl, nlive)), w0, gamma, h, theta, omega, &
          codes, steps, control)
    end do
    !$omp end parallel do

    ! Summary: the first failed state, with rk4_solve's own message for it.
    first = 0
    ncancel = 0
    do i = n, 1, -1
      if (codes(i) /= PENDULA_OK) then
        first = i
        if (codes(i) == PENDULA_ERR_CANCELLED) ncancel = ncancel + 1
        theta(:, i) = 0
        omega(:, i) = 0
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
  function state_status(t, theta0, omega0, w0, gamma, h, code, budget) result(st)
    real(wp), intent(in) :: t(:), theta0, omega0, w0, gamma, h
    integer, intent(in) :: code
    integer(i8), intent(in) :: budget
    type(status_t) :: st
    real(wp), allocatable :: th(:), om(:)
    type(ode_stats_t) :: s
    integer :: ist
    allocate (th(size(t)), om(size(t)), stat=ist)
    call check_alloc(ist, 'the failed state''s rerun', 2_i8 * size(t), 8, st)
    if (st%code /= PENDULA_OK) return
    call rk4_solve(t, theta0, omega0, w0, gamma, h, th, om, s, st, max_steps=budget)
    if (st%code == PENDULA_OK) call set_error(st, code, 'failed in the batch')   ! cannot happen: same kernel
  end function state_status

  !> Integrate the states idx(:) (at most nl, all valid) as one block of lanes;
  !> lanes past size(idx) repeat the first state and are discarded.  Each lane
  !> is rk4_grid's recurrence, operation for operation.
  subroutine run_block(t, idx, w0, gamma, h, theta, omega, codes, steps, control)
    real(wp), intent(in) :: t(:), w0(:), gamma(:), h(:)
    integer, intent(in) :: idx(:)
    real(wp), intent(inout) :: theta(:, :), omega(:, :)
    integer, intent(inout) :: codes(:)
    integer(i8), intent(inout) :: steps(:)
    integer(int64), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    real(wp), dimension(nl) :: y, u, rh, wsq, gam, hl, hs, half, sixth, h2q, hh, c6, w1, w2, cy, g2, wa, wb, &
        bu0, bu1, yn, un, rn
    integer, dimension(nl) :: kk, kn
    integer(i8), dimension(nl) :: nsub, ns
    logical, dimension(nl) :: okv, dead
    real(wp) :: fin(nl)
    integer :: nb, l, j, s
    integer(i8) :: i, nmax, m, work
    real(wp) :: dt, hm
    logical :: uniform
    nb = size(idx)
    if (nb == 0) return
    if (present(control)) then
      if (cancel_requested(control)) return
    end if
    do l = 1, nl
      s = idx(min(l, nb))
      y(l) = theta(1, s)
      u(l) = omega(1, s)
      wsq(l) = w0(at(w0, s)) * w0(at(w0, s))
      gam(l) = gamma(at(gamma, s))
      hl(l) = h(at(h, s))
      call node_reduce(y(l), kk(l), rh(l))
    end do
    uniform = all(hl == hl(1))
    ns = 0
    dead = .false.
    work = 0
    do j = 1, size(t) - 1
      dt = t(j+1) - t(j)
      if (uniform) then
        m = substeps(dt, hl(1))
        hm = dt
        if (m /= 1) hm = dt / real(m, wp)
        nsub = m
        hs = hm
      else
        do l = 1, nl
          nsub(l) = substeps(dt, hl(l))
          hs(l) = dt
          if (nsub(l) /= 1) hs(l) = dt / real(nsub(l), wp)
        end do
      end if
      where (dead) nsub = 0
      nmax = maxval(nsub)
      ! rk4_grid's per-interval constants, lane by lane
      call step_constants(hs, wsq, gam, half, sixth, h2q, hh, c6, w1, w2, cy, g2, wa, wb, bu0, bu1)
      do i = 1, nmax
        call fast_step(y, u, rh, kk, wsq, gam, hs, half, sixth, h2q, hh, c6, w1, w2, cy, g2, wa, wb, bu0, bu1, &
            yn, un, rn, kn, okv)
        if (.not. all(okv)) then
          do l = 1, nl
            if (.not. okv(l) .and. i <= nsub(l)) then
              call plain_step(y(l), u(l), wsq(l), gam(l), hs(l), half(l), sixth(l), c6(l), yn(l), un(l))
              call node_reduce(yn(l), kn(l), rn(l))
            end if
          end do
        end if
        if (uniform) then
          y = yn
          u = un
          rh = rn
          kk = kn
        else
          where (i <= nsub)
            y = yn
            u = un
            rh = rn
            kk = kn
          end where
        end if
      end do
      ns = ns + nsub
      do l = 1, nb
        if (dead(l)) cycle
        theta(j+1, idx(l)) = y(l)
        omega(j+1, idx(l)) = u(l)
      end do
      ! rk4_grid stops at the first output that is not finite and rk4_solve
      ! reports it; such a lane stops too.  One branch-free test per block.
      do l = 1, nl
        fin(l) = merge(merge(1.0_wp, 0.0_wp, abs(u(l)) <= huge(u)), 0.0_wp, abs(y(l)) <= huge(y))
      end do
      if (minval(fin) < 1) then
        do l = 1, nl
          if (fin(l) < 1 .and. .not. dead(l)) then
            dead(l) = .true.
            if (l <= nb) codes(idx(l)) = PENDULA_ERR_SOLVER
          end if
        end do
        where (dead)
          y = 0
          u = 0
          rh = 0
          kk = 0
        end where
      end if
      if (present(control)) then
        work = work + max(nmax, 1_i8)
        if (work >= poll_every) then
          work = 0
          if (cancel_requested(control)) return   ! codes stay PENDULA_ERR_CANCELLED
        end if
      end if
    end do
    do l = 1, nb
      s = idx(l)
      steps(s) = ns(l)
      if (.not. dead(l)) codes(s) = PENDULA_OK
    end do
    if (present(control)) call add_progress(control, int(nb, int64))
  end subroutine run_block

  !> One table-path RK4 step on every lane (rk4_grid's fast branch, same
  !> operations).  okv(l) is false where that lane must take the plain step
  !> instead; such lanes are computed on a neutral state (0, 0) so that no
  !> operation sees a huge argument, and their results are discarded.
  !> Two loops: the table rows are gathered lane by lane first (SSE2 has no
  !> gather), then the arithmetic runs as one branch-free loop over lanes,
  !> which gcc vectorises.
  pure subroutine fast_step(y, u, rh, kk, wsq, gam, hs, half, sixth, h2q, hh, c6, w1, w2, cy, g2, wa, wb, &
      bu0, bu1, yn, un, rn, kn, okv)
    real(wp), dimension(nl), intent(in) :: y, u, rh, wsq, gam, hs, half, sixth, h2q, hh, c6, w1, w2, cy, g2, wa, wb, &
        bu0, bu1
    integer, dimension(nl), intent(in) :: kk
    real(wp), dimension(nl), intent(out) :: yn, un, rn
    integer, dimension(nl), intent(out) :: kn
    logical, dimension(nl), intent(out) :: okv
    real(wp), dimension(nl) :: sk, ck, c2, c3, c4, c5, c6t, c7, c8, c9
    real(wp) :: yv, uv, rv, p2, p4, a4, kfn, kp23
    real(wp) :: r2, r3, r4, k1, k2, m2, m3, s1, s2, s3, s4, dy, z, zz
    integer :: l, ik
    ! The path tests are 0/1 reals built by merges of locals: gfortran turns
    ! .and. (and merges of array elements) into branches, which stop
    ! vectorisation, while these become vector selects.
    real(wp) :: ok0, oki(nl), bnd
    do l = 1, nl
      ik = iand(kk(l), nnodes - 1)
      sk(l) = node_sin(ik)
      ck(l) = node_cos(ik)
      c2(l) = taylor(2, ik)
      c3(l) = taylor(3, ik)
      c4(l) = taylor(4, ik)
      c5(l) = taylor(5, ik)
      c6t(l) = taylor(6, ik)
      c7(l) = taylor(7, ik)
      c8(l) = taylor(8, ik)
      c9(l) = taylor(9, ik)
    end do
    do l = 1, nl
      yv = y(l)
      uv = u(l)
      rv = rh(l)
      bnd = abs(uv) * bu1(l) + bu0(l)
      ok0 = merge(1.0_wp, 0.0_wp, bnd <= 1)
      ok0 = merge(ok0, 0.0_wp, abs(rv) <= stage_rmax)
      yv = merge(yv, 0.0_wp, ok0 == 1)
      uv = merge(uv, 0.0_wp, ok0 == 1)
      rv = merge(rv, 0.0_wp, ok0 == 1)
      p2 = half(l) * uv
      p4 = hs(l) * uv
      a4 = yv + p4
      kfn = round_away((a4 + p2) * nodes_per_radian)
      kp23 = kfn * node_p2 + kfn * node_p3
      r2 = rv + p2
      ! the stage sines: pendula_rk4_kernel's sin_taylor, written out
      z = rv * rv
      zz = z * z
      s1 = ((sk(l) + ck(l) * rv) + z * (c2(l) + c3(l) * rv)) + zz * (((c4(l) + c5(l) * rv) + z * (c6t(l) &
          + c7(l) * rv)) + zz * (c8(l) + c9(l) * rv))
      z = r2 * r2
      zz = z * z
      s2 = ((sk(l) + ck(l) * r2) + z * (c2(l) + c3(l) * r2)) + zz * (((c4(l) + c5(l) * r2) + z * (c6t(l) &
          + c7(l) * r2)) + zz * (c8(l) + c9(l) * r2))
      k1 = -gam(l) * uv - wsq(l) * s1
      r3 = (r2 - h2q(l) * gam(l) * uv) - w1(l) * s1
      m2 = uv + half(l) * k1
      r4 = ((rv + p4) - hh(l) * gam(l) * m2) - w2(l) * s2
      k2 = -gam(l) * m2 - wsq(l) * s2
      z = r3 * r3
      zz = z * z
      s3 = ((sk(l) + ck(l) * r3) + z * (c2(l) + c3(l) * r3)) + zz * (((c4(l) + c5(l) * r3) + z * (c6t(l) &
          + c7(l) * r3)) + zz * (c8(l) + c9(l) * r3))
      m3 = uv + half(l) * k2
      dy = (p4 + c6(l) * ((k1 + k2) - gam(l) * m3)) - cy(l) * s3
      yn(l) = yv + dy
      z = r4 * r4
      zz = z * z
      s4 = ((sk(l) + ck(l) * r4) + z * (c2(l) + c3(l) * r4)) + zz * (((c4(l) + c5(l) * r4) + z * (c6t(l) &
          + c7(l) * r4)) + zz * (c8(l) + c9(l) * r4))
      un(l) = uv + (((sixth(l) * ((k1 + 2 * k2) - gam(l) * uv - g2(l) * m3)) - wa(l) * s3) - wb(l) * s4)
      rn(l) = ((yv - kfn * node_p1) - kp23) + dy
      kn(l) = int(kfn)
      ! (a NaN offset fails here but passes rk4_grid's max(); either way the
      ! state is non-finite from this step on and reported the same)
      oki(l) = merge(ok0, 0.0_wp, abs(a4) <= stage_xmax)
      oki(l) = merge(oki(l), 0.0_wp, abs(r4) <= stage_rmax)
      oki(l) = merge(oki(l), 0.0_wp, abs(r3) <= stage_rmax)
      oki(l) = merge(oki(l), 0.0_wp, abs(r2) <= stage_rmax)
    end do
    okv = oki == 1
  end subroutine fast_step

  !> anint(x) (nearest integer, halves away from zero) for |x| < 2**51
  !> without a call to libm's round (baseline x86-64 has no rounding
  !> instruction, and a call stops vectorisation): adding and subtracting
  !> 2**52 rounds |x| to nearest-even exactly; a half rounded down is put up.
  elemental real(wp) function round_away(x) result(r)
    real(wp), intent(in) :: x
    real(wp), parameter :: two52 = 4503599627370496.0_wp
    real(wp) :: ax
    ax = abs(x)
    r = (ax + two52) - two52
    r = merge(r + 1, r, r - ax == -0.5_wp)
    r = sign(r, x)
  end function round_away

end module pendula_rk4_batch
