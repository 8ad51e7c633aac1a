/* The path transcription's NLP: Hessian structure, rows, Jacobian and Hessian values (in two
 * parts on two threads with dynamics) and the callbacks the engines call. */
#include "path_impl.h"
#include "hess_impl.h"
#include "knot_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- the NLP --------------------------------------------------------------- */

static int64_t ea__pp_key(const ea__pp_t *pp, int i, int j) {
  return ea__hkey(pp->n, i, j);
}

const ea__row_t *ea__pp_hrow(const ea_planner_t *pl, int r) {
  return r < pl->pp->m ? &pl->pp->rows[r] : &pl->orows[r - pl->pp->m];
}

/* Hessian pieces: the rows and the objective pieces. */
int ea__pp_npieces(const ea_planner_t *pl) {
  return pl->pp->m + pl->n_orows;
}

/* Structure of the Lagrangian's Hessian: every pair of a row's (or objective piece's)
 * entries (rn[r] of them in rc[r * EA__ROW_MAX ..]). */
ea_status_t ea__pp_hess_setup(ea_planner_t *pl, const int *rc, const int *rn) {
  ea__pp_t *pp = pl->pp;
  const int nr = ea__pp_npieces(pl);
  size_t cap = 1;
  for (int r = 0; r < nr; ++r) {
    if (!ea__plan_row_curved(ea__pp_hrow(pl, r))) continue;
    const size_t nc = (size_t)rn[r];
    cap += nc * (nc + 1) / 2;
  }
  int64_t *keys = malloc(cap * sizeof *keys);
  pp->hpos_start = calloc((size_t)nr + 1, sizeof *pp->hpos_start);
  if (!keys || !pp->hpos_start) {
    free(keys);
    return EA_ERR_NOMEM;
  }
  size_t nk = 0;
  for (int r = 0; r < nr; ++r) {
    pp->hpos_start[r] = (int)nk;
    if (!ea__plan_row_curved(ea__pp_hrow(pl, r))) continue;
    const int nc = rn[r], *cols = rc + (size_t)r * EA__ROW_MAX;
    for (int a = 0; a < nc; ++a)
      for (int b = 0; b <= a; ++b)
        keys[nk++] = ea__pp_key(pp, cols[a], cols[b]);
  }
  pp->hpos_start[nr] = (int)nk;
  pp->hpos = malloc((nk + 1) * sizeof *pp->hpos);
  const ea_status_t st =
      pp->hpos ? ea__hpattern(keys, nk, pp->n, &pp->nnz_h, &pp->hirow, &pp->hjcol, pp->hpos)
               : EA_ERR_NOMEM;
  free(keys);
  return st;
}

/* Factor of knot-layout entry i in the path layout (d x_k / d x_s) and its curvature. */
static double ea__pp_factor(const ea__pp_t *pp, int i, double *curv) {
  const int k = pp->kknot[i];
  if (pp->kkind[i] == 1) {
    *curv = pp->dq2[6 * k + pp->kcoord[i]];
    return pp->dq[6 * k + pp->kcoord[i]];
  }
  if (pp->kkind[i] == 2) {
    *curv = pp->dq2[6 * k + 3 + pp->kcoord[i]];
    return pp->dq[6 * k + 3 + pp->kcoord[i]];
  }
  *curv = 0.0;
  return 1.0;
}

/* Hessian of g rows (rows[0..g-1], weights w) by the chain rule through the knot layout
 * x_k = phi(x_s): J^T H_k J + sum_i (d row / d x_k,i) phi_i'', with H_k the knot row's
 * (ea__plan_hess_fd_local: differences of its exact gradient at x_k, no spline in the loop)
 * and phi'' the path's and the statics splines' second derivatives in sigma. Added as w at
 * each row's positions hpos[r] (the pairs of ea__pp_row's entries). Consecutive rows on the
 * same knot entries (a mode's two defects) go through the chain rule once, their weighted
 * sum: the map is linear and their positions are the same. */
