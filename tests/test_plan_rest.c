/* Plans that arrive at rest (task key dynamics), judged by the FE transient (ea_traj_simulate,
 * 12 elements, undamped, 3 s after the motion), the ground truth the reduced model is not:
 *  - the paper line at payload factors 0, 0.25 and 0.5 (goal moved in to (0.5, -0.2) where 0.5
 *    makes the paper's goal inadmissible): duration within 1.25 x the quasi-static minimum,
 *    FE residual <= 1 mm (payload 0: also <= 1.60 s), and a small fraction of the
 *    quasi-static plan's (what the model misses);
 *  - a plan allowed a residual (residual_m 5 mm, active at the minimum time): the FE residual
 *    is what the model predicts for it;
 *  - pick-place-3d and polyline-effort made dynamic;
 *  - min_vibration redone on the model against the f1-weighted surrogate and min_effort;
 *  - tasks without the key: the path transcription gives the knot transcription's duration to
 *    1e-9 (the same feasible set). */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_simulate.h"
#include "ea_test.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *src;

static int load(const char *name, ea_task_t *t) {
  char path[1024];
  snprintf(path, sizeof path, "%s/problems/examples/%s", src, name);
  ea_error_t e;
  if (ea_task_load(path, NULL, t, &e)) {
    printf("%s: %s\n", name, e.msg);
    return 1;
  }
  return 0;
}

/* Plan t; the trajectory into tr, info into *info; returns the status. */
static ea_status_t plan(ea_task_t *t, ea_traj_t *tr, ea_plan_info_t *info) {
  ea_error_t e;
  ea_planner_t *pl = NULL;
  ea_status_t st = ea_task_check(t, &e);
  if (!st) st = ea_planner_alloc(t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, info, &e);
  if (!st && tr) st = ea_planner_trajectory(pl, tr, &e);
  if (st) printf("  plan: %s\n", e.msg);
  ea_planner_free(pl);
  return st;
}

static double fe_residual(const ea_task_t *t, const ea_traj_t *tr, double zeta, double *rest) {
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  s.damping_ratio = zeta;
  if (zeta > 0) s.settle = 60.0;
  ea_sim_info_t si;
  ea_error_t e;
  if (ea_traj_simulate(&t->arm, tr, 0.0, &s, NULL, &si, &e)) {
    printf("  simulate: %s\n", e.msg);
    return NAN;
  }
  if (rest) *rest = si.time_to_rest - si.duration;
  return si.residual_peak;
}

static void test_paper_line(void) {
  const double gammas[3] = {0.0, 0.25, 0.5};
  for (int c = 0; c < 3; ++c) {
    ea_task_t t;
    if (load("paper-line.yaml", &t)) return;
    t.payload_factor = gammas[c];
    t.payload_kg = ea_arm_payload_from_factor(&t.arm, gammas[c]);
    if (c == 2) t.goal = ea_task_point_planar(0.5, -0.2, 0.0);
    ea_traj_t qs = {0}, dy = {0};
    ea_plan_info_t iq, id;
    const int okq = plan(&t, &qs, &iq) == EA_OK;
    t.dynamics.modes = 2;
    const int okd = plan(&t, &dy, &id) == EA_OK;
    char w[200];
    snprintf(w, sizeof w, "payload factor %.2f: quasi-static and at-rest plans", gammas[c]);
    ea_test_true(okq && okd, w);
    if (!okq || !okd) continue;
    double rest_d = NAN, rest_q = NAN;
    const double rq = fe_residual(&t, &qs, 0.0, NULL), rd = fe_residual(&t, &dy, 0.0, NULL);
    fe_residual(&t, &qs, 0.02, &rest_q);
    fe_residual(&t, &dy, 0.02, &rest_d);
    printf("payload factor %.2f: quasi-static %.5f s, FE residual %.3f mm (rest within 1 mm "
           "%.2f s after the motion at 2 %% damping); at rest %.5f s (x %.3f, %d iterations, "
           "%.0f ms), FE residual %.4f mm (%.2f %% of the quasi-static; rest %.2f s after)\n",
           gammas[c], iq.duration_s, 1e3 * rq, rest_q, id.duration_s, id.duration_s / iq.duration_s,
           id.iterations, 1e3 * id.time_total_s, 1e3 * rd, 100 * rd / rq, rest_d);
    snprintf(w, sizeof w, "payload factor %.2f: at-rest duration within 1.25 x the minimum",
             gammas[c]);
    ea_test_true(id.duration_s <= 1.25 * iq.duration_s, w);
    /* what the model misses, as a share of the quasi-static residual: measured 1.1 %, 2.5 %,
     * 5.1 % (payload 0.5: heavier, larger deflections); tolerance 2x */
    snprintf(w, sizeof w, "payload factor %.2f: FE residual < %s of the quasi-static's", gammas[c],
             c < 2 ? "5 %" : "10 %");
    ea_test_true(rd < (c < 2 ? 0.05 : 0.10) * rq, w);
    if (c < 2) {
      snprintf(w, sizeof w, "payload factor %.2f: FE residual peak <= 1 mm", gammas[c]);
      ea_test_true(rd <= 1e-3, w);
    }
    if (c == 0) {
      ea_test_true(id.duration_s <= 1.60, "payload 0: at rest in <= 1.60 s");
      /* the stretch goal of the issue: measured 0.23 mm in 1.445 s */
      ea_test_true(rd <= 0.3e-3 && id.duration_s <= 1.57,
                   "payload 0: FE residual <= 0.3 mm in <= 1.57 s");
    }
    ea_traj_free(&qs);
    ea_traj_free(&dy);
  }
}

