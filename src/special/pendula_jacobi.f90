!> The Jacobi elliptic functions sn, cn, dn and the amplitude am for all real u and m
!> (m = k**2; m < 0 and m > 1 by the modulus transformations), their complement forms
!> of mc = 1 - m, and plans: one m, many u.  A plan does the m-dependent work once and
!> tabulates Taylor polynomials of degree 8 of sn, cn, dn, am about a 1/32 grid of
!> [0, K] (DLMF 22.13): a table look-up and four short polynomials per point, no
!> division.  ellipj_plan_pays decides when building the table is worth it.
!>
!> Measured against mpmath at the exact double inputs (tests/python/test_elliptic.py):
!> within 3.1 eps times the condition number in every region (m < 0 to -1e10, 1 - m
!> down to 5e-324, m > 1, |u| to 1e6).
module pendula_jacobi
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use pendula_kinds, only: wp
  use pendula_constants, only: quiet_nan
  use pendula_status, only: status_t, set_error, PENDULA_ERR_SIZE
  use pendula_elliptic_ke, only: ellipk, ellipkm1
  use pendula_elliptic_modulus, only: jacobi_param_t, jacobi_param, MODULUS_CORE, MODULUS_RECIPROCAL, &
                                      MODULUS_IMAGINARY
  use pendula_jacobi_kernel, only: eval_at_param, eval_table_array, ellipj_points, ellipj_point, &
                                   taylor_row_at, ntay, tab_step, tab_inv_step, khi_tab_max
  implicit none
  private

  public :: ellipj, ellipjm1, ellipj_array, ellipjm1_array
  public :: ellipj_plan_t, ellipj_plan, ellipj_planm1, ellipj_eval, ellipj_eval_array
  public :: ellipj_plan_pays, ellipjm1_plan_pays, ellipj_one_m_array, ellipjm1_one_m_array

  !> m-dependent work for many evaluations of sn, cn, dn at one parameter: the
  !> modulus transformation, K in double-double and a table of Taylor polynomials.
  type :: ellipj_plan_t
    private
    type(jacobi_param_t) :: par
    integer :: ntab = -1
    !> Taylor coefficients of sn, cn, dn, am about t_j = j*tab_step, j = 0..ntab (core argument)
    real(wp), allocatable :: tab(:, :, :)
  end type ellipj_plan_t

