/* The solve pipeline: start point, engines, the checks between the knots, the outcome. */
#include "ipopt_impl.h"
#include "dyn_impl.h"
#include "guess_impl.h"
#include "hess_impl.h"
#include "knot_impl.h"
#include "path_entry_impl.h"
#include "vib_impl.h"
#include "plan_impl.h"
#include "plan_ipm_impl.h"
#include "plan_screen_impl.h"
#include "strategy_impl.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Polish the statics of every knot (Newton on T, theta0, kappa0 at the
 * plan's L_c, alpha) so that each knot holds to the statics tolerance
 * whatever Ipopt's; the bounds are kept (a polished value outside them is
 * caught by the final check). */
static void ea__polish(ea_planner_t *pl, double *x) {
  ea_statics_settings_t set;
  ea_statics_settings_default(&set);
  set.allow_negative_tension = 1;
  set.max_cont_steps = 0;
  for (int k = 0; k < pl->N; ++k) {
    const double *gk = pl->g + 3 * k; /* Ipopt's constraint values at x */
    /* only where the final check (1e-9) needs it: a polished theta0 moves
     * the theta0 spline's accelerations by 6 dtheta0 / h^2 */
    if (fmax(fabs(gk[0]), fmax(fabs(gk[1]), fabs(gk[2]))) <= 5e-10) continue;
    const double guess[EA_NP] = {x[EA__IQ(pl, k, 1)], x[EA__IP(pl, k, 0)], x[EA__IP(pl, k, 1)],
                                 x[EA__IP(pl, k, 2)]};
    ea_statics_problem_t prob = ea_statics_problem_cable(x[EA__IQ(pl, k, 0)], guess[0]);
    ea_statics_solution_t sol;
    if (ea_statics_solve(pl->sh, &prob, &set, guess, &sol, NULL) != EA_OK ||
        sol.branch != EA_BRANCH_WARM)
      continue;
    double d = 0.0;
    for (int j = 1; j < EA_NP; ++j)
      d = fmax(d, fabs(sol.p[j] - guess[j]));
    if (d > 1e-6) continue; /* not a polish: keep Ipopt's point */
    for (int j = 1; j < EA_NP; ++j)
      x[EA__IP(pl, k, j - 1)] = sol.p[j];
  }
}

/* ---------------------------------------------------------------------- */
/* Solve                                                                    */
/* ---------------------------------------------------------------------- */

ea_status_t ea__plan_solve_once(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                                ea_plan_info_t *info_out, ea_error_t *err);

static ea_status_t ea__duration_probe(ea_planner_t *pl, ea_plan_info_t *info, ea_error_t *err);

/* Most re-solves with tightened knot bounds for limits between the knots. */
#define EA__BW_PASSES 4

/* A solve, then the limits between the knots (ea__plan_between): where one
 * is exceeded, the bounds at that interval's knots are tightened by 1.5 x
 * the excess and the plan is re-solved from itself, until every limit
 * holds (docs/planner.md, "Limits between the knots"). */
