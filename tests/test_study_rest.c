/* The study metric at_rest (problems/examples/studies/payload-rest.yaml's task, the paper
 * line to (0.5, -0.2) m, at payload factors 0 and 0.5), judged from outside the study code:
 *  - each row equals an independent re-plan of the case (the planner from cold on the
 *    task with the case's payload, without and with dynamics.modes = 2, the latter checked
 *    by the FE and refined as by default: ea_plan_rest_settings, ea_plan_refine) and an
 *    independent FE transient of that plan (ea_traj_simulate, settings written out here);
 *  - the quasi-static minimum time is the spool's bang-bang bound (only the spool's speed
 *    and acceleration limits bind on this line), the at-rest plan is longer, more so with
 *    the payload, and rings a small fraction of the quasi-static plan's residual, <= 1 mm;
 *  - the CSV of one in-process worker and of two worker processes is the same bytes (with
 *    min_time beside at_rest);
 *  - a task whose objective is not min_time is refused, naming it. */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_refine.h"
#include "ea_simulate.h"
#include "ea_test.h"
#include "study_report_impl.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char g_src[1024] = ".";

static double metric(const char *csv, long case_id, const char *name, char *status) {
  ea__study_table_t t;
  ea_error_t e;
  double v = NAN;
  if (ea__study_table_parse(csv, strlen(csv), "csv", &t, &e)) return NAN;
  for (long i = 0; i < t.n_rows; ++i)
    if (t.rows[i].case_id == case_id && !strcmp(t.rows[i].metric, name)) {
      v = t.rows[i].value;
      if (status) snprintf(status, 32, "%s", t.rows[i].status);
    }
  ea__study_table_free(&t);
  return v;
}

static char *run(const ea_study_t *s, int threads, ea_study_info_t *info) {
  ea_study_planner_t *plan = NULL;
  ea_error_t e = {0};
  ea_study_settings_t set;
  ea_study_settings_default(&set);
  if (ea_study_use_planner(s, NULL, &set, &plan, &e)) {
    printf("  plan: %s\n", e.msg);
    return NULL;
  }
  set.threads = threads;
  char *c = NULL;
  if (ea_study_run(s, &set, &c, NULL, info, &e)) printf("  run: %s\n", e.msg);
  ea_study_planner_free(plan);
  return c;
}

/* Independently: plan the task for the case's arm and payload (modes 0: quasi-static)
 * and run the FE transient of the plan: 12 elements, dt 1 ms, 3 s after the motion,
 * undamped, the case's tip mass. */
