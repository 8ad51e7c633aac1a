/* The path transcription's statics tables: (T, theta0, kappa0) along the path coordinate
 * sigma, a cubic Hermite in sigma on a table bisected until each interval's Hermite misses its
 * midpoint by < 16 x 1e-11 (O(h^4): ~1/16 of that between). Its samples come from Chebyshev
 * interpolants of the statics per segment (ea__pp_piece): samples at Chebyshev-Lobatto points,
 * the levels of 8, 16, 32, 64 intervals each checked against the next level's new samples and
 * taken when they miss by < EA__PP_TOL (theta0 [rad], T relative to 1 + T, kappa0 L), tight
 * enough that the knots of a plan hold the statics residual 1e-9 (test_plan_path measures the
 * tables against independent re-solves between the samples). The table also holds dp/dL_c and
 * dp/dalpha per sample (the limits between the knots take the statics' rates from them). An
 * update keeps the samples of the leading segments whose geometry, arm, tip mass and base angle
 * did not change. */
#include "path_impl.h"

#include <gsl/gsl_chebyshev.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- statics along the path --------------------------------------------- */

/* Newton on the knot rows in u = (T, theta0, kappa0) at fixed (L_c, alpha) from a close guess
 * (a neighbour's interpolant): one shot with sensitivities per iteration, the last one's
 * sensitivities give the slopes. Strict: every step full, shrinking the residual, with the
 * shoulder angle moving < 0.05 rad, at most 5 steps, T >= 0 at the end; otherwise 0 and the
 * caller solves from scratch (ea_statics_solve: the branch selection, its errors). A converged
 * sample has the knot rows' residual <= 1e-12 (1e-2 of ea_statics_solve's default: at 1e-10
 * the samples' own error made the splines miss independent re-solves by 3.6e-10, at 1e-12 by
 * 1.0e-10, test_plan_path), 1-2 shots from the spline refinement's guesses instead of
 * ea_statics_solve's 3-4 plus the slopes' shot (xL: the last shot's, before a final step). */
static int ea__pp_newton(const ea_planner_t *pl, ea_shooter_t *sh, const double q[3],
                         double g[EA_NP], double xL[EA_NX], double *S) {
  ea_statics_settings_t set;
  ea_statics_settings_default(&set);
  const ea_arm_t *arm = &pl->task.arm;
  const double ca = cos(q[1]), sa = sin(q[1]);
  const int xi[3] = {EA_X_KAPPA, EA_X_X, EA_X_Y};
  double nr_prev = INFINITY;
  g[EA_P_ALPHA] = q[1];
  for (int it = 0; it <= 5; ++it) {
    if (ea_shoot(sh, g, xL, S)) return 0;
    const double r[3] = {xL[EA_X_KAPPA], xL[EA_X_X] - arm->x_c - q[0] * ca,
                         xL[EA_X_Y] - arm->y_c - q[0] * sa};
    const double nr = fmax(fabs(r[0]), fmax(fabs(r[1]), fabs(r[2])));
    if (!(nr < nr_prev)) return 0;
    if (nr <= 1e-2 * set.tol) return g[EA_P_TENSION] >= 0.0;
    if (it == 5) return 0;
    nr_prev = nr;
    double A[3][3];
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        A[a][c] = S[xi[a] * EA_NP + 1 + c];
    double du[3];
    if (ea__plan_solve3(A, r, du)) return 0;
    if (!(fabs(du[1]) < 0.05)) return 0;
    for (int c = 0; c < 3; ++c)
      g[1 + c] -= du[c];
    /* a start within 1e-9 (a sample's Hermite guess at the finer levels): the step leaves a
     * residual of its square, far below the tolerance, and the slopes from this shot's
     * sensitivities move the splines by less than their 1e-10 (test_plan_path's independent
     * re-solves); one shot fewer per such sample */
    if (nr <= 1e-9) return g[EA_P_TENSION] >= 0.0;
  }
  return 0;
}

