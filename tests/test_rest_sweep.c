/* Plans that promise rest keep it on lines the tests and examples do not use (issue 33,
 * items 2 and 3): a seeded random sweep of straight lines and polylines across the
 * workspace, payload factor 0..0.5, each planned with dynamics {modes: 2, residual_m: 0} and
 * default settings, then checked by the FE and refined as `elasticarm plan` does by default
 * (ea_plan_rest_check, ea_plan_rest_settings). The reference is outside the planner and its
 * loop: the FE transient of the returned plan at converged settings (12 elements,
 * generalized-alpha, dt 0.5 ms, 3 s after the motion, undamped). Every task the task check or
 * the planner refuses is counted with its reason; so is a plan whose check does not reach its
 * bound within the refinement's budget (`elasticarm plan` exits 3 on it, saying what was
 * reached): at most 2 of the 60 (measured: 1, a 0.54 m vertical line at payload 0.38 whose
 * at-rest plan rings with 17.8 mm, the targets that would cancel it not plannable within the
 * task's limits). Every other one must end <= 1 mm.
 * Also: the at-rest paper-line examples get no more than 1 % longer by the check. */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_refine.h"
#include "ea_test.h"
#include "ea_test_sweep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static char src[1024];

static uint64_t rng_state = EA_TS_SEED;
static double urand(void) {
  return ea_ts_urand(&rng_state);
}

static ea_task_point_t rand_point(void) {
  return ea_ts_rand_point(&rng_state);
}

typedef struct {
  int planned, refused_check, refused_plan, refused_rest, within, over_before;
  double worst_mm, times[128];
  int n_times;
  double ratios[128]; /* checked plan's duration / the quasi-static minimum */
  int n_ratios;
} tally_t;

/* The quasi-static minimum time of t (no dynamics); NAN when it cannot be planned. */
static double quasi_static_min(const ea_task_t *t) {
  ea_task_t q = *t;
  q.dynamics.modes = 0;
  q.dynamics.residual_m = 0.0;
  ea_planner_t *pl = NULL;
  ea_plan_info_t pi;
  ea_error_t e = {0};
  const int ok =
      !ea_planner_alloc(&q, &pl, &e) && !ea_planner_solve(pl, EA_PLAN_COLD, NULL, &pi, &e);
  ea_planner_free(pl);
  return ok ? pi.duration_s : NAN;
}

/* Plan t with the default check; counted within when it ends within its promise by the
 * converged FE: 1 mm at rest, else its residual bound. */
static void run_task(const char *name, const ea_task_t *t, tally_t *y) {
  ea_planner_t *pl = NULL;
  ea_plan_info_t pi;
  ea_error_t e = {0};
  ea_refine_info_t *ri = calloc(1, sizeof *ri);
  ea_traj_t tr;
  memset(&tr, 0, sizeof tr);
  const double t0 = ea_ts_mono();
  ea_status_t st = ea_planner_alloc(t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &pi, &e);
  if (st) {
    printf("  %s: refused by the planner: %s: %.200s\n", name, ea_status_name(st), e.msg);
    ++y->refused_plan;
    ea_planner_free(pl);
    free(ri);
    return;
  }
  ea_task_refine_t rs;
  ea_plan_rest_settings(t, &rs);
  st = ri ? ea_plan_refine(pl, &rs, &pi, ri, &e) : EA_ERR_NOMEM;
  if (!st) st = ea_planner_trajectory(pl, &tr, &e);
  const double dt_s = ea_ts_mono() - t0;
  ++y->planned;
  if (y->n_times < 128) y->times[y->n_times++] = dt_s;
  char what[700];
  if (st) {
    snprintf(what, sizeof what, "%s: FE check and refinement ran (%s)", name, e.msg);
    ea_test_true(0, what);
  } else if (!ri->converged) {
    ++y->refused_rest;
    printf("  %s (%.4f, %.4f) -> (%.4f, %.4f), payload %.3f: refused (exit 3): %s\n", name,
           t->start.given[0], t->start.given[1], t->goal.given[0], t->goal.given[1],
           t->payload_factor, ri->message);
  } else {
    const double bound = t->dynamics.residual_m > 0 ? t->dynamics.residual_m : 1e-3;
    const double peak = ea_ts_fe_converged(t, &tr);
    const double qs = quasi_static_min(t);
    if (y->n_ratios < 128 && isfinite(qs)) y->ratios[y->n_ratios++] = ri->duration_s / qs;
    y->worst_mm = fmax(y->worst_mm, 1e3 * peak);
    y->within += peak <= bound;
    y->over_before += ri->residual_peak_before_m > bound;
    snprintf(what, sizeof what,
             "%s (%.4f, %.4f) -> (%.4f, %.4f): payload %.3f, %.4g s: FE residual %.4f mm (dt 0.5 "
             "ms) <= %g mm; loop %.4f mm "
             "-> %.4f mm in %d evaluations, %.0f ms",
             name, t->start.given[0], t->start.given[1], t->goal.given[0], t->goal.given[1],
             t->payload_factor, ri->duration_s, 1e3 * peak, 1e3 * bound,
             1e3 * ri->residual_peak_before_m, 1e3 * ri->residual_peak_m, ri->n_evals, 1e3 * dt_s);
    ea_test_true(peak <= bound && ri->converged, what);
  }
  ea_traj_free(&tr);
  ea_planner_free(pl);
  free(ri);
}

