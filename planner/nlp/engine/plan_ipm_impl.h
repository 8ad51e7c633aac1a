/* Private: a primal-dual interior point on an NLP (engine/nlp_impl.h, engine/ipm.c), its KKT
 * system (engine/kkt_impl.h) factored by LDL'. */
#ifndef EA_PLAN_IPM_IMPL_H
#define EA_PLAN_IPM_IMPL_H

#include "kkt_impl.h"

/** Settings: tol (unscaled stationarity, as the caller's KKT test), ptol (rows), mu_init (the
 *  first barrier parameter; monotone from there), push and push_s (the start and the slacks of
 *  the inequality rows moved this far inside their bounds: Ipopt's bound_push and bound_frac,
 *  slack_bound_push and slack_bound_frac), max_iter; acc_iter > 0 (and the NLP's f): Ipopt's
 *  acceptable termination, acc_iter iterations in a row with the optimality error (scaled as
 *  Ipopt's) at most acc_tol, the rows within ptol and the objective's relative change at most
 *  acc_obj; stop (may be NULL): asked before every iteration, nonzero stops the solve (-1; the
 *  caller's wall-clock limit). */
typedef struct ea__ipm_opt {
  double tol, ptol, mu_init, push, push_s, acc_tol, acc_obj;
  int max_iter, acc_iter;
  int (*stop)(void *ud);
} ea__ipm_opt_t;

/** From x: 0 when x and the multipliers (Ipopt's signs) are a candidate KKT point of the NLP
 *  of k (for the caller to verify), 1 when the acceptable termination stopped it (a candidate
 *  to acc_tol), -1 when none was found (a singular KKT matrix, a failed
 *  callback, max_iter reached, steps that stopped making progress; x and the multipliers are
 *  then undefined). *iters: iterations taken. */
int ea__ipm_solve(ea__kkt_t *k, const ea__ipm_opt_t *o, double *x, double *mult_g, double *mult_xl,
                  double *mult_xu, int *iters);
/** The KKT pattern and its ordering for the next ea__ipm_solve on k (the bounds as
 *  they are then: none may change between), which may run beside other work on another
 *  thread (transcribe/path_*.c: beside the cold guess). 0, or -1 (no pattern). */
int ea__ipm_prepare(ea__kkt_t *k);

#endif