static ea_status_t ea__solve_checked(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                                     ea_plan_info_t *info_out, ea_error_t *err) {
  ea_plan_info_t local, *info = info_out ? info_out : &local;
  ea_status_t st = ea__plan_solve_once(pl, start, prev, info, err);
  if (st && !pl->has_tf && !pl->task.solver.derivative_test &&
      (info->ipopt_status == EA__IPOPT_INFEASIBLE ||
       info->ipopt_status == EA__IPOPT_RESTORATION_FAILED))
    return ea__duration_probe(pl, info, err);
  if (st || pl->task.solver.derivative_test) return st;
  int iters = info->iterations, newton = info->newton_steps, pass = 0;
  int resolves = info->screen_resolves;
  double tt = info->time_total_s, worst = -INFINITY;
  char msg[160] = "";
  for (;; ++pass) {
    const double t0 = ea__mono_s();
    const int n = ea__plan_between(pl, pl->x_sol, &worst, msg, sizeof msg);
    tt += ea__mono_s() - t0;
    if (!(worst > 0.0)) break;
    if (!n || pass == EA__BW_PASSES) {
      pl->have_solution = 0;
      info->status = EA_ERR_NOCONV;
      info->iterations = iters;
      info->newton_steps = newton;
      info->screen_resolves = resolves;
      info->time_total_s = tt;
      info->between_passes = pass;
      snprintf(info->message, sizeof info->message,
               "the planner did not converge: %s (relative %.3g) after %d re-solves with the "
               "knot bounds tightened%s",
               msg, worst, pass, n ? "; use more knots" : " (at pinned knots)");
      return ea_error_set(err, info->status, "%s", info->message);
    }
    pl->refining = 1;
    st = ea__plan_solve_once(pl, EA_PLAN_WARM, NULL, info, err);
    iters += info->iterations;
    newton += info->newton_steps;
    resolves += info->screen_resolves;
    tt += info->time_total_s;
    if (st) { /* from the tightened problem's cold guess */
      st = ea__plan_solve_once(pl, EA_PLAN_COLD, NULL, info, err);
      iters += info->iterations;
      resolves += info->screen_resolves;
      tt += info->time_total_s;
    }
    pl->refining = 0;
    if (st) {
      info->iterations = iters;
      info->newton_steps = newton;
      info->screen_resolves = resolves;
      info->time_total_s = tt;
      info->between_passes = pass + 1;
      return st;
    }
  }
  info->iterations = iters;
  info->newton_steps = newton;
  info->screen_resolves = resolves;
  info->time_total_s = tt;
  info->between_passes = pass;
  if (pass)
    snprintf(info->message, sizeof info->message,
             "plan found: duration %.6g s, %d iterations (%d re-solves for limits between the "
             "knots), min tension margin %.4g N, peak shoulder torque %.4g N m",
             info->duration_s, info->iterations, pass, info->min_tension_margin_N,
             info->peak_shoulder_torque_Nm);
  return ea_error_set(err, EA_OK, "%s", info->message);
}

/* A fixed-duration task Ipopt found (locally) infeasible: the real
 * shortfall is the duration. The same task as min_time gives the shortest
 * admissible duration under the same limits: longer than the task's ->
 * infeasible by that much; not longer -> the task is feasible and the solver
 * failed (EA_ERR_NOCONV). */
static ea_status_t ea__duration_probe(ea_planner_t *pl, ea_plan_info_t *info, ea_error_t *err) {
  ea_task_t t = pl->task;
  const double want = t.duration_s;
  t.objective = EA_TASK_MIN_TIME;
  t.duration_s = NAN;
  t.time_weight = NAN;
  ea_planner_t *pr = NULL;
  ea_plan_info_t pi;
  ea_error_t e2 = {0};
  ea_status_t st = ea_task_check(&t, &e2);
  if (!st) st = ea_planner_alloc(&t, &pr, &e2);
  if (!st) st = ea_planner_solve(pr, EA_PLAN_COLD, NULL, &pi, &e2);
  ea_planner_free(pr);
  info->time_total_s += st ? 0.0 : pi.time_total_s;
  if (st == EA_ERR_INFEASIBLE) {
    snprintf(info->message, sizeof info->message,
             "the task is infeasible for any duration: the same task in minimum time: %.400s",
             e2.msg);
    info->status = EA_ERR_INFEASIBLE;
  } else if (st) {
    return ea_error_set(err, info->status, "%s", info->message); /* keep the first verdict */
  } else if (pi.duration_s > want) {
    snprintf(info->message, sizeof info->message,
             "the task is infeasible: duration_s %.6g s is %.4g s shorter than the shortest "
             "admissible duration %.6g s under the same limits (minimum-time plan, %d knots)",
             want, pi.duration_s - want, pi.duration_s, pl->N);
    info->status = EA_ERR_INFEASIBLE;
  } else {
    snprintf(info->message, sizeof info->message,
             "the planner did not converge (Ipopt: %s after %d iterations); the task is "
             "feasible: a minimum-time plan under the same limits takes %.6g s <= duration_s "
             "%.6g s",
             info->ipopt_status_name, info->iterations, pi.duration_s, want);
    info->status = EA_ERR_NOCONV;
  }
  return ea_error_set(err, info->status, "%s", info->message);
}

