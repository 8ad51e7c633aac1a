/* bench_plan: the paper's line (eq. 18), minimum time, cold and warm
 * started; per-phase times (initial guess, statics shots with
 * sensitivities inside the callbacks, Ipopt itself, rest); exact Hessian vs
 * limited-memory; replanning from a previous plan (same task, goal moved);
 * what features cost (path rows, base variables); scaling from 25 to 400
 * knots. Medians over repetitions; the load average is printed before and
 * after (the machine is shared).
 * Refinement against the FE transient (docs/planner.md): each method on the
 * at-rest paper line (payload 0) and the payload-0.5 line to (0.5, -0.2), from
 * a fresh cold plan: evaluations, wall time, FE residual before/after (the
 * loop's FE settings, and an independent transient at dt 0.25 ms); the robust
 * refinement of the robust paper line (nominal and four corner arms).
 * Polylines over the knot count (duration, objective; not converged).
 * usage: bench_plan [REPEATS] [replan|refine|robust|polyline] (default 5; "replan": only the
 * replanning rows; "refine": the refinement rows, robust ones included; "robust":
 * only the robust refinement rows; "polyline": only the polylines over the knot count) */
#include "bench_util.h"
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_refine.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* getloadavg() is BSD/glibc, not C11 */
static void print_load(const char *when) {
  FILE *fp = fopen("/proc/loadavg", "r");
  char buf[128] = "?";
  if (fp) {
    if (!fgets(buf, sizeof buf, fp)) snprintf(buf, sizeof buf, "?\n");
    fclose(fp);
  }
  printf("load average %s: %s", when, buf);
}

typedef struct {
  double total, guess, statics, ipopt, rest, iters, dur;
  int ok, nvar, ncon, nrow;
} row_t;

/* Per-phase samples of up to 64 solves. */
typedef struct {
  double tot[64], gu[64], st[64], ip[64], re[64], it[64];
} samples_t;

/* Sample i from a solve's info; the row keeps the problem size and duration. */
static void record(samples_t *S, int i, const ea_plan_info_t *info, row_t *r) {
  S->tot[i] = info->time_total_s;
  S->gu[i] = info->time_guess_s;
  S->st[i] = info->time_statics_s;
  S->ip[i] = info->time_ipopt_s;
  S->re[i] = info->time_rest_s;
  S->it[i] = info->iterations;
  r->dur = info->duration_s;
  r->nvar = info->n_var;
  r->ncon = info->n_con;
  r->nrow = info->ipopt_rows;
}

/* Medians of R samples into the row. */
static void summarize(samples_t *S, int R, row_t *r) {
  r->total = ea_bench_median(S->tot, R);
  r->guess = ea_bench_median(S->gu, R);
  r->statics = ea_bench_median(S->st, R);
  r->ipopt = ea_bench_median(S->ip, R);
  r->rest = ea_bench_median(S->re, R);
  r->iters = ea_bench_median(S->it, R);
}

/* Median of R solves (warm: each after one cold solve). */
static row_t run(const ea_task_t *t, int R, int warm) {
  samples_t S;
  row_t r;
  memset(&r, 0, sizeof r);
  r.ok = 1;
  if (R > 64) R = 64;
  ea_planner_t *pl = NULL;
  ea_error_t e;
  if (ea_planner_alloc(t, &pl, &e)) {
    fprintf(stderr, "bench_plan: %s\n", e.msg);
    r.ok = 0;
    return r;
  }
  ea_plan_info_t info;
  if (warm && ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e)) r.ok = 0;
  for (int i = 0; i < R; ++i) {
    if (ea_planner_solve(pl, warm ? EA_PLAN_WARM : EA_PLAN_COLD, NULL, &info, &e)) r.ok = 0;
    record(&S, i, &info, &r);
  }
  summarize(&S, R, &r);
  ea_planner_free(pl);
  return r;
}

/* Medians of R cold solves of each of the nt variants ts of a task (solver settings), the
 * variants' solves alternating so that all see the same machine. */
