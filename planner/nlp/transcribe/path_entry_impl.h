/* Private: what the planner calls of the path transcription (transcribe/path_*.c; its inside:
 * transcribe/path_impl.h). */
#ifndef EA_PATH_ENTRY_IMPL_H
#define EA_PATH_ENTRY_IMPL_H

#include "plan_impl.h"

/** The path transcription (transcribe/path_*.c): does the task qualify (line/polyline, no frequency
 *  model, exact Hessian)? */
int ea__pp_supported(const ea_planner_t *pl);
/** Build it (after the knot planner's rows, bounds and Hessian structure). */
ea_status_t ea__pp_alloc(ea_planner_t *pl, ea_error_t *err);
void ea__pp_free(struct ea__pp *pp);
/** The rates of the statics (T, theta0, kappa0) at knot k of the knot-layout plan x along its
 *  (L_c, alpha) rates, from the path's tabulated partial derivatives (the limits between the
 *  knots' screen, plan_between.c); 0, or -1 without a path transcription. */
int ea__pp_statics_rates(const ea_planner_t *pl, const double *x, int k, double pd[3]);
/** After ea_planner_update: the path moved: statics splines and bounds again. */
ea_status_t ea__pp_update(ea_planner_t *pl, ea_error_t *err);
/** A solve in the path coordinate: guess (start), the engines of the strategy
 *  (strategy/strategy_impl.h); pl->x gets the plan in the knot layout (expanded), pl->g its
 *  rows; *res the engines' outcome (its time excepted), *obj the objective. */
ea_status_t ea__pp_solve(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                         ea_plan_info_t *info, ea__engine_result_t *res, double *obj,
                         ea_error_t *err);
/** For tests (tests/test_plan_hess.c): the path layout's size, its last solution and Hessian
 *  pattern (lower triangle); 0, or -1 without a path transcription. */
int ea__pp_test_dims(const ea_planner_t *pl, int *n, int *m, const double **x_sol, int *nnz_h,
                     const int **hrow, const int **hcol);
/** Path row r at xs: value, entries (cols) and gradient (vals); the entry count. */
int ea__pp_test_row(const ea_planner_t *pl, const double *xs, int r, double *value, int *cols,
                    double *vals);
/** The Lagrangian Hessian of the path layout at xs (objective weight sigma, multipliers lambda)
 *  into values (the pattern's order), as Ipopt and the own interior point get it. */
void ea__pp_test_hess(ea_planner_t *pl, const double *xs, double sigma, const double *lambda,
                      double *values);
/** Threads of the path transcription's evaluations (2 with its worker), 1 without it. */
int ea__pp_threads(const ea_planner_t *pl);
/** Are the modal defects' Hessians and gradients kept in the path layout directly
 *  (ea__plan_dyn_defect_hess_pp)? 1 yes, 0 through the knot layout. */
int ea__pp_test_direct(const ea_planner_t *pl);

#endif
