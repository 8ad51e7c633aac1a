/* Study specs: grid of payload and arm parameters, metrics and their
 * settings; YAML loading with file:line:column errors (docs/studies.md). */
#include "study_impl.h"
#include "yaml_impl.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** Most cases a study may have. */
#define EA__STUDY_MAX_CASES 10000000L
/** Most values of one axis or torque-map grid. */
#define EA__STUDY_MAX_VALUES 100000

static const char *const ea__param_names[EA_STUDY_NPARAM + 1] = {
    "payload_factor", "payload_kg",     "EI_Nm2", "rho_kg_per_m", "length_m", "hand_mass_kg",
    "cable_root_x_m", "cable_root_y_m", NULL};

const char *ea_study_param_name(ea_study_param_t p) {
  return (p >= 0 && p < EA_STUDY_NPARAM) ? ea__param_names[p] : "unknown";
}

/* ---- building -------------------------------------------------------------- */

void ea_study_init(ea_study_t *s, const ea_arm_t *arm) {
  memset(s, 0, sizeof *s);
  if (arm)
    s->arm = *arm;
  else
    ea_arm_default(&s->arm);
  snprintf(s->name, sizeof s->name, "study");
  s->workspace.alpha_min = -60.0 * EA__DEG;
  s->workspace.alpha_max = 10.0 * EA__DEG;
  s->workspace.points = 71;
  s->workspace.inner_cable_length = 0.0;
  s->workspace.limits = 1;
  s->freq.modes = 3;
  s->freq.elements = EA_FE_DEFAULT_ELEMENTS;
  s->path.steps = 20;
  s->at_rest.modes = 2;
  s->at_rest.elements = EA_FE_DEFAULT_ELEMENTS;
  s->at_rest.dt = 1e-3;
  s->at_rest.settle = 3.0;
  s->at_rest.damping_ratio = 0.0;
}

void ea_study_free(ea_study_t *s) {
  if (!s) return;
  for (int i = 0; i < s->n_axes; ++i) {
    free(s->axis[i].values);
    s->axis[i].values = NULL;
  }
  s->n_axes = 0;
  free(s->torque.cable_length);
  free(s->torque.alpha);
  s->torque.cable_length = s->torque.alpha = NULL;
  s->torque.n_len = s->torque.n_alpha = 0;
}

ea_status_t ea_study_set_axis(ea_study_t *s, ea_study_param_t p, const double *values, int n,
                              ea_error_t *err) {
  if (!s || !values || p < 0 || p >= EA_STUDY_NPARAM || n < 1 || n > EA__STUDY_MAX_VALUES)
    return ea_error_set(err, EA_ERR_ARG, "study axis: bad parameter or %d values", n);
  for (int i = 0; i < n; ++i)
    if (!isfinite(values[i]))
      return ea_error_set(err, EA_ERR_INPUT, "study axis %s: value %d is not finite",
                          ea_study_param_name(p), i + 1);
  double *v = malloc((size_t)n * sizeof *v);
  if (!v) return ea_error_set(err, EA_ERR_NOMEM, "study axis: out of memory");
  memcpy(v, values, (size_t)n * sizeof *v);
  int at = -1;
  for (int i = 0; i < s->n_axes; ++i)
    if (s->axis[i].param == p) at = i;
  if (at >= 0) {
    free(s->axis[at].values);
  } else {
    /* keep the axes in parameter (column) order */
    at = s->n_axes;
    while (at > 0 && s->axis[at - 1].param > p) {
      s->axis[at] = s->axis[at - 1];
      --at;
    }
    ++s->n_axes;
  }
  s->axis[at].param = p;
  s->axis[at].n = n;
  s->axis[at].values = v;
  return EA_OK;
}

void ea_study_case_values(const ea_study_t *s, long case_id, double *values) {
  long r = case_id;
  for (int i = s->n_axes - 1; i >= 0; --i) {
    const long n = s->axis[i].n;
    values[i] = s->axis[i].values[r % n];
    r /= n;
  }
}

ea_status_t ea_study_case_arm(const ea_study_t *s, long case_id, ea_arm_t *arm, double *payload_kg,
                              double *payload_factor, ea_error_t *err) {
  double v[EA_STUDY_NPARAM];
  ea_study_case_values(s, case_id, v);
  *arm = s->arm;
  double gamma = 0.0, kg = NAN;
  for (int i = 0; i < s->n_axes; ++i) {
    switch (s->axis[i].param) {
    case EA_STUDY_PAYLOAD_FACTOR:
      gamma = v[i];
      break;
    case EA_STUDY_PAYLOAD_KG:
      kg = v[i];
      break;
    case EA_STUDY_EI:
      arm->EI = v[i];
      break;
    case EA_STUDY_RHO:
      arm->rho = v[i];
      break;
    case EA_STUDY_LENGTH:
      arm->length = v[i];
      break;
    case EA_STUDY_HAND_MASS:
      arm->m_hand = v[i];
      break;
    case EA_STUDY_CABLE_ROOT_X:
      arm->x_c = v[i];
      break;
    case EA_STUDY_CABLE_ROOT_Y:
      arm->y_c = v[i];
      break;
    default:
      break;
    }
  }
  if (isfinite(kg)) {
    *payload_kg = kg;
    *payload_factor = NAN;
  } else {
    *payload_kg = ea_arm_payload_from_factor(arm, gamma);
    *payload_factor = gamma;
  }
  ea_error_t e = {0};
  ea_status_t st = ea_arm_validate(arm, &e);
  if (st) return ea_error_set(err, st, "case %ld: %s", case_id, e.msg);
  if (!(*payload_kg >= 0))
    return ea_error_set(err, EA_ERR_INPUT, "case %ld: payload %g kg is negative", case_id,
                        *payload_kg);
  return EA_OK;
}