/* Statics at sigma (warm-started from guess, which is updated) and its slopes dp/dsigma, by the
 * shooter sh (the planner's, or a worker's: the same shots). */
static ea_status_t ea__pp_statics_sh(const ea_planner_t *pl, ea_shooter_t *sh, int j, double sig,
                                     double guess[EA_NP], int *have, double p[3], double dp[3],
                                     double pa[6], ea_error_t *err) {
  double q[3], dq[3];
  ea__pp_q(pl, j, sig, q, dq);
  double xL[EA_NX], S[EA_NX * EA_NP], g[EA_NP];
  ea_status_t st;
  memcpy(g, guess, sizeof g);
  if (*have && ea__pp_newton(pl, sh, q, g, xL, S)) {
    memcpy(guess, g, sizeof g);
  } else {
    ea_statics_problem_t pr = ea_statics_problem_cable(q[0], q[1]);
    ea_statics_solution_t sol;
    ea_error_t e = {0};
    st = ea_statics_solve(sh, &pr, NULL, *have ? guess : NULL, &sol, &e);
    if (st && *have) st = ea_statics_solve(sh, &pr, NULL, NULL, &sol, &e);
    if (st)
      return ea_error_set(err, st == EA_ERR_INADMISSIBLE ? EA_ERR_INFEASIBLE : st,
                          "the path leaves the workspace at L_c = %.6g m, alpha = %.6g rad: %s",
                          q[0], q[1], e.msg);
    memcpy(guess, sol.p, sizeof(double) * EA_NP);
    *have = 1;
    memcpy(g, sol.p, sizeof g); /* polished to the samples' tolerance, its slopes' shot */
    if (ea__pp_newton(pl, sh, q, g, xL, S))
      memcpy(guess, g, sizeof g);
    else if ((st = ea_shoot(sh, sol.p, xL, S)))
      return ea_error_set(err, st, "shooting failed");
  }
  if (ea__plan_statics_slope(S, q[0], q[1], dq[0], dq[1], dp) ||
      (pa && (ea__plan_statics_slope(S, q[0], q[1], 1.0, 0.0, pa) ||
              ea__plan_statics_slope(S, q[0], q[1], 0.0, 1.0, pa + 3))))
    return ea_error_set(err, EA_ERR_SINGULAR, "statics slope: singular");
  p[0] = guess[EA_P_TENSION];
  p[1] = guess[EA_P_THETA0];
  p[2] = guess[EA_P_KAPPA0];
  return EA_OK;
}

static ea_status_t ea__pp_statics(const ea_planner_t *pl, int j, double sig, double guess[EA_NP],
                                  int *have, double p[3], double dp[3], double pa[6],
                                  ea_error_t *err) {
  return ea__pp_statics_sh(pl, pl->sh, j, sig, guess, have, p, dp, pa, err);
}

double ea__herm(double h, double y0, double d0, double y1, double d1, double u, double *dy) {
  const double u2 = u * u, u3 = u2 * u;
  if (dy)
    *dy = ((6 * u2 - 6 * u) * y0 + (3 * u2 - 4 * u + 1) * h * d0 + (-6 * u2 + 6 * u) * y1 +
           (3 * u2 - 2 * u) * h * d1) /
          h;
  return (2 * u3 - 3 * u2 + 1) * y0 + (u3 - 2 * u2 + u) * h * d0 + (-2 * u3 + 3 * u2) * y1 +
         (u3 - u2) * h * d1;
}

/* The table interval of segment j (its first sample's index) holding sigma, the end ones
 * beyond its ends. */
