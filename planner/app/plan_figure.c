/* Figure of a plan: its trajectory drawn by ea_traj_figure (traj_figure.c)
 * with the task's limits, a title naming the task, the planner's frequency
 * model (min_vibration, a frequency limit) or reduced model (dynamics) along
 * the plan, and the summary's dynamics predictions. Only the public planner
 * API: the plan from ea_planner_trajectory, the arm and load from its task. */
#include "figure_impl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static ea_status_t ea__plan_f1(const void *ctx, double cable_length, double cable_angle,
                               double *hz) {
  return ea_planner_first_frequency((const ea_planner_t *)ctx, cable_length, cable_angle, hz, NULL,
                                    NULL);
}

void ea_traj_figure_opts_limits(ea_traj_figure_opts_t *o, const ea_task_limits_t *L) {
  o->lim.tension_min = L->tension_min;
  o->lim.tension_max = L->tension_max;
  o->lim.cable_length_min = L->cable_length_min;
  o->lim.cable_length_max = L->cable_length_max;
  o->lim.cable_speed_max = L->cable_speed_max;
  o->lim.cable_accel_max = L->cable_accel_max;
  o->lim.shoulder_torque_max = L->shoulder_torque_max;
  o->lim.shoulder_speed_max = L->shoulder_speed_max;
  o->lim.base_speed_max = L->base_speed_max;
  o->lim.base_accel_max = L->base_accel_max;
}

ea_status_t ea_plan_figure(ea_planner_t *pl, const ea_plan_info_t *info, const char *path,
                           ea_error_t *err) {
  return ea_plan_figure_fe(pl, info, NAN, NULL, path, err);
}

ea_status_t ea_plan_figure_fe(ea_planner_t *pl, const ea_plan_info_t *info,
                              double fe_residual_peak_m, const char *fe_check, const char *path,
                              ea_error_t *err) {
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
  ea_traj_figure_opts_t o;
  ea_traj_figure_opts_default(&o, &t->arm);
  char title[256];
  snprintf(title, sizeof title, "plan: %s  (payload %.3g kg, %s)", t->name, t->payload_kg,
           ea_task_objective_name(t->objective));
  o.title = title;
  ea_traj_figure_opts_limits(&o, &t->limits);
  const ea_task_limits_t *L = &t->limits;
  ea_plan_freq_model_info_t fm;
  if (ea_planner_freq_model(pl, &fm) == EA_OK && fm.built) {
    o.f1 = ea__plan_f1;
    o.f1_ctx = pl;
    o.f1_min_hz = L->min_first_frequency_hz;
  } else {
    o.rom = ea_planner_rom_table(pl);
  }
  if (info && o.rom) {
    o.predicted_residual_m = info->predicted_residual_m;
    o.max_modal_deviation_m = info->max_modal_deviation_m;
    o.predicted_time_to_rest_s = info->predicted_time_to_rest_s;
  }
  o.fe_residual_peak_m = fe_residual_peak_m;
  o.fe_check = fe_check;
  st = ea_traj_figure(&tr, sh, &o, path, err);
  ea_shooter_free(sh);
  ea_traj_free(&tr);
  return st;
}
