/* One case of a study: its arm and payload, then only the metrics asked
 * for, each as tidy CSV rows (case_id, parameters, metric, value, unit,
 * status, message). Everything is allocated per case (shooter, FE model)
 * and solved cold, so a case's rows never depend on which thread ran it or
 * what ran before. */
#include "study_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  ea__sbuf_t *b;
  char prefix[512]; /* "case_id,v1,v2," */
  int failed;
} ea__rows_t;

static void ea__row(ea__rows_t *r, const char *metric, double value, const char *unit,
                    ea_status_t st, const char *msg) {
  ea__sbuf_printf(r->b, "%s%s,", r->prefix, metric);
  if (isfinite(value)) ea__sbuf_printf(r->b, "%.12g", value);
  ea__sbuf_printf(r->b, ",%s,%s,", unit, st == EA_OK ? "ok" : ea_status_name(st));
  ea__sbuf_csv_quote(r->b, msg);
  ea__sbuf_put(r->b, "\n", 1);
  if (st != EA_OK) ++r->failed;
}

/* Where an extremum is attained, for the row's message. */
static void ea__extremum_msg(const ea_workspace_extremum_t *e, char *buf, size_t len) {
  int w = snprintf(buf, len, "at alpha = %.6g deg, L_c = %.6g m, tip (%.6g, %.6g) m, on the %s",
                   e->alpha / EA__DEG, e->cable_length, e->x, e->y, ea_ws_bound_name(e->bound));
  if (w < 0 || (size_t)w >= len) return;
  if (e->bound2)
    w += snprintf(buf + w, len - (size_t)w, " where it meets the %s", ea_ws_bound_name(e->bound2));
  if (w < 0 || (size_t)w >= len) return;
  if (e->at_end)
    snprintf(buf + w, len - (size_t)w, "; at the %s: the range, not the arm, bounds it",
             ea_ws_bound_name(e->at_end));
}

static void ea__eval_workspace(const ea_study_t *s, ea_shooter_t *sh, ea__rows_t *r) {
  ea_workspace_settings_t ws;
  ea_workspace_settings_default(&ws);
  ws.alpha_min = s->workspace.alpha_min;
  ws.alpha_max = s->workspace.alpha_max;
  ws.inner_cable_length = s->workspace.inner_cable_length;
  ws.limits = s->workspace.limits;
  ws.samples = s->workspace.points;
  ea_workspace_metrics_t m;
  ea_error_t e = {0};
  const ea_status_t st = ea_workspace_metrics(sh, &ws, &m, &e);
  if (st) {
    const char *names[] = {"area", "max_reach", "x_max", "y_min"};
    const char *units[] = {"m^2", "m", "m", "m"};
    for (int i = 0; i < 4; ++i)
      ea__row(r, names[i], NAN, units[i], st, e.msg);
    return;
  }
  char msg[600], b[400] = "";
  size_t used = 0;
  for (int k = EA_WS_OUTER; k < EA_WS_ALPHA_MIN && used < sizeof b; ++k)
    if (m.bounds & (1u << k)) {
      const int w = snprintf(b + used, sizeof b - used, "%s%s", used ? ", " : "",
                             ea_ws_bound_name((ea_ws_bound_t)k));
      if (w < 0) break;
      used += (size_t)w;
    }
  snprintf(
      msg, sizeof msg, "alpha %.6g to %.6g deg, %s; bounded by the %s; quadrature error < %.1e m^2",
      ws.alpha_min / EA__DEG, ws.alpha_max / EA__DEG,
      ws.limits ? "within the arm's limits" : "no actuator limits", b, fmax(m.area_error, 1e-15));
  ea__row(r, "area", m.area, "m^2", EA_OK, msg);
  ea__extremum_msg(&m.reach, msg, sizeof msg);
  ea__row(r, "max_reach", m.reach.value, "m", EA_OK, msg);
  ea__extremum_msg(&m.x_max, msg, sizeof msg);
  ea__row(r, "x_max", m.x_max.value, "m", EA_OK, msg);
  ea__extremum_msg(&m.y_min, msg, sizeof msg);
  ea__row(r, "y_min", m.y_min.value, "m", EA_OK, msg);
}

