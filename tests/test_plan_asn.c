/* The active-set Newton (planner/nlp/plan_asn.c) on small NLPs with closed-form solutions,
 * through Ipopt's callback signatures:
 *  1. min -x - y on the unit disc, the disc's row given twice (a redundant active row: the
 *     KKT matrix without the row regularisation is singular): x = y = sqrt((1 - m) / 2) with
 *     the margin m, stationarity of the returned multipliers;
 *  2. min (x - 2)^2 + (y - 2)^2 with x <= 1 (a bound) and x + y <= 10 (a row), started with
 *     an empty active set: the free Newton steps to (2, 2), the bound is added, one set change
 *     gives (1 - m, 2) and the bound's multiplier 2 (1 + m);
 *  3. x = 0 and x = 1 (contradictory equality rows): no candidate (-1), as the caller must
 *     then solve with Ipopt. */
#include "ea_test.h"
#include "plan_asn_impl.h"

#include <coin/IpStdCInterface.h>
#include <math.h>
#include <string.h>

static int g_case; /* which NLP the callbacks evaluate */

static Bool grad_f(Index n, Number *x, Bool new_x, Number *g, UserDataPtr ud) {
  (void)n, (void)new_x, (void)ud;
  if (g_case == 1) {
    g[0] = -1.0, g[1] = -1.0;
  } else if (g_case == 2) {
    g[0] = 2.0 * (x[0] - 2.0), g[1] = 2.0 * (x[1] - 2.0);
  } else {
    g[0] = 0.0;
  }
  return TRUE;
}

static Bool eval_g(Index n, Number *x, Bool new_x, Index m, Number *g, UserDataPtr ud) {
  (void)n, (void)new_x, (void)m, (void)ud;
  if (g_case == 1) {
    g[0] = x[0] * x[0] + x[1] * x[1];
    g[1] = 2.0 * g[0];
  } else if (g_case == 2) {
    g[0] = x[0] + x[1];
  } else {
    g[0] = g[1] = x[0];
  }
  return TRUE;
}

static Bool jac(Index n, Number *x, Bool new_x, Index m, Index nele, Index *ir, Index *jc,
                Number *v, UserDataPtr ud) {
  (void)n, (void)new_x, (void)m, (void)nele, (void)ir, (void)jc, (void)ud;
  if (g_case == 1) {
    v[0] = 2.0 * x[0], v[1] = 2.0 * x[1], v[2] = 4.0 * x[0], v[3] = 4.0 * x[1];
  } else if (g_case == 2) {
    v[0] = v[1] = 1.0;
  } else {
    v[0] = v[1] = 1.0;
  }
  return TRUE;
}

static Bool hess(Index n, Number *x, Bool new_x, Number of, Index m, Number *lam, Bool new_lam,
                 Index nele, Index *ir, Index *jc, Number *v, UserDataPtr ud) {
  (void)n, (void)x, (void)new_x, (void)m, (void)new_lam, (void)nele, (void)ir, (void)jc, (void)ud;
  if (g_case == 1) { /* (0,0), (1,1) */
    v[0] = v[1] = 2.0 * lam[0] + 4.0 * lam[1];
  } else if (g_case == 2) {
    v[0] = v[1] = 2.0 * of;
  } else {
    v[0] = 0.0;
  }
  return TRUE;
}

