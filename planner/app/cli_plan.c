/* elasticarm plan: task spec -> trajectory file + JSON summary (+ figure). */
#include "cli_impl.h"
#include "ea_refine.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static void ea__plan_help(FILE *fp) {
  fprintf(fp, "usage: elasticarm plan TASK.yaml [-o OUT.csv] [--summary OUT.json] [--json]\n"
              "                       [--figure OUT.svg|png|pdf] [--knots N] [--refine]\n"
              "                       [--shape zv] [--verify] [--no-verify]\n"
              "                       [--refine-by fe|model|model_only]\n"
              "                       [--derivative-test]\n"
              "                       [--print-level N] [--quiet]\n\n"
              "Plans an admissible trajectory for the task (docs/task-format.md, docs/planner.md)\n"
              "and writes the trajectory file (docs/trajectory-format.md) and a JSON summary next\n"
              "to it (OUT.json). Defaults: the task's outputs, else NAME.csv in the current\n"
              "folder, NAME being the task's name reduced to a safe file name (letters, digits,\n"
              "'-', '_', '.', '+'; no folders, no leading dot).\n\n"
              "Outputs: every path is checked (writable, figure extension known) before the\n"
              "work. A converged plan writes the trajectory and the summary to temporaries,\n"
              "renames the trajectory, then the summary, then draws the figure. Both carry the\n"
              "same run id (the trajectory's '# run_id:' line, the summary's \"run_id\"), and\n"
              "the renames happen under an exclusive lock of OUT.lock (flock; the empty file\n"
              "stays), so runs writing the same outputs at once leave one run's pair; 'figure'\n"
              "and 'simulate' refuse a trajectory whose OUT.json has another run id. A plan that\n"
              "fails (infeasible, not converged) or whose trajectory cannot be written writes\n"
              "only the summary, with the failure status, and removes an earlier trajectory\n"
              "and figure of the same names, so a summary never sits beside a trajectory it\n"
              "does not describe. Temporaries ('NAME.tmp<pid>.*') left by a killed run are\n"
              "removed by the next run writing the same outputs.\n\n");
  fprintf(fp,
          "A task with dynamics keeps its promise by default: a plan that ends at rest is\n"
          "checked by the FE transient (12 elements, generalized-alpha, dt 4 ms, 1.5 s after\n"
          "the motion, undamped) and refined until its residual peak is within 0.5 mm (within\n"
          "dynamics.refine's tolerance_m when the task refines); a plan with residual_m > 0 is\n"
          "checked once against it (as --verify). The text and the summary (\"fe_check\") say\n"
          "what was measured, or that the plan was not checked. A bound not reached: exit 3,\n"
          "the best plan and its summary written, the message says what was reached.\n\n");
  fprintf(fp,
          "  -o FILE            trajectory file ('-' = stdout)\n"
          "  --summary FILE     JSON summary (default: OUT with .json)\n"
          "  --json             print the JSON summary on stdout (also for a failed plan)\n"
          "  --figure FILE      tip path and beam shapes in the workspace, time histories\n"
          "  --knots N          override the task's knot count\n"
          "  --refine           refine the at-rest plan against the FE transient (a task\n"
          "                     with dynamics; the settings of dynamics.refine, else its\n"
          "                     defaults; docs/planner.md): the written plan is the refined\n"
          "                     one, the summary's \"refine\" object lists every evaluation;\n"
          "                     with dynamics.robust also against the FE transients of the\n"
          "                     four corner arms (each corner within robust residual_m);\n"
          "                     not with --shape (usage error)\n"
          "  --shape zv         input-shape the plan with a zero-vibration shaper whose delay\n"
          "                     follows the FE first frequency along the motion (half its\n"
          "                     period, the arm's damping ratio): the written trajectory is\n"
          "                     the shaped one, about half a period longer, checked against\n"
          "                     every limit (refused, exit 1, if it breaks one); the summary's\n"
          "                     \"shape\" object says how (docs/planner.md, \"ZV-shaped plans\");\n"
          "                     not with --refine or the task's dynamics.refine (usage error:\n"
          "                     the shaping would replace the refined trajectory)\n"
          "  --verify           run the FE transient of the written trajectory (as 'elasticarm\n"
          "                     simulate' does by default: 12 elements, generalized-alpha,\n"
          "                     dt 1 ms, 3 s after the motion, the arm's damping) and report\n"
          "                     the measured residual vibration and time to rest beside the\n"
          "                     reduced model's prediction (summary: \"verify\"); it fails\n"
          "                     (exit 3, the plan and summary written, stderr says what was\n"
          "                     reached) if the transient fails, the FE cable tension falls\n"
          "                     below the tension limit (slack), or the residual peak exceeds\n"
          "                     the task's dynamics.residual_m (> 0) or, refined, the\n"
          "                     refinement's tolerance_m\n"
          "  --no-verify        no FE check of the plan's promise (as dynamics.verify: false):\n"
          "                     faster; the text says 'not checked by the FE'\n"
          "  --refine-by WHAT   what measures the check's (or --refine's) candidates (as\n"
          "                     dynamics.refine.by): fe (default), model (the nonlinear reduced\n"
          "                     model until it predicts rest, then the FE verdict, the FE\n"
          "                     refining on where it fails), model_only (no FE transient: the\n"
          "                     text says 'not checked by the FE'); model needs 2 modes and no\n"
          "                     robust corners\n"
          "  --derivative-test  run Ipopt's first-order derivative checker\n"
          "  --print-level N    Ipopt's output (0 = silent); Ipopt only: a plan made by the\n"
          "                     planner's own interior point or active-set Newton prints no\n"
          "                     iterations (stderr then says which engine ran)\n"
          "  --quiet            no progress line\n\n"
          "exit: 0 plan written, 1 infeasible / not converged / shaping refused / an output\n"
          "not written, 2 usage or input error, 3 plan written but its FE check (the default\n"
          "check of a task with dynamics, or --verify) failed\n");
}

