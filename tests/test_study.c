/* Batch studies: the workspace metrics against independent references
 * (another integrator, Simpson in polar coordinates, golden section,
 * regula falsi on the torque limit), the Fig. 3 result (outer edge moves
 * inward with payload), byte-identical CSV for 1, 2, 3 threads, shards
 * merged = single run, shards of different specs refused, interrupted
 * (stop hook, kill -9, torn journal) and resumed = uninterrupted, an edited
 * min_time task refused on resume, rows independent of the working
 * directory, -o moving every output, min-time durations against
 * lower bounds from the limits, failed cases recorded, spec errors with
 * file:line:column. */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_test.h"
#include "study_report_impl.h"

#include <errno.h>
#include <fcntl.h>
#include <gsl/gsl_errno.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static char g_src[1024] = ".";
static char g_tmp[256];

/* A mixed study: workspace + frequencies (one configuration outside the
 * workspace for the heavier payloads) + path + torque map. */
static const char *k_mixed =
    "name: mixed\n"
    "grid:\n"
    "  payload_factor: 0:0.1:0.5\n"
    "  EI_Nm2: [0.6, 0.705]\n"
    "metrics:\n"
    "  workspace: {points: 21}\n"
    "  torque_map: {cable_lengths_m: '0.3:0.1:0.8', cable_angles_deg: [-50, -20, 0]}\n"
    "  frequencies:\n"
    "    modes: 2\n"
    "    elements: 6\n"
    "    configurations:\n"
    "      - {cable_length_m: 0.45, cable_angle_deg: -25}\n"
    "      - {cable_length_m: 0.85, cable_angle_deg: 0}\n"
    "  path: {start: [0.3, -0.2], goal: [0.6, -0.2], steps: 10}\n";

static int load(const char *text, ea_study_t *s) {
  ea_error_t e = {0};
  ea_status_t st = ea_study_load_string("mixed.yaml", text, strlen(text), NULL, s, &e);
  if (st) printf("load: %s\n", e.msg);
  return st;
}

static char *run(const ea_study_t *s, int threads, int k, int n, const char *ckpt, long stop_after,
                 ea_study_info_t *info, ea_status_t *st_out) {
  ea_study_settings_t set;
  ea_study_settings_default(&set);
  set.threads = threads;
  set.shard_k = k;
  set.shard_n = n;
  set.checkpoint = ckpt;
  set.stop_after = stop_after;
  set.fsync = 0;
  char *csv = NULL;
  size_t len = 0;
  ea_error_t e = {0};
  ea_study_info_t dummy;
  ea_status_t st = ea_study_run(s, &set, &csv, &len, info ? info : &dummy, &e);
  if (st_out) *st_out = st;
  if (st && st != EA_ERR_INTERRUPTED) printf("run: %s\n", e.msg);
  return csv;
}

static double metric(const char *csv, long case_id, const char *name, char *status) {
  ea__study_table_t t;
  ea_error_t e;
  double v = NAN;
  if (ea__study_table_parse(csv, strlen(csv), "csv", &t, &e)) return NAN;
  for (long i = 0; i < t.n_rows; ++i)
    if (t.rows[i].case_id == case_id && !strcmp(t.rows[i].metric, name)) {
      v = t.rows[i].value;
      if (status) strcpy(status, t.rows[i].status);
    }
  ea__study_table_free(&t);
  return v;
}

/* ---- workspace metrics: definitions, convergence, independent references ---- */

#define DEG (M_PI / 180.0)

/* A shooter on a different integrator (GSL rkf45, adaptive, 1e-12) than the
 * metrics' (rk8pd, 12 fixed steps): the references below do not share the
 * integration of the code under test. */
static ea_shooter_t *ref_shooter(const ea_arm_t *arm, double gamma) {
  ea_shoot_settings_t rs;
  ea_shoot_settings_default(&rs);
  rs.integrator = EA_INT_RKF45_ADAPTIVE;
  rs.rtol = rs.atol = 1e-12;
  ea_shooter_t *sh = NULL;
  if (ea_shooter_alloc(arm, &rs, &sh, NULL)) return NULL;
  ea_load_t ld = {ea_arm_tip_mass(arm, ea_arm_payload_from_factor(arm, gamma))};
  ea_shooter_set_load(sh, &ld);
  return sh;
}

static ea_statics_settings_t tight(void) {
  ea_statics_settings_t ss;
  ea_statics_settings_default(&ss);
  ss.tol = 1e-12;
  return ss;
}

/* Outer edge at alpha: cable length, and the statics in p (warm start g). */
static double ref_edge(ea_shooter_t *sh, double a, double *g, double p[4]) {
  ea_statics_settings_t ss = tight();
  ea_statics_solution_t sol;
  double guess[4];
  if (g) memcpy(guess, g, sizeof guess);
  if (ea_statics_edge(sh, a, &ss, g ? guess : NULL, &sol, NULL)) return NAN;
  if (p) memcpy(p, sol.p, sizeof sol.p);
  return sol.cable_length;
}

/* The cable length at alpha where the shoulder torque EI kappa0 reaches
 * -tq (between the inner edge and the outer edge): regula falsi on L_c with
 * cable solves (not the metrics' direct statement). */
static double ref_torque_boundary(ea_shooter_t *sh, const ea_arm_t *arm, double a, double tq) {
  ea_statics_settings_t ss = tight();
  double pe[4] = {0};
  double lo = arm->act.cable_length_min, hi = ref_edge(sh, a, NULL, pe);
  if (isnan(hi)) return NAN;
  const double fhi0 = arm->EI * pe[3] + tq;
  if (fhi0 >= 0) return hi; /* the edge itself is within the limit */
  double p[4], flo, fhi = fhi0;
  ea_statics_solution_t sol;
  ea_statics_problem_t pr = ea_statics_problem_cable(lo, a);
  if (ea_statics_solve(sh, &pr, &ss, NULL, &sol, NULL)) return NAN;
  flo = sol.shoulder_torque + tq;
  memcpy(p, sol.p, sizeof p);
  if (flo <= 0) return NAN;
  int side = 0;
  for (int it = 0; it < 200 && hi - lo > 1e-14; ++it) {
    const double L = (lo * fhi - hi * flo) / (fhi - flo);
    pr = ea_statics_problem_cable(L, a);
    if (ea_statics_solve(sh, &pr, &ss, p, &sol, NULL)) return NAN;
    memcpy(p, sol.p, sizeof p);
    const double f = sol.shoulder_torque + tq;
    if (f == 0) return L;
    if ((f > 0) == (flo > 0)) {
      lo = L;
      flo = f;
      if (side == -1) fhi *= 0.5;
      side = -1;
    } else {
      hi = L;
      fhi = f;
      if (side == 1) flo *= 0.5;
      side = 1;
    }
    if (fabs(f) < 1e-13) return L;
  }
  return 0.5 * (lo + hi);
}

/* Composite Simpson of f over [a, b] with n (even) intervals, Richardson
 * extrapolated with n / 2 (Simpson's error is O(h^4)): the reference and
 * |S_n - S_{n/2}| as its quadrature error scale. */
typedef double (*ref_fn)(void *ctx, double a);
static double simpson_rich(ref_fn f, void *ctx, double a, double b, int n, double *diff) {
  double *v = malloc((size_t)(n + 1) * sizeof *v);
  if (!v) return NAN;
  for (int k = 0; k <= n; ++k)
    v[k] = f(ctx, a + (b - a) * k / n);
  double s1 = 0, s2 = 0;
  for (int k = 0; k <= n; ++k)
    s1 += v[k] * (k == 0 || k == n ? 1 : k % 2 ? 4 : 2);
  s1 *= (b - a) / n / 3;
  for (int k = 0; k <= n; k += 2)
    s2 += v[k] * (k == 0 || k == n ? 1 : k % 4 ? 4 : 2);
  s2 *= 2 * (b - a) / n / 3;
  free(v);
  *diff = fabs(s1 - s2);
  return s1 + (s1 - s2) / 15;
}

typedef struct {
  ea_shooter_t *sh;
  const ea_arm_t *arm;
  double inner, tq;
  int torque; /* top = torque boundary instead of the edge */
} ref_ctx_t;

/* (L_top^2 - L_in^2) / 2: the integrand of the area in polar coordinates
 * about the cable root. */
static double ref_integrand(void *vctx, double a) {
  ref_ctx_t *c = vctx;
  const double top =
      c->torque ? ref_torque_boundary(c->sh, c->arm, a, c->tq) : ref_edge(c->sh, a, NULL, NULL);
  return 0.5 * (top * top - c->inner * c->inner);
}

/* x of the outer-edge tip at alpha (negated, for a minimiser). */
static double ref_neg_x(ea_shooter_t *sh, const ea_arm_t *arm, double a) {
  return -(arm->x_c + ref_edge(sh, a, NULL, NULL) * cos(a));
}

