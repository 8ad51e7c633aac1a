/* Active-set Newton on an NLP given by Ipopt's callbacks (docs/planner.md, "Replanning"): from
 * a nearby solution's active set (its multipliers against its gaps), Newton on the KKT system
 * of that set (the stationarity of the free variables, the active rows at their bounds), the
 * set corrected by the signs of the multipliers and the rows' values (a primal-dual active-set
 * step), until it stops changing. The KKT matrix [H J_A'; J_A -dreg I] (the rows regularised:
 * a minimum-time plan's active rows are linearly dependent) is sparse, symmetric and
 * indefinite; it is factored by KLU (SuiteSparse: BTF + AMD ordering, LU with a pivot
 * threshold of 1e-8, i.e. the ordering's diagonal pivots) in a fraction of a millisecond, where
 * an Ipopt iteration through MUMPS costs 2-3 ms.
 *
 * It returns a candidate: the caller verifies the KKT conditions of the whole problem (every
 * row, bound and sign) before it takes it, and otherwise solves with Ipopt. Calls nothing
 * above it. */
#include "plan_asn_impl.h"

#include <klu.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Newton iterations per active set, active-set changes. */
/* The active rows' diagonal in the KKT matrix (their fixed points are KKT points all the same:
 * it only steers the steps). On the paper line 1e-10 .. 1e-6 multiplied the stationarity
 * residual of the first step from a replan's prediction by 10^2 .. 10^5 (the redundant rows of
 * a bang-bang plan's active set are inconsistent to first order away from the solution); with
 * 1e-4 it converges in 3 steps to the rows' rounding floor (1.1e-10). */
#define EA__ASN_DREG 1e-4
#define EA__ASN_NEWTON 6
#define EA__ASN_SWAPS 2

void ea__asn_free(ea__asn_t *a) {
  if (!a) return;
  if (a->sym) klu_free_symbolic(&a->sym, &a->c);
  free(a->act_x), free(a->act_g), free(a->kx), free(a->kg), free(a->Ap), free(a->Ai);
  free(a->cnt), free(a->Ax), free(a->pd), free(a->pj[0]), free(a->pj[1]), free(a->ph[0]),
      free(a->ph[1]);
  free(a->gf), free(a->g), free(a->jv), free(a->hv), free(a->lam), free(a->rhs), free(a->r);
  free(a);
}

ea__asn_t *ea__asn_alloc(const ea__asn_nlp_t *p) {
  ea__asn_t *a = calloc(1, sizeof *a);
  if (!a) return NULL;
  a->p = *p;
  const size_t n = (size_t)p->n, m = (size_t)p->m, nk = n + m + 1;
  const size_t nz = 2 * ((size_t)p->nnz_j + (size_t)p->nnz_h) + nk;
  a->act_x = malloc(sizeof(int) * n), a->act_g = malloc(sizeof(int) * (m + 1));
  a->kx = malloc(sizeof(int) * n), a->kg = malloc(sizeof(int) * (m + 1));
  a->Ap = malloc(sizeof(int) * (nk + 1)), a->cnt = malloc(sizeof(int) * (nk + 1));
  a->pd = malloc(sizeof(int) * nk);
  a->Ai = malloc(sizeof(int) * nz), a->Ax = malloc(sizeof(double) * nz);
  for (int s = 0; s < 2; ++s) {
    a->pj[s] = malloc(sizeof(int) * ((size_t)p->nnz_j + 1));
    a->ph[s] = malloc(sizeof(int) * ((size_t)p->nnz_h + 1));
  }
  a->gf = malloc(sizeof(double) * n), a->g = malloc(sizeof(double) * (m + 1));
  a->jv = malloc(sizeof(double) * ((size_t)p->nnz_j + 1));
  a->hv = malloc(sizeof(double) * ((size_t)p->nnz_h + 1));
  a->lam = malloc(sizeof(double) * (m + 1)), a->rhs = malloc(sizeof(double) * nk);
  a->r = malloc(sizeof(double) * n);
  if (!a->act_x || !a->act_g || !a->kx || !a->kg || !a->Ap || !a->cnt || !a->pd || !a->Ai ||
      !a->Ax || !a->pj[0] || !a->pj[1] || !a->ph[0] || !a->ph[1] || !a->gf || !a->g || !a->jv ||
      !a->hv || !a->lam || !a->rhs || !a->r || !klu_defaults(&a->c)) {
    ea__asn_free(a);
    return NULL;
  }
  /* diagonal pivots unless one is below 1e-8 of its column: the regularised KKT matrix is
   * quasi-definite where the Hessian is positive, and KLU's default threshold (1e-3) took
   * 334 off-diagonal pivots on the paper line's, L + U 221k entries and 35 Mflop per factor
   * instead of 11k and 0.08 Mflop (the Newton iterates and the caller's KKT test catch what
   * a small pivot would spoil) */
  a->c.tol = 1e-8;
  return a;
}

