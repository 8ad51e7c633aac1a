/**
 * @file ea_experiment_plan.h
 * @brief The trajectory of an identification experiment (docs/calibration.md, "The
 *        experiment"): holds at the configurations of a spec (ea_experiment.h) joined by
 *        minimum-time moves planned by the planner (planner/nlp/experiment_plan.c).
 */
#ifndef EA_EXPERIMENT_PLAN_H
#define EA_EXPERIMENT_PLAN_H

#include "ea_experiment.h"
#include "ea_traj.h"

#ifdef __cplusplus
extern "C" {
#endif

/** One hold of an experiment trajectory. */
typedef struct ea_experiment_hold {
  int config;     /**< index into the configurations (ea_experiment_configs' order) */
  double t_start; /**< [s] trajectory time the hold begins (at rest from here) */
  double t_end;   /**< [s] and ends */
} ea_experiment_hold_t;

/** What ea_experiment_plan did. */
typedef struct ea_experiment_plan_info {
  double payload_kg; /**< [kg] */
  int n_configs;     /**< configurations of the spec (lengths x angles) */
  int n_feasible;    /**< of them inside the workspace and the limits */
  int n_holds;       /**< configurations visited (holds) */
  ea_experiment_hold_t holds[EA_EXPERIMENT_MAX_CONFIGS];
  int n_move_failures;    /**< feasible configurations skipped because no move reached them */
  double f1_min_hz;       /**< [Hz] lowest first frequency of the feasible configurations */
  double f1_max_hz;       /**< [Hz] highest */
  double damping_ratio;   /**< zeta the default hold time assumes (ea_experiment_hold_time) */
  double hold_s;          /**< [s] hold per configuration */
  double move_time_s;     /**< [s] sum of the moves' durations */
  double duration_s;      /**< [s] the trajectory's */
  int rows;               /**< its samples */
  int planner_iterations; /**< Ipopt / interior-point iterations over all moves */
  double time_s;          /**< [s] wall time */
  char message[512];      /**< first move failure ("" none) */
} ea_experiment_plan_info_t;

/** Plan the experiment trajectory of payload payload_index of spec s: the configurations of
 *  ea_experiment_configs (the infeasible ones skipped, with their notes in cfg), a hold of
 *  info->hold_s at each (ea_experiment_hold_time), joined by minimum-time moves planned by
 *  the planner between the configurations' actuator coordinates (a task with the spec's arm,
 *  the payload, the arm's limits, spec->knots knots, free path; a configuration no move
 *  reaches is skipped and the next one tried from the same place). The rows: the hold's
 *  start and end at rest (rates and accelerations 0), spec->transition_s, the move's rows
 *  (its end accelerations as planned), spec->transition_s, the next hold. The trajectory
 *  starts and ends at rest; its metadata name the arm file, its hash, the payload and the
 *  spec.
 * @param cfg  n_cable_length * n_angle entries (out: the resolved configurations)
 * @param[out] out the trajectory (ea_traj_t rules of ea_traj.h)
 * @param[out] info may be NULL
 * @return EA_OK; EA_ERR_INFEASIBLE when no configuration is feasible; EA_ERR_ARG,
 *         EA_ERR_NOMEM. */
ea_status_t ea_experiment_plan(const ea_experiment_spec_t *s, int payload_index,
                               ea_experiment_config_t *cfg, ea_traj_t *out,
                               ea_experiment_plan_info_t *info, ea_error_t *err);

#ifdef __cplusplus
}
#endif
#endif /* EA_EXPERIMENT_PLAN_H */
