/* Private: the planner side of batch studies: the minimum-time and at-rest
 * metrics (planner/nlp/study_plan.c), the callbacks that keep Ipopt out of
 * problems/. Parsed result rows, the JSON summary and the figures: planner/app/. */
#ifndef EA_STUDY_PLAN_IMPL_H
#define EA_STUDY_PLAN_IMPL_H

#include "ea_planner.h"
#include "ea_simulate.h"
#include "ea_study.h"

/* ---- minimum-time and at-rest metrics (planner/nlp/study_plan.c) ---------- */

/** State of the planner callbacks: the study's tasks, loaded once. */
typedef struct ea__study_plan ea__study_plan_t;

/** Load the tasks of the study's planner metrics (min_time, at_rest; each
 *  ea_study_metric_task_load: the study's arm file, else default_arm, when
 *  the task names none); each must be a min_time task. */
ea_status_t ea__study_plan_alloc(const ea_study_t *s, const char *default_arm,
                                 ea__study_plan_t **out, ea_error_t *err);
/** Content key of the loaded min_time task (for ea_study_settings_t.min_time_key;
 *  NULL without one). */
const char *ea__study_plan_key(const ea__study_plan_t *p);
/** Content key of the loaded at_rest task (NULL without one). */
const char *ea__study_plan_at_rest_key(const ea__study_plan_t *p);
/** Put the callbacks, their data and keys in set (NULL p: none). */
void ea__study_plan_register(ea__study_plan_t *p, ea_study_settings_t *set);
void ea__study_plan_free(ea__study_plan_t *p);
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
