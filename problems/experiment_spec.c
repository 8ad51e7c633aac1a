/* Identification experiments (ea_experiment.h, docs/calibration.md "The experiment"):
 * the spec, its YAML form, and its configurations resolved against the workspace. */
#include "ea_arm_file.h"
#include "ea_experiment.h"
#include "ea_fe.h"
#include "ea_workspace.h"
#include "yaml_impl.h"

#include <math.h>
#include <string.h>

void ea_experiment_spec_init(ea_experiment_spec_t *s, const ea_arm_t *arm) {
  memset(s, 0, sizeof *s);
  if (arm)
    s->arm = *arm;
  else
    ea_arm_default(&s->arm);
  snprintf(s->name, sizeof s->name, "experiment");
  s->angle_kind = EA_EXPERIMENT_CABLE_ANGLE;
  s->n_payload = 1;
  s->payload_kg[0] = 0.0;
  s->hold_s = NAN;
  s->hold_time_constants = 3.0;
  s->hold_min_s = 2.0;
  s->hold_max_s = 30.0;
  s->assumed_damping_ratio = 0.02;
  s->knots = 40;
  s->transition_s = 0.01;
  s->resample_margin = 0.25;
}

static ea_status_t ea__list_check(const char *key, const double *v, int n, double lo, double hi,
                                  ea_error_t *err) {
  if (n < 1 || n > EA_EXPERIMENT_MAX_VALUES)
    return ea_error_set(err, EA_ERR_INPUT, "%s: %d values: must be 1..%d", key, n,
                        EA_EXPERIMENT_MAX_VALUES);
  for (int i = 0; i < n; ++i)
    if (!(v[i] >= lo && v[i] <= hi))
      return ea_error_set(err, EA_ERR_INPUT, "%s[%d] = %g: must be in [%g, %g]", key, i, v[i], lo,
                          hi);
  return EA_OK;
}

ea_status_t ea_experiment_spec_check(const ea_experiment_spec_t *s, ea_error_t *err) {
  if (!s) return ea_error_set(err, EA_ERR_ARG, "experiment spec is NULL");
  ea_status_t st = ea_arm_validate(&s->arm, err);
  if (st) return st;
  if ((st = ea__list_check("cable_lengths_m", s->cable_length, s->n_cable_length, 1e-6, 100.0,
                           err)) ||
      (st = ea__list_check(s->angle_kind == EA_EXPERIMENT_THETA0 ? "shoulder_angles_rad"
                                                                 : "cable_angles_rad",
                           s->angle, s->n_angle, -2 * M_PI, 2 * M_PI, err)) ||
      (st = ea__list_check("payloads_kg", s->payload_kg, s->n_payload, 0.0, 1000.0, err)))
    return st;
  if (!isnan(s->hold_s) && !(s->hold_s >= 0.1 && s->hold_s <= 3600))
    return ea_error_set(err, EA_ERR_INPUT, "hold_s = %g: must be in [0.1, 3600] s", s->hold_s);
  if (!(s->hold_time_constants > 0 && s->hold_time_constants <= 100))
    return ea_error_set(err, EA_ERR_INPUT, "hold_time_constants = %g: must be in (0, 100]",
                        s->hold_time_constants);
  if (!(s->hold_min_s >= 0.1 && s->hold_min_s <= s->hold_max_s && s->hold_max_s <= 3600))
    return ea_error_set(err, EA_ERR_INPUT,
                        "hold_min_s = %g, hold_max_s = %g: must be 0.1 <= min <= max <= 3600 s",
                        s->hold_min_s, s->hold_max_s);
  if (!(s->assumed_damping_ratio > 0 && s->assumed_damping_ratio < 1))
    return ea_error_set(err, EA_ERR_INPUT, "assumed_damping_ratio = %g: must be in (0, 1)",
                        s->assumed_damping_ratio);
  if (s->knots < 5 || s->knots > 1000)
    return ea_error_set(err, EA_ERR_INPUT, "knots = %d: must be in [5, 1000]", s->knots);
  if (!(s->transition_s >= 1e-3 && s->transition_s <= 1.0))
    return ea_error_set(err, EA_ERR_INPUT, "transition_s = %g: must be in [0.001, 1] s",
                        s->transition_s);
  if (!(s->resample_margin >= 0 && s->resample_margin <= 10))
    return ea_error_set(err, EA_ERR_INPUT, "resample_margin = %g: must be in [0, 10]",
                        s->resample_margin);
  return EA_OK;
}