int main(void) {
  const double m = 1e-9, inf = 1e19;
  ea__nlp_t p = {.grad_f = grad_f, .g = eval_g, .jac = jac, .h = hess};
  const ea__asn_tol_t tol = {.ptol = 1e-12, .dtol = 1e-12, .margin = m};
  char msg[200];
  int it;

  /* 1. the disc, its row twice */
  {
    g_case = 1;
    const double xl[2] = {-inf, -inf}, xu[2] = {inf, inf}, gl[2] = {-inf, -inf}, gu[2] = {1, 2};
    const int jr[4] = {0, 0, 1, 1}, jcl[4] = {0, 1, 0, 1}, hr[2] = {0, 1}, hc[2] = {0, 1};
    p.n = 2, p.m = 2, p.nnz_j = 4, p.nnz_h = 2;
    p.xl = xl, p.xu = xu, p.gl = gl, p.gu = gu, p.jrow = jr, p.jcol = jcl, p.hrow = hr;
    p.hcol = hc;
    ea__kkt_t *k = ea__kkt_alloc(&p);
    ea__asn_t *a = k ? ea__asn_alloc(k) : NULL;
    const double s = sqrt(0.5), xref[2] = {s, s}, gref[2] = {1.0, 2.0};
    double x[2] = {0.69, 0.73}, mg[2] = {0.3, 0.1}, ml[2] = {0, 0}, mu[2] = {0, 0};
    const int rc = a ? ea__asn_solve(a, &tol, xref, gref, x, mg, ml, mu, &it) : -2;
    const double want = sqrt(0.5 * (1.0 - m));
    snprintf(msg, sizeof msg, "disc, row twice: rc %d after %d steps, x = (%.15g, %.15g)", rc, it,
             x[0], x[1]);
    ea_test_true(rc == 0 && it > 0, msg);
    ea_test_rel(x[0], want, 1e-12, "disc: x = sqrt((1 - margin) / 2)");
    ea_test_rel(x[1], want, 1e-12, "disc: y = sqrt((1 - margin) / 2)");
    /* stationarity: -1 + 2 x (lam0 + 2 lam1) = 0, both multipliers >= 0 */
    ea_test_abs(-1.0 + 2.0 * x[0] * (mg[0] + 2.0 * mg[1]), 0.0, 1e-12,
                "disc: stationarity of the returned multipliers");
    ea_test_true(mg[0] >= 0.0 && mg[1] >= 0.0, "disc: multipliers of upper rows >= 0");
    ea__asn_free(a);
    ea__kkt_free(k);
  }
  /* 2. a bound found on the way */
  {
    g_case = 2;
    const double xl[2] = {-inf, -inf}, xu[2] = {1.0, inf}, gl[1] = {-inf}, gu[1] = {10.0};
    const int jr[2] = {0, 0}, jcl[2] = {0, 1}, hr[2] = {0, 1}, hc[2] = {0, 1};
    p.n = 2, p.m = 1, p.nnz_j = 2, p.nnz_h = 2;
    p.xl = xl, p.xu = xu, p.gl = gl, p.gu = gu, p.jrow = jr, p.jcol = jcl, p.hrow = hr;
    p.hcol = hc;
    ea__kkt_t *k = ea__kkt_alloc(&p);
    ea__asn_t *a = k ? ea__asn_alloc(k) : NULL;
    const double xref[2] = {0.0, 0.0}, gref[1] = {0.0};
    double x[2] = {0.0, 0.0}, mg[1] = {0}, ml[2] = {0, 0}, mu[2] = {0, 0};
    const int rc = a ? ea__asn_solve(a, &tol, xref, gref, x, mg, ml, mu, &it) : -2;
    snprintf(msg, sizeof msg, "bound found: rc %d after %d steps, x = (%.15g, %.15g)", rc, it, x[0],
             x[1]);
    ea_test_true(rc == 0, msg);
    ea_test_rel(x[0], 1.0 - m, 1e-14, "bound found: x = 1 - margin");
    ea_test_rel(x[1], 2.0, 1e-14, "bound found: y = 2");
    ea_test_rel(mu[0], 2.0 * (1.0 + m), 1e-12, "bound found: its multiplier 2 (1 + margin)");
    ea_test_true(mg[0] == 0.0 && ml[0] == 0.0 && mu[1] == 0.0, "bound found: the others 0");
    ea__asn_free(a);
    ea__kkt_free(k);
  }
  /* 3. contradictory rows */
  {
    g_case = 3;
    const double xl[1] = {-inf}, xu[1] = {inf}, gl[2] = {0.0, 1.0}, gu[2] = {0.0, 1.0};
    const int jr[2] = {0, 1}, jcl[2] = {0, 0}, hr[1] = {0}, hc[1] = {0};
    p.n = 1, p.m = 2, p.nnz_j = 2, p.nnz_h = 1;
    p.xl = xl, p.xu = xu, p.gl = gl, p.gu = gu, p.jrow = jr, p.jcol = jcl, p.hrow = hr;
    p.hcol = hc;
    ea__kkt_t *k = ea__kkt_alloc(&p);
    ea__asn_t *a = k ? ea__asn_alloc(k) : NULL;
    const double xref[1] = {0.5}, gref[2] = {0.5, 0.5};
    double x[1] = {0.5}, mg[2] = {0, 0}, ml[1] = {0}, mu[1] = {0};
    const int rc = a ? ea__asn_solve(a, &tol, xref, gref, x, mg, ml, mu, &it) : -2;
    snprintf(msg, sizeof msg, "contradictory rows: no candidate (rc %d, want -1)", rc);
    ea_test_true(rc == -1, msg);
    ea__asn_free(a);
    ea__kkt_free(k);
  }
  return ea_test_summary("test_plan_asn");
}
