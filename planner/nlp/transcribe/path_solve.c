/* A solve in the path coordinate: guess, engines, replanning. */
#include "ipopt_impl.h"
#include "guess_impl.h"
#include "knot_impl.h"
#include "path_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Is pp->x (with the multipliers in pp->mult_*) a KKT point to the solver's tolerances
 * (engine/kkt_test.c)? A warm start from the planner's own solution of an unchanged problem, or
 * of one whose change left it optimal (a limit loosened that was not active), then needs no
 * engine: Ipopt would set up its algorithm and MUMPS' analysis and take one iteration. */
static int ea__pp_kkt_ok_tol(ea_planner_t *pl, double dtol) {
  ea__pp_t *pp = pl->pp;
  ea__nlp_t p;
  ea__pp_nlp(pl, &p);
  const ea__kkt_work_t w = {pp->g, pp->xx, pp->kkt_jv};
  return ea__kkt_accept(&p, pp->x, pp->mult_g, pp->mult_xl, pp->mult_xu,
                        fmax(1e-9, pl->task.solver.constr_tol), dtol, &w);
}

static int ea__pp_kkt_ok(ea_planner_t *pl) {
  return ea__pp_kkt_ok_tol(pl, pl->task.solver.tol);
}

/* A warm start solved without Ipopt: the active-set Newton (engine/asn.c) from pp->x with the old
 * plan's multipliers and active set, taken when the result passes the KKT test of the whole
 * problem (ea__pp_kkt_ok). 1: pp->x and pp->mult_* are the solution; 0: they are the start
 * again (restored from pp->x0 and the old plan's multipliers). */
/* The last plan's multipliers as the current ones (a warm start's). */
static void ea__pp_mult_from_sol(ea__pp_t *pp) {
  memcpy(pp->mult_g, pp->mult_g_sol, (size_t)pp->m * sizeof *pp->x);
  memcpy(pp->mult_xl, pp->mult_xl_sol, (size_t)pp->n * sizeof *pp->x);
  memcpy(pp->mult_xu, pp->mult_xu_sol, (size_t)pp->n * sizeof *pp->x);
}

/* The KKT system of the path NLP and the active-set Newton's workspace on it (engine/kkt.c,
 * engine/asn.c), which the interior point (engine/ipm.c) shares: 0, or -1 (out of memory). */
static int ea__pp_asn(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  if (!pp->kkt) {
    ea__nlp_t nlp;
    ea__pp_nlp(pl, &nlp);
    if (!(pp->kkt = ea__kkt_alloc(&nlp))) return -1;
  }
  if (!pp->asn && !(pp->asn = ea__asn_alloc(pp->kkt))) return -1;
  return 0;
}

/* A cold start solved without Ipopt: the interior point of engine/ipm.c from pp->x with the
 * barrier of Ipopt's cold solve (ea__pp_run: mu_init 1e-4 from the cold guess, 1e-7 from a plan
 * file that holds this task's rows), taken when its result passes the KKT test of the whole
 * problem (ea__pp_kkt_ok). 1: pp->x and pp->mult_* are the solution; 0: pp->x is the start
 * again. */
static int ea__pp_ipm_start(ea_planner_t *pl, double mu_init, int *iters) {
  ea__pp_t *pp = pl->pp;
  const ea_task_t *t = &pl->task;
  *iters = 0;
  if (ea__pp_asn(pl)) return 0;
  /* the start 1e-6 inside (Ipopt's setting here, ea__pp_ipopt), the slacks 1e-2 (Ipopt's
   * default): the rows the time-optimal guess holds at their limits give pivots too small for
   * the first solve to refine with slacks 1e-6 inside. From a plan file that holds the task's
   * rows (mu_init 1e-7) the slacks 1e-6 inside: that start is already the plan */
  ea__ipm_opt_t o;
  ea__plan_ipm_opt(pl, mu_init, mu_init < 1e-6 ? 1e-6 : 1e-2, &o);
  memcpy(pp->x0, pp->x, (size_t)pp->n * sizeof *pp->x);
  const int rc = ea__ipm_solve(pp->kkt, &o, pp->x, pp->mult_g, pp->mult_xl, pp->mult_xu, iters);
  if (rc >= 0 && ea__pp_kkt_ok_tol(pl, rc ? o.acc_tol : t->solver.tol)) return 1;
  memcpy(pp->x, pp->x0, (size_t)pp->n * sizeof *pp->x);
  return 0;
}

