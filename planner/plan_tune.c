/* Optional derivative-free tuning of the knot time distribution with NLopt
 * (task solver.tune_schedule, min_time only): the fractions s_k follow
 * s(u) = u - w sin(2 pi u) / (2 pi), u = k / (N - 1); w > 0 packs knots
 * towards the start and the goal, where minimum-time plans switch between
 * acceleration and speed limits. BOBYQA minimises the planned duration over
 * w in [-0.8, 0.8], each evaluation a warm-started plan.
 * It did not earn its keep (docs/planner.md, "Schedule tuning (removed)": -0.002 % of
 * duration at 100 knots for 1 s of tuning): the task key and the CLI flag are gone; this file
 * and the solver's call go with the solver's rewrite. */
#include "plan_impl.h"

#include <math.h>
#include <nlopt.h>

typedef struct {
  ea_planner_t *pl;
  int evals;
  double best_w, best_tf;
} ea__tune_t;

ea_status_t ea__plan_solve_once(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                                ea_plan_info_t *info, ea_error_t *err);

static double ea__tune_f(unsigned n, const double *w, double *grad, void *data) {
  ea__tune_t *t = data;
  (void)n;
  (void)grad;
  ea__plan_schedule(t->pl, w[0]);
  ea_plan_info_t info;
  const ea_status_t st = ea__plan_solve_once(
      t->pl, t->pl->have_solution ? EA_PLAN_WARM : EA_PLAN_COLD, NULL, &info, NULL);
  ++t->evals;
  const double tf = st == EA_OK ? info.duration_s : 1e6;
  if (tf < t->best_tf) {
    t->best_tf = tf;
    t->best_w = w[0];
  }
  return tf;
}

ea_status_t ea__plan_tune(ea_planner_t *pl, double *w_best, ea_error_t *err);
ea_status_t ea__plan_tune(ea_planner_t *pl, double *w_best, ea_error_t *err) {
  ea__tune_t t = {pl, 0, 0.0, INFINITY};
  nlopt_opt opt = nlopt_create(NLOPT_LN_BOBYQA, 1);
  if (!opt) return ea_error_set(err, EA_ERR_NOMEM, "NLopt: cannot create the optimiser");
  const double lb = -0.8, ub = 0.8;
  double w = 0.0, f = 0.0;
  nlopt_set_lower_bounds(opt, &lb);
  nlopt_set_upper_bounds(opt, &ub);
  nlopt_set_min_objective(opt, ea__tune_f, &t);
  nlopt_set_xtol_abs1(opt, 0.02);
  nlopt_set_maxeval(opt, 12);
  const double step = 0.3;
  nlopt_set_initial_step(opt, &step);
  const nlopt_result r = nlopt_optimize(opt, &w, &f);
  nlopt_destroy(opt);
  *w_best = isfinite(t.best_tf) ? t.best_w : 0.0;
  if (r < 0 && !isfinite(t.best_tf))
    return ea_error_set(err, EA_ERR_BACKEND, "NLopt schedule tuning failed (code %d)", (int)r);
  return EA_OK;
}
