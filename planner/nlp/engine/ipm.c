/* A primal-dual interior point on an NLP given by Ipopt's callbacks (docs/planner.md, "The own
 * interior point"): Ipopt's monotone barrier algorithm (Waechter & Biegler 2006, sec. 2-3:
 * slacks for the inequality rows, the primal-dual system condensed to [W + Sigma_x, J';
 * J, -D], the fraction-to-the-boundary rule, the barrier parameter decreased by
 * min(kappa_mu mu, mu^theta) once the barrier problem is solved to kappa_eps mu, the inertia
 * correction, the iterative refinement, the acceptable termination) without its line search,
 * second-order corrections or restoration phase, its KKT system (engine/kkt.c) factored as
 * L D L' in a symmetric AMD order (the diagonal pivots of a quasi-definite matrix) instead of
 * by MUMPS: on the small banded KKT systems of a prescribed path a factorization costs far
 * less than MUMPS's per-front overhead.
 *
 * It is a fast path, not a replacement: from a good start (the path's time-optimal guess) it
 * returns a candidate that the caller verifies by the KKT test of the whole problem, and the
 * caller solves with Ipopt when it returns none or the test fails. Calls nothing above it. */
#include "plan_ipm_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define EA__IPM_INF 1e19 /* |bound| >= this: no bound (Ipopt's nlp_lower/upper_bound_inf) */
/* A barrier problem is solved when its error is <= kappa_eps mu. Ipopt's 10 re-centres each
 * barrier problem for several iterations after the dual error jumps at the new mu; 1e4 lowers
 * mu as soon as the error is within 1e4 mu (the overall test stays tol): fewer iterations, the
 * same plans (docs/planner.md, "The own interior point", "Tried, not adopted"). */
#define EA__IPM_KAPPA_EPS 1e4
#define EA__IPM_KAPPA_MU 0.2 /* mu <- max(mu_min, min(kappa_mu mu, mu^theta_mu)) */
#define EA__IPM_THETA_MU 1.5
#define EA__IPM_KAPPA_SIGMA 1e10 /* bound multipliers kept within this factor of mu / gap */
#define EA__IPM_SMAX 100.0       /* Ipopt's s_max: the dual error's scaling */
/* The equality rows' diagonal (Ipopt's delta_c). Always the diagonal pivot, as the
 * quasi-definite matrix [W + Sigma_x, J'; J, -D] allows in any symmetric order where
 * W + Sigma_x is positive definite; a pivot that spoils the solve shows in its residual
 * (checked, refined) or its inertia, and the Hessian's diagonal is raised. Small enough not to
 * perturb the steps (the active-set Newton's 1e-4 did), large enough for the pivots of nearly
 * dependent rows (docs/planner.md, "Tried, not adopted"). */
#define EA__IPM_DELTA_C 1e-8
#define EA__IPM_REFINE 10 /* refinements of a solve (Ipopt's max_refinement_steps) */

typedef struct {
  double *s, *zl, *zu, *vl, *vu, *y;
  double *dx, *ds, *dzl, *dzu, *dvl, *dvu, *rs;
  double *b, *res; /* the KKT system's right-hand side, its residual */
} ea__ipm_ws_t;

static int ea__lo(double b) {
  return b > -EA__IPM_INF;
}
static int ea__hi(double b) {
  return b < EA__IPM_INF;
}

/* v moved inside [lo, hi] by Ipopt's push (bound_push = bound_frac = push). */
static double ea__ipm_push(double v, double lo, double hi, double push) {
  const double w = ea__lo(lo) && ea__hi(hi) ? hi - lo : INFINITY;
  if (ea__lo(lo)) v = fmax(v, lo + fmin(push * fmax(1.0, fabs(lo)), push * w));
  if (ea__hi(hi)) v = fmin(v, hi - fmin(push * fmax(1.0, fabs(hi)), push * w));
  if (ea__lo(lo) && ea__hi(hi) && !(v > lo && v < hi)) v = 0.5 * (lo + hi);
  return v;
}

