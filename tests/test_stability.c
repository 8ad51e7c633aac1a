/* Stability reported by the FE passive stiffness, against Greenhill's
 * closed form: a standing heavy column (no tip mass, no cable tension) is
 * stable below L_cr = (7.83734743894 EI / (rho g))^(1/3) and unstable above. */
#include "ea_problems.h"
#include "ea_test.h"

#include <gsl/gsl_errno.h>

static int column_stable(double L_over_Lcr, double *Lcr_out) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  arm.m_hand = 0.0;
  arm.I_hand = 0.0;
  const double Lcr = cbrt(7.83734743894 * arm.EI / (arm.rho * arm.g));
  *Lcr_out = Lcr;
  arm.length = L_over_Lcr * Lcr;
  ea_shooter_t *sh = NULL;
  ea_fe_model_t *fe = NULL;
  if (ea_shooter_alloc(&arm, NULL, &sh, NULL) || ea_fe_model_alloc(&arm, NULL, &fe, NULL))
    return -2;
  ea_load_t load = {0.0};
  ea_shooter_set_load(sh, &load);
  /* The straight upright column is an exact solution of eq. 11 with T = 0. */
  ea_config_point_t pt = {0};
  pt.alpha = 1.0;
  pt.tension = 0.0;
  pt.theta0 = M_PI / 2;
  pt.kappa0 = 0.0;
  pt.cable_length = 1.0;
  pt.status = EA_OK;
  pt.admissible = 1;
  ea_status_t st = ea_config_check_stability(sh, fe, &pt);
  ea_fe_model_free(fe);
  ea_shooter_free(sh);
  if (st) return -1;
  return pt.stable;
}

int main(void) {
  gsl_set_error_handler_off();
  double Lcr = 0;
  const double f[] = {0.9, 0.97, 1.03, 1.1};
  for (int i = 0; i < 4; ++i) {
    const int s = column_stable(f[i], &Lcr);
    char what[128];
    snprintf(what, sizeof what, "heavy column at L = %.2f L_cr (L_cr = %.4f m): %s", f[i], Lcr,
             f[i] < 1 ? "stable" : "unstable");
    ea_test_true(s == (f[i] < 1 ? 1 : 0), what);
    printf("  FE says %s\n", s == 1 ? "stable" : s == 0 ? "unstable" : "(FE failed)");
  }
  return ea_test_summary("test_stability");
}
