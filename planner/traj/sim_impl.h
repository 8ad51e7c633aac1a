/* Private: drive of an FE transient from sampled joint commands, shared by
 * ea_traj_simulate (planner/traj/traj_sim.c: a trajectory) and `controller-sim --simulate`
 * (planner/app/cli_stream.c: the setpoints the controller accepted). */
#ifndef EA_SIM_IMPL_H
#define EA_SIM_IMPL_H

#include "ea_fe.h"
#include "ea_simulate.h"
#include "ea_traj.h"

/** Sampled drive: shoulder angle theta0 [rad] and the cable parameter of the
 *  chosen phase (passive: rest length L0 = L_c / (1 + T / EA_c), the moving
 *  reference length that has length L_c at tension T; active: tension T [N])
 *  at times t [s] from 0, interpolated by ea_fe_samples_eval: the cubic Hermite of
 *  the values and rates. Rates not given (NAN) come from centred differences of the
 *  values (zero at the ends). */
typedef struct ea__sim_drive {
  int n;           /**< samples */
  int active;      /**< 1: ACTIVE cable (T drives), 0: PASSIVE (L0 drives) */
  double EA_cable; /**< [N] of the arm */
  double *t;       /**< [s] n sample times, strictly increasing (owned, one block) */
  double *theta0;  /**< [rad] n */
  double *cable;   /**< [m] L0 or [N] T, n */
  double *theta0_rate, *cable_rate; /**< [rad/s], [m/s] or [N/s], n (filled by finish) */
  double *L, *L_rate, *T;           /**< [m], [m/s] (NAN: not given), [N]: n each */
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
/** Rates at sample i (after ea__sim_drive_set): dL_c/dt [m/s] and dtheta0/dt [rad/s];
 *  NAN = not known (centred differences). */
void ea__sim_drive_set_rates(ea__sim_drive_t *d, int i, double L_rate, double theta0_rate);
/** After the last sample: the rates of the drive (passive: dL0/dt = L_c' / (1 + T/EA_c)
 *  - L_c T' / (EA_c (1 + T/EA_c)^2), T' by centred differences), and d->drive pointed
 *  at the samples (d must not move). */
void ea__sim_drive_finish(ea__sim_drive_t *d);
/** Start of the transient: from the full state q (NULL: m's current equilibrium, e.g. an
 *  FE static solve of the start), continuation (ea_fe_static_continue) to the equilibrium
 *  under theta0 = d->theta0[0] and the cable's value at t = 0. */
ea_status_t ea__sim_drive_start(ea_fe_model_t *m, const ea__sim_drive_t *d, const double *q,
                                ea_fe_static_info_t *info, ea_error_t *err);

/* The modal state z (2 K) at the end of tr and its free vibration's peak over settle [s] at the
 * goal into out (traj_sim.c). */
void ea__rom_settle(const ea_rom_table_t *tb, const ea_traj_t *tr, int K, const double *z,
                    double settle, ea_rom_prediction_t *out);
/** Cubic Hermite of a trajectory's column c with its rate column cr at time t [s] (the
 *  interpolant the FE transient and ea_traj_rom_predict follow): value, rate and
 *  acceleration; outside the samples the end value, rate and acceleration 0. */
void ea__traj_hermite(const ea_traj_t *tr, int c, int cr, double t, double *q, double *v,
                      double *a);
/* The actuators q = (L_c, alpha), their rates v and accelerations a at time t [s] since the
 * start of tr (ea__traj_hermite of both). */
void ea__traj_actuators(const ea_traj_t *tr, double t, double q[2], double v[2], double a[2]);

#endif
