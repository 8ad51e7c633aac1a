/* Plans that arrive at rest (docs/planner.md, "Arriving at rest"): the reduced dynamic model of the
 * arm (model/fe_rom.c) in the transcription. Per knot and mode the modal state (eta_i,
 * eta_i'), tied between the knots by Hermite-Simpson defects of
 *   eta'' + 2 zeta omega eta' + omega^2 eta = -B(q) . q'' - q'^T C(q) q'
 * along the trajectory's own interpolant (the cubic Hermite of (L_c, alpha) and their rates:
 * the ends, and the midpoint q_m = (q0 + q1)/2 + h (v0 - v1)/8, v_m = 3 (q1 - q0)/(2 h) -
 * (v0 + v1)/4, a_m = (a0 + a1)/2). The rows:
 *  - EA__ROW_DYN_DEF_POS/VEL: the defects of mode i over interval k;
 *  - EA__ROW_DYN_TENSION:  T_k + sum_i dT_i(q_k) eta_i,k within the tension limits;
 *  - EA__ROW_DYN_TORQUE:   EI kappa0_k + sum_i dM_i(q_k) eta_i,k within the torque limit;
 *  - EA__ROW_DYN_DEVIATION: |sum_i tip_i(q_k) eta_i,k|^2 <= max_tip_deviation^2;
 *  - EA__ROW_DYN_TERMINAL: sum_i |tip_i|^2 (e_i^2 + e_i'^2 / omega_i^2) <= residual^2 / K
 *    at the goal, e = (eta, eta') - the model's target centre (zero unless set), for the
 *    nominal model when residual_m > 0 (else EA__ROW_DYN_REST holds its state at its target)
 *    and for each robust corner (robust residual_m).
 * Each row is a small function of <= 13 variables; its gradient is exact by forward-mode
 * differentiation (ea__dual_t) through the Hermite and the table's exact interpolant
 * derivatives, and so are the Hessians of the defects (second-order forward mode over an
 * interval's trajectory variables, ea__plan_dyn_defect_hess) and of the tension and torque
 * rows (ea__plan_dyn_row_hess), from the table's exact second derivatives. */
#include "ea_simulate.h"
#include "dyn_impl.h"
#include "plan_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- forward-mode dual numbers over the row's local variables ------------ */

#define EA__DN 13
typedef struct {
  double v, d[EA__DN];
} ea__dual_t;

static ea__dual_t ea__dc(double v) {
  ea__dual_t r;
  memset(&r, 0, sizeof r);
  r.v = v;
  return r;
}
static ea__dual_t ea__dvar(double v, int i) {
  ea__dual_t r = ea__dc(v);
  r.d[i] = 1.0;
  return r;
}
static ea__dual_t ea__dadd(ea__dual_t a, ea__dual_t b) {
  a.v += b.v;
  for (int i = 0; i < EA__DN; ++i)
    a.d[i] += b.d[i];
  return a;
}
static ea__dual_t ea__dsub(ea__dual_t a, ea__dual_t b) {
  a.v -= b.v;
  for (int i = 0; i < EA__DN; ++i)
    a.d[i] -= b.d[i];
  return a;
}
static ea__dual_t ea__dmul(ea__dual_t a, ea__dual_t b) {
  ea__dual_t r;
  r.v = a.v * b.v;
  for (int i = 0; i < EA__DN; ++i)
    r.d[i] = a.d[i] * b.v + a.v * b.d[i];
  return r;
}
static ea__dual_t ea__dscale(ea__dual_t a, double s) {
  a.v *= s;
  for (int i = 0; i < EA__DN; ++i)
    a.d[i] *= s;
  return a;
}
static ea__dual_t ea__daxpy(ea__dual_t y, double s, ea__dual_t x) { /* y + s x */
  y.v += s * x.v;
  for (int i = 0; i < EA__DN; ++i)
    y.d[i] += s * x.d[i];
  return y;
}
static ea__dual_t ea__ddiv(ea__dual_t a, ea__dual_t b) {
  ea__dual_t r;
  r.v = a.v / b.v;
  for (int i = 0; i < EA__DN; ++i)
    r.d[i] = (a.d[i] - r.v * b.d[i]) / b.v;
  return r;
}
static ea__dual_t ea__dsqrt(ea__dual_t a) {
  ea__dual_t r;
  r.v = sqrt(a.v);
  for (int i = 0; i < EA__DN; ++i)
    r.d[i] = 0.5 * a.d[i] / r.v;
  return r;
}

/* A tabulated field f at (L, a): f + f_L dL + f_a da. */
static ea__dual_t ea__dfield(double f, double fL, double fa, ea__dual_t L, ea__dual_t a) {
  ea__dual_t r;
  r.v = f;
  for (int i = 0; i < EA__DN; ++i)
    r.d[i] = fL * L.d[i] + fa * a.d[i];
  return r;
}

/* The model's fields at (L, a) as duals. */
typedef struct {
  ea__dual_t w2[EA_ROM_MAX_MODES], B[EA_ROM_MAX_MODES][2], C[EA_ROM_MAX_MODES][3],
      tip[EA_ROM_MAX_MODES][2], dT[EA_ROM_MAX_MODES], dM[EA_ROM_MAX_MODES];
} ea__drom_t;

/* The fields of model j (its pl->Kper modes) from its table's values and derivatives at
 * (L, a). */
