/* Workspace region metrics (docs/statics.md, "Workspace metrics"): the area,
 * the farthest reach, the largest tip x and the lowest tip y of the region
 * of tip positions the arm can hold, each computed to a stated accuracy.
 *
 * The region, in the cable coordinates (L_c, alpha) of the physical branch
 * (the configurations continuous with the T = 0 outer edge):
 *
 *   alpha_min <= alpha <= alpha_max           the cable-angle range
 *   L_inner   <= L_c   <= L_edge(alpha)       T >= 0; T = 0 on the outer edge
 *   and, with limits on, every arm limit:     shoulder angle range, |EI kappa0|
 *                                             <= torque max, T <= tension max,
 *                                             L_c in the spool's range.
 *
 * The tip is c + L_c (cos alpha, sin alpha) with c the cable root: polar
 * coordinates about the root, so at each alpha the admissible cable lengths
 * form intervals [a, b] and the area is the integral over alpha of
 * sum (b^2 - a^2) / 2, with no polygon (chord) error.
 *
 * Which constraint bounds each interval end (its "kind") changes only at
 * isolated angles (switches). The structure is sampled at `samples` angles
 * (and `depth_samples` cable lengths per angle); each switch is located by a
 * root find on the smooth function that changes sign there; each smooth
 * piece between switches is integrated by nested Clenshaw-Curtis rules until
 * two successive rules agree to the tolerance. The extrema lie on an
 * interval end (every objective is monotone in L_c at fixed alpha: the tip
 * moves along the ray from the root), so each is the maximum of smooth end
 * curves: the best quadrature node, then Brent's method on its neighbours.
 */
#include "ea_workspace.h"
#include "ea_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define EA__WS_MAXI 4 /* most admissible intervals per angle */
#define EA__WS_MAXE (2 * EA__WS_MAXI)
#define EA__WS_NC 5       /* limit constraints */
#define EA__WS_CC_MAX 256 /* finest Clenshaw-Curtis rule (intervals) */
#define EA__WS_GEPS 1e-9  /* slack of a limit check at a boundary */
#define EA__WS_MAXCUT 64  /* most structure changes in the range */

/* Limit constraints g_j(p) >= 0, their kinds and the given quantity that
 * puts a configuration on their boundary. */
static const ea_ws_bound_t ea__ws_ckind[EA__WS_NC] = {
    EA_WS_SHOULDER_MIN, EA_WS_SHOULDER_MAX, EA_WS_TORQUE_NEG, EA_WS_TORQUE_POS, EA_WS_TENSION_MAX};

const char *ea_ws_bound_name(ea_ws_bound_t b) {
  static const char *const names[EA_WS_COUNT] = {"none",
                                                 "outer edge (T = 0)",
                                                 "inner edge (shortest cable)",
                                                 "longest cable",
                                                 "shoulder angle minimum",
                                                 "shoulder angle maximum",
                                                 "shoulder torque limit (negative)",
                                                 "shoulder torque limit (positive)",
                                                 "cable tension maximum",
                                                 "cable-angle range start",
                                                 "cable-angle range end"};
  return (b >= 0 && b < EA_WS_COUNT) ? names[b] : "unknown";
}

void ea_workspace_settings_default(ea_workspace_settings_t *s) {
  memset(s, 0, sizeof *s);
  s->alpha_min = -60.0 * EA__DEG;
  s->alpha_max = 10.0 * EA__DEG;
  s->inner_cable_length = 0.0;
  s->limits = 1;
  s->samples = 71;
  s->depth_samples = 8;
  s->tol = 1e-10;
}

/* One evaluated cable angle: the outer edge and the admissible intervals,
 * as ascending interval ends L[0] < L[1] <= L[2] < L[3] ... */
typedef struct {
  double alpha;
  double Le, pe[EA_NP]; /* outer edge */
  int n;                /* intervals */
  double L[EA__WS_MAXE];
  ea_ws_bound_t kind[EA__WS_MAXE];
  double p[EA__WS_MAXE][EA_NP]; /* statics at the ends (warm starts) */
  unsigned char hp[EA__WS_MAXE];
} ea__wsp_t;

typedef struct {
  ea_shooter_t *sh;
  const ea_arm_t *arm;
  ea_workspace_settings_t set;
  ea_statics_settings_t ss;
  double lo;   /* lower cable bound (inner edge, or the spool's minimum) */
  double lmax; /* spool's maximum (INFINITY without limits) */
  double bound[EA__WS_NC];
  int active[EA__WS_NC];
  long solves;
  int too_many; /* more than EA__WS_MAXI intervals at one angle */
  int flip;     /* T < 0 just inside the outer edge */
  /* samples of the last full evaluation (warm starts for the next angle) */
  int cache_m;
  double cache_alpha;
  double cache_ps[EA__WS_CC_MAX + 1][EA_NP];
} ea__ws_t;

static int ea__ws_same(const ea__wsp_t *a, const ea__wsp_t *b) {
  if (a->n != b->n) return 0;
  for (int i = 0; i < 2 * a->n; ++i)
    if (a->kind[i] != b->kind[i]) return 0;
  return 1;
}

static int ea__ws_cidx(ea_ws_bound_t k) {
  for (int j = 0; j < EA__WS_NC; ++j)
    if (ea__ws_ckind[j] == k) return j;
  return -1;
}

/* g_j(p) >= 0 inside the limit j. */
static double ea__ws_g(const ea__ws_t *w, int j, const double p[EA_NP]) {
  const double tq = w->arm->EI * p[EA_P_KAPPA0];
  switch (j) {
  case 0:
    return p[EA_P_THETA0] - w->bound[0];
  case 1:
    return w->bound[1] - p[EA_P_THETA0];
  case 2:
    return tq - w->bound[2];
  case 3:
    return w->bound[3] - tq;
  default:
    return w->bound[4] - p[EA_P_TENSION];
  }
}

static int ea__ws_admissible(const ea__ws_t *w, const double p[EA_NP], double eps) {
  for (int j = 0; j < EA__WS_NC; ++j)
    if (w->active[j] && ea__ws_g(w, j, p) < -eps) return 0;
  return 1;
}

static ea_status_t ea__ws_edge(ea__ws_t *w, double alpha, const double *guess, double *L,
                               double p[EA_NP]) {
  ea_statics_solution_t sol;
  double g[EA_NP];
  if (guess) memcpy(g, guess, sizeof g);
  ++w->solves;
  ea_status_t st = ea_statics_edge(w->sh, alpha, &w->ss, guess ? g : NULL, &sol, NULL);
  if (st && guess) {
    ++w->solves;
    st = ea_statics_edge(w->sh, alpha, &w->ss, NULL, &sol, NULL);
  }
  if (st) return st;
  *L = sol.cable_length;
  memcpy(p, sol.p, sizeof sol.p);
  return EA_OK;
}

