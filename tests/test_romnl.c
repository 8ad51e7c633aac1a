/* The reduced model at large modal deflection (model/fe_romnl.c; issue 33, item 1): on plans that
 * are not at rest (dynamics residual_m 5 mm: the linear model lets the plan ring by 5 mm, the FE
 * rings more), its predicted residual against the FE's at converged settings (12 elements,
 * generalized-alpha, dt 0.5 ms, 3 s after the motion, undamped): within 20 % or 0.2 mm, whichever
 * is larger, on the diagonal and on seeded random lines. The linear model's prediction is
 * printed beside it (it is off by up to 4.5 times on such lines). */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_refine.h"
#include "ea_simulate.h"
#include "ea_test.h"
#include "ea_test_sweep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static char table[16][200]; /* the prediction table's rows */
static int n_lines, n_within, samples = EA_ROMNL_SAMPLES;
static double worst_rel, worst_lin;

static void line(const ea_task_t *base, ea_task_point_t a, ea_task_point_t b, double pf,
                 const char *name) {
  ea_task_t t = *base;
  t.payload_factor = pf;
  t.payload_kg = ea_arm_payload_from_factor(&t.arm, pf);
  t.start = a;
  t.goal = b;
  t.path = EA_TASK_PATH_LINE;
  ea_error_t e = {0};
  if (ea_task_check(&t, &e)) return;
  ea_planner_t *pl = NULL;
  ea_plan_info_t pi;
  ea_traj_t tr;
  memset(&tr, 0, sizeof tr);
  ea_romnl_t *r = NULL;
  ea_status_t st = ea_planner_alloc(&t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &pi, &e);
  if (!st) st = ea_planner_trajectory(pl, &tr, &e);
  if (st) { /* refused by a limit: not a plan to measure */
    ea_planner_free(pl);
    return;
  }
  const ea_rom_table_t *tb = ea_planner_rom_table(pl);
  ea_rom_prediction_t lin, nl;
  double dist = NAN;
  st = ea_traj_rom_predict(tb, &tr, 1e-4, 3.0, &lin, &e);
  if (!st) st = ea_romnl_alloc(&t.arm, ea_arm_tip_mass(&t.arm, t.payload_kg), 0, &r, &e);
  if (!st) st = ea_traj_romnl_sample(r, tb, &tr, samples, &e);
  if (!st) st = ea_traj_romnl_predict(tb, r, &tr, 1e-4, 3.0, &nl, &dist, &e);
  ea_romnl_info_t ri = {0};
  ea_romnl_info(r, &ri);
  const double fe = ea_ts_fe_converged(&t, &tr);
  char what[600];
  if (st) {
    snprintf(what, sizeof what, "%s: the nonlinear model ran: %s", name, e.msg);
    ea_test_true(0, what);
  } else {
    const double err = nl.residual_peak - fe, tol = fmax(0.2 * fe, 2e-4);
    if (n_lines < 16)
      snprintf(table[n_lines], sizeof table[n_lines],
               "| %s | %.3f | %.1f | %.3f | %.3f | %+.1f | %.3f |", name, pf,
               1e3 * nl.max_deviation, 1e3 * fe, 1e3 * nl.residual_peak, 100 * err / fe,
               1e3 * lin.residual_peak);
    ++n_lines;
    n_within += fabs(err) <= tol;
    worst_rel = fmax(worst_rel, fabs(err) / fe);
    worst_lin = fmax(worst_lin, fmax(fe / lin.residual_peak, lin.residual_peak / fe));
    snprintf(what, sizeof what,
             "%s (%.4f, %.4f) -> (%.4f, %.4f) payload %.3f: FE residual %.3f mm, nonlinear model "
             "%.3f mm (%+.1f %%, within 20 %% or 0.2 mm), linear %.3f mm; modal tip deviation "
             "%.1f mm; sampled in %.0f ms, path distance %.2g m",
             name, a.given[0], a.given[1], b.given[0], b.given[1], pf, 1e3 * fe,
             1e3 * nl.residual_peak, 100 * err / fe, 1e3 * lin.residual_peak,
             1e3 * nl.max_deviation, 1e3 * ri.time_s, dist);
    ea_test_true(fabs(err) <= tol, what);
  }
  ea_romnl_free(r);
  ea_traj_free(&tr);
  ea_planner_free(pl);
}

/* At rest by the model alone: the at-rest plan refined with refine.by model_only (no FE
 * transient runs), then the FE at converged settings; on polylines also the unrefined plan's. */
