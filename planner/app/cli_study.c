/* elasticarm study: batch studies of payload and design parameters
 * (docs/studies.md): a spec or the 'payload' shorthand -> tidy CSV + JSON
 * summary + figures; threads, shards, checkpoint/resume; 'study merge'. */
#include "cli_impl.h"
#include "study_report_impl.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static volatile sig_atomic_t ea__study_stop = 0;

static void ea__study_on_signal(int sig) {
  (void)sig;
  ea__study_stop = 1;
  signal(SIGINT, SIG_DFL); /* a second Ctrl-C ends the process at once */
}

static void ea__study_help(FILE *fp) {
  fprintf(
      fp,
      "usage: elasticarm study SPEC.yaml [options]\n"
      "       elasticarm study payload (--payload-factors LIST | --payload-kg LIST)\n"
      "                        [--metrics workspace,torque_map,path,frequencies,min_time,\n"
      "                        at_rest] [metric options] [options]\n"
      "       elasticarm study merge OUT.csv SHARD.csv... [--spec SPEC.yaml] [--summary OUT.json]\n"
      "                        [--cases N]\n\n"
      "Batch study (docs/studies.md): for every case of the grid (full factorial,\n"
      "first parameter slowest) only the metrics asked for; one tidy CSV row per case\n"
      "and metric (case_id, parameters, metric, value, unit, status, message), a JSON\n"
      "summary and figures. A failed case is recorded with its reason; the others run.\n\n"
      "options:\n"
      "  -o, --output FILE    CSV (default: the spec's outputs.csv, else NAME.csv;\n"
      "                       with --shard: NAME.shardK-of-N.csv); -o also moves the\n"
      "                       summary and the figures the spec asks for next to it\n"
      "  --summary FILE       JSON summary (default: OUTPUT with .json)\n"
      "  --figures PREFIX     figures PREFIX-workspace.svg, PREFIX-METRIC.svg\n"
      "  --figure-format F    svg (default), png or pdf (with --figures, or a spec\n"
      "                       whose outputs name figures)\n"
      "  --threads N          workers (default, and 0: all online cores); results\n"
      "                       identical for every N\n"
      "  --workers MODE       auto (default: forked processes when the study plans,\n"
      "                       min_time or at_rest, else threads), threads or processes\n"
      "  --shard K/N          only cases with case_id %% N == K-1 (1 <= K <= N)\n"
      "  --checkpoint FILE    resume journal (default: OUTPUT.journal); rerunning the\n"
      "                       same command after an interruption skips finished cases\n"
      "  --no-checkpoint      no journal (an interruption loses the run)\n"
      "  --restart            discard an existing journal first\n"
      "  --no-fsync           do not fsync the journal per case (faster, not\n"
      "                       power-loss safe)\n"
      "  --arm FILE           arm file when the spec names none\n"
      "  --quiet              no progress or summary table (progress: on stderr once a\n"
      "                       study runs a second, cases done and the time left)\n\n"
      "payload shorthand:\n"
      "  --payload-factors L  list a,b,c or range start:step:stop (eq. 17)\n"
      "  --payload-kg L       payload masses [kg]\n"
      "  --metrics LIST       default workspace\n"
      "  --alpha-min-deg A, --alpha-max-deg A, --points N   workspace region\n"
      "  --no-limits          workspace region without the arm's limits (paper Fig. 3)\n"
      "  --config L:A[,L:A]   frequencies at cable length L [m], angle A [deg]\n"
      "  --modes N            frequencies per configuration (default 3)\n"
      "  --path X0,Y0,X1,Y1   straight tip path for 'path'\n"
      "  --task FILE          task for 'min_time' and 'at_rest' (2 modes, FE 12 elements,\n"
      "                       dt 1 ms, 3 s after the motion, undamped)\n\n"
      "merge: combines shard CSVs into exactly the single-run CSV (byte for byte);\n"
      "  shards of different specs (study_key column) are refused; --cases N checks\n"
      "  that all N cases are present; --spec SPEC.yaml checks that the shards are\n"
      "  that spec's and records it in the summary.\n\n"
      "exit: 0 study complete (failed cases are in the CSV), 1 interrupted or could\n"
      "not run, 2 usage or input error\n");
}

