/* FE-in-the-loop refinement of a plan that arrives at rest (docs/planner.md, "Refinement
 * against the FE transient" and "Robust rest").
 *
 * Parameters: for each refined model j (the nominal; with dynamics.robust also the four
 * corners) and each adjusted mode i the tip amplitudes (a_i, b_i) [m] of the free vibration
 * a_i cos(w_i t) + b_i sin(w_i t) (along the mode's tip direction u_i, t from the end of the
 * motion) that model j predicts after the motion from its terminal target
 *   eta_i = a_i / |tip_i|,  eta_i' = b_i w_i / |tip_i|
 * (tip_i, w_i: model j's tip displacement per unit eta_i and frequency at the goal): the
 * nominal's terminal state (ea_planner_set_terminal_modes), a corner's centre, within robust
 * residual_m of which its terminal state must end (ea_planner_set_terminal_modes_model).
 * Each evaluation re-plans warm with those targets and runs the FE transient of the plan at
 * every model's arm (the task's arm with the model's tip mass and EI; ea_traj_simulate); the
 * FE tip residual after the motion is fitted, by linear least squares, with the free
 * vibration of every mode of that model,
 *   r(t) = sum_i u_i (A_i cos w_i t + B_i sin w_i t),
 * and (A_i, B_i) are the "fitted" amplitudes; (P_i, Q_i), "predicted", are those of the
 * model's own terminal state in the plan (the nominal's: its target). The model error
 * D = (A, B) - (P, Q) is what the model misses; the targets z cancel it where
 *   F(z) = D(z) + z = 0,
 * i.e. the nominal's FE residual is zero and a corner's is its model state about its centre,
 * within robust residual_m. The model says D does not depend on z (Jacobian of F: I); the
 * FE's answer differs by a few percent (nonlinearity), which the Newton method's Broyden
 * update learns. For the nominal alone (P, Q) = z and F = (A, B). The NLopt methods minimise
 * |F|^2 from the first Newton step. Every method stops at the first evaluation whose FE
 * residual peak is within its bound at every model's arm (the nominal: tolerance_m; a
 * corner: robust residual_m + tolerance_m). */
#include "ea_refine.h"
#include "dyn_impl.h"
#include "plan_impl.h"

#include <math.h>
#include <nlopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define EA__RP EA_REFINE_MAX_PARAMS /* most parameters */
#define EA__RM EA_REFINE_MAX_MODELS

typedef struct {
  ea_planner_t *pl;
  const ea_task_t *task;
  ea_refine_info_t *info;
  ea_task_refine_t s;
  int K, m, M, n;                     /* model modes, adjusted modes, models, parameters (2 m M) */
  double w[EA__RM][EA_ROM_MAX_MODES]; /* [rad/s] model frequencies at the goal */
  double tipn[EA__RM][EA_ROM_MAX_MODES]; /* |tip_i| [m per unit eta] */
  double u[EA__RM][EA_ROM_MAX_MODES][2]; /* tip directions */
  ea_arm_t arm[EA__RM];                  /* each model's FE arm */
  double t0;                             /* start of the refinement */
  double last_eval_s;                    /* wall time of the last evaluation */
  int held;                              /* evaluation whose plan the planner holds (-1: unknown) */
  ea_plan_info_t held_info;              /* its solve info */
  ea_traj_t tr;                          /* scratch trajectory */
  int best;                              /* accepted evaluation of least score (-1: none) */
  const char *stop;                      /* why the search stopped (NULL: not yet) */
  nlopt_opt opt;                         /* NLopt run (NULL: Newton) */
  double nl_scale;                       /* [m] NLopt variable unit */
  double nl_z0[EA__RP];                  /* NLopt variables are (z - z0) / nl_scale */
  double penalty;                        /* NLopt objective of a rejected candidate */
  char fe_msg[512];                      /* the last failed FE transient's message */
  ea_romnl_t *nl;                        /* the nonlinear reduced model (settings.by not fe) */
  int nl_sampled;                        /* its coefficients are on a path */
  double nl_dist0; /* [m] the sampled plan's own distance from its samples' polyline */
  int by_model;    /* 1: evaluations integrate it, not the FE transient */
} ea__refine_t;

/* The nonlinear reduced model's loop: its coefficients at EA_ROMNL_SAMPLES points of the plan's
 * path, sampled again when a candidate's path leaves theirs by more than EA__NL_PATH_M [m]; RK4
 * steps of EA__NL_DT [s] (docs/fe.md, "The nonlinear reduced model in the library"); the loop
 * stops when the model's residual peak is within EA__NL_TOL of the tolerance at rest,
 * EA__NL_BOUND of a residual bound (the model then leaves the FE to its own error). */
#define EA__NL_PATH_M 1e-3
#define EA__NL_DT 2e-4
#define EA__NL_TOL 0.1
#define EA__NL_BOUND 0.9

/* Solve the n x n system A x = b (row-major A, destroyed) by Gaussian elimination with
 * partial pivoting; 0 on success, 1 if singular. */
static int ea__rsolve(int n, double *A, double *b, double *x) {
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (fabs(A[r * n + c]) > fabs(A[p * n + c])) p = r;
    if (!(fabs(A[p * n + c]) > 1e-300)) return 1;
    if (p != c) {
      for (int j = 0; j < n; ++j) {
        const double t = A[c * n + j];
        A[c * n + j] = A[p * n + j];
        A[p * n + j] = t;
      }
      const double t = b[c];
      b[c] = b[p];
      b[p] = t;
    }
    for (int r = c + 1; r < n; ++r) {
      const double f = A[r * n + c] / A[c * n + c];
      for (int j = c; j < n; ++j)
        A[r * n + j] -= f * A[c * n + j];
      b[r] -= f * b[c];
    }
  }
  for (int r = n - 1; r >= 0; --r) {
    double v = b[r];
    for (int j = r + 1; j < n; ++j)
      v -= A[r * n + j] * x[j];
    x[r] = v / A[r * n + r];
  }
  return 0;
}

