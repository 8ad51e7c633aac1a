/* Ipopt on an NLP whose inequality rows far inside their limits are left out
 * (docs/planner-measurements.md, "Benches"). Each inequality row costs Ipopt two rows and columns
 * of its KKT system (the row and its slack), and a factorization through MUMPS costs in proportion
 * to that size at 100 knots (overhead per front rather than flops): on the paper line 398 of the
 * 692 rows are inequalities and about 110 of them come near their limits. The rows left out are the
 * two-sided ones whose family (one limit of one coordinate) lies in the inner part of its range at
 * the start; after the solve, every row left out is checked at the solution: strictly inside its
 * limits, it is inactive there and the solution (with multiplier 0 for it) is one of the full NLP
 * too; otherwise it joins, and the caller solves again.
 *
 * The wrappers below present the kept rows to Ipopt and pass the full NLP's user data to its
 * callbacks, which evaluate every row. Calls nothing above it. */
#include "plan_screen_impl.h"

#include <coin/IpStdCInterface.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct ea__screen {
  ea__screen_nlp_t p;
  int ms, nnz_s;                /* kept rows, their Jacobian entries */
  unsigned char *keep;          /* m */
  int *rsub, *joff, *irs, *jcs; /* kept row -> row (ms); row -> first entry (m + 1); structure */
  double *gls, *gus, *gfull, *jfull, *lfull, *msub, *gsub;
};

void ea__screen_free(ea__screen_t *s) {
  if (!s) return;
  free(s->keep), free(s->rsub), free(s->joff), free(s->irs), free(s->jcs), free(s->gls);
  free(s->gus), free(s->gfull), free(s->jfull), free(s->lfull), free(s->msub), free(s->gsub);
  free(s);
}

ea__screen_t *ea__screen_alloc(const ea__screen_nlp_t *p) {
  ea__screen_t *s = calloc(1, sizeof *s);
  if (!s) return NULL;
  s->p = *p;
  const size_t m = (size_t)p->m + 1, nz = (size_t)p->nnz_j + 1;
  s->keep = malloc(m), s->rsub = malloc(sizeof(int) * m), s->joff = malloc(sizeof(int) * m);
  s->irs = malloc(sizeof(int) * nz), s->jcs = malloc(sizeof(int) * nz);
  s->gls = malloc(sizeof(double) * m), s->gus = malloc(sizeof(double) * m);
  s->gfull = malloc(sizeof(double) * m), s->jfull = malloc(sizeof(double) * nz);
  s->lfull = malloc(sizeof(double) * m), s->msub = malloc(sizeof(double) * m);
  s->gsub = malloc(sizeof(double) * m);
  if (!s->keep || !s->rsub || !s->joff || !s->irs || !s->jcs || !s->gls || !s->gus || !s->gfull ||
      !s->jfull || !s->lfull || !s->msub || !s->gsub) {
    ea__screen_free(s);
    return NULL;
  }
  /* each row's entries: contiguous, rows in order */
  int e = 0;
  for (int i = 0; i < p->m; ++i) {
    s->joff[i] = e;
    while (e < p->nnz_j && p->jrow[e] == i)
      ++e;
  }
  s->joff[p->m] = e;
  if (e != p->nnz_j) {
    ea__screen_free(s);
    return NULL;
  }
  ea__screen_all(s);
  return s;
}

/* The kept rows' lists from s->keep. */
static void ea__screen_lists(ea__screen_t *s) {
  const ea__screen_nlp_t *p = &s->p;
  s->ms = s->nnz_s = 0;
  for (int i = 0; i < p->m; ++i) {
    if (!s->keep[i]) continue;
    for (int e = s->joff[i]; e < s->joff[i + 1]; ++e)
      s->irs[s->nnz_s] = s->ms, s->jcs[s->nnz_s++] = p->jcol[e];
    s->gls[s->ms] = p->gl[i], s->gus[s->ms] = p->gu[i];
    s->rsub[s->ms++] = i;
  }
}

/* Row i's distance from its middle in half-widths (0 for the rows never left out: equalities
 * and one-sided rows). */
static int ea__screen_two_sided(const ea__screen_nlp_t *p, int i, double g, double *level) {
  const double lo = p->gl[i], hi = p->gu[i];
  if (!(lo < hi) || !(lo > -1e19) || !(hi < 1e19)) return 0;
  *level = fabs(g - 0.5 * (lo + hi)) / (0.5 * (hi - lo));
  return 1;
}

void ea__screen_all(ea__screen_t *s) {
  memset(s->keep, 1, (size_t)s->p.m);
  ea__screen_lists(s);
}

int ea__screen_select(ea__screen_t *s, const double *g, double band, const int *family, int nfam) {
  int out = 0;
  for (int i = 0; i < s->p.m; ++i) {
    double lv;
    s->keep[i] = !(ea__screen_two_sided(&s->p, i, g[i], &lv) && lv < band);
  }
  /* a family with a row kept keeps its rows: a limit that one knot comes near is the one the
   * solution may push against at others (row by row, rows left out come out far beyond their
   * limits and the solves repeat: docs/planner.md, "Tried, not adopted") */
  if (family && nfam > 0) {
    unsigned char *fk = calloc((size_t)nfam, 1);
    if (!fk) {
      memset(s->keep, 1, (size_t)s->p.m);
    } else {
      for (int i = 0; i < s->p.m; ++i)
        if (s->keep[i] && family[i] >= 0 && family[i] < nfam) fk[family[i]] = 1;
      for (int i = 0; i < s->p.m; ++i)
        if (family[i] >= 0 && family[i] < nfam && fk[family[i]]) s->keep[i] = 1;
      free(fk);
    }
  }
  for (int i = 0; i < s->p.m; ++i)
    out += !s->keep[i];
  ea__screen_lists(s);
  return out;
}

