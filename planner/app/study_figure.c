/* Study results as a table: parsing the tidy CSV, the JSON summary, and the
 * figures (Fig. 3 overlay, each scalar metric against the swept parameter). */
#include "ea_util.h"
#include "ea_problems.h"
#include "figure_impl.h"
#include "study_report_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- parsing ---------------------------------------------------------------- */

static size_t ea__field(const char *p, const char *end, char *buf, size_t len) {
  const char *c = memchr(p, ',', (size_t)(end - p));
  const size_t n = c ? (size_t)(c - p) : (size_t)(end - p);
  snprintf(buf, len, "%.*s", (int)n, p);
  return c ? n + 1 : n;
}

ea_status_t ea__study_table_parse(const char *text, size_t len, const char *name,
                                  ea__study_table_t *t, ea_error_t *err) {
  memset(t, 0, sizeof *t);
  const char *end = text + len;
  const char *e = memchr(text, '\n', len);
  static const char head[] = "case_id,study,study_key,";
  if (!e || strncmp(text, head, sizeof head - 1))
    return ea_error_set(err, EA_ERR_INPUT, "%s:1:1: not a study CSV (no '%s...' header)", name,
                        head);
  int fields = 1;
  for (const char *c = text; c < e; ++c)
    fields += *c == ',';
  t->n_params = fields - 8;
  if (t->n_params < 0 || t->n_params > EA_STUDY_NPARAM)
    return ea_error_set(err, EA_ERR_INPUT, "%s:1:1: unexpected header", name);
  const char *p = text + sizeof head - 1;
  for (int i = 0; i < t->n_params; ++i)
    p += ea__field(p, e, t->params[i], sizeof t->params[i]);
  long nl = 0;
  for (const char *c = e + 1; c < end; ++c)
    nl += *c == '\n';
  t->rows = calloc((size_t)nl + 1, sizeof *t->rows);
  if (!t->rows) return ea_error_set(err, EA_ERR_NOMEM, "out of memory");
  long line = 1;
  for (p = e + 1; p < end;) {
    ++line;
    const char *le = memchr(p, '\n', (size_t)(end - p));
    if (!le) le = end;
    ea__study_row_t *r = &t->rows[t->n_rows];
    char buf[64];
    const char *q = p;
    q += ea__field(q, le, buf, sizeof buf);
    char *x;
    r->case_id = strtol(buf, &x, 10);
    if (x == buf || *x) {
      ea__study_table_free(t);
      return ea_error_set(err, EA_ERR_INPUT, "%s:%ld:1: bad case_id '%s'", name, line, buf);
    }
    char study[128], key[16];
    q += ea__field(q, le, study, sizeof study);
    q += ea__field(q, le, key, sizeof key);
    if (t->n_rows == 0) {
      snprintf(t->study, sizeof t->study, "%s", study);
      snprintf(t->study_key, sizeof t->study_key, "%s", key);
    }
    for (int i = 0; i < t->n_params; ++i) {
      q += ea__field(q, le, buf, sizeof buf);
      r->param[i] = strtod(buf, NULL);
    }
    q += ea__field(q, le, r->metric, sizeof r->metric);
    q += ea__field(q, le, buf, sizeof buf);
    r->value = buf[0] ? strtod(buf, NULL) : NAN;
    q += ea__field(q, le, r->unit, sizeof r->unit);
    q += ea__field(q, le, r->status, sizeof r->status);
    r->ok = !strcmp(r->status, "ok");
    ++t->n_rows;
    p = le + 1;
  }
  return EA_OK;
}

void ea__study_table_free(ea__study_table_t *t) {
  if (!t) return;
  free(t->rows);
  memset(t, 0, sizeof *t);
}

/* Distinct metric names in first-seen order (metrics repeat per case). */
static int ea__metric_names(const ea__study_table_t *t, char (*names)[64], int max) {
  int n = 0;
  for (long i = 0; i < t->n_rows; ++i) {
    int k = 0;
    while (k < n && strcmp(names[k], t->rows[i].metric))
      ++k;
    if (k == n && n < max) snprintf(names[n++], 64, "%s", t->rows[i].metric);
    if (i > 0 && t->rows[i].case_id != t->rows[0].case_id) break; /* first case has them all */
  }
  return n;
}