/* Fit the FE residual of model j's arm after the motion (history rows t >= duration, about the
 * final equilibrium) with model j's K modes: out[2i] (cos), out[2i+1] (sin) [m]. */
static int ea__refine_fit(const ea__refine_t *R, int j, const ea_sim_history_t *h,
                          const ea_sim_info_t *si, double *out) {
  const int np = 2 * R->K;
  double N[4 * EA_ROM_MAX_MODES * EA_ROM_MAX_MODES] = {0}, rhs[2 * EA_ROM_MAX_MODES] = {0};
  int rows = 0;
  for (int r = 0; r < h->rows; ++r) {
    const double *row = h->data + 6 * (size_t)r;
    if (row[0] < si->duration) continue;
    const double tau = row[0] - si->duration;
    for (int d = 0; d < 2; ++d) {
      double a[2 * EA_ROM_MAX_MODES];
      for (int i = 0; i < R->K; ++i) {
        a[2 * i] = R->u[j][i][d] * cos(R->w[j][i] * tau);
        a[2 * i + 1] = R->u[j][i][d] * sin(R->w[j][i] * tau);
      }
      const double y = row[1 + d] - si->final_static_tip[d];
      for (int p = 0; p < np; ++p) {
        rhs[p] += a[p] * y;
        for (int q = 0; q < np; ++q)
          N[p * np + q] += a[p] * a[q];
      }
    }
    ++rows;
  }
  if (rows < 2 * np) return 1;
  return ea__rsolve(np, N, rhs, out);
}

/* The Newton residual F = fitted - predicted + z over the adjusted modes of every model (n). */
static void ea__refine_F(const ea__refine_t *R, const ea_refine_eval_t *e, double *F) {
  for (int j = 0; j < R->M; ++j)
    for (int q = 0; q < 2 * R->m; ++q) {
      const int p = j * 2 * R->m + q, o = j * 2 * R->K + q;
      F[p] = e->fitted_m[o] - e->predicted_m[o] + e->params_m[p];
    }
}

static double ea__rnorm(const ea__refine_t *R, const double *F) {
  double s = 0.0;
  for (int p = 0; p < R->n; ++p)
    s += F[p] * F[p];
  return sqrt(s);
}

/* Is the search over before the next evaluation? Sets R->stop. */
static int ea__refine_budget(ea__refine_t *R) {
  if (R->stop) return 1;
  if (R->info->n_evals >= R->s.max_evaluations) {
    R->stop = "max_evaluations";
    return 1;
  }
  if (ea__mono_s() - R->t0 + R->last_eval_s > R->s.max_time_s) {
    R->stop = "max_time";
    return 1;
  }
  return 0;
}

/* The FE transients of the held plan (R->tr) at every model's arm, fitted; into e. capped: each
 * transient stops where the refinement's time runs out (max_time_s), the first evaluation's
 * too (a small fe_dt_s makes one transient cost more than the whole budget). */
static void ea__refine_fe(ea__refine_t *R, ea_refine_eval_t *e, int capped) {
  ea_refine_info_t *info = R->info;
  const double tf = ea__mono_s();
  e->fe_status = EA_OK;
  e->score = 0.0;
  for (int j = 0; j < R->M && !e->fe_status; ++j) {
    ea_sim_history_t h = {0};
    ea_sim_info_t si;
    ea_error_t err = {0};
    ea_sim_settings_t fe = info->fe;
    if (capped) fe.max_wall_s = fmax(R->t0 + R->s.max_time_s - ea__mono_s(), 1e-3);
    /* the nominal: the arm's hand plus the trajectory's payload, as the planner's */
    const double tm = j ? info->model_tip_mass_kg[j] : -1.0;
    e->fe_status = ea_traj_simulate(&R->arm[j], &R->tr, tm, &fe, &h, &si, &err);
    if (e->fe_status) snprintf(R->fe_msg, sizeof R->fe_msg, "%.500s", err.msg);
    if (e->fe_status == EA_ERR_INTERRUPTED && capped) R->stop = "max_time";
    if (!e->fe_status) {
      e->model_residual_peak_m[j] = si.residual_peak;
      e->model_residual_rms_m[j] = si.residual_rms;
      e->score = fmax(e->score, si.residual_peak / info->allowed_m[j]);
      if (ea__refine_fit(R, j, &h, &si, e->fitted_m + 2 * R->K * j))
        for (int p = 0; p < 2 * R->K; ++p)
          e->fitted_m[2 * R->K * j + p] = NAN;
    }
    ea_sim_history_free(&h);
  }
  if (e->fe_status) e->score = NAN;
  e->residual_peak_m = e->model_residual_peak_m[0];
  e->residual_rms_m = e->model_residual_rms_m[0];
  e->fe_time_s = ea__mono_s() - tf;
  info->time_fe_s += e->fe_time_s;
}

/* The nonlinear reduced model along the held plan (R->tr), in place of the FE transient: its
 * modal state at the goal is the fitted amplitudes (the model's own coordinates are the
 * table's), its free vibration's peak the residual; into e. The coefficients are sampled on the
 * plan's path once and again only when a candidate leaves it (by EA__NL_PATH_M more than the
 * sampled plan itself, whose curve leaves the chords between its samples). */
