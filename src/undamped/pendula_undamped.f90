!> The undamped pendulum theta'' + w0^2 sin(theta) = 0 (eq. 1.6) in closed form
!> for ANY initial state (theta0, Omega0): libration, separatrix and rotation.
!>
!> The text (§1.2-1.3, eqs 1.52, 1.66) solves only Omega0 = 0 and theta0 = 0
!> while the pendulum swings; here the energy decides the regime:
!>   m = k^2 = sin^2(theta0/2) + (Omega0/(2 w0))^2 = E / E_separatrix,
!>   m < 1 libration:  sin(theta/2) = k sn(w0 t + u0 | m), cos(theta/2) = dn(..),
!>                     Omega = 2 k w0 cn(w0 t + u0 | m), u0 = F(phi0 | m),
!>                     phi0 = atan2(sin(theta0/2), Omega0/(2 w0)); T = 4 K(m)/w0,
!>   m > 1 rotation:   theta = 2 s am(k w0 t + v0 | 1/m), Omega = 2 s k w0 dn(..),
!>                     s = sign(Omega0), v0 = F(s theta0/2 | 1/m); one turn takes
!>                     2 K(1/m)/(k w0); theta is unwrapped (keeps counting turns),
!>   m = 1 separatrix: theta = 2 s gd(w0 t + c), Omega = 2 s w0 sech(w0 t + c),
!>                     c = gd^-1(s theta0/2); T = +inf.
!> theta0 is first reduced to theta_r in [-pi, pi] about the nearest stable
!> equilibrium 2 pi N; results are continuous with theta0 (2 pi N is added back).
!> 1 - m is never formed by subtraction: it is cos^2(theta_r/2) - (Omega0/2w0)^2
!> factored as (c - q)(c + q) with q and, where c - |q| can cancel, c carried
!> to ~2 doubles, and it feeds the complement forms of pendula_elliptic, so
!> near-separatrix states keep their accuracy.  Energies are per unit m l^2
!> (units 1/s^2).
!>
!> Many states at once: `undamped_properties` (period, amplitude, m, 1 - m,
!> regime of each state) and `undamped_states` (each state at its own time)
!> compute per state only what is asked -- no F, no K unless needed, a Jacobi
!> plan only for a run of UNDAMPED_PLAN_MIN_TIMES equal states -- with the
!> same numbers as undamped_init + undamped_period/undamped_eval.
!>
!> This module is the facade: the one-state motion lives in
!> pendula_undamped_motion (set-up, properties) and pendula_undamped_eval
!> (evaluation at times), the many-state kernels in pendula_undamped_many.
module pendula_undamped
  use pendula_undamped_motion, only: undamped_motion_t, undamped_init, &
                                     undamped_period, undamped_amplitude, undamped_energy, &
                                    undamped_regime, pendulum_energy, undamped_regime_name, undamped_plan_pays, undamped_add_plan, &
                                     REGIME_LIBRATION, REGIME_SEPARATRIX, REGIME_ROTATION, UNDAMPED_PLAN_MIN_TIMES
  use pendula_undamped_eval, only: undamped_eval, undamped_eval_many, undamped_theta, undamped_omega
  use pendula_angle_dd, only: reduce_angle_2pi
  use pendula_undamped_many, only: undamped_solve, undamped_states, undamped_properties
  implicit none
  private

  public :: undamped_motion_t, undamped_init, undamped_eval, undamped_eval_many, undamped_theta, undamped_omega, &
            undamped_solve, undamped_period, undamped_amplitude, undamped_energy, &
            undamped_regime, pendulum_energy, undamped_regime_name, reduce_angle_2pi, &
            undamped_plan_pays, undamped_add_plan
  public :: undamped_states, undamped_properties
  public :: REGIME_LIBRATION, REGIME_SEPARATRIX, REGIME_ROTATION, UNDAMPED_PLAN_MIN_TIMES
end module pendula_undamped
