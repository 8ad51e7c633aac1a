/**
 * @file ea_refine.h
 * @brief FE-in-the-loop refinement of a plan that arrives at rest (docs/planner.md,
 *        "Refinement against the FE transient"; task key dynamics.refine).
 *
 * The reduced dynamic model the planner uses (model/fe_rom.c) is not the arm: the nonlinear
 * FE transient of an at-rest plan still rings after the motion. The refinement measures that
 * residual with ea_traj_simulate(), fits the free vibration of the model's modes to the FE
 * tip history, and moves the goal's modal targets (ea_planner_set_terminal_modes) to cancel
 * it; every candidate is re-planned warm by the planner, so every limit of the task still
 * holds on it. Never prints.
 */
#ifndef EA_REFINE_H
#define EA_REFINE_H

#include "ea_planner.h"
#include "ea_simulate.h"

#ifdef __cplusplus
extern "C" {
#endif

/** One evaluation of a refinement: a candidate re-planned and its FE transient. */
typedef struct ea_refine_eval {
  double params_m[2 * EA_ROM_MAX_MODES]; /**< [m] the parameters: per adjusted mode i the tip
                                              amplitudes (a_i, b_i) of the free vibration
                                              a_i cos + b_i sin the model predicts after the
                                              motion from the targets below */
  double eta[EA_ROM_MAX_MODES];          /**< [sqrt(kg) m] terminal modal targets */
  double eta_rate[EA_ROM_MAX_MODES];     /**< [sqrt(kg) m / s] */
  ea_status_t plan_status;               /**< the warm re-plan (EA_OK: every limit holds) */
  int plan_iterations;                   /**< Ipopt iterations of the re-plan */
  double plan_time_s;                    /**< [s] wall time of the re-plan */
  double duration_s;                     /**< [s] the candidate's duration (NAN: no plan) */
  ea_status_t fe_status;                 /**< the FE transient (EA_ERR_ARG: not run) */
  double residual_peak_m;                /**< [m] FE: peak |tip - final equilibrium| after the
                                              motion (NAN: not measured) */
  double residual_rms_m;                 /**< [m] FE: its RMS */
  double fitted_m[2 * EA_ROM_MAX_MODES]; /**< [m] (a_i, b_i) of every model mode fitted to the
                                              FE residual (cos, sin about the end of the
                                              motion, along the mode's tip direction) */
  double fe_time_s;                      /**< [s] wall time of the FE transient */
  double elapsed_s;                      /**< [s] since the refinement started, at the end */
  int accepted;                          /**< 1: planned, duration within bounds, FE measured */
  int final_resolve;                     /**< 1: the re-plan of the best candidate at the end */
} ea_refine_eval_t;

/** What a refinement did. */
typedef struct ea_refine_info {
  ea_status_t status;        /**< EA_OK: the planner holds the returned plan */
  int converged;             /**< 1: its FE residual peak is within the tolerance */
  char stop_reason[32];      /**< "tolerance", "max_evaluations", "max_time", "no_progress",
                                  "optimizer" (NLopt stopped by itself), "failed" */
  ea_task_refine_t settings; /**< as used */
  ea_sim_settings_t fe;      /**< FE settings of every evaluation */
  int model_modes;           /**< K of the reduced model */
  int n_params;              /**< 2 x settings.modes */
  int n_evals;               /**< evaluations, the unrefined plan's (index 0) included */
  ea_refine_eval_t evals[EA_TASK_REFINE_MAX_EVALUATIONS + 1];
  int returned;                  /**< index of the evaluation whose plan the planner holds */
  double duration_before_s;      /**< [s] the unrefined at-rest plan */
  double residual_peak_before_m; /**< [m] its FE residual peak */
  double residual_rms_before_m;
  double duration_s;      /**< [s] the returned plan */
  double residual_peak_m; /**< [m] its FE residual peak */
  double residual_rms_m;
  double eta[EA_ROM_MAX_MODES], eta_rate[EA_ROM_MAX_MODES]; /**< its terminal targets */
  double time_s;                                            /**< [s] wall time of the refinement */
  double time_plan_s;                                       /**< [s] of it in re-plans */
  double time_fe_s;                                         /**< [s] of it in FE transients */
  int nlopt_result;                                         /**< NLopt's return code (0: Newton) */
  char message[512];                                        /**< human-readable outcome */
} ea_refine_info_t;

/** Refine the planner's plan against the nonlinear FE transient (docs/planner.md). The task
 *  must have dynamics that end at rest (dynamics.modes >= 1, residual_m 0, not
 *  min_vibration). Evaluation 0 is the at-rest plan (terminal targets zero, re-planned warm:
 *  no iteration when the planner already holds it); then the method of s moves the targets
 *  of the first s->modes modes until the FE residual peak is at most s->tolerance_m, or
 *  s->max_evaluations FE transients were spent, or the next evaluation would pass
 *  s->max_time_s. The planner is left holding the evaluated plan of least FE residual peak
 *  among the accepted ones (re-planned once more if it is not the last one planned, and then
 *  measured again: info->evals[info->returned]); that plan passed every check of
 *  ea_planner_solve.
 * @param s settings (NULL: the task's dynamics.refine; its enabled flag is ignored)
 * @param plan_info the returned plan's solve info (may be NULL)
 * @return EA_OK when the planner holds a refined (or the unrefined) plan, also if the
 *         tolerance was not reached (info->converged says); EA_ERR_ARG for a task without
 *         such dynamics; the planner's or the FE's error when even the at-rest plan could not
 *         be planned or measured. */
ea_status_t ea_plan_refine(ea_planner_t *pl, const ea_task_refine_t *s, ea_plan_info_t *plan_info,
                           ea_refine_info_t *info, ea_error_t *err);

/** The JSON summary of ea_plan_summary_write with a "refine" object (every evaluation:
 *  parameters, targets, re-plan, FE residual, times); refine NULL = ea_plan_summary_write. */
ea_status_t ea_plan_summary_write_refined(const ea_planner_t *pl, const ea_plan_info_t *info,
                                          const ea_refine_info_t *refine, const char *path,
                                          ea_error_t *err);

#ifdef __cplusplus
}
#endif
#endif
