/* Stress test of numerical stability: thousands of random configurations
 * over payload factors 0..0.5, cable angles -60..10 deg and cable lengths
 * from the shortest cable to the outer edge, plus the nasty corners. Every
 * reported solution is re-integrated independently (rkf45 at 1e-13); a
 * wrong "converged" answer fails the test, and so does any failure to
 * converge inside the workspace. */
#include "ea_model.h"
#include "ea_test.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_rng.h>
#include <string.h>

typedef struct {
  int solved, failed, wrong, outside_ok;
  double worst_tip, worst_kappa;
} tally_t;

static void check_one(ea_shooter_t *sh, const ea_arm_t *arm, double Lc, double alpha,
                      const double *guess, tally_t *t) {
  ea_statics_problem_t pr = ea_statics_problem_cable(Lc, alpha);
  ea_statics_solution_t sol;
  ea_status_t st = ea_statics_solve(sh, &pr, NULL, guess, &sol, NULL);
  if (st != EA_OK) {
    ++t->failed;
    printf("  no solution: Lc=%.9g alpha=%.9g deg tip mass %.4g: %s\n", Lc, alpha * 180 / M_PI,
           ea_shooter_load(sh)->tip_mass, ea_strerror(st));
    return;
  }
  ++t->solved;
  double xr[EA_NX];
  const ea_status_t rst = ea_shoot_reference(arm, ea_shooter_load(sh), sol.p, xr);
  const double tx = arm->x_c + Lc * cos(alpha), ty = arm->y_c + Lc * sin(alpha);
  const double etip = hypot(xr[EA_X_X] - tx, xr[EA_X_Y] - ty), ek = fabs(xr[EA_X_KAPPA]);
  t->worst_tip = ea_test_max(t->worst_tip, etip);
  t->worst_kappa = ea_test_max(t->worst_kappa, ek);
  /* written so that a NaN (or a failed re-integration) counts as wrong */
  if (rst != EA_OK || !(etip <= 1e-9) || !(ek <= 1e-8) || !(sol.p[EA_P_TENSION] >= 0)) {
    ++t->wrong;
    printf("  WRONG: Lc=%.9g alpha=%.9g: tip err %.3g kappa_L %.3g T %.6g\n", Lc, alpha, etip, ek,
           sol.p[EA_P_TENSION]);
  }
}

int main(void) {
  gsl_set_error_handler_off();
  ea_arm_t arm;
  ea_arm_default(&arm);
  ea_shooter_t *sh = NULL;
  ea_shooter_alloc(&arm, NULL, &sh, NULL);
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, 20261123);
  tally_t cold = {0}, warm = {0}, nasty = {0};
  int beyond = 0, beyond_ok = 0;
  const int N = 2000;
  for (int k = 0; k < N; ++k) {
    const double gam = 0.5 * gsl_rng_uniform(r);
    const double alpha = (-60.0 + 70.0 * gsl_rng_uniform(r)) * M_PI / 180.0;
    ea_load_t load = {ea_arm_tip_mass(&arm, ea_arm_payload_from_factor(&arm, gam))};
    ea_shooter_set_load(sh, &load);
    ea_statics_solution_t edge;
    if (ea_statics_edge(sh, alpha, NULL, NULL, &edge, NULL) != EA_OK) {
      ++cold.failed;
      printf("  no edge at alpha %.6g gamma %.4g\n", alpha, gam);
      continue;
    }
    const double Lmin = arm.act.cable_length_min, Le = edge.cable_length;
    const double Lc = Lmin + (Le - Lmin) * gsl_rng_uniform(r);
    /* Half cold (continuation from the edge), half warm from the edge. */
    if (k % 2)
      check_one(sh, &arm, Lc, alpha, NULL, &cold);
    else
      check_one(sh, &arm, Lc, alpha, edge.p, &warm);
    /* The nasty ones, every tenth case. */
    if (k % 10 == 0) {
      check_one(sh, &arm, Le * (1 - 1e-7), alpha, NULL, &nasty); /* T -> 0 */
      check_one(sh, &arm, Lmin, alpha, NULL, &nasty);            /* shortest cable */
      /* Beyond the edge: must never be reported as a solution. */
      ea_statics_problem_t pr =
          ea_statics_problem_cable(Le + 0.005 + 0.05 * gsl_rng_uniform(r), alpha);
      ea_statics_solution_t sol;
      ++beyond;
      if (ea_statics_solve(sh, &pr, NULL, NULL, &sol, NULL) != EA_OK && sol.status != EA_OK)
        ++beyond_ok;
    }
  }
  /* Large payload and a nearly straight beam (stiff arm, little weight). */
  {
    ea_load_t load = {ea_arm_tip_mass(&arm, ea_arm_payload_from_factor(&arm, 0.5))};
    ea_shooter_set_load(sh, &load);
    for (int k = 0; k <= 14; ++k)
      check_one(sh, &arm, 0.3, (-60.0 + 5 * k) * M_PI / 180, NULL, &nasty);
    ea_arm_t stiff = arm;
    stiff.EI = 500.0;
    ea_shooter_t *s2 = NULL;
    ea_shooter_alloc(&stiff, NULL, &s2, NULL);
    /* A stiff beam under a moderate pull: nearly straight. (Shortening the
     * cable from its T = 0 edge would need T < 0 here: such a beam is only
     * held on the tension side.) */
    ea_statics_problem_t pt = ea_statics_problem_tension_alpha(50.0, -0.3);
    ea_statics_solution_t e2;
    if (ea_statics_solve(s2, &pt, NULL, NULL, &e2, NULL) == EA_OK) {
      printf("  nearly straight beam: T = 50 N, winding %.3g rad, L_c %.6f m\n", e2.winding,
             e2.cable_length);
      check_one(s2, &stiff, e2.cable_length, -0.3, NULL, &nasty);
    } else {
      ++nasty.failed;
    }
    ea_shooter_free(s2);
  }
  const tally_t *ts[3] = {&cold, &warm, &nasty};
  const char *names[3] = {"cold", "warm", "nasty"};
  for (int i = 0; i < 3; ++i) {
    const int tot = ts[i]->solved + ts[i]->failed;
    printf("%-6s %5d cases: %5d solved, %d not converged (%.3f %%), %d wrong; worst re-integrated "
           "tip error %.3g m, kappa(L) %.3g 1/m\n",
           names[i], tot, ts[i]->solved, ts[i]->failed, tot ? 100.0 * ts[i]->failed / tot : 0.0,
           ts[i]->wrong, ts[i]->worst_tip, ts[i]->worst_kappa);
    char what[96];
    snprintf(what, sizeof what, "%s: no failure to converge inside the workspace", names[i]);
    ea_test_true(ts[i]->failed == 0, what);
    snprintf(what, sizeof what, "%s: no wrong converged answer", names[i]);
    ea_test_true(ts[i]->wrong == 0, what);
  }
  printf("beyond the edge: %d of %d correctly refused\n", beyond_ok, beyond);
  ea_test_true(beyond_ok == beyond, "cable beyond the edge never reported as a solution");
  gsl_rng_free(r);
  ea_shooter_free(sh);
  return ea_test_summary("test_statics_stress");
}
