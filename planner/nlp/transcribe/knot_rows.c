/* The transcription's functions: constraints, their exact sparse Jacobian
 * and the pluggable objective terms (docs/planner.md). One row table
 * (pl->rows) drives the values, the structure and the values of the
 * Jacobian, so the three can never disagree. */
#include "plan_impl.h"
#include "dyn_impl.h"
#include "knot_impl.h"
#include "vib_impl.h"

#include <math.h>
#include <string.h>

ea_status_t ea__plan_shoot_all(ea_planner_t *pl, const double *x, int sens) {
  if (pl->cache_val && (pl->cache_sens || !sens)) return EA_OK;
  const double t0 = ea__mono_s();
  ea_status_t st = EA_OK;
  /* kvalid: 1 the tip state, 2 also its sensitivities */
  const unsigned char want = sens ? 2 : 1;
  for (int k = 0; k < pl->N && !st; ++k) {
    const double p[EA_NP] = {x[EA__IQ(pl, k, 1)], x[EA__IP(pl, k, 0)], x[EA__IP(pl, k, 1)],
                             x[EA__IP(pl, k, 2)]};
    double *key = pl->pkey + 4 * k;
    if (pl->kvalid[k] >= want && key[0] == p[0] && key[1] == p[1] && key[2] == p[2] &&
        key[3] == p[3])
      continue;
    pl->kvalid[k] = 0;
    st = ea_shoot(pl->sh, p, pl->xL + 4 * k, sens ? pl->S + 16 * k : NULL);
    if (st) break;
    memcpy(key, p, sizeof p);
    pl->kvalid[k] = want;
  }
  pl->t_statics += ea__mono_s() - t0;
  if (st) return st;
  pl->cache_val = 1;
  pl->cache_sens = sens != 0;
  return EA_OK;
}

/* Interval data for rows of interval k, coordinate c (EA__C_TH: theta0). */
static void ea__interval(const ea_planner_t *pl, const double *x, int k, int c, double *q0,
                         double *q1, double *v0, double *v1, double *h, double *dhdtf) {
  *q0 = x[EA__IQC(pl, k, c)];
  *q1 = x[EA__IQC(pl, k + 1, c)];
  *v0 = x[EA__IVC(pl, k, c)];
  *v1 = x[EA__IVC(pl, k + 1, c)];
  *dhdtf = pl->s[k + 1] - pl->s[k];
  *h = ea__plan_tf(pl, x) * *dhdtf;
}

double ea__plan_row_unit(const ea_planner_t *pl, const ea__row_t *r) {
  return r->kind == EA__ROW_ACC_START || r->kind == EA__ROW_ACC_END || r->kind == EA__ROW_ACC_CONT
             ? 1.0 / pl->acc_scale
             : 1.0;
}

