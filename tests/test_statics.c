/* Statics: closed forms (Bisshopp-Drucker cantilever, Greenhill heavy
 * column), sensitivities against finite differences, the paper's examples,
 * and independent re-integration of solutions. */
#include "ea_model.h"
#include "ea_problems.h"
#include "ea_test.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_sf_ellint.h>
#include <string.h>

/* An arm whose EI, L and g are not 1, so that a lost factor shows. */
#define T_EI 2.5
#define T_G 9.81
static ea_arm_t test_arm(double rho, double tip_mass, double L) {
  ea_arm_t a;
  ea_arm_default(&a);
  a.rho = rho;
  a.m_hand = tip_mass;
  a.length = L;
  a.EI = T_EI;
  a.g = T_G;
  return a;
}

/* ---- Bisshopp & Drucker (1945): tip-loaded cantilever, closed form ---- */

struct bd_ctx {
  double a;
};
static double bd_k(double phi0) {
  return sqrt((1.0 + sin(phi0)) / 2.0);
}
static double bd_f(double phi0, void *vp) {
  const struct bd_ctx *c = vp;
  const double k = bd_k(phi0), t1 = asin(1.0 / (k * M_SQRT2));
  return gsl_sf_ellint_Kcomp(k, GSL_PREC_DOUBLE) - gsl_sf_ellint_F(t1, k, GSL_PREC_DOUBLE) -
         sqrt(c->a);
}
/* Closed form: vertical deflection / L and horizontal tip position / L. */
static void bisshopp_drucker(double a, double *dv, double *xh) {
  struct bd_ctx c = {a};
  gsl_function F = {bd_f, &c};
  gsl_root_fsolver *s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  gsl_root_fsolver_set(s, &F, 1e-9, M_PI / 2 - 1e-6);
  double phi0 = 0;
  for (int i = 0; i < 200; ++i) {
    gsl_root_fsolver_iterate(s);
    phi0 = gsl_root_fsolver_root(s);
    if (gsl_root_test_interval(gsl_root_fsolver_x_lower(s), gsl_root_fsolver_x_upper(s), 0,
                               1e-15) == GSL_SUCCESS)
      break;
  }
  gsl_root_fsolver_free(s);
  const double k = bd_k(phi0), t1 = asin(1.0 / (k * M_SQRT2));
  *dv = 1.0 - (2.0 / sqrt(a)) * (gsl_sf_ellint_Ecomp(k, GSL_PREC_DOUBLE) -
                                 gsl_sf_ellint_E(t1, k, GSL_PREC_DOUBLE));
  *xh = sqrt(2.0 * sin(phi0) / a);
}

static void test_bisshopp_drucker(void) {
  double dv, xh;
  /* The closed-form code itself against the published values. */
  bisshopp_drucker(1.0, &dv, &xh);
  ea_test_abs(dv, 0.301720773800, 1e-11, "BD closed form a=1 vertical deflection");
  ea_test_abs(1.0 - xh, 0.056433236283, 1e-11, "BD closed form a=1 horizontal shortening");
  bisshopp_drucker(10.0, &dv, &xh);
  ea_test_abs(dv, 0.810609024880, 1e-11, "BD closed form a=10 vertical deflection");
  ea_test_abs(1.0 - xh, 0.554995597754, 1e-11, "BD closed form a=10 horizontal shortening");

  const double as[] = {0.5, 1.0, 2.0, 3.5, 5.0, 7.5, 10.0};
  for (size_t i = 0; i < sizeof as / sizeof *as; ++i) {
    const double a = as[i];
    const double L = 1.3; /* a = P L^2 / EI with P = m g */
    ea_arm_t arm = test_arm(0.0, a * T_EI / (L * L * T_G), L);
    ea_shooter_t *sh = NULL;
    ea_shooter_alloc(&arm, NULL, &sh, NULL);
    ea_statics_problem_t pr = ea_statics_problem_tension_theta0(0.0, 0.0);
    ea_statics_solution_t sol;
    ea_error_t e;
    ea_status_t st = ea_statics_solve(sh, &pr, NULL, NULL, &sol, &e);
    char what[128];
    snprintf(what, sizeof what, "BD a=%.1f solve converged", a);
    ea_test_true(st == EA_OK, what);
    if (st) printf("  %s\n", e.msg);
    bisshopp_drucker(a, &dv, &xh);
    snprintf(what, sizeof what, "BD a=%.1f vertical deflection / L", a);
    ea_test_abs(-sol.tip[EA_X_Y] / L, dv, 1e-9, what);
    snprintf(what, sizeof what, "BD a=%.1f horizontal tip / L", a);
    ea_test_abs(sol.tip[EA_X_X] / L, xh, 1e-9, what);
    ea_shooter_free(sh);
  }
}