static int ea__write_text(const char *cmd, const char *path, const char *text, size_t len) {
  ea_afile_t f;
  ea_error_t err = {0};
  if (ea_afile_open(&f, path, &err)) return ea__cli_fail(cmd, err.status, &err);
  if (fwrite(text, 1, len, f.fp) != len) {
    ea_afile_abort(&f);
    fprintf(stderr, "elasticarm %s: error: cannot write %s\n", cmd, path);
    return EA_EXIT_FAIL;
  }
  if (ea_afile_commit(&f, &err)) return ea__cli_fail(cmd, err.status, &err);
  return 0;
}

/* path as seen from the folder of the file `from` (both relative to the
 * working directory or absolute), so that the summary does not depend on
 * where the command ran; the path as given when it cannot be resolved. */
static void ea__relpath(const char *path, const char *from, char *out, size_t len) {
  snprintf(out, len, "%s", path);
  char ap[PATH_MAX], dir[PATH_MAX], ad[PATH_MAX], rel[2 * PATH_MAX];
  if (!realpath(path, ap)) return;
  const char *slash = strrchr(from, '/');
  if (slash)
    snprintf(dir, sizeof dir, "%.*s", (int)(slash - from) + (slash == from), from);
  else
    snprintf(dir, sizeof dir, ".");
  if (!realpath(dir, ad)) return;
  /* common leading folders */
  size_t i = 0, last = 0;
  while (ap[i] && ad[i] && ap[i] == ad[i]) {
    if (ap[i] == '/') last = i;
    ++i;
  }
  if (!ad[i] && ap[i] == '/') last = i; /* ad is a prefix folder of ap */
  size_t used = 0;
  if (strcmp(ad, "/")) /* one "../" per folder of ad below the common one */
    for (const char *c = ad + last; *c; ++c)
      if (*c == '/') {
        memcpy(rel + used, "../", 3);
        used += 3;
      }
  const size_t tail = strlen(ap + last + 1);
  if (used + tail + 1 > len) return; /* too long: keep the path as given */
  memcpy(rel + used, ap + last + 1, tail + 1);
  memcpy(out, rel, used + tail + 1);
}

/* The summary's "spec" and "csv" entries relative to the summary. */
static void ea__summary_paths(const char *summary, const char *spec, const char *csv,
                              char *spec_rel, char *csv_rel, size_t len) {
  ea_error_t me = {0};
  ea_mkdir_parents(summary, &me);
  if (spec) ea__relpath(spec, summary, spec_rel, len);
  if (csv) ea__relpath(csv, summary, csv_rel, len);
}

/* ---- merge ------------------------------------------------------------------- */

