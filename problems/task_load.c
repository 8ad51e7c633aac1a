/* Task specs: YAML -> ea_task_t with file:line:column in every error
 * (docs/task-format.md). The typed reader is problems/yaml_doc.c. */
#include "ea_arm_file.h"
#include "ea_fe.h"
#include "ea_task.h"
#include "yaml_impl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static ea_status_t ea__load_point(ea__ydoc_t *d, yaml_node_t *n, const char *what,
                                  ea_task_point_t *pt, ea_error_t *err) {
  if (n->type != YAML_MAPPING_NODE)
    return ea__yerr(d, n, err, EA_ERR_INPUT,
                    "%s must be a mapping: {tip: [x, y]} or {tip: [x, y, z]} or "
                    "{cable_length_m: .., cable_angle_rad: .., base_angle_rad: ..}",
                    what);
  static const char *const keys[] = {"tip", "base_angle_rad", "cable_length_m", "cable_angle_rad",
                                     NULL};
  ea_status_t st = ea__ymap_check_keys(d, n, keys, what, err);
  if (st) return st;
  yaml_node_t *tip = ea__ymap_get(d, n, "tip");
  yaml_node_t *lc = ea__ymap_get(d, n, "cable_length_m");
  yaml_node_t *al = ea__ymap_get(d, n, "cable_angle_rad");
  double base = 0.0;
  if ((st = ea__ymap_double(d, n, "base_angle_rad", 0, -4 * M_PI, 4 * M_PI, &base, err))) return st;
  if (tip && (lc || al))
    return ea__yerr(d, n, err, EA_ERR_INPUT,
                    "%s: give either 'tip' or the actuator coordinates (cable_length_m, "
                    "cable_angle_rad), not both",
                    what);
  if (tip) {
    double v[3];
    int cnt = 0;
    if ((st = ea__ymap_vec(d, n, "tip", 1, -3, v, &cnt, err))) return st;
    if (cnt == 2) {
      *pt = ea_task_point_planar(v[0], v[1], base);
    } else if (cnt == 3) {
      if (ea__ymap_get(d, n, "base_angle_rad"))
        return ea__yerr(d, ea__ymap_get(d, n, "base_angle_rad"), err, EA_ERR_INPUT,
                        "%s: key 'base_angle_rad' is not allowed with a 3-D tip [x, y, z] "
                        "(the base angle is atan2(y, x))",
                        what);
      *pt = ea_task_point_3d(v[0], v[1], v[2]);
    } else {
      return ea__yerr(d, tip, err, EA_ERR_INPUT,
                      "%s: key 'tip' must have 2 (planar x, y) or 3 (x, y, z) numbers", what);
    }
  } else {
    double L = NAN, a = NAN;
    if ((st = ea__ymap_double(d, n, "cable_length_m", 1, 1e-9, 100.0, &L, err))) return st;
    if ((st = ea__ymap_double(d, n, "cable_angle_rad", 1, -2 * M_PI, 2 * M_PI, &a, err))) return st;
    *pt = ea_task_point_actuators(L, a, base);
  }
  ea__ynode_where(d, n, pt->where, sizeof pt->where);
  return EA_OK;
}

static ea_status_t ea__load_limits(ea__ydoc_t *d, yaml_node_t *n, ea_task_limits_t *l,
                                   ea_error_t *err) {
  static const char *const keys[] = {"tension_min_N",
                                     "tension_max_N",
                                     "cable_length_min_m",
                                     "cable_length_max_m",
                                     "cable_speed_max_m_per_s",
                                     "cable_accel_max_m_per_s2",
                                     "cable_angle_speed_max_rad_per_s",
                                     "cable_angle_accel_max_rad_per_s2",
                                     "shoulder_torque_max_Nm",
                                     "shoulder_speed_max_rad_per_s",
                                     "base_speed_max_rad_per_s",
                                     "base_accel_max_rad_per_s2",
                                     "min_first_frequency_Hz",
                                     "max_modal_deflection_m",
                                     "resample_margin",
                                     "continuous_acceleration",
                                     NULL};
  double *dst[] = {&l->tension_min,           &l->tension_max,           &l->cable_length_min,
                   &l->cable_length_max,      &l->cable_speed_max,       &l->cable_accel_max,
                   &l->cable_angle_speed_max, &l->cable_angle_accel_max, &l->shoulder_torque_max,
                   &l->shoulder_speed_max,    &l->base_speed_max,        &l->base_accel_max};
  ea_status_t st = ea__ymap_check_keys(d, n, keys, "limits", err);
  if (st) return st;
  for (int i = 0; i < (int)(sizeof dst / sizeof *dst); ++i)
    if ((st = ea__ymap_double(d, n, keys[i], 0, 1e-12, 1e12, dst[i], err))) return st;
  if ((st = ea__ymap_double(d, n, "min_first_frequency_Hz", 0, 0.0, 1e4, &l->min_first_frequency_hz,
                            err)))
    return st;
  if ((st = ea__ymap_double(d, n, "max_modal_deflection_m", 0, 1e-12, 1e3,
                            &l->max_modal_deflection_m, err)))
    return st;
  if ((st = ea__ymap_double(d, n, "resample_margin", 0, 0.0, 0.5, &l->resample_margin, err)))
    return st;
  if ((st = ea__ymap_bool(d, n, "continuous_acceleration", 0, &l->continuous_acceleration, err)))
    return st;
  return EA_OK;
}

