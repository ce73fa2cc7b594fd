!> The Taylor batch's series kernel (pendula_taylor_lanes): the Taylor
!> coefficients of TAYLOR_LANES states side by side, one vector lane each.
!>
!> A file of its own, compiled once per instruction set as the batch RK4
!> kernel is (see pendula_rk4_lanes.F90: meson builds it for baseline x86-64,
!> x86-64-v3 and x86-64-v4, each with its own module and entry name from the
!> preprocessor, and pendula_kernel_path.c picks one at load time from the
!> CPU or PENDULA_KERNEL).  It uses no pendula module, so each variant is a
!> leaf of the build.  Under -ffp-contract=off and without -ffast-math every
!> variant computes each lane's coefficients with the same operations in the
!> same order as taylor_coefficients (pendula_taylor_series): the bits of the
!> scalar call on every path (tests/python/test_taylor_lanes.py).
#ifndef PENDULA_TSERIES_MODULE
#define PENDULA_TSERIES_MODULE pendula_taylor_series_lanes_baseline_m
#define PENDULA_TSERIES_ENTRY pendula_taylor_series_lanes_baseline
#endif
module PENDULA_TSERIES_MODULE
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  implicit none
  private
  public :: PENDULA_TSERIES_ENTRY

  include 'pendula_taylor_lanes.inc'

contains

  !> taylor_coefficients for TAYLOR_LANES states at once, orders 1..pmax
  !> (pmax <= maxo - 1): the sums over c and over s, each as two partial sums
  !> of alternate terms with the newest term last, lane by lane as the scalar
  !> routine forms them.  In: cc(:, 0), ss(:, 0) (cos and sin of theta),
  !> xx(:, 0:1), vv(:, 0:1); out: cc, ss, xx, vv up to order pmax (+1 for xx, vv).
  subroutine PENDULA_TSERIES_ENTRY(pmax, maxo, w0sq, gam, cc, ss, xx, vv) bind(C)
    integer(c_int), intent(in) :: pmax  !< highest order to form
    integer(c_int), intent(in) :: maxo  !< last index of the coefficient arrays
    real(c_double), intent(in) :: w0sq(TAYLOR_LANES)  !< w0**2 of each lane [1/s**2]
    real(c_double), intent(in) :: gam(TAYLOR_LANES)  !< gamma of each lane [1/s]
    real(c_double), intent(inout) :: cc(TAYLOR_LANES, 0:maxo)  !< series of cos(theta)
    real(c_double), intent(inout) :: ss(TAYLOR_LANES, 0:maxo)  !< series of sin(theta)
    real(c_double), intent(inout) :: xx(TAYLOR_LANES, 0:maxo)  !< series of theta
    real(c_double), intent(inout) :: vv(TAYLOR_LANES, 0:maxo)  !< series of Omega
    real(c_double) :: ac1(TAYLOR_LANES), ac2(TAYLOR_LANES), as1(TAYLOR_LANES), as2(TAYLOR_LANES), rk, rk1
    integer :: k, j
    do k = 1, pmax
      ! 1/k as pendula_taylor_series's table holds it (1.0_wp/real(k, wp))
      rk = 1.0_c_double/real(k, c_double)
      rk1 = 1.0_c_double/real(k + 1, c_double)
      ac1 = 0
      ac2 = 0
      as1 = 0
      as2 = 0
      do j = 2, k - 1, 2
        ac1 = ac1 + vv(:, j - 1)*cc(:, k - j)
        as1 = as1 + vv(:, j - 1)*ss(:, k - j)
        ac2 = ac2 + vv(:, j)*cc(:, k - j - 1)
        as2 = as2 + vv(:, j)*ss(:, k - j - 1)
      end do
      if (mod(k, 2) == 0) then
        ac1 = ac1 + vv(:, k - 1)*cc(:, 0)
        as1 = as1 + vv(:, k - 1)*ss(:, 0)
      end if
      ac1 = ((ac1 + ac2) + vv(:, 0)*cc(:, k - 1))*rk
      as1 = ((as1 + as2) + vv(:, 0)*ss(:, k - 1))*rk
      ss(:, k) = ac1
      cc(:, k) = -as1
      xx(:, k + 1) = vv(:, k)*rk1
      vv(:, k + 1) = (-gam*vv(:, k) - w0sq*ac1)*rk1
    end do
  end subroutine PENDULA_TSERIES_ENTRY

end module PENDULA_TSERIES_MODULE