static void run_alternating(const ea_task_t *ts, int nt, int R, row_t *rows) {
  samples_t S[3];
  ea_planner_t *pl[3] = {NULL, NULL, NULL};
  ea_error_t e;
  if (R > 64) R = 64;
  for (int v = 0; v < nt; ++v) {
    memset(&rows[v], 0, sizeof rows[v]);
    rows[v].ok = 1;
    if (ea_planner_alloc(&ts[v], &pl[v], &e)) {
      fprintf(stderr, "bench_plan: %s\n", e.msg);
      rows[v].ok = 0;
    }
  }
  ea_plan_info_t info;
  for (int i = 0; i < R; ++i)
    for (int v = 0; v < nt; ++v) {
      if (!pl[v] || ea_planner_solve(pl[v], EA_PLAN_COLD, NULL, &info, &e)) rows[v].ok = 0;
      record(&S[v], i, &info, &rows[v]);
    }
  for (int v = 0; v < nt; ++v) {
    summarize(&S[v], R, &rows[v]);
    ea_planner_free(pl[v]);
  }
}

/* Median of R plans of task t started from the trajectory of a plan of
 * task prev (EA_PLAN_FROM_TRAJ, a new planner each time as for a new task). */
static row_t run_traj(const ea_task_t *prev, const ea_task_t *t, int R) {
  samples_t S;
  row_t r;
  memset(&r, 0, sizeof r);
  r.ok = 1;
  if (R > 64) R = 64;
  ea_planner_t *p0 = NULL;
  ea_error_t e;
  ea_plan_info_t info;
  ea_traj_t tr;
  memset(&tr, 0, sizeof tr);
  if (ea_planner_alloc(prev, &p0, &e) || ea_planner_solve(p0, EA_PLAN_COLD, NULL, &info, &e) ||
      ea_planner_trajectory(p0, &tr, &e)) {
    fprintf(stderr, "bench_plan: %s\n", e.msg);
    ea_planner_free(p0);
    ea_traj_free(&tr);
    r.ok = 0;
    return r;
  }
  ea_planner_free(p0);
  for (int i = 0; i < R; ++i) {
    ea_planner_t *pl = NULL;
    if (ea_planner_alloc(t, &pl, &e) || ea_planner_solve(pl, EA_PLAN_FROM_TRAJ, &tr, &info, &e))
      r.ok = 0;
    record(&S, i, &info, &r);
    ea_planner_free(pl);
  }
  ea_traj_free(&tr);
  summarize(&S, R, &r);
  return r;
}

/* Median of R replans: a planner solves prev cold (not timed), is updated
 * to task t (ea_planner_update, timed apart: *upd) and solves it warm
 * (EA_PLAN_WARM from the previous plan and multipliers). */
static row_t run_update(const ea_task_t *prev, const ea_task_t *t, int R, double *upd, int *newton,
                        int *by_ipm) {
  samples_t S;
  double up[64];
  row_t r;
  memset(&r, 0, sizeof r);
  r.ok = 1;
  if (R > 64) R = 64;
  ea_error_t e;
  ea_plan_info_t info;
  for (int i = 0; i < R; ++i) {
    ea_planner_t *pl = NULL;
    if (ea_planner_alloc(prev, &pl, &e) || ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e)) {
      fprintf(stderr, "bench_plan: %s\n", e.msg);
      r.ok = 0;
      ea_planner_free(pl);
      return r;
    }
    const double t0 = ea_bench_now();
    if (ea_planner_update(pl, t, &e)) r.ok = 0;
    up[i] = ea_bench_now() - t0;
    if (ea_planner_solve(pl, EA_PLAN_WARM, NULL, &info, &e)) r.ok = 0;
    record(&S, i, &info, &r);
    *newton = info.newton_steps; /* deterministic */
    *by_ipm = info.ipm_iterations > 0 && !info.ipm_fallback;
    ea_planner_free(pl);
  }
  summarize(&S, R, &r);
  *upd = ea_bench_median(up, R);
  return r;
}

static void print_row(const char *name, const row_t *r) {
  printf("%-34s %5d %5d %6.0f %5d %9.2f %8.2f %8.2f %8.2f %7.2f %9.5f %s\n", name, r->nvar, r->ncon,
         r->iters, r->nrow, 1e3 * r->total, 1e3 * r->guess, 1e3 * r->statics, 1e3 * r->ipopt,
         1e3 * r->rest, r->dur, r->ok ? "" : "FAILED");
}

static void header(const char *title) {
  printf("\n%s\n%-34s %5s %5s %6s %5s %9s %8s %8s %8s %7s %9s\n", title, "case", "vars", "cons",
         "iters", "rows", "total ms", "guess", "statics", "ipopt", "rest", "t_f [s]");
}