/* ---- Greenhill's standing heavy column ---- */
#define GH_RHO 0.7

struct gh_ctx {
  int fails;
};
static double gh_sens(double L, void *vp) {
  struct gh_ctx *c = vp;
  ea_arm_t arm = test_arm(GH_RHO, 0.0, L);
  ea_shooter_t *sh = NULL;
  if (ea_shooter_alloc(&arm, NULL, &sh, NULL)) {
    ++c->fails;
    return NAN;
  }
  const double p[EA_NP] = {0.0, 0.0, M_PI / 2, 0.0};
  double xL[EA_NX], S[EA_NX * EA_NP];
  if (ea_shoot(sh, p, xL, S)) ++c->fails;
  ea_shooter_free(sh);
  return S[EA_X_KAPPA * EA_NP + EA_P_KAPPA0]; /* d kappa(L) / d kappa0 */
}

static void test_greenhill(void) {
  const double Lcr = cbrt(7.83734743894 * T_EI / (GH_RHO * T_G));
  struct gh_ctx c = {0};
  gsl_function F = {gh_sens, &c};
  const double lo = 0.75 * Lcr, hi = 1.25 * Lcr;
  ea_test_true(gh_sens(lo, &c) * gh_sens(hi, &c) < 0, "Greenhill: sensitivity changes sign");
  gsl_root_fsolver *s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  gsl_root_fsolver_set(s, &F, lo, hi);
  double L = 0;
  for (int i = 0; i < 100; ++i) {
    gsl_root_fsolver_iterate(s);
    L = gsl_root_fsolver_root(s);
    if (gsl_root_test_interval(gsl_root_fsolver_x_lower(s), gsl_root_fsolver_x_upper(s), 0,
                               1e-13) == GSL_SUCCESS)
      break;
  }
  gsl_root_fsolver_free(s);
  ea_test_true(c.fails == 0, "Greenhill: every shot integrated");
  ea_test_rel(L, Lcr, 1e-8, "Greenhill critical length from exact sensitivities");
}

/* ---- Sensitivities vs central differences ---- */

