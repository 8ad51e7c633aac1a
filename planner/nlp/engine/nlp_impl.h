/* Private: the one description of an NLP that the transcriptions (transcribe/) produce and the
 * engines (engine/: the own interior point, the active-set Newton, Ipopt) consume, and the one
 * KKT acceptance test that judges every engine's answer (engine/kkt_test.c).
 *
 *   min f(x)  subject to  gl <= g(x) <= gu,  xl <= x <= xu
 *
 * The callbacks have the signatures of Ipopt's C interface so that Ipopt takes them unchanged;
 * the other engines call them the same way (new_x, the user data ud). */
#ifndef EA_NLP_IMPL_H
#define EA_NLP_IMPL_H

#include <coin/IpStdCInterface.h>

/** An NLP: sizes, bounds, the Jacobian's and the Hessian's (lower triangle) structures, the
 *  callbacks and their user data. Its arrays are referenced, not copied. */
typedef struct ea__nlp {
  int n, m, nnz_j, nnz_h; /* variables, rows, Jacobian and Hessian entries (nnz_h 0: none) */
  const double *xl, *xu, *gl, *gu;
  const int *jrow, *jcol; /* Jacobian structure (row-major: a row's entries contiguous) */
  const int *hrow, *hcol; /* Hessian structure, lower triangle */
  Eval_F_CB f;            /* the objective (NULL: none; the own interior point's acceptable
                             termination needs it) */
  Eval_Grad_F_CB grad_f;
  Eval_G_CB g;
  Eval_Jac_G_CB jac;
  Eval_H_CB h;
  Intermediate_CB iter; /* Ipopt's per-iteration callback (the wall-clock limit) */
  void *ud;
  /* 1: the Hessian after the rows, and only where a step follows (the rows share nothing with
   * it: no modal defects); 0: before them (dyn_rows.c's defects leave their values and
   * gradients for the rows) */
  int hess_last;
} ea__nlp_t;

/** Scratch of the KKT test: g (m), r (n), jv (nnz_j). */
typedef struct ea__kkt_work {
  double *g, *r, *jv;
} ea__kkt_work_t;

/** The KKT acceptance test, the one every engine's answer passes (a warm start that already is
 *  the solution, the active-set Newton's and the own interior point's candidates): is x with
 *  the multipliers (Ipopt's signs: mult_g > 0 at an upper bound, mult_xl, mult_xu >= 0) a KKT
 *  point of p, unscaled (so at least as strict as Ipopt's own test)? Primal: bounds and rows
 *  within ptol; complementarity of every inequality row and bound <= dtol; dual:
 *  |grad f + J' mult_g - mult_xl + mult_xu| <= dtol for every variable that is not fixed.
 *  Evaluates through p's callbacks g (new_x), grad_f and jac into w. 1 yes, 0 no. */
int ea__kkt_accept(const ea__nlp_t *p, const double *x, const double *mult_g, const double *mult_xl,
                   const double *mult_xu, double ptol, double dtol, const ea__kkt_work_t *w);

#endif
