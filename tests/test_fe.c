/* Tests of the finite element model (model/fe_*.c). References come from
 * outside the code: Euler-Bernoulli clamped-free frequencies, the tip-mass
 * frequency equation solved here with a GSL root finder, central finite
 * differences, the ODE statics of model/statics_*.c, the paper's Fig. 5 trend,
 * and energy conservation / the eigen-solver for the dynamics. */
#include "ea_model.h"
#include "ea_test.h"
#include "fe_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>
#include <string.h>

/* Cantilever arm: no gravity, no cable, no hand; stiff shear and small rotary
 * inertia so that Euler-Bernoulli is the limit to better than 1e-7. */
static ea_arm_t cantilever_arm(void) {
  ea_arm_t a;
  ea_arm_default(&a);
  a.g = 0.0;
  a.I_hand = 0.0;
  a.GA_s *= 100.0;
  a.I_zz = 0.0;
  return a;
}

static double tipmass_eq(double b, void *p) {
  const double mu = *(const double *)p;
  return 1.0 + cos(b) * cosh(b) + mu * b * (cos(b) * sinh(b) - sin(b) * cosh(b));
}

/* Root of the tip-mass frequency equation in [lo, hi] (Brent). */
static double tipmass_root(double mu, double lo, double hi) {
  gsl_function F = {tipmass_eq, &mu};
  gsl_root_fsolver *s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  gsl_root_fsolver_set(s, &F, lo, hi);
  double r = NAN;
  for (int i = 0; i < 200; ++i) {
    gsl_root_fsolver_iterate(s);
    r = gsl_root_fsolver_root(s);
    if (gsl_root_test_interval(gsl_root_fsolver_x_lower(s), gsl_root_fsolver_x_upper(s), 0,
                               1e-14) == GSL_SUCCESS)
      break;
  }
  gsl_root_fsolver_free(s);
  return r;
}

/* Frequencies [Hz] of the straight cantilever with ne elements and tip mass. */
static int cantilever_modes(const ea_arm_t *a, int ne, double tip_mass, double f[3]) {
  ea_fe_settings_t s;
  ea_fe_settings_default(&s);
  s.elements = ne;
  ea_fe_model_t *m = NULL;
  ea_error_t e;
  if (ea_fe_model_alloc(a, &s, &m, &e)) {
    printf("alloc: %s\n", e.msg);
    return 1;
  }
  ea_load_t ld = {tip_mass};
  ea_fe_model_set_load(m, &ld);
  ea_fe_set_straight(m, 0.0);
  ea_fe_modes_info_t mi;
  int rc = ea_fe_modes(m, &mi, &e) != EA_OK;
  for (int k = 0; k < 3; ++k) f[k] = mi.freq_hz[k];
  ea_fe_model_free(m);
  return rc;
}

static void test_cantilever(void) {
  printf("--- (a) straight cantilever: clamped-free frequencies ---\n");
  const ea_arm_t a = cantilever_arm();
  const double L = a.length, c = sqrt(a.EI / a.rho) / (2.0 * M_PI * L * L);
  const double bl[3] = {1.875104068712, 4.694091132974, 7.854757438238};
  double mu = 1.0;
  const double bm[3] = {tipmass_root(mu, 1.0, 1.5), tipmass_root(mu, 3.5, 4.5),
                        tipmass_root(mu, 6.5, 7.5)};
  const double bm_pub[3] = {1.24791741, 4.03113944, 7.13413224};
  for (int k = 0; k < 3; ++k) ea_test_abs(bm[k], bm_pub[k], 1e-8, "tip-mass root (GSL brent) vs published");
  for (int pass = 0; pass < 2; ++pass) {
    const double *b = pass ? bm : bl;
    const double M = pass ? mu * a.rho * L : 0.0;
    double want[3], err[5][3];
    for (int k = 0; k < 3; ++k) want[k] = b[k] * b[k] * c;
    const int meshes[5] = {2, 4, 8, 16, 32};
    printf("%s: elements, f1 f2 f3 [Hz], rel. errors, observed order\n",
           pass ? "tip mass mu = 1" : "no tip mass");
    for (int i = 0; i < 5; ++i) {
      double f[3] = {0, 0, 0};
      if (cantilever_modes(&a, meshes[i], M, f)) ea_test_true(0, "cantilever modes");
      for (int k = 0; k < 3; ++k) err[i][k] = fabs(f[k] - want[k]) / want[k];
      printf("  %2d  %.9f %.9f %.9f  %.2e %.2e %.2e", meshes[i], f[0], f[1], f[2], err[i][0],
             err[i][1], err[i][2]);
      if (i > 0)
        printf("  p = %.2f %.2f %.2f", log2(err[i - 1][0] / err[i][0]),
               log2(err[i - 1][1] / err[i][1]), log2(err[i - 1][2] / err[i][2]));
      printf("\n");
    }
    for (int k = 0; k < 3; ++k) {
      char w[128];
      snprintf(w, sizeof w, "%s mode %d, 32 elements vs closed form", pass ? "mu=1" : "mu=0",
               k + 1);
      /* floor: rounding with EA, GA >> EI (~1e-5) and shear (GA * 100: < 1e-7) */
      ea_test_rel(want[k] * (1.0 + err[4][k]), want[k], 3e-5, w);
      /* order from 4 -> 8 elements, where the discretization error dominates */
      const double p = log2(err[1][k] / err[2][k]);
      snprintf(w, sizeof w, "%s mode %d observed order %.2f >= 2", pass ? "mu=1" : "mu=0", k + 1,
               p);
      ea_test_true(p >= 2.0, w);
    }
  }
}

