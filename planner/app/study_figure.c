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

static void ea__case_label(const ea_study_t *s, long c, char *buf, size_t len) {
  double v[EA_STUDY_NPARAM];
  ea_study_case_values(s, c, v);
  size_t used = 0;
  buf[0] = '\0';
  for (int i = 0; i < s->n_axes && used < len; ++i) {
    if (s->axis[i].n < 2 && s->n_axes > 1) continue;
    int w = snprintf(buf + used, len - used, "%s%s = %g", used ? ", " : "",
                     s->axis[i].param == EA_STUDY_PAYLOAD_FACTOR
                         ? "{/Symbol g}"
                         : ea_study_param_name(s->axis[i].param),
                     v[i]);
    if (w < 0) break;
    used += (size_t)w;
  }
  /* gnuplot enhanced text: escape underscores */
  char tmp[256];
  size_t o = 0;
  for (size_t i = 0; buf[i] && o + 3 < sizeof tmp; ++i) {
    if (buf[i] == '_') tmp[o++] = '\\';
    tmp[o++] = buf[i];
  }
  tmp[o] = '\0';
  if (snprintf(buf, len, "%s", tmp) < 0) buf[0] = '\0';
}

static ea_status_t ea__fig_workspace(const ea_study_t *s, const char *path, ea_error_t *err) {
  const int n = s->workspace.points;
  long pick[8];
  int np = 0;
  if (s->n_cases <= 8)
    for (long c = 0; c < s->n_cases; ++c)
      pick[np++] = c;
  else
    for (int k = 0; k < 8; ++k)
      pick[np++] = (long)((double)k * (s->n_cases - 1) / 7.0 + 0.5);
  double *alpha = malloc((size_t)n * sizeof *alpha);
  ea_config_point_t *outer = calloc((size_t)n, sizeof *outer);
  ea_config_point_t *inner = calloc((size_t)n, sizeof *inner);
  ea_plot_t *pl = NULL;
  ea_status_t st = EA_OK;
  if (!alpha || !outer || !inner) {
    st = ea_error_set(err, EA_ERR_NOMEM, "figure: out of memory");
    goto out;
  }
  for (int k = 0; k < n; ++k)
    alpha[k] =
        s->workspace.alpha_min + (s->workspace.alpha_max - s->workspace.alpha_min) * k / (n - 1);
  if ((st = ea_plot_open(&pl, path, 850, 650, err))) goto out;
  char plot[8192];
  int used = snprintf(plot, sizeof plot, "plot ");
  for (int q = 0; q < np; ++q) {
    ea_arm_t arm;
    double kg, g;
    ea_shooter_t *sh = NULL;
    if (ea_study_case_arm(s, pick[q], &arm, &kg, &g, NULL) ||
        ea_shooter_alloc(&arm, NULL, &sh, NULL))
      continue;
    ea_load_t load = {ea_arm_tip_mass(&arm, kg)};
    ea_shooter_set_load(sh, &load);
    ea_workspace_outer(sh, alpha, n, outer);
    ea_workspace_inner(sh, s->workspace.inner_cable_length, alpha, n, inner);
    ea_shooter_free(sh);
    char name[32], label[200];
    snprintf(name, sizeof name, "ws%d", q);
    ea_plot_data_begin(pl, name);
    for (int k = 0; k < n; ++k)
      ea_plot_data_row(pl, 2, (double[]){outer[k].status ? NAN : outer[k].x, outer[k].y});
    ea_plot_data_row(pl, 1, (double[]){NAN});
    for (int k = n - 1; k >= 0; --k)
      ea_plot_data_row(pl, 2, (double[]){inner[k].status ? NAN : inner[k].x, inner[k].y});
    ea_plot_data_end(pl);
    ea__case_label(s, pick[q], label, sizeof label);
    if (used < (int)sizeof plot - 300)
      used += snprintf(plot + used, sizeof plot - (size_t)used, "%s$ws%d w l lw 2 lc %d t '%s'",
                       q ? ", " : "", q, q + 1, label);
  }
  ea_plot_data_begin(pl, "root");
  ea_plot_data_row(pl, 2, (double[]){s->arm.x_c, s->arm.y_c});
  ea_plot_data_end(pl);
  ea_plot_cmd(pl,
              "set size ratio -1\nset xlabel 'x [m]'\nset ylabel 'y [m]'\nset grid\n"
              "set key outside right\n"
              "set title 'Workspace: outer edge (T = 0) and inner edge, %.0f to %.0f deg'",
              s->workspace.alpha_min / EA__DEG, s->workspace.alpha_max / EA__DEG);
  ea_plot_cmd(pl, "%s, $root w p pt 7 ps 1.5 lc rgb '#c0392b' t 'cable root'", plot);
  st = ea_plot_close(pl, err);
out:
  free(alpha);
  free(outer);
  free(inner);
  return st;
}