/* A list key: 1..EA_EXPERIMENT_MAX_VALUES numbers in [lo, hi]. */
static ea_status_t ea__ylist(ea__ydoc_t *d, yaml_node_t *root, const char *key, int required,
                             double lo, double hi, double *out, int *n, ea_error_t *err) {
  int cnt = 0;
  yaml_node_t *node = ea__ymap_get(d, root, key);
  if (!node) {
    if (required) return ea__yerr(d, root, err, EA_ERR_INPUT, "key '%s' is required", key);
    return EA_OK;
  }
  ea_status_t st = ea__ymap_vec(d, root, key, 1, -EA_EXPERIMENT_MAX_VALUES, out, &cnt, err);
  if (st) return st;
  for (int i = 0; i < cnt; ++i)
    if (!(out[i] >= lo && out[i] <= hi))
      return ea__yerr(d, node, err, EA_ERR_INPUT, "key '%s': value %d = %g: must be in [%g, %g]",
                      key, i + 1, out[i], lo, hi);
  *n = cnt;
  return EA_OK;
}

static ea_status_t ea__spec_parse(ea__ydoc_t *d, const char *default_arm, int from_file,
                                  ea_experiment_spec_t *s, ea_error_t *err) {
  yaml_node_t *root;
  ea_status_t st = ea__ydoc_root_map(d, &root, err);
  if (st) return st;
  static const char *const keys[] = {"name",
                                     "arm_file",
                                     "cable_lengths_m",
                                     "cable_angles_rad",
                                     "shoulder_angles_rad",
                                     "payloads_kg",
                                     "hold_s",
                                     "hold_time_constants",
                                     "hold_min_s",
                                     "hold_max_s",
                                     "assumed_damping_ratio",
                                     "knots",
                                     "transition_s",
                                     "resample_margin",
                                     NULL};
  if ((st = ea__ymap_check_keys(d, root, keys, "the experiment", err))) return st;
  if ((st = ea__ymap_string(d, root, "name", 0, s->name, sizeof s->name, err))) return st;
  if ((st = ea__ymap_arm_file(d, root, from_file ? s->file : NULL, default_arm, s->arm_file,
                              sizeof s->arm_file, &s->arm, err)))
    return st;
  if ((st = ea__ylist(d, root, "cable_lengths_m", 1, 1e-6, 100.0, s->cable_length,
                      &s->n_cable_length, err)))
    return st;
  yaml_node_t *ca = ea__ymap_get(d, root, "cable_angles_rad"),
              *sa = ea__ymap_get(d, root, "shoulder_angles_rad");
  if (!ca == !sa)
    return ea__yerr(d, ca && sa ? sa : root, err, EA_ERR_INPUT,
                    "give exactly one of 'cable_angles_rad' and 'shoulder_angles_rad'");
  s->angle_kind = sa ? EA_EXPERIMENT_THETA0 : EA_EXPERIMENT_CABLE_ANGLE;
  if ((st = ea__ylist(d, root, sa ? "shoulder_angles_rad" : "cable_angles_rad", 1, -2 * M_PI,
                      2 * M_PI, s->angle, &s->n_angle, err)))
    return st;
  if ((st = ea__ylist(d, root, "payloads_kg", 0, 0.0, 1000.0, s->payload_kg, &s->n_payload, err)))
    return st;
  if ((st = ea__ymap_double(d, root, "hold_s", 0, 0.1, 3600, &s->hold_s, err)) ||
      (st = ea__ymap_double(d, root, "hold_time_constants", 0, 1e-3, 100, &s->hold_time_constants,
                            err)) ||
      (st = ea__ymap_double(d, root, "hold_min_s", 0, 0.1, 3600, &s->hold_min_s, err)) ||
      (st = ea__ymap_double(d, root, "hold_max_s", 0, 0.1, 3600, &s->hold_max_s, err)) ||
      (st = ea__ymap_double(d, root, "assumed_damping_ratio", 0, 1e-6, 0.999,
                            &s->assumed_damping_ratio, err)) ||
      (st = ea__ymap_double(d, root, "transition_s", 0, 1e-3, 1.0, &s->transition_s, err)) ||
      (st = ea__ymap_double(d, root, "resample_margin", 0, 0.0, 10.0, &s->resample_margin, err)))
    return st;
  long knots = s->knots;
  if ((st = ea__ymap_int(d, root, "knots", 0, 5, 1000, &knots, err))) return st;
  s->knots = (int)knots;
  if (s->hold_min_s > s->hold_max_s)
    return ea__yerr(
        d, ea__ymap_get(d, root, "hold_min_s") ? ea__ymap_get(d, root, "hold_min_s") : root, err,
        EA_ERR_INPUT, "hold_min_s = %g is above hold_max_s = %g", s->hold_min_s, s->hold_max_s);
  return ea_experiment_spec_check(s, err);
}

