!> The batch RK4 kernel proper (pendula_rk4_batch): one block of up to
!> RK4_BATCH_LANES states (16 on x86-64-v4) integrated over the whole output grid, lane by lane
!> exactly rk4_grid's operations (pendula_rk4_kernel).
!>
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
#define PENDULA_LANES_WIDTH_FN pendula_rk4_lanes_baseline_width
#endif
! The block width (lanes) of this variant: RK4_BATCH_LANES unless meson
! asks for more (x86-64-v4: 16 lanes, two 512-bit vectors).
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
  !> Block steps (of nl lanes each) between two polls of the cancel flag (~0.25 ms).
  integer(i8), parameter :: poll_every = 2048
  !> Output intervals per chunk (their substeps and step constants formed
  !> together ahead of their steps, their outputs stored together).
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
    real(wp), dimension(nl) :: y, u, rh, wsq, gam, hl, fin, yn, un, rn
    integer, dimension(nl) :: kk, kn
    logical, dimension(nl) :: okv
    integer(i8) :: ns(nl)
    logical, dimension(nl) :: dlane
    ! per chunk of output intervals: each interval's substep size and count
    ! (per lane) and rk4_grid's per-interval constants, lane by lane; the
    ! lanes' outputs
    real(wp) :: hsc(nl, nchunk), cst(nl, ncst, nchunk), bth(nl, nchunk), bom(nl, nchunk)
    integer(i8) :: msc(nl, nchunk), nmx(nchunk), nst
    integer :: l, s, j0, jn, jj
    integer(i8) :: i, m, work
    real(wp) :: dt, hm
    logical :: uniform
    done = 0
    nsteps = 0
    dead = 0
    if (poll /= 0) then
      if (control(icancel) /= 0) return
    end if
    do l = 1, nl
      s = idx(min(l, nb))
      y(l) = theta(1, s)
      u(l) = omega(1, s)
      wsq(l) = w0(merge(1, s, nw == 1))*w0(merge(1, s, nw == 1))
      gam(l) = gamma(merge(1, s, ng == 1))
      hl(l) = h(merge(1, s, nh == 1))
      call node_reduce(y(l), kk(l), rh(l))
    end do
    uniform = all(hl == hl(1))
    ns = 0
    dlane = .false.
    work = 0
    j0 = 1
    do while (j0 <= nt - 1)
      jn = min(nchunk, nt - j0)
      ! The chunk's substeps and step constants first: they depend on t, h,
      ! w0 and gamma only, and their divisions and branches then stay off the
      ! states' dependency chain (rk4_grid forms them one interval ahead).
      ! A chunk ends early once it holds poll_every steps (cancel latency).
      nst = 0
      do jj = 1, jn
        dt = t(j0 + jj) - t(j0 + jj - 1)
        if (uniform) then
          m = substeps(dt, hl(1))
          hm = dt
          if (m /= 1) hm = dt/real(m, wp)
          msc(:, jj) = m
          hsc(:, jj) = hm
        else
          do l = 1, nl
            msc(l, jj) = substeps(dt, hl(l))
            hsc(l, jj) = dt
            if (msc(l, jj) /= 1) hsc(l, jj) = dt/real(msc(l, jj), wp)
          end do
        end if
        nst = nst + maxval(msc(:, jj))
        if (nst >= poll_every) then
          jn = jj
          exit
        end if
      end do
      do jj = 1, jn
        call step_constants(hsc(:, jj), wsq, gam, cst(:, c_half, jj), cst(:, c_sixth, jj), cst(:, c_h2q, jj), &
                            cst(:, c_hh, jj), cst(:, c_c6, jj), cst(:, c_w1, jj), cst(:, c_w2, jj), cst(:, c_cy, jj), &
                            cst(:, c_g2, jj), cst(:, c_wa, jj), cst(:, c_wb, jj), cst(:, c_bu0, jj), cst(:, c_bu1, jj))
      end do
      ! Then the chunk's steps, with nothing between two intervals but the
      ! loop control and the store of the lanes' outputs (a lane with fewer
      ! substeps in an interval idles through the rest of it; a stopped lane
      ! takes none).
      do l = 1, nl
        if (dlane(l)) msc(l, 1:jn) = 0
      end do
      nst = 0
      do jj = 1, jn
        nmx(jj) = maxval(msc(:, jj))
        nst = nst + max(nmx(jj), 1_i8)
        ns = ns + msc(:, jj)
      end do
      do jj = 1, jn
        do i = 1, nmx(jj)
          call fast_step(y, u, rh, kk, wsq, gam, hsc(:, jj), cst(:, c_half, jj), cst(:, c_sixth, jj), &
                         cst(:, c_h2q, jj), cst(:, c_hh, jj), cst(:, c_c6, jj), cst(:, c_w1, jj), cst(:, c_w2, jj), &
                         cst(:, c_cy, jj), cst(:, c_g2, jj), cst(:, c_wa, jj), cst(:, c_wb, jj), cst(:, c_bu0, jj), &
                         cst(:, c_bu1, jj), yn, un, rn, kn, okv)
          if (.not. all(okv)) call plain_lanes(i <= msc(:, jj), y, u, wsq, gam, hsc(:, jj), cst(:, c_half, jj), &
                                               cst(:, c_sixth, jj), cst(:, c_c6, jj), okv, yn, un, rn, kn)
          if (uniform) then
            y = yn
            u = un
            rh = rn
            kk = kn
          else
            where (i <= msc(:, jj))
              y = yn
              u = un
              rh = rn
              kk = kn
            end where
          end if
        end do
        bth(:, jj) = y
        bom(:, jj) = u
      end do
      work = work + nst
      ! rk4_grid stops at the first output that is not finite and rk4_solve
      ! reports it; such a lane stops too (its outputs are discarded by the
      ! caller).  One branch-free test per chunk.
      do l = 1, nl
        fin(l) = merge(merge(1.0_wp, 0.0_wp, all(abs(bom(l, 1:jn)) <= huge(u))), 0.0_wp, all(abs(bth(l, 1:jn)) <= huge(y)))
      end do
      if (minval(fin) < 1) then
        do l = 1, nl
          if (fin(l) < 1) dlane(l) = .true.
        end do
        where (dlane)
          y = 0
          u = 0
          rh = 0
          kk = 0
        end where
      end if
      ! each state's outputs are contiguous: stored a chunk at a time (those
      ! of a lane that stopped are discarded by the caller)
      do l = 1, nb
        theta(j0 + 1:j0 + jn, idx(l)) = bth(l, 1:jn)
        omega(j0 + 1:j0 + jn, idx(l)) = bom(l, 1:jn)
      end do
      if (poll /= 0 .and. work >= poll_every) then
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

  !> rk4_grid's plain libm step on the lanes l with okv(l) false that still
  !> take this step (live(l)).  Out of line: the rare path stays out of the
  !> hot loop's registers.  Not vectorised: with AVX2 gcc would call glibc's
  !> vector sin (libmvec, up to 4 ulp), which gfortran declares SIMD-capable,
  !> instead of the scalar libm sin of rk4_grid's plain step.
  subroutine plain_lanes(live, y, u, wsq, gam, hs, half, sixth, c6, okv, yn, un, rn, kn)
    logical, intent(in) :: live(nl)
    real(wp), dimension(nl), intent(in) :: y, u, wsq, gam, hs, half, sixth, c6
    logical, intent(in) :: okv(nl)
    real(wp), dimension(nl), intent(inout) :: yn, un, rn
    integer, intent(inout) :: kn(nl)
    integer :: l
    !GCC$ novector
    do l = 1, nl
      if (.not. okv(l) .and. live(l)) then
        call plain_step(y(l), u(l), wsq(l), gam(l), hs(l), half(l), sixth(l), c6(l), yn(l), un(l))
        call node_reduce(yn(l), kn(l), rn(l))
      end if
    end do
  end subroutine plain_lanes

  !> One table-path RK4 step on every lane (rk4_grid's fast branch, same
  !> operations).  okv(l) is false where that lane must take the plain step
  !> instead; such lanes are computed on a neutral state (0, 0) so that no
  !> operation sees a huge argument, and their results are discarded.
  !> The node's sine and cosine are gathered lane by lane first (SSE2 has no
  !> gather; two loads per lane instead of rk4_grid's ten table entries, whose
  !> products are formed here), then the arithmetic runs as branch-free loops
  !> over lanes, which gcc vectorises.
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
    end do
    do l = 1, nl
      ! the rows of `taylor`, formed as it was (one rounded product each)
      c2(l) = sk(l)*taylor_factor(2)
      c3(l) = ck(l)*taylor_factor(3)
      c4(l) = sk(l)*taylor_factor(4)
      c5(l) = ck(l)*taylor_factor(5)
      c6t(l) = sk(l)*taylor_factor(6)
      c7(l) = ck(l)*taylor_factor(7)
      c8(l) = sk(l)*taylor_factor(8)
      c9(l) = ck(l)*taylor_factor(9)
    end do
    do l = 1, nl
      yv = y(l)
      uv = u(l)
      rv = rh(l)
      bnd = abs(uv)*bu1(l) + bu0(l)
      ok0 = merge(1.0_wp, 0.0_wp, bnd <= 1)
      ok0 = merge(ok0, 0.0_wp, abs(rv) <= stage_rmax)
      yv = merge(yv, 0.0_wp, ok0 == 1)
      uv = merge(uv, 0.0_wp, ok0 == 1)
      rv = merge(rv, 0.0_wp, ok0 == 1)
      p2 = half(l)*uv
      p4 = hs(l)*uv
      a4 = yv + p4
      kfn = round_away((a4 + p2)*nodes_per_radian)
      kp23 = kfn*node_p2 + kfn*node_p3
      r2 = rv + p2
      ! the stage sines: pendula_rk4_kernel's sin_taylor, written out
      z = rv*rv
      zz = z*z
      s1 = ((sk(l) + ck(l)*rv) + z*(c2(l) + c3(l)*rv)) + zz*(((c4(l) + c5(l)*rv) + z*(c6t(l) &
                                                                                      + c7(l)*rv)) + zz*(c8(l) + c9(l)*rv))
      z = r2*r2
      zz = z*z
      s2 = ((sk(l) + ck(l)*r2) + z*(c2(l) + c3(l)*r2)) + zz*(((c4(l) + c5(l)*r2) + z*(c6t(l) &
                                                                                      + c7(l)*r2)) + zz*(c8(l) + c9(l)*r2))
      k1 = -gam(l)*uv - wsq(l)*s1
      r3 = (r2 - h2q(l)*gam(l)*uv) - w1(l)*s1
      m2 = uv + half(l)*k1
      r4 = ((rv + p4) - hh(l)*gam(l)*m2) - w2(l)*s2
      k2 = -gam(l)*m2 - wsq(l)*s2
      z = r3*r3
      zz = z*z
      s3 = ((sk(l) + ck(l)*r3) + z*(c2(l) + c3(l)*r3)) + zz*(((c4(l) + c5(l)*r3) + z*(c6t(l) &
                                                                                      + c7(l)*r3)) + zz*(c8(l) + c9(l)*r3))
      m3 = uv + half(l)*k2
      dy = (p4 + c6(l)*((k1 + k2) - gam(l)*m3)) - cy(l)*s3
      yn(l) = yv + dy
      z = r4*r4
      zz = z*z
      s4 = ((sk(l) + ck(l)*r4) + z*(c2(l) + c3(l)*r4)) + zz*(((c4(l) + c5(l)*r4) + z*(c6t(l) &
                                                                                      + c7(l)*r4)) + zz*(c8(l) + c9(l)*r4))
      un(l) = uv + (((sixth(l)*((k1 + 2*k2) - gam(l)*uv - g2(l)*m3)) - wa(l)*s3) - wb(l)*s4)
      rn(l) = ((yv - kfn*node_p1) - kp23) + dy
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

  include 'pendula_rk4_step.inc'

end module PENDULA_LANES_MODULE
