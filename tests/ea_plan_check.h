/* Re-check of a written trajectory file against every limit of its task and
 * arm, between the knots too (docs/trajectory-format.md, docs/planner.md,
 * "Limits between the knots"). Independent of the planner: it reads the CSV
 * with ea_traj_read, samples it at 1 kHz (and at every knot, both one-sided
 * accelerations) with the documented interpolant, and solves the statics at
 * every sample:
 *  - cable length, cable angle, base angle and theta0: the cubic Hermite of
 *    the value and rate columns on each interval (value, rate, acceleration);
 *  - tension, kappa0 (shoulder torque EI kappa0): the quasi-static values at
 *    the interpolated (L_c, alpha), by ea_statics_solve warm-started from
 *    the previous sample (the first from the file's first row).
 * Limits: the task's (tension, cable length range, cable and cable-angle
 * speed/acceleration, shoulder torque and speed, base speed/acceleration)
 * and the arm's (shoulder acceleration, shoulder and base angle ranges). */
#ifndef EA_PLAN_CHECK_H
#define EA_PLAN_CHECK_H

#include "ea_planner.h"
#include "ea_problems.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

enum {
  EA_CHK_LC = 0, /* cable length range [m] */
  EA_CHK_LC_V,   /* |dL_c/dt| */
  EA_CHK_LC_A,   /* |d2L_c/dt2| */
  EA_CHK_AL_V,   /* |dalpha/dt| (finite limit only) */
  EA_CHK_AL_A,   /* |d2alpha/dt2| */
  EA_CHK_T_MIN,  /* T >= T_min [N] */
  EA_CHK_T_MAX,  /* T <= T_max */
  EA_CHK_TORQUE, /* |EI kappa0| */
  EA_CHK_TH,     /* theta0 range [rad] */
  EA_CHK_TH_V,   /* |dtheta0/dt| */
  EA_CHK_TH_A,   /* |d2theta0/dt2| */
  EA_CHK_BASE,   /* base range [rad] */
  EA_CHK_BASE_V, /* |base rate| */
  EA_CHK_BASE_A, /* |base acceleration| */
  EA_CHK_N
};

static const char *const ea_chk_name[EA_CHK_N] = {
    "cable length range",   "cable speed",      "cable acceleration",    "cable angle speed",
    "cable angle accel.",   "tension >= T_min", "tension <= T_max",      "shoulder torque",
    "shoulder angle range", "shoulder speed",   "shoulder acceleration", "base angle range",
    "base speed",           "base acceleration"};

typedef struct ea_chk {
  double excess[EA_CHK_N]; /* worst excess relative to the limit (<= 0: held) */
  double usage[EA_CHK_N];  /* worst |value| / limit (speeds, accelerations, torque) */
  double t_at[EA_CHK_N];   /* time of the worst excess */
  int samples;             /* samples checked */
  int statics_fail;        /* samples where the statics did not converge */
  double th_dev;           /* max |theta0 cubic - theta0 of the statics at (L_c, alpha)| */
  double acc_col_dev;      /* max |acceleration column - cubic acceleration| (C2 check) */
} ea_chk_t;

/* Cubic Hermite on [0, h] at s in [0, 1]: value, rate, acceleration. */
static void ea_chk_cubic(double h, double s, double q0, double v0, double q1, double v1, double *q,
                         double *v, double *a) {
  const double d = q1 - q0;
  const double c2 = 3.0 * d - h * (2.0 * v0 + v1), c3 = -2.0 * d + h * (v0 + v1);
  *q = q0 + s * (h * v0 + s * (c2 + s * c3));
  *v = (h * v0 + s * (2.0 * c2 + s * 3.0 * c3)) / h;
  *a = (2.0 * c2 + 6.0 * c3 * s) / (h * h);
}

