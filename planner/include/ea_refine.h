/**
 * @file ea_refine.h
 * @brief FE-in-the-loop refinement of a plan that arrives at rest (docs/planner.md,
 *        "Refinement against the FE transient"; task key dynamics.refine), and a plan's
 *        JSON summary with what was measured on it (refinement, ZV shaping, `plan --verify`).
 *
 * The reduced dynamic model the planner uses (model/fe_rom.c) is not the arm: the nonlinear
 * FE transient of an at-rest plan still rings after the motion. The refinement measures that
 * residual with ea_traj_simulate(), fits the free vibration of the model's modes to the FE
 * tip history, and moves the goal's modal targets (ea_planner_set_terminal_modes) to cancel
 * it; every candidate is re-planned warm by the planner, so every limit of the task still
 * holds on it. With dynamics.robust the same for each robust corner (docs/planner.md, "Robust
 * rest"): its FE arm's residual, its centre (ea_planner_set_terminal_modes_model). Never
 * prints.
 */
#ifndef EA_REFINE_H
#define EA_REFINE_H

#include "ea_planner.h"
#include "ea_simulate.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Most models a refinement adjusts: the nominal and, with dynamics.robust, the four corners. */
#define EA_REFINE_MAX_MODELS 5
/** Most parameters: 2 per adjusted mode and model. */
#define EA_REFINE_MAX_PARAMS (2 * EA_REFINE_MAX_MODELS * EA_ROM_MAX_MODES)

/** One evaluation of a refinement: a candidate re-planned and its FE transients. Per-model
 *  arrays are model-major: model j (0 the nominal, 1..4 the robust corners in the order of
 *  ea_plan_dyn_info_t) at j x (values per model). */
typedef struct ea_refine_eval {
  double params_m[EA_REFINE_MAX_PARAMS]; /**< [m] the parameters, 2 x settings.modes per model:
                                              per adjusted mode i the tip amplitudes (a_i, b_i)
                                              of the free vibration a_i cos + b_i sin the model
                                              predicts after the motion from its target (the
                                              nominal's terminal state, a corner's centre) */
  double eta[EA_REFINE_MAX_MODELS * EA_ROM_MAX_MODES];      /**< [sqrt(kg) m] the targets, K per
                                                                 model */
  double eta_rate[EA_REFINE_MAX_MODELS * EA_ROM_MAX_MODES]; /**< [sqrt(kg) m / s] */
  ea_status_t plan_status; /**< the warm re-plan (EA_OK: every limit holds) */
  int plan_iterations;     /**< Ipopt iterations of the re-plan */
  double plan_time_s;      /**< [s] wall time of the re-plan */
  double duration_s;       /**< [s] the candidate's duration (NAN: no plan) */
  ea_status_t fe_status;   /**< the FE transients (EA_ERR_ARG: not run; else the first failure) */
  double residual_peak_m;  /**< [m] FE at the nominal arm: peak |tip - final equilibrium| after
                                the motion (NAN: not measured) */
  double residual_rms_m;   /**< [m] FE at the nominal arm: its RMS */
  double model_residual_peak_m[EA_REFINE_MAX_MODELS]; /**< [m] the same at each model's arm
                                                           (0: the nominal arm) */
  double model_residual_rms_m[EA_REFINE_MAX_MODELS];  /**< [m] */
  double fitted_m[EA_REFINE_MAX_PARAMS];    /**< [m] (a_i, b_i) of every mode of model j fitted to
                                                 the FE residual of model j's arm (cos, sin about
                                                 the end of the motion, along the mode's tip
                                                 direction), 2 K per model */
  double predicted_m[EA_REFINE_MAX_PARAMS]; /**< [m] (a_i, b_i) of model j's own modal state at
                                                 the goal in the plan, 2 K per model */
  double score;     /**< max over the models of model_residual_peak_m / allowed_m (ea_refine_info_t;
                         <= 1: every model within its bound) */
  double fe_time_s; /**< [s] wall time of the FE transients */
  double elapsed_s; /**< [s] since the refinement started, at the end */
  int by_model;     /**< 1: measured by the nonlinear reduced model (settings.by), not the FE: the
                         residual and fitted fields are the model's prediction */
  int accepted;     /**< 1: planned, duration within bounds, FE measured at every model's arm */
  int final_resolve; /**< 1: the re-plan of the best candidate at the end */
} ea_refine_eval_t;

