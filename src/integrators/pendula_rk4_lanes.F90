!> The batch RK4 kernel proper (pendula_rk4_batch): one block of up to
!> RK4_BATCH_LANES states (128 on x86-64-v4) integrated over the whole output grid, lane by lane
!> exactly rk4_grid's operations (pendula_rk4_kernel).
!>
!> Shape: each substep is one loop over the block's lanes (table_step,
!> inlined and vectorised across lanes), with the lanes' state in
!> double-buffered arrays that stay in L1.  When the block shares w0, gamma
!> and h (the common case), the interval's constants are scalars; otherwise
!> they are formed per lane once per interval.  The rare plain (libm) steps
!> and the idle lanes of unequal substep counts are patched after the loop,
!> so that the loop itself has no branch.
!> Why a file of its own, compiled several times: the kernel is a loop over
!> lanes that gcc vectorises, and its speed is set by the vector width of
!> the instruction set it may use.  meson compiles this file once per target
!> (baseline x86-64 = SSE2, x86-64-v3 = AVX2, x86-64-v4 = AVX-512; elsewhere
!> only the portable build), each with its own module and entry name given by
!> the preprocessor (PENDULA_LANES_MODULE, PENDULA_LANES_ENTRY and the width
!> function PENDULA_LANES_WIDTH_FN), and pendula_kernel_path.c picks one at load time from the CPU's features (or
!> from PENDULA_KERNEL).  The module uses no other pendula module, so each
!> variant is a leaf of the build; the step's tables and elemental pieces are
!> the same text as rk4_grid's (pendula_rk4_tables.inc, pendula_rk4_step.inc).
!>
!> Bit-identity: pendula compiles everything with -ffp-contract=off and
!> without -ffast-math, so no variant fuses a multiply and an add or
!> reorders a sum; wider vectors change how many lanes run at once, not what
!> each lane computes.  Every variant therefore returns the bits of rk4_solve
!> (tests/python/test_kernel_paths.py compares them on every path the
!> machine has).
! meson defines the names (and the width where it is not the default) per variant; a build that compiles the file once
! (fpm) gets the portable one, which pendula_kernel_path.c always has.
#ifndef PENDULA_LANES_MODULE
#define PENDULA_LANES_MODULE pendula_rk4_lanes_baseline_m
#define PENDULA_LANES_ENTRY pendula_rk4_lanes_baseline
#define PENDULA_LANES_WIDTH_FN pendula_rk4_lanes_width_baseline
#endif
! The block width (lanes) of this variant: RK4_BATCH_LANES unless meson
! asks for more (x86-64-v4: 128 lanes).
#ifndef PENDULA_LANES_WIDTH
#define PENDULA_LANES_WIDTH RK4_BATCH_LANES
#endif
module PENDULA_LANES_MODULE
  use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double
  use, intrinsic :: iso_fortran_env, only: wp => real64, i8 => int64
  implicit none
  private
  public :: PENDULA_LANES_ENTRY, PENDULA_LANES_WIDTH_FN

  include 'pendula_rk4_tables.inc'

  integer, parameter :: nl = PENDULA_LANES_WIDTH
  !> Lane-steps between two polls of the cancel flag (~0.25 ms of work).
  integer(i8), parameter :: poll_lane_steps = 32768
  !> Output intervals per chunk (their outputs stored together, a cache line
  !> of each state's series at a time).
  integer, parameter :: nchunk = 8
  !> Columns of the step constants (step_constants' outputs, in its order).
  integer, parameter :: c_half = 1, c_sixth = 2, c_h2q = 3, c_hh = 4, c_c6 = 5, c_w1 = 6, c_w2 = 7, c_cy = 8, &
                        c_g2 = 9, c_wa = 10, c_wb = 11, c_bu0 = 12, c_bu1 = 13, ncst = 13

contains

  !> The states per block of this variant (its lanes): the largest nb it takes.
  integer(c_int) function PENDULA_LANES_WIDTH_FN() bind(C)
    PENDULA_LANES_WIDTH_FN = nl
  end function PENDULA_LANES_WIDTH_FN

  !> Integrate the states idx(1:nb) (1 <= nb <= the variant's width, all valid,
  !> theta(1, idx(l)) and omega(1, idx(l)) holding their initial state) as one
  !> block of lanes over the grid t; lanes past nb repeat the first state and
  !> are discarded.  Writes theta(2:, idx(l)), omega(2:, idx(l)), the steps
  !> taken nsteps(l) and dead(l) = 1 where the state stopped being finite
  !> (0 otherwise).  When poll /= 0, control(icancel) /= 0 is looked at about
  !> every 0.25 ms and stops the block with done = 0; done = 1 when it ran to
  !> the end.  w0, gamma, h hold one value per state or one for all.
  subroutine PENDULA_LANES_ENTRY(nt, t, nb, idx, nw, w0, ng, gamma, nh, h, ldn, theta, omega, nsteps, dead, &
                                 poll, ncontrol, control, icancel, done) bind(C)
    integer(c_int), intent(in) :: nt  !< output times, >= 1
    real(c_double), intent(in) :: t(nt)  !< output times [s], strictly increasing
    integer(c_int), intent(in) :: nb  !< states in the block, 1 to the variant's width
    integer(c_int), intent(in) :: idx(nb)  !< their columns in theta and omega
    integer(c_int), intent(in) :: nw  !< size of w0: 1 or ldn
    real(c_double), intent(in) :: w0(nw)  !< small-angle angular frequencies [1/s]
    integer(c_int), intent(in) :: ng  !< size of gamma: 1 or ldn
    real(c_double), intent(in) :: gamma(ng)  !< damping rates [1/s]
    integer(c_int), intent(in) :: nh  !< size of h: 1 or ldn
    real(c_double), intent(in) :: h(nh)  !< RK4 step bounds [s]
    integer(c_int), intent(in) :: ldn  !< states of the whole call (columns of theta and omega)
    real(c_double), intent(inout) :: theta(nt, ldn)  !< theta(:, i) of state i [rad]
    real(c_double), intent(inout) :: omega(nt, ldn)  !< Omega(:, i) of state i [rad/s]
    integer(c_int64_t), intent(out) :: nsteps(nb)  !< RK4 steps taken by each lane
    integer(c_int), intent(out) :: dead(nb)  !< 1 where the lane's state stopped being finite
    integer(c_int), intent(in) :: poll  !< nonzero: look at control(icancel)
    integer(c_int), intent(in) :: ncontrol  !< size of control, >= 1
    integer(c_int64_t), intent(inout), volatile :: control(ncontrol)  !< control(icancel) /= 0 asks to stop
    integer(c_int), intent(in) :: icancel  !< index of the cancel flag in control
    integer(c_int), intent(out) :: done  !< 1 when the block ran to the end, 0 when cancelled
    ! the lanes' state, double-buffered (a step reads buffer a and writes 1 - a)
    real(wp) :: y(nl, 0:1), u(nl, 0:1), rh(nl, 0:1)
    integer :: kk(nl, 0:1)
    real(wp), dimension(nl) :: wsq, gam, hl, hsc, fin
    real(wp) :: cst(nl, ncst), cs(ncst), bth(nl, nchunk), bom(nl, nchunk)
    integer(i8) :: msc(nl), ns(nl), m, i, mx, work
    logical :: dlane(nl), same, same_h
    integer :: l, s, a, j0, jn, jj, c
    real(wp) :: dt, hm, nbad
    done = 0
    nsteps = 0
    dead = 0
    if (poll /= 0) then
      if (control(icancel) /= 0) return
    end if
    do l = 1, nl
      s = idx(min(l, nb))
      y(l, 0) = theta(1, s)
      u(l, 0) = omega(1, s)
      wsq(l) = w0(merge(1, s, nw == 1))*w0(merge(1, s, nw == 1))
      gam(l) = gamma(merge(1, s, ng == 1))
      hl(l) = h(merge(1, s, nh == 1))
      call node_reduce(y(l, 0), kk(l, 0), rh(l, 0))
    end do
    ! One step size and pair of parameters for the whole block (the common
    ! case: scalar w0, gamma and h) takes the interval's constants as scalars.
    same_h = all(hl == hl(1))
    same = same_h .and. all(wsq == wsq(1)) .and. all(gam == gam(1))
    a = 0
    ns = 0
    dlane = .false.
    work = 0
    j0 = 1
    do while (j0 <= nt - 1)
      jn = min(nchunk, nt - j0)
      do jj = 1, jn
        dt = t(j0 + jj) - t(j0 + jj - 1)
        if (same_h) then
          m = substeps(dt, hl(1))
          hm = dt
          if (m /= 1) hm = dt/real(m, wp)
        end if
        if (same) then
          call step_constants(hm, wsq(1), gam(1), cs(c_half), cs(c_sixth), cs(c_h2q), cs(c_hh), cs(c_c6), cs(c_w1), &
                              cs(c_w2), cs(c_cy), cs(c_g2), cs(c_wa), cs(c_wb), cs(c_bu0), cs(c_bu1))
          do i = 1, m
            call same_step(y(:, a), u(:, a), rh(:, a), kk(:, a), wsq(1), gam(1), hm, cs, &
                           y(:, 1 - a), u(:, 1 - a), rh(:, 1 - a), kk(:, 1 - a), fin, nbad)
            if (nbad > 0) then
              do l = 1, nl
                hsc(l) = hm
                do c = 1, ncst
                  cst(l, c) = cs(c)
                end do
              end do
              call plain_lanes(fin, y(:, a), u(:, a), wsq, gam, hsc, cst, y(:, 1 - a), u(:, 1 - a), &
                               rh(:, 1 - a), kk(:, 1 - a))
            end if
            a = 1 - a
          end do
          ns = ns + merge(0_i8, m, dlane)
          work = work + m*nl
        else
          ! parameters per lane: the interval's constants per lane, and its
          ! substeps too when the lanes' step bounds differ (lanes with fewer
          ! substeps then keep their state through the others' last ones)
          if (same_h) then
            hsc = hm
            msc = merge(0_i8, m, dlane)
            mx = m
          else
            do l = 1, nl
              msc(l) = merge(0_i8, substeps(dt, hl(l)), dlane(l))
              hsc(l) = dt
              if (msc(l) > 1) hsc(l) = dt/real(msc(l), wp)
            end do
            mx = maxval(msc)
          end if
          call step_constants(hsc, wsq, gam, cst(:, c_half), cst(:, c_sixth), cst(:, c_h2q), cst(:, c_hh), &
                              cst(:, c_c6), cst(:, c_w1), cst(:, c_w2), cst(:, c_cy), cst(:, c_g2), cst(:, c_wa), &
                              cst(:, c_wb), cst(:, c_bu0), cst(:, c_bu1))
          do i = 1, mx
            call lane_step(y(:, a), u(:, a), rh(:, a), kk(:, a), wsq, gam, hsc, cst, &
                           y(:, 1 - a), u(:, 1 - a), rh(:, 1 - a), kk(:, 1 - a), fin, nbad)
            if (nbad > 0) call plain_lanes(fin, y(:, a), u(:, a), wsq, gam, hsc, cst, y(:, 1 - a), &
                                           u(:, 1 - a), rh(:, 1 - a), kk(:, 1 - a))
            if (.not. same_h) call keep_idle(i, msc, y(:, a), u(:, a), rh(:, a), kk(:, a), &
                                             y(:, 1 - a), u(:, 1 - a), rh(:, 1 - a), kk(:, 1 - a))
            a = 1 - a
          end do
          ns = ns + msc
          work = work + mx*nl
        end if
        bth(:, jj) = y(:, a)
        bom(:, jj) = u(:, a)
        if (work >= poll_lane_steps) then
          jn = jj
          exit
        end if
      end do
      ! rk4_grid stops at the first output that is not finite and rk4_solve
      ! reports it; such a lane stops too (its outputs are discarded by the
      ! caller).  One branch-free test per chunk.
      fin = 1
      do jj = 1, jn
        do l = 1, nl
          fin(l) = merge(fin(l), 0.0_wp, abs(bth(l, jj)) <= huge(dt))
          fin(l) = merge(fin(l), 0.0_wp, abs(bom(l, jj)) <= huge(dt))
        end do
      end do
      if (minval(fin) < 1) then
        do l = 1, nl
          if (fin(l) < 1) dlane(l) = .true.
        end do
        where (dlane)
          y(:, a) = 0
          u(:, a) = 0
          rh(:, a) = 0
          kk(:, a) = 0
        end where
      end if
      ! each state's outputs are contiguous: stored a chunk at a time (those
      ! of a lane that stopped are discarded by the caller)
      do l = 1, nb
        theta(j0 + 1:j0 + jn, idx(l)) = bth(l, 1:jn)
        omega(j0 + 1:j0 + jn, idx(l)) = bom(l, 1:jn)
      end do
      if (poll /= 0 .and. work >= poll_lane_steps) then
        work = 0
        if (control(icancel) /= 0) return
      end if
      j0 = j0 + jn
    end do
    do l = 1, nb
      nsteps(l) = ns(l)
      dead(l) = merge(1, 0, dlane(l))
    end do
    done = 1
  end subroutine PENDULA_LANES_ENTRY

  !> One table-path step of every lane when all lanes share hs, w0sq, gamma
  !> and the interval's constants cs: (yo, uo, ro, ko) -> (yn, un, rn, kn).
  !> okr(l) = 0 where lane l must take the plain step instead, and nbad
  !> counts them.
  pure subroutine same_step(yo, uo, ro, ko, wsq, gam, hs, cs, yn, un, rn, kn, okr, nbad)
    real(wp), intent(in) :: yo(nl), uo(nl), ro(nl), wsq, gam, hs, cs(ncst)
    integer, intent(in) :: ko(nl)
    real(wp), intent(out) :: yn(nl), un(nl), rn(nl), okr(nl), nbad
    integer, intent(out) :: kn(nl)
    real(wp) :: sk(nl), ck(nl)
    integer :: l
    call node_values(ko, sk, ck)
    nbad = 0
    do l = 1, nl
      call table_step(sk(l), ck(l), yo(l), uo(l), ro(l), wsq, gam, hs, cs(c_half), cs(c_sixth), cs(c_h2q), cs(c_hh), &
                      cs(c_c6), cs(c_w1), cs(c_w2), cs(c_cy), cs(c_g2), cs(c_wa), cs(c_wb), cs(c_bu0), cs(c_bu1), &
                      yn(l), un(l), rn(l), kn(l), okr(l))
      nbad = max(nbad, 1 - okr(l))
    end do
  end subroutine same_step

  !> One table-path step of every lane, each with its own parameters and
  !> constants (cst(l, :)).  okr and nbad as same_step's.
  pure subroutine lane_step(yo, uo, ro, ko, wsq, gam, hs, cst, yn, un, rn, kn, okr, nbad)
    real(wp), intent(in) :: yo(nl), uo(nl), ro(nl), wsq(nl), gam(nl), hs(nl), cst(nl, ncst)
    integer, intent(in) :: ko(nl)
    real(wp), intent(out) :: yn(nl), un(nl), rn(nl), okr(nl), nbad
    integer, intent(out) :: kn(nl)
    real(wp) :: sk(nl), ck(nl)
    integer :: l
    call node_values(ko, sk, ck)
    nbad = 0
    do l = 1, nl
      call table_step(sk(l), ck(l), yo(l), uo(l), ro(l), wsq(l), gam(l), hs(l), cst(l, c_half), cst(l, c_sixth), &
                      cst(l, c_h2q), cst(l, c_hh), cst(l, c_c6), cst(l, c_w1), cst(l, c_w2), cst(l, c_cy), &
                      cst(l, c_g2), cst(l, c_wa), cst(l, c_wb), cst(l, c_bu0), cst(l, c_bu1), yn(l), un(l), rn(l), &
                      kn(l), okr(l))
      nbad = max(nbad, 1 - okr(l))
    end do
  end subroutine lane_step

  !> Substep i of an interval in which lane l takes msc(l) substeps: the
  !> lanes past their last one keep their state (yo, ro, ...).
  pure subroutine keep_idle(i, msc, yo, uo, ro, ko, yn, un, rn, kn)
    integer(i8), intent(in) :: i, msc(nl)
    real(wp), intent(in) :: yo(nl), uo(nl), ro(nl)
    integer, intent(in) :: ko(nl)
    real(wp), intent(inout) :: yn(nl), un(nl), rn(nl)
    integer, intent(inout) :: kn(nl)
    where (i > msc)
      yn = yo
      un = uo
      rn = ro
      kn = ko
    end where
  end subroutine keep_idle

  !> rk4_grid's plain libm step on the lanes whose table step failed
  !> (okr(l) = 0), from (yo, uo) with the lane's constants.
  !> Out of line: the rare path stays out of the hot loop's registers.  Not
  !> vectorised: with AVX2 gcc would call glibc's vector sin (libmvec, up to
  !> 4 ulp), which gfortran declares SIMD-capable, instead of the scalar libm
  !> sin of rk4_grid's plain step.
  subroutine plain_lanes(okr, yo, uo, wsq, gam, hs, cst, yn, un, rn, kn)
    real(wp), intent(in) :: okr(nl), yo(nl), uo(nl), wsq(nl), gam(nl), hs(nl), cst(nl, ncst)
    real(wp), intent(inout) :: yn(nl), un(nl), rn(nl)
    integer, intent(inout) :: kn(nl)
    integer :: l
    !GCC$ novector
    do l = 1, nl
      if (okr(l) == 0) then
        call plain_step(yo(l), uo(l), wsq(l), gam(l), hs(l), cst(l, c_half), cst(l, c_sixth), cst(l, c_c6), &
                        yn(l), un(l))
        call node_reduce(yn(l), kn(l), rn(l))
      end if
    end do
  end subroutine plain_lanes

  !> sin x_k and cos x_k of the lanes' nodes k.  A loop of its own: SSE2 has
  !> no gather, and a table lookup inside the step's loop keeps gcc from
  !> vectorising it there.
  pure subroutine node_values(k, sk, ck)
    integer, intent(in) :: k(nl)
    real(wp), intent(out) :: sk(nl), ck(nl)
    integer :: l, ik
    do l = 1, nl
      ik = iand(k(l), nnodes - 1)
      sk(l) = node_sin(ik)
      ck(l) = node_cos(ik)
    end do
  end subroutine node_values

  !> One table-path RK4 step of one lane (rk4_grid's fast branch, the same
  !> operations), inlined into the loops over lanes, which gcc vectorises.
  !> ok = 0 where the lane must take the plain step instead; such a lane is
  !> computed on a neutral state (0, 0) so that no operation sees a huge
  !> argument, and its results are discarded.  The node's Taylor rows are
  !> formed from sin x_k and cos x_k (one rounded product each, as the table
  !> rows of rk4_grid: the same bits) instead of gathering eight more values.
  pure subroutine table_step(sk, ck, y, u, rh, wsq, gam, hs, half, sixth, h2q, hh, c6, w1, w2, cy, g2, wa, wb, &
                             bu0, bu1, yn, un, rn, kn, ok)
    real(wp), intent(in) :: sk, ck  !< sin and cos of the lane's node
    real(wp), intent(in) :: y, u, rh, wsq, gam, hs, half, sixth, h2q, hh, c6, w1, w2, cy, g2, wa, wb, bu0, bu1
    real(wp), intent(out) :: yn, un, rn, ok
    integer, intent(out) :: kn
    real(wp) :: c2, c3, c4, c5, c6t, c7, c8, c9
    real(wp) :: yv, uv, rv, p2, p4, a4, kfn, kp23, r2, r3, r4, k1, k2, m2, m3, s1, s2, s3, s4, dy, ok0
    ! The path tests are 0/1 reals built by merges of locals: gfortran turns
    ! .and. (and merges of array elements) into branches, which stop
    ! vectorisation, while these become vector selects.
    c2 = sk*taylor_factor(2)
    c3 = ck*taylor_factor(3)
    c4 = sk*taylor_factor(4)
    c5 = ck*taylor_factor(5)
    c6t = sk*taylor_factor(6)
    c7 = ck*taylor_factor(7)
    c8 = sk*taylor_factor(8)
    c9 = ck*taylor_factor(9)
    ok0 = merge(1.0_wp, 0.0_wp, abs(u)*bu1 + bu0 <= 1)
    ok0 = merge(ok0, 0.0_wp, abs(rh) <= stage_rmax)
    ! (products, not merges: these selects keep gcc from vectorising the
    ! loop for SSE2; x*1 = x exactly, and a lane with ok0 = 0 is discarded)
    yv = y*ok0
    uv = u*ok0
    rv = rh*ok0
    p2 = half*uv
    p4 = hs*uv
    a4 = yv + p4
    kfn = round_away((a4 + p2)*nodes_per_radian)
    kp23 = kfn*node_p2 + kfn*node_p3
    r2 = rv + p2
    s1 = sin_taylor(sk, ck, c2, c3, c4, c5, c6t, c7, c8, c9, rv)
    s2 = sin_taylor(sk, ck, c2, c3, c4, c5, c6t, c7, c8, c9, r2)
    k1 = -gam*uv - wsq*s1
    r3 = (r2 - h2q*gam*uv) - w1*s1
    m2 = uv + half*k1
    r4 = ((rv + p4) - hh*gam*m2) - w2*s2
    k2 = -gam*m2 - wsq*s2
    s3 = sin_taylor(sk, ck, c2, c3, c4, c5, c6t, c7, c8, c9, r3)
    m3 = uv + half*k2
    dy = (p4 + c6*((k1 + k2) - gam*m3)) - cy*s3
    yn = yv + dy
    s4 = sin_taylor(sk, ck, c2, c3, c4, c5, c6t, c7, c8, c9, r4)
    un = uv + (((sixth*((k1 + 2*k2) - gam*uv - g2*m3)) - wa*s3) - wb*s4)
    rn = ((yv - kfn*node_p1) - kp23) + dy
    kn = int(kfn)
    ! (a NaN offset fails here but passes rk4_grid's max(); either way the
    ! state is non-finite from this step on and reported the same)
    ! (a product of 0/1 selects: a chain of merges becomes one branchy
    ! multi-way join that gcc does not if-convert for SSE2)
    ok = (ok0*merge(1.0_wp, 0.0_wp, abs(a4) <= stage_xmax))*(merge(1.0_wp, 0.0_wp, abs(r4) <= stage_rmax) &
                                       *(merge(1.0_wp, 0.0_wp, abs(r3) <= stage_rmax)*merge(1.0_wp, 0.0_wp, abs(r2) <= stage_rmax)))
  end subroutine table_step

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

  include 'pendula_rk4_step.inc'

end module PENDULA_LANES_MODULE
