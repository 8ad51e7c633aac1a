/* Benchmark of the FE model: mesh convergence (default mesh choice), time of
 * assembly + eigen-solve per backend, a Fig. 5 sweep of 100 cable lengths, and
 * a 5 s transient vs real time. Medians of repeated runs. */
#include "ea_model.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_util.h"

/* FE equilibrium at (Lc, alpha) on a model; returns 0 on success. */
static int fe_at(ea_fe_model_t *m, ea_shooter_t *sh, double Lc, double alpha, const double *guess,
                 ea_statics_solution_t *sol) {
  ea_statics_problem_t pr = ea_statics_problem_cable(Lc, alpha);
  ea_error_t e;
  if (ea_statics_solve(sh, &pr, NULL, guess, sol, &e)) return 1;
  return ea_fe_static_solve(m, sh, sol, NULL, &e) != EA_OK;
}

static ea_fe_model_t *model(const ea_arm_t *a, int ne, ea_fe_eig_backend_t be) {
  ea_fe_settings_t s;
  ea_fe_settings_default(&s);
  s.elements = ne;
  s.eig_backend = be;
  s.static_hold_tip = 1;
  ea_fe_model_t *m = NULL;
  ea_error_t e;
  if (ea_fe_model_alloc(a, &s, &m, &e)) {
    fprintf(stderr, "alloc: %s\n", e.msg);
    exit(1);
  }
  return m;
}

