/* The KKT acceptance test of an engine's answer. */
#include "plan_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Is x (with the multipliers in pl->mult_*) already a KKT point to the
 * solver's tolerances (unscaled, so at least as strict as Ipopt's own test
 * at its first iterate)? A warm start from the planner's own solution of
 * the unchanged problem then needs no Ipopt solve: Ipopt would only push
 * the point into the interior and walk back. Primal: rows and bounds within
 * max(constr_viol_tol, 1e-9) (Ipopt's acceptable level, which the plan's
 * final check also uses); dual: |grad f + J' lambda - z_L + z_U| <= tol;
 * complementarity of every bound and inequality row <= tol. */
int ea__kkt_ok_tol(ea_planner_t *pl, const double *x, double dtol) {
  const ea_task_t *t = &pl->task;
  const double ptol = fmax(1e-9, t->solver.constr_tol);
  pl->cache_val = pl->cache_sens = 0;
  if (ea__plan_eval_g(pl, x, pl->g)) return 0;
  for (int i = 0; i < pl->m; ++i) {
    if (pl->g[i] < pl->gl[i] - ptol || pl->g[i] > pl->gu[i] + ptol) return 0;
    if (pl->gl[i] == pl->gu[i]) continue;
    /* Ipopt's sign: lambda > 0 at the upper bound, < 0 at the lower */
    const double lam = pl->mult_g[i];
    const double gap = lam > 0 ? pl->gu[i] - pl->g[i] : pl->g[i] - pl->gl[i];
    if (fabs(lam) * fmin(gap, 1e19) > dtol) return 0;
  }
  double *r = pl->kkt_r;
  memset(r, 0, (size_t)pl->n * sizeof *r);
  for (int i = 0; i < pl->n_terms; ++i)
    pl->terms[i].grad(pl, x, pl->terms[i].weight, r);
  ea__plan_jac(pl, x, NULL, NULL, pl->jval);
  for (int e = 0; e < pl->nnz; ++e)
    r[pl->jcol[e]] += pl->jval[e] * pl->mult_g[pl->irow[e]];
  for (int i = 0; i < pl->n; ++i) {
    if (x[i] < pl->xl[i] - ptol || x[i] > pl->xu[i] + ptol) return 0;
    if (pl->xl[i] == pl->xu[i]) continue; /* fixed: Ipopt removes it */
    if (fabs(r[i] - pl->mult_xl[i] + pl->mult_xu[i]) > dtol) return 0;
    if (pl->mult_xl[i] * fmin(x[i] - pl->xl[i], 1e19) > dtol ||
        pl->mult_xu[i] * fmin(pl->xu[i] - x[i], 1e19) > dtol)
      return 0;
  }
  return 1;
}

int ea__kkt_ok(ea_planner_t *pl, const double *x) {
  return ea__kkt_ok_tol(pl, x, pl->task.solver.tol);
}
