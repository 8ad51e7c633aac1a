/* Synthetic measurement records for the calibration tests and bench, made by the FE model
 * (never by the fitting model): static records from FE static equilibria with the cable at
 * its commanded (unstretched) length, ring-downs from FE transients with Rayleigh damping
 * set to given modal ratios; Gaussian noise from GSL's RNG with a fixed seed. */
#ifndef EA_TEST_CALIB_H
#define EA_TEST_CALIB_H

#include "ea_problems.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* FE equilibrium of arm at commanded cable length L (the cable's rest length) and cable angle
 * about alpha (the ODE statics on the same arm choose theta0; the FE equilibrium then has
 * its own cable angle): m holds it on success. */
static inline ea_status_t ea_tc_equilibrium(const ea_arm_t *arm, ea_fe_model_t *m, double L,
                                            double alpha, double payload, ea_error_t *err) {
  ea_shooter_t *sh = NULL;
  ea_status_t st = ea_shooter_alloc(arm, NULL, &sh, err);
  if (st) return st;
  ea_load_t load = {arm->m_hand + payload};
  ea_shooter_set_load(sh, &load);
  ea_statics_solution_t sol;
  double T = 0;
  double guess[EA_NP];
  for (int it = 0; it < 4 && !st; ++it) {
    ea_statics_problem_t pr = ea_statics_problem_cable(L * (1 + T / arm->EA_cable), alpha);
    st = ea_statics_solve(sh, &pr, NULL, it ? guess : NULL, &sol, err); /* (sol is cleared) */
    memcpy(guess, sol.p, sizeof guess);
    T = sol.p[EA_P_TENSION];
  }
  if (!st) st = ea_fe_model_set_load(m, &load);
  if (!st) st = ea_fe_static_solve(m, sh, &sol, NULL, err);
  if (!st) st = ea_fe_static_continue(m, sol.p[EA_P_THETA0], EA_FE_CABLE_PASSIVE, L, NULL, err);
  /* the FE equilibrium on the statics' branch (the continuation can leave it near the edge of
   * the workspace: another equilibrium, not the configuration asked for) */
  double Tfe = NAN;
  if (!st) ea_fe_cable_get(m, NULL, NULL, &Tfe, NULL);
  if (!st && !(fabs(Tfe - T) <= 0.01 * T + 0.02))
    st = ea_error_set(err, EA_ERR_NOCONV,
                      "L = %g m, alpha = %g rad: the FE equilibrium (T = %g N) left the statics' "
                      "branch (T = %g N)",
                      L, alpha, Tfe, T);
  ea_shooter_free(sh);
  return st;
}

/* Shoulder torque of the FE state: the clamp balances the moments about the shoulder of the
 * beam's weight (Simpson on each 3-node element, exact for its quadratic interpolation), the
 * tip mass's weight and the cable's pull. */
static inline double ea_tc_fe_torque(const ea_arm_t *arm, const ea_fe_model_t *m, double tip_mass) {
  const int nn = ea_fe_model_nodes(m), ne = (nn - 1) / 2;
  double *q = malloc(sizeof *q * 3 * (size_t)nn);
  if (!q) return NAN;
  ea_fe_get_state(m, q, NULL);
  const double h = arm->length / ne;
  double Mg = 0;
  for (int e = 0; e < ne; ++e)
    Mg -=
        arm->rho * arm->g * h / 6 * (q[3 * (2 * e)] + 4 * q[3 * (2 * e + 1)] + q[3 * (2 * e + 2)]);
  const double xL = q[3 * (nn - 1)], yL = q[3 * (nn - 1) + 1];
  Mg -= tip_mass * arm->g * xL;
  double T, l;
  ea_fe_cable_get(m, NULL, NULL, &T, &l);
  const double Mc = T * (xL * (arm->y_c - yL) - yL * (arm->x_c - xL)) / l;
  free(q);
  return Mg + Mc; /* EI kappa0 (the sign of the statics) */
}

/* Channels of a static record by bit: 1 << EA_CALIB_CH_*. theta0 always. */
typedef struct {
  double noise[EA_CALIB_NCH]; /* standard deviations; 0: exact */
  unsigned channels;          /* which columns besides theta0 */
  int write_noise;            /* write the '# noise_*' headers */
} ea_tc_static_opts_t;

