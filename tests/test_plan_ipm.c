/* The planner's own interior point (planner/nlp/plan_ipm.c) on small NLPs with closed-form
 * solutions, through Ipopt's callback signatures:
 *  1. min (x - 2)^2 + (y - 1)^2 with the rows x + y in [-10, 2] and x - y = 0.2, the bounds
 *     x <= 5, y >= -5 (inactive): the solution (1.1, 0.9), the rows' multipliers 1.0 and 0.8
 *     (Ipopt's signs), the bounds' 0;
 *  2. min -x^2 on [-1, 2] from x = 0.5 (a concave objective: Newton on the barrier problem
 *     without the inertia correction heads for the maximum at 0): the minimum x = 2 with the
 *     bound's multiplier 4, where the Hessian's diagonal had to be raised;
 *  3. x = 0 and x = 1 (contradictory equality rows): no candidate (-1), as the caller must
 *     then solve with Ipopt;
 *  4. problem 1 with a stop that asks to stop (the caller's wall-clock limit): -1 before the
 *     first step.
 * The interior point's answers hold its barrier's last parameter (tol / 10) inside the active
 * limits, so the tolerances below are ~1e-8, its stationarity 1e-9. */
#include "ea_test.h"
#include "plan_ipm_impl.h"

#include <coin/IpStdCInterface.h>
#include <math.h>
#include <string.h>

static int g_case; /* which NLP the callbacks evaluate */

static int stop_now(void *ud) {
  (void)ud;
  return 1;
}

static Bool grad_f(Index n, Number *x, Bool new_x, Number *g, UserDataPtr ud) {
  (void)n, (void)new_x, (void)ud;
  if (g_case == 1) {
    g[0] = 2.0 * (x[0] - 2.0), g[1] = 2.0 * (x[1] - 1.0);
  } else if (g_case == 2) {
    g[0] = -2.0 * x[0];
  } else {
    g[0] = 0.0;
  }
  return TRUE;
}

static Bool eval_g(Index n, Number *x, Bool new_x, Index m, Number *g, UserDataPtr ud) {
  (void)n, (void)new_x, (void)m, (void)ud;
  if (g_case == 1) {
    g[0] = x[0] + x[1];
    g[1] = x[0] - x[1];
  } else if (g_case == 3) {
    g[0] = g[1] = x[0];
  }
  return TRUE;
}

static Bool jac(Index n, Number *x, Bool new_x, Index m, Index nele, Index *ir, Index *jc,
                Number *v, UserDataPtr ud) {
  (void)n, (void)x, (void)new_x, (void)m, (void)nele, (void)ir, (void)jc, (void)ud;
  if (g_case == 1) {
    v[0] = v[1] = v[2] = 1.0, v[3] = -1.0;
  } else if (g_case == 3) {
    v[0] = v[1] = 1.0;
  }
  return TRUE;
}

static Bool hess(Index n, Number *x, Bool new_x, Number of, Index m, Number *lam, Bool new_lam,
                 Index nele, Index *ir, Index *jc, Number *v, UserDataPtr ud) {
  (void)n, (void)x, (void)new_x, (void)m, (void)lam, (void)new_lam, (void)nele, (void)ir;
  (void)jc, (void)ud;
  if (g_case == 1) {
    v[0] = v[1] = 2.0 * of;
  } else if (g_case == 2) {
    v[0] = -2.0 * of;
  } else {
    v[0] = 0.0;
  }
  return TRUE;
}