static ea_status_t ea__ws_cable(ea__ws_t *w, double L, double alpha, const double *guess,
                                double p[EA_NP]) {
  ea_statics_problem_t pr = ea_statics_problem_cable(L, alpha);
  ea_statics_solution_t sol;
  double g[EA_NP];
  if (guess) memcpy(g, guess, sizeof g);
  ++w->solves;
  ea_status_t st = ea_statics_solve(w->sh, &pr, &w->ss, guess ? g : NULL, &sol, NULL);
  if (st) return st;
  memcpy(p, sol.p, sizeof sol.p);
  return EA_OK;
}

/* The configuration on the boundary of limit j at alpha (direct statement:
 * the limited quantity given), warm-started. */
static ea_status_t ea__ws_limit_point(ea__ws_t *w, int j, double alpha, const double *guess,
                                      double *L, double p[EA_NP]) {
  static const ea_given_t q[EA__WS_NC] = {EA_GIVEN_THETA0, EA_GIVEN_THETA0, EA_GIVEN_KAPPA0,
                                          EA_GIVEN_KAPPA0, EA_GIVEN_TENSION};
  double v = w->bound[j];
  if (j == 2 || j == 3) v /= w->arm->EI;
  ea_statics_problem_t pr = {{q[j], EA_GIVEN_ALPHA}, {v, alpha}};
  ea_statics_solution_t sol;
  double g[EA_NP];
  if (guess) memcpy(g, guess, sizeof g);
  ++w->solves;
  ea_status_t st = ea_statics_solve(w->sh, &pr, &w->ss, guess ? g : NULL, &sol, NULL);
  if (st) return st;
  *L = sol.cable_length;
  memcpy(p, sol.p, sizeof sol.p);
  return EA_OK;
}

/* Root of g_j between cable lengths La > Lb (g_j(pa) and g_j(pb) of
 * opposite signs): the direct statement first, then regula falsi
 * (Illinois) on L_c. */
static ea_status_t ea__ws_root(ea__ws_t *w, int j, double alpha, double La, const double *pa,
                               double Lb, const double *pb, double *L, double p[EA_NP]) {
  double ga = ea__ws_g(w, j, pa), gb = ea__ws_g(w, j, pb);
  const double t = ga / (ga - gb);
  double guess[EA_NP];
  for (int i = 0; i < EA_NP; ++i)
    guess[i] = pa[i] + t * (pb[i] - pa[i]);
  const double slack = 1e-9 * (La - Lb) + 1e-12;
  if (ea__ws_limit_point(w, j, alpha, guess, L, p) == EA_OK && *L >= Lb - slack && *L <= La + slack)
    return EA_OK;
  double a = La, b = Lb, qa[EA_NP], qb[EA_NP];
  memcpy(qa, pa, sizeof qa);
  memcpy(qb, pb, sizeof qb);
  int side = 0;
  for (int it = 0; it < 100; ++it) {
    const double s = (ga * b - gb * a) / (ga - gb);
    const double f = (s - b) / (a - b);
    for (int i = 0; i < EA_NP; ++i)
      guess[i] = qb[i] + f * (qa[i] - qb[i]);
    double ps[EA_NP];
    ea_status_t st = ea__ws_cable(w, s, alpha, guess, ps);
    if (st) return st;
    const double gs = ea__ws_g(w, j, ps);
    if (fabs(a - b) < 1e-14 || gs == 0.0) {
      *L = s;
      memcpy(p, ps, sizeof ps);
      return EA_OK;
    }
    if ((gs > 0) == (ga > 0)) {
      a = s;
      ga = gs;
      memcpy(qa, ps, sizeof ps);
      if (side == -1) gb *= 0.5;
      side = -1;
    } else {
      b = s;
      gb = gs;
      memcpy(qb, ps, sizeof ps);
      if (side == 1) ga *= 0.5;
      side = 1;
    }
    if (fabs(a - b) < 1e-13) {
      *L = 0.5 * (a + b);
      memcpy(p, fabs(ga) < fabs(gb) ? qa : qb, sizeof ps);
      return EA_OK;
    }
  }
  return EA_ERR_NOCONV;
}

/* Top and bottom of the cable range at one angle. */
static void ea__ws_range(const ea__ws_t *w, double Le, double *lo, double *hi, ea_ws_bound_t *khi) {
  *lo = w->lo;
  *hi = Le;
  *khi = EA_WS_OUTER;
  if (w->lmax < Le) {
    *hi = w->lmax;
    *khi = EA_WS_CABLE_MAX;
  }
}

/* Full evaluation at alpha: the edge, then the limits sampled along the
 * cable from the top of the range down to the inner edge (secant
 * continuation), each sign change refined to its boundary. */