/* Entry (i, j) of the KKT pattern being counted (pos NULL) or placed (pos: where it went). */
static void ea__asn_entry(ea__asn_t *a, int i, int j, int *pos) {
  if (!pos) {
    a->cnt[j]++;
    return;
  }
  const int q = a->cnt[j]++;
  a->Ai[q] = i;
  *pos = q;
}

int ea__asn_pattern(ea__asn_t *a) {
  const ea__asn_nlp_t *p = &a->p;
  int nk = 0;
  for (int i = 0; i < p->n; ++i)
    a->kx[i] = a->act_x[i] ? -1 : nk++;
  for (int i = 0; i < p->m; ++i)
    a->kg[i] = a->act_g[i] ? nk++ : -1;
  a->nk = nk;
  if (nk == 0) return -1;
  for (int pass = 0; pass < 2; ++pass) {
    memset(a->cnt, 0, sizeof(int) * (size_t)(nk + 1));
    if (pass == 1) memcpy(a->cnt, a->Ap, sizeof(int) * (size_t)nk);
    for (int k = 0; k < nk; ++k) /* every diagonal: the rows' regularisation, the Hessian's own */
      ea__asn_entry(a, k, k, pass ? &a->pd[k] : NULL);
    for (int e = 0; e < p->nnz_h; ++e) {
      const int i = a->kx[p->hrow[e]], j = a->kx[p->hcol[e]];
      a->ph[0][e] = a->ph[1][e] = -1;
      if (i < 0 || j < 0) continue;
      if (i == j) {
        a->ph[0][e] = pass ? a->pd[i] : -1;
        continue;
      }
      ea__asn_entry(a, i, j, pass ? &a->ph[0][e] : NULL);
      ea__asn_entry(a, j, i, pass ? &a->ph[1][e] : NULL);
    }
    for (int e = 0; e < p->nnz_j; ++e) {
      const int r = a->kg[p->jrow[e]], c = a->kx[p->jcol[e]];
      a->pj[0][e] = a->pj[1][e] = -1;
      if (r < 0 || c < 0) continue;
      ea__asn_entry(a, r, c, pass ? &a->pj[0][e] : NULL);
      ea__asn_entry(a, c, r, pass ? &a->pj[1][e] : NULL);
    }
    if (pass == 0) { /* column pointers */
      int s = 0;
      for (int j = 0; j < nk; ++j) {
        const int cj = a->cnt[j];
        a->Ap[j] = s;
        s += cj;
      }
      a->Ap[nk] = s;
      a->nnz_k = s;
    }
  }
  if (a->sym) klu_free_symbolic(&a->sym, &a->c);
  a->sym = klu_analyze(nk, a->Ap, a->Ai, &a->c);
  return a->sym ? 0 : -1;
}

void ea__asn_fill(ea__asn_t *a) {
  const ea__asn_nlp_t *p = &a->p;
  memset(a->Ax, 0, sizeof(double) * (size_t)a->nnz_k);
  for (int e = 0; e < p->nnz_h; ++e) {
    if (a->ph[0][e] >= 0) a->Ax[a->ph[0][e]] += a->hv[e];
    if (a->ph[1][e] >= 0) a->Ax[a->ph[1][e]] += a->hv[e];
  }
  for (int e = 0; e < p->nnz_j; ++e) {
    if (a->pj[0][e] >= 0) a->Ax[a->pj[0][e]] += a->jv[e];
    if (a->pj[1][e] >= 0) a->Ax[a->pj[1][e]] += a->jv[e];
  }
}

int ea__asn_eval(ea__asn_t *a, double *x, int hess) {
  const ea__asn_nlp_t *p = &a->p;
  void *ud = p->ud;
  /* the Hessian first: the modal defects' closed form leaves their values and gradients at x
   * for the rows (dyn_rows.c) */
  if (!p->grad_f(p->n, x, TRUE, a->gf, ud) ||
      (hess && !p->h(p->n, x, FALSE, 1.0, p->m, a->lam, TRUE, p->nnz_h, NULL, NULL, a->hv, ud)) ||
      !p->g(p->n, x, FALSE, p->m, a->g, ud) ||
      !p->jac(p->n, x, FALSE, p->m, p->nnz_j, NULL, NULL, a->jv, ud))
    return -1;
  /* stationarity of every variable: grad f + J' lam */
  memcpy(a->r, a->gf, sizeof(double) * (size_t)p->n);
  for (int e = 0; e < p->nnz_j; ++e)
    a->r[p->jcol[e]] += a->jv[e] * a->lam[p->jrow[e]];
  for (int i = 0; i < p->n + p->m; ++i)
    if (!isfinite(i < p->n ? a->r[i] : a->g[i - p->n])) return -1;
  return 0;
}