ea_status_t ea_study_check(ea_study_t *s, ea_error_t *err) {
  if (!s) return ea_error_set(err, EA_ERR_ARG, "study: NULL");
  const char *f = s->file[0] ? s->file : "study";
  ea_error_t e = {0};
  if (!s->name[0] || strlen(s->name) > 100 ||
      strspn(s->name, "abcdefghijklmnopqrstuvwxyz"
                      "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
                      "0123456789._-") != strlen(s->name))
    return ea_error_set(err, EA_ERR_INPUT,
                        "%s: study name '%s' must be 1 to 100 letters, digits, '.', '_' or '-' "
                        "(it is a CSV column and the default output file name)",
                        f, s->name);
  ea_status_t st = ea_arm_validate(&s->arm, &e);
  if (st) return ea_error_set(err, st, "%s: arm: %s", f, e.msg);
  int has_g = 0, has_kg = 0;
  long n = 1;
  for (int i = 0; i < s->n_axes; ++i) {
    has_g |= s->axis[i].param == EA_STUDY_PAYLOAD_FACTOR;
    has_kg |= s->axis[i].param == EA_STUDY_PAYLOAD_KG;
    if (s->axis[i].n < 1 || !s->axis[i].values)
      return ea_error_set(err, EA_ERR_INPUT, "%s: grid %s has no values", f,
                          ea_study_param_name(s->axis[i].param));
    if (n > EA__STUDY_MAX_CASES / s->axis[i].n)
      return ea_error_set(err, EA_ERR_INPUT, "%s: the grid has more than %ld cases", f,
                          EA__STUDY_MAX_CASES);
    n *= s->axis[i].n;
  }
  if (has_g && has_kg)
    return ea_error_set(err, EA_ERR_INPUT, "%s: grid: give payload_factor or payload_kg, not both",
                        f);
  if (!s->metrics)
    return ea_error_set(err, EA_ERR_INPUT,
                        "%s: no metrics asked for (workspace, torque_map, "
                        "frequencies, path, min_time, at_rest)",
                        f);
  if (s->metrics & EA_STUDY_M_WORKSPACE) {
    if (!(s->workspace.alpha_min < s->workspace.alpha_max) || s->workspace.points < 2)
      return ea_error_set(err, EA_ERR_INPUT,
                          "%s: workspace: need alpha_min < alpha_max and points >= 2", f);
  }
  if ((s->metrics & EA_STUDY_M_TORQUE) && (s->torque.n_len < 1 || s->torque.n_alpha < 1))
    return ea_error_set(err, EA_ERR_INPUT, "%s: torque_map: empty grid", f);
  if (s->metrics & EA_STUDY_M_FREQUENCIES) {
    if (s->freq.n_config < 1)
      return ea_error_set(err, EA_ERR_INPUT, "%s: frequencies: no configurations", f);
    if (s->freq.modes < 1 || s->freq.modes > EA_FE_MAX_MODES)
      return ea_error_set(err, EA_ERR_INPUT, "%s: frequencies: modes must be in [1, %d]", f,
                          EA_FE_MAX_MODES);
    if (s->freq.elements < 1 || s->freq.elements > 1000)
      return ea_error_set(err, EA_ERR_INPUT, "%s: frequencies: elements must be in [1, 1000]", f);
  }
  if ((s->metrics & EA_STUDY_M_PATH) && s->path.steps < 1)
    return ea_error_set(err, EA_ERR_INPUT, "%s: path: steps must be >= 1", f);
  if ((s->metrics & EA_STUDY_M_MIN_TIME) && !s->min_time.task_file[0])
    return ea_error_set(err, EA_ERR_INPUT, "%s: min_time: no task file", f);
  if (s->metrics & EA_STUDY_M_AT_REST) {
    if (!s->at_rest.task_file[0])
      return ea_error_set(err, EA_ERR_INPUT, "%s: at_rest: no task file", f);
    if (s->at_rest.modes < 1 || s->at_rest.modes > EA_ROM_MAX_MODES)
      return ea_error_set(err, EA_ERR_INPUT, "%s: at_rest: modes %d is outside [1, %d]", f,
                          s->at_rest.modes, EA_ROM_MAX_MODES);
    if (s->at_rest.elements < 1 || s->at_rest.elements > 1000)
      return ea_error_set(err, EA_ERR_INPUT, "%s: at_rest: elements %d is outside [1, 1000]", f,
                          s->at_rest.elements);
    if (!(s->at_rest.dt >= 1e-5 && s->at_rest.dt <= 1e-2))
      return ea_error_set(err, EA_ERR_INPUT, "%s: at_rest: fe_dt_s %g is outside [1e-05, 0.01]", f,
                          s->at_rest.dt);
    if (!(s->at_rest.settle >= 0.5 && s->at_rest.settle <= 100))
      return ea_error_set(err, EA_ERR_INPUT, "%s: at_rest: settle_s %g is outside [0.5, 100]", f,
                          s->at_rest.settle);
    if (!(s->at_rest.damping_ratio >= 0 && s->at_rest.damping_ratio < 1))
      return ea_error_set(err, EA_ERR_INPUT, "%s: at_rest: damping_ratio %g is outside [0, 1)", f,
                          s->at_rest.damping_ratio);
  }
  s->n_cases = n;
  for (long c = 0; c < n; ++c) {
    ea_arm_t a;
    double kg, g;
    if ((st = ea_study_case_arm(s, c, &a, &kg, &g, &e))) {
      double v[EA_STUDY_NPARAM];
      ea_study_case_values(s, c, v);
      char vals[512] = "";
      size_t used = 0;
      for (int i = 0; i < s->n_axes && used < sizeof vals; ++i) {
        int w = snprintf(vals + used, sizeof vals - used, "%s%s = %g", i ? ", " : "",
                         ea_study_param_name(s->axis[i].param), v[i]);
        if (w < 0) break;
        used += (size_t)w;
      }
      return ea_error_set(err, st, "%s: grid point (%s): %s", f, vals, e.msg);
    }
  }
  return EA_OK;
}

