/* The path transcription's statics splines (planner/nlp/plan_path.c) against independent
 * statics solves: on a prescribed path the planner tabulates (T, theta0, kappa0) along the path
 * coordinate as cubic Hermites from Chebyshev interpolants of statics samples whose error
 * estimate is below 1e-10, and the plans' statics at every knot come from them. Reference: a chain
 * of ea_statics_solve solves on a shooter of our own (the first from the T = 0 edge by
 * continuation, each next one warm-started from the one before), at 1001 points per segment, most
 * of them between the splines' samples. Stated: theta0 within 3e-10 rad, T within 3e-10 (1 + T) N,
 * kappa0 within 3e-10 / L (the splines' estimate is 1e-10; the reference's residual tolerance
 * 1e-12). Tasks: the paper line (payload 0), a planar polyline with two vias (payload factor 0.25),
 * and that polyline's planner after live updates (ea_planner_update_*): its limits (every
 * segment's samples kept), its goal moved 5 mm (the first two kept), its payload +10 % and its
 * start moved 5 mm (none kept). An update's splines must be those of the changed task: a kept
 * segment checked against the re-solve is what shows the key did not keep a stale one.
 * The statics' rates at a plan's knots from the splines' tabulated partials (the limits between
 * the knots use them) against shots with sensitivities, on the paper line and the polyline.
 * Warm starts of the path transcription (no Ipopt solve when the start is a KKT point; a
 * replan with other limits from the cold guess; a plan file of the task or of another one)
 * on the paper line. */
#include "ea_planner.h"
#include "path_entry_impl.h"
#include "ea_problems.h"
#include "ea_test.h"
#include "plan_impl.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* stated: 3e-10 (the splines' estimate 1e-10, their samples' residual 1e-12; measured
 * 5.4e-12 .. 9.9e-12, 1.0e-10 with the Hermite bisection of shot samples before); the plans'
 * statics rows must hold 1e-9 */
#define SPLINE_TOL 3e-10
#define POINTS 1000

/* The task's points in the arm plane (reach, height): start, vias, goal. */
static int task_points(const ea_task_t *t, double P[][2]) {
  int n = 0;
  P[n][0] = t->start.reach;
  P[n++][1] = t->start.height;
  for (int i = 0; i < t->n_via; ++i) {
    P[n][0] = t->via[i].reach;
    P[n++][1] = t->via[i].height;
  }
  P[n][0] = t->goal.reach;
  P[n++][1] = t->goal.height;
  return n;
}

/* Worst spline error of planner pl (planar task t, fixed base) over every segment, scaled
 * (theta0 [rad], T / (1 + T), kappa0 L); -1 when a reference solve or the splines fail. */
static double spline_error(const ea_planner_t *pl, const ea_task_t *t) {
  const ea_arm_t *arm = &t->arm;
  ea_shooter_t *sh = NULL;
  ea_error_t e;
  if (ea_shooter_alloc(arm, NULL, &sh, &e)) return -1.0;
  const ea_load_t load = {ea_arm_tip_mass(arm, t->payload_kg)};
  ea_shooter_set_load(sh, &load);
  double P[EA_TASK_MAX_VIA + 2][2];
  const int np = task_points(t, P);
  double worst = 0.0, g[EA_NP];
  int have = 0;
  ea_statics_settings_t set; /* the reference 100x tighter than the planner's statics */
  ea_statics_settings_default(&set);
  set.tol = 1e-12;
  if (pl->n_seg != np - 1 || !pl->guess_statics) worst = -1.0;
  for (int j = 0; j + 1 < np && worst >= 0.0; ++j)
    for (int i = 0; i <= POINTS; ++i) {
      const double f = (double)i / POINTS;
      const double x = P[j][0] + f * (P[j + 1][0] - P[j][0]);
      const double y = P[j][1] + f * (P[j + 1][1] - P[j][1]);
      const double L = hypot(x - arm->x_c, y - arm->y_c), a = atan2(y - arm->y_c, x - arm->x_c);
      ea_statics_problem_t pr = ea_statics_problem_cable(L, a);
      ea_statics_solution_t sol;
      double p[3];
      if (ea_statics_solve(sh, &pr, &set, have ? g : NULL, &sol, &e) ||
          !pl->guess_statics(pl, j, f, p)) {
        worst = -1.0;
        break;
      }
      memcpy(g, sol.p, sizeof g);
      have = 1;
      const double T = sol.p[EA_P_TENSION];
      worst = fmax(worst, fabs(p[0] - T) / (1.0 + fabs(T)));
      worst = fmax(worst, fabs(p[1] - sol.p[EA_P_THETA0]));
      worst = fmax(worst, fabs(p[2] - sol.p[EA_P_KAPPA0]) * arm->length);
    }
  ea_shooter_free(sh);
  return worst;
}

