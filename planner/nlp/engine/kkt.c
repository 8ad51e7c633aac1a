/* The KKT system of an NLP (engine/kkt_impl.h): its values, its pattern over the variables
 * and rows in the system, the ordering (KLU's analysis, BTF + AMD, for the LU; AMD's for the
 * symmetric LDL') and the factorizations. Calls nothing above it. */
#include "kkt_impl.h"

#include <amd.h>
#include <klu.h>
#include <ldl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static void ea__kkt_ldl_free(ea__kkt_t *k) {
  int **g[] = {&k->P, &k->Pinv, &k->Lp, &k->Parent, &k->Lnz, &k->Flag, &k->Pattern, &k->Li};
  for (size_t i = 0; i < sizeof g / sizeof *g; ++i)
    free(*g[i]), *g[i] = NULL;
  double **f[] = {&k->Lx, &k->D, &k->Y};
  for (size_t i = 0; i < sizeof f / sizeof *f; ++i)
    free(*f[i]), *f[i] = NULL;
}

void ea__kkt_free(ea__kkt_t *k) {
  if (!k) return;
  ea__kkt_lu_release(k);
  if (k->sym) klu_free_symbolic(&k->sym, &k->c);
  ea__kkt_ldl_free(k);
  free(k->kx), free(k->kg), free(k->Ap), free(k->Ai), free(k->cnt), free(k->Ax), free(k->pd);
  free(k->perm);
  free(k->pj[0]), free(k->pj[1]), free(k->ph[0]), free(k->ph[1]);
  free(k->gf), free(k->g), free(k->jv), free(k->hv), free(k->lam), free(k->rhs), free(k->r);
  free(k);
}

ea__kkt_t *ea__kkt_alloc(const ea__nlp_t *p) {
  ea__kkt_t *k = calloc(1, sizeof *k);
  if (!k) return NULL;
  k->p = *p;
  const size_t n = (size_t)p->n, m = (size_t)p->m, nk = n + m + 1;
  const size_t nz = 2 * ((size_t)p->nnz_j + (size_t)p->nnz_h) + nk;
  k->kx = malloc(sizeof(int) * n), k->kg = malloc(sizeof(int) * (m + 1));
  k->Ap = malloc(sizeof(int) * (nk + 1)), k->cnt = malloc(sizeof(int) * (nk + 1));
  k->pd = malloc(sizeof(int) * nk), k->perm = malloc(sizeof(int) * nk);
  k->Ai = malloc(sizeof(int) * nz), k->Ax = malloc(sizeof(double) * nz);
  for (int s = 0; s < 2; ++s) {
    k->pj[s] = malloc(sizeof(int) * ((size_t)p->nnz_j + 1));
    k->ph[s] = malloc(sizeof(int) * ((size_t)p->nnz_h + 1));
  }
  k->gf = malloc(sizeof(double) * n), k->g = malloc(sizeof(double) * (m + 1));
  k->jv = malloc(sizeof(double) * ((size_t)p->nnz_j + 1));
  k->hv = malloc(sizeof(double) * ((size_t)p->nnz_h + 1));
  k->lam = malloc(sizeof(double) * (m + 1)), k->rhs = malloc(sizeof(double) * nk);
  k->r = malloc(sizeof(double) * n);
  if (!k->kx || !k->kg || !k->Ap || !k->cnt || !k->pd || !k->perm || !k->Ai || !k->Ax ||
      !k->pj[0] || !k->pj[1] || !k->ph[0] || !k->ph[1] || !k->gf || !k->g || !k->jv || !k->hv ||
      !k->lam || !k->rhs || !k->r || !klu_defaults(&k->c)) {
    ea__kkt_free(k);
    return NULL;
  }
  /* diagonal pivots unless one is below 1e-8 of its column: the regularised KKT matrix is
   * quasi-definite where the Hessian is positive, and KLU's default threshold (1e-3) pivots
   * off the diagonal with a much larger fill (the Newton iterates and the caller's KKT test
   * catch what a small pivot would spoil) */
  k->c.tol = 1e-8;
  return k;
}

int ea__kkt_eval(ea__kkt_t *k, double *x, int hess) {
  const ea__nlp_t *p = &k->p;
  void *ud = p->ud;
  /* the Hessian first: the modal defects' closed form leaves their values and gradients at x
   * for the rows (dyn_rows.c) */
  if (!p->grad_f(p->n, x, 1, k->gf, ud) ||
      (hess && !p->h(p->n, x, 0, 1.0, p->m, k->lam, 1, p->nnz_h, NULL, NULL, k->hv, ud)) ||
      !p->g(p->n, x, 0, p->m, k->g, ud) ||
      !p->jac(p->n, x, 0, p->m, p->nnz_j, NULL, NULL, k->jv, ud))
    return -1;
  /* stationarity of every variable: grad f + J' lam */
  memcpy(k->r, k->gf, sizeof(double) * (size_t)p->n);
  for (int e = 0; e < p->nnz_j; ++e)
    k->r[p->jcol[e]] += k->jv[e] * k->lam[p->jrow[e]];
  for (int i = 0; i < p->n + p->m; ++i)
    if (!isfinite(i < p->n ? k->r[i] : k->g[i - p->n])) return -1;
  return 0;
}

