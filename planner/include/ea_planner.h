/**
 * @file ea_planner.h
 * @brief The trajectory planner (docs/planner.md): a task (ea_task.h) transcribed
 *        into an NLP and solved by the planner's own interior point, an
 *        active-set Newton (replans) or Ipopt; replanning, the plan as a
 *        trajectory (ea_traj.h) and its JSON summary, and the planner metrics of
 *        batch studies (ea_study.h: min_time, at_rest) (planner/nlp/).
 */
#ifndef EA_PLANNER_H
#define EA_PLANNER_H

#include "ea_fe.h"
#include "ea_study.h"
#include "ea_task.h"
#include "ea_traj.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Trajectory planner (docs/planner.md): a direct transcription of a task
 *  (ea_task_t) solved by the planner's engines (the own interior point, an
 *  active-set Newton, Ipopt; docs/planner.md, "Engines"). Knots k = 0..N-1 at t_k = t_f s_k; per
 * knot the actuator coordinates q = (L_c, alpha[, base]) and their rates (cubic Hermite between
 * knots, as in the trajectory file), the statics unknowns (T, theta0, kappa0) tied to q by the
 * shooting residual (kappa(L), x_L - x_c - L_c cos alpha, y_L - y_c - L_c sin alpha) = 0 with the
 * exact sensitivities of ea_shoot() in the Jacobian, and theta0's rate (theta0 a C2 cubic spline).
 * Every limit holds between the knots too (docs/planner.md, "Limits between the knots"). */
typedef struct ea_planner ea_planner_t;

/** Where a solve starts from. */
typedef enum ea_plan_start {
  EA_PLAN_COLD = 0, /**< statics continuation along the straight interpolation */
  EA_PLAN_WARM,     /**< the planner's last converged solution, with multipliers
                         (after ea_planner_update: shifted along the change) */
  EA_PLAN_FROM_TRAJ /**< a previous plan (ea_traj_t) resampled onto the knots */
} ea_plan_start_t;

/** ea_plan_info_t::ipopt_status of a solve that another engine finished (the own interior
 *  point, the active-set Newton, or a start that passed the KKT test): Ipopt did not run. */
#define EA_PLAN_NO_IPOPT (-1000)

/** Most distinct active-limit names an info reports. */
#define EA_PLAN_MAX_ACTIVE 16

