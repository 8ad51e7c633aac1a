/* The Lagrangian Hessian (lower triangle) of the knot transcription (exact-Hessian modes).
 *
 * Statics rows (mode "exact" only): the second derivatives of the shooting map from forward
 * differences of its exact first-order sensitivities (4 extra shots with sensitivities per
 * knot), plus the closed-form curvature of -L_c (cos alpha, sin alpha); the "partial" mode
 * (default) leaves them out. Every other row and objective piece is a small local function
 * with an exact gradient: its Hessian in closed form where its kind has one (ea__plan_row_hess:
 * the Hermite rows, the tension and torque rows with modal parts; ea__plan_dyn_defect_hess: the
 * modal defects), else central differences of the exact gradient. docs/planner.md compares
 * the modes. */
#include "plan_impl.h"
#include "dyn_impl.h"
#include "hess_impl.h"
#include "knot_impl.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static int ea__cmp64(const void *a, const void *b) {
  const int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return x < y ? -1 : x > y;
}

/* Sort nk non-negative keys ascending: least-significant-digit radix sort, 11-bit digits, as
 * many passes as the largest key needs (3 for n up to 77 000 variables); qsort when no
 * scratch can be had. The planner's setup sorts every Hessian pair of a transcription, where
 * qsort's comparisons dominated ea_planner_alloc. */
static void ea__sort_keys(int64_t *keys, size_t nk) {
  int64_t mx = 0;
  for (size_t q = 0; q < nk; ++q)
    if (keys[q] > mx) mx = keys[q];
  int64_t *tmp = nk > 64 ? malloc(nk * sizeof *tmp) : NULL;
  if (!tmp) {
    qsort(keys, nk, sizeof *keys, ea__cmp64);
    return;
  }
  int64_t *src = keys, *dst = tmp;
  for (int shift = 0; shift < 63 && (mx >> shift) > 0; shift += 11) {
    size_t cnt[2048 + 1] = {0};
    for (size_t q = 0; q < nk; ++q)
      ++cnt[((uint64_t)src[q] >> shift & 2047u) + 1];
    for (int d = 0; d < 2048; ++d)
      cnt[d + 1] += cnt[d];
    for (size_t q = 0; q < nk; ++q)
      dst[cnt[(uint64_t)src[q] >> shift & 2047u]++] = src[q];
    int64_t *t = src;
    src = dst;
    dst = t;
  }
  if (src != keys) memcpy(keys, src, nk * sizeof *keys);
  free(tmp);
}

int64_t ea__hkey(int n, int i, int j) {
  if (i < j) {
    const int t = i;
    i = j;
    j = t;
  }
  return (int64_t)i * n + j;
}

static int64_t ea__key(const ea_planner_t *pl, int i, int j) {
  return ea__hkey(pl->n, i, j);
}

ea_status_t ea__hpattern(int64_t *keys, size_t nk, int n, int *nnz, int **irow, int **jcol,
                         int *pos) {
  int64_t *orig = malloc((nk + 1) * sizeof *orig);
  int *rowstart = calloc((size_t)n + 2, sizeof *rowstart);
  *irow = *jcol = NULL;
  if (!orig || !rowstart) goto nomem;
  memcpy(orig, keys, nk * sizeof *keys);
  ea__sort_keys(keys, nk);
  size_t u = 0;
  for (size_t q = 0; q < nk; ++q)
    if (u == 0 || keys[q] != keys[u - 1]) keys[u++] = keys[q];
  *nnz = (int)u;
  *irow = malloc((u + 1) * sizeof **irow);
  *jcol = malloc((u + 1) * sizeof **jcol);
  if (!*irow || !*jcol) goto nomem;
  for (size_t q = 0; q < u; ++q) {
    const int64_t i = keys[q] / n;
    (*irow)[q] = (int)i;
    (*jcol)[q] = (int)(keys[q] - i * n);
    ++rowstart[i + 1];
  }
  for (int i = 0; i < n; ++i)
    rowstart[i + 1] += rowstart[i];
  /* each key's entry: a binary search within its row's few entries (cheaper than one search
   * over all the entries) */
  for (size_t q = 0; q < nk; ++q) {
    const int64_t i64 = orig[q] / n;
    const int i = (int)i64, j = (int)(orig[q] - i64 * n);
    int lo = rowstart[i], hi = rowstart[i + 1] - 1;
    pos[q] = -1;
    while (lo <= hi) {
      const int mid = (lo + hi) / 2;
      if ((*jcol)[mid] < j)
        lo = mid + 1;
      else if ((*jcol)[mid] > j)
        hi = mid - 1;
      else {
        pos[q] = mid;
        break;
      }
    }
  }
  free(orig);
  free(rowstart);
  return EA_OK;
nomem:
  free(orig);
  free(rowstart);
  free(*irow);
  free(*jcol);
  *irow = *jcol = NULL;
  return EA_ERR_NOMEM;
}