static ea_status_t ea__load_solver(ea__ydoc_t *d, yaml_node_t *n, ea_planner_settings_t *s,
                                   ea_error_t *err) {
  static const char *const keys[] = {"max_iter",
                                     "tol",
                                     "constr_viol_tol",
                                     "max_time_s",
                                     "derivative_test",
                                     "print_level",
                                     "regularization",
                                     "hessian",
                                     "transcription",
                                     "screen_rows",
                                     "nlp",
                                     "threads",
                                     NULL};
  ea_status_t st = ea__ymap_check_keys(d, n, keys, "solver", err);
  if (st) return st;
  long v = s->max_iter;
  if ((st = ea__ymap_int(d, n, "max_iter", 0, 1, 100000, &v, err))) return st;
  s->max_iter = (int)v;
  v = s->print_level;
  if ((st = ea__ymap_int(d, n, "print_level", 0, 0, 12, &v, err))) return st;
  s->print_level = (int)v;
  v = s->threads;
  if ((st = ea__ymap_int(d, n, "threads", 0, 0, 2, &v, err))) return st;
  s->threads = (int)v;
  if ((st = ea__ymap_double(d, n, "tol", 0, 1e-14, 1.0, &s->tol, err))) return st;
  if ((st = ea__ymap_double(d, n, "constr_viol_tol", 0, 1e-14, 1.0, &s->constr_tol, err)))
    return st;
  if ((st = ea__ymap_double(d, n, "max_time_s", 0, 1e-3, 1e6, &s->max_time_s, err))) return st;
  if ((st = ea__ymap_double(d, n, "regularization", 0, 0.0, 1e6, &s->regularization, err)))
    return st;
  if ((st = ea__ymap_bool(d, n, "derivative_test", 0, &s->derivative_test, err))) return st;
  if ((st = ea__ymap_bool(d, n, "screen_rows", 0, &s->screen_rows, err))) return st;
  static const char *const hess[] = {"limited-memory", "exact", "partial", NULL};
  int h = s->hessian_exact;
  if ((st = ea__ymap_enum(d, n, "hessian", 0, hess, &h, err))) return st;
  s->hessian_exact = h;
  static const char *const trans[] = {"auto", "knots", "path", NULL};
  int tr = (int)s->transcription;
  if ((st = ea__ymap_enum(d, n, "transcription", 0, trans, &tr, err))) return st;
  s->transcription = (ea_task_transcription_t)tr;
  static const char *const nlp[] = {"auto", "ipopt", NULL};
  int nl = (int)s->engines;
  if ((st = ea__ymap_enum(d, n, "nlp", 0, nlp, &nl, err))) return st;
  s->engines = (ea_planner_engines_t)nl;
  return EA_OK;
}