static int ea__pp_interval(const ea__pp_t *pp, int j, double sig) {
  int lo = pp->soff[j], hi = pp->soff[j + 1] - 1;
  if (sig <= pp->ssig[lo]) return lo;
  if (sig >= pp->ssig[hi]) return hi - 1;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (pp->ssig[mid] <= sig)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

/* The statics splines of segment j at sigma: p (T, theta0, kappa0) and dp/dsigma (each
 * segment has its own samples: at a corner the slopes differ). */
void ea__pp_spline(const ea__pp_t *pp, int j, double sig, double p[3], double dp[3],
                   double d2p[3]) {
  const int lo = ea__pp_interval(pp, j, sig), hi = lo + 1;
  const double h = pp->ssig[hi] - pp->ssig[lo], u = (sig - pp->ssig[lo]) / h;
  for (int c = 0; c < 3; ++c)
    p[c] = ea__herm(h, pp->sp[3 * lo + c], pp->sdp[3 * lo + c], pp->sp[3 * hi + c],
                    pp->sdp[3 * hi + c], u, &dp[c]);
  if (d2p)
    for (int c = 0; c < 3; ++c)
      d2p[c] = ((12 * u - 6) * pp->sp[3 * lo + c] + (6 * u - 4) * h * pp->sdp[3 * lo + c] +
                (6 - 12 * u) * pp->sp[3 * hi + c] + (6 * u - 2) * h * pp->sdp[3 * hi + c]) /
               (h * h);
}

/* The partial derivatives of the statics in (L_c, alpha) on segment j at sigma (dp/dL_c,
 * dp/dalpha): linear between the samples, ~1 mm apart (the rates at the knots of the paper
 * line's and the effort polyline's plans within 1e-4 relative, 4e-6 absolute, of the implicit
 * derivative from shots with sensitivities, 2.4e-6 of the largest rate, test_plan_path: for
 * the screen of the limits between the knots, whose band is 1e-3 of each limit). */
static void ea__pp_partials(const ea__pp_t *pp, int j, double sig, double pa[6]) {
  const int lo = ea__pp_interval(pp, j, sig), hi = lo + 1;
  const double h = pp->ssig[hi] - pp->ssig[lo];
  const double u = h > 0.0 ? fmin(fmax((sig - pp->ssig[lo]) / h, 0.0), 1.0) : 0.0;
  for (int c = 0; c < 6; ++c)
    pa[c] = (1.0 - u) * pp->spa[6 * lo + c] + u * pp->spa[6 * hi + c];
}

int ea__pp_statics_rates(const ea_planner_t *pl, const double *x, int k, double pd[3]) {
  const ea__pp_t *pp = pl->pp;
  if (!pp || pp->ns < 2) return -1;
  const double q[3] = {x[EA__IQ(pl, k, 0)], x[EA__IQ(pl, k, 1)],
                       pl->nq == 3 ? x[EA__IQ(pl, k, 2)] : pl->base_fixed};
  const int j =
      pl->seg_of_knot[k] >= 0 ? pl->seg_of_knot[k] : ea__pp_seg(pl, pp->xs_last[EA__PS(pp, k)]);
  double pa[6];
  ea__pp_partials(pp, j, ea__pp_sigma_of(pl, j, q), pa);
  const double vL = x[EA__IV(pl, k, 0)], va = x[EA__IV(pl, k, 1)];
  for (int c = 0; c < 3; ++c)
    pd[c] = pa[c] * vL + pa[3 + c] * va;
  return 0;
}

/* The scaled difference of statics y (T, theta0, kappa0) from sample c (sigma, p[3], dp[3]):
 * T relative to 1 + T, theta0 [rad], kappa0 L. */
static double ea__pp_err(const ea_planner_t *pl, const double y[3], const double c[7]) {
  double worst = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double scale = k == 0 ? 1.0 + fabs(c[1]) : (k == 1 ? 1.0 : 1.0 / pl->task.arm.length);
    worst = fmax(worst, fabs(y[k] - c[1 + k]) / scale);
  }
  return worst;
}

/* The error estimate of the Hermite interpolant of samples a and b (sigma, p[3], dp[3]) at
 * their midpoint's sample c. */
