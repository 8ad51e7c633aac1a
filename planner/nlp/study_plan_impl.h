/* Private: the planner side of batch studies: the minimum-time and at-rest
 * metrics (planner/nlp/study_plan.c), the callbacks that keep Ipopt out of
 * problems/; registered by the public ea_study_use_planner (ea_planner.h).
 * Parsed result rows, the JSON summary and the figures: planner/app/. */
#ifndef EA_STUDY_PLAN_IMPL_H
#define EA_STUDY_PLAN_IMPL_H

#include "ea_planner.h"
#include "ea_simulate.h"
#include "ea_study.h"

/* ---- minimum-time and at-rest metrics (planner/nlp/study_plan.c) ---------- */

/* Their data: the ea_study_planner_t of ea_study_use_planner. */

/** The ea_study_min_time_fn: copies the task, puts the case's arm and
 *  payload in, re-checks it (points inside the case's workspace), plans
 *  from cold and reports the duration. Ipopt (MUMPS) calls are serialised
 *  with a mutex: MUMPS' sequential build is not thread-safe (worker
 *  processes run them in parallel). */
ea_status_t ea__study_min_time(void *data, const ea_study_t *s, const ea_arm_t *arm,
                               double payload_kg, double payload_factor, double *duration_s,
                               char *msg, size_t msg_len);
/** The ea_study_at_rest_fn: the case's task (as above) planned from cold
 *  without dynamics (the quasi-static minimum time) and with
 *  dynamics.modes = the study's at_rest.modes, residual 0, no refinement
 *  (the task's other dynamics settings kept); each plan's FE transient
 *  (ea_traj_simulate with ea__study_at_rest_sim_settings, tip mass of the
 *  case) gives its residual peak. */
ea_status_t ea__study_at_rest(void *data, const ea_study_t *s, const ea_arm_t *arm,
                              double payload_kg, double payload_factor,
                              ea_study_at_rest_result_t *out);
/** The FE settings of the at-rest metric: ea_sim_settings_default with the
 *  study's at_rest elements, dt, settle and damping ratio. */
void ea__study_at_rest_sim_settings(const ea_study_t *s, ea_sim_settings_t *sim);

#endif