/* Remove an earlier output of a failed run: regular files only (never a
 * device such as /dev/null, never stdout). */
static void ea__remove_stale(const char *path) {
  struct stat sb;
  if (path && strcmp(path, "-") && lstat(path, &sb) == 0 && S_ISREG(sb.st_mode)) unlink(path);
}

/* Copy a file to stdout (the summary for --json). */
static void ea__cat(const char *path) {
  FILE *fp = fopen(path, "r");
  if (!fp) return;
  char buf[4096];
  size_t nr;
  while ((nr = fread(buf, 1, sizeof buf, fp)) > 0)
    fwrite(buf, 1, nr, stdout);
  fclose(fp);
}

/* What a plan adds to its summary: the refinement, the shaping, the verification, the run id
 * shared with the trajectory file. */
typedef struct {
  const ea_refine_info_t *ref;
  const ea_shape_info_t *shape;
  const ea_plan_verify_t *verify;
  const char *run_id;
} ea__plan_extra_t;

/* A run id unique across runs and hosts' processes: UTC time, pid and 32 random bits. */
static void ea__plan_run_id(char *buf, size_t len) {
  struct timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  struct tm tm;
  gmtime_r(&ts.tv_sec, &tm);
  unsigned rnd = (unsigned)ts.tv_nsec ^ ((unsigned)getpid() << 16);
  FILE *fp = fopen("/dev/urandom", "rb");
  if (fp) {
    if (fread(&rnd, sizeof rnd, 1, fp) != 1) rnd ^= (unsigned)ts.tv_nsec;
    fclose(fp);
  }
  char when[32];
  strftime(when, sizeof when, "%Y%m%dT%H%M%SZ", &tm);
  snprintf(buf, len, "%s-%ld-%08x", when, (long)getpid(), rnd);
}

/* The exclusive lock that serialises runs writing the same outputs: flock on OUT.lock (the
 * summary's when the trajectory goes to stdout). Returns the descriptor, -1 without a lock
 * (no file path, or the lock file cannot be made: a device such as /dev/null). */
static int ea__plan_lock(const char *out, const char *summary) {
  const char *base = strcmp(out, "-") ? out : summary;
  if (!base) return -1;
  char path[1100];
  snprintf(path, sizeof path, "%s.lock", base);
  const int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (fd < 0) return -1;
  while (flock(fd, LOCK_EX) != 0)
    if (errno != EINTR) {
      close(fd);
      return -1;
    }
  return fd;
}

static void ea__plan_unlock(int fd) {
  if (fd < 0) return;
  flock(fd, LOCK_UN);
  close(fd);
}

/* Write the converged plan: trajectory (with the run id) and summary to temporaries, then,
 * holding the outputs' lock, rename the trajectory, then the summary. On failure nothing of
 * this run is left (the caller then treats the plan as failed). */
static ea_status_t ea__plan_write(ea_planner_t *pl, const ea_traj_t *tr, const ea_plan_info_t *info,
                                  const ea__plan_extra_t *x, const char *out, const char *summary,
                                  ea_error_t *err) {
  char ttmp[1100] = "", stmp[1100] = "";
  ea_status_t st = EA_OK;
  const int to_stdout = !strcmp(out, "-");
  ea_traj_t trx = *tr; /* the same samples, with the run id */
  snprintf(trx.run_id, sizeof trx.run_id, "%s", x->run_id);
  if (!to_stdout) {
    snprintf(ttmp, sizeof ttmp, "%s.tmp%ld.traj", out, (long)getpid());
    st = ea_traj_write(&trx, ttmp, err);
    if (st) ttmp[0] = '\0';
  }
  if (!st && summary) {
    snprintf(stmp, sizeof stmp, "%s.tmp%ld.json", summary, (long)getpid());
    st = ea_plan_summary_write_ex(pl, info, x->ref, x->shape, x->verify, x->run_id, stmp, err);
    if (st) stmp[0] = '\0';
  }
  if (!st && to_stdout) st = ea_traj_write(&trx, "-", err);
  const int lock = st ? -1 : ea__plan_lock(out, summary);
  if (!st && ttmp[0]) {
    if (rename(ttmp, out) != 0)
      st = ea_error_set(err, EA_ERR_IO, "%s: cannot write: %s", out, strerror(errno));
    else
      ttmp[0] = '\0';
  }
  if (!st && stmp[0]) {
    if (rename(stmp, summary) != 0)
      st = ea_error_set(err, EA_ERR_IO, "%s: cannot write: %s", summary, strerror(errno));
    else
      stmp[0] = '\0';
  }
  ea__plan_unlock(lock);
  if (ttmp[0]) unlink(ttmp);
  if (stmp[0]) unlink(stmp);
  return st;
}

/* --shape zv: the plan's trajectory shaped in place; the summary's duration, tension margin
 * and torque become the written trajectory's. On failure info says why. */
