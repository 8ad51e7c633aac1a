/* Time per verified at-rest plan (docs/planner.md, "Keeping the promise of rest"): the plan
 * (allocation, reduced-model table, solve), the FE check and the refinement's re-plans, as
 * `elasticarm plan` runs them by default (ea_plan_rest_check, ea_plan_rest_settings), on the
 * paper line (repeated) and on a seeded random sweep of straight lines across the workspace
 * (payload factor 0..0.5; the generator of tests/test_rest_sweep.c). One thread.
 *
 *   bench_rest [LINES [REPEATS [BY]]]   (default 20 lines, the paper line 7 times, BY fe)
 *
 * BY (fe, model, model_only) is what measures the loop's candidates (dynamics.refine.by): the
 * nonlinear reduced model's time has its own column; with model_only the loop's residual is the
 * model's, no FE transient runs.
 *
 * Prints a markdown table: median, p90 and worst of the total (wall and this thread's CPU
 * time: one core's work on a shared machine) and of each phase (wall), the
 * evaluations and the FE residual reached in the loop. Timings depend on the machine. */
#include "bench_util.h"
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_refine.h"
#include "ea_simulate.h"
#include "ea_test_sweep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static uint64_t rng_state = EA_TS_SEED;
static ea_task_refine_by_t by = EA_TASK_REFINE_BY_FE;
static double urand(void) {
  return ea_ts_urand(&rng_state);
}

/* CPU time of this thread: what one core spends, whatever else runs on the machine */
static double cpu(void) {
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#define NMAX 512
typedef struct {
  int n;
  double total[NMAX], cpu[NMAX], plan[NMAX], fe[NMAX], replan[NMAX], resid[NMAX], evals[NMAX],
      model[NMAX];
  int not_converged;
} runs_t;

/* One verified plan of t, timed by phase; 0 on success. */
static int one(const ea_task_t *t, runs_t *r) {
  ea_refine_info_t *ri = calloc(1, sizeof *ri);
  ea_planner_t *pl = NULL;
  ea_plan_info_t pi;
  ea_error_t e = {0};
  const double t0 = ea_bench_now(), c0 = cpu();
  ea_status_t st = ri ? ea_planner_alloc(t, &pl, &e) : EA_ERR_NOMEM;
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &pi, &e);
  const double t1 = ea_bench_now();
  ea_task_refine_t rs;
  ea_plan_rest_settings(t, &rs);
  rs.by = by;
  if (!st) st = ea_plan_refine(pl, &rs, &pi, ri, &e);
  /* a residual bound: the verdict of one FE transient at --verify's settings, as the CLI */
  double t_verify = 0.0;
  int verdict_fail = 0;
  if (!st && t->dynamics.residual_m > 0) {
    const double tv = ea_bench_now();
    ea_traj_t tr = {0};
    ea_sim_settings_t ss;
    ea_sim_settings_default(&ss);
    ea_sim_info_t si;
    st = ea_planner_trajectory(pl, &tr, &e);
    if (!st) st = ea_traj_simulate(&t->arm, &tr, 0.0, &ss, NULL, &si, &e);
    if (!st) verdict_fail = si.residual_peak > t->dynamics.residual_m;
    ea_traj_free(&tr);
    t_verify = ea_bench_now() - tv;
  }
  const double t2 = ea_bench_now(), c2 = cpu();
  if (!st && r->n < NMAX) {
    const int k = r->n++;
    r->total[k] = t2 - t0;
    r->cpu[k] = c2 - c0;
    r->plan[k] = t1 - t0;
    r->fe[k] = ri->time_fe_s + t_verify;
    r->replan[k] = ri->time_plan_s;
    r->model[k] = ri->time_model_s;
    r->resid[k] = ri->residual_peak_m;
    r->evals[k] = ri->n_evals;
    r->not_converged += !ri->converged || verdict_fail;
  }
  if (st)
    fprintf(stderr, "bench_rest: (%.4f, %.4f) -> (%.4f, %.4f), payload factor %.3f: %s: %s\n",
            t->start.given[0], t->start.given[1], t->goal.given[0], t->goal.given[1],
            t->payload_factor, ea_status_name(st), e.msg);
  ea_planner_free(pl);
  free(ri);
  return st != EA_OK;
}

/* quantile q of v[0..n) (sorted copy) */
static double q(const double *v, int n, double qq) {
  double s[NMAX];
  memcpy(s, v, (size_t)n * sizeof *s);
  qsort(s, (size_t)n, sizeof *s, ea_bench_cmp);
  int i = (int)ceil(qq * n) - 1;
  if (i < 0) i = 0;
  if (i >= n) i = n - 1;
  return qq == 0.5 && n % 2 == 0 ? 0.5 * (s[n / 2 - 1] + s[n / 2]) : s[i];
}

