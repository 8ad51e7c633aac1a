/* The study metrics that need the planner: the minimum-time duration of a task for
 * each case's arm and payload, and the at-rest metric (the plan that arrives at rest
 * and the quasi-static minimum-time plan, each with its FE residual vibration).
 * Registered in ea_study_settings_t as callbacks so that problems/ never depends on
 * planner/. */
#include "study_plan_impl.h"

#include "ea_refine.h"
#include "ea_simulate.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct ea_study_planner {
  int has_min_time, has_at_rest;
  ea_task_t task;      /* min_time */
  ea_task_t rest_task; /* at_rest */
  char key[128];       /* content keys of the tasks and their arm files */
  char rest_key[128];
  int modes, elements; /* at_rest settings of the study */
  double dt, settle, zeta;
  pthread_mutex_t mu;
};

/* Load the task of a planner metric; it must be a min_time task. */
static ea_status_t ea__plan_task(const ea_study_t *s, unsigned metric, const char *default_arm,
                                 ea_task_t *t, char *key, size_t key_len, ea_error_t *err) {
  ea_status_t st = ea_study_metric_task_load(s, metric, default_arm, t, key, key_len, err);
  if (st) return st;
  /* the study's workers run cases in parallel: each plan on one thread (the same plan as on
   * two, solver.threads) */
  t->solver.threads = 1;
  if (t->objective == EA_TASK_MIN_TIME) return EA_OK;
  const int rest = metric == EA_STUDY_M_AT_REST;
  const char *name =
      rest ? (s->at_rest.task_name[0] ? s->at_rest.task_name : s->at_rest.task_file)
           : (s->min_time.task_name[0] ? s->min_time.task_name : s->min_time.task_file);
  return ea_error_set(err, EA_ERR_INPUT, "%s task %s: objective is %s, not min_time",
                      rest ? "at_rest" : "min_time", name, ea_task_objective_name(t->objective));
}

ea_status_t ea_study_use_planner(const ea_study_t *s, const char *default_arm,
                                 ea_study_settings_t *set, ea_study_planner_t **out,
                                 ea_error_t *err) {
  if (!s || !set || !out)
    return ea_error_set(err, EA_ERR_ARG, "ea_study_use_planner: NULL argument");
  *out = NULL;
  set->min_time = NULL, set->min_time_data = NULL, set->min_time_key = NULL;
  set->at_rest = NULL, set->at_rest_data = NULL, set->at_rest_key = NULL;
  if (!(s->metrics & EA_STUDY_M_PLANNER)) return EA_OK;
  ea_study_planner_t *p = calloc(1, sizeof *p);
  if (!p) return ea_error_set(err, EA_ERR_NOMEM, "study planner: out of memory");
  ea_status_t st = EA_OK;
  if (s->metrics & EA_STUDY_M_MIN_TIME) {
    st = ea__plan_task(s, EA_STUDY_M_MIN_TIME, default_arm, &p->task, p->key, sizeof p->key, err);
    p->has_min_time = !st;
  }
  if (!st && (s->metrics & EA_STUDY_M_AT_REST)) {
    st = ea__plan_task(s, EA_STUDY_M_AT_REST, default_arm, &p->rest_task, p->rest_key,
                       sizeof p->rest_key, err);
    p->has_at_rest = !st;
  }
  if (st) {
    free(p);
    return st;
  }
  p->modes = s->at_rest.modes;
  p->elements = s->at_rest.elements;
  p->dt = s->at_rest.dt;
  p->settle = s->at_rest.settle;
  p->zeta = s->at_rest.damping_ratio;
  pthread_mutex_init(&p->mu, NULL);
  if (p->has_min_time) {
    set->min_time = ea__study_min_time;
    set->min_time_data = p;
    set->min_time_key = p->key;
  }
  if (p->has_at_rest) {
    set->at_rest = ea__study_at_rest;
    set->at_rest_data = p;
    set->at_rest_key = p->rest_key;
  }
  *out = p;
  return EA_OK;
}

void ea_study_planner_free(ea_study_planner_t *p) {
  if (!p) return;
  pthread_mutex_destroy(&p->mu);
  free(p);
}

/* The task of a case: the study's task with the case's beam, hand, cable root and
 * payload (the task keeps its limits), re-checked (points inside the case's
 * workspace). NULL with msg when it cannot be. */