/* dynamics.refine: true/false, or a mapping of settings (present = enabled). */
static ea_status_t ea__load_refine(ea__ydoc_t *d, yaml_node_t *dyn, ea_task_refine_t *r,
                                   ea_error_t *err) {
  yaml_node_t *n = ea__ymap_get(d, dyn, "refine");
  if (!n) return EA_OK;
  if (n->type == YAML_SCALAR_NODE) return ea__ymap_bool(d, dyn, "refine", 0, &r->enabled, err);
  if (n->type != YAML_MAPPING_NODE)
    return ea__yerr(d, n, err, EA_ERR_INPUT, "key 'refine' must be true, false or a mapping");
  static const char *const keys[] = {
      "method",  "tolerance_m", "max_evaluations",     "max_time_s", "modes",
      "fe_dt_s", "settle_s",    "max_duration_change", "seed",       "by",
      NULL};
  ea_status_t st = ea__ymap_check_keys(d, n, keys, "dynamics.refine", err);
  if (st) return st;
  r->enabled = 1;
  static const char *const methods[] = {"newton", "bobyqa", "cobyla", "sbplx", NULL};
  int m = (int)r->method;
  if ((st = ea__ymap_enum(d, n, "method", 0, methods, &m, err))) return st;
  r->method = (ea_task_refine_method_t)m;
  static const char *const bys[] = {"fe", "model", "model_only", NULL};
  int b = (int)r->by;
  if ((st = ea__ymap_enum(d, n, "by", 0, bys, &b, err))) return st;
  r->by = (ea_task_refine_by_t)b;
  if ((st = ea__ymap_double(d, n, "tolerance_m", 0, 1e-9, 1.0, &r->tolerance_m, err))) return st;
  long v = r->max_evaluations;
  if ((st = ea__ymap_int(d, n, "max_evaluations", 0, 1, EA_TASK_REFINE_MAX_EVALUATIONS, &v, err)))
    return st;
  r->max_evaluations = (int)v;
  if ((st = ea__ymap_double(d, n, "max_time_s", 0, 1e-3, 1e5, &r->max_time_s, err))) return st;
  v = r->modes;
  if ((st = ea__ymap_int(d, n, "modes", 0, 0, EA_ROM_MAX_MODES, &v, err))) return st;
  r->modes = (int)v;
  if ((st = ea__ymap_double(d, n, "fe_dt_s", 0, 1e-5, 1e-2, &r->fe_dt_s, err))) return st;
  if ((st = ea__ymap_double(d, n, "settle_s", 0, 0.5, 100.0, &r->settle_s, err))) return st;
  if ((st =
           ea__ymap_double(d, n, "max_duration_change", 0, 0.0, 1.0, &r->max_duration_change, err)))
    return st;
  v = (long)r->seed;
  if ((st = ea__ymap_int(d, n, "seed", 0, 0, 2147483647L, &v, err))) return st;
  r->seed = (unsigned long)v;
  return EA_OK;
}

/* One parameter of a calibration report (docs/calibration.md, "The report"): its estimate and
 * standard error; se 0 when the caller held it (state "fixed"); an error when the records
 * could not identify it (no standard error to take corners from). */
static ea_status_t ea__report_param(ea__ydoc_t *r, yaml_node_t *params, const char *name,
                                    double *est, double *se, ea_error_t *err) {
  for (yaml_node_item_t *it = params->data.sequence.items.start;
       it < params->data.sequence.items.top; ++it) {
    yaml_node_t *p = yaml_document_get_node(&r->doc, *it);
    if (!p || p->type != YAML_MAPPING_NODE)
      return ea__yerr(r, p ? p : params, err, EA_ERR_INPUT,
                      "'parameters': each entry must be a mapping");
    const char *nm = ea__ynode_text(ea__ymap_get(r, p, "name"));
    if (!nm || strcmp(nm, name)) continue;
    char state[32] = "";
    ea_status_t st = ea__ymap_string(r, p, "state", 1, state, sizeof state, err);
    if (!st) st = ea__ymap_double(r, p, "estimate", 1, 0.0, INFINITY, est, err);
    if (st) return st;
    if (!strcmp(state, "fixed")) {
      *se = 0.0;
      return EA_OK;
    }
    if (strcmp(state, "fitted"))
      return ea__yerr(r, ea__ymap_get(r, p, "state"), err, EA_ERR_INPUT,
                      "parameter %s: state '%s': the records did not identify it, so the report "
                      "has no standard error to take robust corners from (fix it, or give "
                      "dynamics.robust its half-widths)",
                      name, state);
    return ea__ymap_double(r, p, "standard_error", 1, 0.0, INFINITY, se, err);
  }
  return ea__yerr(r, params, err, EA_ERR_INPUT, "'parameters': no parameter '%s'", name);
}

/* dynamics.robust.from_calibration: the corners at +-k standard errors of the report's EI and
 * hand mass, relative to the task's EI and tip mass (hand + payload). The report must be of
 * the task's arm: its estimates are the arm's values. */