static void ea_chk_abs(ea_chk_t *c, int i, double v, double max, double t) {
  if (!isfinite(max)) return;
  const double u = fabs(v) / max;
  if (u > c->usage[i]) c->usage[i] = u;
  if (u - 1.0 > c->excess[i]) c->excess[i] = u - 1.0, c->t_at[i] = t;
}

static void ea_chk_range(ea_chk_t *c, int i, double v, double lo, double hi, double t) {
  const double e = fmax(lo - v, v - hi) / (hi - lo);
  if (e > c->excess[i]) c->excess[i] = e, c->t_at[i] = t;
}

/* One sample at time tt in interval k (s in [0, 1]); p: warm start in, the
 * statics solution out. */
static void ea_chk_sample(const ea_task_t *t, const ea_traj_t *tr, ea_shooter_t *sh, int k,
                          double s, double p[EA_NP], ea_chk_t *c) {
  const ea_task_limits_t *l = &t->limits;
  const ea_actuators_t *a = &t->arm.act;
  static const int qc[4] = {EA_TRAJ_cable_length, EA_TRAJ_cable_angle, EA_TRAJ_base_angle,
                            EA_TRAJ_theta0};
  static const int vc[4] = {EA_TRAJ_cable_length_rate, EA_TRAJ_cable_angle_rate,
                            EA_TRAJ_base_angle_rate, EA_TRAJ_theta0_rate};
  const double t0 = EA_TRAJ_AT(tr, k, EA_TRAJ_t), h = EA_TRAJ_AT(tr, k + 1, EA_TRAJ_t) - t0;
  const double tt = t0 + s * h;
  double q[4], v[4], acc[4];
  for (int i = 0; i < 4; ++i)
    ea_chk_cubic(h, s, EA_TRAJ_AT(tr, k, qc[i]), EA_TRAJ_AT(tr, k, vc[i]),
                 EA_TRAJ_AT(tr, k + 1, qc[i]), EA_TRAJ_AT(tr, k + 1, vc[i]), &q[i], &v[i], &acc[i]);
  ea_chk_range(c, EA_CHK_LC, q[0], l->cable_length_min, l->cable_length_max, tt);
  ea_chk_abs(c, EA_CHK_LC_V, v[0], l->cable_speed_max, tt);
  ea_chk_abs(c, EA_CHK_LC_A, acc[0], l->cable_accel_max, tt);
  ea_chk_abs(c, EA_CHK_AL_V, v[1], l->cable_angle_speed_max, tt);
  ea_chk_abs(c, EA_CHK_AL_A, acc[1], l->cable_angle_accel_max, tt);
  ea_chk_range(c, EA_CHK_BASE, q[2], a->base_angle_min, a->base_angle_max, tt);
  ea_chk_abs(c, EA_CHK_BASE_V, v[2], l->base_speed_max, tt);
  ea_chk_abs(c, EA_CHK_BASE_A, acc[2], l->base_accel_max, tt);
  ea_chk_range(c, EA_CHK_TH, q[3], a->shoulder_angle_min, a->shoulder_angle_max, tt);
  ea_chk_abs(c, EA_CHK_TH_V, v[3], l->shoulder_speed_max, tt);
  ea_chk_abs(c, EA_CHK_TH_A, acc[3], a->shoulder_accel_max, tt);
  /* acceleration columns vs the cubic at the knots (C2 plans: equal) */
  static const int ac[3] = {EA_TRAJ_cable_length_acc, EA_TRAJ_cable_angle_acc,
                            EA_TRAJ_base_angle_acc};
  if (s == 0.0 || s == 1.0)
    for (int i = 0; i < 3; ++i) {
      const double col = EA_TRAJ_AT(tr, k + (s == 1.0), ac[i]);
      c->acc_col_dev = fmax(c->acc_col_dev, fabs(col - acc[i]));
    }
  /* quasi-static tension and torque at the interpolated (L_c, alpha) */
  ea_statics_settings_t set;
  ea_statics_settings_default(&set);
  set.allow_negative_tension = 1;
  set.tol = 1e-12;
  p[0] = q[1];
  ea_statics_problem_t prob = ea_statics_problem_cable(q[0], q[1]);
  ea_statics_solution_t sol;
  if (ea_statics_solve(sh, &prob, &set, p, &sol, NULL) != EA_OK) {
    ++c->statics_fail;
  } else {
    memcpy(p, sol.p, EA_NP * sizeof *p);
    const double T = sol.p[EA_P_TENSION];
    if ((l->tension_min - T) / l->tension_min > c->excess[EA_CHK_T_MIN])
      c->excess[EA_CHK_T_MIN] = (l->tension_min - T) / l->tension_min, c->t_at[EA_CHK_T_MIN] = tt;
    ea_chk_abs(c, EA_CHK_T_MAX, T, l->tension_max, tt);
    ea_chk_abs(c, EA_CHK_TORQUE, t->arm.EI * sol.p[EA_P_KAPPA0], l->shoulder_torque_max, tt);
    c->th_dev = fmax(c->th_dev, fabs(sol.p[EA_P_THETA0] - q[3]));
  }
  ++c->samples;
}

