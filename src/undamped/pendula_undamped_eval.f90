!> Evaluation of an undamped motion (pendula_undamped_motion) at times:
!> undamped_eval (elemental), undamped_eval_many (blocked, vectorised) and
!> undamped_theta / undamped_omega.  Users `use pendula_undamped` (the facade).
module pendula_undamped_eval
  use, intrinsic :: iso_c_binding, only: c_int
  use pendula_kinds, only: wp
  use pendula_status, only: status_t, check_same_size, PENDULA_OK
  use pendula_constants, only: pi, half_pi, half_pi_lo
  use pendula_elliptic_tables, only: atan_poly
  use pendula_dispatch, only: libration_block_lanes
  use pendula_elliptic, only: ellipj_eval, ellipj_eval_array, ellipjm1
  use pendula_undamped_motion, only: undamped_motion_t, period_needed, REGIME_LIBRATION, &
                                     REGIME_SEPARATRIX, REGIME_ROTATION
  implicit none
  private

  public :: undamped_eval, undamped_eval_many, undamped_theta, undamped_omega
  ! for pendula_undamped_many
  public :: libration_at, libration_parts, libration_lanes

contains

  !> theta(t) [rad] and Omega(t) [rad/s] of the motion at any real time t [s]
  !> (negative, unsorted, arrays: elemental).  theta is continuous with theta0
  !> (rotation keeps counting turns).  Accuracy: a few eps times the condition
  !> number sum |x d theta/dx| over x in {theta0, Omega0, w0, t} (tested to
  !> 16 eps cond over 100 periods against mpmath).  Non-finite t gives NaN;
  !> use `undamped_solve` for a checked call.
  !>
  !> The phase u0 (or v0) is never added to w0 t: the Jacobi functions are taken
  !> at a = w0 t alone and combined with sn, cn, dn at the phase, which the
  !> initial state gives exactly (sin, cos of theta_r/2 and Omega0/(2 w0)), by
  !> the addition theorem (DLMF 22.8.1-3, denominator 1 - m sn^2 a sn^2 b written
  !> as cn^2 a + sn^2 a dn^2 b).  So u0 ~ K (large near the separatrix) costs no
  !> eps*K of the argument, and t = 0 returns the initial state to ~1 ulp.
  elemental subroutine undamped_eval(motion, t, theta, omega)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init (or set_geometry)
    real(wp), intent(in) :: t  !< time [s], any real
    real(wp), intent(out) :: theta  !< angle [rad]
    real(wp), intent(out) :: omega  !< angular velocity [rad/s]
    real(wp) :: a, sa, ca, da, ama, y, x, z, den, sb, ss, cc, delta, ex, tt, turns
    tt = t
    turns = 0
    if (motion%free) then
      theta = motion%theta0 + motion%omega0*t
      omega = motion%omega0
      return
    end if
    if (motion%regime == REGIME_SEPARATRIX) then
      ! |w0 t| ~> 1e301 would overflow; theta is pi to the last bit long before
      if (exponent(t) > 1000 - exponent(motion%rate)) tt = sign(1.0e300_wp, t)/motion%rate
    else if (period_needed(motion, t)) then
      ! |rate t| >~ 5e11: take whole periods out first (modulo is exact; the
      ! period's rounding moves t by ~eps |t|, inside the condition number).
      ! This also kept clear of an ellipj_eval bug of 03:12 UTC (|sn| > 1 from
      ! u ~ 1e17, a crash near 1e25-1e30), fixed in pendula_elliptic 495978f;
      ! it stays because it is exact and keeps rate t finite up to 1e308.
      tt = modulo(t, motion%period)
      turns = anint((t - tt)/motion%period)
    end if
    select case (motion%regime)
    case (REGIME_LIBRATION)
      a = motion%rate*tt
      if (motion%planned) then
        call ellipj_eval(motion%plan, a, sa, ca, da)
      else
        call ellipjm1(a, motion%pmc, sa, ca, da)
      end if
      call libration_at(motion, sa, ca, da, theta, omega)
    case (REGIME_ROTATION)
      a = motion%rate*tt
      if (motion%planned) then
        call ellipj_eval(motion%plan, a, sa, ca, da, ama)
      else
        call ellipjm1(a, motion%pmc, sa, ca, da, ama)
      end if
      ! sn(a+b), cn(a+b) times the denominator, at parameter 1/m, with
      ! sn b = s sh, cn b = ch, dn b = dnb; then am(a+b) = am(a) + delta where
      ! delta = int_a^{a+b} dn lies in (0, pi) for b > 0 (|b| <= K), so the
      ! branch of the atan2 is fixed by the sign of b.
      sb = motion%s*motion%sh
      ss = sa*motion%ch*motion%dnb + sb*ca*da
      cc = ca*motion%ch - sa*sb*da*motion%dnb
      delta = atan2(ss*ca - cc*sa, cc*ca + ss*sa)
      if (sb > 0 .and. delta < -half_pi) delta = delta + 2*pi
      if (sb < 0 .and. delta > half_pi) delta = delta - 2*pi
      theta = motion%center + 2*motion%s*(ama + delta)
      if (turns /= 0) theta = theta + motion%s*(2*pi)*turns
      den = ca*ca + (sa*motion%dnb)**2
      omega = 2*(motion%s*motion%rate*((da*motion%dnb - sa*sb*ca*motion%ch/motion%m)/den))
    case default
      if (motion%s == 0) then
        theta = motion%center + motion%theta_r
        omega = 0
        return
      end if
      x = motion%w0*tt + motion%phase
      ! gd(x) = 2 atan(tanh(x/2)), sech(x) = 2 e^-|x| / (1 + e^-2|x|): no overflow
      ex = exp(-abs(x))
      theta = motion%center + motion%s*4*atan(tanh(0.5_wp*x))
      omega = 2*(motion%s*motion%w0*(2*ex/(1 + ex*ex)))
    end select
  end subroutine undamped_eval

  !> theta and Omega of a libration from sn, cn, dn at a = rate t (parameter
  !> 1 - pmc): the addition theorem about the initial state's argument.
  elemental subroutine libration_at(motion, sa, ca, da, theta, omega)
    type(undamped_motion_t), intent(in) :: motion  !< a libration built by undamped_init (or set_geometry)
    real(wp), intent(in) :: sa  !< sn(a)
    real(wp), intent(in) :: ca  !< cn(a)
    real(wp), intent(in) :: da  !< dn(a)
    real(wp), intent(out) :: theta  !< angle [rad]
    real(wp), intent(out) :: omega  !< angular velocity [rad/s]
    call libration_parts(motion%q, motion%ch, motion%sh, motion%center, motion%w0, sa, ca, da, theta, omega)
  end subroutine libration_at

  !> libration_at from the motion's numbers: q = Omega0/(2 w0), ch, sh = cos, sin of
  !> theta_r/2, the centre 2 pi N and w0 (what pendula_undamped_many's blocks hold).
  elemental subroutine libration_parts(q, ch, sh, center, w0, sa, ca, da, theta, omega)
    real(wp), intent(in) :: q  !< Omega0/(2 w0) = k cn(u0|m)
    real(wp), intent(in) :: ch  !< cos(theta_r/2) = dn(u0|m)
    real(wp), intent(in) :: sh  !< sin(theta_r/2) = k sn(u0|m)
    real(wp), intent(in) :: center  !< 2 pi N [rad]
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s]
    real(wp), intent(in) :: sa  !< sn(a)
    real(wp), intent(in) :: ca  !< cn(a)
    real(wp), intent(in) :: da  !< dn(a)
    real(wp), intent(out) :: theta  !< angle [rad]
    real(wp), intent(out) :: omega  !< angular velocity [rad/s]
    real(wp), dimension(64) :: q1, ch1, sh1, w1, sa1, ca1, da1, th, om
    ! one lane of the block (here, where gcc inlines it: no call through the dispatch per point)
    q1(1) = q; ch1(1) = ch; sh1(1) = sh; w1(1) = w0; sa1(1) = sa; ca1(1) = ca; da1(1) = da
    call libration_block(1, q1, ch1, sh1, w1, sa1, ca1, da1, half_pi, half_pi_lo, atan_poly, th, om)
    theta = center + th(1)
    omega = om(1)
  end subroutine libration_parts

  !> theta - 2 pi N and Omega of a libration at the first n of 64 points from sn, cn, dn at
  !> a = w0 t (parameter 1 - m) and the state's q = Omega0/(2 w0), ch, sh = cos, sin of
  !> theta_r/2: the addition theorem about the initial state's argument (libration_block),
  !> in the variant of the block kernel (pendula_undamped_lanes.F90) that the runtime
  !> dispatch chose for this CPU.
  pure subroutine libration_lanes(n, q, ch, sh, w0, sa, ca, da, theta, omega)
    integer, intent(in) :: n  !< number of points, <= 64
    real(wp), intent(in) :: q(64)  !< Omega0/(2 w0) = k cn(u0|m)
    real(wp), intent(in) :: ch(64)  !< cos(theta_r/2) = dn(u0|m)
    real(wp), intent(in) :: sh(64)  !< sin(theta_r/2) = k sn(u0|m)
    real(wp), intent(in) :: w0(64)  !< small-angle angular frequencies [1/s]
    real(wp), intent(in) :: sa(64)  !< sn(a)
    real(wp), intent(in) :: ca(64)  !< cn(a)
    real(wp), intent(in) :: da(64)  !< dn(a)
    real(wp), intent(out) :: theta(64)  !< theta - 2 pi N [rad]
    real(wp), intent(out) :: omega(64)  !< angular velocities [rad/s]
    call libration_block_lanes(int(n, c_int), q, ch, sh, w0, sa, ca, da, half_pi, half_pi_lo, atan_poly, theta, omega)
  end subroutine libration_lanes

  ! libration_block and atan_ratio: libration_parts runs them here (baseline code, inlined);
  ! libration_lanes calls the variant the runtime dispatch chose (libration_block_lanes,
  ! pendula_undamped_lanes.F90), compiled from this same text.
  include 'pendula_libration_block.inc'

  !> Same as `undamped_eval` for an array of times (results agree to a few
  !> ulps), organised for speed: blocks of times go through the Jacobi
  !> functions, the addition theorem and a vectorisable atan/atan2 loop
  !> (libmvec), which halves the cost per point.  theta and omega must have the
  !> size of t (status PENDULA_ERR_SIZE otherwise, outputs untouched); times are
  !> not checked for finiteness here (`undamped_solve` does that).
  pure subroutine undamped_eval_many(motion, t, theta, omega, status)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init (or set_geometry)
    real(wp), intent(in) :: t(:)  !< times [s], finite, any order
    real(wp), intent(inout) :: theta(:)  !< theta(t(i)) [rad], size(t) elements
    real(wp), intent(inout) :: omega(:)  !< Omega(t(i)) [rad/s], size(t) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    integer, parameter :: nb = 256
    real(wp) :: a(nb), sa(nb), ca(nb), da(nb), ama(nb), y(nb), x(nb), r(nb), sb
    integer :: i0, i1, nc, i, j
    call check_same_size('theta', size(theta), 't', size(t), status)
    call check_same_size('omega', size(omega), 't', size(t), status)
    if (status%code /= PENDULA_OK) return
    if (motion%free .or. (motion%regime /= REGIME_LIBRATION .and. motion%regime /= REGIME_ROTATION)) then
      call undamped_eval(motion, t, theta(1:size(t)), omega(1:size(t)))
      return
    end if
    sb = motion%s*motion%sh
    do i0 = 1, size(t), nb
      nc = min(nb, size(t) - i0 + 1)
      i1 = i0 + nc - 1
      if (any(period_needed(motion, t(i0:i1)))) then
        ! huge times need the period reduction of the scalar path
        call undamped_eval(motion, t(i0:i1), theta(i0:i1), omega(i0:i1))
        cycle
      end if
      a(1:nc) = motion%rate*t(i0:i1)
      if (motion%regime == REGIME_LIBRATION) then
        if (motion%planned) then
          call ellipj_eval_array(motion%plan, a(1:nc), sa(1:nc), ca(1:nc), da(1:nc), status)
        else
          call ellipjm1(a(1:nc), motion%pmc, sa(1:nc), ca(1:nc), da(1:nc))
        end if
        do i = 1, nc
          j = i0 + i - 1
          y(i) = sa(i)*motion%q*motion%ch + motion%sh*ca(i)*da(i)
          x(i) = da(i)*motion%ch - sa(i)*ca(i)*motion%sh*motion%q
          omega(j) = 2*(motion%w0*((ca(i)*motion%q - sa(i)*motion%sh*da(i)*motion%ch) &
                                   /(ca(i)*ca(i) + (sa(i)*motion%ch)**2)))
          r(i) = y(i)/x(i)
        end do
        do i = 1, nc
          theta(i0 + i - 1) = motion%center + 2*atan(r(i))
        end do
        do i = 1, nc
          if (.not. x(i) > 0) theta(i0 + i - 1) = motion%center + 2*atan2(y(i), x(i))
        end do
      else
        if (motion%planned) then
          call ellipj_eval_array(motion%plan, a(1:nc), sa(1:nc), ca(1:nc), da(1:nc), status, ama(1:nc))
        else
          call ellipjm1(a(1:nc), motion%pmc, sa(1:nc), ca(1:nc), da(1:nc), ama(1:nc))
        end if
        do i = 1, nc
          j = i0 + i - 1
          ! ss, cc as in undamped_eval, kept in y, x; r <- the denominator
          y(i) = sa(i)*motion%ch*motion%dnb + sb*ca(i)*da(i)
          x(i) = ca(i)*motion%ch - sa(i)*sb*da(i)*motion%dnb
          r(i) = ca(i)*ca(i) + (sa(i)*motion%dnb)**2
          omega(j) = 2*(motion%s*motion%rate*((da(i)*motion%dnb - sa(i)*sb*ca(i)*motion%ch &
                                               /motion%m)/r(i)))
          r(i) = y(i)*ca(i) - x(i)*sa(i)
          x(i) = x(i)*ca(i) + y(i)*sa(i)
        end do
        do i = 1, nc
          y(i) = atan2(r(i), x(i))
        end do
        do i = 1, nc
          if (sb > 0 .and. y(i) < -half_pi) y(i) = y(i) + 2*pi
          if (sb < 0 .and. y(i) > half_pi) y(i) = y(i) - 2*pi
          theta(i0 + i - 1) = motion%center + 2*motion%s*(ama(i) + y(i))
        end do
      end if
    end do
  end subroutine undamped_eval_many

  !> theta(t) [rad] alone (see undamped_eval).
  elemental real(wp) function undamped_theta(motion, t) result(theta)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init (or set_geometry)
    real(wp), intent(in) :: t  !< time [s], any real
    real(wp) :: omega
    call undamped_eval(motion, t, theta, omega)
  end function undamped_theta

  !> Omega(t) [rad/s] alone (see undamped_eval).
  elemental real(wp) function undamped_omega(motion, t) result(omega)
    type(undamped_motion_t), intent(in) :: motion  !< a motion built by undamped_init (or set_geometry)
    real(wp), intent(in) :: t  !< time [s], any real
    real(wp) :: theta
    call undamped_eval(motion, t, theta, omega)
  end function undamped_omega

end module pendula_undamped_eval
