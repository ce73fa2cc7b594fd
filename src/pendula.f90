!> Umbrella module: `use pendula` gives the public Fortran API, and only that.
!>
!> Every name is listed explicitly, so the argument-checking and message helpers
!> the library uses internally (set_error, check_*, the number formatter, the
!> cancel-flag polling) stay out of user code; a program that needs one of them
!> uses its concern module directly.  Concern modules in architecture order.
module pendula
  use pendula_kinds, only: wp, i8
  use pendula_constants, only: pi
  use pendula_status, only: status_t, status_ok, code_name, PENDULA_MSG_LEN, &
                            PENDULA_OK, PENDULA_ERR_NONFINITE, PENDULA_ERR_DOMAIN, PENDULA_ERR_SIZE, PENDULA_ERR_ORDER, &
                            PENDULA_ERR_UNSTABLE, PENDULA_ERR_SOLVER, PENDULA_ERR_UNAVAILABLE, PENDULA_ERR_MAXSTEPS, &
                            PENDULA_ERR_CANCELLED, PENDULA_ERR_MEMORY
  use pendula_control, only: CONTROL_SIZE, CONTROL_CANCEL, CONTROL_PROGRESS
  use pendula_physics, only: natural_frequency, damping_rate, small_angle_period, period_series, &
                             PENDULA_G_DEFAULT, PENDULA_LENGTH_DEFAULT, PENDULA_PARAM_RTOL
  use pendula_elliptic, only: ellipk, ellipkm1, ellipe, ellipem1, ellipf, ellipfm1, ellipk_array, &
                              ellipe_array, ellipkm1_array, ellipem1_array, ellipj, ellipjm1, ellipj_array, ellipjm1_array, &
                              ellipj_plan_t, ellipj_plan, ellipj_planm1, ellipj_eval, ellipj_eval_array, &
                              ellipj_plan_pays, ellipjm1_plan_pays, ellipj_one_m_array, ellipjm1_one_m_array, &
                              ellipf_array, ellipfm1_array
  use pendula_undamped, only: undamped_motion_t, undamped_init, undamped_eval, undamped_eval_many, &
                              undamped_theta, undamped_omega, undamped_solve, undamped_period, undamped_amplitude, &
                              undamped_energy, undamped_regime, pendulum_energy, undamped_regime_name, &
                             undamped_states, undamped_properties, UNDAMPED_PLAN_MIN_TIMES, undamped_plan_pays, undamped_add_plan, &
                              REGIME_LIBRATION, REGIME_SEPARATRIX, REGIME_ROTATION
  use pendula_small_angle, only: small_angle, harmonic_state, small_angle_solve, small_angle_eval, &
                                 small_angle_bound, small_angle_phase_drift
  use pendula_equilibria, only: equilibrium_angle, equilibrium_type, equilibrium_eigenvalues, &
                                equilibrium, equilibrium_type_name, EQUILIBRIUM_CENTRE, EQUILIBRIUM_SADDLE
  use pendula_linear_damped, only: damping_regime_t, linear_damped_t, &
                                   DAMPING_UNDERDAMPED, DAMPING_CRITICAL, DAMPING_OVERDAMPED, damping_regime, regime_name, &
                                   linear_damped_init, linear_damped_state, linear_damped_theta, linear_damped_omega, &
                                   linear_damped_envelope, linear_damped_eval, linear_damped_arrays
  use pendula_integrators, only: ode_stats_t, linear_eigenvalues, &
                                 PENDULA_CVODE_ADAMS, PENDULA_CVODE_BDF, PENDULA_EVENT_TURNING, PENDULA_EVENT_ZERO, bottom_sign, &
                                 rk4_solve, rk4_final_state, rk4_max_stable_step, rk4_stability_function, &
                                 rk4_batch_solve, rk4_batch_openmp, RK4_BATCH_LANES, &
                                 cvode_solve, cvode_solve_events, cvode_available, cvode_batch_solve, &
                                 taylor_solve, taylor_solve_events, taylor_batch_solve, TAYLOR_DEFAULT_MAX_STEPS
  use pendula_scene, only: scene_t, scene_result_t, scene_cost_t, &
                           scene_init, scene_physics, scene_solve, scene_run_model, scene_estimate, &
                           scene_model_name, scene_model_code, scene_want_name, scene_want_code, &
                           SCENE_MODEL_AUTO, SCENE_MODEL_SMALL_ANGLE, SCENE_MODEL_EXACT, SCENE_MODEL_LINEAR, &
                           SCENE_MODEL_RK4, SCENE_MODEL_CVODE, SCENE_MODEL_TAYLOR, &
                           SCENE_WANT_STATE, SCENE_WANT_THETA, SCENE_WANT_FINAL, SCENE_WANT_ENERGY, &
                           SCENE_WANT_PERIOD, SCENE_WANT_EVENTS
  use pendula_scene_work, only: scene_solve_work, scene_run_work
  use pendula_sensitivity, only: sensitivity_solve, SENSITIVITY_NPARAMS
  use pendula_fit_period, only: period_fit_t, fit_period, period_factor
  use pendula_dispatch, only: kernel_path, kernel_path_available, KERNEL_BASELINE, KERNEL_V3, KERNEL_V4
  use pendula_drive, only: drive_t, DRIVE_TORQUE, DRIVE_PIVOT, drive_period, DRIVEN_MIN_STEPS, DRIVEN_MAX_STEPS, &
                           DRIVEN_DEFAULT_STEPS
  use pendula_driven, only: driven_solve, driven_batch_solve
  use pendula_driven_maps, only: driven_poincare, driven_bifurcation, driven_lyapunov, LYAPUNOV_BLOCKS, LYAPUNOV_ORBITS, &
                                 LYAPUNOV_DEFAULT_STEPS, LYAPUNOV_DEFAULT_PERIODS, &
                                 PARAM_AMPLITUDE, PARAM_FREQUENCY, PARAM_PHASE, PARAM_GAMMA, PARAM_W0
  use pendula_driven_orbits, only: driven_orbits, driven_basins, basin_table, BASIN_UNSETTLED, &
                                   BASIN_UNLISTED, ORBIT_NEWTON_TOL, ORBIT_MAX_PERIOD
  use pendula_driven_linear, only: driven_linear_response, driven_linear_solve
  implicit none
  ! Default public: the module re-exports exactly what the `only:` lists import.
  public
end module pendula