static void check(const ea_planner_t *pl, const ea_task_t *t, const char *name) {
  const double w = spline_error(pl, t);
  char msg[256];
  snprintf(msg, sizeof msg, "%s: statics splines vs independent solves, worst %.3g (<= %.0e)", name,
           w, SPLINE_TOL);
  ea_test_true(w >= 0.0 && w <= SPLINE_TOL, msg);
}

/* Update pl to task t (checked) and check its splines. */
static void update_check(ea_planner_t *pl, ea_task_t *t, const char *name) {
  ea_error_t e;
  if (ea_task_check(t, &e) || ea_planner_update(pl, t, &e))
    ea_test_true(0, e.msg);
  else
    check(pl, t, name);
}

/* Cold plan of task t (a planner of its own): its info. */
static int cold_plan(const ea_task_t *t, ea_plan_info_t *info) {
  ea_planner_t *pl = NULL;
  ea_error_t e;
  const int bad =
      ea_planner_alloc(t, &pl, &e) || ea_planner_solve(pl, EA_PLAN_COLD, NULL, info, &e);
  ea_planner_free(pl);
  return !bad;
}

/* Warm starts of the path transcription: the unchanged task's own solution is a KKT point (no
 * Ipopt iteration, the same plan); an update of an inactive limit leaves it one (no iteration,
 * the cold plan's duration); a tighter active limit makes the replan the cold plan of the new
 * task (its iterations, its duration to 1e-9: a fresh planner's cold plan differed by 1.5e-10,
 * Ipopt's tolerance). */
