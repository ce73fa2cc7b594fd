! f2py-facing layer for the elliptic concern (pendula_elliptic).  Plain
! subroutines over explicit-shape arrays; domain errors come back as NaN
! (documented in pendula_elliptic) and the Python side turns them into
! ValueError.  No numerics here.  The array routines' size check (status) cannot
! fail here: every array is declared with the same n, so their status is not read.

subroutine ellipk_f2py(n, m, k)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipk_array
  use pendula_status, only: status_t
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: m(n)
  real(c_double), intent(out) :: k(n)
  type(status_t) :: status
  call ellipk_array(m, k, status)
end subroutine ellipk_f2py

subroutine ellipkm1_f2py(n, mc, k)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipkm1
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: mc(n)
  real(c_double), intent(out) :: k(n)
  k = ellipkm1(mc)
end subroutine ellipkm1_f2py

subroutine ellipe_f2py(n, m, e)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipe_array
  use pendula_status, only: status_t
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: m(n)
  real(c_double), intent(out) :: e(n)
  type(status_t) :: status
  call ellipe_array(m, e, status)
end subroutine ellipe_f2py

subroutine ellipem1_f2py(n, mc, e)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipem1
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: mc(n)
  real(c_double), intent(out) :: e(n)
  e = ellipem1(mc)
end subroutine ellipem1_f2py

subroutine ellipf_f2py(n, phi, m, f)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipf
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: phi(n), m(n)
  real(c_double), intent(out) :: f(n)
  f = ellipf(phi, m)
end subroutine ellipf_f2py

subroutine ellipfm1_f2py(n, phi, mc, f)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipfm1
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: phi(n), mc(n)
  real(c_double), intent(out) :: f(n)
  f = ellipfm1(phi, mc)
end subroutine ellipfm1_f2py

! Jacobi functions written into arrays the caller allocated (numpy.empty): f2py fills
! the arrays it allocates for intent(out) with zeros first, a wasted pass over 4 n
! doubles.  The *_one_m_* forms take one parameter for many u and let the library
! decide whether a plan pays off; the *_plan_* forms always use one (for the tests).
subroutine ellipj_into_f2py(n, u, m, sn, cn, dn, ph)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipj_array
  use pendula_status, only: status_t
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: u(n), m(n)
  real(c_double), intent(inout) :: sn(n), cn(n), dn(n), ph(n)
  !f2py intent(inplace) :: sn, cn, dn, ph
  type(status_t) :: status
  call ellipj_array(u, m, sn, cn, dn, status, ph)
end subroutine ellipj_into_f2py

subroutine ellipjm1_into_f2py(n, u, mc, sn, cn, dn, ph)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipjm1_array
  use pendula_status, only: status_t
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: u(n), mc(n)
  real(c_double), intent(inout) :: sn(n), cn(n), dn(n), ph(n)
  !f2py intent(inplace) :: sn, cn, dn, ph
  type(status_t) :: status
  call ellipjm1_array(u, mc, sn, cn, dn, status, ph)
end subroutine ellipjm1_into_f2py

subroutine ellipj_plan_into_f2py(n, u, m, sn, cn, dn, ph)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipj_plan_t, ellipj_plan, ellipj_eval_array
  use pendula_status, only: status_t
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: u(n), m
  real(c_double), intent(inout) :: sn(n), cn(n), dn(n), ph(n)
  !f2py intent(inplace) :: sn, cn, dn, ph
  type(ellipj_plan_t) :: plan
  type(status_t) :: status
  plan = ellipj_plan(m)
  call ellipj_eval_array(plan, u, sn, cn, dn, status, ph)
end subroutine ellipj_plan_into_f2py

subroutine ellipjm1_plan_into_f2py(n, u, mc, sn, cn, dn, ph)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipj_plan_t, ellipj_planm1, ellipj_eval_array
  use pendula_status, only: status_t
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: u(n), mc
  real(c_double), intent(inout) :: sn(n), cn(n), dn(n), ph(n)
  !f2py intent(inplace) :: sn, cn, dn, ph
  type(ellipj_plan_t) :: plan
  type(status_t) :: status
  plan = ellipj_planm1(mc)
  call ellipj_eval_array(plan, u, sn, cn, dn, status, ph)
end subroutine ellipjm1_plan_into_f2py

subroutine ellipj_one_m_into_f2py(n, u, m, sn, cn, dn, ph)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipj_one_m_array
  use pendula_status, only: status_t
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: u(n), m
  real(c_double), intent(inout) :: sn(n), cn(n), dn(n), ph(n)
  !f2py intent(inplace) :: sn, cn, dn, ph
  type(status_t) :: status
  call ellipj_one_m_array(u, m, sn, cn, dn, status, ph)
end subroutine ellipj_one_m_into_f2py

subroutine ellipjm1_one_m_into_f2py(n, u, mc, sn, cn, dn, ph)
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  use pendula_elliptic, only: ellipjm1_one_m_array
  use pendula_status, only: status_t
  implicit none
  !f2py threadsafe
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: u(n), mc
  real(c_double), intent(inout) :: sn(n), cn(n), dn(n), ph(n)
  !f2py intent(inplace) :: sn, cn, dn, ph
  type(status_t) :: status
  call ellipjm1_one_m_array(u, mc, sn, cn, dn, status, ph)
end subroutine ellipjm1_one_m_into_f2py