static ea_status_t ea__robust_from_calibration(ea__ydoc_t *d, yaml_node_t *rb, ea_task_t *t,
                                               ea_error_t *err) {
  char rel[512] = "", path[1024];
  ea_status_t st = ea__ymap_string(d, rb, "from_calibration", 1, rel, sizeof rel, err);
  if (st) return st;
  double k = 2.0;
  if ((st = ea__ymap_double(d, rb, "k", 0, 0.1, 10.0, &k, err))) return st;
  yaml_node_t *key = ea__ymap_get(d, rb, "from_calibration");
  if (ea__ymap_get(d, rb, "tip_mass") || ea__ymap_get(d, rb, "EI"))
    return ea__yerr(d, key, err, EA_ERR_INPUT,
                    "dynamics.robust: give either 'from_calibration' or 'tip_mass' / 'EI', not "
                    "both");
  ea__path_beside(d->file, rel, path, sizeof path);
  ea__ydoc_t r;
  ea_error_t e2 = {0};
  if ((st = ea__ydoc_load(&r, path, NULL, 0, &e2)))
    return ea__yerr(d, key, err, st, "dynamics.robust.from_calibration: %s", e2.msg);
  yaml_node_t *root = NULL, *params = NULL;
  st = ea__ydoc_root_map(&r, &root, err);
  if (!st && !ea__ymap_get(&r, root, "elasticarm_calibration"))
    st = ea__yerr(&r, root, err, EA_ERR_INPUT,
                  "not a calibration report (no key 'elasticarm_calibration'; "
                  "elasticarm calibrate --report writes one)");
  char status[64] = "";
  if (!st) st = ea__ymap_string(&r, root, "status", 1, status, sizeof status, err);
  if (!st && strcmp(status, "EA_OK"))
    st = ea__yerr(&r, ea__ymap_get(&r, root, "status"), err, EA_ERR_INPUT,
                  "the calibration did not succeed (status %s)", status);
  if (!st) st = ea__ymap_seq(&r, root, "parameters", 1, &params, err);
  double est[2], se[2];
  static const char *const names[2] = {"EI", "m_hand"};
  for (int i = 0; i < 2 && !st; ++i)
    st = ea__report_param(&r, params, names[i], &est[i], &se[i], err);
  const double arm_v[2] = {t->arm.EI, t->arm.m_hand};
  static const char *const units[2] = {"N m^2", "kg"};
  for (int i = 0; i < 2 && !st; ++i)
    if (!(fabs(est[i] - arm_v[i]) <= 1e-9 * fabs(arm_v[i])))
      st = ea__yerr(d, key, err, EA_ERR_INPUT,
                    "dynamics.robust.from_calibration: %s: the report's %s estimate is %.9g %s, "
                    "the task's arm has %.9g %s: plan on the calibrated arm file (arm_file)",
                    path, names[i], est[i], units[i], arm_v[i], units[i]);
  ea__ydoc_free(&r);
  if (st) return st;
  const double eE = k * se[0] / t->arm.EI, em = k * se[1] / (t->arm.m_hand + t->payload_kg);
  if (!(eE <= 0.5) || !(em <= 0.5))
    return ea__yerr(d, key, err, EA_ERR_INPUT,
                    "dynamics.robust.from_calibration: k = %g standard errors give half-widths "
                    "EI %.3g, tip mass %.3g: above the bound 0.5",
                    k, eE, em);
  t->dynamics.robust_EI = eE;
  t->dynamics.robust_tip_mass = em;
  return EA_OK;
}