static void ea__refine_model(ea__refine_t *R, ea_refine_eval_t *e) {
  ea_refine_info_t *info = R->info;
  const double tm = ea__mono_s();
  const ea_rom_table_t *tb = ea_planner_rom_table(R->pl);
  ea_rom_prediction_t pr;
  ea_error_t err = {0};
  double dist = INFINITY;
  const double settle = fmax(R->s.settle_s, 3.0);
  e->by_model = 1;
  ++info->model_evals;
  ea_status_t st = EA_OK;
  if (R->nl_sampled)
    st = ea_traj_romnl_predict(tb, R->nl, &R->tr, EA__NL_DT, settle, &pr, &dist, &err);
  if (!st && !(dist <= R->nl_dist0 + EA__NL_PATH_M)) {
    R->nl_sampled = 0;
    st = ea_traj_romnl_sample(R->nl, tb, &R->tr, EA_ROMNL_SAMPLES, &err);
    if (!st) {
      R->nl_sampled = 1;
      st = ea_traj_romnl_predict(tb, R->nl, &R->tr, EA__NL_DT, settle, &pr, &dist, &err);
      R->nl_dist0 = dist;
    }
  }
  e->fe_status = st;
  if (st) {
    snprintf(R->fe_msg, sizeof R->fe_msg, "%.500s", err.msg);
  } else {
    /* at rest the model's loop goes to EA__NL_TOL of the tolerance; a residual bound leaves
     * the model's own error (a few per cent) as margin */
    const double tol = R->task->dynamics.residual_m > 0.0 ? EA__NL_BOUND : EA__NL_TOL;
    e->model_residual_peak_m[0] = pr.residual_peak;
    e->score = pr.residual_peak / (tol * info->allowed_m[0]);
    for (int i = 0; i < R->K; ++i) {
      e->fitted_m[2 * i] = pr.eta[i] * R->tipn[0][i];
      e->fitted_m[2 * i + 1] = pr.eta_rate[i] * R->tipn[0][i] / R->w[0][i];
    }
  }
  e->residual_peak_m = e->model_residual_peak_m[0];
  e->fe_time_s = ea__mono_s() - tm;
  info->time_model_s += e->fe_time_s;
}

/* One evaluation at parameters z (n values): re-plan warm with the targets, FE transients,
 * fits. Appends to info->evals; returns its index (-1: no room). */
static int ea__refine_eval(ea__refine_t *R, const double *z, int final_resolve) {
  ea_refine_info_t *info = R->info;
  if (info->n_evals >= EA_TASK_REFINE_MAX_EVALUATIONS + 1) return -1;
  const int idx = info->n_evals++;
  ea_refine_eval_t *e = &info->evals[idx];
  memset(e, 0, sizeof *e);
  e->final_resolve = final_resolve;
  e->duration_s = e->residual_peak_m = e->residual_rms_m = e->score = NAN;
  e->fe_status = EA_ERR_ARG;
  for (int p = 0; p < EA__RP; ++p)
    e->fitted_m[p] = e->predicted_m[p] = NAN;
  for (int j = 0; j < EA__RM; ++j)
    e->model_residual_peak_m[j] = e->model_residual_rms_m[j] = NAN;
  const double te = ea__mono_s();
  for (int j = 0; j < R->M; ++j)
    for (int i = 0; i < R->m; ++i) {
      const int p = j * 2 * R->m + 2 * i;
      e->params_m[p] = z[p];
      e->params_m[p + 1] = z[p + 1];
      e->eta[j * R->K + i] = z[p] / R->tipn[j][i];
      e->eta_rate[j * R->K + i] = z[p + 1] * R->w[j][i] / R->tipn[j][i];
    }
  ea_error_t err = {0};
  ea_plan_info_t pi;
  memset(&pi, 0, sizeof pi);
  ea_status_t st = EA_OK;
  for (int j = 0; j < R->M && !st; ++j)
    st = ea_planner_set_terminal_modes_model(R->pl, j, e->eta + j * R->K, e->eta_rate + j * R->K,
                                             &err);
  if (!st) {
    /* the re-plan stops where the refinement's time runs out (refine.max_time_s), as its FE
     * transients do: a target the limits cannot reach otherwise runs the engine to its own
     * iteration cap; the planner's own limit is restored after */
    const double own = R->pl->task.solver.max_time_s;
    if (!final_resolve)
      R->pl->task.solver.max_time_s = fmin(own, fmax(R->t0 + R->s.max_time_s - te, 1e-3));
    st = ea_planner_solve(R->pl, EA_PLAN_WARM, NULL, &pi, &err);
    R->pl->task.solver.max_time_s = own;
  }
  e->plan_status = st;
  e->plan_iterations = pi.iterations;
  e->plan_time_s = ea__mono_s() - te;
  info->time_plan_s += e->plan_time_s;
  if (st) {
    R->held = -1; /* a failed solve: what the planner holds is not known */
  } else {
    R->held = idx;
    R->held_info = pi;
    e->duration_s = pi.duration_s;
    st = ea_planner_trajectory(R->pl, &R->tr, &err);
  }
  if (!st) { /* each model's own state at the goal, as tip amplitudes */
    for (int j = 0; j < R->M; ++j) {
      double eta[EA_ROM_MAX_MODES], rate[EA_ROM_MAX_MODES];
      if (ea__plan_dyn_terminal(R->pl, j, eta, rate)) continue;
      for (int i = 0; i < R->K; ++i) {
        e->predicted_m[j * 2 * R->K + 2 * i] = eta[i] * R->tipn[j][i];
        e->predicted_m[j * 2 * R->K + 2 * i + 1] = rate[i] * R->tipn[j][i] / R->w[j][i];
      }
    }
    if (R->by_model)
      ea__refine_model(R, e);
    else
      ea__refine_fe(R, e, !final_resolve);
  }
  /* longer than the unrefined plan by more than max_duration_change: rejected (a shorter one
   * is not: a robust refinement's corner centres free the plan, paper line -3.8 %) */
  const double d0 = info->duration_before_s;
  int fitted = 1;
  for (int p = 0; p < 2 * R->K * R->M; ++p)
    fitted = fitted && isfinite(e->fitted_m[p]) && isfinite(e->predicted_m[p]);
  if (R->by_model) fitted = fitted && isfinite(e->residual_peak_m);
  e->accepted = !e->plan_status && !e->fe_status && isfinite(e->score) && fitted &&
                (idx == 0 || e->duration_s - d0 <= R->s.max_duration_change * d0);
  e->elapsed_s = ea__mono_s() - R->t0;
  R->last_eval_s = ea__mono_s() - te;
  if (R->s.progress)
    R->s.progress(R->s.progress_data, idx, R->s.max_evaluations, e->elapsed_s, e->residual_peak_m);
  if (e->accepted && !final_resolve && (R->best < 0 || e->score < info->evals[R->best].score))
    R->best = idx;
  if (e->accepted && e->score <= 1.0 && !R->stop) R->stop = "tolerance";
  return idx;
}