static ea_status_t ea__plan_shape(const ea_task_t *task, ea_traj_t *tr, ea_plan_info_t *info,
                                  ea_shape_info_t *si) {
  ea_traj_t shaped = {0};
  ea_error_t err = {0};
  const ea_status_t st = ea_traj_shape_zv(task, tr, NULL, &shaped, si, &err);
  if (st) {
    info->status = st;
    snprintf(info->message, sizeof info->message, "the plan converged (%.6g s) but %.440s",
             info->duration_s, err.msg);
    return st;
  }
  ea_traj_free(tr);
  *tr = shaped;
  info->duration_s = si->duration_s;
  info->min_tension_margin_N = si->check.min_tension_margin_N;
  info->peak_shoulder_torque_Nm = si->check.peak_shoulder_torque_Nm;
  char plan_msg[sizeof info->message];
  snprintf(plan_msg, sizeof plan_msg, "%s", info->message);
  snprintf(info->message, sizeof info->message, "%.200s; %.300s", plan_msg, si->message);
  return EA_OK;
}

/* --verify: the FE transient of the trajectory to be written (ea_traj_simulate with its
 * defaults: what `elasticarm simulate FILE` runs) and the model's prediction for it. */
static void ea__plan_verify(const ea_planner_t *pl, const ea_task_t *task, const ea_traj_t *tr,
                            const ea_plan_info_t *info, const ea_refine_info_t *ref, int shaped,
                            ea__cli_progress_t *prog, ea_plan_verify_t *v) {
  memset(v, 0, sizeof *v);
  ea_sim_settings_default(&v->settings);
  v->settings.progress = ea__cli_progress_fe;
  v->settings.progress_data = prog;
  ea_error_t err = {0};
  v->status = ea_traj_simulate(&task->arm, tr, 0.0, &v->settings, NULL, &v->sim, &err);
  if (v->status) snprintf(v->message, sizeof v->message, "%s", err.msg);
  /* the bounds the written plan claims: the task's residual bound, else the refinement's
   * tolerance; the cable taut at the task's tension limit */
  v->residual_bound_m = task->dynamics.modes > 0 && task->dynamics.residual_m > 0
                            ? task->dynamics.residual_m
                        : ref ? ref->settings.tolerance_m
                              : NAN;
  v->tension_bound_N = task->limits.tension_min;
  ea_plan_verify_judge(v);
  v->predicted_residual_m = NAN;
  v->predicted_time_to_rest_s = NAN;
  double blo = INFINITY, bhi = -INFINITY;
  for (int k = 0; k < tr->n; ++k) {
    blo = fmin(blo, EA_TRAJ_AT(tr, k, EA_TRAJ_base_angle));
    bhi = fmax(bhi, EA_TRAJ_AT(tr, k, EA_TRAJ_base_angle));
  }
  v->base_travel_rad = bhi >= blo ? bhi - blo : 0.0;
  /* the nonlinear reduced model's prediction beside the FE's measure (2 modes) */
  v->predicted_nonlinear_residual_m = NAN;
  const ea_rom_table_t *tn = ea_planner_rom_table(pl);
  if (tn && task->dynamics.modes == EA_ROMNL_MODES) {
    ea_romnl_t *nl = NULL;
    ea_rom_prediction_t pn;
    if (!ea_romnl_alloc(&task->arm, ea_arm_tip_mass(&task->arm, task->payload_kg), 0, &nl, NULL) &&
        !ea_traj_romnl_sample(nl, tn, tr, EA_ROMNL_SAMPLES, NULL) &&
        !ea_traj_romnl_predict(tn, nl, tr, 1e-4, v->settings.settle, &pn, NULL, NULL))
      v->predicted_nonlinear_residual_m = pn.residual_peak;
    ea_romnl_free(nl);
  }
  if (!shaped) {
    v->predicted_residual_m = info->predicted_residual_m;
    if (isfinite(info->predicted_residual_m))
      v->predicted_time_to_rest_s = info->predicted_time_to_rest_s;
    return;
  }
  /* a shaped plan: the reduced model (if the task has one) along the shaped trajectory */
  const ea_rom_table_t *tb = ea_planner_rom_table(pl);
  ea_rom_prediction_t pr;
  if (tb && ea_traj_rom_predict(tb, tr, 1e-4, v->settings.settle, &pr, NULL) == EA_OK) {
    double sum = 0.0;
    for (int i = 0; i < pr.modes; ++i)
      sum += pr.amplitude_m[i];
    v->predicted_residual_m = sum;
  }
}

/* The verify lines of the text summary; refined: the refinement moved the model's terminal
 * targets (its prediction then describes the model's own state, not the FE's). */