/** Result of a solve. */
typedef struct ea_plan_info {
  ea_status_t status;         /**< EA_OK, EA_ERR_INFEASIBLE, EA_ERR_NOCONV, EA_ERR_MAXITER, ... */
  int ipopt_status;           /**< Ipopt's raw ApplicationReturnStatus when Ipopt gave the result
                                   (ea_plan_engine_name "ipopt"); EA_PLAN_NO_IPOPT when another
                                   engine did; 0 when the solve stopped before any engine. The
                                   engine and its outcome in neutral words: ea_plan_engine_name,
                                   ea_plan_engine_status */
  char ipopt_status_name[48]; /**< its name ("" when Ipopt did not run) */
  int iterations;             /**< iterations of the engines of the call (the own interior point's
                                   plan, or Ipopt's summed over its attempts and re-solves) */
  int newton_steps;           /**< active-set Newton steps of warm starts (the path transcription's
                                   replans, docs/planner.md): with 0 iterations its point was the plan,
                                   else it gave up and Ipopt solved; 0: not tried */
  int ipopt_rows;            /**< rows Ipopt's last solve had (the path transcription leaves out the
                                  inequality rows far inside their limits, docs/planner.md); 0: no
                                  Ipopt solve */
  int screen_resolves;       /**< Ipopt solves repeated because a left-out row reached its limit */
  int ipm_iterations;        /**< iterations of the planner's own interior point (solver.nlp auto,
                                  the path transcription's cold solves; docs/planner.md): the plan's
                                  when ipm_fallback is 0; 0: not tried */
  int ipm_fallback;          /**< 1: it ran and gave no plan that passed the KKT test (Ipopt then
                                  solved from the same start) */
  int threads;               /**< threads the plan's evaluations ran on: 2 with the path
                                  transcription's worker (solver.threads), else 1 */
  int n_var, n_con, nnz_jac; /**< problem size */
  double objective;          /**< final objective value */
  double duration_s;         /**< [s] t_f */
  double min_tension_margin_N;    /**< [N] min_k T_k - tension_min */
  double peak_shoulder_torque_Nm; /**< [N m] max_k |EI kappa0_k| */
  double max_statics_residual;    /**< max-norm of the statics residual at the knots */
  double max_violation;           /**< largest bound or constraint violation at the final point */
  char worst[160];                /**< what it was: constraint name, knot, by how much */
  int n_active;                   /**< limits active (within 1e-6 relative) at some knot */
  char active[EA_PLAN_MAX_ACTIVE][40];
  int active_knots[EA_PLAN_MAX_ACTIVE]; /**< at how many knots / intervals */
  int deriv_errors;              /**< errors found by Ipopt's derivative checker (-1 = not run) */
  int evals_g, evals_jac;        /**< callback counts */
  double time_total_s;           /**< [s] wall time of ea_planner_solve */
  double time_guess_s;           /**< [s] initial guess (statics continuation) */
  double time_statics_s;         /**< [s] shooting with sensitivities inside Ipopt's callbacks */
  double time_ipopt_s;           /**< [s] the engine itself (ea_plan_engine_name: Ipopt or the own
                                      interior point; linear algebra, line search), callbacks excluded
                                      (the summary's phase_times_s.solve) */
  double time_rest_s;            /**< [s] other callback work and post-processing */
  int between_passes;            /**< re-solves with knot bounds tightened because a limit was
                                      exceeded between the knots (docs/planner.md) */
  double time_freq_model_s;      /**< [s] building the FE frequency model (ea_planner_alloc;
                                      0 when the task needs none) */
  double min_first_frequency_hz; /**< [Hz] min over the knots of the model's f1 (NAN: no model) */
  double max_modal_deflection_m; /**< [m] max over the interval ends of |s_c acc_c| / omega1^2,
                                      s = (1, L_c) (NAN: no model) */
  /* dynamics (task key dynamics; NAN without) */
  double time_dyn_model_s;     /**< [s] reduced-model table: built or loaded */
  double predicted_residual_m; /**< [m] the model's residual tip amplitude after the
                                    motion: sum_i of the modes' amplitudes */
  double predicted_amplitude_m[EA_ROM_MAX_MODES]; /**< [m] per mode (nominal model) */
  double predicted_time_to_rest_s;     /**< [s] after the motion until the model's residual bound
                                            (sum of the modes' damped envelopes) stays within 1 mm,
                                            with the arm file's modal damping ratios (INFINITY:
                                            undamped and above 1 mm; 0: within from the start) */
  double predicted_residual_worst_m;   /**< [m] the largest over the models (robust) */
  double max_modal_deviation_m;        /**< [m] max over the knots of the modal tip
                                            deviation from the quasi-static tip */
  double min_dynamic_tension_margin_N; /**< [N] min over the knots of T + modal part - min */
  char message[512];                   /**< human-readable outcome */
} ea_plan_info_t;

/** The reduced dynamic model of a planner (task key dynamics). */
typedef struct ea_plan_dyn_info {
  int built;                 /**< 1 if the task has dynamics */
  int models;                /**< 1, or 5 with dynamics.robust (nominal + four corners) */
  double model_tip_mass[5];  /**< [kg] each model's tip mass */
  double model_EI[5];        /**< [N m^2] each model's EI */
  ea_rom_table_info_t table; /**< grid, box, extrapolated points, build time */
  int cache_loaded;          /**< 1: the table came from the cache */
  int cache_saved;           /**< 1: it was built and saved */
  char cache_path[1200];     /**< the cache file ("" = none) */
  int cache_warnings;        /**< models whose cache file was not used (damaged, another
                                  format, not a regular file) or could not be written */
  char cache_message[2400];  /**< what went wrong with the cache, per model ("" = nothing):
                                  the table was built instead; a warning for the caller */
  double time_s;             /**< [s] to build or load */
} ea_plan_dyn_info_t;

/** Build the transcription for a checked task (ea_task_check / ea_task_load;
 *  the task is copied). Only what the task uses is built: base variables
 *  only when the base moves, path rows only for line/polyline paths,
 *  acceleration and speed rows only for finite limits, the FE frequency
 *  model only for min_vibration, min_first_frequency_Hz or
 *  max_modal_deflection_m. */
ea_status_t ea_planner_alloc(const ea_task_t *task, ea_planner_t **out, ea_error_t *err);
/** ea_planner_alloc with other settings than the task's (task->solver is ignored; settings
 *  validated by ea_planner_settings_validate and copied). The task says what to plan, the
 *  settings how: tolerances, iteration and time caps, transcription, engines, threads
 *  (ea_planner_settings.h). ea_planner_task() then reports them as its solver. */
ea_status_t ea_planner_alloc_with(const ea_task_t *task, const ea_planner_settings_t *settings,
                                  ea_planner_t **out, ea_error_t *err);
/** Free; NULL is a no-op. */
void ea_planner_free(ea_planner_t *pl);
/** The planner's task. */
const ea_task_t *ea_planner_task(const ea_planner_t *pl);
/** Plan. prev is used with EA_PLAN_FROM_TRAJ only (may be NULL otherwise).
 *  EA_PLAN_WARM without a previous converged solution falls back to cold.
 *  Returns EA_OK only for a converged plan satisfying every limit; then
 *  ea_planner_trajectory() gives it. On failure info->message says which
 *  constraint, at which knot, by how much (EA_ERR_INFEASIBLE when Ipopt
 *  proves local infeasibility or the path leaves the workspace). */
