!> The modulus transformations of the Jacobi functions and of F: any real m is mapped
!> to a core parameter in [0, 1] -- m > 1 by the reciprocal modulus (DLMF 22.6.11),
!> m < 0 by the imaginary modulus (DLMF 22.6.12) -- with the scale of u, the scale of
!> sn, the core K (double-double on request) and the Maclaurin coefficients at the core m.
module pendula_elliptic_modulus
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use pendula_kinds, only: wp
  use pendula_double_double, only: two_sum, dd_div, dd_sqrt
  use pendula_elliptic_ke, only: k_unit, k_from_mc, k_double_double
  implicit none
  private

  public :: jacobi_param_t, jacobi_param
  public :: MODULUS_INVALID, MODULUS_CORE, MODULUS_ONE, MODULUS_RECIPROCAL, MODULUS_IMAGINARY

  !> Which transformation a parameter takes (jacobi_param_t%kind).
  integer, parameter :: MODULUS_INVALID = -1     !< m or mc NaN, or 1 - m not finite
  integer, parameter :: MODULUS_CORE = 0         !< 0 <= m < 1: no transformation
  integer, parameter :: MODULUS_ONE = 1          !< m = 1: tanh, sech; K infinite
  integer, parameter :: MODULUS_RECIPROCAL = 2   !< m > 1: core parameter 1/m
  integer, parameter :: MODULUS_IMAGINARY = 3    !< m < 0: core parameter -m/(1 - m)

  !> Parameter-dependent constants of sn, cn, dn at one m (no table; cheap to build).
  type :: jacobi_param_t
    integer :: kind = MODULUS_INVALID   ! one of the MODULUS_* constants
    real(wp) :: m = 0, mc = 1   ! core parameter in [0,1] and its complement
    real(wp) :: mcl = 0         ! low part of mc (double-double), for K in extra precision
    real(wp) :: khi = 0, klo = 0! K of the core parameter, double-double
    real(wp) :: uscale = 1      ! u is multiplied by this before the core
    real(wp) :: uscale_lo = 0   ! ... in double-double, so large u keeps its digits
    real(wp) :: oscale = 1      ! sn scale (m>1: 1/k, m<0: 1/sqrt(1-m))
  end type jacobi_param_t

contains

  !> The transformation of (m, mc = 1 - m) to the core parameter; usemc: mc is the given
  !> (accurate) one, else m is; full: K of the core in double-double (else double).
  pure function jacobi_param(m, mc, usemc, full) result(plan)
    real(wp), intent(in) :: m  !< parameter m (any real)
    real(wp), intent(in) :: mc  !< complementary parameter mc = 1 - m
    logical, intent(in) :: usemc  !< true: mc is the accurate one, else m
    logical, intent(in) :: full  !< true: K of the core parameter in double-double
    type(jacobi_param_t) :: plan
    real(wp) :: mm, wh, wl, ah, al, qh, ql
    ! NaN or infinite m (either form): no modulus (tested before 1 - m is formed, which
    ! for m = +-Inf would be an invalid operation in the checked build)
    if (.not. (ieee_is_finite(m) .and. ieee_is_finite(mc))) then
      plan%kind = MODULUS_INVALID
      return
    end if
    if ((usemc .and. mc == 0) .or. (.not. usemc .and. m == 1)) then
      plan%kind = MODULUS_ONE
      plan%m = 1; plan%mc = 0
      return
    end if
    ! w = 1 - m exactly, as a double-double
    if (usemc) then
      wh = mc; wl = 0
    else
      call two_sum(1.0_wp, -m, wh, wl)
    end if
    if (.not. ieee_is_finite(wh)) then
      plan%kind = MODULUS_INVALID
      return
    end if
    if (wh > 0 .and. wh <= 1) then
      plan%kind = MODULUS_CORE
      mm = m
      plan%mc = wh; plan%mcl = wl
      plan%uscale = 1; plan%uscale_lo = 0
    else if (wh < 0) then
      ! reciprocal modulus (DLMF 22.6.11): core parameter 1/m, u scaled by k = sqrt(m)
      plan%kind = MODULUS_RECIPROCAL
      call two_sum(1.0_wp, -wh, ah, al)         ! m = 1 - w
      al = al - wl
      mm = 1/ah
      call dd_div(-wh, -wl, ah, al, qh, ql)     ! core mc = (m - 1)/m
      plan%mc = qh; plan%mcl = ql
      call dd_sqrt(ah, al, qh, ql)
      plan%uscale = qh; plan%uscale_lo = ql
      plan%oscale = 1/qh
    else
      ! imaginary modulus (DLMF 22.6.12): core mu = -m/(1-m), mc = 1/(1-m), u scaled by sqrt(1-m)
      plan%kind = MODULUS_IMAGINARY
      mm = -m/wh
      if (usemc) mm = (mc - 1)/mc
      call dd_div(1.0_wp, 0.0_wp, wh, wl, qh, ql)
      plan%mc = qh; plan%mcl = ql
      call dd_sqrt(wh, wl, qh, ql)
      plan%uscale = qh; plan%uscale_lo = ql
      plan%oscale = 1/qh
    end if
    plan%m = mm
    if (full) then
      call k_double_double(plan%mc, plan%mcl, plan%khi, plan%klo)
    else if (plan%kind == MODULUS_CORE) then
      plan%khi = k_unit(mm, plan%mc); plan%klo = 0
    else
      plan%khi = k_from_mc(plan%mc); plan%klo = 0
    end if
  end function jacobi_param

end module pendula_elliptic_modulus