static void ea__plan_verify_text(const ea_plan_verify_t *v, int refined) {
  if (v->status) {
    printf("verify: the FE transient failed: %s\n", v->message);
    return;
  }
  const ea_sim_info_t *si = &v->sim;
  char rest[160], pred[300];
  if (isfinite(si->time_to_rest) && si->time_to_rest <= si->duration)
    snprintf(rest, sizeof rest, "within %.3g mm of rest when the motion ends",
             1e3 * v->settings.rest_tolerance);
  else if (isfinite(si->time_to_rest))
    snprintf(rest, sizeof rest, "within %.3g mm of rest %.4g s after the motion",
             1e3 * v->settings.rest_tolerance, si->time_to_rest - si->duration);
  else
    snprintf(rest, sizeof rest, "not within %.3g mm of rest %.3g s after the motion",
             1e3 * v->settings.rest_tolerance, v->settings.settle);
  char nl[80] = "";
  if (isfinite(v->predicted_nonlinear_residual_m))
    snprintf(nl, sizeof nl, ", the nonlinear reduced model %.4f mm",
             1e3 * v->predicted_nonlinear_residual_m);
  if (isfinite(v->predicted_residual_m))
    snprintf(pred, sizeof pred, "the reduced model predicted %.4f mm%s%s",
             1e3 * v->predicted_residual_m,
             refined ? " about the targets the refinement moved to cancel what it misses" : "", nl);
  else
    snprintf(pred, sizeof pred, "no model prediction (quasi-static plan)");
  printf("verify: FE residual vibration peak %.4f mm, rms %.4f mm (damping ratio %.3g), %s; %s\n",
         1e3 * si->residual_peak, 1e3 * si->residual_rms, si->damping_ratio, rest, pred);
  if (v->base_travel_rad > 0)
    printf("verify: the FE transient is planar (the arm in its plane): the base turns %.4g deg in "
           "this plan and the rotation's loads (out-of-plane bending from its angular "
           "acceleration, centrifugal and Coriolis forces) are not in the residual above\n",
           v->base_travel_rad / EA__DEG);
  printf(
      "verify: FE cable tension %.4f N (t = %.4g s) .. %.4f N over the motion and the settle%s\n",
      si->tension_min, si->tension_min_time, si->tension_max,
      si->tension_min > 0 ? "" : ": the cable went slack");
}

/* The command line of `elasticarm plan` and the outputs it resolves to. */
struct ea__plan_run;
static void ea__plan_check_text(const struct ea__plan_run *r);

typedef struct {
  const char *task_path, *out, *summary, *figure;
  int json, quiet, dtest, refine, shape, verify, no_verify, have_by;
  ea_task_refine_by_t by; /* --refine-by (have_by) */
  long knots, plevel;
  char out_buf[1024], sum_buf[1024], fig_buf[1024];
} ea__plan_opts_t;

static const ea__cli_opt_t ea__plan_opts[] = {
    {"help", 0, 'h'},          {"output", 1, 'o'},  {"summary", 1, 0},
    {"figure", 1, 0},          {"json", 0, 0},      {"quiet", 0, 0},
    {"derivative-test", 0, 0}, {"refine", 0, 0},    {"verify", 0, 0},
    {"shape", 1, 0},           {"knots", 1, 0},     {"print-level", 1, 0},
    {"no-verify", 0, 0},       {"refine-by", 1, 0}, {NULL, 0, 0}};

/* Parse the options into o. Returns -1 to go on, else the exit code (0 after --help). */
static int ea__plan_parse(const char *cmd, int argc, char **argv, ea__plan_opts_t *o) {
  memset(o, 0, sizeof *o);
  o->plevel = -1;
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, ea__plan_opts);
  int r;
  while ((r = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt, *v = g.arg;
    if (!a) {
      if (o->task_path) return ea__cli_usage_error(cmd, "more than one task file ('%s')", v);
      o->task_path = v;
    } else if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
      ea__plan_help(stdout);
      return EA_EXIT_OK;
    } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
      o->out = v;
    } else if (!strcmp(a, "--summary")) {
      o->summary = v;
    } else if (!strcmp(a, "--figure")) {
      o->figure = v;
    } else if (!strcmp(a, "--json")) {
      o->json = 1;
    } else if (!strcmp(a, "--quiet")) {
      o->quiet = 1;
    } else if (!strcmp(a, "--derivative-test")) {
      o->dtest = 1;
    } else if (!strcmp(a, "--refine")) {
      o->refine = 1;
    } else if (!strcmp(a, "--verify")) {
      o->verify = 1;
    } else if (!strcmp(a, "--no-verify")) {
      o->no_verify = 1;
    } else if (!strcmp(a, "--refine-by")) {
      if (ea_task_refine_by_from_name(v, &o->by))
        return ea__cli_usage_error(cmd, "--refine-by: '%s' is not one of fe, model, model_only", v);
      o->have_by = 1;
    } else if (!strcmp(a, "--shape")) {
      if (strcmp(v, "zv"))
        return ea__cli_usage_error(cmd, "--shape: '%s' is not a shaper (known: zv)", v);
      o->shape = 1;
    } else if (!strcmp(a, "--knots")) {
      if (ea__cli_int(cmd, a, v, 3, 4000, &o->knots)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--print-level")) {
      if (ea__cli_int(cmd, a, v, 0, 12, &o->plevel)) return EA_EXIT_USAGE;
    }
  }
  if (r < 0) return EA_EXIT_USAGE;
  if (!o->task_path) return ea__cli_usage_error(cmd, "no task file (see elasticarm plan --help)");
  return -1;
}

/* The trajectory, summary and figure paths (options, else the task's outputs, else NAME.csv
 * and its .json), checked before the work. 0 or the exit code. */