static void ea__escape(const char *in, char *out, size_t len) {
  size_t o = 0;
  for (size_t i = 0; in[i] && o + 3 < len; ++i) {
    if (in[i] == '\n' || in[i] == '\r') {
      out[o++] = ' ';
      continue;
    }
    if (in[i] == '_') out[o++] = '\\';  /* '\_': a literal _ in enhanced text */
    if (in[i] == '\'') out[o++] = '\''; /* '': a quote inside a single-quoted string */
    out[o++] = in[i];
  }
  out[o] = '\0';
}

/* One figure per metric: x = the first parameter with more than one value,
 * one curve per combination of the other parameters (at most 12). */
static ea_status_t ea__fig_metric(const ea__study_table_t *t, const char *metric, const char *path,
                                  ea_error_t *err) {
  int xp = -1;
  for (int p = 0; p < t->n_params && xp < 0; ++p)
    for (long i = 1; i < t->n_rows; ++i)
      if (t->rows[i].param[p] != t->rows[0].param[p]) {
        xp = p;
        break;
      }
  if (xp < 0) return EA_OK; /* one case: nothing to plot against */
  /* groups: distinct values of the other parameters */
  double key[12][EA_STUDY_NPARAM];
  int ng = 0;
  const char *unit = "";
  for (long i = 0; i < t->n_rows; ++i) {
    const ea__study_row_t *r = &t->rows[i];
    if (strcmp(r->metric, metric)) continue;
    unit = r->unit;
    int g = 0;
    for (; g < ng; ++g) {
      int same = 1;
      for (int p = 0; p < t->n_params; ++p)
        if (p != xp && key[g][p] != r->param[p]) same = 0;
      if (same) break;
    }
    if (g == ng && ng < 12) {
      memcpy(key[ng], r->param, sizeof key[ng]);
      ++ng;
    }
  }
  ea_plot_t *pl;
  ea_status_t st = ea_plot_open(&pl, path, 800, 550, err);
  if (st) return st;
  char plot[6000];
  int used = snprintf(plot, sizeof plot, "plot ");
  for (int g = 0; g < ng; ++g) {
    char name[16];
    snprintf(name, sizeof name, "m%d", g);
    ea_plot_data_begin(pl, name);
    for (long i = 0; i < t->n_rows; ++i) {
      const ea__study_row_t *r = &t->rows[i];
      if (strcmp(r->metric, metric)) continue;
      int same = 1;
      for (int p = 0; p < t->n_params; ++p)
        if (p != xp && key[g][p] != r->param[p]) same = 0;
      if (!same) continue;
      ea_plot_data_row(pl, 2, (double[]){r->param[xp], r->ok ? r->value : NAN});
    }
    ea_plot_data_end(pl);
    char label[300] = "", esc[300];
    size_t lu = 0;
    for (int p = 0; p < t->n_params; ++p)
      if (p != xp && lu < sizeof label) {
        int w = snprintf(label + lu, sizeof label - lu, "%s%s = %g", lu ? ", " : "", t->params[p],
                         key[g][p]);
        if (w > 0) lu += (size_t)w;
      }
    ea__escape(label[0] ? label : metric, esc, sizeof esc);
    if (used < (int)sizeof plot - 400)
      used += snprintf(plot + used, sizeof plot - (size_t)used, "%s$m%d w lp lw 2 pt 7 t '%s'",
                       g ? ", " : "", g, esc);
  }
  char xl[80], ml[160];
  ea__escape(t->params[xp], xl, sizeof xl);
  ea__escape(metric, ml, sizeof ml);
  ea_plot_cmd(pl,
              "set grid\nset xlabel '%s'\nset ylabel '%s [%s]'\nset title '%s against %s'\n"
              "set key outside right",
              xl, ml, unit, ml, xl);
  ea_plot_cmd(pl, "%s", plot);
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
    if ((st = ea__fig_metric(t, names[m], path, err))) return st;
    ++*n_written;
  }
  return EA_OK;
}
