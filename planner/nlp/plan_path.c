/* Prescribed paths in the path coordinate (docs/planner.md, "Transcriptions"): on a line or
 * polyline the statics along the path do not depend on the timing, so they are computed once
 * along the path coordinate sigma (arc length of the tip path in the base frame) and the NLP
 * keeps per knot only sigma_k and the rates of the cubic Hermites (L_c, alpha[, base],
 * theta0), plus t_f and the modal states of a task with dynamics. No shooting inside Ipopt.
 *
 * It is a reduced space of the knot transcription (plan_nlp.c): its knot-layout vector x_k is
 * a function of the path vector x_s (L_c, alpha, base = the path's geometry at sigma_k,
 * (T, theta0, kappa0) = the path's statics splines at sigma_k, everything else copied), and
 * every row but the statics and path rows (which hold identically) is the knot transcription's
 * own row evaluated at x_k, its Jacobian mapped by the chain rule. The feasible set is the knot
 * transcription's (the knots on the path, the C2 splines through them), so the plans agree.
 *
 * The statics splines: cubic Hermite in sigma of (T, theta0, kappa0) on a table bisected until
 * each interval's Hermite misses its midpoint by < 16 x 1e-11 (O(h^4): ~1/16 of that between),
 * its samples taken from Chebyshev interpolants of the statics per segment (ea__pp_piece):
 * samples at Chebyshev-Lobatto points, the levels of 8, 16, 32, 64 intervals each checked
 * against the next level's new samples, taken when they miss by < 1e-10 (theta0 [rad], T
 * relative to 1 + T, kappa0 L; 1e-9 left statics residuals of up to 3.8e-9 at the knots of a
 * random line sweep: the plans must hold 1e-9, the knots' too). Measured against independent
 * re-solves between the samples: 5.4e-12 on the paper line, 9.9e-12 on a polyline
 * (test_plan_path; the Hermite bisection of shot samples before: 1.0e-10, and the paper line
 * with its goal moved 5 mm took 131 samples where it takes 33 now). The table also holds dp/dL_c
 * and dp/dalpha per sample (the limits between the knots take the statics' rates from them). An
 * update keeps the samples of the leading segments whose geometry, arm, tip mass and base angle did
 * not change (ea_planner_update of the limits: all of them).
 */
#include "plan_asn_impl.h"
#include "plan_impl.h"
#include "plan_ipm_impl.h"
#include "plan_screen_impl.h"

#include <gsl/gsl_chebyshev.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#define EA__PP_TOL 1e-10
#define EA__PP_MAXS 4096

struct ea__pp {
  int nc;  /* coordinates with a rate per knot: nq + 1 (theta0 last) */
  int nbp; /* path variables per knot: 1 + nc */
  int n, m, nnz, nnz_h, itf, ie0;
  /* path: cumulative sigma at the segment starts, total */
  double sig0[EA_TASK_MAX_VIA + 2], S;
  double bref[EA_TASK_MAX_VIA + 1]; /* base angle at each segment's start (unwrap reference) */
  /* statics splines: ns samples sorted in sigma; per sample p = (T, theta0, kappa0), dp/dsigma */
  int ns, soff[EA_TASK_MAX_VIA + 2]; /* samples; segment j's are soff[j] .. soff[j + 1] - 1 */
  double *ssig, *sp, *sdp;
  double *spa;       /* per sample dp/dL_c, dp/dalpha (the limits between the knots' rates) */
  double spline_err; /* estimated max error (theta0 [rad]; T relative) */
  /* what the samples were built for (ea__pp_update keeps the segments that did not change):
   * per segment its geometry and estimated error; the arm, tip mass and fixed base angle */
  int key_nseg;
  double key_seg[EA_TASK_MAX_VIA + 1][8], key_err[EA_TASK_MAX_VIA + 1];
  double key_tip_mass, key_base;
  ea_arm_t key_arm;
  double g_first[EA_NP], q_first[2]; /* the first sample's statics (an update's warm start) */
  int have_first;
  ea_status_t path_status; /* the path's statics (EA_ERR_INFEASIBLE: it leaves the workspace) */
  char path_msg[512];
  /* knot-layout map: for index i of x_k: path index (-1: none) and kind */
  int *kidx;
  unsigned char *kkind; /* 0 copy, 1 q (coordinate kc), 2 statics (j) */
  unsigned char *kcoord;
  int *kknot;
  double *xk, *xs_last; /* expanded vector, the path vector it was expanded from */
  double *dq;           /* N x (3 + 3): dq/dsigma (L, alpha, base), dp/dsigma (T, theta0, kappa0) */
  double *dq2;          /* N x (3 + 3): their second derivatives */
  double *xkx;          /* knot-layout scratch (the Hessian's differences) */
  /* NLP */
  ea__row_t *rows;
  int *rmap; /* knot planner's row of each row */
  double *x, *xl, *xu, *gl, *gu, *g, *mult_g, *mult_xl, *mult_xu;
  double *x_sol, *mult_g_sol, *mult_xl_sol, *mult_xu_sol, *x0;
  double *g_sol;     /* the rows at x_sol (the active-set Newton's gaps) */
  ea__asn_t *asn;    /* the active-set Newton of a warm start (NULL until the first) */
  ea__screen_t *scr; /* Ipopt's rows (plan_screen.c; NULL until the first Ipopt solve) */
  int *rfam, nfam;   /* each row's family for it: one limit of one coordinate */
  double *xstart;    /* the start of an Ipopt solve (a screened solve's second round) */
  int have_solution;
  /* per knot of the solution: its speed along the path [m/s] and its slopes dq/dsigma (N x 4);
   * its segments' starts (the replanning predictor, ea__pp_predict) */
  double *sd_sol, sig0_sol[EA_TASK_MAX_VIA + 2];
  int vk_sol[EA_TASK_MAX_VIA + 2]; /* its via knots */
  int *irow, *jcol;
  int *hirow, *hjcol, *hpos_start, *hpos;
  ea__row_t *orows;
  double *oweight;
  int n_orows;
  double *gk, *xx; /* knot-layout gradient scratch; perturbed path vector */
  /* with dynamics the rows, Jacobian and Hessian are evaluated in two parts, the rows of the
   * knots below split and the rest (plan_par.c; par NULL: both parts on the caller) */
  ea__par_t *par;
  int split;
  int *jstart;       /* each row's first Jacobian entry */
  double *xkx1;      /* part 1's knot-layout scratch */
  ea_shooter_t *sh1; /* the worker's shooter (the statics samples; NULL without a worker) */
  int dyn_direct;    /* the modal defects' Hessians and cached gradients in this layout directly
                        (ea__plan_dyn_defect_hess_pp; 0: through the knot layout) */
  double *hv1;       /* part 1's Hessian values */
  /* with dynamics the rows' values come with their Jacobian's (one pass over the rows), kept
   * for the Jacobian at the same x */
  double *jv_keep, *jv_x;
  int jv_valid;
  IpoptProblem ip;
  int iter;
};

/* the path layout: knot k's sigma and rates */
#define EA__PS(pp, k) ((k) * (pp)->nbp)
#define EA__PR(pp, k, c) ((k) * (pp)->nbp + 1 + (c)) /* c: 0..nq-1, nq = theta0 */

/* ---- path geometry ------------------------------------------------------ */

/* Segment of sigma (the last one whose start is <= sigma). */
static int ea__pp_seg(const ea_planner_t *pl, double sig) {
  const ea__pp_t *pp = pl->pp;
  int j = 0;
  while (j + 1 < pl->n_seg && sig >= pp->sig0[j + 1])
    ++j;
  return j;
}

/* Actuator coordinates (L_c, alpha, base) at sigma on segment j and their first and (d2q not
 * NULL) second derivatives. */
static void ea__pp_q2(const ea_planner_t *pl, int j, double sig, double q[3], double dq[3],
                      double d2q[3]) {
  const ea__pp_t *pp = pl->pp;
  const ea_arm_t *arm = &pl->task.arm;
  const double u = sig - pp->sig0[j];
  const double *A = pl->segA[j], *D = pl->segD[j];
  const double P[3] = {A[0] + u * D[0], A[1] + u * D[1], A[2] + u * D[2]};
  double X, dX, d2X = 0.0, b, db;
  if (pl->nq == 3) {
    X = hypot(P[0], P[1]);
    dX = X > 1e-12 ? (P[0] * D[0] + P[1] * D[1]) / X : 0.0;
    if (X > 1e-12) d2X = (D[0] * D[0] + D[1] * D[1] - dX * dX) / X;
    b = X > 1e-12 ? atan2(P[1], P[0]) : pp->bref[j];
    while (b - pp->bref[j] > M_PI)
      b -= 2 * M_PI;
    while (b - pp->bref[j] < -M_PI)
      b += 2 * M_PI;
    db = X > 1e-12 ? (P[0] * D[1] - P[1] * D[0]) / (X * X) : 0.0;
  } else {
    const double cb = cos(pl->base_fixed), sb = sin(pl->base_fixed);
    X = P[0] * cb + P[1] * sb;
    dX = D[0] * cb + D[1] * sb;
    b = pl->base_fixed;
    db = 0.0;
  }
  const double du = X - arm->x_c, dw = P[2] - arm->y_c;
  const double L = hypot(du, dw);
  q[0] = L;
  q[1] = atan2(dw, du);
  q[2] = b;
  dq[0] = (du * dX + dw * D[2]) / L;
  dq[1] = (du * D[2] - dw * dX) / (L * L);
  dq[2] = db;
  if (d2q) { /* D is constant along the segment: (du dX + dw D_z)' = dX^2 + du X'' + D_z^2 */
    d2q[0] = (dX * dX + du * d2X + D[2] * D[2] - dq[0] * dq[0]) / L;
    d2q[1] = -dw * d2X / (L * L) - 2.0 * dq[1] * dq[0] / L;
    d2q[2] = X > 1e-12 && pl->nq == 3 ? -2.0 * db * dX / X : 0.0;
  }
}