/* The largest step in (0, 1] that keeps v + alpha dv at least (1 - tau) of its gap g from its
 * bound (g: v's distance, dv: the change of that distance). */
static double ea__ftb(double alpha, double g, double dg, double tau) {
  const double a = dg < 0.0 ? -tau * g / dg : alpha;
  return a < alpha ? a : alpha;
}

/* z kept within [mu / (kappa gap), kappa mu / gap] (Ipopt's safeguard of the bound
 * multipliers' drift from the central path). */
static double ea__ipm_clip(double z, double mu, double gap) {
  const double hi = EA__IPM_KAPPA_SIGMA * mu / gap, lo = mu / (EA__IPM_KAPPA_SIGMA * gap);
  z = z < hi ? z : hi;
  return z > lo ? z : lo;
}

/* max(m, |v|) with a NaN kept (fmax drops it), inline (the norms below run over every
 * variable and row at every iteration) */
static inline double ea__ipm_amax(double m, double v) {
  const double a = fabs(v);
  return a > m || isnan(a) ? a : m;
}

/* Errors at the current point for barrier parameter mu: *dual (unscaled, max over the
 * variables and slacks), *prim (rows), *comp (|gap z - mu|, max); returns Ipopt's E_mu (the
 * dual error scaled by s_d, the complementarity by s_c). */
static double ea__ipm_err(const ea__kkt_t *k, const ea__ipm_ws_t *w, const double *x, double mu,
                          double *dual, double *prim, double *comp) {
  const ea__nlp_t *p = &k->p;
  double d = 0.0, c = 0.0, q = 0.0, sy = 0.0, sz = 0.0;
  int nz = 0;
  for (int i = 0; i < p->n; ++i) {
    if (k->kx[i] < 0) continue;
    d = ea__ipm_amax(d, k->r[i] - w->zl[i] + w->zu[i]);
    if (ea__lo(p->xl[i]))
      q = ea__ipm_amax(q, (x[i] - p->xl[i]) * w->zl[i] - mu), sz += w->zl[i], ++nz;
    if (ea__hi(p->xu[i]))
      q = ea__ipm_amax(q, (p->xu[i] - x[i]) * w->zu[i] - mu), sz += w->zu[i], ++nz;
  }
  for (int i = 0; i < p->m; ++i) {
    sy += fabs(w->y[i]);
    if (p->gl[i] == p->gu[i]) {
      c = ea__ipm_amax(c, k->g[i] - p->gl[i]);
      continue;
    }
    c = ea__ipm_amax(c, k->g[i] - w->s[i]);
    d = ea__ipm_amax(d, -w->y[i] - w->vl[i] + w->vu[i]);
    if (ea__lo(p->gl[i]))
      q = ea__ipm_amax(q, (w->s[i] - p->gl[i]) * w->vl[i] - mu), sz += w->vl[i], ++nz;
    if (ea__hi(p->gu[i]))
      q = ea__ipm_amax(q, (p->gu[i] - w->s[i]) * w->vu[i] - mu), sz += w->vu[i], ++nz;
  }
  *dual = d, *prim = c, *comp = q;
  const double sd = fmax(EA__IPM_SMAX, (sy + sz) / fmax(1, p->m + nz)) / EA__IPM_SMAX;
  const double sc = fmax(EA__IPM_SMAX, sz / fmax(1, nz)) / EA__IPM_SMAX;
  return fmax(d / sd, fmax(c, q / sc));
}

static void ea__ipm_ws_free(ea__ipm_ws_t *w) {
  double **f[] = {&w->s,   &w->zl,  &w->zu,  &w->vl,  &w->vu, &w->y, &w->dx, &w->ds,
                  &w->dzl, &w->dzu, &w->dvl, &w->dvu, &w->rs, &w->b, &w->res};
  for (size_t i = 0; i < sizeof f / sizeof *f; ++i)
    free(*f[i]), *f[i] = NULL;
}