/* One refinement row: cold at-rest plan, refinement with method m and tolerance tol, then
 * the returned plan's FE residual at dt 0.25 ms (12 elements, undamped, 3 s). */
static void refine_row(const char *name, const ea_task_t *t, ea_task_refine_method_t m,
                       double tol) {
  ea_planner_t *pl = NULL;
  ea_error_t e = {0};
  ea_plan_info_t info;
  ea_refine_info_t *ri = calloc(1, sizeof *ri);
  ea_traj_t tr;
  memset(&tr, 0, sizeof tr);
  ea_task_refine_t s = t->dynamics.refine;
  s.method = m;
  s.tolerance_m = tol;
  ea_sim_settings_t ss;
  ea_sim_settings_default(&ss);
  ss.dt = 2.5e-4;
  ea_sim_info_t si;
  si.residual_peak = NAN;
  if (!ri || ea_planner_alloc(t, &pl, &e) || ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e) ||
      ea_plan_refine(pl, &s, &info, ri, &e) || ea_planner_trajectory(pl, &tr, &e) ||
      ea_traj_simulate(&t->arm, &tr, -1.0, &ss, NULL, &si, &e)) {
    printf("%-22s %-7s %8.3f FAILED: %s\n", name, ea_task_refine_method_name(m), 1e3 * tol, e.msg);
  } else {
    printf("%-22s %-7s %8.3f %5d %8.2f %8.2f %8.2f %9.4f %9.4f %9.4f %+8.3f %s\n", name,
           ea_task_refine_method_name(m), 1e3 * tol, ri->n_evals, ri->time_s, ri->time_plan_s,
           ri->time_fe_s, 1e3 * ri->residual_peak_before_m, 1e3 * ri->residual_peak_m,
           1e3 * si.residual_peak, 100.0 * (ri->duration_s / ri->duration_before_s - 1.0),
           ri->stop_reason);
  }
  ea_traj_free(&tr);
  ea_planner_free(pl);
  free(ri);
}

/* One robust refinement row: cold robust plan, refinement with method m, then the returned
 * plan's FE residual at the four corner arms at dt 0.25 ms (the arm's hand mass and EI
 * changed; 12 elements, undamped, 3 s). */