static int ea__study_merge_cli(int argc, char **argv) {
  const char *cmd = "study merge";
  const char *out = NULL, *summary = NULL, *spec = NULL, *arm_file = NULL;
  long cases = 0;
  const char **inputs = calloc((size_t)argc + 1, sizeof *inputs);
  int n = 0, rc = 0;
  if (!inputs) return EA_EXIT_FAIL;
  static const ea__cli_opt_t opts[] = {{"help", 0, 'h'}, {"summary", 1, 0}, {"spec", 1, 0},
                                       {"arm", 1, 0},    {"cases", 1, 0},   {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int r;
  while ((r = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt, *v = g.arg;
    if (!a) {
      if (!out)
        out = v;
      else
        inputs[n++] = v;
    } else if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
      ea__study_help(stdout);
      free(inputs);
      return EA_EXIT_OK;
    } else if (!strcmp(a, "--summary")) {
      summary = v;
    } else if (!strcmp(a, "--spec")) {
      spec = v;
    } else if (!strcmp(a, "--arm")) {
      arm_file = v;
    } else if (!strcmp(a, "--cases")) {
      if (ea__cli_int(cmd, a, v, 1, 100000000L, &cases)) goto usage;
    }
  }
  if (r < 0) goto usage;
  if (!out || n < 1) {
    ea__cli_usage_error(cmd, "give OUT.csv and at least one shard CSV");
    goto usage;
  }
  char **texts = calloc((size_t)n, sizeof *texts);
  size_t *lens = calloc((size_t)n, sizeof *lens);
  if (!texts || !lens) {
    free(texts);
    free(lens);
    free(inputs);
    return EA_EXIT_FAIL;
  }
  for (int i = 0; i < n && !rc; ++i) {
    /* regular files only: a FIFO shard would block, a directory would not say so */
    ea_error_t rerr = {0};
    if (ea__file_read_regular(inputs[i], NULL, &texts[i], &lens[i], &rerr)) {
      fprintf(stderr, "elasticarm %s: error: cannot read shard %s\n", cmd, rerr.msg);
      rc = EA_EXIT_USAGE;
    }
  }
  char *merged = NULL;
  size_t mlen = 0;
  ea_error_t err = {0};
  char spec_name[128] = "", spec_key[9] = "";
  if (!rc && spec) {
    /* the spec's key, as a run of it would compute it */
    ea_study_t s;
    ea_status_t st = ea_study_load(spec, arm_file ? arm_file : ea__cli_default_arm(), &s, &err);
    ea_study_planner_t *plan = NULL;
    ea_study_settings_t set;
    ea_study_settings_default(&set);
    if (!st) st = ea_study_use_planner(&s, ea__cli_default_arm(), &set, &plan, &err);
    if (st) {
      rc = ea__cli_fail(cmd, st, &err);
    } else {
      ea_study_key(&s, &set, spec_key);
      snprintf(spec_name, sizeof spec_name, "%s", s.name);
      if (!cases) cases = s.n_cases;
    }
    ea_study_planner_free(plan);
    if (!st) ea_study_free(&s);
  }
  if (!rc) {
    ea_status_t st =
        ea_study_merge((const char *const *)texts, lens, inputs, n, cases, &merged, &mlen, &err);
    if (st) rc = ea__cli_fail(cmd, st, &err);
  }
  if (!rc && spec) {
    ea__study_table_t t;
    ea_status_t st = ea__study_table_parse(merged, mlen, out, &t, &err);
    if (st) {
      rc = ea__cli_fail(cmd, st, &err);
    } else {
      if (strcmp(t.study, spec_name) || strcmp(t.study_key, spec_key)) {
        fprintf(stderr,
                "elasticarm %s: error: the shards are study '%s' key %s, but %s gives study '%s' "
                "key %s (another spec, or the spec, its arm or its task changed)\n",
                cmd, t.study, t.study_key, spec, spec_name, spec_key);
        rc = EA_EXIT_USAGE;
      }
      ea__study_table_free(&t);
    }
  }
  if (!rc) rc = ea__write_text(cmd, out, merged, mlen);
  if (!rc) {
    char sbuf[1100];
    if (!summary && strcmp(out, "-")) {
      ea__replace_ext(out, ".json", sbuf, sizeof sbuf);
      summary = sbuf;
    }
    ea__study_table_t t;
    if (summary) {
      ea_status_t st = ea__study_table_parse(merged, mlen, out, &t, &err);
      if (!st) {
        char spec_rel[1200], csv_rel[1200];
        ea__summary_paths(summary, spec, out, spec_rel, csv_rel, sizeof spec_rel);
        ea__study_run_facts_t f = {
            .spec = spec ? spec_rel : NULL, .csv = csv_rel, .merged_inputs = n};
        st = ea__study_summary_write(&t, &f, summary, &err);
        ea__study_table_free(&t);
      }
      if (st) rc = ea__cli_fail(cmd, st, &err);
    }
    if (!rc)
      printf("merged %d shard(s) into %s%s%s\n", n, out, summary ? ", " : "",
             summary ? summary : "");
  }
  free(merged);
  for (int i = 0; i < n; ++i)
    free(texts[i]);
  free(texts);
  free(lens);
  free(inputs);
  return rc;
usage:
  free(inputs);
  return EA_EXIT_USAGE;
}

/* ---- run ---------------------------------------------------------------------- */

/* Study progress: cases done and, from the pace of the cases this run computed (not those
 * the checkpoint had), the time left. */
typedef struct {
  ea__cli_progress_t p;
  double t0; /* [s] (ea__mono_s) when the run started */
  long base; /* cases done before this run's first: from the checkpoint; -1 until known */
} ea__study_progress_t;

static void ea__progress(void *data, long case_id, long done, long todo, int failed_rows) {
  (void)case_id;
  (void)failed_rows;
  ea__study_progress_t *g = data;
  if (g->base < 0) g->base = done - 1;
  const double el = ea__mono_s() - g->t0;
  const long ran = done - g->base;
  char left[64] = "";
  if (ran > 0 && done < todo) {
    const double eta = el / (double)ran * (double)(todo - done);
    if (eta < 90)
      snprintf(left, sizeof left, ", about %.0f s left", ceil(eta));
    else
      snprintf(left, sizeof left, ", about %.0f min left", ceil(eta / 60));
  }
  ea__cli_progress(&g->p, done == todo, "%ld / %ld cases (%.0f %%), %.1f s%s", done, todo,
                   todo > 0 ? 100.0 * (double)done / (double)todo : 100.0, el, left);
}

typedef struct {
  double *gam, *kg;
  int ng, nkg;
  unsigned metrics;
  double amin, amax;
  long points, modes;
  int n_config;
  double cfg_L[EA_STUDY_MAX_CONFIGS], cfg_a[EA_STUDY_MAX_CONFIGS];
  double path[4];
  int has_path, no_limits;
  const char *task;
} ea__shorthand_t;

static int ea__parse_metrics(const char *cmd, const char *v, unsigned *m) {
  static const char *const names[] = {"workspace", "torque_map", "frequencies",
                                      "path",      "min_time",   "at_rest"};
  *m = 0;
  char buf[256];
  snprintf(buf, sizeof buf, "%s", v);
  for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    int k = 0;
    while (k < 6 && strcmp(names[k], tok))
      ++k;
    if (k == 6)
      return ea__cli_usage_error(cmd,
                                 "--metrics: unknown metric '%s' (workspace, torque_map, "
                                 "frequencies, path, min_time, at_rest)",
                                 tok);
    *m |= 1u << k;
  }
  return 0;
}

/* Options of `study` (not `study merge`). */
typedef struct {
  const char *spec, *out, *summary, *figures, *fmt, *ckpt, *arm_file;
  int no_ckpt, restart, quiet, shorthand, no_fsync, out_given, fmt_given;
  ea_study_workers_t workers;
  long threads, stop_after;
  int shard_k, shard_n;
  ea__shorthand_t sh;
  char out_buf[1100], sum_buf[1100], ck_buf[1200], fig_buf[1100];
} ea__study_opts_t;

/* --config L:A[,L:A...]: frequency configurations of `study payload`. */
static int ea__parse_configs(const char *cmd, const char *v, ea__shorthand_t *sh) {
  char buf[512];
  snprintf(buf, sizeof buf, "%s", v);
  sh->n_config = 0;
  for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    double L, A;
    char tail;
    if (sh->n_config >= EA_STUDY_MAX_CONFIGS || sscanf(tok, "%lf:%lf%c", &L, &A, &tail) != 2 ||
        !(L > 0) || !isfinite(A))
      return ea__cli_usage_error(cmd, "--config: '%s' is not L:A[,L:A...] (at most %d)", v,
                                 EA_STUDY_MAX_CONFIGS);
    sh->cfg_L[sh->n_config] = L;
    sh->cfg_a[sh->n_config++] = A;
  }
  return 0;
}

