/* Robust refinement against the FE transients of the corner arms (docs/planner.md, "Robust
 * rest"; planner/plan_refine.c with dynamics.robust). References are outside the refinement:
 *  - the residual vibration of the returned plan at each corner arm is measured again by an
 *    independent FE transient of the written and re-read trajectory file: the arm file's hand
 *    mass and EI changed (tip mass from the arm, not passed), dt 0.25 ms instead of the loop's
 *    2 ms, 12 elements, undamped, 3 s after the motion (the measurement);
 *  - every limit of the task and arm is re-checked from the written file at 1 kHz
 *    (tests/ea_plan_check.h: the statics solved at every sample);
 *  - the bounds: residual peak <= 1 mm at each corner (tip mass +-20 %, EI +-5 %),
 *    duration <= 1.70 s;
 *  - the JSON summary lists every evaluation with its five residuals.
 * Beside them it prints the corner residuals of the non-robust at-rest plan
 * (paper-line-rest.yaml) and of the unrefined robust plan. */
#include "ea_plan_check.h"
#include "ea_planner.h"
#include "ea_refine.h"
#include "ea_test.h"
#include "ea_test_task.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char src[1024];

static int load(const char *name, ea_task_t *t) {
  return ea_test_load_example(src, name, t);
}

/* Independent FE residual peaks of trajectory tr at the nominal arm (c = 0) and the four
 * corners c = 1..4 (tip mass m (1 -+ 0.2), EI (1 -+ 0.05), light/heavy x soft/stiff): the arm's
 * hand mass and EI changed, the tip mass the arm's hand plus the file's payload (0 here). */
static void fe_corners(const ea_task_t *t, const ea_traj_t *tr, double peak[5]) {
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  s.elements = 12;
  s.dt = 2.5e-4;
  s.settle = 3.0;
  s.damping_ratio = 0.0;
  for (int c = 0; c < 5; ++c) {
    ea_arm_t arm = t->arm;
    if (c > 0) {
      arm.m_hand *= c == 1 || c == 3 ? 0.8 : 1.2;
      arm.EI *= c <= 2 ? 0.95 : 1.05;
    }
    ea_sim_info_t si;
    ea_error_t e = {0};
    peak[c] = NAN;
    if (ea_traj_simulate(&arm, tr, -1.0, &s, NULL, &si, &e))
      printf("fine FE, arm %d: %s\n", c, e.msg);
    else
      peak[c] = si.residual_peak;
  }
}

static const char *const corner_name[5] = {"nominal", "light, soft", "heavy, soft", "light, stiff",
                                           "heavy, stiff"};

static void print_peaks(const char *what, double duration, const double p[5]) {
  printf("  %-34s %.4f s:", what, duration);
  for (int c = 0; c < 5; ++c)
    printf(" %s %.4f mm%s", corner_name[c], 1e3 * p[c], c < 4 ? "," : "\n");
}

/* Write tr with the planner's writer, read it back, re-check every limit at 1 kHz; the file's
 * trajectory into back. Returns the worst relative excess (<= 0: held). */
static double write_read_check(const ea_task_t *t, const ea_traj_t *tr, ea_traj_t *back) {
  char path[] = "/tmp/ea_test_refine_robust_XXXXXX";
  ea_error_t e = {0};
  const int fd = mkstemp(path);
  if (fd < 0) return INFINITY;
  close(fd);
  double w = INFINITY;
  if (!ea_traj_write(tr, path, &e) && !ea_traj_read(back, path, &e)) {
    ea_chk_t c;
    w = ea_chk_traj(t, back, 1000.0, &c);
    ea_chk_print("robust refined plan (file)", &c);
  } else {
    printf("file: %s\n", e.msg);
  }
  remove(path);
  return w;
}

/* A robust task with a residual bound (residual_m 5 mm), refined by the default check: the
 * nominal is held to 5 mm, each corner to its robust residual_m + 0.5 mm (not + 5 mm), and
 * the fine FE at the corners agrees. */