static void warm_starts(ea_planner_t *pl, const ea_task_t *t0) {
  ea_error_t e;
  ea_plan_info_t a, b, c, a2;
  char msg[256];
  if (ea_planner_solve(pl, EA_PLAN_COLD, NULL, &a, &e) ||
      ea_planner_solve(pl, EA_PLAN_WARM, NULL, &b, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  snprintf(msg, sizeof msg,
           "paper line: warm re-solve of its own plan, %d iterations (0), "
           "duration %.12g = %.12g",
           b.iterations, b.duration_s, a.duration_s);
  ea_test_true(b.iterations == 0 && b.duration_s == a.duration_s, msg);
  /* a plan file: of this task (its rows hold: fewer iterations than cold, the same plan),
   * of the goal 5 mm away (the cold guess: the cold plan's iterations and duration) */
  ea_traj_t tr;
  memset(&tr, 0, sizeof tr);
  ea_task_t mv = *t0;
  mv.goal = ea_task_point_planar(0.605, -0.2, 0.0);
  ea_planner_t *p2 = NULL;
  if (ea_planner_trajectory(pl, &tr, &e) || ea_planner_solve(pl, EA_PLAN_FROM_TRAJ, &tr, &b, &e) ||
      ea_task_check(&mv, &e) || !cold_plan(&mv, &c) || ea_planner_alloc(&mv, &p2, &e) ||
      ea_planner_solve(p2, EA_PLAN_FROM_TRAJ, &tr, &a2, &e)) {
    ea_test_true(0, e.msg);
    ea_planner_free(p2);
    ea_traj_free(&tr);
    return;
  }
  ea_planner_free(p2);
  ea_traj_free(&tr);
  snprintf(msg, sizeof msg,
           "paper line: from its own plan file %d iterations < cold %d, duration %.12g vs "
           "%.12g (1e-7)",
           b.iterations, a.iterations, b.duration_s, a.duration_s);
  ea_test_true(b.iterations < a.iterations && fabs(b.duration_s / a.duration_s - 1.0) < 1e-7, msg);
  snprintf(msg, sizeof msg,
           "paper line, goal 5 mm away: from the old plan file %d iterations = cold %d, "
           "duration %.12g vs %.12g (1e-9)",
           a2.iterations, c.iterations, a2.duration_s, c.duration_s);
  ea_test_true(a2.iterations == c.iterations && fabs(a2.duration_s / c.duration_s - 1.0) < 1e-9,
               msg);
  if (ea_planner_solve(pl, EA_PLAN_COLD, NULL, &a, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  ea_task_t t = *t0;
  t.limits.tension_min = 0.5 * a.min_tension_margin_N + t0->limits.tension_min;
  if (ea_task_check(&t, &e) || ea_planner_update(pl, &t, &e) ||
      ea_planner_solve(pl, EA_PLAN_WARM, NULL, &b, &e) || !cold_plan(&t, &c)) {
    ea_test_true(0, e.msg);
    return;
  }
  snprintf(msg, sizeof msg,
           "paper line: tension_min raised within its margin, replan %d "
           "iterations (0), duration %.12g vs cold %.12g",
           b.iterations, b.duration_s, c.duration_s);
  ea_test_true(b.iterations == 0 && fabs(b.duration_s / c.duration_s - 1.0) < 1e-6, msg);
  t.limits.cable_speed_max *= 0.9;
  if (ea_task_check(&t, &e) || ea_planner_update(pl, &t, &e) ||
      ea_planner_solve(pl, EA_PLAN_WARM, NULL, &b, &e) || !cold_plan(&t, &c)) {
    ea_test_true(0, e.msg);
    return;
  }
  snprintf(msg, sizeof msg,
           "paper line: cable speed limit -10 %%, replan %d iterations = cold "
           "%d, duration %.12g = %.12g (1e-9)",
           b.iterations, c.iterations, b.duration_s, c.duration_s);
  ea_test_true(b.iterations == c.iterations && fabs(b.duration_s / c.duration_s - 1.0) < 1e-9 &&
                   b.duration_s > a.duration_s,
               msg);
}

/* Replans solved by the active-set Newton (planner/nlp/plan_asn.c) instead of Ipopt: small
 * changes of the paper line keep the old plan's active set, so the Newton on it gives the new
 * task's KKT point (the whole KKT test passes before it is taken): no Ipopt iteration, the
 * duration and the tension margin of an independent cold plan (Ipopt, a fresh planner) of the
 * changed task to 1e-6 (warm and cold Ipopt plans differ by ~1e-7; measured 1.1e-7). A
 * payload change that leaves the old plan optimal (no tension or torque
 * limit active) needs no step at all. A larger change (start moved 5 mm: the active set
 * changes) falls back to Ipopt and still gives the cold duration. */
static void newton_replans(const ea_task_t *t0) {
  ea_error_t e;
  ea_planner_t *pl = NULL;
  ea_plan_info_t a, b, c;
  char msg[320];
  if (ea_planner_alloc(t0, &pl, &e) || ea_planner_solve(pl, EA_PLAN_COLD, NULL, &a, &e)) {
    ea_test_true(0, e.msg);
    ea_planner_free(pl);
    return;
  }
  const char *names[] = {"goal moved 1 mm", "goal moved 5 mm", "payload factor 0 -> 0.05",
                         "start moved 5 mm"};
  for (int i = 0; i < 4; ++i) {
    ea_task_t t = *t0;
    if (i == 0) t.goal = ea_task_point_planar(0.601, -0.2, 0.0);
    if (i == 1) t.goal = ea_task_point_planar(0.605, -0.2, 0.0);
    if (i == 2) t.payload_kg = ea_arm_payload_from_factor(&t.arm, 0.05);
    if (i == 3) t.start = ea_task_point_planar(0.305, -0.2, 0.0);
    if (ea_task_check(&t, &e) || ea_planner_update(pl, &t, &e) ||
        ea_planner_solve(pl, EA_PLAN_WARM, NULL, &b, &e) || !cold_plan(&t, &c)) {
      ea_test_true(0, e.msg);
      break;
    }
    const double dd = fabs(b.duration_s / c.duration_s - 1.0);
    const double dm = fabs(b.min_tension_margin_N - c.min_tension_margin_N) /
                      fmax(1.0, fabs(c.min_tension_margin_N));
    snprintf(msg, sizeof msg,
             "paper line, %s: replan %d Ipopt iterations and %d Newton steps (%s), duration "
             "%.12g vs cold %.12g (rel %.2g, 1e-6), tension margin rel %.2g (1e-6), violation "
             "%.2g",
             names[i], b.iterations, b.newton_steps, i < 3 ? "Newton" : "Ipopt", b.duration_s,
             c.duration_s, dd, dm, b.max_violation);
    const int path_ok =
        i < 3 ? b.iterations == 0 && (i == 2 || b.newton_steps > 0) : b.iterations > 0;
    ea_test_true(path_ok && dd < 1e-6 && dm < 1e-6 && b.status == EA_OK, msg);
    /* back to the first task (a Newton replan of its own) for the next change */
    if (ea_planner_update(pl, t0, &e) || ea_planner_solve(pl, EA_PLAN_WARM, NULL, &b, &e)) {
      ea_test_true(0, e.msg);
      break;
    }
  }
  ea_planner_free(pl);
}

/* The statics' rates at the knots of pl's plan (solved) as the limits between the knots take
 * them on a prescribed path (ea__pp_statics_rates: the splines' tabulated dp/dL_c, dp/dalpha
 * along the knots' (L_c, alpha) rates) against the implicit derivative from a shot with
 * sensitivities at each knot on a shooter of our own. Stated: 1e-3 of the largest rate of each
 * of T, theta0, kappa0 over the plan (the screen's band is 1e-3 of each limit; measured
 * 2.4e-6 on the paper line, 1.7e-6 on the polyline). */
static void rates_check(const ea_planner_t *pl, const ea_task_t *t, const char *name) {
  ea_shooter_t *sh = NULL;
  ea_error_t e;
  char msg[256];
  if (ea_shooter_alloc(&t->arm, NULL, &sh, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  const ea_load_t load = {ea_arm_tip_mass(&t->arm, t->payload_kg)};
  ea_shooter_set_load(sh, &load);
  const double *x = pl->x_sol;
  double worst[3] = {0}, scale[3] = {0};
  int bad = 0;
  for (int k = 0; k < pl->N; ++k) {
    const double p[EA_NP] = {x[EA__IQ(pl, k, 1)], x[EA__IP(pl, k, 0)], x[EA__IP(pl, k, 1)],
                             x[EA__IP(pl, k, 2)]};
    double xL[EA_NX], S[EA_NX * EA_NP], ref[3], got[3];
    if (ea_shoot(sh, p, xL, S) ||
        ea__plan_statics_slope(S, x[EA__IQ(pl, k, 0)], x[EA__IQ(pl, k, 1)], x[EA__IV(pl, k, 0)],
                               x[EA__IV(pl, k, 1)], ref) ||
        ea__pp_statics_rates(pl, x, k, got)) {
      bad = 1;
      break;
    }
    for (int c = 0; c < 3; ++c) {
      worst[c] = fmax(worst[c], fabs(got[c] - ref[c]));
      scale[c] = fmax(scale[c], fabs(ref[c]));
    }
  }
  ea_shooter_free(sh);
  const double r =
      bad ? INFINITY : fmax(worst[0] / scale[0], fmax(worst[1] / scale[1], worst[2] / scale[2]));
  snprintf(msg, sizeof msg,
           "%s: statics rates from the splines' partials vs shots, worst %.2g of the largest "
           "rate (<= 1e-3)",
           name, r);
  ea_test_true(r <= 1e-3, msg);
}

int main(void) {
  gsl_set_error_handler_off();
  ea_error_t e;
  ea_task_t line;
  ea_task_init(&line, NULL);
  line.start = ea_task_point_planar(0.3, -0.2, 0.0);
  line.goal = ea_task_point_planar(0.6, -0.2, 0.0);
  line.path = EA_TASK_PATH_LINE;
  line.knots = 100;
  ea_planner_t *pl = NULL;
  if (ea_task_check(&line, &e) || ea_planner_alloc(&line, &pl, &e)) {
    ea_test_true(0, e.msg);
  } else {
    check(pl, &line, "paper line, payload 0");
    warm_starts(pl, &line);
    rates_check(pl, &line, "paper line");
    newton_replans(&line);
  }
  ea_planner_free(pl);
  pl = NULL;

  ea_task_t poly;
  ea_task_init(&poly, NULL);
  poly.start = ea_task_point_planar(0.3, -0.2, 0.0);
  poly.via[0] = ea_task_point_planar(0.42, -0.12, 0.0);
  poly.via[1] = ea_task_point_planar(0.52, -0.28, 0.0);
  poly.n_via = 2;
  poly.goal = ea_task_point_planar(0.6, -0.2, 0.0);
  poly.path = EA_TASK_PATH_POLYLINE;
  poly.knots = 60;
  poly.payload_kg = ea_arm_payload_from_factor(&poly.arm, 0.25);
  if (ea_task_check(&poly, &e) || ea_planner_alloc(&poly, &pl, &e)) {
    ea_test_true(0, e.msg);
    return ea_test_summary("test_plan_path");
  }
  check(pl, &poly, "polyline, 2 vias, payload factor 0.25");
  ea_plan_info_t pinfo;
  if (ea_planner_solve(pl, EA_PLAN_COLD, NULL, &pinfo, &e))
    ea_test_true(0, e.msg);
  else
    rates_check(pl, &poly, "polyline");
  ea_task_t t = poly;
  t.limits.cable_speed_max *= 0.8;
  update_check(pl, &t, "polyline after a limits update");
  t.goal = ea_task_point_planar(0.605, -0.2, 0.0);
  update_check(pl, &t, "polyline after its goal moved 5 mm");
  t.payload_kg *= 1.1;
  update_check(pl, &t, "polyline after its payload +10 %");
  t.start = ea_task_point_planar(0.305, -0.2, 0.0);
  update_check(pl, &t, "polyline after its start moved 5 mm");
  /* back to the first task: the splines of a planner built for it */
  update_check(pl, &poly, "polyline updated back to its first task");
  ea_planner_free(pl);
  return ea_test_summary("test_plan_path");
}