static ea_status_t ea__load_dynamics(ea__ydoc_t *d, yaml_node_t *n, ea_task_t *t, ea_error_t *err) {
  ea_task_dynamics_t *dy = &t->dynamics;
  static const char *const keys[] = {
      "modes", "residual_m", "max_tip_deviation_m", "grid", "robust", "refine", "verify", NULL};
  ea_status_t st = ea__ymap_check_keys(d, n, keys, "dynamics", err);
  if (st) return st;
  long v = 2;
  if ((st = ea__ymap_int(d, n, "modes", 0, 1, EA_ROM_MAX_MODES, &v, err))) return st;
  dy->modes = (int)v;
  if ((st = ea__ymap_double(d, n, "residual_m", 0, 0.0, 1.0, &dy->residual_m, err))) return st;
  if ((st = ea__ymap_double(d, n, "max_tip_deviation_m", 0, 1e-6, 10.0, &dy->max_tip_deviation_m,
                            err)))
    return st;
  yaml_node_t *rb = NULL;
  if ((st = ea__ymap_map(d, n, "robust", 0, &rb, err))) return st;
  if (rb) {
    static const char *const rkeys[] = {"tip_mass",         "EI", "residual_m",
                                        "from_calibration", "k",  NULL};
    if ((st = ea__ymap_check_keys(d, rb, rkeys, "dynamics.robust", err))) return st;
    if (ea__ymap_get(d, rb, "from_calibration")) {
      if ((st = ea__robust_from_calibration(d, rb, t, err))) return st;
    } else if (ea__ymap_get(d, rb, "k")) {
      return ea__yerr(d, ea__ymap_get(d, rb, "k"), err, EA_ERR_INPUT,
                      "dynamics.robust: 'k' needs 'from_calibration'");
    }
    if ((st = ea__ymap_double(d, rb, "tip_mass", 0, 0.0, 0.5, &dy->robust_tip_mass, err)))
      return st;
    if ((st = ea__ymap_double(d, rb, "EI", 0, 0.0, 0.5, &dy->robust_EI, err))) return st;
    if ((st = ea__ymap_double(d, rb, "residual_m", 0, 1e-6, 1.0, &dy->robust_residual_m, err)))
      return st;
  }
  double gv[2] = {0, 0};
  int have = 0;
  if ((st = ea__ymap_vec(d, n, "grid", 0, 2, gv, &have, err))) return st;
  if (have)
    for (int i = 0; i < 2; ++i) {
      if (!(gv[i] >= 4 && gv[i] <= 64 && gv[i] == floor(gv[i])))
        return ea__yerr(d, ea__ymap_get(d, n, "grid"), err, EA_ERR_INPUT,
                        "key 'grid': %g points: must be a whole number in [4, 64]", gv[i]);
      dy->grid[i] = (int)gv[i];
    }
  if ((st = ea__load_refine(d, n, &dy->refine, err))) return st;
  if ((st = ea__ymap_bool(d, n, "verify", 0, &dy->verify, err))) return st;
  if (dy->refine.enabled && dy->refine.modes > dy->modes)
    return ea__yerr(d, ea__ymap_get(d, n, "refine"), err, EA_ERR_INPUT,
                    "key 'refine': modes = %d: at most dynamics.modes = %d", dy->refine.modes,
                    dy->modes);
  if (dy->refine.enabled && dy->residual_m > 0.0)
    return ea__yerr(d, ea__ymap_get(d, n, "refine"), err, EA_ERR_INPUT,
                    "key 'refine' sets the refinement of a plan that ends at rest: residual_m 0 "
                    "(got %g m; a residual bound is refined to by the default FE check)",
                    dy->residual_m);
  return EA_OK;
}

/* The arm first (the task's arm_file, relative to the task file; else default_arm;
 * else the built-in values): the limits default to its values. Initialises t. */
static ea_status_t ea__task_arm(ea__ydoc_t *d, yaml_node_t *root, const char *default_arm,
                                ea_task_t *t, ea_error_t *err) {
  ea_status_t st;
  char arm_rel[512] = "";
  if ((st = ea__ymap_string(d, root, "arm_file", 0, arm_rel, sizeof arm_rel, err))) return st;
  ea_arm_t arm;
  char arm_path[512] = "";
  if (arm_rel[0]) {
    const char *slash = strrchr(d->file, '/');
    if (arm_rel[0] == '/' || !slash)
      snprintf(arm_path, sizeof arm_path, "%s", arm_rel);
    else
      snprintf(arm_path, sizeof arm_path, "%.*s/%.*s", (int)(slash - d->file), d->file,
               (int)(sizeof arm_path / 2), arm_rel);
  } else if (default_arm) {
    snprintf(arm_path, sizeof arm_path, "%s", default_arm);
  }
  char warning[sizeof t->arm_warning] = "";
  if (arm_path[0]) {
    ea_error_t e2 = {0};
    if ((st = ea_arm_load_warn(arm_path, &arm, warning, sizeof warning, &e2))) {
      yaml_node_t *an = ea__ymap_get(d, root, "arm_file");
      return ea__yerr(d, an ? an : root, err, st, "arm_file: %s", e2.msg);
    }
  } else {
    ea_arm_default(&arm);
  }
  ea_task_init(t, &arm);
  snprintf(t->arm_warning, sizeof t->arm_warning, "%s", warning);
  snprintf(t->arm_file, sizeof t->arm_file, "%s", arm_path);
  snprintf(t->file, sizeof t->file, "%s", d->file);
  ea__ynode_where(d, root, t->where_limits, sizeof t->where_limits);
  ea__ynode_where(d, root, t->where_objective, sizeof t->where_objective);
  const char *base = strrchr(d->file, '/');
  snprintf(t->name, sizeof t->name, "%.100s", base ? base + 1 : d->file);
  char *dot = strrchr(t->name, '.');
  if (dot) *dot = '\0';
  return EA_OK;
}