/* A plan allowed 5 mm of residual ends with the model's modal amplitude at 5 mm (the limit is
 * active at the minimum time): the FE transient's residual is that amplitude, within what the
 * model misses. */
static void test_terminal_state(void) {
  ea_task_t t;
  if (load("paper-line.yaml", &t)) return;
  t.dynamics.modes = 2;
  t.dynamics.residual_m = 5e-3;
  ea_traj_t tr = {0};
  ea_plan_info_t info;
  if (plan(&t, &tr, &info)) {
    ea_test_true(0, "residual_m 5 mm plan");
    return;
  }
  const double fe = fe_residual(&t, &tr, 0.0, NULL);
  printf("residual_m 5 mm: %.5f s; the model's terminal amplitude %.4f mm (modes %.4f, %.4f), "
         "FE residual %.4f mm\n",
         info.duration_s, 1e3 * info.predicted_residual_m, 1e3 * info.predicted_amplitude_m[0],
         1e3 * info.predicted_amplitude_m[1], 1e3 * fe);
  /* the plan holds sum_i |tip_i|^2 a_i^2 <= r^2 / K: the amplitude is at most 5 mm (7.07 for
   * two modes in phase); measured FE vs model: within 5 % */
  ea_test_rel(fe, info.predicted_residual_m, 0.10,
              "FE residual = the model's terminal modal amplitude (10 %)");
  ea_traj_free(&tr);
}

static void test_other_examples(void) {
  const char *names[2] = {"pick-place-3d.yaml", "polyline-effort.yaml"};
  for (int c = 0; c < 2; ++c) {
    ea_task_t t;
    if (load(names[c], &t)) return;
    ea_traj_t qs = {0}, dy = {0};
    ea_plan_info_t iq, id;
    const int okq = plan(&t, &qs, &iq) == EA_OK;
    t.dynamics.modes = 2;
    const int okd = plan(&t, &dy, &id) == EA_OK;
    ea_test_true(okq && okd, names[c]);
    if (!okq || !okd) continue;
    const double rq = fe_residual(&t, &qs, 0.0, NULL), rd = fe_residual(&t, &dy, 0.0, NULL);
    printf("%s: quasi-static %.4f s, FE residual %.3f mm; at rest %.4f s, FE residual %.4f mm "
           "(%.1f %%)\n",
           names[c], iq.duration_s, 1e3 * rq, id.duration_s, 1e3 * rd, 100 * rd / rq);
    /* measured 0.2 % (pick-place: the in-plane motion shaped within the base's time) and
     * 11 % (polyline: the via point's corner); tolerances 2x */
    char w[160];
    snprintf(w, sizeof w, "%s made dynamic: FE residual < %s of the quasi-static's", names[c],
             c ? "25 %" : "1 %");
    ea_test_true(rd < (c ? 0.25 : 0.01) * rq, w);
    ea_traj_free(&qs);
    ea_traj_free(&dy);
  }
}

/* min_vibration on the model (3 s): the FE residual against the f1-weighted surrogate and
 * min_effort, both without the model */