static void ea__eval_torque(const ea_study_t *s, ea_shooter_t *sh, const ea_arm_t *arm,
                            ea__rows_t *r) {
  const int nl = s->torque.n_len, na = s->torque.n_alpha;
  ea_config_point_t *cells = calloc((size_t)nl * na, sizeof *cells);
  static const char *names[] = {"torque_min", "torque_max", "tension_min", "tension_max"};
  static const char *units[] = {"N m", "N m", "N", "N"};
  if (!cells) {
    for (int i = 0; i < 4; ++i)
      ea__row(r, names[i], NAN, units[i], EA_ERR_NOMEM, "out of memory");
    return;
  }
  ea_status_t st =
      ea_torque_map(sh, s->torque.cable_length, nl, s->torque.alpha, na, &arm->act, cells);
  double v[4] = {NAN, NAN, NAN, NAN};
  long inside = 0, adm = 0, nosol = 0;
  for (long c = 0; c < (long)nl * na; ++c) {
    const ea_config_point_t *p = &cells[c];
    if (p->status == EA_ERR_INADMISSIBLE) continue; /* beyond the T = 0 edge */
    if (p->status != EA_OK) {
      ++nosol;
      continue;
    }
    ++inside;
    adm += p->admissible;
    const double q[4] = {p->shoulder_torque, p->shoulder_torque, p->tension, p->tension};
    for (int i = 0; i < 4; ++i)
      v[i] = !isfinite(v[i]) ? q[i] : (i % 2 ? fmax(v[i], q[i]) : fmin(v[i], q[i]));
  }
  char msg[256] = "";
  ea_status_t rs = st;
  if (!st && !inside) {
    rs = EA_ERR_INADMISSIBLE;
    snprintf(msg, sizeof msg, "no cell of the %d x %d grid is inside the workspace", nl, na);
  } else if (!st && nosol) {
    rs = EA_ERR_NOCONV;
    snprintf(msg, sizeof msg, "%ld of %ld cells without a statics solution", nosol, (long)nl * na);
  } else if (st) {
    snprintf(msg, sizeof msg, "torque map failed: %s", ea_strerror(st));
  }
  for (int i = 0; i < 4; ++i)
    ea__row(r, names[i], v[i], units[i], rs, msg);
  ea__row(r, "torque_map_cells_inside", (double)inside, "-", st, st ? msg : "");
  ea__row(r, "torque_map_cells_admissible", (double)adm, "-", st, st ? msg : "");
  free(cells);
}

static void ea__eval_freq(const ea_study_t *s, ea_shooter_t *sh, const ea_arm_t *arm,
                          double tip_mass, ea__rows_t *r) {
  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  fs.modes = s->freq.modes;
  fs.elements = s->freq.elements;
  ea_fe_model_t *m = NULL;
  ea_error_t e = {0};
  ea_status_t mst = ea_fe_model_alloc(arm, &fs, &m, &e);
  if (!mst) {
    ea_load_t ld = {tip_mass};
    mst = ea_fe_model_set_load(m, &ld);
  }
  for (int c = 0; c < s->freq.n_config; ++c) {
    char msg[700] = "", metric[64];
    ea_status_t st = mst;
    ea_freq_point_t pt;
    memset(&pt, 0, sizeof pt);
    const ea_fe_modes_info_t *mi = &pt.modes;
    const double L = s->freq.cable_length[c], a = s->freq.alpha[c];
    if (st) {
      snprintf(msg, sizeof msg, "FE model: %s", e.msg);
    } else {
      st = ea_freq_point(sh, m, L, a, NULL, &pt);
      const char *why = pt.err.msg[0] ? pt.err.msg : ea_strerror(st);
      if (st && !strcmp(pt.stage, "statics")) {
        snprintf(msg, sizeof msg,
                 "configuration %d (L_c = %.4g m, alpha = %.4g deg) has no admissible statics "
                 "solution: %s",
                 c + 1, L, a / EA__DEG, why);
      } else if (st) {
        snprintf(msg, sizeof msg, "configuration %d: FE %s: %s", c + 1,
                 !strcmp(pt.stage, "modes") ? "modes" : "statics", why);
      } else if (mi->modes < s->freq.modes) {
        st = EA_ERR_BACKEND;
        snprintf(msg, sizeof msg, "configuration %d: only %d modes found", c + 1, mi->modes);
      }
    }
    for (int k = 0; k < s->freq.modes; ++k) {
      snprintf(metric, sizeof metric, "frequency_c%d_mode%d", c + 1, k + 1);
      ea__row(r, metric, st ? NAN : mi->freq_hz[k], "Hz", st, msg);
    }
  }
  ea_fe_model_free(m);
}

