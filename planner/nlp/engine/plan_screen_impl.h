/* Private: Ipopt on an NLP whose inequality rows far inside their limits are left out
 * (engine/ipopt_screen.c). */
#ifndef EA_PLAN_SCREEN_IMPL_H
#define EA_PLAN_SCREEN_IMPL_H

#include "nlp_impl.h"

/** Ipopt's problem (its C interface's IpoptProblem; engine/ipopt_impl.h). */
typedef struct IpoptProblemInfo *ea__ipopt_problem_t;

/** The full NLP (engine/nlp_impl.h; its Jacobian row-major). */
typedef ea__nlp_t ea__screen_nlp_t;

typedef struct ea__screen ea__screen_t;

/** The planner's screening (docs/planner.md, "Engines", "Ipopt's rows"): a two-sided row is left
 * out when its family's rows all lie within EA__SCREEN_BAND of their half-width around their middle
 * at the start; a solution is one of the full problem when every row left out lies within
 *  EA__SCREEN_HOLD (strictly inside its limits: an interior point holds its active rows ~1e-9
 *  inside, and a row that would be active comes out at or beyond its limit without its
 *  barrier). */
#define EA__SCREEN_BAND 0.5
#define EA__SCREEN_HOLD (1.0 - 1e-6)

/** Workspace for the NLP p; NULL when out of memory or when its Jacobian is not row-major. */
ea__screen_t *ea__screen_alloc(const ea__screen_nlp_t *p);
void ea__screen_free(ea__screen_t *s);
/** Keep every row except the two-sided inequality rows whose value g (the full rows at the
 *  start point) lies within band of their half-width around their middle, and whose family
 *  (family[i] in 0..nfam-1: rows of one limit on one coordinate; NULL: each row its own) has
 *  no row beyond band. Returns the rows left out. */
int ea__screen_select(ea__screen_t *s, const double *g, double band, const int *family, int nfam);
/** Keep every row (no screening). */
void ea__screen_all(ea__screen_t *s);
/** Rows left out whose value g (the full rows at a solution of the screened NLP) is not
 *  strictly inside band of their half-width join the kept ones. Returns how many joined: 0
 *  means that solution is one of the full NLP too, its left-out rows inactive. */
int ea__screen_grow(ea__screen_t *s, const double *g, double band);
/** Rows kept. */
int ea__screen_rows(const ea__screen_t *s);
/** Ipopt's problem of the kept rows (xl, xu: the variable bounds, referenced by Ipopt for the
 *  solve); its callbacks pass the full NLP's user data on. NULL on failure. */
ea__ipopt_problem_t ea__screen_problem(ea__screen_t *s, const double *xl, const double *xu);
/** IpoptSolve on that problem (its ApplicationReturnStatus returned) with the full NLP's rows: g
 * and mult_g (in: the start's multipliers; out: the solution's, 0 for the rows left out) have m
 * entries. */
int ea__screen_solve(ea__screen_t *s, ea__ipopt_problem_t ip, double *x, double *g, double *obj,
                     double *mult_g, double *mult_xl, double *mult_xu);

#endif