static int ea__ipm_ws_alloc(ea__ipm_ws_t *w, int n, int m) {
  const size_t N = (size_t)n + 1, M = (size_t)m + 1;
  memset(w, 0, sizeof *w);
  w->s = calloc(M, sizeof(double)), w->vl = calloc(M, sizeof(double));
  w->vu = calloc(M, sizeof(double)), w->y = calloc(M, sizeof(double));
  w->ds = calloc(M, sizeof(double)), w->dvl = calloc(M, sizeof(double));
  w->dvu = calloc(M, sizeof(double)), w->rs = calloc(M, sizeof(double));
  w->zl = calloc(N, sizeof(double)), w->zu = calloc(N, sizeof(double));
  w->dx = calloc(N, sizeof(double)), w->dzl = calloc(N, sizeof(double));
  w->dzu = calloc(N, sizeof(double));
  w->b = calloc(N + M, sizeof(double)), w->res = calloc(N + M, sizeof(double));
  if (w->s && w->vl && w->vu && w->y && w->ds && w->dvl && w->dvu && w->rs && w->zl && w->zu &&
      w->dx && w->dzl && w->dzu && w->b && w->res)
    return 0;
  ea__ipm_ws_free(w);
  return -1;
}

/* The solve of K d = rhs (a->rhs, overwritten by d) with the factors num, refined as Ipopt
 * refines its solves: until the residual ratio |rhs - K d| / (|d| + |rhs|) (max norms) is at
 * most 1e-10 (residual_ratio_max), while it improves (by half at least), at most
 * EA__IPM_REFINE times; then accepted at 1e-5 (residual_ratio_singular). 1: accepted, 0: a
 * small pivot spoilt it (the caller raises the diagonals). */
static int ea__ipm_refined(ea__kkt_t *k, ea__ipm_ws_t *w) {
  const int nk = k->nk;
  double *b = w->b, *res = w->res;
  memcpy(b, k->rhs, sizeof(double) * (size_t)nk);
  ea__kkt_ldl_solve(k, k->rhs);
  double bn = 0.0, prev = INFINITY;
  for (int j = 0; j < nk; ++j)
    bn = ea__ipm_amax(bn, b[j]);
  for (int ref = 0;; ++ref) {
    ea__kkt_residual(k, b, k->rhs, res);
    double rn = 0.0, dn = 0.0;
    for (int j = 0; j < nk; ++j)
      rn = ea__ipm_amax(rn, res[j]), dn = ea__ipm_amax(dn, k->rhs[j]);
    const double ratio = rn / (dn + bn);
    if (ratio <= 1e-10) return 1;
    if (!isfinite(ratio)) break;
    if (ref == EA__IPM_REFINE || !(ratio < 0.5 * prev)) {
      if (ratio <= 1e-5) return 1;
      break;
    }
    ea__kkt_ldl_solve(k, res);
    prev = ratio;
    for (int j = 0; j < nk; ++j)
      k->rhs[j] += res[j];
  }
  memcpy(k->rhs, b, sizeof(double) * (size_t)nk);
  return 0;
}

/* Solve the KKT system in a->Ax, a->rhs (d into a->rhs) with the Hessian's diagonal raised
 * until the matrix has the inertia of [W + Sigma_x + dw I, J'; J, -D] at a minimum (as many
 * negative pivots as rows: Ipopt's inertia correction and its constants) and the solve refines
 * to 1e-10. The inertia is the signs of D. A solve that does not refine with the right
 * inertia has a small pivot in the rows: the equality rows' diagonal -dc is raised 100-fold up
 * to 1e-4 first. *dw: the last iteration's in, this one's out; *dc: this iteration's. 0, or -1
 * (nothing up to dw 1e20 did). */