/* ---- summary ------------------------------------------------------------------ */

ea_status_t ea__study_summary_write(const ea__study_table_t *t, const ea__study_run_facts_t *f,
                                    const char *path, ea_error_t *err) {
  ea_afile_t af;
  ea_status_t st = ea_afile_open(&af, path, err);
  if (st) return st;
  ea_json_t j;
  ea_json_init(&j, af.fp, 1);
  ea_json_obj_begin(&j, NULL);
  if (f && f->name)
    ea_json_str(&j, "study", f->name);
  else if (t->study[0])
    ea_json_str(&j, "study", t->study);
  if (t->study_key[0]) ea_json_str(&j, "study_key", t->study_key);
  if (f && f->spec) ea_json_str(&j, "spec", f->spec);
  if (f && f->csv) ea_json_str(&j, "csv", f->csv);
  long cases = 0, last = -1, failed_cases = 0, failed_rows = 0;
  int case_bad = 0;
  for (long i = 0; i < t->n_rows; ++i) {
    if (t->rows[i].case_id != last) {
      failed_cases += case_bad;
      case_bad = 0;
      ++cases;
      last = t->rows[i].case_id;
    }
    if (!t->rows[i].ok) {
      case_bad = 1;
      ++failed_rows;
    }
  }
  failed_cases += case_bad;
  ea_json_int(&j, "cases", cases);
  ea_json_int(&j, "rows", t->n_rows);
  ea_json_int(&j, "failed_cases", failed_cases);
  ea_json_int(&j, "failed_rows", failed_rows);
  ea_json_arr_begin(&j, "parameters");
  for (int p = 0; p < t->n_params; ++p) {
    ea_json_obj_begin(&j, NULL);
    ea_json_str(&j, "name", t->params[p]);
    /* distinct values, in order of appearance */
    double vals[64];
    int nv = 0, more = 0;
    for (long i = 0; i < t->n_rows; ++i) {
      int k = 0;
      while (k < nv && vals[k] != t->rows[i].param[p])
        ++k;
      if (k == nv) {
        if (nv < 64)
          vals[nv++] = t->rows[i].param[p];
        else
          more = 1;
      }
    }
    ea_json_vec(&j, "values", vals, nv);
    if (more) ea_json_bool(&j, "values_truncated", 1);
    ea_json_obj_end(&j);
  }
  ea_json_arr_end(&j);
  char names[256][64];
  const int nm = ea__metric_names(t, names, 256);
  ea_json_arr_begin(&j, "metrics");
  for (int m = 0; m < nm; ++m) {
    long rows = 0, ok = 0;
    double lo = NAN, hi = NAN;
    const char *unit = "";
    for (long i = 0; i < t->n_rows; ++i) {
      const ea__study_row_t *r = &t->rows[i];
      if (strcmp(r->metric, names[m])) continue;
      ++rows;
      unit = r->unit;
      if (!r->ok) continue;
      ++ok;
      if (isfinite(r->value)) {
        lo = isfinite(lo) ? fmin(lo, r->value) : r->value;
        hi = isfinite(hi) ? fmax(hi, r->value) : r->value;
      }
    }
    ea_json_obj_begin(&j, NULL);
    ea_json_str(&j, "name", names[m]);
    ea_json_str(&j, "unit", unit);
    ea_json_int(&j, "rows", rows);
    ea_json_int(&j, "ok", ok);
    ea_json_int(&j, "failed", rows - ok);
    ea_json_num(&j, "min", lo);
    ea_json_num(&j, "max", hi);
    ea_json_obj_end(&j);
  }
  ea_json_arr_end(&j);
  ea_json_arr_begin(&j, "failed_case_ids");
  last = -1;
  long listed = 0;
  for (long i = 0; i < t->n_rows && listed < 1000; ++i)
    if (!t->rows[i].ok && t->rows[i].case_id != last) {
      ea_json_int(&j, NULL, t->rows[i].case_id);
      last = t->rows[i].case_id;
      ++listed;
    }
  ea_json_arr_end(&j);
  if (f && (f->info || f->merged_inputs)) {
    ea_json_obj_begin(&j, "run");
    if (f->merged_inputs) ea_json_int(&j, "merged_shards", f->merged_inputs);
    if (f->info) {
      ea_json_str(&j, "shard_rule", "case_id % N == K - 1");
      ea_json_int(&j, "shard_k", f->shard_k);
      ea_json_int(&j, "shard_n", f->shard_n);
      ea_json_int(&j, "cases_total", f->info->cases_total);
      ea_json_int(&j, "cases_shard", f->info->cases_shard);
      ea_json_int(&j, "cases_computed", f->info->cases_computed);
      ea_json_int(&j, "cases_skipped_from_checkpoint", f->info->cases_skipped);
      ea_json_int(&j, "threads", f->info->threads);
      ea_json_num(&j, "time_s", f->info->time_s);
    }
    ea_json_obj_end(&j);
  }
  ea_json_obj_end(&j);
  ea_json_end(&j);
  return ea_afile_commit(&af, err);
}

