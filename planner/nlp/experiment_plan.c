/* The trajectory of an identification experiment (ea_experiment_plan.h): holds at the
 * spec's configurations joined by minimum-time moves of the planner. */
#include "ea_experiment_plan.h"
#include "ea_planner.h"
#include "ea_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Growing row buffer (EA_TRAJ_NCOL doubles per row). */
typedef struct {
  double *d;
  int n, cap;
} ea__rows_t;

static ea_status_t ea__rows_push(ea__rows_t *b, const double *row, double t, ea_error_t *err) {
  if (b->n == b->cap) {
    const int cap = b->cap ? 2 * b->cap : 256;
    double *d = realloc(b->d, sizeof(double) * EA_TRAJ_NCOL * (size_t)cap);
    if (!d) return ea_error_set(err, EA_ERR_NOMEM, "experiment: %d rows", cap);
    b->d = d;
    b->cap = cap;
  }
  double *o = b->d + (size_t)EA_TRAJ_NCOL * b->n++;
  memcpy(o, row, sizeof(double) * EA_TRAJ_NCOL);
  o[EA_TRAJ_t] = t;
  return EA_OK;
}

/* A row at rest: every rate and acceleration 0. */
static void ea__at_rest(double *row) {
  static const int c[] = {EA_TRAJ_cable_length_rate, EA_TRAJ_cable_angle_rate,
                          EA_TRAJ_base_angle_rate,   EA_TRAJ_cable_length_acc,
                          EA_TRAJ_cable_angle_acc,   EA_TRAJ_base_angle_acc,
                          EA_TRAJ_theta0_rate};
  for (size_t i = 0; i < sizeof c / sizeof *c; ++i)
    row[c[i]] = 0.0;
}

/* A minimum-time move from configuration a to b with payload payload_kg into mv. */
static ea_status_t ea__move(const ea_experiment_spec_t *s, double payload_kg,
                            const ea_experiment_config_t *a, const ea_experiment_config_t *b,
                            ea_traj_t *mv, int *iterations, ea_error_t *err) {
  ea_task_t task;
  ea_task_init(&task, &s->arm);
  snprintf(task.name, sizeof task.name, "%s", s->name);
  snprintf(task.file, sizeof task.file, "%s", s->file);
  snprintf(task.arm_file, sizeof task.arm_file, "%s", s->arm_file);
  task.payload_kg = payload_kg;
  task.start = ea_task_point_actuators(a->cable_length, a->cable_angle, 0.0);
  task.goal = ea_task_point_actuators(b->cable_length, b->cable_angle, 0.0);
  task.objective = EA_TASK_MIN_TIME;
  task.knots = s->knots;
  task.limits.resample_margin = s->resample_margin;
  ea_status_t st = ea_task_check(&task, err);
  if (st) return st;
  ea_planner_t *pl = NULL;
  if ((st = ea_planner_alloc(&task, &pl, err))) return st;
  ea_plan_info_t pi;
  st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &pi, err);
  *iterations += pi.iterations + pi.ipm_iterations;
  if (!st) st = ea_planner_trajectory(pl, mv, err);
  ea_planner_free(pl);
  return st;
}

/* Two rows of a hold at configuration row `row` from t0 for hold seconds. */
static ea_status_t ea__hold(ea__rows_t *b, const double *row, double t0, double hold,
                            ea_experiment_plan_info_t *info, int config, ea_error_t *err) {
  double r[EA_TRAJ_NCOL];
  memcpy(r, row, sizeof r);
  ea__at_rest(r);
  ea_status_t st = ea__rows_push(b, r, t0, err);
  if (!st) st = ea__rows_push(b, r, t0 + hold, err);
  if (!st) {
    ea_experiment_hold_t *h = &info->holds[info->n_holds++];
    h->config = config;
    h->t_start = t0;
    h->t_end = t0 + hold;
  }
  return st;
}

/* The hold row of a configuration from its statics (a trajectory of one feasible
 * configuration has no move to copy it from). */
static ea_status_t ea__statics_row(const ea_experiment_spec_t *s, const ea_experiment_config_t *c,
                                   double row[EA_TRAJ_NCOL], ea_error_t *err) {
  ea_traj_t one = {0};
  ea_status_t st = ea_traj_alloc(&one, 1);
  if (st) return ea_error_set(err, st, "experiment: one row");
  EA_TRAJ_AT(&one, 0, EA_TRAJ_cable_length) = c->cable_length;
  EA_TRAJ_AT(&one, 0, EA_TRAJ_cable_angle) = c->cable_angle;
  ea_traj_set_statics(&one, 0, c->p, c->tip_state, s->arm.EI);
  memcpy(row, one.data, sizeof(double) * EA_TRAJ_NCOL);
  ea_traj_free(&one);
  return EA_OK;
}