size_t ea_study_csv_header(const ea_study_t *s, char *buf, size_t len) {
  ea__sbuf_t b = {0};
  ea__sbuf_printf(&b, "case_id,study,study_key");
  for (int i = 0; i < s->n_axes; ++i)
    ea__sbuf_printf(&b, ",%s", ea_study_param_name(s->axis[i].param));
  ea__sbuf_printf(&b, ",metric,value,unit,status,message\n");
  size_t n = b.oom ? 0 : b.len;
  if (len) snprintf(buf, len, "%s", b.s ? b.s : "");
  ea__sbuf_free(&b);
  return n;
}

static void ea__describe_vec(ea__sbuf_t *b, const char *name, const double *v, int n) {
  ea__sbuf_printf(b, "%s", name);
  for (int i = 0; i < n; ++i)
    ea__sbuf_printf(b, " %.17g", v[i]);
  ea__sbuf_printf(b, "\n");
}

void ea__study_describe(const ea_study_t *s, const ea_study_settings_t *set, ea__sbuf_t *b) {
  const ea_arm_t *a = &s->arm;
  const ea_actuators_t *l = &a->act;
  ea__sbuf_printf(b, "format 2\nname %s\n", s->name);
  ea__describe_vec(b, "arm",
                   (double[]){a->rho, a->m_hand, a->length, a->EI, a->x_c, a->y_c, a->g, a->EA,
                              a->GA_s, a->EA_cable, a->I_zz, a->I_hand},
                   12);
  ea__describe_vec(b, "actuators",
                   (double[]){l->spool_radius, l->spool_gear_ratio, l->spool_zero_length,
                              l->cable_length_min, l->cable_length_max, l->cable_speed_max,
                              l->cable_accel_max, l->tension_max, l->tension_min,
                              l->shoulder_torque_max, l->shoulder_speed_max, l->shoulder_angle_min,
                              l->shoulder_angle_max, l->shoulder_accel_max, l->base_speed_max,
                              l->base_accel_max, l->base_angle_min, l->base_angle_max},
                   18);
  for (int i = 0; i < s->n_axes; ++i)
    ea__describe_vec(b, ea_study_param_name(s->axis[i].param), s->axis[i].values, s->axis[i].n);
  ea__sbuf_printf(b, "metrics %u\n", s->metrics);
  if (s->metrics & EA_STUDY_M_WORKSPACE)
    ea__describe_vec(b, "workspace",
                     (double[]){s->workspace.alpha_min, s->workspace.alpha_max, s->workspace.points,
                                s->workspace.inner_cable_length, s->workspace.limits},
                     5);
  if (s->metrics & EA_STUDY_M_TORQUE) {
    ea__describe_vec(b, "torque_L", s->torque.cable_length, s->torque.n_len);
    ea__describe_vec(b, "torque_alpha", s->torque.alpha, s->torque.n_alpha);
  }
  if (s->metrics & EA_STUDY_M_FREQUENCIES) {
    ea__describe_vec(b, "freq", (double[]){s->freq.modes, s->freq.elements}, 2);
    ea__describe_vec(b, "freq_L", s->freq.cable_length, s->freq.n_config);
    ea__describe_vec(b, "freq_alpha", s->freq.alpha, s->freq.n_config);
  }
  if (s->metrics & EA_STUDY_M_PATH)
    ea__describe_vec(b, "path",
                     (double[]){s->path.start[0], s->path.start[1], s->path.goal[0],
                                s->path.goal[1], s->path.steps},
                     5);
  /* the task by its name as written in the spec (not the resolved path, which
     depends on the working directory) and by its content key */
  if (s->metrics & EA_STUDY_M_MIN_TIME)
    ea__sbuf_printf(b, "min_time %s\nmin_time_key %s\n",
                    s->min_time.task_name[0] ? s->min_time.task_name : s->min_time.task_file,
                    set && set->min_time ? (set->min_time_key ? set->min_time_key : "unknown")
                                         : "no planner");
  if (s->metrics & EA_STUDY_M_AT_REST) {
    ea__sbuf_printf(b, "at_rest %s\nat_rest_key %s\n",
                    s->at_rest.task_name[0] ? s->at_rest.task_name : s->at_rest.task_file,
                    set && set->at_rest ? (set->at_rest_key ? set->at_rest_key : "unknown")
                                        : "no planner");
    ea__describe_vec(b, "at_rest_settings",
                     (double[]){s->at_rest.modes, s->at_rest.elements, s->at_rest.dt,
                                s->at_rest.settle, s->at_rest.damping_ratio},
                     5);
  }
  char hdr[4096];
  const size_t hl = ea_study_csv_header(s, hdr, sizeof hdr);
  ea__sbuf_put(b, hdr, hl < sizeof hdr ? hl : 0);
}