static int ea__plan_outputs(const char *cmd, const ea_task_t *task, ea__plan_opts_t *o) {
  if (!o->out)
    o->out = ea_task_output_path(task, task->out_trajectory, o->out_buf, sizeof o->out_buf);
  if (!o->out) {
    /* The name is free text: never a path (no folders, no hidden file). */
    char safe[128];
    ea__cli_safe_name(task->name, "plan", safe, sizeof safe);
    snprintf(o->out_buf, sizeof o->out_buf, "%s.csv", safe);
    o->out = o->out_buf;
  }
  const char *out = o->out;
  if (!o->summary)
    o->summary = ea_task_output_path(task, task->out_summary, o->sum_buf, sizeof o->sum_buf);
  if (!o->summary && strcmp(out, "-")) {
    ea__replace_ext(out, ".json", o->sum_buf, sizeof o->sum_buf);
    o->summary = o->sum_buf;
  }
  if (!o->figure)
    o->figure = ea_task_output_path(task, task->out_figure, o->fig_buf, sizeof o->fig_buf);
  const char *summary = o->summary, *figure = o->figure;
  if (summary && !strcmp(summary, "-"))
    return ea__cli_usage_error(cmd, "--summary -: use --json for the summary on stdout");
  if (o->json && !strcmp(out, "-"))
    return ea__cli_usage_error(cmd, "--json and -o - both want stdout");
  if ((summary && !strcmp(summary, out)) ||
      (figure && (!strcmp(figure, out) || (summary && !strcmp(figure, summary)))))
    return ea__cli_usage_error(cmd,
                               "the trajectory, summary and figure need three different "
                               "paths (trajectory %s, summary %s, figure %s)",
                               out, summary ? summary : "-", figure ? figure : "none");
  /* Every output checked before the work (this also clears a killed run's temporaries). */
  int rc = ea__cli_check_output(cmd, out);
  if (!rc && summary) rc = ea__cli_check_output(cmd, summary);
  if (!rc && figure) rc = ea__cli_check_figure(cmd, figure);
  return rc;
}

/* A plan run: the planner, the written plan's info and what its summary adds. */
typedef struct ea__plan_run {
  ea_planner_t *pl;
  ea_plan_info_t info;
  ea_refine_info_t *ref;
  ea_shape_info_t *shp;
  ea_plan_verify_t *ver;
  char run_id[64];                    /**< shared by the trajectory and the summary */
  ea__cli_progress_t prog;            /* the command's clock and progress lines */
  double time_shape_s, time_verify_s; /* [s] wall time of --shape, --verify */
  const char *no_check; /* why the FE did not check the plan's promise (NULL: it did, or the
                           task promises nothing: no dynamics) */
} ea__plan_run_t;

static void ea__plan_run_free(ea__plan_run_t *r) {
  free(r->ref);
  free(r->shp);
  free(r->ver);
  ea_planner_free(r->pl);
}

/* The line that says whether the FE checked the plan's promise and what it measured. */
static void ea__plan_check_text(const ea__plan_run_t *r) {
  /* the verdict: a residual bound's (or --verify's) FE transient at the default settings,
   * else the refinement's last one */
  if (r->ver && isfinite(r->ver->residual_bound_m) && r->ver->status == EA_OK)
    printf("checked by the FE (dt %g ms, %g s after the motion): residual peak %.4g mm %s bound "
           "%.4g mm\n",
           1e3 * r->ver->settings.dt, r->ver->settings.settle, 1e3 * r->ver->sim.residual_peak,
           r->ver->sim.residual_peak <= r->ver->residual_bound_m ? "within" : "NOT within",
           1e3 * r->ver->residual_bound_m);
  else if (r->ref && r->ref->status == EA_OK && r->ref->settings.by == EA_TASK_REFINE_BY_MODEL_ONLY)
    printf("not checked by the FE (dynamics.refine.by: model_only): the nonlinear reduced model "
           "predicts a residual peak of %.4g mm\n",
           1e3 * r->ref->residual_peak_m);
  else if (r->ref && r->ref->status == EA_OK)
    printf("checked by the FE (dt %g ms, %g s after the motion): residual peak %.4g mm %s bound "
           "%.4g mm\n",
           1e3 * r->ref->fe.dt, r->ref->fe.settle, 1e3 * r->ref->residual_peak_m,
           r->ref->converged ? "within" : "NOT within", 1e3 * r->ref->settings.tolerance_m);
  else if (r->no_check)
    printf("not checked by the FE (%s)\n", r->no_check);
}

/* The refinement's progress: a line per evaluation once the command has run a second. */
static void ea__plan_refine_progress(void *data, int evaluation, int max_evaluations,
                                     double elapsed_s, double residual_peak_m) {
  if (isfinite(residual_peak_m))
    ea__cli_progress(data, 1,
                     "refinement: evaluation %d of at most %d, FE residual peak %.4g mm (%.1f s)",
                     evaluation + 1, max_evaluations, 1e3 * residual_peak_m, elapsed_s);
  else /* the candidate's targets could not be planned within the limits (or its FE failed) */
    ea__cli_progress(data, 1,
                     "refinement: evaluation %d of at most %d: no plan or FE transient for its "
                     "targets (%.1f s)",
                     evaluation + 1, max_evaluations, elapsed_s);
}

/* --refine (or the task's dynamics.refine): the refinement of the converged plan. The
 * summary describes the written (refined) plan; iterations and solve times stay those of
 * the at-rest plan, the refinement's are in its own object. */
