/* Replanning: ea_planner_update and its shorthands change what a live planner solves. */
#include "plan_impl.h"
#include "guess_impl.h"
#include "knot_impl.h"
#include "path_entry_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------------- */
/* Updates of a live planner (replanning)                                   */
/* ---------------------------------------------------------------------- */

/* Why task t cannot be solved by pl's transcription (NULL: it can). */
static const char *ea__struct_differs(const ea_planner_t *pl, const ea_task_t *t) {
  const ea_task_t *o = &pl->task;
  const ea_task_limits_t *a = &o->limits, *b = &t->limits;
  const double la[7] = {a->cable_speed_max,       a->cable_accel_max, a->cable_angle_speed_max,
                        a->cable_angle_accel_max, a->base_speed_max,  a->base_accel_max,
                        a->shoulder_speed_max};
  const double lb[7] = {b->cable_speed_max,       b->cable_accel_max, b->cable_angle_speed_max,
                        b->cable_angle_accel_max, b->base_speed_max,  b->base_accel_max,
                        b->shoulder_speed_max};
  if (!(t->start.cable_length > 0) || !(t->goal.cable_length > 0))
    return "task is not checked (ea_task_check)";
  if (t->knots != o->knots) return "knot count";
  if (t->n_via != o->n_via) return "number of via points";
  if (t->path != o->path) return "path kind";
  if (t->objective != o->objective) return "objective";
  if (t->dynamics.modes != o->dynamics.modes || t->dynamics.grid[0] != o->dynamics.grid[0] ||
      t->dynamics.grid[1] != o->dynamics.grid[1] ||
      (t->dynamics.residual_m > 0) != (o->dynamics.residual_m > 0) ||
      isfinite(t->dynamics.max_tip_deviation_m) != isfinite(o->dynamics.max_tip_deviation_m) ||
      t->dynamics.robust_tip_mass != o->dynamics.robust_tip_mass ||
      t->dynamics.robust_EI != o->dynamics.robust_EI ||
      (t->dynamics.modes && t->payload_kg != o->payload_kg))
    return "dynamics (modes, grid, residual or deviation limit, robust models, payload)";
  if (t->base_moves != o->base_moves) return "base motion (base variables)";
  if (isnan(t->duration_s) != isnan(o->duration_s)) return "free/fixed duration";
  if (t->limits.continuous_acceleration != o->limits.continuous_acceleration)
    return "acceleration continuity";
  if (t->solver.hessian_exact != o->solver.hessian_exact) return "Hessian mode";
  if ((t->solver.regularization > 0.0) != (o->solver.regularization > 0.0))
    return "regularization term";
  for (int i = 0; i < 7; ++i)
    if (isfinite(la[i]) != isfinite(lb[i])) return "set of finite speed/acceleration limits";
  if (!ea_arm_equal(&t->arm, &o->arm)) return "arm";
  if (pl->fm) return "task with a frequency model (built for the old task's region)";
  return NULL;
}

