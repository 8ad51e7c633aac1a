/* The engine strategy (planner/nlp/strategy/strategy_impl.h) against its documented decision
 * table: one row per case of the table, with the engines it names and the ones it excludes.
 * The table is the reference (docs/planner.md, "Engines", holds the same); the identity of
 * the plans themselves is bench/plan_identity.sh's. */
#include "ea_test.h"
#include "strategy_impl.h"

#include <stdio.h>

/* one row: the case (transcription, start, warm, replan, timed guess, dynamics, models, free
 * path, exact Hessian, derivative test, solver.nlp ipopt) and the engines it tries */
typedef struct {
  const char *name;
  int path, start, warm, replan, timed, dyn, models, free_path, hess, dtest, nlp_ipopt;
  int kkt_start, asn, ipm, ipm_from_cold, ipopt_monotone;
} row_t;

enum { C = EA_PLAN_COLD, W = EA_PLAN_WARM, F = EA_PLAN_FROM_TRAJ };

/* clang-format off */
static const row_t rows[] = {
  /* name                          pa st wa re ti dy mo fr he dt ni  kkt asn ipm cold mono */
  {"path cold",                     1, C, 0, 0, 1, 0, 0, 0, 1, 0, 0,   0,  0,  1,  0,   1},
  {"path plan file",                1, F, 0, 0, 1, 0, 0, 0, 1, 0, 0,   0,  0,  1,  0,   1},
  {"path warm",                     1, W, 1, 0, 1, 0, 0, 0, 1, 0, 0,   1,  1,  0,  0,   0},
  {"path replan",                   1, W, 1, 1, 1, 0, 0, 0, 1, 0, 0,   1,  1,  1,  1,   0},
  {"path replan dynamics",          1, W, 1, 1, 1, 1, 1, 0, 1, 0, 0,   1,  0,  1,  1,   0},
  {"path cold dynamics",            1, C, 0, 0, 1, 1, 1, 0, 1, 0, 0,   0,  0,  1,  0,   0},
  {"path cold nlp ipopt",           1, C, 0, 0, 1, 0, 0, 0, 1, 0, 1,   0,  0,  0,  0,   1},
  {"path warm derivative test",     1, W, 1, 0, 1, 0, 0, 0, 1, 1, 0,   0,  0,  0,  0,   0},
  {"knots cold timed",              0, C, 0, 0, 1, 0, 0, 0, 1, 0, 0,   0,  0,  1,  0,   1},
  {"knots cold untimed",            0, C, 0, 0, 0, 0, 0, 0, 1, 0, 0,   0,  0,  0,  0,   0},
  {"knots plan file",               0, F, 0, 0, 1, 0, 0, 0, 1, 0, 0,   0,  0,  1,  0,   1},
  {"knots free path",               0, C, 0, 0, 1, 0, 0, 1, 1, 0, 0,   0,  0,  0,  0,   1},
  {"knots limited-memory",          0, C, 0, 0, 1, 0, 0, 0, 0, 0, 0,   0,  0,  0,  0,   1},
  {"knots warm",                    0, W, 1, 0, 1, 0, 0, 0, 1, 0, 0,   1,  0,  0,  0,   0},
  {"knots replan",                  0, W, 1, 1, 1, 0, 0, 0, 1, 0, 0,   1,  0,  0,  0,   0},
  {"knots cold dynamics untimed",   0, C, 0, 0, 0, 1, 1, 0, 1, 0, 0,   0,  0,  1,  0,   1},
  {"knots plan file dynamics",      0, F, 0, 0, 1, 1, 1, 0, 1, 0, 0,   0,  0,  0,  0,   0},
  {"knots replan dynamics",         0, W, 1, 1, 1, 1, 1, 0, 1, 0, 0,   1,  0,  1,  1,   0},
  {"knots robust corners",          0, C, 0, 0, 1, 1, 5, 0, 1, 0, 0,   0,  0,  0,  0,   1},
  {"knots cold nlp ipopt",          0, C, 0, 0, 1, 0, 0, 0, 1, 0, 1,   0,  0,  0,  0,   1},
  {"knots cold derivative test",    0, C, 0, 0, 1, 0, 0, 0, 1, 2, 0,   0,  0,  0,  0,   1},
};
/* clang-format on */

int main(void) {
  for (size_t i = 0; i < sizeof rows / sizeof *rows; ++i) {
    const row_t *r = &rows[i];
    const ea__solve_case_t c = {.path = r->path,
                                .start = (ea_plan_start_t)r->start,
                                .warm = r->warm,
                                .replan = r->replan,
                                .guess_timed = r->timed,
                                .dynamics = r->dyn,
                                .models = r->models,
                                .free_path = r->free_path,
                                .hess_exact = r->hess,
                                .derivative_test = r->dtest,
                                .ipopt_only = r->nlp_ipopt};
    ea__strategy_t s;
    ea__plan_strategy(&c, &s);
    char what[160];
    snprintf(what, sizeof what, "%s: kkt %d asn %d ipm %d from_cold %d monotone %d (why: %s)",
             r->name, s.kkt_start, s.asn, s.ipm, s.ipm_from_cold, s.ipopt_monotone, s.why);
    ea_test_true(s.kkt_start == r->kkt_start && s.asn == r->asn && s.ipm == r->ipm &&
                     s.ipm_from_cold == r->ipm_from_cold && s.ipopt_monotone == r->ipopt_monotone,
                 what);
    ea_test_true(s.ipm == !s.why[0], what); /* a reason exactly when it is not tried */
  }
  return ea_test_summary("test_plan_strategy");
}
