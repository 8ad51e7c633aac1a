/* Private: an active-set Newton on an NLP given by Ipopt's callbacks (engine/asn.c). */
#ifndef EA_PLAN_ASN_IMPL_H
#define EA_PLAN_ASN_IMPL_H

#include "nlp_impl.h"

#include <klu.h>

/** The NLP (engine/nlp_impl.h). */
typedef ea__nlp_t ea__asn_nlp_t;

/** What a converged point is (the caller's solver settings, given at every solve): rows at
 *  their bounds within ptol, stationarity within dtol (both unscaled); active inequality rows
 *  and bounds held margin inside (relative to max(1, |bound|)), as an interior point's
 *  solution is: the plan is then strictly admissible, not at its limits to within rounding. */
typedef struct ea__asn_tol {
  double ptol, dtol, margin;
} ea__asn_tol_t;

/* The workspace; its KKT matrix (pattern, values, KLU's analysis) also serves the interior
 * point of engine/ipm.c. */
struct ea__asn {
  ea__asn_nlp_t p;
  ea__asn_tol_t tol;  /* the current solve's */
  int *act_x, *act_g; /* -1 lower, +1 upper, 0 free / inactive, 2 fixed / equality */
  int *kx, *kg;       /* KKT index of a free variable / an active row (-1: none) */
  int nk, nnz_k, nx;  /* KKT size, its entries; nx: free variables (engine/ipm.c) */
  int ipm_ready; /* the pattern is the interior point's (ea__ipm_prepare), for its next solve */
  int *Ap, *Ai, *cnt; /* KKT pattern (CSC, full symmetric) */
  double *Ax;
  int *pj[2], *ph[2]; /* positions of each Jacobian / Hessian entry in Ax (-1: none) */
  int *pd;            /* position of each diagonal */
  double *gf, *g, *jv, *hv, *lam, *rhs, *r;
  klu_common c;
  klu_symbolic *sym;
};
typedef struct ea__asn ea__asn_t;

/** Workspace for the NLP p (its arrays are referenced, not copied); NULL when out of memory. */
ea__asn_t *ea__asn_alloc(const ea__asn_nlp_t *p);
void ea__asn_free(ea__asn_t *a);
/** From x, with the multipliers (Ipopt's signs: mult_g > 0 at an upper bound) of a nearby
 *  solution x_ref whose rows are g_ref: the active set they show (a multiplier larger than its
 *  gap), Newton on it, the set corrected until it stops changing. 0: x and the multipliers are
 *  a candidate KKT point (for the caller to verify); -1: no candidate (singular KKT matrix,
 *  no convergence, the set kept changing; x and the multipliers are then undefined).
 *  *iters: Newton steps taken. */
int ea__asn_solve(ea__asn_t *a, const ea__asn_tol_t *tol, const double *x_ref, const double *g_ref,
                  double *x, double *mult_g, double *mult_xl, double *mult_xu, int *iters);

/** The KKT pattern of the variables with act_x 0 and the rows with act_g != 0 (in that order:
 *  kx, kg), its positions (pj, ph, pd) and KLU's symbolic analysis. 0, or -1 (nothing free, or
 *  KLU failed). */
int ea__asn_pattern(ea__asn_t *a);
/** The KKT matrix's values from the Hessian (hv) and Jacobian (jv) at their positions of the
 *  current pattern, every other entry (the diagonals of the rows among them) zero. */
void ea__asn_fill(ea__asn_t *a);
/** Gradient (gf), rows (g), Jacobian (jv) and, hess != 0, the Lagrangian's Hessian (hv, the
 *  multipliers lam) at x; r = grad f + J' lam. 0, or -1 (a callback failed, not finite). */
int ea__asn_eval(ea__asn_t *a, double *x, int hess);

#endif
