/* bench_dyn: plans that arrive at rest (task key dynamics), judged by the FE transient.
 *  1. knots: the at-rest paper line (payload 0, 2 modes) at 25..400 knots, both
 *     transcriptions, alternating: the solver's iterations, median wall and CPU time of a cold
 *     plan (ea_planner_alloc + ea_planner_solve) and wall time of its solve alone, the duration
 *     and its change against 400 knots, the model's predicted residual and the FE-measured one
 *     (ea_traj_simulate defaults: 12 elements, generalized-alpha, dt 1 ms, 3 s settle);
 *  2. the reduced-model table: built (empty cache) against loaded (cached);
 *  3. the table's grid: interpolation error at the cell centres against the model computed
 *     there directly (ea_rom_point: an independent FE solve), and what the grid does to the
 *     plan (duration, FE residual), from half to twice the default spacing;
 *  4. replanning after the goal moves 5 mm (warm) against a cold plan.
 * usage: bench_dyn [REPEATS] (default 3) */
#include "bench_util.h"
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_simulate.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int load(const char *name, ea_task_t *t) {
  char path[1024];
  snprintf(path, sizeof path, "%s/problems/examples/%s", EA_SOURCE_DIR, name);
  ea_error_t e;
  if (ea_task_load(path, NULL, t, &e)) {
    fprintf(stderr, "bench_dyn: %s\n", e.msg);
    return 1;
  }
  return 0;
}

typedef struct {
  int ok, iters;
  double wall, cpu, solve, dur, pred, fe;
} res_t;

/* One cold plan of t: wall and CPU time of ea_planner_alloc + ea_planner_solve, wall time of
 * the solve alone, its info; its trajectory into tr (when not NULL). 0, or 1 (printed). */
static int plan_once(const ea_task_t *t, double *wall, double *cpu, double *solve,
                     ea_plan_info_t *info, ea_traj_t *tr) {
  ea_error_t e;
  ea_planner_t *pl = NULL;
  const double w0 = ea_bench_now(), c0 = ea_bench_cpu_now();
  ea_status_t st = ea_planner_alloc(t, &pl, &e);
  const double w1 = ea_bench_now();
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, info, &e);
  *wall = ea_bench_now() - w0;
  *cpu = ea_bench_cpu_now() - c0;
  *solve = ea_bench_now() - w1;
  if (!st && tr) st = ea_planner_trajectory(pl, tr, &e);
  ea_planner_free(pl);
  if (st) fprintf(stderr, "bench_dyn: %s\n", e.msg);
  return st != EA_OK;
}

static double fe_residual(const ea_task_t *t, const ea_traj_t *tr) {
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  ea_sim_info_t si;
  ea_error_t e;
  return ea_traj_simulate(&t->arm, tr, 0.0, &s, NULL, &si, &e) ? NAN : si.residual_peak;
}

/* R cold plans of each of the M (<= 3) tasks, alternating (the machine's pace drifts): medians;
 * the last plans' FE residuals. */
static void plan_set(const ea_task_t *t, int M, int R, res_t *out) {
  double w[3][64], c[3][64], sv[3][64];
  R = R > 64 ? 64 : R;
  ea_traj_t tr[3] = {{0}, {0}, {0}};
  for (int m = 0; m < M; ++m)
    out[m] = (res_t){.ok = 1, .fe = NAN};
  for (int i = 0; i < R; ++i)
    for (int m = 0; m < M; ++m) {
      ea_plan_info_t info;
      if (!out[m].ok) continue;
      if (plan_once(&t[m], &w[m][i], &c[m][i], &sv[m][i], &info, i == R - 1 ? &tr[m] : NULL)) {
        out[m].ok = 0;
        continue;
      }
      out[m].iters = info.iterations;
      out[m].dur = info.duration_s;
      out[m].pred = info.predicted_residual_m;
    }
  for (int m = 0; m < M; ++m) {
    if (out[m].ok) {
      out[m].wall = ea_bench_median(w[m], R);
      out[m].cpu = ea_bench_median(c[m], R);
      out[m].solve = ea_bench_median(sv[m], R);
      out[m].fe = fe_residual(&t[m], &tr[m]);
    }
    ea_traj_free(&tr[m]);
  }
}