ea_status_t ea_planner_solve(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                             ea_plan_info_t *info_out, ea_error_t *err) {
  if (!pl) return ea_error_set(err, EA_ERR_ARG, "ea_planner_solve: NULL planner");
  return ea__solve_checked(pl, start, prev, info_out, err);
}

/* The phases of one solve (ea__plan_solve_once): the info's defaults, the start point
 * (knot transcription), Ipopt's options for that start, Ipopt itself, and the outcome:
 * the plan accepted and kept, or the failure classified. */

/* The info's defaults and the planner's per-solve counters; returns the solve's start time. */
static double ea__solve_begin(ea_planner_t *pl, ea_plan_info_t *info) {
  memset(info, 0, sizeof *info);
  info->deriv_errors = -1;
  info->min_first_frequency_hz = info->max_modal_deflection_m = NAN;
  info->time_freq_model_s = pl->fm ? pl->fm->info.time_s : 0.0;
  info->n_var = pl->n;
  info->n_con = pl->m;
  info->nnz_jac = pl->nnz;
  info->threads = ea__pp_threads(pl);
  info->status = EA_ERR_NOCONV;
  const double t0 = ea__mono_s();
  pl->t_start = t0;
  pl->max_time = pl->task.solver.max_time_s;
  pl->t_statics = pl->t_callbacks = 0.0;
  pl->iter = 0;
  pl->info = info;
  pl->cache_val = pl->cache_sens = 0;
  return t0;
}

/* A solve that stops before its outcome (no start point, a failed path solve). */
static ea_status_t ea__solve_abort(ea_planner_t *pl, ea_plan_info_t *info,
                                   const ea__engine_result_t *res, ea_status_t st, double t0,
                                   const ea_error_t *err) {
  /* the own engines that ran before (Ipopt's status only with a plan or a failure) */
  info->newton_steps = res->newton_steps;
  info->ipm_iterations = res->ipm_iterations;
  info->ipm_fallback = res->ipm_fallback;
  info->status = st;
  snprintf(info->message, sizeof info->message, "%s", err ? err->msg : ea_strerror(st));
  info->time_total_s = ea__mono_s() - t0;
  pl->info = NULL;
  return st;
}

/* The start point in pl->x (knot transcription), inside the bounds. */
/* The last plan's multipliers as the current ones (a warm start's). */
static void ea__mult_from_sol(ea_planner_t *pl) {
  memcpy(pl->mult_g, pl->mult_g_sol, (size_t)pl->m * sizeof *pl->x);
  memcpy(pl->mult_xl, pl->mult_xl_sol, (size_t)pl->n * sizeof *pl->x);
  memcpy(pl->mult_xu, pl->mult_xu_sol, (size_t)pl->n * sizeof *pl->x);
}