static ea_status_t ea__ws_full(ea__ws_t *w, double alpha, const double *edge_guess,
                               ea__wsp_t *out) {
  memset(out, 0, sizeof *out);
  out->alpha = alpha;
  ea_status_t st = ea__ws_edge(w, alpha, edge_guess, &out->Le, out->pe);
  if (st) return st;
  double lo, hi;
  ea_ws_bound_t khi;
  ea__ws_range(w, out->Le, &lo, &hi, &khi);
  if (!(hi > lo)) return EA_OK; /* empty at this angle */
  /* Just inside the edge the cable must be taut (T > 0): where shortening
     the cable from the T = 0 configuration needs a push instead (steep
     angles, the beam hanging), the outer edge does not bound the T >= 0
     region and these metrics do not apply. */
  double Lc = out->Le - 1e-3 * (out->Le - lo), pc[EA_NP];
  st = ea__ws_cable(w, Lc, alpha, out->pe, pc);
  if (st || !(pc[EA_P_TENSION] > 0)) {
    w->flip = 1;
    return st ? st : EA_ERR_INADMISSIBLE;
  }
  if (!w->set.limits) {
    out->n = 1;
    out->L[0] = lo;
    out->kind[0] = EA_WS_INNER;
    out->L[1] = hi;
    out->kind[1] = khi;
    if (khi == EA_WS_OUTER) {
      memcpy(out->p[1], out->pe, sizeof out->pe);
      out->hp[1] = 1;
    }
    return EA_OK;
  }
  const int m = w->set.depth_samples;
  double Ls[EA__WS_CC_MAX + 1], ps[EA__WS_CC_MAX + 1][EA_NP];
  int adm[EA__WS_CC_MAX + 1] = {0};
  /* warm starts: the samples of a nearby angle (the same fractions of the
     range), else a secant continuation from the edge whose short first
     step gives the slope */
  const int cached = w->cache_m == m && fabs(w->cache_alpha - alpha) <= 2.0 * EA__DEG;
  double Lp = out->Le, pp[EA_NP];
  memcpy(pp, out->pe, sizeof pp);
  for (int k = 0; k <= m; ++k) {
    const double L = hi - (hi - lo) * k / m;
    if (k == 0 && khi == EA_WS_OUTER) {
      Ls[0] = out->Le;
      memcpy(ps[0], out->pe, sizeof pp);
    } else {
      double guess[EA_NP];
      if (cached) {
        memcpy(guess, w->cache_ps[k], sizeof guess);
      } else {
        const double f = (L - Lc) / (Lc - Lp);
        for (int i = 0; i < EA_NP; ++i)
          guess[i] = pc[i] + f * (pc[i] - pp[i]);
      }
      Ls[k] = k == m ? lo : L;
      if ((st = ea__ws_cable(w, Ls[k], alpha, guess, ps[k]))) return st;
      Lp = Lc;
      memcpy(pp, pc, sizeof pp);
      Lc = Ls[k];
      memcpy(pc, ps[k], sizeof pc);
    }
    adm[k] = ea__ws_admissible(w, ps[k], 0.0);
  }
  memcpy(w->cache_ps, ps, (size_t)(m + 1) * sizeof ps[0]);
  w->cache_m = m;
  w->cache_alpha = alpha;
  /* intervals, from the top down */
  double Ld[EA__WS_MAXE], pd[EA__WS_MAXE][EA_NP];
  ea_ws_bound_t kd[EA__WS_MAXE];
  int ne = 0;
  if (adm[0]) {
    Ld[ne] = hi;
    kd[ne] = khi;
    memcpy(pd[ne], ps[0], sizeof pd[ne]);
    ++ne;
  }
  for (int k = 0; k < m; ++k) {
    if (adm[k] == adm[k + 1]) continue;
    /* the boundary: going down, the first limit to fail (largest root) or
       the last one to recover (smallest root) */
    double best = adm[k] ? -INFINITY : INFINITY, bp[EA_NP] = {0};
    int bj = -1;
    for (int j = 0; j < EA__WS_NC; ++j) {
      if (!w->active[j]) continue;
      const double ga = ea__ws_g(w, j, ps[k]), gb = ea__ws_g(w, j, ps[k + 1]);
      if (adm[k] ? !(ga >= 0 && gb < 0) : !(ga < 0 && gb >= 0)) continue;
      double L, p[EA_NP];
      if ((st = ea__ws_root(w, j, alpha, Ls[k], ps[k], Ls[k + 1], ps[k + 1], &L, p))) return st;
      if (adm[k] ? L > best : L < best) {
        best = L;
        bj = j;
        memcpy(bp, p, sizeof bp);
      }
    }
    if (bj < 0) return EA_ERR_NOCONV;
    if (ne >= EA__WS_MAXE) return w->too_many = 1, EA_ERR_NOCONV;
    Ld[ne] = best;
    kd[ne] = ea__ws_ckind[bj];
    memcpy(pd[ne], bp, sizeof bp);
    ++ne;
  }
  if (adm[m]) {
    if (ne >= EA__WS_MAXE) return w->too_many = 1, EA_ERR_NOCONV;
    Ld[ne] = lo;
    kd[ne] = EA_WS_INNER;
    memcpy(pd[ne], ps[m], sizeof pd[ne]);
    ++ne;
  }
  if (ne % 2 || ne > EA__WS_MAXE) return EA_ERR_NOCONV;
  out->n = ne / 2;
  for (int i = 0, src = ne - 1; src >= 0; ++i, --src) { /* ascending */
    out->L[i] = Ld[src];
    out->kind[i] = kd[src];
    memcpy(out->p[i], pd[src], sizeof out->p[i]);
    out->hp[i] = 1;
  }
  return EA_OK;
}

/* One interval end of kind k at alpha, warm-started from guess (may be
 * NULL): its cable length and (when a solve was needed) the statics. */
static ea_status_t ea__ws_end(ea__ws_t *w, ea_ws_bound_t k, double alpha, const double *edge_guess,
                              const double *guess, double *L, double p[EA_NP], int *hp) {
  *hp = 0;
  if (k == EA_WS_OUTER) {
    *hp = 1;
    return ea__ws_edge(w, alpha, edge_guess, L, p);
  }
  if (k == EA_WS_INNER || k == EA_WS_CABLE_MAX) {
    *L = k == EA_WS_INNER ? w->lo : w->lmax;
    if (!w->set.limits) return EA_OK;
    *hp = 1;
    return ea__ws_cable(w, *L, alpha, guess, p);
  }
  const int j = ea__ws_cidx(k);
  if (j < 0) return EA_ERR_ARG;
  *hp = 1;
  return ea__ws_limit_point(w, j, alpha, guess, L, p);
}

/* Evaluation at alpha with a known structure (tp's kinds), warm-started
 * from tp. Returns EA_ERR_INADMISSIBLE when the structure does not hold
 * here (an end out of order, or a limit violated at an end). */
static ea_status_t ea__ws_ends(ea__ws_t *w, double alpha, const ea__wsp_t *tp, ea__wsp_t *out) {
  memset(out, 0, sizeof *out);
  out->alpha = alpha;
  ea_status_t st = ea__ws_edge(w, alpha, tp->pe, &out->Le, out->pe);
  if (st) return st;
  double lo, hi;
  ea_ws_bound_t khi;
  ea__ws_range(w, out->Le, &lo, &hi, &khi);
  out->n = tp->n;
  if (tp->n == 0) return hi > lo ? EA_ERR_INADMISSIBLE : EA_OK;
  if (!(hi > lo)) return EA_ERR_INADMISSIBLE;
  const double eps = 1e-12 * (1.0 + hi);
  for (int i = 0; i < 2 * tp->n; ++i) {
    const ea_ws_bound_t k = tp->kind[i];
    out->kind[i] = k;
    if ((k == EA_WS_OUTER || k == EA_WS_CABLE_MAX) && k != khi) return EA_ERR_INADMISSIBLE;
    if (k == EA_WS_OUTER) {
      out->L[i] = out->Le;
      memcpy(out->p[i], out->pe, sizeof out->pe);
      out->hp[i] = 1;
    } else {
      int hp;
      st = ea__ws_end(w, k, alpha, tp->pe, tp->hp[i] ? tp->p[i] : NULL, &out->L[i], out->p[i], &hp);
      if (st) return st;
      out->hp[i] = (unsigned char)hp;
    }
    if (out->L[i] < lo - eps || out->L[i] > hi + eps) return EA_ERR_INADMISSIBLE;
    if (i > 0 && out->L[i] < out->L[i - 1] - eps) return EA_ERR_INADMISSIBLE;
    if (w->set.limits && out->hp[i] && !ea__ws_admissible(w, out->p[i], EA__WS_GEPS))
      return EA_ERR_INADMISSIBLE;
  }
  return EA_OK;
}