contains

  !> Plan for sn, cn, dn at one parameter m (all real m; NaN m gives NaN results).
  !> Does the m-dependent work once: the transformation to a core parameter in [0,1],
  !> K in double-double for the period reduction, the series coefficients.
  pure function ellipj_plan(m) result(plan)
    real(wp), intent(in) :: m  !< parameter m = k**2 (any real)
    type(ellipj_plan_t) :: plan
    plan = build_plan(m, 1 - m, .false.)
  end function ellipj_plan

  !> Plan from the complementary parameter mc = 1 - m (mc >= 0, accurate near m = 1).
  pure function ellipj_planm1(mc) result(plan)
    real(wp), intent(in) :: mc  !< complementary parameter mc = 1 - m, >= 0
    type(ellipj_plan_t) :: plan
    plan = build_plan(1 - mc, mc, .true.)
  end function ellipj_planm1

  pure function build_plan(m, mc, usemc) result(plan)
    real(wp), intent(in) :: m, mc
    logical, intent(in) :: usemc
    type(ellipj_plan_t) :: plan
    integer :: j, ist
    plan%par = jacobi_param(m, mc, usemc, .true.)
    ! K of a core parameter in [0, 1) lies in [pi/2, 374] (374 at the smallest subnormal
    ! mc); anything else (never seen, but NaN would size the table from garbage) gets
    ! no table and the direct evaluation
    if ((plan%par%kind == MODULUS_CORE .or. plan%par%kind >= 2) .and. &
        plan%par%khi >= 1 .and. plan%par%khi <= khi_tab_max) then
      plan%ntab = ceiling(plan%par%khi*tab_inv_step) + 1
      ! a table the memory cannot hold (at most a few hundred kB) is no
      ! error: the plan then evaluates directly, to the same accuracy
      allocate (plan%tab(0:ntay, 4, 0:plan%ntab), stat=ist)
      if (ist /= 0) then
        plan%ntab = -1
        return
      end if
      do j = 0, plan%ntab
        call taylor_row_at(plan%par, j*tab_step, plan%tab(:, :, j))
      end do
    end if
  end function build_plan

  !> Evaluate sn, cn, dn (and optionally am, rad) at u with a plan (see ellipj).
  !> With a tabulated plan (the default) a point costs one table look-up and four
  !> short polynomials, no division and no transcendental call.
  elemental subroutine ellipj_eval(plan, u, sn, cn, dn, am)
    type(ellipj_plan_t), intent(in) :: plan  !< Jacobi plan from ellipj_plan or ellipj_planm1
    real(wp), intent(in) :: u  !< argument u (real, any value)
    real(wp), intent(out) :: sn  !< sn(u|m)
    real(wp), intent(out) :: cn  !< cn(u|m)
    real(wp), intent(out) :: dn  !< dn(u|m)
    real(wp), intent(out), optional :: am  !< optional amplitude am(u|m) [rad]
    real(wp) :: a
    if (allocated(plan%tab)) then
      call eval_at_param(plan%par, u, .true., present(am), sn, cn, dn, a, plan%tab, plan%ntab)
    else
      call eval_at_param(plan%par, u, .true., present(am), sn, cn, dn, a)
    end if
    if (present(am)) am = a
  end subroutine ellipj_eval

  !> ellipj_eval over rank-1 arrays (sn, cn, dn and the optional am of the size of u):
  !> the same numbers as the elemental form, with the table look-up inlined in one loop.
  !> A size mismatch sets status (PENDULA_ERR_SIZE) and the outputs to NaN.
  pure subroutine ellipj_eval_array(plan, u, sn, cn, dn, status, am)
    type(ellipj_plan_t), intent(in) :: plan  !< Jacobi plan from ellipj_plan or ellipj_planm1
    real(wp), intent(in) :: u(:)  !< arguments u (any real values)
    real(wp), intent(out) :: sn(:)  !< sn(u|m), size(u) elements
    real(wp), intent(out) :: cn(:)  !< cn(u|m), size(u) elements
    real(wp), intent(out) :: dn(:)  !< dn(u|m), size(u) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    real(wp), intent(out), optional :: am(:)  !< optional am(u|m) [rad], size(u) elements
    real(wp) :: a
    integer :: i
    logical :: bad
    call outputs_mismatch('ellipj_eval_array', size(u), sn, cn, dn, status, bad, am)
    if (bad) return
    if (allocated(plan%tab)) then
      if (present(am)) then
        call eval_table_array(plan%par, plan%tab, plan%ntab, size(u), u, .true., sn, cn, dn, am)
      else
        call eval_table_array(plan%par, plan%tab, plan%ntab, size(u), u, .false., sn, cn, dn, sn)
      end if
    else
      do i = 1, size(u)
        call eval_at_param(plan%par, u(i), .true., present(am), sn(i), cn(i), dn(i), a)
        if (present(am)) am(i) = a
      end do
    end if
  end subroutine ellipj_eval_array

  !> True (with status set and every output NaN) when sn, cn, dn or am (if present), or
  !> then the parameter array (if given), does not have n elements: the array routines
  !> check before writing anything.
  pure subroutine outputs_mismatch(name, n, sn, cn, dn, status, bad, am, param, nparam)
    character(len=*), intent(in) :: name
    integer, intent(in) :: n
    real(wp), intent(inout) :: sn(:), cn(:), dn(:)
    type(status_t), intent(inout) :: status
    logical, intent(out) :: bad
    real(wp), intent(inout), optional :: am(:)
    character(len=*), intent(in), optional :: param   ! a parameter array that must have n elements
    integer, intent(in), optional :: nparam           ! ... and its size
    bad = size(sn) /= n .or. size(cn) /= n .or. size(dn) /= n
    if (present(am)) bad = bad .or. size(am) /= n
    if (bad) then
      call set_error(status, PENDULA_ERR_SIZE, name//': sn, cn, dn and am must have the size of u')
    else if (present(param) .and. present(nparam)) then
      bad = nparam /= n
      if (bad) call set_error(status, PENDULA_ERR_SIZE, name//': '//param//' must have the size of u')
    end if
    if (.not. bad) return
    sn = quiet_nan(); cn = quiet_nan(); dn = quiet_nan()
    if (present(am)) am = quiet_nan()
  end subroutine outputs_mismatch

  !> Jacobi elliptic functions sn(u|m), cn(u|m), dn(u|m) and the amplitude am(u|m)
  !> (rad, optional) for all real u and all real m (m = k**2; m < 0 and m > 1 by the
  !> modulus transformations; for m > 1 am = asin-branch atan2(sn, cn)).  NaN in gives
  !> NaN out.  Accuracy: a few eps times the condition number; u is reduced
  !> modulo 2K with K in double-double, so large |u| does not lose u*eps.
  elemental subroutine ellipj(u, m, sn, cn, dn, am)
    real(wp), intent(in) :: u  !< argument u (real, any value)
    real(wp), intent(in) :: m  !< parameter m = k**2 (any real)
    real(wp), intent(out) :: sn  !< sn(u|m)
    real(wp), intent(out) :: cn  !< cn(u|m)
    real(wp), intent(out) :: dn  !< dn(u|m)
    real(wp), intent(out), optional :: am  !< optional amplitude am(u|m) [rad]
    real(wp) :: a
    call ellipj_point(u, m, .false., present(am), sn, cn, dn, a)
    if (present(am)) am = a
  end subroutine ellipj

  !> ellipj over rank-1 arrays u, m (and outputs) of one size: the same numbers as the
  !> elemental form, in one loop inside this module.  A size mismatch sets status
  !> (PENDULA_ERR_SIZE) and the outputs to NaN.
  pure subroutine ellipj_array(u, m, sn, cn, dn, status, am)
    real(wp), intent(in) :: u(:)  !< arguments u (any real values)
    real(wp), intent(in) :: m(:)  !< parameters m, size(u) elements
    real(wp), intent(out) :: sn(:)  !< sn(u|m), size(u) elements
    real(wp), intent(out) :: cn(:)  !< cn(u|m), size(u) elements
    real(wp), intent(out) :: dn(:)  !< dn(u|m), size(u) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    real(wp), intent(out), optional :: am(:)  !< optional am(u|m) [rad], size(u) elements
    call array_points('ellipj_array', 'm', u, m, .false., sn, cn, dn, status, am)
  end subroutine ellipj_array

  !> ellipjm1 over rank-1 arrays (same numbers as the elemental form); sizes as ellipj_array.
  pure subroutine ellipjm1_array(u, mc, sn, cn, dn, status, am)
    real(wp), intent(in) :: u(:)  !< arguments u (any real values)
    real(wp), intent(in) :: mc(:)  !< complementary parameters mc = 1 - m, size(u) elements
    real(wp), intent(out) :: sn(:)  !< sn(u|m), size(u) elements
    real(wp), intent(out) :: cn(:)  !< cn(u|m), size(u) elements
    real(wp), intent(out) :: dn(:)  !< dn(u|m), size(u) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    real(wp), intent(out), optional :: am(:)  !< optional am(u|m) [rad], size(u) elements
    call array_points('ellipjm1_array', 'mc', u, mc, .true., sn, cn, dn, status, am)
  end subroutine ellipjm1_array

  ! The body of ellipj_array (m1 false: x is m) and ellipjm1_array (x is mc, named
  ! xname): the size checks, then ellipj_points.
  pure subroutine array_points(name, xname, u, x, m1, sn, cn, dn, status, am)
    character(len=*), intent(in) :: name, xname
    real(wp), intent(in) :: u(:), x(:)
    logical, intent(in) :: m1
    real(wp), intent(out) :: sn(:), cn(:), dn(:)
    type(status_t), intent(out) :: status
    real(wp), intent(out), optional :: am(:)
    logical :: bad
    call outputs_mismatch(name, size(u), sn, cn, dn, status, bad, am, xname, size(x))
    if (bad) return
    if (present(am)) then
      call ellipj_points(size(u), u, x, m1, .true., sn, cn, dn, am)
    else
      call ellipj_points(size(u), u, x, m1, .false., sn, cn, dn, sn)
    end if
  end subroutine array_points

  !> Jacobi functions with the complementary parameter mc = 1 - m (any real mc;
  !> accurate near m = 1 including the smallest subnormal mc; mc = 0 gives tanh/sech).
  elemental subroutine ellipjm1(u, mc, sn, cn, dn, am)
    real(wp), intent(in) :: u  !< argument u (real, any value)
    real(wp), intent(in) :: mc  !< complementary parameter mc = 1 - m (any real)
    real(wp), intent(out) :: sn  !< sn(u|m)
    real(wp), intent(out) :: cn  !< cn(u|m)
    real(wp), intent(out) :: dn  !< dn(u|m)
    real(wp), intent(out), optional :: am  !< optional amplitude am(u|m) [rad]
    real(wp) :: a
    call ellipj_point(u, mc, .true., present(am), sn, cn, dn, a)
    if (present(am)) am = a
  end subroutine ellipjm1

  !> Whether a plan pays off for n points at one parameter m: its table costs ~32 K(core)
  !> kernel evaluations (~1 us each), worth it when each serves >= 16 points (n >= 512 K
  !> of the core parameter), and never below 32 points.  NaN, infinite m and m = 1 take
  !> a plan without a table (K = 0 here).
  pure logical function ellipj_plan_pays(m, n) result(pays)
    real(wp), intent(in) :: m  !< parameter m = k**2 (any real)
    integer, intent(in) :: n  !< number of points to evaluate
    real(wp) :: core_mc
    ! the core complement: 1 - m on [0, 1), (m - 1)/m for m > 1 (reciprocal modulus),
    ! 1/(1 - m) for m < 0 (imaginary modulus); 0 (no table) for NaN, +-Inf and m = 1
    core_mc = 0
    if (ieee_is_finite(m) .and. m /= 1) then
      if (m >= 0 .and. m < 1) then
        core_mc = 1 - m
      else if (m > 1) then
        core_mc = (m - 1)/m
      else
        core_mc = 1/(1 - m)
      end if
    end if
    pays = core_pays(core_mc, n)
  end function ellipj_plan_pays

  !> ellipj_plan_pays for the complementary parameter mc = 1 - m.
  pure logical function ellipjm1_plan_pays(mc, n) result(pays)
    real(wp), intent(in) :: mc  !< complementary parameter mc = 1 - m (any real)
    integer, intent(in) :: n  !< number of points to evaluate
    real(wp) :: core_mc
    core_mc = 0
    if (ieee_is_finite(mc) .and. mc /= 0) then
      if (mc > 0 .and. mc <= 1) then
        core_mc = mc
      else if (mc > 1) then
        core_mc = 1/mc                ! m < 0: core complement 1/(1 - m)
      else
        core_mc = -mc/(1 - mc)        ! m > 1: core complement (m - 1)/m
      end if
    end if
    pays = core_pays(core_mc, n)
  end function ellipjm1_plan_pays

  ! The rule of ellipj_plan_pays given the core complement (0: no table, K taken as 0).
  pure logical function core_pays(core_mc, n) result(pays)
    real(wp), intent(in) :: core_mc
    integer, intent(in) :: n
    real(wp) :: core_k
    core_k = 0
    if (core_mc > 0) core_k = ellipkm1(core_mc)
    pays = n >= 32 .and. real(n, wp) >= 512*core_k
  end function core_pays

  !> sn, cn, dn, am (optional) at the points u for one parameter m: with a plan where
  !> ellipj_plan_pays says so, else point by point; the same numbers as ellipj_eval_array
  !> with ellipj_plan(m), or as ellipj_array.  Sizes as ellipj_array.
  pure subroutine ellipj_one_m_array(u, m, sn, cn, dn, status, am)
    real(wp), intent(in) :: u(:)  !< arguments u (any real values)
    real(wp), intent(in) :: m  !< parameter m = k**2 (any real)
    real(wp), intent(out) :: sn(:)  !< sn(u|m), size(u) elements
    real(wp), intent(out) :: cn(:)  !< cn(u|m), size(u) elements
    real(wp), intent(out) :: dn(:)  !< dn(u|m), size(u) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    real(wp), intent(out), optional :: am(:)  !< optional am(u|m) [rad], size(u) elements
    if (ellipj_plan_pays(m, size(u))) then
      call ellipj_eval_array(ellipj_plan(m), u, sn, cn, dn, status, am)
    else
      call ellipj_array(u, spread(m, 1, size(u)), sn, cn, dn, status, am)
    end if
  end subroutine ellipj_one_m_array

  !> ellipj_one_m_array for the complementary parameter mc = 1 - m.
  pure subroutine ellipjm1_one_m_array(u, mc, sn, cn, dn, status, am)
    real(wp), intent(in) :: u(:)  !< arguments u (any real values)
    real(wp), intent(in) :: mc  !< complementary parameter mc = 1 - m (any real)
    real(wp), intent(out) :: sn(:)  !< sn(u|m), size(u) elements
    real(wp), intent(out) :: cn(:)  !< cn(u|m), size(u) elements
    real(wp), intent(out) :: dn(:)  !< dn(u|m), size(u) elements
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    real(wp), intent(out), optional :: am(:)  !< optional am(u|m) [rad], size(u) elements
    if (ellipjm1_plan_pays(mc, size(u))) then
      call ellipj_eval_array(ellipj_planm1(mc), u, sn, cn, dn, status, am)
    else
      call ellipjm1_array(u, spread(mc, 1, size(u)), sn, cn, dn, status, am)
    end if
  end subroutine ellipjm1_one_m_array

end module pendula_jacobi