static void ea__pp_q(const ea_planner_t *pl, int j, double sig, double q[3], double dq[3]) {
  ea__pp_q2(pl, j, sig, q, dq, NULL);
}

/* Path coordinate of actuator coordinates q on segment j: the tip projected on the segment. */
static double ea__pp_sigma_of(const ea_planner_t *pl, int j, const double q[3]) {
  const double b = pl->nq == 3 ? q[2] : pl->base_fixed;
  double P[3];
  ea__plan_tip3(pl, q[0], q[1], b, P, NULL);
  const double *A = pl->segA[j], *D = pl->segD[j];
  const double u = (P[0] - A[0]) * D[0] + (P[1] - A[1]) * D[1] + (P[2] - A[2]) * D[2];
  return pl->pp->sig0[j] + fmin(fmax(u, 0.0), pl->segLen[j]);
}

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
     * re-solves: 8.9e-11 / 9.96e-11 with and without this shortcut; from 1e-8 on: 1.1e-10);
     * ea_planner_update of the paper line's goal moved 5 mm 2.1 -> 1.75 ms (one shot fewer
     * per such sample) */
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

static double ea__herm(double h, double y0, double d0, double y1, double d1, double u, double *dy) {
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
static void ea__pp_spline(const ea__pp_t *pp, int j, double sig, double p[3], double dp[3],
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
     * last two slopes (the paper line with its goal moved 5 mm: 60 -> 57 shots in all) */
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
static ea_status_t ea__pp_build_splines(ea_planner_t *pl, ea_error_t *err) {
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

/* ---- layouts --------------------------------------------------------------- */

/* Expand knot k of the path vector into pp->xk (and the slopes into pp->dq). */
static void ea__pp_expand_knot(const ea_planner_t *pl, const double *xs, int k) {
  ea__pp_t *pp = pl->pp;
  double *xk = pp->xk;
  const double sig = xs[EA__PS(pp, k)];
  const int sg = pl->seg_of_knot[k] >= 0 ? pl->seg_of_knot[k] : ea__pp_seg(pl, sig);
  double q[3], dq[3], d2q[3], p[3], dp[3], d2p[3];
  ea__pp_q2(pl, sg, sig, q, dq, d2q);
  ea__pp_spline(pp, sg, sig, p, dp, d2p);
  double *d = pp->dq + 6 * k, *d2 = pp->dq2 + 6 * k;
  for (int c = 0; c < 3; ++c) {
    d2[c] = d2q[c];
    d2[3 + c] = d2p[c];
  }
  for (int c = 0; c < pl->nq; ++c) {
    xk[EA__IQ(pl, k, c)] = q[c];
    xk[EA__IV(pl, k, c)] = xs[EA__PR(pp, k, c)];
  }
  for (int c = 0; c < 3; ++c) {
    d[c] = dq[c];
    d[3 + c] = dp[c];
    xk[EA__IP(pl, k, c)] = p[c];
  }
  xk[EA__IW(pl, k)] = xs[EA__PR(pp, k, pl->nq)];
  for (int i = 0; i < 2 * pl->K; ++i)
    xk[pl->ie0 + 2 * pl->K * k + i] = xs[pp->ie0 + 2 * pl->K * k + i];
  memcpy(pp->xs_last + EA__PS(pp, k), xs + EA__PS(pp, k), sizeof(double) * (size_t)pp->nbp);
  for (int i = 0; i < 2 * pl->K; ++i)
    pp->xs_last[pp->ie0 + 2 * pl->K * k + i] = xs[pp->ie0 + 2 * pl->K * k + i];
}

static int ea__pp_knot_dirty(const ea__pp_t *pp, const ea_planner_t *pl, const double *xs, int k) {
  if (memcmp(pp->xs_last + EA__PS(pp, k), xs + EA__PS(pp, k), sizeof(double) * (size_t)pp->nbp))
    return 1;
  for (int i = 0; i < 2 * pl->K; ++i)
    if (pp->xs_last[pp->ie0 + 2 * pl->K * k + i] != xs[pp->ie0 + 2 * pl->K * k + i]) return 1;
  return 0;
}

/* Make pp->xk the expansion of xs (only knots whose variables changed; t_f always). */
static void ea__pp_expand(const ea_planner_t *pl, const double *xs) {
  ea__pp_t *pp = pl->pp;
  for (int k = 0; k < pl->N; ++k)
    if (ea__pp_knot_dirty(pp, pl, xs, k)) ea__pp_expand_knot(pl, xs, k);
  if (pl->has_tf) pp->xk[EA__ITF(pl)] = xs[pp->itf];
}

/* A modal defect row's path entries (the order of EA__PP_DKEY) and their values in xs (t_f: 0
 * if fixed); returns their count. */
static int ea__pp_defect_entries(const ea_planner_t *pl, const double *xs, const ea__row_t *r,
                                 int cols[EA__PP_DKEY], double key[EA__PP_DKEY]) {
  const ea__pp_t *pp = pl->pp;
  const int k = r->knot, i = r->coord;
  const int c[EA__PP_DKEY] = {pp->kidx[EA__IE(pl, k, i)],
                              pp->kidx[EA__IED(pl, k, i)],
                              pp->kidx[EA__IE(pl, k + 1, i)],
                              pp->kidx[EA__IED(pl, k + 1, i)],
                              EA__PS(pp, k),
                              EA__PS(pp, k + 1),
                              EA__PR(pp, k, 0),
                              EA__PR(pp, k + 1, 0),
                              EA__PR(pp, k, 1),
                              EA__PR(pp, k + 1, 1),
                              pl->has_tf ? pp->itf : -1};
  for (int q = 0; q < EA__PP_DKEY; ++q) {
    cols[q] = c[q];
    key[q] = c[q] >= 0 ? xs[c[q]] : 0.0;
  }
  return pl->has_tf ? EA__PP_DKEY : EA__PP_DKEY - 1;
}

/* One row at the path vector: the knot row at the expansion, its entries mapped (entries on
 * the same path variable summed, in the order of first appearance); a modal defect's kept by
 * the Hessian at the same values (ea__plan_dyn_defect_hess_pp) when there. */
static int ea__pp_row(const ea_planner_t *pl, const double *xs, const ea__row_t *r, double *value,
                      int *cols, double *vals) {
  ea__pp_t *pp = pl->pp;
  if (pp->dyn_direct && (r->kind == EA__ROW_DYN_DEF_POS || r->kind == EA__ROW_DYN_DEF_VEL)) {
    int dc[EA__PP_DKEY];
    double key[EA__PP_DKEY];
    const int n = ea__pp_defect_entries(pl, xs, r, dc, key);
    if (ea__plan_dyn_defect_pp_cached(pl, r->knot, r->coord, r->kind == EA__ROW_DYN_DEF_VEL, key,
                                      value, vals)) {
      if (cols) memcpy(cols, dc, sizeof(int) * (size_t)n);
      return n;
    }
  }
  /* only the knots the row can touch (k - 1 .. k + 1) and t_f */
  for (int k = r->knot > 0 ? r->knot - 1 : 0; k <= r->knot + 1 && k < pl->N; ++k)
    if (ea__pp_knot_dirty(pp, pl, xs, k)) ea__pp_expand_knot(pl, xs, k);
  /* (written only when it changed: the two parts of plan_par.c read it at once) */
  if (pl->has_tf && pp->xk[EA__ITF(pl)] != xs[pp->itf]) pp->xk[EA__ITF(pl)] = xs[pp->itf];
  int kc[EA__ROW_MAX], lc[EA__ROW_MAX];
  double kv[EA__ROW_MAX], lv[EA__ROW_MAX];
  const int nk = ea__plan_row_eval(pl, pp->xk, r, value, kc, vals ? kv : NULL);
  int n = 0;
  for (int e = 0; e < nk; ++e) {
    const int i = kc[e], col = pp->kidx[i];
    if (col < 0) continue;
    double f = 1.0;
    if (pp->kkind[i] == 1)
      f = pp->dq[6 * pp->kknot[i] + pp->kcoord[i]];
    else if (pp->kkind[i] == 2)
      f = pp->dq[6 * pp->kknot[i] + 3 + pp->kcoord[i]];
    int q = 0;
    while (q < n && lc[q] != col)
      ++q;
    if (q == n) {
      lc[n] = col;
      lv[n++] = 0.0;
    }
    if (vals) lv[q] += kv[e] * f;
  }
  if (cols) memcpy(cols, lc, sizeof(int) * (size_t)n);
  if (vals) memcpy(vals, lv, sizeof(double) * (size_t)n);
  return n;
}

/* ---- the NLP --------------------------------------------------------------- */

static int64_t ea__pp_key(const ea__pp_t *pp, int i, int j) {
  return ea__hkey(pp->n, i, j);
}

static const ea__row_t *ea__pp_hrow(const ea_planner_t *pl, int r) {
  return r < pl->pp->m ? &pl->pp->rows[r] : &pl->orows[r - pl->pp->m];
}

/* Hessian pieces: the rows and the objective pieces. */
static int ea__pp_npieces(const ea_planner_t *pl) {
  return pl->pp->m + pl->n_orows;
}

/* Structure of the Lagrangian's Hessian: every pair of a row's (or objective piece's)
 * entries (rn[r] of them in rc[r * EA__ROW_MAX ..]). */
static ea_status_t ea__pp_hess_setup(ea_planner_t *pl, const int *rc, const int *rn) {
  ea__pp_t *pp = pl->pp;
  const int nr = ea__pp_npieces(pl);
  size_t cap = 1;
  for (int r = 0; r < nr; ++r) {
    if (!ea__plan_row_curved(ea__pp_hrow(pl, r))) continue;
    const size_t nc = (size_t)rn[r];
    cap += nc * (nc + 1) / 2;
  }
  int64_t *keys = malloc(cap * sizeof *keys);
  pp->hpos_start = calloc((size_t)nr + 1, sizeof *pp->hpos_start);
  if (!keys || !pp->hpos_start) {
    free(keys);
    return EA_ERR_NOMEM;
  }
  size_t nk = 0;
  for (int r = 0; r < nr; ++r) {
    pp->hpos_start[r] = (int)nk;
    if (!ea__plan_row_curved(ea__pp_hrow(pl, r))) continue;
    const int nc = rn[r], *cols = rc + (size_t)r * EA__ROW_MAX;
    for (int a = 0; a < nc; ++a)
      for (int b = 0; b <= a; ++b)
        keys[nk++] = ea__pp_key(pp, cols[a], cols[b]);
  }
  pp->hpos_start[nr] = (int)nk;
  pp->hpos = malloc((nk + 1) * sizeof *pp->hpos);
  const ea_status_t st =
      pp->hpos ? ea__hpattern(keys, nk, pp->n, &pp->nnz_h, &pp->hirow, &pp->hjcol, pp->hpos)
               : EA_ERR_NOMEM;
  free(keys);
  return st;
}

/* Factor of knot-layout entry i in the path layout (d x_k / d x_s) and its curvature. */
static double ea__pp_factor(const ea__pp_t *pp, int i, double *curv) {
  const int k = pp->kknot[i];
  if (pp->kkind[i] == 1) {
    *curv = pp->dq2[6 * k + pp->kcoord[i]];
    return pp->dq[6 * k + pp->kcoord[i]];
  }
  if (pp->kkind[i] == 2) {
    *curv = pp->dq2[6 * k + 3 + pp->kcoord[i]];
    return pp->dq[6 * k + 3 + pp->kcoord[i]];
  }
  *curv = 0.0;
  return 1.0;
}

/* Hessian of g rows (rows[0..g-1], weights w) by the chain rule through the knot layout
 * x_k = phi(x_s): J^T H_k J + sum_i (d row / d x_k,i) phi_i'', with H_k the knot row's
 * (ea__plan_hess_fd_local: differences of its exact gradient at x_k, no spline in the loop)
 * and phi'' the path's and the statics splines' second derivatives in sigma. Added as w at
 * each row's positions hpos[r] (the pairs of ea__pp_row's entries). Consecutive rows on the
 * same knot entries (a mode's two defects) go through the chain rule once, their weighted
 * sum: the map is linear and their positions are the same. */
static void ea__pp_hess_rows(const ea_planner_t *pl, const ea__row_t *rows, const double *w, int g,
                             const int *const *hpos, double *values, double *xx) {
  const ea__pp_t *pp = pl->pp;
  double Hk[EA__HGROUP_MAX][EA__ROW_MAX][EA__ROW_MAX];
  if (pp->dyn_direct &&
      (rows[0].kind == EA__ROW_DYN_DEF_POS || rows[0].kind == EA__ROW_DYN_DEF_VEL)) {
    /* an interval's modal defects: their Hessians in the path variables directly */
    const int k = rows[0].knot;
    const double sig[2] = {pp->xs_last[EA__PS(pp, k)], pp->xs_last[EA__PS(pp, k + 1)]};
    const double *dq[2] = {pp->dq + 6 * k, pp->dq + 6 * (k + 1)};
    const double *d2q[2] = {pp->dq2 + 6 * k, pp->dq2 + 6 * (k + 1)};
    const int n = ea__plan_dyn_defect_hess_pp(pl, pp->xk, sig, dq, d2q, rows, w, g, Hk);
    for (int r = 0; r < g; ++r) {
      if (w[r] == 0.0) continue;
      const int *p = hpos[r];
      for (int a = 0; a < n; ++a)
        for (int b = 0; b <= a; ++b)
          values[*p++] += w[r] * Hk[r][a][b];
    }
    return;
  }
  int kc[EA__HGROUP_MAX][EA__ROW_MAX], nkc[EA__HGROUP_MAX];
  double gk[EA__HGROUP_MAX][EA__ROW_MAX]; /* the knot rows' gradients, in kc[r]'s order */
  ea__plan_hess_fd_local(pl, ea__plan_row_eval, pp->xk, xx, rows, w, g, kc, nkc, Hk, gk);
  for (int r = 0; r < g;) {
    const int nk = nkc[r];
    if (!nk) {
      ++r;
      continue;
    }
    /* rows r .. r + run - 1 share the knot entries: H, grad = their weighted sum */
    int run = 1;
    while (r + run < g && nkc[r + run] == nk &&
           !memcmp(kc[r + run], kc[r], sizeof(int) * (size_t)nk))
      ++run;
    /* the lower triangle (b <= a) of the symmetrised sum */
    double H[EA__ROW_MAX][EA__ROW_MAX], gs[EA__ROW_MAX];
    for (int a = 0; a < nk; ++a) {
      gs[a] = 0.0;
      for (int b = 0; b <= a; ++b)
        H[a][b] = 0.0;
    }
    for (int q = r; q < r + run; ++q) {
      const double wq = w[q], hq = 0.5 * wq;
      for (int a = 0; a < nk; ++a) {
        gs[a] += wq * gk[q][a];
        for (int b = 0; b <= a; ++b)
          H[a][b] += hq * (Hk[q][a][b] + Hk[q][b][a]);
      }
    }
    /* the path entries in ea__pp_row's order, each knot entry's place and factor */
    int lc[EA__ROW_MAX], pos[EA__ROW_MAX], n = 0;
    double f[EA__ROW_MAX], c[EA__ROW_MAX];
    for (int e = 0; e < nk; ++e) {
      const int col = pp->kidx[kc[r][e]];
      pos[e] = -1;
      if (col < 0) continue;
      int q = 0;
      while (q < n && lc[q] != col)
        ++q;
      if (q == n) lc[n++] = col;
      pos[e] = q;
      f[e] = ea__pp_factor(pp, kc[r][e], &c[e]);
    }
    double Hp[EA__ROW_MAX][EA__ROW_MAX];
    for (int a = 0; a < n; ++a)
      for (int b = 0; b <= a; ++b)
        Hp[a][b] = 0.0;
    /* Hp's lower triangle in the path entries' order: an entry (a, b) of H below the diagonal
     * and its mirror (b, a) go to (pa, pb) and (pb, pa), of which one is in it */
    for (int a = 0; a < nk; ++a) {
      const int pa = pos[a];
      if (pa < 0) continue;
      Hp[pa][pa] += gs[a] * c[a] + f[a] * f[a] * H[a][a];
      for (int b = 0; b < a; ++b) {
        const int pb = pos[b];
        if (pb < 0) continue;
        const double v = f[a] * f[b] * H[a][b];
        if (pa > pb)
          Hp[pa][pb] += v;
        else if (pa < pb)
          Hp[pb][pa] += v;
        else
          Hp[pa][pa] += 2.0 * v;
      }
    }
    const int *p = hpos[r];
    for (int a = 0; a < n; ++a)
      for (int b = 0; b <= a; ++b)
        values[*p++] += Hp[a][b];
    r += run;
  }
}

/* The rows' part (ea__par_t's) with dynamics, -1 without. */
static int ea__pp_part(const ea__pp_t *pp, const ea__row_t *r) {
  return pp->split < 0 ? -1 : r->knot >= pp->split;
}

/* One part's work of a callback at x (part -1: all rows; ea__pp_job's). */
typedef struct {
  ea_planner_t *pl;
  const double *x, *lambda;
  double *out;
  double sigma; /* the objective's weight (Hessian) */
  int what;     /* 0 rows' values, 1 Jacobian, 2 Hessian */
} ea__pp_job_t;

static void ea__pp_job_part(void *ctx, int part) {
  const ea__pp_job_t *jb = ctx;
  ea_planner_t *pl = jb->pl;
  ea__pp_t *pp = pl->pp;
  if (jb->what < 2) {
    /* the values come with the Jacobian's where it is kept (pp->jv_keep) */
    double *jac = jb->what == 1 ? jb->out : pp->jv_keep;
    for (int i = 0; i < pp->m; ++i)
      if (ea__pp_part(pp, &pp->rows[i]) == part)
        ea__pp_row(pl, jb->x, &pp->rows[i], jb->what == 0 ? &jb->out[i] : NULL, NULL,
                   jac ? jac + pp->jstart[i] : NULL);
    return;
  }
  double *values = part == 1 ? pp->hv1 : jb->out, *xx = part == 1 ? pp->xkx1 : pp->xkx;
  for (int r = 0; r < pp->m;) {
    const int g = ea__plan_hess_group_len(pp->rows, r, pp->m);
    if (ea__pp_part(pp, &pp->rows[r]) == part && ea__plan_row_curved(&pp->rows[r])) {
      const int *hp[EA__HGROUP_MAX];
      for (int q = 0; q < g; ++q)
        hp[q] = pp->hpos + pp->hpos_start[r + q];
      ea__pp_hess_rows(pl, &pp->rows[r], jb->lambda + r, g, hp, values, xx);
    }
    r += g;
  }
  /* the objective's pieces (of the part's knots too) */
  for (int o = 0; o < pl->n_orows; ++o) {
    const ea__row_t *row = &pl->orows[o];
    const double w = jb->sigma * pl->oweight[o];
    if (ea__pp_part(pp, row) != part || !ea__plan_row_curved(row)) continue;
    const int *hp[1] = {pp->hpos + pp->hpos_start[pp->m + o]};
    ea__pp_hess_rows(pl, row, &w, 1, hp, values, xx);
  }
}

/* Run a callback's work on all rows: in two parts with dynamics, else at once. The parts'
 * rows (the knots' below pp->split and the rest) share the expansion of x and the tables at the
 * knot pp->split (a row of knot k reads the expansion at knots k - 1 .. k + 1, its model tables
 * at k and k + 1), made current first; every other cache they fill is of their own knots. */
static void ea__pp_job(ea__pp_job_t *jb) {
  ea__pp_t *pp = jb->pl->pp;
  if (pp->split < 0) {
    ea__pp_job_part(jb, -1);
    return;
  }
  ea__pp_expand(jb->pl, jb->x);
  ea__plan_dyn_warm(jb->pl, pp->xk, pp->split);
  ea__par_run(pp->par, ea__pp_job_part, jb);
}

/* Hessian values: the chain rule through the knot layout (ea__pp_hess_rows). */
static void ea__pp_hess_values(ea_planner_t *pl, const double *x, double sigma,
                               const double *lambda, double *values) {
  ea__pp_t *pp = pl->pp;
  memset(values, 0, (size_t)pp->nnz_h * sizeof *values);
  ea__pp_expand(pl, x);
  memcpy(pp->xkx, pp->xk, (size_t)pl->n * sizeof *pp->xk);
  if (pp->split >= 0) {
    memset(pp->hv1, 0, (size_t)pp->nnz_h * sizeof *values);
    memcpy(pp->xkx1, pp->xk, (size_t)pl->n * sizeof *pp->xk);
  }
  ea__pp_job_t jb = {pl, x, lambda, values, sigma, 2};
  ea__pp_job(&jb);
  if (pp->split >= 0)
    for (int i = 0; i < pp->nnz_h; ++i)
      values[i] += pp->hv1[i];
}

int ea__pp_test_dims(const ea_planner_t *pl, int *n, int *m, const double **x_sol, int *nnz_h,
                     const int **hrow, const int **hcol) {
  const ea__pp_t *pp = pl->pp;
  if (!pp) return -1;
  *n = pp->n;
  *m = pp->m;
  *x_sol = pp->x_sol;
  *nnz_h = pp->nnz_h;
  *hrow = pp->hirow;
  *hcol = pp->hjcol;
  return 0;
}

int ea__pp_threads(const ea_planner_t *pl) {
  return pl->pp && pl->pp->par ? 2 : 1;
}

int ea__pp_test_direct(const ea_planner_t *pl) {
  return pl->pp && pl->pp->dyn_direct;
}

int ea__pp_test_row(const ea_planner_t *pl, const double *xs, int r, double *value, int *cols,
                    double *vals) {
  return ea__pp_row(pl, xs, &pl->pp->rows[r], value, cols, vals);
}

void ea__pp_test_hess(ea_planner_t *pl, const double *xs, double sigma, const double *lambda,
                      double *values) {
  ea__pp_hess_values(pl, xs, sigma, lambda, values);
}

static Bool ea__pp_cb_f(Index n, Number *x, Bool new_x, Number *f, UserDataPtr ud) {
  ea_planner_t *pl = ud;
  (void)n, (void)new_x;
  const double t0 = ea__mono_s();
  ea__pp_expand(pl, x);
  double v = 0.0;
  for (int i = 0; i < pl->n_terms; ++i)
    v += pl->terms[i].weight * pl->terms[i].value(pl, pl->pp->xk);
  *f = v;
  pl->t_callbacks += ea__mono_s() - t0;
  return isfinite(v);
}

static Bool ea__pp_cb_grad_f(Index n, Number *x, Bool new_x, Number *g, UserDataPtr ud) {
  ea_planner_t *pl = ud;
  ea__pp_t *pp = pl->pp;
  (void)new_x;
  const double t0 = ea__mono_s();
  ea__pp_expand(pl, x);
  memset(pp->gk, 0, (size_t)pl->n * sizeof *pp->gk);
  for (int i = 0; i < pl->n_terms; ++i)
    pl->terms[i].grad(pl, pp->xk, pl->terms[i].weight, pp->gk);
  memset(g, 0, (size_t)n * sizeof *g);
  for (int i = 0; i < pl->n; ++i) {
    if (pp->gk[i] == 0.0 || pp->kidx[i] < 0) continue;
    double f = 1.0;
    if (pp->kkind[i] == 1)
      f = pp->dq[6 * pp->kknot[i] + pp->kcoord[i]];
    else if (pp->kkind[i] == 2)
      f = pp->dq[6 * pp->kknot[i] + 3 + pp->kcoord[i]];
    g[pp->kidx[i]] += pp->gk[i] * f;
  }
  pl->t_callbacks += ea__mono_s() - t0;
  return TRUE;
}

static Bool ea__pp_cb_g(Index n, Number *x, Bool new_x, Index m, Number *g, UserDataPtr ud) {
  ea_planner_t *pl = ud;
  (void)n, (void)new_x, (void)m;
  const double t0 = ea__mono_s();
  ea__pp_t *pp = pl->pp;
  ea__pp_job_t jb = {pl, x, NULL, g, 0.0, 0};
  ea__pp_job(&jb);
  if (pp->jv_keep) {
    memcpy(pp->jv_x, x, (size_t)pp->n * sizeof *x);
    pp->jv_valid = 1;
  }
  if (pl->info) pl->info->evals_g++;
  pl->t_callbacks += ea__mono_s() - t0;
  return TRUE;
}

static Bool ea__pp_cb_jac(Index n, Number *x, Bool new_x, Index m, Index nele, Index *iRow,
                          Index *jCol, Number *values, UserDataPtr ud) {
  ea_planner_t *pl = ud;
  ea__pp_t *pp = pl->pp;
  (void)n, (void)new_x, (void)m, (void)nele;
  if (!values) {
    memcpy(iRow, pp->irow, (size_t)pp->nnz * sizeof *iRow);
    memcpy(jCol, pp->jcol, (size_t)pp->nnz * sizeof *jCol);
    return TRUE;
  }
  const double t0 = ea__mono_s();
  if (pp->jv_valid && !memcmp(pp->jv_x, x, (size_t)pp->n * sizeof *x)) {
    memcpy(values, pp->jv_keep, (size_t)pp->nnz * sizeof *values); /* the rows' pass had them */
  } else {
    ea__pp_job_t jb = {pl, x, NULL, values, 0.0, 1};
    ea__pp_job(&jb);
  }
  if (pl->info) pl->info->evals_jac++;
  pl->t_callbacks += ea__mono_s() - t0;
  return TRUE;
}

static Bool ea__pp_cb_h(Index n, Number *x, Bool new_x, Number of, Index m, Number *lambda,
                        Bool new_lambda, Index nele, Index *iRow, Index *jCol, Number *values,
                        UserDataPtr ud) {
  ea_planner_t *pl = ud;
  ea__pp_t *pp = pl->pp;
  (void)n, (void)new_x, (void)m, (void)new_lambda, (void)nele;
  if (!values) {
    memcpy(iRow, pp->hirow, (size_t)pp->nnz_h * sizeof *iRow);
    memcpy(jCol, pp->hjcol, (size_t)pp->nnz_h * sizeof *jCol);
    return TRUE;
  }
  const double t0 = ea__mono_s();
  ea__pp_hess_values(pl, x, of, lambda, values);
  pl->t_callbacks += ea__mono_s() - t0;
  return TRUE;
}

/* Is pp->x (with the multipliers in pp->mult_*) already a KKT point to the solver's tolerances,
 * unscaled (ea__kkt_ok in plan_solve.c, the same test for the knot transcription)? A warm start
 * from the planner's own solution of an unchanged problem, or of one whose change left it
 * optimal (a limit loosened that was not active), then needs no Ipopt solve: Ipopt would set
 * up its algorithm and MUMPS' analysis and take one iteration (6-12 ms at 100 knots). */
static int ea__pp_kkt_ok_tol(ea_planner_t *pl, double dtol) {
  ea__pp_t *pp = pl->pp;
  const ea_task_t *t = &pl->task;
  const double ptol = fmax(1e-9, t->solver.constr_tol);
  double *x = pp->x, *r = pp->xx;
  for (int i = 0; i < pp->n; ++i)
    if (x[i] < pp->xl[i] - ptol || x[i] > pp->xu[i] + ptol) return 0;
  if (!ea__pp_cb_g(pp->n, x, TRUE, pp->m, pp->g, pl)) return 0;
  for (int i = 0; i < pp->m; ++i) {
    if (!(pp->g[i] >= pp->gl[i] - ptol && pp->g[i] <= pp->gu[i] + ptol)) return 0;
    if (pp->gl[i] == pp->gu[i]) continue;
    /* Ipopt's sign: lambda > 0 at the upper bound, < 0 at the lower */
    const double lam = pp->mult_g[i];
    const double gap = lam > 0 ? pp->gu[i] - pp->g[i] : pp->g[i] - pp->gl[i];
    if (fabs(lam) * fmin(gap, 1e19) > dtol) return 0;
  }
  double *jv = malloc(sizeof(double) * (size_t)(pp->nnz + 1));
  int ok = jv && ea__pp_cb_grad_f(pp->n, x, FALSE, r, pl) &&
           ea__pp_cb_jac(pp->n, x, FALSE, pp->m, pp->nnz, NULL, NULL, jv, pl);
  if (ok) {
    for (int e = 0; e < pp->nnz; ++e)
      r[pp->jcol[e]] += jv[e] * pp->mult_g[pp->irow[e]];
    for (int i = 0; i < pp->n && ok; ++i) {
      if (pp->xl[i] == pp->xu[i]) continue; /* fixed: Ipopt removes it */
      ok = pp->mult_xl[i] >= 0.0 && pp->mult_xu[i] >= 0.0 &&
           fabs(r[i] - pp->mult_xl[i] + pp->mult_xu[i]) <= dtol &&
           pp->mult_xl[i] * fmin(x[i] - pp->xl[i], 1e19) <= dtol &&
           pp->mult_xu[i] * fmin(pp->xu[i] - x[i], 1e19) <= dtol;
    }
  }
  free(jv);
  return ok;
}

static int ea__pp_kkt_ok(ea_planner_t *pl) {
  return ea__pp_kkt_ok_tol(pl, pl->task.solver.tol);
}

/* A warm start solved without Ipopt: the active-set Newton (plan_asn.c) from pp->x with the old
 * plan's multipliers and active set, taken when the result passes the KKT test of the whole
 * problem (ea__pp_kkt_ok). 1: pp->x and pp->mult_* are the solution; 0: they are the start
 * again (restored from pp->x0 and the old plan's multipliers). */
/* The last plan's multipliers as the current ones (a warm start's). */
static void ea__pp_mult_from_sol(ea__pp_t *pp) {
  memcpy(pp->mult_g, pp->mult_g_sol, (size_t)pp->m * sizeof *pp->x);
  memcpy(pp->mult_xl, pp->mult_xl_sol, (size_t)pp->n * sizeof *pp->x);
  memcpy(pp->mult_xu, pp->mult_xu_sol, (size_t)pp->n * sizeof *pp->x);
}

/* The workspace of the active-set Newton and the interior point (plan_asn.c, plan_ipm.c) on the
 * path NLP: 0, or -1 (out of memory). */
static int ea__pp_asn(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  if (!pp->asn) {
    const ea__asn_nlp_t nlp = {.n = pp->n,
                               .m = pp->m,
                               .nnz_j = pp->nnz,
                               .nnz_h = pp->nnz_h,
                               .xl = pp->xl,
                               .xu = pp->xu,
                               .gl = pp->gl,
                               .gu = pp->gu,
                               .jrow = pp->irow,
                               .jcol = pp->jcol,
                               .hrow = pp->hirow,
                               .hcol = pp->hjcol,
                               .f = ea__pp_cb_f,
                               .grad_f = ea__pp_cb_grad_f,
                               .g = ea__pp_cb_g,
                               .jac = ea__pp_cb_jac,
                               .h = ea__pp_cb_h,
                               .ud = pl,
                               .hess_last = pl->K == 0};
    if (!(pp->asn = ea__asn_alloc(&nlp))) return -1;
  }
  return 0;
}

/* A cold start solved without Ipopt: the interior point of plan_ipm.c from pp->x with the
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
   * default): with 1e-6 the rows the time-optimal guess holds at their limits gave pivots so
   * small that in 5-7 of the line sweep's ~100 plans (test_plan_sweep) no raise of the
   * diagonals made the first solve refine (they went to Ipopt), with 1e-3 or 1e-2 none; 1e-2
   * took the paper line 10 -> 9 iterations, the sweep 1052 -> 1002; the start itself 1e-2
   * inside: 25. From a plan file that holds the task's rows (mu_init 1e-7) 1e-6: the paper
   * line's own file in 5 iterations, 16 with 1e-2 */
  ea__ipm_opt_t o;
  ea__plan_ipm_opt(pl, mu_init, mu_init < 1e-6 ? 1e-6 : 1e-2, &o);
  memcpy(pp->x0, pp->x, (size_t)pp->n * sizeof *pp->x);
  const int rc = ea__ipm_solve(pp->asn, &o, pp->x, pp->mult_g, pp->mult_xl, pp->mult_xu, iters);
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

static Bool ea__pp_cb_iter(Index alg_mod, Index iter, Number obj, Number inf_pr, Number inf_du,
                           Number mu, Number d_norm, Number reg, Number alpha_du, Number alpha_pr,
                           Index ls, UserDataPtr ud) {
  ea_planner_t *pl = ud;
  (void)alg_mod, (void)obj, (void)inf_pr, (void)inf_du, (void)mu, (void)d_norm, (void)reg;
  (void)alpha_du, (void)alpha_pr, (void)ls;
  pl->pp->iter = iter;
  return ea__mono_s() - pl->t_start < pl->max_time ? TRUE : FALSE;
}

void ea__pp_free(ea__pp_t *pp) {
  if (!pp) return;
  if (pp->ip) FreeIpoptProblem(pp->ip);
  free(pp->ssig);
  free(pp->spa);
  free(pp->sp);
  free(pp->sdp);
  free(pp->kidx);
  free(pp->kkind);
  free(pp->kcoord);
  free(pp->kknot);
  free(pp->xk);
  free(pp->xs_last);
  free(pp->dq);
  free(pp->dq2);
  free(pp->xkx);
  ea__par_free(pp->par);
  ea_shooter_free(pp->sh1);
  free(pp->jstart);
  free(pp->xkx1);
  free(pp->hv1);
  free(pp->jv_keep);
  free(pp->jv_x);
  free(pp->rows);
  free(pp->rmap);
  free(pp->x);
  free(pp->xl);
  free(pp->xu);
  free(pp->gl);
  free(pp->gu);
  free(pp->g);
  free(pp->mult_g);
  free(pp->mult_xl);
  free(pp->mult_xu);
  free(pp->x_sol);
  free(pp->mult_g_sol);
  free(pp->mult_xl_sol);
  free(pp->mult_xu_sol);
  free(pp->x0);
  free(pp->xstart);
  free(pp->g_sol);
  ea__asn_free(pp->asn);
  ea__screen_free(pp->scr);
  free(pp->rfam);
  free(pp->sd_sol);
  free(pp->irow);
  free(pp->jcol);
  free(pp->hirow);
  free(pp->hjcol);
  free(pp->hpos_start);
  free(pp->hpos);
  free(pp->gk);
  free(pp->xx);
  free(pp);
}

int ea__pp_supported(const ea_planner_t *pl) {
  const ea_task_t *t = &pl->task;
  if (t->solver.transcription == EA_TASK_TRANSCRIPTION_KNOTS) return 0;
  if (t->path == EA_TASK_PATH_FREE) return 0;
  /* with dynamics (auto) the path when the own interior point solves it (one model): the
   * same iterations within 1-3 and less time on every measured task (no statics shots; the
   * at-rest paper line about 44 -> 34 ms); with Ipopt (solver.nlp: ipopt, robust corner
   * models) the knots: fewer Ipopt iterations and less time on every measured task, the same
   * durations to 1e-5 (bench_dyn; paper line at rest 34 -> 27 iterations, payload 0.25 37 ->
   * 27, 0.5 34 -> 25, robust 72 -> 40) */
  if (t->solver.transcription == EA_TASK_TRANSCRIPTION_AUTO && t->dynamics.modes > 0 &&
      (t->solver.nlp_ipopt || pl->M > 1))
    return 0;
  /* the frequency-model rows and the f1-weighted min_vibration stay with the knots */
  if (pl->fm) return 0;
  /* the derivative checker: the knots, unless the path is asked for (its own check) */
  if (t->solver.derivative_test && t->solver.transcription != EA_TASK_TRANSCRIPTION_PATH) return 0;
  for (int j = 0; j < pl->n_seg; ++j)
    if (!(pl->segLen[j] > 1e-9)) return 0;
  return 1;
}

/* The path's statics splines (T, theta0, kappa0) at fraction frac of segment j, for the cold
 * guess (pl->guess_statics); 0 when there are none to offer (the knot fallback, or the path
 * left the workspace). */
static int ea__pp_statics_at(const ea_planner_t *pl, int j, double frac, double p[3]) {
  const ea__pp_t *pp = pl->pp;
  if (!pp || pl->pp_off || pp->path_status) return 0;
  double dp[3];
  ea__pp_spline(pp, j, pp->sig0[j] + frac * pl->segLen[j], p, dp, NULL);
  return 1;
}

/* Path-vector bounds from the knot planner's (rates, t_f, modal copied; sigma within its
 * knot's segment, pinned at the points). */
static void ea__pp_bounds(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  for (int k = 0; k < pl->N; ++k) {
    const int sg = pl->seg_of_knot[k];
    double lo, hi;
    if (sg >= 0) {
      lo = pp->sig0[sg];
      hi = pp->sig0[sg] + pl->segLen[sg];
    } else { /* a point: pinned */
      int j = 0;
      while (j < pl->task.n_via + 2 && pl->via_knot[j] != k)
        ++j;
      lo = hi = j == 0 ? 0.0 : (j >= pl->task.n_via + 1 ? pp->S : pp->sig0[j]);
    }
    pp->xl[EA__PS(pp, k)] = lo;
    pp->xu[EA__PS(pp, k)] = hi;
    for (int c = 0; c < pl->nq; ++c) {
      pp->xl[EA__PR(pp, k, c)] = pl->xl[EA__IV(pl, k, c)];
      pp->xu[EA__PR(pp, k, c)] = pl->xu[EA__IV(pl, k, c)];
    }
    pp->xl[EA__PR(pp, k, pl->nq)] = pl->xl[EA__IW(pl, k)];
    pp->xu[EA__PR(pp, k, pl->nq)] = pl->xu[EA__IW(pl, k)];
    for (int i = 0; i < 2 * pl->K; ++i) {
      pp->xl[pp->ie0 + 2 * pl->K * k + i] = pl->xl[pl->ie0 + 2 * pl->K * k + i];
      pp->xu[pp->ie0 + 2 * pl->K * k + i] = pl->xu[pl->ie0 + 2 * pl->K * k + i];
    }
  }
  if (pl->has_tf) {
    pp->xl[pp->itf] = pl->xl[EA__ITF(pl)];
    pp->xu[pp->itf] = pl->xu[EA__ITF(pl)];
  }
  for (int i = 0; i < pp->m; ++i) { /* the knot planner's rows: their (tightened) bounds */
    pp->gl[i] = pl->gl[pp->rmap[i]];
    pp->gu[i] = pl->gu[pp->rmap[i]];
  }
}

/* The path's cumulative sigma and the base references (after ea__plan_segments). */
static void ea__pp_path(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  const ea_task_t *t = &pl->task;
  double s = 0.0;
  for (int j = 0; j < pl->n_seg; ++j) {
    pp->sig0[j] = s;
    s += pl->segLen[j];
    const ea_task_point_t *a = j == 0 ? &t->start : &t->via[j - 1];
    pp->bref[j] = a->base_angle;
  }
  pp->sig0[pl->n_seg] = s;
  pp->S = s;
}

ea_status_t ea__pp_alloc(ea_planner_t *pl, ea_error_t *err) {
  ea__pp_t *pp = calloc(1, sizeof *pp);
  if (!pp) return ea_error_set(err, EA_ERR_NOMEM, "out of memory (path transcription)");
  pl->pp = pp;
  pl->guess_statics = ea__pp_statics_at;
  const int N = pl->N, K = pl->K;
  pp->nc = pl->nq + 1;
  pp->nbp = 1 + pp->nc;
  pp->itf = N * pp->nbp;
  pp->ie0 = pp->itf + pl->has_tf;
  pp->n = pp->ie0 + 2 * K * N;
  pp->ssig = malloc(sizeof(double) * EA__PP_MAXS);
  pp->sp = malloc(sizeof(double) * 3 * EA__PP_MAXS);
  pp->sdp = malloc(sizeof(double) * 3 * EA__PP_MAXS);
  pp->spa = malloc(sizeof(double) * 6 * EA__PP_MAXS);
  const size_t nk = (size_t)pl->n, n = (size_t)pp->n;
  pp->kidx = malloc(sizeof(int) * nk);
  pp->kkind = calloc(nk, 1);
  pp->kcoord = calloc(nk, 1);
  pp->kknot = calloc(nk, sizeof(int));
  pp->xk = calloc(nk, sizeof(double));
  pp->gk = calloc(nk, sizeof(double));
  pp->xs_last = malloc(sizeof(double) * n);
  pp->dq = calloc((size_t)N * 6, sizeof(double));
  pp->dq2 = calloc((size_t)N * 6, sizeof(double));
  pp->sd_sol = calloc((size_t)N * 4, sizeof(double));
  pp->xkx = calloc(nk, sizeof(double));
  /* rows: the knot planner's, without the statics and path rows */
  pp->rows = malloc(sizeof(ea__row_t) * (size_t)pl->m);
  pp->rmap = malloc(sizeof(int) * (size_t)pl->m);
  pp->gl = malloc(sizeof(double) * (size_t)pl->m);
  pp->gu = malloc(sizeof(double) * (size_t)pl->m);
  double **arr[] = {&pp->x,       &pp->xl,    &pp->xu,          &pp->mult_xl,
                    &pp->mult_xu, &pp->x_sol, &pp->mult_xl_sol, &pp->mult_xu_sol,
                    &pp->x0,      &pp->xx,    &pp->xstart};
  for (size_t i = 0; i < sizeof arr / sizeof *arr; ++i)
    *arr[i] = calloc(n, sizeof(double));
  if (!pp->ssig || !pp->sp || !pp->sdp || !pp->spa || !pp->kidx || !pp->kkind || !pp->kcoord ||
      !pp->kknot || !pp->xk || !pp->gk || !pp->xs_last || !pp->dq || !pp->dq2 || !pp->sd_sol ||
      !pp->xkx || !pp->rows || !pp->rmap || !pp->gl || !pp->gu)
    return ea_error_set(err, EA_ERR_NOMEM, "out of memory (path transcription)");
  for (size_t i = 0; i < sizeof arr / sizeof *arr; ++i)
    if (!*arr[i]) return ea_error_set(err, EA_ERR_NOMEM, "out of memory (path transcription)");
  /* map of the knot layout */
  for (size_t i = 0; i < nk; ++i)
    pp->kidx[i] = -1;
  for (int k = 0; k < N; ++k) {
    for (int c = 0; c < pl->nq; ++c) {
      const int iq = EA__IQ(pl, k, c);
      pp->kidx[iq] = EA__PS(pp, k);
      pp->kkind[iq] = 1;
      pp->kcoord[iq] = (unsigned char)c;
      pp->kknot[iq] = k;
      pp->kidx[EA__IV(pl, k, c)] = EA__PR(pp, k, c);
    }
    for (int j = 0; j < 3; ++j) {
      const int ip = EA__IP(pl, k, j);
      pp->kidx[ip] = EA__PS(pp, k);
      pp->kkind[ip] = 2;
      pp->kcoord[ip] = (unsigned char)j;
      pp->kknot[ip] = k;
    }
    pp->kidx[EA__IW(pl, k)] = EA__PR(pp, k, pl->nq);
    for (int i = 0; i < 2 * K; ++i)
      pp->kidx[pl->ie0 + 2 * K * k + i] = pp->ie0 + 2 * K * k + i;
  }
  if (pl->has_tf) pp->kidx[EA__ITF(pl)] = pp->itf;
  int m = 0;
  for (int i = 0; i < pl->m; ++i) {
    const int kind = pl->rows[i].kind;
    if (kind <= EA__ROW_STATICS_Y || kind == EA__ROW_PATH_NORMAL || kind == EA__ROW_PATH_PROGRESS)
      continue;
    pp->rmap[m] = i;
    pp->rows[m++] = pl->rows[i];
  }
  pp->m = m;
  pp->g = calloc((size_t)m + 1, sizeof(double));
  pp->mult_g = calloc((size_t)m + 1, sizeof(double));
  pp->mult_g_sol = calloc((size_t)m + 1, sizeof(double));
  pp->g_sol = calloc((size_t)m + 1, sizeof(double));
  if (!pp->g || !pp->mult_g || !pp->mult_g_sol || !pp->g_sol)
    return ea_error_set(err, EA_ERR_NOMEM, "out of memory (path transcription)");
  ea__pp_path(pl);
  /* a worker (plan_par.c) when the task allows two threads (solver.threads) and the machine
   * has two processors: the statics samples' refinement levels, the cold guess beside the
   * interior point's preparation and, with dynamics, the rows' evaluations in two parts */
  const int th = pl->task.solver.threads;
  if (th == 2 || (th == 0 && ea__par_cpus() >= 2)) {
    pp->par = ea__par_new();
    if (pp->par && ea_shooter_alloc(&pl->task.arm, NULL, &pp->sh1, NULL)) pp->sh1 = NULL;
  }
  ea_error_t e = {0};
  pp->path_status = ea__pp_build_splines(pl, &e);
  snprintf(pp->path_msg, sizeof pp->path_msg, "%s", e.msg);
  if (pp->path_status && pp->path_status != EA_ERR_INFEASIBLE)
    return ea_error_set(err, pp->path_status, "%s", e.msg);
  if (pp->path_status) { /* a flat spline for the structure: the error comes at the solve */
    pp->key_nseg = 0;    /* not the path's samples */
    for (int j = 0; j < pl->n_seg; ++j) {
      pp->soff[j] = 2 * j;
      pp->ssig[2 * j] = pp->sig0[j];
      pp->ssig[2 * j + 1] = pp->sig0[j] + fmax(pl->segLen[j], 1e-9);
    }
    pp->ns = pp->soff[pl->n_seg] = 2 * pl->n_seg;
    memset(pp->sp, 0, sizeof(double) * 3 * (size_t)pp->ns);
    memset(pp->sdp, 0, sizeof(double) * 3 * (size_t)pp->ns);
    memset(pp->spa, 0, sizeof(double) * 6 * (size_t)pp->ns);
  }
  ea__pp_bounds(pl);
  /* a feasible-looking x for the structure: the midpoints of the bounds */
  for (size_t i = 0; i < n; ++i)
    pp->x[i] = isfinite(pp->xl[i]) && isfinite(pp->xu[i]) && pp->xu[i] < 1e19
                   ? 0.5 * (pp->xl[i] + pp->xu[i])
                   : 0.0;
  if (pl->has_tf) pp->x[pp->itf] = 1.0;
  memset(pp->xs_last, 0xff, sizeof(double) * n); /* NaN: every knot dirty */
  /* every row's and objective piece's entries, once: the Jacobian's and the Hessian's
   * structure */
  const int npc = ea__pp_npieces(pl);
  int *rc = malloc(sizeof(int) * (size_t)(npc + 1) * EA__ROW_MAX);
  int *rn = malloc(sizeof(int) * (size_t)(npc + 1));
  if (!rc || !rn) {
    free(rc);
    free(rn);
    return ea_error_set(err, EA_ERR_NOMEM, "out of memory");
  }
  pp->nnz = 0;
  for (int r = 0; r < npc; ++r) {
    rn[r] = ea__pp_row(pl, pp->x, ea__pp_hrow(pl, r), NULL, rc + (size_t)r * EA__ROW_MAX, NULL);
    if (r < m) pp->nnz += rn[r];
  }
  pp->irow = malloc(sizeof(int) * (size_t)(pp->nnz + 1));
  pp->jcol = malloc(sizeof(int) * (size_t)(pp->nnz + 1));
  pp->jstart = malloc(sizeof(int) * (size_t)(m + 1));
  ea_status_t st = !pp->irow || !pp->jcol || !pp->jstart ? EA_ERR_NOMEM : EA_OK;
  for (int i = 0, nz = 0; i < m && !st; nz += rn[i++]) {
    pp->jstart[i] = nz;
    for (int j = 0; j < rn[i]; ++j) {
      pp->irow[nz + j] = i;
      pp->jcol[nz + j] = rc[(size_t)i * EA__ROW_MAX + j];
    }
  }
  if (!st) st = ea__pp_hess_setup(pl, rc, rn);
  /* with dynamics: the evaluations in two parts (the rows of the first half of the knots and
   * the rest), the second on a worker thread when the task allows two (solver.threads) and
   * the machine has two processors */
  pp->split = -1;
  if (K > 0) {
    /* the modal defects in the path variables directly where their entries are those of the
     * knot layout's mapped (ea__pp_row: the same order) */
    pp->dyn_direct = 1;
    for (int i = 0; i < m && pp->dyn_direct; ++i) {
      const ea__row_t *r = &pp->rows[i];
      if (r->kind != EA__ROW_DYN_DEF_POS && r->kind != EA__ROW_DYN_DEF_VEL) continue;
      int dc[EA__PP_DKEY];
      double key[EA__PP_DKEY];
      const int nd = ea__pp_defect_entries(pl, pp->x, r, dc, key);
      pp->dyn_direct =
          rn[i] == nd && !memcmp(rc + (size_t)i * EA__ROW_MAX, dc, sizeof(int) * (size_t)nd);
    }
    pp->split = N / 2;
    pp->xkx1 = malloc(sizeof(double) * nk);
    pp->hv1 = malloc(sizeof(double) * (size_t)(pp->nnz_h + 1));
    pp->jv_keep = malloc(sizeof(double) * (size_t)(pp->nnz + 1));
    pp->jv_x = malloc(sizeof(double) * n);
    if (!pp->xkx1 || !pp->hv1 || !pp->jv_keep || !pp->jv_x) st = EA_ERR_NOMEM;
  }
  free(rc);
  free(rn);
  return st ? ea_error_set(err, st, "out of memory") : EA_OK;
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
    ea__ipm_prepare(jb->pl->pp->asn); /* (failing: the solve makes the pattern again) */
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

/* Ipopt's rows (plan_screen.c, EA__SCREEN_BAND and EA__SCREEN_HOLD there). Measured
 * (bench_plan, docs/planner.md): the paper line's Ipopt sees 493 of 692 rows, the same
 * iterations and plan in less time per iteration. */
static ea__screen_t *ea__pp_screen_alloc(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  if (!pp->rfam && !(pp->rfam = malloc(sizeof(int) * (size_t)(pp->m + 1)))) return NULL;
  pp->nfam = ea__plan_row_families(pp->rows, pp->m, pp->rfam);
  const ea__screen_nlp_t nlp = {.n = pp->n,
                                .m = pp->m,
                                .nnz_j = pp->nnz,
                                .nnz_h = pp->nnz_h,
                                .gl = pp->gl,
                                .gu = pp->gu,
                                .jrow = pp->irow,
                                .jcol = pp->jcol,
                                .f = ea__pp_cb_f,
                                .g = ea__pp_cb_g,
                                .grad_f = ea__pp_cb_grad_f,
                                .jac = ea__pp_cb_jac,
                                .h = ea__pp_cb_h,
                                .iter = ea__pp_cb_iter,
                                .ud = pl};
  return ea__screen_alloc(&nlp);
}

static ea_status_t ea__pp_ipopt(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  const ea_task_t *t = &pl->task;
  if (pp->ip) FreeIpoptProblem(pp->ip);
  pp->ip = ea__screen_problem(pp->scr, pp->xl, pp->xu);
  if (!pp->ip) return EA_ERR_BACKEND;
  AddIpoptStrOption(pp->ip, "sb", "yes");
  AddIpoptIntOption(pp->ip, "print_level", t->solver.print_level);
  if (t->solver.print_level >= 5) AddIpoptStrOption(pp->ip, "print_timing_statistics", "yes");
  AddIpoptStrOption(pp->ip, "linear_solver", "mumps");
  AddIpoptIntOption(pp->ip, "mumps_permuting_scaling", 0);
  AddIpoptIntOption(pp->ip, "mumps_pivot_order", 0);    /* deterministic (plan_solve.c) */
  AddIpoptIntOption(pp->ip, "min_refinement_steps", 0); /* as needed (plan_solve.c) */
  AddIpoptStrOption(pp->ip, "hessian_approximation", "exact");
  AddIpoptNumOption(pp->ip, "tol", t->solver.tol);
  AddIpoptNumOption(pp->ip, "constr_viol_tol", t->solver.constr_tol);
  AddIpoptNumOption(pp->ip, "acceptable_tol", fmax(1e-4, t->solver.tol));
  AddIpoptIntOption(pp->ip, "acceptable_iter", 8);
  AddIpoptNumOption(pp->ip, "acceptable_constr_viol_tol", fmax(1e-9, t->solver.constr_tol));
  AddIpoptNumOption(pp->ip, "acceptable_obj_change_tol", 1e-8);
  AddIpoptIntOption(pp->ip, "max_iter", t->solver.max_iter);
  AddIpoptNumOption(pp->ip, "bound_relax_factor", 0.0);
  /* the knots near a pinned point have sigma within 1e-2 of its bound: the default push
   * (1e-2) would move them by more than their distance (EA_PP_DEBUG: from 2.9e-4 to 4.6
   * of infeasibility; 19 -> 14 iterations on the paper line) */
  AddIpoptNumOption(pp->ip, "bound_push", 1e-6);
  AddIpoptNumOption(pp->ip, "bound_frac", 1e-6);
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
static void ea__pp_predict(ea_planner_t *pl) {
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
  if (!ea__pp_cb_g(pp->n, pp->x, TRUE, pp->m, pp->g, pl)) return INFINITY;
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
static void ea__pp_run(ea_planner_t *pl, int warm, int replan, ea_plan_start_t start,
                       int traj_exact, char *tmpl, enum ApplicationReturnStatus *rs, double *obj,
                       int *iters) {
  ea__pp_t *pp = pl->pp;
  AddIpoptStrOption(pp->ip, "warm_start_init_point", warm ? "yes" : "no");
  ea__ipopt_start_options(pp->ip, warm, replan || pl->refining);
  if (tmpl && pl->task.solver.derivative_test)
    ea__deriv_test_options(pp->ip, pl->task.solver.derivative_test == 2, tmpl);
  int mono = !warm && !pl->rom &&
             (start == EA_PLAN_FROM_TRAJ || (start == EA_PLAN_COLD && pl->guess_timed));
  if (mono) memcpy(pp->x0, pp->x, (size_t)pp->n * sizeof *pp->x);
  for (;;) {
    AddIpoptStrOption(pp->ip, "mu_strategy", mono ? "monotone" : "adaptive");
    if (mono) AddIpoptNumOption(pp->ip, "mu_init", traj_exact ? 1e-7 : 1e-4);
    pp->iter = 0;
    *rs =
        ea__screen_solve(pp->scr, pp->ip, pp->x, pp->g, obj, pp->mult_g, pp->mult_xl, pp->mult_xu);
    *iters += pp->iter;
    if (!mono || *rs == Solve_Succeeded || *rs == Solved_To_Acceptable_Level ||
        *rs == User_Requested_Stop)
      break;
    mono = 0;
    memcpy(pp->x, pp->x0, (size_t)pp->n * sizeof *pp->x);
    AddIpoptNumOption(pp->ip, "mu_init", 0.1);
  }
}

ea_status_t ea__pp_solve(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                         ea_plan_info_t *info, enum ApplicationReturnStatus *rs, double *obj,
                         int *iters, ea_error_t *err) {
  ea__pp_t *pp = pl->pp;
  const double t0 = ea__mono_s();
  if (pp->path_status)
    return ea_error_set(err, pp->path_status, "infeasible task: %s", pp->path_msg);
  /* A replan whose limits changed is a cold plan, from the cold guess (timed time-optimally
   * along the path under the new limits), unless the old plan is still a KKT point: from the
   * old plan re-timed into them it took 12-13 iterations instead of 10 (cable speed or
   * acceleration limit -5..-10 % on the paper line; -1 %: 9 instead of 10), the old active
   * set's multipliers being wrong. */
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
  int at_solution = 0; /* the old plan under the new limits */
  if (limits_changed && !pl->task.solver.derivative_test) at_solution = ea__pp_kkt_ok(pl);
  if (limits_changed && !at_solution) {
    start = EA_PLAN_COLD;
    warm = replan = 0;
  }
  /* A previous plan (EA_PLAN_FROM_TRAJ) without dynamics: if it holds this task's rows to
   * 1e-6 it is (nearly) this task's plan, and the barrier starts at 1e-7; otherwise the cold
   * guess, timed along this path, is the better start. Measured on the paper line (bench_plan):
   * the same task's plan file 14 -> 7 iterations, a plan of the goal 5 mm away 22 -> 10 (the
   * cold plan's); the file's plan with mu_init 1e-4 .. 1e-7 took 22-45 iterations there. */
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
  if (!warm && !traj_exact) {
    if (start == EA_PLAN_FROM_TRAJ) {
      if ((st = ea__plan_guess_traj(pl, prev, pl->x, err))) return st;
      ea__plan_dyn_fill(pl, pl->x);
      ea__pp_reduce(pl, pl->x, pp->x);
    } else if (pp->par && !pl->task.solver.derivative_test && !pl->task.solver.nlp_ipopt &&
               !ea__pp_asn(pl)) {
      /* a cold solve by the own interior point with a worker: its KKT pattern and ordering
       * (plan_ipm.c) there while the cold guess is made here */
      ea__pp_guess_job_t jb = {pl, info, err, EA_OK};
      ea__par_run(pp->par, ea__pp_guess_part, &jb);
      if ((st = jb.st)) return st;
    } else if ((st = ea__pp_cold_guess(pl, info, err))) {
      return st;
    }
  }
  info->time_guess_s = ea__mono_s() - t0;
  for (int i = 0; i < pp->n; ++i)
    pp->x[i] = fmax(pp->xl[i], fmin(pp->xu[i], pp->x[i]));
  *iters = 0;
  *rs = Internal_Error;
  char tmpl[64] = "";
  if (!at_solution && warm && !pl->task.solver.derivative_test && ea__pp_kkt_ok(pl))
    at_solution = 1; /* the predicted point is already the solution */
  /* not with dynamics: on the at-rest paper line the Newton gave up after 6 steps for goal
   * moves of 0.2, 1, 2 and 5 mm alike (the knot transcription does not try it either) */
  if (!at_solution && warm && !pl->task.solver.derivative_test && pl->K == 0)
    at_solution = ea__pp_newton_start(pl, &info->newton_steps);
  /* a cold solve, or a replan the active-set Newton gave up: the own interior
   * point first (plan_ipm.c), from the cold guess (a replan's too: from its predicted point
   * the paper line's goal moved 20 mm took 18 iterations instead of the cold guess's 9, its
   * start moved 5 mm 10 instead of 11 but in more time) */
  if (!at_solution && (!warm || replan) && !pl->task.solver.derivative_test &&
      !pl->task.solver.nlp_ipopt) {
    if (replan) {
      memcpy(pp->xstart, pp->x, (size_t)pp->n * sizeof *pp->x); /* the predicted point */
      if ((st = ea__pp_cold_guess(pl, info, err))) return st;
    }
    /* the barrier's start as Ipopt's (ea__pp_run; with dynamics the knot transcription's) */
    at_solution = ea__pp_ipm_start(pl,
                                   traj_exact ? 1e-7
                                   : pl->rom  ? 1e-3
                                              : 1e-4,
                                   &info->ipm_iterations);
    info->ipm_fallback = !at_solution;
    if (at_solution) *iters = info->ipm_iterations;
    if (!at_solution && replan) { /* Ipopt's warm start: the predicted point, the multipliers */
      memcpy(pp->x, pp->xstart, (size_t)pp->n * sizeof *pp->x);
      ea__pp_mult_from_sol(pp);
    }
  }
  if (at_solution) {
    *rs = Solve_Succeeded; /* the start is the solution: no Ipopt problem, no iteration */
    ea__pp_cb_f(pp->n, pp->x, FALSE, obj, pl);
  } else {
    /* the rows Ipopt sees (plan_screen.c): the limit rows whose family stays in the inner half
     * of its range at the start are left out; a solution at which one of them reaches its
     * limit is solved again from the same start with it in */
    if (!pp->scr && !(pp->scr = ea__pp_screen_alloc(pl)))
      return ea_error_set(err, EA_ERR_NOMEM, "out of memory (path transcription)");
    if (pl->task.solver.derivative_test || !pl->task.solver.screen_rows ||
        !ea__pp_cb_g(pp->n, pp->x, TRUE, pp->m, pp->g, pl))
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
      if ((st = ea__pp_ipopt(pl)))
        return ea_error_set(err, st, "Ipopt: cannot create the path problem");
      info->ipopt_rows = ea__screen_rows(pp->scr);
      ea__pp_run(pl, warm, replan, start, traj_exact, round ? NULL : tmpl, rs, obj, iters);
      if (!(*rs == Solve_Succeeded || *rs == Solved_To_Acceptable_Level)) break;
      if (!ea__screen_grow(pp->scr, pp->g, EA__SCREEN_HOLD)) break;
      info->screen_resolves++;
    }
  }
  if (tmpl[0]) {
    info->deriv_errors = ea__deriv_errors(tmpl);
    remove(tmpl);
  }
  const int solved = *rs == Solve_Succeeded || *rs == Solved_To_Acceptable_Level;
  if (solved) {
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
  if (solved) ea__pp_keep_speed(pl);
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