/* ---- Newton on F: Broyden updates, finite-difference restarts, backtracking on |F| -------- */

/* Measured: re-planned and every model's FE residual fitted (its F is known; whether its
 * duration is acceptable does not matter to the Newton iteration). */
static int ea__refine_measured(const ea__refine_t *R, const ea_refine_eval_t *e) {
  if (e->plan_status || e->fe_status) return 0;
  for (int p = 0; p < 2 * R->K * R->M; ++p)
    if (!isfinite(e->fitted_m[p]) || !isfinite(e->predicted_m[p])) return 0;
  return 1;
}

/* Broyden's update of J (n x n) over the step from evaluation a to evaluation b. */
static void ea__refine_broyden(const ea__refine_t *R, double *J, const ea_refine_eval_t *a,
                               const ea_refine_eval_t *b) {
  const int n = R->n;
  double Fa[EA__RP], Fb[EA__RP], sv[EA__RP], ss = 0.0;
  ea__refine_F(R, a, Fa);
  ea__refine_F(R, b, Fb);
  for (int p = 0; p < n; ++p) {
    sv[p] = b->params_m[p] - a->params_m[p];
    ss += sv[p] * sv[p];
  }
  if (!(ss > 0.0)) return;
  for (int p = 0; p < n; ++p) {
    double Js = 0.0;
    for (int q = 0; q < n; ++q)
      Js += J[p * n + q] * sv[q];
    for (int q = 0; q < n; ++q)
      J[p * n + q] += (Fb[p] - Fa[p] - Js) * sv[q] / ss;
  }
}

/* The Jacobian of F at evaluation x by forward differences, one evaluation per parameter
 * (step h, the other sign if the first candidate cannot be measured; a column that cannot
 * be measured either way keeps its value). Returns the index of the measured evaluation of
 * least |F| among x and the probes. */
static int ea__refine_fd(ea__refine_t *R, double *J, int x, double h) {
  const int n = R->n;
  double Fx[EA__RP];
  ea__refine_F(R, &R->info->evals[x], Fx);
  int best = x;
  double best_r = ea__rnorm(R, Fx);
  for (int q = 0; q < n && !ea__refine_budget(R); ++q) {
    for (int sgn = 1; sgn >= -1; sgn -= 2) {
      double z[EA__RP];
      memcpy(z, R->info->evals[x].params_m, sizeof z);
      z[q] += sgn * h;
      const int idx = ea__refine_eval(R, z, 0);
      if (idx < 0) return best;
      const ea_refine_eval_t *e = &R->info->evals[idx];
      if (!ea__refine_measured(R, e)) {
        if (ea__refine_budget(R)) return best;
        continue;
      }
      double Fe[EA__RP];
      ea__refine_F(R, e, Fe);
      for (int p = 0; p < n; ++p)
        J[p * n + q] = (Fe[p] - Fx[p]) / (sgn * h);
      if (ea__rnorm(R, Fe) < best_r) {
        best_r = ea__rnorm(R, Fe);
        best = idx;
      }
      break;
    }
    if (R->stop) break;
  }
  return best;
}

/* Newton's method on F(z) = 0 with the merit |F|. The model says J = I; Broyden's update
 * learns the FE's difference along the steps. A step that does not reduce |F| by at least
 * 10 % of the predicted reduction (Armijo) restarts the Jacobian by finite differences at
 * the base point; a step that fails with that Jacobian, or whose candidate cannot be planned,
 * is halved (backtracking), down to a step of 1e-3 tolerance_m ("no_progress"). The base point only
 * moves to a measured point of smaller |F|, so |F| decreases monotonically: the iteration cannot
 * cycle. */