/* ---- figures -------------------------------------------------------------------- */

/* How a parameter is read in a figure: a symbol for the keys ("EI"), a description
 * for an axis ("flexural rigidity EI") and its unit ("" for none), by its CSV column
 * name (ea_study_param_name). An unknown column: its name (escaped), no unit. */
typedef struct {
  const char *symbol, *what, *unit;
} ea__param_label_t;

static ea__param_label_t ea__param_label(const char *column) {
  static const ea__param_label_t known[EA_STUDY_NPARAM] = {
      [EA_STUDY_PAYLOAD_FACTOR] = {"{/Symbol g}", "payload factor {/Symbol g}", ""},
      [EA_STUDY_PAYLOAD_KG] = {"m_p", "payload m_p", "kg"},
      [EA_STUDY_EI] = {"EI", "flexural rigidity EI", "N m^2"},
      [EA_STUDY_RHO] = {"{/Symbol r}", "beam mass per length {/Symbol r}", "kg/m"},
      [EA_STUDY_LENGTH] = {"L", "beam length L", "m"},
      [EA_STUDY_HAND_MASS] = {"m_h", "hand mass m_h", "kg"},
      [EA_STUDY_CABLE_ROOT_X] = {"x_c", "cable root x_c", "m"},
      [EA_STUDY_CABLE_ROOT_Y] = {"y_c", "cable root y_c", "m"},
  };
  for (int p = 0; p < EA_STUDY_NPARAM; ++p)
    if (!strcmp(column, ea_study_param_name((ea_study_param_t)p)) && known[p].symbol)
      return known[p];
  return (ea__param_label_t){NULL, NULL, ""};
}

/* "symbol = value unit" of a parameter (by its column name) into buf at *used. */
static void ea__param_text(const char *column, double v, char *buf, size_t len, size_t *used) {
  const ea__param_label_t l = ea__param_label(column);
  char esc[96];
  if (*used >= len) return;
  const int w = snprintf(buf + *used, len - *used, "%s%s = %g%s%s", *used ? ", " : "",
                         l.symbol ? l.symbol : ea_plot_enh(column, esc, sizeof esc), v,
                         l.unit[0] ? " " : "", l.unit);
  if (w > 0) *used += (size_t)w;
}

/* An axis label "what [unit]" of a parameter column ([-] for a pure number). */
static void ea__param_axis(const char *column, char *buf, size_t len) {
  const ea__param_label_t l = ea__param_label(column);
  char esc[96];
  snprintf(buf, len, "%s [%s]", l.what ? l.what : ea_plot_enh(column, esc, sizeof esc),
           l.unit[0] ? l.unit : "-");
}

/* A metric's description for an axis and a title (without the unit): the known
 * metrics of ea_study_run by name, a natural frequency with its configuration (from
 * the study, when there is one), else the name with spaces for underscores. */