/* Re-check trajectory tr of task t at rate_hz (and at every knot). Returns
 * the worst relative excess over all limits (<= 0: every limit held). */
static double ea_chk_traj(const ea_task_t *t, const ea_traj_t *tr, double rate_hz, ea_chk_t *c) {
  memset(c, 0, sizeof *c);
  for (int i = 0; i < EA_CHK_N; ++i)
    c->excess[i] = -INFINITY;
  ea_shooter_t *sh = NULL;
  if (ea_shooter_alloc(&t->arm, NULL, &sh, NULL)) return INFINITY;
  const ea_load_t load = {ea_arm_tip_mass(&t->arm, t->payload_kg)};
  ea_shooter_set_load(sh, &load);
  double p[EA_NP] = {EA_TRAJ_AT(tr, 0, EA_TRAJ_cable_angle), EA_TRAJ_AT(tr, 0, EA_TRAJ_tension),
                     EA_TRAJ_AT(tr, 0, EA_TRAJ_theta0), EA_TRAJ_AT(tr, 0, EA_TRAJ_kappa0)};
  const double t0 = EA_TRAJ_AT(tr, 0, EA_TRAJ_t), tf = EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t);
  int j = 0;
  for (int k = 0; k + 1 < tr->n; ++k) {
    const double ta = EA_TRAJ_AT(tr, k, EA_TRAJ_t), tb = EA_TRAJ_AT(tr, k + 1, EA_TRAJ_t);
    ea_chk_sample(t, tr, sh, k, 0.0, p, c);
    for (; t0 + j / rate_hz < tb; ++j) {
      const double s = (t0 + j / rate_hz - ta) / (tb - ta);
      if (s > 0.0) ea_chk_sample(t, tr, sh, k, s, p, c);
    }
    ea_chk_sample(t, tr, sh, k, 1.0, p, c);
  }
  (void)tf;
  ea_shooter_free(sh);
  double w = -INFINITY;
  for (int i = 0; i < EA_CHK_N; ++i)
    w = fmax(w, c->excess[i]);
  return c->statics_fail ? INFINITY : w;
}

/* Print the per-limit worst usage / excess. */
static void ea_chk_print(const char *name, const ea_chk_t *c) {
  printf("%s: %d samples, statics failures %d, theta0 cubic vs statics %.3g rad, acc columns vs "
         "cubic %.3g\n",
         name, c->samples, c->statics_fail, c->th_dev, c->acc_col_dev);
  for (int i = 0; i < EA_CHK_N; ++i)
    if (isfinite(c->excess[i]))
      printf("  %-22s worst excess %+.3e (usage %.6f) at t = %.4f s\n", ea_chk_name[i],
             c->excess[i], c->usage[i], c->t_at[i]);
}

#endif