/* Payload: kg or factor (eq. 17), not both. */
static ea_status_t ea__task_payload(ea__ydoc_t *d, yaml_node_t *root, ea_task_t *t,
                                    ea_error_t *err) {
  ea_status_t st;
  yaml_node_t *pk = ea__ymap_get(d, root, "payload_kg"),
              *pf = ea__ymap_get(d, root, "payload_factor");
  if (pk && pf)
    return ea__yerr(d, pf, err, EA_ERR_INPUT,
                    "give either 'payload_kg' or 'payload_factor', not both");
  if (pk && (st = ea__ymap_double(d, root, "payload_kg", 1, 0.0, 1e3, &t->payload_kg, err)))
    return st;
  if (pf) {
    if ((st = ea__ymap_double(d, root, "payload_factor", 1, 0.0, 100.0, &t->payload_factor, err)))
      return st;
    t->payload_kg = ea_arm_payload_from_factor(&t->arm, t->payload_factor);
  }

  return EA_OK;
}

/* Start, goal and the via points. */
static ea_status_t ea__task_points(ea__ydoc_t *d, yaml_node_t *root, ea_task_t *t,
                                   ea_error_t *err) {
  yaml_node_t *n;
  ea_status_t st;
  if (!(n = ea__ymap_get(d, root, "start")))
    return ea__yerr(d, root, err, EA_ERR_INPUT, "missing required key 'start'");
  if ((st = ea__load_point(d, n, "start", &t->start, err))) return st;
  if (!(n = ea__ymap_get(d, root, "goal")))
    return ea__yerr(d, root, err, EA_ERR_INPUT, "missing required key 'goal'");
  if ((st = ea__load_point(d, n, "goal", &t->goal, err))) return st;
  if ((st = ea__ymap_seq(d, root, "via", 0, &n, err))) return st;
  if (n) {
    const int cnt = (int)(n->data.sequence.items.top - n->data.sequence.items.start);
    if (cnt > EA_TASK_MAX_VIA)
      return ea__yerr(d, n, err, EA_ERR_INPUT, "key 'via': %d points, at most %d", cnt,
                      EA_TASK_MAX_VIA);
    for (int i = 0; i < cnt; ++i) {
      yaml_node_t *it = yaml_document_get_node(&d->doc, n->data.sequence.items.start[i]);
      char what[32];
      snprintf(what, sizeof what, "via[%d]", i);
      if ((st = ea__load_point(d, it, what, &t->via[i], err))) return st;
    }
    t->n_via = cnt;
  }

  return EA_OK;
}

/* The path constraint, consistent with the via points. */
static ea_status_t ea__task_path(ea__ydoc_t *d, yaml_node_t *root, ea_task_t *t, ea_error_t *err) {
  ea_status_t st;
  static const char *const paths[] = {"free", "line", "polyline", NULL};
  int iv = (int)t->path;
  if ((st = ea__ymap_enum(d, root, "path", 0, paths, &iv, err))) return st;
  t->path = (ea_task_path_t)iv;
  if (t->path == EA_TASK_PATH_LINE && t->n_via > 0)
    return ea__yerr(d, ea__ymap_get(d, root, "path"), err, EA_ERR_INPUT,
                    "key 'path': 'line' goes straight from start to goal; with via points use "
                    "'polyline'");
  if (t->path == EA_TASK_PATH_POLYLINE && t->n_via == 0)
    return ea__yerr(d, ea__ymap_get(d, root, "path"), err, EA_ERR_INPUT,
                    "key 'path': 'polyline' needs via points (or use 'line')");

  return EA_OK;
}