static double ea__pp_mid_err(const ea_planner_t *pl, const double a[7], const double b[7],
                             const double c[7]) {
  const double h = b[0] - a[0];
  double y[3];
  for (int k = 0; k < 3; ++k)
    y[k] = ea__herm(h, a[1 + k], a[4 + k], b[1 + k], b[4 + k], 0.5, NULL);
  return ea__pp_err(pl, y, c);
}

/* The path's first sample (sigma on segment 0, its statics g): an update's warm start. */
static void ea__pp_keep_first(ea_planner_t *pl, double sig, const double g[EA_NP]) {
  ea__pp_t *pp = pl->pp;
  double q[3], dq[3];
  ea__pp_q(pl, 0, sig, q, dq);
  memcpy(pp->g_first, g, sizeof pp->g_first);
  pp->q_first[0] = q[0];
  pp->q_first[1] = q[1];
  pp->have_first = 1;
}

/* A sample: sigma, p = (T, theta0, kappa0), dp/dsigma, dp/dL_c, dp/dalpha. */
#define EA__PP_V 13

/* Append sample v to the splines' arrays. */
static ea_status_t ea__pp_push(ea__pp_t *pp, int *n, const double v[EA__PP_V], int j,
                               ea_error_t *err) {
  if (*n >= EA__PP_MAXS)
    return ea_error_set(err, EA_ERR_NOCONV,
                        "path statics: more than %d samples for 1e-10 (segment %d)", EA__PP_MAXS,
                        j + 1);
  pp->ssig[*n] = v[0];
  memcpy(pp->sp + 3 * *n, v + 1, 3 * sizeof(double));
  memcpy(pp->sdp + 3 * *n, v + 4, 3 * sizeof(double));
  memcpy(pp->spa + 6 * *n, v + 7, 6 * sizeof(double));
  ++*n;
  return EA_OK;
}

/* The statics of a piece of a segment as Chebyshev interpolants (GSL's Chebyshev series) in
 * sigma of p = (T, theta0, kappa0), with their derivatives, and of its partial derivatives in
 * (L_c, alpha): coefficients from samples at the N + 1 Chebyshev-Lobatto points of [lo, hi]
 * (the discrete cosine transform, y = -cos(pi i / N) at sample i in sigma order). */
#define EA__PP_NMAX 64 /* Lobatto levels 8, 16, 32, 64 intervals; beyond: the piece is halved */
#define EA__PP_NF 9    /* interpolated functions: p, dp/dL_c, dp/dalpha */

typedef struct {
  gsl_cheb_series f[EA__PP_NF], d[3];
  double c[EA__PP_NF + 3][EA__PP_NMAX + 1];
} ea__pp_cheb_t;

static void ea__pp_cheb_fit(ea__pp_cheb_t *ch, double lo, double hi, int N, const double *ps) {
  double ct[2 * EA__PP_NMAX];
  for (int m = 0; m < 2 * N; ++m)
    ct[m] = cos(M_PI * m / N);
  for (int c = 0; c < EA__PP_NF; ++c) {
    gsl_cheb_series *f = &ch->f[c];
    f->c = ch->c[c];
    f->order = f->order_sp = (size_t)N;
    f->a = lo;
    f->b = hi;
    f->f = NULL;
    for (int k = 0; k <= N; ++k) {
      double sum = 0.5 * (ps[c] + ps[EA__PP_NF * N + c] * ct[(N * k) % (2 * N)]);
      for (int i = 1; i < N; ++i)
        sum += ps[EA__PP_NF * i + c] * ct[(i * k) % (2 * N)];
      f->c[k] = (k % 2 ? -2.0 : 2.0) * sum / N * (k == N ? 0.5 : 1.0);
    }
    if (c < 3) {
      gsl_cheb_series *d = &ch->d[c];
      d->c = ch->c[EA__PP_NF + c];
      d->order = d->order_sp = (size_t)N;
      d->f = NULL;
      gsl_cheb_calc_deriv(d, f);
    }
  }
}

