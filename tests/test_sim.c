/* The FE transient of trajectories (ea_traj_simulate), the vibration ground truth, against
 * answers from outside it:
 *  - the dt -> 0 limit (Richardson extrapolation of dt/4 and dt/8, second order) of the
 *    residual vibration of planned examples, and of the paper line on a cable 10x stiffer:
 *    the default settings must be within 1 % of it;
 *  - the observed order in dt of a driven transient with a moving cable length (both schemes);
 *  - a slow cable-length ramp against the ODE statics along it (the quasi-static limit), the
 *    error falling as the ramp slows (the lag ~ acceleration / omega1^2);
 *  - a single linear mode after a cycloid: zero residual when it lasts whole periods, and the
 *    closed-form ratio of the residuals after 1.5 and 2.5 periods;
 *  - a small cycloidal cable-length ramp (passive cable, moving rest length) against the
 *    closed-form Duhamel integral of one linear mode (FE f1 and modal forcing at the start),
 *    and the observed order in dt of that transient against its dt -> 0 limit;
 *  - a plan run on arms it was not planned for (hand mass x0.7..1.3, EI x0.9..1.1, payload
 *    0..0.1 kg; default scheme and dt), and at every default setting the payloads 0.04..0.07 kg
 *    and hand -20 % / EI +5 %: every run starts and ends, and its final equilibrium matches an
 *    independent solve of the ODE statics under the same held inputs (shoulder angle, cable
 *    rest length). */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_simulate.h"
#include "ea_test.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *src;

/* Plan an example task; returns 0 on success. */
static int plan_example(const char *name, ea_traj_t *tr, ea_arm_t *arm) {
  char path[1024];
  snprintf(path, sizeof path, "%s/problems/examples/%s", src, name);
  ea_task_t task;
  ea_error_t e;
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  int rc = 1;
  if (ea_task_load(path, NULL, &task, &e) || ea_planner_alloc(&task, &pl, &e) ||
      ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e) || ea_planner_trajectory(pl, tr, &e)) {
    printf("%s: %s\n", name, e.msg);
    goto out;
  }
  *arm = task.arm;
  rc = 0;
out:
  ea_planner_free(pl);
  return rc;
}

static double sim_peak(const ea_arm_t *arm, const ea_traj_t *tr, ea_fe_scheme_t scheme, double dt,
                       ea_sim_info_t *out) {
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  s.scheme = scheme;
  s.dt = dt;
  ea_sim_info_t si;
  ea_error_t e;
  if (ea_traj_simulate(arm, tr, 0.0, &s, NULL, &si, &e)) {
    printf("simulate: %s\n", e.msg);
    return NAN;
  }
  if (out) *out = si;
  return si.residual_peak;
}

/* 1. default dt against the dt -> 0 limit */
static void test_default_converged(void) {
  const char *names[] = {"paper-line.yaml", "paper-line-smooth.yaml", "polyline-effort.yaml",
                         "paper-line.yaml"};
  for (int c = 0; c < 4; ++c) {
    ea_traj_t tr = {0};
    ea_arm_t arm;
    if (plan_example(names[c], &tr, &arm)) {
      ea_test_true(0, "example planned");
      continue;
    }
    if (c == 3) arm.EA_cable *= 10; /* the stiffer cable: the hard case for the old scheme */
    ea_sim_settings_t d;
    ea_sim_settings_default(&d);
    ea_sim_info_t si = {0};
    const double r0 = sim_peak(&arm, &tr, d.scheme, d.dt, &si);
    const double r4 = sim_peak(&arm, &tr, d.scheme, d.dt / 4, NULL);
    const double r8 = sim_peak(&arm, &tr, d.scheme, d.dt / 8, NULL);
    const double lim = r8 + (r8 - r4) / 3.0;
    const double rg = sim_peak(&arm, &tr, EA_FE_SCHEME_ENERGY, d.dt, NULL);
    printf("%s%s: residual peak %.6f mm at dt %g (%d Newton it), %.6f at dt/4, %.6f at dt/8, "
           "limit %.6f; energy scheme at dt %.6f; time to rest %s\n",
           names[c], c == 3 ? " (EA_c x 10)" : "", 1e3 * r0, d.dt, si.newton_iterations, 1e3 * r4,
           1e3 * r8, 1e3 * lim, 1e3 * rg, isfinite(si.time_to_rest) ? "reached" : "not reached");
    char what[160];
    snprintf(what, sizeof what, "%s%s: default residual within 1 %% of the dt -> 0 limit", names[c],
             c == 3 ? " EA_c x10" : "");
    ea_test_rel(r0, lim, 0.01, what);
    snprintf(what, sizeof what, "%s%s: the energy scheme at the default dt, within 1 %%", names[c],
             c == 3 ? " EA_c x10" : "");
    ea_test_rel(rg, lim, 0.01, what);
    ea_traj_free(&tr);
  }
}

