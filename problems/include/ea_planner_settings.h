/** @file ea_planner_settings.h
 *  How the planner solves (tolerances, iteration and time caps, transcription, engines,
 *  threads), apart from what it plans (ea_task_t). Plain data with a default and one
 *  validation, as OSQP's OSQPSettings. A task file's `solver:` keys load into one
 *  (ea_task_t.solver, docs/task-format.md); ea_planner_alloc plans with those,
 *  ea_planner_alloc_with with any other. Each field says which engines read it: the
 *  planner's own interior point and active-set Newton, Ipopt, or all. */
#ifndef EA_PLANNER_SETTINGS_H
#define EA_PLANNER_SETTINGS_H

#include "ea_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Which transcription plans a task (docs/planner.md, "Transcriptions"). */
typedef enum ea_task_transcription {
  EA_TASK_TRANSCRIPTION_AUTO = 0, /**< the path coordinate for line/polyline paths without a
                                       frequency model (with dynamics: one model, the own
                                       interior point), else knots */
  EA_TASK_TRANSCRIPTION_KNOTS,    /**< knots with the statics shooting rows (every task) */
  EA_TASK_TRANSCRIPTION_PATH      /**< the path coordinate (line/polyline; else refused) */
} ea_task_transcription_t;

/** Which engines may solve (task key solver.nlp; docs/planner.md, "Engines"). */
typedef enum ea_planner_engines {
  EA_PLANNER_ENGINES_AUTO = 0, /**< the planner's own engines where the strategy tries them,
                                    Ipopt for the rest (the default) */
  EA_PLANNER_ENGINES_IPOPT     /**< Ipopt for every solve */
} ea_planner_engines_t;

/** The planner's settings. */
typedef struct ea_planner_settings {
  int max_iter;          /**< iteration cap of a solve (default 500); the own interior point
                              stops at the smaller of this and 40 and hands over to Ipopt */
  double tol;            /**< dual (stationarity) tolerance of every engine's answer, the KKT
                              acceptance test's and Ipopt's tol (default 1e-8) */
  double constr_tol;     /**< constraint violation tolerance of every engine (Ipopt's
                              constr_viol_tol; default 1e-10) */
  double max_time_s;     /**< [s] wall-clock limit of a solve, every engine (default 60) */
  int derivative_test;   /**< Ipopt's derivative checker: 0 off (default), 1 first-order,
                              2 second-order; the solve then runs Ipopt alone */
  int print_level;       /**< Ipopt's output level (default 0 = silent; the own engines print
                              nothing) */
  double regularization; /**< weight of the acceleration-energy term added to min_time
                              (default 1e-4; 0 = pure minimum time) */
  int hessian_exact;     /**< Hessian of the Lagrangian: 2 "partial" (default): exact for
                              every row but without the statics curvature; 1 "exact":
                              with it (second-order statics by differences of the exact
                              sensitivities); 0 "limited-memory": Ipopt's quasi-Newton (Ipopt
                              alone then) */
  ea_task_transcription_t transcription; /**< "auto" (default), "knots" or "path" */
  int screen_rows; /**< 1 (default): limit rows whose family stays inside half its range at the
                        start are left out of Ipopt's problem (and put back if one reaches its
                        limit; docs/planner.md; not in the knot transcription with dynamics);
                        0: Ipopt sees every row */
  ea_planner_engines_t engines; /**< which engines may solve (default auto) */
  int threads; /**< threads of a plan with dynamics on a prescribed path: its rows, Jacobian
                    and Hessian in two parts by knot, the second on a worker thread (2), or
                    both in turn (1); 0 "auto" (default): 2 when the machine has two
                    processors online. The plan is the same either way. */
} ea_planner_settings_t;

/** The former name of ea_planner_settings_t (a task's solver options). */
typedef ea_planner_settings_t ea_task_solver_t;

/** The defaults (each field's comment). s not NULL. */
void ea_planner_settings_default(ea_planner_settings_t *s);

/** EA_OK, or EA_ERR_INPUT naming the field, its value and the bound it breaks; EA_ERR_ARG
 *  for s NULL. */
ea_status_t ea_planner_settings_validate(const ea_planner_settings_t *s, ea_error_t *err);

#ifdef __cplusplus
}
#endif

#endif