/* One row: value and (optionally) its entries (col, val); returns count. */
/* (Over 100 lines: one case per row kind, the rows' definitions side by side.) */
int ea__plan_row_eval(const ea_planner_t *pl, const double *x, const ea__row_t *r, double *value,
                      int *cols, double *vals) {
  const ea_arm_t *arm = &pl->task.arm;
  const int k = r->knot, c = r->coord;
  int n = 0;
#define EA__E(col, v)                                                                              \
  do {                                                                                             \
    if (cols) cols[n] = (col);                                                                     \
    if (vals) vals[n] = (v);                                                                       \
    ++n;                                                                                           \
  } while (0)
  switch ((ea__row_kind_t)r->kind) {
  case EA__ROW_STATICS_KAPPA:
  case EA__ROW_STATICS_X:
  case EA__ROW_STATICS_Y: {
    const double *xL = pl->xL + 4 * k, *S = pl->S + 16 * k;
    const double Lc = x[EA__IQ(pl, k, 0)], al = x[EA__IQ(pl, k, 1)];
    const double ca = cos(al), sa = sin(al);
    int xi;
    double dLc, dal_extra;
    if (r->kind == EA__ROW_STATICS_KAPPA) {
      xi = EA_X_KAPPA;
      if (value) *value = xL[EA_X_KAPPA];
      dLc = 0.0;
      dal_extra = 0.0;
    } else if (r->kind == EA__ROW_STATICS_X) {
      xi = EA_X_X;
      if (value) *value = xL[EA_X_X] - arm->x_c - Lc * ca;
      dLc = -ca;
      dal_extra = Lc * sa;
    } else {
      xi = EA_X_Y;
      if (value) *value = xL[EA_X_Y] - arm->y_c - Lc * sa;
      dLc = -sa;
      dal_extra = -Lc * ca;
    }
    if (r->kind != EA__ROW_STATICS_KAPPA) EA__E(EA__IQ(pl, k, 0), dLc);
    const int nv = vals != NULL;
    EA__E(EA__IQ(pl, k, 1), nv ? S[xi * 4 + EA_P_ALPHA] + dal_extra : 0.0);
    EA__E(EA__IP(pl, k, 0), nv ? S[xi * 4 + EA_P_TENSION] : 0.0);
    EA__E(EA__IP(pl, k, 1), nv ? S[xi * 4 + EA_P_THETA0] : 0.0);
    EA__E(EA__IP(pl, k, 2), nv ? S[xi * 4 + EA_P_KAPPA0] : 0.0);
    break;
  }
  case EA__ROW_ACC_START:
  case EA__ROW_ACC_END: {
    double q0, q1, v0, v1, h, ds, a[2], ga[2][5];
    ea__interval(pl, x, k, c, &q0, &q1, &v0, &v1, &h, &ds);
    ea__plan_hermite_acc(q0, q1, v0, v1, h, a, ga);
    const int e = r->kind == EA__ROW_ACC_END;
    if (value) *value = a[e];
    EA__E(EA__IQC(pl, k, c), ga[e][0]);
    EA__E(EA__IQC(pl, k + 1, c), ga[e][1]);
    EA__E(EA__IVC(pl, k, c), ga[e][2]);
    EA__E(EA__IVC(pl, k + 1, c), ga[e][3]);
    if (pl->has_tf) EA__E(EA__ITF(pl), ga[e][4] * ds);
    break;
  }
  case EA__ROW_ACC_CONT: { /* a_end(interval k-1) - a_start(interval k) at knot k */
    double q0, q1, q2, v0, v1, v2, h0, h1, ds0, ds1, a0[2], a1[2], g0[2][5], g1[2][5];
    ea__interval(pl, x, k - 1, c, &q0, &q1, &v0, &v1, &h0, &ds0);
    ea__interval(pl, x, k, c, &q1, &q2, &v1, &v2, &h1, &ds1);
    ea__plan_hermite_acc(q0, q1, v0, v1, h0, a0, g0);
    ea__plan_hermite_acc(q1, q2, v1, v2, h1, a1, g1);
    if (value) *value = a0[1] - a1[0];
    EA__E(EA__IQC(pl, k - 1, c), g0[1][0]);
    EA__E(EA__IQC(pl, k, c), g0[1][1] - g1[0][0]);
    EA__E(EA__IQC(pl, k + 1, c), -g1[0][1]);
    EA__E(EA__IVC(pl, k - 1, c), g0[1][2]);
    EA__E(EA__IVC(pl, k, c), g0[1][3] - g1[0][2]);
    EA__E(EA__IVC(pl, k + 1, c), -g1[0][3]);
    if (pl->has_tf) EA__E(EA__ITF(pl), g0[1][4] * ds0 - g1[0][4] * ds1);
    break;
  }
  case EA__ROW_SPEED_CTRL: {
    /* The rate of the cubic Hermite is a quadratic in s = (t - t_k) / h with
     * Bernstein coefficients (v0, 3 (q1 - q0) / h - v0 - v1, v1): it lies in
     * their convex hull, so |middle coefficient| <= v with |v0|, |v1| <= v
     * (variable bounds) holds the speed limit on the whole interval. */
    double q0, q1, v0, v1, h, ds;
    ea__interval(pl, x, k, c, &q0, &q1, &v0, &v1, &h, &ds);
    if (value) *value = 3.0 * (q1 - q0) / h - v0 - v1;
    EA__E(EA__IQC(pl, k, c), -3.0 / h);
    EA__E(EA__IQC(pl, k + 1, c), 3.0 / h);
    EA__E(EA__IVC(pl, k, c), -1.0);
    EA__E(EA__IVC(pl, k + 1, c), -1.0);
    if (pl->has_tf) EA__E(EA__ITF(pl), -3.0 * (q1 - q0) / (h * h) * ds);
    break;
  }
  case EA__ROW_PATH_NORMAL:
  case EA__ROW_PATH_PROGRESS: {
    const int sg = pl->seg_of_knot[k];
    const double b = pl->nq == 3 ? x[EA__IQ(pl, k, 2)] : pl->base_fixed;
    double P[3], dP[3][3];
    ea__plan_tip3(pl, x[EA__IQ(pl, k, 0)], x[EA__IQ(pl, k, 1)], b, P, dP);
    const double *dir = r->kind == EA__ROW_PATH_NORMAL ? pl->segN[sg][c] : pl->segD[sg];
    const double *A = pl->segA[sg];
    if (value) *value = dir[0] * (P[0] - A[0]) + dir[1] * (P[1] - A[1]) + dir[2] * (P[2] - A[2]);
    for (int j = 0; j < pl->nq; ++j)
      EA__E(EA__IQ(pl, k, j), dir[0] * dP[0][j] + dir[1] * dP[1][j] + dir[2] * dP[2][j]);
    break;
  }
  case EA__ROW_OBJ_ACC:
  case EA__ROW_OBJ_JERK: {
    double q0, q1, v0, v1, h, ds, a[2], ga[2][5];
    ea__interval(pl, x, k, c, &q0, &q1, &v0, &v1, &h, &ds);
    ea__plan_hermite_acc(q0, q1, v0, v1, h, a, ga);
    const double is = 1.0 / (pl->aref[c] * pl->aref[c]);
    double fa0, fa1, fh;
    if (r->kind == EA__ROW_OBJ_ACC) {
      const double e = a[0] * a[0] + a[0] * a[1] + a[1] * a[1];
      if (value) *value = h / 3.0 * e * is;
      fa0 = h / 3.0 * (2.0 * a[0] + a[1]) * is;
      fa1 = h / 3.0 * (a[0] + 2.0 * a[1]) * is;
      fh = e / 3.0 * is;
    } else {
      const double j = a[1] - a[0];
      if (value) *value = j * j / h * is;
      fa0 = -2.0 * j / h * is;
      fa1 = 2.0 * j / h * is;
      fh = -j * j / (h * h) * is;
    }
    EA__E(EA__IQ(pl, k, c), fa0 * ga[0][0] + fa1 * ga[1][0]);
    EA__E(EA__IQ(pl, k + 1, c), fa0 * ga[0][1] + fa1 * ga[1][1]);
    EA__E(EA__IV(pl, k, c), fa0 * ga[0][2] + fa1 * ga[1][2]);
    EA__E(EA__IV(pl, k + 1, c), fa0 * ga[0][3] + fa1 * ga[1][3]);
    if (pl->has_tf) EA__E(EA__ITF(pl), (fa0 * ga[0][4] + fa1 * ga[1][4] + fh) * ds);
    break;
  }
  case EA__ROW_FREQ_MIN:
  case EA__ROW_DEFL_START:
  case EA__ROW_DEFL_END:
  case EA__ROW_OBJ_VIB:
    return ea__plan_vib_row(pl, x, r, value, cols, vals);
  case EA__ROW_DYN_DEF_POS:
  case EA__ROW_DYN_DEF_VEL:
  case EA__ROW_DYN_TENSION:
  case EA__ROW_DYN_TORQUE:
  case EA__ROW_DYN_DEVIATION:
  case EA__ROW_DYN_TERMINAL:
  case EA__ROW_DYN_REST:
  case EA__ROW_OBJ_DYN:
    return ea__plan_dyn_row(pl, x, r, value, cols, vals);
  default:
    break;
  }
#undef EA__E
  if (r->kind == EA__ROW_ACC_START || r->kind == EA__ROW_ACC_END || r->kind == EA__ROW_ACC_CONT) {
    if (value) *value *= pl->acc_scale;
    if (vals)
      for (int i = 0; i < n; ++i)
        vals[i] *= pl->acc_scale;
  }
  return n;
}