static int ea__ipm_kkt(ea__kkt_t *k, ea__ipm_ws_t *w, double *dw, double *dc) {
  const ea__nlp_t *p = &k->p;
  double cur = 0.0, next = 0.0;
  int rc = -1;
  for (;;) {
    for (int i = 0; i < p->n; ++i)
      if (k->kx[i] >= 0) k->Ax[k->pd[k->kx[i]]] += next - cur;
    cur = next;
    /* the diagonal pivots in the AMD order: LDL' (SuiteSparse's LDL), D's signs the inertia;
     * a zero pivot stops it (d < nk) */
    int neg;
    const int d = ea__kkt_ldl_factor(k, &neg);
    int inertia = 0, good = 0;
    if (d == k->nk) {
      inertia = neg == k->nk - k->nx;
      good = inertia && ea__ipm_refined(k, w);
    }
    if (good) {
      *dw = cur;
      rc = 0;
      break;
    }
    if (inertia && *dc < 1e-4) {
      *dc *= 100.0;
      for (int i = 0; i < p->m; ++i)
        if (p->gl[i] == p->gu[i]) k->Ax[k->pd[k->kg[i]]] = -*dc;
      continue;
    }
    if (cur == 0.0)
      next = *dw == 0.0 ? 1e-4 : fmax(1e-20, *dw / 3);
    else
      next = cur * (*dw == 0.0 ? 100.0 : 8.0);
    if (next > 1e20) break;
  }
  return rc;
}

/* The Newton step of the barrier problem mu at the current point (a->r, a->g, a->jv, a->hv
 * evaluated there; *dw, *dc: the diagonals' raises, ea__ipm_kkt): dx, dy (in a->rhs), ds and
 * the bound multipliers' steps. 0, or -1 (no raise gave a factorization with the right inertia
 * whose solve refined). */
static int ea__ipm_step(ea__kkt_t *k, ea__ipm_ws_t *w, const double *x, double mu, double *dw,
                        double *dc) {
  const ea__nlp_t *p = &k->p;
  ea__kkt_fill(k);
  for (int i = 0; i < p->n; ++i) {
    const int j = k->kx[i];
    if (j < 0) continue;
    double sig = 0.0, rb = k->r[i]; /* grad f + J' y + the barrier's gradient */
    if (ea__lo(p->xl[i])) {
      const double gap = x[i] - p->xl[i];
      sig += w->zl[i] / gap, rb -= mu / gap;
    }
    if (ea__hi(p->xu[i])) {
      const double gap = p->xu[i] - x[i];
      sig += w->zu[i] / gap, rb += mu / gap;
    }
    k->Ax[k->pd[j]] += sig;
    k->rhs[j] = -rb;
  }
  for (int i = 0; i < p->m; ++i) {
    const int j = k->kg[i];
    if (p->gl[i] == p->gu[i]) {
      k->Ax[k->pd[j]] = -*dc;
      k->rhs[j] = -(k->g[i] - p->gl[i]);
      continue;
    }
    double sig = 0.0, rt = -w->y[i]; /* Sigma_s and r~_s = -y - mu / (s - gl) + mu / (gu - s) */
    if (ea__lo(p->gl[i])) {
      const double gap = w->s[i] - p->gl[i];
      sig += w->vl[i] / gap, rt -= mu / gap;
    }
    if (ea__hi(p->gu[i])) {
      const double gap = p->gu[i] - w->s[i];
      sig += w->vu[i] / gap, rt += mu / gap;
    }
    sig = fmax(sig, 1e-20);
    w->rs[i] = rt;
    w->ds[i] = sig; /* Sigma_s until the solve */
    k->Ax[k->pd[j]] = -1.0 / sig;
    k->rhs[j] = -(k->g[i] - w->s[i]) - rt / sig;
  }
  if (ea__ipm_kkt(k, w, dw, dc)) return -1;
  for (int i = 0; i < p->n; ++i) {
    const int j = k->kx[i];
    const double dx = j < 0 ? 0.0 : k->rhs[j];
    w->dx[i] = dx;
    w->dzl[i] = w->dzu[i] = 0.0;
    if (j < 0) continue;
    if (ea__lo(p->xl[i])) {
      const double gap = x[i] - p->xl[i];
      w->dzl[i] = mu / gap - w->zl[i] - w->zl[i] / gap * dx;
    }
    if (ea__hi(p->xu[i])) {
      const double gap = p->xu[i] - x[i];
      w->dzu[i] = mu / gap - w->zu[i] + w->zu[i] / gap * dx;
    }
  }
  for (int i = 0; i < p->m; ++i) {
    w->dvl[i] = w->dvu[i] = 0.0;
    if (p->gl[i] == p->gu[i]) {
      w->ds[i] = 0.0;
      continue;
    }
    const double dy = k->rhs[k->kg[i]];
    const double ds = (dy - w->rs[i]) / w->ds[i];
    w->ds[i] = ds;
    if (ea__lo(p->gl[i])) {
      const double gap = w->s[i] - p->gl[i];
      w->dvl[i] = mu / gap - w->vl[i] - w->vl[i] / gap * ds;
    }
    if (ea__hi(p->gu[i])) {
      const double gap = p->gu[i] - w->s[i];
      w->dvu[i] = mu / gap - w->vu[i] + w->vu[i] / gap * ds;
    }
  }
  return 0;
}