static int cmp(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Draw tasks until n pass the task check (refusals counted); plan each. */
static void sweep(const ea_task_t *base, int n, int vias, tally_t *y) {
  int done = 0, tries = 0;
  while (done < n && tries < 40 * n) {
    ++tries;
    ea_task_t t = *base;
    const double g = 0.5 * urand();
    t.payload_factor = g;
    t.payload_kg = ea_arm_payload_from_factor(&t.arm, g);
    t.start = rand_point();
    t.goal = rand_point();
    t.n_via = vias;
    for (int i = 0; i < vias; ++i)
      t.via[i] = rand_point();
    t.path = vias ? EA_TASK_PATH_POLYLINE : EA_TASK_PATH_LINE;
    ea_error_t e = {0};
    if (ea_task_check(&t, &e)) {
      ++y->refused_check;
      continue;
    }
    char name[64];
    snprintf(name, sizeof name, "%s %d", vias ? "polyline" : "line", done + 1);
    run_task(name, &t, y);
    ++done;
  }
  char what[200];
  snprintf(what, sizeof what, "%d %s drawn that pass the task check (%d tries)", done,
           vias ? "polylines" : "lines", tries);
  ea_test_true(done == n, what);
}

/* The at-rest paper-line examples: the check makes none more than 1 % longer. */
static void examples(void) {
  static const char *const files[] = {"paper-line-rest.yaml", "paper-line-robust.yaml"};
  for (int i = 0; i < 2; ++i) {
    char path[1200];
    snprintf(path, sizeof path, "%s/problems/examples/%s", src, files[i]);
    ea_task_t t;
    ea_error_t e = {0};
    ea_planner_t *pl = NULL;
    ea_plan_info_t pi;
    ea_refine_info_t *ri = calloc(1, sizeof *ri);
    ea_status_t st = ea_task_load(path, NULL, &t, &e);
    if (!st) st = ea_planner_alloc(&t, &pl, &e);
    if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &pi, &e);
    const double d0 = pi.duration_s;
    ea_task_refine_t rs;
    if (!st) ea_plan_rest_settings(&t, &rs);
    if (!st) st = ri ? ea_plan_refine(pl, &rs, &pi, ri, &e) : EA_ERR_NOMEM;
    char what[600];
    snprintf(what, sizeof what, "%s: at rest %.6f s, checked %.6f s (%+.3f %%, <= +1 %%): %s",
             files[i], d0, st ? NAN : ri->duration_s,
             st ? NAN : 100.0 * (ri->duration_s / d0 - 1.0), st ? e.msg : ri->message);
    ea_test_true(!st && ri->converged && ri->duration_s <= 1.01 * d0, what);
    ea_planner_free(pl);
    free(ri);
  }
}