/* R cold plans (median times); the last plan's FE residual when fe. */
static res_t plan_rows(const ea_task_t *t, int R, int fe) {
  res_t r = {.ok = 1, .fe = NAN};
  double w[64], c[64], sv[64];
  R = R > 64 ? 64 : R;
  ea_traj_t tr = {0};
  for (int i = 0; i < R; ++i) {
    ea_plan_info_t info;
    if (plan_once(t, &w[i], &c[i], &sv[i], &info, i == R - 1 && fe ? &tr : NULL)) {
      r.ok = 0;
      ea_traj_free(&tr);
      return r;
    }
    r.iters = info.iterations;
    r.dur = info.duration_s;
    r.pred = info.predicted_residual_m;
  }
  r.wall = ea_bench_median(w, R);
  r.cpu = ea_bench_median(c, R);
  r.solve = ea_bench_median(sv, R);
  if (fe) r.fe = fe_residual(t, &tr);
  ea_traj_free(&tr);
  return r;
}

static void table_knots(const ea_task_t *base, int R) {
  printf("\n1. at-rest paper line (payload 0, 2 modes), cold plans: medians of %d (200 and 400 "
         "knots: 1), the path transcription on 2 threads (path; solver.threads, the default with 2 "
         "processors) and "
         "on 1, and the knot transcription, alternating; wall and cpu: ea_planner_alloc + "
         "ea_planner_solve, solve: ea_planner_solve alone (%d processors online)\n",
         R, (int)sysconf(_SC_NPROCESSORS_ONLN));
  printf("%-6s %-8s %6s %9s %9s %9s %12s %11s %10s %10s\n", "knots", "trans", "iters", "wall ms",
         "cpu ms", "solve ms", "t_f [s]", "dt_f/t_f", "pred mm", "FE mm");
  const int ks[5] = {25, 50, 100, 200, 400};
  const ea_task_transcription_t tk[3] = {EA_TASK_TRANSCRIPTION_PATH, EA_TASK_TRANSCRIPTION_PATH,
                                         EA_TASK_TRANSCRIPTION_KNOTS};
  const int th[3] = {2, 1, 0};
  const char *name[3] = {"path", "path-1t", "knots"};
  res_t rs[5][3];
  for (int i = 0; i < 5; ++i) {
    ea_task_t t[3] = {*base, *base, *base};
    for (int m = 0; m < 3; ++m) {
      t[m].knots = ks[i];
      t[m].solver.transcription = tk[m];
      t[m].solver.threads = th[m];
      ea_error_t e;
      if (ea_task_check(&t[m], &e)) {
        fprintf(stderr, "bench_dyn: %s\n", e.msg);
        return;
      }
    }
    plan_set(t, 3, ks[i] >= 200 ? 1 : R, rs[i]);
  }
  for (int m = 0; m < 3; ++m)
    for (int i = 0; i < 5; ++i) {
      const res_t *r = &rs[i][m];
      printf("%-6d %-8s %6d %9.1f %9.1f %9.1f %12.6f %11.2e %10.4f %10.4f%s\n", ks[i], name[m],
             r->iters, 1e3 * r->wall, 1e3 * r->cpu, 1e3 * r->solve, r->dur,
             (r->dur - rs[4][m].dur) / rs[4][m].dur, 1e3 * r->pred, 1e3 * r->fe,
             r->ok ? "" : "  FAILED");
    }
}

