/* elasticarm plan: task spec -> trajectory file + JSON summary (+ figure). */
#include "cli_impl.h"
#include "ea_refine.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void ea__plan_help(FILE *fp) {
  fprintf(fp,
          "usage: elasticarm plan TASK.yaml [-o OUT.csv] [--summary OUT.json] [--json]\n"
          "                       [--figure OUT.svg|png|pdf] [--knots N] [--refine]\n"
          "                       [--shape zv] [--verify] [--derivative-test]\n"
          "                       [--print-level N] [--quiet]\n\n"
          "Plans an admissible trajectory for the task (docs/task-format.md, docs/planner.md)\n"
          "and writes the trajectory file (docs/trajectory-format.md) and a JSON summary next\n"
          "to it (OUT.json). Defaults: the task's outputs, else NAME.csv in the current\n"
          "folder, NAME being the task's name reduced to a safe file name (letters, digits,\n"
          "'-', '_', '.', '+'; no folders, no leading dot).\n\n"
          "Outputs: every path is checked (writable, figure extension known) before the\n"
          "work. A converged plan writes the trajectory and the summary to temporaries,\n"
          "renames the trajectory, then the summary, then draws the figure. A plan that\n"
          "fails (infeasible, not converged) or whose trajectory cannot be written writes\n"
          "only the summary, with the failure status, and removes an earlier trajectory\n"
          "and figure of the same names, so a summary never sits beside a trajectory it\n"
          "does not describe. Temporaries ('NAME.tmp<pid>.*') left by a killed run are\n"
          "removed by the next run writing the same outputs.\n\n"
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
          "                     four corner arms (each corner within robust residual_m)\n"
          "  --shape zv         input-shape the plan with a zero-vibration shaper whose delay\n"
          "                     follows the FE first frequency along the motion (half its\n"
          "                     period, the arm's damping ratio): the written trajectory is\n"
          "                     the shaped one, about half a period longer, checked against\n"
          "                     every limit (refused, exit 1, if it breaks one); the summary's\n"
          "                     \"shape\" object says how (docs/planner.md, \"ZV-shaped plans\")\n"
          "  --verify           run the FE transient of the written trajectory (as 'elasticarm\n"
          "                     simulate' does by default: 12 elements, generalized-alpha,\n"
          "                     dt 1 ms, 3 s after the motion, the arm's damping) and report\n"
          "                     the measured residual vibration and time to rest beside the\n"
          "                     reduced model's prediction (summary: \"verify\")\n"
          "  --derivative-test  run Ipopt's first-order derivative checker\n"
          "  --print-level N    Ipopt output (0 = silent)\n"
          "  --quiet            no progress line\n\n"
          "exit: 0 plan written, 1 infeasible / not converged / shaping refused / an output\n"
          "not written / the --verify transient failed (the plan is written then), 2 usage\n"
          "or input error\n");
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

/* Write the converged plan: trajectory and summary to temporaries, then
 * rename the trajectory, then the summary. On failure nothing of this run
 * is left (the caller then treats the plan as failed). */
/* What a plan adds to its summary: the refinement, the shaping, the verification. */
typedef struct {
  const ea_refine_info_t *ref;
  const ea_shape_info_t *shape;
  const ea_plan_verify_t *verify;
} ea__plan_extra_t;