/* Golden-section minimum of ref_neg_x on [a, b]. */
static double golden(ea_shooter_t *sh, const ea_arm_t *arm, double a, double b, double *xmin) {
  const double r = 0.5 * (sqrt(5.0) - 1.0);
  double c = b - r * (b - a), d = a + r * (b - a);
  double fc = ref_neg_x(sh, arm, c), fd = ref_neg_x(sh, arm, d);
  while (b - a > 1e-9) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - r * (b - a);
      fc = ref_neg_x(sh, arm, c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + r * (b - a);
      fd = ref_neg_x(sh, arm, d);
    }
  }
  *xmin = 0.5 * (a + b);
  return ref_neg_x(sh, arm, *xmin);
}

static int ws_metrics(const ea_arm_t *arm, double gamma, const ea_workspace_settings_t *set,
                      ea_workspace_metrics_t *m, ea_error_t *e) {
  ea_shooter_t *sh = NULL;
  if (ea_shooter_alloc(arm, NULL, &sh, e)) return -1;
  ea_load_t ld = {ea_arm_tip_mass(arm, ea_arm_payload_from_factor(arm, gamma))};
  ea_shooter_set_load(sh, &ld);
  const int st = ea_workspace_metrics(sh, set, m, e);
  ea_shooter_free(sh);
  return st;
}