static ea_status_t ea__plan_refine_cli(const ea_task_t *task, ea__plan_run_t *r, ea_error_t *err) {
  ea_plan_info_t *info = &r->info;
  r->ref = calloc(1, sizeof *r->ref);
  ea_plan_info_t rinfo;
  const ea_status_t rst = r->ref ? ea_plan_rest_refine(r->pl, &rinfo, r->ref, err) : EA_ERR_NOMEM;
  if (rst) {
    info->status = rst;
    snprintf(info->message, sizeof info->message, "refinement failed: %.480s",
             r->ref ? r->ref->message : "out of memory");
    return rst;
  }
  const ea_plan_info_t cold = *info;
  if (r->ref->returned > 0) *info = rinfo; /* else the cold plan, measured once, is kept */
  info->iterations = cold.iterations;
  info->time_total_s = cold.time_total_s;
  info->time_guess_s = cold.time_guess_s;
  info->time_statics_s = cold.time_statics_s;
  info->time_ipopt_s = cold.time_ipopt_s;
  info->time_rest_s = cold.time_rest_s;
  info->between_passes = cold.between_passes;
  /* the engine of those iterations (the summary's "engine"), not that of the last replan */
  info->ipopt_status = cold.ipopt_status;
  snprintf(info->ipopt_status_name, sizeof info->ipopt_status_name, "%s", cold.ipopt_status_name);
  info->newton_steps = cold.newton_steps;
  info->ipopt_rows = cold.ipopt_rows;
  info->screen_resolves = cold.screen_resolves;
  info->ipm_iterations = cold.ipm_iterations;
  info->ipm_fallback = cold.ipm_fallback;
  if (!r->ref->converged) /* the summary's message: what was reached, not "plan found" */
    snprintf(info->message, sizeof info->message,
             "plan written but NOT %s: the FE residual peak %.4g mm exceeds the bound %.4g "
             "mm after %d evaluation%s (stopped: %s; duration %.6g s)",
             task->dynamics.residual_m > 0 ? "within its residual bound" : "at rest",
             1e3 * r->ref->residual_peak_m, 1e3 * r->ref->settings.tolerance_m, r->ref->n_evals,
             r->ref->n_evals == 1 ? "" : "s", r->ref->stop_reason, info->duration_s);
  return EA_OK;
}

/* A failed plan (st) or unwritten outputs (wst, werr): no trajectory or figure of an
 * earlier run stays beside the failure summary, which is written (and printed with
 * --json). Returns the exit code. */
static int ea__plan_failed(const ea__plan_opts_t *o, ea__plan_run_t *r, ea_status_t st,
                           ea_status_t wst, const ea_error_t *werr) {
  ea_plan_info_t *info = &r->info;
  const int lock = ea__plan_lock(o->out, o->summary); /* not between another run's renames */
  ea__remove_stale(o->out);
  ea__remove_stale(o->figure);
  if (wst) {
    info->status = wst;
    char why[sizeof info->message];
    snprintf(why, sizeof why, "%s", werr->msg);
    snprintf(info->message, sizeof info->message,
             "the plan converged but its outputs could not be written: %.400s", why);
    fprintf(stderr, "elasticarm plan: error: %s\n", werr->msg);
  } else {
    fprintf(stderr, "elasticarm plan: %s: %s\n", st == EA_ERR_INFEASIBLE ? "infeasible" : "failed",
            info->message);
  }
  if (info->deriv_errors >= 0)
    fprintf(stderr, "elasticarm plan: derivative checker: %d error(s)\n", info->deriv_errors);
  int wrote = 0;
  if (o->summary) {
    ea_error_t e2 = {0};
    if (ea_plan_summary_write_ex(r->pl, info, r->ref, r->shp && r->shp->status ? r->shp : NULL,
                                 NULL, r->run_id, o->summary, &e2))
      fprintf(stderr, "elasticarm plan: error: %s\n", e2.msg);
    else
      wrote = 1;
  }
  ea__plan_unlock(lock);
  if (o->json && wrote) ea__cat(o->summary);
  return EA_EXIT_FAIL;
}

/* The figure of what was written: the shaped trajectory (read back), else the plan's.
 * 0 or EA_EXIT_FAIL. */
static int ea__plan_figure_cli(const ea__plan_opts_t *o, const ea_task_t *task,
                               const ea__plan_run_t *r) {
  ea_error_t err = {0};
  ea_status_t st = EA_OK;
  /* what an FE transient of the written trajectory measured: --verify's, else the
   * refinement's of the plan it returned */
  double fe_peak = NAN;
  const char *fe_check = NULL;
  if (r->ver && r->ver->status == EA_OK) {
    fe_peak = r->ver->sim.residual_peak;
    fe_check = "plan --verify";
  } else if (r->ref && !o->shape && r->ref->settings.by != EA_TASK_REFINE_BY_MODEL_ONLY) {
    fe_peak = r->ref->residual_peak_m;
    fe_check = "refinement";
  }
  if (o->shape) {
    ea_traj_t ft = {0};
    ea_shooter_t *sh = NULL;
    st = ea_traj_read(&ft, o->out, &err);
    if (!st) st = ea_shooter_alloc(&task->arm, NULL, &sh, &err);
    if (!st) {
      const ea_load_t load = {ea_arm_tip_mass(&task->arm, task->payload_kg)};
      ea_shooter_set_load(sh, &load);
      char title[700];
      snprintf(title, sizeof title, "%s, ZV-shaped (tip mass %.3g kg)", task->name, load.tip_mass);
      ea_traj_figure_opts_t fo;
      ea_traj_figure_opts_default(&fo, &task->arm);
      fo.title = title;
      ea_traj_figure_opts_limits(&fo, &task->limits); /* which the shaping held */
      fo.fe_residual_peak_m = fe_peak;
      fo.fe_check = fe_check;
      st = ea_traj_figure(&ft, sh, &fo, o->figure, &err);
    }
    ea_shooter_free(sh);
    ea_traj_free(&ft);
  } else {
    st = ea_plan_figure_fe(r->pl, &r->info, fe_peak, fe_check, o->figure, &err);
  }
  if (!st) return 0;
  fprintf(stderr, "elasticarm plan: figure: %s\n", err.msg);
  return EA_EXIT_FAIL;
}