int ea__screen_grow(ea__screen_t *s, const double *g, double band) {
  int in = 0;
  for (int i = 0; i < s->p.m; ++i) {
    double lv;
    if (s->keep[i] || !ea__screen_two_sided(&s->p, i, g[i], &lv)) continue;
    if (!(lv < band)) s->keep[i] = 1, ++in; /* NaN joins too */
  }
  if (in) ea__screen_lists(s);
  return in;
}

int ea__screen_rows(const ea__screen_t *s) {
  return s->ms;
}

static Bool ea__screen_cb_f(Index n, Number *x, Bool new_x, Number *f, UserDataPtr ud) {
  const ea__screen_t *s = ud;
  return s->p.f(n, x, new_x, f, s->p.ud);
}

static Bool ea__screen_cb_grad_f(Index n, Number *x, Bool new_x, Number *gf, UserDataPtr ud) {
  const ea__screen_t *s = ud;
  return s->p.grad_f(n, x, new_x, gf, s->p.ud);
}

static Bool ea__screen_cb_g(Index n, Number *x, Bool new_x, Index m, Number *g, UserDataPtr ud) {
  ea__screen_t *s = ud;
  (void)m;
  if (!s->p.g(n, x, new_x, s->p.m, s->gfull, s->p.ud)) return FALSE;
  for (int i = 0; i < s->ms; ++i)
    g[i] = s->gfull[s->rsub[i]];
  return TRUE;
}

static Bool ea__screen_cb_jac(Index n, Number *x, Bool new_x, Index m, Index nele, Index *iRow,
                              Index *jCol, Number *values, UserDataPtr ud) {
  ea__screen_t *s = ud;
  (void)m, (void)nele;
  if (!values) {
    memcpy(iRow, s->irs, sizeof(int) * (size_t)s->nnz_s);
    memcpy(jCol, s->jcs, sizeof(int) * (size_t)s->nnz_s);
    return TRUE;
  }
  if (!s->p.jac(n, x, new_x, s->p.m, s->p.nnz_j, NULL, NULL, s->jfull, s->p.ud)) return FALSE;
  int nz = 0;
  for (int k = 0; k < s->ms; ++k) {
    const int i = s->rsub[k];
    for (int e = s->joff[i]; e < s->joff[i + 1]; ++e)
      values[nz++] = s->jfull[e];
  }
  return TRUE;
}

static Bool ea__screen_cb_h(Index n, Number *x, Bool new_x, Number of, Index m, Number *lambda,
                            Bool new_lambda, Index nele, Index *iRow, Index *jCol, Number *values,
                            UserDataPtr ud) {
  ea__screen_t *s = ud;
  (void)m;
  if (values) {
    memset(s->lfull, 0, sizeof(double) * (size_t)s->p.m);
    for (int k = 0; k < s->ms; ++k)
      s->lfull[s->rsub[k]] = lambda[k];
  }
  return s->p.h(n, x, new_x, of, s->p.m, values ? s->lfull : NULL, new_lambda, nele, iRow, jCol,
                values, s->p.ud);
}

static Bool ea__screen_cb_iter(Index alg_mod, Index iter, Number obj, Number inf_pr, Number inf_du,
                               Number mu, Number d_norm, Number reg, Number alpha_du,
                               Number alpha_pr, Index ls, UserDataPtr ud) {
  const ea__screen_t *s = ud;
  return s->p.iter(alg_mod, iter, obj, inf_pr, inf_du, mu, d_norm, reg, alpha_du, alpha_pr, ls,
                   s->p.ud);
}

ea__ipopt_problem_t ea__screen_problem(ea__screen_t *s, const double *xl, const double *xu) {
  const ea__screen_nlp_t *p = &s->p;
  IpoptProblem ip = CreateIpoptProblem(p->n, (double *)xl, (double *)xu, s->ms, s->gls, s->gus,
                                       s->nnz_s, p->nnz_h, 0, ea__screen_cb_f, ea__screen_cb_g,
                                       ea__screen_cb_grad_f, ea__screen_cb_jac, ea__screen_cb_h);
  if (ip && p->iter) SetIntermediateCallback(ip, ea__screen_cb_iter);
  return ip;
}

int ea__screen_solve(ea__screen_t *s, ea__ipopt_problem_t ip, double *x, double *g, double *obj,
                     double *mult_g, double *mult_xl, double *mult_xu) {
  for (int k = 0; k < s->ms; ++k)
    s->msub[k] = mult_g[s->rsub[k]];
  const enum ApplicationReturnStatus rs =
      IpoptSolve(ip, x, s->gsub, obj, s->msub, mult_xl, mult_xu, s);
  memset(mult_g, 0, sizeof(double) * (size_t)s->p.m);
  for (int k = 0; k < s->ms; ++k)
    mult_g[s->rsub[k]] = s->msub[k];
  /* every row at the returned point */
  if (!s->p.g(s->p.n, x, TRUE, s->p.m, g, s->p.ud))
    for (int i = 0; i < s->p.m; ++i)
      g[i] = NAN;
  return rs;
}