static void ea__metric_text(const ea_study_t *s, const char *metric, char *buf, size_t len) {
  static const char *const known[][2] = {
      {"area", "workspace area"},
      {"max_reach", "farthest reach from the shoulder"},
      {"x_max", "largest tip x in the workspace"},
      {"y_min", "lowest tip y in the workspace"},
      {"torque_min", "lowest shoulder torque over the map"},
      {"torque_max", "highest shoulder torque over the map"},
      {"tension_min", "lowest cable tension over the map"},
      {"tension_max", "highest cable tension over the map"},
      {"path_admissible", "straight path admissible (1 yes, 0 no)"},
      {"path_tension_min", "lowest cable tension along the path"},
      {"path_torque_max_abs", "largest |shoulder torque| along the path"},
      {"min_time_duration", "minimum-time duration"},
  };
  for (size_t i = 0; i < sizeof known / sizeof known[0]; ++i)
    if (!strcmp(metric, known[i][0])) {
      snprintf(buf, len, "%s", known[i][1]);
      return;
    }
  int c, m;
  char tail;
  if (sscanf(metric, "frequency_c%d_mode%d%c", &c, &m, &tail) == 2) {
    if (s && c >= 1 && c <= s->freq.n_config)
      snprintf(buf, len, "frequency of mode %d at L_c = %g m, {/Symbol a} = %g deg", m,
               s->freq.cable_length[c - 1], s->freq.alpha[c - 1] / EA__DEG);
    else
      snprintf(buf, len, "frequency of mode %d at configuration %d", m, c);
    return;
  }
  char esc[160];
  ea_plot_enh(metric, esc, sizeof esc);
  size_t o = 0;
  for (size_t i = 0; esc[i] && o + 1 < len; ++i) {
    if (esc[i] == '\\' && esc[i + 1] == '_') continue; /* "\_" -> " " */
    buf[o++] = esc[i] == '_' ? ' ' : esc[i];
  }
  buf[o] = '\0';
}

/* Key text of a case: every swept parameter with its unit ("{/Symbol g} = 0.25, EI =
 * 0.705 N m^2"); an axis with one value only when it is the only axis. */
static void ea__case_label(const ea_study_t *s, long c, char *buf, size_t len) {
  double v[EA_STUDY_NPARAM];
  ea_study_case_values(s, c, v);
  size_t used = 0;
  buf[0] = '\0';
  for (int i = 0; i < s->n_axes; ++i) {
    if (s->axis[i].n < 2 && s->n_axes > 1) continue;
    ea__param_text(ea_study_param_name(s->axis[i].param), v[i], buf, len, &used);
  }
}

/* The workspace region of every case, closed (outer edge, the sides along the cable,
 * inner edge), each in its own style; with the arm's limits, the outer-edge points
 * past one marked. */
