/* The knot transcription's callbacks (objective, rows, Jacobian, Hessian, iteration), as the
 * engines call them. */
#include "plan_impl.h"
#include "hess_impl.h"
#include "knot_impl.h"
#include "nlp_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------------- */
/* Ipopt callbacks                                                          */
/* ---------------------------------------------------------------------- */

static void ea__touch(ea_planner_t *pl, int new_x) {
  if (new_x) pl->cache_val = pl->cache_sens = 0;
}

int ea__knot_cb_f(int n, double *x, int new_x, double *f, void *ud) {
  ea_planner_t *pl = ud;
  (void)n;
  const double t0 = ea__mono_s();
  ea__touch(pl, new_x);
  double v = 0.0;
  for (int i = 0; i < pl->n_terms; ++i)
    v += pl->terms[i].weight * pl->terms[i].value(pl, x);
  *f = v;
  pl->t_callbacks += ea__mono_s() - t0;
  return isfinite(v);
}

int ea__knot_cb_grad_f(int n, double *x, int new_x, double *g, void *ud) {
  ea_planner_t *pl = ud;
  const double t0 = ea__mono_s();
  ea__touch(pl, new_x);
  memset(g, 0, (size_t)n * sizeof *g);
  for (int i = 0; i < pl->n_terms; ++i)
    pl->terms[i].grad(pl, x, pl->terms[i].weight, g);
  pl->t_callbacks += ea__mono_s() - t0;
  return 1;
}

int ea__knot_cb_g(int n, double *x, int new_x, int m, double *g, void *ud) {
  ea_planner_t *pl = ud;
  (void)n;
  (void)m;
  const double t0 = ea__mono_s();
  ea__touch(pl, new_x);
  const ea_status_t st = ea__plan_eval_g(pl, x, g);
  if (pl->info) pl->info->evals_g++;
  pl->t_callbacks += ea__mono_s() - t0;
  return st == EA_OK;
}

int ea__knot_cb_jac(int n, double *x, int new_x, int m, int nele, int *iRow, int *jCol,
                    double *values, void *ud) {
  ea_planner_t *pl = ud;
  (void)n;
  (void)m;
  (void)nele;
  if (!values) {
    memcpy(iRow, pl->irow, (size_t)pl->nnz * sizeof *iRow);
    memcpy(jCol, pl->jcol, (size_t)pl->nnz * sizeof *jCol);
    return 1;
  }
  const double t0 = ea__mono_s();
  ea__touch(pl, new_x);
  if (ea__plan_shoot_all(pl, x, 1)) return 0;
  ea__plan_jac(pl, x, NULL, NULL, values);
  if (pl->info) pl->info->evals_jac++;
  pl->t_callbacks += ea__mono_s() - t0;
  return 1;
}

int ea__knot_cb_h(int n, double *x, int new_x, double of, int m, double *lambda, int new_lambda,
                  int nele, int *iRow, int *jCol, double *values, void *ud) {
  ea_planner_t *pl = ud;
  (void)n, (void)m, (void)new_lambda, (void)nele;
  if (!pl->hess_exact) return 0; /* limited-memory quasi-Newton */
  if (!values) {
    memcpy(iRow, pl->hirow, (size_t)pl->nnz_h * sizeof *iRow);
    memcpy(jCol, pl->hjcol, (size_t)pl->nnz_h * sizeof *jCol);
    return 1;
  }
  const double t0 = ea__mono_s();
  ea__touch(pl, new_x);
  const ea_status_t st = ea__plan_hess_values(pl, x, of, lambda, values);
  pl->t_callbacks += ea__mono_s() - t0;
  return st == EA_OK;
}

int ea__plan_time_up(void *ud) {
  const ea_planner_t *pl = ud;
  return !(ea__mono_s() - pl->t_start < pl->max_time);
}

int ea__knot_cb_iter(int alg_mod, int iter, double obj, double inf_pr, double inf_du, double mu,
                     double d_norm, double reg, double alpha_du, double alpha_pr, int ls,
                     void *ud) {
  ea_planner_t *pl = ud;
  (void)alg_mod, (void)obj, (void)inf_pr, (void)inf_du, (void)mu, (void)d_norm, (void)reg;
  (void)alpha_du, (void)alpha_pr, (void)ls;
  pl->iter = iter;
  return ea__mono_s() - pl->t_start < pl->max_time ? 1 : 0;
}

void ea__knot_nlp(const ea_planner_t *pl, ea__nlp_t *p) {
  *p = (ea__nlp_t){.n = pl->n,
                   .m = pl->m,
                   .nnz_j = pl->nnz,
                   .nnz_h = pl->hess_exact ? pl->nnz_h : 0,
                   .xl = pl->xl,
                   .xu = pl->xu,
                   .gl = pl->gl,
                   .gu = pl->gu,
                   .jrow = pl->irow,
                   .jcol = pl->jcol,
                   .hrow = pl->hirow,
                   .hcol = pl->hjcol,
                   .f = ea__knot_cb_f,
                   .grad_f = ea__knot_cb_grad_f,
                   .g = ea__knot_cb_g,
                   .jac = ea__knot_cb_jac,
                   .h = ea__knot_cb_h,
                   .iter = ea__knot_cb_iter,
                   .ud = (void *)pl,
                   .hess_last = pl->K == 0};
}

/* The KKT test's rows and Jacobian: every knot shot again (the cache may hold shots of another
 * task), not counted as the engines' evaluations. */
static int ea__knot_check_g(int n, double *x, int new_x, int m, double *g, void *ud) {
  (void)n, (void)new_x, (void)m;
  return ea__plan_eval_g(ud, x, g) == EA_OK;
}

static int ea__knot_check_jac(int n, double *x, int new_x, int m, int nele, int *iRow, int *jCol,
                              double *values, void *ud) {
  (void)n, (void)new_x, (void)m, (void)nele, (void)iRow, (void)jCol;
  ea__plan_jac(ud, x, NULL, NULL, values);
  return 1;
}

int ea__knot_kkt_ok(ea_planner_t *pl, const double *x, double dtol) {
  ea__nlp_t p;
  ea__knot_nlp(pl, &p);
  p.g = ea__knot_check_g;
  p.jac = ea__knot_check_jac;
  pl->cache_val = pl->cache_sens = 0;
  const ea__kkt_work_t w = {pl->g, pl->kkt_r, pl->jval};
  return ea__kkt_accept(&p, x, pl->mult_g, pl->mult_xl, pl->mult_xu,
                        fmax(1e-9, pl->task.solver.constr_tol), dtol, &w);
}
