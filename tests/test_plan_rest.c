/* Plans that arrive at rest (task key dynamics), judged by the FE transient (ea_traj_simulate, 12
 * elements, undamped, 3 s after the motion), the ground truth the reduced model is not:
 *  - the paper line at payload factors 0, 0.25 and 0.5 (goal moved in to (0.5, -0.2) where 0.5
 *    makes the paper's goal inadmissible): duration within 1.25 x the quasi-static minimum and
 *    a small fraction of the quasi-static plan's residual (what the model misses); FE residual
 *    <= 1 mm at payloads 0 and 0.25 (payload 0: also <= 1.60 s), at 0.5 only after the
 *    refinement against the FE (unrefined: 2.10 mm, asserted <= 2.6 mm; why: the residual grows
 *    with the square of the modal deflection, measured with that deflection bounded); the
 *    refined plans <= 1 mm within 1.25 x at every payload; time to rest at 2 % damping of the
 *    quasi-static, at-rest and refined plans;
 *  - plans not at rest in the model (the quasi-static plans, residual_m 1 mm and 5 mm, the
 *    latter active at the minimum time): the model's predicted residual against the FE's, one
 *    stated factor;
 *  - pick-place-3d and polyline-effort made dynamic;
 *  - min_vibration redone on the model against the f1-weighted surrogate and min_effort;
 *  - tasks without the key: the path transcription gives the knot transcription's duration to
 *    1e-9 (the same feasible set). */
#include "ea_planner.h"
#include "ea_refine.h"
#include "ea_problems.h"
#include "ea_simulate.h"
#include "ea_test.h"
#include "ea_test_task.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *src;

/* the model's residual against the FE transient's on plans not at rest in the model
 * (test_prediction_factor): predicted >= 3 mm: within a factor 1.161 (the payload-0.5
 * residual_m 5 mm plan), stated 1.25; all of them, residual_m 1 mm too: |FE - predicted| at
 * most 0.92 x what the model misses at rest on the same task (the at-rest plan's FE residual),
 * stated 1.25 x */
#define PREDICTION_FACTOR 1.25
#define MISS_FACTOR 1.25