static void ea__eval_path(const ea_study_t *s, ea_shooter_t *sh, const ea_arm_t *arm,
                          ea__rows_t *r) {
  const int n = s->path.steps + 1;
  ea_config_point_t *pts = calloc((size_t)n, sizeof *pts);
  if (!pts) {
    ea__row(r, "path_admissible", NAN, "-", EA_ERR_NOMEM, "out of memory");
    return;
  }
  ea_status_t st =
      ea_path_check_line(sh, s->path.start, s->path.goal, s->path.steps, &arm->act, pts);
  double tmin = NAN, tq = NAN;
  int bad = -1, nbad = 0;
  for (int k = 0; k < n; ++k) {
    if (!pts[k].admissible) {
      if (bad < 0) bad = k;
      ++nbad;
    }
    if (pts[k].status == EA_OK || pts[k].status == EA_ERR_INADMISSIBLE) {
      if (isfinite(pts[k].tension))
        tmin = isfinite(tmin) ? fmin(tmin, pts[k].tension) : pts[k].tension;
      if (isfinite(pts[k].shoulder_torque))
        tq = isfinite(tq) ? fmax(tq, fabs(pts[k].shoulder_torque)) : fabs(pts[k].shoulder_torque);
    }
  }
  char msg[300] = "";
  if (st == EA_ERR_ARG) {
    ea__row(r, "path_admissible", NAN, "-", st, "bad path");
  } else {
    if (bad >= 0)
      snprintf(msg, sizeof msg, "%d of %d points inadmissible; first at beta = %.4g: %s", nbad, n,
               (double)bad / s->path.steps, pts[bad].reason);
    ea__row(r, "path_admissible", bad < 0 ? 1.0 : 0.0, "-", EA_OK, msg);
  }
  ea__row(r, "path_tension_min", tmin, "N", isfinite(tmin) ? EA_OK : EA_ERR_NOCONV,
          isfinite(tmin) ? "" : "no point of the path solved");
  ea__row(r, "path_torque_max_abs", tq, "N m", isfinite(tq) ? EA_OK : EA_ERR_NOCONV,
          isfinite(tq) ? "" : "no point of the path solved");
  free(pts);
}

/* The at-rest rows: the at-rest plan's duration and FE residual, the quasi-static
 * minimum-time plan's, and the ratio of the durations. */
static void ea__eval_at_rest(const ea_study_t *s, const ea_study_settings_t *set,
                             const ea_arm_t *arm, double kg, double gamma, ea__rows_t *r) {
  static const char *const names[4] = {"at_rest_duration_s", "at_rest_fe_residual_peak_m",
                                       "qs_min_time_s", "qs_fe_residual_peak_m"};
  static const char *const units[4] = {"s", "m", "s", "m"};
  ea_study_at_rest_result_t *res = calloc(1, sizeof *res);
  if (!res) {
    for (int i = 0; i < 4; ++i)
      ea__row(r, names[i], NAN, units[i], EA_ERR_NOMEM, "out of memory");
    ea__row(r, "at_rest_time_ratio", NAN, "-", EA_ERR_NOMEM, "out of memory");
    return;
  }
  if (set && set->at_rest) {
    for (int i = 0; i < 4; ++i)
      res->status[i] = EA_ERR_BACKEND; /* a callback that leaves a value unset */
    set->at_rest(set->at_rest_data, s, arm, kg, gamma, res);
  } else {
    for (int i = 0; i < 4; ++i) {
      res->status[i] = EA_ERR_NOTIMPL;
      snprintf(res->msg[i], sizeof res->msg[i],
               "at_rest needs the planner (run through 'elasticarm study')");
    }
  }
  const double v[4] = {res->duration_s, res->residual_peak_m, res->qs_duration_s,
                       res->qs_residual_peak_m};
  for (int i = 0; i < 4; ++i) {
    res->msg[i][sizeof res->msg[i] - 1] = '\0';
    ea__row(r, names[i], res->status[i] ? NAN : v[i], units[i], res->status[i], res->msg[i]);
  }
  char msg[200] = "at-rest duration / quasi-static minimum time";
  ea_status_t rs = EA_OK;
  if (res->status[0] || res->status[2]) {
    rs = res->status[0] ? res->status[0] : res->status[2];
    snprintf(msg, sizeof msg, "needs both durations: the %s plan failed",
             res->status[0] ? "at-rest" : "quasi-static");
  }
  ea__row(r, "at_rest_time_ratio", rs ? NAN : v[0] / v[2], "-", rs, msg);
  free(res);
}