static int ea__pp_newton_start(ea_planner_t *pl, int *steps) {
  ea__pp_t *pp = pl->pp;
  const ea_task_t *t = &pl->task;
  *steps = 0;
  if (ea__pp_asn(pl)) return 0;
  /* the task's tolerances (ea_planner_update may change them): 0.2 of the KKT test's primal
   * one (the rows' rounding floor after the Newton is ~1.1e-10), inside a margin of that
   * tolerance; 1e-1 of its dual one */
  const ea__asn_tol_t tol = {.ptol = 0.2 * fmax(1e-9, t->solver.constr_tol),
                             .dtol = 1e-1 * t->solver.tol,
                             .margin = fmax(1e-9, t->solver.constr_tol)};
  memcpy(pp->x0, pp->x, (size_t)pp->n * sizeof *pp->x);
  if (!ea__asn_solve(pp->asn, &tol, pp->x_sol, pp->g_sol, pp->x, pp->mult_g, pp->mult_xl,
                     pp->mult_xu, steps) &&
      ea__pp_kkt_ok(pl))
    return 1;
  memcpy(pp->x, pp->x0, (size_t)pp->n * sizeof *pp->x);
  ea__pp_mult_from_sol(pp);
  return 0;
}

/* ---- solve -------------------------------------------------------------------- */

/* The cold guess (part 0) beside the interior point's preparation (part 1, ea__ipm_prepare). */
typedef struct {
  ea_planner_t *pl;
  ea_plan_info_t *info;
  ea_error_t *err;
  ea_status_t st;
} ea__pp_guess_job_t;

static ea_status_t ea__pp_cold_guess(ea_planner_t *pl, ea_plan_info_t *info, ea_error_t *err);

static void ea__pp_guess_part(void *ctx, int part) {
  ea__pp_guess_job_t *jb = ctx;
  if (part == 0)
    jb->st = ea__pp_cold_guess(jb->pl, jb->info, jb->err);
  else
    ea__ipm_prepare(jb->pl->pp->kkt); /* (failing: the solve makes the pattern again) */
}

/* The knot-layout vector xk (a guess or a previous plan) in the path layout. */
static void ea__pp_reduce(ea_planner_t *pl, const double *xk, double *xs) {
  ea__pp_t *pp = pl->pp;
  for (int k = 0; k < pl->N; ++k) {
    const int sg = pl->seg_of_knot[k];
    double q[3] = {0, 0, pl->base_fixed};
    for (int c = 0; c < pl->nq; ++c)
      q[c] = xk[EA__IQ(pl, k, c)];
    xs[EA__PS(pp, k)] = sg >= 0 ? ea__pp_sigma_of(pl, sg, q) : pp->xl[EA__PS(pp, k)];
    for (int c = 0; c < pl->nq; ++c)
      xs[EA__PR(pp, k, c)] = xk[EA__IV(pl, k, c)];
    xs[EA__PR(pp, k, pl->nq)] = xk[EA__IW(pl, k)];
    for (int i = 0; i < 2 * pl->K; ++i)
      xs[pp->ie0 + 2 * pl->K * k + i] = xk[pl->ie0 + 2 * pl->K * k + i];
  }
  if (pl->has_tf) xs[pp->itf] = xk[EA__ITF(pl)];
}

/* Ipopt's rows (engine/ipopt_screen.c, EA__SCREEN_BAND and EA__SCREEN_HOLD there;
 * docs/planner.md, "Ipopt"). */
static ea__screen_t *ea__pp_screen_alloc(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  if (!pp->rfam && !(pp->rfam = malloc(sizeof(int) * (size_t)(pp->m + 1)))) return NULL;
  pp->nfam = ea__plan_row_families(pp->rows, pp->m, pp->rfam);
  ea__nlp_t nlp;
  ea__pp_nlp(pl, &nlp);
  return ea__screen_alloc(&nlp);
}

