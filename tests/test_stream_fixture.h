/* Trajectory fixture for the streamer tests and bench: a rest-to-rest move of
 * cable length, shoulder angle and base angle along the septic smoothstep
 * s(u) = 35u^4 - 84u^5 + 70u^6 - 20u^7 (zero rate, acceleration and jerk at
 * both ends), sampled every h seconds. Being of degree 7, it is NOT
 * reproduced exactly by the streamer's quintic Hermite, so the round trip
 * measures a real interpolation error against this closed form. */
#ifndef TEST_STREAM_FIXTURE_H
#define TEST_STREAM_FIXTURE_H

#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_stream.h"

#include <string.h>

typedef struct {
  double T;        /* [s] duration */
  double L0, dL;   /* [m] cable length start, change */
  double th0, dth; /* [rad] theta0 */
  double b0, db;   /* [rad] base */
  double T0, dT;   /* [N] tension */
  double k0, dk;   /* [1/m] kappa0 */
} fx_move_t;

static fx_move_t fx_default_move(void) {
  fx_move_t m = {0.6, 0.40, 0.03, 0.9, 0.2, 0.0, 0.1, 5.0, 2.0, 1.0, 0.5};
  return m;
}

/* s, s', s'' of the smoothstep at time t for duration T. */
static void fx_step(double T, double t, double *s, double *sd, double *sdd) {
  double u = t / T;
  if (u < 0) u = 0;
  if (u > 1) u = 1;
  const double u2 = u * u, u3 = u2 * u, u4 = u3 * u, u5 = u4 * u, u6 = u5 * u, u7 = u6 * u;
  *s = 35 * u4 - 84 * u5 + 70 * u6 - 20 * u7;
  *sd = (140 * u3 - 420 * u4 + 420 * u5 - 140 * u6) / T;
  *sdd = (420 * u2 - 1680 * u3 + 2100 * u4 - 840 * u5) / (T * T);
}

/* Exact joint state of the move at t. */
static void fx_exact(const fx_move_t *m, double t, ea_joint_state_t *q) {
  double s, sd, sdd;
  fx_step(m->T, t, &s, &sd, &sdd);
  memset(q, 0, sizeof *q);
  q->cable_length = m->L0 + m->dL * s;
  q->cable_length_rate = m->dL * sd;
  q->cable_length_acc = m->dL * sdd;
  q->theta0 = m->th0 + m->dth * s;
  q->theta0_rate = m->dth * sd;
  q->theta0_acc = m->dth * sdd;
  q->base_angle = m->b0 + m->db * s;
  q->base_angle_rate = m->db * sd;
  q->base_angle_acc = m->db * sdd;
  q->tension = m->T0 + m->dT * s;
  q->kappa0 = m->k0 + m->dk * s;
}

/* Fill tr with the move sampled every h seconds (the last sample at T). */
static ea_status_t fx_make_traj(const fx_move_t *m, const ea_arm_t *arm, double h, ea_traj_t *tr) {
  const int n = (int)(m->T / h + 0.5) + 1;
  ea_status_t st = ea_traj_alloc(tr, n);
  if (st) return st;
  tr->payload_kg = 0;
  tr->tip_mass_kg = arm->m_hand;
  snprintf(tr->arm_file, sizeof tr->arm_file, "%s", "data/elasticarm.yaml");
  snprintf(tr->task, sizeof tr->task, "%s", "test fixture: septic smoothstep move");
  snprintf(tr->status, sizeof tr->status, "%s", "EA_OK");
  for (int i = 0; i < n; ++i) {
    const double t = (i == n - 1) ? m->T : i * h;
    ea_joint_state_t q;
    fx_exact(m, t, &q);
    EA_TRAJ_AT(tr, i, EA_TRAJ_t) = t;
    EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length) = q.cable_length;
    EA_TRAJ_AT(tr, i, EA_TRAJ_cable_angle) = -0.7;
    EA_TRAJ_AT(tr, i, EA_TRAJ_base_angle) = q.base_angle;
    EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length_rate) = q.cable_length_rate;
    EA_TRAJ_AT(tr, i, EA_TRAJ_base_angle_rate) = q.base_angle_rate;
    EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length_acc) = q.cable_length_acc;
    EA_TRAJ_AT(tr, i, EA_TRAJ_base_angle_acc) = q.base_angle_acc;
    EA_TRAJ_AT(tr, i, EA_TRAJ_tension) = q.tension;
    EA_TRAJ_AT(tr, i, EA_TRAJ_theta0) = q.theta0;
    EA_TRAJ_AT(tr, i, EA_TRAJ_theta0_rate) = q.theta0_rate;
    EA_TRAJ_AT(tr, i, EA_TRAJ_kappa0) = q.kappa0;
    EA_TRAJ_AT(tr, i, EA_TRAJ_shoulder_torque) = arm->EI * q.kappa0;
    EA_TRAJ_AT(tr, i, EA_TRAJ_tip_x) = 0.5;
    EA_TRAJ_AT(tr, i, EA_TRAJ_tip_z) = 0.1;
  }
  return EA_OK;
}

#endif
