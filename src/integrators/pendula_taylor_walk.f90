!> The steps of the adaptive Taylor integrator (pendula_taylor) for one state:
!> the step size, the dense outputs and events inside each step, the error
!> model and the double-double advance.  The state of an integration is a
!> taylor_walk_t.  One procedure (walk) holds the step: the scalar driver
!> (taylor_run) walks to the end through taylor_walk_run, which forms each
!> step's series itself and keeps the state in local variables from step to
!> step (a call per step, with the state loaded from and stored to the
!> derived type, cost the scalar solve ~5%); the batch's block kernel
!> (pendula_taylor_lanes, which forms the series of several states side by
!> side) takes one step at a time through taylor_walk_step.  Both run the
!> same statements: a batch state is bit-identical to the scalar call by
!> construction.  The error model is described in pendula_taylor.
module pendula_taylor_walk
  use pendula_kinds, only: wp, i8
  use pendula_constants, only: two_pi, two_pi_lo
  use pendula_status, only: PENDULA_OK, PENDULA_ERR_SOLVER, PENDULA_ERR_MAXSTEPS, PENDULA_ERR_CANCELLED
  use pendula_control, only: CONTROL_SIZE, cancel_requested, add_progress
  use pendula_ode, only: PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO
  use pendula_double_double, only: two_sum, two_prod
  use pendula_drive, only: drive_t
  use pendula_taylor_series, only: TAYLOR_MAX_ORDER, taylor_step, taylor_shear, taylor_coefficients, taylor_coefficients_driven, &
                                   taylor_drive_series
  implicit none
  private
  public :: taylor_walk_t, taylor_walk_step, taylor_walk_run, taylor_drive_phase, TAYLOR_SAFETY, MAX_STEP_TAU, POLL_STEPS

  !> Factor on the propagated error bound (calibrated: the measured error
  !> stays below the estimate with this margin in every test case).
  real(wp), parameter :: TAYLOR_SAFETY = 2
  !> Largest step in w0 t: below half a small-swing period (pi), so a step holds
  !> at most one turning point and one pass through the bottom per level.
  real(wp), parameter :: MAX_STEP_TAU = 2
  !> Steps between two looks at the budget's pace and the cancel flag.
  integer, parameter :: POLL_STEPS = 128
  ! Per-step rounding: this many ulps of the sum of absolute terms.
  real(wp), parameter :: ROUND_ULPS = 2
  real(wp), parameter :: ULP = epsilon(1.0_wp)/2
  ! Outputs evaluated side by side (series_sums_lanes).
  integer, parameter :: OUT_LANES = 4

  !> An integration in progress (set up by pendula_taylor's taylor_start): the
  !> state and time as double-doubles, the step plan, the error model's sums,
  !> and where it is in the output grid.
  type :: taylor_walk_t
    real(wp) :: xh = 0, xl = 0, vh = 0, vl = 0  !< theta [rad] and Omega [rad/s], double-double
    real(wp) :: th = 0, tl = 0  !< time [s], double-double
    real(wp) :: w0 = 1, inv_w0 = 1, w0sq = 1, gamma = 0  !< parameters [1/s], [s], [1/s**2], [1/s]
    real(wp) :: eps_s = 0  !< per-step tolerance
    real(wp) :: lgr = 1  !< Gronwall rate of the scaled system
    real(wp) :: amp = 0  !< drive amplitude in the series' units (0: none)
    real(wp) :: big_a = 0, big_d = 0, g = 0, ec = -1  !< error model: local sum, growth, shear, its energy
    real(wp) :: r0 = 0, r1 = 0, r2 = 0, gam = 0, lt = 0  !< rounding sums, integrated shear and Gronwall exponent
    real(wp) :: sn = 0, cs = 0, s0abs = 0  !< sin, cos of theta and size of v(1)'s terms (from the series)
    real(wp) :: t_fail = 0  !< time of a failure [s]
    integer(i8) :: steps = 0  !< steps taken
    integer :: p = 4  !< series order
    integer :: i = 2  !< next output index
    integer :: outcome = PENDULA_OK  !< PENDULA_OK or the failure code
    logical :: driven = .false.  !< a drive is present (no shear model)
  end type taylor_walk_t

contains

  !> One step of walk w from the series x, v (taylor_coefficients at w's
  !> state, order w%p, with w%sn, w%cs, w%s0abs): the outputs t(w%i..) inside
  !> the step into theta, omega, err, the events when with_events, then the
  !> advance.  done: the walk ended (w%outcome PENDULA_OK at t(size(t)), or a
  !> failure at w%t_fail: non-finite series or state, step lost in rounding,
  !> max_steps).  For the batch's block kernel, which forms the series.
  subroutine taylor_walk_step(w, t, x, v, with_events, max_steps, theta, omega, err, ev_t, ev_k, ev_th, ev_om, &
                              nev, trunc, done)
    type(taylor_walk_t), intent(inout) :: w  !< the walk
    real(wp), intent(in) :: t(:)  !< output times [s], checked
    real(wp), intent(in) :: x(0:TAYLOR_MAX_ORDER)  !< theta series at w's state, x(0:p+1)
    real(wp), intent(in) :: v(0:TAYLOR_MAX_ORDER)  !< Omega series at w's state, v(0:p+1)
    logical, intent(in) :: with_events  !< whether to locate events
    integer(i8), intent(in) :: max_steps  !< step budget
    real(wp), intent(inout) :: theta(:)  !< theta at t [rad]
    real(wp), intent(inout) :: omega(:)  !< Omega at t [rad/s]
    real(wp), intent(inout) :: err(:)  !< error estimates [rad]
    real(wp), intent(inout) :: ev_t(:)  !< event times [s]
    integer, intent(inout) :: ev_k(:)  !< event kinds
    real(wp), intent(inout) :: ev_th(:)  !< theta at the events [rad]
    real(wp), intent(inout) :: ev_om(:)  !< Omega at the events [rad/s]
    integer, intent(inout) :: nev  !< events stored
    logical, intent(inout) :: trunc  !< more events than the arrays hold
    logical, intent(out) :: done  !< the walk ended
    real(wp) :: xs(0:TAYLOR_MAX_ORDER), vs(0:TAYLOR_MAX_ORDER)
    integer :: q
    q = min(max(w%p, 0) + 1, TAYLOR_MAX_ORDER)
    xs(0:q) = x(0:q)
    vs(0:q) = v(0:q)
    call walk(w, t, xs, vs, .false., with_events, max_steps, theta, omega, err, ev_t, ev_k, ev_th, ev_om, nev, trunc, done)
  end subroutine taylor_walk_step

  !> Walk w to the end of the window, forming each step's series at its state
  !> (taylor_coefficients, or taylor_coefficients_driven with drive): the
  !> same steps as taylor_walk_step's, the state held in registers across
  !> them.  control (optional): polled every POLL_STEPS steps, a cancel ends
  !> the walk with PENDULA_ERR_CANCELLED.  For the scalar driver taylor_run.
  subroutine taylor_walk_run(w, t, with_events, max_steps, theta, omega, err, ev_t, ev_k, ev_th, ev_om, &
                             nev, trunc, control, drive)
    type(taylor_walk_t), intent(inout) :: w  !< the walk
    real(wp), intent(in) :: t(:)  !< output times [s], checked
    logical, intent(in) :: with_events  !< whether to locate events
    integer(i8), intent(in) :: max_steps  !< step budget
    real(wp), intent(inout) :: theta(:)  !< theta at t [rad]
    real(wp), intent(inout) :: omega(:)  !< Omega at t [rad/s]
    real(wp), intent(inout) :: err(:)  !< error estimates [rad]
    real(wp), intent(inout) :: ev_t(:)  !< event times [s]
    integer, intent(inout) :: ev_k(:)  !< event kinds
    real(wp), intent(inout) :: ev_th(:)  !< theta at the events [rad]
    real(wp), intent(inout) :: ev_om(:)  !< Omega at the events [rad/s]
    integer, intent(inout) :: nev  !< events stored
    logical, intent(inout) :: trunc  !< more events than the arrays hold
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    !< optional cancel flag and progress counter (pendula_control)
    type(drive_t), intent(in), optional :: drive  !< optional periodic drive, as taylor_start's
    real(wp) :: x(0:TAYLOR_MAX_ORDER), v(0:TAYLOR_MAX_ORDER)
    logical :: done
    call walk(w, t, x, v, .true., with_events, max_steps, theta, omega, err, ev_t, ev_k, ev_th, ev_om, nev, trunc, done, &
              control, drive)
  end subroutine taylor_walk_run

  ! The walk itself: one step from the series x, v (own false), or every step
  ! to the end, each forming its series into x, v (own true).
  subroutine walk(w, t, x, v, own, with_events, max_steps, theta, omega, err, ev_t, ev_k, ev_th, ev_om, &
                  nev, trunc, done, control, drive)
    type(taylor_walk_t), intent(inout) :: w
    real(wp), intent(in) :: t(:)
    real(wp), intent(inout) :: x(0:TAYLOR_MAX_ORDER), v(0:TAYLOR_MAX_ORDER)
    logical, intent(in) :: own, with_events
    integer(i8), intent(in) :: max_steps
    real(wp), intent(inout) :: theta(:), omega(:), err(:), ev_t(:), ev_th(:), ev_om(:)
    integer, intent(inout) :: ev_k(:), nev
    logical, intent(inout) :: trunc
    logical, intent(out) :: done
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)
    type(drive_t), intent(in), optional :: drive
    real(wp) :: xh, xl, vh, vl, th, tl, h, habs, rem, rs, re, d, ds, de, inv_w0, w0, eps_s
    real(wp) :: big_a, big_d, g, ec, es, lgr, s0abs, xe, ve, xel, vel, s, e, sn, cs, pc, ps
    real(wp) :: r0, r1, r2, gam, lt, rnd, trc, committed, dl(OUT_LANES), rl(OUT_LANES), rvl(OUT_LANES)
    real(wp) :: xol4(OUT_LANES), vol4(OUT_LANES), el4(OUT_LANES), bd, dc(0:TAYLOR_MAX_ORDER)
    integer(i8) :: steps
    integer :: n, i, nl, p
    n = size(t)
    xh = w%xh
    xl = w%xl
    vh = w%vh
    vl = w%vl
    th = w%th
    tl = w%tl
    inv_w0 = w%inv_w0
    w0 = w%w0
    eps_s = w%eps_s
    big_a = w%big_a
    big_d = w%big_d
    g = w%g
    ec = w%ec
    lgr = w%lgr
    s0abs = w%s0abs
    r0 = w%r0
    r1 = w%r1
    r2 = w%r2
    gam = w%gam
    lt = w%lt
    steps = w%steps
    i = w%i
    p = w%p
    sn = w%sn
    cs = w%cs
    done = .true.
    body: do
      if (own) then
        if (present(drive)) then
          call taylor_drive_phase(drive, th, tl, pc, ps)
          call taylor_drive_series(pc, ps, drive%frequency, p, dc)
          call taylor_coefficients_driven(xh, xl, vh, w%w0sq, w%gamma, drive%kind, w%amp, dc, p, x, v, s0abs, sn, cs)
        else
          call taylor_coefficients(xh, xl, vh, w%w0sq, w%gamma, p, x, v, s0abs, sn, cs)
        end if
      end if
      es = 0
      if (.not. w%driven) es = scaled_energy_sc(sn, cs, vh*inv_w0)
      call two_sum(t(n), -th, rs, re)
      rem = rs + (re - tl)
      habs = taylor_step(x, v, p, inv_w0, eps_s, min(abs(rem), MAX_STEP_TAU*inv_w0))
      ! a non-finite series (an overflowing state) or a step lost in the time's rounding
      if (.not. (abs(x(p + 1)) + abs(v(p + 1)) <= huge(1.0_wp) .and. habs > 0) .or. &
          (th + sign(habs, rem) == th .and. habs < abs(rem))) then
        w%outcome = PENDULA_ERR_SOLVER
        w%t_fail = th
        exit body
      end if
      if (habs >= abs(rem)) then
        h = rem
      else
        h = sign(habs, rem)
      end if
      ! the full step first: the state it ends at, and its truncation and
      ! rounding bounds, which bound those of every output inside the step too
      ! (both grow with |d|): the outputs cost one Horner pass each
      call dense_error(h, xe, xel, ve, vel, trc, rnd)
      ! the outputs inside this step, from its polynomial (what was committed
      ! before the step is the same for all of them: formed once)
      committed = -1
      do while (i <= n)
        ! up to OUT_LANES outputs at once: their sums side by side (independent
        ! chains; each output's arithmetic is the one-output sum's)
        nl = 0
        dl = 0
        do while (i + nl <= n .and. nl < OUT_LANES)
          ! two_sum(t(i + nl), -th, ds, de), written out
          ds = t(i + nl) - th
          bd = ds - t(i + nl)
          de = (t(i + nl) - (ds - bd)) + (-th - bd)
          d = ds + (de - tl)
          if (abs(d) > abs(h) .and. h /= rem) exit
          nl = nl + 1
          dl(nl) = d
        end do
        if (nl == 0) exit
        if (committed < 0) committed = sqrt(2.0_wp)*(big_a + big_d + rounding_part()) + trc + rnd
        call series_sums_lanes(dl, rl, rvl)
        call finish_lanes(dl, rl, rvl, xol4, vol4)
        el4 = TAYLOR_SAFETY*committed + ULP*max(abs(xol4), abs(vol4)*inv_w0)
        theta(i:i + nl - 1) = xol4(1:nl)
        omega(i:i + nl - 1) = vol4(1:nl)
        err(i:i + nl - 1) = el4(1:nl)
        i = i + nl
        if (nl < OUT_LANES) exit
      end do
      if (with_events) call events_in_step(h)
      if (h == rem) exit body
      ! advance the double-double state and time by the full step
      if (.not. (abs(xe) <= huge(1.0_wp) .and. abs(ve) <= huge(1.0_wp))) then
        w%outcome = PENDULA_ERR_SOLVER
        w%t_fail = th
        exit body
      end if
      ! error model: growth of what was committed so far, then this step's share
      ! G varies like log|2 - e| and 1/|2 - e|: refreshed when e has moved by
      ! 5% of its distance to 0 or to the separatrix, with a 10% margin
      if (w%driven) then
        g = 1.0e50_wp   ! no shear model: Gronwall's bound (lgr) decides
      else if (abs(es - ec) > 0.05_wp*min(es, abs(2 - es)) .or. ec < 0) then
        ec = es
        g = 1.1_wp*min(taylor_shear(es), 1.0e50_wp)   ! capped: no inf - inf below
      end if
      big_d = big_d + w0*habs*min(g*big_a, lgr*(big_a + big_d))
      big_a = big_a + trc
      ! rounding: independent from step to step, so summed in quadrature, each
      ! share grown by the integrated shear since it was made (gam)
      gam = min(gam + g*w0*habs, 1.0e100_wp)
      lt = lt + lgr*w0*habs
      r0 = r0 + rnd*rnd
      r1 = r1 + rnd*rnd*gam
      r2 = r2 + rnd*rnd*gam*gam
      xh = xe
      xl = xel
      vh = ve
      vl = vel
      call two_sum(th, h, s, e)
      e = e + tl
      th = s + e
      tl = e - (th - s)
      steps = steps + 1
      ! the budget: spent, or (checked every POLL_STEPS steps) certain to be at this pace
      if (steps >= max_steps .or. (mod(steps, int(POLL_STEPS, i8)) == 0 .and. &
                                   abs(rem)/max(abs(th - t(1)) + abs(tl), tiny(1.0_wp)) > real(max_steps, wp)/real(steps, wp))) then
        w%outcome = PENDULA_ERR_MAXSTEPS
        w%t_fail = th
        exit body
      end if
      if (.not. own) then
        done = .false.
        exit body
      end if
      if (present(control) .and. mod(steps, int(POLL_STEPS, i8)) == 0) then
        call add_progress(control, int(POLL_STEPS, i8))
        if (cancel_requested(control)) then
          w%outcome = PENDULA_ERR_CANCELLED
          w%t_fail = th
          exit body
        end if
      end if
    end do body
    w%xh = xh
    w%xl = xl
    w%vh = vh
    w%vl = vl
    w%th = th
    w%tl = tl
    w%big_a = big_a
    w%big_d = big_d
    w%g = g
    w%ec = ec
    w%r0 = r0
    w%r1 = r1
    w%r2 = r2
    w%gam = gam
    w%lt = lt
    w%steps = steps
    w%i = i
    w%s0abs = s0abs
    w%sn = sn
    w%cs = cs

  contains

    ! The state at offset dd from the step's start, as double-doubles: the
    ! term theta' dd exactly (two_prod), the rest by Horner.
    subroutine dense(dd, xo, xol, vo, vol)
      real(wp), intent(in) :: dd
      real(wp), intent(out) :: xo, xol, vo, vol
      real(wp) :: rest, rv
      call series_sums(dd, rest, rv)
      call dense_finish(dd, rest, rv, xo, xol, vo, vol)
    end subroutine dense

    ! The state at offset dd from the series sums rest and rv (series_sums).
    subroutine dense_finish(dd, rest, rv, xo, xol, vo, vol)
      real(wp), intent(in) :: dd, rest, rv
      real(wp), intent(out) :: xo, xol, vo, vol
      real(wp) :: p1, e1, s1, e2, lo, bb
      call two_prod(vh, dd, p1, e1)
      ! two_sum(xh, p1) and two_sum(vh, rv), written out
      s1 = xh + p1
      bb = s1 - xh
      e2 = (xh - (s1 - bb)) + (p1 - bb)
      lo = e2 + (e1 + vl*dd + xl + rest)
      xo = s1 + lo
      xol = lo - (xo - s1)
      s1 = vh + rv
      bb = s1 - vh
      e2 = (vh - (s1 - bb)) + (rv - bb)
      lo = e2 + vl
      vo = s1 + lo
      vol = lo - (vo - s1)
    end subroutine dense_finish

    ! dense_finish's theta and Omega (not their low parts) at OUT_LANES offsets
    ! at once, lane by lane the same arithmetic: two_prod's Dekker product
    ! written out (the head and tail of vh split once), two_prod itself where
    ! a factor is beyond its split's range.
    subroutine finish_lanes(dd, rest, rv, xo, vo)
      real(wp), intent(in) :: dd(OUT_LANES), rest(OUT_LANES), rv(OUT_LANES)
      real(wp), intent(out) :: xo(OUT_LANES), vo(OUT_LANES)
      real(wp), parameter :: BIG = 2.0_wp**996, SPLIT = 134217729.0_wp
      real(wp) :: p1(OUT_LANES), e1(OUT_LANES), s1(OUT_LANES), e2(OUT_LANES), lo(OUT_LANES), bb(OUT_LANES)
      real(wp) :: dh(OUT_LANES), dlo(OUT_LANES), tt(OUT_LANES), ts, vhh, vhl
      integer :: k
      if (abs(vh) <= BIG .and. all(abs(dd) <= BIG)) then
        ts = SPLIT*vh
        vhh = ts - (ts - vh)
        vhl = vh - vhh
        p1 = vh*dd
        tt = SPLIT*dd
        dh = tt - (tt - dd)
        dlo = dd - dh
        e1 = ((vhh*dh - p1) + vhh*dlo + vhl*dh) + vhl*dlo
      else
        do k = 1, OUT_LANES
          call two_prod(vh, dd(k), p1(k), e1(k))
        end do
      end if
      s1 = xh + p1
      bb = s1 - xh
      e2 = (xh - (s1 - bb)) + (p1 - bb)
      lo = e2 + (e1 + vl*dd + xl + rest)
      xo = s1 + lo
      s1 = vh + rv
      bb = s1 - vh
      e2 = (vh - (s1 - bb)) + (rv - bb)
      lo = e2 + vl
      vo = s1 + lo
    end subroutine finish_lanes

    ! rest = sum_{k=2..p} x(k) dd**k and rv = sum_{k=1..p} v(k) dd**k by
    ! Horner in dd**2 over the even and the odd k apart: four independent
    ! chains of p/2 multiply-adds instead of two of p (an output's cost is
    ! the latency of these chains).  Rounding as Horner's: a few ulps of the
    ! absolute terms (the terms decay geometrically).  Needs p >= 3.
    subroutine series_sums(dd, rest, rv)
      real(wp), intent(in) :: dd
      real(wp), intent(out) :: rest, rv
      real(wp) :: q, xev, xod, vev, vod
      integer :: k, ke, ko
      q = dd*dd
      ke = p - mod(p, 2)
      ko = p - 1 + mod(p, 2)
      xev = x(ke)
      vev = v(ke)
      xod = x(ko)
      vod = v(ko)
      do k = ke - 2, 2, -2
        xev = xev*q + x(k)
        vev = vev*q + v(k)
      end do
      do k = ko - 2, 3, -2
        xod = xod*q + x(k)
        vod = vod*q + v(k)
      end do
      vod = vod*q + v(1)
      rest = q*(xev + dd*xod)
      rv = q*vev + dd*vod
    end subroutine series_sums

    ! series_sums at OUT_LANES offsets at once, lane by lane the same arithmetic.
    subroutine series_sums_lanes(dd, rest, rv)
      real(wp), intent(in) :: dd(OUT_LANES)
      real(wp), intent(out) :: rest(OUT_LANES), rv(OUT_LANES)
      real(wp) :: q(OUT_LANES), xev(OUT_LANES), xod(OUT_LANES), vev(OUT_LANES), vod(OUT_LANES)
      integer :: k, ke, ko
      q = dd*dd
      ke = p - mod(p, 2)
      ko = p - 1 + mod(p, 2)
      xev = x(ke)
      vev = v(ke)
      xod = x(ko)
      vod = v(ko)
      do k = ke - 2, 2, -2
        xev = xev*q + x(k)
        vev = vev*q + v(k)
      end do
      do k = ko - 2, 3, -2
        xod = xod*q + x(k)
        vod = vod*q + v(k)
      end do
      vod = vod*q + v(1)
      rest = q*(xev + dd*xod)
      rv = q*vev + dd*vod
    end subroutine series_sums_lanes

    ! The state at offset dd (as dense) and the local error bounds of the
    ! polynomial there, in the max norm of (theta, Omega/w0), in one pass over
    ! the coefficients: trc, twice the first omitted term (the tail of a
    ! series decaying at least by 1/2 a term; ~e**-2 at the optimal order),
    ! and rnd, ROUND_ULPS ulps of the absolute terms.
    subroutine dense_error(dd, xo, xol, vo, vol, trc_, rnd_)
      real(wp), intent(in) :: dd
      real(wp), intent(out) :: xo, xol, vo, vol, trc_, rnd_
      real(wp) :: p1, e1, s1, e2, lo, rest, rv, bb, a, sx, sv, ap, q, xev, xod, vev, vod
      integer :: k, ke, ko
      call two_prod(vh, dd, p1, e1)
      call series_sums(dd, rest, rv)
      ! the absolute terms, sum_{k=2..p} |x(k)| a**k and |v(k)| a**k, split
      ! into even and odd k as in series_sums
      a = abs(dd)
      q = a*a
      ke = p - mod(p, 2)
      ko = p - 1 + mod(p, 2)
      xev = abs(x(ke))
      vev = abs(v(ke))
      xod = abs(x(ko))
      vod = abs(v(ko))
      do k = ke - 2, 2, -2
        xev = xev*q + abs(x(k))
        vev = vev*q + abs(v(k))
      end do
      do k = ko - 2, 3, -2
        xod = xod*q + abs(x(k))
        vod = vod*q + abs(v(k))
      end do
      ap = a**(p + 1)
      sx = q*(xev + a*xod) + abs(x(p + 1))*ap
      sv = q*(vev + a*vod) + abs(v(p + 1))*ap
      trc_ = 2*max(abs(x(p + 1)), abs(v(p + 1))*inv_w0)*ap
      rnd_ = ROUND_ULPS*ULP*(sx + (s0abs*a + sv)*inv_w0 + abs(xl) + abs(vl)*inv_w0)
      s1 = xh + p1
      bb = s1 - xh
      e2 = (xh - (s1 - bb)) + (p1 - bb)
      lo = e2 + (e1 + vl*dd + xl + rest)
      xo = s1 + lo
      xol = lo - (xo - s1)
      s1 = vh + rv
      bb = s1 - vh
      e2 = (vh - (s1 - bb)) + (rv - bb)
      lo = e2 + vl
      vo = s1 + lo
      vol = lo - (vo - s1)
    end subroutine dense_error

    ! The rounding so far, grown by the shear: sqrt(sum r_i**2 (1 + Gamma -
    ! Gamma_i)**2) with Gamma the integrated shear, capped by the Gronwall
    ! factor exp(L tau) (near the separatrix the shear model breaks down).
    real(wp) function rounding_part() result(r)
      real(wp) :: q
      q = r0*(1 + gam)**2 - 2*(1 + gam)*r1 + r2
      r = sqrt(max(q, r0))
      r = min(r, sqrt(r0)*exp(min(lt, 700.0_wp)))
    end function rounding_part

    ! Events in (0, hh] of the current step, in time order.
    subroutine events_in_step(hh)
      real(wp), intent(in) :: hh
      real(wp) :: f0, f1, dt_turn, xend, xendl, dummy, lev_h, lev_l, dz, fs, fe
      integer :: j, j1, j2, jstep
      logical :: pending
      ! turning point: Omega changes sign
      pending = .false.
      dt_turn = 0
      f0 = vh
      if (f0 == 0) f0 = v(1)*hh   ! starts at a turning point: the sign just after
      if (f0 == 0) f0 = v(2)*hh*hh
      call dense(hh, xend, xendl, f1, dummy)
      if (f0 /= 0 .and. (f1 == 0 .or. (f1 > 0) .neqv. (f0 > 0))) then
        dt_turn = root(v, vh + vl, hh)
        pending = .true.
      end if
      ! bottom passes: theta crosses a level 2 pi j (monotonic within a step:
      ! a step is shorter than half a swing)
      if (xend > xh) then
        j1 = floor(xh/two_pi) + 1
        j2 = floor(xend/two_pi)
        jstep = 1
      else
        j1 = ceiling(xh/two_pi) - 1
        j2 = ceiling(xend/two_pi)
        jstep = -1
      end if
      do j = j1, j2, jstep
        lev_h = two_pi*j
        lev_l = two_pi_lo*j + (two_pi*real(j, wp) - lev_h)
        fs = (xh - lev_h) + (xl - lev_l)
        fe = (xend - lev_h) + (xendl - lev_l)
        if (fs == 0 .or. .not. (fe == 0 .or. (fe > 0) .neqv. (fs > 0))) cycle
        dz = root(x, fs, hh)
        if (pending .and. abs(dt_turn) < abs(dz)) then
          call emit(dt_turn, PENDULA_EVENT_TURNING)
          pending = .false.
        end if
        call emit(dz, PENDULA_EVENT_ZERO)
      end do
      if (pending) call emit(dt_turn, PENDULA_EVENT_TURNING)
    end subroutine events_in_step

    subroutine emit(dd, kind)
      real(wp), intent(in) :: dd
      integer, intent(in) :: kind
      real(wp) :: xo, vo, dummy
      if (nev >= size(ev_t)) then
        trunc = .true.
        return
      end if
      nev = nev + 1
      call dense(dd, xo, dummy, vo, dummy)
      ev_t(nev) = th + (tl + dd)
      ev_k(nev) = kind
      ev_th(nev) = xo
      ev_om(nev) = vo
    end subroutine emit

    ! Root in (0, hh] of c0 + sum_{k=1..p} a(k) d**k (a sign change between
    ! 0 and hh is known): bracketed Newton with bisection, to a few ulps of d.
    real(wp) function root(a, c0, hh) result(dr)
      real(wp), intent(in) :: a(0:TAYLOR_MAX_ORDER), c0, hh
      real(wp) :: lo, hi, flo, f, df, dn
      integer :: it, k
      lo = 0
      hi = hh
      flo = c0
      dr = hh/2
      if (a(1) /= 0) then
        dn = -c0/a(1)
        if ((dn - lo)*(dn - hi) < 0) dr = dn
      end if
      do it = 1, 100
        f = a(p)
        df = p*a(p)
        do k = p - 1, 1, -1
          f = f*dr + a(k)
          df = df*dr + k*a(k)
        end do
        f = f*dr + c0
        if (f == 0) return
        if ((f > 0) .eqv. (flo > 0)) then
          lo = dr
          flo = f
        else
          hi = dr
        end if
        dn = dr - f/df
        if (.not. ((dn - lo)*(dn - hi) < 0)) dn = (lo + hi)/2
        if (abs(dn - dr) <= 2*ULP*abs(dr) .or. dn == lo .or. dn == hi) then
          dr = dn
          return
        end if
        dr = dn
      end do
    end function root

  end subroutine walk

  !> cos and sin of the drive phase Omega t + phi at the double-double time
  !> th + tl [s]: Omega th exactly (two_prod), reduced by 2 pi in
  !> double-double, so that the phase keeps ~1e-16 absolute accuracy over
  !> long windows.
  pure subroutine taylor_drive_phase(drive, th, tl, c, s)
    type(drive_t), intent(in) :: drive  !< the drive (frequency [rad/s], phase [rad])
    real(wp), intent(in) :: th  !< time, high part [s]
    real(wp), intent(in) :: tl  !< time, low part [s]
    real(wp), intent(out) :: c  !< cos of the phase
    real(wp), intent(out) :: s  !< sin of the phase
    real(wp) :: ph, pe, s1, e1, kk, a, b, psi
    call two_prod(drive%frequency, th, ph, pe)
    call two_sum(ph, pe + drive%frequency*tl + drive%phase, s1, e1)
    kk = anint(s1/two_pi)
    call two_prod(kk, two_pi, a, b)
    psi = (((s1 - a) - b) + e1) - kk*two_pi_lo
    c = cos(psi)
    s = sin(psi)
  end subroutine taylor_drive_phase

  ! Scaled energy u**2/2 + 1 - cos(x) (u = Omega/w0) from sin(x), cos(x):
  ! 1 - cos = sin**2/(1 + cos) for cos > 0 (no cancellation for small swings).
  pure real(wp) function scaled_energy_sc(sn, cs, u) result(e)
    real(wp), intent(in) :: sn, cs, u
    if (cs > 0) then
      e = u*u/2 + sn*sn/(1 + cs)
    else
      e = u*u/2 + (1 - cs)
    end if
  end function scaled_energy_sc

end module pendula_taylor_walk