static ea_status_t ea__solve_start_point(ea_planner_t *pl, ea_plan_start_t start,
                                         const ea_traj_t *prev, int warm, int replan,
                                         ea_plan_info_t *info, ea_error_t *err) {
  ea_status_t st = EA_OK;
  if (warm) {
    memcpy(pl->x, pl->x_sol, (size_t)pl->n * sizeof *pl->x);
    ea__mult_from_sol(pl);
    /* the task changed (ea_planner_update): shift the solution along */
    /* A prescribed path: the cold guess (statics along the straight
     * interpolation) proves infeasibility when the new path leaves the
     * workspace; the shifted plan alone would not (its knots can step over
     * the inadmissible part of the line). */
    if (replan && pl->task.path != EA_TASK_PATH_FREE) st = ea__plan_guess(pl, pl->x0, info, err);
    if (replan && !st) st = ea__plan_predict(pl, &pl->task_sol, pl->x, 1);
  } else if (start == EA_PLAN_FROM_TRAJ) {
    st = ea__plan_guess_traj(pl, prev, pl->x, err);
  } else {
    st = ea__plan_guess(pl, pl->x, info, err);
  }
  if (!st && !warm && start == EA_PLAN_COLD)
    ea__plan_dyn_guess(pl, pl->x); /* stretched inside its limits, modal states along it */
  else if (!st && (!warm || replan))
    ea__plan_dyn_fill(pl, pl->x); /* modal states along the guess */
  if (st) return st;
  for (int i = 0; i < pl->n; ++i)
    pl->x[i] = fmax(pl->xl[i], fmin(pl->xu[i], pl->x[i]));
  return EA_OK;
}

/* Ipopt's options for this start; with the derivative test, its output file's name in
 * tmpl ("" when none could be made). */
static void ea__solve_options(ea_planner_t *pl, int warm, int replan, char tmpl[64]) {
  ea__ipopt_start_options(pl->ip, warm, replan || pl->refining);
  if (!pl->task.solver.derivative_test) return;
  ea__deriv_test_options(pl->ip, pl->task.solver.derivative_test == 2 && pl->hess_exact == 1, tmpl);
}

static int ea__solve_ipopt_run(ea_planner_t *pl, int mono, double mono_mu, double *obj, int *iters);

/* The engines of this solve of the knot transcription (strategy/strategy_impl.h). */
static void ea__knot_strategy(const ea_planner_t *pl, ea_plan_start_t start, int warm, int replan,
                              ea__strategy_t *s) {
  const ea_task_t *t = &pl->task;
  const ea__solve_case_t c = {.path = 0,
                              .start = start,
                              .warm = warm,
                              .replan = replan,
                              .guess_timed = pl->guess_timed,
                              .dynamics = pl->rom != NULL,
                              .models = pl->M,
                              .free_path = t->path == EA_TASK_PATH_FREE,
                              .hess_exact = pl->hess_exact,
                              .derivative_test = t->solver.derivative_test,
                              .ipopt_only = (t->solver.engines == EA_PLANNER_ENGINES_IPOPT)};
  ea__plan_strategy(&c, s);
}

/* The own interior point (engine/ipm.c) on the knot transcription where the strategy tries it
 * (sg), from Ipopt's monotone mu_init, taken when it passes the KKT test of the whole problem
 * (ea__knot_kkt_ok). 1: pl->x, pl->mult_* and *obj are the plan's (*iters its iterations); 0:
 * pl->x is the start again (res->ipm_fallback when it ran). */
static int ea__solve_ipm(ea_planner_t *pl, const ea__strategy_t *sg, int warm, double mono_mu,
                         ea_plan_info_t *info, ea__engine_result_t *res, double *obj, int *iters) {
  const ea_task_t *t = &pl->task;
  const int from_cold = sg->ipm_from_cold;
  if (!sg->ipm || ea__plan_hess_pattern(pl)) return 0;
  if (!pl->kkt) {
    ea__nlp_t nlp;
    ea__knot_nlp(pl, &nlp);
    if (!(pl->kkt = ea__kkt_alloc(&nlp))) return 0;
  }
  /* with Ipopt's acceptable termination (the partial Hessian lacks the statics rows'
   * curvature: on a third of test_plan_sweep's free paths the iterates stalled with the
   * stationarity near 3e-7, where Ipopt stops by this rule), its candidate verified to
   * acc_tol; the slacks pushed as the path transcription's (transcribe/path_*.c) */
  ea__ipm_opt_t o;
  ea__plan_ipm_opt(pl, mono_mu, 1e-2, &o);
  memcpy(pl->xstart, pl->x, (size_t)pl->n * sizeof *pl->x);
  ea_error_t e = {0};
  if (from_cold && ea__solve_start_point(pl, EA_PLAN_COLD, NULL, 0, 0, info, &e)) {
    memcpy(pl->x, pl->xstart, (size_t)pl->n * sizeof *pl->x); /* no cold guess: Ipopt's start */
    return 0;
  }
  const int rc =
      ea__ipm_solve(pl->kkt, &o, pl->x, pl->mult_g, pl->mult_xl, pl->mult_xu, &res->ipm_iterations);
  const int ok = rc >= 0 && ea__knot_kkt_ok(pl, pl->x, rc ? o.acc_tol : t->solver.tol);
  res->ipm_fallback = !ok;
  if (!ok) { /* Ipopt's start again */
    memcpy(pl->x, pl->xstart, (size_t)pl->n * sizeof *pl->x);
    if (warm) ea__mult_from_sol(pl);
    return 0;
  }
  *iters = res->ipm_iterations;
  ea__knot_cb_f(pl->n, pl->x, 0, obj, pl);
  return 1;
}