/* d^2 a_e / dh d(q0, q1, v0, v1) and d^2 a_e / dh^2 of the Hermite's end accelerations
 * (ea__plan_hermite_acc; e: 0 start, 1 end), which are linear in (q, v) for a fixed h. */
static void ea__hermite_acc_hh(double q0, double q1, double v0, double v1, double h,
                               double H[2][5]) {
  const double dq = q1 - q0, ih = 1.0 / h, ih2 = ih * ih, ih3 = ih2 * ih;
  H[0][0] = 12.0 * ih3;
  H[0][1] = -12.0 * ih3;
  H[0][2] = 4.0 * ih2;
  H[0][3] = 2.0 * ih2;
  H[0][4] = 36.0 * dq * ih3 * ih - 2.0 * (4.0 * v0 + 2.0 * v1) * ih3;
  H[1][0] = -12.0 * ih3;
  H[1][1] = 12.0 * ih3;
  H[1][2] = -2.0 * ih2;
  H[1][3] = -4.0 * ih2;
  H[1][4] = -36.0 * dq * ih3 * ih + 2.0 * (2.0 * v0 + 4.0 * v1) * ih3;
}

int ea__plan_row_hess(const ea_planner_t *pl, const double *x, const ea__row_t *r, int *cols,
                      double H[][EA__ROW_MAX]) {
  const int k = r->knot, c = r->coord;
  const ea__row_kind_t kind = (ea__row_kind_t)r->kind;
  if (kind == EA__ROW_DYN_TENSION || kind == EA__ROW_DYN_TORQUE)
    return ea__plan_dyn_row_hess(pl, x, r, cols, H);
  if (kind != EA__ROW_ACC_START && kind != EA__ROW_ACC_END && kind != EA__ROW_ACC_CONT &&
      kind != EA__ROW_SPEED_CTRL && kind != EA__ROW_OBJ_ACC && kind != EA__ROW_OBJ_JERK)
    return -1;
  const int n = ea__plan_row_eval(pl, x, r, NULL, cols, NULL);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      H[a][b] = 0.0;
  const int t = n - 1; /* t_f's entry, the last (when pl->has_tf) */
  double q0, q1, v0, v1, h, ds, Hh[2][5];
  if (kind == EA__ROW_ACC_CONT) { /* a_end(interval k-1) - a_start(interval k) */
    double q2, v2, h1, ds1, Hh1[2][5];
    ea__interval(pl, x, k - 1, c, &q0, &q1, &v0, &v1, &h, &ds);
    ea__interval(pl, x, k, c, &q1, &q2, &v1, &v2, &h1, &ds1);
    if (!pl->has_tf) return n;
    ea__hermite_acc_hh(q0, q1, v0, v1, h, Hh);
    ea__hermite_acc_hh(q1, q2, v1, v2, h1, Hh1);
    /* entries: q_k-1, q_k, q_k+1, v_k-1, v_k, v_k+1, t_f */
    const double e[6] = {ds * Hh[1][0], ds * Hh[1][1] - ds1 * Hh1[0][0], -ds1 * Hh1[0][1],
                         ds * Hh[1][2], ds * Hh[1][3] - ds1 * Hh1[0][2], -ds1 * Hh1[0][3]};
    for (int a = 0; a < 6; ++a)
      H[t][a] = H[a][t] = pl->acc_scale * e[a];
    H[t][t] = pl->acc_scale * (ds * ds * Hh[1][4] - ds1 * ds1 * Hh1[0][4]);
    return n;
  }
  ea__interval(pl, x, k, c, &q0, &q1, &v0, &v1, &h, &ds);
  /* entries q0, q1, v0, v1[, t_f]: the Hessian in y = (q0, q1, v0, v1, h), then h -> t_f */
  double Hy[5][5] = {{0}};
  ea__hermite_acc_hh(q0, q1, v0, v1, h, Hh);
  if (kind == EA__ROW_ACC_START || kind == EA__ROW_ACC_END) {
    const int e = kind == EA__ROW_ACC_END;
    for (int a = 0; a < 4; ++a)
      Hy[4][a] = Hy[a][4] = pl->acc_scale * Hh[e][a];
    Hy[4][4] = pl->acc_scale * Hh[e][4];
  } else if (kind == EA__ROW_SPEED_CTRL) { /* 3 (q1 - q0) / h - v0 - v1 */
    Hy[4][0] = Hy[0][4] = 3.0 / (h * h);
    Hy[4][1] = Hy[1][4] = -3.0 / (h * h);
    Hy[4][4] = 6.0 * (q1 - q0) / (h * h * h);
  } else { /* f(a0, a1, h): the chain rule through the end accelerations */
    double a[2], ga[2][5];
    ea__plan_hermite_acc(q0, q1, v0, v1, h, a, ga);
    const double is = 1.0 / (pl->aref[c] * pl->aref[c]);
    double fa[2], faa[2][2], fah[2], fhh;
    if (kind == EA__ROW_OBJ_ACC) { /* h / 3 (a0^2 + a0 a1 + a1^2) */
      fa[0] = h / 3.0 * (2.0 * a[0] + a[1]) * is;
      fa[1] = h / 3.0 * (a[0] + 2.0 * a[1]) * is;
      faa[0][0] = faa[1][1] = 2.0 * h / 3.0 * is;
      faa[0][1] = faa[1][0] = h / 3.0 * is;
      fah[0] = (2.0 * a[0] + a[1]) / 3.0 * is;
      fah[1] = (a[0] + 2.0 * a[1]) / 3.0 * is;
      fhh = 0.0;
    } else { /* (a1 - a0)^2 / h */
      const double j = a[1] - a[0];
      fa[0] = -2.0 * j / h * is;
      fa[1] = 2.0 * j / h * is;
      faa[0][0] = faa[1][1] = 2.0 / h * is;
      faa[0][1] = faa[1][0] = -2.0 / h * is;
      fah[0] = 2.0 * j / (h * h) * is;
      fah[1] = -2.0 * j / (h * h) * is;
      fhh = 2.0 * j * j / (h * h * h) * is;
    }
    for (int p = 0; p < 5; ++p)
      for (int q = 0; q < 5; ++q) {
        double v = 0.0;
        for (int e = 0; e < 2; ++e)
          for (int f = 0; f < 2; ++f)
            v += faa[e][f] * ga[e][p] * ga[f][q];
        for (int e = 0; e < 2; ++e) {
          if (p == 4) v += fah[e] * ga[e][q] + fa[e] * Hh[e][q];
          if (q == 4) v += fah[e] * ga[e][p] + (p == 4 ? 0.0 : fa[e] * Hh[e][p]);
        }
        if (p == 4 && q == 4) v += fhh;
        Hy[p][q] = v;
      }
  }
  const int m = pl->has_tf ? 5 : 4;
  for (int p = 0; p < m; ++p)
    for (int q = 0; q < m; ++q)
      H[p][q] = Hy[p][q] * (p == 4 ? ds : 1.0) * (q == 4 ? ds : 1.0);
  return n;
}