static double ea__ws_f(const ea__wsp_t *p) {
  double f = 0.0;
  for (int i = 0; i < p->n; ++i)
    f += 0.5 * (p->L[2 * i + 1] * p->L[2 * i + 1] - p->L[2 * i] * p->L[2 * i]);
  return f;
}

/* ---- switches ------------------------------------------------------------ */

/* The smooth function that changes sign where structure a (left) turns into
 * structure b (right); *ok = 0 when there is none (then: bisection). */
typedef struct {
  ea_ws_bound_t ka, kb; /* differing end: kind on the left, on the right */
  int ia, ib;           /* index of that end in a and in b */
  int vanish;           /* an interval [ia, ia + 1] of a (or of b) shrinks to zero */
  int in_b;             /* the vanishing interval is b's */
} ea__ws_switch_t;

static int ea__ws_switch_kind(const ea__wsp_t *a, const ea__wsp_t *b, ea__ws_switch_t *s) {
  memset(s, 0, sizeof *s);
  if (a->n == b->n) {
    int nd = 0;
    for (int i = 0; i < 2 * a->n; ++i)
      if (a->kind[i] != b->kind[i]) {
        ++nd;
        s->ia = s->ib = i;
      }
    if (nd != 1) return 0;
    s->ka = a->kind[s->ia];
    s->kb = b->kind[s->ib];
    return 1;
  }
  if (abs(a->n - b->n) != 1) return 0;
  const ea__wsp_t *big = a->n > b->n ? a : b, *small = a->n > b->n ? b : a;
  for (int v = 0; v < big->n; ++v) { /* drop interval v of big: same as small? */
    int same = 1;
    for (int i = 0, k = 0; i < 2 * big->n && same; ++i) {
      if (i / 2 == v) continue;
      if (big->kind[i] != small->kind[k++]) same = 0;
    }
    if (same) {
      s->vanish = 1;
      s->in_b = big == b;
      s->ia = 2 * v;
      s->ka = big->kind[2 * v];
      s->kb = big->kind[2 * v + 1];
      return 1;
    }
  }
  return 0;
}

typedef struct {
  ea__ws_t *w;
  const ea__wsp_t *a, *b;
  ea__ws_switch_t s;
} ea__ws_phi_ctx_t;

static ea_status_t ea__ws_phi(ea__ws_phi_ctx_t *c, double alpha, double *phi) {
  ea__ws_t *w = c->w;
  const ea__wsp_t *tp = fabs(alpha - c->a->alpha) < fabs(alpha - c->b->alpha) ? c->a : c->b;
  if (c->s.vanish) { /* width of the vanishing interval */
    const ea__wsp_t *big = c->s.in_b ? c->b : c->a;
    double L0, L1, p0[EA_NP], p1[EA_NP];
    int h0, h1;
    ea_status_t st = ea__ws_end(w, c->s.ka, alpha, big->pe,
                                big->hp[c->s.ia] ? big->p[c->s.ia] : NULL, &L0, p0, &h0);
    if (!st)
      st = ea__ws_end(w, c->s.kb, alpha, big->pe, big->hp[c->s.ia + 1] ? big->p[c->s.ia + 1] : NULL,
                      &L1, p1, &h1);
    *phi = st ? NAN : L1 - L0; /* L1 is not set when the first end failed */
    return st;
  }
  const ea_ws_bound_t ka = c->s.ka, kb = c->s.kb;
  const int ja = ea__ws_cidx(ka), jb = ea__ws_cidx(kb);
  double La, Lb, pa[EA_NP], pb[EA_NP];
  int ha, hb;
  const double *ga = c->a->hp[c->s.ia] ? c->a->p[c->s.ia] : NULL;
  const double *gb = c->b->hp[c->s.ib] ? c->b->p[c->s.ib] : NULL;
  ea_status_t st;
  if (jb >= 0) { /* limit b at the end of kind a */
    if ((st = ea__ws_end(w, ka, alpha, tp->pe, ga, &La, pa, &ha))) return st;
    if (!ha && (st = ea__ws_cable(w, La, alpha, gb, pa))) return st;
    *phi = ea__ws_g(w, jb, pa);
    return EA_OK;
  }
  if (ja >= 0) { /* limit a at the end of kind b */
    if ((st = ea__ws_end(w, kb, alpha, tp->pe, gb, &Lb, pb, &hb))) return st;
    if (!hb && (st = ea__ws_cable(w, Lb, alpha, ga, pb))) return st;
    *phi = ea__ws_g(w, ja, pb);
    return EA_OK;
  }
  if ((st = ea__ws_end(w, ka, alpha, tp->pe, ga, &La, pa, &ha))) return st;
  if ((st = ea__ws_end(w, kb, alpha, tp->pe, gb, &Lb, pb, &hb))) return st;
  *phi = La - Lb;
  return EA_OK;
}

/* Locate the switch between a and b (a->alpha < b->alpha) to about 1e-13
 * rad: regula falsi (Illinois) on the switch function, else bisection on
 * the structure. */
static ea_status_t ea__ws_locate(ea__ws_t *w, const ea__wsp_t *a, const ea__wsp_t *b, double *at) {
  ea__ws_phi_ctx_t c = {w, a, b, {0}};
  double x0 = a->alpha, x1 = b->alpha, f0, f1;
  if (ea__ws_switch_kind(a, b, &c.s) && !ea__ws_phi(&c, x0, &f0) && !ea__ws_phi(&c, x1, &f1) &&
      isfinite(f0) && isfinite(f1) && (f0 <= 0) != (f1 <= 0)) {
    int side = 0;
    for (int it = 0; it < 200 && x1 - x0 > 1e-13; ++it) {
      double x = (f0 == f1) ? 0.5 * (x0 + x1) : (x0 * f1 - x1 * f0) / (f1 - f0);
      if (!(x > x0 && x < x1)) x = 0.5 * (x0 + x1);
      double f;
      if (ea__ws_phi(&c, x, &f) || !isfinite(f)) break;
      if ((f <= 0) == (f0 <= 0)) {
        x0 = x;
        f0 = f;
        if (side == -1) f1 *= 0.5;
        side = -1;
      } else {
        x1 = x;
        f1 = f;
        if (side == 1) f0 *= 0.5;
        side = 1;
      }
      if (f == 0.0) {
        x0 = x1 = x;
        break;
      }
    }
    if (x1 - x0 <= 1e-13) {
      *at = 0.5 * (x0 + x1);
      return EA_OK;
    }
  }
  /* bisection on the structure */
  ea__wsp_t l = *a, r = *b, m;
  while (r.alpha - l.alpha > 1e-12) {
    const double x = 0.5 * (l.alpha + r.alpha);
    ea_status_t st = ea__ws_full(w, x, l.pe, &m);
    if (st) return st;
    if (ea__ws_same(&m, a))
      l = m;
    else
      r = m; /* a third structure on the right: keep the left switch */
  }
  *at = 0.5 * (l.alpha + r.alpha);
  return EA_OK;
}