static void table_cache(const ea_task_t *t) {
  printf("\n2. reduced-model table of the at-rest paper line (2 modes): built vs cached\n");
  char dir[] = "/tmp/bench_dyn_XXXXXX";
  if (!mkdtemp(dir)) {
    printf("no temporary folder\n");
    return;
  }
  setenv("EA_CACHE_DIR", dir, 1);
  printf("%-8s %10s %8s %10s\n", "table", "wall ms", "grid", "cached");
  for (int pass = 0; pass < 2; ++pass) {
    ea_error_t e;
    ea_planner_t *pl = NULL;
    const double w0 = ea_bench_now();
    ea_status_t st = ea_planner_alloc(t, &pl, &e);
    const double w = ea_bench_now() - w0;
    ea_plan_dyn_info_t di;
    if (!st && !ea_planner_dyn_model(pl, &di))
      printf("%-8s %10.1f %4dx%-3d %10s\n", pass ? "loaded" : "built", 1e3 * di.time_s,
             di.table.n_cable_length, di.table.n_cable_angle, di.cache_loaded ? "yes" : "no");
    else
      printf("failed: %s\n", e.msg);
    (void)w;
    /* leave the cache file behind for pass 1, remove it afterwards */
    if (pass == 1 && !st) remove(di.cache_path);
    ea_planner_free(pl);
  }
  rmdir(dir);
  unsetenv("EA_CACHE_DIR");
}

/* Max relative error of the table at the cell centres against ea_rom_point there. */
static void grid_error(const ea_task_t *t, const ea_rom_table_t *tb, double err[4]) {
  ea_rom_table_info_t ti;
  ea_rom_table_info(tb, &ti);
  ea_rom_t *r = NULL;
  ea_error_t e;
  err[0] = err[1] = err[2] = err[3] = NAN;
  if (ea_rom_alloc(&t->arm, ea_arm_tip_mass(&t->arm, t->payload_kg), NULL, &r, &e)) return;
  const int nL = ti.n_cable_length, na = ti.n_cable_angle;
  const double hL = (ti.box[1] - ti.box[0]) / (nL - 1), ha = (ti.box[3] - ti.box[2]) / (na - 1);
  double ew = 0, eB = 0, et = 0;
  int n = 0;
  for (int i = 0; i + 1 < nL; ++i)
    for (int j = 0; j + 1 < na; ++j) {
      const double L = ti.box[0] + (i + 0.5) * hL, a = ti.box[2] + (j + 0.5) * ha;
      ea_rom_point_t d, v;
      if (ea_rom_point(r, L, a, 0, &d, &e)) continue; /* not a stable state */
      ea_rom_table_eval(tb, L, a, &v, NULL, NULL);
      for (int k = 0; k < d.modes; ++k) {
        /* the direct point's sign convention (tip y >= 0) against the table's continued signs */
        const double s = d.tip[k][0] * v.tip[k][0] + d.tip[k][1] * v.tip[k][1] < 0 ? -1.0 : 1.0;
        ew = fmax(ew, fabs(sqrt(v.omega2[k]) / sqrt(d.omega2[k]) - 1));
        eB = fmax(eB, hypot(s * v.B[k][0] - d.B[k][0], (s * v.B[k][1] - d.B[k][1]) * 0.3) /
                          hypot(d.B[k][0], d.B[k][1] * 0.3));
        et = fmax(et, hypot(s * v.tip[k][0] - d.tip[k][0], s * v.tip[k][1] - d.tip[k][1]) /
                          hypot(d.tip[k][0], d.tip[k][1]));
      }
      ++n;
    }
  ea_rom_free(r);
  err[0] = ew;
  err[1] = eB;
  err[2] = et;
  err[3] = n;
}