ea_status_t ea__plan_eval_g(ea_planner_t *pl, const double *x, double *g) {
  ea_status_t st = ea__plan_shoot_all(pl, x, 1); /* the Jacobian follows at the same x */
  if (st) return st;
  for (int i = 0; i < pl->m; ++i)
    ea__plan_row_eval(pl, x, &pl->rows[i], &g[i], NULL, NULL);
  return EA_OK;
}

ea_status_t ea__plan_eval_g_values(ea_planner_t *pl, const double *x, double *g) {
  ea_status_t st = ea__plan_shoot_all(pl, x, 0);
  if (st) return st;
  for (int i = 0; i < pl->m; ++i)
    ea__plan_row_eval(pl, x, &pl->rows[i], &g[i], NULL, NULL);
  return EA_OK;
}

int ea__plan_row_families(const ea__row_t *rows, int m, int *fam) {
  for (int i = 0; i < m; ++i) {
    const ea__row_t *r = &rows[i];
    const int k = r->kind == EA__ROW_ACC_END    ? EA__ROW_ACC_START
                  : r->kind == EA__ROW_DEFL_END ? EA__ROW_DEFL_START
                                                : r->kind;
    fam[i] = k * 256 + r->coord;
  }
  return EA__ROW_KIND_COUNT * 256;
}