/* ---- Clenshaw-Curtis -------------------------------------------------------- */

/* Weights of the (n + 1)-point Clenshaw-Curtis rule on [-1, 1], nodes
 * cos(k pi / n), n even. */
static void ea__cc_weights(int n, double *wt) {
  for (int k = 0; k <= n; ++k) {
    double s = 0.0;
    for (int j = 1; j <= n / 2; ++j) {
      const double bj = (2 * j == n) ? 1.0 : 2.0;
      s += bj / (4.0 * j * j - 1.0) * cos(2.0 * j * k * M_PI / n);
    }
    wt[k] = ((k == 0 || k == n) ? 1.0 : 2.0) / n * (1.0 - s);
  }
}

/* ---- the metrics ----------------------------------------------------------- */

typedef struct {
  double a, b;
  ea__wsp_t tmpl;  /* structure */
  int n;           /* rule: n + 1 nodes */
  ea__wsp_t *node; /* node[k] at alpha = mid - half cos(k pi / n), ascending */
  double integral, error;
} ea__ws_piece_t;

typedef enum { EA__OBJ_REACH = 0, EA__OBJ_X, EA__OBJ_NEG_Y } ea__ws_obj_t;

static double ea__ws_obj(const ea__ws_t *w, ea__ws_obj_t o, double L, double alpha) {
  const double x = w->arm->x_c + L * cos(alpha), y = w->arm->y_c + L * sin(alpha);
  return o == EA__OBJ_REACH ? hypot(x, y) : o == EA__OBJ_X ? x : -y;
}

/* Brent's minimiser of -F along one end curve over [a, b]. */
typedef struct {
  ea__ws_t *w;
  const ea__ws_piece_t *pc;
  int end;
  ea__ws_obj_t o;
  ea_status_t st;
  double L_at_best;
} ea__ws_curve_t;

static double ea__ws_curve(ea__ws_curve_t *c, double alpha, double *L_out) {
  /* nearest node as the warm start */
  const ea__ws_piece_t *pc = c->pc;
  int best = 0;
  for (int k = 1; k <= pc->n; ++k)
    if (fabs(pc->node[k].alpha - alpha) < fabs(pc->node[best].alpha - alpha)) best = k;
  const ea__wsp_t *tp = &pc->node[best];
  double L, p[EA_NP];
  int hp;
  ea_status_t st = ea__ws_end(c->w, tp->kind[c->end], alpha, tp->pe,
                              tp->hp[c->end] ? tp->p[c->end] : NULL, &L, p, &hp);
  if (st) {
    c->st = st;
    return INFINITY;
  }
  if (L_out) *L_out = L;
  return -ea__ws_obj(c->w, c->o, L, alpha);
}

/* Brent (1973), localmin: minimum of f on [a, b] to tolerance tol. */
static double ea__ws_brent(ea__ws_curve_t *c, double a, double b, double tol, double *xmin) {
  const double gold = 0.3819660112501051;
  double x = a + gold * (b - a), v = x, wv = x, e = 0.0, d = 0.0;
  double fx = ea__ws_curve(c, x, NULL), fv = fx, fw = fx;
  for (int it = 0; it < 200; ++it) {
    const double m = 0.5 * (a + b), t1 = tol + 1e-12 * fabs(x), t2 = 2.0 * t1;
    if (fabs(x - m) <= t2 - 0.5 * (b - a)) break;
    double r = 0, q = 0, pp = 0;
    if (fabs(e) > t1) {
      r = (x - wv) * (fx - fv);
      q = (x - v) * (fx - fw);
      pp = (x - v) * q - (x - wv) * r;
      q = 2.0 * (q - r);
      if (q > 0) pp = -pp;
      q = fabs(q);
      r = e;
      e = d;
    }
    if (fabs(pp) < fabs(0.5 * q * r) && pp > q * (a - x) && pp < q * (b - x)) {
      d = pp / q;
      const double u = x + d;
      if (u - a < t2 || b - u < t2) d = x < m ? t1 : -t1;
    } else {
      e = (x < m) ? b - x : a - x;
      d = gold * e;
    }
    const double u = x + (fabs(d) >= t1 ? d : (d > 0 ? t1 : -t1));
    const double fu = ea__ws_curve(c, u, NULL);
    if (fu <= fx) {
      if (u < x)
        b = x;
      else
        a = x;
      v = wv;
      fv = fw;
      wv = x;
      fw = fx;
      x = u;
      fx = fu;
    } else {
      if (u < x)
        a = u;
      else
        b = u;
      if (fu <= fw || wv == x) {
        v = wv;
        fv = fw;
        wv = u;
        fw = fu;
      } else if (fu <= fv || v == x || v == wv) {
        v = u;
        fv = fu;
      }
    }
  }
  *xmin = x;
  return fx;
}

