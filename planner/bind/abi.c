/* The layout of the public structs (ea_abi.h): sizes and field offsets as this
 * compiler laid them out, for bindings without a compiler (python/). The lists
 * hold the structs and fields the Python package declares or reads
 * (python/elasticarm/_cdef.py); python/tests/test_abi.py checks each. */
#include "ea_abi.h"
#include "ea_arm_file.h"
#include "ea_planner.h"
#include "ea_refine.h"
#include "ea_simulate.h"
#include "ea_workspace.h"

#include <string.h>

#define EA__ABI_TYPES(X)                                                                           \
  X(ea_error_t)                                                                                    \
  X(ea_actuators_t)                                                                                \
  X(ea_arm_t)                                                                                      \
  X(ea_load_t)                                                                                     \
  X(ea_statics_problem_t)                                                                          \
  X(ea_statics_solution_t)                                                                         \
  X(ea_fe_settings_t)                                                                              \
  X(ea_fe_static_info_t)                                                                           \
  X(ea_fe_modes_info_t)                                                                            \
  X(ea_config_point_t)                                                                             \
  X(ea_workspace_settings_t)                                                                       \
  X(ea_workspace_extremum_t)                                                                       \
  X(ea_workspace_metrics_t)                                                                        \
  X(ea_freq_point_t)                                                                               \
  X(ea_task_point_t)                                                                               \
  X(ea_task_limits_t)                                                                              \
  X(ea_traj_t)                                                                                     \
  X(ea_sim_settings_t)                                                                             \
  X(ea_sim_info_t)                                                                                 \
  X(ea_sim_history_t)                                                                              \
  X(ea_plan_info_t)                                                                                \
  X(ea_plan_verify_t)                                                                              \
  X(ea_study_settings_t)                                                                           \
  X(ea_study_info_t)                                                                               \
  X(ea_task_t)                                                                                     \
  X(ea_study_t)                                                                                    \
  X(ea_refine_info_t)