/* A trajectory along (L_c(t), alpha) from the ODE statics: n samples over [0, tf] of a
 * quintic smoothstep from L_a to L_b at fixed alpha (rates exact for L_c; theta0 rates by
 * centred differences of the statics). */
static int ramp_traj(const ea_arm_t *arm, double La, double Lb, double alpha, double tf, int n,
                     ea_traj_t *tr) {
  if (ea_traj_alloc(tr, n)) return 1;
  tr->payload_kg = 0.0;
  tr->tip_mass_kg = arm->m_hand;
  for (int i = 0; i < n; ++i) {
    const double t = tf * i / (n - 1), u = t / tf;
    const double s = u * u * u * (10 - 15 * u + 6 * u * u), sd = 30 * u * u * (1 - u) * (1 - u);
    EA_TRAJ_AT(tr, i, EA_TRAJ_t) = t;
    EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length) = La + (Lb - La) * s;
    EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length_rate) = (Lb - La) * sd / tf;
    EA_TRAJ_AT(tr, i, EA_TRAJ_cable_angle) = alpha;
  }
  ea_shooter_t *sh = NULL;
  ea_error_t e;
  if (ea_shooter_alloc(arm, NULL, &sh, &e)) return 1;
  const ea_load_t load = {arm->m_hand};
  ea_shooter_set_load(sh, &load);
  const int st = ea_traj_fill_statics(tr, sh, &e);
  ea_shooter_free(sh);
  if (st) {
    printf("ramp statics: %s\n", e.msg);
    return 1;
  }
  for (int i = 1; i < n - 1; ++i)
    EA_TRAJ_AT(tr, i, EA_TRAJ_theta0_rate) =
        (EA_TRAJ_AT(tr, i + 1, EA_TRAJ_theta0) - EA_TRAJ_AT(tr, i - 1, EA_TRAJ_theta0)) /
        (EA_TRAJ_AT(tr, i + 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, i - 1, EA_TRAJ_t));
  return 0;
}

/* 2. observed order in dt of a driven transient (moving cable length, 1.5 s ramp) */
static void test_order(void) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  ea_traj_t tr = {0};
  if (ramp_traj(&arm, 0.30, 0.40, -0.3, 1.5, 151, &tr)) {
    ea_test_true(0, "ramp trajectory");
    return;
  }
  for (int sc = 0; sc < 2; ++sc) {
    ea_sim_history_t h[3] = {{0}, {0}, {0}};
    const double dts[3] = {2e-3, 1e-3, 5e-4};
    int ok = 1;
    for (int k = 0; k < 3; ++k) {
      ea_sim_settings_t s;
      ea_sim_settings_default(&s);
      s.scheme = sc ? EA_FE_SCHEME_GENALPHA : EA_FE_SCHEME_ENERGY;
      s.dt = dts[k];
      s.settle = 0.5;
      s.keep_history = 1;
      ea_error_t e;
      ok = ok && ea_traj_simulate(&arm, &tr, 0.0, &s, &h[k], NULL, &e) == EA_OK;
    }
    double e01 = 0.0, e12 = 0.0;
    if (ok) /* common times: every 2 ms, i.e. rows 1:2:4 of the three runs */
      for (int r = 0; r < h[0].rows && 4 * r < h[2].rows; ++r)
        for (int c = 1; c <= 2; ++c) {
          e01 = fmax(e01, fabs(h[0].data[6 * r + c] - h[1].data[6 * 2 * r + c]));
          e12 = fmax(e12, fabs(h[1].data[6 * 2 * r + c] - h[2].data[6 * 4 * r + c]));
        }
    const double p = log2(e01 / e12);
    printf("%s: tip history differences %.3e (2 -> 1 ms), %.3e (1 -> 0.5 ms): observed order "
           "%.3f\n",
           sc ? "genalpha" : "energy", e01, e12, p);
    ea_test_abs(p, 2.0, 0.25,
                sc ? "genalpha: observed order 2 (driven, moving cable length)"
                   : "energy: observed order 2 (driven, moving cable length)");
    for (int k = 0; k < 3; ++k)
      ea_sim_history_free(&h[k]);
  }
  ea_traj_free(&tr);
}