int ea__plan_jac(ea_planner_t *pl, const double *x, int *irow, int *jcol, double *values) {
  int nz = 0;
  int cols[EA__ROW_MAX];
  for (int i = 0; i < pl->m; ++i) {
    const int c = ea__plan_row_eval(pl, x, &pl->rows[i], NULL, jcol ? cols : NULL,
                                    values ? values + nz : NULL);
    if (irow)
      for (int j = 0; j < c; ++j) {
        irow[nz + j] = i;
        jcol[nz + j] = cols[j];
      }
    nz += c;
  }
  return nz;
}

const char *ea__plan_row_name(const ea_planner_t *pl, const ea__row_t *r, char *buf, size_t len) {
  static const char *const coord[4] = {"cable length", "cable angle", "base", "shoulder"};
  const char *cn = r->coord < 4 ? coord[r->coord] : "?";
  (void)pl;
  switch ((ea__row_kind_t)r->kind) {
  case EA__ROW_STATICS_KAPPA:
    snprintf(buf, len, "statics residual kappa(L) = 0");
    break;
  case EA__ROW_STATICS_X:
    snprintf(buf, len, "statics residual tip x on the cable");
    break;
  case EA__ROW_STATICS_Y:
    snprintf(buf, len, "statics residual tip y on the cable");
    break;
  case EA__ROW_ACC_START:
  case EA__ROW_ACC_END:
    snprintf(buf, len, "%s acceleration limit", cn);
    break;
  case EA__ROW_SPEED_CTRL:
    snprintf(buf, len, "%s speed limit (interval)", cn);
    break;
  case EA__ROW_ACC_CONT:
    snprintf(buf, len, "%s acceleration continuity", cn);
    break;
  case EA__ROW_PATH_NORMAL:
    snprintf(buf, len, "tip on the path line");
    break;
  case EA__ROW_PATH_PROGRESS:
    snprintf(buf, len, "tip between the path segment's ends");
    break;
  case EA__ROW_FREQ_MIN:
    snprintf(buf, len, "first natural frequency limit");
    break;
  case EA__ROW_DEFL_START:
  case EA__ROW_DEFL_END:
    snprintf(buf, len, "%s modal deflection limit", cn);
    break;
  case EA__ROW_DYN_DEF_POS:
  case EA__ROW_DYN_DEF_VEL:
    snprintf(buf, len, "mode %d dynamics (reduced model)", r->coord + 1);
    break;
  case EA__ROW_DYN_TENSION:
    snprintf(buf, len, "tension limit with the vibration");
    break;
  case EA__ROW_DYN_TORQUE:
    snprintf(buf, len, "shoulder torque limit with the vibration");
    break;
  case EA__ROW_DYN_DEVIATION:
    snprintf(buf, len, "tip deviation limit (dynamics)");
    break;
  case EA__ROW_DYN_TERMINAL:
    snprintf(buf, len, "residual vibration at the goal (dynamics.residual_m)");
    break;
  case EA__ROW_DYN_REST:
    snprintf(buf, len, "mode %d of model %d at rest at the goal", r->coord % pl->K % pl->Kper + 1,
             r->coord % pl->K / pl->Kper + 1);
    break;
  default:
    snprintf(buf, len, "constraint");
    break;
  }
  return buf;
}

