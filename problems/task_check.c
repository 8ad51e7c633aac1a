/* Task specs built in C: defaults, points, and the validation shared with
 * the YAML loader (limits, objective, workspace of every point). */
#include "ea_arm_file.h"
#include "ea_fe.h"
#include "ea_task.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const char *const ea__obj_names[] = {"min_time", "min_effort", "min_jerk", "min_vibration"};
static const char *const ea__path_names[] = {"free", "line", "polyline"};

const char *ea_task_objective_name(ea_task_objective_t o) {
  return ((int)o >= 0 && o <= EA_TASK_MIN_VIBRATION) ? ea__obj_names[o] : "unknown";
}
const char *ea_task_path_name(ea_task_path_t p) {
  return ((int)p >= 0 && p <= EA_TASK_PATH_POLYLINE) ? ea__path_names[p] : "unknown";
}

void ea_task_init(ea_task_t *t, const ea_arm_t *arm) {
  memset(t, 0, sizeof *t);
  if (arm)
    t->arm = *arm;
  else
    ea_arm_default(&t->arm);
  snprintf(t->name, sizeof t->name, "task");
  t->payload_kg = 0.0;
  t->payload_factor = NAN;
  t->path = EA_TASK_PATH_FREE;
  t->objective = EA_TASK_MIN_TIME;
  t->duration_s = NAN;
  const ea_actuators_t *a = &t->arm.act;
  t->limits.tension_min = a->tension_min;
  t->limits.tension_max = a->tension_max;
  t->limits.cable_length_min = a->cable_length_min;
  t->limits.cable_length_max = a->cable_length_max;
  t->limits.cable_speed_max = a->cable_speed_max;
  t->limits.cable_accel_max = a->cable_accel_max;
  t->limits.cable_angle_speed_max = INFINITY;
  t->limits.cable_angle_accel_max = INFINITY;
  t->limits.shoulder_torque_max = a->shoulder_torque_max;
  t->limits.shoulder_speed_max = a->shoulder_speed_max;
  t->limits.base_speed_max = a->base_speed_max;
  t->limits.base_accel_max = a->base_accel_max;
  t->limits.min_first_frequency_hz = 0.0;
  t->limits.max_modal_deflection_m = INFINITY;
  t->limits.resample_margin = 0.0;
  t->limits.continuous_acceleration = 1;
  t->time_weight = NAN;
  t->dynamics.modes = 0;
  t->dynamics.residual_m = 0.0;
  t->dynamics.max_tip_deviation_m = INFINITY;
  t->dynamics.robust_residual_m = 5e-4;
  ea_task_refine_default(&t->dynamics.refine);
  t->dynamics.verify = 1;
  t->knots = 100;
  ea_planner_settings_default(&t->solver);
  t->start = ea_task_point_planar(NAN, NAN, 0.0);
  t->goal = t->start;
}

ea_task_point_t ea_task_point_planar(double x, double y, double base_angle) {
  ea_task_point_t p;
  memset(&p, 0, sizeof p);
  p.kind = EA_TASK_TIP_PLANAR;
  p.given[0] = x;
  p.given[1] = y;
  p.given[2] = base_angle;
  return p;
}
ea_task_point_t ea_task_point_3d(double x, double y, double z) {
  ea_task_point_t p = ea_task_point_planar(x, y, z);
  p.kind = EA_TASK_TIP_3D;
  return p;
}
ea_task_point_t ea_task_point_actuators(double cable_length, double cable_angle,
                                        double base_angle) {
  ea_task_point_t p = ea_task_point_planar(cable_length, cable_angle, base_angle);
  p.kind = EA_TASK_ACTUATORS;
  return p;
}

/* "where: " prefix or "". */
static const char *ea__pre(const char *where, char *buf, size_t len) {
  if (where && where[0])
    snprintf(buf, len, "%s: ", where);
  else
    buf[0] = '\0';
  return buf;
}

