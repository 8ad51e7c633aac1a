/* Private: the one description of an NLP that the transcriptions (transcribe/) produce and the
 * engines (engine/: the own interior point, the active-set Newton, Ipopt) consume, and the one
 * KKT acceptance test that judges every engine's answer (engine/kkt_test.c).
 *
 *   min f(x)  subject to  gl <= g(x) <= gu,  xl <= x <= xu
 *
 * The callbacks have the signatures of Ipopt's C interface (Bool, Index: int; Number: double;
 * nonzero: success) so that Ipopt takes them unchanged (engine/ipopt_*.c); the other engines
 * call them the same way (new_x, the user data ud). No engine's header is needed here. */
#ifndef EA_NLP_IMPL_H
#define EA_NLP_IMPL_H

/** The objective f(x) into *f. */
typedef int (*ea__nlp_f_fn)(int n, double *x, int new_x, double *f, void *ud);
/** Its gradient into g (n). */
typedef int (*ea__nlp_grad_f_fn)(int n, double *x, int new_x, double *g, void *ud);
/** The rows into g (m). */
typedef int (*ea__nlp_g_fn)(int n, double *x, int new_x, int m, double *g, void *ud);
/** The Jacobian: its structure (values NULL) or its values (irow, jcol NULL). */
typedef int (*ea__nlp_jac_fn)(int n, double *x, int new_x, int m, int nele, int *irow, int *jcol,
                              double *values, void *ud);
/** The Lagrangian's Hessian (objective factor of, multipliers lambda), lower triangle: its
 *  structure (values NULL) or its values. */
typedef int (*ea__nlp_h_fn)(int n, double *x, int new_x, double of, int m, double *lambda,
                            int new_lambda, int nele, int *irow, int *jcol, double *values,
                            void *ud);
/** Per iteration (Ipopt's intermediate callback): 0 stops the solve. */
typedef int (*ea__nlp_iter_fn)(int alg_mod, int iter, double obj, double inf_pr, double inf_du,
                               double mu, double d_norm, double reg, double alpha_du,
                               double alpha_pr, int ls, void *ud);

/** An NLP: sizes, bounds, the Jacobian's and the Hessian's (lower triangle) structures, the
 *  callbacks and their user data. Its arrays are referenced, not copied. */
typedef struct ea__nlp {
  int n, m, nnz_j, nnz_h; /* variables, rows, Jacobian and Hessian entries (nnz_h 0: none) */
  const double *xl, *xu, *gl, *gu;
  const int *jrow, *jcol; /* Jacobian structure (row-major: a row's entries contiguous) */
  const int *hrow, *hcol; /* Hessian structure, lower triangle */
  ea__nlp_f_fn f;         /* the objective (NULL: none; the own interior point's acceptable
                             termination needs it) */
  ea__nlp_grad_f_fn grad_f;
  ea__nlp_g_fn g;
  ea__nlp_jac_fn jac;
  ea__nlp_h_fn h;
  ea__nlp_iter_fn iter; /* Ipopt's per-iteration callback (the wall-clock limit) */
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