/* One option with a value (argv[*i], value v); 0 or the exit code. */
static int ea__study_opt(const char *cmd, const char *a, const char *v, ea__study_opts_t *o) {
  ea__shorthand_t *sh = &o->sh;
  if (!strcmp(a, "-o") || !strcmp(a, "--output"))
    o->out = v;
  else if (!strcmp(a, "--summary"))
    o->summary = v;
  else if (!strcmp(a, "--figures"))
    o->figures = v;
  else if (!strcmp(a, "--figure-format")) {
    o->fmt = v;
    o->fmt_given = 1;
    if (strcmp(v, "svg") && strcmp(v, "png") && strcmp(v, "pdf"))
      return ea__cli_usage_error(cmd, "--figure-format: '%s' is not svg, png or pdf", v);
  } else if (!strcmp(a, "--threads"))
    return ea__cli_int(cmd, a, v, 0, 1024, &o->threads); /* 0: every online core */
  else if (!strcmp(a, "--workers")) {
    if (!strcmp(v, "auto"))
      o->workers = EA_STUDY_WORKERS_AUTO;
    else if (!strcmp(v, "threads"))
      o->workers = EA_STUDY_WORKERS_THREADS;
    else if (!strcmp(v, "processes"))
      o->workers = EA_STUDY_WORKERS_PROCESSES;
    else
      return ea__cli_usage_error(cmd, "--workers: '%s' is not auto, threads or processes", v);
  } else if (!strcmp(a, "--stop-after"))
    return ea__cli_int(cmd, a, v, 1, 100000000L, &o->stop_after);
  else if (!strcmp(a, "--shard")) {
    char tail;
    if (sscanf(v, "%d/%d%c", &o->shard_k, &o->shard_n, &tail) != 2 || o->shard_n < 1 ||
        o->shard_k < 1 || o->shard_k > o->shard_n)
      return ea__cli_usage_error(cmd, "--shard: '%s' is not K/N with 1 <= K <= N", v);
  } else if (!strcmp(a, "--checkpoint"))
    o->ckpt = v;
  else if (!strcmp(a, "--arm"))
    o->arm_file = v;
  else if (!strcmp(a, "--payload-factors")) {
    free(sh->gam);
    return ea__cli_list(cmd, a, v, &sh->gam, &sh->ng);
  } else if (!strcmp(a, "--payload-kg")) {
    free(sh->kg);
    return ea__cli_list(cmd, a, v, &sh->kg, &sh->nkg);
  } else if (!strcmp(a, "--metrics"))
    return ea__parse_metrics(cmd, v, &sh->metrics);
  else if (!strcmp(a, "--alpha-min-deg"))
    return ea__cli_double(cmd, a, v, -180, 180, &sh->amin);
  else if (!strcmp(a, "--alpha-max-deg"))
    return ea__cli_double(cmd, a, v, -180, 180, &sh->amax);
  else if (!strcmp(a, "--points"))
    return ea__cli_int(cmd, a, v, 2, 100000, &sh->points);
  else if (!strcmp(a, "--modes"))
    return ea__cli_int(cmd, a, v, 1, EA_FE_MAX_MODES, &sh->modes);
  else if (!strcmp(a, "--config"))
    return ea__parse_configs(cmd, v, sh);
  else if (!strcmp(a, "--path")) {
    char tail;
    sh->has_path = 1;
    if (sscanf(v, "%lf,%lf,%lf,%lf%c", &sh->path[0], &sh->path[1], &sh->path[2], &sh->path[3],
               &tail) != 4)
      return ea__cli_usage_error(cmd, "--path: '%s' is not X0,Y0,X1,Y1", v);
  } else if (!strcmp(a, "--task"))
    sh->task = v;
  else
    return ea__cli_usage_error(cmd, "unknown option '%s'", a);
  return 0;
}