static void test_workspace_metrics(void) {
  char path[1200];
  snprintf(path, sizeof path, "%s/data/elasticarm.yaml", g_src);
  ea_arm_t arm;
  ea_error_t e = {0};
  if (ea_arm_load(path, &arm, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  const double a0 = -60 * DEG, a1 = 10 * DEG, Lin = arm.act.cable_length_min;
  ea_workspace_settings_t set, fine;
  ea_workspace_settings_default(&set);
  fine = set;
  fine.samples = 141;
  fine.depth_samples = 16;
  fine.tol = 1e-13;
  char what[300];

  /* (1) the paper's region (no actuator limits): area against Simpson in
     polar coordinates on the reference edge, Richardson-extrapolated */
  for (int g = 0; g < 2; ++g) {
    const double gamma = g ? 0.5 : 0.0;
    set.limits = fine.limits = 0;
    ea_workspace_metrics_t m, mf;
    const int st = ws_metrics(&arm, gamma, &set, &m, &e);
    const int stf = ws_metrics(&arm, gamma, &fine, &mf, &e);
    ea_test_true(st == 0 && stf == 0, "workspace metrics (no limits) computed");
    if (st || stf) {
      printf("  %s\n", e.msg);
      continue;
    }
    ea_shooter_t *rs = ref_shooter(&arm, gamma);
    ref_ctx_t c = {rs, &arm, Lin, 0, 0};
    double dS;
    const double ref = simpson_rich(ref_integrand, &c, a0, a1, 256, &dS);
    printf("  gamma %g: area %.13f, reference %.13f (|S256 - S128| = %.2g), %ld solves\n", gamma,
           m.area, ref, dS, m.solves);
    /* measured: 2e-12 (the two integrators differ by ~5e-12 m in L_c) */
    snprintf(what, sizeof what, "gamma %g: area = polar Simpson on an independent integrator",
             gamma);
    ea_test_abs(m.area, ref, 1e-10, what);
    snprintf(what, sizeof what, "gamma %g: area converged (141 samples, tol 1e-13)", gamma);
    ea_test_abs(m.area, mf.area, 1e-12, what);
    snprintf(what, sizeof what, "gamma %g: reach, x_max, y_min converged", gamma);
    ea_test_true(fabs(m.reach.value - mf.reach.value) < 1e-12 &&
                     fabs(m.x_max.value - mf.x_max.value) < 1e-12 &&
                     fabs(m.y_min.value - mf.y_min.value) < 1e-12,
                 what);
    /* the old definition: the chord polygon of the 71 edge points */
    if (g == 0) {
      const int n = 71;
      double poly = 0, xp = 0, yp = 0, x0 = 0, y0 = 0;
      for (int k = 0; k < 2 * n; ++k) {
        const double a =
            k < n ? a0 + (a1 - a0) * k / (n - 1) : a0 + (a1 - a0) * (2 * n - 1 - k) / (n - 1);
        const double L = k < n ? ref_edge(rs, a, NULL, NULL) : Lin;
        const double x = arm.x_c + L * cos(a), y = arm.y_c + L * sin(a);
        if (k == 0) {
          x0 = x;
          y0 = y;
        } else {
          poly += xp * y - x * yp;
        }
        xp = x;
        yp = y;
      }
      poly = 0.5 * fabs(poly + xp * y0 - x0 * yp);
      printf("  the 71-point chord polygon misses the area by %.3g m^2\n", ref - poly);
      ea_test_true(ref - poly > 1e-6,
                   "the chord polygon of 71 points is biased low by > 1e-6 m^2 (the old area)");
      /* x_max: interior maximum of the outer edge, by golden section */
      double amax;
      const double xm = -golden(rs, &arm, -30 * DEG, 10 * DEG, &amax);
      printf("  x_max %.13f at %.6f deg; golden section %.13f at %.6f deg\n", m.x_max.value,
             m.x_max.alpha / DEG, xm, amax / DEG);
      ea_test_abs(m.x_max.value, xm, 1e-10, "x_max = golden-section maximum on the reference edge");
      ea_test_true(m.x_max.bound == EA_WS_OUTER && m.x_max.at_end == EA_WS_NONE,
                   "x_max: interior, on the outer edge");
      /* reach and y_min: at the range's start, where the edge leaves the range */
      const double Le = ref_edge(rs, a0, NULL, NULL),
                   Le2 = ref_edge(rs, a0 + 0.5 * DEG, NULL, NULL);
      const double r0 = hypot(arm.x_c + Le * cos(a0), arm.y_c + Le * sin(a0));
      const double r1 =
          hypot(arm.x_c + Le2 * cos(a0 + 0.5 * DEG), arm.y_c + Le2 * sin(a0 + 0.5 * DEG));
      ea_test_abs(m.reach.value, r0, 1e-10, "max_reach = edge distance at alpha_min (reference)");
      ea_test_abs(m.y_min.value, arm.y_c + Le * sin(a0), 1e-10, "y_min = edge height at alpha_min");
      ea_test_true(r1 < r0 && m.reach.at_end == EA_WS_ALPHA_MIN &&
                       m.y_min.at_end == EA_WS_ALPHA_MIN,
                   "reach decreases into the range: the extremum is flagged as the range's");
    }
    ea_shooter_free(rs);
  }

  /* (2) within the arm's limits, gamma 0.5: the shoulder torque limit cuts
     the region; independent: the corner by bisection on the edge torque,
     the torque boundary by regula falsi on L_c, Simpson on both pieces */
  {
    set.limits = fine.limits = 1;
    ea_workspace_metrics_t m, mf;
    const int st = ws_metrics(&arm, 0.5, &set, &m, &e);
    const int stf = ws_metrics(&arm, 0.5, &fine, &mf, &e);
    ea_test_true(st == 0 && stf == 0, "workspace metrics (limits) computed");
    ea_shooter_t *rs = ref_shooter(&arm, 0.5);
    const double tq = arm.act.shoulder_torque_max;
    /* the corner: the edge torque reaches -tq between 0 and 10 deg */
    double lo = 0, hi = 10 * DEG;
    ea_statics_settings_t ss = tight();
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (lo + hi);
      ea_statics_solution_t sol;
      ea_statics_edge(rs, mid, &ss, NULL, &sol, NULL);
      if (sol.shoulder_torque + tq < 0)
        lo = mid;
      else
        hi = mid;
    }
    const double ac = 0.5 * (lo + hi);
    ref_ctx_t ct = {rs, &arm, Lin, tq, 1}, ce = {rs, &arm, Lin, tq, 0};
    double d1, d2;
    const double ref = simpson_rich(ref_integrand, &ct, a0, ac, 128, &d1) +
                       simpson_rich(ref_integrand, &ce, ac, a1, 32, &d2);
    const double Lc = ref_edge(rs, ac, NULL, NULL);
    printf("  limits, gamma 0.5: area %.13f, reference %.13f (|dS| %.2g, %.2g); corner %.9f deg "
           "(metric x_max at %.9f deg); %d pieces, %ld solves\n",
           m.area, ref, d1, d2, ac / DEG, m.x_max.alpha / DEG, m.pieces, m.solves);
    /* measured: 3e-12 */
    ea_test_abs(m.area, ref, 1e-10, "area within the torque limit = independent two-piece Simpson");
    ea_test_abs(m.area, mf.area, 1e-12,
                "area within the limits converged (141 samples, tol 1e-13)");
    ea_test_abs(m.x_max.value, arm.x_c + Lc * cos(ac), 1e-10,
                "x_max at the corner where the outer edge meets the torque limit");
    ea_test_true((m.x_max.bound == EA_WS_OUTER && m.x_max.bound2 == EA_WS_TORQUE_NEG) &&
                     (m.bounds & (1u << EA_WS_TORQUE_NEG)),
                 "x_max names both boundaries of the corner");
    const double Lt = ref_torque_boundary(rs, &arm, a0, tq);
    ea_test_abs(m.reach.value, hypot(arm.x_c + Lt * cos(a0), arm.y_c + Lt * sin(a0)), 1e-10,
                "max_reach on the torque limit at alpha_min (regula falsi reference)");
    ea_test_true(m.reach.bound == EA_WS_TORQUE_NEG, "max_reach lies on the torque limit");
    ea_shooter_free(rs);
  }

  /* (3) edge points are checked against the shoulder range: at -72 deg the
     T = 0 shoulder angle is below -30 deg */
  {
    ea_shooter_t *sh = ref_shooter(&arm, 0.0);
    const double al[2] = {-72 * DEG, -50 * DEG};
    ea_config_point_t pts[2];
    ea_workspace_outer(sh, al, 2, pts);
    printf("  edge at -72 deg: theta0 %.4f rad, admissible %d (%s)\n", pts[0].theta0,
           pts[0].admissible, pts[0].reason);
    ea_test_true(pts[0].theta0 < arm.act.shoulder_angle_min && !pts[0].admissible &&
                     strstr(pts[0].reason, "shoulder angle") && pts[1].admissible,
                 "outer edge point beyond the shoulder limit is not admissible (and says why)");
    ea_shooter_free(sh);
  }

  /* (4) ill-posed regions are errors, not NaN */
  {
    ea_workspace_metrics_t m;
    ea_workspace_settings_t b = set;
    b.inner_cable_length = 5.0;
    b.limits = 0;
    int st = ws_metrics(&arm, 0.0, &b, &m, &e);
    printf("  inner 5 m: %s\n", e.msg);
    ea_test_true(st == EA_ERR_INADMISSIBLE && strstr(e.msg, "empty") && isnan(m.area),
                 "inner cable beyond the outer edge: EA_ERR_INADMISSIBLE, region empty");
    b = set;
    b.alpha_min = -180 * DEG;
    b.alpha_max = 180 * DEG;
    st = ws_metrics(&arm, 0.0, &b, &m, &e);
    ea_test_true(st == EA_ERR_ARG && strstr(e.msg, "(-90, 90)"), "full-turn range refused");
    b = set;
    b.alpha_min = -80 * DEG;
    st = ws_metrics(&arm, 0.0, &b, &m, &e);
    printf("  -80 deg: %s\n", e.msg);
    ea_test_true(st == EA_ERR_INADMISSIBLE && strstr(e.msg, "does not bound"),
                 "steep range where T < 0 inside the edge refused");
  }
}

/* ---- the Fig. 3 study ---------------------------------------------------------- */

static void test_fig3(void) {
  char path[1200];
  snprintf(path, sizeof path, "%s/problems/examples/studies/fig3.yaml", g_src);
  ea_study_t s;
  ea_error_t e = {0};
  ea_status_t st = ea_study_load(path, NULL, &s, &e);
  ea_test_true(st == EA_OK, "fig3.yaml loads");
  if (st) {
    printf("  %s\n", e.msg);
    return;
  }
  ea_test_true(s.n_cases == 4 && s.n_axes == 1 && s.axis[0].param == EA_STUDY_PAYLOAD_FACTOR,
               "fig3: 4 payload factors");
  ea_test_abs(s.workspace.alpha_min * 180 / M_PI, -60, 1e-12, "fig3: alpha from -60 deg");
  ea_test_abs(s.workspace.alpha_max * 180 / M_PI, 10, 1e-12, "fig3: alpha to 10 deg");
  ea_study_info_t info;
  char *csv = run(&s, 0, 1, 1, NULL, 0, &info, &st);
  ea_test_true(csv && st == EA_OK && info.cases_failed == 0, "fig3: every case solved");
  if (!csv) return;
  double reach[4], area[4];
  for (int c = 0; c < 4; ++c) {
    reach[c] = metric(csv, c, "max_reach", NULL);
    area[c] = metric(csv, c, "area", NULL);
    printf("  gamma = %.2f: max reach %.5f m, area %.5f m^2\n", s.axis[0].values[c], reach[c],
           area[c]);
  }
  int dec = 1;
  for (int c = 1; c < 4; ++c)
    dec &= reach[c] < reach[c - 1] && area[c] < area[c - 1];
  ea_test_true(dec, "fig3: reach and area decrease strictly as the payload grows");
  /* Independently of the study code: at every cable angle the outer edge
   * point of gamma = 0.5 lies inside (closer to the cable root than) that
   * of gamma = 0, from separate edge solves. */
  ea_shooter_t *sh = NULL;
  ea_shooter_alloc(&s.arm, NULL, &sh, NULL);
  int inward = sh != NULL;
  for (int k = 0; sh && k <= 14; ++k) {
    const double a = (-60.0 + 5.0 * k) * M_PI / 180;
    double d[2];
    for (int g = 0; g < 2; ++g) {
      ea_load_t ld = {ea_arm_tip_mass(&s.arm, ea_arm_payload_from_factor(&s.arm, g ? 0.5 : 0.0))};
      ea_shooter_set_load(sh, &ld);
      ea_statics_solution_t sol;
      if (ea_statics_edge(sh, a, NULL, NULL, &sol, NULL)) {
        inward = 0;
        d[g] = NAN;
        continue;
      }
      d[g] = sol.cable_length;
    }
    if (!(d[1] < d[0])) inward = 0;
  }
  ea_shooter_free(sh);
  ea_test_true(inward,
               "fig3: outer edge of gamma 0.5 inside gamma 0 at every angle (separate solves)");
  free(csv);
  ea_study_free(&s);
}

/* ---- threads, shards, merge ------------------------------------------------------ */

static void test_threads_shards(void) {
  ea_study_t s;
  if (load(k_mixed, &s)) {
    ea_test_true(0, "mixed study loads");
    return;
  }
  ea_test_true(s.n_cases == 12, "mixed: 6 x 2 = 12 cases");
  char *c1 = run(&s, 1, 1, 1, NULL, 0, NULL, NULL);
  char *c2 = run(&s, 2, 1, 1, NULL, 0, NULL, NULL);
  char *c3 = run(&s, 3, 1, 1, NULL, 0, NULL, NULL);
  ea_test_true(c1 && c2 && c3, "runs with 1, 2, 3 threads");
  if (!c1 || !c2 || !c3) return;
  ea_test_true(!strcmp(c1, c2), "CSV with 2 threads byte-identical to 1 thread");
  ea_test_true(!strcmp(c1, c3), "CSV with 3 threads byte-identical to 1 thread");
  /* order: case ids ascending, first parameter slowest */
  static const char hdr[] =
      "case_id,study,study_key,payload_factor,EI_Nm2,metric,value,unit,status,message\n";
  ea_test_true(!strncmp(c1, hdr, sizeof hdr - 1),
               "header: case_id, study, study_key, parameters (payload first), metric, value, "
               "unit, status, message");
  {
    /* case 3's row against a direct call for the case's arm and payload */
    ea_arm_t arm;
    double kg, g;
    ea_workspace_settings_t ws;
    ea_workspace_settings_default(&ws);
    ws.samples = s.workspace.points;
    ea_workspace_metrics_t m;
    ea_error_t e = {0};
    ea_study_case_arm(&s, 3, &arm, &kg, &g, &e);
    ea_shooter_t *sh = NULL;
    ea_shooter_alloc(&arm, NULL, &sh, &e);
    ea_load_t ld = {ea_arm_tip_mass(&arm, kg)};
    if (sh) ea_shooter_set_load(sh, &ld);
    const int st = sh ? (int)ea_workspace_metrics(sh, &ws, &m, &e) : -1;
    ea_shooter_free(sh);
    ea_test_true(st == 0, "case 3: direct workspace metrics");
    if (!st) {
      ea_test_rel(metric(c1, 3, "area", NULL), m.area, 1e-11,
                  "case 3 (gamma 0.1, EI 0.705): area row = direct call with the case's arm");
      ea_test_rel(metric(c1, 3, "max_reach", NULL), m.reach.value, 1e-11,
                  "case 3: max_reach row = direct call");
    }
  }
  {
    /* shards of a different spec (same header, other workspace samples) */
    ea_study_t o;
    if (!load(k_mixed, &o)) {
      o.workspace.points = 22;
      char *a = run(&s, 1, 1, 2, NULL, 0, NULL, NULL), *b = run(&o, 1, 2, 2, NULL, 0, NULL, NULL);
      const char *texts[2] = {a ? a : "", b ? b : ""};
      size_t lens[2] = {strlen(texts[0]), strlen(texts[1])};
      char *m = NULL;
      ea_error_t e = {0};
      ea_status_t st =
          ea_study_merge(texts, lens, (const char *[]){"a.csv", "b.csv"}, 2, 12, &m, NULL, &e);
      printf("  shards of two specs: %s\n", e.msg);
      ea_test_true(a && b && st == EA_ERR_INPUT && strstr(e.msg, "different specs"),
                   "merge refuses shards of different specs (study_key differs)");
      free(m);
      free(a);
      free(b);
      ea_study_free(&o);
    }
  }

  for (int n = 2; n <= 5; n += 3) {
    const char *texts[5];
    size_t lens[5];
    static const char *const shard_names[5] = {"s1", "s2", "s3", "s4", "s5"};
    const char *names[5];
    char *sh[5] = {0};
    long total = 0;
    for (int k = 1; k <= n; ++k) {
      ea_study_info_t info;
      sh[k - 1] = run(&s, 2, k, n, NULL, 0, &info, NULL);
      total += info.cases_shard;
      texts[n - k] = sh[k - 1] ? sh[k - 1] : ""; /* reversed order on purpose */
      lens[n - k] = strlen(texts[n - k]);
      names[n - k] = shard_names[k - 1];
    }
    char *m = NULL;
    size_t ml = 0;
    ea_error_t e = {0};
    ea_status_t st = ea_study_merge(texts, lens, names, n, 12, &m, &ml, &e);
    char what[96];
    snprintf(what, sizeof what, "%d shards: %ld cases in all, merged = single run byte for byte", n,
             total);
    ea_test_true(st == EA_OK && total == 12 && m && !strcmp(m, c1), what);
    if (st) printf("  %s\n", e.msg);
    free(m);
    /* merge refuses a missing shard and a duplicated one */
    st = ea_study_merge(texts, lens, names, n - 1, 12, &m, &ml, &e);
    printf("  missing shard: %s\n", e.msg);
    ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "missing"), "merge: missing cases named");
    const char *dup[2] = {texts[0], texts[0]};
    size_t dl[2] = {lens[0], lens[0]};
    st = ea_study_merge(dup, dl, names, 2, 0, &m, &ml, &e);
    printf("  duplicate shard: %s\n", e.msg);
    ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "is in"), "merge: duplicated case named");
    for (int k = 0; k < n; ++k)
      free(sh[k]);
  }
  const char *bad[2] = {c1,
                        "case_id,study,study_key,payload_kg,metric,value,unit,status,message\n"};
  size_t bl[2] = {strlen(bad[0]), strlen(bad[1])};
  char *m = NULL;
  ea_error_t e = {0};
  ea_status_t st = ea_study_merge(bad, bl, (const char *[]){"a.csv", "b.csv"}, 2, 0, &m, NULL, &e);
  printf("  other header: %s\n", e.msg);
  ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "b.csv:1:1"), "merge: header mismatch named");
  free(c1);
  free(c2);
  free(c3);
  ea_study_free(&s);
}

