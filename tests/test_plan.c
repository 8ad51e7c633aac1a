/* Planner tests (docs/planner.md). References from outside the planner:
 *  - every knot re-solved independently: ea_statics_solve from a cold start
 *    (edge continuation) and ea_shoot_reference (rkf45 at 1e-13);
 *  - limits re-derived from the trajectory file's columns (cubic Hermite);
 *  - the paper line's minimum time in closed form (only L_c limited);
 *  - a time-optimal path parameterisation by the classical backward /
 *    forward phase-plane (reachability) integration, written here;
 *  - Ipopt's derivative checker on the constraint Jacobian (and Hessian). */
#define EA_SWEEP_NO_MAIN
#include "test_plan_sweep.c"

static const char *src_dir(void) {
  const char *s = getenv("EA_SOURCE_DIR");
  return s ? s : ".";
}

/* ---------------------------------------------------------------------- */
/* Checks of a plan against the task's limits, from the trajectory file.    */
/* ---------------------------------------------------------------------- */

static void check_limits(const ea_task_t *t, const ea_traj_t *tr, const char *name) {
  const ea_task_limits_t *l = &t->limits;
  const double vmax[3] = {l->cable_speed_max, l->cable_angle_speed_max, l->base_speed_max};
  const double amax[3] = {l->cable_accel_max, l->cable_angle_accel_max, l->base_accel_max};
  const int qc[3] = {EA_TRAJ_cable_length, EA_TRAJ_cable_angle, EA_TRAJ_base_angle};
  const int vc[3] = {EA_TRAJ_cable_length_rate, EA_TRAJ_cable_angle_rate, EA_TRAJ_base_angle_rate};
  double worst[8] = {0}; /* relative excess: T_min, T_max, torque, L_c, speed, acc, mid, shoulder */
  for (int k = 0; k < tr->n; ++k) {
    const double T = EA_TRAJ_AT(tr, k, EA_TRAJ_tension);
    worst[0] = fmax(worst[0], (l->tension_min - T) / l->tension_min);
    worst[1] = fmax(worst[1], (T - l->tension_max) / l->tension_max);
    worst[2] =
        fmax(worst[2], (fabs(EA_TRAJ_AT(tr, k, EA_TRAJ_shoulder_torque)) - l->shoulder_torque_max) /
                           l->shoulder_torque_max);
    const double Lc = EA_TRAJ_AT(tr, k, EA_TRAJ_cable_length);
    worst[3] = fmax(worst[3], fmax(l->cable_length_min - Lc, Lc - l->cable_length_max));
    for (int c = 0; c < 3; ++c)
      if (isfinite(vmax[c]))
        worst[4] = fmax(worst[4], (fabs(EA_TRAJ_AT(tr, k, vc[c])) - vmax[c]) / vmax[c]);
    if (k + 1 == tr->n) break;
    const double h = EA_TRAJ_AT(tr, k + 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, k, EA_TRAJ_t);
    for (int c = 0; c < 3; ++c) {
      const double q0 = EA_TRAJ_AT(tr, k, qc[c]), q1 = EA_TRAJ_AT(tr, k + 1, qc[c]);
      const double v0 = EA_TRAJ_AT(tr, k, vc[c]), v1 = EA_TRAJ_AT(tr, k + 1, vc[c]);
      /* cubic Hermite: q(s) on [0, h]; acceleration at both ends, speed in the middle */
      const double a0 = (6 * (q1 - q0) / h - 4 * v0 - 2 * v1) / h;
      const double a1 = (-6 * (q1 - q0) / h + 2 * v0 + 4 * v1) / h;
      const double vm = 1.5 * (q1 - q0) / h - 0.25 * (v0 + v1);
      if (isfinite(amax[c]))
        worst[5] = fmax(worst[5], (fmax(fabs(a0), fabs(a1)) - amax[c]) / amax[c]);
      if (isfinite(vmax[c])) worst[6] = fmax(worst[6], (fabs(vm) - vmax[c]) / vmax[c]);
    }
    if (isfinite(l->shoulder_speed_max)) {
      const double w =
          (EA_TRAJ_AT(tr, k + 1, EA_TRAJ_theta0) - EA_TRAJ_AT(tr, k, EA_TRAJ_theta0)) / h;
      worst[7] = fmax(worst[7], (fabs(w) - l->shoulder_speed_max) / l->shoulder_speed_max);
    }
  }
  static const char *const nm[8] = {"T >= T_min",          "T <= T_max",
                                    "|EI kappa0| <= max",  "L_c in range [m]",
                                    "knot speeds",         "Hermite accelerations",
                                    "mid-interval speeds", "shoulder speed (theta0 differences)"};
  for (int i = 0; i < 8; ++i) {
    char what[200];
    snprintf(what, sizeof what, "%s: %s (worst relative excess %.3g)", name, nm[i], worst[i]);
    ea_test_true(worst[i] <= (i == 3 ? 1e-12 : 1e-6), what);
  }
}