/* 3. a slow ramp against the ODE statics along it */
static void test_slow_ramp(void) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  ea_shooter_t *sh = NULL;
  if (ea_shooter_alloc(&arm, NULL, &sh, NULL)) return;
  const ea_load_t load = {arm.m_hand};
  ea_shooter_set_load(sh, &load);
  double err_T[2];
  const double Tr[2] = {4.0, 8.0};
  for (int k = 0; k < 2; ++k) {
    ea_traj_t tr = {0};
    if (ramp_traj(&arm, 0.30, 0.40, -0.3, Tr[k], (int)(40 * Tr[k]) + 1, &tr)) {
      ea_test_true(0, "slow ramp trajectory");
      break;
    }
    ea_sim_settings_t s;
    ea_sim_settings_default(&s);
    s.settle = 0.0;
    s.keep_history = 1;
    ea_sim_history_t h = {0};
    ea_error_t e;
    err_T[k] = NAN;
    if (ea_traj_simulate(&arm, &tr, 0.0, &s, &h, NULL, &e) == EA_OK) {
      double worst = 0.0, guess[EA_NP];
      int have = 0;
      for (int r = 0; r < h.rows; r += 50) { /* every 50 ms */
        const double t = h.data[6 * r], u = t / Tr[k];
        const double L = 0.30 + 0.10 * u * u * u * (10 - 15 * u + 6 * u * u);
        ea_statics_problem_t pr = ea_statics_problem_cable(L, -0.3);
        ea_statics_solution_t sol;
        if (ea_statics_solve(sh, &pr, NULL, have ? guess : NULL, &sol, NULL)) continue;
        memcpy(guess, sol.p, sizeof guess);
        have = 1;
        worst = fmax(
            worst, hypot(h.data[6 * r + 1] - sol.tip[EA_X_X], h.data[6 * r + 2] - sol.tip[EA_X_Y]));
      }
      err_T[k] = worst;
    }
    printf("slow ramp 0.30 -> 0.40 m in %.0f s: max |tip_FE - tip_ODE(L_c(t))| %.3e m\n", Tr[k],
           err_T[k]);
    ea_sim_history_free(&h);
    ea_traj_free(&tr);
  }
  /* a quasi-static follower lags by ~ acceleration / omega1^2, i.e. ~ 1 / Tr^2: measured
   * 2.1e-4 m at 4 s, 5.3e-5 m at 8 s (ratio 3.9); the FE-ODE static offset is ~3e-6 m */
  ea_test_rel(err_T[0] / err_T[1], 4.0, 0.15, "slow ramp: error / ramp time^-2 (4 s vs 8 s)");
  ea_test_true(err_T[1] < 1e-4, "8 s ramp: FE tip within 0.1 mm of the ODE statics");
  ea_shooter_free(sh);
}