/* Sample v of the interpolants at sigma. */
static void ea__pp_cheb_at(const ea__pp_cheb_t *ch, double sig, double v[EA__PP_V]) {
  v[0] = sig;
  for (int c = 0; c < 3; ++c) {
    v[1 + c] = gsl_cheb_eval(&ch->f[c], sig);
    v[4 + c] = gsl_cheb_eval(&ch->d[c], sig);
  }
  for (int c = 3; c < EA__PP_NF; ++c)
    v[4 + c] = gsl_cheb_eval(&ch->f[c], sig);
}

/* The Hermite samples of segment j in (a, b] from the interpolants, in order: an interval
 * whose midpoint the Hermite of its ends misses by >= 16 EA__PP_HTOL is bisected (the spline
 * on the accepted samples misses by ~1/16 of that, O(h^4)). No shots: the interpolants are
 * the statics here. */
#define EA__PP_HTOL 1e-11
static ea_status_t ea__pp_refine(ea_planner_t *pl, const ea__pp_cheb_t *ch, int j,
                                 const double a[EA__PP_V], const double b[EA__PP_V], int depth,
                                 int *n, double *err_est, ea_error_t *err) {
  ea__pp_t *pp = pl->pp;
  double c[EA__PP_V];
  ea__pp_cheb_at(ch, 0.5 * (a[0] + b[0]), c);
  const double e = ea__pp_mid_err(pl, a, b, c);
  ea_status_t st;
  if (e < 16 * EA__PP_HTOL) {
    *err_est = fmax(*err_est, e / 16);
    if ((st = ea__pp_push(pp, n, c, j, err))) return st;
    return ea__pp_push(pp, n, b, j, err);
  }
  if (depth >= 30)
    return ea_error_set(err, EA_ERR_NOCONV,
                        "path statics: the splines do not reach 1e-10 (segment %d, %.3g)", j + 1,
                        e);
  if ((st = ea__pp_refine(pl, ch, j, a, c, depth + 1, n, err_est, err))) return st;
  return ea__pp_refine(pl, ch, j, c, b, depth + 1, n, err_est, err);
}

/* One level's new samples of ea__pp_piece (the odd Chebyshev-Lobatto points of 2N intervals),
 * part 0 those below the middle, part 1 the rest; e: the interpolant's worst error there. */
typedef struct {
  ea_planner_t *pl;
  const ea__pp_cheb_t *ch;
  int j;
  double lo, hi;
  int N;
  double *pn;
  double e[2];
  ea_status_t st[2];
  ea_error_t err[2];
} ea__pp_level_job_t;

static void ea__pp_level_part(void *ctx, int part) {
  ea__pp_level_job_t *jb = ctx;
  const ea_planner_t *pl = jb->pl;
  ea_shooter_t *sh = part && pl->pp->sh1 ? pl->pp->sh1 : pl->sh;
  enum { W = EA__PP_NF };
  const int N = jb->N;
  for (int i = part ? N + 1 : 1; i < (part ? 2 * N : N); i += 2) {
    const double sig = jb->lo + 0.5 * (jb->hi - jb->lo) * (1.0 - cos(M_PI * i / (2 * N)));
    double v[EA__PP_V], q[3], dq[3], g[EA_NP], c[EA__PP_V];
    ea__pp_cheb_at(jb->ch, sig, v);
    ea__pp_q(pl, jb->j, sig, q, dq);
    g[EA_P_ALPHA] = q[1];
    memcpy(g + 1, v + 1, 3 * sizeof(double));
    int hv = 1;
    if ((jb->st[part] =
             ea__pp_statics_sh(pl, sh, jb->j, sig, g, &hv, c + 1, c + 4, c + 7, &jb->err[part])))
      return;
    jb->e[part] = fmax(jb->e[part], ea__pp_err(pl, v + 1, c)); /* the interpolant's error */
    memcpy(jb->pn + W * i, c + 1, 3 * sizeof(double));
    memcpy(jb->pn + W * i + 3, c + 7, 6 * sizeof(double));
  }
}

