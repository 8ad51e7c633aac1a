/* For the calibration tests: a true arm file, and the session of `controller-sim --simulate
 * --record` run in the library: a planned trajectory resampled at 1 kHz as the streamer sends
 * it (against the arm it was planned on), the trajectory those setpoints describe played on
 * the true arm by its FE transient (energy-conserving scheme, 1 s settle), the records written with
 * default sensor noise (seed 1). The records come from the FE, never from the fitting model. */
#ifndef EA_TEST_RECORD_H
#define EA_TEST_RECORD_H

#include "ea_problems.h"
#include "ea_simulate.h"
#include "ea_stream.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A "true" arm for a calibration test: a copy of the arm file src at dst with EI, the hand
 * mass and the hand's inertia I_L scaled by the given factors and a mode-1 damping ratio zeta
 * (appended: the source must have none); loaded back into *arm and checked. 0 on success. */
static inline int ea_tr_true_arm(const char *src, const char *dst, double f_EI, double f_mass,
                                 double f_IL, double zeta, ea_arm_t *arm) {
  ea_arm_t def;
  ea_error_t e = {0};
  if (ea_arm_load(src, &def, &e)) return 1;
  FILE *in = fopen(src, "r");
  FILE *fo = in ? fopen(dst, "w") : NULL;
  if (!fo) {
    if (in) fclose(in);
    return 1;
  }
  char line[1024];
  while (fgets(line, sizeof line, in)) {
    if (strstr(line, "EI_Nm2:"))
      fprintf(fo, "  EI_Nm2: %.17g\n", f_EI * def.EI);
    else if (strstr(line, "mass_kg:") && strstr(line, "m_h"))
      fprintf(fo, "  mass_kg: %.17g\n", f_mass * def.m_hand);
    else if (f_IL != 1.0 && strstr(line, "Izz_kg_m2:") && strstr(line, "I_L"))
      fprintf(fo, "  Izz_kg_m2: %.17g\n", f_IL * def.I_hand);
    else
      fputs(line, fo);
  }
  fprintf(fo, "damping:\n  modal_ratios: [%.17g]\n", zeta);
  fclose(in);
  if (fclose(fo) || ea_arm_load(dst, arm, &e)) return 1;
  return !(fabs(arm->EI - f_EI * def.EI) < 1e-12 &&
           fabs(arm->m_hand - f_mass * def.m_hand) < 1e-12 &&
           fabs(arm->I_hand - f_IL * def.I_hand) < 1e-15 && arm->n_damping == 1);
}

/* 0 on success; else prints the error (prefixed by what) and returns 1. */
static inline int ea_tr_record_session(const ea_traj_t *tr, const ea_arm_t *plan_arm,
                                       const ea_arm_t *arm, const char *dir, const char *what) {
  ea_setpoint_t *sp = NULL;
  int n = 0;
  ea_error_t e = {0};
  ea_stream_settings_t ss;
  ea_stream_settings_default(&ss);
  if (ea_stream_resample(tr, plan_arm, 1000.0, ss.limit_tol, &sp, &n, &e)) {
    printf("%s: %s\n", what, e.msg);
    return 1;
  }
  double *t = malloc(sizeof(double) * (size_t)n);
  if (!t) {
    free(sp);
    return 1;
  }
  for (int i = 0; i < n; ++i)
    t[i] = i * 1e-3;
  ea_traj_t st = {0};
  ea_sim_history_t h = {0};
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  s.scheme = EA_FE_SCHEME_ENERGY;
  s.settle = 1.0;
  s.keep_history = 1;
  ea_sim_info_t si;
  ea_record_settings_t rs;
  ea_record_settings_default(&rs);
  const int bad = ea_stream_setpoints_traj(arm, arm->m_hand, sp, t, n, &st, NULL, &e) ||
                  ea_traj_simulate(arm, &st, arm->m_hand, &s, &h, &si, &e) ||
                  ea_record_write(dir, &rs, arm, sp, t, n, &h, NULL, &e);
  if (bad) printf("%s: %s\n", what, e.msg);
  ea_sim_history_free(&h);
  ea_traj_free(&st);
  free(t);
  free(sp);
  return bad;
}

#endif