int main(void) {
  ea_arm_t a;
  ea_arm_default(&a);
  ea_shooter_t *sh = NULL;
  if (ea_shooter_alloc(&a, NULL, &sh, NULL)) return 1;
  ea_statics_solution_t sol;

  /* 1. mesh convergence at three cable lengths, alpha = 0 */
  printf("## Mesh convergence (alpha = 0; reference: 64 elements)\n");
  printf("| Lc [m] | elements | f1 [Hz] | f2 [Hz] | f3 [Hz] | err1 | err2 | err3 |\n");
  printf("|---|---|---|---|---|---|---|---|\n");
  const int meshes[] = {2, 3, 4, 5, 6, 8, 10, 12, 16, 24, 32};
  const int nm = (int)(sizeof meshes / sizeof meshes[0]);
  const double Lcs[3] = {0.254, 0.4, 0.635};
  for (int c = 0; c < 3; ++c) {
    double fr[3];
    ea_fe_model_t *mr = model(&a, 64, EA_FE_EIG_DSBGVX);
    ea_fe_modes_info_t mi;
    if (fe_at(mr, sh, Lcs[c], 0.0, NULL, &sol) || ea_fe_modes(mr, &mi, NULL)) {
      fprintf(stderr, "reference failed at Lc = %g\n", Lcs[c]);
      return 1;
    }
    memcpy(fr, mi.freq_hz, sizeof fr);
    ea_fe_model_free(mr);
    for (int i = 0; i < nm; ++i) {
      ea_fe_model_t *m = model(&a, meshes[i], EA_FE_EIG_DSBGVX);
      if (fe_at(m, sh, Lcs[c], 0.0, NULL, &sol) || ea_fe_modes(m, &mi, NULL)) {
        printf("| %.3f | %d | failed | | | | | |\n", Lcs[c], meshes[i]);
        ea_fe_model_free(m);
        continue;
      }
      printf("| %.3f | %d | %.5f | %.5f | %.5f | %.1e | %.1e | %.1e |\n", Lcs[c], meshes[i],
             mi.freq_hz[0], mi.freq_hz[1], mi.freq_hz[2], fabs(mi.freq_hz[0] / fr[0] - 1),
             fabs(mi.freq_hz[1] / fr[1] - 1), fabs(mi.freq_hz[2] / fr[2] - 1));
      ea_fe_model_free(m);
    }
  }

  /* 2. assembly + eigen-solve time per backend and mesh */
  printf("\n## Assembly + eigen-solve (modes 1-3, Lc = 0.4 m), median of 301 runs\n");
  printf("| backend | elements | assembly+stability [us] | eigen [us] | total [us] |\n");
  printf("|---|---|---|---|---|\n");
  const char *bn[EA_FE_EIG_COUNT] = {"LAPACK dsbgvx (band)", "LAPACK dsygv (dense)",
                                     "GSL gensymmv (dense)", "Lanczos (band Cholesky of K)"};
  const int tm[] = {EA_FE_PAPER_ELEMENTS, 8, EA_FE_DEFAULT_ELEMENTS, 24};
  const int ntm = (int)(sizeof tm / sizeof tm[0]);
  for (int b = 0; b < EA_FE_EIG_COUNT; ++b)
    for (int i = 0; i < ntm; ++i) {
      ea_fe_model_t *m = model(&a, tm[i], (ea_fe_eig_backend_t)b);
      if (fe_at(m, sh, 0.4, 0.0, NULL, &sol)) return 1;
      enum { R = 301 };
      static double ta[R], te[R], tt[R];
      for (int r = 0; r < R; ++r) {
        ea_fe_modes_info_t mi;
        const double t0 = ea_bench_now();
        ea_fe_modes(m, &mi, NULL);
        tt[r] = ea_bench_now() - t0;
        ta[r] = mi.time_assembly_s;
        te[r] = mi.time_eigen_s;
      }
      printf("| %s | %d | %.1f | %.1f | %.1f |\n", bn[b], tm[i], 1e6 * ea_bench_median(ta, R),
             1e6 * ea_bench_median(te, R), 1e6 * ea_bench_median(tt, R));
      ea_fe_model_free(m);
    }

  /* 3. Fig. 5 sweep: 100 cable lengths, ODE statics + FE Newton + modes, per band backend */
  printf("\n## Fig. 5 sweep: 100 cable lengths 0.254..0.635 m, alpha = 0 (default mesh)\n");
  const ea_fe_eig_backend_t sweep_be[2] = {EA_FE_EIG_DSBGVX, EA_FE_EIG_LANCZOS};
  ea_fe_model_t *m = NULL;
  for (int b = 0; b < 2; ++b) {
    ea_fe_model_free(m);
    m = model(&a, EA_FE_DEFAULT_ELEMENTS, sweep_be[b]);
    double ts[5], f_first[3] = {0}, f_last[3] = {0};
    for (int rep = 0; rep < 5; ++rep) {
      const double t0 = ea_bench_now();
      double guess[EA_NP];
      int have = 0;
      for (int k = 0; k < 100; ++k) {
        const double Lc = 0.254 + (0.635 - 0.254) * k / 99.0;
        ea_fe_modes_info_t mi;
        if (fe_at(m, sh, Lc, 0.0, have ? guess : NULL, &sol) || ea_fe_modes(m, &mi, NULL)) {
          fprintf(stderr, "sweep failed at Lc = %g\n", Lc);
          return 1;
        }
        memcpy(guess, sol.p, sizeof guess);
        have = 1;
        if (k == 0) memcpy(f_first, mi.freq_hz, sizeof f_first);
        if (k == 99) memcpy(f_last, mi.freq_hz, sizeof f_last);
      }
      ts[rep] = ea_bench_now() - t0;
    }
    printf("%s: time per sweep (median of 5): %.1f ms\n", bn[sweep_be[b]],
           1e3 * ea_bench_median(ts, 5));
    printf("f1 %.4f -> %.4f Hz (+%.1f %% as the cable shortens), f2 %.4f -> %.4f (+%.1f %%), "
           "f3 %.4f -> %.4f (+%.1f %% as it lengthens)\n",
           f_last[0], f_first[0], 100 * (f_first[0] / f_last[0] - 1), f_first[1], f_last[1],
           100 * (f_last[1] / f_first[1] - 1), f_first[2], f_last[2],
           100 * (f_last[2] / f_first[2] - 1));
  }

  /* 4. transient: shoulder move of 0.2 rad in 3 s (smooth), hold 2 s, passive cable */
  printf(
      "\n## Transient: 5 s (3 s shoulder move of 0.2 rad + 2 s hold), passive cable, Lc = 0.4 m\n");
  printf("| dt [ms] | steps | Newton it | wall [ms] | x real time | residual rms [mm] | peak [mm] "
         "|\n");
  printf("|---|---|---|---|---|---|---|\n");
  const double dts[3] = {2e-3, 1e-3, 5e-4};
  for (int i = 0; i < 3; ++i) {
    if (fe_at(m, sh, 0.4, 0.0, NULL, &sol)) {
      fprintf(stderr, "transient: static start failed\n");
      return 1;
    }
    ea_fe_cable_make_passive(m);
    enum { NS = 61 };
    double tt[NS], th[NS];
    for (int k = 0; k < NS; ++k) {
      tt[k] = 3.0 * k / (NS - 1);
      const double u = tt[k] / 3.0;
      th[k] = sol.p[EA_P_THETA0] + 0.2 * (u * u * u * (10 - 15 * u + 6 * u * u));
    }
    double q0[3 * 65];
    ea_fe_get_state(m, q0, NULL);
    for (int k = 0; k < NS; ++k)
      th[k] += q0[2] - sol.p[EA_P_THETA0];
    ea_fe_samples_t hs = {NS, tt, th, NULL};
    ea_fe_drive_t drv = {ea_fe_samples_eval, &hs, NULL, NULL};
    ea_fe_sim_settings_t ss;
    ea_fe_sim_settings_default(&ss);
    ss.dt = dts[i];
    ss.t_end = 5.0;
    ss.t_motion_end = 3.0;
    ea_fe_sim_info_t si;
    ea_error_t e;
    if (ea_fe_simulate(m, &drv, &ss, NULL, 0, &si, &e)) {
      fprintf(stderr, "simulate: %s\n", e.msg);
      return 1;
    }
    printf("| %.1f | %d | %d | %.1f | %.1f | %.4f | %.4f |\n", 1e3 * dts[i], si.steps,
           si.newton_iterations, 1e3 * si.time_s, 5.0 / si.time_s, 1e3 * si.residual_rms,
           1e3 * si.residual_peak);
  }
  ea_fe_model_free(m);
  ea_shooter_free(sh);
  return 0;
}