/* Entry (i, j) of the pattern being counted (pos NULL) or placed (pos: where it went). */
static void ea__kkt_entry(ea__kkt_t *k, int i, int j, int *pos) {
  if (!pos) {
    k->cnt[j]++;
    return;
  }
  const int q = k->cnt[j]++;
  k->Ai[q] = i;
  *pos = q;
}

/* The pattern's entries counted (pass 0: the column pointers) or placed (pass 1). */
static void ea__kkt_place(ea__kkt_t *k, int pass) {
  const ea__nlp_t *p = &k->p;
  const int nk = k->nk;
  memset(k->cnt, 0, sizeof(int) * (size_t)(nk + 1));
  if (pass == 1) memcpy(k->cnt, k->Ap, sizeof(int) * (size_t)nk);
  for (int d = 0; d < nk; ++d) /* every diagonal: the rows' regularisation, the Hessian's own */
    ea__kkt_entry(k, d, d, pass ? &k->pd[d] : NULL);
  for (int e = 0; e < p->nnz_h; ++e) {
    const int i = k->kx[p->hrow[e]], j = k->kx[p->hcol[e]];
    k->ph[0][e] = k->ph[1][e] = -1;
    if (i < 0 || j < 0) continue;
    if (i == j) {
      k->ph[0][e] = pass ? k->pd[i] : -1;
      continue;
    }
    ea__kkt_entry(k, i, j, pass ? &k->ph[0][e] : NULL);
    ea__kkt_entry(k, j, i, pass ? &k->ph[1][e] : NULL);
  }
  for (int e = 0; e < p->nnz_j; ++e) {
    const int r = k->kg[p->jrow[e]], c = k->kx[p->jcol[e]];
    k->pj[0][e] = k->pj[1][e] = -1;
    if (r < 0 || c < 0) continue;
    ea__kkt_entry(k, r, c, pass ? &k->pj[0][e] : NULL);
    ea__kkt_entry(k, c, r, pass ? &k->pj[1][e] : NULL);
  }
  if (pass == 0) { /* column pointers */
    int s = 0;
    for (int j = 0; j < nk; ++j) {
      const int cj = k->cnt[j];
      k->Ap[j] = s;
      s += cj;
    }
    k->Ap[nk] = s;
    k->nnz_k = s;
  }
}

int ea__kkt_pattern(ea__kkt_t *k, const int *act_x, const int *act_g, int lu) {
  const ea__nlp_t *p = &k->p;
  k->full = 0;
  ea__kkt_lu_release(k);
  int nk = 0, nx = 0;
  for (int i = 0; i < p->n; ++i)
    k->kx[i] = (act_x ? act_x[i] : p->xl[i] == p->xu[i]) ? -1 : nk++;
  nx = nk;
  for (int i = 0; i < p->m; ++i)
    k->kg[i] = !act_g || act_g[i] ? nk++ : -1;
  k->nk = nk, k->nx = nx;
  if (nk == 0) return -1;
  ea__kkt_place(k, 0);
  ea__kkt_place(k, 1);
  if (k->sym) klu_free_symbolic(&k->sym, &k->c);
  if (!lu) /* AMD's order of the symmetric pattern (the one KLU's analysis without BTF takes) */
    return amd_order(nk, k->Ap, k->Ai, k->perm, NULL, NULL) >= AMD_OK ? 0 : -1;
  k->sym = klu_analyze(nk, k->Ap, k->Ai, &k->c);
  return k->sym ? 0 : -1;
}

void ea__kkt_fill(ea__kkt_t *k) {
  const ea__nlp_t *p = &k->p;
  memset(k->Ax, 0, sizeof(double) * (size_t)k->nnz_k);
  for (int e = 0; e < p->nnz_h; ++e) {
    if (k->ph[0][e] >= 0) k->Ax[k->ph[0][e]] += k->hv[e];
    if (k->ph[1][e] >= 0) k->Ax[k->ph[1][e]] += k->hv[e];
  }
  for (int e = 0; e < p->nnz_j; ++e) {
    if (k->pj[0][e] >= 0) k->Ax[k->pj[0][e]] += k->jv[e];
    if (k->pj[1][e] >= 0) k->Ax[k->pj[1][e]] += k->jv[e];
  }
}