static ea_status_t ea__pp_ipopt(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  const ea_task_t *t = &pl->task;
  ea__ipopt_free(pp->ip);
  pp->ip = ea__screen_problem(pp->scr, pp->xl, pp->xu);
  if (!pp->ip) return EA_ERR_BACKEND;
  /* the knots near a pinned point have sigma within 1e-2 of its bound: the default push
   * (1e-2) would move them by more than their distance */
  ea__ipopt_options(pp->ip, &t->solver, 1, 1e-6);
  return EA_OK;
}

/* The solution's speed along the path at each knot, sigma_dot = v . dq/dsigma / |dq/dsigma|^2
 * in the weighted coordinates (L_c [m], alpha and base [rad] times the arm length), and the
 * slopes, from the expansion of pp->x_sol (pp->dq); the segments' starts with them. */
static void ea__pp_keep_speed(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  const double w2[3] = {1.0, pl->task.arm.length * pl->task.arm.length,
                        pl->task.arm.length * pl->task.arm.length};
  for (int k = 0; k < pl->N; ++k) {
    double num = 0.0, den = 0.0;
    for (int c = 0; c < pl->nq; ++c) {
      const double d = pp->dq[6 * k + c];
      num += w2[c] * d * pp->x_sol[EA__PR(pp, k, c)];
      den += w2[c] * d * d;
    }
    pp->sd_sol[4 * k] = den > 0.0 ? num / den : 0.0;
    for (int c = 0; c < 3; ++c)
      pp->sd_sol[4 * k + 1 + c] = pp->dq[6 * k + c];
  }
  memcpy(pp->sig0_sol, pp->sig0, sizeof pp->sig0);
  memcpy(pp->vk_sol, pl->via_knot, sizeof pp->vk_sol);
}

/* The old plan's sigma and speed along the path (Hermite in time through its knots) at knot k
 * of segment j whose via knots moved: at the same fraction of the segment's time. Returns the
 * speed's factor new/old of the segment's share of t_f in *dsc. */
static void ea__pp_resample(const ea_planner_t *pl, int j, int k, double *sig, double *sd,
                            double *dsc) {
  const ea__pp_t *pp = pl->pp;
  const double *s = pl->s;
  const int n0 = pl->via_knot[j], n1 = pl->via_knot[j + 1];
  const int o0 = pp->vk_sol[j], o1 = pp->vk_sol[j + 1];
  const double dn = s[n1] - s[n0], dold = s[o1] - s[o0];
  const double tau = s[o0] + (dn > 0.0 ? (s[k] - s[n0]) / dn : 0.0) * dold;
  int i = o0;
  while (i + 1 < o1 && s[i + 1] <= tau)
    ++i;
  const int i1 = i + 1 <= o1 ? i + 1 : i;
  const double tf = pl->has_tf                       ? pp->x_sol[pp->itf]
                    : isnan(pl->task_sol.duration_s) ? pl->tf_fixed
                                                     : pl->task_sol.duration_s; /* the old t_f */
  const double h = (s[i1] - s[i]) * tf, u = h > 0.0 ? (tau - s[i]) * tf / h : 0.0;
  const double y0 = pp->x_sol[EA__PS(pp, i)], y1 = pp->x_sol[EA__PS(pp, i1)];
  const double d0 = pp->sd_sol[4 * i], d1 = pp->sd_sol[4 * i1];
  double dy = d0;
  *sig = h > 0.0 ? ea__herm(h, y0, d0, y1, d1, u, &dy) : y0;
  *sd = dy;
  *dsc = dn > 0.0 ? dold / dn : 1.0;
}

/* Replanning predictor of the path transcription (the task changed, the structure did not):
 * every knot keeps its fraction of its segment and its speed along the path, scaled with the
 * segment's length (a stretched segment is run through in the same time); its rates change
 * with the path's slopes times that speed (the old rates where the path did not change), so
 * the knots lie on the new path and the C2 rows the old plan held hold up to the change of
 * the path's curvature (the knot predictor's affine shift,
 * mapped onto the path, missed them by up to 1.45 m/s^2 after a 5 mm goal move). min_time:
 * re-timed as the knot predictor does (ea__plan_retime); theta0's rates from its spline. */