static void test_sensitivities(void) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  ea_shooter_t *sh = NULL;
  ea_shooter_alloc(&arm, NULL, &sh, NULL);
  ea_load_t load = {0.35};
  ea_shooter_set_load(sh, &load);
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  double worst = 0;
  int shots = 0, failed = 0;
  for (int k = 0; k < 50; ++k) {
    double p[EA_NP] = {-1.0 + 1.2 * gsl_rng_uniform(r), 25.0 * gsl_rng_uniform(r),
                       -0.5 + 2.0 * gsl_rng_uniform(r), -4.0 + 5.0 * gsl_rng_uniform(r)};
    double xL[EA_NX], S[EA_NX * EA_NP];
    ++shots;
    if (ea_shoot(sh, p, xL, S) != EA_OK) {
      ++failed;
      continue;
    }
    for (int j = 0; j < EA_NP; ++j) {
      const double h = 1e-5 * fmax(1.0, fabs(p[j]));
      double pp[EA_NP], pm[EA_NP], xp[EA_NX], xm[EA_NX];
      memcpy(pp, p, sizeof pp);
      memcpy(pm, p, sizeof pm);
      pp[j] += h;
      pm[j] -= h;
      shots += 2;
      if (ea_shoot(sh, pp, xp, NULL) != EA_OK || ea_shoot(sh, pm, xm, NULL) != EA_OK) {
        ++failed;
        continue;
      }
      for (int i = 0; i < EA_NX; ++i) {
        const double fd = (xp[i] - xm[i]) / (2 * h);
        const double e = fabs(fd - S[i * EA_NP + j]) / fmax(1.0, fabs(fd));
        worst = ea_test_max(worst, e); /* a NaN stays and fails the check */
      }
    }
  }
  gsl_rng_free(r);
  ea_shooter_free(sh);
  char what[96];
  snprintf(what, sizeof what, "sensitivities: all %d shots integrated (%d failed)", shots, failed);
  ea_test_true(failed == 0, what);
  ea_test_abs(worst, 0.0, 1e-6, "sensitivities vs central differences (worst, 50 points)");
}

/* ---- The paper's examples ---- */

static void test_paper_line(void) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  ea_shooter_t *sh = NULL;
  ea_shooter_alloc(&arm, NULL, &sh, NULL);
  ea_config_point_t pts[7];
  const double p0[2] = {0.3, -0.2}, p1[2] = {0.6, -0.2};
  ea_status_t st = ea_path_check_line(sh, p0, p1, 6, &arm.act, pts);
  ea_test_true(st == EA_OK, "paper line (eq. 18), 6 steps, payload 0: admissible");
  int allpos = 1, refs = 1;
  double worst = 0;
  for (int k = 0; k <= 6; ++k) {
    allpos &= pts[k].tension > 0;
    /* independent re-integration at 1e-13 by another scheme */
    double xr[EA_NX];
    const double p[EA_NP] = {pts[k].alpha, pts[k].tension, pts[k].theta0, pts[k].kappa0};
    refs &= ea_shoot_reference(&arm, ea_shooter_load(sh), p, xr) == EA_OK;
    const double xd = 0.3 + 0.3 * k / 6.0;
    worst = ea_test_max(worst, ea_test_max(fabs(xr[EA_X_X] - xd), fabs(xr[EA_X_Y] + 0.2)));
    worst = ea_test_max(worst, fabs(xr[EA_X_KAPPA]) * arm.length);
  }
  ea_test_true(refs, "paper line: every reference re-integration succeeded");
  ea_test_true(allpos, "paper line: T > 0 at every step");
  ea_test_abs(worst, 0.0, 1e-9, "paper line: re-integrated tip on the line, kappa(L) = 0");

  /* Beyond the outer edge: never reported as a solution. */
  ea_statics_solution_t edge, out;
  ea_statics_edge(sh, -0.4, NULL, NULL, &edge, NULL);
  ea_statics_problem_t pr = ea_statics_problem_cable(edge.cable_length + 0.02, -0.4);
  st = ea_statics_solve(sh, &pr, NULL, NULL, &out, NULL);
  ea_test_true(st != EA_OK && out.status != EA_OK,
               "cable longer than the T = 0 edge: not reported as a solution");
  ea_shooter_free(sh);
}

static void test_workspace_shrinks(void) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  ea_shooter_t *sh = NULL;
  ea_shooter_alloc(&arm, NULL, &sh, NULL);
  const double gam[] = {0.0, 0.1, 0.25, 0.5};
  double alpha[15];
  for (int k = 0; k < 15; ++k)
    alpha[k] = (-60.0 + 5.0 * k) * M_PI / 180.0;
  ea_config_point_t prev[15], cur[15];
  int ok = 1, conv = 1;
  for (int g = 0; g < 4; ++g) {
    ea_load_t load = {ea_arm_tip_mass(&arm, ea_arm_payload_from_factor(&arm, gam[g]))};
    ea_shooter_set_load(sh, &load);
    conv &= ea_workspace_outer(sh, alpha, 15, cur) == EA_OK;
    if (g > 0)
      for (int k = 0; k < 15; ++k)
        ok &= cur[k].cable_length < prev[k].cable_length;
    memcpy(prev, cur, sizeof cur);
  }
  ea_test_true(conv, "outer edge converged for every payload factor and angle");
  ea_test_true(ok, "outer edge moves inward (shorter cable at every angle) as payload grows");
  ea_shooter_free(sh);
}