static void ea__drom_from(const ea_planner_t *pl, ea__dual_t L, ea__dual_t a,
                          const ea_rom_point_t *v, const ea_rom_point_t *dL,
                          const ea_rom_point_t *da, ea__drom_t *o) {
  for (int k = 0; k < pl->Kper; ++k) {
    o->w2[k] = ea__dfield(v->omega2[k], dL->omega2[k], da->omega2[k], L, a);
    for (int c = 0; c < 2; ++c) {
      o->B[k][c] = ea__dfield(v->B[k][c], dL->B[k][c], da->B[k][c], L, a);
      o->tip[k][c] = ea__dfield(v->tip[k][c], dL->tip[k][c], da->tip[k][c], L, a);
    }
    for (int c = 0; c < 3; ++c)
      o->C[k][c] = ea__dfield(v->C[k][c], dL->C[k][c], da->C[k][c], L, a);
    o->dT[k] = ea__dfield(v->dtension[k], dL->dtension[k], da->dtension[k], L, a);
    o->dM[k] = ea__dfield(v->dtorque[k], dL->dtorque[k], da->dtorque[k], L, a);
  }
}

/* The fields of model j at (L, a): its table there. */
static void ea__drom(const ea_planner_t *pl, int j, ea__dual_t L, ea__dual_t a, ea__drom_t *o) {
  ea_rom_point_t v, dL, da;
  ea_rom_table_eval(pl->roms[j], L.v, a.v, &v, &dL, &da);
  ea__drom_from(pl, L, a, &v, &dL, &da, o);
}

/* Modal forcing of mode k: -B . a - v^T C v. */
static ea__dual_t ea__dforce(const ea__drom_t *m, int k, const ea__dual_t v[2],
                             const ea__dual_t a[2]) {
  ea__dual_t f = ea__dadd(ea__dmul(m->B[k][0], a[0]), ea__dmul(m->B[k][1], a[1]));
  f = ea__dadd(f, ea__dmul(m->C[k][0], ea__dmul(v[0], v[0])));
  f = ea__dadd(f, ea__dscale(ea__dmul(m->C[k][1], ea__dmul(v[0], v[1])), 2.0));
  f = ea__dadd(f, ea__dmul(m->C[k][2], ea__dmul(v[1], v[1])));
  return ea__dscale(f, -1.0);
}

/* Modal acceleration: -omega^2 eta - 2 zeta omega eta' + F. */
static ea__dual_t ea__dacc(const ea__drom_t *m, int k, double zeta, ea__dual_t eta, ea__dual_t etad,
                           ea__dual_t F) {
  ea__dual_t r = ea__dsub(F, ea__dmul(m->w2[k], eta));
  if (zeta > 0) r = ea__dsub(r, ea__dscale(ea__dmul(ea__dsqrt(m->w2[k]), etad), 2 * zeta));
  return r;
}

/* ---- the rows ---------------------------------------------------------- */

static void ea__emit(const ea__dual_t *r, const int *col, int nloc, double *value, int *cols,
                     double *vals, int *n) {
  if (value) *value = r->v;
  for (int i = 0; i < nloc; ++i) {
    if (col[i] < 0) continue;
    if (cols) cols[*n] = col[i];
    if (vals) vals[*n] = r->d[i];
    ++*n;
  }
}

/* The defect rows' work, cached per interval by the values of its 9 trajectory variables
 * (the same for every mode): the Hermite of (L_c, alpha) and the model's fields at its ends
 * (from the knots' tables, ea__dyn_at_knot) and midpoint; the pos and vel defects of each
 * mode are cached by the 9 plus its 4 modal variables. */
typedef struct {
  int valid;
  double key[9];
  ea__dual_t h, v0[2], v1[2], a0[2], a1[2], vm[2], am[2];
  ea__drom_t m0, m1, mm;
} ea__dyn_icache_t;

typedef struct {
  int valid;
  double key[EA__DN];
  ea__dual_t pos, vel;
} ea__dyn_mcache_t;

struct ea__hz_fields;

/* The table at a knot's (L_c, alpha) with its exact first and second derivatives: shared by
 * the knot's tension and torque rows and the closed-form Hessians of both intervals at it. */
typedef struct {
  int valid;
  double key[2];
  ea_rom_point_t v, dL, da, dLL, dLa, daa;
} ea__dyn_kcache_t;

/* A mode's two defects over an interval in the path layout (ea__plan_dyn_defect_hess_pp):
 * keyed by the 11 path values (EA__PP_DKEY), the values and gradients over them. */
typedef struct {
  int valid;
  double key[EA__PP_DKEY];
  double v[2], g[2][EA__PP_DKEY];
} ea__dyn_pcache_t;

struct ea__dyn_cache {
  ea__dyn_icache_t *ic; /* (N - 1) M: per interval and model */
  ea__dyn_mcache_t *mc; /* (N - 1) K: per interval and modal coordinate */
  ea__dyn_pcache_t *pc; /* (N - 1) K: the same in the path layout */
  ea__dyn_kcache_t *kc; /* N M: per knot and model */
};

void ea__plan_dyn_cache_free(struct ea__dyn_cache *c) {
  if (!c) return;
  free(c->ic);
  free(c->mc);
  free(c->pc);
  free(c->kc);
  free(c);
}

/* The table of model j at knot k's (L_c, alpha) in x. */
static const ea__dyn_kcache_t *ea__dyn_at_knot(const ea_planner_t *pl, const double *x, int k,
                                               int j) {
  ea__dyn_kcache_t *c = &pl->dync->kc[k * pl->M + j];
  const double key[2] = {x[EA__IQ(pl, k, 0)], x[EA__IQ(pl, k, 1)]};
  if (!c->valid || memcmp(c->key, key, sizeof key)) {
    ea_rom_table_eval2(pl->roms[j], key[0], key[1], &c->v, &c->dL, &c->da, &c->dLL, &c->dLa,
                       &c->daa);
    memcpy(c->key, key, sizeof key);
    c->valid = 1;
  }
  return c;
}