static ea_status_t ea__check_limits(const ea_task_t *t, ea_error_t *err) {
  const ea_task_limits_t *l = &t->limits;
  const ea_actuators_t *a = &t->arm.act;
  char pre[320];
  ea__pre(t->where_limits, pre, sizeof pre);
  struct {
    const char *key;
    double v, arm_max;
    int may_be_inf;
  } pos[] = {
      {"tension_min_N", l->tension_min, INFINITY, 0},
      {"tension_max_N", l->tension_max, a->tension_max, 0},
      {"cable_length_min_m", l->cable_length_min, INFINITY, 0},
      {"cable_length_max_m", l->cable_length_max, a->cable_length_max, 0},
      {"cable_speed_max_m_per_s", l->cable_speed_max, a->cable_speed_max, 0},
      {"cable_accel_max_m_per_s2", l->cable_accel_max, a->cable_accel_max, 0},
      {"cable_angle_speed_max_rad_per_s", l->cable_angle_speed_max, INFINITY, 1},
      {"cable_angle_accel_max_rad_per_s2", l->cable_angle_accel_max, INFINITY, 1},
      {"shoulder_torque_max_Nm", l->shoulder_torque_max, a->shoulder_torque_max, 0},
      {"shoulder_speed_max_rad_per_s", l->shoulder_speed_max, a->shoulder_speed_max, 1},
      {"base_speed_max_rad_per_s", l->base_speed_max, a->base_speed_max, 0},
      {"base_accel_max_rad_per_s2", l->base_accel_max, a->base_accel_max, 0},
  };
  for (size_t i = 0; i < sizeof pos / sizeof *pos; ++i) {
    const double v = pos[i].v;
    if (isnan(v) || !(v > 0.0) || (isinf(v) && !pos[i].may_be_inf))
      return ea_error_set(err, EA_ERR_INPUT, "%slimits.%s = %g: must be a finite number > 0", pre,
                          pos[i].key, v);
    if (v > pos[i].arm_max * (1.0 + 1e-12))
      return ea_error_set(err, EA_ERR_INPUT,
                          "%slimits.%s = %g exceeds the arm's limit %g (arm file)", pre, pos[i].key,
                          v, pos[i].arm_max);
  }
  if (!(l->tension_min < l->tension_max))
    return ea_error_set(err, EA_ERR_INPUT,
                        "%scontradictory limits: tension_min_N = %g >= tension_max_N = %g", pre,
                        l->tension_min, l->tension_max);
  if (!(l->cable_length_min < l->cable_length_max))
    return ea_error_set(err, EA_ERR_INPUT,
                        "%scontradictory limits: cable_length_min_m = %g >= cable_length_max_m "
                        "= %g",
                        pre, l->cable_length_min, l->cable_length_max);
  if (l->cable_length_min < a->cable_length_min * (1.0 - 1e-12))
    return ea_error_set(err, EA_ERR_INPUT,
                        "%slimits.cable_length_min_m = %g is below the arm's shortest cable %g",
                        pre, l->cable_length_min, a->cable_length_min);
  if (!(l->min_first_frequency_hz >= 0.0) || !isfinite(l->min_first_frequency_hz))
    return ea_error_set(err, EA_ERR_INPUT,
                        "%slimits.min_first_frequency_Hz = %g: must be a finite number >= 0 "
                        "(0 = off)",
                        pre, l->min_first_frequency_hz);
  if (!(l->max_modal_deflection_m > 0.0))
    return ea_error_set(err, EA_ERR_INPUT,
                        "%slimits.max_modal_deflection_m = %g: must be > 0 (INFINITY = off)", pre,
                        l->max_modal_deflection_m);
  if (!(l->resample_margin >= 0.0 && l->resample_margin <= 0.5))
    return ea_error_set(err, EA_ERR_INPUT, "%slimits.resample_margin = %g: must be in [0, 0.5]",
                        pre, l->resample_margin);
  return EA_OK;
}