/* A static record at the n configurations (L[i], alpha[i]) with payload pay[i] into path. */
static inline ea_status_t ea_tc_write_static(const char *path, const ea_arm_t *arm, const double *L,
                                             const double *alpha, const double *pay, int n,
                                             const ea_tc_static_opts_t *o, gsl_rng *rng,
                                             ea_error_t *err) {
  ea_fe_model_t *m = NULL;
  ea_status_t st = ea_fe_model_alloc(arm, NULL, &m, err);
  if (st) return st;
  FILE *fp = fopen(path, "w");
  if (!fp) {
    ea_fe_model_free(m);
    return ea_error_set(err, EA_ERR_IO, "%s: cannot write", path);
  }
  fprintf(fp, "# elasticarm-record 1\n# kind: static\n# source: tests/ea_test_calib.h (FE)\n");
  static const char *nk[EA_CALIB_NCH] = {
      "noise_theta0_rad",     "noise_torque_Nm", "noise_tension_N", "noise_tip_m", NULL,
      "noise_cable_angle_rad"};
  const unsigned ch = o->channels | 1u;
  if (o->write_noise)
    for (int c = 0; c < EA_CALIB_NCH; ++c)
      if ((ch >> c) & 1u && nk[c] && o->noise[c] > 0)
        fprintf(fp, "# %s: %.6g\n", nk[c], o->noise[c]);
  fprintf(fp, "cable_length_m,payload_kg");
  for (int c = 0; c < EA_CALIB_NCH; ++c)
    if ((ch >> c) & 1u) fprintf(fp, ",%s", ea_calib_channel_column(c));
  fprintf(fp, "\n");
  for (int i = 0; i < n && !st; ++i) {
    st = ea_tc_equilibrium(arm, m, L[i], alpha[i], pay[i], err);
    if (st == EA_ERR_NOCONV || st == EA_ERR_INADMISSIBLE) { /* an experiment would not hold it */
      st = EA_OK;
      ea_fe_set_straight(m, 0.0);
      continue;
    }
    if (st) break;
    ea_fe_static_info_t fi;
    ea_fe_newton(m, &fi, NULL);
    double v[EA_CALIB_NCH];
    double q0[3];
    double *q = malloc(sizeof *q * 3 * (size_t)ea_fe_model_nodes(m));
    ea_fe_get_state(m, q, NULL);
    q0[0] = q[2];
    free(q);
    double tip[3], T, l;
    ea_fe_tip(m, tip);
    ea_fe_cable_get(m, NULL, NULL, &T, &l);
    v[EA_CALIB_CH_THETA0] = q0[0];
    v[EA_CALIB_CH_TORQUE] = ea_tc_fe_torque(arm, m, arm->m_hand + pay[i]);
    v[EA_CALIB_CH_TENSION] = T;
    v[EA_CALIB_CH_TIP_X] = tip[0];
    v[EA_CALIB_CH_TIP_Y] = tip[1];
    v[EA_CALIB_CH_CABLE_ANGLE] = atan2(tip[1] - arm->y_c, tip[0] - arm->x_c);
    fprintf(fp, "%.17g,%.17g", L[i], pay[i]);
    for (int c = 0; c < EA_CALIB_NCH; ++c)
      if ((ch >> c) & 1u)
        fprintf(fp, ",%.17g", v[c] + (o->noise[c] > 0 ? gsl_ran_gaussian(rng, o->noise[c]) : 0.0));
    fprintf(fp, "\n");
  }
  fclose(fp);
  ea_fe_model_free(m);
  return st;
}

/* Truth of a ring-down: frequencies [Hz] and first-order modal damping ratios of modes 1..3. */
typedef struct {
  double freq_hz[3], zeta[3];
  double theta0; /* the hold */
} ea_tc_ring_truth_t;

/* A ring-down at (L, alpha) with payload: from the FE equilibrium displaced along modes 1..3
 * by amp[k] (metres of the largest nodal displacement), Rayleigh damping a M + b K_mat with
 * modes 1 and 2 at zeta1, zeta2; records tension and tip position every out_every steps of
 * dt for t_end, with noise (tension [N], tip [m]). */