/* The piece [lo, hi] of segment j: statics samples at the Chebyshev-Lobatto points of 8
 * intervals (in order, each warm-started from the one before and its slope; guess/have: the
 * chain's, left at hi), then each level's new midpoints (2N intervals) warm-started from the
 * N-interval interpolant, whose misses there are its error estimate: below EA__PP_TOL the
 * 2N-interval interpolant is taken (it is closer still: on the paper line the 16-interval
 * interpolant misses independent re-solves by 7e-11, the 32-interval one by < 1e-11). Not
 * there at 64 intervals: the piece is halved. Its Hermite samples (4 intervals, bisected) are
 * appended. The paper line: 33 samples of 1-2 shots against 131 Hermite samples of one solve
 * each before. */
static ea_status_t ea__pp_piece(ea_planner_t *pl, int j, double lo, double hi, double guess[EA_NP],
                                int *have, int depth, int *n, double *err_est, ea_error_t *err) {
  ea__pp_t *pp = pl->pp;
  enum { W = EA__PP_NF };
  double ps[W * (EA__PP_NMAX + 1)], pn[W * (EA__PP_NMAX + 1)], dp[3], dprev[3] = {0};
  double d2[3] = {0}, sprev = lo;
  ea__pp_cheb_t ch;
  int N = 8;
  ea_status_t st;
  for (int i = 0; i <= N; ++i) {
    const double sig = lo + 0.5 * (hi - lo) * (1.0 - cos(M_PI * i / N));
    /* the guess: the sample before, its slope and (from the third on) the curvature of the
     * last two slopes */
    if (i > 0 && *have)
      for (int c = 0; c < 3; ++c)
        guess[1 + c] =
            ps[W * (i - 1) + c] + (dprev[c] + 0.5 * d2[c] * (sig - sprev)) * (sig - sprev);
    if ((st = ea__pp_statics(pl, j, sig, guess, have, ps + W * i, dp, ps + W * i + 3, err)))
      return st;
    if (*n == 0 && i == 0 && j == 0) ea__pp_keep_first(pl, sig, guess);
    for (int c = 0; c < 3 && i > 0; ++c)
      d2[c] = (dp[c] - dprev[c]) / (sig - sprev);
    memcpy(dprev, dp, sizeof dp);
    sprev = sig;
  }
  /* guess stays at hi: the later levels warm-start their own copies */
  double e = INFINITY;
  for (;;) {
    ea__pp_cheb_fit(&ch, lo, hi, N, ps);
    if (e < EA__PP_TOL || N == EA__PP_NMAX) break;
    for (int i = 0; i <= 2 * N; i += 2)
      memcpy(pn + W * i, ps + W * (i / 2), W * sizeof(double));
    /* the new samples, each from the interpolant's guess: the first and the second half on
     * the two parts of plan_par.c (the worker with its own shooter) */
    ea__pp_level_job_t jb = {pl, &ch, j, lo, hi, N, pn, {0.0, 0.0}, {EA_OK, EA_OK}, {{0}, {0}}};
    ea__par_run(pp->sh1 ? pp->par : NULL, ea__pp_level_part, &jb);
    for (int q = 0; q < 2; ++q)
      if (jb.st[q]) {
        if (err) *err = jb.err[q];
        return jb.st[q];
      }
    e = fmax(jb.e[0], jb.e[1]);
    N *= 2;
    memcpy(ps, pn, (size_t)(W * (N + 1)) * sizeof(double));
  }
  if (!(e < EA__PP_TOL)) { /* not resolved at 64 intervals: halve the piece */
    if (depth >= 12)
      return ea_error_set(err, EA_ERR_NOCONV,
                          "path statics: the splines do not reach 1e-10 (segment %d, %.3g "
                          "over %.3g m)",
                          j + 1, e, hi - lo);
    const double mid = 0.5 * (lo + hi);
    /* the chain restarts at lo: its sample there */
    double q[3], dq[3];
    ea__pp_q(pl, j, lo, q, dq);
    guess[EA_P_ALPHA] = q[1];
    memcpy(guess + 1, ps, 3 * sizeof(double));
    if ((st = ea__pp_piece(pl, j, lo, mid, guess, have, depth + 1, n, err_est, err))) return st;
    return ea__pp_piece(pl, j, mid, hi, guess, have, depth + 1, n, err_est, err);
  }
  *err_est = fmax(*err_est, e);
  /* the Hermite samples: from the last one pushed (this piece's lo) or lo */
  double v[5][EA__PP_V];
  for (int i = 0; i <= 4; ++i)
    ea__pp_cheb_at(&ch, lo + (hi - lo) * i / 4.0, v[i]);
  if (*n > pp->soff[j]) {
    v[0][0] = pp->ssig[*n - 1];
    memcpy(v[0] + 1, pp->sp + 3 * (*n - 1), 3 * sizeof(double));
    memcpy(v[0] + 4, pp->sdp + 3 * (*n - 1), 3 * sizeof(double));
    memcpy(v[0] + 7, pp->spa + 6 * (*n - 1), 6 * sizeof(double));
  } else if ((st = ea__pp_push(pp, n, v[0], j, err))) {
    return st;
  }
  v[4][0] = hi;
  double herr = 0.0;
  for (int i = 0; i < 4; ++i)
    if ((st = ea__pp_refine(pl, &ch, j, v[i], v[i + 1], 0, n, &herr, err))) return st;
  *err_est = fmax(*err_est, herr);
  return EA_OK;
}