static void ea__stat_vars(const ea_planner_t *pl, int k, int v[5]) {
  v[0] = EA__IQ(pl, k, 0);
  v[1] = EA__IQ(pl, k, 1);
  v[2] = EA__IP(pl, k, 0);
  v[3] = EA__IP(pl, k, 1);
  v[4] = EA__IP(pl, k, 2);
}

static const ea__row_t *ea__hrow(const ea_planner_t *pl, int r) {
  return r < pl->m ? &pl->rows[r] : &pl->orows[r - pl->m];
}

void ea__plan_hess_free(ea_planner_t *pl) {
  free(pl->orows);
  free(pl->oweight);
  free(pl->hirow);
  free(pl->hjcol);
  free(pl->hpos_start);
  free(pl->hpos);
  free(pl->hpos_stat);
  free(pl->xx);
  pl->orows = NULL;
  pl->oweight = NULL;
  pl->hirow = pl->hjcol = pl->hpos_start = pl->hpos = pl->hpos_stat = NULL;
  pl->xx = NULL;
}

ea_status_t ea__plan_hess_setup(ea_planner_t *pl) {
  const ea_task_t *t = &pl->task;
  const int N = pl->N;
  /* Objective pieces. */
  int kind = -1;
  double w = 0.0;
  if (t->objective == EA_TASK_MIN_TIME && t->solver.regularization > 0.0)
    kind = EA__ROW_OBJ_ACC, w = t->solver.regularization;
  else if (t->objective == EA_TASK_MIN_EFFORT)
    kind = EA__ROW_OBJ_ACC, w = 1.0;
  else if (t->objective == EA_TASK_MIN_JERK)
    kind = EA__ROW_OBJ_JERK, w = 1.0;
  else if (t->objective == EA_TASK_MIN_VIBRATION)
    kind = EA__ROW_OBJ_VIB, w = 1.0;
  /* min_vibration with dynamics: the model's residual (one piece at the goal) and the
   * acceleration energy as regularization */
  const int dyn_obj = pl->rom && t->objective == EA_TASK_MIN_VIBRATION;
  if (dyn_obj) {
    kind = t->solver.regularization > 0.0 ? EA__ROW_OBJ_ACC : -1;
    w = t->solver.regularization;
  }
  const int per_coord = kind != EA__ROW_OBJ_VIB; /* the vibration piece spans all coordinates */
  pl->n_orows = (kind < 0 ? 0 : (N - 1) * (per_coord ? pl->nq : 1)) + dyn_obj;
  pl->orows = calloc((size_t)pl->n_orows + 1, sizeof *pl->orows);
  pl->oweight = calloc((size_t)pl->n_orows + 1, sizeof *pl->oweight);
  pl->xx = calloc((size_t)pl->n, sizeof *pl->xx);
  if (!pl->orows || !pl->oweight || !pl->xx) return EA_ERR_NOMEM;
  int i = 0;
  if (dyn_obj) {
    pl->orows[i] = (ea__row_t){EA__ROW_OBJ_DYN, 0, N - 1};
    pl->oweight[i++] = 1.0;
  }
  if (kind >= 0)
    for (int k = 0; k + 1 < N; ++k)
      for (int c = 0; c < (per_coord ? pl->nq : 1); ++c) {
        pl->orows[i] = (ea__row_t){(unsigned char)kind, (unsigned char)c, k};
        pl->oweight[i++] = w;
      }
  return EA_OK;
}