/* Resolve a point to actuator coordinates and check it in the workspace. */
static ea_status_t ea__check_point(ea_task_t *t, ea_shooter_t *sh, ea_task_point_t *pt,
                                   const char *what, ea_error_t *err) {
  const ea_arm_t *arm = &t->arm;
  char pre[320];
  ea__pre(pt->where, pre, sizeof pre);
  for (int i = 0; i < 3; ++i)
    if (!isfinite(pt->given[i]))
      return ea_error_set(err, EA_ERR_INPUT, "%s%s: coordinate %d is not finite (or not set)", pre,
                          what, i);
  switch (pt->kind) {
  case EA_TASK_TIP_PLANAR:
    pt->reach = pt->given[0];
    pt->height = pt->given[1];
    pt->base_angle = pt->given[2];
    break;
  case EA_TASK_TIP_3D:
    pt->reach = hypot(pt->given[0], pt->given[1]);
    pt->height = pt->given[2];
    pt->base_angle = pt->reach > 0.0 ? atan2(pt->given[1], pt->given[0]) : 0.0;
    break;
  case EA_TASK_ACTUATORS:
    pt->cable_length = pt->given[0];
    pt->cable_angle = pt->given[1];
    pt->base_angle = pt->given[2];
    pt->reach = arm->x_c + pt->cable_length * cos(pt->cable_angle);
    pt->height = arm->y_c + pt->cable_length * sin(pt->cable_angle);
    break;
  default:
    return ea_error_set(err, EA_ERR_INPUT, "%s%s: unknown point kind", pre, what);
  }
  if (pt->kind != EA_TASK_ACTUATORS) {
    pt->cable_length = hypot(pt->reach - arm->x_c, pt->height - arm->y_c); /* eq. 19 */
    pt->cable_angle = atan2(pt->height - arm->y_c, pt->reach - arm->x_c);  /* eq. 20 */
  }
  const ea_task_limits_t *l = &t->limits;
  const double Lc = pt->cable_length;
  if (!(Lc >= l->cable_length_min) || !(Lc <= l->cable_length_max))
    return ea_error_set(err, EA_ERR_INFEASIBLE,
                        "%s%s: outside the workspace: cable length %.4g m is outside the limits "
                        "[%.4g, %.4g] m (tip reach %.4g m, height %.4g m)",
                        pre, what, Lc, l->cable_length_min, l->cable_length_max, pt->reach,
                        pt->height);
  if (pt->base_angle < arm->act.base_angle_min || pt->base_angle > arm->act.base_angle_max)
    return ea_error_set(err, EA_ERR_INFEASIBLE,
                        "%s%s: base angle %.4g rad is outside the base range [%.4g, %.4g] rad", pre,
                        what, pt->base_angle, arm->act.base_angle_min, arm->act.base_angle_max);
  ea_statics_problem_t prob = ea_statics_problem_cable(Lc, pt->cable_angle);
  ea_statics_settings_t set;
  ea_statics_settings_default(&set);
  set.allow_negative_tension = 1;
  ea_statics_solution_t sol;
  ea_error_t e2 = {0};
  ea_status_t st = ea_statics_solve(sh, &prob, &set, NULL, &sol, &e2);
  if (st)
    return ea_error_set(err, EA_ERR_INFEASIBLE,
                        "%s%s: outside the workspace for payload %.4g kg: no static "
                        "equilibrium at cable length %.4g m, cable angle %.4g rad (%s)",
                        pre, what, t->payload_kg, Lc, pt->cable_angle, e2.msg);
  memcpy(pt->p, sol.p, sizeof pt->p);
  const double T = sol.p[EA_P_TENSION];
  if (T < l->tension_min)
    return ea_error_set(err, EA_ERR_INFEASIBLE,
                        "%s%s: outside the workspace for payload %.4g kg: tension T = %.4g N < "
                        "tension_min %.4g N at tip (%.4g, %.4g) m",
                        pre, what, t->payload_kg, T, l->tension_min, pt->reach, pt->height);
  if (T > l->tension_max)
    return ea_error_set(err, EA_ERR_INFEASIBLE,
                        "%s%s: tension T = %.4g N exceeds tension_max %.4g N at tip (%.4g, "
                        "%.4g) m",
                        pre, what, T, l->tension_max, pt->reach, pt->height);
  const double tau = arm->EI * sol.p[EA_P_KAPPA0];
  if (fabs(tau) > l->shoulder_torque_max)
    return ea_error_set(err, EA_ERR_INFEASIBLE,
                        "%s%s: shoulder torque |EI kappa0| = %.4g N m exceeds %.4g N m", pre, what,
                        fabs(tau), l->shoulder_torque_max);
  const double th0 = sol.p[EA_P_THETA0];
  if (th0 < arm->act.shoulder_angle_min || th0 > arm->act.shoulder_angle_max)
    return ea_error_set(err, EA_ERR_INFEASIBLE,
                        "%s%s: shoulder angle theta0 = %.4g rad is outside [%.4g, %.4g] rad", pre,
                        what, th0, arm->act.shoulder_angle_min, arm->act.shoulder_angle_max);
  return EA_OK;
}