/* The engines on the knot transcription from pl->x in the strategy's order
 * (strategy/strategy_impl.h): the start itself, the own interior point, Ipopt. Ipopt sees the
 * rows that can matter (engine/ipopt_screen.c): selected at the start, and if a row left out
 * reaches its limit at the solution, solved again from the start with it
 * (info->screen_resolves). Returns the status in Ipopt's codes; *obj, *iters (every attempt),
 * res's engine, interior-point fields and time [s]. */
static int ea__solve_engines(ea_planner_t *pl, ea_plan_start_t start, int warm, int replan,
                             char tmpl[64], ea_plan_info_t *info, ea__engine_result_t *res,
                             double *obj, int *iters) {
  ea__strategy_t sg;
  ea__knot_strategy(pl, start, warm, replan, &sg);
  /* Barrier strategy: from a near-optimal start (a cold guess timed along its path, or a
   * previous plan) the monotone strategy with mu_init 1e-4 needs about one linear solve per
   * iteration instead of the adaptive strategy's three, in as many or fewer iterations. If it
   * fails, the solve is repeated from the same start with the adaptive strategy, the default
   * for every other start. With dynamics (knot transcription) from a cold start, monotone from
   * mu_init 1e-3, where the adaptive strategy took more iterations or failed (docs/planner.md,
   * "Ipopt"). */
  const double mono_mu = pl->rom ? 1e-3 : 1e-4;
  int rs = EA__IPOPT_INTERNAL_ERROR;
  const double ti = ea__mono_s();
  if (sg.kkt_start && ea__knot_kkt_ok(pl, pl->x, pl->task.solver.tol)) {
    res->engine = EA__ENGINE_KKT_START;
    rs = EA__IPOPT_SOLVE_SUCCEEDED; /* the start is the solution: no Ipopt iteration */
    for (int i = 0; i < pl->n_terms; ++i)
      *obj += pl->terms[i].weight * pl->terms[i].value(pl, pl->x);
    pl->t_callbacks = ea__mono_s() - ti; /* not Ipopt's time */
  } else if (ea__solve_ipm(pl, &sg, warm, mono_mu, info, res, obj, iters)) {
    res->engine = EA__ENGINE_IPM;
    rs = EA__IPOPT_SOLVE_SUCCEEDED; /* the own interior point's plan passed the KKT test */
  } else {
    res->engine = EA__ENGINE_IPOPT;
    /* not with dynamics: an at-rest plan keeps nearly every row anyway (each family has a row
     * near its limit at the cold guess), and screening cost iterations there */
    if (pl->task.solver.derivative_test || !pl->task.solver.screen_rows || pl->rom ||
        ea__plan_eval_g(pl, pl->x, pl->g))
      ea__screen_all(pl->scr);
    else
      ea__screen_select(pl->scr, pl->g, EA__SCREEN_BAND, pl->rfam, pl->nfam);
    memcpy(pl->xstart, pl->x, (size_t)pl->n * sizeof *pl->x);
    for (int round = 0;; ++round) {
      if (round) {
        memcpy(pl->x, pl->xstart, (size_t)pl->n * sizeof *pl->x);
        if (warm) {
          ea__mult_from_sol(pl);
        }
      }
      if (ea__ipopt_create(pl)) break;
      ea__solve_options(pl, warm, replan, tmpl);
      info->ipopt_rows = ea__screen_rows(pl->scr);
      rs = ea__solve_ipopt_run(pl, sg.ipopt_monotone, mono_mu, obj, iters);
      if (!(rs == EA__IPOPT_SOLVE_SUCCEEDED || rs == EA__IPOPT_ACCEPTABLE) ||
          !ea__screen_grow(pl->scr, pl->g, EA__SCREEN_HOLD))
        break;
      info->screen_resolves++;
    }
  }
  res->time_engine_s = ea__mono_s() - ti;
  return rs;
}