static void ea__pp_hess_rows(const ea_planner_t *pl, const ea__row_t *rows, const double *w, int g,
                             const int *const *hpos, double *values, double *xx) {
  const ea__pp_t *pp = pl->pp;
  double Hk[EA__HGROUP_MAX][EA__ROW_MAX][EA__ROW_MAX];
  if (pp->dyn_direct &&
      (rows[0].kind == EA__ROW_DYN_DEF_POS || rows[0].kind == EA__ROW_DYN_DEF_VEL)) {
    /* an interval's modal defects: their Hessians in the path variables directly */
    const int k = rows[0].knot;
    const double sig[2] = {pp->xs_last[EA__PS(pp, k)], pp->xs_last[EA__PS(pp, k + 1)]};
    const double *dq[2] = {pp->dq + 6 * k, pp->dq + 6 * (k + 1)};
    const double *d2q[2] = {pp->dq2 + 6 * k, pp->dq2 + 6 * (k + 1)};
    const int n = ea__plan_dyn_defect_hess_pp(pl, pp->xk, sig, dq, d2q, rows, w, g, Hk);
    for (int r = 0; r < g; ++r) {
      if (w[r] == 0.0) continue;
      const int *p = hpos[r];
      for (int a = 0; a < n; ++a)
        for (int b = 0; b <= a; ++b)
          values[*p++] += w[r] * Hk[r][a][b];
    }
    return;
  }
  int kc[EA__HGROUP_MAX][EA__ROW_MAX], nkc[EA__HGROUP_MAX];
  double gk[EA__HGROUP_MAX][EA__ROW_MAX]; /* the knot rows' gradients, in kc[r]'s order */
  ea__plan_hess_fd_local(pl, ea__plan_row_eval, pp->xk, xx, rows, w, g, kc, nkc, Hk, gk);
  for (int r = 0; r < g;) {
    const int nk = nkc[r];
    if (!nk) {
      ++r;
      continue;
    }
    /* rows r .. r + run - 1 share the knot entries: H, grad = their weighted sum */
    int run = 1;
    while (r + run < g && nkc[r + run] == nk &&
           !memcmp(kc[r + run], kc[r], sizeof(int) * (size_t)nk))
      ++run;
    /* the lower triangle (b <= a) of the symmetrised sum */
    double H[EA__ROW_MAX][EA__ROW_MAX], gs[EA__ROW_MAX];
    for (int a = 0; a < nk; ++a) {
      gs[a] = 0.0;
      for (int b = 0; b <= a; ++b)
        H[a][b] = 0.0;
    }
    for (int q = r; q < r + run; ++q) {
      const double wq = w[q], hq = 0.5 * wq;
      for (int a = 0; a < nk; ++a) {
        gs[a] += wq * gk[q][a];
        for (int b = 0; b <= a; ++b)
          H[a][b] += hq * (Hk[q][a][b] + Hk[q][b][a]);
      }
    }
    /* the path entries in ea__pp_row's order, each knot entry's place and factor */
    int lc[EA__ROW_MAX], pos[EA__ROW_MAX], n = 0;
    double f[EA__ROW_MAX], c[EA__ROW_MAX];
    for (int e = 0; e < nk; ++e) {
      const int col = pp->kidx[kc[r][e]];
      pos[e] = -1;
      if (col < 0) continue;
      int q = 0;
      while (q < n && lc[q] != col)
        ++q;
      if (q == n) lc[n++] = col;
      pos[e] = q;
      f[e] = ea__pp_factor(pp, kc[r][e], &c[e]);
    }
    double Hp[EA__ROW_MAX][EA__ROW_MAX];
    for (int a = 0; a < n; ++a)
      for (int b = 0; b <= a; ++b)
        Hp[a][b] = 0.0;
    /* Hp's lower triangle in the path entries' order: an entry (a, b) of H below the diagonal
     * and its mirror (b, a) go to (pa, pb) and (pb, pa), of which one is in it */
    for (int a = 0; a < nk; ++a) {
      const int pa = pos[a];
      if (pa < 0) continue;
      Hp[pa][pa] += gs[a] * c[a] + f[a] * f[a] * H[a][a];
      for (int b = 0; b < a; ++b) {
        const int pb = pos[b];
        if (pb < 0) continue;
        const double v = f[a] * f[b] * H[a][b];
        if (pa > pb)
          Hp[pa][pb] += v;
        else if (pa < pb)
          Hp[pb][pa] += v;
        else
          Hp[pa][pa] += 2.0 * v;
      }
    }
    const int *p = hpos[r];
    for (int a = 0; a < n; ++a)
      for (int b = 0; b <= a; ++b)
        values[*p++] += Hp[a][b];
    r += run;
  }
}