static const char *const ea__refine_names[] = {"newton", "bobyqa", "cobyla", "sbplx"};

const char *ea_task_refine_method_name(ea_task_refine_method_t m) {
  return ((int)m >= 0 && m <= EA_TASK_REFINE_SBPLX) ? ea__refine_names[m] : "unknown";
}

static const char *const ea__refine_by_names[] = {"fe", "model", "model_only"};

const char *ea_task_refine_by_name(ea_task_refine_by_t b) {
  return ((int)b >= 0 && b <= EA_TASK_REFINE_BY_MODEL_ONLY) ? ea__refine_by_names[b] : "unknown";
}

int ea_task_refine_by_from_name(const char *name, ea_task_refine_by_t *b) {
  for (int k = 0; name && k <= EA_TASK_REFINE_BY_MODEL_ONLY; ++k)
    if (!strcmp(name, ea__refine_by_names[k])) {
      *b = (ea_task_refine_by_t)k;
      return 0;
    }
  return -1;
}

void ea_task_refine_default(ea_task_refine_t *r) {
  memset(r, 0, sizeof *r);
  r->method = EA_TASK_REFINE_NEWTON;
  r->tolerance_m = 5e-5;
  r->max_evaluations = 20;
  r->max_time_s = 10.0;
  r->modes = 0; /* every mode */
  r->fe_dt_s = 4e-3;
  r->settle_s = 1.5;
  r->max_duration_change = 0.25;
  r->seed = 1;
}