static ea_task_t *ea__case_task(const ea_task_t *base, const ea_arm_t *arm, double payload_kg,
                                double payload_factor, char *msg, size_t msg_len, ea_status_t *st) {
  ea_task_t *t = malloc(sizeof *t);
  if (!t) {
    snprintf(msg, msg_len, "out of memory");
    *st = EA_ERR_NOMEM;
    return NULL;
  }
  *t = *base;
  t->arm.rho = arm->rho;
  t->arm.m_hand = arm->m_hand;
  t->arm.length = arm->length;
  t->arm.EI = arm->EI;
  t->arm.x_c = arm->x_c;
  t->arm.y_c = arm->y_c;
  t->payload_kg = payload_kg;
  t->payload_factor = payload_factor;
  ea_error_t e = {0};
  *st = ea_task_check(t, &e);
  if (*st) {
    snprintf(msg, msg_len, "task not feasible for this case: %.360s", e.msg);
    free(t);
    return NULL;
  }
  return t;
}

/* Plan t from cold (Ipopt calls serialised: MUMPS' sequential build is not thread-safe;
 * worker processes each have their own mutex). tr (may be NULL) receives the plan. ref not
 * NULL: a plan that ends at rest is checked by the FE and refined as `elasticarm plan` does
 * by default (ea_plan_rest_check, ea_plan_rest_settings); ref->status EA_ERR_ARG: not run. */
static ea_status_t ea__plan(ea_study_planner_t *p, const ea_task_t *t, ea_traj_t *tr,
                            ea_plan_info_t *info, ea_refine_info_t *ref, char *msg,
                            size_t msg_len) {
  memset(info, 0, sizeof *info);
  if (ref) ref->status = EA_ERR_ARG;
  ea_error_t e = {0};
  ea_planner_t *pl = NULL;
  pthread_mutex_lock(&p->mu);
  ea_status_t st = ea_planner_alloc(t, &pl, &e);
  if (!st) {
    st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, info, &e);
    if (st) snprintf(msg, msg_len, "planner: %s", info->message[0] ? info->message : e.msg);
    if (!st && ref && ea_plan_rest_check(t) == EA_REST_CHECK_REFINE) {
      ea_task_refine_t rs;
      ea_plan_rest_settings(t, &rs);
      const int iterations = info->iterations;
      ea_plan_info_t ri;
      st = ea_plan_refine(pl, &rs, &ri, ref, &e);
      if (!st && ref->returned > 0) *info = ri;
      info->iterations = iterations;
      if (st) snprintf(msg, msg_len, "FE check and refinement: %s", e.msg);
    }
    if (!st && tr && (st = ea_planner_trajectory(pl, tr, &e)))
      snprintf(msg, msg_len, "planner: trajectory: %s", e.msg);
  } else {
    snprintf(msg, msg_len, "planner: %s", e.msg);
  }
  ea_planner_free(pl);
  pthread_mutex_unlock(&p->mu);
  return st;
}

ea_status_t ea__study_min_time(void *data, const ea_study_t *s, const ea_arm_t *arm,
                               double payload_kg, double payload_factor, double *duration_s,
                               char *msg, size_t msg_len) {
  (void)s;
  ea_study_planner_t *p = data;
  *duration_s = NAN;
  if (!p || !p->has_min_time) {
    snprintf(msg, msg_len, "min_time: no task");
    return EA_ERR_ARG;
  }
  ea_status_t st;
  ea_task_t *t = ea__case_task(&p->task, arm, payload_kg, payload_factor, msg, msg_len, &st);
  if (!t) return st;
  ea_plan_info_t info;
  st = ea__plan(p, t, NULL, &info, NULL, msg, msg_len);
  if (!st) *duration_s = info.duration_s;
  free(t);
  return st;
}

/* The FE settings of the at-rest metric's transients. */
void ea__study_at_rest_sim_settings(const ea_study_t *s, ea_sim_settings_t *sim) {
  ea_sim_settings_default(sim);
  sim->elements = s->at_rest.elements;
  sim->dt = s->at_rest.dt;
  sim->settle = s->at_rest.settle;
  sim->damping_ratio = s->at_rest.damping_ratio;
}

/* Plan t (duration into v[0], status st[0], msg[0]), then its FE transient (residual
 * peak into v[1], st[1], msg[1]). what: "quasi-static" or "at-rest". */
