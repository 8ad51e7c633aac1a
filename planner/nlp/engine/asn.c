/* Active-set Newton on an NLP given by Ipopt's callbacks (docs/planner.md, "Replanning"): from
 * a nearby solution's active set (its multipliers against its gaps), Newton on the KKT system
 * of that set (the stationarity of the free variables, the active rows at their bounds), the
 * set corrected by the signs of the multipliers and the rows' values (a primal-dual active-set
 * step), until it stops changing. The KKT matrix [H J_A'; J_A -dreg I] (the rows regularised:
 * a minimum-time plan's active rows are linearly dependent) is sparse, symmetric and
 * indefinite; it is factored by KLU (engine/kkt.c: BTF + AMD ordering, LU with a pivot
 * threshold of 1e-8, i.e. the ordering's diagonal pivots), much cheaper than an Ipopt
 * iteration through MUMPS on these small banded systems.
 *
 * It returns a candidate: the caller verifies the KKT conditions of the whole problem (every
 * row, bound and sign) before it takes it, and otherwise solves with Ipopt. Calls nothing
 * above it. */
#include "plan_asn_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The active rows' diagonal in the KKT matrix (their fixed points are KKT points all the same:
 * it only steers the steps). The redundant rows of a bang-bang plan's active set are
 * inconsistent to first order away from the solution; a smaller diagonal lets the first
 * steps from a replan's prediction blow up the stationarity residual (docs/planner.md, "The
 * active-set Newton"). */
#define EA__ASN_DREG 1e-4
#define EA__ASN_NEWTON 6 /* Newton iterations per active set */
#define EA__ASN_SWAPS 2  /* active-set changes */

void ea__asn_free(ea__asn_t *a) {
  if (!a) return;
  free(a->act_x), free(a->act_g);
  free(a);
}

ea__asn_t *ea__asn_alloc(ea__kkt_t *k) {
  ea__asn_t *a = calloc(1, sizeof *a);
  if (!a) return NULL;
  a->k = k;
  a->act_x = malloc(sizeof(int) * ((size_t)k->p.n + 1));
  a->act_g = malloc(sizeof(int) * ((size_t)k->p.m + 1));
  if (!a->act_x || !a->act_g) {
    ea__asn_free(a);
    return NULL;
  }
  return a;
}

/* Target of active row i: its bound on the active side, margin (relative) inside it. */
static double ea__asn_target(const ea__asn_t *a, int i) {
  const int s = a->act_g[i];
  const double b = s < 0 ? a->k->p.gl[i] : a->k->p.gu[i];
  return s == 2 ? b : b - s * a->tol.margin * fmax(1.0, fabs(b));
}

/* Newton on the current active set from x (the active bounds already on x) with k->lam; 0
 * when the residuals fell below the tolerances, 1 when it is stationary with the active rows
 * off their bounds (no point holds them all: the regularised system's least-squares fixed
 * point), -1 when it failed. */
static int ea__asn_newton_steps(ea__asn_t *a, double *x, int *iters) {
  ea__kkt_t *k = a->k;
  const ea__nlp_t *p = &k->p;
  const ea__asn_tol_t *tl = &a->tol;
  double first = INFINITY, rp_prev = INFINITY;
  for (int it = 0;; ++it) {
    if (ea__kkt_eval(k, x, !p->hess_last)) return -1;
    double rp = 0.0, rd = 0.0;
    for (int i = 0; i < p->n; ++i)
      if (k->kx[i] >= 0) rd = fmax(rd, fabs(k->r[i]));
    for (int i = 0; i < p->m; ++i)
      if (k->kg[i] >= 0) rp = fmax(rp, fabs(k->g[i] - ea__asn_target(a, i)));
    if (rp <= tl->ptol && rd <= tl->dtol) return 0;
    /* stationary, but the rows stay off their bounds: the set is inconsistent */
    if (rd <= tl->dtol && rp > 0.5 * rp_prev) return 1;
    rp_prev = rp;
    const double res = rp / tl->ptol + rd / tl->dtol;
    if (it == 0) first = res;
    if (it == EA__ASN_NEWTON || !(res < 1e3 * first)) return -1;
    /* a converged point needs no Hessian: after the test when the rows allow */
    if (p->hess_last && !p->h(p->n, x, 0, 1.0, p->m, k->lam, 1, p->nnz_h, NULL, NULL, k->hv, p->ud))
      return -1;
    /* K [dx; dlam] = -[r_free; g_A - b_A] */
    ea__kkt_fill(k);
    for (int i = 0; i < p->m; ++i)
      if (k->kg[i] >= 0) k->Ax[k->pd[k->kg[i]]] = -EA__ASN_DREG;
    for (int i = 0; i < p->n; ++i)
      if (k->kx[i] >= 0) k->rhs[k->kx[i]] = -k->r[i];
    for (int i = 0; i < p->m; ++i)
      if (k->kg[i] >= 0) k->rhs[k->kg[i]] = -(k->g[i] - ea__asn_target(a, i));
    /* the first step's pivot order kept for the next steps (ea__kkt_lu_solve) */
    if (ea__kkt_lu_solve(k)) return -1;
    for (int i = 0; i < p->n; ++i)
      if (k->kx[i] >= 0) x[i] += k->rhs[k->kx[i]];
    for (int i = 0; i < p->m; ++i)
      if (k->kg[i] >= 0) k->lam[i] += k->rhs[k->kg[i]];
    ++*iters;
  }
}

