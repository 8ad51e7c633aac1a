/* Ipopt with rows left out (planner/nlp/plan_screen.c) on a small NLP with a closed-form
 * solution: min (x - 3)^2 + (y - 1/2)^2 with the rows
 *   0: x in [-1, 1]        (family 0)
 *   1: y in [-1, 1]        (family 1)
 *   2: x + y in [-10, 10]  (family 2)
 *   3: x in [-5/2, 5/2]    (family 0)
 *   4: x - y <= 100        (one-sided: never left out)
 * Solution (1, 1/2), row 0 active with multiplier 4, the others inactive.
 *  1. From (0, 0) every two-sided row is inside half its range: all four are left out, the
 *     screened solution (3, 1/2) breaks rows 0 and 3, which join (grow returns 2); the second
 *     solve from the same start gives (1, 1/2), row 0's multiplier 4, the rows still left out
 *     (1, 2) with multiplier 0 and strictly inside, so grow returns 0.
 *  2. From (0.9, 0): row 0 is beyond half its range, and row 3 (inside, same family) is kept
 *     with it; rows 1 and 2 are left out: 3 rows kept, one solve.
 *  3. A Jacobian whose rows are not in order is refused (NULL). */
#include "ea_test.h"
#include "plan_screen_impl.h"

#include <coin/IpStdCInterface.h>
#include <math.h>
#include <string.h>

#define NROW 5
static const int g_jr[] = {0, 1, 2, 2, 3, 4, 4}, g_jc[] = {0, 1, 0, 1, 0, 0, 1};
static int g_evals; /* row evaluations seen by the full NLP's callback */

static Bool f_cb(Index n, Number *x, Bool new_x, Number *f, UserDataPtr ud) {
  (void)n, (void)new_x, (void)ud;
  *f = (x[0] - 3.0) * (x[0] - 3.0) + (x[1] - 0.5) * (x[1] - 0.5);
  return TRUE;
}

static Bool grad_cb(Index n, Number *x, Bool new_x, Number *g, UserDataPtr ud) {
  (void)n, (void)new_x, (void)ud;
  g[0] = 2.0 * (x[0] - 3.0), g[1] = 2.0 * (x[1] - 0.5);
  return TRUE;
}

static Bool g_cb(Index n, Number *x, Bool new_x, Index m, Number *g, UserDataPtr ud) {
  (void)n, (void)new_x, (void)ud;
  if (m != NROW) return FALSE; /* the full NLP's callbacks always see every row */
  g[0] = x[0], g[1] = x[1], g[2] = x[0] + x[1], g[3] = x[0], g[4] = x[0] - x[1];
  ++g_evals;
  return TRUE;
}

static Bool jac_cb(Index n, Number *x, Bool new_x, Index m, Index nele, Index *ir, Index *jc,
                   Number *v, UserDataPtr ud) {
  (void)n, (void)x, (void)new_x, (void)ud;
  if (m != NROW || nele != 7) return FALSE;
  if (!v) {
    memcpy(ir, g_jr, sizeof g_jr);
    memcpy(jc, g_jc, sizeof g_jc);
    return TRUE;
  }
  const double val[7] = {1, 1, 1, 1, 1, 1, -1};
  memcpy(v, val, sizeof val);
  return TRUE;
}

static Bool h_cb(Index n, Number *x, Bool new_x, Number of, Index m, Number *lam, Bool new_lam,
                 Index nele, Index *ir, Index *jc, Number *v, UserDataPtr ud) {
  (void)n, (void)x, (void)new_x, (void)m, (void)lam, (void)new_lam, (void)nele, (void)ud;
  if (!v) {
    ir[0] = jc[0] = 0, ir[1] = jc[1] = 1;
    return TRUE;
  }
  v[0] = v[1] = 2.0 * of; /* the rows are linear */
  return TRUE;
}

static const double g_gl[NROW] = {-1, -1, -10, -2.5, -1e20}, g_gu[NROW] = {1, 1, 10, 2.5, 100};

static IpoptProblem problem(ea__screen_t *s, const double *xl, const double *xu) {
  IpoptProblem ip = ea__screen_problem(s, xl, xu);
  if (ip) {
    AddIpoptStrOption(ip, "sb", "yes");
    AddIpoptIntOption(ip, "print_level", 0);
    AddIpoptNumOption(ip, "tol", 1e-12);
    AddIpoptNumOption(ip, "bound_relax_factor", 0.0); /* as the planner: limits exactly */
    AddIpoptStrOption(ip, "option_file_name", "");
  }
  return ip;
}