void ea__pp_predict(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  const int N = pl->N, nq = pl->nq;
  double *x = pp->x, *xk = pp->xk;
  memcpy(x, pp->x_sol, sizeof(double) * (size_t)pp->n);
  const int moved = memcmp(pp->vk_sol, pl->via_knot, sizeof pp->vk_sol) != 0;
  double *sdn = pp->x0; /* scratch: the new speed along the path (or the stretch) */
  for (int j = 0; j < pl->n_seg; ++j) {
    const double lo = pp->sig0_sol[j + 1] - pp->sig0_sol[j], ln = pp->sig0[j + 1] - pp->sig0[j];
    const double r = lo > 0.0 ? ln / lo : 1.0;
    for (int k = pl->via_knot[j]; k <= pl->via_knot[j + 1]; ++k) {
      double so = pp->x_sol[EA__PS(pp, k)], sd = 0.0, dsc = 1.0;
      if (moved) ea__pp_resample(pl, j, k, &so, &sd, &dsc);
      x[EA__PS(pp, k)] =
          fmax(pp->xl[EA__PS(pp, k)],
               fmin(pp->xu[EA__PS(pp, k)], pp->sig0[j] + (so - pp->sig0_sol[j]) * r));
      sdn[k] = moved ? sd * r * dsc : r;
    }
  }
  memset(pp->xs_last, 0xff, sizeof(double) * (size_t)pp->n);
  ea__pp_expand(pl, x); /* the new slopes at the new sigma_k */
  /* rates: the new slopes times the new speed; with the via knots kept,
   * r (v + (dq_new - dq_old) sigma_dot), the old rates exactly where nothing moved */
  for (int k = 0; k < N; ++k)
    for (int c = 0; c < nq; ++c)
      x[EA__PR(pp, k, c)] =
          moved ? pp->dq[6 * k + c] * sdn[k]
                : sdn[k] * (pp->x_sol[EA__PR(pp, k, c)] +
                            (pp->dq[6 * k + c] - pp->sd_sol[4 * k + 1 + c]) * pp->sd_sol[4 * k]);
  memset(pp->xs_last, 0xff, sizeof(double) * (size_t)pp->n);
  ea__pp_expand(pl, x);
  if (pl->has_tf && pl->task.objective == EA_TASK_MIN_TIME) {
    /* xk re-timed in place; x the same (xk's rates are x's: no new expansion) */
    const double lam = ea__plan_retime(pl, xk);
    x[pp->itf] = xk[EA__ITF(pl)];
    for (int k = 0; k < N; ++k)
      for (int c = 0; c < nq; ++c)
        x[EA__PR(pp, k, c)] /= lam;
  }
  ea__plan_theta0_rates(pl, xk);
  for (int k = 0; k < N; ++k)
    x[EA__PR(pp, k, nq)] = xk[EA__IW(pl, k)];
}

/* Largest violation of the path problem's rows at pp->x (absolute, unscaled). */
static double ea__pp_violation(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  if (!ea__pp_cb_g(pp->n, pp->x, 1, pp->m, pp->g, pl)) return INFINITY;
  double v = 0.0;
  for (int i = 0; i < pp->m; ++i) {
    if (!isfinite(pp->g[i])) return INFINITY;
    v = fmax(v, fmax(pp->gl[i] - pp->g[i], pp->g[i] - pp->gu[i]));
  }
  return v;
}

/* Do two tasks' limit values differ (every speed, acceleration, tension, torque, length and
 * frequency limit and the margin)? */
