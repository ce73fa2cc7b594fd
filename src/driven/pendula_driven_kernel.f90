!> The driven pendulum's fixed-step RK4 on blocks of DRIVEN_LANES states.
!>
!> Each lane is one state with its own w0, gamma and drive (kind shared by
!> the block); the step is h = T/N for an integer N per drive period T, so
!> the stage times of step j of any period are t0 + (k + j/N) T and
!> t0 + (k + (j + 1/2)/N) T: the drive's P(t) and Q(t) (pendula_drive) are
!> tabulated once per call at the 2 N + 1 half-step phases, computed from
!> integers, and no phase is lost however many periods run.
!>
!> Why lanes: a step of one state is a chain of dependent operations; a loop
!> over lanes has none, so gcc vectorises it.  sin(theta) and cos(theta) are
!> a branch-free polynomial (lane_sincos: Cody-Waite reduction by pi, Taylor
!> series to degree 21/22 on [-pi/2, pi/2], about 1 ulp) instead of libm,
!> which does not vectorise.  Every lane performs the same operations in the
!> same order whatever the other lanes hold (no FMA contraction:
!> -ffp-contract=off), so a state's result never depends on its batch.
!>
!> The tangent form also carries two tangent vectors through the RK4 stages
!> (the exact derivative of the RK4 map: the variational equation
!> dp' = q, dq' = -gamma q - P(t) cos(theta) p at the stage states), for
!> Lyapunov exponents and monodromy matrices.
module pendula_driven_kernel
  use pendula_kinds, only: wp
  use pendula_constants, only: pi
  use pendula_kinds, only: i8
  use pendula_status, only: status_t, check_alloc
  use pendula_drive, only: DRIVE_PIVOT
  implicit none
  private
  public :: DRIVEN_LANES, lanes_t, lanes_setup, lanes_steps, lanes_steps_tangent, lane_sincos, &
            lanes_partial, lanes_finite

  !> States per block: SIMD lanes of the kernel.
  integer, parameter :: DRIVEN_LANES = 8
  integer, parameter :: nl = DRIVEN_LANES

  ! Cody-Waite split of pi (fdlibm's pio2_1, pio2_2, pio2_3 doubled): k pi1
  ! and k pi2 are exact for |k| < 2**20.
  real(wp), parameter :: pi1 = 3.14159265346825122833_wp, pi2 = 1.21542010130079319532e-10_wp, &
                         pi3 = 4.04453249742233291160e-21_wp
  real(wp), parameter :: inv_pi = 0.318309886183790671538_wp
  ! Adding and subtracting 1.5 * 2**52 rounds to the nearest integer (vectorises; anint may not).
  real(wp), parameter :: round_magic = 6755399441055744.0_wp

  !> A block's constants: step, damping and the drive tables of each lane.
  type :: lanes_t
    integer :: nsteps = 0
    real(wp) :: h(nl) = 0, hh(nl) = 0, h6(nl) = 0, gam(nl) = 0
    !> P and Q of each lane at half-step phase index m = 0..2 nsteps.
    real(wp), allocatable :: p(:, :), q(:, :)
    !> phase0 + the drive phase at t0 of each lane, amplitude, frequency, w0, kind (for lanes_partial).
    real(wp) :: phase(nl) = 0, amp(nl) = 0, freq(nl) = 1, wsq(nl) = 0
    integer :: kind = 1
  end type lanes_t

contains

  !> Fill a block: lane l gets w0(l), gamma(l) and a drive of this kind with
  !> amplitude amp(l), frequency freq(l) and phase phase0(l) [rad] at the
  !> start time t0 (phase0 = Omega t0 + phi); nsteps RK4 steps per period.
  !> The tables hold 2 x DRIVEN_LANES x (2 nsteps + 1) doubles; when they
  !> cannot be allocated, status (optional) gets PENDULA_ERR_MEMORY with the
  !> size and the block is left without tables (b%nsteps = 0: the stepping
  !> routines then do nothing).
  pure subroutine lanes_setup(b, kind, nsteps, w0, gamma, amp, freq, phase0, status)
    type(lanes_t), intent(inout) :: b  !< the block (tables reallocated when nsteps changes)
    integer, intent(in) :: kind  !< DRIVE_TORQUE or DRIVE_PIVOT
    integer, intent(in) :: nsteps  !< RK4 steps per drive period
    real(wp), intent(in), dimension(nl) :: w0  !< small-angle angular frequencies [1/s]
    real(wp), intent(in), dimension(nl) :: gamma  !< damping rates [1/s]
    real(wp), intent(in), dimension(nl) :: amp  !< drive amplitudes (rad/s**2, or a/l)
    real(wp), intent(in), dimension(nl) :: freq  !< drive frequencies [rad/s]
    real(wp), intent(in), dimension(nl) :: phase0  !< drive phases at the start time [rad]
    type(status_t), intent(inout), optional :: status  !< receives PENDULA_ERR_MEMORY when the tables cannot be allocated
    integer :: m, l, ist
    real(wp) :: c
    if (allocated(b%p)) then
      if (size(b%p, 2) /= 2*nsteps + 1) deallocate (b%p, b%q)
    end if
    if (.not. allocated(b%p)) then
      allocate (b%p(nl, 0:2*nsteps), b%q(nl, 0:2*nsteps), stat=ist)
      if (ist /= 0) then
        if (allocated(b%p)) deallocate (b%p)
        if (allocated(b%q)) deallocate (b%q)
        b%nsteps = 0
        if (present(status)) call check_alloc(ist, 'the drive tables of a block of lanes', 2_i8*nl*(2_i8*nsteps + 1), 8, &
                                              status)
        return
      end if
    end if
    b%nsteps = nsteps
    b%kind = kind
    do l = 1, nl
      b%h(l) = (2*pi/freq(l))/nsteps
      b%hh(l) = 0.5_wp*b%h(l)
      b%h6(l) = b%h(l)/6
      b%gam(l) = gamma(l)
      b%phase(l) = phase0(l)
      b%amp(l) = amp(l)
      b%freq(l) = freq(l)
      b%wsq(l) = w0(l)*w0(l)
      do m = 0, 2*nsteps
        ! the half-step phase from integers: exact whatever the period count
        c = cos(phase0(l) + (2*pi)*(real(m, wp)/(2*nsteps)))
        if (kind == DRIVE_PIVOT) then
          b%p(l, m) = b%wsq(l) + amp(l)*freq(l)**2*c
          b%q(l, m) = 0
        else
          b%p(l, m) = b%wsq(l)
          b%q(l, m) = amp(l)*c
        end if
      end do
    end do
  end subroutine lanes_setup

  !> sin(x) and cos(x) to about 1 ulp for |x| < 2**20 pi (beyond, the
  !> reduction error grows like ulp(x): the angle itself is no better known).
  elemental subroutine lane_sincos(x, s, c)
    real(wp), intent(in) :: x  !< angle [rad], |x| < 2**50
    real(wp), intent(out) :: s  !< sin(x)
    real(wp), intent(out) :: c  !< cos(x)
    real(wp) :: k, r, z, z2, z4, e0, e1, sg, kh
    include 'pendula_driven_sincos.inc'
  end subroutine lane_sincos

  !> sin and cos of every lane (lane_sincos as one loop over the lanes, which
  !> gcc vectorises whether or not it inlines this).
  pure subroutine lanes_sc(xa, sa, ca)
    real(wp), intent(in) :: xa(nl)  !< angles [rad]
    real(wp), intent(out) :: sa(nl)  !< sin(xa)
    real(wp), intent(out) :: ca(nl)  !< cos(xa)
    real(wp) :: k, r, z, z2, z4, e0, e1, sg, kh, x, s, c
    integer :: l
    do l = 1, nl
      x = xa(l)
      include 'pendula_driven_sincos.inc'
      sa(l) = s
      ca(l) = c
    end do
  end subroutine lanes_sc

  !> sin of every lane (lanes_sc without the cosine).
  pure subroutine lanes_s(xa, sa)
    real(wp), intent(in) :: xa(nl)  !< angles [rad]
    real(wp), intent(out) :: sa(nl)  !< sin(xa)
    real(wp) :: k, r, z, z2, z4, e0, e1, sg, kh, x, s
    integer :: l
    do l = 1, nl
      x = xa(l)
      include 'pendula_driven_sin.inc'
      sa(l) = s
    end do
  end subroutine lanes_s

  !> Advance every lane by steps j = j0, ..., j1 - 1 of the current period
  !> (0 <= j0 <= j1 <= nsteps).
  pure subroutine lanes_steps(b, j0, j1, y, u)
    type(lanes_t), intent(in) :: b  !< the block
    integer, intent(in) :: j0  !< first step (0-based) within the period
    integer, intent(in) :: j1  !< one past the last step
    real(wp), intent(inout) :: y(nl)  !< angles [rad]
    real(wp), intent(inout) :: u(nl)  !< angular velocities [rad/s]
    real(wp), dimension(nl) :: y2, u2, y3, u3, y4, u4, s, k1, k2, k3, k4
    integer :: j, m
    if (.not. allocated(b%p)) return   ! a block whose tables could not be allocated (lanes_setup)
    do j = j0, j1 - 1
      m = 2*j
      call lanes_s(y, s)
      k1 = (b%q(:, m) - b%gam*u) - b%p(:, m)*s
      y2 = y + b%hh*u
      u2 = u + b%hh*k1
      call lanes_s(y2, s)
      k2 = (b%q(:, m + 1) - b%gam*u2) - b%p(:, m + 1)*s
      y3 = y + b%hh*u2
      u3 = u + b%hh*k2
      call lanes_s(y3, s)
      k3 = (b%q(:, m + 1) - b%gam*u3) - b%p(:, m + 1)*s
      y4 = y + b%h*u3
      u4 = u + b%h*k3
      call lanes_s(y4, s)
      k4 = (b%q(:, m + 2) - b%gam*u4) - b%p(:, m + 2)*s
      y = y + b%h6*((u + 2*(u2 + u3)) + u4)
      u = u + b%h6*((k1 + 2*(k2 + k3)) + k4)
    end do
  end subroutine lanes_steps

  !> lanes_steps with two tangent vectors (p1, q1) and (p2, q2) per lane
  !> carried by the derivative of each RK4 step.
  pure subroutine lanes_steps_tangent(b, j0, j1, y, u, v)
    type(lanes_t), intent(in) :: b  !< the block
    integer, intent(in) :: j0  !< first step (0-based) within the period
    integer, intent(in) :: j1  !< one past the last step
    real(wp), intent(inout) :: y(nl)  !< angles [rad]
    real(wp), intent(inout) :: u(nl)  !< angular velocities [rad/s]
    real(wp), intent(inout) :: v(nl, 4)  !< tangent vectors: (p1, q1, p2, q2) per lane
    real(wp), dimension(nl) :: y2, u2, y3, u3, y4, u4, s, c, k1, k2, k3, k4, a1, a2, a3, a4
    real(wp), dimension(nl) :: p, q, e2, f2, e3, f3, e4, f4, l1, l2, l3, l4
    integer :: j, m, i
    if (.not. allocated(b%p)) return   ! a block whose tables could not be allocated (lanes_setup)
    do j = j0, j1 - 1
      m = 2*j
      call lanes_sc(y, s, c)
      a1 = b%p(:, m)*c
      k1 = (b%q(:, m) - b%gam*u) - b%p(:, m)*s
      y2 = y + b%hh*u
      u2 = u + b%hh*k1
      call lanes_sc(y2, s, c)
      a2 = b%p(:, m + 1)*c
      k2 = (b%q(:, m + 1) - b%gam*u2) - b%p(:, m + 1)*s
      y3 = y + b%hh*u2
      u3 = u + b%hh*k2
      call lanes_sc(y3, s, c)
      a3 = b%p(:, m + 1)*c
      k3 = (b%q(:, m + 1) - b%gam*u3) - b%p(:, m + 1)*s
      y4 = y + b%h*u3
      u4 = u + b%h*k3
      call lanes_sc(y4, s, c)
      a4 = b%p(:, m + 2)*c
      k4 = (b%q(:, m + 2) - b%gam*u4) - b%p(:, m + 2)*s
      y = y + b%h6*((u + 2*(u2 + u3)) + u4)
      u = u + b%h6*((k1 + 2*(k2 + k3)) + k4)
      do i = 1, 3, 2
        p = v(:, i)
        q = v(:, i + 1)
        l1 = -b%gam*q - a1*p
        e2 = p + b%hh*q
        f2 = q + b%hh*l1
        l2 = -b%gam*f2 - a2*e2
        e3 = p + b%hh*f2
        f3 = q + b%hh*l2
        l3 = -b%gam*f3 - a3*e3
        e4 = p + b%h*f3
        f4 = q + b%h*l3
        l4 = -b%gam*f4 - a4*e4
        v(:, i) = p + b%h6*((q + 2*(f2 + f3)) + f4)
        v(:, i + 1) = q + b%h6*((l1 + 2*(l2 + l3)) + l4)
      end do
    end do
  end subroutine lanes_steps_tangent

  !> One RK4 step of size frac h (0 < frac < 1) from the grid state (y, u) at
  !> half-step phase index 2 j of the period, for an output between grid
  !> times; the drive is evaluated directly there (libm cos).  Lane l only.
  pure subroutine lanes_partial(b, l, j, frac, y, u, yo, uo)
    type(lanes_t), intent(in) :: b  !< the block
    integer, intent(in) :: l  !< the lane
    integer, intent(in) :: j  !< step index within the period of the grid state
    real(wp), intent(in) :: frac  !< fraction of a step to take, in [0, 1)
    real(wp), intent(in) :: y  !< grid angle [rad]
    real(wp), intent(in) :: u  !< grid angular velocity [rad/s]
    real(wp), intent(out) :: yo  !< angle at the output time [rad]
    real(wp), intent(out) :: uo  !< angular velocity at the output time [rad/s]
    real(wp) :: h, psi0, pp(0:2), qq(0:2), c, k1, k2, k3, k4, y2, u2, y3, u3, y4, u4
    integer :: i
    if (frac == 0) then
      yo = y
      uo = u
      return
    end if
    h = frac*b%h(l)
    psi0 = b%phase(l) + (2*pi)*(real(j, wp)/b%nsteps)
    do i = 0, 2
      c = cos(psi0 + (0.5_wp*i)*(h*b%freq(l)))
      if (b%kind == DRIVE_PIVOT) then
        pp(i) = b%wsq(l) + b%amp(l)*b%freq(l)**2*c
        qq(i) = 0
      else
        pp(i) = b%wsq(l)
        qq(i) = b%amp(l)*c
      end if
    end do
    k1 = (qq(0) - b%gam(l)*u) - pp(0)*sin(y)
    y2 = y + 0.5_wp*h*u
    u2 = u + 0.5_wp*h*k1
    k2 = (qq(1) - b%gam(l)*u2) - pp(1)*sin(y2)
    y3 = y + 0.5_wp*h*u2
    u3 = u + 0.5_wp*h*k2
    k3 = (qq(1) - b%gam(l)*u3) - pp(1)*sin(y3)
    y4 = y + h*u3
    u4 = u + h*k3
    k4 = (qq(2) - b%gam(l)*u4) - pp(2)*sin(y4)
    yo = y + h/6*((u + 2*(u2 + u3)) + u4)
    uo = u + h/6*((k1 + 2*(k2 + k3)) + k4)
  end subroutine lanes_partial

  !> 1 where the lane's state is finite and |theta| < 2**50 rad (the
  !> polynomial's reduction range), else 0 (branch-free over the lanes).
  pure function lanes_finite(y, u) result(ok)
    real(wp), intent(in) :: y(nl)  !< angles [rad]
    real(wp), intent(in) :: u(nl)  !< angular velocities [rad/s]
    logical :: ok(nl)
    integer :: l
    do l = 1, nl
      ok(l) = abs(y(l)) < 1.0e15_wp .and. abs(u(l)) <= huge(u)
    end do
  end function lanes_finite

end module pendula_driven_kernel