int main(void) {
  const double inf = 1e19;
  ea__nlp_t p = {.grad_f = grad_f, .g = eval_g, .jac = jac, .h = hess};
  const ea__ipm_opt_t o = {
      .tol = 1e-8, .ptol = 1e-10, .mu_init = 1e-4, .push = 1e-6, .push_s = 1e-2, .max_iter = 40};
  char msg[240];
  int it;

  /* 1. two rows, one of them an equality, both active */
  {
    g_case = 1;
    const double xl[2] = {-inf, -5.0}, xu[2] = {5.0, inf}, gl[2] = {-10.0, 0.2}, gu[2] = {2.0, 0.2};
    const int jr[4] = {0, 0, 1, 1}, jcl[4] = {0, 1, 0, 1}, hr[2] = {0, 1}, hc[2] = {0, 1};
    p.n = 2, p.m = 2, p.nnz_j = 4, p.nnz_h = 2;
    p.xl = xl, p.xu = xu, p.gl = gl, p.gu = gu, p.jrow = jr, p.jcol = jcl, p.hrow = hr;
    p.hcol = hc;
    ea__kkt_t *a = ea__kkt_alloc(&p);
    double x[2] = {0.0, 0.0}, mg[2] = {0, 0}, ml[2] = {0, 0}, mu[2] = {0, 0};
    const int rc = a ? ea__ipm_solve(a, &o, x, mg, ml, mu, &it) : -2;
    snprintf(msg, sizeof msg,
             "two rows: rc %d after %d iterations, x = (%.12g, %.12g), multipliers %.12g %.12g", rc,
             it, x[0], x[1], mg[0], mg[1]);
    ea_test_true(rc == 0 && it > 0, msg);
    ea_test_abs(x[0], 1.1, 1e-8, "two rows: x = 1.1");
    ea_test_abs(x[1], 0.9, 1e-8, "two rows: y = 0.9");
    ea_test_abs(mg[0], 1.0, 1e-7, "two rows: x + y <= 2 has multiplier 1 (> 0: upper)");
    ea_test_abs(mg[1], 0.8, 1e-7, "two rows: x - y = 0.2 has multiplier 0.8");
    ea_test_true(fabs(ml[1]) < 1e-8 && fabs(mu[0]) < 1e-8, "two rows: the bounds' multipliers 0");
    /* stationarity of the returned point and multipliers */
    const double r0 = 2.0 * (x[0] - 2.0) + mg[0] + mg[1] + mu[0];
    const double r1 = 2.0 * (x[1] - 1.0) + mg[0] - mg[1] - ml[1];
    ea_test_abs(fmax(fabs(r0), fabs(r1)), 0.0, 1e-9, "two rows: stationarity");
    /* 4. the same, told to stop */
    ea__ipm_opt_t os = o;
    os.stop = stop_now;
    double xs[2] = {0.0, 0.0};
    const int rs = a ? ea__ipm_solve(a, &os, xs, mg, ml, mu, &it) : -2;
    snprintf(msg, sizeof msg, "stop: rc %d after %d iterations (want -1 after 0)", rs, it);
    ea_test_true(rs == -1 && it == 0, msg);
    ea__kkt_free(a);
  }
  /* 2. a concave objective on an interval */
  {
    g_case = 2;
    const double xl[1] = {-1.0}, xu[1] = {2.0};
    const int hr[1] = {0}, hc[1] = {0};
    p.n = 1, p.m = 0, p.nnz_j = 0, p.nnz_h = 1;
    p.xl = xl, p.xu = xu, p.gl = NULL, p.gu = NULL, p.jrow = NULL, p.jcol = NULL, p.hrow = hr;
    p.hcol = hc;
    ea__kkt_t *a = ea__kkt_alloc(&p);
    double x[1] = {0.5}, mg[1] = {0}, ml[1] = {0}, mu[1] = {0};
    const int rc = a ? ea__ipm_solve(a, &o, x, mg, ml, mu, &it) : -2;
    snprintf(msg, sizeof msg, "concave: rc %d after %d iterations, x = %.12g, z_U = %.12g", rc, it,
             x[0], mu[0]);
    ea_test_true(rc == 0, msg);
    ea_test_abs(x[0], 2.0, 1e-8, "concave: the minimum at the upper bound (not the maximum 0)");
    ea_test_abs(mu[0], 4.0, 1e-7, "concave: its multiplier -f'(2) = 4");
    ea__kkt_free(a);
  }
  /* 3. contradictory rows */
  {
    g_case = 3;
    const double xl[1] = {-inf}, xu[1] = {inf}, gl[2] = {0.0, 1.0}, gu[2] = {0.0, 1.0};
    const int jr[2] = {0, 1}, jcl[2] = {0, 0}, hr[1] = {0}, hc[1] = {0};
    p.n = 1, p.m = 2, p.nnz_j = 2, p.nnz_h = 1;
    p.xl = xl, p.xu = xu, p.gl = gl, p.gu = gu, p.jrow = jr, p.jcol = jcl, p.hrow = hr;
    p.hcol = hc;
    ea__kkt_t *a = ea__kkt_alloc(&p);
    double x[1] = {0.5}, mg[2] = {0, 0}, ml[1] = {0}, mu[1] = {0};
    const int rc = a ? ea__ipm_solve(a, &o, x, mg, ml, mu, &it) : -2;
    snprintf(msg, sizeof msg, "contradictory rows: no candidate (rc %d after %d iterations)", rc,
             it);
    ea_test_true(rc == -1, msg);
    ea__kkt_free(a);
  }
  return ea_test_summary("test_plan_ipm");
}