/* Every knot against an independent cold statics solve and a reference
 * re-integration. */
static void check_statics(const ea_task_t *t, const ea_traj_t *tr, const char *name) {
  ea_shooter_t *sh = NULL;
  ea_error_t e;
  if (ea_shooter_alloc(&t->arm, NULL, &sh, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  ea_load_t load = {ea_arm_tip_mass(&t->arm, t->payload_kg)};
  ea_shooter_set_load(sh, &load);
  double dp = 0.0, dref = 0.0, dtip = 0.0;
  int fails = 0;
  for (int k = 0; k < tr->n; ++k) {
    const double Lc = EA_TRAJ_AT(tr, k, EA_TRAJ_cable_length);
    const double al = EA_TRAJ_AT(tr, k, EA_TRAJ_cable_angle);
    const double p[EA_NP] = {al, EA_TRAJ_AT(tr, k, EA_TRAJ_tension),
                             EA_TRAJ_AT(tr, k, EA_TRAJ_theta0), EA_TRAJ_AT(tr, k, EA_TRAJ_kappa0)};
    ea_statics_problem_t prob = ea_statics_problem_cable(Lc, al);
    ea_statics_solution_t sol;
    if (ea_statics_solve(sh, &prob, NULL, NULL, &sol, &e) != EA_OK) {
      ++fails;
      continue;
    }
    dp = fmax(dp, fabs(sol.p[EA_P_TENSION] - p[1]) / fmax(1.0, fabs(p[1])));
    dp = fmax(dp, fabs(sol.p[EA_P_THETA0] - p[2]));
    dp = fmax(dp, fabs(sol.p[EA_P_KAPPA0] - p[3]));
    double xL[EA_NX];
    if (ea_shoot_reference(&t->arm, &load, p, xL) != EA_OK) {
      ++fails;
      continue;
    }
    dref = fmax(dref, fabs(xL[EA_X_KAPPA]));
    dref = fmax(dref, fabs(xL[EA_X_X] - t->arm.x_c - Lc * cos(al)));
    dref = fmax(dref, fabs(xL[EA_X_Y] - t->arm.y_c - Lc * sin(al)));
    const double b = EA_TRAJ_AT(tr, k, EA_TRAJ_base_angle);
    dtip = fmax(dtip, fabs(EA_TRAJ_AT(tr, k, EA_TRAJ_tip_x) - xL[EA_X_X] * cos(b)));
    dtip = fmax(dtip, fabs(EA_TRAJ_AT(tr, k, EA_TRAJ_tip_y) - xL[EA_X_X] * sin(b)));
    dtip = fmax(dtip, fabs(EA_TRAJ_AT(tr, k, EA_TRAJ_tip_z) - xL[EA_X_Y]));
  }
  char what[200];
  snprintf(what, sizeof what, "%s: every knot re-solved cold (%d failures)", name, fails);
  ea_test_true(fails == 0, what);
  snprintf(what, sizeof what, "%s: plan vs cold re-solve (T rel, theta0, kappa0)", name);
  ea_test_abs(dp, 0.0, 1e-9, what);
  snprintf(what, sizeof what, "%s: statics residual by reference re-integration [m, 1/m]", name);
  ea_test_abs(dref, 0.0, 1e-9, what);
  snprintf(what, sizeof what, "%s: tip columns vs reference tip [m]", name);
  ea_test_abs(dtip, 0.0, 1e-9, what);
  ea_shooter_free(sh);
}

/* ---------------------------------------------------------------------- */
/* Time-optimal path parameterisation (reference): path q(beta), beta in    */
/* [0, 1], limits |q_c'| bd <= v_c, |q_c' bdd + q_c'' bd^2| <= a_c. State    */
/* x = bd^2, control u = bdd, x_{i+1} = x_i + 2 u_i D. Backward pass: the    */
/* largest x_i from which the rest stays admissible and stops at beta = 1;  */
/* forward pass: the largest admissible u within those sets.                */
/* ---------------------------------------------------------------------- */

typedef void (*path_fn)(double beta, double q1[2], double q2[2]);

static void paper_line_path(double beta, double q1[2], double q2[2]) {
  const double xc = 0.098, yc = -0.006;
  const double X = 0.3 * beta + 0.3 - xc, Y = -0.2 - yc, L2 = X * X + Y * Y, L = sqrt(L2);
  q1[0] = 0.3 * X / L; /* dL_c/dbeta (eq. 19) */
  q2[0] = 0.09 * Y * Y / (L2 * L);
  q1[1] = -0.3 * Y / L2; /* dalpha/dbeta (eq. 20) */
  q2[1] = 0.18 * X * Y / (L2 * L2);
}

/* u interval at x; returns 0 if empty. */
static int topp_u(const double q1[2], const double q2[2], const double a[2], double x, double *lo,
                  double *hi) {
  *lo = -INFINITY;
  *hi = INFINITY;
  for (int c = 0; c < 2; ++c) {
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

static double topp_time(path_fn f, const double v[2], const double a[2], int M) {
  const double D = 1.0 / M;
  double *K = malloc((size_t)(M + 1) * sizeof *K), *X = malloc((size_t)(M + 1) * sizeof *X);
  K[M] = 0.0;
  for (int i = M - 1; i >= 0; --i) {
    double q1[2], q2[2];
    f(i * D, q1, q2);
    double mvc = INFINITY;
    for (int c = 0; c < 2; ++c)
      if (fabs(q1[c]) > 0) mvc = fmin(mvc, (v[c] / q1[c]) * (v[c] / q1[c]));
    double lo = 0.0, hi = mvc;
    for (int it = 0; it < 100; ++it) { /* largest feasible x in [0, mvc] */
      const double xm = 0.5 * (lo + hi);
      double ul, uh;
      int ok = topp_u(q1, q2, a, xm, &ul, &uh);
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
    double q1[2], q2[2], ul, uh;
    f(i * D, q1, q2);
    topp_u(q1, q2, a, X[i], &ul, &uh);
    X[i + 1] = fmax(0.0, fmin(K[i + 1], X[i] + 2 * D * uh));
    T += 2 * D / (sqrt(X[i]) + sqrt(X[i + 1]));
  }
  free(K);
  free(X);
  return T;
}

/* ---------------------------------------------------------------------- */

static ea_status_t plan(ea_task_t *t, ea_planner_t **pl, ea_traj_t *tr, ea_plan_info_t *info,
                        ea_error_t *e) {
  ea_status_t st = ea_planner_alloc(t, pl, e);
  if (!st) st = ea_planner_solve(*pl, EA_PLAN_COLD, NULL, info, e);
  if (!st) st = ea_planner_trajectory(*pl, tr, e);
  return st;
}

static void test_paper_line(void) {
  char path[1024], what[600];
  snprintf(path, sizeof path, "%s/problems/examples/paper-line.yaml", src_dir());
  ea_task_t t;
  ea_error_t e = {0};
  ea_status_t st = ea_task_load(path, NULL, &t, &e);
  ea_test_true(st == EA_OK, "paper-line loads");
  if (st) return;
  ea_planner_t *pl = NULL;
  ea_traj_t tr;
  memset(&tr, 0, sizeof tr);
  ea_plan_info_t info;
  st = plan(&t, &pl, &tr, &info, &e);
  snprintf(what, sizeof what, "paper line, min time, 100 knots: %s (%s)", ea_status_name(st),
           e.msg);
  ea_test_true(st == EA_OK && tr.n == 100, what);
  if (!st) {
    check_statics(&t, &tr, "paper line");
    check_limits(&t, &tr, "paper line");
    /* Tip on the line y = -0.2 between x = 0.3 and 0.6 (eq. 18). */
    double dl = 0.0;
    for (int k = 0; k < tr.n; ++k) {
      dl = fmax(dl, fabs(EA_TRAJ_AT(&tr, k, EA_TRAJ_tip_z) + 0.2));
      const double x = EA_TRAJ_AT(&tr, k, EA_TRAJ_tip_x);
      dl = fmax(dl, fmax(0.3 - x, x - 0.6));
    }
    ea_test_abs(dl, 0.0, 1e-9, "paper line: tip on the line of eq. 18 [m]");
    /* Only L_c is limited (alpha free, shoulder limits inactive): minimum
     * time of a rest-to-rest move of distance D is D / v + v / a. */
    const double D = hypot(0.6 - 0.098, -0.2 + 0.006) - hypot(0.3 - 0.098, -0.2 + 0.006);
    /* the planner plans 1 + resample_margin inside the limits (docs/planner.md) */
    const double rm = 1.0 + t.limits.resample_margin;
    const double v = t.limits.cable_speed_max / rm, a = t.limits.cable_accel_max / rm;
    /* continuous acceleration (default) ramps each switch over one interval:
     * O(h) above the bang-bang closed form (1.3e-4 at 100 knots) */
    ea_test_rel(info.duration_s, D / v + v / a, 5e-4,
                "paper line: duration vs closed form (limits / (1 + resample_margin))");
    printf("paper line: %d iterations, %.1f ms (statics %.1f, Ipopt %.1f)\n", info.iterations,
           1e3 * info.time_total_s, 1e3 * info.time_statics_s, 1e3 * info.time_ipopt_s);
    /* Warm start from the planner's own solution and from the file. */
    ea_plan_info_t w;
    st = ea_planner_solve(pl, EA_PLAN_WARM, NULL, &w, &e);
    ea_test_true(st == EA_OK && w.iterations <= 5, "warm start: converged in <= 5 iterations");
    ea_test_rel(w.duration_s, info.duration_s, 1e-6, "warm start: same duration");
    st = ea_planner_solve(pl, EA_PLAN_FROM_TRAJ, &tr, &w, &e);
    ea_test_true(st == EA_OK, "warm start from the trajectory file converges");
    ea_test_rel(w.duration_s, info.duration_s, 1e-5, "warm start from file: same duration");
    /* Round trip through the file format. */
    char out[] = "/tmp/ea_test_plan_XXXXXX";
    const int fd = mkstemp(out);
    if (fd >= 0) {
      close(fd);
      ea_traj_t back;
      memset(&back, 0, sizeof back);
      st = ea_traj_write(&tr, out, &e);
      if (!st) st = ea_traj_read(&back, out, &e);
      ea_test_true(st == EA_OK && back.n == tr.n, "trajectory file written and read back");
      ea_traj_free(&back);
      remove(out);
    }
  }
  ea_traj_free(&tr);
  ea_planner_free(pl);
}

static void test_topp(void) {
  ea_task_t t;
  ea_task_init(&t, NULL);
  t.start = ea_task_point_planar(0.3, -0.2, 0.0);
  t.goal = ea_task_point_planar(0.6, -0.2, 0.0);
  t.path = EA_TASK_PATH_LINE;
  t.knots = 100;
  t.limits.cable_speed_max = 0.25;
  t.limits.cable_accel_max = 1.0;
  t.limits.cable_angle_speed_max = 0.5;
  t.limits.cable_angle_accel_max = 2.0;
  /* Only actuator speed and acceleration limits may bind: the shoulder,
   * tension and torque limits must come out inactive (checked below). */
  t.solver.regularization = 1e-6;
  ea_error_t e = {0};
  ea_status_t st = ea_task_check(&t, &e);
  ea_test_true(st == EA_OK, "TOPP task checks");
  ea_planner_t *pl = NULL;
  ea_traj_t tr;
  memset(&tr, 0, sizeof tr);
  ea_plan_info_t info;
  if (!st) st = plan(&t, &pl, &tr, &info, &e);
  ea_test_true(st == EA_OK, "TOPP comparison: plan converged");
  if (!st) {
    const double rm = 1.0 + t.limits.resample_margin;
    const double v[2] = {0.25 / rm, 0.5 / rm}, a[2] = {1.0 / rm, 2.0 / rm};
    const double T20k = topp_time(paper_line_path, v, a, 20000);
    const double T40k = topp_time(paper_line_path, v, a, 40000);
    ea_test_rel(T20k, T40k, 1e-3, "TOPP reference converged in its grid");
    ea_test_rel(info.duration_s, T40k, 1e-2, "min time vs time-optimal path parameterisation");
    check_limits(&t, &tr, "TOPP task");
    int alpha_active = 0;
    for (int i = 0; i < info.n_active; ++i)
      if (strstr(info.active[i], "cable angle")) alpha_active = 1;
    for (int i = 0; i < info.n_active; ++i)
      printf("active: %s (%d)\n", info.active[i], info.active_knots[i]);
    ea_test_true(alpha_active, "TOPP task: a cable-angle limit is active");
    int other = 0;
    for (int i = 0; i < info.n_active; ++i)
      if (!strstr(info.active[i], "cable")) other = 1;
    ea_test_true(!other, "TOPP task: only cable length / angle limits active");
  }
  ea_traj_free(&tr);
  ea_planner_free(pl);
}

static void test_derivatives(void) {
  /* 3-D line with base motion, min time (t_f variable): every row kind. */
  ea_task_t t;
  ea_task_init(&t, NULL);
  t.start = ea_task_point_3d(0.40, 0.05, -0.20);
  t.goal = ea_task_point_3d(0.30, 0.35, -0.10);
  t.path = EA_TASK_PATH_LINE;
  t.knots = 8;
  t.limits.cable_angle_speed_max = 1.0;
  t.limits.cable_angle_accel_max = 4.0;
  t.solver.max_iter = 1;
  t.solver.hessian_exact = 1; /* with the statics curvature, for the second-order check */
  for (int order = 1; order <= 2; ++order) {
    t.solver.derivative_test = order;
    ea_error_t e = {0};
    ea_planner_t *pl = NULL;
    ea_plan_info_t info;
    ea_status_t st = ea_task_check(&t, &e);
    if (!st) st = ea_planner_alloc(&t, &pl, &e);
    if (!st) ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
    char what[200];
    snprintf(what, sizeof what, "derivative checker (%s, 3-D line, min time): %d errors",
             order == 1 ? "first order" : "second order", pl ? info.deriv_errors : -1);
    ea_test_true(pl && info.deriv_errors == 0, what);
    ea_planner_free(pl);
  }
  /* Polyline with vias, min jerk (fixed duration). */
  ea_task_init(&t, NULL);
  t.start = ea_task_point_planar(0.35, -0.25, 0.0);
  t.via[0] = ea_task_point_actuators(0.45, -0.2, 0.0);
  t.n_via = 1;
  t.goal = ea_task_point_planar(0.55, -0.3, 0.0);
  t.path = EA_TASK_PATH_POLYLINE;
  t.objective = EA_TASK_MIN_JERK;
  t.duration_s = 2.0;
  t.knots = 9;
  t.solver.max_iter = 1;
  t.solver.derivative_test = 1;
  ea_error_t e = {0};
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  ea_status_t st = ea_task_check(&t, &e);
  if (!st) st = ea_planner_alloc(&t, &pl, &e);
  if (!st) ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  ea_test_true(pl && info.deriv_errors == 0, "derivative checker (polyline, min jerk)");
  ea_planner_free(pl);
}

static void test_infeasible(void) {
  char path[1024];
  snprintf(path, sizeof path, "%s/problems/examples/infeasible-line.yaml", src_dir());
  ea_task_t t;
  ea_error_t e = {0};
  ea_status_t st = ea_task_load(path, NULL, &t, &e);
  ea_test_true(st == EA_OK, "infeasible-line: both ends inside the workspace");
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  if (!st) st = ea_planner_alloc(&t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  char what[700];
  snprintf(what, sizeof what, "infeasible-line reported infeasible: %s", e.msg);
  ea_test_true(
      st == EA_ERR_INFEASIBLE && strstr(e.msg, "knot") && strstr(e.msg, "cable_length_min"), what);
  ea_traj_t tr;
  memset(&tr, 0, sizeof tr);
  ea_test_true(pl && ea_planner_trajectory(pl, &tr, NULL) != EA_OK,
               "no trajectory for an infeasible plan");
  ea_traj_free(&tr);
  ea_planner_free(pl);
  /* A free path whose limits cannot be met: a shoulder-torque limit below
   * what the goal needs is caught at the goal; a tension floor above the
   * start's tension at the start. */
  ea_task_init(&t, NULL);
  t.start = ea_task_point_planar(0.3, -0.2, 0.0);
  t.goal = ea_task_point_planar(0.6, -0.2, 0.0);
  t.limits.tension_min = 50.0;
  st = ea_task_check(&t, &e);
  ea_test_true(st == EA_ERR_INFEASIBLE && strstr(e.msg, "start"), "tension floor: start named");
}

/* Replanning (ea_planner_update + EA_PLAN_WARM): the plan of a changed task
 * from a live planner must be the plan a cold solve of that task finds
 * (duration, statics re-solved independently, limits from the file), in
 * fewer iterations; a change that makes the task infeasible must be
 * reported, never answered with the old plan. */
static void test_replan(void) {
  ea_task_t t, moved, bad;
  ea_task_init(&t, NULL);
  t.start = ea_task_point_planar(0.3, -0.2, 0.0);
  t.goal = ea_task_point_planar(0.6, -0.2, 0.0);
  t.path = EA_TASK_PATH_LINE;
  t.knots = 100;
  ea_error_t e = {0};
  ea_status_t st = ea_task_check(&t, &e);
  ea_test_true(st == EA_OK, "replan: paper line checks");
  if (st) return;
  ea_planner_t *pl = NULL, *pc = NULL;
  ea_traj_t tr, trc;
  memset(&tr, 0, sizeof tr);
  memset(&trc, 0, sizeof trc);
  ea_plan_info_t info, w, c;
  char what[700];
  st = plan(&t, &pl, &tr, &info, &e);
  ea_test_true(st == EA_OK, "replan: first plan");
  if (st) goto done;
  /* goal moved 5 mm along the line: warm replan vs a cold plan */
  const ea_task_point_t g5 = ea_task_point_planar(0.605, -0.2, 0.0);
  st = ea_planner_update_goal(pl, &g5, &e);
  ea_test_true(st == EA_OK, "replan: goal moved 5 mm accepted");
  ea_test_true(ea_planner_trajectory(pl, &tr, NULL) != EA_OK,
               "replan: no trajectory between an update and its solve");
  if (!st) st = ea_planner_solve(pl, EA_PLAN_WARM, NULL, &w, &e);
  snprintf(what, sizeof what, "replan: goal +5 mm converges (%s)", e.msg);
  ea_test_true(st == EA_OK, what);
  if (!st) st = ea_planner_trajectory(pl, &tr, &e);
  moved = t;
  moved.goal = g5;
  if (!st) st = ea_task_check(&moved, &e);
  if (!st) st = plan(&moved, &pc, &trc, &c, &e);
  ea_test_true(st == EA_OK, "replan: cold plan of the moved task");
  if (!st) {
    printf("replan goal +5 mm: warm %d iterations %.1f ms, cold %d iterations %.1f ms\n",
           w.iterations, 1e3 * w.time_total_s, c.iterations, 1e3 * c.time_total_s);
    ea_test_rel(w.duration_s, c.duration_s, 1e-6, "replan: same duration as the cold plan");
    snprintf(what, sizeof what, "replan: fewer iterations than cold (%d < %d)", w.iterations,
             c.iterations);
    ea_test_true(w.iterations < c.iterations, what);
    check_statics(&moved, &tr, "replan goal +5 mm");
    check_limits(&moved, &tr, "replan goal +5 mm");
    double dg = fabs(EA_TRAJ_AT(&tr, tr.n - 1, EA_TRAJ_tip_x) - 0.605);
    ea_test_abs(dg, 0.0, 1e-9, "replan: the plan ends at the moved goal [m]");
  }
  /* a structural change is refused, the planner keeps its task */
  ea_task_t k50 = moved;
  k50.knots = 50;
  st = ea_planner_update(pl, &k50, &e);
  ea_test_true(st == EA_ERR_ARG && strstr(e.msg, "knot"), "replan: knot count change refused");
  ea_test_true(ea_planner_task(pl)->knots == 100, "replan: refused update leaves the task");
  /* a goal outside the workspace is refused by the check */
  const ea_task_point_t gout = ea_task_point_planar(2.0, -0.2, 0.0);
  st = ea_planner_update_goal(pl, &gout, &e);
  ea_test_true(st == EA_ERR_INFEASIBLE, "replan: goal outside the workspace refused");
  /* a large change whose line leaves the workspace (both ends inside):
   * reported infeasible with the constraint, never the old plan */
  bad = t;
  bad.start = ea_task_point_planar(0.34, 0.08, 0.0);
  bad.goal = ea_task_point_planar(0.34, -0.30, 0.0);
  st = ea_task_check(&bad, &e);
  ea_test_true(st == EA_OK, "replan: infeasible line's ends inside the workspace");
  if (!st) st = ea_planner_update(pl, &bad, &e);
  ea_test_true(st == EA_OK, "replan: infeasible line accepted as an update");
  if (!st) {
    st = ea_planner_solve(pl, EA_PLAN_WARM, NULL, &w, &e);
    snprintf(what, sizeof what, "replan: infeasible line reported infeasible: %s", e.msg);
    ea_test_true(st == EA_ERR_INFEASIBLE && strstr(e.msg, "knot"), what);
    ea_test_true(ea_planner_trajectory(pl, &tr, NULL) != EA_OK,
                 "replan: no trajectory after an infeasible replan");
  }
done:
  ea_traj_free(&tr);
  ea_traj_free(&trc);
  ea_planner_free(pl);
  ea_planner_free(pc);
}

int main(int argc, char **argv) {
  test_paper_line();
  test_topp();
  test_derivatives();
  test_infeasible();
  test_replan();
  ea_sweep_run(argc > 1 ? atoi(argv[1]) : 10, 0x2545F4914F6CDD1DULL, 30);
  return ea_test_summary("test_plan");
}