static void ea__refine_newton(ea__refine_t *R) {
  const int n = R->n;
  static const size_t nn = (size_t)EA__RP * EA__RP;
  double *J = calloc(nn, sizeof *J), *A = calloc(nn, sizeof *A);
  if (!J || !A) {
    free(J);
    free(A);
    R->stop = "failed";
    return;
  }
  for (int p = 0; p < n; ++p)
    J[p * n + p] = 1.0;
  int x = R->best; /* the base point: measured, least |F| so far */
  int fresh = 0;   /* 1: J is a finite-difference Jacobian at x, no step failed with it yet */
  double t = 1.0;  /* step fraction (backtracking with a fresh Jacobian) */
  while (!ea__refine_budget(R)) {
    const ea_refine_eval_t *b = &R->info->evals[x];
    double Fb[EA__RP], rhs[EA__RP], dz[EA__RP], z[EA__RP];
    ea__refine_F(R, b, Fb);
    const double rb = ea__rnorm(R, Fb);
    memcpy(A, J, (size_t)n * n * sizeof *A);
    for (int p = 0; p < n; ++p)
      rhs[p] = -Fb[p];
    if (ea__rsolve(n, A, rhs, dz)) { /* singular: the model's Jacobian */
      memset(J, 0, nn * sizeof *J);
      for (int p = 0; p < n; ++p) {
        J[p * n + p] = 1.0;
        dz[p] = -Fb[p];
      }
      fresh = 0;
    }
    /* at most 4 x |F| per step (the model's scale: J near I) */
    double len = 0.0;
    for (int p = 0; p < n; ++p)
      len += dz[p] * dz[p];
    len = sqrt(len);
    const double f = t * (len > 4.0 * rb ? 4.0 * rb / len : 1.0);
    if (f * len < 1e-3 * R->s.tolerance_m) {
      R->stop = "no_progress";
      break;
    }
    for (int p = 0; p < n; ++p)
      z[p] = b->params_m[p] + f * dz[p];
    const int idx = ea__refine_eval(R, z, 0);
    if (idx < 0) break;
    const ea_refine_eval_t *e = &R->info->evals[idx];
    const int measured = ea__refine_measured(R, e);
    double re = INFINITY;
    if (measured) {
      double Fe[EA__RP];
      ea__refine_F(R, e, Fe);
      re = ea__rnorm(R, Fe);
      ea__refine_broyden(R, J, b, e);
    }
    /* the linear model predicts |F| -> (1 - f') |F| for the step fraction f' of the Newton
     * step (f' = f when dz is the full step) */
    const double frac = len > 0.0 ? fmin(f, 1.0) : 0.0;
    if (measured && re <= (1.0 - 0.1 * frac) * rb) {
      x = idx;
      fresh = 0;
      t = 1.0;
      continue;
    }
    if (R->stop) break;
    if (!measured) { /* not planned (a target the plan cannot reach): a shorter step */
      t *= 0.5;
    } else if (!fresh) { /* restart: the Jacobian by differences at x */
      const double h = fmax(0.1 * rb / sqrt((double)n), 0.1 * R->s.tolerance_m);
      const int bx = ea__refine_fd(R, J, x, h);
      fresh = bx == x; /* a better probe: step from there with J (another restart allowed) */
      x = bx;
      t = 1.0;
    } else {
      t *= 0.5;
    }
  }
  free(J);
  free(A);
}

/* ---- NLopt on |F|^2 ------------------------------------------------------------------------ */

static double ea__refine_nlopt_f(unsigned n, const double *x, double *grad, void *data) {
  ea__refine_t *R = data;
  (void)grad;
  if (ea__refine_budget(R)) {
    nlopt_force_stop(R->opt);
    return R->penalty;
  }
  double z[EA__RP];
  for (unsigned p = 0; p < n; ++p)
    z[p] = R->nl_z0[p] + R->nl_scale * x[p];
  const int idx = ea__refine_eval(R, z, 0);
  if (idx < 0) {
    nlopt_force_stop(R->opt);
    return R->penalty;
  }
  const ea_refine_eval_t *e = &R->info->evals[idx];
  if (R->stop) nlopt_force_stop(R->opt);
  if (!e->accepted) return R->penalty;
  double F[EA__RP];
  ea__refine_F(R, e, F);
  const double r = ea__rnorm(R, F) / R->nl_scale;
  return r * r;
}

static void ea__refine_nlopt(ea__refine_t *R) {
  static const nlopt_algorithm algs[] = {NLOPT_LN_BOBYQA, NLOPT_LN_BOBYQA, NLOPT_LN_COBYLA,
                                         NLOPT_LN_SBPLX};
  const int n = R->n;
  const ea_refine_eval_t *e0 = &R->info->evals[R->best];
  double F0[EA__RP];
  ea__refine_F(R, e0, F0);
  const double r0 = ea__rnorm(R, F0);
  /* variables in units of the tolerance, from the first Newton step z0 = z - F */
  R->nl_scale = R->s.tolerance_m;
  for (int p = 0; p < n; ++p)
    R->nl_z0[p] = e0->params_m[p] - F0[p];
  const double r0u = r0 / R->nl_scale;
  R->penalty = 100.0 * (r0u * r0u + 1.0);
  double x[EA__RP] = {0}, lb[EA__RP], ub[EA__RP], step[EA__RP];
  for (int p = 0; p < n; ++p) {
    const double box = fmax(4.0 * r0u, 10.0);
    lb[p] = -box;
    ub[p] = box;
    step[p] = fmax(0.1 * r0u, 0.25);
  }
  R->opt = nlopt_create(algs[R->s.method], (unsigned)n);
  if (!R->opt) {
    R->stop = "failed";
    return;
  }
  nlopt_srand(R->s.seed);
  nlopt_set_lower_bounds(R->opt, lb);
  nlopt_set_upper_bounds(R->opt, ub);
  nlopt_set_min_objective(R->opt, ea__refine_nlopt_f, R);
  nlopt_set_initial_step(R->opt, step);
  nlopt_set_xtol_abs1(R->opt, 1e-3);
  nlopt_set_maxeval(R->opt, R->s.max_evaluations); /* the budget check stops it first */
  double f = 0.0;
  const nlopt_result res = nlopt_optimize(R->opt, x, &f);
  R->info->nlopt_result = (int)res;
  nlopt_destroy(R->opt);
  R->opt = NULL;
  if (!R->stop) R->stop = "optimizer";
}