void ea_study_key(const ea_study_t *s, const ea_study_settings_t *set, char key[9]) {
  ea__sbuf_t d = {0};
  ea__study_describe(s, set, &d);
  snprintf(key, 9, "%08x", d.oom ? 0u : (unsigned)ea_crc32(0, d.s, d.len));
  ea__sbuf_free(&d);
}

/* A file's bytes (malloc'd, the shared regular-file reader); NULL on error. */
static char *ea__slurp(const char *path, size_t *len) {
  char *b = NULL;
  return ea__file_read_regular(path, NULL, &b, len, NULL) ? NULL : b;
}

/* Replace a leading "from" in a message position with "to". */
static void ea__rename_where(char *where, size_t len, const char *from, const char *to) {
  const size_t n = strlen(from);
  if (!n || strncmp(where, from, n) || where[n] != ':') return;
  const size_t nt = strlen(to), rest = strlen(where + n);
  if (nt + rest + 1 > len) return; /* does not fit: keep the path */
  memmove(where + nt, where + n, rest + 1);
  memcpy(where, to, nt);
}

ea_status_t ea_study_task_load(const ea_study_t *s, const char *default_arm, ea_task_t *task,
                               char *key, size_t key_len, ea_error_t *err) {
  return ea_study_metric_task_load(s, EA_STUDY_M_MIN_TIME, default_arm, task, key, key_len, err);
}

ea_status_t ea_study_metric_task_load(const ea_study_t *s, unsigned metric, const char *default_arm,
                                      ea_task_t *task, char *key, size_t key_len, ea_error_t *err) {
  if (!s || !task || !key || key_len < 32 ||
      (metric != EA_STUDY_M_MIN_TIME && metric != EA_STUDY_M_AT_REST))
    return ea_error_set(err, EA_ERR_ARG, "study task: bad argument");
  const int rest = metric == EA_STUDY_M_AT_REST;
  const char *label = rest ? "at_rest" : "min_time";
  const char *path = rest ? s->at_rest.task_file : s->min_time.task_file;
  const char *tname = rest ? s->at_rest.task_name : s->min_time.task_name;
  const char *name = tname[0] ? tname : path;
  if (!path[0]) return ea_error_set(err, EA_ERR_INPUT, "%s: no task file", label);
  size_t n0 = 0, n1 = 0, na0 = 0, na1 = 0;
  char *t0 = ea__slurp(path, &n0);
  if (!t0) return ea_error_set(err, EA_ERR_IO, "%s task %s: cannot read it", label, name);
  ea_error_t e = {0};
  ea_status_t st = ea_task_load(path, s->arm_file[0] ? s->arm_file : default_arm, task, &e);
  char *t1 = ea__slurp(path, &n1);
  char *a0 = NULL, *a1 = NULL;
  if (!st && task->arm_file[0]) {
    a0 = ea__slurp(task->arm_file, &na0);
    a1 = ea__slurp(task->arm_file, &na1);
  }
  if (st) {
    /* the message names the task as written in the spec */
    char msg[sizeof e.msg];
    snprintf(msg, sizeof msg, "%s", e.msg);
    ea__rename_where(msg, sizeof msg, path, name);
    st = ea_error_set(err, st, "%s task: %s", label, msg);
  } else if (!t1 || n0 != n1 || memcmp(t0, t1, n0)) {
    st = ea_error_set(err, EA_ERR_IO, "%s task %s changed while it was read", label, name);
  } else if (task->arm_file[0] && (!a0 || !a1 || na0 != na1 || memcmp(a0, a1, na0))) {
    st = ea_error_set(err, EA_ERR_IO,
                      "%s task %s: its arm file cannot be read or changed "
                      "while it was read",
                      label, name);
  } else {
    snprintf(key, key_len, "task=%08x/%zu arm=", (unsigned)ea_crc32(0, t0, n0), n0);
    const size_t used = strlen(key);
    if (a0)
      snprintf(key + used, key_len - used, "%08x/%zu", (unsigned)ea_crc32(0, a0, na0), na0);
    else
      snprintf(key + used, key_len - used, "built-in");
    ea__rename_where(task->start.where, sizeof task->start.where, path, name);
    ea__rename_where(task->goal.where, sizeof task->goal.where, path, name);
    for (int i = 0; i < task->n_via && i < EA_TASK_MAX_VIA; ++i)
      ea__rename_where(task->via[i].where, sizeof task->via[i].where, path, name);
    ea__rename_where(task->where_limits, sizeof task->where_limits, path, name);
    ea__rename_where(task->where_objective, sizeof task->where_objective, path, name);
  }
  free(t0);
  free(t1);
  free(a0);
  free(a1);
  return st;
}