static void bound_corners(const ea_task_t *robust, ea_refine_info_t *ri) {
  ea_task_t t = *robust;
  t.dynamics.residual_m = 0.005;
  ea_planner_t *pl = NULL;
  ea_plan_info_t pi;
  ea_traj_t tr;
  memset(&tr, 0, sizeof tr);
  ea_error_t e = {0};
  ea_status_t st = ea_task_check(&t, &e);
  if (!st) st = ea_planner_alloc(&t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &pi, &e);
  if (!st) st = ea_plan_rest_refine(pl, &pi, ri, &e);
  if (!st) st = ea_planner_trajectory(pl, &tr, &e);
  double p[5] = {NAN, NAN, NAN, NAN, NAN};
  if (!st) fe_corners(&t, &tr, p);
  if (!st) print_peaks("residual bound 5 mm, refined", ri->duration_s, p);
  const double corner = t.dynamics.robust_residual_m + EA_TASK_REST_TOLERANCE_M;
  char what[1200];
  snprintf(what, sizeof what,
           "residual bound 5 mm: refined (%s); bounds nominal %.4g mm, corners %.4g mm (robust "
           "residual_m + 0.5 mm)",
           st ? e.msg : ri->message, 1e3 * ri->allowed_m[0], 1e3 * ri->allowed_m[1]);
  ea_test_true(!st && ri->converged && ri->allowed_m[0] == 0.005 &&
                   fabs(ri->allowed_m[1] - corner) < 1e-15 &&
                   fabs(ri->allowed_m[4] - corner) < 1e-15,
               what);
  double worst = 0.0;
  for (int c = 1; c < 5; ++c)
    worst = fmax(worst, p[c]);
  snprintf(what, sizeof what,
           "residual bound 5 mm: fine FE (dt 0.25 ms, 3 s) nominal %.4f mm <= 5 mm, worst corner "
           "%.4f mm <= %.4g mm + 0.1 mm (the loop's FE against the fine one)",
           1e3 * p[0], 1e3 * worst, 1e3 * corner);
  ea_test_true(p[0] <= 0.005 && worst <= corner + 1e-4, what);
  ea_traj_free(&tr);
  ea_planner_free(pl);
}