void ea__plan_dyn_warm(const ea_planner_t *pl, const double *x, int k) {
  for (int j = 0; j < pl->M; ++j)
    ea__dyn_at_knot(pl, x, k, j);
}

static const ea__dyn_icache_t *ea__dyn_interval(const ea_planner_t *pl, const double *x, int k,
                                                int j, const double *xv, const ea__dual_t *loc) {
  ea__dyn_icache_t *ic = &pl->dync->ic[k * pl->M + j];
  if (ic->valid && !memcmp(ic->key, xv + 4, sizeof ic->key)) return ic;
  const double ds = pl->s[k + 1] - pl->s[k];
  const ea__dual_t h = ea__dscale(loc[12], ds), ih = ea__ddiv(ea__dc(1.0), h);
  const ea__dual_t ih2 = ea__dmul(ih, ih);
  ea__dual_t q0[2], q1[2], qm[2];
  for (int c = 0; c < 2; ++c) {
    q0[c] = loc[4 + 4 * c];
    q1[c] = loc[5 + 4 * c];
    ic->v0[c] = loc[6 + 4 * c];
    ic->v1[c] = loc[7 + 4 * c];
    const ea__dual_t dq = ea__dsub(q1[c], q0[c]);
    /* a0 = 6 dq / h^2 - (4 v0 + 2 v1) / h, a1 = -6 dq / h^2 + (2 v0 + 4 v1) / h */
    const ea__dual_t t6 = ea__dscale(ea__dmul(dq, ih2), 6.0);
    ic->a0[c] = ea__dsub(t6, ea__dmul(ea__daxpy(ea__dscale(ic->v0[c], 4.0), 2.0, ic->v1[c]), ih));
    ic->a1[c] = ea__dadd(ea__dscale(t6, -1.0),
                         ea__dmul(ea__daxpy(ea__dscale(ic->v0[c], 2.0), 4.0, ic->v1[c]), ih));
    qm[c] = ea__dadd(ea__dscale(ea__dadd(q0[c], q1[c]), 0.5),
                     ea__dscale(ea__dmul(h, ea__dsub(ic->v0[c], ic->v1[c])), 0.125));
    ic->vm[c] = ea__dsub(ea__dscale(ea__dmul(dq, ih), 1.5),
                         ea__dscale(ea__dadd(ic->v0[c], ic->v1[c]), 0.25));
    ic->am[c] = ea__dscale(ea__dadd(ic->a0[c], ic->a1[c]), 0.5);
  }
  ic->h = h;
  const ea__dyn_kcache_t *e0 = ea__dyn_at_knot(pl, x, k, j), *e1 = ea__dyn_at_knot(pl, x, k + 1, j);
  ea__drom_from(pl, q0[0], q0[1], &e0->v, &e0->dL, &e0->da, &ic->m0);
  ea__drom_from(pl, q1[0], q1[1], &e1->v, &e1->dL, &e1->da, &ic->m1);
  ea__drom(pl, j, qm[0], qm[1], &ic->mm);
  memcpy(ic->key, xv + 4, sizeof ic->key);
  ic->valid = 1;
  return ic;
}

/* Hermite-Simpson defects of mode i over interval k (pos: 0, vel: 1). Local variables:
 * 0 eta_k, 1 eta'_k, 2 eta_k+1, 3 eta'_k+1, 4..7 (q0, q1, v0, v1) of L_c, 8..11 of alpha,
 * 12 t_f. */
static void ea__defect_cols(const ea_planner_t *pl, int k, int i, int col[EA__DN]) {
  col[0] = EA__IE(pl, k, i);
  col[1] = EA__IED(pl, k, i);
  col[2] = EA__IE(pl, k + 1, i);
  col[3] = EA__IED(pl, k + 1, i);
  for (int c = 0; c < 2; ++c) {
    col[4 + 4 * c] = EA__IQ(pl, k, c);
    col[5 + 4 * c] = EA__IQ(pl, k + 1, c);
    col[6 + 4 * c] = EA__IV(pl, k, c);
    col[7 + 4 * c] = EA__IV(pl, k + 1, c);
  }
  col[12] = pl->has_tf ? EA__ITF(pl) : -1;
}

/* The defect's local values (t_f's when fixed: pl->tf_fixed), its rows' cache key. */
static void ea__defect_values(const ea_planner_t *pl, const double *x, const int col[EA__DN],
                              double xv[EA__DN]) {
  for (int j = 0; j < EA__DN; ++j)
    xv[j] = col[j] >= 0 ? x[col[j]] : pl->tf_fixed;
}

