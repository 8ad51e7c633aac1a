/* Vibration-aware planning (docs/planner.md, "Vibration"). References from
 * outside the planner:
 *  - the frequency model vs direct FE frequencies (ea_statics_solve +
 *    ea_fe_static_solve holding the tip + ea_fe_modes) at off-grid points
 *    (cell centres) along and beside the paper line;
 *  - the FE transient (`elasticarm simulate`, the nonlinear FE model driven
 *    by the plan's theta0(t) and cable rest length): the residual vibration
 *    after the motion of min_vibration vs min_effort and min_jerk plans of
 *    the same duration;
 *  - Ipopt's derivative checker on a min_vibration task with the frequency
 *    and modal deflection limits (first order). */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_simulate.h"
#include "ea_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *bin, *src;

static ea_task_t line_task(ea_task_objective_t obj, double duration, int knots) {
  ea_task_t t;
  ea_task_init(&t, NULL);
  t.start = ea_task_point_planar(0.3, -0.2, 0.0);
  t.goal = ea_task_point_planar(0.6, -0.2, 0.0);
  t.path = EA_TASK_PATH_LINE;
  t.objective = obj;
  t.duration_s = duration;
  t.knots = knots;
  return t;
}

/* Direct FE f1 at (L_c, alpha) for tip mass m_L. */
static double fe_f1(const ea_arm_t *arm, double tip_mass, double Lc, double al) {
  ea_shooter_t *sh = NULL;
  ea_fe_model_t *m = NULL;
  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  fs.static_hold_tip = 1;
  double f = NAN;
  if (ea_shooter_alloc(arm, NULL, &sh, NULL) || ea_fe_model_alloc(arm, &fs, &m, NULL)) goto out;
  ea_load_t load = {tip_mass};
  ea_shooter_set_load(sh, &load);
  ea_fe_model_set_load(m, &load);
  ea_statics_problem_t pr = ea_statics_problem_cable(Lc, al);
  ea_statics_solution_t sol;
  ea_fe_static_info_t fi;
  ea_fe_modes_info_t mi;
  if (ea_statics_solve(sh, &pr, NULL, NULL, &sol, NULL) ||
      ea_fe_static_solve(m, sh, &sol, &fi, NULL) || ea_fe_modes(m, &mi, NULL))
    goto out;
  f = mi.freq_hz[0];
out:
  ea_fe_model_free(m);
  ea_shooter_free(sh);
  return f;
}

static void test_model_accuracy(void) {
  ea_task_t t = line_task(EA_TASK_MIN_VIBRATION, 3.0, 30);
  ea_error_t e;
  ea_test_true(ea_task_check(&t, &e) == EA_OK, "paper line task (min_vibration) checks");
  ea_planner_t *pl = NULL;
  ea_test_true(ea_planner_alloc(&t, &pl, &e) == EA_OK, "planner with frequency model");
  if (!pl) return;
  ea_plan_freq_model_info_t fi;
  ea_planner_freq_model(pl, &fi);
  printf("frequency model: %d x %d grid, L_c %.4f..%.4f m, alpha %.4f..%.4f rad, f1 %.4f..%.4f "
         "Hz, %d extrapolated, built in %.1f ms\n",
         fi.n_cable_length, fi.n_cable_angle, fi.cable_length_range[0], fi.cable_length_range[1],
         fi.cable_angle_range[0], fi.cable_angle_range[1], fi.f1_min_hz, fi.f1_max_hz,
         fi.n_extrapolated, 1e3 * fi.time_s);
  ea_test_true(fi.built == 1, "frequency model built");
  /* cell centres (farthest from the knots of the spline) along the line
   * (u = 0..1 of the tip path) and 0.02 m below it */
  const double tm = ea_arm_tip_mass(&t.arm, t.payload_kg);
  double worst = 0.0;
  for (int i = 0; i < 7; ++i) {
    const double u = (i + 0.5) / 7.0, dy = (i % 2) ? -0.02 : 0.0;
    const double X = 0.3 + 0.3 * u, Y = -0.2 + dy;
    const double Lc = hypot(X - t.arm.x_c, Y - t.arm.y_c), al = atan2(Y - t.arm.y_c, X - t.arm.x_c);
    double f_model, g[2];
    ea_planner_first_frequency(pl, Lc, al, &f_model, g, &e);
    const double f_fe = fe_f1(&t.arm, tm, Lc, al);
    const double rel = fabs(f_model - f_fe) / f_fe;
    worst = fmax(worst, rel);
    /* the spline's gradient against a central difference of direct FE */
    const double d = 2e-3;
    const double gL = (fe_f1(&t.arm, tm, Lc + d, al) - fe_f1(&t.arm, tm, Lc - d, al)) / (2 * d);
    printf("  L_c %.4f m alpha %+.4f rad: model %.6f Hz, FE %.6f Hz, rel err %.2e; df/dL_c "
           "model %.4f FE %.4f Hz/m\n",
           Lc, al, f_model, f_fe, rel, g[0], gL);
    ea_test_rel(g[0], gL, 0.05, "df1/dL_c: spline vs central difference of direct FE");
  }
  /* measured 1.5e-4; tolerance 3x */
  ea_test_abs(worst, 0.0, 5e-4, "frequency model vs direct FE at off-grid points (max rel err)");
  ea_planner_free(pl);
}