/* 4. one linear mode after a cycloid of the shoulder angle */
static double cycloid_residual(const ea_arm_t *arm, double th0, double L, double alpha,
                               double Lrest, double A, double T, double settle) {
  const int n = 401;
  ea_traj_t tr = {0};
  if (ea_traj_alloc(&tr, n)) return NAN;
  tr.tip_mass_kg = arm->m_hand;
  for (int i = 0; i < n; ++i) {
    const double t = T * i / (n - 1), w = 2 * M_PI / T;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_t) = t;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_length) = L;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_angle) = alpha;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_theta0) = th0 + A * (t / T - sin(w * t) / (2 * M_PI));
    EA_TRAJ_AT(&tr, i, EA_TRAJ_theta0_rate) = A * (1 - cos(w * t)) / T;
    /* the cable's rest length held: T = EA_c (L / L0 - 1) at the constant L */
    EA_TRAJ_AT(&tr, i, EA_TRAJ_tension) = arm->EA_cable * (L / Lrest - 1.0);
  }
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  s.settle = settle;
  ea_sim_info_t si;
  ea_error_t e;
  double r = NAN;
  if (ea_traj_simulate(arm, &tr, 0.0, &s, NULL, &si, &e) == EA_OK)
    r = si.residual_peak;
  else
    printf("cycloid: %s\n", e.msg);
  ea_traj_free(&tr);
  return r;
}

static void test_cycloid(void) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  ea_shooter_t *sh = NULL;
  ea_fe_model_t *m = NULL;
  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  const ea_load_t load = {arm.m_hand};
  if (ea_shooter_alloc(&arm, NULL, &sh, NULL) || ea_fe_model_alloc(&arm, &fs, &m, NULL)) return;
  ea_shooter_set_load(sh, &load);
  ea_fe_model_set_load(m, &load);
  const double L = 0.40, alpha = -0.3;
  ea_statics_problem_t pr = ea_statics_problem_cable(L, alpha);
  ea_statics_solution_t sol;
  ea_fe_static_info_t fi;
  ea_fe_modes_info_t mi;
  if (ea_statics_solve(sh, &pr, NULL, NULL, &sol, NULL) ||
      ea_fe_static_solve(m, sh, &sol, &fi, NULL) || ea_fe_modes(m, &mi, NULL)) {
    ea_test_true(0, "cycloid: start state");
    goto out;
  }
  const double f1 = mi.freq_hz[0];
  const double Lrest = ea_fe_cable_rest_length(fi.cable_length, fi.tension, arm.EA_cable);
  const double A = 2e-3; /* [rad]: small, a linear response */
  double R[3];
  const double k[3] = {1.5, 2.0, 2.5};
  for (int i = 0; i < 3; ++i) {
    R[i] = cycloid_residual(&arm, fi.theta0, fi.cable_length, fi.cable_angle, Lrest, A, k[i] / f1,
                            3.0);
  }
  /* closed form, one undamped mode driven by the cycloid's acceleration: residual amplitude
   * proportional to |sin(omega T / 2)| / (k (k^2 - 1)) for T = k periods */
  const double want = (2.5 * (2.5 * 2.5 - 1)) / (1.5 * (1.5 * 1.5 - 1));
  printf("cycloid of %.0e rad at f1 = %.4f Hz: residual peak %.4e / %.4e / %.4e m after 1.5 / "
         "2 / 2.5 periods; ratio 1.5:2.5 %.4f (one mode: %.4f)\n",
         A, f1, R[0], R[1], R[2], R[0] / R[2], want);
  /* measured 1.8e-3 with the default generalized-alpha (1.8e-4 with the energy scheme: the
   * other modes, the change of f1 along the small motion); tolerance 3x */
  ea_test_rel(R[0] / R[2], want, 5e-3, "cycloid: residual ratio 1.5 vs 2.5 periods (one mode)");
  /* measured 8e-4 of the 1.5-period residual; tolerance 5x */
  ea_test_true(R[1] < 4e-3 * R[0], "cycloid lasting whole periods: residual < 0.4 % of 1.5's");
out:
  ea_fe_model_free(m);
  ea_shooter_free(sh);
}

/* 4b. a small cycloidal cable-length ramp L_c(t) = L + dL (t / T - sin(Omega t) / (2 pi)),
 * Omega = 2 pi / T, on the passive cable (rest length moving with L_c), against one linear
 * mode: eta'' + omega^2 eta = -B q'' with q'' = dL Omega sin(Omega t) / T. The Duhamel
 * integral over the ramp in closed form,
 *   |int_0^T q''(tau) exp(-i omega tau) dtau| = (dL Omega / T) 2 Omega |sin(omega T / 2)|
 *                                               / |Omega^2 - omega^2|,
 * gives the free vibration after it: |eta| = |B| / omega times that, tip amplitude
 * |tip_1| |eta| (omega, B, tip_1 of the FE at the start configuration, ea_rom_point). */