#define EA__ABI_FIELDS(X)                                                                          \
  X(ea_error_t, status)                                                                            \
  X(ea_error_t, msg)                                                                               \
  X(ea_actuators_t, spool_radius)                                                                  \
  X(ea_actuators_t, spool_gear_ratio)                                                              \
  X(ea_actuators_t, spool_zero_length)                                                             \
  X(ea_actuators_t, cable_length_min)                                                              \
  X(ea_actuators_t, cable_length_max)                                                              \
  X(ea_actuators_t, cable_speed_max)                                                               \
  X(ea_actuators_t, cable_accel_max)                                                               \
  X(ea_actuators_t, tension_max)                                                                   \
  X(ea_actuators_t, tension_min)                                                                   \
  X(ea_actuators_t, shoulder_torque_max)                                                           \
  X(ea_actuators_t, shoulder_speed_max)                                                            \
  X(ea_actuators_t, shoulder_angle_min)                                                            \
  X(ea_actuators_t, shoulder_angle_max)                                                            \
  X(ea_actuators_t, shoulder_accel_max)                                                            \
  X(ea_actuators_t, base_speed_max)                                                                \
  X(ea_actuators_t, base_accel_max)                                                                \
  X(ea_actuators_t, base_angle_min)                                                                \
  X(ea_actuators_t, base_angle_max)                                                                \
  X(ea_arm_t, rho)                                                                                 \
  X(ea_arm_t, m_hand)                                                                              \
  X(ea_arm_t, length)                                                                              \
  X(ea_arm_t, EI)                                                                                  \
  X(ea_arm_t, x_c)                                                                                 \
  X(ea_arm_t, y_c)                                                                                 \
  X(ea_arm_t, g)                                                                                   \
  X(ea_arm_t, EA)                                                                                  \
  X(ea_arm_t, GA_s)                                                                                \
  X(ea_arm_t, EA_cable)                                                                            \
  X(ea_arm_t, I_zz)                                                                                \
  X(ea_arm_t, I_hand)                                                                              \
  X(ea_arm_t, act)                                                                                 \
  X(ea_arm_t, n_damping)                                                                           \
  X(ea_arm_t, damping_ratio)                                                                       \
  X(ea_load_t, tip_mass)                                                                           \
  X(ea_statics_problem_t, given)                                                                   \
  X(ea_statics_problem_t, value)                                                                   \
  X(ea_statics_solution_t, p)                                                                      \
  X(ea_statics_solution_t, tip)                                                                    \
  X(ea_statics_solution_t, cable_length)                                                           \
  X(ea_statics_solution_t, shoulder_torque)                                                        \
  X(ea_statics_solution_t, residual)                                                               \
  X(ea_statics_solution_t, iterations)                                                             \
  X(ea_statics_solution_t, cont_steps)                                                             \
  X(ea_statics_solution_t, branch)                                                                 \
  X(ea_statics_solution_t, winding)                                                                \
  X(ea_statics_solution_t, status)                                                                 \
  X(ea_fe_settings_t, elements)                                                                    \
  X(ea_fe_settings_t, modes)                                                                       \
  X(ea_fe_settings_t, newton_tol)                                                                  \
  X(ea_fe_settings_t, newton_max_iter)                                                             \
  X(ea_fe_settings_t, eig_backend)                                                                 \
  X(ea_fe_settings_t, static_hold_tip)                                                             \
  X(ea_fe_static_info_t, status)                                                                   \
  X(ea_fe_static_info_t, iterations)                                                               \
  X(ea_fe_static_info_t, residual)                                                                 \
  X(ea_fe_static_info_t, tip)                                                                      \
  X(ea_fe_static_info_t, tension)                                                                  \
  X(ea_fe_static_info_t, cable_length)                                                             \
  X(ea_fe_static_info_t, cable_angle)                                                              \
  X(ea_fe_static_info_t, theta0)                                                                   \
  X(ea_fe_static_info_t, tip_shift)                                                                \
  X(ea_fe_static_info_t, time_s)                                                                   \
  X(ea_fe_modes_info_t, status)                                                                    \
  X(ea_fe_modes_info_t, modes)                                                                     \
  X(ea_fe_modes_info_t, freq_hz)                                                                   \
  X(ea_fe_modes_info_t, lambda)                                                                    \
  X(ea_fe_modes_info_t, stable)                                                                    \
  X(ea_fe_modes_info_t, time_assembly_s)                                                           \
  X(ea_fe_modes_info_t, time_eigen_s)                                                              \
  X(ea_fe_modes_info_t, backend_info)                                                              \
  X(ea_fe_modes_info_t, iterations)                                                                \
  X(ea_fe_modes_info_t, fallback)                                                                  \
  X(ea_config_point_t, cable_length)                                                               \
  X(ea_config_point_t, alpha)                                                                      \
  X(ea_config_point_t, x)                                                                          \
  X(ea_config_point_t, y)                                                                          \
  X(ea_config_point_t, tension)                                                                    \
  X(ea_config_point_t, theta0)                                                                     \
  X(ea_config_point_t, kappa0)                                                                     \
  X(ea_config_point_t, shoulder_torque)                                                            \
  X(ea_config_point_t, residual)                                                                   \
  X(ea_config_point_t, iterations)                                                                 \
  X(ea_config_point_t, status)                                                                     \
  X(ea_config_point_t, stable)                                                                     \
  X(ea_config_point_t, admissible)                                                                 \
  X(ea_config_point_t, reason)                                                                     \
  X(ea_workspace_settings_t, alpha_min)                                                            \
  X(ea_workspace_settings_t, alpha_max)                                                            \
  X(ea_workspace_settings_t, inner_cable_length)                                                   \
  X(ea_workspace_settings_t, limits)                                                               \
  X(ea_workspace_settings_t, samples)                                                              \
  X(ea_workspace_settings_t, depth_samples)                                                        \
  X(ea_workspace_settings_t, tol)                                                                  \
  X(ea_workspace_extremum_t, value)                                                                \
  X(ea_workspace_extremum_t, alpha)                                                                \
  X(ea_workspace_extremum_t, cable_length)                                                         \
  X(ea_workspace_extremum_t, x)                                                                    \
  X(ea_workspace_extremum_t, y)                                                                    \
  X(ea_workspace_extremum_t, bound)                                                                \
  X(ea_workspace_extremum_t, bound2)                                                               \
  X(ea_workspace_extremum_t, at_end)                                                               \
  X(ea_workspace_metrics_t, area)                                                                  \
  X(ea_workspace_metrics_t, area_error)                                                            \
  X(ea_workspace_metrics_t, reach)                                                                 \
  X(ea_workspace_metrics_t, x_max)                                                                 \
  X(ea_workspace_metrics_t, y_min)                                                                 \
  X(ea_workspace_metrics_t, bounds)                                                                \
  X(ea_workspace_metrics_t, pieces)                                                                \
  X(ea_workspace_metrics_t, solves)                                                                \
  X(ea_freq_point_t, cable_length)                                                                 \
  X(ea_freq_point_t, alpha)                                                                        \
  X(ea_freq_point_t, ode)                                                                          \
  X(ea_freq_point_t, fe)                                                                           \
  X(ea_freq_point_t, modes)                                                                        \
  X(ea_freq_point_t, status)                                                                       \
  X(ea_freq_point_t, stage)                                                                        \
  X(ea_freq_point_t, err)                                                                          \
  X(ea_task_point_t, kind)                                                                         \
  X(ea_task_point_t, given)                                                                        \
  X(ea_task_point_t, cable_length)                                                                 \
  X(ea_task_point_t, cable_angle)                                                                  \
  X(ea_task_point_t, base_angle)                                                                   \
  X(ea_task_point_t, reach)                                                                        \
  X(ea_task_point_t, height)                                                                       \
  X(ea_task_point_t, p)                                                                            \
  X(ea_task_point_t, where)                                                                        \
  X(ea_task_limits_t, tension_min)                                                                 \
  X(ea_task_limits_t, tension_max)                                                                 \
  X(ea_task_limits_t, cable_length_min)                                                            \
  X(ea_task_limits_t, cable_length_max)                                                            \
  X(ea_task_limits_t, cable_speed_max)                                                             \
  X(ea_task_limits_t, cable_accel_max)                                                             \
  X(ea_task_limits_t, cable_angle_speed_max)                                                       \
  X(ea_task_limits_t, cable_angle_accel_max)                                                       \
  X(ea_task_limits_t, shoulder_torque_max)                                                         \
  X(ea_task_limits_t, shoulder_speed_max)                                                          \
  X(ea_task_limits_t, base_speed_max)                                                              \
  X(ea_task_limits_t, base_accel_max)                                                              \
  X(ea_task_limits_t, min_first_frequency_hz)                                                      \
  X(ea_task_limits_t, max_modal_deflection_m)                                                      \
  X(ea_task_limits_t, resample_margin)                                                             \
  X(ea_task_limits_t, continuous_acceleration)                                                     \
  X(ea_traj_t, n)                                                                                  \
  X(ea_traj_t, data)                                                                               \
  X(ea_traj_t, payload_kg)                                                                         \
  X(ea_traj_t, tip_mass_kg)                                                                        \
  X(ea_traj_t, arm_file)                                                                           \
  X(ea_traj_t, has_arm_hash)                                                                       \
  X(ea_traj_t, arm_hash)                                                                           \
  X(ea_traj_t, task)                                                                               \
  X(ea_traj_t, run_id)                                                                             \
  X(ea_traj_t, status)                                                                             \
  X(ea_sim_settings_t, elements)                                                                   \
  X(ea_sim_settings_t, scheme)                                                                     \
  X(ea_sim_settings_t, dt)                                                                         \
  X(ea_sim_settings_t, rho_inf)                                                                    \
  X(ea_sim_settings_t, settle)                                                                     \
  X(ea_sim_settings_t, cable_active)                                                               \
  X(ea_sim_settings_t, drive_fe)                                                                   \
  X(ea_sim_settings_t, damping_ratio)                                                              \
  X(ea_sim_settings_t, rayleigh_mass)                                                              \
  X(ea_sim_settings_t, rayleigh_stiffness)                                                         \
  X(ea_sim_settings_t, rest_tolerance)                                                             \
  X(ea_sim_settings_t, keep_history)                                                               \
  X(ea_sim_settings_t, max_wall_s)                                                                 \
  X(ea_sim_settings_t, progress)                                                                   \
  X(ea_sim_settings_t, progress_data)                                                              \
  X(ea_sim_info_t, status)                                                                         \
  X(ea_sim_info_t, tip_mass)                                                                       \
  X(ea_sim_info_t, damping_ratio)                                                                  \
  X(ea_sim_info_t, duration)                                                                       \
  X(ea_sim_info_t, simulated_time)                                                                 \
  X(ea_sim_info_t, steps)                                                                          \
  X(ea_sim_info_t, newton_iterations)                                                              \
  X(ea_sim_info_t, max_step_iterations)                                                            \
  X(ea_sim_info_t, start_newton_iterations)                                                        \
  X(ea_sim_info_t, start_tension)                                                                  \
  X(ea_sim_info_t, start_theta0_mismatch)                                                          \
  X(ea_sim_info_t, start_tension_mismatch)                                                         \
  X(ea_sim_info_t, start_freq_hz)                                                                  \
  X(ea_sim_info_t, modal_damping)                                                                  \
  X(ea_sim_info_t, n_modal_damping)                                                                \
  X(ea_sim_info_t, rayleigh_mass)                                                                  \
  X(ea_sim_info_t, rayleigh_stiffness)                                                             \
  X(ea_sim_info_t, residual_rms)                                                                   \
  X(ea_sim_info_t, residual_peak)                                                                  \
  X(ea_sim_info_t, time_to_rest)                                                                   \
  X(ea_sim_info_t, max_tracking_error)                                                             \
  X(ea_sim_info_t, max_tracking_error_time)                                                        \
  X(ea_sim_info_t, static_offset_start)                                                            \
  X(ea_sim_info_t, static_offset_end)                                                              \
  X(ea_sim_info_t, final_static_tip)                                                               \
  X(ea_sim_info_t, energy_start)                                                                   \
  X(ea_sim_info_t, energy_end)                                                                     \
  X(ea_sim_info_t, energy_drift_max)                                                               \
  X(ea_sim_info_t, kinetic_max)                                                                    \
  X(ea_sim_info_t, tension_min)                                                                    \
  X(ea_sim_info_t, tension_max)                                                                    \
  X(ea_sim_info_t, tension_min_time)                                                               \
  X(ea_sim_info_t, tension_max_time)                                                               \
  X(ea_sim_info_t, wall_time_s)                                                                    \
  X(ea_sim_history_t, rows)                                                                        \
  X(ea_sim_history_t, data)                                                                        \
  X(ea_sim_history_t, loads)                                                                       \
  X(ea_plan_info_t, status)                                                                        \
  X(ea_plan_info_t, ipopt_status)                                                                  \
  X(ea_plan_info_t, ipopt_status_name)                                                             \
  X(ea_plan_info_t, iterations)                                                                    \
  X(ea_plan_info_t, newton_steps)                                                                  \
  X(ea_plan_info_t, ipopt_rows)                                                                    \
  X(ea_plan_info_t, screen_resolves)                                                               \
  X(ea_plan_info_t, ipm_iterations)                                                                \
  X(ea_plan_info_t, ipm_fallback)                                                                  \
  X(ea_plan_info_t, threads)                                                                       \
  X(ea_plan_info_t, n_var)                                                                         \
  X(ea_plan_info_t, n_con)                                                                         \
  X(ea_plan_info_t, nnz_jac)                                                                       \
  X(ea_plan_info_t, objective)                                                                     \
  X(ea_plan_info_t, duration_s)                                                                    \
  X(ea_plan_info_t, min_tension_margin_N)                                                          \
  X(ea_plan_info_t, peak_shoulder_torque_Nm)                                                       \
  X(ea_plan_info_t, max_statics_residual)                                                          \
  X(ea_plan_info_t, max_violation)                                                                 \
  X(ea_plan_info_t, worst)                                                                         \
  X(ea_plan_info_t, n_active)                                                                      \
  X(ea_plan_info_t, active)                                                                        \
  X(ea_plan_info_t, active_knots)                                                                  \
  X(ea_plan_info_t, deriv_errors)                                                                  \
  X(ea_plan_info_t, evals_g)                                                                       \
  X(ea_plan_info_t, evals_jac)                                                                     \
  X(ea_plan_info_t, time_total_s)                                                                  \
  X(ea_plan_info_t, time_guess_s)                                                                  \
  X(ea_plan_info_t, time_statics_s)                                                                \
  X(ea_plan_info_t, time_ipopt_s)                                                                  \
  X(ea_plan_info_t, time_rest_s)                                                                   \
  X(ea_plan_info_t, between_passes)                                                                \
  X(ea_plan_info_t, time_freq_model_s)                                                             \
  X(ea_plan_info_t, min_first_frequency_hz)                                                        \
  X(ea_plan_info_t, max_modal_deflection_m)                                                        \
  X(ea_plan_info_t, time_dyn_model_s)                                                              \
  X(ea_plan_info_t, predicted_residual_m)                                                          \
  X(ea_plan_info_t, predicted_amplitude_m)                                                         \
  X(ea_plan_info_t, predicted_time_to_rest_s)                                                      \
  X(ea_plan_info_t, predicted_residual_worst_m)                                                    \
  X(ea_plan_info_t, max_modal_deviation_m)                                                         \
  X(ea_plan_info_t, min_dynamic_tension_margin_N)                                                  \
  X(ea_plan_info_t, message)                                                                       \
  X(ea_plan_verify_t, status)                                                                      \
  X(ea_plan_verify_t, message)                                                                     \
  X(ea_plan_verify_t, settings)                                                                    \
  X(ea_plan_verify_t, sim)                                                                         \
  X(ea_plan_verify_t, predicted_residual_m)                                                        \
  X(ea_plan_verify_t, predicted_time_to_rest_s)                                                    \
  X(ea_plan_verify_t, residual_bound_m)                                                            \
  X(ea_plan_verify_t, tension_bound_N)                                                             \
  X(ea_plan_verify_t, passed)                                                                      \
  X(ea_plan_verify_t, failure)                                                                     \
  X(ea_plan_verify_t, base_travel_rad)                                                             \
  X(ea_plan_verify_t, predicted_nonlinear_residual_m)                                              \
  X(ea_study_settings_t, threads)                                                                  \
  X(ea_study_settings_t, shard_k)                                                                  \
  X(ea_study_settings_t, shard_n)                                                                  \
  X(ea_study_settings_t, checkpoint)                                                               \
  X(ea_study_settings_t, fsync)                                                                    \
  X(ea_study_settings_t, fsync_interval_s)                                                         \
  X(ea_study_settings_t, stop_after)                                                               \
  X(ea_study_settings_t, stop_request)                                                             \
  X(ea_study_settings_t, min_time)                                                                 \
  X(ea_study_settings_t, min_time_data)                                                            \
  X(ea_study_settings_t, min_time_key)                                                             \
  X(ea_study_settings_t, progress)                                                                 \
  X(ea_study_settings_t, progress_data)                                                            \
  X(ea_study_settings_t, at_rest)                                                                  \
  X(ea_study_settings_t, at_rest_data)                                                             \
  X(ea_study_settings_t, at_rest_key)                                                              \
  X(ea_study_settings_t, workers)                                                                  \
  X(ea_study_info_t, status)                                                                       \
  X(ea_study_info_t, cases_total)                                                                  \
  X(ea_study_info_t, cases_shard)                                                                  \
  X(ea_study_info_t, cases_skipped)                                                                \
  X(ea_study_info_t, cases_computed)                                                               \
  X(ea_study_info_t, cases_failed)                                                                 \
  X(ea_study_info_t, rows_failed)                                                                  \
  X(ea_study_info_t, journal_dropped_bytes)                                                        \
  X(ea_study_info_t, threads)                                                                      \
  X(ea_study_info_t, processes)                                                                    \
  X(ea_study_info_t, workers_lost)                                                                 \
  X(ea_study_info_t, time_s)                                                                       \
  X(ea_task_t, name)                                                                               \
  X(ea_task_t, file)                                                                               \
  X(ea_task_t, arm_file)                                                                           \
  X(ea_task_t, arm)                                                                                \
  X(ea_task_t, payload_kg)                                                                         \
  X(ea_task_t, payload_factor)                                                                     \
  X(ea_task_t, start)                                                                              \
  X(ea_task_t, goal)                                                                               \
  X(ea_task_t, n_via)                                                                              \
  X(ea_task_t, path)                                                                               \
  X(ea_task_t, objective)                                                                          \
  X(ea_task_t, duration_s)                                                                         \
  X(ea_task_t, limits)                                                                             \
  X(ea_task_t, dynamics.modes)                                                                     \
  X(ea_task_t, dynamics.residual_m)                                                                \
  X(ea_task_t, dynamics.refine.enabled)                                                            \
  X(ea_task_t, dynamics.refine.tolerance_m)                                                        \
  X(ea_task_t, dynamics.refine.by)                                                                 \
  X(ea_task_t, dynamics.verify)                                                                    \
  X(ea_task_t, knots)                                                                              \
  X(ea_study_t, name)                                                                              \
  X(ea_study_t, n_cases)                                                                           \
  X(ea_refine_info_t, status)                                                                      \
  X(ea_refine_info_t, converged)                                                                   \
  X(ea_refine_info_t, stop_reason)                                                                 \
  X(ea_refine_info_t, n_evals)                                                                     \
  X(ea_refine_info_t, duration_before_s)                                                           \
  X(ea_refine_info_t, residual_peak_before_m)                                                      \
  X(ea_refine_info_t, duration_s)                                                                  \
  X(ea_refine_info_t, residual_peak_m)                                                             \
  X(ea_refine_info_t, residual_rms_m)                                                              \
  X(ea_refine_info_t, time_s)                                                                      \
  X(ea_refine_info_t, message)                                                                     \
  X(ea_refine_info_t, settings.tolerance_m)                                                        \
  X(ea_refine_info_t, model_evals)                                                                 \
  X(ea_refine_info_t, time_model_s)