/* The rows' part (ea__par_t's) with dynamics, -1 without. */
static int ea__pp_part(const ea__pp_t *pp, const ea__row_t *r) {
  return pp->split < 0 ? -1 : r->knot >= pp->split;
}

/* One part's work of a callback at x (part -1: all rows; ea__pp_job's). */
typedef struct {
  ea_planner_t *pl;
  const double *x, *lambda;
  double *out;
  double sigma; /* the objective's weight (Hessian) */
  int what;     /* 0 rows' values, 1 Jacobian, 2 Hessian */
} ea__pp_job_t;

static void ea__pp_job_part(void *ctx, int part) {
  const ea__pp_job_t *jb = ctx;
  ea_planner_t *pl = jb->pl;
  ea__pp_t *pp = pl->pp;
  if (jb->what < 2) {
    /* the values come with the Jacobian's where it is kept (pp->jv_keep) */
    double *jac = jb->what == 1 ? jb->out : pp->jv_keep;
    for (int i = 0; i < pp->m; ++i)
      if (ea__pp_part(pp, &pp->rows[i]) == part)
        ea__pp_row(pl, jb->x, &pp->rows[i], jb->what == 0 ? &jb->out[i] : NULL, NULL,
                   jac ? jac + pp->jstart[i] : NULL);
    return;
  }
  double *values = part == 1 ? pp->hv1 : jb->out, *xx = part == 1 ? pp->xkx1 : pp->xkx;
  for (int r = 0; r < pp->m;) {
    const int g = ea__plan_hess_group_len(pp->rows, r, pp->m);
    if (ea__pp_part(pp, &pp->rows[r]) == part && ea__plan_row_curved(&pp->rows[r])) {
      const int *hp[EA__HGROUP_MAX];
      for (int q = 0; q < g; ++q)
        hp[q] = pp->hpos + pp->hpos_start[r + q];
      ea__pp_hess_rows(pl, &pp->rows[r], jb->lambda + r, g, hp, values, xx);
    }
    r += g;
  }
  /* the objective's pieces (of the part's knots too) */
  for (int o = 0; o < pl->n_orows; ++o) {
    const ea__row_t *row = &pl->orows[o];
    const double w = jb->sigma * pl->oweight[o];
    if (ea__pp_part(pp, row) != part || !ea__plan_row_curved(row)) continue;
    const int *hp[1] = {pp->hpos + pp->hpos_start[pp->m + o]};
    ea__pp_hess_rows(pl, row, &w, 1, hp, values, xx);
  }
}

/* Run a callback's work on all rows: in two parts with dynamics, else at once. The parts'
 * rows (the knots' below pp->split and the rest) share the expansion of x and the tables at the
 * knot pp->split (a row of knot k reads the expansion at knots k - 1 .. k + 1, its model tables
 * at k and k + 1), made current first; every other cache they fill is of their own knots. */
static void ea__pp_job(ea__pp_job_t *jb) {
  ea__pp_t *pp = jb->pl->pp;
  if (pp->split < 0) {
    ea__pp_job_part(jb, -1);
    return;
  }
  ea__pp_expand(jb->pl, jb->x);
  ea__plan_dyn_warm(jb->pl, pp->xk, pp->split);
  ea__par_run(pp->par, ea__pp_job_part, jb);
}