/* ---------------------------------------------------------------------- */
/* Objective terms                                                          */
/* ---------------------------------------------------------------------- */

static double ea__term_time_value(const ea_planner_t *pl, const double *x) {
  return ea__plan_tf(pl, x);
}
static void ea__term_time_grad(const ea_planner_t *pl, const double *x, double w, double *g) {
  (void)x;
  if (pl->has_tf) g[EA__ITF(pl)] += w;
}

/* Integral over the plan of sum_c (acc_c / aref_c)^2 (jerk = 0) or of
 * sum_c (jerk_c / aref_c)^2 (jerk = 1); cubic Hermite: acceleration linear,
 * jerk constant per interval, so both integrals are exact. */
static double ea__acc_energy(const ea_planner_t *pl, const double *x, double w, double *g,
                             int jerk) {
  double f = 0.0;
  for (int k = 0; k + 1 < pl->N; ++k)
    for (int c = 0; c < pl->nq; ++c) {
      double q0, q1, v0, v1, h, ds, a[2], ga[2][5];
      ea__interval(pl, x, k, c, &q0, &q1, &v0, &v1, &h, &ds);
      ea__plan_hermite_acc(q0, q1, v0, v1, h, a, g ? ga : NULL);
      const double is = 1.0 / (pl->aref[c] * pl->aref[c]);
      double fa0, fa1, fh;
      if (!jerk) {
        const double e = a[0] * a[0] + a[0] * a[1] + a[1] * a[1];
        f += h / 3.0 * e * is;
        fa0 = h / 3.0 * (2.0 * a[0] + a[1]) * is;
        fa1 = h / 3.0 * (a[0] + 2.0 * a[1]) * is;
        fh = e / 3.0 * is;
      } else {
        const double j = a[1] - a[0];
        f += j * j / h * is;
        fa0 = -2.0 * j / h * is;
        fa1 = 2.0 * j / h * is;
        fh = -j * j / (h * h) * is;
      }
      if (!g) continue;
      const int idx[4] = {EA__IQ(pl, k, c), EA__IQ(pl, k + 1, c), EA__IV(pl, k, c),
                          EA__IV(pl, k + 1, c)};
      for (int i = 0; i < 4; ++i)
        g[idx[i]] += w * (fa0 * ga[0][i] + fa1 * ga[1][i]);
      if (pl->has_tf) g[EA__ITF(pl)] += w * (fa0 * ga[0][4] + fa1 * ga[1][4] + fh) * ds;
    }
  return f;
}