/** What a refinement did. */
typedef struct ea_refine_info {
  ea_status_t status;        /**< EA_OK: the planner holds the returned plan */
  int converged;             /**< 1: every model's FE residual peak within its bound */
  char stop_reason[32];      /**< "tolerance", "max_evaluations", "max_time", "no_progress",
                                  "optimizer" (NLopt stopped by itself), "failed" */
  ea_task_refine_t settings; /**< as used */
  ea_sim_settings_t fe;      /**< FE settings of every evaluation */
  int model_modes;           /**< K of the reduced model */
  int models;                /**< models refined: 1, or 5 with dynamics.robust */
  double model_tip_mass_kg[EA_REFINE_MAX_MODELS]; /**< [kg] each model's (and its FE arm's) tip
                                                       mass */
  double model_EI_Nm2[EA_REFINE_MAX_MODELS];      /**< [N m^2] each model's EI */
  double allowed_m[EA_REFINE_MAX_MODELS]; /**< [m] bound of each model's FE residual peak: the
                                               nominal settings.tolerance_m, a corner robust
                                               residual_m + tolerance_m */
  int n_params;                           /**< models x 2 x settings.modes */
  int n_evals; /**< evaluations, the unrefined plan's (index 0) included */
  ea_refine_eval_t evals[EA_TASK_REFINE_MAX_EVALUATIONS + 1];
  int returned;                  /**< index of the evaluation whose plan the planner holds */
  double duration_before_s;      /**< [s] the unrefined at-rest plan */
  double residual_peak_before_m; /**< [m] its FE residual peak (nominal arm) */
  double residual_rms_before_m;
  double model_residual_peak_before_m[EA_REFINE_MAX_MODELS]; /**< [m] per model's arm */
  double score_before;                                       /**< its score */
  double duration_s;                                         /**< [s] the returned plan */
  double residual_peak_m; /**< [m] its FE residual peak (nominal arm) */
  double residual_rms_m;
  double model_residual_peak_m[EA_REFINE_MAX_MODELS]; /**< [m] per model's arm */
  double score;                                       /**< its score */
  double eta[EA_REFINE_MAX_MODELS * EA_ROM_MAX_MODES],
      eta_rate[EA_REFINE_MAX_MODELS * EA_ROM_MAX_MODES]; /**< its targets, K per model */
  double time_s;                                         /**< [s] wall time of the refinement */
  double time_plan_s;                                    /**< [s] of it in re-plans */
  double time_fe_s;                                      /**< [s] of it in FE transients */
  double time_model_s;      /**< [s] of it in the nonlinear reduced model (settings.by): sampling
                                 its coefficients and integrating it */
  int model_evals;          /**< evaluations measured by the nonlinear reduced model */
  double model_only_peak_m; /**< [m] settings.by model: the model's residual peak at the plan it
                                 corrected, before the FE verdict (NAN: not run) */
  int nlopt_result;         /**< NLopt's return code (0: Newton) */
  char message[512];        /**< human-readable outcome */
} ea_refine_info_t;

/** Refine the planner's plan against the nonlinear FE transient (docs/planner.md). The task
 *  must have dynamics (dynamics.modes >= 1, not min_vibration) that end at rest
 *  (residual_m 0) or within a residual bound (residual_m > 0: the planner keeps the model's
 *  terminal state within the bound about the target centre, and the tolerance is the bound,
 *  whatever s->tolerance_m says). Evaluation 0 is the plan itself (terminal targets zero,
 *  re-planned warm: no iteration when the planner already holds it); then the method of s
 *  moves the targets of the first s->modes modes of every model (the nominal; with
 *  dynamics.robust also the four corners' centres) by the model's error at the goal until
 *  the FE residual peak is at most the tolerance at the nominal arm and at most robust
 *  residual_m + s->tolerance_m at each corner arm (with a residual bound: robust residual_m
 *  + EA_TASK_REST_TOLERANCE_M) (score <= 1), or s->max_evaluations evaluations were spent,
 *  or the next evaluation would pass s->max_time_s. The planner is left holding the
 *  evaluated plan of least score among the accepted ones (re-planned once more if it is not
 *  the last one planned, and then measured again: info->evals[info->returned]); that plan
 *  passed every check of ea_planner_solve.
 * @param s settings (NULL: the task's dynamics.refine; its enabled flag is ignored)
 * @param plan_info the returned plan's solve info (may be NULL)
 * @return EA_OK when the planner holds a refined (or the unrefined) plan, also if the
 *         tolerance was not reached (info->converged says); EA_ERR_ARG for a task without
 *         such dynamics; the planner's or the FE's error when even the at-rest plan could not
 *         be planned or measured. */
ea_status_t ea_plan_refine(ea_planner_t *pl, const ea_task_refine_t *s, ea_plan_info_t *plan_info,
                           ea_refine_info_t *info, ea_error_t *err);