int main(void) {
  const char *s = getenv("EA_SOURCE_DIR");
  snprintf(src, sizeof src, "%s", s ? s : ".");
  char arm[1200];
  snprintf(arm, sizeof arm, "%s/data/elasticarm.yaml", src);
  ea_arm_t a;
  ea_error_t e = {0};
  if (ea_arm_load(arm, &a, &e)) {
    ea_test_true(0, e.msg);
    return ea_test_summary("test_rest_sweep");
  }
  examples();
  ea_task_t base;
  ea_task_init(&base, &a);
  snprintf(base.name, sizeof base.name, "sweep");
  base.objective = EA_TASK_MIN_TIME;
  base.dynamics.modes = 2;
  base.dynamics.residual_m = 0.0;
  tally_t y;
  memset(&y, 0, sizeof y);
  sweep(&base, 50, 0, &y);
  sweep(&base, 10, 2, &y);
  qsort(y.times, (size_t)y.n_times, sizeof(double), cmp);
  qsort(y.ratios, (size_t)y.n_ratios, sizeof(double), cmp);
  printf("sweep: %d planned (%d within 1 mm, worst %.4f mm, %d not within the bound in the loop: "
         "refused), %d refused by the task check, %d by the planner; time per verified plan "
         "median %.0f ms, worst %.0f ms\n",
         y.planned, y.within, y.worst_mm, y.refused_rest, y.refused_check, y.refused_plan,
         y.n_times ? 1e3 * y.times[y.n_times / 2] : NAN,
         y.n_times ? 1e3 * y.times[y.n_times - 1] : NAN);
  printf("durations: the checked plan over the quasi-static minimum, %d plans: median %.3f, p90 "
         "%.3f, worst %.3f\n",
         y.n_ratios, y.n_ratios ? y.ratios[y.n_ratios / 2] : NAN,
         y.n_ratios ? y.ratios[(9 * y.n_ratios) / 10] : NAN,
         y.n_ratios ? y.ratios[y.n_ratios - 1] : NAN);
  ea_test_true(y.planned >= 50 && y.within == y.planned - y.refused_rest,
               "sweep: every planned task whose check passed ends within 1 mm by the converged FE");
  ea_test_true(y.refused_rest <= 2, "sweep: at most 2 of 60 refused by the check (exit 3)");
  /* A residual bound (residual_m 5 mm) is refined to by the same loop: the sweep's first 20
   * lines again. The plan the model allows 5 mm can leave twice that in the FE on these
   * lines; the check alone (one FE transient) refused those. */
  rng_state = EA_TS_SEED;
  base.dynamics.residual_m = 0.005;
  tally_t b;
  memset(&b, 0, sizeof b);
  sweep(&base, 20, 0, &b);
  printf("bound 5 mm: %d planned (%d within 5 mm, worst %.4f mm; %d over it before the "
         "refinement; %d not within the bound in the loop: refused)\n",
         b.planned, b.within, b.worst_mm, b.over_before, b.refused_rest);
  ea_test_true(b.planned >= 15 && b.within == b.planned - b.refused_rest,
               "bound 5 mm: every planned task whose check passed ends within 5 mm by the "
               "converged FE");
  ea_test_true(b.refused_rest <= 1, "bound 5 mm: at most 1 of 20 refused by the check");
  qsort(b.ratios, (size_t)b.n_ratios, sizeof(double), cmp);
  printf("durations, bound 5 mm: the checked plan over the quasi-static minimum, %d plans: "
         "median %.3f, worst %.3f\n",
         b.n_ratios, b.n_ratios ? b.ratios[b.n_ratios / 2] : NAN,
         b.n_ratios ? b.ratios[b.n_ratios - 1] : NAN);
  return ea_test_summary("test_rest_sweep");
}