int main(void) {
  const ea__screen_nlp_t p = {.n = 2,
                              .m = NROW,
                              .nnz_j = 7,
                              .nnz_h = 2,
                              .gl = g_gl,
                              .gu = g_gu,
                              .jrow = g_jr,
                              .jcol = g_jc,
                              .f = f_cb,
                              .g = g_cb,
                              .grad_f = grad_cb,
                              .jac = jac_cb,
                              .h = h_cb};
  const double xl[2] = {-1e20, -1e20}, xu[2] = {1e20, 1e20};
  char msg[200];
  /* 1. every two-sided row left out, two join, solved again */
  {
    ea__screen_t *s = ea__screen_alloc(&p);
    ea_test_true(s != NULL, "screen: workspace");
    if (!s) return ea_test_summary("test_plan_screen");
    double x[2] = {0, 0}, g[NROW], mg[NROW] = {0}, ml[2] = {0}, mu[2] = {0}, obj = 0;
    g_cb(2, x, TRUE, NROW, g, NULL);
    const int out = ea__screen_select(s, g, 0.5, (const int[]){0, 1, 2, 0, 3}, 4);
    snprintf(msg, sizeof msg, "from (0, 0): %d rows left out (want 4), %d kept (want 1)", out,
             ea__screen_rows(s));
    ea_test_true(out == 4 && ea__screen_rows(s) == 1, msg);
    IpoptProblem ip = problem(s, xl, xu);
    int rs = ip ? ea__screen_solve(s, ip, x, g, &obj, mg, ml, mu) : -100;
    FreeIpoptProblem(ip);
    snprintf(msg, sizeof msg, "screened solve: status %d, x = (%.12g, %.12g) (want (3, 1/2))", rs,
             x[0], x[1]);
    ea_test_true(rs == Solve_Succeeded && fabs(x[0] - 3.0) < 1e-8 && fabs(x[1] - 0.5) < 1e-8, msg);
    ea_test_abs(g[2], 3.5, 1e-8, "screened solve: every row returned (x + y)");
    const int in = ea__screen_grow(s, g, 1.0 - 1e-6);
    snprintf(msg, sizeof msg, "rows 0 and 3 broken: %d join (want 2), %d kept (want 3)", in,
             ea__screen_rows(s));
    ea_test_true(in == 2 && ea__screen_rows(s) == 3, msg);
    x[0] = x[1] = 0.0;
    ip = problem(s, xl, xu);
    rs = ip ? ea__screen_solve(s, ip, x, g, &obj, mg, ml, mu) : -100;
    FreeIpoptProblem(ip);
    snprintf(msg, sizeof msg, "second solve: status %d, x = (%.12g, %.12g) (want (1, 1/2))", rs,
             x[0], x[1]);
    ea_test_true(rs == Solve_Succeeded, msg);
    ea_test_true(x[0] <= 1.0 && x[0] > 1.0 - 1e-8,
                 "second solve: x = 1 (row 0 at its upper limit, inside it)");
    ea_test_abs(x[1], 0.5, 1e-8, "second solve: y = 1/2");
    ea_test_abs(mg[0], 4.0, 1e-6, "second solve: row 0's multiplier 2 (3 - 1) = 4");
    snprintf(msg, sizeof msg, "rows left out: multipliers %g, %g (want 0)", mg[1], mg[2]);
    ea_test_true(mg[1] == 0.0 && mg[2] == 0.0, msg);
    ea_test_abs(mg[3], 0.0, 1e-8, "row 3 (kept, inactive): multiplier ~0");
    ea_test_true(ea__screen_grow(s, g, 1.0 - 1e-6) == 0,
                 "second solve: the rows left out strictly inside, nothing joins");
    ea__screen_free(s);
  }
  /* 2. a family kept with its row near the limit */
  {
    ea__screen_t *s = ea__screen_alloc(&p);
    double x[2] = {0.9, 0}, g[NROW];
    g_cb(2, x, TRUE, NROW, g, NULL);
    const int out = s ? ea__screen_select(s, g, 0.5, (const int[]){0, 1, 2, 0, 3}, 4) : -1;
    snprintf(msg, sizeof msg, "from (0.9, 0): %d left out (want 2: rows 1, 2), %d kept (want 3)",
             out, s ? ea__screen_rows(s) : -1);
    ea_test_true(out == 2 && ea__screen_rows(s) == 3, msg);
    /* each row its own family: row 3 (level 0.36) is left out too */
    const int out1 = s ? ea__screen_select(s, g, 0.5, NULL, 0) : -1;
    snprintf(msg, sizeof msg, "no families: %d left out (want 3)", out1);
    ea_test_true(out1 == 3, msg);
    ea__screen_all(s);
    ea_test_true(ea__screen_rows(s) == NROW, "screen_all keeps every row");
    ea__screen_free(s);
  }
  /* 3. rows out of order */
  {
    ea__screen_nlp_t q = p;
    const int jr[] = {1, 0, 2, 2, 3, 4, 4};
    q.jrow = jr;
    ea__screen_t *s = ea__screen_alloc(&q);
    ea_test_true(s == NULL, "a Jacobian not row by row is refused");
    ea__screen_free(s);
  }
  return ea_test_summary("test_plan_screen");
}