static ea_status_t ea__fig_workspace(const ea_study_t *s, const char *path, ea_error_t *err) {
  const int n = s->workspace.points;
  double *alpha = malloc((size_t)n * sizeof *alpha);
  ea_config_point_t *outer = calloc((size_t)n, sizeof *outer);
  const size_t cap = 2048 + (size_t)s->n_cases * 400;
  char *plot = malloc(cap);
  ea_plot_t *pl = NULL;
  ea_status_t st = EA_OK;
  if (!alpha || !outer || !plot) {
    st = ea_error_set(err, EA_ERR_NOMEM, "figure: out of memory");
    goto out;
  }
  for (int k = 0; k < n; ++k)
    alpha[k] =
        s->workspace.alpha_min + (s->workspace.alpha_max - s->workspace.alpha_min) * k / (n - 1);
  if ((st = ea_plot_open(&pl, path, 1000, 700, err))) goto out;
  size_t used = (size_t)snprintf(plot, cap, "plot ");
  int drawn = 0, marked = 0, roots = 0;
  double root0[2] = {s->arm.x_c, s->arm.y_c};
  for (long c = 0; c < s->n_cases; ++c) {
    ea_arm_t arm;
    double kg, g;
    ea_shooter_t *sh = NULL;
    if (ea_study_case_arm(s, c, &arm, &kg, &g, NULL) || ea_shooter_alloc(&arm, NULL, &sh, NULL))
      continue;
    ea_load_t load = {ea_arm_tip_mass(&arm, kg)};
    ea_shooter_set_load(sh, &load);
    ea_workspace_outer(sh, alpha, n, outer);
    ea_shooter_free(sh);
    const double inner = s->workspace.inner_cable_length > 0 ? s->workspace.inner_cable_length
                                                             : arm.act.cable_length_min;
    char name[32], label[300], style[96];
    snprintf(name, sizeof name, "ws%ld", c);
    if (!ea_plot_region(pl, name, &arm, outer, n, inner)) continue;
    ea__case_label(s, c, label, sizeof label);
    used += (size_t)snprintf(plot + used, cap - used, "%s$%s w l lw 2 %s t '%s'", drawn ? ", " : "",
                             name, ea_plot_style(drawn, 0, style, sizeof style), label);
    if (s->workspace.limits) {
      int past = 0;
      for (int k = 0; k < n; ++k)
        past += outer[k].status == EA_OK && !outer[k].admissible;
      if (past) {
        snprintf(name, sizeof name, "past%ld", c);
        ea_plot_data_begin(pl, name);
        for (int k = 0; k < n; ++k)
          if (outer[k].status == EA_OK && !outer[k].admissible)
            ea_plot_data_row(pl, 2, (double[]){outer[k].x, outer[k].y});
        ea_plot_data_end(pl);
        used += (size_t)snprintf(plot + used, cap - used, ", $%s w p pt 2 ps 0.6 lc rgb '%s' %s",
                                 name, ea_plot_colour(drawn), "notitle");
        ++marked;
      }
    }
    if (arm.x_c != root0[0] || arm.y_c != root0[1]) roots = 1;
    ++drawn;
  }
  if (!drawn) {
    ea_plot_discard(pl);
    pl = NULL;
    st = ea_error_set(err, EA_ERR_NOCONV, "%s: no case has a workspace edge to draw", path);
    goto out;
  }
  ea_plot_data_begin(pl, "root");
  for (long c = 0; c < s->n_cases; ++c) {
    ea_arm_t arm;
    double kg, g;
    if (!ea_study_case_arm(s, c, &arm, &kg, &g, NULL))
      ea_plot_data_row(pl, 2, (double[]){arm.x_c, arm.y_c});
  }
  ea_plot_data_end(pl);
  ea_plot_cmd(pl,
              "set size ratio -1\nset xlabel 'x [m]'\nset ylabel 'y [m]'\nset grid\n"
              "set key outside right top\n"
              "set title \"Workspace regions of %ld case%s%s\\nouter edge (T = 0), inner edge, "
              "sides at {/Symbol a} = %.0f and %.0f deg\\n%s\"",
              s->n_cases, s->n_cases == 1 ? "" : "s",
              drawn > EA_PLOT_NSTYLES ? " (styles repeat after 40)" : "",
              s->workspace.alpha_min / EA__DEG, s->workspace.alpha_max / EA__DEG,
              s->workspace.limits ? (marked ? "the arm's limits cut a region where its outer edge "
                                              "is marked x"
                                            : "the arm's limits hold on every outer edge")
                                  : "without the arm's actuator limits");
  ea_plot_cmd(pl, "%s, $root w p pt 7 ps 1.5 lc rgb '#c0392b' t 'cable root%s'%s", plot,
              roots ? "s" : "",
              marked ? ", NaN w p pt 2 lc rgb 'black' t 'outer edge past an arm limit (x)'" : "");
  st = ea_plot_close(pl, err);
  pl = NULL;
out:
  ea_plot_discard(pl);
  free(alpha);
  free(outer);
  free(plot);
  return st;
}

/* Is row r in group key (every parameter but xp equal)? */
static int ea__in_group(const ea__study_table_t *t, const ea__study_row_t *r, const double *key,
                        int xp) {
  for (int p = 0; p < t->n_params; ++p)
    if (p != xp && key[p] != r->param[p]) return 0;
  return 1;
}

/* One figure per metric: x = the first parameter with more than one value, one
 * curve per combination of the other parameters (every one, each in its own style;
 * the key says which values, with units). */