/* "median / worst" of v in ms */
static void mw(const double *v, int n) {
  printf(" %.0f / %.0f |", 1e3 * q(v, n, 0.5), 1e3 * q(v, n, 1.0));
}

static void row(const char *name, const runs_t *r) {
  const int n = r->n;
  printf("| %s%s%s | %d | %.0f / %.0f / %.0f | %.0f / %.0f / %.0f |", name, by ? ", by " : "",
         by ? ea_task_refine_by_name(by) : "", n, 1e3 * q(r->total, n, 0.5),
         1e3 * q(r->total, n, 0.9), 1e3 * q(r->total, n, 1.0), 1e3 * q(r->cpu, n, 0.5),
         1e3 * q(r->cpu, n, 0.9), 1e3 * q(r->cpu, n, 1.0));
  mw(r->plan, n);
  mw(r->fe, n);
  mw(r->replan, n);
  if (by != EA_TASK_REFINE_BY_FE) mw(r->model, n);
  printf(" %.0f / %.0f | %.4f / %.4f | %d |\n", q(r->evals, n, 0.5), q(r->evals, n, 1.0),
         1e3 * q(r->resid, n, 0.5), 1e3 * q(r->resid, n, 1.0), r->not_converged);
}

int main(int argc, char **argv) {
  const int lines = argc > 1 ? atoi(argv[1]) : 20, reps = argc > 2 ? atoi(argv[2]) : 7;
  if (argc > 3 && ea_task_refine_by_from_name(argv[3], &by)) {
    fprintf(stderr, "bench_rest: BY '%s' is not one of fe, model, model_only\n", argv[3]);
    return 2;
  }
  char path[1200];
  snprintf(path, sizeof path, "%s/problems/examples/paper-line-rest.yaml", EA_SOURCE_DIR);
  ea_task_t paper;
  ea_error_t e = {0};
  if (ea_task_load(path, NULL, &paper, &e)) {
    fprintf(stderr, "bench_rest: %s\n", e.msg);
    return 1;
  }
  paper.solver.threads = 1;
  static runs_t rp, rs;
  one(&paper, &rp); /* warm: the reduced model's table into the cache */
  rp.n = rp.not_converged = 0;
  for (int i = 0; i < reps; ++i)
    one(&paper, &rp);
  ea_task_t base = paper;
  static runs_t rb;
  int refused = 0, refused_b = 0;
  for (int pass = 0; pass < 2; ++pass) { /* at rest, then the same lines allowed 5 mm */
    runs_t *r = pass ? &rb : &rs;
    rng_state = EA_TS_SEED;
    base.dynamics.residual_m = pass ? 0.005 : 0.0;
    int tries = 0;
    while (r->n < lines && tries < 40 * lines && r->n < NMAX) {
      ++tries;
      ea_task_t t = base;
      const double g = 0.5 * urand();
      t.payload_factor = g;
      t.payload_kg = ea_arm_payload_from_factor(&t.arm, g);
      t.start = ea_ts_rand_point(&rng_state);
      t.goal = ea_ts_rand_point(&rng_state);
      if (ea_task_check(&t, &e)) continue;
      *(pass ? &refused_b : &refused) += one(&t, r);
    }
  }
  printf("| case | plans | wall [ms]: median / p90 / worst | CPU [ms]: median / p90 / worst | "
         "plan: median / worst | FE: median / worst | re-plans: median / worst |%s evaluations: "
         "median / worst | loop %s residual [mm]: median / worst | not within bound |\n",
         by != EA_TASK_REFINE_BY_FE ? " nonlinear model: median / worst |" : "",
         by == EA_TASK_REFINE_BY_MODEL_ONLY ? "model" : "FE");
  printf("|---|---|---|---|---|---|---|%s---|---|---|\n", by != EA_TASK_REFINE_BY_FE ? "---|" : "");
  row("paper line (paper-line-rest.yaml)", &rp);
  row("random straight lines", &rs);
  row("the same, residual_m 5 mm", &rb);
  printf("(refine.by %s; %d lines refused by the planner, %d allowed 5 mm; one thread; with a "
         "residual bound the FE column includes the verdict's transient at dt 1 ms over 3 s)\n",
         ea_task_refine_by_name(by), refused, refused_b);
  return 0;
}