static ea_status_t ea__plan_write(ea_planner_t *pl, const ea_traj_t *tr, const ea_plan_info_t *info,
                                  const ea__plan_extra_t *x, const char *out, const char *summary,
                                  ea_error_t *err) {
  char ttmp[1100] = "", stmp[1100] = "";
  ea_status_t st = EA_OK;
  const int to_stdout = !strcmp(out, "-");
  if (!to_stdout) {
    snprintf(ttmp, sizeof ttmp, "%s.tmp%ld.traj", out, (long)getpid());
    st = ea_traj_write(tr, ttmp, err);
    if (st) ttmp[0] = '\0';
  }
  if (!st && summary) {
    snprintf(stmp, sizeof stmp, "%s.tmp%ld.json", summary, (long)getpid());
    st = ea_plan_summary_write_ex(pl, info, x->ref, x->shape, x->verify, stmp, err);
    if (st) stmp[0] = '\0';
  }
  if (!st && to_stdout) st = ea_traj_write(tr, "-", err);
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
                            const ea_plan_info_t *info, int shaped, ea_plan_verify_t *v) {
  memset(v, 0, sizeof *v);
  ea_sim_settings_default(&v->settings);
  ea_error_t err = {0};
  v->status = ea_traj_simulate(&task->arm, tr, 0.0, &v->settings, NULL, &v->sim, &err);
  if (v->status) snprintf(v->message, sizeof v->message, "%s", err.msg);
  v->predicted_residual_m = NAN;
  v->predicted_time_to_rest_s = NAN;
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

/* The verify line of the text summary. */
static void ea__plan_verify_text(const ea_plan_verify_t *v) {
  if (v->status) {
    printf("verify: the FE transient failed: %s\n", v->message);
    return;
  }
  const ea_sim_info_t *si = &v->sim;
  char rest[160], pred[160];
  if (isfinite(si->time_to_rest) && si->time_to_rest <= si->duration)
    snprintf(rest, sizeof rest, "within %.3g mm of rest when the motion ends",
             1e3 * v->settings.rest_tolerance);
  else if (isfinite(si->time_to_rest))
    snprintf(rest, sizeof rest, "within %.3g mm of rest %.4g s after the motion",
             1e3 * v->settings.rest_tolerance, si->time_to_rest - si->duration);
  else
    snprintf(rest, sizeof rest, "not within %.3g mm of rest %.3g s after the motion",
             1e3 * v->settings.rest_tolerance, v->settings.settle);
  if (isfinite(v->predicted_residual_m))
    snprintf(pred, sizeof pred, "the reduced model predicted %.4f mm",
             1e3 * v->predicted_residual_m);
  else
    snprintf(pred, sizeof pred, "no model prediction (quasi-static plan)");
  printf("verify: FE residual vibration peak %.4f mm, rms %.4f mm (damping ratio %.3g), %s; %s\n",
         1e3 * si->residual_peak, 1e3 * si->residual_rms, si->damping_ratio, rest, pred);
  printf(
      "verify: FE cable tension %.4f N (t = %.4g s) .. %.4f N over the motion and the settle%s\n",
      si->tension_min, si->tension_min_time, si->tension_max,
      si->tension_min > 0 ? "" : ": the cable went slack");
}

int ea__cli_plan(int argc, char **argv) {
  const char *cmd = "plan";
  const char *task_path = NULL, *out = NULL, *summary = NULL, *figure = NULL;
  int json = 0, quiet = 0, dtest = 0, refine = 0, shape = 0, verify = 0;
  long knots = 0, plevel = -1;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
      ea__plan_help(stdout);
      return EA_EXIT_OK;
    } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
      if (!(out = ea__cli_value(cmd, argc, argv, &i))) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--summary")) {
      if (!(summary = ea__cli_value(cmd, argc, argv, &i))) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--figure")) {
      if (!(figure = ea__cli_value(cmd, argc, argv, &i))) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--json")) {
      json = 1;
    } else if (!strcmp(a, "--quiet")) {
      quiet = 1;
    } else if (!strcmp(a, "--derivative-test")) {
      dtest = 1;
    } else if (!strcmp(a, "--refine")) {
      refine = 1;
    } else if (!strcmp(a, "--verify")) {
      verify = 1;
    } else if (!strcmp(a, "--shape")) {
      const char *v = ea__cli_value(cmd, argc, argv, &i);
      if (!v) return EA_EXIT_USAGE;
      if (strcmp(v, "zv"))
        return ea__cli_usage_error(cmd, "--shape: '%s' is not a shaper (known: zv)", v);
      shape = 1;
    } else if (!strcmp(a, "--knots")) {
      const char *v = ea__cli_value(cmd, argc, argv, &i);
      if (!v || ea__cli_int(cmd, a, v, 3, 4000, &knots)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--print-level")) {
      const char *v = ea__cli_value(cmd, argc, argv, &i);
      if (!v || ea__cli_int(cmd, a, v, 0, 12, &plevel)) return EA_EXIT_USAGE;
    } else if (a[0] == '-' && a[1]) {
      return ea__cli_usage_error(cmd, "unknown option '%s' (see elasticarm plan --help)", a);
    } else if (!task_path) {
      task_path = a;
    } else {
      return ea__cli_usage_error(cmd, "more than one task file ('%s')", a);
    }
  }
  if (!task_path) return ea__cli_usage_error(cmd, "no task file (see elasticarm plan --help)");

  ea_task_t task;
  ea_error_t err = {0};
  ea_status_t st = ea_task_load(task_path, ea__cli_default_arm(), &task, &err);
  if (st == EA_ERR_INFEASIBLE) {
    fprintf(stderr, "elasticarm plan: infeasible task: %s\n", err.msg);
    return EA_EXIT_FAIL;
  }
  if (st) return ea__cli_fail(cmd, st, &err);
  if (knots) task.knots = (int)knots;
  if (dtest) task.solver.derivative_test = 1;
  if (refine) task.dynamics.refine.enabled = 1;
  if (plevel >= 0) task.solver.print_level = (int)plevel;
  if ((st = ea_task_check(&task, &err))) return ea__cli_fail(cmd, st, &err);

  char out_buf[1024], sum_buf[1024], fig_buf[1024];
  if (!out) out = ea_task_output_path(&task, task.out_trajectory, out_buf, sizeof out_buf);
  if (!out) {
    /* The name is free text: never a path (no folders, no hidden file). */
    char safe[128];
    ea__cli_safe_name(task.name, "plan", safe, sizeof safe);
    snprintf(out_buf, sizeof out_buf, "%s.csv", safe);
    out = out_buf;
  }
  if (!summary) summary = ea_task_output_path(&task, task.out_summary, sum_buf, sizeof sum_buf);
  if (!summary && strcmp(out, "-")) {
    ea__replace_ext(out, ".json", sum_buf, sizeof sum_buf);
    summary = sum_buf;
  }
  if (!figure) figure = ea_task_output_path(&task, task.out_figure, fig_buf, sizeof fig_buf);
  if (summary && !strcmp(summary, "-"))
    return ea__cli_usage_error(cmd, "--summary -: use --json for the summary on stdout");
  if (json && !strcmp(out, "-"))
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
  if (rc) return rc;

  ea_planner_t *pl = NULL;
  if ((st = ea_planner_alloc(&task, &pl, &err))) return ea__cli_fail(cmd, st, &err);
  ea_plan_info_t info;
  st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &err);
  ea_refine_info_t *ref = NULL;
  if (!st && task.dynamics.refine.enabled) {
    /* The summary describes the written (refined) plan; iterations and solve times stay
     * those of the at-rest plan, the refinement's are in its own object. */
    if (!quiet && !json && strcmp(out, "-")) printf("%s\n", info.message);
    ref = calloc(1, sizeof *ref);
    ea_plan_info_t rinfo;
    const ea_status_t rst = ref ? ea_plan_refine(pl, NULL, &rinfo, ref, &err) : EA_ERR_NOMEM;
    if (rst) {
      st = info.status = rst;
      snprintf(info.message, sizeof info.message, "refinement failed: %.480s",
               ref ? ref->message : "out of memory");
    } else {
      const ea_plan_info_t cold = info;
      info = rinfo;
      info.iterations = cold.iterations;
      info.time_total_s = cold.time_total_s;
      info.time_guess_s = cold.time_guess_s;
      info.time_statics_s = cold.time_statics_s;
      info.time_ipopt_s = cold.time_ipopt_s;
      info.time_rest_s = cold.time_rest_s;
      info.between_passes = cold.between_passes;
    }
  }
  /* The trajectory to write: the plan's, shaped with --shape; --verify simulates it. */
  ea_traj_t tr = {0};
  ea_shape_info_t *shp = shape ? calloc(1, sizeof *shp) : NULL;
  ea_plan_verify_t *ver = NULL;
  ea_error_t werr = {0};
  ea_status_t wst = EA_OK;
  if (shape && !shp) wst = ea_error_set(&werr, EA_ERR_NOMEM, "out of memory");
  if (!st && !wst) wst = ea_planner_trajectory(pl, &tr, &werr);
  if (!st && !wst && shape) st = ea__plan_shape(&task, &tr, &info, shp);
  if (!st && !wst && verify) {
    if ((ver = calloc(1, sizeof *ver)))
      ea__plan_verify(pl, &task, &tr, &info, shape, ver);
    else
      wst = ea_error_set(&werr, EA_ERR_NOMEM, "out of memory");
  }
  const ea__plan_extra_t extra = {ref, shp, ver};
  if (!st && !wst) wst = ea__plan_write(pl, &tr, &info, &extra, out, summary, &werr);
  ea_traj_free(&tr);
  if (st || wst) {
    /* Failed: no trajectory or figure of an earlier run stays beside the
     * failure summary. */
    ea__remove_stale(out);
    ea__remove_stale(figure);
    if (wst) {
      info.status = wst;
      char why[sizeof info.message];
      snprintf(why, sizeof why, "%s", werr.msg);
      snprintf(info.message, sizeof info.message,
               "the plan converged but its outputs could not be written: %.400s", why);
      fprintf(stderr, "elasticarm plan: error: %s\n", werr.msg);
    } else {
      fprintf(stderr, "elasticarm plan: %s: %s\n",
              st == EA_ERR_INFEASIBLE ? "infeasible" : "failed", info.message);
    }
    if (info.deriv_errors >= 0)
      fprintf(stderr, "elasticarm plan: derivative checker: %d error(s)\n", info.deriv_errors);
    int wrote = 0;
    if (summary) {
      ea_error_t e2 = {0};
      if (ea_plan_summary_write_ex(pl, &info, ref, shp && shp->status ? shp : NULL, NULL, summary,
                                   &e2))
        fprintf(stderr, "elasticarm plan: error: %s\n", e2.msg);
      else
        wrote = 1;
    }
    if (json && wrote) ea__cat(summary);
    free(ref);
    free(shp);
    free(ver);
    ea_planner_free(pl);
    return EA_EXIT_FAIL;
  }
  if (figure && shape) {
    /* the figure of what was written: the shaped trajectory */
    ea_traj_t ft = {0};
    ea_shooter_t *sh = NULL;
    st = ea_traj_read(&ft, out, &err);
    if (!st) st = ea_shooter_alloc(&task.arm, NULL, &sh, &err);
    if (!st) {
      const ea_load_t load = {ea_arm_tip_mass(&task.arm, task.payload_kg)};
      ea_shooter_set_load(sh, &load);
      char title[700];
      snprintf(title, sizeof title, "%s, ZV-shaped (tip mass %.3g kg)", task.name, load.tip_mass);
      ea_traj_figure_opts_t o;
      ea_traj_figure_opts_default(&o, &task.arm);
      o.title = title;
      ea_traj_figure_opts_limits(&o, &task.limits); /* which the shaping held */
      st = ea_traj_figure(&ft, sh, &o, figure, &err);
    }
    ea_shooter_free(sh);
    ea_traj_free(&ft);
    if (st) {
      fprintf(stderr, "elasticarm plan: figure: %s\n", err.msg);
      rc = EA_EXIT_FAIL;
    }
  } else if (figure && (st = ea_plan_figure(pl, &info, figure, &err))) {
    fprintf(stderr, "elasticarm plan: figure: %s\n", err.msg);
    rc = EA_EXIT_FAIL;
  }
  if (json && summary) {
    ea__cat(summary);
  } else if (!quiet && strcmp(out, "-")) {
    printf("%s\n", ref ? ref->message : info.message);
    printf("wrote %s%s%s%s%s\n", out, summary ? ", " : "", summary ? summary : "",
           figure && !rc ? ", " : "", figure && !rc ? figure : "");
    printf("time: %.2f ms total (guess %.2f, statics Jacobians %.2f, Ipopt %.2f, rest %.2f); "
           "%d variables, %d constraints\n",
           1e3 * info.time_total_s, 1e3 * info.time_guess_s, 1e3 * info.time_statics_s,
           1e3 * info.time_ipopt_s, 1e3 * info.time_rest_s, info.n_var, info.n_con);
    if (info.deriv_errors >= 0) printf("derivative checker: %d error(s)\n", info.deriv_errors);
    if (ver) ea__plan_verify_text(ver);
  }
  if (ver && ver->status) {
    fprintf(stderr, "elasticarm plan: error: --verify: the FE transient of %s failed: %s\n", out,
            ver->message);
    rc = EA_EXIT_FAIL;
  }
  if (ref && !ref->converged)
    fprintf(stderr,
            "elasticarm plan: warning: the refinement did not reach its tolerance (%s); the "
            "written plan is the best one evaluated\n",
            ref->stop_reason);
  free(ref);
  free(shp);
  free(ver);
  ea_planner_free(pl);
  return rc;
}
