/* Private: an active-set Newton on an NLP given by Ipopt's callbacks (engine/asn.c). */
#ifndef EA_PLAN_ASN_IMPL_H
#define EA_PLAN_ASN_IMPL_H

#include "kkt_impl.h"

/** What a converged point is (the caller's solver settings, given at every solve): rows at
 *  their bounds within ptol, stationarity within dtol (both unscaled); active inequality rows
 *  and bounds held margin inside (relative to max(1, |bound|)), as an interior point's
 *  solution is: the plan is then strictly admissible, not at its limits to within rounding. */
typedef struct ea__asn_tol {
  double ptol, dtol, margin;
} ea__asn_tol_t;

/* The workspace: the active set on the KKT system k (engine/kkt_impl.h), which the interior
 * point of engine/ipm.c may share between solves. */
struct ea__asn {
  ea__kkt_t *k;       /* referenced, not owned */
  ea__asn_tol_t tol;  /* the current solve's */
  int *act_x, *act_g; /* -1 lower, +1 upper, 0 free / inactive, 2 fixed / equality */
};
typedef struct ea__asn ea__asn_t;

/** Workspace on the KKT system k (its NLP's); NULL when out of memory. */
ea__asn_t *ea__asn_alloc(ea__kkt_t *k);
void ea__asn_free(ea__asn_t *a);
/** From x, with the multipliers (Ipopt's signs: mult_g > 0 at an upper bound) of a nearby
 *  solution x_ref whose rows are g_ref: the active set they show (a multiplier larger than its
 *  gap), Newton on it, the set corrected until it stops changing. 0: x and the multipliers are
 *  a candidate KKT point (for the caller to verify); -1: no candidate (singular KKT matrix,
 *  no convergence, the set kept changing; x and the multipliers are then undefined).
 *  *iters: Newton steps taken. */
int ea__asn_solve(ea__asn_t *a, const ea__asn_tol_t *tol, const double *x_ref, const double *g_ref,
                  double *x, double *mult_g, double *mult_xl, double *mult_xu, int *iters);

#endif
