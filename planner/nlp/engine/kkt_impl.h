/* Private: the KKT system of an NLP (engine/nlp_impl.h) that the active-set Newton
 * (engine/asn.c) and the own interior point (engine/ipm.c) solve: its values at a point (the
 * callbacks' gradient, rows, Jacobian and Hessian), the sparse pattern of the matrix
 * [H J'; J D] over a chosen set of variables and rows, the fill-reducing ordering and the two
 * factorizations (SuiteSparse): KLU's LU (BTF + AMD) for the active-set Newton, LDL' (AMD) for
 * the interior point (engine/kkt.c). */
#ifndef EA_KKT_IMPL_H
#define EA_KKT_IMPL_H

#include "nlp_impl.h"

#include <klu.h>

/** The workspace. The matrix is held in CSC with both triangles (full symmetric); a variable
 *  or row outside the chosen set has no KKT index. */
typedef struct ea__kkt {
  ea__nlp_t p;
  /* values at the last ea__kkt_eval: gradient, rows, Jacobian, Hessian (at the multipliers
   * lam), r = grad f + J' lam; rhs: a right-hand side of the solves (overwritten by the
   * solution) */
  double *gf, *g, *jv, *hv, *lam, *r, *rhs;
  int *kx, *kg;      /* KKT index of a variable / a row (-1: not in the system) */
  int nk, nnz_k, nx; /* KKT size, its entries, the variables among them */
  int full; /* the pattern is the interior point's, prepared for its next solve (engine/ipm.c) */
  int *Ap, *Ai, *cnt; /* the pattern (CSC, both triangles) */
  double *Ax;
  int *pj[2], *ph[2]; /* positions of each Jacobian / Hessian entry in Ax (-1: none) */
  int *pd;            /* position of each diagonal */
  int *perm;          /* AMD's symmetric ordering of the pattern (for the LDL') */
  /* KLU: its analysis (the ordering) and the LU factors of the active-set Newton */
  klu_common c;
  klu_symbolic *sym;
  klu_numeric *num;
  double rcond0; /* the pivots' ratio of num's first factorization */
  /* LDL' in the order P (perm) */
  int *P, *Pinv, *Lp, *Parent, *Lnz, *Flag, *Pattern, *Li;
  double *Lx, *D, *Y;
} ea__kkt_t;

/** Workspace for the NLP p (its arrays are referenced, not copied); NULL when out of memory. */
ea__kkt_t *ea__kkt_alloc(const ea__nlp_t *p);
void ea__kkt_free(ea__kkt_t *k);

/** Gradient (gf), rows (g), Jacobian (jv) and, hess != 0, the Lagrangian's Hessian (hv, at the
 *  multipliers lam) at x; r = grad f + J' lam. 0, or -1 (a callback failed, not finite). */
int ea__kkt_eval(ea__kkt_t *k, double *x, int hess);

/** The pattern of the variables with act_x[i] == 0 (act_x NULL: every variable that is not
 *  fixed, xl < xu) and the rows with act_g[i] != 0 (act_g NULL: every row), in that order, the
 *  positions pj, ph, pd and the ordering: lu 1, KLU's analysis (BTF + AMD) for
 *  ea__kkt_lu_solve; lu 0, AMD's symmetric ordering (perm) for the LDL'. Clears k->full. 0,
 *  or -1 (nothing in the system, or the ordering failed). */
int ea__kkt_pattern(ea__kkt_t *k, const int *act_x, const int *act_g, int lu);
/** The matrix's values from the Hessian (hv) and Jacobian (jv) at their positions of the
 *  current pattern, every other entry (the diagonals of the rows among them) zero. */
void ea__kkt_fill(ea__kkt_t *k);

/** K d = rhs (k->rhs, overwritten by d) by KLU's LU: the factors of the last solve since
 *  ea__kkt_lu_release refactored in their pivot order, unless that lost more than a factor
 *  1e3 in the pivots' ratio min |u_kk| / max |u_kk|; then factored anew. 0, or -1. */
int ea__kkt_lu_solve(ea__kkt_t *k);
/** The LU factors freed (a new pattern or values that need a fresh pivot order follow). */
void ea__kkt_lu_release(ea__kkt_t *k);

/** LDL's symbolic factorization of the current pattern in its AMD ordering (ea__kkt_pattern
 *  with lu 0). 0, or -1 (out of memory). */
int ea__kkt_ldl_symbolic(ea__kkt_t *k);
/** LDL' of the current matrix: the count of pivots factored (nk when it succeeded, less at a
 *  zero pivot); *neg: the negative pivots (the inertia) when it succeeded. */
int ea__kkt_ldl_factor(ea__kkt_t *k, int *neg);
/** x <- K^-1 x from the LDL' factors. */
void ea__kkt_ldl_solve(ea__kkt_t *k, double *x);
/** res = b - K d (the current matrix). */
void ea__kkt_residual(const ea__kkt_t *k, const double *b, const double *d, double *res);

#endif