static int replan(const char *task_path, const ea_arm_t *arm, double kg, int modes, double *dur,
                  double *residual) {
  ea_task_t t;
  ea_error_t e = {0};
  if (ea_task_load(task_path, NULL, &t, &e)) {
    printf("  task: %s\n", e.msg);
    return 1;
  }
  t.arm.EI = arm->EI;
  t.arm.rho = arm->rho;
  t.arm.m_hand = arm->m_hand;
  t.arm.length = arm->length;
  t.arm.x_c = arm->x_c;
  t.arm.y_c = arm->y_c;
  t.payload_kg = kg;
  t.dynamics.modes = modes;
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  ea_traj_t tr = {0};
  ea_status_t st = ea_task_check(&t, &e);
  if (!st) st = ea_planner_alloc(&t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  ea_refine_info_t *ri = modes > 0 ? calloc(1, sizeof *ri) : NULL;
  if (!st && modes > 0) {
    ea_task_refine_t rs;
    ea_plan_rest_settings(&t, &rs);
    st = ri ? ea_plan_refine(pl, &rs, &info, ri, &e) : EA_ERR_NOMEM;
    if (!st) info.duration_s = ri->duration_s;
  }
  free(ri);
  if (!st) st = ea_planner_trajectory(pl, &tr, &e);
  ea_planner_free(pl);
  if (st) {
    printf("  replan: %s\n", e.msg);
    ea_traj_free(&tr);
    return 1;
  }
  *dur = info.duration_s;
  ea_sim_settings_t sim;
  ea_sim_settings_default(&sim);
  sim.elements = 12;
  sim.dt = 1e-3;
  sim.settle = 3.0;
  sim.damping_ratio = 0.0;
  ea_sim_info_t si;
  st = ea_traj_simulate(arm, &tr, arm->m_hand + kg, &sim, NULL, &si, &e);
  ea_traj_free(&tr);
  if (st) {
    printf("  simulate: %s\n", e.msg);
    return 1;
  }
  *residual = si.residual_peak;
  return 0;
}

static void test_at_rest(void) {
  char task[1200], text[4000];
  snprintf(task, sizeof task, "%s/problems/examples/studies/line-to-0.5.yaml", g_src);
  snprintf(text, sizeof text,
           "name: rest\n"
           "arm_file: %s/data/elasticarm.yaml\n"
           "grid: {payload_factor: [0, 0.5]}\n"
           "metrics:\n"
           "  min_time: {task: %s}\n"
           "  at_rest: {task: %s, modes: 2}\n",
           g_src, task, task);
  ea_study_t s;
  ea_error_t e = {0};
  if (ea_study_load_string("rest.yaml", text, strlen(text), NULL, &s, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  ea_study_info_t i1, i2;
  char *c1 = run(&s, 1, &i1), *c2 = run(&s, 2, &i2);
  ea_test_true(c1 && c2 && !i1.processes && i2.processes && i2.threads == 2,
               "at_rest study: 1 in-process worker, then 2 worker processes");
  ea_test_true(c1 && c2 && !strcmp(c1, c2),
               "at_rest + min_time: CSV of 2 worker processes byte-identical to 1 worker");
  if (!c1) return;
  double worst_dur = 0, worst_res = 0, res_rest[2] = {0}, dur_rest[2] = {0};
  for (long k = 0; k < 2; ++k) {
    ea_arm_t arm;
    double kg, g;
    ea_study_case_arm(&s, k, &arm, &kg, &g, &e);
    char st[5][32];
    const double d = metric(c1, k, "at_rest_duration_s", st[0]);
    const double r = metric(c1, k, "at_rest_fe_residual_peak_m", st[1]);
    const double dq = metric(c1, k, "qs_min_time_s", st[2]);
    const double rq = metric(c1, k, "qs_fe_residual_peak_m", st[3]);
    const double ratio = metric(c1, k, "at_rest_time_ratio", st[4]);
    const double mt = metric(c1, k, "min_time_duration", NULL);
    int ok = 1;
    for (int i = 0; i < 5; ++i)
      ok &= !strcmp(st[i], "ok");
    double d_ref = NAN, r_ref = NAN, dq_ref = NAN, rq_ref = NAN;
    ok &=
        !replan(task, &arm, kg, 2, &d_ref, &r_ref) && !replan(task, &arm, kg, 0, &dq_ref, &rq_ref);
    printf("  gamma %g: at rest %.6f s (re-plan %.6f), FE residual %.4f mm (re-run %.4f); "
           "quasi-static %.6f s (%.6f), FE residual %.4f mm (%.4f); ratio %.4f\n",
           g, d, d_ref, 1e3 * r, 1e3 * r_ref, dq, dq_ref, 1e3 * rq, 1e3 * rq_ref, ratio);
    ea_test_true(ok, "at_rest rows ok and the case re-planned independently");
    worst_dur = fmax(worst_dur, fmax(fabs(d - d_ref) / d_ref, fabs(dq - dq_ref) / dq_ref));
    worst_res = fmax(worst_res, fmax(fabs(r - r_ref) / r_ref, fabs(rq - rq_ref) / rq_ref));
    ea_test_rel(ratio, d / dq, 1e-11, "at_rest_time_ratio = at-rest duration / quasi-static");
    ea_test_rel(mt, dq, 1e-11, "qs_min_time_s = the min_time metric of the same task");
    /* only the spool binds on this line: the bang-bang bound of the cable, with the limits
       tightened by the task's resample margin; measured 1.000124 of it */
    ea_task_t tdef;
    ea_task_init(&tdef, &arm);
    const double dL = hypot(0.5 - arm.x_c, -0.2 - arm.y_c) - hypot(0.3 - arm.x_c, -0.2 - arm.y_c);
    const double v = arm.act.cable_speed_max, a = arm.act.cable_accel_max,
                 m = tdef.limits.resample_margin;
    const double tb = fabs(dL) * (1 + m) / v + v / a;
    printf("  gamma %g: spool bang-bang bound %.6f s, quasi-static / bound %.6f\n", g, tb, dq / tb);
    ea_test_true(dq >= tb && dq <= 1.001 * tb,
                 "qs_min_time_s within 0.1% above the spool's bang-bang bound");
    /* the plan at rest is slower and leaves a small part of the quasi-static ringing:
       measured 1.9 % (gamma 0) and 5.1 % (gamma 0.5) of it; tolerance 2x the larger */
    ea_test_true(d > dq && ratio > 1.0, "the at-rest plan takes longer than the minimum time");
    ea_test_true(r < 0.10 * rq, "at-rest FE residual < 10 % of the quasi-static plan's");
    res_rest[k] = r;
    dur_rest[k] = d;
  }
  /* the same plan and the same FE transient: agreement to the CSV's 12 digits (measured
     2.8e-12 for the durations, 1.2e-12 for the residuals; tolerance 1e-10 relative) */
  printf("  largest relative difference from the independent re-plan: duration %.2e, FE "
         "residual %.2e\n",
         worst_dur, worst_res);
  ea_test_true(worst_dur <= 1e-10,
               "at_rest and qs durations = an independent re-plan of the case (1e-10)");
  ea_test_true(worst_res <= 1e-10, "at_rest and qs FE residual peaks = an independent "
                                   "ea_traj_simulate of the same plan (1e-10)");
  char what[300];
  snprintf(what, sizeof what,
           "payload 0.5 costs time to rest (%.5f s > %.5f s); both checked plans ring <= 1 mm "
           "(%.4f, %.4f mm)",
           dur_rest[1], dur_rest[0], 1e3 * res_rest[0], 1e3 * res_rest[1]);
  ea_test_true(dur_rest[1] > dur_rest[0] && res_rest[0] <= 1e-3 && res_rest[1] <= 1e-3, what);
  free(c1);
  free(c2);
  ea_study_free(&s);
}

/* The shipped example loads; a task of another objective is refused by name. */
static void test_tasks(void) {
  char path[1200];
  snprintf(path, sizeof path, "%s/problems/examples/studies/payload-rest.yaml", g_src);
  ea_study_t s;
  ea_error_t e = {0};
  const ea_status_t st = ea_study_load(path, NULL, &s, &e);
  ea_test_true(st == EA_OK && s.n_cases == 3 && (s.metrics & EA_STUDY_M_AT_REST) &&
                   s.at_rest.modes == 2,
               "payload-rest.yaml: 3 cases, at_rest with 2 modes");
  if (!st) ea_study_free(&s);
  char text[1500];
  snprintf(text, sizeof text,
           "grid: {payload_factor: [0]}\nmetrics: {at_rest: {task: "
           "%s/problems/examples/polyline-effort.yaml}}\n",
           g_src);
  if (ea_study_load_string("x.yaml", text, strlen(text), NULL, &s, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  ea_study_planner_t *p = NULL;
  ea_study_settings_t set;
  ea_study_settings_default(&set);
  const ea_status_t pst = ea_study_use_planner(&s, NULL, &set, &p, &e);
  printf("  %s\n", e.msg);
  ea_test_true(pst == EA_ERR_INPUT && strstr(e.msg, "at_rest task") &&
                   strstr(e.msg, "polyline-effort.yaml") && strstr(e.msg, "not min_time"),
               "at_rest task of another objective refused, naming the task");
  ea_test_true(!p && !set.min_time && !set.at_rest, "refused: no planner, no callbacks");
  ea_study_planner_free(p);
  ea_study_free(&s);
}

int main(void) {
  gsl_set_error_handler_off(); /* every GSL return is checked */
  const char *src = getenv("EA_SOURCE_DIR");
  if (src) snprintf(g_src, sizeof g_src, "%s", src);
  test_tasks();
  test_at_rest();
  return ea_test_summary("test_study_rest");
}