/* ---- Problem statements agree with each other ---- */

static void test_problem_statements(void) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  ea_shooter_t *sh = NULL;
  ea_shooter_alloc(&arm, NULL, &sh, NULL);
  ea_statics_problem_t pa = ea_statics_problem_cable(0.45, -0.3);
  ea_statics_solution_t a, b, c, d;
  ea_test_true(ea_statics_solve(sh, &pa, NULL, NULL, &a, NULL) == EA_OK, "cable statement solves");
  ea_statics_problem_t pb = ea_statics_problem_tip(a.tip[EA_X_X], a.tip[EA_X_Y]);
  ea_statics_problem_t pc = ea_statics_problem_tension_theta0(a.p[EA_P_TENSION], a.p[EA_P_THETA0]);
  ea_statics_problem_t pd = ea_statics_problem_tension_alpha(a.p[EA_P_TENSION], a.p[EA_P_ALPHA]);
  ea_test_true(ea_statics_solve(sh, &pb, NULL, NULL, &b, NULL) == EA_OK, "tip statement solves");
  ea_test_true(ea_statics_solve(sh, &pc, NULL, NULL, &c, NULL) == EA_OK,
               "tension + theta0 statement solves");
  ea_test_true(ea_statics_solve(sh, &pd, NULL, NULL, &d, NULL) == EA_OK,
               "tension + alpha statement solves");
  double worst = 0;
  for (int j = 0; j < EA_NP; ++j) {
    worst = ea_test_max(worst, fabs(b.p[j] - a.p[j]) / fmax(1, fabs(a.p[j])));
    worst = ea_test_max(worst, fabs(c.p[j] - a.p[j]) / fmax(1, fabs(a.p[j])));
    worst = ea_test_max(worst, fabs(d.p[j] - a.p[j]) / fmax(1, fabs(a.p[j])));
  }
  ea_test_abs(worst, 0.0, 1e-8, "all four problem statements give the same configuration");
  ea_test_true(a.branch == EA_BRANCH_EDGE, "cold solve reports the edge-continued branch");
  ea_statics_solution_t w;
  ea_test_true(ea_statics_solve(sh, &pa, NULL, a.p, &w, NULL) == EA_OK &&
                   w.branch == EA_BRANCH_WARM && w.iterations <= 1,
               "warm start at the solution converges at once");
  /* Bad arguments */
  ea_statics_problem_t bad = ea_statics_problem_cable(NAN, 0.0);
  ea_error_t e;
  ea_test_true(ea_statics_solve(sh, &bad, NULL, NULL, &w, &e) == EA_ERR_ARG,
               "NaN given value is EA_ERR_ARG");
  bad = pa;
  bad.given[1] = bad.given[0];
  ea_test_true(ea_statics_solve(sh, &bad, NULL, NULL, &w, &e) == EA_ERR_ARG,
               "same quantity given twice is EA_ERR_ARG");
  ea_test_true(ea_shooter_alloc(NULL, NULL, &sh, NULL) == EA_ERR_ARG, "NULL arm is EA_ERR_ARG");
  ea_shooter_free(NULL);
  ea_shooter_free(sh);
}

int main(void) {
  gsl_set_error_handler_off();
  test_bisshopp_drucker();
  test_greenhill();
  test_sensitivities();
  test_paper_line();
  test_workspace_shrinks();
  test_problem_statements();
  return ea_test_summary("test_statics");
}
