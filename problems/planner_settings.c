/* The planner's settings: defaults and their one validation (ea_planner_settings.h). */
#include "ea_planner_settings.h"

#include <math.h>
#include <string.h>

void ea_planner_settings_default(ea_planner_settings_t *s) {
  memset(s, 0, sizeof *s);
  s->max_iter = 500;
  s->tol = 1e-8;
  s->constr_tol = 1e-10;
  s->max_time_s = 60.0;
  s->derivative_test = 0;
  s->print_level = 0;
  s->regularization = 1e-4;
  s->hessian_exact = 2;
  s->transcription = EA_TASK_TRANSCRIPTION_AUTO;
  s->screen_rows = 1;
  s->engines = EA_PLANNER_ENGINES_AUTO;
  s->threads = 0;
}

ea_status_t ea_planner_settings_validate(const ea_planner_settings_t *s, ea_error_t *err) {
  if (!s) return ea_error_set(err, EA_ERR_ARG, "ea_planner_settings_validate: NULL settings");
#define EA__INT_IN(f, lo, hi)                                                                      \
  if (!((long)(s->f) >= (lo) && (long)(s->f) <= (hi)))                                             \
    return ea_error_set(err, EA_ERR_INPUT,                                                         \
                        "solver options out of range: %s = %ld, not in [%ld, %ld]", #f,            \
                        (long)(s->f), (long)(lo), (long)(hi));
  EA__INT_IN(max_iter, 1, 2147483647L)
  EA__INT_IN(derivative_test, 0, 2)
  EA__INT_IN(print_level, 0, 12)
  EA__INT_IN(hessian_exact, 0, 2)
  EA__INT_IN(transcription, EA_TASK_TRANSCRIPTION_AUTO, EA_TASK_TRANSCRIPTION_PATH)
  EA__INT_IN(screen_rows, 0, 1)
  EA__INT_IN(engines, EA_PLANNER_ENGINES_AUTO, EA_PLANNER_ENGINES_IPOPT)
  EA__INT_IN(threads, 0, 2)
#undef EA__INT_IN
#define EA__POS(f)                                                                                 \
  if (!(s->f > 0) || !isfinite(s->f))                                                              \
    return ea_error_set(err, EA_ERR_INPUT, "solver options out of range: %s = %g, not > 0", #f,    \
                        s->f);
  EA__POS(tol)
  EA__POS(constr_tol)
  EA__POS(max_time_s)
#undef EA__POS
  if (!(s->regularization >= 0) || !isfinite(s->regularization))
    return ea_error_set(err, EA_ERR_INPUT,
                        "solver options out of range: regularization = %g, not >= 0",
                        s->regularization);
  return EA_OK;
}