int main(void) {
  const char *s = getenv("EA_SOURCE_DIR");
  snprintf(src, sizeof src, "%s", s ? s : ".");
  char what[600];

  /* the non-robust at-rest plan at the corner arms (printed beside, not asserted) */
  ea_task_t tr_;
  double rest[5] = {NAN, NAN, NAN, NAN, NAN}, rest_dur = NAN;
  if (!load("paper-line-rest.yaml", &tr_)) {
    ea_planner_t *pl = NULL;
    ea_plan_info_t pi;
    ea_traj_t tr;
    memset(&tr, 0, sizeof tr);
    ea_error_t e = {0};
    if (!ea_planner_alloc(&tr_, &pl, &e) && !ea_planner_solve(pl, EA_PLAN_COLD, NULL, &pi, &e) &&
        !ea_planner_trajectory(pl, &tr, &e)) {
      fe_corners(&tr_, &tr, rest);
      rest_dur = pi.duration_s;
      /* a planner without robust models has no corner to set */
      const double c[2] = {1e-3, 0.0};
      const ea_status_t sc = ea_planner_set_terminal_modes_model(pl, 1, c, c, &e);
      printf("  %s\n", e.msg);
      ea_test_true(sc == EA_ERR_ARG && strstr(e.msg, "model 1"),
                   "corner target on a non-robust planner: EA_ERR_ARG naming the model");
    } else {
      printf("paper-line-rest: %s\n", e.msg);
    }
    ea_traj_free(&tr);
    ea_planner_free(pl);
  }

  ea_task_t t;
  if (load("paper-line-robust.yaml", &t)) {
    ea_test_true(0, "load paper-line-robust.yaml");
    return ea_test_summary("test_refine_robust");
  }
  ea_test_true(t.dynamics.robust_tip_mass == 0.2 && t.dynamics.robust_EI == 0.05 &&
                   t.dynamics.modes == 1 && t.dynamics.robust_residual_m == 5e-4,
               "paper-line-robust.yaml: 1 mode, tip mass +-20 %, EI +-5 %, corners within 0.5 mm");
  ea_refine_info_t *ri = calloc(1, sizeof *ri);
  if (!ri) return EXIT_FAILURE;
  ea_planner_t *pl = NULL;
  ea_plan_info_t pi;
  ea_traj_t tr, back;
  memset(&tr, 0, sizeof tr);
  memset(&back, 0, sizeof back);
  ea_error_t e = {0};
  ea_status_t st = ea_planner_alloc(&t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &pi, &e);
  if (!st) {
    const double bad[1] = {NAN};
    ea_status_t sb = ea_planner_set_terminal_modes_model(pl, 5, NULL, NULL, &e);
    printf("  %s\n", e.msg);
    ea_test_true(sb == EA_ERR_ARG && strstr(e.msg, "model 5"),
                 "corner target of model 5 (of 5 models 0..4): EA_ERR_ARG");
    sb = ea_planner_set_terminal_modes_model(pl, 2, bad, NULL, &e);
    printf("  %s\n", e.msg);
    ea_test_true(sb == EA_ERR_ARG && strstr(e.msg, "not finite"),
                 "corner target NaN: EA_ERR_ARG (not finite)");
  }
  double unref[5] = {NAN, NAN, NAN, NAN, NAN}, unref_dur = NAN;
  if (!st) st = ea_planner_trajectory(pl, &tr, &e);
  if (!st) {
    fe_corners(&t, &tr, unref);
    unref_dur = pi.duration_s;
  }
  /* the task's refinement defaults; the wall-time cap out of the way so that the evaluations
   * (and the plan) do not depend on the machine's load: the budget is max_evaluations */
  ea_task_refine_t set;
  ea_task_refine_default(&set);
  set.max_time_s = 1e4;
  if (!st) st = ea_plan_refine(pl, &set, &pi, ri, &e);
  if (!st) st = ea_planner_trajectory(pl, &tr, &e);
  if (st) printf("plan and refine: %s\n", e.msg);
  ea_test_true(st == EA_OK, "paper line, robust: planned and refined");
  if (!st) {
    for (int i = 0; i < ri->n_evals; ++i) {
      const ea_refine_eval_t *v = &ri->evals[i];
      printf("  eval %d: plan %s (%d it), t_f %.6f s, FE peaks (loop, dt 2 ms) %.4f %.4f %.4f %.4f "
             "%.4f mm, score %.3f%s\n",
             i, ea_status_name(v->plan_status), v->plan_iterations, v->duration_s,
             1e3 * v->model_residual_peak_m[0], 1e3 * v->model_residual_peak_m[1],
             1e3 * v->model_residual_peak_m[2], 1e3 * v->model_residual_peak_m[3],
             1e3 * v->model_residual_peak_m[4], v->score,
             v->final_resolve ? " (final re-plan)" : "");
    }
    printf("  %s\n", ri->message);
    snprintf(what, sizeof what, "robust refinement converged (%s, %d evaluations, %.2f s)",
             ri->stop_reason, ri->n_evals, ri->time_s);
    ea_test_true(ri->status == EA_OK && ri->converged && ri->models == 5, what);
    /* the planner's own corner states: within robust residual_m of their centres (the rows),
     * not of zero (the centres moved) */
    const ea_refine_eval_t *er = &ri->evals[ri->returned];
    double about = 0.0, from0 = 0.0;
    for (int j = 1; j < 5; ++j) {
      const double *z = er->params_m + 2 * j, *p = er->predicted_m + 2 * j;
      about = fmax(about, hypot(p[0] - z[0], p[1] - z[1]));
      from0 = fmax(from0, hypot(p[0], p[1]));
    }
    snprintf(what, sizeof what,
             "returned plan: every corner model's state within %.4f mm of its centre (largest "
             "%.4f mm); from zero up to %.4f mm",
             1e3 * t.dynamics.robust_residual_m, 1e3 * about, 1e3 * from0);
    ea_test_true(about <= t.dynamics.robust_residual_m * (1.0 + 1e-6) &&
                     from0 > t.dynamics.robust_residual_m,
                 what);
    const double w = write_read_check(&t, &tr, &back);
    snprintf(what, sizeof what,
             "every limit held by the written robust refined trajectory at 1 kHz (worst relative "
             "excess %.3g, tolerance 0)",
             w);
    ea_test_true(w <= 0.0, what);
    snprintf(what, sizeof what,
             "tension margins of the refined plan: quasi-static %.4g N, with the modal part of "
             "every model %.4g N (>= 0)",
             pi.min_tension_margin_N, pi.min_dynamic_tension_margin_N);
    ea_test_true(pi.min_tension_margin_N >= 0.0 && pi.min_dynamic_tension_margin_N >= -1e-9, what);
    double ref[5];
    fe_corners(&t, &back, ref);
    const double dur = EA_TRAJ_AT(&back, back.n - 1, EA_TRAJ_t) - EA_TRAJ_AT(&back, 0, EA_TRAJ_t);
    print_peaks("non-robust at-rest plan (2 modes)", rest_dur, rest);
    print_peaks("robust plan", unref_dur, unref);
    print_peaks("robust refined plan", dur, ref);
    for (int c = 1; c <= 4; ++c) {
      /* measured 0.5225 / 0.5392 / 0.4893 / 0.3946 mm (loop at dt 2 ms: 0.5218 / 0.5387 /
       * 0.4891 / 0.3939): the 1 mm is 1.85 x the worst; the refinement's own bound,
       * robust residual_m + tolerance = 0.55 mm, holds by 11 um against a loop step error of
       * 1 um. Without the corner targets (the nominal's alone refined) the heavy, soft corner
       * measured 1.047 mm. */
      snprintf(what, sizeof what,
               "corner %d (%s): FE residual peak of the written refined plan at dt 0.25 ms %.4f "
               "mm <= 1 mm and <= robust residual_m + tolerance %.4f mm (unrefined robust plan "
               "%.4f mm)",
               c, corner_name[c], 1e3 * ref[c], 1e3 * ri->allowed_m[c], 1e3 * unref[c]);
      ea_test_true(ref[c] <= 1e-3 && ref[c] <= ri->allowed_m[c], what);
    }
    /* measured 0.0383 mm (loop 0.0377 mm): the refinement's tolerance 0.05 mm, the issue's
     * refined bound 0.3 mm */
    snprintf(what, sizeof what,
             "nominal arm: FE residual peak %.4f mm <= tolerance %.4f mm (unrefined %.4f mm)",
             1e3 * ref[0], 1e3 * ri->allowed_m[0], 1e3 * unref[0]);
    ea_test_true(ref[0] <= ri->allowed_m[0], what);
    /* measured 1.5246 s (unrefined 1.5845 s) */
    snprintf(what, sizeof what,
             "duration of the written refined plan %.4f s <= 1.70 s (unrefined %.4f s, returned "
             "%.4f s)",
             dur, unref_dur, ri->duration_s);
    ea_test_true(dur <= 1.70 && fabs(dur - ri->duration_s) <= 1e-12, what);

    /* the JSON summary: every evaluation with the five residuals */
    char jp[] = "/tmp/ea_test_refine_robust_json_XXXXXX";
    const int fd = mkstemp(jp);
    if (fd >= 0) close(fd);
    int ok = fd >= 0 && !ea_plan_summary_write_refined(pl, &pi, ri, jp, &e);
    char *buf = NULL;
    if (ok) {
      FILE *fp = fopen(jp, "r");
      buf = calloc(1, 1 << 20);
      ok = fp && buf && fread(buf, 1, (1 << 20) - 1, fp) > 0;
      if (fp) fclose(fp);
    }
    int logged = 0;
    for (const char *p = buf ? buf : ""; (p = strstr(p, "\"score\": ")); ++p)
      ++logged;
    snprintf(what, sizeof what,
             "JSON summary: \"models\": 5, per-model residuals, %d scores for %d evaluations + "
             "the returned plan",
             logged, ri->n_evals);
    ea_test_true(ok && strstr(buf, "\"models\": 5") &&
                     strstr(buf, "\"model_residual_peak_m\": [") &&
                     strstr(buf, "\"predicted_m\": [") && logged == ri->n_evals + 1,
                 what);
    free(buf);
    remove(jp);
  }
  ea_traj_free(&tr);
  ea_traj_free(&back);
  ea_planner_free(pl);
  pl = NULL;
  bound_corners(&t, ri);
  free(ri);
  return ea_test_summary("test_refine_robust");
}