static int ea__pp_limits_differ(const ea_task_limits_t *a, const ea_task_limits_t *b) {
  const double va[] = {a->tension_min,
                       a->tension_max,
                       a->cable_length_min,
                       a->cable_length_max,
                       a->cable_speed_max,
                       a->cable_accel_max,
                       a->cable_angle_speed_max,
                       a->cable_angle_accel_max,
                       a->shoulder_torque_max,
                       a->shoulder_speed_max,
                       a->base_speed_max,
                       a->base_accel_max,
                       a->min_first_frequency_hz,
                       a->max_modal_deflection_m,
                       a->resample_margin};
  const double vb[] = {b->tension_min,
                       b->tension_max,
                       b->cable_length_min,
                       b->cable_length_max,
                       b->cable_speed_max,
                       b->cable_accel_max,
                       b->cable_angle_speed_max,
                       b->cable_angle_accel_max,
                       b->shoulder_torque_max,
                       b->shoulder_speed_max,
                       b->base_speed_max,
                       b->base_accel_max,
                       b->min_first_frequency_hz,
                       b->max_modal_deflection_m,
                       b->resample_margin};
  for (size_t i = 0; i < sizeof va / sizeof *va; ++i)
    if (!(va[i] == vb[i])) return 1;
  return 0;
}

ea_status_t ea__pp_update(ea_planner_t *pl, ea_error_t *err) {
  if (!pl->pp) return EA_OK;
  ea__pp_t *pp = pl->pp;
  ea__pp_path(pl);
  ea_error_t e = {0};
  pp->path_status = ea__pp_build_splines(pl, &e);
  snprintf(pp->path_msg, sizeof pp->path_msg, "%s", e.msg);
  if (pp->path_status && pp->path_status != EA_ERR_INFEASIBLE)
    return ea_error_set(err, pp->path_status, "%s", e.msg);
  memset(pl->pp->xs_last, 0xff, sizeof(double) * (size_t)pl->pp->n);
  ea__pp_bounds(pl);
  return EA_OK;
}

/* The cold guess (timed along the path, modal states along it) as the path vector pp->x,
 * inside its bounds. */
static ea_status_t ea__pp_cold_guess(ea_planner_t *pl, ea_plan_info_t *info, ea_error_t *err) {
  ea__pp_t *pp = pl->pp;
  const ea_status_t st = ea__plan_guess(pl, pl->x, info, err);
  if (st) return st;
  ea__plan_dyn_guess(pl, pl->x);
  ea__pp_reduce(pl, pl->x, pp->x);
  for (int i = 0; i < pp->n; ++i)
    pp->x[i] = fmax(pp->xl[i], fmin(pp->xu[i], pp->x[i]));
  return EA_OK;
}

/* One Ipopt solve of the problem just created (ea__pp_ipopt) from pp->x with the start's
 * options: a timed cold guess or a plan file's plan with the monotone barrier, and if that
 * fails the adaptive one from the same start. The derivative checker's output goes to tmpl
 * (NULL: no check). */
static void ea__pp_run(ea_planner_t *pl, int warm, int replan, int mono, int traj_exact, char *tmpl,
                       int *rs, double *obj, int *iters) {
  ea__pp_t *pp = pl->pp;
  ea__ipopt_start_options(pp->ip, warm, replan || pl->refining);
  if (tmpl && pl->task.solver.derivative_test)
    ea__deriv_test_options(pp->ip, pl->task.solver.derivative_test == 2, tmpl);
  if (mono) memcpy(pp->x0, pp->x, (size_t)pp->n * sizeof *pp->x);
  for (;;) {
    ea__ipopt_barrier_options(pp->ip, mono, mono ? (traj_exact ? 1e-7 : 1e-4) : 0.0, 0, 10.0);
    pp->iter = 0;
    *rs =
        ea__screen_solve(pp->scr, pp->ip, pp->x, pp->g, obj, pp->mult_g, pp->mult_xl, pp->mult_xu);
    *iters += pp->iter;
    if (!mono || *rs == EA__IPOPT_SOLVE_SUCCEEDED || *rs == EA__IPOPT_ACCEPTABLE ||
        *rs == EA__IPOPT_USER_STOP)
      break;
    mono = 0;
    memcpy(pp->x, pp->x0, (size_t)pp->n * sizeof *pp->x);
    ea__ipopt_barrier_options(pp->ip, 0, 0.1, 0, 10.0); /* the adaptive barrier */
  }
}