/* Target of active row i: its bound on the active side, margin (relative) inside it. */
static double ea__asn_target(const ea__asn_t *a, int i) {
  const int s = a->act_g[i];
  const double b = s < 0 ? a->p.gl[i] : a->p.gu[i];
  return s == 2 ? b : b - s * a->tol.margin * fmax(1.0, fabs(b));
}

/* Newton on the current active set from x (the active bounds already on x) with lam; 0 when
 * the residuals fell below the tolerances, 1 when it is stationary with the active rows off
 * their bounds (no point holds them all: the regularised system's least-squares fixed
 * point), -1 when it failed. */
static int ea__asn_newton_steps(ea__asn_t *a, double *x, int *iters, klu_numeric **num,
                                double *rcond0) {
  const ea__asn_nlp_t *p = &a->p;
  const ea__asn_tol_t *tl = &a->tol;
  double first = INFINITY, rp_prev = INFINITY;
  for (int it = 0;; ++it) {
    if (ea__asn_eval(a, x, !p->hess_last)) return -1;
    double rp = 0.0, rd = 0.0;
    for (int i = 0; i < p->n; ++i)
      if (a->kx[i] >= 0) rd = fmax(rd, fabs(a->r[i]));
    for (int i = 0; i < p->m; ++i)
      if (a->kg[i] >= 0) rp = fmax(rp, fabs(a->g[i] - ea__asn_target(a, i)));
    if (rp <= tl->ptol && rd <= tl->dtol) return 0;
    /* stationary, but the rows stay off their bounds: the set is inconsistent */
    if (rd <= tl->dtol && rp > 0.5 * rp_prev) return 1;
    rp_prev = rp;
    const double res = rp / tl->ptol + rd / tl->dtol;
    if (it == 0) first = res;
    if (it == EA__ASN_NEWTON || !(res < 1e3 * first)) return -1;
    /* a converged point needs no Hessian: after the test when the rows allow (the replan of
     * the paper line's goal moved 5 mm: one of its four, 2 M instructions of 39 M) */
    if (p->hess_last &&
        !p->h(p->n, x, FALSE, 1.0, p->m, a->lam, TRUE, p->nnz_h, NULL, NULL, a->hv, p->ud))
      return -1;
    /* K [dx; dlam] = -[r_free; g_A - b_A] */
    ea__asn_fill(a);
    for (int i = 0; i < p->m; ++i)
      if (a->kg[i] >= 0) a->Ax[a->pd[a->kg[i]]] = -EA__ASN_DREG;
    for (int i = 0; i < p->n; ++i)
      if (a->kx[i] >= 0) a->rhs[a->kx[i]] = -a->r[i];
    for (int i = 0; i < p->m; ++i)
      if (a->kg[i] >= 0) a->rhs[a->kg[i]] = -(a->g[i] - ea__asn_target(a, i));
    /* the first step's pivot order kept for the next steps (klu_refactor), unless it lost
     * more than a factor 1e3 in the pivots' ratio min |u_kk| / max |u_kk| */
    if (*num && (!klu_refactor(a->Ap, a->Ai, a->Ax, a->sym, *num, &a->c) || a->c.status != KLU_OK ||
                 !klu_rcond(a->sym, *num, &a->c) || !(a->c.rcond >= 1e-3 * *rcond0)))
      klu_free_numeric(num, &a->c);
    if (!*num) {
      *num = klu_factor(a->Ap, a->Ai, a->Ax, a->sym, &a->c);
      if (!*num) return -1;
      *rcond0 = a->c.status == KLU_OK && klu_rcond(a->sym, *num, &a->c) ? a->c.rcond : 0.0;
    }
    if (a->c.status != KLU_OK || !klu_solve(a->sym, *num, a->nk, 1, a->rhs, &a->c)) return -1;
    for (int i = 0; i < p->n; ++i)
      if (a->kx[i] >= 0) x[i] += a->rhs[a->kx[i]];
    for (int i = 0; i < p->m; ++i)
      if (a->kg[i] >= 0) a->lam[i] += a->rhs[a->kg[i]];
    ++*iters;
  }
}