/* The engine in the time line's words. */
static const char *ea__plan_engine_label(const ea_plan_info_t *info) {
  const char *e = ea_plan_engine_name(info);
  if (!strcmp(e, "interior-point-ldl")) return "interior point (LDL)";
  if (!strcmp(e, "active-set-newton")) return "active-set Newton";
  if (!strcmp(e, "kkt-test")) return "KKT test";
  return "Ipopt";
}

/* What a written plan reports: the summary (--json) or the progress lines; a failed
 * verification, an unconverged refinement and --print-level without Ipopt on stderr.
 * Returns rc, or EA_EXIT_VERIFY when rc is 0 and --verify failed. */
static int ea__plan_report(const ea__plan_opts_t *o, const ea__plan_run_t *r, int rc) {
  const ea_plan_info_t *info = &r->info;
  const char *out = o->out, *summary = o->summary, *figure = o->figure;
  ea__cli_progress_end((ea__cli_progress_t *)&r->prog);
  if (o->json && summary) {
    ea__cat(summary);
  } else if (!o->quiet && strcmp(out, "-")) {
    printf("%s\n", info->message);
    if (r->ref) printf("%s\n", r->ref->message);
    ea__plan_check_text(r);
    printf("wrote %s%s%s%s%s\n", out, summary ? ", " : "", summary ? summary : "",
           figure && !rc ? ", " : "", figure && !rc ? figure : "");
    /* the whole command's wall time, its phases named; what is left is reading the task,
     * writing the outputs and drawing the figure */
    const double total = ea__cli_progress_elapsed(&r->prog);
    double other = total - info->time_total_s - r->time_shape_s - r->time_verify_s;
    char extra[400] = "";
    int u = 0;
    if (r->ref) {
      char nl[80] = "";
      if (r->ref->settings.by != EA_TASK_REFINE_BY_FE)
        snprintf(nl, sizeof nl, ", nonlinear reduced model %.2f", 1e3 * r->ref->time_model_s);
      u += snprintf(extra + u, sizeof extra - (size_t)u,
                    ", refinement %.2f (%d evaluation%s: re-plans %.2f, FE transients %.2f%s)",
                    1e3 * r->ref->time_s, r->ref->n_evals, r->ref->n_evals == 1 ? "" : "s",
                    1e3 * r->ref->time_plan_s, 1e3 * r->ref->time_fe_s, nl);
      other -= r->ref->time_s;
    }
    if (o->shape && u >= 0 && (size_t)u < sizeof extra)
      u +=
          snprintf(extra + u, sizeof extra - (size_t)u, ", ZV shaping %.2f", 1e3 * r->time_shape_s);
    if (r->ver && u >= 0 && (size_t)u < sizeof extra)
      snprintf(extra + u, sizeof extra - (size_t)u, ", --verify FE transient %.2f",
               1e3 * r->time_verify_s);
    printf("time: %.2f ms total: plan %.2f (guess %.2f, statics Jacobians %.2f, %s %.2f, rest "
           "%.2f)%s, task, outputs and figure %.2f; %d variables, %d constraints; %d thread%s\n",
           1e3 * total, 1e3 * info->time_total_s, 1e3 * info->time_guess_s,
           1e3 * info->time_statics_s, ea__plan_engine_label(info), 1e3 * info->time_ipopt_s,
           1e3 * info->time_rest_s, extra, 1e3 * fmax(other, 0.0), info->n_var, info->n_con,
           info->threads, info->threads == 1 ? "" : "s");
    if (info->deriv_errors >= 0) printf("derivative checker: %d error(s)\n", info->deriv_errors);
    if (r->ver) ea__plan_verify_text(r->ver, r->ref && r->ref->returned > 0);
  }
  if (r->ver && !r->ver->passed) {
    fprintf(stderr, "elasticarm plan: error: %s failed for %s (written, with its summary): %s\n",
            o->verify ? "--verify" : "the FE check of the residual bound", out, r->ver->failure);
    if (!rc) rc = EA_EXIT_VERIFY;
  }
  if (o->plevel > 0 && strcmp(ea_plan_engine_name(info), "ipopt"))
    fprintf(stderr,
            "elasticarm plan: note: --print-level applies to Ipopt only; this plan was made by "
            "the %s (%d iterations), which prints no iterations\n",
            ea__plan_engine_label(info), info->iterations);
  if (r->ref && !r->ref->converged) {
    fprintf(stderr,
            "elasticarm plan: error: the plan does not keep its promise of %s: %s (written, "
            "with its summary: the best plan evaluated)\n",
            ea_planner_task(r->pl)->dynamics.residual_m > 0 ? "a residual bound" : "rest",
            info->message);
    if (!rc) rc = EA_EXIT_VERIFY;
  }
  return rc;
}