/* The engines of this solve in the path coordinate (strategy/strategy_impl.h). */
static void ea__pp_strategy(const ea_planner_t *pl, ea_plan_start_t start, int warm, int replan,
                            ea__strategy_t *s) {
  const ea_task_t *t = &pl->task;
  const ea__solve_case_t c = {.path = 1,
                              .start = start,
                              .warm = warm,
                              .replan = replan,
                              .guess_timed = pl->guess_timed,
                              .dynamics = pl->K > 0,
                              .models = pl->M,
                              .free_path = 0,
                              .hess_exact = pl->hess_exact,
                              .derivative_test = t->solver.derivative_test,
                              .ipopt_only = (t->solver.engines == EA_PLANNER_ENGINES_IPOPT)};
  ea__plan_strategy(&c, s);
}

/* The engines before Ipopt (the strategy's sg): the start itself, the active-set Newton, the
 * own interior point. *at_solution (in: the old plan passed the KKT test under the new
 * limits) 1 when one of them gave the plan (res->engine); otherwise pp->x and the multipliers
 * are Ipopt's start. */
static ea_status_t ea__pp_own_engines(ea_planner_t *pl, const ea__strategy_t *sg, int traj_exact,
                                      ea_plan_info_t *info, ea__engine_result_t *res,
                                      int *at_solution, ea_error_t *err) {
  ea__pp_t *pp = pl->pp;
  if (*at_solution) res->engine = EA__ENGINE_KKT_START; /* the old plan under the new limits */
  if (!*at_solution && sg->kkt_start && ea__pp_kkt_ok(pl)) {
    *at_solution = 1; /* the predicted point is already the solution */
    res->engine = EA__ENGINE_KKT_START;
  }
  if (!*at_solution && sg->asn) {
    *at_solution = ea__pp_newton_start(pl, &res->newton_steps);
    if (*at_solution) res->engine = EA__ENGINE_ASN;
  }
  /* a cold solve, or a replan the active-set Newton gave up: the own interior point */
  if (!*at_solution && sg->ipm) {
    if (sg->ipm_from_cold) {
      memcpy(pp->xstart, pp->x, (size_t)pp->n * sizeof *pp->x); /* the predicted point */
      const ea_status_t st = ea__pp_cold_guess(pl, info, err);
      if (st) return st;
    }
    /* the barrier's start as Ipopt's (ea__pp_run; with dynamics the knot transcription's) */
    *at_solution = ea__pp_ipm_start(pl,
                                    traj_exact ? 1e-7
                                    : pl->rom  ? 1e-3
                                               : 1e-4,
                                    &res->ipm_iterations);
    res->ipm_fallback = !*at_solution;
    if (*at_solution) {
      res->iterations = res->ipm_iterations;
      res->engine = EA__ENGINE_IPM;
    }
    if (!*at_solution &&
        sg->ipm_from_cold) { /* Ipopt's warm start: the predicted point, the multipliers */
      memcpy(pp->x, pp->xstart, (size_t)pp->n * sizeof *pp->x);
      ea__pp_mult_from_sol(pp);
    }
  }
  return EA_OK;
}

/* Ipopt on the path NLP from pp->x, its rows screened (engine/ipopt_screen.c): the limit rows
 * whose family stays in the inner half of its range at the start are left out; a solution at
 * which one of them reaches its limit is solved again from the same start with it in. *rs:
 * Ipopt's return code; tmpl: the derivative checker's file (ea__pp_run). */
