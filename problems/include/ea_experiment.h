/**
 * @file ea_experiment.h
 * @brief Identification experiments for calibration (docs/calibration.md, "The
 *        experiment"): what a user asks (a spec: cable lengths x angles x payloads and
 *        hold times), loaded from YAML and resolved to configurations checked against
 *        the workspace and the limits, each with its first natural frequency
 *        (problems/experiment_spec.c). The trajectory that visits them is planned by
 *        ea_experiment_plan (ea_experiment_plan.h). Knows nothing of Ipopt.
 */
#ifndef EA_EXPERIMENT_H
#define EA_EXPERIMENT_H

#include "ea_arm.h"
#include "ea_statics.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Most values of each list of a spec. */
#define EA_EXPERIMENT_MAX_VALUES 16
/** Most configurations (cable lengths x angles) of one payload. */
#define EA_EXPERIMENT_MAX_CONFIGS (EA_EXPERIMENT_MAX_VALUES * EA_EXPERIMENT_MAX_VALUES)

/** How a spec gives the angle of a configuration. */
typedef enum ea_experiment_angle {
  EA_EXPERIMENT_CABLE_ANGLE = 0, /**< cable angle alpha [rad] (key cable_angles_rad) */
  EA_EXPERIMENT_THETA0           /**< shoulder angle theta0 [rad] (key shoulder_angles_rad) */
} ea_experiment_angle_t;

/** An experiment spec. Plain data, no owned memory. */
typedef struct ea_experiment_spec {
  char name[128];
  char file[512];     /**< spec file ("" when built in C) */
  char arm_file[512]; /**< arm file the experiment is planned with ("" = built-in defaults) */
  ea_arm_t arm;
  int n_cable_length;
  double cable_length[EA_EXPERIMENT_MAX_VALUES]; /**< [m] commanded cable lengths L_c */
  ea_experiment_angle_t angle_kind;
  int n_angle;
  double angle[EA_EXPERIMENT_MAX_VALUES]; /**< [rad] cable angles or shoulder angles */
  int n_payload;
  double payload_kg[EA_EXPERIMENT_MAX_VALUES]; /**< [kg] payloads, one trajectory each
                                                    (default one: 0) */
  double hold_s;                /**< [s] hold per configuration; NAN (default): from the
                                     ring-down, ea_experiment_hold_time */
  double hold_time_constants;   /**< default hold: this many decay time constants
                                     1 / (zeta omega1) of the slowest configuration
                                     (default 3: the ringing falls to e^-3 = 5 %) */
  double hold_min_s;            /**< [s] bounds of the default hold (default 2) */
  double hold_max_s;            /**< [s] (default 30) */
  double assumed_damping_ratio; /**< zeta used when the arm file gives none (default 0.02) */
  int knots;                    /**< knots of each move's plan (default 40) */
  double transition_s;          /**< [s] between a hold and a move (default 0.01): the move's
                                     end acceleration is released in it; at least one stream
                                     period */
  double resample_margin;       /**< the moves' speed and acceleration limits are planned
                                     1 + this tighter (ea_task_limits_t.resample_margin;
                                     default 0.25): at a hold's edge the streamer takes
                                     theta0's acceleration as the mean of the hold's 0 and
                                     the move's, and its quintic then exceeds the plan's
                                     cubic by up to 19 % of the move's end acceleration */
} ea_experiment_spec_t;

/** Defaults for arm (copied; NULL = ea_arm_default); the lists still empty. */
void ea_experiment_spec_init(ea_experiment_spec_t *s, const ea_arm_t *arm);
/** Check a spec (lists non-empty, values finite, cable lengths > 0, hold bounds ordered...);
 *  err names the key, the value and the bound. */
ea_status_t ea_experiment_spec_check(const ea_experiment_spec_t *s, ea_error_t *err);
/** Load a spec file (docs/calibration.md, "The experiment"); arm_file relative to the spec's
 *  folder; without one, default_arm (NULL = built-in defaults). Errors say
 *  file:line:column, key and value (EA_ERR_IO, EA_ERR_PARSE, EA_ERR_INPUT). */
ea_status_t ea_experiment_spec_load(const char *path, const char *default_arm,
                                    ea_experiment_spec_t *s, ea_error_t *err);
/** The same from len bytes of text named name (arm files relative to the current folder). */
ea_status_t ea_experiment_spec_load_string(const char *name, const char *text, size_t len,
                                           const char *default_arm, ea_experiment_spec_t *s,
                                           ea_error_t *err);

/** One configuration of an experiment, resolved. */
typedef struct ea_experiment_config {
  int index;               /**< position in the spec's grid: i_length * n_angle + i_angle */
  double cable_length;     /**< [m] L_c */
  double cable_angle;      /**< [rad] alpha (given, or from the statics of L_c and theta0) */
  double p[EA_NP];         /**< statics (alpha, T, theta0, kappa0) */
  double tip_state[EA_NX]; /**< statics tip state (theta_L, kappa_L, x_L, y_L) */
  double shoulder_torque;  /**< [N m] EI kappa0 */
  double f1_hz;            /**< [Hz] first FE frequency (passive cable, the payload's tip mass);
                                NAN when not feasible */
  int feasible;            /**< 1: inside the workspace and the limits, stable */
  char note[400];          /**< why it is skipped ("" when feasible) */
} ea_experiment_config_t;

/** The configurations of payload payload_kg in the order the experiment visits them: the
 *  cable lengths in the spec's order, the angles of each length in the spec's order for
 *  the first length, reversed for the second, and so on (a serpentine, so that each move is
 *  short). Each: statics of (L_c, alpha) or (L_c, theta0) from the outer edge (the physical
 *  branch); checked: a static solution with T >= tension_min, T <= tension_max,
 *  |EI kappa0| <= shoulder_torque_max, L_c and theta0 in the arm's ranges; FE statics
 *  holding the tip and its first frequency (passive cable), stable. A configuration that
 *  fails is kept with feasible = 0 and a note.
 * @param cfg  n_cable_length * n_angle entries
 * @param[out] n_feasible how many are feasible
 * @return EA_OK (even when none is feasible); EA_ERR_ARG / EA_ERR_NOMEM. */
ea_status_t ea_experiment_configs(const ea_experiment_spec_t *s, double payload_kg,
                                  ea_experiment_config_t *cfg, int *n_feasible, ea_error_t *err);

/** The hold time of an experiment: spec's hold_s when given; else hold_time_constants decay
 *  time constants 1 / (zeta 2 pi f1_min) of its slowest feasible configuration (f1_min
 *  [Hz]), bounded to [hold_min_s, hold_max_s]; zeta the arm file's ratio of mode 1, else
 *  the spec's assumed_damping_ratio. *zeta_used (may be NULL) gets the zeta. */
double ea_experiment_hold_time(const ea_experiment_spec_t *s, double f1_min_hz, double *zeta_used);

#ifdef __cplusplus
}
#endif
#endif /* EA_EXPERIMENT_H */
