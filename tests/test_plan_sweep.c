/* Robustness sweep: random start/goal pairs (planar and 3-D) and payloads.
 * Pairs the task check accepts must plan (status EA_OK, every knot in
 * statics, T >= T_min); pairs outside the workspace must be reported as
 * infeasible, never planned. Run as a `slow` test with 200 pairs, free paths (the knot
 * transcription) and then straight lines (the path transcription, whose planner may also
 * report the line leaving the workspace between admissible ends);
 * test_plan.c includes it for a short unit sweep. */
#include "ea_plan_check.h"
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Deterministic generator (xorshift64*), independent of libc's rand(). */
static double ea_sweep_rand(unsigned long long *s) {
  *s ^= *s >> 12;
  *s ^= *s << 25;
  *s ^= *s >> 27;
  return (double)((*s * 2685821657736338717ULL) >> 11) / 9007199254740992.0;
}

/* Largest relative excess of a limit accepted by the 1 kHz re-check of the
 * written file (ea_plan_check.h). */
#define EA_SWEEP_LIMIT_TOL 0.0

/* Every limit between the knots of trajectory tr of task t, from its written file at 1 kHz:
 * 1 when the worst relative excess is within EA_SWEEP_LIMIT_TOL (the worst and the theta0
 * spline's deviation are accumulated into *worst, *th_dev). */
static int ea_sweep_file(const ea_task_t *t, const ea_traj_t *tr, double *worst, double *th_dev) {
  char csv[] = "/tmp/ea_sweep_XXXXXX";
  const int fd = mkstemp(csv);
  ea_traj_t back = {0};
  ea_error_t e;
  if (fd >= 0) close(fd);
  const int io = fd >= 0 && !ea_traj_write(tr, csv, &e) && !ea_traj_read(&back, csv, &e);
  if (fd >= 0) remove(csv);
  int ok = io;
  if (ok) {
    ea_chk_t c;
    const double w = ea_chk_traj(t, &back, 1000.0, &c);
    *worst = fmax(*worst, w);
    *th_dev = fmax(*th_dev, c.th_dev);
    if (w > EA_SWEEP_LIMIT_TOL) {
      ok = 0;
      ea_chk_print("limits re-checked at 1 kHz", &c);
    }
  }
  ea_traj_free(&back);
  return ok;
}

/* Replans of the line sweep: each planned line's goal moved by up to 5 mm in L_c and 0.01 rad
 * in alpha (its own random stream: the sweep's draws and published totals are unchanged),
 * ea_planner_update + EA_PLAN_WARM (the active-set Newton where it holds, else Ipopt) against
 * a cold plan of the moved task by a fresh planner: the same outcome, the duration to 1e-6,
 * every limit from the written file at 1 kHz. */
typedef struct {
  int n, newton, ipm, ipopt, both_infeasible, failures;
  double worst_dur, worst_excess, th_dev;
} ea_sweep_rp_t;

static void ea_sweep_replan(ea_planner_t *pl, const ea_task_t *t0, unsigned long long seed,
                            ea_sweep_rp_t *rp) {
  ea_task_t t = *t0;
  const double dL = 0.005 * (2.0 * ea_sweep_rand(&seed) - 1.0);
  const double da = 0.01 * (2.0 * ea_sweep_rand(&seed) - 1.0);
  t.goal =
      ea_task_point_actuators(t0->goal.given[0] + dL, t0->goal.given[1] + da, t0->goal.given[2]);
  ea_error_t e = {0};
  if (ea_task_check(&t, &e)) return; /* moved out of the workspace: no replan to compare */
  ea_plan_info_t w, c;
  ea_planner_t *p2 = NULL;
  ea_status_t sw = ea_planner_update(pl, &t, &e);
  if (!sw) sw = ea_planner_solve(pl, EA_PLAN_WARM, NULL, &w, &e);
  /* the reference: a cold plan by Ipopt (the replans that the active-set Newton gives up are
   * solved by the own interior point from the cold guess, as a cold plan is) */
  ea_task_t ti = t;
  ti.solver.engines = EA_PLANNER_ENGINES_IPOPT;
  ea_status_t sc = ea_planner_alloc(&ti, &p2, &e);
  if (!sc) sc = ea_planner_solve(p2, EA_PLAN_COLD, NULL, &c, &e);
  ea_planner_free(p2);
  ++rp->n;
  char what[400];
  if (sw != sc) {
    ++rp->failures;
    snprintf(what, sizeof what, "replan sweep: warm %s, cold %s (goal moved %.4f m, %.4f rad)",
             ea_status_name(sw), ea_status_name(sc), dL, da);
    ea_test_true(0, what);
    return;
  }
  if (sw) {
    ++rp->both_infeasible;
    return;
  }
  const int newton = w.iterations == 0 && w.newton_steps > 0;
  rp->newton += newton;
  const int by_ipm = w.ipm_iterations > 0 && !w.ipm_fallback;
  rp->ipm += by_ipm;
  rp->ipopt += w.iterations > 0 && !by_ipm;
  const double d = w.duration_s / c.duration_s - 1.0;
  rp->worst_dur = fmax(rp->worst_dur, fabs(d));
  ea_traj_t tr = {0};
  int ok = fabs(d) <= 1e-6 && !ea_planner_trajectory(pl, &tr, &e) &&
           ea_sweep_file(&t, &tr, &rp->worst_excess, &rp->th_dev);
  ea_traj_free(&tr);
  if (!ok) {
    ++rp->failures;
    snprintf(what, sizeof what,
             "replan sweep: goal moved %.4f m, %.4f rad: warm %.12g s (%s) vs cold %.12g s", dL, da,
             w.duration_s,
             newton   ? "Newton"
             : by_ipm ? "own interior point"
                      : "Ipopt",
             c.duration_s);
    ea_test_true(0, what);
  }
}