static double cyc_ramp_residual(const ea_arm_t *arm, double L, double dL, double alpha, double T,
                                double dt, ea_fe_scheme_t scheme, double settle,
                                ea_sim_history_t *h) {
  const int n = 401;
  ea_traj_t tr = {0};
  if (ea_traj_alloc(&tr, n)) return NAN;
  tr.payload_kg = 0.0;
  tr.tip_mass_kg = arm->m_hand;
  const double W = 2 * M_PI / T;
  for (int i = 0; i < n; ++i) {
    const double t = T * i / (n - 1);
    EA_TRAJ_AT(&tr, i, EA_TRAJ_t) = t;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_length) = L + dL * (t / T - sin(W * t) / (2 * M_PI));
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_length_rate) = dL * (1 - cos(W * t)) / T;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_angle) = alpha;
  }
  ea_shooter_t *sh = NULL;
  ea_error_t e;
  double r = NAN;
  const ea_load_t load = {arm->m_hand};
  if (ea_shooter_alloc(arm, NULL, &sh, &e)) goto out;
  ea_shooter_set_load(sh, &load);
  if (ea_traj_fill_statics(&tr, sh, &e)) {
    printf("cable ramp statics: %s\n", e.msg);
    goto out;
  }
  for (int i = 0; i < n; ++i) { /* theta0 rates: centred differences (one-sided at rest ends) */
    const int a = i > 0 ? i - 1 : i, b = i < n - 1 ? i + 1 : i;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_theta0_rate) =
        (i == 0 || i == n - 1)
            ? 0.0
            : (EA_TRAJ_AT(&tr, b, EA_TRAJ_theta0) - EA_TRAJ_AT(&tr, a, EA_TRAJ_theta0)) /
                  (EA_TRAJ_AT(&tr, b, EA_TRAJ_t) - EA_TRAJ_AT(&tr, a, EA_TRAJ_t));
  }
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  s.scheme = scheme;
  s.dt = dt;
  s.settle = settle;
  s.keep_history = h != NULL;
  ea_sim_info_t si;
  if (ea_traj_simulate(arm, &tr, 0.0, &s, h, &si, &e) == EA_OK)
    r = si.residual_peak;
  else
    printf("cable ramp: %s\n", e.msg);
out:
  ea_shooter_free(sh);
  ea_traj_free(&tr);
  return r;
}

