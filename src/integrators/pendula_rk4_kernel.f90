!> The inner loop of the classic RK4 for the pendulum (text eq. 2.2) and the
!> stage-sine evaluation it rests on.
!>
!> Why: with libm, one RK4 step chains two dependent `sin` calls on each of
!> its two recurrences (theta -> sin -> k1 -> sin -> k3 -> theta' and
!> Omega -> sin -> k2 -> sin -> k4 -> Omega'), and each call also spills every
!> live register, and the step is far slower than its arithmetic.  All four stage arguments of a
!> step lie within h |Omega| + O(h**2) of theta, so they are reduced ONCE per
!> step against the node 2 pi k / 256 nearest the step's midpoint (Cody-Waite,
!> three-part constant) and each stage sine is then, for |r| <= 0.1, the
!> degree-9 Taylor polynomial of sin(x_k + r) in r, whose coefficients
!> (+-sin x_k / j!, +-cos x_k / j!) are tabulated per node at compile time
!> and evaluated in Estrin order (sin_taylor: angle addition folded into one
!> polynomial; Muller, "Elementary Functions", 3rd ed., ch. 11; Tang, ACM
!> TOMS 15 (1989) 144 for the table-driven form).  The step is bound by
!> floating-point throughput and latency together.  Steps whose offsets leave
!> that range, or with |theta| > 2**20, take the plain libm step.
!>
!> Accuracy of a stage sine: absolute error <= 2 eps against sin of the
!> exact argument (measured max 1.02 eps, tests/fortran/test_rk4_kernel.f90); the
!> RK4 results differ from the plain libm formulation by rounding only.
!> Constants: tools/gen/gen_stage_sine_table.py (node table and split).
module pendula_rk4_kernel
  use pendula_kinds, only: wp, i8
  use pendula_control, only: CONTROL_SIZE, cancel_requested, add_progress
  implicit none
  private
  public :: rk4_grid, substeps, step_constants, plain_step, node_reduce, sin_node, sin_shift
  public :: stage_rmax, stage_xmax, RK4_POLL_STEPS, RK4_BATCH_LANES
  ! the node tables and reduction constants, for the batch kernel's own copy
  ! of the step (pendula_rk4_batch: the same operations, across states)
  public :: nnodes, node_sin, node_cos, taylor, node_p1, node_p2, node_p3, nodes_per_radian

  !> Steps between two looks at the cancel flag of `control` (about 0.1 ms of
  !> work at ~25 ns a step: Ctrl-C latency stays far below a millisecond,
  !> and one volatile load per 4096 steps costs nothing measurable).
  integer(i8), parameter :: RK4_POLL_STEPS = 4096

  include 'pendula_rk4_tables.inc'