static void ea__plan_and_simulate(ea_study_planner_t *p, const ea_study_t *s, const ea_task_t *t,
                                  const char *what, double v[2], ea_status_t st[2],
                                  char (*msg)[400]) {
  ea_traj_t tr = {0};
  ea_plan_info_t info;
  ea_refine_info_t *ref = t->dynamics.modes > 0 ? calloc(1, sizeof *ref) : NULL;
  if (t->dynamics.modes > 0 && !ref) {
    st[0] = st[1] = EA_ERR_NOMEM;
    snprintf(msg[0], sizeof msg[0], "out of memory");
    snprintf(msg[1], sizeof msg[1], "out of memory");
    return;
  }
  st[0] = ea__plan(p, t, &tr, &info, ref, msg[0], sizeof msg[0]);
  if (st[0]) {
    st[1] = st[0];
    snprintf(msg[1], sizeof msg[1], "no %s plan to simulate", what);
    ea_traj_free(&tr);
    free(ref);
    return;
  }
  v[0] = info.duration_s;
  if (t->dynamics.modes > 0 && ref->status == EA_OK)
    snprintf(msg[0], sizeof msg[0],
             "%d modes, residual 0 (the reduced model's modal state zero at the goal); %d "
             "iterations; checked by the FE (dt %g s): residual peak %.4g mm %s bound %.4g mm "
             "after %d evaluation%s",
             t->dynamics.modes, info.iterations, ref->fe.dt, 1e3 * ref->residual_peak_m,
             ref->converged ? "within" : "NOT within", 1e3 * ref->settings.tolerance_m,
             ref->n_evals, ref->n_evals == 1 ? "" : "s");
  else if (t->dynamics.modes > 0)
    snprintf(msg[0], sizeof msg[0],
             "%d modes, residual 0 (the reduced model's modal state zero at the goal); %d "
             "iterations; not checked by the FE (dynamics.verify: false)",
             t->dynamics.modes, info.iterations);
  else
    snprintf(msg[0], sizeof msg[0], "quasi-static minimum time; %d iterations", info.iterations);
  ea_sim_settings_t sim;
  ea__study_at_rest_sim_settings(s, &sim);
  ea_sim_info_t si;
  ea_error_t e = {0};
  st[1] =
      ea_traj_simulate(&t->arm, &tr, ea_arm_tip_mass(&t->arm, t->payload_kg), &sim, NULL, &si, &e);
  if (st[1]) {
    snprintf(msg[1], sizeof msg[1], "FE transient of the %s plan: %.340s", what, e.msg);
  } else {
    v[1] = si.residual_peak;
    snprintf(msg[1], sizeof msg[1],
             "peak |tip - final equilibrium| over %g s after the %s plan's motion; FE %d "
             "elements, dt %g s, damping ratio %g",
             sim.settle, what, sim.elements, sim.dt, sim.damping_ratio);
  }
  ea_traj_free(&tr);
  free(ref);
}

ea_status_t ea__study_at_rest(void *data, const ea_study_t *s, const ea_arm_t *arm,
                              double payload_kg, double payload_factor,
                              ea_study_at_rest_result_t *out) {
  ea_study_planner_t *p = data;
  memset(out, 0, sizeof *out);
  out->duration_s = out->residual_peak_m = out->qs_duration_s = out->qs_residual_peak_m = NAN;
  ea_status_t st = EA_OK;
  char why[400] = "at_rest: no task";
  ea_task_t *t = NULL;
  if (!p || !p->has_at_rest)
    st = EA_ERR_ARG;
  else
    t = ea__case_task(&p->rest_task, arm, payload_kg, payload_factor, why, sizeof why, &st);
  if (!t) {
    for (int i = 0; i < 4; ++i) {
      out->status[i] = st;
      snprintf(out->msg[i], sizeof out->msg[i], "%s", why);
    }
    return st;
  }
  /* the quasi-static minimum-time plan: the task without dynamics */
  t->dynamics.modes = 0;
  t->dynamics.residual_m = 0;
  t->dynamics.refine.enabled = 0;
  double v[2] = {NAN, NAN};
  ea__plan_and_simulate(p, s, t, "quasi-static", v, &out->status[2], out->msg + 2);
  out->qs_duration_s = v[0];
  out->qs_residual_peak_m = v[1];
  /* the plan that arrives at rest: the task's dynamics settings (robust, grid, refine,
     verify, ...) with the study's modes and residual 0, checked by the FE as by default */
  t->dynamics = p->rest_task.dynamics;
  t->dynamics.modes = p->modes;
  t->dynamics.residual_m = 0;
  v[0] = v[1] = NAN;
  ea__plan_and_simulate(p, s, t, "at-rest", v, &out->status[0], out->msg);
  out->duration_s = v[0];
  out->residual_peak_m = v[1];
  free(t);
  for (int i = 0; i < 4; ++i)
    if (out->status[i]) return out->status[i];
  return EA_OK;
}