/* Out of memory making the pattern: nothing of it kept (the next need tries again). */
static ea_status_t ea__pattern_fail(ea_planner_t *pl, int64_t *keys) {
  free(keys);
  free(pl->hpos_start);
  free(pl->hpos_stat);
  free(pl->hirow);
  free(pl->hjcol);
  pl->hpos_start = pl->hpos_stat = pl->hirow = pl->hjcol = NULL;
  pl->nnz_h = 0;
  return EA_ERR_NOMEM;
}

/* The knot transcription's Hessian pattern and each row's positions in it, made when a knot
 * solve first needs them (ea__ipopt_create, the own interior point's knot solve): a planner
 * that solves in the path coordinate (transcribe/path_*.c, its own pattern) never does; they took
 * half of ea_planner_alloc for the at-rest paper line (~3 of 6 ms). */
ea_status_t ea__plan_hess_pattern(ea_planner_t *pl) {
  if (pl->hpos) return EA_OK;
  const int N = pl->N;
  /* Pairs. */
  const int nr = pl->m + pl->n_orows;
  int cols[EA__ROW_MAX];
  size_t cap = (size_t)15 * N + 1;
  for (int r = 0; r < nr; ++r) {
    const ea__row_t *row = ea__hrow(pl, r);
    if (!ea__plan_row_curved(row)) continue;
    const size_t nc = (size_t)ea__plan_row_eval(pl, pl->x, row, NULL, cols, NULL);
    cap += nc * (nc + 1) / 2;
  }
  int64_t *keys = malloc(cap * sizeof *keys);
  pl->hpos_start = calloc((size_t)nr + 1, sizeof *pl->hpos_start);
  pl->hpos_stat = calloc((size_t)N * 15, sizeof *pl->hpos_stat);
  if (!keys || !pl->hpos_start || !pl->hpos_stat) return ea__pattern_fail(pl, keys);
  size_t nk = 0;
  for (int k = 0; k < N; ++k) {
    int v[5];
    ea__stat_vars(pl, k, v);
    for (int a = 0; a < 5; ++a)
      for (int b = 0; b <= a; ++b)
        keys[nk++] = ea__key(pl, v[a], v[b]);
  }
  const size_t nstat = nk;
  for (int r = 0; r < nr; ++r) {
    pl->hpos_start[r] = (int)(nk - nstat);
    const ea__row_t *row = ea__hrow(pl, r);
    if (!ea__plan_row_curved(row)) continue;
    const int nc = ea__plan_row_eval(pl, pl->x, row, NULL, cols, NULL);
    for (int a = 0; a < nc; ++a)
      for (int b = 0; b <= a; ++b)
        keys[nk++] = ea__key(pl, cols[a], cols[b]);
  }
  pl->hpos_start[nr] = (int)(nk - nstat);
  int *pos = malloc((nk + 1) * sizeof *pos);
  pl->hpos = malloc((nk - nstat + 1) * sizeof *pl->hpos);
  if (!pos || !pl->hpos || ea__hpattern(keys, nk, pl->n, &pl->nnz_h, &pl->hirow, &pl->hjcol, pos)) {
    free(pos);
    free(pl->hpos);
    pl->hpos = NULL;
    return ea__pattern_fail(pl, keys);
  }
  memcpy(pl->hpos_stat, pos, nstat * sizeof *pos);
  memcpy(pl->hpos, pos + nstat, (nk - nstat) * sizeof *pos);
  free(pos);
  free(keys);
  return EA_OK;
}

int ea__plan_hess_group_len(const ea__row_t *rows, int r, int nr) {
  const int k0 = rows[r].kind;
  if (k0 != EA__ROW_DYN_DEF_POS && k0 != EA__ROW_DYN_DEF_VEL) return 1;
  int g = 1;
  while (r + g < nr &&
         (rows[r + g].kind == EA__ROW_DYN_DEF_POS || rows[r + g].kind == EA__ROW_DYN_DEF_VEL) &&
         rows[r + g].knot == rows[r].knot && g < EA__HGROUP_MAX)
    ++g;
  return g;
}