static void robust_row(const char *name, const ea_task_t *t, ea_task_refine_method_t m) {
  ea_planner_t *pl = NULL;
  ea_error_t e = {0};
  ea_plan_info_t info;
  ea_refine_info_t *ri = calloc(1, sizeof *ri);
  ea_traj_t tr;
  memset(&tr, 0, sizeof tr);
  ea_task_refine_t s = t->dynamics.refine;
  s.method = m;
  ea_sim_settings_t ss;
  ea_sim_settings_default(&ss);
  ss.dt = 2.5e-4;
  double worst = 0.0;
  ea_status_t st = ri ? EA_OK : EA_ERR_NOMEM;
  if (!st) st = ea_planner_alloc(t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  if (!st) st = ea_plan_refine(pl, &s, &info, ri, &e);
  if (!st) st = ea_planner_trajectory(pl, &tr, &e);
  for (int c = 1; c <= 4 && !st; ++c) {
    ea_arm_t arm = t->arm;
    arm.m_hand *= 1.0 + ((c - 1) & 1 ? t->dynamics.robust_tip_mass : -t->dynamics.robust_tip_mass);
    arm.EI *= 1.0 + ((c - 1) & 2 ? t->dynamics.robust_EI : -t->dynamics.robust_EI);
    ea_sim_info_t si;
    st = ea_traj_simulate(&arm, &tr, -1.0, &ss, NULL, &si, &e);
    worst = fmax(worst, si.residual_peak);
  }
  if (st) {
    printf("%-24s %-7s FAILED: %s\n", name, ea_task_refine_method_name(m), e.msg);
  } else {
    double c0 = 0.0, c1 = 0.0;
    for (int j = 1; j < ri->models; ++j) {
      c0 = fmax(c0, ri->model_residual_peak_before_m[j]);
      c1 = fmax(c1, ri->model_residual_peak_m[j]);
    }
    printf("%-24s %-7s %5d %7.2f %7.2f %7.2f %7.4f %7.4f %8.4f %8.4f %8.4f %8.4f %8.4f %s\n", name,
           ea_task_refine_method_name(m), ri->n_evals, ri->time_s, ri->time_plan_s, ri->time_fe_s,
           ri->duration_before_s, ri->duration_s, 1e3 * ri->residual_peak_before_m,
           1e3 * ri->residual_peak_m, 1e3 * c0, 1e3 * c1, 1e3 * worst, ri->stop_reason);
  }
  ea_traj_free(&tr);
  ea_planner_free(pl);
  free(ri);
}

static int robust_rows(const ea_task_t *line) {
  ea_task_t t[2];
  const char *nm[2] = {"robust, residual 0.5 mm", "robust, residual 0.4 mm"};
  ea_error_t e;
  for (int i = 0; i < 2; ++i) {
    t[i] = *line;
    t[i].dynamics.modes = 1;
    t[i].dynamics.residual_m = 0.0;
    t[i].dynamics.robust_tip_mass = 0.2;
    t[i].dynamics.robust_EI = 0.05;
    t[i].dynamics.robust_residual_m = i ? 4e-4 : 5e-4;
    if (ea_task_check(&t[i], &e)) {
      fprintf(stderr, "bench_plan: %s\n", e.msg);
      return 1;
    }
  }
  printf("\nrobust refinement (paper line, 100 knots, 1 mode, corners tip mass +-20 %%, EI +-5 %%; "
         "FE at the nominal and the 4 corner arms per evaluation: 12 elements, genalpha, dt 2 "
         "ms, 3 s; tolerance 0.05 mm, 10 s cap)\nresidual = FE residual peak [mm]: nominal "
         "before/after (loop), worst corner before/after (loop), worst corner after (independent, "
         "dt 0.25 ms, hand mass and EI changed)\n");
  printf("%-24s %-7s %5s %7s %7s %7s %7s %7s %8s %8s %8s %8s %8s %s\n", "case", "method", "evals",
         "time s", "plan s", "FE s", "t_f0 s", "t_f s", "nom. 0", "nom.", "corn. 0", "corn.",
         "c dt.25", "stop");
  const ea_task_refine_method_t ms[3] = {EA_TASK_REFINE_NEWTON, EA_TASK_REFINE_BOBYQA,
                                         EA_TASK_REFINE_COBYLA};
  for (int j = 0; j < 3; ++j)
    robust_row(nm[0], &t[0], ms[j]);
  robust_row(nm[1], &t[1], EA_TASK_REFINE_NEWTON);
  return 0;
}

static int refine_rows(const ea_task_t *line) {
  ea_task_t t[2];
  const char *nm[2] = {"paper line, payload 0", "payload 0.5, (0.5,-0.2)"};
  ea_error_t e;
  for (int i = 0; i < 2; ++i) {
    t[i] = *line;
    t[i].dynamics.modes = 2;
    t[i].dynamics.residual_m = 0.0;
  }
  t[1].payload_kg = ea_arm_payload_from_factor(&line->arm, 0.5);
  t[1].goal = ea_task_point_planar(0.5, -0.2, 0.0);
  for (int i = 0; i < 2; ++i)
    if (ea_task_check(&t[i], &e)) {
      fprintf(stderr, "bench_plan: %s\n", e.msg);
      return 1;
    }
  printf("\nrefinement against the FE transient (100 knots, dynamics modes 2; loop FE: 12 "
         "elements, genalpha, dt 2 ms, 3 s)\nresidual = FE residual peak [mm]: before, after "
         "(loop), after (independent, dt 0.25 ms); dt_f = duration change\n");
  printf("%-22s %-7s %8s %5s %8s %8s %8s %9s %9s %9s %8s %s\n", "case", "method", "tol mm", "evals",
         "time s", "plan s", "FE s", "before", "after", "dt.25ms", "dt_f %", "stop");
  const ea_task_refine_method_t ms[4] = {EA_TASK_REFINE_NEWTON, EA_TASK_REFINE_BOBYQA,
                                         EA_TASK_REFINE_COBYLA, EA_TASK_REFINE_SBPLX};
  const double tols[2] = {5e-5, 1e-5};
  for (int i = 0; i < 2; ++i)
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 4; ++j)
        refine_row(nm[i], &t[i], ms[j], tols[k]);
  return 0;
}