static void test_cable_ramp_duhamel(void) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  ea_rom_t *rom = NULL;
  ea_rom_point_t pt;
  ea_error_t e;
  const double L = 0.40, alpha = -0.3;
  if (ea_rom_alloc(&arm, arm.m_hand, NULL, &rom, &e) || ea_rom_point(rom, L, alpha, 0, &pt, &e)) {
    printf("reduced model point: %s\n", e.msg);
    ea_test_true(0, "cable ramp: FE modal data at the start");
    ea_rom_free(rom);
    return;
  }
  ea_rom_free(rom);
  const double w = sqrt(pt.omega2[0]), B = fabs(pt.B[0][0]),
               tipn = hypot(pt.tip[0][0], pt.tip[0][1]);
  const double k[2] = {1.5, 2.5}, dLs[2] = {2e-3, 1e-3};
  double rel[2][2]; /* [amplitude][periods]: FE / Duhamel - 1 */
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const double T = k[i] * 2 * M_PI / w, W = 2 * M_PI / T, dL = dLs[j];
      const double duh = (dL * W / T) * 2 * W * fabs(sin(w * T / 2)) / fabs(W * W - w * w);
      const double want = tipn * B / w * duh;
      const double got =
          cyc_ramp_residual(&arm, L, dL, alpha, T, 1e-3, EA_FE_SCHEME_GENALPHA, 3.0, NULL);
      rel[j][i] = got / want - 1;
      printf("cable ramp %.0f mm over %.1f periods (f1 %.4f Hz, B %.4g sqrt(kg), |tip_1| %.4g "
             "m/sqrt(kg)): FE residual peak %.5e m, one-mode Duhamel %.5e m (%+.2e)\n",
             1e3 * dL, k[i], w / (2 * M_PI), B, tipn, got, want, rel[j][i]);
    }
  /* measured +4.0e-3 / +3.5e-3 at 1 mm, +7.8e-3 / +6.4e-3 at 2 mm: the difference is first
   * order in dL (the change of f1 and B along the ramp, the quadratic forcing q'^T C q');
   * extrapolated to dL -> 0 (2 r(1 mm) - r(2 mm)) what is left is the other modes and the time
   * step: measured 1.6e-4 / 6.6e-4. Tolerances 3x. */
  for (int i = 0; i < 2; ++i) {
    char what[160];
    snprintf(what, sizeof what, "1 mm cable ramp, %.1f periods: FE residual = one-mode Duhamel",
             k[i]);
    ea_test_abs(rel[1][i], 0.0, 1.2e-2, what);
    snprintf(what, sizeof what,
             "cable ramp, %.1f periods, extrapolated to dL -> 0: FE = one-mode Duhamel", k[i]);
    ea_test_abs(2 * rel[1][i] - rel[0][i], 0.0, 2e-3, what);
  }

  /* observed order in dt against the dt -> 0 limit (dt = 1/16 ms) for this moving-cable
   * drive: tip history errors at dt 2, 1, 0.5 ms at their common times */
  const double T = 1.5 * 2 * M_PI / w;
  for (int sc = 0; sc < 2; ++sc) {
    const ea_fe_scheme_t scheme = sc ? EA_FE_SCHEME_GENALPHA : EA_FE_SCHEME_ENERGY;
    ea_sim_history_t ref = {0}, h[3] = {{0}, {0}, {0}};
    const double dts[3] = {2e-3, 1e-3, 5e-4}, dref = 1e-3 / 16;
    int ok = isfinite(cyc_ramp_residual(&arm, L, 2e-3, alpha, T, dref, scheme, 0.5, &ref));
    double err[3];
    for (int d = 0; d < 3 && ok; ++d) {
      ok = isfinite(cyc_ramp_residual(&arm, L, 2e-3, alpha, T, dts[d], scheme, 0.5, &h[d]));
      const int stride = (int)lround(dts[d] / dref);
      err[d] = 0.0;
      for (int r = 0; ok && r < h[d].rows && stride * r < ref.rows; ++r)
        err[d] = fmax(err[d], hypot(h[d].data[6 * r + 1] - ref.data[6 * stride * r + 1],
                                    h[d].data[6 * r + 2] - ref.data[6 * stride * r + 2]));
    }
    const double p1 = ok ? log2(err[0] / err[1]) : NAN, p2 = ok ? log2(err[1] / err[2]) : NAN;
    printf("%s, cable ramp vs dt = 1/16 ms: tip history error %.3e / %.3e / %.3e m at dt 2 / 1 "
           "/ 0.5 ms: observed order %.3f, %.3f\n",
           sc ? "genalpha" : "energy", ok ? err[0] : NAN, ok ? err[1] : NAN, ok ? err[2] : NAN, p1,
           p2);
    ea_test_abs(p1, 2.0, 0.25,
                sc ? "genalpha: order 2 against the dt -> 0 limit (2 -> 1 ms)"
                   : "energy: order 2 against the dt -> 0 limit (2 -> 1 ms)");
    ea_test_abs(p2, 2.0, 0.25,
                sc ? "genalpha: order 2 against the dt -> 0 limit (1 -> 0.5 ms)"
                   : "energy: order 2 against the dt -> 0 limit (1 -> 0.5 ms)");
    ea_sim_history_free(&ref);
    for (int d = 0; d < 3; ++d)
      ea_sim_history_free(&h[d]);
  }
}

/* 5. off-nominal arms: the ODE statics under held theta0 and rest length L0 (the tension T
 * such that the tip of the (T, theta0) problem is L0 (1 + T / EA_c) from the cable root) */
typedef struct {
  ea_shooter_t *sh;
  double theta0, L0, EA_c;
  double tip[2];
  double guess[EA_NP];
  int have;
} held_t;