ea_status_t ea_planner_update(ea_planner_t *pl, const ea_task_t *task, ea_error_t *err) {
  if (!pl || !task) return ea_error_set(err, EA_ERR_ARG, "ea_planner_update: NULL argument");
  const char *why = ea__struct_differs(pl, task);
  if (why)
    return ea_error_set(err, EA_ERR_ARG,
                        "ea_planner_update: %s differs from the planner's; the transcription "
                        "would change: build a new planner (ea_planner_alloc)",
                        why);
  /* A segment that becomes (or stops being) a point changes the path rows. */
  unsigned char deg[EA_TASK_MAX_VIA + 1];
  for (int j = 0; j < pl->n_seg; ++j)
    deg[j] = pl->segLen[j] > 1e-9;
  const double tip_mass = pl->tip_mass;
  const ea_task_t old = pl->task;
  int vk_old[EA_TASK_MAX_VIA + 2];
  memcpy(vk_old, pl->via_knot, sizeof vk_old);
  pl->task = *task;
  ea__plan_derive(pl);
  /* The path transcription places the via knots as a cold planner of the new task would (its
   * rows and their structure do not depend on them): a kept via knot fixes the time at which
   * the plan passes the via to the old task's fraction of t_f (a via moved 10 mm replanned
   * 1.1-3.3 % slower than a cold plan). The knot transcription keeps them: its path rows
   * (lines with dynamics) follow the knots, and its predictor shifts the old plan along the old
   * via knots (a free path with its via moved 10 mm replanned 2.9 % faster than cold, whose
   * estimate placed the via knot worse). */
  if (pl->pp)
    ea__plan_layout(pl);
  else
    ea__plan_segments(pl);
  for (int j = 0; j < pl->n_seg; ++j)
    if (deg[j] != (pl->segLen[j] > 1e-9) && pl->task.path != EA_TASK_PATH_FREE) {
      pl->task = old;
      ea__plan_derive(pl);
      memcpy(pl->via_knot, vk_old, sizeof vk_old);
      ea__plan_segments(pl);
      return ea_error_set(err, EA_ERR_ARG,
                          "ea_planner_update: path segment %d %s a point: the path rows would "
                          "change; build a new planner",
                          j, deg[j] ? "becomes" : "stops being");
    }
  ea__knot_rows(pl);
  ea__knot_bounds(pl);
  ea__plan_terms_setup(pl);
  if (pl->hess_exact)
    for (int i = 0; i < pl->n_orows; ++i)
      if (pl->task.objective == EA_TASK_MIN_TIME) pl->oweight[i] = pl->task.solver.regularization;
  if (pl->tip_mass != tip_mass) memset(pl->kvalid, 0, (size_t)pl->N);
  pl->cache_val = pl->cache_sens = 0;
  ea_status_t st = ea__pp_update(pl, err);
  if (st) return st;
  if (pl->have_solution) pl->updated = 1;
  return ea_error_set(err, EA_OK, "ok");
}

/* Copy of the planner's task with one change, checked, then the update. */
static ea_status_t ea__update_checked(ea_planner_t *pl, ea_task_t *t, ea_error_t *err) {
  const ea_status_t st = ea_task_check(t, err);
  if (st) return st;
  return ea_planner_update(pl, t, err);
}

ea_status_t ea_planner_update_goal(ea_planner_t *pl, const ea_task_point_t *goal, ea_error_t *err) {
  if (!pl || !goal) return ea_error_set(err, EA_ERR_ARG, "ea_planner_update_goal: NULL argument");
  ea_task_t t = pl->task;
  t.goal = *goal;
  return ea__update_checked(pl, &t, err);
}

ea_status_t ea_planner_update_start(ea_planner_t *pl, const ea_task_point_t *start,
                                    ea_error_t *err) {
  if (!pl || !start) return ea_error_set(err, EA_ERR_ARG, "ea_planner_update_start: NULL argument");
  ea_task_t t = pl->task;
  t.start = *start;
  return ea__update_checked(pl, &t, err);
}

ea_status_t ea_planner_update_payload(ea_planner_t *pl, double payload_kg, ea_error_t *err) {
  if (!pl) return ea_error_set(err, EA_ERR_ARG, "ea_planner_update_payload: NULL planner");
  ea_task_t t = pl->task;
  t.payload_kg = payload_kg;
  t.payload_factor = NAN;
  return ea__update_checked(pl, &t, err);
}

ea_status_t ea_planner_update_limits(ea_planner_t *pl, const ea_task_limits_t *limits,
                                     ea_error_t *err) {
  if (!pl || !limits)
    return ea_error_set(err, EA_ERR_ARG, "ea_planner_update_limits: NULL argument");
  ea_task_t t = pl->task;
  t.limits = *limits;
  return ea__update_checked(pl, &t, err);
}