/* ---- (b) tangent vs central finite differences of the internal force ---- */

static double max_abs(const double *a, int n) {
  double r = 0;
  for (int i = 0; i < n; ++i) r = fmax(r, fabs(a[i]));
  return r;
}

static void fd_check(ea_arm_t a, int large, const char *label) {
  ea_fe_settings_t s;
  ea_fe_settings_default(&s);
  s.elements = 3;
  ea_fe_model_t *m = NULL;
  if (ea_fe_model_alloc(&a, &s, &m, NULL)) {
    ea_test_true(0, "fd: alloc");
    return;
  }
  const int nd = m->nd, nf = m->nf;
  double *q = calloc((size_t)nd, sizeof *q), *f1 = calloc((size_t)nd, sizeof *f1),
         *f2 = calloc((size_t)nd, sizeof *f2), *K = calloc((size_t)nd * nd, sizeof *K);
  /* a curved, strained configuration (deterministic pseudo-random) */
  unsigned r = 12345u;
  for (int i = 0; i < m->nn; ++i) {
    const double si = a.length * i / (m->nn - 1), th = 0.3 + 1.2 * si / a.length;
    double rnd[3];
    for (int k = 0; k < 3; ++k) {
      r = r * 1103515245u + 12345u;
      rnd[k] = ((r >> 8) & 0xffff) / 65535.0 - 0.5;
    }
    const double amp = large ? 1.0 : 1e-4;
    q[3 * i] = si * cos(0.3) * 0.95 + amp * 0.03 * rnd[0] * (i > 0);
    q[3 * i + 1] = si * sin(0.3) + amp * 0.03 * rnd[1] * (i > 0);
    q[3 * i + 2] = th + amp * 0.5 * rnd[2];
  }
  const ea_fe_cable_phase_t phases[3] = {EA_FE_CABLE_NONE, EA_FE_CABLE_ACTIVE,
                                         EA_FE_CABLE_PASSIVE};
  const double l = hypot(a.x_c - q[nd - 3], a.y_c - q[nd - 2]);
  const double vals[3] = {0.0, 12.0, l * (large ? 0.9 : 0.9999)};
  for (int ph = 0; ph < 3; ++ph) {
    ea__fe_assemble(m, q, phases[ph], vals[ph], m->fi, m->Kb);
    for (int j = 0; j < nd; ++j)
      for (int i = 0; i < nd; ++i) {
        const int lo = i < j ? i : j, hi = i < j ? j : i;
        K[i + (size_t)j * nd] =
            (hi - lo <= EA__FE_KD) ? m->Kb[(EA__FE_KD + lo - hi) + (size_t)hi * EA__FE_LDS] : 0.0;
      }
    double dK = 0, dF = 0, Kmax = max_abs(K, nd * nd), Fmax = 0;
    for (int j = 3; j < nd; ++j) {
      const double h = 1e-6, qj = q[j];
      q[j] = qj + h;
      const double Vp = ea__fe_assemble(m, q, phases[ph], vals[ph], f1, NULL);
      q[j] = qj - h;
      const double Vm = ea__fe_assemble(m, q, phases[ph], vals[ph], f2, NULL);
      q[j] = qj;
      for (int i = 3; i < nd; ++i)
        dK = fmax(dK, fabs((f1[i] - f2[i]) / (2 * h) - K[i + (size_t)j * nd]));
      ea__fe_assemble(m, q, phases[ph], vals[ph], f1, NULL);
      dF = fmax(dF, fabs((Vp - Vm) / (2 * h) - f1[j]));
      Fmax = fmax(Fmax, fabs(f1[j]));
    }
    char w[200];
    snprintf(w, sizeof w, "%s, cable phase %d: max|K_fd - K| / max|K| = %.2e (nf = %d)", label,
             ph, dK / Kmax, nf);
    ea_test_true(dK / Kmax < 1e-7, w);
    snprintf(w, sizeof w, "%s, cable phase %d: force = gradient of potential, %.2e", label, ph,
             dF / Fmax);
    ea_test_true(dF / Fmax < 1e-7, w);
  }
  free(q);
  free(f1);
  free(f2);
  free(K);
  ea_fe_model_free(m);
}

static void test_tangent(void) {
  printf("--- (b) analytic tangent vs central finite differences ---\n");
  ea_arm_t a;
  ea_arm_default(&a);
  ea_arm_t soft = a;
  soft.EA = 40.0; /* all stiffness terms of one size: geometric terms are tested */
  soft.GA_s = 15.0;
  fd_check(soft, 1, "soft arm, large strains and rotations");
  fd_check(a, 0, "paper's arm, small strains");
}

int main(void) {
  gsl_set_error_handler_off();
  test_cantilever();
  test_tangent();
  return ea_test_summary("test_fe");
}
