/* The path transcription's geometry (the path coordinate sigma: segment, actuator
 * coordinates and their slopes) and the map from its layout to the knot transcription's. */
#include "path_impl.h"
#include "knot_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- path geometry ------------------------------------------------------ */

/* Segment of sigma (the last one whose start is <= sigma). */
int ea__pp_seg(const ea_planner_t *pl, double sig) {
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

void ea__pp_q(const ea_planner_t *pl, int j, double sig, double q[3], double dq[3]) {
  ea__pp_q2(pl, j, sig, q, dq, NULL);
}

/* Path coordinate of actuator coordinates q on segment j: the tip projected on the segment. */
double ea__pp_sigma_of(const ea_planner_t *pl, int j, const double q[3]) {
  const double b = pl->nq == 3 ? q[2] : pl->base_fixed;
  double P[3];
  ea__plan_tip3(pl, q[0], q[1], b, P, NULL);
  const double *A = pl->segA[j], *D = pl->segD[j];
  const double u = (P[0] - A[0]) * D[0] + (P[1] - A[1]) * D[1] + (P[2] - A[2]) * D[2];
  return pl->pp->sig0[j] + fmin(fmax(u, 0.0), pl->segLen[j]);
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
void ea__pp_expand(const ea_planner_t *pl, const double *xs) {
  ea__pp_t *pp = pl->pp;
  for (int k = 0; k < pl->N; ++k)
    if (ea__pp_knot_dirty(pp, pl, xs, k)) ea__pp_expand_knot(pl, xs, k);
  if (pl->has_tf) pp->xk[EA__ITF(pl)] = xs[pp->itf];
}

/* A modal defect row's path entries (the order of EA__PP_DKEY) and their values in xs (t_f: 0
 * if fixed); returns their count. */
int ea__pp_defect_entries(const ea_planner_t *pl, const double *xs, const ea__row_t *r,
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
int ea__pp_row(const ea_planner_t *pl, const double *xs, const ea__row_t *r, double *value,
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