static int ea__dyn_defect(const ea_planner_t *pl, const double *x, int k, int i, int vel,
                          double *value, int *cols, double *vals) {
  int col[EA__DN];
  ea__defect_cols(pl, k, i, col);
  if (!value && !vals) { /* the entries alone (patterns) */
    int n = 0;
    for (int j = 0; j < EA__DN; ++j)
      if (col[j] >= 0) {
        if (cols) cols[n] = col[j];
        ++n;
      }
    return n;
  }
  double xv[EA__DN];
  ea__defect_values(pl, x, col, xv);
  ea__dyn_mcache_t *mc = &pl->dync->mc[k * pl->K + i];
  if (!mc->valid || memcmp(mc->key, xv, sizeof mc->key)) {
    ea__dual_t loc[EA__DN];
    for (int j = 0; j < EA__DN; ++j)
      loc[j] = col[j] >= 0 ? ea__dvar(xv[j], j) : ea__dc(xv[j]);
    /* modal coordinate i: mode mi of model j */
    const int j = i / pl->Kper, mi = i % pl->Kper;
    const ea__dyn_icache_t *ic = ea__dyn_interval(pl, x, k, j, xv, loc);
    const double zeta = pl->zeta[i];
    const ea__dual_t e0 = loc[0], ed0 = loc[1], e1 = loc[2], ed1 = loc[3];
    const ea__dual_t acc0 =
        ea__dacc(&ic->m0, mi, zeta, e0, ed0, ea__dforce(&ic->m0, mi, ic->v0, ic->a0));
    const ea__dual_t acc1 =
        ea__dacc(&ic->m1, mi, zeta, e1, ed1, ea__dforce(&ic->m1, mi, ic->v1, ic->a1));
    const ea__dual_t h8 = ea__dscale(ic->h, 0.125), h6 = ea__dscale(ic->h, 1.0 / 6.0);
    const ea__dual_t em =
        ea__dadd(ea__dscale(ea__dadd(e0, e1), 0.5), ea__dmul(h8, ea__dsub(ed0, ed1)));
    const ea__dual_t edm =
        ea__dadd(ea__dscale(ea__dadd(ed0, ed1), 0.5), ea__dmul(h8, ea__dsub(acc0, acc1)));
    const ea__dual_t sp = ea__dadd(ea__daxpy(ed0, 4.0, edm), ed1);
    mc->pos = ea__dscale(ea__dsub(ea__dsub(e1, e0), ea__dmul(h6, sp)), pl->dyn_scale);
    const ea__dual_t accm =
        ea__dacc(&ic->mm, mi, zeta, em, edm, ea__dforce(&ic->mm, mi, ic->vm, ic->am));
    const ea__dual_t sv = ea__dadd(ea__daxpy(acc0, 4.0, accm), acc1);
    mc->vel = ea__dscale(ea__dsub(ea__dsub(ed1, ed0), ea__dmul(h6, sv)), pl->dyn_scale);
    memcpy(mc->key, xv, sizeof mc->key);
    mc->valid = 1;
  }
  int n = 0;
  ea__emit(vel ? &mc->vel : &mc->pos, col, EA__DN, value, cols, vals, &n);
  return n;
}

/* Rows at knot k for model j: the tension or torque with the modal part, or the tip
 * deviation. Local variables: 0 L_c, 1 alpha, 2 T or kappa0, 3.. eta of the model's modes. */
static int ea__dyn_knot(const ea_planner_t *pl, const double *x, int kind, int k, int j,
                        double *value, int *cols, double *vals) {
  const int K = pl->Kper;
  int col[EA__DN];
  const int nloc = 3 + K;
  col[0] = EA__IQ(pl, k, 0);
  col[1] = EA__IQ(pl, k, 1);
  col[2] = kind == EA__ROW_DYN_TORQUE ? EA__IP(pl, k, 2)
                                      : (kind == EA__ROW_DYN_TENSION ? EA__IP(pl, k, 0) : -1);
  for (int i = 0; i < K; ++i)
    col[3 + i] = EA__IE(pl, k, j * K + i);
  if (kind != EA__ROW_DYN_DEVIATION) { /* affine in the modal states: directly */
    const int tq = kind == EA__ROW_DYN_TORQUE;
    if (cols) memcpy(cols, col, sizeof(int) * (size_t)nloc);
    if (!value && !vals) return nloc;
    const ea__dyn_kcache_t *c = ea__dyn_at_knot(pl, x, k, j);
    const double *f = tq ? c->v.dtorque : c->v.dtension, *fL = tq ? c->dL.dtorque : c->dL.dtension,
                 *fa = tq ? c->da.dtorque : c->da.dtension;
    const double base = tq ? pl->task.arm.EI : 1.0;
    double r = base * x[col[2]], gL = 0.0, ga = 0.0;
    for (int i = 0; i < K; ++i) {
      const double e = x[col[3 + i]];
      r += e * f[i];
      gL += e * fL[i];
      ga += e * fa[i];
    }
    if (value) *value = r;
    if (vals) {
      vals[0] = gL;
      vals[1] = ga;
      vals[2] = base;
      for (int i = 0; i < K; ++i)
        vals[3 + i] = f[i];
    }
    return nloc;
  }
  ea__dual_t loc[EA__DN];
  for (int q = 0; q < nloc; ++q)
    loc[q] = col[q] >= 0 ? ea__dvar(x[col[q]], q) : ea__dc(0.0);
  ea__drom_t m;
  ea__drom(pl, j, loc[0], loc[1], &m);
  ea__dual_t r;
  {
    ea__dual_t dx = ea__dc(0.0), dy = ea__dc(0.0);
    for (int i = 0; i < K; ++i) {
      dx = ea__dadd(dx, ea__dmul(m.tip[i][0], loc[3 + i]));
      dy = ea__dadd(dy, ea__dmul(m.tip[i][1], loc[3 + i]));
    }
    r = ea__dadd(ea__dmul(dx, dx), ea__dmul(dy, dy));
  }
  int n = 0;
  ea__emit(&r, col, nloc, value, cols, vals, &n);
  return n;
}

/* Residual amplitude of model j at the goal: sum_i |tip_i|^2 (e_i^2 + e_i'^2 / omega_i^2)
 * [m^2] (scaled), e_i = eta_i - c_i, e_i' = eta_i' - c_i' about the model's target centre c
 * (zero unless set). Local variables: 0 L_c, 1 alpha, 2.. (eta_i, eta'_i) of the model. */
