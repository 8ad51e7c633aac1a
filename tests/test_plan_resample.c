/* Plans are admissible under the streamer's resampling (docs/planner.md,
 * "Limits between the knots"): the paper line planned with the default
 * limits.resample_margin, resampled at 1 kHz by ea_stream_resample (quintic
 * Hermite of value, rate and acceleration, planner/stream_*.c, outside the
 * planner) passes ea_stream_check_limits at every setpoint without time
 * scaling; with resample_margin = 0 it does not (the check can fail). */
#include "ea_planner.h"
#include "ea_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Plan the paper line; resample at 1 kHz; returns the resample status and
 * the least admissible time scale. */
static ea_status_t plan_resample(int knots, double margin, int c2, ea_task_objective_t obj,
                                 double *scale) {
  ea_task_t t;
  ea_task_init(&t, NULL);
  t.start = ea_task_point_planar(0.3, -0.2, 0.0);
  t.goal = ea_task_point_planar(0.6, -0.2, 0.0);
  t.path = EA_TASK_PATH_LINE;
  t.knots = knots;
  t.limits.resample_margin = margin;
  t.limits.continuous_acceleration = c2;
  if (obj != EA_TASK_MIN_TIME) {
    t.objective = obj;
    t.duration_s = 1.4;
  }
  ea_error_t e;
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  ea_traj_t tr = {0};
  ea_setpoint_t *sp = NULL;
  int n = 0;
  ea_status_t st = ea_task_check(&t, &e);
  if (!st) st = ea_planner_alloc(&t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  if (!st) st = ea_planner_trajectory(pl, &tr, &e);
  if (st) {
    printf("plan failed: %s\n", e.msg);
    ea_planner_free(pl);
    return EA_ERR_NOCONV;
  }
  st = ea_stream_resample(&tr, &t.arm, 1000.0, 1e-6, &sp, &n, &e);
  *scale = NAN;
  ea_stream_min_time_scale(&tr, &t.arm, 1000.0, 1e-6, scale, NULL);
  printf("%s, %3d knots, resample_margin %.4f, continuous acceleration %d: duration %.5f s, %d "
         "setpoints: %s; least time "
         "scale %.5f\n",
         ea_task_objective_name(obj), knots, margin, c2, info.duration_s, n,
         st ? e.msg : "every setpoint within the arm's limits", *scale);
  free(sp);
  ea_traj_free(&tr);
  ea_planner_free(pl);
  return st;
}

int main(void) {
  double s;
  const int ks[] = {30, 100, 200};
  for (int i = 0; i < 3; ++i) {
    char what[128];
    snprintf(what, sizeof what, "paper line, %d knots, defaults: resampled at 1 kHz within limits",
             ks[i]);
    ea_test_true(plan_resample(ks[i], 0.005, 1, EA_TASK_MIN_TIME, &s) == EA_OK, what);
    ea_test_abs(s, 1.0, 1e-12, "no time scaling needed");
  }
  ea_test_true(plan_resample(100, 0.005, 1, EA_TASK_MIN_EFFORT, &s) == EA_OK,
               "min_effort 1.4 s, defaults: within limits");
  /* the old plan (acceleration jumps at the knots, no margin): the quintic
   * exceeds the acceleration limit between the knots */
  ea_test_true(plan_resample(100, 0.0, 0, EA_TASK_MIN_TIME, &s) == EA_ERR_INADMISSIBLE,
               "jumps allowed, no margin: the resampled min-time plan is refused");
  ea_test_true(s > 1.0, "jumps allowed, no margin: a time scale > 1 is needed");
  /* a margin alone does not fix it (the overshoot depends on where the switch falls) */
  const ea_status_t st = plan_resample(100, 0.01, 0, EA_TASK_MIN_TIME, &s);
  printf("jumps allowed, 1 %% margin: %s\n", st ? "refused" : "admissible");
  return ea_test_summary("test_plan_resample");
}
