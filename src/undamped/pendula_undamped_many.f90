!> Many undamped states at once (undamped_states, undamped_properties) and the
!> checked one-state convenience undamped_solve, built on pendula_undamped_motion and
!> pendula_undamped_eval with the same numbers as undamped_init + undamped_period/undamped_eval.
!> Users `use pendula_undamped` (the facade).
module pendula_undamped_many
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_positive_inf
  use pendula_kinds, only: wp
  use pendula_status, only: status_t, check_finite, check_all_finite, set_error, PENDULA_OK, PENDULA_ERR_SIZE
  use pendula_undamped_motion, only: undamped_motion_t, undamped_init, &
                                     check_state, set_geometry, set_period, period_needed, &
                                     UNDAMPED_PLAN_MIN_TIMES, M_TINY, motion_amplitude, &
                                     REGIME_LIBRATION, REGIME_SEPARATRIX, REGIME_ROTATION
  use pendula_constants, only: pi, half_pi, half_pi_lo
  use pendula_elliptic_tables, only: atan_poly
  use pendula_elliptic, only: ellipjm1_array
  use pendula_elliptic_ke, only: k_unit_many   ! ellipkm1 over an array, inside the elliptic concern
  use pendula_angle_dd, only: cos_half
  use pendula_undamped_parameter, only: state_parameter, parameter_lanes, period_parts
  use pendula_undamped_eval, only: undamped_eval, undamped_eval_many, libration_lanes
  implicit none
  private

  public :: undamped_solve, undamped_states, undamped_properties

  !> States of their own (one time each) evaluated together by undamped_states.
  integer, parameter :: nq_max = 64