/* ---- YAML ------------------------------------------------------------------ */

/* Numbers of a grid value node: a sequence [a, b, c], a range string
 * "start:step:stop" (step > 0), or a single number. *out malloc'd. */
static ea_status_t ea__grid_values(ea__ydoc_t *d, yaml_node_t *n, const char *key, double lo,
                                   double hi, double scale, double **out, int *count,
                                   ea_error_t *err) {
  *out = NULL;
  *count = 0;
  double *v = NULL;
  int m = 0;
  if (n->type == YAML_SEQUENCE_NODE) {
    m = (int)(n->data.sequence.items.top - n->data.sequence.items.start);
    if (m < 1 || m > EA__STUDY_MAX_VALUES)
      return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s' must list 1 to %d numbers", key,
                      EA__STUDY_MAX_VALUES);
    if (!(v = malloc((size_t)m * sizeof *v)))
      return ea__yerr(d, n, err, EA_ERR_NOMEM, "out of memory");
    for (int i = 0; i < m; ++i) {
      yaml_node_t *it = yaml_document_get_node(&d->doc, n->data.sequence.items.start[i]);
      ea_status_t st = ea__ynode_double(d, it, key, lo, hi, &v[i], err);
      if (st) {
        free(v);
        return st;
      }
    }
  } else {
    const char *t = ea__ynode_text(n);
    if (!t)
      return ea__yerr(d, n, err, EA_ERR_INPUT,
                      "key '%s' must be a list [a, b, ...], a range 'start:step:stop' or a "
                      "number",
                      key);
    double a, step, b;
    char tail;
    if (strchr(t, ':')) {
      if (sscanf(t, "%lf:%lf:%lf%c", &a, &step, &b, &tail) != 3 || !isfinite(a) ||
          !isfinite(step) || !isfinite(b) || !(step > 0) || b < a ||
          (b - a) / step > EA__STUDY_MAX_VALUES - 1)
        return ea__yerr(d, n, err, EA_ERR_INPUT,
                        "key '%s': '%s' is not a range start:step:stop with step > 0, "
                        "start <= stop and at most %d values",
                        key, t, EA__STUDY_MAX_VALUES);
      m = (int)floor((b - a) / step + 1e-9) + 1;
      if (!(v = malloc((size_t)m * sizeof *v)))
        return ea__yerr(d, n, err, EA_ERR_NOMEM, "out of memory");
      for (int i = 0; i < m; ++i) {
        v[i] = a + i * step;
        /* snap values that are round in decimal (0.1 * 3 -> 0.3) */
        const double r = round(v[i] * 1e9) / 1e9;
        if (fabs(r - v[i]) < 1e-12 * fmax(1.0, fabs(v[i]))) v[i] = r;
        if (v[i] < lo || v[i] > hi) {
          free(v);
          return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s': range value %g is outside [%g, %g]",
                          key, a + i * step, lo, hi);
        }
      }
    } else {
      if (!(v = malloc(sizeof *v))) return ea__yerr(d, n, err, EA_ERR_NOMEM, "out of memory");
      m = 1;
      ea_status_t st = ea__ynode_double(d, n, key, lo, hi, &v[0], err);
      if (st) {
        free(v);
        return st;
      }
    }
  }
  for (int i = 0; i < m; ++i)
    v[i] *= scale;
  *out = v;
  *count = m;
  return EA_OK;
}

/* A metric's node: a mapping, or empty (null) for the defaults. */
static ea_status_t ea__metric_node(ea__ydoc_t *d, yaml_node_t *n, const char *key,
                                   yaml_node_t **map, ea_error_t *err) {
  *map = NULL;
  if (n->type == YAML_MAPPING_NODE) {
    *map = n;
    return EA_OK;
  }
  const char *t = ea__ynode_text(n);
  if (t && (!t[0] || !strcmp(t, "~") || !strcmp(t, "null") || !strcmp(t, "{}"))) return EA_OK;
  return ea__yerr(d, n, err, EA_ERR_INPUT,
                  "key '%s' must be a mapping of its settings (or empty for the defaults)", key);
}