static void ea__ws_extremum(ea__ws_t *w, ea__ws_piece_t *pcs, int np, ea__ws_obj_t o,
                            ea_workspace_extremum_t *ex, ea_status_t *st_out) {
  double best = -INFINITY;
  int bp = -1, bk = -1, be = -1;
  for (int q = 0; q < np; ++q)
    for (int k = 0; k <= pcs[q].n; ++k) {
      const ea__wsp_t *nd = &pcs[q].node[k];
      for (int i = 0; i < 2 * nd->n; ++i) {
        const double f = ea__ws_obj(w, o, nd->L[i], nd->alpha);
        if (f > best) {
          best = f;
          bp = q;
          bk = k;
          be = i;
        }
      }
    }
  ex->value = NAN;
  ex->bound = ex->at_end = EA_WS_NONE;
  if (bp < 0) return;
  double alpha = pcs[bp].node[bk].alpha, L = pcs[bp].node[bk].L[be];
  ea_ws_bound_t kind = pcs[bp].node[bk].kind[be];
  /* refine every end curve of every piece whose best node is close */
  for (int q = 0; q < np; ++q) {
    const ea__ws_piece_t *pc = &pcs[q];
    for (int k = 0; k <= pc->n; ++k) {
      const ea__wsp_t *nd = &pc->node[k];
      for (int i = 0; i < 2 * nd->n; ++i) {
        if (ea__ws_obj(w, o, nd->L[i], nd->alpha) < best - 1e-3) continue;
        /* a local maximum among the nodes of this curve? */
        const double fk = ea__ws_obj(w, o, nd->L[i], nd->alpha);
        const double fl =
            k > 0 ? ea__ws_obj(w, o, pc->node[k - 1].L[i], pc->node[k - 1].alpha) : -INFINITY;
        const double fr =
            k < pc->n ? ea__ws_obj(w, o, pc->node[k + 1].L[i], pc->node[k + 1].alpha) : -INFINITY;
        if (fk < fl || fk < fr) continue;
        const double a = pc->node[k > 0 ? k - 1 : 0].alpha;
        const double b = pc->node[k < pc->n ? k + 1 : pc->n].alpha;
        ea__ws_curve_t c = {w, pc, i, o, EA_OK, NAN};
        double xm;
        const double fm = -ea__ws_brent(&c, a, b, 1e-10, &xm);
        if (c.st) {
          *st_out = c.st;
          return;
        }
        if (fm > best) {
          double Lm = NAN;
          ea__ws_curve(&c, xm, &Lm);
          best = fm;
          alpha = xm;
          L = Lm;
          kind = nd->kind[i];
        }
      }
    }
  }
  ex->value = o == EA__OBJ_NEG_Y ? -best : best;
  ex->alpha = alpha;
  ex->cable_length = L;
  ex->x = w->arm->x_c + L * cos(alpha);
  ex->y = w->arm->y_c + L * sin(alpha);
  ex->bound = kind;
  ex->bound2 = EA_WS_NONE;
  const double span = w->set.alpha_max - w->set.alpha_min;
  /* at a corner (a structure change): both boundaries, in enum order */
  for (int q = 1; q < np; ++q) {
    if (fabs(alpha - pcs[q].a) > 1e-9 * span) continue;
    const ea__wsp_t *l = &pcs[q - 1].node[pcs[q - 1].n], *r = &pcs[q].node[0];
    ea_ws_bound_t k2[2] = {EA_WS_NONE, EA_WS_NONE};
    const ea__wsp_t *side[2] = {l, r};
    for (int sd = 0; sd < 2; ++sd) {
      double dbest = INFINITY;
      for (int i = 0; i < 2 * side[sd]->n; ++i)
        if (fabs(side[sd]->L[i] - L) < dbest) {
          dbest = fabs(side[sd]->L[i] - L);
          k2[sd] = side[sd]->kind[i];
        }
    }
    if (k2[0] != k2[1] && k2[0] != EA_WS_NONE && k2[1] != EA_WS_NONE) {
      ex->bound = k2[0] < k2[1] ? k2[0] : k2[1];
      ex->bound2 = k2[0] < k2[1] ? k2[1] : k2[0];
    }
  }
  if (alpha - w->set.alpha_min <= 1e-7 * span)
    ex->at_end = EA_WS_ALPHA_MIN;
  else if (w->set.alpha_max - alpha <= 1e-7 * span)
    ex->at_end = EA_WS_ALPHA_MAX;
}

/* Integrate one piece: nested Clenshaw-Curtis rules (n = 16, 32, ...) until
 * two agree to tol. Returns EA_ERR_INADMISSIBLE with *bad_alpha when the
 * structure does not hold at a node (a switch the samples missed). */
static ea_status_t ea__ws_piece(ea__ws_t *w, ea__ws_piece_t *pc, const ea__wsp_t *coarse, int nc,
                                double tol, double *bad_alpha) {
  const double mid = 0.5 * (pc->a + pc->b), half = 0.5 * (pc->b - pc->a);
  double prev = NAN, wt[EA__WS_CC_MAX + 1];
  ea__wsp_t *old = NULL;
  int nold = 0;
  for (int n = 16; n <= EA__WS_CC_MAX; n *= 2) {
    ea__wsp_t *node = calloc((size_t)n + 1, sizeof *node);
    if (!node) {
      free(old);
      return EA_ERR_NOMEM;
    }
    for (int k = 0; k <= n; ++k) {
      if (old && k % 2 == 0) {
        node[k] = old[k / 2];
        continue;
      }
      const double alpha = k == 0 ? pc->a : k == n ? pc->b : mid - half * cos(k * M_PI / n);
      /* warm start: the nearest evaluated angle of this structure */
      const ea__wsp_t *tp = &pc->tmpl;
      double dbest = fabs(tp->alpha - alpha);
      for (int i = 0; i < nc; ++i)
        if (ea__ws_same(&coarse[i], &pc->tmpl) && fabs(coarse[i].alpha - alpha) < dbest) {
          tp = &coarse[i];
          dbest = fabs(coarse[i].alpha - alpha);
        }
      for (int i = 0; i < k; ++i)
        if (fabs(node[i].alpha - alpha) < dbest) {
          tp = &node[i];
          dbest = fabs(node[i].alpha - alpha);
        }
      if (old)
        for (int i = 0; i <= nold; ++i)
          if (fabs(old[i].alpha - alpha) < dbest) {
            tp = &old[i];
            dbest = fabs(old[i].alpha - alpha);
          }
      ea_status_t st = ea__ws_ends(w, alpha, tp, &node[k]);
      if (st) {
        free(node);
        free(old);
        *bad_alpha = alpha;
        return st;
      }
    }
    ea__cc_weights(n, wt);
    double I = 0.0;
    for (int k = 0; k <= n; ++k)
      I += wt[k] * ea__ws_f(&node[k]);
    I *= half;
    free(old);
    old = node;
    nold = n;
    if (isfinite(prev) && fabs(I - prev) <= tol) {
      pc->integral = I;
      pc->error = fabs(I - prev);
      pc->n = n;
      pc->node = node;
      return EA_OK;
    }
    prev = I;
  }
  /* not converged at the finest rule */
  free(old);
  return EA_ERR_NOCONV;
}

static int ea__ws_insert(ea__wsp_t **coarse, int *nc, int *cap, const ea__wsp_t *p) {
  if (*nc == *cap) {
    const int nc2 = *cap * 2;
    ea__wsp_t *c2 = realloc(*coarse, (size_t)nc2 * sizeof *c2);
    if (!c2) return -1;
    *coarse = c2;
    *cap = nc2;
  }
  int at = *nc;
  while (at > 0 && (*coarse)[at - 1].alpha > p->alpha) {
    (*coarse)[at] = (*coarse)[at - 1];
    --at;
  }
  (*coarse)[at] = *p;
  ++*nc;
  return 0;
}

