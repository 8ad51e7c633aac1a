/* plan_identity: plans a fixed random sweep of tasks (tests/test_plan_sweep.c's generator:
 * planar and 3-D pairs, payloads, free paths and straight lines, the lines also by Ipopt
 * alone (solver.nlp ipopt), every line replanned warm
 * after its goal moved) and writes every trajectory and a text record of every solve's
 * outcome (all of ea_plan_info_t but its times) into a folder, for comparing two builds of
 * the planner byte for byte (bench/plan_identity.sh).
 * usage: plan_identity OUTDIR [PAIRS] (default 40) */
#include "ea_planner.h"
#include "ea_problems.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* tests/test_plan_sweep.c's generator (xorshift64*). */
static double id_rand(unsigned long long *s) {
  *s ^= *s >> 12;
  *s ^= *s << 25;
  *s ^= *s >> 27;
  return (double)((*s * 2685821657736338717ULL) >> 11) / 9007199254740992.0;
}

/* Every field of info but the wall times. */
static void id_info(FILE *fp, const char *what, ea_status_t st, const ea_plan_info_t *in) {
  fprintf(fp, "== %s\nreturn %d\nstatus %d\nengine %s %s\nipopt %d %s\n", what, (int)st,
          (int)in->status, ea_plan_engine_name(in), ea_plan_engine_status(in), in->ipopt_status,
          in->ipopt_status_name);
  fprintf(fp, "iterations %d newton %d rows %d resolves %d ipm %d fallback %d threads %d\n",
          in->iterations, in->newton_steps, in->ipopt_rows, in->screen_resolves, in->ipm_iterations,
          in->ipm_fallback, in->threads);
  fprintf(fp, "size %d %d %d evals %d %d between %d deriv %d\n", in->n_var, in->n_con, in->nnz_jac,
          in->evals_g, in->evals_jac, in->between_passes, in->deriv_errors);
  fprintf(fp, "objective %.17g duration %.17g margin %.17g torque %.17g\n", in->objective,
          in->duration_s, in->min_tension_margin_N, in->peak_shoulder_torque_Nm);
  fprintf(fp, "residual %.17g violation %.17g worst %s\n", in->max_statics_residual,
          in->max_violation, in->worst);
  fprintf(fp, "f1 %.17g defl %.17g\n", in->min_first_frequency_hz, in->max_modal_deflection_m);
  fprintf(fp, "dyn %.17g %.17g %.17g %.17g %.17g\n", in->predicted_residual_m,
          in->predicted_time_to_rest_s, in->predicted_residual_worst_m, in->max_modal_deviation_m,
          in->min_dynamic_tension_margin_N);
  for (int i = 0; i < in->n_active && i < EA_PLAN_MAX_ACTIVE; ++i)
    fprintf(fp, "active %s %d\n", in->active[i], in->active_knots[i]);
  fprintf(fp, "message %s\n", in->message);
}

static void id_traj(const char *dir, const char *name, const ea_planner_t *pl) {
  ea_traj_t tr = {0};
  ea_error_t e = {0};
  char path[1024];
  snprintf(path, sizeof path, "%s/%s.csv", dir, name);
  if (ea_planner_trajectory(pl, &tr, &e) || ea_traj_write(&tr, path, &e))
    fprintf(stderr, "%s: %s\n", name, e.msg);
  ea_traj_free(&tr);
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: plan_identity OUTDIR [PAIRS]\n");
    return 1;
  }
  const char *dir = argv[1];
  const int n = argc > 2 ? atoi(argv[2]) : 40;
  char path[1024];
  snprintf(path, sizeof path, "%s/sweep.txt", dir);
  FILE *fp = fopen(path, "w");
  if (!fp) return 1;
  /* free paths, lines, and the lines again with Ipopt alone (solver.nlp ipopt: the reference
   * test_plan_sweep compares the own engines with) */
  for (int pass = 0; pass < 3; ++pass) {
    const ea_task_path_t kind = pass ? EA_TASK_PATH_LINE : EA_TASK_PATH_FREE;
    unsigned long long seed = 0x9E3779B97F4A7C15ULL;
    for (int i = 0; i < n; ++i) {
      ea_task_t t;
      ea_task_init(&t, NULL);
      t.knots = 50;
      t.path = kind;
      if (pass == 2) t.solver.engines = EA_PLANNER_ENGINES_IPOPT;
      const double gamma = 0.5 * id_rand(&seed);
      t.payload_factor = gamma;
      t.payload_kg = ea_arm_payload_from_factor(&t.arm, gamma);
      const int three_d = i % 2;
      for (int k = 0; k < 2; ++k) {
        const double Lc = 0.26 + 0.5 * id_rand(&seed);
        const double al = -1.1 + 1.3 * id_rand(&seed);
        const double b = three_d ? -1.4 + 2.8 * id_rand(&seed) : 0.0;
        ea_task_point_t p = ea_task_point_actuators(Lc, al, b);
        if (k == 0)
          t.start = p;
        else
          t.goal = p;
      }
      ea_error_t e = {0};
      if (ea_task_check(&t, &e)) continue;
      ea_planner_t *pl = NULL;
      ea_plan_info_t info;
      memset(&info, 0, sizeof info);
      char name[64];
      snprintf(name, sizeof name, "%s-%03d", pass == 2 ? "line-ipopt" : pass ? "line" : "free", i);
      ea_status_t st = ea_planner_alloc(&t, &pl, &e);
      if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
      id_info(fp, name, st, &info);
      if (!st) id_traj(dir, name, pl);
      if (!st && kind == EA_TASK_PATH_LINE) {
        /* the replan of test_plan_sweep.c: goal moved, warm */
        unsigned long long s2 = 0xD1B54A32D192ED03ULL ^ (unsigned long long)i;
        ea_task_t t2 = t;
        const double dL = 0.005 * (2.0 * id_rand(&s2) - 1.0);
        const double da = 0.01 * (2.0 * id_rand(&s2) - 1.0);
        t2.goal =
            ea_task_point_actuators(t.goal.given[0] + dL, t.goal.given[1] + da, t.goal.given[2]);
        if (!ea_task_check(&t2, &e)) {
          memset(&info, 0, sizeof info);
          st = ea_planner_update(pl, &t2, &e);
          if (!st) st = ea_planner_solve(pl, EA_PLAN_WARM, NULL, &info, &e);
          strcat(name, "-warm");
          id_info(fp, name, st, &info);
          if (!st) id_traj(dir, name, pl);
        }
      }
      ea_planner_free(pl);
    }
  }
  fclose(fp);
  return 0;
}