contains

  !> Checked array convenience: theta(i), omega(i) at times t(i) for one initial
  !> state.  Arrays must have equal sizes; every t finite (status otherwise).
  !> From UNDAMPED_PLAN_MIN_TIMES times on, a Jacobi plan and the blocked
  !> undamped_eval_many; below, a light motion (no F, no plan) and
  !> undamped_eval, exactly as undamped_states evaluates the same state.
  pure subroutine undamped_solve(t, theta0, omega0, w0, theta, omega, status)
    real(wp), intent(in) :: t(:)  !< times [s], finite, any order
    real(wp), intent(in) :: theta0  !< initial angle [rad], finite
    real(wp), intent(in) :: omega0  !< initial angular velocity [rad/s], finite
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], > 0
    real(wp), intent(out) :: theta(:)  !< theta(t(i)) [rad], size(t) elements
    real(wp), intent(out) :: omega(:)  !< Omega(t(i)) [rad/s], size(t) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    type(undamped_motion_t) :: motion
    theta = 0
    omega = 0
    call check_state(theta0, omega0, w0, status)
    if (status%code /= PENDULA_OK) return
    call check_all_finite('t', t, status)
    if (status%code /= PENDULA_OK) return
    if (size(t) < UNDAMPED_PLAN_MIN_TIMES) then
      call undamped_states(t, [theta0], [omega0], [w0], theta, omega, status)
    else
      call undamped_init(motion, theta0, omega0, w0, status, plan=.true.)
      call undamped_eval_many(motion, t, theta, omega, status)
    end if
  end subroutine undamped_solve

  !> Many initial states, each at its own time: theta(i), omega(i) of the state
  !> (theta0(i), omega0(i), w0(i)) at t(i).  Each input has the size of theta
  !> and omega or size 1 (one value for every element); status otherwise.
  !> Each state costs its elementary geometry and one Jacobi evaluation -- no
  !> F, no K (unless |w0 t| > ~5e11), no plan -- the same numbers as
  !> undamped_init + undamped_eval.  A run of equal consecutive states is built
  !> once; from UNDAMPED_PLAN_MIN_TIMES on, with a Jacobi plan.  On a bad
  !> element (message naming the argument of the first one, checked in the
  !> order theta0, omega0, w0, t) theta and omega are 0.
  pure subroutine undamped_states(t, theta0, omega0, w0, theta, omega, status)
    real(wp), intent(in) :: t(:)  !< times [s], finite, any order
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad], finite, n elements or one
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], finite, n elements or one
    real(wp), intent(in) :: w0(:)  !< angular frequencies [1/s], > 0, n elements or one
    real(wp), intent(out) :: theta(:)  !< theta [rad] of each state at its time
    real(wp), intent(out) :: omega(:)  !< Omega [rad/s] of each state at its time
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    type(undamped_motion_t) :: motion
    integer :: i, j, n, run, nq, idx(nq_max)
    n = size(theta)
    if (size(omega) /= n .or. .not. (fits(t, n) .and. fits(theta0, n) .and. fits(omega0, n) .and. fits(w0, n))) then
      call set_error(status, PENDULA_ERR_SIZE, &
                     'theta and omega must have one size, and t, theta0, omega0, w0 that size or size 1')
      return
    end if
    theta = 0
    omega = 0
    call check_states(n, theta0, omega0, w0, status, t)
    if (status%code /= PENDULA_OK) return
    i = 1
    nq = 0
    do while (i <= n)
      run = same_state_run(i, n, theta0, omega0, w0)
      if (run == 1) then
        ! a state of its own: queued, and evaluated with the next nq_max in one block
        nq = nq + 1
        idx(nq) = i
        if (nq == nq_max) call states_block(nq, idx, t, theta0, omega0, w0, theta, omega)
        i = i + 1
        cycle
      end if
      if (run >= UNDAMPED_PLAN_MIN_TIMES) then
        call undamped_init(motion, at(theta0, i), at(omega0, i), at(w0, i), status, plan=.true.)
      else
        call set_geometry(motion, at(theta0, i), at(omega0, i), at(w0, i))
      end if
      do j = i, i + run - 1
        if (motion%period == 0 .and. period_needed(motion, at(t, j))) call set_period(motion)
        call undamped_eval(motion, at(t, j), theta(j), omega(j))
      end do
      i = i + run
    end do
    call states_block(nq, idx, t, theta0, omega0, w0, theta, omega)
  end subroutine undamped_states

  ! Evaluate the queued states (the elements idx(1:nq)) at their times, then empty the
  ! queue (nq = 0), with the numbers of set_geometry + undamped_eval for each.  A
  ! libration with |theta0| < pi (no reduction) and |w0 t| < 2**40 (no period) is set up
  ! here in passes over the block (parameter_lanes, the block kernel of the running path;
  ! cos(theta0/2) in double-double near the separatrix) -- and its Jacobi functions come from one
  ! array call (their blocks vectorise); the others take set_geometry and undamped_eval
  ! one by one.
  pure subroutine states_block(nq, idx, t, theta0, omega0, w0, theta, omega)
    integer, intent(inout) :: nq
    integer, intent(in) :: idx(:)
    real(wp), intent(in) :: t(:), theta0(:), omega0(:), w0(:)
    real(wp), intent(inout) :: theta(:), omega(:)
    real(wp), dimension(nq_max) :: th, om, w, tt, sh, q, ch, a, p, sa, ca, da, lq, lch, lsh, lw, lth, lom, mcs
    integer :: lane(nq_max), k, j, nl
    logical :: fast(nq_max)
    type(undamped_motion_t) :: motion
    type(status_t) :: status
    do k = 1, nq
      j = idx(k)
      th(k) = at(theta0, j); om(k) = at(omega0, j); w(k) = at(w0, j); tt(k) = at(t, j)
    end do
    ! |t| < 2**19 s and w0 < 2**19 /s keep |w0 t| below 2**38: no period reduction
    ! (period_needed is false; larger ones take the general path, which decides)
    do k = 1, nq
      fast(k) = abs(th(k)) < pi .and. abs(tt(k)) < 2.0_wp**19 .and. w(k) < 2.0_wp**19
    end do
    call parameter_lanes(nq, th, om, w, fast, sh, ch, q, mcs)
    nl = 0
    do k = 1, nq
      fast(k) = fast(k) .and. mcs(k) > 0
      if (.not. fast(k)) cycle
      ! the light motion's ellipjm1 at a = rate t, rate = w0, parameter 1 - mc
      nl = nl + 1
      lane(nl) = k
      a(nl) = w(k)*tt(k)
      p(nl) = mcs(k)
    end do
    if (nl > 0) call ellipjm1_array(a(1:nl), p(1:nl), sa(1:nl), ca(1:nl), da(1:nl), status)
    do j = 1, nl
      k = lane(j)
      lq(j) = q(k); lch(j) = ch(k); lsh(j) = sh(k); lw(j) = w(k)
    end do
    call libration_lanes(nl, lq, lch, lsh, lw, sa, ca, da, lth, lom)
    do j = 1, nl
      theta(idx(lane(j))) = lth(j)
      omega(idx(lane(j))) = lom(j)
    end do
    do k = 1, nq
      if (fast(k)) cycle
      j = idx(k)
      call set_geometry(motion, th(k), om(k), w(k))
      if (period_needed(motion, tt(k))) call set_period(motion)
      call undamped_eval(motion, tt(k), theta(j), omega(j))
    end do
    nq = 0
  end subroutine states_block

  !> Whether an input of size 1 or n fits n elements.
  pure logical function fits(x, n)
    real(wp), intent(in) :: x(:)
    integer, intent(in) :: n
    fits = size(x) == n .or. size(x) == 1
  end function fits

  !> Element i of an input of size n or 1 (one value for every element).
  pure real(wp) function at(x, i)
    real(wp), intent(in) :: x(:)
    integer, intent(in) :: i
    at = x(min(i, size(x)))
  end function at

  !> How many elements from i on (up to n) share the state of element i.
  pure integer function same_state_run(i, n, theta0, omega0, w0) result(run)
    integer, intent(in) :: i, n
    real(wp), intent(in) :: theta0(:), omega0(:), w0(:)
    integer :: j
    run = 1
    do j = i + 1, n
      if (at(theta0, j) /= at(theta0, i) .or. at(omega0, j) /= at(omega0, i) .or. at(w0, j) /= at(w0, i)) exit
      run = run + 1
    end do
  end function same_state_run

  !> The checks of undamped_init over n states (inputs of size n or 1), then
  !> of t if present: status names the argument of the first bad element (its
  !> checks in the order theta0, omega0, w0, t).  One vectorisable pass when
  !> all are good.
  pure subroutine check_states(n, theta0, omega0, w0, status, t)
    integer, intent(in) :: n
    real(wp), intent(in) :: theta0(:), omega0(:), w0(:)
    type(status_t), intent(out) :: status
    real(wp), intent(in), optional :: t(:)
    integer :: i
    if (all(ieee_is_finite(theta0)) .and. all(ieee_is_finite(omega0)) .and. &
        all(w0 > 0 .and. w0 <= huge(w0))) then
      if (.not. present(t)) return
      if (all(ieee_is_finite(t))) return
    end if
    do i = 1, n
      call check_state(at(theta0, i), at(omega0, i), at(w0, i), status)
      if (present(t)) call check_finite('t', at(t, i), status)
      if (status%code /= PENDULA_OK) return
    end do
  end subroutine check_states

  !> Properties of many states (theta0(i), omega0(i), w0(i)) at once, each only
  !> when its output is present: period [s], amplitude [rad], the elliptic
  !> parameter m and 1 - m, the regime code (see undamped_period etc.).  The
  !> same numbers as undamped_init gives, from each state's elementary geometry
  !> and, for the period, one K: no F, no plan, no motion kept.  The outputs
  !> have one size n, each input n or 1 (one value for every state), and every
  !> state must be valid: otherwise status names the argument of the first bad
  !> state and the outputs are 0.
  pure subroutine undamped_properties(theta0, omega0, w0, status, period, amplitude, m, mc, regime)
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad], finite, n elements or one
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], finite, n elements or one
    real(wp), intent(in) :: w0(:)  !< angular frequencies [1/s], > 0, n elements or one
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    real(wp), intent(out), optional :: period(:)  !< optional periods [s] (+inf on the separatrix)
    real(wp), intent(out), optional :: amplitude(:)  !< optional amplitudes [rad] (+inf for rotation)
    real(wp), intent(out), optional :: m(:)  !< optional elliptic parameters m
    real(wp), intent(out), optional :: mc(:)  !< optional 1 - m
    integer, intent(out), optional :: regime(:)  !< optional regime codes (REGIME_*)
    integer, parameter :: nb = 256
    real(wp) :: c, den(nb), hp, hp_lo, atanp(0:10), inf
    real(wp), dimension(nb) :: th, om, w, sh, ch, q, mb, mcb, lib, amp
    integer :: i, i0, i1, n, k, nk, bad_k, regb(nb)
    logical :: bad, want_m, amplitudes_only, fast(nb)
    type(undamped_motion_t) :: motion
    n = max(size(theta0), size(omega0), size(w0))
    if (min(size(theta0), size(omega0), size(w0)) == 0) n = 0
    bad = .not. (fits(theta0, n) .and. fits(omega0, n) .and. fits(w0, n))
    if (present(period)) bad = bad .or. size(period) /= n
    if (present(amplitude)) bad = bad .or. size(amplitude) /= n
    if (present(m)) bad = bad .or. size(m) /= n
    if (present(mc)) bad = bad .or. size(mc) /= n
    if (present(regime)) bad = bad .or. size(regime) /= n
    if (bad) then
      call set_error(status, PENDULA_ERR_SIZE, &
                     'the outputs must have one size, and theta0, omega0, w0 that size or size 1')
      return
    end if
    want_m = present(m) .or. present(amplitude)
    ! local copies: the amplitude loop's stores then cannot touch them (it vectorises)
    hp = half_pi
    hp_lo = half_pi_lo
    atanp = atan_poly
    inf = ieee_value(1.0_wp, ieee_positive_inf)
    amplitudes_only = present(period) .and. .not. (want_m .or. present(mc) .or. present(regime)) .and. &
                      size(omega0) == 1 .and. size(w0) == 1 .and. size(theta0) == n
    if (amplitudes_only) amplitudes_only = omega0(1) == 0 .and. w0(1) > 0 .and. w0(1) <= huge(w0)
    do i0 = 1, n, nb
      i1 = min(n, i0 + nb - 1)
      if (amplitudes_only) then
        ! Omega0 = 0 and one w0 for all: 1 - m = cos^2(theta0/2) for |theta0| < pi
        ! (what state_parameter gives there, q = qlo = 0), a libration; others below.
        ! The cosines in one vectorised pass (cos_half: no libm call), then K.
        if (all(abs(theta0(i0:i1)) < pi)) then
          do i = i0, i1
            c = cos_half(0.5_wp*theta0(i))
            den(i - i0 + 1) = c*c
          end do
          call k_unit_many(den(1:i1 - i0 + 1), period(i0:i1))   ! = ellipkm1, 0 < 1 - m <= 1 here
          period(i0:i1) = (4*period(i0:i1))/w0(1)
          cycle
        end if
      end if
      nk = i1 - i0 + 1
      do k = 1, nk
        th(k) = at(theta0, i0 + k - 1)
        om(k) = at(omega0, i0 + k - 1)
        w(k) = at(w0, i0 + k - 1)
      end do
      ! the first bad state names its argument (checked here, not in a pass over all
      ! inputs before: one read of the inputs).  A scalar loop that stops there: a
      ! vectorised test would compare NaNs with signalling compares (invalid).
      bad_k = 0
      do k = 1, nk
        if (.not. (ieee_is_finite(th(k)) .and. ieee_is_finite(om(k)) .and. w(k) > 0 .and. w(k) <= huge(w))) then
          bad_k = k
          exit
        end if
      end do
      if (bad_k > 0) then
        k = bad_k
        call check_state(th(k), om(k), w(k), status)
        if (present(period)) period = 0
        if (present(amplitude)) amplitude = 0
        if (present(m)) m = 0
        if (present(mc)) mc = 0
        if (present(regime)) regime = 0
        return
      end if
      ! the parameter alone (no motion built): the block's |theta0| < pi states in
      ! passes over the block, the others one by one (state_parameter: the same numbers)
      do k = 1, nk
        fast(k) = abs(th(k)) < pi
      end do
      call parameter_lanes(nk, th, om, w, fast, sh, ch, q, mcb)
      do k = 1, nk
        regb(k) = merge(REGIME_LIBRATION, merge(REGIME_ROTATION, REGIME_SEPARATRIX, mcb(k) < 0), mcb(k) > 0)
        mb(k) = merge(sh(k)*sh(k) + q(k)*q(k), 0.0_wp, want_m .or. mcb(k) < 0)
      end do
      do k = 1, nk
        if (.not. fast(k)) call state_parameter(th(k), om(k), w(k), want_m, mb(k), mcb(k), regb(k))
      end do
      if (present(amplitude)) then
        ! motion_amplitude's numbers, 2 atan(k/sqrt(1 - m)) for a libration, as one
        ! vector loop (atan_ratio is plain arithmetic); other regimes take a neutral
        ! 0/1 there and their value after (min first: a free rotor's m is +inf, and
        ! inf*0 would raise invalid)
        do k = 1, nk
          lib(k) = merge(1.0_wp, 0.0_wp, regb(k) == REGIME_LIBRATION)
          amp(k) = 2*atan_ratio(sqrt(min(mb(k), 1.0_wp)*lib(k)), sqrt(merge(mcb(k), 1.0_wp, lib(k) > 0)), hp, hp_lo, atanp)
        end do
        do k = 1, nk
          amplitude(i0 + k - 1) = merge(amp(k), merge(pi, inf, regb(k) == REGIME_SEPARATRIX), lib(k) > 0)
        end do
        ! m that lost bits to the subnormal range (tiny states): the one-state amplitude,
        ! from the parts of m
        do k = 1, nk
          if (lib(k) > 0 .and. mb(k) < M_TINY) then
            call set_geometry(motion, th(k), om(k), w(k))
            amplitude(i0 + k - 1) = motion_amplitude(motion)
          end if
        end do
      end if
      ! numerator and denominator: the divisions of a block run as one vector loop below
      if (present(period)) call block_periods(nk, regb, mb, mcb, om, w, period(i0:i1), den)
      if (present(m)) m(i0:i1) = mb(1:nk)
      if (present(mc)) mc(i0:i1) = mcb(1:nk)
      if (present(regime)) regime(i0:i1) = regb(1:nk)
      if (present(period)) period(i0:i1) = period(i0:i1)/den(1:i1 - i0 + 1)
    end do
  end subroutine undamped_properties

  ! period_parts of the n states of a block (num/den, the same numbers): the K of its
  ! librations and rotations, ellipkm1 of an argument in (0, 1], by one k_unit_many call
  ! (the array form: ellipkm1's bits there, from the block kernel of the running path),
  ! the others (free rotor, separatrix, an argument that underflowed) by period_parts.
  pure subroutine block_periods(n, reg, m, mc, om, w, num, den)
    integer, intent(in) :: n, reg(:)
    real(wp), intent(in) :: m(:), mc(:), om(:), w(:)
    real(wp), intent(out) :: num(:), den(:)
    real(wp) :: p(n), kk(n), pk
    integer :: idx(n), j, k, nk
    logical :: rot
    nk = 0
    do k = 1, n
      rot = reg(k) == REGIME_ROTATION
      if (rot) rot = m(k) <= huge(m)
      ! ellipkm1's argument in period_parts: mc (libration), -mc/m (rotation)
      pk = 0
      if (reg(k) == REGIME_LIBRATION) pk = mc(k)
      if (rot) pk = -mc(k)/m(k)
      if (pk > 0 .and. pk <= 1) then
        nk = nk + 1
        idx(nk) = k
        p(nk) = pk
      else
        call period_parts(reg(k), m(k), mc(k), om(k), w(k), num(k), den(k))
      end if
    end do
    call k_unit_many(p(1:nk), kk(1:nk))
    do j = 1, nk
      k = idx(j)
      if (reg(k) == REGIME_LIBRATION) then
        num(k) = 4*kk(j)
        den(k) = w(k)
      else
        num(k) = 2*kk(j)
        den(k) = sqrt(m(k))*w(k)
      end if
    end do
  end subroutine block_periods

  ! atan_ratio: the amplitudes' atan, the same text as motion_amplitude's
  include 'pendula_atan_ratio.inc'

end module pendula_undamped_many