static ea_status_t ea__spec_load(const char *path, const char *text, size_t len,
                                 const char *default_arm, ea_experiment_spec_t *s,
                                 ea_error_t *err) {
  if (!path || !s) return ea_error_set(err, EA_ERR_ARG, "experiment spec: NULL argument");
  ea_experiment_spec_init(s, NULL);
  if (!text) snprintf(s->file, sizeof s->file, "%s", path);
  ea__ydoc_t d;
  ea_status_t st = ea__ydoc_load(&d, path, text, len, err);
  if (!st) st = ea__spec_parse(&d, default_arm, text == NULL, s, err);
  ea__ydoc_free(&d);
  return st;
}

ea_status_t ea_experiment_spec_load(const char *path, const char *default_arm,
                                    ea_experiment_spec_t *s, ea_error_t *err) {
  return ea__spec_load(path, NULL, 0, default_arm, s, err);
}

ea_status_t ea_experiment_spec_load_string(const char *name, const char *text, size_t len,
                                           const char *default_arm, ea_experiment_spec_t *s,
                                           ea_error_t *err) {
  if (!text) return ea_error_set(err, EA_ERR_ARG, "experiment spec: NULL text");
  return ea__spec_load(name, text, len, default_arm, s, err);
}

/* Resolve one configuration: statics, limits, FE frequency; sets feasible or the note. */
static void ea__config_resolve(const ea_experiment_spec_t *s, ea_shooter_t *sh, ea_fe_model_t *m,
                               ea_experiment_config_t *c, double angle) {
  const ea_actuators_t *a = &s->arm.act;
  const double L = c->cable_length;
  const int by_theta0 = s->angle_kind == EA_EXPERIMENT_THETA0;
  ea_statics_problem_t pr = ea_statics_problem_cable(L, angle);
  if (by_theta0) {
    pr.given[0] = EA_GIVEN_CABLE_LENGTH;
    pr.value[0] = L;
    pr.given[1] = EA_GIVEN_THETA0;
    pr.value[1] = angle;
  }
  const char *what = by_theta0 ? "theta0" : "alpha";
  ea_statics_solution_t sol;
  ea_error_t e = {0};
  if (ea_statics_solve(sh, &pr, NULL, NULL, &sol, &e) != EA_OK) {
    snprintf(c->note, sizeof c->note,
             "L_c = %g m, %s = %g rad: outside the workspace (no static solution with T >= 0)", L,
             what, angle);
    return;
  }
  memcpy(c->p, sol.p, sizeof c->p);
  memcpy(c->tip_state, sol.tip, sizeof c->tip_state);
  c->cable_angle = sol.p[EA_P_ALPHA];
  c->shoulder_torque = sol.shoulder_torque;
  const double T = sol.p[EA_P_TENSION], th = sol.p[EA_P_THETA0];
  const char *why = NULL;
  double v = 0, b = 0;
  if (T < a->tension_min)
    why = "tension below tension_min", v = T, b = a->tension_min;
  else if (T > a->tension_max)
    why = "tension above tension_max", v = T, b = a->tension_max;
  else if (fabs(sol.shoulder_torque) > a->shoulder_torque_max)
    why = "|shoulder torque| above torque_max", v = sol.shoulder_torque, b = a->shoulder_torque_max;
  else if (L < a->cable_length_min)
    why = "cable length below cable_length_min", v = L, b = a->cable_length_min;
  else if (L > a->cable_length_max)
    why = "cable length above cable_length_max", v = L, b = a->cable_length_max;
  else if (th < a->shoulder_angle_min)
    why = "theta0 below angle_min", v = th, b = a->shoulder_angle_min;
  else if (th > a->shoulder_angle_max)
    why = "theta0 above angle_max", v = th, b = a->shoulder_angle_max;
  if (why) {
    snprintf(c->note, sizeof c->note, "L_c = %g m, %s = %g rad: %s (%g, bound %g)", L, what, angle,
             why, v, b);
    return;
  }
  ea_freq_point_t fp;
  if (ea_freq_point(sh, m, L, c->cable_angle, sol.p, &fp) != EA_OK || fp.modes.modes < 1) {
    snprintf(c->note, sizeof c->note, "L_c = %g m, %s = %g rad: no FE frequency (%s: %.200s)", L,
             what, angle, fp.stage ? fp.stage : "", fp.err.msg);
    return;
  }
  if (!fp.modes.stable || !(fp.modes.lambda[0] > 0)) {
    snprintf(c->note, sizeof c->note, "L_c = %g m, %s = %g rad: not stable (FE)", L, what, angle);
    return;
  }
  c->f1_hz = fp.modes.freq_hz[0];
  c->feasible = 1;
}