/* One Ipopt solve of pl->ip from pl->x: the monotone barrier from a near-optimal start, and if
 * it fails the adaptive one from the same start. */
static int ea__solve_ipopt_run(ea_planner_t *pl, int mono, double mono_mu, double *obj,
                               int *iters) {
  int rs = EA__IPOPT_INTERNAL_ERROR;
  if (mono) memcpy(pl->x0, pl->x, (size_t)pl->n * sizeof *pl->x);
  {
    for (;;) {

      /* With dynamics from a cold start and one model the bound multipliers start at
       * mu_init / slack instead of 1 (at mu_init 1e-3 the constant 1 is far off the central
       * path): fewer iterations, the same durations. The robust plans (corner models) keep
       * 1: their first barrier phase backtracked with it. Every dynamics cold start solves
       * each barrier subproblem to 100 mu instead of 10 mu (docs/planner.md, "Ipopt"). */
      ea__ipopt_barrier_options(pl->ip, mono, mono ? mono_mu : 0.0, mono && pl->rom && pl->M == 1,
                                mono && pl->rom ? 100.0 : 10.0);
      pl->iter = 0;
      rs = ea__screen_solve(pl->scr, pl->ip, pl->x, pl->g, obj, pl->mult_g, pl->mult_xl,
                            pl->mult_xu);
      *iters += pl->iter;
      if (!mono || rs == EA__IPOPT_SOLVE_SUCCEEDED || rs == EA__IPOPT_ACCEPTABLE ||
          rs == EA__IPOPT_USER_STOP || pl->task.solver.derivative_test)
        break;
      mono = 0;
      memcpy(pl->x, pl->x0, (size_t)pl->n * sizeof *pl->x);
      ea__ipopt_barrier_options(pl->ip, 0, 0.1, 0, 10.0); /* the adaptive barrier */
    }
  }
  return rs;
}

/* A solve that did not give an admissible plan: info's status and message. Only Ipopt's
 * converged restoration phase (a local minimum of the constraint violation that is not
 * zero) says "infeasible", and only with a violation well above the solver's tolerance; a
 * failed restoration phase proves nothing (docs/planner.md). */
static void ea__solve_failure(ea_plan_info_t *info, int rs, double tol_viol) {
  const int infeasible = rs == EA__IPOPT_INFEASIBLE && info->max_violation > tol_viol;
  if (infeasible)
    info->status = EA_ERR_INFEASIBLE;
  else if (rs == EA__IPOPT_MAX_ITER)
    info->status = EA_ERR_MAXITER;
  else if (rs == EA__IPOPT_INVALID_PROBLEM || rs == EA__IPOPT_INVALID_OPTION ||
           rs == EA__IPOPT_NO_MEMORY || rs < -100)
    info->status = EA_ERR_BACKEND;
  else
    info->status = EA_ERR_NOCONV;
  if (infeasible)
    snprintf(info->message, sizeof info->message,
             "the task is locally infeasible (Ipopt: %s after %d iterations); at the point of "
             "least violation Ipopt found: %s",
             info->ipopt_status_name, info->iterations, info->worst);
  else
    snprintf(info->message, sizeof info->message,
             "the planner did not converge (Ipopt: %s after %d iterations%s); worst constraint "
             "at the last iterate: %s",
             info->ipopt_status_name, info->iterations,
             rs == EA__IPOPT_RESTORATION_FAILED || rs == EA__IPOPT_INFEASIBLE
                 ? "; not a proof that the task is infeasible"
                 : "",
             info->worst[0] ? info->worst : "none violated");
}