static inline ea_status_t ea_tc_write_ringdown(const char *path, const ea_arm_t *arm, double L,
                                               double alpha, double payload, double zeta1,
                                               double zeta2, const double amp[3], double dt,
                                               int out_every, double t_end, double noise_T,
                                               double noise_tip, gsl_rng *rng,
                                               ea_tc_ring_truth_t *truth, ea_error_t *err) {
  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  fs.modes = 3;
  ea_fe_model_t *m = NULL;
  ea_status_t st = ea_fe_model_alloc(arm, &fs, &m, err);
  if (st) return st;
  const int nn = ea_fe_model_nodes(m);
  double *q = calloc(3 * (size_t)nn, sizeof *q), *phi = calloc(3 * (size_t)nn, sizeof *phi);
  const int nsteps = (int)lround(t_end / dt), rows = nsteps / out_every + 1;
  double *tip = malloc(sizeof *tip * 4 * (size_t)(nsteps + 1));
  FILE *fp = NULL;
  if (!q || !phi || !tip) {
    st = ea_error_set(err, EA_ERR_NOMEM, "oom");
    goto out;
  }
  if ((st = ea_tc_equilibrium(arm, m, L, alpha, payload, err))) goto out;
  ea_fe_modes_info_t mi;
  if ((st = ea_fe_modes(m, &mi, err))) goto out;
  double b_ref, zm[EA_FE_MAX_MODES];
  if ((st = ea_fe_strain_damping(m, 0, 0.01, &b_ref, zm))) goto out;
  double w[3], c[3];
  for (int k = 0; k < 3; ++k) {
    w[k] = 2 * M_PI * mi.freq_hz[k];
    c[k] = zm[k] / b_ref;
  }
  /* zeta_k = a / (2 w_k) + b c_k for k = 1, 2 */
  const double a11 = 1 / (2 * w[0]), a12 = c[0], a21 = 1 / (2 * w[1]), a22 = c[1];
  const double det = a11 * a22 - a12 * a21;
  double ra = (zeta1 * a22 - a12 * zeta2) / det, rb = (a11 * zeta2 - a21 * zeta1) / det;
  if (ra < 0) ra = 0, rb = zeta2 / c[1];
  if (rb < 0) rb = 0, ra = zeta1 * 2 * w[0];
  ea_fe_get_state(m, q, NULL);
  const double theta0 = q[2];
  for (int k = 0; k < 3; ++k) {
    truth->freq_hz[k] = mi.freq_hz[k];
    truth->zeta[k] = ra / (2 * w[k]) + rb * c[k];
    if ((st = ea_fe_mode_shape(m, k, phi))) goto out;
    for (int i = 3; i < 3 * nn; ++i)
      q[i] += amp[k] * phi[i];
  }
  truth->theta0 = theta0;
  if ((st = ea_fe_set_state(m, q, NULL))) goto out;
  if ((st = ea_fe_relax_positions(m, err))) goto out;
  double L0;
  ea_fe_cable_get(m, NULL, &L0, NULL, NULL);
  ea_fe_sim_settings_t ss;
  ea_fe_sim_settings_default(&ss);
  ss.dt = dt;
  ss.t_end = nsteps * dt;
  ss.rayleigh_mass = ra;
  ss.rayleigh_stiffness = rb;
  ss.output_every = 1;
  ea_fe_sim_info_t si;
  if ((st = ea_fe_simulate(m, NULL, &ss, tip, nsteps + 1, &si, err))) goto out;
  fp = fopen(path, "w");
  if (!fp) {
    st = ea_error_set(err, EA_ERR_IO, "%s: cannot write", path);
    goto out;
  }
  fprintf(fp,
          "# elasticarm-record 1\n# kind: ringdown\n# source: tests/ea_test_calib.h (FE "
          "transient)\n# cable_length_m: %.17g\n# theta0_rad: %.17g\n# payload_kg: %.17g\n",
          L, theta0, payload);
  if (noise_T > 0) fprintf(fp, "# noise_tension_N: %.6g\n", noise_T);
  if (noise_tip > 0) fprintf(fp, "# noise_tip_m: %.6g\n", noise_tip);
  fprintf(fp, "t_s,tension_N,tip_x_m,tip_y_m\n");
  for (int r = 0; r < rows && r * out_every < si.rows; ++r) {
    const double *v = tip + 4 * (size_t)(r * out_every);
    const double l = hypot(v[1] - arm->x_c, v[2] - arm->y_c);
    const double T = l > L0 ? arm->EA_cable * (l - L0) / L0 : 0.0;
    fprintf(fp, "%.17g,%.17g,%.17g,%.17g\n", v[0],
            T + (noise_T > 0 ? gsl_ran_gaussian(rng, noise_T) : 0),
            v[1] + (noise_tip > 0 ? gsl_ran_gaussian(rng, noise_tip) : 0),
            v[2] + (noise_tip > 0 ? gsl_ran_gaussian(rng, noise_tip) : 0));
  }
out:
  if (fp) fclose(fp);
  free(q);
  free(phi);
  free(tip);
  ea_fe_model_free(m);
  return st;
}

#endif
