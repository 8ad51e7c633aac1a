/* The path transcription's setup: does a task qualify, its layout, bounds and rows. */
#include "ipopt_impl.h"
#include "path_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void ea__pp_free(ea__pp_t *pp) {
  if (!pp) return;
  ea__ipopt_free(pp->ip);
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
  ea__kkt_free(pp->kkt);
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
  free(pp->kkt_jv);
  free(pp);
}

int ea__pp_supported(const ea_planner_t *pl) {
  const ea_task_t *t = &pl->task;
  if (t->solver.transcription == EA_TASK_TRANSCRIPTION_KNOTS) return 0;
  if (t->path == EA_TASK_PATH_FREE) return 0;
  /* with dynamics (auto) the path when the own interior point solves it (one model: no
   * statics shots inside the solve); with Ipopt (solver.nlp: ipopt, robust corner models) the
   * knots, where Ipopt takes fewer iterations (docs/planner.md, "Arriving at rest") */
  if (t->solver.transcription == EA_TASK_TRANSCRIPTION_AUTO && t->dynamics.modes > 0 &&
      ((t->solver.engines == EA_PLANNER_ENGINES_IPOPT) || pl->M > 1))
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
void ea__pp_bounds(ea_planner_t *pl) {
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
void ea__pp_path(ea_planner_t *pl) {
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

/* The sizes of the path layout and its arrays (those of the rows after ea__pp_map). 0, or -1
 * (out of memory). */
static int ea__pp_arrays(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
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
    return -1;
  for (size_t i = 0; i < sizeof arr / sizeof *arr; ++i)
    if (!*arr[i]) return -1;
  return 0;
}

/* The map of the knot layout onto the path layout and the rows the path keeps (the knot
 * planner's, without the statics and path rows), with their arrays. 0, or -1 (out of
 * memory). */
static int ea__pp_map(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  const int N = pl->N, K = pl->K;
  const size_t nk = (size_t)pl->n;
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
  return !pp->g || !pp->mult_g || !pp->mult_g_sol || !pp->g_sol ? -1 : 0;
}

/* The Jacobian's and the Hessian's structure from every row's and objective piece's entries
 * at pp->x and, with dynamics, the two-part evaluations' arrays. */
static ea_status_t ea__pp_structure(ea_planner_t *pl) {
  ea__pp_t *pp = pl->pp;
  const int N = pl->N, K = pl->K, m = pp->m;
  const size_t nk = (size_t)pl->n, n = (size_t)pp->n;
  /* every row's and objective piece's entries, once: the Jacobian's and the Hessian's
   * structure */
  const int npc = ea__pp_npieces(pl);
  int *rc = malloc(sizeof(int) * (size_t)(npc + 1) * EA__ROW_MAX);
  int *rn = malloc(sizeof(int) * (size_t)(npc + 1));
  if (!rc || !rn) {
    free(rc);
    free(rn);
    return EA_ERR_NOMEM;
  }
  pp->nnz = 0;
  for (int r = 0; r < npc; ++r) {
    rn[r] = ea__pp_row(pl, pp->x, ea__pp_hrow(pl, r), NULL, rc + (size_t)r * EA__ROW_MAX, NULL);
    if (r < m) pp->nnz += rn[r];
  }
  pp->irow = malloc(sizeof(int) * (size_t)(pp->nnz + 1));
  pp->jcol = malloc(sizeof(int) * (size_t)(pp->nnz + 1));
  pp->jstart = malloc(sizeof(int) * (size_t)(m + 1));
  pp->kkt_jv = malloc(sizeof(double) * (size_t)(pp->nnz + 1));
  ea_status_t st = !pp->irow || !pp->jcol || !pp->jstart || !pp->kkt_jv ? EA_ERR_NOMEM : EA_OK;
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
  return st;
}

ea_status_t ea__pp_alloc(ea_planner_t *pl, ea_error_t *err) {
  ea__pp_t *pp = calloc(1, sizeof *pp);
  if (!pp) return ea_error_set(err, EA_ERR_NOMEM, "out of memory (path transcription)");
  pl->pp = pp;
  pl->guess_statics = ea__pp_statics_at;
  if (ea__pp_arrays(pl) || ea__pp_map(pl))
    return ea_error_set(err, EA_ERR_NOMEM, "out of memory (path transcription)");
  const size_t n = (size_t)pp->n;
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
  const ea_status_t st = ea__pp_structure(pl);
  return st ? ea_error_set(err, st, "out of memory") : EA_OK;
}