/* metrics.at_rest: {task: FILE, modes: K, elements: N, fe_dt_s: DT, settle_s: S,
 * damping_ratio: Z}: every value checked at its position. */
static ea_status_t ea__load_at_rest(ea__ydoc_t *d, yaml_node_t *n, ea_study_t *s, int from_file,
                                    ea_error_t *err) {
  if (n->type != YAML_MAPPING_NODE)
    return ea__yerr(d, n, err, EA_ERR_INPUT,
                    "key 'at_rest' must be a mapping {task: FILE, modes: K, ...}");
  s->metrics |= EA_STUDY_M_AT_REST;
  static const char *const ak[] = {"task",     "modes",         "elements", "fe_dt_s",
                                   "settle_s", "damping_ratio", NULL};
  ea_status_t st = ea__ymap_check_keys(d, n, ak, "metrics.at_rest", err);
  if (st) return st;
  long modes = s->at_rest.modes, el = s->at_rest.elements;
  char rel[512];
  if ((st = ea__ymap_string(d, n, "task", 1, rel, sizeof rel, err)) ||
      (st = ea__ymap_int(d, n, "modes", 0, 1, EA_ROM_MAX_MODES, &modes, err)) ||
      (st = ea__ymap_int(d, n, "elements", 0, 1, 1000, &el, err)) ||
      (st = ea__ymap_double(d, n, "fe_dt_s", 0, 1e-5, 1e-2, &s->at_rest.dt, err)) ||
      (st = ea__ymap_double(d, n, "settle_s", 0, 0.5, 100, &s->at_rest.settle, err)) ||
      (st = ea__ymap_double(d, n, "damping_ratio", 0, 0, 0.999, &s->at_rest.damping_ratio, err)))
    return st;
  s->at_rest.modes = (int)modes;
  s->at_rest.elements = (int)el;
  ea__path_beside(from_file ? s->file : NULL, rel, s->at_rest.task_file,
                  sizeof s->at_rest.task_file);
  snprintf(s->at_rest.task_name, sizeof s->at_rest.task_name, "%s", rel);
  return EA_OK;
}