/* ---- driver ------------------------------------------------------------------------------ */

/* The task and the settings must allow a refinement; the message says why not. */
static ea_status_t ea__refine_check(const ea__refine_t *R, ea_error_t *err) {
  const ea_task_t *task = R->task;
  ea_refine_info_t *info = R->info;
  if (!ea_planner_rom_table(R->pl) || task->dynamics.modes < 1) {
    snprintf(info->message, sizeof info->message,
             "refinement needs a task with dynamics (dynamics.modes >= 1)");
    return ea_error_set(err, EA_ERR_ARG, "%s", info->message);
  }
  if (task->objective == EA_TASK_MIN_VIBRATION || R->s.modes < 0 ||
      R->s.modes > task->dynamics.modes) {
    snprintf(info->message, sizeof info->message,
             "refinement needs a plan that promises rest or a residual bound (not "
             "min_vibration) and 0 (every mode) <= refine.modes <= dynamics.modes = %d (got %d)",
             task->dynamics.modes, R->s.modes);
    return ea_error_set(err, EA_ERR_ARG, "%s", info->message);
  }
  const ea_task_refine_t *r = &R->s;
  if (!(r->tolerance_m > 0.0) || r->max_evaluations < 1 ||
      r->max_evaluations > EA_TASK_REFINE_MAX_EVALUATIONS || !(r->max_time_s > 0.0) ||
      !(r->fe_dt_s > 0.0) || !(r->settle_s > 0.0) || !(r->max_duration_change >= 0.0) ||
      (int)r->method < 0 || r->method > EA_TASK_REFINE_SBPLX) {
    snprintf(info->message, sizeof info->message,
             "refinement settings out of range (docs/task-format.md, dynamics.refine)");
    return ea_error_set(err, EA_ERR_ARG, "%s", info->message);
  }
  return EA_OK;
}

/* The sizes (modes, models, parameters) and the loop's FE settings. */
static ea_status_t ea__refine_setup(ea__refine_t *R, ea_plan_dyn_info_t *di, ea_error_t *err) {
  ea_refine_info_t *info = R->info;
  ea_planner_dyn_model(R->pl, di);
  R->t0 = ea__mono_s();
  R->K = R->task->dynamics.modes;
  R->m = R->s.modes > 0 ? R->s.modes : R->K; /* 0: every mode */
  R->s.modes = R->m;
  info->settings.modes = R->m;
  R->M = di->models > 1 ? di->models : 1;
  R->n = 2 * R->m * R->M;
  info->model_modes = R->K;
  info->models = R->M;
  info->n_params = R->n;
  ea_sim_settings_default(&info->fe);
  info->fe.elements = EA_FE_DEFAULT_ELEMENTS;
  info->fe.scheme = EA_FE_SCHEME_GENALPHA;
  info->fe.dt = R->s.fe_dt_s;
  info->fe.settle = R->s.settle_s;
  info->fe.damping_ratio = NAN;
  info->fe.keep_history = 1;
  const ea_status_t st = ea_sim_settings_validate(&info->fe, err);
  if (st) snprintf(info->message, sizeof info->message, "%s", err ? err->msg : "FE settings");
  return st;
}

/* Every model at the goal (the last knot is pinned there): frequencies and tip directions;
 * its FE arm: the task's with the model's EI, its tip mass (hand + payload, scaled). */
static ea_status_t ea__refine_models(ea__refine_t *R, const ea_plan_dyn_info_t *di,
                                     ea_error_t *err) {
  const ea_task_t *task = R->task;
  ea_refine_info_t *info = R->info;
  for (int j = 0; j < R->M; ++j) {
    const ea_rom_table_t *tj = ea__plan_rom_model(R->pl, j);
    ea_rom_point_t v;
    ea_rom_table_eval(tj, task->goal.cable_length, task->goal.cable_angle, &v, NULL, NULL);
    R->arm[j] = task->arm;
    R->arm[j].EI = di->model_EI[j];
    info->model_tip_mass_kg[j] = di->model_tip_mass[j];
    info->model_EI_Nm2[j] = di->model_EI[j];
    /* a corner: its model's bound plus the tolerance at rest (with a residual bound, which is
     * the nominal's tolerance, the default check's tolerance at rest) */
    const double slack =
        task->dynamics.residual_m > 0.0 ? EA_TASK_REST_TOLERANCE_M : R->s.tolerance_m;
    info->allowed_m[j] = j ? task->dynamics.robust_residual_m + slack : R->s.tolerance_m;
    for (int i = 0; i < R->K; ++i) {
      R->w[j][i] = sqrt(fmax(v.omega2[i], 0.0));
      R->tipn[j][i] = hypot(v.tip[i][0], v.tip[i][1]);
      if (!(R->w[j][i] > 0.0) || !(R->tipn[j][i] > 0.0)) {
        info->status = EA_ERR_UNSTABLE;
        snprintf(info->message, sizeof info->message,
                 "the reduced model%s at the goal has mode %d with frequency %g rad/s and tip "
                 "displacement %g m per unit: cannot refine",
                 j ? " of a robust corner" : "", i + 1, R->w[j][i], R->tipn[j][i]);
        return ea_error_set(err, info->status, "%s", info->message);
      }
      R->u[j][i][0] = v.tip[i][0] / R->tipn[j][i];
      R->u[j][i][1] = v.tip[i][1] / R->tipn[j][i];
    }
  }
  return EA_OK;
}