/* dynamics.refine: only for a plan that ends at rest in the reduced model. */
static ea_status_t ea__check_refine(const ea_task_t *t, ea_error_t *err) {
  const ea_task_refine_t *r = &t->dynamics.refine;
  /* what measures the default check's refinement too (plan --refine-by) */
  if ((int)r->by < 0 || r->by > EA_TASK_REFINE_BY_MODEL_ONLY)
    return ea_error_set(err, EA_ERR_INPUT, "dynamics.refine: unknown 'by' %d", (int)r->by);
  if (r->by != EA_TASK_REFINE_BY_FE && t->dynamics.modes > 0 &&
      (t->dynamics.modes != EA_ROMNL_MODES || t->dynamics.robust_tip_mass > 0.0 ||
       t->dynamics.robust_EI > 0.0))
    return ea_error_set(
        err, EA_ERR_INPUT,
        "dynamics.refine.by = %s: the nonlinear reduced model has %d modes and no "
        "robust corners (the task has dynamics.modes = %d%s)",
        ea_task_refine_by_name(r->by), EA_ROMNL_MODES, t->dynamics.modes,
        t->dynamics.robust_tip_mass > 0.0 || t->dynamics.robust_EI > 0.0 ? " and robust" : "");
  if (!r->enabled) return EA_OK;
  if (t->dynamics.modes < 1)
    return ea_error_set(err, EA_ERR_INPUT,
                        "dynamics.refine needs the reduced dynamic model: dynamics.modes >= 1 "
                        "(the task has none)");
  if (t->dynamics.residual_m > 0.0)
    return ea_error_set(err, EA_ERR_INPUT,
                        "dynamics.refine sets the refinement of a plan that ends at rest: "
                        "dynamics.residual_m 0 (got %g m; a residual bound is refined to by the "
                        "default FE check)",
                        t->dynamics.residual_m);
  if (t->objective == EA_TASK_MIN_VIBRATION)
    return ea_error_set(err, EA_ERR_INPUT,
                        "dynamics.refine is not for objective min_vibration (its plan does not "
                        "end at rest in the model)");
  if ((int)r->method < 0 || r->method > EA_TASK_REFINE_SBPLX)
    return ea_error_set(err, EA_ERR_INPUT, "dynamics.refine: unknown method %d", (int)r->method);
  if (r->modes < 0 || r->modes > t->dynamics.modes)
    return ea_error_set(err, EA_ERR_INPUT,
                        "dynamics.refine.modes = %d: must be in [0 (every mode), dynamics.modes = "
                        "%d]",
                        r->modes, t->dynamics.modes);
  if (!(r->tolerance_m > 0.0 && r->tolerance_m <= 1.0))
    return ea_error_set(err, EA_ERR_INPUT, "dynamics.refine.tolerance_m = %g: must be in (0, 1] m",
                        r->tolerance_m);
  if (r->max_evaluations < 1 || r->max_evaluations > EA_TASK_REFINE_MAX_EVALUATIONS)
    return ea_error_set(err, EA_ERR_INPUT,
                        "dynamics.refine.max_evaluations = %d: must be in [1, %d]",
                        r->max_evaluations, EA_TASK_REFINE_MAX_EVALUATIONS);
  if (!(r->max_time_s > 0.0 && r->max_time_s <= 1e5))
    return ea_error_set(err, EA_ERR_INPUT, "dynamics.refine.max_time_s = %g: must be in (0, 1e5] s",
                        r->max_time_s);
  if (!(r->fe_dt_s >= 1e-5 && r->fe_dt_s <= 1e-2))
    return ea_error_set(err, EA_ERR_INPUT,
                        "dynamics.refine.fe_dt_s = %g: must be in [1e-5, 1e-2] s", r->fe_dt_s);
  if (!(r->settle_s >= 0.5 && r->settle_s <= 100.0))
    return ea_error_set(err, EA_ERR_INPUT, "dynamics.refine.settle_s = %g: must be in [0.5, 100] s",
                        r->settle_s);
  if (!(r->max_duration_change >= 0.0 && r->max_duration_change <= 1.0))
    return ea_error_set(err, EA_ERR_INPUT,
                        "dynamics.refine.max_duration_change = %g: must be in [0, 1]",
                        r->max_duration_change);
  return EA_OK;
}