static ea_status_t ea__load_metrics(ea__ydoc_t *d, yaml_node_t *mm, ea_study_t *s, int from_file,
                                    ea_error_t *err) {
  static const char *const keys[] = {"workspace", "torque_map", "frequencies", "path",
                                     "min_time",  "at_rest",    NULL};
  ea_status_t st = ea__ymap_check_keys(d, mm, keys, "metrics", err);
  if (st) return st;
  yaml_node_t *n, *m;
  if ((n = ea__ymap_get(d, mm, "workspace"))) {
    if ((st = ea__metric_node(d, n, "workspace", &m, err))) return st;
    s->metrics |= EA_STUDY_M_WORKSPACE;
    if (m) {
      static const char *const wk[] = {"alpha_min_deg",        "alpha_max_deg", "points",
                                       "inner_cable_length_m", "limits",        NULL};
      if ((st = ea__ymap_check_keys(d, m, wk, "metrics.workspace", err))) return st;
      double amin = s->workspace.alpha_min / EA__DEG, amax = s->workspace.alpha_max / EA__DEG;
      long pts = s->workspace.points;
      if ((st = ea__ymap_double(d, m, "alpha_min_deg", 0, -180, 180, &amin, err)) ||
          (st = ea__ymap_double(d, m, "alpha_max_deg", 0, -180, 180, &amax, err)) ||
          (st = ea__ymap_int(d, m, "points", 0, 2, 100000, &pts, err)) ||
          (st = ea__ymap_double(d, m, "inner_cable_length_m", 0, 1e-6, 100,
                                &s->workspace.inner_cable_length, err)) ||
          (st = ea__ymap_bool(d, m, "limits", 0, &s->workspace.limits, err)))
        return st;
      if (!(amin < amax))
        return ea__yerr(d, ea__ymap_get(d, m, "alpha_max_deg"), err, EA_ERR_INPUT,
                        "key 'alpha_max_deg': %g must be above alpha_min_deg %g", amax, amin);
      s->workspace.alpha_min = amin * EA__DEG;
      s->workspace.alpha_max = amax * EA__DEG;
      s->workspace.points = (int)pts;
    }
  }
  if ((n = ea__ymap_get(d, mm, "torque_map"))) {
    if ((st = ea__metric_node(d, n, "torque_map", &m, err))) return st;
    s->metrics |= EA_STUDY_M_TORQUE;
    static const char *const tk[] = {"cable_lengths_m", "cable_angles_deg", NULL};
    if (m && (st = ea__ymap_check_keys(d, m, tk, "metrics.torque_map", err))) return st;
    yaml_node_t *ln = m ? ea__ymap_get(d, m, "cable_lengths_m") : NULL;
    yaml_node_t *an = m ? ea__ymap_get(d, m, "cable_angles_deg") : NULL;
    free(s->torque.cable_length);
    free(s->torque.alpha);
    s->torque.cable_length = s->torque.alpha = NULL;
    if (ln) {
      if ((st = ea__grid_values(d, ln, "cable_lengths_m", 1e-6, 100, 1.0, &s->torque.cable_length,
                                &s->torque.n_len, err)))
        return st;
    } else {
      const double lo = s->arm.act.cable_length_min;
      s->torque.n_len = 13;
      if (!(s->torque.cable_length = malloc(13 * sizeof(double))))
        return ea__yerr(d, n, err, EA_ERR_NOMEM, "out of memory");
      for (int i = 0; i < 13; ++i)
        s->torque.cable_length[i] = lo + 0.05 * i;
    }
    if (an) {
      if ((st = ea__grid_values(d, an, "cable_angles_deg", -180, 180, EA__DEG, &s->torque.alpha,
                                &s->torque.n_alpha, err)))
        return st;
    } else {
      s->torque.n_alpha = 8;
      if (!(s->torque.alpha = malloc(8 * sizeof(double))))
        return ea__yerr(d, n, err, EA_ERR_NOMEM, "out of memory");
      for (int i = 0; i < 8; ++i)
        s->torque.alpha[i] = (-60.0 + 10.0 * i) * EA__DEG;
    }
  }
  if ((n = ea__ymap_get(d, mm, "frequencies"))) {
    if (n->type != YAML_MAPPING_NODE)
      return ea__yerr(d, n, err, EA_ERR_INPUT,
                      "key 'frequencies' must be a mapping with 'configurations'");
    s->metrics |= EA_STUDY_M_FREQUENCIES;
    static const char *const fk[] = {"modes", "elements", "configurations", NULL};
    if ((st = ea__ymap_check_keys(d, n, fk, "metrics.frequencies", err))) return st;
    long modes = s->freq.modes, el = s->freq.elements;
    if ((st = ea__ymap_int(d, n, "modes", 0, 1, EA_FE_MAX_MODES, &modes, err)) ||
        (st = ea__ymap_int(d, n, "elements", 0, 1, 1000, &el, err)))
      return st;
    s->freq.modes = (int)modes;
    s->freq.elements = (int)el;
    yaml_node_t *cs;
    if ((st = ea__ymap_seq(d, n, "configurations", 1, &cs, err))) return st;
    const int nc = (int)(cs->data.sequence.items.top - cs->data.sequence.items.start);
    if (nc < 1 || nc > EA_STUDY_MAX_CONFIGS)
      return ea__yerr(d, cs, err, EA_ERR_INPUT,
                      "key 'configurations' must list 1 to %d configurations",
                      EA_STUDY_MAX_CONFIGS);
    for (int i = 0; i < nc; ++i) {
      yaml_node_t *c = yaml_document_get_node(&d->doc, cs->data.sequence.items.start[i]);
      if (c->type != YAML_MAPPING_NODE)
        return ea__yerr(d, c, err, EA_ERR_INPUT,
                        "a configuration must be {cable_length_m: L, cable_angle_deg: A}");
      static const char *const ck[] = {"cable_length_m", "cable_angle_deg", NULL};
      if ((st = ea__ymap_check_keys(d, c, ck, "a frequencies configuration", err))) return st;
      double L, a;
      if ((st = ea__ymap_double(d, c, "cable_length_m", 1, 1e-6, 100, &L, err)) ||
          (st = ea__ymap_double(d, c, "cable_angle_deg", 1, -180, 180, &a, err)))
        return st;
      s->freq.cable_length[i] = L;
      s->freq.alpha[i] = a * EA__DEG;
    }
    s->freq.n_config = nc;
  }
  if ((n = ea__ymap_get(d, mm, "path"))) {
    if (n->type != YAML_MAPPING_NODE)
      return ea__yerr(d, n, err, EA_ERR_INPUT,
                      "key 'path' must be a mapping {start: [x, y], goal: [x, y], steps: N}");
    s->metrics |= EA_STUDY_M_PATH;
    static const char *const pk[] = {"start", "goal", "steps", NULL};
    if ((st = ea__ymap_check_keys(d, n, pk, "metrics.path", err))) return st;
    long steps = s->path.steps;
    if ((st = ea__ymap_vec(d, n, "start", 1, 2, s->path.start, NULL, err)) ||
        (st = ea__ymap_vec(d, n, "goal", 1, 2, s->path.goal, NULL, err)) ||
        (st = ea__ymap_int(d, n, "steps", 0, 1, 100000, &steps, err)))
      return st;
    s->path.steps = (int)steps;
  }
  if ((n = ea__ymap_get(d, mm, "min_time"))) {
    if (n->type != YAML_MAPPING_NODE)
      return ea__yerr(d, n, err, EA_ERR_INPUT, "key 'min_time' must be a mapping {task: FILE}");
    s->metrics |= EA_STUDY_M_MIN_TIME;
    static const char *const mk[] = {"task", NULL};
    if ((st = ea__ymap_check_keys(d, n, mk, "metrics.min_time", err))) return st;
    char rel[512];
    if ((st = ea__ymap_string(d, n, "task", 1, rel, sizeof rel, err))) return st;
    ea__path_beside(from_file ? s->file : NULL, rel, s->min_time.task_file,
                    sizeof s->min_time.task_file);
    snprintf(s->min_time.task_name, sizeof s->min_time.task_name, "%s", rel);
  }
  if ((n = ea__ymap_get(d, mm, "at_rest")) && (st = ea__load_at_rest(d, n, s, from_file, err)))
    return st;
  return EA_OK;
}