/* The outcome of Ipopt's run: the iterate polished and measured; an admissible plan becomes
 * the planner's solution, anything else a classified failure (info->status). */
static void ea__solve_outcome(ea_planner_t *pl, ea_plan_info_t *info,
                              const ea__engine_result_t *res, double obj, int path_mode) {
  const int rs = res->ipopt_status;
  ea__engine_result_fill(res, info);
  info->objective = obj;
  const int solved = res->solved;
  if (solved) {
    if (!path_mode) { /* path mode: theta0 and its rates are the path spline's (1e-10) */
      ea__polish(pl, pl->x);
      ea__plan_theta0_rates(pl, pl->x); /* the spline of the polished theta0 */
    }
  }
  ea__plan_stats(pl, pl->x, info);
  ea__plan_vib_stats(pl, pl->x, info);
  ea__plan_dyn_stats(pl, pl->x, info);
  info->time_freq_model_s = pl->fm ? pl->fm->info.time_s : 0.0;
  const double tol_viol = 1e-6;
  if (!(solved && info->max_violation <= tol_viol && info->max_statics_residual <= 1e-9)) {
    ea__solve_failure(info, rs, tol_viol);
    return;
  }
  info->status = EA_OK;
  memcpy(pl->x_sol, pl->x, (size_t)pl->n * sizeof *pl->x);
  memcpy(pl->mult_g_sol, pl->mult_g, (size_t)pl->m * sizeof *pl->x);
  memcpy(pl->mult_xl_sol, pl->mult_xl, (size_t)pl->n * sizeof *pl->x);
  memcpy(pl->mult_xu_sol, pl->mult_xu, (size_t)pl->n * sizeof *pl->x);
  pl->have_solution = 1;
  pl->updated = 0;
  pl->task_sol = pl->task;
  snprintf(info->message, sizeof info->message,
           "plan found: duration %.6g s, %d iterations, min tension margin %.4g N, peak "
           "shoulder torque %.4g N m",
           info->duration_s, info->iterations, info->min_tension_margin_N,
           info->peak_shoulder_torque_Nm);
}

