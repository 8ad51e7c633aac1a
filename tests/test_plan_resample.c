/* Plans are admissible under the streamer's resampling (docs/planner.md,
 * "Limits between the knots"): plans resampled at 1 kHz by
 * ea_stream_resample (quintic Hermite of value, rate and acceleration,
 * planner/stream/stream_*.c, outside the planner) pass ea_stream_check_limits (the
 * arm's limits, shoulder speed and acceleration included) at every setpoint
 * without time scaling and without any margin inside the limits (the
 * default limits.resample_margin is 0): the paper line (30, 100, 200
 * knots, min_time; min_effort) and the line (0.25, -0.45) -> (0.6, -0.3) at
 * payload factor 0.25, where the shoulder limits bind. A plan whose
 * acceleration jumps at the knots (continuous_acceleration off, no margin)
 * is refused. */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_stream.h"
#include "ea_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Plan the paper line; resample at 1 kHz; returns the resample status and
 * the least admissible time scale. */
static ea_status_t plan_resample_line(const double A[2], const double B[2], double gamma, int knots,
                                      double margin, int c2, ea_task_objective_t obj,
                                      double *scale) {
  ea_task_t t;
  ea_task_init(&t, NULL);
  t.payload_factor = gamma;
  t.payload_kg = ea_arm_payload_from_factor(&t.arm, gamma);
  t.start = ea_task_point_planar(A[0], A[1], 0.0);
  t.goal = ea_task_point_planar(B[0], B[1], 0.0);
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

static ea_status_t plan_resample(int knots, double margin, int c2, ea_task_objective_t obj,
                                 double *scale) {
  const double A[2] = {0.3, -0.2}, B[2] = {0.6, -0.2};
  return plan_resample_line(A, B, 0.0, knots, margin, c2, obj, scale);
}

int main(void) {
  double s;
  const int ks[] = {30, 100, 200};
  for (int i = 0; i < 3; ++i) {
    char what[128];
    snprintf(what, sizeof what, "paper line, %d knots, defaults: resampled at 1 kHz within limits",
             ks[i]);
    ea_test_true(plan_resample(ks[i], 0.0, 1, EA_TASK_MIN_TIME, &s) == EA_OK, what);
    ea_test_abs(s, 1.0, 1e-12, "no time scaling needed");
  }
  ea_test_true(plan_resample(100, 0.0, 1, EA_TASK_MIN_EFFORT, &s) == EA_OK,
               "min_effort 1.4 s, defaults: within limits");
  /* the shoulder limits bind (the old plan needed a time scale of 2.97) */
  const double A2[2] = {0.25, -0.45}, B2[2] = {0.6, -0.3};
  ea_test_true(plan_resample_line(A2, B2, 0.25, 100, 0.0, 1, EA_TASK_MIN_TIME, &s) == EA_OK,
               "shoulder-limited line, defaults: resampled at 1 kHz within limits");
  ea_test_abs(s, 1.0, 1e-12, "shoulder-limited line: no time scaling needed");
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