ea_status_t ea_planner_solve(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                             ea_plan_info_t *info, ea_error_t *err);
/** Replanning: change what a live planner solves without rebuilding it.
 *  task (checked by ea_task_check; copied) may differ from the planner's in
 *  its points (start, goal, vias), payload, limit values, duration, objective
 *  weights and solver settings (task->solver becomes the planner's settings, as
 *  in ea_planner_alloc), but not in anything that shapes the
 *  transcription: knot count, number of vias, path kind, objective, base
 *  motion, free/fixed duration, acceleration continuity, Hessian mode,
 *  which speed/acceleration limits are finite, the arm, nor a task with a
 *  frequency model; then EA_ERR_ARG says what differs (build a new planner).
 *  The next ea_planner_solve(EA_PLAN_WARM) starts from the previous plan and
 *  its multipliers, shifted along the change (docs/planner.md: points
 *  moved, statics re-solved at every knot, min_time re-timed), and falls
 *  back to a cold solve if that does not converge; info->iterations counts
 *  both. Without a previous plan the next solve is cold. */
ea_status_t ea_planner_update(ea_planner_t *pl, const ea_task_t *task, ea_error_t *err);
/** ea_planner_update with the planner's task and another goal (resolved and
 *  checked: EA_ERR_INFEASIBLE when it is outside the workspace). */
ea_status_t ea_planner_update_goal(ea_planner_t *pl, const ea_task_point_t *goal, ea_error_t *err);
/** ... another start point. */
ea_status_t ea_planner_update_start(ea_planner_t *pl, const ea_task_point_t *start,
                                    ea_error_t *err);
/** ... another payload [kg] (every point re-checked against its workspace). */
ea_status_t ea_planner_update_payload(ea_planner_t *pl, double payload_kg, ea_error_t *err);
/** ... other limit values (the same limits finite). */
ea_status_t ea_planner_update_limits(ea_planner_t *pl, const ea_task_limits_t *limits,
                                     ea_error_t *err);
/** The last converged plan, one row per knot, every column filled
 *  (tip from the statics tip and the base angle). tr is (re)allocated.
 *  EA_ERR_ARG when no plan converged since the last ea_planner_update. */
ea_status_t ea_planner_trajectory(const ea_planner_t *pl, ea_traj_t *tr, ea_error_t *err);
/** Which engine gave info's plan (or its failure): "interior-point-ldl" (the planner's own
 *  interior point, KKT systems by LDL), "ipopt", "active-set-newton" (a replan's Newton
 *  steps), "kkt-test" (a warm start that already was the solution: no iteration) or "none"
 *  (the solve stopped before an engine ran, e.g. no start point). Static string. */
const char *ea_plan_engine_name(const ea_plan_info_t *info);
/** The engine's outcome in words that name no engine: "converged", "converged-acceptable"
 *  (Ipopt's acceptable level), "max-iterations", "max-time", "infeasible" (Ipopt's
 *  restoration converged to a point of nonzero violation), "failed", or "none". Ipopt's own
 *  status is info->ipopt_status(_name) when the engine is "ipopt". Static string. */
const char *ea_plan_engine_status(const ea_plan_info_t *info);
/** Write the JSON summary (status, duration, iterations, times, margins,
 *  active limits) atomically. */
ea_status_t ea_plan_summary_write(const ea_planner_t *pl, const ea_plan_info_t *info,
                                  const char *path, ea_error_t *err);

/** The planner's model of the first natural frequency f1(L_c, alpha): FE
 *  frequencies (ea_fe_static_solve holding the tip + ea_fe_modes, passive
 *  cable, the task's tip mass) on a grid over the task's region of the
 *  (L_c, alpha) plane, interpolated by a GSL bicubic spline (docs/planner.md). */
typedef struct ea_plan_freq_model_info {
  int built;                         /**< 1 if the task needed (and got) the model */
  int n_cable_length, n_cable_angle; /**< grid points */
  double cable_length_range[2];      /**< [m] grid box (also bounds L_c in the plan) */
  double cable_angle_range[2];       /**< [rad] grid box (also bounds alpha in the plan) */
  int n_extrapolated;                /**< grid points without a valid FE state (outside the
                                          workspace or not converged), filled by extrapolation */
  double f1_min_hz, f1_max_hz;       /**< [Hz] over the valid grid points */
  double f_ref_hz;                   /**< [Hz] f1 at the start (scale of the vibration term) */
  double time_s;                     /**< [s] wall time to build it */
} ea_plan_freq_model_info_t;

