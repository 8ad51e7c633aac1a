/* Private: drive of an FE transient from sampled joint commands, shared by
 * `simulate` (planner/cli_fe.c: a trajectory) and `controller-sim --simulate`
 * (planner/cli_stream.c: the setpoints the controller accepted). */
#ifndef EA_SIM_IMPL_H
#define EA_SIM_IMPL_H

#include "ea_planner.h"

/** Sampled drive: shoulder angle theta0 [rad] and the cable parameter of the
 *  chosen phase (passive: rest length L0 = L_c / (1 + T / EA_c), the moving
 *  reference length that has length L_c at tension T; active: tension T [N])
 *  at times t [s] from 0, interpolated by ea_fe_samples_eval. */
typedef struct ea__sim_drive {
  int n;          /**< samples */
  int active;     /**< 1: ACTIVE cable (T drives), 0: PASSIVE (L0 drives) */
  double *t;      /**< [s] n sample times, strictly increasing (owned, one block) */
  double *theta0; /**< [rad] n */
  double *cable;  /**< [m] L0 or [N] T, n */
  ea_fe_samples_t s_theta0, s_cable;
  ea_fe_drive_t drive; /**< ready for ea_fe_simulate after ea__sim_drive_finish */
} ea__sim_drive_t;

/** Allocate n >= 1 samples; d is zeroed first (ea__sim_drive_free is then always safe). */
ea_status_t ea__sim_drive_alloc(ea__sim_drive_t *d, int n, int active, ea_error_t *err);
void ea__sim_drive_free(ea__sim_drive_t *d);
/** Sample i at time t [s] of cable length L [m], tension T [N] and shoulder angle
 *  theta0 [rad]. EA_ERR_INPUT if T < 0 or a value is not finite (err names them). */
ea_status_t ea__sim_drive_set(ea__sim_drive_t *d, const ea_arm_t *arm, int i, double t, double L,
                              double T, double theta0, ea_error_t *err);
/** After the last ea__sim_drive_set: point d->drive at the samples (d must not move). */
void ea__sim_drive_finish(ea__sim_drive_t *d);
/** Start of the transient: from the full state q (NULL: m's current state, e.g. an FE
 *  static solve near the start), set theta0 = d->theta0[0], the cable phase and its
 *  value at t = 0, and Newton to the equilibrium under them (theta0 held). */
ea_status_t ea__sim_drive_start(ea_fe_model_t *m, const ea__sim_drive_t *d, const double *q,
                                ea_fe_static_info_t *info, ea_error_t *err);

#endif