typedef struct {
  int lines, within, refused, better;
  double worst, times[256];
} rest_tally_t;

static int rest_line(const ea_task_t *base, ea_task_point_t a, ea_task_point_t b, double pf,
                     const char *name, int n_via, const ea_task_point_t *via, rest_tally_t *y) {
  ea_task_t t = *base;
  t.n_via = n_via;
  for (int i = 0; i < n_via; ++i)
    t.via[i] = via[i];
  t.payload_factor = pf;
  t.payload_kg = ea_arm_payload_from_factor(&t.arm, pf);
  t.start = a;
  t.goal = b;
  t.path = n_via ? EA_TASK_PATH_POLYLINE : EA_TASK_PATH_LINE;
  t.dynamics.residual_m = 0.0;
  ea_error_t e = {0};
  if (ea_task_check(&t, &e)) return 0;
  ea_planner_t *pl = NULL;
  ea_plan_info_t pi;
  ea_traj_t tr;
  memset(&tr, 0, sizeof tr);
  ea_refine_info_t *ri = calloc(1, sizeof *ri);
  const double t0 = ea_ts_mono();
  ea_status_t st = ea_planner_alloc(&t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &pi, &e);
  if (st || !ri) { /* refused by a limit */
    ea_planner_free(pl);
    free(ri);
    return 0;
  }
  double before = NAN; /* the at-rest plan's own FE residual (polylines) */
  if (n_via && !ea_planner_trajectory(pl, &tr, &e)) before = ea_ts_fe_converged(&t, &tr);
  ea_task_refine_t rs;
  ea_plan_rest_settings(&t, &rs);
  rs.by = EA_TASK_REFINE_BY_MODEL_ONLY;
  st = ea_plan_refine(pl, &rs, &pi, ri, &e);
  if (!st) st = ea_planner_trajectory(pl, &tr, &e);
  const double dt = ea_ts_mono() - t0;
  char what[700];
  if (st) {
    snprintf(what, sizeof what, "%s: at rest by the model: %s", name, e.msg);
    ea_test_true(0, what);
  } else if (!ri->converged) {
    ++y->refused;
    printf("  %s (%.4f, %.4f) -> (%.4f, %.4f) payload %.3f: the model's loop did not reach rest: "
           "%s\n",
           name, a.given[0], a.given[1], b.given[0], b.given[1], pf, ri->message);
  } else {
    const double fe = ea_ts_fe_converged(&t, &tr);
    ++y->lines;
    y->within += fe <= 1e-3;
    y->better += fe < 0.5 * before;
    y->worst = fmax(y->worst, fe);
    if (y->lines <= 256) y->times[y->lines - 1] = dt;
    snprintf(what, sizeof what,
             "%s (%.4f, %.4f) -> (%.4f, %.4f) payload %.3f: at rest by the model alone "
             "(predicted %.3f mm -> %.4f mm in %d evaluations, %.0f ms, %d FE transients), FE "
             "residual %.4f mm (the at-rest plan's %.4f mm); duration %.4f -> %.4f s",
             name, a.given[0], a.given[1], b.given[0], b.given[1], pf,
             1e3 * ri->residual_peak_before_m, 1e3 * ri->residual_peak_m, ri->n_evals, 1e3 * dt,
             ri->n_evals - ri->model_evals, 1e3 * fe, 1e3 * before, ri->duration_before_s,
             ri->duration_s);
    printf("  %s\n", what);
  }
  ea_traj_free(&tr);
  ea_planner_free(pl);
  free(ri);
  return 1;
}

/* Tasks drawn until n are planned (the task check and the planner refuse some): lines, or
 * polylines through n_via random points. */
static void rest_sweep(const ea_task_t *base, uint64_t *rng, int n, int n_via, rest_tally_t *y) {
  for (int i = 0, done = 0; done < n && i < 40 * n; ++i) {
    char name[40];
    snprintf(name, sizeof name, "at rest: %s %d", n_via ? "polyline" : "line", done + 1);
    const double pf = 0.5 * ea_ts_urand(rng);
    const ea_task_point_t p0 = ea_ts_rand_point(rng), p1 = ea_ts_rand_point(rng);
    ea_task_point_t via[EA_TASK_MAX_VIA];
    memset(via, 0, sizeof via);
    for (int k = 0; k < n_via; ++k)
      via[k] = ea_ts_rand_point(rng);
    done += rest_line(base, p0, p1, pf, name, n_via, via, y);
  }
}