/* Segment j's geometry as the samples' key: start, direction, length, start sigma. */
static void ea__pp_seg_key(const ea_planner_t *pl, int j, double key[8]) {
  for (int c = 0; c < 3; ++c) {
    key[c] = pl->segA[j][c];
    key[3 + c] = pl->segD[j][c];
  }
  key[6] = pl->segLen[j];
  key[7] = pl->pp->sig0[j];
}

/* Build the statics splines of every segment (4 intervals, each bisected until its error
 * estimate is below EA__PP_TOL); also checks the path's admissibility (tension, torque,
 * shoulder range) at the samples and the spline's extrema between them. */
ea_status_t ea__pp_build_splines(ea_planner_t *pl, ea_error_t *err) {
  ea__pp_t *pp = pl->pp;
  if (pl->K > 0) ea__plan_dyn_pp_forget(pl); /* the defects kept at sigma values */
  pp->jv_valid = 0;                          /* and the Jacobian */
  if (pp->sh1) {                             /* the worker's shooter: the planner's load */
    const ea_load_t load = {pl->tip_mass};
    ea_shooter_set_load(pp->sh1, &load);
  }
  const ea_task_t *t = &pl->task;
  int n = 0;
  double err_est = 0.0;
  double guess[EA_NP];
  int have = 0;
  /* the leading segments whose samples hold as they are: same arm, tip mass, base angle and
   * geometry (an update of the limits keeps all, a moved goal of a polyline all but the last) */
  int j0 = 0;
  if (pp->key_nseg > 0 && ea_arm_equal(&pp->key_arm, &t->arm) && pp->key_tip_mass == pl->tip_mass &&
      pp->key_base == pl->base_fixed)
    for (; j0 < pl->n_seg && j0 < pp->key_nseg; ++j0) {
      double key[8];
      ea__pp_seg_key(pl, j0, key);
      if (memcmp(key, pp->key_seg[j0], sizeof key)) break;
      err_est = fmax(err_est, pp->key_err[j0]);
    }
  pp->key_nseg = 0; /* invalid until the build ends */
  if (j0 > 0) {
    n = pp->soff[j0];
    double q[3], dq[3];
    ea__pp_q(pl, j0 - 1, pp->ssig[n - 1], q, dq);
    guess[EA_P_ALPHA] = q[1];
    memcpy(guess + 1, pp->sp + 3 * (n - 1), 3 * sizeof(double));
    have = 1;
  } else if (pp->have_first && pl->n_seg > 0) {
    /* an update: the previous first sample, when the new one is near it in (L_c, alpha) */
    double q[3], dq[3];
    ea__pp_q(pl, 0, pp->sig0[0], q, dq);
    if (fabs(q[0] - pp->q_first[0]) < 0.05 && fabs(q[1] - pp->q_first[1]) < 0.2) {
      memcpy(guess, pp->g_first, sizeof guess);
      have = 1;
    }
  }
  for (int j = j0; j < pl->n_seg; ++j) {
    const double a = pp->sig0[j], len = pl->segLen[j];
    pp->soff[j] = n;
    double seg_err = 0.0;
    if (len < 1e-12) { /* a point: 9 equal samples, as the spline wants h > 0 */
      for (int i = 0; i <= 8; ++i) {
        double vi[EA__PP_V];
        vi[0] = a;
        ea_status_t st = ea__pp_statics(pl, j, a, guess, &have, vi + 1, vi + 4, vi + 7, err);
        if (!st) st = ea__pp_push(pp, &n, vi, j, err);
        if (!st && i == 0 && j == 0) ea__pp_keep_first(pl, a, guess);
        if (st) return st;
      }
    } else {
      ea_status_t st = ea__pp_piece(pl, j, a, a + len, guess, &have, 0, &n, &seg_err, err);
      if (st) return st;
    }
    /* guess: the segment's end, where the next one starts */
    ea__pp_seg_key(pl, j, pp->key_seg[j]);
    pp->key_err[j] = seg_err;
    err_est = fmax(err_est, seg_err);
  }
  pp->key_nseg = pl->n_seg;
  pp->key_arm = t->arm;
  pp->key_tip_mass = pl->tip_mass;
  pp->key_base = pl->base_fixed;
  pp->ns = n;
  pp->soff[pl->n_seg] = n;
  pp->spline_err = err_est;
  /* admissibility along the path */
  const ea_task_limits_t *l = &t->limits;
  for (int j = 0; j < pl->n_seg; ++j)
    for (int i = pp->soff[j]; i + 1 < pp->soff[j + 1]; ++i)
      for (int q = 0; q <= 8; ++q) {
        const double s = pp->ssig[i] + (pp->ssig[i + 1] - pp->ssig[i]) * q / 8.0;
        double p[3], dp[3];
        ea__pp_spline(pp, j, s, p, dp, NULL);
        const char *why = NULL;
        double v = 0, bnd = 0;
        if (p[0] < l->tension_min)
          why = "tension below tension_min", v = p[0], bnd = l->tension_min;
        else if (p[0] > l->tension_max)
          why = "tension above tension_max", v = p[0], bnd = l->tension_max;
        else if (fabs(t->arm.EI * p[2]) > l->shoulder_torque_max)
          why = "shoulder torque above its limit", v = t->arm.EI * p[2],
          bnd = l->shoulder_torque_max;
        else if (p[1] < t->arm.act.shoulder_angle_min || p[1] > t->arm.act.shoulder_angle_max)
          why = "shoulder angle outside its range", v = p[1],
          bnd = p[1] < t->arm.act.shoulder_angle_min ? t->arm.act.shoulder_angle_min
                                                     : t->arm.act.shoulder_angle_max;
        if (why)
          return ea_error_set(err, EA_ERR_INFEASIBLE,
                              "the path leaves the workspace at %.4g m along it: %s (%.6g, limit "
                              "%.6g)",
                              s, why, v, bnd);
      }
  return EA_OK;
}