/* Polylines over the knot count: a minimum-time polyline through one via, and the
 * polyline-effort example (problems/examples/polyline-effort.yaml, fixed 3 s, minimum
 * acceleration effort); the duration / objective of a cold plan at 30..400 knots (one solve
 * each, deterministic). Not converged (docs/planner.md, "Prescribed paths"). */
static void polyline_rows(void) {
  printf("\npolylines over the knot count (cold; not converged, docs/planner.md)\n");
  printf("%-28s %6s %12s %6s\n", "case", "knots", "value", "iters");
  ea_task_t a, b;
  ea_task_init(&a, NULL);
  a.start = ea_task_point_planar(0.3, -0.2, 0.0);
  a.via[0] = ea_task_point_planar(0.45, -0.12, 0.0);
  a.n_via = 1;
  a.goal = ea_task_point_planar(0.6, -0.25, 0.0);
  a.path = EA_TASK_PATH_POLYLINE;
  /* as `elasticarm plan` loads it: the arm file data/elasticarm.yaml */
  ea_error_t le = {0};
  if (ea_task_load(EA_SOURCE_DIR "/problems/examples/polyline-effort.yaml",
                   EA_SOURCE_DIR "/data/elasticarm.yaml", &b, &le)) {
    printf("bench_plan: %s\n", le.msg);
    return;
  }
  const int ks[5] = {30, 60, 100, 200, 400};
  for (int c = 0; c < 2; ++c)
    for (int i = 0; i < 5; ++i) {
      ea_task_t t = c ? b : a;
      t.knots = ks[i];
      ea_planner_t *pl = NULL;
      ea_error_t e;
      ea_plan_info_t info;
      const char *name = c ? "polyline-effort: objective" : "polyline min time: t_f [s]";
      if (ea_task_check(&t, &e) || ea_planner_alloc(&t, &pl, &e) ||
          ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e))
        printf("%-28s %6d FAILED: %s\n", name, ks[i], e.msg);
      else
        printf("%-28s %6d %12.6f %6d\n", name, ks[i], c ? info.objective : info.duration_s,
               info.iterations);
      ea_planner_free(pl);
    }
}