static void table_grid(const ea_task_t *base) {
  printf("\n3. the table's grid: interpolation error at the cell centres (max relative, against "
         "ea_rom_point there) and the at-rest plan with it\n");
  printf("%-8s %8s %10s %10s %10s %7s %12s %10s\n", "spacing", "grid", "omega err", "B err",
         "tip err", "cells", "t_f [s]", "FE mm");
  ea_task_t t = *base;
  ea_error_t e;
  ea_planner_t *pl = NULL;
  if (ea_task_check(&t, &e) || ea_planner_alloc(&t, &pl, &e)) {
    printf("failed: %s\n", e.msg);
    return;
  }
  ea_plan_dyn_info_t di;
  ea_planner_dyn_model(pl, &di);
  ea_planner_free(pl);
  const int n0 = di.table.n_cable_length, m0 = di.table.n_cable_angle;
  const double f[3] = {2.0, 1.0, 0.5};
  for (int i = 0; i < 3; ++i) {
    t = *base;
    t.dynamics.grid[0] = (int)lround((n0 - 1) / f[i]) + 1;
    t.dynamics.grid[1] = (int)lround((m0 - 1) / f[i]) + 1;
    if (t.dynamics.grid[0] > 48) t.dynamics.grid[0] = 48;
    if (t.dynamics.grid[1] > 48) t.dynamics.grid[1] = 48;
    if (ea_task_check(&t, &e) || ea_planner_alloc(&t, &pl, &e)) {
      printf("failed: %s\n", e.msg);
      continue;
    }
    double err[4];
    grid_error(&t, ea_planner_rom_table(pl), err);
    ea_planner_free(pl);
    const res_t r = plan_rows(&t, 1, 1);
    printf("%-8s %4dx%-3d %10.2e %10.2e %10.2e %7.0f %12.6f %10.4f\n",
           i == 0   ? "x2"
           : i == 1 ? "default"
                    : "x1/2",
           t.dynamics.grid[0], t.dynamics.grid[1], err[0], err[1], err[2], err[3], r.dur,
           1e3 * r.fe);
  }
}

static void table_replan(const ea_task_t *base, int R) {
  printf("\n4. replanning the at-rest paper line after the goal moves 5 mm in x (medians of %d)\n",
         R);
  printf("%-10s %6s %9s %9s %12s\n", "start", "iters", "wall ms", "cpu ms", "t_f [s]");
  ea_task_t t = *base;
  ea_error_t e;
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  if (ea_task_check(&t, &e) || ea_planner_alloc(&t, &pl, &e) ||
      ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e)) {
    printf("failed: %s\n", e.msg);
    ea_planner_free(pl);
    return;
  }
  double w[64], c[64], it = 0, dur = 0;
  R = R > 64 ? 64 : R;
  int ok = 1;
  for (int i = 0; i < R; ++i) {
    /* alternately 5 mm out and back: every re-plan moves the goal 5 mm */
    ea_task_point_t g =
        ea_task_point_planar(t.goal.given[0] + (i % 2 ? 0.0 : 0.005), t.goal.given[1], 0.0);
    const double w0 = ea_bench_now(), c0 = ea_bench_cpu_now();
    ea_status_t st = ea_planner_update_goal(pl, &g, &e);
    if (!st) st = ea_planner_solve(pl, EA_PLAN_WARM, NULL, &info, &e);
    w[i] = ea_bench_now() - w0;
    c[i] = ea_bench_cpu_now() - c0;
    if (st) ok = 0;
    it = info.iterations;
    dur = info.duration_s;
  }
  printf("%-10s %6.0f %9.1f %9.1f %12.6f%s\n", "warm", it, 1e3 * ea_bench_median(w, R),
         1e3 * ea_bench_median(c, R), dur, ok ? "" : "  FAILED");
  ea_planner_free(pl);
  t.goal = ea_task_point_planar(t.goal.given[0] + 0.005, t.goal.given[1], 0.0);
  if (!ea_task_check(&t, &e)) {
    const res_t r = plan_rows(&t, R, 0);
    printf("%-10s %6d %9.1f %9.1f %12.6f%s\n", "cold", r.iters, 1e3 * r.wall, 1e3 * r.cpu, r.dur,
           r.ok ? "" : "  FAILED");
  }
}

int main(int argc, char **argv) {
  const int R = ea_bench_count(argc, argv, 1, 3, 1000, "bench_dyn [repetitions 1..1000]");
  if (R < 0 || argc > 2) return 2;
  ea_task_t t;
  if (load("paper-line-rest.yaml", &t)) return 1;
  FILE *fp = fopen("/proc/loadavg", "r");
  char buf[128] = "?\n";
  if (fp) {
    if (!fgets(buf, sizeof buf, fp)) snprintf(buf, sizeof buf, "?\n");
    fclose(fp);
  }
  printf("bench_dyn: load average %s", buf);
  ea_bench_print_pace();
  table_cache(&t);
  table_knots(&t, R < 1 ? 1 : R);
  table_grid(&t);
  table_replan(&t, R < 2 ? 2 : R);
  return 0;
}
