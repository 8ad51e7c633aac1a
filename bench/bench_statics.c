/* Work-precision benchmark of the statics solve (issue 2, item 6).
 *
 * A sweep of warm-started solves (10 cable angles x 40 cable lengths, each
 * started from its neighbour, as a torque map or a planner does) for every
 * integrator and tolerance; error against an independent reference: the same
 * configurations solved with GSL rkf45 at 1e-13 and the solution's tip
 * re-integrated by that reference. Prints median time per solve against the
 * errors achieved. Writes bench_statics_ref.csv for bench/peer_scipy.py.
 *
 * usage: bench_statics [repeats]   (default 15) */
#include "ea_model.h"
#include "ea_problems.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_util.h"

#define NA 10
#define NL 40
#define NC (NA * NL)

typedef struct {
  double Lc, alpha;
  double p[EA_NP];
} cfg_t;

static cfg_t cfgs[NC];

/* One sweep: along each angle, from long to short cable, warm-started. */
static int sweep(ea_shooter_t *sh, const ea_statics_settings_t *set, double (*out)[EA_NP],
                 int *fails) {
  int iters = 0;
  for (int i = 0; i < NA; ++i) {
    /* first point: warm from the reference's; then the secant predictor
     * from the two previous solutions (equal spacing) */
    double guess[EA_NP];
    memcpy(guess, cfgs[i * NL].p, sizeof guess);
    for (int j = 0; j < NL; ++j) {
      const cfg_t *c = &cfgs[i * NL + j];
      ea_statics_problem_t pr = ea_statics_problem_cable(c->Lc, c->alpha);
      ea_statics_solution_t sol;
      if (j >= 2)
        for (int q = 0; q < EA_NP; ++q)
          guess[q] = 2.0 * out[i * NL + j - 1][q] - out[i * NL + j - 2][q];
      else if (j == 1)
        memcpy(guess, out[i * NL], sizeof guess);
      if (ea_statics_solve(sh, &pr, set, guess, &sol, NULL) != EA_OK) ++*fails;
      memcpy(out[i * NL + j], sol.p, sizeof sol.p);
      iters += sol.iterations;
    }
  }
  return iters;
}

