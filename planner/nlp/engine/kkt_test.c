/* The KKT acceptance test of an engine's answer (engine/nlp_impl.h). */
#include "nlp_impl.h"

#include <math.h>
#include <stddef.h>

int ea__kkt_accept(const ea__nlp_t *p, const double *x, const double *mult_g, const double *mult_xl,
                   const double *mult_xu, double ptol, double dtol, const ea__kkt_work_t *w) {
  double *xv = (double *)x; /* Ipopt's callbacks take a non-const x; they do not change it */
  for (int i = 0; i < p->n; ++i)
    if (!(x[i] >= p->xl[i] - ptol && x[i] <= p->xu[i] + ptol)) return 0;
  if (!p->g(p->n, xv, 1, p->m, w->g, p->ud)) return 0;
  for (int i = 0; i < p->m; ++i) {
    if (!(w->g[i] >= p->gl[i] - ptol && w->g[i] <= p->gu[i] + ptol)) return 0;
    if (p->gl[i] == p->gu[i]) continue;
    /* Ipopt's sign: lambda > 0 at the upper bound, < 0 at the lower */
    const double lam = mult_g[i];
    const double gap = lam > 0 ? p->gu[i] - w->g[i] : w->g[i] - p->gl[i];
    if (fabs(lam) * fmin(gap, 1e19) > dtol) return 0;
  }
  if (!p->grad_f(p->n, xv, 0, w->r, p->ud) ||
      !p->jac(p->n, xv, 0, p->m, p->nnz_j, NULL, NULL, w->jv, p->ud))
    return 0;
  for (int e = 0; e < p->nnz_j; ++e)
    w->r[p->jcol[e]] += w->jv[e] * mult_g[p->jrow[e]];
  for (int i = 0; i < p->n; ++i) {
    if (p->xl[i] == p->xu[i]) continue; /* fixed: Ipopt removes it */
    if (!(mult_xl[i] >= 0.0 && mult_xu[i] >= 0.0 &&
          fabs(w->r[i] - mult_xl[i] + mult_xu[i]) <= dtol &&
          mult_xl[i] * fmin(x[i] - p->xl[i], 1e19) <= dtol &&
          mult_xu[i] * fmin(p->xu[i] - x[i], 1e19) <= dtol))
      return 0;
  }
  return 1;
}