/* Central differences of the exact gradients of rows[0..g-1] over the union of their
 * variables, whose accuracy the ill-conditioned problems need (forward differences did not
 * converge on fine knot grids). */
static void ea__hess_fd(const ea_planner_t *pl, ea__rowfn fn, const double *x, double *xx,
                        const ea__row_t *rows, const double *w, int g, int cols[][EA__ROW_MAX],
                        int *nc, double Hl[][EA__ROW_MAX][EA__ROW_MAX]) {
  double gp[EA__ROW_MAX], gm[EA__ROW_MAX];
  int uni[EA__HGROUP_MAX * EA__ROW_MAX], nu = 0;
  for (int r = 0; r < g; ++r) {
    nc[r] = w[r] != 0.0 ? fn(pl, x, &rows[r], NULL, cols[r], NULL) : 0;
    for (int a = 0; a < nc[r]; ++a) {
      int seen = 0;
      for (int u = 0; u < nu && !seen; ++u)
        seen = uni[u] == cols[r][a];
      if (!seen) uni[nu++] = cols[r][a];
    }
  }
  for (int u = 0; u < nu; ++u) {
    const int v = uni[u];
    const double d = 1e-6 * fmax(1.0, fabs(x[v]));
    for (int sgn = 0; sgn < 2; ++sgn) {
      xx[v] = x[v] + (sgn ? -d : d);
      for (int r = 0; r < g; ++r) {
        int a = 0;
        while (a < nc[r] && cols[r][a] != v)
          ++a;
        if (a == nc[r]) continue;
        fn(pl, xx, &rows[r], NULL, NULL, sgn ? gm : gp);
        for (int b = 0; b < nc[r]; ++b)
          Hl[r][a][b] = sgn ? (Hl[r][a][b] - gm[b]) / (2.0 * d) : gp[b];
      }
    }
    xx[v] = x[v];
  }
}

void ea__plan_hess_fd_local(const ea_planner_t *pl, ea__rowfn fn, const double *x, double *xx,
                            const ea__row_t *rows, const double *w, int g, int cols[][EA__ROW_MAX],
                            int *nc, double Hl[][EA__ROW_MAX][EA__ROW_MAX],
                            double g0[][EA__ROW_MAX]) {
  const int closed = fn == ea__plan_row_eval;
  /* an interval's modal defects: closed form (ea__plan_dyn_defect_hess) */
  if (closed && g > 0 &&
      (rows[0].kind == EA__ROW_DYN_DEF_POS || rows[0].kind == EA__ROW_DYN_DEF_VEL)) {
    ea__plan_dyn_defect_hess(pl, x, rows, w, g, cols, nc, Hl);
  } else {
    /* a row with a closed form of its own (ea__plan_row_hess; -1: none), else differences */
    int n = -1;
    if (closed && g == 1) n = w[0] != 0.0 ? ea__plan_row_hess(pl, x, &rows[0], cols[0], Hl[0]) : 0;
    if (n >= 0)
      nc[0] = n;
    else
      ea__hess_fd(pl, fn, x, xx, rows, w, g, cols, nc, Hl);
  }
  for (int r = 0; r < g && g0; ++r)
    if (nc[r]) fn(pl, x, &rows[r], NULL, NULL, g0[r]);
}

void ea__plan_hess_fd_group(const ea_planner_t *pl, ea__rowfn fn, const double *x, double *xx,
                            const ea__row_t *rows, const double *w, int g, const int *const *hpos,
                            double *values) {
  int cols[EA__HGROUP_MAX][EA__ROW_MAX], nc[EA__HGROUP_MAX];
  double Hl[EA__HGROUP_MAX][EA__ROW_MAX][EA__ROW_MAX];
  ea__plan_hess_fd_local(pl, fn, x, xx, rows, w, g, cols, nc, Hl, NULL);
  for (int r = 0; r < g; ++r) {
    const int *p = hpos[r];
    for (int a = 0; a < nc[r]; ++a)
      for (int b = 0; b <= a; ++b)
        values[*p++] += w[r] * 0.5 * (Hl[r][a][b] + Hl[r][b][a]);
  }
}

