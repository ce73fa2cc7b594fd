!> The integrators concern in one `use`: the nonlinear damped pendulum
!> (text eq. 2.2) by classic RK4 (pendula_rk4) and by SUNDIALS CVODE
!> (pendula_cvode, and for many states pendula_cvode_batch; a stub returning PENDULA_ERR_UNAVAILABLE when SUNDIALS was
!> not built), by an adaptive Taylor method to a tolerance (pendula_taylor,
!> pendula_taylor_batch), with the shared definitions of pendula_ode.
module pendula_integrators
  use pendula_ode, only: ode_stats_t, linear_eigenvalues, &
                         PENDULA_CVODE_ADAMS, PENDULA_CVODE_BDF, PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO, bottom_sign
  use pendula_rk4, only: rk4_solve, rk4_final_state, rk4_max_stable_step, rk4_stability_function
  use pendula_rk4_batch, only: rk4_batch_solve, rk4_batch_openmp, RK4_BATCH_LANES
  use pendula_cvode, only: cvode_solve, cvode_solve_events, cvode_available
  use pendula_cvode_batch, only: cvode_batch_solve
  use pendula_taylor, only: taylor_solve, taylor_solve_events, TAYLOR_DEFAULT_MAX_STEPS
  use pendula_taylor_batch, only: taylor_batch_solve
  implicit none
  private
  public :: ode_stats_t, linear_eigenvalues
  public :: PENDULA_CVODE_ADAMS, PENDULA_CVODE_BDF, PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO, bottom_sign
  public :: rk4_solve, rk4_final_state, rk4_max_stable_step, rk4_stability_function
  public :: rk4_batch_solve, rk4_batch_openmp, RK4_BATCH_LANES
  public :: cvode_solve, cvode_solve_events, cvode_available, cvode_batch_solve
  public :: taylor_solve, taylor_solve_events, taylor_batch_solve, TAYLOR_DEFAULT_MAX_STEPS
end module pendula_integrators
