!> Which compiled variant of the hot kernels (the batch RK4 block kernel, the
!> Taylor batch's series kernel, the block kernel of the K and E array forms, the
!> compensated AGM of K in double-double for a block, the core of the Jacobi array forms,
!> the librations of undamped_states, the elliptic parameter of a block of undamped states) runs (runtime CPU dispatch):
!> the portable baseline, x86-64-v3 (AVX2 + FMA) or x86-64-v4 (AVX-512).
!> The choice is made once when the library is loaded, from the CPU's
!> features or the environment variable PENDULA_KERNEL = baseline | v3 | v4
!> (pendula_kernel_path.c); every path gives the same bits (see
!> pendula_rk4_lanes.F90), only the speed differs.  Non-x86 builds have the
!> baseline path only.
module pendula_dispatch
  use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double
  implicit none
  private
  public :: KERNEL_BASELINE, KERNEL_V3, KERNEL_V4, kernel_path, kernel_path_available
  public :: rk4_lanes, rk4_lanes_width, taylor_series_lanes, ke_block_lanes, k_dd_block_lanes, &
            core_block_lanes, libration_block_lanes, parameter_block_lanes

  !> Kernel paths: portable baseline (SSE2 on x86-64), x86-64-v3, x86-64-v4.
  integer, parameter :: KERNEL_BASELINE = 0, KERNEL_V3 = 1, KERNEL_V4 = 2

  interface
    function c_kernel_path() bind(C, name='pendula_kernel_path')
      import :: c_int
      integer(c_int) :: c_kernel_path
    end function c_kernel_path
    function c_kernel_available(p) bind(C, name='pendula_kernel_available')
      import :: c_int
      integer(c_int), intent(in) :: p
      integer(c_int) :: c_kernel_available
    end function c_kernel_available
    !> States per block (lanes) of the running path's batch RK4 kernel: the
    !> largest nb that rk4_lanes takes (RK4_BATCH_LANES, or 128 on x86-64-v4).
    function rk4_lanes_width() bind(C, name='pendula_rk4_lanes_width')
      import :: c_int
      integer(c_int) :: rk4_lanes_width
    end function rk4_lanes_width
    !> The batch RK4 block kernel of the running path (pendula_rk4_lanes.F90).
    subroutine rk4_lanes(nt, t, nb, idx, nw, w0, ng, gamma, nh, h, ldn, theta, omega, nsteps, dead, &
                         poll, ncontrol, control, icancel, done) bind(C, name='pendula_rk4_lanes')
      import :: c_int, c_int64_t, c_double
      integer(c_int), intent(in) :: nt  !< output times
      real(c_double), intent(in) :: t(nt)  !< output times [s]
      integer(c_int), intent(in) :: nb  !< states in the block
      integer(c_int), intent(in) :: idx(nb)  !< their columns in theta and omega
      integer(c_int), intent(in) :: nw  !< size of w0
      real(c_double), intent(in) :: w0(nw)  !< angular frequencies [1/s]
      integer(c_int), intent(in) :: ng  !< size of gamma
      real(c_double), intent(in) :: gamma(ng)  !< damping rates [1/s]
      integer(c_int), intent(in) :: nh  !< size of h
      real(c_double), intent(in) :: h(nh)  !< step bounds [s]
      integer(c_int), intent(in) :: ldn  !< columns of theta and omega
      real(c_double), intent(inout) :: theta(nt, ldn)  !< angles [rad]
      real(c_double), intent(inout) :: omega(nt, ldn)  !< angular velocities [rad/s]
      integer(c_int64_t), intent(out) :: nsteps(nb)  !< steps of each lane
      integer(c_int), intent(out) :: dead(nb)  !< 1 where a lane stopped being finite
      integer(c_int), intent(in) :: poll  !< nonzero: look at control(icancel)
      integer(c_int), intent(in) :: ncontrol  !< size of control
      integer(c_int64_t), intent(inout), volatile :: control(ncontrol)  !< cancel flag holder
      integer(c_int), intent(in) :: icancel  !< index of the cancel flag
      integer(c_int), intent(out) :: done  !< 1 when the block finished
    end subroutine rk4_lanes
    !> The Taylor batch's series kernel of the running path (pendula_taylor_series_lanes.F90).
    subroutine taylor_series_lanes(pmax, maxo, w0sq, gam, cc, ss, xx, vv) bind(C, name='pendula_taylor_series_lanes')
      import :: c_int, c_double
      integer(c_int), intent(in) :: pmax  !< highest order to form
      integer(c_int), intent(in) :: maxo  !< last index of the coefficient arrays
      real(c_double), intent(in) :: w0sq(*)  !< w0**2 of each lane [1/s**2]
      real(c_double), intent(in) :: gam(*)  !< gamma of each lane [1/s]
      real(c_double), intent(inout) :: cc(*)  !< series of cos(theta), (lanes, 0:maxo)
      real(c_double), intent(inout) :: ss(*)  !< series of sin(theta)
      real(c_double), intent(inout) :: xx(*)  !< series of theta
      real(c_double), intent(inout) :: vv(*)  !< series of Omega
    end subroutine taylor_series_lanes
    !> The block kernel of the K and E array forms of the running path
    !> (pendula_elliptic_ke_lanes.F90): K (second = 0) or E of n <= 256 pairs (m, 1 - m).
    pure subroutine ke_block_lanes(n, m, mc, second, x) bind(C, name='pendula_ke_block')
      import :: c_int, c_double
      integer(c_int), intent(in) :: n  !< elements, 1 to 256
      real(c_double), intent(in) :: m(n)  !< parameters m in [0, 1)
      real(c_double), intent(in) :: mc(n)  !< 1 - m
      integer(c_int), intent(in) :: second  !< 0: K, otherwise E
      real(c_double), intent(out) :: x(n)  !< K(m(j)) or E(m(j))
    end subroutine ke_block_lanes
    !> K in double-double of nb points by the compensated AGM, of the running path
    !> (pendula_elliptic_k_lanes.F90): mc = mch + mcl > 0 each, pi/2 = hp + hp_lo.
    pure subroutine k_dd_block_lanes(nb, mch, mcl, hp, hp_lo, khi, klo) bind(C, name='pendula_k_dd_block')
      import :: c_int, c_double
      integer(c_int), intent(in) :: nb  !< points, >= 0
      real(c_double), intent(in) :: mch(nb)  !< 1 - m, high part, > 0 (1: no K wanted)
      real(c_double), intent(in) :: mcl(nb)  !< 1 - m, low part
      real(c_double), intent(in) :: hp  !< pi/2, high part
      real(c_double), intent(in) :: hp_lo  !< pi/2, low part
      real(c_double), intent(out) :: khi(nb)  !< K, high part
      real(c_double), intent(out) :: klo(nb)  !< K, low part
    end subroutine k_dd_block_lanes
    !> sn, cn, dn at nb core arguments 0 <= v <= K/2 (parameters m, mc = 1 - m), of the
    !> running path (pendula_jacobi_lanes.F90).
    pure subroutine core_block_lanes(nb, v, m, mc, s, c, d) bind(C, name='pendula_jacobi_core_block')
      import :: c_int, c_double
      integer(c_int), intent(in) :: nb  !< points, >= 0
      real(c_double), intent(in) :: v(nb)  !< core arguments
      real(c_double), intent(in) :: m(nb)  !< parameters m in [0, 1]
      real(c_double), intent(in) :: mc(nb)  !< 1 - m
      real(c_double), intent(out) :: s(nb)  !< sn(v|m)
      real(c_double), intent(out) :: c(nb)  !< cn(v|m)
      real(c_double), intent(out) :: d(nb)  !< dn(v|m)
    end subroutine core_block_lanes
    !> theta - 2 pi N and Omega of n <= 64 librations by the addition theorem, of the
    !> running path (undamped/pendula_undamped_lanes.F90).
    pure subroutine libration_block_lanes(n, q, ch, sh, w0, sa, ca, da, hp, hp_lo, atanp, theta, omega) &
      bind(C, name='pendula_libration_block')
      import :: c_int, c_double
      integer(c_int), intent(in) :: n  !< number of points, <= 64
      real(c_double), intent(in) :: q(64)  !< Omega0/(2 w0)
      real(c_double), intent(in) :: ch(64)  !< cos(theta_r/2)
      real(c_double), intent(in) :: sh(64)  !< sin(theta_r/2)
      real(c_double), intent(in) :: w0(64)  !< small-angle angular frequencies [1/s]
      real(c_double), intent(in) :: sa(64)  !< sn(a)
      real(c_double), intent(in) :: ca(64)  !< cn(a)
      real(c_double), intent(in) :: da(64)  !< dn(a)
      real(c_double), intent(in) :: hp  !< pi/2, high part
      real(c_double), intent(in) :: hp_lo  !< pi/2, low part
      real(c_double), intent(in) :: atanp(0:10)  !< the atan polynomial's coefficients
      real(c_double), intent(out) :: theta(64)  !< theta - 2 pi N [rad]
      real(c_double), intent(out) :: omega(64)  !< angular velocities [rad/s]
    end subroutine libration_block_lanes
    !> sin, cos of theta0/2, Omega0/(2 w0) and 1 - m of n undamped states with |theta0| < pi
    !> (fast(k) /= 0; cleared where |q| > 1e150), of the running path
    !> (undamped/pendula_undamped_parameter_lanes.F90).
    pure subroutine parameter_block_lanes(n, th, om, w, fast, hp, hp_lo, sh, ch, q, mc) &
      bind(C, name='pendula_parameter_block')
      import :: c_int, c_double
      integer(c_int), intent(in) :: n  !< states in the block
      real(c_double), intent(in) :: th(n)  !< initial angles [rad], finite
      real(c_double), intent(in) :: om(n)  !< initial angular velocities [rad/s], finite
      real(c_double), intent(in) :: w(n)  !< angular frequencies [1/s], > 0
      integer(c_int), intent(inout) :: fast(n)  !< 1: a state to set up; set to 0 where |q| > 1e150
      real(c_double), intent(in) :: hp  !< pi/2, high part
      real(c_double), intent(in) :: hp_lo  !< pi/2, low part
      real(c_double), intent(out) :: sh(n)  !< sin(theta0/2)
      real(c_double), intent(out) :: ch(n)  !< cos(theta0/2), high part
      real(c_double), intent(out) :: q(n)  !< Omega0/(2 w0)
      real(c_double), intent(out) :: mc(n)  !< 1 - m
    end subroutine parameter_block_lanes
  end interface

contains

  !> The kernel path this process runs (KERNEL_BASELINE, KERNEL_V3 or KERNEL_V4).
  integer function kernel_path()
    kernel_path = int(c_kernel_path())
  end function kernel_path

  !> True when this build has kernel path p and this CPU can run it.
  logical function kernel_path_available(p)
    integer, intent(in) :: p  !< KERNEL_BASELINE, KERNEL_V3 or KERNEL_V4
    kernel_path_available = c_kernel_available(int(p, c_int)) /= 0
  end function kernel_path_available

end module pendula_dispatch