void ea__kkt_lu_release(ea__kkt_t *k) {
  if (k->num) klu_free_numeric(&k->num, &k->c);
}

int ea__kkt_lu_solve(ea__kkt_t *k) {
  if (k->num &&
      (!klu_refactor(k->Ap, k->Ai, k->Ax, k->sym, k->num, &k->c) || k->c.status != KLU_OK ||
       !klu_rcond(k->sym, k->num, &k->c) || !(k->c.rcond >= 1e-3 * k->rcond0)))
    klu_free_numeric(&k->num, &k->c);
  if (!k->num) {
    k->num = klu_factor(k->Ap, k->Ai, k->Ax, k->sym, &k->c);
    if (!k->num) return -1;
    k->rcond0 = k->c.status == KLU_OK && klu_rcond(k->sym, k->num, &k->c) ? k->c.rcond : 0.0;
  }
  if (k->c.status != KLU_OK || !klu_solve(k->sym, k->num, k->nk, 1, k->rhs, &k->c)) return -1;
  return 0;
}

int ea__kkt_ldl_symbolic(ea__kkt_t *k) {
  ea__kkt_ldl_free(k);
  const size_t nk = (size_t)k->nk + 1;
  k->P = malloc(nk * sizeof(int)), k->Pinv = malloc(nk * sizeof(int));
  k->Lp = malloc((nk + 1) * sizeof(int)), k->Parent = malloc(nk * sizeof(int));
  k->Lnz = malloc(nk * sizeof(int)), k->Flag = malloc(nk * sizeof(int));
  k->Pattern = malloc(nk * sizeof(int));
  k->D = malloc(nk * sizeof(double)), k->Y = malloc(nk * sizeof(double));
  if (!k->P || !k->Pinv || !k->Lp || !k->Parent || !k->Lnz || !k->Flag || !k->Pattern || !k->D ||
      !k->Y)
    return -1;
  memcpy(k->P, k->perm, sizeof(int) * (size_t)k->nk);
  ldl_symbolic(k->nk, k->Ap, k->Ai, k->Lp, k->Parent, k->Lnz, k->Flag, k->P, k->Pinv);
  const size_t lnz = (size_t)k->Lp[k->nk] + 1;
  k->Li = malloc(lnz * sizeof(int)), k->Lx = malloc(lnz * sizeof(double));
  return k->Li && k->Lx ? 0 : -1;
}

int ea__kkt_ldl_factor(ea__kkt_t *k, int *neg) {
  const int d = ldl_numeric(k->nk, k->Ap, k->Ai, k->Ax, k->Lp, k->Parent, k->Lnz, k->Li, k->Lx,
                            k->D, k->Y, k->Pattern, k->Flag, k->P, k->Pinv);
  *neg = 0;
  if (d == k->nk)
    for (int i = 0; i < k->nk; ++i)
      *neg += k->D[i] < 0.0;
  return d;
}

/* sum_q v[q] u[i[q]] over q0 <= q < q1, in two partial sums (one sum's chain of dependent
 * additions is latency-bound: LDL's ldl_ltsolve, which also stores the sum at every entry) */
static double ea__kkt_dot(const double *v, const int *i, const double *u, int q0, int q1) {
  double s0 = 0.0, s1 = 0.0;
  int q = q0;
  for (; q + 1 < q1; q += 2)
    s0 += v[q] * u[i[q]], s1 += v[q + 1] * u[i[q + 1]];
  if (q < q1) s0 += v[q] * u[i[q]];
  return s0 + s1;
}

void ea__kkt_ldl_solve(ea__kkt_t *k, double *x) {
  const int nk = k->nk;
  double *Y = k->Y;
  ldl_perm(nk, Y, x, k->P);
  ldl_lsolve(nk, Y, k->Lp, k->Li, k->Lx);
  ldl_dsolve(nk, Y, k->D);
  for (int j = nk - 1; j >= 0; --j) /* L' x = y by the rows of L' */
    Y[j] -= ea__kkt_dot(k->Lx, k->Li, Y, k->Lp[j], k->Lp[j + 1]);
  ldl_permt(nk, x, Y, k->P);
}

void ea__kkt_residual(const ea__kkt_t *k, const double *b, const double *d, double *res) {
  /* row i of the symmetric K is its column i (the pattern holds both triangles, with the
   * same values) */
  for (int i = 0; i < k->nk; ++i)
    res[i] = b[i] - ea__kkt_dot(k->Ax, k->Ai, d, k->Ap[i], k->Ap[i + 1]);
}