static ea_status_t ea__pp_solve_ipopt(ea_planner_t *pl, const ea__strategy_t *sg, int warm,
                                      int replan, int traj_exact, char tmpl[64],
                                      ea_plan_info_t *info, int *rs, double *obj, int *iters,
                                      ea_error_t *err) {
  ea__pp_t *pp = pl->pp;
  /* the rows Ipopt sees (engine/ipopt_screen.c): the limit rows whose family stays in the inner
   * half of its range at the start are left out; a solution at which one of them reaches its
   * limit is solved again from the same start with it in */
  if (!pp->scr && !(pp->scr = ea__pp_screen_alloc(pl)))
    return ea_error_set(err, EA_ERR_NOMEM, "out of memory (path transcription)");
  if (pl->task.solver.derivative_test || !pl->task.solver.screen_rows ||
      !ea__pp_cb_g(pp->n, pp->x, 1, pp->m, pp->g, pl))
    ea__screen_all(pp->scr);
  else
    ea__screen_select(pp->scr, pp->g, EA__SCREEN_BAND, pp->rfam, pp->nfam);
  memcpy(pp->xstart, pp->x, (size_t)pp->n * sizeof *pp->x);
  for (int round = 0;; ++round) {
    if (round) {
      memcpy(pp->x, pp->xstart, (size_t)pp->n * sizeof *pp->x);
      if (warm) {
        ea__pp_mult_from_sol(pp);
      }
    }
    const ea_status_t st = ea__pp_ipopt(pl);
    if (st) return ea_error_set(err, st, "Ipopt: cannot create the path problem");
    info->ipopt_rows = ea__screen_rows(pp->scr);
    ea__pp_run(pl, warm, replan, sg->ipopt_monotone, traj_exact, round ? NULL : tmpl, rs, obj,
               iters);
    if (!(*rs == EA__IPOPT_SOLVE_SUCCEEDED || *rs == EA__IPOPT_ACCEPTABLE)) break;
    if (!ea__screen_grow(pp->scr, pp->g, EA__SCREEN_HOLD)) break;
    info->screen_resolves++;
  }
  return EA_OK;
}

/* After the engines: the solution kept (res->solved from res->ipopt_status), the plan
 * expanded to the knot layout into pl->x and the knot planner's rows at it into pl->g. */
static ea_status_t ea__pp_finish(ea_planner_t *pl, ea__engine_result_t *res) {
  ea__pp_t *pp = pl->pp;
  const int rs = res->ipopt_status;
  res->solved = rs == EA__IPOPT_SOLVE_SUCCEEDED || rs == EA__IPOPT_ACCEPTABLE;
  if (res->solved) {
    memcpy(pp->x_sol, pp->x, (size_t)pp->n * sizeof *pp->x);
    memcpy(pp->mult_g_sol, pp->mult_g, (size_t)pp->m * sizeof *pp->x);
    memcpy(pp->mult_xl_sol, pp->mult_xl, (size_t)pp->n * sizeof *pp->x);
    memcpy(pp->mult_xu_sol, pp->mult_xu, (size_t)pp->n * sizeof *pp->x);
    memcpy(pp->g_sol, pp->g, (size_t)pp->m * sizeof *pp->x);
    pp->have_solution = 1;
  }
  /* the plan in the knot layout; the knot planner's rows at it (statics rows: the splines'
   * 1e-9, path rows exact) */
  memset(pp->xs_last, 0xff, sizeof(double) * (size_t)pp->n);
  ea__pp_expand(pl, pp->x);
  if (res->solved) ea__pp_keep_speed(pl);
  memcpy(pl->x, pp->xk, (size_t)pl->n * sizeof *pl->x);
  memset(pl->mult_g, 0, (size_t)pl->m * sizeof *pl->mult_g);
  memset(pl->mult_xl, 0, (size_t)pl->n * sizeof *pl->mult_xl);
  memset(pl->mult_xu, 0, (size_t)pl->n * sizeof *pl->mult_xu);
  pl->cache_val = pl->cache_sens = 0;
  const double te = ea__mono_s(); /* not Ipopt's time (its statics shots are counted) */
  /* the tip states only (the limits between the knots take the statics' rates from the
   * splines' partials, ea__pp_statics_rates): a shot without sensitivities costs ~0.45 of one
   * with them */
  const ea_status_t se = ea__plan_eval_g_values(pl, pl->x, pl->g);
  pl->t_callbacks += ea__mono_s() - te;
  return se;
}

