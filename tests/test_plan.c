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

#include <stddef.h>

static const char *src_dir(void) {
  const char *s = getenv("EA_SOURCE_DIR");
  return s ? s : ".";
}

/* ---------------------------------------------------------------------- */
/* Checks of a plan against the task's limits, from the trajectory file:    */
/* written, read back and re-checked at 1 kHz and at every knot with the    */
/* file's interpolant (ea_plan_check.h), between the knots too.             */
/* ---------------------------------------------------------------------- */

static void check_limits(const ea_task_t *t, const ea_traj_t *tr, const char *name) {
  char path[] = "/tmp/ea_test_plan_lim_XXXXXX", what[300];
  const int fd = mkstemp(path);
  ea_traj_t back = {0};
  ea_error_t e = {0};
  if (fd >= 0) close(fd);
  const int io = fd >= 0 && !ea_traj_write(tr, path, &e) && !ea_traj_read(&back, path, &e);
  if (fd >= 0) remove(path);
  ea_test_true(io, "trajectory file written and read back for the limits check");
  if (!io) return;
  ea_chk_t c;
  const double w = ea_chk_traj(t, &back, 1000.0, &c);
  ea_chk_print(name, &c);
  /* measured: active limits at usage 1 - 1e-7 (interior point); no excess */
  snprintf(what, sizeof what,
           "%s: every limit held at 1 kHz and the knots, from the file (worst relative excess "
           "%.3g, tolerance 0)",
           name, w);
  ea_test_true(w <= 0.0, what);
  ea_traj_free(&back);
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

/* The info names Ipopt's status only where Ipopt gave the result: the paper line's cold plan
 * is the own interior point's (the strategy's table, strategy/strategy_impl.h: a path with
 * solver.nlp auto), its warm re-solve without a change passes the KKT test as it was, and
 * with settings.engines ipopt Ipopt plans it. */
static void test_engine_info(void) {
  char path[1024], what[800];
  snprintf(path, sizeof path, "%s/problems/examples/paper-line.yaml", src_dir());
  ea_task_t t;
  ea_error_t e = {0};
  if (ea_task_load(path, NULL, &t, &e)) {
    ea_test_true(0, "engine info: paper-line loads");
    return;
  }
  ea_planner_settings_t s;
  ea_planner_settings_default(&s);
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  ea_status_t st = ea_planner_alloc_with(&t, &s, &pl, &e);
  const char *want[2] = {"interior-point-ldl", "kkt-test"};
  for (int pass = 0; pass < 2 && !st; ++pass) {
    st = ea_planner_solve(pl, pass ? EA_PLAN_WARM : EA_PLAN_COLD, NULL, &info, &e);
    snprintf(what, sizeof what, "engine info: %s plan by %s, ipopt_status %d \"%s\" (%s)",
             pass ? "warm" : "cold", ea_plan_engine_name(&info), info.ipopt_status,
             info.ipopt_status_name, e.msg);
    ea_test_true(st == EA_OK && !strcmp(ea_plan_engine_name(&info), want[pass]) &&
                     !strcmp(ea_plan_engine_status(&info), "converged") &&
                     info.ipopt_status == EA_PLAN_NO_IPOPT && !info.ipopt_status_name[0],
                 what);
  }
  ea_planner_free(pl);
  pl = NULL;
  s.engines = EA_PLANNER_ENGINES_IPOPT;
  st = ea_planner_alloc_with(&t, &s, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  snprintf(what, sizeof what, "engine info: Ipopt's plan, ipopt_status %d \"%s\" (%s)",
           info.ipopt_status, info.ipopt_status_name, e.msg);
  ea_test_true(st == EA_OK && !strcmp(ea_plan_engine_name(&info), "ipopt") &&
                   info.ipopt_status == 0 && !strcmp(info.ipopt_status_name, "Solve_Succeeded"),
               what);
  ea_planner_free(pl);
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
     * time of a rest-to-rest move of distance D is D / v + v / a at the
     * arm's nominal limits (no margin: docs/planner.md). */
    const double D = hypot(0.6 - 0.098, -0.2 + 0.006) - hypot(0.3 - 0.098, -0.2 + 0.006);
    const double v = t.limits.cable_speed_max, a = t.limits.cable_accel_max;
    /* continuous acceleration (default) ramps each switch over one interval:
     * O(h) above the bang-bang closed form; measured 1.28e-4 at 100 knots,
     * tolerance 2e-4 (a plan 0.4 % slow, as with the old 0.5 % margin, fails) */
    ea_test_rel(info.duration_s, D / v + v / a, 2e-4,
                "paper line: duration vs closed form D/v + v/a (nominal limits)");
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

/* The planner's settings apart from the task (ea_planner_alloc_with): validation names the
 * field; other settings than the task file's are the ones the planner uses (Ipopt alone, an
 * iteration cap of 1), the task itself unchanged; the plan's duration is the closed form's
 * D/v + v/a whichever engine solved. */
static void test_settings(void) {
  ea_planner_settings_t s;
  ea_error_t e = {0};
  ea_planner_settings_default(&s);
  ea_test_true(ea_planner_settings_validate(&s, &e) == EA_OK, "settings: defaults validate");
  s.tol = 0.0;
  ea_test_true(ea_planner_settings_validate(&s, &e) == EA_ERR_INPUT && strstr(e.msg, "tol = 0"),
               "settings: tol 0 refused, named");
  ea_planner_settings_default(&s);
  s.threads = 3;
  ea_test_true(ea_planner_settings_validate(&s, &e) == EA_ERR_INPUT &&
                   strstr(e.msg, "threads = 3, not in [0, 2]"),
               "settings: threads 3 refused, with its bound");
  char path[1024];
  snprintf(path, sizeof path, "%s/problems/examples/paper-line.yaml", src_dir());
  ea_task_t t;
  if (ea_task_load(path, NULL, &t, &e)) {
    ea_test_true(0, "settings: paper-line loads");
    return;
  }
  const double D = hypot(0.6 - 0.098, -0.2 + 0.006) - hypot(0.3 - 0.098, -0.2 + 0.006);
  const double v = t.limits.cable_speed_max, a = t.limits.cable_accel_max;
  for (int pass = 0; pass < 2; ++pass) {
    ea_planner_settings_default(&s);
    s.engines = EA_PLANNER_ENGINES_IPOPT;
    if (pass) s.max_iter = 1;
    ea_planner_t *pl = NULL;
    ea_plan_info_t info;
    ea_status_t st = ea_planner_alloc_with(&t, &s, &pl, &e);
    if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
    char what[700];
    snprintf(what, sizeof what, "settings: Ipopt alone%s: %s, engine %s (%s)",
             pass ? ", 1 iteration" : "", ea_status_name(st), ea_plan_engine_name(&info), e.msg);
    if (!pass) {
      ea_test_true(st == EA_OK && !strcmp(ea_plan_engine_name(&info), "ipopt"), what);
      ea_test_rel(info.duration_s, D / v + v / a, 2e-4, "settings: Ipopt's duration");
    } else {
      ea_test_true(st == EA_ERR_MAXITER, what);
    }
    ea_test_true(pl && ea_planner_task(pl)->solver.engines == EA_PLANNER_ENGINES_IPOPT &&
                     t.solver.engines == EA_PLANNER_ENGINES_AUTO,
                 "settings: the planner's, the task unchanged");
    ea_planner_free(pl);
  }
  ea_test_true(ea_planner_alloc_with(&t, NULL, &(ea_planner_t *){NULL}, &e) == EA_ERR_ARG,
               "settings: NULL refused");
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
    /* the nominal limits (no margin) */
    const double v[2] = {0.25, 0.5}, a[2] = {1.0, 2.0};
    const double T20k = topp_time(paper_line_path, v, a, 20000);
    const double T40k = topp_time(paper_line_path, v, a, 40000);
    /* measured 5.1e-6 between the grids */
    ea_test_rel(T20k, T40k, 2e-5, "TOPP reference converged in its grid");
    /* measured 1.97e-4 above the reference (the C2 plan ramps each of the
     * acceleration switches over one interval: O(h)), tolerance 1.5x; the
     * old 0.5 % margin (0.40 % slower) fails it */
    ea_test_rel(info.duration_s, T40k, 3e-4, "min time vs time-optimal path parameterisation");
    ea_test_true(info.duration_s >= T40k * (1 - 1e-5), "min time not below the TOPP reference");
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

/* Closed-form optima of one coordinate: only the cable length changes (the
 * tip moves along the ray of a fixed cable angle), rest to rest in a fixed
 * duration T, no limit active. With u = t / T and D the length change:
 *  - min_effort (integral of acc^2, position and rate given at the ends):
 *    Euler-Lagrange q'''' = 0, the cubic q = L0 + D (3 u^2 - 2 u^3); the
 *    plan's C2 cubic spline contains it, so the plan is it up to the
 *    solver's tolerance;
 *  - min_jerk (integral of jerk^2, position and rate given, acceleration
 *    free at the ends): q^(6) = 0 with the natural conditions q''' = 0 at
 *    both ends, the quintic q = L0 + D (5/2 u^2 - 5/2 u^4 + u^5); the C2
 *    cubic spline (piecewise constant jerk) approaches it as h^2.
 * The cable angle must stay at its value (any motion of it costs). */
static double closed_form(int jerk, double u, double *rate_per_T) {
  if (!jerk) {
    *rate_per_T = 6.0 * u - 6.0 * u * u;
    return 3.0 * u * u - 2.0 * u * u * u;
  }
  *rate_per_T = 5.0 * u - 10.0 * u * u * u + 5.0 * u * u * u * u;
  return 2.5 * u * u - 2.5 * u * u * u * u + u * u * u * u * u;
}

static void test_closed_forms(void) {
  const double L0 = 0.30, L1 = 0.45, al = -0.70, T = 3.0, D = L1 - L0;
  for (int jerk = 0; jerk <= 1; ++jerk) {
    double err_prev = NAN;
    const int ks[3] = {25, 50, 100};
    for (int ik = 0; ik < 3; ++ik) {
      ea_task_t t;
      ea_task_init(&t, NULL);
      t.start = ea_task_point_actuators(L0, al, 0.0);
      t.goal = ea_task_point_actuators(L1, al, 0.0);
      t.objective = jerk ? EA_TASK_MIN_JERK : EA_TASK_MIN_EFFORT;
      t.duration_s = T;
      t.knots = ks[ik];
      ea_error_t e = {0};
      ea_planner_t *pl = NULL;
      ea_traj_t tr = {0};
      ea_plan_info_t info;
      ea_status_t st = ea_task_check(&t, &e);
      if (!st) st = plan(&t, &pl, &tr, &info, &e);
      char what[700];
      snprintf(what, sizeof what, "%s, one coordinate, %d knots: planned (%s)",
               jerk ? "min_jerk" : "min_effort", ks[ik], e.msg);
      ea_test_true(st == EA_OK, what);
      if (!st) {
        double eq = 0.0, ev = 0.0, ea = 0.0;
        for (int k = 0; k < tr.n; ++k) {
          const double u = EA_TRAJ_AT(&tr, k, EA_TRAJ_t) / T;
          double r;
          const double q = closed_form(jerk, u, &r);
          eq = fmax(eq, fabs(EA_TRAJ_AT(&tr, k, EA_TRAJ_cable_length) - (L0 + D * q)) / D);
          ev = fmax(ev, fabs(EA_TRAJ_AT(&tr, k, EA_TRAJ_cable_length_rate) - D * r / T) / (D / T));
          ea = fmax(ea, fabs(EA_TRAJ_AT(&tr, k, EA_TRAJ_cable_angle) - al));
        }
        printf("%s, %3d knots: max |L_c - closed form| / D = %.3g, rates / (D/T) %.3g, "
               "|alpha - alpha0| %.3g rad\n",
               jerk ? "min_jerk" : "min_effort", ks[ik], eq, ev, ea);
        snprintf(what, sizeof what, "%s, %d knots: L_c and its rate vs the closed form",
                 jerk ? "min_jerk (quintic)" : "min_effort (cubic)", ks[ik]);
        /* measured (max of positions / D and rates / (D/T)): min_effort
         * 2.8e-9, 2.5e-9, 5.1e-9 (solver tolerance); min_jerk 8.7e-5,
         * 2.1e-5, 5.3e-6 at 25, 50, 100 knots (h^2); tolerances 2x */
        const double tol = jerk ? 2.0 * 8.8e-5 * pow(25.0 / ks[ik], 2) : 1e-8;
        ea_test_abs(fmax(eq, ev), 0.0, tol, what);
        snprintf(what, sizeof what, "%s, %d knots: the cable angle stays [rad]",
                 jerk ? "min_jerk" : "min_effort", ks[ik]);
        ea_test_abs(ea, 0.0, 1e-9, what); /* measured <= 3.7e-10 */
        if (jerk && ik > 0) {
          snprintf(what, sizeof what, "min_jerk: error / 4 when the knots double (%.3g -> %.3g)",
                   err_prev, fmax(eq, ev));
          ea_test_true(fmax(eq, ev) < 0.3 * err_prev, what);
        }
        err_prev = fmax(eq, ev);
      }
      ea_traj_free(&tr);
      ea_planner_free(pl);
    }
  }
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
  /* The path transcription's own Jacobian and Hessian (the chain rule through the path's
   * second derivatives): the same 3-D line, then a polyline with min jerk. */
  t.solver.transcription = EA_TASK_TRANSCRIPTION_PATH;
  for (int order = 1; order <= 2; ++order) {
    t.solver.derivative_test = order;
    ea_error_t e = {0};
    ea_planner_t *pl = NULL;
    ea_plan_info_t info;
    info.deriv_errors = -1;
    ea_status_t st = ea_task_check(&t, &e);
    if (!st) st = ea_planner_alloc(&t, &pl, &e);
    if (!st) ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
    char what[200];
    snprintf(what, sizeof what,
             "derivative checker (%s, 3-D line, min time, path transcription): %d errors",
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
  /* the path transcription on the same polyline, min time (its corners and the C2 rows through
   * them; min jerk's steep objective puts Ipopt's forward differences themselves off by 1e-5
   * relative at their default step: the second derivatives in sigma were checked to converge
   * to ours as that step shrinks, 1e-6 .. 3e-8) */
  pl = NULL;
  t.solver.transcription = EA_TASK_TRANSCRIPTION_PATH;
  t.solver.derivative_test = 2;
  t.objective = EA_TASK_MIN_TIME;
  t.duration_s = NAN;
  info.deriv_errors = -1;
  st = ea_task_check(&t, &e);
  if (!st) st = ea_planner_alloc(&t, &pl, &e);
  if (!st) ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  char what[200];
  snprintf(what, sizeof what,
           "derivative checker (second order, polyline, min time, path transcription): %d errors",
           pl ? info.deriv_errors : -1);
  ea_test_true(pl && info.deriv_errors == 0, what);
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

/* Replanning a polyline loaded from text (two segments, the base turning): the moved task's
 * arm differs from the planner's only in bytes that mean nothing (the padding after n_damping,
 * the unused damping slots; the comparison once read them with memcmp and refused updates as
 * "arm differs", depending on what the loader's stack held); every update (via, goal, base
 * angle moved) must be accepted and give a cold plan's duration to 1e-6, the small ones by the
 * active-set Newton, or where it gives up by the own interior point from the cold guess (the
 * cold plan's iterations) or by Ipopt in fewer iterations than cold. */
static void test_replan_loaded(void) {
  static const char *fmt = "name: p\npayload_factor: 0.1\nstart:\n  tip: [0.35, -0.25]\nvia:\n"
                           "  - tip: [%.4f, %.4f]\n    base_angle_rad: 0.2\ngoal:\n"
                           "  tip: [%.4f, -0.30]\n  base_angle_rad: %.4f\npath: polyline\n"
                           "objective: min_time\nknots: 60\n";
  /* 5 mm / 0.02 rad moves; then the via 10 mm away, where a cold planner of the moved task
   * places the via knot elsewhere (kept, it fixed the time of passing the via: 1.1 and 3.3 %
   * slower than cold) */
  const double mv[6][4] = {{0.005, 0, 0, 0}, {0, 0.005, 0, 0}, {0, 0, 0.005, 0},
                           {0, 0, 0, 0.02},  {0.01, 0, 0, 0},  {0.01, -0.01, 0, 0}};
  char text[512], what[700];
  ea_task_t t0, t1;
  ea_error_t e = {0};
  memset(&t0, 0x00, sizeof t0);
  snprintf(text, sizeof text, fmt, 0.45, -0.2, 0.55, 0.4);
  ea_status_t st = ea_task_load_string("p.yaml", text, strlen(text), NULL, &t0, &e);
  ea_test_true(st == EA_OK, "replan loaded: polyline task loads");
  if (st) return;
  for (int m = 0; m < 6; ++m) {
    ea_planner_t *pl = NULL, *pc = NULL;
    ea_plan_info_t i0, w, c;
    memset(&t1, 0xA5, sizeof t1);
    snprintf(text, sizeof text, fmt, 0.45 + mv[m][0], -0.2 + mv[m][1], 0.55 + mv[m][2],
             0.4 + mv[m][3]);
    st = ea_task_load_string("p.yaml", text, strlen(text), NULL, &t1, &e);
    /* what the arm's comparison must not read: the bytes after n_damping (padding) and the
     * damping slots beyond n_damping (unused: those modes are undamped) */
    unsigned char *pad = (unsigned char *)&t1.arm + offsetof(ea_arm_t, n_damping) + sizeof(int);
    memset(pad, 0x5A,
           offsetof(ea_arm_t, damping_ratio) - offsetof(ea_arm_t, n_damping) - sizeof(int));
    for (int i = t1.arm.n_damping; i < EA_ARM_MAX_DAMPED_MODES; ++i)
      t1.arm.damping_ratio[i] = 0.25 + 0.01 * m;
    if (!st) st = ea_planner_alloc(&t0, &pl, &e);
    if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &i0, &e);
    if (!st) st = ea_planner_update(pl, &t1, &e);
    snprintf(what, sizeof what, "replan loaded: update %d accepted (%s)", m, e.msg);
    ea_test_true(st == EA_OK, what);
    if (!st) st = ea_planner_solve(pl, EA_PLAN_WARM, NULL, &w, &e);
    if (!st) st = ea_planner_alloc(&t1, &pc, &e);
    if (!st) st = ea_planner_solve(pc, EA_PLAN_COLD, NULL, &c, &e);
    snprintf(what, sizeof what, "replan loaded: update %d warm and cold solves (%s)", m, e.msg);
    ea_test_true(st == EA_OK, what);
    if (!st) {
      printf("replan loaded %d: warm %d iterations, cold %d\n", m, w.iterations, c.iterations);
      snprintf(what, sizeof what, "replan loaded: update %d duration as cold", m);
      ea_test_rel(w.duration_s, c.duration_s, 1e-6, what);
      /* the small moves: the active-set Newton's replan, or (where it gives up) the own
       * interior point from the cold guess, the cold plan's iterations; by Ipopt fewer
       * iterations than cold */
      const int by_ipm = w.ipm_iterations > 0 && !w.ipm_fallback;
      snprintf(what, sizeof what,
               "replan loaded: update %d by the Newton, or by the own interior point from the "
               "cold guess in the cold plan's iterations, or by Ipopt in fewer (%d, %s, cold %d)",
               m, w.iterations, by_ipm ? "own interior point" : "Ipopt", c.iterations);
      if (m < 4)
        ea_test_true(by_ipm ? w.iterations == c.iterations : w.iterations < c.iterations, what);
    }
    ea_planner_free(pl);
    ea_planner_free(pc);
  }
  /* fixed duration, minimum effort (polyline-effort's points): the via's cable length moved */
  static const char *fe = "name: e\npayload_factor: 0.1\nstart:\n  tip: [0.35, -0.25]\nvia:\n"
                          "  - cable_length_m: %.4f\n    cable_angle_rad: -0.2\n"
                          "    base_angle_rad: 0.2\ngoal:\n  tip: [0.55, -0.30]\n"
                          "  base_angle_rad: 0.4\npath: polyline\nobjective:\n  type: min_effort\n"
                          "  duration_s: 3.0\nknots: 60\n";
  for (int m = 0; m < 2; ++m) {
    ea_planner_t *pl = NULL, *pc = NULL;
    ea_plan_info_t i0, w, c;
    snprintf(text, sizeof text, fe, 0.45);
    st = ea_task_load_string("e.yaml", text, strlen(text), NULL, &t0, &e);
    snprintf(text, sizeof text, fe, m ? 0.42 : 0.50);
    if (!st) st = ea_task_load_string("e.yaml", text, strlen(text), NULL, &t1, &e);
    if (!st) st = ea_planner_alloc(&t0, &pl, &e);
    if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &i0, &e);
    if (!st) st = ea_planner_update(pl, &t1, &e);
    if (!st) st = ea_planner_solve(pl, EA_PLAN_WARM, NULL, &w, &e);
    if (!st) st = ea_planner_alloc(&t1, &pc, &e);
    if (!st) st = ea_planner_solve(pc, EA_PLAN_COLD, NULL, &c, &e);
    snprintf(what, sizeof what, "replan loaded: min effort, via moved %d: solves (%s)", m, e.msg);
    ea_test_true(st == EA_OK, what);
    snprintf(what, sizeof what, "replan loaded: min effort, via moved %d: objective as cold", m);
    if (!st) ea_test_rel(w.objective, c.objective, 1e-8, what);
    ea_planner_free(pl);
    ea_planner_free(pc);
  }
  /* a real difference of the arm is still refused */
  ea_planner_t *pl = NULL;
  t1 = t0;
  t1.arm.damping_ratio[0] = 0.01;
  t1.arm.n_damping = 1;
  st = ea_planner_alloc(&t0, &pl, &e);
  if (!st) st = ea_planner_update(pl, &t1, &e);
  ea_test_true(st == EA_ERR_ARG && strstr(e.msg, "arm"), "replan loaded: a damped mode refused");
  t1 = t0;
  t1.arm.EI *= 1.01;
  st = pl ? ea_planner_update(pl, &t1, &e) : EA_ERR_ARG;
  ea_test_true(st == EA_ERR_ARG && strstr(e.msg, "arm"), "replan loaded: EI + 1 % refused");
  ea_planner_free(pl);
}

int main(int argc, char **argv) {
  test_paper_line();
  test_settings();
  test_engine_info();
  test_topp();
  test_closed_forms();
  test_derivatives();
  test_infeasible();
  test_replan();
  test_replan_loaded();
  ea_sweep_run(argc > 1 ? atoi(argv[1]) : 10, 0x2545F4914F6CDD1DULL, 30, EA_TASK_PATH_FREE);
  return ea_test_summary("test_plan");
}