/* Evaluation 0: the unrefined plan (targets zero; no iteration if the planner holds it). */
static ea_status_t ea__refine_first(ea__refine_t *R, ea_error_t *err) {
  ea_refine_info_t *info = R->info;
  const double zero[EA__RP] = {0};
  const int i0 = ea__refine_eval(R, zero, 0);
  const ea_refine_eval_t *e0 = &info->evals[i0];
  info->duration_before_s = e0->duration_s;
  if (!e0->accepted) {
    info->status =
        e0->plan_status ? e0->plan_status : (e0->fe_status ? e0->fe_status : EA_ERR_SINGULAR);
    if (e0->fe_status == EA_ERR_INTERRUPTED)
      snprintf(info->message, sizeof info->message,
               "the at-rest plan's FE transient did not finish within refine.max_time_s = %g s "
               "(%.200s): nothing to refine against; a larger refine.fe_dt_s (now %g s) or "
               "max_time_s",
               R->s.max_time_s, R->fe_msg, R->s.fe_dt_s);
    else
      snprintf(info->message, sizeof info->message,
               "the at-rest plan %s (%s%s%.200s): nothing to refine against",
               e0->plan_status ? "could not be planned" : "has no FE residual",
               ea_status_name(info->status), R->fe_msg[0] && !e0->plan_status ? ": " : "",
               e0->plan_status ? "" : R->fe_msg);
    return ea_error_set(err, info->status, "%s", info->message);
  }
  info->residual_peak_before_m = e0->residual_peak_m;
  info->residual_rms_before_m = e0->residual_rms_m;
  info->score_before = e0->score;
  for (int j = 0; j < R->M; ++j)
    info->model_residual_peak_before_m[j] = e0->model_residual_peak_m[j];
  return EA_OK;
}

/* The planner must hold the best plan: re-plan it if a later candidate was planned. The index
 * of the returned evaluation in *ret. */
static ea_status_t ea__refine_hold_best(ea__refine_t *R, int *ret, ea_error_t *err) {
  ea_refine_info_t *info = R->info;
  *ret = R->best;
  if (R->held == R->best) return EA_OK;
  const int bi = R->best;
  const int idx = ea__refine_eval(R, info->evals[bi].params_m, 1);
  const ea_refine_eval_t *e = idx >= 0 ? &info->evals[idx] : NULL;
  if (!e || e->plan_status) {
    const ea_status_t st = e ? e->plan_status : EA_ERR_NOMEM;
    info->status = st;
    snprintf(info->message, sizeof info->message,
             "re-planning the best candidate (evaluation %d) failed: %s", bi, ea_status_name(st));
    return ea_error_set(err, st, "%s", info->message);
  }
  *ret = idx;
  return EA_OK;
}

/* settings.by model: the model's search is over; the FE transient of its best plan is the
 * verdict, and where that is not within the tolerance the FE search goes on from it (the
 * model's Jacobian I again: Broyden learns the FE's). */
static void ea__refine_verdict(ea__refine_t *R) {
  ea_refine_info_t *info = R->info;
  const int b = R->best;
  R->by_model = 0;
  if (b < 0) return;
  info->model_only_peak_m = info->evals[b].residual_peak_m;
  const char *model_stop = R->stop;
  R->stop = NULL;
  R->best = -1;
  double z[EA__RP];
  memcpy(z, info->evals[b].params_m, sizeof z);
  if (ea__refine_budget(R) || ea__refine_eval(R, z, 0) < 0 || R->best < 0) {
    /* no FE measure of the model's plan: it is returned, not converged (ea__refine_report) */
    R->best = b;
    if (!R->stop) R->stop = model_stop ? model_stop : "failed";
    return;
  }
  if (R->stop) return;
  if (R->s.method == EA_TASK_REFINE_NEWTON)
    ea__refine_newton(R);
  else
    ea__refine_nlopt(R);
}

/* The returned evaluation ret into info, and the summary message. */
static void ea__refine_report(const ea__refine_t *R, int ret) {
  ea_refine_info_t *info = R->info;
  const ea_refine_eval_t *er = &info->evals[ret];
  info->returned = ret;
  info->duration_s = er->duration_s;
  info->residual_peak_m = er->residual_peak_m;
  info->residual_rms_m = er->residual_rms_m;
  info->score = er->score;
  for (int j = 0; j < R->M; ++j)
    info->model_residual_peak_m[j] = er->model_residual_peak_m[j];
  for (int i = 0; i < R->K * R->M; ++i) {
    info->eta[i] = er->eta[i];
    info->eta_rate[i] = er->eta_rate[i];
  }
  /* by the model alone a plan is converged in the model's terms; else only by the FE */
  info->converged = er->accepted && er->score <= 1.0 &&
                    (!er->by_model || R->s.by == EA_TASK_REFINE_BY_MODEL_ONLY);
  snprintf(info->stop_reason, sizeof info->stop_reason, "%s", R->stop);
  info->time_s = ea__mono_s() - R->t0;
  info->status = EA_OK;
  char corners[160] = "";
  if (R->M > 1) {
    double c0 = 0.0, c1 = 0.0;
    for (int j = 1; j < R->M; ++j) {
      c0 = fmax(c0, info->model_residual_peak_before_m[j]);
      c1 = fmax(c1, info->model_residual_peak_m[j]);
    }
    snprintf(corners, sizeof corners, "; robust corners: worst %.4g mm -> %.4g mm (bound %.4g mm)",
             1e3 * c0, 1e3 * c1, 1e3 * info->allowed_m[1]);
  }
  const char *by = R->s.by == EA_TASK_REFINE_BY_MODEL_ONLY
                       ? ", by the nonlinear reduced model alone: its"
                   : R->s.by == EA_TASK_REFINE_BY_MODEL
                       ? ", the nonlinear reduced model's prediction, then the FE's:"
                       : ": FE";
  snprintf(info->message, sizeof info->message,
           "refinement (%s)%s residual peak %.4g mm -> %.4g mm (tolerance %.4g mm)%s%s in %d "
           "evaluation%s, %.3g s; duration %.6g s -> %.6g s; stopped: %s",
           ea_task_refine_method_name(R->s.method), by, 1e3 * info->residual_peak_before_m,
           1e3 * info->residual_peak_m, 1e3 * R->s.tolerance_m, corners,
           info->converged ? ", reached" : ", NOT reached", info->n_evals,
           info->n_evals == 1 ? "" : "s", info->time_s, info->duration_before_s, info->duration_s,
           info->stop_reason);
}

