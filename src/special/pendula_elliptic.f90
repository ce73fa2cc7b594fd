!> Complete and incomplete elliptic integrals of the first and second kind and
!> the Jacobi elliptic functions, for every real parameter m = k**2: the public
!> face of the elliptic concern, re-exporting its modules' public names.
!>
!> Conventions follow DLMF ch. 19 and 22 (and scipy.special): parameter m = k**2,
!> F(phi|m) = int_0^phi dt / sqrt(1 - m sin^2 t), K(m) = F(pi/2|m), E(m) likewise.
!> Every function has a complement form taking mc = 1 - m directly (suffix m1, as in
!> SciPy's ellipkm1), because near the separatrix (m -> 1) forming 1 - m loses every digit.
!>
!> Domain errors in the elemental functions give a quiet NaN (never stop/print):
!> K, E need m <= 1 (mc >= 0); F needs m sin^2(phi) <= 1; NaN in gives NaN out.
!>
!> Where each piece lives (own implementations from the papers):
!>  * pendula_elliptic_ke: K, E (piecewise polynomials, logarithmic form near m = 1,
!>    <= 2.4 ulps), K in double-double (AGM);
!>  * pendula_elliptic_f: F by Carlson's R_F, phi reduced modulo pi in double-double
!>    (<= 3.4 ulps);
!>  * pendula_jacobi (kernel pendula_jacobi_kernel, transformations
!>    pendula_elliptic_modulus): sn, cn, dn, am by series and duplication, within
!>    3.1 eps times the condition number; plans for one m and many u;
!>  * pendula_elliptic_tables: generated coefficients (tools/gen/gen_elliptic_tables.py; it
!>    also writes pendula_jacobi_series.inc, the series coefficients the kernel includes).
module pendula_elliptic
  use pendula_elliptic_ke, only: ellipk, ellipkm1, ellipe, ellipem1, ellipk_array, ellipe_array, ellipkm1_array, &
                                 ellipem1_array
  use pendula_elliptic_f, only: ellipf, ellipfm1, ellipf_array, ellipfm1_array
  use pendula_jacobi, only: ellipj, ellipjm1, ellipj_array, ellipjm1_array, &
                            ellipj_plan_t, ellipj_plan, ellipj_planm1, ellipj_eval, ellipj_eval_array, &
                            ellipj_plan_pays, ellipjm1_plan_pays, ellipj_one_m_array, ellipjm1_one_m_array
  implicit none
  private

  public :: ellipk, ellipkm1, ellipe, ellipem1, ellipf, ellipfm1, ellipk_array, ellipe_array, ellipkm1_array, ellipem1_array
  public :: ellipf_array, ellipfm1_array
  public :: ellipj, ellipjm1, ellipj_array, ellipjm1_array
  public :: ellipj_plan_t, ellipj_plan, ellipj_planm1, ellipj_eval, ellipj_eval_array
  public :: ellipj_plan_pays, ellipjm1_plan_pays, ellipj_one_m_array, ellipjm1_one_m_array
end module pendula_elliptic