static int load(const char *name, ea_task_t *t) {
  return ea_test_load_example(src, name, t);
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

/* The FE transient's residual peak (undamped: 3 s after the motion; damped, zeta at mode 1:
 * settle s after it) and the time to rest within 1 mm after the motion. */
static double fe_residual_settle(const ea_task_t *t, const ea_traj_t *tr, double zeta,
                                 double settle, double *rest);
static double fe_residual(const ea_task_t *t, const ea_traj_t *tr, double zeta, double *rest) {
  return fe_residual_settle(t, tr, zeta, 60.0, rest);
}

static double fe_residual_settle(const ea_task_t *t, const ea_traj_t *tr, double zeta,
                                 double settle, double *rest) {
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  s.damping_ratio = zeta;
  if (zeta > 0) s.settle = settle;
  ea_sim_info_t si;
  ea_error_t e;
  if (ea_traj_simulate(&t->arm, tr, 0.0, &s, NULL, &si, &e)) {
    printf("  simulate: %s\n", e.msg);
    return NAN;
  }
  if (rest) *rest = si.time_to_rest - si.duration;
  return si.residual_peak;
}

/* Plans that are not at rest in the model (quasi-static plans, plans allowed a residual): the
 * model's predicted residual peak against the FE transient's, collected for one factor. */
enum { MAX_PAIRS = 16 };
static struct {
  char what[200];
  double predicted, measured, miss;
} pairs[MAX_PAIRS];
static int npairs;
static double rest_miss[3] = {NAN, NAN, NAN}; /* the at-rest paper line's FE residual by payload */

/* miss: the FE residual of the same task's at-rest plan (what the model misses at rest) */
static void add_pair(const char *what, double predicted, double measured, double miss) {
  printf("model vs FE: %s: predicted %.4f mm, FE %.4f mm, FE / predicted %.3f, |FE - predicted| "
         "%.4f mm = %.2f x the at-rest plan's FE residual\n",
         what, 1e3 * predicted, 1e3 * measured, measured / predicted,
         1e3 * fabs(measured - predicted), fabs(measured - predicted) / miss);
  if (npairs < MAX_PAIRS) {
    snprintf(pairs[npairs].what, sizeof pairs[npairs].what, "%s", what);
    pairs[npairs].predicted = predicted;
    pairs[npairs].measured = measured;
    pairs[npairs].miss = miss;
    ++npairs;
  }
}

/* The model's residual peak for a trajectory (the planner's table; 3 s after the motion, as
 * the FE transient). */
static double predicted(const ea_planner_t *pl, const ea_traj_t *tr) {
  ea_rom_prediction_t pr;
  ea_error_t e;
  if (ea_traj_rom_predict(ea_planner_rom_table(pl), tr, 1e-4, 3.0, &pr, &e)) {
    printf("  predict: %s\n", e.msg);
    return NAN;
  }
  return pr.residual_peak;
}

static void test_paper_line(void) {
  const double gammas[3] = {0.0, 0.25, 0.5};
  for (int c = 0; c < 3; ++c) {
    ea_task_t t;
    if (load("paper-line.yaml", &t)) return;
    t.payload_factor = gammas[c];
    t.payload_kg = ea_arm_payload_from_factor(&t.arm, gammas[c]);
    if (c == 2) t.goal = ea_task_point_planar(0.5, -0.2, 0.0);
    ea_traj_t qs = {0}, dy = {0}, rf = {0};
    ea_plan_info_t iq, id, ir;
    const int okq = plan(&t, &qs, &iq) == EA_OK;
    t.dynamics.modes = 2;
    /* the at-rest plan, kept for its table and its refinement */
    ea_planner_t *pl = NULL;
    ea_error_t e = {0};
    int okd = !ea_task_check(&t, &e) && !ea_planner_alloc(&t, &pl, &e) &&
              !ea_planner_solve(pl, EA_PLAN_COLD, NULL, &id, &e) &&
              !ea_planner_trajectory(pl, &dy, &e);
    if (!okd) printf("  plan: %s\n", e.msg);
    char w[200];
    snprintf(w, sizeof w, "payload factor %.2f: quasi-static and at-rest plans", gammas[c]);
    ea_test_true(okq && okd, w);
    if (!okq || !okd) {
      ea_planner_free(pl);
      continue;
    }
    double rest_d = NAN, rest_q = NAN, rest_r = NAN;
    const double rq = fe_residual(&t, &qs, 0.0, NULL), rd = fe_residual(&t, &dy, 0.0, NULL);
    /* the quasi-static plans: within 1 mm 24-33 s after the motion, 40 s suffice */
    const double pq = fe_residual_settle(&t, &qs, 0.02, 40.0, &rest_q);
    /* at rest and refined: within 1 mm in seconds, 20 s suffice */
    const double pd = fe_residual_settle(&t, &dy, 0.02, 20.0, &rest_d);
    printf("payload factor %.2f: quasi-static %.5f s, FE residual %.3f mm (rest within 1 mm "
           "%.2f s after the motion at 2 %% damping); at rest %.5f s (x %.3f, %d iterations, "
           "%.0f ms), FE residual %.4f mm (%.2f %% of the quasi-static; rest %.2f s after)\n",
           gammas[c], iq.duration_s, 1e3 * rq, rest_q, id.duration_s, id.duration_s / iq.duration_s,
           id.iterations, 1e3 * id.time_total_s, 1e3 * rd, 100 * rd / rq, rest_d);
    snprintf(w, sizeof w, "payload factor %.2f: quasi-static plan", gammas[c]);
    add_pair(w, predicted(pl, &qs), rq, rd);
    rest_miss[c] = rd;
    snprintf(w, sizeof w, "payload factor %.2f: at-rest duration within 1.25 x the minimum",
             gammas[c]);
    ea_test_true(id.duration_s <= 1.25 * iq.duration_s, w);
    /* what the model misses, as a share of the quasi-static residual: measured 1.1 %, 2.5 %,
     * 5.1 % (payload 0.5: heavier, larger deflections); tolerance 2x */
    snprintf(w, sizeof w, "payload factor %.2f: FE residual < %s of the quasi-static's", gammas[c],
             c < 2 ? "5 %" : "10 %");
    ea_test_true(rd < (c < 2 ? 0.05 : 0.10) * rq, w);
    /* the 1 mm: the at-rest plan meets it at payloads 0 and 0.25 (0.23, 0.47 mm); at
     * payload 0.5 it leaves 2.10 mm (what the linear model misses grows with the square of
     * the modal deflection, below), asserted as measured (tolerance 1.25x), and the refined
     * plan (FE in the loop, below) meets it */
    snprintf(w, sizeof w, "payload factor %.2f: FE residual peak <= %s mm", gammas[c],
             c < 2 ? "1" : "2.6 (unrefined)");
    ea_test_true(rd <= (c < 2 ? 1e-3 : 2.6e-3), w);
    if (c == 0) {
      ea_test_true(id.duration_s <= 1.60, "payload 0: at rest in <= 1.60 s");
      /* the stretch goal of the issue: measured 0.23 mm in 1.445 s */
      ea_test_true(rd <= 0.3e-3 && id.duration_s <= 1.57,
                   "payload 0: FE residual <= 0.3 mm in <= 1.57 s");
    }
    /* refined against the FE transient (the task's refinement defaults, no wall-time cap so
     * that the evaluations do not depend on the load), measured by this test's transient (dt
     * 1 ms, not the loop's 2 ms) */
    ea_task_refine_t rs;
    ea_task_refine_default(&rs);
    rs.max_time_s = 1e4;
    ea_refine_info_t ri;
    const int okr = !ea_plan_refine(pl, &rs, &ir, &ri, &e) && !ea_planner_trajectory(pl, &rf, &e);
    if (!okr) printf("  refine: %s\n", e.msg);
    const double rr = okr ? fe_residual(&t, &rf, 0.0, NULL) : NAN;
    const double pr = okr ? fe_residual_settle(&t, &rf, 0.02, 20.0, &rest_r) : NAN;
    printf("payload factor %.2f refined: %.5f s (x %.3f, %d evaluations), FE residual %.4f mm "
           "(rest %.2f s after)\n",
           gammas[c], ri.duration_s, ri.duration_s / iq.duration_s, ri.n_evals, 1e3 * rr, rest_r);
    printf("time to rest within 1 mm at 2 %% damping, payload factor %.2f: quasi-static %.2f s, "
           "at rest %.2f s, refined %.2f s after the motion; residual peak at 2 %% damping "
           "%.3f, %.3f, %.3f mm\n",
           gammas[c], fmax(rest_q, 0.0), fmax(rest_d, 0.0), fmax(rest_r, 0.0), 1e3 * pq, 1e3 * pd,
           1e3 * pr);
    snprintf(w, sizeof w,
             "payload factor %.2f: refined FE residual <= 1 mm within 1.25 x the minimum time",
             gammas[c]);
    ea_test_true(okr && rr <= 1e-3 && ri.duration_s <= 1.25 * iq.duration_s, w);
    if (c == 2) {
      /* why the payload-0.5 plan leaves 2.1 mm: not the modes (3 and 4 modes: 2.10, 2.09 mm,
       * tests/test_rom_modes), knots or grid; the FE residual of the at-rest plan grows with
       * the square of its largest modal tip deflection during the motion. Bounding that
       * deflection (dynamics.max_tip_deviation_m) buys the 1 mm at more than 1.25 x. */
      const double devs[2] = {0.015, 0.010};
      double k0 = rd / (id.max_modal_deviation_m * id.max_modal_deviation_m), kmin = k0, kmax = k0;
      printf("payload factor 0.50, at rest: largest modal tip deflection %.2f mm, FE residual "
             "%.4f mm, residual / deflection^2 %.2f 1/m\n",
             1e3 * id.max_modal_deviation_m, 1e3 * rd, k0);
      for (int d = 0; d < 2; ++d) {
        ea_task_t td = t;
        td.dynamics.max_tip_deviation_m = devs[d];
        ea_traj_t tv = {0};
        ea_plan_info_t iv;
        if (plan(&td, &tv, &iv)) {
          ea_test_true(0, "payload 0.5: at rest with the deflection bounded");
          continue;
        }
        const double rv = fe_residual(&td, &tv, 0.0, NULL);
        const double k = rv / (iv.max_modal_deviation_m * iv.max_modal_deviation_m);
        kmin = fmin(kmin, k);
        kmax = fmax(kmax, k);
        printf("payload factor 0.50, at rest, max_tip_deviation_m %.3f: %.5f s (x %.3f), largest "
               "modal tip deflection %.2f mm, FE residual %.4f mm, residual / deflection^2 %.2f "
               "1/m\n",
               devs[d], iv.duration_s, iv.duration_s / iq.duration_s,
               1e3 * iv.max_modal_deviation_m, 1e3 * rv, k);
        if (d == 1) {
          /* measured 0.57 mm at 1.264 s (1.381 x) */
          ea_test_true(rv <= 1e-3 && iv.duration_s > 1.25 * iq.duration_s,
                       "payload 0.5: the deflection bounded to 10 mm meets 1 mm, beyond 1.25 x");
        }
        ea_traj_free(&tv);
      }
      /* measured 5.0 .. 5.7 1/m over deflections 10 .. 20.5 mm: quadratic within 15 % */
      ea_test_true(kmax < 1.3 * kmin,
                   "payload 0.5: FE residual / deflection^2 constant within 30 % (nonlinear)");
    }
    /* plans allowed 1 mm and 5 mm, not at rest in the model (5 mm at payload 0:
     * test_terminal_state) */
    for (int k = 0; k < 2; ++k) {
      if (k == 1 && c == 0) continue;
      ea_task_t t5 = t;
      t5.dynamics.residual_m = k ? 5e-3 : 1e-3;
      ea_traj_t tr5 = {0};
      ea_plan_info_t i5;
      if (!plan(&t5, &tr5, &i5)) {
        snprintf(w, sizeof w, "payload factor %.2f: residual_m %d mm", gammas[c], k ? 5 : 1);
        add_pair(w, i5.predicted_residual_m, fe_residual(&t5, &tr5, 0.0, NULL), rd);
      } else {
        ea_test_true(0, "residual_m plan");
      }
      ea_traj_free(&tr5);
    }
    ea_planner_free(pl);
    ea_traj_free(&qs);
    ea_traj_free(&dy);
    ea_traj_free(&rf);
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
  add_pair("payload factor 0.00: residual_m 5 mm", info.predicted_residual_m, fe, rest_miss[0]);
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
    ea_planner_t *pl = NULL;
    ea_error_t e = {0};
    const int okd = !ea_task_check(&t, &e) && !ea_planner_alloc(&t, &pl, &e) &&
                    !ea_planner_solve(pl, EA_PLAN_COLD, NULL, &id, &e) &&
                    !ea_planner_trajectory(pl, &dy, &e);
    if (!okd) printf("  plan: %s\n", e.msg);
    ea_test_true(okq && okd, names[c]);
    if (!okq || !okd) {
      ea_planner_free(pl);
      continue;
    }
    const double rq = fe_residual(&t, &qs, 0.0, NULL), rd = fe_residual(&t, &dy, 0.0, NULL);
    printf("%s: quasi-static %.4f s, FE residual %.3f mm; at rest %.4f s, FE residual %.4f mm "
           "(%.1f %%)\n",
           names[c], iq.duration_s, 1e3 * rq, id.duration_s, 1e3 * rd, 100 * rd / rq);
    char w[160];
    snprintf(w, sizeof w, "%s: quasi-static plan", names[c]);
    add_pair(w, predicted(pl, &qs), rq, rd);
    /* measured 0.2 % (pick-place: the in-plane motion shaped within the base's time) and
     * 11 % (polyline: the via point's corner); tolerances 2x */
    snprintf(w, sizeof w, "%s made dynamic: FE residual < %s of the quasi-static's", names[c],
             c ? "25 %" : "1 %");
    ea_test_true(rd < (c ? 0.25 : 0.01) * rq, w);
    ea_planner_free(pl);
    ea_traj_free(&qs);
    ea_traj_free(&dy);
  }
}

/* The model's prediction against the FE transient on every plan above that is not at rest in
 * the model: one factor. */
static void test_prediction_factor(void) {
  double worst = 1.0, worst_miss = 0.0;
  int at = -1, at_miss = -1, nbig = 0;
  for (int i = 0; i < npairs; ++i) {
    const double d = fabs(pairs[i].measured - pairs[i].predicted) / pairs[i].miss;
    if (!(d <= worst_miss)) worst_miss = d, at_miss = i;
    if (!(pairs[i].predicted >= 3e-3)) continue;
    ++nbig;
    const double f =
        fmax(pairs[i].measured / pairs[i].predicted, pairs[i].predicted / pairs[i].measured);
    if (!(f <= worst)) worst = f, at = i;
  }
  printf("model vs FE on %d plans not at rest in the model: the %d predicted >= 3 mm within a "
         "factor %.3f (worst: %s); |FE - predicted| <= %.2f x the same task's at-rest FE "
         "residual (worst: %s)\n",
         npairs, nbig, worst, at >= 0 ? pairs[at].what : "-", worst_miss,
         at_miss >= 0 ? pairs[at_miss].what : "-");
  ea_test_true(npairs == 11 && nbig == 8, "model vs FE: 11 plans, 8 predicted >= 3 mm");
  ea_test_true(worst <= PREDICTION_FACTOR,
               "model vs FE: predicted >= 3 mm: predicted and measured within the stated factor");
  ea_test_true(worst_miss <= MISS_FACTOR,
               "model vs FE: |FE - predicted| within the stated multiple of the at-rest miss");
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

/* Plan t on 1 and on 2 threads (solver.threads): 1 when both plans succeed with the same
 * iterations, duration and trajectory bit for bit; what printed. */
static int same_on_threads(ea_task_t *t, const char *what) {
  ea_traj_t tr[2] = {{0}, {0}};
  ea_plan_info_t info[2];
  int ok = 1;
  for (int th = 0; th < 2; ++th) {
    t->solver.threads = th + 1;
    ok = ok && plan(t, &tr[th], &info[th]) == EA_OK;
  }
  int same = ok && tr[0].n == tr[1].n && info[0].iterations == info[1].iterations &&
             memcmp(&info[0].duration_s, &info[1].duration_s, sizeof(double)) == 0;
  for (int i = 0; same && i < tr[0].n * EA_TRAJ_NCOL; ++i)
    same = memcmp(&tr[0].data[i], &tr[1].data[i], sizeof(double)) == 0;
  printf("threads 1 and 2, %s: %.12g s (%d iterations), %.12g s (%d)\n", what, info[0].duration_s,
         info[0].iterations, info[1].duration_s, info[1].iterations);
  ea_traj_free(&tr[0]);
  ea_traj_free(&tr[1]);
  return same;
}

/* solver.threads: the path transcription's two parts (planner/nlp/plan_par.c) on one thread
 * or two give the same plan bit for bit (the parts and their sums are the same): at rest at
 * an even and an odd knot count, payload factors 0 and 0.5 (goal (0.5, -0.2) m, as
 * test_paper_line); quasi-static plans (the statics samples' levels on the worker, the cold
 * guess beside the interior point's preparation) on the paper line and the polyline. */
static void test_threads(void) {
  const int kn[3] = {100, 37, 60};
  const double gam[3] = {0.0, 0.0, 0.5};
  char what[96], w[160];
  for (int c = 0; c < 3; ++c) {
    ea_task_t t;
    if (load("paper-line-rest.yaml", &t)) return;
    t.knots = kn[c];
    t.payload_factor = gam[c];
    t.payload_kg = ea_arm_payload_from_factor(&t.arm, gam[c]);
    if (c == 2) t.goal = ea_task_point_planar(0.5, -0.2, 0.0);
    t.solver.transcription = EA_TASK_TRANSCRIPTION_PATH;
    snprintf(what, sizeof what, "at rest, %d knots, payload factor %g", kn[c], gam[c]);
    snprintf(w, sizeof w, "%s: the same plan on 1 and 2 threads", what);
    ea_test_true(same_on_threads(&t, what), w);
  }
  const char *qs[2] = {"paper-line.yaml", "polyline-effort.yaml"};
  for (int c = 0; c < 2; ++c) {
    ea_task_t t;
    if (load(qs[c], &t)) return;
    snprintf(w, sizeof w, "%s: the same plan on 1 and 2 threads", qs[c]);
    ea_test_true(same_on_threads(&t, qs[c]), w);
  }
}

int main(void) {
  gsl_set_error_handler_off();
  src = getenv("EA_SOURCE_DIR");
  if (!src) {
    printf("EA_SOURCE_DIR not set (run through ctest)\n");
    return EXIT_FAILURE;
  }
  test_threads();
  test_transcriptions();
  test_paper_line();
  test_terminal_state();
  test_other_examples();
  test_min_vibration();
  test_prediction_factor();
  return ea_test_summary("test_plan_rest");
}