static ea_status_t ea__study_parse(ea__ydoc_t *d, const char *default_arm, ea_study_t *s,
                                   int from_file, ea_error_t *err) {
  yaml_node_t *root;
  ea_status_t st = ea__ydoc_root_map(d, &root, err);
  if (st) return st;
  static const char *const keys[] = {"name", "arm_file", "grid", "metrics", "outputs", NULL};
  if ((st = ea__ymap_check_keys(d, root, keys, "the study", err))) return st;
  if ((st = ea__ymap_string(d, root, "name", 0, s->name, sizeof s->name, err))) return st;
  if ((st = ea__ymap_arm_file(d, root, from_file ? s->file : NULL, default_arm, s->arm_file,
                              sizeof s->arm_file, &s->arm, err)))
    return st;
  yaml_node_t *g;
  if ((st = ea__ymap_map(d, root, "grid", 1, &g, err))) return st;
  if ((st = ea__ymap_check_keys(d, g, ea__param_names, "grid", err))) return st;
  static const double lo[EA_STUDY_NPARAM] = {0, 0, 1e-9, 1e-9, 1e-6, 0, -100, -100};
  static const double hi[EA_STUDY_NPARAM] = {100, 1000, 1e9, 1e6, 100, 1000, 100, 100};
  for (int p = 0; p < EA_STUDY_NPARAM; ++p) {
    yaml_node_t *n = ea__ymap_get(d, g, ea__param_names[p]);
    if (!n) continue;
    double *v;
    int m;
    if ((st = ea__grid_values(d, n, ea__param_names[p], lo[p], hi[p], 1.0, &v, &m, err))) return st;
    st = ea_study_set_axis(s, (ea_study_param_t)p, v, m, err);
    free(v);
    if (st) return st;
  }
  if (ea__ymap_get(d, g, "payload_factor") && ea__ymap_get(d, g, "payload_kg"))
    return ea__yerr(d, ea__ymap_get(d, g, "payload_kg"), err, EA_ERR_INPUT,
                    "key 'payload_kg': give payload_factor or payload_kg, not both");
  yaml_node_t *mm;
  if ((st = ea__ymap_map(d, root, "metrics", 1, &mm, err))) return st;
  if ((st = ea__load_metrics(d, mm, s, from_file, err))) return st;
  if (!s->metrics)
    return ea__yerr(d, mm, err, EA_ERR_INPUT,
                    "key 'metrics': ask for at least one of workspace, torque_map, "
                    "frequencies, path, min_time, at_rest");
  yaml_node_t *o;
  if ((st = ea__ymap_map(d, root, "outputs", 0, &o, err))) return st;
  if (o) {
    static const char *const ok[] = {"csv", "summary", "figures", NULL};
    if ((st = ea__ymap_check_keys(d, o, ok, "outputs", err))) return st;
    char *dst[] = {s->out_csv, s->out_summary, s->out_figures};
    for (int i = 0; i < 3; ++i) {
      char r[512] = "";
      if ((st = ea__ymap_string(d, o, ok[i], 0, r, sizeof r, err))) return st;
      ea__path_beside(from_file ? s->file : NULL, r, dst[i], 512);
    }
  }
  return ea_study_check(s, err);
}

static ea_status_t ea__study_load_any(const char *name, const char *text, size_t len,
                                      const char *default_arm, ea_study_t *s, ea_error_t *err) {
  if (!s || !name) return ea_error_set(err, EA_ERR_ARG, "study load: NULL argument");
  ea_study_init(s, NULL);
  snprintf(s->file, sizeof s->file, "%s", text ? "" : name);
  ea__ydoc_t d;
  ea_status_t st = ea__ydoc_load(&d, name, text, len, err);
  if (!st) st = ea__study_parse(&d, default_arm, s, text == NULL, err);
  ea__ydoc_free(&d);
  if (st) ea_study_free(s);
  return st;
}

ea_status_t ea_study_load(const char *path, const char *default_arm, ea_study_t *s,
                          ea_error_t *err) {
  return ea__study_load_any(path, NULL, 0, default_arm, s, err);
}

ea_status_t ea_study_load_string(const char *name, const char *text, size_t len,
                                 const char *default_arm, ea_study_t *s, ea_error_t *err) {
  if (!text) return ea_error_set(err, EA_ERR_ARG, "study load: NULL text");
  return ea__study_load_any(name, text, len, default_arm, s, err);
}