static int ea__dyn_terminal(const ea_planner_t *pl, const double *x, int j, double *value,
                            int *cols, double *vals) {
  const int K = pl->Kper, k = pl->N - 1;
  int col[EA__DN];
  const int nloc = 2 + 2 * K;
  col[0] = EA__IQ(pl, k, 0);
  col[1] = EA__IQ(pl, k, 1);
  for (int i = 0; i < K; ++i) {
    col[2 + 2 * i] = EA__IE(pl, k, j * K + i);
    col[3 + 2 * i] = EA__IED(pl, k, j * K + i);
  }
  ea__dual_t loc[EA__DN];
  for (int q = 0; q < nloc; ++q)
    loc[q] = ea__dvar(x[col[q]], q);
  ea__drom_t m;
  ea__drom(pl, j, loc[0], loc[1], &m);
  ea__dual_t r = ea__dc(0.0);
  for (int i = 0; i < K; ++i) {
    const ea__dual_t t2 =
        ea__dadd(ea__dmul(m.tip[i][0], m.tip[i][0]), ea__dmul(m.tip[i][1], m.tip[i][1]));
    /* about the model's target centre (zero unless set: ea_planner_set_terminal_modes_model) */
    const int ci = j * K + i;
    const ea__dual_t e = ea__dsub(loc[2 + 2 * i], ea__dc(pl->dyn_target[ci]));
    const ea__dual_t ed = ea__dsub(loc[3 + 2 * i], ea__dc(pl->dyn_target[EA__DYN_MAX + ci]));
    const ea__dual_t a2 = ea__dadd(ea__dmul(e, e), ea__ddiv(ea__dmul(ed, ed), m.w2[i]));
    r = ea__dadd(r, ea__dmul(t2, a2));
  }
  r = ea__dscale(r, pl->dyn_term_scale);
  int n = 0;
  ea__emit(&r, col, nloc, value, cols, vals, &n);
  return n;
}

/* ---- the defects' Hessian in closed form ---------------------------------
 * Second-order forward mode over an interval's 9 trajectory variables z (L_c: q0 q1 v0 v1,
 * alpha: q0 q1 v0 v1, t_f; the defect's local variables 4..12): value, gradient and packed
 * lower-triangle Hessian. The defects are affine in the modal states e = (eta_k, eta'_k,
 * eta_k+1, eta'_k+1) (dyn_rows.c's header): pos, vel = sum_j e_j C_j(z) + C_4(z), with
 *   acc_P = F_P - W_P eta_P - c_P eta'_P at the ends (W = omega^2, c = 2 zeta omega,
 *   F = -B . a - v^T C v), d = acc_0 - acc_1,
 *   pos / s = eta_1 - eta_0 - h/2 (eta'_0 + eta'_1) - h^2/12 d,
 *   em = (eta_0 + eta_1)/2 + h/8 (eta'_0 - eta'_1), edm = (eta'_0 + eta'_1)/2 + h/8 d,
 *   accm = F_m - W_m em - c_m edm at the midpoint,
 *   vel / s = eta'_1 - eta'_0 - h/6 (acc_0 + acc_1) - 2h/3 accm,
 * so the Hessian is: z-z sum_j e_j C_j'' + C_4'' (the second-order mode of the defect with e
 * as numbers, ea__hz_defect), z-e_j C_j' (first order), e-e 0. */
/* An interval's end in the second-order mode: its (L_c, alpha) are the variables iL and iA (the
 * knot layout) or, iA < 0, functions of the one variable iL (the path layout's sigma) with
 * first and second derivatives d, d2 there. */
typedef struct {
  int iL, iA;
  double d[2], d2[2];
} ea__hz_end_t;

#define EA__HZCAT2(a, b) a##b
#define EA__HZCAT(a, b) EA__HZCAT2(a, b)
#define EA__HZN(name) EA__HZCAT(name, EA__HZ)
#define EA__HZ 9
#include "dyn_hz.h"
#undef EA__HZ
#define EA__HZ 7
#include "dyn_hz.h"
#undef EA__HZ

/* The knot layout's kinematics of interval k: z = (L_c q0 q1 v0 v1, alpha q0 q1 v0 v1, t_f). */
static void ea__hz_kin(const ea_planner_t *pl, const double *x, int k, ea__hz_kin_t9 *o) {
  ea__hz_t9 h, q[2][2], v[3][2];
  ea__hz_step9(pl, x, k, 8, &h);
  for (int c = 0; c < 2; ++c) {
    ea__hz_var9(&q[0][c], x[EA__IQ(pl, k, c)], 4 * c);
    ea__hz_var9(&q[1][c], x[EA__IQ(pl, k + 1, c)], 4 * c + 1);
    ea__hz_var9(&v[0][c], x[EA__IV(pl, k, c)], 4 * c + 2);
    ea__hz_var9(&v[1][c], x[EA__IV(pl, k + 1, c)], 4 * c + 3);
  }
  ea__hz_kin_from9(q, v, &h, o);
}

/* The values and gradients of mode i's defects, into the rows' cache (ea__dyn_defect's, keyed
 * by its 13 local values): the row evaluations at the same x (the interior point evaluates the
 * Hessian first) then need no dual numbers. */
static void ea__hz_fill(const ea_planner_t *pl, const double *x, int k, int i,
                        const int col[EA__DN], const ea__hz_t9 phi[2], ea__dz_t9 C[2][4]) {
  ea__dyn_mcache_t *mc = &pl->dync->mc[k * pl->K + i];
  ea__defect_values(pl, x, col, mc->key);
  const double s = pl->dyn_scale;
  for (int d = 0; d < 2; ++d) {
    ea__dual_t *r = d ? &mc->vel : &mc->pos;
    for (int q = 0; q < 4; ++q)
      r->d[q] = s * C[d][q].v;
    r->v = s * phi[d].v;
    for (int a = 0; a < 9; ++a)
      r->d[4 + a] = s * phi[d].g[a];
    if (!pl->has_tf) r->d[12] = 0.0;
  }
  mc->valid = 1;
}