/* The objective: a name, or {type, duration_s | time_weight}. */
static ea_status_t ea__task_objective(ea__ydoc_t *d, yaml_node_t *root, ea_task_t *t,
                                      ea_error_t *err) {
  yaml_node_t *n;
  ea_status_t st;
  int iv;
  static const char *const objs[] = {"min_time", "min_effort", "min_jerk", "min_vibration", NULL};
  n = ea__ymap_get(d, root, "objective");
  if (n && n->type == YAML_SCALAR_NODE) {
    iv = 0;
    if ((st = ea__ymap_enum(d, root, "objective", 1, objs, &iv, err))) return st;
    t->objective = (ea_task_objective_t)iv;
  } else if (n) {
    if (n->type != YAML_MAPPING_NODE)
      return ea__yerr(d, n, err, EA_ERR_INPUT,
                      "key 'objective' must be a name or a mapping {type: .., duration_s: ..}");
    static const char *const okeys[] = {"type", "duration_s", "time_weight", NULL};
    if ((st = ea__ymap_check_keys(d, n, okeys, "objective", err))) return st;
    iv = 0;
    if ((st = ea__ymap_enum(d, n, "type", 1, objs, &iv, err))) return st;
    t->objective = (ea_task_objective_t)iv;
    if ((st = ea__ymap_double(d, n, "duration_s", 0, 1e-6, 1e6, &t->duration_s, err))) return st;
    if ((st = ea__ymap_double(d, n, "time_weight", 0, 1e-12, 1e12, &t->time_weight, err)))
      return st;
    yaml_node_t *dn = ea__ymap_get(d, n, "duration_s");
    yaml_node_t *tw = ea__ymap_get(d, n, "time_weight");
    if (tw && t->objective != EA_TASK_MIN_VIBRATION)
      return ea__yerr(d, tw, err, EA_ERR_INPUT,
                      "key 'time_weight': only for type min_vibration (free duration)");
    if (tw && dn)
      return ea__yerr(d, tw, err, EA_ERR_INPUT,
                      "key 'time_weight': contradicts 'duration_s' (give one: fixed or free "
                      "duration)");
    if (dn && t->objective == EA_TASK_MIN_TIME)
      return ea__yerr(d, dn, err, EA_ERR_INPUT,
                      "key 'duration_s': contradicts 'type: min_time' (the duration is what "
                      "is minimised)");
    if (!dn && !tw && t->objective != EA_TASK_MIN_TIME)
      return ea__yerr(d, n, err, EA_ERR_INPUT, "missing required key 'duration_s' for type %s",
                      objs[iv]);
  }
  if (n) ea__ynode_where(d, n, t->where_objective, sizeof t->where_objective);

  return EA_OK;
}

/* solver.transcription: path needs a path the transcription can follow (line, polyline) and
 * no FE frequency model (its rows stay with the knots): asked for where it cannot run, it is
 * refused rather than replaced by the knots without a word. */
static ea_status_t ea__check_transcription(ea__ydoc_t *d, yaml_node_t *solver, const ea_task_t *t,
                                           ea_error_t *err) {
  if (t->solver.transcription != EA_TASK_TRANSCRIPTION_PATH) return EA_OK;
  const char *why = NULL;
  if (t->path == EA_TASK_PATH_FREE)
    why = "the task's path is free (the path coordinate needs path: line or polyline)";
  else if (t->objective == EA_TASK_MIN_VIBRATION && t->dynamics.modes == 0)
    why = "objective min_vibration without dynamics uses the FE frequency model, whose rows "
          "only the knot transcription has";
  else if (t->limits.min_first_frequency_hz > 0.0 || isfinite(t->limits.max_modal_deflection_m))
    why = "limits min_first_frequency_Hz / max_modal_deflection_m use the FE frequency model, "
          "whose rows only the knot transcription has";
  if (!why) return EA_OK;
  return ea__yerr(d, ea__ymap_get(d, solver, "transcription"), err, EA_ERR_INPUT,
                  "key 'transcription': 'path' cannot plan this task: %s; use 'knots' or 'auto'",
                  why);
}