/* Returns the number of failures. path: free, or line (the path transcription). */
static int ea_sweep_run(int n, unsigned long long seed, int knots, ea_task_path_t path) {
  int planned = 0, infeasible = 0, failures = 0, outside_reported = 0;
  double tmax = 0.0, chk_worst = -INFINITY, th_dev = 0.0;
  int n_between = 0; /* plans re-solved for a limit exceeded between knots */
  int line_left = 0; /* line paths the planner reported leaving the workspace */
  long iters = 0, resolves = 0;
  /* the path transcription's cold solves by the own interior point (solver.nlp auto) against
   * the same tasks solved by Ipopt (solver.nlp ipopt) */
  int ipm = 0, ipm_fallback = 0, ipm_cmp = 0, ipm_bad = 0;
  double ipm_worst = 0.0;
  ea_sweep_rp_t rp = {0, 0, 0, 0, 0, 0, 0.0, -INFINITY, 0.0};
  for (int i = 0; i < n; ++i) {
    ea_task_t t;
    ea_task_init(&t, NULL);
    t.knots = knots;
    t.path = path;
    const double gamma = 0.5 * ea_sweep_rand(&seed);
    t.payload_factor = gamma;
    t.payload_kg = ea_arm_payload_from_factor(&t.arm, gamma);
    const int three_d = i % 2;
    for (int e = 0; e < 2; ++e) {
      const double Lc = 0.26 + 0.5 * ea_sweep_rand(&seed);
      const double al = -1.1 + 1.3 * ea_sweep_rand(&seed);
      const double b = three_d ? -1.4 + 2.8 * ea_sweep_rand(&seed) : 0.0;
      ea_task_point_t p = ea_task_point_actuators(Lc, al, b);
      if (e == 0)
        t.start = p;
      else
        t.goal = p;
    }
    /* Every 10th: a goal beyond the outer edge on purpose. */
    const int on_purpose = i % 10 == 9;
    if (on_purpose) {
      t.start = ea_task_point_actuators(0.3, -0.6, t.start.given[2]);
      t.goal = ea_task_point_actuators(0.95, -0.1, t.goal.given[2]);
    }
    ea_error_t e = {0};
    ea_status_t st = ea_task_check(&t, &e);
    char what[700];
    if (st) {
      const int ok = st == EA_ERR_INFEASIBLE;
      ++infeasible;
      if (on_purpose && ok && strstr(e.msg, "goal")) ++outside_reported;
      if (!ok) {
        ++failures;
        snprintf(what, sizeof what, "sweep %d: check failed with %s: %s", i, ea_status_name(st),
                 e.msg);
        ea_test_true(0, what);
      }
      continue;
    }
    if (on_purpose) {
      ++failures;
      ea_test_true(0, "sweep: a goal beyond the outer edge was accepted");
      continue;
    }
    ea_planner_t *pl = NULL;
    ea_plan_info_t info;
    st = ea_planner_alloc(&t, &pl, &e);
    if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
    /* a straight line between two admissible points can leave the workspace: the planner
     * must say so (where, which limit), never plan it */
    if (path == EA_TASK_PATH_LINE && st == EA_ERR_INFEASIBLE &&
        strstr(e.msg, "prescribed path leaves the workspace") && strstr(e.msg, "knot")) {
      ++infeasible;
      ++line_left;
      ea_planner_free(pl);
      continue;
    }
    int ok = st == EA_OK;
    const char *why = st ? e.msg : "limits violated";
    char whyb[160];
    if (ok) {
      ea_traj_t tr;
      memset(&tr, 0, sizeof tr);
      ok = ea_planner_trajectory(pl, &tr, &e) == EA_OK;
      if (!ok) why = "no trajectory";
      for (int k = 0; ok && k < tr.n; ++k)
        if (!(ok = EA_TRAJ_AT(&tr, k, EA_TRAJ_tension) >= t.limits.tension_min - 1e-9))
          why = "tension below tension_min at a knot";
      if (ok && !(info.max_statics_residual <= 1e-9)) {
        ok = 0;
        snprintf(whyb, sizeof whyb, "statics residual %.3g above 1e-9", info.max_statics_residual);
        why = whyb;
      }
      if (ok && !ea_sweep_file(&t, &tr, &chk_worst, &th_dev)) {
        ok = 0;
        why = "limits re-checked at 1 kHz from the written file";
      }
      ea_traj_free(&tr);
      if (ok && path == EA_TASK_PATH_LINE)
        ea_sweep_replan(pl, &t, 0xD1B54A32D192ED03ULL ^ (unsigned long long)i, &rp);
      tmax = fmax(tmax, info.time_total_s);
      if (info.between_passes) ++n_between;
      iters += info.iterations;
      resolves += info.screen_resolves;
      ++planned;
      if (info.ipm_iterations || info.ipm_fallback) {
        ipm += !info.ipm_fallback;
        ipm_fallback += info.ipm_fallback;
        ea_task_t ti = t;
        ti.solver.engines = EA_PLANNER_ENGINES_IPOPT;
        ea_planner_t *pi = NULL;
        ea_plan_info_t ii;
        ++ipm_cmp;
        if (ea_planner_alloc(&ti, &pi, &e) || ea_planner_solve(pi, EA_PLAN_COLD, NULL, &ii, &e) ||
            ii.ipm_iterations)
          ++ipm_bad;
        else
          ipm_worst = fmax(ipm_worst, fabs(info.duration_s / ii.duration_s - 1.0));
        ea_planner_free(pi);
      }
    }
    if (!ok) {
      ++failures;
      snprintf(what, sizeof what,
               "sweep %d (gamma %.3f, %s, start L_c %.3f alpha %.3f base %.3f, goal L_c %.3f "
               "alpha %.3f base %.3f): %s",
               i, gamma, three_d ? "3-D" : "planar", t.start.given[0], t.start.given[1],
               t.start.given[2], t.goal.given[0], t.goal.given[1], t.goal.given[2], why);
      ea_test_true(0, what);
    }
    ea_planner_free(pl);
  }
  char what[400];
  snprintf(what, sizeof what,
           "sweep of %d (%s paths): %d planned, %d reported infeasible (%d beyond the edge on "
           "purpose, %d lines leaving the workspace between admissible ends), %d failures; "
           "slowest plan %.3f s; %ld iterations in all (Ipopt's or the own interior point's); "
           "%ld Ipopt solves repeated with a left-out row at its limit",
           n, path == EA_TASK_PATH_LINE ? "line" : "free", planned, infeasible, outside_reported,
           line_left, failures, tmax, iters, resolves);
  ea_test_true(failures == 0, what);
  snprintf(what, sizeof what,
           "sweep: every limit re-checked from the written files at 1 kHz: worst relative "
           "excess %.3g (tolerance %.0e); theta0 spline vs statics at the interpolated (L_c, "
           "alpha) %.3g rad; %d plans re-solved with knot bounds tightened",
           chk_worst, EA_SWEEP_LIMIT_TOL, th_dev, n_between);
  ea_test_true(chk_worst <= EA_SWEEP_LIMIT_TOL, what);
  ea_test_true(planned >= n / 3, "sweep: at least a third of the pairs are feasible and planned");
  if (path == EA_TASK_PATH_LINE) {
    snprintf(what, sizeof what,
             "sweep (line paths): %d cold plans by the own interior point, %d by Ipopt after it "
             "gave no plan that passed the KKT test; each against the task solved by Ipopt "
             "(solver.nlp ipopt): worst duration difference %.2g (1e-6), %d Ipopt solves failed",
             ipm, ipm_fallback, ipm_worst, ipm_bad);
    ea_test_true(ipm_cmp > 0 && ipm_bad == 0 && ipm_worst <= 1e-6, what);
  } else {
    /* free paths are Ipopt's (plan_solve.c, ea__solve_ipm) */
    ea_test_true(ipm_cmp == 0, "sweep (free paths): no plan by the own interior point");
  }
  ea_test_true(outside_reported == n / 10, "sweep: every goal beyond the edge reported");
  if (path == EA_TASK_PATH_LINE) {
    snprintf(what, sizeof what,
             "replan sweep (each planned line's goal moved up to 5 mm / 0.01 rad): %d replans, "
             "%d by the active-set Newton, %d by the own interior point after it, %d by Ipopt, "
             "%d infeasible both warm and cold, %d failures; worst duration vs Ipopt's cold plan "
             "%.2g (1e-6); "
             "worst relative excess from the files %.3g (tolerance %.0e)",
             rp.n, rp.newton, rp.ipm, rp.ipopt, rp.both_infeasible, rp.failures, rp.worst_dur,
             rp.worst_excess, EA_SWEEP_LIMIT_TOL);
    ea_test_true(rp.failures == 0 && rp.n > 0 && rp.worst_excess <= EA_SWEEP_LIMIT_TOL, what);
  }
  return failures + rp.failures;
}

#ifndef EA_SWEEP_NO_MAIN
int main(int argc, char **argv) {
  const int n = argc > 1 ? atoi(argv[1]) : 200;
  ea_sweep_run(n > 0 ? n : 200, 0x9E3779B97F4A7C15ULL, 50, EA_TASK_PATH_FREE);
  ea_sweep_run(n > 0 ? n : 200, 0x9E3779B97F4A7C15ULL, 50, EA_TASK_PATH_LINE);
  return ea_test_summary("test_plan_sweep");
}
#endif