ea_status_t ea__plan_hess_values(ea_planner_t *pl, const double *x, double sigma,
                                 const double *lambda, double *values) {
  memset(values, 0, (size_t)pl->nnz_h * sizeof *values);
  ea_status_t st = ea__plan_shoot_all(pl, x, 1);
  if (st) return st;
  const ea_arm_t *arm = &pl->task.arm;
  /* Statics blocks (skipped in the "partial" mode, docs/planner.md). */
  const double t0 = ea__mono_s();
  for (int k = 0; k < pl->N && pl->hess_exact == 1; ++k) {
    const double lk = lambda[3 * k], lx = lambda[3 * k + 1], ly = lambda[3 * k + 2];
    if (lk == 0.0 && lx == 0.0 && ly == 0.0) continue;
    const double Lc = x[EA__IQ(pl, k, 0)], al = x[EA__IQ(pl, k, 1)];
    const double p0[EA_NP] = {al, x[EA__IP(pl, k, 0)], x[EA__IP(pl, k, 1)], x[EA__IP(pl, k, 2)]};
    const double *S0 = pl->S + 16 * k;
    double H[5][5] = {{0}};
    double D[EA_NP][EA_NX * EA_NP]; /* D[j] = d S / d p_j (forward differences) */
    for (int j = 0; j < EA_NP; ++j) {
      double p[EA_NP], xL[EA_NX], S[EA_NX * EA_NP];
      memcpy(p, p0, sizeof p);
      const double d = 1e-7 * fmax(1.0, fabs(p0[j]));
      p[j] += d;
      if ((st = ea_shoot(pl->sh, p, xL, S))) return st;
      for (int e = 0; e < EA_NX * EA_NP; ++e)
        D[j][e] = (S[e] - S0[e]) / d;
    }
    const int xi[3] = {EA_X_KAPPA, EA_X_X, EA_X_Y};
    const double lam[3] = {lk, lx, ly};
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < EA_NP; ++a)
        for (int b = 0; b < EA_NP; ++b)
          H[1 + a][1 + b] += lam[r] * 0.5 * (D[a][xi[r] * EA_NP + b] + D[b][xi[r] * EA_NP + a]);
    /* -L_c cos(alpha), -L_c sin(alpha) */
    H[1][1] += lx * Lc * cos(al) + ly * Lc * sin(al);
    H[1][0] += lx * sin(al) - ly * cos(al);
    H[0][1] = H[1][0];
    int e = 0;
    for (int a = 0; a < 5; ++a)
      for (int b = 0; b <= a; ++b)
        values[pl->hpos_stat[15 * k + e++]] += H[a][b];
  }
  pl->t_statics += ea__mono_s() - t0;
  (void)arm;
  /* Local rows and objective pieces (the modal defects of an interval together: they share
   * its trajectory variables and, in dyn_rows.c, their work). */
  memcpy(pl->xx, x, (size_t)pl->n * sizeof *x);
  for (int r = 0; r < pl->m;) {
    const int g = ea__plan_hess_group_len(pl->rows, r, pl->m);
    const ea__row_t *row = &pl->rows[r];
    if (!ea__plan_row_curved(row)) {
      r += g;
      continue;
    }
    const int *hp[EA__HGROUP_MAX];
    for (int q = 0; q < g; ++q)
      hp[q] = pl->hpos + pl->hpos_start[r + q];
    ea__plan_hess_fd_group(pl, ea__plan_row_eval, x, pl->xx, row, lambda + r, g, hp, values);
    r += g;
  }
  for (int o = 0; o < pl->n_orows; ++o) {
    const ea__row_t *row = &pl->orows[o];
    const double w = sigma * pl->oweight[o];
    if (!ea__plan_row_curved(row)) continue;
    const int *hp[1] = {pl->hpos + pl->hpos_start[pl->m + o]};
    ea__plan_hess_fd_group(pl, ea__plan_row_eval, x, pl->xx, row, &w, 1, hp, values);
  }
  return EA_OK;
}
