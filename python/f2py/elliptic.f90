! f2py-facing layer for the elliptic concern (pendula_elliptic).  Plain
! subroutines over explicit-shape arrays; domain errors come back as NaN
! (documented in pendula_elliptic) and the Python side turns them into
! ValueError.  No numerics here.  The array routines' size check (status) cannot
! fail here: every array is declared with the same n, so their status is not read.

subroutine ellip_ke_f2py(which, n, x, y)
  ! which = GLUE_ELLIPK: y = K(x = m); GLUE_ELLIPKM1: K(1 - x), x = p; GLUE_ELLIPE,
  ! GLUE_ELLIPEM1: the same for E.  y is the caller's (numpy.empty): see ellipj_into_f2py.
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipk_array, ellipkm1_array, ellipe_array, ellipem1_array
  use pendula_status, only: status_t
  implicit none
  include 'pendula_glue_codes.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: which, n
  real(c_double), intent(in) :: x(n)
  real(c_double), intent(inout) :: y(n)
  !f2py intent(inplace) :: y
  type(status_t) :: status
  select case (which)
  case (GLUE_ELLIPK)
    call ellipk_array(x, y, status)
  case (GLUE_ELLIPKM1)
    call ellipkm1_array(x, y, status)
  case (GLUE_ELLIPE)
    call ellipe_array(x, y, status)
  case default
    call ellipem1_array(x, y, status)
  end select
end subroutine ellip_ke_f2py

subroutine ellipf_f2py(which, n, phi, x, f)
  ! F(phi | x) for which = GLUE_PARAM_M, F(phi | 1 - x) for GLUE_PARAM_P; f is the
  ! caller's (numpy.empty).
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipf_array, ellipfm1_array
  use pendula_status, only: status_t
  implicit none
  include 'pendula_glue_codes.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: which, n
  real(c_double), intent(in) :: phi(n), x(n)
  real(c_double), intent(inout) :: f(n)
  !f2py intent(inplace) :: f
  type(status_t) :: status
  if (which == GLUE_PARAM_M) then
    call ellipf_array(phi, x, f, status)
  else
    call ellipfm1_array(phi, x, f, status)
  end if
end subroutine ellipf_f2py

! Jacobi functions written into arrays the caller allocated (numpy.empty): f2py fills
! the arrays it allocates for intent(out) with zeros first, a wasted pass over 4 n
! doubles.  which = GLUE_PARAM_M: x is m, GLUE_PARAM_P: x is p = 1 - m.
subroutine ellipj_into_f2py(which, n, u, x, sn, cn, dn, ph)
  ! One parameter per u.
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipj_array, ellipjm1_array
  use pendula_status, only: status_t
  implicit none
  include 'pendula_glue_codes.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: which, n
  real(c_double), intent(in) :: u(n), x(n)
  real(c_double), intent(inout) :: sn(n), cn(n), dn(n), ph(n)
  !f2py intent(inplace) :: sn, cn, dn, ph
  type(status_t) :: status
  if (which == GLUE_PARAM_M) then
    call ellipj_array(u, x, sn, cn, dn, status, ph)
  else
    call ellipjm1_array(u, x, sn, cn, dn, status, ph)
  end if
end subroutine ellipj_into_f2py

subroutine ellipj_one_into_f2py(which, how, n, u, x, sn, cn, dn, ph)
  ! One parameter for all u: how = GLUE_JACOBI_AUTO lets the library decide whether a
  ! plan pays off, GLUE_JACOBI_PLAN always uses one.
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipj_plan_t, ellipj_plan, ellipj_planm1, ellipj_eval_array, &
                              ellipj_one_m_array, ellipjm1_one_m_array
  use pendula_status, only: status_t
  implicit none
  include 'pendula_glue_codes.inc'
  !f2py threadsafe
  integer(c_int), intent(in) :: which, how, n
  real(c_double), intent(in) :: u(n), x
  real(c_double), intent(inout) :: sn(n), cn(n), dn(n), ph(n)
  !f2py intent(inplace) :: sn, cn, dn, ph
  type(ellipj_plan_t) :: plan
  type(status_t) :: status
  if (how == GLUE_JACOBI_PLAN) then
    if (which == GLUE_PARAM_M) then
      plan = ellipj_plan(x)
    else
      plan = ellipj_planm1(x)
    end if
    call ellipj_eval_array(plan, u, sn, cn, dn, status, ph)
  else if (which == GLUE_PARAM_M) then
    call ellipj_one_m_array(u, x, sn, cn, dn, status, ph)
  else
    call ellipjm1_one_m_array(u, x, sn, cn, dn, status, ph)
  end if
end subroutine ellipj_one_into_f2py