static int cmpd(const void *x, const void *y) {
  const double a = *(const double *)x, b = *(const double *)y;
  return (a > b) - (a < b);
}

int main(int argc, char **argv) {
  const char *s = getenv("EA_SOURCE_DIR");
  char arm[1200];
  snprintf(arm, sizeof arm, "%s/data/elasticarm.yaml", s ? s : ".");
  ea_arm_t a;
  ea_error_t e = {0};
  if (ea_arm_load(arm, &a, &e)) {
    ea_test_true(0, e.msg);
    return ea_test_summary("test_romnl");
  }
  ea_task_t base;
  ea_task_init(&base, &a);
  snprintf(base.name, sizeof base.name, "romnl");
  base.objective = EA_TASK_MIN_TIME;
  base.dynamics.modes = 2;
  base.dynamics.residual_m = 0.005;
  base.dynamics.verify = 0;
  const ea_task_point_t d0 = {.kind = EA_TASK_TIP_PLANAR, .given = {0.25, -0.45}};
  const ea_task_point_t d1 = {.kind = EA_TASK_TIP_PLANAR, .given = {0.6, -0.3}};
  line(&base, d0, d1, 0.25, "the diagonal");
  uint64_t rng = EA_TS_SEED ^ 0x51ULL;
  const int n = argc > 1 ? atoi(argv[1]) : 8;
  if (argc > 2) samples = atoi(argv[2]);
  for (int i = 0; i < n; ++i) {
    char name[32];
    snprintf(name, sizeof name, "line %d", i + 1);
    const double pf = 0.5 * ea_ts_urand(&rng);
    const ea_task_point_t p0 = ea_ts_rand_point(&rng), p1 = ea_ts_rand_point(&rng);
    line(&base, p0, p1, pf, name);
  }
  printf(
      "\n| line | payload factor | modal tip deviation [mm] | FE residual [mm] | nonlinear model "
      "[mm] | its error [%%] | linear model [mm] |\n|---|---|---|---|---|---|---|\n");
  for (int i = 0; i < n_lines && i < 16; ++i)
    printf("%s\n", table[i]);
  printf(
      "\n%d lines measured, %d within; worst nonlinear error %.1f %%; the linear model off by up "
      "to %.2f times\n",
      n_lines, n_within, 100 * worst_rel, worst_lin);
  ea_test_true(n_lines >= (n > 4 ? 4 : n), "at least 4 lines planned and measured");
  /* at rest by the model alone: the diagonal and seeded random lines */
  rest_tally_t L, P;
  memset(&L, 0, sizeof L);
  memset(&P, 0, sizeof P);
  rest_line(&base, d0, d1, 0.25, "at rest: the diagonal", 0, NULL, &L);
  rng = EA_TS_SEED ^ 0x52ULL;
  const int nr = argc > 3 ? atoi(argv[3]) : 20;
  rest_sweep(&base, &rng, nr, 0, &L);
  const int np = argc > 4 ? atoi(argv[4]) : 8;
  rest_sweep(&base, &rng, np, 2, &P);
  for (int k = 0; k < 2; ++k) {
    rest_tally_t *y = k ? &P : &L;
    const int m = y->lines < 256 ? y->lines : 256;
    qsort(y->times, (size_t)m, sizeof(double), cmpd);
    printf("at rest by the model alone, %s: %d planned, %d within 1 mm by the FE (worst %.4f mm), "
           "%d not at rest in the model's loop; time per plan median %.0f ms\n",
           k ? "polylines" : "lines", y->lines, y->within, 1e3 * y->worst, y->refused,
           m ? 1e3 * y->times[m / 2] : NAN);
  }
  /* issue 33, item 1: model-only at-rest plans <= 1 mm on at least 95 % of a random sweep of
   * straight lines (measured: every one) */
  ea_test_true(L.lines + L.refused >= nr + 1 && L.refused == 0 && L.within == L.lines,
               "at rest by the model alone, lines: every one ends <= 1 mm by the FE");
  /* polylines run longer, where the model's error grows (docs/fe.md): the model alone at least
   * halves each at-rest plan's FE residual, and the default check (the FE) is what keeps the
   * promise there (tests/test_rest_sweep) */
  ea_test_true(P.lines + P.refused >= np && P.refused <= 1 && P.better == P.lines &&
                   2 * P.within >= P.lines,
               "at rest by the model alone, polylines: each halves the at-rest plan's FE "
               "residual, at least half within 1 mm");
  return ea_test_summary("test_romnl");
}