/* The step's lengths by the fraction-to-the-boundary rule: primal (x, s), dual (z, v). */
static void ea__ipm_alphas(const ea__kkt_t *k, const ea__ipm_ws_t *w, const double *x, double tau,
                           double *apr, double *adu) {
  const ea__nlp_t *p = &k->p;
  double ap = 1.0, ad = 1.0;
  for (int i = 0; i < p->n; ++i) {
    if (k->kx[i] < 0) continue;
    if (ea__lo(p->xl[i]))
      ap = ea__ftb(ap, x[i] - p->xl[i], w->dx[i], tau), ad = ea__ftb(ad, w->zl[i], w->dzl[i], tau);
    if (ea__hi(p->xu[i]))
      ap = ea__ftb(ap, p->xu[i] - x[i], -w->dx[i], tau), ad = ea__ftb(ad, w->zu[i], w->dzu[i], tau);
  }
  for (int i = 0; i < p->m; ++i) {
    if (p->gl[i] == p->gu[i]) continue;
    if (ea__lo(p->gl[i]))
      ap = ea__ftb(ap, w->s[i] - p->gl[i], w->ds[i], tau),
      ad = ea__ftb(ad, w->vl[i], w->dvl[i], tau);
    if (ea__hi(p->gu[i]))
      ap = ea__ftb(ap, p->gu[i] - w->s[i], -w->ds[i], tau),
      ad = ea__ftb(ad, w->vu[i], w->dvu[i], tau);
  }
  *apr = ap, *adu = ad;
}

int ea__ipm_prepare(ea__kkt_t *k) {
  /* every free variable and every row in the KKT matrix, in AMD's symmetric ordering (for
   * the LDL' of ea__ipm_kkt) */
  const int pat = ea__kkt_pattern(k, NULL, NULL, 0);
  k->full = !pat;
  return pat ? -1 : 0;
}