static double ea__term_acc_value(const ea_planner_t *pl, const double *x) {
  return ea__acc_energy(pl, x, 0.0, NULL, 0);
}
static void ea__term_acc_grad(const ea_planner_t *pl, const double *x, double w, double *g) {
  ea__acc_energy(pl, x, w, g, 0);
}
static double ea__term_jerk_value(const ea_planner_t *pl, const double *x) {
  return ea__acc_energy(pl, x, 0.0, NULL, 1);
}
static void ea__term_jerk_grad(const ea_planner_t *pl, const double *x, double w, double *g) {
  ea__acc_energy(pl, x, w, g, 1);
}

/* Sum of the vibration pieces (one per interval, vib_rows.c). */
static double ea__term_vib_value(const ea_planner_t *pl, const double *x) {
  double f = 0.0;
  for (int k = 0; k + 1 < pl->N; ++k) {
    const ea__row_t r = {EA__ROW_OBJ_VIB, 0, k};
    double v;
    ea__plan_vib_row(pl, x, &r, &v, NULL, NULL);
    f += v;
  }
  return f;
}
static void ea__term_vib_grad(const ea_planner_t *pl, const double *x, double w, double *g) {
  int cols[EA__ROW_MAX];
  double vals[EA__ROW_MAX];
  for (int k = 0; k + 1 < pl->N; ++k) {
    const ea__row_t r = {EA__ROW_OBJ_VIB, 0, k};
    const int n = ea__plan_vib_row(pl, x, &r, NULL, cols, vals);
    for (int i = 0; i < n; ++i)
      g[cols[i]] += w * vals[i];
  }
}