/* ---- failed cases ---------------------------------------------------------------- */

static void test_failed_case(void) {
  ea_study_t s;
  if (load(k_mixed, &s)) return;
  ea_study_info_t info;
  ea_status_t st;
  char *c = run(&s, 2, 1, 1, NULL, 0, &info, &st);
  ea_test_true(c && st == EA_OK, "a study with failing cases completes");
  if (!c) return;
  char s1[32] = "", s2[32] = "";
  int others_ok = 1, all_fail = 1;
  for (long k = 0; k < 12; ++k) {
    metric(c, k, "frequency_c1_mode1", s1);
    const double f2 = metric(c, k, "frequency_c2_mode2", s2);
    others_ok &= !strcmp(s1, "ok") && isfinite(metric(c, k, "max_reach", NULL));
    all_fail &= !strcmp(s2, "EA_ERR_INADMISSIBLE") && isnan(f2);
  }
  ea_test_true(all_fail, "configuration outside the workspace: every case records "
                         "EA_ERR_INADMISSIBLE with an empty value");
  ea_test_true(others_ok, "the other metrics of the failing cases still computed");
  ea_test_true(strstr(c, "configuration 2 (L_c = 0.85 m, alpha = 0 deg)") != NULL,
               "the reason names the configuration");
  ea_test_true(info.cases_failed == 12 && info.rows_failed == 24,
               "info counts 12 failed cases, 24 failed rows");
  /* min_time without the planner callback: recorded as not implemented */
  ea_study_t m;
  const char *mt = "grid: {payload_factor: [0]}\nmetrics: {min_time: {task: x.yaml}}\n";
  ea_error_t e = {0};
  if (ea_study_load_string("mt.yaml", mt, strlen(mt), NULL, &m, &e) == EA_OK) {
    char *r = run(&m, 1, 1, 1, NULL, 0, &info, &st);
    ea_test_true(r && strstr(r, "min_time_duration,,s,EA_ERR_NOTIMPL"),
                 "min_time without the planner: EA_ERR_NOTIMPL row");
    free(r);
    ea_study_free(&m);
  } else {
    ea_test_true(0, e.msg);
  }
  free(c);
  ea_study_free(&s);
}

/* ---- resume ---------------------------------------------------------------------- */

static long journal_cases(const char *path) {
  FILE *fp = fopen(path, "r");
  if (!fp) return 0;
  char line[4096];
  long n = 0;
  while (fgets(line, sizeof line, fp))
    n += !strncmp(line, "#case ", 6);
  fclose(fp);
  return n;
}

static void slow_progress(void *d, long c, long done, long todo, int failed) {
  (void)d, (void)c, (void)done, (void)todo, (void)failed;
  struct timespec ts = {0, 20 * 1000000L};
  nanosleep(&ts, NULL);
}

static void test_resume(void) {
  ea_study_t s;
  if (load(k_mixed, &s)) return;
  char *ref = run(&s, 1, 1, 1, NULL, 0, NULL, NULL);
  char ck[400];
  ea_study_info_t info;
  ea_status_t st;

  /* (a) injected stop after 5 cases, then resume */
  snprintf(ck, sizeof ck, "%s/a.journal", g_tmp);
  unlink(ck);
  char *c = run(&s, 2, 1, 1, ck, 5, &info, &st);
  ea_test_true(st == EA_ERR_INTERRUPTED && !c && info.cases_computed == 5,
               "stop hook: interrupted after 5 cases, no CSV");
  ea_test_true(journal_cases(ck) == 5, "journal holds 5 cases");
  c = run(&s, 3, 1, 1, ck, 0, &info, &st);
  printf("  resume: skipped %ld, computed %ld\n", info.cases_skipped, info.cases_computed);
  ea_test_true(st == EA_OK && info.cases_skipped == 5 && info.cases_computed == 7,
               "resume skips the 5 finished cases and computes 7");
  ea_test_true(c && ref && !strcmp(c, ref), "resumed CSV byte-identical to uninterrupted run");
  free(c);
  /* a finished journal: nothing recomputed */
  c = run(&s, 2, 1, 1, ck, 0, &info, &st);
  ea_test_true(c && !strcmp(c, ref) && info.cases_computed == 0 && info.cases_skipped == 12,
               "rerun on a complete journal recomputes nothing");
  free(c);

  /* (b) torn tail: half a block appended, as a crash mid-write leaves it */
  FILE *fp = fopen(ck, "r+b");
  if (fp) {
    fseek(fp, 0, SEEK_END);
    const long size = ftell(fp);
    /* cut the last block in half: drop its trailer and half its rows */
    fclose(fp);
    if (truncate(ck, size - 200) != 0) printf("  truncate failed\n");
  }
  c = run(&s, 2, 1, 1, ck, 0, &info, &st);
  printf("  torn tail: dropped %ld bytes, recomputed %ld\n", info.journal_dropped_bytes,
         info.cases_computed);
  ea_test_true(c && !strcmp(c, ref) && info.journal_dropped_bytes > 0 && info.cases_computed == 1 &&
                   info.cases_skipped == 11,
               "torn journal tail dropped, that case recomputed, CSV identical");
  free(c);
  /* a corrupted byte inside a block: CRC catches it, the rest is recomputed */
  fp = fopen(ck, "r+b");
  if (fp) {
    fseek(fp, 300, SEEK_SET);
    int ch = fgetc(fp);
    fseek(fp, 300, SEEK_SET);
    fputc(ch == '1' ? '2' : '1', fp);
    fclose(fp);
  }
  c = run(&s, 2, 1, 1, ck, 0, &info, &st);
  ea_test_true(c && !strcmp(c, ref) && info.cases_skipped < 12,
               "corrupted block: CRC mismatch, recomputed, CSV identical");
  free(c);

  /* (c) a journal of another study is refused */
  ea_study_t o;
  if (!load(k_mixed, &o)) {
    o.workspace.points = 22;
    ea_error_t e = {0};
    ea_study_settings_t set;
    ea_study_settings_default(&set);
    set.checkpoint = ck;
    char *x = NULL;
    st = ea_study_run(&o, &set, &x, NULL, &info, &e);
    printf("  other study: %s\n", e.msg);
    ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "another study"),
                 "journal of another study refused");
    free(x);
    ea_study_free(&o);
  }

  /* (d) kill -9 in the middle of a run (fsync on), then resume */
  snprintf(ck, sizeof ck, "%s/d.journal", g_tmp);
  unlink(ck);
  pid_t pid = fork();
  if (pid == 0) {
    ea_study_settings_t set;
    ea_study_settings_default(&set);
    set.threads = 2;
    set.checkpoint = ck;
    set.progress = slow_progress; /* keep the child alive long enough */
    char *x = NULL;
    ea_study_run(&s, &set, &x, NULL, NULL, NULL);
    _exit(0);
  }
  long seen = 0;
  for (int i = 0; i < 5000 && seen < 4; ++i) {
    struct timespec ts = {0, 1000000L};
    nanosleep(&ts, NULL);
    seen = journal_cases(ck);
  }
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  const long at_kill = journal_cases(ck);
  printf("  killed with %ld cases in the journal\n", at_kill);
  ea_test_true(WIFSIGNALED(status) && at_kill >= 4 && at_kill < 12,
               "child killed (SIGKILL) halfway through");
  c = run(&s, 2, 1, 1, ck, 0, &info, &st);
  printf("  after kill -9: skipped %ld, computed %ld\n", info.cases_skipped, info.cases_computed);
  ea_test_true(c && ref && !strcmp(c, ref) && info.cases_skipped == at_kill &&
                   info.cases_computed == 12 - at_kill,
               "resumed after kill -9: finished cases skipped, CSV byte-identical");
  free(c);
  unlink(ck);
  snprintf(ck, sizeof ck, "%s/a.journal", g_tmp);
  unlink(ck);
  free(ref);
  ea_study_free(&s);
}