int ea__ipm_solve(ea__kkt_t *k, const ea__ipm_opt_t *o, double *x, double *mult_g, double *mult_xl,
                  double *mult_xu, int *iters) {
  const ea__nlp_t *p = &k->p;
  *iters = 0;
  ea__ipm_ws_t w;
  if (ea__ipm_ws_alloc(&w, p->n, p->m)) return -1;
  int rc = -1;
  const int pat = k->full ? 0 : ea__ipm_prepare(k);
  k->full = 0;
  if (pat || ea__kkt_ldl_symbolic(k)) goto done;
  double mu = o->mu_init, dw = 0.0, dc = EA__IPM_DELTA_C;
  const double mu_min = 0.1 * o->tol;
  /* the start: inside its bounds, the slacks the rows' values inside theirs, the bound
   * multipliers on the central path (mu / gap), the rows' zero */
  for (int i = 0; i < p->n; ++i) {
    if (k->kx[i] < 0) {
      x[i] = p->xl[i];
      continue;
    }
    x[i] = ea__ipm_push(x[i], p->xl[i], p->xu[i], o->push);
    if (ea__lo(p->xl[i])) w.zl[i] = mu / (x[i] - p->xl[i]);
    if (ea__hi(p->xu[i])) w.zu[i] = mu / (p->xu[i] - x[i]);
  }
  memset(k->lam, 0, sizeof(double) * (size_t)p->m);
  if (ea__kkt_eval(k, x, 0)) goto done;
  for (int i = 0; i < p->m; ++i) {
    if (p->gl[i] == p->gu[i]) continue;
    w.s[i] = ea__ipm_push(k->g[i], p->gl[i], p->gu[i], o->push_s);
    if (ea__lo(p->gl[i])) w.vl[i] = mu / (w.s[i] - p->gl[i]);
    if (ea__hi(p->gu[i])) w.vu[i] = mu / (p->gu[i] - w.s[i]);
  }
  int n_acc = 0;
  double f_prev = NAN;
  for (int it = 0;; ++it) {
    memcpy(k->lam, w.y, sizeof(double) * (size_t)p->m);
    if (ea__kkt_eval(k, x, 1)) goto done;
    double dual, prim, comp;
    const double e0 = ea__ipm_err(k, &w, x, 0.0, &dual, &prim, &comp);
    if (dual <= 0.5 * o->tol && prim <= 0.5 * o->ptol && comp <= 0.5 * o->tol) {
      rc = 0;
      break;
    }
    /* Ipopt's acceptable termination */
    if (o->acc_iter > 0 && p->f) {
      double f;
      if (!p->f(p->n, x, 0, &f, p->ud) || !isfinite(f)) goto done;
      const int acc = e0 <= o->acc_tol && prim <= o->ptol &&
                      fabs(f - f_prev) <= o->acc_obj * fmax(1.0, fabs(f));
      n_acc = acc ? n_acc + 1 : 0;
      f_prev = f;
      if (n_acc >= o->acc_iter) {
        rc = 1;
        break;
      }
    }
    /* the barrier problem solved: the next mu (more than once if the point allows) */
    while (mu > mu_min && ea__ipm_err(k, &w, x, mu, &dual, &prim, &comp) <= EA__IPM_KAPPA_EPS * mu)
      mu = fmax(mu_min, fmin(EA__IPM_KAPPA_MU * mu, pow(mu, EA__IPM_THETA_MU)));
    if (it == o->max_iter || (o->stop && o->stop(p->ud))) goto done;
    dc = EA__IPM_DELTA_C;
    if (ea__ipm_step(k, &w, x, mu, &dw, &dc)) goto done;
    const double tau = fmax(0.99, 1.0 - mu);
    double apr, adu;
    ea__ipm_alphas(k, &w, x, tau, &apr, &adu);
    if (!(apr > 1e-12)) goto done;
    for (int i = 0; i < p->n; ++i) {
      if (k->kx[i] < 0) continue;
      x[i] += apr * w.dx[i];
      if (ea__lo(p->xl[i])) w.zl[i] = ea__ipm_clip(w.zl[i] + adu * w.dzl[i], mu, x[i] - p->xl[i]);
      if (ea__hi(p->xu[i])) w.zu[i] = ea__ipm_clip(w.zu[i] + adu * w.dzu[i], mu, p->xu[i] - x[i]);
    }
    for (int i = 0; i < p->m; ++i) {
      w.y[i] += apr * k->rhs[k->kg[i]];
      if (p->gl[i] == p->gu[i]) continue;
      w.s[i] += apr * w.ds[i];
      if (ea__lo(p->gl[i])) w.vl[i] = ea__ipm_clip(w.vl[i] + adu * w.dvl[i], mu, w.s[i] - p->gl[i]);
      if (ea__hi(p->gu[i])) w.vu[i] = ea__ipm_clip(w.vu[i] + adu * w.dvu[i], mu, p->gu[i] - w.s[i]);
    }
    ++*iters;
  }
  memcpy(mult_g, w.y, sizeof(double) * (size_t)p->m);
  for (int i = 0; i < p->n; ++i) {
    mult_xl[i] = k->kx[i] < 0 ? 0.0 : w.zl[i];
    mult_xu[i] = k->kx[i] < 0 ? 0.0 : w.zu[i];
  }
done:
  ea__ipm_ws_free(&w);
  return rc;
}