/* Phase 1: check the settings and fill the search's workspace w. */
static ea_status_t ea__ws_setup(ea_shooter_t *sh, const ea_workspace_settings_t *set, ea__ws_t *w,
                                ea_error_t *err) {
  memset(w, 0, sizeof *w);
  w->sh = sh;
  w->arm = ea_shooter_arm(sh);
  w->set = *set;
  const ea_actuators_t *act = &w->arm->act;
  if (!(isfinite(set->alpha_min) && isfinite(set->alpha_max) && set->alpha_min < set->alpha_max))
    return ea_error_set(err, EA_ERR_ARG,
                        "workspace: the cable-angle range needs alpha_min < alpha_max (got %g, "
                        "%g deg)",
                        set->alpha_min / EA__DEG, set->alpha_max / EA__DEG);
  if (!(set->alpha_min > -0.5 * M_PI && set->alpha_max < 0.5 * M_PI))
    return ea_error_set(err, EA_ERR_ARG,
                        "workspace: the cable-angle range %g to %g deg must lie inside (-90, 90) "
                        "deg: the region is defined with the tip in front of the cable root "
                        "(beyond, the outer edge folds: the beam hangs, or stands over the top)",
                        set->alpha_min / EA__DEG, set->alpha_max / EA__DEG);
  if (set->samples < 2 || set->samples > 100000 || set->depth_samples < 2 ||
      set->depth_samples > EA__WS_CC_MAX || !(set->tol > 0))
    return ea_error_set(err, EA_ERR_ARG,
                        "workspace: need samples >= 2, 2 <= depth_samples <= %d and tol > 0",
                        EA__WS_CC_MAX);
  const double inner =
      set->inner_cable_length > 0 ? set->inner_cable_length : act->cable_length_min;
  if (!isfinite(inner))
    return ea_error_set(err, EA_ERR_ARG, "workspace: inner cable length is not finite");
  w->lo = set->limits ? fmax(inner, act->cable_length_min) : inner;
  w->lmax = set->limits ? act->cable_length_max : INFINITY;
  w->bound[0] = act->shoulder_angle_min;
  w->bound[1] = act->shoulder_angle_max;
  w->bound[2] = -act->shoulder_torque_max;
  w->bound[3] = act->shoulder_torque_max;
  w->bound[4] = act->tension_max;
  for (int j = 0; j < EA__WS_NC; ++j)
    w->active[j] = set->limits && isfinite(w->bound[j]);
  ea_statics_settings_default(&w->ss);
  w->ss.tol = 1e-12;
  return EA_OK;
}

/* Phase 2: the region's structure at set->samples equally spaced cable angles (coarse, *nc of
 * them); refused when the region is empty. */
static ea_status_t ea__ws_sample(ea__ws_t *w, ea__wsp_t *coarse, int *nc, ea_error_t *err) {
  const ea_workspace_settings_t *set = &w->set;
  const int n0 = set->samples;
  for (int j = 0; j < n0; ++j) {
    const double alpha = j == n0 - 1
                             ? set->alpha_max
                             : set->alpha_min + (set->alpha_max - set->alpha_min) * j / (n0 - 1);
    const ea_status_t st = ea__ws_full(w, alpha, *nc ? coarse[*nc - 1].pe : NULL, &coarse[*nc]);
    if (st) {
      if (w->flip)
        return ea_error_set(err, EA_ERR_INADMISSIBLE,
                            "workspace: at alpha = %.6g deg the outer edge (T = 0) does not bound "
                            "the region: shortening the cable from it would need T < 0 (the beam "
                            "hangs too steeply); narrow the cable-angle range",
                            alpha / EA__DEG);
      if (w->too_many)
        return ea_error_set(err, st,
                            "workspace: more than %d admissible intervals of cable length at "
                            "alpha = %.6g deg",
                            EA__WS_MAXI, alpha / EA__DEG);
      return ea_error_set(err, st,
                          "workspace: no statics solution at alpha = %.6g deg (%s): the outer edge "
                          "(T = 0) or a configuration inside it did not solve; narrow the "
                          "cable-angle range",
                          alpha / EA__DEG, ea_strerror(st));
    }
    ++*nc;
  }
  int any = 0;
  double Le_max = -INFINITY;
  for (int j = 0; j < *nc; ++j) {
    any |= coarse[j].n > 0;
    Le_max = fmax(Le_max, coarse[j].Le);
  }
  if (any) return EA_OK;
  if (Le_max <= w->lo)
    return ea_error_set(err, EA_ERR_INADMISSIBLE,
                        "workspace: the region is empty: the inner edge (cable length %.6g m) "
                        "lies beyond the outer edge (T = 0) at every cable angle from %.6g to "
                        "%.6g deg (longest outer-edge cable %.6g m)",
                        w->lo, set->alpha_min / EA__DEG, set->alpha_max / EA__DEG, Le_max);
  return ea_error_set(err, EA_ERR_INADMISSIBLE,
                      "workspace: the region is empty: every sampled configuration from %.6g "
                      "to %.6g deg violates a limit of the arm",
                      set->alpha_min / EA__DEG, set->alpha_max / EA__DEG);
}

/* Phase 3a: the angles cut[0..*ncut) where the region's structure changes between neighbouring
 * samples, and each piece's template sample (tmpl[0..*ncut]). */
static ea_status_t ea__ws_cuts(ea__ws_t *w, const ea__wsp_t *coarse, int nc, double *cut,
                               ea__wsp_t *tmpl, int *ncut, ea_error_t *err) {
  *ncut = 0;
  tmpl[0] = coarse[0];
  for (int j = 0; j + 1 < nc; ++j) {
    if (ea__ws_same(&coarse[j], &coarse[j + 1])) continue;
    if (*ncut + 1 >= EA__WS_MAXCUT)
      return ea_error_set(err, EA_ERR_NOCONV, "workspace: more than %d structure changes",
                          EA__WS_MAXCUT - 1);
    double at;
    const ea_status_t st = ea__ws_locate(w, &coarse[j], &coarse[j + 1], &at);
    if (st)
      return ea_error_set(err, st,
                          "workspace: cannot locate where the region's boundary changes between "
                          "alpha = %.6g and %.6g deg (%s)",
                          coarse[j].alpha / EA__DEG, coarse[j + 1].alpha / EA__DEG,
                          ea_strerror(st));
    cut[(*ncut)++] = at;
    tmpl[*ncut] = coarse[j + 1];
  }
  return EA_OK;
}

/* A structure change between the samples near alpha = bad: the angle is added to the samples
 * (the caller redoes the pieces). */