void ea__plan_dyn_defect_hess(const ea_planner_t *pl, const double *x, const ea__row_t *rows,
                              const double *w, int g, int cols[][EA__ROW_MAX], int *nc,
                              double Hl[][EA__ROW_MAX][EA__ROW_MAX]) {
  const int k = rows[0].knot;
  ea__hz_kin_t9 kin;
  ea__hz_kin(pl, x, k, &kin);
  ea__hz_fields_t9 F[3]; /* the fields at the interval's ends and midpoint */
  int have_model = -1, have_coord = -1;
  const ea__hz_fields_t9 *m[3] = {&F[0], &F[1], &F[2]};
  ea__hz_t9 phi[2];
  ea__dz_t9 C[2][4];
  for (int r = 0; r < g; ++r) {
    nc[r] = 0;
    if (w[r] == 0.0) continue;
    const int i = rows[r].coord, j = i / pl->Kper, mi = i % pl->Kper;
    const int vel = rows[r].kind == EA__ROW_DYN_DEF_VEL;
    if (j != have_model) {
      for (int P = 0; P < 3; ++P) {
        const ea__hz_end_t e = {P, P + 4, {0, 0}, {0, 0}};
        ea__hz_point9(pl, j, &kin.q[P][0], &kin.q[P][1],
                      P < 2 ? ea__dyn_at_knot(pl, x, k + P, j) : NULL, P < 2 ? &e : NULL, &F[P]);
      }
      have_model = j;
    }
    int col[EA__DN]; /* ea__dyn_defect's 13 local variables, t_f (the last) dropped if fixed */
    ea__defect_cols(pl, k, i, col);
    const int nloc = pl->has_tf ? 13 : 12;
    nc[r] = nloc;
    memcpy(cols[r], col, sizeof(int) * (size_t)nloc);
    if (i != have_coord) { /* pos and vel of one mode: one evaluation */
      double e[4];
      for (int q = 0; q < 4; ++q)
        e[q] = x[col[q]];
      ea__hz_defect9(&kin, m, mi, e, phi, C);
      have_coord = i;
      ea__hz_fill(pl, x, k, i, col, phi, C);
    }
    const double s = pl->dyn_scale;
    const ea__hz_t9 *P = &phi[vel];
    const int nz = nloc - 4;
    for (int q = 0; q < 4; ++q)
      for (int b = 0; b < 4; ++b)
        Hl[r][q][b] = 0.0;
    int p = 0;
    for (int a = 0; a < 9; ++a)
      for (int b = 0; b <= a; ++b, ++p)
        if (a < nz) Hl[r][4 + a][4 + b] = Hl[r][4 + b][4 + a] = s * P->H[p];
    for (int q = 0; q < 4; ++q)
      for (int a = 0; a < nz; ++a)
        Hl[r][q][4 + a] = Hl[r][4 + a][q] = s * C[vel][q].g[a];
  }
}

/* The path layout's kinematics of interval k (transcribe/path_*.c): z = (sigma_k, sigma_k+1, the
 * rates of L_c and alpha at k and k + 1, t_f); (L_c, alpha) at the ends are functions of sigma with
 * slopes and curvatures dq[P], d2q[P]. */
static void ea__hz_kin_pp(const ea_planner_t *pl, const double *x, int k, const double *dq[2],
                          const double *d2q[2], ea__hz_kin_t7 *o) {
  ea__hz_t7 h, q[2][2], v[3][2];
  ea__hz_step7(pl, x, k, 6, &h);
  for (int P = 0; P < 2; ++P)
    for (int c = 0; c < 2; ++c) {
      ea__hz_c7(&q[P][c], x[EA__IQ(pl, k + P, c)]);
      q[P][c].g[P] = dq[P][c];
      q[P][c].H[P * (P + 1) / 2 + P] = d2q[P][c];
      q[P][c].s1 = P;
      ea__hz_var7(&v[P][c], x[EA__IV(pl, k + P, c)], 2 + 2 * c + P);
    }
  ea__hz_kin_from7(q, v, &h, o);
}