/* The reduced model's residual amplitude at the goal [m^2 / (1 mm)^2] (dyn_rows.c). */
static double ea__term_dyn_value(const ea_planner_t *pl, const double *x) {
  const ea__row_t r = {EA__ROW_OBJ_DYN, 0, pl->N - 1};
  double v;
  ea__plan_dyn_row(pl, x, &r, &v, NULL, NULL);
  return v;
}
static void ea__term_dyn_grad(const ea_planner_t *pl, const double *x, double w, double *g) {
  int cols[EA__ROW_MAX];
  double vals[EA__ROW_MAX];
  const ea__row_t r = {EA__ROW_OBJ_DYN, 0, pl->N - 1};
  const int n = ea__plan_dyn_row(pl, x, &r, NULL, cols, vals);
  for (int i = 0; i < n; ++i)
    g[cols[i]] += w * vals[i];
}

void ea__plan_terms_setup(ea_planner_t *pl) {
  const ea_task_t *t = &pl->task;
  pl->n_terms = 0;
  ea__plan_term_t *tm = pl->terms;
  switch (t->objective) {
  case EA_TASK_MIN_TIME:
    tm[pl->n_terms++] = (ea__plan_term_t){"time", 1.0, ea__term_time_value, ea__term_time_grad};
    if (t->solver.regularization > 0.0)
      tm[pl->n_terms++] = (ea__plan_term_t){"acceleration energy", t->solver.regularization,
                                            ea__term_acc_value, ea__term_acc_grad};
    break;
  case EA_TASK_MIN_EFFORT:
    tm[pl->n_terms++] =
        (ea__plan_term_t){"acceleration energy", 1.0, ea__term_acc_value, ea__term_acc_grad};
    break;
  case EA_TASK_MIN_JERK:
    tm[pl->n_terms++] =
        (ea__plan_term_t){"jerk energy", 1.0, ea__term_jerk_value, ea__term_jerk_grad};
    break;
  case EA_TASK_MIN_VIBRATION:
    if (pl->rom) { /* the model's residual at the goal, an effort term to make it unique */
      tm[pl->n_terms++] =
          (ea__plan_term_t){"residual vibration", 1.0, ea__term_dyn_value, ea__term_dyn_grad};
      if (t->solver.regularization > 0.0)
        tm[pl->n_terms++] = (ea__plan_term_t){"acceleration energy", t->solver.regularization,
                                              ea__term_acc_value, ea__term_acc_grad};
      if (pl->has_tf)
        tm[pl->n_terms++] =
            (ea__plan_term_t){"time", t->time_weight, ea__term_time_value, ea__term_time_grad};
      break;
    }
    tm[pl->n_terms++] = (ea__plan_term_t){"vibration", 1.0, ea__term_vib_value, ea__term_vib_grad};
    if (pl->has_tf)
      tm[pl->n_terms++] =
          (ea__plan_term_t){"time", t->time_weight, ea__term_time_value, ea__term_time_grad};
    break;
  }
}