static void test_min_vibration(void) {
  double r[3];
  const ea_task_objective_t obj[3] = {EA_TASK_MIN_VIBRATION, EA_TASK_MIN_EFFORT,
                                      EA_TASK_MIN_VIBRATION};
  for (int c = 0; c < 3; ++c) {
    ea_task_t t;
    if (load("paper-line.yaml", &t)) return;
    t.objective = obj[c];
    t.duration_s = 3.0;
    t.dynamics.modes = c == 2 ? 2 : 0;
    ea_traj_t tr = {0};
    ea_plan_info_t info;
    r[c] = plan(&t, &tr, &info) == EA_OK ? fe_residual(&t, &tr, 0.0, NULL) : NAN;
    ea_traj_free(&tr);
  }
  printf("3 s paper line, FE residual: min_vibration (f1 surrogate) %.4f mm, min_effort %.4f mm, "
         "min_vibration on the reduced model %.4f mm\n",
         1e3 * r[0], 1e3 * r[1], 1e3 * r[2]);
  /* measured 2.48, 0.97 and 0.009 mm */
  ea_test_true(r[2] < 0.05 * r[1] && r[2] < 0.05 * r[0],
               "min_vibration on the model: < 5 % of min_effort's and the surrogate's residual");
}

/* The path transcription against the knot transcription on tasks without the key. */
static void test_transcriptions(void) {
  const char *names[3] = {"paper-line.yaml", "polyline-effort.yaml", "paper-line.yaml"};
  for (int c = 0; c < 3; ++c) {
    ea_task_t t;
    if (load(names[c], &t)) return;
    if (c == 2) t.payload_kg = ea_arm_payload_from_factor(&t.arm, 0.25);
    ea_plan_info_t ik, ip;
    ea_traj_t tk = {0}, tp = {0};
    t.solver.transcription = EA_TASK_TRANSCRIPTION_KNOTS;
    const int ok1 = plan(&t, &tk, &ik) == EA_OK;
    t.solver.transcription = EA_TASK_TRANSCRIPTION_PATH;
    const int ok2 = plan(&t, &tp, &ip) == EA_OK;
    double dq = 0.0;
    for (int i = 0; ok1 && ok2 && i < tk.n && i < tp.n; ++i)
      for (int col = 0; col < EA_TRAJ_NCOL; ++col)
        dq = fmax(dq, fabs(EA_TRAJ_AT(&tk, i, col) - EA_TRAJ_AT(&tp, i, col)));
    printf("%s%s: knots %.15g s (%d iterations, %.0f ms), path %.15g s (%d iterations, %.0f "
           "ms); trajectories differ by %.2e at most\n",
           names[c], c == 2 ? " (payload 0.25)" : "", ik.duration_s, ik.iterations,
           1e3 * ik.time_total_s, ip.duration_s, ip.iterations, 1e3 * ip.time_total_s, dq);
    char w[160];
    snprintf(w, sizeof w, "%s: path transcription = knot transcription (duration, 1e-9)", names[c]);
    ea_test_true(ok1 && ok2 && fabs(ip.duration_s - ik.duration_s) <= 1e-9 * ik.duration_s, w);
    ea_traj_free(&tk);
    ea_traj_free(&tp);
  }
  /* with dynamics: the at-rest paper line in both transcriptions (the knot transcription's
   * statics rows against the path's splines to 1e-9) at 100 and 200 knots, where the knot
   * transcription's adaptive barrier once failed after 500 iterations (monotone now: 111);
   * measured agreement 1.1e-7 / 2.4e-7 relative (the splines' and the polish's tolerances) */
  const int kn[2] = {100, 200};
  for (int c = 0; c < 2; ++c) {
    ea_task_t t;
    if (load("paper-line-rest.yaml", &t)) return;
    t.knots = kn[c];
    ea_plan_info_t ik, ip;
    t.solver.transcription = EA_TASK_TRANSCRIPTION_KNOTS;
    const int ok1 = plan(&t, NULL, &ik) == EA_OK;
    t.solver.transcription = EA_TASK_TRANSCRIPTION_PATH;
    const int ok2 = plan(&t, NULL, &ip) == EA_OK;
    printf("paper-line-rest, %d knots: knots %.12g s (%d iterations), path %.12g s (%d)\n", kn[c],
           ik.duration_s, ik.iterations, ip.duration_s, ip.iterations);
    char w[160];
    snprintf(w, sizeof w,
             "at rest, %d knots: both transcriptions converge to the same duration "
             "(1e-6)",
             kn[c]);
    ea_test_true(ok1 && ok2 && fabs(ip.duration_s - ik.duration_s) <= 1e-6 * ik.duration_s, w);
  }
}

int main(void) {
  gsl_set_error_handler_off();
  src = getenv("EA_SOURCE_DIR");
  if (!src) {
    printf("EA_SOURCE_DIR not set (run through ctest)\n");
    return EXIT_FAILURE;
  }
  test_transcriptions();
  test_paper_line();
  test_terminal_state();
  test_other_examples();
  test_min_vibration();
  return ea_test_summary("test_plan_rest");
}