ea_rest_check_t ea_plan_rest_check(const ea_task_t *task) {
  if (!task || task->dynamics.modes < 1 || !task->dynamics.verify ||
      task->objective == EA_TASK_MIN_VIBRATION)
    return EA_REST_CHECK_NONE;
  return task->dynamics.residual_m > 0.0 ? EA_REST_CHECK_BOUND : EA_REST_CHECK_REFINE;
}

void ea_plan_rest_settings(const ea_task_t *task, ea_task_refine_t *s) {
  *s = task->dynamics.refine;
  if (!s->enabled) s->tolerance_m = EA_TASK_REST_TOLERANCE_M;
  if (task->dynamics.residual_m > 0.0) s->tolerance_m = task->dynamics.residual_m;
  s->enabled = 1;
}

ea_status_t ea_plan_rest_refine(ea_planner_t *pl, ea_plan_info_t *plan_info, ea_refine_info_t *info,
                                ea_error_t *err) {
  if (!pl) return ea_error_set(err, EA_ERR_ARG, "ea_plan_rest_refine: NULL planner");
  ea_task_refine_t s;
  ea_plan_rest_settings(ea_planner_task(pl), &s);
  return ea_plan_refine(pl, &s, plan_info, info, err);
}

ea_status_t ea_plan_refine(ea_planner_t *pl, const ea_task_refine_t *s, ea_plan_info_t *plan_info,
                           ea_refine_info_t *info, ea_error_t *err) {
  if (!pl || !info) return ea_error_set(err, EA_ERR_ARG, "ea_plan_refine: NULL argument");
  memset(info, 0, sizeof *info);
  info->status = EA_ERR_ARG;
  snprintf(info->stop_reason, sizeof info->stop_reason, "failed");
  const ea_task_t *task = ea_planner_task(pl);
  ea__refine_t R;
  memset(&R, 0, sizeof R);
  R.pl = pl;
  R.task = task;
  R.info = info;
  R.s = s ? *s : task->dynamics.refine;
  R.s.enabled = 1;
  /* a residual bound: the planner keeps the model's state within it about the target centre,
   * which the refinement moves by the model's error; the FE residual is held to the bound */
  if (task->dynamics.residual_m > 0.0) R.s.tolerance_m = task->dynamics.residual_m;
  R.held = R.best = -1;
  info->settings = R.s;
  ea_plan_dyn_info_t di;
  ea_status_t st = ea__refine_check(&R, err);
  if (!st) st = ea__refine_setup(&R, &di, err);
  if (!st) st = ea__refine_models(&R, &di, err);
  info->model_only_peak_m = NAN;
  if (!st && R.s.by != EA_TASK_REFINE_BY_FE) {
    if (R.M > 1 || R.K != EA_ROMNL_MODES) {
      snprintf(info->message, sizeof info->message,
               "refinement by the nonlinear reduced model needs dynamics.modes = %d and no "
               "robust corners (the task: %d modes, %d models)",
               EA_ROMNL_MODES, R.K, R.M);
      st = ea_error_set(err, EA_ERR_ARG, "%s", info->message);
    } else {
      st = ea_romnl_alloc(&R.arm[0], ea_arm_tip_mass(&R.arm[0], task->payload_kg), 0, &R.nl, err);
      if (st) snprintf(info->message, sizeof info->message, "%s", err ? err->msg : "romnl");
      R.by_model = 1;
    }
  }
  if (st) {
    ea_romnl_free(R.nl);
    return st;
  }
  memset(&R.tr, 0, sizeof R.tr);
  int ret = -1;
  if (!(st = ea__refine_first(&R, err))) {
    if (!R.stop) {
      if (R.s.method == EA_TASK_REFINE_NEWTON)
        ea__refine_newton(&R);
      else
        ea__refine_nlopt(&R);
    }
    if (R.s.by == EA_TASK_REFINE_BY_MODEL) ea__refine_verdict(&R);
    if (!R.stop) R.stop = "no_progress";
    st = ea__refine_hold_best(&R, &ret, err);
  }
  if (!st) {
    ea__refine_report(&R, ret);
    if (plan_info) *plan_info = R.held_info;
    st = ea_error_set(err, EA_OK, "%s", info->message);
  }
  ea_traj_free(&R.tr);
  ea_romnl_free(R.nl);
  return st;
}