static double held_f(double T, void *data) {
  held_t *h = data;
  ea_statics_problem_t pr = ea_statics_problem_tension_theta0(T, h->theta0);
  ea_statics_solution_t sol;
  if (ea_statics_solve(h->sh, &pr, NULL, h->have ? h->guess : NULL, &sol, NULL) &&
      ea_statics_solve(h->sh, &pr, NULL, NULL, &sol, NULL))
    return NAN;
  memcpy(h->guess, sol.p, sizeof h->guess);
  h->have = 1;
  h->tip[0] = sol.tip[EA_X_X];
  h->tip[1] = sol.tip[EA_X_Y];
  return sol.cable_length - h->L0 * (1.0 + T / h->EA_c);
}

static int held_equilibrium(const ea_arm_t *arm, double tip_mass, double theta0, double L0,
                            double T_guess, double tip[2]) {
  held_t h = {NULL, theta0, L0, arm->EA_cable, {0, 0}, {0}, 0};
  if (ea_shooter_alloc(arm, NULL, &h.sh, NULL)) return 1;
  const ea_load_t load = {tip_mass};
  ea_shooter_set_load(h.sh, &load);
  gsl_function F = {held_f, &h};
  gsl_root_fsolver *s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  double lo = 0.5 * T_guess, hi = 1.5 * T_guess;
  int rc = 1;
  const double flo = held_f(lo, &h), fhi = held_f(hi, &h);
  if (s && isfinite(flo) && isfinite(fhi) && flo * fhi < 0 && !gsl_root_fsolver_set(s, &F, lo, hi))
    for (int it = 0; it < 100; ++it) {
      gsl_root_fsolver_iterate(s);
      lo = gsl_root_fsolver_x_lower(s);
      hi = gsl_root_fsolver_x_upper(s);
      if (hi - lo < 1e-10 * hi) {
        held_f(0.5 * (lo + hi), &h);
        tip[0] = h.tip[0];
        tip[1] = h.tip[1];
        rc = 0;
        break;
      }
    }
  gsl_root_fsolver_free(s);
  ea_shooter_free(h.sh);
  return rc;
}

