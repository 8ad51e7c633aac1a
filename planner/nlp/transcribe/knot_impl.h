/* Private: the knot transcription (transcribe/knot_rows.c, knot_build.c, knot_callbacks.c):
 * its rows and their evaluation, the bounds, the callbacks and its NLP description. */
#ifndef EA_KNOT_IMPL_H
#define EA_KNOT_IMPL_H

#include "plan_impl.h"

/** Shoot every knot at x, with sensitivities when sens (a knot whose p is unchanged and
 *  whose shot has what is asked is not shot again). */
ea_status_t ea__plan_shoot_all(ea_planner_t *pl, const double *x, int sens);
/** The rows' families (m): one limit of one coordinate (an interval's start and end rows of
 *  a limit together), for leaving rows out of Ipopt's problem (engine/ipopt_screen.c); returns the
 *  number of families. */
int ea__plan_row_families(const ea__row_t *rows, int m, int *fam);
/** Constraint values at x into g (m). */
ea_status_t ea__plan_eval_g(ea_planner_t *pl, const double *x, double *g);
/** The same from shots without sensitivities (a check of the rows' values only). */
ea_status_t ea__plan_eval_g_values(ea_planner_t *pl, const double *x, double *g);
/** Jacobian: structure (values NULL) or values (irow/jcol NULL). Returns nnz. */
int ea__plan_jac(ea_planner_t *pl, const double *x, int *irow, int *jcol, double *values);
/** One row (constraint or objective piece): value and entries (col, val);
 *  returns the entry count (<= EA__ROW_MAX). Statics rows read the cached sensitivities. */
int ea__plan_row_eval(const ea_planner_t *pl, const double *x, const ea__row_t *r, double *value,
                      int *cols, double *vals);
/** The closed-form Hessian of a row whose curvature is the Hermite's in t_f (acceleration,
 *  acceleration continuity, the speed rows' middle coefficient, the acceleration and jerk
 *  objective pieces) or the table's (the tension and torque rows with the modal parts): H[a][b]
 * over the row's entries (cols, in ea__plan_row_eval's order); returns their count, or -1 for any
 * other kind. */
int ea__plan_row_hess(const ea_planner_t *pl, const double *x, const ea__row_t *r, int *cols,
                      double H[][EA__ROW_MAX]);
/** Objective terms for the task. */
void ea__plan_terms_setup(ea_planner_t *pl);
/** Name of a row kind ("tension", ...). */
const char *ea__plan_row_name(const ea_planner_t *pl, const ea__row_t *r, char *buf, size_t len);
/** Physical units per unit of row r's value (1 / acc_scale for the
 *  acceleration rows, else 1). */
double ea__plan_row_unit(const ea_planner_t *pl, const ea__row_t *r);
/** The rows (pl->rows NULL: only counted); returns their count. */
int ea__knot_rows(ea_planner_t *pl);
/** Variable and row bounds from the task. */
void ea__knot_bounds(ea_planner_t *pl);
/* The callbacks of the knot transcription, in Ipopt's C interface's signatures. */
int ea__knot_cb_f(int n, double *x, int new_x, double *f, void *ud);
int ea__knot_cb_grad_f(int n, double *x, int new_x, double *g, void *ud);
int ea__knot_cb_g(int n, double *x, int new_x, int m, double *g, void *ud);
int ea__knot_cb_jac(int n, double *x, int new_x, int m, int nele, int *iRow, int *jCol,
                    double *values, void *ud);
int ea__knot_cb_h(int n, double *x, int new_x, double of, int m, double *lambda, int new_lambda,
                  int nele, int *iRow, int *jCol, double *values, void *ud);
int ea__knot_cb_iter(int alg_mod, int iter, double obj, double inf_pr, double inf_du, double mu,
                     double d_norm, double reg, double alpha_du, double alpha_pr, int ls, void *ud);
struct ea__nlp;
/** Its description (engine/nlp_impl.h), for the engines. */
void ea__knot_nlp(const ea_planner_t *pl, struct ea__nlp *p);
/** Is x with pl->mult_* a KKT point (engine/kkt_test.c: ea__kkt_accept) to the task's row
 *  tolerance and dual tolerance dtol? 1 yes, 0 no. */
int ea__knot_kkt_ok(ea_planner_t *pl, const double *x, double dtol);

#endif