static ea_status_t ea__ws_add_sample(ea__ws_t *w, double bad, ea__wsp_t **coarse, int *nc, int *cap,
                                     ea_error_t *err) {
  ea__wsp_t extra;
  const ea__wsp_t *near = &(*coarse)[0];
  for (int i = 0; i < *nc; ++i)
    if (fabs((*coarse)[i].alpha - bad) < fabs(near->alpha - bad)) near = &(*coarse)[i];
  const ea_status_t st = ea__ws_full(w, bad, near->pe, &extra);
  if (st)
    return ea_error_set(err, st, "workspace: no statics solution at alpha = %.6g deg (%s)",
                        bad / EA__DEG, ea_strerror(st));
  int dup = 0;
  for (int i = 0; i < *nc; ++i)
    dup |= (*coarse)[i].alpha == bad;
  if (dup || ea__ws_insert(coarse, nc, cap, &extra))
    return ea_error_set(err, EA_ERR_NOCONV,
                        "workspace: inconsistent region structure at alpha = %.6g deg",
                        bad / EA__DEG);
  return EA_OK;
}

/* Phase 3b: integrate the np pieces between the cuts; *redo when a sample had to be added. */
static ea_status_t ea__ws_integrate(ea__ws_t *w, ea__ws_piece_t *pcs, int np, const double *cut,
                                    const ea__wsp_t *tmpl, ea__wsp_t **coarse, int *nc, int *cap,
                                    int *redo, ea_error_t *err) {
  const ea_workspace_settings_t *set = &w->set;
  const double tol_total = set->tol, span = set->alpha_max - set->alpha_min;
  const int ncut = np - 1;
  *redo = 0;
  for (int q = 0; q < np; ++q) {
    pcs[q].a = q ? cut[q - 1] : set->alpha_min;
    pcs[q].b = q < ncut ? cut[q] : set->alpha_max;
    pcs[q].tmpl = tmpl[q];
    if (!(pcs[q].b > pcs[q].a)) {
      pcs[q].b = pcs[q].a; /* zero width: nothing to integrate */
      pcs[q].n = 0;
      pcs[q].node = calloc(1, sizeof *pcs[q].node);
      if (!pcs[q].node) return ea_error_set(err, EA_ERR_NOMEM, "workspace: out of memory");
      pcs[q].node[0] = tmpl[q];
      continue;
    }
    const double tq = fmax(tol_total * (pcs[q].b - pcs[q].a) / span, 1e-15);
    double bad = NAN;
    const ea_status_t st = ea__ws_piece(w, &pcs[q], *coarse, *nc, tq, &bad);
    if (st == EA_ERR_INADMISSIBLE) {
      *redo = 1;
      return ea__ws_add_sample(w, bad, coarse, nc, cap, err);
    }
    if (st)
      return ea_error_set(err, st,
                          "workspace: the area between alpha = %.6g and %.6g deg did not "
                          "converge (%s)",
                          pcs[q].a / EA__DEG, pcs[q].b / EA__DEG, ea_strerror(st));
  }
  return EA_OK;
}

/* Phase 4: area, bounds and the extrema from the integrated pieces. */
static ea_status_t ea__ws_results(ea__ws_t *w, ea__ws_piece_t *pcs, int np,
                                  ea_workspace_metrics_t *m, ea_error_t *err) {
  double area = 0.0, aerr = 0.0;
  unsigned mask = 0;
  for (int q = 0; q < np; ++q) {
    area += pcs[q].integral;
    aerr += pcs[q].error;
    for (int i = 0; i < 2 * pcs[q].tmpl.n; ++i)
      mask |= 1u << pcs[q].tmpl.kind[i];
  }
  m->area = area;
  m->area_error = aerr;
  m->pieces = np;
  m->bounds = mask;
  ea_status_t st = EA_OK;
  ea__ws_extremum(w, pcs, np, EA__OBJ_REACH, &m->reach, &st);
  if (!st) ea__ws_extremum(w, pcs, np, EA__OBJ_X, &m->x_max, &st);
  if (!st) ea__ws_extremum(w, pcs, np, EA__OBJ_NEG_Y, &m->y_min, &st);
  if (st)
    return ea_error_set(err, st, "workspace: an extremum search failed (%s)", ea_strerror(st));
  return EA_OK;
}

static void ea__ws_free_pieces(ea__ws_piece_t *pcs, int np) {
  if (pcs)
    for (int q = 0; q < np; ++q)
      free(pcs[q].node);
  free(pcs);
}

ea_status_t ea_workspace_metrics(ea_shooter_t *sh, const ea_workspace_settings_t *set,
                                 ea_workspace_metrics_t *m, ea_error_t *err) {
  if (!sh || !set || !m) return ea_error_set(err, EA_ERR_ARG, "workspace metrics: NULL argument");
  memset(m, 0, sizeof *m);
  m->area = NAN;
  m->reach.value = m->x_max.value = m->y_min.value = NAN;
  ea__ws_t w;
  ea_status_t st = ea__ws_setup(sh, set, &w, err);
  if (st) return st;
  int cap = set->samples + 16, nc = 0, np = 0;
  ea__wsp_t *coarse = malloc((size_t)cap * sizeof *coarse);
  ea__wsp_t *tmpl = malloc(EA__WS_MAXCUT * sizeof *tmpl);
  ea__ws_piece_t *pcs = NULL;
  if (!coarse || !tmpl) {
    st = ea_error_set(err, EA_ERR_NOMEM, "workspace: out of memory");
    goto out;
  }
  if ((st = ea__ws_sample(&w, coarse, &nc, err))) goto out;
  for (int round = 0; round < 16; ++round) {
    double cut[EA__WS_MAXCUT];
    int ncut = 0, redo = 0;
    if ((st = ea__ws_cuts(&w, coarse, nc, cut, tmpl, &ncut, err))) goto out;
    ea__ws_free_pieces(pcs, np);
    np = ncut + 1;
    pcs = calloc((size_t)np, sizeof *pcs);
    if (!pcs) {
      st = ea_error_set(err, EA_ERR_NOMEM, "workspace: out of memory");
      goto out;
    }
    st = ea__ws_integrate(&w, pcs, np, cut, tmpl, &coarse, &nc, &cap, &redo, err);
    if (st) goto out;
    if (redo) continue;
    st = ea__ws_results(&w, pcs, np, m, err);
    goto out;
  }
  st = ea_error_set(err, EA_ERR_NOCONV,
                    "workspace: the region's structure kept changing between samples; raise "
                    "samples");
out:
  ea__ws_free_pieces(pcs, np);
  free(coarse);
  free(tmpl);
  m->solves = w.solves;
  if (st) {
    m->area = NAN;
    m->reach.value = m->x_max.value = m->y_min.value = NAN;
  }
  return st;
}
