/* Work-precision of the FE transient of a trajectory (ea_traj_simulate), the vibration
 * ground truth: both time schemes at dt 4, 2, 1, 0.5 ms on planned examples, against the
 * energy scheme at dt = 1/16 ms (on the paper line it agrees with dt = 1/32 ms to 9e-7 of
 * the residual peak; the errors at dt >= 0.5 ms are larger). Errors: the residual
 * vibration peak (relative) and the tip history (max over the run of |tip - tip_ref| at the
 * coarse run's times); wall time the median of reps runs (default 3; about 25 s with 1). A
 * run that does not converge is a row saying so. Usage: bench_sim [reps]. */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_simulate.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_util.h"

#ifndef EA_SOURCE_DIR
#define EA_SOURCE_DIR "."
#endif

static int plan_example(const char *name, ea_traj_t *tr, ea_arm_t *arm) {
  char path[1024];
  snprintf(path, sizeof path, "%s/problems/examples/%s", EA_SOURCE_DIR, name);
  ea_task_t task;
  ea_error_t e;
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  int rc = 1;
  if (ea_task_load(path, NULL, &task, &e) || ea_planner_alloc(&task, &pl, &e) ||
      ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e) || ea_planner_trajectory(pl, tr, &e))
    fprintf(stderr, "%s: %s\n", name, e.msg);
  else
    rc = 0;
  *arm = task.arm;
  ea_planner_free(pl);
  return rc;
}

static int run(const ea_arm_t *arm, const ea_traj_t *tr, ea_fe_scheme_t sc, double dt,
               ea_sim_history_t *h, ea_sim_info_t *si) {
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  s.scheme = sc;
  s.dt = dt;
  s.keep_history = h != NULL;
  ea_error_t e;
  if (ea_traj_simulate(arm, tr, 0.0, &s, h, si, &e)) {
    fprintf(stderr, "simulate (dt %g): %s\n", dt, e.msg);
    return 1;
  }
  return 0;
}

int main(int argc, char **argv) {
  const int reps = ea_bench_count(argc, argv, 1, 3, 1000, "bench_sim [repetitions 1..1000]");
  if (reps < 0 || argc > 2) return 2;
  const char *names[4] = {"paper-line.yaml", "paper-line-smooth.yaml", "polyline-effort.yaml",
                          "paper-line.yaml"};
  enum { NDT = 4 };
  const double dts[NDT] = {4e-3, 2e-3, 1e-3, 5e-4}, dt_ref = 1e-3 / 16;
  ea_sim_settings_t def;
  ea_sim_settings_default(&def);
  printf("## FE transient work-precision (12 elements, 3 s after the motion; reference: energy "
         "scheme at dt = %.4g ms; wall time median of %d)\n\n",
         1e3 * dt_ref, reps);
  printf("| case | scheme | dt [ms] | steps | Newton it | wall [ms] | x real time | residual "
         "peak [mm] | rel. error | tip history error [m] |\n");
  printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (int c = 0; c < 4; ++c) {
    ea_traj_t tr = {0};
    ea_arm_t arm;
    if (plan_example(names[c], &tr, &arm)) return 1;
    if (c == 3) arm.EA_cable *= 10;
    ea_sim_history_t href = {0};
    ea_sim_info_t sref;
    if (run(&arm, &tr, EA_FE_SCHEME_ENERGY, dt_ref, &href, &sref)) return 1;
    char label[64];
    snprintf(label, sizeof label, "%.*s%s", (int)(strlen(names[c]) - 5), names[c],
             c == 3 ? " (EA_c x10)" : "");
    printf("| %s | energy (ref) | %.4g | %d | %d | %.0f | %.1f | %.6f | | |\n", label, 1e3 * dt_ref,
           sref.steps, sref.newton_iterations, 1e3 * sref.wall_time_s,
           sref.simulated_time / sref.wall_time_s, 1e3 * sref.residual_peak);
    for (int sc = 0; sc < 2; ++sc)
      for (int k = 0; k < NDT; ++k) {
        double wall[16];
        ea_sim_info_t si;
        ea_sim_history_t h = {0};
        int n = reps < 1 ? 1 : reps < 16 ? reps : 16, failed = 0;
        for (int r = 0; r < n && !failed; ++r) {
          failed = run(&arm, &tr, sc ? EA_FE_SCHEME_GENALPHA : EA_FE_SCHEME_ENERGY, dts[k],
                       r == 0 ? &h : NULL, &si);
          wall[r] = si.wall_time_s;
        }
        if (failed) {
          printf("| %s | %s | %.4g | did not converge | | | | | | |\n", label,
                 sc ? "genalpha" : "energy", 1e3 * dts[k]);
          ea_sim_history_free(&h);
          continue;
        }
        const int stride = (int)lround(dts[k] / dt_ref);
        double herr = 0.0;
        for (int i = 0; i < h.rows && stride * i < href.rows; ++i)
          herr = fmax(herr, hypot(h.data[6 * i + 1] - href.data[6 * stride * i + 1],
                                  h.data[6 * i + 2] - href.data[6 * stride * i + 2]));
        const double w = ea_bench_median(wall, n);
        printf("| %s | %s | %.4g | %d | %d | %.1f | %.1f | %.6f | %.1e | %.1e |%s\n", label,
               sc ? "genalpha" : "energy", 1e3 * dts[k], si.steps, si.newton_iterations, 1e3 * w,
               si.simulated_time / w, 1e3 * si.residual_peak,
               fabs(si.residual_peak / sref.residual_peak - 1), herr,
               (sc == (def.scheme == EA_FE_SCHEME_GENALPHA) && dts[k] == def.dt) ? " default" : "");
        ea_sim_history_free(&h);
      }
    ea_sim_history_free(&href);
    ea_traj_free(&tr);
  }
  return 0;
}