contains

  !> sin(2 pi k / 256 + r) for |r| <= stage_rmax; absolute error <= 2 eps.
  elemental real(wp) function sin_node(k, r) result(s)
    integer, intent(in) :: k  !< node index (x_k = 2 pi k / 256)
    real(wp), intent(in) :: r  !< offset from the node [rad], |r| <= stage_rmax
    integer :: i
    i = iand(k, nnodes - 1)
    s = sin_taylor(node_sin(i), node_cos(i), taylor(2, i), taylor(3, i), taylor(4, i), taylor(5, i), &
                   taylor(6, i), taylor(7, i), taylor(8, i), taylor(9, i), r)
  end function sin_node

  !> sin(x + d) of the exact sum x + d (no rounding of the argument) by
  !> node_reduce and sin_node; libm sin(x + d) (rounded sum) when |x| >
  !> stage_xmax or the offset leaves the polynomials' range.  For tests.
  elemental real(wp) function sin_shift(x, d) result(s)
    real(wp), intent(in) :: x  !< angle [rad]
    real(wp), intent(in) :: d  !< offset added exactly to x [rad]
    integer :: k
    real(wp) :: rho, r
    call node_reduce(x, k, rho)
    r = rho + d
    if (abs(rho) <= stage_rmax .and. abs(d) <= stage_rmax .and. abs(r) <= stage_rmax) then
      s = sin_node(k, r)
    else
      s = sin(x + d)
    end if
  end function sin_shift

  include 'pendula_rk4_step.inc'

  !> Classic RK4 for theta'' = -gamma theta' - w0sq sin(theta) over the output
  !> grid t (strictly increasing; not checked here): theta(1) [rad], omega(1)
  !> [rad/s] hold the state at t(1) on entry; between t(i) and t(i+1) the
  !> fewest equal substeps of at most h [s] (substeps) are taken and the state
  !> is stored in theta(i+1), omega(i+1).  steps: substeps taken; fast: those
  !> on the table path (the others use libm sines).  bad = 0, or the first
  !> index whose state is not finite (the run stops there), or -j when the
  !> cancel flag of `control` stopped the run inside interval j (outputs up to
  !> t(j) are written), or huge(bad) when theta or omega does not have
  !> size(t) >= 1 elements (nothing is then read or written).  control (optional, see pendula_control): polled every
  !> RK4_POLL_STEPS steps, progress counted in steps.  One loop over all
  !> outputs, so the recurrence never leaves registers between outputs; the
  !> poll splits an interval's steps into blocks without touching the state.
  subroutine rk4_grid(t, w0sq, gamma, h, theta, omega, steps, fast, bad, control)
    real(wp), intent(in) :: t(:)  !< output times [s], strictly increasing (not checked)
    real(wp), intent(in) :: w0sq  !< w0**2 [1/s^2]
    real(wp), intent(in) :: gamma  !< damping rate [1/s]
    real(wp), intent(in) :: h  !< largest step [s], > 0
    real(wp), intent(inout) :: theta(:)  !< theta(1) [rad] on entry; theta(t(i)) on exit
    real(wp), intent(inout) :: omega(:)  !< Omega(1) [rad/s] on entry; Omega(t(i)) on exit
    integer(i8), intent(out) :: steps  !< substeps taken
    integer(i8), intent(out) :: fast  !< substeps on the table path
    integer, intent(out) :: bad
    !< 0, the first non-finite index, -j when cancelled in interval j, or huge(bad) for bad sizes
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag (polled every RK4_POLL_STEPS steps) and progress counter in steps
    real(wp) :: y, u, rh, hs, half, sixth, h2q, hh, c6, sk, ck, p2, p4, a4, kfn, kp23, bu0, bu1
    real(wp) :: c2, c3, c4, c5, c6t, c7, c8, c9
    real(wp) :: r2, r3, r4, k1, k2, yn, un, rn, s1, s2, s3, s4, m2, m3, w1, w2, cy, g2, wa, wb, dy
    integer :: kk, kn, j, ik
    integer(i8) :: i, n, nf, ns, n_nx, left, nb, poll_in
    real(wp) :: hs_nx
    logical :: ok, polling
    polling = present(control)
    poll_in = RK4_POLL_STEPS
    if (size(t) < 1 .or. size(theta) /= size(t) .or. size(omega) /= size(t)) then
      steps = 0; fast = 0; bad = huge(bad)
      return
    end if
    y = theta(1)
    u = omega(1)
    call node_reduce(y, kk, rh)
    nf = 0
    ns = 0
    bad = 0
    ! The substep count and size of each interval are formed one interval
    ! ahead: they depend on t only, and their two divisions then run beside
    ! the previous interval's steps instead of stalling the first step of
    ! their own (which shows when outputs are a few steps apart).
    if (size(t) > 1) call interval(1, n_nx, hs_nx)
    do j = 1, size(t) - 1
      n = n_nx
      hs = hs_nx
      if (j + 1 < size(t)) call interval(j + 1, n_nx, hs_nx)
      call step_constants(hs, w0sq, gamma, half, sixth, h2q, hh, c6, w1, w2, cy, g2, wa, wb, bu0, bu1)
      left = n
      do while (left > 0)
        ! blocks end at the next poll; without control one block is the interval
        nb = left
        if (polling) nb = min(left, poll_in)
        do i = 1, nb
          p2 = half*u
          p4 = hs*u
          ! A priori bound on the stage offsets, so that the polynomials never
          ! see a huge argument (no overflow on extreme inputs); a posteriori
          ! check below.  It is |p4| + hh (2 gamma |u| + gamma hh (gamma |u| +
          ! w0sq) + 2 w0sq), regrouped as |u| bu1 + bu0 with the parts that do
          ! not change along the interval formed once (two flops per step).
          ok = abs(rh) <= stage_rmax .and. abs(u)*bu1 + bu0 <= 1
          if (ok) then
            ik = iand(kk, nnodes - 1)
            sk = node_sin(ik)
            ck = node_cos(ik)
            c2 = taylor(2, ik)
            c3 = taylor(3, ik)
            c4 = taylor(4, ik)
            c5 = taylor(5, ik)
            c6t = taylor(6, ik)
            c7 = taylor(7, ik)
            c8 = taylor(8, ik)
            c9 = taylor(9, ik)
            ! Next step's node: the one nearest its midpoint theta' + h Omega'/2,
            ! predicted to O(h**2) by theta + 3 h Omega / 2; then all four stage
            ! offsets are within |h Omega|/2 + pi/256 + O(h**2) of it.
            a4 = y + p4
            kfn = anint((a4 + p2)*nodes_per_radian)
            kp23 = kfn*node_p2 + kfn*node_p3
            ! The RK4 combinations are regrouped so that each stage sine enters
            ! its consumer through one multiply and one subtract (the parts
            ! without it are formed beside the sines): the same sums as
            ! r3 = r2 + h2q k1, r4 = rho + h m3, theta' = theta + h u +
            ! (h**2/6)(k1 + k2 + k3), Omega' = Omega + (h/6)(k1 + 2 k2 + 2 k3 + k4).
            r2 = rh + p2
            s1 = sin_taylor(sk, ck, c2, c3, c4, c5, c6t, c7, c8, c9, rh)
            s2 = sin_taylor(sk, ck, c2, c3, c4, c5, c6t, c7, c8, c9, r2)
            k1 = -gamma*u - w0sq*s1
            r3 = (r2 - h2q*gamma*u) - w1*s1
            m2 = u + half*k1
            r4 = ((rh + p4) - hh*gamma*m2) - w2*s2
            k2 = -gamma*m2 - w0sq*s2
            s3 = sin_taylor(sk, ck, c2, c3, c4, c5, c6t, c7, c8, c9, r3)
            m3 = u + half*k2
            ! theta and Omega are each rounded once (as in the plain step): the
            ! increments are summed first, so rotations (|theta| >> 1) keep the
            ! rounding noise of the plain loop.  rho' is formed from the same
            ! increment beside theta' (it then carries theta + dy - x_k', which
            ! is theta' to within half an ulp of theta').
            dy = (p4 + c6*((k1 + k2) - gamma*m3)) - cy*s3
            yn = y + dy
            s4 = sin_taylor(sk, ck, c2, c3, c4, c5, c6t, c7, c8, c9, r4)
            un = u + (((sixth*((k1 + 2*k2) - gamma*u - g2*m3)) - wa*s3) - wb*s4)
            rn = ((y - kfn*node_p1) - kp23) + dy
            ok = max(abs(r2), abs(r3), abs(r4)) <= stage_rmax .and. abs(a4) <= stage_xmax
          end if
          if (ok) then
            kn = int(kfn)
            nf = nf + 1
          else
            call plain_step(y, u, w0sq, gamma, hs, half, sixth, c6, yn, un)
            call node_reduce(yn, kn, rn)
          end if
          y = yn
          u = un
          rh = rn
          kk = kn
        end do
        left = left - nb
        if (polling) then
          poll_in = poll_in - nb
          if (poll_in == 0) then
            poll_in = RK4_POLL_STEPS
            call add_progress(control, RK4_POLL_STEPS)
            if (cancel_requested(control)) then
              bad = -j
              steps = ns + (n - left)
              fast = nf
              return
            end if
          end if
        end if
      end do
      ns = ns + n
      theta(j + 1) = y
      omega(j + 1) = u
      if (.not. (abs(y) <= huge(y) .and. abs(u) <= huge(u))) then
        bad = j + 1
        exit
      end if
    end do
    steps = ns
    fast = nf
    if (polling) call add_progress(control, RK4_POLL_STEPS - poll_in)

  contains

    !> Substeps m and their size hm for the interval (t(jj), t(jj+1)).
    pure subroutine interval(jj, m, hm)
      integer, intent(in) :: jj
      integer(i8), intent(out) :: m
      real(wp), intent(out) :: hm
      m = substeps(t(jj + 1) - t(jj), h)
      if (m == 1) then
        hm = t(jj + 1) - t(jj)
      else
        hm = (t(jj + 1) - t(jj))/real(m, wp)
      end if
    end subroutine interval
  end subroutine rk4_grid

end module pendula_rk4_kernel