ea_status_t ea__pp_solve(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                         ea_plan_info_t *info, ea__engine_result_t *res, double *obj,
                         ea_error_t *err) {
  ea__pp_t *pp = pl->pp;
  int rs = EA__IPOPT_INTERNAL_ERROR;
  int *iters = &res->iterations;
  const double t0 = ea__mono_s();
  if (pp->path_status)
    return ea_error_set(err, pp->path_status, "infeasible task: %s", pp->path_msg);
  /* A replan whose limits changed is a cold plan, from the cold guess (timed time-optimally
   * along the path under the new limits), unless the old plan is still a KKT point: the old
   * plan re-timed into them took more iterations, the old active set's multipliers being
   * wrong. */
  const int limits_changed = start == EA_PLAN_WARM && pp->have_solution && pl->updated &&
                             ea__pp_limits_differ(&pl->task.limits, &pl->task_sol.limits);
  int warm = start == EA_PLAN_WARM && pp->have_solution;
  int replan = warm && pl->updated;
  ea__pp_bounds(pl);
  ea_status_t st = EA_OK;
  if (warm) {
    memcpy(pp->x, pp->x_sol, (size_t)pp->n * sizeof *pp->x);
    ea__pp_mult_from_sol(pp);
    if (replan && !limits_changed) ea__pp_predict(pl); /* the task changed */
  }
  ea__strategy_t sg;
  ea__pp_strategy(pl, start, warm, replan, &sg);
  int at_solution = 0; /* the old plan under the new limits */
  if (limits_changed && sg.kkt_start) at_solution = ea__pp_kkt_ok(pl);
  if (limits_changed && !at_solution) {
    start = EA_PLAN_COLD;
    warm = replan = 0;
  }
  /* A previous plan (EA_PLAN_FROM_TRAJ) without dynamics: if it holds this task's rows to
   * 1e-6 it is (nearly) this task's plan, and the barrier starts at 1e-7; otherwise the cold
   * guess, timed along this path, is the better start (docs/planner.md, "Initial guess"). */
  int traj_exact = 0;
  if (!warm && start == EA_PLAN_FROM_TRAJ && !pl->rom) {
    if ((st = ea__plan_guess_traj(pl, prev, pl->x, err))) return st;
    ea__plan_dyn_fill(pl, pl->x);
    ea__pp_reduce(pl, pl->x, pp->x);
    for (int i = 0; i < pp->n; ++i)
      pp->x[i] = fmax(pp->xl[i], fmin(pp->xu[i], pp->x[i]));
    traj_exact = ea__pp_violation(pl) <= 1e-6;
    if (!traj_exact) start = EA_PLAN_COLD;
  }
  ea__pp_strategy(pl, start, warm, replan, &sg); /* the start as the solve takes it */
  if (!warm && !traj_exact) {
    if (start == EA_PLAN_FROM_TRAJ) {
      if ((st = ea__plan_guess_traj(pl, prev, pl->x, err))) return st;
      ea__plan_dyn_fill(pl, pl->x);
      ea__pp_reduce(pl, pl->x, pp->x);
    } else if (pp->par && sg.ipm && !ea__pp_asn(pl)) {
      /* a cold solve by the own interior point with a worker: its KKT pattern and ordering
       * (engine/ipm.c) there while the cold guess is made here */
      ea__pp_guess_job_t jb = {pl, info, err, EA_OK};
      ea__par_run(pp->par, ea__pp_guess_part, &jb);
      if ((st = jb.st)) return st;
    } else if ((st = ea__pp_cold_guess(pl, info, err))) {
      return st;
    }
  }
  info->time_guess_s = ea__mono_s() - t0;
  /* again with the guess made: Ipopt's monotone start needs a guess timed along the path */
  ea__pp_strategy(pl, start, warm, replan, &sg);
  for (int i = 0; i < pp->n; ++i)
    pp->x[i] = fmax(pp->xl[i], fmin(pp->xu[i], pp->x[i]));
  *iters = 0;
  char tmpl[64] = "";
  if ((st = ea__pp_own_engines(pl, &sg, traj_exact, info, res, &at_solution, err))) return st;
  if (at_solution) {
    rs = EA__IPOPT_SOLVE_SUCCEEDED; /* the start is the solution: no Ipopt problem, no iteration */
    ea__pp_cb_f(pp->n, pp->x, 0, obj, pl);
  } else {
    res->engine = EA__ENGINE_IPOPT;
    if ((st = ea__pp_solve_ipopt(pl, &sg, warm, replan, traj_exact, tmpl, info, &rs, obj, iters,
                                 err)))
      return st;
  }
  if (tmpl[0]) {
    info->deriv_errors = ea__deriv_errors(tmpl);
    remove(tmpl);
  }
  res->ipopt_status = (int)rs;
  return ea__pp_finish(pl, res);
}