int ea__plan_dyn_defect_hess_pp(const ea_planner_t *pl, const double *x, const double sig[2],
                                const double *dq[2], const double *d2q[2], const ea__row_t *rows,
                                const double *w, int g, double Hl[][EA__ROW_MAX][EA__ROW_MAX]) {
  const int k = rows[0].knot, n = pl->has_tf ? EA__PP_DKEY : EA__PP_DKEY - 1, nz = n - 4;
  ea__hz_kin_t7 kin;
  ea__hz_kin_pp(pl, x, k, dq, d2q, &kin);
  ea__hz_fields_t7 F[3]; /* the fields at the interval's ends and midpoint */
  int have_model = -1, have_coord = -1;
  const ea__hz_fields_t7 *m[3] = {&F[0], &F[1], &F[2]};
  ea__hz_t7 phi[2];
  ea__dz_t7 C[2][4];
  const double s = pl->dyn_scale;
  for (int r = 0; r < g; ++r) {
    if (w[r] == 0.0) continue;
    const int i = rows[r].coord, j = i / pl->Kper, mi = i % pl->Kper;
    const int vel = rows[r].kind == EA__ROW_DYN_DEF_VEL;
    if (j != have_model) {
      for (int P = 0; P < 3; ++P) {
        const ea__hz_end_t e = {P,
                                -1,
                                {P < 2 ? dq[P][0] : 0, P < 2 ? dq[P][1] : 0},
                                {P < 2 ? d2q[P][0] : 0, P < 2 ? d2q[P][1] : 0}};
        ea__hz_point7(pl, j, &kin.q[P][0], &kin.q[P][1],
                      P < 2 ? ea__dyn_at_knot(pl, x, k + P, j) : NULL, P < 2 ? &e : NULL, &F[P]);
      }
      have_model = j;
    }
    if (i != have_coord) { /* pos and vel of one mode: one evaluation, cached for the rows */
      int col[EA__DN];
      ea__defect_cols(pl, k, i, col);
      double e[4];
      for (int q = 0; q < 4; ++q)
        e[q] = x[col[q]];
      ea__hz_defect7(&kin, m, mi, e, phi, C);
      have_coord = i;
      ea__dyn_pcache_t *pc = &pl->dync->pc[k * pl->K + i];
      for (int q = 0; q < 4; ++q)
        pc->key[q] = e[q];
      const double zk[7] = {sig[0],
                            sig[1],
                            x[EA__IV(pl, k, 0)],
                            x[EA__IV(pl, k + 1, 0)],
                            x[EA__IV(pl, k, 1)],
                            x[EA__IV(pl, k + 1, 1)],
                            pl->has_tf ? x[EA__ITF(pl)] : 0.0};
      memcpy(pc->key + 4, zk, sizeof zk);
      for (int d = 0; d < 2; ++d) {
        pc->v[d] = s * phi[d].v;
        for (int q = 0; q < 4; ++q)
          pc->g[d][q] = s * C[d][q].v;
        for (int a = 0; a < 7; ++a)
          pc->g[d][4 + a] = s * phi[d].g[a];
      }
      pc->valid = 1;
    }
    const ea__hz_t7 *P = &phi[vel];
    for (int q = 0; q < 4; ++q)
      for (int b = 0; b <= q; ++b)
        Hl[r][q][b] = 0.0;
    int p = 0;
    for (int a = 0; a < 7; ++a)
      for (int b = 0; b <= a; ++b, ++p)
        if (a < nz) Hl[r][4 + a][4 + b] = s * P->H[p];
    for (int q = 0; q < 4; ++q)
      for (int a = 0; a < nz; ++a)
        Hl[r][4 + a][q] = s * C[vel][q].g[a];
  }
  return n;
}

int ea__plan_dyn_defect_pp_cached(const ea_planner_t *pl, int k, int i, int vel,
                                  const double key[EA__PP_DKEY], double *value, double *vals) {
  const ea__dyn_pcache_t *pc = &pl->dync->pc[k * pl->K + i];
  if (!pc->valid || memcmp(pc->key, key, sizeof pc->key)) return 0;
  const int n = pl->has_tf ? EA__PP_DKEY : EA__PP_DKEY - 1;
  if (value) *value = pc->v[vel];
  if (vals) memcpy(vals, pc->g[vel], sizeof(double) * (size_t)n);
  return n;
}

void ea__plan_dyn_pp_forget(const ea_planner_t *pl) {
  if (!pl->dync) return;
  const size_t ni = (size_t)(pl->N > 1 ? pl->N - 1 : 1) * (size_t)pl->K;
  for (size_t q = 0; q < ni; ++q)
    pl->dync->pc[q].valid = 0;
}

int ea__plan_dyn_row_hess(const ea_planner_t *pl, const double *x, const ea__row_t *r, int *cols,
                          double H[][EA__ROW_MAX]) {
  if (r->kind != EA__ROW_DYN_TENSION && r->kind != EA__ROW_DYN_TORQUE) return -1;
  /* T (or EI kappa0) + sum_i f_i(L_c, alpha) eta_i: entries L_c, alpha, T or kappa0, eta_i */
  const int k = r->knot, j = r->coord, K = pl->Kper;
  const int n = ea__dyn_knot(pl, x, r->kind, k, j, NULL, cols, NULL);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      H[a][b] = 0.0;
  const ea__dyn_kcache_t *c = ea__dyn_at_knot(pl, x, k, j);
  const int tq = r->kind == EA__ROW_DYN_TORQUE;
  for (int i = 0; i < K; ++i) {
    const double e = x[cols[3 + i]];
    H[0][0] += e * (tq ? c->dLL.dtorque[i] : c->dLL.dtension[i]);
    H[0][1] += e * (tq ? c->dLa.dtorque[i] : c->dLa.dtension[i]);
    H[1][1] += e * (tq ? c->daa.dtorque[i] : c->daa.dtension[i]);
    H[0][3 + i] = H[3 + i][0] = tq ? c->dL.dtorque[i] : c->dL.dtension[i];
    H[1][3 + i] = H[3 + i][1] = tq ? c->da.dtorque[i] : c->da.dtension[i];
  }
  H[1][0] = H[0][1];
  return n;
}

int ea__plan_dyn_row(const ea_planner_t *pl, const double *x, const ea__row_t *r, double *value,
                     int *cols, double *vals) {
  switch ((ea__row_kind_t)r->kind) {
  case EA__ROW_DYN_DEF_POS:
    return ea__dyn_defect(pl, x, r->knot, r->coord, 0, value, cols, vals);
  case EA__ROW_DYN_DEF_VEL:
    return ea__dyn_defect(pl, x, r->knot, r->coord, 1, value, cols, vals);
  case EA__ROW_DYN_TENSION:
  case EA__ROW_DYN_TORQUE:
  case EA__ROW_DYN_DEVIATION:
    return ea__dyn_knot(pl, x, r->kind, r->knot, r->coord, value, cols, vals);
  case EA__ROW_DYN_TERMINAL:
  case EA__ROW_OBJ_DYN:
    return ea__dyn_terminal(pl, x, r->coord, value, cols, vals);
  case EA__ROW_DYN_REST: { /* linear: x - target (a row, not a bound: the guess keeps its
                            * integrated terminal state and the dynamics their consistency) */
    const int i = r->coord % pl->K, d = r->coord >= pl->K;
    const int col = d ? EA__IED(pl, pl->N - 1, i) : EA__IE(pl, pl->N - 1, i);
    /* scaled so that Ipopt's gradient-based scaling holds it at its largest gradient (100):
     * at-rest paper line 116/65/194 -> 65/47/44 Ipopt iterations at payload 0/0.25/0.5 */
    const double sc = 100.0;
    if (value) *value = sc * (x[col] - pl->dyn_target[d ? EA__DYN_MAX + i : i]);
    if (cols) cols[0] = col;
    if (vals) vals[0] = sc;
    return 1;
  }
  default:
    if (value) *value = 0.0;
    return 0;
  }
}

