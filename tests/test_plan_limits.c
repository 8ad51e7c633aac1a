/* Every limit of the arm file and the task holds on the written trajectory,
 * between the knots too (docs/planner.md, "Limits between the knots"),
 * re-checked from the file at 1 kHz (ea_plan_check.h: cubic Hermite of the
 * value and rate columns, the statics solved at every sample):
 *  - every feasible example in problems/examples/;
 *  - the line (0.25, -0.45) -> (0.6, -0.3) at payload factor 0.25, where
 *    the shoulder acceleration limit (8 rad/s^2) binds: its duration vs a
 *    time-optimal path parameterisation written here (phase-plane
 *    reachability with theta0(beta) from cold statics solves along the
 *    line, independent of the planner);
 *  - the paper line at 2000 knots (was "infeasible ... Restoration_Failed"),
 *    and its duration vs the closed form D / v + v / a;
 *  - a fixed duration below the shortest admissible one: infeasible, with
 *    the shortfall against the closed form. */
#include "ea_plan_check.h"
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *src_dir(void) {
  const char *s = getenv("EA_SOURCE_DIR");
  return s ? s : ".";
}

/* Plan t, write the trajectory file, read it back, re-check it at 1 kHz.
 * Returns the plan status; *dur the duration. */
static ea_status_t plan_and_check(ea_task_t *t, const char *name, double *dur, ea_chk_t *c) {
  ea_error_t e = {0};
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  ea_traj_t tr = {0}, back = {0};
  char path[] = "/tmp/ea_test_plan_limits_XXXXXX", what[800];
  *dur = NAN;
  ea_status_t st = ea_planner_alloc(t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  snprintf(what, sizeof what, "%s: planned (%s)", name, e.msg);
  ea_test_true(st == EA_OK, what);
  if (!st) st = ea_planner_trajectory(pl, &tr, &e);
  const int fd = st ? -1 : mkstemp(path);
  if (fd >= 0) {
    close(fd);
    st = ea_traj_write(&tr, path, &e);
    if (!st) st = ea_traj_read(&back, path, &e);
    remove(path);
  }
  if (!st) {
    *dur = info.duration_s;
    const double w = ea_chk_traj(t, &back, 1000.0, c);
    ea_chk_print(name, c);
    /* measured: the worst usage of an active limit is 1 - 1e-7 (Ipopt's
     * interior point); no excess is accepted */
    snprintf(what, sizeof what,
             "%s: every limit held at 1 kHz and at the knots from the written file (worst "
             "relative excess %.3g, tolerance 0)",
             name, w);
    ea_test_true(w <= 0.0, what);
    if (t->limits.min_first_frequency_hz > 0.0) {
      /* the frequency limit is defined on the planner's FE model of f1
       * (docs/planner.md): the model along the file's cubics at 1 kHz */
      double fmin = INFINITY;
      const double t0 = EA_TRAJ_AT(&back, 0, EA_TRAJ_t);
      for (int k = 0, j = 0; k + 1 < back.n; ++k) {
        const double ta = EA_TRAJ_AT(&back, k, EA_TRAJ_t), tb = EA_TRAJ_AT(&back, k + 1, EA_TRAJ_t);
        for (; t0 + j / 1000.0 <= tb; ++j) {
          double q[2], v, a, f;
          const int qc[2] = {EA_TRAJ_cable_length, EA_TRAJ_cable_angle};
          const int vc[2] = {EA_TRAJ_cable_length_rate, EA_TRAJ_cable_angle_rate};
          for (int i = 0; i < 2; ++i)
            ea_chk_cubic(tb - ta, (t0 + j / 1000.0 - ta) / (tb - ta), EA_TRAJ_AT(&back, k, qc[i]),
                         EA_TRAJ_AT(&back, k, vc[i]), EA_TRAJ_AT(&back, k + 1, qc[i]),
                         EA_TRAJ_AT(&back, k + 1, vc[i]), &q[i], &v, &a);
          if (!ea_planner_first_frequency(pl, q[0], q[1], &f, NULL, NULL))
            fmin = fmin < f ? fmin : f;
        }
      }
      snprintf(what, sizeof what, "%s: f1 (FE model) at 1 kHz >= %g Hz: min %.6g Hz", name,
               t->limits.min_first_frequency_hz, fmin);
      ea_test_true(fmin >= t->limits.min_first_frequency_hz, what);
    }
  }
  ea_traj_free(&tr);
  ea_traj_free(&back);
  ea_planner_free(pl);
  return st;
}

static void test_examples(void) {
  static const char *const ex[] = {"paper-line", "paper-line-smooth", "pick-place-3d",
                                   "polyline-effort"};
  for (size_t i = 0; i < sizeof ex / sizeof *ex; ++i) {
    char path[1024];
    snprintf(path, sizeof path, "%s/problems/examples/%s.yaml", src_dir(), ex[i]);
    ea_task_t t;
    ea_error_t e = {0};
    const ea_status_t st = ea_task_load(path, NULL, &t, &e);
    ea_test_true(st == EA_OK, path);
    if (st) continue;
    double d;
    ea_chk_t c;
    plan_and_check(&t, ex[i], &d, &c);
  }
}

/* ---------------------------------------------------------------------- */
/* Time-optimal path parameterisation with tabulated path derivatives:     */
/* q_c(beta) on beta = i / M, |q_c' bd| <= v_c, |q_c' bdd + q_c'' bd^2| <= */
/* a_c. Backward pass: largest x = bd^2 from which the rest can stop at     */
/* beta = 1; forward pass at the largest admissible bdd (as in test_plan). */
/* ---------------------------------------------------------------------- */

#define NC 3
static int u_range(const double q1[NC], const double q2[NC], const double a[NC], double x,
                   double *lo, double *hi) {
  *lo = -INFINITY;
  *hi = INFINITY;
  for (int c = 0; c < NC; ++c) {
    if (!isfinite(a[c])) continue;
    if (fabs(q1[c]) < 1e-300) {
      if (fabs(q2[c] * x) > a[c]) return 0;
      continue;
    }
    double l = (-a[c] - q2[c] * x) / q1[c], h = (a[c] - q2[c] * x) / q1[c];
    if (q1[c] < 0) {
      const double tmp = l;
      l = h;
      h = tmp;
    }
    *lo = fmax(*lo, l);
    *hi = fmin(*hi, h);
  }
  return *lo <= *hi;
}

static double topp_tab(int M, double (*d1)[NC], double (*d2)[NC], const double v[NC],
                       const double a[NC]) {
  const double D = 1.0 / M;
  double *K = malloc((size_t)(M + 1) * sizeof *K), *X = malloc((size_t)(M + 1) * sizeof *X);
  K[M] = 0.0;
  for (int i = M - 1; i >= 0; --i) {
    double mvc = INFINITY;
    for (int c = 0; c < NC; ++c)
      if (isfinite(v[c]) && fabs(d1[i][c]) > 0) mvc = fmin(mvc, pow(v[c] / d1[i][c], 2));
    double lo = 0.0, hi = fmin(mvc, 1e6);
    for (int it = 0; it < 100; ++it) {
      const double xm = 0.5 * (lo + hi);
      double ul, uh;
      int ok = u_range(d1[i], d2[i], a, xm, &ul, &uh);
      if (ok) {
        ul = fmax(ul, -xm / (2 * D));
        uh = fmin(uh, (K[i + 1] - xm) / (2 * D));
        ok = ul <= uh;
      }
      if (ok)
        lo = xm;
      else
        hi = xm;
    }
    K[i] = lo;
  }
  X[0] = 0.0;
  double T = 0.0;
  for (int i = 0; i < M; ++i) {
    double ul, uh;
    u_range(d1[i], d2[i], a, X[i], &ul, &uh);
    X[i + 1] = fmax(0.0, fmin(K[i + 1], X[i] + 2 * D * uh));
    T += 2 * D / (sqrt(X[i]) + sqrt(X[i + 1]));
  }
  free(K);
  free(X);
  return T;
}

/* Minimum time along the line A -> B (planar tips) for the task's arm,
 * payload and limits: L_c and alpha in closed form (eqs. 19-20), theta0 by
 * statics solves on M + 1 points (edge continuation at the first, warm
 * after), its derivatives by central differences. */
static double line_topp(const ea_task_t *t, const double A[2], const double B[2], int M) {
  const ea_arm_t *arm = &t->arm;
  ea_shooter_t *sh = NULL;
  if (ea_shooter_alloc(arm, NULL, &sh, NULL)) return NAN;
  const ea_load_t load = {ea_arm_tip_mass(arm, t->payload_kg)};
  ea_shooter_set_load(sh, &load);
  double(*q)[NC] = calloc((size_t)M + 1, sizeof *q);
  double(*d1)[NC] = calloc((size_t)M + 1, sizeof *d1);
  double(*d2)[NC] = calloc((size_t)M + 1, sizeof *d2);
  double p[EA_NP], T = NAN;
  int ok = 1;
  for (int i = 0; i <= M && ok; ++i) {
    const double b = (double)i / M;
    const double X = A[0] + b * (B[0] - A[0]) - arm->x_c, Y = A[1] + b * (B[1] - A[1]) - arm->y_c;
    q[i][0] = hypot(X, Y);
    q[i][1] = atan2(Y, X);
    ea_statics_problem_t prob = ea_statics_problem_cable(q[i][0], q[i][1]);
    ea_statics_solution_t sol;
    p[0] = q[i][1];
    ok = ea_statics_solve(sh, &prob, NULL, i ? p : NULL, &sol, NULL) == EA_OK;
    memcpy(p, sol.p, sizeof p);
    q[i][2] = sol.p[EA_P_THETA0];
  }
  if (ok) {
    for (int i = 0; i <= M; ++i) {
      const int lo = i > 0 ? i - 1 : 0, hi = i < M ? i + 1 : M, m = i == 0 ? 1 : i == M ? M - 1 : i;
      for (int c = 0; c < NC; ++c) {
        d1[i][c] = (q[hi][c] - q[lo][c]) * M / (hi - lo);
        d2[i][c] = (q[m + 1][c] - 2 * q[m][c] + q[m - 1][c]) * M * M;
      }
    }
    const ea_task_limits_t *l = &t->limits;
    const double v[NC] = {l->cable_speed_max, l->cable_angle_speed_max, l->shoulder_speed_max};
    const double a[NC] = {l->cable_accel_max, l->cable_angle_accel_max,
                          arm->act.shoulder_accel_max};
    T = topp_tab(M, d1, d2, v, a);
  }
  free(q);
  free(d1);
  free(d2);
  ea_shooter_free(sh);
  return T;
}

static void test_shoulder_line(void) {
  ea_task_t t;
  ea_task_init(&t, NULL);
  const double A[2] = {0.25, -0.45}, B[2] = {0.6, -0.3};
  t.payload_factor = 0.25;
  t.payload_kg = ea_arm_payload_from_factor(&t.arm, 0.25);
  t.start = ea_task_point_planar(A[0], A[1], 0.0);
  t.goal = ea_task_point_planar(B[0], B[1], 0.0);
  t.path = EA_TASK_PATH_LINE;
  t.knots = 100;
  ea_error_t e = {0};
  ea_status_t st = ea_task_check(&t, &e);
  ea_test_true(st == EA_OK, "line (0.25, -0.45) -> (0.6, -0.3), payload factor 0.25: checks");
  if (st) return;
  double d;
  ea_chk_t c;
  st = plan_and_check(&t, "shoulder-limited line, 100 knots", &d, &c);
  if (st) return;
  /* the shoulder limits are the binding ones here */
  ea_test_true(c.usage[EA_CHK_TH_A] > 0.999999, "shoulder acceleration limit reached (active)");
  const double T2k = line_topp(&t, A, B, 2000), T4k = line_topp(&t, A, B, 4000);
  /* measured: 2000 and 4000 cells agree to 2.3e-5 (first order in the cell) */
  ea_test_rel(T2k, T4k, 1e-4, "TOPP reference (theta0 from statics) converged in its grid");
  printf("shoulder-limited line: plan %.6f s, time-optimal reference %.6f s (%+.3g)\n", d, T4k,
         d / T4k - 1);
  /* measured +2.05e-4 at 100 knots (the C2 plan ramps each acceleration
   * switch over one interval: O(h)); tolerance 2x */
  ea_test_rel(d, T4k, 4e-4, "shoulder-limited line: duration vs time-optimal reference");
  ea_test_true(d >= T4k * (1 - 5e-5),
               "shoulder-limited line: not below the reference (grid 2.3e-5)");
}

/* A free-path 3-D task of the sweep (tests/test_plan_sweep.c, task 177)
 * whose shoulder torque limit is active: between two knots the quasi-static
 * torque at the interpolated (L_c, alpha) exceeded the limit by 2.5e-4
 * (relative) before the planner checked it there (plan_between.c). */
static void test_torque_between_knots(void) {
  ea_task_t t;
  ea_task_init(&t, NULL);
  t.knots = 50;
  t.payload_factor = 0.40616907473044639;
  t.payload_kg = ea_arm_payload_from_factor(&t.arm, t.payload_factor);
  t.start = ea_task_point_actuators(0.45425462421110224, 0.16635846292788914, 0.27343758315094857);
  t.goal = ea_task_point_actuators(0.62848611368454277, -1.0754634883647793, 0.78531939170818177);
  ea_error_t e = {0};
  ea_status_t st = ea_task_check(&t, &e);
  ea_test_true(st == EA_OK, e.msg);
  if (st) return;
  double d;
  ea_chk_t c;
  if (plan_and_check(&t, "free 3-D task, torque limit active", &d, &c)) return;
  ea_test_true(c.usage[EA_CHK_TORQUE] > 0.999, "the shoulder torque limit is reached");
}

static void test_many_knots(void) {
  char path[1024];
  snprintf(path, sizeof path, "%s/problems/examples/paper-line.yaml", src_dir());
  ea_task_t t;
  ea_error_t e = {0};
  if (ea_task_load(path, NULL, &t, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  const double D = hypot(0.6 - 0.098, -0.2 + 0.006) - hypot(0.3 - 0.098, -0.2 + 0.006);
  const double v = t.limits.cable_speed_max, a = t.limits.cable_accel_max;
  /* 2000 and 2500 knots (once "infeasible ... Restoration_Failed"; 3000 plans too, in 14 s,
   * not run here): measured 3.8e-6 / 4.7e-6 above the closed form at 2000 / 2500 knots (no
   * longer the O(h) gap of the one-interval ramps, which would fall) */
  const int knots[2] = {2000, 2500};
  for (int k = 0; k < 2; ++k) {
    t.knots = knots[k];
    double d;
    ea_chk_t c;
    char what[128];
    snprintf(what, sizeof what, "paper line, %d knots", knots[k]);
    if (plan_and_check(&t, what, &d, &c)) continue;
    snprintf(what, sizeof what, "paper line, %d knots: duration vs closed form D/v + v/a",
             knots[k]);
    ea_test_rel(d, D / v + v / a, 1e-5, what);
  }
}

static void test_shortfall(void) {
  char path[1024], what[800];
  snprintf(path, sizeof path, "%s/problems/examples/paper-line.yaml", src_dir());
  ea_task_t t;
  ea_error_t e = {0};
  if (ea_task_load(path, NULL, &t, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  t.objective = EA_TASK_MIN_EFFORT;
  t.duration_s = 1.2;
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  ea_status_t st = ea_task_check(&t, &e);
  if (!st) st = ea_planner_alloc(&t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  snprintf(what, sizeof what, "min_effort in 1.2 s: infeasible, says by how much: %s", e.msg);
  const char *p = strstr(e.msg, "shortest admissible duration ");
  ea_test_true(st == EA_ERR_INFEASIBLE && p, what);
  if (p) {
    const double tmin = strtod(p + strlen("shortest admissible duration "), NULL);
    const double D = hypot(0.6 - 0.098, -0.2 + 0.006) - hypot(0.3 - 0.098, -0.2 + 0.006);
    const double v = t.limits.cable_speed_max, a = t.limits.cable_accel_max;
    /* measured 1.3e-4 above the closed form (100 knots; message rounds to 6 digits) */
    ea_test_rel(tmin, D / v + v / a, 2e-4, "reported shortest duration vs closed form D/v + v/a");
  }
  ea_planner_free(pl);
  t.duration_s = 1.3;
  double d;
  ea_chk_t c;
  plan_and_check(&t, "min_effort in 1.3 s (above the shortest)", &d, &c);
}

int main(void) {
  test_examples();
  test_shoulder_line();
  test_torque_between_knots();
  test_many_knots();
  test_shortfall();
  return ea_test_summary("test_plan_limits");
}