ea_status_t ea_experiment_configs(const ea_experiment_spec_t *s, double payload_kg,
                                  ea_experiment_config_t *cfg, int *n_feasible, ea_error_t *err) {
  if (!s || !cfg || !n_feasible) return ea_error_set(err, EA_ERR_ARG, "experiment: NULL argument");
  *n_feasible = 0;
  ea_status_t st = ea_experiment_spec_check(s, err);
  if (st) return st;
  ea_shooter_t *sh = NULL;
  ea_fe_model_t *m = NULL;
  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  fs.static_hold_tip = 1;
  fs.modes = 1;
  const ea_load_t load = {ea_arm_tip_mass(&s->arm, payload_kg)};
  if ((st = ea_shooter_alloc(&s->arm, NULL, &sh, err)) ||
      (st = ea_fe_model_alloc(&s->arm, &fs, &m, err)) || (st = ea_fe_model_set_load(m, &load))) {
    ea_fe_model_free(m);
    ea_shooter_free(sh);
    return st;
  }
  ea_shooter_set_load(sh, &load);
  int k = 0;
  for (int i = 0; i < s->n_cable_length; ++i)
    for (int jj = 0; jj < s->n_angle; ++jj, ++k) {
      const int j = (i % 2) ? s->n_angle - 1 - jj : jj; /* serpentine */
      ea_experiment_config_t *c = &cfg[k];
      memset(c, 0, sizeof *c);
      c->index = i * s->n_angle + j;
      c->cable_length = s->cable_length[i];
      c->cable_angle = c->shoulder_torque = c->f1_hz = NAN;
      for (int q = 0; q < EA_NP; ++q)
        c->p[q] = NAN;
      ea__config_resolve(s, sh, m, c, s->angle[j]);
      *n_feasible += c->feasible;
    }
  ea_fe_model_free(m);
  ea_shooter_free(sh);
  return EA_OK;
}

double ea_experiment_hold_time(const ea_experiment_spec_t *s, double f1_min_hz, double *zeta_used) {
  const double zeta = s->arm.n_damping > 0 && s->arm.damping_ratio[0] > 0
                          ? s->arm.damping_ratio[0]
                          : s->assumed_damping_ratio;
  if (zeta_used) *zeta_used = zeta;
  if (!isnan(s->hold_s)) return s->hold_s;
  if (!(f1_min_hz > 0)) return s->hold_max_s;
  const double h = s->hold_time_constants / (zeta * 2 * M_PI * f1_min_hz);
  return fmin(fmax(h, s->hold_min_s), s->hold_max_s);
}