/* Hessian values: the chain rule through the knot layout (ea__pp_hess_rows). */
static void ea__pp_hess_values(ea_planner_t *pl, const double *x, double sigma,
                               const double *lambda, double *values) {
  ea__pp_t *pp = pl->pp;
  memset(values, 0, (size_t)pp->nnz_h * sizeof *values);
  ea__pp_expand(pl, x);
  memcpy(pp->xkx, pp->xk, (size_t)pl->n * sizeof *pp->xk);
  if (pp->split >= 0) {
    memset(pp->hv1, 0, (size_t)pp->nnz_h * sizeof *values);
    memcpy(pp->xkx1, pp->xk, (size_t)pl->n * sizeof *pp->xk);
  }
  ea__pp_job_t jb = {pl, x, lambda, values, sigma, 2};
  ea__pp_job(&jb);
  if (pp->split >= 0)
    for (int i = 0; i < pp->nnz_h; ++i)
      values[i] += pp->hv1[i];
}

int ea__pp_test_dims(const ea_planner_t *pl, int *n, int *m, const double **x_sol, int *nnz_h,
                     const int **hrow, const int **hcol) {
  const ea__pp_t *pp = pl->pp;
  if (!pp) return -1;
  *n = pp->n;
  *m = pp->m;
  *x_sol = pp->x_sol;
  *nnz_h = pp->nnz_h;
  *hrow = pp->hirow;
  *hcol = pp->hjcol;
  return 0;
}

int ea__pp_threads(const ea_planner_t *pl) {
  return pl->pp && pl->pp->par ? 2 : 1;
}

int ea__pp_test_direct(const ea_planner_t *pl) {
  return pl->pp && pl->pp->dyn_direct;
}

int ea__pp_test_row(const ea_planner_t *pl, const double *xs, int r, double *value, int *cols,
                    double *vals) {
  return ea__pp_row(pl, xs, &pl->pp->rows[r], value, cols, vals);
}

void ea__pp_test_hess(ea_planner_t *pl, const double *xs, double sigma, const double *lambda,
                      double *values) {
  ea__pp_hess_values(pl, xs, sigma, lambda, values);
}

int ea__pp_cb_f(int n, double *x, int new_x, double *f, void *ud) {
  ea_planner_t *pl = ud;
  (void)n, (void)new_x;
  const double t0 = ea__mono_s();
  ea__pp_expand(pl, x);
  double v = 0.0;
  for (int i = 0; i < pl->n_terms; ++i)
    v += pl->terms[i].weight * pl->terms[i].value(pl, pl->pp->xk);
  *f = v;
  pl->t_callbacks += ea__mono_s() - t0;
  return isfinite(v);
}

int ea__pp_cb_grad_f(int n, double *x, int new_x, double *g, void *ud) {
  ea_planner_t *pl = ud;
  ea__pp_t *pp = pl->pp;
  (void)new_x;
  const double t0 = ea__mono_s();
  ea__pp_expand(pl, x);
  memset(pp->gk, 0, (size_t)pl->n * sizeof *pp->gk);
  for (int i = 0; i < pl->n_terms; ++i)
    pl->terms[i].grad(pl, pp->xk, pl->terms[i].weight, pp->gk);
  memset(g, 0, (size_t)n * sizeof *g);
  for (int i = 0; i < pl->n; ++i) {
    if (pp->gk[i] == 0.0 || pp->kidx[i] < 0) continue;
    double f = 1.0;
    if (pp->kkind[i] == 1)
      f = pp->dq[6 * pp->kknot[i] + pp->kcoord[i]];
    else if (pp->kkind[i] == 2)
      f = pp->dq[6 * pp->kknot[i] + 3 + pp->kcoord[i]];
    g[pp->kidx[i]] += pp->gk[i] * f;
  }
  pl->t_callbacks += ea__mono_s() - t0;
  return 1;
}