static ea_status_t ea__fig_metric(const ea_study_t *s, const ea__study_table_t *t,
                                  const char *metric, const char *path, ea_error_t *err) {
  int xp = -1;
  for (int p = 0; p < t->n_params && xp < 0; ++p)
    for (long i = 1; i < t->n_rows; ++i)
      if (t->rows[i].param[p] != t->rows[0].param[p]) {
        xp = p;
        break;
      }
  if (xp < 0) return EA_OK; /* one case: nothing to plot against */
  /* groups: distinct values of the other parameters, in order of appearance */
  double(*key)[EA_STUDY_NPARAM] = malloc((size_t)(t->n_rows + 1) * sizeof *key);
  if (!key) return ea_error_set(err, EA_ERR_NOMEM, "figure: out of memory");
  int ng = 0;
  const char *unit = "";
  for (long i = 0; i < t->n_rows; ++i) {
    const ea__study_row_t *r = &t->rows[i];
    if (strcmp(r->metric, metric)) continue;
    unit = r->unit;
    int g = 0;
    while (g < ng && !ea__in_group(t, r, key[g], xp))
      ++g;
    if (g == ng) memcpy(key[ng++], r->param, sizeof key[0]);
  }
  /* which other parameters vary (those name a curve) */
  int varies[EA_STUDY_NPARAM] = {0};
  for (int g = 1; g < ng; ++g)
    for (int p = 0; p < t->n_params; ++p)
      varies[p] |= p != xp && key[g][p] != key[0][p];
  const size_t cap = 1024 + (size_t)ng * 400;
  char *plot = malloc(cap);
  ea_plot_t *pl = NULL;
  ea_status_t st = plot ? ea_plot_open(&pl, path, 950, 600, err)
                        : ea_error_set(err, EA_ERR_NOMEM, "figure: out of memory");
  if (st) {
    free(plot);
    free(key);
    return st;
  }
  size_t used = (size_t)snprintf(plot, cap, "plot ");
  for (int g = 0; g < ng; ++g) {
    char name[24];
    snprintf(name, sizeof name, "m%d", g);
    ea_plot_data_begin(pl, name);
    for (long i = 0; i < t->n_rows; ++i) {
      const ea__study_row_t *r = &t->rows[i];
      if (!strcmp(r->metric, metric) && ea__in_group(t, r, key[g], xp))
        ea_plot_data_row(pl, 2, (double[]){r->param[xp], r->ok ? r->value : NAN});
    }
    ea_plot_data_end(pl);
    char label[400] = "", style[96];
    size_t lu = 0;
    for (int p = 0; p < t->n_params; ++p)
      if (varies[p]) ea__param_text(t->params[p], key[g][p], label, sizeof label, &lu);
    if (!label[0]) ea__metric_text(s, metric, label, sizeof label);
    used += (size_t)snprintf(plot + used, cap - used, "%s$%s w lp lw 2 %s t '%s'", g ? ", " : "",
                             name, ea_plot_style(g, 1, style, sizeof style), label);
  }
  char xl[160], ml[200], uq[40];
  ea__param_axis(t->params[xp], xl, sizeof xl);
  ea__metric_text(s, metric, ml, sizeof ml);
  ea_plot_enh(strcmp(unit, "-") ? unit : "", uq, sizeof uq);
  for (char *c = strstr(uq, "\\^"); c; c = strstr(c, "\\^")) /* m^2: a superscript */
    memmove(c, c + 1, strlen(c));
  ea_plot_cmd(pl,
              "set grid\nset xlabel '%s'\nset ylabel '%s [%s]'\nset title '%s%s'\n"
              "set key outside right top",
              xl, ml, uq[0] ? uq : "-", ml,
              ng > EA_PLOT_NSTYLES ? " (styles repeat after 40 curves)" : "");
  ea_plot_cmd(pl, "%s", plot);
  free(plot);
  free(key);
  return ea_plot_close(pl, err);
}

ea_status_t ea__study_figures(const ea_study_t *s, const ea__study_table_t *t, const char *prefix,
                              const char *ext, int *n_written, ea_error_t *err) {
  *n_written = 0;
  char path[1100];
  ea_status_t st;
  if (s && (s->metrics & EA_STUDY_M_WORKSPACE)) {
    if (snprintf(path, sizeof path, "%s-workspace.%s", prefix, ext) >= (int)sizeof path)
      return ea_error_set(err, EA_ERR_ARG, "figure prefix too long");
    if ((st = ea__fig_workspace(s, path, err))) return st;
    ++*n_written;
  }
  char names[256][64];
  const int nm = ea__metric_names(t, names, 256);
  for (int m = 0; m < nm; ++m) {
    if (!strncmp(names[m], "torque_map_cells", 16) || !strcmp(names[m], "case")) continue;
    if (snprintf(path, sizeof path, "%s-%s.%s", prefix, names[m], ext) >= (int)sizeof path)
      return ea_error_set(err, EA_ERR_ARG, "figure prefix too long");
    if ((st = ea__fig_metric(s, t, names[m], path, err))) return st;
    ++*n_written;
  }
  return EA_OK;
}