/* The options; 0, -1 (help printed: exit 0) or the exit code. */
static int ea__study_parse(const char *cmd, int argc, char **argv, ea__study_opts_t *o) {
  o->fmt = "svg";
  o->shard_k = o->shard_n = 1;
  o->sh.amin = -60;
  o->sh.amax = 10;
  o->sh.points = 71;
  o->sh.modes = 3;
  static const ea__cli_opt_t opts[] = {{"help", 0, 'h'},
                                       {"quiet", 0, 0},
                                       {"no-checkpoint", 0, 0},
                                       {"restart", 0, 0},
                                       {"no-fsync", 0, 0},
                                       {"no-limits", 0, 0},
                                       {"output", 1, 'o'},
                                       {"summary", 1, 0},
                                       {"figures", 1, 0},
                                       {"figure-format", 1, 0},
                                       {"threads", 1, 0},
                                       {"workers", 1, 0},
                                       {"stop-after", 1, 0},
                                       {"shard", 1, 0},
                                       {"checkpoint", 1, 0},
                                       {"arm", 1, 0},
                                       {"payload-factors", 1, 0},
                                       {"payload-kg", 1, 0},
                                       {"metrics", 1, 0},
                                       {"alpha-min-deg", 1, 0},
                                       {"alpha-max-deg", 1, 0},
                                       {"points", 1, 0},
                                       {"modes", 1, 0},
                                       {"config", 1, 0},
                                       {"path", 1, 0},
                                       {"task", 1, 0},
                                       {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int r;
  while ((r = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt, *v = g.arg;
    if (!a) {
      if (o->spec)
        return ea__cli_usage_error(cmd, "more than one spec ('%s' and '%s')", o->spec, v);
      o->spec = v;
      o->shorthand = !strcmp(v, "payload");
      continue;
    }
    if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
      ea__study_help(stdout);
      return -1;
    }
    int *flag = !strcmp(a, "--quiet")           ? &o->quiet
                : !strcmp(a, "--no-checkpoint") ? &o->no_ckpt
                : !strcmp(a, "--restart")       ? &o->restart
                : !strcmp(a, "--no-fsync")      ? &o->no_fsync
                : !strcmp(a, "--no-limits")     ? &o->sh.no_limits
                                                : NULL;
    if (flag) {
      *flag = 1;
      continue;
    }
    const int bad = ea__study_opt(cmd, a, v, o);
    if (bad) return bad;
  }
  if (r < 0) return EA_EXIT_USAGE;
  if (!o->spec) return ea__cli_usage_error(cmd, "no study spec (SPEC.yaml, 'payload' or 'merge')");
  const ea__shorthand_t *sh = &o->sh;
  if (!o->shorthand && (sh->gam || sh->kg || sh->metrics || sh->n_config || sh->has_path ||
                        sh->task || sh->no_limits))
    return ea__cli_usage_error(cmd, "--payload-factors, --metrics, --config, --path, --task, "
                                    "--no-limits belong to 'elasticarm study payload'");
  return 0;
}

/* The study of `study payload`: the arm, one payload axis, the metrics' settings.
 * 0 (s to be freed) or the exit code (s freed). */
static int ea__study_shorthand(const char *cmd, const ea__study_opts_t *o, ea_study_t *s) {
  const ea__shorthand_t *sh = &o->sh;
  ea_arm_t arm;
  int rc = ea__cli_load_arm(cmd, o->arm_file, &arm);
  if (rc) return rc;
  if (!!sh->gam == !!sh->kg)
    return ea__cli_usage_error(cmd, "study payload: give --payload-factors or --payload-kg");
  ea_study_init(s, &arm);
  ea_error_t err = {0};
  snprintf(s->name, sizeof s->name, "payload");
  snprintf(s->arm_file, sizeof s->arm_file, "%s",
           o->arm_file ? o->arm_file : ea__cli_default_arm());
  ea_status_t st = sh->gam ? ea_study_set_axis(s, EA_STUDY_PAYLOAD_FACTOR, sh->gam, sh->ng, &err)
                           : ea_study_set_axis(s, EA_STUDY_PAYLOAD_KG, sh->kg, sh->nkg, &err);
  s->metrics = sh->metrics ? sh->metrics : EA_STUDY_M_WORKSPACE;
  s->workspace.alpha_min = sh->amin * EA__DEG;
  s->workspace.alpha_max = sh->amax * EA__DEG;
  s->workspace.points = (int)sh->points;
  s->workspace.limits = !sh->no_limits;
  s->freq.modes = (int)sh->modes;
  s->freq.n_config = sh->n_config;
  for (int k = 0; k < sh->n_config; ++k) {
    s->freq.cable_length[k] = sh->cfg_L[k];
    s->freq.alpha[k] = sh->cfg_a[k] * EA__DEG;
  }
  /* the path: given, or the paper's line (eq. 18) */
  const double path[4] = {0.3, -0.2, 0.6, -0.2};
  if (sh->has_path || (s->metrics & EA_STUDY_M_PATH)) {
    const double *p = sh->has_path ? sh->path : path;
    s->path.start[0] = p[0];
    s->path.start[1] = p[1];
    s->path.goal[0] = p[2];
    s->path.goal[1] = p[3];
  }
  if (sh->task) {
    snprintf(s->min_time.task_file, sizeof s->min_time.task_file, "%s", sh->task);
    snprintf(s->at_rest.task_file, sizeof s->at_rest.task_file, "%s", sh->task);
  }
  if (!st && (s->metrics & EA_STUDY_M_TORQUE)) {
    s->torque.n_len = 13;
    s->torque.n_alpha = 8;
    s->torque.cable_length = malloc(13 * sizeof(double));
    s->torque.alpha = malloc(8 * sizeof(double));
    if (!s->torque.cable_length || !s->torque.alpha) st = EA_ERR_NOMEM;
    for (int k = 0; !st && k < 13; ++k)
      s->torque.cable_length[k] = arm.act.cable_length_min + 0.05 * k;
    for (int k = 0; !st && k < 8; ++k)
      s->torque.alpha[k] = (-60.0 + 10.0 * k) * EA__DEG;
  }
  if (!st) st = ea_study_check(s, &err);
  if (st) {
    ea_study_free(s);
    return ea__cli_fail(cmd, st, &err);
  }
  return 0;
}

/* Output paths: -o moves the summary and the spec's figures along with the CSV; the
 * journal beside the CSV unless told otherwise. 0 or the exit code. */
static int ea__study_paths(const char *cmd, const ea_study_t *s, ea__study_opts_t *o) {
  o->out_given = o->out != NULL;
  if (!o->out) {
    if (s->out_csv[0] && o->shard_n == 1) {
      o->out = s->out_csv;
    } else {
      char stem[600];
      if (s->out_csv[0])
        ea__replace_ext(s->out_csv, "", stem, sizeof stem);
      else
        snprintf(stem, sizeof stem, "%.500s", s->name);
      if (o->shard_n > 1)
        snprintf(o->out_buf, sizeof o->out_buf, "%.600s.shard%d-of-%d.csv", stem, o->shard_k,
                 o->shard_n);
      else
        snprintf(o->out_buf, sizeof o->out_buf, "%.600s.csv", stem);
      o->out = o->out_buf;
    }
  }
  const int to_stdout = !strcmp(o->out, "-");
  if (!o->summary && !o->out_given && s->out_summary[0] && o->shard_n == 1)
    o->summary = s->out_summary;
  if (!o->summary && !to_stdout) {
    ea__replace_ext(o->out, ".json", o->sum_buf, sizeof o->sum_buf);
    o->summary = o->sum_buf;
  }
  if (!o->figures && s->out_figures[0] && o->shard_n == 1) {
    if (o->out_given && !to_stdout) {
      ea__replace_ext(o->out, "", o->fig_buf, sizeof o->fig_buf);
      o->figures = o->fig_buf;
    } else {
      o->figures = s->out_figures;
    }
  }
  if (o->fmt_given && !o->figures)
    return ea__cli_usage_error(cmd,
                               "--figure-format %s needs --figures PREFIX (or a spec whose "
                               "outputs name figures): without them nothing is drawn",
                               o->fmt);
  if (!o->ckpt && !o->no_ckpt && !to_stdout) {
    snprintf(o->ck_buf, sizeof o->ck_buf, "%s.journal", o->out);
    o->ckpt = o->ck_buf;
  }
  if (o->no_ckpt) o->ckpt = NULL;
  if (o->ckpt) {
    ea_error_t me = {0};
    if (ea_mkdir_parents(o->ckpt, &me)) return ea__cli_fail(cmd, me.status, &me);
    if (o->restart) unlink(o->ckpt);
  }
  return 0;
}

/* Run the study (the min_time planner callback when asked for, Ctrl-C finishes the
 * running cases). 0 with *csv, or the exit code. */
static int ea__study_execute(const char *cmd, const ea__study_opts_t *o, const ea_study_t *s,
                             char **csv, size_t *csv_len, ea_study_info_t *info) {
  ea_error_t err = {0};
  ea_status_t st;
  ea_study_planner_t *plan = NULL;
  ea_study_settings_t set;
  ea_study_settings_default(&set);
  if ((st = ea_study_use_planner(s, ea__cli_default_arm(), &set, &plan, &err)))
    return ea__cli_fail(cmd, st, &err);
  set.threads = (int)o->threads;
  set.shard_k = o->shard_k;
  set.shard_n = o->shard_n;
  set.checkpoint = o->ckpt;
  set.fsync = !o->no_fsync;
  set.stop_after = o->stop_after;
  set.stop_request = &ea__study_stop;
  set.workers = o->workers;
  ea__study_progress_t prog;
  ea__cli_progress_init(&prog.p, "study", !o->quiet);
  prog.t0 = ea__mono_s();
  prog.base = -1;
  set.progress = ea__progress;
  set.progress_data = &prog;
  struct sigaction sa, old;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = ea__study_on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &old);
  sigaction(SIGTERM, &sa, NULL);
  st = ea_study_run(s, &set, csv, csv_len, info, &err);
  sigaction(SIGINT, &old, NULL);
  signal(SIGTERM, SIG_DFL);
  ea__cli_progress_end(&prog.p);
  ea_study_planner_free(plan);
  if (st == EA_ERR_INTERRUPTED) {
    fprintf(stderr, "elasticarm study: interrupted: %s\n", err.msg);
    if (o->ckpt) fprintf(stderr, "elasticarm study: checkpoint %s\n", o->ckpt);
    return EA_EXIT_FAIL;
  }
  return st ? ea__cli_fail(cmd, st, &err) : 0;
}

/* The CSV, its summary and figures; the journal removed once they are written.
 * 0 or the exit code; *nfig counts the figures. */
static int ea__study_reports(const char *cmd, const ea__study_opts_t *o, const ea_study_t *s,
                             const char *csv, size_t csv_len, const ea_study_info_t *info,
                             ea__study_table_t *t, int *nfig) {
  ea_error_t err = {0};
  ea_status_t st;
  int rc = ea__write_text(cmd, o->out, csv, csv_len);
  if (!rc && (o->summary || o->figures) &&
      (st = ea__study_table_parse(csv, csv_len, o->out, t, &err)))
    rc = ea__cli_fail(cmd, st, &err);
  if (!rc && o->summary) {
    char spec_rel[1200], csv_rel[1200];
    ea__summary_paths(o->summary, o->shorthand ? NULL : o->spec, o->out, spec_rel, csv_rel,
                      sizeof spec_rel);
    ea__study_run_facts_t f = {.name = s->name,
                               .spec = o->shorthand ? NULL : spec_rel,
                               .csv = csv_rel,
                               .info = info,
                               .shard_k = o->shard_k,
                               .shard_n = o->shard_n};
    if ((st = ea__study_summary_write(t, &f, o->summary, &err))) rc = ea__cli_fail(cmd, st, &err);
  }
  if (!rc && o->figures && (st = ea__study_figures(s, t, o->figures, o->fmt, nfig, &err))) {
    fprintf(stderr, "elasticarm study: figure: %s\n", err.msg);
    rc = EA_EXIT_FAIL;
  }
  if (!rc && o->ckpt) unlink(o->ckpt); /* the outputs are committed: the journal has served */
  return rc;
}

/* Per metric: unit, rows ok and failed, range of the values. */
static void ea__study_print_metrics(const ea__study_table_t *t) {
  printf("%-30s %-6s %6s %6s %14s %14s\n", "metric", "unit", "ok", "failed", "min", "max");
  char seen[64][64];
  int ns = 0;
  for (long i = 0; i < t->n_rows && ns < 64; ++i) {
    int k = 0;
    while (k < ns && strcmp(seen[k], t->rows[i].metric))
      ++k;
    if (k < ns) continue;
    snprintf(seen[ns++], 64, "%s", t->rows[i].metric);
    long ok = 0, bad = 0;
    double lo = NAN, hi = NAN;
    for (long q = 0; q < t->n_rows; ++q) {
      if (strcmp(t->rows[q].metric, t->rows[i].metric)) continue;
      if (!t->rows[q].ok) {
        ++bad;
        continue;
      }
      ++ok;
      const double v = t->rows[q].value;
      if (isfinite(v)) {
        lo = isfinite(lo) ? fmin(lo, v) : v;
        hi = isfinite(hi) ? fmax(hi, v) : v;
      }
    }
    printf("%-30s %-6s %6ld %6ld %14.6g %14.6g\n", t->rows[i].metric, t->rows[i].unit, ok, bad, lo,
           hi);
  }
}

/* study SPEC.yaml | study payload [...]: parse, build or load, paths, run, reports. */
int ea__cli_study(int argc, char **argv) {
  const char *cmd = "study";
  if (argc >= 2 && !strcmp(argv[1], "merge")) return ea__study_merge_cli(argc - 1, argv + 1);
  ea__study_opts_t o;
  memset(&o, 0, sizeof o);
  int rc = ea__study_parse(cmd, argc, argv, &o);
  ea_study_t s;
  if (rc) {
    rc = rc < 0 ? EA_EXIT_OK : rc;
    goto done;
  }
  if (o.shorthand) {
    if ((rc = ea__study_shorthand(cmd, &o, &s))) goto done;
  } else {
    ea_error_t err = {0};
    ea_status_t st =
        ea_study_load(o.spec, o.arm_file ? o.arm_file : ea__cli_default_arm(), &s, &err);
    if (st) {
      rc = ea__cli_fail(cmd, st, &err);
      goto done;
    }
  }
  char *csv = NULL;
  size_t csv_len = 0;
  ea_study_info_t info;
  ea__study_table_t t;
  memset(&t, 0, sizeof t);
  int nfig = 0;
  if (!(rc = ea__study_paths(cmd, &s, &o)) &&
      !(rc = ea__study_execute(cmd, &o, &s, &csv, &csv_len, &info))) {
    rc = ea__study_reports(cmd, &o, &s, csv, csv_len, &info, &t, &nfig);
    if (!o.quiet && strcmp(o.out, "-")) {
      printf("study %s: %ld case(s)%s, %ld computed, %ld from the checkpoint, %ld with failures "
             "(%ld rows), %d %s, %.3f s\n",
             s.name, info.cases_shard, o.shard_n > 1 ? " in this shard" : "", info.cases_computed,
             info.cases_skipped, info.cases_failed, info.rows_failed, info.threads,
             info.processes ? "worker process(es)" : "thread(s)", info.time_s);
      if (info.workers_lost)
        printf("%ld worker process(es) died while computing a case: those cases are failed "
               "rows\n",
               info.workers_lost);
      if (info.journal_dropped_bytes)
        printf("checkpoint: dropped a torn tail of %ld bytes\n", info.journal_dropped_bytes);
      if (!rc) {
        ea__study_print_metrics(&t);
        printf("wrote %s%s%s", o.out, o.summary ? ", " : "", o.summary ? o.summary : "");
        if (nfig) printf(", %d figure(s) %s-*.%s", nfig, o.figures, o.fmt);
        printf("\n");
      }
    }
  }
  ea__study_table_free(&t);
  free(csv);
  ea_study_free(&s);
done:
  free(o.sh.gam);
  free(o.sh.kg);
  return rc;
}