static int ea__asn_newton(ea__asn_t *a, double *x, int *iters) {
  klu_numeric *num = NULL;
  double rcond0 = 0.0;
  const int rc = ea__asn_newton_steps(a, x, iters, &num, &rcond0);
  if (num) klu_free_numeric(&num, &a->c);
  return rc;
}

int ea__asn_solve(ea__asn_t *a, const ea__asn_tol_t *tol, const double *x_ref, const double *g_ref,
                  double *x, double *mult_g, double *mult_xl, double *mult_xu, int *iters) {
  const ea__asn_nlp_t *p = &a->p;
  a->tol = *tol;
  a->ipm_ready = 0; /* its own pattern follows */
  *iters = 0;
  /* the active set of the nearby solution: a multiplier larger than its gap */
  for (int i = 0; i < p->n; ++i) {
    a->act_x[i] = 0;
    if (p->xl[i] == p->xu[i])
      a->act_x[i] = 2;
    else if (mult_xl[i] > x_ref[i] - p->xl[i])
      a->act_x[i] = -1;
    else if (mult_xu[i] > p->xu[i] - x_ref[i])
      a->act_x[i] = 1;
  }
  for (int i = 0; i < p->m; ++i) {
    a->act_g[i] = 0;
    if (p->gl[i] == p->gu[i])
      a->act_g[i] = 2;
    else if (mult_g[i] < 0.0 && -mult_g[i] > g_ref[i] - p->gl[i])
      a->act_g[i] = -1;
    else if (mult_g[i] > 0.0 && mult_g[i] > p->gu[i] - g_ref[i])
      a->act_g[i] = 1;
    a->lam[i] = a->act_g[i] ? mult_g[i] : 0.0;
  }
  for (int swap = 0;; ++swap) {
    for (int i = 0; i < p->n; ++i)
      if (a->act_x[i] == 2)
        x[i] = p->xu[i];
      else if (a->act_x[i]) {
        const double b = a->act_x[i] > 0 ? p->xu[i] : p->xl[i];
        x[i] = b - a->act_x[i] * tol->margin * fmax(1.0, fabs(b));
      }
    if (ea__asn_pattern(a)) return -1;
    const int nw = ea__asn_newton(a, x, iters);
    if (nw < 0) return -1;
    /* signs and the rows and bounds outside the set (a->r, a->g are at x); a multiplier of
     * the wrong sign but below 1e-3 dtol stays (degenerate: at its bound with nothing to
     * hold), reported as 0 */
    const double tiny = 1e-3 * tol->dtol;
    int changed = 0;
    for (int i = 0; i < p->m; ++i) {
      const int s = a->act_g[i];
      if ((s == -1 && a->lam[i] > tiny) || (s == 1 && a->lam[i] < -tiny) ||
          (nw == 1 && s == -1 && a->g[i] > p->gl[i] + tol->ptol) ||
          (nw == 1 && s == 1 && a->g[i] < p->gu[i] - tol->ptol)) {
        a->act_g[i] = 0, a->lam[i] = 0.0, changed = 1; /* leaves the set */
      } else if (s == 0 && a->g[i] < p->gl[i] - tol->ptol) {
        a->act_g[i] = -1, changed = 1;
      } else if (s == 0 && a->g[i] > p->gu[i] + tol->ptol) {
        a->act_g[i] = 1, changed = 1;
      }
    }
    for (int i = 0; i < p->n; ++i) {
      const int s = a->act_x[i];
      if ((s == -1 && a->r[i] < -tiny) || (s == 1 && a->r[i] > tiny)) {
        a->act_x[i] = 0, changed = 1;
      } else if (s == 0 && x[i] < p->xl[i]) {
        a->act_x[i] = -1, changed = 1;
      } else if (s == 0 && x[i] > p->xu[i]) {
        a->act_x[i] = 1, changed = 1;
      }
    }
    if (!changed) {
      if (nw) return -1;
      break;
    }
    if (swap == EA__ASN_SWAPS) return -1;
  }
  /* Ipopt's multipliers: the rows' lam, the bounds' from the stationarity of their variables */
  for (int i = 0; i < p->m; ++i)
    mult_g[i] = a->act_g[i] == -1  ? fmin(a->lam[i], 0.0)
                : a->act_g[i] == 1 ? fmax(a->lam[i], 0.0)
                                   : a->lam[i];
  for (int i = 0; i < p->n; ++i) {
    mult_xl[i] = a->act_x[i] == -1 ? fmax(a->r[i], 0.0) : 0.0;
    mult_xu[i] = a->act_x[i] == 1 ? fmax(-a->r[i], 0.0) : 0.0;
  }
  return 0;
}