/* Hold, transition, move, transition, hold ...: every feasible configuration from first on. */
static ea_status_t ea__build(const ea_experiment_spec_t *s, double payload_kg,
                             ea_experiment_config_t *cfg, int ncfg, ea__rows_t *b,
                             ea_experiment_plan_info_t *info, ea_error_t *err) {
  const double hold = info->hold_s, tr = s->transition_s;
  int cur = -1;
  ea_traj_t mv = {0};
  ea_status_t st = EA_OK;
  for (int k = 0; k < ncfg && !st; ++k) {
    if (!cfg[k].feasible) continue;
    if (cur < 0) {
      cur = k;
      continue;
    }
    ea_error_t e = {0};
    const ea_status_t sm =
        ea__move(s, payload_kg, &cfg[cur], &cfg[k], &mv, &info->planner_iterations, &e);
    if (sm == EA_ERR_NOMEM) {
      st = ea_error_set(err, sm, "%s", e.msg);
      break;
    }
    if (sm) {
      snprintf(cfg[k].note, sizeof cfg[k].note, "L_c = %g m, alpha = %g rad: no move to it: %.250s",
               cfg[k].cable_length, cfg[k].cable_angle, e.msg);
      if (!info->message[0]) snprintf(info->message, sizeof info->message, "%s", cfg[k].note);
      ++info->n_move_failures;
      continue;
    }
    const int last = mv.n - 1;
    if (info->n_holds == 0 && (st = ea__hold(b, mv.data, 0.0, hold, info, cur, err))) break;
    /* the move starts exactly where the hold is (its statics columns), with its acceleration */
    double *r0 = mv.data;
    const double *h = b->d + (size_t)EA_TRAJ_NCOL * (b->n - 1);
    static const int pos[] = {
        EA_TRAJ_cable_length, EA_TRAJ_cable_angle, EA_TRAJ_base_angle,      EA_TRAJ_tension,
        EA_TRAJ_theta0,       EA_TRAJ_kappa0,      EA_TRAJ_shoulder_torque, EA_TRAJ_tip_x,
        EA_TRAJ_tip_y,        EA_TRAJ_tip_z};
    for (size_t i = 0; i < sizeof pos / sizeof *pos; ++i)
      r0[pos[i]] = h[pos[i]];
    const double t0 = h[EA_TRAJ_t] + tr - EA_TRAJ_AT(&mv, 0, EA_TRAJ_t);
    for (int i = 0; i < mv.n && !st; ++i)
      st = ea__rows_push(b, mv.data + (size_t)EA_TRAJ_NCOL * i, EA_TRAJ_AT(&mv, i, EA_TRAJ_t) + t0,
                         err);
    if (st) break;
    info->move_time_s += EA_TRAJ_AT(&mv, last, EA_TRAJ_t) - EA_TRAJ_AT(&mv, 0, EA_TRAJ_t);
    st = ea__hold(b, mv.data + (size_t)EA_TRAJ_NCOL * last,
                  EA_TRAJ_AT(&mv, last, EA_TRAJ_t) + t0 + tr, hold, info, k, err);
    cur = k;
  }
  ea_traj_free(&mv);
  if (!st && info->n_holds == 0 && cur >= 0) { /* one configuration reached: a hold alone */
    double row[EA_TRAJ_NCOL];
    if (!(st = ea__statics_row(s, &cfg[cur], row, err)))
      st = ea__hold(b, row, 0.0, hold, info, cur, err);
  }
  return st;
}

ea_status_t ea_experiment_plan(const ea_experiment_spec_t *s, int payload_index,
                               ea_experiment_config_t *cfg, ea_traj_t *out,
                               ea_experiment_plan_info_t *info, ea_error_t *err) {
  ea_experiment_plan_info_t loc;
  if (!info) info = &loc;
  memset(info, 0, sizeof *info);
  if (!s || !cfg || !out) return ea_error_set(err, EA_ERR_ARG, "experiment: NULL argument");
  if (payload_index < 0 || payload_index >= s->n_payload)
    return ea_error_set(err, EA_ERR_ARG, "experiment: payload %d of %d", payload_index + 1,
                        s->n_payload);
  const double wall0 = ea__mono_s();
  const double payload = s->payload_kg[payload_index];
  info->payload_kg = payload;
  info->n_configs = s->n_cable_length * s->n_angle;
  ea_status_t st = ea_experiment_configs(s, payload, cfg, &info->n_feasible, err);
  if (st) return st;
  info->f1_min_hz = INFINITY;
  info->f1_max_hz = -INFINITY;
  for (int k = 0; k < info->n_configs; ++k)
    if (cfg[k].feasible) {
      info->f1_min_hz = fmin(info->f1_min_hz, cfg[k].f1_hz);
      info->f1_max_hz = fmax(info->f1_max_hz, cfg[k].f1_hz);
    }
  if (info->n_feasible == 0) {
    info->f1_min_hz = info->f1_max_hz = NAN;
    return ea_error_set(err, EA_ERR_INFEASIBLE,
                        "experiment: none of the %d configurations is feasible at payload %g kg "
                        "(first: %s)",
                        info->n_configs, payload, cfg[0].note);
  }
  info->hold_s = ea_experiment_hold_time(s, info->f1_min_hz, &info->damping_ratio);
  ea__rows_t b = {0};
  st = ea__build(s, payload, cfg, info->n_configs, &b, info, err);
  if (!st && (st = ea_traj_alloc(out, b.n))) ea_error_set(err, st, "experiment: %d rows", b.n);
  if (!st) {
    memcpy(out->data, b.d, sizeof(double) * EA_TRAJ_NCOL * (size_t)b.n);
    out->payload_kg = payload;
    out->tip_mass_kg = ea_arm_tip_mass(&s->arm, payload);
    snprintf(out->arm_file, sizeof out->arm_file, "%s", s->arm_file);
    out->has_arm_hash = 1;
    out->arm_hash = ea_arm_hash(&s->arm);
    snprintf(out->task, sizeof out->task, "%s", s->file[0] ? s->file : s->name);
    snprintf(out->status, sizeof out->status, "EA_OK");
    info->rows = b.n;
    info->duration_s = EA_TRAJ_AT(out, b.n - 1, EA_TRAJ_t);
  }
  free(b.d);
  info->time_s = ea__mono_s() - wall0;
  return st;
}
