/* Private: which engine solves a plan's NLP, and the fallback chain (strategy.c).
 *
 * A transcription (transcribe/: the knots, or the path coordinate) produces one NLP
 * (engine/nlp_impl.h); this is the one place that decides which engine consumes it. The
 * engines are tried in a fixed order; each later one runs only where the earlier ones are
 * not tried or give no point that passes the KKT acceptance test (engine/kkt_test.c):
 *
 *   1. kkt-test            the start itself: a warm start (the planner's last plan, after
 *                          ea_planner_update shifted along the change) that already passes
 *                          the KKT test is the plan, no engine runs.
 *   2. active-set-newton   engine/asn.c, from the warm start with the old plan's active set
 *                          and multipliers.
 *   3. interior-point-ldl  engine/ipm.c, the planner's own primal-dual interior point (its
 *                          KKT system factored by LDL'), from the cold guess or a plan file.
 *   4. ipopt               engine/ipopt_problem.c, always last: it solves whatever the others
 *                          did not, and is the only engine that classifies a failure
 *                          (infeasible, iteration or time limit). Its barrier is monotone
 *                          from a near-optimal start, adaptive otherwise and after a failed
 *                          monotone solve.
 *
 * Decision table (ea__plan_strategy; "-" = any):
 *
 *   step               transcription  start                 other conditions
 *   kkt-test           both           warm                  no derivative test
 *   active-set-newton  path           warm                  no dynamics, no derivative test
 *   interior-point-ldl path           cold, plan file,      solver.nlp auto, no derivative test
 *                                     replan (from the
 *                                     cold guess)
 *   interior-point-ldl knots          monotone start (*),   solver.nlp auto, no derivative
 *                                     or a replan with      test, exact Hessian, not a free
 *                                     dynamics (from the    path, one model (no robust
 *                                     cold guess)           corners)
 *   ipopt              both           -                     always, after the above
 *
 * (*) a monotone start: not warm, and with dynamics a cold start; without dynamics a plan
 * file, or a cold guess timed along its path. The path transcription's Ipopt starts monotone
 * only without dynamics.
 *
 * Why these conditions: the derivative test is Ipopt's (so it runs alone); the own interior
 * point lacks a line search and the statics rows' curvature in the knot transcription's
 * partial Hessian, so on free paths and robust corner models it fails the KKT test often
 * enough to cost more than it saves; the active-set Newton gave up on every measured replan
 * with dynamics (docs/planner.md, "Engines"). Which transcription a task gets is decided
 * before (ea__pp_supported, transcribe/path_build.c). */
#ifndef EA_STRATEGY_IMPL_H
#define EA_STRATEGY_IMPL_H

#include "ea_planner.h"

/** The engines, in the order the strategy tries them. */
typedef enum ea__engine {
  EA__ENGINE_NONE = 0,  /**< none ran: the solve stopped before (e.g. no start point) */
  EA__ENGINE_KKT_START, /**< the start passed the KKT test as it was */
  EA__ENGINE_ASN,       /**< the active-set Newton (engine/asn.c) */
  EA__ENGINE_IPM,       /**< the own interior point with LDL' (engine/ipm.c) */
  EA__ENGINE_IPOPT      /**< Ipopt (engine/ipopt_problem.c) */
} ea__engine_t;

/** What the strategy needs to know of one solve. */
typedef struct ea__solve_case {
  int path;              /**< 1: the path transcription; 0: the knots */
  ea_plan_start_t start; /**< the start after the transcription's own choice (a plan file that
                              is not near this task's plan becomes EA_PLAN_COLD) */
  int warm;              /**< from the planner's last plan */
  int replan;            /**< warm, after ea_planner_update changed the task */
  int guess_timed;       /**< the cold guess is timed along its path */
  int dynamics;          /**< modal states in the NLP (task key dynamics) */
  int models;            /**< dynamic models: 0 without dynamics, 1, or 5 (robust corners) */
  int free_path;         /**< the task's path is free (knots only) */
  int hess_exact;        /**< exact Hessian (solver.hessian) */
  int derivative_test;   /**< solver.derivative_test (0 none, 1 first, 2 second order) */
  int ipopt_only;        /**< solver.nlp: ipopt (settings.engines EA_PLANNER_ENGINES_IPOPT) */
} ea__solve_case_t;

/** The engines one solve tries (ea__plan_strategy); Ipopt always comes last. */
typedef struct ea__strategy {
  int kkt_start;      /**< test the start first; passing it, no engine runs */
  int asn;            /**< then the active-set Newton */
  int ipm;            /**< then the own interior point */
  int ipm_from_cold;  /**< its start is the cold guess (a replan's; its predicted point is
                           Ipopt's start if the interior point fails) */
  int ipopt_monotone; /**< Ipopt starts with the monotone barrier (else the adaptive one) */
  const char *why;    /**< why the own interior point is not tried ("" when it is) */
} ea__strategy_t;

/** The engines for the solve c (the table above). Pure: no planner state. */
void ea__plan_strategy(const ea__solve_case_t *c, ea__strategy_t *s);

/** An engine's outcome in neutral words: which engine gave the point, whether it converged,
 *  its iterations and time. ipopt_status is Ipopt's return code when engine is
 *  EA__ENGINE_IPOPT (the only engine that classifies a failure); the plan's info shows it only
 *  then (ea__engine_result_fill: EA_PLAN_NO_IPOPT otherwise). */
typedef struct ea__engine_result {
  ea__engine_t engine;  /**< the engine that gave the final point */
  int solved;           /**< 1: converged (to its tolerance or Ipopt's acceptable level) */
  int ipopt_status;     /**< Ipopt's ApplicationReturnStatus (engine/ipopt_impl.h; the
                             success code when another engine converged) */
  int iterations;       /**< of every engine's attempt that counts (see ea_plan_info_t) */
  int newton_steps;     /**< the active-set Newton's (0: not tried) */
  int ipm_iterations;   /**< the own interior point's (0: not tried) */
  int ipm_fallback;     /**< 1: the interior point ran and Ipopt solved after it */
  double time_engine_s; /**< [s] the engines' time, callbacks included */
} ea__engine_result_t;

/** info's engine fields from r: Ipopt's status code and name (where Ipopt gave the result),
 *  iterations, steps, the interior point's iterations and fallback. */
void ea__engine_result_fill(const ea__engine_result_t *r, ea_plan_info_t *info);

#endif