int ea__cli_plan(int argc, char **argv) {
  const char *cmd = "plan";
  ea__plan_opts_t o;
  ea__plan_run_t r = {0};
  ea__cli_progress_init(&r.prog, cmd, 1);
  int rc = ea__plan_parse(cmd, argc, argv, &o);
  if (rc >= 0) return rc;
  r.prog.on = !o.quiet;

  ea_task_t task;
  ea_error_t err = {0};
  task.arm_warning[0] = '\0'; /* set by the load once it read the arm file */
  ea_status_t st = ea_task_load(o.task_path, ea__cli_default_arm(), &task, &err);
  if (task.arm_warning[0]) fprintf(stderr, "elasticarm plan: warning: %s\n", task.arm_warning);
  if (st == EA_ERR_INFEASIBLE) {
    fprintf(stderr, "elasticarm plan: infeasible task: %s\n", err.msg);
    return EA_EXIT_FAIL;
  }
  if (st) return ea__cli_fail(cmd, st, &err);
  if (o.knots) task.knots = (int)o.knots;
  if (o.dtest) task.solver.derivative_test = 1;
  if (o.refine) task.dynamics.refine.enabled = 1;
  if (o.no_verify) task.dynamics.verify = 0;
  if (o.have_by) task.dynamics.refine.by = o.by;
  task.dynamics.refine.progress = ea__plan_refine_progress;
  task.dynamics.refine.progress_data = &r.prog;
  if (o.plevel >= 0) task.solver.print_level = (int)o.plevel;
  if (o.shape && task.dynamics.refine.enabled)
    return ea__cli_usage_error(
        cmd,
        "--shape zv and %s cannot be combined: the refinement tunes the plan against the FE "
        "transient, the shaping would then write another trajectory than the refined one "
        "(and report the refinement for it); choose one",
        o.refine ? "--refine" : "the task's dynamics.refine (--refine)");
  if ((st = ea_task_check(&task, &err))) return ea__cli_fail(cmd, st, &err);
  if ((rc = ea__plan_outputs(cmd, &task, &o))) return rc;

  ea__plan_run_id(r.run_id, sizeof r.run_id);
  if ((st = ea_planner_alloc(&task, &r.pl, &err))) return ea__cli_fail(cmd, st, &err);
  ea_plan_dyn_info_t di;
  if (ea_planner_dyn_model(r.pl, &di) == EA_OK && di.cache_message[0])
    fprintf(stderr, "elasticarm %s: warning: reduced-model cache: %s\n", cmd, di.cache_message);
  st = ea_planner_solve(r.pl, EA_PLAN_COLD, NULL, &r.info, &err);
  /* the promise of rest or of a residual bound: refined until the FE holds it (explicit
   * refine, or the default check; not for a shaped plan); a bound's verdict by --verify's FE */
  const ea_rest_check_t check = o.shape ? EA_REST_CHECK_NONE : ea_plan_rest_check(&task);
  if (task.dynamics.modes > 0 && check == EA_REST_CHECK_NONE && !task.dynamics.refine.enabled)
    r.no_check = o.shape                                   ? "a ZV-shaped plan: --verify checks it"
                 : task.objective == EA_TASK_MIN_VIBRATION ? "min_vibration promises no rest"
                 : o.no_verify                             ? "plan --no-verify"
                                                           : "dynamics.verify: false";
  if (!st && (task.dynamics.refine.enabled || check != EA_REST_CHECK_NONE))
    st = ea__plan_refine_cli(&task, &r, &err);
  /* The trajectory to write: the plan's, shaped with --shape; --verify simulates it. */
  ea_traj_t tr = {0};
  r.shp = o.shape ? calloc(1, sizeof *r.shp) : NULL;
  ea_error_t werr = {0};
  ea_status_t wst = EA_OK;
  if (o.shape && !r.shp) wst = ea_error_set(&werr, EA_ERR_NOMEM, "out of memory");
  if (!st && !wst) wst = ea_planner_trajectory(r.pl, &tr, &werr);
  double t_phase = ea__mono_s();
  if (!st && !wst && o.shape) st = ea__plan_shape(&task, &tr, &r.info, r.shp);
  r.time_shape_s = ea__mono_s() - t_phase;
  t_phase = ea__mono_s();
  if (!st && !wst && (o.verify || check == EA_REST_CHECK_BOUND)) {
    if ((r.ver = calloc(1, sizeof *r.ver)))
      ea__plan_verify(r.pl, &task, &tr, &r.info, r.ref, o.shape, &r.prog, r.ver);
    else
      wst = ea_error_set(&werr, EA_ERR_NOMEM, "out of memory");
  }
  r.time_verify_s = ea__mono_s() - t_phase;
  const ea__plan_extra_t extra = {r.ref, r.shp, r.ver, r.run_id};
  if (!st && !wst) wst = ea__plan_write(r.pl, &tr, &r.info, &extra, o.out, o.summary, &werr);
  ea_traj_free(&tr);
  if (st || wst) {
    ea__cli_progress_end(&r.prog);
    rc = ea__plan_failed(&o, &r, st, wst, &werr);
  } else {
    rc = o.figure ? ea__plan_figure_cli(&o, &task, &r) : 0;
    rc = ea__plan_report(&o, &r, rc);
  }
  ea__plan_run_free(&r);
  return rc;
}
