/* Benchmark of the calibration (docs/calibration.md, "Numbers"): time of ea_calib_fit and the
 * parameters' errors against the number of static records' rows and the sensor noise, on
 * records made by the FE model of an arm that differs from the paper's (EI +20 %, rho -10 %,
 * hand mass +15 %, I_L x2, cable root +1 cm, damping 2 % and 1 %), fitted from the paper's
 * arm. Each row: one static record (every fourth configuration at a known 0.2 kg payload)
 * and two ring-downs (tension and tip position, 6 s at 1 kHz), noise scaled from the
 * reference (encoder 0.5 mrad, torque 0.01 N m, tension 0.05 N, tip 0.2 mm). Errors
 * relative; "max err/se" is the largest |error| / standard error over the fitted parameters.
 * usage: bench_calib [REPEATS] */
#include "ea_test_calib.h"

#include <gsl/gsl_errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench_util.h"

int main(int argc, char **argv) {
  gsl_set_error_handler_off();
  const int reps = ea_bench_count(argc, argv, 1, 1, 20, "bench_calib [REPEATS]");
  if (reps < 0) return 2;
  char dir[] = "/tmp/bench_calib_XXXXXX";
  if (!mkdtemp(dir)) return 1;
  ea_arm_t prior, truth;
  /* the ring-downs are damped modally (the same ratios at every hold): their mean */
  ea_calib_settings_t set;
  ea_calib_settings_default(&set);
  set.damping_at_start = 0;
  ea_arm_default(&prior);
  truth = prior;
  truth.EI *= 1.2;
  truth.rho *= 0.9;
  truth.m_hand *= 1.15;
  truth.I_hand *= 2.0;
  truth.x_c += 0.01;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  printf("## Calibration: time and error against rows and noise (pace %.1f ms)\n",
         ea_bench_pace_ms());
  printf("| static rows | noise x | fit time [s] | iterations | EI err | rho err | m_hand err | "
         "I_L err | zeta_1 err | zeta_2 err | max err/se |\n");
  printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  const int rows_set[3] = {9, 18, 36};
  const double noise_set[3] = {0.5, 1.0, 2.0};
  for (int ni = 0; ni < 3; ++ni) {
    const double nx = noise_set[ni];
    gsl_rng_set(rng, 1000 + ni);
    char rp[2][300];
    ea_tc_ring_truth_t tr[2];
    const double rl[2] = {0.38, 0.50}, amp[3] = {0.01, 0.002, 0.003};
    for (int k = 0; k < 2; ++k) {
      snprintf(rp[k], sizeof rp[k], "%s/ring%d.csv", dir, k);
      ea_error_t err = {0};
      if (ea_tc_write_ringdown(rp[k], &truth, rl[k], 0.0, 0, 0.02, 0.01, amp, 1e-3, 1, 6.0,
                               0.05 * nx, 2e-4 * nx, rng, &tr[k], &err)) {
        fprintf(stderr, "ring-down: %s\n", err.msg);
        return 1;
      }
    }
    for (int ri = 0; ri < 3; ++ri) {
      const int n = rows_set[ri];
      double L[64], a[64], pay[64];
      for (int i = 0; i < n; ++i) { /* lengths 0.30..0.62 m, angles -30, 0, 30 deg */
        L[i] = 0.30 + 0.32 * (i / 3) / ((n - 1) / 3 > 0 ? (n - 1) / 3 : 1);
        a[i] = ((i % 3) - 1) * 30 * M_PI / 180;
        pay[i] = (i % 4 == 3) ? 0.2 : 0.0;
      }
      char sp[300];
      snprintf(sp, sizeof sp, "%s/static.csv", dir);
      ea_tc_static_opts_t so = {{5e-4 * nx, 0.01 * nx, 0.05 * nx, 0, 0, 0},
                                (1u << EA_CALIB_CH_TORQUE) | (1u << EA_CALIB_CH_TENSION),
                                1};
      ea_error_t err = {0};
      if (ea_tc_write_static(sp, &truth, L, a, pay, n, &so, rng, &err)) {
        fprintf(stderr, "static: %s\n", err.msg);
        return 1;
      }
      ea_calib_record_t recs[3];
      const char *paths[3] = {sp, rp[0], rp[1]};
      for (int r = 0; r < 3; ++r)
        if (ea_calib_record_read(paths[r], &recs[r], &err)) {
          fprintf(stderr, "%s\n", err.msg);
          return 1;
        }
      double t[20];
      ea_calib_result_t res;
      memset(&res, 0, sizeof res);
      ea_status_t st = EA_OK;
      for (int q = 0; q < reps; ++q) {
        ea_calib_result_free(&res);
        const double t0 = ea_bench_now();
        st = ea_calib_fit(&prior, recs, 3, &set, &res, &err);
        t[q] = ea_bench_now() - t0;
      }
      const double tm = ea_bench_median(t, reps);
      if (st) {
        printf("| %d | %g | %.2f | - | fit failed: %s |||||||\n", recs[0].rows, nx, tm, err.msg);
      } else {
        double worst = 0;
        for (int k = 0; k < EA_CALIB_NP; ++k)
          if (res.state[k] == EA_CALIB_FITTED)
            worst = fmax(worst, fabs(res.value[k] - ea_calib_param_get(&truth, k)) / res.se[k]);
        const double z1 = 0.5 * (tr[0].zeta[0] + tr[1].zeta[0]);
        const double z2 = 0.5 * (tr[0].zeta[1] + tr[1].zeta[1]);
#define REL(k) (res.value[k] / ea_calib_param_get(&truth, k) - 1.0)
        printf("| %d | %g | %.2f | %d | %+.2e | %+.2e | %+.2e | %+.2e | %+.2e | %+.2e | %.2f |\n",
               recs[0].rows, nx, tm, res.iterations, REL(EA_CALIB_P_EI), REL(EA_CALIB_P_RHO),
               REL(EA_CALIB_P_M_HAND), REL(EA_CALIB_P_I_HAND),
               res.n_zeta > 0 ? res.zeta[0] / z1 - 1 : NAN,
               res.n_zeta > 1 ? res.zeta[1] / z2 - 1 : NAN, worst);
#undef REL
      }
      fflush(stdout);
      ea_calib_result_free(&res);
      for (int r = 0; r < 3; ++r)
        ea_calib_record_free(&recs[r]);
    }
  }
  gsl_rng_free(rng);
  char rm[300];
  snprintf(rm, sizeof rm, "rm -rf '%s'", dir);
  if (system(rm) != 0) fprintf(stderr, "could not remove %s\n", dir);
  return 0;
}
