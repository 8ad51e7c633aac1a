/* Figure of a plan: its trajectory drawn by ea_traj_figure (traj_figure.c)
 * with the task's limits and a title naming the task. Only the public
 * planner API: the plan from ea_planner_trajectory, the arm and load from
 * its task. */
#include "figure_impl.h"

#include <stdio.h>
#include <string.h>

ea_status_t ea_plan_figure(ea_planner_t *pl, const char *path, ea_error_t *err) {
  if (!pl || !path) return ea_error_set(err, EA_ERR_ARG, "ea_plan_figure: NULL argument");
  ea_traj_t tr;
  memset(&tr, 0, sizeof tr);
  ea_status_t st = ea_planner_trajectory(pl, &tr, err);
  if (st) return st;
  const ea_task_t *t = ea_planner_task(pl);
  ea_shooter_t *sh = NULL;
  if ((st = ea_shooter_alloc(&t->arm, NULL, &sh, err))) {
    ea_traj_free(&tr);
    return st;
  }
  const ea_load_t load = {ea_arm_tip_mass(&t->arm, t->payload_kg)};
  ea_shooter_set_load(sh, &load);
  char title[256];
  snprintf(title, sizeof title, "plan: %s  (payload %.3g kg, %s)", t->name, t->payload_kg,
           ea_task_objective_name(t->objective));
  st = ea_traj_figure(&tr, sh, t->limits.cable_length_min, t->limits.tension_min, title, path, err);
  ea_shooter_free(sh);
  ea_traj_free(&tr);
  return st;
}