/* ---- the planner metric ------------------------------------------------------------ */

static char *run_plan_w(const ea_study_t *s, int threads, ea_study_workers_t workers) {
  ea_study_planner_t *plan = NULL;
  ea_error_t e = {0};
  ea_study_settings_t set;
  ea_study_settings_default(&set);
  if (ea_study_use_planner(s, NULL, &set, &plan, &e)) {
    printf("  plan: %s\n", e.msg);
    return NULL;
  }
  set.threads = threads;
  set.workers = workers;
  char *c = NULL;
  ea_study_info_t info;
  ea_study_run(s, &set, &c, NULL, &info, &e);
  /* auto: forked workers for a planner metric on more than one worker */
  if (c && info.processes != (workers == EA_STUDY_WORKERS_PROCESSES ||
                              (workers == EA_STUDY_WORKERS_AUTO && info.threads > 1))) {
    printf("  run: %d workers, processes %d\n", info.threads, info.processes);
    free(c);
    c = NULL;
  }
  ea_study_planner_free(plan);
  return c;
}

/* A C caller of the public API alone (ea_study.h, ea_planner.h): ea_study_run without the
 * planner reports min_time as not implemented; after ea_study_use_planner it reports the
 * duration of an independent cold plan of the case's task, and the task's content key is
 * part of the study key. */