static void test_off_nominal(void) {
  ea_traj_t tr = {0};
  ea_arm_t nom;
  if (plan_example("paper-line.yaml", &tr, &nom)) {
    ea_test_true(0, "paper line planned");
    return;
  }
  const int n = tr.n;
  const double th_end = EA_TRAJ_AT(&tr, n - 1, EA_TRAJ_theta0);
  const double L0_end =
      ea_fe_cable_rest_length(EA_TRAJ_AT(&tr, n - 1, EA_TRAJ_cable_length),
                              EA_TRAJ_AT(&tr, n - 1, EA_TRAJ_tension), nom.EA_cable);
  const double T_end = EA_TRAJ_AT(&tr, n - 1, EA_TRAJ_tension);
  int runs = 0, ok = 0;
  double worst = 0.0, sag_max = 0.0;
  const double hm[7] = {0.7, 0.8, 0.9, 1.0, 1.1, 1.2, 1.3}, ei[5] = {0.9, 0.95, 1.0, 1.05, 1.1};
  const double pay[3] = {0.0, 0.05, 0.1};
  for (int p = 0; p < 3; ++p)
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < 5; ++j) {
        if (p > 0 && ((i != 0 && i != 3 && i != 6) || (j != 0 && j != 2 && j != 4))) continue;
        ea_arm_t arm = nom;
        arm.m_hand *= hm[i];
        arm.EI *= ei[j];
        const double tm = ea_arm_tip_mass(&arm, pay[p]);
        ea_sim_settings_t s;
        ea_sim_settings_default(&s); /* the default scheme and dt */
        s.settle = 0.01;
        ea_sim_info_t si;
        ea_error_t e;
        ++runs;
        if (ea_traj_simulate(&arm, &tr, tm, &s, NULL, &si, &e)) {
          printf("hand x%.2f EI x%.2f payload %.2f kg: %s\n", hm[i], ei[j], pay[p], e.msg);
          continue;
        }
        double tip[2];
        if (held_equilibrium(&arm, tm, th_end, L0_end, T_end, tip)) {
          printf("hand x%.2f EI x%.2f payload %.2f kg: ODE re-solve failed\n", hm[i], ei[j],
                 pay[p]);
          continue;
        }
        ++ok;
        const double d = hypot(si.final_static_tip[0] - tip[0], si.final_static_tip[1] - tip[1]);
        worst = fmax(worst, d);
        sag_max = fmax(sag_max, si.static_offset_end);
      }
  printf("off-nominal arms: %d of %d runs started and matched; final equilibrium vs the ODE "
         "statics under the held inputs: worst %.3e m (largest offset from the planned goal "
         "%.1f mm)\n",
         ok, runs, worst, 1e3 * sag_max);
  ea_test_true(ok == runs, "every off-nominal arm (hand x0.7..1.3, EI x0.9..1.1, payload "
                           "0..0.1 kg) simulates");
  /* the FE and the ODE differ by the beam's extensibility: measured ~1e-6 m at the nominal
   * arm (test_fe); tolerance 1e-5 m against sags of tens of millimetres */
  ea_test_true(worst < 1e-5, "final equilibria match the ODE statics under the held inputs");

  /* the points the outside review found failing (start equilibrium or step 3 not converging),
   * with every setting at its default (settle included): the nominal arm with payload 0.04,
   * 0.05, 0.06, 0.07 kg, and hand mass -20 % with EI +5 % */
  const struct {
    double hand, EI, payload;
  } pts[5] = {
      {1.0, 1.0, 0.04}, {1.0, 1.0, 0.05}, {1.0, 1.0, 0.06}, {1.0, 1.0, 0.07}, {0.8, 1.05, 0.0}};
  int ok2 = 0;
  double worst2 = 0.0;
  for (int k = 0; k < 5; ++k) {
    ea_arm_t arm = nom;
    arm.m_hand *= pts[k].hand;
    arm.EI *= pts[k].EI;
    const double tm = ea_arm_tip_mass(&arm, pts[k].payload);
    ea_sim_settings_t s;
    ea_sim_settings_default(&s);
    ea_sim_info_t si;
    ea_error_t e;
    double tip[2];
    if (ea_traj_simulate(&arm, &tr, tm, &s, NULL, &si, &e)) {
      printf("default settings, hand x%.2f EI x%.2f payload %.2f kg: %s\n", pts[k].hand, pts[k].EI,
             pts[k].payload, e.msg);
      continue;
    }
    if (held_equilibrium(&arm, tm, th_end, L0_end, T_end, tip)) {
      printf("default settings, payload %.2f kg: ODE re-solve failed\n", pts[k].payload);
      continue;
    }
    const double d = hypot(si.final_static_tip[0] - tip[0], si.final_static_tip[1] - tip[1]);
    printf("default settings, hand x%.2f EI x%.2f payload %.2f kg: %d steps, residual peak %.3f "
           "mm, final equilibrium %.2f mm from the planned goal, %.3e m from the ODE statics\n",
           pts[k].hand, pts[k].EI, pts[k].payload, si.steps, 1e3 * si.residual_peak,
           1e3 * si.static_offset_end, d);
    ++ok2;
    worst2 = fmax(worst2, d);
  }
  ea_test_true(ok2 == 5, "default settings: payload 0.04 / 0.05 / 0.06 / 0.07 kg and hand "
                         "-20 % with EI +5 % simulate to the end");
  /* measured 1.6e-8 .. 5.1e-7 m for the payloads, 1.7e-6 m for hand -20 %; tolerance 1e-5 m */
  ea_test_true(worst2 < 1e-5, "default settings: their final equilibria match the ODE statics");
  ea_traj_free(&tr);
}

int main(void) {
  gsl_set_error_handler_off();
  src = getenv("EA_SOURCE_DIR");
  if (!src) {
    printf("EA_SOURCE_DIR not set (run through ctest)\n");
    return EXIT_FAILURE;
  }
  test_default_converged();
  test_order();
  test_slow_ramp();
  test_cycloid();
  test_cable_ramp_duhamel();
  test_off_nominal();
  return ea_test_summary("test_sim");
}