/* The rows' common prefix "case_id,study,study_key,v1,v2,". */
static void ea__rows_init(ea__rows_t *r, const ea_study_t *s, long case_id, const char *ident,
                          ea__sbuf_t *b) {
  memset(r, 0, sizeof *r);
  r->b = b;
  double v[EA_STUDY_NPARAM];
  ea_study_case_values(s, case_id, v);
  size_t used = (size_t)snprintf(r->prefix, sizeof r->prefix, "%ld,%s,", case_id, ident);
  for (int i = 0; i < s->n_axes && used < sizeof r->prefix; ++i)
    used += (size_t)snprintf(r->prefix + used, sizeof r->prefix - used, "%.10g,", v[i]);
}

int ea__study_case_fail(const ea_study_t *s, long case_id, const char *ident, ea_status_t st,
                        const char *msg, ea__sbuf_t *b) {
  ea__rows_t r;
  ea__rows_init(&r, s, case_id, ident, b);
  ea__row(&r, "case", NAN, "-", st, msg);
  return b->oom ? -1 : r.failed;
}

int ea__study_case_eval(const ea_study_t *s, long case_id, const ea_study_settings_t *set,
                        const char *ident, ea__sbuf_t *b) {
  ea__rows_t r;
  ea__rows_init(&r, s, case_id, ident, b);

  ea_arm_t arm;
  double kg, gamma;
  ea_error_t e = {0};
  ea_status_t st = ea_study_case_arm(s, case_id, &arm, &kg, &gamma, &e);
  ea_shooter_t *sh = NULL;
  if (!st) st = ea_shooter_alloc(&arm, NULL, &sh, &e);
  if (st) {
    ea__row(&r, "case", NAN, "-", st, e.msg);
    return b->oom ? -1 : r.failed;
  }
  const double tip_mass = ea_arm_tip_mass(&arm, kg);
  ea_load_t load = {tip_mass};
  ea_shooter_set_load(sh, &load);
  if (s->metrics & EA_STUDY_M_WORKSPACE) ea__eval_workspace(s, sh, &r);
  if (s->metrics & EA_STUDY_M_TORQUE) ea__eval_torque(s, sh, &arm, &r);
  if (s->metrics & EA_STUDY_M_FREQUENCIES) ea__eval_freq(s, sh, &arm, tip_mass, &r);
  if (s->metrics & EA_STUDY_M_PATH) ea__eval_path(s, sh, &arm, &r);
  if (s->metrics & EA_STUDY_M_MIN_TIME) {
    double dur = NAN;
    char msg[512] = "";
    ea_status_t ms = EA_ERR_NOTIMPL;
    if (set && set->min_time)
      ms = set->min_time(set->min_time_data, s, &arm, kg, gamma, &dur, msg, sizeof msg);
    else
      snprintf(msg, sizeof msg, "min_time needs the planner (run through 'elasticarm study')");
    ea__row(&r, "min_time_duration", ms ? NAN : dur, "s", ms, msg);
  }
  if (s->metrics & EA_STUDY_M_AT_REST) ea__eval_at_rest(s, set, &arm, kg, gamma, &r);
  ea_shooter_free(sh);
  return b->oom ? -1 : r.failed;
}

long ea__study_row_case(const char *row, size_t len) {
  long v = 0;
  size_t i = 0;
  if (!len || row[0] < '0' || row[0] > '9') return -1;
  for (; i < len && row[i] >= '0' && row[i] <= '9'; ++i) {
    if (v > 100000000L) return -1;
    v = v * 10 + (row[i] - '0');
  }
  return (i < len && row[i] == ',') ? v : -1;
}