static void test_public_planner(void) {
  char text[1400], task_path[1100];
  snprintf(task_path, sizeof task_path, "%s/problems/examples/paper-line.yaml", g_src);
  snprintf(text, sizeof text, "grid: {payload_factor: [0.25]}\nmetrics: {min_time: {task: %s}}\n",
           task_path);
  ea_study_t s;
  ea_error_t e = {0};
  if (ea_study_load_string("pub.yaml", text, strlen(text), NULL, &s, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  ea_study_settings_t set;
  ea_study_settings_default(&set);
  set.threads = 1;
  char key0[9], key1[9], st0[32] = "", st1[32] = "";
  ea_study_key(&s, &set, key0);
  char *c0 = NULL, *c1 = NULL;
  ea_study_info_t info;
  ea_study_run(&s, &set, &c0, NULL, &info, &e);
  if (c0) metric(c0, 0, "min_time_duration", st0);
  ea_test_true(c0 && !strcmp(st0, "EA_ERR_NOTIMPL"),
               "public API: min_time without ea_study_use_planner is EA_ERR_NOTIMPL");
  ea_study_planner_t *pl = NULL;
  const ea_status_t ust = ea_study_use_planner(&s, NULL, &set, &pl, &e);
  ea_test_true(!ust && pl && set.min_time && set.min_time_key && !set.at_rest,
               "ea_study_use_planner: the min_time callback and its task's key registered");
  ea_study_key(&s, &set, key1);
  ea_test_true(strcmp(key0, key1) != 0, "the min_time task's content key is in the study key");
  double d = NAN;
  if (!ust && !ea_study_run(&s, &set, &c1, NULL, &info, &e))
    d = metric(c1, 0, "min_time_duration", st1);
  ea_study_planner_free(pl);
  /* the same plan outside the study: the task with the case's beam, cable root and payload,
   * from cold */
  ea_arm_t arm;
  double kg = NAN, g = NAN, dref = NAN;
  ea_task_t t;
  ea_planner_t *p = NULL;
  ea_plan_info_t pi;
  if (!ea_study_case_arm(&s, 0, &arm, &kg, &g, &e) && !ea_task_load(task_path, NULL, &t, &e)) {
    t.arm.rho = arm.rho, t.arm.m_hand = arm.m_hand, t.arm.length = arm.length;
    t.arm.EI = arm.EI, t.arm.x_c = arm.x_c, t.arm.y_c = arm.y_c;
    t.payload_kg = kg;
    t.payload_factor = g;
    if (!ea_task_check(&t, &e) && !ea_planner_alloc(&t, &p, &e) &&
        !ea_planner_solve(p, EA_PLAN_COLD, NULL, &pi, &e))
      dref = pi.duration_s;
  }
  ea_planner_free(p);
  printf("  public API: min_time %.9f s (%s), an independent cold plan %.9f s\n", d, st1, dref);
  ea_test_true(!strcmp(st1, "ok") && isfinite(d) && fabs(d - dref) <= 1e-9 * dref,
               "public API: min_time through ea_study_use_planner is the duration of the "
               "case's cold plan");
  free(c0);
  free(c1);
  ea_study_free(&s);
}

static char *run_plan(const ea_study_t *s, int threads) {
  return run_plan_w(s, threads, EA_STUDY_WORKERS_AUTO);
}

static void test_min_time(void) {
  char text[1400];
  snprintf(text, sizeof text,
           "grid: {payload_factor: [0, 0.25, 3]}\n"
           "metrics: {min_time: {task: %s/problems/examples/paper-line.yaml}}\n",
           g_src);
  ea_study_t s;
  ea_error_t e = {0};
  if (ea_study_load_string("mt.yaml", text, strlen(text), NULL, &s, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  char *c[2] = {run_plan(&s, 1), run_plan(&s, 2)};
  ea_test_true(c[0] && c[1] && !strcmp(c[0], c[1]),
               "min_time: 1 worker and 2 worker processes byte-identical");
  char *ct = run_plan_w(&s, 2, EA_STUDY_WORKERS_THREADS);
  ea_test_true(c[0] && ct && !strcmp(c[0], ct),
               "min_time: 2 threads (planner calls serialised) byte-identical");
  free(ct);
  if (c[0]) {
    char st0[32] = "", st2[32] = "";
    const double d0 = metric(c[0], 0, "min_time_duration", st0);
    const double d1 = metric(c[0], 1, "min_time_duration", NULL);
    metric(c[0], 2, "min_time_duration", st2);
    /* Lower bound from the spool limits alone: the cable length grows
       monotonically along the line (eqs. 18-19), so no plan beats the
       bang-bang profile with the limits tightened by the resample margin:
       t = dL (1 + m) / v + v / a. */
    const ea_arm_t *a = &s.arm;
    ea_task_t tdef;
    ea_task_init(&tdef, a);
    const double dL = hypot(0.6 - a->x_c, -0.2 - a->y_c) - hypot(0.3 - a->x_c, -0.2 - a->y_c);
    const double v = a->act.cable_speed_max, acc = a->act.cable_accel_max,
                 m = tdef.limits.resample_margin;
    const double tb = dL * (1 + m) / v + v / acc;
    printf("  paper line: durations %.6f s (gamma 0), %.6f s (gamma 0.25); spool bound %.6f s; "
           "gamma 3: %s\n",
           d0, d1, tb, st2);
    /* measured: 1.00023 tb for both payloads: only the spool binds */
    ea_test_true(!strcmp(st0, "ok") && d0 >= tb && d0 <= tb * 1.001 && d1 >= tb && d1 <= tb * 1.001,
                 "min_time on the paper line: within 0.1% above the spool's bang-bang bound, "
                 "for both payloads (only the spool limits bind there)");
    ea_test_true(strcmp(st2, "ok") != 0,
                 "min_time: payload factor 3 (line outside the workspace) recorded as failed");
  }
  free(c[0]);
  free(c[1]);
  ea_study_free(&s);

  /* The shipped design study: the shoulder speed limit binds, so the
     duration is at least |theta0(goal) - theta0(start)| (1 + m) / speed,
     with theta0 from the statics of each case's arm, and it varies. */
  char path[1200];
  snprintf(path, sizeof path, "%s/problems/examples/studies/design.yaml", g_src);
  if (ea_study_load(path, NULL, &s, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  char *d = run_plan(&s, 2);
  ea_test_true(d != NULL, "design study runs");
  double lo = INFINITY, hi = -INFINITY, worst = 0;
  int ok = d != NULL;
  for (long k = 0; d && k < s.n_cases; ++k) {
    ea_arm_t arm;
    double kg, g;
    ea_study_case_arm(&s, k, &arm, &kg, &g, &e);
    ea_shooter_t *sh = NULL;
    ea_shooter_alloc(&arm, NULL, &sh, &e);
    ea_load_t ld = {ea_arm_tip_mass(&arm, kg)};
    ea_shooter_set_load(sh, &ld);
    ea_statics_solution_t s0, s1;
    ea_statics_problem_t p0 = ea_statics_problem_cable(0.40, -0.9),
                         p1 = ea_statics_problem_cable(0.40, -0.1);
    const int sst = ea_statics_solve(sh, &p0, NULL, NULL, &s0, NULL) ||
                    ea_statics_solve(sh, &p1, NULL, NULL, &s1, NULL);
    ea_shooter_free(sh);
    char st[32] = "";
    const double dur = metric(d, k, "min_time_duration", st);
    /* bang-bang in theta0 under the shoulder speed and acceleration limits (tightened by
     * the default resample margin m) */
    ea_task_t tdef;
    ea_task_init(&tdef, &arm);
    const double m = tdef.limits.resample_margin;
    const double dth = fabs(s1.p[EA_P_THETA0] - s0.p[EA_P_THETA0]) * (1 + m);
    const double wv = arm.act.shoulder_speed_max, wa = arm.act.shoulder_accel_max;
    const double tb = dth >= wv * wv / wa ? dth / wv + wv / wa : 2.0 * sqrt(dth / wa);
    printf("  design case %ld (gamma %g, EI %g): %.6f s, shoulder bound %.6f s (ratio %.5f)\n", k,
           g, arm.EI, dur, tb, dur / tb);
    ok &= !sst && !strcmp(st, "ok") && dur >= tb && dur <= tb * 1.001;
    worst = fmax(worst, dur / tb);
    lo = fmin(lo, dur);
    hi = fmax(hi, dur);
  }
  /* measured: ratio 1.0001 to 1.0003 of the bang-bang bound under the shoulder speed and
     acceleration limits; tolerance 0.1 % */
  ea_test_true(ok, "design study: every duration within 0.1% above the shoulder's bang-bang "
                   "bound");
  printf("  design durations %.6f to %.6f s (spread %.1f%%), worst ratio %.5f\n", lo, hi,
         100 * (hi - lo) / lo, worst);
  ea_test_true((hi - lo) / lo > 0.1,
               "design study: the duration changes with payload and EI by more than 10%");
  free(d);
  ea_study_free(&s);
}

/* ---- worker processes --------------------------------------------------------------- */

static pid_t g_main_pid;
static double g_kill_gamma = NAN; /* a worker process computing this payload factor dies */
static int g_kill_exit;           /* 0: by SIGKILL, 1: by _exit(7) */

/* A stand-in for the planner (cheap, deterministic): 1 + gamma^2 s. In a worker process
 * the case of payload factor g_kill_gamma ends the process instead. */
static ea_status_t fake_min_time(void *data, const ea_study_t *s, const ea_arm_t *arm, double kg,
                                 double gamma, double *dur, char *msg, size_t len) {
  (void)data, (void)s, (void)arm, (void)kg;
  if (getpid() != g_main_pid && gamma == g_kill_gamma) {
    if (g_kill_exit) _exit(7);
    raise(SIGKILL);
  }
  *dur = 1.0 + gamma * gamma;
  snprintf(msg, len, "stand-in");
  return EA_OK;
}

static char *run_fake(const ea_study_t *s, int threads, ea_study_workers_t workers,
                      const char *ckpt, long stop_after, ea_study_info_t *info, ea_status_t *st) {
  ea_study_settings_t set;
  ea_study_settings_default(&set);
  set.threads = threads;
  set.workers = workers;
  set.checkpoint = ckpt;
  set.stop_after = stop_after;
  set.fsync = 0;
  set.min_time = fake_min_time;
  set.min_time_key = "stand-in";
  char *csv = NULL;
  ea_error_t e = {0};
  *st = ea_study_run(s, &set, &csv, NULL, info, &e);
  if (*st && *st != EA_ERR_INTERRUPTED) printf("  run: %s\n", e.msg);
  return csv;
}

/* No child process left, running or zombie. */
static int no_children(void) {
  errno = 0;
  return waitpid(-1, NULL, WNOHANG) == -1 && errno == ECHILD;
}

/* The CSV without the rows of case c. */
static char *drop_case(const char *csv, long c) {
  char *out = malloc(strlen(csv) + 1), *o = out;
  char pre[32];
  const int n = snprintf(pre, sizeof pre, "%ld,", c);
  for (const char *p = csv; *p;) {
    const char *e = strchr(p, '\n');
    const size_t len = e ? (size_t)(e - p) + 1 : strlen(p);
    if (strncmp(p, pre, (size_t)n)) {
      memcpy(o, p, len);
      o += len;
    }
    p += len;
  }
  *o = '\0';
  return out;
}

static void test_workers(void) {
  g_main_pid = getpid();
  const char *text = "name: fake\ngrid: {payload_factor: '0:0.1:0.9'}\n"
                     "metrics:\n  min_time: {task: x.yaml}\n"
                     "  path: {start: [0.3, -0.2], goal: [0.6, -0.2], steps: 4}\n";
  ea_study_t s;
  ea_error_t e = {0};
  if (ea_study_load_string("fake.yaml", text, strlen(text), NULL, &s, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  ea_study_info_t i1, i2, i3;
  ea_status_t st1, st2, st3;
  char *ref = run_fake(&s, 1, EA_STUDY_WORKERS_THREADS, NULL, 0, &i1, &st1);
  char *p2 = run_fake(&s, 2, EA_STUDY_WORKERS_AUTO, NULL, 0, &i2, &st2);
  char *p3 = run_fake(&s, 3, EA_STUDY_WORKERS_PROCESSES, NULL, 0, &i3, &st3);
  ea_test_true(ref && !st1 && !i1.processes && i2.processes && i2.threads == 2 && i3.processes,
               "workers: 1 in-process worker; auto with 2 and a planner metric: 2 processes");
  ea_test_true(ref && p2 && p3 && !strcmp(ref, p2) && !strcmp(ref, p3),
               "workers: CSV of 2 and 3 worker processes byte-identical to 1 in-process worker");
  ea_test_true(no_children(), "workers: every worker process waited for (no zombie)");
  free(p2);
  free(p3);

  /* a worker killed (SIGKILL) while computing case 3: that case is one failed row, the
     others are computed (a new worker takes the rest) and equal to the reference */
  for (int how = 0; how < 2 && ref; ++how) {
    g_kill_gamma = 0.3;
    g_kill_exit = how;
    ea_study_info_t info;
    ea_status_t st;
    char *k = run_fake(&s, 2, EA_STUDY_WORKERS_PROCESSES, NULL, 0, &info, &st);
    g_kill_gamma = NAN;
    char *a = k ? drop_case(k, 3) : NULL, *b = drop_case(ref, 3);
    const char *row = k ? strstr(k, "\n3,") : NULL;
    const char *want = how ? "exited with status 7" : "killed by signal 9";
    if (row) printf("  %.*s\n", (int)strcspn(row + 1, "\n"), row + 1);
    char what[200];
    snprintf(what, sizeof what,
             "workers: a worker %s computing case 3: run completes, 1 worker lost, case 3 one "
             "failed row saying so, every other row as in the reference",
             how ? "exiting (status 7)" : "killed (SIGKILL)");
    ea_test_true(st == EA_OK && info.workers_lost == 1 &&
                     info.cases_failed == i1.cases_failed + 1 && row &&
                     !strncmp(row + 1, "3,fake,", 7) && strstr(row, ",case,,-,EA_ERR_BACKEND,") &&
                     strstr(row, want) && !strstr(row + 1, "\n3,") && a && !strcmp(a, b),
                 what);
    ea_test_true(no_children(), "workers: no zombie after a worker died");
    free(a);
    free(b);
    free(k);
  }

  /* stopped after 4 cases (worker processes), resumed from the journal by other processes */
  char ck[400];
  snprintf(ck, sizeof ck, "%s/w.journal", g_tmp);
  unlink(ck);
  ea_study_info_t info;
  ea_status_t st;
  char *c = run_fake(&s, 2, EA_STUDY_WORKERS_PROCESSES, ck, 4, &info, &st);
  ea_test_true(st == EA_ERR_INTERRUPTED && !c && info.cases_computed == 4 && journal_cases(ck) == 4,
               "workers: stop hook after 4 cases, journal holds 4 (written by the parent)");
  c = run_fake(&s, 3, EA_STUDY_WORKERS_PROCESSES, ck, 0, &info, &st);
  ea_test_true(st == EA_OK && c && ref && !strcmp(c, ref) && info.cases_skipped == 4 &&
                   info.cases_computed == 6,
               "workers: resumed by worker processes = uninterrupted run, byte for byte");
  ea_test_true(no_children(), "workers: no zombie after stop and resume");
  free(c);
  unlink(ck);
  free(ref);
  ea_study_free(&s);
}

/* ---- the CLI: task edited between runs, working directory, -o, merge ------------- */

static char g_out[1 << 17];

static int sh_run(const char *fmt, ...) {
  char cmd[8192];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(cmd, sizeof cmd, fmt, ap);
  va_end(ap);
  FILE *p = popen(cmd, "r");
  g_out[0] = '\0';
  if (!p) return -1;
  const size_t n = fread(g_out, 1, sizeof g_out - 1, p);
  g_out[n] = '\0';
  const int rc = pclose(p);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

static int put(const char *dir, const char *name, const char *text) {
  char path[1200];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *fp = fopen(path, "w");
  if (!fp) return -1;
  fputs(text, fp);
  return fclose(fp);
}

static char *slurp(const char *dir, const char *name) {
  char path[1200];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *fp = fopen(path, "rb");
  if (!fp) return NULL;
  char *b = malloc(1 << 20);
  size_t n = b ? fread(b, 1, (1 << 20) - 1, fp) : 0;
  fclose(fp);
  if (b) b[n] = '\0';
  return b;
}

static int exists(const char *dir, const char *name) {
  char path[1200];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  return access(path, F_OK) == 0;
}

static const char *k_task = "name: swing\n"
                            "arm_file: %s/data/elasticarm.yaml\n"
                            "start: {cable_length_m: 0.40, cable_angle_rad: -0.9}\n"
                            "goal: {cable_length_m: 0.40, cable_angle_rad: -0.1}\n"
                            "objective: min_time\n"
                            "knots: %d\n";

static void test_cli(void) {
  const char *bin = getenv("EA_BINARY");
  if (!bin) {
    printf("EA_BINARY not set (run through ctest): CLI checks skipped\n");
    ea_test_true(0, "EA_BINARY set");
    return;
  }
  char dir[600], text[2000];
  /* (a) kill a study, edit the task, resume: refused, not mixed */
  snprintf(dir, sizeof dir, "%s/edit", g_tmp);
  mkdir(dir, 0755);
  snprintf(text, sizeof text, k_task, g_src, 60);
  put(dir, "task.yaml", text);
  put(dir, "spec.yaml",
      "name: edit\ngrid: {payload_factor: [0, 0.1, 0.2]}\nmetrics: {min_time: {task: "
      "task.yaml}}\n");
  int rc = sh_run("cd %s && %s study spec.yaml -o r.csv --threads 1 --stop-after 1 --quiet 2>&1",
                  dir, bin);
  ea_test_true(rc == 1 && exists(dir, "r.csv.journal"), "CLI: interrupted study keeps its journal");
  snprintf(text, sizeof text, k_task, g_src, 40); /* the task changes */
  put(dir, "task.yaml", text);
  rc = sh_run("cd %s && %s study spec.yaml -o r.csv --threads 1 --quiet 2>&1", dir, bin);
  printf("  resume after the task changed: exit %d: %s", rc, g_out);
  ea_test_true(rc == 2 && strstr(g_out, "another study") && !exists(dir, "r.csv"),
               "CLI: resuming after the min_time task changed is refused (exit 2, no CSV)");
  rc = sh_run("cd %s && %s study spec.yaml -o r.csv --threads 1 --quiet --restart 2>&1 && "
              "%s study spec.yaml -o fresh.csv --no-checkpoint --quiet 2>&1",
              dir, bin, bin);
  char *r1 = slurp(dir, "r.csv"), *r2 = slurp(dir, "fresh.csv");
  ea_test_true(rc == 0 && r1 && r2 && !strcmp(r1, r2),
               "CLI: --restart after the edit = a fresh run of the edited task");
  free(r1);
  free(r2);

  /* (b) the same spec run from two working directories: same bytes; a
     failed case's message names the task as written in the spec */
  snprintf(dir, sizeof dir, "%s/cwd", g_tmp);
  mkdir(dir, 0755);
  snprintf(text, sizeof text, k_task, g_src, 40);
  put(dir, "task.yaml", text);
  put(dir, "spec.yaml",
      "name: cwd\ngrid: {payload_factor: [0, 3]}\nmetrics: {min_time: {task: task.yaml}}\n");
  rc = sh_run("cd %s && %s study spec.yaml -o a/r.csv --no-checkpoint --quiet 2>&1", dir, bin);
  const int rc2 = sh_run("cd / && %s study %s/spec.yaml -o %s/b/r.csv --no-checkpoint --quiet 2>&1",
                         bin, dir, dir);
  r1 = slurp(dir, "a/r.csv");
  r2 = slurp(dir, "b/r.csv");
  char *j1 = slurp(dir, "a/r.json"), *j2 = slurp(dir, "b/r.json");
  if (r1) printf("  %s", strstr(r1, "\n1,") ? strstr(r1, "\n1,") + 1 : r1);
  ea_test_true(rc == 0 && rc2 == 0 && r1 && r2 && !strcmp(r1, r2) &&
                   strstr(r1, "\"task not feasible for this case: task.yaml:") &&
                   !strstr(r1, g_tmp),
               "CLI: CSV byte-identical from two working directories; messages name the task "
               "relative to the spec");
  ea_test_true(j1 && j2 && strstr(j1, "\"spec\": \"../spec.yaml\"") &&
                   strstr(j2, "\"spec\": \"../spec.yaml\"") && strstr(j1, "\"csv\": \"r.csv\""),
               "CLI: summary names the spec and CSV relative to itself");
  free(r1);
  free(r2);
  free(j1);
  free(j2);

  /* (c) -o moves the summary and the figures the spec asks for */
  snprintf(dir, sizeof dir, "%s/redir", g_tmp);
  mkdir(dir, 0755);
  put(dir, "spec.yaml",
      "name: redir\ngrid: {payload_factor: [0, 0.5]}\n"
      "metrics: {workspace: {points: 11, limits: false}}\n"
      "outputs: {csv: o/s.csv, summary: o/s.json, figures: o/s}\n");
  rc = sh_run("cd %s && %s study spec.yaml -o red/x.csv --no-checkpoint --quiet 2>&1", dir, bin);
  ea_test_true(rc == 0 && exists(dir, "red/x.csv") && exists(dir, "red/x.json") &&
                   exists(dir, "red/x-workspace.svg") && !exists(dir, "o"),
               "CLI: -o X.csv puts the summary (X.json) and figures (X-*.svg) next to it, not at "
               "the spec's outputs");

  /* (d) merge: shards of this spec merged with --spec: the summary names the
     study, its key and the spec; a shard of another spec is refused */
  rc = sh_run("cd %s && %s study spec.yaml --shard 1/2 -o sh1.csv --no-checkpoint --quiet 2>&1 && "
              "%s study spec.yaml --shard 2/2 -o sh2.csv --no-checkpoint --quiet 2>&1 && "
              "%s study merge m/all.csv sh1.csv sh2.csv --spec spec.yaml 2>&1",
              dir, bin, bin, bin);
  char *mj = slurp(dir, "m/all.json"), *mc = slurp(dir, "m/all.csv"), *xc = slurp(dir, "red/x.csv");
  ea_test_true(rc == 0 && mj && strstr(mj, "\"study\": \"redir\"") &&
                   strstr(mj, "\"study_key\": \"") && strstr(mj, "\"spec\": \"../spec.yaml\"") &&
                   mc && xc && !strcmp(mc, xc),
               "CLI merge --spec: CSV = single run; summary has study, study_key and spec");
  free(mj);
  free(mc);
  free(xc);
  put(dir, "other.yaml",
      "name: redir\ngrid: {payload_factor: [0, 0.5]}\n"
      "metrics: {workspace: {points: 12, limits: false}}\n");
  rc = sh_run("cd %s && %s study other.yaml --shard 2/2 -o oth2.csv --no-checkpoint --quiet 2>&1 "
              "&& %s study merge m/mixed.csv sh1.csv oth2.csv 2>&1",
              dir, bin, bin);
  printf("  merge of two specs: exit %d: %s", rc, g_out);
  ea_test_true(rc == 2 && strstr(g_out, "different specs") && !exists(dir, "m/mixed.csv"),
               "CLI merge: shards of two specs refused (exit 2, nothing written)");
  rc = sh_run("cd %s && %s study merge m/chk.csv sh1.csv sh2.csv --spec other.yaml 2>&1", dir, bin);
  ea_test_true(rc == 2 && !exists(dir, "m/chk.csv"), "CLI merge --spec of another spec refused");
  /* a shard that is a FIFO (no writer: a plain open blocks for ever; timeout gives 124) or a
     directory: refused at once, saying what it is, nothing written */
  {
    char fifo[1300], sub[1300];
    snprintf(fifo, sizeof fifo, "%s/fifo.csv", dir);
    snprintf(sub, sizeof sub, "%s/shard.d", dir);
    ea_test_true(mkfifo(fifo, 0600) == 0 && mkdir(sub, 0755) == 0, "mkfifo, mkdir");
    rc = sh_run("cd %s && timeout 10 %s study merge m/ff.csv sh1.csv fifo.csv 2>&1", dir, bin);
    printf("  merge of a FIFO shard: exit %d: %s", rc, g_out);
    ea_test_true(rc == 2 && strstr(g_out, "fifo.csv: is a FIFO (named pipe), not a regular file") &&
                     !exists(dir, "m/ff.csv"),
                 "CLI merge: a FIFO shard refused at once (exit 2, named), nothing written");
    rc = sh_run("cd %s && timeout 10 %s study merge m/dd.csv sh1.csv shard.d 2>&1", dir, bin);
    printf("  merge of a directory shard: exit %d: %s", rc, g_out);
    ea_test_true(rc == 2 && strstr(g_out, "shard.d: is a directory, not a regular file") &&
                     !exists(dir, "m/dd.csv"),
                 "CLI merge: a directory shard refused (exit 2, named), nothing written");
    unlink(fifo);
    rmdir(sub);
  }

  rc = sh_run("cd %s && %s study spec.yaml --workers fibers -o w.csv 2>&1", dir, bin);
  ea_test_true(rc == 2 && strstr(g_out, "--workers: 'fibers' is not auto, threads or processes") &&
                   !exists(dir, "w.csv"),
               "CLI --workers with another value: exit 2 naming it");

  /* (e) workspace: an empty or ill-posed region is an error, never NaN */
  rc = sh_run("%s workspace --inner-length 5 2>&1", bin);
  printf("  workspace --inner-length 5: exit %d: %s", rc, g_out);
  ea_test_true(rc == 2 && strstr(g_out, "empty") && !strstr(g_out, "nan"),
               "CLI workspace --inner-length 5: exit 2, 'region is empty', no NaN");
  rc = sh_run("%s workspace --alpha-min-deg -180 --alpha-max-deg 180 --points 13 2>&1", bin);
  ea_test_true(rc == 2 && !strstr(g_out, "nan"),
               "CLI workspace over a full turn: exit 2 with the reason, no NaN");
  rc = sh_run("%s workspace 2>&1", bin);
  ea_test_true(rc == 0 && !strstr(g_out, "nan") && strstr(g_out, "0.2799213894"),
               "CLI workspace: the metrics table (gamma 0 area 0.2799213894 m^2)");
  sh_run("rm -rf %s/edit %s/cwd %s/redir", g_tmp, g_tmp, g_tmp);
}

/* ---- spec errors ------------------------------------------------------------------ */

static void test_spec_errors(void) {
  static const struct {
    const char *text, *want;
  } cases[] = {
      {"grid:\n  payload_factr: [0]\nmetrics: {workspace: }\n",
       "spec.yaml:2:3: unknown key 'payload_factr' in grid"},
      {"grid:\n  payload_factor: [0, abc]\nmetrics: {workspace: }\n",
       "spec.yaml:2:23: key 'payload_factor': 'abc' is not a number"},
      {"grid:\n  payload_factor: '0:-0.1:0.5'\nmetrics: {workspace: }\n",
       "spec.yaml:2:19: key 'payload_factor': '0:-0.1:0.5' is not a range"},
      {"grid:\n  payload_factor: [0]\n  payload_kg: [1]\nmetrics: {workspace: }\n",
       "spec.yaml:3:15: key 'payload_kg': give payload_factor or payload_kg, not both"},
      {"grid:\n  payload_factor: [0]\n", "spec.yaml:1:1: missing required key 'metrics'"},
      {"grid:\n  EI_Nm2: [-1]\nmetrics: {workspace: }\n",
       "spec.yaml:2:12: key 'EI_Nm2': value -1 is below the bound"},
      {"grid: {payload_factor: [0]}\nmetrics:\n  frequencies:\n    modes: 99\n"
       "    configurations: [{cable_length_m: 0.4, cable_angle_deg: 0}]\n",
       "spec.yaml:4:12: key 'modes': value 99 is outside [1, 16]"},
      {"grid: {payload_factor: [0]}\nmetrics:\n  workspace: {alpha_min_deg: 10, alpha_max_deg: "
       "-10}\n",
       "spec.yaml:3:49: key 'alpha_max_deg': -10 must be above alpha_min_deg 10"},
      {"grid: {payload_factor: [0]}\nmetrics:\n  frequencies:\n    configurations:\n"
       "      - {cable_length: 0.4}\n",
       "spec.yaml:5:10: unknown key 'cable_length' in a frequencies configuration"},
      {"grid: {payload_factor: [0]}\nmetrics: {}\n",
       "spec.yaml:2:10: key 'metrics': ask for at least one"},
      {"grid: [0\n", "spec.yaml:2:1: YAML syntax error"},
      {"grid: {payload_factor: [0]}\nmetrics:\n  at_rest: {task: t.yaml, mode: 2}\n",
       "spec.yaml:3:27: unknown key 'mode' in metrics.at_rest"},
      {"grid: {payload_factor: [0]}\nmetrics:\n  at_rest: {task: t.yaml, modes: 9}\n",
       "spec.yaml:3:34: key 'modes': value 9 is outside [1, 4]"},
      {"grid: {payload_factor: [0]}\nmetrics:\n  at_rest: {modes: 2}\n",
       "spec.yaml:3:12: missing required key 'task'"},
      {"grid: {payload_factor: [0]}\nmetrics:\n  at_rest:\n    task: t.yaml\n"
       "    fe_dt_s: 0.5\n",
       "spec.yaml:5:14: key 'fe_dt_s': value 0.5 is above the bound"},
      {"grid: {payload_factor: [0]}\nmetrics:\n  at_rest: t.yaml\n",
       "spec.yaml:3:12: key 'at_rest' must be a mapping"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
    ea_study_t s;
    ea_error_t e = {0};
    ea_status_t st =
        ea_study_load_string("spec.yaml", cases[i].text, strlen(cases[i].text), NULL, &s, &e);
    const int ok = st != EA_OK && !strncmp(e.msg, cases[i].want, strlen(cases[i].want));
    char what[300];
    snprintf(what, sizeof what, "spec error %zu: '%s'", i + 1, cases[i].want);
    ea_test_true(ok, what);
    if (!ok) printf("  got (%s): %s\n", ea_status_name(st), e.msg);
    if (!st) ea_study_free(&s);
  }
  ea_study_t s;
  ea_error_t e = {0};
  ea_test_true(ea_study_load("/nonexistent/x.yaml", NULL, &s, &e) == EA_ERR_IO &&
                   strstr(e.msg, "/nonexistent/x.yaml"),
               "missing spec file: EA_ERR_IO naming the file");
}

int main(void) {
  gsl_set_error_handler_off(); /* every GSL return is checked */
  const char *src = getenv("EA_SOURCE_DIR");
  if (src) snprintf(g_src, sizeof g_src, "%s", src);
  snprintf(g_tmp, sizeof g_tmp, "/tmp/ea_test_study.XXXXXX");
  if (!mkdtemp(g_tmp)) snprintf(g_tmp, sizeof g_tmp, "/tmp");
  test_workspace_metrics();
  test_fig3();
  test_threads_shards();
  test_failed_case();
  test_resume();
  test_public_planner();
  test_min_time();
  test_workers();
  test_cli();
  test_spec_errors();
  rmdir(g_tmp);
  return ea_test_summary("test_study");
}