typedef struct {
  const char *type;
  size_t size;
} ea__abi_type_t;

typedef struct {
  const char *type, *field;
  size_t offset;
} ea__abi_field_t;

#define EA__ABI_TYPE(t) {#t, sizeof(t)},
#define EA__ABI_FIELD(t, f) {#t, #f, offsetof(t, f)},
static const ea__abi_type_t ea__abi_types[] = {EA__ABI_TYPES(EA__ABI_TYPE)};
static const ea__abi_field_t ea__abi_fields[] = {EA__ABI_FIELDS(EA__ABI_FIELD)};

size_t ea_abi_sizeof(const char *type) {
  if (!type) return 0;
  for (size_t i = 0; i < sizeof ea__abi_types / sizeof *ea__abi_types; ++i)
    if (!strcmp(ea__abi_types[i].type, type)) return ea__abi_types[i].size;
  return 0;
}

size_t ea_abi_offsetof(const char *type, const char *field) {
  if (!type || !field) return (size_t)-1;
  for (size_t i = 0; i < sizeof ea__abi_fields / sizeof *ea__abi_fields; ++i)
    if (!strcmp(ea__abi_fields[i].type, type) && !strcmp(ea__abi_fields[i].field, field))
      return ea__abi_fields[i].offset;
  return (size_t)-1;
}