/* Limits, knots, solver, dynamics and outputs. */
static ea_status_t ea__task_settings(ea__ydoc_t *d, yaml_node_t *root, ea_task_t *t,
                                     ea_error_t *err) {
  yaml_node_t *n;
  ea_status_t st;
  if ((st = ea__ymap_map(d, root, "limits", 0, &n, err))) return st;
  if (n) {
    if ((st = ea__load_limits(d, n, &t->limits, err))) return st;
    ea__ynode_where(d, n, t->where_limits, sizeof t->where_limits);
  }
  long k = t->knots;
  if ((st = ea__ymap_int(d, root, "knots", 0, 3, 4000, &k, err))) return st;
  t->knots = (int)k;
  if (t->n_via + 2 > t->knots)
    return ea__yerr(d, ea__ymap_get(d, root, "knots"), err, EA_ERR_INPUT,
                    "key 'knots': %d knots cannot hold %d via points", t->knots, t->n_via);
  yaml_node_t *solver = NULL;
  if ((st = ea__ymap_map(d, root, "solver", 0, &solver, err))) return st;
  if (solver && (st = ea__load_solver(d, solver, &t->solver, err))) return st;
  if ((st = ea__ymap_map(d, root, "dynamics", 0, &n, err))) return st;
  if (n && (st = ea__load_dynamics(d, n, t, err))) return st;
  if (solver && (st = ea__check_transcription(d, solver, t, err))) return st;
  if ((st = ea__ymap_map(d, root, "outputs", 0, &n, err))) return st;
  if (n) {
    static const char *const okeys[] = {"trajectory", "summary", "figure", NULL};
    if ((st = ea__ymap_check_keys(d, n, okeys, "outputs", err))) return st;
    if ((st = ea__ymap_string(d, n, "trajectory", 0, t->out_trajectory, sizeof t->out_trajectory,
                              err)))
      return st;
    if ((st = ea__ymap_string(d, n, "summary", 0, t->out_summary, sizeof t->out_summary, err)))
      return st;
    if ((st = ea__ymap_string(d, n, "figure", 0, t->out_figure, sizeof t->out_figure, err)))
      return st;
    const char *fig = t->out_figure;
    const char *ext = strrchr(fig, '.');
    if (fig[0] && !(ext && (!strcmp(ext, ".svg") || !strcmp(ext, ".png") || !strcmp(ext, ".pdf"))))
      return ea__yerr(d, ea__ymap_get(d, n, "figure"), err, EA_ERR_INPUT,
                      "key 'figure': '%s' must end in .svg, .png or .pdf", fig);
  }
  return EA_OK;
}

static ea_status_t ea__task_from_doc(ea__ydoc_t *d, const char *default_arm, ea_task_t *t,
                                     ea_error_t *err) {
  yaml_node_t *root;
  ea_status_t st = ea__ydoc_root_map(d, &root, err);
  if (st) return st;
  static const char *const top[] = {"name",  "arm_file", "payload_kg", "payload_factor", "start",
                                    "goal",  "via",      "path",       "objective",      "limits",
                                    "knots", "solver",   "outputs",    "dynamics",       NULL};
  if ((st = ea__ymap_check_keys(d, root, top, "the task file", err))) return st;
  if ((st = ea__task_arm(d, root, default_arm, t, err))) return st;
  if ((st = ea__ymap_string(d, root, "name", 0, t->name, sizeof t->name, err))) return st;
  if ((st = ea__task_payload(d, root, t, err)) || (st = ea__task_points(d, root, t, err)) ||
      (st = ea__task_path(d, root, t, err)) || (st = ea__task_objective(d, root, t, err)) ||
      (st = ea__task_settings(d, root, t, err)))
    return st;
  return ea_task_check(t, err);
}

ea_status_t ea_task_load_string(const char *name, const char *text, size_t len,
                                const char *default_arm, ea_task_t *task, ea_error_t *err) {
  if (!text || !task) return ea_error_set(err, EA_ERR_ARG, "ea_task_load_string: NULL argument");
  ea__ydoc_t d;
  ea_status_t st = ea__ydoc_load(&d, name, text, len, err);
  if (!st) st = ea__task_from_doc(&d, default_arm, task, err);
  ea__ydoc_free(&d);
  return st;
}

ea_status_t ea_task_load(const char *path, const char *default_arm, ea_task_t *task,
                         ea_error_t *err) {
  if (!path || !task) return ea_error_set(err, EA_ERR_ARG, "ea_task_load: NULL argument");
  ea__ydoc_t d;
  ea_status_t st = ea__ydoc_load(&d, path, NULL, 0, err);
  if (!st) st = ea__task_from_doc(&d, default_arm, task, err);
  ea__ydoc_free(&d);
  return st;
}
