/* Private: the planner side of batch studies: the minimum-time metric
 * (planner/nlp/study_plan.c), the callback that keeps Ipopt out of problems/.
 * Parsed result rows, the JSON summary and the figures: planner/app/. */
#ifndef EA_STUDY_PLAN_IMPL_H
#define EA_STUDY_PLAN_IMPL_H

#include "ea_planner.h"
#include "ea_study.h"

/* ---- minimum-time metric (planner/nlp/study_plan.c) ----------------------- */

/** State of the min_time callback: the study's task, loaded once. */
typedef struct ea__study_plan ea__study_plan_t;

/** Load the study's task (ea_study_task_load: the study's arm file, else
 *  default_arm, when the task names none). */
ea_status_t ea__study_plan_alloc(const ea_study_t *s, const char *default_arm,
                                 ea__study_plan_t **out, ea_error_t *err);
/** Content key of the loaded task (for ea_study_settings_t.min_time_key). */
const char *ea__study_plan_key(const ea__study_plan_t *p);
void ea__study_plan_free(ea__study_plan_t *p);
/** The ea_study_min_time_fn: copies the task, puts the case's arm and
 *  payload in, re-checks it (points inside the case's workspace), plans
 *  from cold and reports the duration. Ipopt (MUMPS) calls are serialised
 *  with a mutex: MUMPS' sequential build is not thread-safe. */
ea_status_t ea__study_min_time(void *data, const ea_study_t *s, const ea_arm_t *arm,
                               double payload_kg, double payload_factor, double *duration_s,
                               char *msg, size_t msg_len);

#endif