static int ea__asn_newton(ea__asn_t *a, double *x, int *iters) {
  const int rc = ea__asn_newton_steps(a, x, iters);
  ea__kkt_lu_release(a->k);
  return rc;
}

int ea__asn_solve(ea__asn_t *a, const ea__asn_tol_t *tol, const double *x_ref, const double *g_ref,
                  double *x, double *mult_g, double *mult_xl, double *mult_xu, int *iters) {
  ea__kkt_t *k = a->k;
  const ea__nlp_t *p = &k->p;
  a->tol = *tol;
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
    k->lam[i] = a->act_g[i] ? mult_g[i] : 0.0;
  }
  for (int swap = 0;; ++swap) {
    for (int i = 0; i < p->n; ++i)
      if (a->act_x[i] == 2)
        x[i] = p->xu[i];
      else if (a->act_x[i]) {
        const double b = a->act_x[i] > 0 ? p->xu[i] : p->xl[i];
        x[i] = b - a->act_x[i] * tol->margin * fmax(1.0, fabs(b));
      }
    if (ea__kkt_pattern(k, a->act_x, a->act_g, 1)) return -1;
    const int nw = ea__asn_newton(a, x, iters);
    if (nw < 0) return -1;
    /* signs and the rows and bounds outside the set (k->r, k->g are at x); a multiplier of
     * the wrong sign but below 1e-3 dtol stays (degenerate: at its bound with nothing to
     * hold), reported as 0 */
    const double tiny = 1e-3 * tol->dtol;
    int changed = 0;
    for (int i = 0; i < p->m; ++i) {
      const int s = a->act_g[i];
      if ((s == -1 && k->lam[i] > tiny) || (s == 1 && k->lam[i] < -tiny) ||
          (nw == 1 && s == -1 && k->g[i] > p->gl[i] + tol->ptol) ||
          (nw == 1 && s == 1 && k->g[i] < p->gu[i] - tol->ptol)) {
        a->act_g[i] = 0, k->lam[i] = 0.0, changed = 1; /* leaves the set */
      } else if (s == 0 && k->g[i] < p->gl[i] - tol->ptol) {
        a->act_g[i] = -1, changed = 1;
      } else if (s == 0 && k->g[i] > p->gu[i] + tol->ptol) {
        a->act_g[i] = 1, changed = 1;
      }
    }
    for (int i = 0; i < p->n; ++i) {
      const int s = a->act_x[i];
      if ((s == -1 && k->r[i] < -tiny) || (s == 1 && k->r[i] > tiny)) {
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
    mult_g[i] = a->act_g[i] == -1  ? fmin(k->lam[i], 0.0)
                : a->act_g[i] == 1 ? fmax(k->lam[i], 0.0)
                                   : k->lam[i];
  for (int i = 0; i < p->n; ++i) {
    mult_xl[i] = a->act_x[i] == -1 ? fmax(k->r[i], 0.0) : 0.0;
    mult_xu[i] = a->act_x[i] == 1 ? fmax(-k->r[i], 0.0) : 0.0;
  }
  return 0;
}