int main(int argc, char **argv) {
  const char *usage = "bench_plan [repetitions 1..1000] [replan|refine|robust|polyline]";
  const int R = ea_bench_count(argc, argv, 1, 5, 1000, usage);
  if (R < 0) return 2;
  const int only_replan = argc > 2 && !strcmp(argv[2], "replan");
  const int only_refine = argc > 2 && !strcmp(argv[2], "refine");
  const int only_robust = argc > 2 && !strcmp(argv[2], "robust");
  const int only_poly = argc > 2 && !strcmp(argv[2], "polyline");
  if (argc > 3 || (argc > 2 && !only_replan && !only_refine && !only_robust && !only_poly)) {
    fprintf(stderr, "bench_plan: unknown section '%s'\nusage: %s\n", argv[2], usage);
    return 2;
  }
  ea_task_t line;
  ea_task_init(&line, NULL);
  line.start = ea_task_point_planar(0.3, -0.2, 0.0); /* eq. 18, beta = 0 */
  line.goal = ea_task_point_planar(0.6, -0.2, 0.0);  /* beta = 1 */
  line.path = EA_TASK_PATH_LINE;
  line.knots = 100;
  ea_error_t e;
  if (ea_task_check(&line, &e)) {
    fprintf(stderr, "bench_plan: %s\n", e.msg);
    return 1;
  }
  printf("bench_plan: paper line (eq. 18), payload factor 0, minimum time; medians of %d\n", R);
  print_load("before");
  ea_bench_print_pace();
  printf("vars, cons = the knot layout's variables and rows; iters = Ipopt's iterations, or "
         "the own interior\npoint's (a prescribed path's cold plans, solver.nlp auto); rows = the "
         "rows of Ipopt's last solve (0: none;\nthe path transcription has its own, limit rows "
         "far inside their limits left out); statics = shots\nwith sensitivities in Ipopt's "
         "callbacks (Jacobian, Hessian), ipopt = the solver without callbacks\n(linear algebra, "
         "line search; KLU for the own interior point), rest = other callback work + checks;\n"
         "targets: <= 15 ms cold, <= 5 ms warm\n");
  row_t r;
  if (only_poly) {
    polyline_rows();
    return 0;
  }
  if (only_robust) {
    const int rc = robust_rows(&line);
    print_load("after");
    return rc;
  }
  if (only_refine) {
    const int rc = refine_rows(&line) || robust_rows(&line);
    print_load("after");
    return rc;
  }
  if (!only_replan) {
    double ta[64];
    const int Ra = R < 64 ? R : 64;
    for (int i = 0; i < Ra; ++i) {
      ea_planner_t *pa = NULL;
      const double t0 = ea_bench_now();
      if (ea_planner_alloc(&line, &pa, &e)) {
        fprintf(stderr, "bench_plan: %s\n", e.msg);
        return 1;
      }
      ta[i] = ea_bench_now() - t0;
      ea_planner_free(pa);
    }
    printf("\nea_planner_alloc (transcription, the path's statics splines): %.2f ms\n",
           1e3 * ea_bench_median(ta, Ra));
    header("paper line, 100 knots");
    r = run(&line, R, 0);
    print_row("cold, partial Hessian (default)", &r);
    r = run(&line, R, 1);
    print_row("warm (previous solution)", &r);
    ea_task_t ex = line;
    ex.solver.hessian_exact = 1;
    r = run(&ex, R, 0);
    print_row("cold, exact Hessian", &r);
    r = run(&ex, R, 1);
    print_row("warm, exact Hessian", &r);
    ea_task_t lm = line;
    lm.solver.hessian_exact = 0;
    r = run(&lm, R, 0);
    print_row("cold, limited-memory Hessian", &r);
    r = run(&lm, R, 1);
    print_row("warm, limited-memory Hessian", &r);

    header("cold solvers (solver.nlp, solver.screen_rows), the variants' solves alternating");
    {
      ea_task_t fr = line, k2 = line;
      fr.path = EA_TASK_PATH_FREE;
      k2.knots = 200;
      const struct {
        const char *name;
        const ea_task_t *t;
      } cs[] = {{"paper line", &line}, {"paper line, 200 knots", &k2}, {"free path", &fr}};
      for (size_t i = 0; i < sizeof cs / sizeof *cs; ++i) {
        /* the default (own interior point on a prescribed path), Ipopt with its rows screened,
         * Ipopt with every row; a free path: the last two */
        const int path = cs[i].t->path != EA_TASK_PATH_FREE;
        ea_task_t ts[3] = {*cs[i].t, *cs[i].t, *cs[i].t};
        ts[1].solver.engines = ts[2].solver.engines = EA_PLANNER_ENGINES_IPOPT;
        ts[2].solver.screen_rows = 0;
        static const char *const what[3] = {"own interior point", "Ipopt, rows screened",
                                            "Ipopt, every row"};
        row_t rr[3];
        run_alternating(ts + !path, 3 - !path, cs[i].t->knots >= 200 ? (R < 5 ? R : 5) : R, rr);
        for (int v = !path; v < 3; ++v) {
          char nm[64];
          snprintf(nm, sizeof nm, "%s: %s", cs[i].name, what[v]);
          print_row(nm, &rr[v - !path]);
        }
      }
    }

    header("replanning from a previous plan (EA_PLAN_FROM_TRAJ, 100 knots)");
    r = run_traj(&line, &line, R);
    print_row("same task", &r);
    ea_task_t moved = line;
    moved.goal = ea_task_point_planar(0.605, -0.2, 0.0);
    if (ea_task_check(&moved, &e)) {
      fprintf(stderr, "bench_plan: %s\n", e.msg);
      return 1;
    }
    r = run_traj(&line, &moved, R);
    print_row("goal moved 5 mm", &r);
  }

  header("replanning a live planner (ea_planner_update + EA_PLAN_WARM, 100 knots) vs cold");
  {
    ea_task_t ch[6];
    const char *nm[6] = {"goal moved 1 mm",
                         "goal moved 5 mm",
                         "goal moved 20 mm",
                         "start moved 5 mm",
                         "payload +5 % (factor 0.2 -> 0.21)",
                         "cable speed limit -10 %"};
    ea_task_t base[6];
    for (int i = 0; i < 6; ++i)
      base[i] = ch[i] = line;
    ch[0].goal = ea_task_point_planar(0.601, -0.2, 0.0);
    ch[1].goal = ea_task_point_planar(0.605, -0.2, 0.0);
    ch[2].goal = ea_task_point_planar(0.620, -0.2, 0.0);
    ch[3].start = ea_task_point_planar(0.305, -0.2, 0.0);
    base[4].payload_kg = ea_arm_payload_from_factor(&line.arm, 0.2);
    ch[4].payload_kg = 1.05 * base[4].payload_kg;
    ch[5].limits.cable_speed_max *= 0.9;
    for (int i = 0; i < 6; ++i) {
      if (ea_task_check(&base[i], &e) || ea_task_check(&ch[i], &e)) {
        fprintf(stderr, "bench_plan: %s\n", e.msg);
        return 1;
      }
      double upd = 0.0;
      char name[80];
      r = run(&ch[i], R, 0);
      snprintf(name, sizeof name, "%s: cold", nm[i]);
      print_row(name, &r);
      int newton = 0, by_ipm = 0;
      r = run_update(&base[i], &ch[i], R, &upd, &newton, &by_ipm);
      snprintf(name, sizeof name, "%s: replan", nm[i]);
      print_row(name, &r);
      /* the steps of a Newton that gave up are not published: how far it goes before it
       * diverges or stalls is not a figure of merit */
      if (r.iters == 0)
        printf("%-34s (ea_planner_update %.3f ms; active-set Newton: %d steps%s, no Ipopt)\n", "",
               1e3 * upd, newton, newton ? "" : " (the shifted plan passed the KKT test)");
      else
        printf("%-34s (ea_planner_update %.3f ms; active-set Newton: %s, %s)\n", "", 1e3 * upd,
               newton ? "gave up" : "not tried",
               by_ipm ? "the own interior point from the cold guess" : "Ipopt");
    }
  }

  if (only_replan) {
    print_load("after");
    return 0;
  }
  header("what features cost (100 knots, cold)");
  ea_task_t fr = line;
  fr.path = EA_TASK_PATH_FREE;
  r = run(&fr, R, 0);
  print_row("free path (no path rows)", &r);
  r = run(&line, R, 0);
  print_row("line path (2 rows per knot)", &r);
  ea_task_t b3 = line;
  b3.goal = ea_task_point_planar(0.6, -0.2, 0.3);
  b3.path = EA_TASK_PATH_FREE;
  ea_task_check(&b3, &e);
  r = run(&b3, R, 0);
  print_row("free + base turns 0.3 rad (3 coords)", &r);
  ea_task_t sh = line;
  sh.limits.shoulder_speed_max = 0.3;
  r = run(&sh, R, 0);
  print_row("line, shoulder speed 0.3 rad/s active", &r);
  /* the arm's shoulder acceleration (8 rad/s^2) and speed bind */
  ea_task_t sa = line;
  sa.payload_kg = ea_arm_payload_from_factor(&line.arm, 0.25);
  sa.start = ea_task_point_planar(0.25, -0.45, 0.0);
  sa.goal = ea_task_point_planar(0.6, -0.3, 0.0);
  if (ea_task_check(&sa, &e)) {
    fprintf(stderr, "bench_plan: %s\n", e.msg);
    return 1;
  }
  r = run(&sa, R, 0);
  print_row("line (0.25,-0.45)-(0.6,-0.3), g 0.25", &r);

  header("scaling with the knot count (line, cold)");
  /* the paper line's minimum time at the nominal limits: D / v + v / a */
  const double D = hypot(0.6 - 0.098, -0.2 + 0.006) - hypot(0.3 - 0.098, -0.2 + 0.006);
  const double tmin =
      D / line.limits.cable_speed_max + line.limits.cable_speed_max / line.limits.cable_accel_max;
  const int ks[] = {25, 50, 100, 200, 400, 1000, 2000};
  for (size_t i = 0; i < sizeof ks / sizeof *ks; ++i) {
    ea_task_t t = line;
    t.knots = ks[i];
    char name[64];
    snprintf(name, sizeof name, "%d knots", ks[i]);
    r = run(&t, ks[i] >= 1000 ? 1 : ks[i] >= 200 ? (R < 3 ? R : 3) : R, 0);
    print_row(name, &r);
    printf("%-34s %5s %5s %6s %5s %9.2f  (per iteration); t_f / (D/v + v/a) - 1 = %.2e\n", "", "",
           "", "", "", r.iters > 0 ? 1e3 * r.total / r.iters : 0.0, r.dur / tmin - 1.0);
  }
  polyline_rows();
  if (refine_rows(&line) || robust_rows(&line)) return 1;
  print_load("after");
  return 0;
}