int ea__pp_cb_g(int n, double *x, int new_x, int m, double *g, void *ud) {
  ea_planner_t *pl = ud;
  (void)n, (void)new_x, (void)m;
  const double t0 = ea__mono_s();
  ea__pp_t *pp = pl->pp;
  ea__pp_job_t jb = {pl, x, NULL, g, 0.0, 0};
  ea__pp_job(&jb);
  if (pp->jv_keep) {
    memcpy(pp->jv_x, x, (size_t)pp->n * sizeof *x);
    pp->jv_valid = 1;
  }
  if (pl->info) pl->info->evals_g++;
  pl->t_callbacks += ea__mono_s() - t0;
  return 1;
}

int ea__pp_cb_jac(int n, double *x, int new_x, int m, int nele, int *iRow, int *jCol,
                  double *values, void *ud) {
  ea_planner_t *pl = ud;
  ea__pp_t *pp = pl->pp;
  (void)n, (void)new_x, (void)m, (void)nele;
  if (!values) {
    memcpy(iRow, pp->irow, (size_t)pp->nnz * sizeof *iRow);
    memcpy(jCol, pp->jcol, (size_t)pp->nnz * sizeof *jCol);
    return 1;
  }
  const double t0 = ea__mono_s();
  if (pp->jv_valid && !memcmp(pp->jv_x, x, (size_t)pp->n * sizeof *x)) {
    memcpy(values, pp->jv_keep, (size_t)pp->nnz * sizeof *values); /* the rows' pass had them */
  } else {
    ea__pp_job_t jb = {pl, x, NULL, values, 0.0, 1};
    ea__pp_job(&jb);
  }
  if (pl->info) pl->info->evals_jac++;
  pl->t_callbacks += ea__mono_s() - t0;
  return 1;
}

int ea__pp_cb_h(int n, double *x, int new_x, double of, int m, double *lambda, int new_lambda,
                int nele, int *iRow, int *jCol, double *values, void *ud) {
  ea_planner_t *pl = ud;
  ea__pp_t *pp = pl->pp;
  (void)n, (void)new_x, (void)m, (void)new_lambda, (void)nele;
  if (!values) {
    memcpy(iRow, pp->hirow, (size_t)pp->nnz_h * sizeof *iRow);
    memcpy(jCol, pp->hjcol, (size_t)pp->nnz_h * sizeof *jCol);
    return 1;
  }
  const double t0 = ea__mono_s();
  ea__pp_hess_values(pl, x, of, lambda, values);
  pl->t_callbacks += ea__mono_s() - t0;
  return 1;
}

int ea__pp_cb_iter(int alg_mod, int iter, double obj, double inf_pr, double inf_du, double mu,
                   double d_norm, double reg, double alpha_du, double alpha_pr, int ls, void *ud) {
  ea_planner_t *pl = ud;
  (void)alg_mod, (void)obj, (void)inf_pr, (void)inf_du, (void)mu, (void)d_norm, (void)reg;
  (void)alpha_du, (void)alpha_pr, (void)ls;
  pl->pp->iter = iter;
  return ea__mono_s() - pl->t_start < pl->max_time ? 1 : 0;
}

void ea__pp_nlp(const ea_planner_t *pl, ea__nlp_t *p) {
  const ea__pp_t *pp = pl->pp;
  *p = (ea__nlp_t){.n = pp->n,
                   .m = pp->m,
                   .nnz_j = pp->nnz,
                   .nnz_h = pp->nnz_h,
                   .xl = pp->xl,
                   .xu = pp->xu,
                   .gl = pp->gl,
                   .gu = pp->gu,
                   .jrow = pp->irow,
                   .jcol = pp->jcol,
                   .hrow = pp->hirow,
                   .hcol = pp->hjcol,
                   .f = ea__pp_cb_f,
                   .grad_f = ea__pp_cb_grad_f,
                   .g = ea__pp_cb_g,
                   .jac = ea__pp_cb_jac,
                   .h = ea__pp_cb_h,
                   .iter = ea__pp_cb_iter,
                   .ud = (void *)pl,
                   .hess_last = pl->K == 0};
}
