/* Private: Ipopt, one of the engines (engine/ipopt_problem.c): every option the planner gives
 * it is set here; the rows Ipopt sees are engine/ipopt_screen.c's. Ipopt's own header is
 * included by engine/ipopt_*.c alone: the rest of the planner sees its problem as an opaque
 * pointer and its return codes as the values below. */
#ifndef EA_IPOPT_IMPL_H
#define EA_IPOPT_IMPL_H

#include "plan_impl.h"
#include "plan_screen_impl.h"

/** The ApplicationReturnStatus values the planner reads (their values checked against Ipopt's
 *  at compile time, engine/ipopt_problem.c). */
enum {
  EA__IPOPT_SOLVE_SUCCEEDED = 0,
  EA__IPOPT_ACCEPTABLE = 1,
  EA__IPOPT_INFEASIBLE = 2,
  EA__IPOPT_USER_STOP = 5, /* the planner's wall-clock limit (solver.max_time_s) */
  EA__IPOPT_MAX_ITER = -1,
  EA__IPOPT_RESTORATION_FAILED = -2,
  EA__IPOPT_MAX_CPU_TIME = -4,
  EA__IPOPT_INVALID_PROBLEM = -11,
  EA__IPOPT_INVALID_OPTION = -12,
  EA__IPOPT_NO_MEMORY = -102,
  EA__IPOPT_INTERNAL_ERROR = -199
};

/** The Ipopt problem of the knot transcription with its rows of the next solve and the
 *  options (none for a planner that solves in the path coordinate). */
ea_status_t ea__ipopt_create(ea_planner_t *pl);
/** Name of an ApplicationReturnStatus. */
const char *ea__ipopt_name(int s);
/** The options of a problem of either transcription: output, MUMPS, the solver settings'
 *  tolerances and iterations, the Hessian (exact or limited-memory), no bound relaxation;
 *  bound_push > 0: Ipopt's bound_push and bound_frac (0: Ipopt's defaults). */
void ea__ipopt_options(ea__ipopt_problem_t ip, const ea_planner_settings_t *s, int hess_exact,
                       double bound_push);
/** The start: cold, warm (the last plan with its multipliers) or updated (warm after
 *  ea_planner_update or bounds tightened between the knots): the barrier's mu_init and the
 *  warm-start pushes. */
void ea__ipopt_start_options(ea__ipopt_problem_t ip, int warm, int updated);
/** The barrier strategy of one attempt: monotone (mono) or adaptive, mu_init (> 0: set; 0:
 *  the start's), the bound multipliers' start (mu-based or constant), barrier_tol_factor. */
void ea__ipopt_barrier_options(ea__ipopt_problem_t ip, int mono, double mu_init, int mu_based_mult,
                               double barrier_tol_factor);
/** Ipopt's derivative checker (second: of the Hessian too) writing to a temporary file whose
 *  name goes to tmpl ("" when none could be made). */
void ea__deriv_test_options(ea__ipopt_problem_t ip, int second, char tmpl[64]);
/** The count of errors the derivative checker reported in its file (-1: unknown). */
int ea__deriv_errors(const char *path);

/** Free Ipopt's problem (NULL: nothing). */
void ea__ipopt_free(ea__ipopt_problem_t ip);

#endif
