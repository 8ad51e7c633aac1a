/* The study metric that needs the planner: the minimum-time duration of a
 * task for each case's arm and payload. Registered in ea_study_settings_t
 * as a callback so that problems/ never depends on planner/. */
#include "study_plan_impl.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct ea__study_plan {
  ea_task_t task;
  char key[128]; /* content key of the task and its arm file */
  pthread_mutex_t mu;
};

ea_status_t ea__study_plan_alloc(const ea_study_t *s, const char *default_arm,
                                 ea__study_plan_t **out, ea_error_t *err) {
  *out = NULL;
  ea__study_plan_t *p = calloc(1, sizeof *p);
  if (!p) return ea_error_set(err, EA_ERR_NOMEM, "min_time: out of memory");
  ea_status_t st = ea_study_task_load(s, default_arm, &p->task, p->key, sizeof p->key, err);
  if (st) {
    free(p);
    return st;
  }
  if (p->task.objective != EA_TASK_MIN_TIME) {
    const ea_task_objective_t o = p->task.objective;
    free(p);
    return ea_error_set(err, EA_ERR_INPUT, "min_time task %s: objective is %s, not min_time",
                        s->min_time.task_name[0] ? s->min_time.task_name : s->min_time.task_file,
                        ea_task_objective_name(o));
  }
  pthread_mutex_init(&p->mu, NULL);
  *out = p;
  return EA_OK;
}

const char *ea__study_plan_key(const ea__study_plan_t *p) {
  return p ? p->key : NULL;
}

void ea__study_plan_free(ea__study_plan_t *p) {
  if (!p) return;
  pthread_mutex_destroy(&p->mu);
  free(p);
}

ea_status_t ea__study_min_time(void *data, const ea_study_t *s, const ea_arm_t *arm,
                               double payload_kg, double payload_factor, double *duration_s,
                               char *msg, size_t msg_len) {
  (void)s;
  ea__study_plan_t *p = data;
  *duration_s = NAN;
  if (!p) {
    snprintf(msg, msg_len, "min_time: no task");
    return EA_ERR_ARG;
  }
  ea_task_t *t = malloc(sizeof *t);
  if (!t) {
    snprintf(msg, msg_len, "min_time: out of memory");
    return EA_ERR_NOMEM;
  }
  *t = p->task;
  /* the case's beam, hand and cable root; the task keeps its limits */
  t->arm.rho = arm->rho;
  t->arm.m_hand = arm->m_hand;
  t->arm.length = arm->length;
  t->arm.EI = arm->EI;
  t->arm.x_c = arm->x_c;
  t->arm.y_c = arm->y_c;
  t->payload_kg = payload_kg;
  t->payload_factor = payload_factor;
  ea_error_t e = {0};
  ea_status_t st = ea_task_check(t, &e);
  if (st) {
    snprintf(msg, msg_len, "task not feasible for this case: %s", e.msg);
    free(t);
    return st;
  }
  pthread_mutex_lock(&p->mu);
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  memset(&info, 0, sizeof info);
  st = ea_planner_alloc(t, &pl, &e);
  if (!st) {
    st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
    if (st)
      snprintf(msg, msg_len, "planner: %s", info.message[0] ? info.message : e.msg);
    else
      *duration_s = info.duration_s;
  } else {
    snprintf(msg, msg_len, "planner: %s", e.msg);
  }
  ea_planner_free(pl);
  pthread_mutex_unlock(&p->mu);
  free(t);
  return st;
}