/** The frequency model's info (built = 0 when the task needs none). */
ea_status_t ea_planner_freq_model(const ea_planner_t *pl, ea_plan_freq_model_info_t *info);
/** f1 [Hz] of the model at (L_c [m], alpha [rad]) (clamped to the grid box)
 *  and its gradient [Hz/m, Hz/rad] (grad may be NULL). EA_ERR_ARG when the
 *  planner has no frequency model. */
ea_status_t ea_planner_first_frequency(const ea_planner_t *pl, double cable_length,
                                       double cable_angle, double *f1_hz, double grad[2],
                                       ea_error_t *err);

/** The reduced dynamic model's info (built = 0 when the task has no dynamics). */
ea_status_t ea_planner_dyn_model(const ea_planner_t *pl, ea_plan_dyn_info_t *info);
/** The planner's reduced-model table (NULL when the task has no dynamics); owned by pl. */
const ea_rom_table_t *ea_planner_rom_table(const ea_planner_t *pl);
/** A task with dynamics that ends at rest: hold the modal state at the goal at (eta_i,
 *  eta_i') [sqrt(kg) m, sqrt(kg) m / s] (K values each; NULL = zeros) instead of zero; with
 *  a residual bound (residual_m > 0): keep it within the bound about (eta, eta_rate). An
 *  FE-in-the-loop refinement uses it to cancel what the reduced model misses: the next
 *  ea_planner_solve (EA_PLAN_WARM from the last plan) plans for the new target. EA_ERR_ARG
 *  without dynamics or with min_vibration. */
ea_status_t ea_planner_set_terminal_modes(ea_planner_t *pl, const double *eta,
                                          const double *eta_rate, ea_error_t *err);
/** The same for model `model` of a robust plan (dynamics.robust; 0 = the nominal, as
 *  ea_planner_set_terminal_modes; 1..4 = the corners in ea_plan_dyn_info_t's order): a
 *  corner's terminal row becomes "modal state within robust residual_m of (eta, eta_rate)"
 *  (K values each; NULL = zeros, the default). EA_ERR_ARG for a model the planner does not
 *  have or a target that is not finite. */
ea_status_t ea_planner_set_terminal_modes_model(ea_planner_t *pl, int model, const double *eta,
                                                const double *eta_rate, ea_error_t *err);

/* ------------------------------------------------------------------------ */
/* The planner metrics of batch studies (planner/nlp/study_plan.c)           */
/* ------------------------------------------------------------------------ */

/** The planner side of a batch study (ea_study.h, docs/studies.md): the tasks of its
 *  min_time and at_rest metrics, loaded once, behind the callbacks ea_study_run calls for
 *  each case. problems/ does not link Ipopt: without these callbacks a study's min_time and
 *  at_rest rows report EA_ERR_NOTIMPL. */
typedef struct ea_study_planner ea_study_planner_t;

/** Let ea_study_run compute the study's planner metrics. Loads the task of each
 *  (ea_study_metric_task_load: relative to the spec; the study's arm file, else default_arm
 *  (may be NULL), when the task names no arm file; each must be a min_time task) and puts
 *  the callbacks, their data and the tasks' content keys (part of the study key) in set:
 *  set->min_time, min_time_data, min_time_key, at_rest, at_rest_data, at_rest_key; no other
 *  field is touched. Per case, min_time plans the task with the case's arm and payload
 *  (re-checked: its points inside the case's workspace) from cold and reports its duration;
 *  at_rest plans it quasi-statically and with dynamics.modes = the study's at_rest.modes,
 *  residual 0, and measures the FE residual of each plan (ea_traj_simulate; the study's
 *  at_rest elements, dt, settle and damping ratio). Planner calls are serialised within a
 *  process (MUMPS' sequential build is not thread-safe); worker processes
 *  (set->workers) run them in parallel.
 * @param[out] out what set points to: keep it until ea_study_run returns, then
 *             ea_study_planner_free. NULL (and the callbacks NULL) when the study has
 *             neither metric.
 * @return EA_OK; else the error of loading a task (EA_ERR_IO, EA_ERR_INPUT: e.g. a task
 *         whose objective is not min_time, named as in the spec) or EA_ERR_NOMEM, with
 *         *out NULL and set's callbacks NULL. */
ea_status_t ea_study_use_planner(const ea_study_t *s, const char *default_arm,
                                 ea_study_settings_t *set, ea_study_planner_t **out,
                                 ea_error_t *err);
/** Free what ea_study_use_planner loaded (NULL: nothing). */
void ea_study_planner_free(ea_study_planner_t *p);

#ifdef __cplusplus
}
#endif
#endif /* EA_PLANNER_H */