/* ---- build, guess, figures --------------------------------------------- */

ea_status_t ea__plan_dyn_build(ea_planner_t *pl, ea_error_t *err) {
  const ea_task_t *t = &pl->task;
  pl->rom = NULL;
  pl->K = pl->Kper = pl->M = 0;
  memset(&pl->dyn_info, 0, sizeof pl->dyn_info);
  if (t->dynamics.modes <= 0) return EA_OK;
  const double t0 = ea__mono_s();
  double box[4];
  ea__plan_box(pl, box);
  /* grid: ~0.025 m in L_c and ~0.06 rad in alpha (test_rom: 1e-3 on omega^2 at the cell centres
   * of a 12 x 12 grid over 0.3 m x 0.75 rad), 6..24 points */
  int nL = t->dynamics.grid[0], na = t->dynamics.grid[1];
  if (nL <= 0) nL = (int)ceil((box[1] - box[0]) / 0.025) + 1;
  if (na <= 0) na = (int)ceil((box[3] - box[2]) / 0.06) + 1;
  nL = nL < 6 ? 6 : nL > 24 ? 24 : nL;
  na = na < 6 ? 6 : na > 24 ? 24 : na;
  ea_rom_settings_t rs;
  ea_rom_settings_default(&rs);
  rs.modes = t->dynamics.modes;
  char dir[1024];
  const char *cache = ea_rom_cache_dir(dir, sizeof dir);
  /* the models: the nominal arm, and with a robust key the four corners of tip mass
   * m (1 +- e_m) and EI (1 +- e_EI) */
  const double em = t->dynamics.robust_tip_mass, eE = t->dynamics.robust_EI;
  const int robust = em > 0 || eE > 0;
  pl->M = robust ? 5 : 1;
  pl->Kper = rs.modes;
  pl->K = pl->M * pl->Kper;
  ea_plan_dyn_info_t *di = &pl->dyn_info;
  for (int j = 0; j < pl->M; ++j) {
    ea_arm_t arm = t->arm;
    double tm = pl->tip_mass;
    if (j > 0) {
      tm *= 1.0 + ((j - 1) & 1 ? em : -em);
      arm.EI *= 1.0 + ((j - 1) & 2 ? eE : -eE);
    }
    ea_rom_cache_info_t ci;
    ea_error_t e = {0};
    ea_status_t st = ea_rom_table_cached(&arm, tm, &rs, box, nL, na, cache, &pl->roms[j], &ci, &e);
    if (st)
      return ea_error_set(err, st,
                          "dynamics: the reduced model of the arm%s over L_c [%g, %g] m, "
                          "alpha [%g, %g] rad: %s",
                          j ? " (a robust corner)" : "", box[0], box[1], box[2], box[3], e.msg);
    di->model_tip_mass[j] = tm;
    di->model_EI[j] = arm.EI;
    if (ci.message[0]) { /* the first model's message whole, then as much as fits */
      const size_t used = strlen(di->cache_message);
      snprintf(di->cache_message + used, sizeof di->cache_message - used, "%s%s%s",
               used ? "; " : "", j ? "a robust corner: " : "", ci.message);
      ++di->cache_warnings;
    }
    if (j == 0) {
      di->cache_loaded = ci.loaded;
      di->cache_saved = ci.saved;
      snprintf(di->cache_path, sizeof di->cache_path, "%s", ci.path);
    }
  }
  pl->rom = pl->roms[0];
  di->models = pl->M;
  pl->dync = calloc(1, sizeof *pl->dync);
  const size_t ni = (size_t)(pl->N > 1 ? pl->N - 1 : 1);
  if (pl->dync) {
    pl->dync->ic = calloc(ni * (size_t)pl->M, sizeof *pl->dync->ic);
    pl->dync->mc = calloc(ni * (size_t)pl->K, sizeof *pl->dync->mc);
    pl->dync->pc = calloc(ni * (size_t)pl->K, sizeof *pl->dync->pc);
    pl->dync->kc = calloc((size_t)pl->N * (size_t)pl->M, sizeof *pl->dync->kc);
  }
  if (!pl->dync || !pl->dync->ic || !pl->dync->mc || !pl->dync->pc || !pl->dync->kc)
    return ea_error_set(err, EA_ERR_NOMEM, "dynamics: out of memory");
  /* each model's mode mi damped by the arm file's measured ratio of mode mi + 1 (modes beyond
   * the measured ones, and an arm without damping: undamped, the worst case) */
  for (int i = 0; i < EA__DYN_MAX; ++i) {
    const int mi = i % pl->Kper;
    pl->zeta[i] = i < pl->K && mi < t->arm.n_damping ? t->arm.damping_ratio[mi] : 0.0;
  }
  pl->dyn_scale = 1.0;
  pl->dyn_term_scale = 1e6; /* 1 mm -> 1 */
  di->built = 1;
  ea_rom_table_info(pl->rom, &di->table);
  di->time_s = ea__mono_s() - t0;
  return EA_OK;
}