int main(int argc, char **argv) {
  gsl_set_error_handler_off();
  const int reps =
      ea_bench_count(argc, argv, 1, 15, 100000, "bench_statics [repetitions 1..100000]");
  if (reps < 0 || argc > 2) return 2;
  ea_arm_t arm;
  ea_arm_default(&arm);

  /* Reference: rkf45 at 1e-13, cold solves. */
  ea_shoot_settings_t rs;
  ea_shoot_settings_default(&rs);
  rs.integrator = EA_INT_RKF45_ADAPTIVE;
  rs.rtol = rs.atol = 1e-13;
  ea_shooter_t *ref = NULL;
  ea_shooter_alloc(&arm, &rs, &ref, NULL);
  ea_statics_settings_t tight;
  ea_statics_settings_default(&tight);
  tight.tol = 1e-12;
  for (int i = 0; i < NA; ++i) {
    const double alpha = (-60.0 + 70.0 * i / (NA - 1)) * M_PI / 180.0;
    ea_statics_solution_t edge;
    if (ea_statics_edge(ref, alpha, &tight, NULL, &edge, NULL) != EA_OK) {
      fprintf(stderr, "reference edge failed\n");
      return 1;
    }
    for (int j = 0; j < NL; ++j) {
      cfg_t *c = &cfgs[i * NL + j];
      c->alpha = alpha;
      c->Lc = edge.cable_length - (edge.cable_length - 0.254) * (0.02 + 0.98 * j / (NL - 1));
      ea_statics_problem_t pr = ea_statics_problem_cable(c->Lc, alpha);
      ea_statics_solution_t sol;
      if (ea_statics_solve(ref, &pr, &tight, j ? cfgs[i * NL + j - 1].p : edge.p, &sol, NULL)) {
        fprintf(stderr, "reference solve failed at alpha %g Lc %g\n", alpha, c->Lc);
        return 1;
      }
      memcpy(c->p, sol.p, sizeof c->p);
    }
  }
  FILE *fp = fopen("bench_statics_ref.csv", "w");
  if (fp) {
    fprintf(fp, "cable_length_m,cable_angle_rad,tension_N,theta0_rad,kappa0_per_m\n");
    for (int k = 0; k < NC; ++k)
      fprintf(fp, "%.17g,%.17g,%.17g,%.17g,%.17g\n", cfgs[k].Lc, cfgs[k].alpha,
              cfgs[k].p[EA_P_TENSION], cfgs[k].p[EA_P_THETA0], cfgs[k].p[EA_P_KAPPA0]);
    fclose(fp);
  }

  struct {
    ea_integrator_t it;
    int steps;
    double tol;
  } cases[] = {
      {EA_INT_RK8PD_FIXED, 8, 0},       {EA_INT_RK8PD_FIXED, 12, 0},
      {EA_INT_RK8PD_FIXED, 16, 0},      {EA_INT_RK8PD_FIXED, 24, 0},
      {EA_INT_RK8PD_FIXED, 32, 0},      {EA_INT_RK8PD_FIXED, 48, 0},
      {EA_INT_RK4_FIXED, 50, 0},        {EA_INT_RK4_FIXED, 200, 0},
      {EA_INT_RK4_FIXED, 800, 0},       {EA_INT_RK8PD_ADAPTIVE, 0, 1e-6},
      {EA_INT_RK8PD_ADAPTIVE, 0, 1e-9}, {EA_INT_RK8PD_ADAPTIVE, 0, 1e-12},
      {EA_INT_RKF45_ADAPTIVE, 0, 1e-6}, {EA_INT_RKF45_ADAPTIVE, 0, 1e-9},
  };
  const int ncase = (int)(sizeof cases / sizeof *cases);
  static double sol[NC][EA_NP];
  double *times = malloc((size_t)reps * sizeof *times);
  printf("Statics work-precision: %d warm-started solves per sweep (10 angles x 40 cable "
         "lengths), median of %d sweeps\n\n",
         NC, reps);
  printf("| integrator | steps / tol | median us/solve | Newton it/solve | max tip err [m] | "
         "max rel err T | max rel err theta0 | failures |\n");
  printf("|---|---|---|---|---|---|---|---|\n");
  for (int c = 0; c < ncase; ++c) {
    ea_shoot_settings_t s;
    ea_shoot_settings_default(&s);
    s.integrator = cases[c].it;
    if (cases[c].steps) s.steps = cases[c].steps;
    if (cases[c].tol > 0) s.rtol = s.atol = cases[c].tol;
    ea_shooter_t *sh = NULL;
    ea_shooter_alloc(&arm, &s, &sh, NULL);
    ea_statics_settings_t set;
    ea_statics_settings_default(&set);
    if (cases[c].tol > 0) set.tol = fmax(set.tol, 10 * cases[c].tol);
    int fails = 0, iters = 0;
    for (int r = 0; r < reps; ++r) {
      fails = 0;
      const double t0 = ea_bench_now();
      iters = sweep(sh, &set, sol, &fails);
      times[r] = (ea_bench_now() - t0) / NC;
    }
    qsort(times, (size_t)reps, sizeof *times, ea_bench_cmp);
    double etip = 0, eT = 0, eth = 0;
    for (int k = 0; k < NC; ++k) {
      double xr[EA_NX];
      ea_load_t load = {arm.m_hand};
      ea_shoot_reference(&arm, &load, sol[k], xr);
      const double tx = arm.x_c + cfgs[k].Lc * cos(cfgs[k].alpha);
      const double ty = arm.y_c + cfgs[k].Lc * sin(cfgs[k].alpha);
      etip = fmax(etip, hypot(xr[EA_X_X] - tx, xr[EA_X_Y] - ty));
      eT = fmax(eT, fabs(sol[k][EA_P_TENSION] - cfgs[k].p[EA_P_TENSION]) /
                        fabs(cfgs[k].p[EA_P_TENSION]));
      eth = fmax(eth,
                 fabs(sol[k][EA_P_THETA0] - cfgs[k].p[EA_P_THETA0]) / fabs(cfgs[k].p[EA_P_THETA0]));
    }
    char st[32];
    if (cases[c].steps)
      snprintf(st, sizeof st, "%d steps", cases[c].steps);
    else
      snprintf(st, sizeof st, "tol %.0e", cases[c].tol);
    printf("| %s | %s | %.2f | %.2f | %.2e | %.2e | %.2e | %d |\n", ea_integrator_name(cases[c].it),
           st, 1e6 * times[reps / 2], (double)iters / NC, etip, eT, eth, fails);
    ea_shooter_free(sh);
  }

  /* A 50 x 50 torque map with the default settings. */
  ea_shooter_t *sh = NULL;
  ea_shooter_alloc(&arm, NULL, &sh, NULL);
  double Ls[50], As[50];
  for (int k = 0; k < 50; ++k) {
    Ls[k] = 0.254 + (0.85 - 0.254) * k / 49.0;
    As[k] = (-60.0 + 70.0 * k / 49.0) * M_PI / 180.0;
  }
  ea_config_point_t *cells = malloc(2500 * sizeof *cells);
  for (int r = 0; r < reps; ++r) {
    const double t0 = ea_bench_now();
    ea_torque_map(sh, Ls, 50, As, 50, &arm.act, cells);
    times[r] = ea_bench_now() - t0;
  }
  qsort(times, (size_t)reps, sizeof *times, ea_bench_cmp);
  int inside = 0;
  for (int k = 0; k < 2500; ++k)
    inside += cells[k].status == EA_OK;
  printf("\n50 x 50 torque map (default settings, cold edge per angle): median %.1f ms, %d cells "
         "inside the workspace\n",
         1e3 * times[reps / 2], inside);
  free(cells);
  free(times);
  ea_shooter_free(sh);
  ea_shooter_free(ref);
  return 0;
}