/** What the FE checks of a task's plan by default (docs/planner.md, "Keeping the promise of
 *  rest"): EA_REST_CHECK_NONE (no dynamics, min_vibration, or dynamics.verify 0),
 *  EA_REST_CHECK_REFINE (ends at rest: ea_plan_refine with ea_plan_rest_settings until the FE
 *  residual is within EA_TASK_REST_TOLERANCE_M) or EA_REST_CHECK_BOUND (residual_m > 0: the
 *  same refinement until the FE residual is within residual_m, then the verdict of one FE
 *  transient at ea_sim_settings_default's settings, `plan --verify`'s). */
typedef enum ea_rest_check {
  EA_REST_CHECK_NONE = 0,
  EA_REST_CHECK_REFINE = 1,
  EA_REST_CHECK_BOUND = 2
} ea_rest_check_t;
ea_rest_check_t ea_plan_rest_check(const ea_task_t *task);

/** The refinement settings of the default check of a plan's promise: the task's
 *  dynamics.refine when it is enabled (tolerance_m 5e-5 m by default), else its defaults
 *  with tolerance_m = EA_TASK_REST_TOLERANCE_M (0.5 mm); with residual_m > 0, tolerance_m is
 *  residual_m. */
void ea_plan_rest_settings(const ea_task_t *task, ea_task_refine_t *s);

/** The default check of a plan's promise (ea_plan_rest_check not EA_REST_CHECK_NONE):
 *  ea_plan_refine with ea_plan_rest_settings of the planner's task. */
ea_status_t ea_plan_rest_refine(ea_planner_t *pl, ea_plan_info_t *plan_info, ea_refine_info_t *info,
                                ea_error_t *err);

/** The JSON summary of ea_plan_summary_write with a "refine" object (every evaluation:
 *  parameters, targets, re-plan, FE residual, times); refine NULL = ea_plan_summary_write. */
ea_status_t ea_plan_summary_write_refined(const ea_planner_t *pl, const ea_plan_info_t *info,
                                          const ea_refine_info_t *refine, const char *path,
                                          ea_error_t *err);

/* ------------------------------------------------------------------------ */
/* A plan's summary with what was measured (planner/nlp/plan_output.c)       */
/* ------------------------------------------------------------------------ */

/** `plan --verify`: the FE transient (ea_traj_simulate) of the written trajectory beside what
 *  the planner's reduced model predicted for it. */
typedef struct ea_plan_verify {
  ea_status_t status;              /**< of ea_traj_simulate */
  char message[512];               /**< its error, or "" */
  ea_sim_settings_t settings;      /**< used */
  ea_sim_info_t sim;               /**< measured */
  double predicted_residual_m;     /**< [m] the model's residual amplitude (sum over the modes,
                                        undamped) for the written trajectory; NAN: no model
                                        (a quasi-static plan) */
  double predicted_time_to_rest_s; /**< [s] after the motion (ea_plan_info_t); NAN: none,
                                        INFINITY: never */
  double residual_bound_m;         /**< [m] the measured residual peak must not exceed this: the
                                        task's dynamics.residual_m when > 0, else the refinement's
                                        tolerance_m when the plan was refined; NAN: no bound */
  double tension_bound_N;          /**< [N] the measured cable tension must stay at or above this
                                        (the task's tension limit, > 0: a slack cable fails) */
  int passed;                      /**< 1: the transient ran and met every bound above */
  char failure[512];               /**< what failed and what was reached ("" when passed) */
  double base_travel_rad;          /**< [rad] the trajectory's base-angle range (max - min): the
                                        FE transient is planar, the base rotation's loads
                                        (inertia, centrifugal, Coriolis) are not in it */
  double predicted_nonlinear_residual_m; /**< [m] the nonlinear reduced model's residual peak
                                              for the written trajectory (model/fe_romnl.c; a task
                                              with 2 modes); NAN: not computed */
} ea_plan_verify_t;

/** Judge a verification: v->status, v->sim against v->residual_bound_m and
 *  v->tension_bound_N; sets v->passed and v->failure. */
void ea_plan_verify_judge(ea_plan_verify_t *v);

/** The JSON summary of ea_plan_summary_write_refined (refine NULL: none) with a "shape" object
 *  (shape not NULL: the ZV shaping of the written trajectory, its limits check), a "verify"
 *  object (verify not NULL: measured FE residual beside the prediction) and "run_id" (run_id
 *  not NULL: the id the caller also wrote into the trajectory file's '# run_id:' line, so a
 *  reader can tell that the two files come from the same run). Atomic. */
ea_status_t ea_plan_summary_write_ex(const ea_planner_t *pl, const ea_plan_info_t *info,
                                     const ea_refine_info_t *refine, const ea_shape_info_t *shape,
                                     const ea_plan_verify_t *verify, const char *run_id,
                                     const char *path, ea_error_t *err);

#ifdef __cplusplus
}
#endif
#endif