ea_status_t ea__plan_solve_once(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                                ea_plan_info_t *info_out, ea_error_t *err) {
  ea_plan_info_t local, *info = info_out ? info_out : &local;
  const double t0 = ea__solve_begin(pl, info);
  ea_status_t st = EA_OK;
  const int path_mode = pl->pp && !pl->pp_off;
  const int warm = start == EA_PLAN_WARM && pl->have_solution;
  const int replan = warm && pl->updated;
  double obj = 0.0;
  ea__engine_result_t res = {.engine = EA__ENGINE_NONE, .ipopt_status = EA__IPOPT_INTERNAL_ERROR};
  if (path_mode) {
    /* the prescribed path in the path coordinate (transcribe/path_*.c): its own guess and Ipopt
     * problem; pl->x gets the plan in the knot layout */
    const double ti = ea__mono_s();
    st = ea__pp_solve(pl, start, prev, info, &res, &obj, err);
    res.time_engine_s = ea__mono_s() - ti - info->time_guess_s; /* its guess is timed apart */
    if (st) return ea__solve_abort(pl, info, &res, st, t0, err);
  } else {
    st = ea__solve_start_point(pl, start, prev, warm, replan, info, err);
    info->time_guess_s = ea__mono_s() - t0;
    if (st) return ea__solve_abort(pl, info, &res, st, t0, err);
    char tmpl[64] = "";
    res.ipopt_status =
        ea__solve_engines(pl, start, warm, replan, tmpl, info, &res, &obj, &res.iterations);
    res.solved =
        res.ipopt_status == EA__IPOPT_SOLVE_SUCCEEDED || res.ipopt_status == EA__IPOPT_ACCEPTABLE;
    if (tmpl[0]) {
      info->deriv_errors = ea__deriv_errors(tmpl);
      remove(tmpl);
    }
  }
  ea__solve_outcome(pl, info, &res, obj, path_mode);
  pl->cache_val = pl->cache_sens = 0;
  info->time_total_s = ea__mono_s() - t0;
  info->time_statics_s = pl->t_statics;
  info->time_ipopt_s = res.time_engine_s - pl->t_callbacks;
  info->time_rest_s =
      info->time_total_s - info->time_guess_s - info->time_statics_s - info->time_ipopt_s;
  pl->info = NULL;
  if (replan && info->status) {
    /* the shifted plan led nowhere: solve the changed task cold (its guess
     * also proves a prescribed path infeasible); both solves are counted */
    const int it = info->iterations;
    const double tw = info->time_total_s;
    st = ea__plan_solve_once(pl, EA_PLAN_COLD, NULL, info, err);
    info->iterations += it;
    info->time_total_s += tw;
    return st;
  }
  if (info->status) return ea_error_set(err, info->status, "%s", info->message);
  return ea_error_set(err, EA_OK, "%s", info->message);
}

ea_status_t ea_planner_set_terminal_modes(ea_planner_t *pl, const double *eta,
                                          const double *eta_rate, ea_error_t *err) {
  return ea_planner_set_terminal_modes_model(pl, 0, eta, eta_rate, err);
}

ea_status_t ea_planner_set_terminal_modes_model(ea_planner_t *pl, int model, const double *eta,
                                                const double *eta_rate, ea_error_t *err) {
  if (!pl) return ea_error_set(err, EA_ERR_ARG, "ea_planner_set_terminal_modes: NULL planner");
  /* at rest (residual_m 0): the state at the goal is the target; with a residual bound: the
   * bound's centre */
  if (model == 0 && (!pl->rom || pl->task.objective == EA_TASK_MIN_VIBRATION))
    return ea_error_set(err, EA_ERR_ARG,
                        "terminal modal targets need a task with dynamics that ends at rest or "
                        "within a residual bound (not min_vibration)");
  if (model != 0 &&
      (!pl->rom || model < 1 || model >= pl->M || pl->task.objective == EA_TASK_MIN_VIBRATION))
    return ea_error_set(err, EA_ERR_ARG,
                        "terminal target of model %d: the task has %d model%s (robust corners "
                        "1..4 need dynamics.robust, not min_vibration)",
                        model, pl->M, pl->M == 1 ? "" : "s");
  for (int i = 0; i < pl->Kper; ++i) { /* the model's modes */
    const double e = eta ? eta[i] : 0.0, ed = eta_rate ? eta_rate[i] : 0.0;
    if (!isfinite(e) || !isfinite(ed))
      return ea_error_set(err, EA_ERR_ARG,
                          "terminal modal target of mode %d (model %d) is not "
                          "finite",
                          i + 1, model);
  }
  for (int i = 0; i < pl->Kper; ++i) {
    const int c = model * pl->Kper + i;
    pl->dyn_target[c] = eta ? eta[i] : 0.0;
    pl->dyn_target[EA__DYN_MAX + c] = eta_rate ? eta_rate[i] : 0.0;
  }
  if (model > 0) return EA_OK; /* a corner's centre is in its row's value only */
  ea__knot_bounds(pl);
  return EA_OK;
}