static void test_derivatives(void) {
  ea_task_t t = line_task(EA_TASK_MIN_VIBRATION, 3.0, 12);
  t.limits.min_first_frequency_hz = 0.8;
  t.limits.max_modal_deflection_m = 0.05;
  t.solver.derivative_test = 1;
  ea_error_t e;
  ea_task_check(&t, &e);
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  if (ea_planner_alloc(&t, &pl, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  printf("derivative checker (min_vibration, f1 >= 0.8 Hz, deflection <= 0.05 m): %d errors; "
         "%s\n",
         info.deriv_errors, info.message);
  ea_test_true(info.deriv_errors == 0, "Ipopt derivative checker: no errors on min_vibration");
  ea_planner_free(pl);
  /* free duration with a time weight */
  t = line_task(EA_TASK_MIN_VIBRATION, NAN, 12);
  t.time_weight = 0.05;
  t.solver.derivative_test = 1;
  ea_test_true(ea_task_check(&t, &e) == EA_OK, "min_vibration with time_weight checks");
  if (ea_planner_alloc(&t, &pl, &e)) return;
  ea_status_t st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  printf("free-time min_vibration: %s (derivative checker %d errors)\n", info.message,
         info.deriv_errors);
  ea_test_true(st == EA_OK && info.deriv_errors == 0,
               "free-time min_vibration plans, derivative checker clean");
  ea_planner_free(pl);
}

/* Plan t, run the FE transient of the plan (ea_traj_simulate, 3 s after the motion, the
 * default settings) and again at a quarter of the time step; returns the residual peak [m]
 * and checks that the two agree (the default is converged). */
static double plan_and_simulate(ea_task_t *t, const char *name, double *min_f1) {
  ea_error_t e;
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  ea_traj_t tr = {0};
  double peak = NAN;
  if (ea_task_check(t, &e) || ea_planner_alloc(t, &pl, &e) ||
      ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e) || ea_planner_trajectory(pl, &tr, &e)) {
    printf("%s: %s\n", name, e.msg);
    goto out;
  }
  if (min_f1) *min_f1 = info.min_first_frequency_hz;
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  ea_sim_info_t si, sf;
  if (ea_traj_simulate(&t->arm, &tr, 0.0, &s, NULL, &si, &e)) {
    printf("%s: simulate: %s\n", name, e.msg);
    goto out;
  }
  s.dt /= 4;
  if (ea_traj_simulate(&t->arm, &tr, 0.0, &s, NULL, &sf, &e)) {
    printf("%s: simulate: %s\n", name, e.msg);
    goto out;
  }
  peak = si.residual_peak;
  printf("%-14s duration %.3f s, %2d iterations, %.0f ms: FE residual vibration peak %.4f mm "
         "(dt %g s), %.4f mm (dt %g s)\n",
         name, info.duration_s, info.iterations, 1e3 * info.time_total_s, 1e3 * peak, 4 * s.dt,
         1e3 * sf.residual_peak, s.dt);
  /* measured: within 2e-4 relative; the default must be within 1 % of the refined answer */
  ea_test_rel(si.residual_peak, sf.residual_peak, 0.01,
              "FE residual at the default dt vs a quarter of it");
out:
  ea_traj_free(&tr);
  ea_planner_free(pl);
  return peak;
}

static void test_residual_vibration(void) {
  ea_task_t te = line_task(EA_TASK_MIN_EFFORT, 3.0, 100);
  ea_task_t tj = line_task(EA_TASK_MIN_JERK, 3.0, 100);
  ea_task_t tv = line_task(EA_TASK_MIN_VIBRATION, 3.0, 100);
  const double re = plan_and_simulate(&te, "min_effort", NULL);
  const double rj = plan_and_simulate(&tj, "min_jerk", NULL);
  const double rv = plan_and_simulate(&tv, "min_vibration", NULL);
  printf("residual vibration peak (FE transient, 3 s after a 3 s paper line): min_effort %.3f "
         "mm, min_jerk %.3f mm, min_vibration %.3f mm (%.0f %% of min_effort)\n",
         1e3 * re, 1e3 * rj, 1e3 * rv, 100 * rv / re);
  ea_test_true(isfinite(re) && isfinite(rj) && isfinite(rv), "three plans simulated");
  /* At converged settings the f1-weighted acceleration surrogate of min_vibration does not
   * beat min_effort or min_jerk (measured 2.5 vs 0.97 / 0.86 mm): it is not a model of the
   * vibration. No ranking is asserted here; the modal model of the at-rest planner is
   * judged by the FE transient in test_plan_rest. */
  /* the frequency limit is met at every knot (by the model) */
  ea_task_t tf = tv;
  tf.limits.min_first_frequency_hz = 0.9;
  double f1 = NAN;
  plan_and_simulate(&tf, "f1 >= 0.9 Hz", &f1);
  ea_test_true(f1 >= 0.9 - 1e-6, "min_first_frequency_Hz = 0.9 holds at every knot");
  const double fg =
      fe_f1(&tf.arm, ea_arm_tip_mass(&tf.arm, 0.0), tf.goal.cable_length, tf.goal.cable_angle);
  printf("  min f1 over the knots %.5f Hz; direct FE f1 at the goal %.5f Hz\n", f1, fg);
  /* a limit above the goal's own frequency cannot be met */
  tf.limits.min_first_frequency_hz = fg * 1.02;
  ea_error_t e;
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  ea_status_t st = ea_task_check(&tf, &e);
  if (!st) st = ea_planner_alloc(&tf, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  printf("  min_first_frequency_Hz = %.4f (goal %.4f): %s\n", tf.limits.min_first_frequency_hz, fg,
         e.msg);
  ea_test_true(st != EA_OK, "a frequency limit above the goal's f1 is refused");
  ea_planner_free(pl);
}

int main(void) {
  bin = getenv("EA_BINARY");
  src = getenv("EA_SOURCE_DIR");
  if (!bin || !src) {
    printf("EA_BINARY / EA_SOURCE_DIR not set (run through ctest)\n");
    return EXIT_FAILURE;
  }
  test_model_accuracy();
  test_derivatives();
  test_residual_vibration();
  return ea_test_summary("test_plan_vib");
}