ea_status_t ea_task_check(ea_task_t *t, ea_error_t *err) {
  if (!t) return ea_error_set(err, EA_ERR_ARG, "ea_task_check: NULL task");
  ea_status_t st = ea_arm_validate(&t->arm, err);
  if (st) return st;
  char pre[320];
  if (!(t->payload_kg >= 0.0) || !isfinite(t->payload_kg))
    return ea_error_set(err, EA_ERR_INPUT, "payload %g kg: must be finite and >= 0", t->payload_kg);
  if ((st = ea__check_limits(t, err))) return st;
  if (t->knots < 3 || t->knots > 4000)
    return ea_error_set(err, EA_ERR_INPUT, "knots = %d: must be in [3, 4000]", t->knots);
  if (t->n_via < 0 || t->n_via > EA_TASK_MAX_VIA)
    return ea_error_set(err, EA_ERR_INPUT, "%d via points: at most %d", t->n_via, EA_TASK_MAX_VIA);
  if (t->n_via + 1 > t->knots - 1)
    return ea_error_set(err, EA_ERR_INPUT, "%d via points need more than %d knots", t->n_via,
                        t->knots);
  ea__pre(t->where_objective, pre, sizeof pre);
  if ((int)t->objective < 0 || t->objective > EA_TASK_MIN_VIBRATION)
    return ea_error_set(err, EA_ERR_INPUT, "%sunknown objective", pre);
  if (t->objective != EA_TASK_MIN_VIBRATION && !isnan(t->time_weight))
    return ea_error_set(err, EA_ERR_INPUT,
                        "%stime_weight = %g is only for min_vibration with a free duration", pre,
                        t->time_weight);
  if (t->objective == EA_TASK_MIN_VIBRATION && isnan(t->duration_s)) {
    if (!(t->time_weight > 0.0 && isfinite(t->time_weight)))
      return ea_error_set(err, EA_ERR_INPUT,
                          "%smin_vibration needs either duration_s (fixed time) or a finite "
                          "time_weight > 0 (free time; got %g)",
                          pre, t->time_weight);
  } else if (t->objective == EA_TASK_MIN_VIBRATION && !isnan(t->time_weight)) {
    return ea_error_set(err, EA_ERR_INPUT,
                        "%scontradictory objective: min_vibration with both duration_s = %g "
                        "and time_weight = %g",
                        pre, t->duration_s, t->time_weight);
  } else if (t->objective == EA_TASK_MIN_TIME && !isnan(t->duration_s))
    return ea_error_set(err, EA_ERR_INPUT,
                        "%scontradictory objective: min_time with a fixed duration_s = %g", pre,
                        t->duration_s);
  if (t->objective != EA_TASK_MIN_TIME && isnan(t->time_weight) &&
      !(t->duration_s > 0.0 && isfinite(t->duration_s)))
    return ea_error_set(err, EA_ERR_INPUT, "%sobjective %s needs a finite duration_s > 0 (got %g)",
                        pre, ea_task_objective_name(t->objective), t->duration_s);
  if ((int)t->path < 0 || t->path > EA_TASK_PATH_POLYLINE)
    return ea_error_set(err, EA_ERR_INPUT, "unknown path type");
  if (t->path == EA_TASK_PATH_LINE && t->n_via > 0)
    return ea_error_set(err, EA_ERR_INPUT,
                        "path 'line' goes straight from start to goal: use 'polyline' with via "
                        "points");
  if ((st = ea_planner_settings_validate(&t->solver, err))) return st;
  if ((st = ea__check_refine(t, err))) return st;

  ea_shooter_t *sh = NULL;
  if ((st = ea_shooter_alloc(&t->arm, NULL, &sh, err))) return st;
  ea_load_t load = {ea_arm_tip_mass(&t->arm, t->payload_kg)};
  ea_shooter_set_load(sh, &load);
  st = ea__check_point(t, sh, &t->start, "start", err);
  for (int i = 0; !st && i < t->n_via; ++i) {
    char what[32];
    snprintf(what, sizeof what, "via[%d]", i);
    st = ea__check_point(t, sh, &t->via[i], what, err);
  }
  if (!st) st = ea__check_point(t, sh, &t->goal, "goal", err);
  ea_shooter_free(sh);
  if (st) return st;
  t->base_moves = 0;
  for (int i = 0; i < t->n_via; ++i)
    if (t->via[i].base_angle != t->start.base_angle) t->base_moves = 1;
  if (t->goal.base_angle != t->start.base_angle) t->base_moves = 1;
  const double d = fabs(t->goal.cable_length - t->start.cable_length) +
                   fabs(t->goal.cable_angle - t->start.cable_angle) +
                   fabs(t->goal.base_angle - t->start.base_angle);
  if (d == 0.0 && t->n_via == 0 && t->objective == EA_TASK_MIN_TIME)
    return ea_error_set(err, EA_ERR_INPUT, "start and goal are the same point: nothing to plan");
  return EA_OK;
}

const char *ea_task_output_path(const ea_task_t *t, const char *rel, char *buf, size_t len) {
  if (!rel || !rel[0]) return NULL;
  const char *slash = strrchr(t->file, '/');
  if (rel[0] == '/' || !slash || !strcmp(rel, "-"))
    snprintf(buf, len, "%s", rel);
  else
    snprintf(buf, len, "%.*s/%s", (int)(slash - t->file), t->file, rel);
  return buf;
}
